"""Tests of trajkit.io.ros2: plans written as ROS 2 bags, read back by two readers.

Every bag is read with rosbags (the library that wrote it) and, for MCAP, with the
independent ``mcap`` reader and its ROS 2 decoder. The numbers in a bag are float64
and the writer stores exactly what the plan evaluates to, so values compare bit for
bit; times compare as whole nanoseconds.
"""

from __future__ import annotations

import itertools
import math
import os
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

pytest.importorskip(
    "rosbags", reason='trajkit.io.ros2 writes bags with rosbags: pip install "trajkit[ros]"'
)
pytest.importorskip(
    "mcap", reason="bags are read back by the independent MCAP reader: pip install mcap"
)
pytest.importorskip(
    "mcap_ros2",
    reason="bags are read back by the independent MCAP reader: pip install mcap-ros2-support",
)

from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory
from rosbags.rosbag2 import Reader
from rosbags.typesys import Stores, get_typestore
from rosbags.typesys.store import Typestore

import trajkit as tk
from support import assert_state, joint_arrays, limits_positive, ndofs
from trajkit.curve import sample_times
from trajkit.errors import InvalidInputError, TrajkitError
from trajkit.io import atomic
from trajkit.io.ros2 import Ros2Unavailable, write_bag
from trajkit.mobile import MobileTrajectory, constant_twist, rotate_translate_rotate

TYPES = get_typestore(Stores.ROS2_HUMBLE)
BILLION = 1_000_000_000
#: builtin_interfaces/Time has an int32 ``sec``: the last stamp a message can carry (ns).
LAST_STAMP = (2**31 - 1) * BILLION + BILLION - 1

JOINT_TRAJECTORY = "trajectory_msgs/msg/JointTrajectory"
JOINT_STATE = "sensor_msgs/msg/JointState"
POINT = "trajectory_msgs/msg/JointTrajectoryPoint"
TWIST = "geometry_msgs/msg/Twist"
PATH = "nav_msgs/msg/Path"


class WriterFailed(Exception):
    """Raised on purpose inside the writer under test."""


# Plans ----------------------------------------------------------------------------
def _cubic() -> tk.Trajectory:
    return tk.cubic(np.radians([0, 0]), np.radians([67, -45]), vmax=np.radians([9, 11]))


def _trapezoid() -> tk.Trajectory:  # 6 joints, time-synchronised: many breakpoints
    return tk.trapezoidal(np.zeros(6), np.radians([10, -20, 30, 45, -60, 90]), 1.0, 2.0)


def _scurve() -> tk.Trajectory:
    return tk.scurve(np.zeros(2), [1.0, -0.5], 1.0, 2.0, 10.0)


def _quintic() -> tk.Trajectory:
    return tk.quintic(np.zeros(2), [1.0, 2.0], 1.5)


def _septic() -> tk.Trajectory:  # degree 7 > 5: sampled every 10 ms
    return tk.septic(np.zeros(3), [1.0, 2.0, -1.0], 2.0)


def _shifted(plan: tk.Trajectory, by: float) -> tk.Trajectory:
    """``plan`` starting ``by`` seconds later (coefficients are local to each piece)."""
    return tk.Trajectory(plan.breakpoints + by, plan.coefficients)


def _constant_twist() -> MobileTrajectory:
    return constant_twist(0.1, np.radians(10), 15.0, rate_hz=10)


def _rtr() -> MobileTrajectory:  # no rate_hz of its own: commands at 10 Hz
    return rotate_translate_rotate(
        (1.0, 0.5, 0.3), vmax=0.5, wmax=1.0, amax=0.5, alpha_max=1.0, profile="trapezoid"
    )


# Reading bags -----------------------------------------------------------------------
def _names(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir())


def _read(bag: Path) -> dict[str, list[tuple[int, Any]]]:
    """Topic -> [(bag time ns, message)] in bag order, read by rosbags."""
    topics: dict[str, list[tuple[int, Any]]] = {}
    with Reader(bag) as reader:
        for connection, stamp, raw in reader.messages():
            message = TYPES.deserialize_cdr(raw, connection.msgtype)
            assert message.__msgtype__ == connection.msgtype
            topics.setdefault(connection.topic, []).append((stamp, message))
    return topics


def _read_mcap(bag: Path) -> dict[str, list[tuple[int, Any]]]:
    """Topic -> [(log time ns, message)], read by the independent MCAP reader."""
    (file,) = bag.glob("*.mcap")
    topics: dict[str, list[tuple[int, Any]]] = {}
    with file.open("rb") as handle:
        reader = make_reader(handle, decoder_factories=[DecoderFactory()])
        for schema, channel, message, decoded in reader.iter_decoded_messages(log_time_order=False):
            assert channel.message_encoding == "cdr"
            topics.setdefault(channel.topic, []).append((message.log_time, (schema.name, decoded)))
    return topics


def _mcap_types(topics: dict[str, list[tuple[int, Any]]]) -> dict[str, set[str]]:
    return {topic: {schema for _, (schema, _) in entries} for topic, entries in topics.items()}


def _strip(topics: dict[str, list[tuple[int, Any]]]) -> dict[str, list[tuple[int, Any]]]:
    """Drop the schema names of :func:`_read_mcap` entries."""
    return {t: [(s, m) for s, (_, m) in entries] for t, entries in topics.items()}


def _ns(stamp: Any) -> int:
    """A builtin_interfaces Time or Duration as whole nanoseconds; the split is canonical."""
    assert 0 <= stamp.nanosec < BILLION
    return stamp.sec * BILLION + stamp.nanosec


def _rint_ns(seconds: np.ndarray) -> list[int]:
    """Round-to-nearest nanoseconds, as plain ints."""
    return [round(s * 1e9) for s in np.asarray(seconds, float).tolist()]


