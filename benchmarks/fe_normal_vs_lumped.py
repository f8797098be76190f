"""The FE model against the lumped one with the base moving along Z (docs/validation.md,
"A base moving along Z").

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

Losing contact, the block's pitching and its contact's damping decide which orbit each
model settles on (docs/validation.md):

    --block low   the block 5 mm tall on a footprint twice as long and wide (0.06 x 0.08
                  x 0.005 m, the same 0.5 kg: 20,800 kg/m^3): the pitching moment of
                  the friction at z = 0 against the inertia at mid-height, and the
                  pressure swing it makes across the face, 20 times smaller
    --contact-damping lumped
                  fem.damping = c_n / k_pen, c_n = 2 zeta_n sqrt(k_n m) the lumped
                  contact's dashpot (analytic/normal.py contact_damping): each node's
                  penalty dashpot beta k_pen,i then sums to the lumped one (the FE
                  default's damping ratio is ~3e-3, the lumped default 0.02)
    --contact-damping modal
                  fem.damping = c_n / k_n: the FE damping beta (K + K_pen) damps each
                  mode at beta w / 2, so the FE bounce (w_b = sqrt(k_n / m), k_n matched
                  to it) at zeta_n, as the lumped body's. "lumped" damps it at
                  zeta_n k_n / k_pen instead: the same on the low block (k_n = 0.99
                  k_pen), 0.74 zeta_n on the paper's block at E x 10, whose own
                  compliance is a quarter of its bounce's
    --zeta-n      contact.zeta_n, the lumped contact's damping ratio (0.02)
    --hold        the FE block held as the lumped body is: drive.attach = "load-group",
                  drive.holder = "translating" (the drive and load at its top face, which
                  moves as one rigid translation: fem/model/holder.py), so that it
                  cannot pitch or rock; the lumped side is unchanged (it has no
                  attachment point and no rotation)

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
        [--block paper|low] [--contact-damping fe|lumped|modal] [--zeta-n 0.02]
        [--lumped-only] [--hold]
        (docs/validation.md's tables: --stiffer 10 --block low --contact-damping
        lumped [--zeta-n 0.05], with and without --levels ... --kv 6; its scan of
        the lumped orbits: --levels 1.0,1.002,...,1.03 --kv 6 --lumped-only; the
        held paper's block: --stiffer 10 --contact-damping modal --zeta-n 0.05
        --hold, with and without --levels ... --kv 6|0)
    .venv/bin/python benchmarks/fe_normal_vs_lumped.py --stiffer 1 --integrator explicit
        --levels 0.6,0.8,0.95,1.012
        (the normal motion alone, k_v = 0 (``--kv``), at those fractions of A_th; the
        explicit FE run at the lumped time.dt: docs/validation.md's paper's-block table)

prints a markdown table: each model's F_dv/F_d0, their relative difference, each
one's contact_loss_fraction and summed normal force's range, and the FE judgement.
"""

import argparse
import math
import platform
import time

from vibrofric.analytic.normal import contact_damping
from vibrofric.analytic.solve import solve
from vibrofric.api import load_scene
from vibrofric.core.bounce import bounce_stiffness, default_penalty
from vibrofric.fem import run_fe
from vibrofric.fem.simulate import answer_ratio

STIFFER = 100.0
BLOCKS = {"paper": (0.03, 0.04, 0.053), "low": (0.06, 0.08, 0.005)}   # body.size (m)
AVERAGED = 20
# The FE block held as the lumped body is (--hold): pulled and pressed at its top face,
# which translates without turning (fem/model/holder.py).
HELD = {"drive.attach": "load-group", "drive.holder": "translating"}
CASES = (("no normal motion", 0.0, None, 6.0, {}),
         ("in contact", 0.45, None, 6.0, {}),
         ("elliptical", 0.45, 90.0, 6.0, {}),
         ("normal only", 0.45, None, 0.0, {}),
         ("contact lost", 1.012, None, 6.0, {}))


