"""What a run reports: cycle-averaged drive force (eqs 40-41), F_d0, breakaway."""

import math

import numpy as np

from ..core.errors import NumericalError
from ..core import settling
from ..core.series import TimeSeries, averaging_steps
from ..core.shooting import periodic_block


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
    return scene.friction.steady_sliding_force(scene.contact.F_N, scene.drive.v_d)


def window_drift(series: TimeSeries, steps: int, dt: float):
    """How far the drive-force mean moved between the last two averaging windows:
    |F_k - F_{k-1}| / |F_k|, F_k the mean over the last ``steps`` steps (eq 40)
    and F_{k-1} over the ``steps`` before them.

    None where the series does not hold two whole windows at every step (a run
    shorter than two windows): then nothing says the average has settled.
    """
    if series.t.size < 2 * steps or series.t[-1] - series.t[-2 * steps] > (2 * steps - 0.5) * dt:
        return None
    last = cycle_average(series.F_d, steps)
    before = float(np.mean(series.F_d[-2 * steps:-steps]))
    if last == before:
        return 0.0
    return abs(last - before) / abs(last) if last != 0.0 else None


def summarize(series: TimeSeries, scene, wall_time_s: float) -> dict:
    """The JSON keys of a summary (docs/command-line.md) for one run, and whether it settled.

    F_dv/F_d0 is None when there is no friction to reduce (F_d0 = 0, mu = 0).
    ``settled`` is True where the drift still to come, extrapolated from the decay of
    successive windows' means (core/settling.py), is at most time.settle_tolerance:
    the averaged drive force no longer depends on when the run stopped.
    """
    window = averaging_steps(scene)
    F_dv = cycle_average(series.F_d, window)
    if not math.isfinite(F_dv):
        raise NumericalError(f"the cycle-averaged drive force is {F_dv}")
    F_d0 = steady_drive_force(scene)
    tolerance = scene.time.settle_tolerance
    since = scene.vibration.t_on if scene.vibrated else 0.0
    judged = settling.judge(series.t, series.F_d, window, scene.time.dt, since,
                            window_drift(series, window, scene.time.dt), tolerance)
    return {
        "F_dv_over_F_d0": F_dv / F_d0 if F_d0 > 0.0 else None,
        "F_dv": F_dv,
        "F_d0": F_d0,
        "breakaway_time_s": breakaway_time(series, scene.F_c),
        "steps": scene.steps,
        "wall_time_s": wall_time_s,
        **judged.as_dict(),
        "settle_tolerance": tolerance,
    }


def unsettled_warning(summary: dict, label: str = "") -> str | None:
    """One line for stderr if the summary's average has not settled, else None."""
    if summary["settled"]:
        return None
    what = f"{label} " if label else ""
    drift = summary["window_drift"]
    remaining = summary.get("drift_remaining")
    if summary.get("normal_force") == "transient":     # an FE run's (fem/outputs/normal_swing.py)
        moved = ("the block's free vibration on its contact was still decaying as the "
                 "averaging window began (the summed normal force)")
    elif drift is None:
        moved = "the run holds fewer than two averaging windows after the vibration starts"
    elif remaining is not None:
        moved = (f"its mean moved by {drift:.2%} between the last two averaging windows and "
                 f"may still move by {remaining:.2%} ({summary['settle_note']})")
    else:
        moved = (f"its mean moved by {drift:.2%} between the last two averaging windows; "
                 f"how much more it may move is not known ({summary['settle_note']})")
    why = ""
    if "breakaway_time_s" in summary and summary["breakaway_time_s"] is None:
        # a drive spring still loading a body held by friction (a huge F_N, a tiny v_d)
        why = " (the drive force never reached F_c = mu F_N: no breakaway)"
    return (f"warning: the {what}cycle-averaged drive force has not settled: {moved} "
            f"(time.settle_tolerance {summary['settle_tolerance']:g}); lengthen time.T{why}")


def summarize_orbit(orbit, scene) -> dict:
    """The summary of a run answered by the periodic orbit (periodic.find_orbit): F_dv
    the mean drive force over its cycle (eq 40 over one whole cycle, which equals the
    mean over any number of them). No breakaway time (the orbit starts after it);
    settled, its drift 0: the orbit is the state the stepped run settles to."""
    F_dv = float(np.mean(orbit.cycle[:, 1]))
    if not math.isfinite(F_dv):
        raise NumericalError(f"the cycle-averaged drive force is {F_dv}")
    F_d0 = steady_drive_force(scene)
    return {
        "F_dv_over_F_d0": F_dv / F_d0 if F_d0 > 0.0 else None,
        "F_dv": F_dv,
        "F_d0": F_d0,
        "breakaway_time_s": None,
        "steps": orbit.cycles_integrated * orbit.steps,
        "wall_time_s": orbit.solver_time_s,
        "window_drift": 0.0,
        "settled": True,
        "settle_decay_rate": None,
        "drift_remaining": 0.0,
        "settle_note": "the periodic orbit: the state a stepped run settles to",
        "settle_tolerance": scene.time.settle_tolerance,
        "periodic": periodic_block(orbit, scene),
    }
