"""Structured hexahedral mesh of the sliding block, built by gmsh and cached.

The block occupies [0, Lx] x [0, Ly] x [0, Lz]: X is the sliding direction,
Z points up and the contact face is z = 0. It is meshed with nx x ny x nz
first-order hexahedra (8 nodes, transfinite and recombined), and its six faces
are physical groups whose tags are the module constants below.

gmsh is imported only while a mesh is built or read. gmsh 4.8 resets Ctrl-C
(SIGINT) to the default handler until ``gmsh.finalize()``, newer versions also
SIGTERM, for good: ``gmsh_model`` puts Python's handlers back. This package
never imports DOLFINx: ``vibrofric.fem.model.dolfinx_adapter.load_block`` turns the
cached file into a DOLFINx mesh.
"""

import contextlib
import os
import re
import signal
import threading
import uuid
from pathlib import Path

DEFAULT_SIZE = (0.03, 0.04, 0.053)  # m: Lx (sliding), Ly, Lz (height)

# Refinement levels: element counts (nx, ny, nz). From "coarse" on each level
# halves the element edge: about 7.5 mm at "coarse" on the default block.
LEVELS = {
    "tiny": (1, 1, 1),
    "coarse": (4, 5, 7),
    "medium": (8, 10, 14),
    "fine": (16, 20, 28),
    "finer": (32, 40, 56),
}

# Physical group tags. Facets (dim 2):
CONTACT = 1  # z = 0, on the base
TOP = 2      # z = Lz
FRONT = 3    # x = Lx, the face the drive pulls (the block slides in +X)
BACK = 4     # x = 0
LEFT = 5     # y = 0
RIGHT = 6    # y = Ly
# Cells (dim 3):
BLOCK = 1

# tag -> (physical name, normal axis 0/1/2, True if the face is at the far end)
FACES = {
    CONTACT: ("contact", 2, False),
    TOP: ("top", 2, True),
    FRONT: ("front", 0, True),
    BACK: ("back", 0, False),
    LEFT: ("left", 1, False),
    RIGHT: ("right", 1, True),
}

# Part of every cache file name: bump it when the meshes written here change.
_FORMAT = "v1"


def level_counts(level: str) -> tuple:
    """Return the element counts (nx, ny, nz) of a level.

    ``level`` is a name from LEVELS or explicit counts written "NXxNYxNZ"
    (e.g. "4x4x6"). Anything else raises ValueError naming it.
    """
    if level in LEVELS:
        return LEVELS[level]
    match = re.fullmatch(r"(\d+)x(\d+)x(\d+)", str(level))
    if match:
        counts = tuple(int(n) for n in match.groups())
        if min(counts) < 1:
            raise ValueError(f"mesh level {level!r}: every element count (NXxNYxNZ) must be >= 1")
        return counts
    raise ValueError(f"unknown mesh level {level!r}: use one of "
                     f"{', '.join(LEVELS)}, or element counts such as '4x4x6'")


def describe(level: str, size=DEFAULT_SIZE) -> str:
    """One line on a level: its counts, elements, nodes, DOFs and edge lengths."""
    nx, ny, nz = level_counts(level)
    nodes = (nx + 1) * (ny + 1) * (nz + 1)
    edges = " x ".join(f"{1e3 * L / n:.3g}" for L, n in zip(_checked_size(size), (nx, ny, nz)))
    return (f"{level}: {nx}x{ny}x{nz} = {nx * ny * nz} hexahedra, {nodes} nodes, "
            f"{3 * nodes} DOFs, element edges {edges} mm")


def _checked_size(size) -> tuple:
    """Return size as three floats, or raise ValueError unless all are > 0."""
    size = tuple(float(L) for L in size)
    if len(size) != 3 or not all(L > 0 for L in size):
        raise ValueError(f"block size must be three lengths > 0 (m), got {size}")
    return size


@contextlib.contextmanager
def gmsh_model(name: str):
    """Yield the gmsh module with a new, empty, silent model ``name`` current.

    Initializes gmsh if needed and finalizes it afterwards only in that case,
    so that a caller's own gmsh session survives; the model is removed. The
    Ctrl-C and SIGTERM handlers are Python's again afterwards.
    """
    handlers = _signal_handlers()
    import gmsh

    owner = not _gmsh_initialized(gmsh)
    if owner:
        gmsh.initialize(readConfigFiles=False)
    else:
        previous_model = gmsh.model.getCurrent()
        previous_terminal = gmsh.option.getNumber("General.Terminal")
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add(name)
    try:
        yield gmsh
    finally:
        gmsh.model.setCurrent(name)
        gmsh.model.remove()
        if owner:
            gmsh.finalize()
        else:
            gmsh.model.setCurrent(previous_model)
            gmsh.option.setNumber("General.Terminal", previous_terminal)
        for number, handler in handlers.items():
            signal.signal(number, handler)


