"""The 1D longitudinal model of the paper's reference [23].

The body and the base move along X only: the friction law sees a slip along
X and no phase 2 (eqs 4-6 for Dahl: ds/dt = v_r - (k_t / F_c) |v_r| s,
F = k_t s). Kept as its own short stepper so that the coupled stepper at
theta = 0 can be checked against it, for any law.
"""

import math

import numpy as np

from ..core.base_motion import base_displacement
from ..core.chunks import run_in_chunks
from ..core.law_limits import divergence_force
from ..core.series import COLUMNS, NO_STEPS, RecordPlan, TimeSeries, full_resolution_steps
from ..friction_law import law_kernel
from ..friction_law.contract import FASTMATH
from .coupled import (COS_PHASE, FX, ROW, SIN_PHASE, VX, XB, X, at_rest, check_finished,
                      record_row)


@law_kernel(cache=True, error_model="numpy", fastmath=FASTMATH)
def longitudinal_loop(mass, k_d, v_d, prescribed, u0, omega, t_on, F_N, state, params, dt,
                      first, last, stride, full_from, f_max, carried, out):
    """Steps ``first``..``last`` as coupled.coupled_loop, in X only (``carried`` holds
    coupled's slots X, VX, FX, XB, the phase and the row)."""
    x, v, f, x_b = carried[X], carried[VX], carried[FX], carried[XB]
    sin_phase, cos_phase = carried[SIN_PHASE], carried[COS_PHASE]
    cos_step, sin_step = math.cos(omega * dt), math.sin(omega * dt)
    j = int(carried[ROW])
    for i in range(first, last + 1):
        t = i * dt
        if prescribed:
            x_new = v_d * t
        else:
            v += dt * (k_d * (v_d * (t - dt) - x) - f) / mass   # eq 12 with eq 17
            x_new = x + dt * v
        x_b_new, sin_phase, cos_phase = base_displacement(i, dt, omega, t_on, u0, sin_phase,
                                                          cos_phase, cos_step, sin_step)  # eq 23
        f, _ = law_update((x_new - x) - (x_b_new - x_b), 0.0, 0.0, 0.0,  # noqa: F821 (eq 6)
                          F_N, 1.0, state, params, dt)
        x, x_b = x_new, x_b_new
        f_d = f if prescribed else k_d * (v_d * t - x)                 # eq 17
        if not abs(f) <= f_max:
            return i
        if i >= full_from or i % stride == 0:
            record_row(out, j, t, f_d, f, 0.0, x, 0.0, x_b, 0.0)
            j += 1
    carried[X], carried[VX], carried[FX], carried[XB] = x, v, f, x_b
    carried[SIN_PHASE], carried[COS_PHASE], carried[ROW] = sin_phase, cos_phase, j
    return 0


def _run_loop(scene, plan: RecordPlan, out: np.ndarray) -> int:
    """The 1D loop, compiled for the scene's law, over ``plan``'s steps into ``out``;
    returns the failing step, or 0."""
    law = scene.friction
    state, carried = law.law.initial_state(1)[0], at_rest()

    def args(first, last):
        return (scene.body.mass, scene.drive.k_d, scene.drive.v_d, scene.drive.prescribed,
                scene.u0, scene.omega, scene.vibration.t_on, scene.contact.F_N, state,
                law.params, scene.time.dt, first, last, plan.stride, plan.full_from,
                divergence_force(scene), carried, out)

    loop = longitudinal_loop.prepared(law.law, args(1, 0), "the longitudinal analytic stepper")
    return run_in_chunks(plan.steps, lambda first, last: loop(*args(first, last)))


def load_longitudinal(scene) -> None:
    """Load the 1D loop compiled for the scene's law (see coupled.load_coupled)."""
    _run_loop(scene, NO_STEPS, np.empty((0, len(COLUMNS))))


def run_longitudinal(scene) -> TimeSeries:
    """Integrate the scene's X motion in 1D (its theta and eta_y are ignored)."""
    plan = RecordPlan.for_scene(scene, full_resolution_steps(scene))
    out = np.empty((plan.rows, len(COLUMNS)))
    check_finished(_run_loop(scene, plan, out), scene)
    return TimeSeries.from_table(out)
