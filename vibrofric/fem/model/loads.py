"""The normal load: gravity plus a uniform pressure on the top face (docs/model.md section 5).

Both are dead loads in -Z. Their nodal forces:

    gravity    f_z,i = -m_i g                (m_i the node's lumped mass: the
                                              consistent load int rho g phi_i dV)
    pressure   f_z,i = -p a_i                (a_i the node's tributary area on TOP)

with the pressure sized so that the static normal reaction of the base equals F_N:

    M g + p A_top = F_N   =>   p = (F_N - M g) / A_top,   M = rho V the block's mass.
"""

import numpy as np

from ...core.errors import NormalLoadTooSmall


def top_pressure(scene, block_mass: float, top_area: float) -> float:
    """The uniform top pressure p (Pa) that brings the normal reaction to F_N.

    A block heavier than F_N / g would need the top pulled up (p < 0): that is
    not the paper's load, and the run is refused.
    """
    weight = block_mass * scene.body.gravity
    pressure = (scene.contact.F_N - weight) / top_area
    if pressure < 0.0:
        raise NormalLoadTooSmall(f"normal load {scene.contact.F_N} N is less than the block's own weight "
                                        f"{weight:.4g} N ({block_mass:.4g} kg at g = {scene.body.gravity}"
                                        " m/s^2): the top would have to be pulled up instead of pressed")
    return pressure


def normal_load(mass: np.ndarray, top_area: np.ndarray, gravity: float, pressure: float) -> np.ndarray:
    """Nodal external forces (3 nodes,): gravity on every node, pressure on TOP, both -Z."""
    force = np.zeros_like(mass)
    force[2::3] = -mass[2::3] * gravity - pressure * top_area
    return force