def _signal_handlers() -> dict:
    """Python's SIGINT and SIGTERM handlers ({} outside the main thread, which cannot set them)."""
    if threading.current_thread() is not threading.main_thread():
        return {}
    return {number: signal.getsignal(number) for number in (signal.SIGINT, signal.SIGTERM)}


def _gmsh_initialized(gmsh) -> bool:
    """Whether gmsh is initialized.

    gmsh 4.8 has no ``gmsh.isInitialized()``. An initialized gmsh always holds
    a model (``initialize`` creates one); before the first ``initialize`` the
    model list is empty, and after ``finalize`` asking for it raises.
    """
    if hasattr(gmsh, "isInitialized"):
        return bool(gmsh.isInitialized())
    try:
        return len(gmsh.model.list()) > 0
    except Exception:
        return False


@contextlib.contextmanager
def block_mesh_model(size=DEFAULT_SIZE, level: str = "coarse"):
    """Build and mesh the block in gmsh; yield the gmsh module, block model current.

    The model holds the hexahedral mesh and the physical groups (the volume
    BLOCK, the faces CONTACT ... RIGHT, all named); it is removed on exit.
    """
    Lx, Ly, Lz = lengths = _checked_size(size)
    counts = level_counts(level)
    with gmsh_model("vibrofric-block") as gmsh:
        occ, model = gmsh.model.occ, gmsh.model
        volume = occ.addBox(0.0, 0.0, 0.0, Lx, Ly, Lz)
        occ.synchronize()

        for _, curve in model.getEntities(1):
            box = model.getBoundingBox(1, curve)
            axis = max(range(3), key=lambda a: box[a + 3] - box[a])
            model.mesh.setTransfiniteCurve(curve, counts[axis] + 1)
        for _, surface in model.getEntities(2):
            model.mesh.setTransfiniteSurface(surface)
            model.mesh.setRecombine(2, surface)
        model.mesh.setTransfiniteVolume(volume)

        model.addPhysicalGroup(3, [volume], BLOCK)
        model.setPhysicalName(3, BLOCK, "block")
        eps = 1e-3 * min(lengths)
        for tag, (name, axis, far) in FACES.items():
            # The one face inside a thin slab around its plane.
            low, high = [-eps] * 3, [L + eps for L in lengths]
            plane = lengths[axis] if far else 0.0
            low[axis], high[axis] = plane - eps, plane + eps
            (_, surface), = model.getEntitiesInBoundingBox(*low, *high, dim=2)
            model.addPhysicalGroup(2, [surface], tag)
            model.setPhysicalName(2, tag, name)

        model.mesh.generate(3)
        yield gmsh


def default_cache_dir() -> Path:
    """The default mesh cache: meshes/ in disk_cache.cache_root() ($VIBROFRIC_CACHE, else
    $XDG_CACHE_HOME/vibrofric, else ~/.cache/vibrofric)."""
    from ..disk_cache import cache_root

    return cache_root() / "meshes"


def block_mesh_file(size=DEFAULT_SIZE, level: str = "coarse", cache_dir=None) -> Path:
    """Return the path of the block's .msh file (gmsh format 4.1), meshing it if absent.

    The file lives in ``cache_dir`` (default: ``default_cache_dir()``) under a name made
    of the size and the element counts, and is written to a temporary name then
    renamed, so a reader never sees a half-written file.
    """
    size = _checked_size(size)
    counts = level_counts(level)
    folder = Path(cache_dir) if cache_dir is not None else default_cache_dir()
    name = "block_{}x{}x{}m_{}x{}x{}_{}.msh".format(*map(repr, size), *counts, _FORMAT)
    path = folder / name
    if path.exists():
        return path

    folder.mkdir(parents=True, exist_ok=True)
    tmp = folder / f".{path.stem}.{uuid.uuid4().hex}.msh"  # unique to this writer
    try:
        with block_mesh_model(size, level) as gmsh:
            gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
            gmsh.write(str(tmp))
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)
    return path
