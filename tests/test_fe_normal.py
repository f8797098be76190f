"""The FE model's base moving along Z (vibration.normal_amplitude > 0): the gaps,
the outputs, the energy balance (docs/fe-model.md, "The base moving along Z")."""

import math

import numpy as np
import pytest

from vibrofric.analytic.normal import contact_damping
from vibrofric.analytic.solve import solve
from vibrofric.api import load_scene
from vibrofric.fem import run_fe
from vibrofric.fem.integrators.normal_start import bounce_frequency
from vibrofric.fem.model.contact import contact_forces
from vibrofric.fem.model.fe_model import build_model
from vibrofric.fem.outputs.normal_swing import judge, settled
from vibrofric.fem.simulate import answer_ratio
from vibrofric.meshes import DEFAULT_SIZE

from low_block import low_block_scene, stiff_block_scene


def _normal_scene(amplitude, integrator="explicit", mesh="tiny", **keys):
    """The longitudinal scene on a small block, its base moving along Z from 2 ms, the
    energy balance recorded, 8 averaged cycles (2 ms) from T = 10 ms."""
    values = {"vibration__normal_amplitude": amplitude, "vibration__t_on": 0.002,
              "time__T": 0.01, "time__average_cycles": 8, "time__method": "transient",
              "time__error_estimate": False, "fem__integrator": integrator,
              "fem__mesh": mesh, "fem__energy": True, "fem__output_every": 0, **keys}
    if integrator != "explicit":
        values.setdefault("time__dt", 5e-6)
    return load_scene("longitudinal", **values)


def test_a_base_and_body_moved_together_along_z_leave_every_force_as_it_was():
    """contact.contact_forces sees the gap g0 + u_z - z_b and the speed v_z - v_zb
    alone: the same relative motion at any base height (and any rest height g0) gives
    the same forces, to the rounding of the added heights."""
    scene = load_scene("longitudinal")
    law = scene.friction
    kernel = contact_forces.for_law(law.law)
    n = 6
    share = np.array([0.1, 0.2, 0.3, 0.25, 0.1, 0.05])
    old = np.zeros((n, 3))
    old[:, 2] = [-2e-9, -5e-9, -1e-9, -3e-9, 1e-10, 0.0]        # the last two out of contact
    new = old + [1e-9, 0.0, 0.0]
    vel = np.array([1e-4, -2e-4, 0.0, 3e-4, -1e-4, 0.0])
    results = []
    for z_b, v_zb, gap0 in ((0.0, 0.0, 0.0), (3e-8, 2e-3, 0.0), (-4e-8, -1e-3, 1e-8)):
        lifted_old, lifted_new = old.copy(), new.copy()
        lifted_old[:, 2] += z_b - gap0
        lifted_new[:, 2] += z_b - gap0
        states = law.law.initial_state(n)
        normal, friction = np.empty(n), np.empty((n, 2))
        kernel(lifted_old, lifted_new, vel + v_zb, 0.0, 0.0, 0.0, np.full(n, gap0), z_b, v_zb,
               1e10 * share, share, np.zeros(n), 2e-7, law.params, 1e-6, np.inf, states,
               normal, friction)
        results.append((normal.copy(), friction.copy()))
    base_normal, base_friction = results[0]
    assert base_normal[:4].min() > 0.0 and not base_normal[4:].any()
    for normal, friction in results[1:]:
        # 1e-6: heights of 4e-8 m added to and taken from gaps of 1e-9 m lose ~1e-16 m
        assert normal == pytest.approx(base_normal, rel=1e-6, abs=0.0)
        assert friction == pytest.approx(base_friction, rel=1e-6, abs=0.0)


