"""What an FE run keeps, and how it proceeds: the recorded rows, the state at its end,
its statistics, the chunks between ParaView frames.

Every integrator records one row per kept step (COLUMNS, plus ENERGY when
fem.energy is on) with ``keep``. Which steps are kept is the analytic
stepper's RecordPlan (core/series.py): every ``stride``-th step, and every
step of the last ``full`` steps (the averaging window of F_dv and the plotted
cycles). A run that may stop early (steady.py) does not know in advance which
steps are its last ones, so the most recent ``full`` rows are kept in a ring
buffer as well; ``Recorder.table(last)`` then returns exactly the rows that
RecordPlan(last, stride, last - full + 1) names: the series ends where the run
stopped, at full resolution over its last ``full`` steps, and
analytic.summary.summarize averages the settled cycles.

Beside the rows, the contact nodes' normal forces N_i over the same last
``full`` steps, every ``node_stride``-th step (at least NODE_SAMPLES_PER_CYCLE
a vibration cycle), in a ring of their own (``Recorder.node_normals``): what
the normal-force rule acts on (normal_swing.node_swing).
"""

import time
from dataclasses import dataclass

import numpy as np
from numba import njit

from ...core.base_table import moves_along_z
from ...core.chunks import CHUNK_SECONDS, next_chunk
from ...core.series import COLUMNS as SERIES_COLUMNS
from ...core.series import RecordPlan
from . import trouble
from .steady import settled

# The recorded table: the analytic TimeSeries columns, then the summed normal force.
COLUMNS = SERIES_COLUMNS + ("F_n",)
# The nodes' normal forces are kept at least this often a vibration cycle (their swing's
# extremes to ~0.2% of it for a sinusoid: 1 - cos(pi / 50); benchmarks/normal_force_swing.py
# samples as often).
NODE_SAMPLES_PER_CYCLE = 50

# fem.energy adds, cumulative from t = 0 and relative to the static preload (J):
#   W_drive  work of the drive point B on the spring: int F_d v_d dt
#   W_base   work of the base on the asperities: sum_i int -F_i . db (db = (dx_b, eta_y dy_b))
#   E_kin    kinetic energy 1/2 v^T M v
#   E_el     elastic energy: the block and its penalty springs under the dead loads
#            (their total potential above the preload's), the drive spring
#            F_d^2 / (2 k_d) and the asperities sum_i k_t w_i s_i^2 / 2
#   D_fric   friction dissipation: sum over steps and nodes of F_i . (du_i - db) - d(k_t w_i s_i^2 / 2)
#   D_damp   Rayleigh damping of the block and the penalty dashpots
# Balance: W_drive + W_base = E_kin + E_el + D_fric + D_damp (+ the integrator's
# numerical dissipation, zero for fem.rho_infinity = 1); see energy.py.
ENERGY = ("W_drive", "W_base", "E_kin", "E_el", "D_fric", "D_damp")
# Their places in a recorded row.
W_DRIVE, W_BASE, E_KIN, E_EL, D_FRIC, D_DAMP = range(len(COLUMNS), len(COLUMNS) + len(ENERGY))


# A base moving along Z (vibration.normal_amplitude > 0, or a motion given per step along
# Z: core/base_table.py) adds, last, the lumped model's
# normal columns (analytic/normal.py NORMAL_COLUMNS), here for the FE body:
#   z    the contact face's mean height from the preload, sum_i w_i (u_z,i - u0_z,i) (m)
#   z_b  the base's height (m)
#   N    the summed normal force sum_i N_i (N; the same as F_n)
NORMAL = ("z", "z_b", "N")


def columns(energy: bool, normal: bool = False) -> tuple:
    return COLUMNS + (ENERGY if energy else ()) + (NORMAL if normal else ())


def extra_columns(energy: bool, normal: bool = False) -> tuple:
    """The columns after the TimeSeries' standard ones (TimeSeries.extra)."""
    return columns(energy, normal)[len(SERIES_COLUMNS):]


def scene_columns(scene) -> tuple:
    """The recorded columns of an FE run of ``scene``."""
    return columns(scene.fem.energy, moves_along_z(scene.vibration))


def scene_extra_columns(scene) -> tuple:
    """scene_columns after the TimeSeries' standard ones."""
    return scene_columns(scene)[len(SERIES_COLUMNS):]


@njit(cache=True)
def record_normal(row, z, z_b, f_n):
    """The NORMAL columns, the row's last three (a base moving along Z)."""
    k = row.shape[0]
    row[k - 3] = z
    row[k - 2] = z_b
    row[k - 1] = f_n


