"""fem.integrators.borrowed: arrays without reference counts, the same memory and values."""

import sys
from typing import NamedTuple

import numpy as np
import pytest
from numba import njit
from numba.core.errors import TypingError

from vibrofric.fem.integrators.borrowed import borrowed


class Pair(NamedTuple):
    values: np.ndarray
    scale: float


@njit
def _scaled_through_borrowed(pair, matrix):
    pair, matrix = borrowed((pair, matrix))
    for k in range(pair.values.shape[0]):
        pair.values[k] *= pair.scale
    matrix[1, :] = pair.values[:2]     # a view of a borrowed array is borrowed too
    return matrix.sum()


def test_a_borrowed_array_is_the_callers_memory():
    values, matrix = np.arange(1.0, 4.0), np.zeros((2, 2))
    _scaled_through_borrowed(Pair(values.copy(), 1.0), matrix.copy())   # compiled
    counts = sys.getrefcount(values), sys.getrefcount(matrix)
    total = _scaled_through_borrowed(Pair(values, 2.0), matrix)
    np.testing.assert_array_equal(values, [2.0, 4.0, 6.0])
    np.testing.assert_array_equal(matrix, [[0.0, 0.0], [2.0, 4.0]])
    assert total == 6.0
    # numba took and gave back the same Python references: none leaked or lost
    assert (sys.getrefcount(values), sys.getrefcount(matrix)) == counts


@njit
def _borrow_a_list(items):
    return borrowed(items)


def test_only_arrays_and_tuples_of_them_can_be_borrowed():
    from numba.typed import List

    with pytest.raises(TypingError):
        _borrow_a_list(List([1.0, 2.0]))
