"""The FE model against Mindlin-Deresiewicz: the held hemisphere of benchmarks/
cattaneo_mindlin.py (E = 5 GPa, R = 10 mm, P = 100 N, mu = 0.5) with Q cycled between
-Q* and +Q* by the base, the energy dissipated per cycle against Johnson's eq 7.59
(vibrofric/analytic/contact_mechanics.py, derived in its docstring and in
docs/validation.md), as the pole's mesh refines.

tests/pulled_ball.py (cycle_scene, cycle_dissipation) sets the run up: the ball held at
rest, the base moving as u0 sin(2 pi 200 Hz t), 2.25 cycles; Q* and the loop's area W
over the second cycle; the closed form at the measured Q*.

    PYTHONPATH=. python benchmarks/mindlin_deresiewicz.py [--sizes 1.5e-4 1e-4] [--q 0.3 0.6 0.9]

Prints a Markdown table (docs/validation.md, "Curved contacts").
"""

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))

import pulled_ball as pb  # noqa: E402

from vibrofric.analytic import contact_mechanics as cm  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=float, nargs="+", default=[1.5e-4, 1e-4])
    parser.add_argument("--q", type=float, nargs="+", default=[0.3, 0.6, 0.9])
    args = parser.parse_args()
    a = pb.hertz_radius()
    print("| pole mesh | nodes | Q* / mu P | W FE (uJ) | W eq 7.59 (uJ) | error | s |")
    print("|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as directory:
        for size in args.sizes:
            body = pb.ball(directory, size)
            for q in args.q:
                start = time.perf_counter()
                result = pb.run(body, pb.cycle_scene(q, pb.stable_step(size)))
                Q, W = pb.cycle_dissipation(result)
                closed = cm.mindlin_deresiewicz_dissipation(Q, pb.MU, pb.LOAD, a, pb.E, pb.NU)
                print(f"| {size * 1e6:.0f} um | {result.info['nodes']} | "
                      f"{Q / (pb.MU * pb.LOAD):.3f} | "
                      f"{W * 1e6:.2f} | {closed * 1e6:.2f} | {W / closed - 1:+.1%} | "
                      f"{time.perf_counter() - start:.0f} |", flush=True)


if __name__ == "__main__":
    with tempfile.TemporaryDirectory() as cache:   # the balls' models kept apart from the
        os.environ["VIBROFRIC_CACHE"] = cache       # user's cache
        main()
