"""The lumped model's answer with its step error: the same solver again at dt/2 and dt/4.

Every F_dv/F_d0 of the analytic steppers carries Richardson's estimate of its time
step's error (core/step_error.py): the answer F(h) at the step h the solver used
(time.dt, or the step nearest it that divides the base's cycle for the periodic
method: core.shooting.cycle_steps), and the same solver's answers at h/2 and h/4:

- a periodic answer: the orbits with 2n and 4n steps a cycle (and 8n where the
  three answers scatter: core.step_error.scattered), shot from the orbit at h (its
  state a cycle's start is the finer orbits' start, its Jacobian their Newton's
  first matrix: a few iterations each), their multipliers not judged again;
- a stepped answer (time.method transient, or the fallback of auto/periodic):
  the stepped runs through time.T at h/2 and h/4.

The two-phase update is first order in dt (fe_beside_analytic.ANALYTIC_DT), the
order assumed where it cannot be observed. With ~13 steps a cycle the answer
depends on where the steps fall in the cycle and the halvings need not converge
monotonically; the estimator then takes no order (step_error.richardson). Where
the estimate exceeds time.accuracy, step_meeting names a step that divides the
cycle and that the estimate says would meet it.
"""

import dataclasses
import math

import numpy as np

from ..core.errors import NumericalError
from ..core.series import averaging_steps
from ..core.step_error import StepError, not_estimated, richardson, scattered
from ..sense import RANGES
from .periodic import TOLERANCE, find_orbit
from .summary import cycle_average

FORMAL_ORDER = 1.0   # the two-phase update's order in dt
HALVINGS = 2         # answers at dt/2 and dt/4 beside the one at dt


def step_meeting(error: StepError, accuracy: float, f: float) -> float | None:
    """The longest step that divides the base's cycle (1/(f n), n whole) at or below
    the one the estimate says would bring it to ``accuracy``; None where the estimate
    already meets it or none was made."""
    h = error.step_for(accuracy, FORMAL_ORDER)
    if h is None:
        return None
    return 1.0 / (f * math.ceil(1.0 / (f * h) - 1e-9))


def halved(scene, dt: float):
    """The scene at the step ``dt``, a halving of its own: its other keys as they are.

    Not checked again (scene.with_values: 2 ms, two thirds of a periodic answer's
    estimate on Fig 7): a finer step keeps every check the scene passed (more steps
    a cycle, a smaller slip a step for the law) but time.dt's range, checked here
    (ValueError below it)."""
    if dt < RANGES["time.dt"][0]:
        raise ValueError(f"time.dt {dt:g} s is below its range")
    return dataclasses.replace(scene, time=dataclasses.replace(scene.time, dt=dt))


def periodic_error(scene, stepper: str, orbit, answer: float, F_d0: float) -> StepError:
    """The step error of a periodic answer ``answer`` (F_dv/F_d0 of ``orbit``, shot at
    orbit.dt with orbit.steps a cycle): orbits at 2n and 4n steps a cycle, each shot
    from the coarser one's state, and at 8n where those three scatter
    (step_error.scattered: a finer reference for the estimate, for a few milliseconds)."""
    answers = [(orbit.dt, answer)]
    start = orbit.z

    def halve() -> bool:
        """The orbit at half the finest step so far, appended to ``answers``."""
        nonlocal start
        try:
            finer_scene = halved(scene, answers[-1][0] / 2)
        except ValueError:      # a step below time.dt's range
            return False
        finer = find_orbit(finer_scene, stepper, start, plain_cycles=0, judge=False,
                           jacobian=orbit.jacobian)
        if not finer.converged:
            return False
        answers.append((finer.dt, float(np.mean(finer.cycle[:, 1])) / F_d0))
        start = finer.z
        return True

    while len(answers) <= HALVINGS and halve():
        pass
    if len(answers) < 2:
        return not_estimated(orbit.dt, scene.time.dt,
                             "the orbit at dt/2 did not converge from the one at dt, "
                             "or dt/2 is below time.dt's range")
    # the orbit's mean is converged to Newton's tolerance on forces scaled by F_c,
    # which the slowest multiplier m amplifies by 1/(1 - |m|) on the cycle's mean
    slowest = orbit.floquet_max_modulus if orbit.floquet.size else 0.0
    resolution = TOLERANCE * scene.F_c / F_d0 / max(1.0 - slowest, 1e-6)
    error = richardson(answers, scene.time.dt, FORMAL_ORDER, resolution)
    if scattered(error) and halve():
        error = richardson(answers, scene.time.dt, FORMAL_ORDER, resolution)
    return error


def stepped_error(scene, stepper: str, answer: float, F_d0: float, settled_to: float) -> StepError:
    """The step error of a stepped answer ``answer`` (F_dv/F_d0 at time.dt through
    time.T): the runs at dt/2 and dt/4. ``settled_to``: the answer's drift still to
    come (relative), below which their differences are not the step's."""
    from .solve import LOADERS, STEPPERS    # (solve imports this module)

    dt = scene.time.dt
    answers = [(dt, answer)]
    for k in range(1, HALVINGS + 1):
        try:
            finer = halved(scene, dt / 2**k)
            LOADERS[stepper](finer)
            series = STEPPERS[stepper](finer)
        except (NumericalError, ValueError):   # the stepper failed; a step below
            break                              # time.dt's range
        answers.append((dt / 2**k, cycle_average(series.F_d, averaging_steps(finer)) / F_d0))
    if len(answers) < 2:
        return not_estimated(dt, dt, "the stepped run at dt/2 failed, or dt/2 is below "
                                     "time.dt's range")
    return richardson(answers, dt, FORMAL_ORDER, settled_to * abs(answer))


def error_keys(error: StepError, scene) -> dict:
    """The summary's keys of the step error (StepError.as_dict), the accuracy asked
    (time.accuracy) and the step that would meet it (None where it is met)."""
    accuracy = scene.time.accuracy
    return {**error.as_dict(), "accuracy": accuracy,
            "dt_for_accuracy": step_meeting(error, accuracy, scene.vibration.f)}


def no_ratio(dt_used: float, scene) -> dict:
    """The step error's keys where there is no F_dv/F_d0 to estimate it on (F_d0 = 0)."""
    return error_keys(not_estimated(dt_used, scene.time.dt,
                                    "no friction to reduce (F_d0 = 0): F_dv/F_d0 is undefined"),
                      scene)
