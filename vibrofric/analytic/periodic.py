"""The steady state directly: the periodic orbit of the lumped steppers by shooting.

Once the drive spring's transient has died out, the lumped model's motion is
periodic with the base's period P = 1/f in the frame that moves with the drive:
x - v_d t, the body's velocities, the friction force and the law's state return
to themselves after one base cycle (the transverse position y is not restrained
by any spring and only its increments enter the friction law, so it is left out).
Instead of stepping through the whole transient (600 base cycles on the Fig 7
scene to settle to 1e-4), we solve for that state z:

    R(z) = Phi(z) - z = 0,     Phi = one base cycle of the SAME discrete stepper

(coupled.coupled_loop / longitudinal.longitudinal_loop written from a given
state; the step is the one of the transient run, or the nearest one that puts a
whole number of steps in a cycle). So the periodic answer is the settled stepped
answer of the same scheme to the Newton tolerance: no new discretization error,
and every law works through the contract (its state is part of z).

Newton's matrix dR/dz = M - I is built by finite differences (one cycle per
unknown: the state has 5 + STATE_SIZE floats), the step is globalized by
backtracking on the scaled residual, and plain cycles are run where Newton stalls.
The eigenvalues of M, the cycle map's Jacobian, are the orbit's Floquet
multipliers: the orbit is stable (and what a long transient run settles to) when
all lie inside the unit circle; a multiplier on or outside it (near -1: period
doubling) is confirmed by following perturbations of the orbit over enough cycles
to tell its growth from a decay (core/orbit_decay.py: the differences of a map
with kinks can claim a multiplier the orbit does not have); an orbit they leave is
reported and not returned as the answer, one they return to is the answer, its
multiplier the decay seen.

A base moving along Z too (analytic/normal.py): NormalCycleMap, the state extended by
the body's z, dz/dt and normal force. Where the orbit loses contact the map is not
smooth (a landing moves by whole steps) and the bouncing body has coexisting steady
motions: an orbit out of contact whose stability only the decay check vouches for is
not the answer (NormalCycleMap.bounce, docs/periodic.md "The base moving along Z").

Time-domain shooting on a map of the integrator: Keller, "Numerical solution of
two point boundary value problems" (1976); for friction-damped systems e.g.
Peletan et al., Nonlinear Dyn. 78 (2014), who use harmonic balance alongside.
"""

import math
from time import perf_counter

import numpy as np

from ..core.base_motion import vibration_axis
from ..core.law_limits import divergence_force
from ..core.orbit_decay import perturbation_decay
from ..core.series import COLUMNS, PLOT_CYCLES, TimeSeries
from ..core.shooting import STABLE, Orbit, cycle_steps, instability
from ..friction_law import law_kernel
from ..friction_law.contract import FASTMATH
from . import coupled, normal
from .coupled import at_rest, coupled_loop
from .longitudinal import longitudinal_loop

# Positions in the shooting state z (the law's state follows).
X, VX, VY, FX, FY, LAW = range(6)
CARRIED = [coupled.X, coupled.VX, coupled.VY, coupled.FX, coupled.FY]  # their slots in the loops'
TOLERANCE = 1e-10        # converged: every scaled residual component below this (the state is
                         # scaled by its natural size, so this is ~1e-10 of F_c, of v_a, ...);
                         # one cycle's rounding leaves ~2e-11 (Fig 9 at k_v = 2 stalls there)
MAX_NEWTON = 40          # Newton iterations before giving up (each one 1 + n cycles)
FD_STEP = 1e-7           # finite-difference step, relative to each unknown's scale: about the
                         # square root of the rounding error of one cycle (~1e-14 relative)
PRESLIDE_STEPS = 1_000_000  # at most this many law updates to reach steady sliding (initial guess)


@law_kernel(cache=True, error_model="numpy", fastmath=FASTMATH)
def preslide(state, slip, F_N, params, dt, max_steps):
    """Slide the law's ``state`` in X by ``slip`` a step until its force stops changing
    (to 1e-14 of itself); returns the force. The initial guess of steady sliding."""
    f_old = math.inf
    f = 0.0
    for _ in range(max_steps):
        f, _ = law_update(slip, 0.0, 0.0, 0.0, F_N, 1.0, state, params, dt)  # noqa: F821
        if abs(f - f_old) <= 1e-14 * abs(f):
            break
        f_old = f
    return f


