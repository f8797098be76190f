"""ParaView output: a .pvd time series of the block's node fields (DOLFINx VTKFile,
through ``dolfinx_adapter.VTKSeries``).

Every frame holds, on the mesh's Q1 nodes:

    displacement       u (vector, m), including the static preload
    velocity           v (vector, m/s)
    contact_pressure   N_i / a_i (Pa) on the contact nodes, 0 elsewhere
    friction_traction  F_i / a_i (vector, Pa): the friction force per tributary area
    friction_force     F_i (vector, N): the nodal friction force of contact.py, so
                       that its sum over the contact face is the series' (F_x, F_y)
    asperity_deformation  the law's elastic deformation (vector, m; Dahl, LuGre: s_i e_i = N' - M)
    slip               (u_x - u0_x - x_b, u_y - u0_y - y_b) (vector, m): the node's
                       displacement relative to the base since the preload

(the contact fields are in the XY plane, their Z components 0; paper sign:
F_i acts on the body as -F_i). The frame time is the simulated time.

DOLFINx 0.5.2's VTKFile writes files that readers mishandle; each frame is
repaired right after it is written (``repair_frame``):

- the .pvtu lists its one piece once per function written (7 times here), so
  ParaView and pyvista load the block 7 times over and every sum over the
  points is 7 times too large: each piece is kept once;
- a scalar is declared with NumberOfComponents="0" in the .pvtu: set to 1;
- the .vtu is stamped version "2.2", VTK 9.1's marker for its new node
  ordering of *higher-order* Lagrange hexahedra (degree 1, written here, is
  ordered the same either way), which meshio (5.x) refuses: stamped "1.0".
"""

import re
from pathlib import Path

import numpy as np

from .dolfinx_adapter import VTKSeries, communicator

FIELDS = ("displacement", "velocity", "contact_pressure", "friction_traction",
          "friction_force", "asperity_deformation", "slip")


def node_fields(model, state) -> dict:
    """The frame's fields as numpy arrays on the nodes: vectors (nodes, 3), contact_pressure (nodes,).

    Plain numpy: FEResult.fields holds these for the run's last step.
    """
    nodes, c = model.disc.nodes, model.contact_nodes
    out = {name: np.zeros((nodes, 3)) for name in FIELDS if name != "contact_pressure"}
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
    return out


class FrameWriter:
    """Writes ``vtk_dir/block.pvd`` (+ .vtu per frame); call with a recording.State."""

    def __init__(self, model, comm, vtk_dir):
        self.model = model
        self.path = Path(vtk_dir) / "block.pvd"
        self.path.parent.mkdir(parents=True, exist_ok=True)
        comm = communicator(comm)
        self.series = VTKSeries(model.disc.vector_space(comm), comm, self.path, FIELDS,
                                scalars=("contact_pressure",))
        self.frames = 0

    def __call__(self, state) -> None:
        self.series.write(node_fields(self.model, state), state.t)
        repair_frame(self.path.parent / f"{self.path.stem}{self.frames:06d}.pvtu")
        self.frames += 1

    def close(self) -> None:
        self.series.close()


def repair_frame(pvtu: Path) -> None:
    """Fix DOLFINx 0.5.2's defects in one frame's .pvtu and its .vtu pieces (see above).

    A file that does not show them (another DOLFINx) is left as it is.
    """
    if not pvtu.exists():
        return
    text = pvtu.read_text()
    pieces = re.findall(r"<Piece [^>]*/>\n?", text)
    kept = list(dict.fromkeys(pieces))
    if len(kept) < len(pieces):
        first = text.index(pieces[0])
        end = text.rindex(pieces[-1]) + len(pieces[-1])
        text = text[:first] + "    ".join(kept) + text[end:]
    text = text.replace('NumberOfComponents="0"', 'NumberOfComponents="1"')
    pvtu.write_text(text)
    for source in re.findall(r'<Piece Source="([^"]+)"', text):
        vtu = pvtu.parent / source
        content = vtu.read_text()
        head = content[:200]
        if 'type="UnstructuredGrid" version="2.2"' in head:
            vtu.write_text(head.replace('version="2.2"', 'version="1.0"', 1) + content[200:])
