"""DOLFINx behind one door: mesh from gmsh, vector Q1 space, K, lumped M, face areas, cells,
the cell-wise stress operator; and the stack's sparse Cholesky (PETSc's CHOLMOD).

The only module that imports DOLFINx, UFL, petsc4py and DOLFINx's gmsh bridge.
Everything it returns is plain numpy / scipy, except the mesh and space handles
that only come back in here. It runs on DOLFINx
0.5.2 (Debian bookworm) through 0.11 (PyPI ``dolfinx-solver-real``,
conda-forge, the Docker images) by detecting what the installed version
offers, never by reading its version string:

    vector P1 space   fem.functionspace(mesh, ("Lagrange", 1, (3,)))  (0.8+)
                      else fem.VectorFunctionSpace(mesh, ("Lagrange", 1))
    DG0 6-vectors     fem.functionspace(mesh, ("DG", 0, (6,)))  (0.8+)
                      else fem.VectorFunctionSpace(mesh, ("DG", 0), dim=6)
    gmsh bridge       dolfinx.io.gmsh (0.10+) else dolfinx.io.gmshio; its
                      model_to_mesh returns a MeshData object (0.10+) or a
                      (mesh, cell_tags, facet_tags) tuple
    PETSc assembly    dolfinx.fem.petsc, imported explicitly (0.9+ needs it)
    VTK cells         dolfinx.plot.vtk_mesh (0.7+) else dolfinx.plot.create_vtk_mesh

mpi4py.MPI is imported before DOLFINx: the PyPI wheel finds its MPI library
only once mpi4py has loaded it.

The body is linear elastic (small strains), first-order Lagrange: vector Q1
(trilinear) on hexahedra, vector P1 (linear) on tetrahedra:

    stiffness   K_ij = int_V  sigma(phi_j) : eps(phi_i) dV,
                sigma(u) = 2 G eps(u) + lambda tr(eps(u)) I,  eps(u) = sym(grad u)
                G = E / (2 (1 + nu)),  lambda = E nu / ((1 + nu)(1 - 2 nu))
    lumped mass m_i = sum_j int_V rho phi_i . phi_j dV = int_V rho phi_i dV
                (row sums; on Q1 hexahedra and P1 tetrahedra all positive and summing
                to rho V)
    face areas  a_i = int_face phi_i dA  (each node's tributary area on a face)
    cell stress S = diag(1 / |cell|) A,  A_(c k),j = int_cell sigma(phi_j)_k dV
                (the L2 projection of sigma(u) onto cell-wise constants, DG0: each
                cell's mean stress, Voigt order xx, yy, zz, yz, xz, xy; S u gives
                the stresses of a displacement u)

Arrays are indexed like DOLFINx's blocked vector space: node d carries the
degrees of freedom 3 d + c, c = 0, 1, 2 for X, Y, Z.
"""

import sys

import numpy as np
import scipy.sparse as sp

from ... import meshes


def _dolfinx():
    """Import and return (dolfinx, ufl, PETSc), mpi4py.MPI first.

    PETSc starts without its own signal handlers: those of recent releases end
    the process on SIGTERM, before Python's handler (a sweep's orderly stop)
    could run.
    """
    from mpi4py import MPI  # noqa: F401  (before dolfinx: the wheel's libmpi)
    if "petsc4py.PETSc" not in sys.modules:
        import petsc4py
        petsc4py.init(["-no_signal_handler"])  # the program name is added
    import dolfinx
    import dolfinx.fem
    import dolfinx.fem.petsc  # noqa: F401  (0.5 loads it with dolfinx.fem; 0.9+ needs it)
    import dolfinx.io
    import ufl
    from petsc4py import PETSc
    return dolfinx, ufl, PETSc


def communicator(comm=None):
    """``comm``, or MPI.COMM_SELF for None: mpi4py is imported only here, when DOLFINx
    is about to be used (starting MPI costs a run time that a run from the model
    cache does not need: docs/first-answer.md)."""
    if comm is None:
        from mpi4py import MPI
        comm = MPI.COMM_SELF
    return comm


def _model_to_mesh(model, comm, rank):
    """(mesh, facet_tags) from a gmsh model on ``rank`` (None on the other ranks)."""
    try:
        from dolfinx.io import gmsh as bridge  # 0.10+
    except ImportError:
        from dolfinx.io import gmshio as bridge  # 0.5 - 0.9
    data = bridge.model_to_mesh(model, comm, rank, gdim=3)
    if hasattr(data, "facet_tags"):  # 0.10+: MeshData
        return data.mesh, data.facet_tags
    mesh, _, facet_tags = data
    return mesh, facet_tags


