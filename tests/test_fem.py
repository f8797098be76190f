"""The finite-element model (vibrofric.fem) against the lumped stepper and itself.

Fast tests (the default selection) use the "coarse" mesh (720 DOFs) and short
runs; the paper's cases to a steady vibration cycle are marked slow.
"""

import math
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("dolfinx")

from vibrofric import scene as scenes  # noqa: E402
from vibrofric.analytic import breakaway_time, run_coupled, summarize  # noqa: E402
from vibrofric.analytic.summary import unsettled_warning  # noqa: E402
from vibrofric.core.errors import NumericalError, StepTooLong  # noqa: E402
from vibrofric.core.series import RecordPlan, full_resolution_steps  # noqa: E402
from vibrofric.fem import FEResult, run_fe  # noqa: E402
from vibrofric.fem import simulate as fem_simulate  # noqa: E402
from vibrofric.fem.integrators import explicit  # noqa: E402
from vibrofric.fem.model import fe_model  # noqa: E402
from vibrofric.fem.outputs import normal_swing, recording  # noqa: E402
from vibrofric.fem.outputs.paraview import FIELDS  # noqa: E402
from vibrofric.fem.model.stability import max_frequency  # noqa: E402
from vibrofric.fem.model.drive import drive_stiffness_action  # noqa: E402
from vibrofric.fe_beside_analytic import fe_beside_analytic  # noqa: E402
from vibrofric.scene import REFUSAL_KEYS  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
LONGITUDINAL = ROOT / "scenes" / "longitudinal.toml"
TRANSVERSE = ROOT / "scenes" / "transverse.toml"

# A short vibrated run, stepped: vibration from 0.5 ms, 2 ms of it (8 cycles at 4 kHz).
SHORT = ["vibration.t_on=0.0005", "time.T=0.0025", "time.average_cycles=2",
         'time.method="transient"']


def load(path, *overrides):
    return scenes.load(path, list(overrides))


@pytest.fixture(scope="module")
def comm():
    from mpi4py import MPI
    return MPI.COMM_SELF


# --- the model: block, loads, preload, stable step -----------------------------------------

@pytest.mark.parametrize("path, mass", [(LONGITUDINAL, 0.5), (TRANSVERSE, 2.0)])
def test_block_mass_loads_and_static_preload(path, mass, comm):
    scene = load(path)
    m = fe_model.build_model(scene, comm)
    # Mass: rho = mass / volume and a row-sum lumped mass are exact (rounding only).
    assert m.block_mass == pytest.approx(mass, rel=1e-12)
    assert m.disc.mass[2::3].sum() == pytest.approx(mass, rel=1e-12)
    # Loads: gravity + top pressure = F_N (exact up to rounding).
    assert -m.load[2::3].sum() == pytest.approx(scene.contact.F_N, rel=1e-12)
    assert m.area_share.sum() == pytest.approx(1.0, rel=1e-12)
    assert m.contact_area.sum() == pytest.approx(0.03 * 0.04, rel=1e-12)
    # Preload: every contact node pressed; reactions sum to F_N (a direct solve: 1e-9).
    assert np.all(m.normal0 > 0)
    assert m.normal0.sum() == pytest.approx(scene.contact.F_N, rel=1e-9)
    # ... and they are equilibrium: K u0 = f + contact forces, residual at solver precision.
    reaction = np.zeros(m.dofs)
    reaction[3 * m.contact_nodes + 2] = m.normal0
    residual = m.stiffness @ m.u0 - m.load - reaction
    assert np.abs(residual).max() <= 1e-8 * np.abs(m.load).max()
    # The load presses the face nearly uniformly: N_i / (F_N w_i) within 2.5%
    # (measured: corners 0.4% low for 0.5 kg, 1.9% low for 2 kg, whose weight is 39%
    # of F_N); a wrong area share (e.g. 1/n per node) would be off by 50% or more.
    assert np.allclose(m.normal0 / (scene.contact.F_N * m.area_share), 1.0, atol=0.025)
    # Symmetric preload: the face expands (Poisson) but its mean X displacement is 0,
    # up to the weakly pinned rigid modes (preload.REGULARIZATION): measured 3e-4
    # of the expansion; a load with an X component would show at order 1.
    expansion = np.abs(m.u0[0::3]).max()
    assert expansion > 0
    assert abs(np.dot(m.attach_weights, m.u0[3 * m.attach_nodes])) < 1e-3 * expansion


