"""Closed forms of elastic contact against a rigid flat: the references the FE model is
checked against (docs/validation.md, "Curved contacts").

An elastic body (Young's modulus E, Poisson's ratio nu, shear modulus G = E / 2 (1 + nu))
pressed on a rigid flat, as in vibrofric's FE model (the base is rigid):

    E* = E / (1 - nu^2)          the plane-strain modulus (Johnson, Contact Mechanics,
                                 1985, eq 4.22 with the flat rigid)
    1 / G* = (2 - nu) / G        the tangential compliance's modulus (Johnson eq 7.42
                                 with the flat rigid)

Hertz, a sphere of radius R under the normal load P (Johnson section 4.2):

    a  = (3 P R / 4 E*)^(1/3)          contact radius             (eq 4.22)
    p0 = 3 P / (2 pi a^2)              peak pressure, at the centre
    d  = a^2 / R                       approach
    p(r) = p0 sqrt(1 - r^2 / a^2)

Hertz, a cylinder (roller) of radius R along its axis under P' per unit length, plane
strain (Johnson section 4.3):

    a  = 2 sqrt(P' R / pi E*)          half-width                 (eq 4.43)
    p0 = 2 P' / (pi a)

Cattaneo-Mindlin, the sphere held at P and pulled by a tangential force Q < mu P that
grows from 0 (Johnson section 7.2): an annulus c < r < a slips, the centre sticks,

    c     = a (1 - Q / mu P)^(1/3)                                  (eq 7.40)
    delta = 3 mu P / (16 G* a) [1 - (1 - Q / mu P)^(2/3)]           (eq 7.42)

delta the tangential displacement of the body far from the contact against the flat.

Mindlin-Deresiewicz, Q cycled between -Q* and +Q* at constant P (Johnson section 7.3):
each reversal starts a new Cattaneo-Mindlin process of twice the scale from the turning
point (the Masing rule), so the branch from +Q* down is

    delta_down(Q) = delta*(Q*) - 2 delta((Q* - Q) / 2),     delta* = delta(Q*)

and the branch up its mirror. The energy dissipated per cycle is the loop's area,

    W = int_{-Q*}^{Q*} (delta_down - delta_up) dQ = 4 Q* delta* - 8 int_0^{Q*} delta(x) dx

and with int_0^{Q*} delta dx = 3 mu P / (16 G* a) [Q* - (3 mu P / 5)(1 - (1 - q)^(5/3))],
q = Q* / mu P:

    W = 9 mu^2 P^2 / (10 G* a) [1 - (1 - q)^(5/3) - (5 q / 6)(1 + (1 - q)^(2/3))]   (eq 7.59)

which grows as W = mu^2 P^2 q^3 / (36 G* a) for small q (the bracket's series starts
at 5 q^3 / 162: the slipping annulus is thin) and reaches 3 mu^2 P^2 / (20 G* a) at
q = 1, where the whole contact slips at the turning points.

>>> a = hertz_radius(P=50.0, R=0.01, E=209e9, nu=0.3)
>>> round(a * 1e3, 4)                # mm
0.1178
>>> round(hertz_peak_pressure(P=50.0, R=0.01, E=209e9, nu=0.3) / 1e9, 3)   # GPa
1.722
>>> stick_radius(Q=0.0, mu=0.5, P=50.0, a=a) == a
True
"""

import math


def plane_strain_modulus(E: float, nu: float) -> float:
    """E* = E / (1 - nu^2): an elastic body against a rigid one (Johnson eq 4.22)."""
    return E / (1.0 - nu * nu)


def tangential_modulus(E: float, nu: float) -> float:
    """G* = G / (2 - nu), G = E / 2 (1 + nu): an elastic body against a rigid one
    (Johnson eq 7.42)."""
    return E / (2.0 * (1.0 + nu)) / (2.0 - nu)


def hertz_radius(P: float, R: float, E: float, nu: float) -> float:
    """Contact radius a = (3 P R / 4 E*)^(1/3) of a sphere on a rigid flat, m."""
    return (3.0 * P * R / (4.0 * plane_strain_modulus(E, nu))) ** (1.0 / 3.0)


def hertz_peak_pressure(P: float, R: float, E: float, nu: float) -> float:
    """Peak pressure p0 = 3 P / (2 pi a^2) of a sphere on a rigid flat, Pa."""
    return 3.0 * P / (2.0 * math.pi * hertz_radius(P, R, E, nu) ** 2)


def hertz_approach(P: float, R: float, E: float, nu: float) -> float:
    """Approach d = a^2 / R of a sphere on a rigid flat, m."""
    return hertz_radius(P, R, E, nu) ** 2 / R


def line_half_width(P_per_length: float, R: float, E: float, nu: float) -> float:
    """Half-width a = 2 sqrt(P' R / pi E*) of a cylinder on a rigid flat (plane strain), m."""
    return 2.0 * math.sqrt(P_per_length * R / (math.pi * plane_strain_modulus(E, nu)))


def line_peak_pressure(P_per_length: float, R: float, E: float, nu: float) -> float:
    """Peak pressure p0 = 2 P' / (pi a) of a cylinder on a rigid flat, Pa."""
    return 2.0 * P_per_length / (math.pi * line_half_width(P_per_length, R, E, nu))


def _loaded_fraction(Q: float, mu: float, P: float) -> float:
    """q = Q / mu P, refused outside [0, 1]: beyond mu P the whole contact slides."""
    q = Q / (mu * P)
    if not 0.0 <= q <= 1.0:
        raise ValueError(f"tangential load Q = {Q:g} N must lie in [0, mu P = {mu * P:g} N]")
    return q


def stick_radius(Q: float, mu: float, P: float, a: float) -> float:
    """Cattaneo-Mindlin stick radius c = a (1 - Q / mu P)^(1/3), m."""
    return a * (1.0 - _loaded_fraction(Q, mu, P)) ** (1.0 / 3.0)


def mindlin_displacement(Q: float, mu: float, P: float, a: float, E: float, nu: float) -> float:
    """Cattaneo-Mindlin tangential displacement delta = 3 mu P / (16 G* a)
    [1 - (1 - Q / mu P)^(2/3)] of a sphere on a rigid flat, m."""
    q = _loaded_fraction(Q, mu, P)
    return 3.0 * mu * P / (16.0 * tangential_modulus(E, nu) * a) * (1.0 - (1.0 - q) ** (2.0 / 3.0))


def mindlin_deresiewicz_dissipation(Q_amplitude: float, mu: float, P: float, a: float,
                                    E: float, nu: float) -> float:
    """Energy dissipated per cycle of Q between -Q* and +Q* at constant P (Johnson
    eq 7.59, derived in the module's docstring), J."""
    q = _loaded_fraction(Q_amplitude, mu, P)
    scale = 9.0 * (mu * P) ** 2 / (10.0 * tangential_modulus(E, nu) * a)
    return scale * (1.0 - (1.0 - q) ** (5.0 / 3.0)
                    - 5.0 * q / 6.0 * (1.0 + (1.0 - q) ** (2.0 / 3.0)))
