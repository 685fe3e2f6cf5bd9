"""From a task-space motion to a checked joint-space trajectory.

The pipeline, all batched over samples:

1. Inverse kinematics at every sample. Closed-form arms keep one solution
   branch throughout; other chains are solved at a coarse set of knots in order
   (each warm-started from the last, so the solution follows one branch), then at
   every sample at once from seeds interpolated between the knots.
2. Revolute angles are unwrapped, so no sample jumps by a whole turn.
3. Joint velocities and accelerations from the Jacobian:
   ``q̇ = J⁺ ẋ`` and ``q̈ = J⁺ (ẍ - J̇ q̇)``.
4. A quintic Hermite spline through (q, q̇, q̈) at every sample: continuous up to
   acceleration. Its forward kinematics is compared with the task path between
   samples, and the joint limits are checked on its exact pieces.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from trajkit._validation import positive_scalar
from trajkit.errors import InfeasibleError, InvalidInputError, UnreachableError
from trajkit.kinematics.chain import SerialChain
from trajkit.kinematics.robots import AnalyticChain
from trajkit.limits import Report, check
from trajkit.profiles.polynomial import hermite_pieces
from trajkit.renamed import renamed_keywords
from trajkit.rotations import rotation_error
from trajkit.taskspace.motion import TaskState, TaskTrajectory
from trajkit.tolerances import LIMIT_RTOL
from trajkit.trajectory import Trajectory

FloatArray = NDArray[np.float64]

__all__ = ["JointSpacePlan", "to_joint_space"]

#: A step between samples larger than this many times the step the joint
#: velocities predict (plus a small floor) means the solution left its branch.
_JUMP_FACTOR = 10.0


@dataclass(frozen=True)
class JointSpacePlan:
    """A joint trajectory made from a task-space motion, with what was checked.

    Attributes
    ----------
    trajectory : Trajectory
        Quintic Hermite spline through the IK samples (continuous acceleration).
    t, q, qd, qdd : ndarray
        The samples (s; rad or m and their rates) the spline interpolates.
    path_error : float
        Largest distance between the spline's tool position and the task path,
        measured between samples (length unit of the robot).
    limits : Report
        Joint position and velocity limits checked on the spline's exact pieces.
    first_violation : tuple (time, joint, quantity) or None
        The earliest sample where a joint leaves its position or velocity
        bounds (joint counts from 0).
    inverse_condition : ndarray, shape (m,)
        ``σ_min / σ_max`` of the task Jacobian at each sample; 0 at a singularity.
    singular_time : float or None
        First sample time where ``inverse_condition`` falls below the threshold.
    """

    trajectory: Trajectory
    t: FloatArray
    q: FloatArray
    qd: FloatArray
    qdd: FloatArray
    path_error: float
    limits: Report
    first_violation: tuple[float, int, str] | None
    inverse_condition: FloatArray
    singular_time: float | None

    @property
    def ok(self) -> bool:
        """True when no limit is broken and no sample is near a singularity."""
        return self.limits.ok and self.first_violation is None and self.singular_time is None

    def problems(self) -> list[str]:
        """One sentence per problem found (empty when :attr:`ok`)."""
        out = []
        if self.first_violation is not None:
            time, joint, quantity = self.first_violation
            out.append(f"joint {joint + 1} first exceeds its {quantity} limit at t={time:.6g} s")
        out += [str(v) for v in self.limits.violations]
        if self.singular_time is not None:
            out.append(
                f"near a singularity from t={self.singular_time:.6g} s "
                f"(inverse condition number {self.inverse_condition.min():.3g})"
            )
        return out


#: Most inverse-kinematics samples one mapping makes. Each costs kilobytes (poses,
#: Jacobians, every branch), so the cap is tighter than Trajectory.sample's
#: ``MAX_SAMPLES`` row count; the rule and the message are the same.
MAX_IK_SAMPLES = 1_000_000


def _sample_times(duration: float, ik_step: float) -> FloatArray:
    ratio = duration / ik_step
    if not ratio <= MAX_IK_SAMPLES:
        raise InvalidInputError(
            f"ik_step={ik_step:g} s over {duration:g} s gives {ratio:.3g} samples; at most "
            f"{MAX_IK_SAMPLES:.0e} are made: use a longer ik_step"
        )
    count = int(np.floor(ratio + 1e-9))
    times = np.arange(count + 1) * ik_step
    # A task shorter than the tolerance still keeps its start: two times at least.
    if count == 0 or duration - times[-1] > 1e-9 * max(1.0, duration):
        times = np.append(times, duration)
    else:
        times[-1] = duration
    return times


def _targets(task: TaskState, position_only: bool) -> FloatArray:
    return task.position if position_only else task.poses()


def _unwrap(q: FloatArray, robot: SerialChain, reference: FloatArray | None) -> FloatArray:
    """Unwrap continuous joints along time; start within π of ``reference``."""
    out = q.copy()
    out[:, robot.continuous] = np.unwrap(q[:, robot.continuous], axis=0)
    if reference is None:
        return out
    # Whole turns on continuous joints, zero elsewhere: the whole path moves by them.
    return out - (out[0] - robot.wrap_near(out[0], reference))


def _analytic_ik(
    robot: AnalyticChain, task: TaskState, q_start: FloatArray | None, branch: int | str | None
) -> FloatArray:
    solutions = robot.ik_branches(task.position)  # (m, nbranch, ndof)
    unreachable = np.flatnonzero(np.any(np.isnan(solutions[:, 0]), axis=1))
    if unreachable.size:
        k = int(unreachable[0])
        try:
            robot.ik(task.position[k])
        except UnreachableError as exc:
            raise UnreachableError(f"task sample at t={task.t[k]:.6g} s: {exc}", index=k) from None
    if branch is not None:
        chosen = robot.branch_index(branch)
    elif q_start is not None:
        first = robot.wrap_near(solutions[:1], q_start[np.newaxis, np.newaxis])[0]
        distance = np.nan_to_num(np.linalg.norm(first - q_start, axis=1), nan=np.inf)
        chosen = int(np.argmin(distance))
    else:
        chosen = 0
    return solutions[:, chosen]


def _rates(
    robot: SerialChain, q: FloatArray, task: TaskState, position_only: bool
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Joint velocities and accelerations from the Jacobian, and its inverse condition."""
    rows = slice(0, 3) if position_only else slice(0, 6)
    jacobian = robot.jacobian(q)[:, rows]
    if position_only:
        twist, twist_rate = task.velocity, task.acceleration
    else:
        assert task.angular_velocity is not None and task.angular_acceleration is not None
        twist = np.concatenate([task.velocity, task.angular_velocity], axis=1)
        twist_rate = np.concatenate([task.acceleration, task.angular_acceleration], axis=1)
    singular_values = np.linalg.svd(jacobian, compute_uv=False)
    inverse_condition = singular_values[:, -1] / np.maximum(singular_values[:, 0], 1e-300)
    pinv = np.linalg.pinv(jacobian)
    qd = np.einsum("mjk,mk->mj", pinv, twist)
    bias = np.einsum("mkj,mj->mk", robot.jacobian_dot(q, qd)[:, rows], qd)
    qdd = np.einsum("mjk,mk->mj", pinv, twist_rate - bias)
    return qd, qdd, inverse_condition


