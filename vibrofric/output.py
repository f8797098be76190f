"""Results directories and files: written whole or not at all, and never over a user's files.

Everything a command writes goes first into a hidden partial directory or file
beside the target (named ``.<target>.part-*``), which is renamed into place
only once complete; a run that fails leaves nothing behind, and a process
killed mid-write leaves only partials, which remove_partials() clears.

Every results directory holds the marker file MARKER, naming the command
that wrote it. ``check_target`` decides, before any work, what a command may
do with its ``--out``:

    missing, or an empty directory       write it
    a results directory of this tool     replace it only with --force; a sweep
                                         resumes its own (same command, no --force)
    anything else (a file, a directory   refused: OutputError, nothing touched
    of the user's, ``.``, an unwritable
    place)
"""

import contextlib
import csv
import ctypes
import datetime
import errno
import fcntl
import gc
import json
import os
import re
import shutil
import signal
import sys
import traceback
from pathlib import Path

from .parallel import stop_if_interrupted

MARKER = ".vibrofric"  # in every results directory: {"command": ...}


class OutputError(ValueError):
    """An ``--out`` the command may not write; the message says why."""


def default_dir(scene_name: str) -> Path:
    """``results/<scene>-<time>``, claimed at once (an empty directory made
    with mkdir, which only one process can do): two runs started in the same
    second get ``...-<time>`` and ``...-<time>-2``. staged() replaces the empty
    directory with the results, or removes it if the run fails."""
    stamp = datetime.datetime.now().strftime("%Y%m%d-%H%M%S")
    base = Path("results") / f"{scene_name}-{stamp}"
    base.parent.mkdir(parents=True, exist_ok=True)
    for n in range(1, 10_000):
        candidate = base if n == 1 else base.with_name(f"{base.name}-{n}")
        try:
            candidate.mkdir()
            return candidate
        except FileExistsError:
            continue
    raise OutputError(f"{base}: no free results directory name")


def read_marker(directory: Path) -> dict | None:
    """The marker of a results directory of this tool, or None."""
    try:
        marker = json.loads((Path(directory) / MARKER).read_text())
    except (OSError, ValueError):
        return None
    return marker if isinstance(marker, dict) and "command" in marker else None


def write_marker(directory: Path, command: str) -> None:
    (Path(directory) / MARKER).write_text(json.dumps({"command": command}) + "\n")


def existing_ancestor(path: Path) -> Path:
    """``path`` itself if it exists, else its nearest existing parent."""
    path = Path(path).absolute()
    while not path.exists():
        path = path.parent
    return path


# The kernel's table of this process's mounts (Linux): one line a mount, its mount
# point the fifth field, with space, tab, newline and backslash written as \ooo.
MOUNTINFO = Path("/proc/self/mountinfo")


def mount_points() -> set:
    """Every mount point MOUNTINFO lists (empty where there is none)."""
    try:
        lines = MOUNTINFO.read_text(errors="surrogateescape").splitlines()
    except OSError:
        return set()
    points = set()
    for line in lines:
        fields = line.split(" ")
        if len(fields) > 4:
            points.add(re.sub(r"\\([0-7]{3})", lambda code: chr(int(code[1], 8)), fields[4]))
    return points


def is_mount_point(path: Path) -> bool:
    """Whether ``path`` (resolved) is a mount point. os.path.ismount compares devices
    and inodes with the parent's, which misses a bind mount of a folder of the same
    file system (a container's usual output folder): the kernel's own table says."""
    return os.path.ismount(path) or str(path) in mount_points()


def check_target(target: Path, command: str, force: bool = False) -> str:
    """What ``command`` may do with ``target``: "new", "replace" or "resume" (a
    sweep's own directory); raise OutputError if it may do nothing (see the module)."""
    target = Path(target)
    here = Path.cwd().resolve()
    resolved = target.resolve()
    if target.name in ("", ".", "..") or resolved == here or resolved in here.parents:
        raise OutputError(f"--out {target}: the current directory or one above it; "
                          "name a new directory for the results")
    if resolved.is_dir() and is_mount_point(resolved):
        raise OutputError(f"--out {target}: is a mount point, which results (moved into place "
                          "whole by a rename) cannot replace; nothing was touched: name a new "
                          f"directory inside it, e.g. --out {target / 'results'}")
    target = real_target(target)
    if target.exists() and not target.is_dir():
        raise OutputError(f"--out {target}: is a file, not a results directory; nothing was touched")
    if target.is_dir():
        marker = read_marker(target)
        if marker is None and any(target.iterdir()):
            raise OutputError(f"--out {target}: holds files vibrofric did not write (no {MARKER} "
                              "marker); nothing was touched: name a new directory")
        if marker is not None and not force:
            if command == "sweep" and marker["command"] == "sweep":
                _check_writable(target, target)
                return "resume"
            raise OutputError(f"--out {target}: holds earlier results of vibrofric "
                              f"{marker['command']}; add --force to replace them")
    _check_writable(existing_ancestor(target.parent), target)
    return "replace" if target.is_dir() and any(target.iterdir()) else "new"


