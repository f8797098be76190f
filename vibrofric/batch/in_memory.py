"""The analytic stepper over a grid of scene values, in memory, on both cores.

For scripts, tests and benchmarks: results come back as a list and nothing is
written. ``vibrofric sweep`` goes through study.run_sweep instead, which
writes each point as it ends and resumes an interrupted sweep.
"""

from tqdm import tqdm

from ..analytic.run import run
from ..grid import grid_points
from ..parallel import default_workers, run_on_pool


def run_point(scene, values: dict) -> dict:
    """One grid point: its values followed by the summary of its analytic run."""
    _, summary = run(scene.with_values(values))
    return {**values, **summary}


def _run_task(task):
    _, scene, values = task
    return run_point(scene, values)


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

        tasks = [(i, scene, values) for i, values in enumerate(points)]
        run_on_pool(_run_task, tasks, workers or default_workers(), store)
    return results