def test_stable_step_is_the_largest_frequency_of_the_whole_stiffness(comm):
    """Lanczos on a small mesh against a dense eigensolve of M^-1/2 K_total M^-1/2
    (block + penalty + 2 k_t shares + drive); 1e-8 is the iteration's tolerance."""
    scene = load(LONGITUDINAL, 'fem.mesh="2x2x3"')
    m = fe_model.build_model(scene, comm)
    K = m.stiffness.toarray()
    c = m.contact_nodes
    K[3 * c + 2, 3 * c + 2] += m.penalty_share
    for axis in (0, 1):
        K[3 * c + axis, 3 * c + axis] += 2 * scene.contact.k_t * m.area_share
    a = 3 * m.attach_nodes
    K[np.ix_(a, a)] += scene.drive.k_d * np.outer(m.attach_weights, m.attach_weights)
    s = 1 / np.sqrt(m.disc.mass)
    dense = math.sqrt(np.linalg.eigvalsh(s[:, None] * K * s[None, :])[-1])
    assert m.omega_max == pytest.approx(dense, rel=1e-8)
    # Damped central difference: dt_crit = (2 / w)(sqrt(1 + xi^2) - xi), xi = beta w / 2.
    xi = m.beta * m.omega_max / 2
    assert m.dt_stable == pytest.approx(2 / m.omega_max * (math.sqrt(1 + xi ** 2) - xi), rel=1e-14)
    action = drive_stiffness_action(scene.drive.k_d, m.attach_nodes, m.attach_weights, m.dofs)
    assert max_frequency(m.stiffness, m.disc.mass, c, m.penalty_share,
                         2 * scene.contact.k_t * m.area_share, action) == pytest.approx(dense, rel=1e-8)


@pytest.mark.parametrize("factor, stable", [(0.97, True), (1.03, False)])
def test_the_loop_is_stable_just_below_dt_stable_and_not_just_above(factor, stable, comm,
                                                                      monkeypatch):
    """The stable step is a sharp limit: 3% above it the highest mode grows from
    rounding noise by ~|-1.5|^n and is caught as a NumericalError within 3000
    steps; 3% below it the run is quiet. Fails if dt_stable is over- or
    underestimated by more than 3%."""
    base = load(LONGITUDINAL)
    m = fe_model.build_model(base, comm)
    scene = load(LONGITUDINAL, f"time.dt={factor * m.dt_stable!r}", "vibration.t_on=0.0005",
                 "time.T=0.003", "time.average_cycles=2")
    monkeypatch.setattr(explicit, "check_step", lambda scene, model: None)
    plan = RecordPlan.for_scene(scene, full_resolution_steps(scene))
    if stable:
        out = explicit.ExplicitRun(scene, m).integrate(plan)
        assert np.all(np.isfinite(out.table))
        assert np.abs(out.table[:, -1] - scene.contact.F_N).max() < 0.01 * scene.contact.F_N
    else:
        with pytest.raises(NumericalError, match=r"failed at t = .* s \(step \d+"):
            explicit.ExplicitRun(scene, m).integrate(plan)


def test_a_sweep_keeps_one_model_for_the_points_that_share_it(comm):
    """Within kept_between_runs (a sweep's run of points), a scene that changes only the
    vibration gets the model built last, read-only; one that changes what the model is
    built from (the normal load, the law's stiffness) gets its own, equal to a fresh
    build bit for bit; outside it every call builds afresh."""
    scene = load(LONGITUDINAL)
    with fe_model.kept_between_runs():
        first = fe_model.build_model(scene, comm)
        assert fe_model.build_model(scene.with_values({"vibration.k_v": 6.0,
                                                       "vibration.theta_deg": 90.0}), comm) is first
        assert not first.u0.flags.writeable
        for change in ({"contact.F_N": 40.0}, {"contact.k_t": 2.0 * scene.contact.k_t}):
            other = fe_model.build_model(scene.with_values(change), comm)
            assert other is not first
            fresh = fe_model._built(scene.with_values(change), comm)
            assert np.array_equal(other.u0, fresh.u0) and other.dt_stable == fresh.dt_stable
    assert fe_model.build_model(scene, comm) is not fe_model.build_model(scene, comm)
    assert fe_model.build_model(scene, comm).u0.flags.writeable


