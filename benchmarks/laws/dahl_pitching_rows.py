"""Dahl's law ("return" rule) on the five rows of contact nodes of a rigid block
that pitches quasi-statically, for the lumped stepper (benchmarks/pitch_check.py).
Row r (at xi_r = -1, -0.5, 0, 0.5, 1 along X from the back to the front, area
share w_r = 1/8, 1/4, 1/4, 1/4, 1/8 as on the default mesh) carries

    N_r = N w_r (1 + pitch xi_r F / F_c + tilt xi_r)

with F the previous step's summed friction force and F_c = mu N: the contact
pressure shifts to the front as the friction force rises, as the FE model's
block does. pitch = tilt = 0: Dahl's law bit for bit."""
from numba import njit

from vibrofric.friction_law import Bounds, Parameter
from vibrofric.friction_law.dahl import _phase
from vibrofric.friction_law.asperity import to_normal_force, UPDATES

PARAMETERS = {
    "k_t": Parameter(80e6, "N/m", low=0.0, low_open=True, doc="tangential stiffness of the whole contact"),
    "mu": Parameter(0.1, "", low=0.0, doc="Coulomb friction coefficient"),
    "update": Parameter("exact", choices=UPDATES, doc="as Dahl's"),
    "dahl_exponent": Parameter(1.0, "", low=0.0, high=10.0, doc="Dahl's shape exponent"),
    "pitch": Parameter(0.0, "", doc="a row's normal-force swing per xi and per F / F_c"),
    "tilt": Parameter(0.0, "", doc="a row's constant normal-force offset per xi"),
}
ROWS = 5
STATE_SIZE = 4 * ROWS + 1
INITIAL_STATE = (0.0, 1.0, 0.0, 0.0) * ROWS + (0.0,)
ORDER = 1


@njit
def _row(r):
    xi = -1.0 + 0.5 * r
    w = 0.125 if (r == 0 or r == ROWS - 1) else 0.25
    return xi, w


def update(slip_x, slip_y, free_x, free_y, normal_force, area_share, state, params, dt):
    mu, scheme, exponent, alpha, beta = params[1], params[2], params[3], params[4], params[5]
    if normal_force <= 0.0 or mu <= 0.0:
        for j in range(STATE_SIZE):
            state[j] = 0.0
        return 0.0, 0.0
    f_c = mu * normal_force
    F_prev = state[4 * ROWS]
    fx = fy = 0.0
    for r in range(ROWS):
        xi, w = _row(r)
        stiffness = params[0] * area_share * w
        n_r = normal_force * w * (1.0 + alpha * xi * F_prev / f_c + beta * xi)
        j = 4 * r
        if n_r <= 0.0:
            state[j] = 0.0
            state[j + 3] = 0.0
            continue
        s_c = mu * n_r / stiffness
        s = to_normal_force(state[j], state[j + 3], s_c, 1.0, 0)
        ex, ey = state[j + 1], state[j + 2]
        if slip_x != 0.0 or slip_y != 0.0:
            s, ex, ey = _phase(s, ex, ey, s * ex + slip_x, s * ey + slip_y, s_c, exponent, scheme)
        if free_x != 0.0 or free_y != 0.0:
            s, ex, ey = _phase(s, ex, ey, s * ex - free_x, s * ey - free_y, s_c, exponent, scheme)
        state[j], state[j + 1], state[j + 2], state[j + 3] = s, ex, ey, s_c
        fx += stiffness * s * ex
        fy += stiffness * s * ey
    state[4 * ROWS] = fx
    return fx, fy


def stored_energy(state, params, area_share):
    e = 0.0
    for r in range(ROWS):
        w = _row(r)[1]
        e += 0.5 * params[0] * area_share * w * state[4 * r] ** 2
    return e


def compiled_parameters(p):
    return (p.k_t, p.mu, float(UPDATES.index(p.update)), p.dahl_exponent, p.pitch, p.tilt)


def bounds(p, dt):
    top = 2.0 ** p.dahl_exponent
    return Bounds(stiffness=p.k_t, max_stiffness=p.k_t * top, friction_coefficient=p.mu,
                  max_friction_coefficient=p.mu * 2.0, departure=max(1.0, top - 1.0))


def steady_sliding_force(p, normal_force, v):
    return p.mu * normal_force
