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

__all__ = [
    "PhasePlan",
    "final_states",
    "merge_breakpoints",
    "phase_states",
    "plan_info",
    "plan_to_trajectory",
]

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
    end_position, end_velocity : ndarray, shape (..., ndof), optional
        The state the phases are planned to reach (the problem's ``qf``, ``vf``):
        where given, each joint coasts on from exactly it and a trajectory made
        from the plan ends in exactly it, not in the rounding of the phase sums.
    end_acceleration : ndarray, shape (..., ndof), optional
        The same for the acceleration, for plans whose phases end at a known one
        (an S-curve's end at zero acceleration).
    """

    __slots__ = (
        "accelerations", "durations", "end_acceleration", "end_position", "end_velocity",
        "jerks", "position", "velocity",
    )  # fmt: skip

    def __init__(
        self,
        position: FloatArray,
        velocity: FloatArray,
        durations: FloatArray,
        accelerations: FloatArray,
        jerks: FloatArray,
        end_position: FloatArray | None = None,
        end_velocity: FloatArray | None = None,
        end_acceleration: FloatArray | None = None,
    ) -> None:
        self.position = position
        self.velocity = velocity
        self.durations = durations
        self.accelerations = accelerations
        self.jerks = jerks
        self.end_position = end_position
        self.end_velocity = end_velocity
        self.end_acceleration = end_acceleration

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
    period: float | None,
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
        # A trapezoid's acceleration jumps at its switches, an S-curve's jerk.
        "continuity": 1 if planner == "trapezoidal" else 2,
        "sync": sync,
        "period": period,
        "duration": float(duration),
        "minimum_durations": tuple(float(x) for x in own),
        "limiting_joint": None if joint < 0 else joint,
        "phase_times": tuple(tuple(float(x) for x in row) for row in phase_times),
        "peak_velocity": tuple(float(x) for x in peak_velocity),
    }


def plan_to_trajectory(plan: PhasePlan, duration: float, info: dict[str, object]) -> Trajectory:
    """One Trajectory holding every joint's phases (a single problem: no leading axes).

    Joints whose phases end before ``duration`` continue at their final velocity
    with zero acceleration (at rest, if they end at rest). With the plan's
    ``end_position`` and ``end_velocity`` the coast starts from exactly them and the
    trajectory's exact end state is theirs (see :class:`~trajkit.Trajectory`).
    """
    t_start, p_start, v_start = phase_states(plan)
    ndof, count = plan.durations.shape
    # An extra open-ended coasting phase per joint keeps kinematics consistent.
    ends = t_start[:, -1] + plan.durations[:, -1]
    final_p, final_v, end_state = final_states(plan, t_start, p_start, v_start, duration)
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
    if duration == 0.0:
        end_state = None  # a standstill: its one value is its start
    pieces = Trajectory(breakpoints, coefficients, info=info)
    if end_state is None:
        return pieces
    # The phase sums reach the targets; the pieces, on breakpoints rounded at their own
    # size, may not (1e-9 s phases at t = 1000 s): there the polynomial's value stands.
    return pieces.with_boundaries_where_they_agree(end=end_state)


def final_states(
    plan: PhasePlan,
    t_start: FloatArray,
    p_start: FloatArray,
    v_start: FloatArray,
    duration: FloatArray | float,
) -> tuple[FloatArray, FloatArray, FloatArray | None]:
    """Where each joint's phases end, and the exact end state they were planned for.

    Vectorized over leading axes; ``duration`` is the (common) end time of each
    problem, broadcastable to ``(...)``. Returns the position and velocity the final
    coast starts from, shape ``(..., ndof)`` (the plan's targets where the phases reach
    them up to rounding), and the exact end state ``(rows, ..., ndof)`` (row ``i``:
    derivative ``i``, NaN where the polynomial's own value stands), or None when the
    plan names no targets.
    """
    d, a, j = plan.durations, plan.accelerations, plan.jerks
    last = lambda x: x[..., -1]  # noqa: E731
    final_v = last(v_start) + last(a) * last(d) + last(j) * last(d) ** 2 / 2.0
    final_p = (
        last(p_start) + last(v_start) * last(d) + last(a) * last(d) ** 2 / 2.0
        + last(j) * last(d) ** 3 / 6.0
    )  # fmt: skip
    if plan.end_position is None or plan.end_velocity is None:
        return final_p, final_v, None
    target_p = np.broadcast_to(plan.end_position, final_p.shape)
    target_v = np.broadcast_to(plan.end_velocity, final_v.shape)
    # Only where the phases do reach the target (up to rounding); anything else is a
    # planning defect this conversion must not paper over.
    # The size of the terms summed: what the rounding of the sums scales with.
    v_terms = np.abs(v_start).max(axis=-1) + (np.abs(a * d) + np.abs(j * d**2 / 2)).sum(axis=-1)
    p_terms = np.abs(p_start).max(axis=-1) + (
        np.abs(v_start * d) + np.abs(a * d**2 / 2) + np.abs(j * d**3 / 6)
    ).sum(axis=-1)
    reached = _close(final_p, target_p, p_terms) & _close(final_v, target_v, v_terms)
    final_p = np.where(reached, target_p, final_p)
    final_v = np.where(reached, target_v, final_v)
    # A joint that arrives early and coasts on at a speed is elsewhere at the end, if
    # beyond rounding (arriving 1e-14 s early at 1e-3 rad/s moves it by 1e-17 rad).
    ends = last(t_start) + last(d)
    span = np.asarray(duration, dtype=np.float64)[..., np.newaxis]
    with np.errstate(over="ignore", invalid="ignore"):
        drift = final_v * np.maximum(span - ends, 0.0)
        coasting = ~_close(target_p + drift, target_p, p_terms)
    rows = [np.where(reached & ~coasting, final_p, np.nan), np.where(reached, final_v, np.nan)]
    if plan.end_acceleration is not None:
        final_a = last(a) + last(j) * last(d)
        target_a = np.broadcast_to(plan.end_acceleration, final_a.shape)
        a_terms = np.abs(a).max(axis=-1) + np.abs(j * d).sum(axis=-1)
        # An early joint coasts at zero acceleration: the polynomial's 0 is exact.
        good = reached & _close(final_a, target_a, a_terms)
        rows.append(np.where(good, target_a, np.nan))
    return final_p, final_v, np.stack(rows)


def _close(value: FloatArray, target: FloatArray, scale: FloatArray) -> FloatArray:
    """``value`` equals ``target`` up to the rounding of sums of terms of size ``scale``."""
    return np.abs(value - target) <= 1e-9 * (1.0 + np.abs(target) + scale)
