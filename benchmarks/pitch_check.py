"""Is the tall stiff block's FE-vs-lumped difference its pitching? Two checks.

    .venv/bin/python benchmarks/pitch_check.py

The Fig 7 scene (0.3 s, reduced integrator, default mesh) on the "stiff" block of
benchmarks/law_agreement.py (E = 2.09e13 Pa, 53 mm tall), Dahl ("return") at
several shape exponents i:

1. the FE model as it is, and with benchmarks/laws/dahl_nominal_normal.py: the
   same law fed each node's nominal normal force F_N w_i. The block still
   pitches; the law no longer sees the nodes' normal forces swing;
2. the lumped model with benchmarks/laws/dahl_pitching_rows.py: Dahl on the five
   rows of contact nodes, row r's normal force N w_r (1 + pitch xi_r F / F_c +
   tilt xi_r), pitch and tilt fitted to the FE nodes' normal forces over the last
   4 cycles (Dahl, i = 0.5). No FE in this one.

If the difference is the law's answer to the pitching's normal forces, (1) takes
it away and (2) puts it back. docs/friction-laws.md holds a measured copy.
"""

import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent
sys.path.insert(0, str(ROOT.parent))
sys.path.insert(0, str(ROOT))

import law_agreement  # noqa: E402  (imports mpi4py before DOLFINx)
import normal_force_swing  # noqa: E402

from vibrofric.fem import simulate as fem_simulate  # noqa: E402

NOMINAL = str(ROOT / "laws" / "dahl_nominal_normal.py")
ROWS = str(ROOT / "laws" / "dahl_pitching_rows.py")
EXPONENTS = (0.0, 0.25, 0.5, 0.75, 1.0, 2.0)


def fitted_pitch(exponent=0.5):
    """(pitch, tilt): N_i / mean(N_i) - 1 = pitch xi_i F / F_c + tilt xi_i, least squares
    over the contact nodes and the samples of the last 4 cycles (xi = -1 back, +1 front)."""
    scene = law_agreement.scene_for("dahl", {"dahl_exponent": exponent}, "stiff",
                                    **{"fem.output_every": normal_force_swing.SAMPLE})
    fem_simulate.FrameWriter = normal_force_swing.NodeSampler
    fem_simulate.run_fe(scene, vtk_dir=Path("/nonexistent"))
    samples = normal_force_swing.NodeSampler.samples
    t = np.array([s[0] for s in samples])
    keep = t >= t[-1] - 4.0 / scene.vibration.f
    normal = np.array([s[1] for s in samples])[keep]
    friction = np.array([s[2][:, 0].sum() for s in samples])[keep] / scene.F_c
    model = normal_force_swing.NodeSampler.model
    x = model.disc.coordinates[model.contact_nodes, 0]
    xi = (x - x.mean()) / (x.max() - x.mean())
    relative = normal / normal.mean(axis=0) - 1.0
    columns = np.column_stack([np.outer(friction, xi).ravel(), np.tile(xi, len(friction))])
    (pitch, tilt), *_ = np.linalg.lstsq(columns, relative.ravel(), rcond=None)
    return pitch, tilt


def percent(value, reference) -> str:
    return f"{100.0 * (value - reference) / reference:+.2f}%"


def main() -> int:
    pitch, tilt = fitted_pitch()
    print(f"fitted on the FE nodes: pitch {pitch:.3f}, tilt {tilt:.3f}\n")
    print("| i | lumped | FE stiff | vs lumped | FE stiff, law at nominal N | vs lumped "
          "| lumped, pitching rows | vs lumped |")
    print("|---|---|---|---|---|---|---|---|")
    for i in EXPONENTS:
        lumped = law_agreement.ratio_analytic(law_agreement.scene_for(
            "dahl", {"dahl_exponent": i}, "steel"))
        fe = law_agreement.ratio_fe(law_agreement.scene_for("dahl", {"dahl_exponent": i}, "stiff"))
        nominal = law_agreement.ratio_fe(law_agreement.scene_for(
            NOMINAL, {"dahl_exponent": i}, "stiff"))
        rows = law_agreement.ratio_analytic(law_agreement.scene_for(
            ROWS, {"dahl_exponent": i, "pitch": pitch, "tilt": tilt}, "steel"))
        print(f"| {i:g} | {lumped:.4f} | {fe:.4f} | {percent(fe, lumped)} | {nominal:.4f} | "
              f"{percent(nominal, lumped)} | {rows:.4f} | {percent(rows, lumped)} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
