"""What the run plots show at their scale (vibrofric/plots.py): a steady cycle against
the base's phase, both models on one span; a history of too many cycles as each
cycle's mean and range."""

from types import SimpleNamespace

import numpy as np
import pytest
from matplotlib.collections import PolyCollection

from vibrofric import plots
from vibrofric import scene as scene_module
from vibrofric.analytic.solve import solve
from vibrofric.core.series import written

from conftest import SCENES

LONGITUDINAL = str(SCENES / "longitudinal.toml")


@pytest.fixture(scope="module")
def steady_run():
    """The Fig 7 scene's analytic answer by its steady cycle (the default method)."""
    scene = scene_module.load(LONGITUDINAL, ["time.T=0.2"])
    series, summary = solve(scene)
    assert summary["periodic"]["method"] == "periodic"
    return scene, written(series, scene), summary


def test_steady_cycles_are_drawn_against_the_phase_on_one_span(steady_run):
    """Two runs answered by their steady cycles (here the stepper's and a stand-in
    0.97 times it): each curve spans one cycle, phase 0 to 360°, and each dashed line
    is its F_dv, the summary's to rounding (1e-12: the mean of the same n steps,
    summed in another order)."""
    scene, series, summary = steady_run
    other = SimpleNamespace(t=series.t, F_d=0.97 * series.F_d)
    fig = plots.drive_force_figure({"analytic": series, "FE": other}, scene,
                                   steady=("analytic", "FE"))
    lines = fig.axes[0].get_lines()
    curves = [line for line in lines if line.get_linestyle() == "-"]
    levels = [line for line in lines if line.get_linestyle() == "--"]
    assert len(curves) == 2 and len(levels) == 2
    for curve in curves:
        phase = np.asarray(curve.get_xdata())
        assert phase[0] == pytest.approx(0.0, abs=1e-6) and phase[-1] == 360.0
        assert np.all(np.diff(phase) > 0)
    F_dv = summary["F_dv"]
    assert [line.get_ydata()[0] for line in levels] == pytest.approx([F_dv, 0.97 * F_dv],
                                                                      rel=1e-12)


def test_a_run_not_all_steady_is_drawn_against_time(steady_run):
    """Where a run is not answered by its steady cycle, the plot is over time."""
    scene, series, _ = steady_run
    fig = plots.drive_force_figure({"analytic": series}, scene, steady=())
    assert fig.axes[0].get_xlabel().startswith("time")


def test_a_history_of_many_cycles_is_each_cycles_mean_and_range():
    """A made-up stepped run: flat before t_on, then 1 + 0.3 sin over 500 cycles sampled
    10 times a cycle. Drawn as a line of one point a cycle after t_on (the cycles' means)
    and a band between each cycle's extremes: the band's half-width is the swing within
    a sample's phase step (0.3 cos(pi / 10) at worst: 10 samples a cycle, at most half
    a step off the peak) and the mean 1 to the samples' symmetry (1e-9)."""
    f, t_on, cycles, per = 1000.0, 0.1, 500, 10
    t = np.concatenate([np.linspace(0.0, t_on, 50, endpoint=False),
                        t_on + np.arange(cycles * per) / (per * f) + 0.25 / (per * f)])
    y = np.where(t < t_on, 1.0, 1.0 + 0.3 * np.sin(2 * np.pi * f * (t - t_on)))
    scene = SimpleNamespace(name="made-up", F_c=2.0, vibrated=True, contact=SimpleNamespace(F_N=1.0),
                            vibration=SimpleNamespace(f=f, k_v=1.0, theta_deg=0.0, t_on=t_on))
    middle, low, mean, high = plots.cycle_envelope(t, y, f, t_on)
    assert len(middle) == cycles
    assert np.allclose(mean, 1.0, atol=1e-9)
    assert np.all(high <= 1.3) and np.all(high >= 1.0 + 0.3 * np.cos(np.pi / per) - 1e-12)
    assert np.all(low >= 0.7) and np.all(low <= 1.0 - 0.3 * np.cos(np.pi / per) + 1e-12)

    fig = plots.drive_force_figure({"FE": SimpleNamespace(t=t, F_d=y)}, scene)
    ax = fig.axes[0]
    line = ax.get_lines()[0]
    assert len(line.get_xdata()) == 50 + cycles       # the rows before t_on, then one a cycle
    assert any(isinstance(c, PolyCollection) for c in ax.collections)


