"""The Fig 12 FE study under each normal-force rule, against the analytic model.

    PYTHONPATH=. .venv/bin/python benchmarks/fig12_normal_force_rule.py
        [--grid full|half|reduced|axis] [--dt 1e-5] [--set KEY=VALUE ...]
        [--out results/fig12-normal-force-rule] [--workers N]
        [--figure docs/fig12_normal_force_rule.png]

Runs, for fem.normal_force = "nodal" (the default) and "nominal", the study of
docs/command-line.md (the coupled scene, reduced integrator, dt = 1e-5 s or
--dt, k_v = 2, 3, 4, 6, 20 x 25 angles over 360 deg; --grid half: the same k_v x
13 angles over 0-180 deg, the FE answers being symmetric about 180 deg to 5e-6,
the block and its mesh mirror-symmetric in Y; --grid reduced: k_v = 2, 6, 20 x 13
angles over 360 deg; --grid axis: k_v = 2, 4, 6 along X, to see the step's error
with --dt) as `vibrofric sweep ... --fe` into OUT/nodal and
OUT/nominal (rerun to resume: finished points are kept), then prints a Markdown
table per k_v of the FE answer against the analytic stepper beside it (the
stepper at the slip-resolving step: fe_beside_analytic.analytic_scene) under
each rule, and of the contact nodes' normal-force swing (fe.normal_force_node_swing,
fem/outputs/normal_swing.py), and draws FE - analytic against the angle for both
rules. docs/validation.md holds a measured copy.
"""

import argparse
import csv
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
RULES = ("nodal", "nominal")
GRIDS = {"full": ("vibration.k_v=2,3,4,6,20", "vibration.theta_deg=0:360:25"),
         "half": ("vibration.k_v=2,3,4,6,20", "vibration.theta_deg=0:180:13"),
         "reduced": ("vibration.k_v=2,6,20", "vibration.theta_deg=0:360:13"),
         "axis": ("vibration.k_v=2,4,6", "vibration.theta_deg=0")}


def sweep(rule: str, grid, dt: str, out: Path, workers: int, more=()) -> Path:
    """Run (or resume) the study under ``rule`` into ``out``; returns its results.csv."""
    scene = ROOT / "scenes" / "coupled.toml"
    command = [sys.executable, "-m", "vibrofric.cli", "sweep", str(scene), "--fe",
               "--set", "fem.output_every=0", "--set", "fem.integrator=reduced",
               "--set", f"time.dt={dt}", "--set", f'fem.normal_force="{rule}"',
               *[arg for value in more for arg in ("--set", value)],
               "--grid", grid[0], "--grid", grid[1], "--out", str(out), "--workers", str(workers)]
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    subprocess.run(command, check=True, env=env, cwd=ROOT)
    return out / "results.csv"


def read(path: Path) -> dict:
    """{(k_v, theta): (FE, analytic, node swing)} of a sweep's results.csv."""
    points = {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            key = (float(row["vibration.k_v"]), float(row["vibration.theta_deg"]))
            points[key] = (float(row["fe.F_dv_over_F_d0"]), float(row["analytic.F_dv_over_F_d0"]),
                           float(row["fe.normal_force_node_swing"]))
    return points


def table(results: dict) -> str:
    """The Markdown table: per k_v, the analytic range, FE - analytic (median |.|, worst
    signed with its angle) under each rule, and the node swing's range."""
    lines = ["| k_v | analytic F_dv/F_d0 | " + " | ".join(
        f"FE vs analytic, {rule}: median abs. | worst" for rule in RULES)
        + " | node swing (nodal) |",
        "|---|---|" + "---|---|" * len(RULES) + "---|"]
    nodal = results["nodal"]
    for k_v in sorted({k for k, _ in nodal}):
        keys = sorted(key for key in nodal if key[0] == k_v)
        analytic = np.array([nodal[key][1] for key in keys])
        row = f"| {k_v:g} | {analytic.min():.4f}-{analytic.max():.4f} |"
        for rule in RULES:
            error = np.array([results[rule][key][0] / results[rule][key][1] - 1.0 for key in keys])
            worst = int(np.argmax(np.abs(error)))
            row += (f" {np.median(np.abs(error)):.2%} | {error[worst]:+.2%} "
                    f"({keys[worst][1]:g} deg) |")
        swing = np.array([nodal[key][2] for key in keys])
        lines.append(row + f" {swing.min():.0%}-{swing.max():.0%} |")
    return "\n".join(lines)


def figure(results: dict, dt: str, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.5, 4.2))
    k_values = sorted({k for k, _ in results["nodal"]})
    colors = plt.cm.viridis(np.linspace(0.0, 0.9, len(k_values)))
    for k_v, color in zip(k_values, colors):
        for rule, style in zip(RULES, ("-o", "--s")):
            keys = sorted(key for key in results[rule] if key[0] == k_v)
            theta = [key[1] for key in keys]
            error = [100.0 * (results[rule][key][0] / results[rule][key][1] - 1.0) for key in keys]
            ax.plot(theta, error, style, color=color, markersize=3, linewidth=1,
                    label=f"k_v = {k_v:g}, {rule}")
    ax.axhline(0.0, color="black", linewidth=0.5)
    ax.set_xlabel("theta (deg)")
    ax.set_ylabel("FE / analytic - 1 (%)")
    ax.set_title(f"Fig 12 study, FE (reduced, {dt} s) against the analytic model:\n"
                 "fem.normal_force = \"nodal\" (solid) and \"nominal\" (dashed)")
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grid", choices=sorted(GRIDS), default="full")
    parser.add_argument("--out", type=Path, default=ROOT / "results" / "fig12-normal-force-rule")
    parser.add_argument("--dt", default="1e-5", help="time.dt of the FE runs, s")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                        help="another scene key for both rules' sweeps (repeatable)")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--figure", type=Path, default=None, help="write the figure here (PNG)")
    args = parser.parse_args()
    grid = GRIDS[args.grid]
    results = {rule: read(sweep(rule, grid, args.dt, args.out / rule, args.workers, args.set))
               for rule in RULES}
    print(table(results))
    if args.figure is not None:
        figure(results, args.dt, args.figure)
    return 0


if __name__ == "__main__":
    sys.exit(main())
