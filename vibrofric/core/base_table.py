"""A base motion given step by step: a measured motion (a CSV of t, x_b, y_b, z_b) or
harmonics of the paper's sine, sampled once at the run's step into a table that the
compiled stepper reads (docs/model.md section 6, docs/scenes.md "A base motion of your
own").

The table is ADDED to the paper's motion (core/base_motion.py, eqs 23-25 and the normal
sine), which keeps its own arithmetic: a scene with a measured motion has k_v = 0 and
no normal_amplitude (the sine is exactly 0 and the table is the whole motion); a
scene with harmonics keeps its sine and adds

    x_b += a_x sin(n w s + phi_x),  y_b += a_y sin(n w s + phi_y),  z_b += a_z sin(n w s + phi_z)

(s = t - t_on, n the harmonic's order, w = 2 pi vibration.f), so a harmonic of
amplitude 0 adds exactly 0.0 to every step's displacement.

The table's rows are the steps from the first step at or after t_on (``first_step``):
row k is step first_step + k, at s_k = (first_step + k) dt - t_on. Each row holds
x_b, y_b, z_b and their velocities (TABLE_COLUMNS). ``period`` > 0: the rows repeat
every ``period`` steps (a periodic motion whose period is a whole number of steps);
0: the last row holds once the table ends (a motion that ends: its last displacement,
velocity 0). Harmonics whose base cycle is not a whole number of steps, and a periodic
measured motion whose period is not, are sampled at every step of the run instead
(6 floats a step).

The readers: analytic/normal.py normal_loop (and the periodic solver's cycle map
over it), fem/integrators/explicit.py explicit_steps; each reads row table_row(i) of
step i and adds it to the sine's base position.

A measured motion is interpolated LINEARLY in displacement (exact at the file's
samples, never overshooting them: a file sampled at the run's steps is reproduced to
rounding). Before t_on the base rests at 0; at t_on it is at the file's first row
(a file that does not start at 0 moves the base there in one step). Its velocity,
which the contact's normal dashpot sees (analytic/normal.py, fem/model/contact.py),
is the derivative of a cubic spline through the same samples (scipy's CubicSpline;
periodic end conditions for a periodic motion, not-a-knot otherwise): the linear
interpolant's derivative jumps at every sample, and a dashpot fed by it would be
kicked there; the spline's is continuous and its error of order h^3 (h the file's
sampling interval). Harmonics are sampled exactly.
"""

import csv
import functools
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numba import njit

from .errors import BadBaseMotion

FILE_COLUMNS = ("t", "x_b", "y_b", "z_b")       # a measured motion's header; z_b optional
TABLE_COLUMNS = ("x_b", "y_b", "z_b", "vx_b", "vy_b", "vz_b")
WHOLE_STEPS = 1e-9      # a period is a whole number of steps to this relative tolerance
                        # (core.shooting.cycle_steps' test)


@dataclass(frozen=True)
class MeasuredMotion:
    """A measured base motion: times t (s, from 0, increasing) and the base's displacements
    x, y, z (m) at them."""

    t: np.ndarray
    x: np.ndarray
    y: np.ndarray
    z: np.ndarray

    @property
    def span(self) -> float:
        return float(self.t[-1])


@dataclass(frozen=True)
class Harmonic:
    """One harmonic of the base's motion: ``order`` n times the base's frequency, the
    amplitudes along X, Y, Z (m) and their phases (deg)."""

    order: int
    x: float = 0.0
    y: float = 0.0
    z: float = 0.0
    phase_x_deg: float = 0.0
    phase_y_deg: float = 0.0
    phase_z_deg: float = 0.0

    def __str__(self) -> str:
        """As a scene writes it, its order and the keys not 0: {order = 2, x = 2e-08}."""
        keys = [f"{name} = {value:.12g}" for name, value in vars(self).items()
                if name != "order" and value != 0.0]
        return "{" + ", ".join([f"order = {self.order}", *keys]) + "}"


@dataclass(frozen=True)
class BaseTable:
    """The sampled motion (module docstring): ``rows`` (n, 6) of TABLE_COLUMNS, the step
    ``first_step`` of row 0, and the ``period`` in steps (0: the last row holds)."""

    rows: np.ndarray
    first_step: int
    period: int


NO_TABLE = BaseTable(np.zeros((0, len(TABLE_COLUMNS))), 0, 0)


@njit(cache=True, error_model="numpy")
def table_row(rows, first_step, period, i):
    """The row of ``rows`` that step i reads, or -1 before the first step (the base at rest)
    or where there is no table."""
    if rows.shape[0] == 0 or i < first_step:
        return -1
    k = i - first_step
    if period > 0:
        return k % period
    return min(k, rows.shape[0] - 1)


