"""One analytic run of a scene: the time series and the summary of interface.md."""

import time

from .coupled import run_coupled
from .longitudinal import run_longitudinal
from .summary import summarize

STEPPERS = {"coupled": run_coupled, "longitudinal": run_longitudinal}


def run(scene, stepper: str = "coupled"):
    """Integrate ``scene`` with the named stepper; return (TimeSeries, summary dict)."""
    start = time.perf_counter()
    series = STEPPERS[stepper](scene)
    return series, summarize(series, scene, time.perf_counter() - start)
