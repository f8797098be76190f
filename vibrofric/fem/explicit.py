"""Explicit central-difference time integration: the Abaqus/Explicit analogue.

With the lumped (diagonal) mass M, one step from t_n to t_{n+1} = t_n + dt is

    f_n       = f_ext - K (u_n + beta v_n)                  elastic + Rayleigh damping C = beta K
              + sum_i [N_i e_z - F_i]_n                     contact: normal (penalty spring and its
                                                            share beta k_pen w_i of the damping)
                                                            and friction (contact.py)
              + sum_a w_a F_d,n e_x                         drive, F_d,n = k_d (v_d t_n - x_A,n) (eq 17)
    v_{n+1/2} = v_{n-1/2} + dt M^-1 f_n
    u_{n+1}   = u_n + dt v_{n+1/2}

(the damping uses the lagging velocity v_{n-1/2}, as Abaqus does, which keeps
the step explicit; stable while dt <= dt_crit, stability.py). Then the base
moves to its position at t_{n+1} (eqs 23-25), every contact node's normal force
and asperity are updated from its displacement increment (contact.py, the
VFRIC analogue), and F_d = k_d (v_d t_{n+1} - x_A,n+1) is recorded.

This is the lumped stepper's order of operations (analytic/coupled.py, which
writes the same scheme as semi-implicit Euler: v += dt a, x += dt v): drive
force from the start of the step, friction force from the previous update.

The whole step (sparse product with K in 3x3 node blocks, contact, friction,
drive, base, recording, checks) is one numba loop; Python only sees the run again every
``fem.output_every`` steps, to write a ParaView frame.
"""

import math
import time
from dataclasses import dataclass

import numpy as np
from numba import njit

from ..analytic.coupled import base_phase, friction_law_args, vibration_axis
from ..analytic.series import NumericalError
from ..friction_law.kernels import FASTMATH
from .contact import contact_forces
from .drive import attachment_position
from .model import check_step

# Columns of the recorded table: the standard TimeSeries columns, then F_n.
COLUMNS = ("t", "F_d", "F_x", "F_y", "x", "y", "x_b", "y_b", "F_n")
EXTRA = ("F_n",)

# Failure codes returned by the loop, and what they mean.
OK, NOT_FINITE, FRICTION_DIVERGED, NORMAL_BLOWUP, LIFT_OFF = 0, 1, 2, 3, 4

# A summed friction force beyond DIVERGED times its Coulomb limit, or a summed
# normal force beyond NORMAL_LIMIT times F_N, is numerical divergence, not physics
# (a Dahl asperity never exceeds its sliding length; the normal load is F_N).
DIVERGED = 3.0
NORMAL_LIMIT = 10.0

