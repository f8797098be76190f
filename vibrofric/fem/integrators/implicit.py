"""Implicit time integration: generalized-alpha with the linear operator factorized once.

u = u0 + T q (T = I for the full model, a Craig-Bampton basis for the reduced
one); each step solves M q'' + C q' + K q = P f_c - P_z N0 + d_x F_d with the
linear part in one matrix A, factorized once a run, and the contact forces
f_c (the friction law) and the drive F_d (eq 17) iterated in the contact
space to a fixed point. docs/fe-model.md ("How an implicit step works")
gives the equations, why the iteration converges at any step, and where it
does not (nodes near lift-off: a Newton step on the critical nodes).

The parts: generalized_alpha.py (coefficients, the linear system, the
contact tangent; the step's linear response and the Newmark update),
contact_solve.py (the contact forces at a trial state and the iteration: the
only part compiled for each friction law), step_cost.py (for "auto"),
energy.py (the balance); here, the prepared run (ImplicitRun: the
factorization, the contact operator G, the refusal of a too-long step) and
its compiled step, implicit_steps.

A base motion given per step (vibration.harmonics, vibration.motion: core/base_table.py)
is read at every friction sub-step's end, where the sine is evaluated
(contact_solve.table_over_substeps), and added to it; where it moves the base along Z
the body starts on its forced response to the sine's and the table's z_b together
(normal_start.py), as the explicit integrator's does.
"""

import math
import time
from typing import NamedTuple

import numpy as np
import scipy.sparse as sp
from numba import njit

from ...core.base_motion import (base_displacement, normal_displacement, normal_phase,
                                 vibration_axis)
from ...core.base_table import TABLE_COLUMNS, substep_table, table_moves_along_z, table_row
from ...core.errors import StepTooLong
from ...core.law_limits import slip_per_step
from ...friction_law import law_kernel
from ...friction_law.contract import FASTMATH
from ..outputs import energy, recording, trouble
from .anderson import DEPTH, History
from .borrowed import borrowed
from .contact_solve import (ITERATION_TOLERANCE, MAX_ACCELERATED_CONTRACTION, MAX_CONTRACTION,
                            MAX_ITERATIONS, NOT_CONVERGED,
                            STALLED, ContactData, StepStart, base_over_substeps, commit_contact,
                            implicit_substeps, iterate_contact, normal_over_substeps,
                            still_substeps, table_over_substeps)
from .normal_start import (first_step_on, normal_force_limit, restart_normal_forces,
                           start_gain, start_motion)
from ..model.drive import attachment_xy
from ..outputs.energy import SUMS, add_contact_work, add_damping_and_drive_work
from ..outputs.energy import record as record_energy, stored as energy_stored
from .interface import Watch, watched_contact
from .generalized_alpha import (LinearSystem, Scheme, coefficients, contact_tangent,
                                free_response, newmark_update)
from ..model.linalg import apply, bsr, columns_of_inverse, factorize, inverse, solve
from ..outputs.recording import (COS, LOOP_SCALARS, SIN, XB, YB, finish_step, keep_step,
                                 record_normal)
from .step_cost import step_cost
from .time_loop import Started, TimeLoop

# scalars[]: the implicit loop's own carried state, after recording's: the drive's force
# and a prescribed drive's hold in Y at the last step, the contact iteration's statistics,
# the base's Z at the last step
OWN_SCALARS = 6
F_D, ITER_MAX, ITER_SUM, ITER_STALLED, F_HOLD, ZB = range(LOOP_SCALARS,
                                                          LOOP_SCALARS + OWN_SCALARS)


