"""The lumped model's two cases whose steady state is not a stable period-1 orbit, run on
the FE model (Fig 7 scene, coarse mesh, vibration from 10 ms): too long for the test
suite, run once for docs/periodic.md ("Checked").

- k_v = 1 along X with k_t x 100: the lumped orbit has a multiplier of -1.14 (period
  doubling). The FE orbit (explicit, 1e-6 s) and the stepped run to 1.5 s: the stepped
  run's drive force averaged over 0.1 s windows approaching the orbit's (period 1) or
  not, and the last two cycles' friction force against each other (a period-2 response
  differs from one cycle to the next).
- k_v = 0.5 along X: the slip never reverses; the lumped model's drive spring is not
  damped (multipliers of modulus 1). The FE orbit (reduced, 1e-5 s) and the stepped run
  to 3 s: the drive force's spread in 0.25 s windows (the free swing of the block on the
  drive spring over the forced ripple) and how fast it shrinks a cycle.

    PYTHONPATH=. python benchmarks/fe_steady_state_cases.py     # about 2 min
"""

import time

import numpy as np

from vibrofric import scene as scene_module
from vibrofric.analytic.summary import summarize
from vibrofric.fem import run_fe

BASE = {"vibration.t_on": 0.01, "fem.output_every": 0}


def windows(series, start: float, width: float):
    """(window start, mean and standard deviation of F_d) over windows of ``width`` s."""
    t, force = series.t, series.F_d
    rows = []
    for a in np.arange(start, t[-1] - width + 1e-12, width):
        inside = (t > a) & (t <= a + width)
        rows.append((a, force[inside].mean(), force[inside].std()))
    return rows


def last_cycles(series, f: float, count: int = 2):
    """The friction force F_x over each of the last ``count`` base cycles (the series'
    full-resolution end)."""
    t = series.t
    n = int(round(1.0 / (f * (t[-1] - t[-2]))))
    return [series.F_x[t.size - (k + 1) * n:t.size - k * n] for k in reversed(range(count))]


def case(changes: dict, T: float, width: float):
    scene = scene_module.load("scenes/longitudinal.toml").with_values({**BASE, **changes})
    begin = time.perf_counter()
    shot = run_fe(scene.with_values({"time.method": "periodic", "time.T": 0.3}))
    shot_s = time.perf_counter() - begin
    block = shot.info["periodic"]
    F_d0 = scene.friction.steady_sliding_force(scene.contact.F_N, scene.drive.v_d)
    stepped_scene = scene.with_values({"time.T": T})
    begin = time.perf_counter()
    stepped = run_fe(stepped_scene)
    stepped_s = time.perf_counter() - begin
    orbit_ratio = float(np.mean(shot.orbit.cycle[:, 1])) / F_d0
    summary = summarize(stepped.series, stepped_scene, 0.0)
    print(f"\n{changes}: shot {shot_s:.1f} s, stepped to {T} s {stepped_s:.1f} s")
    print(f"  orbit: method {block['method']}, converged {block['converged']}, cycles "
          f"{block['cycles_integrated']}, largest multiplier {block['floquet_max_modulus']}, "
          f"note {block.get('floquet_note', '')!r}, reason {block['reason']!r}")
    print(f"  orbit F_dv/F_d0 {orbit_ratio:.8f}; stepped {summary['F_dv_over_F_d0']:.8f} "
          f"(drift {summary['window_drift']:.2e})")
    rows = windows(stepped.series, scene.vibration.t_on, width)
    for a, mean, spread in rows:
        print(f"  {a:.2f}-{a + width:.2f} s: F_d/F_d0 mean {mean / F_d0:.8f}, spread {spread:.3e} N")
    one, two = last_cycles(stepped.series, scene.vibration.f)
    print(f"  last two cycles' friction force: largest difference {np.abs(one - two).max():.3e} N")
    return rows


def main():
    case({"fem.integrator": "explicit", "time.dt": 1e-6, "contact.k_t": 8e9,
          "vibration.k_v": 1.0}, 1.5, 0.1)
    rows = case({"fem.integrator": "reduced", "time.dt": 1e-5, "vibration.k_v": 0.5}, 3.0, 0.25)
    f = 4000.0
    first, last = rows[1], rows[-1]
    cycles = (last[0] - first[0]) * f
    print(f"  spread shrinks by {(last[2] / first[2]) ** (1 / cycles):.6f} a cycle "
          f"over {first[0]:.2f}-{last[0]:.2f} s")


if __name__ == "__main__":
    main()
