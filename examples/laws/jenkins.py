"""A Jenkins friction law: one spring in series with a Coulomb slider, in 2D.

The worked example of docs/friction-laws.md, written only against the public
contract (vibrofric.friction_law.contract). The node's state is the spring's
deformation vector d = (d_x, d_y); the friction force is F = k d, with
k = k_t w the node's share of the contact stiffness. The slider slips once
|F| reaches the Coulomb limit mu N, so d lives in the slip circle

    |d| <= r,   r = mu N / k      (the sliding length s_c of Dahl's law)

Each step, the VFRIC call:

    phase 1  the body end moves by the slip:        d <- d + (slip_x, slip_y)
    phase 2  the free end moves by (free_x, free_y): d <- d - (free_x, free_y)
             (the base carries the slider's far end: moving it by +f shortens
             d by f, as the paper's eq 33 writes d2 = d1 - (0, eta_y dy_b))
    return   if |d| > r, d <- r d / |d|   (the radial return: exact for a
             rate-independent slider, and the contract's rule for a normal
             force that dropped since the last step)

N <= 0 releases the spring (d = 0). Rate-independent and exact for any step:
ORDER is that of the two-phase split, 1. At a constant normal force it is
Dahl's law with dahl_exponent = 0. In a scene:

    [contact]
    law = "examples/laws/jenkins.py"
    k_t = 80e6
    mu = 0.1
"""

import math

from numba import njit

from vibrofric.friction_law import Bounds, Parameter

PARAMETERS = {
    "k_t": Parameter(80e6, "N/m", low=0.0, low_open=True,
                     doc="tangential stiffness of the whole contact"),
    "mu": Parameter(0.1, "", low=0.0, doc="Coulomb friction coefficient"),
}
STATE_SIZE = 2                 # the spring's deformation (d_x, d_y)
INITIAL_STATE = (0.0, 0.0)
ORDER = 1


@njit
def _return_to_circle(d_x, d_y, radius):
    """d brought back into the slip circle |d| <= radius along its own direction."""
    length = math.sqrt(d_x * d_x + d_y * d_y)
    if length > radius:
        scale = radius / length
        return d_x * scale, d_y * scale
    return d_x, d_y


def update(slip_x, slip_y, free_x, free_y, normal_force, area_share, state, params, dt):
    k = params[0] * area_share
    mu = params[1]
    if normal_force <= 0.0 or mu <= 0.0 or k <= 0.0:
        state[0] = state[1] = 0.0
        return 0.0, 0.0
    radius = mu * normal_force / k
    d_x, d_y = _return_to_circle(state[0], state[1], radius)    # the step's own N
    d_x, d_y = _return_to_circle(d_x + slip_x, d_y + slip_y, radius)   # phase 1
    d_x, d_y = _return_to_circle(d_x - free_x, d_y - free_y, radius)   # phase 2
    state[0], state[1] = d_x, d_y
    return k * d_x, k * d_y


def stored_energy(state, params, area_share):
    return 0.5 * params[0] * area_share * (state[0] * state[0] + state[1] * state[1])


def bounds(p, dt):
    """Sticking: the tangent is k_t; sliding: 0. Never past mu N."""
    return Bounds(stiffness=p.k_t, max_stiffness=p.k_t, friction_coefficient=p.mu,
                  max_friction_coefficient=p.mu, departure=1.0)


def steady_sliding_force(p, normal_force, v):
    return p.mu * normal_force


def deformation(states):
    """The spring's deformation, for ParaView."""
    return states
