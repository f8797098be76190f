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

The readers, each adding what it reads to the sine's base position:

- analytic/normal.py normal_loop (and the periodic solver's cycle map over it) and
  fem/integrators/explicit.py explicit_steps read row table_row(i) for step i: the
  base at the step's end t_{i} = i dt (the explicit start also takes dz_b/dt half a
  step before the first step on, table_velocity_z).
- fem/integrators/implicit.py implicit_steps (implicit and reduced) moves the base
  along each step's m friction sub-steps (contact_solve.implicit_substeps), where the
  sine is evaluated at every sub-step's end t_{i-1} + j dt / m, j = 1..m (the last:
  t_i). Its table (substep_table) is this module's table sampled at dt / m: row
  table_row(k) for sub-step index k = (i - 1) m + j, its period m times the steps'
  (where it is not periodic, 6 m floats a step of the run).
  Before t_on the implicit base's sine moves along Z from the start of the first step
  on (normal_start.py: the body starts there, a step before); the table's z_b and
  dz_b/dt there, at that step's start and sub-steps, are ``lead`` (table_z_at: a
  harmonic exactly, a periodic motion wrapped round its period, one that ends held at
  its first row's z_b, its spline's velocity).
- fem/integrators/cycle_map.py (the FE periodic solver) loads each cycle's start with
  the table's row there: a cycle is a whole number of steps, and a periodic table's
  period is the base cycle (harmonics of integer orders; a periodic motion's file
  spans 1/f), so every cycle reads the same rows.

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


def plane_speed(vibration, omega: float, v_a: float) -> float:
    """A bound of the base's in-plane speed, m/s: the sine's v_a where the sine alone moves
    it; with harmonics v_a plus each one's n w sqrt(x^2 + y^2); a measured motion's
    fastest chord between its samples (its linear interpolant's; k_v is 0 beside it)."""
    if not vibration.sampled:
        return v_a
    if vibration.motion is not None:
        motion = read_motion(vibration.motion)
        return float(np.max(np.hypot(np.diff(motion.x), np.diff(motion.y)) / np.diff(motion.t)))
    return v_a + sum(h.order * omega * math.hypot(h.x, h.y) for h in vibration.harmonics)


def plane_order(vibration) -> int:
    """The highest multiple of the base's frequency at which it moves in the plane: the
    largest order of a harmonic with an x or a y, else 1 (the sine's; a measured motion's
    period is the base cycle, its content unknown here)."""
    return max((h.order for h in vibration.harmonics if h.x != 0.0 or h.y != 0.0), default=1)


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


def table_z_at(vibration, omega: float, s: np.ndarray) -> np.ndarray:
    """(len(s), 2): the table's z_b and dz_b/dt at the times ``s`` from t_on, which may
    precede it (the implicit start's ``lead``, substep_table): harmonics exactly, a
    measured motion's z_b linearly and its velocity by its spline (module docstring),
    wrapped round its period where periodic; one that ends holds its first row's z_b
    before t = 0 (its spline's velocity there extrapolated). Zeros without a table."""
    s = np.asarray(s, dtype=float)
    out = np.zeros((s.size, 2))
    if vibration.motion is not None:
        from scipy.interpolate import CubicSpline

        motion = read_motion(vibration.motion)
        z = np.array(motion.z)
        if vibration.motion_periodic:
            z[-1] = z[0]
            s = np.mod(s, motion.span)
        spline = CubicSpline(motion.t, z, bc_type="periodic" if vibration.motion_periodic
                             else "not-a-knot")
        out[:, 0] = np.interp(s, motion.t, z)
        out[:, 1] = spline(s, 1)
        return out
    for h in vibration.harmonics:
        if h.z == 0.0:
            continue
        w = h.order * omega
        phase = w * s + math.radians(h.phase_z_deg)
        out[:, 0] += h.z * np.sin(phase)
        out[:, 1] += h.z * w * np.cos(phase)
    return out


@dataclass(frozen=True)
class SubstepTable:
    """The table an implicit integrator reads (module docstring): ``table`` at dt / m
    (its steps the friction sub-steps), ``per_step`` m, and ``lead`` (m_on + 1, 2):
    z_b, dz_b/dt at the start of the first step on and at its m_on sub-steps' ends."""

    table: BaseTable
    per_step: int
    lead: np.ndarray


def substep_table(vibration, omega: float, dt: float, substeps: int, on_step_substeps: int,
                  t_on: float, on_step: int, last_step: int) -> SubstepTable:
    """The table of a scene's [vibration] at each of the implicit step's ``substeps``
    friction sub-steps (module docstring), from the first sub-step at or after t_on to
    the end of ``last_step``; ``on_step`` the first step on, run on ``on_step_substeps``
    sub-steps (fewer where it ends at t_on exactly: contact_solve.still_substeps).
    NO_TABLE and no lead where the sine alone moves the base."""
    from .base_motion import first_step_on

    h = dt / substeps
    first = first_step_on(t_on, h)
    table = base_table(vibration, omega, h, t_on, first, last_step * substeps)
    if table.rows.shape[0] == 0:
        return SubstepTable(table, substeps, np.zeros((0, 2)))
    start = (on_step - 1) * dt
    s = start + np.arange(on_step_substeps + 1) * (dt / on_step_substeps) - t_on
    return SubstepTable(table, substeps, table_z_at(vibration, omega, s))
