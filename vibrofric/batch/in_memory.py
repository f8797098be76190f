"""The analytic stepper over a grid of scene values, in memory, on both cores.

For scripts, tests and benchmarks: results come back as a list and nothing is
written. ``vibrofric sweep`` goes through study.run_sweep instead, which
writes each point as it ends and resumes an interrupted sweep.
"""

from tqdm import tqdm

from ..analytic.continuation import chunks, run_in_sequence
from ..analytic.solve import solve
from ..friction_law.specialize import specialized_first
from ..grid import grid_points
from ..parallel import default_workers, run_on_pool


def run_point(scene, values: dict) -> dict:
    """One grid point: its values followed by the summary of its analytic run."""
    _, summary = solve(scene.with_values(values))
    return {**values, **summary}


def _run_task(task):
    _, scene, values = task
    return run_point(scene, values)


def _run_chunk(task):
    """A contiguous run of grid points by continuation (analytic/continuation.py)."""
    _, scene, points = task
    return [{**values, **summary} for values, summary in zip(points, run_in_sequence(scene, points))]


@specialized_first
def sweep(scene, grid, workers: int | None = None, progress: bool = True) -> list[dict]:
    """Run the analytic stepper at every grid point; results in grid order.

    Every point's scene is checked first: a bad value raises SceneError before any work.
    """
    points = grid_points(grid)
    for values in points:
        scene.with_values(values)
    results = [None] * len(points)
    with tqdm(total=len(points), desc="sweep", unit="point", delay=2.0, disable=not progress) as bar:
        def store(task, record):
            results[task[0]] = record
            bar.update()

        workers = workers or default_workers()
        if scene.time.method == "transient":
            tasks = [(i, scene, values) for i, values in enumerate(points)]
            run_on_pool(_run_task, tasks, workers, store)
        else:   # periodic: each worker a contiguous run of the grid, by continuation
            def store_chunk(task, records):
                for i, record in zip(task[0], records):
                    store((i,), record)

            tasks = [(part, scene, [points[i] for i in part])
                     for part in chunks(len(points), 4 * workers)]
            run_on_pool(_run_chunk, tasks, workers, store_chunk)
    return results
