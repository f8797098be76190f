"""Shooting for a periodic steady state: what the lumped and the FE solvers share.

A model stepped by a fixed discrete scheme and driven with the base's period P
has, once its transient has died out, a state z that one base cycle of the
same scheme returns to itself (in the frame that moves with the drive):

    R(z) = Phi(z) - z = 0,        Phi = one base cycle of the stepper

(analytic/periodic.py for the lumped steppers, fem/integrators/periodic.py for the FE
integrators). Here: the whole number of steps a cycle takes, the Orbit and its
summary block, the judgement of the Floquet multipliers (the eigenvalues of
dPhi/dz at the orbit), and, for states too large for a finite-difference
Jacobian (the FE integrators), newton_picard: Newton on the few slowest
directions, plain cycles on the rest, Anderson-accelerated; and
largest_multipliers: Arnoldi on directional derivatives
J d ~ (Phi(z + h d) - Phi(z)) / h, one cycle each.

Plain Newton-Krylov (GMRES on those products from the start) was tried first on
the FE map and did not converge from steady sliding: the contact's kinks
(nodes lifting off, Dahl's direction turning) make the full Newton step
overshoot, while the slow drive mode, which alone makes the transient long, is
smooth. Largest Floquet multipliers as Ritz values of the cycle map's Jacobian:
Sanchez, Net, Garcia-Archilla & Simo, J. Comput. Phys. 201 (2004).
"""

import math
from dataclasses import dataclass, field

import numpy as np

STABLE = 1.0 - 1e-6      # a Floquet multiplier modulus at or above this is not a stable orbit
# newton_picard starts afresh (its Newton matrix retaken, Anderson's history dropped) where
# the residual exceeds ASTRAY times its best, or has not improved on it for STALL
# iterations. Over ten FE cases from steady sliding (Fig 7 and nine of the Fig 12 grid,
# reduced) the cycles came to 1039 with a restart wherever the residual doubled (each
# restart throws away the history that accelerates the tail), 478 with ASTRAY 20 (the
# same for 50 and never), 474 with STALL 8; without STALL, LuGre on Fig 7 cycled among
# three states (residuals 4.7e-4, 7.7e-4, 9.6e-4) until the cycles ran out. A return to a
# state met since the last start (its residual the same to the bit: the map is
# deterministic) after Anderson's history was dropped on the way (a failed trial) is
# such a cycle for certain: nothing has changed that could lead elsewhere, so it restarts
# at once rather than after STALL iterations. (A return with the history kept is left to
# Anderson, whose next combination can break the cycle.) An iterate is refused where its
# residual is beyond ASTRAY times the best, where the next iteration would start afresh:
# Anderson's combinations short of that mostly lead on. (Cycles measured with each choice:
# docs/performance.md, "Design choices measured".)
ASTRAY = 20.0
STALL = 8
MARGIN = 0.1     # largest_multipliers: settled to this fraction of the distance to the unit circle


def cycle_steps(scene) -> tuple:
    """(n, dt): the whole number of steps n of one base cycle nearest 1/(f time.dt),
    and the step that puts exactly n in a cycle (time.dt itself where 1/(f dt) is whole)."""
    exact = 1.0 / (scene.vibration.f * scene.time.dt)
    n = max(1, int(round(exact)))
    if abs(exact - n) <= 1e-9 * exact:
        return n, scene.time.dt
    return n, 1.0 / (scene.vibration.f * n)


def period_doubling(multipliers: np.ndarray) -> bool:
    """The largest multiplier (``multipliers`` largest modulus first) is real and at or
    beyond -1: a period-2 response branches off here."""
    if not multipliers.size:
        return False
    lead = multipliers[0]
    return bool(abs(lead.imag) < 1e-6 and lead.real <= -STABLE)


