"""What the DOLFINx adapter returns, pinned independently of DOLFINx.

One hexahedron's stiffness and lumped mass against the Q1 element matrices
written out below in numpy (2x2x2 Gauss quadrature, exact for a rectangular
box), the face areas, the mesh itself, and the coarse mesh's first
eigenfrequencies against stored values.
"""

import itertools
from types import SimpleNamespace

import numpy as np
import pytest

pytest.importorskip("mpi4py")
from mpi4py import MPI  # noqa: E402  (before dolfinx: the PyPI wheel's libmpi)

pytest.importorskip("dolfinx")

from vibrofric import meshes  # noqa: E402
from vibrofric.fem.model import dolfinx_adapter as adapter  # noqa: E402

E, NU, RHO = 210e9, 0.3, 7850.0  # steel
SIZE = meshes.DEFAULT_SIZE       # 30 x 40 x 53 mm: three different edges
PLANES = {tag: (axis, far) for tag, (_, axis, far) in meshes.FACES.items()}


@pytest.fixture(autouse=True)
def _own_mesh_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("VIBROFRIC_CACHE", str(tmp_path))


def q1_hexahedron(size, corners, E, nu, rho):
    """Stiffness (24, 24) and row-sum mass (24,) of one trilinear box element.

    ``corners`` (8, 3) are the node positions in the order wanted; the box is
    [0, a] x [0, b] x [0, c]. N_i = prod_k (1 + s_ik xi_k) / 2 with s_ik = +-1
    the corner's side, xi in [-1, 1]^3; x_k = (1 + xi_k) L_k / 2, so
    dN_i/dx_k = (2 / L_k) dN_i/dxi_k and dV = (a b c / 8) dxi. Voigt order
    (xx, yy, zz, yz, xz, xy) with engineering shear strains.
    """
    L = np.asarray(size, dtype=float)
    signs = np.where(corners > L / 2, 1.0, -1.0)
    lame = E * nu / ((1 + nu) * (1 - 2 * nu))
    shear = E / (2 * (1 + nu))
    D = np.zeros((6, 6))
    D[:3, :3] = lame
    D[np.arange(3), np.arange(3)] += 2 * shear
    D[np.arange(3, 6), np.arange(3, 6)] = shear
    K = np.zeros((24, 24))
    mass = np.zeros(24)
    gauss = np.array([-1.0, 1.0]) / np.sqrt(3.0)  # 2-point rule, weights 1
    for xi in itertools.product(gauss, repeat=3):
        xi = np.array(xi)
        factors = (1 + signs * xi) / 2                       # (8, 3)
        N = factors.prod(axis=1)
        grad = np.empty((8, 3))
        for k in range(3):
            others = np.delete(factors, k, axis=1).prod(axis=1)
            grad[:, k] = signs[:, k] / 2 * others * 2 / L[k]
        B = np.zeros((6, 24))
        for i in range(8):
            gx, gy, gz = grad[i]
            B[:, 3 * i:3 * i + 3] = [[gx, 0, 0], [0, gy, 0], [0, 0, gz],
                                     [0, gz, gy], [gz, 0, gx], [gy, gx, 0]]
        dV = L.prod() / 8
        K += B.T @ D @ B * dV
        mass += rho * np.repeat(N, 3) * dV  # sum_j N_i N_j = N_i
    return K, mass


def load_block(comm, size, level):
    """(mesh, facet_tags) of the block (meshes.block_body) through the adapter's load_body."""
    return adapter.load_body(comm, meshes.block_body(size, level))


def block_in_a_cache_of_its_own(tmp_path_factory, level):
    """load_block for a module's fixture, which the function's cache (_own_mesh_cache)
    does not reach: the block meshed in a mesh cache of its own."""
    patch = pytest.MonkeyPatch()
    patch.setenv("VIBROFRIC_CACHE", str(tmp_path_factory.mktemp("cache")))
    try:
        return load_block(MPI.COMM_SELF, SIZE, level)
    finally:
        patch.undo()


def hexahedra(V):
    """The cells of ``V``'s mesh, asserted hexahedra (adapter.cells)."""
    cells, vtk_type = adapter.cells(V)
    assert vtk_type == adapter.VTK_HEXAHEDRON and cells.shape[1] == 8
    return cells


