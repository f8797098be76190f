"""A user's own tetrahedral part, run end to end by `vibrofric run`: pressed and pulled
from its top (one face named both "load" and "drive"), it slides, and the run writes its
results and its pictures."""

import csv
import json
import textwrap

import pytest

pytest.importorskip("dolfinx")

PUCK = """\
// a steel box 20 x 20 x 10 mm, pressed and pulled from its top, in 5 mm tetrahedra
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.02, 0.02, 0.01};
Mesh.MeshSizeMin = 0.005;
Mesh.MeshSizeMax = 0.005;
Physical Volume("part") = {1};
Physical Surface("contact") = {5};
Physical Surface("load") = {6};
Physical Surface("drive") = {6};
"""

SCENE = """\
[body]
mesh = "part.geo"
mass = 0.0314            # kg: steel, 7850 kg/m^3 x 4e-6 m^3
[contact]
law = "dahl"
mu = 0.3
F_N = 20.0
k_t = 80e6
[drive]
attach = "drive-group"
k_d = 96068.0
v_d = 0.05               # m/s: F_d reaches mu F_N = 6 N after 1.25 ms
[vibration]
f = 4000.0
k_v = 0.0
[time]
T = 0.004
dt = 1e-7
method = "transient"
error_estimate = false
[fem]
damping = 1e-7           # s: the part's free ringing after breakaway (~100 kHz) damped
                         # within the run, so that its summed normal force is steady
"""


def test_a_tetrahedral_part_pulled_from_its_top_slides_and_its_run_is_written(tmp_path):
    """Its run exits 0 and writes the summary, the series and every picture. The drive's
    force acts on the part: it breaks away and the top moves forward (before the groups
    "load" and "drive" on one face became one group, the drive's was empty and nothing
    moved)."""
    from vibrofric.cli import main

    (tmp_path / "part.geo").write_text(textwrap.dedent(PUCK))
    (tmp_path / "part.toml").write_text(SCENE)
    out = tmp_path / "results"
    assert main(["run", str(tmp_path / "part.toml"), "--set", "fem.integrator=explicit",
                 "--out", str(out)]) == 0
    for name in ("summary.json", "timeseries.csv", "block.png", "drive_force.png"):
        assert (out / name).stat().st_size > 0, name
    json.loads((out / "summary.json").read_text())
    with open(out / "timeseries.csv") as table:
        rows = list(csv.DictReader(table))
    # breakaway: the part slides and, on its drive spring, swings about the sliding force
    # mu F_N = 6 N by v_d sqrt(k_d m) = 2.7 N (the spring-mass oscillation the breakaway
    # starts); the first peak reaches their sum but for the damping and Dahl's rounding
    # of the breakaway (5%)
    peak = max(float(row["F_d"]) for row in rows)
    assert peak == pytest.approx(6.0 + 0.05 * (96068.0 * 0.0314) ** 0.5, rel=0.05)
    assert float(rows[-1]["x"]) > 1e-5     # the top moved forward (v_d T = 2e-4 m pulled)


def test_the_picture_of_a_tetrahedral_contact_face_draws(tmp_path):
    """The contact face of the box, 80 mm tall, meshed at vibrofric's sizes (refined toward the
    contact): its nodes along the straight edges are collinear but for rounding (1e-20 m
    off them in the FE model's coordinates), and the slivers Delaunay put between them made
    matplotlib refuse the triangulation, failing the run after its steps. The picture of
    the model's contact face at rest draws."""
    import numpy as np

    from vibrofric import picture, scene
    from vibrofric.fem.model import fe_model

    geo = PUCK.replace("Mesh.MeshSizeMin = 0.005;\nMesh.MeshSizeMax = 0.005;\n", "")
    geo = geo.replace("0.02, 0.02, 0.01}", "0.02, 0.02, 0.08}")   # 80 mm tall: its face's
    # mesh has such nodes (the 10 mm box's, as gmsh 4.8 meshes it, has none)
    (tmp_path / "part.geo").write_text(textwrap.dedent(geo))
    (tmp_path / "part.toml").write_text(SCENE)
    model = fe_model.build_model(scene.load(tmp_path / "part.toml"), None)
    coordinates = model.disc.coordinates
    pressure = np.zeros(len(coordinates))
    pressure[model.contact_nodes] = model.normal0 / model.contact_area
    traction = np.zeros((len(coordinates), 3))
    traction[model.contact_nodes, 0] = 0.3 * pressure[model.contact_nodes]
    fields = {"coordinates": coordinates, "contact_nodes": model.contact_nodes,
              "contact_pressure": pressure, "friction_traction": traction, "t": 0.0}
    path = tmp_path / "block.png"
    picture.draw(picture.picture_rows(fields), path)
    assert path.stat().st_size > 10_000
