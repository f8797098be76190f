"""The analytic answers' step-error estimate against their true error: docs/validation.md's table.

Every analytic F_dv/F_d0 carries an estimate of its time step's error from the same
solver at dt/2 and dt/4 (vibrofric/analytic/accuracy.py). Here it is set against the
true error, taken as |F(dt) - F(dt/10)| (the same solver at a tenth of the step the
answer used: the periodic orbit with 10 n steps a cycle, or the stepped run at dt/10),
over the paper's grids at the default step (Fig 6: longitudinal scene, Fig 9:
transverse, k_v = 0, 1, ..., 20; Fig 12: coupled, k_v 2, 3, 4, 6, 20 x 25 angles) and
at the steps of the cases in docs/validation.md (longitudinal at dt 1.9e-5 and
2.4e-5 s, coupled at 1e-5 s). The estimate should lie within a factor 3 of the true
error wherever that exceeds 1e-6 (below, both are at the level of the reference's
own error). Also measured: what the estimate adds to the cost (the answer, then the
two halved orbits or runs, timed apart), on Fig 7 and over the 125 Fig 12 points.

    PYTHONPATH=. python benchmarks/step_error_table.py            # ~3 min on a loaded machine
    PYTHONPATH=. python benchmarks/step_error_table.py --quick    # Fig 12 at k_v 2 and 20 only
"""

import argparse
import math
import sys

import numpy as np

import vibrofric as vf
from vibrofric.analytic.continuation import run_in_sequence
from vibrofric.analytic.coupled import run_coupled
from vibrofric.analytic.periodic import find_orbit
from vibrofric.analytic.solve import solve
from vibrofric.analytic.summary import cycle_average
from vibrofric.core.series import averaging_steps

REFERENCE_DIVISOR = 10
FACTOR = 3.0            # the estimate within this factor of the true error ...
TRUE_FLOOR = 1e-6       # ... wherever the true error exceeds this


def grids(quick: bool) -> dict:
    k_v = [float(k) for k in range(21)]
    fig12_k_v = (2.0, 20.0) if quick else (2.0, 3.0, 4.0, 6.0, 20.0)
    return {
        "Fig 6": ("longitudinal", [{"vibration.k_v": k} for k in k_v]),
        "Fig 9": ("transverse", [{"vibration.k_v": k} for k in k_v]),
        "Fig 12": ("coupled", [{"vibration.k_v": k, "vibration.theta_deg": float(t)}
                               for k in fig12_k_v for t in np.linspace(0, 360, 25)]),
    }


CASES = [
    ("longitudinal, dt 1.9e-5 s", "longitudinal", {"time.dt": 1.9e-5}),
    ("longitudinal, dt 2.4e-5 s", "longitudinal", {"time.dt": 2.4e-5}),
    ("coupled, dt 1e-5 s", "coupled", {"time.dt": 1e-5}),
    ("coupled, k_v 20, theta 180", "coupled",
     {"vibration.k_v": 20.0, "vibration.theta_deg": 180.0}),
]


def reference_answer(scene, method: str, dt: float) -> float:
    """F_dv/F_d0 of the same solver at ``dt`` (the answer alone, no estimate of its own):
    the periodic orbit, from steady sliding, or the stepped run through time.T."""
    finer = scene.with_values({"time.dt": dt})
    if method == "periodic":
        orbit = find_orbit(finer, "coupled", judge=False)
        assert orbit.converged, f"the reference orbit at dt {dt:g} did not converge"
        return float(np.mean(orbit.cycle[:, 1])) / finer.F_c
    series = run_coupled(finer)
    return cycle_average(series.F_d, averaging_steps(finer)) / finer.F_c


def measure(scene) -> dict:
    """The answer with its estimate (solve: the method the scene asks), and the true
    error against the same method at dt_used / 10."""
    _, summary = solve(scene)
    method = summary.get("periodic", {}).get("method", "transient")
    answer = summary["F_dv_over_F_d0"]
    true = abs(answer - reference_answer(scene, method, summary["dt_used"] / REFERENCE_DIVISOR))
    return {"answer": answer, "estimate": summary["error_estimate"],
            "order": summary["error_order"], "dt": summary["dt_used"], "true": true,
            "method": method}


