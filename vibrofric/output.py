"""Results directories: written whole or not at all.

Everything a command writes goes first into a hidden staging directory beside
the target, which is renamed into place only once complete; a run that fails
leaves nothing behind.
"""

import contextlib
import csv
import datetime
import json
import shutil
import tempfile
from pathlib import Path

from . import scene as scene_module


def default_dir(scene_name: str) -> Path:
    stamp = datetime.datetime.now().strftime("%Y%m%d-%H%M%S")
    return Path("results") / f"{scene_name}-{stamp}"


@contextlib.contextmanager
def staged(target: Path):
    """Yield a staging directory that becomes ``target`` on success, and vanishes on failure."""
    target = Path(target)
    target.parent.mkdir(parents=True, exist_ok=True)
    stage = Path(tempfile.mkdtemp(prefix=f".{target.name}.", dir=target.parent))
    try:
        yield stage
    except BaseException:
        shutil.rmtree(stage, ignore_errors=True)
        raise
    if target.exists():
        old = Path(tempfile.mkdtemp(prefix=f".{target.name}.old.", dir=target.parent))
        target.rename(old / target.name)
        stage.rename(target)
        shutil.rmtree(old, ignore_errors=True)
    else:
        stage.rename(target)


def write_scene(directory: Path, scene) -> None:
    (directory / "scene.toml").write_text(scene_module.to_toml(scene))


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


def write_results_csv(directory: Path, records: list) -> None:
    """One row per grid point, nested keys flattened with dots."""
    rows = [flatten(r) for r in records]
    names = list(dict.fromkeys(k for row in rows for k in row))
    with open(directory / "results.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=names)
        writer.writeheader()
        writer.writerows(rows)
