"""Richardson's step-error estimate (core/step_error.py) on answers of known error."""

import math

import pytest

from vibrofric.core.step_error import (SAFETY_ASSUMED, SAFETY_OBSERVED, not_estimated,
                                       richardson)

EXACT = 0.137


def answers(order, coefficient=0.02, h=1e-5, count=3, noise=0.0):
    """F(h) = F* + C h^p (h in units of 1e-5 s) at h, h/2, h/4."""
    return [(h / 2**k, EXACT + coefficient * (h / 2**k / 1e-5) ** order + noise * (-1) ** k)
            for k in range(count)]


@pytest.mark.parametrize("order", [1.0, 2.0, 1.5])
def test_observed_order_and_error_of_an_asymptotic_scheme(order):
    est = richardson(answers(order), dt_asked=1e-5)
    true_error = abs(answers(order)[0][1] - EXACT)
    # the answers are exactly C h^p: the order is observed to rounding, and the
    # estimate is the true error times the factor of safety
    assert est.order == pytest.approx(order, rel=1e-9)
    assert est.estimate == pytest.approx(SAFETY_OBSERVED * true_error, rel=1e-9)


def test_a_higher_order_term_leaves_the_estimate_within_its_safety_factor():
    """F = F* + C h + D h^2 with D h = C/4 at h: not yet asymptotic, still bounded."""
    data = [(h, EXACT + 0.02 * h / 1e-5 + 0.005 * (h / 1e-5) ** 2)
            for h in (1e-5, 0.5e-5, 0.25e-5)]
    est = richardson(data, dt_asked=1e-5)
    true_error = data[0][1] - EXACT
    assert true_error <= est.estimate <= 3 * true_error


def test_oscillating_answers_claim_no_order():
    data = [(1e-5, EXACT + 0.01), (0.5e-5, EXACT - 0.004), (0.25e-5, EXACT + 0.001)]
    est = richardson(data, dt_asked=1e-5)
    assert est.order is None
    # F(h)'s distance from the finest answer, plus the finest's own (the last change)
    assert est.estimate == pytest.approx(0.009 + 0.005)
    assert est.estimate >= 0.01      # the true error


def test_two_answers_assume_the_formal_order():
    data = answers(1.0, count=2)
    est = richardson(data, dt_asked=1e-5, formal_order=1.0)
    assert est.order is None
    assert est.estimate == pytest.approx(SAFETY_ASSUMED * (data[0][1] - EXACT), rel=1e-9)


def test_answers_within_the_resolution_give_the_resolution():
    est = richardson([(1e-5, EXACT), (0.5e-5, EXACT + 1e-12), (0.25e-5, EXACT)],
                     dt_asked=1e-5, resolution=1e-10)
    assert est.estimate == 1e-10 and est.order is None


def test_step_for_an_accuracy():
    est = richardson(answers(1.0), dt_asked=1e-5)
    h = est.step_for(1e-3)
    # error 1.25 * 0.02 (h / 1e-5) = 1e-3 at h = 1e-5 / 25
    assert h == pytest.approx(1e-5 / 25, rel=1e-9)
    assert est.step_for(1.0) is None
    assert not_estimated(1e-5, 1e-5, "asked").step_for(1e-3) is None


def test_refuses_steps_that_are_not_halved_and_reports_non_finite():
    with pytest.raises(ValueError, match="halved"):
        richardson([(1e-5, 1.0), (0.3e-5, 1.0)], dt_asked=1e-5)
    est = richardson([(1e-5, 1.0), (0.5e-5, math.nan)], dt_asked=1e-5)
    assert est.estimate is None and est.note.startswith("not estimated")
    assert set(est.as_dict()) == {"error_estimate", "error_order", "dt_used", "dt_asked",
                                  "error_note"}


def test_two_answers_take_the_factor_of_safety_asked_for():
    data = answers(2.0, count=2)
    est = richardson(data, dt_asked=1e-5, formal_order=2.0, two_step_safety=1.25)
    # the answers are exactly C h^2: Richardson's error at order 2 is exact, times 1.25
    assert est.estimate == pytest.approx(1.25 * (data[0][1] - EXACT), rel=1e-9)
    assert "factor of safety 1.25" in est.note


def test_a_fourth_answer_is_the_finer_reference_where_three_scatter():
    """Answers off the converged one by 6e-6, 1.3e-5, 5e-8, 5.6e-7 (the lumped model on
    Fig 7 at 250, 500, 1000, 2000 steps a cycle): three scatter, and with the fourth
    the estimate is |F(h) - F(h/8)| + |F(h/4) - F(h/8)|, within a factor 3 of the
    true error where the three alone gave |F(h) - F(h/4)| + |F(h/2) - F(h/4)| (2.2 times
    it)."""
    from vibrofric.core.step_error import scattered

    offsets = (6.0e-6, 1.3e-5, 5e-8, 5.6e-7)
    data = [(1e-6 / 2**k, EXACT + e) for k, e in enumerate(offsets)]
    three = richardson(data[:3], dt_asked=1e-6)
    assert scattered(three) and three.estimate == pytest.approx(6.0e-6 - 5e-8 + 1.3e-5 - 5e-8)
    four = richardson(data, dt_asked=1e-6)
    assert not scattered(four)
    assert four.estimate == pytest.approx(6.0e-6 - 5.6e-7 + 5.6e-7 - 5e-8)
    assert 6.0e-6 / 3 <= four.estimate <= 3 * 6.0e-6