@pytest.fixture(scope="module")
def one_hexahedron(tmp_path_factory):
    mesh, facet_tags = block_in_a_cache_of_its_own(tmp_path_factory, "tiny")
    V = adapter.vector_space(mesh)
    return dict(K=adapter.stiffness(V, E, NU).toarray(), mass=adapter.lumped_mass(V, RHO),
                X=adapter.node_coordinates(V),
                areas=adapter.face_areas(V, facet_tags, list(meshes.FACES)),
                volume=adapter.volume(mesh))


def test_one_hexahedron_is_the_q1_element(one_hexahedron):
    """K and M equal the closed-form element to rounding: both integrate the
    same polynomials exactly, so only summation order differs (1e-12 of the
    largest entry is ~1e4 ulps of room, and far below any wrong term)."""
    X = one_hexahedron["X"]
    assert X.shape == (8, 3)
    K_ref, mass_ref = q1_hexahedron(SIZE, X, E, NU, RHO)
    K = one_hexahedron["K"]
    assert np.abs(K - K_ref).max() <= 1e-12 * np.abs(K_ref).max()
    assert np.allclose(one_hexahedron["mass"], mass_ref, rtol=1e-12, atol=0)


def test_one_hexahedron_stiffness_has_the_rigid_motions_as_null_space(one_hexahedron):
    """Symmetric; the 3 translations and 3 rotations cost no energy, and
    nothing else does (rank 24 - 6 = 18). Relative 1e-12: rounding."""
    K, X = one_hexahedron["K"], one_hexahedron["X"]
    scale = np.abs(K).max()
    assert np.abs(K - K.T).max() <= 1e-12 * scale
    rigid = []
    for axis in range(3):
        translation = np.zeros((8, 3))
        translation[:, axis] = 1.0
        rigid.append(translation.ravel())
        rotation = np.cross(np.eye(3)[axis], X)  # omega x r
        rigid.append(rotation.ravel())
    rigid = np.array(rigid).T
    assert np.abs(K @ rigid).max() <= 1e-12 * scale * np.abs(rigid).max()
    eigenvalues = np.linalg.eigvalsh(K)
    assert np.all(eigenvalues[:6] < 1e-10 * eigenvalues[-1])
    assert np.all(eigenvalues[6:] > 1e-3 * eigenvalues[-1])


def test_one_hexahedron_mass_and_face_areas(one_hexahedron):
    """Each node carries an eighth of rho V on each component, an area
    quarter of each of its three faces (exact to rounding)."""
    volume = np.prod(SIZE)
    assert one_hexahedron["volume"] == pytest.approx(volume, rel=1e-14)
    assert np.allclose(one_hexahedron["mass"], RHO * volume / 8, rtol=1e-13, atol=0)
    X = one_hexahedron["X"]
    for tag, (axis, far) in PLANES.items():
        area = one_hexahedron["areas"][tag]
        on_face = np.isclose(X[:, axis], SIZE[axis] if far else 0.0)
        face = np.prod(np.delete(SIZE, axis))
        assert on_face.sum() == 4
        assert np.allclose(area[on_face], face / 4, rtol=1e-13, atol=0)
        assert np.all(area[~on_face] == 0.0)


@pytest.mark.parametrize("level", ["coarse", "2x3x4"])
def test_load_block_gives_the_tagged_hexahedral_block(level):
    import dolfinx
    comm = MPI.COMM_WORLD if level == "coarse" else MPI.COMM_SELF
    mesh, facet_tags = load_block(comm, SIZE, level)
    counts = meshes.level_counts(level)

    assert mesh.topology.cell_type == dolfinx.mesh.CellType.hexahedron
    assert comm.allreduce(mesh.topology.index_map(3).size_local) == np.prod(counts)
    assert comm.allreduce(adapter.volume(mesh)) == pytest.approx(np.prod(SIZE), rel=1e-12)

    assert facet_tags.dim == 2
    mesh.topology.create_connectivity(2, 3)
    owned = mesh.topology.index_map(2).size_local
    for tag, (axis, far) in PLANES.items():
        facets = facet_tags.find(tag)
        facets = facets[facets < owned]
        assert comm.allreduce(len(facets)) == np.prod(np.delete(counts, axis))
        midpoints = dolfinx.mesh.compute_midpoints(mesh, 2, facets)
        assert np.allclose(midpoints[:, axis], SIZE[axis] if far else 0.0, rtol=0, atol=1e-12)


