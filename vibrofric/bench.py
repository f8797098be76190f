"""``vibrofric bench``: wall time against error, every method side by side in one run.

The scene is the paper's Fig 7 case (scenes/longitudinal.toml: k_v = 6, 0.3 s
simulated). Each method's answer, F_dv/F_d0, is compared with a converged
reference of the *same* model:

- the analytic stepper (paper and exact Dahl updates, several dt) against the
  exact-update stepper at plan.analytic_reference_dt (100x below the finest
  step measured; its own error is below 1e-6);
- the FE model (integrators x dt, and mesh levels) against the FE reference
  plan.fe_reference: the explicit integrator at the smallest step on the
  finest mesh of the plan. Its own time-step error is bounded by the gap to
  the explicit run at twice its step (a row of the table);

and, separately, every FE answer against the analytic reference: the lumped
model's own error (the block's compliance and rocking, docs/model.md).

It also measures how the cost grows, on a short vibrated run (GROWTH: the
vibration from 1 ms, F_dv over 20 cycles): the time loop's wall time per
simulated second against DOFs over the mesh levels (explicit at each level's
own stable step, implicit and reduced at a fixed step), and against
simulated time on one mesh, each with the fitted power-law exponent. The
set-up (the model's assembly, the factorization, the reduction) is reported
beside the loop: it is paid once a run, so it is not part of either slope.

Timings are of one core: the bench runs everything in this process, one
run after another, after compiling every loop once (warm_up).
"""

import math
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from . import scene as scene_module

SCENE = Path(__file__).resolve().parent / "scenes" / "longitudinal.toml"  # package data
EXAMPLE_LAW = Path(__file__).resolve().parent.parent / "examples" / "laws" / "maxwell_slip.py"

# The friction laws the bench compares on the same scene: (label, contact.law, its parameters).
LAWS = (("Dahl, i = 1", "dahl", {}),
        ("Dahl, i = 0.5", "dahl", {"dahl_exponent": 0.5}),
        ("Dahl, i = 2", "dahl", {"dahl_exponent": 2.0}),
        ("LuGre, F_s = 1.2 F_c, v_s = 2 mm/s", "lugre", {"F_s": 6.6, "v_s": 2e-3}))
if EXAMPLE_LAW.exists():  # a checkout; an installed package has no examples/
    LAWS += (("Maxwell-slip (examples/laws)", str(EXAMPLE_LAW), {}),)

# The short run the cost growth is measured on: vibration from 1 ms, F_dv over 20 cycles.
GROWTH = {"vibration.t_on": 0.001, "time.average_cycles": 20}


@dataclass(frozen=True)
class Plan:
    """What one bench run measures."""

    T: float                   # s simulated (the Fig 7 scene)
    analytic_dts: tuple        # steps of the analytic stepper, both updates
    analytic_reference_dt: float
    fe_cases: tuple            # (integrator, mesh, dt): speed against error
    fe_reference: tuple        # (integrator, mesh, dt) of the converged FE reference
    dofs_cases: tuple          # (integrator, ((mesh, dt), ...)): cost against DOFs
    dofs_T: float              # s simulated in the DOFs cases
    time_cases: tuple          # (integrator, mesh, dt, (T, ...)): cost against simulated time
    laws: tuple = ()           # (label, law, parameters): a row per friction law (LAWS)
    law_dt: float = 1e-6       # the analytic stepper's step in the law rows
    law_fe: tuple = ()         # (integrator, mesh, dt) of the law rows' FE run; () for none
    breakdown_cases: tuple = ()  # (integrator, mesh, dt): a step's parts against the roofline
    mesh_study: tuple = ()     # (integrator, dt, (level, ...) coarse to fine): the spatial error
    periodic: bool = False     # the periodic solver against the transient (periodic_bench.py)


_MESH_STEPS = (("tiny", 2e-6), ("coarse", 1e-6), ("medium", 5e-7))  # explicit: below each stable step

# The mesh study's levels, coarse to fine: element edges ~13, 7.5, 5 and 3.8 mm on the
# default block (FULL adds "fine", 1.9 mm).
MESH_LEVELS = ("2x3x4", "coarse", "6x8x10", "medium")

