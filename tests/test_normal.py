"""The lumped body's normal degree of freedom (vibrofric/analytic/normal.py)."""

import math

import numpy as np
import pytest

from vibrofric.analytic import normal
from vibrofric.analytic.coupled import run_coupled
from vibrofric.analytic.longitudinal import run_longitudinal
from vibrofric.analytic.solve import solve, solve_with_orbit
from vibrofric.api import load_scene
from vibrofric.core.bounce import bar_on_spring_root, bounce_stiffness, default_penalty
from vibrofric.core.series import COLUMNS, RecordPlan, full_resolution_steps
from vibrofric.scene import SceneError, check_fe_scene
from vibrofric.scene.schema import Contact

from low_block import low_block_scene
from vibrofric.scene.validation import normal_step_bound


def _normal_only(amplitude: float, **keys):
    """The longitudinal scene with no in-plane vibration, its base moving along Z from
    t_on = 10 ms: every step of the last 20 cycles kept, 1000 steps a cycle."""
    values = {"vibration__k_v": 0.0, "vibration__t_on": 0.01, "vibration__f": 4000.0,
              "vibration__normal_amplitude": amplitude, "time__T": 0.03, "time__dt": 2.5e-7,
              "time__average_cycles": 20, "time__method": "transient", **keys}
    return load_scene("longitudinal", **values)


def _forced_amplitude(scene) -> float:
    """The closed form: k_n A r^2 / |1 - r^2|, r = w / w_n (undamped, in contact)."""
    r = scene.omega / math.sqrt(scene.normal_stiffness / scene.body.mass)
    return scene.normal_stiffness * scene.vibration.normal_amplitude * r * r / abs(1.0 - r * r)


def _loss_threshold(scene) -> float:
    """The amplitude A at which the closed form's normal-force swing reaches F_N."""
    return scene.vibration.normal_amplitude * scene.contact.F_N / _forced_amplitude(scene)


@pytest.mark.parametrize("f", [4000.0, 12000.0])   # r = 0.18 and 0.54
def test_normal_force_amplitude_below_contact_loss_is_the_closed_form(f):
    probe = _normal_only(1e-9, vibration__f=f)
    scene = _normal_only(0.5 * _loss_threshold(probe), vibration__f=f)
    series, summary = solve(scene, "longitudinal", estimate=False)
    N = series.extra["N"][-round(20 / (f * scene.time.dt)):]
    measured = 0.5 * (N.max() - N.min())
    # 1e-3: semi-implicit Euler shifts w_n by (w_n dt)^2 / 24 = 5e-5 at this step, the
    # peak falls between steps by at most 1 - cos(pi w dt) < 1e-4, the contact's damping
    # (contact.zeta_n) moves the amplitude by < 1e-4 (normal.py); the rest is the tolerance's margin
    assert measured == pytest.approx(_forced_amplitude(scene), rel=1e-3)
    assert summary["contact_loss_fraction"] == 0.0
    assert summary["normal_force_mean"] == pytest.approx(scene.contact.F_N, rel=1e-3)


def test_contact_loss_starts_at_the_closed_forms_threshold_to_one_step():
    threshold = _loss_threshold(_normal_only(1e-9))
    step = 0.01 * threshold                     # the amplitudes tried: 1% apart
    amplitudes = threshold * (0.96 + 0.01 * np.arange(9))
    lost = [solve(_normal_only(a), "longitudinal", estimate=False)[1]["contact_loss_fraction"] > 0
            for a in amplitudes]
    assert not lost[0] and lost[-1]
    first = amplitudes[lost.index(True)]      # the first amplitude tried that loses contact
    assert abs(first - threshold) <= step * (1 + 1e-9)


@pytest.mark.parametrize("stepper, run", [("coupled", run_coupled),
                                          ("longitudinal", run_longitudinal)])
