"""Contact of the body's contact face with the rigid base, node by node.

Normal direction: a penalty spring per contact node (and, with the model's
stiffness-proportional damping, a dashpot beside it), against the base's
plane at height z_b(t) (0 unless vibration.normal_amplitude > 0: the base
moving along Z, core/base_motion.py normal_displacement). Node i's gap is

    g_i = g0_i + u_z,i - z_b          (g0_i: FEModel.initial_gap, its height at rest
                                       before the preload; 0 on the block's face)

and, with v_z,i - v_zb its speed relative to the base, it is pushed up by

    N_i = k_pen w_i min(max(0, -g_i - beta (v_z,i - v_zb)), -2 g_i)   if g_i < 0,   else 0

(written below for the block, g = u_z, v_zb = 0: a base that stays at z = 0 gives
the gap u_z to the bit). A node whose gap opens carries no force (N_i = 0, its
friction law released) until it touches down again; the min() below is the
touch-down rule.

where w_i = a_i / A is the node's share of the contact area (a_i its tributary
area, sum w_i = 1) and k_pen the penalty stiffness of the whole face. The
dashpot term beta k_pen w_i v_z is the penalty spring's share of the Rayleigh
damping C = beta K; the max() keeps the contact from pulling. The min() keeps
the dashpot's push within the spring's own, so that N_i goes to 0 as the
penetration does: without it a node touching down at speed v_z < 0 would
meet a force beta k_pen w_i |v_z| at zero penetration, a jump that the
implicit integrators' contact iteration cannot converge on (it alternated
between the two sides, 0 and 0.04 N, on a rocking block at k_t x 100). In
steady contact beta |v_z| is ~1e-4 of the penetration and the min() never
acts; it does on nodes touching down in the start's transient, which moves
the shipped scenes' F_dv by at most 3e-7 of itself (0.16 s runs of each
integrator; the peak normal forces of the transient by up to 4e-5).

Tangential direction: the friction law of docs/model.md sections 1-3 per node,
the analogue of Abaqus' VFRIC subroutine. Each step every contact node gets

    stiffness      k_t w_i                   (its share of the contact stiffness)
    Coulomb limit  mu N_i                    (its own normal force, eq 3)
    phase 1 slip   (du_x - dx_b, du_y)       (body minus base in X, eq 14; body in Y)
    phase 2        free end by (0, eta_y dy_b)  (eq 30)

exactly as the lumped stepper (analytic/coupled.py) does for its single node,
and returns the friction force F_i (eqs 1, 38-39); it acts on the body node as
-F_i. The lumped model is the case of one node with w = 1 and N = F_N.

The normal force the law sees (``fem.normal_force``). The block pitches as it
slides and vibrates, so each node's N_i swings over the cycle (on the paper's
steel block by +-67% about its mean, docs/friction-laws.md), and what the
law's state does when N_i changes (contact.normal_change of the asperity laws)
moves the FE answer by several percent. The paper's Abaqus model assumed the
normal contact pressure constant (its conclusion; the paper: docs/model.md).
The two rules:

    "nodal"    (default) the law sees N_i, the node's own penalty force above;
    "nominal"  the law sees N_i^nom = F_N w_i, the node's nominal share of the
               normal load (the same share w_i its stiffness k_t w_i takes),
               while the node is in contact (N_i > 0); out of contact it sees
               N_i = 0 and is released as under "nodal". The Coulomb limit is
               then mu F_N w_i at every step: a uniform, constant pressure.

Only what the law is passed changes: the normal contact stays the penalty
spring, its force N_i still acts on the body and is what the summed normal
force and the outputs report. The lumped model has one node with N = F_N
under either rule. The rule is a setting of the FE model ([fem]), not a key of
[contact]: [contact] holds the friction law's parameters (a user's law may
name its own), and the lumped model, which [contact] also describes, has no
nodes to choose for.
"""

import math

import numpy as np
from numba import njit

