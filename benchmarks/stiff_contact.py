"""F_dv/F_d0 against the contact stiffness, toward the rigid-Coulomb limit.

Prescribed sliding (drive.mode = "velocity", the setting of the closed-form
literature) on the paper's two cases, the Fig 7 scene (longitudinal, k_v = 6)
and the transverse one (k_v = 20, theta = 270 deg), with k_t from the paper's
80 MN/m to 1000 times it. For each: the lumped stepper (at the step that
resolves the slip, core.law_limits.slip_resolved), the FE model with the explicit
integrator (on the coarse mesh, at 1e-6 s or the largest of 5e-7, 2.5e-7 s
below the stable step), and the rigid-Coulomb ratio (analytic/closed_form.py).

    .venv/bin/python benchmarks/stiff_contact.py [--out docs/stiff_contact.png]
        [--factors 1,10,100,1000] [--fe-factors 1,10,100,1000]

It prints a markdown table (with the FE run's wall time and time per step,
and the friction law's sub-steps) and draws the figure. Both cases run 0.14 s
of plain sliding, then 20 ms of vibration (the start's transient decays slowly
on a stiff contact: with 18 ms of sliding before the vibration, the transverse
case at k_t x 100 was still 9% low after 20 ms of vibration).
"""

import argparse
import math
import platform
import sys
import time
from pathlib import Path

from mpi4py import MPI

from vibrofric import scene as scene_module
from vibrofric.analytic import run_coupled, summarize
from vibrofric.analytic.closed_form import coulomb_ratio
from vibrofric.bench.machine import cpu_name
from vibrofric.fem import run_fe
from vibrofric.fem.model.fe_model import build_model
from vibrofric.core.law_limits import slip_resolved

SCENES = Path(__file__).resolve().parent.parent / "scenes"
CASES = {"longitudinal": "longitudinal.toml", "transverse": "transverse.toml"}
PAPER_K_T = 80e6
SETTINGS = {"drive.mode": "velocity", "vibration.t_on": 0.14, "time.T": 0.16,
            "fem.output_every": 0, "fem.integrator": "explicit"}
STEPS = (1e-6, 5e-7, 2.5e-7)


def case_scene(case: str, factor: float):
    scene = scene_module.load(SCENES / CASES[case])
    return scene.with_values({**SETTINGS, "contact.k_t": PAPER_K_T * factor})


def explicit_step(scene) -> float:
    """The largest of STEPS below the mesh's stable step at this k_t."""
    stable = build_model(scene, MPI.COMM_SELF).dt_stable
    return max(dt for dt in STEPS if dt <= stable)


def lumped(scene) -> float:
    stepper_scene = slip_resolved(scene)
    return summarize(run_coupled(stepper_scene), stepper_scene, 0.0)["F_dv_over_F_d0"]


def fe(scene) -> dict:
    scene = scene.with_values({"time.dt": explicit_step(scene)})
    start = time.perf_counter()
    result = run_fe(scene, MPI.COMM_SELF)
    wall = time.perf_counter() - start
    info = result.info
    return {"ratio": summarize(result.series, scene, 0.0)["F_dv_over_F_d0"],
            "dt": scene.time.dt, "wall": wall,
            "per_step_us": 1e6 * info["wall_time_s"] / info["steps"],
            "substeps": info["friction_substeps"],
            "F_n": (info["F_n_min_window"], info["F_n_max_window"])}


def rigid(scene) -> float:
    v = scene.vibration
    return coulomb_ratio(v.k_v, v.theta_deg, scene.contact.eta_y)


def draw(rows, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    figure, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=False)
    for ax, case in zip(axes, CASES):
        mine = [r for r in rows if r["case"] == case]
        ax.semilogx([r["factor"] for r in mine], [r["lumped"] for r in mine], "o-",
                    label="lumped stepper")
        fe_rows = [r for r in mine if r.get("fe")]
        ax.semilogx([r["factor"] for r in fe_rows], [r["fe"]["ratio"] for r in fe_rows], "s",
                    label="FE (explicit, coarse mesh)")
        ax.axhline(mine[0]["rigid"], color="k", ls="--", label="rigid Coulomb")
        ax.set_title(f"{case} (prescribed sliding)")
        ax.set_xlabel("k_t / paper's 80 MN/m")
        ax.set_ylabel("F_dv / F_d0")
        ax.legend()
    figure.tight_layout()
    figure.savefig(path, dpi=100)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("docs/stiff_contact.png"))
    parser.add_argument("--factors", default="1,3,10,30,100,300,1000")
    parser.add_argument("--fe-factors", default="1,10,100,1000")
    args = parser.parse_args()
    factors = [float(f) for f in args.factors.split(",")]
    fe_factors = {float(f) for f in args.fe_factors.split(",")}
    print(f"machine: {cpu_name()} ({platform.machine()})", file=sys.stderr)
    rows = []
    for case in CASES:
        for factor in factors:
            scene = case_scene(case, factor)
            row = {"case": case, "factor": factor, "lumped": lumped(scene), "rigid": rigid(scene)}
            if factor in fe_factors:
                row["fe"] = fe(scene)
            rows.append(row)
            print(row, file=sys.stderr, flush=True)
    print("| case | k_t / paper's | lumped | FE (explicit) | FE - lumped | rigid Coulomb | "
          "FE step | sub-steps at most | time a step | FE run | summed normal force |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        f = r.get("fe")
        fe_cells = (f"{f['ratio']:.4f} | {100 * (f['ratio'] / r['lumped'] - 1):+.2f}% | "
                    if f else " | | ")
        run_cells = (f"{f['dt']:.3g} s | {f['substeps']} | {f['per_step_us']:.0f} us | "
                     f"{f['wall']:.0f} s | {f['F_n'][0]:.2f}-{f['F_n'][1]:.2f} N"
                     if f else " | | | | ")
        print(f"| {r['case']} | {r['factor']:g} | {r['lumped']:.4f} | {fe_cells}"
              f"{r['rigid']:.4f} | {run_cells} |")
    draw(rows, args.out)
    return 0 if all(math.isfinite(r["lumped"]) for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