QUICK = Plan(
    T=0.3,
    analytic_dts=(1e-5, 4e-6, 2e-6, 1e-6),
    analytic_reference_dt=1e-8,
    fe_cases=(("explicit", "coarse", 1e-6),
              ("implicit", "coarse", 2e-5), ("implicit", "coarse", 1e-5),
              ("reduced", "coarse", 2e-5), ("reduced", "coarse", 1e-5),
              ("reduced", "coarse", 5e-6)),
    fe_reference=("explicit", "coarse", 5e-7),
    dofs_cases=(("explicit", _MESH_STEPS),
                ("implicit", tuple((mesh, 1e-5) for mesh, _ in _MESH_STEPS)),
                ("reduced", tuple((mesh, 1e-5) for mesh, _ in _MESH_STEPS))),
    dofs_T=0.01,
    time_cases=(("implicit", "coarse", 1e-5, (0.01, 0.02, 0.04)),
                ("reduced", "coarse", 1e-5, (0.02, 0.04, 0.08, 0.16))),
    laws=LAWS,
    law_fe=("reduced", "coarse", 1e-5),
    breakdown_cases=(("explicit", "coarse", 1e-6), ("implicit", "coarse", 1e-5),
                     ("reduced", "coarse", 1e-5)),
    mesh_study=("reduced", 1e-5, MESH_LEVELS),
    periodic=True,
)

FULL = Plan(
    T=0.3,
    analytic_dts=(2e-5, 1e-5, 4e-6, 2e-6, 1e-6, 5e-7),
    analytic_reference_dt=5e-9,
    fe_cases=QUICK.fe_cases + (("explicit", "coarse", 5e-7), ("implicit", "coarse", 5e-6),
                               ("reduced", "coarse", 2.5e-6),
                               ("explicit", "medium", 5e-7), ("reduced", "medium", 1e-5)),
    fe_reference=("explicit", "medium", 2.5e-7),
    dofs_cases=(("explicit", _MESH_STEPS),
                ("implicit", tuple((mesh, 1e-5) for mesh, _ in _MESH_STEPS)),
                ("reduced", tuple((mesh, 1e-5) for mesh, _ in _MESH_STEPS) + (("fine", 1e-5),))),
    dofs_T=0.01,
    time_cases=QUICK.time_cases[:1] + (("reduced", "coarse", 1e-5, (0.02, 0.04, 0.08, 0.16, 0.32)),),
    laws=LAWS,
    law_fe=("reduced", "coarse", 1e-5),
    breakdown_cases=QUICK.breakdown_cases + (("explicit", "medium", 5e-7),
                                             ("reduced", "medium", 1e-5)),
    mesh_study=("reduced", 1e-5, MESH_LEVELS + ("fine",)),
    periodic=True,
)


@dataclass
class Measurement:
    method: str                # "analytic paper", "FE explicit", ...
    setting: str               # "dt = 1e-6", "coarse, dt = 1e-5"
    dofs: int                  # 0 for the analytic stepper
    wall_s: float              # the whole run
    ratio: float               # F_dv / F_d0
    loop_s: float = math.nan   # FE: the time loop alone
    setup_s: float = math.nan  # FE: the model, the factorization, the reduction
    error: float = math.nan    # |ratio - reference| / reference of the same model
    vs_analytic: float = math.nan  # (ratio - analytic reference) / analytic reference
    steps: int = 0             # FE: steps run
    iterations: float = 0.0    # FE implicit, reduced: mean contact iterations a step


def base_scene(plan: Plan):
    return scene_module.load(SCENE, [f"time.T={plan.T}", "fem.output_every=0"])


def measure_analytic(scene, update: str, dt: float, repeats: int = 3) -> Measurement:
    """The analytic stepper's answer and its best wall time of ``repeats`` runs."""
    from .analytic.run import run

    case = scene.with_values({"contact.update": update, "time.dt": dt})
    best = min((run(case)[1] for _ in range(repeats)), key=lambda s: s["wall_time_s"])
    return Measurement(f"analytic {update}", f"dt = {dt:g}", 0, best["wall_time_s"],
                       best["F_dv_over_F_d0"])


