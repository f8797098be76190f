"""Whether a stepped run's cycle-averaged drive force has settled: the drift still to come.

The last two averaging windows' means (eq 40 over whole cycles) differing by little
does not make a run settled: a slow mode (the drive spring's, whose Floquet
multiplier is 0.99998 a cycle with k_d = 100 N/m on the Fig 7 scene) moves the mean
by a small amount a window for a long time. Where the means of successive windows
W_k approach their limit as a geometric series, W_k = W_inf + A r^k (the slowest
mode dominating, r its decay a window), the differences d_k = W_k - W_{k-1} fall by
r a window and the drift still to come after the last window is

    W_last - W_inf = d_last r / (1 - r)                  (the geometric series' tail)

(the same extrapolation as Aitken's delta-squared process: Aitken, Proc. R. Soc.
Edinb. 46 (1926) 289). r is taken from the differences of the last DECAY_WINDOWS
windows: the RMS of the newer half of them over the RMS of the older half, to the
power 1/(half): an amplitude ratio, so that a complex pair of slow multipliers,
whose differences oscillate in sign, gives its modulus. The run has settled where
that drift, relative to the last window's mean, is at most time.settle_tolerance;
it has not where the windows are too few to tell r, where r cannot be told from 1
(R_MAX), or where the drift is larger.

The windows' means before the last two are taken from the rows the run keeps
there (one every time.series_dt: core/series.py), which are the same phases of
every cycle where series_dt divides it, so their constant quadrature offset
cancels in the differences; d_last is the exact difference of the last two
windows, which the run keeps at every step.
"""

import math
from dataclasses import dataclass

import numpy as np

DECAY_WINDOWS = 7     # windows whose 6 differences give r (3 newer against 3 older)
R_MAX = 0.995         # a decay a window above this cannot be told from 1 (no decay): the
                      # remaining drift d r/(1-r) would be d times 200 or more, and the
                      # ratio of two RMS of 3 differences is no more certain than that
ROUNDING = 1e-10      # differences below this, relative to the mean, are the sums' rounding: a
                      # window sums up to ~1e6 forces whose swing is up to ~30 times their
                      # mean (k_v = 20: F_dv ~ 0.03 F_c), ~1e-16 x 1e3 x 30 = 3e-12 (3.4e-12
                      # measured there); a slow mode whose differences are below it moves
                      # the mean by a tolerance of 1e-3 only with r above 1 - 1e-7


@dataclass(frozen=True)
class Settling:
    """The judgement of a stepped run's settling.

    settled          the drift still to come is at most the tolerance
    window_drift     |W_last - W_before| / |W_last| (None: fewer than two whole windows)
    decay_rate       r, the differences' decay a window (None: not told)
    drift_remaining  |d_last| r / (1 - r) / |W_last|, relative (None: r not told or >= R_MAX)
    windows          the whole windows after the vibration starts the judgement had
    note             how it was judged, or why it is not settled
    """

    settled: bool
    window_drift: float | None
    decay_rate: float | None
    drift_remaining: float | None
    windows: int
    note: str

    def as_dict(self) -> dict:
        """The summary's keys, as plain Python values (summary.json, --json)."""
        return {"window_drift": _plain(self.window_drift), "settled": bool(self.settled),
                "settle_decay_rate": _plain(self.decay_rate),
                "drift_remaining": _plain(self.drift_remaining), "settle_note": self.note}


def _plain(value):
    """A float, or None: numpy's scalars are not JSON's."""
    return None if value is None else float(value)


def window_means(t: np.ndarray, values: np.ndarray, steps: int, dt: float,
                 since: float) -> np.ndarray:
    """The means of ``values`` over successive windows of ``steps`` steps (each step dt
    long) ending at the last row, oldest first, of those windows that begin at or
    after ``since`` and hold rows; the rows may be thinned (core/series.py)."""
    width = steps * dt
    end = t[-1]
    count = int(math.floor((end - since) / width + 1e-9))
    means = []
    for k in range(count, 0, -1):
        low, high = end - k * width, end - (k - 1) * width
        inside = (t > low + 0.5 * dt) & (t <= high + 0.5 * dt)
        if inside.any():
            means.append(float(np.mean(values[inside])))
    return np.array(means)


def judge(t: np.ndarray, values: np.ndarray, steps: int, dt: float, since: float,
          last_drift: float | None, tolerance: float) -> Settling:
    """Settled or not, and the drift still to come (module docstring).

    ``t``, ``values``: the kept rows of the averaged quantity; ``steps``: the averaging
    window in steps of ``dt``; ``since``: when the vibration starts (no earlier window
    counts); ``last_drift``: |W_last - W_before| / |W_last| from the last two windows
    at every step (None where the run does not hold them); ``tolerance``: on the
    relative drift still to come."""
    if last_drift is None:
        return Settling(False, None, None, None, 0,
                        "the run holds fewer than two averaging windows after the vibration starts")
    means = window_means(t, values, steps, dt, since)
    windows = means.size
    if last_drift <= ROUNDING:
        return Settling(True, last_drift, None, last_drift, windows,
                        "the last two windows' means agree to rounding")
    if windows < DECAY_WINDOWS:
        return Settling(False, last_drift, None, None, windows,
                        f"{windows} averaging windows after the vibration starts: "
                        f"{DECAY_WINDOWS} are needed to tell how fast the mean settles")
    d = np.diff(means[-DECAY_WINDOWS:])
    half = d.size // 2
    newer = float(np.sqrt(np.mean(d[-half:] ** 2)))
    older = float(np.sqrt(np.mean(d[:half] ** 2)))
    scale = abs(means[-1]) if means[-1] != 0.0 else 1.0
    if older <= ROUNDING * scale:
        rate = 0.0 if newer <= ROUNDING * scale else math.inf
    else:
        rate = (newer / older) ** (1.0 / half)
    if rate >= R_MAX:
        told = rate if math.isfinite(rate) else None
        if np.any(d[1:] * d[:-1] < 0.0):
            # No trend: the means swing about a steady value (a slow mode oscillating,
            # as the drive spring's without vibration, which Dahl's velocity-free force
            # does not damp) with a half-period within the windows judged, so their
            # spread bounds where they go on swinging.
            spread = float(np.ptp(means[-DECAY_WINDOWS:])) / scale
            return Settling(spread <= tolerance, last_drift, told, spread, windows,
                            f"the windows' means swing without decaying, within "
                            f"{spread:.2e} of the mean over the last {DECAY_WINDOWS}")
        return Settling(False, last_drift, told, None, windows,
                        f"the windows' means drift one way without a decay told from 1 "
                        f"(their differences fall by {rate:.4g} a window)")
    remaining = last_drift * rate / (1.0 - rate)
    settled = remaining <= tolerance
    note = (f"differences of successive windows' means fall by {rate:.4g} a window: "
            f"{remaining:.2e} of the mean still to come")
    return Settling(settled, last_drift, rate, remaining, windows, note)