from ...core.bounce import PENALTY_FACTOR as BLOCK_PENALTY_FACTOR
from ...core.law_limits import SLIP_PER_STEP
from ...friction_law import law_kernel
from ...friction_law.contract import FASTMATH

# Default penalty per unit contact area k_c = PENALTY_FACTOR E / H (Pa/m), H the body's
# height: on the paper's block, whose face of area A = L_x L_y stands on it, the whole
# face's PENALTY_FACTOR E A / L_z, this many times the block's axial stiffness.
#  - Stiff enough to be "hard" contact: the penalty adds 1/10 of the block's own
#    axial compliance, and the static penetration F_N / k_pen is ~1 nm, far
#    below the vibration amplitude u0 ~ 1e-7 m and the Dahl length
#    s_c = F_c / k_t ~ 7e-8 m that the tangential law works on.
#  - Soft enough for the explicit step: on the "coarse" mesh it raises the
#    highest frequency by ~10% (the stable step of the 0.5 kg block goes from
#    1.22 to 1.11 us); 30 E A / L_z would bring it under the paper's 1e-6 s.
#  - Per unit area (not per element as Abaqus' default), so the body's rigid-body
#    contact modes (bounce, rocking, 10-25 kHz on the block) do not move when the
#    mesh is refined.
PENALTY_FACTOR = BLOCK_PENALTY_FACTOR
# On a curved body (its candidates at rest not all on the base) the contact's own
# compliance is Hertz's: under the peak pressure p0 = 2 E* a / (pi R) (Johnson,
# "Contact Mechanics", CUP 1985, eq 4.23) a penalty k_c penetrates p0 / k_c, against
# the Hertz approach a^2 / R. With k_c = HERTZ_PENALTY E* / a their ratio is
# 2 / (pi HERTZ_PENALTY) = 0.6%: a spring layer that much softer than the patch
# widens it and lowers p0 by a fraction of that (docs/fe-model.md, "The per-area
# penalty"). The default is the larger of this and PENALTY_FACTOR E / H.
HERTZ_PENALTY = 100.0

# A node whose slip in an explicit step is more than SUBSTEP_ONSET sliding
# lengths s_c runs the friction law on sub-steps of at most SLIP_PER_STEP s_c
# (core.law_limits). The two-phase update's split error grows with the slip a
# step makes against s_c, which a stiff contact shrinks: at k_t x 100 a 1e-6 s
# step of the transverse scene (k_v = 20) slides up to 15 s_c, and prescribed
# sliding gave F_dv/F_d0 0.148 against the lumped stepper's 0.181 (0.1808 with
# the sub-steps). The paper's scenes slide at most 0.15 s_c a step (k_v = 20 at
# 1e-6 s) and keep one update a step, as Abaqus calls VFRIC.
SUBSTEP_ONSET = 0.25
# At most this many (a diverging step's slip would ask for billions; the loop's
# checks then stop the run). The most measured: 3308, transverse at k_t x 1000.
MAX_SUBSTEPS = 100_000


def nominal_normal(rule: str, F_N: float, area_share: np.ndarray) -> np.ndarray:
    """(n,): the normal force each node's law sees while in contact under ``rule``
    (fem.normal_force): F_N w_i under "nominal"; zeros under "nodal", which
    law_normal_force reads as "the node's own penalty force"."""
    if rule == "nominal":
        return F_N * area_share
    return np.zeros_like(area_share)


def default_contact_stiffness(E: float, nu: float, height: float, F_N: float,
                              radius: float) -> float:
    """The default penalty per unit contact area, Pa/m: PENALTY_FACTOR E / H (H the body's
    height), raised on a curved body (``radius`` R of its contact's curvature, inf for a
    flat one) to HERTZ_PENALTY E* / a, a = (3 F_N R / (4 E*))^(1/3) the Hertz contact
    radius on the rigid base (Johnson eq 4.22), E* = E / (1 - nu^2)."""
    flat = PENALTY_FACTOR * E / height
    if not math.isfinite(radius):
        return flat
    e_star = E / (1.0 - nu * nu)
    a = (3.0 * F_N * radius / (4.0 * e_star)) ** (1.0 / 3.0)
    return max(flat, HERTZ_PENALTY * e_star / a)


