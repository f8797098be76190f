"""The contact inside an implicit step: every contact node's forces at trial
displacements, and the iteration that makes them consistent with the step
(the fixed point in the contact space, Newton on the critical nodes, Anderson's
acceleration past the plain iteration's reach; docs/fe-model.md, "How an implicit
step works", explains why it converges).

This is the part of an implicit step that calls the friction law, compiled
for each law (friction_law/specialize.py); the rest of the step is compiled
once for all laws (generalized_alpha.py, energy.py, implicit.py), and so is
the Newton step's linear algebra (newton_on_subset). Each function here is
compiled on its own and linked into its callers (none is inlined by numba,
which would type it afresh at each call site: docs/first-answer.md; LLVM
inlines _node_over_step, forceinline, where it is linked).

Each node's contact over the step is the VFRIC analogue (contact.node_contact,
the same per-node update as explicit.py) on implicit_substeps(scene)
sub-steps, the base on its exact sinusoid (eq 23), the node at its mean
velocity over the step.
"""

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from ...core.base_motion import normal_displacement
from ...core.base_table import plane_order, table_row
from ...core.law_limits import slip_resolving_step
from ...friction_law import law_kernel
from ...friction_law.contract import FASTMATH
from ..model.contact import node_contact
from ..model.drive import attachment_xy, prescribed_position
from ..model.linalg import apply
from .anderson import accelerated_step

# Convergence of the contact iteration: the change of every contact
# displacement below this fraction of F_N / k_t (~7e-13 m on the paper's
# cases: 1e-5 of the Dahl sliding length s_c, far above rounding). Measured on
# the Fig 7 scene at dt = 1e-5 s: 2.2 iterations a step, F_dv within 1e-5 of
# a 10x tighter tolerance's (2.6 iterations), the energy balance to 1e-7.
ITERATION_TOLERANCE = 1e-6
MAX_ITERATIONS = 30
# Then the plain fixed point (delta = -rho), slower, for steps where the Newton
# steps alternate across contact kinks.
FALLBACK_ITERATIONS = 300
# Backtracking: a Newton step that does not lower the residual is halved, down
# to this fraction. A step that has not converged after all iterations is
# accepted at its best iterate if that one's residual is within STALL_FACTOR
# times the tolerance (1e-4 of F_N / k_t, ~1e-3 of s_c: a normal force error
# of ~1e-3 F_N / contacts on one node): it sits on a node's contact kink,
# where the Newton steps of the two sides can alternate. Counted as
# iterations_stalled.
MIN_STEP = 1.0 / 64.0
STALL_FACTOR = 1e2
# Nodes below this fraction of their preload's normal force get a Newton step
# (newton_correction), with tangents by forward differences of FD_STEP times
# the node's natural length (its sliding length, its preload penetration).
CRITICAL = 0.25
FD_STEP = 1e-4
# A node counts as pressing at a step's start (forces_at_start) while its normal force
# is above this fraction of its preload's: g_prev - l q_old is its force to rounding.
PRESSING = 1e-6
# The friction law runs on at least this many sub-steps a vibration cycle (implicit_substeps).
SUBSTEPS_PER_CYCLE = 100
# Above this estimated contraction factor the iteration is accelerated (anderson.py:
# at 0.5 the plain one needs ~25 iterations, and more as the factor nears 1). Above 1
# the bound no longer says the map contracts in every direction: refused.
MAX_CONTRACTION = 0.5
MAX_ACCELERATED_CONTRACTION = 1.0
# What iterate_contact returns: converged; stalled on a contact kink and taken at its best
# iterate (within STALL_FACTOR of the tolerance); not converged.
CONVERGED, STALLED, NOT_CONVERGED = range(3)