def load_body(comm, body, rank: int = 0):
    """Return (mesh, facet_tags): the body (a meshes.BodyMesh) as a distributed DOLFINx mesh.

    Rank ``rank`` of ``comm`` reads the placed .msh file ``body.path`` through gmsh;
    DOLFINx then distributes the mesh over ``comm``. The facet tags are the mesh's
    physical tags (``body.facet_groups`` names them). First-order hexahedra or
    tetrahedra (``cells`` refuses others). (DOLFINx 0.5.2's ``gmshio.read_from_msh``
    ends in a NameError; this does what it means to do.)
    """
    _dolfinx()
    if comm.rank != rank:
        return _model_to_mesh(None, comm, rank)
    with meshes.gmsh_model("vibrofric-load") as gmsh:
        gmsh.merge(str(body.path))
        kinds = {int(kind) for kind in gmsh.model.mesh.getElementTypes(3)}
        if not kinds <= set(FIRST_ORDER_GMSH):
            names = [gmsh.model.mesh.getElementProperties(kind)[0] for kind in sorted(kinds)]
            raise ValueError(f"{body.description or body.path}: its cells are {', '.join(names)}; "
                             "only first-order tetrahedra or hexahedra are accepted (a row-sum "
                             "lumped mass of second-order tetrahedra has zero or negative corner "
                             "masses, which the explicit step cannot take)")
        return _model_to_mesh(gmsh.model, comm, rank)


# gmsh's element types of the accepted cells: 4-node tetrahedron, 8-node hexahedron
FIRST_ORDER_GMSH = (4, 5)


def vector_space(mesh):
    """The vector (3 components) Q1 Lagrange space on ``mesh``."""
    dolfinx, _, _ = _dolfinx()
    fem = dolfinx.fem
    if hasattr(fem, "functionspace"):  # 0.8+
        return fem.functionspace(mesh, ("Lagrange", 1, (3,)))
    return fem.VectorFunctionSpace(mesh, ("Lagrange", 1))


def _to_csr(matrix) -> sp.csr_matrix:
    """A PETSc AIJ matrix as scipy CSR, indices sorted."""
    indptr, indices, data = matrix.getValuesCSR()
    csr = sp.csr_matrix((data.copy(), indices.copy(), indptr.copy()), shape=matrix.getSize())
    csr.sort_indices()
    return csr


def _strain(w):
    _, ufl, _ = _dolfinx()
    return ufl.sym(ufl.grad(w))


def _hooke(mesh, E: float, nu: float):
    """sigma(w) = 2 G eps(w) + lambda tr(eps(w)) I, as a function of a UFL argument.

    Material values enter as Constants, so that the compiled form (cached by
    FFCx on its symbolic content) is reused for every E and nu."""
    dolfinx, ufl, PETSc = _dolfinx()
    E_ = dolfinx.fem.Constant(mesh, PETSc.ScalarType(E))
    nu_ = dolfinx.fem.Constant(mesh, PETSc.ScalarType(nu))
    shear = E_ / (2.0 * (1.0 + nu_))                       # G (Lame mu)
    lame = E_ * nu_ / ((1.0 + nu_) * (1.0 - 2.0 * nu_))   # Lame lambda

    def stress(w):
        return 2.0 * shear * _strain(w) + lame * ufl.tr(_strain(w)) * ufl.Identity(3)

    return stress


def stiffness(V, E: float, nu: float) -> sp.csr_matrix:
    """K of the linear elastic block (Young's modulus E, Poisson's ratio nu), scipy CSR."""
    dolfinx, ufl, PETSc = _dolfinx()
    fem, strain, stress = dolfinx.fem, _strain, _hooke(V.mesh, E, nu)
    u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
    matrix = fem.petsc.assemble_matrix(fem.form(ufl.inner(stress(u), strain(v)) * ufl.dx))
    matrix.assemble()
    K = _to_csr(matrix)
    matrix.destroy()
    return K


# The Voigt order of the stress operator's rows (tensor indices of each component)
VOIGT = ((0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1))


