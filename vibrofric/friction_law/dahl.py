"""Dahl's friction law (paper eqs 1-6), with the shape exponent i of eq 2.

dF/dx = k (1 - (F / F_c) sgn(v_r))^i, F_c = mu F_N: the force rises from 0
with stiffness k towards the Coulomb limit F_c. i = 1 is the paper's value;
i < 1 reaches F_c in a finite slip (i = 0: linear up to F_c, "brittle"),
i > 1 approaches it ever more slowly ("ductile"; paper Fig 2). In terms of
the asperity length s = F / k this is asperity.relax_length, along the
direction of the two-phase update (asperity.py).
"""

from numba import njit

from . import asperity
from .asperity import NORMAL_CHANGES, UPDATES, relax_length, to_normal_force, trial
from .contract import FASTMATH, Bounds, Parameter

PARAMETERS = {
    **asperity.PARAMETERS,   # k_t, mu, update, normal_change
    "dahl_exponent": Parameter(1.0, "", low=0.0, high=10.0,
                               doc="Dahl's shape exponent i (eq 2): 0 brittle, 1 the paper's, "
                                   "up to 2 ductile"),
}
deformation = asperity.deformation  # the contract's ParaView field: s e
STATE_SIZE = asperity.STATE_SIZE        # (s, e_x, e_y, s_c): length, direction, last s_c
INITIAL_STATE = asperity.INITIAL_STATE
ORDER = 1                       # the two-phase split is first order in dt


@njit(cache=True, error_model="numpy", fastmath=FASTMATH, inline="always")
def _phase(s, ex, ey, trial_x, trial_y, s_c, exponent, update):
    """One phase: stretch the asperity to the trial vector, relax its length (eqs 18-22, 31-35)."""
    length, ex, ey = trial(s, ex, ey, trial_x, trial_y)
    s_new = relax_length(s, length - s, s_c, exponent, update)
    if s_new < 0.0:  # relaxed through zero: the direction turns round
        s_new, ex, ey = -s_new, -ex, -ey
    return s_new, ex, ey


def update(slip_x, slip_y, free_x, free_y, normal_force, area_share, state, params, dt):
    stiffness = params[0] * area_share
    mu, scheme, exponent, rule = params[1], params[2], params[3], params[4]
    if normal_force <= 0.0 or mu <= 0.0 or stiffness <= 0.0:
        # Out of contact, frictionless or without area: no force, the asperity released.
        state[0] = 0.0
        state[3] = 0.0
        return 0.0, 0.0
    compliance = 1.0 / stiffness
    s_c = mu * normal_force * compliance        # sliding length F_c / k (eqs 3, 6)
    # The step's own normal force (contract: a changing normal force).
    s = to_normal_force(state[0], state[3], s_c, 1.0, rule)
    ex, ey = state[1], state[2]
    # Phase 1 (eqs 18-22): the body end moves by the slip, the free end M stays.
    if slip_x != 0.0 or slip_y != 0.0:
        s, ex, ey = _phase(s, ex, ey, s * ex + slip_x, s * ey + slip_y, s_c, exponent, scheme)
    # Phase 2 (eqs 28-35): M moves by eta_y dy_b; d2 = s' e1 - (0, eta_y dy_b) (eq 33).
    if free_x != 0.0 or free_y != 0.0:
        s, ex, ey = _phase(s, ex, ey, s * ex - free_x, s * ey - free_y, s_c, exponent, scheme)
    state[0], state[1], state[2], state[3] = s, ex, ey, s_c
    force = stiffness * s                       # eq 1
    return force * ex, force * ey


def stored_energy(state, params, area_share):
    return 0.5 * params[0] * area_share * state[0] * state[0]


def compiled_parameters(p):
    return (p.k_t, p.mu, float(UPDATES.index(p.update)), p.dahl_exponent,
            float(NORMAL_CHANGES.index(p.normal_change)))


def bounds(p, dt):
    """The tangent dF/dx = k r^i with r in [0, 2]: k at rest, up to 2^i k (reversal at -F_c).
    Under normal_change = "keep" an asperity past a dropped limit holds up to the limit of
    the largest normal force it has seen: the bound says mu, which holds for "return" and
    "scale" only."""
    top = 2.0 ** p.dahl_exponent
    return Bounds(stiffness=p.k_t, max_stiffness=p.k_t * top, friction_coefficient=p.mu,
                  max_friction_coefficient=p.mu, departure=max(1.0, top - 1.0))


def steady_sliding_force(p, normal_force, v):
    return p.mu * normal_force

