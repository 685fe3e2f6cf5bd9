"""Arm trajectories executed in MuJoCo: joint servos or torque control, desired against actual.

Four ways to drive the joints, as real arm controllers do:

* :class:`PositionServo` — a PD servo on position (Gazebo's
  ``effort_controllers/JointPositionController``); the setpoint is the plan's
  position, held over each control period.
* :class:`VelocityServo` — the plan's velocity is the command; the drive
  integrates it into a position setpoint (``kp``) and damps the velocity error
  (``kv``), as a velocity interface over a position loop does.
* :class:`PDFeedforward` — the torque of the inverse dynamics along the plan
  (from its accelerations, for all control times at once) plus PD on the
  position and velocity errors.
* :class:`ComputedTorque` — inverse dynamics at the *measured* state with the
  plan's acceleration corrected by the errors: ``τ = M(q)(q̈_d + K_d ė + K_p e) + h(q, q̇)``.

The first three are open-loop in their inputs (the servo acts inside MuJoCo every
physics step), so a whole run is one call into MuJoCo's ``rollout``; computed
torque needs the measured state and steps once per control period.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from trajkit._validation import FloatArray, finite_array, positive_scalar
from trajkit.errors import InvalidInputError
from trajkit.io.table import write_csv
from trajkit.sim.dynamics import inverse_dynamics
from trajkit.sim.engine import control_grid, mujoco_module, open_loop
from trajkit.sim.mjcf import Actuator
from trajkit.sim.scenes import ArmScene
from trajkit.trajectory import Trajectory

__all__ = [
    "ArmLog",
    "ComputedTorque",
    "PDFeedforward",
    "PositionServo",
    "VelocityServo",
    "arm_controller",
    "model_for",
    "run_arm",
]


def _gains(name: str, value: Any, ndof: int, unit: str) -> FloatArray:
    gains = finite_array(name, value, unit=unit)
    gains = np.full(ndof, float(gains)) if gains.ndim == 0 else gains
    if gains.shape != (ndof,) or np.any(gains < 0.0):
        raise InvalidInputError(
            f"{name} must be one number or one per joint ({ndof}), each >= 0 {unit}, got "
            f"{np.asarray(value).tolist()}"
        )
    return gains


@dataclass(frozen=True)
class PositionServo:
    """PD position servo: ``τ = kp (q_d − q) − kv q̇`` (N·m/rad, N·m·s/rad).

    The defaults are the gains of Gazebo's RRBot position controllers (p 100, d 10).
    """

    kp: Any = 100.0
    kv: Any = 10.0
    name: str = "position servo"

    def actuators(self, ndof: int) -> list[Actuator]:
        """One MuJoCo position actuator per joint."""
        return [
            Actuator(
                "position",
                _gains("kp", self.kp, ndof, "N·m/rad"),
                _gains("kv", self.kv, ndof, "N·m·s/rad"),
            )
        ]

    def inputs(self, q: FloatArray, qd: FloatArray, torque: FloatArray | None) -> FloatArray:
        """The control columns for desired states (one row per control time)."""
        return q


@dataclass(frozen=True)
class VelocityServo:
    """Velocity command ``u = q̇_d``: ``τ = kp (∫u dt − q) + kv (u − q̇)``."""

    kp: Any = 100.0
    kv: Any = 10.0
    name: str = "velocity servo"

    def actuators(self, ndof: int) -> list[Actuator]:
        """An integrated-velocity (position loop) and a velocity actuator per joint."""
        return [
            Actuator("intvelocity", kp=_gains("kp", self.kp, ndof, "N·m/rad")),
            Actuator("velocity", kv=_gains("kv", self.kv, ndof, "N·m·s/rad")),
        ]

    def inputs(self, q: FloatArray, qd: FloatArray, torque: FloatArray | None) -> FloatArray:  # noqa: D102
        return np.concatenate([qd, qd], axis=1)


@dataclass(frozen=True)
class PDFeedforward:
    """Inverse-dynamics feed-forward plus PD: ``τ = τ_ID(q_d, q̇_d, q̈_d) + kp e + kv ė``."""

    kp: Any = 100.0
    kv: Any = 10.0
    name: str = "PD + feed-forward"

    def actuators(self, ndof: int) -> list[Actuator]:
        """A motor, a position and a velocity actuator per joint."""
        return [
            Actuator("motor"),
            Actuator("position", kp=_gains("kp", self.kp, ndof, "N·m/rad")),
            Actuator("velocity", kv=_gains("kv", self.kv, ndof, "N·m·s/rad")),
        ]

    def inputs(self, q: FloatArray, qd: FloatArray, torque: FloatArray | None) -> FloatArray:  # noqa: D102
        return np.concatenate([torque, q, qd], axis=1)


@dataclass(frozen=True)
class ComputedTorque:
    """Computed torque with error dynamics ``ë + 2ζω ė + ω² e = 0``.

    Parameters
    ----------
    frequency : float
        Natural frequency ``ω`` of the error dynamics (rad/s).
    damping_ratio : float
        ``ζ``; 1 is critically damped.
    """

    frequency: float = 30.0
    damping_ratio: float = 1.0
    name: str = "computed torque"

    def actuators(self, ndof: int) -> list[Actuator]:
        """One motor per joint."""
        return [Actuator("motor")]

    def gains(self) -> tuple[float, float]:
        """``(ω², 2ζω)``."""
        omega = positive_scalar("frequency", self.frequency, unit="rad/s")
        zeta = positive_scalar("damping_ratio", self.damping_ratio)
        return omega**2, 2.0 * zeta * omega


ArmController = PositionServo | VelocityServo | PDFeedforward | ComputedTorque

_NAMED: dict[str, type] = {
    "position": PositionServo,
    "velocity": VelocityServo,
    "pd_feedforward": PDFeedforward,
    "computed_torque": ComputedTorque,
}


def arm_controller(controller: str | ArmController) -> ArmController:
    """A controller object from itself or its name, with default gains.

    Names: ``"position"``, ``"velocity"``, ``"pd_feedforward"``, ``"computed_torque"``.
    """
    if isinstance(controller, str):
        if controller not in _NAMED:
            raise InvalidInputError(
                f"unknown arm controller {controller!r}; choose one of {sorted(_NAMED)}"
            )
        return _NAMED[controller]()
    if not isinstance(controller, (PositionServo, VelocityServo, PDFeedforward, ComputedTorque)):
        raise InvalidInputError(
            "controller must be a name or a PositionServo, VelocityServo, PDFeedforward or "
            f"ComputedTorque, got {type(controller).__name__}"
        )
    return controller


@dataclass(frozen=True, eq=False)
class ArmLog:
    """One simulated arm run, one row per control time.

    Attributes
    ----------
    t : ndarray, shape (n,)
        Control times (s).
    desired, desired_velocity, desired_acceleration : ndarray, shape (n, ndof)
        The plan's state at those times (rad, rad/s, rad/s²).
    actual, actual_velocity : ndarray, shape (n, ndof)
        The simulated joints' positions and velocities.
    commands : ndarray, shape (n, ncontrol)
        What was sent to the actuators, as MuJoCo's ``ctrl`` (per actuator kind,
        one column per joint: setpoints in rad or rad/s, torques in N·m).
    efforts : ndarray, shape (n, ndof)
        Total actuator torque on every joint during the period after each time (N·m).
    joint_names : tuple of str
    controller : str
    """

    t: FloatArray
    desired: FloatArray
    desired_velocity: FloatArray
    desired_acceleration: FloatArray
    actual: FloatArray
    actual_velocity: FloatArray
    commands: FloatArray
    efforts: FloatArray
    joint_names: tuple[str, ...]
    controller: str

    @property
    def error(self) -> FloatArray:
        """``q − q_d`` at every row (rad)."""
        return self.actual - self.desired

    @property
    def rms_error(self) -> FloatArray:
        """Root mean square tracking error per joint (rad)."""
        return np.sqrt(np.mean(self.error**2, axis=0))

    @property
    def max_error(self) -> FloatArray:
        """Largest tracking error magnitude per joint (rad)."""
        return np.abs(self.error).max(axis=0)

    @property
    def final_error(self) -> FloatArray:
        """Tracking error at the last row, per joint (rad)."""
        return self.error[-1]

    @property
    def peak_effort(self) -> FloatArray:
        """Largest actuator torque magnitude per joint (N·m)."""
        return np.abs(self.efforts).max(axis=0)

    def summary(self) -> str:
        """A line per joint: RMS, maximum and final error, peak effort."""
        lines = [f"{self.controller}: {self.t.size} control steps over {self.t[-1]:.6g} s"]
        for j, name in enumerate(self.joint_names):
            lines.append(
                f"  {name}: RMS error {np.degrees(self.rms_error[j]):.3g} deg, max "
                f"{np.degrees(self.max_error[j]):.3g} deg, final "
                f"{np.degrees(self.final_error[j]):.3g} deg, peak effort "
                f"{self.peak_effort[j]:.3g} N·m"
            )
        return "\n".join(lines)

    def to_csv(self, path: str | os.PathLike[str]) -> Path:
        """Write every row: time, desired and actual states, efforts (SI units)."""
        header = ["t [s]"]
        columns = [self.t[:, None]]
        for label, data, unit in (
            ("desired", self.desired, "rad"),
            ("actual", self.actual, "rad"),
            ("desired_velocity", self.desired_velocity, "rad/s"),
            ("actual_velocity", self.actual_velocity, "rad/s"),
            ("effort", self.efforts, "N·m"),
        ):
            header += [f"{name}_{label} [{unit}]" for name in self.joint_names]
            columns.append(data)
        return write_csv(path, header, np.concatenate(columns, axis=1))


def model_for(scene: ArmScene, controller: str | ArmController) -> Any:
    """The scene's MuJoCo model with ``controller``'s actuators (compiled once).

    Torque controllers compute gravity in their own inverse dynamics, so their
    model never adds the servo's gravity compensation.
    """
    control = arm_controller(controller)
    torque_control = isinstance(control, (PDFeedforward, ComputedTorque))
    return scene.compiled(control.actuators(scene.ndof),
                          scene.gravity_compensation and not torque_control)  # fmt: skip


def run_arm(
    scene: ArmScene,
    plan: Trajectory,
    *,
    control_rate_hz: float = 1000.0,
    duration: float | None = None,
    controller: str | ArmController = "position",
) -> ArmLog:
    """Execute a joint trajectory on the simulated arm; see :func:`trajkit.sim.run`."""
    if not isinstance(plan, Trajectory):
        raise InvalidInputError(f"an arm scene runs a joint Trajectory, got {type(plan).__name__}")
    if plan.ndof != scene.ndof:
        raise InvalidInputError(
            f"the plan has {plan.ndof} joint(s) but {scene.robot.name} has {scene.ndof}"
        )
    control = arm_controller(controller)
    end = (
        plan.end_time
        if duration is None
        else plan.start_time + positive_scalar("duration", duration, unit="s")
    )
    if end <= plan.start_time:
        raise InvalidInputError("the plan has no duration to simulate; pass duration=")
    times, substeps = control_grid(scene.timestep, end - plan.start_time, control_rate_hz)
    ndof = scene.ndof
    torque_control = isinstance(control, (PDFeedforward, ComputedTorque))
    model = model_for(scene, control)
    mujoco = mujoco_module()
    data = mujoco.MjData(model)
    desired = [plan.evaluate(plan.start_time + times, order) for order in (0, 1, 2)]
    # Past the plan's end the robot is asked to stand still at the end position.
    after = plan.start_time + times > plan.end_time
    desired[1][after] = desired[2][after] = 0.0
    data.qpos[:], data.qvel[:] = desired[0][0], desired[1][0]
    if isinstance(control, VelocityServo):
        data.act[:] = desired[0][0]  # the integrated setpoint starts where the joints are
    mujoco.mj_forward(model, data)
    if isinstance(control, ComputedTorque):
        actual, velocity, commands, efforts = _computed_torque(
            model, data, control, desired, substeps
        )
    else:
        torque = inverse_dynamics(scene.robot, model, *desired) if torque_control else None
        commands = control.inputs(desired[0], desired[1], torque)
        sensors = open_loop(model, data, np.repeat(commands[:-1], substeps, axis=0), commands[-1])
        rows = sensors[::substeps]
        actual, velocity, efforts = rows[:, :ndof], rows[:, ndof : 2 * ndof], rows[:, 2 * ndof :]
    return ArmLog(
        t=times,
        desired=desired[0],
        desired_velocity=desired[1],
        desired_acceleration=desired[2],
        actual=actual,
        actual_velocity=velocity,
        commands=commands,
        efforts=efforts,
        joint_names=tuple(scene.robot.names),
        controller=control.name,
    )


def _computed_torque(
    model: Any, data: Any, control: ComputedTorque, desired: list[FloatArray], substeps: int
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    mujoco = mujoco_module()
    kp, kd = control.gains()
    q_d, qd_d, qdd_d = desired
    count, ndof = q_d.shape
    # a_ref = q̈_d + kd (q̇_d − q̇) + kp (q_d − q) is one matrix product per period,
    # gains[k] @ (q, q̇, 1), with the plan's part in the last column: the loop's
    # Python work stays a few calls.
    gains = np.zeros((count, ndof, 2 * ndof + 1))
    gains[:, :, :ndof] = -kp * np.eye(ndof)
    gains[:, :, ndof : 2 * ndof] = -kd * np.eye(ndof)
    gains[:, :, -1] = qdd_d + kd * qd_d + kp * q_d
    states = np.ones((count, 2 * ndof + 1))
    commands, efforts = np.empty((count, ndof)), np.empty((count, ndof))
    spec = mujoco.mjtState.mjSTATE_QPOS | mujoco.mjtState.mjSTATE_QVEL
    qacc, ctrl, torque, applied = data.qacc, data.ctrl, data.qfrc_inverse, data.qfrc_actuator
    for k in range(count):  # feedback on the measured state: sequential by nature
        mujoco.mj_getState(model, data, states[k, :-1], spec)
        np.matmul(gains[k], states[k], out=qacc)
        # Inverse dynamics on the simulation's own data: it reads qpos, qvel and qacc
        # and writes only quantities the next step recomputes.
        mujoco.mj_inverse(model, data)
        ctrl[:] = torque
        commands[k] = torque
        if k + 1 < count:
            mujoco.mj_step(model, data, substeps)
        else:
            mujoco.mj_forward(model, data)
        efforts[k] = applied
    return states[:, :ndof], states[:, ndof:-1], commands, efforts