# The coarse block's (4x5x7 hexahedra, 720 DOFs) first elastic eigenfrequencies,
# steel, free, lumped mass, Hz: computed once with this adapter on DOLFINx 0.5.2
# (Debian) and confirmed on 0.11 (PyPI) to ~1e-13. A regression pin: they move
# if the element, the quadrature, the lumping, the material formulas or the
# mesh change. Plausibility: the lowest mode of a free 30 x 40 x 53 mm steel
# block is of the order of a half shear wave over its length,
# c_s / (2 L) = 3200 m/s / 0.106 m ~ 30 kHz.
COARSE_FREQUENCIES = [25218.21001868, 31934.85022298, 35734.49960561, 43677.31185015,
                      45820.81511616, 45957.79907428]


def test_coarse_mesh_eigenfrequencies():
    """Six rigid modes at (numerically) zero, then the stored frequencies.
    1e-9 relative: the stored values have 13 significant digits (their last is
    ~1e-12 relative) and dense symmetric eigenvalues of a 720-DOF problem are
    accurate to ~1e-13 of the largest; 1e-9 is far tighter than any change of
    the discretization (a different quadrature or lumping moves them by %)."""
    mesh, _ = load_block(MPI.COMM_SELF, SIZE, "coarse")
    V = adapter.vector_space(mesh)
    K = adapter.stiffness(V, E, NU).toarray()
    scale = 1 / np.sqrt(adapter.lumped_mass(V, RHO))
    omega2 = np.linalg.eigvalsh(scale[:, None] * K * scale[None, :])
    assert np.all(np.abs(omega2[:6]) < 1e-10 * omega2[-1])
    frequencies = np.sqrt(omega2[6:12]) / (2 * np.pi)
    assert np.allclose(frequencies, COARSE_FREQUENCIES, rtol=1e-9, atol=0)


