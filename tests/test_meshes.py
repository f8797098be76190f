"""The block mesh: hexahedra, counts, volume, tagged faces, cache, DOLFINx loading."""

import itertools

import meshio
import numpy as np
import pytest

from vibrofric import meshes
from vibrofric.meshes import block

# (size, level, counts): two named levels on the default block, and explicit
# counts, all different per axis so that a swapped axis shows, on another size.
CASES = [
    (meshes.DEFAULT_SIZE, "tiny", (1, 1, 1)),
    (meshes.DEFAULT_SIZE, "coarse", meshes.LEVELS["coarse"]),
    ((0.02, 0.05, 0.01), "2x3x4", (2, 3, 4)),
]

# tag -> (normal axis, at the far end?), as the task states them.
PLANES = {1: (2, False), 2: (2, True), 3: (0, True), 4: (0, False), 5: (1, False), 6: (1, True)}


@pytest.fixture(scope="module")
def mesh_files(tmp_path_factory):
    """The .msh file of each case, read by meshio (an independent reader)."""
    folder = tmp_path_factory.mktemp("meshes")
    return {level: meshio.read(meshes.block_mesh_file(size, level, cache_dir=folder))
            for size, level, _ in CASES}


def hex_volumes(points, hexes):
    """Volumes of trilinear hexahedra in gmsh node order (2x2x2 Gauss: exact)."""
    corners = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],  # bottom, then
                        [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]])     # top, both ccw
    x = points[hexes]
    volumes = np.zeros(len(hexes))
    for xi in itertools.product((-3 ** -0.5, 3 ** -0.5), repeat=3):
        shape = 1.0 + corners * xi  # (8, 3): the three 1D factors of each node's function
        dN = np.stack([corners[:, i] * np.prod(np.delete(shape, i, axis=1), axis=1) / 8
                       for i in range(3)], axis=1)
        volumes += np.linalg.det(np.einsum("nak,ai->nki", x, dN))
    return volumes


