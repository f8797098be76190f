"""The FE integrators: implicit (generalized-alpha), reduced (Craig-Bampton), auto,
early steady state and the energy balance (vibrofric.fem, issue 4).

Fast tests use the "coarse" mesh (720 DOFs) and runs of a few milliseconds;
the paper's scenes to a steady cycle are marked slow. The reference for the
integrators is the explicit central-difference baseline at dt = 1e-6 s.
"""

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp
from numba import njit

pytest.importorskip("dolfinx")

from vibrofric import scene as scenes  # noqa: E402
from vibrofric.analytic import run_coupled, summarize  # noqa: E402
from vibrofric.core.errors import NumericalError  # noqa: E402
from vibrofric.core.series import RecordPlan  # noqa: E402
from vibrofric.fem import run_fe  # noqa: E402
from vibrofric.fem.integrators import registry  # noqa: E402
from vibrofric.fem.model import fe_model  # noqa: E402
from vibrofric.fem.model.linalg import apply, bsr, columns_of_inverse, factorize, inverse, solve  # noqa: E402
from vibrofric.fem.model.drive import START_TIME, prescribed_position  # noqa: E402
from vibrofric.fem.outputs.recording import ENERGY, Recorder, keep  # noqa: E402
from vibrofric.fem.integrators.reduction import Reduction, compliance_error  # noqa: E402
from vibrofric.fem.outputs.steady import SteadyState, settled  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
LONGITUDINAL = ROOT / "scenes" / "longitudinal.toml"
TRANSVERSE = ROOT / "scenes" / "transverse.toml"

# A short vibrated run: vibration from 0.5 ms, 4.5 ms of it (18 cycles at 4 kHz).
SHORT = ["vibration.t_on=0.0005", "time.T=0.005", "time.average_cycles=4", "fem.output_every=0"]


def load(path, *overrides):
    """The scene stepped through time.T (time.method transient): these tests compare the
    integrators' time loops (their steady cycles: test_fe_periodic.py)."""
    return scenes.load(path, ['time.method="transient"', *overrides])


def ratio(fe, scene):
    return summarize(fe.series, scene, 0.0)["F_dv_over_F_d0"]


@pytest.fixture(scope="module")
def comm():
    from mpi4py import MPI
    return MPI.COMM_SELF


# --- linear algebra in the loops -----------------------------------------------------------

@njit
def _apply(op, x, out):
    apply(op, x, out)


