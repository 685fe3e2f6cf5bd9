"""Tests of trajkit.taskspace.to_joint_space: task motions mapped to checked joint splines.

Seeds 002 (planar 2R) and 003 (3-DOF spatial arm) end to end against their own
closed-form inverse kinematics; RRBot and the UR5; unreachable samples,
singularities, joint limits and branch selection; bad input.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import support
from support import CLOSED_FORM
from trajkit.errors import InfeasibleError, InvalidInputError, UnreachableError
from trajkit.kinematics import UR5, DHRow, Planar2R, RRBot, SerialChain, Spatial3R
from trajkit.rotations import rotation_error
from trajkit.taskspace import (
    Arc,
    Ellipse,
    JointSpacePlan,
    Line,
    through_poses,
    timed,
    to_joint_space,
)

# Tolerances ---------------------------------------------------------------------
PATH_TOL = 1e-9  # FK of the joint spline against the task path (length unit)
IK_TOL = 1e-9  # joint samples against a closed-form inverse kinematics (rad)
RATE_TOL = 1e-9  # J q̇ against the task velocity, relative to max(1, |v|)
EXACT = 1e-12  # samples the spline must interpolate exactly
PATH_ERROR_FACTOR = 1.5  # dense FK error vs path_error, measured at quarter points only
PEAK_RTOL = 1e-5  # dense sampling against exact extrema of a spline piece
LIMIT_RTOL = 1e-9  # the slack trajkit's own limit checks allow
FEW = settings(max_examples=12, deadline=None)

SEED003_LENGTHS = (5.0, 10.0, 8.0, 12.0)  # l0..l3 (cm)


# ------------------------------------------------------------------------- helpers
def seed003_ik(points: np.ndarray, lengths=SEED003_LENGTHS) -> np.ndarray:
    """The seed's closed-form inverse kinematics, transcribed as given."""
    l0, l1, l2, l3 = lengths
    x, y, z = points.T
    q3 = np.arccos((x**2 + y**2 + (z - l0) ** 2 - l1**2 - l2**2 - l3**2) / (2 * l2 * l3))
    q2 = np.arcsin(y / np.sqrt((l2 + l3 * np.cos(q3)) ** 2 + (l3 * np.sin(q3)) ** 2)) - np.arctan2(
        l3 * np.sin(q3), l2 + l3 * np.cos(q3)
    )
    reach = l3 * np.cos(q2 + q3) + l2 * np.cos(q2)
    q1 = -np.arcsin(x / np.sqrt(reach**2 + l1**2)) + np.arctan2(reach, l1)
    return np.stack([q1, q2, q3], axis=1)


def seed002_ik(points: np.ndarray, l1: float, l2: float) -> np.ndarray:
    """The seed's planar 2R formulas: elbow with sqrt(1 - D^2) > 0."""
    x, y = points[:, 0], points[:, 1]
    d = (x**2 + y**2 - l1**2 - l2**2) / (2 * l1 * l2)
    theta2 = np.arctan2(np.sqrt(1 - d**2), d)
    theta1 = np.arctan2(y, x) - np.arctan2(l2 * np.sin(theta2), l1 + l2 * np.cos(theta2))
    return np.stack([theta1, theta2], axis=1)


def wrapped(angle: np.ndarray) -> np.ndarray:
    """Angles to (-pi, pi]."""
    return np.angle(np.exp(1j * np.asarray(angle)))


def tool_positions(robot: SerialChain, plan: JointSpacePlan, t: np.ndarray) -> np.ndarray:
    return robot.fk(plan.trajectory.position(t))[:, :3, 3]


def seed003(**kwargs):
    arm = Spatial3R(*SEED003_LENGTHS)
    motion = timed(Line([0.0, -12.0, 20.0], [10.0, 12.0, 20.0]), "cubic", duration=10.0)
    return arm, motion, to_joint_space(arm, motion, ik_step=0.01, **kwargs)


def seed002(l1: float, l2: float, period: float = 5.0, **kwargs):
    h = 2.0 / 3.0 * (l1 + l2)
    arm = Planar2R(l1, l2)
    segment = Ellipse([0.0, h, 0.0], 0.9 * np.sqrt((l1 + l2) ** 2 - h**2), 0.0)
    motion = timed(segment, "linear", duration=period)
    return arm, motion, to_joint_space(arm, motion, ik_step=0.01, **kwargs)


