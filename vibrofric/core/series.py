"""The time series every run keeps, and what of it a run writes.

A 1 s run at dt = 1e-6 has 10^6 steps; a run keeps every step of its last
vibration cycles (for the cycle average, eqs 40-41, whether it has settled,
and the Fig 8 / 11 plots)
and, before them, one step every ``time.series_dt``; its summary comes from
all of these. The file it writes (timeseries.csv) holds by default fewer rows,
written(): at least ROWS_PER_CYCLE a vibration cycle, and every step of the
last PLOT_CYCLES cycles; with --full-series every kept row.
"""

import math
from dataclasses import dataclass, field

import numpy as np

from .errors import WindowDoesNotFit

COLUMNS = ("t", "F_d", "F_x", "F_y", "x", "y", "x_b", "y_b")
PLOT_CYCLES = 4  # cycles shown at full resolution in the F_x, F_y plot
ROWS_PER_CYCLE = 8  # at least this many rows a vibration cycle in the written series: the
                    # friction force's waveform still shows (transverse F_x swings at 2f)


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

    def select(self, keep: np.ndarray) -> "TimeSeries":
        """The rows ``keep`` (a boolean mask) selects."""
        return TimeSeries.from_table(self.table()[keep], tuple(self.extra))

    def within(self, duration: float) -> np.ndarray:
        """Which rows lie within ``duration`` of the series' end (a boolean mask)."""
        return self.t >= self.t[-1] - duration * (1 + 1e-9)

    def tail(self, duration: float) -> "TimeSeries":
        """The part of the series within ``duration`` of its end."""
        return self.select(self.within(duration))


@dataclass(frozen=True)
class RecordPlan:
    """Steps 1..steps are kept if a multiple of ``stride`` or from ``full_from`` on."""

    steps: int
    stride: int
    full_from: int

    @classmethod
    def for_scene(cls, scene, full_steps: int) -> "RecordPlan":
        steps = scene.steps
        return cls(steps, recording_stride(scene), max(1, steps - full_steps + 1))

    @property
    def rows(self) -> int:
        return (self.full_from - 1) // self.stride + (self.steps - self.full_from + 1)


NO_STEPS = RecordPlan(0, 1, 1)  # a run of no steps, keeping no rows


def recording_stride(scene) -> int:
    """Steps between the kept rows before the last cycles: one every time.series_dt."""
    return max(1, int(round(scene.time.series_dt / scene.time.dt)))


def written_stride(scene) -> int:
    """Steps between the rows of the written series: 1 / (ROWS_PER_CYCLE f) rounded
    down to a multiple of the recording's stride (so that every row it names was
    kept, evenly spaced), and never below that stride."""
    recorded = recording_stride(scene)
    per_row = 1.0 / (ROWS_PER_CYCLE * scene.vibration.f * scene.time.dt)
    return recorded * max(1, int(per_row / recorded + 1e-9))


def written(series: TimeSeries, scene, full: bool = False) -> TimeSeries:
    """The rows a results directory's time series holds by default: one every
    written_stride(scene) steps, and every kept row of the last PLOT_CYCLES
    cycles, those the F_x, F_y plot draws; with ``full`` (--full-series) every kept
    row. ``scene`` is the one the series was run with (its time.dt numbers the steps)."""
    if full:
        return series
    step = np.rint(series.t / scene.time.dt).astype(np.int64)
    keep = (step % written_stride(scene) == 0) | series.within(PLOT_CYCLES / scene.vibration.f)
    return series.select(keep)


def written_rows(scene) -> int:
    """About how many rows written() keeps of a whole run of ``scene`` (budget.py)."""
    plotted = int(round(PLOT_CYCLES / (scene.vibration.f * scene.time.dt))) + 1
    kept = RecordPlan.for_scene(scene, full_resolution_steps(scene)).rows
    return min(kept, scene.steps // written_stride(scene) + plotted)


def averaging_steps(scene) -> int:
    """Steps in the final window averaged into F_dv: whole cycles of n = 1/(f dt) steps (eq 41).

    A scene without vibration averages over as many cycles of ``vibration.f``.
    """
    return max(1, int(round(scene.averaged_cycles / (scene.vibration.f * scene.time.dt))))


def shortest_stepped_T(scene) -> float:
    """The shortest time.T that holds a stepped run's averaging window after the
    vibration starts, t_on + averaged_cycles / f (eqs 40-41), rounded up to 4
    significant digits."""
    shortest = scene.vibration.t_on + scene.averaged_cycles / scene.vibration.f
    unit = 10.0 ** (math.floor(math.log10(shortest)) - 3)
    return float(f"{math.ceil(shortest / unit - 1e-9) * unit:.4g}")


def check_stepped_window(scene, why: str = "") -> None:
    """Refuse (WindowDoesNotFit) a scene to be stepped through time.T whose
    averaging window (scene.averaged_cycles, eqs 40-41) does not fit between
    the vibration's onset and time.T: its F_dv would average over the time before
    the onset. Checked where periodic or auto fall back to stepping (``why``: the
    reason, for the message; time.method transient is checked with the scene,
    scene.validation); the orbit they solve for otherwise needs no window."""
    vib, time = scene.vibration, scene.time
    cycles = scene.averaged_cycles
    window = cycles / vib.f
    if time.T - vib.t_on < window * (1.0 - 1e-9):   # (a window that fits to rounding fits)
        raise WindowDoesNotFit(f"{why}{cycles} cycles ({window:.3g} s) do not fit between "
                               f"vibration.t_on = {vib.t_on} s and time.T = {time.T} s; the "
                               f"shortest T that works is {shortest_stepped_T(scene):g} s")


def full_resolution_steps(scene) -> int:
    """Steps kept at every step at the end of a run: the last two averaging
    windows (F_dv and whether it has settled, summary.window_drift) and the
    plotted cycles."""
    plot = int(round(PLOT_CYCLES / (scene.vibration.f * scene.time.dt)))
    return min(scene.steps, max(2 * averaging_steps(scene), plot))
