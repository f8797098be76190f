"""ParaView output: a .pvd time series of the body's node and cell fields.

Every frame holds, on the mesh's Q1 nodes (point data):

    displacement       u (vector, m), including the static preload
    velocity           v (vector, m/s)
    contact_pressure   N_i / a_i (Pa) on the contact nodes, 0 elsewhere
    friction_traction  F_i / a_i (vector, Pa): the friction force per tributary area
    friction_force     F_i (vector, N): the nodal friction force of model/contact.py, so
                       that its sum over the contact face is the series' (F_x, F_y)
    asperity_deformation  the law's elastic deformation (vector, m; Dahl, LuGre: s_i e_i = N' - M)
    slip               (u_x - u0_x - x_b, u_y - u0_y - y_b) (vector, m): the node's
                       displacement relative to the base since the preload
    gap                g_i = g0_i + u_z,i - z_b (m) on the contact candidates, g0_i their
                       height at rest (FEModel.initial_gap), z_b the base's Z (0 where it
                       moves only in its plane); negative: the penalty's penetration. 0
                       elsewhere
    contact_state      0 open, 1 stick, 2 slip on the candidates (outputs/contact_patch.py:
                       slip once |F_i| >= 0.98 mu N_i), 0 elsewhere

(the contact fields are in the XY plane, their Z components 0; paper sign:
F_i acts on the body as -F_i), and on its cells (cell data: each cell's mean,
the DG0 projection of sigma(u) of model/dolfinx_adapter.cell_stress):

    stress             the Cauchy stress tensor sigma (9 components, Pa; tension positive),
                       including the preload's
    von_mises          sqrt(3/2 s:s), s the deviator of sigma (Pa): von_mises()
    normal_stress      sigma_zz (Pa; compression negative): on the bottom layer of cells,
                       the normal stress on the contact, against contact_pressure

docs/fe-model.md ("The ParaView series") describes each for the user; a test holds
its table to FIELDS and CELL_FIELDS. The frame time is the simulated time (a run
answered by its steady cycle: the cycle ending at time.T, integrators/periodic.py).

The files: ``block.pvd`` lists the frames with their times, each frame one
``blockNNNNNN.vtu`` (VTK's XML unstructured grid, binary): the body's nodes
(assembly.Discretization.coordinates) and its hexahedra or tetrahedra (``cells``,
the nodes in VTK's order, as DOLFINx's plot module gives them), the fields above as
point data. What DOLFINx's own VTKFile wrote for the same run holds the same
points, cells and arrays (tests/test_dolfinx_adapter.py); writing from the
arrays needs no DOLFINx, so a run from the model cache never loads it.

A .vtu is written here directly (vtu_text): VTK's XML format with each array
inline and zlib-compressed (VTK's vtkZLibDataCompressor: a header of UInt64
sizes, then the compressed little-endian bytes, each in base64), as meshio
wrote it before; importing meshio took a run longer than writing all its
frames (docs/performance.md, "Design choices measured"). An array whose bytes hardly
deflate (a field's float noise: a velocity shrinks by a few per cent, at tens of
MB/s) is put in the zlib stream stored (level 0), the others are deflated at zlib's
fastest level (_compressed), and a series encodes its mesh (points and cells, the same
in every frame) once (FrameWriter).
"""

import base64
import zlib
from pathlib import Path

import numpy as np

from .contact_patch import contact_state

FIELDS = ("displacement", "velocity", "contact_pressure", "friction_traction",
          "friction_force", "asperity_deformation", "slip", "gap", "contact_state")
SCALAR_FIELDS = ("contact_pressure", "gap", "contact_state")
CELL_FIELDS = ("stress", "von_mises", "normal_stress")


