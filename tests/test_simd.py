"""fem.model.simd: four-lane vectors in numba loops, each lane rounded as the scalar code rounds."""

from fractions import Fraction

import numpy as np
import scipy.sparse as sp
from numba import njit

from vibrofric.fem.model import simd
from vibrofric.fem.model.linalg import apply, bsr


def fused(a: float, b: float, c: float) -> float:
    """a b + c rounded once (exact rationals, then the correctly rounded float)."""
    return float(Fraction(a) * Fraction(b) + Fraction(c))


@njit
def _fma_lanes(a, b, c):
    return simd.sum3(simd.fma(simd.load(a, 0), simd.load(b, 0), simd.load(c, 0)))


def test_fma_rounds_once_per_lane():
    """(1 + e)(1 - e) - 1 is -e^2 when fused and 0 when the product is rounded first;
    lane 3 (5.0) stays out of sum3."""
    e = 2.0 ** -30
    a, b = np.full(4, 1.0 + e), np.full(4, 1.0 - e)
    c = np.array([-1.0, -1.0, 0.0, 5.0])
    assert (1.0 + e) * (1.0 - e) - 1.0 == 0.0
    lanes = [fused(a[k], b[k], c[k]) for k in range(3)]
    assert lanes[0] == -e * e
    assert _fma_lanes(a, b, c) == (lanes[0] + lanes[1]) + lanes[2]


@njit
def _load3_lanes(a, i):
    """load3(a, i): the sum of lanes 0-2, and lane 3 alone (moved to lane 0 by a product
    with (0, 0, 0, 1) ... summed: lanes 0-2 of that product are zero)."""
    v = simd.load3(a, i)
    lane3_only = simd.fma(v, simd.load(np.array([0.0, 0.0, 0.0, 1.0]), 0), simd.zeros())
    return simd.sum3(v), simd.sum3(lane3_only)


def test_load3_reads_three_lanes_up_to_the_array_end():
    a = np.arange(1.0, 8.0)                          # a[i + 3] exists and is not zero
    assert _load3_lanes(a, 2) == ((3.0 + 4.0) + 5.0, 0.0)
    assert _load3_lanes(a, a.size - 3) == ((5.0 + 6.0) + 7.0, 0.0)   # the last three


@njit
def _product(op, x, out):
    apply(op, x, out)


def block_product(indptr, columns, blocks, x):
    """K x in linalg._bsr_apply's arithmetic, written out in scalars: per node row, lane k
    of row r sums B_p[r, k] x[c_p + k] with one rounding a block, blocks alternating between
    two sets of sums (an odd last block to the first); then the sets, then the lanes."""
    out = np.empty_like(x)
    for node in range(indptr.size - 1):
        first, end = int(indptr[node]), int(indptr[node + 1])
        paired_end = first + 2 * ((end - first) // 2)
        sums = np.zeros((2, 3, 3))                    # [set, row r, lane k]
        for p in range(first, end):
            which = (p - first) % 2 if p < paired_end else 0
            c = int(columns[p])
            for r in range(3):
                for k in range(3):
                    sums[which, r, k] = fused(blocks[p, r, k], x[c + k], sums[which, r, k])
        lanes = sums[0] + sums[1]
        out[3 * node:3 * node + 3] = (lanes[:, 0] + lanes[:, 1]) + lanes[:, 2]
    return out


def test_block_product_is_the_documented_arithmetic():
    """Bit for bit against block_product, on a matrix with rows of odd and even block counts."""
    rng = np.random.default_rng(3)
    nodes = 7
    pattern = sp.random(nodes, nodes, 0.5, random_state=4) + sp.eye(nodes)
    K = sp.kron(pattern, np.ones((3, 3))).tocsr()
    K.data = rng.standard_normal(K.data.size)
    indptr, columns, data = op = bsr(K)
    counts = np.diff(indptr.astype(int))
    assert set(counts % 2) == {0, 1}
    assert data.size == 9 * columns.size + 1 and data[-1] == 0.0   # the zero after the last block
    x, out = rng.standard_normal(3 * nodes), np.empty(3 * nodes)
    _product(op, x, out)
    assert np.array_equal(out, block_product(indptr, columns, data[:-1].reshape(-1, 3, 3), x))
    assert np.allclose(out, K @ x, rtol=1e-13, atol=1e-13 * np.abs(K @ x).max())
