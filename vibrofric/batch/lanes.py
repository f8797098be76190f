"""Continuation lanes: which point each grid point's steady cycle starts from.

With time.method periodic or auto, a point's orbit is solved from a neighbour's
orbit rather than from steady sliding (analytic/continuation.py; docs/periodic.md,
Sweeps): Newton then starts near the answer. The grid is cut into lanes, runs of
consecutive points along its last key, and every point of a lane starts from the
orbit of the point before it in that lane; a lane's first point, from steady sliding.

The lanes are a function of the grid alone, never of the number of workers or MPI
ranks, nor of which point happens to end first: every point is solved from the
same start however the sweep is run (1, 2 or N workers, mpirun, a resumed sweep,
vibrofric.sweep in memory), so its results are the same bit for bit. A lane

- holds points that differ only in the last key's value (one row of the grid);
- continues only between float values of that key (a parameter of the model):
  across another value (a law, an integrator, a mesh, a method) the orbit's state
  has another size or meaning, so every such point is a lane of its own;
- holds at most LANE_POINTS points: a longer row is cut into near-equal lanes, so
  that a grid of one key is still worked on every core (a lane's points run one
  after the other).

The price of the cold starts, against lanes of 8 or whole rows, is measured in
docs/performance.md (Design choices measured).
"""

import math

from ..analytic.continuation import chunks

LANE_POINTS = 4   # a 6-point grid is two lanes: two cores at work


def lanes(points: list) -> list:
    """The grid's points (``{key: value}`` dicts in grid order, first key slowest) cut
    into lanes: lists of their indices, each in grid order; every index in one lane."""
    found = []
    run = []

    def close():
        if run:
            found.extend([run[r.start:r.stop] for r in chunks(len(run), math.ceil(len(run) / LANE_POINTS))])
            run.clear()

    for i, values in enumerate(points):
        *row, last = values.items()
        if run and (row != list(points[run[-1]].items())[:-1] or not _continues(last[1])):
            close()
        if not _continues(last[1]):
            found.append([i])
            continue
        run.append(i)
    close()
    return found


def _continues(value) -> bool:
    """A value along which an orbit is continued: a float (not a bool, int or string)."""
    return isinstance(value, float)
