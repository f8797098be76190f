"""The FE model against the lumped one with the base moving along Z (docs/validation.md,
"FE against the lumped model: a base moving along Z").

The paper's block (the longitudinal scene, 0.5 kg, contact-plane drive) made
``--stiffer`` times stiffer (body.E x 100 by default), so that its own compliance,
which the lumped body lacks, does not dominate: the FE penalty fem.penalty is fixed
at the default block's (10 E A / L_z at E = 209 GPa) and the lumped contact.k_n
matched to the stiff block's bounce on it (core/bounce.py, the bar on the spring: 3%
below the penalty at E x 100). At E x 100 the reduced model's steady cycle is
unstable at 100-250 steps a cycle, with or without the normal motion, and its
stepped runs drift: docs/validation.md's table is at --stiffer 10. Cases (A_th: the
amplitude at which the forced normal-force swing m w^2 A_n / (1 - r^2) reaches F_N):

    in contact   A_n = 0.45 A_th, phase 0, with the longitudinal vibration k_v = 6
                 (and without the normal motion: the stiff block's in-plane agreement)
    elliptical   A_n = 0.45 A_th, normal_phase_deg = 90, k_v = 6
    normal only  A_n = 0.45 A_th, k_v = 0 (the normal motion alone lowers F_dv)
    contact lost A_n = 1.012 A_th, k_v = 6 (the lumped body out of contact for 9% of
                 its cycle; 1.7e-7 m on the paper's block: tests/test_normal.py)

The vibration starts at the scene's t_on (0.14 s of sliding). The FE model answers
by its steady cycle (time.method auto: the shooting of integrators/periodic.py, or
stepped through time.T = t_on + ``--cycles`` / f where it finds none) with its
reduced integrator (the stiff block's explicit stable step is ten times shorter) at
``--steps-per-cycle`` (200: at 100 the elliptical case's FE answer lay 2% low, its
step error); the lumped one is stepped at ``--lumped-dt`` (5e-7 s) through the same
T, both averaging the last 20 cycles. (Stepped for 60 cycles from 5 ms of sliding, the drive spring's slow mode,
0.984 a cycle, had not settled: the in-plane case alone differed by 10%.)

    .venv/bin/python benchmarks/fe_normal_vs_lumped.py [--mesh coarse] [--cycles 800]
        [--stiffer 100] [--steps-per-cycle 200] [--lumped-dt 5e-7]
        (docs/validation.md's table: --stiffer 10)
    .venv/bin/python benchmarks/fe_normal_vs_lumped.py --stiffer 1 --integrator explicit
        --levels 0.6,0.8,0.95,1.012
        (the normal motion alone, k_v = 0, at those fractions of A_th; the explicit
        FE run at the lumped time.dt: docs/validation.md's second table)

prints a markdown table: each model's F_dv/F_d0, their relative difference, each
one's contact_loss_fraction and summed normal force's range, and the FE judgement.
"""

import argparse
import math
import platform
import time

from vibrofric.analytic.solve import solve
from vibrofric.api import load_scene
from vibrofric.core.bounce import bounce_stiffness, default_penalty
from vibrofric.fem import run_fe
from vibrofric.fem.simulate import answer_ratio

STIFFER = 100.0
AVERAGED = 20
CASES = (("no normal motion", 0.0, None, 6.0, {}),
         ("in contact", 0.45, None, 6.0, {}),
         ("elliptical", 0.45, 90.0, 6.0, {}),
         ("normal only", 0.45, None, 0.0, {}),
         ("contact lost", 1.012, None, 6.0, {}))


def stiff_scene(mesh: str, cycles: int, stiffer: float = STIFFER, **keys):
    """The longitudinal scene on the block ``stiffer`` times stiffer, penalty and lumped
    k_n matched."""
    base = load_scene("longitudinal")
    body = base.body
    E = stiffer * body.E
    penalty = default_penalty(body.E, body.size)
    rho = body.mass / math.prod(body.size)
    k_n = bounce_stiffness(body.mass, E, rho, body.size, penalty)
    f, t_on = base.vibration.f, base.vibration.t_on
    values = {"body.E": E, "fem.penalty": penalty, "contact.k_n": k_n, "fem.mesh": mesh,
              "fem.integrator": "reduced", "time.T": t_on + cycles / f,
              "time.average_cycles": AVERAGED, "time.method": "auto",
              "time.error_estimate": False, "fem.output_every": 0, **keys}
    return load_scene("longitudinal", **values)


