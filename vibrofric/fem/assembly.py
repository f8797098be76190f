"""The elastic block discretized by DOLFINx: stiffness, lumped mass, face areas.

This module and ``paraview.py`` are the only ones that call DOLFINx; they hand
the rest of the FE model plain numpy / scipy arrays, so a newer DOLFINx needs
changes here only (see spec/dolfinx-notes.md for what moved after 0.5).

The block is linear elastic (small strains) and discretized with vector Q1
(trilinear Lagrange) elements on the hexahedral mesh of ``vibrofric.meshes``:

    stiffness   K_ij = int_V  sigma(phi_j) : eps(phi_i) dV,
                sigma(u) = 2 G eps(u) + lambda tr(eps(u)) I,  eps(u) = sym(grad u)
                G = E / (2 (1 + nu)),  lambda = E nu / ((1 + nu)(1 - 2 nu))
    lumped mass m_i = sum_j int_V rho phi_i . phi_j dV = int_V rho phi_i dV
                (row sums; on Q1 hexahedra all positive and summing to rho V)
    face areas  a_i = int_face phi_i dA  (the "boundary mass" of a face: each
                node's tributary area, summing to the face's area)

Every array is indexed like DOLFINx's blocked vector space: node d carries the
degrees of freedom 3 d + c, c = 0, 1, 2 for X, Y, Z.
"""

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from .. import meshes


@dataclass
class Discretization:
    """The block as plain arrays (and, for output only, the DOLFINx space).

    level        the mesh level it was built on
    coordinates  (nodes, 3) node positions of the undeformed block, m
    stiffness    scipy CSR (3 nodes, 3 nodes), N/m
    mass         (3 nodes,) lumped (row-sum) mass of each degree of freedom, kg
    face_area    {face tag: (nodes,) tributary area of each node on that face, m^2}
    volume       m^3
    space        the DOLFINx vector Q1 space (for ``paraview.FrameWriter``)
    """

    level: str
    coordinates: np.ndarray
    stiffness: sp.csr_matrix
    mass: np.ndarray
    face_area: dict
    volume: float
    space: object = field(default=None, repr=False)

    @property
    def nodes(self) -> int:
        return self.coordinates.shape[0]

    @property
    def dofs(self) -> int:
        return 3 * self.nodes


def _to_csr(matrix) -> sp.csr_matrix:
    """A PETSc AIJ matrix as scipy CSR (0.5: getValuesCSR; 0.9+: MatrixCSR.to_scipy())."""
    indptr, indices, data = matrix.getValuesCSR()
    size = matrix.getSize()
    csr = sp.csr_matrix((data.copy(), indices.copy(), indptr.copy()), shape=size)
    csr.sort_indices()
    return csr


def assemble_block(comm, size, level, E, nu, density, faces) -> Discretization:
    """Mesh the block at ``level`` and assemble K, the lumped mass and the face areas.

    ``faces`` lists the facet tags (vibrofric.meshes.CONTACT, TOP, ...) whose
    nodal areas are wanted. An unknown level raises ValueError (from meshes).
    Serial only: ``comm`` must hold one process (the caller checks).
    """
    import dolfinx.fem.petsc  # noqa: F401  (0.5 loads it with dolfinx.fem; 0.9+ needs it)
    import ufl
    from dolfinx import fem
    from petsc4py import PETSc

    meshes.level_counts(level)  # refuse an unknown level before any meshing
    mesh, facet_tags = meshes.load_block(comm, size, level)
    V = fem.VectorFunctionSpace(mesh, ("Lagrange", 1))
    u, v = ufl.TrialFunction(V), ufl.TestFunction(V)

    # Material values enter as Constants, so that the compiled forms (cached by
    # FFCx on their symbolic content) are reused for every E, nu and rho.
    E_ = fem.Constant(mesh, PETSc.ScalarType(E))
    nu_ = fem.Constant(mesh, PETSc.ScalarType(nu))
    rho = fem.Constant(mesh, PETSc.ScalarType(density))
    shear = E_ / (2.0 * (1.0 + nu_))                       # G (Lame mu)
    lame = E_ * nu_ / ((1.0 + nu_) * (1.0 - 2.0 * nu_))   # Lame lambda

    def strain(w):
        return ufl.sym(ufl.grad(w))

    def stress(w):
        return 2.0 * shear * strain(w) + lame * ufl.tr(strain(w)) * ufl.Identity(3)

    stiffness_form = fem.form(ufl.inner(stress(u), strain(v)) * ufl.dx)
    matrix = fem.petsc.assemble_matrix(stiffness_form)
    matrix.assemble()
    K = _to_csr(matrix)
    matrix.destroy()

    ones = ufl.as_vector((1.0, 1.0, 1.0))
    # Row sums of the consistent mass rho phi_i . phi_j: the action on a field of ones.
    mass = fem.petsc.assemble_vector(fem.form(rho * ufl.inner(ones, v) * ufl.dx))
    mass_array = mass.array.copy()

    ds = ufl.Measure("ds", domain=mesh, subdomain_data=facet_tags)
    face_area = {}
    for tag in faces:
        area = fem.petsc.assemble_vector(fem.form(ufl.inner(ones, v) * ds(tag)))
        face_area[tag] = area.array[0::3].copy()  # the same for all three components

    volume = fem.assemble_scalar(fem.form(1.0 * ufl.dx(domain=mesh)))
    coordinates = V.tabulate_dof_coordinates()[:, :3].copy()
    nodes = V.dofmap.index_map.size_local
    assert coordinates.shape[0] == nodes and K.shape == (3 * nodes, 3 * nodes)
    return Discretization(level=level, coordinates=coordinates, stiffness=K,
                          mass=mass_array, face_area=face_area, volume=float(volume), space=V)
