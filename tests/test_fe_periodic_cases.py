"""The FE steady state by shooting against the settled stepped run of the same integrator
at the same step, over the scenes, grid points, laws and models of docs/periodic.md's
"Checked" list (fem/integrators/periodic.py); the Fig 7 cases are in test_fe_periodic.py.

Each case is stepped from the vibration's start at 10 ms to time.T on the coarse mesh
(unless said) and shot; the time step is the one that puts a whole number of steps in
a base cycle (core.shooting.cycle_steps: 33 steps of 1.0101e-5 s at 3 kHz), so both runs
integrate the same discrete map."""

import pytest

from vibrofric import scene as scene_module
from vibrofric.analytic.summary import summarize
from vibrofric.core import shooting
from vibrofric.fem import run_fe

LONGITUDINAL = "scenes/longitudinal.toml"
TRANSVERSE = "scenes/transverse.toml"
COUPLED = "scenes/coupled.toml"
REDUCED = {"fem.integrator": "reduced", "time.dt": 1e-5}
EXPLICIT = {"fem.integrator": "explicit", "time.dt": 1e-6}

# (scene, changes, time.T). T: the stepped run must have settled (its slowest mode, the
# block on the drive spring, ~0.96-0.99 a cycle: 1200-1600 cycles from the start bring
# it below 1e-7); at k_v = 2, 135 deg a mode of 0.994 a cycle (measured from the stepped
# run's approach) needs 1.2 s (3570 cycles: 2e-9).
CASES = {
    "coupled scene (k_v 6, 45 deg)": (COUPLED, REDUCED, 0.4),
    "coupled scene, explicit": (COUPLED, EXPLICIT, 0.4),
    "transverse scene (k_v 20, 270 deg), explicit": (TRANSVERSE, EXPLICIT, 0.4),
    "Fig 6: k_v 4, 0 deg": (LONGITUDINAL, {**REDUCED, "vibration.k_v": 4.0}, 0.4),
    "Fig 9: k_v 2, 90 deg": (TRANSVERSE, {**REDUCED, "vibration.k_v": 2.0,
                                          "vibration.theta_deg": 90.0}, 0.4),
    "Fig 12: k_v 20, 180 deg": (COUPLED, {**REDUCED, "vibration.k_v": 20.0,
                                          "vibration.theta_deg": 180.0}, 0.4),
    "Fig 12: k_v 2, 135 deg": (COUPLED, {**REDUCED, "vibration.k_v": 2.0,
                                         "vibration.theta_deg": 135.0}, 1.2),
    "Dahl i = 0": (LONGITUDINAL, {**REDUCED, "contact.dahl_exponent": 0.0}, 0.4),
    "Dahl i = 2": (LONGITUDINAL, {**REDUCED, "contact.dahl_exponent": 2.0}, 0.4),
    # the contact 100 times stiffer: the explicit step at 1e-6 s is 6 times cheaper than
    # the reduced one's contact iteration there (multiplier 0.960: settled by 0.25 s)
    "k_t x 100, explicit": (LONGITUDINAL, {**EXPLICIT, "contact.k_t": 8e9}, 0.25),
    "medium mesh": (LONGITUDINAL, {**REDUCED, "fem.mesh": "medium"}, 0.25),
}


def stepped_scene(path, changes, T):
    scene = scene_module.load(path).with_values(
        {"vibration.t_on": 0.01, "time.T": T, "fem.output_every": 0, **changes})
    _, dt = shooting.cycle_steps(scene)
    return scene.with_values({"time.dt": dt})


def ratio(fe, scene) -> float:
    return summarize(fe.series, scene, 0.0)["F_dv_over_F_d0"]


@pytest.mark.slow
@pytest.mark.parametrize("path, changes, T", CASES.values(), ids=CASES.keys())
def test_the_orbit_equals_the_settled_stepped_run(path, changes, T):
    """The orbit answers (converged, every multiplier inside the unit circle) and its
    F_dv equals the stepped run's within 1e-4 relative (the issue's FE target; measured
    1e-9 to 1.5e-6), the stepped run having settled (its last two windows within 1e-6)."""
    scene = stepped_scene(path, changes, T)
    stepped = run_fe(scene)
    assert summarize(stepped.series, scene, 0.0)["window_drift"] < 1e-6
    periodic_scene = scene.with_values({"time.method": "periodic"})
    shot = run_fe(periodic_scene)
    block = shot.info["periodic"]
    assert block["method"] == "periodic" and block["converged"] and not block["dt_adjusted"]
    assert block["floquet_max_modulus"] < shooting.STABLE
    assert ratio(shot, periodic_scene) == pytest.approx(ratio(stepped, scene), rel=1e-4)


@pytest.mark.slow
def test_an_orbit_whose_perturbation_grows_before_it_decays_answers():
    """k_v = 1 along X (Fig 7, reduced), where the lumped model's drive spring is not
    damped (multipliers of modulus 1): the FE shooting converges, Arnoldi's largest Ritz
    value is 1.8 and a perturbation grows over cycles 10-40 (1.0099 a cycle), then
    decays (0.972 a cycle over cycles 40-70: periodic.decay_rate), so the orbit answers,
    its block saying how it was judged, and equals the stepped run through T, which
    settles there (measured 2e-7; 1e-4 the issue's FE target)."""
    scene = stepped_scene(LONGITUDINAL, {**REDUCED, "vibration.k_v": 1.0}, 0.4)
    fe = run_fe(scene.with_values({"time.method": "periodic"}))
    block = fe.info["periodic"]
    assert block["converged"] and block["method"] == "periodic"
    assert "not confirmed" in block["floquet_note"] and block["floquet_max_modulus"] < 1.0
    stepped = run_fe(scene)
    assert summarize(stepped.series, scene, 0.0)["window_drift"] < 1e-6
    assert ratio(fe, scene) == pytest.approx(ratio(stepped, scene), rel=1e-4)
