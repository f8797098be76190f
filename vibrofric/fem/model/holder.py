"""The holder: the drive's attachment group moving as one rigid translation.

A ball-on-flat or pin-on-flat tribometer (and Cattaneo and Mindlin's ball) holds the
body in a holder that presses it down and pulls it along without letting it turn. In
the FE model, ``drive.holder = "translating"`` makes the nodes a of the drive's
attachment group (drive.py: its weights w_a, sum 1) move together, the penalty form
of a kinematic coupling of their three translations to one reference point (Abaqus'
*COUPLING, KINEMATIC with the rotations left out): springs tie each node's
displacement to the group's weighted mean u_bar = sum_b w_b u_b, storing

    E_hold = k_hold / 2 sum_a w_a |u_a - u_bar|^2,

whose stiffness is k_hold (W - w w^T) on each of X, Y and Z (W = diag(w)). A rigid
translation of the group stores nothing: the drive moves the group, the load presses
it, freely. Any rotation or distortion of the group stretches the ties; the group's
tilt theta about X or Y costs k_hold sum_a w_a r_a^2 theta^2 / 2 (r_a the lever arm
from the group's centre), so the moment the contact makes under the drive is carried
by the holder instead of turning the body.

The ties are part of the body's stiffness: the static preload (preload.py) is solved
with them, so it is the held body's static state, and every integrator, the stable
step and the damping C = beta (K + K_pen) see them as they see K.

k_hold is HOLD_FACTOR times the sum of the stiffness matrix's diagonal over the
group's degrees of freedom (the mean over X, Y, Z): node a's tie, k_hold w_a (1 - w_a),
is then about its own diagonal entry K_aa (where K_aa grows with the node's area, as
w_a does), as stiff as the layer of elements beneath the group. That holds the group
rigid against the body (whose tilting under the contact's moment is resisted by the
small contact patch, orders of magnitude softer), and raises the highest frequency
of the group's nodes by at most sqrt(2): the explicit step is set at the contact's
refined elements on the built-in shapes, not at their holder.
"""

import numpy as np
import scipy.sparse as sp

HOLD_FACTOR = 1.0


def hold_stiffness(stiffness: sp.spmatrix, nodes: np.ndarray) -> float:
    """k_hold, N/m: HOLD_FACTOR times the group's mean (over X, Y, Z) diagonal sum."""
    diagonal = stiffness.diagonal()
    return HOLD_FACTOR * float(np.mean([diagonal[3 * nodes + c].sum() for c in range(3)]))


def holder_stiffness(nodes: np.ndarray, weights: np.ndarray, k_hold: float,
                     dofs: int) -> sp.csr_matrix:
    """The ties' stiffness k_hold (W - w w^T) on each of X, Y, Z of ``nodes`` (weights
    ``weights``, sum 1), as a (dofs, dofs) CSR matrix: symmetric, positive semi-definite,
    zero on a common translation of the nodes."""
    block = k_hold * (np.diag(weights) - np.outer(weights, weights))
    rows, cols = np.meshgrid(nodes, nodes, indexing="ij")
    parts = [sp.coo_matrix((block.ravel(), (3 * rows.ravel() + c, 3 * cols.ravel() + c)),
                           shape=(dofs, dofs)) for c in range(3)]
    return sum(parts[1:], parts[0]).tocsr()


def held(stiffness: sp.csr_matrix, nodes: np.ndarray, weights: np.ndarray) -> sp.csr_matrix:
    """``stiffness`` with the holder's ties on ``nodes`` added (module docstring)."""
    k_hold = hold_stiffness(stiffness, nodes)
    return (stiffness + holder_stiffness(nodes, weights, k_hold, stiffness.shape[0])).tocsr()
