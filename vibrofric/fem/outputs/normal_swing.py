"""The normal force over the averaging window: the sum's judged steady, rocking, a
transient, or ringing; the nodes' swing, and whether it makes the normal-force rule
matter.

The in-plane load moves the sum of the contact nodes' normal forces, sum N_i,
only through the block's vertical inertia. A sound run shows one of:

- steady: within F_N (1 +- STEADY_NORMAL) over the window. The forced response
  through Poisson coupling is +-0.1% (longitudinal k_v = 6) to +-0.35%
  (transverse k_v = 20) of F_N on the coarse mesh, the same with 7x the damping.
- rocking: a larger swing that is the block's forced response, at least
  FORCED_FRACTION of its variance at harmonics of the vibration frequency f.
  A contact stiffer than the block's own shear stiffness rocks it: on the
  Fig 7 scene at k_t x 100 the sum swings 53.8-56.1 N, 99.8% at harmonics, the
  same at dt = 1e-6 and 5e-7 s.
- with the base moving along Z (vibration.normal_amplitude > 0), a swing at
  the harmonics of f is its forced response: "forced" while the sum stays above
  0 (the body in contact throughout), "bouncing" where it reaches 0 (the body
  leaves the base and lands on it each cycle, as the lumped body does out of
  contact, its contact_loss_fraction > 0). The periodic solver's steady cycle
  and a stepped run settled on the same orbit are judged alike. A sum at the
  harmonics of f / k (SUBHARMONIC_PERIODS) is "subharmonic"; one reaching 0
  off any such cycle is "bouncing" too, and unsettled (settled).
- transient: the window's end (END_FRACTION of its whole cycles, at least
  END_CYCLES) is steady or rocking and its beginning is not: the block's free
  vibration on its contact, set going when the base starts (its velocity jumps
  from 0 to v_a at vibration.t_on), still decaying as the window begins. A stiff
  contact locks the block to the base and damps that vibration slowly: the
  transverse scene at k_t x 100, vibrated 2 ms after the start, swings 49.5-52.1 N
  over its first quarter of the window (11 kHz, 28% at harmonics) and 50.3-51.4 N,
  99.9% at harmonics, over its last, the same at dt = 1e-6 and 5e-7 s. That is
  physics: the run is kept, its swing reported, and it is reported unsettled
  (its average holds part of the transient).
- anything else is ringing: a free vibration that has not decayed by the window's
  end. The spec's trap (loads applied at once, no damping: 44-69 N instead of
  55 N, a drive force 25% off) and a block bouncing on its contact (a front-face
  drive at mu = 0.3: 41-71 N, 0.3% at harmonics) are refused (NumericalError).

The nodes' normal forces swing even where their sum holds: the block pitches
with the friction force at the contact plane and its inertia at mid-height, and
the pressure moves between the face's front and back rows in step with the
friction force (docs/friction-laws.md). ``node_swing`` measures it over the
window: each node's half range of N_i, summed over the nodes, over the sum of
their means; the fraction of the normal load that moves between the nodes (0
for a constant distribution, 1/2 for a linear one tilting from zero at the back
edge to zero at the front). What a node's law does as its N_i changes is the
normal-force rule (fem.normal_force, "nodal" or "nominal"; the asperity laws'
contact.normal_change), which the lumped model, its F_N constant, never meets.
Above RULE_MATTERS the rule moves F_dv/F_d0 by more than the step's error, and
the run says so (rule_note).
"""

from dataclasses import dataclass

import numpy as np

from ...core.errors import NumericalError

STEADY_NORMAL = 0.01
# A base moving along Z: the cycles of f a steady bouncing cycle may span (judge).
SUBHARMONIC_PERIODS = (2, 4)
# node_swing above which the normal-force rule matters (measured: docs/validation.md,
# "The normal-force rule").
RULE_MATTERS = 0.1
FORCED_FRACTION = 0.95
# The window's end: this fraction of its whole cycles of f, at least END_CYCLES
# (forced_fraction needs a few cycles to tell harmonics from a free mode).
END_FRACTION = 0.25
END_CYCLES = 4