def real_target(target: Path) -> Path:
    """``target`` with a symlink in its last part followed: results go into the
    folder the link names (and --force replaces that folder, never the link)."""
    target = Path(target)
    return Path(os.path.realpath(target)) if target.is_symlink() else target


class Busy(OutputError):
    """Another vibrofric process is writing the same results directory."""


def _lock_path(target: Path) -> Path:
    return target.with_name(f".{target.name}.lock")


@contextlib.contextmanager
def locked(target: Path):
    """Hold the lock of results directory ``target`` (fcntl.flock on ``.<name>.lock``
    beside it) while within; raise Busy at once if another process holds it.

    The lock file is removed on the way out; a process that opened it just
    before finds, once it holds the lock, that the name now points elsewhere
    (or nowhere) and tries again, so two holders of one name are impossible.
    The kernel releases the lock of a killed process; a stale lock file is
    harmless (it is taken over).
    """
    target = real_target(target)
    target.parent.mkdir(parents=True, exist_ok=True)
    path = _lock_path(target)
    while True:
        fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o666)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(fd)
            raise Busy(f"--out {target}: another vibrofric process is writing it now "
                       f"(it holds {path.name}); nothing was touched") from None
        try:
            same = os.stat(path).st_ino == os.fstat(fd).st_ino
        except FileNotFoundError:
            same = False
        if same:
            break
        os.close(fd)
    try:
        os.ftruncate(fd, 0)
        os.write(fd, f"{os.getpid()}\n".encode())
        yield target
    finally:
        with contextlib.suppress(OSError):
            os.unlink(path)
        os.close(fd)


def leftovers(target: Path) -> list:
    """What killed writers of ``target`` left beside it: ``.<name>.part-*`` entries
    (stages never renamed in, old results not yet deleted). Call it holding the lock."""
    target = Path(target)
    prefix = f".{target.name}{PARTIAL}"
    try:
        return sorted(p for p in target.parent.iterdir() if p.name.startswith(prefix))
    except FileNotFoundError:
        return []


def clear_leftovers(target: Path) -> list:
    """Remove leftovers(target); return their names (for the caller to report)."""
    found = leftovers(target)
    for entry in found:
        _delete(entry)
    return [entry.name for entry in found]


def _delete(path: Path) -> None:
    if path.is_dir() and not path.is_symlink():
        shutil.rmtree(path, ignore_errors=True)
    else:
        with contextlib.suppress(FileNotFoundError):
            path.unlink()


def _check_writable(directory: Path, target: Path) -> None:
    """Make and remove an empty directory in ``directory``: the one sure test
    (permissions, a read-only file system, root's rights) before any work."""
    probe = _partial(directory / "probe", "probe-")
    try:
        probe.mkdir()
        probe.rmdir()
    except OSError as err:
        raise OutputError(f"--out {target}: cannot write in {directory} ({err.strerror})") from None


PARTIAL = ".part-"  # in the name of everything not yet renamed into place


def _partial(target: Path, kind: str = "", suffix: str = "") -> Path:
    """A fresh partial name beside ``target``. Created by the caller with mkdir or
    open, which respect the umask (tempfile's 0700 / 0600 would hide results
    from the rest of a cluster group)."""
    unique = f"{os.getpid()}-{os.urandom(4).hex()}"
    return target.with_name(f".{target.name}{PARTIAL}{kind}{unique}{suffix}")


def remove_partials(directory: Path) -> None:
    """Clear what killed writers left in ``directory``: its ``.<name>.part-*`` entries only."""
    for entry in Path(directory).iterdir():
        if entry.name.startswith(".") and PARTIAL in entry.name:
            if entry.is_dir():
                shutil.rmtree(entry, ignore_errors=True)
            else:
                entry.unlink(missing_ok=True)


