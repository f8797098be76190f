"""The per-node contact update: the VFRIC analogue.

Every increment the caller hands over, for each contact node, the slip
increment of the body relative to the base, the free-end increment of phase 2,
the normal force, the node's share of the contact area, and the node's state
(its asperity deformation vector); it gets back each node's friction force and
new state. The lumped model is the one-node case with area share 1.
"""

from dataclasses import dataclass

import numpy as np
from numba import njit

from .kernels import DAHL, EXACT, LUGRE, PAPER, node_step

LAWS = {"dahl": DAHL, "lugre": LUGRE}
UPDATES = {"paper": PAPER, "exact": EXACT}


@dataclass(frozen=True)
class FrictionLaw:
    """Parameters of the tangential law for the whole contact.

    k_t, h_t, h_v are for the whole contact and are shared out by area; the
    Coulomb limit mu F_n and the stiction F_s (as mu_s = F_s / F_N) are taken
    per node from its own normal force.
    """

    law: str = "dahl"
    update: str = "exact"
    mu: float = 0.1
    k_t: float = 80e6
    mu_s: float = 0.1
    v_s: float = 1e-3
    h_t: float = 0.0
    h_v: float = 0.0

    def steady_sliding_force(self, normal_force: float, v: float) -> float:
        """F once s has settled at constant v_r = v: g(v) + h_v v (Dahl: mu F_N)."""
        coulomb = self.mu * normal_force
        if self.law == "dahl":
            return coulomb
        stiction = self.mu_s * normal_force
        return coulomb + (stiction - coulomb) * np.exp(-((v / self.v_s) ** 2)) + self.h_v * v

    def kernel_args(self):
        """The scalar parameters in the order ``node_step`` takes them after the stiffness."""
        return (self.mu, self.mu_s, self.v_s, LAWS[self.law], UPDATES[self.update])


@dataclass
class AsperityState:
    """Each node's asperity: length s (n,) and unit direction e (n, 2) of d = N' - M."""

    length: np.ndarray
    direction: np.ndarray

    @classmethod
    def at_rest(cls, n: int) -> "AsperityState":
        """Undeformed asperities; the direction before any motion is X."""
        direction = np.zeros((n, 2))
        direction[:, 0] = 1.0
        return cls(np.zeros(n), direction)

    @property
    def deformation(self) -> np.ndarray:
        """The (n, 2) deformation vectors d = s e."""
        return self.length[:, None] * self.direction


@njit(cache=True, error_model="numpy")
def _contact_step(length, direction, slip, free_end, normal_force, area_share,
                  k_t, mu, mu_s, v_s, h_t, h_v, law, update, dt, force):
    for i in range(length.shape[0]):
        w = area_share[i]
        s, ex, ey, fx, fy = node_step(
            length[i], direction[i, 0], direction[i, 1], slip[i, 0], slip[i, 1],
            free_end[i, 0], free_end[i, 1], normal_force[i],
            k_t * w, mu, mu_s, v_s, h_t * w, h_v * w, law, update, dt)
        length[i] = s
        direction[i, 0] = ex
        direction[i, 1] = ey
        force[i, 0] = fx
        force[i, 1] = fy


def contact_step(law: FrictionLaw, state: AsperityState, slip, free_end, normal_force, area_share,
                 dt, force=None):
    """Advance every contact node by one step; ``state`` is updated in place.

    slip         (n, 2) phase-1 slip increment (body minus base)
    free_end     (n, 2) phase-2 increment of the free end (eta_y dy_b in Y)
    normal_force (n,)   each node's normal force; <= 0 means no contact
    area_share   (n,)   each node's tributary area over the whole contact area
    Returns the (n, 2) friction force F (it acts on the body as -F).
    """
    if force is None:
        force = np.empty_like(slip)
    mu, mu_s, v_s, code, update = law.kernel_args()
    _contact_step(state.length, state.direction, slip, free_end, normal_force, area_share,
                  law.k_t, mu, mu_s, v_s, law.h_t, law.h_v, code, update, dt, force)
    return force
