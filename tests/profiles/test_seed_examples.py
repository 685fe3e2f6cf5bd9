"""The coursework seeds' polynomial problems, computed exactly (their hand values are not).

Seed 000 §3.1: a two-joint RRBot, cubic rest-to-rest moves under per-joint velocity limits.
Seed 003: a cubic straight line in task space from P_A to P_B in 10 s.
(Seed 004's A a = b examples live in test_polynomial.py next to polynomial().)
"""

from __future__ import annotations

from math import radians

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import support
import trajkit as tk
from support import CLOSED_FORM

# ------------------------------------------------------------------------ seed 000 §3.1
REGISTRATION = 5351
JOINT_1_DEG = round(REGISTRATION / 80)  # round(66.8875) = 67
JOINT_2_DEG = -round(REGISTRATION / 120)  # -round(44.59...) = -45
Q0 = np.radians([0.0, 0.0])
QF = np.radians([JOINT_1_DEG, JOINT_2_DEG])
VMAX = np.radians([9.0, 11.0])  # 9 deg/s and 11 deg/s
# Cubic rest to rest: peak velocity 1.5 D / T at T/2, so T_min = 1.5 D / vmax per joint.
T_JOINT_1 = 1.5 * 67 / 9  # 11.1666... s
T_JOINT_2 = 1.5 * 45 / 11  # 6.1363... s


def test_seed_000_targets():
    assert JOINT_1_DEG == 67
    assert JOINT_2_DEG == -45


def test_seed_000_minimum_common_duration():
    tr = tk.cubic(Q0, QF, vmax=VMAX)
    assert tr.duration == pytest.approx(T_JOINT_1, rel=CLOSED_FORM)
    assert tr.duration == pytest.approx(11.0 + 1.0 / 6.0, rel=CLOSED_FORM)
    assert tr.info["minimum_durations"] == pytest.approx((T_JOINT_1, T_JOINT_2), rel=CLOSED_FORM)
    assert tr.info["limiting_joint"] == 0
    assert tr.info["limiting"] == "vmax"
    assert tr.check(tk.Limits(velocity=VMAX)).ok
    velocity = tr.extrema(1)
    # Joint 1 reaches exactly 9 deg/s at mid-move; joint 2 runs slower than it could.
    assert velocity.maximum[0] == pytest.approx(VMAX[0], rel=CLOSED_FORM)
    assert velocity.time_of_maximum[0] == pytest.approx(T_JOINT_1 / 2, rel=CLOSED_FORM)
    assert velocity.minimum[1] == pytest.approx(-radians(1.5 * 45 / T_JOINT_1), rel=CLOSED_FORM)
    assert abs(velocity.minimum[1]) < VMAX[1]
    support.assert_state(tr.position(tr.duration), QF)
    support.assert_state(tr.velocity(np.array([0.0, tr.duration])), np.zeros((2, 2)))


def test_seed_000_the_hand_bounds_are_rounded_low():
    # The seed derives t_f >= 11.1 s (joint 1, from 0.37 pi for 67 deg) and t_f >= 6.11 s
    # (joint 2, from pi/16.3 for 11 deg/s); both are below the exact minima.
    assert T_JOINT_1 > 11.1
    assert T_JOINT_2 > 6.11
    tr = tk.cubic(Q0, QF, vmax=VMAX)
    assert tr.info["minimum_durations"][0] > 11.1
    assert tr.info["minimum_durations"][1] > 6.11


def test_seed_000_hand_choice_of_11_s_violates_joint_1():
    tr = tk.cubic(Q0, QF, 11.0)
    report = tr.check(tk.Limits(velocity=VMAX))
    assert not report.ok
    assert len(report.violations) == 1
    violation = report.violations[0]
    assert violation.quantity == "velocity"
    assert violation.joint == 0
    assert violation.time == pytest.approx(5.5, rel=CLOSED_FORM)
    assert violation.value == pytest.approx(radians(1.5 * 67 / 11), rel=CLOSED_FORM)  # 9.136 deg/s
    assert violation.bound == pytest.approx(VMAX[0], rel=CLOSED_FORM)
    # Asked to verify 11 s against the limits, the planner refuses and gives the minimum.
    with pytest.raises(tk.InfeasibleError) as raised:
        tk.cubic(Q0, QF, 11.0, vmax=VMAX)
    message = str(raised.value)
    assert "duration 11 s is below the minimum 11.1667 s" in message
    assert f"vmax={VMAX[0]:.6g} rad/s (joint 1)" in message


def test_seed_000_hand_choice_of_6_s_violates_both_joints():
    # Joint 1 would need 11.17 s and joint 2 6.14 s: 6 s is too short for both.
    tr = tk.cubic(Q0, QF, 6.0)
    report = tr.check(tk.Limits(velocity=VMAX))
    assert {(v.quantity, v.joint) for v in report.violations} == {
        ("velocity", 0),
        ("velocity", 1),
    }
    by_joint = {v.joint: v for v in report.violations}
    assert by_joint[0].value == pytest.approx(radians(1.5 * 67 / 6), rel=CLOSED_FORM)  # 16.75
    assert by_joint[1].value == pytest.approx(-radians(1.5 * 45 / 6), rel=CLOSED_FORM)  # -11.25
    assert by_joint[1].bound == pytest.approx(-VMAX[1], rel=CLOSED_FORM)


