"""The ranges of scene values that make physical and numerical sense.

scene.validate refuses what its own checks let through but no study can mean:
a value that is not a finite number, or a key outside its range below. Each
range is wide (orders of magnitude beyond any bench or machine test) and
exists because outside it the double-precision stepper returns an answer
that looks like a result and is not:

    contact.F_N   1e-6 .. 1e9 N    beyond: the sliding force mu F_N dwarfs the
                                   drive spring's reach within time.T (1e17 N
                                   gave a "settled" frictionless answer); below:
                                   ratios of underflowed forces (1e-300 N: 6e297)
    drive.v_d     1e-9 .. 1e3 m/s  below: the body never breaks away within time.T
                                   (1e-300 m/s: F_dv ~ 0, "settled")
    body.mass     1e-9 .. 1e6 kg   and
    drive.k_d     1e-6 .. 1e15 N/m the drive's period 2 pi sqrt(m / k_d), which
                                   sets the averaging window, finite and
                                   countable in cycles (5e-324 N/m overflowed)
    vibration.f   1e-3 .. 1e9 Hz   and
    time.dt       1e-12 .. 1e3 s   steps a cycle 1 / (f dt) a finite number
                                   (5e-324 Hz divided by zero)
    vibration.theta_deg  -360 .. 360 deg   an angle; 1e20 deg has no cosine worth
                                   the name in double precision (its ulp is 16384 deg)
"""

import math

RANGES = {
    "body.mass": (1e-9, 1e6, "kg"),
    "drive.k_d": (1e-6, 1e15, "N/m"),
    "contact.F_N": (1e-6, 1e9, "N"),
    "drive.v_d": (1e-9, 1e3, "m/s"),
    "vibration.f": (1e-3, 1e9, "Hz"),
    "time.dt": (1e-12, 1e3, "s"),
    "vibration.theta_deg": (-360.0, 360.0, "deg"),
}


def nonsense(values: dict):
    """(key, why) for the first value of ``values`` ({"section.key": value}) that
    makes no sense (not finite, or outside RANGES), else None."""
    for key, value in values.items():
        if isinstance(value, float) and not math.isfinite(value):
            return key, f"must be a finite number, got {value}"
    for key, (low, high, unit) in RANGES.items():
        value = values.get(key)
        if value is not None and not low <= value <= high:
            return key, (f"{value:g} {unit} is outside the range that makes physical and "
                         f"numerical sense here, {low:g} to {high:g} {unit}")
    return None