class ContactData(NamedTuple):
    """The contact nodes as the step sees them (``contact`` in the compiled functions)."""

    u0c: np.ndarray             # (contacts, 3) preload displacement
    normal0: np.ndarray         # (contacts,) preload normal force
    penalty_share: np.ndarray   # (contacts,) k_pen w_i
    area_share: np.ndarray      # (contacts,) w_i
    nominal_normal: np.ndarray  # (contacts,) what each law sees in contact (contact.nominal_normal)
    initial_gap: np.ndarray     # (contacts,) g0_i, each node's height at rest (FEModel.initial_gap)
    tangent: np.ndarray         # (3 contacts,) l, the tangent the factorized matrix holds
    assumed: np.ndarray         # (contacts,) 1.0 where in contact at the preload


class StepStart(NamedTuple):
    """The state a step starts from, and the base over its friction sub-steps (``step``)."""

    q_old: np.ndarray
    v_old: np.ndarray
    vt: np.ndarray              # predictors
    qt: np.ndarray
    base_dx: np.ndarray         # (substeps,) the base's X increments
    base_free: np.ndarray       # (substeps,) the free end's: eta_y dy_b (eq 30)
    base_z: np.ndarray          # (substeps,) the base's Z at each sub-step's end (0: no
    base_vz: np.ndarray         # normal motion) and its Z velocity


def implicit_substeps(scene) -> int:
    """Friction sub-steps per step: enough for SUBSTEPS_PER_CYCLE a vibration cycle.

    The friction law is the scene's fastest nonlinearity: its asperity
    follows the base's sinusoid, whose phase moves by w dt a step (0.25 rad
    at 4 kHz and dt = 1e-5 s). Integrating it in one piece over such a step
    errs by ~1% of F_dv (the lumped stepper at dt = 1e-5 s: -0.6%, at
    6.25e-6 s: -1.6%). On sub-steps of 2 pi / 100, the base on its exact
    sinusoid and the body at its mean velocity over the step, a rigid block
    (trapezoidal rule, Fig 7 scene) is within 0.2% at dt = 1e-5 s. (A cubic
    path through the end velocities is no more accurate there, and it
    carries the unresolved, undamped penalty modes' velocities into the slip.)
    And the split of each sub-step into base and body phases errs in
    proportion to the slip a sub-step makes against the sliding length
    (core.law_limits.SLIP_PER_STEP), most where the sliding direction turns:
    so the sub-steps are also at most core.law_limits.slip_resolving_step.
    On the coupled scene at k_v = 20, theta = 75 deg, dt = 1e-5 s: with the
    cycle rule alone (3 sub-steps) F_dv was 4.8% below the explicit run at
    2.5e-7 s; with 28 sub-steps it is 0.25% below (at 120 deg +0.8%).
    A base motion given per step (core/base_table.py) counts in both rules: its
    highest in-plane harmonic n sets SUBSTEPS_PER_CYCLE a cycle of n f, and its
    in-plane speed the fastest sliding (law_limits.slip_resolving_step).
    """
    dt = scene.time.dt
    cycles = plane_order(scene.vibration) * scene.vibration.f * dt
    per_cycle = math.ceil(SUBSTEPS_PER_CYCLE * cycles - 1e-9)
    resolving = math.ceil(dt / slip_resolving_step(scene) - 1e-9)
    return max(1, per_cycle, resolving)


def still_substeps(scene) -> int:
    """Friction sub-steps per step before the base moves (t <= vibration.t_on).

    There is no sinusoid to follow, no phase 2 to split from phase 1 (the
    free end moves with the base), and the block slides at about the
    drive's v_d: enough sub-steps for SLIP_PER_STEP s_c at v_d, which is
    implicit_substeps' slip rule with v_a = 0. On the Fig 7 scene at
    dt = 1e-5 s that is 2 where the vibration needs 11 (the time this saves:
    docs/performance.md, "Design choices measured"). With the exact Dahl update the
    sub-steps of a steady slide compose: F_dv/F_d0 moved by 2e-13 of itself
    (Fig 7), 5e-10 (coupled, k_v = 20, 75 deg), 1e-10 (LuGre on Fig 7, whose
    measured F_d0 agreed to 10 digits); step by step the summed normal force
    moved by up to 5e-7 of itself before the start (the sub-steps sample the
    penalty dashpot) and F_x by 1e-6 of F_c just after it.
    """
    if scene.drive.v_d <= 0.0:
        return 1
    resting = slip_resolving_step(scene, speed=scene.drive.v_d)   # infinite without friction
    return min(implicit_substeps(scene), max(1, math.ceil(scene.time.dt / resting - 1e-9)))


