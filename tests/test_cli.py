"""The vibrofric command: JSON, results directories, refusals."""

import csv
import json

import pytest

from vibrofric.cli import EXIT_BAD_INPUT, EXIT_POINTS_FAILED, main

SHORT = ["--set", "time.T=0.2"]
SUMMARY_KEYS = {"F_dv_over_F_d0", "F_dv", "F_d0", "breakaway_time_s", "steps", "wall_time_s"}


def test_analytic_json_and_results(tmp_path, capsys):
    out = tmp_path / "run"
    assert main(["analytic", "scenes/longitudinal.toml", *SHORT, "--out", str(out), "--json"]) == 0
    document = json.loads(capsys.readouterr().out)
    assert SUMMARY_KEYS <= set(document)
    # the default answers by the steady cycle: the cycles it integrated, far fewer steps
    # than stepping through T (200 000)
    assert document["periodic"]["method"] == "periodic" and document["settled"]
    assert 0 < document["steps"] < 200_000 and 0 < document["F_dv_over_F_d0"] < 1
    names = {p.name for p in out.iterdir()}
    assert {"scene.toml", "summary.json", "timeseries.csv", "drive_force.png",
            "friction_last_cycles.png"} <= names
    with open(out / "timeseries.csv") as f:
        header = next(csv.reader(f))
    assert header == ["t", "F_d", "F_x", "F_y", "x", "y", "x_b", "y_b"]
    written = json.loads((out / "summary.json").read_text())["analytic"]
    assert written["F_dv"] == document["F_dv"]


def test_a_shipped_scene_by_name_from_another_directory(tmp_path, capsys, monkeypatch):
    """``vibrofric analytic longitudinal`` reads the package's own scene file: the same
    answer as the repository's file; a bare name that is neither a file nor a shipped
    scene is refused, naming the shipped ones."""
    answers = []
    for scene in ("scenes/longitudinal.toml", "longitudinal"):
        assert main(["analytic", scene, *SHORT, "--json", "--out", str(tmp_path / scene.replace("/", "-"))]) == 0
        answers.append(json.loads(capsys.readouterr().out)["F_dv_over_F_d0"])
        monkeypatch.chdir(tmp_path)   # the name works from anywhere
    assert answers[0] == answers[1]
    assert main(["analytic", "longitudinl", *SHORT, "--out", str(tmp_path / "never")]) == EXIT_BAD_INPUT
    err = capsys.readouterr().err
    assert "longitudinl: no such scene file, nor a shipped scene (ball, coupled, longitudinal, pin, transverse)" in err
    assert not (tmp_path / "never").exists()


@pytest.mark.parametrize("override", ["body.mass=-1", "time.dt=0", "vibration.k_v=-1", "bogus.key=1"])
def test_refused_scene_writes_nothing(tmp_path, capsys, override):
    out = tmp_path / "never"
    code = main(["analytic", "scenes/longitudinal.toml", "--set", override, "--out", str(out)])
    assert code == EXIT_BAD_INPUT
    assert override.split("=")[0] in capsys.readouterr().err
    assert not out.exists() and list(tmp_path.iterdir()) == []


def test_numerical_trouble_writes_nothing(tmp_path, capsys):
    out = tmp_path / "never"
    code = main(["analytic", "scenes/longitudinal.toml", "--set", "contact.update=paper",
                 "--set", "contact.k_t=8e9", *SHORT, "--out", str(out)])
    assert code != 0 and "diverged" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


def test_sweep_over_k_v_and_angle(tmp_path, capsys):
    out = tmp_path / "sweep"
    code = main(["sweep", "scenes/coupled.toml", *SHORT, "--grid", "vibration.k_v=2,6",
                 "--grid", "vibration.theta_deg=0:90:3", "--out", str(out), "--json"])
    assert code == 0
    records = json.loads(capsys.readouterr().out)
    assert [(r["vibration.k_v"], r["vibration.theta_deg"]) for r in records] == [
        (2, 0.0), (2, 45.0), (2, 90.0), (6, 0.0), (6, 45.0), (6, 90.0)]
    assert all(SUMMARY_KEYS <= set(r) for r in records)
    with open(out / "results.csv") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 6 and float(rows[4]["F_dv_over_F_d0"]) == records[4]["F_dv_over_F_d0"]
    assert (out / "ratio_against_angle.png").exists()


