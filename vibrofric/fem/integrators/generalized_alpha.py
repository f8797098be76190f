"""The linear part of an implicit step: generalized-alpha's coefficients, the
model's linear system in its coordinates q, the contact's tangent that the
factorized matrix holds, and the compiled linear parts of a step: the
predictors and b_n, solved for y = A^-1 b_n, and the update of q, v, a at
its end (docs/fe-model.md, "How an implicit step works", explains the scheme).

    alpha_m = (2 rho_inf - 1) / (rho_inf + 1),   alpha_f = rho_inf / (rho_inf + 1)
    gamma = 1/2 - alpha_m + alpha_f,             beta_N = (1 - alpha_m + alpha_f)^2 / 4
    c_M = (1 - alpha_m) / (beta_N dt^2),         c_V = gamma / (beta_N dt)

The compiled functions here do not call the friction law: they are compiled
once for every law (implicit.implicit_steps, compiled per law, calls them).
"""

from typing import NamedTuple

import numpy as np
from numba import njit

from ...friction_law.contract import FASTMATH
from ..model.linalg import apply, solve


class Scheme(NamedTuple):
    """What the compiled step needs of the scheme (``scheme`` in implicit.py)."""

    dt: float
    alpha_m: float
    alpha_f: float
    beta_n: float
    gamma: float
    c_m: float
    c_v: float
    beta: float             # the model's Rayleigh damping, s
    tolerance: float        # of the contact iteration, m
    max_iterations: int
    still_substeps: int     # friction sub-steps a step before the base moves (contact_solve)


class Coefficients(NamedTuple):
    """Generalized-alpha's coefficients for rho_inf and dt (the module docstring)."""

    alpha_m: float
    alpha_f: float
    beta_n: float
    gamma: float
    c_m: float
    c_v: float


def coefficients(rho_inf: float, dt: float) -> Coefficients:
    """Generalized-alpha's coefficients for rho_inf and dt (Chung & Hulbert 1993)."""
    alpha_m = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0)
    alpha_f = rho_inf / (rho_inf + 1.0)
    gamma = 0.5 - alpha_m + alpha_f
    beta_n = 0.25 * (1.0 - alpha_m + alpha_f) ** 2
    return Coefficients(alpha_m, alpha_f, beta_n, gamma, (1.0 - alpha_m) / (beta_n * dt * dt),
                        gamma / (beta_n * dt))


class LinearSystem:
    """The linear part of a model in its coordinates q (u = u0 + T q).

    mass, stiffness  M and K: a diagonal (1-D array) and a scipy sparse matrix
                     (the full model), or dense 2-D arrays (the reduced model)
    contact_dofs     (contacts, 3) the q index of each contact node's X, Y, Z
    drive_index, drive_x, drive_y
                     x_A = sum drive_x q[drive_index], y_A likewise (model/drive.py)
    expand           q -> T q, the node displacement field (for frames and fields)
    rigid            a rigid motion of the block's nodes (dofs,) -> its q (T q equals it:
                     the basis spans rigid motions, cycle_map.py)
    """

    def __init__(self, mass, stiffness, contact_dofs, drive_index, drive_x, drive_y, expand,
                 rigid):
        self.mass = mass
        self.stiffness = stiffness
        self.contact_dofs = np.ascontiguousarray(contact_dofs, dtype=np.int64)
        self.drive_index = np.ascontiguousarray(drive_index, dtype=np.int64)
        self.drive_x = np.ascontiguousarray(drive_x, dtype=float)
        self.drive_y = np.ascontiguousarray(drive_y, dtype=float)
        self.expand = expand
        self.rigid = rigid

    @property
    def size(self) -> int:
        return self.stiffness.shape[0]

    @property
    def dense(self) -> bool:
        return isinstance(self.stiffness, np.ndarray)


def full_system(model) -> LinearSystem:
    """The full model: q = u - u0, every DOF."""
    contacts = model.contact_nodes
    weights = model.attach_weights
    index = 3 * model.attach_nodes
    return LinearSystem(model.disc.mass, model.stiffness,
                        3 * contacts[:, None] + np.arange(3)[None, :],
                        np.concatenate([index, index + 1]),
                        np.concatenate([weights, np.zeros_like(weights)]),
                        np.concatenate([np.zeros_like(weights), weights]),
                        lambda q: q, lambda motion: motion)


