"""The analytic command's plots, drawn by its plot process (vibrofric/plot_worker.py):
the same figures as drawn in one process, and a failure on either side fails
the run, leaves nothing written and no process behind."""

import re
import shutil
import subprocess
import sys
import time
from types import SimpleNamespace

import pytest

from vibrofric import output, plot_worker, plots
from vibrofric import scene as scene_module
from vibrofric.analytic.solve import solve
from vibrofric.cli import EXIT_BAD_INPUT, main
from vibrofric.core.series import written

from conftest import SCENES, child_environment

LONGITUDINAL = str(SCENES / "longitudinal.toml")
SHORT = ["--set", "time.T=0.2"]


@pytest.fixture
def started(monkeypatch):
    """The plot processes the command starts, as a list (to check they were reaped)."""
    processes = []

    class Recorded(plot_worker.PlotProcess):
        def __init__(self, *args):
            super().__init__(*args)
            processes.append(self.process)

    monkeypatch.setattr(plot_worker, "PlotProcess", Recorded)
    return processes


def test_plots_are_those_drawn_in_one_process(tmp_path, started):
    out = tmp_path / "run"
    assert main(["analytic", LONGITUDINAL, *SHORT, "--out", str(out)]) == 0
    assert len(started) == 1 and started[0].returncode == 0
    scene = scene_module.load(LONGITUDINAL, ["time.T=0.2"])
    series, summary = solve(scene)
    runs = {"coupled": written(series, scene)}
    steady = plot_worker.steady_labels({"coupled": summary})
    assert steady == ("coupled",)   # the default method answers by the steady cycle
    plots.drive_force_history(runs, scene, tmp_path / "drive_force.png", steady)
    plots.friction_last_cycles(runs, scene, tmp_path / "friction_last_cycles.png")
    for name in ("drive_force.png", "friction_last_cycles.png"):
        assert (out / name).read_bytes() == (tmp_path / name).read_bytes(), name


def test_a_base_moving_along_z_draws_the_lumped_normal_force(tmp_path, started):
    """The command's normal_force.png of a run with normal motion is the one drawn in one
    process (plots.normal_force_history of the series' N), and run_analytic writes it too."""
    from vibrofric.api import run_analytic

    changes = ["time.T=0.2", "vibration.normal_amplitude=1e-7"]
    out = tmp_path / "run"
    assert main(["analytic", LONGITUDINAL, *[a for c in changes for a in ("--set", c)],
                 "--out", str(out)]) == 0
    scene = scene_module.load(LONGITUDINAL, changes)
    series, summary = solve(scene)
    rows = written(series, scene)
    plots.normal_force_history(rows, scene, tmp_path / "normal_force.png",
                               summary["periodic"]["method"] == "periodic", "N")
    assert (out / "normal_force.png").read_bytes() == (tmp_path / "normal_force.png").read_bytes()
    run_analytic(scene, out=tmp_path / "api")
    drawn = (out / "normal_force.png").read_bytes()
    assert (tmp_path / "api" / "normal_force.png").read_bytes() == drawn
    # and a run without normal motion draws none
    assert main(["analytic", LONGITUDINAL, *SHORT, "--out", str(tmp_path / "plain")]) == 0
    assert not (tmp_path / "plain" / "normal_force.png").exists()


def test_the_friction_legend_leaves_the_axes_clear():
    """The friction curves sweep the axes' whole height every cycle: any legend inside
    would cover one. Its box lies wholly below the axes (and inside the figure)."""
    scene = scene_module.load(SCENES / "transverse.toml", ["time.T=0.2"])
    series = written(solve(scene)[0], scene)
    fig = plots.friction_last_cycles_figure({"FE": series, "analytic": series}, scene)
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[0]
    legend = ax.get_legend().get_window_extent(renderer)
    lowest = min(ax.get_window_extent(renderer).y0,             # the axes, their tick labels
                 ax.xaxis.get_tightbbox(renderer).y0)           # and the x label
    assert legend.y1 <= lowest and legend.y0 >= 0.0


@pytest.fixture(autouse=True)
def _crash_logs_in_tmp(tmp_path, monkeypatch):
    """The failures below are logged (cli._crash_log) under the test's own directory."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path.parent / f"{tmp_path.name}-cache"))


def test_a_plot_failure_fails_the_run_and_leaves_nothing(tmp_path, monkeypatch, started, capsys):
    """The plot process fails (here: a scene without the values the plots read):
    PlotError with its traceback, no results directory, no stage."""
    monkeypatch.setattr(plot_worker, "plotted_scene", lambda scene: SimpleNamespace(name="bare"))
    assert main(["analytic", LONGITUDINAL, *SHORT, "--out", str(tmp_path / "run")]) == 1  # one line (cli._unexpected)
    assert re.search(r"AttributeError.*(vibrated|F_c)", capsys.readouterr().err)
    assert started[0].returncode == 1
    assert list(tmp_path.iterdir()) == []


def test_a_plot_process_that_fails_to_start_fails_the_run(tmp_path, monkeypatch, started, capsys):
    """It dies before it reads the rows (here: a matplotlib that cannot be imported):
    the rows are not its to read, and its traceback is the run's error."""
    broken = tmp_path / "broken" / "matplotlib"
    broken.mkdir(parents=True)
    (broken / "__init__.py").write_text("raise ImportError('no matplotlib here')\n")
    monkeypatch.setenv("PYTHONPATH", str(broken.parent))
    assert main(["analytic", LONGITUDINAL, *SHORT, "--out", str(tmp_path / "run")]) == 1  # one line (cli._unexpected)
    assert re.search(r"ImportError: no matplotlib here", capsys.readouterr().err)
    assert started[0].returncode == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == ["broken"]


