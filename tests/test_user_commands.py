"""The vibrofric command as a user meets it: run as a process, from a directory of theirs.

Every case asserts the exit code, the message, and what the file system holds
afterwards: nothing of the user's touched (byte for byte), nothing half-written
or hidden left behind.
"""

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from conftest import as_in_a_terminal

from vibrofric import output, plots
from vibrofric import scene as scene_module
from vibrofric.core.series import TimeSeries

SCENES = Path(__file__).resolve().parent.parent / "scenes"
LONGITUDINAL = str(SCENES / "longitudinal.toml")
COUPLED = str(SCENES / "coupled.toml")
SHORT = ["--set", "time.T=0.3"]  # settled: the drive-force mean moves 9e-4 between its last windows
# 20 ms of vibration, stepped: the mean moves 60%
UNSETTLED = ["--set", "time.T=0.16", "--set", "time.method=transient"]
# FE runs short enough for a test: vibration from 10 ms, averaged over 10 cycles
FE_SHORT = ["--set", "vibration.t_on=0.01", "--set", "time.average_cycles=10"]


def vibrofric(args, cwd, **popen):
    """Run the command as a user would; return the CompletedProcess."""
    return subprocess.run([sys.executable, "-m", "vibrofric.cli", *map(str, args)], cwd=cwd,
                          capture_output=True, text=True, timeout=600, **popen)


def tree(root: Path) -> dict:
    """Every path under root (hidden ones too) and the bytes of each file."""
    return {str(p.relative_to(root)): (p.read_bytes() if p.is_file() else None)
            for p in sorted(root.rglob("*"))}


def one_line(stderr: str) -> str:
    lines = stderr.strip().splitlines()
    assert len(lines) == 1, stderr
    return lines[0]


@pytest.fixture
def home(tmp_path):
    """A user's working directory with files of their own in it."""
    (tmp_path / "notes.txt").write_text("my notes\n")
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "data.csv").write_text("1,2,3\n")
    return tmp_path


# --- never destroy what the tool did not write ------------------------------------------

@pytest.mark.parametrize("out", ["mine", "notes.txt"])
def test_out_that_is_not_a_results_directory_is_refused_untouched(home, out):
    before = tree(home)
    done = vibrofric(["analytic", LONGITUDINAL, *SHORT, "--out", out], home)
    assert done.returncode == 2
    assert one_line(done.stderr).startswith(f"vibrofric: --out {out}: ")
    assert tree(home) == before


@pytest.mark.parametrize("out", [".", "..", "./"])
def test_out_of_the_current_directory_or_above_is_refused(home, out):
    before = tree(home.parent)
    done = vibrofric(["analytic", LONGITUDINAL, *SHORT, "--out", out], home)
    assert done.returncode == 2 and "the current directory or one above it" in one_line(done.stderr)
    assert tree(home.parent) == before


def test_unwritable_out_is_refused_before_any_work(home):
    if os.geteuid() == 0:
        place = Path("/sys/vibrofric-results")  # root may write anywhere but in sysfs
    else:
        locked = home / "locked"
        locked.mkdir()
        locked.chmod(0o555)
        place = locked / "results"
    before = tree(home)
    done = vibrofric(["analytic", LONGITUDINAL, *SHORT, "--out", place], home)
    assert done.returncode == 2 and "cannot write in" in one_line(done.stderr)
    assert tree(home) == before and not place.exists()


def test_earlier_results_are_replaced_only_with_force(home):
    first = vibrofric(["analytic", LONGITUDINAL, *SHORT, "--out", "R"], home)
    assert first.returncode == 0, first.stderr
    assert output.read_marker(home / "R") == {"command": "analytic"}
    before = tree(home)
    for command in (["analytic", LONGITUDINAL], ["run", LONGITUDINAL], ["sweep", LONGITUDINAL,
                                                                         "--grid", "vibration.k_v=2"]):
        again = vibrofric([*command, *SHORT, "--out", "R"], home)
        assert again.returncode == 2 and "add --force" in one_line(again.stderr)
        assert tree(home) == before
    forced = vibrofric(["analytic", LONGITUDINAL, *SHORT, "--set", "contact.mu=0.2", "--out", "R",
                        "--force"], home)
    assert forced.returncode == 0, forced.stderr
    assert json.loads((home / "R" / "summary.json").read_text())["analytic"]["F_d0"] == pytest.approx(11.0)
    assert not [p for p in home.iterdir() if output.PARTIAL in p.name]


