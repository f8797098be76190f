"""The energy balance of an FE run (scene fem.energy): input, storage, dissipation.

The implicit integrators' first; the explicit one's shadow form below (explicit_energy_step).

Energies are measured from the static preload u0 (q = u - u0, v the velocity).
What goes in, accumulated step by step with the forces the integrator used
over the step (generalized-alpha: F_bar = (1 - alpha_f) F_{n+1} + alpha_f F_n):

    W_drive  += F_d,bar v_d dt                 the drive point B pulling the spring (eq 17)
    W_base   += sum_i -F_i,bar . db            the base carrying the asperities' free ends,
                                               db = (dx_b, eta_y dy_b) (phase 1 and eq 30)
              + sum_i N_i,bar dz_b             and pushing the nodes up as it moves along Z

What is stored, at every recorded row:

    E_kin = 1/2 v^T M v
    E_el  = 1/2 q^T K q + sum_i E_pen,i        the block and its penalty springs under the
                                               dead loads: their potential above the preload's
          + F_d^2 / (2 k_d)                    the drive spring
          + sum_i E_law,i                      the friction law's stored energy (Dahl:
                                               k_t w_i s_i^2 / 2, eq 1)

    E_pen,i = N0_i q_z + k_i max(0, -g)^2 / 2 - k_i max(0, -g0)^2 / 2   (the gap
    g = g0_i + u0_z + q_z - z_b, contact.py, g0 = g0_i + u0_z at the preload; k_i =
    k_pen w_i, N0_i the preload reaction): 1/2 k_i q_z^2 while in contact on a base at
    rest, and >= 0 always (the preload minimizes the convex potential).

What is dissipated, per step:

    D_fric += sum_i F_i,bar . (du_i - db) - d E_law,i
              the work put into node i's asperity minus what it stores: the
              slip work (paper Fig. 1: N' moves by du_i, M is carried by db
              and slides); >= 0 for the Dahl law (k |v_r| s^2 / s_c per unit time)
    D_damp += beta dq^T K dq / dt              Rayleigh damping C = beta K of the block
            + sum_i beta k_i dg_i^2 / dt       the penalty dashpots, on the nodes in
                                               contact at both ends of the step
                                               (dg = dq_z - dz_b)
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

import numpy as np
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
def penalty_energy(q_z, u0_z, normal0, penalty, gap0, z_b):
    """E_pen,i of one node (see the module docstring), its gap g0_i + u_z - z_b."""
    gap = min(0.0, gap0 + u0_z + q_z - z_b)
    rest = min(0.0, gap0 + u0_z)
    return normal0 * q_z + 0.5 * penalty * (gap * gap - rest * rest)



@law_kernel(cache=True, error_model="numpy")
def add_contact_work(q_old, q_new, contact_dofs, penalty_share, area_share, params,
                     states_old, states_new, force_old, force_new, normal_old, normal_new,
                     alpha_f, db_x, db_y, z_b, z_b_new, beta, dt, sums):
    """Add one step's base work, friction and penalty-dashpot dissipation to ``sums``.

    q_old, q_new        the coordinates at the start and end of the step
    contact_dofs        (n, 3) each contact node's X, Y, Z index in q
    area_share          (n,) w_i; params the law's parameters
    z_b, z_b_new        the base's Z at the start and end of the step
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
        # the normal force's work: the base's through dz_b; the penalty dashpot's on the
        # gap's change dg = dq_z - dz_b, on the nodes in contact at both ends of the step
        dz_b = z_b_new - z_b
        sums[SUM_W_BASE] += (a * normal_new[c] + alpha_f * normal_old[c]) * dz_b
        if normal_old[c] > 0.0 and normal_new[c] > 0.0:
            sums[SUM_D_DAMP] += beta * penalty_share[c] * (q_new[iz] - q_old[iz] - dz_b) ** 2 / dt


@law_kernel(cache=True, error_model="numpy")
def stored(q, v, mass_v, stiffness_q, contact_dofs, u0_z, initial_gap, z_b, normal0,
           penalty_share, area_share, params, states, f_d, k_d):
    """(E_kin, E_el) of the state; mass_v = M v and stiffness_q = K q already computed."""
    kinetic = elastic = 0.0
    for k in range(q.shape[0]):
        kinetic += 0.5 * v[k] * mass_v[k]
        elastic += 0.5 * q[k] * stiffness_q[k]
    for c in range(contact_dofs.shape[0]):
        elastic += penalty_energy(q[contact_dofs[c, 2]], u0_z[c], normal0[c], penalty_share[c],
                                  initial_gap[c], z_b)
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