def test_an_explicit_run_records_the_normal_motion_and_closes_its_energy_balance():
    """Below contact loss: the series' z, z_b, N columns (z_b the base's sinusoid, N the
    summed normal force), the summary's normal-force keys, the normal force's forced
    swing as the rigid body on its bounce stiffness has it, and the explicit balance
    closing to rounding (no node touches down or lifts off: every force is linear over
    the window, and the shadow form's identity is exact)."""
    amplitude, phase = 5e-8, 30.0
    scene = _normal_scene(amplitude, vibration__normal_phase_deg=phase)
    result = run_fe(scene)
    series, info = result.series, result.info
    assert series.names[-3:] == ("z", "z_b", "N")
    assert np.array_equal(series.extra["N"], series.extra["F_n"])
    on = series.t >= scene.vibration.t_on
    expected = amplitude * np.sin(scene.omega * (series.t[on] - scene.vibration.t_on)
                                  + math.radians(phase))
    # 1e-12 m: the phase is rotated step by step and re-anchored every 1024 (base_motion.py)
    assert series.extra["z_b"][on] == pytest.approx(expected, abs=1e-12 * amplitude / 1e-8)
    assert not series.extra["z_b"][~on].any()
    assert info["contact_loss_fraction"] == 0.0
    assert info["normal_force_min"] > 0.0
    # the forced swing of the body on its contact, m w^2 A_n / (1 - r^2); 3%: the block is
    # not rigid (the bar's first mode, core/bounce.py) and the friction rocks it a little
    model = build_model(scene, None)
    r = scene.omega / bounce_frequency(model, scene)
    forced = model.block_mass * scene.omega ** 2 * amplitude / (1.0 - r * r)
    swing = 0.5 * (info["normal_force_max"] - info["normal_force_min"])
    assert swing == pytest.approx(forced, rel=0.03)
    assert info["normal_force_mean"] == pytest.approx(scene.contact.F_N, rel=1e-3)
    # the body follows the base: its face's mean height swings by H A_n, H = 1 / (1 - r^2)
    z = series.extra["z"][-2000:]
    assert 0.5 * (z.max() - z.min()) == pytest.approx(amplitude / (1.0 - r * r), rel=0.03)
    assert info["energy_base_work"] > 0.0
    assert info["energy_closure"] < 1e-8       # rounding: measured 5e-14


def test_a_shipped_scene_keeps_its_columns_and_no_normal_motion_means_no_normal_columns():
    scene = _normal_scene(0.0, fem__energy=False)
    result = run_fe(scene)
    assert "z_b" not in result.series.extra and "N" not in result.series.extra
    assert result.info["contact_loss_fraction"] == 0.0
    assert result.info["normal_force_mean"] == pytest.approx(scene.contact.F_N, rel=1e-2)


@pytest.mark.slow
@pytest.mark.parametrize("integrator", ["explicit", "implicit", "reduced"])
@pytest.mark.parametrize("amplitude", [5e-8, 2.2e-7])      # in contact; losing it
def test_the_energy_balance_closes_within_one_percent_of_the_base_work(integrator, amplitude):
    """The acceptance: the balance closes within 1% of the base's work over the averaged
    cycles, for every integrator, with and without contact loss (coarse block). Losing
    contact, the body bounces irregularly on its penalty springs (22 kHz, contacts of
    ~20 us), and what each touch-down and lift-off leaves (the penalty's kink within a
    step) shrinks with the step: measured explicit 1.0% at 1e-6 s, 0.25% at 5e-7 s;
    implicit (rho_infinity = 1: no numerical dissipation) 1.6-2.4% at 2.5e-6 s, 0.7% at
    1e-6 and 5e-7 s, 0.02% at 2.5e-7 s; reduced 0.96% at 5e-7 s, 0.11% at 2.5e-7 s. So
    the runs losing contact take 5e-7 s (explicit) and 2.5e-7 s (implicit, reduced)."""
    keys = {"time__T": 0.012}
    if amplitude > 1e-7:
        keys["time__dt"] = 5e-7 if integrator == "explicit" else 2.5e-7
        if integrator != "explicit":
            keys["fem__rho_infinity"] = 1.0
    scene = _normal_scene(amplitude, integrator, mesh="coarse", **keys)
    info = run_fe(scene).info
    lost = info["contact_loss_fraction"] > 0.0
    assert lost == (amplitude > 1e-7)
    assert info["energy_closure"] < 0.01


@pytest.mark.parametrize("integrator", ["explicit", "implicit", "reduced"])
def test_a_base_starting_at_its_crest_does_not_strike_the_body(integrator):
    """normal_start.py: at phase 90 deg the base comes on at z_b = A_n, a jump; the body
    starts on its forced response (its face at H_face z_b, its speed H dz_b/dt), so it
    keeps its contact from the first step (k_pen A_n = 2.4e3 N here, 43 F_N: a strike
    would lose it) and its summed normal force swings by the forced m w^2 A_n / (1 - r^2)
    over the window. The implicit integrators at 1e-6 s: at 5e-6 s (50 steps a cycle,
    w_b dt = 0.7) a free bounce of ~3 N was left in the window (19.4 N against 16.3)."""
    amplitude = 5e-8
    scene = _normal_scene(amplitude, integrator, vibration__normal_phase_deg=90.0,
                          vibration__k_v=0.0, fem__energy=False, time__dt=1e-6)
    result = run_fe(scene)
    info = result.info
    model = build_model(scene, None)
    r = scene.omega / bounce_frequency(model, scene)
    forced = model.block_mass * scene.omega ** 2 * amplitude / (1.0 - r * r)
    on = result.series.t >= scene.vibration.t_on
    assert result.series.extra["N"][on].min() > 0.6 * scene.contact.F_N   # forced: 0.70 F_N
    # 2%: the block's compliance and what the start leaves of the bounce (measured 0.8%)
    assert 0.5 * (info["normal_force_max"] - info["normal_force_min"]) == pytest.approx(
        forced, rel=0.02)
    assert info["contact_loss_fraction"] == 0.0
    assert info["F_n_kind"] == "forced"


