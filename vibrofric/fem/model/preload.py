"""The static preload: the body pressed on the base before anything moves.

Starting the dynamics from an unloaded body with the loads applied at once
sets it ringing on its contact (docs/model.md "Traps measured": the normal
force swung 44-69 N instead of 55 N). Instead every run starts from the static
equilibrium of the normal load on the penalty springs of the nodes in contact:

    (K + K_pen(C)) u0 = f - K_pen(C) g0,    K_pen(C) = diag(k_pen,i, i in C) on the Z dofs

C the contact patch (the active set), g0 the candidates' initial gaps (their heights
at rest, 0 on the block's face): node i in C is pushed up by N_i = -k_pen,i g_i with
g_i = g0_i + u_z,i its gap, every other node carries nothing. The patch is found by
a primal-dual active set iteration (Hintermueller, Ito and Kunisch, SIAM J. Optim.
13 (2003) 865, a semi-smooth Newton method): start from every candidate in C; after
each solve drop the nodes of C that would pull (g_i > 0) and add those outside it
that penetrate (g_i < 0), until neither is left. On the block every node starts in
C and stays. On a curved body the first solve pulls every candidate down onto the
base, a patch that holds the body as the block's face does; the patch then shrinks
to the nodes in compression, symmetric as the body and its load are. Started from
the nodes touching at rest (a ball's pole alone), the first solve has nothing but
the weak springs below against the body's rocking (a rotation of radians from the
mesh's asymmetry), and the patches that follow swing from side to side.
A patch of one or a few nodes, where the mesh is coarse against the contact's true
size (a ball's Hertz radius), holds the body's rocking about it only by the weak
springs below: a full step from it rocks the body from one side to the other and
the sets can cycle (gmsh 4.15's coarse ball unheld: 55 candidates, down to 2 nodes,
then 26, ... back to a patch of 26). The equilibrium is there all the same: it is
the minimum of the energy

    E(u) = 1/2 u^T K' u - f^T u + sum_i 1/2 k_pen,i min(g_i, 0)^2

(K' the stiffness with the in-plane springs below), convex and, held in Z by the
contact, with one minimum; each full step above is a Newton step on it (exact on
the patch's quadratic piece). Where the sets come back, the preload goes on from
there by the same steps shortened by an exact line search on E (damped_patch: the
damped Newton method for a convex piecewise quadratic, J. Sun, Math. Program. 76
(1997) 451), which lowers E every step and ends on the patch of the minimum.
Only if that does not settle within DAMPED_STEPS is the preload refused
(PatchUnresolved: refine the mesh there).

The contact is frictionless during the preload (the asperities start undeformed,
as the lumped model's), so the only loads are in Z. The in-plane rigid motions
(X, Y, rotation about Z) that K + K_pen leaves free carry no load and are pinned by
tangential springs on every candidate REGULARIZATION times weaker than the contact
stiffness k_t, which changes u0 by a relative ~1e-12. On a curved body (a ball on
its pole) the same springs, at the candidates' different heights, also hold the
rocking (rotations about X and Y) that a patch of one or a few nodes does not;
once the patch has grown, its springs hold it. The drive spring is unstretched and
v = 0.

The static reaction sum_i N_i must equal the applied normal load F_N to solver
precision.
"""

import numpy as np
import scipy.sparse as sp

from ...core.errors import NormalLoadTooSmall, PatchUnresolved
from .linalg import spd_factor

REGULARIZATION = 1e-9
RELATIVE_TOLERANCE = 1e-8  # on sum N_i = F_N: a direct solve gives ~1e-12


