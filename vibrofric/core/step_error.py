"""The time step's error of a cycle-averaged answer, from the same solver at halved steps.

A scheme of order p gives an answer F(h) = F* + C h^p + O(h^(p+1)) at step h. From
the answers at h, h/2 and h/4 (Richardson, Phil. Trans. R. Soc. A 210 (1911) 307):

    d1 = F(h) - F(h/2),    d2 = F(h/2) - F(h/4)
    p_observed = log2(d1 / d2)                       (where d1 and d2 share their sign)
    F(h) - F*  ~ d1 / (1 - 2^-p)

and with two answers only, the same with the scheme's formal order p. The estimate
reported is that error times Roache's factor of safety (1.25 where the order was
observed, 3 where it was assumed: Roache, "Verification and validation in
computational science and engineering", Hermosa 1998, ch. 5, the grid convergence
index), so that it bounds the true error with the margin of a three-grid study.

Where the answers do not converge monotonically (d1 and d2 of opposite signs, or
an observed order below MIN_ORDER: the steps are too coarse for the asymptotic
range) no order is claimed: the answers then scatter about the converged one by
where the steps fall in the base's cycle (the lumped model's answer at 250, 500,
1000 steps a cycle on the Fig 7 scene is 1.0e-5, 1.3e-5, 5e-8 off, not in that
order), so the finest answer F(h/4) is the best one known and the estimate is
F(h)'s distance from it plus F(h/4)'s own, taken as the last halving's change:
|F(h) - F(h/4)| + |d2|. (|d1| + |d2| times 3, the first rule, was 6 times the
true error there.) Where the answer at h/2 is the one that strays, that is
|d2| large, the estimate is several times the true error; a solver for which a
fourth answer is cheap (the lumped model's orbits) adds F(h/8) where the three
scatter (``scattered``), and the same rule takes it as the finest:
|F(h) - F(h/8)| + |F(h/4) - F(h/8)| (docs/validation.md has what each gave on the
paper's grids). Where the answers agree to the solver's own
resolution (its convergence tolerance: differences below it are noise), the
estimate is that resolution.

The answer reported is always F(h) at the step the solver used (the step asked
for, or the one nearest it that divides the base's cycle: the estimate is the
error of that answer against the converged one, so it covers the snapping).
"""

import math
from dataclasses import dataclass

SAFETY_OBSERVED = 1.25   # Roache's factor of safety, order observed from three steps
SAFETY_ASSUMED = 3.0     # and where it is assumed (two steps) or not in the asymptotic range
MIN_ORDER = 0.5          # below this the answers are not yet in their asymptotic range
SCATTER = "not converging at a steady order"   # said in the note of answers that scatter
MAX_ORDER = 4.0          # above it the halvings' ratio is noise or a kink, not an order


@dataclass(frozen=True)
class StepError:
    """The step error of an answer (absolute, on the answer itself).

    estimate   the bound on |F(h) - F*| (None: no estimate was made, ``note`` says why)
    order      the order observed from three steps (None: assumed or not asymptotic)
    dt_used    the step the answer was computed at
    dt_asked   the step the scene asked for (time.dt)
    answers    ((dt, F), ...) the answers the estimate comes from, finest last
    note       how it was made, or why not
    scatters   the answers scatter rather than converge at a steady order (the estimate
               is then |F(dt) - F(finest)| + the last halving's change)
    """

    estimate: float | None
    order: float | None
    dt_used: float
    dt_asked: float
    answers: tuple = ()
    note: str = ""
    scatters: bool = False

    def step_for(self, accuracy: float, formal_order: float = 1.0) -> float | None:
        """The step that would bring the estimate to ``accuracy`` (assuming the error
        falls as h^p, p the observed order or else ``formal_order``), or None where
        no estimate was made or it already meets it."""
        if self.estimate is None or self.estimate <= accuracy:
            return None
        p = self.order if self.order is not None else formal_order
        return self.dt_used * (accuracy / self.estimate) ** (1.0 / p)

    def as_dict(self) -> dict:
        """The summary's keys: ``error_estimate`` (absolute, on F_dv/F_d0 where the
        answer is that ratio), ``error_order``, ``dt_used``, ``dt_asked``, ``error_note``."""
        return {"error_estimate": self.estimate, "error_order": self.order,
                "dt_used": self.dt_used, "dt_asked": self.dt_asked, "error_note": self.note}