@dataclass
class State:
    """A run's state at one step, on the block's nodes (DOLFINx dof order).

    What the ParaView frames and FEResult.fields show (paraview.node_fields).
    """

    step: int
    t: float
    u: np.ndarray           # (dofs,) displacement, including the preload
    v: np.ndarray           # (dofs,) velocity
    law_state: np.ndarray   # (contacts, the law's STATE_SIZE)
    deformation: np.ndarray  # (contacts, 2) the law's elastic deformation (Dahl: s e)
    normal: np.ndarray      # (contacts,) normal force N_i
    friction: np.ndarray    # (contacts, 2) friction force F_i (acts on the body as -F_i)
    x_b: float
    y_b: float


@dataclass
class Integration:
    """What an integrator returns: the recorded table, the final state, statistics.

    stats holds at least loop_time_s, F_n_min, F_n_max, F_n_min_after_t_on,
    F_n_max_after_t_on, steps (the steps run) and the early-stop entries of
    steady.SteadyState.report().
    """

    table: np.ndarray       # (rows, len(columns))
    state: State            # at the end of the run
    stats: dict
    node_normals: np.ndarray  # (samples, contacts): N_i over the averaging window (Recorder)


def node_stride(scene) -> int:
    """Steps between two kept samples of the nodes' normal forces: NODE_SAMPLES_PER_CYCLE
    a vibration cycle or more (every step where a cycle has fewer steps)."""
    return max(1, int(1.0 / (NODE_SAMPLES_PER_CYCLE * scene.vibration.f * scene.time.dt)))


