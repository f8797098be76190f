"""What the periodic solver saves: steps and solver time against the transient settled
to a tolerance (Fig 7), the Fig 12 analytic study, and the cost against steps per cycle;
for the FE integrators (fe_fig7) the same on Fig 7, and the cost against the contact's
stiffness (steps a cycle) and the mesh.

Measurements for ``vibrofric bench`` and benchmarks/periodic_vs_transient.py;
the numbers themselves go in docs/periodic.md, with the machine named.
"""

import csv
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from .. import scene as scene_module
from ..analytic.continuation import run_in_sequence
from ..analytic.periodic import find_orbit, load_cycle
from ..analytic.solve import solve
from ..core.series import averaging_steps

SCENES = Path(__file__).resolve().parent.parent / "scenes"  # package data
FIG12 = [{"vibration.k_v": float(k_v), "vibration.theta_deg": float(theta)}
         for k_v in (2, 3, 4, 6, 20) for theta in np.linspace(0.0, 360.0, 25)]


def settled_steps(scene, answer: float, tolerance: float, T: float = 1.5) -> int:
    """Steps from t = 0 after which the transient's averaging window (eq 40) ends within
    ``tolerance`` of ``answer`` and stays there, stepped to ``T`` with every row kept."""
    long = scene.with_values({"time.T": T, "time.method": "transient",
                              "time.series_dt": scene.time.dt})
    series, _ = solve(long, estimate=False)
    window = averaging_steps(long)
    means = np.convolve(series.F_d, np.ones(window) / window, mode="valid")
    off = np.flatnonzero(np.abs(means / answer - 1.0) > tolerance)
    return int((off[-1] + 1 if off.size else 0) + window)


def fig7(tolerances=(1e-4, 1e-6)) -> dict:
    """The Fig 7 scene: the periodic run's steps and solver time beside the transient's."""
    scene = scene_module.load(SCENES / "longitudinal.toml")
    periodic = scene.with_values({"time.method": "periodic"})
    solve(periodic, estimate=False)                          # compiled, then timed
    _, answer = solve(periodic, estimate=False)
    _, transient = solve(scene, estimate=False)
    t_on_steps = int(round(scene.vibration.t_on / scene.time.dt))
    settled = {tol: settled_steps(scene, answer["F_dv"], tol) for tol in tolerances}
    return {"periodic_steps": answer["steps"], "periodic_solver_s": answer["wall_time_s"],
            "newton_iterations": answer["periodic"]["newton_iterations"],
            "cycles": answer["periodic"]["cycles_integrated"],
            "transient_steps": transient["steps"], "transient_solver_s": transient["wall_time_s"],
            "settled_steps": settled, "t_on_steps": t_on_steps}


def fig12() -> dict:
    """The 125-point Fig 12 analytic study on one core, from steady sliding at each
    point and by continuation: solver time (the shootings alone) and steps."""
    scene = scene_module.load(SCENES / "coupled.toml").with_values({"time.method": "periodic"})
    load_cycle(scene)
    result = {}
    solver = steps = periodic_points = 0
    for values in FIG12:
        orbit = find_orbit(scene.with_values(values))
        solver += orbit.solver_time_s
        steps += orbit.cycles_integrated * orbit.steps
        periodic_points += orbit.converged and orbit.stable
    result["from_sliding"] = (solver, steps, periodic_points)
    start = time.perf_counter()
    summaries = run_in_sequence(scene, FIG12)
    wall = time.perf_counter() - start
    shot = [s for s in summaries if s["periodic"]["method"] == "periodic"]
    result["continuation"] = (sum(s["wall_time_s"] for s in shot), sum(s["steps"] for s in shot),
                              len(shot), wall)
    return result


def steps_per_cycle(dts=(1e-6, 5e-7, 2.5e-7)) -> list:
    """Fig 7's periodic solver time at finer steps (more steps a cycle: what a stiffer
    contact needs): (steps a cycle, cycles integrated, solver s)."""
    scene = scene_module.load(SCENES / "longitudinal.toml").with_values({"time.method": "periodic"})
    rows = []
    for dt in dts:
        point = scene.with_values({"time.dt": dt})
        solve(point, estimate=False)
        _, summary = solve(point, estimate=False)
        rows.append((summary["periodic"]["steps_per_cycle"],
                     summary["periodic"]["cycles_integrated"], summary["wall_time_s"]))
    return rows


# The FE cases: (label, integrator, time.dt, mesh, more scene values). k_t x 100 needs a
# step 10x finer for the implicit integrators' trusted slip per step (contact_solve).
FE_CASES = [("reduced", "reduced", 1e-5, "coarse", {}),
            ("implicit", "implicit", 1e-5, "coarse", {}),
            ("explicit", "explicit", 1e-6, "coarse", {}),
            ("reduced, k_t x 100", "reduced", 1e-6, "coarse", {"contact.k_t": 8e9}),
            ("reduced, medium mesh", "reduced", 1e-5, "medium", {})]


