"""The linear part of an implicit step: generalized-alpha's coefficients, the
model's linear system in its coordinates q, and the contact's tangent that
the factorized matrix holds (implicit.py explains the scheme).

    alpha_m = (2 rho_inf - 1) / (rho_inf + 1),   alpha_f = rho_inf / (rho_inf + 1)
    gamma = 1/2 - alpha_m + alpha_f,             beta_N = (1 - alpha_m + alpha_f)^2 / 4
    c_M = (1 - alpha_m) / (beta_N dt^2),         c_V = gamma / (beta_N dt)
"""

from typing import NamedTuple

import numpy as np


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


def coefficients(rho_inf: float, dt: float) -> tuple:
    """(alpha_m, alpha_f, beta_N, gamma, c_M, c_V) of generalized-alpha for rho_inf and dt."""
    alpha_m = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0)
    alpha_f = rho_inf / (rho_inf + 1.0)
    gamma = 0.5 - alpha_m + alpha_f
    beta_n = 0.25 * (1.0 - alpha_m + alpha_f) ** 2
    return alpha_m, alpha_f, beta_n, gamma, (1.0 - alpha_m) / (beta_n * dt * dt), gamma / (beta_n * dt)


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
