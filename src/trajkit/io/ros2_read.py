"""ROS 2 bags read back into trajkit objects (``rosbags``, no ROS install).

:func:`read_bag` opens a bag folder (MCAP or sqlite3) as written by trajkit or
recorded on a robot, and gives its topics as trajkit data, so a recorded run can be
plotted against its plan and checked against limits:

* ``trajectory_msgs/JointTrajectory`` → the :class:`~trajkit.Trajectory` a joint
  trajectory controller follows through its points
  (:func:`~trajkit.io.trajectory_controller.controller_trajectory`);
* ``sensor_msgs/JointState`` → :class:`JointStates` (positions, velocities, efforts);
* ``geometry_msgs/Twist`` or ``TwistStamped`` → :class:`Twists` (commands);
* ``nav_msgs/Odometry`` → :class:`Odometry`; ``nav_msgs/Path`` → :class:`Poses`.

Times are seconds from ``origin_ns``: by default the earliest stamp in the bag, so
a trajkit bag's times are its plan's. A message's header stamp is its time where it
has one (the bag's receive time otherwise).
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from trajkit._validation import FloatArray
from trajkit.errors import InvalidInputError
from trajkit.limits import Limits, Report, compare
from trajkit.trajectory import Extrema, Trajectory

__all__ = ["Bag", "JointStates", "Odometry", "Poses", "Twists", "read_bag"]

_BILLION = 1_000_000_000
_STATE = "sensor_msgs/msg/JointState"
_TRAJECTORY = "trajectory_msgs/msg/JointTrajectory"
_TWISTS = ("geometry_msgs/msg/Twist", "geometry_msgs/msg/TwistStamped")
_ODOMETRY = "nav_msgs/msg/Odometry"
_PATH = "nav_msgs/msg/Path"


@dataclass(frozen=True, eq=False)
class JointStates:
    """A ``sensor_msgs/JointState`` topic, one row per message.

    Attributes
    ----------
    t : ndarray, shape (n,)
        Times (s from the bag's origin).
    names : tuple of str
        The joints, in the columns' order.
    position, velocity, effort : ndarray, shape (n, ndof), or None
        What the messages carry (rad or m, per second, N·m or N); None where they
        carry none.
    """

    t: FloatArray
    names: tuple[str, ...]
    position: FloatArray | None
    velocity: FloatArray | None
    effort: FloatArray | None

    def check(self, limits: Limits, *, effort: Any = None) -> Report:
        """The samples against ``limits``' position and velocity bounds (and ``effort``).

        Sampled values only: what happened between two messages is not seen.

        Parameters
        ----------
        limits : Limits
            Bounds per joint (the same units as the columns).
        effort : float, array_like or (lower, upper), optional
            Bounds on the efforts (N·m or N).

        Returns
        -------
        Report
            Violations (at most one per quantity, joint and side) and peaks.
        """
        if not isinstance(limits, Limits):
            raise InvalidInputError(f"limits must be a trajkit.Limits, got {type(limits).__name__}")
        checks: list[tuple[str, Any, FloatArray | None]] = [
            ("position", limits.position, self.position),
            ("velocity", limits.velocity, self.velocity),
        ]
        if effort is not None:
            checks.append(("effort", Limits(velocity=effort).velocity, self.effort))
        violations, peaks, bounds = [], {}, {}
        for quantity, bound, values in checks:
            if bound is None:
                continue
            if values is None:
                raise InvalidInputError(f"the joint states carry no {quantity} to check")
            lower, upper = bound.for_ndof(quantity, values.shape[1])
            low, high = values.argmin(axis=0), values.argmax(axis=0)
            columns = np.arange(values.shape[1])
            found = Extrema(0, values[low, columns], self.t[low], values[high, columns],
                            self.t[high])  # fmt: skip
            peaks[quantity] = (found.minimum, found.maximum)
            bounds[quantity] = (np.asarray(lower, float), np.asarray(upper, float))
            violations += compare(quantity, found, np.asarray(lower, float),
                                  np.asarray(upper, float), 1e-9, self.names)  # fmt: skip
        return Report(tuple(violations), peaks, bounds, dict.fromkeys(peaks, self.names))


@dataclass(frozen=True, eq=False)
class Twists:
    """A ``geometry_msgs/Twist`` or ``TwistStamped`` topic: ``linear`` and ``angular`` (n, 3)."""

    t: FloatArray
    linear: FloatArray
    angular: FloatArray
    frame: str = ""

    @property
    def commands(self) -> FloatArray:
        """``(v, ω)`` of a planar base: forward speed (m/s) and turn rate (rad/s), (n, 2)."""
        return np.stack([self.linear[:, 0], self.angular[:, 2]], axis=1)


@dataclass(frozen=True, eq=False)
class Poses:
    """Planar poses ``(x, y, θ)`` (m, m, rad) at times ``t``; θ from the quaternion's yaw."""

    t: FloatArray
    poses: FloatArray
    frame: str = ""


@dataclass(frozen=True, eq=False)
class Odometry(Poses):
    """A ``nav_msgs/Odometry`` topic: poses, and the twist ``(v, ω)`` in the child frame."""

    twist: FloatArray = field(default_factory=lambda: np.zeros((0, 2)))
    child_frame: str = ""


@dataclass(frozen=True)
class Bag:
    """A bag's messages, by topic (see :func:`read_bag`).

    Attributes
    ----------
    folder : Path
        The bag folder.
    origin_ns : int
        The bag time that is ``t = 0`` here (ns).
    topics : dict
        Topic name → ``(message type, message count)``.
    """

    folder: Path
    origin_ns: int
    topics: dict[str, tuple[str, int]]
    _messages: dict[str, list[tuple[int, Any]]] = field(repr=False)

    def _topic(self, topic: str, types: tuple[str, ...]) -> list[tuple[int, Any]]:
        if topic not in self.topics:
            raise InvalidInputError(
                f"the bag has no topic {topic!r}; it has {sorted(self.topics) or 'none'}"
            )
        if self.topics[topic][0] not in types:
            raise InvalidInputError(
                f"{topic} holds {self.topics[topic][0]}, not {' or '.join(types)}"
            )
        return self._messages[topic]

    def _default(self, topic: str | None, usual: str, kind: str) -> str:
        """``topic``, or ``usual`` when the bag has it, or the bag's one topic of ``kind``."""
        if topic is not None or usual in self.topics:
            return usual if topic is None else topic
        found = sorted(name for name, (held, _) in self.topics.items() if held == kind)
        if len(found) != 1:
            what = f"{len(found)} of them ({', '.join(found)})" if found else "none"
            raise InvalidInputError(f"the bag has no {usual} and {what} of {kind}: name the "
                                    "topic")  # fmt: skip
        return found[0]

    def _seconds(self, stamps: list[int]) -> FloatArray:
        return (np.asarray(stamps, dtype=np.int64) - self.origin_ns) / 1e9

    def joint_trajectory(self, topic: str | None = None, index: int = -1) -> Trajectory:
        """The curve a joint trajectory controller follows through a message's points.

        ``topic`` defaults to ``/joint_trajectory``, else the bag's one
        JointTrajectory topic (``/joint_trajectory_controller/joint_trajectory``,
        say). ``index`` picks the message (default the last). Times are the
        message's stamp plus each point's ``time_from_start``;
        ``info["joint_names"]`` holds the joints.
        """
        from trajkit.io.trajectory_controller import controller_trajectory

        topic = self._default(topic, "/joint_trajectory", _TRAJECTORY)

        stamp, message = self._topic(topic, (_TRAJECTORY,))[index]
        points = message.points
        if len(points) < 2:
            raise InvalidInputError(f"{topic}: a trajectory needs at least 2 points, got "
                                    f"{len(points)}")  # fmt: skip
        start = _ns(message.header.stamp) or stamp
        times = self._seconds([start + _ns(p.time_from_start) for p in points])
        fields = []
        for name in ("positions", "velocities", "accelerations"):
            rows = [np.asarray(getattr(p, name), dtype=float) for p in points]
            sizes = {row.size for row in rows}
            if sizes == {0}:
                fields.append(None)
                continue
            if len(sizes) != 1:
                raise InvalidInputError(
                    f"{topic}: the points' {name} differ in length ({sorted(sizes)}); a "
                    "controller needs them all or none"
                )
            fields.append(np.stack(rows))
        if fields[0] is None:
            raise InvalidInputError(f"{topic}: the points carry no positions")
        curve = controller_trajectory(times, *fields)
        return curve.with_info({**curve.info, "joint_names": tuple(message.joint_names)})

    def joint_states(self, topic: str = "/joint_states") -> JointStates:
        """A JointState topic as :class:`JointStates` (its joints those of the first message)."""
        entries = self._topic(topic, (_STATE,))
        names = tuple(entries[0][1].name)
        stamps, columns = [], {"position": [], "velocity": [], "effort": []}
        for stamp, message in entries:
            if tuple(message.name) != names:
                raise InvalidInputError(f"{topic}: the messages name different joints "
                                        f"({list(names)}, then {list(message.name)})")  # fmt: skip
            stamps.append(_ns(message.header.stamp) or stamp)
            for key in columns:
                columns[key].append(np.asarray(getattr(message, key), dtype=float))
        arrays = {}
        for key, rows in columns.items():
            sizes = {row.size for row in rows}
            arrays[key] = np.stack(rows) if sizes == {len(names)} else None
        return JointStates(self._seconds(stamps), names, arrays["position"], arrays["velocity"],
                           arrays["effort"])  # fmt: skip

    def twists(self, topic: str = "/cmd_vel") -> Twists:
        """A Twist or TwistStamped topic (commands) as :class:`Twists`."""
        entries = self._topic(topic, _TWISTS)
        stamped = self.topics[topic][0] == _TWISTS[1]
        stamps = [(_ns(m.header.stamp) or s) if stamped else s for s, m in entries]
        twists = [m.twist if stamped else m for _, m in entries]
        return Twists(self._seconds(stamps), _vectors([w.linear for w in twists]),
                      _vectors([w.angular for w in twists]),
                      entries[0][1].header.frame_id if stamped else "")  # fmt: skip

    def odometry(self, topic: str = "/odom") -> Odometry:
        """An Odometry topic as :class:`Odometry`: planar poses and ``(v, ω)``."""
        entries = self._topic(topic, (_ODOMETRY,))
        messages = [m for _, m in entries]
        stamps = [_ns(m.header.stamp) or s for s, m in entries]
        twist = np.array([[m.twist.twist.linear.x, m.twist.twist.angular.z] for m in messages])
        return Odometry(self._seconds(stamps), _planar([m.pose.pose for m in messages]),
                        messages[0].header.frame_id, twist,
                        messages[0].child_frame_id)  # fmt: skip

    def path(self, topic: str = "/plan", index: int = -1) -> Poses:
        """A Path message's poses as :class:`Poses` (default the last message)."""
        stamp, message = self._topic(topic, (_PATH,))[index]
        stamps = [_ns(p.header.stamp) or stamp for p in message.poses]
        return Poses(self._seconds(stamps), _planar([p.pose for p in message.poses]),
                     message.header.frame_id)  # fmt: skip


def read_bag(path: str | os.PathLike[str], *, origin_ns: int | None = None) -> Bag:
    """Open a ROS 2 bag folder and read its messages.

    Parameters
    ----------
    path : path-like
        The bag folder (with its ``metadata.yaml``), MCAP or sqlite3.
    origin_ns : int, optional
        The bag time (ns) that becomes ``t = 0``; default the earliest stamp, of
        headers or of the bag.

    Returns
    -------
    Bag
        Its topics; ``joint_trajectory()``, ``joint_states()``, ``twists()``,
        ``odometry()`` and ``path()`` read them as trajkit data. Topics of other
        types are listed but not decoded.

    Raises
    ------
    Ros2Unavailable
        rosbags is not installed.
    InvalidInputError
        Not a bag folder, or a malformed bag.
    """
    from trajkit.io.ros2 import Ros2Unavailable

    try:
        from rosbags.rosbag2 import Reader
        from rosbags.typesys import Stores, get_typestore
    except ImportError as exc:
        raise Ros2Unavailable.absent("ROS 2 bags", "the rosbags library", "ros", exc) from None
    folder = Path(path)
    if not (folder / "metadata.yaml").is_file():
        raise InvalidInputError(f"{folder} is not a ROS 2 bag (a folder with metadata.yaml)")
    types = get_typestore(Stores.ROS2_HUMBLE)
    known = (_STATE, _TRAJECTORY, *_TWISTS, _ODOMETRY, _PATH)
    topics: dict[str, tuple[str, int]] = {}
    messages: dict[str, list[tuple[int, Any]]] = {}
    try:
        with Reader(folder) as reader:
            for connection in reader.connections:
                count, kind = topics.get(connection.topic, ("", 0))[1], connection.msgtype
                topics[connection.topic] = (kind, count + connection.msgcount)
            wanted = [c for c in reader.connections if c.msgtype in known]
            for connection, stamp, raw in reader.messages(connections=wanted):
                message = types.deserialize_cdr(raw, connection.msgtype)
                messages.setdefault(connection.topic, []).append((stamp, message))
    except InvalidInputError:
        raise
    except Exception as exc:  # rosbags' own errors: a malformed or truncated bag
        raise InvalidInputError(f"{folder}: not a readable ROS 2 bag ({exc})") from None
    if origin_ns is None:
        stamps = [_ns(getattr(m, "header", None) and m.header.stamp) or s
                  for entries in messages.values() for s, m in entries]  # fmt: skip
        origin_ns = min(stamps) if stamps else 0
    return Bag(folder, int(origin_ns), topics, messages)


def _ns(stamp: Any) -> int:
    """A builtin_interfaces Time or Duration in ns (0 for none)."""
    if not stamp:
        return 0
    return int(stamp.sec) * _BILLION + int(stamp.nanosec)


def _vectors(vectors: list[Any]) -> FloatArray:
    return np.array([[v.x, v.y, v.z] for v in vectors], dtype=float).reshape(-1, 3)


def _planar(poses: list[Any]) -> FloatArray:
    """``(x, y, yaw)`` of geometry_msgs/Pose messages."""
    rows = [(p.position.x, p.position.y, p.orientation.w, p.orientation.x, p.orientation.y,
             p.orientation.z) for p in poses]  # fmt: skip
    fields = np.array(rows, dtype=float).reshape(-1, 6)
    x, y, w, qx, qy, qz = fields.T
    return np.stack([x, y, np.arctan2(2.0 * (w * qz + qx * qy), 1.0 - 2.0 * (qy**2 + qz**2))],
                    axis=1)  # fmt: skip
