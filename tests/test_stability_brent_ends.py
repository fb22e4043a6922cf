"""A threshold's refinement solves each trial speed once: Brent's method is handed the real parts
already solved at the bracket's two ends (each a whole eigen-solution of the machine) instead of
solving them again (review_ana finding 1). A closed-form real part, so the thresholds are known."""
import numpy as np
import pytest

from rotordyn_modal.analysis.stability import threshold_speeds

SPEEDS = np.linspace(0.0, 10.0, 11)      # [rad/s]
ZERO = 4.3                               # [rad/s], where the real part crosses zero
SLOPE = 0.02                             # [1/s per rad/s]


def _real_part(speed):
    return SLOPE * (speed - ZERO)


def _eigenvalues():
    """One lightly damped mode whose real part rises through zero at ``ZERO``; (N, 1)."""
    return (_real_part(SPEEDS) + 10j)[:, None]


def _largest_by_root(calls):
    def largest(speed, clip=True, near=None):
        calls.append(float(speed))
        return _real_part(speed)
    return largest


def _largest_plain(calls):
    def largest(speed, clip=True):          # a caller's own, without ``near``: Brent's route
        calls.append(float(speed))
        return _real_part(speed)
    return largest


@pytest.mark.parametrize("make", [_largest_by_root, _largest_plain], ids=["crossing root", "largest real part"])
def test_each_trial_speed_of_a_threshold_is_solved_once(make):
    calls = []
    found, modes, onsets = threshold_speeds(None, SPEEDS, _eigenvalues(), np.zeros(len(SPEEDS)), make(calls))
    assert found == pytest.approx([ZERO], rel=1e-12) and list(modes) == [1] and list(onsets) == [True]
    assert 4.0 in calls and 5.0 in calls              # the bracket's ends, solved again once
    assert len(calls) == len(set(calls)), sorted(calls)