def test_sweep_resumes_its_own_directory_and_force_starts_afresh(home):
    args = ["sweep", LONGITUDINAL, *SHORT, "--grid", "vibration.k_v=2,6", "--out", "S"]
    assert vibrofric(args, home).returncode == 0
    resumed = vibrofric(args, home)
    assert resumed.returncode == 0 and "2 points (2 reused)" in resumed.stderr
    fresh = vibrofric([*args, "--force"], home)
    assert fresh.returncode == 0 and "2 points (0 reused)" in fresh.stderr
    assert output.read_marker(home / "S") == {"command": "sweep"}


def test_default_names_never_collide(home, monkeypatch):
    """Four runs started at once, within the same second: four results directories."""
    runs = [subprocess.Popen([sys.executable, "-m", "vibrofric.cli", "analytic", LONGITUDINAL, *SHORT],
                             cwd=home, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
            for _ in range(4)]
    for run in runs:
        _, err = run.communicate(timeout=300)
        assert run.returncode == 0, err
    made = sorted((home / "results").iterdir())
    assert len(made) == 4 and all((d / "summary.json").exists() for d in made)
    # and names taken within one second in one process
    monkeypatch.chdir(home)
    names = {output.default_dir("x") for _ in range(3)}
    assert len(names) == 3 and all(name.is_dir() for name in names)


def test_a_claimed_name_stays_claimed_while_its_results_move_in(tmp_path, monkeypatch):
    """Another run finishing in the same second, asking for a default name just as
    this one's stage takes its claimed directory, gets a name of its own."""
    monkeypatch.chdir(tmp_path)
    second = output.datetime.datetime(2026, 1, 1, 12, 0, 0)  # every name taken within one second
    monkeypatch.setattr(output.datetime, "datetime", type("Clock", (), {"now": lambda: second}))
    mine, others = output.default_dir("x"), []

    def while_another_run_claims(move):
        """``move`` (a rename, or the exchange of two names), with another run asking for
        a default name as it moves a stage to ``mine``."""
        def moved(source, target):
            if Path(target) == mine:
                others.append(output.default_dir("x"))
            return move(source, target)
        return moved

    monkeypatch.setattr(Path, "rename", while_another_run_claims(Path.rename))
    monkeypatch.setattr(output, "_exchange", while_another_run_claims(output._exchange))
    with output.staged(mine, "analytic", claimed=True) as stage:
        (stage / "summary.json").write_text("{}")
    assert others == [mine.with_name(mine.name + "-2")]
    assert (mine / "summary.json").exists() and not any(others[0].iterdir())


def wait_for_frames(process, home: Path, frames: int, timeout: float = 300) -> None:
    """Wait until the run's staging directory holds ``frames`` ParaView frames:
    its FE time loop is under way."""
    deadline = time.monotonic() + timeout
    while len(list(home.glob(f".*{output.PARTIAL}*/paraview/*.vtu"))) < frames:
        assert process.poll() is None, "the run ended before it was interrupted"
        assert time.monotonic() < deadline
        time.sleep(0.05)



@pytest.mark.parametrize("how, said, code", [(signal.SIGINT, "(Ctrl-C)", 130),
                                             (signal.SIGTERM, "by SIGTERM", 143)])
def test_single_run_interrupted_in_its_time_loop_leaves_nothing(home, how, said, code):
    before = tree(home)
    run = subprocess.Popen([sys.executable, "-m", "vibrofric.cli", "run", LONGITUDINAL, *FE_SHORT,
                            "--set", "time.T=0.1", "--set", "fem.output_every=100", "--out", "R"],
                           cwd=home, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                           preexec_fn=as_in_a_terminal)
    wait_for_frames(run, home, 5)  # 400 steps of the FE time loop run, frames on disk
    run.send_signal(how)
    _, err = run.communicate(timeout=120)
    assert run.returncode == code
    assert err.decode().strip().splitlines()[-1] == f"vibrofric: run interrupted {said}; nothing was written"
    time.sleep(0.5)  # what a writer's destructor might still do happens by now
    assert tree(home) == before


def test_a_writer_the_failure_left_open_cannot_recreate_the_stage(tmp_path):
    """The interrupted run above, without its timing: a writer whose destructor writes
    a file (DOLFINx's VTKFile writes its .pvd again), still held by the frames of
    the work that an interrupt stopped. output.staged lets it go before it removes
    the stage; removed first, the writer's destructor would recreate it once the
    exception is dropped (it did, under load: a .R.part-*/paraview/block.pvd)."""
    class LateWriter:
        def __init__(self, path):
            self.path = path

        def __del__(self):
            self.path.parent.mkdir(parents=True, exist_ok=True)
            self.path.write_text("written by a destructor")

    def work(stage):
        writer = LateWriter(stage / "paraview" / "block.pvd")  # noqa: F841 (held by this frame)
        raise KeyboardInterrupt

    try:
        with output.staged(tmp_path / "R", "run") as stage:
            work(stage)
    except KeyboardInterrupt:
        pass
    assert list(tmp_path.iterdir()) == []


def worker_pids(parent: int) -> list:
    """The live processes whose parent is ``parent`` (from /proc/*/stat)."""
    pids = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[1]) == parent and fields[0] != "Z":
            pids.append(int(stat.parent.name))
    return pids