def static_preload(stiffness, load, nodes, penalty_share, area_share, k_t, F_N, order=None,
                   initial_gap=None):
    """Return (u0, normal, in_contact): the static displacement (dofs,), the contact
    forces (n,) and the contact patch (n,) bool.

    ``order``: the DOFs' elimination order for the factorization (linalg.spd_factor);
    ``initial_gap``: (n,) the candidates' gaps at rest, m (None: all 0, a flat face).

    The first solve has every candidate in the patch (A_0). Where it leaves a node
    pulling, the patch is found on the candidates' Z alone from that one factorization
    (``patch_iteration``), and u0 solved with that patch's springs; should rounding
    leave that solve a node to move, the whole-system iteration goes on from there.
    On the block's face no node pulls: one solve, as it always was.

    Where a patch comes back to an earlier one (the full steps would cycle), the steps
    go on shortened (damped_patch).

    Raises NormalLoadTooSmall if no node stays in contact, PatchUnresolved if the
    damped steps do not settle either, RuntimeError if the reaction does not balance F_N.
    """
    gap0 = np.zeros(nodes.size) if initial_gap is None else np.asarray(initial_gap, dtype=float)
    z = 3 * nodes + 2
    active = np.ones(nodes.size, dtype=bool)
    seen = set()
    while True:
        seen.add(active.tobytes())
        lu, u0 = _solve(stiffness, load, nodes, penalty_share, area_share, k_t, order, gap0, active)
        gap = gap0 + u0[z]
        lifted = active & (gap > 0.0)
        touching = ~active & (gap < 0.0)
        if not (lifted.any() or touching.any()):
            break
        if len(seen) == 1:      # the first solve, every candidate in: condense on them
            active = patch_iteration(lu, z, stiffness.shape[0], penalty_share, gap0, u0[z])
        else:
            active = (active & ~lifted) | touching
        if active is None or active.tobytes() in seen:
            # full steps that come back: shortened from here until they settle
            u0, active = damped_patch(stiffness, load, nodes, penalty_share, area_share,
                                      k_t, order, gap0, u0)
            gap = gap0 + u0[z]
            break
        if not active.any():
            raise NormalLoadTooSmall("no contact node stays on the base under the preload")
    normal = np.where(active, penalty_share * np.maximum(-gap, 0.0), 0.0)
    if not np.isclose(normal.sum(), F_N, rtol=RELATIVE_TOLERANCE, atol=0.0):
        raise RuntimeError(f"the static normal reaction {normal.sum():.12g} N does not balance "
                           f"F_N = {F_N} N: the preload solve failed")
    return u0, normal, active


def _in_plane_springs(stiffness, nodes, area_share, k_t) -> np.ndarray:
    """(dofs,) the springs on the candidates' X and Y dofs (the module docstring)."""
    springs = np.zeros(stiffness.shape[0])
    springs[3 * nodes] = springs[3 * nodes + 1] = REGULARIZATION * k_t * area_share
    return springs


def _solve(stiffness, load, nodes, penalty_share, area_share, k_t, order, gap0, active):
    """(the factorization, u): (K + K_pen(S) + the in-plane springs) u = f - K_pen(S) g0
    for the patch ``active``."""
    springs = _in_plane_springs(stiffness, nodes, area_share, k_t)
    z = 3 * nodes + 2
    springs[z[active]] = penalty_share[active]
    force = load.copy()
    force[z[active]] -= penalty_share[active] * gap0[active]  # 0 on a flat face: f itself
    lu = spd_factor(stiffness + sp.diags(springs), order)
    return lu, lu.solve(force)


DAMPED_STEPS = 100  # damped_patch's Newton steps at most
LINE_SEARCH_HALVINGS = 60  # bisections of the step length: 2^-60, below rounding


