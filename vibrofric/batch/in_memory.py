"""The analytic stepper over a grid of scene values, in memory, on both cores.

For scripts, tests and benchmarks: results come back as a list and nothing is
written. ``vibrofric sweep`` goes through study.run_sweep instead, which
writes each point as it ends and resumes an interrupted sweep.
"""

import warnings

from tqdm import tqdm

from ..analytic.continuation import run_in_sequence
from ..analytic.solve import solve
from ..friction_law.specialize import specialized_first
from ..grid import grid_points
from ..parallel import run_on_pool, worker_count
from .lanes import lanes


def run_point(scene, values: dict) -> dict:
    """One grid point: its values followed by the summary of its analytic run."""
    _, summary = solve(scene.with_values(values))
    return {**values, **summary}


def _run_task(task):
    _, scene, values = task
    return run_point(scene, values)


def _run_lane(task):
    """A lane of grid points by continuation (lanes.py, analytic/continuation.py)."""
    _, scene, points = task
    return [{**values, **summary} for values, summary in zip(points, run_in_sequence(scene, points))]


@specialized_first
def sweep(scene, grid, workers: int | None = None, progress: bool = True) -> list[dict]:
    """Run the analytic stepper at every grid point; results in grid order.

    Every point's scene is checked first: a bad value raises SceneError before any work.
    ``workers`` processes (default: both cores), never more than the tasks that can
    run side by side or than the cores (parallel.worker_count; a warning says so).
    """
    points = list(grid_points(grid))
    for values in points:
        scene.with_values(values)
    results = [None] * len(points)
    with tqdm(total=len(points), desc="sweep", unit="point", delay=2.0, disable=not progress) as bar:
        def store(task, record):
            results[task[0]] = record
            bar.update()

        if scene.time.method == "transient":
            tasks = [(i, scene, values) for i, values in enumerate(points)]
            run_on_pool(_run_task, tasks, _workers(workers, len(tasks), "points"), store)
        else:   # periodic or auto: the grid's lanes, each by continuation (as vibrofric sweep)
            def store_lane(task, records):
                for i, record in zip(task[0], records):
                    store((i,), record)

            tasks = [(lane, scene, [points[i] for i in lane]) for lane in lanes(points)]
            run_on_pool(_run_lane, tasks, _workers(workers, len(tasks), "lanes of points"), store_lane)
    return results


def _workers(requested, tasks: int, what: str) -> int:
    count, note = worker_count(requested, tasks, oversubscribe=None, what=what)
    if note:
        warnings.warn(note.replace("vibrofric: --workers ", "workers="), stacklevel=3)
    return count
