"""The FE model's steady state directly: the periodic orbit of an integrator by shooting.

The FE analogue of analytic/periodic.py. The unknowns are the integrator's whole
state at the start of a base cycle in the frame that moves with the drive, its
unrestrained rigid motions gauged out (cycle_map.py); the residual is one cycle
of the integrator's own compiled step less the start, so the orbit is the state
the stepped run of the same integrator at the same step settles to, to the Newton
tolerance. The state has hundreds to thousands of entries (reduced Fig 7,
coarse mesh: 598; the full model's: 3 x its DOFs and more), too many for a
finite-difference Jacobian. Solved by core.shooting.newton_picard: Newton on
the drive mode (the block's rigid X translation and velocity on the drive
spring, the map's slowest: 0.984 a cycle on Fig 7, the reason the stepped
transient needs ~1000 cycles), plain cycles on the rest, Anderson-accelerated;
started from steady sliding (the preload moving at v_d, set back by the drive
spring's stretch under the mean drive force expected: the lumped model's F_dv
where the caller has it, else F_d0) after PLAIN_CYCLES plain cycles that bring
every node's friction law into its vibrated sliding (and give the law's state its
scale: set_law_scale), or from a neighbour's orbit (``start``: sweeps). The largest
Floquet multipliers: Arnoldi on directional derivatives at the orbit, on the map
with its contact iteration converged tightly (SMOOTH_ITERATION).

Where 1/(f dt) is not a whole number the scene is run at the nearest step that
puts a whole number in a cycle (periodic_scene; the summary's periodic.dt and
dt_adjusted say so).
"""

import math
from time import perf_counter

import numpy as np

from ...core.shooting import (Orbit, cycle_steps, instability, largest_multipliers,
                             newton_picard)
from .cycle_map import FECycleMap
from ..outputs.recording import XB, YB, State

TOLERANCE = 1e-6         # converged: the RMS of the scaled residual (each entry divided by its
                         # natural size, cycle_map.FECycleMap._scales: displacements by 10 F_c /
                         # k_pen, 1.2 nm on Fig 7) at most this. F_dv against the orbit converged
                         # to 1e-7 (Fig 7, reduced): 4.7e-7 at 1e-5, 4e-8 at 1e-6; at k_v = 20 on
                         # the coupled scene the residual stalled at 2.9e-7 (the contact
                         # iteration's tolerance inside each step)
MIN_CYCLES = 400         # the shooting may always take this many cycles (shooting_cycles)
STEPPED_SHARE = 1.0 / 3.0  # and up to this share of those the stepped run would integrate
PLAIN_CYCLES = 3         # at least 1: the laws' states at rest give them no scale (set_law_scale)
FD_STEP = 1e-6           # Arnoldi's difference step (scaled): the multipliers agree to 1e-3 for
                         # 1e-5 to 1e-7 on Fig 7 (reduced)
DECAY_CYCLES = 40        # decay_rate: cycles run from a perturbed orbit, the first DECAY_SKIP
DECAY_SKIP = 10          # of them letting the fast components die out (30 more where it grew)
DECAY_AMPLITUDE = 1e-3   # the perturbation's RMS, scaled
SMOOTH_ITERATION = 1e-10  # the contact iteration's tolerance for the multipliers' cycles: the
                         # stepper's own (1e-6) leaves a roughness that the difference steps see.
                         # The iteration contracts ~100 times an iteration, so its error at
                         # 1e-10 is ~1e-12 (docs/performance.md, "Design choices measured")
FRAMES_PER_CYCLE = 16    # ParaView frames of the steady cycle


def periodic_scene(scene):
    """(the scene at the step that puts a whole number of steps in a cycle, those steps)
    (core.shooting.cycle_steps: time.dt itself where 1/(f dt) is whole)."""
    steps, dt = cycle_steps(scene)
    if dt == scene.time.dt:
        return scene, steps
    return scene.with_values({"time.dt": dt}), steps


