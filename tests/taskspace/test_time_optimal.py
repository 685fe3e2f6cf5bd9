"""Tests of trajkit.taskspace.time_optimal: a tool path timed as fast as the joint limits allow.

Seed 003's line on the course's 3-DOF arm, an arc on a planar 2R arm with asymmetric
limits, and a line on the UR5 (numerical IK): the joint limits hold exactly, the
tightest is reached, the tool stays on the path and never runs backwards, the move
is at rest at both ends, and it beats the same path timed by a quintic at the
shortest duration whose joint peaks keep the limits. Jerk limits, TaskTrajectory
input, bad input and unreachable paths.
"""

from __future__ import annotations

import numpy as np
import pytest

import trajkit as tk
from support import LIMIT_TOUCH
from trajkit.errors import InvalidInputError, UnreachableError
from trajkit.kinematics import UR5, Planar2R, SerialChain, Spatial3R
from trajkit.taskspace import Arc, Line, TimeOptimalMove, time_optimal, timed, to_joint_space

# Tolerances ---------------------------------------------------------------------
ON_PATH = 1e-6  # length unit of the robot: dense FK of the timed joints against the path
EXACT = 1e-9  # length unit / rad: the ends, where IK is solved exactly
REST = 1e-12  # rad/s: joint velocities at the ends
KEPT = 1e-9  # relative: check()'s slack on a bound
PATH_ERROR_FACTOR = 1.5  # dense FK error vs path_error (measured at quarter points only)
DENSE = 4001  # samples along the timed move

# The course's 3-DOF arm (cm) and seed 003's line; joint limits in rad/s, rad/s².
ARM = Spatial3R(5.0, 10.0, 8.0, 12.0)
SEED_LINE = Line([0.0, -12.0, 20.0], [10.0, 12.0, 20.0])
ARM_LIMITS = tk.Limits(velocity=1.0, acceleration=2.0)

PLANAR = Planar2R(1.0, 0.8)
HALF_CIRCLE = Arc([0.0, 0.0, 0.0], [1.2, 0.0, 0.0], np.pi)
PLANAR_LIMITS = tk.Limits(velocity=[1.0, 2.0], acceleration=(-3.0, 4.0))

UR5_A = np.array([0.2, -1.0, 1.3, -1.6, -1.4, 0.4])
UR5_B = np.array([-0.4, -1.4, 1.8, -2.0, -1.7, -0.3])
UR5_LIMITS = tk.Limits(velocity=np.pi, acceleration=[8.0, 8.0, 8.0, 10.0, 10.0, 10.0])


def ur5_line() -> tuple[SerialChain, Line]:
    ur5 = UR5()
    points = ur5.fk(np.stack([UR5_A, UR5_B]))[:, :3, 3]
    return ur5, Line(points[0], points[1])


def peak_ratio(trajectory: tk.Trajectory, limits: tk.Limits) -> float:
    """Largest peak / bound over the limited rates (both sides, every joint)."""
    report = trajectory.check(limits)
    worst = 0.0
    for quantity in ("velocity", "acceleration", "jerk"):
        if quantity in report.peaks:
            low, high = report.peaks[quantity]
            lower, upper = report.bounds[quantity]
            worst = max(worst, float(np.max(np.maximum(high / upper, low / lower))))
    return worst


def tool(robot: SerialChain, trajectory: tk.Trajectory, t: np.ndarray) -> np.ndarray:
    return robot.fk(trajectory.position(t))[:, :3, 3]


def along_line(points: np.ndarray, line: Line) -> tuple[np.ndarray, np.ndarray]:
    """Distance of each point from the line's segment, and its parameter u along it."""
    start, delta = line.start, line.end - line.start
    u = (points - start) @ delta / (delta @ delta)
    foot = start + np.clip(u, 0.0, 1.0)[:, None] * delta
    return np.linalg.norm(points - foot, axis=1), u


def dense_times(trajectory: tk.Trajectory) -> np.ndarray:
    return np.linspace(trajectory.start_time, trajectory.end_time, DENSE)


def assert_timed_move(move: TimeOptimalMove, limits: tk.Limits) -> tk.Trajectory:
    """What every time-optimal move must satisfy, whatever the robot."""
    trajectory = move.trajectory
    report = trajectory.check(limits)
    assert report.ok, str(report)
    # Time-optimal: the tightest limit is reached, not merely kept.
    assert 1.0 - LIMIT_TOUCH <= peak_ratio(trajectory, limits) <= 1.0 + KEPT
    assert trajectory.start_time == 0.0 and move.duration == trajectory.duration > 0.0
    np.testing.assert_allclose(trajectory.velocity([0.0, move.duration]), 0.0, atol=REST)
    assert trajectory.info["planner"] == "time_optimal"
    assert trajectory.info["path_error"] == move.path_error == move.geometry.path_error
    assert move.path_error <= 1e-6  # the default tolerance
    return trajectory


