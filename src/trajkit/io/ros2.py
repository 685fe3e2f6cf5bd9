"""ROS 2 bags of trajkit plans, written without a ROS install (the ``rosbags`` library).

An arm plan becomes one ``trajectory_msgs/JointTrajectory`` message with all its
points (what a ``joint_trajectory_controller`` takes), and optionally a stream of
``sensor_msgs/JointState`` (or ``trajectory_msgs/JointTrajectoryPoint``) messages
at a controller rate. A mobile plan becomes a command stream on ``/cmd_vel``
(``geometry_msgs/Twist`` as ROS 2 Humble's controllers take it, or
``geometry_msgs/TwistStamped`` as Jazzy's ``diff_drive_controller`` and Nav2 do) and
one ``nav_msgs/Path``. With a simulated run (``run=``), the bag also holds what the
simulated robot did (:func:`write_bag`). Bags are MCAP by default (sqlite3 on request),
ROS 2 Humble message definitions; ``pip install "trajkit[ros]"``.

A bag is a folder; it is written beside its destination under a temporary name
and renamed into place, so a failure leaves no partial bag.
"""

from __future__ import annotations

import os
import re
from collections.abc import Sequence
from pathlib import Path
from typing import Any, Literal

import numpy as np

from trajkit._validation import FloatArray, positive_scalar
from trajkit.curve import sample_times
from trajkit.errors import InvalidInputError, MissingDependencyError
from trajkit.io.atomic import staged_files
from trajkit.mobile.trajectory import MobileTrajectory
from trajkit.renamed import renamed_keywords
from trajkit.trajectory import Trajectory

__all__ = ["Ros2Unavailable", "require_rosbags", "write_bag"]

Storage = Literal["mcap", "sqlite3"]
Stream = Literal["joint_state", "point"]
Command = Literal["Twist", "TwistStamped"]
#: Pieces up to this degree are reproduced exactly by a controller's quintic
#: interpolation between points that carry position, velocity and acceleration.
_QUINTIC = 5
#: Sampling period (s) of arm plans that points at the breakpoints would not reproduce.
_DENSE_PERIOD = 0.01
#: The last time builtin_interfaces/Time can hold (its seconds are a signed 32-bit int).
_LAST_STAMP = (2**31 - 1) * 1_000_000_000 + 999_999_999
_NAME = re.compile(r"(/[A-Za-z][A-Za-z0-9_]*)+")


class Ros2Unavailable(MissingDependencyError):
    """The ``rosbags`` library is not installed."""


def require_rosbags() -> tuple[Any, Any, Any]:
    """Rosbags' Writer, StoragePlugin and the ROS 2 Humble typestore; or Ros2Unavailable."""
    try:
        from rosbags.rosbag2 import StoragePlugin, Writer
        from rosbags.typesys import Stores, get_typestore
    except ImportError as exc:
        raise Ros2Unavailable.absent("ROS 2 bags", "the rosbags library", "ros", exc) from None
    return Writer, StoragePlugin, get_typestore(Stores.ROS2_HUMBLE)


