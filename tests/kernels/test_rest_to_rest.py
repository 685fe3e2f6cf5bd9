"""The rest-to-rest closed forms against the general laws, problem by problem.

:func:`trajkit.profiles._kernels.synchronize.plan` takes the closed forms of
:mod:`trajkit.profiles._kernels.rest_to_rest` for moves between states of rest
under symmetric limits and the general laws for everything else; both must give
the same plan: status, duration, limiting joint, each joint's own minimum and
every phase duration (to 1e-12 of the duration: the closed forms round
differently), with every sync mode but phase, ``min_duration`` and discrete
durations.
"""

import math

import numpy as np
import pytest

from trajkit.profiles._kernels import rest_to_rest
from trajkit.profiles._kernels import synchronize as S
from trajkit.profiles._kernels.layout import SIZE, T

TOLERANCE = 1e-12  # relative to the duration


def random_problem(rng, ndof):
    m = np.zeros((11, ndof))
    m[0] = rng.normal(0.0, 2.0, ndof)
    m[1] = rng.normal(0.0, 2.0, ndof)
    if rng.random() < 0.2:
        m[1, 0] = m[0, 0]  # a joint that stays
    if rng.random() < 0.1:
        m[1] = m[0] + rng.normal(0.0, 1e-3, ndof)  # short moves: no limit reached
    v, a = rng.uniform(0.08, 16.0, ndof), rng.uniform(0.08, 16.0, ndof)
    j = rng.uniform(0.08, 16.0, ndof) if rng.random() < 0.7 else np.full(ndof, math.inf)
    m[6], m[7], m[8], m[9], m[10] = -v, v, -a, a, j
    sync = rng.choice([0, 0, 0, 2, 3], ndof).astype(np.int64)
    floor = rng.uniform(0.0, 10.0) if rng.random() < 0.2 else math.nan
    dt = 0.01 if rng.random() < 0.2 else 0.0
    return m, sync, floor, dt


def plans(m, sync, floor, dt, law):
    ndof = m.shape[1]
    control, enabled = np.zeros(ndof, np.int64), np.ones(ndof, np.int64)
    records, own, out = np.zeros((ndof, SIZE)), np.zeros(ndof), np.zeros(4)
    status = law(m, control, sync, enabled, floor, dt, records, own, out)
    return status, records, own, out


@pytest.mark.parametrize("seed", range(4))
def test_closed_forms_plan_as_the_general_laws(seed):
    rng = np.random.default_rng(seed)
    ndof = 4
    compared = 0
    for _ in range(1500):
        m, sync, floor, dt = random_problem(rng, ndof)
        control, enabled = np.zeros(ndof, np.int64), np.ones(ndof, np.int64)
        if not (rest_to_rest.applies(m, control, sync, enabled) and S.ordinary(m)):
            continue
        compared += 1
        fast = plans(m, sync, floor, dt, S.plan)
        general = plans(m, sync, floor, dt, S.general_plan)
        assert fast[0] == general[0] == S.OK
        duration = general[3][0]
        scale = max(duration, 1e-300)
        assert abs(fast[3][0] - duration) <= TOLERANCE * scale
        assert fast[3][1] == general[3][1]  # the limiting joint
        np.testing.assert_allclose(fast[2], general[2], rtol=0, atol=TOLERANCE * scale)
        np.testing.assert_allclose(
            fast[1][:, T : T + 7], general[1][:, T : T + 7], rtol=0, atol=TOLERANCE * scale
        )
    assert compared > 1000


def test_only_rest_to_rest_under_symmetric_limits_applies():
    m, sync, _, _ = random_problem(np.random.default_rng(7), 3)
    sync[:] = 0
    control, enabled = np.zeros(3, np.int64), np.ones(3, np.int64)
    assert rest_to_rest.applies(m, control, sync, enabled)
    for row, value in ((2, 0.1), (3, -0.1), (4, 0.2), (5, 0.2), (6, -99.0), (8, -99.0)):
        moving = m.copy()
        moving[row, 1] = value
        assert not rest_to_rest.applies(moving, control, sync, enabled)
    phase = sync.copy()
    phase[0] = 1
    assert not rest_to_rest.applies(m, control, phase, enabled)
    velocity = control.copy()
    velocity[2] = 1
    assert not rest_to_rest.applies(m, velocity, sync, enabled)


@pytest.mark.parametrize("jmax", [3.0, math.inf])
def test_stretched_profiles_reach_the_target_at_the_duration(jmax):
    # Each shape of the stretch: the acceleration limit held, or not reached.
    prof = np.zeros(SIZE)
    for distance, duration in ((2.0, 4.0), (2.0, 40.0), (1e-3, 1.0), (5.0, 3.1)):
        own = rest_to_rest.fastest(prof, 0.0, distance, 1.5, 2.0, jmax)
        assert own > 0.0
        assert rest_to_rest.timed(prof, 0.0, distance, max(duration, own), 1.5, 2.0, jmax)
        assert prof[T : T + 7].sum() == pytest.approx(max(duration, own), rel=1e-14)
