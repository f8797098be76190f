"""Batch sweeps (vibrofric.batch): FE grids that agree however they are run,
survive being killed, and keep going past a failed point."""

import csv
import json
import pathlib
import shutil
import signal
import subprocess
import sys
import time

import pytest
from conftest import as_in_a_terminal, child_environment

from vibrofric.cli import EXIT_BAD_INPUT, EXIT_INTERRUPTED, EXIT_POINTS_FAILED, EXIT_TERMINATED, main

ROOT = pathlib.Path(__file__).resolve().parent.parent
SCENE = str(ROOT / "scenes" / "longitudinal.toml")
# The tiny mesh (24 DOFs) to 0.16 s, no ParaView frames: an FE point in ~0.3 s once warm.
# Stepped (time.method transient): a pool's or the MPI ranks' points equal the serial
# ones bit for bit. By their orbits they would agree only to the Newton tolerance: a
# sweep by continuation starts each worker's contiguous run from steady sliding.
TINY_FE = ["--set", "time.T=0.16", "--set", "fem.mesh=tiny", "--set", "fem.output_every=0",
           "--set", "time.method=transient"]
GRID_2X2 = ["--grid", "vibration.k_v=2,6", "--grid", "vibration.theta_deg=0,90"]


def fe_sweep(out, *more):
    return ["sweep", SCENE, *TINY_FE, *GRID_2X2, "--fe", "--out", str(out), *more]


def analytic_sweep(out, *more):
    return ["sweep", SCENE, "--set", "time.T=0.2", "--grid", "vibration.k_v=2,6", "--out", str(out), *more]


def command(args):
    """The vibrofric command in a fresh interpreter, as a user runs it.

    FE sweeps run this way, never in the test process, which they would leave
    with DOLFINx and MPI loaded (in which pyvista's rendering, in tests that
    read the ParaView series back, aborts if VTK was not loaded first:
    std::bad_alloc in VTK's std::regex).
    """
    return [sys.executable, "-m", "vibrofric.cli", *args]


def vibrofric(args):
    return subprocess.run(command(args), env=child_environment(), cwd=ROOT, capture_output=True, text=True,
                          timeout=300)


def results(out) -> list:
    with open(out / "results.csv") as f:
        return list(csv.DictReader(f))


def without_timing(rows) -> list:
    """The rows less their wall-time columns, the only ones that differ between runs."""
    return [{k: v for k, v in row.items() if not k.endswith("wall_time_s")} for row in rows]


def summary_times(out) -> dict:
    """Each finished point's summary.json modification time: rewritten only if rerun.
    (Hidden directories are partials, not yet renamed into place: not finished.)"""
    return {p.parent.name: p.stat().st_mtime_ns for p in (out / "points").glob("*/summary.json")
            if not p.parent.name.startswith(".")}


@pytest.fixture(scope="module")
def serial(tmp_path_factory):
    """The 2 x 2 FE grid run serially."""
    out = tmp_path_factory.mktemp("serial") / "sweep"
    done = vibrofric(fe_sweep(out, "--workers", "1"))
    assert done.returncode == 0, done.stderr
    return out


def test_serial_sweep_writes_every_point_and_the_study(serial):
    rows = results(serial)
    assert [(r["vibration.k_v"], r["vibration.theta_deg"]) for r in rows] == [
        ("2.0", "0.0"), ("2.0", "90.0"), ("6.0", "0.0"), ("6.0", "90.0")]
    assert list(rows[0])[:3] == ["vibration.k_v", "vibration.theta_deg", "fe.F_dv_over_F_d0"]
    assert {"analytic.F_dv_over_F_d0", "rel_error", "error"} <= set(rows[0])
    assert all(r["error"] == "" and 0 < float(r["fe.F_dv_over_F_d0"]) < 1 for r in rows)
    point = serial / "points" / "vibration.k_v=6.0,vibration.theta_deg=0.0"
    assert {"scene.toml", "summary.json", "timeseries.csv", "analytic_timeseries.csv"} <= {
        p.name for p in point.iterdir()}
    summary = json.loads((point / "summary.json").read_text())
    assert summary["point"] == {"vibration.k_v": 6, "vibration.theta_deg": 0}
    assert float(rows[2]["fe.F_dv_over_F_d0"]) == summary["result"]["fe"]["F_dv_over_F_d0"]
    assert {"scene.toml", "ratio_against_angle.png", "fe_error.png"} <= {p.name for p in serial.iterdir()}