@law_kernel(cache=True, error_model="numpy", fastmath=FASTMATH, forceinline=True)
def _node_over_step(c, qx, qy, qz, q_old, v_old, vt, qt, base_dx, base_free, base_z, base_vz,
                    contact_dofs, u0c, initial_gap, penalty_share, area_share, nominal, params,
                    dt, c_v, beta, states, state):
    """Contact node c over the step, ending at the trial displacements (qx, qy, qz).

    The friction law runs over the step's sub-steps (implicit_substeps): the
    node moves at its mean velocity over the step, the base along its exact
    sinusoid; the normal force's dashpot sees the velocity interpolated
    between v_n and v_{n+1} (Newmark, from q_{n+1}); the gap and the closing speed are
    the node's against the base's Z (base_z, base_vz: contact.py). The node's law state
    starts from states[c] and ends in ``state``. Returns contact.node_contact's
    (N, F_x, F_y) at the end.

    Arrays come one by one and the state is copied element by element: a
    tuple unpacked or a row view taken here, once per node and evaluation,
    costs numba a reference-count pair each (10% of the reduced Fig 7 loop,
    measured before implicit_steps took its arrays through borrowed.py).
    """
    ix, iy, iz = contact_dofs[c, 0], contact_dofs[c, 1], contact_dofs[c, 2]
    m = base_dx.shape[0]
    slip_x, slip_y = (qx - q_old[ix]) / m, (qy - q_old[iy]) / m
    z0, dz = u0c[c, 2] + q_old[iz], (qz - q_old[iz]) / m
    vz0, vz1 = v_old[iz], vt[iz] + c_v * (qz - qt[iz])
    for k in range(state.shape[0]):
        state[k] = states[c, k]
    n_i = f_x = f_y = 0.0
    for j in range(1, m + 1):
        tau = j / m
        gap = initial_gap[c] + (z0 + j * dz) - base_z[j - 1]    # z0 + j dz to the bit at rest
        closing = vz0 + tau * (vz1 - vz0) - base_vz[j - 1]
        n_i, f_x, f_y = node_contact(slip_x, slip_y, gap, closing,
                                     base_dx[j - 1], base_free[j - 1], penalty_share[c],
                                     area_share[c], nominal[c], beta, params, dt / m, state)
    return n_i, f_x, f_y


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def _contact_g(c, n_i, f_x, f_y, qx, qy, qz, tangent, assumed):
    """g_c = f_c + l q_c of node c from its forces (N, F_x, F_y) at (qx, qy, qz):
    the friction acts on the body as -F, and g has l only where A holds it (the nodes
    in contact at the preload, implicit.py held): on a candidate off the preload's
    patch an l q_c in g that A does not hold is a negative stiffness -l, which ran a
    ball's rim nodes away (e-folding in ~2 us, whatever the step)."""
    held = assumed[c]
    return (-f_x + tangent[3 * c] * held * qx, -f_y + tangent[3 * c + 1] * held * qy,
            n_i + tangent[3 * c + 2] * held * qz)