# The explicit integrator's balance (central differences), in its shadow form.
#
# Central differences, v_{n+1/2} = v_{n-1/2} + dt M^-1 f_n, u_{n+1} = u_n + dt v_{n+1/2},
# keep one identity exactly: with du_n = (u_{n+1} - u_{n-1}) / 2 = dt (v_{n+1/2} + v_{n-1/2}) / 2,
#
#     1/2 v_{n+1/2}^T M v_{n+1/2} - 1/2 v_{n-1/2}^T M v_{n-1/2} = f_n^T du_n,
#
# the kinetic energy at the half steps changing by the step's force times the mid-step
# displacement. Each force's work f_n^T du_n then telescopes into a "shadow" energy at
# n + 1/2 where the force is linear: a spring k x_n stores k x_n x_{n+1} / 2 (the
# product of its two ends), for the block (1/2 q_n^T K q_{n+1}), the drive spring
# (F_d,n F_d,n+1 / (2 k_d)) and each penalty spring (k_i m_n m_{n+1} / 2 with
# m = min(0, g), g the node's gap). So a row recorded at step n + 1 holds
#
#     E_kin = 1/2 v_{n+1/2}^T M v_{n+1/2}
#     E_el  = 1/2 q_n^T K q_{n+1}
#             + sum_i [N0_i (q_z,n + q_z,n+1) / 2 + k_i (m_n m_{n+1} - m_0^2) / 2]
#             + F_d,n F_d,n+1 / (2 k_d) + sum_i E_law,i(s_{n+1})
#
# and the sums add each step's mid-step works:
#
#     W_drive += F_d,n v_d dt
#     W_base  += sum_i [-F_i,n . db_n + N_i,n dz_b,n]         db, dz_b: the base's mid-step
#     D_fric  += sum_i F_i,n . (du_i - db_n) - d E_law,i           displacements
#     D_damp  += beta (K v_{n-1/2})^T du_n                        Rayleigh, lagging velocity
#              + sum_i -(N_i,n - S_i,n) (du_z,i - dz_b,n)         the penalty dashpots
#                                                                 (S = k_i max(0, -g), the spring)
#
# The balance then closes to rounding except where the penalty's force is not linear
# over the three points n - 1, n, n + 1: the steps around a node's touch-down or
# lift-off, where k_i m_n (m_{n+1} - g_{n+1}) / 2 is left over. That is what an impact
# injects (or takes), and what energy_closure measures (energy_closure below).


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def _explicit_vectors(u, u0, v, v_old, inverse_mass, k_q, k_v, beta, dt, sums):
    """Add the Rayleigh damping's mid-step work to sums; return (E_kin at n + 1/2,
    1/2 q_n^T K q_{n+1}); k_q = K q_n and k_v = K v_{n-1/2} computed before the step."""
    kinetic = shadow = damping = 0.0
    for k in range(u.shape[0]):
        du = 0.5 * dt * (v[k] + v_old[k])
        damping += k_v[k] * du
        kinetic += 0.5 * v[k] * v[k] / inverse_mass[k]
        shadow += 0.5 * k_q[k] * (u[k] - u0[k])
    sums[SUM_D_DAMP] += beta * damping
    return kinetic, shadow


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def _penalty_step(contact_nodes, u0, u, v, v_old, initial_gap, disp, penalty_share, normal0,
                  normal, friction, z_b, z_b_new, dz_b, db_x, db_y, dt, sums):
    """The contact's share of one explicit step (the module's shadow form): the base's
    work through the normal and friction forces of step n, the penalty dashpots', the
    friction's work on the slip; returns the penalty springs' shadow energy at n + 1/2."""
    stored = 0.0
    for c in range(contact_nodes.shape[0]):
        d = 3 * contact_nodes[c]
        k_i = penalty_share[c]
        gap0 = initial_gap[c] + u0[d + 2]
        g_n = initial_gap[c] + disp[c, 2] - z_b
        g_new = initial_gap[c] + u[d + 2] - z_b_new
        m_n, m_new, m_0 = min(0.0, g_n), min(0.0, g_new), min(0.0, gap0)
        stored += (0.5 * normal0[c] * (disp[c, 2] + u[d + 2] - 2.0 * u0[d + 2])
                   + 0.5 * k_i * (m_n * m_new - m_0 * m_0))
        du_x = 0.5 * dt * (v[d] + v_old[d])
        du_y = 0.5 * dt * (v[d + 1] + v_old[d + 1])
        du_z = 0.5 * dt * (v[d + 2] + v_old[d + 2])
        spring = -k_i * m_n
        sums[SUM_W_BASE] += normal[c] * dz_b - friction[c, 0] * db_x - friction[c, 1] * db_y
        sums[SUM_D_DAMP] -= (normal[c] - spring) * (du_z - dz_b)
        sums[SUM_D_FRIC] += friction[c, 0] * (du_x - db_x) + friction[c, 1] * (du_y - db_y)
    return stored