class Work(NamedTuple):
    """The loop's scratch arrays (n the system's size, nc = 3 contacts)."""

    qt: np.ndarray          # (n,) predictors q~, v~
    vt: np.ndarray
    x1: np.ndarray          # (n,) vectors multiplied by M and K
    x2: np.ndarray
    r1: np.ndarray          # (n,) their products
    r2: np.ndarray
    rhs: np.ndarray         # (n,) b_n
    y: np.ndarray           # (n,) A^-1 b_n
    q_new: np.ndarray       # (n,) q_{n+1}
    gw: np.ndarray          # (nc + 2,) [g_c; F_d; F_hold] (F_hold: a drive held in Y)
    qc: np.ndarray          # (nc,) the contact-space iterate
    yc: np.ndarray
    target: np.ndarray
    g: np.ndarray
    delta: np.ndarray
    rho: np.ndarray
    trial_state: np.ndarray  # (contacts, STATE_SIZE) the trial law states and forces
    scratch_state: np.ndarray  # (STATE_SIZE,) one node's: the contact space's, a Newton tangent's
    normal_t: np.ndarray
    force_t: np.ndarray     # (contacts, 2)
    qc_best: np.ndarray     # (nc,) the iterate with the smallest residual
    subset: np.ndarray      # (contacts,) int: the critical nodes
    jac: np.ndarray         # (3,)
    base_dx: np.ndarray     # (substeps,) the base's X increments over the friction sub-steps
    base_free: np.ndarray   # (substeps,) the free end's: eta_y dy_b (eq 30)
    base_z: np.ndarray      # (substeps,) the base's Z and Z velocity at the sub-steps' ends
    base_vz: np.ndarray
    history: History        # the contact iteration's accelerator (depth 0: none)

    @classmethod
    def allocate(cls, n: int, contacts: int, substeps: int, state_size: int,
                 depth: int) -> "Work":
        nc = 3 * contacts
        return cls(*(np.empty(n) for _ in range(9)), np.empty(nc + 2),
                   *(np.empty(nc) for _ in range(6)),
                   np.empty((contacts, state_size)), np.empty(state_size),
                   np.empty(contacts), np.empty((contacts, 2)),
                   np.empty(nc), np.empty(contacts, dtype=np.int64), np.empty(3),
                   *(np.empty(substeps) for _ in range(4)), History.allocate(nc + 1, depth))


class Operators(NamedTuple):
    """The factorized linear system as the compiled step takes it (``operators``)."""

    mass: object            # M: diagonal array (full) or dense matrix (reduced)
    stiffness: object       # K: BSR blocks (full) or dense matrix (reduced)
    inv: object             # A^-1: its factorization (model/linalg.py)
    Z: np.ndarray           # A^-1 [P d_x] (and d_y for a drive held in Y)
    G: np.ndarray           # P^T A^-1 P
    h: np.ndarray           # P^T A^-1 d_x
    e: float                # d_x^T A^-1 d_x
    h_y: np.ndarray         # P^T A^-1 d_y   (a prescribed drive, held in Y; else zeros)
    e_xy: float             # d_x^T A^-1 d_y
    e_yy: float             # d_y^T A^-1 d_y
    contact_dofs: np.ndarray
    others: np.ndarray      # the q indices that are not contact DOFs
    drive_index: np.ndarray
    drive_x: np.ndarray
    drive_y: np.ndarray
    watch_rows: np.ndarray  # the candidates left out of a reduced model's interface
    watch_rest: np.ndarray  # (interface.Watch; none: zero rows)


class BaseMotion(NamedTuple):
    """The vibrating base (eqs 23-25, 30), and along Z (base_motion.normal_displacement)."""

    amplitude: float
    omega: float
    t_on: float
    cos_theta: float
    sin_theta: float
    eta_y: float
    amplitude_n: float      # vibration.normal_amplitude (0: the base stays at z = 0)
    sin_n: float            # sin, cos of vibration.normal_phase_deg
    cos_n: float
    on_step: int            # the first step on, where the body starts on its forced
    gain: tuple             # response (normal_start.py): (Re H, Im H)
    lift: np.ndarray        # (n,) the q of every node moving by 1 in Z
    origin: np.ndarray      # (n,) zeros: q's preload (start_motion's reference)
    body_mass: float        # kg
    table: np.ndarray       # a motion given per step at the friction sub-steps
    table_from: int         # (core/base_table.py substep_table: its rows, first sub-step,
    table_period: int       # period in sub-steps, sub-steps a step, lead before t_on);
    table_per_step: int     # no rows: the sine alone
    table_lead: np.ndarray
    table_lifts: bool       # the table moves the base along Z


class Drive(NamedTuple):
    k_d: float
    v_d: float
    prescribed: bool    # drive.mode = "velocity": the attachment moves at exactly v_d


class Limits(NamedTuple):
    """What numerical trouble is measured against (outputs/trouble.py)."""

    F_N: float
    mu_max: float
    normal_limit: float     # the summed normal force's (normal_start.normal_force_limit)