def find_orbit(phi: FECycleMap, start: np.ndarray | None = None,
               drive_force: float | None = None, stability: bool = True) -> Orbit:
    """Shoot for the periodic steady state of the cycle map ``phi`` (FECycleMap: the
    prepared integrator's compiled step, loaded; its scene's step puts phi.steps steps
    in a cycle). ``start``: a neighbour's orbit state (Orbit.z, unscaled) on the same
    model; else steady sliding set back by the drive spring's stretch under
    ``drive_force`` (the mean drive force expected, such as the lumped model's F_dv),
    or under the steady sliding force F_d0 where it is not given. Never raises for a
    failed or unstable orbit: the Orbit says. Its solver_time_s counts from here: the
    compiled step was loaded with phi, as the stepped run's loop time counts from its
    first step. ``stability`` False: no Floquet multipliers, the orbit taken as stable
    (fem/step_error.py: the same orbit at half the step, where the answer's was judged)."""
    begin = perf_counter()
    scene = phi.scene
    steps = phi.steps
    fresh = start is None or np.shape(start) != (phi.full_size,)
    z_raw = _sliding_start(phi, drive_force) if fresh else np.array(start, dtype=float)
    shot = _shoot(phi, z_raw)
    if not shot.converged and fresh and drive_force is not None and math.isfinite(drive_force):
        # Set back by the lumped model's F_dv, the start is nearer most orbits (Fig 7:
        # 70 cycles against 90 from F_d0), not every law's for certain:
        # examples/laws/maxwell_slip.py on Fig 7 (reduced) once did not converge in
        # 400 cycles from there and did from steady sliding under F_d0 (docs/periodic.md).
        # So a second try starts there.
        shot = _shoot(phi, _sliding_start(phi, None))
    multipliers = np.empty(0)
    reason = shot.reason
    orbit_note = ""
    cycle = np.empty((steps, phi.recorder.row.size))
    z = shot.z * phi.scale
    smooth = None
    if shot.converged and not stability:
        _, cycle = phi.raw_cycle(z, rows=True)
    elif shot.converged:
        smooth = _smooth_map(phi)
        x = shot.z
        multipliers, _ = largest_multipliers(smooth, x, smooth(x), FD_STEP)
        reason = instability(multipliers)
        if reason:      # confirmed, or not, by a perturbation's decay (see decay_rate)
            rate = decay_rate(phi, x)
            if rate < 1.0:
                orbit_note = (f"Arnoldi's largest Ritz value {abs(multipliers[0]):.4g} not "
                              f"confirmed: a perturbation decays by {rate:.4f} a cycle")
                multipliers, reason = np.array([rate]), ""
            else:
                reason += f"; a perturbation grows by {rate:.4f} a cycle"
        _, cycle = phi.raw_cycle(z, rows=True)
    cycles = phi.cycles + (smooth.cycles if smooth is not None else 0)
    stable = shot.converged and not reason
    orbit = Orbit(shot.converged, stable, z, cycle, shot.iterations, cycles,
                  shot.residual, multipliers, scene.time.dt, steps,
                  perf_counter() - begin, reason)
    orbit.extra["start"] = "steady sliding" if fresh else "neighbour"
    if orbit_note:
        orbit.extra["floquet_note"] = orbit_note
    return orbit


def _sliding_start(phi: FECycleMap, drive_force: float | None) -> np.ndarray:
    """Steady sliding set back by the drive spring's stretch under ``drive_force`` (the
    steady sliding force F_d0 where None), after PLAIN_CYCLES plain cycles (unscaled)."""
    scene = phi.scene
    if drive_force is None or not math.isfinite(drive_force):
        drive_force = scene.friction.steady_sliding_force(scene.contact.F_N, scene.drive.v_d)
    z_raw = phi.initial_state(drive_force)
    for _ in range(PLAIN_CYCLES):
        z_next, _ = phi.raw_cycle(z_raw)
        if not np.all(np.isfinite(z_next)):
            break
        z_raw = z_next
    return z_raw


def shooting_cycles(scene) -> int:
    """The cycles the shooting may take before the run is stepped through time.T instead:
    STEPPED_SHARE of the cycles that stepped run integrates with the base on, and at least
    MIN_CYCLES. A shooting that fails so adds at most that share to the stepped run (twice
    it where find_orbit tries a second start).

    Newton acts on the drive mode only (cycle_map.slow_directions); the other modes
    converge by plain (Anderson-accelerated) cycles, which can take more than MIN_CYCLES:
    the coarse ball (reduced, reach 3) at 1e-6 s, where a perturbation of its orbit
    decays by only 0.967 a cycle, had a residual of 4.1e-5 after 400 cycles and
    converged after 518 (docs/performance.md, "the balls' answers against the step"),
    where the stepped run takes 3440 cycles (T = 1 s, t_on = 0.14 s, 4 kHz): 1147
    allowed."""
    vibrated = max(0.0, scene.time.T - scene.vibration.t_on) * scene.vibration.f
    return max(MIN_CYCLES, math.ceil(STEPPED_SHARE * vibrated))


def _shoot(phi: FECycleMap, z_raw: np.ndarray):
    """Newton-Picard (core.shooting) from the unscaled state ``z_raw``, for at most
    shooting_cycles."""
    phi.set_law_scale(z_raw)
    slow, steps = phi.slow_directions()
    return newton_picard(phi, phi.gauge(z_raw / phi.scale), slow, steps, TOLERANCE,
                         shooting_cycles(phi.scene))


