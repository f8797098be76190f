"""Sweeps: the analytic stepper over a grid of scene values, on both cores.

A grid is a list of (key, values) pairs; every combination is one point. Every
point's scene is built and checked before any runs, so a bad value stops the
sweep before any work.
"""

import itertools
import os
from concurrent.futures import ProcessPoolExecutor, as_completed

import numpy as np
from tqdm import tqdm

from ..scene import SceneError, parse_value
from .run import run


def parse_grid(text: str):
    """``KEY=VALUES`` -> (key, [values]); VALUES is ``a,b,c`` or ``start:stop:count`` (inclusive)."""
    key, sep, values = text.partition("=")
    if not sep or not values:
        raise SceneError(text, "a grid is KEY=VALUES, e.g. vibration.k_v=2,3,4 or vibration.theta_deg=0:360:25")
    key = key.strip()
    parts = values.split(":")
    if len(parts) == 3:
        try:
            start, stop, count = float(parts[0]), float(parts[1]), int(parts[2])
        except ValueError:
            raise SceneError(key, f"grid range {values!r} is not start:stop:count") from None
        if count < 1:
            raise SceneError(key, f"grid range {values!r} needs a count >= 1")
        return key, [float(v) for v in np.linspace(start, stop, count)]
    return key, [parse_value(v.strip()) for v in values.split(",")]


def grid_points(grid):
    """Every combination of the grid's values, as ``{key: value}`` dicts, first key slowest."""
    keys = [key for key, _ in grid]
    return [dict(zip(keys, combo)) for combo in itertools.product(*(values for _, values in grid))]


def run_point(scene, values: dict) -> dict:
    """One grid point: its values followed by the summary of its analytic run."""
    _, summary = run(scene.with_values(values))
    return {**values, **summary}


def default_workers() -> int:
    return min(2, os.cpu_count() or 1)


def sweep(scene, grid, workers: int | None = None, progress: bool = True) -> list[dict]:
    """Run the analytic stepper at every grid point; results in grid order."""
    points = grid_points(grid)
    for values in points:  # refuse a bad point before any work
        scene.with_values(values)
    workers = workers or default_workers()
    results = [None] * len(points)
    bar = tqdm(total=len(points), desc="sweep", unit="point", delay=2.0, disable=not progress)
    with ProcessPoolExecutor(max_workers=workers) as pool:
        futures = {pool.submit(run_point, scene, values): i for i, values in enumerate(points)}
        for future in as_completed(futures):
            results[futures[future]] = future.result()
            bar.update()
    bar.close()
    return results
