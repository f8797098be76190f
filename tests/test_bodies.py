"""The bodies of a scene's [body] as meshes (meshes.body_mesh): the built-in shapes and a
user's own file, their groups, placement, volumes and sizes, and every bad body refused
before any work with the key to change."""

import math
import pathlib
import textwrap

import meshio
import numpy as np
import pytest

from vibrofric import meshes
from vibrofric import scene as scene_module
from vibrofric.core.errors import BadBody
from vibrofric.meshes import checks, mesh_data, refinement, shapes

from conftest import ROOT

EXAMPLES = ROOT / "examples" / "bodies"
STEEL = 7850.0   # kg/m^3

# The built-in shapes as scenes set them: (name, [body] keys).
SHAPES = {
    "ball": {"shape": "ball", "radius": 0.01},
    "hemisphere": {"shape": "ball", "radius": 0.01, "hemisphere": True},
    "pin": {"shape": "cylinder", "radius": 0.004, "height": 0.02, "edge_radius": 0.0005},
    "sharp pin": {"shape": "cylinder", "radius": 0.004, "height": 0.02},
    "roller": {"shape": "roller", "radius": 0.005, "length": 0.02},
}


def shape_body(name, **more):
    keys = dict(SHAPES[name], **more)
    probe = scene_module.Body(**{k: v for k, v in keys.items() if k != "mass"})
    keys.setdefault("mass", STEEL * shapes.volume(probe))
    return scene_module.from_dict({"body": keys}).body


@pytest.fixture(scope="module")
def cache(tmp_path_factory):
    return tmp_path_factory.mktemp("bodies")


def read(body_mesh):
    """The body's .msh through meshio (an independent reader): points, tetrahedra and
    hexahedra, and each named facet group's nodes."""
    msh = meshio.read(body_mesh.path)
    tags = {name: tag for name, (tag, dim) in msh.field_data.items() if dim == 2}
    groups = {}
    for block, physical in zip(msh.cells, msh.cell_data["gmsh:physical"]):
        if block.type in ("triangle", "quad"):
            for name, tag in tags.items():
                nodes = block.data[physical == tag].ravel()
                groups[name] = np.union1d(groups.get(name, []), nodes).astype(int)
    return msh, groups


def volumes(msh):
    total = 0.0
    if "tetra" in msh.cells_dict:
        total += mesh_data.tetrahedron_volumes(msh.points, msh.cells_dict["tetra"]).sum()
    if "hexahedron" in msh.cells_dict:
        total += mesh_data.hexahedron_volumes(msh.points, msh.cells_dict["hexahedron"]).sum()
    return total


@pytest.mark.parametrize("name", SHAPES)
def test_a_shape_is_placed_with_its_groups_and_its_volume(cache, name):
    body = shape_body(name)
    mesh = meshes.body_mesh(body, "coarse", cache_dir=cache)
    msh, groups = read(mesh)
    assert set(mesh.facet_groups) == {"contact", "load"} == set(groups)
    assert mesh.facet_groups == {"contact": shapes.CONTACT, "load": shapes.LOAD}
    assert set(msh.cells_dict) >= {"tetra"} and "hexahedron" not in msh.cells_dict
    # placed: the lowest contact node on the base's plane, no node below it
    assert msh.points[groups["contact"], 2].min() == 0.0
    assert msh.points[:, 2].min() == 0.0
    assert mesh.placement == (0.0, 0.0, 0.0)
    # the candidates are the lower facets and the load's the upper ones (the roller's
    # halves meet on the lines at the axis' height: equal to rounding)
    top_of_contact = msh.points[groups["contact"], 2].max()
    assert top_of_contact <= msh.points[groups["load"], 2].min() + 1e-12 * body.radius
    # The mesh inscribes the curved surface: its volume is below the closed form, by
    # the facets' chord deficit, about (h / R)^2 / 4 for facets of edge h on a radius
    # R; h_body / R = 1/3 at "coarse" and gmsh's facets reach ~1.2 times the target, so
    # (h_body / R)^2 / 2 bounds it.
    exact = shapes.volume(body)
    _, h_body = refinement.sizes("coarse", body.radius)
    assert volumes(msh) == pytest.approx(mesh.volume, rel=1e-12)
    assert 0.0 < 1.0 - mesh.volume / exact < 0.5 * (h_body / body.radius) ** 2