def read_motion(path) -> MeasuredMotion:
    """A measured motion file: a header naming t, x_b, y_b and optionally z_b (any order),
    then rows of numbers (lines starting with # are comments); at least 2 rows, every
    value finite, t starting at 0 and strictly increasing. Raises BadBaseMotion naming
    vibration.motion. Read once for each content (the scene's checks, the sampling at
    each step of an error estimate): kept by path, size and modification time."""
    path = Path(path)
    try:
        stat = path.stat()
    except FileNotFoundError:
        raise BadBaseMotion(f"{path}: no such file") from None
    except OSError as err:
        raise BadBaseMotion(f"{path} cannot be read: {err}") from None
    return _parsed(str(path), stat.st_size, stat.st_mtime_ns)


@functools.lru_cache(maxsize=8)
def _parsed(name: str, size: int, mtime_ns: int) -> MeasuredMotion:
    """read_motion's parse of the file ``name`` (``size``, ``mtime_ns``: its cache key);
    the arrays read-only, as the cache shares them."""
    motion = _parse_motion(Path(name))
    for values in (motion.t, motion.x, motion.y, motion.z):
        values.flags.writeable = False
    return motion


def _parse_motion(path: Path) -> MeasuredMotion:
    """The file's columns, checked (read_motion)."""
    try:
        with path.open(newline="", encoding="utf-8") as stream:
            lines = [(number, row) for number, row in enumerate(csv.reader(stream), 1)
                     if any(c.strip() for c in row) and not row[0].lstrip().startswith("#")]
    except FileNotFoundError:
        raise BadBaseMotion(f"{path}: no such file") from None
    except (OSError, UnicodeDecodeError) as err:
        raise BadBaseMotion(f"{path} cannot be read: {err}") from None
    if not lines:
        raise BadBaseMotion(f"{path} is empty: give a header t, x_b, y_b[, z_b] and rows")
    header = [name.strip() for name in lines[0][1]]
    missing = [name for name in FILE_COLUMNS[:3] if name not in header]
    if missing:
        raise BadBaseMotion(f"{path}: the header {', '.join(header)} lacks the column(s) "
                            f"{', '.join(missing)} (t in s, x_b, y_b[, z_b] in m)")
    if len(lines) < 3:
        raise BadBaseMotion(f"{path} holds {len(lines) - 1} row(s): a motion needs at least 2")
    columns = {}
    for name in FILE_COLUMNS:
        if name not in header:
            continue
        index = header.index(name)
        values = np.empty(len(lines) - 1)
        for r, (number, row) in enumerate(lines[1:]):
            try:
                values[r] = float(row[index])
            except (IndexError, ValueError):
                raise BadBaseMotion(f"{path} line {number}: no number in column {name}") from None
            if not math.isfinite(values[r]):
                raise BadBaseMotion(f"{path} line {number}: {name} = {values[r]} is not a "
                                    "finite number")
        columns[name] = values
    t = columns["t"]
    if t[0] != 0.0:
        raise BadBaseMotion(f"{path}: t starts at {t[0]:g} s; it starts at 0 (the moment "
                            "vibration.t_on)")
    late = np.flatnonzero(np.diff(t) <= 0.0)
    if late.size:
        raise BadBaseMotion(f"{path} line {lines[late[0] + 2][0]}: t = {t[late[0] + 1]:g} s "
                            f"does not increase (after {t[late[0]]:g} s)")
    z = columns.get("z_b", np.zeros_like(t))
    return MeasuredMotion(t, columns["x_b"], columns["y_b"], z)


def check_closed(motion: MeasuredMotion, path) -> None:
    """A periodic motion's last row is the next period's first: the same displacements,
    to 1e-9 of the motion's range (refused otherwise: the base would jump once a period)."""
    for name, values in zip(FILE_COLUMNS[1:], (motion.x, motion.y, motion.z)):
        reach = max(float(np.max(np.abs(values))), 1e-300)
        if abs(values[-1] - values[0]) > 1e-9 * reach:
            raise BadBaseMotion(f"{path}: periodic, but the last row's {name} = {values[-1]:g} "
                                f"differs from the first's {values[0]:g} (the last row is the "
                                "next period's first)")


def whole_steps(span: float, dt: float):
    """The whole number of steps of ``span`` at ``dt`` (to WHOLE_STEPS relative), or None."""
    exact = span / dt
    n = int(round(exact))
    return n if n >= 1 and abs(exact - n) <= WHOLE_STEPS * exact else None


def check_harmonics(harmonics) -> None:
    """Each harmonic's order a positive integer (its amplitudes and phases are finite
    numbers by their type: scene/keys.py)."""
    for h in harmonics:
        if isinstance(h.order, bool) or not isinstance(h.order, int) or h.order < 1:
            raise BadBaseMotion(f"order = {h.order!r}: a harmonic's order is a positive integer "
                                "(1: the base's frequency)", "vibration.harmonics")


