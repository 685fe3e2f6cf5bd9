"""The compiled brake pre-profile against ruckig's, and what it promises.

For start states beyond the limits (or bound to leave them) the brake must end
in a state inside the limits from which the velocity can be brought to rest
(acceleration ramped to zero at full jerk) without crossing a limit; its jerks
are bounded by j_max; and its durations, jerks and braked states equal ruckig's
(``Trajectory.profiles[0][0].brake`` exposes ``duration, t, j, a, v, p``), up to
1e-12 (the formulas are the same; only the compiler's rounding may differ).
States within the limits give no brake.
"""

import math

import numpy as np
import pytest

from trajkit.profiles._kernels.brake import (
    position_brake,
    second_order_position_brake,
    second_order_velocity_brake,
    velocity_brake,
)
from trajkit.profiles._kernels.layout import (
    BRAKE_A,
    BRAKE_DURATION,
    BRAKE_J,
    BRAKE_P,
    BRAKE_T,
    BRAKE_V,
    A,
    P,
    V,
)
from trajkit.profiles._kernels.profile import (
    finalize_brake,
    finalize_brake_second_order,
    new_profile,
)

ruckig = pytest.importorskip("ruckig", reason="ruckig (test oracle) is not installed")
from ruckig import ControlInterface, InputParameter, Result, Ruckig, Trajectory  # noqa: E402

SEED = 7321
N = 200
# The brake's 2.2e-14 s margins leave a velocity up to ~|a| * 2.2e-14 beyond its limit.
TOL = 1e-12

OTG = Ruckig(1)
TRAJ = Trajectory(1)


def _ruckig_brake(v0, a0, v_max, v_min, a_max, a_min, j_max, interface="position"):
    inp = InputParameter(1)
    inp.current_position = [0.3]
    inp.current_velocity = [v0]
    inp.current_acceleration = [a0]
    inp.target_position = [0.0]
    inp.max_velocity = [v_max]
    inp.min_velocity = [v_min]
    inp.max_acceleration = [a_max]
    inp.min_acceleration = [a_min]
    inp.max_jerk = [j_max]
    if interface == "velocity":
        inp.control_interface = ControlInterface.Velocity
    assert OTG.calculate(inp, TRAJ) == Result.Working
    return TRAJ.profiles[0][0].brake


def _ours(v0, a0, v_max, v_min, a_max, a_min, j_max):
    prof = new_profile()
    prof[P], prof[V], prof[A] = 0.3, v0, a0
    position_brake(prof, v0, a0, v_max, v_min, a_max, a_min, j_max)
    finalize_brake(prof)
    return prof


def _limits(rng):
    """Asymmetric limits: v_max, v_min, a_max, a_min, j_max."""
    return (
        rng.uniform(0.5, 3.0),
        -rng.uniform(0.5, 3.0),
        rng.uniform(0.5, 3.0),
        -rng.uniform(0.5, 3.0),
        rng.uniform(0.5, 5.0),
    )


def _state(rng, case, v_max, v_min, a_max, a_min, j_max):
    """A start state of the given kind (all but 'inside' need braking)."""
    if case == "v_above":
        return v_max + rng.uniform(0.01, 3.0), rng.uniform(a_min, a_max)
    if case == "v_below":
        return v_min - rng.uniform(0.01, 3.0), rng.uniform(a_min, a_max)
    if case == "a_above":
        return rng.uniform(v_min - 2.0, v_max + 2.0), a_max + rng.uniform(0.01, 3.0)
    if case == "a_below":
        return rng.uniform(v_min - 2.0, v_max + 2.0), a_min - rng.uniform(0.01, 3.0)
    if case == "overshoot_up":
        # Inside both limits, but a0 > 0 carries v past v_max before a reaches 0.
        a0 = rng.uniform(0.2, 1.0) * a_max
        reach = a0 * a0 / (2.0 * j_max)
        return v_max - rng.uniform(0.01, 0.99) * min(reach, v_max - v_min), a0
    if case == "overshoot_down":
        a0 = rng.uniform(0.2, 1.0) * a_min
        reach = a0 * a0 / (2.0 * j_max)
        return v_min + rng.uniform(0.01, 0.99) * min(reach, v_max - v_min), a0
    assert case == "inside"
    while True:
        v0, a0 = rng.uniform(v_min, v_max), rng.uniform(a_min, a_max)
        v_rest = v0 + a0 * abs(a0) / (2.0 * j_max)
        if v_min < v_rest < v_max:
            return v0, a0


def _assert_safe(v, a, v_max, v_min, a_max, a_min, j_max):
    """Inside the limits, and ramping a to zero at j_max stays inside too.

    Where the velocity band is narrower than what ramping a limit acceleration
    to zero changes the velocity by, no state at that acceleration is inside for
    good: the brake then ends beyond the velocity limit, heading into the band,
    exactly where the ramp to a = 0 ends on the opposite limit. Returns whether
    that happened.
    """
    assert a_min - TOL <= a <= a_max + TOL
    v_rest = v + a * abs(a) / (2.0 * j_max)
    assert v_min - TOL <= v_rest <= v_max + TOL
    if v > v_max + TOL:
        assert a < 0.0 and v_rest == pytest.approx(v_min, abs=1e-9)
        return True
    if v < v_min - TOL:
        assert a > 0.0 and v_rest == pytest.approx(v_max, abs=1e-9)
        return True
    return False


