"""A sweep's finished points as their directories hold them, and results.csv.

results.csv is never kept up to date by hand: it is regenerated from the point
directories (points.read_point) and replaced whole (output.staged_file) as
points finish, so at any moment it lists, in grid order, points whose
directories are there, done or failed, and never a half-written row. The
sweep's end, or its interruption, rewrites it from every directory.

Rewriting it after every point would cost a sweep of many quick points time
quadratic in their number (1000 analytic points: 30 s of rewriting), so while
points run it is rewritten no sooner than PAUSE times its last rewrite took
(milliseconds) after that rewrite: it trails the directories by the points of
those milliseconds, until the next point finishes.
"""

import time
from pathlib import Path

from .. import output
from .points import DAMAGED, ERROR, read_point

PAUSE = 10       # rewrites of results.csv take at most 1 / (1 + PAUSE) of a sweep's time


class Ledger:
    """Records of the finished points of one sweep, by point name."""

    def __init__(self, points: list, mode: str, directory: Path):
        self.points = points
        self.mode = mode
        self.directory = directory
        self.records = {}
        self.damaged = set()  # names of points whose directories did not check out
        self._next_write = 0.0  # time.monotonic() before which a throttled rewrite is skipped

    def read(self, points=None) -> None:
        """Read these points' directories again (default: every point)."""
        for point in self.points if points is None else points:
            record = read_point(point, self.mode)
            if record is None or record is DAMAGED:
                self.records.pop(point.name, None)
                if record is DAMAGED:
                    self.damaged.add(point.name)
            else:
                self.records[point.name] = record

    def in_grid_order(self) -> list:
        return [self.records[p.name] for p in self.points if p.name in self.records]

    def is_done(self, point) -> bool:
        record = self.records.get(point.name)
        return record is not None and ERROR not in record

    @property
    def failed(self) -> list:
        return [r for r in self.in_grid_order() if ERROR in r]

    def write_csv(self, throttled: bool = False) -> None:
        """results.csv: grid keys, result keys flattened with dots, then "error"
        (why the point failed; empty if it did not).

        throttled: skip this rewrite if the last one was too recent (see PAUSE)
        """
        start = time.monotonic()
        if throttled and start < self._next_write:
            return
        output.write_results_csv(self.directory, self.in_grid_order(), last=(ERROR,))
        self._next_write = start + (1 + PAUSE) * (time.monotonic() - start)
