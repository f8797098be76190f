"""The FE answer's time-step error, and the step fem.integrator = "auto" takes by it.

The error of F_dv/F_d0 at the step dt is Richardson's estimate (core/step_error.py)
from the same integrator on the same model at dt/2 (and dt/4 where three steps are
run: the order is then observed). A steady cycle (time.method periodic / auto) at
dt/2 is shot from the orbit found at dt (continuation: the orbit moves little with
the step, so the shooting takes a few cycles); a stepped run is run again through T.

With two steps the integrators' formal order, 2, is assumed (central differences;
generalized-alpha, Chung & Hulbert, J. Appl. Mech. 60 (1993) 371) and the factor of
safety is TWO_STEP_SAFETY, 1.25, not Roache's 3 for an assumed order: on the paper's
scenes the answers often converge faster than that order at the first halving
(F(dt/2) nearly converged already, then alternating by a little),
where 3 x 4/3 |F(dt) - F(dt/2)| was 4.5-6.2 times the true error (Fig 10 at k_v 20,
Fig 12 at k_v 6, 150 deg and k_v 20, 300 deg, reduced at 1e-5 s), while elsewhere the
observed order is ~1 (Fig 7: reduced from 1e-5 s to 2.5e-6 s, explicit from 1e-6 s),
where order 2 understates the error. With 1.25 the estimate was 0.57-2.6 times
the true error |F(dt) - F(dt/10)| on the seven cases of docs/validation.md (table
by benchmarks/fe_step_error.py): an estimate within a factor 3, not a bound
(Fig 12 at k_v 3, 75 deg: 0.57). Three steps (auto) observe the order and take
Roache's 1.25 as well.

When it is made (time.error_estimate, ``reason_not_to``): true, always; false,
never; "auto", where the second answer is cheap: the run was answered by its
steady cycle (the answer at dt/2 continues from it) on the coarse mesh or a
coarser one (the paper's scenes answer in seconds there). A stepped run would
cost as much again as the answer, a finer mesh many times more: there the output
says not estimated, and how to ask for it.

fem.integrator = "auto" (``search_step``): the answers at AUTO_STEPS_PER_CYCLE
steps a vibration cycle, then at each halving, until the estimate from three
successive steps (h, h/2, h/4) meets time.accuracy at h; the answer reported is
F(h), its estimate the one that met it, at most MAX_HALVINGS halvings (then the
finest triple's, saying the accuracy was not met).
"""

import math
from dataclasses import dataclass

from ..core.step_error import StepError, not_estimated, richardson
from ..meshes import level_counts

FORMAL_ORDER = 2.0
TWO_STEP_SAFETY = 1.25         # see the module docstring
# The steady cycle's F_dv/F_d0 is converged to about this (periodic.TOLERANCE: 4.7e-7 at
# 1e-5 s on Fig 7, reduced): answers closer than this at dt and dt/2 are the same.
PERIODIC_RESOLUTION = 1e-6
# "auto" estimates on this mesh or a coarser one (fewer elements).
CHEAP_MESH = "coarse"
AUTO_STEPS_PER_CYCLE = 25      # auto's first step: 1e-5 s at the paper's 4 kHz
MAX_HALVINGS = 4               # the cost cap: auto's finest reported step has 25 * 2^4 = 400
                               # steps a cycle (its estimate takes answers at 800 and 1600)


def reason_not_to(scene, answered_periodic: bool) -> str | None:
    """None where time.error_estimate asks for the estimate on this run, else why not,
    and how to ask for it (the error_note)."""
    choice = scene.time.error_estimate
    if choice is True:
        return None
    if choice is False:
        return ("time.error_estimate = false (true makes it, from a second run of the "
                "same integrator at dt/2)")
    if not answered_periodic:
        return ('time.error_estimate = "auto" estimates steady cycles only, and this run '
                "was stepped through T: a second run at dt/2 would cost twice the answer's "
                "time (time.error_estimate = true makes it)")
    if math.prod(level_counts(scene.fem.mesh)) > math.prod(level_counts(CHEAP_MESH)):
        return (f'time.error_estimate = "auto" estimates on the {CHEAP_MESH} mesh or coarser '
                f'ones, and fem.mesh is "{scene.fem.mesh}" (time.error_estimate = true makes '
                "it, from a second run at dt/2)")
    return None