def assert_samples_are_interpolated(plan: JointSpacePlan) -> None:
    np.testing.assert_array_equal(plan.trajectory.breakpoints, plan.t)
    support.assert_state(plan.trajectory.position(plan.t), plan.q, rtol=EXACT)
    support.assert_state(plan.trajectory.velocity(plan.t), plan.qd, rtol=EXACT)
    support.assert_state(plan.trajectory.acceleration(plan.t), plan.qdd, rtol=EXACT)


# ------------------------------------------------------------------------- seed 003
def test_seed003_tool_follows_the_line_at_random_times():
    arm, motion, plan = seed003()
    assert plan.ok and plan.problems() == []
    assert plan.first_violation is None and plan.singular_time is None
    assert plan.path_error < PATH_TOL
    t = np.random.default_rng(2003).uniform(0.0, 10.0, 12_000)
    np.testing.assert_allclose(
        tool_positions(arm, plan, t), motion.state(t).position, rtol=0, atol=PATH_TOL
    )
    # Samples every dt, the last one at the end.
    assert plan.t.size == 1001 and plan.t[-1] == 10.0
    np.testing.assert_allclose(np.diff(plan.t), 0.01, rtol=1e-9)
    assert plan.trajectory.info["planner"] == "to_joint_space"


def test_seed003_samples_equal_the_seed_closed_form_ik():
    arm, motion, plan = seed003()
    expected = seed003_ik(motion.state(plan.t).position)
    # All three of the seed's formulas agree with branch 0 along its line (z > l0).
    np.testing.assert_allclose(plan.q, expected, rtol=0, atol=IK_TOL)
    np.testing.assert_allclose(
        arm.ik_branches(motion.state(plan.t).position)[:, 0], expected, rtol=0, atol=IK_TOL
    )


def test_seed003_q1_formula_holds_only_above_joint_1():
    # q1 = -asin(x / R) + atan2(reach, l1) is acos(x / R) - atan2(l1, reach): it assumes the
    # tool is above joint 1 (z > l0). Below it, FK decides: the seed's q1 is the mirror image
    # and misses by 2 |z - l0|, while trajkit's branch 0 is exact.
    arm = Spatial3R(*SEED003_LENGTHS)
    above = np.array([[5.0, 0.0, 20.0], [-8.0, 3.0, 12.0]])
    below = np.array([[10.0, 3.0, 0.0], [3.0, 1.0, -10.0]])
    for points, good in ((above, True), (below, False)):
        seed_q = seed003_ik(points)
        miss = np.linalg.norm(arm.fk(seed_q)[:, :3, 3] - points, axis=1)
        if good:
            np.testing.assert_allclose(miss, 0.0, atol=PATH_TOL)
        else:
            np.testing.assert_allclose(miss, 2 * np.abs(points[:, 2] - 5.0), rtol=1e-9)
        branch0 = arm.ik_branches(points)[:, 0]
        np.testing.assert_allclose(arm.fk(branch0)[:, :3, 3], points, atol=PATH_TOL)
        # q2 and q3 of the seed are right either way.
        np.testing.assert_allclose(seed_q[:, 1:], branch0[:, 1:], atol=IK_TOL)


def test_seed003_joint_spline_is_continuous_to_acceleration():
    _, _, plan = seed003()
    support.assert_continuous(plan.trajectory, 2, rtol=CLOSED_FORM)
    assert plan.trajectory.degree == 5
    assert_samples_are_interpolated(plan)


def test_seed003_rates_come_from_the_jacobian():
    arm, motion, plan = seed003()
    state = motion.state(plan.t)
    jacobian = arm.jacobian(plan.q)[:, :3]
    support.assert_state(np.einsum("mkj,mj->mk", jacobian, plan.qd), state.velocity, rtol=RATE_TOL)
    bias = np.einsum("mkj,mj->mk", arm.jacobian_dot(plan.q, plan.qd)[:, :3], plan.qd)
    support.assert_state(
        np.einsum("mkj,mj->mk", jacobian, plan.qdd) + bias, state.acceleration, rtol=RATE_TOL
    )
    # The cubic line starts and ends at rest; joints too.
    np.testing.assert_allclose(plan.qd[[0, -1]], 0.0, atol=EXACT)
    assert np.all(plan.inverse_condition > 1e-3)