def test_products_and_solves_match_scipy():
    """Every operator type the loops take against scipy/numpy: rounding only (1e-12)."""
    rng = np.random.default_rng(0)
    n = 30
    blocks = sp.random(n // 3, n // 3, 0.3, random_state=1)
    K = sp.kron(blocks + blocks.T + 5 * sp.eye(n // 3), np.ones((3, 3)) + 3 * np.eye(3)).tocsr()
    x, out = rng.standard_normal(n), np.empty(n)
    for op, reference in ((bsr(K), K @ x), (K.toarray(), K @ x), (np.arange(1.0, n + 1), np.arange(1.0, n + 1) * x)):
        _apply(op, x, out)
        assert np.allclose(out, reference, rtol=1e-12, atol=1e-12)
    for inv in (factorize(K), inverse(K)):
        solve(inv, x, out)
        assert np.abs(K @ out - x).max() < 1e-12 * np.abs(x).max()
        dofs = np.array([0, 4, 17, 29])
        assert np.allclose(columns_of_inverse(inv, dofs), np.linalg.inv(K.toarray())[np.ix_(dofs, dofs)],
                           rtol=1e-10, atol=1e-14)


def test_nested_dissection_orders_a_grid_for_less_fill(comm):
    """On the medium mesh's K (plus springs on every DOF): the order is a permutation,
    the LU solves backward stably and like the minimum-degree one (1e-10: rounding
    through the matrix's condition), in the numba solve too, and it fills less than
    the minimum degree (1.9 M against 2.6 M entries)."""
    from vibrofric.fem.model.linalg import dof_points, nested_dissection, symmetric_lu

    model = fe_model.build_model(load(LONGITUDINAL, "fem.mesh=medium"), comm)
    A = (model.stiffness + sp.diags(np.r_[np.full(model.dofs - 1, 1e7), 1e7])).tocsc()
    points = dof_points(model.disc.coordinates)
    order = nested_dissection(points)
    assert np.array_equal(np.sort(order), np.arange(model.dofs))
    b = np.random.default_rng(2).standard_normal(model.dofs)
    ordered, plain = symmetric_lu(A, order), symmetric_lu(A)
    x = ordered.solve(b)
    assert np.abs(A @ x - b).max() < 1e-12 * abs(A).max() * np.abs(x).max()  # backward stable
    assert np.allclose(x, plain.solve(b), rtol=1e-10, atol=1e-10 * np.abs(x).max())
    out = np.empty(model.dofs)
    solve(factorize(A, order), b, out)
    assert np.allclose(out, x, rtol=1e-10, atol=1e-10 * np.abs(x).max())
    assert ordered.L.nnz + ordered.U.nnz < 0.8 * (plain.L.nnz + plain.U.nnz)


# --- recording and early steady state --------------------------------------------------------

@pytest.mark.parametrize("last", [1000, 537, 80])
def test_recorder_returns_the_plans_rows_wherever_the_run_ends(last):
    """Stopping at ``last`` must give exactly RecordPlan(last, stride, last - full + 1)'s
    rows, and the nodes' normal forces of every 3rd step of any window of its last
    ``full`` steps."""
    plan = RecordPlan(1000, 10, 901)
    normal = np.zeros(2)
    recorder = Recorder(plan, 1, normal, stride=3)
    arrays = recorder.arrays
    for i in range(1, last + 1):
        arrays[0][0] = i
        normal[:] = i, -i
        keep(i, arrays)
    expected = RecordPlan(last, 10, max(1, last - 99))
    steps = [i for i in range(1, last + 1) if i >= expected.full_from or i % 10 == 0]
    assert recorder.table(last)[:, 0].tolist() == steps
    assert len(steps) == expected.rows
    for window in (1, 7, min(last, recorder.full)):
        kept = [i for i in range(last - window + 1, last + 1) if i % 3 == 0]
        assert recorder.node_normals(last, window).tolist() == [[i, -i] for i in kept]


def test_steady_state_stops_at_the_first_settled_cycle_boundary():
    """A drive force settling as 1 + 0.5 exp(-t / 20 ms) with a 4 kHz ripple of +-1
    (whole cycles average it out), fed step by step from vibration.t_on: the
    detector must stop at exactly the first cycle boundary where the window
    mean (the last averaging_steps steps) differs by at most the tolerance from
    each of the previous steady_cycles boundaries' means, computed here
    directly; about 0.107 s after t_on for 1e-3 over 20 cycles (the window's
    change 0.5 e^{-t/tau} (tau / W)(e^{W/tau} - 1)(e^{20 / (f tau)} - 1) = 1e-3).
    With tolerance 0 it never stops."""
    scene = load(LONGITUDINAL, "vibration.t_on=0.05", "time.T=0.3", "time.dt=1e-5",
                 "time.steady_tolerance=1e-3", "time.steady_cycles=20")
    steady = SteadyState(scene)
    arrays = steady.arrays
    dt, f, on = scene.time.dt, scene.vibration.f, steady.first
    t = np.arange(scene.steps + 1) * dt - scene.vibration.t_on
    force = 1.0 + 0.5 * np.exp(-t / 0.02) + np.sin(2 * np.pi * f * t)
    stop = next(i for i in range(1, scene.steps + 1) if settled(i, force[i], arrays))

    W, m, per_cycle = steady.window, scene.time.steady_cycles, 1 / (f * dt)
    boundaries = [on + int(round(k * per_cycle)) for k in range(int(scene.steps / per_cycle))]
    boundaries = [b for b in boundaries if b - on + 1 >= W and b <= scene.steps]
    means = [force[b - W + 1:b + 1].mean() for b in boundaries]
    expected = next(b for k, b in enumerate(boundaries) if k >= m and
                    max(abs(means[k] - means[k - j]) for j in range(1, m + 1)) <= 1e-3 * abs(means[k]))
    assert stop == expected
    assert (stop - on) * dt == pytest.approx(0.107, abs=0.002)
    assert steady.report(stop)["stopped_early"]
    never = SteadyState(load(LONGITUDINAL, "time.dt=1e-5"))
    assert not any(settled(i, 1.0, never.arrays) for i in range(1, 100001))


@pytest.fixture(scope="module")
def early_stop():
    """The Fig 7 scene to 0.3 s (reduced, dt = 1e-5), stopped once settled to 3e-3 over 20
    cycles (a loose setting, to stop within 0.3 s)."""
    scene = load(LONGITUDINAL, "time.T=0.3", "time.dt=1e-5", 'fem.integrator="reduced"',
                 "fem.output_every=0", "time.steady_tolerance=3e-3", "time.steady_cycles=20")
    return scene, run_fe(scene)


def test_an_early_stop_ends_the_series_where_it_stopped(early_stop):
    """The stopped run's series is the series of the same run with time.T at the stop,
    bit for bit: the rows, their times and the F_dv summarize() takes from them."""
    scene, fe = early_stop
    info = fe.info
    assert info["stopped_early"] and info["steps"] < info["steps_planned"]
    assert info["stop_time_s"] == pytest.approx(fe.series.t[-1], rel=1e-12)
    assert info["saving"] == pytest.approx(1 - info["steps"] / info["steps_planned"], rel=1e-12)
    assert info["steady_change"] <= scene.time.steady_tolerance
    whole = run_fe(scene.with_values({"time.T": info["stop_time_s"], "time.steady_tolerance": 0.0}))
    assert not whole.info["stopped_early"]
    assert np.array_equal(whole.series.table(), fe.series.table())


def test_the_settled_average_is_the_steady_one(early_stop):
    """F_dv from the settled window against the whole 0.3 s run. The tolerance
    bounds the window mean's change over the last 20 cycles (5 ms), not what is
    left of the transient after it (it decays over ~50 ms after t_on): measured
    stop at 0.262 s (12.7% saved), +0.8% (with 1e-3: 0.281 s, +0.2%; 1e-3 over
    40 cycles: 0.2955 s, +0.03%). 1% bounds it."""
    scene, fe = early_stop
    full = run_fe(scene.with_values({"time.steady_tolerance": 0.0}))
    assert not full.info["stopped_early"]
    assert ratio(fe, scene) == pytest.approx(ratio(full, scene), rel=0.01)


# --- the implicit and reduced integrators against the explicit baseline -----------------------

@pytest.fixture(scope="module")
def short_runs():
    """The short vibrated run with every integrator (explicit and the 1e-6 s runs are the
    references; 1e-5 s is the paper's Abaqus step)."""
    runs = {}
    for name, dt in (("explicit", "1e-6"), ("implicit", "1e-6"), ("implicit", "1e-5"),
                     ("reduced", "1e-6"), ("reduced", "1e-5")):
        scene = load(LONGITUDINAL, *SHORT, f'fem.integrator="{name}"', f"time.dt={dt}")
        runs[name, dt] = scene, run_fe(scene)
    return runs


def _on_common_times(a, b):
    ta, tb = np.round(a.series.t, 9), np.round(b.series.t, 9)
    common = np.intersect1d(ta, tb)
    return np.isin(ta, common), np.isin(tb, common)


@pytest.mark.parametrize("name", ["implicit", "reduced"])
def test_at_the_explicit_step_the_integrators_reproduce_the_explicit_run(short_runs, name):
    """At dt = 1e-6 s every step's friction force within 1% of F_c (measured 0.43%:
    explicit lags the friction force by one step, the implicit schemes do not) and
    F_dv within 0.1% (measured 1e-4 implicit, 1e-5 reduced): the same model."""
    scene, reference = short_runs["explicit", "1e-6"]
    fe_scene, fe = short_runs[name, "1e-6"]
    a, b = _on_common_times(reference, fe)
    assert np.abs(reference.series.F_x[a] - fe.series.F_x[b]).max() < 0.01 * scene.F_c
    assert ratio(fe, fe_scene) == pytest.approx(ratio(reference, scene), rel=1e-3)
    assert fe.info["integrator"] == name and fe.info["iterations_max"] <= 5


def test_before_the_base_moves_fewer_friction_substeps_give_the_same_run(monkeypatch):
    """Before t_on the friction law runs on enough sub-steps for the drive's slide
    (2 on the Fig 7 scene at 1e-5 s, against the vibration's 11): the exact Dahl
    update composes over a steady slide, so the drive force matches the run with
    11 sub-steps on every step. Measured on this run (tiny mesh, breakaway
    included): 1.4e-11 of the largest drive force; 1e-10 allows for the normal
    force's variation within a step, which the sub-steps sample, on other
    builds' rounding."""
    from vibrofric.fem.integrators import contact_solve, implicit
    scene = load(LONGITUDINAL, "fem.mesh=tiny", "fem.integrator=reduced", "time.dt=1e-5",
                 "vibration.t_on=0.02", "time.T=0.025", "time.average_cycles=4",
                 "fem.output_every=0")
    assert contact_solve.still_substeps(scene) == 2
    assert contact_solve.implicit_substeps(scene) == 11
    fewer = run_fe(scene).series.F_d
    monkeypatch.setattr(implicit, "still_substeps", contact_solve.implicit_substeps)
    every = run_fe(scene).series.F_d
    assert not np.array_equal(fewer, every)     # the sub-steps did change
    assert np.abs(fewer - every).max() < 1e-10 * np.abs(every).max()


@pytest.mark.parametrize("name", ["implicit", "reduced"])
def test_at_the_abaqus_step_the_integrators_stay_within_one_percent(short_runs, name):
    """At dt = 1e-5 s (25 steps a cycle), 10x the explicit step: F_dv within 1.5% of
    the explicit run (measured +1.07% implicit, +1.11% reduced on this 18-cycle
    transient; +0.15% at 5e-6 s, and the explicit run within 3e-4 of its own at
    5e-7 s). The contract's normal-force rule returns each node to its Coulomb
    limit as its normal force drops, and the nodes' normal forces swing by up to
    +-67% a cycle: 25 steps sample that less well than the old rule (keep: +0.5%
    at 1e-5 s). The summed normal force as steady as the explicit run's (+-0.2%)."""
    scene, reference = short_runs["explicit", "1e-6"]
    fe_scene, fe = short_runs[name, "1e-5"]
    assert ratio(fe, fe_scene) == pytest.approx(ratio(reference, scene), rel=0.015)
    # 11: each sub-step's fastest slip (v_a + v_d) at most 0.05 s_c (slip_resolving_step)
    assert fe.info["friction_substeps"] == 11
    F_N = scene.contact.F_N
    assert abs(fe.info["F_n_min_window"] - F_N) < 0.002 * F_N
    assert abs(fe.info["F_n_max_window"] - F_N) < 0.002 * F_N


def test_the_reduced_model_is_small_and_says_what_it_kept(short_runs):
    info = short_runs["reduced", "1e-5"][1].info
    # 30 contact nodes x 3 DOFs, the fixed-interface modes below 12 x 4 kHz:
    # 7.6, 9.0, 13.3, 24.7, 26.3, 27.1 ... kHz on the coarse mesh (measured 8).
    assert info["reduced_size"] == 90 + info["kept_modes"]
    assert 4 <= info["kept_modes"] <= 12
    assert info["kept_modes_hz"][0] == pytest.approx(7.62e3, rel=0.01)
    assert max(info["kept_modes_hz"]) < info["cutoff_hz"] == 48e3
    assert 0 < info["reduction_error_estimate"] < 0.01


def test_reduced_frames_show_the_whole_block(tmp_path, comm):
    """The reduced run's ParaView frames and end fields expand its coordinates to every
    node: a frame at t = 0, every fem.output_every steps and at the early stop;
    the friction force field sums to the series' last row (rounding), and the
    top of the block has moved with the face: within twice the block's shear
    under the Coulomb force, F_c L_z / (G A) = 3e-9 m (measured 4e-9 m, 1.2% of
    the 3.3e-7 m it moved), a rigid-body offset would be off by far more."""
    scene = load(LONGITUDINAL, *SHORT, 'fem.integrator="reduced"', "time.dt=1e-5",
                 "fem.output_every=100")
    fe = run_fe(scene, comm, vtk_dir=tmp_path)
    assert fe.info["frames"] == 6 and (tmp_path / "block.pvd").exists()
    total = fe.fields["friction_force"].sum(axis=0)
    assert total[:2] == pytest.approx([fe.series.F_x[-1], fe.series.F_y[-1]], rel=1e-12, abs=1e-12)
    coordinates, u = fe.fields["coordinates"], fe.fields["displacement"]
    model = fe_model.build_model(scene, comm)
    moved = (u - model.u0.reshape(-1, 3))[:, 0]
    top = np.isclose(coordinates[:, 2], scene.body.size[2])
    Lx, Ly, Lz = scene.body.size
    shear = scene.F_c * Lz / (scene.body.E / (2 * (1 + scene.body.nu)) * Lx * Ly)
    assert abs(moved[top].mean() - fe.series.x[-1]) < 2 * shear


# --- the reduction ---------------------------------------------------------------------------

def test_craig_bampton_is_statically_exact_and_converges_with_the_cutoff(comm):
    """Constraint modes make the reduction exact for loads on the face (rounding:
    1e-10); the dynamic compliance error at the excitation's harmonics falls as
    more fixed-interface modes are kept (measured at 3 f: 28%, 15%, 0.8%, 0.1%
    for cutoffs 0, 5, 12, 20 f: the 12 kHz third harmonic sits between the
    block's rocking modes on its contact, 10.7 and 12.7 kHz)."""
    scene = load(LONGITUDINAL)
    model = fe_model.build_model(scene, comm)
    errors = []
    for cutoff in (0.0, 5.0, 12.0, 20.0):
        reduction = Reduction(model, cutoff * scene.vibration.f)
        errors.append(compliance_error(model, reduction, scene)["max"])
        if cutoff == 0.0:  # Guyan: statics only
            springs = np.zeros(model.dofs)
            face = reduction.boundary
            springs[face] = 1e9
            load_ = np.zeros(model.dofs)
            load_[face[0::3]] = model.area_share
            full = np.linalg.solve((model.stiffness + sp.diags(springs)).toarray(), load_)
            red = np.linalg.solve(reduction.stiffness + np.diag(springs[face]), load_[face])
            assert np.abs(red - full[face]).max() < 1e-10 * np.abs(full[face]).max()
    assert errors[0] > errors[1] > errors[2] > errors[3]
    assert errors[2] < 0.01


def test_a_sweep_reuses_the_reduction_of_the_same_block_only(comm):
    """The reduction a process keeps is reused for the same model and cutoff (a
    sweep's points), made again for another cutoff or another block, and the
    kept full compliances give the error the uncached computation gives, bit
    for bit."""
    from vibrofric.fem.integrators.reduction import forget, reduced
    scene = load(LONGITUDINAL)
    cutoff = scene.fem.cutoff * scene.vibration.f
    forget()
    model = fe_model.build_model(scene, comm)
    first = reduced(model, cutoff)
    assert reduced(fe_model.build_model(scene, comm), cutoff) is first   # rebuilt, same block
    assert reduced(model, 2 * cutoff) is not first
    softer = fe_model.build_model(load(LONGITUDINAL, "body.E=1e11"), comm)
    assert reduced(softer, cutoff) is not reduced(model, cutoff)
    forget()
    fresh = compliance_error(model, Reduction(model, cutoff), scene)
    forget()
    kept = reduced(model, cutoff)
    compliance_error(model, kept, scene)                 # fills the kept compliances
    again = compliance_error(model, reduced(model, cutoff), scene)
    assert again == fresh
    forget()


def test_the_reduction_estimate_sees_a_stiff_contact_lift_the_rocking_modes(comm):
    """k_t x 100 on the Fig 7 scene: the rocking modes on the contact rise above 3 f
    and the friction's spectrum reaches far above it, so the compliance is compared
    up to 8 f. There the default cutoff (12 f) errs by 5.2% at 5-6 f (measured; its
    run's F_dv was 10% below the implicit one) and 24 f by 0.2%: auto takes the
    reduced model only with the larger cutoff."""
    from vibrofric.fem.integrators.reduction import MAX_HARMONICS, compared_harmonics
    scene = load(LONGITUDINAL, "contact.k_t=8e9")
    assert list(compared_harmonics(scene)) == list(range(1, MAX_HARMONICS + 1))
    assert list(compared_harmonics(load(LONGITUDINAL))) == [1, 2, 3]   # the paper's k_t
    model = fe_model.build_model(scene, comm)
    default, doubled = (compliance_error(model, Reduction(model, cutoff * scene.vibration.f),
                                         scene)["max"] for cutoff in (12.0, 24.0))
    assert default > scene.fem.accuracy > doubled


@pytest.mark.parametrize("body", ["block", "ball"])
def test_the_full_compliance_from_one_real_factorization_is_the_complex_lu_s(body, comm):
    """The full model's compliances for the estimate (FullCompliance: one real
    factorization of K + L + s M and the Krylov space it generates) against the complex
    LU at each compared harmonic (direct_compliance), on the Fig 7 block and on the coarse
    ball with every candidate kept (its estimate, 0.41%, against 1.5e-5 on its default
    interface: the cases of reduction.py's docstring). The space settles each compliance
    to 1e-10 of itself and the Galerkin error is second order: they agree to 1e-9 of
    the static compliance c(0) (measured 1e-13 and 5e-13), which moves an estimate of
    1e-5 of c(0) or more by 1e-4 of itself at most, far inside the 1% decision it serves.
    The space stays small: 14 and 18 vectors (measured), bound 60."""
    from vibrofric.fem.integrators.reduction import (FullCompliance, compared_harmonics,
                                                     direct_compliance)
    scene = load(LONGITUDINAL) if body == "block" else \
        scenes.load(ROOT / "scenes" / "ball.toml").with_values({"fem.interface_reach": "all"})
    model = fe_model.build_model(scene, comm if body == "block" else None)
    reduction = Reduction(model, scene.fem.cutoff * scene.vibration.f)
    k_t = scene.law_bounds.stiffness
    omegas = [2 * math.pi * h * scene.vibration.f for h in compared_harmonics(scene)]
    solver = FullCompliance(model, reduction.boundary, k_t, omegas)
    assert solver.settled and solver.size <= 60
    static = np.abs(direct_compliance(model, reduction.boundary, k_t, 0.0))
    for omega in omegas:
        exact = direct_compliance(model, reduction.boundary, k_t, omega)
        assert np.all(np.abs(solver.at(omega) - exact) < 1e-9 * static)


# --- energy ----------------------------------------------------------------------------------

@pytest.mark.parametrize("mode", ["spring", "velocity"])
@pytest.mark.parametrize("name", ["implicit", "reduced"])
def test_the_energy_balance_closes_and_dissipation_never_decreases(name, mode):
    """W_drive + W_base = E_kin + E_el + D_fric + D_damp with the trapezoidal rule
    (fem.rho_infinity = 1). What is left is the contact iteration's tolerance and
    the steps where a node lifts off or touches down (the penalty force's kink):
    measured 1.1e-7 (implicit) and 1.0e-7 (reduced) of the work put in over 10
    ms at dt = 1e-5 with the drive spring. A prescribed drive starts the block at
    v_d in one step: a node lifts off in that shear at 0.18 ms, which costs
    4.2e-10 J, 1.03e-5 of the (smaller) work put in. 2e-5 bounds both. The
    dissipations are non-negative step by step (1e-15 of the total allows
    rounding: steps of -7e-24 J were seen)."""
    scene = load(LONGITUDINAL, "vibration.t_on=0.002", "time.T=0.01", "time.average_cycles=4",
                 "fem.output_every=0", "fem.energy=true", "time.series_dt=1e-5", "time.dt=1e-5",
                 f'fem.integrator="{name}"', "fem.rho_infinity=1.0", f'drive.mode="{mode}"')
    e = run_fe(scene).series.extra
    put_in = e["W_drive"] + e["W_base"]
    stored_and_lost = e["E_kin"] + e["E_el"] + e["D_fric"] + e["D_damp"]
    assert np.abs(put_in - stored_and_lost).max() < 2e-5 * np.abs(put_in).max()
    for key in ("D_fric", "D_damp"):
        assert np.diff(e[key]).min() >= -1e-15 * e[key][-1]
    assert e["D_fric"][-1] > 0.9 * e["W_base"][-1] > 0   # the base's work is lost in friction
    assert set(ENERGY) <= set(e)


@pytest.mark.parametrize("path", [LONGITUDINAL, TRANSVERSE])
@pytest.mark.parametrize("name, dt", [("explicit", 1e-6), ("reduced", 1e-5)])
def test_prescribed_sliding_moves_the_attachment_at_v_d_and_matches_the_lumped_model(path, name,
                                                                                      dt, comm):
    """drive.mode = "velocity": the attachment (the contact face, by area) moves at
    exactly v_d in X once started (drive.START_TIME) and is held in Y, as the lumped
    body is, and F_d is the force
    that moves it. The contact-plane drive leaves the block's compliance out of the
    slip, so FE and lumped agree closely: measured against the lumped stepper at
    1e-7 s over 20 ms of vibration, longitudinal -5e-4 (explicit) and -8e-4 (reduced
    at 1e-5 s), transverse -1.3e-4 and +8e-4; 2e-3 bounds them (the lumped stepper
    at 1e-6 s is itself 5e-4 off)."""
    scene = load(path, 'drive.mode="velocity"', "time.T=0.16", "fem.output_every=0",
                 f'fem.integrator="{name}"', f"time.dt={dt}")
    fe = run_fe(scene, comm)
    # x_A = v_d t (after its start) and y_A = 0 to rounding of the displacements (~1e-20 m)
    target = [prescribed_position(t, scene.drive.v_d) for t in fe.series.t]
    assert np.abs(fe.series.x - target).max() < 1e-15
    late = fe.series.t > START_TIME
    assert np.diff(fe.series.x[late]) / np.diff(fe.series.t[late]) == pytest.approx(
        scene.drive.v_d, rel=1e-9)   # (rounding of x over one step: 1e-20 m of 5e-10 m)
    assert np.abs(fe.series.y).max() < 1e-15
    fine = scene.with_values({"time.dt": 1e-7})
    lumped = summarize(run_coupled(fine), fine, 0.0)
    assert ratio(fe, scene) == pytest.approx(lumped["F_dv_over_F_d0"], rel=2e-3)


# --- auto and refusals -----------------------------------------------------------------------

@pytest.mark.parametrize("overrides, picked", [
    (["time.dt=1e-5"], "reduced"),                          # its estimated error 0.8% <= 1%
    (["time.dt=1e-5", "fem.accuracy=1e-4"], "implicit"),    # explicit cannot run 1e-5 s
    (["time.dt=1e-6", "fem.accuracy=1e-4"], "explicit"),    # the cheapest step at 1e-6 s
    (["time.dt=1e-6"], "explicit"),                         # cheaper than reduced (24 vs 75 us)
])
def test_auto_picks_the_cheapest_that_meets_the_accuracy_and_says_why(overrides, picked, comm):
    """registry.choose: the integrator auto takes at its first step."""
    scene = load(LONGITUDINAL, 'fem.integrator="auto"', *overrides)
    run = registry.choose(scene, fe_model.build_model(scene, comm))
    assert run.name == picked
    assert run.choice.startswith(f"{picked}: the cheapest at {scene.time.dt:.4g} s within "
                                 "fem.accuracy")


@pytest.mark.parametrize("overrides, key", [
    (['fem.integrator="explicit"', "fem.energy=true", 'drive.mode="velocity"'], "fem.energy"),
    # LuGre's dampings at a long step: the contact iteration may not converge
    (['fem.integrator="implicit"', "time.dt=1e-5", 'contact.law="lugre"', "contact.h_t=4e4"],
     "time.dt"),                                             # (estimated contraction 1.6)
    (['fem.integrator="reduced"', "fem.rho_infinity=1.5"], "fem.rho_infinity"),
    (['fem.integrator="reduced"', "time.steady_cycles=-1"], "time.steady_cycles"),
    (['fem.integrator="auto"', "fem.accuracy=0"], "fem.accuracy"),
])
def test_scenes_an_integrator_cannot_run_are_refused_naming_the_key(overrides, key, refused_key, tmp_path,
                                                                   comm):
    assert refused_key(lambda: run_fe(load(LONGITUDINAL, *SHORT, *overrides), comm,
                                      vtk_dir=tmp_path / "out")) == key
    assert not (tmp_path / "out").exists()


def test_a_partly_unloaded_face_runs_and_agrees_with_the_explicit_run(comm):
    """Pulled at the front face's mid-height with mu = 0.3 (no vibration, v_d 4x the
    paper's to get there in 80 ms), the block's back edge lifts off once the
    drive's moment F_d L_z / 2 exceeds F_N L_x / 6 (F_d > 10.4 N; 15.3 N at the
    end): 6 nodes at zero normal force, as in the explicit run. The implicit step
    solves them with their exact tangent; F_d against the explicit run within
    0.1% of F_c (measured 1e-6)."""
    base = ["vibration.k_v=0", "time.T=0.08", "drive.v_d=0.002", 'drive.attach="front-face"',
            "contact.mu=0.3", "fem.output_every=0"]
    explicit = run_fe(load(LONGITUDINAL, *base), comm)
    scene = load(LONGITUDINAL, *base, 'fem.integrator="reduced"', "time.dt=1e-5")
    reduced = run_fe(scene, comm)
    def lifted(fe):
        return fe.fields["contact_pressure"][fe.fields["contact_nodes"]] == 0.0
    assert lifted(reduced).sum() >= 3
    assert np.array_equal(lifted(reduced), lifted(explicit))
    assert reduced.series.F_d[-1] == pytest.approx(explicit.series.F_d[-1], abs=1e-3 * scene.F_c)


# --- the paper's scenes to a steady cycle (slow) ---------------------------------------------

def _fig7(*overrides):
    scene = load(LONGITUDINAL, "time.T=0.3", "fem.output_every=0", *overrides)
    return scene, run_fe(scene)


@pytest.fixture(scope="module")
def fig7_explicit():
    """The explicit references, at 1e-6 s: under the earlier normal-force rule (keep)
    and under the contract's (return)."""
    return {rule: _fig7(f"contact.normal_change={rule}") for rule in ("keep", "return")}


@pytest.mark.slow
@pytest.mark.parametrize("name", ["implicit", "reduced"])
def test_fig7_at_the_abaqus_step_within_one_percent_of_explicit(fig7_explicit, name):
    """Fig 7 (longitudinal, k_v = 6, 0.3 s) at dt = 1e-5 s against the explicit run
    at 1e-6 s, same mesh: 1% is the issue's target (measured -0.17% implicit,
    +0.03% reduced). The integrators' own accuracy, under the normal-force rule
    that asks least of the step (keep); the contract's rule: the next test."""
    scene, reference = fig7_explicit["keep"]
    fe_scene, fe = _fig7(f'fem.integrator="{name}"', "time.dt=1e-5", "contact.normal_change=keep")
    assert ratio(fe, fe_scene) == pytest.approx(ratio(reference, scene), rel=0.01)


@pytest.mark.slow
def test_fig7_under_the_normal_force_rule_converges_in_dt(fig7_explicit):
    """Under the contract's rule (return) the reduced integrator needs a finer step on
    Fig 7 (steel block: the nodes' normal forces swing by +-67% a cycle): measured
    against the explicit run at 1e-6 s, +2.9% at 1e-5 s, +1.1% at 5e-6 s, +0.18% at
    2.5e-6 s. At 2.5e-6 s within 0.5%, and closer than at 1e-5 s by a factor >= 5."""
    scene, reference = fig7_explicit["return"]
    errors = []
    for dt in ("1e-5", "2.5e-6"):
        fe_scene, fe = _fig7('fem.integrator="reduced"', f"time.dt={dt}")
        errors.append(abs(ratio(fe, fe_scene) / ratio(reference, scene) - 1.0))
    assert errors[1] < 0.005 and errors[0] > 5.0 * errors[1], errors


@pytest.mark.slow
@pytest.mark.parametrize("path, size, tolerance", [
    (LONGITUDINAL, "[0.03, 0.04, 0.053]", 0.006),
    (TRANSVERSE, "[0.03, 0.04, 0.053]", 0.009),
    (LONGITUDINAL, "[0.03, 0.04, 0.005]", 0.003),
    (TRANSVERSE, "[0.03, 0.04, 0.005]", 0.003),
])
def test_a_100x_stiffer_block_matches_the_lumped_model(path, size, tolerance):
    """E x 100 (reduced, dt = 1e-5 s) against the lumped stepper at 1e-6 s. On the
    paper's block what remains is its rocking: the friction acts at z = 0, the
    inertia at mid-height, so the contact pressure swings front to back every
    cycle (per node 0 to 2x its share): measured +0.44% and -0.70%. Made 5 mm
    tall with the same mass it all but vanishes: -0.15%, -0.17%."""
    density = 31400 if path == TRANSVERSE else 7850
    if "0.005" in size:
        density *= 0.053 / 0.005
    scene = load(path, "time.T=0.3", "fem.output_every=0", "body.E=209e11", f"body.size={size}",
                 f"body.density={density}", 'fem.integrator="reduced"', "time.dt=1e-5",
                 'fem.mesh="4x5x2"' if "0.005" in size else 'fem.mesh="coarse"')
    fe = ratio(run_fe(scene), scene)
    lumped_scene = load(path, "time.T=0.3", "time.dt=1e-6")
    lumped = summarize(run_coupled(lumped_scene), lumped_scene, 0.0)["F_dv_over_F_d0"]
    assert fe == pytest.approx(lumped, rel=tolerance)


@pytest.mark.slow
def test_a_one_second_run_closes_its_energy_balance():
    """1 s of the Fig 7 scene (reduced, dt = 1e-5, trapezoidal): the balance within
    1e-5 of the work put in (measured 2e-6) and no dissipation ever decreasing."""
    scene = load(LONGITUDINAL, "fem.output_every=0", "fem.energy=true", 'fem.integrator="reduced"',
                 "time.dt=1e-5", "fem.rho_infinity=1.0")
    e = run_fe(scene).series.extra
    put_in = e["W_drive"] + e["W_base"]
    residual = put_in - (e["E_kin"] + e["E_el"] + e["D_fric"] + e["D_damp"])
    assert np.abs(residual).max() < 1e-5 * np.abs(put_in).max()
    for key in ("D_fric", "D_damp"):
        assert np.diff(e[key]).min() >= -1e-15 * e[key][-1]


@pytest.mark.slow
@pytest.mark.parametrize("overrides", [
    ['contact.law="lugre"', "contact.F_s=8.0", "contact.v_s=1e-5"],                # sharp Stribeck
    ['contact.law="lugre"', "contact.F_s=7.0", "contact.v_s=2e-3", "contact.h_t=20",
     "contact.h_v=5"],
])
def test_lugre_at_the_abaqus_step_matches_explicit(overrides):
    """LuGre (its rates are per friction sub-step) at dt = 1e-5 s against explicit at
    1e-6 s: within 1% (measured -0.05% and -0.08%, reduced)."""
    scene, reference = _fig7(*overrides)
    fe_scene, fe = _fig7(*overrides, 'fem.integrator="reduced"', "time.dt=1e-5")
    assert ratio(fe, fe_scene) == pytest.approx(ratio(reference, scene), rel=0.01)


@pytest.mark.slow
def test_a_bouncing_block_is_refused_as_by_the_explicit_run():
    """Front-face drive with mu = 0.3 and k_v = 6: the block bounces on its partly
    lifted face (the explicit run's normal force swings 41-71 N); every
    integrator refuses it rather than report a drive force."""
    with pytest.raises(NumericalError, match="ringing|did not converge"):
        _fig7('drive.attach="front-face"', "contact.mu=0.3", 'fem.integrator="reduced"',
              "time.dt=1e-5")


@pytest.mark.slow
@pytest.mark.parametrize("path, overrides, picked", [
    # k_v = 20 transverse: measured -0.43% (reduced, dt = 1e-5) against explicit
    (TRANSVERSE, ["time.dt=1e-5"], "reduced"),
    # an ultrasonic base, 20 kHz at 10 steps a cycle: the reduced model would keep
    # 617 of the coarse mesh's modes (1.6 ms a step), so auto takes the implicit
    # one (0.38 ms); measured +0.37% against explicit
    (LONGITUDINAL, ["vibration.f=20000", "time.dt=5e-6"], "implicit"),
])
def test_hard_scenes_with_auto_stay_within_one_percent_of_explicit(path, overrides, picked):
    """1% is the issue's target against the explicit baseline (same mesh, dt = 1e-6)."""
    base = ["time.T=0.3", "fem.output_every=0"]
    scene = load(path, *base, *overrides[:-1], "time.dt=1e-6")
    reference = run_fe(scene)
    fe_scene = load(path, *base, *overrides, 'fem.integrator="auto"')
    fe = run_fe(fe_scene)
    assert fe.info["integrator"] == picked
    assert ratio(fe, fe_scene) == pytest.approx(ratio(reference, scene), rel=0.01)


@pytest.mark.slow
def test_without_friction_the_block_swings_on_the_drive_spring():
    """mu = 0: no friction force at any node, every step; the block then swings on
    the drive spring: x = v_d t - (v_d / w_d) sin(w_d t), F_d = k_d (v_d t - x) =
    (k_d v_d / w_d) sin(w_d t), w_d = sqrt(k_d / m), for a rigid block, which the
    FE block follows within 1% of the amplitude (measured 0.5%)."""
    scene = load(LONGITUDINAL, "time.T=0.3", "fem.output_every=0",
                 'fem.integrator="reduced"', "time.dt=1e-5")
    # mu = 0 set past the scene's check, which refuses it (F_dv/F_d0 undefined): the
    # model itself is what is tested here
    contact = dataclasses.replace(scene.contact, parameters={**scene.contact.parameters, "mu": 0.0})
    scene = dataclasses.replace(scene, contact=contact)
    fe = run_fe(scene)
    assert np.all(fe.series.F_x == 0.0) and np.all(fe.series.F_y == 0.0)
    k_d, v_d, m = scene.drive.k_d, scene.drive.v_d, scene.body.mass
    w_d = math.sqrt(k_d / m)
    rigid = k_d * v_d / w_d * np.sin(w_d * fe.series.t)
    assert np.abs(fe.series.F_d - rigid).max() < 0.01 * k_d * v_d / w_d


def test_the_scene_offers_exactly_the_integrators_there_are():
    """scene.validate refuses an unknown fem.integrator before any work; the
    registry must hold every name it lets through, and no other."""
    from vibrofric.fem.integrators.registry import INTEGRATORS
    from vibrofric.scene import CHOICES

    assert set(CHOICES["fem.integrator"]) == set(INTEGRATORS)


# --- stiff contacts (k_t up to 1000x the paper's) --------------------------------------------

def test_the_normal_force_goes_to_zero_with_the_penetration():
    """The penalty dashpot pushes at most as hard as the spring: a node touching down
    at speed meets no force at zero penetration (a jump there kept the implicit contact
    iteration alternating between its two sides). In steady contact nothing changes."""
    from vibrofric.fem.model.contact import normal_force
    k, beta = 1.5e9, 6e-8
    assert normal_force(-1e-9, 0.0, k, beta) == k * 1e-9               # the spring alone
    assert normal_force(-1e-9, -1e-3, k, beta) == k * (1e-9 + beta * 1e-3)  # dashpot within
    for gap in (1e-12, 1e-15, 1e-18):                                  # touching down at 1 mm/s
        assert normal_force(-gap, -1e-3, k, beta) == 2.0 * k * gap
    assert normal_force(0.0, -1e-3, k, beta) == 0.0
    assert normal_force(-1e-9, 1.0, k, beta) == 0.0                    # lifting off: no pull


@pytest.mark.parametrize("name", ["implicit", "reduced"])
def test_a_stiff_contact_past_the_plain_iterations_reach_is_accelerated(name, comm):
    """k_t x 100 (stiffer than the block's own shear) at the paper's 1e-5 s: the
    iteration's estimated contraction is 0.60-0.61 (measured), past the plain
    iteration's 0.5 and within 1: the run takes Anderson's (contact_solve); at the
    halved step the estimate is within 0.5 and it does not."""
    from vibrofric.fem.integrators.contact_solve import (MAX_ACCELERATED_CONTRACTION,
                                                         MAX_CONTRACTION)
    scene = load(LONGITUDINAL, *SHORT, f'fem.integrator="{name}"', "time.dt=1e-5",
                 "contact.k_t=8e9")
    model = fe_model.build_model(scene, comm)
    run = registry.select(scene)(scene, model)
    assert MAX_CONTRACTION < run.contraction <= MAX_ACCELERATED_CONTRACTION
    assert run.info["contact_accelerated"] is True
    halved = registry.select(scene)(scene.with_values({"time.dt": 5e-6}), model)
    assert halved.contraction <= MAX_CONTRACTION
    assert halved.info["contact_accelerated"] is False


def test_a_step_too_long_for_lugres_dampings_is_refused_naming_the_contraction(comm):
    """LuGre's dampings over a long step (h_t = 4e4 N s/m at 1e-5 s) depart from k_t by
    ~100 times: the estimated contraction 1.6 is past what the accelerated iteration is
    given (the map may expand): refused, before any work."""
    from vibrofric.core.errors import StepTooLong
    scene = load(LONGITUDINAL, *SHORT, 'fem.integrator="implicit"', "time.dt=1e-5",
                 'contact.law="lugre"', "contact.h_t=4e4")
    model = fe_model.build_model(scene, comm)
    with pytest.raises(StepTooLong, match=r"estimated contraction \S+ > 1.0"):
        registry.select(scene)(scene, model)


@pytest.mark.slow
def test_the_contact_iteration_converges_on_a_block_rocking_on_a_stiff_contact(comm):
    """k_t x 100, reduced at 6.25e-7 s over 10 ms of vibration: the block rocks and its
    corner nodes lift off and touch down every cycle. This run stopped with "contact
    iteration did not converge" 0.6 ms after the vibration started while the penalty
    dashpot could jump at touch-down; now at most 3 iterations a step (measured; 10
    leaves room), and the rocking is kept as the forced response it is."""
    scene = load(LONGITUDINAL, "vibration.t_on=0.002", "time.T=0.012", "time.average_cycles=8",
                 "fem.output_every=0", 'fem.integrator="reduced"', "time.dt=6.25e-7",
                 "contact.k_t=8e9")
    info = run_fe(scene, comm).info
    assert info["iterations_max"] <= 10
    assert info["iterations_stalled"] == 0


@pytest.mark.slow
@pytest.mark.parametrize("path", [LONGITUDINAL, TRANSVERSE])
def test_prescribed_sliding_on_a_stiff_block_on_a_stiff_contact_matches_the_lumped_model(path,
                                                                                       comm):
    """E x 100 and k_t x 100 (8e9 N/m): the block is nearly the lumped model's rigid
    body, and the contact is at the rigid-Coulomb limit. Reduced at 1e-6 s, 2 ms of
    vibration after 2 ms of sliding, against the lumped stepper at the step that
    resolves the slip (core.law_limits.slip_resolved): measured -1e-4 (longitudinal) and
    -3e-4 (transverse). 1e-3 leaves room for the block's remaining compliance
    and rocking (the README's 5 mm tall stiff block: 1.5e-3 and 1.7e-3)."""
    from vibrofric.core.law_limits import slip_resolved
    scene = load(path, 'drive.mode="velocity"', "contact.k_t=8e9", "body.E=2.09e13",
                 "vibration.t_on=0.002", "time.T=0.006", "time.average_cycles=8",
                 "fem.output_every=0", 'fem.integrator="reduced"', "time.dt=1e-6")
    fe = run_fe(scene, comm)
    stepper = slip_resolved(scene)
    lumped = summarize(run_coupled(stepper), stepper, 0.0)["F_dv_over_F_d0"]
    assert ratio(fe, scene) == pytest.approx(lumped, rel=1e-3)