def test_a_failure_while_it_draws_ends_it_before_the_stage_goes(tmp_path, monkeypatch, started, capsys):
    """The command fails after sending the rows: the plot process is ended and
    reaped before the stage is removed, so it writes no PNG into a removed stage."""
    def disk_full(*args, **kwargs):
        raise OSError(28, "No space left on device")

    removed_with_it = []  # at each removal of the stage: the plot process's exit code
    remove_tree = shutil.rmtree

    def rmtree(path, **kwargs):
        removed_with_it.append(started[0].poll())
        remove_tree(path, **kwargs)

    monkeypatch.setattr(output, "write_timeseries", disk_full)
    monkeypatch.setattr(shutil, "rmtree", rmtree)
    assert main(["analytic", LONGITUDINAL, *SHORT, "--out", str(tmp_path / "run")]) == 1  # one line (cli._unexpected)
    assert re.search(r"No space left", capsys.readouterr().err)
    assert removed_with_it and None not in removed_with_it
    time.sleep(0.5)  # what a plot process left running would write by now
    assert list(tmp_path.iterdir()) == []


def test_a_run_refused_before_its_plots_ends_the_plot_process(tmp_path, capsys, started):
    code = main(["analytic", LONGITUDINAL, "--set", "body.mass=-1", "--out", str(tmp_path / "no")])
    assert code == EXIT_BAD_INPUT and "body.mass" in capsys.readouterr().err
    assert started[0].returncode is not None
    assert list(tmp_path.iterdir()) == []


def test_the_plot_process_ends_quietly_when_no_rows_come(tmp_path):
    """Its command stopped early or died: the process's input closes without rows."""
    child = subprocess.run([sys.executable, "-P", "-m", "vibrofric.plot_worker"],
                           stdin=subprocess.DEVNULL, capture_output=True, cwd=tmp_path,
                           env=child_environment(), timeout=120)
    assert (child.returncode, child.stdout, child.stderr) == (0, b"", b"")
    assert list(tmp_path.iterdir()) == []


def packages_loaded_by(code: str, directory) -> set:
    """The top-level packages a fresh interpreter has loaded after running ``code``."""
    child = subprocess.run(
        [sys.executable, "-c", f"import sys; {code}; print(' '.join(sys.modules))"],
        capture_output=True, text=True, cwd=directory, env=child_environment(), timeout=120)
    assert child.returncode == 0, child.stderr
    return {name.split(".")[0] for name in child.stdout.split()}


def test_the_plot_process_imports_matplotlib_not_numba(tmp_path):
    """What makes it ready before the stepping ends: it imports no numba, nor the FE stack."""
    loaded = packages_loaded_by("from vibrofric import plot_worker, plots; "
                                "plot_worker.warm_up(plots)", tmp_path)
    assert "matplotlib" in loaded
    assert loaded.isdisjoint({"numba", "llvmlite", "scipy", "dolfinx", "mpi4py", "gmsh"})


def block_fields(t: float) -> dict:
    """Node fields of a made-up 3 x 2 x 2 block (FEResult.fields' keys that the picture
    reads): the pressure rising along x, the traction along -x."""
    import numpy as np

    x, y, z = np.meshgrid([0.0, 0.05, 0.1], [0.0, 0.04], [0.0, 0.02], indexing="ij")
    coordinates = np.column_stack([x.ravel(), y.ravel(), z.ravel()])
    nodes = len(coordinates)
    contact = np.flatnonzero(coordinates[:, 2] == 0.0)
    pressure, traction = np.zeros(nodes), np.zeros((nodes, 3))
    pressure[contact] = 4e4 + 2e5 * coordinates[contact, 0]
    traction[contact, 0] = -0.5 * pressure[contact]
    return {"coordinates": coordinates, "contact_nodes": contact, "contact_pressure": pressure,
            "friction_traction": traction, "t": t}


