"""The FE ball and pin against the lumped model on the paper's Fig 7 vibration
(docs/validation.md, "A ball and a pin against the lumped model").

Both shipped scenes hold their body in a tribometer's holder (drive.attach =
"load-group", drive.holder = "translating": the load and the drive on the top, which
translates without turning). The lumped body is rigid on one contact spring, the law's
k_t (contact.k_t, 80e6 N/m in scenes/ball.toml and scenes/pin.toml). The FE body rests
on its preload's patch, each node on its share k_t a_i / A_0 of that spring
(fe_model.patch_share), behind its own elastic compliance between its mass and the
patch, which the lumped body lacks. What the FE contact amounts to, as the lumped
body's one spring, is its tangential stiffness under the load the vibration puts on
it: a uniform inertial load Q = m a along X on the preloaded, held body with its
contact stuck (each patch node on its k_t a_i / A_0 in X and Y, on its penalty in Z),
over the centre of mass's displacement:

    k_FE = Q / delta_cm

and of the body alone (the patch's nodes held: the law's springs made rigid),
k_body, so that 1 / k_FE = 1 / k_t + 1 / k_body to the coupling of the two. For the
ball, k_body against Mindlin's no-slip stiffness of an elastic sphere on a rigid
flat, 8 G a / (2 - nu) (Johnson, Contact Mechanics, eq 7.41 with one body rigid),
a the Hertz radius (3 F_N R / 4 E*)^(1/3) (eq 4.22).

The lumped model (analytic, coupled stepper, the scene's time.dt and T) is run with
k_t and with k_FE. With --fe, the FE model too (time.method auto: the steady cycle by
shooting, stepped through T where it finds none): explicit at EXPLICIT_FRACTION of its
stable step, which resolves the contact's fastest motion (the reference); the
reduced model at REDUCED_STEP; and that on the same body RIGID_E times
stiffer (body.E; the penalty, which scales with E, too), which takes its compliance
out: what is left between that and the lumped k_t answer is the FE model's own (its
contact split over nodes, its holder, its reduction, its step). With --integrators,
one row a body of every integrator's answer and wall time (measured on the machine it
runs on) at the scene's time.dt, the explicit one at EXPLICIT_FRACTION of its stable
step.

With --steady, the held ball's steady answer (its orbit by shooting, time.method
"periodic") under the reduced integrator at each of STEADY_STEPS: F_dv/F_d0, the
wall time (the model from its cache, VIBROFRIC_CACHE, if an earlier run left it: run
twice to time the answer rather than the reduction), the contact iteration's estimated
contraction and whether it was accelerated (docs/fe-model.md, "How an implicit step
works"), the shooting's loop time and its time a step (its iterations a step are not
reported for a shooting: a stepped run's fe_info has them, iterations_mean).

    .venv/bin/python benchmarks/fe_body_vs_lumped.py [--mesh coarse] [--fe]
    .venv/bin/python benchmarks/fe_body_vs_lumped.py --integrators
    .venv/bin/python benchmarks/fe_body_vs_lumped.py --steady --mesh fine [--dt 5e-6]

prints markdown tables.
"""

import argparse
import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from vibrofric.analytic.solve import solve
from vibrofric.api import load_scene
from vibrofric.core.errors import NumericalError, Refusal
from vibrofric.fem import run_fe
from vibrofric.fem.model import fe_model
from vibrofric.fem.simulate import answer_ratio

BODIES = ("ball", "pin")
RIGID = 1e6   # k_t times this holds the patch's nodes: the body's compliance alone
RIGID_E = 100.0   # body.E times this: the body's compliance 100 times below the law's
INTEGRATORS = ("explicit", "implicit", "reduced", "auto")
EXPLICIT_FRACTION = 0.9   # of the model's stable step: the explicit integrator's time.dt
REDUCED_STEP = 1e-6       # s: the reduced integrator's time.dt in the comparison's table
STEADY_STEPS = (5e-6, 2.5e-6, 1e-6)   # s: the reduced integrator's, for --steady


def contact_stiffness(model, k_t: float) -> float:
    """Q / delta_cm along X of the preloaded body, its patch stuck on springs k_t a_i / A_0
    (X, Y) and its penalty (Z); Q a uniform acceleration's inertial load m_i a."""
    springs = np.zeros(model.dofs)
    patch = model.contact_nodes[model.in_contact0]
    share = model.area_share[model.in_contact0]
    springs[3 * patch] = springs[3 * patch + 1] = k_t * share
    springs[3 * patch + 2] = model.penalty_share[model.in_contact0]
    matrix = (model.disc.stiffness + sp.diags(springs)).tocsc()
    mass = model.disc.mass
    load = np.zeros(model.dofs)
    load[0::3] = mass[0::3]                  # a = 1 m/s^2 along X
    u = spla.spsolve(matrix, load)
    delta = np.dot(mass[0::3], u[0::3]) / mass[0::3].sum()
    return mass[0::3].sum() / delta


def mindlin_stiffness(scene) -> float:
    """8 G a / (2 - nu): an elastic sphere's no-slip tangential stiffness on a rigid flat."""
    body = scene.body
    e_star = body.E / (1.0 - body.nu ** 2)
    a = (3.0 * scene.contact.F_N * body.radius / (4.0 * e_star)) ** (1.0 / 3.0)
    return 8.0 * body.E / (2.0 * (1.0 + body.nu)) * a / (2.0 - body.nu)


