"""Plan many problems at once: arrays of shape ``(B, ndof)``, no Python loop per problem.

Each planner returns a :class:`BatchTrajectory` holding every problem's phases;
it evaluates all problems in one vectorized call and turns any one of them into an
ordinary :class:`~trajkit.Trajectory`.

Examples
--------
>>> import numpy as np, trajkit as tk
>>> rng = np.random.default_rng(0)
>>> q0, qf = rng.uniform(-1, 1, (1000, 6)), rng.uniform(-1, 1, (1000, 6))
>>> plans = tk.batch.trapezoidal(q0, qf, vmax=1.0, amax=2.0)
>>> plans.durations.shape, plans.position(0.5).shape
((1000,), (1000, 6))
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from trajkit._validation import FloatArray, finite_array, positive_scalar
from trajkit.errors import InfeasibleError, InvalidInputError
from trajkit.limits import LimitSpec
from trajkit.profiles import _trapezoid_math as math
from trajkit.profiles._phases import PhasePlan, final_states, phase_states, plan_to_trajectory
from trajkit.profiles.scurve import SCurveSolution, quantize_scurve, solve_scurve
from trajkit.profiles.scurve import rest_plan as scurve_rest_plan
from trajkit.profiles.trapezoidal import (
    Sync,
    TrapezoidSolution,
    _read_sync,
    quantize_trapezoid,
    solve_trapezoid,
)
from trajkit.trajectory import Trajectory

__all__ = ["BatchTrajectory", "scurve", "trapezoidal"]


class BatchTrajectory:
    """``B`` planned problems of ``ndof`` joints each, stored as phase plans.

    Attributes
    ----------
    durations : ndarray, shape (B,)
        Duration of each problem (s).
    info : dict
        Per-problem plan arrays (phase times, peaks, each joint's own minimum,
        limiting joint), each with ``B`` on its first axis.

    Notes
    -----
    Evaluation clamps ``t`` to ``[0, duration]`` per problem, like
    :class:`~trajkit.Trajectory`; a joint that finishes before its problem's
    duration continues at its final velocity with zero acceleration.
    """

    __slots__ = (
        "_end_state", "_info", "_make_info", "_make_plan", "_plan", "_tables", "durations"
    )  # fmt: skip

    def __init__(
        self,
        durations: FloatArray,
        plan: Callable[[], PhasePlan],
        info: Callable[[], dict[str, Any]],
    ) -> None:
        # Planning is the hot path: phase tables and info are built on first use.
        self.durations = durations
        self._make_plan, self._make_info = plan, info
        self._plan: PhasePlan | None = None
        self._info: dict[str, Any] | None = None
        self._tables: tuple[FloatArray, ...] | None = None
        self._end_state: FloatArray | None = None  # (rows, B, ndof), NaN: the polynomial's

    @property
    def plan(self) -> PhasePlan:
        """Every problem's phases (start states, durations, accelerations, jerks)."""
        if self._plan is None:
            self._plan = self._make_plan()
        return self._plan

    @property
    def info(self) -> dict[str, Any]:
        """Per-problem plan arrays, ``B`` on the first axis of each."""
        if self._info is None:
            self._info = self._make_info()
        return self._info

    def _phase_tables(self) -> tuple[FloatArray, ...]:
        """Start time and state of every phase, plus a final open-ended coast."""
        if self._tables is None:
            plan = self.plan
            t_start, p_start, v_start = phase_states(plan)
            d, a, j = plan.durations, plan.accelerations, plan.jerks
            last_t = t_start[..., -1] + d[..., -1]
            # The final coast starts from the targets where the phases reach them, as
            # in problem i's own Trajectory (batch[i]); the end state holds after.
            last_p, last_v, end_state = final_states(plan, t_start, p_start, v_start,
                                                     self.durations)  # fmt: skip
            self._end_state = end_state
            extend = lambda x, y: np.concatenate([x, y[..., np.newaxis]], axis=-1)  # noqa: E731
            zero = np.zeros_like(last_t)
            self._tables = (
                extend(t_start, last_t),
                extend(p_start, last_p),
                extend(v_start, last_v),
                extend(a, zero),
                extend(j, zero),
            )
        return self._tables

    def __len__(self) -> int:
        return int(self.durations.shape[0])

    @property
    def ndof(self) -> int:
        """Number of joints per problem."""
        return int(self.plan.position.shape[-1])

    def __repr__(self) -> str:
        return f"BatchTrajectory(problems={len(self)}, ndof={self.ndof})"

    def evaluate(self, t: ArrayLike, order: int = 0) -> FloatArray:
        """Derivative ``order`` (0-3) of every problem at time(s) ``t``.

        ``t`` scalar gives ``(B, ndof)``; ``t`` of shape ``(m,)`` gives ``(B, m, ndof)``.
        """
        if isinstance(order, bool) or order not in (0, 1, 2, 3):
            raise InvalidInputError(f"order must be 0, 1, 2 or 3, got {order!r}")
        times = finite_array("t", t, unit="s")
        if times.ndim > 1:
            raise InvalidInputError(f"t must be a number or a 1-D array, got shape {times.shape}")
        scalar = times.ndim == 0
        m = np.atleast_1d(times)  # (m,)
        clamped = np.clip(m[np.newaxis, :], 0.0, self.durations[:, np.newaxis])  # (B, m)
        starts, *states = self._phase_tables()
        begun = starts[:, :, np.newaxis, :] <= clamped[:, np.newaxis, :, np.newaxis]
        # Like Trajectory: at the very end the last phase holds; the open-ended coast
        # of a joint that arrived early starts right at its arrival.
        at_end = (clamped >= self.durations[:, np.newaxis])[:, np.newaxis, :]
        begun[..., -1] &= (starts[:, :, np.newaxis, -1] < clamped[:, np.newaxis, :]) | ~at_end
        # Zero-length phases hold no time: never the phase a time falls in (a pure coast's
        # empty fall phase once lent it its acceleration at the end). The final coast
        # serves when nothing else has begun (a standstill).
        begun &= np.concatenate(
            [self.plan.durations > 0.0, np.ones((*starts.shape[:2], 1), bool)], axis=-1
        )[:, :, np.newaxis, :]
        begun[..., -1] |= ~begun[..., :-1].any(axis=-1)
        # The last non-empty phase begun wins.
        index = (begun.shape[-1] - 1) - np.argmax(begun[..., ::-1], axis=-1)  # (B, ndof, m)
        take = lambda x: np.take_along_axis(x, index, axis=-1)  # noqa: E731
        x = clamped[:, np.newaxis, :] - take(starts)
        p, v, a, j = (take(q) for q in states)
        if order == 0:
            value = p + v * x + a * x**2 / 2 + j * x**3 / 6
        elif order == 1:
            value = v + a * x + j * x**2 / 2
        elif order == 2:
            value = a + j * x
        else:
            value = j + 0 * x
        value = np.moveaxis(value, 1, -1)  # (B, m, ndof)
        exact = self._end_state
        if exact is not None and order < exact.shape[0]:
            # From the end time on, the exact end state each problem was planned for
            # (as Trajectory gives it), not the phases' rounded sums.
            known = exact[order][:, np.newaxis, :]  # (B, 1, ndof)
            after = (m[np.newaxis, :] >= self.durations[:, np.newaxis])[..., np.newaxis]
            value = np.where(after & ~np.isnan(known), known, value)
        return value[:, 0, :] if scalar else value

    def position(self, t: ArrayLike) -> FloatArray:
        """Positions of every problem at ``t``."""
        return self.evaluate(t, 0)

    def velocity(self, t: ArrayLike) -> FloatArray:
        """Velocities of every problem at ``t``."""
        return self.evaluate(t, 1)

    def acceleration(self, t: ArrayLike) -> FloatArray:
        """Accelerations of every problem at ``t``."""
        return self.evaluate(t, 2)

    def jerk(self, t: ArrayLike) -> FloatArray:
        """Jerks of every problem at ``t`` (zero between switches of a trapezoid)."""
        return self.evaluate(t, 3)

    def __getitem__(self, i: int) -> Trajectory:
        """Problem ``i`` as an ordinary Trajectory."""
        if isinstance(i, bool) or not isinstance(i, int | np.integer):
            raise InvalidInputError(f"index must be an integer, got {i!r}")
        if not -len(self) <= i < len(self):
            raise IndexError(f"problem {i} out of range for {len(self)} problems")
        plan = self.plan
        single = PhasePlan(
            plan.position[i],
            plan.velocity[i],
            plan.durations[i],
            plan.accelerations[i],
            plan.jerks[i],
            None if plan.end_position is None else plan.end_position[i],
            None if plan.end_velocity is None else plan.end_velocity[i],
            None if plan.end_acceleration is None else plan.end_acceleration[i],
        )
        info = {key: _item(value, i) for key, value in self.info.items()}
        return plan_to_trajectory(single, float(self.durations[i]), info)


