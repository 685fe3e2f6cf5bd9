"""Mobile plans driven on a simulated differential-drive base in MuJoCo.

Twist commands leave the controller at the command rate, become wheel-speed
setpoints of the wheel motors' velocity servos, and the physics (tyre contact,
chassis mass, motor torque) moves the base. The log holds the ground truth from
the simulator, the odometry from the wheel encoders, and where trajkit's
kinematic model says the same commands should have taken the robot.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike

from trajkit._validation import FloatArray, finite_array, positive_scalar
from trajkit.errors import InvalidInputError
from trajkit.io.table import write_csv
from trajkit.mobile.control import Controller, Feedforward, controller_named
from trajkit.mobile.limits import MobileLimits, check_limits
from trajkit.mobile.models import chain_arcs, pose_array, wrap_angle
from trajkit.mobile.simulate import HeldCommands, SimulationLog, log_fields
from trajkit.mobile.trajectory import MobileTrajectory
from trajkit.sim.engine import control_grid, mujoco_module, stability_watch
from trajkit.sim.scenes import MobileScene

__all__ = ["PhysicsLog", "run_mobile"]

Feedback = Literal["ground_truth", "odometry"]


@dataclass(frozen=True, eq=False)
class PhysicsLog(SimulationLog):
    """A :class:`~trajkit.mobile.SimulationLog` of a MuJoCo run, one row per command.

    ``actual`` is the simulator's ground truth. Besides the fields of a
    kinematic log:

    Attributes
    ----------
    odometry : ndarray, shape (n, 3)
        The pose integrated from the wheel encoders (exact arcs between rows).
    kinematic : ndarray, shape (n, 3)
        Where trajkit's kinematic model takes the robot under the same commands:
        each held for its period from the start pose, with no slip.
    measured_wheel_speeds : ndarray, shape (n, 2)
        Left and right wheel speeds measured at each command time (rad/s).
    wheel_torques : ndarray, shape (n, 2)
        Motor torques at each command time, as the new command takes effect: the
        largest of the period for the wheels' velocity servos (N·m).
    feedback : str
        What the controller saw: ``"ground_truth"`` or ``"odometry"``.
    """

    odometry: FloatArray | None = None
    kinematic: FloatArray | None = None
    measured_wheel_speeds: FloatArray | None = None
    wheel_torques: FloatArray | None = None
    feedback: str = "ground_truth"

    @property
    def odometry_drift(self) -> float:
        """Largest distance between odometry and ground truth (m)."""
        return float(np.hypot(*(self.odometry[:, :2] - self.actual[:, :2]).T).max())

    @property
    def kinematic_gap(self) -> float:
        """Largest distance between the kinematic model's prediction and ground truth (m)."""
        return float(np.hypot(*(self.kinematic[:, :2] - self.actual[:, :2]).T).max())

    @property
    def peak_wheel_torque(self) -> float:
        """Largest wheel motor torque magnitude (N·m)."""
        return float(np.abs(self.wheel_torques).max())

    def summary(self) -> str:  # noqa: D102
        return (
            f"{super().summary()}; odometry drift {self.odometry_drift:.3g} m, kinematic model "
            f"off by {self.kinematic_gap:.3g} m, peak wheel torque {self.peak_wheel_torque:.3g} N·m"
        )

    def to_csv(self, path: str | os.PathLike[str]) -> Path:
        """Every row: time, desired and true poses, odometry, kinematic prediction, wheels."""
        header = [
            "t [s]",
            "x_desired [m]",
            "y_desired [m]",
            "theta_desired [rad]",
            "x [m]",
            "y [m]",
            "theta [rad]",
            "x_odometry [m]",
            "y_odometry [m]",
            "theta_odometry [rad]",
            "x_kinematic [m]",
            "y_kinematic [m]",
            "theta_kinematic [rad]",
            "v_desired [m/s]",
            "omega_desired [rad/s]",
            "v_command [m/s]",
            "omega_command [rad/s]",
            "wheel_left_command [rad/s]",
            "wheel_right_command [rad/s]",
            "wheel_left [rad/s]",
            "wheel_right [rad/s]",
            "torque_left [N·m]",
            "torque_right [N·m]",
        ]
        columns = [
            self.t[:, None],
            self.desired,
            self.actual,
            self.odometry,
            self.kinematic,
            self.desired_twist,
            self.commands,
            self.wheel_speeds,
            self.measured_wheel_speeds,
            self.wheel_torques,
            self.path_distance[:, None],
        ]
        return write_csv(path, [*header, "path_distance [m]"], np.concatenate(columns, axis=1))

    @classmethod
    def _csv_extras(cls, source: Path, header: list[str], table: FloatArray) -> dict:
        """Odometry, prediction and wheels from the CSV (``from_csv``, inherited).

        The file does not say the controller (its name stands for it) nor the
        feedback (``"ground_truth"``).
        """
        from trajkit.mobile.simulate import csv_block

        names = ("x_odometry [m]", "y_odometry [m]", "theta_odometry [rad]", "x_kinematic [m]",
                 "y_kinematic [m]", "theta_kinematic [rad]", "wheel_left_command [rad/s]",
                 "wheel_right_command [rad/s]", "wheel_left [rad/s]", "wheel_right [rad/s]",
                 "torque_left [N·m]", "torque_right [N·m]")  # fmt: skip
        extra = csv_block(source, header, table, names)
        return {"odometry": extra[:, 0:3], "kinematic": extra[:, 3:6],
                "wheel_speeds": extra[:, 6:8], "measured_wheel_speeds": extra[:, 8:10],
                "wheel_torques": extra[:, 10:12]}  # fmt: skip


