"""The FE model against Mindlin-Deresiewicz: the held hemisphere of benchmarks/
cattaneo_mindlin.py (E = 5 GPa, R = 10 mm, P = 100 N, mu = 0.5) with Q cycled between
-Q* and +Q* by the base, the energy dissipated per cycle against Johnson's eq 7.59
(vibrofric/analytic/contact_mechanics.py, derived in its docstring and in
docs/validation.md), as the pole's mesh refines.

tests/pulled_ball.py (cycle_scene, cycle_dissipation) sets the run up: the ball held at
rest, the base moving as u0 sin(2 pi f t), f = 500 Hz, 2.25 cycles; Q* and the loop's
area W over the last cycle; the closed form at the measured Q*.

    PYTHONPATH=. python benchmarks/mindlin_deresiewicz.py [--sizes 1.5e-4 1e-4] [--q 0.3 0.6 0.9]
        [--k_t 1e9] [--frequency 500] [--cycles 2.25] [--ring 2.5e-5] [--annulus]
        [--before 0.25] [--spring 1e8] [--implicit 1e-5]

(--k_t: the Dahl law's tangential stiffness for the whole patch, N/m, default
pulled_ball.K_T, the column "k_t".) The column "Dahl's own" is what the law's
pre-sliding adds in Mindlin's stick circle at the measured Q*, estimated on the closed
forms (tests/pulled_ball.py presliding_loop), against eq 7.59. --frequency and --cycles
change the base's cycle (pulled_ball.CYCLE_FREQUENCY, CYCLES: the loop is read over the
last cycle). --ring refines each ball further along the patch's edge r = a, to that
element size within 0.12 a of it (pulled_ball.ball: Mindlin's slipping annulus at
Q* = 0.3 mu P is 0.112 a wide), the step taken on that size; the column "pole mesh"
then names both. --annulus widens the ring's band inwards to the whole of Mindlin's
slipping annulus at each run's q, from the stick radius c = a (1 - q)^(1/3) to a, with
the same margin of 0.12 a on either side (pulled_ball.ball's annulus_q: a mesh per q).
--before adds the column "W earlier vs last": the loop over the cycle that
ends that many cycles before the run's end, against the last (a steady loop keeps its
area). --spring holds the ball's top through a drive spring of that stiffness (N/m,
drive.mode = "spring") instead of prescribing it, so that the explicit integrator keeps
its energy balance (fem.energy), and adds the columns "W base", "D fric" and "D damp":
over the loop's cycle, the base's work on the ball and what the friction (its slip and
Dahl's pre-sliding) and the damping dissipated, uJ. --implicit runs the implicit integrator
(fem.integrator = "implicit", generalized-alpha with the contact iterated in each step:
docs/fe-model.md) at that step, s, instead of the explicit one; the column "pole mesh"
then says so.

Prints a Markdown table (docs/validation.md, "Curved contacts").
"""

import argparse
import itertools
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))

import pulled_ball as pb  # noqa: E402

from vibrofric.analytic import contact_mechanics as cm  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=float, nargs="+", default=[1.5e-4, 1e-4])
    parser.add_argument("--q", type=float, nargs="+", default=[0.3, 0.6, 0.9])
    parser.add_argument("--k_t", type=float, nargs="+", default=[pb.K_T])
    parser.add_argument("--frequency", type=float, default=pb.CYCLE_FREQUENCY)
    parser.add_argument("--cycles", type=float, default=pb.CYCLES)
    parser.add_argument("--ring", type=float, default=None)
    parser.add_argument("--annulus", action="store_true")
    parser.add_argument("--before", type=float, default=None)
    parser.add_argument("--spring", type=float, default=None)
    parser.add_argument("--implicit", type=float, default=None)
    args = parser.parse_args()
    a = pb.hertz_radius()
    earlier = args.before is not None
    spring = ({} if args.spring is None else
              {"drive.mode": "spring", "drive.k_d": args.spring, "fem.energy": True})
    balance = ("W base", "D fric", "D damp") if spring else ()
    integrator = {"fem.integrator": "implicit"} if args.implicit else {}
    print("| pole mesh | nodes | k_t (N/m) | Q* / mu P | W FE (uJ) | W eq 7.59 (uJ) | error | "
          "Dahl's own | " + ("W earlier vs last | " if earlier else "")
          + "".join(f"{name} | " for name in balance) + "s |")
    print("|---|---|---|---|---|---|---|---|" + ("---|" if earlier else "")
          + "---|" * len(balance) + "---|")
    with tempfile.TemporaryDirectory() as directory:
        for size, q in itertools.product(args.sizes, args.q):
            body = pb.ball(directory, size, args.ring, q if args.annulus else None)
            mesh = f"{size * 1e6:.0f} um" + (f", {args.ring * 1e6:.0f} um at " if args.ring
                                             else "")
            if args.ring and args.annulus:
                c_over_a = cm.stick_radius(q * pb.MU * pb.LOAD, pb.MU, pb.LOAD, 1.0)
                mesh += f"{c_over_a:.2f} a < r < a"
            elif args.ring:
                mesh += "r = a"
            step = args.implicit or pb.stable_step(size, args.ring)
            if args.implicit:
                mesh += f", implicit at {args.implicit:g} s"
            for k_t in args.k_t:
                start = time.perf_counter()
                scene = pb.cycle_scene(q, step, args.frequency, args.cycles,
                                       **{"contact.k_t": k_t, **spring, **integrator})
                result = pb.run(body, scene)
                Q, W = pb.cycle_dissipation(result, args.frequency)
                closed = cm.mindlin_deresiewicz_dissipation(Q, pb.MU, pb.LOAD, a, pb.E, pb.NU)
                cells = ""
                if earlier:
                    _, W_earlier = pb.cycle_dissipation(result, args.frequency, args.before)
                    cells = f"{W_earlier / W - 1:+.1%} | "
                if spring:
                    cells += "".join(f"{work * 1e6:.3f} | " for work in
                                      cycle_balance(result, args.frequency))
                print(f"| {mesh} | {result.info['nodes']} | {k_t:.0e} | "
                      f"{Q / (pb.MU * pb.LOAD):.3f} | "
                      f"{W * 1e6:.2f} | {closed * 1e6:.2f} | {W / closed - 1:+.1%} | "
                      f"{pb.presliding_loop(Q, k_t) / closed:.1%} | {cells}"
                      f"{time.perf_counter() - start:.0f} |", flush=True)


def cycle_balance(result, frequency):
    """(W_base, D_fric, D_damp) over the run's last cycle, J: the energy balance's columns
    (fem.energy, recording.ENERGY) between the rows that bound it."""
    s = result.series
    rows = np.flatnonzero(s.t >= s.t[-1] - 1.0 / frequency - 0.5 * (s.t[1] - s.t[0]))
    return tuple(float(s.extra[name][rows[-1]] - s.extra[name][rows[0]])
                 for name in ("W_base", "D_fric", "D_damp"))


if __name__ == "__main__":
    with tempfile.TemporaryDirectory() as cache:   # the balls' models kept apart from the
        os.environ["VIBROFRIC_CACHE"] = cache       # user's cache
        main()
