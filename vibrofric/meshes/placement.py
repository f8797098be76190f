"""The body placed on the base: translated along Z so that its lowest contact node lies
on z = 0, the base's plane (X and Y are left as drawn)."""

import numpy as np

from ..core.errors import BadBody
from .mesh_data import MeshData

# Heights closer than this fraction of the body's extent are equal: a node of the contact
# group at the body's bottom, written with a few digits, may differ from the lowest node
# by rounding (the block's contact face is 0 to the bit: fem/model/fe_model.py).
HEIGHT_TOLERANCE = 1e-9


def translation(data: MeshData, key: str = "body.mesh") -> tuple:
    """(0, 0, -z_c) with z_c the lowest contact node's height, after checking that no node
    of the body lies below it (the body would start inside the base)."""
    points = data.points
    contact = data.groups["contact"].nodes
    extent = float(np.ptp(points, axis=0).max())
    lowest_contact = float(points[contact, 2].min())
    lowest = int(np.argmin(points[:, 2]))
    depth = lowest_contact - float(points[lowest, 2])
    if depth > HEIGHT_TOLERANCE * extent:
        x, y, z = points[lowest]
        raise BadBody(f"the body would start inside the base: its node at ({x:.4g}, {y:.4g}, "
                      f"{z:.4g}) m lies {depth:.3g} m below the lowest node of its 'contact' group; "
                      "'contact' must hold the facets at the bottom of the body (the mesh's "
                      "-Z side, the base's)", key)
    return (0.0, 0.0, -lowest_contact if lowest_contact != 0.0 else 0.0)


def move(gmsh, data: MeshData, shift) -> None:
    """Translate the current gmsh model's nodes and ``data``'s points by ``shift``."""
    shift = np.asarray(shift, dtype=float)
    if not shift.any():
        return
    tags, coords, parametric = gmsh.model.mesh.getNodes()
    coords = np.asarray(coords).reshape(-1, 3) + shift
    for tag, xyz in zip(tags, coords):
        gmsh.model.mesh.setNode(int(tag), list(xyz), [])
    data.points = data.points + shift
