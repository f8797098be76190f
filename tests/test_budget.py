"""What a run will need (vibrofric.budget): refusals that name the key which changes it."""

import pathlib

import pytest

from vibrofric import budget
from vibrofric import scene as scenes
from vibrofric.scene import SceneError

SCENE = pathlib.Path(__file__).resolve().parent.parent / "scenes" / "longitudinal.toml"


@pytest.fixture
def eight_gib(monkeypatch):
    """A machine with 8 GiB available, so that the refusals do not depend on this one's."""
    monkeypatch.setattr(budget, "available_memory", lambda: 8 * 2**30)


def test_a_step_too_fine_for_the_kept_series_names_time_dt_not_time_T(eight_gib, tmp_path):
    """time.dt = 1e-10: the rows kept at every step (the last two averaging windows)
    overflow memory, which neither time.T nor time.series_dt changes: the refusal names
    time.dt, and what it advises does lower those rows."""
    scene = scenes.load(SCENE, ["time.dt=1e-10"])
    with pytest.raises(SceneError) as refused:
        budget.check([scene], fe=False, out=tmp_path)
    assert refused.value.key == "time.dt" and "raise time.dt" in str(refused.value)
    assert "time.T" not in str(refused.value) and "series_dt" not in str(refused.value)
    rows = budget.estimate(scene, fe=False)["full_rows"]
    assert budget.estimate(scene.with_values({"time.T": 0.5}), fe=False)["full_rows"] == rows
    assert budget.estimate(scene.with_values({"time.series_dt": 1e-3}), fe=False)["full_rows"] == rows
    assert budget.estimate(scene.with_values({"time.dt": 1e-8}), fe=False)["full_rows"] == pytest.approx(
        rows / 100, rel=0.01)


def test_a_run_too_long_for_its_series_names_time_T(eight_gib, tmp_path):
    """time.T = 1e5 s: the rows a time.series_dt apart overflow memory: time.T is named."""
    scene = scenes.load(SCENE, ["time.T=1e5"])
    with pytest.raises(SceneError) as refused:
        budget.check([scene], fe=False, out=tmp_path)
    assert refused.value.key == "time.T" and "shorten time.T or raise time.series_dt" in str(refused.value)