def test_the_pins_closed_form_volume_takes_off_the_rounding():
    """Against the sharp pin's pi R^2 H, and the ring the rounding takes off integrated
    over its height: at z in [0, r] the section's radius is R - r + sqrt(r^2 - (r - z)^2)."""
    sharp, rounded = shape_body("sharp pin"), shape_body("pin")
    R, r = rounded.radius, rounded.edge_radius
    assert shapes.volume(sharp) == pytest.approx(math.pi * R ** 2 * 0.02, rel=1e-15)
    z = (np.arange(200000) + 0.5) * r / 200000          # midpoint rule
    inner = R - r + np.sqrt(r * r - (r - z) ** 2)
    ring = np.sum(math.pi * (R ** 2 - inner ** 2)) * r / 200000
    # (the midpoint rule's error: the integrand's square-root end at z = 0 limits it to
    # about (dz / r)^1.5 of the ring)
    assert shapes.volume(sharp) - shapes.volume(rounded) == pytest.approx(ring, rel=1e-6)


def test_the_ball_refines_toward_its_pole_and_resolves_its_hertz_patch_at_fine(cache):
    body = shape_body("ball")
    load = 55.0
    a = refinement.hertz_point_radius(load, body.radius, body.E, body.nu)
    mesh = meshes.body_mesh(body, "fine", cache_dir=cache, normal_load=load)
    msh, groups = read(mesh)
    tets = msh.cells_dict["tetra"]
    edges = np.linalg.norm(msh.points[tets[:, 1]] - msh.points[tets[:, 0]], axis=1)
    distance = np.linalg.norm(msh.points[tets].mean(axis=1), axis=1)   # from the pole
    # N = 5 elements across the patch's radius: a disk of radius a triangulated with
    # edges a / N holds about (2 pi / sqrt 3) N^2 = 3.6 N^2 nodes; the edge grows within
    # the patch (by GRADING), so at least 2 N^2
    elements = refinement.PATCH_ELEMENTS["fine"]
    in_patch = np.linalg.norm(msh.points[groups["contact"]], axis=1) < a
    assert np.count_nonzero(in_patch) >= 2 * elements ** 2
    # and 20 times larger two radii away
    assert np.median(edges[distance > body.radius]) > 20 * np.median(edges[distance < a])


def test_the_rollers_line_contact_is_too_narrow_for_isotropic_tetrahedra():
    """shapes.patch_radius leaves the roller to its level: its Hertz strip (Johnson eq
    4.45) under the scenes' 55 N is ~10 um wide, against the ball's 0.12 mm patch."""
    roller = shape_body("roller")
    b = refinement.hertz_line_half_width(55.0, roller.radius, roller.length, roller.E, roller.nu)
    assert 5e-6 < b < 2e-5 and shapes.patch_radius(roller, 55.0) is None
    ball = shape_body("ball")
    assert shapes.patch_radius(ball, 55.0) == pytest.approx(1.2e-4, rel=0.02)


def test_the_load_shapes_only_the_levels_that_resolve_the_patch(cache):
    body = shape_body("ball")
    coarse = {meshes.body_mesh(body, "coarse", cache_dir=cache, normal_load=F).path
              for F in (10.0, 55.0, None)}
    fine = {meshes.body_mesh(body, "fine", cache_dir=cache, normal_load=F).path
            for F in (10.0, 55.0)}
    assert len(coarse) == 1 and len(fine) == 2