def alive(pid: int) -> bool:
    try:
        return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
def test_sweep_workers_die_with_their_parent(home):
    sweep = subprocess.Popen([sys.executable, "-m", "vibrofric.cli", "sweep", LONGITUDINAL,
                              "--set", "time.T=300", "--set", "time.series_dt=0.01",
                              "--set", "time.method=transient",   # stepped: minutes a point
                              "--grid", "vibration.k_v=2,3,4,6",
                              "--workers", "2", "--out", "S"],
                             cwd=home, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    while len(workers := worker_pids(sweep.pid)) < 2:
        if time.monotonic() > deadline or sweep.poll() is not None:
            sweep.kill()   # before reading its stderr, which its 300 s run would hold open
            pytest.fail(f"the sweep started {len(workers)} workers in 120 s: "
                        f"{sweep.communicate(timeout=30)[1]}")
        time.sleep(0.1)
    sweep.kill()  # kill -9: the parent cannot clean up
    sweep.wait()
    deadline = time.monotonic() + 10
    while any(alive(pid) for pid in workers):
        assert time.monotonic() < deadline, f"workers {workers} outlived their parent"
        time.sleep(0.1)


# --- never hand back a wrong number silently --------------------------------------------

def test_unsettled_average_is_flagged_and_warned(home):
    done = vibrofric(["analytic", LONGITUDINAL, *UNSETTLED, "--out", "U", "--json"], home)
    assert done.returncode == 0
    result = json.loads(done.stdout)
    assert result["settled"] is False and result["window_drift"] > 0.1
    assert "has not settled" in done.stderr and "lengthen time.T" in done.stderr
    written = json.loads((home / "U" / "summary.json").read_text())["analytic"]
    assert written["settled"] is False and written["window_drift"] == result["window_drift"]

    settled = vibrofric(["analytic", LONGITUDINAL, *SHORT, "--out", "S", "--json"], home)
    result = json.loads(settled.stdout)
    assert result["settled"] is True and result["window_drift"] <= result["settle_tolerance"]
    assert settled.stderr == ""


def test_sweep_counts_unsettled_points(home):
    done = vibrofric(["sweep", LONGITUDINAL, *UNSETTLED, "--grid", "vibration.k_v=2,6", "--out", "S",
                      "--json"], home)
    assert done.returncode == 0
    assert [r["settled"] for r in json.loads(done.stdout)] == [False, False]
    assert "2 unsettled" in done.stderr.strip().splitlines()[-1]


def test_longitudinal_stepper_refuses_a_transverse_scene(home):
    before = tree(home)
    done = vibrofric(["analytic", LONGITUDINAL, "--stepper", "longitudinal",
                      "--set", "vibration.theta_deg=270", "--out", "L"], home)
    assert done.returncode == 2 and "vibration.theta_deg" in one_line(done.stderr)
    assert tree(home) == before


@pytest.mark.parametrize("command", [["analytic"], ["run"], ["sweep", "--fe", "--grid", "vibration.k_v=2"]])
@pytest.mark.parametrize("setting, said", [
    ("fem.mesh=abc", "fem.mesh: unknown mesh level 'abc'"),
    ("fem.mesh=0x1x1", "fem.mesh: mesh level '0x1x1': every element count"),
    ("fem.integrator=fast", "fem.integrator: must be one of"),
    ("time.series_dt=2", "time.series_dt: 2.0 s is longer than time.T"),
    ("time.T=1e9", "time.T: 1e+09 s at time.dt = 1e-06 s is 1e+15 steps"),
    ("fem.mesh=200x200x200", "fem.mesh: '200x200x200' has 24,361,803 degrees of freedom"),
])
def test_scene_values_are_checked_before_any_work(home, command, setting, said):
    if setting.startswith("fem.mesh=200") and command[0] == "analytic":
        pytest.skip("the analytic stepper has no mesh")
    before = tree(home)
    name, *rest = command
    start = time.monotonic()
    done = vibrofric([name, LONGITUDINAL, *rest, "--set", setting, "--out", "X"], home)
    assert done.returncode == 2 and said in one_line(done.stderr)
    assert time.monotonic() - start < 30  # refused at once, not after meshing or stepping
    assert tree(home) == before


def test_sweep_of_only_invalid_points_reports_them(home):
    done = vibrofric(["sweep", LONGITUDINAL, "--grid", "vibration.k_v=-1", "--out", "S"], home)
    assert done.returncode == 4 and "Traceback" not in done.stderr
    assert "failed vibration.k_v=-1.0: invalid scene: vibration.k_v" in done.stderr


def test_worker_count_below_one_is_refused(home):
    done = vibrofric(["sweep", LONGITUDINAL, "--grid", "vibration.k_v=2", "--workers", "0"], home)
    assert done.returncode == 2 and "--workers 0: at least 1 process" in one_line(done.stderr)
    assert not (home / "results").exists()


# --- every mistake of the user: one line, exit 2, nothing written -----------------------

@pytest.mark.parametrize("name, content, said", [
    ("mine", None, "is a directory, not a scene file"),
    ("binary.toml", b"\xff\xfe\x00bad", "is not a text file (not UTF-8)"),
    ("table.toml", b"body = 3\n", "body: expected a table [body] of keys"),
    ("missing.toml", None, "no such scene file"),
])
def test_scene_files_that_are_not_scenes(home, name, content, said):
    path = home / name
    if content is not None:
        path.write_bytes(content)
    before = tree(home)
    done = vibrofric(["analytic", path, "--set", "body.mass=1"], home)
    assert done.returncode == 2 and said in one_line(done.stderr)
    assert tree(home) == before


def test_grid_values_are_compared_as_numbers(home):
    before = tree(home)
    twice = vibrofric(["sweep", LONGITUDINAL, "--grid", "vibration.k_v=2,2.0", "--out", "S"], home)
    assert twice.returncode == 2 and "gives the value 2.0 twice" in one_line(twice.stderr)
    split = vibrofric(["sweep", LONGITUDINAL, "--grid", "vibration.k_v=2", "--grid", "vibration.k_v=3",
                       "--out", "S"], home)
    assert split.returncode == 2 and "vibration.k_v: given in two --grid options" in one_line(split.stderr)
    assert tree(home) == before
    assert vibrofric(["sweep", LONGITUDINAL, *SHORT, "--grid", "vibration.k_v=2.0", "--out", "S"],
                     home).returncode == 0
    resumed = vibrofric(["sweep", LONGITUDINAL, *SHORT, "--grid", "vibration.k_v=2", "--out", "S"], home)
    assert resumed.returncode == 0 and "1 points (1 reused)" in resumed.stderr


# --- also ---------------------------------------------------------------------------------

def test_single_fe_run_shows_progress_unless_json_goes_to_a_pipe(home):
    args = ["run", LONGITUDINAL, *FE_SHORT, "--set", "fem.mesh=tiny", "--set", "time.T=0.03",
            "--set", "fem.output_every=0", "--set", "time.method=transient"]
    shown = vibrofric([*args, "--out", "A"], home)
    assert shown.returncode == 0, shown.stderr
    assert "FE: 100%|" in shown.stderr and "0.03/0.03 s simulated" in shown.stderr
    quiet = vibrofric([*args, "--out", "B", "--json"], home)
    assert quiet.returncode == 0 and "FE:" not in quiet.stderr
    assert json.loads(quiet.stdout)["out"] == "B"


def test_drive_force_plot_shows_the_whole_run(tmp_path):
    scene = scene_module.load(LONGITUDINAL)
    t = [0.0, 0.5, 1.0]
    series = TimeSeries(*([t] + [[0.0, 1.0, 2.0]] * 7))
    figure = plots.drive_force_figure({"run": series}, scene)
    assert figure.axes[0].get_xlim()[1] >= 1.0


def test_analytic_command_imports_nothing_of_the_fe_model(home):
    """``vibrofric analytic`` loads the stepper, never the FE stack; nor matplotlib,
    which its plot process imports (plot_worker)."""
    run = subprocess.run(
        [sys.executable, "-c",
         "import sys; from vibrofric.cli import main; "
         f"main(['analytic', {LONGITUDINAL!r}, '--set', 'time.T=0.2', '--out', 'A']); "
         "print(' '.join(sorted(name.split('.')[0] for name in sys.modules)))"],
        cwd=home, capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    loaded = set(run.stdout.splitlines()[-1].split())
    assert "numba" in loaded
    assert loaded.isdisjoint({"dolfinx", "ufl", "basix", "ffcx", "petsc4py", "mpi4py", "gmsh",
                              "meshio", "pyvista", "tqdm", "matplotlib"})
