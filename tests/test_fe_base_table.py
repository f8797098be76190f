"""The FE integrators on a base motion given per step (core/base_table.py): the implicit
and reduced integrators read it at their friction sub-steps, and the FE periodic solver
shoots over one period of a periodic one (docs/fe-model.md, "A base motion of your
own"). The explicit integrator's own checks are in test_base_table.py."""

import numpy as np
import pytest

from vibrofric.analytic.summary import summarize
from vibrofric.core.base_table import SubstepTable, substep_table, table_row
from vibrofric.fem import run_fe
from vibrofric.fem.integrators.contact_solve import implicit_substeps
from vibrofric.scene import check_fe_scene

# Stepped as the explicit integrator's table tests: the coarse block, the base on from
# 0.14 s, 20 ms of it, at the implicit integrators' step 1e-5 s (25 steps a cycle)
STEPPED = {"time__method": "transient", "time__T": 0.16, "time__average_cycles": 10,
           "fem__output_every": 0, "time__dt": 1e-5}


def _sine_csv(path, scene, interval):
    """One cycle of ``scene``'s base motion u0 sin(w t) along X, sampled every ``interval``
    (a whole number of them in the cycle), as a periodic motion file."""
    rows = round(1.0 / (scene.vibration.f * interval))
    t = np.arange(rows + 1) * interval
    x = scene.u0 * np.sin(scene.omega * t)
    x[-1] = x[0]
    lines = ["t,x_b,y_b,z_b"] + [f"{float(a)!r},{float(b)!r},0.0,0.0" for a, b in zip(t, x)]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_the_substep_table_samples_each_substeps_end(load_scene):
    """Sub-step j of step i ends at (i - 1) dt + j dt / m, the sine's own instants
    (contact_solve.base_over_substeps): a harmonic read there is the harmonic at that
    time (to the rounding of the times, 1e-12 of its amplitude), its period m times a
    cycle's steps; before t_on the lead holds z_b along the first step on."""
    scene = load_scene("longitudinal", **STEPPED,
                       vibration__harmonics=[{"order": 2, "x": 1e-8, "z": 2e-8,
                                              "phase_z_deg": 30.0}])
    dt, t_on, w = scene.time.dt, scene.vibration.t_on, scene.omega
    m = implicit_substeps(scene)
    on_step = round(t_on / dt)
    motion = substep_table(scene.vibration, w, dt, m, m, t_on, on_step, scene.steps)
    assert isinstance(motion, SubstepTable) and motion.per_step == m
    assert motion.table.period == m * round(1.0 / (scene.vibration.f * dt))
    table = motion.table
    for i, j in ((on_step + 1, 1), (on_step + 37, m), (on_step + 1000, 2)):
        s = (i - 1) * dt + j * dt / m - t_on
        row = table.rows[table_row(table.rows, table.first_step, table.period,
                                   (i - 1) * m + j)]
        assert row[0] == pytest.approx(1e-8 * np.sin(2 * w * s), abs=1e-12 * 1e-8)
        assert row[2] == pytest.approx(2e-8 * np.sin(2 * w * s + np.radians(30.0)),
                                       abs=1e-12 * 2e-8)
    s = (on_step - 1) * dt + np.arange(m + 1) * dt / m - t_on      # from a step before t_on
    assert motion.lead[:, 0] == pytest.approx(2e-8 * np.sin(2 * w * s + np.radians(30.0)),
                                              abs=1e-12 * 2e-8)


@pytest.mark.parametrize("integrator", [
    pytest.param("implicit", marks=pytest.mark.slow),   # three runs of 16 000 steps: 16 s
    "reduced"])                                         # 3 s measured
