"""The FE model's steady state by shooting (fem/integrators/periodic.py, fem/integrators/cycle_map.py)."""

import json
import re

import numpy as np
import pytest

from vibrofric import scene as scene_module
from vibrofric.analytic.summary import summarize
from vibrofric.cli import main
from vibrofric.core import shooting
from vibrofric.fem import run_fe
from vibrofric.fem.integrators import periodic

LONGITUDINAL = "scenes/longitudinal.toml"
# The Fig 7 scene with the vibration on at 10 ms: a stepped run to T = 0.4 s has had
# 1560 cycles to settle, and the slowest mode (the block on the drive spring, largest
# multiplier 0.984 a cycle) has decayed by 0.984^1560 ~ 1e-11 by then.
SHORT = {"vibration.t_on": 0.01, "time.T": 0.4, "fem.output_every": 0}
# Where the FE integrators run (their own tests: test_integrators.py): reduced and
# implicit at 1e-5 s (25 steps a cycle), explicit at its own 1e-6 s.
STEPS = {"reduced": 1e-5, "implicit": 1e-5, "explicit": 1e-6}


# A law other than Dahl's: LuGre with a Stribeck peak and contact damping (as in
# benchmarks/same_results.py), and the user's Maxwell-slip law of examples/laws.
LUGRE = {"contact.law": "lugre", "contact.F_s": 6.6, "contact.v_s": 0.002, "contact.h_t": 50.0}
MAXWELL = {"contact.law": "examples/laws/maxwell_slip.py"}


def fig7(path=LONGITUDINAL, **changes):
    scene = scene_module.load(path)
    return scene.with_values({**SHORT, **{k.replace("__", "."): v for k, v in changes.items()}})


def ratio(fe, scene) -> float:
    return summarize(fe.series, scene, 0.0)["F_dv_over_F_d0"]


CASES = [("reduced", {}), ("implicit", {}), ("explicit", {}), ("reduced", LUGRE),
         ("reduced", MAXWELL)]


@pytest.mark.slow
@pytest.mark.parametrize("name, law", CASES,
                         ids=["reduced", "implicit", "explicit", "reduced-lugre",
                              "reduced-maxwell-slip"])
def test_the_orbit_equals_the_settled_transient_of_the_same_integrator(name, law):
    """Periodic F_dv equals that of the stepped run of the same integrator at the same
    step within 1e-4 relative (the issue's FE target; measured 1e-9 to 1e-8), the
    orbit is stable with its largest multiplier the drive mode's (0.984 on Fig 7),
    and the stepped run had settled (drift below 1e-6)."""
    stepped_scene = fig7(**{"fem.integrator": name, "time.dt": STEPS[name], **law})
    stepped = run_fe(stepped_scene)
    assert summarize(stepped.series, stepped_scene, 0.0)["window_drift"] < 1e-6
    scene = stepped_scene.with_values({"time.method": "periodic"})
    shot = run_fe(scene)
    block = shot.info["periodic"]
    assert block["method"] == "periodic" and block["converged"]
    assert 0.9 < block["floquet_max_modulus"] < shooting.STABLE
    assert ratio(shot, scene) == pytest.approx(ratio(stepped, stepped_scene), rel=1e-4)
    # far fewer cycles than the stepped run's after the vibration starts (1560)
    assert block["cycles_integrated"] < 0.25 * (scene.time.T - scene.vibration.t_on) * scene.vibration.f


@pytest.mark.slow
def test_an_orbit_that_is_not_stable_is_stepped_and_says_why(monkeypatch):
    """Where Arnoldi's multipliers say the orbit is not stable (the rule checked by
    tightening the threshold below the orbit's largest multiplier, 0.984) and a
    perturbation does not decay (decay_rate made to say 1.02), the scene is stepped
    through T and the periodic block says why; never the orbit returned silently.
    Where the perturbation does decay (its real rate), Arnoldi's value is not
    confirmed: the orbit answers, its block says so and gives the decay rate."""
    real = shooting.instability
    monkeypatch.setattr(periodic, "instability", lambda m: real(m, 0.5))
    scene = fig7(fem__integrator="reduced", time__dt=1e-5, time__T=0.05, time__method="auto")
    confirmed = run_fe(scene)
    block = confirmed.info["periodic"]
    assert block["method"] == "periodic" and "not confirmed" in block["floquet_note"]
    assert 0.9 < block["floquet_max_modulus"] < 1.0
    monkeypatch.setattr(periodic, "decay_rate", lambda phi, x: 1.02)
    fe = run_fe(scene)
    block = fe.info["periodic"]
    assert block["method"] == "transient" and block["converged"]
    assert "multiplier" in block["reason"] and "grows" in block["reason"]
    assert fe.info["steps"] == scene.steps
    assert fe.series.t[-1] == pytest.approx(scene.time.T)


