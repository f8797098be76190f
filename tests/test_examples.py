"""The paper's figures (examples/fig*.py) run in their fast form, and what they
show agrees with what the paper states of its figures (docs/model.md section 4).

Each example is executed as a script (runpy), as ``make figures`` runs it, with
VIBROFRIC_FAST=1: a reduced grid to 0.2 s, no FE points (the FE model has its
own tests). Its variables are then read back.
"""

import runpy
from pathlib import Path

import numpy as np
import pytest

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
FIGURES = {
    "fig06_longitudinal.py": ["fig06.png"],
    "fig07_08_longitudinal_time.py": ["fig07.png", "fig08.png"],
    "fig09_transverse.py": ["fig09.png"],
    "fig10_11_transverse_time.py": ["fig10.png", "fig11.png"],
    "fig12_coupled.py": ["fig12.png"],
    "fig12_normal.py": ["fig12_normal.png"],
}
PNG = b"\x89PNG\r\n\x1a\n"


def run_example(name, tmp_path, monkeypatch) -> dict:
    monkeypatch.setenv("VIBROFRIC_FAST", "1")
    monkeypatch.setenv("VIBROFRIC_FIGURES", str(tmp_path))
    variables = runpy.run_path(str(EXAMPLES / name), run_name="__main__")
    for png in FIGURES[name]:
        assert (tmp_path / png).read_bytes()[:8] == PNG, png
    return variables


def test_every_figure_script_is_listed():
    assert sorted(p.name for p in EXAMPLES.glob("fig*.py")) == sorted(FIGURES)


def test_fig06_longitudinal(tmp_path, monkeypatch):
    v = run_example("fig06_longitudinal.py", tmp_path, monkeypatch)
    ratio = dict(zip(v["coupled"]["vibration.k_v"], v["coupled"]["F_dv_over_F_d0"]))
    # no reduction below k_v = 1 (the paper); 1e-3: at 0.2 s the average still holds
    # part of the drive spring's oscillation from breakaway (4e-5 measured)
    assert ratio[0.5] == pytest.approx(1.0, abs=1e-3)
    assert ratio[2.0] > ratio[6.0]  # a steady decrease above k_v = 1
    # the 1D model [23] and the coupled one along X are one model (the contract suite's check)
    assert v["one_d"] == pytest.approx(list(v["coupled"]["F_dv_over_F_d0"]), rel=1e-9)


def test_fig07_08_longitudinal_time(tmp_path, monkeypatch):
    v = run_example("fig07_08_longitudinal_time.py", tmp_path, monkeypatch)
    for run in v["runs"].values():
        # breakaway near 0.12 s, as the paper reads it off its Fig 7 (two digits)
        assert run.summary["breakaway_time_s"] == pytest.approx(0.12, abs=0.01)
        assert run.F_dv_over_F_d0 < 0.5


def test_fig09_transverse(tmp_path, monkeypatch):
    v = run_example("fig09_transverse.py", tmp_path, monkeypatch)
    ratio = dict(zip(v["coupled"]["vibration.k_v"], v["coupled"]["F_dv_over_F_d0"]))
    assert ratio[0.5] < 0.995  # transverse vibration reduces the force already below k_v = 1
    assert ratio[0.5] > ratio[2.0] > ratio[20.0]


def test_fig10_11_transverse_time(tmp_path, monkeypatch):
    v = run_example("fig10_11_transverse_time.py", tmp_path, monkeypatch)
    run = v["runs"]["new model (coupled stepper)"]
    assert run.summary["breakaway_time_s"] == pytest.approx(0.11, abs=0.01)  # "t ~ 0.11 sec"
    last = run.timeseries[run.timeseries["t"] >= 0.199]
    # at k_v = 20, F_x changes only in magnitude, F_y in magnitude and direction
    assert (last["F_x"] > 0).all() and (last["F_y"] > 0).any() and (last["F_y"] < 0).any()