def stiff_scene(mesh: str, cycles: int, stiffer: float = STIFFER, block: str = "paper",
                damping: str = "fe", **keys):
    """The longitudinal scene on the block ``stiffer`` times stiffer, penalty and lumped
    k_n matched; ``block`` names its size (BLOCKS, the same mass), ``damping`` "lumped"
    sets fem.damping so that the FE contact's dashpots sum to the lumped one's
    (c_n = 2 contact.zeta_n sqrt(k_n m)), "modal" so that the FE bounce mode is damped at
    contact.zeta_n (fem.damping = c_n / k_n)."""
    base = load_scene("longitudinal")
    body = base.body
    E = stiffer * body.E
    size = BLOCKS[block]
    penalty = default_penalty(body.E, body.size)     # the paper's block's, for every block
    rho = body.mass / math.prod(size)
    k_n = bounce_stiffness(body.mass, E, rho, size, penalty)
    f, t_on = base.vibration.f, base.vibration.t_on
    values = {"body.E": E, "body.size": list(size), "fem.penalty": penalty,
              "contact.k_n": k_n, "fem.mesh": mesh,
              "fem.integrator": "reduced", "time.T": t_on + cycles / f,
              "time.average_cycles": AVERAGED, "time.method": "auto",
              "time.error_estimate": False, "fem.output_every": 0, **keys}
    scene = load_scene("longitudinal", **values)
    if damping == "lumped":
        scene = scene.with_values({"fem.damping": contact_damping(scene) / penalty})
    elif damping == "modal":
        scene = scene.with_values({"fem.damping": contact_damping(scene) / scene.normal_stiffness})
    return scene


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
                        help="comma-separated fractions of A_th, at k_v = --kv, phase 0")
    parser.add_argument("--kv", type=float, default=0.0,
                        help="vibration.k_v of the --levels rows (0: the normal motion alone)")
    parser.add_argument("--block", default="paper", choices=tuple(BLOCKS))
    parser.add_argument("--contact-damping", default="fe", choices=("fe", "lumped", "modal"))
    parser.add_argument("--zeta-n", type=float, default=None, help="contact.zeta_n")
    parser.add_argument("--hold", action="store_true",
                        help="FE: drive.attach = load-group, drive.holder = translating")
    parser.add_argument("--lumped-only", action="store_true",
                        help="the lumped model's columns alone (a fine scan of --levels)")
    args = parser.parse_args()
    label = "normal only" if args.kv == 0.0 else f"k_v = {args.kv:g}"
    cases = CASES if args.levels is None else tuple(
        (f"{label}, {level:g} A_th", level, None, args.kv, {})
        for level in map(float, args.levels.split(",")))
    posed = {"block": args.block, "damping": args.contact_damping}
    if args.zeta_n is not None:
        posed["contact.zeta_n"] = args.zeta_n
    probe = stiff_scene(args.mesh, args.cycles, args.stiffer, **posed)
    a_th = threshold(probe)
    held = HELD if args.hold else {}
    print(f"Block {list(probe.body.size)} m (E x {args.stiffer:g}"
          f"{', held at its top face' if args.hold else ''}), fem.damping "
          f"{probe.fem.damping:.4g} s (0: its default), contact.zeta_n "
          f"{probe.contact.zeta_n:g}, fem.penalty {probe.fem.penalty:.4g} N/m, "
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
        lumped_scene = stiff_scene(args.mesh, args.cycles, args.stiffer, **posed, **keys)
        try:
            _, lumped = solve(lumped_scene.with_values({"time.method": "transient"}))
        except Exception as trouble:     # a failed run is a row of the table
            print(f"| {name} | {level * a_th:.3g} | {phase or 0:g} | {k_v:g} | "
                  f"lumped failed: {trouble} |", flush=True)
            continue
        if args.lumped_only:
            print(f"| {name} | {level * a_th:.3g} | {phase or 0:g} | {k_v:g} | "
                  f"{lumped['F_dv_over_F_d0']:.4f} | | | {lumped['contact_loss_fraction']:.3f} | "
                  f"| {lumped['normal_force_min']:.3g}-{lumped['normal_force_max']:.3g} |", flush=True)
            continue
        fe_scene = lumped_scene.with_values(
            {"time.dt": fe_step(args, lumped_scene.vibration.f), "fem.integrator": args.integrator,
             **held})
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