def test_without_normal_motion_the_normal_loop_answers_the_existing_loops_bit_for_bit(stepper, run):
    """normal_loop at A_n = 0 holds N = F_N exactly, so it passes the friction law
    what coupled_loop passes; the existing loops stay what runs without normal motion."""
    scene = load_scene(stepper, time__T=0.2, time__method="transient",
                       **({"vibration__theta_deg": 30.0} if stepper == "coupled" else {}))
    plan = RecordPlan.for_scene(scene, full_resolution_steps(scene))
    out = np.empty((plan.rows, len(COLUMNS) + len(normal.NORMAL_COLUMNS)))
    assert normal._run_loop(scene, stepper == "coupled", plan, out) == 0
    existing = run(scene).table()
    # to 1e-11 of each column's largest value, not to the bit: the two are separately
    # compiled loops, which numba's compile variants may round apart (equal in most fresh
    # clones; one differed, as the FE table loop's 2.6e-13: benchmarks/same_results.py
    # holds the shipped scenes' own bits)
    scale = np.abs(existing).max(axis=0)
    assert np.all(np.abs(out[:, :len(COLUMNS)] - existing) <= 1e-11 * scale)
    assert np.all(out[:, -1] == scene.contact.F_N) and np.all(out[:, 8:10] == 0.0)
    assert "N" not in run(scene).extra      # and their series keep their columns


def _popov_scene(F_N, k_t, f, mass, v_tilde, alpha, r):
    """A scene of Popov et al.'s regime (Friction 5 (2017) 45-55): a stiff system, the
    body driven at exactly v_d; the normal-force oscillation imposed on the contact,
    N = F_N + k_n z_b, the body too heavy to follow the base in Z (r = w / w_n >> 1;
    held fixed, with the contact's damping ratio). Set by their dimensionless sliding
    velocity v~ = v_d / (w u_c), u_c = mu F_N / k_t the sliding length, and amplitude
    alpha = k_n A / F_N; time in cycles: 500 steps a cycle, t_on 20 cycles, T 60 (t_on
    and T whole numbers of steps, so that both runs start the base on the same step).
    Popov's pair as closed_form.normal_oscillation_ratio takes it (the normal force's
    swing over F_N, alpha G(r, zeta), and k_t v_d / (w mu F_N alpha G)) is a function of
    these two, r and the contact's damping ratio: held fixed with them."""
    mu = 0.1
    omega = 2 * math.pi * f
    k_n = mass * (omega / r) ** 2
    return load_scene("longitudinal", drive__mode="velocity", contact__F_N=F_N, contact__mu=mu,
                      contact__k_t=k_t, contact__k_n=k_n, body__mass=mass,
                      drive__v_d=v_tilde * omega * mu * F_N / k_t, vibration__k_v=0.0,
                      vibration__f=f, vibration__normal_amplitude=alpha * F_N / k_n,
                      vibration__t_on=10_000 / (500 * f), time__T=30_000 / (500 * f),
                      time__dt=1 / (500 * f),
                      time__average_cycles=20, time__method="transient")


# The tolerance: far inside the answers' own step error (time.accuracy 1e-3 on the ratio).
# The two runs are one discrete system in different units, apart from rounding (the
# phase's w dt, the scaled keys); in contact their answers agreed to 4.5e-8, and where
# the body leaves its contact (alpha > 1) the bouncing orbit amplifies rounding: 2.9e-5.
@pytest.mark.parametrize("alpha, tolerance", [(0.5, 1e-6), (1.5, 1e-4)])
def test_popov_scaling_the_ratio_depends_on_the_dimensionless_groups_alone(alpha, tolerance):
    first = _popov_scene(F_N=55.0, k_t=2e6, f=4000.0, mass=0.5, v_tilde=0.3, alpha=alpha, r=20.0)
    second = _popov_scene(F_N=7.0, k_t=3.1e7, f=900.0, mass=2.3, v_tilde=0.3, alpha=alpha, r=20.0)
    ratios = [solve(s, "longitudinal", estimate=False)[1]["F_dv_over_F_d0"]
              for s in (first, second)]
    assert ratios[0] < 0.99                   # the normal motion lowers the friction
    assert ratios[1] == pytest.approx(ratios[0], rel=tolerance)


