"""The normal load: gravity plus a uniform pressure on the body's "load" group (docs/model.md section 5).

Both are dead loads in -Z. Their nodal forces:

    gravity    f_z,i = -m_i g                (m_i the node's lumped mass: the
                                              consistent load int rho g phi_i dV)
    pressure   f_z,i = -p a_i                (a_i the node's tributary area on the
                                              group "load": the block's top face)

with the pressure sized so that the static normal reaction of the base equals F_N:

    M g + p A_load = F_N   =>   p = (F_N - M g) / A_load,   M = rho V the body's mass.

A body without a "load" group carries its weight alone: F_N must then be M g.
"""

import numpy as np

from ...core.errors import NormalLoadTooSmall


# F_N and the weight M g of a body without a load group agree within this (relative):
# the weight rho V g rounds differently from the F_N a user computed from the same values.
WEIGHT_TOLERANCE = 1e-9


def load_pressure(scene, body_mass: float, load_area, body: str = "") -> float:
    """The uniform pressure p (Pa) on the load group that brings the normal reaction to
    F_N; ``load_area`` (nodes,) its nodes' tributary areas, None for a body without one
    (p = 0, and F_N must be its weight). Refuses (NormalLoadTooSmall) a load that
    would pull (a body heavier than F_N / g) and a body without a load group whose
    weight is not F_N (``body`` names it).
    """
    weight = body_mass * scene.body.gravity
    if load_area is None:
        if not np.isclose(scene.contact.F_N, weight, rtol=WEIGHT_TOLERANCE, atol=0.0):
            raise NormalLoadTooSmall(
                f"the body's mesh ({body}) has no \"load\" facet group, so only its weight "
                f"{weight:.6g} N presses it on the base, not F_N = {scene.contact.F_N} N: add a "
                "\"load\" group to its mesh, or set contact.F_N to the weight")
        return 0.0
    return top_pressure(scene, body_mass, load_area.sum())


def top_pressure(scene, block_mass: float, top_area: float) -> float:
    """The uniform top pressure p (Pa) that brings the normal reaction to F_N.

    A body heavier than F_N / g would need the load surface pulled up (p < 0): that
    is not the paper's load, and the run is refused.
    """
    weight = block_mass * scene.body.gravity
    pressure = (scene.contact.F_N - weight) / top_area
    if pressure < 0.0:
        raise NormalLoadTooSmall(f"normal load {scene.contact.F_N} N is less than the body's own weight "
                                        f"{weight:.4g} N ({block_mass:.4g} kg at g = {scene.body.gravity}"
                                        " m/s^2): its load surface would have to be pulled up instead of pressed")
    return pressure


def normal_load(mass: np.ndarray, load_area, gravity: float, pressure: float) -> np.ndarray:
    """Nodal external forces (3 nodes,): gravity on every node, the pressure on the load
    group (``load_area``: its nodes' tributary areas, None for none), both -Z."""
    force = np.zeros_like(mass)
    if load_area is None:
        force[2::3] = -mass[2::3] * gravity
    else:
        force[2::3] = -mass[2::3] * gravity - pressure * load_area
    return force