# ------------------------------------------------------------------ seed 003's line
def test_course_arm_line_keeps_the_limits_and_follows_the_line():
    move = time_optimal(ARM, SEED_LINE, ARM_LIMITS)
    trajectory = assert_timed_move(move, ARM_LIMITS)
    ends = tool(ARM, trajectory, np.array([0.0, move.duration]))
    np.testing.assert_allclose(ends, [SEED_LINE.start, SEED_LINE.end], rtol=0, atol=EXACT)
    distance, u = along_line(tool(ARM, trajectory, dense_times(trajectory)), SEED_LINE)
    # Measured 1.0e-9 cm (path_error 1.7e-9 cm).
    assert distance.max() <= min(ON_PATH, PATH_ERROR_FACTOR * move.path_error + 1e-12)
    # Retiming never runs the path backwards: the tool's progress only grows.
    assert np.all(np.diff(u) >= -1e-12) and u[0] == pytest.approx(0, abs=1e-12)
    assert u[-1] == pytest.approx(1.0, abs=1e-12)
    assert move.duration == pytest.approx(3.2285, abs=1e-4)  # measured 3.228524 s


def test_planar_arm_half_circle_with_asymmetric_limits():
    move = time_optimal(PLANAR, HALF_CIRCLE, PLANAR_LIMITS)
    trajectory = assert_timed_move(move, PLANAR_LIMITS)
    points = tool(PLANAR, trajectory, dense_times(trajectory))
    np.testing.assert_allclose(np.linalg.norm(points[:, :2], axis=1), 1.2, rtol=0, atol=ON_PATH)
    np.testing.assert_allclose(points[:, 2], 0.0, atol=ON_PATH)
    heading = np.unwrap(np.arctan2(points[:, 1], points[:, 0]))
    assert np.all(np.diff(heading) >= -1e-12)  # counter-clockwise, never back
    np.testing.assert_allclose(heading[[0, -1]], [0.0, np.pi], atol=EXACT)


def test_ur5_line_from_its_start_configuration():
    ur5, line = ur5_line()
    move = time_optimal(ur5, line, UR5_LIMITS, q_start=UR5_A)
    trajectory = assert_timed_move(move, UR5_LIMITS)
    np.testing.assert_allclose(trajectory(0.0), UR5_A, atol=1e-8)
    distance, u = along_line(tool(ur5, trajectory, dense_times(trajectory)), line)
    assert distance.max() <= ON_PATH
    assert np.all(np.diff(u) >= -1e-9) and u[-1] == pytest.approx(1.0, abs=1e-9)


def test_branch_selects_the_elbow():
    up = time_optimal(ARM, SEED_LINE, ARM_LIMITS)
    down = time_optimal(ARM, SEED_LINE, ARM_LIMITS, branch="forward_elbow_negative")
    t = dense_times(down.trajectory)
    assert np.all(up.trajectory(dense_times(up.trajectory))[:, 2] > 0.0)
    assert np.all(down.trajectory(t)[:, 2] < 0.0)
    assert down.trajectory.check(ARM_LIMITS).ok
    distance, _ = along_line(tool(ARM, down.trajectory, t), SEED_LINE)
    assert distance.max() <= ON_PATH