def _force_swing_gain(r: float) -> float:
    """N's swing over k_n A_n in contact at r = w / w_n, the contact's dashpot included."""
    two_zeta_r = 2.0 * Contact().zeta_n * r   # the scenes' default
    return r * r * math.hypot(1.0, two_zeta_r) / math.hypot(1.0 - r * r, two_zeta_r)


# Popov's groups as closed_form.normal_oscillation_ratio takes them: alpha the normal force's
# swing over F_N, v~ = k_t v_d / (w mu alpha F_N). The tolerance: the step's error at 500
# steps a cycle (measured 1.6e-6 to 1.1e-5 off the closed form at these points, estimated
# by analytic/accuracy.py at 1.7e-6 to 1.4e-5; 1e-14 at v~ > 1); 3e-5 leaves a factor 3.
@pytest.mark.parametrize("v_tilde, alpha", [(0.05, 0.9), (0.3, 0.6), (0.7, 0.3), (1.2, 0.6)])
def test_an_elastic_plastic_contact_under_normal_oscillation_is_popovs_closed_form(v_tilde, alpha):
    """Dahl's law at exponent 0 (elastic up to mu N, then sliding) in Popov et al.'s stiff
    system (_popov_scene: the body driven at v_d, too heavy to follow the base in Z) is
    the elastic-plastic contact of their model: its ratio is the closed form's."""
    from vibrofric.analytic.closed_form import normal_oscillation_ratio

    r = 20.0
    scene = _popov_scene(F_N=55.0, k_t=2e6, f=4000.0, mass=0.5, v_tilde=v_tilde * alpha,
                         alpha=alpha / _force_swing_gain(r), r=r).with_values(
        {"contact.dahl_exponent": 0.0, "time.method": "periodic"})
    _, summary = solve(scene)
    assert summary["periodic"]["method"] == "periodic" and summary["contact_loss_fraction"] == 0.0
    # the normal force swings by alpha F_N (the gain's closed form; 1e-3: the peak between steps)
    swing = summary["normal_force_max"] - scene.contact.F_N
    assert swing == pytest.approx(alpha * scene.contact.F_N, rel=1e-3)
    closed = normal_oscillation_ratio(v_tilde, alpha)
    assert summary["F_dv_over_F_d0"] == pytest.approx(closed, abs=3e-5)
    assert summary["error_estimate"] <= 3e-5


def _quasi_static_contact_ratio(v_tilde: float, alpha: float, steps: int = 50_000) -> float:
    """The contact of closed_form.normal_oscillation_ratio stepped directly over the phase:
    the spring loads by alpha v_tilde dtau a step and is held at or below the limit
    max(0, 1 + alpha cos tau) (released where that is 0); three cycles from rest, the last
    averaged. Independent of the closed form's stick interval and its area."""
    step = 2.0 * math.pi / steps
    limits = np.maximum(0.0, 1.0 + alpha * np.cos((np.arange(steps) + 0.5) * step))
    force, total = 0.0, 0.0
    for cycle in range(3):
        total = 0.0
        for limit in limits:
            force = min(force + alpha * v_tilde * step, limit)
            total += force
    return total / limits.sum()


# The tolerance: the stepped contact's error, first order in its step (the limit sampled
# at midpoints, the landing and the stick's end found to a step): at 50 000 steps a
# cycle measured 1.5e-5 at most at these points (4.4e-5 at 20 000, 1.8e-6 at 400 000);
# 1e-4 leaves a factor 6. alpha > 1 loses contact over part of the cycle.
@pytest.mark.parametrize("v_tilde, alpha", [(0.1, 0.6), (0.5, 0.9), (0.1, 1.5), (0.3, 1.5),
                                            (0.7, 3.0), (0.95, 1.2)])
def test_popovs_closed_form_is_the_contact_stepped_over_its_phase(v_tilde, alpha):
    from vibrofric.analytic.closed_form import normal_oscillation_ratio

    closed = normal_oscillation_ratio(v_tilde, alpha)
    assert closed < 0.999                      # a reduction to check, not the plain 1
    assert closed == pytest.approx(_quasi_static_contact_ratio(v_tilde, alpha), abs=1e-4)


