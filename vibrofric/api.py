"""The Python API: scenes, runs and sweeps from a script or a notebook.

    >>> import vibrofric as vf
    >>> scene = vf.load_scene("longitudinal", **{"time.T": 0.3})
    >>> a = vf.run_analytic(scene)
    >>> round(a.F_dv_over_F_d0, 3), a.settled
    (0.137, True)

Everything here is what the ``vibrofric`` command does, without the command:
``load_scene`` reads a scene as ``vibrofric ... SCENE --set KEY=VALUE`` does,
``run_analytic`` is ``vibrofric analytic``, ``run_fe`` is ``vibrofric run``
(the FE model beside the analytic stepper), ``sweep`` is ``vibrofric sweep``. A run
writes files only when given ``out``; its results come back as a Result, with
the time series as a pandas DataFrame. Bad input raises SceneError (a
ValueError) naming the key; numerical trouble raises NumericalError.
"""

from __future__ import annotations

import tempfile
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, Mapping

if TYPE_CHECKING:  # imported on use: pandas and the models are not light
    import pandas

    from .friction_law import FrictionLaw
    from .scene import Scene

SCENE_SUFFIX = ".toml"


def scene_names() -> list[str]:
    """The scenes that ship with the package, by name (the paper's cases).

    >>> scene_names()
    ['ball', 'coupled', 'longitudinal', 'pin', 'transverse']
    """
    folder = resources.files("vibrofric") / "scenes"
    return sorted(p.name[:-len(SCENE_SUFFIX)] for p in folder.iterdir()
                  if p.name.endswith(SCENE_SUFFIX))


def _scene_path(name: str) -> Path:
    """A shipped scene's file, for ``name`` without a folder or suffix."""
    return Path(str(resources.files("vibrofric") / "scenes" / f"{name}{SCENE_SUFFIX}"))


def scene_file(source: str | Path) -> Path:
    """The scene file ``source`` names: a file, or a shipped scene by name (scene_names()),
    so that ``vibrofric analytic longitudinal`` runs from an installed package too.

    Raises SceneError for a bare name that is neither a file here nor a shipped scene.

    >>> scene_file("transverse").name
    'transverse.toml'
    """
    from . import scene as scene_module

    path = Path(source)
    if path.exists() or path.parent != Path(".") or path.suffix != "":
        return path
    if path.name not in scene_names():
        raise scene_module.SceneError(
            str(source), f"no such scene file, nor a shipped scene ({', '.join(scene_names())})")
    return _scene_path(path.name)


def _key(name: str) -> str:
    """``time__T`` (a keyword argument) or ``time.T``: the scene key ``time.T``."""
    return name.replace("__", ".", 1) if "." not in name else name


def load_scene(source: str | Path | Mapping | "Scene" = "longitudinal", **overrides: Any) -> "Scene":
    """A scene, checked, with ``overrides`` applied.

    ``source`` is a scene file (TOML), the name of a shipped scene
    (``"longitudinal"``, ``"transverse"``, ``"coupled"``: scene_names()), a
    nested dict ``{"vibration": {"k_v": 6}, ...}`` (every key left out takes
    its default) or a Scene. Overrides name a key as ``section.key`` (give
    them as ``**{"time.T": 0.3}``) or ``section__key`` (``time__T=0.3``). A
    law file given as ``contact.law`` is taken relative to the current
    directory, and one named in a scene file relative to that file.

    Raises SceneError naming the key for any value that cannot be run.

    >>> scene = load_scene("longitudinal", time__T=0.3, **{"vibration.k_v": 2})
    >>> scene.time.T, scene.vibration.k_v
    (0.3, 2.0)
    >>> load_scene({"vibration": {"k_v": 20, "theta_deg": 90}}).v_a
    0.01
    >>> load_scene("longitudinal", time__dt=-1)
    Traceback (most recent call last):
    ...
    vibrofric.scene.SceneError: time.dt: must be > 0, got -1.0
    """
    from . import scene as scene_module
    from .friction_law.contract import is_law_file

    if isinstance(source, scene_module.Scene):
        scene = source
    elif isinstance(source, Mapping):
        scene = scene_module.from_dict({section: dict(values) for section, values in source.items()})
    else:
        scene = scene_module.load(scene_file(source))
    values = {_key(name): value for name, value in overrides.items()}
    if "contact.law" in values:  # another law: the present one's parameters kept where it has them
        law = values.pop("contact.law")
        if is_law_file(law):
            path = Path(law).expanduser()
            law = str(path if path.is_absolute() else path.resolve())
        scene = scene.with_law(law)
    if isinstance(values.get("vibration.motion"), str):   # relative to the current directory
        values["vibration.motion"] = str(Path(values["vibration.motion"]).expanduser().resolve())
    return scene.with_values(values) if values else scene


