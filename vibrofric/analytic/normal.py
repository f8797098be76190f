"""The lumped body's normal degree of freedom: a base that also moves along Z (docs/model.md
section 6).

Used only where vibration.normal_amplitude > 0 (solve.STEPPERS); every other run
steps through coupled.coupled_loop / longitudinal.longitudinal_loop, which this
module leaves as they are. Its periodic steady state: periodic.NormalCycleMap, the
shooting state extended by z, dz/dt and N.

Signs: z is the body's upward displacement and z_b the base's, both from the static
equilibrium under the load (z = z_b = 0 at rest). The contact is a unilateral spring
of stiffness k_n (contact.k_n) with a dashpot c_n beside it; its penetration is

    p = F_N / k_n + z_b - z              (F_N / k_n: the static penetration)

and it pushes the body up by

    N = min(max(0, k_n p + c_n dp/dt), 2 k_n p)   for p > 0,   else 0

(the FE model's penalty contact, fem/model/contact.py normal_force, on the whole
face: it never pulls, and the dashpot's push is at most the spring's, so N goes to
0 with p). F_N is the constant downward load (the body's weight included), so

    m d2z/dt2 = N - F_N

integrated by the same semi-implicit Euler as X and Y (coupled.py), k_n p computed as
F_N + k_n (z_b - z) so that the body at rest holds N = F_N exactly: with A_n = 0 the
friction law sees what coupled_loop passes it and the loop answers its answer bit for
bit (tests/test_normal.py). The base moves as

    z_b(t) = A_n sin(w (t - t_on) + phi)   for t >= t_on, else 0

(A_n vibration.normal_amplitude, phi vibration.normal_phase_deg). At t_on the body
starts on its steady forced response in contact (start_gain), as a base brought up
to its amplitude slowly would leave it. Started at rest, the body would bounce
freely by about k_n A_n r / |1 - r^2| (in N, r = w / w_n), 1/r times its forced
swing: on the paper's block (r = 0.18) that lost contact from 0.5 of the threshold
below, and at 0.9 of it the body stayed on a bouncing orbit (a second attractor of
the unilateral oscillator) out of contact 91% of the time.
The friction law sees N(t) as its normal force every step (friction_law/contract.py:
the force is held within mu_max N of that step, and N = 0 releases it). So the
update is taken as diverged past core.law_limits.divergence_force scaled by
max(1, N / F_N): a landing after a bounce pushes N, and with it the law's force,
above their static values.

The dashpot: c_n = 2 zeta_n sqrt(k_n m), zeta_n = contact.zeta_n (0.02 by default).
It damps the free bounce the start of the motion excites, so that a steady cycle
exists (an undamped unilateral oscillator never forgets its start). Below contact
loss it changes the forced amplitude by the factor
sqrt(1 + (2 zeta_n r)^2) / sqrt(1 + (2 zeta_n r / (1 - r^2))^2), r = w / w_n: within
1e-5 of 1 for r < 0.25 at 0.02. Above the contact-loss threshold it decides which
orbit the body settles on: each landing sets off a free bounce, which must die out
within the ~1/r bounce periods of a cycle. On the low stiff block of
benchmarks/fe_normal_vs_lumped.py (r = 0.08) the body at 1.012 times the threshold
stays near its forced orbit (out of contact 6% of the cycle) at zeta_n = 0.02 and 0.01
and jumps onto the bouncing one (98-99%) at 0.005 and below (docs/validation.md).

The default k_n: the FE block's first bounce mode on its penalty contact
(core/bounce.py, Scene.normal_stiffness). What the lumped body still lacks: rocking (the FE
block tips on its face under the friction's moment, its nodes' normal forces
differ) and the block's own elastic modes beyond the first (the FE model moves its
base in Z too: fem/model/contact.py, docs/fe-model.md). It stands for an FE body
held so that it cannot turn (drive.holder) and stiff enough that its face stays flat
(docs/validation.md "A base moving along Z").
"""

import math

import numpy as np

from ..core.base_motion import base_displacement, normal_displacement, vibration_axis
from ..core.base_table import base_table, table_row
from ..core.base_motion import first_step_on as base_first_step_on
from ..core.chunks import run_in_chunks
from ..core.law_limits import divergence_force
from ..core.series import COLUMNS, NO_STEPS, RecordPlan, TimeSeries, full_resolution_steps
from ..friction_law import law_kernel
from ..friction_law.contract import FASTMATH
from .coupled import (COS_PHASE, FX, FY, ROW, SIN_PHASE, VX, VY, XB, YB, X, Y, at_rest,
                      body_step, check_finished, record_row)

NORMAL_COLUMNS = ("z", "z_b", "N")   # the time series' columns after core.series.COLUMNS

