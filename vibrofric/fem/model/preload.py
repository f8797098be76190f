"""The static preload: the block pressed on the base before anything moves.

Starting the dynamics from an unloaded block with the loads applied at once
sets it ringing on its contact (docs/model.md "Traps measured": the normal
force swung 44-69 N instead of 55 N). Instead every run starts from the static
equilibrium of the normal load on the penalty springs:

    (K + K_pen) u0 = f,     K_pen = diag(k_pen w_i) on the Z dofs of the contact nodes

with v = 0, the asperities at rest and the drive spring unstretched. The
contact is frictionless during the preload (the asperities start undeformed,
as the lumped model's), so the only loads are in Z; the three in-plane rigid
motions (X, Y, rotation about Z) that K + K_pen leaves free carry no load and
are pinned by tangential springs REGULARIZATION times weaker than the contact
stiffness k_t, which changes u0 by a relative ~1e-12.

A node that would be pulled (u_z > 0) is taken out of contact and the solve
repeated until the active set settles. The static reaction sum_i N_i must
equal the applied normal load F_N to solver precision.
"""

import numpy as np
import scipy.sparse as sp

from ...core.errors import NormalLoadTooSmall
from .linalg import symmetric_lu

REGULARIZATION = 1e-9
RELATIVE_TOLERANCE = 1e-8  # on sum N_i = F_N: a direct solve gives ~1e-12


def static_preload(stiffness, load, nodes, penalty_share, area_share, k_t, F_N, order=None):
    """Return (u0, normal): the static displacement (dofs,) and contact forces (n,).

    ``order``: the DOFs' elimination order for the factorization (linalg.symmetric_lu).

    Raises NormalLoadTooSmall if no node stays in contact.
    """
    dofs = stiffness.shape[0]
    active = np.ones(nodes.size, dtype=bool)
    for _ in range(nodes.size + 1):
        springs = np.zeros(dofs)
        springs[3 * nodes[active] + 2] = penalty_share[active]
        springs[3 * nodes] = springs[3 * nodes + 1] = REGULARIZATION * k_t * area_share
        u0 = symmetric_lu(stiffness + sp.diags(springs), order).solve(load)
        gap = u0[3 * nodes + 2]
        lifted = active & (gap > 0.0)
        if not lifted.any():
            break
        active &= ~lifted
        if not active.any():
            raise NormalLoadTooSmall("no contact node stays on the base under the preload")
    normal = np.where(active, penalty_share * np.maximum(-gap, 0.0), 0.0)
    if not np.isclose(normal.sum(), F_N, rtol=RELATIVE_TOLERANCE, atol=0.0):
        raise RuntimeError(f"the static normal reaction {normal.sum():.12g} N does not balance "
                           f"F_N = {F_N} N: the preload solve failed")
    return u0, normal
