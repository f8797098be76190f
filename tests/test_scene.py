"""Scene loading, overrides and the refusals of docs/scenes.md."""

import tomllib
from pathlib import Path

import pytest

from vibrofric import scene as scene_module
from vibrofric.scene import SceneError

# (override, the key the message must name)
INVALID = [
    ("body.mass=0", "body.mass"),
    ("body.mass=-0.5", "body.mass"),
    ("contact.mu=-0.1", "contact.mu"),
    ("contact.F_N=0", "contact.F_N"),
    ("contact.k_t=-1", "contact.k_t"),
    ("time.dt=0", "time.dt"),
    ("time.dt=-1e-6", "time.dt"),
    ("time.T=0.1", "time.T"),                 # ends before vibration.t_on = 0.14
    ("time.dt=2", "time.dt"),                 # longer than the run
    ("time.dt=1e-4", "time.dt"),              # 2.5 steps a vibration cycle
    ("drive.k_d=0", "drive.k_d"),
    ("drive.v_d=0", "drive.v_d"),
    ("vibration.f=0", "vibration.f"),
    ("vibration.k_v=-2", "vibration.k_v"),
    ("vibration.t_on=-1", "vibration.t_on"),
    ("contact.eta_y=1.5", "contact.eta_y"),
    ("body.nu=0.5", "body.nu"),
    ("body.E=0", "body.E"),
    ("body.size=[0.03, 0, 0.05]", "body.size"),
    ("body.size=[0.03, 0.05]", "body.size"),
    ("body.density=-7850", "body.density"),
    ("contact.law='coulomb'", "contact.law"),
    ("contact.update='implicit'", "contact.dahl.update"),
    ("drive.attach='top'", "drive.attach"),
    ("drive.mode='force'", "drive.mode"),
    ("contact.v_s=0", "contact.v_s"),
    ("contact.F_s=-1", "contact.F_s"),
    ("fem.penalty=0", "fem.penalty"),
    ("time.average_cycles=-1", "time.average_cycles"),
    ("time.average_cycles=100000", "time.average_cycles"),  # longer than T - t_on (stepped)
    ("body.mass='heavy'", "body.mass"),       # wrong type
    ("body.mass=true", "body.mass"),
    ("time.average_cycles=2.5", "time.average_cycles"),
    ("contact.law=1", "contact.law"),
    ("body.colour=1", "body.colour"),         # unknown key
    ("shape.mass=1", "shape.mass"),           # unknown section
]


@pytest.mark.parametrize("override,key", INVALID)
def test_invalid_values_are_refused_naming_the_key(load_scene, override, key):
    # stepped: the averaging window is checked only for a scene to be stepped through time.T
    with pytest.raises(SceneError) as err:
        scene_module.load("scenes/longitudinal.toml", ['time.method="transient"', override])
    assert err.value.key == key
    assert str(err.value).startswith(key)


