"""The lumped steppers against each other, the closed forms and the paper's statements."""

import math

import numpy as np
import pytest

from vibrofric.analytic import run_coupled
from vibrofric.core.errors import NumericalError
from vibrofric.analytic.closed_form import coulomb_ratio, longitudinal_ratio
from vibrofric.analytic.solve import solve
from vibrofric.batch import sweep

FIG12_KV = (2, 3, 4, 6, 20)


def ratio(scene):
    return solve(scene)[1]["F_dv_over_F_d0"]


@pytest.mark.parametrize("k_v", [2.0, 6.0, 20.0])
def test_coupled_at_theta_zero_agrees_with_the_1d_longitudinal_model(load_scene, k_v):
    scene = load_scene("longitudinal", vibration__k_v=k_v)
    coupled = solve(scene, "coupled")[1]["F_dv_over_F_d0"]
    one_d = solve(scene, "longitudinal")[1]["F_dv_over_F_d0"]
    assert abs(coupled - one_d) < 0.005  # the bound; measured ~1e-7


def test_coupled_stepper_converges_in_dt(load_scene):
    """Semi-implicit Euler with the exact Dahl update: first order in dt (the stepped run)."""
    scene = load_scene("longitudinal", time__T=0.25, time__average_cycles=40,
                       time__method="transient")
    reference = ratio(scene.with_values({"time.dt": 1.25e-7}))
    errors = [abs(ratio(scene.with_values({"time.dt": dt})) - reference) for dt in (2e-6, 1e-6, 5e-7)]
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    # the reference carries 1/8 of the finest error: the observed order lies
    # between 1 and that bias's effect; anything below 0.8 is not first order
    assert np.all(orders > 0.8), (errors, orders)
    assert errors[1] < 0.01  # dt = 1e-6, the paper's step: under 1% of F_d0


def test_breakaway_times_and_forces_of_the_paper(load_scene):
    for name, t_paper in (("longitudinal", 0.12), ("transverse", 0.11)):
        scene = load_scene(name, vibration__k_v=0.0)
        series, summary = solve(scene)
        # the paper reads its breakaway off a plot, to about 0.01 s
        assert summary["breakaway_time_s"] == pytest.approx(t_paper, abs=0.01)
        # the spring alone takes F_c / (k_d v_d) to reach F_c; presliding of a
        # few s_c (1e-7 m) at v_d (5e-4 m/s) adds well under a millisecond
        spring_only = scene.F_c / (scene.drive.k_d * scene.drive.v_d)
        assert summary["breakaway_time_s"] == pytest.approx(spring_only, rel=0.01)
        # breakaway force: F_d passes F_c, overshooting by the body's inertia as
        # it jumps from rest to v_d on the spring, at most v_d sqrt(m k_d)
        # (0.11 N for 0.5 kg, 0.22 N for 2 kg), then slides at F_c
        peak = series.F_d[series.t < scene.vibration.t_on].max()
        overshoot = scene.drive.v_d * math.sqrt(scene.body.mass * scene.drive.k_d)
        assert scene.F_c < peak <= scene.F_c + overshoot
        assert summary["F_dv"] == pytest.approx(scene.F_c, rel=0.005)


@pytest.mark.parametrize("k_v", [0.3, 0.6, 0.9])
def test_no_reduction_for_longitudinal_k_v_below_one(load_scene, k_v):
    # the residual drive-spring oscillation averages out over one period: ~1e-4
    assert ratio(load_scene("longitudinal", vibration__k_v=k_v)) == pytest.approx(1.0, abs=1e-3)


def test_transverse_reduces_already_below_k_v_one(load_scene):
    ratios = [ratio(load_scene("transverse", vibration__k_v=k)) for k in (0.3, 0.6, 0.9)]
    assert ratios[0] < 0.999 and np.all(np.diff(ratios) < 0), ratios


@pytest.fixture(scope="module")
def fig12(load_scene):
    """The Fig 12 grid on a 15-degree lattice of the first half turn plus mirrors."""
    grid = [("vibration.k_v", list(FIG12_KV)),
            ("vibration.theta_deg", [0.0, 30.0, 60.0, 90.0, 120.0, 150.0, 180.0, 210.0, 330.0])]
    records = sweep(load_scene("coupled"), grid, progress=False)
    return {(r["vibration.k_v"], r["vibration.theta_deg"]): r["F_dv_over_F_d0"] for r in records}


def test_larger_k_v_lowers_the_drive_force_at_every_angle(fig12):
    for theta in {t for _, t in fig12}:
        values = [fig12[(k, theta)] for k in FIG12_KV]
        assert np.all(np.diff(values) < 0), (theta, values)


