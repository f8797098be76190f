"""What a ParaView frame holds (fem/outputs/paraview.py) against what the guide says
it holds (docs/fe-model.md, "The ParaView series")."""

import re
from types import SimpleNamespace

import numpy as np
import scipy.sparse as sp

from vibrofric.fem.outputs import paraview
from vibrofric.fem.outputs.recording import State

from conftest import ROOT


def documented_fields() -> dict:
    """{field: where} of the table in docs/fe-model.md's "The ParaView series"."""
    text = (ROOT / "docs" / "fe-model.md").read_text()
    section = text.split("## The ParaView series", 1)[1].split("\n## ", 1)[0]
    return dict(re.findall(r"^\| `(\w+)` \| (nodes|cells)\b", section, flags=re.MULTILINE))


def one_hexahedron_frame(tmp_path) -> str:
    """A frame written by FrameWriter of a one-cell block (its four bottom nodes in
    contact), as text."""
    corners = np.array([[x, y, z] for z in (0.0, 1.0) for y in (0.0, 1.0) for x in (0.0, 1.0)])
    disc = SimpleNamespace(nodes=8, coordinates=corners, cells=np.array([[0, 1, 3, 2, 4, 5, 7, 6]]),
                           cell_stress=sp.csr_matrix((6, 24)), cell_type=paraview.VTK_HEXAHEDRON)
    contact = np.arange(4)
    model = SimpleNamespace(disc=disc, contact_nodes=contact, contact_area=np.full(4, 0.25),
                            u0=np.zeros(24), initial_gap=np.zeros(4), friction_coefficient=0.1)
    state = State(step=0, t=0.5, u=np.zeros(24), v=np.zeros(24), law_state=np.zeros((4, 4)),
                  deformation=np.zeros((4, 2)), normal=np.ones(4), friction=np.zeros((4, 2)),
                  x_b=0.0, y_b=0.0)
    writer = paraview.FrameWriter(model, tmp_path)
    writer(state)
    writer.close()
    return (tmp_path / "block000000.vtu").read_text()


def test_every_field_written_is_documented_and_every_documented_one_written(tmp_path):
    """The names of the PointData and CellData arrays of a written frame are exactly the
    guide's table's, each documented on the nodes or the cells where it is written."""
    text = one_hexahedron_frame(tmp_path)

    def names(part):
        block = re.search(rf"<{part}>(.*?)</{part}>", text, flags=re.DOTALL).group(1)
        return set(re.findall(r'Name="(\w+)"', block))

    documented = documented_fields()
    assert names("PointData") == {name for name, where in documented.items() if where == "nodes"}
    assert names("CellData") == {name for name, where in documented.items() if where == "cells"}
    assert set(documented) == set(paraview.FIELDS) | set(paraview.CELL_FIELDS)


def test_von_mises_of_textbook_stress_states():
    """Uniaxial s: |s|; pure shear t (any of the three planes): sqrt(3) |t|; a
    hydrostatic state: 0; a sum of hydrostatic and uniaxial: the uniaxial's
    (von Mises sees the deviator only). Rounding only: 1e-12 relative."""
    s = 2.5e5
    states = np.array([[s, 0, 0, 0, 0, 0], [0, 0, -s, 0, 0, 0], [0, 0, 0, s, 0, 0],
                       [0, 0, 0, 0, -s, 0], [0, 0, 0, 0, 0, s], [-s, -s, -s, 0, 0, 0],
                       [s - 3e5, -3e5, -3e5, 0, 0, 0]])
    expected = [s, s, np.sqrt(3) * s, np.sqrt(3) * s, np.sqrt(3) * s, 0.0, s]
    assert np.allclose(paraview.von_mises(states), expected, rtol=1e-12, atol=1e-12 * s)


def test_the_stress_tensor_is_written_symmetric_from_the_voigt_components():
    """cell_fields: the 9 tensor components row-major, the Voigt shear components
    (yz, xz, xy) on both sides of the diagonal; normal_stress is sigma_zz."""
    voigt = np.array([1.0, 2.0, 3.0, 4.0, 5.0, 6.0])
    disc = SimpleNamespace(cell_stress=sp.csr_matrix(voigt[:, None]))
    fields = paraview.cell_fields(SimpleNamespace(disc=disc), SimpleNamespace(u=np.ones(1)))
    assert np.array_equal(fields["stress"].reshape(3, 3),
                          [[1.0, 6.0, 5.0], [6.0, 2.0, 4.0], [5.0, 4.0, 3.0]])
    assert fields["normal_stress"].tolist() == [3.0]


def test_arrays_are_read_back_whether_deflated_or_stored(tmp_path):
    """A frame's arrays as a VTK reader reads them (meshio's, as ParaView): a field of
    float noise, which hardly deflates, is stored in its zlib stream (level 0: the
    stream no shorter than the bytes), a field of zeros deflated, and both read back
    bit for bit, beside the mesh written once for the series."""
    import meshio

    rng = np.random.default_rng(1)
    points = rng.random((4000, 3))
    cells = np.arange(4000, dtype=np.int64).reshape(-1, 4)
    noise, zeros = rng.standard_normal((4000, 3)), np.zeros(4000)
    mesh = paraview.vtu_mesh(points, cells, paraview.VTK_TETRAHEDRON)
    text = paraview.vtu_text(points, cells, {"noise": noise, "zeros": zeros},
                             cell_type=paraview.VTK_TETRAHEDRON, mesh=mesh)
    assert len(paraview._compressed(noise.tobytes())) > noise.nbytes       # stored
    assert len(paraview._compressed(zeros.tobytes())) < zeros.nbytes / 100  # deflated
    (tmp_path / "frame.vtu").write_text(text)
    read = meshio.read(tmp_path / "frame.vtu")
    assert np.array_equal(read.points, points)
    assert np.array_equal(read.cells_dict["tetra"], cells)
    assert np.array_equal(read.point_data["noise"], noise)
    assert np.array_equal(read.point_data["zeros"], zeros)