def test_the_implicit_integrators_step_a_table(load_scene, tmp_path, integrator):
    """The paper's sine as a measured motion sampled at the friction sub-steps (the file's
    own samples: the linear interpolation returns them), and k_v = 3 plus a first
    harmonic of its amplitude (as many sub-steps as k_v = 6: its speed counts,
    law_limits.slip_resolving_step), each give the sine's drive force to 1e-9 of its
    largest value. The table's sine against the loop's (its step ends by a rotated
    phase, core/base_motion.py) differs by rounding: 3e-13 to 2.5e-12 measured. The
    bound is ten times the spread numba's compile variants give an FE series
    (~1e-10, benchmarks/same_results.py): the contact iteration, stopping at its
    tolerance, may carry a rounding difference further than the explicit step does."""
    paper = load_scene("longitudinal", **STEPPED, fem__integrator=integrator)
    interval = paper.time.dt / implicit_substeps(paper)
    csv = _sine_csv(tmp_path / "sine.csv", paper, interval)
    measured = load_scene("longitudinal", **STEPPED, fem__integrator=integrator,
                          vibration__k_v=0.0, vibration__motion=str(csv),
                          vibration__motion_periodic=True)
    half = paper.with_values({"vibration.k_v": 3.0})
    added = half.with_values({"vibration.harmonics": [{"order": 1, "x": half.u0}]})
    for s in (measured, added):
        check_fe_scene(s)
    reference = run_fe(paper).series.F_d
    scale = np.max(np.abs(reference))
    for s in (measured, added):
        assert np.max(np.abs(run_fe(s).series.F_d - reference)) <= 1e-9 * scale


@pytest.mark.parametrize("integrator", ["implicit", "reduced"])   # 10 s, 2 s measured
def test_the_implicit_integrators_move_the_base_along_z_by_a_table(load_scene, integrator):
    """A first harmonic along Z is the normal_amplitude of its size: the same start (the
    table's lead a step before t_on), the same gaps at every sub-step; the drive force,
    the face's height, the base's and the summed normal force to 1e-9 of their largest
    values (rounding, as above: F_d 1e-12, N 3e-11 measured; 2e-8 m at 1e-5 s is
    within what a step's penalty takes, scene/validation.py check_fe_scene)."""
    normal = load_scene("longitudinal", **STEPPED, fem__integrator=integrator,
                        vibration__normal_amplitude=2e-8)
    harmonic = load_scene("longitudinal", **STEPPED, fem__integrator=integrator,
                          vibration__harmonics=[{"order": 1, "z": 2e-8}])
    check_fe_scene(harmonic)
    a, b = run_fe(normal).series, run_fe(harmonic).series
    for name in ("F_d", "z", "z_b", "N"):
        x, y = (s.F_d if name == "F_d" else s.extra[name] for s in (a, b))
        assert np.max(np.abs(y - x)) <= 1e-9 * np.max(np.abs(x)), name


@pytest.mark.parametrize("integrator, dt", [("explicit", 1e-6), ("implicit", 5e-6),
                                            ("reduced", 5e-6)])   # under 3 s each measured
def test_the_energy_balance_closes_within_one_percent_of_the_base_work_on_a_table(
        load_scene, integrator, dt):
    """The energy balance with a base motion given per step: harmonics along X and Z (in
    contact) on the coarse block, its balance over the averaged cycles within 1% of the
    base's work (the bound test_fe_normal.py sets the sine along Z; explicit 2e-13, implicit
    and reduced 0.18% measured), and the base's work through the table is there (positive)."""
    scene = load_scene("longitudinal", vibration__t_on=0.002, time__T=0.012,
                       time__average_cycles=8, time__method="transient",
                       time__error_estimate=False, fem__integrator=integrator,
                       fem__mesh="coarse", fem__energy=True, fem__output_every=0,
                       time__dt=dt, vibration__harmonics=[
                           {"order": 2, "x": 3e-9, "z": 5e-9, "phase_z_deg": 45.0}])
    info = run_fe(scene).info
    assert info["contact_loss_fraction"] == 0.0
    assert info["energy_base_work"] > 0.0
    assert info["energy_closure"] < 0.01


# The Fig 7 scene with the vibration on at 10 ms stepped to T = 0.4 s: 1560 cycles to
# settle, the drive mode (0.984 a cycle) decayed by 1e-11 (test_fe_periodic.py); each
# integrator at its own step there
SETTLED = {"vibration__t_on": 0.01, "time__T": 0.4, "fem__output_every": 0}
STEPS = {"reduced": 1e-5, "explicit": 1e-6}