# scalars[]: the loop's carried scalar state
XB, YB, SIN, COS, FN_MIN, FN_MAX, FN_MIN_ON, FN_MAX_ON = range(8)


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def explicit_steps(first, last, dt,
                   indptr, indices, data, inverse_mass, load, beta,
                   contact_nodes, penalty_share, area_share,
                   k_t, mu, mu_s, v_s, h_t, h_v, law, update, eta_y,
                   attach_nodes, attach_weights, k_d, v_d,
                   amplitude, omega, t_on, cos_theta, sin_theta,
                   stride, full_from, F_N, mu_max,
                   reference, u, v, work, force_sum, disp, disp_new, vel_z,
                   length, ex, ey, normal, friction, scalars, counters, out):
    """Advance steps ``first`` .. ``last`` (inclusive). Returns (failed step, code), (0, OK) if none.

    (indptr, indices, data) is K in block sparse rows of 3x3 node blocks
    (scipy BSR), data of shape (blocks, 3, 3).

    All state lives in the arrays (u, v, disp, length, ex, ey, normal,
    friction, scalars, counters) so that a run can be resumed chunk by chunk.
    """
    dofs = u.shape[0]
    contacts = contact_nodes.shape[0]
    xb, yb = scalars[XB], scalars[YB]
    sin_phase, cos_phase = scalars[SIN], scalars[COS]
    cos_step, sin_step = math.cos(omega * dt), math.sin(omega * dt)
    j = counters[0]
    for i in range(first, last + 1):
        t = i * dt
        # Drive force at the start of the step (eq 17).
        x_a, y_a = attachment_position(u, reference, attach_nodes, attach_weights)
        f_d = k_d * (v_d * (t - dt) - x_a)

        # f = f_ext - K (u + beta v): elastic and stiffness-proportional damping forces.
        for k in range(dofs):
            work[k] = u[k] + beta * v[k]
        # K in 3x3 blocks (node rows; BSR): four times faster than scalar CSR here.
        for node in range(indptr.shape[0] - 1):
            a0 = a1 = a2 = 0.0
            for p in range(indptr[node], indptr[node + 1]):
                col = 3 * indices[p]
                w0, w1, w2 = work[col], work[col + 1], work[col + 2]
                b = data[p]
                a0 += b[0, 0] * w0 + b[0, 1] * w1 + b[0, 2] * w2
                a1 += b[1, 0] * w0 + b[1, 1] * w1 + b[1, 2] * w2
                a2 += b[2, 0] * w0 + b[2, 1] * w1 + b[2, 2] * w2
            row = 3 * node
            force_sum[row] = load[row] - a0
            force_sum[row + 1] = load[row + 1] - a1
            force_sum[row + 2] = load[row + 2] - a2
        # Contact: normal force up, friction -F on the body (from the last update).
        for c in range(contacts):
            d = 3 * contact_nodes[c]
            force_sum[d] -= friction[c, 0]
            force_sum[d + 1] -= friction[c, 1]
            force_sum[d + 2] += normal[c]
        # Drive: F_d spread over the attachment nodes by their weights.
        for a in range(attach_nodes.shape[0]):
            force_sum[3 * attach_nodes[a]] += attach_weights[a] * f_d
        # Central difference: v_{n+1/2} = v_{n-1/2} + dt M^-1 f_n;  u_{n+1} = u_n + dt v_{n+1/2}.
        for k in range(dofs):
            v[k] += dt * inverse_mass[k] * force_sum[k]
            u[k] += dt * v[k]

        # Base at t_{n+1} (eqs 23-25).
        u_base = 0.0
        if t >= t_on:
            sin_phase, cos_phase = base_phase(i, dt, omega, t_on, sin_phase, cos_phase,
                                              cos_step, sin_step)
            u_base = amplitude * sin_phase
        xb_new, yb_new = u_base * cos_theta, u_base * sin_theta

        # Contact nodes: normal force and the two-phase friction update (VFRIC analogue).
        for c in range(contacts):
            d = 3 * contact_nodes[c]
            disp_new[c, 0] = u[d]
            disp_new[c, 1] = u[d + 1]
            disp_new[c, 2] = u[d + 2]
            vel_z[c] = v[d + 2]
        f_n, f_x, f_y = contact_forces(
            disp, disp_new, vel_z, xb_new - xb, yb_new - yb, eta_y,
            penalty_share, area_share, beta,
            k_t, mu, mu_s, v_s, h_t, h_v, law, update, dt,
            length, ex, ey, normal, friction)
        magnitude = 0.0
        for c in range(contacts):
            disp[c, 0] = disp_new[c, 0]
            disp[c, 1] = disp_new[c, 1]
            disp[c, 2] = disp_new[c, 2]
            magnitude += math.sqrt(friction[c, 0] ** 2 + friction[c, 1] ** 2)
        xb, yb = xb_new, yb_new

        x_a, y_a = attachment_position(u, reference, attach_nodes, attach_weights)
        f_d = k_d * (v_d * t - x_a)  # eq 17

        # Numerical trouble stops the run at once.
        code = OK
        if not (math.isfinite(f_d) and math.isfinite(f_n) and math.isfinite(magnitude)):
            code = NOT_FINITE
        elif f_n > NORMAL_LIMIT * F_N:
            code = NORMAL_BLOWUP
        elif f_n <= 0.0:
            code = LIFT_OFF
        elif magnitude > DIVERGED * mu_max * max(f_n, F_N):
            code = FRICTION_DIVERGED
        if code != OK:
            counters[0] = j
            return i, code

        scalars[FN_MIN] = min(scalars[FN_MIN], f_n)
        scalars[FN_MAX] = max(scalars[FN_MAX], f_n)
        if t >= t_on:
            scalars[FN_MIN_ON] = min(scalars[FN_MIN_ON], f_n)
            scalars[FN_MAX_ON] = max(scalars[FN_MAX_ON], f_n)
        if i >= full_from or i % stride == 0:
            out[j, 0] = t
            out[j, 1] = f_d
            out[j, 2] = f_x
            out[j, 3] = f_y
            out[j, 4] = x_a
            out[j, 5] = y_a
            out[j, 6] = xb
            out[j, 7] = yb
            out[j, 8] = f_n
            j += 1

    scalars[XB], scalars[YB] = xb, yb
    scalars[SIN], scalars[COS] = sin_phase, cos_phase
    counters[0] = j
    return 0, OK


@dataclass
class State:
    """The explicit run's state between chunks (node arrays in DOLFINx dof order)."""

    step: int
    t: float
    u: np.ndarray           # (dofs,) displacement, including the preload
    v: np.ndarray           # (dofs,) velocity
    length: np.ndarray      # (contacts,) asperity length s
    ex: np.ndarray          # (contacts,) asperity direction e
    ey: np.ndarray
    normal: np.ndarray      # (contacts,) normal force N_i
    friction: np.ndarray    # (contacts, 2) friction force F_i (acts on the body as -F_i)
    x_b: float
    y_b: float