def _spectrum(values, dt: float, f: float):
    """The power spectrum of ``values`` (a whole number of cycles of f, sampled every
    dt) about their mean, and which of its bins are the harmonics k f, k >= 1."""
    power = np.abs(np.fft.rfft(values - values.mean())) ** 2
    cycles = values.size * dt * f                 # the window's length in cycles of f
    bins = np.arange(power.size) / cycles         # each bin's frequency over f
    harmonic = (bins > 0) & (np.abs(bins - np.round(bins)) < 0.5 / cycles)
    return power, harmonic


def forced_fraction(values, dt: float, f: float) -> float:
    """The fraction of the variance of ``values`` (a whole number of cycles of f,
    sampled every dt) at the harmonics k f, k >= 1."""
    power, harmonic = _spectrum(values, dt, f)
    total = power[1:].sum()
    if total == 0.0:
        return 1.0
    return float(power[harmonic].sum() / total)


def free_frequency(values, dt: float, f: float) -> float:
    """The frequency (Hz) of the largest spectral line of ``values`` that is not a
    harmonic of f: the free vibration's, to the window's resolution 1 / (n dt)."""
    power, harmonic = _spectrum(values, dt, f)
    power[0] = 0.0
    power[harmonic] = 0.0
    return float(np.argmax(power) / (values.size * dt))


@dataclass
class NormalSwing:
    """The window's summed normal force as judged above (kind: "steady", "rocking",
    "forced" (a base moving along Z, the body in contact throughout: the sum stays
    above 0), "bouncing" (the base moving along Z, the sum reaching 0: the body leaves
    the base and lands on it, either each cycle of f, forced at its harmonics, or off
    any cycle), "subharmonic" (its bouncing cycle spanning SUBHARMONIC_PERIODS cycles
    of f; forced then at f / k) or "transient"); low/high over the whole window,
    forced the window's forced fraction, end_low/end_high and end_forced over its end,
    free_frequency_hz the largest free line over the window (None where steady)."""

    kind: str
    low: float
    high: float
    forced: float
    end_low: float
    end_high: float
    end_forced: float
    free_frequency_hz: float | None


def settled(kind: str, forced: float) -> bool:
    """Whether a stepped window judged ``kind`` with its ``forced`` fraction (judge) is
    a steady cycle's: not a transient, nor a body bouncing off the harmonics of f."""
    return kind != "transient" and not (kind == "bouncing" and forced < FORCED_FRACTION)


def node_swing(samples) -> float:
    """The nodes' swing (module docstring) of ``samples`` (times, nodes) of N_i:
    sum_i (max_t N_i - min_t N_i) / 2 over sum_i mean_t N_i."""
    samples = np.asarray(samples)
    load = samples.mean(axis=0).sum() if samples.size else 0.0
    if load <= 0.0:
        return 0.0
    return float((samples.max(axis=0) - samples.min(axis=0)).sum() / (2.0 * load))


def rule_note(swing: float, rule: str) -> str | None:
    """Where ``swing`` (node_swing) exceeds RULE_MATTERS, one line saying the answer
    depends on the normal-force rule, naming the one the run used (``rule``,
    fem.normal_force) and the other; else None."""
    if swing <= RULE_MATTERS:
        return None
    other = "nominal" if rule == "nodal" else "nodal"
    return (f"the nodes' normal forces swing by {swing:.0%} over the cycle, so the answer "
            f"depends on fem.normal_force (\"{rule}\"; compare \"{other}\")")


def _swings(values, F_N: float) -> bool:
    return max(F_N - values.min(), values.max() - F_N) > STEADY_NORMAL * F_N


