"""Files that several processes share: the cache directory, a lock, checked atomic entries.

The cache lives in $VIBROFRIC_CACHE, else $XDG_CACHE_HOME/vibrofric, else
~/.cache/vibrofric (``cache_root``): the meshes (meshes/), the FE models
(models/: fem/model/model_cache.py). ``make clean-cache`` removes it.

Several processes (a sweep's workers, MPI ranks, parallel test workers) may
build the same entry at once. An entry is written to a temporary name in its
directory and renamed into place (rename(2) is atomic), so a reader sees the
old file, the new one or none, never half of one; it starts with the SHA-256
of what follows, so a damaged entry (a full disk, a crash mid-copy, a flipped
bit) is detected, removed and built again rather than used. ``locked`` lets
one process build while the others wait for its result instead of building
it too.
"""

import fcntl
import hashlib
import io
import os
import tempfile
from contextlib import ExitStack, contextmanager
from pathlib import Path

import numpy as np

MAGIC = b"vibrofric-cache 1\n"


def cache_root() -> Path:
    """$VIBROFRIC_CACHE, else $XDG_CACHE_HOME/vibrofric, else ~/.cache/vibrofric."""
    root = os.environ.get("VIBROFRIC_CACHE")
    if root:
        return Path(root)
    xdg = os.environ.get("XDG_CACHE_HOME")
    return (Path(xdg) if xdg else Path.home() / ".cache") / "vibrofric"


@contextmanager
def locked(path: Path):
    """Hold an exclusive lock (flock) on ``path`` (created if need be) for the block.
    The lock goes with the process: one that dies holding it releases it."""
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "a") as handle:
        fcntl.flock(handle, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(handle, fcntl.LOCK_UN)


def write_entry(path: Path, payload: bytes) -> None:
    """Write ``payload`` to ``path`` with its checksum: a temporary file renamed into place."""
    path.parent.mkdir(parents=True, exist_ok=True)
    digest = hashlib.sha256(payload).hexdigest().encode()
    handle, temporary = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.")
    try:
        with os.fdopen(handle, "wb") as file:
            file.write(MAGIC + digest + b"\n" + payload)
            file.flush()
            os.fsync(file.fileno())
        os.replace(temporary, path)
    finally:
        Path(temporary).unlink(missing_ok=True)


def read_entry(path: Path) -> bytes | None:
    """The payload written by write_entry, or None: absent, or damaged (then removed)."""
    try:
        data = path.read_bytes()
    except OSError:                 # absent, or unreadable: not there for this process
        return None
    head = len(MAGIC) + 65
    digest, payload = data[len(MAGIC):head - 1], data[head:]
    if (data[:len(MAGIC)] != MAGIC or data[head - 1:head] != b"\n"
            or hashlib.sha256(payload).hexdigest().encode() != digest):
        _remove(path)
        return None
    return payload


def _remove(path: Path) -> None:
    try:
        path.unlink(missing_ok=True)
    except OSError:
        pass


def write_arrays(path: Path, arrays: dict) -> None:
    """Numbers by name (numpy arrays, floats, ints) as one checked entry (.npz inside)."""
    buffer = io.BytesIO()
    np.savez(buffer, **{name: np.asarray(value) for name, value in arrays.items()})
    write_entry(path, buffer.getvalue())


def read_arrays(path: Path) -> dict | None:
    """What write_arrays wrote, as numpy arrays by name, or None (absent or damaged)."""
    payload = read_entry(path)
    if payload is None:
        return None
    try:
        with np.load(io.BytesIO(payload), allow_pickle=False) as archive:
            return {name: archive[name] for name in archive.files}
    except (ValueError, OSError, KeyError):  # a checksum that matched a foreign payload
        _remove(path)
        return None


def array_digest(array: np.ndarray) -> str:
    """The SHA-256 of an array's bytes in C order (what ``mapped_array`` checks)."""
    return hashlib.sha256(np.ascontiguousarray(array).data).hexdigest()


def write_array_file(path: Path, array: np.ndarray) -> None:
    """Write ``array`` as a .npy file at ``path``: a temporary file renamed into place."""
    path.parent.mkdir(parents=True, exist_ok=True)
    handle, temporary = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.")
    try:
        with os.fdopen(handle, "wb") as file:
            np.save(file, np.ascontiguousarray(array), allow_pickle=False)
            file.flush()
            os.fsync(file.fileno())
        os.replace(temporary, path)
    finally:
        Path(temporary).unlink(missing_ok=True)


def mapped_array(path: Path, digest: str, shape: tuple) -> np.ndarray | None:
    """The float64 array that write_array_file wrote at ``path``, mapped read-only, or
    None: absent, or not the array of SHA-256 ``digest`` and ``shape`` (then removed).
    The map stays valid if another process removes the file meanwhile (pruning)."""
    try:
        array = np.load(path, mmap_mode="r", allow_pickle=False)
    except FileNotFoundError:
        return None
    except (ValueError, OSError):   # a truncated or foreign file
        _remove(path)
        return None
    if (array.dtype != np.float64 or array.shape != tuple(shape)
            or not array.flags.c_contiguous or array_digest(array) != digest):
        del array
        _remove(path)
        return None
    return array.view(np.ndarray)   # a plain array over the map (its products too)


def prune(directory: Path, pattern: str, kept: int) -> None:
    """Remove the entries matching ``pattern`` beyond the ``kept`` most recently modified
    (with their lock files; best effort: another process may be removing them too)."""
    try:
        entries = sorted(directory.glob(pattern), key=lambda p: p.stat().st_mtime, reverse=True)
        for path in entries[kept:]:
            path.unlink(missing_ok=True)
            path.with_name(path.name + ".lock").unlink(missing_ok=True)
    except OSError:
        pass


def cached_arrays(path: Path, build) -> tuple[dict, bool]:
    """(arrays, hit): the entry at ``path``, else ``build()`` (a dict of arrays) written
    there. Processes asking for the same entry at once build it once: the others
    wait on its lock and read it.

    A cache that cannot be written (a read-only or full disk) is passed by: the
    entry is built and used, not stored.
    """
    arrays = read_arrays(path)
    if arrays is not None:
        return arrays, True
    with ExitStack() as stack:
        try:
            stack.enter_context(locked(path.with_name(path.name + ".lock")))
        except OSError:
            pass                        # no lock to be had: build it here all the same
        arrays = read_arrays(path)      # built by another process while this one waited
        if arrays is not None:
            return arrays, True
        arrays = {name: np.asarray(value) for name, value in build().items()}
        try:
            write_arrays(path, arrays)
        except OSError:
            pass
    return arrays, False
