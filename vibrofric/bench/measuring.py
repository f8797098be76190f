"""Each measurement of the bench: one run of a method, timed, and its answer; and
measure(plan), every measurement of a plan in one process, one run after another."""

import math
import time
from dataclasses import dataclass

from . import periodic_vs_transient
from .fits import fitted_exponent, relative, richardson
from .plans import GROWTH, Plan, base_scene


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


def measure_analytic(scene, update: str, dt: float, repeats: int = 3) -> Measurement:
    """The analytic stepper's answer and its best wall time of ``repeats`` runs."""
    from ..analytic.solve import solve

    case = scene.with_values({"contact.update": update, "time.dt": dt})
    best = min((solve(case, estimate=False)[1] for _ in range(repeats)),
               key=lambda s: s["wall_time_s"])
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
    from ..analytic.solve import solve

    case = scene.with_law(law, parameters)
    reference = solve(case.with_values({"time.dt": plan.analytic_reference_dt}),
                      estimate=False)[1]["F_dv_over_F_d0"]
    stepped = case.with_values({"time.dt": plan.law_dt})
    best = min((solve(stepped, estimate=False)[1] for _ in range(3)),
               key=lambda s: s["wall_time_s"])
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
    from ..analytic.summary import summarize
    from ..fem import run_fe
    from ..fem.integrators import reduction

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
    """One integrator's step in parts (step_breakdown), from a measured run."""

    integrator: str
    setting: str
    step_s: float               # measured: the run's loop time over its steps
    parts: list                 # step_breakdown.Part

    @property
    def bound(self) -> float:
        return sum(part.bound for part in self.parts)


def element_size(level: str) -> float:
    """m: the mean element edge of a mesh level on the bench's block, (volume / elements)^(1/3)."""
    from ..meshes import block

    return (math.prod(block.DEFAULT_SIZE) / math.prod(block.level_counts(level))) ** (1.0 / 3.0)


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
    (step_breakdown)."""
    from mpi4py import MPI

    from ..fem.integrators import registry
    from ..fem.model.fe_model import build_model
    from .step_breakdown import breakdown

    run = min((measure_fe(scene, integrator, mesh, dt) for _ in range(2)),
              key=lambda m: m.loop_s / m.steps)
    case = scene.with_values({"fem.integrator": integrator, "fem.mesh": mesh, "time.dt": dt})
    prepared = registry.select(case)(case, build_model(case, MPI.COMM_SELF))
    step_s = run.loop_s / run.steps
    return Breakdown(integrator, run.setting, step_s, breakdown(prepared, step_s, run.iterations))


def warm_up(scene, integrators) -> None:
    """Compile every integrator's loop once (numba caches it on disk) so that the timings
    are of the runs: a 5 ms run on the one-element mesh."""
    for integrator in integrators:
        measure_fe(scene, integrator, "tiny", 1e-6,
                   {"vibration.t_on": 0.0, "time.T": 0.005, "time.average_cycles": 4})


def measure(plan: Plan, progress=print) -> dict:
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
        progress("periodic steady state against the transient")
        periodic = periodic_vs_transient.measure(plan.periodic_fe, plan.periodic_fe_study)
    return {"plan": plan, "analytic_reference": analytic_reference, "fe_reference": fe_reference,
            "rows": rows, "growth": growth, "laws": laws, "breakdowns": breakdowns,
            "mesh": mesh, "periodic": periodic}
