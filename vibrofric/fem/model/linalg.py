"""Linear algebra inside the numba time loops: matrix products and factorized solves.

The implicit loop (integrators/implicit.py) runs unchanged on the full model (sparse, tens
of thousands of DOFs) and on the reduced one (dense, about a hundred): the
operators it gets decide, at compile time, which code runs.

    apply(op, x, out)    out = op x, for
                         a 1-D array        (a diagonal: the lumped mass)
                         a 2-D array        (a dense matrix: the reduced model,
                                            the contact space; BLAS gemv)
                         BSR (indptr, columns, data)
                                            (the block's K in 3x3 node blocks, bsr();
                                            four-lane vectors, simd.py)
    solve(inv, b, out)   out = A^-1 b, for
                         a 2-D array        (A^-1 itself: small dense systems)
                         SparseLU           (triangular factors of A: P_r A P_c = L U)

``factorize(A)`` returns the SparseLU of a scipy sparse matrix (SuperLU, as
scipy.sparse.linalg.splu computes it), ``inverse(A)`` the dense inverse.
Time loops run inside ``one_blas_thread()``.
"""

import math
from typing import NamedTuple

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla
from numba import njit, types
from numba.extending import overload
from threadpoolctl import threadpool_limits

from . import simd


# Sums may be reordered (SIMD, several accumulators): 2-4x faster products and
# solves, the same results to rounding; NaN and infinity still propagate.
LINEAR_FASTMATH = {"reassoc", "contract", "arcp", "nsz"}


class SparseLU(NamedTuple):
    """P_r A P_c = L U with L unit lower and U upper triangular, rows in CSR.

    Solving A x = b: z[perm_r] = b, z = L^-1 z, z = U^-1 z, x = z[perm_c]
    (scipy's SuperLU convention, checked by the tests).
    """

    lower_indptr: np.ndarray    # L without its unit diagonal
    lower_indices: np.ndarray
    lower_data: np.ndarray
    upper_indptr: np.ndarray    # U without its diagonal
    upper_indices: np.ndarray
    upper_data: np.ndarray
    inverse_diagonal: np.ndarray  # 1 / diag(U)
    perm_r: np.ndarray
    perm_c: np.ndarray
    work: np.ndarray            # scratch of length n

    @property
    def entries(self) -> int:
        """Stored entries of L + U: the multiply-adds of one solve."""
        return int(self.lower_data.size + self.upper_data.size + self.inverse_diagonal.size)


def _off_diagonal(matrix):
    """A CSR copy of ``matrix`` without its diagonal, and that diagonal."""
    csr = sp.csr_matrix(matrix)
    diagonal = csr.diagonal().copy()
    csr.setdiag(0.0)
    csr.eliminate_zeros()
    csr.sort_indices()
    return csr, diagonal


def _grid_values(points):
    """The points' coordinates scaled to the largest extent and rounded: equal values
    lie in one grid layer."""
    return np.round(points / max(np.ptp(points, axis=0).max(), 1e-300), 9)


def on_grid(points) -> bool:
    """Whether the rows' points (n, 3) are the nodes of a structured grid (the block's),
    nested_dissection's precondition: as many as the product of their distinct X, Y
    and Z values. An unstructured mesh's points are nearly all in layers of their own,
    which separate nothing (its order filled a tetrahedral ball's factor 30x: scipy's
    minimum degree serves it)."""
    grid = _grid_values(points)
    return math.prod(np.unique(grid[:, k]).size for k in range(3)) == points.shape[0]


