"""Arm trajectories executed in MuJoCo, desired against actual.

The servos and PD + feed-forward are open-loop in their inputs (the servo acts
inside MuJoCo every physics step), so a whole run is a few calls into MuJoCo's
``rollout``; computed torque needs the measured state and steps once per control
period. Controllers are in :mod:`trajkit.sim.controllers`.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from trajkit._validation import FloatArray, positive_scalar
from trajkit.errors import InvalidInputError
from trajkit.io.table import write_csv
from trajkit.sim.controllers import (
    ArmController,
    ComputedTorque,
    VelocityServo,
    arm_controller,
    is_torque_control,
)
from trajkit.sim.dynamics import inverse_dynamics
from trajkit.sim.engine import control_grid, mujoco_module, open_loop, stability_watch
from trajkit.sim.scenes import ArmScene
from trajkit.trajectory import Trajectory

__all__ = ["ArmLog", "run_arm"]


@dataclass(frozen=True, eq=False)
class ArmLog:
    """One simulated arm run, one row per control time.

    Attributes
    ----------
    t : ndarray, shape (n,)
        Control times, in the plan's time (s).
    desired, desired_velocity, desired_acceleration : ndarray, shape (n, ndof)
        The plan's state at those times (rad, rad/s, rad/s²; m, m/s, m/s² for a
        prismatic joint); past the plan's end, at rest at its end position.
    actual, actual_velocity : ndarray, shape (n, ndof)
        The simulated joints' positions and velocities.
    commands : ndarray, shape (n, ncontrol)
        What was sent to the actuators, as MuJoCo's ``ctrl`` (per actuator kind,
        one column per joint: setpoints in rad or rad/s, torques in N·m).
    efforts : ndarray, shape (n, ndof)
        Total actuator torque (N·m, or force in N) on every joint at each control
        time, as the new command takes effect: for a servo, the largest of its
        period.
    joint_names : tuple of str
    controller : str
    revolute : ndarray of bool, shape (ndof,)
        Which joints turn (angles in rad, torques in N·m); the others slide (m, N).
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
    revolute: NDArray[np.bool_]

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

    def units(self) -> list[tuple[str, float, str]]:
        """Per joint: the display unit of positions, its scale from SI, the effort unit."""
        return [("deg", 180.0 / np.pi, "N·m") if turns else ("mm", 1000.0, "N")
                for turns in self.revolute]  # fmt: skip

    def summary(self) -> str:
        """A line per joint: RMS, maximum and final error, peak effort."""
        lines = [f"{self.controller}: {self.t.size} control steps over "
                 f"{self.t[-1] - self.t[0]:.6g} s"]  # fmt: skip
        for j, (name, (unit, scale, effort)) in enumerate(
            zip(self.joint_names, self.units(), strict=True)
        ):
            lines.append(
                f"  {name}: RMS error {self.rms_error[j] * scale:.3g} {unit}, max "
                f"{self.max_error[j] * scale:.3g} {unit}, final "
                f"{self.final_error[j] * scale:.3g} {unit}, peak effort "
                f"{self.peak_effort[j]:.3g} {effort}"
            )
        return "\n".join(lines)

    @classmethod
    def from_csv(cls, path: str | os.PathLike[str]) -> ArmLog:
        """Read a log written by :meth:`to_csv` (to plot or check a recorded run again).

        The file holds no actuator commands nor controller name: ``commands`` comes
        back empty, ``controller`` is the file's name. Joints are revolute where their
        positions are in rad.

        Raises
        ------
        InvalidInputError
            A file whose header is not :meth:`to_csv`'s (the message names the
            column), or a malformed row.
        """
        from trajkit.io.table import read_csv

        source = Path(path)
        header, table = read_csv(source)
        if header[0] != "t [s]" or (len(header) - 1) % 6:
            raise InvalidInputError(f"{source}: not an arm log (t [s], then 6 columns per "
                                    f"joint), got {len(header)} columns")  # fmt: skip
        ndof = (len(header) - 1) // 6
        names, revolute = [], []
        for j, cell in enumerate(header[1 : 1 + ndof]):
            name, _, unit = cell.partition("_desired [")
            if unit not in ("rad]", "m]"):
                raise InvalidInputError(f"{source}: column {j + 2} {cell!r} is not "
                                        "'<joint>_desired [rad]' or '[m]'")  # fmt: skip
            names.append(name)
            revolute.append(unit == "rad]")
        labels = ("desired", "actual", "desired_velocity", "actual_velocity",
                  "desired_acceleration", "effort")  # fmt: skip
        for k, label in enumerate(labels):
            for j, name in enumerate(names):
                cell = header[1 + k * ndof + j]
                if not cell.startswith(f"{name}_{label} ["):
                    raise InvalidInputError(f"{source}: column {2 + k * ndof + j} {cell!r} is "
                                            f"not {name}_{label}")  # fmt: skip
        blocks = [table[:, 1 + k * ndof : 1 + (k + 1) * ndof] for k in range(6)]
        return cls(table[:, 0], blocks[0], blocks[2], blocks[4], blocks[1], blocks[3],
                   np.zeros((table.shape[0], 0)), blocks[5], tuple(names), source.stem,
                   np.array(revolute))  # fmt: skip

    def to_csv(self, path: str | os.PathLike[str]) -> Path:
        """Write every row: time, desired and actual states, efforts (SI units)."""
        header = ["t [s]"]
        columns = [self.t[:, None]]
        linear = ["rad" if turns else "m" for turns in self.revolute]
        for label, data, suffix in (
            ("desired", self.desired, ""),
            ("actual", self.actual, ""),
            ("desired_velocity", self.desired_velocity, "/s"),
            ("actual_velocity", self.actual_velocity, "/s"),
            ("desired_acceleration", self.desired_acceleration, "/s^2"),
        ):
            header += [f"{name}_{label} [{unit}{suffix}]"
                       for name, unit in zip(self.joint_names, linear, strict=True)]  # fmt: skip
            columns.append(data)
        efforts = ["N·m" if turns else "N" for turns in self.revolute]
        header += [f"{name}_effort [{unit}]"
                   for name, unit in zip(self.joint_names, efforts, strict=True)]  # fmt: skip
        columns.append(self.efforts)
        return write_csv(path, header, np.concatenate(columns, axis=1))


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
    _check_ranges(scene, plan)
    ndof = scene.ndof
    torque_control = is_torque_control(control)
    model = scene.compiled(control)
    mujoco = mujoco_module()
    data = mujoco.MjData(model)
    clock = plan.start_time + times
    desired = [plan.evaluate(clock, order) for order in (0, 1, 2)]
    # Past the plan's end the robot is asked to stand still at the end position.
    after = clock > plan.end_time
    desired[1][after] = desired[2][after] = 0.0
    data.qpos[:], data.qvel[:] = desired[0][0], desired[1][0]
    if isinstance(control, VelocityServo):
        data.act[:] = desired[0][0]  # the integrated setpoint starts where the joints are
    mujoco.mj_forward(model, data)
    advice = (
        f"the {control.name} at {control_rate_hz:g} Hz is unstable on this arm: lower its "
        "gains or raise the control rate"
    )
    with stability_watch(data, advice):
        if isinstance(control, ComputedTorque):
            actual, velocity, commands, efforts = _computed_torque(
                model, data, control, desired, substeps
            )
        else:
            torque = inverse_dynamics(scene.robot, model, *desired) if torque_control else None
            commands = control.inputs(desired[0], desired[1], torque)
            rows = open_loop(model, data, commands[:-1], substeps, commands[-1])
            actual, velocity = rows[:, :ndof], rows[:, ndof : 2 * ndof]
            efforts = rows[:, 2 * ndof :]
    return ArmLog(
        t=clock,
        desired=desired[0],
        desired_velocity=desired[1],
        desired_acceleration=desired[2],
        actual=actual,
        actual_velocity=velocity,
        commands=commands,
        efforts=efforts,
        joint_names=tuple(scene.robot.names),
        controller=control.name,
        revolute=scene.robot.revolute.copy(),
    )


def _check_ranges(scene: ArmScene, plan: Trajectory) -> None:
    """Refuse a plan that leaves the arm's joint ranges (the run would start or end in them)."""
    extrema = plan.extrema(0)
    lower, upper = scene.robot.lower, scene.robot.upper
    slack = 1e-9 * np.maximum(1.0, np.abs(np.stack([lower, upper])))
    low = extrema.minimum < np.where(np.isfinite(lower), lower - slack[0], -np.inf)
    high = extrema.maximum > np.where(np.isfinite(upper), upper + slack[1], np.inf)
    for j in np.flatnonzero(low | high):
        value = extrema.minimum[j] if low[j] else extrema.maximum[j]
        raise InvalidInputError(
            f"the plan takes joint {scene.robot.names[j]} to {value:.6g}, outside its range "
            f"[{lower[j]:.6g}, {upper[j]:.6g}]"
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