def load_law(name: str | Path) -> "FrictionLaw":
    """A friction law: ``"dahl"``, ``"lugre"``, a law file (.py, relative to
    the current directory) or an importable module, checked against the
    contract (vibrofric/friction_law/contract.py). Raises LawError.

    >>> law = load_law("dahl")
    >>> sorted(law.parameters)
    ['dahl_exponent', 'k_t', 'mu', 'normal_change', 'update']
    >>> law.parameters["k_t"].unit
    'N/m'
    """
    from .friction_law import load_law as load

    return load(str(name))


def scene_keys(source: str | Path | Mapping | "Scene" = "longitudinal",
               **overrides: Any) -> "pandas.DataFrame":
    """Every key of a scene, one row a key: ``key`` (as ``--set`` names it), the scene's
    ``value``, the ``default``, the ``unit`` ("" for none) and its ``meaning``; the
    sections' keys, then the parameters of its law, then other laws' tables it holds.
    ``source`` and ``overrides`` as for load_scene (scene.reference).

    >>> keys = scene_keys("transverse").set_index("key")
    >>> keys.loc["body.mass", ["value", "default", "unit"]].tolist()
    [2.0, 0.5, 'kg']
    >>> keys.loc["contact.k_t", ["value", "unit"]].tolist()
    [67290000.0, 'N/m']
    """
    import pandas

    from .scene.reference import scene_keys as keys

    rows = keys(load_scene(source, **overrides))
    return pandas.DataFrame([(k.key, k.value, k.default, k.unit, k.meaning) for k in rows],
                            columns=["key", "value", "default", "unit", "meaning"])


@dataclass
class Result:
    """One run's results.

    summary     the run's summary.json block (F_dv, F_d0, F_dv_over_F_d0,
                window_drift, settled, wall_time_s, and its error: error_estimate,
                error_order, dt_used, dt_asked, error_note, ...; an FE run adds its
                integrator, DOFs, steps, normal_force, mesh_error_estimate,
                mesh_error_note)
    timeseries  the kept rows of the time series (t, F_d, F_x, F_y, x, y,
                x_b, y_b, and an FE run's summed normal force F_n), one row a
                kept step: every step of the last averaging windows, one every
                time.series_dt before them
    out         the results directory (None if nothing was written); an FE
                run's ParaView series is out / "paraview" / "block.pvd"
    analytic    for an FE run, the analytic stepper's Result beside it (at
                the scene's time.dt: run_analytic's); None for an analytic run
    rel_error   for an FE run, |FE - analytic| / analytic on F_dv/F_d0
    info        for an FE run, the model's information (fe_info of summary.json)
    """

    summary: dict
    timeseries: "pandas.DataFrame"
    out: Path | None = None
    analytic: "Result | None" = None
    rel_error: float | None = None
    info: dict = field(default_factory=dict)

    @property
    def F_dv_over_F_d0(self) -> float | None:
        """The cycle-averaged drive force over the force of steady sliding (eqs 40-41);
        None where there is no friction to reduce (F_d0 = 0)."""
        return self.summary["F_dv_over_F_d0"]

    @property
    def settled(self) -> bool:
        """Whether the drive-force mean has settled: a periodic answer always; a stepped
        one where the drift still to come, from the decay of successive windows' means,
        is at most time.settle_tolerance (summary's drift_remaining; core/settling.py)."""
        return self.summary["settled"]

    @property
    def error_estimate(self) -> float | None:
        """The estimated error of F_dv/F_d0 (absolute), from the same solver at dt/2 and
        dt/4 (Richardson: core/step_error.py; an FE run's adds the mesh's where a block of
        another refinement is cached); None where none was made (summary's error_note
        says why)."""
        return self.summary.get("error_estimate")

    @property
    def dt_used(self) -> float | None:
        """The step the answer was computed at: time.dt, or for a periodic answer the
        step nearest it that divides the base's cycle."""
        return self.summary.get("dt_used")

    @property
    def step_error(self):
        """The step error as a core.step_error.StepError (estimate, order, dt_used,
        dt_asked, note); None where the summary has none."""
        from .core.step_error import StepError

        s = self.summary
        if "dt_used" not in s:
            return None
        return StepError(s["error_estimate"], s.get("error_order"), s["dt_used"],
                         s.get("dt_asked", s["dt_used"]), (), s.get("error_note", ""))

    def __repr__(self) -> str:
        ratio = self.F_dv_over_F_d0
        shown = "None" if ratio is None else f"{ratio:.5g}"
        error = self.error_estimate
        plus = f" ± {error:.1g}" if error is not None and ratio is not None else ""
        return (f"Result(F_dv_over_F_d0={shown}{plus}, settled={self.settled}, "
                f"rows={len(self.timeseries)}, out={self.out!r})")