@pytest.mark.parametrize("branch", [0, 1, 2, 3])
def test_seed003_every_branch_tracks_and_q_start_selects_it(branch):
    arm, motion, plan = seed003(branch=branch)
    t = np.linspace(0.0, 10.0, 2001)
    np.testing.assert_allclose(
        tool_positions(arm, plan, t), motion.state(t).position, rtol=0, atol=PATH_TOL
    )
    assert plan.ok
    by_name = to_joint_space(arm, motion, 0.01, branch=arm.branch_names[branch])
    np.testing.assert_array_equal(by_name.q, plan.q)
    # A configuration near the branch's first sample selects that branch...
    near = to_joint_space(arm, motion, 0.01, q_start=plan.q[0] + 0.05)
    np.testing.assert_allclose(near.q, plan.q, atol=EXACT)
    # ...and one a whole turn away gives the same motion a whole turn away.
    turns = np.array([2 * np.pi, 0.0, -2 * np.pi])
    turned = to_joint_space(arm, motion, 0.01, q_start=plan.q[0] + turns)
    np.testing.assert_allclose(turned.q, plan.q + turns, atol=1e-9)


def test_branches_are_different_solutions():
    arm, motion, _ = seed003()
    plans = [to_joint_space(arm, motion, 0.01, branch=b) for b in range(4)]
    for i in range(4):
        for j in range(i + 1, 4):
            assert np.abs(wrapped(plans[i].q - plans[j].q)).max() > 0.1


# ------------------------------------------------------------------------- seed 002
def test_seed002_tracks_the_harmonic_segment():
    arm, motion, plan = seed002(1.0, 0.8)
    assert plan.ok
    t = np.linspace(0.0, 5.0, 5001)
    np.testing.assert_allclose(
        tool_positions(arm, plan, t), motion.state(t).position, rtol=0, atol=PATH_TOL
    )
    # The tool is back where it started after one period, and so are the joints.
    np.testing.assert_allclose(plan.q[-1], plan.q[0], atol=IK_TOL)
    support.assert_continuous(plan.trajectory, 2, rtol=CLOSED_FORM)


def test_seed002_both_elbows_are_valid_and_different():
    arm, motion, positive = seed002(1.0, 0.8, branch="elbow_positive")
    _, _, negative = seed002(1.0, 0.8, branch="elbow_negative")
    t = np.linspace(0.0, 5.0, 1001)
    for plan in (positive, negative):
        np.testing.assert_allclose(
            tool_positions(arm, plan, t), motion.state(t).position, rtol=0, atol=PATH_TOL
        )
        assert plan.ok
    assert np.all(positive.q[:, 1] > 0.0) and np.all(negative.q[:, 1] < 0.0)
    np.testing.assert_allclose(negative.q[:, 1], -positive.q[:, 1], atol=IK_TOL)
    # Default branch 0 is elbow_positive; q_start near the other elbow selects it.
    _, _, default = seed002(1.0, 0.8)
    np.testing.assert_array_equal(default.q, positive.q)
    _, _, chosen = seed002(1.0, 0.8, q_start=negative.q[0] + [0.1, -0.1])
    np.testing.assert_allclose(chosen.q, negative.q, atol=EXACT)


def test_seed002_formulas_are_branch_elbow_positive():
    l1, l2 = 1.0, 0.8
    _, motion, plan = seed002(l1, l2, branch="elbow_positive")
    expected = seed002_ik(motion.state(plan.t).position, l1, l2)
    np.testing.assert_allclose(plan.q[:, 1], expected[:, 1], rtol=0, atol=IK_TOL)
    np.testing.assert_allclose(wrapped(plan.q[:, 0] - expected[:, 0]), 0.0, atol=IK_TOL)


@FEW
@given(l1=st.floats(0.3, 2.0), l2=st.floats(0.3, 2.0))
def test_property_seed002_for_any_link_lengths(l1, l2):
    # At x = 0 the tool is at r = h = 2/3 (L1 + L2): inside the annulus when L1/L2 <= 5.
    assume(2.0 / 3.0 * (l1 + l2) > abs(l1 - l2) * 1.05)
    arm, motion, plan = seed002(l1, l2, branch="elbow_positive")
    t = np.linspace(0.0, 5.0, 2001)
    np.testing.assert_allclose(
        tool_positions(arm, plan, t), motion.state(t).position, rtol=0, atol=PATH_TOL
    )
    expected = seed002_ik(motion.state(plan.t).position, l1, l2)
    np.testing.assert_allclose(plan.q[:, 1], expected[:, 1], rtol=0, atol=IK_TOL)
    np.testing.assert_allclose(wrapped(plan.q[:, 0] - expected[:, 0]), 0.0, atol=IK_TOL)
    _, _, negative = seed002(l1, l2, branch="elbow_negative")
    np.testing.assert_allclose(
        tool_positions(arm, negative, t), motion.state(t).position, rtol=0, atol=PATH_TOL
    )
    assert np.all(plan.q[:, 1] > 0.0) and np.all(negative.q[:, 1] < 0.0)
    assert plan.ok and negative.ok