def test_unknown_section_in_a_file(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text("[vibrations]\nk_v = 2\n")
    with pytest.raises(SceneError, match="vibrations"):
        scene_module.load(path)


def test_defaults_and_overrides(tmp_path):
    path = tmp_path / "minimal.toml"
    path.write_text("[vibration]\nk_v = 3\n")
    scene = scene_module.load(path, ["time.T=0.5", "contact.law=lugre", "body.size=[0.02, 0.02, 0.02]"])
    assert scene.name == "minimal"
    assert scene.vibration.k_v == 3.0 and isinstance(scene.vibration.k_v, float)
    assert scene.time.T == 0.5 and scene.contact.law == "lugre"
    assert scene.body.size == (0.02, 0.02, 0.02)
    assert scene.contact.mu == scene_module.Contact().mu  # untouched keys keep defaults
    assert scene.u0 == pytest.approx(3 * 5e-4 / (2 * 3.141592653589793 * 4000))


def test_scene_round_trips_through_toml(load_scene, tmp_path):
    scene = load_scene("transverse", contact__law="lugre", contact__F_s=6.0)
    path = tmp_path / "again.toml"
    path.write_text(scene_module.to_toml(scene))
    again = scene_module.load(path)
    assert scene_module.to_dict(again) == scene_module.to_dict(scene)


@pytest.mark.parametrize("name,mass,theta,k_v", [("longitudinal", 0.5, 0.0, 6.0),
                                                ("transverse", 2.0, 270.0, 20.0),
                                                ("coupled", 2.0, 45.0, 6.0)])
def test_shipped_scenes_hold_the_papers_cases(load_scene, name, mass, theta, k_v):
    scene = load_scene(name)
    assert (scene.body.mass, scene.vibration.theta_deg, scene.vibration.k_v) == (mass, theta, k_v)
    assert scene.time.dt == 1e-6 and scene.time.T == 1.0 and scene.vibration.t_on == 0.14


LAWS_ROOT = Path(__file__).resolve().parents[1] / "examples" / "laws"


@pytest.mark.parametrize("scene_name", ["longitudinal", "transverse", "coupled"])
@pytest.mark.parametrize("law", ["dahl", "lugre", str(LAWS_ROOT / "jenkins.py"),
                                 str(LAWS_ROOT / "maxwell_slip.py")])
def test_any_law_runs_from_any_shipped_scene(scene_name, law):
    """--set contact.law=... on a shipped scene: the other laws' tables stay unapplied
    (the Dahl table's update reaches Dahl only), the shared keys reach the new law."""
    scene = scene_module.load(f"scenes/{scene_name}.toml", [f"contact.law={law}"])
    values = scene.contact.law_values
    assert values["k_t"] == scene_module.load(f"scenes/{scene_name}.toml").contact.k_t
    assert ("update" in values) == (law in ("dahl", "lugre"))
    assert scene.contact.tables["dahl"] == {"update": "exact"}


def test_a_law_table_applies_to_its_own_law_only():
    """[contact.lugre] reaches LuGre alone, over [contact]'s value; a round trip through
    the written scene keeps every table where it was."""
    scene = scene_module.load("scenes/longitudinal.toml", ["contact.lugre.mu=0.2",
                                                           "contact.dahl.update=paper"])
    assert scene.contact.mu == 0.1 and scene.contact.update == "paper"
    lugre = scene.with_values({"contact.law": "lugre"})
    assert lugre.contact.mu == 0.2 and lugre.contact.update == "exact"
    again = scene_module.from_dict(tomllib.loads(scene_module.to_toml(lugre)))
    assert again.contact == lugre.contact


def test_set_changes_a_key_where_the_scene_holds_it():
    """--set contact.update=paper changes the chosen law's table, not [contact]: the
    scene then still switches to a law without an update."""
    scene = scene_module.load("scenes/longitudinal.toml", ["contact.update=paper"])
    assert scene.contact.tables["dahl"] == {"update": "paper"} and "update" not in scene.contact.parameters
    jenkins = scene.with_values({"contact.law": str(LAWS_ROOT / "jenkins.py")})
    assert set(jenkins.contact.law_values) == {"k_t", "mu"}


@pytest.mark.parametrize("overrides, key", [
    (["contact.dahl.updat=paper"], "contact.dahl.updat"),        # a typo in a built-in's table
    (["contact.lugre.v_s=-1"], "contact.lugre.v_s"),             # checked though Dahl runs
    (["contact.dalh.update=paper"], "contact.dalh"),             # a misspelled law's table
    ([f"contact.law={LAWS_ROOT / 'jenkins.py'}", "contact.dahl_exponent=0"],
     "contact.dahl_exponent"),                                   # not the chosen law's key
    ([f"contact.law={LAWS_ROOT / 'jenkins.py'}", "contact.jenkins.k_T=1"], "contact.jenkins.k_T"),
])
def test_a_key_for_no_law_or_another_law_is_refused(overrides, key, refused_key):
    assert refused_key(lambda: scene_module.load("scenes/longitudinal.toml", overrides)) == key


def test_a_short_T_is_refused_where_the_scene_is_stepped_naming_the_shortest_T():
    """time.T must hold a stepped run's averaging window after vibration.t_on: under
    time.method transient a shorter T is refused naming the shortest one, which runs.
    Under auto and periodic the steady cycle needs no window: a short T runs (T ends
    the written series), and only a fallback to stepping is refused, naming the same T
    (tests/test_periodic.py)."""
    import vibrofric as vf
    from vibrofric.core.series import shortest_stepped_T

    scene = scene_module.load("scenes/longitudinal.toml", ['time.method="transient"'])
    shortest = shortest_stepped_T(scene)
    # t_on and the window of the drive system's period (57 cycles at 4 kHz)
    assert shortest == pytest.approx(0.14 + 57 / 4000.0, abs=1e-4)
    for T in (0.1, 0.15, shortest - 1e-4):
        with pytest.raises(SceneError) as err:
            scene.with_values({"time.T": T})
        assert err.value.key == "time.T"
        assert f"the shortest T that works is {shortest:g} s" in str(err.value)
    vf.run_analytic(scene.with_values({"time.T": shortest}))    # runs, without a refusal
    for method in ("auto", "periodic"):
        short = scene.with_values({"time.method": method, "time.T": 0.1})
        assert vf.run_analytic(short).summary["periodic"]["method"] == "periodic"
    docs = (Path(__file__).resolve().parents[1] / "docs" / "periodic.md").read_text()
    assert f"({shortest:g} s on the shipped\nlongitudinal scene" in docs
