"""A base motion given per step (vibrofric/core/base_table.py): a measured motion file or
harmonics, sampled into the table the lumped stepper reads (analytic/normal.py)."""

import math

import numpy as np
import pytest

from vibrofric import scene as scene_module
from vibrofric.analytic.solve import solve
from vibrofric.cli import EXIT_BAD_INPUT, main
from vibrofric.core.base_table import (NO_TABLE, MeasuredMotion, sample_measured, table_row)
from vibrofric.scene import SceneError, check_fe_scene

# A short stepped run of the longitudinal scene: breakaway near 0.12 s, the base on from
# 0.14 s, F_dv averaged over the last drive period's cycles (0.29-0.3 s)
SHORT = {"time__method": "transient", "time__T": 0.3}


def _sine_csv(path, scene, periodic=True, steps_per_row=1, z_amplitude=0.0):
    """One cycle of ``scene``'s base motion u0 sin(w s) along X (and z_amplitude sin(w s)
    along Z), sampled every ``steps_per_row`` steps of time.dt, written as a motion file."""
    dt, w = scene.time.dt, scene.omega
    rows = round(1.0 / (scene.vibration.f * dt * steps_per_row))
    t = np.arange(rows + 1) * dt * steps_per_row
    x, z = scene.u0 * np.sin(w * t), z_amplitude * np.sin(w * t)
    if periodic:
        x[-1], z[-1] = x[0], z[0]
    lines = ["# a sampled sine", "t,x_b,y_b,z_b"]
    # (as Python floats: numpy 2's repr of a float64 is "np.float64(...)")
    lines += [f"{float(a)!r},{float(b)!r},0.0,{float(c)!r}" for a, b, c in zip(t, x, z)]
    path.write_text("\n".join(lines) + "\n")
    return path


def _measured(load_scene, csv, periodic=True, **keys):
    """The longitudinal scene with ``csv`` as its measured motion instead of the sine."""
    values = {"vibration__k_v": 0.0, "vibration__motion": str(csv),
              "vibration__motion_periodic": periodic, **keys}
    return load_scene("longitudinal", **values)


def _answer(scene, stepper="coupled"):
    return solve(scene, stepper, estimate=False)[1]["F_dv_over_F_d0"]


def test_a_csv_sampling_the_papers_sine_gives_the_papers_answer(load_scene, tmp_path):
    paper = load_scene("longitudinal", **SHORT)
    measured = _measured(load_scene, _sine_csv(tmp_path / "sine.csv", paper), **SHORT)
    assert measured.vibration.f == paper.vibration.f   # the file's period sets f
    # The file holds the sine at every step to its last bit (repr), linear interpolation
    # at the file's own times returns it; the loop's sine is a rotated phase re-anchored
    # every 1024 steps (core/base_motion.py, drift < 1e-13): 2e-14 measured, 1e-12 bound
    assert _answer(measured) == pytest.approx(_answer(paper), rel=1e-12, abs=0)


def test_the_periodic_solver_takes_a_periodic_measured_motion(load_scene, tmp_path):
    paper = load_scene("longitudinal")
    measured = _measured(load_scene, _sine_csv(tmp_path / "sine.csv", paper))
    series, summary = solve(measured, "coupled", estimate=False)
    assert summary["periodic"]["method"] == "periodic"
    # both orbits meet the shooting's tolerance (periodic.TOLERANCE 1e-10 of the scaled
    # state, amplified by 1 / (1 - 0.986), the largest Floquet multiplier): 5e-12 measured
    assert summary["F_dv_over_F_d0"] == pytest.approx(_answer(paper), rel=1e-8, abs=0)


def test_a_coarser_csv_is_its_linear_interpolant(load_scene, tmp_path):
    """A file sampled every 5 steps: the base between its samples is the chord, off the
    sine by up to u0 (w h)^2 / 8 = 2e-3 u0 at h = 5 us; the answer moves by that order
    (5e-3 measured) and less than ten times it."""
    paper = load_scene("longitudinal", **SHORT)
    coarse = _measured(load_scene, _sine_csv(tmp_path / "coarse.csv", paper, steps_per_row=5),
                       **SHORT)
    chord_error = (paper.omega * 5 * paper.time.dt) ** 2 / 8
    difference = abs(_answer(coarse) / _answer(paper) - 1.0)
    assert 0.0 < difference < 10 * chord_error