# The candidates touching at rest span an area (a flat face) where their rms width
# across their thinnest plan direction is above this fraction of the candidates' plan
# extent: far above gmsh's rounding of a line of nodes (~1e-16 of it), far below any
# flat end's width.
FLAT_WIDTH = 1e-6


def touching_width(xy: np.ndarray) -> float:
    """The rms width of the plan positions ``xy`` (m, 2) across their thinnest direction:
    0 for one point or a line of them."""
    if xy.shape[0] < 3:
        return 0.0
    centred = xy - xy.mean(axis=0)
    return float(np.linalg.svd(centred, compute_uv=False)[-1] / math.sqrt(xy.shape[0]))


def curvature_radius(xy: np.ndarray, initial_gap: np.ndarray) -> float:
    """R of the sphere r^2 + g0^2 = 2 R g0 closest (least squares, weighted by g0) to the
    candidates' initial gaps ``initial_gap`` (n,) at plan positions ``xy`` (n, 2), r
    measured from the centre of those touching at rest (g0 = 0):

        R = sum g0 (r^2 + g0^2) / (2 sum g0^2)

    inf where all touch (a flat face). A sphere's cap gives its radius exactly; a
    paraboloid g0 = r^2 / 2 R a little more (by g0 / 2); a cylinder on its side, whose
    gap grows across it only, more (its axial offsets count as r): an estimate of the
    patch's scale, which is all default_contact_stiffness needs of it.

    Also inf where those touching at rest span an area in plan (FLAT_WIDTH), not a
    point (a ball) or a line (a roller): a flat punch, such as a pin on its end, whose
    patch is its flat face at any load, the rounding of its edge aside. Hertz's radius a
    does not size that patch, and the Hertz rule's 100 E* / a (a from the edge's fitted
    R) would make its penalty some 1000 times the flat face's 10 E / H, and the explicit
    step 7 times shorter, for no accuracy: the flat face's default is the block's."""
    touching = initial_gap <= 0.0
    if touching.all() or touching_width(xy[touching]) > FLAT_WIDTH * float(np.ptp(xy, axis=0).max()):
        return math.inf
    r2 = ((xy - xy[touching].mean(axis=0)) ** 2).sum(axis=1)
    g = initial_gap
    return float(np.dot(g, r2 + g * g) / (2.0 * np.dot(g, g)))


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def normal_force(u_z, v_z, penalty_share, beta):
    """N_i = k_pen,i min(max(0, -u_z - beta v_z), -2 u_z) if the node penetrates (u_z < 0),
    else 0: continuous in u_z (the dashpot's push at most the spring's). u_z is the
    node's gap g_i and v_z its speed relative to the base (module docstring)."""
    if u_z >= 0.0:
        return 0.0
    closing = -u_z - beta * v_z
    if closing <= 0.0:
        return 0.0
    # (a NaN displacement gives NaN, caught by the loop)
    return penalty_share * min(closing, -2.0 * u_z)


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def law_normal_force(n_i, nominal):
    """The normal force a node's law sees (module docstring, fem.normal_force): its
    penalty force n_i where ``nominal`` is 0 ("nodal"), else ``nominal`` = F_N w_i
    while the node is in contact (n_i > 0) and n_i (0: released) out of it."""
    if nominal > 0.0 and n_i > 0.0:
        return nominal
    return n_i