def _rows(values: list[Any]) -> np.ndarray:
    """float64 sequences (numpy arrays or lists) stacked into an (n, ndof) array."""
    return np.array([np.asarray(v, dtype=np.float64) for v in values])


def _c2(plan: tk.Trajectory) -> bool:
    inner = plan.breakpoints[1:-1]
    if inner.size == 0:
        return True
    before = plan.evaluate(np.nextafter(inner, -np.inf), 2)
    return bool(np.abs(plan.evaluate(inner, 2) - before).max() <= 1e-9)


def _arm_times(plan: tk.Trajectory, dt: float | None) -> np.ndarray:
    # Breakpoints where the controller's quintic interpolation reproduces the plan (degree
    # <= 5, acceleration continuous), else every 10 ms; never two points in one nanosecond.
    if dt is not None:
        times = sample_times(plan.start_time, plan.end_time, dt)
    elif plan.degree <= 5 and _c2(plan):
        times = plan.breakpoints
    else:
        times = sample_times(plan.start_time, plan.end_time, 0.01)
    stamps = np.rint((times - plan.start_time) * 1e9).astype(np.int64)
    return times[np.append(np.diff(stamps) > 0, True)]


def _assert_points(
    points: list[Any], plan: tk.Trajectory, times: np.ndarray, *, accelerations: bool = True
) -> None:
    """Each point is the plan's state at ``times`` (exactly) and its time since the start."""
    assert len(points) == times.size
    np.testing.assert_array_equal(_rows([p.positions for p in points]), plan.evaluate(times, 0))
    np.testing.assert_array_equal(_rows([p.velocities for p in points]), plan.evaluate(times, 1))
    if accelerations:
        np.testing.assert_array_equal(
            _rows([p.accelerations for p in points]), plan.evaluate(times, 2)
        )
    assert all(len(p.effort) == 0 for p in points)
    assert [_ns(p.time_from_start) for p in points] == _rint_ns(times - plan.start_time)


def _assert_joint_trajectory(
    message: Any, plan: tk.Trajectory, times: np.ndarray, names: list[str], start_ns: int
) -> None:
    assert list(message.joint_names) == names
    assert _ns(message.header.stamp) == start_ns
    assert message.header.frame_id == ""
    _assert_points(list(message.points), plan, times)


# 1. The JointTrajectory of an arm plan ----------------------------------------------
ARM_CASES = [
    pytest.param(_cubic, None, id="cubic-breakpoints"),
    pytest.param(_trapezoid, None, id="trapezoid-6-joints-breakpoints"),
    pytest.param(_scurve, None, id="scurve-breakpoints"),
    pytest.param(_quintic, None, id="quintic-breakpoints"),
    pytest.param(_septic, None, id="septic-every-10-ms"),
    pytest.param(_cubic, 0.25, id="cubic-dt"),
    pytest.param(_septic, 0.3, id="septic-dt-uneven-end"),
    pytest.param(lambda: _shifted(_scurve(), 3.25), None, id="scurve-starting-late"),
    pytest.param(lambda: _shifted(_septic(), -1.5), 0.07, id="septic-starting-early-dt"),
]


@pytest.mark.parametrize(("make", "dt"), ARM_CASES)
def test_an_arm_plan_is_one_joint_trajectory_read_back_by_both_readers(
    tmp_path: Path, make: Callable[[], tk.Trajectory], dt: float | None
) -> None:
    plan = make()
    times = _arm_times(plan, dt)
    names = [f"joint{j + 1}" for j in range(plan.ndof)]
    bag = write_bag(tmp_path / "arm", plan, sample_step=dt)
    assert bag == tmp_path / "arm"
    assert _names(bag) == ["arm.mcap", "metadata.yaml"]

    ours = _read(bag)
    assert list(ours) == ["/joint_trajectory"]
    ((stamp, message),) = ours["/joint_trajectory"]
    assert stamp == 0
    assert message.__msgtype__ == JOINT_TRAJECTORY
    _assert_joint_trajectory(message, plan, times, names, 0)

    theirs = _read_mcap(bag)
    assert _mcap_types(theirs) == {"/joint_trajectory": {JOINT_TRAJECTORY}}
    ((stamp, message),) = _strip(theirs)["/joint_trajectory"]
    assert stamp == 0
    _assert_joint_trajectory(message, plan, times, names, 0)


def test_the_sampling_rule_by_degree() -> None:
    # The cases above rely on these: breakpoints up to degree 5, 10 ms beyond.
    assert _cubic().degree == 3 and _trapezoid().degree <= 5 and _scurve().degree <= 5
    assert _quintic().degree == 5 and _septic().degree == 7
    assert _arm_times(_septic(), None).size == 201
    assert _trapezoid().breakpoints.size > 2  # several pieces, not one


def test_the_last_point_is_the_end_of_the_plan_to_the_nanosecond(tmp_path: Path) -> None:
    for make, dt in [(_trapezoid, None), (_septic, None), (_septic, 0.3), (_cubic, 0.25)]:
        plan = make()
        bag = write_bag(tmp_path / "bag", plan, sample_step=dt)
        ((_, message),) = _read(bag)["/joint_trajectory"]
        assert _ns(message.points[0].time_from_start) == 0
        assert _ns(message.points[-1].time_from_start) == round(plan.duration * 1e9)
        np.testing.assert_array_equal(message.points[-1].positions, plan.end_state.position)


def test_joint_names_are_written_as_given(tmp_path: Path) -> None:
    names = ["shoulder_pan", "shoulder_lift", "elbow", "wrist_1", "wrist_2", "wrist_3"]
    plan = _trapezoid()
    bag = write_bag(tmp_path / "bag", plan, joint_names=tuple(names), stream="joint_state")
    ((_, trajectory),) = _read(bag)["/joint_trajectory"]
    assert list(trajectory.joint_names) == names
    assert all(list(state.name) == names for _, state in _read(bag)["/joint_states"])
    ((_, decoded),) = _strip(_read_mcap(bag))["/joint_trajectory"]
    assert list(decoded.joint_names) == names