def _stamp(types: Any, nanoseconds: int, kind: str) -> Any:
    return types.types[f"builtin_interfaces/msg/{kind}"](
        sec=int(nanoseconds // 1_000_000_000), nanosec=int(nanoseconds % 1_000_000_000)
    )


def _nanoseconds(seconds: FloatArray) -> np.ndarray:
    return np.rint(np.asarray(seconds) * 1e9).astype(np.int64)


@renamed_keywords(dt="sample_step")
def write_bag(
    path: str | os.PathLike[str],
    plan: Trajectory | MobileTrajectory,
    *,
    joint_names: Sequence[str] | None = None,
    sample_step: float | None = None,
    stream: Stream | None = None,
    rate_hz: float | None = None,
    storage: Storage = "mcap",
    start_ns: int = 0,
    frame_id: str = "odom",
    topic_prefix: str = "",
    cmd_vel: Command = "Twist",
    base_frame: str = "base_link",
    run: Any = None,
    controller: str | None = None,
) -> Path:
    """Write a plan as a ROS 2 bag (a folder), and what a simulated robot did with it.

    Parameters
    ----------
    path : path-like
        The bag folder to create (replaced atomically if it exists).
    plan : Trajectory or MobileTrajectory
    joint_names : sequence of str, optional
        Arm plans: the joints' names (default ``joint1`` ...).
    sample_step : float, optional
        Arm plans: the spacing of the ``JointTrajectory`` points (s). Default: the
        plan's breakpoints when its pieces are of degree 5 or less and its
        acceleration is continuous (a controller's quintic interpolation of
        positions, velocities and accelerations then reproduces the plan exactly),
        else every 10 ms. Points never share a nanosecond. Mobile plans: the spacing of
        the ``Path`` poses (default 0.1 s).
    stream : {"joint_state", "point"}, optional
        Arm plans: also a stream of ``sensor_msgs/JointState`` on ``/joint_states``
        or of ``trajectory_msgs/JointTrajectoryPoint`` on ``/joint_trajectory_point``
        at ``rate_hz``.
    rate_hz : float, optional
        The stream's rate (arm plans, default 100 Hz) or the ``Twist`` command rate
        on ``/cmd_vel`` (mobile plans; default the plan's own command rate, else
        10 Hz).
    storage : {"mcap", "sqlite3"}
    start_ns : int
        Bag time (ns) of the plan's start.
    frame_id : str
        Mobile plans: the ``Path``'s frame.
    topic_prefix : str
        Put before every topic name, e.g. ``"/robot1"``.
    cmd_vel : {"Twist", "TwistStamped"}
        Mobile plans: the command message. ``"Twist"`` for ROS 2 Humble,
        ``"TwistStamped"`` (stamped with its bag time, in ``base_frame``) for Jazzy.
    base_frame : str
        Mobile plans: the base's frame (``TwistStamped`` commands, odometry, TF).
    controller : str, optional
        Arm plans: the joint trajectory controller's name. Its ``JointTrajectory``
        then goes on ``/<controller>/joint_trajectory``, the topic ros2_controllers'
        controller subscribes to (``joint_trajectory_controller`` in its examples);
        default ``/joint_trajectory``.
    run : trajkit.sim.ArmLog, trajkit.sim.PhysicsLog or trajkit.mobile.SimulationLog, optional
        A simulated run of the plan, stamped with the simulation clock from
        ``start_ns`` (the plan's start). An arm's: ``/joint_states`` of the simulated
        joints (positions, velocities, efforts) and the commands sent to its
        actuators, as ``std_msgs/Float64MultiArray`` on a topic named after the
        simulated controller (``/position_servo_controller/commands`` for the
        position servos, say). A base's: the commands sent on
        ``/cmd_vel`` (instead of the plan's), ``nav_msgs/Odometry`` on ``/odom``
        (from the wheel encoders of a MuJoCo run, else the simulated pose; its twist
        from the change of pose over each row, in the base's frame) with the same
        ``odom`` to ``base_frame`` transform on ``/tf``; for a MuJoCo run also the
        simulator's true pose on ``/ground_truth`` and the wheels' measured speeds
        and torques on ``/joint_states``. A plan stream on ``/joint_states`` is then
        refused (it would be read as the robot's).

    Returns
    -------
    Path
        The bag folder.

    Raises
    ------
    Ros2Unavailable
        If rosbags is not installed.
    InvalidInputError
        For an unknown storage or stream, bad rates or names.
    """
    writer_class, plugins, types = require_rosbags()
    if storage not in ("mcap", "sqlite3"):
        raise InvalidInputError(f"storage must be 'mcap' or 'sqlite3', got {storage!r}")
    if (not isinstance(start_ns, (int, np.integer)) or isinstance(start_ns, bool)
            or start_ns < 0):  # fmt: skip
        raise InvalidInputError(f"start_ns must be a whole number >= 0, got {start_ns!r}")
    if not isinstance(topic_prefix, str) or (topic_prefix and not _NAME.fullmatch(topic_prefix)):
        raise InvalidInputError(
            "topic_prefix must be a ROS name such as '/robot1' (a '/' before each part of "
            f"letters, digits and '_', starting with a letter), got {topic_prefix!r}"
        )
    end_ns = start_ns + int(np.ceil(plan.duration * 1e9)) if hasattr(plan, "duration") else 0
    if end_ns > _LAST_STAMP:
        raise InvalidInputError(
            f"start_ns {start_ns} puts the plan past ROS time's last second (2**31 - 1 s: "
            "builtin_interfaces/Time counts seconds in 32 bits)"
        )
    if isinstance(plan, Trajectory):
        if cmd_vel != "Twist" or base_frame != "base_link":
            raise InvalidInputError("cmd_vel and base_frame are for mobile plans "
                                    "(a MobileTrajectory)")  # fmt: skip
        if run is not None and stream == "joint_state":
            raise InvalidInputError(
                "stream='joint_state' puts the plan on /joint_states, where the simulated "
                "run's joint states go: use stream='point' (or no stream) with run="
            )
        messages = _arm_messages(
            types, plan, joint_names, sample_step, stream, rate_hz, int(start_ns)
        )
        if controller is not None:
            if not isinstance(controller, str) or not _NAME.fullmatch(f"/{controller}"):
                raise InvalidInputError(
                    "controller must be a ROS name such as 'joint_trajectory_controller' "
                    f"(letters, digits and '_', starting with a letter), got {controller!r}"
                )
            messages = [(f"/{controller}/joint_trajectory" if m[0] == "/joint_trajectory"
                         else m[0], *m[1:]) for m in messages]  # fmt: skip
    elif isinstance(plan, MobileTrajectory):
        if joint_names is not None or stream is not None or controller is not None:
            raise InvalidInputError(
                "joint_names, stream and controller are for arm plans (a Trajectory)"
            )
        messages = _mobile_messages(types, plan, sample_step, rate_hz, int(start_ns), frame_id,
                                    cmd_vel, base_frame)  # fmt: skip
    else:
        raise InvalidInputError(
            f"plan must be a Trajectory or a MobileTrajectory, got {type(plan).__name__}"
        )
    if run is not None:
        from trajkit.io.ros2_run import run_messages

        names = next((message.joint_names for topic, _, _, message in messages
                      if topic.endswith("/joint_trajectory")), None)  # fmt: skip
        messages = run_messages(types, plan, run, int(start_ns), messages, names, cmd_vel,
                                base_frame, frame_id)  # fmt: skip
    plugin = plugins.MCAP if storage == "mcap" else plugins.SQLITE3
    return _atomic_bag(Path(path), writer_class, plugin, types, messages, topic_prefix)


def _arm_messages(
    types: Any,
    plan: Trajectory,
    joint_names: Sequence[str] | None,
    sample_step: float | None,
    stream: Stream | None,
    rate_hz: float | None,
    start_ns: int,
) -> list[tuple[str, str, int, Any]]:
    names = [f"joint{j + 1}" for j in range(plan.ndof)] if joint_names is None else joint_names
    if isinstance(names, str) or not all(isinstance(name, str) for name in names):
        raise InvalidInputError(f"joint_names must be a list of names, got {joint_names!r}")
    names = list(names)
    if len(names) != plan.ndof or len(set(names)) != len(names) or not all(names):
        raise InvalidInputError(
            f"joint_names must be {plan.ndof} distinct non-empty names, got {list(names)}"
        )
    if stream not in (None, "joint_state", "point"):
        raise InvalidInputError(f"stream must be 'joint_state' or 'point', got {stream!r}")
    if sample_step is not None:
        times = sample_times(
            plan.start_time, plan.end_time, positive_scalar("sample_step", sample_step, unit="s")
        )
    elif plan.degree <= _QUINTIC and _continuous_acceleration(plan):
        times = plan.breakpoints
    else:
        times = sample_times(plan.start_time, plan.end_time, _DENSE_PERIOD)
    header = types.types["std_msgs/msg/Header"]
    point = types.types["trajectory_msgs/msg/JointTrajectoryPoint"]
    times = _distinct(times, plan.start_time)
    states = [np.ascontiguousarray(plan.evaluate(times, order)) for order in range(3)]
    since = _nanoseconds(times - plan.start_time)
    points = [
        point(positions=states[0][k], velocities=states[1][k], accelerations=states[2][k],
              effort=np.zeros(0), time_from_start=_stamp(types, since[k], "Duration"))
        for k in range(times.size)
    ]  # fmt: skip
    trajectory = types.types["trajectory_msgs/msg/JointTrajectory"](
        header=header(stamp=_stamp(types, start_ns, "Time"), frame_id=""),
        joint_names=names,
        points=points,
    )
    messages = [("/joint_trajectory", trajectory.__msgtype__, start_ns, trajectory)]
    if stream is None:
        if rate_hz is not None:
            raise InvalidInputError("rate_hz sets the stream's rate: pass stream= too")
        return messages
    rate = 100.0 if rate_hz is None else positive_scalar("rate_hz", rate_hz, unit="Hz")
    ticks = _distinct(
        sample_times(plan.start_time, plan.end_time, 1.0 / rate, name="1/rate_hz"), plan.start_time
    )
    values = [np.ascontiguousarray(plan.evaluate(ticks, order)) for order in range(3)]
    stamps = start_ns + _nanoseconds(ticks - plan.start_time)
    for k, stamp in enumerate(stamps.tolist()):
        if stream == "joint_state":
            message = types.types["sensor_msgs/msg/JointState"](
                header=header(stamp=_stamp(types, stamp, "Time"), frame_id=""),
                name=names, position=values[0][k], velocity=values[1][k], effort=np.zeros(0),
            )  # fmt: skip
            messages.append(("/joint_states", message.__msgtype__, stamp, message))
        else:
            since_start = _stamp(types, stamp - start_ns, "Duration")
            message = point(positions=values[0][k], velocities=values[1][k],
                            accelerations=values[2][k], effort=np.zeros(0),
                            time_from_start=since_start)  # fmt: skip
            messages.append(("/joint_trajectory_point", message.__msgtype__, stamp, message))
    return messages


def _continuous_acceleration(plan: Trajectory) -> bool:
    """True when the acceleration has no jump at any interior breakpoint."""
    inner = plan.breakpoints[1:-1]
    if inner.size == 0:
        return True
    before = plan.evaluate(np.nextafter(inner, -np.inf), 2)
    after = plan.evaluate(inner, 2)
    scale = max(1.0, float(np.abs(after).max()))
    return bool(np.abs(after - before).max() <= 1e-9 * scale)


def _distinct(times: FloatArray, start: float) -> FloatArray:
    """``times`` without those that round to the same nanosecond as the next one.

    Controllers refuse points whose ``time_from_start`` does not strictly increase;
    of a run of equal stamps the last (the plan's end, for one) is kept.
    """
    stamps = _nanoseconds(times - start)
    return times[np.append(np.diff(stamps) > 0, True)]


def _mobile_messages(
    types: Any,
    plan: MobileTrajectory,
    sample_step: float | None,
    rate_hz: float | None,
    start_ns: int,
    frame_id: str,
    cmd_vel: Command = "Twist",
    base_frame: str = "base_link",
) -> list[tuple[str, str, int, Any]]:
    for name, value in (("frame_id", frame_id), ("base_frame", base_frame)):
        if not isinstance(value, str) or not value:
            raise InvalidInputError(f"{name} must be a non-empty name, got {value!r}")
    if cmd_vel not in ("Twist", "TwistStamped"):
        raise InvalidInputError(
            f"cmd_vel must be 'Twist' (ROS 2 Humble) or 'TwistStamped' (Jazzy), got {cmd_vel!r}"
        )
    rate = rate_hz if rate_hz is not None else plan.info.get("rate_hz") or 10.0
    times, twists = plan.commands(positive_scalar("rate_hz", rate, unit="Hz"))
    messages = command_messages(types, start_ns + _nanoseconds(times), twists, cmd_vel,
                                base_frame)  # fmt: skip
    header = types.types["std_msgs/msg/Header"]
    spacing = 0.1 if sample_step is None else positive_scalar("sample_step", sample_step, unit="s")
    ticks = sample_times(0.0, plan.duration, spacing) if plan.duration > 0 else np.zeros(1)
    poses = plan.pose(ticks)
    names = ("PoseStamped", "Pose", "Point", "Quaternion")
    stamped, pose, point, quaternion = (types.types[f"geometry_msgs/msg/{n}"] for n in names)
    path_poses = [
        stamped(header=header(stamp=_stamp(types, start_ns + stamp, "Time"), frame_id=frame_id),
                pose=pose(position=point(x=x, y=y, z=0.0),
                          orientation=quaternion(x=0.0, y=0.0, z=np.sin(theta / 2.0),
                                                 w=np.cos(theta / 2.0))))
        for stamp, (x, y, theta) in zip(_nanoseconds(ticks).tolist(), poses.tolist(), strict=True)
    ]  # fmt: skip
    path = types.types["nav_msgs/msg/Path"](
        header=header(stamp=_stamp(types, start_ns, "Time"), frame_id=frame_id), poses=path_poses
    )
    messages.insert(0, ("/plan", path.__msgtype__, start_ns, path))
    return messages


def command_messages(types: Any, stamps: np.ndarray, twists: FloatArray, cmd_vel: Command,
                     base_frame: str) -> list[tuple[str, str, int, Any]]:  # fmt: skip
    """``(v, ω)`` commands on ``/cmd_vel`` at the bag times ``stamps`` (ns)."""
    vector, twist = types.types["geometry_msgs/msg/Vector3"], types.types["geometry_msgs/msg/Twist"]
    header = types.types["std_msgs/msg/Header"]
    stamped_twist = types.types["geometry_msgs/msg/TwistStamped"]
    messages = []
    for stamp, (v, omega) in zip(stamps.tolist(), twists.tolist(), strict=True):
        message = twist(linear=vector(x=v, y=0.0, z=0.0), angular=vector(x=0.0, y=0.0, z=omega))
        if cmd_vel == "TwistStamped":
            message = stamped_twist(header=header(stamp=_stamp(types, stamp, "Time"),
                                                  frame_id=base_frame), twist=message)  # fmt: skip
        messages.append(("/cmd_vel", message.__msgtype__, stamp, message))
    return messages


def _atomic_bag(
    target: Path,
    writer_class: Any,
    plugin: Any,
    types: Any,
    messages: list[tuple[str, str, int, Any]],
    prefix: str,
) -> Path:
    folder = target.parent if str(target.parent) else Path(".")
    if not folder.is_dir():
        raise InvalidInputError(f"the bag's folder {folder} does not exist")
    if target.exists() and not (target / "metadata.yaml").is_file():
        raise InvalidInputError(f"{target} exists and is not a ROS 2 bag; not replacing it")
    with staged_files() as stage:
        staged = stage.folder(target)
        with writer_class(staged, version=9, storage_plugin=plugin) as writer:
            connections: dict[str, Any] = {}
            for topic, msgtype, stamp, message in messages:
                if topic not in connections:
                    connections[topic] = writer.add_connection(prefix + topic, msgtype,
                                                               typestore=types)  # fmt: skip
                writer.write(connections[topic], stamp, types.serialize_cdr(message, msgtype))
    return target