@dataclass
class LawRow:
    """One friction law on the bench's scene: the analytic stepper against its own
    converged reference, and (if the plan asks) an FE run against that reference."""

    label: str
    analytic: Measurement
    reference: float            # F_dv/F_d0 of the stepper at plan.analytic_reference_dt
    fe: Measurement | None = None


def measure_law(scene, plan: Plan, label: str, law: str, parameters: dict) -> LawRow:
    """The law's row: the stepper at plan.law_dt (best of 3, after a first run that
    compiles it), its reference, the FE run."""
    from .analytic.run import run

    case = scene.with_law(law, parameters)
    reference = run(case.with_values({"time.dt": plan.analytic_reference_dt}))[1]["F_dv_over_F_d0"]
    stepped = case.with_values({"time.dt": plan.law_dt})
    best = min((run(stepped)[1] for _ in range(3)), key=lambda s: s["wall_time_s"])
    analytic = Measurement(f"analytic {label}", f"dt = {plan.law_dt:g}", 0, best["wall_time_s"],
                           best["F_dv_over_F_d0"])
    analytic.error = relative(analytic.ratio, reference)
    row = LawRow(label, analytic, reference)
    if plan.law_fe:
        warm_up(case, [plan.law_fe[0]])  # each law's loops are compiled for it
        row.fe = measure_fe(case, *plan.law_fe)
        row.fe.vs_analytic = relative(row.fe.ratio, reference)
    return row


def measure_fe(scene, integrator: str, mesh: str, dt: float, values=None) -> Measurement:
    """One FE run of ``scene`` with the integrator, mesh level and step (and ``values``),
    with its whole set-up (no reduction kept from an earlier run)."""
    from .analytic.summary import summarize
    from .fem import reduction, run_fe

    reduction.forget()
    case = scene.with_values({"fem.integrator": integrator, "fem.mesh": mesh, "time.dt": dt,
                              **(values or {})})
    start = time.perf_counter()
    result = run_fe(case)
    wall = time.perf_counter() - start
    summary = summarize(result.series, case, wall)
    info = result.info
    return Measurement(f"FE {integrator}", f"{mesh}, dt = {dt:g}", info["dofs"], wall,
                       summary["F_dv_over_F_d0"], info["loop_time_s"], info["setup_time_s"],
                       steps=info["steps"], iterations=info.get("iterations_mean", 0.0))


@dataclass
class Breakdown:
    """One integrator's step in parts (fem.step_breakdown), from a measured run."""

    integrator: str
    setting: str
    step_s: float               # measured: the run's loop time over its steps
    parts: list                 # step_breakdown.Part

    @property
    def bound(self) -> float:
        return sum(part.bound for part in self.parts)


def element_size(level: str) -> float:
    """m: the mean element edge of a mesh level on the bench's block, (volume / elements)^(1/3)."""
    from .meshes import block

    return (math.prod(block.DEFAULT_SIZE) / math.prod(block.level_counts(level))) ** (1.0 / 3.0)


def richardson(h, values) -> tuple:
    """(f_0, p, uncertainty): the mesh-converged value of f(h) = f_0 + C h^p from the last
    three levels (h decreasing), its observed order p, and the uncertainty of f_0.

    p solves (f_1 - f_2) / (f_2 - f_3) = (h_1^p - h_2^p) / (h_2^p - h_3^p) (bisection on
    [0.1, 8]; nan if the differences change sign: not yet in the asymptotic range);
    f_0 = f_3 - (f_2 - f_3) h_3^p / (h_2^p - h_3^p). The uncertainty is Roache's grid
    convergence index on the finest level, 1.25 |f_3 - f_0|.
    """
    (h1, h2, h3), (f1, f2, f3) = h[-3:], values[-3:]
    observed = (f1 - f2) / (f2 - f3) if f2 != f3 else math.nan
    if not observed > 0.0:
        return math.nan, math.nan, math.nan

    def mismatch(p):
        return (h1 ** p - h2 ** p) / (h2 ** p - h3 ** p) - observed

    low, high = 0.1, 8.0
    if mismatch(low) * mismatch(high) > 0.0:
        return math.nan, math.nan, math.nan
    for _ in range(100):
        mid = 0.5 * (low + high)
        low, high = (mid, high) if mismatch(low) * mismatch(mid) > 0.0 else (low, mid)
    p = 0.5 * (low + high)
    f0 = f3 - (f2 - f3) * h3 ** p / (h2 ** p - h3 ** p)
    return f0, p, 1.25 * abs(f3 - f0)