def _item(value: Any, i: int) -> Any:
    if isinstance(value, np.ndarray) and value.ndim >= 1:
        item = value[i]
        return item.tolist() if isinstance(item, np.ndarray) else item.item()
    return value


def _problem_array(name: str, value: ArrayLike, unit: str) -> FloatArray:
    array = finite_array(name, value, unit=unit)
    if array.ndim > 2:
        raise InvalidInputError(
            f"{name} must have shape (B, ndof) or broadcast to it, got {array.shape}"
        )
    return array


def _limit_pair(
    name: str, spec: LimitSpec, shape: tuple[int, int], unit: str
) -> tuple[FloatArray, FloatArray]:
    """``(upper, -lower)`` magnitudes, broadcastable to ``(B, ndof)`` (not copied)."""
    if spec is None:
        raise InvalidInputError(f"{name} is required ({unit})")
    if isinstance(spec, tuple):
        if len(spec) != 2:
            raise InvalidInputError(f"{name} given as a tuple must be (lower, upper)")
        upper = _problem_array(f"{name} upper bound", spec[1], unit)
        negative = -_problem_array(f"{name} lower bound", spec[0], unit)
    else:
        upper = _problem_array(name, spec, unit)
        negative = upper  # symmetric: the same object, which the planners detect
    for value in (upper, negative):
        try:
            np.broadcast_shapes(value.shape, shape)
        except ValueError:
            raise InvalidInputError(
                f"{name} must broadcast to the problems' shape {shape}, got {value.shape}"
            ) from None
    if np.any(upper <= 0) or np.any(negative <= 0):
        raise InvalidInputError(f"{name} must allow motion both ways: lower < 0 < upper ({unit})")
    return upper, negative