def _first_violation(
    t: FloatArray, q: FloatArray, qd: FloatArray, robot: SerialChain, rtol: float = LIMIT_RTOL
) -> tuple[float, int, str] | None:
    first: tuple[float, int, str] | None = None
    lower, upper = robot.lower, robot.upper
    speed = robot.velocity_limits
    for quantity, values, low, high in (
        ("position", q, lower, upper),
        ("velocity", qd, -speed, speed),
    ):
        finite_low = np.where(np.isfinite(low), np.abs(low), 0.0)
        slack = rtol * np.maximum(finite_low, np.where(np.isfinite(high), np.abs(high), 0.0))
        bad = (values < low - slack) | (values > high + slack)
        if bad.any():
            k, j = np.argwhere(bad)[0]
            if first is None or t[k] < first[0]:
                first = (float(t[k]), int(j), quantity)
    return first


@renamed_keywords(dt="ik_step")
def to_joint_space(
    robot: SerialChain,
    task: TaskTrajectory,
    ik_step: float,
    q_start: ArrayLike | None = None,
    *,
    branch: int | str | None = None,
    tolerance: float = 1e-6,
    singularity_threshold: float = 1e-3,
) -> JointSpacePlan:
    """Map a task-space motion to a smooth, checked joint trajectory.

    Parameters
    ----------
    robot : SerialChain
    task : TaskTrajectory
        With orientation, the full tool pose is followed; without, the position only.
    ik_step : float
        Sample period of the inverse kinematics (s); the last sample is at the end.
    q_start : array_like, shape (ndof,), optional
        Configuration to start from: selects the solution branch (closed-form
        arms) or seeds the search (other chains).
    branch : int or str, optional
        For closed-form arms: the branch to follow (overrides ``q_start``).
    tolerance : float
        Largest allowed distance between the spline's tool position and the path
        between samples (length unit); beyond it :class:`~trajkit.InfeasibleError`
        asks for a smaller ``ik_step``.
    singularity_threshold : float
        Samples whose Jacobian has ``σ_min/σ_max`` below this are reported.

    Returns
    -------
    JointSpacePlan

    Raises
    ------
    UnreachableError
        A sample is outside the workspace (the message gives its time).
    InfeasibleError
        The joint solution jumps between samples (a branch change at a
        singularity), or the spline strays from the path by more than ``tolerance``.
    """
    if not isinstance(robot, SerialChain):
        raise InvalidInputError(f"robot must be a trajkit SerialChain, got {type(robot).__name__}")
    if not isinstance(task, TaskTrajectory):
        raise InvalidInputError(f"task must be a TaskTrajectory, got {type(task).__name__}")
    ik_step = positive_scalar("ik_step", ik_step, unit="s")
    tolerance = positive_scalar("tolerance", tolerance)
    threshold = positive_scalar("singularity_threshold", singularity_threshold)
    start = None
    if q_start is not None:
        configs, single = robot.configurations(q_start, "q_start")
        if not single:
            raise InvalidInputError(
                f"q_start must be one configuration of shape ({robot.ndof},), got "
                f"{configs.shape[0]} rows"
            )
        start = configs[0]
    position_only = not task.has_orientation
    analytic = isinstance(robot, AnalyticChain)
    if analytic and not position_only:
        raise InvalidInputError(
            f"{robot.name} sets only its tool position: give a task without orientation"
        )
    if task.duration <= 0.0:
        raise InvalidInputError("the task has zero duration")
    t = _sample_times(task.duration, ik_step)
    state = task.state(t)
    if analytic:
        q = _analytic_ik(robot, state, start, branch)
    else:
        if branch is not None:
            raise InvalidInputError(f"branch applies to closed-form arms only, not {robot.name}")
        try:
            q = robot.ik_path(_targets(state, position_only), start, position_only=position_only).q
        except UnreachableError as exc:
            where = "" if exc.index is None else f"task sample at t={t[exc.index]:.6g} s: "
            raise UnreachableError(f"{where}{exc}", index=exc.index) from None
    q = _unwrap(q, robot, start)
    qd, qdd, inverse_condition = _rates(robot, q, state, position_only)
    _check_jumps(t, q, qd)
    durations = np.diff(t)
    boundary = np.stack([q, qd, qdd])  # (3, m, ndof)
    coefficients = hermite_pieces(boundary[:, :-1], boundary[:, 1:], durations[:, np.newaxis])
    info = {"planner": "to_joint_space", "ik_step": ik_step, "continuity": 2}  # quintic Hermite: C2
    trajectory = Trajectory(t, coefficients, info=info)
    path_error = _path_error(robot, trajectory, task, t, position_only)
    singular = np.flatnonzero(inverse_condition < threshold)
    if path_error > tolerance:
        cause = (
            f"the path passes through or near a singularity at t={t[singular[0]]:.6g} s"
            if singular.size
            else f"use a smaller ik_step than {ik_step:g} s"
        )
        raise InfeasibleError(
            f"the joint spline strays {path_error:.3g} from the task path between samples, "
            f"more than the tolerance {tolerance:g}: {cause}"
        )
    return JointSpacePlan(
        trajectory=trajectory,
        t=t,
        q=q,
        qd=qd,
        qdd=qdd,
        path_error=path_error,
        limits=check(trajectory, robot.limits()),
        first_violation=_first_violation(t, q, qd, robot),
        inverse_condition=inverse_condition,
        singular_time=float(t[singular[0]]) if singular.size else None,
    )


