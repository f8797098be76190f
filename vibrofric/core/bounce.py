"""The block's bounce on its contact: the first mode of an elastic bar on a spring.

The FE block (fem/model/contact.py) stands on a penalty spring k_p for its whole
face, default 10 E A / L_z. Its first normal mode is the block as a uniform bar of
length L_z, free on top, on that spring: with u(z) = cos(beta (L_z - z)), the
spring's force at the bottom E A u'(0) = k_p u(0) gives

    (beta L_z) tan(beta L_z) = k_p L_z / (E A),     w_b = beta sqrt(E / rho)

(the longitudinal modes of a bar with a spring at one end, e.g. Rao, "Vibration
of Continuous Systems", Wiley 2007, chapter on longitudinal vibration). The lumped body of mass m bounces at the same frequency on

    k_n = m w_b^2

which is the rigid-block value k_p when the block is far stiffer than the spring
(k_p L_z / (E A) -> 0: beta L_z -> sqrt(k_p L_z / (E A))); at the default penalty
(k_p L_z / (E A) = 10) beta L_z = 1.43 and k_n = 0.204 k_p: on the paper's steel
block (0.5 kg, 30 x 40 x 53 mm) 22.1 kHz, where a rigid block on k_p would bounce
at 49 kHz.
"""

import math

PENALTY_FACTOR = 10.0   # fem/model/contact.py's default penalty, in E A / L_z


def default_penalty(E: float, size) -> float:
    """The FE contact's default penalty stiffness for the whole face, PENALTY_FACTOR E A / L_z."""
    Lx, Ly, Lz = size
    return PENALTY_FACTOR * E * Lx * Ly / Lz


def bar_on_spring_root(ratio: float) -> float:
    """x in (0, pi/2) with x tan(x) = ``ratio`` (> 0), by bisection to rounding."""
    low, high = 0.0, 0.5 * math.pi
    for _ in range(200):
        middle = 0.5 * (low + high)
        if middle * math.tan(middle) < ratio:
            low = middle
        else:
            high = middle
        if high - low <= 1e-15:
            break
    return 0.5 * (low + high)


def bounce_stiffness(mass: float, E: float, density: float, size, penalty: float) -> float:
    """k_n = m w_b^2, w_b the first bounce mode of the block (a bar of ``density``,
    Young's modulus E and edges ``size``) on the contact spring ``penalty`` (N/m)."""
    Lx, Ly, Lz = size
    x = bar_on_spring_root(penalty * Lz / (E * Lx * Ly))
    omega = x / Lz * math.sqrt(E / density)
    return mass * omega * omega