def test_a_changed_refinement_table_is_a_new_mesh_and_leaves_the_block_alone(tmp_path,
                                                                           monkeypatch):
    """The tables of meshes/refinement.py decide a meshed body's sizes: they are part of
    its cache key, so a changed table meshes anew rather than reading the cached mesh of
    the old one. The block's counts are its own (block.LEVELS): its file is the same."""
    ball, puck = shape_body("ball"), scene_module.load(EXAMPLES / "puck.toml").body
    block = scene_module.load("scenes/longitudinal.toml").body

    def paths():
        return [meshes.body_mesh(body, "tiny", cache_dir=tmp_path).path
                for body in (ball, puck, block)]

    before = paths()
    monkeypatch.setitem(refinement.BODY_DIVISIONS, "tiny", 2)
    after = paths()
    assert after[0] != before[0] and after[1] != before[1]   # the shape, a .geo
    assert after[2] == before[2]                                # the block
    # and the new mesh is the new table's: edges half as long away from the contact
    assert len(read(meshes.body_mesh(ball, "tiny", cache_dir=tmp_path))[0].points) > len(
        meshio.read(before[0]).points)


def test_a_results_directory_holds_its_body_file_and_the_files_it_names(tmp_path):
    """A user's .geo, and the file it includes, are copied into the results directory
    and named there (output.write_scene_and_inputs): moved elsewhere, the originals gone,
    its scene.toml meshes the same body (the cache key of the same content) and answers
    the same."""
    import shutil

    from vibrofric.api import run_analytic

    part = tmp_path / "part"
    part.mkdir()
    geo = (EXAMPLES / "puck.geo").read_text()
    sizes = "R = 0.02;    // m, radius\nH = 0.01;    // m, height\n"
    assert sizes in geo
    (part / "sizes.geo").write_text(sizes)
    (part / "puck.geo").write_text(geo.replace(sizes, 'Include "sizes.geo";\n'))
    (part / "puck.toml").write_text((EXAMPLES / "puck.toml").read_text())
    scene = scene_module.load(part / "puck.toml").with_values({"time.T": 0.3})
    first = run_analytic(scene, out=tmp_path / "results")
    key = meshes.body_mesh(scene.body, "coarse", cache_dir=tmp_path / "meshes").key

    moved = tmp_path / "elsewhere"
    shutil.move(tmp_path / "results", moved)
    shutil.rmtree(part)
    assert sorted(p.name for p in moved.glob("*.geo")) == ["puck.geo", "sizes.geo"]
    again = scene_module.load(moved / "scene.toml")
    assert again.body.mesh == str(moved / "puck.geo")
    assert meshes.body_mesh(again.body, "coarse", cache_dir=tmp_path / "meshes").key == key
    assert run_analytic(again).F_dv_over_F_d0 == first.F_dv_over_F_d0


def test_the_block_is_the_same_file_as_ever(cache):
    scene = scene_module.load("scenes/longitudinal.toml")
    mesh = meshes.body_mesh(scene.body, "coarse", cache_dir=cache)
    assert mesh.path == meshes.block_mesh_file(scene.body.size, "coarse", cache_dir=cache)
    assert mesh.path.name == "block_0.03x0.04x0.053m_4x5x7_v1.msh"
    assert mesh.volume == math.prod(scene.body.size)


def test_the_example_geo_block_is_the_built_in_blocks_mesh(cache):
    """examples/bodies/block.geo meshes the built-in block's hexahedra at "coarse": the same
    nodes, cells and contact and load (top) faces, in coordinates (node numbers may differ)."""
    user = scene_module.load(EXAMPLES / "block.toml")
    assert pathlib.Path(user.body.mesh) == EXAMPLES / "block.geo"   # relative to the scene
    built_in = scene_module.load("scenes/longitudinal.toml")
    ours = read(meshes.body_mesh(user.body, "coarse", cache_dir=cache))
    block = read(meshes.body_mesh(built_in.body, "coarse", cache_dir=cache))

    def cells(msh):
        return sorted(tuple(sorted(map(tuple, msh.points[c].round(12)))) for c in
                      msh.cells_dict["hexahedron"])

    def nodes(msh, group):
        return sorted(map(tuple, msh[0].points[msh[1][group]].round(12)))

    assert cells(ours[0]) == cells(block[0])
    assert nodes(ours, "contact") == nodes(block, "contact")
    assert nodes(ours, "load") == nodes(block, "top")