# The tolerance: the next order of the small-velocity expansion, measured 1.34e-5 of the
# limit at v~ = 1e-5 (linear in v~: 1.3e-4 at 1e-4); 1e-4 leaves a factor 7.
@pytest.mark.parametrize("alpha", [1.5, 3.0, 10.0])
def test_past_contact_loss_popovs_ratio_vanishes_with_the_sliding_velocity(alpha):
    """Released at every loss of contact, the spring loads from 0 over the contact arc
    2 theta (cos theta = -1 / alpha) and stays below the limit: the mean force is the
    line's, ratio -> alpha theta^2 / (theta + alpha sin theta) v~, where in contact it
    tends to 1 - alpha."""
    from vibrofric.analytic.closed_form import mean_contact_load, normal_oscillation_ratio

    theta = math.acos(-1.0 / alpha)
    # the contact's mean load, against the midpoint rule on 200 000 points (its error
    # ~h^2 where the load's slope jumps: measured below 1e-10)
    phase = (np.arange(200_000) + 0.5) * (2.0 * math.pi / 200_000)
    mean = float(np.mean(np.maximum(0.0, 1.0 + alpha * np.cos(phase))))
    assert mean_contact_load(alpha) == pytest.approx(mean, rel=1e-9)
    slope = alpha * theta ** 2 / (theta + alpha * math.sin(theta))
    v_tilde = 1e-5
    assert normal_oscillation_ratio(v_tilde, alpha) / v_tilde == pytest.approx(slope, rel=1e-4)
    assert normal_oscillation_ratio(v_tilde, 0.6) == pytest.approx(0.4, abs=1e-4)


def _jumping_scene(v_tilde: float, alpha: float):
    """Popov's stiff system past contact loss on the lumped body: driven at exactly v_d,
    the base's Z swing imposed on a body too heavy to follow it (r = w / w_n = 50: the
    body moves by 1/r^2 = 4e-4 of the base), the contact's dashpot nearly off
    (zeta_n = 2e-5: it leads the spring's force by 2 zeta_n r = 0.002 rad, and still
    damps the body's free bounce enough for the periodic orbit to be found). The body
    sinks until the contact carries F_N on average: the indentation's mean d_0 then
    holds k_n d_0 mean_contact_load(alpha) = F_N, and A_n is set so that its swing
    (the base's, times the forced response's gain) is alpha d_0. 2000 steps a cycle."""
    from vibrofric.analytic.closed_form import mean_contact_load

    F_N, mu, k_t, f, mass, r, zeta = 55.0, 0.1, 2e6, 4000.0, 0.5, 50.0, 2e-5
    omega = 2.0 * math.pi * f
    k_n = mass * (omega / r) ** 2
    k_n_d_0 = F_N / mean_contact_load(alpha)
    gain = r * r * math.hypot(1.0, 2 * zeta * r) / math.hypot(1.0 - r * r, 2 * zeta * r)
    return load_scene("longitudinal", drive__mode="velocity", contact__F_N=F_N,
                      contact__mu=mu, contact__k_t=k_t, contact__dahl_exponent=0.0,
                      contact__k_n=k_n, contact__zeta_n=zeta, body__mass=mass,
                      drive__v_d=v_tilde * alpha * omega * mu * k_n_d_0 / k_t,
                      vibration__k_v=0.0, vibration__f=f,
                      vibration__normal_amplitude=alpha * k_n_d_0 / (k_n * gain),
                      time__dt=1.0 / (2000 * f), time__method="periodic")


