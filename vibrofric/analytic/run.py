"""One analytic run of a scene: the time series and the summary of interface.md."""

from time import perf_counter

from .coupled import load_coupled, run_coupled
from .longitudinal import load_longitudinal, run_longitudinal
from .summary import summarize

STEPPERS = {"coupled": run_coupled, "longitudinal": run_longitudinal}
LOADERS = {"coupled": load_coupled, "longitudinal": load_longitudinal}


def run(scene, stepper: str = "coupled"):
    """Integrate ``scene`` with the named stepper; return (TimeSeries, summary dict).

    The summary's wall_time_s is the stepping alone: the compiled loop is loaded
    from numba's cache (or compiled) before the clock starts, since that costs
    a new process ~0.3 s whatever the scene.
    """
    LOADERS[stepper](scene)
    start = perf_counter()
    series = STEPPERS[stepper](scene)
    return series, summarize(series, scene, perf_counter() - start)