# The docstring: quintic interpolation between the points reproduces a plan of degree <= 5.
def _quintic_hermite(
    t0: float, t1: float, start: tuple[np.ndarray, ...], end: tuple[np.ndarray, ...], t: np.ndarray
) -> np.ndarray:
    """The quintic with position, velocity and acceleration ``start`` at t0, ``end`` at t1."""
    h = t1 - t0
    s = ((t - t0) / h)[:, None]
    s3, s4, s5 = s**3, s**4, s**5
    (p0, v0, a0), (p1, v1, a1) = start, end
    return (
        (1 - 10 * s3 + 15 * s4 - 6 * s5) * p0
        + h * (s - 6 * s3 + 8 * s4 - 3 * s5) * v0
        + h * h * (0.5 * s**2 - 1.5 * s3 + 1.5 * s4 - 0.5 * s5) * a0
        + (10 * s3 - 15 * s4 + 6 * s5) * p1
        + h * (-4 * s3 + 7 * s4 - 3 * s5) * v1
        + h * h * (0.5 * s3 - s4 + 0.5 * s5) * a1
    )


def test_the_quintic_hermite_helper_is_exact_on_a_quintic() -> None:
    # Check the test's own interpolant: one piece of degree 5 is reproduced.
    plan = _quintic()
    (t0, t1) = plan.breakpoints
    ends = [tuple(plan.evaluate(t, order) for order in range(3)) for t in (t0, t1)]
    t = np.linspace(t0, t1, 101)
    assert_state(_quintic_hermite(t0, t1, ends[0], ends[1], t), plan.evaluate(t), rtol=1e-12)


@pytest.mark.parametrize(
    "make",
    [
        pytest.param(_scurve, id="scurve"),
        pytest.param(_cubic, id="cubic"),
        pytest.param(_quintic, id="quintic"),
        pytest.param(lambda: _shifted(_scurve(), 3.25), id="scurve-starting-late"),
        # A trapezoid's acceleration jumps: sampled every 10 ms, the interpolation is
        # close (within 1e-5 rad) but not exact; see the test below.
    ],
)
def test_quintic_interpolation_between_the_points_reproduces_the_plan(
    tmp_path: Path, make: Callable[[], tk.Trajectory]
) -> None:
    plan = make()
    assert plan.degree <= 5
    bag = write_bag(tmp_path / "bag", plan)
    ((_, message),) = _read(bag)["/joint_trajectory"]
    points = list(message.points)
    worst, where = 0.0, float("nan")
    for before, after in itertools.pairwise(points):
        # What a controller knows: the points' times (whole ns) and states.
        t0 = plan.start_time + _ns(before.time_from_start) / 1e9
        t1 = plan.start_time + _ns(after.time_from_start) / 1e9
        start = (before.positions, before.velocities, before.accelerations)
        end = (after.positions, after.velocities, after.accelerations)
        t = np.linspace(t0, t1, 41)
        expected = plan.evaluate(t)
        error = np.abs(_quintic_hermite(t0, t1, start, end, t) - expected)
        error /= np.maximum(1.0, np.abs(expected))
        if error.max() > worst:
            worst, where = float(error.max()), float(t[np.argmax(error.max(axis=1))])
    assert worst <= 1e-9, f"quintic interpolation is off by {worst:.3g} at t = {where:.6g} s"


# 2. Streams ---------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("make", "rate_hz", "start_ns"),
    [
        pytest.param(_scurve, None, 0, id="scurve-default-100-Hz"),
        pytest.param(_cubic, 40.0, 0, id="cubic-40-Hz"),
        pytest.param(_trapezoid, 30.0, 5 * BILLION + 7, id="trapezoid-30-Hz-late"),
        pytest.param(lambda: _shifted(_septic(), 2.5), 250, 123, id="septic-starting-late"),
    ],
)
def test_the_joint_state_stream(
    tmp_path: Path, make: Callable[[], tk.Trajectory], rate_hz: float | None, start_ns: int
) -> None:
    plan = make()
    rate = 100.0 if rate_hz is None else rate_hz
    ticks = sample_times(plan.start_time, plan.end_time, 1.0 / rate)
    stamps = [start_ns + ns for ns in _rint_ns(ticks - plan.start_time)]
    names = [f"joint{j + 1}" for j in range(plan.ndof)]
    bag = write_bag(
        tmp_path / "bag", plan, stream="joint_state", rate_hz=rate_hz, start_ns=start_ns
    )

    theirs = _read_mcap(bag)
    assert _mcap_types(theirs) == {
        "/joint_trajectory": {JOINT_TRAJECTORY},
        "/joint_states": {JOINT_STATE},
    }
    for topics in (_read(bag), _strip(theirs)):
        assert sorted(topics) == ["/joint_states", "/joint_trajectory"]
        ((stamp, trajectory),) = topics["/joint_trajectory"]
        assert stamp == start_ns
        _assert_joint_trajectory(trajectory, plan, _arm_times(plan, None), names, start_ns)
        states = topics["/joint_states"]
        assert len(states) == len(sample_times(plan.start_time, plan.end_time, 1.0 / rate))
        assert [stamp for stamp, _ in states] == stamps
        assert [_ns(state.header.stamp) for _, state in states] == stamps
        assert all(state.header.frame_id == "" for _, state in states)
        assert all(list(state.name) == names for _, state in states)
        np.testing.assert_array_equal(_rows([s.position for _, s in states]), plan.evaluate(ticks))
        np.testing.assert_array_equal(
            _rows([s.velocity for _, s in states]), plan.evaluate(ticks, 1)
        )
        assert all(len(state.effort) == 0 for _, state in states)