def instability(multipliers: np.ndarray, stable: float = STABLE) -> str:
    """Why an orbit with these multipliers (largest modulus first) is not the answer,
    or "" where every one lies inside the unit circle (moduli below ``stable``)."""
    if not multipliers.size:
        return ""
    modulus = float(abs(multipliers[0]))
    if modulus < stable:
        return ""
    if period_doubling(multipliers):
        kind = "unstable by period doubling (a multiplier beyond -1)"
    elif modulus < 1.0 + 1e-6:
        kind = "not attracting (a multiplier on the unit circle: an undamped mode)"
    else:
        kind = "unstable"
    return f"the periodic orbit is {kind}: largest Floquet multiplier modulus {modulus:.6g}"


@dataclass
class Orbit:
    """What a shooting found (analytic/periodic.py, fem/integrators/periodic.py).

    converged            Newton's residual reached its tolerance
    stable               every Floquet multiplier inside the unit circle (STABLE)
    z                    the state at the start of a cycle (the solver's own layout)
    cycle                (steps, columns) the steady cycle's recorded rows
    newton_iterations, cycles_integrated, residual (the solver's measure of R)
    floquet              the multipliers, largest modulus first (FE: the largest few)
    dt, steps            the step used and steps in a cycle
    solver_time_s        the shooting's wall time (compiled code loaded before)
    reason               why it is not the answer ("" where it is)
    extra                {"start": "steady sliding" or "neighbour" (a sweep's continuation),
                         "floquet_note": how the stability was judged, where not by the
                         multipliers alone}
    jacobian             dPhi/dz at the orbit in the solver's scaled unknowns, where it was
                         formed (the lumped model's); a finer step's Newton starts from it
    """

    converged: bool
    stable: bool
    z: np.ndarray
    cycle: np.ndarray
    newton_iterations: int
    cycles_integrated: int
    residual: float
    floquet: np.ndarray
    dt: float
    steps: int
    solver_time_s: float = 0.0
    reason: str = ""
    extra: dict = field(default_factory=dict)
    jacobian: np.ndarray | None = None

    @property
    def floquet_max_modulus(self) -> float:
        return float(np.max(np.abs(self.floquet))) if self.floquet.size else math.nan

    @property
    def period_doubling(self) -> bool:
        """The largest multiplier near -1: a period-2 response branches off here."""
        return period_doubling(self.floquet)


def periodic_block(orbit, scene) -> dict:
    """The summary's "periodic" block: how the shooting went (Orbit, or None
    where it was not tried) and which method produced the answer."""
    if orbit is None:
        return {"method": "transient", "converged": False, "newton_iterations": 0,
                "cycles_integrated": 0, "residual": None, "floquet_max_modulus": None,
                "dt": scene.time.dt, "steps_per_cycle": None,
                "reason": ("a measured base motion that ends (vibration.motion_periodic "
                           "false) has no periodic orbit" if scene.vibrated
                           else "no vibration: the steady state is steady sliding")}
    periodic = orbit.converged and orbit.stable
    return {"method": "periodic" if periodic else "transient",
            "converged": orbit.converged,
            "stable": orbit.stable if orbit.converged else None,
            "newton_iterations": orbit.newton_iterations,
            "cycles_integrated": orbit.cycles_integrated,
            "residual": float(orbit.residual) if math.isfinite(orbit.residual) else None,
            "floquet_max_modulus": (float(orbit.floquet_max_modulus) if orbit.floquet.size else None),
            "period_doubling": orbit.period_doubling,
            "dt": float(orbit.dt),
            "dt_adjusted": bool(orbit.dt != scene.time.dt),
            "steps_per_cycle": orbit.steps,
            "start": orbit.extra.get("start", "steady sliding"),
            **({"floquet_note": orbit.extra["floquet_note"]}
               if "floquet_note" in orbit.extra else {}),
            "reason": orbit.reason}


def rms(r: np.ndarray) -> float:
    """The root mean square of a scaled residual; inf where it is not finite."""
    value = float(np.sqrt(np.mean(r * r))) if r.size else 0.0
    return value if math.isfinite(value) else math.inf


@dataclass
class Shot:
    """What newton_picard found: the state, Phi of it, the residual's RMS, the
    iterations, the cycles integrated, and why it stopped where it did not converge."""

    z: np.ndarray
    phi_z: np.ndarray
    residual: float
    iterations: int
    cycles: int
    converged: bool
    reason: str = ""