def node_fields(model, state) -> dict:
    """The frame's fields as numpy arrays on the nodes: vectors (nodes, 3), the
    SCALAR_FIELDS (nodes,).

    Plain numpy: FEResult.fields holds these for the run's last step.
    """
    nodes, c = model.disc.nodes, model.contact_nodes
    out = {name: np.zeros((nodes, 3)) for name in FIELDS if name not in SCALAR_FIELDS}
    out["displacement"][:] = state.u.reshape(-1, 3)
    out["velocity"][:] = state.v.reshape(-1, 3)
    out["friction_force"][c, :2] = state.friction
    out["friction_traction"][c, :2] = state.friction / model.contact_area[:, None]
    out["asperity_deformation"][c, :2] = state.deformation
    relative = (state.u - model.u0).reshape(-1, 3)[c]
    out["slip"][c, 0] = relative[:, 0] - state.x_b
    out["slip"][c, 1] = relative[:, 1] - state.y_b
    pressure = np.zeros(nodes)
    pressure[c] = state.normal / model.contact_area
    out["contact_pressure"] = pressure
    gap = np.zeros(nodes)
    # the base's Z displacement: a State of a base moving in its plane only has none
    gap[c] = model.initial_gap + state.u[3 * c + 2] - getattr(state, "z_b", 0.0)
    out["gap"] = gap
    states = np.zeros(nodes)
    states[c] = contact_state(state.normal, state.friction, model.friction_coefficient)
    out["contact_state"] = states
    return out


def von_mises(voigt: np.ndarray) -> np.ndarray:
    """The von Mises equivalent stress sqrt(3 J2) of stresses in Voigt order (..., 6:
    xx, yy, zz, yz, xz, xy):

        sqrt(((s_xx - s_yy)^2 + (s_yy - s_zz)^2 + (s_zz - s_xx)^2) / 2
             + 3 (s_yz^2 + s_xz^2 + s_xy^2))

    (uniaxial stress s: |s|; pure shear t: sqrt(3) |t|)."""
    xx, yy, zz, yz, xz, xy = np.moveaxis(np.asarray(voigt), -1, 0)
    return np.sqrt(0.5 * ((xx - yy) ** 2 + (yy - zz) ** 2 + (zz - xx) ** 2)
                   + 3.0 * (yz ** 2 + xz ** 2 + xy ** 2))


# A Voigt component's places in the row-major 3 x 3 tensor
TENSOR_OF_VOIGT = np.array([[0, 5, 4], [5, 1, 3], [4, 3, 2]]).ravel()


def cell_fields(model, state) -> dict:
    """The frame's cell fields (CELL_FIELDS): stress (cells, 9), von_mises and
    normal_stress (cells,), from the displacement by the cell stress operator."""
    voigt = (model.disc.cell_stress @ state.u).reshape(-1, 6)
    return {"stress": voigt[:, TENSOR_OF_VOIGT], "von_mises": von_mises(voigt),
            "normal_stress": voigt[:, 2].copy()}


class FrameWriter:
    """Writes ``vtk_dir/block.pvd`` (+ a .vtu per frame); call with a recording.State."""

    def __init__(self, model, vtk_dir):
        self.model = model
        self.path = Path(vtk_dir) / "block.pvd"
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.times = []
        self.frames = 0
        self.mesh = None        # the frames' mesh as vtu_mesh encodes it, made once

    def __call__(self, state) -> None:
        disc = self.model.disc
        if self.mesh is None:
            self.mesh = vtu_mesh(disc.coordinates, disc.cells, disc.cell_type)
        name = f"{self.path.stem}{self.frames:06d}.vtu"
        (self.path.parent / name).write_text(vtu_text(disc.coordinates, disc.cells,
                                                      node_fields(self.model, state),
                                                      cell_fields(self.model, state),
                                                      disc.cell_type, self.mesh))
        self.times.append((state.t, name))
        self.frames += 1

    def close(self) -> None:
        """Write the .pvd: the frames written so far, with their times."""
        self.path.write_text(collection(self.times))


def quoteattr(text: str) -> str:
    """``text`` as an XML attribute value, in double quotes (xml.sax.saxutils'
    quoteattr, whose module imports urllib and ssl with it)."""
    escaped = text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
    return '"' + escaped.replace('"', "&quot;") + '"'


VTK_HEXAHEDRON = 12  # VTK's cell type of the linear hexahedron (8 corners in VTK's order)
VTK_TETRAHEDRON = 10  # and of the linear tetrahedron (4 corners)


SAMPLE_BYTES = 1 << 16   # the leading bytes deflated to judge an array (_compressed)
STORED_ABOVE = 0.9       # the sample deflating to more than this of itself: stored
DEFLATE_LEVEL = 1        # zlib's fastest: on a run's fields within a few per cent of the
                         # default level's size, in a fraction of its time (performance.md)