class Recorder:
    """The kept rows of a run that may stop before ``plan.steps``, and its contact
    nodes' normal forces every ``stride`` steps over the last ``full`` steps: those the
    loop writes into ``normal`` (time_loop.ContactState.normal) at each step."""

    def __init__(self, plan: RecordPlan, ncols: int, normal=None, stride: int = 1):
        self.plan = plan
        self.full = plan.steps - plan.full_from + 1
        self.strided = np.empty((plan.steps // plan.stride, ncols))
        self.ring = np.empty((self.full, ncols))
        self.count = np.zeros(1, dtype=np.int64)  # strided rows written
        self.row = np.empty(ncols)                # the row being filled
        self.normal = np.empty(0) if normal is None else normal
        self.node_stride = stride
        self.node_ring = np.empty((self.full // stride + 1, self.normal.size))

    @property
    def arrays(self):
        """What the numba loops take: (row, strided, ring, count, stride, normal,
        node_ring, node_stride)."""
        return (self.row, self.strided, self.ring, self.count, self.plan.stride,
                self.normal, self.node_ring, self.node_stride)

    def node_normals(self, last: int, steps: int) -> np.ndarray:
        """(samples, nodes): the nodes' normal forces kept over steps last - steps + 1 ..
        last (steps <= full), in step order."""
        assert steps <= self.full
        stride = self.node_stride
        first = -(-(last - steps + 1) // stride) * stride     # the first multiple of stride
        kept = np.arange(first, last + 1, stride) // stride
        return self.node_ring[kept % self.node_ring.shape[0]]

    def table(self, last: int) -> np.ndarray:
        """The rows of RecordPlan(last, stride, max(1, last - full + 1)), in step order."""
        plan = RecordPlan(last, self.plan.stride, max(1, last - self.full + 1))
        before = (plan.full_from - 1) // plan.stride       # strided steps before the full window
        steps = np.arange(plan.full_from, last + 1)
        table = np.concatenate([self.strided[:before], self.ring[steps % self.full]])
        assert table.shape[0] == plan.rows
        return table


@njit(cache=True)
def keep(i, recorder):
    """Keep the filled ``row`` as step i's: in the ring, and if i is a stride multiple;
    and the nodes' ``normal`` forces if i is a node_stride multiple."""
    row, strided, ring, count, stride, normal, node_ring, node_stride = recorder
    ring[i % ring.shape[0], :] = row
    if i % stride == 0:
        strided[count[0], :] = row
        count[0] += 1
    if i % node_stride == 0:
        node_ring[(i // node_stride) % node_ring.shape[0], :] = normal


@njit(cache=True, error_model="numpy")
def keep_step(i, f_d, recorder, steady):
    """Keep step i's row and its nodes' normal forces; True when the run may stop after
    it (steady.settled)."""
    keep(i, recorder)
    return settled(i, f_d, steady)


# scalars[]: the state every time loop carries between chunks; an integrator's own follow
# from LOOP_SCALARS on (implicit.py's).
LOOP_SCALARS = 8
XB, YB, SIN, COS, FN_MIN, FN_MAX, FN_MIN_ON, FN_MAX_ON = range(LOOP_SCALARS)


def initial_scalars(extra: int = 0) -> np.ndarray:
    """The base at rest, sin/cos of its phase, the normal-force extremes unset, ``extra`` zeros."""
    start = [0.0, 0.0, 0.0, 1.0, np.inf, -np.inf, np.inf, -np.inf]
    assert len(start) == LOOP_SCALARS
    return np.array(start + [0.0] * extra)


@njit(cache=True, error_model="numpy")
def finish_step(t, t_on, f_d, f_n, f_x, f_y, x, y, x_b, y_b, friction_magnitude, F_N, mu_max,
                normal_limit, lifts_off, scalars, row):
    """Check a finished step (trouble.step_trouble; ``normal_limit`` the summed normal
    force's, ``lifts_off``: the base moves along Z, and the whole face may leave it),
    track the summed normal force's extremes and fill the row's COLUMNS. Returns the
    trouble code."""
    code = trouble.step_trouble(f_d, f_n, friction_magnitude, F_N, mu_max, normal_limit,
                                lifts_off)
    if code != trouble.OK:
        return code
    scalars[FN_MIN] = min(scalars[FN_MIN], f_n)
    scalars[FN_MAX] = max(scalars[FN_MAX], f_n)
    if t >= t_on:
        scalars[FN_MIN_ON] = min(scalars[FN_MIN_ON], f_n)
        scalars[FN_MAX_ON] = max(scalars[FN_MAX_ON], f_n)
    row[0] = t
    row[1] = f_d
    row[2] = f_x
    row[3] = f_y
    row[4] = x
    row[5] = y
    row[6] = x_b
    row[7] = y_b
    row[8] = f_n
    return code


# With a progress callback, the compiled loop returns to Python at least this
# often (steps): ~0.1-0.5 s of an FE loop, so that a progress bar moves and a
# Ctrl-C is answered. The loops keep all their state in arrays, so where a run
# is cut into chunks does not change its results.
PROGRESS_STEPS = 5000


def run_in_chunks(steps: int, frame, every: int, state, advance, progress=None, onset=0,
                  longest=None):
    """Run steps 1..steps by ``advance(first, last) -> stop step or 0``, returning to
    Python for the ParaView frames, frame(state(i)) at i = 0, every ``every``
    steps and at the last step, for ``progress(i, steps)`` every
    PROGRESS_STEPS steps and at the end, and ``progress(0, steps)`` first (the
    loop's clock starts: its compiled step is ready), and at least every
    CHUNK_SECONDS or so (a chunk of steps doubles while it takes under half of
    it): Ctrl-C and SIGTERM, which Python handles only between compiled calls,
    end even a run of slow steps (a stiff contact's thousands of friction
    sub-steps) at once.

    ``onset`` is the first step of the vibration, where a step may become many
    times slower at once (every contact node's friction sub-steps start there): no
    chunk runs across it, and the chunks start again from one step there. (Grown
    over the quick steps before it, a chunk of thousands of steps ran for minutes
    past the onset with SIGTERM waiting.) No chunk is longer than ``longest`` steps
    (None: no bound): what a caller reads back from a ring after each chunk fits in it.
    Returns (the last step run, the loop's seconds)."""
    frames = frame is not None and every > 0
    if progress is not None:
        progress(0, steps)
    if frame is not None:
        frame(state(0))
    start = time.perf_counter()
    first, last = 1, 0
    chunk = 1  # steps a call, grown while a call takes under CHUNK_SECONDS / 2
    while first <= steps:
        last = min(steps, first + chunk - 1)
        if frames:
            last = min(last, (first // every + 1) * every)
        if progress is not None:
            last = min(last, (first // PROGRESS_STEPS + 1) * PROGRESS_STEPS)
        if first < onset:
            last = min(last, onset - 1)
        if longest is not None:
            last = min(last, first + longest - 1)
        called = time.perf_counter()
        stop = advance(first, last)
        took = time.perf_counter() - called
        chunk = 1 if last + 1 == onset else next_chunk(chunk, took, last - first + 1)
        if stop:
            last = stop
            break
        if frames and last % every == 0:
            frame(state(last))
        if progress is not None:
            progress(last, steps)
        first = last + 1
    loop_time = time.perf_counter() - start
    if frame is not None and not (frames and last % every == 0):
        frame(state(last))
    if progress is not None:
        progress(last, steps)
    return last, loop_time


def loop_stats(scalars, loop_time) -> dict:
    """The statistics every integrator reports."""
    return {"loop_time_s": loop_time,
            "F_n_min": scalars[FN_MIN], "F_n_max": scalars[FN_MAX],
            "F_n_min_after_t_on": scalars[FN_MIN_ON], "F_n_max_after_t_on": scalars[FN_MAX_ON]}
