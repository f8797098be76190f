"""The body on the base as one idea: a placed mesh with named groups.

Whatever the body is (the paper's block, a built-in shape, the user's own
file), the FE model receives a ``BodyMesh``: a gmsh .msh file (format 4.1,
first-order cells) whose physical groups name

    contact   the facets that may touch the base (required): their nodes are the
              contact candidates, each with its own initial gap (its height z)
    load      where the normal load acts as a uniform traction (optional)
    drive     where the drive spring attaches (optional)

and whose coordinates are placed: the lowest contact point lies on z = 0, the
base's plane, X is the sliding direction and Z points up. The block is one
instance (meshes/block.py): its bottom face is ``contact``, its top ``load``,
and its other faces keep their own names (``front`` for drive.attach =
"front-face").
"""

from dataclasses import dataclass, field
from pathlib import Path

from . import block


@dataclass(frozen=True)
class BodyMesh:
    """A placed body mesh and what its groups are called.

    path         the .msh file (gmsh format 4.1), already placed
    facet_groups {name: physical tag} of the facet groups ("contact" always)
    cell_group   the physical tag of the body's volume
    volume       the body's volume, m^3 (its density is mass / volume unless body.density
                 is given): the block's L_x L_y L_z, a shape's or a user mesh's from its cells
    key          what identifies the mesh's content for the model cache (equal keys:
                 the same nodes, cells and groups)
    placement    (3,) the translation applied to the source's coordinates, m
    description  one line for summaries and errors
    """

    path: Path
    facet_groups: dict = field(hash=False)
    cell_group: int
    volume: float
    key: str
    placement: tuple = (0.0, 0.0, 0.0)
    description: str = ""

    def tag(self, name: str):
        """The physical tag of facet group ``name``, None if the mesh has none."""
        return self.facet_groups.get(name)


# The block's faces by the names the FE model asks for (meshes/block.py FACES), with
# the top face as the load's group.
BLOCK_GROUPS = {**{name: tag for tag, (name, _, _) in block.FACES.items()}, "load": block.TOP}


def block_body(size, level: str, cache_dir=None) -> BodyMesh:
    """The paper's block as a BodyMesh (its contact face already on z = 0)."""
    path = block.block_mesh_file(size, level, cache_dir)
    counts = block.level_counts(level)
    return BodyMesh(path=path, facet_groups=dict(BLOCK_GROUPS), cell_group=block.BLOCK,
                    volume=float(size[0] * size[1] * size[2]),
                    key=f"block {tuple(float(s) for s in size)} {counts}",
                    description=block.describe(level, size))