def _frame(series) -> "pandas.DataFrame":
    """A TimeSeries as a DataFrame, its columns by name."""
    import pandas

    return pandas.DataFrame(series.table(), columns=list(series.names))


def run_analytic(scene: "Scene", out: str | Path | None = None, *, stepper: str = "coupled",
             force: bool = False, full_series: bool = False) -> Result:
    """Run the lumped analytic stepper on ``scene``.

    ``stepper``: "coupled" (the two-phase model, any vibration angle) or
    "longitudinal" (the 1D model [23], vibration along X). With ``out``, the
    results are written there as ``vibrofric analytic --out`` writes them
    (scene.toml, summary.json, timeseries.csv, the two plots and, where the base moves
    along Z, normal_force.png; ``force``
    replaces an earlier results directory, ``full_series`` writes every kept
    row). The first run in a process loads (or compiles) the stepper.

    >>> a = run_analytic(load_scene("transverse", time__T=0.3))
    >>> round(a.F_dv_over_F_d0, 3), list(a.timeseries.columns)[:4]
    (0.14, ['t', 'F_d', 'F_x', 'F_y'])
    """
    from . import budget, output
    from .analytic.solve import solve
    from .core.series import written

    check_stepper(scene, stepper)
    target = Path(out) if out is not None else None
    if target is not None:
        output.check_target(target, "analytic", force)
        budget.check([scene], fe=False, out=target, full_series=full_series)
    series, summary = solve(scene, stepper)
    if target is not None:
        from . import plots
        from .plot_worker import steady_labels

        rows = written(series, scene, full_series)
        with output.staged(target, "analytic", claimed=False) as stage:
            output.write_scene_and_inputs(stage, scene)
            output.write_summary(stage, {"analytic": summary, "stepper": stepper})
            output.write_timeseries(stage, rows)
            plots.drive_force_history({stepper: rows}, scene, stage / "drive_force.png",
                                      steady_labels({stepper: summary}))
            plots.friction_last_cycles({stepper: rows}, scene, stage / "friction_last_cycles.png")
            if "N" in rows.extra:     # a base moving along Z: the lumped body's normal force
                plots.normal_force_history(rows, scene, stage / "normal_force.png",
                                           bool(steady_labels({stepper: summary})), "N")
    return Result(summary, _frame(series), target)


def check_stepper(scene, stepper: str) -> None:
    """The 1D longitudinal model [23] has the base moving along X only."""
    from .scene import SceneError

    if stepper not in ("coupled", "longitudinal"):
        raise SceneError("stepper", f"{stepper!r}: expected coupled or longitudinal")
    if stepper == "longitudinal" and scene.vibrated and scene.vibration.theta_deg % 180.0 != 0.0:
        raise SceneError("vibration.theta_deg",
                         f"{scene.vibration.theta_deg:g} deg: the 1D longitudinal model [23] "
                         "vibrates the base along X only (0 or 180 deg); use --stepper coupled")


def write_fe_run(scene: "Scene", stage: Path,
                 progress: Callable[[float, float | None], None] | None = None,
                 full_series: bool = False, out: str | None = None):
    """The FE run beside the analytic stepper, written into ``stage`` as
    ``vibrofric run`` writes it (its files, summary.json, plots and the block's
    picture). Returns (document, FEBesideAnalytic): document is the command's
    JSON, with "out" where ``out`` is given."""
    from . import output
    from .fe_beside_analytic import run_beside, write_beside
    from .plot_worker import PlotProcess, plots_job, steady_labels

    # started first: it imports matplotlib while the FE run goes on
    with PlotProcess("fe") as plotter:
        done = run_beside(scene, stage, progress=progress)
        document = {**done.document, "out": out} if out is not None else done.document
        runs = {"FE": done.fe.series, "analytic": done.analytic_series}
        steady = steady_labels({"FE": done.document["fe"], "analytic": done.document["analytic"]})
        job = plots_job(runs, scene, stage, fe=done.fe.series,
                        picture=done.fe.fields if done.fe_info["frames"] else None,
                        steady=steady, fe_steady="FE" in steady)
        with plotter.drawing(job):   # it draws while the files are written
            write_beside(stage, scene, done, full_series)
            output.write_summary(stage, {**document, "fe_info": done.fe_info})
    return document, done


