"""What the bench fits to its measurements: power-law exponents, the mesh-converged value
(Richardson extrapolation), and errors relative to a reference."""

import math

import numpy as np


def fitted_exponent(x, y) -> float:
    """The slope p of log y = p log x + c, least squares.

    >>> round(fitted_exponent([1e3, 1e4, 1e5], [2.0, 2.0 * 10 ** 1.5, 2.0 * 100 ** 1.5]), 12)
    1.5
    """
    return float(np.polyfit(np.log(x), np.log(y), 1)[0])


def relative(value: float, reference: float) -> float:
    """(value - reference) / |reference|: an error signed as the value's departure.

    >>> round(relative(0.135, 0.15), 12)
    -0.1
    """
    return (value - reference) / abs(reference)


def richardson(h, values) -> tuple:
    """(f_0, p, uncertainty): the mesh-converged value of f(h) = f_0 + C h^p from the last
    three levels (h decreasing), its observed order p, and the uncertainty of f_0.

    p solves (f_1 - f_2) / (f_2 - f_3) = (h_1^p - h_2^p) / (h_2^p - h_3^p) (bisection on
    [0.1, 8]; nan if the differences change sign: not yet in the asymptotic range);
    f_0 = f_3 - (f_2 - f_3) h_3^p / (h_2^p - h_3^p). The uncertainty is Roache's grid
    convergence index on the finest level, 1.25 |f_3 - f_0|.

    >>> f0, p, _ = richardson([0.02, 0.01, 0.005], [0.14 + 3 * h ** 2 for h in (0.02, 0.01, 0.005)])
    >>> round(f0, 9), round(p, 6)
    (0.14, 2.0)
    """
    (h1, h2, h3), (f1, f2, f3) = h[-3:], values[-3:]
    observed = (f1 - f2) / (f2 - f3) if f2 != f3 else math.nan
    if not observed > 0.0:
        return math.nan, math.nan, math.nan

    def mismatch(p):
        return (h1 ** p - h2 ** p) / (h2 ** p - h3 ** p) - observed

    low, high = 0.1, 8.0
    if mismatch(low) * mismatch(high) > 0.0:
        return math.nan, math.nan, math.nan
    for _ in range(100):
        mid = 0.5 * (low + high)
        low, high = (mid, high) if mismatch(low) * mismatch(mid) > 0.0 else (low, mid)
    p = 0.5 * (low + high)
    f0 = f3 - (f2 - f3) * h3 ** p / (h2 ** p - h3 ** p)
    return f0, p, 1.25 * abs(f3 - f0)