def fe_settled_steps(series, scene, answer: float, tolerance: float) -> int:
    """Steps from t = 0 after which an FE run's averaging window ends within ``tolerance``
    of ``answer`` and stays there (its series kept at every step)."""
    window = averaging_steps(scene)
    means = np.convolve(series.F_d, np.ones(window) / window, mode="valid")
    off = np.flatnonzero(np.abs(means / answer - 1.0) > tolerance)
    return int((off[-1] + 1 if off.size else 0) + window)


def fe_fig7(cases=FE_CASES, T: float = 0.45, tolerance: float = 1e-4) -> list:
    """Fig 7 with each FE integrator: the periodic run's solver time and cycles beside the
    transient's: the steps after the vibration starts it needs to come within
    ``tolerance`` of the orbit's F_dv (stepped to T, 0.31 s after t_on), at its cost
    per vibrated step (the loop time of a run to T less that of a run to T - 0.1 s,
    over the steps between: a step before t_on is cheaper)."""
    from ..fem import run_fe

    scene = scene_module.load(SCENES / "longitudinal.toml")
    rows = []
    for label, integrator, dt, mesh, more in cases:
        base = scene.with_values({"fem.integrator": integrator, "time.dt": dt, "fem.mesh": mesh,
                                  "fem.output_every": 0, "time.T": T, "time.method": "transient",
                                  **more})
        periodic = base.with_values({"time.method": "periodic"})
        # started, as `vibrofric run` starts it, from the lumped model's F_dv (its own
        # orbit: a few ms, not counted)
        _, lumped = solve(periodic)
        run_fe(periodic, drive_force=lumped["F_dv"])           # compiled and cached, then timed
        shot = run_fe(periodic, drive_force=lumped["F_dv"])
        stepped = run_fe(base.with_values({"time.series_dt": dt}))
        shorter = run_fe(base.with_values({"time.T": T - 0.1}))
        per_step = ((stepped.info["loop_time_s"] - shorter.info["loop_time_s"])
                    / (stepped.info["steps"] - shorter.info["steps"]))
        answer = float(np.mean(shot.orbit.cycle[:, 1]))
        steps = fe_settled_steps(stepped.series, base, answer, tolerance)
        after_t_on = steps - int(round(base.vibration.t_on / dt))
        rows.append({"case": label, "dt": dt, "steps_per_cycle": shot.orbit.steps,
                     "unknowns": int(shot.orbit.z.size), "cycles": shot.orbit.cycles_integrated,
                     "periodic_s": shot.orbit.solver_time_s, "setup_s": shot.info["setup_time_s"],
                     "transient_loop_s": stepped.info["loop_time_s"],
                     "transient_steps": stepped.info["steps"], "step_us": per_step * 1e6,
                     "settled_after_t_on": after_t_on, "settled_loop_s": per_step * after_t_on,
                     "rel_difference": abs(answer / float(np.mean(
                         stepped.series.F_d[-averaging_steps(base):])) - 1.0),
                     "floquet": shot.info["periodic"]["floquet_max_modulus"]})
    return rows


# The Fig 12 FE study as a user types it (docs/periodic.md), reduced on the coarse mesh;
# stepped, each point stops once settled to 2e-3 (docs/performance.md's study).
FE_STUDY = ["sweep", str(SCENES / "coupled.toml"), "--fe", "--set", "fem.output_every=0",
            "--set", "fem.integrator=reduced", "--set", "time.dt=1e-5"]
FE_GRID = ["--grid", "vibration.k_v=2,3,4,6,20", "--grid", "vibration.theta_deg=0:360:25"]
ONE_POINT = ["--grid", "vibration.k_v=2", "--grid", "vibration.theta_deg=45"]
STEPPED = ["--set", "time.method=transient", "--set", "time.steady_tolerance=2e-3"]