# --- whole runs ------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def breakaway_runs():
    """Without vibration, to just past breakaway (0.115 s): FE and the lumped stepper."""
    scene = load(LONGITUDINAL, "vibration.k_v=0", "time.T=0.14")
    return scene, run_fe(scene), run_coupled(scene)


def test_no_vibration_breaks_away_at_the_coulomb_force_when_the_lumped_model_does(breakaway_runs):
    scene, fe, lumped = breakaway_runs
    assert isinstance(fe, FEResult)
    F_c = scene.F_c
    t_fe, t_lumped = breakaway_time(fe.series, F_c), breakaway_time(lumped, F_c)
    assert t_fe is not None and t_lumped is not None
    # Breakaway time within 2% (the task's tolerance; measured: the same step).
    assert t_fe == pytest.approx(t_lumped, rel=0.02)
    # The force it slides at: F_d averaged from breakaway on is F_c within 1%
    # (it oscillates +-1.6% about F_c with the drive spring; measured 1e-5 from the lumped mean).
    after = fe.series.t >= t_lumped
    assert fe.series.F_d[after].mean() == pytest.approx(F_c, rel=0.01)
    # The same rows as the lumped stepper, and the same curve within 0.1% of F_c
    # (the block's compliance; measured 6e-5 N).
    assert np.array_equal(fe.series.t, lumped.t)
    assert np.abs(fe.series.F_d - lumped.F_d).max() < 1e-3 * F_c
    # Summed normal reaction = F_N within 0.5% at every step (measured 1e-9).
    assert np.abs(fe.series.extra["F_n"] - scene.contact.F_N).max() < 0.005 * scene.contact.F_N
    assert fe.info["F_n_min"] > 0.995 * scene.contact.F_N
    assert fe.info["F_n_max"] < 1.005 * scene.contact.F_N
    # The summary the CLI writes works on the FE series unchanged.
    summary = summarize(fe.series, scene, fe.info["wall_time_s"])
    assert summary["breakaway_time_s"] == pytest.approx(t_lumped, rel=0.02)


def test_run_info_and_fields(breakaway_runs):
    scene, fe, _ = breakaway_runs
    info = fe.info
    assert (info["mesh"], info["integrator"], info["dofs"], info["contact_nodes"]) == \
        ("coarse", "explicit", 720, 30)
    assert info["steps"] == scene.steps and info["dt"] == scene.time.dt
    assert scene.time.dt <= info["dt_stable"] < 1.2e-6
    assert info["wall_time_s"] >= info["loop_time_s"] > 0
    assert info["F_n_min_after_t_on"] is None  # no vibration
    # The contact patch at the end: the whole face closed, its area the face's (rounding:
    # 1e-12), the peak above the mean F_N / A (the block pitches as it slides)
    assert info["nodes_in_contact"] == 30
    assert info["contact_area"] == pytest.approx(0.03 * 0.04, rel=1e-12)
    assert info["peak_pressure"] > scene.contact.F_N / (0.03 * 0.04)
    # The friction force fields sum to the series' last row.
    force = fe.fields["friction_force"]
    assert force.sum(axis=0)[:2] == pytest.approx([fe.series.F_x[-1], fe.series.F_y[-1]],
                                                  rel=1e-12, abs=1e-12)
    contact = fe.fields["contact_nodes"]
    assert np.all(fe.fields["coordinates"][contact, 2] == pytest.approx(0.0, abs=1e-12))
    assert set(FIELDS) <= set(fe.fields)
    # the face's nodes at rest on the base: their gap is the penalty's penetration
    # (negative, ~1 nm under 55 N); closed, each slides or sticks
    gap, state = fe.fields["gap"][contact], fe.fields["contact_state"][contact]
    assert np.all(gap < 0.0) and np.all(gap > -1e-7)
    assert set(state.tolist()) <= {1.0, 2.0}


