"""Grids of scene values: what a sweep runs, and a stable name for each point.

A grid is a list of (key, values) pairs from ``--grid KEY=VALUES``; every
combination is one point, ``{key: value}``, first key slowest.
"""

import itertools
import re

import numpy as np

from .scene import SceneError, check_key, coerce, parse_value


def parse_grid(text: str):
    """``KEY=VALUES`` -> (key, [values]); VALUES is ``a,b,c`` or ``start:stop:count`` (inclusive)."""
    key, sep, values = text.partition("=")
    if not sep or not values:
        raise SceneError(text, "a grid is KEY=VALUES, e.g. vibration.k_v=2,3,4 or vibration.theta_deg=0:360:25")
    key = key.strip()
    parts = values.split(":")
    if len(parts) == 3:
        try:
            start, stop, count = float(parts[0]), float(parts[1]), int(parts[2])
        except ValueError:
            raise SceneError(key, f"grid range {values!r} is not start:stop:count") from None
        if count < 1:
            raise SceneError(key, f"grid range {values!r} needs a count >= 1")
        return key, [float(v) for v in np.linspace(start, stop, count)]
    return key, [parse_value(v.strip()) for v in values.split(",")]


def canonical_grid(grid):
    """The grid with each value as the scene holds it (scene.coerce: ``2`` and
    ``2.0`` of a float key are one value, and name one point directory); a
    key given in two ``--grid`` options, or a value given twice, is refused.

    A value the scene cannot take is left as given: that point fails alone.
    """
    seen = set()
    canonical = []
    for key, values in grid:
        if key in seen:
            raise SceneError(key, "given in two --grid options; give all its values in one")
        seen.add(key)
        check_key(key)
        coerced = []
        for value in values:
            try:
                value = coerce(key, value)
            except SceneError:
                pass
            if value in coerced:
                raise SceneError(key, f"the grid gives the value {value!r} twice")
            coerced.append(value)
        canonical.append((key, coerced))
    return canonical


def grid_points(grid):
    """Every combination of the grid's values, as ``{key: value}`` dicts, first key slowest."""
    keys = [key for key, _ in grid]
    return [dict(zip(keys, combo)) for combo in itertools.product(*(values for _, values in grid))]


# Characters kept in a point's directory name; anything else (a "/" in a string
# value, spaces) becomes "_".
_UNSAFE = re.compile(r"[^A-Za-z0-9._+=,-]")


def point_name(values: dict) -> str:
    """A point's directory name, the same on every run of the same grid.

    ``{"vibration.k_v": 2, "vibration.theta_deg": 45.0}`` ->
    ``vibration.k_v=2,vibration.theta_deg=45.0``: the values as Python prints
    them (a float's shortest round-trip form, so two different values never
    share a name through rounding).
    """
    return _UNSAFE.sub("_", ",".join(f"{key}={value}" for key, value in values.items()))


def unique_names(points) -> list:
    """The points' directory names; a grid naming the same point twice is refused."""
    names = [point_name(values) for values in points]
    seen = set()
    for name in names:
        if name in seen:
            raise SceneError("--grid", f"the grid holds the point {name} twice")
        seen.add(name)
    return names
