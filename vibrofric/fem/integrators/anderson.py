"""Anderson acceleration of a fixed-point iteration (Walker & Ni, "Anderson
acceleration for fixed-point iterations", SIAM J. Numer. Anal. 49(4), 2011,
Algorithm AA with mixing parameter beta = 1).

For the iteration x_{k+1} = x_k + f_k, f_k = f(x_k) its step, keep the last m
differences dX = [x_{i+1} - x_i], dF = [f_{i+1} - f_i] and step instead to

    x_{k+1} = x_k + f_k - (dX + dF) gamma_k,   gamma_k = argmin || f_k - dF gamma ||_2

the step of the combination of the last m + 1 iterates whose linearized step is
smallest. On a linear map x -> B x + c, the whole history kept (m at least the
iterations), it is GMRES on (I - B) x = c (Walker & Ni, Theorem 2.2): it converges
where the plain iteration's contraction factor nears or passes 1; truncated to the
last m, it still removes the few slowest directions that dominate. The contact
iteration (contact_solve.iterate_contact) takes it only on scenes whose
estimated contraction is beyond the plain iteration's (docs/fe-model.md, "How an
implicit step works"); compiled once for all friction laws.
"""

from typing import NamedTuple

import numpy as np
from numba import njit

from ...friction_law.contract import FASTMATH

# The history kept: 5 differences (Walker & Ni's examples take 1 to 50; a few suffice
# where a few slow directions dominate, as the patch's softest tangential modes do).
DEPTH = 5
# Singular values of dF below this fraction of its largest are dropped (np.linalg.lstsq's
# rcond): differences that have become linearly dependent near convergence.
RCOND = 1e-10


class History(NamedTuple):
    """The last DEPTH differences of the iterates and their steps, in a ring."""

    dx: np.ndarray          # (DEPTH, n) x_{i+1} - x_i
    df: np.ndarray          # (DEPTH, n) f_{i+1} - f_i
    x_last: np.ndarray      # (n,) the last iterate and its step
    f_last: np.ndarray
    x: np.ndarray           # (n,) the caller's iterate and step, for accelerated_step
    f: np.ndarray

    @classmethod
    def allocate(cls, n: int, depth: int) -> "History":
        """depth = 0: no acceleration (zero-size arrays the compiled loop carries)."""
        size = n if depth > 0 else 0
        return cls(np.zeros((depth, size)), np.zeros((depth, size)),
                   *(np.zeros(size) for _ in range(4)))


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def accelerated_step(x, f, count, history):
    """Overwrite the plain step f at iterate x with Anderson's (the module docstring),
    from the count pairs (x, f) seen since the history was last restarted (count = 0:
    restart, the plain step). Returns the new count."""
    depth = history.dx.shape[0]
    n = x.shape[0]
    if count > 0:
        slot = (count - 1) % depth
        for p in range(n):
            history.dx[slot, p] = x[p] - history.x_last[p]
            history.df[slot, p] = f[p] - history.f_last[p]
    for p in range(n):
        history.x_last[p] = x[p]
        history.f_last[p] = f[p]
    k = min(count, depth)
    if k > 0:
        df = np.empty((n, k))
        for j in range(k):
            for p in range(n):
                df[p, j] = history.df[j, p]
        gamma = np.linalg.lstsq(df, history.f_last, rcond=RCOND)[0]
        if np.isfinite(gamma).all():
            for j in range(k):
                for p in range(n):
                    f[p] -= (history.dx[j, p] + history.df[j, p]) * gamma[j]
    return count + 1