# The tolerance: the lumped body is Popov's prescribed indentation up to its dashpot's
# lead (2 zeta_n r = 0.002 rad: the force comes off before the spring does; the
# difference grows with zeta_n: 2.7e-3 at 8e-5 at alpha 2, v~ 0.7, 4000 steps a cycle),
# the body's own motion and the landing found to a step (2 pi / 2000 rad). Over the 28
# points of benchmarks/popov_normal.py's contact-loss table they differ from the closed
# form by at most 4.4e-4, here +6.4e-5 and -3.5e-4; 1.5e-3 leaves a factor 3.4. The
# contact is out over the closed form's arc to 1e-3 (measured 6e-4: the dashpot's lead
# and a step).
@pytest.mark.parametrize("v_tilde, alpha", [(0.3, 1.5), (0.7, 3.0)])
def test_the_lumped_body_losing_contact_is_popovs_closed_form_past_contact_loss(v_tilde, alpha):
    from vibrofric.analytic.closed_form import normal_oscillation_ratio

    _, summary = solve(_jumping_scene(v_tilde, alpha))
    assert summary["periodic"]["method"] == "periodic"
    theta = math.acos(-1.0 / alpha)
    assert summary["contact_loss_fraction"] == pytest.approx(1.0 - theta / math.pi, abs=1e-3)
    assert summary["F_dv_over_F_d0"] == pytest.approx(normal_oscillation_ratio(v_tilde, alpha),
                                                      abs=1.5e-3)


def test_the_fe_model_refuses_a_base_moving_into_the_body_faster_than_its_step_resolves():
    """scene/validation.py normal_step_bound: A_n w dt <= 10 F_N / k_pen (4.6e-7 m on the
    paper's block at 4 kHz and 1e-6 s); just above it is refused, just below taken."""
    scene = load_scene("longitudinal", vibration__normal_amplitude=1e-8)
    bound = normal_step_bound(scene)
    assert bound == pytest.approx(10.0 * 55.0 / (10.0 * 209e9 * 0.03 * 0.04 / 0.053)
                                  / (2 * math.pi * 4000.0 * 1e-6), rel=1e-2)
    check_fe_scene(scene)
    check_fe_scene(load_scene("longitudinal", vibration__normal_amplitude=0.99 * bound))
    with pytest.raises(SceneError, match="^vibration.normal_amplitude: .*more than the penalty"):
        check_fe_scene(load_scene("longitudinal", vibration__normal_amplitude=1.01 * bound))
    check_fe_scene(load_scene("longitudinal"))


def test_a_phase_without_an_amplitude_is_refused():
    with pytest.raises(SceneError, match="^vibration.normal_phase_deg: "):
        load_scene("longitudinal", vibration__normal_phase_deg=90.0)
    load_scene("longitudinal", vibration__normal_phase_deg=90.0, vibration__normal_amplitude=1e-8)


def test_the_default_normal_stiffness_bounces_at_the_bar_on_its_penalty_spring():
    from vibrofric.fem.model.contact import default_contact_stiffness

    scene = load_scene("longitudinal")
    body = scene.body
    # the FE model's per-area default on the block's face (flat: no curvature radius)
    # is the lumped model's whole-face penalty (to rounding: 1e-15)
    Lx, Ly, Lz = body.size
    per_area = default_contact_stiffness(body.E, body.nu, Lz, scene.contact.F_N, math.inf)
    assert per_area * Lx * Ly == pytest.approx(default_penalty(body.E, body.size), rel=1e-15)
    x = bar_on_spring_root(10.0)
    assert x * math.tan(x) == pytest.approx(10.0, rel=1e-12)
    # a far stiffer block bounces as a rigid one on the penalty spring: k_n -> k_p
    # (x tan x = x^2 (1 + x^2 / 3 + ...): at k_p L / (E A) = 1e-5, 3e-6 of k_p is left)
    stiff = bounce_stiffness(body.mass, 1e6 * body.E, 7850.0 * 1e6, body.size,
                             default_penalty(body.E, body.size))
    rigid = default_penalty(body.E, body.size) * body.mass / (7850.0 * 1e6 * 0.03 * 0.04 * 0.053)
    assert stiff == pytest.approx(rigid, rel=1e-5)
    assert scene.normal_stiffness == pytest.approx(0.204 * default_penalty(body.E, body.size),
                                                   rel=0.01)


