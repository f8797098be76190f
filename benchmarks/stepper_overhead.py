"""The transient lumped stepper against a plain numba loop of the same model.

``run_coupled`` (analytic/coupled.py) runs the coupled loop in chunks of steps
that hand back to Python (core/chunks.py: Ctrl-C), with the loop compiled for the
scene's law and its state carried between chunks, then makes the TimeSeries. The
plain loop here is the same model (the same equations, Dahl's update linked in,
the same rows kept, the same divergence check) in one compiled call from rest,
as the stepper was before its chunking: the ratio of the two is what the
stepper's Python around the loop costs.

Each repeat times both in turn in one process (the plain loop, then the stepper,
both compiled or loaded before), so that a shared machine's load falls on both
alike; the medians and the median of the per-repeat ratios are printed. The
answers are compared too (the same F_d series, to the bit).

    PYTHONPATH=. python benchmarks/stepper_overhead.py [--repeats 15] [--scene longitudinal]
"""

import argparse
import math
import statistics
import time
from pathlib import Path

import numpy as np
from numba import njit

from vibrofric import scene as scene_module
from vibrofric.analytic.coupled import record_row, run_coupled
from vibrofric.core.base_motion import base_displacement, vibration_axis
from vibrofric.core.law_limits import divergence_force
from vibrofric.core.series import COLUMNS, RecordPlan, full_resolution_steps
from vibrofric.friction_law import dahl
from vibrofric.friction_law.contract import FASTMATH

SCENES = Path(__file__).resolve().parent.parent / "scenes"
dahl_update = njit(error_model="numpy", fastmath=FASTMATH)(dahl.update)


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def plain_loop(mass, k_d, v_d, u0, omega, t_on, cos_theta, sin_theta, eta_y, F_N, state,
               params, dt, steps, stride, full_from, f_max, out):
    """coupled.coupled_loop's steps 1..steps from rest in one call (a driven body)."""
    x = y = vx = vy = f_x = f_y = xb = yb = 0.0
    sin_phase, cos_phase = 0.0, 1.0
    cos_step, sin_step = math.cos(omega * dt), math.sin(omega * dt)
    j = 0
    for i in range(1, steps + 1):
        t = i * dt
        f_d = k_d * (v_d * (t - dt) - x)
        vx += dt * (f_d - f_x) / mass
        vy += dt * (-f_y) / mass
        x_new, y_new = x + dt * vx, y + dt * vy
        u, sin_phase, cos_phase = base_displacement(i, dt, omega, t_on, u0, sin_phase, cos_phase,
                                                    cos_step, sin_step)
        xb_new, yb_new = u * cos_theta, u * sin_theta
        f_x, f_y = dahl_update((x_new - x) - (xb_new - xb), y_new - y, 0.0,
                               eta_y * (yb_new - yb), F_N, 1.0, state, params, dt)
        x, y, xb, yb = x_new, y_new, xb_new, yb_new
        f_d = k_d * (v_d * t - x)
        if not (math.sqrt(f_x * f_x + f_y * f_y) <= f_max and math.isfinite(f_d)):
            return i
        if i >= full_from or i % stride == 0:
            record_row(out, j, t, f_d, f_x, f_y, x, y, xb, yb)
            j += 1
    return 0


def run_plain(scene) -> np.ndarray:
    """The plain loop over the scene's steps; the kept rows."""
    plan = RecordPlan.for_scene(scene, full_resolution_steps(scene))
    out = np.empty((plan.rows, len(COLUMNS)))
    cos_theta, sin_theta = vibration_axis(scene.vibration.theta_deg)
    law = scene.friction
    failed = plain_loop(scene.body.mass, scene.drive.k_d, scene.drive.v_d, scene.u0, scene.omega,
                        scene.vibration.t_on, cos_theta, sin_theta, scene.contact.eta_y,
                        scene.contact.F_N, law.law.initial_state(1)[0], law.params,
                        scene.time.dt, plan.steps, plan.stride, plan.full_from,
                        divergence_force(scene), out)
    assert failed == 0
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", default="longitudinal")
    parser.add_argument("--repeats", type=int, default=15)
    options = parser.parse_args()
    scene = scene_module.load(SCENES / f"{options.scene}.toml").with_values(
        {"time.method": "transient"})
    assert scene.contact.law == "dahl" and not scene.drive.prescribed
    plain, stepper = run_plain(scene), run_coupled(scene)      # compiled or loaded
    moved = np.max(np.abs(plain[:, 1] - stepper.F_d)) / np.max(np.abs(stepper.F_d))
    plain_s, stepper_s, ratios = [], [], []
    for _ in range(options.repeats):
        started = time.perf_counter()
        run_plain(scene)
        plain_s.append(time.perf_counter() - started)
        started = time.perf_counter()
        run_coupled(scene)
        stepper_s.append(time.perf_counter() - started)
        ratios.append(stepper_s[-1] / plain_s[-1])
    print(f"{options.scene} ({round(scene.time.T / scene.time.dt)} steps), {options.repeats} "
          f"repeats in turn: plain loop {statistics.median(plain_s) * 1e3:.1f} ms, stepper "
          f"{statistics.median(stepper_s) * 1e3:.1f} ms (medians); ratio median "
          f"{statistics.median(ratios):.3f} (range {min(ratios):.3f}-{max(ratios):.3f}); "
          f"F_d's largest difference between the two {moved:.1e} of its largest value")


if __name__ == "__main__":
    main()
