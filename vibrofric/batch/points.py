"""The points of a sweep: each one a directory, written whole when the point ends.

``<sweep>/points/<name>/`` (name: grid.point_name, e.g.
``vibration.k_v=2,vibration.theta_deg=45.0``) holds

    summary.json  {"point": {grid key: value}, "mode": "analytic" | "fe",
                   "result": {...}}: the result keys of the sweep's JSON
                   (``fe``: those of ``vibrofric run`` plus "fe_info"), or, for a
                   failed point, "error": "invalid scene: ..." instead of "result"
    scene.toml    the point's scene as run (none if its values make no valid scene)
    fe points also: timeseries.csv, analytic_timeseries.csv and, if
                   fem.output_every > 0, the ParaView series paraview/block.pvd
    orbit.npy     with time.method periodic or auto, where the point's steady cycle
                   answered: its orbit state (the FE one for an FE point), from
                   which the next point of the grid starts (continuation; read
                   back by a resumed sweep, neighbour_orbit)

    checks.json   the size and SHA-256 of each of the files above, written last

A point's directory appears whole or not at all (output.staged), so a
directory that is there is a finished point: done, or failed with its error,
unless something changed it since: a point whose files do not match
checks.json, or whose summary is not one a point writes, is DAMAGED, and runs again.
"""

import contextlib
import functools
import json
import math
import traceback
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .. import output
from .. import scene as scene_module
from ..core.errors import NumericalError
from ..grid import canonical_grid, grid_points, unique_names
from ..parallel import stop_if_interrupted
from ..scene import Scene, SceneError

ERROR = "error"  # a failed point's summary.json and record hold why under this key
DAMAGED = "damaged"  # read_point's answer for a point directory that does not check out
PLAIN_ERRORS = {SceneError: "invalid scene", NumericalError: "numerical trouble"}


@dataclass(frozen=True)
class Point:
    """One grid point: its values, where it is written, and the scene it runs.

    scene    None when the values make no valid scene; then refusal says why
    """

    values: dict
    directory: Path
    scene: Scene | None = None
    refusal: str | None = None

    @property
    def name(self) -> str:
        return self.directory.name

    @functools.cached_property
    def scene_toml(self) -> str | None:
        """scene.toml as this point would write it: how a rerun recognises its results."""
        return None if self.scene is None else scene_module.to_toml(self.scene)


def plan(scene, grid, directory: Path) -> list:
    """The grid's points in grid order, each with its scene or the reason it has none.

    A grid that names an unknown key, a key twice or a value twice (2 and
    2.0 are one value: grid.canonical_grid) is the command line's mistake,
    refused (SceneError) before any work; a value that makes no valid scene is
    not: that point fails, the others run.
    """
    values = list(grid_points(canonical_grid(grid)))
    points = []
    for name, point_values in zip(unique_names(values), values):
        try:
            points.append(Point(point_values, directory / name, scene.with_values(point_values)))
        except SceneError as err:
            points.append(Point(point_values, directory / name, refusal=_describe(err)))
    return points


def _describe(err: Exception) -> str:
    return f"{PLAIN_ERRORS.get(type(err), type(err).__name__)}: {err}"


def _run_analytic(scene, directory: Path, start=None) -> tuple:
    """The analytic stepper: only scene.toml and the summary are kept, as a
    125-point sweep takes seconds (``vibrofric analytic`` on the point's
    scene.toml gives the time series and plots). Returns (the result keys, the
    orbit state or None)."""
    from ..analytic.solve import solve_with_orbit

    _, summary, orbit = solve_with_orbit(scene, start=start)
    output.write_scene(directory, scene)
    return {"result": summary}, orbit


def _run_fe(scene, directory: Path, start=None) -> tuple:
    """The FE run beside the analytic stepper, with BLAS on one thread: the
    sweep already runs a point on every core, and an OpenBLAS thread left
    spinning after a set-up's product takes the core of the point beside it
    (the Fig 12 study: 123 s with them, 108 s without; every F_dv/F_d0 moved
    by at most 4e-8 of itself, as the set-up's products round differently).
    Returns (the result keys, the FE orbit state or None)."""
    from ..fem.model.linalg import one_blas_thread
    from ..fe_beside_analytic import fe_beside_analytic

    with one_blas_thread():
        # scene.toml naming its files where they are, as every point's: a resumed sweep
        # knows the point by that text (read_point, Point.scene_toml)
        done = fe_beside_analytic(scene, directory, start=start, inputs=False)
    periodic = done.document["fe"].get("periodic") or {}
    orbit = done.fe.orbit.z if periodic.get("method") == "periodic" else None
    return {"result": done.document, "fe_info": done.fe_info}, orbit


