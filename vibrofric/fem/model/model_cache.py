"""The FE model's costly parts kept on disk between runs: the body and its reduction.

A run's set-up reads the body's mesh (a meshes.BodyMesh), assembles K, the lumped M
and the facet groups' areas (DOLFINx) and, for the reduced integrator, builds the
Craig-Bampton basis (integrators/reduction.py). A repeat run, or every point of a
sweep on one body, would build the same again. This module keeps them in
``disk_cache.cache_root()/models``:

    body-<key>.npz        coordinates, K and the cell stress operator (CSR arrays), M,
                          the groups' areas, volume, cells and their VTK type: keyed by
                          the mesh's content (BodyMesh.key) and its groups' tags, E, nu,
                          density, the groups asked for, the DOLFINx version and the
                          package's
    source-<key>.npz      the name of the body entry a scene's body at a mesh level was
                          built into: keyed by what the scene says of its body and the
                          level (fe_model.cached_levels asks it without meshing)
    preload-<key>.npz     the static preload (preload.static_preload): u0, the contact
                          forces and patch, keyed by a digest of everything it is solved
                          from (K, the load, the candidates, their springs, shares and
                          gaps, k_t, F_N, the elimination order)
    reduction-<key>.npz   reduction.Reduction's small arrays (the reduced matrices, the
                          boundary, the drive's and the compliance loads' projections)
                          and its basis's SHA-256: keyed by the model's content
                          (reduction.model_key), the cutoff, numpy's, scipy's and
                          the package's versions
    basis-<key>.npy       the reduction's basis T (dofs x size, dense: 0.7 GB on a 47k
                          DOF ball), same key: a plain .npy file, mapped into memory
                          and checked against that SHA-256 only when a run first
                          expands a state into the whole field (its frames, its last
                          fields): the steps need only the small arrays
    compliance-<key>.npz  the full model's dynamic compliance at one frequency, for the
                          reduction's error estimate (reduction.compliance_error):
                          keyed by the model's content, k_t, the frequency, what its
                          loads and springs act on (the preload's patch), its solver's
                          tolerance and the same versions

A key covers everything the entry is computed from, so an entry is either
right or never looked up; "the package's version" is its version and the hash
of its sources (friction_law.contract.package_hash), so an edited package
builds afresh. Entries are checked and written atomically (disk_cache.py):
a damaged one is rebuilt, never used; processes building the same entry at
once build it once. The body's entry holds its cells too, from which the
ParaView frames are written (outputs/paraview.py): a run from the cache never loads
DOLFINx, gmsh or MPI.

The values are the computed arrays stored bit for bit (.npz of float64, the basis
a .npy): a run gives the same results with or without the cache.
VIBROFRIC_MODEL_CACHE=0 turns it off.
"""

import functools
import hashlib
import importlib.metadata
import importlib.util
import json
import os

import numpy as np
import scipy
import scipy.sparse as sp

from ... import __version__, disk_cache
from ...friction_law.contract import package_hash
from . import dolfinx_adapter
from .assembly import Discretization, assemble_body

FORMAT = 4   # the entries' layout: a change here makes every entry anew
# Entries of each kind kept: the most recently used (the basis of the "fine" block's
# reduction ~270 MB, the "coarse" one's ~0.6 MB).
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


def array_file(kind: str, parts: dict):
    """The .npy file of the large array of ``kind`` computed from ``parts``."""
    return entry_path(kind, parts).with_suffix(".npy")


def store_array(kind: str, parts: dict, array: np.ndarray) -> str:
    """Keep ``array`` as the file array_file(kind, parts) (where the cache is on and can
    be written); its SHA-256 (the cache off: ""), which the entry naming it holds
    (mapped_array checks it)."""
    if not enabled():
        return ""
    path = array_file(kind, parts)
    try:
        disk_cache.write_array_file(path, array)
    except OSError:
        pass                        # passed by, as an entry that cannot be written
    disk_cache.prune(path.parent, f"{kind}-*.npy", KEPT_ENTRIES)
    return disk_cache.array_digest(array)


def mapped_array(kind: str, parts: dict, digest: str, shape: tuple):
    """The array store_array kept (mapped read-only), or None: the cache off, the file
    pruned or damaged (then removed)."""
    if not enabled():
        return None
    path = array_file(kind, parts)
    array = disk_cache.mapped_array(path, digest, shape)
    if array is not None:
        _touch(path)
    return array


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


