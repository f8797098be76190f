"""Faults and hostile input: colliding writers, kills at any moment, damaged
sweep points, odd --out targets, a full disk, nonsense scene values.

Each case asserts what the user sees (exit code, one line on stderr) and what
the file system holds afterwards: old or new results whole, nothing hidden left.
"""

import json
import os
import random
import shutil
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest
from conftest import as_in_a_terminal, child_environment

from vibrofric import output
from vibrofric.cli import EXIT_BAD_INPUT, main

ROOT = Path(__file__).resolve().parent.parent
SCENE = str(ROOT / "scenes" / "longitudinal.toml")
SHORT = ["--set", "time.T=0.2"]


def vibrofric(args, cwd, **popen):
    return subprocess.run([sys.executable, "-m", "vibrofric.cli", *map(str, args)], cwd=cwd,
                          env=child_environment(), capture_output=True, text=True, timeout=600,
                          **popen)


def whole(directory: Path) -> dict:
    """The results of an analytic run in ``directory``, checked whole: marker,
    scene, summary and series all there and readable."""
    assert output.read_marker(directory) == {"command": "analytic"}
    summary = json.loads((directory / "summary.json").read_text())
    assert (directory / "scene.toml").read_text().startswith("[")
    lines = (directory / "timeseries.csv").read_text().splitlines()
    assert len(lines) > 10 and lines[-1].count(",") == lines[0].count(",")
    return summary


def hidden(parent: Path) -> list:
    return sorted(p.name for p in parent.iterdir() if p.name.startswith("."))


# -- 1. one writer at a time -------------------------------------------------------------------