BRAKING_CASES = ["v_above", "v_below", "a_above", "a_below", "overshoot_up", "overshoot_down"]


@pytest.mark.parametrize("case", BRAKING_CASES)
def test_position_brake_ends_safe_and_matches_ruckig(case):
    rng = np.random.default_rng(SEED + BRAKING_CASES.index(case))
    narrow = 0
    for _ in range(N):
        limits = _limits(rng)
        j_max = limits[4]
        v0, a0 = _state(rng, case, *limits)
        prof = _ours(v0, a0, *limits)
        assert prof[BRAKE_DURATION] > 0.0, (case, v0, a0, limits)
        for k in range(2):
            assert prof[BRAKE_T + k] >= 0.0
            assert abs(prof[BRAKE_J + k]) <= j_max
        # The second phase holds an acceleration limit: no jerk.
        assert prof[BRAKE_J + 1] == 0.0
        narrow += _assert_safe(prof[V], prof[A], *limits)

        ref = _ruckig_brake(v0, a0, *limits)
        np.testing.assert_allclose(prof[BRAKE_T : BRAKE_T + 2], ref.t, rtol=1e-12, atol=1e-12)
        np.testing.assert_array_equal(prof[BRAKE_J : BRAKE_J + 2], ref.j)
        assert prof[BRAKE_DURATION] == pytest.approx(ref.duration, rel=1e-12, abs=1e-12)
        # Braked states at the start of each phase that runs.
        for k in range(2 if prof[BRAKE_T + 1] > 0.0 else 1):
            for off, ref_vals in ((BRAKE_P, ref.p), (BRAKE_V, ref.v), (BRAKE_A, ref.a)):
                assert prof[off + k] == pytest.approx(ref_vals[k], rel=1e-10, abs=1e-10)
    # Most cases end inside the band (narrow ones arise from the random limits).
    assert narrow < N // 4


def test_position_brake_inside_limits_is_none():
    rng = np.random.default_rng(SEED + 10)
    for _ in range(N):
        limits = _limits(rng)
        v0, a0 = _state(rng, "inside", *limits)
        prof = _ours(v0, a0, *limits)
        np.testing.assert_array_equal(prof[BRAKE_T : BRAKE_T + 2], [0.0, 0.0])
        np.testing.assert_array_equal(prof[BRAKE_J : BRAKE_J + 2], [0.0, 0.0])
        assert prof[BRAKE_DURATION] == 0.0
        assert (prof[V], prof[A]) == (v0, a0)  # the start state is untouched
        assert _ruckig_brake(v0, a0, *limits).duration == 0.0


@pytest.mark.parametrize(
    ("v0", "a0"),
    [
        (1.0, 0.0),  # on the velocity limit, at rest in acceleration
        (0.0, 2.0),  # on the acceleration limit, v far from overshooting
        (-1.0, 0.0),
        (0.0, -2.0),
        (0.5, 2.0),  # on the acceleration limit and overshooting v_max
        (-0.5, -2.0),
    ],
)
def test_position_brake_on_the_limits(v0, a0):
    limits = (1.0, -1.0, 2.0, -2.0, 3.0)
    prof = _ours(v0, a0, *limits)
    ref = _ruckig_brake(v0, a0, *limits)
    np.testing.assert_allclose(prof[BRAKE_T : BRAKE_T + 2], ref.t, rtol=1e-12, atol=1e-12)
    np.testing.assert_array_equal(prof[BRAKE_J : BRAKE_J + 2], ref.j)
    _assert_safe(prof[V], prof[A], *limits)
    # Exactly on a limit without overshoot needs no brake.
    overshoots = abs(v0 + a0 * abs(a0) / 6.0) > 1.0
    assert (prof[BRAKE_DURATION] > 0.0) == overshoots


def test_position_brake_known_values():
    # v0 = 2 above v_max = 1 at a0 = 0, limits 1: ramp a to -1 (1 s, v -> 1.5),
    # then hold a = -1 until v = 1 (0.5 s).
    prof = _ours(2.0, 0.0, 1.0, -1.0, 1.0, -1.0, 1.0)
    np.testing.assert_allclose(prof[BRAKE_T : BRAKE_T + 2], [1.0, 0.5], atol=1e-13)
    np.testing.assert_array_equal(prof[BRAKE_J : BRAKE_J + 2], [-1.0, 0.0])
    assert prof[V] == pytest.approx(1.0, abs=1e-13)
    assert prof[A] == pytest.approx(-1.0, abs=1e-13)


def test_position_brake_zero_limits_disable_braking():
    for limits in ((1.0, -1.0, 1.0, -1.0, 0.0), (1.0, -1.0, 0.0, -1.0, 1.0),
                   (1.0, -1.0, 1.0, 0.0, 1.0)):  # fmt: skip
        prof = new_profile()
        prof[BRAKE_T : BRAKE_T + 2] = 5.0  # stale values must be cleared
        prof[BRAKE_J : BRAKE_J + 2] = 5.0
        position_brake(prof, 3.0, 3.0, *limits)
        np.testing.assert_array_equal(prof[BRAKE_T : BRAKE_J + 2], np.zeros(4))