@contextlib.contextmanager
def staged(target: Path, command: str | None = None, claimed: bool = False):
    """Yield a staging directory that becomes ``target`` on success, and vanishes on failure.

    command  the command writing it, recorded in its MARKER (None: a part of a
             results directory, such as a sweep's point, which has no marker)

    claimed  ``target`` is an empty directory default_dir() made for this
             run: removed on failure too
    """
    target = Path(target)
    target.parent.mkdir(parents=True, exist_ok=True)
    stage = _partial(target)
    try:
        stage.mkdir()
        if command is not None:
            write_marker(stage, command)
        yield stage
        # A Ctrl-C or SIGTERM whose KeyboardInterrupt was swallowed on the way (raised
        # in a callback from compiled code: llvmlite's, DOLFINx's) still ends the run.
        stop_if_interrupted()
    except BaseException as failure:
        # The failed work's frames go first: an open writer they still hold (DOLFINx's
        # VTKFile, interrupted by Ctrl-C) writes its .pvd when destroyed, and would
        # recreate the stage after its removal.
        traceback.clear_frames(failure.__traceback__)
        gc.collect()
        shutil.rmtree(stage, ignore_errors=True)
        if claimed:
            with contextlib.suppress(OSError):
                target.rmdir()  # only if still empty
        raise
    commit(stage, target)


# Results moved in: renames done by commit(), for an honest message on an interrupt.
committed = []

RENAME_EXCHANGE = 2  # linux/fs.h


def _exchange(a: Path, b: Path) -> bool:
    """Swap the names ``a`` and ``b`` in one step (renameat2 RENAME_EXCHANGE);
    False where the kernel, C library or file system cannot."""
    if not sys.platform.startswith("linux"):
        return False
    try:
        renameat2 = ctypes.CDLL(None, use_errno=True).renameat2
    except AttributeError:
        return False
    AT_FDCWD = -100
    if renameat2(AT_FDCWD, os.fsencode(a), AT_FDCWD, os.fsencode(b), RENAME_EXCHANGE) == 0:
        return True
    code = ctypes.get_errno()
    if code in (errno.EINVAL, errno.ENOSYS, errno.ENOTSUP):
        return False
    raise OSError(code, os.strerror(code), str(a))


def commit(stage: Path, target: Path) -> None:
    """Move the finished ``stage`` in as ``target``: at every instant the old
    results (if any) or the new ones are whole under the name.

    An existing ``target`` (earlier results, replaced with --force, a damaged
    sweep point, or the empty directory default_dir() claimed) is swapped with
    the stage in one step and deleted afterwards under its partial name; where
    the file system cannot swap, it is renamed aside first. Ctrl-C and SIGTERM
    wait until the new results are in place. A kill while the old ones are
    being deleted leaves them as a partial, which the next run clears.
    """
    blocked = {signal.SIGINT, signal.SIGTERM}
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, blocked)
    try:
        if os.path.lexists(target):
            if not _exchange(stage, target):
                aside = _partial(target, "old-")
                os.rename(target, aside)
                os.rename(stage, target)
                stage = aside
            committed.append(target)
            _delete(stage)  # now the old results
        else:
            # rename(2) replaces an empty directory in one step: a name default_dir()
            # claimed is never free for another run to claim while results move in.
            stage.rename(target)
            committed.append(target)
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


def remove(target: Path) -> None:
    """Delete a results directory at once: renamed to a partial first, so a kill
    mid-way leaves a partial (remove_partials) rather than half a directory."""
    doomed = _partial(Path(target), "old-")
    Path(target).rename(doomed)
    _delete(doomed)


@contextlib.contextmanager
def staged_file(target: Path):
    """Yield a path to write that then replaces ``target`` (os.replace): readers
    see the old file or the new one, never a half-written one."""
    target = Path(target)
    partial = _partial(target, suffix=target.suffix)  # writers such as savefig go by the suffix
    try:
        yield partial
        os.replace(partial, target)
    except BaseException:
        partial.unlink(missing_ok=True)
        raise


def write_scene(directory: Path, scene, files: dict | None = None) -> None:
    """``scene.toml``: the scene as run, every key; replaced whole if already there.
    ``files``: keys naming files, written as other names (scene.to_toml)."""
    from . import scene as scene_module  # here: importing the scene module imports numba,
                                         # which the command's first moments do without (cli)

    with staged_file(Path(directory) / "scene.toml") as partial:
        partial.write_text(scene_module.to_toml(scene, files))


def write_scene_and_inputs(directory: Path, scene) -> None:
    """``scene.toml`` as write_scene writes it, with the files the scene reads copied
    beside it and named there relatively (copy_inputs; scene.load reads a file named
    relative to its scene file): the directory reruns on another machine.
    (A sweep's scene.toml keeps absolute names: a sweep resumes by comparing its
    scene, and a point by its scene.toml's text, batch/points.py read_point.)
    """
    write_scene(directory, scene, copy_inputs(directory, scene))