# --------------------------------------------------------------------------- RRBot
@pytest.mark.parametrize("angle", [2 * np.pi, -1.5 * np.pi])
def test_rrbot_tracks_a_circle_in_its_xz_plane(angle):
    bot = RRBot()
    center = np.array([-0.4, 0.2, 2.6])
    circle = Arc(center, center + np.array([0.0, 0.0, 0.25]), angle, normal=[0.0, 1.0, 0.0])
    motion = timed(circle, "trapezoid", vmax=0.4, amax=1.0)
    plan = to_joint_space(bot, motion, ik_step=0.005)
    assert plan.ok
    # The trapezoid's acceleration jumps between samples, so the quintic spline strays a
    # little there: within the measured path_error, itself within the default tolerance.
    assert plan.path_error < 1e-6
    t = np.linspace(0.0, motion.duration, 4001)
    tool = tool_positions(bot, plan, t)
    error = np.linalg.norm(tool - motion.state(t).position, axis=1)
    assert error.max() <= PATH_ERROR_FACTOR * plan.path_error + EXACT
    np.testing.assert_allclose(tool[:, 1], 0.2, atol=PATH_TOL)  # the arm's plane
    np.testing.assert_allclose(
        np.linalg.norm(tool - center, axis=1), 0.25, atol=PATH_ERROR_FACTOR * plan.path_error
    )
    # At the samples themselves the tool is on the circle to rounding.
    at_samples = bot.fk(plan.q)[:, :3, 3]
    np.testing.assert_allclose(at_samples, motion.state(plan.t).position, atol=PATH_TOL)


def test_rrbot_cannot_leave_its_plane():
    bot = RRBot()
    motion = timed(Line([0.3, 0.2, 3.0], [0.3, 0.5, 3.0]), "quintic", duration=1.0)
    with pytest.raises(UnreachableError, match=r"task sample at t=0\.1 s") as excinfo:
        to_joint_space(bot, motion, ik_step=0.1)
    assert excinfo.value.index == 1


# ------------------------------------------------------------------------------ UR5
UR5_A = np.array([0.2, -1.0, 1.3, -1.6, -1.4, 0.4])
UR5_B = np.array([-0.4, -1.4, 1.8, -2.0, -1.7, -0.3])


@pytest.mark.parametrize(
    "limits", [{"durations": [3.0]}, {"vmax": 0.25, "amax": 0.8, "wmax": 0.6, "alpha_max": 2.0}]
)
def test_ur5_full_pose_motion_between_two_configurations(limits):
    ur5 = UR5()
    assert min(ur5.manipulability(UR5_A), ur5.manipulability(UR5_B)) > 0.05  # far from singular
    poses = ur5.fk(np.stack([UR5_A, UR5_B]))
    profile = "quintic" if "durations" in limits else "trapezoid"
    motion = through_poses(poses, profile, **limits)
    plan = to_joint_space(ur5, motion, ik_step=0.01, q_start=UR5_A)
    assert plan.ok, plan.problems()
    np.testing.assert_allclose(plan.q[0], UR5_A, atol=IK_TOL)
    # The goal pose is reached in the configuration it came from (same branch).
    np.testing.assert_allclose(plan.q[-1], UR5_B, atol=1e-8)
    assert plan.path_error < 1e-6  # the default tolerance, position and orientation
    t = np.linspace(0.0, motion.duration, 1501)
    reached = ur5.fk(plan.trajectory.position(t))
    desired = motion.state(t)
    np.testing.assert_allclose(reached[:, :3, 3], desired.position, atol=1e-6)
    angle = np.linalg.norm(rotation_error(desired.rotation, reached[:, :3, :3]), axis=1)
    assert angle.max() < 1e-6
    # Angular rows of J q̇ follow the SLERP's angular velocity at the samples.
    twist = np.einsum("mkj,mj->mk", ur5.jacobian(plan.q), plan.qd)
    state = motion.state(plan.t)
    support.assert_state(twist[:, 3:], state.angular_velocity, rtol=1e-8)
    support.assert_state(twist[:, :3], state.velocity, rtol=1e-8)


