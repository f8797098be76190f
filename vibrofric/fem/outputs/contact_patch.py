"""The contact patch: which candidate nodes touch the base, over what area, how hard.

From the nodes' normal forces N_i (model/contact.py) and tributary areas a_i
(assembly.Discretization.face_area["contact"]):

    nodes_in_contact   the count of candidates with N_i > 0 (closed)
    contact_area       sum of a_i over them, m^2
    peak_pressure      max_i N_i / a_i, Pa: the nodal pressure, each node's force over
                       its tributary area (the lumped traction; on a Hertzian patch it
                       reads the pressure at the node nearest the centre, which the
                       mesh's spacing there resolves: docs/fe-model.md "The contact patch")

and each node's contact state for the ParaView frames (contact_state):

    0 open    N_i = 0
    1 stick   closed, |F_i| < SLIP_FRACTION mu N_i
    2 slip    closed, |F_i| >= SLIP_FRACTION mu N_i

(mu the law's sliding coefficient). The Dahl law's force reaches mu N only as the
slip grows without end, F = mu N (1 - exp(-s / s_c)) from rest: it passes
SLIP_FRACTION = 0.98 after s = 3.9 s_c of slip, where the node slides at the law's
limit for all the outputs can tell.
"""

import numpy as np

SLIP_FRACTION = 0.98

OPEN, STICK, SLIP = 0, 1, 2


def patch(contact_area: np.ndarray, normal: np.ndarray) -> dict:
    """nodes_in_contact, contact_area (m^2) and peak_pressure (Pa) of the nodal normal
    forces ``normal`` (n,) on nodes of tributary areas ``contact_area`` (n,)."""
    closed = normal > 0.0
    return {"contact_area": float(contact_area[closed].sum()),
            "peak_pressure": float((normal / contact_area).max(initial=0.0)),
            "nodes_in_contact": int(closed.sum())}


def patch_range(contact_area: np.ndarray, node_normals: np.ndarray) -> dict:
    """Each of patch's keys as [min, max] over the samples of ``node_normals``
    (samples, n): a steady cycle's range (None without samples)."""
    samples = [patch(contact_area, normal) for normal in node_normals]
    if not samples:
        return {f"{key}_range": None for key in ("contact_area", "peak_pressure",
                                                   "nodes_in_contact")}
    return {f"{key}_range": [min(s[key] for s in samples), max(s[key] for s in samples)]
            for key in samples[0]}


def contact_state(normal: np.ndarray, friction: np.ndarray, mu: float) -> np.ndarray:
    """(n,) OPEN, STICK or SLIP of each node from its normal force (n,) and friction
    force (n, 2), against the law's sliding coefficient ``mu``."""
    closed = normal > 0.0
    sliding = np.hypot(friction[:, 0], friction[:, 1]) >= SLIP_FRACTION * mu * normal
    return np.where(closed, np.where(sliding, SLIP, STICK), OPEN)