# The carried state's slots after coupled's: the body's Z displacement and velocity,
# and the contact's normal force of the last step.
Z, VZ, N = ROW + 1, ROW + 2, ROW + 3


def normal_at_rest(F_N: float) -> np.ndarray:
    """coupled.at_rest() and the body at rest on its contact: z = 0, N = F_N."""
    carried = np.zeros(N + 1)
    carried[:ROW + 1] = at_rest()
    carried[N] = F_N
    return carried


@law_kernel(cache=True, error_model="numpy", fastmath=FASTMATH)
def normal_loop(mass, k_d, v_d, prescribed, u0, omega, t_on, cos_theta, sin_theta, eta_y,
                F_N, k_n, c_n, amplitude_n, phase_n, gain_re, gain_im, on_step, table, table_from,
                table_period, state, params, dt, first, last, stride, full_from, f_max, carried,
                out):
    """coupled.coupled_loop with the body's Z motion on the unilateral contact (the
    module docstring's equations); ``out``'s rows add z, z_b, N (NORMAL_COLUMNS).
    The 1D stepper is this loop with sin_theta = eta_y = 0. ``table`` (rows of
    core.base_table.TABLE_COLUMNS from step ``table_from``, repeating every
    ``table_period`` steps, 0: the last row held; no rows: none) adds the base's
    motion given per step to the sine's."""
    x, y, vx, vy = carried[X], carried[Y], carried[VX], carried[VY]
    f_x, f_y, xb, yb = carried[FX], carried[FY], carried[XB], carried[YB]
    z, vz, n = carried[Z], carried[VZ], carried[N]
    sin_phase, cos_phase = carried[SIN_PHASE], carried[COS_PHASE]
    cos_step, sin_step = math.cos(omega * dt), math.sin(omega * dt)
    sin_n, cos_n = math.sin(phase_n), math.cos(phase_n)
    j = int(carried[ROW])
    for i in range(first, last + 1):
        t = i * dt
        x_new, y_new, vx, vy = body_step(prescribed, mass, k_d, v_d, t, dt, x, y, vx, vy,
                                         f_x, f_y)
        vz += dt * (n - F_N) / mass                 # m z'' = N - F_N
        z += dt * vz
        u, sin_phase, cos_phase = base_displacement(i, dt, omega, t_on, u0, sin_phase, cos_phase,
                                                    cos_step, sin_step)
        xb_new, yb_new = u * cos_theta, u * sin_theta
        zb, vzb = 0.0, 0.0
        if t >= t_on:   # A_n sin(w (t - t_on) + phi) by the in-plane motion's rotated phase
            zb, vzb = normal_displacement(amplitude_n, omega, sin_n, cos_n, sin_phase, cos_phase)
        k = table_row(table, table_from, table_period, i)
        if k >= 0:      # the motion given per step, added (core/base_table.py)
            xb_new += table[k, 0]
            yb_new += table[k, 1]
            zb += table[k, 2]
            vzb += table[k, 5]
        if i == on_step:    # the first step on: the body on its forced response
            z = gain_re * zb + gain_im * vzb / omega
            vz = gain_re * vzb - gain_im * omega * zb
        spring = F_N + k_n * (zb - z)               # k_n p, exactly F_N at rest
        n = 0.0
        if spring > 0.0:
            n = min(max(0.0, spring + c_n * (vzb - vz)), 2.0 * spring)
        f_x, f_y = law_update(  # noqa: F821 (the scene's law, friction_law/specialize.py)
            (x_new - x) - (xb_new - xb), y_new - y,
            0.0, eta_y * (yb_new - yb),
            n, 1.0, state, params, dt)
        x, y, xb, yb = x_new, y_new, xb_new, yb_new
        f_d = f_x if prescribed else k_d * (v_d * t - x)
        # f_max: core.law_limits.divergence_force at F_N; a landing's N above F_N
        # raises it in proportion (the law holds |F| within mu_max N)
        limit = f_max if n <= F_N else f_max * (n / F_N)
        if not (math.sqrt(f_x * f_x + f_y * f_y) <= limit and math.isfinite(f_d)
                and math.isfinite(z)):
            return i
        if i >= full_from or i % stride == 0:
            record_row(out, j, t, f_d, f_x, f_y, x, y, xb, yb)
            out[j, 8] = z
            out[j, 9] = zb
            out[j, 10] = n
            j += 1
    carried[X], carried[Y], carried[VX], carried[VY] = x, y, vx, vy
    carried[FX], carried[FY], carried[XB], carried[YB] = f_x, f_y, xb, yb
    carried[Z], carried[VZ], carried[N] = z, vz, n
    carried[SIN_PHASE], carried[COS_PHASE], carried[ROW] = sin_phase, cos_phase, j
    return 0