@pytest.mark.parametrize("stepper", ["coupled", "longitudinal"])
def test_a_harmonic_of_amplitude_zero_changes_no_bit(load_scene, stepper):
    paper = load_scene("longitudinal", **SHORT)
    zero = paper.with_values({"vibration.harmonics": [{"order": 3}]})
    assert _answer(zero, stepper) == _answer(paper, stepper)


def test_a_first_harmonic_adds_to_the_sine(load_scene):
    """k_v = 3 plus a first harmonic of the sine's own amplitude along X is the scene at
    k_v = 6; a first harmonic along Z is the normal_amplitude of the same size (its
    velocity, which the contact's dashpot sees, sampled exactly)."""
    paper = load_scene("longitudinal", **SHORT)
    half = paper.with_values({"vibration.k_v": 3.0})
    added = half.with_values({"vibration.harmonics": [{"order": 1, "x": half.u0}]})
    # the harmonic is sampled by numpy's sine, the loop's by its rotated phase: 1e-12 as above
    assert _answer(added) == pytest.approx(_answer(paper), rel=1e-12, abs=0)
    normal = paper.with_values({"vibration.normal_amplitude": 5e-8})
    as_harmonic = paper.with_values({"vibration.harmonics": [{"order": 1, "z": 5e-8}]})
    assert _answer(as_harmonic) == pytest.approx(_answer(normal), rel=1e-12, abs=0)


def test_a_measured_normal_motion_with_its_splines_velocity(load_scene, tmp_path):
    """z_b from the file at every step; its velocity from the cubic spline, off the sine's
    by at most about (w h)^3 / 24 = 7e-7 relative at h = 1 us, in the dashpot's force
    alone (c_n v, 2% damping, a few 1e-3 of N's swing): the answer within 1e-8 of the
    normal_amplitude scene's (9e-12 measured)."""
    paper = load_scene("longitudinal", **SHORT)
    normal = paper.with_values({"vibration.normal_amplitude": 5e-8})
    measured = _measured(load_scene, _sine_csv(tmp_path / "z.csv", paper, z_amplitude=5e-8),
                         **SHORT)
    plane = _measured(load_scene, _sine_csv(tmp_path / "x.csv", paper), **SHORT)
    assert _answer(measured) == pytest.approx(_answer(normal), rel=1e-8, abs=0)
    assert abs(_answer(measured) - _answer(plane)) > 1e-6     # the Z motion does act


def test_a_motion_that_ends_holds_its_last_position_and_is_stepped(load_scene, tmp_path):
    motion = MeasuredMotion(np.array([0.0, 1e-5, 2e-5]), np.array([0.0, 1e-9, 3e-9]),
                            np.zeros(3), np.zeros(3))
    table = sample_measured(motion, False, 1e-6, 0.0, 0, 100)
    rows = table.rows
    assert table.period == 0 and rows.shape[0] == 22      # 21 steps over 20 us, then at rest
    assert rows[5, 0] == pytest.approx(0.5e-9, rel=1e-12)   # linear between the samples
    assert rows[table_row(rows, 0, 0, 10_000)].tolist() == [3e-9, 0.0, 0.0, 0.0, 0.0, 0.0]
    assert table_row(NO_TABLE.rows, 0, 0, 5) == -1
    assert table_row(rows, 10, 0, 9) == -1                # before t_on: the base at rest
    paper = load_scene("longitudinal", **SHORT)
    ends = _measured(load_scene, _sine_csv(tmp_path / "once.csv", paper, periodic=False),
                     periodic=False, time__method="auto", time__T=0.3)
    series, summary = solve(ends, "coupled", estimate=False)
    assert summary["periodic"]["method"] == "transient"
    assert "ends" in summary["periodic"]["reason"]
    x_b = series.x_b[series.t > 0.141]
    assert np.all(x_b == x_b[-1])                         # held after the file's 250 us