def test_seed_000_rounded_coefficients_explain_the_nonzero_end_velocity():
    # The seed rounds a2, a3 to 0.03 and -0.002 and then finds q1'(11) = -0.066 rad/s
    # "~= 0"; the exact cubic ends at rest. Exact: a2 = 3D/T^2, a3 = -2D/T^3.
    T = 11.0
    tr = tk.cubic(Q0, QF, T)
    D = QF - Q0
    a = tr.absolute_coefficients()[::-1, 0, :]  # ascending powers, per joint
    np.testing.assert_allclose(a[2], 3 * D / T**2, rtol=CLOSED_FORM)
    np.testing.assert_allclose(a[3], -2 * D / T**3, rtol=CLOSED_FORM)
    assert a[2][0] > 0 > a[2][1]  # the seed's "(2): a2 = -1.11 pi / 121" has the wrong sign
    np.testing.assert_allclose(tr.velocity(T), 0.0, atol=1e-15)
    seed_velocity = 0.06 * T - 0.006 * T**2  # the seed's q1' with rounded coefficients
    assert seed_velocity == pytest.approx(-0.066)


def test_seed_000_docstring_example():
    tr = tk.cubic(np.radians([0, 0]), np.radians([67, -45]), vmax=np.radians([9, 11]))
    assert round(tr.duration, 6) == 11.166667


# ------------------------------------------------------------------------------ seed 003
P_A = np.array([0.0, -12.0, 20.0])
P_B = np.array([10.0, 12.0, 20.0])
TF = 10.0


def _seed_003_closed_form(t: float) -> np.ndarray:
    return P_A + 3 / TF**2 * (P_B - P_A) * t**2 - 2 / TF**3 * (P_B - P_A) * t**3


def test_seed_003_positions_at_start_middle_end():
    tr = tk.cubic(P_A, P_B, TF)
    assert tr.ndof == 3
    support.assert_state(tr.position(0.0), P_A)
    support.assert_state(tr.position(5.0), (P_A + P_B) / 2)  # (5, 0, 20)
    support.assert_state(tr.position(10.0), P_B)
    support.assert_state(tr.velocity(np.array([0.0, 10.0])), np.zeros((2, 3)))
    # Peak speed along the line: 1.5 |P_B - P_A| / T_f at t = 5 s.
    speed = np.linalg.norm(tr.velocity(5.0))
    assert speed == pytest.approx(1.5 * np.linalg.norm(P_B - P_A) / TF, rel=CLOSED_FORM)


@given(t=st.floats(0.0, TF))
def test_seed_003_closed_form_at_random_times(t):
    tr = tk.cubic(P_A, P_B, TF)
    support.assert_state(tr.position(t), _seed_003_closed_form(t))
    velocity = 6 / TF**2 * (P_B - P_A) * t - 6 / TF**3 * (P_B - P_A) * t**2
    support.assert_state(tr.velocity(t), velocity)


def test_seed_003_is_a_straight_line():
    tr = tk.cubic(P_A, P_B, TF)
    t = np.random.default_rng(3).uniform(0.0, TF, 200)
    t.sort()
    points = tr.position(t)
    direction = (P_B - P_A) / np.linalg.norm(P_B - P_A)
    offsets = points - P_A
    # Collinear: no component across the line; z stays at 20.
    across = offsets - np.outer(offsets @ direction, direction)
    assert np.abs(across).max() <= CLOSED_FORM * np.linalg.norm(P_B - P_A)
    np.testing.assert_allclose(points[:, 2], 20.0, rtol=CLOSED_FORM)
    # Monotone progress from P_A to P_B (never overshoots or backs up).
    progress = offsets @ direction / np.linalg.norm(P_B - P_A)
    assert np.all(np.diff(progress) >= -CLOSED_FORM)
    assert progress.min() >= -CLOSED_FORM
    assert progress.max() <= 1 + CLOSED_FORM


def test_seed_003_sampling_has_no_lag_and_reaches_p_b():
    # The seed's MATLAB stores S((k-2) dt) at t(k) = (k-1) dt and stops at 9.999 s; sampling
    # the trajectory puts S(k dt) at index k and ends exactly at T_f on P_B.
    dt = 0.001
    samples = tk.cubic(P_A, P_B, TF).sample(dt)
    assert samples.t.size == 10001
    assert samples.t[-1] == TF
    support.assert_state(samples.q[-1], P_B)
    for k in (0, 1, 2, 5000, 7777, 10000):
        assert samples.t[k] == pytest.approx(k * dt, rel=1e-15, abs=1e-15)
        support.assert_state(samples.q[k], _seed_003_closed_form(k * dt))
