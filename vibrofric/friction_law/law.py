"""The per-node contact update over many nodes: the VFRIC analogue as a call.

Every increment the caller hands over, for each contact node, the slip
increment of the body relative to the base, the free-end increment of phase 2,
the normal force, the node's share of the contact area, and the node's state;
it gets back each node's friction force, the state updated in place. The
lumped model is the one-node case with area share 1.
"""

import numpy as np

from .contract import FASTMATH, ContactLaw
from .specialize import law_kernel


@law_kernel(cache=True, error_model="numpy", fastmath=FASTMATH)
def _contact_step(states, slip, free_end, normal_force, area_share, params, dt, force):
    for i in range(states.shape[0]):
        force[i, 0], force[i, 1] = law_update(  # noqa: F821 (the law's, specialize.py)
            slip[i, 0], slip[i, 1], free_end[i, 0], free_end[i, 1], normal_force[i],
            area_share[i], states[i], params, dt)


def contact_step(law: ContactLaw, states, slip, free_end, normal_force, area_share, dt, force=None):
    """Advance every contact node by one step; ``states`` (n, STATE_SIZE) is updated in place.

    slip         (n, 2) phase-1 slip increment (body minus base)
    free_end     (n, 2) phase-2 increment of the free end (eta_y dy_b in Y)
    normal_force (n,)   each node's normal force; <= 0 means no contact
    area_share   (n,)   each node's tributary area over the whole contact area
    Returns the (n, 2) friction force F (it acts on the body as -F).
    """
    if force is None:
        force = np.empty_like(slip)
    _contact_step.for_law(law.law)(states, slip, free_end, normal_force, area_share, law.params,
                                   dt, force)
    return force