def test_shipped_body_scenes_mesh(cache):
    for name in ("ball", "pin"):
        scene = scene_module.load(f"scenes/{name}.toml")
        mesh = meshes.body_mesh(scene.body, scene.fem.mesh, cache_dir=cache,
                                normal_load=scene.contact.F_N)
        assert mesh.tag("contact") is not None
        # the scenes' masses are steel's
        assert scene.body.mass / mesh.volume == pytest.approx(STEEL, rel=0.05)


def test_the_dolfinx_bridge_reads_a_shapes_facet_tags(cache):
    gmshio = pytest.importorskip("dolfinx.io.gmshio")
    from mpi4py import MPI

    mesh = meshes.body_mesh(shape_body("ball"), "coarse", cache_dir=cache)
    with meshes.gmsh_model("read") as gmsh:
        gmsh.merge(str(mesh.path))
        dmesh, cell_tags, facet_tags = gmshio.model_to_mesh(gmsh.model, MPI.COMM_SELF, 0, gdim=3)
    assert set(np.unique(facet_tags.values)) == set(mesh.facet_groups.values())
    assert set(np.unique(cell_tags.values)) == {mesh.cell_group}


# --- a user's own file --------------------------------------------------------------

BOX = """
SetFactory("OpenCASCADE");
Box(1) = {{0, 0, {z0}, {a}, {a}, {a}}};
Physical Volume("part") = {{1}};
{groups}
"""


def user_body(tmp_path, text, name="part.geo", **keys):
    path = tmp_path / name
    path.write_text(textwrap.dedent(text)) if isinstance(text, str) else path.write_bytes(text)
    return scene_module.from_dict({"body": {"mesh": str(path), **keys}}).body


def box_geo(z0=0.0, a=0.02, groups='Physical Surface("contact") = {5};'):
    # (OpenCASCADE's box: surface 5 is z = z0, 6 is its top)
    return BOX.format(z0=z0, a=a, groups=groups)


def test_a_geo_part_is_meshed_placed_and_refined_toward_its_contact(tmp_path, cache):
    body = user_body(tmp_path, box_geo(z0=0.01), mass=STEEL * 0.02 ** 3)
    mesh = meshes.body_mesh(body, "coarse", cache_dir=cache)
    msh, groups = read(mesh)
    assert mesh.placement == pytest.approx((0.0, 0.0, -0.01), abs=1e-15)
    assert msh.points[:, 2].min() == pytest.approx(0.0, abs=1e-15)
    assert mesh.volume == pytest.approx(0.02 ** 3, rel=1e-9)   # a box: exact in tetrahedra
    assert "moved by -0.01 m" in mesh.description
    tets = msh.cells_dict["tetra"]
    edges = np.linalg.norm(msh.points[tets[:, 1]] - msh.points[tets[:, 0]], axis=1)
    height = msh.points[tets, 2].mean(axis=1)
    assert np.median(edges[height < 0.002]) < 0.5 * np.median(edges[height > 0.015])


def test_a_msh_file_is_read_as_it_is(tmp_path, cache):
    placed = meshes.body_mesh(scene_module.load(EXAMPLES / "block.toml").body, "coarse",
                              cache_dir=cache)
    body = user_body(tmp_path, placed.path.read_bytes(), "block.msh", mass=0.5)
    coarse = meshes.body_mesh(body, "coarse", cache_dir=cache)
    assert meshes.body_mesh(body, "fine", cache_dir=cache).path == coarse.path
    assert coarse.volume == pytest.approx(math.prod(meshes.DEFAULT_SIZE), rel=1e-12)