def test_the_steady_normal_force_is_drawn_over_one_cycle(steady_run):
    """normal_force_figure of a steady FE run (a stand-in: the stepper's series with a
    normal force added): one cycle against the phase."""
    scene, series, _ = steady_run
    fe = SimpleNamespace(t=series.t, extra={"F_n": scene.contact.F_N + 0.01 * series.F_x})
    fig = plots.normal_force_figure(fe, scene, steady=True)
    phase = np.asarray(fig.axes[0].get_lines()[0].get_xdata())
    assert phase[0] == pytest.approx(0.0, abs=1e-6) and phase[-1] == 360.0


@pytest.mark.parametrize("method", ["auto", "transient"])
def test_the_lumped_normal_force_is_drawn_where_the_base_moves_along_z(method):
    """A base moving along Z past contact loss (1.7e-7 m: 5% of the cycle out of contact):
    the lumped body's N is drawn, over one steady cycle against the phase (auto) or over
    time (stepped), the curve the series' own N, reaching 0 (out of contact)."""
    scene = scene_module.load(LONGITUDINAL, ["time.T=0.2", "vibration.normal_amplitude=1.7e-7",
                                             f'time.method="{method}"'])
    series, summary = solve(scene, estimate=False)
    steady = summary.get("periodic", {}).get("method") == "periodic"
    assert steady == (method == "auto")
    rows = written(series, scene)
    fig = plots.normal_force_figure(rows, scene, steady=steady, column="N")
    ax = fig.axes[0]
    curve = ax.get_lines()[0]
    assert curve.get_label().startswith("contact normal force $N$")
    if steady:
        assert ax.get_xlabel() == plots.PHASE_LABEL
        assert np.asarray(curve.get_xdata())[-1] == 360.0
        N = np.asarray(curve.get_ydata())
        assert N.min() == 0.0 and N.max() == summary["normal_force_max"]
    else:
        assert ax.get_xlabel().startswith("time")
        # 0.2 s at 4 kHz after t_on: too many cycles to draw, each one's range shaded
        assert any(isinstance(c, PolyCollection) for c in ax.collections)


@pytest.mark.parametrize("steady", [True, False])
def test_the_fe_and_lumped_normal_forces_share_one_plot(steady_run, steady):
    """vibrofric run of a base moving along Z: the FE summed normal force and the lumped
    N on one axes (stand-ins: the stepper's series with normal forces added, the lumped
    one dropping to 0 where it would leave the contact), each curve its own series'."""
    scene, series, _ = steady_run
    fe = SimpleNamespace(t=series.t, extra={"F_n": scene.contact.F_N + 0.01 * series.F_x})
    lumped = SimpleNamespace(t=series.t,
                             extra={"N": np.maximum(scene.contact.F_N + 0.02 * series.F_x, 0.0)})
    fig = plots.normal_force_figure(fe, scene, steady=steady, lumped=lumped)
    ax = fig.axes[0]
    fe_curve, lumped_curve = ax.get_lines()[:2]
    assert fe_curve.get_label().startswith("FE: " + plots.NORMAL_FORCES["F_n"][0])
    assert lumped_curve.get_label().startswith("lumped: " + plots.NORMAL_FORCES["N"][0])
    if steady:
        _, rows = plots.steady_phase(series.t, scene.vibration.f)
        assert ax.get_xlabel() == plots.PHASE_LABEL
        np.testing.assert_array_equal(lumped_curve.get_ydata(), lumped.extra["N"][rows])
        np.testing.assert_array_equal(fe_curve.get_ydata(), fe.extra["F_n"][rows])
    else:
        assert ax.get_xlabel().startswith("time")