LOOPS = {"coupled": coupled_loop, "longitudinal": longitudinal_loop}


class CycleMap:
    """Phi: one base cycle of the scene's stepper, as a function of the shooting state.

    The state: X..FY (the loops' slots CARRIED), the law's state (``law_slots``), then
    the loop's further slots ``extra`` (none here; NormalCycleMap's z, dz/dt, N)."""

    extra = []          # the carried slots after the law's state in the shooting state
                        # (a list: numpy indexes by it as by one axis)
    columns = len(COLUMNS)

    def __init__(self, scene, stepper: str = "coupled"):
        self.scene = scene
        self.stepper = stepper
        self.steps, self.dt = cycle_steps(scene)
        law = scene.friction
        self.law = law
        self.params = law.params
        self.arguments = self._head()   # the loop's arguments before the law's state
        self.f_max = divergence_force(scene)
        self.cycles = 0
        self.law_slots = slice(LAW, LAW + law.law.initial_state(1).shape[1])
        self.size = self.law_slots.stop + len(self.extra)
        self._at_rest = self._rest()
        self._carried, self._no_rows = self._rest(), np.empty((0, self.columns))
        sample = self._arguments(law.law.initial_state(1)[0], self._carried, self.steps + 1,
                                 self._no_rows)
        self.loop = self._loop().prepared(law.law, sample, self._what())
        self.free = self._free_unknowns()
        self.scale = self._scales()

    def _head(self) -> tuple:
        """The loop's arguments before the law's state: the cycle starts at t_on = 0."""
        s = self.scene
        head = (s.body.mass, s.drive.k_d, s.drive.v_d, s.drive.prescribed, s.u0, s.omega, 0.0)
        if self.stepper == "coupled":
            head += (*vibration_axis(s.vibration.theta_deg), s.contact.eta_y)
        return (*head, s.contact.F_N)

    def _rest(self) -> np.ndarray:
        return at_rest()

    def _loop(self):
        return LOOPS[self.stepper]

    def _what(self) -> str:
        return f"the {self.stepper} analytic stepper"

    def bounce(self, cycle: np.ndarray) -> str:
        """Why an orbit with this cycle, judged stable only by the decay of its
        perturbations, is not the answer ("" where it may be): see NormalCycleMap."""
        return ""

    def from_neighbour(self, z: np.ndarray) -> np.ndarray:
        """The start from a neighbouring sweep point's orbit ``z``: that orbit itself."""
        return z

    def _free_unknowns(self) -> np.ndarray:
        """The unknowns the map acts on: a prescribed drive fixes x and the velocities;
        the 1D stepper has no transverse velocity or force."""
        free = np.ones(self.size, dtype=bool)
        if self.scene.drive.prescribed:
            free[[X, VX, VY]] = False
        if self.stepper == "longitudinal":
            free[[VY, FY]] = False
        return np.flatnonzero(free)

    def _scales(self) -> np.ndarray:
        """Each unknown's natural size: the Coulomb force, the spring's stretch under it,
        the fastest velocity, and for the law's state its steady-sliding values."""
        s = self.scene
        F_c = max(s.F_c, 1e-300) if s.F_c > 0 else 1.0
        scale = np.empty(self.size)
        scale[X] = F_c / s.drive.k_d
        scale[VX] = scale[VY] = max(s.drive.v_d, s.v_a)
        scale[FX] = scale[FY] = F_c
        sliding = self.sliding_state()[self.law_slots]
        law_scale = max(float(np.max(np.abs(sliding))), 1e-300) if sliding.size else 1.0
        scale[self.law_slots] = np.maximum(np.abs(sliding), 1e-3 * law_scale)
        return scale

    def __call__(self, z: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
        """Phi(z): one cycle of the stepper's own loop (coupled.coupled_loop or
        longitudinal.longitudinal_loop, t from the cycle's start, the base at phase
        zero) from ``z``; NaN where the law's force diverged. With ``out`` ((steps,
        columns) rows), every step's row is kept, x in the drive's frame."""
        self.cycles += 1
        carried = self._carried
        carried[:] = self._at_rest
        carried[CARRIED] = z[:LAW]
        carried[self.extra] = z[self.law_slots.stop:]
        state = z[self.law_slots].copy()
        keep_from = 1 if out is not None else self.steps + 1   # every step, or none
        rows = out if out is not None else self._no_rows
        failed = self.loop(*self._arguments(state, carried, keep_from, rows))
        if failed:
            return np.full_like(z, np.nan)
        if out is not None:
            out[:, 4] -= self.scene.drive.v_d * out[:, 0]
        end = np.empty_like(z)
        end[X] = carried[coupled.X] - self.scene.drive.v_d * self.steps * self.dt
        end[VX:LAW] = carried[CARRIED[1:]]
        end[self.law_slots] = state
        end[self.law_slots.stop:] = carried[self.extra]
        return end

    def _arguments(self, state, carried, keep_from, rows) -> tuple:
        """The loop's arguments for steps 1..steps, keeping rows from step ``keep_from``."""
        return (*self.arguments, state, self.params, self.dt, 1, self.steps, self.steps + 1,
                keep_from, self.f_max, carried, rows)

    def sliding_state(self) -> np.ndarray:
        """Steady sliding at v_d without vibration: the initial guess (eq 17 with F = F_d0)."""
        s = self.scene
        state = self.law.law.initial_state(1)[0].copy()
        v_d = s.drive.v_d
        args = (state, v_d * self.dt, s.contact.F_N, self.params, self.dt, PRESLIDE_STEPS)
        f = preslide.prepared(self.law.law, args, "the pre-sliding steps")(*args)
        z = np.zeros(self.size)
        z[X] = 0.0 if s.drive.prescribed else -f / s.drive.k_d - v_d * self.dt
        z[VX] = v_d
        z[FX] = f
        z[self.law_slots] = state
        return z

    def residual(self, z: np.ndarray) -> tuple:
        """(Phi(z), (Phi(z) - z) / scale on the free unknowns, its largest modulus)."""
        phi_z = self(z)
        r = ((phi_z - z) / self.scale)[self.free]
        norm = float(np.max(np.abs(r))) if np.all(np.isfinite(r)) else math.inf
        return phi_z, r, norm

    def jacobian(self, z: np.ndarray, phi_z: np.ndarray) -> np.ndarray:
        """d Phi / dz on the free unknowns, in scaled variables, by forward differences
        from ``phi_z`` = Phi(z) (one cycle per unknown)."""
        n = self.free.size
        M = np.empty((n, n))
        for k, j in enumerate(self.free):
            h = FD_STEP * max(abs(z[j]), self.scale[j])
            plus = z.copy()
            plus[j] += h
            column = (self(plus) - phi_z) / h * self.scale[j] / self.scale
            M[:, k] = column[self.free]
        return M


class NormalCycleMap(CycleMap):
    """Phi of a scene whose base moves along Z too: one cycle of normal.normal_loop
    (for the 1D stepper with sin theta = eta_y = 0: its X motion alone). The shooting
    state adds the body's z and dz/dt and the contact's normal force N of the cycle's
    last step (the loop's slots normal.Z, VZ, N), so the orbit is periodic in the
    normal motion as in the rest. The loop does not put the body on its forced
    response at the cycle's start (NO_START): the state says where it is."""

    extra = [normal.Z, normal.VZ, normal.N]
    columns = len(COLUMNS) + len(normal.NORMAL_COLUMNS)
    N_COLUMN = len(COLUMNS) + normal.NORMAL_COLUMNS.index("N")   # N in the cycle's rows
    NO_START = -1       # normal_loop's step that puts the body on its forced response: none

    def _head(self) -> tuple:
        s, vib = self.scene, self.scene.vibration
        cos_theta, sin_theta = vibration_axis(vib.theta_deg)
        eta_y = s.contact.eta_y
        if self.stepper == "longitudinal":
            sin_theta, eta_y = 0.0, 0.0
        return (s.body.mass, s.drive.k_d, s.drive.v_d, s.drive.prescribed, s.u0, s.omega, 0.0,
                cos_theta, sin_theta, eta_y, s.contact.F_N, s.normal_stiffness,
                normal.contact_damping(s), vib.normal_amplitude,
                math.radians(vib.normal_phase_deg or 0.0), *normal.start_gain(s), self.NO_START,
                *normal.motion_table(s, self.dt, 0.0, self.steps))

    def _rest(self) -> np.ndarray:
        return normal.normal_at_rest(self.scene.contact.F_N)

    def _loop(self):
        return normal.normal_loop

    def _what(self) -> str:
        return "the analytic stepper with normal motion"

    def _scales(self) -> np.ndarray:
        """CycleMap's; z by the larger of the base's amplitude and the contact's static
        penetration F_N / k_n, dz/dt by w times that, N by F_N."""
        scale = super()._scales()
        s = self.scene
        length = max(s.vibration.normal_amplitude, s.contact.F_N / s.normal_stiffness)
        scale[self.law_slots.stop:] = (length, s.omega * length, max(s.contact.F_N, 1e-300))
        return scale

    def bounce(self, cycle: np.ndarray) -> str:
        """Why an orbit that loses contact, judged stable by the decay of perturbations
        where the Jacobian claimed a multiplier beyond the unit circle, is not the answer.

        Out of contact the cycle map is not smooth: the step a landing falls on moves by
        whole steps, so finite differences across it are not a derivative (on the paper's
        block at 1.75e-7 m the Jacobian claimed a multiplier 4.2 that perturbations did not
        show). And the bouncing body has coexisting steady motions: there the stepped run
        from the forced start went on to bounce off 96% of the time, never settling, while
        the shooting found an orbit out of contact 23% of it (docs/periodic.md). An orbit
        whose multipliers alone judge it stable (a short loss of contact, the map smooth
        enough) remains the answer: at 1.7e-7 m, 5% out of contact, it matched the stepped
        run's settled answer to 2e-13."""
        lost = float(np.mean(cycle[:, self.N_COLUMN] <= 0.0))
        if lost == 0.0:
            return ""
        return (f"the orbit loses contact over {lost:.1%} of its cycle, where the cycle map is not "
                f"smooth and the bouncing body has other steady motions: the shooting's need not "
                f"be the one a stepped run reaches")

    def from_neighbour(self, z: np.ndarray) -> np.ndarray:
        """The neighbour's orbit with this scene's start of the normal motion
        (sliding_state's z, dz/dt, N). The body's normal motion does not depend on the
        in-plane one, so a neighbour's is no better a guess, and where the normal
        motion differs (another phase or amplitude) a worse one: from it, a sweep over
        the phase at 45 degree steps (A_n half the amplitude of contact loss, the
        coupled scene) found a bouncing orbit, out of contact 86% of the cycle, at two
        of eight phases, where the stepped run and the forced start keep contact."""
        z = z.copy()
        z[self.law_slots.stop:] = self.sliding_state()[self.law_slots.stop:]
        return z

    def sliding_state(self) -> np.ndarray:
        """CycleMap's, the body on its forced response in contact at the cycle's start
        (normal.start_gain; the base at phase phi) holding N = F_N."""
        z = super().sliding_state()
        vib, w = self.scene.vibration, self.scene.omega
        phase = math.radians(vib.normal_phase_deg or 0.0)
        z_b = vib.normal_amplitude * math.sin(phase)
        v_b = vib.normal_amplitude * w * math.cos(phase)
        gain_re, gain_im = normal.start_gain(self.scene)
        z[self.law_slots.stop:] = (gain_re * z_b + gain_im * v_b / w,
                                   gain_re * v_b - gain_im * w * z_b, self.scene.contact.F_N)
        return z


def cycle_map(scene, stepper: str = "coupled") -> CycleMap:
    """The scene's cycle map: NormalCycleMap where its base moves along Z."""
    return (NormalCycleMap if normal.moves_normally(scene) else CycleMap)(scene, stepper)


def _update(z, step, free, scale):
    new = z.copy()
    new[free] += step * scale[free]
    return new


def find_orbit(scene, stepper: str = "coupled", start: np.ndarray | None = None,
               plain_cycles: int = 2, judge: bool = True,
               jacobian: np.ndarray | None = None) -> Orbit:
    """Shoot for the periodic steady state of the scene's lumped model.

    ``start``: a state to begin from (a neighbouring sweep point's orbit: continuation),
    else steady sliding without vibration. ``plain_cycles`` plain cycles are run first
    (they damp the fast components cheaply). ``judge``: compute the Floquet multipliers
    and judge the orbit's stability (without: the orbit at a halved step of one already
    judged, analytic/accuracy.py; it is taken as stable where it converged).
    ``jacobian``: the cycle map's Jacobian (scaled free unknowns) of a neighbouring
    problem, Newton's first matrix instead of finite differences (the orbit at dt
    for those at dt/2 and dt/4: the map changes little; Broyden's updates and a
    fresh Jacobian where its step fails correct it). Never
    raises on non-convergence: the Orbit says whether it converged and whether it is
    stable.
    """
    phi = cycle_map(scene, stepper)
    begin = perf_counter()
    if start is not None and np.shape(start) != (phi.size,):
        start = None        # a neighbour of another state's layout (with or without normal motion)
    z = phi.sliding_state() if start is None else phi.from_neighbour(np.array(start, dtype=float))
    for _ in range(plain_cycles):
        z_next = phi(z)
        if not np.all(np.isfinite(z_next)):
            break
        z = z_next
    free, scale = phi.free, phi.scale
    phi_z, r, norm = phi.residual(z)
    iterations = 0
    reason = ""
    A = None            # the Newton matrix M - I: finite differences, then Broyden updates
    if jacobian is not None and jacobian.shape == (free.size, free.size):
        A = jacobian - np.eye(free.size)
    rose = False        # the last accepted step raised the residual (watchdog, below)
    watch = math.inf    # the residual before that rise: the next step must go below it
    while norm > TOLERANCE and iterations < MAX_NEWTON:
        iterations += 1
        if A is None:
            M = phi.jacobian(z, phi_z)
            if not np.all(np.isfinite(M)):
                reason = "the cycle diverged near the trial state"
                break
            A = M - np.eye(free.size)
            fresh = True
        else:
            fresh = False
        step = np.linalg.lstsq(A, -r, rcond=None)[0]
        accepted = False
        lam = 1.0
        for _ in range(12):
            trial = _update(z, lam * step, free, scale)
            phi_t, r_t, norm_t = phi.residual(trial)
            # A full step may raise the residual once if the next one falls below where
            # it rose from (a watchdog: a law state such as Dahl's direction flips where
            # its length crosses zero, so the residual of the representation jumps
            # while the force stays continuous); otherwise backtrack.
            if (norm_t < (1.0 - 1e-4 * lam) * norm or norm_t < (1.0 - 1e-4) * watch
                    or (lam == 1.0 and not rose and math.isfinite(norm_t))):
                accepted = True
                break
            lam *= 0.5
        if accepted:
            s_step = lam * step
            if norm_t < 0.5 * norm and math.isfinite(norm_t):   # Broyden's update (good)
                A = A + np.outer(r_t - r - A @ s_step, s_step) / (s_step @ s_step)
            else:                                                # slow: a fresh Jacobian
                A = None
            rose = norm_t >= norm
            watch = norm if rose else math.inf
            z, phi_z, r, norm = trial, phi_t, r_t, norm_t
        elif fresh:           # Newton stalls: a few plain cycles move on, then try again
            for _ in range(4):
                z = phi(z)
            phi_z, r, norm = phi.residual(z)
            A = None
            if not math.isfinite(norm):
                reason = "the cycle diverged"
                break
        else:
            A = None          # Broyden's matrix led nowhere: a fresh Jacobian
    converged = norm <= TOLERANCE
    multipliers = np.empty(0)
    vectors = np.empty((free.size, 0))
    M = None
    if converged and judge:
        M = phi.jacobian(z, phi_z)   # at the orbit itself: its Floquet multipliers
        if np.all(np.isfinite(M)):
            multipliers, vectors = np.linalg.eig(M)
            order = np.argsort(-np.abs(multipliers))
            multipliers, vectors = multipliers[order], vectors[:, order]
        else:   # a difference step left the stepper's range: no verdict, so not the answer
            reason = "the cycle diverged near the orbit: its Floquet multipliers are unknown"
    elif not converged:
        reason = reason or f"Newton did not reach {TOLERANCE:g} in {MAX_NEWTON} iterations"
    extra = {"start": "steady sliding" if start is None else "neighbour"}
    stable = (converged and not reason
              and bool(multipliers.size == 0 or np.max(np.abs(multipliers)) < STABLE))
    if converged and not stable and not reason:
        reason = instability(multipliers, STABLE)
        decay = confirm_by_decay(phi, z, multipliers, vectors)
        claimed = float(np.abs(multipliers[0]))
        growth_claimed = claimed >= 1.0 + (1.0 - STABLE)   # not merely on the unit circle
        if decay.verdict == "grows" or (decay.verdict == "neutral" and not growth_claimed):
            reason += f"; confirmed: {decay.note}"
        else:
            # a decay, or no growth where growth was claimed: the perturbations stay
            # bounded and the claimed multiplier is not the orbit's; the multiplier
            # reported is the slowest decay seen (~1 where it was not separated from 1)
            extra["floquet_note"] = (f"the Jacobian's largest multiplier {claimed:.6g} not "
                                     f"confirmed: {decay.note}")
            multipliers, stable, reason = np.array([decay.rate]), True, ""
    cycle = np.empty((phi.steps, phi.columns))
    if converged:
        phi(z, cycle)
    if stable and "floquet_note" in extra:
        bounce = phi.bounce(cycle)
        if bounce:      # the multipliers are not the orbit's, and it need not be the attractor
            stable, reason = False, f"{bounce}; {extra.pop('floquet_note')}"
    return Orbit(converged, stable, z, cycle, iterations, phi.cycles, norm, multipliers,
                 phi.dt, phi.steps, perf_counter() - begin, reason, extra,
                 M if M is not None and np.all(np.isfinite(M)) else None)


def confirm_by_decay(phi: CycleMap, z: np.ndarray, multipliers: np.ndarray,
                     vectors: np.ndarray):
    """core.orbit_decay.perturbation_decay on the orbit ``z``: perturbations along the
    eigenvectors of the multipliers on or beyond the unit circle (real and imaginary
    parts; the Jacobian's, scaled free unknowns) and a random direction."""
    free, scale = phi.free, phi.scale

    def cycle(x):
        full = z.copy()
        full[free] = x * scale[free]
        return phi(full)[free] / scale[free]

    leading = vectors[:, np.abs(multipliers) >= STABLE]
    directions = np.column_stack([leading.real, leading.imag])
    return perturbation_decay(cycle, z[free] / scale[free], directions,
                              float(np.abs(multipliers[0])))


def load_cycle(scene, stepper: str = "coupled") -> None:
    """Compile (or load from numba's cache) the cycle kernels for the scene's law."""
    phi = cycle_map(scene, stepper)
    phi(phi.sliding_state())


def steady_series(orbit: Orbit, scene, cycles: int = PLOT_CYCLES) -> TimeSeries:
    """``cycles`` repeats of the steady cycle ending at time.T, in the ground frame
    (x = x - v_d t + v_d t; y and the base as in one cycle), for outputs and plots."""
    n, dt = orbit.steps, orbit.dt
    table = np.tile(orbit.cycle, (cycles, 1))
    start = scene.time.T - cycles * n * dt
    t = start + dt * np.arange(1, cycles * n + 1)
    table[:, 0] = t
    table[:, 4] += scene.drive.v_d * t
    return TimeSeries.from_table(table, normal.NORMAL_COLUMNS[:table.shape[1] - len(COLUMNS)])