def judge(window, dt: float, f: float, F_N: float, damping: float,
          moving_base: bool = False) -> NormalSwing:
    """Judge the averaging window's summed normal force (sampled every dt over whole
    cycles of f); raise NumericalError for ringing (``damping``: the model's beta, s,
    for the message). ``moving_base``: the base moves along Z, and a swing at the
    harmonics of f is its forced response, "forced" rather than "rocking"."""
    window = np.asarray(window)
    cycles = int(round(window.size * dt * f))
    end_cycles = min(cycles, max(END_CYCLES, int(END_FRACTION * cycles)))
    end = window[-int(round(end_cycles / (f * dt))):]
    forced, end_forced = forced_fraction(window, dt, f), forced_fraction(end, dt, f)
    swing = NormalSwing("steady", float(window.min()), float(window.max()), forced,
                        float(end.min()), float(end.max()), end_forced, None)
    if not _swings(window, F_N):
        return swing
    swing.free_frequency_hz = free_frequency(window, dt, f)
    if moving_base and forced < FORCED_FRACTION:
        # a body bouncing on a base moving along Z may settle on a cycle of several of
        # the base's (period doubling: the bouncing ball's route to chaos); forced
        # still, at the harmonics of f / k
        for cycles_per_period in SUBHARMONIC_PERIODS:
            at = f / cycles_per_period
            if (forced_fraction(window, dt, at) >= FORCED_FRACTION
                    and forced_fraction(end, dt, at) >= FORCED_FRACTION):
                swing.kind = "subharmonic"
                swing.forced, swing.end_forced = (forced_fraction(window, dt, at),
                                                  forced_fraction(end, dt, at))
                swing.free_frequency_hz = None
                return swing
    if forced >= FORCED_FRACTION:
        # at the harmonics of f: the block's forced response. With the base moving along
        # Z it is "bouncing" where the summed force reaches 0 (the body leaves the base
        # and lands on it each cycle: the lumped body out of contact, analytic/normal.py),
        # whether a steady cycle (integrators/periodic.py) or a stepped run settled on it
        if not moving_base:
            swing.kind = "rocking"
        else:
            swing.kind = "bouncing" if swing.low <= 0.0 else "forced"
    elif not _swings(end, F_N) or end_forced >= FORCED_FRACTION:
        swing.kind = "transient"
    elif moving_base and swing.end_low <= 0.0:
        # the body leaves the base and lands again off its cycle: a bouncing body, not
        # numerical trouble (the lumped body does the same from just above its contact-
        # loss threshold, analytic/normal.py); kept, and reported unsettled (settled)
        swing.kind = "bouncing"
    else:
        raise NumericalError(
            f"the summed normal force swung between {swing.end_low:.4g} and "
            f"{swing.end_high:.4g} N (F_N = {F_N} N) over the last {end_cycles} cycles of the "
            f"averaging window, only {end_forced:.1%} of it at harmonics of the vibration "
            f"(the largest free line at {swing.free_frequency_hz / 1e3:.3g} kHz): the block is "
            f"ringing or bouncing on its contact, not rocking with the base; raise fem.damping "
            f"(now {damping:.3g} s) or lower time.dt, or, if it rings the same at half the "
            f"step (the block's own free vibration, slow to decay on a stiff contact), "
            f"average later (time.T)")
    return swing


def normal_force_keys(f_n: np.ndarray, node_normals: np.ndarray) -> dict:
    """The summary's normal-force keys over the averaging window (the interface's, as the
    lumped model reports them: analytic/normal.py normal_force_keys): the summed normal
    force's mean, min and max (N, every step ``f_n``) and contact_loss_fraction, the mean
    fraction of the contact nodes out of contact (N_i = 0) over the window's kept
    samples of the nodes' forces (``node_normals``, (samples, nodes): at least
    NODE_SAMPLES_PER_CYCLE a cycle, recording.py)."""
    open_fraction = float(np.mean(node_normals <= 0.0)) if node_normals.size else 0.0
    return {"contact_loss_fraction": open_fraction, "normal_force_mean": float(np.mean(f_n)),
            "normal_force_min": float(np.min(f_n)), "normal_force_max": float(np.max(f_n))}