@dataclass
class MeshStudy:
    """F_dv/F_d0 on successively finer meshes, one integrator and step."""

    integrator: str
    dt: float
    runs: list                  # Measurement per level, coarse to fine
    sizes: list                 # element_size per level, m

    @property
    def converged(self) -> tuple:
        """richardson() of the runs."""
        return richardson(self.sizes, [run.ratio for run in self.runs])


def measure_breakdown(scene, integrator: str, mesh: str, dt: float) -> Breakdown:
    """The step of a run of the bench's scene (the faster of two runs), in parts
    (fem.step_breakdown)."""
    from mpi4py import MPI

    from .fem import integrators
    from .fem.model import build_model
    from .fem.step_breakdown import breakdown

    run = min((measure_fe(scene, integrator, mesh, dt) for _ in range(2)),
              key=lambda m: m.loop_s / m.steps)
    case = scene.with_values({"fem.integrator": integrator, "fem.mesh": mesh, "time.dt": dt})
    prepared = integrators.select(case)(case, build_model(case, MPI.COMM_SELF))
    step_s = run.loop_s / run.steps
    return Breakdown(integrator, run.setting, step_s, breakdown(prepared, step_s, run.iterations))


def warm_up(scene, integrators) -> None:
    """Compile every integrator's loop once (numba caches it on disk) so that the timings
    are of the runs: a 5 ms run on the one-element mesh."""
    for integrator in integrators:
        measure_fe(scene, integrator, "tiny", 1e-6,
                   {"vibration.t_on": 0.0, "time.T": 0.005, "time.average_cycles": 4})


def fitted_exponent(x, y) -> float:
    """The slope p of log y = p log x + c, least squares."""
    return float(np.polyfit(np.log(x), np.log(y), 1)[0])


def relative(value: float, reference: float) -> float:
    return (value - reference) / abs(reference)


def bench(plan: Plan, progress=print) -> dict:
    """Run every measurement of the plan; return what markdown() and plot() show."""
    scene = base_scene(plan)
    progress(f"analytic reference (exact update, dt = {plan.analytic_reference_dt:g})")
    analytic_reference = measure_analytic(scene, "exact", plan.analytic_reference_dt, repeats=1).ratio

    rows = []
    for update in ("paper", "exact"):
        for dt in plan.analytic_dts:
            m = measure_analytic(scene, update, dt)
            m.error = m.vs_analytic = relative(m.ratio, analytic_reference)
            rows.append(m)

    integrators = sorted({case[0] for case in plan.fe_cases + (plan.fe_reference,)})
    progress("compiling the FE loops")
    warm_up(scene, integrators)
    progress(f"FE reference: {plan.fe_reference}")
    fe_reference = measure_fe(scene, *plan.fe_reference)
    fe_reference.error = 0.0
    fe_reference.vs_analytic = relative(fe_reference.ratio, analytic_reference)
    for case in plan.fe_cases:
        m = measure_fe(scene, *case)
        progress(f"FE {case}: {m.wall_s:.1f} s")
        m.error = relative(m.ratio, fe_reference.ratio)
        m.vs_analytic = relative(m.ratio, analytic_reference)
        rows.append(m)

    growth = []
    short = dict(GROWTH, **{"time.T": plan.dofs_T})
    for integrator, steps in plan.dofs_cases:
        progress(f"cost against DOFs: {integrator}")
        points = [measure_fe(scene, integrator, mesh, dt, short) for mesh, dt in steps]
        progress(f"  {', '.join(f'{p.wall_s:.1f}' for p in points)} s")
        growth.append(("DOFs", integrator, points,
                       [p.dofs for p in points], [p.loop_s for p in points]))
    for integrator, mesh, dt, spans in plan.time_cases:
        progress(f"cost against simulated time: {integrator}")
        points = [measure_fe(scene, integrator, mesh, dt, dict(GROWTH, **{"time.T": T}))
                  for T in spans]
        progress(f"  {', '.join(f'{p.wall_s:.1f}' for p in points)} s")
        growth.append(("simulated time", integrator, points, list(spans),
                       [p.loop_s for p in points]))
    growth = [(axis, integrator, points, x, y, fitted_exponent(x, y))
              for axis, integrator, points, x, y in growth]
    mesh = None
    if plan.mesh_study:
        integrator, dt, levels = plan.mesh_study
        progress(f"mesh study: {integrator}, dt = {dt:g}, {', '.join(levels)}")
        mesh = MeshStudy(integrator, dt, [measure_fe(scene, integrator, level, dt)
                                          for level in levels],
                         [element_size(level) for level in levels])
    breakdowns = []
    for case in plan.breakdown_cases:
        progress(f"step breakdown: {case}")
        breakdowns.append(measure_breakdown(scene, *case))
    laws = []
    for label, law, parameters in plan.laws:
        progress(f"friction law: {label}")
        laws.append(measure_law(scene, plan, label, law, parameters))
    periodic = None
    if plan.periodic:
        from . import periodic_bench

        progress("periodic steady state against the transient")
        periodic = periodic_bench.measure()
    return {"plan": plan, "analytic_reference": analytic_reference, "fe_reference": fe_reference,
            "rows": rows, "growth": growth, "laws": laws, "breakdowns": breakdowns,
            "mesh": mesh, "periodic": periodic}


