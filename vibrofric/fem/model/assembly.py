"""The elastic body as plain arrays: stiffness, lumped mass, group areas, cell stresses.

DOLFINx computes them (``dolfinx_adapter``: first-order Lagrange on the body's
placed mesh, a ``vibrofric.meshes.BodyMesh`` of hexahedra or tetrahedra, the
forms written out there); this module gathers them into the Discretization the
rest of the FE model uses.

Every array is indexed like DOLFINx's blocked vector space: node d carries the
degrees of freedom 3 d + c, c = 0, 1, 2 for X, Y, Z.
"""

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from . import dolfinx_adapter


@dataclass
class Discretization:
    """The body as plain arrays.

    description  the mesh it was built on (BodyMesh.description)
    coordinates  (nodes, 3) node positions of the placed, undeformed body, m
    stiffness    scipy CSR (3 nodes, 3 nodes), N/m
    mass         (3 nodes,) lumped (row-sum) mass of each degree of freedom, kg
    face_area    {group name: (nodes,) tributary area a_i = int phi_i dA of each node on
                 that facet group ("contact", "load", ...), m^2}
    volume       m^3
    cells        (elements, corners) each cell's nodes in VTK's corner order (the
                 ParaView frames: outputs/paraview.py)
    cell_type    VTK's type of the cells: 12 hexahedron, 10 tetrahedron
    cell_stress  scipy CSR (6 elements, 3 nodes): each cell's mean stress (Voigt: xx,
                 yy, zz, yz, xz, xy; Pa) in a displacement, the cells as in ``cells``
                 (dolfinx_adapter.cell_stress; the frames' stress fields)
    """

    description: str
    coordinates: np.ndarray
    stiffness: sp.csr_matrix
    mass: np.ndarray
    face_area: dict
    volume: float
    cells: np.ndarray = field(repr=False)
    cell_stress: sp.csr_matrix = field(repr=False)
    cell_type: int = dolfinx_adapter.VTK_HEXAHEDRON

    @property
    def nodes(self) -> int:
        return self.coordinates.shape[0]

    @property
    def dofs(self) -> int:
        return 3 * self.nodes


def assemble_body(comm, body, E, nu, density, groups) -> Discretization:
    """Read the body's placed mesh (a meshes.BodyMesh) and assemble K, the lumped mass,
    the cell stress operator and the tributary areas of its facet groups ``groups``
    (names; those the mesh lacks are left out of face_area).

    Serial only: ``comm`` must hold one process (the caller checks).
    """
    mesh, facet_tags = dolfinx_adapter.load_body(comm, body)
    V = dolfinx_adapter.vector_space(mesh)
    K = dolfinx_adapter.stiffness(V, E, nu)
    mass = dolfinx_adapter.lumped_mass(V, density)
    present = {name: body.tag(name) for name in groups if body.tag(name) is not None}
    by_tag = dolfinx_adapter.face_areas(V, facet_tags, tuple(present.values()))
    coordinates = dolfinx_adapter.node_coordinates(V)
    cells, cell_type = dolfinx_adapter.cells(V)
    assert K.shape == (3 * coordinates.shape[0],) * 2
    return Discretization(description=body.description, coordinates=coordinates, stiffness=K,
                          mass=mass, face_area={name: by_tag[tag] for name, tag in present.items()},
                          volume=dolfinx_adapter.volume(mesh), cells=cells,
                          cell_stress=dolfinx_adapter.cell_stress(V, E, nu), cell_type=cell_type)
