"""The contact iteration's Anderson acceleration (vibrofric/fem/integrators/anderson.py):
on linear maps, where it is GMRES (Walker & Ni 2011), and inside the implicit step,
where it runs only on scenes beyond the plain iteration's estimated contraction."""

import contextlib
from pathlib import Path

import numpy as np
import pytest

from vibrofric.fem.integrators.anderson import DEPTH, History, accelerated_step

ROOT = Path(__file__).resolve().parents[1]
LONGITUDINAL = ROOT / "scenes" / "longitudinal.toml"


def linear_map(radius: float, n: int = 4):
    """x -> B x + c with B symmetric, eigenvalues from `radius` down to -0.3, and its
    fixed point x* = (I - B)^-1 c."""
    rng = np.random.default_rng(7)
    basis, _ = np.linalg.qr(rng.standard_normal((n, n)))
    B = basis @ np.diag(np.linspace(radius, -0.3, n)) @ basis.T
    c = rng.standard_normal(n)
    return B, c, np.linalg.solve(np.eye(n) - B, c)


def iterate(B, c, iterations: int, depth: int):
    """The fixed point x_{k+1} = x_k + f_k, f_k = B x_k + c - x_k, from x = 0; Anderson's
    step in place of f_k with depth > 0. Returns the last iterate."""
    x = np.zeros(c.size)
    history = History.allocate(c.size, depth)
    count = 0
    for _ in range(iterations):
        f = B @ x + c - x
        if depth > 0:
            count = accelerated_step(x.copy(), f, count, history)
        x = x + f
    return x


@pytest.mark.parametrize("radius", [0.9, 1.2])
def test_anderson_converges_where_the_plain_fixed_point_is_slow_or_diverges(radius):
    """On 4 unknowns with depth 5 >= 4 Anderson is GMRES without restart: exact (to
    rounding) after n + 1 = 5 maps; 12 leave room for rounding. The plain iteration
    errs by 0.9^12 = 0.28 of its start at 0.9 and grows at 1.2."""
    B, c, fixed = linear_map(radius)
    start_error = np.linalg.norm(fixed)
    accelerated = iterate(B, c, 12, DEPTH)
    plain = iterate(B, c, 12, 0)
    # 1e-9: a few orders above rounding on a system whose condition, 1 / min|1 - lambda|
    # = 10 or 5, amplifies it
    assert np.linalg.norm(accelerated - fixed) < 1e-9 * start_error
    assert np.linalg.norm(plain - fixed) > 0.1 * start_error


def test_a_restarted_history_takes_the_plain_step():
    """count = 0 (a restart): the step is the plain one, unchanged to the bit."""
    B, c, _ = linear_map(0.9)
    history = History.allocate(c.size, DEPTH)
    x = np.ones(c.size)
    f = B @ x + c - x
    plain = f.copy()
    assert accelerated_step(x, f, 0, history) == 1
    assert np.array_equal(f, plain)


pytest.importorskip("dolfinx")

from vibrofric import scene as scenes  # noqa: E402
from vibrofric.analytic import summarize  # noqa: E402
from vibrofric.fem import run_fe  # noqa: E402
from vibrofric.fem.integrators import implicit  # noqa: E402

# A short vibrated run: vibration from 0.5 ms, 4.5 ms of it (18 cycles at 4 kHz).
SHORT = ['time.method="transient"', "vibration.t_on=0.0005", "time.T=0.005",
         "time.average_cycles=4", "fem.output_every=0"]


@pytest.fixture(scope="module")
def comm():
    from mpi4py import MPI
    return MPI.COMM_SELF


@contextlib.contextmanager
def contraction_threshold(value):
    """implicit.MAX_CONTRACTION, the estimate past which the iteration is accelerated,
    set to ``value`` for the runs inside (a module fixture has no monkeypatch)."""
    threshold = implicit.MAX_CONTRACTION
    implicit.MAX_CONTRACTION = value
    try:
        yield
    finally:
        implicit.MAX_CONTRACTION = threshold


@pytest.fixture(scope="module")
def plain_and_forced(comm):
    """The coarse block, reduced at 1e-5 s (contraction ~0.004, the plain iteration's):
    as shipped, and with the accelerator forced on (its threshold lowered to 0)."""
    scene = scenes.load(LONGITUDINAL, [*SHORT, 'fem.integrator="reduced"', "time.dt=1e-5"])
    plain = run_fe(scene, comm)
    with contraction_threshold(0.0):
        forced = run_fe(scene, comm)
    return scene, plain, forced


def test_the_accelerator_does_not_run_where_the_plain_iteration_contracts(plain_and_forced):
    scene, plain, forced = plain_and_forced
    assert plain.info["contact_accelerated"] is False
    assert forced.info["contact_accelerated"] is True


def test_the_accelerated_iteration_finds_the_plain_ones_fixed_point(plain_and_forced):
    """Both iterate to the same tolerance (1e-6 F_N / k_t on each contact displacement):
    F_dv/F_d0 agrees to 1e-5 of itself (the tolerance's own effect on the answer, measured
    on Fig 7 at 1e-5 s: contact_solve.ITERATION_TOLERANCE), and the accelerated one
    takes no more iterations a step."""
    scene, plain, forced = plain_and_forced
    answer, again = (summarize(run.series, scene, 0.0)["F_dv_over_F_d0"] for run in
                     (plain, forced))
    assert again == pytest.approx(answer, rel=1e-5)
    assert forced.info["iterations_mean"] <= plain.info["iterations_mean"] + 0.1


def test_past_the_plain_iterations_reach_the_accelerated_one_takes_fewer_iterations(comm):
    """k_t x 100 at 1e-5 s (estimated contraction 0.60-0.61, accelerated; fem.damping
    raised, so that the stiff contact's ringing dies within the short run): against the
    plain iteration on the same scene (its threshold raised past the estimate), the
    same F_dv/F_d0 (1e-5 of itself, as above) in fewer iterations a step on average
    (on the fine ball, 5.1 against 10.0: docs/performance.md)."""
    scene = scenes.load(LONGITUDINAL, [*SHORT, 'fem.integrator="reduced"', "time.dt=1e-5",
                                       "contact.k_t=8e9", "fem.damping=1e-6"])
    accelerated = run_fe(scene, comm)
    with contraction_threshold(1.0):
        plain = run_fe(scene, comm)
    assert accelerated.info["contact_accelerated"] and not plain.info["contact_accelerated"]
    answer, again = (summarize(run.series, scene, 0.0)["F_dv_over_F_d0"] for run in
                     (plain, accelerated))
    assert again == pytest.approx(answer, rel=1e-5)
    assert accelerated.info["iterations_mean"] < plain.info["iterations_mean"]