@pytest.mark.parametrize("side", [1.0, -1.0])
def test_second_order_position_brake(side):
    rng = np.random.default_rng(SEED + 20 + int(side))
    for _ in range(N):
        v_max, v_min, a_max, a_min, _j = _limits(rng)
        v0 = v_max + rng.uniform(0.01, 3.0) if side > 0 else v_min - rng.uniform(0.01, 3.0)
        prof = new_profile()
        prof[P], prof[V] = 0.3, v0
        second_order_position_brake(prof, v0, v_max, v_min, a_max, a_min)
        assert prof[BRAKE_A] == (a_min if side > 0 else a_max)
        assert prof[BRAKE_T + 1] == 0.0 and prof[BRAKE_A + 1] == 0.0
        np.testing.assert_array_equal(prof[BRAKE_J : BRAKE_J + 2], [0.0, 0.0])
        finalize_brake_second_order(prof)
        assert v_min - TOL <= prof[V] <= v_max + TOL
        # It brakes to the limit it was beyond.
        assert prof[V] == pytest.approx(v_max if side > 0 else v_min, abs=TOL)

        ref = _ruckig_brake(v0, 0.0, v_max, v_min, a_max, a_min, math.inf)
        assert prof[BRAKE_T] == pytest.approx(ref.t[0], rel=1e-12, abs=1e-12)
        assert prof[BRAKE_A] == ref.a[0]
        assert prof[BRAKE_DURATION] == pytest.approx(ref.duration, rel=1e-12, abs=1e-12)
        assert prof[BRAKE_V] == pytest.approx(ref.v[0], rel=1e-12)


def test_second_order_position_brake_inside_or_zero_limits_is_none():
    rng = np.random.default_rng(SEED + 30)
    for _ in range(N):
        v_max, v_min, a_max, a_min, _j = _limits(rng)
        v0 = rng.uniform(v_min, v_max)
        prof = new_profile()
        prof[BRAKE_A] = 9.0  # stale
        second_order_position_brake(prof, v0, v_max, v_min, a_max, a_min)
        np.testing.assert_array_equal(prof[BRAKE_T : BRAKE_A + 2], np.zeros(6))
        assert _ruckig_brake(v0, 0.0, v_max, v_min, a_max, a_min, math.inf).duration == 0.0
    prof = new_profile()
    second_order_position_brake(prof, 5.0, 1.0, -1.0, 0.0, -1.0)
    assert prof[BRAKE_T] == 0.0


@pytest.mark.parametrize("side", [1.0, -1.0, 0.0])
def test_velocity_brake(side):
    rng = np.random.default_rng(SEED + 40 + int(side))
    for _ in range(N):
        v_max, v_min, a_max, a_min, j_max = _limits(rng)
        if side > 0:
            a0 = a_max + rng.uniform(0.01, 3.0)
        elif side < 0:
            a0 = a_min - rng.uniform(0.01, 3.0)
        else:
            a0 = rng.uniform(a_min, a_max)
        v0 = rng.uniform(-5.0, 5.0)  # irrelevant without a position target
        prof = new_profile()
        prof[P], prof[V], prof[A] = 0.3, v0, a0
        velocity_brake(prof, a0, a_max, a_min, j_max)
        assert prof[BRAKE_T + 1] == 0.0 and prof[BRAKE_J + 1] == 0.0
        assert prof[BRAKE_J] == -side * j_max
        finalize_brake(prof)
        assert a_min - TOL <= prof[A] <= a_max + TOL
        if side != 0.0:
            # Ramped back exactly to the limit it was beyond (to the 2.2e-14 s margin).
            assert prof[A] == pytest.approx(a_max if side > 0 else a_min, abs=TOL)
        else:
            assert prof[BRAKE_DURATION] == 0.0

        ref = _ruckig_brake(v0, a0, v_max, v_min, a_max, a_min, j_max, "velocity")
        np.testing.assert_allclose(prof[BRAKE_T : BRAKE_T + 2], ref.t, rtol=1e-12, atol=1e-12)
        np.testing.assert_array_equal(prof[BRAKE_J : BRAKE_J + 2], ref.j)
        assert prof[BRAKE_DURATION] == pytest.approx(ref.duration, rel=1e-12, abs=1e-12)


def test_velocity_brake_zero_jerk_is_none():
    prof = new_profile()
    velocity_brake(prof, 5.0, 1.0, -1.0, 0.0)
    np.testing.assert_array_equal(prof[BRAKE_T : BRAKE_J + 2], np.zeros(4))


def test_second_order_velocity_brake_clears():
    prof = new_profile()
    prof[BRAKE_T : BRAKE_J + 2] = 1.0
    second_order_velocity_brake(prof)
    np.testing.assert_array_equal(prof[BRAKE_T : BRAKE_J + 2], np.zeros(4))
    finalize_brake(prof)
    assert prof[BRAKE_DURATION] == 0.0