def sample_measured(motion: MeasuredMotion, periodic: bool, dt: float, t_on: float,
                    first_step: int, last_step: int) -> BaseTable:
    """The measured ``motion`` at the steps from ``first_step`` (module docstring): where
    ``periodic``, one period where it is a whole number of steps, else every step to
    ``last_step``; not periodic, to the file's end and a last row held at rest."""
    from scipy.interpolate import CubicSpline   # (scipy only where a motion is measured)

    values = np.column_stack([motion.x, motion.y, motion.z])
    offset = first_step * dt - t_on
    period = None
    if periodic:
        period = whole_steps(motion.span, dt)
        steps = period if period is not None else max(1, last_step - first_step + 1)
        values[-1] = values[0]
        s = np.mod(offset + np.arange(steps) * dt, motion.span)
        spline = CubicSpline(motion.t, values, bc_type="periodic")
    else:
        steps = max(0, int(math.floor((motion.span - offset) / dt)) + 1)
        s = offset + np.arange(steps) * dt
        spline = CubicSpline(motion.t, values, bc_type="not-a-knot")
    rows = np.empty((steps + (0 if periodic else 1), len(TABLE_COLUMNS)))
    for axis in range(3):
        rows[:steps, axis] = np.interp(s, motion.t, values[:, axis])
    rows[:steps, 3:] = spline(s, 1)
    if not periodic:       # the motion ended: its last displacement, at rest
        rows[-1, :3], rows[-1, 3:] = values[-1], 0.0
    return BaseTable(rows, first_step, period or 0)


def sample_harmonics(harmonics, omega: float, dt: float, t_on: float, first_step: int,
                     last_step: int) -> BaseTable:
    """The harmonics' added motion at the steps from ``first_step``: one cycle of the base
    where 2 pi / (w dt) is a whole number of steps, else every step to ``last_step``."""
    period = whole_steps(2.0 * math.pi / omega, dt)
    steps = period if period is not None else max(1, last_step - first_step + 1)
    s = (first_step + np.arange(steps)) * dt - t_on
    rows = np.zeros((steps, len(TABLE_COLUMNS)))
    for h in harmonics:
        w = h.order * omega
        for axis, (amplitude, phase_deg) in enumerate(((h.x, h.phase_x_deg), (h.y, h.phase_y_deg),
                                                       (h.z, h.phase_z_deg))):
            if amplitude == 0.0:
                continue
            phase = w * s + math.radians(phase_deg)
            rows[:, axis] += amplitude * np.sin(phase)
            rows[:, axis + 3] += amplitude * w * np.cos(phase)
    return BaseTable(rows, first_step, period or 0)


def base_table(vibration, omega: float, dt: float, t_on: float, first_step: int,
               last_step: int) -> BaseTable:
    """The table of a scene's [vibration] (its motion, motion_periodic and harmonics keys)
    at the step ``dt`` from ``first_step`` (the first step at or after ``t_on``) to
    ``last_step``; NO_TABLE where the sine alone moves the base."""
    if vibration.motion is not None:
        return sample_measured(read_motion(vibration.motion), vibration.motion_periodic, dt,
                               t_on, first_step, last_step)
    if vibration.harmonics:
        check_harmonics(vibration.harmonics)
        return sample_harmonics(vibration.harmonics, omega, dt, t_on, first_step, last_step)
    return NO_TABLE


def table_moves_along_z(vibration) -> bool:
    """Whether the motion given per step moves the base along Z: a harmonic with a z, or
    a measured motion whose z_b is not all 0 (an unreadable file: False; the scene's
    checks refuse it)."""
    if any(h.z != 0.0 for h in vibration.harmonics):
        return True
    if vibration.motion is None:
        return False
    try:
        return bool(np.any(read_motion(vibration.motion).z != 0.0))
    except BadBaseMotion:
        return False


def moves_along_z(vibration) -> bool:
    """Whether the base moves along Z: vibration.normal_amplitude, or a table that does."""
    return vibration.normal_amplitude > 0.0 or table_moves_along_z(vibration)


def table_speed_z(vibration, omega: float) -> float:
    """A bound of the table's |dz_b/dt|, m/s: each harmonic's n w |z| summed, or a measured
    motion's fastest chord in z_b between its samples."""
    if vibration.motion is not None:
        motion = read_motion(vibration.motion)
        return float(np.max(np.abs(np.diff(motion.z)) / np.diff(motion.t)))
    return sum(h.order * omega * abs(h.z) for h in vibration.harmonics)


def table_velocity_z(vibration, omega: float, s: float) -> float:
    """The table's dz_b/dt at the time s from t_on, m/s, between the steps it is sampled at
    (harmonics exactly, a measured motion by its spline: the module docstring); 0 without
    a table. The explicit FE integrator's start needs it half a step before t_on's step."""
    if vibration.motion is not None:
        from scipy.interpolate import CubicSpline

        motion = read_motion(vibration.motion)
        z = np.array(motion.z)
        if vibration.motion_periodic:
            z[-1] = z[0]
            s = s % motion.span
        spline = CubicSpline(motion.t, z, bc_type="periodic" if vibration.motion_periodic
                             else "not-a-knot")
        return float(spline(s, 1))
    return sum(h.z * h.order * omega * math.cos(h.order * omega * s + math.radians(h.phase_z_deg))
               for h in vibration.harmonics)