def _problems(q0: ArrayLike, qf: ArrayLike, v0: ArrayLike, vf: ArrayLike) -> tuple[FloatArray, ...]:
    """Validated problem arrays; boundary velocities stay unbroadcast (often scalar 0)."""
    arrays = [
        _problem_array(n, v, u)
        for n, v, u in (
            ("q0", q0, "rad"), ("qf", qf, "rad"), ("v0", v0, "rad/s"), ("vf", vf, "rad/s"),
        )
    ]  # fmt: skip
    try:
        shape = np.broadcast_shapes(*(a.shape for a in arrays))
    except ValueError:
        raise InvalidInputError(
            "q0, qf, v0, vf must broadcast to one (B, ndof) shape, got "
            + ", ".join(str(a.shape) for a in arrays)
        ) from None
    if len(shape) != 2 or 0 in shape:
        raise InvalidInputError(
            f"problems must have shape (B, ndof) with B, ndof >= 1, got {shape}"
        )
    start, end, start_v, end_v = arrays
    return np.broadcast_to(start, shape), np.broadcast_to(end, shape), start_v, end_v


def _refuse_fast_boundaries(
    start_v: FloatArray,
    end_v: FloatArray,
    vpos: FloatArray,
    vneg: FloatArray,
    shape: tuple[int, int],
    label: str,
) -> None:
    """Refuse a boundary velocity beyond its limit, naming the problem and joint."""
    for name, values in (("v0", start_v), ("vf", end_v)):
        if not values.any():
            continue  # at rest: within any limit (cheap test first: the common case)
        beyond = np.broadcast_to((values > vpos) | (values < -vneg), shape)
        if beyond.any():
            b, j = np.argwhere(beyond)[0]
            value = np.broadcast_to(values, shape)[b, j]
            raise InfeasibleError(
                f"{name}={value:.6g} rad/s is beyond {label} (problem {b}, joint {j + 1})"
            )


