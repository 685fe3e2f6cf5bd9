"""The topics of a simulated run in a ROS 2 bag, beside its plan's.

:func:`~trajkit.io.ros2.write_bag` with ``run=`` writes them.

What a recorded robot would publish, stamped with the simulation clock: an arm's
``sensor_msgs/JointState`` and its actuator commands; a base's ``/cmd_vel``
commands, ``nav_msgs/Odometry`` and ``/tf``, its true pose and its wheels.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from typing import Any

import numpy as np

from trajkit._validation import FloatArray
from trajkit.errors import InvalidInputError
from trajkit.io.ros2 import Command, _nanoseconds, _stamp, command_messages
from trajkit.mobile.models import wrap_angle

__all__ = ["run_messages"]

Message = tuple[str, str, int, Any]


def run_messages(
    types: Any,
    plan: Any,
    run: Any,
    start_ns: int,
    messages: list[Message],
    joint_names: Sequence[str] | None,
    cmd_vel: Command,
    base_frame: str,
    odom_frame: str,
) -> list[Message]:
    """``messages`` (the plan's) with the run's topics, all in bag-time order per topic."""
    from trajkit.mobile.simulate import SimulationLog
    from trajkit.mobile.trajectory import MobileTrajectory
    from trajkit.sim.arm import ArmLog
    from trajkit.trajectory import Trajectory

    if isinstance(run, ArmLog) and isinstance(plan, Trajectory):
        if run.desired.shape[1] != plan.ndof:
            raise InvalidInputError(
                f"the run has {run.desired.shape[1]} joints but the plan has {plan.ndof}"
            )
        stamps = _stamps(run.t, plan.start_time, start_ns)
        return messages + _arm_run(types, run, stamps, list(joint_names or run.joint_names))
    if isinstance(run, SimulationLog) and isinstance(plan, MobileTrajectory):
        stamps = _stamps(run.t, 0.0, start_ns)
        # The commands that were sent replace the plan's own on /cmd_vel.
        kept = [m for m in messages if m[0] != "/cmd_vel"]
        sent = command_messages(types, stamps, np.asarray(run.commands), cmd_vel, base_frame)
        return kept + sent + _base_run(types, run, stamps, base_frame, odom_frame)
    raise InvalidInputError(
        "run must be the simulated run of the plan: a trajkit.sim.ArmLog for a Trajectory, "
        f"a SimulationLog (or PhysicsLog) for a MobileTrajectory, got {type(run).__name__} "
        f"for a {type(plan).__name__}"
    )


def _stamps(t: FloatArray, origin: float, start_ns: int) -> np.ndarray:
    """Bag times (ns) of the run's rows: ``start_ns`` at the plan's start ``origin``."""
    since = _nanoseconds(np.asarray(t) - origin)
    if since.size and since[0] < 0:
        raise InvalidInputError("the run starts before its plan: no bag time for its first rows")
    return start_ns + since


def _header(types: Any, stamp: int, frame: str) -> Any:
    return types.types["std_msgs/msg/Header"](stamp=_stamp(types, stamp, "Time"), frame_id=frame)


def _arm_run(types: Any, run: Any, stamps: np.ndarray, names: list[str]) -> list[Message]:
    state = types.types["sensor_msgs/msg/JointState"]
    array = types.types["std_msgs/msg/Float64MultiArray"]
    layout = types.types["std_msgs/msg/MultiArrayLayout"]
    dimension = types.types["std_msgs/msg/MultiArrayDimension"]
    width = run.commands.shape[1]
    shape = layout(dim=[dimension(label="actuators", size=width, stride=width)], data_offset=0)
    # A ROS name from the controller's ("position servo" -> position_servo_controller).
    controller = re.sub(r"[^a-z0-9]+", "_", run.controller.lower()).strip("_") or "arm"
    topic = f"/{controller}_controller/commands"
    out: list[Message] = []
    for k, stamp in enumerate(stamps.tolist()):
        message = state(header=_header(types, stamp, ""), name=names,
                        position=np.ascontiguousarray(run.actual[k]),
                        velocity=np.ascontiguousarray(run.actual_velocity[k]),
                        effort=np.ascontiguousarray(run.efforts[k]))  # fmt: skip
        out.append(("/joint_states", message.__msgtype__, stamp, message))
        command = array(layout=shape, data=np.ascontiguousarray(run.commands[k]))
        out.append((topic, command.__msgtype__, stamp, command))
    return out


def _base_run(types: Any, run: Any, stamps: np.ndarray, base_frame: str,
              odom_frame: str) -> list[Message]:  # fmt: skip
    odometry = getattr(run, "odometry", None)
    out = _odometry(types, "/odom", run.t, run.actual if odometry is None else odometry, stamps,
                    odom_frame, base_frame, tf=True)  # fmt: skip
    if odometry is not None:  # a MuJoCo run: its true pose, and the wheels
        out += _odometry(types, "/ground_truth", run.t, run.actual, stamps, "world", base_frame)
        state = types.types["sensor_msgs/msg/JointState"]
        for k, stamp in enumerate(stamps.tolist()):
            message = state(header=_header(types, stamp, ""),
                            name=["left_wheel", "right_wheel"], position=np.zeros(0),
                            velocity=np.ascontiguousarray(run.measured_wheel_speeds[k]),
                            effort=np.ascontiguousarray(run.wheel_torques[k]))  # fmt: skip
            out.append(("/joint_states", message.__msgtype__, stamp, message))
    return out


def body_twist(t: FloatArray, poses: FloatArray) -> FloatArray:
    """``(v, ω)`` of each row from the change of pose since the previous row (0 at the first).

    ``v`` is the displacement along the previous heading over the time step (m/s).
    """
    out = np.zeros((len(t), 2))
    if len(t) > 1:
        step = np.diff(t)
        moved = np.diff(poses[:, :2], axis=0)
        heading = poses[:-1, 2]
        out[1:, 0] = (moved[:, 0] * np.cos(heading) + moved[:, 1] * np.sin(heading)) / step
        out[1:, 1] = wrap_angle(np.diff(poses[:, 2])) / step
    return out


def _odometry(types: Any, topic: str, t: FloatArray, poses: FloatArray, stamps: np.ndarray,
              frame: str, child: str, *, tf: bool = False) -> list[Message]:  # fmt: skip
    names = ("Point", "Quaternion", "Pose", "PoseWithCovariance", "Twist", "TwistWithCovariance",
             "Vector3", "Transform", "TransformStamped")  # fmt: skip
    (point, quaternion, pose, pose_cov, twist, twist_cov, vector, transform,
     transform_stamped) = (types.types[f"geometry_msgs/msg/{n}"] for n in names)  # fmt: skip
    odometry = types.types["nav_msgs/msg/Odometry"]
    tf_message = types.types["tf2_msgs/msg/TFMessage"]
    covariance = np.zeros(36)
    rates = body_twist(np.asarray(t), np.asarray(poses))
    out: list[Message] = []
    for k, stamp in enumerate(stamps.tolist()):
        x, y, theta = (float(value) for value in poses[k])
        rotation = quaternion(x=0.0, y=0.0, z=np.sin(theta / 2.0), w=np.cos(theta / 2.0))
        v, omega = (float(value) for value in rates[k])
        message = odometry(
            header=_header(types, stamp, frame), child_frame_id=child,
            pose=pose_cov(pose=pose(position=point(x=x, y=y, z=0.0), orientation=rotation),
                          covariance=covariance),
            twist=twist_cov(twist=twist(linear=vector(x=v, y=0.0, z=0.0),
                                        angular=vector(x=0.0, y=0.0, z=omega)),
                            covariance=covariance))  # fmt: skip
        out.append((topic, message.__msgtype__, stamp, message))
        if tf:
            moved = transform_stamped(header=_header(types, stamp, frame), child_frame_id=child,
                                      transform=transform(translation=vector(x=x, y=y, z=0.0),
                                                          rotation=rotation))  # fmt: skip
            message = tf_message(transforms=[moved])
            out.append(("/tf", message.__msgtype__, stamp, message))
    return out
