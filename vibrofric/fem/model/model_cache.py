"""The FE model's costly parts kept on disk between runs: the block and its reduction.

A run's set-up meshes the block (gmsh), assembles K, the lumped M and the
face areas (DOLFINx) and, for the reduced integrator, builds the Craig-Bampton
basis (integrators/reduction.py). A repeat run, or every point of a sweep on one block,
would build the same again. This module keeps them in
``disk_cache.cache_root()/models``:

    block-<key>.npz       coordinates, K and the cell stress operator (CSR arrays), M,
                          face areas, volume, cells: keyed by
                          the block's size, mesh level, E, nu, density, the faces
                          asked for, the DOLFINx version and the package's
    reduction-<key>.npz   reduction.Reduction's arrays: keyed by the model's content
                          (reduction.model_key), the cutoff, numpy's, scipy's and
                          the package's versions
    compliance-<key>.npz  the full model's dynamic compliance at one frequency, for the
                          reduction's error estimate (reduction.compliance_error):
                          keyed by the model's content, k_t, the frequency and the
                          same versions

A key covers everything the entry is computed from, so an entry is either
right or never looked up; "the package's version" is its version and the hash
of its sources (friction_law.contract.package_hash), so an edited package
builds afresh. Entries are checked and written atomically (disk_cache.py):
a damaged one is rebuilt, never used; processes building the same entry at
once build it once. The block's entry holds its cells too, from which the
ParaView frames are written (outputs/paraview.py): a run from the cache never loads
DOLFINx, gmsh or MPI.

The values are the computed arrays stored bit for bit (.npz of float64): a
run gives the same results with or without the cache.
VIBROFRIC_MODEL_CACHE=0 turns it off.
"""

import functools
import hashlib
import importlib.metadata
import importlib.util
import json
import os

import numpy as np
import scipy.sparse as sp

from ... import __version__, disk_cache
from ...friction_law.contract import package_hash
from ...meshes import LEVELS
from . import dolfinx_adapter
from .assembly import Discretization, assemble_block

FORMAT = 3   # the entries' layout: a change here makes every entry anew
# Entries of each kind kept: the most recently used (a reduction of the "fine" mesh
# holds its dense basis, ~270 MB; the "coarse" one's ~0.6 MB).
KEPT_ENTRIES = 12


def enabled() -> bool:
    """Whether the model cache is used (VIBROFRIC_MODEL_CACHE=0 turns it off)."""
    return os.environ.get("VIBROFRIC_MODEL_CACHE", "1") != "0"


def directory():
    return disk_cache.cache_root() / "models"


@functools.cache
def dolfinx_version() -> str:
    """The installed DOLFINx's version, read without importing it (slow: docs/first-answer.md)."""
    for name in ("fenics-dolfinx", "dolfinx-solver-real", "dolfinx"):
        try:
            return f"{name} {importlib.metadata.version(name)}"
        except importlib.metadata.PackageNotFoundError:
            continue
    spec = importlib.util.find_spec("dolfinx")
    if spec is None or spec.origin is None:
        return "none"
    return f"{spec.origin} {os.stat(spec.origin).st_mtime_ns}"


def entry_path(kind: str, parts: dict):
    """The file of the entry of ``kind`` computed from ``parts`` (with the package's version)."""
    keyed = {**parts, "kind": kind, "format": FORMAT, "vibrofric": __version__,
             "sources": package_hash()}
    digest = hashlib.sha256(json.dumps(keyed, sort_keys=True).encode()).hexdigest()[:32]
    return directory() / f"{kind}-{digest}.npz"


def cached(kind: str, parts: dict, build) -> dict:
    """The arrays of the entry (kind, parts), ``build()`` run and stored if it is missing."""
    if not enabled():
        return {name: np.asarray(value) for name, value in build().items()}
    path = entry_path(kind, parts)
    arrays, hit = disk_cache.cached_arrays(path, build)
    if hit:
        _touch(path)
    else:
        disk_cache.prune(path.parent, f"{kind}-*.npz", KEPT_ENTRIES)
    return arrays


def _touch(path) -> None:
    """Mark an entry used now (prune keeps the most recently used)."""
    try:
        os.utime(path)
    except OSError:
        pass


def _packed_csr(name: str, matrix: sp.csr_matrix) -> dict:
    return {f"{name}_data": matrix.data, f"{name}_indices": matrix.indices,
            f"{name}_indptr": matrix.indptr, f"{name}_shape": np.array(matrix.shape)}


def _unpacked_csr(name: str, arrays: dict) -> sp.csr_matrix:
    return sp.csr_matrix((arrays[f"{name}_data"], arrays[f"{name}_indices"],
                          arrays[f"{name}_indptr"]),
                         shape=tuple(int(n) for n in arrays[f"{name}_shape"]))


def _packed(disc: Discretization, faces) -> dict:
    arrays = {"coordinates": disc.coordinates, **_packed_csr("K", disc.stiffness),
              **_packed_csr("S", disc.cell_stress), "mass": disc.mass,
              "volume": disc.volume, "cells": disc.cells}
    for tag in faces:
        arrays[f"face_{tag}"] = disc.face_area[tag]
    return arrays


def _unpacked(arrays: dict, level: str, faces) -> Discretization:
    K = _unpacked_csr("K", arrays)
    K.has_sorted_indices = True   # as dolfinx_adapter made it (sorted before it was stored)
    return Discretization(level=level, coordinates=arrays["coordinates"], stiffness=K,
                          mass=arrays["mass"],
                          face_area={tag: arrays[f"face_{tag}"] for tag in faces},
                          volume=float(arrays["volume"]), cells=arrays["cells"],
                          cell_stress=_unpacked_csr("S", arrays))


def block(comm, size, level, E, nu, density, faces) -> Discretization:
    """assembly.assemble_block's Discretization, from the cache when it holds it
    (``comm`` None: MPI.COMM_SELF, started only if DOLFINx is needed)."""
    faces = tuple(faces)
    parts = _block_parts(size, level, E, nu, density, faces)

    def build():
        return _packed(assemble_block(dolfinx_adapter.communicator(comm), size, level, E, nu,
                                      density, faces), faces)

    return _unpacked(cached("block", parts, build), level, faces)


def _block_parts(size, level, E, nu, density, faces) -> dict:
    """What a block's entry is computed from (its key)."""
    return {"size": [float(s) for s in size], "level": level, "E": float(E), "nu": float(nu),
            "density": float(density), "faces": list(faces), "dolfinx": dolfinx_version()}


def cached_levels(size, E, nu, density, faces) -> list[str]:
    """The refinement levels (meshes.LEVELS) whose block of these inputs the cache holds."""
    if not enabled():
        return []
    return [level for level in LEVELS
            if entry_path("block", _block_parts(size, level, E, nu, density, tuple(faces))).exists()]
