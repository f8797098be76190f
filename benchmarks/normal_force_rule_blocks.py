"""What the normal-force rule moves, against how much the contact nodes' normal forces swing.

    PYTHONPATH=. .venv/bin/python benchmarks/normal_force_rule_blocks.py

The Fig 7 scene (longitudinal, k_v = 6, Dahl i = 1) answered by its steady cycle
(time.method "auto"), reduced integrator at dt = 1e-5 s, on the three blocks of
benchmarks/law_agreement.py (steel, the paper's; stiff, 100 times stiffer; flat,
stiff and 5 mm tall), under fem.normal_force = "nodal" with each
contact.normal_change and under "nominal". Prints a Markdown table of the
nodes' swing (fem/outputs/normal_swing.py, node_swing) and F_dv/F_d0 against the
analytic stepper beside it: what sets normal_swing.RULE_MATTERS. Then, on the
steel block, both rules at dt = 1e-5, 5e-6 and 2.5e-6 s: each rule's step error.
docs/validation.md holds a measured copy.
"""

import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from mpi4py import MPI  # noqa: E402,F401  (before DOLFINx: the PyPI stack's libmpi)

from vibrofric import scene as scene_module  # noqa: E402
from vibrofric.core.errors import NumericalError  # noqa: E402
from vibrofric.fe_beside_analytic import run_beside  # noqa: E402

BODIES = {
    "steel": [],
    "stiff": ["body.E=2.09e13"],
    "flat": ["body.E=2.09e13", "body.size=[0.03, 0.04, 0.005]"],
}
RULES = [("nodal", "return"), ("nodal", "keep"), ("nodal", "scale"), ("nominal", "return")]
SETTINGS = ['fem.integrator="reduced"', "fem.output_every=0", "time.T=0.3"]
STEPS = ("1e-5", "5e-6", "2.5e-6")


def answer(body: str, normal_force: str, normal_change: str, dt: str = "1e-5"):
    """(FE F_dv/F_d0, analytic F_dv/F_d0, node swing), or None where the FE run fails."""
    scene = scene_module.load(ROOT / "scenes" / "longitudinal.toml", [
        *BODIES[body], *SETTINGS, f"time.dt={dt}", f'fem.normal_force="{normal_force}"',
        f'contact.normal_change="{normal_change}"'])
    try:
        document = run_beside(scene, Path(tempfile.mkdtemp())).document
    except NumericalError:
        return None
    fe = document["fe"]
    return fe["F_dv_over_F_d0"], document["analytic"]["F_dv_over_F_d0"], \
        fe["normal_force_node_swing"]


def main() -> int:
    print("| block | node swing (nodal, return) | analytic | "
          + " | ".join(f"{force}, {change}" for force, change in RULES)
          + " | spread |\n|---|---|---|" + "---|" * len(RULES) + "---|")
    for body in BODIES:
        results = [answer(body, force, change) for force, change in RULES]
        done = [r for r in results if r is not None]
        analytic = done[0][1]
        cells = [f"{r[0]:.4f} ({r[0] / r[1] - 1:+.2%})" if r else "fails" for r in results]
        ratios = [r[0] for r in done]
        spread = (max(ratios) - min(ratios)) / analytic
        print(f"| {body} | {results[0][2]:.1%} | {analytic:.4f} | " + " | ".join(cells)
              + f" | {spread:.2%} |", flush=True)
    print("\n| steel block, dt (s) | " + " | ".join(STEPS) + " |\n|---|" + "---|" * len(STEPS))
    for force in ("nodal", "nominal"):
        cells = []
        for dt in STEPS:
            fe, analytic, _ = answer("steel", force, "return", dt)
            cells.append(f"{fe:.4f} ({fe / analytic - 1:+.2%})")
        print(f"| {force} | " + " | ".join(cells) + " |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