def test_ur5_position_only_motion():
    ur5 = UR5()
    points = ur5.fk(np.stack([UR5_A, UR5_B]))[:, :3, 3]
    motion = through_poses(points, "quintic", durations=[3.0])
    plan = to_joint_space(ur5, motion, ik_step=0.01, q_start=UR5_A)
    np.testing.assert_allclose(plan.q[0], UR5_A, atol=IK_TOL)
    t = np.linspace(0.0, 3.0, 601)
    np.testing.assert_allclose(tool_positions(ur5, plan, t), motion.state(t).position, atol=1e-8)


# ----------------------------------------------------------------------- unreachable
def test_unreachable_sample_gives_its_time_and_index():
    arm = Planar2R(1.0, 0.8)
    # x = 1 + 0.95 t leaves the annulus r <= 1.8 at t = 0.842: first sample outside 0.85 s.
    motion = timed(Line([1.0, 0.0, 0.0], [2.9, 0.0, 0.0]), "linear", duration=2.0)
    with pytest.raises(UnreachableError, match=r"t=0\.85 s") as excinfo:
        to_joint_space(arm, motion, ik_step=0.01)
    assert type(excinfo.value) is UnreachableError
    assert excinfo.value.index == 85
    assert "out of reach" in str(excinfo.value)


def test_unreachable_sample_of_the_spatial_arm():
    arm = Spatial3R(*SEED003_LENGTHS)
    motion = timed(Line([0.0, -12.0, 20.0], [0.0, -12.0, 60.0]), "linear", duration=4.0)
    with pytest.raises(UnreachableError, match=r"task sample at t=[0-9.]+ s") as excinfo:
        to_joint_space(arm, motion, ik_step=0.05)
    k = excinfo.value.index
    far = np.linalg.norm(motion.state(np.arange(81) * 0.05).position - [0.0, 0.0, 5.0], axis=1)
    limit = np.hypot(10.0, 20.0)  # farthest reach from joint 1
    assert far[k] > limit and np.all(far[:k] <= limit)


def test_unreachable_sample_of_a_numerical_chain():
    arm = SerialChain.from_dh([DHRow(a=1.0), DHRow(a=0.5)])
    motion = timed(Line([1.0, 0.2, 0.0], [2.0, 0.2, 0.0]), "linear", duration=1.0)
    with pytest.raises(UnreachableError, match=r"task sample at t=0\.5 s") as excinfo:
        to_joint_space(arm, motion, ik_step=0.05, q_start=[0.0, 0.5])
    assert type(excinfo.value) is UnreachableError
    # The first sample past r = 1.5 (index 10, r = 1.513), not the first coarse IK knot
    # that fails (index 11).
    radius = np.hypot(1.0 + np.arange(21) * 0.05, 0.2)
    assert excinfo.value.index == int(np.flatnonzero(radius > 1.5)[0]) == 10


# ---------------------------------------------------------------------- singularities
def test_a_line_out_to_full_stretch_is_reported_singular():
    arm = Planar2R(1.0, 1.0)
    motion = timed(Line([1.0, 0.0, 0.0], [2.0, 0.0, 0.0]), "quintic", duration=1.0)
    plan = to_joint_space(arm, motion, ik_step=0.01)
    assert plan.singular_time is not None and not plan.ok
    k = np.flatnonzero(plan.inverse_condition < 1e-3)[0]
    assert plan.singular_time == plan.t[k]
    assert plan.inverse_condition[-1] == pytest.approx(0.0, abs=1e-6)  # stretched out
    assert any("near a singularity from t=" in p for p in plan.problems())
    assert plan.limits.ok  # no limit broken: the singularity alone makes it not ok


def test_out_to_full_stretch_and_back():
    arm = Planar2R(1.0, 1.0)
    motion = through_poses(
        [[1.0, 0.0, 0.0], [2.0, 0.0, 0.0], [1.0, 0.5, 0.0]], "quintic", durations=[1.0, 1.0]
    )
    plan = to_joint_space(arm, motion, ik_step=0.01)
    assert plan.singular_time is not None and plan.singular_time <= 1.0 < plan.t[-1]
    assert not plan.ok
    # A lower threshold ignores it everywhere but the stretched sample itself.
    strict = to_joint_space(arm, motion, ik_step=0.01, singularity_threshold=1e-12)
    assert strict.singular_time == pytest.approx(1.0, abs=1e-9)