def test_a_step_part_is_read_in_metres_its_bottom_contact_and_its_top_load(tmp_path, cache):
    """A STEP file declares its unit (gmsh writes millimetres, as most CAD does): a box of
    20 x 20 x 10 mm drawn 5 mm above the origin is read as 0.02 x 0.02 x 0.01 m, placed."""
    step = tmp_path / "part.step"
    with meshes.gmsh_model("step") as gmsh:
        gmsh.model.occ.addBox(0, 0, 5, 20, 20, 10)
        gmsh.model.occ.synchronize()
        gmsh.write(str(step))
    assert "SI_UNIT(.MILLI.,.METRE.)" in step.read_text()
    body = scene_module.from_dict({"body": {"mesh": str(step), "mass": STEEL * 4e-6}}).body
    mesh = meshes.body_mesh(body, "coarse", cache_dir=cache)
    msh, groups = read(mesh)
    assert mesh.volume == pytest.approx(4e-6, rel=1e-9)
    assert mesh.placement == pytest.approx((0.0, 0.0, -0.005), rel=1e-12)
    assert msh.points[groups["contact"], 2].max() == pytest.approx(0.0, abs=1e-12)
    assert msh.points[groups["load"], 2].min() == pytest.approx(0.01, rel=1e-9)


# --- bad bodies, each refused with its key before any work ----------------------------

def refusal(body, cache, **kwargs):
    with pytest.raises(BadBody) as caught:
        meshes.body_mesh(body, "coarse", cache_dir=cache, **kwargs)
    assert "\n" not in str(caught.value)
    return scene_module.refused(caught.value)


def test_a_mesh_without_a_contact_group_is_refused(tmp_path, cache):
    body = user_body(tmp_path, box_geo(groups='Physical Surface("bottom") = {5};'), mass=0.06)
    error = refusal(body, cache)
    assert error.key == "body.mesh" and "'contact'" in str(error)


def test_a_file_gmsh_cannot_read_is_refused(tmp_path, cache):
    body = user_body(tmp_path, "$MeshFormat\nnot a mesh\n", "broken.msh")
    error = refusal(body, cache)
    assert error.key == "body.mesh" and "gmsh cannot read" in str(error)


def test_a_flat_mesh_is_refused(tmp_path, cache):
    text = """
    SetFactory("OpenCASCADE");
    Rectangle(1) = {0, 0, 0, 0.02, 0.02};
    Physical Surface("contact") = {1};
    """
    error = refusal(user_body(tmp_path, text), cache)
    assert "no volume" in str(error)


MSH_ONE_TET = """\
$MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
2
2 1 "contact"
3 2 "body"
$EndPhysicalNames
$Nodes
4
1 0 0 0
2 0.01 0 0
3 0 0.01 0
4 0 0 0.01
$EndNodes
$Elements
2
1 2 2 1 1 1 3 2
2 4 2 2 1 {order}
$EndElements
"""


def test_an_inverted_mesh_is_refused(tmp_path, cache):
    density = 0.01 ** 3 / 6 * STEEL
    good = user_body(tmp_path, MSH_ONE_TET.format(order="1 2 3 4"), "good.msh", mass=density)
    assert meshes.body_mesh(good, "coarse", cache_dir=cache).volume == pytest.approx(0.01 ** 3 / 6)
    bad = user_body(tmp_path, MSH_ONE_TET.format(order="1 3 2 4"), "bad.msh", mass=density)
    error = refusal(bad, cache)
    assert "inverted" in str(error)


def test_a_body_starting_inside_the_base_is_refused(tmp_path, cache):
    """Its contact group is its top face: the rest of the body lies below it."""
    body = user_body(tmp_path, box_geo(groups='Physical Surface("contact") = {6};'),
                     mass=STEEL * 0.02 ** 3)
    error = refusal(body, cache)
    assert "inside the base" in str(error)


def test_a_part_drawn_in_millimetres_is_refused(tmp_path, cache):
    body = user_body(tmp_path, box_geo(a=20.0), mass=STEEL * 0.02 ** 3)
    error = refusal(body, cache)
    assert error.key == "body.mesh" and "millimetres" in str(error)
    # the same part with its density given is taken as meant
    meant = scene_module.from_dict({"body": {"mesh": body.mesh, "mass": 0.06, "density": 0.0075}})
    assert meshes.body_mesh(meant.body, "coarse", cache_dir=cache).volume > 1.0