def test_the_steady_cycle_is_shot_for_where_the_contact_holds():
    """time.method auto: the cycle map is smooth while every node stays in contact, and
    the shooting answers (integrators/periodic.py); the normal keys come from its cycle."""
    scene = _normal_scene(5e-8, mesh="coarse", time__method="auto", fem__energy=False)
    result = run_fe(scene)
    info = result.info
    assert info["periodic"]["method"] == "periodic", info["periodic"]["reason"]
    assert info["contact_loss_fraction"] == 0.0
    F_N = scene.contact.F_N
    assert info["normal_force_min"] < 0.8 * F_N and info["normal_force_max"] > 1.2 * F_N
    assert result.series.names[-3:] == ("z", "z_b", "N")


def test_the_command_line_reports_the_fe_normal_keys_and_columns(tmp_path, capsys):
    import json

    from vibrofric.cli import main

    out = tmp_path / "run"
    assert main(["run", "longitudinal", "--set", "vibration.normal_amplitude=5e-8",
                 "--set", 'fem.mesh="tiny"', "--set", "vibration.t_on=0.002",
                 "--set", "time.T=0.01", "--set", "time.average_cycles=8",
                 "--set", 'time.method="transient"', "--set", "time.error_estimate=false",
                 "--set", "fem.energy=true", "--json", "--out", str(out)]) == 0
    fe = json.loads(capsys.readouterr().out)["fe"]
    for key in ("contact_loss_fraction", "normal_force_mean", "normal_force_min",
                "normal_force_max", "energy_closure"):
        assert isinstance(fe[key], float), key
    assert fe["normal_force"] == "forced"
    header = (out / "timeseries.csv").read_text().splitlines()[0].split(",")
    assert header[-3:] == ["z", "z_b", "N"]
    assert json.loads((out / "summary.json").read_text())["fe"]["energy_closure"] == fe[
        "energy_closure"]


def test_a_body_leaving_the_base_each_cycle_is_judged_bouncing_not_forced():
    """normal_swing.judge with the base moving along Z, 40 cycles of f = 4 kHz at dt =
    1e-6 s around F_N = 55 N: a swing at the harmonics of f that stays above 0 is the
    body's forced response in contact; the same swing cut off at 0 (the body out of
    contact for part of each cycle and landing, as a steady cycle found by the shooting
    is) is bouncing and settled; reaching 0 with a free 10.7 kHz line on top (no cycle)
    it is bouncing and unsettled."""
    F_N, dt, f = 55.0, 1e-6, 4000.0
    t = np.arange(10000) * dt
    forced = np.sin(2 * np.pi * f * t) + 0.3 * np.cos(2 * np.pi * 3 * f * t)
    in_contact = judge(F_N * (1 + 0.7 * forced / 1.3), dt, f, F_N, 1e-8, moving_base=True)
    assert in_contact.kind == "forced" and in_contact.low > 0.0
    cycle = judge(np.maximum(F_N * (1 + 1.2 * forced / 1.3), 0.0), dt, f, F_N, 1e-8,
                  moving_base=True)
    assert cycle.kind == "bouncing" and cycle.low == 0.0
    assert settled(cycle.kind, cycle.forced)
    free = np.sin(2 * np.pi * 10700 * t)
    irregular = judge(np.maximum(F_N * (1 + 0.2 * forced + 1.2 * free), 0.0), dt, f, F_N,
                      1e-8, moving_base=True)
    assert irregular.kind == "bouncing" and not settled(irregular.kind, irregular.forced)


