"""The scene's friction law as every stepper checks it: the force past which an
update has diverged, and the step that resolves the slip."""

import math

from .base_table import plane_speed

# No law reaches beyond its largest friction coefficient (friction_law.Bounds)
# for long: a force past a few times that has diverged.
DIVERGED = 3.0
# A summed normal force beyond NORMAL_LIMIT times F_N is numerical divergence, not
# physics (fem/outputs/trouble.py); a base moving along Z further into the body in one
# step than the penalty's penetration at that force is refused (scene/validation.py).
NORMAL_LIMIT = 10.0


def divergence_force(scene) -> float:
    """Friction force (N, whole contact) past which an update has diverged."""
    return DIVERGED * scene.mu_max * scene.contact.F_N


# The two-phase update (base phase, then body phase, eqs 28-30) splits each
# step, with an error first order in the slip a step makes against the
# sliding length s_c = F_c / k_t. It is largest where the sliding direction
# turns (oblique vibration, 2D): F_dv/F_d0 at k_v = 20, theta = 75 deg
# (scenes/coupled.toml) against dt = 2.5e-7 s is -1.1% at 1e-6 s, where the
# fastest slip makes 0.14 s_c a step, and -3.3% at 2.5e-6 s.
SLIP_PER_STEP = 0.05


def sliding_length(scene) -> float:
    """The law's sliding length at the scene's normal load (Dahl: s_c = F_c / k_t), m;
    infinite without friction (nothing to resolve)."""
    if scene.F_c <= 0.0:
        return math.inf
    return scene.law_bounds.sliding_length(scene.contact.F_N)


def slip_resolving_step(scene, speed: float | None = None) -> float:
    """The step in which the fastest sliding, v_a + v_d (or ``speed``), moves
    SLIP_PER_STEP of the law's sliding length. (v_a: the base's largest in-plane speed,
    with a motion given per step too: core.base_table.plane_speed.)

    At it the two-phase split errs by ~0.4% of F_dv in the worst case above
    (~0.1% or less along the axes). Infinite without friction.
    """
    if speed is None:
        speed = plane_speed(scene.vibration, scene.omega, scene.v_a) + scene.drive.v_d
    return SLIP_PER_STEP * sliding_length(scene) / speed


def slip_per_step(scene) -> float:
    """The slip of one time.dt at the fastest sliding, v_a + v_d, in sliding lengths
    s_c (0 without friction): what a stiff contact raises."""
    return SLIP_PER_STEP * scene.time.dt / slip_resolving_step(scene)


# The lumped model's converged reference takes at most this step and at most
# slip_resolving_step (Fig 7 scene: F_dv/F_d0 -0.65% at 1e-5 s against 1e-6 s,
# within 3e-5 of 1e-8 s at 1e-6 s; k_v = 20 at 75 deg: -1.1% at 1e-6 s).
REFERENCE_DT = 1e-6


def slip_resolved(scene):
    """The scene at a step that resolves the slip (at most REFERENCE_DT and
    slip_resolving_step): the lumped stepper as the reference the FE model is
    measured against (tests, benchmarks). A run answers at the scene's own time.dt."""
    dt = min(scene.time.dt, REFERENCE_DT, slip_resolving_step(scene))
    if dt == scene.time.dt:
        return scene
    return scene.with_values({"time.dt": dt})
