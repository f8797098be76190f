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

``body_mesh`` makes the BodyMesh of a scene's [body]: the block (block_body, the same
file as ever), a built-in shape (meshes/shapes.py) or the user's file
(meshes/user_mesh.py), placed (meshes/placement.py), checked (meshes/checks.py) and
cached like the block's (a content-keyed name, written whole then renamed).
"""

import hashlib
import json
import os
import signal
import uuid
from dataclasses import dataclass, field
from pathlib import Path

from . import block, checks, placement, refinement, shapes, user_mesh
from .mesh_data import FIRST_ORDER_CELLS, read_model

# Part of every cache file name of a shape or a user's body: bump it when the meshes
# written here change.
_FORMAT = "b2"


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


def body_mesh(body, level: str, scene_dir=None, cache_dir=None, normal_load=None) -> BodyMesh:
    """The BodyMesh of a scene's Body at fem.mesh ``level``.

    body.shape "block" without body.mesh: block_body. A shape, or body.mesh (a path
    relative to ``scene_dir`` unless absolute), is meshed or read with gmsh, placed with
    its lowest contact node on z = 0 and checked; ``normal_load`` (N, the scene's F_N)
    lets the ball's "fine" and "finer" levels resolve its Hertz patch
    (meshes/refinement.py). Refusals are core.errors.BadBody naming the key to change.
    """
    if body.mesh is None and body.shape == "block":
        return block_body(body.size, level, cache_dir)
    if body.mesh is not None:
        source = user_mesh.source_path(body.mesh, scene_dir)
        what = f"body.mesh {source.name}"
        kind = source.suffix.lower().lstrip(".")
        # a .msh is read as it is; anything else is meshed at the level's sizes
        level_part = "" if kind == "msh" else refinement.level_key(level)
        meshed_by = "" if kind == "msh" else _gmsh_version()  # another gmsh meshes otherwise
        content = f"{kind} {user_mesh.content_hash(source)} {level_part} {meshed_by}"
        stem = f"{source.stem}_{kind}"
    else:
        source, what = None, f"body.shape {body.shape}"
        refinement.check_level(level)
        # the load shapes the mesh only where it sizes the Hertz patch
        if level not in refinement.PATCH_ELEMENTS or shapes.patch_radius(body, normal_load) is None:
            normal_load = None
        content = f"{body.shape} {sorted(shapes.dimensions(body).items())} {body.E!r} {body.nu!r} " \
                  f"{normal_load!r} {refinement.level_key(level)} {_gmsh_version()}"
        stem = body.shape
    folder = Path(cache_dir) if cache_dir is not None else block.default_cache_dir()
    name = f"{stem}_{hashlib.sha256(content.encode()).hexdigest()[:16]}_{_FORMAT}"
    path, notes = folder / f"{name}.msh", folder / f"{name}.json"
    if not (path.exists() and notes.exists()):
        _write(path, notes, body, level, source, normal_load, what)
    facts = json.loads(notes.read_text())   # the placement and sizes, as written
    with block.gmsh_model("vibrofric-body-check") as gmsh:
        gmsh.merge(str(path))
        data = read_model(gmsh)
    volume = float(checks.check_cells(data, what).sum())
    checks.check_groups(data, what)
    if body.density is None:
        lengths = "body.mesh" if body.mesh is not None else "body.radius"
        checks.check_density(body.mass, volume, what,
                             checks.density_key(body.mass, volume, lengths))
    checks.check_memory(len(data.points), what, _memory_key(body))
    cell_kinds = " and ".join(f"{len(c):,} {FIRST_ORDER_CELLS[t]}" for t, c in data.cells.items())
    sizes = facts["sizes"]
    sized = ""
    if sizes:
        sized = f", edges {1e3 * sizes[0]:.3g} mm at the contact to {1e3 * sizes[1]:.3g} mm"
        if source is not None:
            sized += " where the file sets none"
    dz = facts["placement"][2]
    groups = data.facet_groups()
    groups.update({name: groups[other] for name, other in facts["same_as"].items()})
    return BodyMesh(path=path, facet_groups=groups,
                    cell_group=data.cell_groups()[0].tag, volume=volume,
                    key=f"{stem} {hashlib.sha256(path.read_bytes()).hexdigest()}",
                    placement=tuple(facts["placement"]),
                    description=f"{what} ({level if sizes else 'as meshed'}): "
                                f"{len(data.points):,} nodes, {cell_kinds}{sized}; placed "
                                f"{'as drawn' if dz == 0 else f'moved by {dz:+.4g} m in Z'}")


def _write(path: Path, notes: Path, body, level, source, normal_load, what) -> None:
    """Mesh or read the body, check and place it, and write the cache's .msh (format 4.1)
    and its notes (the placement, the sizes), each to a temporary name then renamed."""
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.parent / f".{path.stem}.{uuid.uuid4().hex}"
    with block.gmsh_model("vibrofric-body") as gmsh, refinement.gmsh_options(gmsh):
        if source is None:
            sizes = shapes.build(gmsh, body, level, normal_load)
        else:
            sizes = user_mesh.load(gmsh, source, level)
            user_mesh.ensure_volume_group(gmsh.model)
        same_as = user_mesh.merge_shared_groups(gmsh.model, what)
        data = read_model(gmsh)
        checks.check_cells(data, what)
        checks.check_groups(data, what)
        checks.check_memory(len(data.points), what, _memory_key(body))
        shift = placement.translation(data)
        placement.move(gmsh, data, shift)
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        try:
            Path(f"{tmp}.json").write_text(json.dumps({"placement": list(shift),
                                                       "sizes": sizes and list(sizes),
                                                       "same_as": same_as}))
            gmsh.write(f"{tmp}.msh")
            os.replace(f"{tmp}.json", notes)
            os.replace(f"{tmp}.msh", path)
        finally:
            Path(f"{tmp}.json").unlink(missing_ok=True)
            Path(f"{tmp}.msh").unlink(missing_ok=True)


def _memory_key(body) -> str:
    """The key that makes a body's mesh smaller: its file's, or fem.mesh (a shape's level)."""
    return "body.mesh" if body.mesh is not None else "fem.mesh"


def _gmsh_version() -> str:
    """The gmsh that meshes here: part of a meshed body's cache key, as two gmsh releases
    mesh the same shape differently (4.8's coarse ball rests on 3 nodes, 4.15's on a
    patch that does not settle) and two stacks may share the cache."""
    handlers = block._signal_handlers()
    import gmsh

    for number, handler in handlers.items():
        signal.signal(number, handler)
    return gmsh.__version__
