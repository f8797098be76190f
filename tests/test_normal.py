"""The lumped body's normal degree of freedom (vibrofric/analytic/normal.py)."""

import math

import numpy as np
import pytest

from vibrofric.analytic import normal
from vibrofric.analytic.coupled import run_coupled
from vibrofric.analytic.longitudinal import run_longitudinal
from vibrofric.analytic.solve import solve
from vibrofric.api import load_scene
from vibrofric.core.bounce import bar_on_spring_root, bounce_stiffness, default_penalty
from vibrofric.core.series import COLUMNS, RecordPlan, full_resolution_steps
from vibrofric.scene import SceneError, check_fe_scene
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
    # (ZETA_N) moves the amplitude by < 1e-4 (normal.py); the rest is the tolerance's margin
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
    assert np.array_equal(out[:, :len(COLUMNS)], existing)
    assert np.all(out[:, -1] == scene.contact.F_N) and np.all(out[:, 8:10] == 0.0)
    assert "N" not in run(scene).extra      # and their series keep their columns


def _popov_scene(F_N, k_t, f, mass, v_tilde, alpha, r):
    """A scene of Popov et al.'s regime (Friction 5 (2017) 45-55): a stiff system, the
    body driven at exactly v_d; the normal-force oscillation imposed on the contact,
    N = F_N + k_n z_b, the body too heavy to follow the base in Z (r = w / w_n >> 1;
    held fixed, with the contact's damping ratio). Set by their dimensionless sliding
    velocity v~ = v_d / (w u_c), u_c = mu F_N / k_t the sliding length, and amplitude
    alpha = k_n A / F_N; time in cycles: 500 steps a cycle, t_on 20 cycles, T 60 (t_on
    and T whole numbers of steps, so that both runs start the base on the same step)."""
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
    from vibrofric.fem.model.contact import default_penalty as fe_penalty

    scene = load_scene("longitudinal")
    body = scene.body
    assert default_penalty(body.E, body.size) == fe_penalty(body.E, body.size)
    x = bar_on_spring_root(10.0)
    assert x * math.tan(x) == pytest.approx(10.0, rel=1e-12)
    # a far stiffer block bounces as a rigid one on the penalty spring: k_n -> k_p
    # (x tan x = x^2 (1 + x^2 / 3 + ...): at k_p L / (E A) = 1e-5, 3e-6 of k_p is left)
    stiff = bounce_stiffness(body.mass, 1e6 * body.E, 7850.0 * 1e6, body.size,
                             default_penalty(body.E, body.size))
    rigid = default_penalty(body.E, body.size) * body.mass / (7850.0 * 1e6 * 0.03 * 0.04 * 0.053)
    assert stiff == pytest.approx(rigid, rel=1e-5)
    assert scene.normal_stiffness == pytest.approx(0.204 * fe_penalty(body.E, body.size), rel=0.01)


@pytest.mark.parametrize("phase", [0.0, 90.0])
def test_a_normal_run_carries_its_step_error_and_is_judged_settled(phase):
    """The stepped answer's error from the runs at dt/2 and dt/4 (analytic/accuracy.py),
    whatever step the base's start falls on; the summary's settled judgement."""
    scene = load_scene("longitudinal", vibration__normal_amplitude=1e-7, time__T=0.3,
                       vibration__normal_phase_deg=phase)
    series, summary = solve(scene)
    assert summary["periodic"]["method"] == "transient"          # stepped, saying why
    assert "normal motion" in summary["periodic"]["reason"]
    assert summary["error_estimate"] is not None and summary["dt_used"] == scene.time.dt
    assert summary["settled"] is True
    # started on its forced response, the body keeps its contact at 0.6 of the threshold
    assert summary["contact_loss_fraction"] == 0.0
    assert summary["normal_force_max"] - scene.contact.F_N == pytest.approx(
        _forced_amplitude(scene), rel=1e-2)   # 1e-2: 250 steps a cycle here, 1000 above
    assert series.names[-3:] == normal.NORMAL_COLUMNS


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
