"""Solve a scene with an analytic stepper: the time series and the summary (summary.json, docs/command-line.md)
(stepped through time.T, or the periodic orbit found directly)."""

from time import perf_counter

from .accuracy import error_keys, no_ratio, periodic_error, stepped_error
from .coupled import load_coupled, run_coupled
from .longitudinal import load_longitudinal, run_longitudinal
from .periodic import find_orbit, load_cycle, steady_series
from .summary import periodic_block, summarize, summarize_orbit

STEPPERS = {"coupled": run_coupled, "longitudinal": run_longitudinal}
LOADERS = {"coupled": load_coupled, "longitudinal": load_longitudinal}


def solve(scene, stepper: str = "coupled", start=None):
    """Integrate ``scene`` with the named stepper; return (TimeSeries, summary dict)
    (see solve_with_orbit)."""
    series, summary, _ = solve_with_orbit(scene, stepper, start)
    return series, summary


def solve_with_orbit(scene, stepper: str = "coupled", start=None):
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
    solver at dt/2 and dt/4; error_estimate, dt_used, dt_asked, ...), and its
    wall_time_s that of the answer and of the estimate together.
    """
    orbit = None
    if scene.time.method != "transient" and scene.vibrated:
        load_cycle(scene, stepper)
        start_time = perf_counter()
        orbit = find_orbit(scene, stepper, start)
        if orbit.converged and orbit.stable:
            summary = summarize_orbit(orbit, scene)
            ratio = summary["F_dv_over_F_d0"]
            error = (no_ratio(orbit.dt, scene) if ratio is None else
                     error_keys(periodic_error(scene, stepper, orbit, ratio, summary["F_d0"]),
                                scene))
            summary.update(error, wall_time_s=perf_counter() - start_time)
            return steady_series(orbit, scene), summary, orbit.z
    LOADERS[stepper](scene)
    start_time = perf_counter()
    series = STEPPERS[stepper](scene)
    summary = summarize(series, scene, perf_counter() - start_time)
    ratio = summary["F_dv_over_F_d0"]
    error = (no_ratio(scene.time.dt, scene) if ratio is None else
             error_keys(stepped_error(scene, stepper, ratio, summary["F_d0"],
                                      summary["drift_remaining"] or 0.0), scene))
    summary.update(error, wall_time_s=perf_counter() - start_time)
    if scene.time.method != "transient":
        summary["periodic"] = periodic_block(orbit, scene)
    return series, summary, None