def test_a_mesh_too_large_for_the_memory_is_refused(cache, monkeypatch):
    monkeypatch.setattr(checks, "available_memory", lambda: 100 * checks.BYTES_PER_NODE)
    error = refusal(shape_body("ball"), cache)
    assert error.key == "fem.mesh" and "memory" in str(error)


@pytest.mark.parametrize("keys, key", [
    ({"shape": "ball", "radius": 10.0, "mass": 0.5}, "body.radius"),   # drawn in mm
    ({"shape": "ball", "radius": 0.01}, "body.mass"),   # the block's 0.5 kg: 119,000 kg/m^3
    ({"shape": "ball"}, "body.radius"),
    ({"shape": "ball", "radius": -0.01}, "body.radius"),
    ({"shape": "cylinder", "radius": 0.004}, "body.height"),
    ({"shape": "roller", "radius": 0.004}, "body.length"),
    ({"shape": "cylinder", "radius": 0.004, "height": 0.02, "edge_radius": 0.004}, "body.edge_radius"),
    ({"radius": 0.01}, "body.radius"),                                   # not the block's
    ({"shape": "ball", "radius": 0.01, "mass": 0.03, "height": 0.01}, "body.height"),
    ({"shape": "ball", "radius": 0.01, "mass": 0.03, "size": [0.1, 0.1, 0.1]}, "body.size"),
    ({"shape": "roller", "radius": 0.005, "length": 0.02, "hemisphere": True}, "body.hemisphere"),
    ({"shape": "ball", "radius": 0.01, "mass": 0.03, "mesh": "x.msh"}, "body.shape"),
    ({"shape": "cube"}, "body.shape"),
    ({"mesh": "part.txt"}, "body.mesh"),
    ({"mesh": "no-such-part.msh"}, "body.mesh"),
])
def test_bad_body_keys_are_refused_when_the_scene_is_read(keys, key, refused_key):
    assert refused_key(lambda: scene_module.from_dict({"body": keys})) == key


def test_the_scene_names_the_shapes_the_meshes_draw():
    assert set(scene_module.schema.SHAPE_KEYS) == {"block", *shapes.SHAPES}


def test_a_hexahedron_folded_at_a_corner_is_refused():
    """A unit cube whose top corner above the origin is pushed through the bottom: its
    volume stays > 0, its Jacobian at that corner does not."""
    cube = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
                     [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], dtype=float)
    folded = cube.copy()
    folded[4] = [0.9, 0.9, 0.2]
    for points, refused in ((cube, False), (folded, True)):
        data = mesh_data.MeshData(points, {mesh_data.HEXAHEDRON: np.arange(8)[None, :]})
        assert mesh_data.hexahedron_volumes(points, data.cells[5])[0] > 0
        if refused:
            with pytest.raises(BadBody, match="inverted, flat or folded"):
                checks.check_cells(data, "a cell")
        else:
            checks.check_cells(data, "a cell")


def test_the_lumped_normal_stiffness_is_asked_for_under_another_body(refused_key):
    """contact.k_n's default is the block's FE bounce: another body's must be given."""
    keys = {"body": {"shape": "ball", "radius": 0.01, "mass": 0.0329},
            "vibration": {"normal_amplitude": 1e-7}}
    assert refused_key(lambda: scene_module.from_dict(keys)) == "contact.k_n"
    given = scene_module.from_dict({**keys, "contact": {"k_n": 1e8}})
    assert given.normal_stiffness == 1e8


def test_explicit_counts_are_the_blocks_alone(refused_key):
    keys = {"body": {"shape": "ball", "radius": 0.01, "mass": 0.0329}, "fem": {"mesh": "4x4x4"}}
    assert refused_key(lambda: scene_module.from_dict(keys)) == "fem.mesh"


