"""Numerical trouble: what every integrator checks after each step, and what it says.

A run in trouble stops at once and is reported as core.errors.NumericalError
naming the time, the step and what went wrong, with a hint for the scene.
"""

import math

from numba import njit

from ...core.errors import ContactBeyondInterface, NumericalError
from ...core.law_limits import DIVERGED, NORMAL_LIMIT

# Codes returned by the time loops, and what they mean.
OK, NOT_FINITE, FRICTION_DIVERGED, NORMAL_BLOWUP, LIFT_OFF, NOT_CONVERGED, BEYOND_INTERFACE = \
    range(7)

# A summed friction force beyond DIVERGED times its Coulomb limit, or a summed
# normal force beyond NORMAL_LIMIT (core/law_limits.py) times F_N, is numerical
# divergence, not physics (a Dahl asperity never exceeds its sliding length; the normal
# load is F_N).

_WHAT = {
    NOT_FINITE: "a force became NaN or infinite",
    FRICTION_DIVERGED: f"the summed friction force exceeded {DIVERGED} times its Coulomb limit "
                       "(a diverging asperity update)",
    NORMAL_BLOWUP: f"the summed normal force exceeded {NORMAL_LIMIT} F_N (with a base moving "
                   f"along Z, {NORMAL_LIMIT} times F_N plus the impact at the base's speed)",
    LIFT_OFF: "the body lost all contact with the base (summed normal force 0)",
    NOT_CONVERGED: "the contact iteration of the step did not converge (nodes lifting off and "
                   "touching down within the step: the body is bouncing on its contact, or "
                   "the step is too long for the friction law)",
}


@njit(cache=True, error_model="numpy")
def step_trouble(f_d, f_n, friction_magnitude, F_N, mu_max, normal_limit, lifts_off):
    """The trouble code of a finished step (OK if none). ``normal_limit``: the summed
    normal force past which it has diverged (normal_start.normal_force_limit: NORMAL_LIMIT
    F_N with a base at rest in Z); ``lifts_off``: the base moves along Z, and a face out
    of contact (f_n = 0) is the motion's, not trouble."""
    if not (math.isfinite(f_d) and math.isfinite(f_n) and math.isfinite(friction_magnitude)):
        return NOT_FINITE
    if f_n > normal_limit:
        return NORMAL_BLOWUP
    if f_n <= 0.0 and not lifts_off:
        return LIFT_OFF
    if friction_magnitude > DIVERGED * mu_max * max(f_n, F_N):
        return FRICTION_DIVERGED
    return OK


def failure(step, code, scene, hint) -> NumericalError:
    """The error for a run that stopped at ``step`` with ``code``; ``hint`` says what to change.

    The paper's explicit Dahl update diverging gets its own hint whatever the integrator.
    A body that left the base (LIFT_OFF) keeps the integrator's hint: a step past the
    stable one throws the body off the base as often as it makes a NaN.
    """
    dt = scene.time.dt
    if code == BEYOND_INTERFACE:     # physics the reduced model left out, not numbers
        return ContactBeyondInterface(
            f"at t = {step * dt:.6g} s (step {step}) a contact candidate outside the reduced "
            "model's interface reached the base; raise fem.interface_reach or set it to "
            "\"all\"")
    if code == FRICTION_DIVERGED and scene.contact.law_values.get("update") == "paper":
        hint = ("the paper's explicit Dahl update is stable only while |v_r| dt < 2 s_c per node; "
                "use contact.update = \"exact\" or a smaller time.dt")
    return NumericalError(f"FE run failed at t = {step * dt:.6g} s (step {step}, dt = {dt:g} s): "
                          f"{_WHAT[code]}; {hint}")