def _front_minus_back(fields):
    """Mean contact pressure on the front edge (x = L_x) minus the back edge (x = 0), Pa."""
    p, x, c = fields["contact_pressure"], fields["coordinates"][:, 0], fields["contact_nodes"]
    return p[c[np.isclose(x[c], 0.03)]].mean() - p[c[np.isclose(x[c], 0.0)]].mean()


def test_front_face_drive_tilts_the_block(comm, breakaway_runs):
    """Pulled at mid-height of the front face, the block is pressed harder at its
    front edge than at its back (the lumped model cannot show this); attached on
    the contact plane it is not. Checked just after breakaway (F_d ~ F_c): the
    moment F_c L_z / 2 over the face's section modulus L_y L_x^2 / 6 predicts a
    front-back pressure difference of 2 x 24 kPa, ~106% of the mean 46 kPa; >= 20%
    leaves room for the coarse mesh and its corner nodes. Attached on the contact
    plane, the difference is below 5%: only the block's own inertia (m a at the
    centre of mass, the drive-spring oscillation of +-0.09 N) tilts it, by ~800 Pa
    (measured 690 Pa, 1.5%)."""
    scene = load(LONGITUDINAL, "vibration.k_v=0", "time.T=0.12", 'drive.attach="front-face"')
    fe = run_fe(scene, comm)
    mean = scene.contact.F_N / (0.03 * 0.04)
    assert _front_minus_back(fe.fields) > 0.2 * mean
    assert abs(_front_minus_back(breakaway_runs[1].fields)) < 0.05 * mean
    # ... while the summed reaction stays F_N within 0.5%.
    assert np.abs(fe.series.extra["F_n"] - scene.contact.F_N).max() < 0.005 * scene.contact.F_N
    assert fe.info["attach_nodes"] == 6 * 8  # the front face's nodes


def _frames(pvd: Path):
    """(time, [.vtu paths]) of each frame of a .pvd."""
    return [(float(entry.get("timestep")), [pvd.parent / entry.get("file")])
            for entry in ET.parse(pvd).getroot().iter("DataSet")]


def test_paraview_series_reads_back_in_meshio_and_pyvista(tmp_path, comm):
    meshio = pytest.importorskip("meshio")
    pyvista = pytest.importorskip("pyvista")
    scene = load(LONGITUDINAL, *SHORT, "vibration.theta_deg=30", "fem.output_every=500")
    fe = run_fe(scene, comm, vtk_dir=tmp_path)
    pvd = tmp_path / "block.pvd"
    assert fe.info["vtk"] == str(pvd) and fe.info["frames"] == 6
    frames = _frames(pvd)
    assert [t for t, _ in frames] == pytest.approx([0.0, 5e-4, 1e-3, 1.5e-3, 2e-3, 2.5e-3])

    reader = pyvista.get_reader(str(pvd))
    assert reader.time_values == pytest.approx([t for t, _ in frames])
    A = 0.03 * 0.04
    for k, (t, pieces) in enumerate(frames):
        assert len(pieces) == 1
        by_meshio = meshio.read(pieces[0])
        reader.set_active_time_value(t)
        grid = reader.read()[0]
        assert grid.n_points == by_meshio.points.shape[0] == 240
        for data in (by_meshio.point_data, grid.point_data):
            for name in FIELDS:
                values = np.asarray(data[name])
                assert values.shape[0] == 240 and np.all(np.isfinite(values)), name
            z = np.asarray(by_meshio.points)[:, 2]
            on_face = np.abs(z) < 1e-12
            pressure = np.asarray(data["contact_pressure"]).ravel()
            assert np.all(pressure[~on_face] == 0)
            # Mean contact pressure ~ F_N / A (within 5%: the corner nodes' tributary areas differ).
            assert pressure[on_face].mean() == pytest.approx(scene.contact.F_N / A, rel=0.05)
            # friction_force summed over the face = the series' F_x, F_y at that step.
            # The frames are binary (exact); 1e-9 of F_c: the sum's rounding is far below.
            total = np.asarray(data["friction_force"]).sum(axis=0)
            if t > 0:
                row = np.flatnonzero(np.isclose(fe.series.t, t, rtol=0, atol=1e-9))
                assert row.size == 1
                assert total[0] == pytest.approx(fe.series.F_x[row[0]], abs=1e-9 * scene.F_c)
                assert total[1] == pytest.approx(fe.series.F_y[row[0]], abs=1e-9 * scene.F_c)
            else:
                assert np.all(total == 0)
        if t == frames[-1][0]:
            assert np.abs(total[:2]).max() > 0.1 * scene.F_c  # a real friction force was written