def damped_patch(stiffness, load, nodes, penalty_share, area_share, k_t, order, gap0, u):
    """(u0, patch): the preload's equilibrium, the minimum of E (module docstring), by
    Newton steps from ``u`` shortened by an exact line search.

    From u, the patch S = {g_i < 0}; the full step goes to u_S, the solve for that
    patch (_solve: the minimum of E's quadratic piece on S), d = u_S - u. Along d,
    E's slope

        phi'(t) = d^T (K' u - f) + t d^T K' d + sum_i k_pen,i d_z,i min(g_i + t d_z,i, 0)

    is continuous and rises with t (E is convex): the step length t is its zero in
    (0, 1], or 1 where phi'(1) <= 0, found by bisection. Settled once a full step
    leaves no node of S pulling and none off it penetrating (static_preload's test).
    Raises PatchUnresolved after DAMPED_STEPS steps, NormalLoadTooSmall if no node
    stays in contact.
    """
    z = 3 * nodes + 2
    free = stiffness + sp.diags(_in_plane_springs(stiffness, nodes, area_share, k_t))
    for _ in range(DAMPED_STEPS):
        gap = gap0 + u[z]
        active = gap < 0.0
        if not active.any():
            raise NormalLoadTooSmall("no contact node stays on the base under the preload")
        _, full = _solve(stiffness, load, nodes, penalty_share, area_share, k_t, order,
                         gap0, active)
        new_gap = gap0 + full[z]
        if not ((active & (new_gap > 0.0)).any() or (~active & (new_gap < 0.0)).any()):
            return full, active
        d = full - u
        slope_at_0 = d @ (free @ u - load)
        curvature = d @ (free @ d)
        dz = d[z]

        def slope(t):
            return (slope_at_0 + t * curvature
                    + penalty_share @ (dz * np.minimum(gap + t * dz, 0.0)))

        if slope(1.0) <= 0.0:
            u = full
            continue
        low, high = 0.0, 1.0
        for _ in range(LINE_SEARCH_HALVINGS):
            middle = 0.5 * (low + high)
            low, high = (middle, high) if slope(middle) < 0.0 else (low, middle)
        u = u + high * d
    raise _unresolved(DAMPED_STEPS, gap0 + u[z] < 0.0)


def _unresolved(steps: int, active) -> PatchUnresolved:
    return PatchUnresolved(
        f"the preload's contact patch does not settle (after {steps} damped steps, at a "
        f"patch of {int(active.sum())} nodes): a patch of a few nodes does not hold the "
        "body's rocking; refine the mesh where it touches the base")


# Right-hand sides solved at once while the candidates' compliance is gathered
COMPLIANCE_BATCH = 64


def candidate_compliance(lu, z: np.ndarray, dofs: int) -> np.ndarray:
    """(n, n) C = P^T A_0^-1 P: the candidates' Z displacements under a unit Z force on
    each (P selects their Z dofs), from the factorization of A_0 (n solves, in batches
    of COMPLIANCE_BATCH right-hand sides)."""
    n = z.size
    compliance = np.empty((n, n))
    for first in range(0, n, COMPLIANCE_BATCH):
        columns = z[first:first + COMPLIANCE_BATCH]
        unit = np.zeros((dofs, columns.size))
        unit[columns, np.arange(columns.size)] = 1.0
        compliance[:, first:first + columns.size] = lu.solve(unit)[z]
    return 0.5 * (compliance + compliance.T)


def patch_iteration(lu, z, dofs, penalty_share, gap0, y0) -> np.ndarray:
    """The contact patch (n,) bool, found on the candidates' Z alone.

    A_0 holds every candidate's spring k_i. The patch S takes out the springs of the
    nodes off it; their action is put back as forces on those nodes, r_i = k_i g_i
    (cancelling the spring's -k_i g_i), so that

        u = A_0^-1 (f - P K g0) + A_0^-1 P r,     g = g0 + y0 + C r

    with y0 the candidates' Z in the first solve and C their compliance
    (candidate_compliance). Off the patch r_i = k_i g_i gives, on those nodes O,

        (K_O^-1 - C_OO) r_O = g0_O + y0_O

    a dense system of the nodes off the patch. The patch then changes as the
    primal-dual active set method (module docstring) says, until it settles: what
    solving the whole system for each patch gives, to rounding, at the cost of n solves
    and small dense ones instead of a factorization a patch. None where a patch comes
    back (the full steps cycle: static_preload goes on with damped_patch).
    """
    compliance = candidate_compliance(lu, z, dofs)
    active = np.ones(z.size, dtype=bool)
    gap = gap0 + y0
    seen = {active.tobytes()}
    while True:
        lifted = active & (gap > 0.0)
        touching = ~active & (gap < 0.0)
        if not (lifted.any() or touching.any()):
            break
        active = (active & ~lifted) | touching
        if not active.any():
            raise NormalLoadTooSmall("no contact node stays on the base under the preload")
        if active.tobytes() in seen:
            return None     # it comes back: the whole system's damped steps take over
        seen.add(active.tobytes())
        off = ~active
        system = np.diag(1.0 / penalty_share[off]) - compliance[np.ix_(off, off)]
        release = np.linalg.solve(system, gap0[off] + y0[off])
        gap = gap0 + y0 + compliance[:, off] @ release
    return active
