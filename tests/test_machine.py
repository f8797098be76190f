"""The roofline (vibrofric.bench.machine) and the operation counts a step's parts are bounded by
(bench.step_breakdown.operator_cost)."""

import numpy as np
import pytest
import scipy.sparse as sp

from vibrofric.bench import machine


def test_bound_is_the_slower_of_memory_and_arithmetic():
    rate, bandwidth = machine.multiply_add_rate(), machine.bandwidth(1_000_000)
    assert rate > 0 and bandwidth > 0
    assert machine.bound(rate, 0) == pytest.approx(1.0)   # one second of multiply-adds
    assert machine.bound(0, 1_000_000) == pytest.approx(1_000_000 / bandwidth)
    assert machine.bound(rate, 1_000_000) == pytest.approx(max(1.0, 1_000_000 / bandwidth))
    assert machine.bound(0, 0) == 0.0


def test_operator_costs_count_every_stored_entry():
    pytest.importorskip("dolfinx")   # fem imports the adapter's siblings
    from vibrofric.fem.model.linalg import bsr, factorize
    from vibrofric.bench.step_breakdown import operator_cost

    rng = np.random.default_rng(1)
    dense = rng.random((6, 6))
    spd = sp.csr_matrix(dense @ dense.T + 6 * np.eye(6))
    blocks = bsr(spd)
    assert operator_cost(blocks)[0] == 36               # two full rows of 3x3 blocks, squared
    assert operator_cost(dense) == (36, 8.0 * (36 + 12))
    assert operator_cost(np.ones(6)) == (6, 24.0 * 6)
    lu = factorize(spd)
    assert operator_cost(lu)[0] == lu.entries