@pytest.mark.parametrize("phase, method", [(0.0, "auto"), (90.0, "auto"), (90.0, "transient")])
def test_a_normal_run_carries_its_step_error_and_is_judged_settled(phase, method):
    """The answer's error (analytic/accuracy.py): the orbits at dt/2 and dt/4, or the
    stepped runs at dt/2 and dt/4 whatever step the base's start falls on; the summary's
    settled judgement and normal-force keys."""
    scene = load_scene("longitudinal", vibration__normal_amplitude=1e-7, time__T=0.3,
                       vibration__normal_phase_deg=phase, time__method=method)
    series, summary = solve(scene)
    if method == "auto":
        assert summary["periodic"]["method"] == "periodic", summary["periodic"]
        assert summary["dt_used"] == summary["periodic"]["dt"]
    else:
        assert summary["dt_used"] == scene.time.dt
    assert summary["error_estimate"] is not None
    assert summary["settled"] is True
    # started on its forced response, the body keeps its contact at 0.6 of the threshold
    assert summary["contact_loss_fraction"] == 0.0
    assert summary["normal_force_max"] - scene.contact.F_N == pytest.approx(
        _forced_amplitude(scene), rel=1e-2)   # 1e-2: 250 steps a cycle here, 1000 above
    assert series.names[-3:] == normal.NORMAL_COLUMNS


# 1.7e-7 m: 1% above the closed form's threshold of contact loss (168 nm), the orbit out
# of contact over 5% of its cycle. The stepped run to 1.2 s has settled (its slowest
# multiplier 0.98 a cycle: decayed below 1e-20 over its 4000 cycles), so the two agree to
# rounding (measured 2e-13 on the ratio); 1e-9 leaves room for the compiled variants.
@pytest.mark.parametrize("amplitude", [1e-7, 1.7e-7])
def test_the_periodic_answer_with_normal_motion_is_the_settled_stepped_one(amplitude):
    scene = load_scene("longitudinal", vibration__normal_amplitude=amplitude,
                       vibration__normal_phase_deg=30.0, time__method="periodic")
    _, answer = solve(scene, estimate=False)
    block = answer["periodic"]
    assert block["method"] == "periodic" and block["floquet_max_modulus"] < 1.0, block
    stepped = scene.with_values({"time.method": "transient", "time.dt": block["dt"],
                                 "time.T": 1.2})
    _, transient = solve(stepped, estimate=False)
    assert transient["window_drift"] < 1e-9
    assert answer["F_dv"] == pytest.approx(transient["F_dv"], rel=1e-9)
    # a whole number of cycles averaged: the same steps out of contact, the same N's extremes
    assert answer["contact_loss_fraction"] == pytest.approx(transient["contact_loss_fraction"],
                                                            abs=1e-12)
    assert (answer["contact_loss_fraction"] > 0.0) == (amplitude > 1.68e-7)
    for key in ("normal_force_mean", "normal_force_min", "normal_force_max"):
        assert answer[key] == pytest.approx(transient[key], rel=1e-9, abs=1e-9 * scene.contact.F_N)


def test_a_bouncing_orbit_judged_by_its_perturbations_alone_is_not_the_answer():
    """At 1.75e-7 m the shooting finds an orbit out of contact 23% of its cycle whose
    Jacobian claims a multiplier 4.2 (the cycle map is not smooth where the body lands)
    and whose perturbations decay; the stepped run bounces off 96% of the time instead
    (periodic.NormalCycleMap.bounce). The scene is stepped, saying why."""
    scene = load_scene("longitudinal", vibration__normal_amplitude=1.75e-7, time__T=0.3)
    _, summary = solve(scene, estimate=False)
    block = summary["periodic"]
    assert block["method"] == "transient" and block["converged"] and not block["stable"]
    assert block["reason"].startswith("the orbit loses contact over ")
    assert summary["contact_loss_fraction"] > 0.5


def test_a_neighbours_state_of_another_layout_is_not_a_start():
    """A sweep's continuation across normal_amplitude = 0 hands on a state without z,
    dz/dt, N: the shooting starts from steady sliding instead."""
    scene = load_scene("longitudinal", vibration__normal_amplitude=1e-7, time__T=0.3)
    _, summary = solve(scene, start=np.zeros(3), estimate=False)
    assert summary["periodic"]["method"] == "periodic"
    assert summary["periodic"]["start"] == "steady sliding"


