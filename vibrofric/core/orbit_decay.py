"""Whether a periodic orbit attracts: small perturbations' sizes followed over cycles.

A finite-difference Jacobian of the cycle map is a poor judge where the map has
kinks at the orbit (Dahl's direction turning, the stick-slip switch): the lumped
model on the coupled scene with k_t = 6.729e9 N/m, k_v = 1, theta 0 gave a
multiplier of -1.136 ("period doubling") for an orbit that a stepped run settles
to (F_dv/F_d0 1.0000 after 5 s, the orbit's own mean) and that no perturbation
leaves. So a verdict that rejects an orbit is checked by plain cycles from
perturbed orbits, as a stepped run would go: along the eigenvectors of the
multipliers the Jacobian claims (their real and imaginary parts) and along a
reproducible random direction, each of RMS AMPLITUDE in the scaled unknowns.

Each perturbation's distance from the orbit is followed by its envelope, the
largest distance over BLOCK cycles (a slow mode oscillates: at one cycle the
distance can be ten times below its envelope), against the envelope of the first
BLOCK cycles after SKIP (the fast components' transient, the reference):

- it grows where the distance exceeds SEPARATION times the reference;
- it decays where the envelope falls below the reference over SEPARATION, after
  at least the N cycles in which the claimed multiplier m would have grown it by
  SEPARATION (|m|^N = SEPARATION: a decay then refutes the claim) and 2 BLOCKs;
- otherwise it is followed for HORIZON N cycles (at least MIN_CYCLES, at most
  MAX_CYCLES), in which m would have grown it SEPARATION^HORIZON-fold, and judged
  by where its envelope ends: below the reference over NEUTRAL decays, above
  NEUTRAL times it grows, between is neutral: a mode not separated from 1 (the
  drive spring's on the case above, 0.99999994 a cycle: barely damped).

The verdict: "grows" if any perturbation grows, else "neutral" if any is neutral,
else "decays"; its rate the slowest over the perturbations, (envelope /
reference)^(1 / cycles between them). What follows from it is the caller's
(analytic/periodic.find_orbit: a claimed growth refuted by a decaying or neutral
verdict, a claim of a multiplier on the unit circle only by a decay). (The FE
model's check, fem/integrators/periodic.decay_rate, follows one random
perturbation over a fixed 40 cycles.)
"""

import math
from dataclasses import dataclass

import numpy as np

AMPLITUDE = 1e-6      # the perturbation's RMS in the scaled unknowns (the natural sizes):
                      # ~10 times the square root of a cycle's rounding, and 1e4 times the
                      # orbit's own accuracy (Newton's 1e-10), so that its decay by
                      # SEPARATION stays above the orbit's error
SEPARATION = 10.0     # a decay or growth by this factor tells the perturbation's fate
SKIP = 5              # cycles over which the fast components settle (the reference: their maximum)
HORIZON = 4           # followed for this many times the cycles the claimed multiplier takes to
                      # grow a perturbation by SEPARATION (then by SEPARATION^4 = 1e4)
MIN_CYCLES = 1000     # and at least this many (ten blocks)
BLOCK = 100           # a slow mode's envelope is its largest distance over this many cycles:
                      # the drive spring's oscillation on the case above takes ~90
NEUTRAL = 1.1         # an envelope that ends within this factor of its reference (above or
                      # below) over the horizon neither decays nor grows as told: a mode not
                      # separated from 1 (a block's largest distance samples an oscillation
                      # of ~90 cycles to ~0.1%; a multiplier of 1.0001 would leave it in
                      # 1000 cycles, one of 0.99999994, the case above, stays in it)
MAX_CYCLES = 5000     # at most (the lumped model: ~0.5 s at 333 steps a cycle)


@dataclass(frozen=True)
class Decay:
    """The fate of perturbations of an orbit.

    verdict   "decays"; "neutral": the slowest perturbation's envelope neither fell nor grew
              beyond NEUTRAL over the horizon (the claimed multiplier refuted, a mode not
              separated from 1); "grows" (or the stepper failed from a perturbed orbit)
    rate      the slowest decay a cycle seen (decays, neutral), a growth (grows), or None
    cycles    the most cycles any perturbation was followed
    note      how the verdict was made
    """

    verdict: str
    rate: float | None
    cycles: int
    note: str


