"""The elastic block as plain arrays: stiffness, lumped mass, face areas, cell stresses.

DOLFINx computes them (``dolfinx_adapter``: vector Q1 on the hexahedral mesh of
``vibrofric.meshes``, the forms written out there); this module gathers them
into the Discretization the rest of the FE model uses.

Every array is indexed like DOLFINx's blocked vector space: node d carries the
degrees of freedom 3 d + c, c = 0, 1, 2 for X, Y, Z.
"""

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from ... import meshes
from . import dolfinx_adapter


@dataclass
class Discretization:
    """The block as plain arrays.

    level        the mesh level it was built on
    coordinates  (nodes, 3) node positions of the undeformed block, m
    stiffness    scipy CSR (3 nodes, 3 nodes), N/m
    mass         (3 nodes,) lumped (row-sum) mass of each degree of freedom, kg
    face_area    {face tag: (nodes,) tributary area of each node on that face, m^2}
    volume       m^3
    cells        (elements, 8) each hexahedron's nodes in VTK's corner order (the
                 ParaView frames: outputs/paraview.py)
    cell_stress  scipy CSR (6 elements, 3 nodes): each cell's mean stress (Voigt: xx,
                 yy, zz, yz, xz, xy; Pa) in a displacement, the cells as in ``cells``
                 (dolfinx_adapter.cell_stress; the frames' stress fields)
    """

    level: str
    coordinates: np.ndarray
    stiffness: sp.csr_matrix
    mass: np.ndarray
    face_area: dict
    volume: float
    cells: np.ndarray = field(repr=False)
    cell_stress: sp.csr_matrix = field(repr=False)

    @property
    def nodes(self) -> int:
        return self.coordinates.shape[0]

    @property
    def dofs(self) -> int:
        return 3 * self.nodes


def assemble_block(comm, size, level, E, nu, density, faces) -> Discretization:
    """Mesh the block at ``level`` and assemble K, the lumped mass and the face areas.

    ``faces`` lists the facet tags (vibrofric.meshes.CONTACT, TOP, ...) whose
    nodal areas are wanted. An unknown level raises ValueError (from meshes).
    Serial only: ``comm`` must hold one process (the caller checks).
    """
    meshes.level_counts(level)  # refuse an unknown level before any meshing
    mesh, facet_tags = dolfinx_adapter.load_block(comm, size, level)
    V = dolfinx_adapter.vector_space(mesh)
    K = dolfinx_adapter.stiffness(V, E, nu)
    mass = dolfinx_adapter.lumped_mass(V, density)
    face_area = dolfinx_adapter.face_areas(V, facet_tags, faces)
    coordinates = dolfinx_adapter.node_coordinates(V)
    assert K.shape == (3 * coordinates.shape[0],) * 2
    return Discretization(level=level, coordinates=coordinates, stiffness=K, mass=mass,
                          face_area=face_area, volume=dolfinx_adapter.volume(mesh),
                          cells=dolfinx_adapter.hexahedra(V),
                          cell_stress=dolfinx_adapter.cell_stress(V, E, nu))