def scattered(error: StepError) -> bool:
    """The three answers of ``error`` scatter rather than converge at a steady order:
    a fourth, at h/8, makes a finer reference of the estimate (richardson)."""
    return len(error.answers) == 3 and error.scatters


def not_estimated(dt_used: float, dt_asked: float, why: str) -> StepError:
    """A StepError that says no estimate was made, and why."""
    return StepError(None, None, dt_used, dt_asked, (), f"not estimated: {why}")


def richardson(answers, dt_asked: float, formal_order: float = 1.0,
               resolution: float = 0.0, two_step_safety: float = SAFETY_ASSUMED) -> StepError:
    """The step error of ``answers[0]`` from answers at successively halved steps.

    ``answers``: ((h, F(h)), (h/2, F(h/2))[, (h/4, F(h/4))[, (h/8, F(h/8))]]), the
    reported answer first (a fourth where the first three scatter: ``scattered``); ``formal_order``: the scheme's order, used where it cannot be observed;
    ``resolution``: the solver's own accuracy on F (differences below it are noise);
    ``two_step_safety``: the factor of safety on the estimate from two answers (a
    solver whose estimate has been measured against its true errors may take less
    than Roache's 3: fem/step_error.py).
    """
    answers = tuple((float(h), float(f)) for h, f in answers)
    if len(answers) not in (2, 3, 4):
        raise ValueError(f"richardson needs 2 to 4 answers at halved steps, got {len(answers)}")
    for (h, _), (h_next, _) in zip(answers, answers[1:]):
        if not math.isclose(h_next, h / 2.0, rel_tol=1e-9):
            raise ValueError(f"richardson needs halved steps: {h:g} then {h_next:g}")
    dt_used = answers[0][0]
    values = [f for _, f in answers]
    if not all(math.isfinite(f) for f in values):
        return not_estimated(dt_used, dt_asked, "an answer at a halved step is not finite")
    d1 = values[0] - values[1]
    if abs(d1) <= resolution:
        return StepError(resolution, None, dt_used, dt_asked, answers,
                         f"the answers at dt and dt/2 agree within the solver's resolution "
                         f"{resolution:.1e}")
    if len(answers) >= 3:
        d2 = values[1] - values[2]
        ratio = d1 / d2 if d2 != 0.0 else math.inf
        if math.isfinite(ratio) and ratio > 0.0:
            order = math.log2(ratio)
            if MIN_ORDER <= order <= MAX_ORDER:
                error = abs(d1) / (1.0 - 2.0 ** -order)
                return StepError(SAFETY_OBSERVED * error, order, dt_used, dt_asked, answers,
                                 f"Richardson from dt, dt/2, dt/4 (order {order:.2f} observed)")
        finest, last = len(answers) - 1, 2 ** (len(answers) - 1)
        error = abs(values[0] - values[finest]) + abs(values[finest - 1] - values[finest])
        steps = ", ".join(["dt"] + [f"dt/{2**k}" for k in range(1, len(answers))])
        return StepError(error, None, dt_used, dt_asked, answers,
                         f"{steps} {SCATTER}: |F(dt) - F(dt/{last})| + "
                         f"|F(dt/{last // 2}) - F(dt/{last})|", scatters=True)
    error = abs(d1) / (1.0 - 2.0 ** -formal_order)
    return StepError(two_step_safety * error, None, dt_used, dt_asked, answers,
                     f"Richardson from dt and dt/2 (the scheme's order {formal_order:g} assumed, "
                     f"factor of safety {two_step_safety:g})")