def copy_inputs(directory: Path, scene) -> dict:
    """Copy the files ``scene`` reads into ``directory``; return the keys that name them
    with the copies' names, relative to ``directory``. The files:

        vibration.motion   the measured base motion, as base_motion<suffix>
        body.mesh          the body's mesh or geometry file under its own name, and the
                           files a .geo names beside it (meshes/user_mesh.py named_files)
                           under theirs; one named by an absolute path or out of its
                           folder (..) stays where it is, named as the .geo names it
        contact.law        a law file, under its own name (its stem names its table
                           [contact.<stem>]); only the file: a law file is one module
                           (friction_law/contract.py). A built-in law or an importable
                           module is named, not copied.

    Copied byte for byte: the rerun's mesh cache key, base motion and law fingerprint
    (its compiled loops) are the run's.
    """
    from .friction_law.contract import is_law_file

    directory = Path(directory)
    files = {}
    if scene.vibration.motion is not None:
        name = "base_motion" + Path(scene.vibration.motion).suffix
        shutil.copyfile(scene.vibration.motion, directory / name)
        files["vibration.motion"] = name
    if scene.body.mesh is not None:
        from .meshes.user_mesh import named_files

        source = Path(scene.body.mesh)
        for name, other in named_files(source):
            if Path(name).is_absolute() or ".." in Path(name).parts:
                continue
            (directory / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(other, directory / name)
        shutil.copyfile(source, directory / source.name)
        files["body.mesh"] = source.name
    if is_law_file(scene.contact.law):
        source = Path(scene.contact.law)
        shutil.copyfile(source, directory / source.name)
        files["contact.law"] = source.name
    return files


CHECKS = "checks.json"  # in a sweep's point: {file: {"bytes": n, "sha256": hex}} of the others


def _files(directory: Path) -> list:
    return sorted(p.relative_to(directory).as_posix() for p in Path(directory).rglob("*")
                  if p.is_file() and p.name != CHECKS)


def _digest(path: Path) -> dict:
    import hashlib

    with open(path, "rb") as f:
        return {"bytes": path.stat().st_size, "sha256": hashlib.file_digest(f, "sha256").hexdigest()}


def write_checks(directory: Path) -> None:
    """Record the size and SHA-256 of every file in ``directory`` (written last)."""
    directory = Path(directory)
    checks = {name: _digest(directory / name) for name in _files(directory)}
    (directory / CHECKS).write_text(json.dumps(checks, indent=1) + "\n")


def checks_out(directory: Path) -> bool:
    """True if ``directory`` holds exactly the files write_checks() recorded, unchanged."""
    directory = Path(directory)
    try:
        checks = json.loads((directory / CHECKS).read_text())
        return (isinstance(checks, dict) and sorted(checks) == _files(directory)
                and all(_digest(directory / name) == checks[name] for name in checks))
    except (OSError, ValueError):
        return False


def write_summary(directory: Path, summary: dict) -> None:
    (directory / "summary.json").write_text(json.dumps(summary, indent=2) + "\n")


CSV_CHUNK_ROWS = 10_000  # rows formatted at once: a long series never sits in memory as text


def write_timeseries(directory: Path, series, name: str = "timeseries.csv") -> None:
    """``t, F_d, F_x, F_y, x, y, x_b, y_b`` (and any extra columns), full precision.

    The text is the csv module's (each value its repr, rows ending in CRLF), made
    a chunk of rows at a time by one %-format instead of a Python call per row.
    """
    table = series.table()
    row = ",".join(["%r"] * table.shape[1]) + "\r\n"
    with open(directory / name, "w", newline="") as f:
        f.write(",".join(series.names) + "\r\n")
        for start in range(0, len(table), CSV_CHUNK_ROWS):
            chunk = table[start:start + CSV_CHUNK_ROWS]
            f.write((row * len(chunk)) % tuple(chunk.ravel().tolist()))


def flatten(record: dict, prefix: str = "") -> dict:
    """Nested dicts to dotted keys: ``{"fe": {"F_dv": 1}}`` -> ``{"fe.F_dv": 1}``."""
    flat = {}
    for key, value in record.items():
        if isinstance(value, dict):
            flat.update(flatten(value, f"{prefix}{key}."))
        else:
            flat[f"{prefix}{key}"] = value
    return flat


def write_results_csv(directory: Path, records: list, last=()) -> None:
    """``results.csv``: one row per grid point, nested keys flattened with dots.

    Columns in order of first appearance, those named in ``last`` at the end;
    a key a row lacks is left empty. The file is replaced whole (staged_file).
    """
    rows = [flatten(r) for r in records]
    names = [k for k in dict.fromkeys(k for row in rows for k in row) if k not in last]
    with staged_file(directory / "results.csv") as partial, open(partial, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=names + list(last))
        writer.writeheader()
        writer.writerows(rows)
