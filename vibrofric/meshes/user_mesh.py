"""A user's own body: a gmsh .msh file read, a .geo or STEP file meshed with gmsh.

    .msh         read as it is (any format gmsh reads); fem.mesh does not change it
    .geo         gmsh's own script, run; if it meshes nothing in 3D, meshed here with the
                 level's sizes, refined toward its "contact" surfaces
                 (meshes/refinement.py). Its own mesh controls (transfinite curves,
                 extrusion layers, characteristic lengths it sets) are kept
    .step .stp   imported with OpenCASCADE, converted to metres from the unit the file
                 declares, and meshed likewise. A STEP file names no
                 groups: "contact" is every surface reaching the part's bottom (lowest
                 z) but not its top, "load" every surface reaching its top but not its
                 bottom. To choose them, write a .geo
                 that merges the STEP file and names its Physical Surfaces.

Each is loaded into the current gmsh model (``load``); a file gmsh cannot read, or
one without a "contact" group, is refused (core.errors.BadBody) before any meshing.

Groups may name the same surfaces (the top of a part both its "load" and its "drive"):
a facet carries one tag in the FE model, so such groups become one group under two
names (``merge_shared_groups``); groups that share only some surfaces are refused.
"""

import hashlib
import re
from pathlib import Path

import numpy as np

from ..core.errors import BadBody
from . import refinement

SUFFIXES = (".msh", ".geo", ".step", ".stp")


def source_path(mesh, scene_dir=None) -> Path:
    """The mesh file named by body.mesh: relative to ``scene_dir`` (the scene file's folder;
    default: the current directory) unless absolute; refused unless a readable file of a
    known kind."""
    path = Path(mesh).expanduser()
    if not path.is_absolute() and scene_dir is not None:
        path = Path(scene_dir) / path
    if path.suffix.lower() not in SUFFIXES:
        raise BadBody(f"{mesh}: not a mesh or geometry file gmsh is asked to read here "
                      f"(use {', '.join(SUFFIXES)})")
    if not path.is_file():
        raise BadBody(f"{path}: no such file")
    return path.resolve()


def named_files(path: Path) -> list:
    """The files a .geo names in quotes (Merge "part.step", Include "common.geo") that
    exist beside it, as (name as written, path), sorted by name; none for other kinds."""
    if path.suffix.lower() != ".geo":
        return []
    names = sorted(set(re.findall(r'"([^"\n]+)"', path.read_text(errors="replace"))))
    return [(name, path.parent / name) for name in names
            if (path.parent / name).is_file() and path.parent / name != path]


def content_hash(path: Path) -> str:
    """SHA-256 of the file, and of the files it names (``named_files``): what its mesh is
    made of."""
    digest = hashlib.sha256(path.read_bytes())
    for name, other in named_files(path):
        digest.update(name.encode() + other.read_bytes())
    return digest.hexdigest()


def load(gmsh, path: Path, level: str) -> tuple | None:
    """Load ``path`` into the current gmsh model and mesh it if it holds no 3D mesh;
    return the sizes (h_contact, h_body) it was meshed with, None if it came meshed."""
    model = gmsh.model
    suffix = path.suffix.lower()
    try:
        if suffix in (".step", ".stp"):
            _import_step(gmsh, path)
            _name_step_groups(model)
        else:
            gmsh.merge(str(path))   # (a .geo is synchronized as its script ends)
    except Exception as err:
        raise BadBody(f"{path}: gmsh cannot read it ({_gmsh_message(err)})") from None
    if not model.getEntities(3):
        raise BadBody(f"{path}: holds no volume (a body is a 3D mesh or solid)")
    contact = [tag for dim, tag in model.getPhysicalGroups(2)
               if model.getPhysicalName(dim, tag) == "contact"]
    if not contact:
        raise BadBody(f"{path}: has no Physical Surface named 'contact' (the facets that may "
                      "touch the base)")
    if len(model.mesh.getElements(3)[0]):   # meshed already (a .msh; a .geo saying Mesh 3)
        return None
    surfaces = model.getEntitiesForPhysicalGroup(2, contact[0])
    box = np.array(model.getBoundingBox(-1, -1))
    scale = 0.5 * float(np.prod(box[3:] - box[:3])) ** (1.0 / 3.0)   # a ball's: 0.8 R
    h_contact, h_body = refinement.sizes(refinement.check_level(level), scale)
    refinement.surface_distance_field(gmsh, surfaces, h_contact, h_body)
    gmsh.option.setNumber("Mesh.ElementOrder", 1)
    try:
        model.mesh.generate(3)
    except Exception as err:
        raise BadBody(f"{path}: gmsh cannot mesh it ({_gmsh_message(err)})") from None
    return h_contact, h_body