@pytest.mark.parametrize(
    ("make", "rate_hz"),
    [pytest.param(_scurve, None, id="scurve-100-Hz"), pytest.param(_septic, 33.0, id="septic")],
)
def test_the_point_stream(
    tmp_path: Path, make: Callable[[], tk.Trajectory], rate_hz: float | None
) -> None:
    plan = make()
    rate = 100.0 if rate_hz is None else rate_hz
    ticks = sample_times(plan.start_time, plan.end_time, 1.0 / rate)
    start_ns = 42 * BILLION + 999_999_999
    bag = write_bag(tmp_path / "bag", plan, stream="point", rate_hz=rate_hz, start_ns=start_ns)

    theirs = _read_mcap(bag)
    assert _mcap_types(theirs)["/joint_trajectory_point"] == {POINT}
    for topics in (_read(bag), _strip(theirs)):
        assert sorted(topics) == ["/joint_trajectory", "/joint_trajectory_point"]
        stream = topics["/joint_trajectory_point"]
        assert len(stream) == len(ticks)
        assert [stamp for stamp, _ in stream] == [
            start_ns + ns for ns in _rint_ns(ticks - plan.start_time)
        ]
        _assert_points([point for _, point in stream], plan, ticks)


# 3. Mobile plans ----------------------------------------------------------------------
def _assert_twists(entries: list[tuple[int, Any]], plan: MobileTrajectory, rate: float, start_ns):
    times, twists = plan.commands(rate)
    assert [stamp for stamp, _ in entries] == [start_ns + ns for ns in _rint_ns(times)]
    messages = [message for _, message in entries]
    linear = np.array([[m.linear.x, m.linear.y, m.linear.z] for m in messages])
    angular = np.array([[m.angular.x, m.angular.y, m.angular.z] for m in messages])
    zeros = np.zeros(len(messages))
    np.testing.assert_array_equal(linear, np.stack([twists[:, 0], zeros, zeros], axis=1))
    np.testing.assert_array_equal(angular, np.stack([zeros, zeros, twists[:, 1]], axis=1))


def _assert_path(
    entries: list[tuple[int, Any]], plan: MobileTrajectory, dt: float, start_ns: int, frame: str
) -> None:
    ((stamp, path),) = entries
    assert stamp == start_ns
    assert _ns(path.header.stamp) == start_ns
    assert path.header.frame_id == frame
    ticks = sample_times(0.0, plan.duration, dt)
    poses = plan.pose(ticks)
    stamped = list(path.poses)
    assert len(stamped) == ticks.size
    assert [_ns(p.header.stamp) for p in stamped] == [start_ns + ns for ns in _rint_ns(ticks)]
    assert all(p.header.frame_id == frame for p in stamped)
    position = np.array(
        [[p.pose.position.x, p.pose.position.y, p.pose.position.z] for p in stamped]
    )
    np.testing.assert_array_equal(position[:, :2], poses[:, :2])
    np.testing.assert_array_equal(position[:, 2], 0.0)
    orientation = np.array(
        [[o.x, o.y, o.z, o.w] for o in (p.pose.orientation for p in stamped)], dtype=np.float64
    )
    half = [theta / 2.0 for theta in poses[:, 2].tolist()]
    expected = np.array([[0.0, 0.0, np.sin(a), np.cos(a)] for a in half])
    np.testing.assert_array_equal(orientation, expected)
    # The same rotation as the heading, to rounding (sin, cos vs the math module).
    assert np.allclose(orientation[:, 2], [math.sin(a) for a in half], rtol=0, atol=1e-15)
    assert np.allclose(np.linalg.norm(orientation, axis=1), 1.0, rtol=0, atol=1e-15)


def test_a_constant_twist_plan(tmp_path: Path) -> None:
    plan = _constant_twist()
    assert plan.info["rate_hz"] == 10.0
    bag = write_bag(tmp_path / "base", plan)
    assert _names(bag) == ["base.mcap", "metadata.yaml"]
    theirs = _read_mcap(bag)
    assert _mcap_types(theirs) == {"/plan": {PATH}, "/cmd_vel": {TWIST}}
    for topics in (_read(bag), _strip(theirs)):
        assert sorted(topics) == ["/cmd_vel", "/plan"]
        assert len(topics["/cmd_vel"]) == plan.info["command_count"] == 150
        _assert_twists(topics["/cmd_vel"], plan, 10.0, 0)
        _assert_path(topics["/plan"], plan, 0.1, 0, "odom")
        assert len(topics["/plan"][0][1].poses) == 151


def test_the_command_rate_and_path_spacing_can_be_chosen(tmp_path: Path) -> None:
    plan = _constant_twist()
    bag = write_bag(tmp_path / "base", plan, rate_hz=25.0, sample_step=0.7, frame_id="map")
    for topics in (_read(bag), _strip(_read_mcap(bag))):
        assert len(topics["/cmd_vel"]) == 375
        _assert_twists(topics["/cmd_vel"], plan, 25.0, 0)
        _assert_path(topics["/plan"], plan, 0.7, 0, "map")


def test_a_rotate_translate_rotate_plan_in_sqlite3(tmp_path: Path) -> None:
    plan = _rtr()
    assert plan.info.get("rate_hz") is None  # so commands go at 10 Hz
    start_ns = 3 * BILLION + 500
    bag = write_bag(tmp_path / "rtr", plan, storage="sqlite3", sample_step=0.05, start_ns=start_ns)
    assert _names(bag) == ["metadata.yaml", "rtr.db3"]
    topics = _read(bag)
    assert sorted(topics) == ["/cmd_vel", "/plan"]
    assert len(topics["/cmd_vel"]) == math.ceil(plan.duration * 10)
    _assert_twists(topics["/cmd_vel"], plan, 10.0, start_ns)
    _assert_path(topics["/plan"], plan, 0.05, start_ns, "odom")
    with Reader(bag) as reader:
        assert {c.topic: c.msgtype for c in reader.connections} == {
            "/plan": PATH,
            "/cmd_vel": TWIST,
        }


