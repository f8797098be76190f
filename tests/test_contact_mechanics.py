"""The contact-mechanics closed forms (analytic/contact_mechanics.py) against what they
are derived from: the Masing loop integrated numerically, Hertz's force balance, limits."""

import doctest
import math

import numpy as np
import pytest
from scipy.integrate import quad

from vibrofric.analytic import contact_mechanics as cm

STEEL = {"E": 209e9, "nu": 0.3}


def test_docstring_examples_run():
    outcome = doctest.testmod(cm)
    assert outcome.attempted >= 3 and outcome.failed == 0


def test_hertz_pressure_integrates_to_the_load():
    """int p0 sqrt(1 - r^2/a^2) 2 pi r dr = P: the three Hertz forms agree (quadrature
    to 1e-10 relative)."""
    P, R = 50.0, 0.01
    a, p0 = cm.hertz_radius(P, R, **STEEL), cm.hertz_peak_pressure(P, R, **STEEL)
    force, _ = quad(lambda r: p0 * math.sqrt(max(0.0, 1 - (r / a) ** 2)) * 2 * math.pi * r, 0, a)
    assert force == pytest.approx(P, rel=1e-10)


def test_line_contact_pressure_integrates_to_the_load_per_length():
    P_line, R = 2000.0, 0.005
    a, p0 = cm.line_half_width(P_line, R, **STEEL), cm.line_peak_pressure(P_line, R, **STEEL)
    force, _ = quad(lambda x: p0 * math.sqrt(max(0.0, 1 - (x / a) ** 2)), -a, a)
    assert force == pytest.approx(P_line, rel=1e-10)


def test_mindlin_limits():
    """Nothing slips at Q = 0 (c = a, delta = 0); at Q = mu P the stick zone vanishes and
    delta = 3 mu P / 16 G* a."""
    mu, P, a = 0.5, 50.0, 1e-4
    assert cm.stick_radius(0.0, mu, P, a) == a and cm.mindlin_displacement(0.0, mu, P, a, **STEEL) == 0
    assert cm.stick_radius(mu * P, mu, P, a) == 0.0
    full = 3 * mu * P / (16 * cm.tangential_modulus(**STEEL) * a)
    assert cm.mindlin_displacement(mu * P, mu, P, a, **STEEL) == pytest.approx(full, rel=1e-15)
    with pytest.raises(ValueError, match="mu P"):
        cm.stick_radius(1.01 * mu * P, mu, P, a)


@pytest.mark.parametrize("q", [0.05, 0.3, 0.6, 0.9, 1.0])
def test_mindlin_deresiewicz_is_the_area_of_the_masing_loop(q):
    """The closed form against the loop of delta_up / delta_down built from the
    Cattaneo-Mindlin curve by the Masing rule and integrated by quadrature (1e-9
    relative: the integrand is smooth but for its (1 - x)^(2/3) end)."""
    mu, P, a = 0.4, 80.0, 2e-4
    Q_star = q * mu * P

    def delta(Q):
        return cm.mindlin_displacement(Q, mu, P, a, **STEEL)

    def gap(Q):   # delta_down - delta_up at the same Q
        down = delta(Q_star) - 2 * delta((Q_star - Q) / 2)
        up = -delta(Q_star) + 2 * delta((Q + Q_star) / 2)
        return down - up

    area, _ = quad(gap, -Q_star, Q_star, epsabs=0, epsrel=1e-12, limit=200)
    assert cm.mindlin_deresiewicz_dissipation(Q_star, mu, P, a, **STEEL) == pytest.approx(
        area, rel=1e-9)


def test_mindlin_deresiewicz_small_amplitude_series():
    """W -> mu^2 P^2 q^3 / (36 G* a) as q -> 0 (the docstring's series; at q = 1e-3 the
    next term is ~q smaller)."""
    mu, P, a, q = 0.4, 80.0, 2e-4, 1e-3
    series = (mu * P) ** 2 * q ** 3 / (36 * cm.tangential_modulus(**STEEL) * a)
    got = cm.mindlin_deresiewicz_dissipation(q * mu * P, mu, P, a, **STEEL)
    assert got == pytest.approx(series, rel=3e-3)
    assert np.isfinite(got)