def _import_step(gmsh, path: Path) -> None:
    """Import a STEP file converted to metres from the unit it declares (CAD files are
    mostly in millimetres), gmsh's unit option put back afterwards."""
    unit = gmsh.option.getString("Geometry.OCCTargetUnit")
    gmsh.option.setString("Geometry.OCCTargetUnit", "M")
    try:
        gmsh.model.occ.importShapes(str(path))
        gmsh.model.occ.synchronize()
    finally:
        gmsh.option.setString("Geometry.OCCTargetUnit", unit)


def _name_step_groups(model) -> None:
    """The STEP part's groups: its volumes; contact, the surfaces reaching its bottom; load,
    those reaching its top. A surface reaching both (a box's side) is neither, unless it
    is all there is (a sphere's one face)."""
    volumes = [tag for _, tag in model.getEntities(3)]
    if not volumes:
        return
    box = np.array(model.getBoundingBox(-1, -1))
    eps = 1e-6 * float((box[3:] - box[:3]).max())
    boxes = {s: model.getBoundingBox(2, s) for _, s in model.getEntities(2)}
    bottom = {s for s, b in boxes.items() if b[2] <= box[2] + eps}
    top = {s for s, b in boxes.items() if b[5] >= box[5] - eps}
    for tag, name, surfaces in ((1, "contact", (bottom - top) or bottom),
                                (2, "load", (top - bottom) or top)):
        model.addPhysicalGroup(2, sorted(surfaces), tag)
        model.setPhysicalName(2, tag, name)
    model.addPhysicalGroup(3, volumes, 1)
    model.setPhysicalName(3, 1, "body")


def ensure_volume_group(model) -> int:
    """The tag of the mesh's volume group, made (named "body", over every volume) if the
    file has none: DOLFINx's gmsh bridge reads only cells in a physical group."""
    groups = model.getPhysicalGroups(3)
    if groups:
        return groups[0][1]
    model.addPhysicalGroup(3, [tag for _, tag in model.getEntities(3)], 1)
    model.setPhysicalName(3, 1, "body")
    return 1


NAMED_GROUPS = ("contact", "load", "drive")


def merge_shared_groups(model, what: str) -> dict:
    """{name: the group it is the same as}: of the named facet groups (NAMED_GROUPS), each
    that names the same surfaces as one before it is removed from ``model`` and
    answered by that one's name; groups sharing only some of their surfaces are refused
    (BadBody: a facet carries one group in the FE model)."""
    tags = {model.getPhysicalName(2, tag): tag for _, tag in model.getPhysicalGroups(2)}
    surfaces = {name: frozenset(int(s) for s in model.getEntitiesForPhysicalGroup(2, tags[name]))
                for name in NAMED_GROUPS if name in tags}
    same_as = {}
    names = list(surfaces)
    for i, name in enumerate(names):
        for earlier in names[:i]:
            if earlier in same_as or not surfaces[name] & surfaces[earlier]:
                continue
            if surfaces[name] != surfaces[earlier]:
                raise BadBody(f"{what}: its groups '{earlier}' and '{name}' share some surfaces "
                              "but not all; a facet belongs to one group, so make them the "
                              "same surfaces or separate ones")
            same_as[name] = earlier
            model.removePhysicalGroups([(2, tags[name])])
            break
    return same_as


def _gmsh_message(err) -> str:
    text = str(err).strip() or type(err).__name__
    return text.splitlines()[0]