def test_longitudinal_gives_the_greatest_reduction(fig12):
    for k_v in FIG12_KV:
        by_angle = {t: v for (k, t), v in fig12.items() if k == k_v}
        assert min(by_angle, key=by_angle.get) in (0.0, 180.0)


def test_symmetry_of_the_angle_dependence(fig12):
    for k_v in FIG12_KV:
        # 360 - theta mirrors Y: exact up to rounding (the orbits' Newton tolerance);
        # 180 - theta is a half-period shift of the vibration and a mirror, equal once
        # averaged over many cycles (the stepped runs' gap ~1e-9). The orbit is shot at
        # 333 steps a cycle (3 kHz: 1/(f dt) made whole), an odd number: the half-period
        # shift is not one of the discrete stepper's and its first-order error, locked to
        # the base's phase, differs between the two by up to 1.7e-3 (k_v = 20, 0 and 180 deg)
        assert fig12[(k_v, 330.0)] == pytest.approx(fig12[(k_v, 30.0)], rel=1e-8)
        assert fig12[(k_v, 150.0)] == pytest.approx(fig12[(k_v, 30.0)], rel=3e-3)
        assert fig12[(k_v, 120.0)] == pytest.approx(fig12[(k_v, 60.0)], rel=3e-3)
        assert fig12[(k_v, 180.0)] == pytest.approx(fig12[(k_v, 0.0)], rel=3e-3)
        assert fig12[(k_v, 210.0)] == pytest.approx(fig12[(k_v, 150.0)], rel=1e-8)


def test_closed_form_agrees_with_its_longitudinal_special_case():
    for k_v in (0.5, 1.5, 2.0, 6.0, 20.0):
        # midpoint rule across the jump of sgn(v_r): error ~ 1/N = 5e-6
        assert coulomb_ratio(k_v, 0.0, 0.71) == pytest.approx(longitudinal_ratio(k_v), abs=2e-5)


def rigid_contact(scene, k_v, update):
    """Body moved at exactly v_d; k_t u0 / F_c = 1200; steps small against s_c.

    The two-phase split rotates the asperity by a finite angle each step: its
    error is first order in (v dt / s_c), ~0.3% at 320000 steps a cycle.
    """
    f = scene.vibration.f
    u0 = k_v * scene.drive.v_d / (2 * math.pi * f)
    return scene.with_values({
        "drive.mode": "velocity", "vibration.k_v": k_v, "vibration.t_on": 0.0,
        "contact.k_t": 1200 * scene.F_c / u0, "contact.update": update,
        "time.T": 6 / f, "time.dt": 1 / (320_000 * f), "time.average_cycles": 4,
        "time.method": "transient"})


@pytest.mark.parametrize("update", ["paper", "exact"])
@pytest.mark.parametrize("name,theta", [("longitudinal", 0.0), ("transverse", 270.0)])
def test_rigid_coulomb_limit(load_scene, name, theta, update):
    scene = load_scene(name)
    for k_v in (2.0, 6.0):
        rigid = rigid_contact(scene, k_v, update)
        assert rigid.contact.k_t * rigid.u0 / rigid.F_c > 1000
        expected = coulomb_ratio(k_v, theta, scene.contact.eta_y)
        assert ratio(rigid) == pytest.approx(expected, rel=0.01)


def test_paper_update_past_its_stable_step_is_refused(load_scene):
    scene = load_scene("longitudinal", contact__update="paper", contact__k_t=8e9, time__T=0.2)
    with pytest.raises(NumericalError, match="2 s_c"):
        run_coupled(scene)
    assert np.isfinite(run_coupled(scene.with_values({"contact.update": "exact"})).F_d).all()


def test_wall_time_is_the_stepping_alone(load_scene, monkeypatch):
    """The compiled loop is loaded (numba's cache) before the clock starts."""
    from vibrofric.analytic import solve as solve_module

    scene = load_scene("longitudinal", time__T=0.2, time__method="transient")
    events = []
    load, step = solve_module.LOADERS["coupled"], solve_module.STEPPERS["coupled"]
    monkeypatch.setitem(solve_module.LOADERS, "coupled",
                        lambda s: (events.append("load"), load(s))[1])
    monkeypatch.setitem(solve_module.STEPPERS, "coupled",
                        lambda s: (events.append("step"), step(s))[1])
    clock = iter([10.0, 10.25])
    monkeypatch.setattr(solve_module, "perf_counter", lambda: (events.append("clock"), next(clock))[1])
    # the answer alone: the step-error estimate's runs are timed apart (error_wall_time_s)
    series, summary = solve(scene, estimate=False)
    assert events == ["load", "clock", "step", "clock"]
    assert summary["wall_time_s"] == 0.25 and series.t.size > 0