def test_a_line_through_the_folded_singularity_is_infeasible():
    arm = Planar2R(1.0, 1.0)  # the origin is reached folded, q2 = pi, with q1 arbitrary
    motion = timed(Line([-1.0, 0.0, 0.0], [1.0, 0.0, 0.0]), "quintic", duration=1.0)
    with pytest.raises(InfeasibleError, match="singularity") as excinfo:
        to_joint_space(arm, motion, ik_step=0.01)
    assert type(excinfo.value) is InfeasibleError


Q_FAST = [-0.15, 1.29]  # near the elbow-up solution at fast_line's start


def fast_line():
    return timed(Line([1.2, 0.3, 0.0], [0.3, 1.2, 0.0]), "quintic", duration=1.0)


def test_too_coarse_an_ik_step_asks_for_a_smaller_one():
    arm = Planar2R(1.0, 0.5)
    with pytest.raises(InfeasibleError, match=r"use a smaller ik_step than 0\.1 s") as excinfo:
        to_joint_space(arm, fast_line(), ik_step=0.1)
    assert type(excinfo.value) is InfeasibleError
    plan = to_joint_space(arm, fast_line(), ik_step=0.1, tolerance=1e-3)  # a loose tolerance passes
    assert 1e-6 < plan.path_error < 1e-3 and plan.t.size == 11
    assert to_joint_space(arm, fast_line(), ik_step=0.02).path_error < 1e-9


def test_an_arc_about_the_base_is_exact_with_few_samples():
    # Turning the 2R rigidly about its base is a quintic in q1 alone: the spline is exact.
    arm = Planar2R(1.0, 0.8)
    motion = timed(Arc([0.0, 0.0, 0.0], [1.2, 0.0, 0.0], np.pi), "quintic", duration=1.0)
    plan = to_joint_space(arm, motion, ik_step=0.5)
    assert plan.path_error < 1e-12 and plan.t.tolist() == [0.0, 0.5, 1.0]
    np.testing.assert_allclose(plan.q[:, 1], plan.q[0, 1], atol=EXACT)


def test_last_sample_lands_on_the_end_when_dt_does_not_divide_it():
    arm = Planar2R(1.0, 0.8)
    motion = timed(Arc([0.0, 0.0, 0.0], [1.2, 0.0, 0.0], 0.5), "quintic", duration=1.0)
    plan = to_joint_space(arm, motion, ik_step=0.3, tolerance=1e-3)
    np.testing.assert_allclose(plan.t, [0.0, 0.3, 0.6, 0.9, 1.0], rtol=CLOSED_FORM)
    assert plan.t[-1] == 1.0
    assert_samples_are_interpolated(plan)


# ----------------------------------------------------------------------- joint limits
def test_velocity_limit_violation_is_reported_first_by_time():
    # On fast_line the joints peak at 2.28 and 1.45 rad/s; joint 2 is limited to 0.4.
    rows = [DHRow(a=1.0, velocity=5.0), DHRow(a=0.5, lower=-3.0, upper=3.0, velocity=0.4)]
    arm = SerialChain.from_dh(rows)
    plan = to_joint_space(arm, fast_line(), ik_step=0.01, q_start=Q_FAST)
    assert not plan.ok and not plan.limits.ok
    limit = np.array([5.0, 0.4])
    over = np.abs(plan.qd) > limit * (1 + LIMIT_RTOL)
    k, j = np.argwhere(over)[0]
    assert plan.first_violation == (plan.t[k], j, "velocity")
    assert plan.first_violation[1] == 1  # joint 2 is the slow one
    assert f"joint 2 first exceeds its velocity limit at t={plan.t[k]:.6g} s" in plan.problems()
    violation = next(v for v in plan.limits.violations if v.quantity == "velocity")
    assert violation.joint == 1 and abs(violation.bound) == 0.4
    assert abs(violation.value) == pytest.approx(np.abs(plan.qd[:, 1]).max(), rel=1e-3)
    assert not any(v.joint == 0 for v in plan.limits.violations)
    # Positions stay in range: the numerical IK projects onto it.
    assert np.all(np.abs(plan.q[:, 1]) <= 3.0)


def test_generous_limits_are_ok():
    rows = [
        DHRow(a=1.0, lower=-4.0, upper=4.0, velocity=50.0),
        DHRow(a=0.5, lower=-3.0, upper=3.0, velocity=50.0),
    ]
    arm = SerialChain.from_dh(rows)
    plan = to_joint_space(arm, fast_line(), ik_step=0.01, q_start=Q_FAST)
    assert plan.ok and plan.first_violation is None and plan.limits.ok
    assert set(plan.limits.peaks) == {"position", "velocity"}