@pytest.mark.slow
def test_vibrofric_run_reports_the_block_and_writes_one_steady_cycle(tmp_path, capsys):
    """vibrofric run with time.method periodic: the JSON's fe.periodic block, a settled
    answer without a breakaway time, the time series ending at time.T, and a ParaView
    series of one cycle (FRAMES_PER_CYCLE + 1 frames)."""
    out = tmp_path / "run"
    code = main(["run", LONGITUDINAL, "--json", "--out", str(out),
                 "--set", 'fem.integrator="reduced"', "--set", "time.dt=1e-5",
                 "--set", 'time.method="periodic"', "--set", "fem.output_every=100",
                 "--set", "time.T=0.3"])
    assert code in (0, None)
    document = json.loads(capsys.readouterr().out)
    fe = document["fe"]
    block = fe["periodic"]
    for key in ("converged", "newton_iterations", "cycles_integrated", "residual",
                "floquet_max_modulus", "method"):
        assert key in block
    assert block["method"] == "periodic" and fe["settled"] and fe["breakaway_time_s"] is None
    frames = sorted((out / "paraview").glob("block*.vtu"))
    assert len(frames) == periodic.FRAMES_PER_CYCLE + 1
    series = np.genfromtxt(out / "timeseries.csv", delimiter=",", names=True)
    assert series["t"][-1] == pytest.approx(0.3)
    # The frames are the cycle the series ends with: the last at time.T itself (the
    # pvd's times as written, repr of floats), the first one base period before
    times = [float(t) for t in re.findall(r'timestep="([^"]+)"',
                                          (out / "paraview" / "block.pvd").read_text())]
    assert times[-1] == 0.3
    assert times[-1] - times[0] == pytest.approx(1.0 / 4000.0, rel=1e-9)
    assert np.all(np.diff(times) > 0)


# --- sweeps by continuation (vibrofric sweep) -----------------------------------------------

def _sweep(out, *more):
    import subprocess
    import sys

    from conftest import ROOT, child_environment
    args = [sys.executable, "-m", "vibrofric.cli", "sweep", LONGITUDINAL, "--json", "--out", str(out),
            *more]
    return subprocess.run(args, env=child_environment(), cwd=ROOT, capture_output=True,
                          text=True, timeout=600)


def _points(out) -> dict:
    return {p.parent.name: json.loads(p.read_text())
            for p in (out / "points").glob("*/summary.json")}


@pytest.mark.slow
def test_an_fe_sweep_continues_from_the_neighbours_orbit_and_says_which_method_ran(tmp_path):
    """An FE sweep with time.method periodic (reduced, 4 points on one worker): every
    point after the first starts from its neighbour's orbit, each says which method
    answered, and each equals its own shot from steady sliding within 1e-6 (the Newton
    tolerance's reach; measured ~1e-8). A rerun reuses every point (resumable)."""
    out = tmp_path / "sweep"
    settings = ["--set", 'fem.integrator="reduced"', "--set", "time.dt=1e-5",
                "--set", 'time.method="periodic"', "--set", "fem.output_every=0",
                "--set", "time.T=0.3", "--grid", "vibration.k_v=4,5,6,7", "--fe",
                "--workers", "1"]
    done = _sweep(out, *settings)
    assert done.returncode == 0, done.stderr
    points = _points(out)
    blocks = {name: s["result"]["fe"]["periodic"] for name, s in points.items()}
    assert all(b["method"] == "periodic" for b in blocks.values())
    by_kv = sorted(blocks, key=lambda n: float(n.split("=")[1]))
    starts = [blocks[name]["start"] for name in by_kv]
    assert starts == ["steady sliding", "neighbour", "neighbour", "neighbour"]
    assert all((out / "points" / name / "orbit.npy").is_file() for name in points)
    # the same point shot on its own from steady sliding
    alone = run_fe(scene_module.load(LONGITUDINAL).with_values(
        {"fem.integrator": "reduced", "time.dt": 1e-5, "time.method": "periodic",
         "fem.output_every": 0, "time.T": 0.3, "vibration.k_v": 7}))
    assert points[by_kv[-1]]["result"]["fe"]["F_dv"] == pytest.approx(
        float(np.mean(alone.orbit.cycle[:, 1])), rel=1e-6)
    again = _sweep(out, *settings)
    assert again.returncode == 0 and "4 reused" in again.stderr + again.stdout


