"""Scene loading, overrides and the refusals of docs/scenes.md."""

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
    ("contact.update='implicit'", "contact.update"),
    ("drive.attach='top'", "drive.attach"),
    ("drive.mode='force'", "drive.mode"),
    ("contact.v_s=0", "contact.v_s"),
    ("contact.F_s=-1", "contact.F_s"),
    ("fem.penalty=0", "fem.penalty"),
    ("time.average_cycles=-1", "time.average_cycles"),
    ("time.average_cycles=100000", "time.average_cycles"),  # longer than T - t_on
    ("body.mass='heavy'", "body.mass"),       # wrong type
    ("body.mass=true", "body.mass"),
    ("time.average_cycles=2.5", "time.average_cycles"),
    ("contact.law=1", "contact.law"),
    ("body.colour=1", "body.colour"),         # unknown key
    ("shape.mass=1", "shape.mass"),           # unknown section
]


@pytest.mark.parametrize("override,key", INVALID)
def test_invalid_values_are_refused_naming_the_key(load_scene, override, key):
    with pytest.raises(SceneError) as err:
        scene_module.load("scenes/longitudinal.toml", [override])
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