def test_an_arm_plan_in_sqlite3(tmp_path: Path) -> None:
    plan = _septic()
    bag = write_bag(tmp_path / "arm", plan, storage="sqlite3", stream="point")
    assert _names(bag) == ["arm.db3", "metadata.yaml"]
    topics = _read(bag)
    ((_, trajectory),) = topics["/joint_trajectory"]
    _assert_joint_trajectory(
        trajectory, plan, _arm_times(plan, None), ["joint1", "joint2", "joint3"], 0
    )
    _assert_points([p for _, p in topics["/joint_trajectory_point"]], plan, _arm_times(plan, None))


# 4. start_ns, topic_prefix and the metadata -------------------------------------------
def test_start_ns_and_topic_prefix_for_an_arm_plan(tmp_path: Path) -> None:
    plan = _scurve()
    start_ns = 1_700_000_000_123_456_789
    bag = write_bag(
        tmp_path / "bag", plan, stream="joint_state", start_ns=start_ns, topic_prefix="/robot1"
    )
    ticks = sample_times(plan.start_time, plan.end_time, 0.01)
    stamps = [start_ns + ns for ns in _rint_ns(ticks)]
    for topics in (_read(bag), _strip(_read_mcap(bag))):
        assert sorted(topics) == ["/robot1/joint_states", "/robot1/joint_trajectory"]
        ((stamp, trajectory),) = topics["/robot1/joint_trajectory"]
        assert stamp == start_ns
        assert (trajectory.header.stamp.sec, trajectory.header.stamp.nanosec) == (
            1_700_000_000,
            123_456_789,
        )
        # time_from_start stays relative to the plan's start.
        _assert_joint_trajectory(trajectory, plan, plan.breakpoints, ["joint1", "joint2"], start_ns)
        states = topics["/robot1/joint_states"]
        assert [s for s, _ in states] == stamps
        assert [_ns(m.header.stamp) for _, m in states] == stamps

    with Reader(bag) as reader:
        assert reader.message_count == 1 + ticks.size
        assert {c.topic: c.msgcount for c in reader.connections} == {
            "/robot1/joint_trajectory": 1,
            "/robot1/joint_states": ticks.size,
        }
        assert reader.start_time == start_ns
        assert reader.end_time == stamps[-1] + 1  # rosbags: one past the last message
    (file,) = bag.glob("*.mcap")
    with file.open("rb") as handle:
        summary = make_reader(handle).get_summary()
    assert summary is not None and summary.statistics is not None
    statistics = summary.statistics
    assert statistics.message_count == 1 + ticks.size
    counts = {summary.channels[k].topic: n for k, n in statistics.channel_message_counts.items()}
    assert counts == {"/robot1/joint_trajectory": 1, "/robot1/joint_states": ticks.size}
    assert (statistics.message_start_time, statistics.message_end_time) == (start_ns, stamps[-1])


def test_start_ns_and_topic_prefix_for_a_mobile_plan(tmp_path: Path) -> None:
    plan = _constant_twist()
    start_ns = np.int64(9 * BILLION + 1)  # numpy integers are whole numbers too
    bag = write_bag(tmp_path / "bag", plan, start_ns=start_ns, topic_prefix="/fleet/r2")
    for topics in (_read(bag), _strip(_read_mcap(bag))):
        assert sorted(topics) == ["/fleet/r2/cmd_vel", "/fleet/r2/plan"]
        _assert_twists(topics["/fleet/r2/cmd_vel"], plan, 10.0, int(start_ns))
        _assert_path(topics["/fleet/r2/plan"], plan, 0.1, int(start_ns), "odom")
    with Reader(bag) as reader:
        assert reader.message_count == 151
        assert {c.topic: c.msgcount for c in reader.connections} == {
            "/fleet/r2/plan": 1,
            "/fleet/r2/cmd_vel": 150,
        }
        assert {c.topic: c.msgtype for c in reader.connections} == {
            "/fleet/r2/plan": PATH,
            "/fleet/r2/cmd_vel": TWIST,
        }


@pytest.mark.parametrize("storage", ["mcap", "sqlite3"])
def test_twist_stamped_commands_for_ros2_jazzy(tmp_path: Path, storage: str) -> None:
    # Jazzy's diff_drive_controller and Nav2 take geometry_msgs/TwistStamped on /cmd_vel:
    # the same twists, each stamped with its own bag time in the base's frame.
    plan = _constant_twist()
    start_ns = 1_796_634_000 * BILLION + 7
    bag = write_bag(tmp_path / "bag", plan, start_ns=start_ns, cmd_vel="TwistStamped",
                    base_frame="base_footprint", storage=storage)  # fmt: skip
    readings = [_read(bag)]
    if storage == "mcap":  # the independent reader too, with the schema names it saw
        mcap = _read_mcap(bag)
        assert _mcap_types(mcap)["/cmd_vel"] == {"geometry_msgs/msg/TwistStamped"}
        readings.append(_strip(mcap))
    for topics in readings:
        entries = topics["/cmd_vel"]
        assert all(_ns(m.header.stamp) == stamp for stamp, m in entries)
        assert {m.header.frame_id for _, m in entries} == {"base_footprint"}
        _assert_twists([(stamp, m.twist) for stamp, m in entries], plan, 10.0, start_ns)
        _assert_path(topics["/plan"], plan, 0.1, start_ns, "odom")
    with Reader(bag) as reader:
        types = {c.topic: c.msgtype for c in reader.connections}
    assert types == {"/plan": PATH, "/cmd_vel": "geometry_msgs/msg/TwistStamped"}


