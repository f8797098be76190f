"""The energy balance of an implicit run (scene fem.energy): input, storage, dissipation.

Energies are measured from the static preload u0 (q = u - u0, v the velocity).
What goes in, accumulated step by step with the forces the integrator used
over the step (generalized-alpha: F_bar = (1 - alpha_f) F_{n+1} + alpha_f F_n):

    W_drive  += F_d,bar v_d dt                 the drive point B pulling the spring (eq 17)
    W_base   += sum_i -F_i,bar . db            the base carrying the asperities' free ends,
                                               db = (dx_b, eta_y dy_b) (phase 1 and eq 30)

What is stored, at every recorded row:

    E_kin = 1/2 v^T M v
    E_el  = 1/2 q^T K q + sum_i E_pen,i        the block and its penalty springs under the
                                               dead loads: their potential above the preload's
          + F_d^2 / (2 k_d)                    the drive spring
          + sum_i E_law,i                      the friction law's stored energy (Dahl:
                                               k_t w_i s_i^2 / 2, eq 1)

    E_pen,i = N0_i q_z + k_i max(0, -u_z)^2 / 2 - k_i u0_z^2 / 2   (u_z = u0_z + q_z,
    k_i = k_pen w_i, N0_i = -k_i u0_z the preload reaction): 1/2 k_i q_z^2 while in
    contact, and >= 0 always (the preload minimizes the convex potential).

What is dissipated, per step:

    D_fric += sum_i F_i,bar . (du_i - db) - d E_law,i
              the work put into node i's asperity minus what it stores: the
              slip work (paper Fig. 1: N' moves by du_i, M is carried by db
              and slides); >= 0 for the Dahl law (k |v_r| s^2 / s_c per unit time)
    D_damp += beta dq^T K dq / dt              Rayleigh damping C = beta K of the block
            + sum_i beta k_i dq_z,i^2 / dt     the penalty dashpots, on the nodes in
                                               contact at both ends of the step
              (both >= 0: the dampers' work at the step's mean velocity dq / dt)

For the trapezoidal rule (fem.rho_infinity = 1: alpha_m = alpha_f = 1/2,
gamma = 1/2, beta = 1/4) dq = dt (v_n + v_{n+1}) / 2, so dq^T M (a_n + a_{n+1}) / 2
= dE_kin, dq^T K (q_n + q_{n+1}) / 2 = d(q^T K q / 2), and the forces' work is
the sum above, exactly: the balance

    W_drive + W_base = E_kin + E_el + D_fric + D_damp

closes to the contact iteration's tolerance and rounding, except over the
steps in which a node touches down or lifts off (the penalty force has a
kink there, which the trapezoid does not follow): measured ~1e-7 of the work
put in at dt = 1e-5 s. With rho_infinity < 1 the scheme also dissipates in its high
frequencies; the difference of the two sides measures that numerical dissipation.
"""

from numba import njit

from ...friction_law import law_kernel
from ...friction_law.contract import FASTMATH
from ..model.drive import prescribed_position
from ..model.linalg import apply
from . import recording

# sums[]: the accumulated inputs and dissipations (each recorded row copies them into its
# columns recording.W_DRIVE ... D_DAMP: ``record``)
SUM_W_DRIVE, SUM_W_BASE, SUM_D_FRIC, SUM_D_DAMP = range(4)
SUMS = 4


@njit(cache=True, error_model="numpy")
def penalty_energy(q_z, u0_z, normal0, penalty):
    """E_pen,i of one node (see the module docstring)."""
    gap = min(0.0, u0_z + q_z)
    return normal0 * q_z + 0.5 * penalty * (gap * gap - u0_z * u0_z)


