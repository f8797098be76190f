"""The built-in friction laws through the contract: Dahl (with its shape exponent) and
LuGre, both updates, isotropy, no contact."""

import math

import numpy as np
import pytest

from vibrofric.friction_law import ContactLaw, contact_step, load_law
from vibrofric.friction_law.asperity import EXACT, PAPER, relax_length

RNG = np.random.default_rng(20261121)
F_N = 55.0
K_T = 80e6
S_C = 0.1 * F_N / K_T  # sliding length F_c / k_t


def random_history(steps=400, nodes=50, scale=0.3 * S_C):
    """Random phase-1 slips and phase-2 free-end moves, up to ~0.3 s_c a step."""
    slip = RNG.normal(scale=scale, size=(steps, nodes, 2)) + np.array([0.1 * scale, 0.0])
    free = np.zeros_like(slip)
    free[..., 1] = RNG.normal(scale=scale, size=(steps, nodes))
    return slip, free


def friction_law(law="dahl", **values) -> ContactLaw:
    """A built-in law with its parameters (defaults: mu = 0.1, k_t = K_T) on a contact of F_N."""
    loaded = load_law(law)
    return ContactLaw(loaded, loaded.values({"k_t": K_T, **values}), F_N)


def run_history(law, slip, free, normal_force=None, share=None, dt=1e-6):
    """Forces (steps, nodes, 2) and the final states of contact_step over a history."""
    nodes = slip.shape[1]
    normal_force = np.full(nodes, F_N) if normal_force is None else normal_force
    share = np.ones(nodes) if share is None else share
    state = law.law.initial_state(nodes)
    forces = np.array([contact_step(law, state, s, f, normal_force, share, dt) for s, f in zip(slip, free)])
    return forces, state


@pytest.mark.parametrize("update", ["paper", "exact"])
def test_lugre_without_damping_and_stribeck_is_dahl(update):
    """h_t = h_v = 0 and F_s = mu F_N: g(v) = mu F_N whatever v_s is, the same law.
    The two modules' compiled code may round differently (numba 0.68 fuses other
    multiply-adds than 0.56): equal to 1e-13 of F_c, a few ulps, not bit for bit."""
    slip, free = random_history()
    dahl = friction_law("dahl", update=update)
    lugre = friction_law("lugre", update=update, v_s=1e-4)
    f_dahl, s_dahl = run_history(dahl, slip, free)
    f_lugre, s_lugre = run_history(lugre, slip, free)
    np.testing.assert_allclose(f_lugre, f_dahl, rtol=0, atol=1e-13 * 0.1 * F_N)
    np.testing.assert_allclose(s_lugre[:, 0], s_dahl[:, 0], rtol=0, atol=1e-13 * S_C)
    # and LuGre with a Stribeck peak really is another law
    stribeck = friction_law("lugre", update=update, F_s=0.2 * F_N, v_s=1e-4)
    assert not np.allclose(run_history(stribeck, slip, free)[0], f_dahl)


def dahl_closed_form(s0, v, t):
    """ds/dt = v (1 - s / s_c) for v > 0: s = s_c + (s0 - s_c) exp(-v t / s_c)."""
    return S_C + (s0 - S_C) * np.exp(-v * t / S_C)


def integrate_length(update, s0, v, dt, steps):
    s = s0
    for _ in range(steps):
        s = relax_length(s, v * dt, S_C, 1.0, update)
    return s


def test_exact_update_matches_closed_form():
    v, T = 5e-4, 4e-4  # slides 2.9 s_c: well into the exponential approach
    for dt in (1e-5, 1e-6):
        steps = round(T / dt)
        s = integrate_length(EXACT, 0.2 * S_C, v, dt, steps)
        # exact for constant v_r whatever dt: only rounding over the steps remains
        assert s == pytest.approx(dahl_closed_form(0.2 * S_C, v, T), rel=1e-12)
    # unloading (v < 0) relaxes towards -s_c, through zero
    s = integrate_length(EXACT, 0.5 * S_C, -v, 1e-6, 400)
    expected = -S_C + 1.5 * S_C * math.exp(-v * 4e-4 / S_C)
    assert s == pytest.approx(expected, rel=1e-12)


def test_paper_update_converges_at_first_order():
    v, T = 5e-4, 2e-4
    exact = dahl_closed_form(0.0, v, T)
    errors = [abs(integrate_length(PAPER, 0.0, v, T / n, n) - exact) for n in (50, 100, 200, 400)]
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    # explicit Euler: order 1, approached as dt shrinks (the first ratio carries O(dt^2) terms)
    assert np.all(np.abs(orders - 1.0) < 0.05), orders
    assert errors[-1] < 1e-3 * S_C


def rotate(vectors, angle):
    c, s = math.cos(angle), math.sin(angle)
    return vectors @ np.array([[c, s], [-s, c]])


@pytest.mark.parametrize("law", [friction_law("dahl", update="paper"),
                                 friction_law("dahl", update="exact"),
                                 friction_law("dahl", dahl_exponent=0.5),
                                 friction_law("lugre", update="exact", F_s=0.15 * F_N,
                                              v_s=1e-3, h_t=50.0, h_v=20.0)])