def threshold(scene) -> float:
    """A_th: m w^2 A / (1 - r^2) = F_N on the lumped contact k_n."""
    m, w = scene.body.mass, scene.omega
    r2 = w * w * m / scene.normal_stiffness
    return scene.contact.F_N * (1.0 - r2) / (m * w * w)


def fe_step(args, f: float) -> float:
    """The FE time.dt: the reduced integrator's ``--steps-per-cycle``; the explicit one at
    the lumped step (below the coarse block's stable step, 1.05e-6 s at E x 1)."""
    return args.lumped_dt if args.integrator == "explicit" else 1.0 / (args.steps_per_cycle * f)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mesh", default="coarse")
    parser.add_argument("--cycles", type=int, default=800)
    parser.add_argument("--stiffer", type=float, default=STIFFER)
    parser.add_argument("--steps-per-cycle", type=int, default=200)
    parser.add_argument("--lumped-dt", type=float, default=5e-7)
    parser.add_argument("--integrator", default="reduced", choices=("reduced", "explicit"))
    parser.add_argument("--levels", default=None,
                        help="comma-separated fractions of A_th: the normal motion alone")
    args = parser.parse_args()
    cases = CASES if args.levels is None else tuple(
        (f"normal only, {level:g} A_th", level, None, 0.0, {})
        for level in map(float, args.levels.split(",")))
    probe = stiff_scene(args.mesh, args.cycles, args.stiffer)
    a_th = threshold(probe)
    print(f"Stiff block (E x {args.stiffer:g}), fem.penalty {probe.fem.penalty:.4g} N/m, "
          f"contact.k_n {probe.normal_stiffness:.4g} N/m, A_th = {a_th:.3g} m; mesh {args.mesh}, "
          f"{args.integrator} at {fe_step(args, probe.vibration.f):.3g} s, lumped at "
          f"{args.lumped_dt:g} s; "
          f"T = t_on + {args.cycles} cycles, the last {AVERAGED} averaged; {platform.node()}")
    print()
    print("| case | A_n (m) | phase | k_v | lumped F_dv/F_d0 | FE F_dv/F_d0 | FE - lumped | "
          "loss lumped | loss FE | N lumped (N) | N FE (N) | FE judged | FE answered by | "
          "FE wall (s) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for name, level, phase, k_v, extra in cases:
        keys = {"vibration.normal_amplitude": level * a_th, "vibration.k_v": k_v,
                "time.dt": args.lumped_dt, **extra}
        if phase is not None:
            keys["vibration.normal_phase_deg"] = phase
        lumped_scene = stiff_scene(args.mesh, args.cycles, args.stiffer, **keys)
        try:
            _, lumped = solve(lumped_scene.with_values({"time.method": "transient"}))
        except Exception as trouble:     # a failed run is a row of the table
            print(f"| {name} | {level * a_th:.3g} | {phase or 0:g} | {k_v:g} | "
                  f"lumped failed: {trouble} |", flush=True)
            continue
        fe_scene = lumped_scene.with_values(
            {"time.dt": fe_step(args, lumped_scene.vibration.f), "fem.integrator": args.integrator})
        start = time.perf_counter()
        try:
            result = run_fe(fe_scene)
        except Exception as trouble:     # a refused or failed run is a row of the table
            print(f"| {name} | {level * a_th:.3g} | {phase or 0:g} | {k_v:g} | "
                  f"{lumped['F_dv_over_F_d0']:.4f} | failed: {trouble} |")
            continue
        wall = time.perf_counter() - start
        fe = answer_ratio(result, fe_scene)
        info = result.info
        answered = info.get("periodic", {}).get("method", "stepped")
        print(f"| {name} | {level * a_th:.3g} | {phase or 0:g} | {k_v:g} | "
              f"{lumped['F_dv_over_F_d0']:.4f} | {fe:.4f} | "
              f"{(fe - lumped['F_dv_over_F_d0']) / abs(lumped['F_dv_over_F_d0']):+.2%} | "
              f"{lumped['contact_loss_fraction']:.3f} | {info['contact_loss_fraction']:.3f} | "
              f"{lumped['normal_force_min']:.3g}-{lumped['normal_force_max']:.3g} | "
              f"{info['normal_force_min']:.3g}-{info['normal_force_max']:.3g} | "
              f"{info['F_n_kind']} | {answered} | {wall:.1f} |", flush=True)


if __name__ == "__main__":
    main()