def ratio(row) -> float:
    return row["estimate"] / row["true"] if row["true"] > 0 else math.inf


def judged(row) -> bool:
    """Within FACTOR (above or below) where the true error exceeds TRUE_FLOOR."""
    if row["true"] <= TRUE_FLOOR:
        return True
    return row["estimate"] is not None and 1.0 / FACTOR <= ratio(row) <= FACTOR


def label(values: dict) -> str:
    return ", ".join(f"{k.split('.')[-1]} {v:g}" for k, v in values.items())


def cost(quick: bool) -> list[str]:
    """The estimate's cost beside the answer's, from the summaries' wall_time_s (the
    answer) and error_wall_time_s (the halved orbits or runs): Fig 7 periodic (the
    median of 20) and stepped to 1 s, and the Fig 12 points in sequence, each from its
    neighbour's orbit as a sweep runs them."""
    scene = vf.load_scene("longitudinal")
    solve(scene)   # loaded (compiled) before any clock
    runs = [solve(scene)[1] for _ in range(20)]
    answer = float(np.median([r["wall_time_s"] for r in runs]))
    estimate = float(np.median([r["error_wall_time_s"] for r in runs]))
    lines = [f"| Fig 7 (periodic) | {answer * 1e3:.1f} ms | {estimate * 1e3:.1f} ms | "
             f"{estimate / answer:.0%} |"]
    _, stepped = solve(scene.with_values({"time.method": "transient"}))
    lines.append(f"| Fig 7 (transient, T = 1 s) | {stepped['wall_time_s']:.2f} s | "
                 f"{stepped['error_wall_time_s']:.2f} s | "
                 f"{stepped['error_wall_time_s'] / stepped['wall_time_s']:.0%} |")
    name, points = grids(quick)["Fig 12"]
    summaries = run_in_sequence(vf.load_scene(name), points)
    answer = sum(s["wall_time_s"] for s in summaries)
    estimate = sum(s["error_wall_time_s"] for s in summaries)
    lines.append(f"| Fig 12, {len(points)} points in sequence (periodic) | {answer:.2f} s | "
                 f"{estimate:.2f} s | {estimate / answer:.0%} |")
    return lines


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args(argv)
    out = ["| grid | points | true error > 1e-6 | true error (max) | estimate / true "
           "(min - max, where true > 1e-6) | outside a factor 3 |",
           "|---|---|---|---|---|---|"]
    exceptions = []
    for figure, (name, points) in grids(args.quick).items():
        scene = vf.load_scene(name)
        rows = []
        for values in points:
            row = measure(scene.with_values(values))
            row["point"] = label(values)
            rows.append(row)
            print(f"{figure} {row['point']}: {row}", file=sys.stderr, flush=True)
        counted = [r for r in rows if r["true"] > TRUE_FLOOR]
        bad = [r for r in rows if not judged(r)]
        ratios = [ratio(r) for r in counted]
        span = f"{min(ratios):.2f} - {max(ratios):.2f}" if ratios else "-"
        out.append(f"| {figure} ({name}) | {len(rows)} | {len(counted)} | "
                   f"{max(r['true'] for r in rows):.2g} | {span} | "
                   f"{', '.join(r['point'] for r in bad) or 'none'} |")
        exceptions += [(figure, r) for r in bad]
    out += ["", "| case | dt used (s) | F_dv/F_d0 | estimate | order | true error | "
                "estimate / true |", "|---|---|---|---|---|---|---|"]
    for title, name, values in CASES:
        row = measure(vf.load_scene(name, **values))
        order = f"{row['order']:.2f}" if row["order"] is not None else "-"
        out.append(f"| {title} | {row['dt']:.6g} | {row['answer']:.5f} | {row['estimate']:.2g} | "
                   f"{order} | {row['true']:.2g} | {ratio(row):.2f} |")
        if not judged(row):
            exceptions.append((title, row))
    if exceptions:
        out += ["", "Outside a factor 3:"]
        out += [f"- {where} {r.get('point', '')}: estimate {r['estimate']:.2g}, true "
                f"{r['true']:.2g} ({r['method']}, dt {r['dt']:.6g})" for where, r in exceptions]
    out += ["", "| cost | the answer | its estimate | added |", "|---|---|---|---|"]
    out += cost(args.quick)
    print("\n".join(out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