# --- refusals and numerical trouble --------------------------------------------------------

def test_dt_above_the_stable_step_is_refused_with_the_limit(tmp_path, comm):
    scene = load(LONGITUDINAL, "time.dt=1.5e-6", "fem.output_every=10", *SHORT)
    with pytest.raises(StepTooLong) as error:
        run_fe(scene, comm, vtk_dir=tmp_path / "out")
    assert REFUSAL_KEYS[type(error.value)] == "time.dt"
    limit = float(re.search(r"stable step ([0-9.e+-]+) s", str(error.value)).group(1))
    assert 1.0e-6 < limit < 1.1e-6  # coarse mesh, 0.5 kg block: measured 1.046e-6 s
    assert not (tmp_path / "out").exists()  # refused before any output


@pytest.mark.parametrize("overrides, key", [
    (['fem.mesh="huge"'], "fem.mesh"),
    (['fem.integrator="leapfrog"'], "fem.integrator"),
    (["contact.F_N=2.0"], "contact.F_N"),                         # below the block's weight
    (['drive.attach="front-face"', "contact.mu=0.6"], "drive.attach"),  # tips the block over
])
def test_scenes_the_model_cannot_run_are_refused_naming_the_key(overrides, key, refused_key, comm):
    assert refused_key(lambda: run_fe(load(LONGITUDINAL, *SHORT, *overrides), comm)) == key


@pytest.mark.parametrize("integrator, dt", [("explicit", 1e-6), ("implicit", 1e-5)])
def test_progress_reports_leave_the_results_bit_identical(integrator, dt, comm):
    """With a progress callback the compiled loop returns to Python every
    recording.PROGRESS_STEPS steps; the loops keep their whole state in arrays,
    so the results must not change by a bit. The reports rise to time.T."""
    scene = load(LONGITUDINAL, "vibration.t_on=0.005", "time.T=0.012", "time.average_cycles=2",
                 "fem.output_every=0", f"fem.integrator={integrator!r}", f"time.dt={dt!r}",
                 'time.method="transient"')
    reports = []
    quiet = run_fe(scene, comm)
    reported = run_fe(scene, comm, progress=lambda done, total: reports.append((done, total)))
    assert np.array_equal(quiet.series.table(), reported.series.table())
    done = [d for d, _ in reports]
    assert len(reports) >= scene.steps // recording.PROGRESS_STEPS and done == sorted(done)
    assert done[-1] == pytest.approx(scene.time.T) and {t for _, t in reports} == {scene.time.T}


def test_a_parallel_communicator_is_refused():
    class TwoProcesses:
        size = 2
    with pytest.raises(ValueError, match="serial"):
        run_fe(load(LONGITUDINAL, *SHORT), TwoProcesses())


def test_nan_is_raised_as_numerical_error_with_the_time(comm, monkeypatch):
    real = fe_model.build_model

    def poisoned(scene, comm):
        model = real(scene, comm)
        model.load[3 * model.contact_nodes[0] + 2] = np.nan
        return model

    monkeypatch.setattr(fem_simulate, "build_model", poisoned)
    with pytest.raises(NumericalError, match=r"t = 1e-06 s \(step 1.*NaN"):
        run_fe(load(LONGITUDINAL, *SHORT), comm)


def test_a_swinging_normal_force_is_refused_as_ringing(comm, monkeypatch):
    """The check on the averaging window: with a tolerance tighter than this
    short run's +-0.06% swing, and a demand for a forced response above its
    measured 97% at harmonics of f, the run must be refused."""
    monkeypatch.setattr(normal_swing, "STEADY_NORMAL", 1e-5)
    monkeypatch.setattr(normal_swing, "FORCED_FRACTION", 0.999)
    with pytest.raises(NumericalError, match="ringing"):
        run_fe(load(LONGITUDINAL, *SHORT), comm)