@pytest.mark.parametrize("size, level, counts", CASES)
def test_cells_are_hexahedra_and_nodes_form_the_grid(mesh_files, size, level, counts):
    msh = mesh_files[level]
    nx, ny, nz = counts
    assert {c.type for c in msh.cells} == {"hexahedron", "quad"}
    assert len(msh.cells_dict["hexahedron"]) == nx * ny * nz
    assert len(msh.points) == (nx + 1) * (ny + 1) * (nz + 1)
    for axis, n in enumerate(counts):  # nodes on n + 1 equally spaced planes, equally many
        distance = np.abs(msh.points[:, [axis]] - np.linspace(0.0, size[axis], n + 1))
        assert np.all(distance.min(axis=1) < 1e-12)
        per_plane = np.bincount(distance.argmin(axis=1), minlength=n + 1)
        assert np.all(per_plane == len(msh.points) // (n + 1))


@pytest.mark.parametrize("size, level, counts", CASES)
def test_volume_is_the_block_and_cells_are_positive(mesh_files, size, level, counts):
    msh = mesh_files[level]
    volumes = hex_volumes(msh.points, msh.cells_dict["hexahedron"])
    assert np.all(volumes > 0)
    assert volumes.sum() == pytest.approx(np.prod(size), rel=1e-12)


@pytest.mark.parametrize("size, level, counts", CASES)
def test_each_face_is_tagged_on_its_plane(mesh_files, size, level, counts):
    msh = mesh_files[level]
    assert {name: list(v) for name, v in msh.field_data.items()} == {
        "contact": [1, 2], "top": [2, 2], "front": [3, 2], "back": [4, 2],
        "left": [5, 2], "right": [6, 2], "block": [1, 3]}
    quads = np.concatenate([c.data for c in msh.cells if c.type == "quad"])
    tags = np.concatenate([d for c, d in zip(msh.cells, msh.cell_data["gmsh:physical"])
                           if c.type == "quad"])
    for tag, (axis, far) in PLANES.items():
        facets = quads[tags == tag]
        assert len(facets) == np.prod(np.delete(counts, axis))
        coordinate = msh.points[np.unique(facets), axis]
        assert np.allclose(coordinate, size[axis] if far else 0.0, rtol=0, atol=1e-12)


def test_named_constants():
    assert (meshes.CONTACT, meshes.TOP, meshes.FRONT, meshes.BACK, meshes.LEFT,
            meshes.RIGHT, meshes.BLOCK) == (1, 2, 3, 4, 5, 6, 1)


def test_levels_refine_and_coarse_edge_is_about_7_5_mm():
    counts = list(meshes.LEVELS.values())
    assert all(np.all(np.greater(b, a)) for a, b in zip(counts, counts[1:]))
    edges = np.divide(meshes.DEFAULT_SIZE, meshes.LEVELS["coarse"])
    assert 7.0e-3 <= edges.min() and edges.max() <= 8.0e-3


def test_level_counts_and_describe():
    assert meshes.level_counts("medium") == meshes.LEVELS["medium"]
    assert meshes.level_counts("4x4x6") == (4, 4, 6)
    assert "3x4x5 = 60 hexahedra, 120 nodes, 360 DOFs" in meshes.describe("3x4x5")


@pytest.mark.parametrize("level", ["huge", "4x4", ""])
def test_unknown_level_raises_naming_it_and_the_known_ones(level, tmp_path):
    with pytest.raises(ValueError, match=f"'{level}'") as error:
        meshes.block_mesh_file(level=level, cache_dir=tmp_path)
    assert all(name in str(error.value) for name in meshes.LEVELS)
    assert not list(tmp_path.iterdir())


def test_zero_element_counts_are_refused_as_counts(tmp_path):
    with pytest.raises(ValueError, match="'0x2x2': every element count .* must be >= 1"):
        meshes.block_mesh_file(level="0x2x2", cache_dir=tmp_path)
    assert not list(tmp_path.iterdir())


def test_bad_size_raises(tmp_path):
    with pytest.raises(ValueError, match="size"):
        meshes.block_mesh_file((0.03, 0.0, 0.05), "tiny", cache_dir=tmp_path)


def test_cache_returns_the_file_without_remeshing(tmp_path, monkeypatch):
    first = meshes.block_mesh_file(level="tiny", cache_dir=tmp_path)
    mtime = first.stat().st_mtime_ns

    def no_meshing(*args):
        raise AssertionError("meshed again")

    monkeypatch.setattr(block, "block_mesh_model", no_meshing)
    assert meshes.block_mesh_file(level="tiny", cache_dir=tmp_path) == first
    assert first.stat().st_mtime_ns == mtime
    assert list(tmp_path.iterdir()) == [first]  # no temporary file left behind
    with pytest.raises(AssertionError, match="meshed again"):
        meshes.block_mesh_file(level="2x1x1", cache_dir=tmp_path)
    assert list(tmp_path.iterdir()) == [first]  # nor after a failure


def test_file_names_tell_sizes_and_levels_apart(tmp_path):
    paths = {meshes.block_mesh_file(size, level, cache_dir=tmp_path)
             for size in [(0.03, 0.04, 0.053), (0.04, 0.03, 0.053)] for level in ["tiny", "1x1x2"]}
    assert len(paths) == 4 and all(p.parent == tmp_path for p in paths)


def test_default_cache_follows_vibrofric_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("VIBROFRIC_CACHE", str(tmp_path))
    assert meshes.block_mesh_file(level="tiny").parent == tmp_path / "meshes"


def test_a_callers_gmsh_session_survives(tmp_path):
    gmsh = pytest.importorskip("gmsh")
    gmsh.initialize(readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("callers")
        meshes.block_mesh_file(level="1x2x1", cache_dir=tmp_path)
        assert gmsh.model.getCurrent() == "callers"  # fails if gmsh was finalized
    finally:
        gmsh.finalize()