def _args(start, end, start_v, end_v, vpos, vneg, apos, aneg):
    shape = start.shape
    # Every argument (B, ndof): the general solver concatenates them, so shared scalar,
    # per-joint or tuple limits must be spread over the problems first.
    return tuple(np.broadcast_to(x, shape) for x in
                 (end - start, start_v, end_v, vpos, vneg, apos, aneg))  # fmt: skip


def _rest_to_rest(
    start: FloatArray,
    end: FloatArray,
    vpos: FloatArray,
    vneg: FloatArray,
    apos: FloatArray,
    aneg: FloatArray,
    sync: Sync,
) -> TrapezoidSolution:
    """The common case, in closed form, computed joint-major.

    numpy is several times faster on ``(ndof, B)`` arrays than on ``(B, ndof)``
    ones: its inner loops then run over the problems instead of over six joints,
    and the reduction over joints becomes elementwise.
    """
    distance = np.ascontiguousarray((end - start).T)
    joint_major = [
        limit if limit.ndim < 2 else np.ascontiguousarray(limit.T)
        for limit in (vpos, vneg, apos, aneg)
    ]
    # (ndof,) limits become (ndof, 1); keep symmetric limits the same object.
    column = {id(x): (x[:, np.newaxis] if x.ndim == 1 else x) for x in joint_major}
    limits = [column[id(x)] for x in joint_major]
    own, phases_at = math.rest_plan(distance, *limits)
    T = own.max(axis=0)
    target = own if sync is None else T
    phases = phases_at(target)
    return TrapezoidSolution(None, None, None, T, own.T, None, phases=phases, joint_major=True)


def trapezoidal(
    q0: ArrayLike,
    qf: ArrayLike,
    vmax: LimitSpec,
    amax: LimitSpec,
    *,
    v0: ArrayLike = 0.0,
    vf: ArrayLike = 0.0,
    sync: Sync = "time",
    dt: float | None = None,
) -> BatchTrajectory:
    """Time-optimal trapezoid profiles for ``B`` problems at once.

    Same meaning as :func:`trajkit.trapezoidal` (limit mode), with every argument
    of shape ``(B, ndof)`` or broadcastable to it (limits may be per joint
    ``(ndof,)``, per problem, or a ``(lower, upper)`` tuple of such arrays).

    Returns
    -------
    BatchTrajectory
        ``durations`` (B,); ``info`` with ``minimum_durations`` (B, ndof),
        ``limiting_joint`` (B,; -1 under phase sync), ``phase_times`` (B, ndof, 3),
        ``peak_velocity`` (B, ndof), ``accelerations`` (B, ndof, 2).
    """
    start, end, start_v, end_v = _problems(q0, qf, v0, vf)
    shape = start.shape
    vpos, vneg = _limit_pair("vmax", vmax, shape, "rad/s")
    apos, aneg = _limit_pair("amax", amax, shape, "rad/s^2")
    sync = _read_sync(sync)
    _refuse_fast_boundaries(start_v, end_v, vpos, vneg, shape, "the velocity limit")
    if sync != "phase" and not start_v.any() and not end_v.any():
        solution = _rest_to_rest(start, end, vpos, vneg, apos, aneg, sync)
    else:
        solution = solve_trapezoid(
            *_args(start, end, start_v, end_v, vpos, vneg, apos, aneg), sync=sync
        )
    start_v, end_v = np.broadcast_to(start_v, shape), np.broadcast_to(end_v, shape)
    args = _args(start, end, start_v, end_v, vpos, vneg, apos, aneg)
    step = None
    if dt is not None:
        step = positive_scalar("dt", dt, unit="s")
        solution = quantize_trapezoid(solution, step, args, sync)
    durations = np.broadcast_to(solution.duration, shape[:1]).copy()

    def plan() -> PhasePlan:
        return PhasePlan(
            np.array(start), np.array(start_v), solution.times, solution.accelerations,
            np.zeros_like(solution.times), np.array(end), np.array(end_v),
        )  # fmt: skip

    def info() -> dict[str, Any]:
        return {
            "planner": "trapezoidal",
            "continuity": 1,
            "sync": sync,
            "dt": step,
            "minimum_durations": solution.own,
            "limiting_joint": solution.limiting,
            "phase_times": solution.times,
            "peak_velocity": solution.peak_velocity,
            "accelerations": solution.accelerations[..., [0, 2]],
        }

    return BatchTrajectory(durations, plan, info)