def _packed(disc: Discretization) -> dict:
    arrays = {"coordinates": disc.coordinates, **_packed_csr("K", disc.stiffness),
              **_packed_csr("S", disc.cell_stress), "mass": disc.mass,
              "volume": disc.volume, "cells": disc.cells, "cell_type": disc.cell_type,
              "groups": np.array(sorted(disc.face_area))}
    for name, area in disc.face_area.items():
        arrays[f"area_{name}"] = area
    return arrays


def _unpacked(arrays: dict, description: str) -> Discretization:
    K = _unpacked_csr("K", arrays)
    K.has_sorted_indices = True   # as dolfinx_adapter made it (sorted before it was stored)
    return Discretization(description=description, coordinates=arrays["coordinates"],
                          stiffness=K, mass=arrays["mass"],
                          face_area={str(name): arrays[f"area_{name}"] for name in arrays["groups"]},
                          volume=float(arrays["volume"]), cells=arrays["cells"],
                          cell_stress=_unpacked_csr("S", arrays),
                          cell_type=int(arrays["cell_type"]))


def body(comm, body_mesh, E, nu, density, groups, source=None) -> Discretization:
    """assembly.assemble_body's Discretization of ``body_mesh`` (a meshes.BodyMesh), from
    the cache when it holds it (``comm`` None: MPI.COMM_SELF, started only if DOLFINx is
    needed). ``source``: what the mesh was made from (a dict), remembered as leading to
    this entry (holds_source)."""
    groups = tuple(groups)
    parts = body_parts(body_mesh, E, nu, density, groups)

    def build():
        return _packed(assemble_body(dolfinx_adapter.communicator(comm), body_mesh, E, nu,
                                     density, groups))

    disc = _unpacked(cached("body", parts, build), body_mesh.description)
    if source is not None and enabled():
        alias = entry_path("source", {**source, "dolfinx": dolfinx_version()})
        name = entry_path("body", parts).name.encode()
        if disk_cache.read_entry(alias) != name:
            disk_cache.write_entry(alias, name)
            disk_cache.prune(alias.parent, "source-*.npz", SOURCES_KEPT)
    return disc


def preload(solve, stiffness, load, nodes, penalty_share, area_share, k_t, F_N, order,
            initial_gap) -> tuple:
    """``solve(...)``'s (u0, normal, in_contact) (preload.static_preload, which it is given
    with these arguments), from the cache when it holds them: a curved body's preload
    factorizes the whole model (docs/performance.md, 2026-11-27). A refusal is not kept."""
    digest = hashlib.blake2b(digest_size=16)
    for array in (stiffness.indptr, stiffness.indices, stiffness.data, load, nodes,
                  penalty_share, area_share, initial_gap,
                  np.zeros(0) if order is None else order):
        digest.update(np.ascontiguousarray(array).tobytes())
    parts = {"inputs": digest.hexdigest(), "k_t": float(k_t), "F_N": float(F_N),
             "ordered": order is not None, "numpy": np.__version__,
             "scipy": scipy.__version__, "dolfinx": dolfinx_version()}

    def build():
        u0, normal, in_contact = solve(stiffness, load, nodes, penalty_share, area_share, k_t,
                                       F_N, order, initial_gap)
        return {"u0": u0, "normal": normal, "in_contact": in_contact}

    arrays = cached("preload", parts, build)
    return arrays["u0"], arrays["normal"], arrays["in_contact"]


# Source entries kept (each a few bytes): those of the kept bodies, at every level
SOURCES_KEPT = 8 * KEPT_ENTRIES


def holds_source(source) -> bool:
    """Whether the cache holds the body entry that ``source`` was last built into."""
    if not enabled():
        return False
    name = disk_cache.read_entry(entry_path("source", {**source, "dolfinx": dolfinx_version()}))
    return name is not None and (directory() / name.decode()).exists()


def body_parts(body_mesh, E, nu, density, groups) -> dict:
    """What a body's entry is computed from (its key)."""
    return {"mesh": body_mesh.key, "tags": {name: body_mesh.tag(name) for name in groups},
            "E": float(E), "nu": float(nu), "density": float(density), "groups": list(groups),
            "dolfinx": dolfinx_version()}