@law_kernel(cache=True, error_model="numpy", fastmath=FASTMATH, inline="always")
def node_contact(slip_x, slip_y, u_z, v_z, dx_b, free_y, penalty_share, w, nominal, beta,
                 params, dt, state):
    """One node's step: (N_i, F_x, F_y) after the body moved by (slip_x, slip_y) and
    reached the gap u_z at speed v_z relative to the base (module docstring), the base
    by dx_b and the free end by free_y; the
    node's law ``state`` is updated in place (the VFRIC call). N_i is the penalty
    force; the law sees law_normal_force(N_i, nominal) (``nominal``: the node's
    entry of nominal_normal)."""
    n_i = normal_force(u_z, v_z, penalty_share, beta)
    f_x, f_y = law_update(  # noqa: F821 (the scene's law, friction_law/specialize.py)
        slip_x - dx_b, slip_y,      # phase 1: body minus base in X (eq 14), body in Y
        0.0, free_y,                # phase 2: the free end by eta_y dy_b (eq 30)
        law_normal_force(n_i, nominal), w, state, params, dt)
    return n_i, f_x, f_y


@law_kernel(cache=True, error_model="numpy", fastmath=FASTMATH)
def contact_forces(disp_old, disp_new, vel_z, dx_b, dy_b, eta_y, initial_gap, z_b, v_zb,
                   penalty_share, area_share, nominal, beta, params, dt, sliding_length,
                   states, normal, force):
    """Advance every contact node by one step; outputs are written in place.

    disp_old, disp_new  (n, 3) the nodes' displacements at the start and end of the step
    vel_z               (n,) their Z velocities at the end of the step
    dx_b, dy_b          the base's increment over the step (eqs 24-25)
    initial_gap         (n,) g0_i, each node's height at rest (FEModel.initial_gap)
    z_b, v_zb           the base's height and Z velocity at the end of the step
    penalty_share       (n,) k_pen w_i;  area_share (n,) w_i
    nominal             (n,) nominal_normal: what each node's law sees in contact
    params              the law's parameters (friction_law.ContactLaw.params)
    sliding_length      the law's s_c (m) for the sub-steps: a node whose slip in the step,
                        |du_x - dx_b| + |du_y| + |eta_y dy_b|, is more than SUBSTEP_ONSET
                        s_c runs the law on sub-steps of at most SLIP_PER_STEP s_c (the
                        node's and the base's increments split evenly, the normal force
                        the step's end's; SUBSTEP_ONSET says why)
    states              (n, the law's STATE_SIZE): every node's state at the start of
                        the step, replaced by those at its end
    normal              (n,) out: the normal force N_i at the end of the step
    force               (n, 2) out: the friction force F_i (acts on the body as -F_i)

    Returns the sums (sum N_i, sum F_x, sum F_y).
    """
    free_y = eta_y * dy_b
    total_n = total_x = total_y = 0.0
    onset, resolving = SUBSTEP_ONSET * sliding_length, SLIP_PER_STEP * sliding_length
    for i in range(states.shape[0]):
        slip_x, slip_y = disp_new[i, 0] - disp_old[i, 0], disp_new[i, 1] - disp_old[i, 1]
        slip = abs(slip_x - dx_b) + abs(slip_y) + abs(free_y)
        substeps = 1             # (also for a NaN slip: the loop catches it)
        if slip > onset:
            count = slip / resolving
            substeps = MAX_SUBSTEPS if count > MAX_SUBSTEPS else math.ceil(count)
        n_i = f_x = f_y = 0.0
        gap = initial_gap[i] + disp_new[i, 2] - z_b      # u_z to the bit on the block at rest
        closing = vel_z[i] - v_zb
        for _ in range(substeps):   # (dividing by 1 is exact: one update as before)
            n_i, f_x, f_y = node_contact(
                slip_x / substeps, slip_y / substeps, gap, closing,
                dx_b / substeps, free_y / substeps, penalty_share[i], area_share[i],
                nominal[i], beta, params, dt / substeps, states[i])
        normal[i] = n_i
        force[i, 0] = f_x
        force[i, 1] = f_y
        total_n += n_i
        total_x += f_x
        total_y += f_y
    return total_n, total_x, total_y