def cell_stress(V, E: float, nu: float) -> sp.csr_matrix:
    """S (6 cells, 3 nodes), scipy CSR: row 6 c + k of cell c's mean stress component k
    (VOIGT) in a displacement u on V: sigma_c = S u, Pa for u in m (the DG0 projection:
    see the module's docstring). Its cells are in the order of the mesh's local cells,
    that of ``cells``."""
    dolfinx, ufl, PETSc = _dolfinx()
    fem, mesh = dolfinx.fem, V.mesh
    if hasattr(fem, "functionspace"):  # 0.8+
        W = fem.functionspace(mesh, ("DG", 0, (6,)))
    else:
        W = fem.VectorFunctionSpace(mesh, ("DG", 0), dim=6)
    stress = _hooke(mesh, E, nu)(ufl.TrialFunction(V))
    voigt = ufl.as_vector([stress[i, j] for i, j in VOIGT])
    tau = ufl.TestFunction(W)
    matrix = fem.petsc.assemble_matrix(fem.form(ufl.inner(voigt, tau) * ufl.dx))
    matrix.assemble()
    A = _to_csr(matrix)
    matrix.destroy()
    ones = ufl.as_vector([1.0] * 6)
    cell_volume = fem.petsc.assemble_vector(fem.form(ufl.inner(ones, tau) * ufl.dx))
    S = sp.diags(1.0 / cell_volume.array) @ A      # W's blocks of 6 rows, in its dof order
    cells = mesh.topology.index_map(mesh.topology.dim).size_local
    block = np.array([W.dofmap.cell_dofs(c)[0] for c in range(cells)])  # cell c's DG0 block
    assert W.dofmap.index_map_bs == 6 and np.unique(block).size == cells
    rows = (6 * block[:, None] + np.arange(6)).ravel()
    return sp.csr_matrix(S[rows])


def lumped_mass(V, density: float) -> np.ndarray:
    """(3 nodes,) row sums of the consistent mass rho phi_i . phi_j, kg."""
    dolfinx, ufl, PETSc = _dolfinx()
    fem = dolfinx.fem
    rho = fem.Constant(V.mesh, PETSc.ScalarType(density))
    ones = ufl.as_vector((1.0, 1.0, 1.0))
    # the action of the mass form on a field of ones
    mass = fem.petsc.assemble_vector(fem.form(rho * ufl.inner(ones, ufl.TestFunction(V)) * ufl.dx))
    return mass.array.copy()


def face_areas(V, facet_tags, faces) -> dict:
    """{tag: (nodes,) tributary area of each node on that tagged face}, m^2."""
    dolfinx, ufl, _ = _dolfinx()
    fem = dolfinx.fem
    ds = ufl.Measure("ds", domain=V.mesh, subdomain_data=facet_tags)
    ones, v = ufl.as_vector((1.0, 1.0, 1.0)), ufl.TestFunction(V)
    areas = {}
    for tag in faces:
        area = fem.petsc.assemble_vector(fem.form(ufl.inner(ones, v) * ds(tag)))
        areas[tag] = area.array[0::3].copy()  # the same for all three components
    return areas


def volume(mesh) -> float:
    dolfinx, ufl, _ = _dolfinx()
    return float(dolfinx.fem.assemble_scalar(dolfinx.fem.form(1.0 * ufl.dx(domain=mesh))))


def node_coordinates(V) -> np.ndarray:
    """(nodes, 3) positions of the space's nodes, in its own (owned) node order."""
    coordinates = V.tabulate_dof_coordinates()[:, :3].copy()
    assert coordinates.shape[0] == V.dofmap.index_map.size_local
    return coordinates


# VTK's cell types of the first-order cells (their corner counts)
VTK_HEXAHEDRON = 12
VTK_TETRAHEDRON = 10
CORNERS = {VTK_HEXAHEDRON: 8, VTK_TETRAHEDRON: 4}