@law_kernel(cache=True, error_model="numpy")
def law_energies(states, params, area_share):
    """sum_i E_law,i: the friction law's stored energy over the nodes."""
    total = 0.0
    for c in range(states.shape[0]):
        total += law_energy(states[c], params, area_share[c])  # noqa: F821 (the law's)
    return total


def energy_closure(series, scene, steps: int) -> dict:
    """The balance over the last ``steps`` recorded rows (the steady cycles averaged
    over): what is left, (W_drive + W_base) - (E_kin + E_el + D_fric + D_damp), its
    change over the window, relative to the base's work in it (W_base's change):

        energy_closure = |d(W_in - E - D)| / |d W_base|

    0 for a balance that closes; the integrator's numerical dissipation (generalized-
    alpha with fem.rho_infinity < 1) and what impacts inject show here. Also the
    window's base work (J) and the friction's and damping's dissipation in it."""
    extra = series.extra
    if "W_base" not in extra:
        return {}
    cols = {name: np.asarray(extra[name][-steps:]) for name in recording.ENERGY}
    left = (cols["W_drive"] + cols["W_base"] - cols["E_kin"] - cols["E_el"] - cols["D_fric"]
            - cols["D_damp"])
    base = float(cols["W_base"][-1] - cols["W_base"][0])
    closure = abs(float(left[-1] - left[0])) / abs(base) if base != 0.0 else None
    return {"energy_closure": closure, "energy_base_work": base,
            "energy_friction_dissipation": float(cols["D_fric"][-1] - cols["D_fric"][0]),
            "energy_damping_dissipation": float(cols["D_damp"][-1] - cols["D_damp"][0])}


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def energy_before_step(u, u0, v, v_old, stiffness, k_q, k_v):
    """Before an explicit step: v_old = v_{n-1/2}, k_q = K q_n (q = u - u0), k_v = K v_{n-1/2}."""
    for k in range(u.shape[0]):
        v_old[k] = v[k]
        k_v[k] = u[k] - u0[k]
    apply(stiffness, k_v, k_q)
    apply(stiffness, v_old, k_v)


@law_kernel(cache=True, error_model="numpy", fastmath=FASTMATH)
def explicit_energy_step(u, u0, v, v_old, inverse_mass, k_q, k_v, beta, dt, contact_nodes,
                         initial_gap, disp, penalty_share, normal0, normal, friction, z_b,
                         z_b_new, dz_b, db_x, db_y, f_d, v_d, params, area_share, states, sums):
    """After an explicit step's update, before its contact update: add step n's mid-step
    works to ``sums`` (the shadow form above; dz_b, db_x, db_y the base's mid-step
    displacements, f_d = F_d,n) and the law's stored energy at its start to D_fric.
    Returns (E_kin, the shadow energies of the block and the penalty springs) at n + 1/2."""
    kinetic, shadow = _explicit_vectors(u, u0, v, v_old, inverse_mass, k_q, k_v, beta, dt, sums)
    shadow += _penalty_step(contact_nodes, u0, u, v, v_old, initial_gap, disp, penalty_share,
                            normal0, normal, friction, z_b, z_b_new, dz_b, db_x, db_y, dt, sums)
    sums[SUM_W_DRIVE] += f_d * v_d * dt
    sums[SUM_D_FRIC] += law_energies(states, params, area_share)
    return kinetic, shadow


@law_kernel(cache=True, error_model="numpy", fastmath=FASTMATH)
def explicit_energy_end(kinetic, shadow, f_d, f_d_new, k_d, params, area_share, states, sums):
    """After the contact update: the law's stored energy at its end leaves D_fric; returns
    (E_kin, E_el) at n + 1/2 (E_el with the drive spring's shadow F_d,n F_d,n+1 / (2 k_d))."""
    stored = law_energies(states, params, area_share)
    sums[SUM_D_FRIC] -= stored
    return kinetic, shadow + stored + 0.5 * f_d * f_d_new / k_d
