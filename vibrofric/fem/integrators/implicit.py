"""Implicit time integration: generalized-alpha with the linear operator factorized once.

Coordinates. u = u0 + T q, u0 the static preload (model/preload.py). The full model
has T = I; the reduced one (reduction.py) a Craig-Bampton basis. In both, each
contact node's X, Y, Z displacement is a coordinate of its own (``contact_dofs``;
P picks them out of q), and the drive's attachment is x_A = d_x^T q (model/drive.py).
The equation of motion is

    M q'' + C q' + K q = P f_c - P_z N0 + d_x F_d,        C = beta K

with f_c = (-F_x, -F_y, N) per contact node (model/contact.py: the friction law and
the penalty spring with its dashpot), N0 the preload's reactions (the dead
loads less K u0), F_d = k_d (v_d t - x_A) (eq 17) and the model's Rayleigh
damping beta (model/stability.py), as in explicit.py.

Generalized-alpha (Chung & Hulbert, J. Appl. Mech. 60, 1993), with the
spectral radius rho_inf at infinite frequency (scene fem.rho_infinity):

    alpha_m = (2 rho_inf - 1) / (rho_inf + 1),   alpha_f = rho_inf / (rho_inf + 1)
    gamma = 1/2 - alpha_m + alpha_f,             beta_N = (1 - alpha_m + alpha_f)^2 / 4
    q_{n+1} = q_n + dt v_n + dt^2 ((1/2 - beta_N) a_n + beta_N a_{n+1})
    v_{n+1} = v_n + dt ((1 - gamma) a_n + gamma a_{n+1})
    M a_{n+1-alpha_m} + C v_{n+1-alpha_f} + K q_{n+1-alpha_f} = r_{n+1-alpha_f}

(x_{n+1-alpha} = (1 - alpha) x_{n+1} + alpha x_n). rho_inf = 1 is the trapezoidal
rule (Newmark average acceleration): second order, unconditionally stable for
linear systems, no numerical damping; rho_inf < 1 damps the modes above 1 / dt
(the mesh's and the penalty springs', which the scene does not need), keeping
second order. The default, 0.9, is there because the contact is nonlinear: a
penalty spring switching on and off pumps energy into the undamped modes
above 1 / dt. With rho_inf = 1 a thin, 100x stiffer block (30 x 40 x 5 mm,
transverse scene) lost contact after 64 ms of plain dragging at dt = 1e-5 s,
and sooner at 5e-6 s; with 0.9 its normal force stays within 50.799-50.801 N.
On the Fig 7 scene 0.9 moves F_dv/F_d0 by -0.18% against 1 (explicit at 1e-6 s
lies between), on the k_v = 20 transverse scene by -0.003%.

One step. Everything linear is one matrix, factorized once per run:

    A = c_M M + (1 - alpha_f) ((1 + beta c_V) K + P diag(l) P^T),
    c_M = (1 - alpha_m) / (beta_N dt^2),   c_V = gamma / (beta_N dt)

where l is the contact forces' tangent per contact DOF: k_t w_i in X and Y
(the Dahl law's stiffness at rest, the middle of its range [0, 2 k_t w_i]) and
k_pen w_i (1 + beta c_V) in Z (the penalty spring and its dashpot) for the
nodes in contact at the preload. Then

    A q_{n+1} = b_n + (1 - alpha_f) g,      g = P (f_c + l q_c) + d_x F_d

with b_n known from step n, and g the part the matrix does not hold: the
friction law's departure from its tangent, the drive. g depends on q_{n+1}
only through q_c and x_A. With y = A^-1 b_n and Z = A^-1 [P d_x] (computed once):

    q_c = y_c + (1 - alpha_f) (G g_c + h F_d),     G = P^T A^-1 P,  h = P^T A^-1 d_x
    x_A = y_A + (1 - alpha_f) (h^T g_c + e F_d),   e = d_x^T A^-1 d_x

a fixed point in 3 x contacts + 1 unknowns, iterated to ITERATION_TOLERANCE
(each iteration: the friction law on every node, one product with G); then
q_{n+1} = y + (1 - alpha_f) Z [g_c; F_d] (on the contact DOFs that is the
iteration's last q_c). Per step: one solve with A, two products (M, K), the
non-contact rows of Z, and the iterations.

The friction law inside the step. f_c(q_c) is each node's contact over the
step from q_n to the trial q_{n+1}: the VFRIC analogue (contact.node_contact,
the same per-node update as explicit.py) run on implicit_substeps(scene)
sub-steps, at least SUBSTEPS_PER_CYCLE a vibration cycle (before the base
starts, still_substeps: enough for the drive's slide), with the base on
its exact sinusoid (eq 23) and the node at its mean velocity over the step.
At dt = 1e-5 s, 25 steps a cycle, one piece would miss the base's curved
path by ~1% of F_dv; four sub-steps bring it within 0.2%.

Why this is stable and converges at any dt. The matrix holds the mass, the
block, the penalty springs and the contact's own tangent: what stays in g is
the friction law's departure from k_t w_i, at most k_t w_i per node (Dahl:
dF/d(slip) lies in [0, 2 k_t w_i]), and the drive spring k_d. The iteration
contracts by (1 - alpha_f) ||G diag(departure)||: below (1 - alpha_f) k_t w_i
G_ii <= 1 - alpha_f ~ 1/2 node by node (G_ii <= 1 / l_i), and for the whole
face together k_t / (k_t + c_M m) ~ 0.004 at dt = 1e-5 s (the rigid block's
2 kHz mode on k_t, which explicit friction would have to resolve). Nothing is
lagged: the step is implicit in the friction force too, so the penalty does
not limit dt, and no tuning is needed. The bound grows where the contact
is as stiff as the block (G_ii l_i -> 1 on the face: 0.60 at k_t x 100 and
1e-5 s) or LuGre's dampings act over a long step; ImplicitRun refuses a
step whose bound exceeds MAX_CONTRACTION, naming the halved step
(working_step) at which it does not.

The parts: generalized_alpha.py (coefficients, the linear system, the
contact tangent), contact_solve.py (the contact forces at a trial state and
the iteration), step_cost.py (for "auto"), outputs/energy.py (the balance); here, the
prepared run and its compiled step.

Where that bound does not hold: nodes near lift-off. The block rocks on its
face every cycle (friction at z = 0, inertia at mid-height): the corner
nodes' normal forces swing between 0 and twice their share even in the
explicit run. A node that lifts off loses its penalty spring and its
friction; one whose normal force is small has a tiny Coulomb limit, a
saturated friction force and a strong pull of N on F (mu dN/dq_z). Those
critical nodes get a Newton step with their own 3x3 tangents
(newton_correction), halved when it does not lower the residual; should the
Newton steps still alternate across a node's contact kink, the plain fixed
point takes over, and the step is accepted at its best iterate within a
looser tolerance (STALL_FACTOR) or refused as not converged.
"""