def decay_rate(phi: FECycleMap, x: np.ndarray) -> float:
    """The rate a cycle at which plain cycles bring a perturbed orbit back: the RMS
    distance from the orbit ``x`` (scaled) after DECAY_CYCLES cycles against that after
    DECAY_SKIP, to the power 1 / (DECAY_CYCLES - DECAY_SKIP), from a reproducible
    random perturbation of RMS DECAY_AMPLITUDE; where that grows, the rate over the
    next DECAY_CYCLES - DECAY_SKIP cycles; inf where the stepper fails.

    Arnoldi's differences are not enough where the map is not smooth at the orbit:
    on the Fig 12 grid (reduced, coupled scene) Dahl's direction turning round and
    nodes lifting off gave Ritz values of 1.61, 1.02, 0.986, 0.952 at k_v = 6, 45 deg
    for steps of 1e-5 to 1e-8, while a perturbation decayed by 0.983 a cycle. A
    perturbation can grow for a while before it decays (the slow modes fed by the
    others as those die out): at k_v = 3, 135 deg it grew by 1.0096 a cycle over
    cycles 10-40 and decayed by 0.993 a cycle from cycle 40 on, steadily to 160, and
    the stepped run settles there."""
    rng = np.random.default_rng(0)
    d = phi.gauge(rng.standard_normal(x.size))
    y = x + DECAY_AMPLITUDE * d / np.sqrt(np.mean(d * d))
    window = DECAY_CYCLES - DECAY_SKIP
    distances = []

    def run(cycles):
        nonlocal y
        for _ in range(cycles):
            y = phi(y)
            distances.append(float(np.sqrt(np.mean((y - x) ** 2))))
            if not math.isfinite(distances[-1]):
                return False
        return True

    if not run(DECAY_CYCLES) or distances[DECAY_SKIP - 1] == 0.0:
        return math.inf
    rate = (distances[-1] / distances[DECAY_SKIP - 1]) ** (1.0 / window)
    if rate < 1.0:
        return rate
    if not run(window):
        return math.inf
    return (distances[-1] / distances[DECAY_CYCLES - 1]) ** (1.0 / window)


def _smooth_map(phi: FECycleMap) -> FECycleMap:
    """The cycle map ``phi`` with the contact iteration converged to SMOOTH_ITERATION
    (implicit and reduced; the explicit step has no iteration), on the same scales."""
    run = phi.run
    tolerance = getattr(run, "iteration_tolerance", None)
    if tolerance is not None:
        run.iteration_tolerance = SMOOTH_ITERATION
    try:
        smooth = FECycleMap(run, phi.model, phi.steps)
    finally:
        if tolerance is not None:
            run.iteration_tolerance = tolerance
    smooth.scale = phi.scale
    if phi.on_cycle is not None:     # both maps report the cycles of both (progress)
        report = phi.on_cycle
        smooth.on_cycle = lambda cycles: report(phi.cycles + cycles)
        phi.on_cycle = lambda cycles: report(cycles + smooth.cycles)
    return smooth


def steady_table(orbit: Orbit, scene, cycles: int) -> np.ndarray:
    """``cycles`` repeats of the steady cycle's rows (recording.columns) ending at time.T,
    in the ground frame (x = the drive's frame's x + v_d t)."""
    n, dt = orbit.steps, orbit.dt
    table = np.tile(orbit.cycle, (cycles, 1))
    t = scene.time.T - cycles * n * dt + dt * np.arange(1, cycles * n + 1)
    table[:, 4] += scene.drive.v_d * (t - table[:, 0])
    table[:, 0] = t
    return table


def cycle_frames(phi: FECycleMap, orbit: Orbit, end_time: float, frame=None) -> State:
    """frame(State), if given, at FRAMES_PER_CYCLE + 1 evenly spaced steps of one steady
    cycle (its start and end included); returns the state at its end (FEResult.fields).

    The cycle map integrates the cycle one cycle after the vibration starts (steps
    i0 .. i0 + n); the states are shown as the cycle that ends at ``end_time``
    (time.T), as steady_table's rows: their times moved by shift = end_time - (i0 + n)
    dt, and the block translated by the drive's v_d shift in X (the orbit is periodic
    in the frame that moves with the drive); the base, periodic, is where it is at
    the same phase. So the last frame is at time.T exactly, where the series ends."""
    law = phi.scene.friction.law
    v_d = phi.scene.drive.v_d
    dt = phi.dt
    i0, n = phi.i0, phi.steps
    phi.load(orbit.z)
    c, scalars = phi.contact, phi.scalars

    def state(step):
        u, v = phi.started.fields()
        u = u.copy()
        u[0::3] += v_d * (end_time - (i0 + n) * dt)   # the drive's translation, X
        return phi.run.full_state(State(step, end_time - (i0 + n - step) * dt, u, v.copy(),
                                        c.state.copy(), law.deformation(c.state),
                                        c.normal.copy(), c.friction.copy(), scalars[XB],
                                        scalars[YB]))

    if frame is not None:
        frame(state(i0))
    marks = np.unique(np.linspace(0, n, FRAMES_PER_CYCLE + 1).round().astype(int))
    for a, b in zip(marks[:-1], marks[1:]):
        phi.started.steps(i0 + a + 1, i0 + b)
        if frame is not None:
            frame(state(i0 + b))
    return state(i0 + n)
