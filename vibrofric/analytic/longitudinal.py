"""The 1D longitudinal model of the paper's reference [23].

Dahl in one dimension with the signed deformation s and the relative velocity
v_r = x' - x_b' (eqs 4-6): ds/dt = v_r - (k_t / F_c) |v_r| s, F = k_t s.
Kept as its own short stepper so that the coupled stepper at theta = 0 can be
checked against it.
"""

import math

import numpy as np
from numba import njit

from ..friction_law import relax_length
from ..friction_law.kernels import FASTMATH
from ..friction_law.law import UPDATES
from ..core.base_motion import base_displacement
from ..core.friction import divergence_bound
from ..core.series import RecordPlan, TimeSeries, full_resolution_steps
from .coupled import _record, check_finished


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def longitudinal_loop(mass, k_d, v_d, prescribed, u0, omega, t_on, k_t, F_c, update, dt,
                      steps, stride, full_from, s_max, out):
    x = v = s = f = x_b = 0.0
    s_c = F_c / k_t
    sin_phase, cos_phase = 0.0, 1.0
    cos_step, sin_step = math.cos(omega * dt), math.sin(omega * dt)
    j = 0
    for i in range(1, steps + 1):
        t = i * dt
        if prescribed:
            x_new = v_d * t
        else:
            v += dt * (k_d * (v_d * (t - dt) - x) - f) / mass   # eq 12 with eq 17
            x_new = x + dt * v
        x_b_new, sin_phase, cos_phase = base_displacement(i, dt, omega, t_on, u0, sin_phase,
                                                          cos_phase, cos_step, sin_step)  # eq 23
        s = relax_length(s, (x_new - x) - (x_b_new - x_b), s_c, update)  # eq 6
        f = k_t * s                                                     # eq 1
        x, x_b = x_new, x_b_new
        f_d = f if prescribed else k_d * (v_d * t - x)                 # eq 17
        if not abs(s) <= s_max:
            return i
        if i >= full_from or i % stride == 0:
            _record(out, j, t, f_d, f, 0.0, x, 0.0, x_b, 0.0)
            j += 1
    return 0


def run_longitudinal(scene) -> TimeSeries:
    """Integrate the scene's X motion with the 1D Dahl model (its theta and eta_y are ignored)."""
    if scene.contact.law != "dahl":
        raise ValueError("the 1D longitudinal model [23] is Dahl only")
    plan = RecordPlan.for_scene(scene, full_resolution_steps(scene))
    out = np.empty((plan.rows, 8))
    failed = longitudinal_loop(
        scene.body.mass, scene.drive.k_d, scene.drive.v_d, scene.drive.mode == "velocity",
        scene.u0, scene.omega, scene.vibration.t_on, scene.contact.k_t, scene.F_c,
        UPDATES[scene.contact.update], scene.time.dt,
        plan.steps, plan.stride, plan.full_from, divergence_bound(scene), out)
    check_finished(failed, scene)
    return TimeSeries.from_table(out)
