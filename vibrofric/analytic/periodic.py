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
from ..core.series import PLOT_CYCLES, TimeSeries
from ..core.shooting import STABLE, Orbit, cycle_steps, instability
from ..friction_law import law_kernel
from ..friction_law.contract import FASTMATH
from . import coupled
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
    """Phi: one base cycle of the scene's stepper, as a function of the shooting state."""

    def __init__(self, scene, stepper: str = "coupled"):
        self.scene = scene
        self.stepper = stepper
        self.steps, self.dt = cycle_steps(scene)
        law = scene.friction
        self.law = law
        self.params = law.params
        s = scene
        head = (s.body.mass, s.drive.k_d, s.drive.v_d, s.drive.prescribed, s.u0, s.omega, 0.0)
        if stepper == "coupled":
            head += (*vibration_axis(s.vibration.theta_deg), s.contact.eta_y)
        self.arguments = (*head, s.contact.F_N)    # the loop's arguments before the law's state
        self.f_max = divergence_force(scene)
        self.cycles = 0
        self.size = LAW + law.law.initial_state(1).shape[1]
        self._at_rest, self._carried, self._no_rows = at_rest(), at_rest(), np.empty((0, 8))
        sample = self._arguments(law.law.initial_state(1)[0], self._carried, self.steps + 1,
                                 self._no_rows)
        self.loop = LOOPS[stepper].prepared(law.law, sample, f"the {stepper} analytic stepper")
        self.free = self._free_unknowns()
        self.scale = self._scales()

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
        sliding = self.sliding_state()[LAW:]
        law_scale = max(float(np.max(np.abs(sliding))), 1e-300) if sliding.size else 1.0
        scale[LAW:] = np.maximum(np.abs(sliding), 1e-3 * law_scale)
        return scale

    def __call__(self, z: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
        """Phi(z): one cycle of the stepper's own loop (coupled.coupled_loop or
        longitudinal.longitudinal_loop, t from the cycle's start, the base at phase
        zero) from ``z``; NaN where the law's force diverged. With ``out`` ((steps, 8)
        rows), every step's row is kept, x in the drive's frame."""
        self.cycles += 1
        carried = self._carried
        carried[:] = self._at_rest
        carried[CARRIED] = z[:LAW]
        state = z[LAW:].copy()
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
        end[LAW:] = state
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
        z[LAW:] = state
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
    phi = CycleMap(scene, stepper)
    begin = perf_counter()
    z = phi.sliding_state() if start is None else np.array(start, dtype=float)
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
    cycle = np.empty((phi.steps, 8))
    if converged:
        phi(z, cycle)
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
    phi = CycleMap(scene, stepper)
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
    return TimeSeries.from_table(table)
