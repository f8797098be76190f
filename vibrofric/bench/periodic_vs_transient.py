"""What the periodic solver saves: steps and solver time against the transient settled
to a tolerance (Fig 7), the Fig 12 analytic study, and the cost against steps per cycle.

Measurements for ``vibrofric bench`` and benchmarks/periodic_vs_transient.py;
the numbers themselves go in docs/periodic.md, with the machine named.
"""

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
    series, _ = solve(long)
    window = averaging_steps(long)
    means = np.convolve(series.F_d, np.ones(window) / window, mode="valid")
    off = np.flatnonzero(np.abs(means / answer - 1.0) > tolerance)
    return int((off[-1] + 1 if off.size else 0) + window)


def fig7(tolerances=(1e-4, 1e-6)) -> dict:
    """The Fig 7 scene: the periodic run's steps and solver time beside the transient's."""
    scene = scene_module.load(SCENES / "longitudinal.toml")
    periodic = scene.with_values({"time.method": "periodic"})
    solve(periodic)                                          # compiled, then timed
    _, answer = solve(periodic)
    _, transient = solve(scene)
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
        solve(point)
        _, summary = solve(point)
        rows.append((summary["periodic"]["steps_per_cycle"],
                     summary["periodic"]["cycles_integrated"], summary["wall_time_s"]))
    return rows


def measure() -> dict:
    return {"fig7": fig7(), "fig12": fig12(), "steps_per_cycle": steps_per_cycle()}


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
    return lines
