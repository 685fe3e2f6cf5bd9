"""Task space: paths, time laws, SLERP poses, and the mapping to joint space (seeds 002, 003)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import trajkit as tk
from trajkit.errors import InfeasibleError, InvalidInputError, UnreachableError
from trajkit.kinematics import UR5, DHRow, Planar2R, RRBot, SerialChain, Spatial3R
from trajkit.rotations import axis_rotation, rotation_error
from trajkit.taskspace import (
    Arc,
    Ellipse,
    FigureEight,
    Line,
    Polyline,
    path_law,
    through_poses,
    timed,
    to_joint_space,
)

EXACT = 1e-12  # closed forms
FD_STEP = 1e-6
FD_TOL = 1e-6  # central differences at that step
PATH_TOL = 1e-9  # FK of a mapped joint trajectory against the task path
LIMIT_RTOL = 1e-9

PATHS = {
    "line": Line([0, -12, 20], [10, 12, 20]),
    "arc": Arc([1, 0, 0], [2, 0, 0.5], 1.5 * np.pi, normal=[0, 1, 1]),
    "ellipse": Ellipse([0, 1, 0], 0.8, 0.3, turns=1.5, phase=0.4),
    "segment": Ellipse([0, 1.2, 0], 0.9, 0.0),
    "eight": FigureEight([0.5, 0, 0], 2.0, 1.0, normal=[0, 0, 1]),
    "polyline": Polyline([[0, 0, 0], [1, 0, 0], [1, 2, 0], [0, 2, 1]]),
}


# ---------------------------------------------------------------------- paths


@pytest.mark.parametrize("name", [n for n in PATHS if n != "polyline"])
def test_path_derivatives_match_finite_differences(name):
    path = PATHS[name]
    u = np.linspace(0.01, 0.99, 57)
    for order in (1, 2):
        numeric = (
            path.evaluate(u + FD_STEP, order - 1) - path.evaluate(u - FD_STEP, order - 1)
        ) / (2 * FD_STEP)
        np.testing.assert_allclose(path.evaluate(u, order), numeric, atol=FD_TOL * 100)


@pytest.mark.parametrize("name", list(PATHS))
def test_path_bounds_hold(name):
    path = PATHS[name]
    u = np.linspace(0.0, 1.0, 20001)
    assert np.linalg.norm(path.evaluate(u, 1), axis=1).max() <= path.speed_bound * (1 + 1e-12)
    assert (
        np.linalg.norm(path.evaluate(u, 2), axis=1).max()
        <= path.curvature_bound * (1 + 1e-12) + 1e-12
    )


def test_arc_geometry():
    arc = PATHS["arc"]
    normal = np.array([0, 1, 1]) / np.sqrt(2)
    points = arc.evaluate(np.linspace(0, 1, 101))
    center = np.array([1, 0, 0]) + normal * ((np.array([1, 0, 0.5])) @ normal)
    np.testing.assert_allclose(np.linalg.norm(points - center, axis=1), arc.radius, rtol=EXACT)
    np.testing.assert_allclose(arc.start, [2, 0, 0.5], atol=EXACT)
    start, end = arc.start - center, arc.end - center
    swept = np.arctan2(np.cross(start, end) @ normal, start @ end) % (2 * np.pi)
    assert swept == pytest.approx(1.5 * np.pi, rel=EXACT)


def test_seed002_families():
    t = np.linspace(0, 1, 101)
    eight = PATHS["eight"].evaluate(t)
    np.testing.assert_allclose(eight[:, 0], 0.5 + np.sin(2 * np.pi * t), atol=EXACT)
    np.testing.assert_allclose(eight[:, 1], 0.5 * np.sin(4 * np.pi * t), atol=EXACT)
    segment = PATHS["segment"].evaluate(t)
    np.testing.assert_allclose(segment[:, 0], 0.9 * np.cos(2 * np.pi * t), atol=EXACT)
    np.testing.assert_allclose(segment[:, 1], 1.2, atol=EXACT)


def test_polyline_knots_are_proportional_to_distance():
    path = PATHS["polyline"]
    np.testing.assert_allclose(path.evaluate(path.knots), path.waypoints, atol=EXACT)
    lengths = np.linalg.norm(np.diff(path.waypoints, axis=0), axis=1)
    np.testing.assert_allclose(np.diff(path.knots), lengths / lengths.sum(), rtol=EXACT)
    assert path.length == pytest.approx(lengths.sum(), rel=EXACT)


@pytest.mark.parametrize(
    ("make", "message"),
    [
        (lambda: Line([0, 0, np.nan], [1, 0, 0]), "start must be finite"),
        (lambda: Line([0, 0, 0, 0], [1, 0, 0]), "start must be a point"),
        (lambda: Arc([0, 0, 0], [0, 0, 1], 1.0), "radius would be 0"),
        (lambda: Arc([0, 0, 0], [1, 0, 0], 0.0), "angle must be non-zero"),
        (lambda: Ellipse([0, 0, 0], 1.0, -0.1), "b must be >= 0"),
        (lambda: Ellipse([0, 0, 0], 1.0, 0.5, turns=0), "turns must be non-zero"),
        (lambda: Ellipse([0, 0, 0], 1.0, 0.5, x_axis=[0, 0, 1]), "not be parallel"),
        (lambda: FigureEight([0, 0, 0], -1.0, 1.0), "width must be > 0"),
        (lambda: Polyline([[0, 0, 0]]), "k >= 2"),
        (lambda: Polyline([[0, 0, 0], [0, 0, 0]]), "waypoints 0 and 1 coincide"),
        (lambda: PATHS["line"].evaluate(0.5, order=3), "order must be 0, 1 or 2"),
    ],
)
def test_path_bad_input(make, message):
    with pytest.raises(InvalidInputError, match=message) as excinfo:
        make()
    assert type(excinfo.value) is InvalidInputError


# ------------------------------------------------------------------ time laws


@pytest.mark.parametrize("profile", ["linear", "cubic", "quintic", "septic", "trapezoid"])
def test_laws_go_from_0_to_1(profile):
    kwargs = {"duration": 2.0} if profile != "trapezoid" else {"vmax": 1.0, "amax": 2.0}
    law = path_law(profile, **kwargs)
    assert law.position(0.0)[0] == pytest.approx(0.0, abs=EXACT)
    assert law.position(law.end_time)[0] == pytest.approx(1.0, abs=EXACT)


def test_seed003_cubic_line_closed_form():
    motion = timed(PATHS["line"], "cubic", duration=10.0)
    t = np.linspace(0, 10, 1001)
    s = 3 * (t / 10) ** 2 - 2 * (t / 10) ** 3
    expected = np.array([0, -12, 20]) + s[:, np.newaxis] * np.array([10, 24, 0])
    np.testing.assert_allclose(motion.evaluate(t).position, expected, atol=EXACT * 30)


def dense_state(motion, count=20001):
    return motion.evaluate(np.linspace(0, motion.duration, count))


def test_trapezoid_on_a_line_is_time_optimal():
    motion = timed(PATHS["line"], "trapezoid", vmax=2.0, amax=1.5)
    state = dense_state(motion)
    assert np.linalg.norm(state.velocity, axis=1).max() == pytest.approx(2.0, rel=1e-9)
    assert np.linalg.norm(state.acceleration, axis=1).max() == pytest.approx(1.5, rel=1e-9)
    length = 26.0
    assert motion.duration == pytest.approx(length / 2.0 + 2.0 / 1.5, rel=EXACT)


@pytest.mark.parametrize("name", ["arc", "ellipse", "eight"])
@pytest.mark.parametrize("profile", ["trapezoid", "quintic"])
def test_cartesian_limits_hold_on_curves(name, profile):
    motion = timed(PATHS[name], profile, vmax=0.7, amax=1.3)
    state = dense_state(motion)
    assert np.linalg.norm(state.velocity, axis=1).max() <= 0.7 * (1 + LIMIT_RTOL)
    assert np.linalg.norm(state.acceleration, axis=1).max() <= 1.3 * (1 + LIMIT_RTOL)


def test_scurve_law_on_a_line_keeps_the_jerk_limit():
    motion = timed(PATHS["line"], "scurve", vmax=2.0, amax=1.5, jmax=4.0)
    law = motion.segments[0].law
    jerk = np.abs(law.jerk(np.linspace(0, law.duration, 20001))).max() * 26.0
    assert jerk <= 4.0 * (1 + LIMIT_RTOL)


@pytest.mark.parametrize("name", ["arc", "eight"])
def test_task_velocity_and_acceleration_are_derivatives(name):
    motion = timed(PATHS[name], "quintic", duration=3.0)
    t = np.linspace(0.1, 2.9, 41)
    plus, minus, now = (
        motion.evaluate(t + FD_STEP),
        motion.evaluate(t - FD_STEP),
        motion.evaluate(t),
    )
    np.testing.assert_allclose(now.velocity, (plus.position - minus.position) / (2 * FD_STEP),
                               atol=FD_TOL * 10)  # fmt: skip
    np.testing.assert_allclose(now.acceleration, (plus.velocity - minus.velocity) / (2 * FD_STEP),
                               atol=FD_TOL * 10)  # fmt: skip


def rotation(rotvec):
    rotvec = np.asarray(rotvec, dtype=float)
    angle = np.linalg.norm(rotvec)
    return axis_rotation(rotvec / angle, angle)


def test_slerp_orientation():
    start, end = rotation([0.3, -0.2, 0.1]), rotation([-0.5, 1.0, 0.4])
    motion = timed(PATHS["line"], "quintic", duration=4.0, orientation=(start, end))
    assert motion.has_orientation
    ends = motion.evaluate([0.0, 4.0])
    np.testing.assert_allclose(ends.rotation[0], start, atol=EXACT)
    np.testing.assert_allclose(ends.rotation[1], end, atol=1e-12)
    t = np.linspace(0.2, 3.8, 31)
    plus, minus, now = (
        motion.evaluate(t + FD_STEP),
        motion.evaluate(t - FD_STEP),
        motion.evaluate(t),
    )
    numeric = rotation_error(plus.rotation, minus.rotation) / (2 * FD_STEP)
    np.testing.assert_allclose(now.angular_velocity, numeric, atol=FD_TOL)
    numeric = (plus.angular_velocity - minus.angular_velocity) / (2 * FD_STEP)
    np.testing.assert_allclose(now.angular_acceleration, numeric, atol=FD_TOL)
    directions = now.angular_velocity / np.linalg.norm(now.angular_velocity, axis=1)[:, None]
    np.testing.assert_allclose(directions, np.tile(directions[0], (31, 1)), atol=EXACT)
    poses = now.poses()
    np.testing.assert_allclose(poses[:, :3, 3], now.position, atol=0)


def test_through_poses_rests_at_every_pose_and_honors_limits():
    poses = np.stack([np.eye(4)] * 3)
    poses[1, :3, 3] = [0.3, 0.0, 0.1]
    poses[1, :3, :3] = rotation([0, 0, 0.8])
    poses[2, :3, 3] = [0.3, 0.4, 0.1]
    motion = through_poses(poses, "trapezoid", vmax=0.2, amax=0.5, wmax=0.3, alpha_max=1.0)
    assert len(motion.segments) == 2
    rest = motion.evaluate(motion.breakpoints)
    np.testing.assert_allclose(rest.velocity, 0.0, atol=EXACT)
    np.testing.assert_allclose(rest.angular_velocity, 0.0, atol=EXACT)
    np.testing.assert_allclose(rest.poses(), poses, atol=1e-12)
    state = dense_state(motion)
    assert np.linalg.norm(state.velocity, axis=1).max() <= 0.2 * (1 + LIMIT_RTOL)
    assert np.linalg.norm(state.acceleration, axis=1).max() <= 0.5 * (1 + LIMIT_RTOL)
    assert np.linalg.norm(state.angular_velocity, axis=1).max() <= 0.3 * (1 + LIMIT_RTOL)
    assert np.linalg.norm(state.angular_acceleration, axis=1).max() <= 1.0 * (1 + LIMIT_RTOL)
    # The first segment turns by 0.8 rad: the angular limit sets its duration, 0.8/0.3 + 0.3/1.
    assert motion.breakpoints[1] == pytest.approx(0.8 / 0.3 + 0.3 / 1.0, rel=1e-12)


def test_through_points_with_durations_and_clamping():
    points = [[0, 0, 0], [1, 0, 0], [1, 1, 0]]
    motion = through_poses(points, "quintic", durations=[2.0, 1.0])
    assert not motion.has_orientation and motion.duration == pytest.approx(3.0)
    outside = motion.evaluate([-1.0, 5.0])
    np.testing.assert_allclose(outside.position, [[0, 0, 0], [1, 1, 0]], atol=EXACT)
    np.testing.assert_allclose(outside.velocity, 0.0, atol=EXACT)


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: timed(PATHS["line"], "bang"), "profile must be one of"),
        (lambda: timed(PATHS["line"], "cubic"), "give a duration or Cartesian limits"),
        (lambda: timed(PATHS["arc"], "scurve", vmax=1, amax=1, jmax=1), "straight paths only"),
        (lambda: timed(PATHS["line"], "trapezoid", vmax=1.0), "needs vmax and amax"),
        (lambda: timed(PATHS["line"], "cubic", duration=-1.0), "duration must be > 0"),
        (lambda: timed("line", "cubic", duration=1.0), "path must be a trajkit.taskspace Path"),
        (lambda: timed(PATHS["line"], tk.cubic([0.0], [2.0], 1.0)), "from u=0 to u=1"),
        (lambda: timed(PATHS["line"], tk.cubic([0.0, 0.0], [1.0, 1.0], 1.0)), "1-joint"),
        (
            lambda: timed(PATHS["line"], "cubic", duration=1.0, orientation=np.ones((3, 3))),
            "not a rotation matrix",
        ),
        (lambda: through_poses([[0, 0, 0]], durations=[]), "at least 2 poses"),
        (lambda: through_poses([[0, 0, 0], [1, 0, 0]], durations=[1, 2]), "durations must be 1"),
        (lambda: through_poses([[0, 0, 0], [1, 0, 0]]), "give durations or limits"),
        (lambda: through_poses([[0, 0, 0], [0, 0, 0]], durations=[1]), "coincide"),
        (lambda: through_poses(np.zeros((2, 2)), durations=[1]), "poses must have shape"),
    ],
)
def test_motion_bad_input(call, message):
    with pytest.raises(InvalidInputError, match=message) as excinfo:
        call()
    assert type(excinfo.value) is InvalidInputError


# --------------------------------------------------------------- joint space


def seed003():
    arm = Spatial3R(5.0, 10.0, 8.0, 12.0)
    motion = timed(PATHS["line"], "cubic", duration=10.0)
    return arm, motion, to_joint_space(arm, motion, dt=0.01)


def test_seed003_end_to_end():
    arm, motion, plan = seed003()
    assert plan.ok and plan.problems() == []
    t = np.random.default_rng(1).uniform(0, 10, 10_000)
    tool = arm.fk(plan.trajectory.position(t))[:, :3, 3]
    np.testing.assert_allclose(tool, motion.evaluate(t).position, atol=PATH_TOL)
    # The seed's closed-form IK (q3 = +acos, forward reach) at every sample.
    l0, l1, l2, l3 = 5.0, 10.0, 8.0, 12.0
    x, y, z = motion.evaluate(plan.t).position.T
    q3 = np.arccos((x**2 + y**2 + (z - l0) ** 2 - l1**2 - l2**2 - l3**2) / (2 * l2 * l3))
    q2 = np.arcsin(y / np.sqrt((l2 + l3 * np.cos(q3)) ** 2 + (l3 * np.sin(q3)) ** 2)) - np.arctan2(
        l3 * np.sin(q3), l2 + l3 * np.cos(q3)
    )
    np.testing.assert_allclose(plan.q[:, 2], q3, atol=1e-9)
    np.testing.assert_allclose(plan.q[:, 1], q2, atol=1e-9)
    # Continuous position, velocity and acceleration at every breakpoint.
    inner = plan.trajectory.breakpoints[1:-1]
    for order in range(3):
        left = plan.trajectory.evaluate(inner - 1e-12, order)
        right = plan.trajectory.evaluate(inner + 1e-12, order)
        np.testing.assert_allclose(left, right, atol=1e-7)
    # Rates from the Jacobian: J q̇ equals the task velocity.
    jacobian = arm.jacobian(plan.q)[:, :3]
    twist = np.einsum("mkj,mj->mk", jacobian, plan.qd)
    np.testing.assert_allclose(twist, motion.evaluate(plan.t).velocity, atol=1e-9)


def seed002(l1, l2, period=5.0, branch="elbow_positive"):
    h = 2.0 / 3.0 * (l1 + l2)
    arm = Planar2R(l1, l2)
    path = Ellipse([0.0, h, 0.0], 0.9 * np.sqrt((l1 + l2) ** 2 - h**2), 0.0)
    motion = timed(path, "linear", duration=period)
    return arm, motion, to_joint_space(arm, motion, dt=0.01, branch=branch)


@settings(max_examples=10, deadline=None)
@given(l1=st.floats(0.3, 2.0), l2=st.floats(0.3, 2.0))
def test_seed002_tracking(l1, l2):
    arm, motion, plan = seed002(l1, l2)
    t = np.linspace(0, 5, 2001)
    tool = arm.fk(plan.trajectory.position(t))[:, :3, 3]
    np.testing.assert_allclose(tool, motion.evaluate(t).position, atol=PATH_TOL)
    # The seed's formulas are branch "elbow_positive".
    x, y, _ = motion.evaluate(plan.t).position.T
    d = (x**2 + y**2 - l1**2 - l2**2) / (2 * l1 * l2)
    theta2 = np.arctan2(np.sqrt(1 - d**2), d)
    theta1 = np.arctan2(y, x) - np.arctan2(l2 * np.sin(theta2), l1 + l2 * np.cos(theta2))
    np.testing.assert_allclose(plan.q[:, 1], theta2, atol=1e-9)
    np.testing.assert_allclose(plan.q[:, 0], np.unwrap(theta1) - np.unwrap(theta1)[0]
                               + plan.q[0, 0], atol=1e-9)  # fmt: skip


def test_seed002_other_branch():
    arm, motion, positive = seed002(1.0, 0.8)
    _, _, negative = seed002(1.0, 0.8, branch="elbow_negative")
    assert np.all(positive.q[:, 1] > 0) and np.all(negative.q[:, 1] < 0)
    tool = arm.fk(negative.trajectory.position(np.linspace(0, 5, 501)))[:, :3, 3]
    np.testing.assert_allclose(tool, motion.evaluate(np.linspace(0, 5, 501)).position, atol=1e-9)
    # q_start selects the branch too.
    chosen = to_joint_space(arm, motion, 0.01, q_start=negative.q[0])
    np.testing.assert_allclose(chosen.q, negative.q, atol=1e-12)


def test_rrbot_tracks_a_circle_in_its_plane():
    bot = RRBot()
    center = np.array([0.5, 0.2, 2.8])
    circle = Arc(center, center + np.array([0.3, 0, 0]), 2 * np.pi, normal=[0, 1, 0])
    motion = timed(circle, "quintic", duration=4.0)
    plan = to_joint_space(bot, motion, dt=0.01)
    t = np.linspace(0, 4, 1001)
    np.testing.assert_allclose(
        bot.fk(plan.trajectory.position(t))[:, :3, 3], motion.evaluate(t).position, atol=1e-8
    )


def test_ur5_full_pose_motion():
    ur5 = UR5()
    q_start = np.array([0.3, -1.2, 1.5, -1.9, -1.57, 0.2])
    start = ur5.fk(q_start)
    goal = start.copy()
    goal[:3, 3] += [0.1, 0.15, -0.1]
    goal[:3, :3] = rotation([0.0, 0.0, 0.5]) @ start[:3, :3]
    motion = through_poses(np.stack([start, goal]), "quintic", durations=[4.0])
    plan = to_joint_space(ur5, motion, dt=0.01, q_start=q_start)
    np.testing.assert_allclose(plan.q[0], q_start, atol=1e-9)
    assert plan.ok and plan.path_error < 1e-8
    t = np.linspace(0, 4, 401)
    poses = ur5.fk(plan.trajectory.position(t))
    desired = motion.evaluate(t)
    np.testing.assert_allclose(poses[:, :3, 3], desired.position, atol=1e-8)
    assert np.abs(rotation_error(desired.rotation, poses[:, :3, :3])).max() < 1e-8


def test_unreachable_sample_gives_its_time():
    arm = Planar2R(1.0, 0.5)
    motion = timed(Line([1.0, 0.0, 0.0], [2.0, 0.0, 0.0]), "linear", duration=2.0)
    with pytest.raises(UnreachableError, match=r"t=1\.1 s") as excinfo:
        to_joint_space(arm, motion, dt=0.1)
    assert "beyond" in str(excinfo.value)


def test_unreachable_sample_of_a_numerical_chain():
    ur5 = UR5()
    start = ur5.fk([0.3, -1.2, 1.5, -1.9, -1.57, 0.2])
    goal = start.copy()
    goal[:3, 3] += [3.0, 0.0, 0.0]
    motion = through_poses(np.stack([start, goal]), "cubic", durations=[2.0])
    with pytest.raises(UnreachableError, match=r"task sample at t="):
        to_joint_space(ur5, motion, dt=0.05, q_start=[0.3, -1.2, 1.5, -1.9, -1.57, 0.2])


def test_singularity_is_reported():
    arm = Planar2R(1.0, 1.0)
    # Out to full stretch and back along the x axis: the elbow straightens at t = 1.
    motion = through_poses([[1.0, 0.0, 0.0], [2.0, 0.0, 0.0], [1.0, 0.0, 0.0]], "quintic",
                           durations=[1.0, 1.0])  # fmt: skip
    plan = to_joint_space(arm, motion, dt=0.01)
    assert plan.singular_time == pytest.approx(1.0, abs=0.02)
    assert not plan.ok
    assert any("singularity" in p for p in plan.problems())


def test_joint_limit_violation_reports_first_time_and_joint():
    rows = [DHRow(a=1.0, velocity=0.5), DHRow(a=0.5, lower=0.0, upper=2.0, velocity=5.0)]
    arm = SerialChain.from_dh(rows)
    motion = timed(Arc([0, 0, 0], [1.2, 0, 0], np.pi / 2), "quintic", duration=1.0)
    plan = to_joint_space(arm, motion, dt=0.01, q_start=[-0.5, 1.2])
    assert not plan.ok
    time, joint, quantity = plan.first_violation
    assert (joint, quantity) == (0, "velocity")
    speed = np.abs(plan.qd[:, 0])
    assert time == pytest.approx(plan.t[np.argmax(speed > 0.5 * (1 + 1e-9))])
    assert any("joint 1 first exceeds its velocity limit" in p for p in plan.problems())
    assert any(v.quantity == "velocity" and v.joint == 0 for v in plan.limits.violations)


def test_a_line_through_the_inner_singularity_is_named():
    arm = SerialChain.from_dh([DHRow(a=1.0), DHRow(a=0.5)])  # numerical IK
    motion = timed(Line([1.0, 0.5, 0.0], [-1.0, 0.5, 0.0]), "quintic", duration=3.0)
    with pytest.raises(InfeasibleError, match="singularity"):
        to_joint_space(arm, motion, dt=0.02, q_start=[0.0, 1.0])


def test_tolerance_asks_for_a_smaller_dt():
    arm, motion, _ = seed003()
    with pytest.raises(InfeasibleError, match="use a smaller dt"):
        to_joint_space(arm, motion, dt=2.5, tolerance=1e-12)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"dt": 0.0}, "dt must be > 0"),
        ({"dt": np.nan}, "dt must be finite"),
        ({"dt": 0.1, "q_start": [0.0, 0.0]}, r"q_start must have shape \(3,\)"),
        ({"dt": 0.1, "tolerance": -1.0}, "tolerance must be > 0"),
        ({"dt": 0.1, "branch": "sideways"}, "branch must be one of"),
    ],
)
def test_joint_space_bad_input(kwargs, message):
    arm, motion, _ = seed003()
    with pytest.raises(InvalidInputError, match=message) as excinfo:
        to_joint_space(arm, motion, **kwargs)
    assert type(excinfo.value) is InvalidInputError


def test_orientation_task_on_a_position_only_arm():
    oriented = timed(PATHS["line"], "cubic", duration=10.0, orientation=np.eye(3))
    with pytest.raises(InvalidInputError, match="sets only its tool position"):
        to_joint_space(Spatial3R(), oriented, dt=0.1)
    with pytest.raises(InvalidInputError, match="robot must be a trajkit SerialChain"):
        to_joint_space("arm", oriented, dt=0.1)  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match="branch applies to closed-form arms only"):
        to_joint_space(UR5(), oriented, dt=0.1, branch=0)


@settings(max_examples=15, deadline=None)
@given(
    x0=st.floats(0.6, 1.1), y0=st.floats(0.6, 0.9), x1=st.floats(-1.1, -0.6), y1=st.floats(0.6, 0.9)
)
def test_property_planar_lines_are_tracked_and_checked(x0, y0, x1, y1):
    # A plain chain with a joint range: numerical IK, and a limit that may bind.
    arm_joints = SerialChain.from_dh([DHRow(a=1.0, lower=-4, upper=4), DHRow(a=0.5)])
    motion = timed(Line([x0, y0, 0.0], [x1, y1, 0.0]), "quintic", duration=3.0)
    plan = to_joint_space(arm_joints, motion, dt=0.02, q_start=[0.0, 1.0])
    t = np.linspace(0, 3, 3001)
    tool = arm_joints.fk(plan.trajectory.position(t))[:, :3, 3]
    error = np.linalg.norm(tool - motion.evaluate(t).position, axis=1).max()
    assert error <= max(plan.path_error * 2, 1e-9)
    dense = plan.trajectory.position(t)
    inside = np.all((dense >= -4 - 1e-9) & (dense <= 4 + 1e-9))
    assert inside == plan.limits.ok
