"""The FE contact patch against Hertz: a steel hemisphere (R = 10 mm, pole down) pressed
by P = 100 N on the rigid base, the static preload only, as the pole's mesh refines.

For each mesh (first-order tetrahedra of the pole's size within 0.4 mm of the pole,
growing to R / 4: tests/hemisphere.py) it builds the FE model of the Fig 7 scene with
that body (fe_model.build_model: density 7850 kg/m^3, no gravity, F_N = 100 N on the flat
top, the default per-area penalty) and compares its preload's patch with the closed
forms (Johnson, "Contact Mechanics", eqs 4.22-4.23): a = (3 P R / 4 E*)^(1/3),
p0 = 3 P / (2 pi a^2), E* = E / (1 - nu^2):

    a fit, p0 fit   the Hertz field p^2 = p0^2 (1 - r^2 / a^2) fitted to the nodal
                    pressures N_i / a_i above 0.3 of the largest (tests/hemisphere.py
                    hertz_fit): its edge and its centre
    peak            the largest nodal pressure (the summary's peak_pressure)
    a of area       sqrt(contact_area / pi), contact_area the summary's (the tributary
                    areas of the closed nodes: the edge nodes' whole areas count)

    PYTHONPATH=. python benchmarks/hertz_ball.py [--sizes 6e-5 4e-5 3e-5]

Prints a Markdown table (docs/validation.md, "Hertz: a ball on the base").
"""

import argparse
import math
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))

from hemisphere import ball_model, hemisphere, hertz, hertz_fit  # noqa: E402

from vibrofric import scene as scenes  # noqa: E402
from vibrofric.fem.outputs.contact_patch import patch  # noqa: E402

RADIUS, LOAD, FINE = 0.01, 100.0, 4e-4
SCENE = Path(__file__).resolve().parent.parent / "scenes" / "longitudinal.toml"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=float, nargs="+", default=[8e-5, 6e-5, 4e-5, 3e-5])
    args = parser.parse_args()
    scene = scenes.load(SCENE).with_values({"contact.F_N": LOAD, "body.gravity": 0.0,
                                            "body.density": 7850.0})
    a, p0 = hertz(scene.body.E, scene.body.nu, RADIUS, LOAD)
    print(f"Hertz: a = {a * 1e3:.4f} mm, p0 = {p0 / 1e9:.4f} GPa (E = {scene.body.E:g} Pa, "
          f"nu = {scene.body.nu:g}, R = {RADIUS:g} m, P = {LOAD:g} N)\n")
    print("| pole mesh | nodes | in contact | a fit | p0 fit | peak | a of area | s |")
    print("|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as directory:
        for size in args.sizes:
            start = time.perf_counter()
            body = hemisphere(directory, RADIUS, size, FINE)
            model = ball_model(body, scene)
            seconds = time.perf_counter() - start
            a_fit, p0_fit = hertz_fit(model)
            summary = patch(model.contact_area, model.normal0)
            a_area = math.sqrt(summary["contact_area"] / math.pi)
            print(f"| {size * 1e6:.0f} um | {model.disc.nodes} | {summary['nodes_in_contact']} | "
                  f"{a_fit / a - 1:+.2%} | {p0_fit / p0 - 1:+.2%} | "
                  f"{summary['peak_pressure'] / p0 - 1:+.2%} | {a_area / a - 1:+.2%} | "
                  f"{seconds:.0f} |", flush=True)


if __name__ == "__main__":
    main()