def fe_study(workers: int = 2) -> dict:
    """The 125-point Fig 12 FE study by its orbits (the default) and stepped, each the
    ``vibrofric`` command of this environment run on ``workers`` processes into a
    directory of its own (a command, as the package's studies run above the bench),
    after a one-point run of the same that loads (or compiles) its loops: {method:
    (wall s, CPU s of the command and its workers, points answered by their orbit)},
    or {} where there is no such command."""
    command = Path(sys.executable).parent / "vibrofric"
    if not command.is_file():
        return {}
    result = {}
    for method, more in (("periodic", []), ("transient", STEPPED)):
        def run(grid, out):
            subprocess.run([str(command), *FE_STUDY, *grid, *more, "--out", out,
                            "--workers", str(workers)], check=True, capture_output=True)

        with tempfile.TemporaryDirectory() as warm, tempfile.TemporaryDirectory() as out:
            run(ONE_POINT, warm)
            before = resource.getrusage(resource.RUSAGE_CHILDREN)
            start = time.perf_counter()
            run(FE_GRID, out)
            wall = time.perf_counter() - start
            after = resource.getrusage(resource.RUSAGE_CHILDREN)
            with open(Path(out) / "results.csv", newline="") as f:
                answered = sum(row.get("fe.periodic.method") == "periodic"
                               for row in csv.DictReader(f))
        cpu = after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime
        result[method] = (wall, cpu, answered)
    return result


def measure(fe_cases=tuple(case[0] for case in FE_CASES), study: bool = False) -> dict:
    """Every row; the FE ones for the FE_CASES labelled ``fe_cases``; with ``study``, the
    Fig 12 FE study (fe_study)."""
    cases = [case for case in FE_CASES if case[0] in fe_cases]
    return {"fig7": fig7(), "fig12": fig12(), "steps_per_cycle": steps_per_cycle(),
            "fe": fe_fig7(cases) if cases else [], "fe_study": fe_study() if study else {}}


def markdown(result: dict) -> list:
    f7, f12 = result["fig7"], result["fig12"]
    lines = ["Periodic steady state (time.method = \"periodic\", docs/periodic.md) against the "
             "transient, analytic, one core:", "",
             "| case | transient | periodic |", "|---|---|---|"]
    for tol, steps in f7["settled_steps"].items():
        after = steps - f7["t_on_steps"]
        lines.append(f"| Fig 7, steps to F_dv within {tol:g} | {steps} from t = 0 ({after} after "
                     f"t_on) | {f7['periodic_steps']} ({f7['cycles']} cycles, "
                     f"{f7['newton_iterations']} Newton iterations): {steps / f7['periodic_steps']:.0f}x "
                     f"fewer ({after / f7['periodic_steps']:.0f}x after t_on) |")
    lines.append(f"| Fig 7, solver time | {f7['transient_solver_s'] * 1e3:.1f} ms "
                 f"({f7['transient_steps']} steps) | {f7['periodic_solver_s'] * 1e3:.1f} ms |")
    s, n, ok = f12["from_sliding"]
    cs, cn, cok, _ = f12["continuation"]
    lines.append(f"| Fig 12 study, 125 points | | {s:.3f} s solver, {n} steps from sliding "
                 f"({ok} answered periodic); by continuation {cs:.3f} s, {cn} steps over the "
                 f"{cok} answered periodic (the others are stepped through T) |")
    for steps, cycles, solver in result["steps_per_cycle"]:
        lines.append(f"| Fig 7 at {steps} steps a cycle | | {cycles} cycles, "
                     f"{solver * 1e3:.1f} ms |")
    if result.get("fe"):
        lines += ["", "FE, Fig 7 (coarse mesh unless said), one core, set-up apart (the same "
                  "for both):", "",
                  "| case | dt, steps a cycle | unknowns | transient: steps after t_on to F_dv "
                  "within 1e-4, at its us a vibrated step | periodic: cycles (steps), solver | "
                  "periodic vs transient to T = 0.45 s | largest multiplier |",
                  "|---|---|---|---|---|---|---|"]
        for r in result["fe"]:
            lines.append(f"| {r['case']} | {r['dt']:g} s, {r['steps_per_cycle']} | {r['unknowns']} | "
                         f"{r['settled_after_t_on']} ({r['step_us']:.0f} us: "
                         f"{r['settled_loop_s']:.2f} s) | {r['cycles']} "
                         f"({r['cycles'] * r['steps_per_cycle']}), {r['periodic_s']:.2f} s | "
                         f"{r['rel_difference']:.1e} | {r['floquet']:.4f} |")
    if result.get("fe_study"):
        lines += [""] + study_markdown(result["fe_study"])
    return lines


def study_markdown(study: dict) -> list:
    """The table of fe_study's result."""
    (pw, pc, pn), (tw, tc, tn) = study["periodic"], study["transient"]
    return ["The Fig 12 FE study (125 points, reduced, coarse mesh, `vibrofric sweep` on "
            "both cores; stepped: each point stopped once settled to 2e-3):", "",
            "| | stepped | by its orbits (the default) |", "|---|---|---|",
            f"| wall, CPU | {tw:.1f} s, {tc:.1f} s | {pw:.1f} s, {pc:.1f} s |",
            f"| points answered by their orbit | {tn} | {pn} |"]