def run_fe(scene: "Scene", out: str | Path | None = None, *, force: bool = False,
       progress: Callable[[float, float | None], None] | None = None,
       full_series: bool = False) -> Result:
    """Run the scene's finite-element model (DOLFINx) and the analytic stepper beside it.

    With ``out`` the results are written there as ``vibrofric run --out``
    writes them, the ParaView series included (a frame every
    fem.output_every steps); without, nothing is kept (no ParaView frames are
    made). ``progress(t_done, t_total)``, if given, is called as the FE time
    loop advances (simulated seconds), and as ``progress(cycles, None)`` after
    each base cycle while the steady cycle is shot for. The Result's ``analytic`` is the
    stepper's run beside it and ``rel_error`` their relative difference.

    A short FE run on the tiny mesh (skipped by the docstring check: the FE
    model has its own tests):

    >>> r = run_fe(load_scene("longitudinal", time__T=0.16, fem__mesh="tiny"))  # doctest: +SKIP
    >>> r.summary["integrator"], r.rel_error < 0.05                       # doctest: +SKIP
    ('explicit', True)
    """
    from . import budget, output

    target = Path(out) if out is not None else None
    if target is not None:
        output.check_target(target, "run", force)
        budget.check([scene], fe=True, out=target, full_series=full_series)
        with output.staged(target, "run", claimed=False) as stage:
            document, done = write_fe_run(scene, stage, progress, full_series, out=str(target))
        info = {**done.fe_info}
    else:
        quiet = scene.with_values({"fem.output_every": 0})
        with tempfile.TemporaryDirectory(prefix="vibrofric-") as scratch:
            document, done = write_fe_run(quiet, Path(scratch), progress, full_series)
        info = {**done.fe_info, "vtk": None}
    beside = Result(document["analytic"], _frame(done.analytic_series))
    return Result(document["fe"], _frame(done.fe.series), target, beside,
                  document["rel_error"], info)


def sweep(scene: "Scene", grid: Mapping[str, Any], fe: bool = False, out: str | Path | None = None,
          *, workers: int | None = None, force: bool = False) -> "pandas.DataFrame":
    """Run every combination of ``grid``'s values, one row a point, first key slowest.

    ``grid`` maps a scene key to its values: ``{"vibration.k_v": [2, 6, 20]}``.
    Without ``fe`` and ``out`` the analytic stepper runs in memory on
    ``workers`` processes (default: both cores) and the columns are the grid
    keys followed by the summary's. With ``fe``, or with ``out``, it is
    ``vibrofric sweep`` (``--fe``): the points are written under ``out`` (a
    temporary directory if None), a rerun into the same ``out`` resumes it
    (``force`` starts afresh), and the columns are those of its results.csv
    (``fe.F_dv_over_F_d0``, ``analytic.F_dv_over_F_d0``, ``rel_error``, ...;
    ``error`` where a point failed).

    >>> table = sweep(load_scene("longitudinal", time__T=0.3), {"vibration.k_v": [2, 20]}, workers=1)
    >>> table[["vibration.k_v", "F_dv_over_F_d0"]].round(3).values.tolist()
    [[2.0, 0.556], [20.0, 0.033]]
    """
    import pandas

    from . import output
    from .batch import run_sweep
    from .batch import sweep as in_memory
    from .grid import canonical_grid

    axes = canonical_grid([(_key(key), list(values)) for key, values in grid.items()])
    if not fe and out is None:
        return pandas.DataFrame(in_memory(scene, axes, workers=workers))
    mode = "fe" if fe else "analytic"
    if out is None:
        with tempfile.TemporaryDirectory(prefix="vibrofric-sweep-") as scratch:
            outcome = run_sweep(scene, axes, mode, Path(scratch) / "sweep", workers)
            return pandas.DataFrame([output.flatten(r) for r in outcome.records])
    fresh = output.check_target(Path(out), "sweep", force) == "replace"
    outcome = run_sweep(scene, axes, mode, Path(out), workers, fresh=fresh)
    return pandas.DataFrame([output.flatten(r) for r in outcome.records])