def lumped(scene, k_t: float) -> float:
    _, summary = solve(scene.with_values({"contact.k_t": k_t}), "coupled")
    return summary["F_dv_over_F_d0"]


def fe_answer(scene, integrator: str, **values) -> str:
    """The FE answer as a table cell: F_dv/F_d0 (how: the orbit or stepped, wall time), or
    what stopped it."""
    start = time.perf_counter()
    try:
        result = run_fe(scene.with_values({"fem.integrator": integrator,
                                           "time.error_estimate": False,
                                           "fem.output_every": 0, **values}))
    except (NumericalError, Refusal) as error:
        return f"fails ({str(error)[:90]}...)"
    periodic = result.info.get("periodic") or {}
    how = "orbit" if periodic.get("converged") else "stepped"
    return f"{answer_ratio(result, scene):.4f} ({how}, {time.perf_counter() - start:.0f} s)"


def comparison(args) -> None:
    print("| body | patch nodes | k_t (law) | k_body (FE) | Mindlin 8Ga/(2-nu) | k_FE | "
          "lumped, k_t | lumped, k_FE | FE, explicit | FE, reduced | "
          f"FE, reduced, E x {RIGID_E:g} |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for name in BODIES:
        scene = load_scene(name, **{"fem.mesh": args.mesh})
        model = fe_model.build_model(scene, None)
        k_t = scene.contact.k_t
        k_fe = contact_stiffness(model, k_t)
        k_body = contact_stiffness(model, RIGID * k_t)
        mindlin = f"{mindlin_stiffness(scene):.3g}" if scene.body.shape == "ball" else "-"
        explicit = reduced = rigid = "-"
        if args.fe:
            explicit = fe_answer(scene, "explicit", **{"time.dt": explicit_step(model)})
            reduced = fe_answer(scene, "reduced", **{"time.dt": REDUCED_STEP})
            rigid = fe_answer(scene, "reduced", **{"body.E": RIGID_E * scene.body.E,
                                                   "time.dt": REDUCED_STEP})
        print(f"| {name} | {int(model.in_contact0.sum())} of {model.contact_nodes.size} | "
              f"{k_t:.3g} | {k_body:.3g} | {mindlin} | {k_fe:.3g} | {lumped(scene, k_t):.4f} | "
              f"{lumped(scene, k_fe):.4f} | {explicit} | {reduced} | {rigid} |")


def explicit_step(model) -> float:
    """EXPLICIT_FRACTION of the model's stable step, to 2 digits."""
    return float(f"{EXPLICIT_FRACTION * model.dt_stable:.2g}")


def integrators(args) -> None:
    print("| body | " + " | ".join(INTEGRATORS) + " |")
    print("|---|" + "---|" * len(INTEGRATORS))
    for name in BODIES:
        scene = load_scene(name, **{"fem.mesh": args.mesh})
        explicit_dt = explicit_step(fe_model.build_model(scene, None))
        cells = [fe_answer(scene, integrator,
                           **({"time.dt": explicit_dt} if integrator == "explicit" else {}))
                 for integrator in INTEGRATORS]
        cells[0] += f" at dt = {explicit_dt:g} s"
        print(f"| {name} | " + " | ".join(cells) + " |")


def steady(args) -> None:
    print("| mesh | time.dt | F_dv/F_d0 | wall | loop | a step | contraction | accelerated | "
          "shooting (Newton, cycles) |")
    print("|---|---|---|---|---|---|---|---|---|")
    scene = load_scene("ball", **{"fem.mesh": args.mesh})
    for dt in args.dt or STEADY_STEPS:
        start = time.perf_counter()
        try:
            result = run_fe(scene.with_values({"fem.integrator": "reduced", "time.dt": dt,
                                               "time.method": "periodic",
                                               "time.error_estimate": False,
                                               "fem.output_every": 0}))
        except (NumericalError, Refusal) as error:
            print(f"| {args.mesh} | {dt:g} | fails ({str(error)[:120]}...) |||||||")
            continue
        info, wall = result.info, time.perf_counter() - start
        shooting = info.get("periodic") or {}
        print(f"| {args.mesh} | {dt:g} | {answer_ratio(result, scene):.4f} | {wall:.1f} s | "
              f"{info['loop_time_s']:.1f} s | {1e3 * info['loop_time_s'] / info['steps']:.1f} ms | "
              f"{info['contraction_bound']:.2f} | {info['contact_accelerated']} | "
              f"{shooting.get('newton_iterations')}, {shooting.get('cycles_integrated')} |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mesh", default="coarse")
    parser.add_argument("--fe", action="store_true", help="run the FE model too")
    parser.add_argument("--integrators", action="store_true",
                        help="instead: every integrator on each body")
    parser.add_argument("--steady", action="store_true",
                        help="instead: the held ball's steady answer, reduced, at STEADY_STEPS")
    parser.add_argument("--dt", type=float, action="append",
                        help="with --steady: this time.dt (s) instead (repeatable)")
    args = parser.parse_args()
    if args.steady:
        steady(args)
    elif args.integrators:
        integrators(args)
    else:
        comparison(args)


if __name__ == "__main__":
    main()