@dataclass
class Integration:
    """What an integrator returns: the recorded table and run statistics."""

    table: np.ndarray       # (rows, len(COLUMNS))
    state: State            # at the end of the run
    stats: dict


_HINTS = {
    NOT_FINITE: "a force became NaN or infinite",
    FRICTION_DIVERGED: "the summed friction force exceeded {DIVERGED} times its Coulomb limit "
                       "(a diverging asperity update)",
    NORMAL_BLOWUP: "the summed normal force exceeded {NORMAL_LIMIT} F_N",
    LIFT_OFF: "the block lost contact with the base (summed normal force 0)",
}


def _failure(step, code, scene, model):
    dt = scene.time.dt
    what = _HINTS[code].format(DIVERGED=DIVERGED, NORMAL_LIMIT=NORMAL_LIMIT)
    if code == FRICTION_DIVERGED and scene.contact.update == "paper":
        hint = ("the paper's explicit Dahl update is stable only while |v_r| dt < 2 s_c per node; "
                "use contact.update = \"exact\" or a smaller time.dt")
    else:
        hint = (f"try a smaller time.dt (stable step {model.dt_stable:.4g} s) or more "
                f"fem.damping (now {model.beta:.3g} s)")
    return NumericalError(f"FE run failed at t = {step * dt:.6g} s (step {step}, dt = {dt:g} s): "
                          f"{what}; {hint}")


def integrate(model, scene, plan, frame=None, every=0) -> Integration:
    """Run the scene's steps with central differences.

    plan   analytic.series.RecordPlan: which steps to keep
    frame  optional callable frame(state) called at t = 0 and every ``every`` steps
    """
    check_step(scene, model)  # (run_fe checks before opening output; this guards direct calls)
    c, dt = scene.contact, scene.time.dt
    k_t, mu, mu_s, v_s, h_t, h_v, law, update = friction_law_args(scene)
    cos_theta, sin_theta = vibration_axis(scene.vibration.theta_deg)
    dofs, contacts = model.dofs, model.contact_nodes.size

    u = model.u0.copy()
    v = np.zeros(dofs)
    work, force_sum = np.empty(dofs), np.empty(dofs)
    disp = u.reshape(-1, 3)[model.contact_nodes].copy()
    disp_new, vel_z = np.empty_like(disp), np.zeros(contacts)
    length = np.zeros(contacts)
    ex, ey = np.ones(contacts), np.zeros(contacts)  # before any motion the asperities point along X
    normal = model.normal0.copy()
    friction = np.zeros((contacts, 2))
    scalars = np.array([0.0, 0.0, 0.0, 1.0, np.inf, -np.inf, np.inf, -np.inf])
    counters = np.zeros(1, dtype=np.int64)
    out = np.empty((plan.rows, len(COLUMNS)))
    K = model.stiffness.tobsr(blocksize=(3, 3))  # node-by-node 3x3 blocks
    K.sort_indices()

    def state(step):
        return State(step, step * dt, u, v, length, ex, ey, normal, friction,
                     scalars[XB], scalars[YB])

    chunk = every if (frame is not None and every > 0) else plan.steps
    if frame is not None:
        frame(state(0))
    start = time.perf_counter()
    first = 1
    while first <= plan.steps:
        last = min(plan.steps, first + chunk - 1)
        failed, code = explicit_steps(
            first, last, dt,
            K.indptr, K.indices, K.data, model.inverse_mass, model.load, model.beta,
            model.contact_nodes, model.penalty_share, model.area_share,
            k_t, mu, mu_s, v_s, h_t, h_v, law, update, c.eta_y,
            model.attach_nodes, model.attach_weights, scene.drive.k_d, scene.drive.v_d,
            scene.u0, scene.omega, scene.vibration.t_on, cos_theta, sin_theta,
            plan.stride, plan.full_from, c.F_N, max(mu, mu_s),
            model.u0, u, v, work, force_sum, disp, disp_new, vel_z,
            length, ex, ey, normal, friction, scalars, counters, out)
        if code != OK:
            raise _failure(failed, code, scene, model)
        if frame is not None and last % chunk == 0:
            frame(state(last))
        first = last + 1
    loop_time = time.perf_counter() - start
    if counters[0] != plan.rows:
        raise RuntimeError(f"recorded {counters[0]} rows, planned {plan.rows}")
    stats = {"loop_time_s": loop_time,
             "F_n_min": scalars[FN_MIN], "F_n_max": scalars[FN_MAX],
             "F_n_min_after_t_on": scalars[FN_MIN_ON], "F_n_max_after_t_on": scalars[FN_MAX_ON]}
    return Integration(out, state(plan.steps), stats)
