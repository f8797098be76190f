"""The time integrators, selected by scene fem.integrator.

An integrator is a time_loop.TimeLoop prepared once per run (the loop owns
the initial state, the chunks, the failures and the statistics; each
integrator its preparation and its compiled step):

    Run(scene, model)
        refuses (core.errors.Refusal) a scene it cannot run, and
        does the run's set-up (a factorization, a reduction); run_fe calls it
        before any output is opened
    run.name, run.info, run.choice
        which integrator this is, what the set-up found (FEResult.info), and
        for "auto" why it was picked (None otherwise)
    run.cost_per_step
        its time per step in ns, roughly (step_cost.COST; for "auto")
    run.integrate(plan, frame=None, every=0, progress=None) -> recording.Integration
        run ``plan.steps`` steps of ``scene.time.dt`` from the static preload
        (fewer once settled, outputs/steady.py), keep the rows ``plan``
        (core.series.RecordPlan) asks for (columns recording.columns),
        call ``frame(state)`` at t = 0, every ``every`` steps and at the end
        when given, ``progress(step, steps)`` now and then (recording.run_in_chunks),
        and raise core.errors.NumericalError on numerical trouble

The integrators, all driving the same per-node friction law (model/contact.py):

    explicit   central differences, lumped mass (explicit.py): the Abaqus/Explicit
               analogue; dt below the mesh's stable step (~1e-6 s)
    implicit   generalized-alpha on the full model, factorized once (implicit.py);
               any dt that resolves the vibration (>= 10 steps a cycle)
    reduced    the same on a Craig-Bampton reduction of the block to its contact
               face, drive and modes below fem.cutoff * f (reduction.py)
    auto       the cheapest of those at a coarse first step (choose() below), its step
               refined until its estimated error meets time.accuracy (fem/step_error.py)
"""

from ...core.errors import Refusal, StepTooLong
from . import step_cost
from .explicit import ExplicitRun
from .generalized_alpha import full_system
from .implicit import ImplicitRun
from .reduction import ReducedRun


def implicit_run(scene, model) -> ImplicitRun:
    """Generalized-alpha on the full model (implicit.py)."""
    return ImplicitRun(scene, model, full_system(model))


def choose(scene, model):
    """fem.integrator = "auto": the cheapest integrator at the scene's step (the first
    step auto tries, fem/step_error.py, which then refines the step by its estimated
    error until it meets time.accuracy).

    All three run the same steps, so the cheapest is the one with the cheapest step
    (cost_per_step, calibrated in step_cost.COST). Candidates:

    explicit  the full model, where time.dt is below its stable step
    reduced   where its reduction error (reduction.py: the face's dynamic
              compliance against the full model's, computed for the scene, taken as
              an F_dv error) is within fem.accuracy: a model error, which no
              step removes
    implicit  the full model; prepared (factorized) only when neither of the
              others qualifies or its estimated cost (step_cost.estimated_cost)
              is below theirs: it always costs more than explicit at the same
              step, but less than a reduced model that keeps hundreds of modes
              (an ultrasonic base)

    Returns the prepared run, its ``choice`` saying what was picked and why.
    """
    accuracy = scene.fem.accuracy
    reasons, candidates = [], []
    for name in ("explicit", "reduced"):
        try:
            run = INTEGRATORS[name](scene, model)
        except Refusal as error:
            reasons.append(f"{name} refused ({error})")
            continue
        if name == "reduced":
            estimate = run.info["reduction_error_estimate"]
            if estimate > accuracy:
                reasons.append(f"reduced: estimated reduction error {estimate:.2g} > "
                               f"fem.accuracy {accuracy:g}")
                continue
            reasons.append(f"reduced: estimated reduction error {estimate:.2g} <= "
                           f"fem.accuracy {accuracy:g}")
        candidates.append(run)
    cheapest = min((run.cost_per_step for run in candidates), default=float("inf"))
    if step_cost.estimated_cost(scene, model) < cheapest:
        try:
            candidates.append(implicit_run(scene, model))
            reasons.append("implicit: the full model at any time.dt")
        except Refusal as error:
            reasons.append(f"implicit refused ({error})")
    if not candidates:
        raise StepTooLong(f"time step {scene.time.dt:g} s: no integrator runs it within "
                          f"fem.accuracy {accuracy:g}: " + "; ".join(reasons))
    best = min(candidates, key=lambda run: run.cost_per_step)
    costs = ", ".join(f"{run.name} {run.cost_per_step / 1e3:.3g}" for run in candidates)
    best.choice = (f"{best.name}: the cheapest at {scene.time.dt:.4g} s within fem.accuracy "
                   f"{accuracy:g} (estimated us a step: {costs}); " + "; ".join(reasons))
    return best


INTEGRATORS = {
    "explicit": ExplicitRun,
    "implicit": implicit_run,
    "reduced": ReducedRun,
    "auto": choose,
}


def select(scene):
    """The integrator named by fem.integrator (a callable (scene, model) -> run); the
    scene's validation has checked the name against scene.CHOICES."""
    return INTEGRATORS[scene.fem.integrator]