def cycles_to_tell(claimed: float) -> int | None:
    """The cycles N in which a multiplier of modulus ``claimed`` grows a perturbation
    by SEPARATION (at least SKIP + 1); None where it would not in MAX_CYCLES (a
    multiplier on the unit circle, or inside it)."""
    if not claimed > 1.0 or MAX_CYCLES * math.log(claimed) < math.log(SEPARATION):
        return None
    return max(SKIP + 1, math.ceil(math.log(SEPARATION) / math.log(claimed)))


def _follow(cycle, x: np.ndarray, y: np.ndarray, least: int):
    """Plain cycles from ``y`` and the envelope of its distance from ``x``: the largest
    distance over the first BLOCK cycles after SKIP (the reference) and over the last
    BLOCK, followed until the distance has grown by SEPARATION above the
    reference (at once), or the envelope has fallen by SEPARATION after at least
    ``least`` cycles, or for the whole horizon (HORIZON ``least``, at least MIN_CYCLES,
    at most MAX_CYCLES) and then judged by whether the envelope fell:
    (verdict "decays" | "grows" | "failed", rate a cycle, cycles)."""
    horizon = min(MAX_CYCLES, max(HORIZON * least, MIN_CYCLES))
    distances = []
    for k in range(1, horizon + 1):
        y = cycle(y)
        distance = float(np.sqrt(np.mean((y - x) ** 2)))
        if not math.isfinite(distance):
            return "failed", None, k
        distances.append(distance)
        if k < SKIP + BLOCK:
            continue
        reference = max(distances[SKIP:SKIP + BLOCK])
        if reference == 0.0:
            return "decays", 0.0, k
        if distance >= SEPARATION * reference:
            return "grows", (distance / reference) ** (1.0 / (k - SKIP)), k
        envelope = max(distances[-BLOCK:])
        if k >= max(least, SKIP + 2 * BLOCK) and envelope <= reference / SEPARATION:
            return "decays", (envelope / reference) ** (1.0 / (k - SKIP - BLOCK)), k
    change = envelope / reference
    rate = change ** (1.0 / (horizon - SKIP - BLOCK))
    verdict = ("decays" if change < 1.0 / NEUTRAL else "neutral" if change <= NEUTRAL
               else "grows")
    return verdict, rate, horizon


def perturbation_decay(cycle, x: np.ndarray, directions: np.ndarray, claimed: float,
                       seed: int = 0) -> Decay:
    """Follow perturbations of the orbit ``x`` (scaled unknowns: ``cycle`` maps them one
    base cycle on) along each column of ``directions`` and a random direction, each of
    RMS AMPLITUDE, for at least cycles_to_tell(``claimed``) cycles (module docstring)."""
    rng = np.random.default_rng(seed)
    columns = [d for d in np.atleast_2d(directions.T) if np.any(d != 0.0)]
    columns.append(rng.standard_normal(x.size))
    growth = cycles_to_tell(claimed)
    least = growth if growth is not None else SKIP + 1
    rates, neutral, most = [], False, 0
    for d in columns:
        d = d / np.sqrt(np.mean(d * d))
        verdict, rate, cycles = _follow(cycle, x, x + AMPLITUDE * d, least)
        most = max(most, cycles)
        if verdict in ("grows", "failed"):
            what = (f"grows by {rate:.6g} a cycle over {cycles} cycles" if rate
                    else "makes the stepper fail")
            return Decay("grows", rate, most,
                         f"a perturbation of {AMPLITUDE:g} of the state's scales {what}")
        neutral = neutral or verdict == "neutral"
        rates.append(rate)
    slowest = max(rates)
    told = (f"in which the claimed multiplier {claimed:.4g} would have grown them by "
            f"{SEPARATION:g}^{HORIZON} or more" if growth is not None else
            f"the claimed multiplier {claimed:.7f} on the unit circle")
    if neutral:
        return Decay("neutral", slowest, most,
                     f"perturbations of {AMPLITUDE:g} of the state's scales along the Jacobian's "
                     f"leading eigenvectors and a random direction do not grow over {most} "
                     f"cycles ({told}); the slowest neither decays nor grows beyond "
                     f"{NEUTRAL:g} ({slowest:.7f} a cycle): a mode not separated from 1")
    return Decay("decays", slowest, most,
                 f"perturbations of {AMPLITUDE:g} of the state's scales along the Jacobian's "
                 f"leading eigenvectors and a random direction all decay (slowest by "
                 f"{slowest:.6g} a cycle, followed for up to {most} cycles, {told})")