def _scene_file(tmp_path, vibration: str, time: str = "") -> str:
    path = tmp_path / "scene.toml"
    path.write_text(f"[vibration]\n{vibration}\n[time]\nT = 0.3\n{time}\n")
    return str(path)


GOOD = "t,x_b,y_b,z_b\n0,0,0,0\n1e-4,1e-8,0,0\n2e-4,0,0,0\n"


@pytest.mark.parametrize("text, keys, key, words", [
    (None, "", "vibration.motion", "no such file"),
    ("t,x,y_b\n0,0,0\n1e-4,0,0\n", "", "vibration.motion", "lacks the column(s) x_b"),
    ("t,x_b,y_b\n0,0,0\n1e-4,nan,0\n2e-4,0,0\n", "", "vibration.motion", "line 3: x_b = nan"),
    ("t,x_b,y_b\n0,0,0\n2e-4,1e-9,0\n1e-4,0,0\n", "", "vibration.motion", "does not increase"),
    ("t,x_b,y_b\n0,0,0\n", "", "vibration.motion", "at least 2"),
    ("t,x_b,y_b\n0,0,0\n1e-4,1e-9,0\n", "", "vibration.motion", "differs from the first"),
    ("t,x_b,y_b\n0,0,0\n1e-4,1,0\n2e-4,0,0\n", "", "vibration.motion", "1e+04 m/s"),
    (GOOD, "k_v = 2.0", "vibration.k_v", "moves the base alone"),
    (GOOD, "normal_amplitude = 1e-9", "vibration.normal_amplitude", "moves the base alone"),
    (GOOD, "harmonics = [{order = 2, x = 1e-9}]", "vibration.harmonics", "moves the base alone"),
    (GOOD, "f = 1000.0", "vibration.f", "makes it 5000"),
    ("t,x_b,y_b\n0,0,0\n1.00005e-4,1e-9,0\n2.0001e-4,0,0\n", "", "time.dt",
     "does not divide"),
])
def test_a_bad_measured_motion_is_refused_naming_the_key(tmp_path, text, keys, key, words):
    csv = tmp_path / "base.csv"
    if text is not None:
        csv.write_text(text)
    path = _scene_file(tmp_path, f'motion = "base.csv"\nmotion_periodic = true\n{keys}',
                       'method = "periodic"\ndt = 1e-6')
    with pytest.raises(SceneError) as err:
        scene_module.load(path)
    assert err.value.key == key and words in str(err.value)


def test_a_motion_that_ends_is_refused_the_periodic_method(tmp_path):
    (tmp_path / "base.csv").write_text(GOOD)
    with pytest.raises(SceneError) as err:
        scene_module.load(_scene_file(tmp_path, 'motion = "base.csv"', 'method = "periodic"'))
    assert err.value.key == "time.method"


@pytest.mark.parametrize("harmonics, key", [
    ("[{order = 0, x = 1e-9}]", "vibration.harmonics"),
    ("[{order = 1.5, x = 1e-9}]", "vibration.harmonics[1].order"),
    ("[{x = 1e-9}]", "vibration.harmonics"),
    ("[{order = 2, w = 1e-9}]", "vibration.harmonics"),
    ("[{order = 2, x = \"big\"}]", "vibration.harmonics[1].x"),
    ("[{order = 30, x = 1e-9}]", "vibration.harmonics"),     # 8.3 steps a cycle at 120 kHz
    ("[{order = 2, y = 2e-2}]", "vibration.harmonics"),      # 1e3 m/s, past 0.1 c in steel
])
def test_bad_harmonics_are_refused_naming_the_key(tmp_path, harmonics, key):
    with pytest.raises(SceneError) as err:
        scene_module.load(_scene_file(tmp_path, f"harmonics = {harmonics}"))
    assert err.value.key == key


