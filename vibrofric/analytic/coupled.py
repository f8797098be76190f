"""The coupled longitudinal-transverse stepper (paper eqs 7-39, docs/model.md section 2).

A rigid body of mass m is pulled in X through the drive spring k_d from the
point B moving at v_d (eq 17) and rubs on the base through one lumped asperity,
updated by the scene's friction law (friction_law/contract.py: the
one-node case of the FE model's per-node update, area share 1). The base vibrates along the axis at theta
(eqs 23-25). Physical sign convention: the slip is body minus base.

Body motion (eqs 12, 15-16) is integrated by semi-implicit (symplectic) Euler:

    v_{n+1} = v_n + dt (F_d,n - F_n) / m,     x_{n+1} = x_n + dt v_{n+1}

which is the central-difference scheme of the FE model written in velocities.
"""

import math

import numpy as np
from numba import njit

from ..core.base_motion import base_displacement, vibration_axis
from ..core.chunks import run_in_chunks
from ..core.errors import NumericalError
from ..core.law_limits import divergence_force
from ..core.series import COLUMNS, NO_STEPS, RecordPlan, TimeSeries, full_resolution_steps
from ..friction_law import law_kernel
from ..friction_law.contract import FASTMATH


@njit(cache=True, error_model="numpy")
def record_row(out, j, t, f_d, f_x, f_y, x, y, xb, yb):
    """Row j of the kept series (core.series.COLUMNS): t, F_d, F_x, F_y, x, y, x_b, y_b."""
    out[j, 0] = t
    out[j, 1] = f_d
    out[j, 2] = f_x
    out[j, 3] = f_y
    out[j, 4] = x
    out[j, 5] = y
    out[j, 6] = xb
    out[j, 7] = yb


@njit(error_model="numpy", fastmath=FASTMATH, inline="always")
def body_step(prescribed, mass, k_d, v_d, t, dt, x, y, vx, vy, f_x, f_y):
    """The body's in-plane step to t = i dt: (x, y, v_x, v_y) after it.

    Pulled through the drive spring from B at v_d t (eq 17 at the start of the step)
    against the friction force (f_x, f_y) of the step before, by semi-implicit Euler
    (eqs 12, 15-16); a prescribed drive moves it at v_d exactly. The step of
    coupled_loop and normal.normal_loop, inlined by numba (inline="always") into each,
    so that either loop's machine code is what it was with the lines written out."""
    if prescribed:
        return v_d * t, 0.0, vx, vy
    f_d = k_d * (v_d * (t - dt) - x)          # eq 17 at the start of the step
    vx += dt * (f_d - f_x) / mass            # eq 12
    vy += dt * (-f_y) / mass                 # eqs 15-16
    return x + dt * vx, y + dt * vy, vx, vy


# The coupled loop's state between two chunks of steps (core.chunks): the body's
# displacement and velocity (eqs 13-16), the friction force (eqs 38-39), the base's
# displacement (eqs 24-25), the base's phase, and the next row of the kept series.
X, Y, VX, VY, FX, FY, XB, YB, SIN_PHASE, COS_PHASE, ROW = range(11)


def at_rest() -> np.ndarray:
    """The carried state at t = 0: everything at rest, the phase's cosine 1."""
    carried = np.zeros(ROW + 1)
    carried[COS_PHASE] = 1.0
    return carried