def test_an_fe_runs_plots_and_picture_are_those_drawn_in_one_process(tmp_path):
    """The "fe" kind (vibrofric run): its three plots and the block's picture as drawn
    in one process; the FE series here is the stepper's with a normal force added (any
    TimeSeries with extra["F_n"] is drawn the same way), the block a made-up one."""
    import numpy as np

    from vibrofric import picture

    scene = scene_module.load(LONGITUDINAL, ["time.T=0.2"])
    analytic = written(solve(scene)[0], scene)
    fe = written(solve(scene)[0], scene)
    fe.extra["F_n"] = scene.contact.F_N * (1.0 + 0.01 * np.sin(2e4 * fe.t))
    runs = {"FE": fe, "analytic": analytic}
    fields = block_fields(0.2)
    child, one = tmp_path / "child", tmp_path / "one"
    child.mkdir()
    one.mkdir()
    with plot_worker.PlotProcess("fe") as plotter:
        with plotter.drawing(plot_worker.plots_job(runs, scene, child, fe=fe, picture=fields)):
            pass
    plots.drive_force_history(runs, scene, one / plot_worker.DRIVE_FORCE)
    plots.friction_last_cycles(runs, scene, one / plot_worker.LAST_CYCLES)
    plots.normal_force_history(fe, scene, one / plot_worker.NORMAL_FORCE)
    picture.draw(picture.picture_rows(fields), one / plot_worker.PICTURE)
    for name in (plot_worker.DRIVE_FORCE, plot_worker.LAST_CYCLES, plot_worker.NORMAL_FORCE,
                 plot_worker.PICTURE):
        assert (child / name).read_bytes() == (one / name).read_bytes(), name


def test_an_fe_run_with_normal_motion_draws_the_lumped_n_beside_its_own(tmp_path):
    """vibrofric run of a base moving along Z: normal_force.png has the FE summed normal
    force and the analytic run's N on one plot, as drawn in one process (stand-ins: the
    lumped run of 1e-7 m as both, the FE one's F_n its N plus a ripple)."""
    import numpy as np

    scene = scene_module.load(LONGITUDINAL, ["time.T=0.2", "vibration.normal_amplitude=1e-7"])
    series, summary = solve(scene)
    analytic, fe = written(series, scene), written(series, scene)
    fe.extra["F_n"] = fe.extra["N"] * (1.0 + 0.01 * np.sin(2e4 * fe.t))
    runs = {"FE": fe, "analytic": analytic}
    steady = plot_worker.steady_labels({"FE": summary, "analytic": summary})
    job = plot_worker.plots_job(runs, scene, tmp_path, fe=fe, steady=steady, fe_steady=True)
    assert job["normal_steady"] and job["lumped_normal"].extra["N"] is analytic.extra["N"]
    with plot_worker.PlotProcess("fe") as plotter:
        with plotter.drawing(job):
            pass
    plots.normal_force_history(fe, scene, tmp_path / "one.png", True, "F_n", lumped=analytic)
    assert (tmp_path / plot_worker.NORMAL_FORCE).read_bytes() == (tmp_path / "one.png").read_bytes()
    # without normal motion the FE run's plot has its own curve only
    plain = written(solve(scene_module.load(LONGITUDINAL, ["time.T=0.2"]))[0], scene)
    assert "lumped_normal" not in plot_worker.plots_job({"FE": fe, "analytic": plain}, scene,
                                                        tmp_path, fe=fe)


def test_the_picture_draws_the_contact_face_coloured_by_its_pressure(tmp_path):
    """Left of the colour bar, the picture holds the colour map's colours over most of
    its range (the contact face, its pressure rising along x from 4e4 to 6e4 Pa), and
    crimson (the arrows)."""
    import numpy as np
    from matplotlib import cm
    from matplotlib.image import imread

    from vibrofric import picture

    path = tmp_path / "block.png"
    picture.draw(picture.picture_rows(block_fields(0.3)), path)
    image = imread(path)[..., :3]
    assert image.shape[:2] == (700, 900)
    block = image[:, :650].reshape(-1, 3)          # the colour bar stands right of x = 700
    shades = cm.viridis(np.linspace(0.0, 1.0, 256))[:, :3]
    gap = np.abs(block[:, None, :] - shades[None, :, :]).max(axis=2)
    on_map = gap.min(axis=1) < 0.02                 # a colour of the map (PNG rounding: 1/255)
    position = gap.argmin(axis=1)[on_map] / 255.0
    assert on_map.mean() > 0.01                     # the face: a few % of the picture
    # each triangle takes its mean pressure's colour: not the very ends of the map
    assert position.min() < 0.2 and position.max() > 0.8
    crimson = np.abs(block - np.array([220, 20, 60]) / 255).max(axis=1) < 0.08
    assert crimson.mean() > 0.0005


def test_the_plot_process_draws_the_picture_without_numba_or_the_fe_stack(tmp_path):
    """The "fe" kind gets ready (matplotlib, its 3D axes) in a process without numba,
    DOLFINx or VTK: no renderer to set up, nothing of the run's to load."""
    loaded = packages_loaded_by("from vibrofric import plot_worker, plots, picture; "
                                "plot_worker.warm_up(plots); picture.warm_up()", tmp_path)
    assert {"matplotlib", "mpl_toolkits"} <= loaded
    assert loaded.isdisjoint({"numba", "llvmlite", "scipy", "dolfinx", "mpi4py", "gmsh",
                              "pyvista", "vtkmodules"})
