"""The time integrators, replaceable parts selected by scene fem.integrator.

An integrator is a pair of functions:

    check(scene, model)
        refuse, with SceneError naming the key, a scene it cannot run
        (the explicit one: time.dt above model.dt_stable); called before any
        output is opened
    integrate(model, scene, plan, frame=None, every=0) -> explicit.Integration
        run ``plan.steps`` steps of ``scene.time.dt`` from the static preload
        of ``model`` (model.FEModel: plain arrays), keep the rows ``plan``
        (analytic.series.RecordPlan) asks for in ``Integration.table``
        (columns explicit.COLUMNS), call ``frame(state)`` at t = 0 and every
        ``every`` steps when given, and raise analytic.series.NumericalError
        on numerical trouble

An implicit Newmark or a reduced (modal) model fits behind the same pair.
"""

from dataclasses import dataclass
from typing import Callable

from ..scene import SceneError
from . import explicit
from .model import check_step


@dataclass(frozen=True)
class Integrator:
    name: str
    check: Callable
    integrate: Callable


INTEGRATORS = {
    # central difference with the lumped mass: the Abaqus/Explicit analogue
    "explicit": Integrator("explicit", check_step, explicit.integrate),
}


def select(scene) -> Integrator:
    """The integrator named by fem.integrator, or SceneError naming the key."""
    try:
        return INTEGRATORS[scene.fem.integrator]
    except KeyError:
        raise SceneError("fem.integrator", f"unknown integrator {scene.fem.integrator!r}; "
                                           f"known: {', '.join(INTEGRATORS)}") from None