@st.composite
def planar_lines(draw: st.DrawFn, l1: float, l2: float):
    """Lines whose every point lies well inside the 2R's annulus."""
    inner, outer = abs(l1 - l2), l1 + l2
    low, high = inner + 0.2 * (outer - inner), outer - 0.1 * (outer - inner)
    points = []
    for _ in range(2):
        r = draw(st.floats(low, high))
        a = draw(st.floats(-np.pi, np.pi))
        points.append(np.array([r * np.cos(a), r * np.sin(a), 0.0]))
    start, end = points
    chord = end - start
    assume(np.linalg.norm(chord) > 0.05)
    s = np.clip(-(start @ chord) / (chord @ chord), 0.0, 1.0)
    assume(np.linalg.norm(start + s * chord) > low)
    return start, end


@FEW
@given(data=st.data(), l1=st.floats(0.5, 2.0), l2=st.floats(0.5, 2.0))
def test_property_random_planar_lines_stay_within_path_error(data, l1, l2):
    start, end = data.draw(planar_lines(l1, l2))
    arm = Planar2R(l1, l2)
    motion = timed(Line(start, end), "quintic", duration=2.0)
    plan = to_joint_space(arm, motion, ik_step=0.02, branch=data.draw(st.sampled_from([0, 1])))
    t = np.linspace(0.0, 2.0, 8001)
    error = np.linalg.norm(tool_positions(arm, plan, t) - motion.state(t).position, axis=1)
    assert error.max() <= PATH_ERROR_FACTOR * plan.path_error + EXACT
    assert plan.path_error <= 1e-6 and plan.singular_time is None


@FEW
@given(data=st.data(), vlimit=st.floats(0.3, 3.0))
def test_property_limit_check_agrees_with_dense_sampling(data, vlimit):
    # The DH 2R has the geometry of Planar2R(1, 0.5) but goes through numerical IK. Its
    # ranges are wide enough for every line drawn (a narrower one would make the numerical
    # IK, which keeps to the ranges, report a target out of reach).
    rows = [
        DHRow(a=1.0, lower=-8.0, upper=8.0, velocity=vlimit),
        DHRow(a=0.5, lower=-3.0, upper=3.0, velocity=vlimit),
    ]
    arm = SerialChain.from_dh(rows)
    start, end = data.draw(planar_lines(1.0, 0.5))
    q_start = wrapped(Planar2R(1.0, 0.5).ik_branches(start)[data.draw(st.sampled_from([0, 1]))])
    motion = timed(Line(start, end), "quintic", duration=1.5)
    plan = to_joint_space(arm, motion, ik_step=0.02, q_start=q_start)
    t = np.linspace(0.0, 1.5, 6001)
    velocity = plan.trajectory.velocity(t)
    reported = [v for v in plan.limits.violations if v.quantity == "velocity"]
    for j in range(2):
        for sign in (1.0, -1.0):  # each side of each joint separately
            dense = (sign * velocity[:, j]).max()
            found = [v for v in reported if v.joint == j and sign * v.value > 0]
            if dense > vlimit * (1 + 1e-6):
                assert found, f"joint {j} reaches {sign * dense:g}, limit {vlimit:g}: not reported"
            for violation in found:
                # The reported value is the exact extreme: dense samples get close, never past.
                exact = sign * violation.value
                assert exact > vlimit and violation.bound == sign * vlimit
                assert dense <= exact * (1 + EXACT)
                assert dense == pytest.approx(exact, rel=PEAK_RTOL)
                at = plan.trajectory.velocity(violation.time)[j]
                assert at == pytest.approx(violation.value, rel=EXACT)
    # Positions are within range everywhere, as the report says.
    q = plan.trajectory.position(t)
    assert np.all(np.abs(q) <= [8.0, 3.0]) == (
        not any(v.quantity == "position" for v in plan.limits.violations)
    )
    # first_violation is the first sample over a limit, if any.
    over = np.argwhere(np.abs(plan.qd) > vlimit * (1 + LIMIT_RTOL))
    if over.size:
        assert plan.first_violation == (plan.t[over[0, 0]], over[0, 1], "velocity")
        assert not plan.ok
    else:
        assert plan.first_violation is None
    assert plan.ok == (plan.limits.ok and plan.singular_time is None)


