"""Steps and solver time: the periodic orbit (time.method = "periodic") against the
transient stepped until settled, on the analytic Fig 7 scene and the Fig 12 study.

    PYTHONPATH=. python benchmarks/periodic_vs_transient.py
"""

import time

import numpy as np

from vibrofric import scene as scene_module
from vibrofric.analytic.periodic import find_orbit, load_cycle
from vibrofric.analytic.run import run
from vibrofric.core.series import averaging_steps


def settled_steps(scene, answer: float, tolerance: float) -> int:
    """The fewest steps after which the transient's averaging window ends within
    ``tolerance`` of ``answer`` and stays there (stepped to T = 1.5 s with every row kept)."""
    long = scene.with_values({"time.T": 1.5, "time.method": "transient"})
    series, _ = run(long.with_values({"time.series_dt": long.time.dt}))
    window = averaging_steps(long)
    means = np.convolve(series.F_d, np.ones(window) / window, mode="valid")
    off = np.abs(means / answer - 1.0) > tolerance
    last_off = np.flatnonzero(off)[-1] if off.any() else -1
    return int(last_off + 1 + window)


def fig7():
    scene = scene_module.load("scenes/longitudinal.toml").with_values({"time.method": "periodic"})
    _, summary = run(scene)                       # compiles / loads
    start = time.perf_counter()
    _, summary = run(scene)
    elapsed = time.perf_counter() - start
    answer = summary["F_dv"]
    for tolerance in (1e-4, 1e-6):
        steps = settled_steps(scene, answer, tolerance)
        print(f"Fig 7: transient settled to {tolerance:g}: {steps} steps; periodic "
              f"{summary['steps']} steps ({steps / summary['steps']:.0f}x fewer), "
              f"{summary['periodic']['newton_iterations']} Newton iterations, "
              f"solver {summary['wall_time_s'] * 1e3:.1f} ms (run() {elapsed * 1e3:.1f} ms)")
    transient = scene.with_values({"time.method": "transient"})
    _, t = run(transient)
    print(f"Fig 7 transient to T = 1 s: {t['steps']} steps, {t['wall_time_s'] * 1e3:.1f} ms")


def fig12():
    base = scene_module.load("scenes/coupled.toml").with_values({"time.method": "periodic"})
    points = [(k_v, theta) for k_v in (2, 3, 4, 6, 20) for theta in np.linspace(0, 360, 25)]
    load_cycle(base)
    solver = wall = 0.0
    steps = 0
    methods = {}
    start_state = None
    for continuation in (False, True):
        solver = steps = 0
        methods = {}
        start = time.perf_counter()
        for k_v, theta in points:
            scene = base.with_values({"vibration.k_v": k_v, "vibration.theta_deg": float(theta)})
            orbit = find_orbit(scene, start=start_state if continuation else None)
            solver += orbit.solver_time_s
            steps += orbit.cycles_integrated * orbit.steps
            ok = orbit.converged and orbit.stable
            methods[ok] = methods.get(ok, 0) + 1
            start_state = orbit.z if ok else None
        wall = time.perf_counter() - start
        print(f"Fig 12 analytic, 125 points, {'continuation' if continuation else 'from sliding'}: "
              f"solver {solver:.3f} s, {steps} steps, periodic at {methods.get(True, 0)} points, "
              f"refused at {methods.get(False, 0)} (wall {wall:.3f} s, one core)")


if __name__ == "__main__":
    fig7()
    fig12()