def test_a_bad_body_on_the_command_line_is_one_line_exit_2_nothing_written(tmp_path, capsys):
    from vibrofric.cli import EXIT_BAD_INPUT, main

    out = tmp_path / "never"
    code = main(["analytic", "scenes/ball.toml", "--set", "body.radius=10", "--out", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == EXIT_BAD_INPUT and not out.exists()
    assert len(err) == 1 and "body.radius" in err[0] and "millimetres" in err[0]


@pytest.mark.slow   # the pin's model and its stable step: 33 s here, loaded
def test_the_explicit_fe_run_refuses_the_pin_s_step_before_any_work(tmp_path, capsys):
    """The pin's explicit stable step (2.7e-8 s at "coarse": its small tetrahedra and
    its flat end's penalty) is far below the scene's 1e-6 s: one line naming time.dt and
    the integrators without that bound, nothing written."""
    from vibrofric.cli import EXIT_BAD_INPUT, main

    out = tmp_path / "never"
    code = main(["run", "scenes/pin.toml", "--set", "fem.integrator=explicit", "--out", str(out)])
    err = [line for line in capsys.readouterr().err.splitlines()
           if line.startswith("vibrofric:") and "compiling" not in line]
    assert code == EXIT_BAD_INPUT and not out.exists()
    assert len(err) == 1 and "time.dt" in err[0] and "stable step" in err[0]
    assert 'fem.integrator = "reduced"' in err[0]


def test_meshing_a_body_leaves_a_callers_gmsh_options_as_they_were(tmp_path):
    with meshes.gmsh_model("caller") as gmsh:
        before = {name: gmsh.option.getNumber(name) for name in refinement.OPTIONS}
        meshes.body_mesh(shape_body("roller"), "tiny", cache_dir=tmp_path)
        assert {name: gmsh.option.getNumber(name) for name in refinement.OPTIONS} == before


def test_a_mesh_is_named_relative_to_the_scene_file_or_on_the_command_line_to_here(
        tmp_path, monkeypatch):
    scene = scene_module.load("scenes/longitudinal.toml", ["body.mesh=examples/bodies/block.geo"])
    assert scene.body.mesh == str(EXAMPLES / "block.geo")
    # a scene as run, written and read back elsewhere, names the same file
    (tmp_path / "again.toml").write_text(scene_module.to_toml(scene_module.load(
        EXAMPLES / "puck.toml")))
    monkeypatch.chdir(tmp_path)
    assert scene_module.load("again.toml").body.mesh == str(EXAMPLES / "puck.geo")


def test_groups_naming_the_same_faces_become_one_group_under_both_names(tmp_path, cache):
    """The top named both "load" and "drive" (a part pressed and pulled from its top): one
    facet tag, both names; the FE model's facets carry one tag each, so two groups on the
    same faces would otherwise leave one of them empty."""
    groups = ('Physical Surface("contact") = {5};\n'
              'Physical Surface("load") = {6};\nPhysical Surface("drive") = {6};')
    body = user_body(tmp_path, box_geo(groups=groups), mass=STEEL * 0.02 ** 3)
    mesh = meshes.body_mesh(body, "coarse", cache_dir=cache)
    assert mesh.tag("load") == mesh.tag("drive") != mesh.tag("contact")
    _, found = read(mesh)
    top = found[next(name for name, tag in mesh.facet_groups.items()
                     if tag == mesh.tag("load") and name in found)]
    assert len(top) > 0


def test_groups_sharing_only_some_faces_are_refused(tmp_path, cache):
    groups = ('Physical Surface("contact") = {5};\n'
              'Physical Surface("load") = {6};\nPhysical Surface("drive") = {1, 6};')
    body = user_body(tmp_path, box_geo(groups=groups), mass=STEEL * 0.02 ** 3)
    error = refusal(body, cache)
    assert error.key == "body.mesh"
    assert "'load' and 'drive' share some surfaces but not all" in str(error)
