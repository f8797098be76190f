"""The FE model against Cattaneo-Mindlin: a held hemisphere (E = 5 GPa, R = 10 mm) pressed by
P = 100 N and pulled tangentially, quasi-statically, as its pole's mesh refines.

tests/pulled_ball.py sets the run up and says what is compared: per mesh, three pulls to
~0.94 mu P (3 ms, explicit):

    stuck      mu = 10: the linear compliance C_stuck = dx / dQ of the top (bulk + contact)
    pulled     mu = 0.5, Dahl with k_t = 1e9 N/m (close to rigid Coulomb)
    to q       the same pull stopped where Q first reached q mu P (its time from the pull
               above): the stick radius at its last step

and the table's columns (closed forms of vibrofric/analytic/contact_mechanics.py,
Johnson, Contact Mechanics, eqs 7.40 and 7.42):

    C_stuck / C_0       the stuck compliance over Mindlin's no-slip 1 / (8 G* a) (the
                        excess is the bulk's shear and the mesh's contact compliance)
    delta q=...         x(Q) - (C_stuck - C_0) Q against delta(Q): the top's
                        displacement less the bulk's linear share
    slip part q=...     x(Q) - C_stuck Q against delta(Q) - C_0 Q, no slope of the closed
                        form used (stricter: a difference of near numbers, the mesh's
                        discrete slip front in it)
    c q=...             the stick radius against a (1 - q)^(1/3), read from the nodes'
                        states (tests/pulled_ball.py stick_radius: to half a node
                        spacing) and, "fit", from the stuck nodes' tractions on
                        Mindlin's shape (stick_radius_fit; its slope, -1 for Mindlin's
                        field, in "slope")

    PYTHONPATH=. python benchmarks/cattaneo_mindlin.py [--sizes 1.5e-4 1e-4]

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

DELTA_AT = (0.3, 0.6, 0.9)
STICK_AT = (0.5, 0.8)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=float, nargs="+", default=[1.5e-4, 1e-4])
    args = parser.parse_args()
    a = pb.hertz_radius()
    print(f"Hertz a = {a * 1e3:.4f} mm, C_0 = {pb.no_slip_compliance():.4g} m/N, mu P = "
          f"{pb.MU * pb.LOAD:g} N\n")
    print("| pole mesh | nodes | closed | C_stuck / C_0 | "
          + " | ".join(f"delta q={q}" for q in DELTA_AT) + " | "
          + " | ".join(f"slip part q={q}" for q in DELTA_AT) + " | "
          + " | ".join(f"c q={q}" for q in STICK_AT) + " | "
          + " | ".join(f"c fit q={q}" for q in STICK_AT) + " | "
          + " | ".join(f"slope q={q}" for q in STICK_AT) + " | s |")
    print("|---" * (5 + 2 * len(DELTA_AT) + 3 * len(STICK_AT)) + "|")
    with tempfile.TemporaryDirectory() as directory:
        for size in args.sizes:
            start = time.perf_counter()
            body, dt = pb.ball(directory, size), pb.stable_step(size)
            stuck = pb.run(body, pb.pull_scene(pb.STUCK_MU, pb.PULL_TIME, dt))
            pulled = pb.run(body, pb.pull_scene(pb.MU, pb.PULL_TIME, dt))
            errors = pb.delta_errors(pulled, stuck, DELTA_AT)
            stick, fit, slopes = [], [], []
            for q in STICK_AT:
                T = pb.time_at(pulled, q * pb.MU * pb.LOAD)
                to_q = pb.run(body, pb.pull_scene(pb.MU, T, dt))
                c = cm.stick_radius(float(to_q.series.F_d[-1]), pb.MU, pb.LOAD, a)
                c_fit, slope = pb.stick_radius_fit(to_q)
                stick.append(pb.stick_radius(to_q) / c - 1)
                fit.append(c_fit / c - 1)
                slopes.append(slope)
            ratio = pb.stuck_compliance(stuck) / pb.no_slip_compliance()
            print(f"| {size * 1e6:.0f} um | {pulled.info['nodes']} | "
                  f"{pulled.info['nodes_in_contact']} | {ratio:.3f} | "
                  + " | ".join(f"{errors[q][0]:+.1%}" for q in DELTA_AT) + " | "
                  + " | ".join(f"{errors[q][1]:+.1%}" for q in DELTA_AT) + " | "
                  + " | ".join(f"{e:+.1%}" for e in stick) + " | "
                  + " | ".join(f"{e:+.1%}" for e in fit) + " | "
                  + " | ".join(f"{s:.2f}" for s in slopes)
                  + f" | {time.perf_counter() - start:.0f} |", flush=True)


if __name__ == "__main__":
    with tempfile.TemporaryDirectory() as cache:   # the balls' models kept apart from the
        os.environ["VIBROFRIC_CACHE"] = cache       # user's cache
        main()