class _Base:
    """Where the base's state sits in MuJoCo's ``qpos``/``qvel`` (free joint, wheels)."""

    def __init__(self, model: Any) -> None:
        mujoco = mujoco_module()
        joint = mujoco.mj_name2id
        kind = mujoco.mjtObj.mjOBJ_JOINT
        self.free = int(model.jnt_qposadr[joint(model, kind, "chassis")])
        wheels = [joint(model, kind, f"{side}_wheel") for side in ("left", "right")]
        self.angles = model.jnt_qposadr[wheels]
        self.speeds = model.jnt_dofadr[wheels]

    def poses(self, qpos: FloatArray) -> FloatArray:
        """Planar poses ``(x, y, yaw)`` of rows of ``qpos`` (..., nq)."""
        f = self.free
        w, qx, qy, qz = (qpos[..., f + i] for i in range(3, 7))
        yaw = np.arctan2(2.0 * (w * qz + qx * qy), 1.0 - 2.0 * (qy * qy + qz * qz))
        return np.stack([qpos[..., f], qpos[..., f + 1], yaw], axis=-1)

    def pose(self, qpos: FloatArray) -> FloatArray:
        """:meth:`poses` of one ``qpos`` row, in scalar arithmetic (it runs every period)."""
        f = self.free
        w, qx, qy, qz = qpos[f + 3 : f + 7].tolist()
        yaw = math.atan2(2.0 * (w * qz + qx * qy), 1.0 - 2.0 * (qy * qy + qz * qz))
        return np.array([qpos[f], qpos[f + 1], yaw])

    def place(self, data: Any, pose: FloatArray, height: float) -> None:
        """Put the base at ``pose`` with its axle ``height`` above the ground, at rest."""
        half = pose[2] / 2.0
        data.qpos[self.free : self.free + 7] = (
            pose[0],
            pose[1],
            height,
            np.cos(half),
            0,
            0,
            np.sin(half),
        )


