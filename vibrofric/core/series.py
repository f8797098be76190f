"""The time series every run writes, and which steps it keeps.

A 1 s run at dt = 1e-6 has 10^6 steps; a run keeps every step of its last
vibration cycles (for the cycle average, eqs 40-41, whether it has settled,
and the Fig 8 / 11 plots)
and, before them, one step every ``time.series_dt``.
"""

from dataclasses import dataclass, field

import numpy as np

COLUMNS = ("t", "F_d", "F_x", "F_y", "x", "y", "x_b", "y_b")
PLOT_CYCLES = 4  # cycles shown at full resolution in the F_x, F_y plot


@dataclass
class TimeSeries:
    """Columns of COLUMNS, each an array over the kept steps.

    ``extra`` holds further columns a model adds (the FE model's summed normal
    force ``F_n``), written after the standard ones.
    """

    t: np.ndarray
    F_d: np.ndarray
    F_x: np.ndarray
    F_y: np.ndarray
    x: np.ndarray
    y: np.ndarray
    x_b: np.ndarray
    y_b: np.ndarray
    extra: dict = field(default_factory=dict)

    @classmethod
    def from_table(cls, table: np.ndarray, extra_names=()) -> "TimeSeries":
        columns = table.T.copy()
        extra = dict(zip(extra_names, columns[len(COLUMNS):]))
        return cls(*columns[:len(COLUMNS)], extra=extra)

    @property
    def names(self) -> tuple:
        return COLUMNS + tuple(self.extra)

    def table(self) -> np.ndarray:
        return np.column_stack([getattr(self, c) for c in COLUMNS] + list(self.extra.values()))

    def tail(self, duration: float) -> "TimeSeries":
        """The part of the series within ``duration`` of its end."""
        keep = self.t >= self.t[-1] - duration * (1 + 1e-9)
        return TimeSeries.from_table(self.table()[keep], tuple(self.extra))


@dataclass(frozen=True)
class RecordPlan:
    """Steps 1..steps are kept if a multiple of ``stride`` or from ``full_from`` on."""

    steps: int
    stride: int
    full_from: int

    @classmethod
    def for_scene(cls, scene, full_steps: int) -> "RecordPlan":
        steps = scene.steps
        stride = max(1, int(round(scene.time.series_dt / scene.time.dt)))
        return cls(steps, stride, max(1, steps - full_steps + 1))

    @property
    def rows(self) -> int:
        return (self.full_from - 1) // self.stride + (self.steps - self.full_from + 1)


NO_STEPS = RecordPlan(0, 1, 1)  # a run of no steps, keeping no rows


def averaging_steps(scene) -> int:
    """Steps in the final window averaged into F_dv: whole cycles of n = 1/(f dt) steps (eq 41).

    A scene without vibration averages over as many cycles of ``vibration.f``.
    """
    return max(1, int(round(scene.averaged_cycles / (scene.vibration.f * scene.time.dt))))


def full_resolution_steps(scene) -> int:
    """Steps kept at every step at the end of a run: the last two averaging
    windows (F_dv and whether it has settled, summary.window_drift) and the
    plotted cycles."""
    plot = int(round(PLOT_CYCLES / (scene.vibration.f * scene.time.dt)))
    return min(scene.steps, max(2 * averaging_steps(scene), plot))