@law_kernel(cache=True, error_model="numpy", fastmath=FASTMATH)
def _contact_space(qc, xa, t, step, contact_dofs, contact, params, drive, scheme, states, work):
    """Evaluate the contact forces at the trial contact displacements ``qc`` and drive x_A.

    Fills g (work) with g_c = f_c + l q_c and returns (F_d, sum N, sum F_x, sum F_y);
    the trial asperity states and forces land in work (not committed).
    """
    q_old, v_old, vt, qt, base_dx, base_free, base_z, base_vz = step
    u0c, normal0, penalty_share, area_share, nominal, initial_gap, tangent, assumed = contact
    dt, c_v, beta = scheme.dt, scheme.c_v, scheme.beta
    k_d, v_d, prescribed = drive
    g, trial_state, state = work.g, work.trial_state, work.scratch_state
    normal_t, force_t = work.normal_t, work.force_t
    f_n = f_x = f_y = 0.0
    for c in range(contact_dofs.shape[0]):
        qx, qy, qz = qc[3 * c], qc[3 * c + 1], qc[3 * c + 2]
        n_i, fx_i, fy_i = _node_over_step(c, qx, qy, qz, q_old, v_old, vt, qt, base_dx,
                                          base_free, base_z, base_vz, contact_dofs, u0c,
                                          initial_gap, penalty_share, area_share, nominal,
                                          params, dt, c_v, beta, states, state)
        for k in range(state.shape[0]):
            trial_state[c, k] = state[k]
        normal_t[c], force_t[c, 0], force_t[c, 1] = n_i, fx_i, fy_i
        g[3 * c], g[3 * c + 1], g[3 * c + 2] = _contact_g(c, n_i, fx_i, fy_i, qx, qy, qz,
                                                          tangent, assumed)
        f_n += n_i
        f_x += fx_i
        f_y += fy_i
    return k_d * (v_d * t - xa), f_n, f_x, f_y