@law_kernel(cache=True, error_model="numpy", fastmath=FASTMATH)
def coupled_loop(mass, k_d, v_d, prescribed, u0, omega, t_on, cos_theta, sin_theta, eta_y,
                 F_N, state, params, dt, first, last, stride, full_from, f_max, carried, out):
    """Run steps ``first``..``last`` from the law's ``state`` and the ``carried`` state
    (at_rest() before step 1), both updated in place; keep rows in ``out``.
    Returns the failing step, or 0."""
    x, y, vx, vy = carried[X], carried[Y], carried[VX], carried[VY]
    f_x, f_y, xb, yb = carried[FX], carried[FY], carried[XB], carried[YB]
    sin_phase, cos_phase = carried[SIN_PHASE], carried[COS_PHASE]
    cos_step, sin_step = math.cos(omega * dt), math.sin(omega * dt)
    j = int(carried[ROW])
    for i in range(first, last + 1):
        t = i * dt
        x_new, y_new, vx, vy = body_step(prescribed, mass, k_d, v_d, t, dt, x, y, vx, vy,
                                         f_x, f_y)
        u, sin_phase, cos_phase = base_displacement(i, dt, omega, t_on, u0, sin_phase, cos_phase,
                                                    cos_step, sin_step)  # eq 23
        xb_new, yb_new = u * cos_theta, u * sin_theta  # eqs 24-25
        f_x, f_y = law_update(  # noqa: F821 (the scene's law, friction_law/specialize.py)
            (x_new - x) - (xb_new - xb), y_new - y,  # phase 1: body minus base in X (eq 14)
            0.0, eta_y * (yb_new - yb),              # phase 2: free end by eta_y dy_b (eq 30)
            F_N, 1.0, state, params, dt)
        x, y, xb, yb = x_new, y_new, xb_new, yb_new
        f_d = f_x if prescribed else k_d * (v_d * t - x)  # eq 17
        if not (math.sqrt(f_x * f_x + f_y * f_y) <= f_max and math.isfinite(f_d)):
            return i
        if i >= full_from or i % stride == 0:
            record_row(out, j, t, f_d, f_x, f_y, x, y, xb, yb)
            j += 1
    carried[X], carried[Y], carried[VX], carried[VY] = x, y, vx, vy
    carried[FX], carried[FY], carried[XB], carried[YB] = f_x, f_y, xb, yb
    carried[SIN_PHASE], carried[COS_PHASE], carried[ROW] = sin_phase, cos_phase, j
    return 0


def check_finished(failed_step: int, scene) -> None:
    """Raise NumericalError for a run that stopped at ``failed_step``."""
    if failed_step:
        c, dt = scene.contact, scene.time.dt
        hint = ("the paper's explicit update is stable only while |v_r| dt < 2 s_c; "
                "use contact.update = \"exact\" or a smaller time.dt"
                if c.law_values.get("update") == "paper" else "try a smaller time.dt")
        raise NumericalError(f"the friction law's update diverged at t = {failed_step * dt:.6g} s "
                             f"(step {failed_step}, dt = {dt:g} s): {hint}")


def _run_loop(scene, plan: RecordPlan, out: np.ndarray) -> int:
    """The coupled loop, compiled for the scene's law, over ``plan``'s steps into ``out``
    in chunks (core.chunks); returns the failing step, or 0."""
    cos_theta, sin_theta = vibration_axis(scene.vibration.theta_deg)
    law = scene.friction
    state, carried = law.law.initial_state(1)[0], at_rest()

    def args(first, last):
        return (scene.body.mass, scene.drive.k_d, scene.drive.v_d, scene.drive.prescribed,
                scene.u0, scene.omega, scene.vibration.t_on, cos_theta, sin_theta,
                scene.contact.eta_y, scene.contact.F_N, state, law.params, scene.time.dt,
                first, last, plan.stride, plan.full_from, divergence_force(scene), carried, out)

    loop = coupled_loop.prepared(law.law, args(1, 0), "the coupled analytic stepper")
    return run_in_chunks(plan.steps, lambda first, last: loop(*args(first, last)))


def load_coupled(scene) -> None:
    """Load the coupled loop compiled for the scene's law from numba's cache (compile it
    on a first run): a run of no steps, with the argument types of a real one, so that
    a timed run_coupled() is the stepping alone."""
    _run_loop(scene, NO_STEPS, np.empty((0, len(COLUMNS))))


def run_coupled(scene) -> TimeSeries:
    """Integrate the scene with the coupled two-phase stepper."""
    plan = RecordPlan.for_scene(scene, full_resolution_steps(scene))
    out = np.empty((plan.rows, len(COLUMNS)))
    check_finished(_run_loop(scene, plan, out), scene)
    return TimeSeries.from_table(out)