import math
import time
from typing import NamedTuple

import numpy as np
import scipy.sparse as sp

from ...core.base_motion import base_displacement, vibration_axis
from ...core.errors import StepTooLong
from ...core.law_limits import slip_per_step
from ...friction_law import law_kernel
from ...friction_law.contract import FASTMATH
from ..outputs import energy, recording, trouble
from .borrowed import borrowed
from .contact_solve import (FALLBACK_ITERATIONS, ITERATION_TOLERANCE, MAX_CONTRACTION,
                            MAX_ITERATIONS, MIN_STEP, STALL_FACTOR, ContactData, StepStart,
                            contact_residual, implicit_substeps, newton_correction,
                            still_substeps)
from ..model.drive import prescribed_position
from ..outputs.energy import add_contact_work, stored as energy_stored
from .generalized_alpha import LinearSystem, Scheme, coefficients, contact_tangent
from ..model.linalg import apply, bsr, columns_of_inverse, factorize, inverse, solve
from ..outputs.recording import COS, SIN, XB, YB, finish_step, keep_step
from .step_cost import step_cost
from .time_loop import Started, TimeLoop

# scalars[]: the loop's carried scalar state, after recording's
F_D, ITER_MAX, ITER_SUM, STALLED, F_HOLD = range(8, 13)


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

    @classmethod
    def allocate(cls, n: int, contacts: int, substeps: int, state_size: int) -> "Work":
        nc = 3 * contacts
        return cls(*(np.empty(n) for _ in range(9)), np.empty(nc + 2),
                   *(np.empty(nc) for _ in range(6)),
                   np.empty((contacts, state_size)), np.empty(state_size),
                   np.empty(contacts), np.empty((contacts, 2)),
                   np.empty(nc), np.empty(contacts, dtype=np.int64), np.empty(3),
                   np.empty(substeps), np.empty(substeps))


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