def test_two_processes_give_the_serial_results(serial, tmp_path):
    out = tmp_path / "pool"
    done = vibrofric(fe_sweep(out, "--workers", "2", "--json"))
    assert done.returncode == 0, done.stderr
    records = json.loads(done.stdout)
    assert len(records) == 4 and {"fe", "analytic", "rel_error"} <= set(records[0])
    assert "sweep: 4 points (0 reused), 0 failed" in done.stderr and "worst |FE - analytic|" in done.stderr
    assert without_timing(results(out)) == without_timing(results(serial))


def mpi_launcher():
    """The mpirun of this interpreter's MPI: the one beside it (the PyPI wheel's
    MPICH) or else the one on PATH (Debian's Open MPI); None if there is none."""
    beside = pathlib.Path(sys.executable).parent / "mpirun"
    return str(beside) if beside.exists() else shutil.which("mpirun")


@pytest.mark.skipif(mpi_launcher() is None, reason="no mpirun")
def test_mpirun_on_two_ranks_gives_the_serial_results(serial, tmp_path):
    out = tmp_path / "mpi"
    # Only environment variables, no launcher flag: MPICH rejects Open MPI's
    # --oversubscribe and --allow-run-as-root and ignores these. Open MPI
    # refuses to run as root unless told twice, and more ranks than cores
    # only if allowed.
    env = child_environment(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
                      OMPI_MCA_rmaps_base_oversubscribe="1")
    done = subprocess.run([mpi_launcher(), "-n", "2", *command(fe_sweep(out))],
                          env=env, cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert done.stderr.count("sweep: 4 points") == 1  # rank 0 reports for both
    assert without_timing(results(out)) == without_timing(results(serial))


MPI_ENVIRONMENT = dict(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
                       OMPI_MCA_rmaps_base_oversubscribe="1")   # see the test above


@pytest.mark.skipif(mpi_launcher() is None, reason="no mpirun")
def test_mpirun_sweeps_by_continuation_give_the_results_of_one_worker(tmp_path):
    """The ranks work the same lanes (batch/lanes.py): results.csv equals one worker's."""
    runs = {}
    for name, launcher, more in [("one", [], ["--workers", "1"]), ("mpi", [mpi_launcher(), "-n", "2"], [])]:
        out = tmp_path / name
        done = subprocess.run([*launcher, *command(["sweep", SCENE, "--grid", "vibration.k_v=0:20:6",
                                                    "--out", str(out), *more])],
                              env=child_environment(**MPI_ENVIRONMENT), cwd=ROOT, capture_output=True,
                              text=True, timeout=300)
        assert done.returncode == 0, done.stderr
        runs[name] = without_timing(results(out))
    assert runs["mpi"] == runs["one"]


@pytest.mark.skipif(mpi_launcher() is None or "Open MPI" not in subprocess.run(
    [mpi_launcher() or "true", "--version"], capture_output=True, text=True).stdout, reason="no Open MPI")
@pytest.mark.parametrize("how", [signal.SIGTERM, signal.SIGKILL])
def test_mpirun_stopped_or_killed_takes_its_ranks_with_it(tmp_path, how):
    """SIGTERM to Open MPI's mpirun (it sends its ranks SIGTERM, for SIGINT too, and exits 1
    itself, whatever they return): one line from rank 0, no partial directory; SIGKILL to
    it: its ranks end too (mpi.end_with_launcher), within seconds."""
    out = tmp_path / "sweep"
    args = ["sweep", str(ROOT / "scenes" / "coupled.toml"), "--grid", "vibration.k_v=0:20:41",
            "--grid", "vibration.theta_deg=0:360:25", "--out", str(out)]
    launcher = subprocess.Popen([mpi_launcher(), "-n", "2", *command(args)],
                                env=child_environment(**MPI_ENVIRONMENT), cwd=ROOT,
                                stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    while not (out / "points").is_dir() or len(summary_times(out)) < 4:
        assert launcher.poll() is None and time.monotonic() < deadline, launcher.stderr.read()
        time.sleep(0.05)
    launcher.send_signal(how)
    launcher.wait(timeout=60)
    err = launcher.stderr.read()
    stopped = time.monotonic()
    while processes_running(str(out)) and time.monotonic() < stopped + 10:
        time.sleep(0.1)
    assert processes_running(str(out)) == []
    if how == signal.SIGTERM:
        assert launcher.returncode == 1
        assert err.count("vibrofric: sweep interrupted by SIGTERM (Open MPI's mpirun sends it") == 1, err
        assert [p.name for p in (out / "points").iterdir() if p.name.startswith(".")] == []


def test_the_rank_is_read_from_the_launchers_variables(monkeypatch):
    """parallel.launcher_rank: Open MPI's, Hydra's or PMIx's variable; none outside a
    launcher, nor under an inherited singleton (see batch.mpi.world)."""
    from vibrofric.parallel import RANK_VARIABLES, launcher_rank

    for variable in (*RANK_VARIABLES, "OMPI_MCA_ess"):
        monkeypatch.delenv(variable, raising=False)
    assert launcher_rank() is None
    monkeypatch.setenv("PMI_RANK", "3")
    assert launcher_rank() == 3
    monkeypatch.setenv("OMPI_MCA_ess", "singleton")
    assert launcher_rank() is None


def kill_after_its_first_point(args, out) -> None:
    """Start the sweep, SIGTERM it as soon as a point has finished, and see it stop."""
    sweep = subprocess.Popen(command(args), env=child_environment(), cwd=ROOT,
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    while not (out / "points").is_dir() or not summary_times(out):
        assert sweep.poll() is None and time.monotonic() < deadline, sweep.stderr.read()
        time.sleep(0.01)
    sweep.send_signal(signal.SIGTERM)
    assert sweep.wait(timeout=60) == EXIT_TERMINATED, sweep.stderr.read()


def test_a_killed_sweep_resumes_without_rerunning_finished_points(serial, tmp_path):
    out = tmp_path / "killed"
    kill_after_its_first_point(fe_sweep(out, "--workers", "1"), out)

    finished = summary_times(out)
    assert 1 <= len(finished) < 4
    # nothing half-written: the point in flight left at most a partial (hidden) directory
    assert {p.name for p in (out / "points").iterdir() if not p.name.startswith(".")} == set(finished)
    assert len(results(out)) == len(finished)

    done = vibrofric(fe_sweep(out, "--workers", "1"))
    assert done.returncode == 0, done.stderr
    assert f"({len(finished)} reused)" in done.stderr
    assert {name: summary_times(out)[name] for name in finished} == finished
    assert without_timing(results(out)) == without_timing(results(serial))
    assert not [p for p in (out / "points").iterdir() if p.name.startswith(".")]


def test_an_fe_sweep_on_a_measured_motion_reuses_its_finished_points(tmp_path):
    """An FE point's scene.toml names its files where they are, as every point's: a
    resumed sweep knows a point by that text (points.read_point). (Written as ``vibrofric
    run`` writes it, with the motion copied beside it, the text was not the point's
    scene's, and every resume ran every FE point again.)"""
    out = tmp_path / "sweep"
    args = ["sweep", str(ROOT / "examples" / "base_motion" / "measured.toml"), *TINY_FE,
            "--grid", "contact.mu=0.1,0.12", "--fe", "--out", str(out)]
    for run in range(2):
        done = vibrofric(args)
        assert done.returncode == 0, done.stderr
    assert "(2 reused)" in done.stderr
    assert not list((out / "points").glob("*/base_motion.csv"))


def processes_running(text) -> list:
    """Process ids whose command line mentions ``text`` (forked workers share their parent's)."""
    pids = []
    for cmdline in pathlib.Path("/proc").glob("[0-9]*/cmdline"):
        try:
            if text in cmdline.read_bytes().decode(errors="replace"):
                pids.append(int(cmdline.parent.name))
        except OSError:  # ended meanwhile
            pass
    return pids


def test_a_killed_pool_stops_its_workers_and_resumes(tmp_path):
    # ~30 ms a point, 30 points on two workers (and no figure for this grid); stepped, so
    # that the resumed sweep equals the whole one bit for bit (see TINY_FE)
    def pool_sweep(out):
        return ["sweep", SCENE, "--set", "time.T=0.5", "--set", "time.method=transient",
                "--grid", "vibration.theta_deg=0:348:30", "--out", str(out), "--workers", "2"]

    out = tmp_path / "killed"
    kill_after_its_first_point(pool_sweep(out), out)
    time.sleep(0.5)
    assert processes_running(str(out)) == []  # the workers went with it
    finished = summary_times(out)
    assert 1 <= len(finished) < 30 and len(results(out)) == len(finished)

    assert main(pool_sweep(out)) == 0
    assert {name: summary_times(out)[name] for name in finished} == finished
    whole = tmp_path / "whole"
    assert main(pool_sweep(whole)) == 0
    assert without_timing(results(out)) == without_timing(results(whole))



@pytest.mark.parametrize("how, code", [(signal.SIGINT, EXIT_INTERRUPTED), (signal.SIGTERM, EXIT_TERMINATED)])
def test_an_interrupted_pool_leaves_no_partial_directory(tmp_path, how, code):
    """Ctrl-C or SIGTERM to a two-worker sweep while both workers are inside a point
    (an analytic point stages its directory for its whole run: ~0.1 s stepped to
    T = 2 s): the workers end, their staged directories are cleared on the way out,
    and the exit code is 128 + the signal's number."""
    out = tmp_path / "sweep"
    args = ["sweep", SCENE, "--set", "time.T=2", "--set", "time.method=transient",
            "--grid", "vibration.theta_deg=0:348:30", "--out", str(out), "--workers", "2"]
    sweep = subprocess.Popen(command(args), env=child_environment(), cwd=ROOT, stdout=subprocess.DEVNULL,
                             stderr=subprocess.PIPE, text=True, preexec_fn=as_in_a_terminal)
    deadline = time.monotonic() + 120
    while not (out / "points").is_dir() or not summary_times(out):
        assert sweep.poll() is None and time.monotonic() < deadline, sweep.stderr.read()
        time.sleep(0.01)
    sweep.send_signal(how)
    assert sweep.wait(timeout=60) == code, sweep.stderr.read()
    assert [p.name for p in (out / "points").iterdir() if p.name.startswith(".")] == []
    assert len(results(out)) == len(summary_times(out)) >= 1


def test_an_invalid_point_fails_alone_and_is_reported(tmp_path):
    out = tmp_path / "sweep"
    done = vibrofric(["sweep", SCENE, *TINY_FE, "--grid", "vibration.k_v=6,-1", "--fe", "--out", str(out)])
    assert done.returncode == EXIT_POINTS_FAILED, done.stderr
    assert "1 failed" in done.stderr
    assert "failed vibration.k_v=-1.0: invalid scene: vibration.k_v" in done.stderr
    good, bad = results(out)
    assert good["error"] == "" and 0 < float(good["fe.F_dv_over_F_d0"]) < 1
    assert bad["vibration.k_v"] == "-1.0" and bad["fe.F_dv_over_F_d0"] == ""
    assert bad["error"].startswith("invalid scene: vibration.k_v: must be >= 0")
    assert "error" in json.loads((out / "points" / "vibration.k_v=-1.0" / "summary.json").read_text())


def test_a_point_that_fails_in_its_run_is_recorded_and_retried_alone(tmp_path, capsys):
    out = tmp_path / "sweep"
    # the paper's explicit update diverges at a stiff contact: numerical trouble in the run
    args = ["sweep", SCENE, "--set", "time.T=0.2", "--set", "contact.update=paper",
            "--grid", "contact.k_t=8e7,8e9", "--out", str(out)]
    assert main(args) == EXIT_POINTS_FAILED
    assert "failed contact.k_t=8000000000.0: numerical trouble" in capsys.readouterr().err
    failed = out / "points" / "contact.k_t=8000000000.0"
    assert sorted(p.name for p in failed.iterdir()) == ["checks.json", "scene.toml", "summary.json"]
    assert [r["error"] == "" for r in results(out)] == [True, False]

    before = summary_times(out)
    assert main(args) == EXIT_POINTS_FAILED
    after = summary_times(out)
    assert after["contact.k_t=80000000.0"] == before["contact.k_t=80000000.0"]
    assert after["contact.k_t=8000000000.0"] != before["contact.k_t=8000000000.0"]


def test_partial_point_directories_are_ignored_and_cleared(tmp_path):
    out = tmp_path / "sweep"
    assert main(analytic_sweep(out)) == 0
    # what a process killed mid-write (SIGKILL, node loss) leaves: a staging
    # directory that was never renamed into place, and no directory for its point
    point = out / "points" / "vibration.k_v=6.0"
    partial = out / "points" / ".vibration.k_v=6.0.part-123-abcdef12"
    point.rename(partial)
    before = summary_times(out)
    assert main(analytic_sweep(out)) == 0
    assert not partial.exists() and (point / "summary.json").exists()
    assert summary_times(out)["vibration.k_v=2.0"] == before["vibration.k_v=2.0"]
    assert len(results(out)) == 2


def test_another_scene_is_refused_on_a_sweeps_out_and_replaces_it_with_force(tmp_path, capsys):
    """A sweep of another base scene (here --set contact.mu) on a sweep's --out would
    rewrite the results.csv and scene.toml of the one there: refused in one line, exit 2,
    nothing touched; with --force it replaces it, every point run again."""
    out = tmp_path / "sweep"
    assert main(analytic_sweep(out)) == 0
    first = results(out)
    before = summary_times(out)
    scene_toml = (out / "scene.toml").read_bytes()
    capsys.readouterr()
    assert main(analytic_sweep(out, "--set", "contact.mu=0.12")) == EXIT_BAD_INPUT
    error = capsys.readouterr().err.strip().splitlines()
    assert len(error) == 1 and "another scene" in error[0] and "contact.mu" in error[0]
    assert results(out) == first and summary_times(out) == before
    assert (out / "scene.toml").read_bytes() == scene_toml
    assert main(analytic_sweep(out, "--set", "contact.mu=0.12", "--force")) == 0
    assert all(summary_times(out)[name] != mtime for name, mtime in before.items())
    assert [float(r["F_d0"]) for r in first] == [5.5, 5.5]
    assert [float(r["F_d0"]) for r in results(out)] == pytest.approx([6.6, 6.6])


def test_the_same_scene_with_a_grown_grid_resumes(tmp_path, capsys):
    """The same scene and --set with more grid values: the sweep there is resumed, its
    points reused."""
    out = tmp_path / "sweep"
    assert main(analytic_sweep(out)) == 0
    before = summary_times(out)
    capsys.readouterr()
    grown = ["sweep", SCENE, "--set", "time.T=0.2", "--grid", "vibration.k_v=2,6,20",
             "--out", str(out)]
    assert main(grown) == 0
    assert "(2 reused" in capsys.readouterr().err
    assert {name: summary_times(out)[name] for name in before} == before
    assert len(results(out)) == 3


@pytest.mark.parametrize("mistake", [["--set", "time.dt=0"], ["--grid", "bogus.key=1,2"],
                                     ["--grid", "vibration.f=1000,1000"]])
def test_command_line_mistakes_are_refused_before_any_work(tmp_path, capsys, mistake):
    out = tmp_path / "never"
    code = main(["sweep", SCENE, "--grid", "vibration.k_v=2,6", *mistake, "--fe", "--out", str(out)])
    assert code == EXIT_BAD_INPUT
    assert mistake[1].split("=")[0] in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


def test_a_sweep_by_continuation_gives_the_same_results_however_it_is_run(tmp_path):
    """Six k_v points by their periodic orbits (two lanes): one worker, two workers twice,
    and vibrofric.sweep in memory give the same numbers bit for bit, timing aside. (Before
    the lanes were a function of the grid alone, two-worker runs differed from each other
    by up to 5e-12 and from one worker by 6.7e-9: each point's Newton start depended on
    the pool's timing.)"""
    from vibrofric import api

    def run(name, workers):
        out = tmp_path / name
        args = ["sweep", SCENE, "--grid", "vibration.k_v=0:20:6", "--out", str(out), "--workers", workers]
        assert main(args) == 0
        return without_timing(results(out))

    one = run("one", "1")
    assert run("two", "2") == one and run("two-again", "2") == one
    table = api.sweep(api.load_scene("longitudinal"), {"vibration.k_v": [0, 4, 8, 12, 16, 20]})
    assert [float(r["F_dv_over_F_d0"]) for r in one] == list(table["F_dv_over_F_d0"])
    assert sum(r["periodic.method"] == "periodic" for r in one) >= 4   # continuation was used


@pytest.mark.slow
def test_an_fe_sweep_by_continuation_gives_the_same_results_on_one_worker_and_two(tmp_path):
    """Six FE points by their periodic orbits (tiny mesh, reduced; two lanes): one worker
    and two give the same results.csv bit for bit, timing aside (~10 s once compiled)."""
    runs = []
    for workers in ("1", "2"):
        out = tmp_path / workers
        done = vibrofric(["sweep", SCENE, "--fe", "--set", "fem.mesh=tiny", "--set", "fem.output_every=0",
                          "--set", "fem.integrator=reduced", "--set", "time.dt=1e-5", "--set", "time.T=0.3",
                          "--grid", "vibration.k_v=2:12:6", "--out", str(out), "--workers", workers])
        assert done.returncode == 0, done.stderr
        assert "6 answered by their periodic orbit" in done.stderr
        runs.append(without_timing(results(out)))
    assert runs[0] == runs[1]


def test_a_sweep_over_the_law_and_another_key_runs_every_point(tmp_path):
    """contact.law with k_v: each law's points are a lane of their own (an orbit's state
    has the law's size: a LuGre point started from a Dahl orbit failed with 'operands
    could not be broadcast'), on one worker and on two."""
    law = str(ROOT / "examples" / "laws" / "jenkins.py")
    for workers in ("1", "2"):
        out = tmp_path / workers
        args = ["sweep", SCENE, "--grid", f"contact.law=dahl,lugre,{law}", "--grid", "vibration.k_v=2,6",
                "--out", str(out), "--workers", workers]
        assert main(args) == 0
        rows = results(out)
        assert len(rows) == 6 and all(r["error"] == "" for r in rows)
    assert without_timing(results(tmp_path / "1")) == without_timing(results(tmp_path / "2"))


def test_workers_are_never_more_than_the_points_or_the_cores_unless_asked_twice(monkeypatch):
    """parallel.worker_count on a machine of 2 cores: never more processes than tasks that
    can run side by side, nor than the cores without oversubscribe, nor than fit in memory;
    a line says why, when fewer than asked for run."""
    from vibrofric import parallel

    monkeypatch.setattr(parallel, "cores", lambda: 2)
    count, note = parallel.worker_count(100000, 2, what="points")
    assert note == "vibrofric: --workers 100000: 2 processes, as the sweep has 2 points to run side by side"
    assert count == 2
    count, note = parallel.worker_count(5, 10)
    assert count == 2 and "2 cores" in note and "--oversubscribe" in note
    assert parallel.worker_count(5, 10, oversubscribe=True) == (5, None)
    assert parallel.worker_count(5, 3, oversubscribe=True)[0] == 3
    count, note = parallel.worker_count(5, 10, True, worker_bytes=2**30, available=3 * 2**30)
    assert count == 3 and "memory" in note
    assert parallel.worker_count(None, 10) == (2, None)       # the default: both cores, said nothing
    assert parallel.worker_count(None, 1) == (1, None)


def test_a_sweep_asked_for_more_workers_than_points_runs_as_many_as_it_can_and_says_so(tmp_path, capsys):
    """--workers 100000 on two points (stepped: each point on its own) starts two
    processes, says so in one line, and gives the serial results."""
    out = tmp_path / "many"
    assert main(analytic_sweep(out, "--set", "time.method=transient", "--workers", "100000")) == 0
    err = capsys.readouterr().err
    assert "vibrofric: --workers 100000: 2 processes, as the sweep has 2 points to run side by side" in err
    serial = tmp_path / "serial"
    assert main(analytic_sweep(serial, "--set", "time.method=transient", "--workers", "1")) == 0
    assert without_timing(results(out)) == without_timing(results(serial))
    capsys.readouterr()
    over = tmp_path / "over"   # three points, three processes even on two cores: asked twice
    args = ["sweep", SCENE, "--set", "time.T=0.2", "--set", "time.method=transient",
            "--grid", "vibration.k_v=2,6,20", "--out", str(over), "--workers", "3", "--oversubscribe"]
    assert main(args) == 0
    assert "--workers" not in capsys.readouterr().err


# Runs the command given as its arguments and prints its exit code and peak resident
# memory (KiB). Launched from a small interpreter rather than from the test process:
# Linux counts in a child's ru_maxrss the memory of the process it was forked from at
# its exec, so a command started from a pytest worker holding over 1 GiB (after FE
# tests) reports that worker's peak, not its own.
PEAK_OF_CHILD = """
import resource, subprocess, sys
code = subprocess.run(sys.argv[1:]).returncode
print(code, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)
"""


@pytest.mark.parametrize("count", ["1000000000", "10000000000000000000000"])
def test_a_grid_too_large_is_refused_in_one_line_before_it_is_expanded(tmp_path, count):
    """A range of 1e9 or 1e22 values is counted, not made (grid.Range): refused in one line
    naming the grid and what it would take, exit 2, nothing written, and without the
    memory a list of its values would take (1e9 floats: 24 GB before; the child's peak is
    allowed 1 GB, several times what the command needs to load). Not timed: the
    command's imports and a first compile take what the machine's load makes them."""
    grid = f"vibration.k_v=0:20:{count}"
    child = subprocess.run([sys.executable, "-c", PEAK_OF_CHILD,
                            *command(["sweep", SCENE, "--grid", grid, "--out", str(tmp_path / "never")])],
                           env=child_environment(), cwd=ROOT, capture_output=True, text=True)
    returncode, peak = map(int, child.stdout.split())
    err = child.stderr.strip().splitlines()
    assert returncode == EXIT_BAD_INPUT and len(err) == 1, err
    assert err[0].startswith(f"vibrofric: invalid scene: --grid {grid}: {int(count):,} points would take")
    assert "of disk" in err[0] and "of computing on" in err[0]
    assert peak < 2**20      # KiB: 1 GiB
    assert list(tmp_path.iterdir()) == []


def test_a_long_sweep_is_announced_and_a_short_one_is_not(tmp_path):
    """budget.check_grid's estimate of a million-point grid passes (it fits) and is
    announced in one line; the Fig 6 grid of 41 points says nothing."""
    from vibrofric import budget
    from vibrofric import scene as scenes
    from vibrofric.grid import Range

    base = scenes.load(pathlib.Path(SCENE))
    needs = budget.check_grid([("vibration.k_v", Range(0.0, 20.0, 10**6))], [base], False, tmp_path, 2)
    notice = budget.long_sweep_notice(needs, 2)
    assert needs["points"] == 10**6 and notice.startswith("vibrofric: a sweep of 1,000,000 points")
    assert "\n" not in notice and "of computing on 2 processes" in notice
    short = budget.check_grid([("vibration.k_v", Range(0.0, 20.0, 41))], [base], False, tmp_path, 2)
    assert budget.long_sweep_notice(short, 2) is None


def test_grid_ranges_are_numpys_linspace_value_for_value():
    """grid.Range computes each value as numpy.linspace does (point names depend on it)."""
    import numpy as np

    from vibrofric.grid import Range, parse_grid

    for start, stop, count in [(0, 20, 41), (0, 360, 25), (0.1, 0.7, 13), (1e-3, 3.3, 7), (2, 2, 1),
                               (5, -3, 9)]:
        expected = [float(v) for v in np.linspace(start, stop, count)]
        assert list(Range(float(start), float(stop), count)) == expected
    assert parse_grid("vibration.k_v=0:20:1e22")[1][-1] == 20.0


def test_the_summary_line_counts_every_point_by_how_it_was_answered(tmp_path):
    """A grid over time.method: the points stepped because their scene said transient are
    counted as stepped, beside those whose orbit did not answer: every point is counted."""
    from vibrofric.batch.study import Outcome

    stepped = {"periodic": {"method": "transient", "reason": "no stable orbit"}}
    records = [{"time.method": "transient"}, {"time.method": "periodic", "periodic": {"method": "periodic"}},
               {"time.method": "auto", **stepped}, {"time.method": "auto", "error": "invalid scene: ..."}]
    line = Outcome(records, ["time.method"], tmp_path, 0, 1.0, True).summary_line()
    assert "; 1 answered by their periodic orbit, 2 stepped;" in line
    only_stepped = Outcome(records[:1], ["time.method"], tmp_path, 0, 1.0, True).summary_line()
    assert "periodic orbit" not in only_stepped


def test_lanes_are_a_function_of_the_grid_alone():
    """Lanes run along the last key between float values, at most LANE_POINTS long, cut
    near-equally; a law (any value not a float) is never crossed: each such point is a
    lane of its own, and a row of another key's value starts new lanes."""
    from vibrofric.batch.lanes import LANE_POINTS, lanes
    from vibrofric.grid import Range, canonical_grid, grid_points

    def cut(*grid):
        return lanes(list(grid_points(canonical_grid(list(grid)))))

    assert LANE_POINTS == 4   # the cases below are written for it
    assert cut(("vibration.k_v", Range(0.0, 20.0, 6))) == [[0, 1, 2], [3, 4, 5]]
    assert cut(("vibration.k_v", Range(0.0, 20.0, 9))) == [[0, 1, 2], [3, 4, 5], [6, 7, 8]]
    assert cut(("contact.law", ["dahl", "lugre"]), ("vibration.k_v", [2, 6])) == [[0, 1], [2, 3]]
    assert cut(("vibration.k_v", [2, 6]), ("contact.law", ["dahl", "lugre"])) == [[0], [1], [2], [3]]


def run_lanes(tmp_path, monkeypatch, workers, completion_order, finished_before=()):
    """_run_by_continuation on a 2 x 6 grid (two rows of two lanes each) with a pool
    that finishes its tasks in the order ``completion_order`` picks from those in flight;
    each point's "orbit" is its name, and a point finished by an earlier run (named in
    ``finished_before``) holds "disk:<name>". Returns (the points in grid order, {point:
    the start it was given}, the most tasks in flight at once, the points reported)."""
    from vibrofric import scene as scenes
    from vibrofric.batch import study
    from vibrofric.batch.ledger import Ledger
    from vibrofric.batch.points import plan

    base = scenes.load(pathlib.Path(SCENE), ['time.method="periodic"'])
    grid = [("vibration.theta_deg", [0.0, 90.0]), ("vibration.k_v", [2.0, 3.0, 4.0, 6.0, 12.0, 20.0])]
    ledger = Ledger(plan(base, grid, tmp_path / "points"), "fe", tmp_path)
    names = [point.name for point in ledger.points]
    starts, flights = {}, []

    def pool(function, tasks, pool_workers, on_result):
        assert pool_workers == workers
        flight = list(tasks)
        while flight:
            flights.append(len(flight))
            task = flight.pop(completion_order(len(flight)))
            point, _, start, _ = task
            starts[point.name] = start
            flight.extend(on_result(task, point.name) or ())

    def in_process(point, mode, start):
        starts[point.name] = start
        return point.name

    monkeypatch.setattr(study, "run_on_pool", pool)
    monkeypatch.setattr(study, "run_point", in_process)
    monkeypatch.setattr(study, "neighbour_orbit", lambda directory: f"disk:{directory.name}")
    todo = [point for point in ledger.points if point.name not in finished_before]
    reported = []
    study._run_by_continuation(todo, ledger, "fe", workers, reported.append)
    return names, starts, max(flights, default=1), [point.name for point in reported]


@pytest.mark.parametrize("workers, order", [(1, "first"), (2, "first"), (2, "last"), (3, "last"),
                                            (9, "first")])
def test_every_point_starts_from_its_lanes_point_before_however_many_workers(
        tmp_path, monkeypatch, workers, order):
    """Whatever the workers and whichever task ends first: every point runs once, from
    the orbit of the point before it in its lane (lanes.py: here [0 1 2] [3 4 5] of each
    row), a lane's first from none; no more lanes at once than workers."""
    pick = (lambda n: 0) if order == "first" else (lambda n: n - 1)
    names, starts, most, reported = run_lanes(tmp_path, monkeypatch, workers, pick)
    assert sorted(reported) == sorted(names)
    firsts = {0, 3, 6, 9}
    assert [starts[name] for name in names] == [
        None if k in firsts else names[k - 1] for k in range(len(names))]
    assert most <= workers


def test_a_resumed_sweep_starts_from_the_orbits_its_finished_points_left(tmp_path, monkeypatch):
    """A point whose lane's point before it was finished by an earlier run starts from
    the orbit that one's directory holds, as it would have in one run."""
    from vibrofric.grid import point_name

    done = {point_name({"vibration.theta_deg": 0.0, "vibration.k_v": 3.0})}
    names, starts, _, reported = run_lanes(tmp_path, monkeypatch, 2, lambda n: 0, done)
    assert sorted(reported) == sorted(set(names) - done)
    assert starts[names[2]] == f"disk:{names[1]}" and starts[names[0]] is None


def test_the_sweeps_time_left_leaves_out_each_workers_first_point(tmp_path):
    """Progress: no time left until each worker's first point has finished (it loads or
    compiles the loops), then the rate since then: here a first point of 30 s (a
    compile), then a point every second, 8 of 10 left."""
    from types import SimpleNamespace

    from vibrofric.batch.study import Progress

    now = [0.0]
    ledger = SimpleNamespace(points=list(range(10)), records={}, failed=[])
    bar = Progress(ledger, enabled=False, warm_up=1, clock=lambda: now[0])
    shown = []

    def finish(seconds):
        now[0] += seconds
        ledger.records[len(ledger.records)] = {}
        bar.update()
        shown.append(bar.bar.postfix)

    finish(30.0)
    finish(1.0)
    finish(1.0)
    assert "left" not in shown[0]        # the compile's point: no rate from it
    assert shown[1].endswith("left=8 s") and shown[2].endswith("left=7 s")