def test_the_fe_model_refuses_a_table_faster_along_z_than_a_step_takes(load_scene):
    """1 um at 4 kHz: 2.5e-8 m a step at 1 us, past what the penalty takes in one
    (10 F_N / k_pen = 1.15e-8 m on the block): refused before any work, naming the key."""
    values = {"time__method": "transient", "vibration__harmonics": [{"order": 1, "z": 1e-6}]}
    with pytest.raises(SceneError) as err:
        check_fe_scene(load_scene("longitudinal", **values))
    assert err.value.key == "vibration.harmonics"


@pytest.mark.parametrize("integrator", ["explicit", "implicit", "reduced", "auto"])
@pytest.mark.parametrize("method", ["transient", "periodic", "auto"])
def test_every_fe_integrator_and_method_takes_a_table(load_scene, integrator, method):
    """Every FE integrator reads a table, and the FE periodic solver a periodic one
    (test_fe_base_table.py runs them)."""
    check_fe_scene(load_scene("longitudinal", time__method=method, fem__integrator=integrator,
                              vibration__harmonics=[{"order": 2, "x": 1e-9}]))


@pytest.mark.slow   # four FE runs of 160 000 steps: 14 s measured
def test_the_fe_explicit_integrator_steps_a_table(load_scene, tmp_path):
    """On the coarse block, stepped 20 ms past t_on: a harmonic of amplitude 0, the
    paper's sine as a measured motion, and k_v = 3 plus a first harmonic of its
    amplitude each give the sine's drive force to 1e-11 of its largest value (the
    table's sine against the loop's rotated phase, ~1e-16 of u0 a step, as in the
    lumped model: 4e-13 measured). The zero harmonic adds exact zeros, but it runs the
    loop compiled with a table, whose rounding numba's compile variants may set apart
    from the plain loop's (2.6e-13 measured in one fresh clone, 0 in another;
    benchmarks/same_results.py): that the shipped scenes keep their bits is
    same_results' check, not this one's."""
    from vibrofric.fem import run_fe

    settings = {"time__method": "transient", "time__T": 0.16, "time__average_cycles": 10,
                "fem__output_every": 0}
    paper = load_scene("longitudinal", **settings)
    csv = _sine_csv(tmp_path / "sine.csv", paper)
    half = paper.with_values({"vibration.k_v": 3.0})
    scenes = [paper.with_values({"vibration.harmonics": [{"order": 2}]}),
              _measured(load_scene, csv, **settings),
              half.with_values({"vibration.harmonics": [{"order": 1, "x": half.u0}]})]
    for s in scenes:
        check_fe_scene(s)
    reference = run_fe(paper).series.F_d
    zero, measured, added = (run_fe(s).series.F_d for s in scenes)
    scale = np.max(np.abs(reference))
    for F_d in (zero, measured, added):
        assert np.max(np.abs(F_d - reference)) <= 1e-11 * scale


@pytest.mark.slow   # two FE runs of 160 000 steps
def test_the_fe_explicit_integrator_moves_the_base_along_z_by_a_table(load_scene):
    """A first harmonic along Z is the normal_amplitude of its size on the coarse block
    too: the same start (the table's z_b and its exact velocity half a step before), the
    same gaps; the drive force, the face's height, the base's and the summed normal
    force to 1e-10 of their largest values (the table's sine against the loop's rotated
    phase, ~1e-16 of A_n a step, through the penalty's stiff contact: F_d 5e-13, z_b
    7e-13, N 2.4e-11 measured)."""
    from vibrofric.fem import run_fe

    settings = {"time__method": "transient", "time__T": 0.16, "time__average_cycles": 10,
                "fem__output_every": 0}
    normal = load_scene("longitudinal", vibration__normal_amplitude=5e-8, **settings)
    harmonic = load_scene("longitudinal", vibration__harmonics=[{"order": 1, "z": 5e-8}],
                          **settings)
    check_fe_scene(harmonic)
    a, b = run_fe(normal).series, run_fe(harmonic).series
    assert set(b.extra) == set(a.extra) and "z_b" in b.extra
    for name in ("F_d", "z", "z_b", "N"):
        x, y = (s.F_d if name == "F_d" else s.extra[name] for s in (a, b))
        assert np.max(np.abs(y - x)) <= 1e-10 * np.max(np.abs(x)), name