def _arnoldi(product, start: np.ndarray, steps: int, stop=None):
    """Arnoldi's process on the linear map ``product`` from ``start``: (V, H, k) with
    V (n, k + 1) orthonormal and H (k + 1, k) upper Hessenberg, product(V_k) = V H.
    ``stop(V, H, k)`` may end it early (True). Modified Gram-Schmidt, twice."""
    n = start.size
    V = np.zeros((n, steps + 1))
    H = np.zeros((steps + 1, steps))
    V[:, 0] = start / np.linalg.norm(start)
    k = 0
    for k in range(1, steps + 1):
        w = product(V[:, k - 1])
        for _ in range(2):
            for j in range(k):
                c = V[:, j] @ w
                H[j, k - 1] += c
                w -= c * V[:, j]
        H[k, k - 1] = np.linalg.norm(w)
        if H[k, k - 1] <= 1e-14 * max(1.0, np.abs(H[:k, k - 1]).max()):
            return V[:, :k + 1], H[:k + 1, :k], k      # an invariant subspace: exact
        V[:, k] = w / H[k, k - 1]
        if stop is not None and stop(V, H, k):
            break
    return V[:, :k + 1], H[:k + 1, :k], k


def newton_picard(cycle, x: np.ndarray, slow: np.ndarray, slow_step, tolerance: float,
                  max_cycles: int, memory: int = 20) -> Shot:
    """Solve cycle(x) = x (scaled variables) where a few known directions decay slowly.

    ``slow`` (n, p): directions spanning the map's slowest modes (the FE model: the
    block's rigid motion on the drive spring, multiplier ~0.985 a cycle on Fig 7,
    which makes the stepped transient take ~1000 cycles). On their span, Newton:
    the p x p matrix H = S^T J S by forward differences of ``slow_step`` (one step,
    or one for each of the p directions) along each (one cycle each: a step large
    against the map's roughness, the contact iteration's tolerance, and still in
    its linear range); on the rest, plain cycles (Picard): the Newton-Picard
    splitting of Lust, Roose, Spence & Champneys, SIAM J. Sci. Comput. 19 (1998).
    That iteration

        T(x) = x + (I - S S^T) r + S dp,    (H - I) dp = -S^T r,    r = cycle(x) - x

    is accelerated by Anderson's mixing over the last ``memory`` iterates (Anderson,
    J. ACM 12, 1965; Walker & Ni, SIAM J. Numer. Anal. 49, 2011): the next x is
    the combination of the T's whose residuals' combination is least. Where the
    residual grows to ASTRAY times its best or has not improved on it for STALL
    iterations, H is taken afresh there and the history dropped (H taken far from
    the orbit can send the slow modes astray; Anderson's combinations on a map with
    kinks can cycle); where the stepper fails from the combined state, the plain
    step is taken. Converged:
    the RMS of r at most ``tolerance``; at most ``max_cycles`` cycles.
    """
    cycles = 0

    def phi(y):
        nonlocal cycles
        cycles += 1
        return cycle(y)

    S, _ = np.linalg.qr(slow)
    steps = np.broadcast_to(np.asarray(slow_step, dtype=float), (S.shape[1],))

    def newton_matrix(y, g_y):
        """H - I, H = S^T J S at y by forward differences (p cycles)."""
        H = np.column_stack([(phi(y + h * S[:, j]) - g_y) / h for j, h in enumerate(steps)])
        if not np.all(np.isfinite(H)):     # the stepper failed: plain cycles there too
            return -np.eye(S.shape[1])
        return S.T @ H - np.eye(S.shape[1])

    g = phi(x)
    newton = newton_matrix(x, g)
    xs, ts = [], []
    best, best_g, since_best = math.inf, g, 0
    visited = {}            # residual met since the last start -> drops of the history before
    drops = 0               # the times a failed trial dropped Anderson's history
    iterations = 0
    reason = ""
    while True:
        r = g - x
        norm = rms(r)
        if not math.isfinite(norm):
            reason = "the cycle diverged"
            break
        if norm <= tolerance:
            break
        if cycles >= max_cycles:
            reason = (f"Newton-Picard did not reach {tolerance:g} in {max_cycles} cycles "
                      f"(residual {norm:.3g})")
            break
        if norm < best:
            best_g, since_best = g, 0
        else:
            since_best += 1
        cycling = visited.get(norm, drops) < drops     # back, the history dropped since
        if norm > ASTRAY * best or since_best > STALL or cycling:
            # Astray (the slow modes' multipliers have moved since H was taken far from
            # the orbit, or Anderson's combination overshot), or stalled or back at a
            # state met before (the iteration cycling among the same few states): H
            # afresh here, history dropped.
            newton = newton_matrix(x, g)
            xs, ts = [], []
            best, since_best = norm, 0
            visited.clear()
        visited.setdefault(norm, drops)
        best = min(best, norm)
        iterations += 1
        dp = np.linalg.solve(newton, -(S.T @ r))
        t = x + r - S @ (S.T @ r) + S @ dp
        xs.append(x)
        ts.append(t)
        xs, ts = xs[-(memory + 1):], ts[-(memory + 1):]
        accelerated = t
        if len(xs) > 1:
            F = np.array(ts).T - np.array(xs).T        # T(x) - x of each kept iterate
            gamma, *_ = np.linalg.lstsq(np.diff(F, axis=1), F[:, -1], rcond=None)
            accelerated = ts[-1] - np.diff(np.array(ts).T, axis=1) @ gamma
        # Where the stepper fails from the accelerated state (its contact iteration, far
        # from the orbit) or it lands astray (where the next iteration would start afresh),
        # the plain Newton-Picard step, a plain cycle, or a plain cycle from the best state
        # so far, instead.
        for trial in (accelerated, t, g, best_g):
            g_trial = phi(trial)
            if np.all(np.isfinite(g_trial)) and rms(g_trial - trial) <= ASTRAY * best:
                break
            xs, ts = [], []
            drops += 1
        x, g = trial, g_trial
    return Shot(x, g, norm, iterations, cycles, norm <= tolerance, reason)