def test_a_second_writer_is_refused_at_once_in_one_line(tmp_path, capsys):
    out = tmp_path / "R"
    with output.locked(out):
        code = main(["analytic", SCENE, *SHORT, "--out", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == EXIT_BAD_INPUT
    assert len(err) == 1 and "another vibrofric process is writing it now" in err[0]
    assert list(tmp_path.iterdir()) == []  # nothing made, and the lock file gone with its holder


def test_a_sweep_is_locked_too(tmp_path, capsys):
    out = tmp_path / "S"
    with output.locked(out):
        code = main(["sweep", SCENE, *SHORT, "--grid", "vibration.k_v=2,6", "--out", str(out)])
    assert code == EXIT_BAD_INPUT
    assert "another vibrofric process" in capsys.readouterr().err
    assert not out.exists()


def test_the_lock_is_taken_over_from_a_killed_holder(tmp_path):
    """The kernel drops a dead process's flock; its lock file left behind is no obstacle."""
    out = tmp_path / "R"
    holder = subprocess.Popen([sys.executable, "-c", textwrap.dedent(f"""
        import time
        from vibrofric import output
        with output.locked({str(out)!r}):
            print("held", flush=True)
            time.sleep(60)
        """)], env=child_environment(), stdout=subprocess.PIPE, text=True)
    assert holder.stdout.readline() == "held\n"
    with pytest.raises(output.Busy):
        with output.locked(out):
            pass
    holder.kill()
    holder.wait()
    assert (tmp_path / ".R.lock").exists()
    with output.locked(out) as target:
        assert target == out
    assert list(tmp_path.iterdir()) == []


def test_two_commands_on_one_out_never_both_claim_success(tmp_path):
    """A run beside another into the same --out, no --force: one writes, the other is
    refused (busy, or finding the first one's results); never both 'results in'."""
    runs = [subprocess.Popen([sys.executable, "-m", "vibrofric.cli", "analytic", SCENE, *SHORT,
                              "--set", f"vibration.k_v={k}", "--out", "R"],
                             cwd=tmp_path, env=child_environment(), stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True) for k in (2, 6)]
    done = [(run.wait(timeout=300), run.communicate()) for run in runs]
    codes = sorted(code for code, _ in done)
    assert codes == [0, EXIT_BAD_INPUT], done
    (out, err), = [streams for code, streams in done if code == 0]
    summary = whole(tmp_path / "R")  # which one won is up to the scheduler
    assert summary["analytic"]["F_dv_over_F_d0"] == pytest.approx(
        float(out.split("F_dv/F_d0 = ")[1].split()[0]), abs=1e-4)  # printed to 4 decimals
    assert hidden(tmp_path) == []


# -- 2. --force replaces whole --------------------------------------------------------------------

def test_force_swaps_old_and_new_in_one_step(tmp_path, monkeypatch):
    """Seen at the moment the new results move in: the name holds the old or the new, whole."""
    target = tmp_path / "R"
    with output.staged(target, "analytic") as stage:
        (stage / "summary.json").write_text('"old"')
    seen = []
    exchange = output._exchange

    def watched(a, b):
        seen.append((b / "summary.json").read_text())
        done = exchange(a, b)
        seen.append((b / "summary.json").read_text())
        return done

    monkeypatch.setattr(output, "_exchange", watched)
    with output.staged(target, "analytic") as stage:
        (stage / "summary.json").write_text('"new"')
    assert seen == ['"old"', '"new"']
    assert (target / "summary.json").read_text() == '"new"' and hidden(tmp_path) == []


def test_force_without_an_exchanging_file_system_renames_aside_first(tmp_path, monkeypatch):
    monkeypatch.setattr(output, "_exchange", lambda a, b: False)
    target = tmp_path / "R"
    for text in ('"old"', '"new"'):
        with output.staged(target, "analytic") as stage:
            (stage / "summary.json").write_text(text)
    assert (target / "summary.json").read_text() == '"new"' and hidden(tmp_path) == []


KILLED_WRITER = """
import sys
from pathlib import Path
from vibrofric import output
target, n = Path(sys.argv[1]), 0
print("started", flush=True)
while True:
    n += 1
    with output.staged(target, "analytic") as stage:
        for i in range(200):  # a directory big enough to take a while to write and delete
            (stage / f"f{i}.txt").write_text(str(n) * 200)
        (stage / "summary.json").write_text(str(n))
"""


@pytest.mark.parametrize("seed", range(3))
def test_kill_harness_replacing_results_in_a_loop(tmp_path, seed):
    """A writer replacing its results over and over, killed at random moments by
    SIGINT, SIGTERM or SIGKILL: the name always holds one whole result set, and
    what the kill left beside it is found and cleared."""
    rng = random.Random(seed)
    target = tmp_path / "R"
    for _ in range(5):
        child = subprocess.Popen([sys.executable, "-c", KILLED_WRITER, str(target)],
                                 env=child_environment(), stdout=subprocess.PIPE, text=True,
                                 preexec_fn=as_in_a_terminal)
        try:
            assert child.stdout.readline() == "started\n"
            time.sleep(rng.uniform(0.05, 0.4))
            child.send_signal(rng.choice([signal.SIGINT, signal.SIGTERM, signal.SIGKILL]))
            child.wait(timeout=30)
        finally:  # a writer that outlived its signal would loop on after the test
            child.kill()
            child.wait()
        if target.exists():
            n = (target / "summary.json").read_text()
            files = sorted(p.name for p in target.iterdir())
            assert len(files) == 202 and all((target / f"f{i}.txt").read_text() == n * 200
                                             for i in range(200))
        output.clear_leftovers(target)
        assert hidden(tmp_path) == []


STARTING_COMMAND = """
import os, signal, sys
sys.argv = ["vibrofric", "analytic", "scene.toml"]
import vibrofric.cli  # the command's process, still starting: main() not yet called
os.kill(os.getpid(), signal.{signal})
print("not ended")
"""


@pytest.mark.parametrize("name, code", [("SIGINT", 130), ("SIGTERM", 143)])
def test_signal_while_the_command_starts_ends_it_with_128_and_its_number(tmp_path, name, code):
    """A signal while the command is still importing (seen under load: the random kills
    of the next test came before main() took over and the command died of the signal,
    exit -2) ends it the same way as later: one line, exit 130 (SIGINT) or 143
    (SIGTERM), nothing written."""
    child = subprocess.run([sys.executable, "-c", STARTING_COMMAND.format(signal=name)],
                           cwd=tmp_path, env=child_environment(), capture_output=True, text=True,
                           timeout=60, preexec_fn=as_in_a_terminal)
    assert child.returncode == code, child.stderr
    assert child.stderr == "vibrofric: interrupted while starting; nothing was written\n"
    assert "not ended" not in child.stdout and list(tmp_path.iterdir()) == []


def test_cli_kill_harness_force_replacement(tmp_path):
    """The command itself, --force into results of its own, killed at random moments:
    R holds whole results (the old or the new) each time, and the next run leaves
    nothing hidden beside it."""
    rng = random.Random(7)
    assert vibrofric(["analytic", SCENE, *SHORT, "--out", "R"], tmp_path).returncode == 0
    for _ in range(4):
        child = subprocess.Popen([sys.executable, "-m", "vibrofric.cli", "analytic", SCENE, *SHORT,
                                  "--out", "R", "--force"], cwd=tmp_path, env=child_environment(),
                                 stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                 preexec_fn=as_in_a_terminal)
        time.sleep(rng.uniform(0.3, 3.0))
        child.send_signal(rng.choice([signal.SIGINT, signal.SIGTERM, signal.SIGKILL]))
        child.communicate(timeout=60)
        # 130 / 143 interrupted, 0 finished first; killed by the signal itself (-2, -15)
        # where it lands after the command's end, while Python shuts down with its
        # handlers reset (seen once, on the PyPI stack): the results are whole in every case,
        # which is what this checks
        assert child.returncode in (0, 130, 143, -signal.SIGINT, -signal.SIGTERM,
                                    -signal.SIGKILL)
        whole(tmp_path / "R")
    done = vibrofric(["analytic", SCENE, *SHORT, "--out", "R", "--force"], tmp_path)
    assert done.returncode == 0, done.stderr
    whole(tmp_path / "R")
    assert hidden(tmp_path) == []


def test_leftovers_beside_the_target_are_cleared_and_reported(tmp_path, capsys):
    (tmp_path / ".R.part-123-abcdef12").mkdir()
    (tmp_path / ".R.part-old-123-abcdef13").mkdir()
    assert main(["analytic", SCENE, *SHORT, "--out", str(tmp_path / "R")]) == 0
    err = capsys.readouterr().err
    assert "removed what a killed run left beside" in err and ".R.part-old-123-abcdef13" in err
    assert hidden(tmp_path) == []


# -- 3. odd --out targets ----------------------------------------------------------------------

def test_out_through_a_symlink_writes_into_its_folder_and_keeps_the_link(tmp_path):
    (tmp_path / "real").mkdir()
    (tmp_path / "link").symlink_to("real")
    for more in ([], ["--force"]):
        done = vibrofric(["analytic", SCENE, *SHORT, "--out", "link", *more], tmp_path)
        assert done.returncode == 0, done.stderr
        assert (tmp_path / "link").is_symlink() and os.readlink(tmp_path / "link") == "real"
        whole(tmp_path / "real")
    assert hidden(tmp_path) == []


def test_out_on_a_mount_point_is_refused_before_any_work(tmp_path, capsys, monkeypatch):
    out = tmp_path / "mnt"
    out.mkdir()
    mounted = os.path.ismount
    monkeypatch.setattr(output.os.path, "ismount", lambda p: Path(p) == out or mounted(p))
    assert main(["analytic", SCENE, *SHORT, "--out", str(out)]) == EXIT_BAD_INPUT
    err = capsys.readouterr().err
    assert "is a mount point" in err and f"--out {out / 'results'}" in err
    assert list(tmp_path.iterdir()) == [out] and list(out.iterdir()) == []


def test_a_bind_mount_of_the_same_file_system_is_found_by_the_kernels_table(tmp_path, capsys,
                                                                            monkeypatch):
    """A folder bind-mounted from the same file system has its parent's device, so
    os.path.ismount misses it (the rename into it then failed with EBUSY after all the
    work, exit 1, results left hidden beside it); the mount table lists it."""
    out = tmp_path / "with space"
    out.mkdir()
    table = tmp_path / "mountinfo"
    table.write_text(f"22 1 8:1 / / rw - ext4 /dev/vda rw\n"
                     f"98 22 8:1 /srv/data {str(out).replace(' ', chr(92) + '040')} rw - ext4 "
                     f"/dev/vda rw\n")
    monkeypatch.setattr(output, "MOUNTINFO", table)
    assert not os.path.ismount(out) and output.is_mount_point(out)
    for command in (["analytic"], ["sweep", "--grid", "vibration.k_v=2,6"]):
        assert main([command[0], SCENE, *command[1:], *SHORT, "--out", str(out)]) == EXIT_BAD_INPUT
        assert "is a mount point" in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["mountinfo", "with space"]
    assert list(out.iterdir()) == []


@pytest.mark.skipif(os.geteuid() != 0 or not shutil.which("unshare"),
                    reason="a real bind mount needs root (in a private mount namespace)")
def test_out_on_a_real_bind_mount_is_refused_before_any_work(tmp_path):
    """The same with a real bind mount, made in a mount namespace of its own so that
    nothing outside the test sees it."""
    source, out = tmp_path / "source", tmp_path / "out"
    source.mkdir()
    out.mkdir()
    cannot_mount = 97
    script = (f"mount --bind {source} {out} || exit {cannot_mount}; {sys.executable} -m "
              f"vibrofric.cli analytic {SCENE} {' '.join(SHORT)} --out {out}")
    done = subprocess.run(["unshare", "-m", "sh", "-c", script], cwd=tmp_path, timeout=600,
                          env=child_environment(), capture_output=True, text=True)
    if done.returncode == cannot_mount:
        pytest.skip(f"cannot bind-mount here: {done.stderr.strip()}")
    assert done.returncode == EXIT_BAD_INPUT, done.stderr
    assert "is a mount point" in done.stderr and done.stderr.count("\n") == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out", "source"]
    assert list(source.iterdir()) == []


# -- 4. damaged sweep points -----------------------------------------------------------------------

def analytic_sweep(out):
    return ["sweep", SCENE, *SHORT, "--grid", "vibration.k_v=2,6", "--workers", "1", "--out", str(out)]


def damage_summary(text):
    def damage(point: Path):
        (point / "summary.json").write_text(text)
    return damage


def edit_ratio(value):
    def damage(point: Path):
        summary = json.loads((point / "summary.json").read_text())
        summary["result"]["F_dv_over_F_d0"] = value
        (point / "summary.json").write_text(json.dumps(summary))
    return damage


def replace_with_a_file(point: Path):
    import shutil

    shutil.rmtree(point)
    point.write_text("not a point")


def truncate_scene(point: Path):
    with open(point / "scene.toml", "r+") as f:
        f.truncate(10)


DAMAGES = {"[]": damage_summary("[]"), "{}": damage_summary("{}"),
           "random bytes": damage_summary("\x00\x9f garbage \xff"),
           "ratio 9.2": edit_ratio(9.2), "ratio NaN": edit_ratio("NaN"),
           "point folder a file": replace_with_a_file, "scene.toml truncated": truncate_scene,
           "checks.json gone": lambda point: (point / output.CHECKS).unlink()}


@pytest.mark.parametrize("damage", DAMAGES.values(), ids=DAMAGES.keys())
def test_a_damaged_point_is_recomputed_and_counted(tmp_path, capsys, damage):
    out = tmp_path / "S"
    assert main(analytic_sweep(out)) == 0
    good = json.loads((out / "points" / "vibration.k_v=6.0" / "summary.json").read_text())
    capsys.readouterr()
    damage(out / "points" / "vibration.k_v=6.0")
    assert main(analytic_sweep(out)) == 0
    last = capsys.readouterr().err.strip().splitlines()[-1]
    assert "2 points (1 reused, 1 found damaged and rerun), 0 failed" in last
    again = json.loads((out / "points" / "vibration.k_v=6.0" / "summary.json").read_text())
    assert again["result"]["F_dv_over_F_d0"] == good["result"]["F_dv_over_F_d0"]
    assert output.checks_out(out / "points" / "vibration.k_v=6.0")


# -- 8. unexpected failures: one line, and where the traceback went ---------------------------------

def test_an_unexpected_error_prints_one_line_and_logs_the_traceback(tmp_path, capsys, monkeypatch):
    from vibrofric.analytic import solve as analytic_solve

    def broken(*args, **kwargs):
        raise ZeroDivisionError("a bug")

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    monkeypatch.setattr(analytic_solve, "solve", broken)
    assert main(["analytic", SCENE, *SHORT, "--out", str(tmp_path / "R")]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "analytic failed unexpectedly: ZeroDivisionError: a bug" in err[0]
    log, = (tmp_path / "cache" / "vibrofric").iterdir()
    assert str(log) in err[0] and "Traceback" in log.read_text() and "a bug" in log.read_text()
    assert not (tmp_path / "R").exists()


# -- 9. the disk --------------------------------------------------------------------------------------

def test_an_analytic_sweep_is_estimated_at_what_it_writes(tmp_path):
    """A point writes scene.toml, summary.json and checks.json (~5 kB, 16 KiB of blocks
    with its directory), not the time series it never keeps."""
    from vibrofric import budget
    from vibrofric import scene as scene_module

    scene = scene_module.load(SCENE)
    assert budget.estimate(scene, fe=False, series=False)["disk"] == budget.POINT_BYTES
    assert main(analytic_sweep(tmp_path / "S")) == 0
    point = tmp_path / "S" / "points" / "vibration.k_v=2.0"
    written = sum(p.stat().st_size for p in point.iterdir())
    assert written < budget.POINT_BYTES


def test_a_disk_that_fills_mid_run_gives_one_line_and_nothing_half_written(tmp_path, capsys,
                                                                             monkeypatch):
    import errno

    def full(directory, series, name="timeseries.csv"):
        (directory / name).write_text("t,F_d\n0.0,")  # what got out before the disk filled
        raise OSError(errno.ENOSPC, "No space left on device", str(directory / name))

    monkeypatch.setattr(output, "write_timeseries", full)
    assert main(["analytic", SCENE, *SHORT, "--out", str(tmp_path / "R")]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "the disk is full (No space left on device) writing" in err[0]
    assert list(tmp_path.iterdir()) == []


# -- 6. nonsense refused, fuzzed scenes and --set values --------------------------------------------

@pytest.mark.parametrize("assignment, said", [
    ("contact.F_N=1e17", "contact.F_N: 1e+17 N is outside the range"),
    ("contact.F_N=1e-300", "contact.F_N: 1e-300 N is outside the range"),
    ("drive.v_d=1e-300", "drive.v_d: 1e-300 m/s is outside the range"),
    ("vibration.theta_deg=1e20", "vibration.theta_deg: 1e+20 deg is outside the range"),
    ("body.mass=0.5\nbody.E=1", "holds a line break"),
    ("contact.F_N=inf", "contact.F_N"),
])
def test_nonsense_is_refused_naming_its_range(tmp_path, capsys, assignment, said):
    assert main(["analytic", SCENE, "--set", assignment, "--out", str(tmp_path / "R")]) == EXIT_BAD_INPUT
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and said in err[0]
    assert list(tmp_path.iterdir()) == []


def test_an_empty_scene_file_is_refused(tmp_path, capsys):
    empty = tmp_path / "empty.toml"
    empty.write_text("\n  \n")
    assert main(["analytic", str(empty), "--out", str(tmp_path / "R")]) == EXIT_BAD_INPUT
    assert "empty.toml: is empty" in capsys.readouterr().err
    commented = tmp_path / "defaults.toml"
    commented.write_text("# the default scene\n")
    from vibrofric import scene as scene_module

    assert scene_module.load(commented).contact.F_N == scene_module.Contact.F_N


from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from vibrofric import scene as scene_module  # noqa: E402
from vibrofric.scene import SceneError  # noqa: E402

NUMERIC_KEYS = ["body.mass", "body.E", "body.nu", "contact.F_N", "contact.mu", "contact.k_t",
                "drive.k_d", "drive.v_d", "vibration.k_v", "vibration.f", "vibration.theta_deg",
                "vibration.t_on", "time.T", "time.dt", "time.series_dt"]
numbers = st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.integers(-10**30, 10**30),
                    st.sampled_from([0, -0.0, 1e-300, 1e300, 1e17, 5e-324]))
text_values = st.text(st.characters(blacklist_categories=("Cs",)), max_size=30)


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.lists(st.tuples(st.sampled_from(NUMERIC_KEYS), st.one_of(numbers, text_values)), max_size=4))
def test_fuzzed_set_values_load_or_are_refused_by_name(tmp_path, changes):
    """Any --set text: a scene, or a SceneError naming a key; never another exception."""
    assignments = [f"{key}={value!r}" if isinstance(value, str) else f"{key}={value}"
                   for key, value in changes]
    try:
        scene = scene_module.load(SCENE, assignments)
    except SceneError as err:
        assert str(err).strip()
        return
    for key, (low, high, _) in __import__("vibrofric.sense", fromlist=["RANGES"]).RANGES.items():
        assert low <= scene.get(key) <= high


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.text(max_size=200))
def test_fuzzed_scene_files_load_or_are_refused(tmp_path, text):
    path = tmp_path / "fuzzed.toml"
    path.write_text(text, encoding="utf-8")
    try:
        scene_module.load(path)
    except SceneError:
        pass


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(F_N=st.floats(1e-6, 1e9), v_d=st.floats(1e-9, 1e3), theta=st.floats(-360, 360))
def test_accepted_extremes_give_a_result_or_say_why_not(F_N, v_d, theta):
    """Within the ranges, the stepper answers with a finite ratio, or is refused or stopped
    with a message (SceneError: too many steps; NumericalError): never NaN or inf."""
    from vibrofric.analytic.solve import solve
    from vibrofric.core.errors import NumericalError, Refusal

    try:
        scene = scene_module.load(SCENE, ["time.T=0.2", f"contact.F_N={F_N!r}", f"drive.v_d={v_d!r}",
                                          f"vibration.theta_deg={theta!r}"])
        _, summary = solve(scene, "coupled")
    except (SceneError, NumericalError, Refusal):
        return
    ratio = summary["F_dv_over_F_d0"]
    assert ratio is None or __import__("math").isfinite(ratio)


# -- 5. long runs: the estimate counts friction sub-steps; the FE loop returns to Python often ------

def test_the_run_time_estimate_counts_friction_sub_steps(load_scene):
    from vibrofric import budget

    gentle = load_scene("longitudinal", vibration__t_on=0.01, time__T=0.05)
    stiff = gentle.with_values({"vibration.k_v": 1e6})
    assert budget.friction_updates(gentle) == 1 and budget.friction_updates(stiff) > 1000
    assert budget.estimate(stiff, fe=True)["seconds"] > 1000 * budget.estimate(gentle, fe=True)["seconds"]


@pytest.mark.parametrize("change", [{"drive.v_d": 1e-9}, {"contact.F_N": 1e9}])
def test_a_body_that_never_broke_away_is_said_so(load_scene, change):
    """At the ends of the accepted ranges the drive spring may never load the body to
    F_c within time.T (1e-9 m/s, 1e9 N: F_dv/F_d0 ~ 2e-5 and 1.4e-7); the summary says
    it has not settled and has no breakaway time, and the warning says why."""
    from vibrofric.analytic.solve import solve
    from vibrofric.analytic.summary import unsettled_warning

    shipped_scene = load_scene("longitudinal", time__T=0.3, time__method="transient")
    _, summary = solve(shipped_scene.with_values(change), "coupled")
    assert summary["settled"] is False and summary["breakaway_time_s"] is None
    assert "no breakaway" in unsettled_warning(summary)
    _, shipped = solve(shipped_scene, "coupled")
    assert shipped["breakaway_time_s"] > 0.0 and "no breakaway" not in (
        unsettled_warning(shipped) or "")


def test_a_run_estimated_beyond_an_hour_is_announced_before_it_starts(load_scene, tmp_path):
    """vibration.k_v = 1e6 and T = 10 s: ~22 days by the estimate (every contact node's
    friction sub-steps), under the 30 days refused. It started without a word, its
    progress bar's first ETA under an hour (the quick steps before the vibration);
    now one line says the estimate first. The shipped scene says nothing."""
    from vibrofric import budget

    gentle = load_scene("longitudinal")
    stiff = gentle.with_values({"vibration.k_v": 1e6, "vibration.t_on": 0.01, "time.T": 10.0})
    seconds = budget.check([stiff], fe=True, out=tmp_path / "out")
    assert budget.LONG_RUN_S < seconds < budget.LONGEST_RUN_S
    assert "days of computing" in budget.long_run_notice(seconds)
    assert budget.long_run_notice(budget.check([gentle], fe=True, out=tmp_path / "out")) is None


def test_the_fe_loop_returns_to_python_in_growing_chunks():
    """run_in_chunks calls the compiled step over chunks that start at one step and
    double while quick: a signal is handled between two calls."""
    from vibrofric.fem.outputs.recording import run_in_chunks

    calls = []

    def advance(first, last):
        calls.append((first, last))
        return 0

    last, _ = run_in_chunks(1000, None, 0, None, advance)
    assert last == 1000 and calls[0] == (1, 1) and calls[1] == (2, 3) and calls[-1][1] == 1000
    assert all(b[0] == a[1] + 1 for a, b in zip(calls, calls[1:]))  # every step once, in order


def test_the_fe_loop_starts_its_chunks_again_at_the_vibrations_onset():
    """Steps before the vibration are quick, so the chunks grow to thousands of steps;
    from the onset a step can be many times slower (every contact node's friction
    sub-steps: vibration.k_v = 1e6 made a step ~50 ms). A chunk grown before the
    onset then ran for minutes with SIGTERM waiting (measured: 263 s). Here a step
    after the onset sleeps 10 ms: no call may run across the onset, the chunks start
    again from one step there, and no call past it takes much more than
    CHUNK_SECONDS (twice it: the chunk halves only once a call took longer)."""
    from vibrofric.fem.outputs.recording import CHUNK_SECONDS, run_in_chunks

    onset, slow = 3000, 0.01
    calls = []

    def advance(first, last):
        called = time.perf_counter()
        time.sleep(slow * max(0, last - max(first, onset) + 1))
        calls.append((first, last, time.perf_counter() - called))
        return 0

    last, _ = run_in_chunks(onset + 100, None, 0, None, advance, onset=onset)
    assert last == onset + 100
    assert all(b[0] == a[1] + 1 for a, b in zip(calls, calls[1:]))  # every step once, in order
    assert any(a[1] - a[0] > 100 for a in calls)      # the quick steps ran in long chunks
    assert (onset - 1) in [a[1] for a in calls] and (onset, onset) in [a[:2] for a in calls]
    assert max(took for first, _, took in calls if first >= onset) < 2 * CHUNK_SECONDS


@pytest.mark.parametrize("stepper", ["coupled", "longitudinal"])
def test_the_analytic_steppers_run_in_chunks_to_the_same_bits(load_scene, monkeypatch, stepper):
    """The lumped steppers hand back to Python between chunks of steps (core.chunks), so
    that Ctrl-C and SIGTERM end even a slow user law's run at once (measured with a law
    that spends ~0.2 ms a step: SIGINT answered in 0.26 s, SIGTERM in 0.07 s; before,
    after 50 s, at the end of the run). Cut anywhere, a run gives the same bits: here
    chunks of 1 to 700 steps at random against the growing chunks of a normal run."""
    from vibrofric.analytic import coupled, longitudinal
    from vibrofric.core import chunks

    module = coupled if stepper == "coupled" else longitudinal
    run = coupled.run_coupled if stepper == "coupled" else longitudinal.run_longitudinal
    scene = load_scene("coupled", vibration__t_on=0.002, time__T=0.012, time__average_cycles=4)
    whole = run(scene)
    sizes = random.Random(1)
    calls = []

    def ragged(steps, advance):
        first = 1
        while first <= steps:
            last = min(steps, first + sizes.randint(1, 700) - 1)
            calls.append((first, last))
            stop = advance(first, last)
            if stop:
                return stop
            first = last + 1
        return 0

    monkeypatch.setattr(module, "run_in_chunks", ragged)
    cut = run(scene)
    assert len(calls) > 20 and calls[-1][1] == scene.steps
    for name in ("t", "F_d", "F_x", "F_y", "x", "y", "x_b", "y_b"):
        assert np.array_equal(getattr(whole, name), getattr(cut, name)), name
    assert chunks.run_in_chunks(10, lambda first, last: 7 if last >= 7 else 0) == 7