# --------------------------------------------------- against a quintic at its fastest
CASES = {
    "arm_line": (ARM, SEED_LINE, ARM_LIMITS, {}),
    "planar_arc": (PLANAR, HALF_CIRCLE, PLANAR_LIMITS, {}),
    "ur5_line": (*ur5_line(), UR5_LIMITS, {"q_start": UR5_A}),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_faster_than_a_quintic_at_the_shortest_duration_within_the_limits(case):
    robot, path, limits, options = CASES[case]
    samples = 200

    def quintic(duration: float) -> tk.Trajectory:
        motion = timed(path, "quintic", duration=duration)
        return to_joint_space(robot, motion, ik_step=duration / samples, **options).trajectory

    # The same u-samples at any duration: joint velocities scale with 1/T and
    # accelerations with 1/T², so the shortest duration within the limits is exact.
    report = quintic(1.0).check(limits)
    need = {}
    for quantity in ("velocity", "acceleration"):
        low, high = report.peaks[quantity]
        lower, upper = report.bounds[quantity]
        need[quantity] = float(np.max(np.maximum(high / upper, low / lower)))
    shortest = max(need["velocity"], np.sqrt(need["acceleration"]))
    at_limit = quintic(shortest)
    assert at_limit.check(limits).ok
    assert peak_ratio(at_limit, limits) == pytest.approx(1.0, abs=1e-6)  # it is the shortest
    move = time_optimal(robot, path, limits, samples=samples, **options)
    # Measured: 0.654 (arm line, 3.23 s vs 4.94 s), 0.583 (planar arc, 3.43 vs 5.89),
    # 0.768 (UR5 line, 0.625 vs 0.815).
    assert move.duration < 0.8 * shortest


# ------------------------------------------------------------------------------ jerk
def test_a_jerk_limit_passes_through_to_the_timing():
    limits = tk.Limits(velocity=1.0, acceleration=2.0, jerk=5.0)
    move = time_optimal(ARM, SEED_LINE, limits)
    trajectory = assert_timed_move(move, limits)
    assert trajectory.info["jerk_limited"] is True
    np.testing.assert_allclose(trajectory.acceleration([0.0, move.duration]), 0.0, atol=1e-9)
    unlimited = time_optimal(ARM, SEED_LINE, ARM_LIMITS)
    # Measured 4.41 s against 3.23 s without the jerk limit.
    assert unlimited.duration < move.duration < 1.5 * unlimited.duration
    distance, u = along_line(tool(ARM, trajectory, dense_times(trajectory)), SEED_LINE)
    assert distance.max() <= ON_PATH
    assert np.all(np.diff(u) >= -1e-12)


# --------------------------------------------------------------- TaskTrajectory input
def test_a_task_trajectory_gives_its_geometry_only():
    from_path = time_optimal(ARM, SEED_LINE, ARM_LIMITS)
    motion = timed(SEED_LINE, "cubic", duration=7.0)
    move = time_optimal(ARM, motion, ARM_LIMITS)
    trajectory = assert_timed_move(move, ARM_LIMITS)
    distance, _ = along_line(tool(ARM, trajectory, dense_times(trajectory)), SEED_LINE)
    assert distance.max() <= ON_PATH
    # The cubic's own timing is gone: within the grid's resolution of the same timing
    # as from the bare path (measured 3.2495 s vs 3.2285 s: 0.65%).
    assert move.duration == pytest.approx(from_path.duration, rel=0.01)


def test_a_quintic_task_trajectory_is_timed_like_its_path():
    from_path = time_optimal(ARM, SEED_LINE, ARM_LIMITS)
    move = time_optimal(ARM, timed(SEED_LINE, "quintic", duration=7.0), ARM_LIMITS)
    assert move.trajectory.check(ARM_LIMITS).ok
    assert move.duration == pytest.approx(from_path.duration, rel=0.01)


# ------------------------------------------------------------------------- bad input
@pytest.mark.parametrize("samples", [1, 0, -5, 2.0, 2.5, True, "200", None])
def test_samples_must_be_an_integer_of_at_least_two(samples):
    with pytest.raises(InvalidInputError, match="samples must be an integer >= 2, got") as e:
        time_optimal(ARM, SEED_LINE, ARM_LIMITS, samples=samples)
    assert repr(samples) in str(e.value)


@pytest.mark.parametrize(
    ("path", "kind"),
    [
        ([[0.0, -12.0, 20.0], [10.0, 12.0, 20.0]], "list"),
        (np.zeros((2, 3)), "ndarray"),
        (tk.cubic_spline([0.0, 1.0], [[0.0, 0.0, 0.0], [1.0, 1.0, 1.0]]), "Trajectory"),
    ],
)
def test_path_must_be_a_taskspace_path_or_task_trajectory(path, kind):
    with pytest.raises(InvalidInputError, match="path must be a taskspace Path or TaskTrajectory"
                       ) as e:  # fmt: skip
        time_optimal(ARM, path, ARM_LIMITS)
    assert str(e.value).endswith(f"got {kind}")


def test_limits_need_velocity_and_acceleration():
    with pytest.raises(InvalidInputError, match="velocity and acceleration bounds"):
        time_optimal(ARM, SEED_LINE, tk.Limits(velocity=1.0))


def test_an_unreachable_path_names_the_first_sample_outside():
    # x = 1 + 1.9 u leaves the annulus r <= 1.8 at u = 0.421: sample 85 of 200, u = 0.425.
    with pytest.raises(UnreachableError, match=r"t=0\.425 s: .* out of reach of planar 2R"):
        time_optimal(PLANAR, Line([1.0, 0.0, 0.0], [2.9, 0.0, 0.0]), PLANAR_LIMITS)


def test_the_timed_move_ends_exactly_at_rest_where_the_path_ends():
    # Issue 16 item 6: the task-space timing keeps topp's exact boundary states (it used
    # to rebuild the trajectory from its pieces, whose end velocity is a rounding residue).
    move = time_optimal(ARM, SEED_LINE, ARM_LIMITS)
    tr = move.trajectory
    np.testing.assert_array_equal(tr.velocity([tr.end_time, tr.end_time + 1.0]), 0.0)
    np.testing.assert_array_equal(tr.velocity(tr.start_time), 0.0)
    assert tr.info["planner"] == "time_optimal"