@law_kernel(cache=True, error_model="numpy", fastmath=FASTMATH)
def newton_correction(rho, delta, qc, step, G, contact_dofs, contact, params, scheme, mu_max,
                       states, work):
    """delta: the step of the contact-space fixed point.

    -rho (the fixed-point step) on every node the matrix describes well; a
    Newton step on the critical ones: those whose contact differs from the
    matrix's assumption, or whose normal force is below CRITICAL of its
    preload (there the Coulomb limit mu N_i is small, the friction
    saturates and its tangent leaves k_t w_i, and the node may lift off
    within the step). Their 3x3 tangents J_c = dg_c/dq_c are taken by forward
    differences, and

        (I - (1 - af) G_SS J_SS) d_S = -rho_S,   delta = -rho + (1 - af) G_:S J_SS d_S.
    """
    q_old, v_old, vt, qt, base_dx, base_free, base_z, base_vz = step
    u0c, normal0, penalty_share, area_share, nominal, initial_gap, tangent, assumed = contact
    af1 = 1.0 - scheme.alpha_f
    g, normal_t, subset, jac = work.g, work.normal_t, work.subset, work.jac
    for p in range(rho.shape[0]):
        delta[p] = -rho[p]
    nodes = 0
    for c in range(normal_t.shape[0]):
        active = 1.0 if normal_t[c] > 0.0 else 0.0
        if active != assumed[c] or normal_t[c] < CRITICAL * normal0[c]:
            subset[nodes] = c
            nodes += 1
    if nodes == 0:
        return
    tangents = np.empty((nodes, 3, 3))    # tangents[b, :, k] = dg_c / dq_(c,k)
    for b in range(nodes):
        c = subset[b]
        scale = max(normal0[c], 1e-300)
        steps = (FD_STEP * scale * max(mu_max, 0.01) / tangent[3 * c],
                 FD_STEP * scale * max(mu_max, 0.01) / tangent[3 * c + 1],
                 FD_STEP * scale / tangent[3 * c + 2])
        for k in range(3):
            x, y, z = qc[3 * c], qc[3 * c + 1], qc[3 * c + 2]
            if k == 0:
                x += steps[0]
            elif k == 1:
                y += steps[1]
            else:
                z += steps[2]
            n_i, f_x, f_y = _node_over_step(c, x, y, z, q_old, v_old, vt, qt, base_dx, base_free,
                                            base_z, base_vz, contact_dofs, u0c, initial_gap,
                                            penalty_share, area_share, nominal, params,
                                            scheme.dt, scheme.c_v, scheme.beta, states,
                                            work.scratch_state)
            g_c = _contact_g(c, n_i, f_x, f_y, x, y, z, tangent, assumed)
            for r in range(3):
                tangents[b, r, k] = (g_c[r] - g[3 * c + r]) / steps[k]
    newton_on_subset(rho, delta, G, subset, nodes, tangents, af1, jac)


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def newton_on_subset(rho, delta, G, subset, nodes, tangents, af1, jac):
    """The Newton part of newton_correction, compiled once for all laws: with the
    critical nodes subset[:nodes] and their tangents J_c (tangents[b, :, k] = dg_c/dq_(c,k)),
    solve (I - (1 - af) G_SS J_SS) d_S = -rho_S and add (1 - af) G_:S J_SS d_S to delta."""
    m = 3 * nodes
    small = np.empty((m, m))
    rhs = np.empty(m)
    for a in range(m):
        pa = 3 * subset[a // 3] + a % 3
        rhs[a] = -rho[pa]
        for b in range(nodes):
            cb = subset[b]
            for k in range(3):          # column 3 b + k of G_SS J_SS
                s = 0.0
                for r in range(3):
                    s += G[pa, 3 * cb + r] * tangents[b, r, k]
                small[a, 3 * b + k] = (1.0 if a == 3 * b + k else 0.0) - af1 * s
    if not (np.isfinite(small).all() and np.isfinite(rhs).all()):
        # a trial state gone non-finite (a shooting's Newton trial far off the orbit, on
        # a ball rocking on 3 nodes): no Newton step; the iteration does not converge and
        # the step ends in trouble (the cycle map's failed cycle), not in numba's LinAlgError
        return
    d_s = np.linalg.solve(small, rhs)
    for b in range(nodes):
        cb = subset[b]
        for r in range(3):
            s = 0.0
            for k in range(3):
                s += tangents[b, r, k] * d_s[3 * b + k]
            jac[r] = af1 * s
        for r in range(3):
            col = 3 * cb + r
            for p in range(rho.shape[0]):
                delta[p] += G[p, col] * jac[r]


@law_kernel(cache=True, error_model="numpy", fastmath=FASTMATH)
def contact_residual(qc, x_a, y_a, t, step, G, h, e, af1, contact_dofs, contact, params, drive,
              drive_now, scheme, states, work):
    """Evaluate the contact space at (qc, x_a): fills g, target = y_c + (1 - af) (G g + h F_d)
    and rho = qc - target (work). Returns (F_d, F_hold, sum N, sum F_x, sum F_y, max |rho|,
    the x_A the fixed point maps x_a to).

    F_d is the drive spring's k_d (v_d t - x_a) (eq 17), F_hold = 0. A prescribed
    drive (drive.mode = "velocity") puts its attachment at x_A = v_d t (after its start,
    drive.prescribed_position), y_A = 0:
    (F_d, F_hold) are the reactions that do it, from

        x_A = y_A + (1 - af) (h^T g_c + e F_d + e_xy F_hold) = v_d t
        y_A = y_Ay + (1 - af) (h_y^T g_c + e_xy F_d + e_yy F_hold) = 0

    with drive_now = (y_Ay, h_y, e_xy, e_yy) (implicit.Operators).
    """
    g, target, rho, yc = work.g, work.target, work.rho, work.yc
    f_d, f_n, f_x, f_y = _contact_space(qc, x_a, t, step, contact_dofs, contact, params, drive,
                                        scheme, states, work)
    apply(G, g, target)
    f_hold = 0.0
    if drive.prescribed:
        y_ay, h_y, e_xy, e_yy = drive_now
        hg = hyg = 0.0
        for p in range(qc.shape[0]):
            hg += h[p] * g[p]
            hyg += h_y[p] * g[p]
        x_target = prescribed_position(t, drive.v_d)
        r_x = (x_target - y_a) / af1 - hg
        r_y = -y_ay / af1 - hyg
        det = e * e_yy - e_xy * e_xy
        f_d = (e_yy * r_x - e_xy * r_y) / det
        f_hold = (e * r_y - e_xy * r_x) / det
        residual = 0.0
        for p in range(qc.shape[0]):
            target[p] = yc[p] + af1 * (target[p] + h[p] * f_d + h_y[p] * f_hold)
            rho[p] = qc[p] - target[p]
            residual = max(residual, abs(rho[p]))
        return f_d, f_hold, f_n, f_x, f_y, residual, x_target
    hg = residual = 0.0
    for p in range(qc.shape[0]):
        target[p] = yc[p] + af1 * (target[p] + h[p] * f_d)
        rho[p] = qc[p] - target[p]
        residual = max(residual, abs(rho[p]))
        hg += h[p] * g[p]
    return f_d, f_hold, f_n, f_x, f_y, residual, y_a + af1 * (hg + e * f_d)


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def base_over_substeps(t, dt, u_base, amplitude, omega, t_on, cos_theta, sin_theta, eta_y,
                       base_dx, base_free):
    """The base over the step's friction sub-steps (eq 23), along its exact sinusoid and
    ending at u_base: each sub-step's X increment (base_dx) and the free end's,
    eta_y dy_b (base_free, eq 30), over the first len(base_dx) entries."""
    m = base_dx.shape[0]
    u_prev = amplitude * math.sin(omega * (t - dt - t_on)) if t - dt >= t_on else 0.0
    for j in range(m):
        t_j = t - dt + (j + 1) * dt / m
        u_j = u_base if j == m - 1 else (
            amplitude * math.sin(omega * (t_j - t_on)) if t_j >= t_on else 0.0)
        base_dx[j] = (u_j - u_prev) * cos_theta
        base_free[j] = eta_y * (u_j - u_prev) * sin_theta  # phase 2: eta_y dy_b (eq 30)
        u_prev = u_j


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def normal_over_substeps(t, dt, amplitude_n, omega, t_on, t_from, sin_n, cos_n, base_z,
                         base_vz):
    """The base's Z and Z velocity at each sub-step's end (base_motion.normal_displacement
    on its exact sinusoid), over the first len(base_z) entries: from t_from, the start
    of the step whose end is the first at or past t_on (normal_start.py: the body
    starts there on its forced response; the base's sinusoid taken on up to a step
    before t_on, so that it does not jump within the step), 0 before."""
    m = base_z.shape[0]
    for j in range(m):
        t_j = t - dt + (j + 1) * dt / m
        base_z[j] = base_vz[j] = 0.0
        if amplitude_n > 0.0 and t_j > t_from:
            phase = omega * (t_j - t_on)
            base_z[j], base_vz[j] = normal_displacement(amplitude_n, omega, sin_n, cos_n,
                                                        math.sin(phase), math.cos(phase))


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def table_over_substeps(i, on_step, rows, first, period, per_step, lead, eta_y, base_dx,
                        base_free, base_z, base_vz):
    """Add a base motion given per step (core/base_table.py substep_table) to the sine's
    over step i's friction sub-steps, the first len(base_dx) entries: its X and eta_y Y
    increments (base_dx, base_free) and its Z and Z velocity at each sub-step's end
    (base_z, base_vz). Sub-step j of the step ends at the table's index
    (i - 1) per_step + j + 1; a step before the base starts, on fewer sub-steps
    (still_substeps), meets the table only at its end, i per_step. Where the table has
    not started, X and Y rest at 0 (as the sine does before t_on) and, in the first
    step on (on_step), Z follows ``lead`` (the table's z_b, dz_b/dt at that step's
    sub-steps: as normal_over_substeps takes the sine on a step before t_on).
    Returns the table's (x_b, y_b) at the step's end."""
    m = base_dx.shape[0]
    k = table_row(rows, first, period, (i - 1) * per_step)
    x_prev = rows[k, 0] if k >= 0 else 0.0
    y_prev = rows[k, 1] if k >= 0 else 0.0
    for j in range(m):
        index = (i - 1) * per_step + j + 1 if m == per_step else (i * per_step if j == m - 1
                                                                   else -1)
        k = table_row(rows, first, period, index) if index >= 0 else -1
        if k >= 0:
            x, y, z, vz = rows[k, 0], rows[k, 1], rows[k, 2], rows[k, 5]
        else:
            x = y = z = vz = 0.0
            if i == on_step and lead.shape[0] == m + 1:
                z, vz = lead[j + 1, 0], lead[j + 1, 1]
        base_dx[j] += x - x_prev
        base_free[j] += eta_y * (y - y_prev)   # phase 2: eta_y dy_b (eq 30)
        base_z[j] += z
        base_vz[j] += vz
        x_prev, y_prev = x, y
    return x_prev, y_prev


@law_kernel(cache=True, error_model="numpy", fastmath=FASTMATH)
def iterate_contact(t, step, operators, contact, params, drive, scheme, mu_max, states, g_prev,
                    work):
    """The contact-space fixed point of one step, from the last step's g (g_prev).

    Starts from q_c = y_c + (1 - af) (G g_prev + h F_d,prev), x_A likewise; iterates
    contact_residual with a Newton step on the critical nodes (newton_correction)
    for up to scheme.max_iterations, then the plain fixed point for
    FALLBACK_ITERATIONS more, until no contact displacement nor x_A changes by
    more than scheme.tolerance. With an accelerator in work.history (a scene whose
    estimated contraction is past MAX_CONTRACTION: implicit.ImplicitRun) each step is
    Anderson's (anderson.py) and the Newton steps are not halved. Returns (CONVERGED, STALLED or NOT_CONVERGED,
    iterations, F_d, F_hold, sum N, sum F_x, sum F_y); work holds g, the target
    q_c and the trial states and forces of the last evaluation.
    """
    G, h, e = operators.G, operators.h, operators.e
    contact_dofs = operators.contact_dofs
    y, qc, yc, target, delta, rho, qc_best = (work.y, work.qc, work.yc, work.target, work.delta,
                                              work.rho, work.qc_best)
    nc = qc.shape[0]
    af1 = 1.0 - scheme.alpha_f
    tolerance = scheme.tolerance
    y_a, y_a_y = attachment_xy(y, operators.drive_index, operators.drive_x, operators.drive_y)
    drive_now = (y_a_y, operators.h_y, operators.e_xy, operators.e_yy)
    g_start = work.g
    forces_at_start(g_prev, step, contact, contact_dofs, scheme.beta, scheme.dt, g_start)
    apply(G, g_start, target)
    for p in range(nc):
        yc[p] = y[contact_dofs[p // 3, p % 3]]
        qc[p] = yc[p] + af1 * (target[p] + h[p] * g_prev[nc])
    hg = 0.0
    for p in range(nc):
        hg += h[p] * g_start[p]
    x_a = x_a_best = y_a + af1 * (hg + e * g_prev[nc])
    converged = False
    accelerated = work.history.dx.shape[0] > 0
    count = 0                   # the accelerator's pairs since its restart
    iterations = 0
    residual_old = best = np.inf
    factor = 1.0
    f_d = f_hold = f_n = f_x = f_y = 0.0
    while iterations < scheme.max_iterations + FALLBACK_ITERATIONS:
        iterations += 1
        newton = iterations <= scheme.max_iterations
        f_d, f_hold, f_n, f_x, f_y, residual, x_a_new = contact_residual(
            qc, x_a, y_a, t, step, G, h, e, af1, contact_dofs, contact, params, drive,
            drive_now, scheme, states, work)
        if residual < best:
            best = residual
            for p in range(nc):     # (element by element: a slice copy compiles numba's
                qc_best[p] = qc[p]  # shape-mismatch message into every law's loop)
            x_a_best = x_a
        if (newton and not accelerated and residual >= residual_old
                and factor > MIN_STEP):
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
        if accelerated and change > tolerance:
            # the step past the plain one's reach (anderson.py); restarted where the
            # Newton steps end, the map they iterate changing there
            if iterations == scheme.max_iterations + 1:
                count = 0
            x_a = _accelerate(qc, x_a, delta, x_a_new, count, work.history)
            count += 1
        else:
            for p in range(nc):
                qc[p] += delta[p]
            x_a = x_a_new
        residual_old = residual
        factor = 1.0
        if change <= tolerance:
            converged = True
            break
    if converged:
        return CONVERGED, iterations, f_d, f_hold, f_n, f_x, f_y
    if best > tolerance * STALL_FACTOR:
        return NOT_CONVERGED, iterations, f_d, f_hold, f_n, f_x, f_y
    # Stalled on a node's contact kink, within the looser tolerance: take the best iterate.
    for p in range(nc):
        qc[p] = qc_best[p]
    f_d, f_hold, f_n, f_x, f_y, residual, x_a_new = contact_residual(
        qc, x_a_best, y_a, t, step, G, h, e, af1, contact_dofs, contact, params, drive,
        drive_now, scheme, states, work)
    return STALLED, iterations, f_d, f_hold, f_n, f_x, f_y


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def forces_at_start(g_prev, step, contact, contact_dofs, beta, dt, g):
    """g: the contact forces the step's iteration starts from, the last step's g_prev
    with the base's known move along Z over the step added on each node that pressed
    at the step's start.

    A node pressing on the matrix's tangent l = k_pen,i has
    g_z = N_i + l q_z = k_pen,i (z_b - g0_i - u0_z - beta (v_z - v_zb)) + l q_z
    (contact.normal_force), in which q_z cancels but the base does not: the base
    moving by dz_b and dv_zb over the step moves g_z by k_pen,i (dz_b + beta dv_zb).
    Left out of the start, that move is what the first iterations make up
    (docs/performance.md, 2026-11-28). dz_b and dv_zb come from the sub-steps' ends,
    extrapolated back to the step's start (from the end's Z velocity on a step of one
    sub-step). Whether a node pressed is read from the state alone, N_i = g_z - l q_z
    at the step's start (q_old), so that the cycle map stays a function of its state;
    a node off the base keeps its g_prev (started as pressing too, a bouncing block's
    energy balance no longer closed: docs/performance.md). With the base still in Z,
    g is g_prev to the bit."""
    base_z, base_vz, q_old = step.base_z, step.base_vz, step.q_old
    m = base_z.shape[0]
    nc = g.shape[0]
    for p in range(nc):
        g[p] = g_prev[p]
    if base_vz[0] == 0.0 and base_vz[m - 1] == 0.0 and base_z[0] == base_z[m - 1]:
        return
    if m > 1:
        scale = m / (m - 1.0)
        dz_b = (base_z[m - 1] - base_z[0]) * scale
        dv_zb = (base_vz[m - 1] - base_vz[0]) * scale
    else:
        dz_b, dv_zb = dt * base_vz[0], 0.0
    penalty_share, assumed = contact.penalty_share, contact.assumed
    normal0, tangent = contact.normal0, contact.tangent
    for c in range(nc // 3):
        if assumed[c] > 0.0:
            pressing = g_prev[3 * c + 2] - tangent[3 * c + 2] * q_old[contact_dofs[c, 2]]
            if pressing > PRESSING * normal0[c]:
                g[3 * c + 2] += penalty_share[c] * (dz_b + beta * dv_zb)


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def _accelerate(qc, x_a, delta, x_a_new, count, history):
    """Advance the iterate (qc, x_a) by Anderson's step (anderson.accelerated_step) in
    place of the plain (delta, x_a_new - x_a); returns the new x_a."""
    nc = qc.shape[0]
    x, f = history.x, history.f
    for p in range(nc):
        x[p] = qc[p]
        f[p] = delta[p]
    x[nc], f[nc] = x_a, x_a_new - x_a
    accelerated_step(x, f, count, history)
    for p in range(nc):
        qc[p] += f[p]
    return x_a + f[nc]


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def commit_contact(states, normal, friction, work):
    """The converged evaluation's trial law states and forces become the nodes' state;
    returns sum |F_i|, the friction forces' summed magnitude."""
    trial_state, normal_t, force_t = work.trial_state, work.normal_t, work.force_t
    for c in range(states.shape[0]):
        states[c, :] = trial_state[c]
        normal[c] = normal_t[c]
        friction[c, 0] = force_t[c, 0]
        friction[c, 1] = force_t[c, 1]
    magnitude = 0.0
    for c in range(states.shape[0]):
        magnitude += math.sqrt(friction[c, 0] ** 2 + friction[c, 1] ** 2)
    return magnitude