@pytest.mark.parametrize(
    ("plan", "kwargs", "message"),
    [
        (_constant_twist, {"cmd_vel": "twist"}, r"cmd_vel must be 'Twist' \(ROS 2 Humble\) or"),
        (_constant_twist, {"cmd_vel": None}, "cmd_vel must be 'Twist'"),
        (_constant_twist, {"base_frame": ""}, "base_frame must be a non-empty name"),
        (_cubic, {"cmd_vel": "TwistStamped"}, "cmd_vel and base_frame are for mobile plans"),
    ],
)
def test_bad_command_messages_are_refused(tmp_path: Path, plan, kwargs, message) -> None:
    with pytest.raises(InvalidInputError, match=message):
        write_bag(tmp_path / "bag", plan(), **kwargs)
    assert not (tmp_path / "bag").exists()


def test_the_metadata_counts_every_topic(tmp_path: Path) -> None:
    plan = _septic()
    bag = write_bag(tmp_path / "bag", plan, stream="point", rate_hz=20.0, storage="sqlite3")
    ticks = sample_times(plan.start_time, plan.end_time, 1.0 / 20.0)
    with Reader(bag) as reader:
        assert reader.message_count == 1 + ticks.size == 42
        assert {c.topic: (c.msgtype, c.msgcount) for c in reader.connections} == {
            "/joint_trajectory": (JOINT_TRAJECTORY, 1),
            "/joint_trajectory_point": (POINT, ticks.size),
        }
    text = (bag / "metadata.yaml").read_text()
    assert "storage_identifier: sqlite3" in text
    assert f"message_count: {1 + ticks.size}" in text


# 5. Atomicity -------------------------------------------------------------------------
def _snapshot(bag: Path) -> dict[str, tuple[int, bytes]]:
    return {p.name: (p.stat().st_ino, p.read_bytes()) for p in sorted(bag.iterdir())}


def _fail_on_call(monkeypatch: pytest.MonkeyPatch, call: int, error: BaseException) -> list[int]:
    """Make the ``call``-th Typestore.serialize_cdr raise ``error``; returns the call log."""
    calls: list[int] = []
    real = Typestore.serialize_cdr

    def serialize(self: Typestore, message: Any, typename: str, *args: Any, **kwargs: Any):
        calls.append(1)
        if len(calls) == call:
            raise error
        return real(self, message, typename, *args, **kwargs)

    monkeypatch.setattr(Typestore, "serialize_cdr", serialize)
    return calls


