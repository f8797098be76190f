"""The rigid Coulomb limit (k_t -> infinity, body moved at exactly v_d).

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