@pytest.mark.slow   # a stepped run of 40 000 (reduced) or 400 000 (explicit) steps, a
                    # shooting: 15-22 s, 8-28 s measured
@pytest.mark.parametrize("integrator", ["reduced", "explicit"])
def test_the_fe_periodic_solver_shoots_a_harmonics_scene(load_scene, integrator):
    """Harmonics along X, Y and Z: the periodic solver's steady answer equals the settled
    stepped run's of the same integrator within 1e-5, its orbit stable. The orbit is
    converged to the shooting's TOLERANCE (1e-6 of the scaled state: F_dv within ~5e-7,
    fem/integrators/periodic.py), the stepped run's window has drifted by less than
    1e-6: 1e-5 holds both with a margin (7e-8 reduced, 6e-8 explicit measured)."""
    harmonics = [{"order": 2, "x": 5e-9, "y": 3e-9, "z": 5e-9, "phase_z_deg": 60.0},
                 {"order": 1, "y": 2e-9, "phase_y_deg": 30.0}]
    stepped_scene = load_scene("longitudinal", time__method="transient",
                               vibration__harmonics=harmonics, fem__integrator=integrator,
                               time__dt=STEPS[integrator], **SETTLED)
    stepped = run_fe(stepped_scene)
    expected = summarize(stepped.series, stepped_scene, 0.0)
    assert expected["window_drift"] < 1e-6          # settled
    scene = stepped_scene.with_values({"time.method": "periodic"})
    check_fe_scene(scene)
    shot = run_fe(scene)
    block = shot.info["periodic"]
    assert block["method"] == "periodic" and block["converged"] and block["stable"]
    answer = summarize(shot.series, scene, 0.0)["F_dv_over_F_d0"]
    assert answer == pytest.approx(expected["F_dv_over_F_d0"], rel=1e-5)
    # the harmonics act: the answer is not the sine's alone
    paper = summarize(run_fe(scene.with_values({"vibration.harmonics": []})).series,
                      scene, 0.0)["F_dv_over_F_d0"]
    assert abs(answer - paper) > 1e-3 * paper


def test_the_fe_periodic_solver_shoots_a_periodic_measured_motion(load_scene, tmp_path):
    """The paper's sine as a periodic measured motion, sampled at the reduced integrator's
    friction sub-steps: its orbit answers the sine's orbit within 1e-5 (both converged
    to the shooting's TOLERANCE, F_dv within ~5e-7 each; the inputs differ by rounding)."""
    settings = {"time__method": "periodic", "fem__integrator": "reduced", "time__dt": 1e-5,
                "vibration__t_on": 0.01, "fem__output_every": 0}
    paper = load_scene("longitudinal", **settings)
    csv = _sine_csv(tmp_path / "sine.csv", paper, paper.time.dt / implicit_substeps(paper))
    measured = load_scene("longitudinal", **settings, vibration__k_v=0.0,
                          vibration__motion=str(csv), vibration__motion_periodic=True)
    check_fe_scene(measured)
    answers = []
    for scene in (paper, measured):
        result = run_fe(scene)
        assert result.info["periodic"]["method"] == "periodic"
        answers.append(summarize(result.series, scene, 0.0)["F_dv_over_F_d0"])
    assert answers[1] == pytest.approx(answers[0], rel=1e-5)


def test_a_motion_that_ends_is_stepped_under_auto(load_scene, tmp_path):
    """The FE periodic solver needs a motion that repeats: under time.method "auto" a
    measured motion that ends is stepped (simulate.shoots), under "periodic" refused
    by the scene's checks (test_base_table.py)."""
    from vibrofric.fem.simulate import shoots

    csv = tmp_path / "ends.csv"
    csv.write_text("t,x_b,y_b\n0,0,0\n1e-3,1e-9,0\n")
    ends = load_scene("longitudinal", time__method="auto", vibration__k_v=0.0,
                      vibration__motion=str(csv))
    assert not shoots(ends)
    assert shoots(load_scene("longitudinal", time__method="auto",
                             vibration__harmonics=[{"order": 2, "x": 1e-9}]))
