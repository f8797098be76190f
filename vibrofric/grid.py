"""Grids of scene values: what a sweep runs, and a stable name for each point.

A grid is a list of (key, values) pairs from ``--grid KEY=VALUES``; every
combination is one point, ``{key: value}``, first key slowest. The values of
``start:stop:count`` are a Range, computed one at a time when asked for, so
that a grid can be counted (grid_size) and refused before it is expanded: a
count of 1e9 would otherwise be 24 GB of Python floats before anything checks it.
"""

import itertools
import math
import re
from dataclasses import dataclass

from .scene import SceneError, check_key, coerce, parse_value


@dataclass(frozen=True)
class Range:
    """``count`` values from ``start`` to ``stop`` inclusive, evenly spaced: those of
    ``numpy.linspace(start, stop, count)`` bit for bit (the same float operations:
    ``i * step + start``, the last value ``stop`` itself), one at a time.
    ``key``: the scene key whose type each value is given (scene.coerce; a value
    it cannot take left as given), for a key that does not hold floats."""

    start: float
    stop: float
    count: int
    key: str | None = None

    def __len__(self) -> int:   # (Python's len() stops at 2**63: grid.grid_size reads count)
        return self.count

    def __getitem__(self, i: int):
        value = self._value(i)
        if self.key is None:
            return value
        try:
            return coerce(self.key, value)
        except SceneError:
            return value

    def _value(self, i: int) -> float:
        if not -self.count <= i < self.count:
            raise IndexError(i)
        i %= self.count
        if self.count == 1:
            return self.start
        if i == self.count - 1:
            return self.stop
        step = (self.stop - self.start) / (self.count - 1)
        if step == 0:   # numpy's order of operations where the step underflows
            return float(i) / (self.count - 1) * (self.stop - self.start) + self.start
        return float(i) * step + self.start

    def __iter__(self):
        return (self[i] for i in range(self.count))

    def __str__(self) -> str:
        return f"{self.start:g}:{self.stop:g}:{self.count}"


def _count(text: str) -> int:
    """A range's count: a whole number, also as ``1e6``."""
    value = float(text)
    if not value.is_integer():
        raise ValueError(text)
    return int(value)


def parse_grid(text: str):
    """``KEY=VALUES`` -> (key, values); VALUES is ``a,b,c`` (a list) or
    ``start:stop:count`` (inclusive; a Range)."""
    key, sep, values = text.partition("=")
    if not sep or not values:
        raise SceneError(text, "a grid is KEY=VALUES, e.g. vibration.k_v=2,3,4 or vibration.theta_deg=0:360:25")
    key = key.strip()
    parts = values.split(":")
    if len(parts) == 3:
        try:
            start, stop, count = float(parts[0]), float(parts[1]), _count(parts[2])
        except (ValueError, OverflowError):
            raise SceneError(key, f"grid range {values!r} is not start:stop:count") from None
        if count < 1:
            raise SceneError(key, f"grid range {values!r} needs a count >= 1")
        if not (math.isfinite(start) and math.isfinite(stop)):
            raise SceneError(key, f"grid range {values!r} needs finite ends")
        return key, Range(start, stop, count)
    return key, [parse_value(v.strip()) for v in values.split(",")]


def canonical_grid(grid):
    """The grid with each value as the scene holds it (scene.coerce: ``2`` and
    ``2.0`` of a float key are one value, and name one point directory); a
    key given in two ``--grid`` options, or a value given twice, is refused.

    A value the scene cannot take is left as given: that point fails alone.
    A Range stays one, counted and not expanded (grid_size): for a key that does
    not hold floats, one that gives each value that key's type.
    """
    seen = set()
    canonical = []
    for key, values in grid:
        if key in seen:
            raise SceneError(key, "given in two --grid options; give all its values in one")
        seen.add(key)
        check_key(key)
        if isinstance(values, Range):
            if values.count > 1 and values.start == values.stop:
                raise SceneError(key, f"the grid gives the value {values.start!r} twice")
            floats = _holds_floats(key, values)
            canonical.append((key, values if floats else Range(values.start, values.stop, values.count, key)))
            continue
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


def _holds_floats(key: str, values: Range) -> bool:
    try:
        held = coerce(key, values.start)
    except SceneError:
        return False
    return isinstance(held, float)


def grid_size(grid) -> int:
    """Points of the grid, counted without expanding it."""
    return math.prod(values.count if isinstance(values, Range) else len(values) for _, values in grid)


def describe(grid) -> str:
    """The grid as the command line gave it, for a message: ``vibration.k_v=0:20:1000000000``."""
    return " ".join(f"--grid {key}={values if isinstance(values, Range) else ','.join(map(str, values))}"
                    for key, values in grid)


def samples(grid) -> list:
    """A few points that bound the grid's cost, without expanding it: every combination
    of each key's first and last value (of the first MAX_CORNER_KEYS keys; the others
    at their first), and each value of a list (as typed: its largest may lie inside)
    with the other keys at their first. A Range's values are monotonic: its ends bound them."""
    keys = [key for key, _ in grid]
    picks = [(values[0], values[-1]) if k < MAX_CORNER_KEYS else (values[0],)
             for k, (_, values) in enumerate(grid)]
    found = [dict(zip(keys, combo)) for combo in itertools.product(*picks)]
    firsts = {key: values[0] for key, values in grid}
    for key, values in grid:
        if not isinstance(values, Range):
            found.extend({**firsts, key: value} for value in values)
    unique = {repr(point): point for point in found}
    return list(unique.values())


MAX_CORNER_KEYS = 6   # 64 corner scenes at most


def grid_points(grid):
    """Every combination of the grid's values, as ``{key: value}`` dicts, first key
    slowest, one at a time (an iterator: count it with grid_size first)."""
    keys = [key for key, _ in grid]
    return (dict(zip(keys, combo)) for combo in itertools.product(*(values for _, values in grid)))


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
