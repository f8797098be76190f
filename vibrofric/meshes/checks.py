"""What a body's mesh must be before the FE model takes it, each failure one BadBody
(core/errors.py) naming the scene key to change and the reason:

    cells    3D first-order cells (tetrahedra, hexahedra), none inverted, flat or (a
             hexahedron) folded at a corner
    groups   a facet group named "contact" (and "load", "drive" facets where present),
             one volume group
    density  the mass over the mesh's volume a density of a real solid (a part drawn in
             millimetres in a scene in metres has a volume 1e9 times too large)
    memory   the FE model's estimated bytes within the machine's available memory

(Where the body lies against the base is meshes/placement.py's.)
"""

import os

import numpy as np

from ..core.errors import BadBody
from .mesh_data import (FIRST_ORDER_CELLS, HEXAHEDRON, OTHER_CELLS, MeshData, cell_volumes,
                        hexahedron_corner_jacobians)

# The densities of real solids, kg/m^3. The lightest a linear elastic body sliding on a
# base is made of: wood (balsa 100-200), polymer foams of structural grade (100+); the
# densest: osmium and iridium (22,600). A body outside this range by a factor 1e9 (or
# 1e-9) was drawn in other units than the scene's (mm against m); one just outside it
# sets body.density to say so.
DENSITY_RANGE = (100.0, 25000.0)

# The FE model's bytes per mesh node: 3 DOFs, each row of the stiffness holding up to
# 81 entries (a node of a hexahedral mesh couples to its 27 neighbours' 3 DOFs; of a
# tetrahedral one, to about 15), each 8 bytes of value and 4 of column index, kept three
# times (DOLFINx's PETSc matrix as assembled, its scipy copy and the model cache's):
# 3 x 81 x 12 x 3 = 8,748 bytes. A lower bound: the implicit integrators' factors take
# more; a mesh refused by it cannot run at all.
BYTES_PER_NODE = 3 * 81 * 12 * 3


def check_cells(data: MeshData, what: str) -> np.ndarray:
    """The cells' signed volumes, after refusing a mesh without 3D cells, with cells other
    than first-order tetrahedra or hexahedra, or with a cell of volume <= 0."""
    others = [OTHER_CELLS.get(t, f"gmsh element type {t}") for t in data.cells
              if t not in FIRST_ORDER_CELLS]
    if others:
        raise BadBody(f"{what} holds {', '.join(others)}: the FE model takes first-order "
                      "tetrahedra and hexahedra only (gmsh: Mesh.ElementOrder = 1, no prisms "
                      "or pyramids)")
    if not data.cells:
        raise BadBody(f"{what} has no 3D cells: a body is a volume mesh (gmsh: Mesh 3, "
                      "or a .geo ending in a volume)")
    volumes = cell_volumes(data)
    bad = int(np.count_nonzero(volumes <= 0.0))
    if HEXAHEDRON in data.cells:   # a hexahedron folded at a corner may keep a volume > 0
        corners = hexahedron_corner_jacobians(data.points, data.cells[HEXAHEDRON])
        folded = np.any(corners <= 0.0, axis=1) & (volumes[-len(corners):] > 0.0)
        bad += int(np.count_nonzero(folded))
    if bad:
        raise BadBody(f"{what} has {bad} of {len(volumes)} cells inverted, flat or folded (a "
                      "volume or a corner's Jacobian <= 0: their nodes in the wrong order or "
                      "crossed): remesh it, or reverse the inverted volumes")
    if np.ptp(data.points[:, 2]) == 0.0:
        raise BadBody(f"{what} is flat (every node at one height): a body is 3D")
    return volumes


def check_groups(data: MeshData, what: str) -> None:
    """A facet group "contact"; "load" and "drive", where present, facets too; one volume group."""
    contact = data.groups.get("contact")
    if contact is None:
        named = sorted(name for name in data.groups if not name.startswith("#"))
        raise BadBody(f"{what} has no physical group named 'contact' (the facets that may "
                      f"touch the base); its groups: {', '.join(named) or 'none'}")
    for name in ("contact", "load", "drive"):
        group = data.groups.get(name)
        if group is not None and group.dim != 2:
            raise BadBody(f"{what}: its group '{name}' is of dimension {group.dim}; it must "
                          "name facets (a Physical Surface)")
        if group is not None and len(group.nodes) == 0:
            raise BadBody(f"{what}: its group '{name}' holds no mesh facets")
    if len(data.cell_groups()) > 1:
        names = ", ".join(g.name or str(g.tag) for g in data.cell_groups())
        raise BadBody(f"{what} has {len(data.cell_groups())} volume groups ({names}): a body "
                      "is one elastic material, one Physical Volume")


def density_key(mass: float, volume: float, length_key: str) -> str:
    """The key to change for a density out of range: too light, the body's lengths
    (``length_key``: body.mesh, body.radius) were drawn in other units; too heavy, body.mass."""
    return length_key if mass / volume < DENSITY_RANGE[0] else "body.mass"


def check_density(mass: float, volume: float, what: str, key: str = "body.mesh") -> None:
    """Refuse a mass over volume outside DENSITY_RANGE, saying which units would fit."""
    density = mass / volume
    low, high = DENSITY_RANGE
    if low <= density <= high:
        return
    if low <= density * 1e9 <= high:   # a volume 1e9 times too large: lengths 1e3 times
        hint = ": drawn in millimetres? the scene's lengths are metres"
    elif density < low:
        hint = ": is it drawn in other units than metres?"
    else:
        hint = ": is the mass right for its size?"
    raise BadBody(f"{what} has a volume of {volume:.4g} m^3, so body.mass = {mass:g} kg gives a "
                  f"density of {density:.4g} kg/m^3, outside the range of real solids "
                  f"{low:g}-{high:g} kg/m^3{hint} (set body.density if the value is meant)", key)


def available_memory() -> int | None:
    """The machine's available memory in bytes (Linux's MemAvailable), None if unknown."""
    try:
        with open("/proc/meminfo") as meminfo:
            for line in meminfo:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return None


def check_memory(nodes: int, what: str, key: str = "fem.mesh", available=None) -> None:
    """Refuse a mesh whose FE model (nodes x BYTES_PER_NODE) exceeds the available memory."""
    available = available_memory() if available is None else available
    need = nodes * BYTES_PER_NODE
    if available is not None and need > available:
        raise BadBody(f"{what} has {nodes:,} nodes: its FE model needs at least {need / 2**30:.3g} "
                      f"GiB ({BYTES_PER_NODE:,} bytes a node), more than the "
                      f"{available / 2**30:.3g} GiB of memory available: take a coarser mesh",
                      key)