def system_matrix(system: LinearSystem, model, coefficients, held):
    """A = c_M M + (1 - alpha_f) ((1 + beta c_V) K + P diag(l) P^T): dense for a
    reduced system, scipy sparse for the full one."""
    alpha_m, alpha_f, beta_n, gamma, c_m, c_v = coefficients
    dofs = system.contact_dofs.ravel()
    scale = (1.0 - alpha_f) * (1.0 + model.beta * c_v)
    if system.dense:
        A = c_m * system.mass + scale * system.stiffness
        A[dofs, dofs] += (1.0 - alpha_f) * held
        return A
    contact = np.zeros(system.size)
    contact[dofs] = (1.0 - alpha_f) * held
    return sp.diags(c_m * system.mass + contact) + scale * system.stiffness


def factorized(system: LinearSystem, model, A):
    """A's inverse as linalg.solve takes it: dense for a reduced system, the ordered
    sparse LU for the full one."""
    return inverse(A) if system.dense else factorize(A, model.elimination_order)


def contraction(G, held, alpha_f: float, departure: float) -> float:
    """The contact iteration's estimated contraction factor (the module docstring):
    (1 - alpha_f) * departure * spectral radius of diag(l)^1/2 G diag(l)^1/2 over X, Y."""
    planar = np.flatnonzero(np.tile([1.0, 1.0, 0.0], held.size // 3) * held)
    if planar.size == 0:
        return 0.0
    root = np.sqrt(held[planar])
    scaled = root[:, None] * G[np.ix_(planar, planar)] * root[None, :]
    radius = np.abs(np.linalg.eigvalsh(0.5 * (scaled + scaled.T))).max()
    return (1.0 - alpha_f) * departure * radius


# A refused step is halved up to this many times looking for one the iteration takes.
STEP_HALVINGS = 8


def working_step(scene, model, system: LinearSystem):
    """The largest time.dt / 2^k (k <= STEP_HALVINGS) whose estimated contraction is
    within MAX_ACCELERATED_CONTRACTION, or None. A shorter step lets the mass c_M M outweigh
    the contact in A, and G with it; the law's departure is taken at that step
    (LuGre's grows as its dampings act over shorter steps)."""
    dofs = system.contact_dofs.ravel()
    assumed = np.repeat((model.normal0 > 0.0).astype(float), 3)
    for k in range(1, STEP_HALVINGS + 1):
        trial = scene.with_values({"time.dt": scene.time.dt / 2 ** k})
        scheme = coefficients(trial.fem.rho_infinity, trial.time.dt)
        held = contact_tangent(model, trial, scheme.c_v) * assumed
        G = columns_of_inverse(factorized(system, model, system_matrix(system, model, scheme,
                                                                       held)), dofs)
        if (contraction(G, held, scheme.alpha_f, trial.law_bounds.departure)
                <= MAX_ACCELERATED_CONTRACTION):
            return trial.time.dt
    return None


class ImplicitRun(TimeLoop):
    """An implicit run prepared for a scene: the factorization and the contact operator.

    Raises core.errors.Refusal for a scene it cannot run; ``info``
    says what was prepared; ``integrate`` (time_loop.TimeLoop) runs it.
    """

    extra_scalars = OWN_SCALARS
    iteration_tolerance = ITERATION_TOLERANCE   # the contact iteration's, relative (contact_solve)

    def __init__(self, scene, model, system: LinearSystem, name="implicit"):
        t = scene.time
        self.scene, self.model, self.system, self.name = scene, model, system, name
        self.watch = Watch.none(system.size)   # a reduced run's left-out candidates (reduction.py)
        self.coefficients = coefficients(scene.fem.rho_infinity, t.dt)
        self.substeps = implicit_substeps(scene)
        # a base motion given per step, at the friction sub-steps (core/base_table.py)
        on_step = first_step_on(scene)
        on_substeps = self.substeps if on_step * t.dt > scene.vibration.t_on else \
            still_substeps(scene)
        self.table = substep_table(scene.vibration, scene.omega, t.dt, self.substeps,
                                   on_substeps, scene.vibration.t_on, on_step, scene.steps)
        alpha_m, alpha_f, beta_n, gamma, c_m, c_v = self.coefficients
        self.tangent = contact_tangent(model, scene, c_v)
        self.assumed = (model.normal0 > 0.0).astype(float)   # in contact at the preload
        held = self.tangent * np.repeat(self.assumed, 3)
        dofs = system.contact_dofs.ravel()

        start = time.perf_counter()
        self.inv = factorized(system, model, system_matrix(system, model, self.coefficients,
                                                           held))
        self.mass_op = system.mass
        self.stiffness_op = system.stiffness if system.dense else bsr(system.stiffness)
        # Z = A^-1 [P d_x]: the response to unit contact forces and to the drive
        # (and d_y: a prescribed drive holds its attachment in Y too).
        self.prescribed = scene.drive.prescribed
        nc = dofs.size
        loads = np.zeros((system.size, nc + (2 if self.prescribed else 1)))
        loads[dofs, np.arange(nc)] = 1.0
        loads[system.drive_index, nc] = system.drive_x
        if self.prescribed:
            loads[system.drive_index, nc + 1] = system.drive_y
        self.Z = np.empty_like(loads)
        for k in range(loads.shape[1]):
            solve(self.inv, loads[:, k], self.Z[:, k])
        self.G = np.ascontiguousarray(self.Z[dofs, :nc])
        self.G = 0.5 * (self.G + self.G.T)
        self.h = np.ascontiguousarray(self.Z[dofs, nc])
        self.e = float(system.drive_x @ self.Z[system.drive_index, nc])
        self.h_y, self.e_xy, self.e_yy = np.zeros(nc), 0.0, 1.0
        if self.prescribed:
            self.h_y = np.ascontiguousarray(self.Z[dofs, nc + 1])
            self.e_xy = float(system.drive_x @ self.Z[system.drive_index, nc + 1])
            self.e_yy = float(system.drive_y @ self.Z[system.drive_index, nc + 1])
        self.Z = np.ascontiguousarray(self.Z)
        self.factor_time = time.perf_counter() - start
        self.contraction = contraction(self.G, held, alpha_f, scene.law_bounds.departure)
        # beyond the plain iteration's reach, Anderson's (contact_solve.iterate_contact)
        self.accelerated = bool(self.contraction > MAX_CONTRACTION)
        if self.contraction > MAX_ACCELERATED_CONTRACTION:
            working = working_step(scene, model, system)
            advice = (f"use time.dt <= {working:.3g} s" if working is not None
                      else "use a much smaller time.dt")
            raise StepTooLong(f"time step {t.dt:g} s is too long for the {name} integrator's "
                              f"contact iteration (estimated contraction "
                              f"{self.contraction:.2f} > {MAX_ACCELERATED_CONTRACTION}: the "
                              "friction law "
                              "departs from the tangent k_t w_i that the matrix holds, most "
                              "for a contact as stiff as the block or for LuGre's dampings "
                              "over a long step): " + advice)

    @property
    def cost_per_step(self) -> float:
        """ns a step, roughly (COST)."""
        s = self.system
        entries = s.size ** 2 if s.dense else self.inv.entries
        return step_cost(s, entries, self.G.shape[0] // 3, self.substeps)

    @property
    def info(self) -> dict:
        alpha_m, alpha_f, beta_n, gamma, _, _ = self.coefficients
        return {"rho_infinity": self.scene.fem.rho_infinity, "alpha_m": alpha_m, "alpha_f": alpha_f,
                "system_size": self.system.size,
                "factor_entries": self.system.size ** 2 if self.system.dense else self.inv.entries,
                "factor_time_s": self.factor_time,
                "friction_substeps": self.substeps,
                "slip_per_step": slip_per_step(self.scene),
                "contraction_bound": self.contraction,
                "contact_accelerated": self.accelerated}

    @property
    def hint(self) -> str:
        return f"try a smaller time.dt (the {self.name} integrator)"

    def start(self, contact, scalars, recorder, steady) -> Started:
        scene, model, system = self.scene, self.model, self.system
        c, dt = scene.contact, scene.time.dt
        cos_theta, sin_theta = vibration_axis(scene.vibration.theta_deg)
        n, contacts = system.size, model.contact_nodes.size
        nc = 3 * contacts
        law = scene.friction
        params = law.params
        use_energy = scene.fem.energy

        q, v, a = np.zeros(n), np.zeros(n), np.zeros(n)
        u0c = model.u0.reshape(-1, 3)[model.contact_nodes].copy()
        g_prev = np.zeros(nc + 2)   # g at the preload: q = 0, f_c = (0, 0, N0), F_d = 0
        g_prev[2:nc:3] = model.normal0
        sums = np.zeros(SUMS)
        work = Work.allocate(n, contacts, self.substeps, law.law.state_size,
                             DEPTH if self.accelerated else 0)

        others = np.setdiff1d(np.arange(n), system.contact_dofs.ravel())
        operators = Operators(self.mass_op, self.stiffness_op, self.inv, self.Z, self.G, self.h,
                              self.e, self.h_y, self.e_xy, self.e_yy, system.contact_dofs, others,
                              system.drive_index, system.drive_x, system.drive_y,
                              *self.watch)
        nodes = ContactData(u0c, model.normal0, model.penalty_share, model.area_share,
                            model.nominal_normal, model.initial_gap, self.tangent, self.assumed)
        lift = np.ascontiguousarray(system.rigid(np.tile([0.0, 0.0, 1.0], model.dofs // 3)))
        vib, on_step, motion = scene.vibration, first_step_on(scene), self.table
        base = BaseMotion(scene.u0, scene.omega, vib.t_on, cos_theta, sin_theta,
                          c.eta_y, vib.normal_amplitude, *normal_phase(vib.normal_phase_deg),
                          on_step, start_gain(scene, model), lift, np.zeros_like(lift),
                          model.block_mass, motion.table.rows, motion.table.first_step,
                          motion.table.period, motion.per_step, motion.lead,
                          table_moves_along_z(vib))
        scheme = Scheme(dt, *self.coefficients, model.beta,
                        self.iteration_tolerance * c.F_N / scene.law_bounds.stiffness, MAX_ITERATIONS,
                        still_substeps(scene))
        drive = Drive(scene.drive.k_d, scene.drive.v_d, self.prescribed)
        limits = Limits(c.F_N, scene.mu_max, normal_force_limit(scene, model))

        def arguments(first, last):
            return (first, last, operators, nodes, params, base, drive, scheme, limits,
                    use_energy, q, v, a, contact.state, contact.normal, contact.friction,
                    g_prev, scalars, sums, recorder.arrays, steady.arrays, work)

        kernel = implicit_steps.prepared(law.law, arguments(1, 0), f"the {self.name} FE loop",
                                         direct=True)

        def steps(first, last):
            return kernel(*arguments(first, last))

        held = self.tangent * np.repeat(self.assumed, 3)

        def rigid(motion):
            # q moves by the motion's q; g = f_c + l q_c (contact_solve._contact_g) by l q_c
            # on the X and Y rows of the nodes A holds (a motion in the plane: Z and the
            # forces stay)
            moved = system.rigid(motion)
            shift = np.zeros_like(g_prev)
            planar = np.tile([1.0, 1.0, 0.0], contacts)
            shift[:nc] = held * planar * moved[system.contact_dofs.ravel()]
            return {"q": moved, "v": np.zeros(n), "a": np.zeros(n), "g_prev": shift}

        return Started(steps, lambda: (model.u0 + system.expand(q), system.expand(v)),
                       {"q": q, "v": v, "a": a, "g_prev": g_prev}, rigid)

    def table_row_at(self, i: int) -> np.ndarray:
        """The row of the base motion given per step read at the end of step i: the table
        at the friction sub-steps, its sub-step index i m."""
        if not self.scene.vibration.sampled:
            return np.zeros(len(TABLE_COLUMNS))
        table = self.table.table
        k = table_row(table.rows, table.first_step, table.period, i * self.table.per_step)
        return table.rows[k].copy() if k >= 0 else np.zeros(len(TABLE_COLUMNS))

    def stats(self, scalars, last: int) -> dict:
        return {"iterations_max": int(scalars[ITER_MAX]),
                "iterations_mean": scalars[ITER_SUM] / max(last, 1),
                "iterations_stalled": int(scalars[ITER_STALLED])}


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def face_height_q(q, contact_dofs, area_share):
    """The contact face's mean height from the preload, sum_i w_i q_z,i (its nodes' q are
    their displacements, full and reduced alike)."""
    z = 0.0
    for c in range(contact_dofs.shape[0]):
        z += area_share[c] * q[contact_dofs[c, 2]]
    return z


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def new_displacements(y, g, target, f_d, f_hold, operators, alpha_f, g_prev, gw, q_new):
    """q_{n+1} = y + (1 - alpha_f) Z [g_c; F_d] with the converged iteration's g: on the
    contact DOFs that is its target, the other rows take Z. g_prev keeps [g_c; F_d; F_hold]
    for the next step's first iterate."""
    Z, contact_dofs, others = operators.Z, operators.contact_dofs, operators.others
    nc = g.shape[0]
    drives = Z.shape[1] - nc   # 1, or 2 for a drive held in Y
    af1 = 1.0 - alpha_f
    for p in range(nc):
        gw[p] = g[p]
        g_prev[p] = g[p]
        q_new[contact_dofs[p // 3, p % 3]] = target[p]
    gw[nc] = f_d
    g_prev[nc] = f_d
    gw[nc + 1] = g_prev[nc + 1] = f_hold
    for r in range(others.shape[0]):
        k = others[r]
        s = 0.0
        for p in range(nc + drives):
            s += Z[k, p] * gw[p]
        q_new[k] = y[k] + af1 * s


@law_kernel(cache=True, error_model="numpy", fastmath=FASTMATH)
def implicit_steps(first, last, operators, contact, params, base, drive, scheme, limits, use_energy,
                   q, v, a, states, normal, friction, g_prev, scalars, sums,
                   recorder, steady, work):
    """Advance steps ``first`` .. ``last``. Returns (failed step, code, stop step):
    (0, OK, 0) if all ran, (0, OK, i) if the run settled at step i (outputs/steady.py).

    Each step: the linear response y = A^-1 b_n (generalized_alpha.free_response),
    the base (eqs 23-25) and its friction sub-steps, the contact iteration
    (contact_solve.iterate_contact: the only part that calls the friction law,
    with the energy's contact work and stored energy), q_{n+1} and the Newmark
    update, the recorded row.
    """
    # The caller holds every array through the call: the loop uses them without
    # reference counts (borrowed.py).
    (operators, contact, params, work, q, v, a, states, normal, friction, g_prev, scalars, sums,
     recorder) = borrowed((operators, contact, params, work, q, v, a, states, normal, friction,
                           g_prev, scalars, sums, recorder))
    amplitude, omega, t_on, cos_theta, sin_theta, eta_y = base[:6]
    amplitude_n, sin_n, cos_n, on_step, gain, lift, origin, body_mass = base[6:14]
    table, table_from, table_period, table_per_step, lead = base[14:19]
    has_table = table.shape[0] > 0
    lifts_off = amplitude_n > 0.0 or base.table_lifts
    k_d, v_d, prescribed = drive
    spring = math.inf if prescribed else k_d   # the drive spring's stiffness (energy)
    dt, alpha_f, beta_n, gamma, beta = scheme.dt, scheme.alpha_f, scheme.beta_n, scheme.gamma, scheme.beta
    F_N, mu_max, normal_limit = limits
    row = recorder[0]
    xb, yb, zb = scalars[XB], scalars[YB], scalars[ZB]
    sin_phase, cos_phase = scalars[SIN], scalars[COS]
    f_d_old = scalars[F_D]
    f_hold_old = scalars[F_HOLD]
    cos_step, sin_step = math.cos(omega * dt), math.sin(omega * dt)
    stop = 0
    for i in range(first, last + 1):
        t = i * dt
        if i == on_step and lifts_off:
            # the state at t_n, a step before the first step on: onto the body's forced
            # response to the base's sinusoid there (normal_start.py), its contact
            # forces afresh; the base moves along it from t_n (normal_over_substeps)
            z_lead = lead[0, 0] if has_table else 0.0    # the table's z_b, dz_b/dt there
            vz_lead = lead[0, 1] if has_table else 0.0
            start_motion(q, origin, v, lift, operators.contact_dofs[:, 2], contact.area_share,
                         gain, t - dt, dt, t_on, amplitude_n, omega, sin_n, cos_n, 0.0, z_lead,
                         vz_lead)
            phase = omega * (t - dt - t_on)
            z_on, vz_on = normal_displacement(amplitude_n, omega, sin_n, cos_n, math.sin(phase),
                                              math.cos(phase))
            if has_table:
                z_on += z_lead
                vz_on += vz_lead
            change = restart_normal_forces(q, v, operators.contact_dofs, contact.u0c[:, 2],
                                           contact.initial_gap, contact.penalty_share, beta,
                                           z_on, vz_on, contact.tangent, contact.assumed,
                                           normal, g_prev)
            for k in range(a.shape[0]):      # the rigid body's acceleration by the change
                a[k] += lift[k] * change / body_mass
            zb = z_on
        free_response(q, v, a, friction, normal, f_d_old, f_hold_old, operators, contact.normal0,
                      scheme, prescribed, work)

        # Base at t_{n+1} (eqs 23-25), and over the friction sub-steps: fewer while it
        # has not started (contact_solve.still_substeps).
        u_base, sin_phase, cos_phase = base_displacement(i, dt, omega, t_on, amplitude, sin_phase,
                                                         cos_phase, cos_step, sin_step)
        xb_new, yb_new = u_base * cos_theta, u_base * sin_theta
        m = work.base_dx.shape[0] if t > t_on else scheme.still_substeps
        base_over_substeps(t, dt, u_base, amplitude, omega, t_on, cos_theta, sin_theta, eta_y,
                           work.base_dx[:m], work.base_free[:m])
        normal_over_substeps(t, dt, amplitude_n, omega, t_on, (on_step - 1) * dt, sin_n, cos_n,
                             work.base_z[:m], work.base_vz[:m])
        if has_table:   # the motion given per step (core/base_table.py), added
            x_table, y_table = table_over_substeps(
                i, on_step, table, table_from, table_period, table_per_step, lead, eta_y,
                work.base_dx[:m], work.base_free[:m], work.base_z[:m], work.base_vz[:m])
            xb_new += x_table
            yb_new += y_table
        dx_b, dy_b = xb_new - xb, yb_new - yb
        step = StepStart(q, v, work.vt, work.qt, work.base_dx[:m], work.base_free[:m],
                         work.base_z[:m], work.base_vz[:m])
        zb_new = work.base_z[m - 1]

        outcome, iterations, f_d, f_hold, f_n, f_x, f_y = iterate_contact(
            t, step, operators, contact, params, drive, scheme, mu_max, states, g_prev, work)
        if outcome == NOT_CONVERGED:
            return i, trouble.NOT_CONVERGED, 0
        if outcome == STALLED:
            scalars[ITER_STALLED] += 1
        scalars[ITER_MAX] = max(scalars[ITER_MAX], iterations)
        scalars[ITER_SUM] += iterations

        new_displacements(work.y, work.g, work.target, f_d, f_hold, operators, alpha_f, g_prev,
                          work.gw, work.q_new)
        if use_energy:
            add_damping_and_drive_work(q, work.q_new, operators.stiffness, beta, dt, t, f_d,
                                       f_d_old, alpha_f, v_d, prescribed, work.x1, work.r1, sums)
            add_contact_work(q, work.q_new, operators.contact_dofs, contact.penalty_share,
                             contact.area_share, params, states, work.trial_state, friction,
                             work.force_t, normal, work.normal_t, alpha_f, dx_b, eta_y * dy_b,
                             zb, zb_new, beta, dt, sums)
        newmark_update(q, v, a, work.q_new, work.qt, work.vt, beta_n, gamma, dt)
        magnitude = commit_contact(states, normal, friction, work)
        xb, yb = xb_new, yb_new
        zb = zb_new
        if watched_contact(q, operators.watch_rows, operators.watch_rest, zb):
            return i, trouble.BEYOND_INTERFACE, 0
        f_d_old = f_d
        f_hold_old = f_hold

        x_out, y_out = attachment_xy(q, operators.drive_index, operators.drive_x,
                                     operators.drive_y)
        if not prescribed:
            f_d = k_d * (v_d * t - x_out)  # eq 17; prescribed: the iteration's reaction
        code = finish_step(t, t_on, f_d, f_n, f_x, f_y, x_out, y_out, xb, yb, magnitude, F_N,
                           mu_max, normal_limit, lifts_off, scalars, row)
        if code != trouble.OK:
            return i, code, 0
        if use_energy:
            apply(operators.mass, v, work.r1)
            apply(operators.stiffness, q, work.r2)
            kinetic, elastic = energy_stored(q, v, work.r1, work.r2, operators.contact_dofs,
                                             contact.u0c[:, 2], contact.initial_gap, zb,
                                             contact.normal0, contact.penalty_share,
                                             contact.area_share, params, states, f_d, spring)
            record_energy(row, sums, kinetic, elastic)
        if lifts_off:
            record_normal(row, face_height_q(q, operators.contact_dofs, contact.area_share),
                          zb, f_n)
        if keep_step(i, f_d, recorder, steady):
            stop = i
            break

    scalars[XB], scalars[YB], scalars[ZB] = xb, yb, zb
    scalars[SIN], scalars[COS] = sin_phase, cos_phase
    scalars[F_D] = f_d_old
    scalars[F_HOLD] = f_hold_old
    return 0, trouble.OK, stop
