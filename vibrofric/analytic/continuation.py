"""Sweeps by continuation: each grid point's periodic orbit starts from its neighbour's.

Along a row of a grid the steady state changes little from one point to the next,
so the converged orbit state of one point (analytic/periodic.py) is a better start
for Newton than steady sliding (the Fig 12 study: docs/periodic.md). A point that
falls back to stepping (no stable orbit) hands nothing on: the next starts from
steady sliding again.
"""

from .solve import solve_with_orbit


def run_in_sequence(scene, points: list, stepper: str = "coupled") -> list[dict]:
    """Run ``scene`` with each of ``points`` (dicts of scene values) in order, each
    periodic point from the previous point's orbit; the summaries, in order."""
    summaries = []
    start = None
    for values in points:
        _, summary, start = solve_with_orbit(scene.with_values(values), stepper, start)
        summaries.append(summary)
    return summaries


def chunks(count: int, parts: int) -> list[range]:
    """``count`` indices cut into at most ``parts`` contiguous ranges of near-equal size."""
    parts = max(1, min(parts, count))
    edges = [round(k * count / parts) for k in range(parts + 1)]
    return [range(a, b) for a, b in zip(edges, edges[1:]) if b > a]
