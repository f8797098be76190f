"""Solve a scene with an analytic stepper: the time series and the summary (summary.json, docs/command-line.md)
(stepped through time.T, or the periodic orbit found directly)."""

from time import perf_counter

from ..core.series import check_stepped_window
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
    """
    orbit = None
    if scene.time.method != "transient" and scene.vibrated:
        load_cycle(scene, stepper)
        orbit = find_orbit(scene, stepper, start)
        if orbit.converged and orbit.stable:
            return steady_series(orbit, scene), summarize_orbit(orbit, scene), orbit.z
        check_stepped_window(scene, "no stable periodic orbit, so the scene is stepped through time.T: its ")
    LOADERS[stepper](scene)
    start_time = perf_counter()
    series = STEPPERS[stepper](scene)
    summary = summarize(series, scene, perf_counter() - start_time)
    if scene.time.method != "transient":
        summary["periodic"] = periodic_block(orbit, scene)
    return series, summary, None
