"""The written time series: the default rows, every kept row with --full-series,
and a summary that does not depend on which rows are written."""

import json

import numpy as np
import pytest

from vibrofric import budget
from vibrofric.analytic.solve import solve
from vibrofric.analytic.summary import cycle_average
from vibrofric.cli import main
from vibrofric.core.series import averaging_steps, written, written_rows, written_stride

# Runs stepped through time.T (time.method transient), whose kept and written rows these
# tests count; an answer by the steady cycle writes its few repeats whole.
STEPPED = ["--set", "time.method=transient"]
SHORT = ["--set", "time.T=0.2", *STEPPED]
# vibration from 10 ms, 0.03 s in all: every step of it fits a test
EVERY_STEP = ["--set", "vibration.t_on=0.01", "--set", "time.T=0.03",
              "--set", "time.average_cycles=10", "--set", "time.series_dt=1e-6", *STEPPED]


def analytic(tmp_path, capsys, name: str, *args) -> dict:
    """``vibrofric analytic`` into tmp_path/name; its JSON, less its times and out."""
    out = tmp_path / name
    assert main(["analytic", *args, "--out", str(out), "--json"]) == 0
    document = json.loads(capsys.readouterr().out)
    del document["wall_time_s"], document["error_wall_time_s"], document["out"]
    return document


@pytest.mark.parametrize("name, overrides, stride", [
    ("longitudinal", {}, 30),       # 4 kHz at 1 us: 250 steps a cycle, 31.25 a row, down to 3 x 10
    ("transverse", {}, 40),         # 3 kHz: 333.3 steps a cycle, 41.7 a row, down to 4 x 10
    ("longitudinal", {"time.series_dt": 1e-4}, 100),   # never finer than the recording
    ("longitudinal", {"time.dt": 2.5e-5}, 1),  # the coarsest step a scene takes: 10 a cycle
])
def test_written_stride(load_scene, name, overrides, stride):
    scene = load_scene(name).with_values(overrides)
    assert written_stride(scene) == stride


def test_default_series_holds_the_documented_rows(tmp_path, capsys, load_scene, written_by_rule):
    analytic(tmp_path, capsys, "A", "scenes/transverse.toml", *SHORT)
    scene = load_scene("transverse", time__T=0.2, time__method="transient")
    table = written_by_rule(tmp_path / "A" / "timeseries.csv", scene)
    kept = solve(scene)[0]
    assert 8 * 0.2 * scene.vibration.f < len(table) < kept.t.size / 3
    assert np.array_equal(table, written(kept, scene).table())  # the values, to the last bit


def test_full_series_writes_every_step(tmp_path, capsys, load_scene):
    analytic(tmp_path, capsys, "A", "scenes/longitudinal.toml", *EVERY_STEP, "--full-series")
    table = np.loadtxt(tmp_path / "A" / "timeseries.csv", delimiter=",", skiprows=1)
    scene = load_scene("longitudinal", vibration__t_on=0.01, time__T=0.03,
                       time__average_cycles=10, time__series_dt=1e-6, time__method="transient")
    assert np.array_equal(np.rint(table[:, 0] / scene.time.dt), np.arange(1, scene.steps + 1))
    assert np.array_equal(table, solve(scene)[0].table())


def test_summary_does_not_depend_on_the_written_rows(tmp_path, capsys, load_scene):
    default = analytic(tmp_path, capsys, "A", "scenes/coupled.toml", *SHORT)
    full = analytic(tmp_path, capsys, "B", "scenes/coupled.toml", *SHORT, "--full-series")
    assert default == full
    rows = {name: np.loadtxt(tmp_path / name / "timeseries.csv", delimiter=",", skiprows=1)
            for name in "AB"}
    assert len(rows["A"]) < len(rows["B"]) / 3
    # F_dv is the mean over the last window of every kept step, which only the full file holds
    window = averaging_steps(load_scene("coupled", time__T=0.2, time__method="transient"))
    assert cycle_average(rows["B"][:, 1], window) == full["F_dv"]
    assert cycle_average(rows["A"][:, 1], window) != full["F_dv"]


def test_disk_estimate_counts_the_written_rows(tmp_path, capsys, load_scene):
    analytic(tmp_path, capsys, "A", "scenes/longitudinal.toml", *SHORT)
    scene = load_scene("longitudinal", time__T=0.2, time__method="transient")
    rows = len(np.loadtxt(tmp_path / "A" / "timeseries.csv", delimiter=",", skiprows=1))
    assert rows <= written_rows(scene) <= 1.05 * rows
    assert budget.estimate(scene, fe=False)["disk"] < budget.estimate(scene, fe=False,
                                                                       full_series=True)["disk"]