def markdown(result: dict) -> str:
    """The bench as Markdown: speed against error, then the cost growth."""
    plan, fe_ref = result["plan"], result["fe_reference"]
    lines = [
        f"Fig 7 scene (longitudinal, k_v = 6, {plan.T:g} s simulated), one core.",
        f"Analytic reference: the exact update at dt = {plan.analytic_reference_dt:g} s, "
        f"F_dv/F_d0 = {result['analytic_reference']:.5f}. FE reference: {fe_ref.method[3:]}, "
        f"{fe_ref.setting} s ({fe_ref.dofs} DOFs, {fe_ref.wall_s:.3g} s wall), "
        f"F_dv/F_d0 = {fe_ref.ratio:.5f}, {fe_ref.vs_analytic:+.2%} from the analytic reference.",
        "",
        "| method | setting | DOFs | wall s | set-up s | F_dv/F_d0 | error vs own reference "
        "| FE vs analytic |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for m in result["rows"]:
        fe = m.dofs > 0
        lines.append(f"| {m.method} | {m.setting} | {m.dofs if fe else '-'} | {m.wall_s:.3g} "
                     f"| {f'{m.setup_s:.2g}' if fe else '-'} | {m.ratio:.5f} | {m.error:+.2e} "
                     f"| {f'{m.vs_analytic:+.2%}' if fe else '-'} |")
    lines += ["",
              f"Cost growth: the time loop's wall time on a short run (vibration from "
              f"{GROWTH['vibration.t_on'] * 1e3:g} ms, F_dv over {GROWTH['time.average_cycles']} "
              f"cycles; {plan.dofs_T:g} s simulated against DOFs), set-up aside.",
              "",
              "| cost against | integrator | points (size: loop s, set-up s) | fitted exponent |",
              "|---|---|---|---|"]
    for axis, integrator, points, x, y, exponent in result["growth"]:
        pairs = ", ".join(f"{size:g}: {p.loop_s:.3g}, {p.setup_s:.2g}"
                          for size, p in zip(x, points))
        lines.append(f"| {axis} | {integrator} | {pairs} | {exponent:.2f} |")
    if result["laws"]:
        lines += ["",
                  f"Friction laws on the same scene: the analytic stepper at dt = "
                  f"{plan.law_dt:g} s against its own reference at dt = "
                  f"{plan.analytic_reference_dt:g} s"
                  + (f"; FE {plan.law_fe[0]}, {plan.law_fe[1]} mesh, dt = {plan.law_fe[2]:g} s, "
                     "against the same reference" if plan.law_fe else "") + ".",
                  "",
                  "| law | reference F_dv/F_d0 | analytic wall s | analytic error "
                  "| FE wall s | FE F_dv/F_d0 | FE vs analytic |",
                  "|---|---|---|---|---|---|---|"]
        for row in result["laws"]:
            fe = row.fe
            fe_cells = (f"{fe.wall_s:.3g} | {fe.ratio:.5f} | {fe.vs_analytic:+.2%}" if fe
                        else "- | - | -")
            lines.append(f"| {row.label} | {row.reference:.5f} | {row.analytic.wall_s:.3g} "
                         f"| {row.analytic.error:+.2e} | {fe_cells} |")
    if result.get("mesh"):
        lines += [""] + mesh_markdown(result["mesh"])
    if result.get("breakdowns"):
        lines += [""] + breakdown_markdown(result["breakdowns"])
    if result.get("periodic"):
        from . import periodic_bench

        lines += [""] + periodic_bench.markdown(result["periodic"])
    return "\n".join(lines) + "\n"


def mesh_markdown(study: MeshStudy) -> list:
    """The mesh study as Markdown lines: each level against the mesh-converged value."""
    f0, p, uncertainty = study.converged
    lines = [f"Mesh study: FE {study.integrator} at dt = {study.dt:g} s on successively finer "
             f"meshes. Richardson extrapolation of the last three: mesh-converged F_dv/F_d0 = "
             f"{f0:.5f} +- {uncertainty:.1e}, observed order {p:.2f} in the element size.",
             "",
             "| mesh | element size mm | DOFs | set-up s | loop s | F_dv/F_d0 "
             "| error vs mesh-converged |",
             "|---|---|---|---|---|---|---|"]
    for run, h in zip(study.runs, study.sizes):
        level = run.setting.split(",")[0]
        lines.append(f"| {level} | {h * 1e3:.2f} | {run.dofs} | {run.setup_s:.2g} "
                     f"| {run.loop_s:.3g} | {run.ratio:.5f} | {relative(run.ratio, f0):+.2e} |")
    return lines


def breakdown_markdown(breakdowns) -> list:
    """The step breakdowns as Markdown lines: a table of parts, then each step's fraction."""
    from .core import machine

    lines = [f"A step in parts, on {machine.cpu_name()} (one core): this machine's multiply-add "
             f"rate {machine.multiply_add_rate() / 1e9:.1f} G/s (operands from L1) and bandwidth "
             f"{machine.bandwidth(32_000) / 1e9:.0f} / {machine.bandwidth(400_000) / 1e9:.0f} / "
             f"{machine.bandwidth(4_000_000) / 1e9:.0f} / {machine.bandwidth(256_000_000) / 1e9:.0f}"
             " GB/s (32 KB / 400 KB / 4 MB / 256 MB working sets). Each part's bound is "
             "max(bytes / bandwidth, multiply-adds / rate); the friction law and the rest have "
             "none (fem/step_breakdown.py).",
             "",
             "| integrator | setting | part | us a step | multiply-adds | KB | bound us "
             "| bound / time |",
             "|---|---|---|---|---|---|---|---|"]
    for b in breakdowns:
        for part in b.parts:
            bounded = part.bound > 0.0
            lines.append(
                f"| {b.integrator} | {b.setting} | {part.name} | {part.seconds * 1e6:.2f} "
                f"| {f'{part.multiply_adds:,.0f}' if bounded else '-'} "
                f"| {f'{part.nbytes / 1e3:,.0f}' if bounded else '-'} "
                f"| {f'{part.bound * 1e6:.2f}' if bounded else '-'} "
                f"| {f'{part.bound / part.seconds:.0%}' if bounded else '-'} |")
        lines.append(f"| {b.integrator} | {b.setting} | **whole step** | "
                     f"**{b.step_s * 1e6:.2f}** | | | {b.bound * 1e6:.2f} "
                     f"| **{b.bound / b.step_s:.0%}** |")
    return lines


def plot(result: dict, path) -> None:
    """Wall time against error, log-log, one line per method."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4.5))
    for method in dict.fromkeys(m.method for m in result["rows"]):
        points = sorted((m.wall_s, abs(m.error)) for m in result["rows"]
                        if m.method == method and m.error != 0.0 and "medium" not in m.setting)
        if points:
            ax.loglog(*zip(*points), "o-", ms=4, label=method)
    ax.set(xlabel="wall time, one core (s)",
           ylabel="|error| of F_dv/F_d0 against its own reference",
           title=f"speed against error: Fig 7 scene, {result['plan'].T:g} s simulated")
    ax.legend(fontsize=8)
    ax.grid(True, which="both", lw=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