def test_the_command_refuses_a_bad_motion_and_writes_nothing(tmp_path, capsys):
    (tmp_path / "base.csv").write_text("t,x_b,y_b\n0,0,0\n1e-4,inf,0\n")
    out = tmp_path / "never"
    code = main(["analytic", _scene_file(tmp_path, 'motion = "base.csv"'), "--out", str(out)])
    assert code == EXIT_BAD_INPUT
    err = capsys.readouterr().err
    assert "vibration.motion" in err and "inf" in err and len(err.strip().splitlines()) == 1
    assert not out.exists()


def test_a_motion_file_named_in_the_api_is_relative_to_the_current_directory(
        tmp_path, monkeypatch):
    from vibrofric.api import load_scene as api_load

    (tmp_path / "base.csv").write_text(GOOD)
    monkeypatch.chdir(tmp_path)
    scene = api_load("longitudinal", vibration__motion="base.csv", vibration__k_v=0.0)
    assert scene.vibration.motion == str(tmp_path / "base.csv")


def test_the_example_scenes_load(load_scene):
    harmonics = scene_module.load("examples/base_motion/harmonics.toml")
    assert [h.order for h in harmonics.vibration.harmonics] == [2, 1]
    assert harmonics.vibration.k_v == load_scene("longitudinal").vibration.k_v


def test_the_examples_motion_file_is_the_papers_sine(load_scene):
    example = scene_module.load("examples/base_motion/measured.toml")
    paper = load_scene("longitudinal")
    assert example.vibration.f == paper.vibration.f
    t = np.loadtxt(example.vibration.motion, delimiter=",", skiprows=3)
    assert np.allclose(t[:-1, 1], paper.u0 * np.sin(paper.omega * t[:-1, 0]), rtol=0,
                       atol=1e-15 * paper.u0)
    assert math.isclose(t[-1, 0] * paper.vibration.f, 1.0, rel_tol=1e-12)


def test_a_results_directory_reruns_moved_elsewhere_with_its_motion_and_law_files(load_scene,
                                                                                  tmp_path):
    """scene.toml in a results directory names its measured motion and its user's law
    file beside it (output.write_scene_and_inputs), not where they were: the directory,
    moved and the original files gone, reruns to the same answer, bit for bit, on the
    same compiled law (the copy's fingerprint is the original's)."""
    import pathlib
    import shutil

    from vibrofric.api import run_analytic
    from vibrofric.friction_law import load_law

    inputs = tmp_path / "inputs"
    inputs.mkdir()
    original = _sine_csv(inputs / "sine.csv", load_scene("longitudinal"))
    law = inputs / "maxwell_slip.py"
    shutil.copyfile(pathlib.Path(__file__).parent.parent / "examples" / "laws" / "maxwell_slip.py",
                    law)
    first = run_analytic(_measured(load_scene, original, contact__law=str(law)),
                         out=tmp_path / "results")
    written = scene_module.load(tmp_path / "results" / "scene.toml")
    assert written.vibration.motion == str(tmp_path / "results" / "base_motion.csv")
    assert written.contact.law == str(tmp_path / "results" / "maxwell_slip.py")
    text = (tmp_path / "results" / "scene.toml").read_text()
    assert 'motion = "base_motion.csv"' in text and 'law = "maxwell_slip.py"' in text
    fingerprint = load_law(str(law)).fingerprint

    moved = tmp_path / "elsewhere" / "results"
    shutil.move(tmp_path / "results", moved)
    shutil.rmtree(inputs)
    rerun = scene_module.load(moved / "scene.toml")
    assert load_law(rerun.contact.law).fingerprint == fingerprint
    again = run_analytic(rerun)
    assert again.F_dv_over_F_d0 == first.F_dv_over_F_d0