@dataclass(frozen=True)
class Answer:
    """F_dv/F_d0 at one step: ``ratio`` (None where there is none: ``failed`` says why),
    ``start`` the orbit state to continue from at the next step (None: stepped)."""

    dt: float
    ratio: float | None
    start: object = None
    failed: str = ""


def resolution(answers) -> float:
    """The answers' own accuracy on F_dv/F_d0: the steady cycle's convergence where
    every one is an orbit; 0 for stepped runs (their averaging window's drift is
    reported apart, as ``settled``)."""
    return PERIODIC_RESOLUTION if all(a.start is not None for a in answers) else 0.0


def halved_estimate(first: Answer, answer_at, dt_asked: float) -> StepError:
    """The step error of ``first`` from ``answer_at(dt / 2, first.start)`` (an Answer)."""
    half = answer_at(first.dt / 2.0, first.start)
    if half.ratio is None:
        return not_estimated(first.dt, dt_asked, f"the answer at dt/2 failed: {half.failed}")
    answers = (first, half)
    return richardson([(a.dt, a.ratio) for a in answers], dt_asked, FORMAL_ORDER,
                      resolution(answers), TWO_STEP_SAFETY)


@dataclass(frozen=True)
class StepChoice:
    """What search_step found: the step ``dt`` (its answer's ``start`` to continue
    from), its ``error``, and ``text`` saying how."""

    dt: float
    start: object
    error: StepError
    text: str


def first_step(scene) -> float:
    """auto's first step: AUTO_STEPS_PER_CYCLE steps a vibration cycle, time.dt where
    there is no vibration."""
    if not scene.vibrated:
        return scene.time.dt
    return 1.0 / (AUTO_STEPS_PER_CYCLE * scene.vibration.f)


def search_step(scene, answer_at, dt0: float) -> StepChoice:
    """fem.integrator = "auto": halve the step from ``dt0`` until Richardson's estimate
    from h, h/2, h/4 meets time.accuracy at h (module docstring). ``answer_at(dt,
    start)`` gives an Answer; a failed answer ends the search where the last triple
    stands (or raises its failure as a NumericalError where there is none)."""
    from ..core.errors import NumericalError

    accuracy, dt_asked = scene.time.accuracy, scene.time.dt
    answers = [answer_at(dt0, None)]
    best = None
    while answers[-1].ratio is not None:
        if len(answers) >= 3:
            triple = answers[-3:]
            error = richardson([(a.dt, a.ratio) for a in triple], dt_asked, FORMAL_ORDER,
                               resolution(triple))
            best = (triple[0], error)
            if error.estimate is not None and error.estimate <= accuracy:
                return StepChoice(triple[0].dt, triple[0].start, error,
                                  f"time step {triple[0].dt:.4g} s: the coarsest of "
                                  f"{dt0:.4g} s halved whose estimated error "
                                  f"{error.estimate:.2g} meets time.accuracy {accuracy:g}")
        if len(answers) == MAX_HALVINGS + 3:
            break
        answers.append(answer_at(answers[-1].dt / 2.0, answers[-1].start))
    if best is None:
        failed = answers[-1]
        raise NumericalError(f"fem.integrator auto: no answer at time step {failed.dt:.4g} s "
                             f"to estimate the step's error from: {failed.failed}")
    first, error = best
    finer = error.step_for(accuracy, FORMAL_ORDER)
    return StepChoice(first.dt, first.start, error,
                      f"time step {first.dt:.4g} s: the finest tried from {dt0:.4g} s "
                      f"({MAX_HALVINGS} halvings); its estimated error {error.estimate} does "
                      f"not meet time.accuracy {accuracy:g}"
                      + (f" (a step of {finer:.3g} s would, by its order)" if finer else ""))