def contact_tangent(model, scene, c_v) -> np.ndarray:
    """l: (3 contacts,) the contact forces' tangent per contact DOF (see the docstring)."""
    tangent = np.empty((model.contact_nodes.size, 3))
    tangent[:, 0] = tangent[:, 1] = scene.law_bounds.stiffness * model.area_share
    tangent[:, 2] = model.penalty_share * (1.0 + model.beta * c_v)
    return tangent.ravel()


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def predictors(q, v, a, scheme, qt, vt, x1, x2):
    """The predictors q~, v~ (q_{n+1} = q~ + beta_N dt^2 a_{n+1}, v_{n+1} = v~ + gamma dt
    a_{n+1}) and the vectors b_n multiplies by M and K: x1 = c_M q~ - alpha_m a_n,
    x2 = beta ((1 - af)(v~ - c_V q~) + af v_n) + af q_n."""
    dt, alpha_m, alpha_f, beta_n = scheme.dt, scheme.alpha_m, scheme.alpha_f, scheme.beta_n
    gamma, c_m, c_v, beta = scheme.gamma, scheme.c_m, scheme.c_v, scheme.beta
    for k in range(q.shape[0]):
        qt[k] = q[k] + dt * v[k] + dt * dt * (0.5 - beta_n) * a[k]
        vt[k] = v[k] + dt * (1.0 - gamma) * a[k]
        x1[k] = c_m * qt[k] - alpha_m * a[k]
        x2[k] = beta * ((1.0 - alpha_f) * (vt[k] - c_v * qt[k]) + alpha_f * v[k]) + alpha_f * q[k]


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def free_response(q, v, a, friction, normal, f_d_old, f_hold_old, operators, normal0, scheme,
                  prescribed, work):
    """y = A^-1 b_n (work.y): the step's end without the part of the contact and drive
    forces the matrix does not hold, with

        b_n = M (c_M q~ - alpha_m a_n) - K (beta ((1-af)(v~ - c_V q~) + af v_n) + af q_n)
              + alpha_f r_n - P_z N0

    (r_n the contact forces P f_c and the drive's d_x F_d, and d_y F_hold for a
    drive held in Y, at step n); also fills the predictors work.qt, work.vt."""
    mass, stiffness, inv = operators.mass, operators.stiffness, operators.inv
    contact_dofs, drive_index = operators.contact_dofs, operators.drive_index
    drive_x, drive_y = operators.drive_x, operators.drive_y
    x1, x2, r1, r2, rhs = work.x1, work.x2, work.r1, work.r2, work.rhs
    alpha_f = scheme.alpha_f
    predictors(q, v, a, scheme, work.qt, work.vt, x1, x2)
    apply(mass, x1, r1)
    apply(stiffness, x2, r2)
    for k in range(q.shape[0]):
        rhs[k] = r1[k] - r2[k]
    for c in range(contact_dofs.shape[0]):
        rhs[contact_dofs[c, 0]] -= alpha_f * friction[c, 0]
        rhs[contact_dofs[c, 1]] -= alpha_f * friction[c, 1]
        rhs[contact_dofs[c, 2]] += alpha_f * normal[c] - normal0[c]
    for k in range(drive_index.shape[0]):
        rhs[drive_index[k]] += alpha_f * drive_x[k] * f_d_old
    if prescribed:
        for k in range(drive_index.shape[0]):
            rhs[drive_index[k]] += alpha_f * drive_y[k] * f_hold_old
    solve(inv, rhs, work.y)


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def newmark_update(q, v, a, q_new, qt, vt, beta_n, gamma, dt):
    """The step's end: a_{n+1} = (q_{n+1} - q~) / (beta_N dt^2), v_{n+1} = v~ + gamma dt a_{n+1},
    q = q_{n+1}."""
    for k in range(q.shape[0]):
        a_new = (q_new[k] - qt[k]) / (beta_n * dt * dt)
        v[k] = vt[k] + gamma * dt * a_new
        a[k] = a_new
        q[k] = q_new[k]