def test_rotating_every_increment_rotates_every_force(law):
    slip, free = random_history(steps=300, nodes=20)
    free = RNG.normal(scale=0.3 * S_C, size=free.shape)  # phase-2 moves in any direction
    forces, _ = run_history(law, slip, free)
    angle = 0.7
    rotated, _ = run_history(law, rotate(slip, angle), rotate(free, angle))
    # the law has no preferred direction: equal up to rounding of the rotation
    # itself (~1e-16 per step, accumulated over 300 steps)
    np.testing.assert_allclose(rotated, rotate(forces, angle), rtol=0, atol=1e-11 * F_N)


@pytest.mark.parametrize("update", ["paper", "exact"])
def test_zero_normal_force_gives_zero_force_and_finite_state(update):
    slip, free = random_history(steps=100, nodes=5)
    normal_force = np.array([F_N, 0.0, -3.0, F_N, 0.0])
    share = np.array([0.5, 0.5, 0.0, 0.0, 0.0])  # node 3: loaded but without contact area
    law = friction_law("lugre", update=update, F_s=0.2 * F_N, h_t=1.0, h_v=1.0)
    forces, state = run_history(law, slip, free, normal_force=normal_force, share=share)
    assert np.all(np.isfinite(forces)) and np.all(np.isfinite(state))
    idle = (normal_force <= 0) | (share == 0)
    assert np.all(forces[:, idle] == 0.0)
    assert np.all(state[idle, 0] == 0.0)
    assert np.all(np.abs(forces[:, 0]).sum(axis=-1) > 0)  # the loaded node does carry friction


def test_vanishing_normal_force_stays_finite_with_the_exact_update():
    # s_c = mu F_n / k is denormal here: every step slides past it. The exact
    # update saturates; the paper's explicit one would diverge (|v_r| dt > 2 s_c).
    slip, free = random_history(steps=100, nodes=2)
    forces, state = run_history(friction_law(), slip, free, normal_force=np.array([1e-300, 1e-12]))
    assert np.all(np.isfinite(forces)) and np.all(np.isfinite(state))
    assert np.all(np.hypot(*forces[-1].T) <= 0.1 * np.array([1e-300, 1e-12]) * (1 + 1e-12))


def test_sliding_saturates_at_the_coulomb_limit_of_each_node():
    steps = 2000
    slip = np.zeros((steps, 3, 2))
    slip[..., 0] = 0.05 * S_C
    free = np.zeros_like(slip)
    normal_force = np.array([10.0, 20.0, 25.0])
    share = np.array([0.2, 0.3, 0.5])
    forces, _ = run_history(friction_law(), slip, free, normal_force, share)
    # 100 s_c of sliding: exp(-100) of the initial gap is left
    np.testing.assert_allclose(forces[-1, :, 0], 0.1 * normal_force, rtol=1e-12)
    assert np.all(forces[-1, :, 1] == 0.0)


def dahl_breakaway(x, exponent):
    """F / F_c after a slip x from rest at a constant rate: dr/dx = -r^i / s_c, r = 1 - F / F_c."""
    u = x / S_C
    if exponent == 1.0:
        r = np.exp(-u)
    elif exponent < 1.0:
        r = np.maximum(0.0, 1.0 - (1.0 - exponent) * u) ** (1.0 / (1.0 - exponent))
    else:
        r = (1.0 + (exponent - 1.0) * u) ** (-1.0 / (exponent - 1.0))
    return 1.0 - r


def breakaway_curve(law, slip_per_step, steps):
    """The force along X of one node slid along X by the same slip every step."""
    slip = np.zeros((steps, 1, 2))
    slip[..., 0] = slip_per_step
    forces, _ = run_history(law, slip, np.zeros_like(slip))
    return forces[:, 0, 0] / (0.1 * F_N)


@pytest.mark.parametrize("exponent", [0.0, 0.5, 1.0, 2.0, 1.7])
def test_dahl_breakaway_follows_its_closed_form_with_the_exact_update(exponent):
    """Dahl with shape exponent i (eq 2): F(x) from rest at constant slip rate. The exact
    update solves the law over each step, so only rounding separates it from the closed
    form, whatever the step: 1e-9 of F_c is far above rounding (~1e-13 over 300 steps)."""
    for slip_per_step in (0.01 * S_C, 0.2 * S_C):
        steps = 300
        x = slip_per_step * np.arange(1, steps + 1)
        curve = breakaway_curve(friction_law(dahl_exponent=exponent), slip_per_step, steps)
        np.testing.assert_allclose(curve, dahl_breakaway(x, exponent), rtol=0, atol=1e-9)


@pytest.mark.parametrize("exponent", [0.5, 2.0])
def test_dahl_paper_update_with_an_exponent_converges_at_first_order(exponent):
    """The paper's explicit update (eq 18 with r^i) is explicit Euler in the slip: the
    error of F at x = s_c halves with the slip per step (order 1 within 0.1)."""
    errors = []
    for n in (50, 100, 200, 400):
        curve = breakaway_curve(friction_law(dahl_exponent=exponent, update="paper"), S_C / n, n)
        errors.append(abs(curve[-1] - dahl_breakaway(S_C, exponent)))
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(np.abs(orders - 1.0) < 0.1), orders