RUNNERS = {"analytic": _run_analytic, "fe": _run_fe}
ORBIT = "orbit.npy"


def run_point(point: Point, mode: str, start=None):
    """Run one point and write its directory whole: its results, or its error.
    ``start``: a neighbour's orbit state (time.method periodic or auto). Returns
    the point's own orbit state where its steady cycle answered, else None.

    Any exception from the run fails this point only (recorded with its
    message; with a traceback if it is not a plain SceneError or
    NumericalError); an interrupt leaves nothing.
    """
    failure = {ERROR: point.refusal}
    if point.scene is not None:
        try:
            with output.staged(point.directory) as stage:
                ran, orbit = RUNNERS[mode](point.scene, stage, start)
                output.write_summary(stage, {"point": point.values, "mode": mode, **ran})
                if orbit is not None:
                    np.save(stage / ORBIT, orbit)
                output.write_checks(stage)
                stop_if_interrupted()  # a run a swallowed interrupt cut short is not kept
            return orbit
        except Exception as err:  # a failed point is recorded, and the sweep goes on
            stop_if_interrupted()  # unless the failure is an interrupt's doing
            failure = {ERROR: _describe(err)}
            if type(err) not in PLAIN_ERRORS:
                failure["traceback"] = traceback.format_exc()
    with output.staged(point.directory) as stage:
        if point.scene is not None:
            output.write_scene(stage, point.scene)
        output.write_summary(stage, {"point": point.values, "mode": mode, **failure})
        output.write_checks(stage)
    return None


def run_point_on_worker(task):
    """run_point((point, mode, start, ...)) on a pool's worker (a module-level function),
    which keeps its FE model between the points it is handed (fe_model.kept_for_this_process)."""
    point, mode, start = task[:3]
    if mode == "fe":
        from ..fem.model.fe_model import kept_for_this_process
        kept_for_this_process()
    return run_point(point, mode, start)


def model_kept(mode: str):
    """FE points run one after another in this process share their model
    (fe_model.kept_between_runs)."""
    if mode != "fe":
        return contextlib.nullcontext()
    from ..fem.model.fe_model import kept_between_runs
    return kept_between_runs()


def neighbour_orbit(directory: Path):
    """The orbit state a finished point's directory holds (ORBIT), or None: where
    there is none, or the directory does not check out."""
    path = directory / ORBIT
    if not path.is_file() or not output.checks_out(directory):
        return None
    try:
        return np.load(path)
    except (OSError, ValueError):
        return None


def _ratios_make_sense(result: dict) -> bool:
    """Every F_dv/F_d0 of a result (an FE point's FE and analytic ones) a finite
    number, or None (no friction): a summary edited to "NaN" or text is not."""
    ratios = [result.get(k, {}).get("F_dv_over_F_d0") for k in ("fe", "analytic")
              if isinstance(result.get(k), dict)] or [result.get("F_dv_over_F_d0")]
    return all(r is None or (isinstance(r, (int, float)) and not isinstance(r, bool) and math.isfinite(r))
               for r in ratios)


def read_point(point: Point, mode: str):
    """The point's record as its directory holds it: the grid values, then the
    result keys or "error". None if there is no directory, or it holds another
    sweep's point (another scene.toml, e.g. after a change to the base scene,
    or the other mode): that one is rerun and replaced. DAMAGED if it is there
    but does not check out (see the module): rerun, and counted as such."""
    if not point.directory.exists() and not point.directory.is_symlink():
        return None
    if not point.directory.is_dir() or not output.checks_out(point.directory):
        return DAMAGED
    try:
        summary = json.loads((point.directory / "summary.json").read_text())
    except (OSError, ValueError):
        return DAMAGED
    if not isinstance(summary, dict) or not isinstance(summary.get("mode"), str):
        return DAMAGED
    # a point refused now has no scene, and its directory none either
    written = point.directory / "scene.toml"
    scene_toml = written.read_text() if written.exists() else None
    if summary["mode"] != mode or scene_toml != point.scene_toml:
        return None
    if ERROR in summary:
        return {**point.values, ERROR: str(summary[ERROR])}
    result = summary.get("result")
    if not isinstance(result, dict) or not _ratios_make_sense(result):
        return DAMAGED
    return {**point.values, **result}
