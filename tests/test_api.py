"""The Python API (vibrofric.api): the same answers as the command, light to import."""

import ast
import doctest
import importlib
import json
import subprocess
import sys
from pathlib import Path

import pytest

import vibrofric as vf
from vibrofric import api
from vibrofric.cli import main
from vibrofric.scene import SceneError

from conftest import ROOT, child_environment

SHORT = {"time.T": 0.2}


def test_docstring_examples_run():
    """Every example in the API's docstrings gives what it shows (the FE one is skipped: slow)."""
    outcome = doctest.testmod(api, optionflags=doctest.ELLIPSIS)
    assert outcome.attempted >= 10 and outcome.failed == 0


@pytest.mark.parametrize("module", ["vibrofric.scene", "vibrofric.scene.keys", "vibrofric.bench.fits"])
def test_other_public_modules_docstring_examples_run(module):
    outcome = doctest.testmod(importlib.import_module(module), optionflags=doctest.ELLIPSIS)
    assert outcome.attempted >= 2 and outcome.failed == 0


def test_import_is_light():
    """import vibrofric loads neither numpy nor numba; the API's names appear on first use."""
    code = ("import sys, vibrofric as vf; heavy = [m for m in ('numpy', 'numba', 'dolfinx', 'pandas') "
            "if m in sys.modules]; assert not heavy, heavy; vf.load_scene; "
            "assert 'load_scene' in dir(vf); print(vf.__version__)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          env=child_environment(), cwd=ROOT)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == vf.__version__


def test_version_option(capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["--version"])
    assert exit_.value.code == 0 and capsys.readouterr().out.strip() == f"vibrofric {vf.__version__}"


def test_unknown_name_is_an_attribute_error():
    with pytest.raises(AttributeError, match="no_such_thing"):
        vf.no_such_thing  # noqa: B018


def test_scene_from_name_file_dict_and_overrides():
    by_name = vf.load_scene("coupled", **SHORT)
    by_file = vf.load_scene(ROOT / "scenes" / "coupled.toml", time__T=0.2)
    assert by_name == by_file
    assert vf.load_scene(by_name) is by_name
    from_dict = vf.load_scene({"vibration": {"k_v": 3}})
    assert from_dict.vibration.k_v == 3.0 and from_dict.body == vf.load_scene({}).body
    with pytest.raises(SceneError, match="no such scene file, nor a shipped scene"):
        vf.load_scene("no_such_scene")
    with pytest.raises(SceneError, match="vibration.bogus"):
        vf.load_scene("coupled", **{"vibration.bogus": 1})


def test_law_file_override_is_relative_to_the_current_directory(monkeypatch):
    monkeypatch.chdir(ROOT / "examples")
    scene = vf.load_scene("longitudinal", **{"contact.law": "laws/maxwell_slip.py"})
    assert Path(scene.contact.law) == ROOT / "examples" / "laws" / "maxwell_slip.py"
    assert vf.load_law(scene.contact.law).parameters.keys() >= {"k_t", "mu"}


def test_analytic_equals_the_command(tmp_path, capsys):
    """The API's run and written files are the command's: same summary values, same files."""
    out_cli, out_api = tmp_path / "cli", tmp_path / "api"
    assert main(["analytic", "scenes/longitudinal.toml", "--set", "time.T=0.2",
                 "--out", str(out_cli), "--json"]) == 0
    document = json.loads(capsys.readouterr().out)
    result = vf.run_analytic(vf.load_scene("longitudinal", **SHORT), out=out_api)
    moving = {"wall_time_s", "error_wall_time_s", "out"}
    assert {k: v for k, v in result.summary.items() if k not in moving} == \
           {k: v for k, v in document.items() if k not in moving}
    assert result.F_dv_over_F_d0 == document["F_dv_over_F_d0"]
    assert result.settled is document["settled"] and result.out == out_api
    for name in ("scene.toml", "timeseries.csv"):
        assert (out_api / name).read_bytes() == (out_cli / name).read_bytes(), name
    assert {p.name for p in out_api.iterdir()} == {p.name for p in out_cli.iterdir()}
    # the DataFrame holds every kept row (a stepped run: more than the file's; a periodic
    # answer: the steady cycles, all written), its last row the run's end
    table = result.timeseries
    assert list(table.columns) == ["t", "F_d", "F_x", "F_y", "x", "y", "x_b", "y_b"]
    last_written = (out_cli / "timeseries.csv").read_text().splitlines()[-1].split(",")
    assert table.iloc[-1].tolist() == [float(v) for v in last_written]
    assert len(table) >= len((out_cli / "timeseries.csv").read_text().splitlines()) - 1


def test_analytic_refuses_like_the_command(tmp_path):
    scene = vf.load_scene("coupled", **SHORT, **{"vibration.theta_deg": 45})
    with pytest.raises(SceneError, match="vibration.theta_deg"):
        vf.run_analytic(scene, stepper="longitudinal")
    (tmp_path / "mine.txt").write_text("a user's file")
    with pytest.raises(Exception, match="vibrofric"):
        vf.run_analytic(scene, out=tmp_path)
    assert [p.name for p in tmp_path.iterdir()] == ["mine.txt"]


def test_sweep_table_equals_single_runs():
    scene = vf.load_scene("coupled", **SHORT)
    table = vf.sweep(scene, {"vibration.k_v": [2, 6], "vibration.theta_deg": [0, 90]}, workers=1)
    assert table[["vibration.k_v", "vibration.theta_deg"]].values.tolist() == [
        [2.0, 0.0], [2.0, 90.0], [6.0, 0.0], [6.0, 90.0]]
    # a lane's first point (batch/lanes.py: here each row's first) starts from steady
    # sliding as a single run does: the same bits; the next one from its orbit, to the
    # Newton tolerance (1e-10 of each unknown's size)
    first = vf.run_analytic(scene.with_values({"vibration.k_v": 6.0, "vibration.theta_deg": 0.0}))
    assert table["F_dv_over_F_d0"].iloc[2] == first.F_dv_over_F_d0
    one = vf.run_analytic(scene.with_values({"vibration.k_v": 6.0, "vibration.theta_deg": 90.0}))
    assert table["F_dv_over_F_d0"].iloc[3] == pytest.approx(one.F_dv_over_F_d0, rel=1e-9)


def _as_value(scene) -> tuple:
    """What makes a scene a value: its pickle, its hash, and an unpickled copy equal to it."""
    import pickle

    data = pickle.dumps(scene)
    assert pickle.loads(data) == scene
    return data, hash(scene)


def test_a_scene_is_the_same_value_after_a_run():
    """A run keeps nothing in its scene: a scene run, then swept over both cores, which
    pickles it into the workers (five points: two lanes of continuation, one per
    worker, batch/lanes.py)."""
    scene = vf.load_scene("longitudinal", **SHORT)
    before = _as_value(scene)
    vf.run_analytic(scene)
    assert _as_value(scene) == before
    assert vf.load_scene(scene) == scene and hash(vf.load_scene(scene)) == before[1]
    table = vf.sweep(scene, {"vibration.k_v": [2, 3, 4, 5, 6]}, workers=2)
    assert len(table) == 5 and table["F_dv_over_F_d0"].notna().all()
    assert _as_value(scene) == before
    other = scene.with_values({"contact.mu": 0.2})
    assert other != scene and hash(other) != hash(scene)   # a law parameter is part of the value


def test_sweep_to_disk_resumes(tmp_path):
    scene = vf.load_scene("longitudinal", **SHORT)
    first = vf.sweep(scene, {"vibration.k_v": [2, 6]}, out=tmp_path / "s", workers=1)
    assert (tmp_path / "s" / "results.csv").exists()
    again = vf.sweep(scene, {"vibration.k_v": [2, 6]}, out=tmp_path / "s", workers=1)
    assert again["F_dv_over_F_d0"].tolist() == first["F_dv_over_F_d0"].tolist()
    in_memory = vf.sweep(scene, {"vibration.k_v": [2, 6]})
    # each point's orbit shot from the same start by either path (batch/lanes.py)
    assert in_memory["F_dv_over_F_d0"].tolist() == first["F_dv_over_F_d0"].tolist()


def test_only_the_command_imports_the_api():
    """The API sits above every model layer: nothing but cli.py (and the package's
    lazy __getattr__) imports it."""
    package = ROOT / "vibrofric"
    importers = []
    for path in sorted(package.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and (node.module or "").split(".")[-1] == "api":
                importers.append(path.relative_to(package).as_posix())
            elif isinstance(node, ast.ImportFrom) and node.level == 1 and node.module is None \
                    and any(alias.name == "api" for alias in node.names):
                importers.append(path.relative_to(package).as_posix())
    assert sorted(set(importers)) == ["__init__.py", "cli.py"]


@pytest.mark.slow
def test_fe_result_beside_the_analytic_one(tmp_path):
    scene = vf.load_scene("longitudinal", **{"time.T": 0.16, "fem.mesh": "tiny"})
    before = _as_value(scene)
    quiet = vf.run_fe(scene)
    assert _as_value(scene) == before   # the FE run kept nothing in its scene either
    # one scene, one analytic answer: the stepper beside the FE model runs at the scene's dt
    assert quiet.analytic.F_dv_over_F_d0 == vf.run_analytic(scene).F_dv_over_F_d0
    assert quiet.out is None and quiet.info["vtk"] is None
    assert quiet.analytic is not None and 0 < quiet.F_dv_over_F_d0 < 1
    assert quiet.rel_error == abs(quiet.F_dv_over_F_d0 - quiet.analytic.F_dv_over_F_d0) / \
        quiet.analytic.F_dv_over_F_d0
    assert "F_n" in quiet.timeseries.columns
    written = vf.run_fe(scene, out=tmp_path / "fe")
    assert written.F_dv_over_F_d0 == quiet.F_dv_over_F_d0  # ParaView frames change no number
    assert (tmp_path / "fe" / "paraview" / "block.pvd").exists()
    assert json.loads((tmp_path / "fe" / "summary.json").read_text())["out"] == str(tmp_path / "fe")


def test_scene_keys_lists_every_key_with_its_value_default_and_unit():
    """Every key of a scene, each settable by its name to the value listed (setting every
    one gives the scene back); defaults those of a scene of defaults; a unit for each
    number of the sections (scene.reference.UNITS) and the law's own."""
    from vibrofric import scene as scene_module
    from vibrofric.scene.reference import UNITS

    scene = vf.load_scene("transverse", **{"vibration.k_v": 2, "contact.lugre.F_s": 7.0})
    table = vf.scene_keys(scene)
    assert list(table.columns) == ["key", "value", "default", "unit", "meaning"]
    keys = table.set_index("key")
    defaults = scene_module.from_dict({})
    for section, cls in scene_module.SECTIONS.items():
        for name in cls.__dataclass_fields__:
            if name not in ("parameters", "tables"):
                key = f"{section}.{name}"
                assert keys.loc[key, "value"] == scene.get(key)
                assert keys.loc[key, "default"] == defaults.get(key)
    assert set(UNITS) <= set(keys.index)
    assert keys.loc["vibration.k_v", ["value", "default"]].tolist() == [2.0, 6.0]
    assert keys.loc["contact.k_t", "value"] == scene.contact.k_t and \
        keys.loc["contact.k_t", "unit"] == "N/m"
    assert keys.loc["contact.lugre.F_s", "value"] == 7.0          # another law's table
    settable = {key: value for key, value in zip(table["key"], table["value"]) if value is not None}
    again = scene.with_values(settable)   # (the law's defaults now set outright: same values)
    assert again.contact.law_values == scene.contact.law_values
    assert scene_module.to_dict(again) | {"contact": {}} == scene_module.to_dict(scene) | {
        "contact": {}} and again.contact.tables == scene.contact.tables
    assert keys.loc["body.mass", "meaning"] == "the body's mass"   # the comment, less its unit


def test_keys_command_is_the_api_in_a_table(capsys):
    from vibrofric.cli import main

    assert main(["keys", "transverse", "--set", "vibration.k_v=2"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].split() == ["key", "value", "default", "unit", "meaning"]
    rows = {line.split()[0]: line.split() for line in lines[1:]}
    assert len(rows) == len(vf.scene_keys("transverse"))
    assert rows["vibration.k_v"][1:4] == ["2", "6", "-"]
    assert rows["body.mass"][1:4] == ["2", "0.5", "kg"]
    assert main(["keys", "--json"]) == 0
    listed = json.loads(capsys.readouterr().out)
    assert {row["key"]: row["value"] for row in listed}["body.mass"] == 0.5   # the defaults
    assert main(["keys", "--set", "vibration.kv=2"]) == 2
    assert "vibration.kv: unknown key" in capsys.readouterr().err
