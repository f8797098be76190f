"""Dahl's law (vibrofric.friction_law.dahl, "return" rule) fed a constant normal
force: each node's nominal share F_N w of the contact, whatever its own N_i in the
FE model (only N_i <= 0 still releases it). For benchmarks/pitch_check.py: the
block still pitches in the FE dynamics, but the law no longer sees the swing of
the nodes' normal forces that the pitching causes. At a constant normal force
(the lumped model) it is Dahl's law bit for bit."""
from vibrofric.friction_law import Bounds, Parameter
from vibrofric.friction_law.dahl import _phase
from vibrofric.friction_law.asperity import to_normal_force, UPDATES

PARAMETERS = {
    "k_t": Parameter(80e6, "N/m", low=0.0, low_open=True, doc="tangential stiffness of the whole contact"),
    "mu": Parameter(0.1, "", low=0.0, doc="Coulomb friction coefficient"),
    "update": Parameter("exact", choices=UPDATES, doc="as Dahl's"),
    "dahl_exponent": Parameter(1.0, "", low=0.0, high=10.0, doc="Dahl's shape exponent"),
    "nominal_normal_force": Parameter(55.0, "N", low=0.0, doc="F_N the law sees, shared by area"),
}
STATE_SIZE = 4
INITIAL_STATE = (0.0, 1.0, 0.0, 0.0)
ORDER = 1


def update(slip_x, slip_y, free_x, free_y, normal_force, area_share, state, params, dt):
    stiffness = params[0] * area_share
    mu, scheme, exponent = params[1], params[2], params[3]
    if normal_force <= 0.0:
        state[0] = 0.0
        state[3] = 0.0
        return 0.0, 0.0
    s_c = mu * params[4] * area_share / stiffness
    s = to_normal_force(state[0], state[3], s_c, 1.0, 0)
    ex, ey = state[1], state[2]
    if slip_x != 0.0 or slip_y != 0.0:
        s, ex, ey = _phase(s, ex, ey, s * ex + slip_x, s * ey + slip_y, s_c, exponent, scheme)
    if free_x != 0.0 or free_y != 0.0:
        s, ex, ey = _phase(s, ex, ey, s * ex - free_x, s * ey - free_y, s_c, exponent, scheme)
    state[0], state[1], state[2], state[3] = s, ex, ey, s_c
    force = stiffness * s
    return force * ex, force * ey


def stored_energy(state, params, area_share):
    return 0.5 * params[0] * area_share * state[0] * state[0]


def compiled_parameters(p):
    return (p.k_t, p.mu, float(UPDATES.index(p.update)), p.dahl_exponent, p.nominal_normal_force)


def bounds(p, dt):
    top = 2.0 ** p.dahl_exponent
    return Bounds(stiffness=p.k_t, max_stiffness=p.k_t * top, friction_coefficient=p.mu,
                  max_friction_coefficient=p.mu * 3.0, departure=max(1.0, top - 1.0))


def steady_sliding_force(p, normal_force, v):
    return p.mu * normal_force


def deformation(states):
    return states[:, :1] * states[:, 1:3]
