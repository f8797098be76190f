"""Where an integrator's step spends its time, against what the machine allows.

A step's parts are the compiled functions it calls, each timed alone on the
run's own operators, repeated in a compiled loop (best of several passes):

    explicit            the product with K (3x3 node blocks), the DOF vectors
                        (u + beta v, the loads less K (u + beta v), the central
                        difference), the contact nodes' normal force and friction law
    implicit, reduced   the solve with A, the products with M and K, the
                        contact-space product with G (once per iteration)

Each part's roofline bound is max(bytes / bandwidth, multiply-adds / rate)
with this machine's bandwidth at the part's working set and its multiply-add
rate (bench.machine). The friction law has no such bound: it is a chain of
divisions, square roots and exponentials on a few dozen nodes, latency and
not throughput; it is reported by its time. The rest of a step (drive, base,
recording, checks, and for the implicit integrators the iteration's
bookkeeping) is the measured step less its timed parts.

    breakdown(run, step_s, iterations) -> [Part, ...]

``run`` is a prepared integrator (fem.integrators.registry.select), ``step_s`` its measured
seconds a step, ``iterations`` its mean contact iterations a step.
"""

import time
from dataclasses import dataclass

import numpy as np
from numba import njit

from ..core.law_limits import sliding_length
from ..friction_law.contract import FASTMATH
from ..fem.model.contact import contact_forces
from ..fem.integrators.explicit import central_difference, damped_displacement, external_less
from ..fem.model.linalg import SparseLU, apply, bsr, one_blas_thread, solve
from . import machine


@dataclass
class Part:
    name: str
    seconds: float          # a step
    multiply_adds: float    # a step; 0 where no roofline applies
    nbytes: float           # working set a step

    @property
    def bound(self) -> float:
        """Seconds a step: the roofline bound (0: none, see the module)."""
        return machine.bound(self.multiply_adds, self.nbytes)


# Passes of each timed part, and the wall time a pass aims at.
PASSES, PASS_SECONDS = 5, 0.03


@njit  # not cached: a cached loop would keep the linalg it was compiled with
def _products(op, x, out, repeats):
    for _ in range(repeats):
        apply(op, x, out)


@njit  # not cached: a cached loop would keep the linalg it was compiled with
def _solves(inv, b, out, repeats):
    for _ in range(repeats):
        solve(inv, b, out)


@njit(fastmath=FASTMATH)  # not cached (see _products)
def _vector_updates(u, v, work, force, load, inverse_mass, beta, dt, repeats):
    for _ in range(repeats):
        damped_displacement(u, v, beta, work)
        external_less(load, force)
        central_difference(u, v, force, inverse_mass, dt)


@njit  # not cached (see _products)
def _contact_steps(kernel, arguments, repeats):
    for _ in range(repeats):
        kernel(*arguments)


def _seconds(call) -> float:
    """Seconds a call of ``call(repeats)``, best of PASSES passes of ~PASS_SECONDS, on one
    BLAS thread as in the time loop."""
    with one_blas_thread():
        call(1)
        start = time.perf_counter()
        call(10)
        once = max((time.perf_counter() - start) / 10, 1e-9)
        repeats = max(1, int(PASS_SECONDS / once))
        best = np.inf
        for _ in range(PASSES):
            start = time.perf_counter()
            call(repeats)
            best = min(best, (time.perf_counter() - start) / repeats)
    return best


def operator_cost(op) -> tuple:
    """(multiply-adds, bytes) of one product or solve with ``op`` (linalg.apply / solve)."""
    if isinstance(op, SparseLU):
        entries = op.entries
        return entries, 16.0 * entries + 48.0 * op.work.size  # value + column; the vectors
    if isinstance(op, tuple):                                   # bsr: 3x3 blocks
        indptr, columns, data = op
        n, entries = 3 * (indptr.size - 1), 9 * columns.size   # (data: the entries and one zero)
        return entries, 8.0 * entries + columns.nbytes + indptr.nbytes + 16.0 * n
    if op.ndim == 1:                                            # a diagonal
        return op.size, 24.0 * op.size
    rows, cols = op.shape                                       # dense
    return rows * cols, 8.0 * (rows * cols + rows + cols)


def explicit_parts(run) -> list:
    """The explicit step's parts (module docstring)."""
    model, scene = run.model, run.scene
    n, contacts = model.dofs, model.contact_nodes.size
    stiffness = bsr(model.stiffness)
    x, out = model.u0.copy(), np.empty(n)
    product = Part("product with K", _seconds(lambda r: _products(stiffness, x, out, r)),
                   *operator_cost(stiffness))

    u, v, work, force = model.u0.copy(), np.zeros(n), np.empty(n), np.zeros(n)
    beta, dt = model.beta, scene.time.dt
    vectors = Part("DOF vectors", _seconds(lambda r: _vector_updates(
        u, v, work, force, model.load, model.inverse_mass, beta, dt, r)),
        4.0 * n, 8.0 * 11 * n)  # 4 operations a DOF; u, v, work, force, load, 1/m: 11 reads or writes

    law = scene.friction
    kernel = contact_forces.for_law(law.law)
    disp = model.u0.reshape(-1, 3)[model.contact_nodes].copy()
    moved = disp + 1e-9        # every node slides 1 nm a step, in contact
    moved[:, 2] = disp[:, 2]
    states = law.law.initial_state(contacts)
    normal, friction = model.normal0.copy(), np.zeros((contacts, 2))
    vel_z = np.zeros(contacts)

    arguments = (disp, moved, vel_z, 0.0, 0.0, scene.contact.eta_y, model.initial_gap, 0.0, 0.0,
                 model.penalty_share,
                 model.area_share, model.nominal_normal, beta, law.params, dt,
                 sliding_length(scene), states, normal, friction)
    friction_part = Part(f"contact and friction law ({contacts} nodes)",
                         _seconds(lambda r: _contact_steps(kernel, arguments, r)), 0, 0)
    return [product, vectors, friction_part]


def implicit_parts(run, iterations: float) -> list:
    """The implicit (or reduced) step's linear algebra (module docstring)."""
    n = run.system.size
    b, y = np.ones(n), np.empty(n)
    parts = [Part("solve with A", _seconds(lambda r: _solves(run.inv, b, y, r)),
                  *operator_cost(run.inv))]
    for name, op in (("product with M", run.mass_op), ("product with K", run.stiffness_op)):
        parts.append(Part(name, _seconds(lambda r: _products(op, b, y, r)), *operator_cost(op)))
    g, target = np.ones(run.G.shape[1]), np.empty(run.G.shape[0])
    adds, nbytes = operator_cost(run.G)
    parts.append(Part(f"product with G (x {iterations:.2f} iterations)",
                      iterations * _seconds(lambda r: _products(run.G, g, target, r)),
                      iterations * adds, nbytes))
    return parts


def breakdown(run, step_s: float, iterations: float = 0.0) -> list:
    """The step's timed parts, then "the rest" (the step less those parts)."""
    parts = explicit_parts(run) if run.name == "explicit" else implicit_parts(run, iterations)
    rest = step_s - sum(part.seconds for part in parts)
    label = ("drive, base, recording, checks" if run.name == "explicit"
             else "friction law on the sub-steps, iteration, drive, recording, checks")
    return parts + [Part(f"rest: {label}", rest, 0, 0)]