def test_fig12_coupled(tmp_path, monkeypatch):
    v = run_example("fig12_coupled.py", tmp_path, monkeypatch)
    dahl, lugre = v["dahl"], v["lugre"]
    for k_v in v["k_v"]:
        rows = dahl[dahl["vibration.k_v"] == k_v]
        theta, ratio = rows["vibration.theta_deg"].to_numpy(), rows["F_dv_over_F_d0"].to_numpy()
        # symmetric about 180 deg: theta and 360 - theta are mirror images across X
        np.testing.assert_allclose(ratio, ratio[::-1], rtol=1e-9)
        assert theta[np.argmin(ratio)] % 180.0 == 0.0  # the greatest reduction is longitudinal
    # LuGre with h_t = h_v = 0 and F_s = mu F_N is Dahl: the paper's "exact match"
    both = dahl.merge(lugre, on=["vibration.k_v", "vibration.theta_deg"], suffixes=("", "_lugre"))
    assert len(both) == len(lugre) > 0
    np.testing.assert_allclose(both["F_dv_over_F_d0_lugre"], both["F_dv_over_F_d0"], rtol=1e-12)
    # a larger k_v lowers the force at every angle
    low, high = (dahl[dahl["vibration.k_v"] == k]["F_dv_over_F_d0"].to_numpy()
                 for k in (v["k_v"][0], v["k_v"][-1]))
    assert (high < low).all()


def test_fig12_normal(tmp_path, monkeypatch):
    v = run_example("fig12_normal.py", tmp_path, monkeypatch)
    by_angle, by_phase, scene, r = v["by_angle"], v["by_phase"], v["scene"], v["r"]
    assert not v["WITH_FE"]
    k_n, A_loss = scene.normal_stiffness, v["A_loss"]
    for amplitude in by_angle["vibration.normal_amplitude"].unique():
        rows = by_angle[by_angle["vibration.normal_amplitude"] == amplitude]
        # every point answered by its steady cycle (a neighbour's start included)
        assert all(block["method"] == "periodic" for block in rows["periodic"])
        ratio = rows["F_dv_over_F_d0"].to_numpy()
        # the mirror across X (y -> -y) leaves z alone: symmetric about 180 deg as Fig 12
        np.testing.assert_allclose(ratio, ratio[::-1], rtol=1e-9)
        # below A_loss the body keeps its contact, its normal force swinging by the closed
        # form k_n A_n r^2 / |1 - r^2| whatever the in-plane motion (1e-3: the peak between
        # two of 333 steps a cycle, 4e-5; the contact's damping, 1e-5; Euler's shift of the
        # bounce frequency, (w_n dt)^2 / 24 = 2e-4 on w_n, less on the swing)
        assert (rows["contact_loss_fraction"] == 0.0).all()
        swing = k_n * amplitude * r * r / abs(1.0 - r * r)
        np.testing.assert_allclose(rows["normal_force_max"] - scene.contact.F_N, swing,
                                   rtol=1e-3, atol=1e-9)
    # the normal motion in phase with a backward-inclined in-plane one carries the body
    # forward: at A_loss / 2 the drive force turns negative along -X (the vibratory conveyor)
    half = by_angle[np.isclose(by_angle["vibration.normal_amplitude"], 0.5 * A_loss)]
    assert half[half["vibration.theta_deg"] == 180.0]["F_dv_over_F_d0"].iloc[0] < 0.0
    # theta = 180 at phase phi is theta = 0 at phi + 180 half a cycle later, and theta = 90
    # at phi + 180 its mirror across X half a cycle later: the same answers but for where
    # the steps fall in the cycle (333 a cycle: half a cycle is not whole steps), so within
    # the two answers' step errors
    assert all(block["method"] == "periodic" for block in by_phase["periodic"])
    assert (by_phase["contact_loss_fraction"] == 0.0).all()
    phases = sorted(by_phase["vibration.normal_phase_deg"].unique())
    half_turn = (len(phases) - 1) // 2     # phases 0 to 360 at equal steps

    def curve(theta):
        rows = by_phase[by_phase["vibration.theta_deg"] == theta].sort_values(
            "vibration.normal_phase_deg")
        rows = rows[rows["vibration.normal_phase_deg"] < 360.0]   # 360 is 0 again
        return rows["F_dv_over_F_d0"].to_numpy(), rows["error_estimate"].to_numpy()

    for first, second, shift in [(0.0, 180.0, half_turn), (90.0, 90.0, half_turn)]:
        (a, a_error), (b, b_error) = curve(first), curve(second)
        shifted, shifted_error = np.roll(b, -shift), np.roll(b_error, -shift)
        assert np.all(np.abs(a - shifted) <= a_error + shifted_error), (a, shifted)
    # and the phase matters along X: the ratio swings by more than 0.3 over phi at theta = 0
    assert np.ptp(curve(0.0)[0]) > 0.3