def test_sweep_with_a_bad_point_runs_the_others_and_reports_it(tmp_path, capsys):
    out = tmp_path / "sweep"
    code = main(["sweep", "scenes/coupled.toml", *SHORT, "--grid", "vibration.k_v=2,-1", "--out", str(out),
                 "--json"])
    assert code == EXIT_POINTS_FAILED
    captured = capsys.readouterr()
    assert "failed vibration.k_v=-1.0: invalid scene: vibration.k_v" in captured.err
    good, bad = json.loads(captured.out)
    assert 0 < good["F_dv_over_F_d0"] < 1 and "error" not in good
    assert bad == {"vibration.k_v": -1, "error": bad["error"]} and "vibration.k_v" in bad["error"]
    with open(out / "results.csv") as f:
        rows = list(csv.DictReader(f))
    assert [(r["vibration.k_v"], r["error"] == "") for r in rows] == [("2.0", True), ("-1.0", False)]


def test_sweep_over_a_bad_base_scene_is_refused_before_any_work(tmp_path, capsys):
    out = tmp_path / "sweep"
    code = main(["sweep", "scenes/coupled.toml", "--set", "body.mass=-1", "--grid", "vibration.k_v=2,6",
                 "--out", str(out)])
    assert code == EXIT_BAD_INPUT and "body.mass" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


def test_run_fe_and_analytic_json_and_results(tmp_path, capsys, load_scene, written_by_rule):
    """Stepped through T (a run answered by its steady cycle: test_fe_periodic.py)."""
    out = tmp_path / "fe"
    code = main(["run", "scenes/longitudinal.toml", "--set", "time.T=0.16", "--set", "fem.mesh=tiny",
                 "--set", "fem.output_every=5000", "--set", "time.method=transient",
                 "--out", str(out), "--json"])
    assert code == 0
    document = json.loads(capsys.readouterr().out)
    assert SUMMARY_KEYS | {"dofs", "contact_nodes", "contact_area", "peak_pressure",
                           "nodes_in_contact"} <= set(document["fe"])
    assert SUMMARY_KEYS <= set(document["analytic"])
    assert document["fe"]["dofs"] == 24 and document["fe"]["contact_nodes"] == 4
    # the one-element block slides on its whole face (30 x 40 mm, to rounding), pressed
    # at least as hard as F_N spread over it at its most loaded corner
    assert document["fe"]["nodes_in_contact"] == 4
    assert document["fe"]["contact_area"] == pytest.approx(0.03 * 0.04, rel=1e-12)
    assert document["fe"]["peak_pressure"] >= 55.0 / (0.03 * 0.04)
    fe, analytic = document["fe"]["F_dv_over_F_d0"], document["analytic"]["F_dv_over_F_d0"]
    assert document["rel_error"] == pytest.approx(abs(fe - analytic) / analytic, rel=1e-12)
    names = {p.name for p in out.iterdir()}
    assert {"scene.toml", "summary.json", "timeseries.csv", "analytic_timeseries.csv",
            "drive_force.png", "friction_last_cycles.png", "normal_force.png", "block.png",
            "paraview"} <= names
    frames = sorted((out / "paraview").glob("*.vtu"))
    assert (out / "paraview" / "block.pvd").exists() and len(frames) == 33  # steps 0, 5000, ..., 160000
    scene = load_scene("longitudinal", time__T=0.16, fem__mesh="tiny", fem__output_every=5000,
                       time__method="transient")
    assert written_by_rule(out / "timeseries.csv", scene).shape[1] == 9  # and F_n
    written_by_rule(out / "analytic_timeseries.csv", scene)  # at the scene's own dt


def test_run_refuses_a_step_above_the_stable_limit(tmp_path, capsys):
    out = tmp_path / "fe"
    code = main(["run", "scenes/longitudinal.toml", "--set", "fem.mesh=medium", "--out", str(out)])
    assert code == EXIT_BAD_INPUT and "time.dt" in capsys.readouterr().err
    assert not out.exists() and list(tmp_path.iterdir()) == []
