"""Scene files: a TOML file read (with ``section.key=value`` overrides) into a Scene, and a
Scene written back as TOML. A law file, a body's mesh file and a measured base motion are
named relative to the scene file that names them, or to the current directory on the
command line."""

import tomllib
from pathlib import Path

import tomli_w

from ..friction_law.contract import is_law_file
from .build import from_dict
from .errors import SceneError
from .keys import assign, parse_assignment
from .schema import Scene, to_dict


def _law_path(value, base: Path):
    """A law file named relative to ``base`` as an absolute path; other values as they are."""
    if is_law_file(value):
        path = Path(value).expanduser()
        return str(path if path.is_absolute() else (base / path).resolve())
    return value


def _mesh_path(value, base: Path):
    """body.mesh (or vibration.motion) named relative to ``base`` as an absolute path."""
    if isinstance(value, str):
        path = Path(value).expanduser()
        return str(path if path.is_absolute() else (base / path).resolve())
    return value


def _read_scene_text(path: Path) -> str:
    try:
        return path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise SceneError(str(path), "no such scene file") from None
    except IsADirectoryError:
        raise SceneError(str(path), "is a directory, not a scene file") from None
    except UnicodeDecodeError:
        raise SceneError(str(path), "is not a text file (not UTF-8): a scene is TOML") from None
    except OSError as err:
        raise SceneError(str(path), f"cannot be read: {err.strerror}") from None


def load(path, overrides=()) -> Scene:
    """Read a scene file and apply ``section.key=value`` overrides."""
    path = Path(path)
    text = _read_scene_text(path)
    if not text.strip():
        raise SceneError(str(path), "is empty: a scene holds the keys that differ from the "
                                    "defaults (a comment line alone runs the defaults)")
    try:
        raw = tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise SceneError(str(path), f"not valid TOML: {err}") from None
    for section, values in raw.items():
        if not isinstance(values, dict):
            raise SceneError(section, f"expected a table [{section}] of keys, got {values!r}")
    if "law" in raw.get("contact", {}):  # a law file is named relative to the scene file
        raw["contact"]["law"] = _law_path(raw["contact"]["law"], path.resolve().parent)
    if "mesh" in raw.get("body", {}):   # and so is the body's mesh file
        raw["body"]["mesh"] = _mesh_path(raw["body"]["mesh"], path.resolve().parent)
    if "motion" in raw.get("vibration", {}):   # and a measured base motion
        raw["vibration"]["motion"] = _mesh_path(raw["vibration"]["motion"], path.resolve().parent)
    for text in overrides:
        key, value = parse_assignment(text)
        # ... and on the command line, relative to the current directory
        if key == "contact.law":
            value = _law_path(value, Path.cwd())
        elif key in ("body.mesh", "vibration.motion"):
            value = _mesh_path(value, Path.cwd())
        assign(raw, key, value)
    return from_dict(raw, path.stem)


def to_toml(scene: Scene, files: dict | None = None) -> str:
    """The scene as TOML, every key (to_dict). ``files`` ({"section.key": name}) writes
    those keys, which name files the scene reads, as ``name`` instead: the copies a
    results directory holds beside its scene.toml (output.write_scene_and_inputs), named
    relative to it, as load() reads them."""
    raw = to_dict(scene)
    for key, name in (files or {}).items():
        section, _, field = key.partition(".")
        raw[section][field] = name
    return tomli_w.dumps(raw)
