"""The roller's line contact against plane-strain Hertz at mid-length, as its mesh level
refines: R = 5 mm, L = 10 mm, P = 100 N, E = 0.2 GPa (tests/roller.py): the preload's
nodal pressures within 0.5 mm of y = 0 fitted by p^2 = p0^2 (1 - x^2 / a^2), against
a = 2 sqrt(P' R / pi E*) and p0 = 2 P' / pi a (Johnson, Contact Mechanics, eq 4.43).

    PYTHONPATH=. python benchmarks/roller_hertz.py [--levels coarse medium]

Prints a Markdown table (docs/validation.md, "Curved contacts").
"""

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))

import roller  # noqa: E402

from vibrofric.fem.model import fe_model  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--levels", nargs="+", default=["coarse", "medium"])
    args = parser.parse_args()
    a, p0 = roller.hertz()
    print(f"Hertz: a = {a * 1e3:.4f} mm, p0 = {p0 / 1e6:.3f} MPa\n")
    print("| fem.mesh | nodes | closed | a fit | p0 fit | s |")
    print("|---|---|---|---|---|---|")
    for level in args.levels:
        start = time.perf_counter()
        model = fe_model.build_model(roller.roller_scene(ROOT, level), None)
        a_fit, p0_fit = roller.mid_length_fit(model)
        print(f"| {level} | {model.disc.nodes} | {int((model.normal0 > 0).sum())} | "
              f"{a_fit / a - 1:+.1%} | {p0_fit / p0 - 1:+.1%} | "
              f"{time.perf_counter() - start:.0f} |", flush=True)


if __name__ == "__main__":
    with tempfile.TemporaryDirectory() as cache:   # the rollers' meshes and models kept apart
        os.environ["VIBROFRIC_CACHE"] = cache       # from the user's cache
        main()