def scurve(
    q0: ArrayLike,
    qf: ArrayLike,
    vmax: ArrayLike,
    amax: ArrayLike,
    jmax: ArrayLike,
    *,
    v0: ArrayLike = 0.0,
    vf: ArrayLike = 0.0,
    sync: Sync = "time",
    dt: float | None = None,
) -> BatchTrajectory:
    """Time-optimal jerk-limited (double-S) profiles for ``B`` problems at once.

    Same meaning as :func:`trajkit.scurve`, with every argument of shape
    ``(B, ndof)`` or broadcastable to it; limits are symmetric magnitudes.

    Returns
    -------
    BatchTrajectory
        ``durations`` (B,); ``info`` with ``minimum_durations`` (B, ndof),
        ``limiting_joint`` (B,), ``phase_times`` and ``jerks`` (B, ndof, 7),
        ``peak_velocity`` (B, ndof).
    """
    start, end, start_v, end_v = _problems(q0, qf, v0, vf)
    shape = start.shape
    limits = []
    for name, value, unit in (
        ("vmax", vmax, "rad/s"),
        ("amax", amax, "rad/s^2"),
        ("jmax", jmax, "rad/s^3"),
    ):
        if isinstance(value, tuple):
            raise InvalidInputError(
                f"{name}: S-curve limits are symmetric magnitudes, not (lower, upper)"
            )
        upper, _ = _limit_pair(name, value, shape, unit)
        limits.append(upper)
    V, A, J = limits
    sync = _read_sync(sync)
    _refuse_fast_boundaries(start_v, end_v, V, V, shape, "vmax")
    step = None if dt is None else positive_scalar("dt", dt, unit="s")
    args = (end - start, np.broadcast_to(start_v, shape), np.broadcast_to(end_v, shape), V, A, J)
    if sync != "phase" and step is None and not start_v.any() and not end_v.any():
        solution = _scurve_rest_to_rest(start, end, V, A, J, sync)
    else:
        solution = solve_scurve(*args, sync=sync)
        if step is not None:
            solution = quantize_scurve(solution, step, args, sync)
    durations = np.broadcast_to(solution.duration, shape[:1]).copy()

    def plan() -> PhasePlan:
        return PhasePlan(
            np.array(start), np.array(np.broadcast_to(start_v, shape)), solution.durations,
            solution.accelerations, solution.jerks, np.array(end),
            np.array(np.broadcast_to(end_v, shape)), np.zeros(shape),
        )  # fmt: skip

    def info() -> dict[str, Any]:
        return {
            "planner": "scurve",
            "continuity": 2,
            "sync": sync,
            "dt": step,
            "minimum_durations": solution.own,
            "limiting_joint": solution.limiting,
            "phase_times": solution.durations,
            "jerks": solution.jerks,
            "peak_velocity": solution.peak_velocity,
        }

    return BatchTrajectory(durations, plan, info)


def _scurve_rest_to_rest(
    start: FloatArray, end: FloatArray, V: FloatArray, A: FloatArray, J: FloatArray, sync: Sync
) -> SCurveSolution:
    """Closed forms, joint-major (see :func:`_rest_to_rest`); phases built lazily."""
    distance = np.ascontiguousarray((end - start).T)
    columns = [x[:, np.newaxis] if x.ndim == 1 else np.ascontiguousarray(x.T) for x in (V, A, J)]
    own, phases_at = scurve_rest_plan(distance, *columns)
    T = own.max(axis=0)
    target = own if sync is None else T

    profile = phases_at(target)  # the whole plan: four numbers per joint

    def make() -> tuple[FloatArray, ...]:
        durations, jerks, peak, accelerations = profile.phases()
        swap = lambda x: np.swapaxes(x, 0, 1)  # noqa: E731
        return swap(durations), swap(jerks), peak.T, swap(accelerations)

    limiting = np.argmax(own, axis=0)
    return SCurveSolution(None, None, None, T, own.T, limiting, make=make)
