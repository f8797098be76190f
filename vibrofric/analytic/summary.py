"""What a run reports: cycle-averaged drive force (eqs 40-41), F_d0, breakaway."""

import math

import numpy as np

from ..friction_law import FrictionLaw
from .series import NumericalError, TimeSeries, averaging_steps


def cycle_average(values: np.ndarray, steps: int) -> float:
    """Mean of the last ``steps`` values: F_dv = (1/n) sum F_d over whole cycles (eq 40)."""
    return float(np.mean(values[-steps:]))


def breakaway_time(series: TimeSeries, F_c: float):
    """First time the drive force reaches the Coulomb force F_c = mu F_N, or None.

    Without friction (F_c = 0) nothing holds the body: there is no breakaway.
    """
    if F_c <= 0.0:
        return None
    reached = np.flatnonzero(series.F_d >= F_c)
    return float(series.t[reached[0]]) if reached.size else None


def steady_drive_force(scene) -> float:
    """F_d0: the drive force of steady sliding at v_d without vibration (F_c for Dahl)."""
    c = scene.contact
    law = FrictionLaw(law=c.law, mu=c.mu, mu_s=scene.F_s / c.F_N, v_s=c.v_s, h_v=c.h_v)
    return law.steady_sliding_force(c.F_N, scene.drive.v_d)


def summarize(series: TimeSeries, scene, wall_time_s: float) -> dict:
    """The JSON keys of spec/interface.md for one run.

    F_dv/F_d0 is None when there is no friction to reduce (F_d0 = 0, mu = 0).
    """
    F_dv = cycle_average(series.F_d, averaging_steps(scene))
    if not math.isfinite(F_dv):
        raise NumericalError(f"the cycle-averaged drive force is {F_dv}")
    F_d0 = steady_drive_force(scene)
    return {
        "F_dv_over_F_d0": F_dv / F_d0 if F_d0 > 0.0 else None,
        "F_dv": F_dv,
        "F_d0": F_d0,
        "breakaway_time_s": breakaway_time(series, scene.F_c),
        "steps": scene.steps,
        "wall_time_s": wall_time_s,
    }
