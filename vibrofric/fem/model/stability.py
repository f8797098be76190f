"""The explicit stable step, and the default stiffness-proportional damping.

Central difference with lumped mass M and Rayleigh damping C = beta K is stable
while (e.g. Belytschko, Liu & Moran, Nonlinear Finite Elements, section 6.3)

    dt <= dt_crit = (2 / w_max) (sqrt(1 + xi^2) - xi),     xi = beta w_max / 2,

with w_max^2 the largest eigenvalue of M^-1 K_total and xi the damping ratio
of that highest mode. K_total is everything that acts as a stiffness in the
loop: the block's K, the contact penalty springs k_pen w_i (Z), the contact's
tangential stiffness (Dahl's tangent dF/d(slip) = k (1 - sgn(v_r) s / s_c) is
at most 2 k_t w_i, on a reversal at full stretch; X and Y), and the drive
spring k_d w w^T (X).

w_max is found by Lanczos iteration (scipy eigsh, ARPACK) on the symmetric
form M^-1/2 K_total M^-1/2: the same largest eigenvalue as a power iteration on
M^-1 K_total, converged to 1e-8 in tens of products instead of thousands.
"""

import math

import numpy as np
import scipy.sparse.linalg as sla

# Default damping (scene fem.damping = 0): stiffness-proportional Rayleigh
# damping beta = 2 XI_MAX / w_max, i.e. a damping ratio XI_MAX in the mesh's
# highest mode and xi(w) = XI_MAX w / w_max below it.  See fe_model.py (DAMPING)
# for what this has to damp and why this value.
XI_MAX = 0.06


def max_frequency(stiffness, mass, contact_nodes, penalty_share, tangential_share,
                  drive_action=None, tol=1e-8) -> float:
    """w_max (rad/s): sqrt of the largest eigenvalue of M^-1 K_total."""
    dofs = stiffness.shape[0]
    diagonal = np.zeros(dofs)
    diagonal[3 * contact_nodes + 2] = penalty_share
    diagonal[3 * contact_nodes] = diagonal[3 * contact_nodes + 1] = tangential_share
    scale = 1.0 / np.sqrt(mass)

    def product(x):
        x = np.asarray(x).ravel()
        y = scale * x
        out = stiffness @ y + diagonal * y
        if drive_action is not None:
            out += drive_action(y)
        return scale * out

    operator = sla.LinearOperator((dofs, dofs), matvec=product, dtype=float)
    if dofs <= 12:  # ARPACK wants k < n - 1 with room to spare: do it densely
        dense = np.column_stack([product(e) for e in np.eye(dofs)])
        return math.sqrt(np.linalg.eigvalsh(0.5 * (dense + dense.T))[-1])
    start = np.random.default_rng(0).standard_normal(dofs)  # reproducible
    eigenvalue = sla.eigsh(operator, k=1, which="LA", tol=tol, v0=start,
                           return_eigenvectors=False)[0]
    return math.sqrt(eigenvalue)


def critical_step(omega_max: float, beta: float) -> float:
    """dt_crit = (2 / w_max)(sqrt(1 + xi^2) - xi), xi = beta w_max / 2."""
    xi = 0.5 * beta * omega_max
    return 2.0 / omega_max * (math.sqrt(1.0 + xi * xi) - xi)


def default_damping(omega_max: float) -> float:
    """beta (s) giving the highest mode the damping ratio XI_MAX."""
    return 2.0 * XI_MAX / omega_max