def test_the_forced_fraction_tells_a_forced_swing_from_a_free_one():
    """Over 8 cycles of f = 4 kHz at dt = 1e-6: harmonics of f are forced (1 to
    rounding), a mode at 10.7 kHz (the block rocking on its contact) is not (0 but
    for the leakage of a tone between harmonics over 8 cycles: 1.8%), and their mix
    in between."""
    t = np.arange(2000) * 1e-6
    forced = np.sin(2 * np.pi * 4000 * t) + 0.3 * np.cos(2 * np.pi * 12000 * t)
    free = np.sin(2 * np.pi * 10700 * t)
    assert normal_swing.forced_fraction(forced, 1e-6, 4000.0) == pytest.approx(1.0, abs=1e-12)
    assert normal_swing.forced_fraction(free, 1e-6, 4000.0) < 0.05
    mixed = normal_swing.forced_fraction(forced + free, 1e-6, 4000.0)
    assert 0.3 < mixed < 0.7


def test_the_normal_swing_is_steady_rocking_transient_or_ringing():
    """40 cycles of f = 4 kHz at dt = 1e-6 s around F_N = 55 N: a forced swing of
    0.5% is steady and one of 2% rocking; a free 10.7 kHz vibration of 3% on top
    that decays (time constant 1.5 ms: 0.02% by the window's last 10 cycles) is a
    transient, reported with its frequency (to the window's resolution, 100 Hz);
    the same vibration undecayed is ringing, refused."""
    F_N, dt, f = 55.0, 1e-6, 4000.0
    t = np.arange(10000) * dt
    forced = np.sin(2 * np.pi * f * t) + 0.3 * np.cos(2 * np.pi * 3 * f * t)
    free = np.sin(2 * np.pi * 10700 * t)
    assert normal_swing.judge(F_N * (1 + 0.005 * forced / 1.3), dt, f, F_N, 1e-8).kind == "steady"
    assert normal_swing.judge(F_N * (1 + 0.02 * forced / 1.3), dt, f, F_N, 1e-8).kind == "rocking"
    decaying = F_N * (1 + 0.005 * forced / 1.3 + 0.03 * np.exp(-t / 1.5e-3) * free)
    swing = normal_swing.judge(decaying, dt, f, F_N, 1e-8)
    assert swing.kind == "transient"
    assert swing.free_frequency_hz == pytest.approx(10700, abs=100)
    with pytest.raises(NumericalError, match="ringing"):
        normal_swing.judge(F_N * (1 + 0.005 * forced / 1.3 + 0.03 * free), dt, f, F_N, 1e-8)


@pytest.mark.slow
def test_a_stiff_contacts_free_vibration_is_a_transient_the_same_in_dt(comm, tmp_path):
    """Transverse scene at k_t x 100, vibrated 2 ms after the start: the base's
    start sets the block vibrating freely on its stiff contact (11 kHz, decaying
    over ~5 ms) into the averaging window, which ends rocking at harmonics of f.
    Physics, not ringing: kept, reported as a transient (and unsettled), the same
    at dt = 1e-6 and 5e-7 s: the free line to the window's resolution (2 bins
    of 1 / 15 ms; measured equal, 11.0 kHz), the swing's extremes within 0.1% of F_N
    (measured 0.036%, the two steps' discretization error; 3x that as margin)."""
    swings = []
    for dt in (1e-6, 5e-7):
        scene = load(TRANSVERSE, "contact.k_t=6.729e9", "vibration.t_on=0.002", "time.T=0.02",
                     "time.average_cycles=45", f"time.dt={dt}", 'time.method="transient"')
        if dt == 1e-6:      # as vibrofric run reports it: unsettled, saying why
            done = fe_beside_analytic(scene, tmp_path, comm)
            fe, summary = done.fe, done.document["fe"]
            assert summary["normal_force"] == "transient" and not summary["settled"]
            assert "free vibration" in unsettled_warning(summary, "FE")
        else:
            fe = run_fe(scene, comm)
        assert fe.info["F_n_kind"] == "transient"
        assert fe.info["F_n_forced_fraction_end"] >= normal_swing.FORCED_FRACTION
        swings.append(fe.info)
    resolution = 1 / 0.015
    assert swings[0]["F_n_free_frequency_hz"] == pytest.approx(swings[1]["F_n_free_frequency_hz"],
                                                               abs=2 * resolution)
    for key in ("F_n_min_window", "F_n_max_window", "F_n_min_window_end", "F_n_max_window_end"):
        assert swings[0][key] == pytest.approx(swings[1][key], abs=1e-3 * scene.contact.F_N)