def test_frames_from_the_arrays_match_dolfinxs_own(tmp_path, monkeypatch):
    """A ParaView frame as paraview.FrameWriter writes it from the model's arrays
    (VTK XML of its own, the cells of ``hexahedra``) against the one DOLFINx's VTKFile writes
    of the same fields: read back by VTK's reader (ParaView's), the same points,
    the same cells, the same arrays (names, components, values at each point)."""
    pyvista = pytest.importorskip("pyvista")
    import dolfinx.fem
    import dolfinx.io

    from vibrofric.fem.outputs import paraview

    mesh, _ = load_block(MPI.COMM_SELF, SIZE, "coarse")
    V = adapter.vector_space(mesh)
    coordinates = adapter.node_coordinates(V)
    nodes = coordinates.shape[0]
    rng = np.random.default_rng(27)
    values = {name: rng.standard_normal(nodes if name in paraview.SCALAR_FIELDS else (nodes, 3))
              for name in paraview.FIELDS}

    # DOLFINx's writer: the vectors on V, the scalar on its collapsed first component
    Q, q_to_v = V.sub(0).collapse()
    functions = []
    for name in paraview.FIELDS:
        scalar = name in paraview.SCALAR_FIELDS
        function = dolfinx.fem.Function(Q if scalar else V, name=name)
        function.x.array[:] = (values[name][np.asarray(q_to_v) // 3] if scalar
                               else values[name].ravel())
        functions.append(function)
    with dolfinx.io.VTKFile(MPI.COMM_SELF, str(tmp_path / "dolfinx" / "block.pvd"), "w") as file:
        file.write_function(functions, 0.25)
    (piece,) = (tmp_path / "dolfinx").glob("*.vtu")   # one process: one piece
    theirs = pyvista.read(piece)

    # FrameWriter, its fields those above, and cell fields of its own (DOLFINx 0.5's
    # VTKFile writes no cell data to compare with: VTK's reader reads them back)
    cells = hexahedra(V)
    cell_values = {name: rng.standard_normal((cells.shape[0], 9) if name == "stress"
                                             else cells.shape[0])
                   for name in paraview.CELL_FIELDS}
    monkeypatch.setattr(paraview, "node_fields", lambda model, state: values)
    monkeypatch.setattr(paraview, "cell_fields", lambda model, state: cell_values)
    model = SimpleNamespace(disc=SimpleNamespace(coordinates=coordinates, cells=cells,
                                                 cell_type=adapter.VTK_HEXAHEDRON))
    writer = paraview.FrameWriter(model, tmp_path / "meshio")
    writer(SimpleNamespace(t=0.25))
    writer.close()
    reader = pyvista.get_reader(str(tmp_path / "meshio" / "block.pvd"))
    assert reader.time_values == [0.25]
    ours = reader.read()[0]

    # Each of our points is one of theirs (to rounding: DOLFINx 0.5 writes 16 digits in ASCII).
    assert ours.n_points == theirs.n_points == nodes
    gaps = np.linalg.norm(ours.points[:, None, :] - theirs.points[None, :, :], axis=2)
    match = gaps.argmin(axis=1)
    assert np.all(gaps[np.arange(nodes), match] < 1e-12 * max(SIZE))
    assert np.unique(match).size == nodes
    # The same hexahedra, their corners in the same order: DOLFINx's as VTK's Lagrange
    # hexahedron of degree 1 (type 72), ours as the linear one (12), which every reader
    # knows; at degree 1 both list the 8 corners in the same order.
    assert set(np.asarray(ours.celltypes).tolist()) == {adapter.VTK_HEXAHEDRON}
    assert set(np.asarray(theirs.celltypes).tolist()) <= {adapter.VTK_HEXAHEDRON, 72}
    ours_cells = {tuple(cell) for cell in match[ours.cells.reshape(-1, 9)[:, 1:]]}
    assert ours_cells == {tuple(cell) for cell in theirs.cells.reshape(-1, 9)[:, 1:]}
    # The same arrays (DOLFINx adds VTK's parallel bookkeeping: vtkGhostType,
    # vtkOriginalPointIds); the values to DOLFINx's 16 digits (1e-15 of each field's size).
    assert set(ours.point_data.keys()) == set(paraview.FIELDS)
    assert {name for name in theirs.point_data.keys() if not name.startswith("vtk")} == set(
        paraview.FIELDS)
    for name in paraview.FIELDS:
        mine, dolfinx_values = np.asarray(ours.point_data[name]), np.asarray(theirs.point_data[name])
        assert mine.shape == dolfinx_values.shape, name
        assert np.array_equal(mine, values[name]), name
        scale = np.abs(values[name]).max()
        assert np.allclose(mine, dolfinx_values[match], rtol=0, atol=1e-15 * scale), name
    assert set(ours.cell_data.keys()) == set(paraview.CELL_FIELDS)
    for name in paraview.CELL_FIELDS:
        assert np.array_equal(np.asarray(ours.cell_data[name]), cell_values[name]), name


# --- the cell stresses of the frames (dolfinx_adapter.cell_stress) -----------------------

@pytest.fixture(scope="module")
def coarse_stress(tmp_path_factory):
    """The coarse block's node positions, cells (hexahedra) and cell stress operator."""
    mesh, _ = block_in_a_cache_of_its_own(tmp_path_factory, "coarse")
    V = adapter.vector_space(mesh)
    return adapter.node_coordinates(V), hexahedra(V), adapter.cell_stress(V, E, NU)


def uniform_strain_displacement(X, sigma):
    """u = eps x at the nodes X, eps = C^-1 sigma (isotropic Hooke's law: the strain
    of the uniform stress tensor ``sigma``)."""
    eps = ((1 + NU) * sigma - NU * np.trace(sigma) * np.eye(3)) / E
    return (X @ eps.T).ravel()


@pytest.mark.parametrize("state", ["uniaxial", "shear", "hydrostatic"])
def test_cell_stress_of_a_uniform_stress_state_and_its_von_mises(coarse_stress, state):
    """A displacement linear in x (Q1 holds it exactly) of a known uniform stress gives
    that stress in every cell, and von Mises its textbook value: uniaxial s -> s, pure
    shear t -> sqrt(3) t, hydrostatic p -> 0. 1e-9 of s: the cell means are sums of
    ~24 products of gradients (1e2 /m) and displacements (1e-6 m), rounded to ~1e-16
    relative each; 1e-9 is far below a wrong factor or a swapped component."""
    from vibrofric.fem.outputs.paraview import TENSOR_OF_VOIGT, von_mises

    X, cells, S = coarse_stress
    s = 1e6   # Pa
    sigma, expected = {"uniaxial": (np.diag([s, 0.0, 0.0]), s),
                       "shear": (np.array([[0.0, s, 0.0], [s, 0.0, 0.0], [0.0, 0.0, 0.0]]),
                                 np.sqrt(3.0) * s),
                       "hydrostatic": (-s * np.eye(3), 0.0)}[state]
    voigt = (S @ uniform_strain_displacement(X, sigma)).reshape(-1, 6)
    assert voigt.shape == (cells.shape[0], 6)
    assert np.allclose(voigt[:, TENSOR_OF_VOIGT], sigma.ravel(), rtol=0, atol=1e-9 * s)
    assert np.allclose(von_mises(voigt), expected, rtol=0, atol=1e-9 * s)


def test_cell_stress_rows_are_the_cells_of_the_frames(coarse_stress):
    """u_x = a x^2 / 2: eps_xx = a x, so each cell's mean sigma_xx is (lambda + 2 G) a
    times its centre's x (the Q1 interpolant's slope over a cell is exactly the mean
    of x there), and the rows follow the cells the frames are written with
    (``hexahedra``): a stress drawn on the wrong cells fails. 1e-9: rounding, as above."""
    X, cells, S = coarse_stress
    a = 1e-3   # 1/m
    u = np.zeros_like(X)
    u[:, 0] = a * X[:, 0] ** 2 / 2
    sigma_xx = (S @ u.ravel()).reshape(-1, 6)[:, 0]
    lame, shear = E * NU / ((1 + NU) * (1 - 2 * NU)), E / (2 * (1 + NU))
    centres = X[cells].mean(axis=1)
    expected = (lame + 2 * shear) * a * centres[:, 0]
    assert np.allclose(sigma_xx, expected, rtol=0, atol=1e-9 * np.abs(expected).max())


def _spd_matrix(n: int):
    """A sparse symmetric positive definite matrix: a 1D Laplacian with a spread diagonal
    (condition number ~1e4), random symmetric couplings two apart."""
    import scipy.sparse as sp

    rng = np.random.default_rng(3)
    far = rng.uniform(-0.1, 0.1, n - 2)
    return (sp.diags([-np.ones(n - 1), 2.5 + rng.uniform(0.0, 1e3, n), -np.ones(n - 1)],
                     [-1, 0, 1]) + sp.diags([far, far], [-2, 2])).tocsr()


def test_cholesky_solves_vectors_and_batches_of_columns(monkeypatch):
    A = _spd_matrix(200)
    factor = adapter.cholesky(A)
    if factor is None:
        pytest.skip("this stack's PETSc has no CHOLMOD (linalg.spd_factor uses SuperLU)")
    monkeypatch.setattr(adapter, "SOLVE_BATCH", 3)        # 7 columns: three batches
    rng = np.random.default_rng(4)
    b, B = rng.standard_normal(200), rng.standard_normal((200, 7))
    dense = A.toarray()
    # a direct solve of a matrix of condition ~1e4 agrees with LAPACK's to ~1e-12
    np.testing.assert_allclose(factor.solve(b), np.linalg.solve(dense, b), rtol=1e-10, atol=0)
    np.testing.assert_allclose(factor.solve(B), np.linalg.solve(dense, B), rtol=1e-10, atol=0)
    assert factor.solve(B[:, :1]).shape == (200, 1)


def test_spd_factor_on_a_grid_keeps_superlu_and_without_cholmod_falls_back(monkeypatch):
    from vibrofric.fem.model import linalg

    A = _spd_matrix(60)
    ordered = linalg.spd_factor(A, np.arange(60)[::-1])
    assert isinstance(ordered, linalg.OrderedLU)       # the block's factor, unchanged
    monkeypatch.setattr(adapter, "_cholmod_present", False)
    unordered = linalg.spd_factor(A)
    b = np.linspace(-1.0, 1.0, 60)
    assert not isinstance(unordered, adapter.CholeskyFactor)
    np.testing.assert_allclose(unordered.solve(b), ordered.solve(b), rtol=1e-10, atol=0)