@law_kernel(cache=True, error_model="numpy")
def add_contact_work(q_old, q_new, contact_dofs, penalty_share, area_share, params,
                 states_old, states_new, force_old, force_new, normal_old, normal_new,
                 alpha_f, db_x, db_y, beta, dt, sums):
    """Add one step's base work, friction and penalty-dashpot dissipation to ``sums``.

    q_old, q_new        the coordinates at the start and end of the step
    contact_dofs        (n, 3) each contact node's X, Y, Z index in q
    area_share          (n,) w_i; params the law's parameters
    states_old, _new    (n, STATE_SIZE) the law's states at both ends
    force_*, normal_*   the friction (n, 2) and normal (n,) forces at both ends
    """
    a = 1.0 - alpha_f
    for c in range(contact_dofs.shape[0]):
        ix, iy, iz = contact_dofs[c, 0], contact_dofs[c, 1], contact_dofs[c, 2]
        fx = a * force_new[c, 0] + alpha_f * force_old[c, 0]
        fy = a * force_new[c, 1] + alpha_f * force_old[c, 1]
        sums[SUM_W_BASE] -= fx * db_x + fy * db_y
        sums[SUM_D_FRIC] += (fx * (q_new[ix] - q_old[ix] - db_x) + fy * (q_new[iy] - q_old[iy] - db_y)
                         - law_energy(states_new[c], params, area_share[c])  # noqa: F821
                         + law_energy(states_old[c], params, area_share[c]))  # noqa: F821
        if normal_old[c] > 0.0 and normal_new[c] > 0.0:
            sums[SUM_D_DAMP] += beta * penalty_share[c] * (q_new[iz] - q_old[iz]) ** 2 / dt


@law_kernel(cache=True, error_model="numpy")
def stored(q, v, mass_v, stiffness_q, contact_dofs, u0_z, normal0, penalty_share,
           area_share, params, states, f_d, k_d):
    """(E_kin, E_el) of the state; mass_v = M v and stiffness_q = K q already computed."""
    kinetic = elastic = 0.0
    for k in range(q.shape[0]):
        kinetic += 0.5 * v[k] * mass_v[k]
        elastic += 0.5 * q[k] * stiffness_q[k]
    for c in range(contact_dofs.shape[0]):
        elastic += penalty_energy(q[contact_dofs[c, 2]], u0_z[c], normal0[c], penalty_share[c])
        elastic += law_energy(states[c], params, area_share[c])  # noqa: F821 (the law's)
    return kinetic, elastic + 0.5 * f_d * f_d / k_d


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def add_damping_and_drive_work(q_old, q_new, stiffness, beta, dt, t, f_d, f_d_old, alpha_f,
                               v_d, prescribed, dq, k_dq, sums):
    """Add one step's Rayleigh dissipation beta dq^T K dq / dt and the drive's work
    F_d,bar (x_B(t) - x_B(t - dt)) (F_d,bar = (1 - af) F_d + af F_d,old; x_B moves at
    v_d, a prescribed drive as drive.prescribed_position) to ``sums``; dq and k_dq
    are scratch vectors."""
    for k in range(q_old.shape[0]):
        dq[k] = q_new[k] - q_old[k]
    apply(stiffness, dq, k_dq)
    rayleigh = 0.0
    for k in range(q_old.shape[0]):
        rayleigh += dq[k] * k_dq[k]
    sums[SUM_D_DAMP] += beta * rayleigh / dt
    moved = (prescribed_position(t, v_d) - prescribed_position(t - dt, v_d)
             if prescribed else v_d * dt)
    sums[SUM_W_DRIVE] += ((1.0 - alpha_f) * f_d + alpha_f * f_d_old) * moved


@njit(cache=True, error_model="numpy")
def record(row, sums, kinetic, elastic):
    """The energy columns of a recorded row (recording.ENERGY) from the sums and the
    stored energies."""
    row[recording.W_DRIVE] = sums[SUM_W_DRIVE]
    row[recording.W_BASE] = sums[SUM_W_BASE]
    row[recording.E_KIN] = kinetic
    row[recording.E_EL] = elastic
    row[recording.D_FRIC] = sums[SUM_D_FRIC]
    row[recording.D_DAMP] = sums[SUM_D_DAMP]