def largest_multipliers(cycle, z: np.ndarray, phi_z: np.ndarray, fd_step: float,
                        steps: int = 30, settle: float = 1e-4, margin: float = MARGIN,
                        seed: int = 0):
    """(multipliers largest modulus first, cycles integrated): the Ritz values of the
    cycle map's Jacobian at ``z`` (Arnoldi on forward-difference products, from a
    reproducible random start; [inf] where the stepper failed in one), stopped (after
    at least 5 products) once the largest modulus rho changes by at most ``settle``
    rho from one product to the next, or by at most ``margin`` |1 - rho| over each of
    the last two: settled well enough to say on which side of the unit circle it
    lies, the verdict it is taken for."""
    h = fd_step * max(1.0, float(np.sqrt(np.mean(z * z))))
    count = 0

    def jacobian(d):
        nonlocal count
        count += 1
        product = (cycle(z + h * d) - phi_z) / h    # |d| = 1: Arnoldi's vectors are unit
        if not np.all(np.isfinite(product)):
            raise _Failed
        return product

    history = []

    def settled(V, H, k):
        ritz = np.linalg.eigvals(H[:k, :k])
        history.append(float(np.abs(ritz).max()))
        if k < 5:
            return False
        rho = history[-1]
        change = np.abs(np.diff(history[-3:]))
        return bool(change[-1] <= settle * rho or np.all(change <= margin * abs(1.0 - rho)))

    start = np.random.default_rng(seed).standard_normal(z.size)
    try:
        V, H, k = _arnoldi(jacobian, start, steps, settled)
    except _Failed:         # the stepper failed from a perturbed orbit: nothing is judged
        return np.array([math.inf]), count
    ritz = np.linalg.eigvals(H[:k, :k])
    return ritz[np.argsort(-np.abs(ritz))], count


class _Failed(Exception):
    """The stepper failed in one of largest_multipliers' products."""