def _compressed(raw: bytes) -> bytes:
    """``raw`` as a zlib stream: deflated, or stored (level 0: the same stream format,
    read alike) where its first SAMPLE_BYTES deflate to more than STORED_ABOVE of
    themselves; deflated at DEFLATE_LEVEL."""
    if (len(raw) > SAMPLE_BYTES and len(zlib.compress(raw[:SAMPLE_BYTES], DEFLATE_LEVEL))
            > STORED_ABOVE * SAMPLE_BYTES):
        return zlib.compress(raw, 0)
    return zlib.compress(raw, DEFLATE_LEVEL)


def _data_array(values: np.ndarray, vtk_type: str, name: str, components: int = 1) -> str:
    """One inline DataArray, "binary" and compressed in one block: base64 of the header
    (blocks, block size, last block's size, its compressed size: UInt64), then base64
    of the compressed bytes."""
    raw = np.ascontiguousarray(values).tobytes()
    packed = _compressed(raw)
    header = np.array([1, len(raw), len(raw), len(packed)], dtype="<u8").tobytes()
    encoded = base64.b64encode(header).decode() + base64.b64encode(packed).decode()
    count = f' NumberOfComponents="{components}"' if components > 1 else ""
    return (f'<DataArray type="{vtk_type}" Name={quoteattr(name)}{count} format="binary">'
            f"{encoded}</DataArray>\n")


def _data_arrays(data: dict) -> str:
    """Float64 DataArrays of ``data`` (name: (n,) or (n, components))."""
    return "".join(_data_array(np.asarray(v, dtype="<f8"), "Float64", name,
                               1 if np.ndim(v) == 1 else np.shape(v)[1])
                   for name, v in data.items())


def vtu_mesh(points: np.ndarray, cells: np.ndarray, cell_type: int = VTK_HEXAHEDRON) -> str:
    """A .vtu's Piece opening, Points and Cells: ``cells`` (cells, corners) of VTK's type
    ``cell_type`` (VTK_HEXAHEDRON: 8 corners, VTK_TETRAHEDRON: 4) over ``points``
    (nodes, 3)."""
    cells = np.asarray(cells, dtype="<i8")
    offsets = np.arange(1, cells.shape[0] + 1, dtype="<i8") * cells.shape[1]
    types = np.full(cells.shape[0], cell_type, dtype=np.uint8)
    return (f'<Piece NumberOfPoints="{len(points)}" NumberOfCells="{len(cells)}">\n'
            "<Points>\n" + _data_array(np.asarray(points, dtype="<f8"), "Float64", "Points", 3)
            + "</Points>\n<Cells>\n"
            + _data_array(cells.ravel(), "Int64", "connectivity")
            + _data_array(offsets, "Int64", "offsets")
            + _data_array(types, "UInt8", "types")
            + "</Cells>\n")


def vtu_text(points: np.ndarray, cells: np.ndarray, point_data: dict,
             cell_data: dict | None = None, cell_type: int = VTK_HEXAHEDRON,
             mesh: str | None = None) -> str:
    """A .vtu (VTK XML unstructured grid) of ``cells`` over ``points`` (vtu_mesh, or its
    text ``mesh`` made once for a series), with the node arrays ``point_data`` (name:
    (nodes,) or (nodes, components)) and the cell arrays ``cell_data`` (name: (cells,)
    or (cells, components))."""
    if mesh is None:
        mesh = vtu_mesh(points, cells, cell_type)
    fields = _data_arrays(point_data)
    cell_part = (f"<CellData>\n{_data_arrays(cell_data)}</CellData>\n" if cell_data else "")
    return ('<?xml version="1.0"?>\n'
            '<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" '
            'header_type="UInt64" compressor="vtkZLibDataCompressor">\n<UnstructuredGrid>\n'
            + mesh + "<PointData>\n" + fields + "</PointData>\n" + cell_part
            + "</Piece>\n</UnstructuredGrid>\n</VTKFile>\n")


def collection(times) -> str:
    """A .pvd (ParaView's collection file) of ``times``: [(t, file name)], each time to
    12 significant digits (a steady cycle's times T - k dt read 0.299781, not
    0.29978099999999996; frames are at least a step apart)."""
    entries = "".join(f'    <DataSet timestep="{float(t):.12g}" group="" part="0" '
                      f'file={quoteattr(name)}/>\n' for t, name in times)
    return ('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n  <Collection>\n'
            + entries + "  </Collection>\n</VTKFile>\n")
