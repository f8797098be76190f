"""The LuGre law (paper section 5, eqs 42-47) on the same asperity as Dahl.

The sliding length follows the Stribeck curve of the step's relative
velocity v_r, g(v_r) = F_c + (F_s - F_c) exp(-(v_r / v_s)^2) (eq 43), and the
force adds contact and viscous damping (eqs 46-47):

    F = k s + h_t ds/dt + h_v v_r

With h_t = h_v = 0 and F_s = F_c it is Dahl's law with i = 1, bit for bit.
"""

import math

from numba import njit

from . import asperity
from .asperity import NORMAL_CHANGES, UPDATES, relax_length, to_normal_force, trial
from .contract import FASTMATH, Bounds, Parameter

PARAMETERS = {
    **asperity.PARAMETERS,   # k_t, mu, update, normal_change
    "F_s": Parameter(None, "N", low=0.0, doc="stiction force of the whole contact; default mu F_N"),
    "v_s": Parameter(1e-3, "m/s", low=0.0, low_open=True, doc="Stribeck velocity"),
    "h_t": Parameter(0.0, "N s/m", low=0.0, doc="contact damping of the whole contact"),
    "h_v": Parameter(0.0, "N s/m", low=0.0, doc="viscous damping of the whole contact"),
}
deformation = asperity.deformation  # the contract's ParaView field: s e
STATE_SIZE = asperity.STATE_SIZE        # (s, e_x, e_y, s_c): length, direction, last s_c
INITIAL_STATE = asperity.INITIAL_STATE
ORDER = 1


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def stribeck_limit(v_r, coulomb, stiction, v_s):
    """LuGre's sliding limit g(v_r) = F_c + (F_s - F_c) exp(-(v_r / v_s)^2) (eq 43), as a length."""
    return coulomb + (stiction - coulomb) * math.exp(-((v_r / v_s) ** 2))


@njit(cache=True, error_model="numpy", fastmath=FASTMATH, inline="always")
def _phase(s, ex, ey, trial_x, trial_y, s_c, s_s, v_s, scheme, dt):
    """One phase (eqs 44-45): stretch to the trial vector; relax towards g(v_r) / k.
    Returns (s, ex, ey, |trial|)."""
    length, ex, ey = trial(s, ex, ey, trial_x, trial_y)
    stretch = length - s
    s_new = relax_length(s, stretch, stribeck_limit(stretch / dt, s_c, s_s, v_s), 1.0, scheme)
    if s_new < 0.0:
        s_new, ex, ey = -s_new, -ex, -ey
    return s_new, ex, ey, length


def update(slip_x, slip_y, free_x, free_y, normal_force, area_share, state, params, dt):
    stiffness = params[0] * area_share
    mu, scheme, mu_s, v_s = params[1], params[2], params[3], params[4]
    h_t, h_v, rule = params[5] * area_share, params[6] * area_share, params[7]
    if normal_force <= 0.0 or mu <= 0.0 or stiffness <= 0.0:
        state[0] = 0.0
        state[3] = 0.0
        return 0.0, 0.0
    compliance = 1.0 / stiffness
    s_c = mu * normal_force * compliance
    s_s = mu_s * normal_force * compliance
    # The step's own normal force (contract): the Stribeck curve g(v_r) / k reaches at
    # most max(s_c, s_s) = max(1, F_s / F_c) s_c.
    s0 = s = to_normal_force(state[0], state[3], s_c, max(1.0, mu_s / mu), rule)
    ex, ey = state[1], state[2]
    if slip_x != 0.0 or slip_y != 0.0:
        s, ex, ey, _ = _phase(s, ex, ey, s * ex + slip_x, s * ey + slip_y, s_c, s_s, v_s, scheme, dt)
    trial_length = s
    if free_x != 0.0 or free_y != 0.0:
        s, ex, ey, trial_length = _phase(s, ex, ey, s * ex - free_x, s * ey - free_y,
                                         s_c, s_s, v_s, scheme, dt)
    state[0], state[1], state[2], state[3] = s, ex, ey, s_c
    # eqs 46-47: contact damping on ds/dt and viscous damping on
    # v_r = (|N'_1 M'_2| - s) / dt, both over the whole step.
    force = stiffness * s
    force += h_t * (s - s0) / dt + h_v * (trial_length - s0) / dt
    return force * ex, force * ey


def stored_energy(state, params, area_share):
    return 0.5 * params[0] * area_share * state[0] * state[0]


def _stiction(p):
    return p.mu * p.F_N if p.F_s is None else p.F_s


def compiled_parameters(p):
    return (p.k_t, p.mu, float(UPDATES.index(p.update)), _stiction(p) / p.F_N, p.v_s, p.h_t, p.h_v,
            float(NORMAL_CHANGES.index(p.normal_change)))


def bounds(p, dt):
    """Dahl's tangent range [0, 2 k], plus the Stribeck term (g changing with the step's
    slip: at most sqrt(2/e) (F_s - F_c) / F_c, at v_r = v_s / sqrt 2) and the dampings
    (h_t ds + h_v dv_r) / dt: (2 h_t + h_v) / (k dt)."""
    coulomb = p.mu * p.F_N
    stiction = _stiction(p)
    stribeck = math.sqrt(2.0 / math.e) * abs(stiction - coulomb) / max(coulomb, 1e-300)
    return Bounds(stiffness=p.k_t, max_stiffness=2.0 * p.k_t, friction_coefficient=p.mu,
                  max_friction_coefficient=max(p.mu, stiction / p.F_N),
                  departure=1.0 + stribeck + (2.0 * p.h_t + p.h_v) / (p.k_t * dt))


def steady_sliding_force(p, normal_force, v):
    """g(v) + h_v v, with F_s scaled to the node's normal force."""
    coulomb = p.mu * normal_force
    stiction = _stiction(p) / p.F_N * normal_force
    return coulomb + (stiction - coulomb) * math.exp(-((v / p.v_s) ** 2)) + p.h_v * v