def run_mobile(
    scene: MobileScene,
    plan: MobileTrajectory,
    *,
    control_rate_hz: float = 50.0,
    duration: float | None = None,
    controller: Controller | None = None,
    initial_pose: ArrayLike | None = None,
    limits: MobileLimits | None = None,
    feedback: Feedback = "ground_truth",
) -> PhysicsLog:
    """Drive a mobile plan on the simulated base; see :func:`trajkit.sim.run`."""
    if not isinstance(plan, MobileTrajectory):
        raise InvalidInputError(
            f"a mobile scene runs a MobileTrajectory, got {type(plan).__name__}"
        )
    controller = Feedforward() if controller is None else controller
    if isinstance(controller, str):
        controller = controller_named(controller)
    if not callable(getattr(controller, "law", None)):
        raise InvalidInputError(
            f"controller must be a name or have a law(plan, start) method, got "
            f"{type(controller).__name__}"
        )
    name = getattr(controller, "name", type(controller).__name__)
    if feedback not in ("ground_truth", "odometry"):
        raise InvalidInputError(f"feedback must be 'ground_truth' or 'odometry', got {feedback!r}")
    end = plan.duration if duration is None else positive_scalar("duration", duration, unit="s")
    if end <= 0.0:
        raise InvalidInputError("the plan has no duration to simulate; pass duration=")
    times, substeps = control_grid(scene.timestep, end, control_rate_hz)
    start = plan.start_pose
    if initial_pose is not None:
        given = finite_array("initial_pose", initial_pose)
        start = pose_array("initial_pose", [*given, start[2]] if given.shape == (2,) else given)
    robot = scene.model
    limits = check_limits(plan.limits if limits is None else limits)
    commander = HeldCommands(plan, controller.law(plan, start), end, control_rate_hz, robot, limits)
    model = scene.compiled()
    mujoco = mujoco_module()
    data = mujoco.MjData(model)
    base = _Base(model)
    base.place(data, start, robot.wheel_radius)
    mujoco.mj_forward(model, data)
    count = times.size
    qpos, qvel = np.empty((count, model.nq)), np.empty((count, model.nv))
    torques, commands = np.empty((count, 2)), np.empty((count, 2))
    odometry = start.copy()
    advice = (
        f"the {name} at {control_rate_hz:g} Hz is unstable on this base: lower its gains, "
        "the wheel gain, or raise the command rate"
    )
    with stability_watch(data, advice):
        for k in range(count):  # a closed loop is sequential by nature
            qpos[k], qvel[k] = data.qpos, data.qvel
            if feedback == "odometry":
                if k > 0:
                    odometry = chain_arcs(odometry, *_wheel_arcs(qpos[k - 1 : k + 1, base.angles],
                                                                 robot))[-1]  # fmt: skip
                v, w = commander(odometry)
            else:
                v, w = commander(base.pose(qpos[k]))
            commands[k] = v, w
            data.ctrl[:] = robot.wheel_pair(v, w)
            if k + 1 < count:
                # The torque of the first step, as the new command takes effect: a
                # velocity servo's largest of the period.
                mujoco.mj_step(model, data)
                torques[k] = data.actuator_force
                if substeps > 1:
                    mujoco.mj_step(model, data, substeps - 1)
            else:
                mujoco.mj_forward(model, data)
                torques[k] = data.actuator_force
    truth = base.poses(qpos)
    # The true heading, unwrapped so that it compares with the plan's unwrapped heading.
    truth[:, 2] = start[2] + np.unwrap(wrap_angle(truth[:, 2] - start[2]))
    period = times[1] - times[0] if count > 1 else 0.0
    return PhysicsLog(
        **log_fields(plan, times, truth, commands, robot),
        controller=name,
        odometry=chain_arcs(start, *_wheel_arcs(qpos[:, base.angles], robot)),
        kinematic=chain_arcs(start, commands[:-1, 0] * period, commands[:-1, 1] * period),
        measured_wheel_speeds=qvel[:, base.speeds],
        wheel_torques=torques,
        feedback=feedback,
    )


def _wheel_arcs(angles: FloatArray, robot: Any) -> tuple[FloatArray, FloatArray]:
    """Distances rolled and angles turned between rows of wheel angles (left, right; rad)."""
    left, right = robot.wheel_radius * np.diff(angles, axis=0).T
    return (left + right) / 2.0, (right - left) / robot.effective_track
