"""The FE model against the lumped one with the base moving along Z (docs/validation.md,
"A base moving along Z").

The paper's block (the longitudinal scene, 0.5 kg, contact-plane drive) made
``--stiffer`` times stiffer (body.E x 100 by default), so that its own compliance,
which the lumped body lacks, does not dominate: the FE penalty fem.penalty is fixed
at the default block's (10 E A / L_z at E = 209 GPa) and the lumped contact.k_n
matched to the stiff block's bounce on it (core/bounce.py, the bar on the spring: 3%
below the penalty at E x 100). At E x 100 the reduced model's steady cycle of the
block unheld is unstable at 100-250 steps a cycle, with or without the normal
motion, and its stepped runs drift: docs/validation.md's first table is at --stiffer
10. Held (--hold), its steady cycle is stable at E x 100 too: docs/validation.md
"Stiff enough", --stiffer 100 --contact-damping modal --zeta-n 0.05 --hold
--steps-per-cycle 400 --lumped-dt 1.25e-7 [--levels ... --kv 6|0 [--phase 90]]. Cases (A_th: the
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
        --hold --steps-per-cycle 400 --lumped-dt 1.25e-7, with and without --levels
        ... --kv 6|0: each model within 0.3% of its converged answer, --converge below)
    .venv/bin/python benchmarks/fe_normal_vs_lumped.py --stiffer 1 --integrator explicit
        --levels 0.6,0.8,0.95,1.012
        (the normal motion alone, k_v = 0 (``--kv``), at those fractions of A_th; the
        explicit FE run at the lumped time.dt: docs/validation.md's paper's-block table)

    .venv/bin/python benchmarks/fe_normal_vs_lumped.py --stiffer 10 --contact-damping modal
        --zeta-n 0.05 --hold --levels 1.05 --kv 6|0 --converge 100,200,400,800,1600
        --lumped-dt 1e-6
        (the step convergence: each model at each step, the lumped step halved with the
        FE one, every FE step against every lumped one, each model's Richardson limit)
    .venv/bin/python benchmarks/fe_normal_vs_lumped.py --stiffer 10 --contact-damping modal
        --zeta-n 0.05 --hold --shift --levels 1.02,1.035,1.05,1.1 --kv 6|0
        --steps-per-cycle 400 --lumped-dt 1.25e-7
        (each model's own contact-loss threshold, found by bisection, and the rows
        compared at equal A_n over it, at equal contact-loss fraction, and as a shift of
        the lumped curve along A_n)

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


def richardson(answers):
    """The limit of three answers at steps h, h/2, h/4 and the observed order p:
    p = log2((a1 - a2) / (a2 - a3)), limit a3 + (a3 - a2) / (2^p - 1) (Richardson
    extrapolation; None where the differences do not shrink monotonically)."""
    a1, a2, a3 = answers[-3:]
    if (a1 - a2) * (a2 - a3) <= 0.0 or abs(a2 - a3) >= abs(a1 - a2):
        return None, None
    p = math.log2((a1 - a2) / (a2 - a3))
    return a3 + (a3 - a2) / (2.0 ** p - 1.0), p


def lumped_answer(args, posed, a_th, level, k_v, dt=None) -> dict:
    """The lumped model's summary at ``level`` A_th (phase 0, vibration.k_v ``k_v``),
    stepped at ``dt`` (--lumped-dt)."""
    keys = {"vibration.normal_amplitude": level * a_th, "vibration.k_v": k_v,
            "time.dt": dt or args.lumped_dt, "time.method": "transient"}
    return solve(stiff_scene(args.mesh, args.cycles, args.stiffer, **posed, **keys))[1]


def fe_answer(args, posed, held, a_th, level, k_v, steps=None):
    """The FE model's F_dv/F_d0 and run info at ``level`` A_th (phase 0, k_v ``k_v``) at
    ``steps`` a cycle (--steps-per-cycle)."""
    scene = stiff_scene(args.mesh, args.cycles, args.stiffer, **posed, **held,
                        **{"vibration.normal_amplitude": level * a_th, "vibration.k_v": k_v,
                           "fem.integrator": args.integrator})
    scene = scene.with_values(
        {"time.dt": 1.0 / ((steps or args.steps_per_cycle) * scene.vibration.f)})
    result = run_fe(scene)
    return answer_ratio(result, scene), result.info


def first_level(reached, low: float, high: float, tolerance: float = 5e-4) -> float:
    """The lowest level in [low, high] at which ``reached(level)`` holds (by bisection,
    to ``tolerance``; ``reached`` false at low and true at high)."""
    if reached(low) or not reached(high):
        raise ValueError(f"the level is not bracketed by {low:g} and {high:g}")
    while high - low > tolerance:
        middle = 0.5 * (low + high)
        low, high = (low, middle) if reached(middle) else (middle, high)
    return 0.5 * (low + high)


def shift(args, levels, posed, held, a_th) -> None:
    """Each model's own contact-loss threshold (the A_n / A_th at which the summed normal
    force's minimum over the steady cycle first reaches 0; for the FE model also where
    its first node opens) and, at each of ``levels``, the two models compared at equal
    A_n, at equal A_n over their own thresholds, at equal contact-loss fraction, and
    the lumped level at which the lumped body answers the FE's F_dv/F_d0 (the shift
    along A_n that would make the curves meet)."""
    k_v = args.kv

    def lumped_ratio(level):
        return lumped_answer(args, posed, a_th, level, k_v)

    def fe_ratio(level):
        return fe_answer(args, posed, held, a_th, level, k_v)

    own_lumped = first_level(lambda level: lumped_ratio(level)["normal_force_min"] <= 0.0,
                             0.9, 1.1)
    own_fe = first_level(lambda level: fe_ratio(level)[1]["normal_force_min"] <= 0.0,
                         0.9, 1.1)
    first_node = first_level(lambda level: fe_ratio(level)[1]["contact_loss_fraction"] > 0.0,
                             0.5, 1.1)
    print(f"k_v = {k_v:g}. Own thresholds (A_n / A_th, the summed N's minimum reaching 0): "
          f"lumped {own_lumped:.4f}, FE {own_fe:.4f} (FE / lumped - 1 = "
          f"{own_fe / own_lumped - 1.0:+.2%}); the FE's first node opens at {first_node:.4f}")
    print()
    print("| A_n / A_th | lumped F_dv/F_d0 (loss) | FE F_dv/F_d0 (loss) | FE - lumped | "
          "at equal A_n / own threshold: lumped, FE - lumped | at the FE's loss: lumped "
          "level, FE - lumped | lumped level answering the FE's F_dv/F_d0 (shift) |")
    print("|---|---|---|---|---|---|---|")
    for level in levels:
        lumped = lumped_ratio(level)
        fe, info = fe_ratio(level)
        a = lumped["F_dv_over_F_d0"]
        own = lumped_ratio(level * own_lumped / own_fe)["F_dv_over_F_d0"]
        fe_loss = info["contact_loss_fraction"]
        try:
            at_loss = first_level(
                lambda x: lumped_ratio(x)["contact_loss_fraction"] >= fe_loss, 0.95, 1.2)
            equal_loss = lumped_ratio(at_loss)["F_dv_over_F_d0"]
            loss_text = f"{at_loss:.4f}, {(fe - equal_loss) / abs(equal_loss):+.2%}"
        except ValueError as trouble:
            loss_text = str(trouble)
        try:      # the lumped F_dv/F_d0 falls with A_n above A_th (docs/validation.md)
            answering = first_level(lambda x: lumped_ratio(x)["F_dv_over_F_d0"] <= fe,
                                    level - 0.05, level + 0.05)
            shift_text = f"{answering:.4f} ({answering / level - 1.0:+.2%})"
        except ValueError as trouble:
            shift_text = str(trouble)
        print(f"| {level:g} | {a:.4f} ({lumped['contact_loss_fraction']:.3f}) | {fe:.4f} "
              f"({fe_loss:.3f}) | {(fe - a) / abs(a):+.2%} | {own:.4f}, "
              f"{(fe - own) / abs(own):+.2%} | {loss_text} | {shift_text} |", flush=True)


def converge(args, cases, posed, a_th, held) -> None:
    """Each --levels row at the FE steps a cycle of --converge and the lumped steps
    halved alongside (--lumped-dt at the first): each model run once per step, so that
    every FE step meets every lumped one (the row's diagonal halves both steps, its
    columns one model's alone), then each model's Richardson limit."""
    steps = [int(n) for n in args.converge.split(",")]
    lumped_dts = [args.lumped_dt * steps[0] / n for n in steps]
    for name, level, phase, k_v, extra in cases:
        keys = {"vibration.normal_amplitude": level * a_th, "vibration.k_v": k_v, **extra}
        if phase is not None:
            keys["vibration.normal_phase_deg"] = phase
        lumped, fe = [], []
        for dt in lumped_dts:
            scene = stiff_scene(args.mesh, args.cycles, args.stiffer, **posed, **keys,
                                **{"time.dt": dt, "time.method": "transient"})
            start = time.perf_counter()
            _, summary = solve(scene)
            lumped.append(summary["F_dv_over_F_d0"])
            print(f"{name}: lumped at {dt:.4g} s: {lumped[-1]!r} (out of contact "
                  f"{summary['contact_loss_fraction']:.3f}, N {summary['normal_force_min']:.3g}-"
                  f"{summary['normal_force_max']:.3g}; {time.perf_counter() - start:.0f} s)",
                  flush=True)
        for n in steps:
            scene = stiff_scene(args.mesh, args.cycles, args.stiffer, **posed, **keys,
                                **held, **{"fem.integrator": args.integrator})
            scene = scene.with_values({"time.dt": 1.0 / (n * scene.vibration.f)})
            start = time.perf_counter()
            result = run_fe(scene)
            fe.append(answer_ratio(result, scene))
            info = result.info
            print(f"{name}: FE at {n} steps a cycle: {fe[-1]!r} (out of contact "
                  f"{info['contact_loss_fraction']:.3f}, N {info['normal_force_min']:.3g}-"
                  f"{info['normal_force_max']:.3g}, {info['F_n_kind']}, "
                  f"{info.get('periodic', {}).get('method', 'stepped')}; "
                  f"{time.perf_counter() - start:.0f} s)", flush=True)
        print()
        print(f"{name}: FE - lumped, relative (rows: FE steps a cycle; columns: lumped step)")
        print()
        print("| FE \\ lumped | " + " | ".join(f"{dt:.3g} s: {a:.4f}" for dt, a in
                                               zip(lumped_dts, lumped)) + " |")
        print("|---" * (len(steps) + 1) + "|")
        for n, b in zip(steps, fe):
            print(f"| {n}: {b:.4f} | " + " | ".join(f"{(b - a) / abs(a):+.2%}" for a in lumped)
                  + " |")
        if len(steps) >= 3:
            limits = [richardson(answers) for answers in (lumped, fe)]
            for model, answers, (limit, order) in zip(("lumped", "FE"), (lumped, fe), limits):
                print(f"\n{model}: Richardson limit " + (
                    f"none (not monotone; the last two steps differ by "
                    f"{(answers[-1] - answers[-2]) / abs(answers[-2]):+.2%})" if limit is None
                    else f"{limit:.4f}, observed order {order:.2f}"))
            if None not in (limits[0][0], limits[1][0]):
                print(f"\nFE - lumped at the limits: "
                      f"{(limits[1][0] - limits[0][0]) / abs(limits[0][0]):+.2%}")
        print(flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mesh", default="coarse")
    parser.add_argument("--cycles", type=int, default=800)
    parser.add_argument("--stiffer", type=float, default=STIFFER)
    parser.add_argument("--steps-per-cycle", type=int, default=200)
    parser.add_argument("--lumped-dt", type=float, default=5e-7)
    parser.add_argument("--integrator", default="reduced", choices=("reduced", "explicit"))
    parser.add_argument("--levels", default=None,
                        help="comma-separated fractions of A_th, at k_v = --kv, phase --phase")
    parser.add_argument("--kv", type=float, default=0.0,
                        help="vibration.k_v of the --levels rows (0: the normal motion alone)")
    parser.add_argument("--phase", type=float, default=None,
                        help="vibration.normal_phase_deg of the --levels rows (90: elliptical)")
    parser.add_argument("--block", default="paper", choices=tuple(BLOCKS))
    parser.add_argument("--contact-damping", default="fe", choices=("fe", "lumped", "modal"))
    parser.add_argument("--zeta-n", type=float, default=None, help="contact.zeta_n")
    parser.add_argument("--hold", action="store_true",
                        help="FE: drive.attach = load-group, drive.holder = translating")
    parser.add_argument("--lumped-only", action="store_true",
                        help="the lumped model's columns alone (a fine scan of --levels)")
    parser.add_argument("--converge", default=None, metavar="N1,N2,N3",
                        help="the --levels rows at each FE --steps-per-cycle N_i, the lumped "
                             "model at --lumped-dt x N1 / N_i alongside: each model's answer "
                             "against its own step, every pairing, and Richardson's limit")
    parser.add_argument("--shift", action="store_true",
                        help="each model's own contact-loss threshold, and the --levels rows "
                             "(at --kv) compared at equal A_n over it, at equal contact-loss "
                             "fraction, and as a shift along A_n")
    args = parser.parse_args()
    label = "normal only" if args.kv == 0.0 else f"k_v = {args.kv:g}"
    if args.phase is not None:
        label += f", phase {args.phase:g} deg"
    cases = CASES if args.levels is None else tuple(
        (f"{label}, {level:g} A_th", level, args.phase, args.kv, {})
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
    if args.converge is not None:
        converge(args, cases, posed, a_th, held)
        return
    if args.shift:
        shift(args, [level for _, level, *_ in cases], posed, held, a_th)
        return
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