# ------------------------------------------------------------------------ bad input
ORIENTED = timed(
    Line([0.0, -12.0, 20.0], [10.0, 12.0, 20.0]), "cubic", duration=10.0, orientation=np.eye(3)
)
PLAIN = timed(Line([0.0, -12.0, 20.0], [10.0, 12.0, 20.0]), "cubic", duration=10.0)


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: to_joint_space(Spatial3R(), PLAIN, ik_step=0.0), "ik_step must be > 0"),
        (lambda: to_joint_space(Spatial3R(), PLAIN, ik_step=-0.01), "ik_step must be > 0"),
        (lambda: to_joint_space(Spatial3R(), PLAIN, ik_step=np.nan), "ik_step must be finite"),
        (lambda: to_joint_space(Spatial3R(), PLAIN, ik_step=np.inf), "ik_step must be finite"),
        (
            lambda: to_joint_space(Spatial3R(), PLAIN, ik_step=[0.1, 0.2]),
            "ik_step must be a single",
        ),
        (lambda: to_joint_space(Spatial3R(), ORIENTED, ik_step=0.1), "sets only its tool position"),
        (
            lambda: to_joint_space(Planar2R(1, 1), ORIENTED, ik_step=0.1),
            "sets only its tool position",
        ),
        (lambda: to_joint_space("arm", PLAIN, ik_step=0.1), "robot must be a trajkit SerialChain"),
        (lambda: to_joint_space(Spatial3R(), "line", ik_step=0.1), "task must be a TaskTrajectory"),
        (
            lambda: to_joint_space(Spatial3R(), PLAIN, ik_step=0.1, q_start=[0.0, 0.0]),
            r"q_start must have shape \(3,\)",
        ),
        (
            lambda: to_joint_space(Spatial3R(), PLAIN, ik_step=0.1, q_start=[0.0, np.nan, 0.0]),
            "q_start must be finite",
        ),
        (
            lambda: to_joint_space(Spatial3R(), PLAIN, ik_step=0.1, tolerance=0.0),
            "tolerance must be",
        ),
        (
            lambda: to_joint_space(Spatial3R(), PLAIN, ik_step=0.1, singularity_threshold=np.nan),
            "singularity_threshold must be finite",
        ),
        (
            lambda: to_joint_space(Spatial3R(), PLAIN, ik_step=0.1, branch="sideways"),
            "branch must be",
        ),
        (
            lambda: to_joint_space(Spatial3R(), PLAIN, ik_step=0.1, branch=4),
            "branch must be an index",
        ),
        (lambda: to_joint_space(UR5(), ORIENTED, ik_step=0.1, branch=0), "closed-form arms only"),
    ],
)
def test_bad_input_raises_invalid_input_error(call, message):
    with pytest.raises(InvalidInputError, match=message) as excinfo:
        call()
    assert type(excinfo.value) is InvalidInputError


# ---------------------------------------------------------------------- known bugs
def test_q_start_with_several_rows_is_refused():
    with pytest.raises(InvalidInputError, match="q_start"):
        to_joint_space(Spatial3R(), PLAIN, ik_step=0.1, q_start=[[0.8, -1.6, 1.2], [0.0, 0.0, 0.0]])


def test_a_velocity_limit_on_some_joints_only_makes_the_plan_not_ok():
    arm = SerialChain.from_dh([DHRow(a=1.0, velocity=0.5), DHRow(a=0.5)])
    plan = to_joint_space(arm, fast_line(), ik_step=0.01, q_start=Q_FAST)
    assert plan.first_violation is not None and plan.first_violation[2] == "velocity"
    assert plan.problems()  # it is reported...
    assert not plan.ok  # ...but ok must agree: "True when no limit is broken"


def test_first_violation_reports_a_one_sided_position_limit():
    # Joint 1 has an upper limit only. Closed-form IK does not keep samples in range, so
    # along this line (elbow negative, polar angle above 1.2 rad) joint 1 stays above 1 rad.
    plain = Planar2R(1.0, 0.5)
    joints = [dataclasses.replace(plain.joints[0], upper=1.0), plain.joints[1]]

    class OneSided(Planar2R):
        def __init__(self) -> None:
            super().__init__(1.0, 0.5)
            SerialChain.__init__(self, joints, base=self.base, tool=self.tool, name="one-sided")

    arm = OneSided()
    motion = timed(Line([0.45, 1.1, 0.0], [0.35, 1.2, 0.0]), "quintic", duration=1.0)
    plan = to_joint_space(arm, motion, ik_step=0.01, branch="elbow_negative")
    assert np.all(plan.q[:, 0] > 1.0)
    assert any(v.quantity == "position" and v.joint == 0 for v in plan.limits.violations)
    assert plan.first_violation == (0.0, 0, "position")
