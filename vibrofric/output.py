"""Results directories and files: written whole or not at all.

Everything a command writes goes first into a hidden partial directory or file
beside the target (named ``.<target>.part-*``), which is renamed into place
only once complete; a run that fails leaves nothing behind, and a process
killed mid-write leaves only partials, which remove_partials() clears.
"""

import contextlib
import csv
import datetime
import json
import os
import shutil
import uuid
from pathlib import Path

from . import scene as scene_module


def default_dir(scene_name: str) -> Path:
    stamp = datetime.datetime.now().strftime("%Y%m%d-%H%M%S")
    return Path("results") / f"{scene_name}-{stamp}"


PARTIAL = ".part-"  # in the name of everything not yet renamed into place


def _partial(target: Path, kind: str = "", suffix: str = "") -> Path:
    """A fresh partial name beside ``target``. Created by the caller with mkdir or
    open, which respect the umask (tempfile's 0700 / 0600 would hide results
    from the rest of a cluster group)."""
    return target.with_name(f".{target.name}{PARTIAL}{kind}{os.getpid()}-{uuid.uuid4().hex[:8]}{suffix}")


def remove_partials(directory: Path) -> None:
    """Clear what killed writers left in ``directory``: its ``.<name>.part-*`` entries only."""
    for entry in Path(directory).iterdir():
        if entry.name.startswith(".") and PARTIAL in entry.name:
            if entry.is_dir():
                shutil.rmtree(entry, ignore_errors=True)
            else:
                entry.unlink(missing_ok=True)


@contextlib.contextmanager
def staged(target: Path):
    """Yield a staging directory that becomes ``target`` on success, and vanishes on failure."""
    target = Path(target)
    target.parent.mkdir(parents=True, exist_ok=True)
    stage = _partial(target)
    try:
        stage.mkdir()
        yield stage
    except BaseException:
        shutil.rmtree(stage, ignore_errors=True)
        raise
    if target.exists():
        remove(target)
    stage.rename(target)


def remove(target: Path) -> None:
    """Delete a results directory at once: renamed to a partial first, so a kill
    mid-way leaves a partial (remove_partials) rather than half a directory."""
    doomed = _partial(Path(target), "old-")
    Path(target).rename(doomed)
    shutil.rmtree(doomed, ignore_errors=True)


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


def write_scene(directory: Path, scene) -> None:
    """``scene.toml``: the scene as run, every key; replaced whole if already there."""
    with staged_file(directory / "scene.toml") as partial:
        partial.write_text(scene_module.to_toml(scene))


def write_summary(directory: Path, summary: dict) -> None:
    (directory / "summary.json").write_text(json.dumps(summary, indent=2) + "\n")


def write_timeseries(directory: Path, series, name: str = "timeseries.csv") -> None:
    """``t, F_d, F_x, F_y, x, y, x_b, y_b`` (and any extra columns), full precision."""
    with open(directory / name, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(series.names)
        writer.writerows(series.table().tolist())


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
