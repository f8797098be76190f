"""How the FE body starts when the base also moves along Z (vibration.normal_amplitude > 0).

The base comes on at t_on at z_b = A_n sin(phi), dz_b/dt = A_n w cos(phi): a body
left at rest there would be struck (phi != 0) and, in any case, set bouncing
freely on its contact at its bounce frequency w_b, by about k_b A_n r / |1 - r^2|
(r = w / w_b), 1/r times its forced swing (analytic/normal.py says the same of the
lumped body: on the paper's block, r = 0.18, that free bounce alone lost contact
at half the forced threshold, and a bouncing orbit was a second attractor). So, as
the lumped model does (analytic/normal.py start_gain), the body starts on its
forced response in contact: the explicit integrator at the state of the first step
on (first_step_on, its time t_1 >= t_on: u at t_1 and v at t_1 - dt/2, before the
contact sees the base), the implicit ones at the state a step before (t_1 - dt, their
base then moving along its sinusoid from there, not jumping within the step; the
nodes' normal forces set afresh), the body is put, rigidly (every node moved alike
in Z), on

    z_face = H_face z_b,   dz/dt = H dz_b/dt,   H = 1 / (1 - (w / w_b)^2),
    H_face = 1 + (k_b / k_pen) (H - 1)

with w_b the block's first bounce mode on its penalty springs (core/bounce.py:
the block as a bar on the spring k_pen; k_b = m w_b^2): the body's centre moves
by H z_b, and its contact face, its mean height set, where the penalty carries the
contact force's forced swing k_b (z_b - H z_b) (a face set at H z_b would open its
gap by (H - 1) z_b, 5 times what the swing takes on the paper's block, where
k_b = 0.2 k_pen: measured, the contact lost at the start). What the rigid shift
leaves of the free bounce (the bar's quasi-static compression under the body's
acceleration is not set) decays on the penalty dashpots (beta k_pen w_i, a damping
ratio beta w_b / 2 ~ 3e-3: e-folding in ~50 bounce periods, ~2 ms on the paper's
block) and, where the contact opens, in the impacts' dashpot losses. The steady
cycle is then the forced one: the averaging window (time.T - t_on of at least the
averaged cycles, scene/validation.py) starts tens of those decay times later in
the shipped scenes' timing; the summed normal force's judgement (outputs/
normal_swing.py) reports a window still carrying the bounce as "transient".

Where the contact is lost for part of the cycle the steady orbit is reached the
same way, by the impacts' losses; a scene with a second, bouncing attractor (the
lumped model found one at 0.9 of the contact-loss threshold when started at rest)
starts off it.
"""

import math

from numba import njit

from ...core.base_motion import first_step_on as base_first_step_on
from ...core.base_motion import normal_displacement
from ...core.base_table import moves_along_z, table_speed_z
from ...core.bounce import bounce_stiffness
from ...core.law_limits import NORMAL_LIMIT
from ...friction_law.contract import FASTMATH
from ..model.contact import normal_force


def first_step_on(scene) -> int:
    """The first step at or past vibration.t_on (core.base_motion.first_step_on)."""
    return base_first_step_on(scene.vibration.t_on, scene.time.dt)


def bounce_frequency(model, scene) -> float:
    """w_b (rad/s): the block's first bounce mode on its penalty springs (core/bounce.py)."""
    k_b = bounce_stiffness(model.block_mass, scene.body.E, model.density, scene.body.size,
                           model.penalty)
    return math.sqrt(k_b / model.block_mass)


def normal_force_limit(scene, model) -> float:
    """The summed normal force past which a run has diverged (outputs/trouble.py):
    NORMAL_LIMIT times the largest the physics explains, F_N at rest and, where the base
    moves along Z, F_N plus the force of the body meeting its contact at the base's
    speed amplitude A_n w (plus a table's largest dz_b/dt, core/base_table.py
    table_speed_z), A_n w sqrt(k_b m) (a rigid body on the bounce stiffness
    k_b = m w_b^2: 5.5 times the forced swing m w^2 A_n on the paper's block). The
    impacts of a body losing contact reach several F_N (at 1.3 times the threshold on
    the paper's block the coarse mesh's exceeded 10 F_N) and are physics; a diverging
    run grows past any such bound within a few steps."""
    F_N = scene.contact.F_N
    vib = scene.vibration
    if not moves_along_z(vib):
        return NORMAL_LIMIT * F_N
    speed = vib.normal_amplitude * scene.omega + table_speed_z(vib, scene.omega)
    impact = speed * model.block_mass * bounce_frequency(model, scene)
    return NORMAL_LIMIT * (F_N + impact)