@pytest.mark.parametrize("args", [
    ["analytic", "longitudinal", "--set", "vibration.normal_phase_deg=90"],
    ["run", "longitudinal", "--set", "vibration.normal_amplitude=1e-5"],
    ["sweep", "longitudinal", "--fe", "--grid", "vibration.normal_amplitude=0,1e-5"],
])
def test_the_command_line_refuses_in_one_line_naming_the_key_and_writes_nothing(
        tmp_path, monkeypatch, capsys, args):
    from vibrofric.cli import EXIT_BAD_INPUT, main

    monkeypatch.chdir(tmp_path)
    assert main(args) == EXIT_BAD_INPUT
    err = capsys.readouterr().err.strip().splitlines()
    key = "vibration.normal_phase_deg" if "analytic" in args else "vibration.normal_amplitude"
    assert len(err) == 1 and err[0].startswith(f"vibrofric: invalid scene: {key}: "), err
    assert list(tmp_path.iterdir()) == []


def test_a_neighbours_orbit_starts_the_in_plane_state_not_the_normal_one():
    """A sweep's continuation over the phase of the normal motion: the neighbour's orbit
    at phase 0 hands on its in-plane state, the body's normal motion starting on this
    scene's forced response (periodic.NormalCycleMap.from_neighbour); from the whole of
    it the shooting found a bouncing orbit (86% out of contact) at phase 45. The same
    orbit as from steady sliding, to Newton's tolerance (1e-9 on the ratio: the residual
    1e-10 of F_c amplified by 1 / (1 - 0.98), the slowest multiplier)."""
    A_n = 0.5 * 6.62e-8         # half the amplitude of contact loss on the coupled scene
    neighbour = load_scene("coupled", vibration__normal_amplitude=A_n, vibration__theta_deg=0.0)
    _, _, start = solve_with_orbit(neighbour, estimate=False)
    scene = neighbour.with_values({"vibration.normal_phase_deg": 45.0})
    _, continued, _ = solve_with_orbit(scene, start=start, estimate=False)
    _, fresh, _ = solve_with_orbit(scene, estimate=False)
    assert continued["periodic"]["start"] == "neighbour"
    assert continued["contact_loss_fraction"] == fresh["contact_loss_fraction"] == 0.0
    assert continued["F_dv_over_F_d0"] == pytest.approx(fresh["F_dv_over_F_d0"], rel=1e-9)


def test_a_normal_scene_shorter_than_the_averaging_window_is_answered_by_its_orbit():
    """Under auto the steady cycle needs no averaging window, with normal motion as
    without; stepped (transient) the window is still asked for, naming time.T."""
    scene = load_scene("longitudinal", vibration__normal_amplitude=1e-7, time__T=0.141)
    _, summary = solve(scene, estimate=False)
    assert summary["periodic"]["method"] == "periodic"
    with pytest.raises(SceneError, match="^time.T: 0.141 s is too short"):
        load_scene("longitudinal", vibration__normal_amplitude=1e-7, time__T=0.141,
                   time__method="transient")


def test_a_negative_contact_damping_ratio_is_refused_naming_its_key():
    with pytest.raises(SceneError, match="^contact.zeta_n: must be >= 0, got -0.01"):
        load_scene("longitudinal", contact__zeta_n=-0.01)


@pytest.mark.parametrize("zeta_n, near_forced", [(0.02, True), (0.005, False)])
def test_the_contact_damping_decides_the_orbit_just_above_the_threshold(zeta_n, near_forced):
    """1.2% above A_th on the low stiff block (r = 0.08) each landing sets off a free
    bounce that must die out within the ~12 bounce periods of a cycle (normal.py): at
    zeta_n = 0.02 the body stays near its forced orbit, out of contact for a few % of
    the cycle (measured 6%), at 0.005 it bounces (measured 99%). The bounds sit far
    from both measured values and from each other's orbit."""
    scene = low_block_scene(1.012, 6.0, zeta_n, **{"time.method": "transient"})
    _, summary = solve(scene, estimate=False)
    loss = summary["contact_loss_fraction"]
    if near_forced:
        assert 0.01 < loss < 0.3
    else:
        assert loss > 0.8
