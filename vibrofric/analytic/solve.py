"""Solve a scene with an analytic stepper: the time series and the summary (summary.json, docs/command-line.md)
(stepped through time.T, or the periodic orbit found directly)."""

from time import perf_counter

from ..core.series import averaging_steps, check_stepped_window
from ..core.step_error import not_estimated
from .accuracy import error_keys, no_ratio, periodic_error, stepped_error
from .coupled import load_coupled, run_coupled
from .longitudinal import load_longitudinal, run_longitudinal
from .normal import load_normal, moves_normally, normal_force_keys, run_normal
from .periodic import find_orbit, load_cycle, steady_series
from .summary import periodic_block, summarize, summarize_orbit

def _stepper(run, planar: bool):
    """``run``, or normal.run_normal where the base moves along Z (``planar``: coupled)."""
    def stepped(scene):
        return run_normal(scene, planar) if moves_normally(scene) else run(scene)
    return stepped


def _loader(load, planar: bool):
    """``load``, or normal.load_normal where the base moves along Z."""
    def loaded(scene):
        return load_normal(scene, planar) if moves_normally(scene) else load(scene)
    return loaded


# The lumped steppers by name; a scene whose base moves along Z runs the loop with the
# body's normal degree of freedom (normal.py), every other the existing loops unchanged.
STEPPERS = {"coupled": _stepper(run_coupled, True),
            "longitudinal": _stepper(run_longitudinal, False)}
LOADERS = {"coupled": _loader(load_coupled, True),
           "longitudinal": _loader(load_longitudinal, False)}


def solve(scene, stepper: str = "coupled", start=None, estimate: bool = True):
    """Integrate ``scene`` with the named stepper; return (TimeSeries, summary dict)
    (see solve_with_orbit)."""
    series, summary, _ = solve_with_orbit(scene, stepper, start, estimate)
    return series, summary


def solve_with_orbit(scene, stepper: str = "coupled", start=None, estimate: bool = True):
    """Integrate ``scene`` with the named stepper; return (TimeSeries, summary dict,
    the periodic orbit's state or None).

    With time.method "periodic" or "auto" the steady cycle is found directly
    (periodic.find_orbit, from ``start`` if given: a neighbour's orbit state) and the
    series is its last cycles; where the shooting does not converge or its orbit
    is not stable, the scene is stepped through T as with "transient", and the
    summary's "periodic" block says so. The summary's wall_time_s is the solving
    alone: the compiled loops are loaded from numba's cache (or compiled) before
    the clock starts, since that costs a new process the same whatever the scene.

    The summary carries the answer's step error (analytic/accuracy.py: the same
    solver at dt/2 and dt/4; error_estimate, dt_used, dt_asked, ...) and the time
    that took, error_wall_time_s (wall_time_s stays the answer's own). Without
    ``estimate`` (a measurement of the answer alone: the bench, a reference run)
    the keys are there and say that none was made.

    The summary's normal-force keys (normal.normal_force_keys) are over the steady
    cycles: the orbit's where it is the answer. A base moving along Z (normal.py) is
    shot for with the body's z, dz/dt and N in the state (periodic.NormalCycleMap), and
    so is a base whose motion is given per step (core/base_table.py); a measured motion
    that ends (vibration.motion_periodic false) has no orbit: it is stepped.
    """
    orbit = None
    if scene.time.method != "transient" and scene.vibrated and scene.vibration.repeats:
        load_cycle(scene, stepper)
        orbit = find_orbit(scene, stepper, start)
        if orbit.converged and orbit.stable:
            summary = summarize_orbit(orbit, scene)

            def periodic():
                return periodic_error(scene, stepper, orbit, summary["F_dv_over_F_d0"],
                                      summary["F_d0"])

            summary.update(_error(summary, scene, orbit.dt, periodic, estimate))
            series = steady_series(orbit, scene)
            summary.update(normal_force_keys(series, scene, orbit.steps))
            return series, summary, orbit.z
        check_stepped_window(scene, "no stable periodic orbit, so the scene is stepped through time.T: its ")

    LOADERS[stepper](scene)
    start_time = perf_counter()
    series = STEPPERS[stepper](scene)
    summary = summarize(series, scene, perf_counter() - start_time)
    summary.update(normal_force_keys(series, scene, averaging_steps(scene)))

    def stepped():
        return stepped_error(scene, stepper, summary["F_dv_over_F_d0"], summary["F_d0"],
                             summary["drift_remaining"] or 0.0)

    summary.update(_error(summary, scene, scene.time.dt, stepped, estimate))
    if scene.time.method != "transient":
        summary["periodic"] = periodic_block(orbit, scene)
    return series, summary, None


def _error(summary: dict, scene, dt_used: float, estimator, estimate: bool) -> dict:
    """The summary's step-error keys: ``estimator()``'s StepError where there is a
    ratio and an estimate is asked for, else why not; and the time it took."""
    if summary["F_dv_over_F_d0"] is None:
        return {**no_ratio(dt_used, scene), "error_wall_time_s": 0.0}
    if not estimate:
        return {**error_keys(not_estimated(dt_used, scene.time.dt, "not asked for"), scene),
                "error_wall_time_s": 0.0}
    start_time = perf_counter()
    keys = error_keys(estimator(), scene)
    return {**keys, "error_wall_time_s": perf_counter() - start_time}
