"""FE against the lumped model for every friction law, block and normal-force rule.

    .venv/bin/python benchmarks/law_agreement.py [--quick] [--out results/law_agreement.json]

The Fig 7 scene (longitudinal, k_v = 6) to 0.3 s with the reduced integrator
on the default mesh, for each law of LAWS on three blocks:

    steel  the paper's block (E = 209 GPa, 0.03 x 0.04 x 0.053 m)
    stiff  the same block 100 times stiffer (E = 2.09e13 Pa): the lumped model's
           rigid body, but still tall: the friction force at the contact plane
           and the block's inertia at mid-height pitch it, and the contact
           pressure shifts between the front and back nodes
    flat   stiff and 5 mm tall (the same mass): the pitching moment 10 times
           smaller, the one contact patch under a rigid block that the lumped
           model describes

and, for the asperity laws (Dahl, LuGre), each contact.normal_change rule. Prints
a Markdown table of F_dv/F_d0 (analytic; FE and its difference per block) and
writes every number as JSON. docs/friction-laws.md holds a measured copy.
"""

import argparse
import json
import math
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from mpi4py import MPI  # noqa: E402,F401  (before DOLFINx: the PyPI stack's libmpi)

from vibrofric import scene as scene_module  # noqa: E402
from vibrofric.analytic.solve import solve as run_analytic  # noqa: E402
from vibrofric.analytic.summary import summarize  # noqa: E402
from vibrofric.core.errors import NumericalError  # noqa: E402
from vibrofric.fem import run_fe  # noqa: E402
from vibrofric.core.law_limits import slip_resolved  # noqa: E402

LAWS_DIR = ROOT / "examples" / "laws"
LAWS = [  # (label, contact.law, its parameters)
    ("Dahl, i = 0", "dahl", {"dahl_exponent": 0.0}),
    ("Dahl, i = 0.5", "dahl", {"dahl_exponent": 0.5}),
    ("Dahl, i = 1", "dahl", {}),
    ("Dahl, i = 2", "dahl", {"dahl_exponent": 2.0}),
    ("LuGre (defaults)", "lugre", {}),
    ("maxwell_slip (4 elements)", str(LAWS_DIR / "maxwell_slip.py"), {}),
    ("Jenkins (jenkins.py)", str(LAWS_DIR / "jenkins.py"), {}),
]
BODIES = {
    "steel": {},
    "stiff": {"body.E": 2.09e13},
    "flat": {"body.E": 2.09e13, "body.size": [0.03, 0.04, 0.005]},
}
RULES = ("return", "keep", "scale")
SETTINGS = {"time.T": 0.3, "fem.integrator": "reduced", "fem.output_every": 0}


def scene_for(law, parameters, body, scene_file="longitudinal", **more):
    scene = scene_module.load(ROOT / "scenes" / f"{scene_file}.toml")
    scene = scene.with_law(law, parameters).with_values({**SETTINGS, **BODIES[body], **more})
    return scene


def ratio_fe(scene) -> float:
    """F_dv/F_d0 of the FE run; NaN for a run that failed (its error on stderr)."""
    try:
        fe = run_fe(scene)
    except NumericalError as err:
        print(f"{scene.contact.law} {scene.contact.given} E = {scene.body.E:g}: {err}",
              file=sys.stderr)
        return math.nan
    return summarize(fe.series, scene, 0.0)["F_dv_over_F_d0"]


def ratio_analytic(scene) -> float:
    return run_analytic(slip_resolved(scene))[1]["F_dv_over_F_d0"]


def rows(quick: bool):
    for label, law, parameters in LAWS[:3] if quick else LAWS:
        asperity = law in ("dahl", "lugre")
        for rule in RULES if asperity else (None,):
            given = {**parameters, **({"normal_change": rule} if rule else {})}
            analytic = ratio_analytic(scene_for(law, given, "steel"))
            fe = {body: ratio_fe(scene_for(law, given, body))
                  for body in (("steel",) if quick else BODIES)}
            print(label, rule, analytic, fe, file=sys.stderr, flush=True)
            yield {"law": label, "rule": rule, "analytic": analytic, "fe": fe}


def spread(quick: bool):
    """Dahl (i = 1) on each shipped scene, steel block, under each rule."""
    for scene_file in ("longitudinal",) if quick else ("longitudinal", "transverse", "coupled"):
        for rule in RULES:
            scene = scene_for("dahl", {"normal_change": rule}, "steel", scene_file)
            yield {"scene": scene_file, "rule": rule, "analytic": ratio_analytic(scene),
                   "fe": ratio_fe(scene)}


def percent(fe, analytic) -> str:
    return f"{100.0 * (fe - analytic) / analytic:+.2f}%"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="three laws, the steel block only")
    parser.add_argument("--out", type=Path, default=ROOT / "results" / "law_agreement.json")
    args = parser.parse_args(argv)
    start = time.perf_counter()
    table = list(rows(args.quick))
    bodies = list(table[0]["fe"])
    print("| law | normal_change | analytic | " + " | ".join(f"FE {b} | vs analytic" for b in bodies)
          + " |")
    print("|---|---|---|" + "---|---|" * len(bodies))
    for row in table:
        cells = " | ".join(f"{row['fe'][b]:.4f} | {percent(row['fe'][b], row['analytic'])}"
                           for b in bodies)
        print(f"| {row['law']} | {row['rule'] or '(radial return)'} | {row['analytic']:.4f} | "
              f"{cells} |")
    scenes = list(spread(args.quick))
    print("\n| scene | normal_change | analytic | FE steel | vs analytic |\n|---|---|---|---|---|")
    for row in scenes:
        print(f"| {row['scene']} | {row['rule']} | {row['analytic']:.4f} | {row['fe']:.4f} | "
              f"{percent(row['fe'], row['analytic'])} |")
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps({"laws": table, "scenes": scenes}, indent=1))
    print(f"\n{time.perf_counter() - start:.0f} s; {args.out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