def test_a_block_rocking_on_a_stiff_contact_runs_and_reports_its_swing(comm):
    """k_t x 100 (8e9 N/m, above the block's own shear stiffness ~1.8e9 N/m): the
    friction rocks the block and the summed normal force swings by ~2% of F_N,
    a forced response at harmonics of f once the start's transient has rung out
    (measured 99.8% over 10 ms of vibration; 2.9% over the first 2 ms), the
    same at dt = 1e-6 and 5e-7 s: physics, reported in info, not refused as ringing."""
    scene = load(LONGITUDINAL, "vibration.t_on=0.002", "time.T=0.012", "time.average_cycles=8",
                 "contact.k_t=8e9")
    fe = run_fe(scene, comm)
    info = fe.info
    swing = max(scene.contact.F_N - info["F_n_min_window"], info["F_n_max_window"] - scene.contact.F_N)
    assert swing > normal_swing.STEADY_NORMAL * scene.contact.F_N
    assert info["F_n_forced_fraction"] > 0.99
    assert info["F_n_kind"] == "rocking"


# --- the paper's cases to a steady cycle (slow) ----------------------------------------------

def _compare(path, *overrides):
    scene = load(path, "time.T=0.3", *overrides)
    fe = run_fe(scene)
    fe_ratio = summarize(fe.series, scene, 0.0)["F_dv_over_F_d0"]
    lumped_ratio = summarize(run_coupled(scene), scene, 0.0)["F_dv_over_F_d0"]
    error = fe_ratio / lumped_ratio - 1
    print(f"\n{path.stem} {overrides}: FE {fe_ratio:.5f}, lumped {lumped_ratio:.5f}, "
          f"error {100 * error:+.2f}%, F_n window {fe.info['F_n_min_window']:.4f}.."
          f"{fe.info['F_n_max_window']:.4f} N, {fe.info['steps']} steps in "
          f"{fe.info['wall_time_s']:.1f} s")
    return scene, fe, error


@pytest.mark.slow
@pytest.mark.parametrize("path", [LONGITUDINAL, TRANSVERSE])
def test_paper_cases_match_the_lumped_model_within_3_percent(path):
    """F_dv / F_d0 at T = 0.3 s (the lumped value is within 0.1% of its 1 s value
    by then). 3% is the task's tolerance; measured +2.8% (longitudinal k_v = 6)
    and +1.1% (transverse k_v = 20), most of it the block's compliance (next test)."""
    scene, fe, error = _compare(path)
    assert abs(error) < 0.03
    # The normal force is steady over the averaging window: within 0.5% of F_N
    # (measured 0.1% and 0.35%), not the ringing of the spec's trap (+-20%).
    F_N = scene.contact.F_N
    assert fe.info["F_n_min_window"] > 0.995 * F_N and fe.info["F_n_max_window"] < 1.005 * F_N


@pytest.mark.slow
@pytest.mark.parametrize("path, dt", [(LONGITUDINAL, "1e-7"), (TRANSVERSE, "2e-7")])
def test_a_100x_stiffer_block_comes_closer_to_the_lumped_model(path, dt):
    """With E (and so the default penalty) 100x larger the block is nearly rigid:
    what remains of the difference is not its compliance. Measured: +0.6%
    (longitudinal), -0.7% (transverse), against +2.8% and +1.1% at steel's E.
    1% bounds what the per-node contact (pressure 0.5% non-uniform) may leave.
    The stable step shrinks 10x with E: about 80 s and 60 s."""
    scene, fe, error = _compare(path, "body.E=209e11", f"time.dt={dt}")
    assert abs(error) < 0.01