class BaseMotion(NamedTuple):
    """The vibrating base (eqs 23-25, 30)."""

    amplitude: float
    omega: float
    t_on: float
    cos_theta: float
    sin_theta: float
    eta_y: float


class Drive(NamedTuple):
    k_d: float
    v_d: float
    prescribed: bool    # drive.mode = "velocity": the attachment moves at exactly v_d


class Limits(NamedTuple):
    """What numerical trouble is measured against (outputs/trouble.py)."""

    F_N: float
    mu_max: float


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
    within MAX_CONTRACTION, or None. A shorter step lets the mass c_M M outweigh
    the contact in A, and G with it; the law's departure is taken at that step
    (LuGre's grows as its dampings act over shorter steps)."""
    dofs = system.contact_dofs.ravel()
    assumed = np.repeat((model.normal0 > 0.0).astype(float), 3)
    for k in range(1, STEP_HALVINGS + 1):
        trial = scene.with_values({"time.dt": scene.time.dt / 2 ** k})
        scheme = coefficients(trial.fem.rho_infinity, trial.time.dt)
        held = contact_tangent(model, trial, scheme[5]) * assumed
        G = columns_of_inverse(factorized(system, model, system_matrix(system, model, scheme,
                                                                       held)), dofs)
        if contraction(G, held, scheme[1], trial.law_bounds.departure) <= MAX_CONTRACTION:
            return trial.time.dt
    return None


class ImplicitRun(TimeLoop):
    """An implicit run prepared for a scene: the factorization and the contact operator.

    Raises core.errors.Refusal for a scene it cannot run; ``info``
    says what was prepared; ``integrate`` (time_loop.TimeLoop) runs it.
    """

    extra_scalars = 5  # F_D, ITER_MAX, ITER_SUM, STALLED, F_HOLD
    iteration_tolerance = ITERATION_TOLERANCE   # the contact iteration's, relative (contact_solve)

    def __init__(self, scene, model, system: LinearSystem, name="implicit"):
        t = scene.time
        self.scene, self.model, self.system, self.name = scene, model, system, name
        self.coefficients = coefficients(scene.fem.rho_infinity, t.dt)
        self.substeps = implicit_substeps(scene)
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
        if self.contraction > MAX_CONTRACTION:
            working = working_step(scene, model, system)
            advice = (f"use time.dt <= {working:.3g} s" if working is not None
                      else "use a much smaller time.dt")
            raise StepTooLong(f"time step {t.dt:g} s is too long for the {name} integrator's "
                              f"contact iteration (estimated contraction "
                              f"{self.contraction:.2f} > {MAX_CONTRACTION}: the friction law "
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
                "contraction_bound": self.contraction}

    @property
    def hint(self) -> str:
        return f"try a smaller time.dt (the {self.name} integrator)"

    def start(self, contact, scalars, recorder, steady) -> Started:
        scene, model, system = self.scene, self.model, self.system
        c, dt = scene.contact, scene.time.dt
        alpha_m, alpha_f, beta_n, gamma, c_m, c_v = self.coefficients
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
        sums = np.zeros(4)
        work = Work.allocate(n, contacts, self.substeps, law.law.state_size)

        others = np.setdiff1d(np.arange(n), system.contact_dofs.ravel())
        operators = Operators(self.mass_op, self.stiffness_op, self.inv, self.Z, self.G, self.h,
                              self.e, self.h_y, self.e_xy, self.e_yy, system.contact_dofs, others,
                              system.drive_index, system.drive_x, system.drive_y)
        nodes = ContactData(u0c, model.normal0, model.penalty_share, model.area_share,
                            self.tangent, self.assumed)
        base = BaseMotion(scene.u0, scene.omega, scene.vibration.t_on, cos_theta, sin_theta, c.eta_y)
        scheme = Scheme(dt, alpha_m, alpha_f, beta_n, gamma, c_m, c_v, model.beta,
                        self.iteration_tolerance * c.F_N / scene.law_bounds.stiffness, MAX_ITERATIONS,
                        still_substeps(scene))
        drive = Drive(scene.drive.k_d, scene.drive.v_d, self.prescribed)
        limits = Limits(c.F_N, scene.mu_max)

        def arguments(first, last):
            return (first, last, operators, nodes, params, base, drive, scheme, limits,
                    use_energy, q, v, a, contact.state, contact.normal, contact.friction,
                    g_prev, scalars, sums, recorder.arrays, steady.arrays, work)

        kernel = implicit_steps.prepared(law.law, arguments(1, 0), f"the {self.name} FE loop")

        def steps(first, last):
            return kernel(*arguments(first, last))

        tangent = self.tangent

        def rigid(motion):
            # q moves by the motion's q; g = f_c + l q_c (contact_solve._contact_g) by l q_c
            # on the X and Y rows (a motion in the plane: Z and the forces stay)
            moved = system.rigid(motion)
            shift = np.zeros_like(g_prev)
            planar = np.tile([1.0, 1.0, 0.0], contacts)
            shift[:nc] = tangent * planar * moved[system.contact_dofs.ravel()]
            return {"q": moved, "v": np.zeros(n), "a": np.zeros(n), "g_prev": shift}

        return Started(steps, lambda: (model.u0 + system.expand(q), system.expand(v)),
                       {"q": q, "v": v, "a": a, "g_prev": g_prev}, rigid)

    def stats(self, scalars, last: int) -> dict:
        return {"iterations_max": int(scalars[ITER_MAX]),
                "iterations_mean": scalars[ITER_SUM] / max(last, 1),
                "iterations_stalled": int(scalars[STALLED])}


@law_kernel(cache=True, error_model="numpy", fastmath=FASTMATH)
def implicit_steps(first, last, operators, contact, params, base, drive, scheme, limits, use_energy,
                   q, v, a, states, normal, friction, g_prev, scalars, sums,
                   recorder, steady, work):
    """Advance steps ``first`` .. ``last``. Returns (failed step, code, stop step):
    (0, OK, 0) if all ran, (0, OK, i) if the run settled at step i (outputs/steady.py)."""
    # The caller holds every array through the call: the loop uses them without
    # reference counts (borrowed.py).
    (operators, contact, params, work, q, v, a, states, normal, friction, g_prev, scalars, sums,
     recorder) = borrowed((operators, contact, params, work, q, v, a, states, normal, friction,
                           g_prev, scalars, sums, recorder))
    (mass, stiffness, inv, Z, G, h, e, h_y, e_xy, e_yy, contact_dofs, others, drive_index,
     drive_x, drive_y) = operators
    drives = Z.shape[1] - 3 * contact_dofs.shape[0]   # 1, or 2 for a drive held in Y
    u0c, normal0, penalty_share, area_share, tangent, assumed = contact
    amplitude, omega, t_on, cos_theta, sin_theta, eta_y = base
    k_d, v_d, prescribed = drive
    spring = math.inf if prescribed else k_d   # the drive spring's stiffness (energy)
    dt, alpha_m, alpha_f, beta_n, gamma, c_m, c_v, beta, tolerance, max_iterations, still = scheme
    stall_tolerance = tolerance * STALL_FACTOR
    F_N, mu_max = limits
    qt, vt, x1, x2, r1, r2, rhs, y, q_new = (work.qt, work.vt, work.x1, work.x2, work.r1,
                                             work.r2, work.rhs, work.y, work.q_new)
    gw, qc, yc, target, g, delta, rho, qc_best = (work.gw, work.qc, work.yc, work.target,
                                                  work.g, work.delta, work.rho, work.qc_best)
    trial_state = work.trial_state
    normal_t, force_t = work.normal_t, work.force_t
    base_dx, base_free = work.base_dx, work.base_free
    n = q.shape[0]
    nc = qc.shape[0]
    af1 = 1.0 - alpha_f
    row = recorder[0]
    xb, yb = scalars[XB], scalars[YB]
    sin_phase, cos_phase = scalars[SIN], scalars[COS]
    f_d_old = scalars[F_D]
    f_hold_old = scalars[F_HOLD]
    cos_step, sin_step = math.cos(omega * dt), math.sin(omega * dt)
    stop = 0
    for i in range(first, last + 1):
        t = i * dt
        # Predictors: q_{n+1} = qt + beta_N dt^2 a_{n+1},  v_{n+1} = vt + gamma dt a_{n+1}.
        for k in range(n):
            qt[k] = q[k] + dt * v[k] + dt * dt * (0.5 - beta_n) * a[k]
            vt[k] = v[k] + dt * (1.0 - gamma) * a[k]
            x1[k] = c_m * qt[k] - alpha_m * a[k]
            x2[k] = beta * ((1.0 - alpha_f) * (vt[k] - c_v * qt[k]) + alpha_f * v[k]) + alpha_f * q[k]
        # b_n = M (c_M qt - alpha_m a_n) - K (beta ((1-af)(vt - c_V qt) + af v_n) + af q_n)
        #       + alpha_f r_n - P_z N0
        apply(mass, x1, r1)
        apply(stiffness, x2, r2)
        for k in range(n):
            rhs[k] = r1[k] - r2[k]
        for c in range(contact_dofs.shape[0]):
            rhs[contact_dofs[c, 0]] -= alpha_f * friction[c, 0]
            rhs[contact_dofs[c, 1]] -= alpha_f * friction[c, 1]
            rhs[contact_dofs[c, 2]] += alpha_f * normal[c] - normal0[c]
        for k in range(drive_index.shape[0]):
            rhs[drive_index[k]] += alpha_f * drive_x[k] * f_d_old
        if prescribed:
            for k in range(drive_index.shape[0]):
                rhs[drive_index[k]] += alpha_f * drive_y[k] * f_hold_old
        solve(inv, rhs, y)

        # Base at t_{n+1} (eqs 23-25).
        u_base, sin_phase, cos_phase = base_displacement(i, dt, omega, t_on, amplitude, sin_phase,
                                                         cos_phase, cos_step, sin_step)
        xb_new, yb_new = u_base * cos_theta, u_base * sin_theta
        dx_b, dy_b = xb_new - xb, yb_new - yb
        # The base over the friction sub-steps (eq 23): its exact sinusoid, ending at u_base;
        # fewer sub-steps while it has not started (contact_solve.still_substeps).
        m = base_dx.shape[0] if t > t_on else still
        u_prev = amplitude * math.sin(omega * (t - dt - t_on)) if t - dt >= t_on else 0.0
        for j in range(m):
            t_j = t - dt + (j + 1) * dt / m
            u_j = u_base if j == m - 1 else (
                amplitude * math.sin(omega * (t_j - t_on)) if t_j >= t_on else 0.0)
            base_dx[j] = (u_j - u_prev) * cos_theta
            base_free[j] = eta_y * (u_j - u_prev) * sin_theta  # phase 2: eta_y dy_b (eq 30)
            u_prev = u_j
        step = StepStart(q, v, vt, qt, base_dx[:m], base_free[:m])

        # The contact-space fixed point, from the last step's g.
        y_a = y_a_y = 0.0
        for k in range(drive_index.shape[0]):
            y_a += drive_x[k] * y[drive_index[k]]
            y_a_y += drive_y[k] * y[drive_index[k]]
        drive_now = (y_a_y, h_y, e_xy, e_yy)
        apply(G, g_prev[:nc], target)
        for p in range(nc):
            yc[p] = y[contact_dofs[p // 3, p % 3]]
            qc[p] = yc[p] + af1 * (target[p] + h[p] * g_prev[nc])
        hg = 0.0
        for p in range(nc):
            hg += h[p] * g_prev[p]
        x_a = x_a_best = y_a + af1 * (hg + e * g_prev[nc])
        converged = False
        iterations = 0
        residual_old = best = np.inf
        factor = 1.0
        while iterations < max_iterations + FALLBACK_ITERATIONS:
            iterations += 1
            newton = iterations <= max_iterations
            f_d, f_hold, f_n, f_x, f_y, residual, x_a_new = contact_residual(
                qc, x_a, y_a, t, step, G, h, e, af1, contact_dofs, contact, params, drive,
                drive_now, scheme, states, work)
            if residual < best:
                best = residual
                qc_best[:] = qc
                x_a_best = x_a
            if newton and residual >= residual_old and factor > MIN_STEP:
                # No progress (a Newton step across a contact kink): halve it.
                factor *= 0.5
                for p in range(nc):
                    qc[p] -= factor * delta[p]
                continue
            if newton:
                newton_correction(rho, delta, qc, step, G, contact_dofs, contact, params, scheme,
                                  mu_max, states, work)
            else:
                for p in range(nc):
                    delta[p] = -rho[p]
            change = abs(x_a_new - x_a)
            for p in range(nc):
                change = max(change, abs(delta[p]))
                qc[p] += delta[p]
            x_a = x_a_new
            residual_old = residual
            factor = 1.0
            if change <= tolerance:
                converged = True
                break
        if not converged:
            if best > stall_tolerance:
                return i, trouble.NOT_CONVERGED, 0
            # Stalled on a node's contact kink, within the looser tolerance: take the best iterate.
            scalars[STALLED] += 1
            qc[:] = qc_best
            x_a = x_a_best
            f_d, f_hold, f_n, f_x, f_y, residual, x_a_new = contact_residual(
                qc, x_a, y_a, t, step, G, h, e, af1, contact_dofs, contact, params, drive,
                drive_now, scheme, states, work)
        scalars[ITER_MAX] = max(scalars[ITER_MAX], iterations)
        scalars[ITER_SUM] += iterations

        # q_{n+1} = y + (1 - alpha_f) Z [g_c; F_d] (with g from the last evaluation): on the
        # contact DOFs that is the last iteration's target; the other rows take Z.
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
        if use_energy:
            # Rayleigh: beta dq^T K dq / dt (r1 = K dq).
            for k in range(n):
                x1[k] = q_new[k] - q[k]
            apply(stiffness, x1, r1)
            rayleigh = 0.0
            for k in range(n):
                rayleigh += x1[k] * r1[k]
            sums[energy.D_DAMP] += beta * rayleigh / dt
            # the attachment's velocity over the step (v_d once started)
            moved = (prescribed_position(t, v_d) - prescribed_position(t - dt, v_d)
                     if prescribed else v_d * dt)
            sums[energy.W_DRIVE] += (af1 * f_d + alpha_f * f_d_old) * moved
            add_contact_work(q, q_new, contact_dofs, penalty_share, area_share, params, states,
                             trial_state, friction, force_t, normal, normal_t, alpha_f, dx_b,
                             eta_y * dy_b, beta, dt, sums)
        for k in range(n):
            a_new = (q_new[k] - qt[k]) / (beta_n * dt * dt)
            v[k] = vt[k] + gamma * dt * a_new
            a[k] = a_new
            q[k] = q_new[k]
        # Commit the contact state of the converged evaluation.
        for c in range(states.shape[0]):
            states[c, :] = trial_state[c]
            normal[c] = normal_t[c]
            friction[c, 0] = force_t[c, 0]
            friction[c, 1] = force_t[c, 1]
        xb, yb = xb_new, yb_new
        f_d_old = f_d
        f_hold_old = f_hold

        magnitude = 0.0
        for c in range(states.shape[0]):
            magnitude += math.sqrt(friction[c, 0] ** 2 + friction[c, 1] ** 2)
        x_out = y_out = 0.0
        for k in range(drive_index.shape[0]):
            x_out += drive_x[k] * q[drive_index[k]]
            y_out += drive_y[k] * q[drive_index[k]]
        if not prescribed:
            f_d = k_d * (v_d * t - x_out)  # eq 17; prescribed: the iteration's reaction
        code = finish_step(t, t_on, f_d, f_n, f_x, f_y, x_out, y_out, xb, yb, magnitude, F_N,
                           mu_max, scalars, row)
        if code != trouble.OK:
            return i, code, 0
        if use_energy:
            apply(mass, v, r1)
            apply(stiffness, q, r2)
            kinetic, elastic = energy_stored(q, v, r1, r2, contact_dofs, u0c[:, 2], normal0,
                                             penalty_share, area_share, params, states, f_d,
                                             spring)
            row[recording.W_DRIVE] = sums[energy.W_DRIVE]
            row[recording.W_BASE] = sums[energy.W_BASE]
            row[recording.E_KIN] = kinetic
            row[recording.E_EL] = elastic
            row[recording.D_FRIC] = sums[energy.D_FRIC]
            row[recording.D_DAMP] = sums[energy.D_DAMP]
        if keep_step(i, f_d, recorder, steady):
            stop = i
            break

    scalars[XB], scalars[YB] = xb, yb
    scalars[SIN], scalars[COS] = sin_phase, cos_phase
    scalars[F_D] = f_d_old
    scalars[F_HOLD] = f_hold_old
    return 0, trouble.OK, stop
