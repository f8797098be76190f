"""Early steady state: stop a run once its cycle-averaged drive force has settled.

F_dv is the mean drive force over the averaging window: the last W =
core.series.averaging_steps(scene) steps, whole vibration cycles (eqs
40-41). At every cycle boundary after the vibration has started and a whole
window has run since, the window mean

    F_k = (1/W) sum_{j = i - W + 1}^{i} F_d,j          (i the boundary's step)

is compared with the means at the previous m boundaries (m =
time.steady_cycles, by default the window's own cycles: then the window
is compared with the one before it, which it does not overlap); the run
stops at boundary k as soon as

    max_{j = 1..m} |F_k - F_{k-j}| <= time.steady_tolerance * |F_k|

(time.steady_tolerance = 0, the default, never stops). The F_dv the summary
then reports is F_k itself: the recorded series ends at that step
(recording.py), and summarize() averages its last W rows.

Cycle boundaries are the steps i_on + round(k n), n = 1 / (f dt) steps per
cycle, i_on the first step at or after vibration.t_on (t = 0 without
vibration). The window sum is kept as a running sum over a ring of the last
W drive forces (its rounding drift over 10^6 steps is ~1e-10 of F_dv).
"""

import math

import numpy as np
from numba import njit

from ...core.series import averaging_steps

# ints[]: the detector's integer state; floats[]: its real state.
CYCLE, SEEN, MEANS, STOPPED = range(4)
SUM, CHANGE = range(2)


class SteadyState:
    """The detector's parameters and state for one run (numba arrays)."""

    def __init__(self, scene):
        t = scene.time
        self.tolerance = t.steady_tolerance
        self.cycles = t.steady_cycles or scene.averaged_cycles
        self.window = averaging_steps(scene)
        self.steps_per_cycle = 1.0 / (scene.vibration.f * t.dt)
        self.first = int(math.ceil(scene.vibration.t_on / t.dt - 1e-9)) if scene.vibrated else 0
        self.forces = np.zeros(self.window)           # ring of the last W drive forces
        self.means = np.zeros(self.cycles + 1)        # ring of the last m + 1 window means
        self.ints = np.zeros(4, dtype=np.int64)       # CYCLE, SEEN, MEANS, STOPPED
        self.floats = np.array([0.0, np.inf])         # SUM, CHANGE
        self.planned = scene.steps
        self.dt = t.dt

    @property
    def arrays(self):
        """What the numba loops take."""
        return (self.tolerance, self.first, self.steps_per_cycle,
                self.forces, self.means, self.ints, self.floats)

    def report(self, last: int) -> dict:
        """The early-stop entries of a run's info, ``last`` the step it ended at."""
        stopped = bool(self.ints[STOPPED])
        change = float(self.floats[CHANGE])
        return {
            "steady_tolerance": self.tolerance,
            "steady_cycles": self.cycles,
            "stopped_early": stopped,
            "stop_time_s": last * self.dt if stopped else None,
            "steps_planned": self.planned,
            "steps": last,
            "saving": 1.0 - last / self.planned,
            # the settling measure at the last boundary checked (None if none was)
            "steady_change": change if math.isfinite(change) else None,
        }


@njit(cache=True, error_model="numpy")
def settled(i, f_d, steady) -> bool:
    """Account step i's drive force; True when the run may stop after step i."""
    tolerance, first, per_cycle, forces, means, ints, floats = steady
    if tolerance <= 0.0 or i < first:
        return False
    window = forces.shape[0]
    slot = ints[SEEN] % window
    floats[SUM] += f_d - forces[slot]
    forces[slot] = f_d
    ints[SEEN] += 1
    boundary = first + int(round(ints[CYCLE] * per_cycle))
    if i < boundary:
        return False
    ints[CYCLE] += 1
    if ints[SEEN] < window:
        return False
    mean = floats[SUM] / window
    m = means.shape[0]
    means[ints[MEANS] % m] = mean
    ints[MEANS] += 1
    if ints[MEANS] < m:
        return False
    change = 0.0
    for j in range(m):
        change = max(change, abs(means[j] - mean))
    change /= max(abs(mean), 1e-300)
    floats[CHANGE] = change
    if change <= tolerance:
        ints[STOPPED] = 1
        return True
    return False