@pytest.mark.slow
def test_a_shooting_reports_each_cycle_it_runs_to_the_progress_callback():
    """progress(cycles, None) after every base cycle, counted over the Newton-Picard
    cycles and the stability check's alike, ending at the summary's cycles_integrated."""
    reports = []
    scene = fig7(fem__integrator="reduced", time__dt=STEPS["reduced"], time__method="periodic")
    fe = run_fe(scene, progress=lambda done, total: reports.append((done, total)))
    counts = [done for done, total in reports]
    assert all(total is None for _, total in reports)
    assert counts == list(range(1, fe.info["periodic"]["cycles_integrated"] + 1))


def test_a_shooting_that_fails_from_the_lumped_answer_tries_again_from_steady_sliding(
        monkeypatch):
    """Where Newton-Picard does not converge from steady sliding set back by the lumped
    model's F_dv (as vibrofric run starts it; examples/laws/maxwell_slip.py on Fig 7 did
    not, before the iterates between 10 and ASTRAY times the best residual were taken),
    it tries again from steady sliding under F_d0, and the run is answered by that orbit,
    not stepped. The first try is made to fail here by allowing it 5 cycles."""
    from vibrofric.analytic.solve import solve

    scene = fig7(fem__integrator="reduced", time__dt=STEPS["reduced"], time__method="periodic",
                 time__error_estimate=False)     # the answer's shootings alone
    lumped = solve(scene)[1]["F_dv"]
    real = periodic.newton_picard
    starts = []

    def first_fails(cycle, x, *args):
        starts.append(x.copy())
        if len(starts) == 1:
            args = args[:-1] + (5,)          # max_cycles
        return real(cycle, x, *args)

    monkeypatch.setattr(periodic, "newton_picard", first_fails)
    fe = run_fe(scene, drive_force=lumped)
    block = fe.info["periodic"]
    assert len(starts) == 2 and not np.array_equal(starts[0], starts[1])
    assert block["method"] == "periodic" and block["converged"], block
    assert block["cycles_integrated"] > 5      # the first try's cycles count


def test_the_shooting_may_take_a_third_of_the_stepped_run_s_cycles_and_at_least_400():
    """shooting_cycles: STEPPED_SHARE of the cycles the stepped run integrates with the
    base on ((T - t_on) f), at least MIN_CYCLES."""
    ball = scene_module.load("scenes/ball.toml")       # T = 1 s, t_on = 0.14 s, 4 kHz
    assert periodic.shooting_cycles(ball) == 1147       # ceil(3440 / 3)
    short = ball.with_values({"time.T": 0.2})           # 240 cycles on: at least 400
    assert periodic.shooting_cycles(short) == periodic.MIN_CYCLES
    assert periodic.shooting_cycles(fig7()) == 520      # 0.39 s at 4 kHz: 1560 / 3


@pytest.mark.slow
@pytest.mark.usefixtures("own_model_cache")     # conftest.py: the ball kept apart
def test_the_coarse_ball_s_orbit_at_a_short_step_is_found_past_400_cycles():
    """The coarse ball, reduced at reach 3, at 1e-6 s: its rocking on the pole (29 kHz,
    lightly damped at that step) makes Newton-Picard converge slowly; with 400 cycles it
    stopped at a residual of 4e-5 and the run was stepped through T; now it
    finds the orbit (518 cycles, measured). Its answer lies within 1e-3 of the explicit
    model's steady cycle, 0.2747 (docs/validation.md, "A ball and a pin against the
    lumped model"): the step's own error at 1e-6 s, where the scheme carries the rocking
    mode 0.3% low, was 4e-4 (0.2743; docs/performance.md, "the balls' answers against
    the step")."""
    from vibrofric.fem.integrators import registry
    from vibrofric.fem.model import fe_model
    from vibrofric.fem.integrators.cycle_map import FECycleMap

    scene = scene_module.load("scenes/ball.toml").with_values(
        {"fem.interface_reach": 3.0, "time.dt": 1e-6, "fem.output_every": 0})
    model = fe_model.build_model(scene, None)
    shot_scene, steps = periodic.periodic_scene(scene)
    run = registry.select(shot_scene)(shot_scene, model)
    orbit = periodic.find_orbit(FECycleMap(run, run.model, steps), stability=False)
    assert orbit.converged, orbit.reason
    F_d0 = scene.friction.steady_sliding_force(scene.contact.F_N, scene.drive.v_d)
    assert abs(float(np.mean(orbit.cycle[:, 1])) / F_d0 - 0.2747) < 1e-3
