"""Piecewise-constant-jerk phase plans and their conversion to a Trajectory.

Limit-driven profiles (trapezoid, S-curve) are planned as a short list of phases
per joint: each phase has a duration, the acceleration it starts with and a
constant jerk. A trapezoid's phases have zero jerk and set their acceleration; an
S-curve's phases carry the acceleration on continuously. Everything here is
vectorized over leading axes (joints, problems).
"""

from __future__ import annotations

import numpy as np

from trajkit._validation import FloatArray
from trajkit.trajectory import Trajectory

__all__ = ["PhasePlan", "merge_breakpoints", "phase_states", "plan_info", "plan_to_trajectory"]

# Breakpoints closer than this (relative to the whole duration) are the same switch
# computed along two roundings; anything longer is a phase and is kept, however short.
_MERGE = 4e-16


class PhasePlan:
    """Phases of every joint: arrays of shape ``(..., ndof, P)``.

    Attributes
    ----------
    position, velocity : ndarray, shape (..., ndof)
        Start state of each joint.
    durations : ndarray, shape (..., ndof, P)
        Phase durations (s), >= 0.
    accelerations : ndarray, shape (..., ndof, P)
        Acceleration at the start of each phase.
    jerks : ndarray, shape (..., ndof, P)
        Constant jerk within each phase.
    """

    __slots__ = ("accelerations", "durations", "jerks", "position", "velocity")

    def __init__(
        self,
        position: FloatArray,
        velocity: FloatArray,
        durations: FloatArray,
        accelerations: FloatArray,
        jerks: FloatArray,
    ) -> None:
        self.position = position
        self.velocity = velocity
        self.durations = durations
        self.accelerations = accelerations
        self.jerks = jerks

    @property
    def joint_durations(self) -> FloatArray:
        """Each joint's own duration (s), shape ``(..., ndof)``."""
        return self.durations.sum(axis=-1)


def phase_states(plan: PhasePlan) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Start times, positions and velocities of every phase, shape ``(..., ndof, P)``."""
    d, a, j = plan.durations, plan.accelerations, plan.jerks
    dv = a * d + j * d**2 / 2.0
    v_start = plan.velocity[..., np.newaxis] + np.concatenate(
        [np.zeros_like(dv[..., :1]), np.cumsum(dv[..., :-1], axis=-1)], axis=-1
    )
    dp = v_start * d + a * d**2 / 2.0 + j * d**3 / 6.0
    p_start = plan.position[..., np.newaxis] + np.concatenate(
        [np.zeros_like(dp[..., :1]), np.cumsum(dp[..., :-1], axis=-1)], axis=-1
    )
    t_start = np.concatenate([np.zeros_like(d[..., :1]), np.cumsum(d[..., :-1], axis=-1)], axis=-1)
    return t_start, p_start, v_start


def merge_breakpoints(times: FloatArray, duration: float) -> FloatArray:
    """Sorted unique breakpoints in ``[0, duration]``, merging near-duplicates."""
    if duration == 0.0:
        return np.zeros(2)
    points = np.sort(np.concatenate([[0.0, duration], times.ravel()]))
    points = points[(points >= 0.0) & (points <= duration)]
    keep = np.concatenate([[True], np.diff(points) > _MERGE * duration])
    points = points[keep]
    points[-1] = duration
    if points.size >= 2 and points[-1] - points[-2] <= _MERGE * duration:
        points = np.delete(points, -2)
    if points.size < 2:
        points = np.array([0.0, duration])
    return points


def plan_info(
    planner: str,
    sync: object,
    dt: float | None,
    duration: FloatArray,
    own: FloatArray,
    limiting: FloatArray,
    phase_times: FloatArray,
    peak_velocity: FloatArray,
) -> dict[str, object]:
    """The ``info`` fields every limit-driven planner reports, as plain Python numbers."""
    joint = int(limiting)
    return {
        "planner": planner,
        "sync": sync,
        "dt": dt,
        "duration": float(duration),
        "minimum_durations": tuple(float(x) for x in own),
        "limiting_joint": None if joint < 0 else joint,
        "phase_times": tuple(tuple(float(x) for x in row) for row in phase_times),
        "peak_velocity": tuple(float(x) for x in peak_velocity),
    }


def plan_to_trajectory(plan: PhasePlan, duration: float, info: dict[str, object]) -> Trajectory:
    """One Trajectory holding every joint's phases (a single problem: no leading axes).

    Joints whose phases end before ``duration`` continue at their final velocity
    with zero acceleration (at rest, if they end at rest).
    """
    t_start, p_start, v_start = phase_states(plan)
    ndof, count = plan.durations.shape
    # An extra open-ended coasting phase per joint keeps kinematics consistent.
    ends = t_start[:, -1] + plan.durations[:, -1]
    final_v = (
        v_start[:, -1]
        + plan.accelerations[:, -1] * plan.durations[:, -1]
        + (plan.jerks[:, -1] * plan.durations[:, -1] ** 2 / 2.0)
    )
    d_last = plan.durations[:, -1]
    final_p = (
        p_start[:, -1]
        + v_start[:, -1] * d_last
        + plan.accelerations[:, -1] * d_last**2 / 2.0
        + plan.jerks[:, -1] * d_last**3 / 6.0
    )
    starts = np.concatenate([t_start, ends[:, np.newaxis]], axis=1)
    p0 = np.concatenate([p_start, final_p[:, np.newaxis]], axis=1)
    v0 = np.concatenate([v_start, final_v[:, np.newaxis]], axis=1)
    a0 = np.concatenate([plan.accelerations, np.zeros((ndof, 1))], axis=1)
    j0 = np.concatenate([plan.jerks, np.zeros((ndof, 1))], axis=1)
    # Zero-length phases would shadow their successors in the search below.
    nonempty = np.concatenate([plan.durations > 0, np.ones((ndof, 1), bool)], axis=1)
    breakpoints = merge_breakpoints(np.where(nonempty, starts, 0.0), duration)
    middles = 0.5 * (breakpoints[:-1] + breakpoints[1:])
    # Phase of each joint containing each piece: the last non-empty phase starting before.
    began = nonempty[:, np.newaxis, :] & (
        starts[:, np.newaxis, :] <= middles[np.newaxis, :, np.newaxis]
    )
    index = count - np.argmax(began[..., ::-1], axis=-1)  # (ndof, pieces), into P + 1 phases
    rows = np.arange(ndof)[:, np.newaxis]
    x = breakpoints[:-1][np.newaxis, :] - starts[rows, index]
    jerk = j0[rows, index]
    acc = a0[rows, index] + jerk * x
    vel = v0[rows, index] + a0[rows, index] * x + jerk * x**2 / 2.0
    pos = p0[rows, index] + v0[rows, index] * x + a0[rows, index] * x**2 / 2.0 + jerk * x**3 / 6.0
    coefficients = np.stack([jerk / 6.0, acc / 2.0, vel, pos]).transpose(0, 2, 1)
    return Trajectory(breakpoints, coefficients, info=info)