def _check_jumps(t: FloatArray, q: FloatArray, qd: FloatArray) -> None:
    step = np.abs(np.diff(q, axis=0))
    dt = np.diff(t)[:, np.newaxis]
    predicted = np.maximum(np.abs(qd[:-1]), np.abs(qd[1:])) * dt
    floor = 1e-6 + 1e-3 * np.abs(q).max()
    jumps = np.argwhere(step > _JUMP_FACTOR * predicted + floor)
    if jumps.size:
        k, j = jumps[0]
        raise InfeasibleError(
            f"joint {j + 1} jumps by {step[k, j]:.6g} between t={t[k]:.6g} s and "
            f"t={t[k + 1]:.6g} s: the solution changes branch (the path passes through "
            "or near a singularity)"
        )


def _path_error(
    robot: SerialChain,
    trajectory: Trajectory,
    task: TaskTrajectory,
    t: FloatArray,
    position_only: bool,
) -> float:
    """Largest tool deviation from the task at the quarter points between samples."""
    fractions = np.array([0.25, 0.5, 0.75])
    between = (t[:-1, np.newaxis] + np.diff(t)[:, np.newaxis] * fractions).reshape(-1)
    tool = robot.fk(trajectory.position(between))
    desired = task.state(between)
    error = np.linalg.norm(tool[:, :3, 3] - desired.position, axis=1)
    if not position_only:
        assert desired.rotation is not None
        # Orientation error (rad) times the robot's scale, to compare in one unit.
        angle = np.linalg.norm(rotation_error(desired.rotation, tool[:, :3, :3]), axis=1)
        error = np.maximum(error, angle * max(robot.reach(), 1.0))
    return float(error.max()) if error.size else 0.0