def start_gain(scene, model):
    """(H_face, H): the forced response to the base's normal motion (module docstring)
    of the contact face's height, z_face = H_face z_b, and of the body's speed,
    dz/dt = H dz_b/dt, H = 1 / (1 - (w / w_b)^2). The body's centre moves by H z_b on
    the bounce stiffness k_b = m w_b^2, which is the penalty k_pen and the block's own
    compliance in series; the face sits where the penalty carries the contact force's
    swing k_b (z_b - H z_b): z_face = z_b + (k_b / k_pen) (H - 1) z_b."""
    w_b = bounce_frequency(model, scene)
    r = scene.omega / w_b
    H = 1.0 / (1.0 - r * r)
    k_b = model.block_mass * w_b * w_b
    return (1.0 + k_b / model.penalty * (H - 1.0), H)


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def start_motion(u, reference, v, lift, face_z, area_share, gain, t, dt, t_on, amplitude_n,
                 omega, sin_n, cos_n, lag, table_z, table_vz):
    """Put the body, rigidly along ``lift`` (every node's Z, in the integrator's
    coordinates), on its forced response to the base (gain = (H_face, H), start_gain):
    its contact face's mean height from the preload (``reference``),
    sum_i w_i (u - reference)[face_z[i]], to H_face z_b at t, its mean Z velocity to
    H dz_b/dt at t - lag dt (lag: 1/2 for central differences' half-step velocity, 0
    for the implicit state).
    Set, not added: whatever the base's first step did to the body (a base starting at
    phi != 0 jumps by A_n sin phi) is replaced. The body must be at its place to a small
    fraction of the base's amplitude: the contact turns a misplacement dz into a force
    k_pen dz (k_pen A_n ~ 60 F_N on the stiff block of benchmarks/fe_normal_vs_lumped.py).
    ``table_z``, ``table_vz``: a base motion given per step (core/base_table.py), its z_b
    at t and dz_b/dt at t - lag dt, added to the sine's (0 without one); the gain is the
    sine's, at w (for a harmonic of order n > 1 the start of a free bounce, as in the
    lumped model)."""
    phase = omega * (t - t_on)
    z_b, _ = normal_displacement(amplitude_n, omega, sin_n, cos_n, math.sin(phase),
                                 math.cos(phase))
    _, v_lag = normal_displacement(amplitude_n, omega, sin_n, cos_n,
                                       math.sin(phase - omega * lag * dt),
                                       math.cos(phase - omega * lag * dt))
    z_b += table_z      # a motion given per step: its z_b at t, dz_b/dt at t - lag dt
    v_lag += table_vz
    z_face = v_face = 0.0
    for c in range(face_z.shape[0]):
        z_face += area_share[c] * (u[face_z[c]] - reference[face_z[c]])
        v_face += area_share[c] * v[face_z[c]]
    dz = gain[0] * z_b - z_face
    dv = gain[1] * v_lag - v_face
    for k in range(u.shape[0]):
        u[k] += lift[k] * dz
        v[k] += lift[k] * dv


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def restart_normal_forces(q, v, contact_dofs, u0_z, initial_gap, penalty_share, beta, z_b, v_zb,
                          tangent, assumed, normal, g_prev):
    """The contact nodes' normal forces at a state just moved (start_motion), against
    the base at z_b, v_zb (contact.normal_force), and the implicit contact iteration's
    first iterate g_z = N + l q_z (contact_solve._contact_g) with them. Returns the
    summed normal force's change (N): the body's acceleration changes by it over its mass."""
    change = 0.0
    for c in range(contact_dofs.shape[0]):
        iz = contact_dofs[c, 2]
        gap = initial_gap[c] + (u0_z[c] + q[iz]) - z_b
        before = normal[c]
        normal[c] = normal_force(gap, v[iz] - v_zb, penalty_share[c], beta)
        change += normal[c] - before
        g_prev[3 * c + 2] = normal[c] + tangent[3 * c + 2] * assumed[c] * q[iz]
    return change