def moves_normally(scene) -> bool:
    """Whether the scene steps through normal_loop: its base moves along Z
    (vibration.normal_amplitude > 0), or its motion is given per step (a measured motion
    or harmonics, core/base_table.py: this loop alone reads the table; with z_b = 0 it
    answers coupled_loop's answer bit for bit)."""
    return scene.vibration.normal_amplitude > 0.0 or scene.vibration.sampled


def motion_table(scene, dt: float, t_on: float, last_step: int) -> tuple:
    """normal_loop's (table, table_from, table_period) for the scene at the step ``dt``,
    the motion starting at ``t_on`` (0 in a periodic cycle), to ``last_step``."""
    table = base_table(scene.vibration, scene.omega, dt, t_on, base_first_step_on(t_on, dt),
                       last_step)
    return table.rows, table.first_step, table.period


def start_gain(scene) -> tuple:
    """(Re H, Im H): the body's forced response in contact over the base's motion,
    H = (k_n + i c_n w) / (k_n - m w^2 + i c_n w), on which it starts (module docstring):
    z = Re H z_b + Im H dz_b/dt / w."""
    k_n, c_n, m, w = scene.normal_stiffness, contact_damping(scene), scene.body.mass, scene.omega
    H = complex(k_n, c_n * w) / complex(k_n - m * w * w, c_n * w)
    return H.real, H.imag


def first_step_on(scene) -> int:
    """The first step i whose time i dt is at or past t_on (the test of
    core.base_motion.base_displacement, to the bit)."""
    return base_first_step_on(scene.vibration.t_on, scene.time.dt)


def contact_damping(scene) -> float:
    """c_n = 2 zeta_n sqrt(k_n m), N s/m (zeta_n: contact.zeta_n)."""
    return 2.0 * scene.contact.zeta_n * math.sqrt(scene.normal_stiffness * scene.body.mass)


def _run_loop(scene, planar: bool, plan: RecordPlan, out: np.ndarray) -> int:
    """The loop, compiled for the scene's law, over ``plan``'s steps; ``planar``: the
    coupled stepper's X and Y, else the 1D stepper's X alone. Returns the failing step, or 0."""
    cos_theta, sin_theta = vibration_axis(scene.vibration.theta_deg)
    eta_y = scene.contact.eta_y
    if not planar:
        sin_theta, eta_y = 0.0, 0.0
    law, vib = scene.friction, scene.vibration
    state, carried = law.law.initial_state(1)[0], normal_at_rest(scene.contact.F_N)
    table = motion_table(scene, scene.time.dt, vib.t_on, scene.steps)

    def args(first, last):
        return (scene.body.mass, scene.drive.k_d, scene.drive.v_d, scene.drive.prescribed,
                scene.u0, scene.omega, vib.t_on, cos_theta, sin_theta, eta_y,
                scene.contact.F_N, scene.normal_stiffness, contact_damping(scene),
                vib.normal_amplitude, math.radians(vib.normal_phase_deg or 0.0),
                *start_gain(scene), first_step_on(scene), *table, state,
                law.params, scene.time.dt, first, last, plan.stride, plan.full_from,
                divergence_force(scene), carried, out)

    loop = normal_loop.prepared(law.law, args(1, 0), "the analytic stepper with normal motion")
    return run_in_chunks(plan.steps, lambda first, last: loop(*args(first, last)))


def load_normal(scene, planar: bool = True) -> None:
    """Load the loop compiled for the scene's law (see coupled.load_coupled)."""
    _run_loop(scene, planar, NO_STEPS, np.empty((0, len(COLUMNS) + len(NORMAL_COLUMNS))))


def run_normal(scene, planar: bool = True) -> TimeSeries:
    """Integrate the scene with its base moving along Z too; the series adds z, z_b, N."""
    plan = RecordPlan.for_scene(scene, full_resolution_steps(scene))
    out = np.empty((plan.rows, len(COLUMNS) + len(NORMAL_COLUMNS)))
    check_finished(_run_loop(scene, planar, plan, out), scene)
    return TimeSeries.from_table(out, NORMAL_COLUMNS)


def normal_force_keys(series: TimeSeries, scene, steps: int) -> dict:
    """The summary's normal-force keys over the last ``steps`` kept rows (the steady
    cycles the drive force is averaged over): the fraction of them out of contact
    (N = 0) and N's mean, min and max. A run without normal motion holds N = F_N."""
    if "N" not in series.extra:
        F_N = scene.contact.F_N
        return {"contact_loss_fraction": 0.0, "normal_force_mean": F_N,
                "normal_force_min": F_N, "normal_force_max": F_N}
    n = series.extra["N"][-steps:]
    return {"contact_loss_fraction": float(np.mean(n <= 0.0)),
            "normal_force_mean": float(np.mean(n)), "normal_force_min": float(np.min(n)),
            "normal_force_max": float(np.max(n))}
