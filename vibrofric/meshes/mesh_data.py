"""A mesh read out of gmsh as plain arrays, and the volumes of its cells.

``read_model`` takes the current gmsh model's nodes, its 3D cells by gmsh element
type and its physical groups (name, dimension, tag, nodes), so that the checks
(meshes/checks.py), the placement (meshes/placement.py) and the volume work on
numpy arrays, not on gmsh calls.
"""

import itertools
from dataclasses import dataclass, field

import numpy as np

# gmsh element types: first-order 3D cells the FE model takes, and the others a file may hold.
TETRAHEDRON, HEXAHEDRON = 4, 5
FIRST_ORDER_CELLS = {TETRAHEDRON: "tetrahedra", HEXAHEDRON: "hexahedra"}
OTHER_CELLS = {6: "prisms", 7: "pyramids", 11: "second-order tetrahedra (10 nodes)",
               12: "second-order hexahedra (27 nodes)", 17: "second-order hexahedra (20 nodes)",
               18: "second-order prisms", 19: "second-order pyramids"}


@dataclass
class Group:
    """A physical group: its dimension, tag, name and the indices of its nodes."""

    dim: int
    tag: int
    name: str
    nodes: np.ndarray


@dataclass
class MeshData:
    """points (n, 3) m; cells {gmsh element type: (m, k) node indices}; groups {name: Group}
    (unnamed groups under "#dim/tag")."""

    points: np.ndarray
    cells: dict
    groups: dict = field(default_factory=dict)

    def facet_groups(self) -> dict:
        """{name: tag} of the named 2D groups."""
        return {g.name: g.tag for g in self.groups.values() if g.dim == 2 and g.name}

    def cell_groups(self) -> list:
        return [g for g in self.groups.values() if g.dim == 3]


def read_model(gmsh) -> MeshData:
    """The current gmsh model's mesh: every node, the 3D cells, the physical groups."""
    model = gmsh.model
    tags, coords, _ = model.mesh.getNodes()
    points = np.asarray(coords, dtype=float).reshape(-1, 3)
    index = np.full(int(tags.max()) + 1 if len(tags) else 1, -1, dtype=np.int64)
    index[np.asarray(tags, dtype=np.int64)] = np.arange(len(tags))
    cells = {}
    types, _, nodes = model.mesh.getElements(3)
    for etype, enodes in zip(types, nodes):
        per_cell = model.mesh.getElementProperties(etype)[3]
        cells[int(etype)] = index[np.asarray(enodes, dtype=np.int64)].reshape(-1, per_cell)
    groups = {}
    for dim, tag in model.getPhysicalGroups():
        name = model.getPhysicalName(dim, tag)
        group_nodes, _ = model.mesh.getNodesForPhysicalGroup(dim, tag)
        key = name or f"#{dim}/{tag}"
        groups[key] = Group(dim, tag, name, index[np.asarray(group_nodes, dtype=np.int64)])
    return MeshData(points, cells, groups)


# The eight corners of the reference hexahedron in gmsh's node order (bottom, then top, both
# counter-clockwise seen from +z).
_HEX_CORNERS = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                         [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], dtype=float)


def tetrahedron_volumes(points, tets) -> np.ndarray:
    """Signed volumes det[x1 - x0, x2 - x0, x3 - x0] / 6 (> 0 in gmsh's positive order)."""
    x = points[tets]
    return np.linalg.det(np.stack([x[:, 1] - x[:, 0], x[:, 2] - x[:, 0], x[:, 3] - x[:, 0]],
                                  axis=1)) / 6.0


def hexahedron_volumes(points, hexes) -> np.ndarray:
    """Signed volumes of trilinear hexahedra: the Jacobian's determinant integrated by
    2x2x2 Gauss points (exact: it is a polynomial of degree 2 in each reference axis)."""
    x = points[hexes]
    volumes = np.zeros(len(hexes))
    for xi in itertools.product((-3 ** -0.5, 3 ** -0.5), repeat=3):
        shape = 1.0 + _HEX_CORNERS * xi
        dN = np.stack([_HEX_CORNERS[:, i] * np.prod(np.delete(shape, i, axis=1), axis=1) / 8
                       for i in range(3)], axis=1)
        volumes += np.linalg.det(np.einsum("nak,ai->nki", x, dN))
    return volumes


def hexahedron_corner_jacobians(points, hexes) -> np.ndarray:
    """(m, 8) the Jacobian's determinant at each hexahedron's corners: all > 0 for a valid,
    positively ordered cell (a cell folded at one corner has a negative one there)."""
    x = points[hexes]
    out = np.empty((len(hexes), 8))
    for corner, xi in enumerate(_HEX_CORNERS):
        shape = 1.0 + _HEX_CORNERS * xi
        dN = np.stack([_HEX_CORNERS[:, i] * np.prod(np.delete(shape, i, axis=1), axis=1) / 8
                       for i in range(3)], axis=1)
        out[:, corner] = np.linalg.det(np.einsum("nak,ai->nki", x, dN))
    return out


def cell_volumes(data: MeshData) -> np.ndarray:
    """Signed volumes of every first-order cell (tetrahedra, then hexahedra), m^3."""
    parts = []
    if TETRAHEDRON in data.cells:
        parts.append(tetrahedron_volumes(data.points, data.cells[TETRAHEDRON]))
    if HEXAHEDRON in data.cells:
        parts.append(hexahedron_volumes(data.points, data.cells[HEXAHEDRON]))
    return np.concatenate(parts) if parts else np.zeros(0)
