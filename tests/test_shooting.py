"""core.shooting.newton_picard on small maps whose behaviour is known by hand.

The maps act on (y1, y2); y1 is the slow direction handed to Newton, y2 is left to
plain cycles and Anderson's mixing. Both swap the states a = (1, 1) and b = (1, -1),
a two-cycle through which the iteration passes from a.
"""

import numpy as np

from vibrofric.core.shooting import STALL, newton_picard

SLOW = np.array([[1.0], [0.0]])
A = np.array([1.0, 1.0])
B = np.array([1.0, -1.0])


def swap_map(elsewhere: float | None):
    """y1 -> y1 / 2 + 1/2 (fixed at 1); y2 -> -y2 where |y2| = 1 (a <-> b), else y2 / 2
    (fixed at 0: the orbit (1, 0)) or, with ``elsewhere``, that value: a map on which
    every state off the two-cycle is rejected as far astray. Records its arguments."""
    calls = []

    def cycle(y):
        calls.append(np.array(y))
        y2 = -y[1] if abs(y[1]) == 1.0 else (0.5 * y[1] if elsewhere is None else elsewhere)
        return np.array([0.5 * y[0] + 0.5, y2])

    return cycle, calls


def test_a_two_cycle_anderson_can_combine_is_left_to_it_and_the_orbit_found():
    # From a, the plain step lands on b and the next on a again; Anderson's combination
    # of the two is (1, 0), the orbit itself. A restart at the return would drop the
    # history that finds it, and restart again at every later return.
    cycle, calls = swap_map(elsewhere=None)
    shot = newton_picard(cycle, A.copy(), SLOW, 1e-3, tolerance=1e-12, max_cycles=50)
    assert shot.converged
    np.testing.assert_array_equal(shot.z, [1.0, 0.0])   # the map is exact at its orbit
    assert shot.cycles < 10


def test_a_return_after_the_history_was_dropped_retakes_the_newton_matrix_at_once():
    # Off the two-cycle the map sends y2 far away, so Anderson's combination is refused
    # (its history dropped) and the plain step returns to a: nothing can lead elsewhere
    # from there. The Newton matrix is taken afresh (a probe along y1 from a) at that
    # return, the third iteration, not after STALL iterations without progress.
    cycle, calls = swap_map(elsewhere=1e6)
    shot = newton_picard(cycle, A.copy(), SLOW, 1e-3, tolerance=1e-12, max_cycles=40)
    assert not shot.converged
    probes = [k for k, y in enumerate(calls) if y[0] != 1.0]    # Newton matrix columns
    assert len(probes) >= 2
    # calls: phi(a), probe, phi(b) [accepted], phi(combination) [refused], phi(a)
    # [accepted], then the probe of the restart
    assert probes[1] == 5
    assert probes[1] < 2 * STALL
