"""Closed forms of F_dv/F_d0: the rigid Coulomb limit, and an elastic contact under an
oscillating indentation, with and without contact loss (normal_oscillation_ratio).

The rigid Coulomb limit (k_t -> infinity, body moved at exactly v_d).

With a rigid contact the friction force has the Coulomb magnitude F_c and the
direction of the relative velocity of body and free end, (v_d - v_bx,
-eta_y v_by) (phase 1 carries the base's X motion in full, phase 2 its Y motion
scaled by eta_y). Averaged over a cycle of v_b = v_a cos(phi) (cos theta,
sin theta):

    F_x / F_c = < (v_d - v_bx) / |(v_d - v_bx, eta_y v_by)| >_phi

Longitudinal (theta = 0): (2/pi) arcsin(1/k_v) for k_v > 1, else 1.
"""

import math

import numpy as np

QUADRATURE_POINTS = 200_000  # midpoint rule; the integrand jumps where v_r changes sign: error ~ 1/N


def longitudinal_ratio(k_v: float) -> float:
    """F_dv / F_d0 of rigid Coulomb friction under longitudinal vibration."""
    return 1.0 if k_v <= 1.0 else 2.0 / math.pi * math.asin(1.0 / k_v)


def coulomb_ratio(k_v: float, theta_deg: float, eta_y: float) -> float:
    """F_dv / F_d0 of rigid Coulomb friction for vibration along theta."""
    phi = (np.arange(QUADRATURE_POINTS) + 0.5) * (2.0 * math.pi / QUADRATURE_POINTS)
    theta = math.radians(theta_deg)
    v_bx = k_v * np.cos(phi) * math.cos(theta)  # in units of v_d
    v_by = k_v * np.cos(phi) * math.sin(theta)
    along = 1.0 - v_bx
    return float(np.mean(along / np.hypot(along, eta_y * v_by)))


def mean_contact_load(alpha: float) -> float:
    """The mean of max(0, 1 + alpha cos tau) over a cycle: the mean normal force of a
    linear contact (the flat punch's constant stiffness k_z) whose indentation swings as
    d_0 (1 + alpha cos w t), in units of k_z d_0. 1 while contact is kept (alpha <= 1);
    past it the contact carries only the arc |tau| < theta, cos theta = -1 / alpha:

        (theta + alpha sin theta) / pi"""
    if alpha <= 1.0:
        return 1.0
    theta = math.acos(-1.0 / alpha)
    return (theta + alpha * math.sin(theta)) / math.pi


def normal_oscillation_ratio(v_tilde: float, alpha: float) -> float:
    """<F_x> / (mu <N>) of an elastic-perfectly-plastic contact (a tangential spring k_x
    that slips at mu N) dragged at a constant velocity v_0 while its indentation swings
    as d = d_0 (1 + alpha cos w t) on a linear normal stiffness k_z, N = k_z max(0, d):
    the stiff system with a flat punch of Popov, Popov & Popov, "Reduction of friction by
    normal oscillations. I. Influence of contact stiffness", Friction 5 (2017) 45-55,
    doi 10.1007/s40544-016-0136-4 (the system far stiffer than the contact, the
    indentation prescribed, quasi-static), derived here for that model as its abstract
    describes it: the paper's own formulas and figures were not read (docs/validation.md).

    alpha = the indentation's amplitude over its mean (while contact is kept, alpha <= 1,
    the normal force's swing over its mean F_N = k_z d_0; past 1 the contact is lost over
    part of each cycle, the body "jumps"). v_tilde = k_x v_0 / (w mu k_z alpha d_0): the
    spring's loading rate over the fastest rise of the limit mu k_z d. In units of
    mu k_z d_0 and of the phase tau = w t the limit is l(tau) = max(0, 1 + alpha cos tau)
    and the spring, stuck, loads at alpha v_tilde. The force slides along the limit
    while the limit rises no faster than that, sin tau >= -v_tilde; it sticks from
    tau_1 = pi + arcsin v_tilde, rising on the line l(tau_1) + alpha v_tilde (tau - tau_1),
    until the limit comes down to it at tau_2:
    cos tau_2 - cos tau_1 = v_tilde (tau_2 - tau_1). Where the contact is lost (the
    limit 0 for cos tau < -1 / alpha) the spring is released, and it sticks again from
    the landing, tau_1 = pi + arccos(1 / alpha), where that comes later. The mean force
    falls short of the limit's mean, mean_contact_load(alpha), by the area between the
    two over the stick:

        A = alpha [sin tau_2 - sin tau_1 - (tau_2 - tau_1) cos tau_1
                   - v_tilde (tau_2 - tau_1)^2 / 2],
        ratio = 1 - A / (2 pi mean_contact_load(alpha))

    1 from v_tilde = 1 on (the spring outruns the limit: sliding throughout). As
    v_tilde -> 0 it tends to 1 - alpha in contact, and past contact loss to 0 as
    alpha theta^2 / (theta + alpha sin theta) v_tilde (cos theta = -1 / alpha): the
    spring, released every cycle, has no time to load. In contact alpha enters only as
    the factor, so the reduction over alpha depends on v_tilde alone."""
    if not alpha >= 0.0:
        raise ValueError(f"alpha {alpha}: the indentation's amplitude over its mean, >= 0")
    if v_tilde >= 1.0 or alpha == 0.0:
        return 1.0
    tau_1 = math.pi + math.asin(v_tilde)
    if alpha > 1.0:
        tau_1 = max(tau_1, math.pi + math.acos(1.0 / alpha))   # the landing

    def gap(tau):   # the limit above the stuck spring's line, over alpha (positive while stuck)
        return math.cos(tau) - math.cos(tau_1) - v_tilde * (tau - tau_1)

    # gap rises from 0 at tau_1 (<= 3 pi / 2, the landing too) while the limit rises
    # faster than the spring, up to 2 pi - arcsin v_tilde; a cycle on, the line is above
    # the limit
    low, high = 2.0 * math.pi - math.asin(v_tilde), tau_1 + 2.0 * math.pi  # gap > 0, <= 0
    for _ in range(200):            # bisection to the float's resolution
        middle = 0.5 * (low + high)
        if middle in (low, high):
            break
        low, high = (middle, high) if gap(middle) > 0.0 else (low, middle)
    tau_2 = low
    span = tau_2 - tau_1
    area = alpha * (math.sin(tau_2) - math.sin(tau_1) - span * math.cos(tau_1)
                    - 0.5 * v_tilde * span * span)
    return 1.0 - area / (2.0 * math.pi * mean_contact_load(alpha))
