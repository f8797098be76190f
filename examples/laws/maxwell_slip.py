"""A Maxwell-slip friction law: several Jenkins elements in parallel.

A user's law for vibrofric, written only against the public contract
(vibrofric.friction_law.contract). Element j is a spring of stiffness
k_j = k_t / ELEMENTS in series with a Coulomb slider that slips once the
spring's force reaches its own share of the Coulomb limit,
phi_j mu F_N, the shares phi_j rising linearly (their sum is 1). So
the contact starts at stiffness k_t and yields gradually, element by
element, towards mu F_N: a "stick, then partial slip, then gross slip"
curve that Dahl's law rounds off.

Each element keeps its spring's deformation (2-vector): the state holds
2 ELEMENTS floats. Per step, per element: stretch the spring by the slip
(phase 1) and by minus the free-end's move (phase 2), then return it to
its slip circle |d_j| <= phi_j mu N / k_j (a radial return, exact for
the rate-independent slider). In a scene:

    [contact]
    law = "examples/laws/maxwell_slip.py"   # relative to the scene file
    k_t = 80e6
    mu = 0.1
"""

import math

import numpy as np
from numba import njit

from vibrofric.friction_law import Bounds, Parameter

ELEMENTS = 4

PARAMETERS = {
    "k_t": Parameter(80e6, "N/m", low=0.0, low_open=True,
                     doc="tangential stiffness of the whole contact (all elements)"),
    "mu": Parameter(0.1, "", low=0.0, doc="Coulomb friction coefficient of the whole contact"),
}
STATE_SIZE = 2 * ELEMENTS
INITIAL_STATE = (0.0,) * STATE_SIZE
ORDER = 1


@njit
def _share(j):
    """phi_j: the element's share of the Coulomb limit, rising linearly, summing to 1."""
    return 2.0 * (j + 1) / (ELEMENTS * (ELEMENTS + 1))


@njit
def _return_to_circle(dx, dy, radius):
    length = math.sqrt(dx * dx + dy * dy)
    if length > radius:
        scale = radius / length
        return dx * scale, dy * scale
    return dx, dy


def update(slip_x, slip_y, free_x, free_y, normal_force, area_share, state, params, dt):
    k = params[0] * area_share / ELEMENTS
    mu = params[1]
    if normal_force <= 0.0 or mu <= 0.0 or k <= 0.0:
        for i in range(STATE_SIZE):
            state[i] = 0.0
        return 0.0, 0.0
    f_x = f_y = 0.0
    for j in range(ELEMENTS):
        radius = _share(j) * mu * normal_force / k
        dx, dy = _return_to_circle(state[2 * j] + slip_x, state[2 * j + 1] + slip_y, radius)
        dx, dy = _return_to_circle(dx - free_x, dy - free_y, radius)
        state[2 * j], state[2 * j + 1] = dx, dy
        f_x += k * dx
        f_y += k * dy
    return f_x, f_y


def stored_energy(state, params, area_share):
    k = params[0] * area_share / ELEMENTS
    energy = 0.0
    for i in range(STATE_SIZE):
        energy += 0.5 * k * state[i] * state[i]
    return energy


def bounds(p, dt):
    """Every element sticking: k_t, the largest tangent too; no element exceeds its limit."""
    return Bounds(stiffness=p.k_t, max_stiffness=p.k_t, friction_coefficient=p.mu,
                  max_friction_coefficient=p.mu, departure=1.0)


def steady_sliding_force(p, normal_force, v):
    return p.mu * normal_force


def deformation(states):
    """The elements' mean spring deformation, for ParaView."""
    return np.asarray(states).reshape(len(states), ELEMENTS, 2).mean(axis=1)