def nested_dissection(points, leaf: int = 48) -> np.ndarray:
    """An elimination order for a matrix whose rows sit at ``points`` (n, 3) of a
    structured hexahedral grid: order[k] is the row eliminated k-th.

    The rows are split by the layer of grid points across the middle of their
    longest extent; a layer separates the two sides (a first-order hexahedron
    couples adjacent layers only), so each side is ordered first, recursively,
    and the layer last. The factor's fill then grows as n^(4/3) rather than the
    minimum degree's faster growth on a 3D mesh: on the fine mesh (31 k DOFs)
    31.6 M entries in 14 s against 65.7 M in 75 s.
    """
    grid = _grid_values(points)  # layers: equal values
    order = []

    def split(rows):
        p = grid[rows]
        axis = int(np.argmax(np.ptp(p, axis=0))) if rows.size > leaf else 0
        layers = np.unique(p[:, axis]) if rows.size > leaf else ()
        if len(layers) < 3:
            order.append(rows)
            return
        cut = layers[len(layers) // 2]
        split(rows[p[:, axis] < cut])
        split(rows[p[:, axis] > cut])
        order.append(rows[p[:, axis] == cut])

    split(np.arange(points.shape[0]))
    return np.concatenate(order)


class OrderedLU:
    """SuperLU of A[order][:, order] (symmetric mode, no reordering of its own): A x = b
    is solved as x[order] = LU^-1 b[order]."""

    def __init__(self, matrix, order):
        self.order = order
        permuted = sp.csc_matrix(matrix)[order][:, order].tocsc()
        self.lu = sla.splu(permuted, permc_spec="NATURAL", diag_pivot_thresh=0.0,
                           options=dict(SymmetricMode=True))
        # A = P^T B P (B the permuted matrix): B's row and column permutations in A's terms.
        inverse_order = np.argsort(order)
        self.L, self.U = self.lu.L, self.lu.U
        self.perm_r = np.empty_like(self.lu.perm_r)
        self.perm_r[order] = self.lu.perm_r
        self.perm_c = self.lu.perm_c[inverse_order]

    def solve(self, b):
        x = np.empty_like(b, dtype=np.result_type(b, self.L.dtype))
        x[self.order] = self.lu.solve(b[self.order])
        return x


def symmetric_lu(matrix, order=None):
    """The LU of a symmetric (or complex-symmetric) sparse matrix, with ``.solve(b)``.

    The pivots stay on the diagonal (symmetric mode): the matrices factorized
    here are symmetric positive definite, or that plus a small complex or
    negative shift far from singular, which needs no pivoting; it keeps the
    fill of a Cholesky factor. The ordering: ``order`` when given (OrderedLU;
    nested_dissection of the rows' points on the block's grid), else scipy's
    minimum degree on A + A^T (on the medium mesh 2.6 M entries against nested
    dissection's 1.9 M and COLAMD's 3.2 M).
    """
    if order is not None:
        return OrderedLU(matrix, order)
    return sla.splu(sp.csc_matrix(matrix), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                    options=dict(SymmetricMode=True))


def spd_factor(matrix, order=None):
    """A factorization of a real symmetric positive definite sparse matrix, with
    ``.solve(b)`` for b (n,) or (n, k): on the block's grid (``order`` given) its
    symmetric_lu as ever; on any other mesh the DOLFINx stack's Cholesky
    (dolfinx_adapter.cholesky: CHOLMOD, its own fill-reducing order and dense kernels),
    where the stack has none symmetric_lu's minimum degree. On the fine ball (23k DOFs,
    tetrahedra) CHOLMOD factorized in 1.2 s and solved 564 right-hand sides in 2.6 s,
    SuperLU in 24-34 s and ~25 s (docs/performance.md, "2026-11-27: the FE ball and block
    from 20k to 100k DOFs")."""
    if order is None:
        from . import dolfinx_adapter

        factor = dolfinx_adapter.cholesky(matrix)
        if factor is not None:
            return factor
    return symmetric_lu(matrix, order)


def fastest_spd_factor(matrix, order=None):
    """spd_factor's factorization, but CHOLMOD (dolfinx_adapter.cholesky) on the block's
    grid too where the stack has it: for solves whose results may differ from the
    nested-dissection LU's in their last bits (the reduction's error estimate,
    integrators/reduction.py FullCompliance), not for those the block's answers are
    computed from (the preload, the reduction), which stay spd_factor's. On the fine
    block (31k DOFs) CHOLMOD factorized in 4.8 s, the nested-dissection LU in 51 s
    (docs/performance.md, "2026-11-27: the reduction's error estimate from one real
    factorization")."""
    from . import dolfinx_adapter

    factor = dolfinx_adapter.cholesky(matrix)
    return factor if factor is not None else spd_factor(matrix, order)


def dof_points(coordinates) -> np.ndarray:
    """(3 nodes, 3): every DOF at its node's position (node d carries DOFs 3 d + c)."""
    return np.repeat(coordinates, 3, axis=0)


def factorize(matrix, order=None) -> SparseLU:
    """The symmetric LU of a sparse matrix (symmetric_lu), in the form ``solve`` takes."""
    lu = symmetric_lu(matrix, order)
    lower, _ = _off_diagonal(lu.L)
    upper, diagonal = _off_diagonal(lu.U)
    if not np.all(np.isfinite(diagonal)) or np.any(diagonal == 0.0):
        raise np.linalg.LinAlgError("singular matrix")
    index = np.uint64  # unsigned: no test for Python's negative indices in the solve (bsr)
    return SparseLU(lower.indptr.astype(index), lower.indices.astype(index), lower.data,
                    upper.indptr.astype(index), upper.indices.astype(index), upper.data,
                    1.0 / diagonal, lu.perm_r.astype(index), lu.perm_c.astype(index),
                    np.empty(matrix.shape[0]))


def inverse(matrix) -> np.ndarray:
    """The dense inverse of a small symmetric positive definite matrix."""
    dense = np.asarray(matrix.toarray() if sp.issparse(matrix) else matrix, dtype=float)
    inv = np.linalg.inv(dense)
    return 0.5 * (inv + inv.T)


def columns_of_inverse(inv, dofs: np.ndarray) -> np.ndarray:
    """A^-1 restricted to rows and columns ``dofs``: (len(dofs), len(dofs)) dense."""
    if isinstance(inv, np.ndarray):
        return inv[np.ix_(dofs, dofs)].copy()
    n = inv.work.size
    out = np.empty((dofs.size, dofs.size))
    unit, column = np.zeros(n), np.empty(n)
    for k, dof in enumerate(dofs):
        unit[dof] = 1.0
        solve(inv, unit, column)
        unit[dof] = 0.0
        out[:, k] = column[dofs]
    return 0.5 * (out + out.T)


def bsr(matrix):
    """A sparse matrix of 3x3 node blocks as the (indptr, columns, data) ``apply`` takes:
    block p of node row i holds K[3i:3i+3, c:c+3], c = columns[p] the first DOF of its
    column node, row-major at data[9p:9p+9]; one zero follows the last block, so that
    the product's four-lane load of its last row stays inside the array (_bsr_apply).

    indptr and columns are unsigned: numba indexes an array by a signed integer
    through a test for negative indices (Python's wrap-around), three per block
    here, which kept the product at half its speed.
    """
    blocks = sp.bsr_matrix(matrix, blocksize=(3, 3))
    blocks.sort_indices()
    data = np.zeros(blocks.data.size + 1)
    data[:-1] = blocks.data.ravel()
    return (blocks.indptr.astype(np.uint64), 3 * blocks.indices.astype(np.uint64), data)


def one_blas_thread():
    """A context in which BLAS runs on the calling thread only (threadpoolctl).

    The dense products are BLAS gemv calls of ~100 x 100 on the paper's
    meshes. OpenBLAS splits a gemv of more than 9,216 entries over its
    threads, and for a product of a microsecond the hand-off costs more than
    the work (measured: docs/performance.md, "Design choices measured"). A
    single run's set-up keeps its threads; a sweep's FE points run on one
    thread throughout, as the sweep already keeps every core busy
    (batch/points.py).
    """
    return threadpool_limits(limits=1, user_api="blas")


def apply(op, x, out):
    """out = op x (compiled per operator type, see the module docstring)."""
    raise NotImplementedError("apply runs inside numba")


def solve(inv, b, out):
    """out = A^-1 b (compiled per type, see the module docstring)."""
    if isinstance(inv, np.ndarray):
        out[:] = inv @ b
    else:
        _lu_solve(inv, b, out)


@overload(apply, jit_options={"cache": True, "fastmath": LINEAR_FASTMATH})
def _apply(op, x, out):
    if isinstance(op, types.Array) and op.ndim == 1:
        def diagonal(op, x, out):
            for k in range(x.shape[0]):
                out[k] = op[k] * x[k]
        return diagonal
    if isinstance(op, types.Array) and op.ndim == 2:
        def dense(op, x, out):
            np.dot(op, x, out)
        return dense
    if isinstance(op, types.BaseTuple) and len(op) == 3:
        def blocks(op, x, out):
            _bsr_apply(op[0], op[1], op[2], x, out)
        return blocks
    return None


# Unsigned offsets keep an unsigned index unsigned (bsr; numba would type index + 1 as signed).
_ONE, _TWO, _THREE, _FOUR, _SIX = (np.uint64(1), np.uint64(2), np.uint64(3), np.uint64(4),
                                   np.uint64(6))


@njit(cache=True, fastmath={"contract"}, inline="always")
def _block_rows(data, p, w, s0, s1, s2):
    """(s0, s1, s2) + the rows of block p times w, lane by lane (the block's 9 multiply-adds).

    Each row is loaded four lanes wide: its fourth lane is the next row's first
    entry (or the zero after the last block), and w's fourth lane is zero."""
    q = np.uint64(9) * p
    return (simd.fma(simd.load(data, q), w, s0),
            simd.fma(simd.load(data, q + _THREE), w, s1),
            simd.fma(simd.load(data, q + _SIX), w, s2))


@njit(cache=True, fastmath={"contract"})
def _bsr_apply(indptr, columns, data, x, out):
    """out = K x, K in 3x3 node blocks (bsr), a node row at a time.

    A row of blocks B_p (columns c_p) gives out_r = sum_p sum_k B_p[r, k] x[c_p + k].
    The sums run in four-lane vectors (simd.py), one a block row: lane k of s_r
    adds B_p[r, k] x[c_p + k], and out_r is the sum of its three lanes at the
    row's end. Two blocks at a time, into two sets of sums, keep two multiply-adds
    in flight on each. LLVM does not find this shape by itself: with reordering
    of sums allowed it vectorized across blocks with gathered loads, which
    Intel's Gather Data Sampling mitigation makes several times slower, and
    without it the scalar loop did 9 multiply-adds a block one by one
    (measured: docs/performance.md, "Design choices measured").
    """
    for node in range(indptr.shape[0] - 1):
        s0, s1, s2 = simd.zeros(), simd.zeros(), simd.zeros()
        t0, t1, t2 = simd.zeros(), simd.zeros(), simd.zeros()
        p, end = indptr[node], indptr[node + 1]
        while p + _ONE < end:
            s0, s1, s2 = _block_rows(data, p, simd.load3(x, columns[p]), s0, s1, s2)
            t0, t1, t2 = _block_rows(data, p + _ONE, simd.load3(x, columns[p + _ONE]),
                                     t0, t1, t2)
            p += _TWO
        if p < end:
            s0, s1, s2 = _block_rows(data, p, simd.load3(x, columns[p]), s0, s1, s2)
        row = 3 * node
        out[row] = simd.sum3(simd.add(s0, t0))
        out[row + 1] = simd.sum3(simd.add(s1, t1))
        out[row + 2] = simd.sum3(simd.add(s2, t2))


@njit(cache=True, fastmath={"contract"}, inline="always")
def _row_dot(indptr, indices, data, z, i):
    """sum_p data[p] z[indices[p]] over row i of a CSR matrix, in four running sums.

    Four sums keep four multiply-adds in flight (one sum waits on each; measured
    2.3x faster than one). Summing them in another order is left to no compiler
    ("contract" only): with reordering allowed, LLVM vectorizes the row with
    gather instructions, which Intel's Gather Data Sampling mitigation makes
    several times slower.
    """
    s0 = s1 = s2 = s3 = 0.0
    p, end = indptr[i], indptr[i + 1]
    while p + _THREE < end:
        s0 += data[p] * z[indices[p]]
        s1 += data[p + _ONE] * z[indices[p + _ONE]]
        s2 += data[p + _TWO] * z[indices[p + _TWO]]
        s3 += data[p + _THREE] * z[indices[p + _THREE]]
        p += _FOUR
    while p < end:
        s0 += data[p] * z[indices[p]]
        p += _ONE
    return (s0 + s1) + (s2 + s3)


@njit(cache=True, fastmath={"contract"})
def _lu_solve(lu, b, out):
    (lp, li, lx, up, ui, ux, dinv, perm_r, perm_c, z) = lu
    n = b.shape[0]
    for i in range(n):
        z[perm_r[i]] = b[i]
    for i in range(n):                      # L z = P_r b, unit diagonal
        z[i] -= _row_dot(lp, li, lx, z, i)
    for i in range(n - 1, -1, -1):          # U z = z
        z[i] = (z[i] - _row_dot(up, ui, ux, z, i)) * dinv[i]
    for i in range(n):
        out[i] = z[perm_c[i]]


@overload(solve, jit_options={"cache": True, "fastmath": LINEAR_FASTMATH})
def _solve(inv, b, out):
    if isinstance(inv, types.Array) and inv.ndim == 2:
        def dense(inv, b, out):
            apply(inv, b, out)
        return dense
    if isinstance(inv, types.BaseTuple):
        def sparse(inv, b, out):
            _lu_solve(inv, b, out)
        return sparse
    return None
