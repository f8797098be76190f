"""The FE answer's step-error estimate against its true error, and the FE accuracy
figures of README.md, docs/fe-model.md and docs/performance.md, under the current
defaults (the shipped scenes, time.method auto: each answer its steady cycle).

    PYTHONPATH=. python benchmarks/fe_step_error.py [--quick] [--out DIR]

Two Markdown tables on stdout (and DIR/fe_step_error.md):

estimate  per case, F_dv/F_d0 at the case's step dt with the estimate the run
          reports (fem/step_error.py: the same integrator at dt/2, order 2 assumed),
          against the true error |F(dt) - F(dt/10)| (the same integrator at a tenth
          of the step; its own error is below a tenth of the difference where the
          order is at least 1); "within 3" where estimate / true lies in [1/3, 3] (or
          the true error is below 1e-6, the shooting's resolution). The table of
          docs/validation.md, "FE: the step-error estimate".
steps     Fig 7 per integrator and step, against the converged FE answer: the
          explicit integrator at REFERENCE_DT (the full model, converged in dt to
          ~3e-5: its answers at 2.5e-7 and 1.25e-7 s differ by 4e-5, order ~1).
          The figures README.md's "Which FE integrator" and docs/fe-model.md quote.

Wall times are measured on the machine it runs on, in one process (the first answer
of each integrator compiles or loads its loop: its time is left out of nothing,
read the estimate's added time, error_wall_time_s, against the answer's).
"""

import argparse
import time
from pathlib import Path

import vibrofric as vf
from vibrofric.fem import answer_ratio, run_fe

ROOT = Path(__file__).resolve().parent.parent
REFERENCE_DT = 1e-7
QUIET = {"fem.output_every": 0}

# (label, scene, overrides, dt)
ESTIMATE_CASES = [
    ("Fig 7, explicit", "longitudinal", {"fem.integrator": "explicit"}, 1e-6),
    ("Fig 7, reduced", "longitudinal", {"fem.integrator": "reduced"}, 1e-5),
    ("Fig 7, implicit", "longitudinal", {"fem.integrator": "implicit"}, 1e-5),
    ("Fig 10, k_v 20, reduced", "transverse", {"fem.integrator": "reduced"}, 1e-5),
    ("Fig 12, k_v 3, 75 deg, reduced", "coupled",
     {"fem.integrator": "reduced", "vibration.k_v": 3, "vibration.theta_deg": 75}, 1e-5),
    ("Fig 12, k_v 6, 150 deg, reduced", "coupled",
     {"fem.integrator": "reduced", "vibration.k_v": 6, "vibration.theta_deg": 150}, 1e-5),
    ("Fig 12, k_v 20, 300 deg, reduced", "coupled",
     {"fem.integrator": "reduced", "vibration.k_v": 20, "vibration.theta_deg": 300}, 1e-5),
]
QUICK_CASES = ("Fig 7, explicit", "Fig 7, reduced")

STEP_CASES = [("explicit", (1e-6, 5e-7, 2.5e-7)),
              ("implicit", (1e-5, 5e-6, 2.5e-6, 1e-6)),
              ("reduced", (1e-5, 5e-6, 2.5e-6, 1.25e-6, 1e-6))]


def scene_of(name, overrides, dt, estimate):
    return vf.load_scene(ROOT / "scenes" / f"{name}.toml",
                         **{**QUIET, **overrides, "time.dt": dt, "time.error_estimate": estimate})


def answer(name, overrides, dt, estimate=False):
    """(F_dv/F_d0, FEResult, wall s) of one FE run."""
    scene = scene_of(name, overrides, dt, estimate)
    begin = time.perf_counter()
    result = run_fe(scene)
    return answer_ratio(result, scene), result, time.perf_counter() - begin


def estimate_table(cases) -> list[str]:
    rows = ["| case | dt s | F_dv/F_d0 | estimate | order | true error (vs dt/10) | "
            "estimate / true | within 3 | answer s | estimate s |",
            "|---|---|---|---|---|---|---|---|---|---|"]
    for label, name, overrides, dt in cases:
        ratio, result, wall = answer(name, overrides, dt, estimate=True)
        reference, _, _ = answer(name, overrides, dt / 10)
        error = result.step_error
        true = abs(ratio - reference)
        quotient = error.estimate / true if error.estimate is not None and true > 0 else None
        within = true <= 1e-6 or (quotient is not None and 1 / 3 <= quotient <= 3)
        order = f"{error.order:.2f}" if error.order is not None else "2 assumed"
        spent = result.info["error_wall_time_s"]
        rows.append(f"| {label} | {dt:g} | {ratio:.5f} | {error.estimate:.2e} | {order} | "
                    f"{true:.2e} | {quotient:.2f} | {'yes' if within else 'NO'} | "
                    f"{wall - spent:.2f} | {spent:.2f} |")
        print(rows[-1], flush=True)
    return rows


def steps_table() -> list[str]:
    reference, _, wall = answer("longitudinal", {"fem.integrator": "explicit"}, REFERENCE_DT)
    rows = [f"Fig 7, coarse mesh, each answer its steady cycle. Converged FE answer: explicit at "
            f"{REFERENCE_DT:g} s, F_dv/F_d0 = {reference:.5f} ({wall:.1f} s).", "",
            "| integrator | dt s | F_dv/F_d0 | error vs converged | relative | wall s |",
            "|---|---|---|---|---|---|"]
    for integrator, steps in STEP_CASES:
        for dt in steps:
            ratio, _, wall = answer("longitudinal", {"fem.integrator": integrator}, dt)
            rows.append(f"| {integrator} | {dt:g} | {ratio:.5f} | {ratio - reference:+.2e} | "
                        f"{(ratio - reference) / reference:+.2%} | {wall:.2f} |")
            print(rows[-1], flush=True)
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="Fig 7 only, no steps table")
    parser.add_argument("--out", type=Path)
    args = parser.parse_args()
    cases = [c for c in ESTIMATE_CASES if not args.quick or c[0] in QUICK_CASES]
    lines = estimate_table(cases)
    if not args.quick:
        lines += [""] + steps_table()
    text = "\n".join(lines)
    print(text)
    if args.out is not None:
        args.out.mkdir(parents=True, exist_ok=True)
        (args.out / "fe_step_error.md").write_text(text + "\n")


if __name__ == "__main__":
    main()