def follows_the_lumped_body_losing_contact(scene, fe_values=(), steps=200):
    """Check ``scene`` (a stiff block above A_th) against the lumped body, as
    docs/validation.md "A base moving along Z" poses it: the lumped body stepped, the
    FE block (with ``fe_values``) at ``steps`` a cycle. Both lose contact for part of
    the cycle, their loss fractions within 0.05 of each other, and their F_dv/F_d0
    within the acceptance's 5%."""
    _, lumped = solve(scene.with_values({"time.method": "transient"}), estimate=False)
    fe_scene = scene.with_values({"time.dt": 1.0 / (steps * scene.vibration.f),
                                  **dict(fe_values)})
    result = run_fe(fe_scene)
    loss = lumped["contact_loss_fraction"]
    assert 0.05 < loss < 0.3 and lumped["normal_force_min"] == 0.0
    assert result.info["normal_force_min"] == pytest.approx(0.0, abs=1e-6)
    assert result.info["contact_loss_fraction"] == pytest.approx(loss, abs=0.05)
    assert answer_ratio(result, fe_scene) == pytest.approx(lumped["F_dv_over_F_d0"], rel=0.05)
    # its steady cycle (or a stepped run settled on it) named as the orbit it is
    assert result.info["F_n_kind"] == "bouncing"


def test_the_low_stiff_block_posed_alike_follows_the_lumped_body_losing_contact():
    """docs/validation.md "A base moving along Z": the low stiff block (its rocking
    moment small, its own compliance out of the bounce), both contacts damped alike
    (contact.zeta_n = 0.05, fem.damping = c_n / k_pen), 2% above A_th: both models out of
    contact for part of the cycle (measured 12.6% of the lumped cycle, 11.6% of the FE
    node-time) and their F_dv/F_d0 within 0.1%. The bounds: the acceptance's 5%, the
    loss fractions within 0.05 (the nodes near the face's edges open a little longer);
    the FE block's default dashpots (damping ratio ~3e-3) send it onto the bouncing
    orbit, out of contact ~96% of the time, its F_dv/F_d0 near 0."""
    scene = low_block_scene(1.02, 6.0, 0.05)
    follows_the_lumped_body_losing_contact(scene)


# The FE block held as the lumped body is: pulled and pressed at its top face, which
# translates without turning (fem/model/holder.py).
HELD = {"drive.attach": "load-group", "drive.holder": "translating"}


@pytest.mark.slow
def test_the_paper_block_held_at_its_top_follows_the_lumped_body_losing_contact():
    """docs/validation.md "A base moving along Z": the paper's 53 mm block, stiff (E x
    10), held as the lumped body is: pulled and pressed at its top face, which
    translates without turning (drive.attach = "load-group", drive.holder =
    "translating"); its bounce damped at the lumped contact.zeta_n = 0.05 (fem.damping
    = c_n / k_n: the Rayleigh damping beta (K + K_pen) damps a mode at beta w / 2). 2%
    above A_th both models lose contact for part of the cycle (measured 10.8% of the
    lumped cycle, 12.8% of the FE node-time) and their F_dv/F_d0 agree within 2%
    (measured -1.80%). The bounds: the acceptance's 5%; the loss fractions within 0.05
    (the back half of the face opens a little longer). Unheld (the contact-plane drive)
    the same block rocks, one edge landing alone, and goes over to bouncing: out of
    contact 97.5% of the node-time, F_dv/F_d0 0.094 against 0.428 (measured with the
    holder's keys taken out), which fails both bounds."""
    scene = stiff_block_scene(DEFAULT_SIZE, 1.02, 6.0, 0.05)
    scene = scene.with_values({"fem.damping": contact_damping(scene) / scene.normal_stiffness})
    follows_the_lumped_body_losing_contact(scene, HELD)


@pytest.mark.slow
@pytest.mark.parametrize("phase", [0.0, 90.0])
def test_the_paper_block_stiff_enough_follows_the_lumped_body_where_the_curve_is_steep(phase):
    """docs/validation.md "A base moving along Z": 5% above A_th, where F_dv/F_d0 falls
    by about 0.05 F_d0 for each 1% of A_n, the held paper's block follows the lumped
    body once it is stiff enough that its face stays flat: at E x 100 both lose contact
    22% of the cycle and their F_dv/F_d0 agree within 2% (measured +1.85% along X,
    +0.25% elliptical, phase 90 deg; converged in both steps +2.7% along X). Both
    models at steps where each is within 1% of its limit (FE 400 a cycle, lumped
    1.25e-7 s). The bound is the acceptance's 5%. At E x 10 the case along X gives +5.0% here (+5.8% at the
    benchmark's timing: the face opening back half first) and fails it; unheld at
    E x 100 the block rocks over onto bouncing (out of contact 99% of the node-time
    in both cases) and fails the loss fraction's bound."""
    scene = stiff_block_scene(DEFAULT_SIZE, 1.05, 6.0, 0.05, stiffer=100.0,
                              **{"time.dt": 1.25e-7, "vibration.normal_phase_deg": phase})
    scene = scene.with_values({"fem.damping": contact_damping(scene) / scene.normal_stiffness})
    follows_the_lumped_body_losing_contact(scene, HELD, steps=400)