def test_accepts_a_string_and_a_relative_path(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    result = write_bag("relative", _cubic())
    assert result == Path("relative")
    assert isinstance(result, Path)
    assert write_bag(str(tmp_path / "absolute"), _cubic()) == tmp_path / "absolute"
    assert _names(tmp_path) == ["absolute", "relative"]
    assert _names(tmp_path / "relative") == ["metadata.yaml", "relative.mcap"]


def test_writing_over_a_bag_replaces_it_and_leaves_nothing_behind(tmp_path: Path) -> None:
    target = tmp_path / "bag"
    write_bag(target, _cubic(), stream="joint_state")
    plan = _septic()
    write_bag(target, plan)
    assert _names(tmp_path) == ["bag"]  # no hidden temporary folder, no old bag
    assert _names(target) == ["bag.mcap", "metadata.yaml"]
    topics = _read(target)
    assert list(topics) == ["/joint_trajectory"]  # the old stream is gone
    ((_, message),) = topics["/joint_trajectory"]
    _assert_points(list(message.points), plan, _arm_times(plan, None))
    # Another storage: the old .mcap file does not linger beside the .db3.
    write_bag(target, _constant_twist(), storage="sqlite3")
    assert _names(tmp_path) == ["bag"]
    assert _names(target) == ["bag.db3", "metadata.yaml"]
    assert sorted(_read(target)) == ["/cmd_vel", "/plan"]


@pytest.mark.parametrize("call", [1, 3], ids=["first-message", "mid-bag"])
def test_a_failure_while_writing_leaves_no_new_folder(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, call: int
) -> None:
    error = WriterFailed("disk on fire")
    calls = _fail_on_call(monkeypatch, call, error)
    with pytest.raises(WriterFailed) as excinfo:
        write_bag(tmp_path / "bag", _scurve(), stream="point")
    assert excinfo.value is error  # the failure itself, unchanged
    assert len(calls) == call
    assert _names(tmp_path) == []


def test_a_failure_while_writing_leaves_an_existing_bag_untouched(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    target = write_bag(tmp_path / "bag", _cubic())
    before, folder = _snapshot(target), target.stat().st_ino
    _fail_on_call(monkeypatch, 5, WriterFailed())
    with pytest.raises(WriterFailed):
        write_bag(target, _septic(), stream="joint_state")
    assert _names(tmp_path) == ["bag"]
    assert target.stat().st_ino == folder
    assert _snapshot(target) == before
    monkeypatch.undo()
    ((_, message),) = _read(target)["/joint_trajectory"]
    _assert_points(list(message.points), _cubic(), _cubic().breakpoints)


def test_an_interrupt_also_cleans_up(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    target = write_bag(tmp_path / "bag", _cubic())
    before = _snapshot(target)
    _fail_on_call(monkeypatch, 2, KeyboardInterrupt())
    with pytest.raises(KeyboardInterrupt):
        write_bag(target, _scurve(), stream="point")
    assert _names(tmp_path) == ["bag"]
    assert _snapshot(target) == before


def test_a_failing_final_rename_keeps_the_old_bag(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    target = write_bag(tmp_path / "bag", _cubic())
    before = _snapshot(target)
    real = os.replace
    renames: list[tuple[str, str]] = []

    def replace(source: Any, destination: Any) -> None:
        renames.append((str(source), str(destination)))
        if Path(destination) == target and not str(source).endswith(".old"):
            raise OSError("rename failed")  # the new bag into place; putting the old back works
        real(source, destination)

    monkeypatch.setattr(atomic.os, "replace", replace)
    with pytest.raises(OSError, match="rename failed"):
        write_bag(target, _septic())
    monkeypatch.undo()
    assert _names(tmp_path) == ["bag"]
    assert _snapshot(target) == before


def test_a_folder_that_is_not_a_bag_is_refused(tmp_path: Path) -> None:
    target = tmp_path / "results"
    target.mkdir()
    (target / "notes.txt").write_bytes(b"keep")
    with pytest.raises(InvalidInputError, match="is not a ROS 2 bag; not replacing it"):
        write_bag(target, _cubic())
    assert _names(tmp_path) == ["results"]
    assert _names(target) == ["notes.txt"]
    assert (target / "notes.txt").read_bytes() == b"keep"


def test_a_file_in_the_way_is_refused(tmp_path: Path) -> None:
    target = tmp_path / "bag"
    target.write_bytes(b"not a folder")
    with pytest.raises(InvalidInputError, match="is not a ROS 2 bag"):
        write_bag(target, _constant_twist())
    assert _names(tmp_path) == ["bag"]
    assert target.read_bytes() == b"not a folder"


def test_a_missing_parent_folder_is_refused(tmp_path: Path) -> None:
    with pytest.raises(InvalidInputError, match="does not exist"):
        write_bag(tmp_path / "missing" / "bag", _cubic())
    assert _names(tmp_path) == []


# 6. Bad input -------------------------------------------------------------------------
ARM_ERRORS = [
    ({"storage": "zip"}, "storage must be 'mcap' or 'sqlite3', got 'zip'"),
    ({"stream": "foo"}, "stream must be 'joint_state' or 'point', got 'foo'"),
    ({"joint_names": ["a"]}, "joint_names must be 2 distinct non-empty names, got ['a']"),
    ({"joint_names": ["a", "b", "c"]}, "joint_names must be 2 distinct non-empty names"),
    ({"joint_names": ["a", "a"]}, "joint_names must be 2 distinct non-empty names"),
    ({"joint_names": ["a", ""]}, "joint_names must be 2 distinct non-empty names"),
    ({"joint_names": []}, "joint_names must be 2 distinct non-empty names, got []"),
    ({"start_ns": -1}, "start_ns must be a whole number >= 0, got -1"),
    ({"start_ns": 1.5}, "start_ns must be a whole number >= 0, got 1.5"),
    ({"start_ns": 1e9}, "start_ns must be a whole number >= 0"),
    ({"start_ns": "0"}, "start_ns must be a whole number >= 0"),
    ({"rate_hz": 50.0}, "rate_hz sets the stream's rate: pass stream= too"),
    ({"topic_prefix": "robot"}, "topic_prefix must be a ROS name"),
    ({"topic_prefix": "/robot/"}, "topic_prefix must be a ROS name"),
    ({"topic_prefix": "/"}, "topic_prefix must be a ROS name"),
    ({"sample_step": float("nan")}, "sample_step must be finite"),
    ({"sample_step": -0.1}, "sample_step must be > 0"),
    ({"sample_step": 0.0}, "sample_step must be > 0"),
    ({"stream": "joint_state", "rate_hz": float("nan")}, "rate_hz must be finite"),
    ({"stream": "point", "rate_hz": -10.0}, "rate_hz must be > 0"),
    ({"stream": "point", "rate_hz": float("inf")}, "rate_hz must be finite"),
]
MOBILE_ERRORS = [
    ({"joint_names": ["a"]}, "joint_names, stream and controller are for arm plans (a Traj"),
    ({"stream": "joint_state"}, "joint_names, stream and controller are for arm plans"),
    ({"sample_step": float("nan")}, "sample_step must be finite"),
    ({"sample_step": -1.0}, "sample_step must be > 0"),
    ({"rate_hz": float("nan")}, "rate_hz must be finite"),
    ({"rate_hz": -5.0}, "rate_hz must be > 0"),
    ({"rate_hz": 0.0}, "rate_hz must be > 0"),
    ({"frame_id": ""}, "frame_id must be a non-empty name, got ''"),
    ({"frame_id": None}, "frame_id must be a non-empty name, got None"),
    ({"storage": "zip"}, "storage must be 'mcap' or 'sqlite3'"),
    ({"start_ns": -5}, "start_ns must be a whole number >= 0"),
    ({"topic_prefix": "robot/"}, "topic_prefix must be a ROS name"),
]


def _case_id(case: tuple[dict[str, Any], str]) -> str:
    return ",".join(f"{k}={v!r}" for k, v in case[0].items())


@pytest.mark.parametrize(("kwargs", "fragment"), ARM_ERRORS, ids=map(_case_id, ARM_ERRORS))
def test_bad_input_for_an_arm_plan(tmp_path: Path, kwargs: dict[str, Any], fragment: str) -> None:
    with pytest.raises(InvalidInputError) as excinfo:
        write_bag(tmp_path / "bag", _cubic(), **kwargs)
    assert fragment in str(excinfo.value)
    assert _names(tmp_path) == []


@pytest.mark.parametrize(("kwargs", "fragment"), MOBILE_ERRORS, ids=map(_case_id, MOBILE_ERRORS))
def test_bad_input_for_a_mobile_plan(tmp_path: Path, kwargs: dict[str, Any], fragment: str) -> None:
    with pytest.raises(InvalidInputError) as excinfo:
        write_bag(tmp_path / "bag", _constant_twist(), **kwargs)
    assert fragment in str(excinfo.value)
    assert _names(tmp_path) == []


@pytest.mark.parametrize(
    ("plan", "name"),
    [(np.zeros((3, 2)), "ndarray"), (None, "NoneType"), ("plan.csv", "str")],
)
def test_a_non_plan_is_refused(tmp_path: Path, plan: Any, name: str) -> None:
    with pytest.raises(InvalidInputError, match=f"a Trajectory or a MobileTrajectory, got {name}"):
        write_bag(tmp_path / "bag", plan)
    assert _names(tmp_path) == []


def test_a_bool_start_ns_is_refused(tmp_path: Path) -> None:
    with pytest.raises(InvalidInputError, match="start_ns must be a whole number"):
        write_bag(tmp_path / "bag", _cubic(), start_ns=True)


def test_start_ns_up_to_the_last_stamp_of_ros_time(tmp_path: Path) -> None:
    plan = _cubic()
    start_ns = LAST_STAMP - round(plan.duration * 1e9)
    bag = write_bag(tmp_path / "bag", plan, stream="point", start_ns=start_ns)
    for topics in (_read(bag), _strip(_read_mcap(bag))):
        ((stamp, trajectory),) = topics["/joint_trajectory"]
        assert stamp == _ns(trajectory.header.stamp) == start_ns
        assert trajectory.header.stamp.sec == 2**31 - 12
        assert topics["/joint_trajectory_point"][-1][0] == LAST_STAMP


@pytest.mark.parametrize("start_ns", [LAST_STAMP + 1, 2**63 - 1, 2**64])
def test_start_ns_beyond_ros_time_is_refused(tmp_path: Path, start_ns: int) -> None:
    with pytest.raises(InvalidInputError, match="start_ns"):
        write_bag(tmp_path / "bag", _cubic(), start_ns=start_ns)
    assert _names(tmp_path) == []


def test_stream_stamps_beyond_ros_time_leave_nothing_behind(tmp_path: Path) -> None:
    # The plan would end past ROS time's last second: refused before writing anything.
    with pytest.raises(InvalidInputError, match="past ROS time's last second"):
        write_bag(tmp_path / "bag", _cubic(), stream="joint_state", start_ns=LAST_STAMP)
    assert _names(tmp_path) == []


@pytest.mark.parametrize("missing", ["rosbags.rosbag2", "rosbags.typesys"])
def test_without_rosbags_it_says_how_to_install_it(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, missing: str
) -> None:
    monkeypatch.setitem(sys.modules, missing, None)
    with pytest.raises(Ros2Unavailable) as excinfo:
        write_bag(tmp_path / "bag", _cubic())
    assert 'pip install "trajkit[ros]"' in str(excinfo.value)
    assert isinstance(excinfo.value, TrajkitError)
    assert _names(tmp_path) == []


def test_without_rosbags_even_bad_input_says_how_to_install_it(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setitem(sys.modules, "rosbags.rosbag2", None)
    monkeypatch.setitem(sys.modules, "rosbags.typesys", None)
    with pytest.raises(Ros2Unavailable, match=r'pip install "trajkit\[ros\]"'):
        write_bag(tmp_path / "bag", _cubic(), storage="zip")


# Points a controller must accept: time_from_start strictly increasing -------------------
@pytest.mark.parametrize(
    ("make", "dt"),
    [
        pytest.param(
            lambda: tk.trapezoidal([1.0, -2.0], [1.0, -2.0], 1.0, 1.0),
            None,
            id="zero-duration-plan",
        ),
        pytest.param(
            lambda: tk.septic(np.zeros(1), [1.0], 2.0 + 1e-10),
            None,
            id="end-just-past-a-10-ms-tick",
        ),
        pytest.param(
            lambda: tk.cubic([0.0], [1.0], 1.0 + 2e-10),
            0.1,
            id="end-just-past-a-dt-tick",
        ),
        pytest.param(_trapezoid, None, id="trapezoid"),
        pytest.param(_septic, None, id="septic"),
        pytest.param(_cubic, 0.3, id="cubic-dt"),
    ],
)
def test_time_from_start_strictly_increases(
    tmp_path: Path, make: Callable[[], tk.Trajectory], dt: float | None
) -> None:
    # joint_trajectory_controller rejects a trajectory whose points' times do not
    # strictly increase ("Time between points ... is not strictly increasing").
    bag = write_bag(tmp_path / "bag", make(), sample_step=dt)
    ((_, message),) = _read(bag)["/joint_trajectory"]
    times = [_ns(point.time_from_start) for point in message.points]
    assert all(b > a for a, b in itertools.pairwise(times)), times[-3:]


# 7. Property: any trapezoid's points are the plan at its breakpoints --------------------
@st.composite
def trapezoid_problems(draw: st.DrawFn) -> tk.Trajectory:
    ndof = draw(ndofs)
    q0 = draw(joint_arrays(ndof))
    qf = draw(joint_arrays(ndof))
    vmax = draw(joint_arrays(ndof, limits_positive))
    amax = draw(joint_arrays(ndof, limits_positive))
    sync = draw(st.sampled_from(["time", "phase", None]))
    return tk.trapezoidal(q0, qf, vmax, amax, sync=sync)


@settings(
    max_examples=25,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)
@given(plan=trapezoid_problems(), start_ns=st.integers(0, LAST_STAMP - 10**6 * BILLION))
def test_property_bag_points_are_the_plan_at_its_breakpoints(
    tmp_path: Path, plan: tk.Trajectory, start_ns: int
) -> None:
    # One path for every example: each write also replaces the previous bag.
    bag = write_bag(tmp_path / "bag", plan, start_ns=start_ns)
    assert _names(tmp_path) == ["bag"]
    names = [f"joint{j + 1}" for j in range(plan.ndof)]
    for topics in (_read(bag), _strip(_read_mcap(bag))):
        ((stamp, message),) = topics["/joint_trajectory"]
        assert stamp == start_ns
        _assert_joint_trajectory(message, plan, _arm_times(plan, None), names, start_ns)
        assert _ns(message.points[-1].time_from_start) == round(plan.duration * 1e9)


def test_a_trapezoid_is_sampled_densely_and_interpolates_closely(tmp_path: Path) -> None:
    # Its acceleration jumps at breakpoints, which points there could not carry: every
    # 10 ms instead, so quintic interpolation stays within (10 ms)^2 * jump / 8.
    plan = tk.trapezoidal([0.0], [1.0], 1.0, 2.0)
    bag = write_bag(tmp_path / "bag", plan)
    ((_, message),) = _read(bag)["/joint_trajectory"]
    assert len(message.points) == sample_times(0.0, plan.duration, 0.01).size
