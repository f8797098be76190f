"""What this machine can do: the roofline a time loop is measured against.

Two numbers, measured here by small compiled kernels rather than taken from a
data sheet (a virtual machine's share of a core is what the loops get):

    bandwidth(nbytes)     bytes/s streamed from the cache level that holds a
                          working set of ``nbytes`` (L1 ... DRAM)
    multiply_add_rate()   multiply-adds/s with both operands streamed from L1:
                          the most a sparse or dense product can do, since each
                          of its multiply-adds reads a matrix entry

A kernel that moves B bytes and does F multiply-adds cannot take less than
max(B / bandwidth(B), F / multiply_add_rate()) seconds: its roofline bound.
"""

import functools
import platform
import time

import numpy as np
from numba import njit

# Operands of the multiply-add rate: 2 x 8 KB, well inside any L1 data cache.
_L1_DOUBLES = 1024


@njit(cache=True, fastmath=True)
def _dot(a, b):
    s = 0.0
    for k in range(a.shape[0]):
        s += a[k] * b[k]
    return s


@njit(cache=True, fastmath=True)
def _dots(a, b, repeats):
    """``repeats`` dot products of a and b (vectorized, reordered: fastmath)."""
    total = 0.0
    for _ in range(repeats):
        total += _dot(a, b)
    return total


def _best_time(a, b, repeats: int, trials: int = 5) -> float:
    _dots(a, b, 1)
    best = np.inf
    for _ in range(trials):
        start = time.perf_counter()
        _dots(a, b, repeats)
        best = min(best, time.perf_counter() - start)
    return best


@functools.cache
def bandwidth(nbytes: int) -> float:
    """Bytes/s read from a working set of ``nbytes`` (two arrays of half that, dotted),
    best of 5 passes of about 0.05 s."""
    n = max(int(nbytes) // 16, 64)
    a, b = np.full(n, 0.5), np.full(n, 2.0)
    repeats = max(1, int(4e7 // n))
    return 16.0 * n * repeats / _best_time(a, b, repeats)


@functools.cache
def multiply_add_rate() -> float:
    """Multiply-adds/s, operands from L1, best of 5 passes of about 0.05 s."""
    a, b = np.full(_L1_DOUBLES, 0.5), np.full(_L1_DOUBLES, 2.0)
    repeats = int(4e8 // _L1_DOUBLES)
    return _L1_DOUBLES * repeats / _best_time(a, b, repeats)


def bound(multiply_adds: float, nbytes: float) -> float:
    """Seconds: the roofline bound of ``multiply_adds`` on ``nbytes`` of working set."""
    if multiply_adds == 0 and nbytes == 0:
        return 0.0
    return max(nbytes / bandwidth(int(nbytes)), multiply_adds / multiply_add_rate())


def cpu_name() -> str:
    """The CPU's model name (Linux: /proc/cpuinfo), else what platform reports."""
    try:
        with open("/proc/cpuinfo") as cpuinfo:
            for line in cpuinfo:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()