def cells(V):
    """(cells, vtk_type): each cell's nodes (cells, corners) (the space's node indices,
    as node_coordinates orders them) in VTK's corner order, and VTK's type of them all
    (VTK_HEXAHEDRON or VTK_TETRAHEDRON): the cells of the ParaView frames
    (fem/outputs/paraview.py). ValueError for any other cell (second order, prisms,
    a mix)."""
    dolfinx, _, _ = _dolfinx()
    import dolfinx.plot

    make = getattr(dolfinx.plot, "vtk_mesh", None) or dolfinx.plot.create_vtk_mesh
    topology, cell_types, points = make(V)
    types = np.unique(np.asarray(cell_types))
    if types.size != 1 or int(types[0]) not in CORNERS:
        raise ValueError(f"the body's mesh has VTK cell types {types.tolist()}: only first-order "
                         "hexahedra (12) or tetrahedra (10), one kind per mesh, are accepted")
    vtk_type = int(types[0])
    assert np.array_equal(points, node_coordinates(V))  # its points are the space's nodes
    corners = CORNERS[vtk_type]
    rows = np.asarray(topology).reshape(-1, corners + 1)  # [corners, n_0 ...] per cell
    assert np.all(rows[:, 0] == corners)
    return rows[:, 1:].astype(np.int64), vtk_type


# The sparse Cholesky of the DOLFINx stack's PETSc (CHOLMOD: Chen, Davis, Hager and
# Rajamanickam, ACM TOMS 35 (2008) 22), whether this PETSc has it (None: not asked yet).
_cholmod_present = None
# Right-hand sides solved at once by CholeskyFactor.solve (bounds the dense copies PETSc
# takes of them: 256 columns of a 100k-DOF body are 200 MB)
SOLVE_BATCH = 256


class CholeskyFactor:
    """L L^T of a real symmetric positive definite sparse matrix, by CHOLMOD through
    PETSc, ordered by CHOLMOD itself. ``solve(b)``: b of shape (n,) or (n, k)."""

    def __init__(self, PETSc, matrix):
        csr = sp.csr_matrix(matrix, dtype=float)
        csr.sort_indices()
        index = PETSc.IntType
        self._PETSc = PETSc
        self._matrix = PETSc.Mat().createAIJ(
            size=csr.shape, csr=(csr.indptr.astype(index), csr.indices.astype(index), csr.data),
            comm=PETSc.COMM_SELF)
        self._matrix.setOption(PETSc.Mat.Option.SPD, True)
        self._ksp = PETSc.KSP().create(PETSc.COMM_SELF)
        self._ksp.setOperators(self._matrix)
        self._ksp.setType("preonly")
        pc = self._ksp.getPC()
        pc.setType("cholesky")
        pc.setFactorSolverType("cholmod")
        self._ksp.setUp()
        self._factor = pc.getFactorMatrix()
        self.shape = csr.shape

    def solve(self, b: np.ndarray) -> np.ndarray:
        PETSc, n = self._PETSc, self.shape[0]
        b = np.asarray(b, dtype=float)
        if b.ndim == 1:
            x = np.zeros(n)
            self._factor.solve(PETSc.Vec().createWithArray(np.array(b), comm=PETSc.COMM_SELF),
                               PETSc.Vec().createWithArray(x, comm=PETSc.COMM_SELF))
            return x
        x = np.empty(b.shape)
        for first in range(0, b.shape[1], SOLVE_BATCH):
            columns = b[:, first:first + SOLVE_BATCH]
            k = columns.shape[1]
            rhs = PETSc.Mat().createDense((n, k), array=np.asfortranarray(columns).ravel(order="F"),
                                          comm=PETSc.COMM_SELF)
            out = PETSc.Mat().createDense((n, k), comm=PETSc.COMM_SELF)
            out.setUp()
            self._factor.matSolve(rhs, out)
            x[:, first:first + k] = out.getDenseArray()
            rhs.destroy()
            out.destroy()
        return x


def cholesky(matrix):
    """The CholeskyFactor of a real symmetric positive definite sparse matrix, or None
    where the installed stack has no petsc4py or its PETSc no CHOLMOD (the caller then
    factorizes with SciPy). Imports petsc4py (and mpi4py) only when called."""
    global _cholmod_present
    if _cholmod_present is False:
        return None
    try:
        from mpi4py import MPI  # noqa: F401  (before petsc4py, as _dolfinx)
        if "petsc4py.PETSc" not in sys.modules:
            import petsc4py
            petsc4py.init(["-no_signal_handler"])
        from petsc4py import PETSc
    except ImportError:
        _cholmod_present = False
        return None
    try:
        factor = CholeskyFactor(PETSc, matrix)
    except PETSc.Error:
        if _cholmod_present:   # CHOLMOD worked before: this matrix is the trouble
            raise
        _cholmod_present = False
        return None
    _cholmod_present = True
    return factor
