"""Setting one scene key: ``section.key=value`` parsed (``--set``), the value checked
against the key's type, and set in a scene's nested ``{section: {key: value}}``."""

import dataclasses
import math
import tomllib
import typing

from .errors import SceneError
from .schema import CONTACT_KEYS, SECTIONS, Contact, law_key, split_key


def assign(raw: dict, key: str, value) -> None:
    """Set ``section.key`` (or ``contact.<law>.<key>``) in the nested ``raw``. A law
    parameter that the chosen law's own table holds is set there: ``contact.update``
    changes the update of the law that runs."""
    section, name = split_key(key)
    table = raw.setdefault(section, {})
    law, _, name = name.rpartition(".")
    if section == "contact" and not law and name not in CONTACT_KEYS:
        chosen = law_key(table.get("law", Contact.law))
        if name in (table.get(chosen) if isinstance(table.get(chosen), dict) else ()):
            law = chosen
    if law:
        table = table.setdefault(law, {})
        if not isinstance(table, dict):
            raise SceneError(key, f"contact.{law} is a value, not a law's table")
    table[name] = value


def check_type(key: str, value, annotation):
    """Coerce a TOML value to the field's type, or refuse it."""
    optional = typing.get_origin(annotation) is typing.Union
    if optional and type(None) not in typing.get_args(annotation):   # a choice of types
        if float in typing.get_args(annotation) and type(value) is int:
            value = float(value)      # 2 and 2.0 are one value
        if isinstance(value, float) and not math.isfinite(value):
            raise SceneError(key, f"expected a finite number, got {value!r}")
        if not isinstance(value, typing.get_args(annotation)):
            names = " or ".join(t.__name__ for t in typing.get_args(annotation))
            raise SceneError(key, f"expected {names}, got {value!r}")
        return value
    base = typing.get_args(annotation)[0] if optional else annotation
    if base is float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise SceneError(key, f"expected a number, got {value!r}")
        value = float(value)
        if not math.isfinite(value):
            raise SceneError(key, f"expected a finite number, got {value!r}")
        return value
    if base is int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise SceneError(key, f"expected an integer, got {value!r}")
        return value
    if base is bool:
        if not isinstance(value, bool):
            raise SceneError(key, f"expected true or false, got {value!r}")
        return value
    if base is str:
        if not isinstance(value, str):
            raise SceneError(key, f"expected a string, got {value!r}")
        return value
    if typing.get_origin(base) is tuple:     # a list of tables, each a dataclass's keys
        return _tables(key, value, typing.get_args(base)[0])
    if base is tuple:
        if not isinstance(value, (list, tuple)) or len(value) != 3:
            raise SceneError(key, f"expected a list of 3 numbers, got {value!r}")
        return tuple(check_type(key, v, float) for v in value)
    raise TypeError(f"no type check for {annotation}")


def _tables(key: str, value, cls) -> tuple:
    """A list of tables (vibration.harmonics) as a tuple of ``cls``, each key type-checked."""
    if not isinstance(value, (list, tuple)):
        raise SceneError(key, f"expected a list of tables, got {value!r}")
    hints = typing.get_type_hints(cls)
    items = []
    for n, table in enumerate(value):
        if isinstance(table, cls):
            table = dataclasses.asdict(table)
        if not isinstance(table, dict):
            raise SceneError(key, f"entry {n + 1}: expected a table of keys, got {table!r}")
        unknown = sorted(set(table) - set(hints))
        if unknown:
            raise SceneError(key, f"entry {n + 1}: unknown key {unknown[0]!r}; known: "
                                  f"{', '.join(hints)}")
        missing = [f.name for f in dataclasses.fields(cls)
                   if f.default is dataclasses.MISSING and f.name not in table]
        if missing:
            raise SceneError(key, f"entry {n + 1}: needs {', '.join(missing)}")
        items.append(cls(**{name: check_type(f"{key}[{n + 1}].{name}", v, hints[name])
                            for name, v in table.items()}))
    return tuple(items)


def parse_value(text: str):
    """A ``--set`` value: TOML syntax (``2``, ``1e-6``, ``[1, 2, 3]``, ``"dahl"``), else a bare string.

    >>> parse_value("1e-6"), parse_value("[0.03, 0.04, 0.053]"), parse_value("lugre")
    (1e-06, [0.03, 0.04, 0.053], 'lugre')
    """
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        return text


def parse_assignment(text: str):
    """``section.key=value`` -> (key, value).

    >>> parse_assignment("vibration.k_v = 20")
    ('vibration.k_v', 20)
    >>> parse_assignment("vibration.kv=20")
    Traceback (most recent call last):
    ...
    vibrofric.scene.SceneError: vibration.kv: unknown key in [vibration]; known: f, k_v, theta_deg, t_on, normal_amplitude, normal_phase_deg, harmonics, motion, motion_periodic
    """
    key, sep, value = text.partition("=")
    if not sep:
        raise SceneError(text, "expected section.key=value")
    if "\n" in text or "\r" in text:
        raise SceneError(key.strip(), f"{text!r} holds a line break: give one section.key=value "
                                      "per --set")
    key = key.strip()
    split_key(key)
    return key, parse_value(value.strip())


def check_key(key: str) -> None:
    """Refuse (SceneError) a ``section.key`` that names no scene key."""
    split_key(key)


def coerce(key: str, value):
    """``value`` as the scene would hold it for ``key`` (an integer for a
    float key becomes a float: 2 and 2.0 are one value); raises SceneError."""
    section, name = split_key(key)
    hints = typing.get_type_hints(SECTIONS[section])
    if name not in hints:  # a law parameter: a number as a float, else as given
        is_number = isinstance(value, (int, float)) and not isinstance(value, bool)
        return check_type(key, value, float) if is_number else value
    return check_type(key, value, hints[name])
