"""The small kernels several laws share: keeping a candidate, a single profile's block times.

The laws' own tests cover them through the profiles they plan; these pin the
contracts the laws rely on (the next scratch row starts from the same boundary; a
drifting single profile blocks every longer duration).
"""

import math

import numpy as np

from trajkit.profiles._kernels.layout import AF, BRAKE_DURATION, PF, SIZE, VF, A, P, T, V
from trajkit.profiles._kernels.profile import duration, keep, set_boundary, single_profile


def _rows(n: int) -> np.ndarray:
    valid = np.full((n, SIZE), np.nan)
    valid[0, :] = 0.0
    set_boundary(valid[0], 0.5, -1.0, 2.0, 3.0, 0.25, -0.5)
    valid[0, BRAKE_DURATION] = 0.125
    return valid


def test_keep_counts_the_candidate_and_hands_its_boundary_to_the_next_row() -> None:
    valid = _rows(3)
    valid[0, T + 3] = 7.0  # a phase of the kept candidate: not carried over
    assert keep(valid, 0) == 1
    for field in (P, V, A, PF, VF, AF, BRAKE_DURATION):
        assert valid[1, field] == valid[0, field]
    assert math.isnan(valid[1, T + 3])


def test_keep_in_the_last_row_only_counts() -> None:
    valid = _rows(1)
    before = valid.copy()
    assert keep(valid, 0) == 1
    np.testing.assert_array_equal(valid, before)


def test_a_single_profile_blocks_nothing_unless_it_drifts() -> None:
    prof = _rows(1)[0]
    times = np.zeros(5)
    single_profile(times, prof, False)
    assert times[0] == duration(prof) == 0.125
    assert np.all(np.isinf(times[1:]))
    single_profile(times, prof, True)
    assert times[1] == times[0]
    assert np.all(np.isinf(times[2:]))
