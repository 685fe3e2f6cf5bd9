"""Plan many problems at once: arrays of shape ``(B, ndof)``, no Python loop per problem.

Each planner runs the compiled engine over every problem in parallel and returns a
:class:`BatchTrajectory` holding each problem's phase tables; it evaluates all
problems in one call and turns any one of them into the same
:class:`~trajkit.Trajectory` the single-problem planner returns.

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
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from trajkit._validation import (
    FloatArray,
    as_float_array,
    choice,
    finite_array,
    positive_scalar,
)
from trajkit.curve import Curve, check_order
from trajkit.errors import InvalidInputError, TrajkitError
from trajkit.limits import LimitSpec
from trajkit.profiles import engine, limited
from trajkit.profiles._docstrings import with_sections
from trajkit.profiles._phases import PhasePlan
from trajkit.profiles.velocity import velocity_room
from trajkit.renamed import renamed_keywords
from trajkit.trajectory import Trajectory

if TYPE_CHECKING:
    from trajkit.samples import Samples

__all__ = ["BatchTrajectory", "scurve", "trapezoidal", "velocity_change"]


class BatchTrajectory(Curve):
    """``B`` planned problems of ``ndof`` joints each, stored as phase tables.

    Attributes
    ----------
    durations : ndarray, shape (B,)
        Duration of each problem (s).
    info : dict
        Per-problem plan arrays (phase times, peaks, each joint's own minimum,
        limiting joint), each with ``B`` on its first axis.

    Notes
    -----
    Evaluation is that of each problem's :class:`~trajkit.Trajectory` (``batch[i]``):
    ``t`` clamped to ``[0, duration]`` per problem, the exact end state from the
    end on; a joint that finishes before its problem's duration continues at its
    final velocity with zero acceleration.
    """

    __slots__ = ("_info", "_make_info", "_matrix", "_planner", "_result", "durations")

    def __init__(
        self,
        planner: str,
        matrix: FloatArray,
        result: engine.EngineResult,
        info: Callable[[], dict[str, Any]],
    ) -> None:
        self._planner = planner
        self._matrix = matrix  # (B, 11, ndof): the problems as the engine read them
        self._result = result
        self.durations = result.duration
        self._make_info = info
        self._info: dict[str, Any] | None = None

    @property
    def info(self) -> dict[str, Any]:
        """Per-problem plan arrays, ``B`` on the first axis of each."""
        if self._info is None:
            self._info = self._make_info()
        return self._info

    @property
    def plan(self) -> PhasePlan:
        """Every problem's nine phases (start states, durations, accelerations, jerks)."""
        m = self._matrix
        return engine.phase_plan(self._result, m[:, 0], m[:, 2], m[:, 4])

    def __len__(self) -> int:
        return int(self.durations.shape[0])

    @property
    def ndof(self) -> int:
        """Number of joints per problem."""
        return int(self._matrix.shape[-1])

    def __repr__(self) -> str:
        return f"BatchTrajectory(problems={len(self)}, ndof={self.ndof})"

    highest_order = 3

    def evaluate(self, t: ArrayLike, order: int = 0) -> FloatArray:
        """Derivative ``order`` (0-3) of every problem at time(s) ``t``.

        ``t`` scalar gives ``(B, ndof)``; ``t`` of shape ``(m,)`` gives ``(B, m, ndof)``.
        A problem the single planner refuses as too long to keep its short phases in
        absolute time (``batch[i]`` raises :class:`~trajkit.InfeasibleError`) is NaN.
        """
        from trajkit.profiles._kernels.tables import evaluate_batch

        order = check_order(order, self.highest_order)
        times = finite_array("t", t, unit="s")
        if times.ndim > 1:
            raise InvalidInputError(f"t must be a number or a 1-D array, got shape {times.shape}")
        scalar = times.ndim == 0
        grid = np.ascontiguousarray(np.atleast_1d(times), dtype=np.float64)
        out = np.empty((len(self), grid.size, self.ndof))
        r = self._result
        engine.run(
            "evaluate_batch",
            evaluate_batch,
            self._matrix,
            r.t,
            r.u,
            r.second_order,
            self.durations,
            grid,
            int(order),
            out,
        )
        return out[:, 0, :] if scalar else out

    @property
    def end_time(self) -> float:
        """The longest problem's duration (s): every problem holds its end state after its own."""
        return float(self.durations.max()) if self.durations.size else 0.0

    def sample(self, sample_step: float, *, unit: str | None = "rad") -> Samples:
        """Refused, naming the way: Samples hold one problem, ``batch[i].sample(...)``."""
        raise InvalidInputError(
            f"a BatchTrajectory holds {len(self)} problems and Samples one: "
            "sample one of them, batch[i].sample(sample_step)"
        )

    def __getitem__(self, i: int) -> Trajectory:
        """Problem ``i`` as an ordinary Trajectory (the same pieces its single planner builds)."""
        from trajkit.profiles._kernels.tables import PHASES, pieces

        if isinstance(i, bool) or not isinstance(i, int | np.integer):
            raise InvalidInputError(f"index must be an integer, got {i!r}")
        if not -len(self) <= i < len(self):
            raise IndexError(f"problem {i} out of range for {len(self)} problems")
        i = int(i) % len(self)
        m = self._matrix[i]
        r = self._result
        ndof = self.ndof
        breakpoints = np.empty(PHASES * ndof + 2)
        coefficients = np.empty((4, PHASES * ndof + 1, ndof))
        end = np.empty((3, ndof))
        count = engine.run(
            "pieces",
            pieces,
            m[[0, 2, 4]],  # start: q0, v0, a0 (3, ndof)
            m[[1, 3, 5]],  # target: qf, vf, af
            r.t[i],
            r.u[i],
            r.second_order[i],
            float(self.durations[i]),
            breakpoints,
            coefficients,
            end,
        )
        if count < 0:  # the pieces miss a target: as the single planner, refuse them
            raise engine.unresolved(self.info["planner"], float(self.durations[i]),
                                    f" in problem {i}")  # fmt: skip
        info = {key: _item(value, i) for key, value in self.info.items()}
        return Trajectory._trusted(
            breakpoints[: count + 1],
            np.ascontiguousarray(coefficients[:, :count]),
            limited.LazyInfo(lambda: info),
            end,
        )


def _item(value: Any, i: int) -> Any:
    if isinstance(value, np.ndarray) and value.ndim >= 1:
        item = value[i]
        return item.tolist() if isinstance(item, np.ndarray) else item.item()
    return value


_ROWS = ("q0", "qf", "v0", "vf", "a0", "af")
_UNITS = ("rad", "rad", "rad/s", "rad/s", "rad/s^2", "rad/s^2")


def _problem_array(name: str, value: ArrayLike, unit: str) -> FloatArray:
    array = finite_array(name, value, unit=unit)
    if array.ndim > 2:
        raise InvalidInputError(
            f"{name} must have shape (B, ndof) or broadcast to it, got {array.shape}"
        )
    return array


def _limit_rows(name: str, spec: LimitSpec, unit: str) -> tuple[FloatArray, FloatArray]:
    """(lower, upper) of a limit, each broadcastable to ``(B, ndof)``."""
    if spec is None:
        raise InvalidInputError(f"{name} is required ({unit})")
    if isinstance(spec, tuple):
        if len(spec) != 2:
            raise InvalidInputError(f"{name} given as a tuple must be (lower, upper)")
        lower = _problem_array(f"{name} lower bound", spec[0], unit)
        upper = _problem_array(f"{name} upper bound", spec[1], unit)
        if np.any(lower >= 0) or np.any(upper <= 0):
            raise InvalidInputError(
                f"{name} must allow motion both ways: (lower, upper) with lower < 0 < upper "
                f"{unit}, got lower {_extreme(lower, np.max)}, upper {_extreme(upper, np.min)}"
            )
        return lower, upper
    upper = _problem_array(name, spec, unit)
    if np.any(upper <= 0):
        raise InvalidInputError(
            f"{name} must allow motion both ways: a symmetric limit must be > 0 {unit}, got "
            f"{float(upper[upper <= 0].flat[0]):g}"
        )
    return -upper, upper


def _extreme(values: FloatArray, pick: Any) -> str:
    return f"{float(pick(values)):g}"


def _broadcast(names: tuple[str, ...], rows: list[FloatArray]) -> tuple[int, ...]:
    try:
        return np.broadcast_shapes(*(r.shape for r in rows))
    except ValueError:
        shapes = ", ".join(f"{n} {r.shape}" for n, r in zip(names, rows, strict=True) if r.ndim)
        raise InvalidInputError(
            f"{', '.join(names)} must broadcast to one (B, ndof) shape, got {shapes}"
        ) from None


def _matrix(
    planner: str, values: dict[str, ArrayLike], vmax: LimitSpec, amax: LimitSpec, jmax: ArrayLike
) -> FloatArray:
    """Every problem as the engine reads it, ``(B, 11, ndof)``, validated."""
    rows = [_problem_array(n, values[n], u) for n, u in zip(_ROWS, _UNITS, strict=True)]
    rows += [*_limit_rows("vmax", vmax, "rad/s"), *_limit_rows("amax", amax, "rad/s^2")]
    jerk = np.array(as_float_array("jmax", jmax), dtype=float)
    if jerk.ndim > 2:
        raise InvalidInputError(
            f"jmax must have shape (B, ndof) or broadcast to it, got {jerk.shape}"
        )
    rows.append(jerk)
    shape = _broadcast(_ROWS, rows[:6])
    for name, pair in (("vmax", rows[6:8]), ("amax", rows[8:10]), ("jmax", rows[10:])):
        for row in pair:
            try:
                shape = np.broadcast_shapes(shape, row.shape)
            except ValueError:
                raise InvalidInputError(
                    f"{name} must broadcast to the problems' shape {shape}, got {row.shape}"
                ) from None
    if len(shape) != 2 or 0 in shape:
        raise InvalidInputError(
            f"problems must have shape (B, ndof) with B, ndof >= 1, got {shape}"
        )
    m = np.empty((shape[0], 11, shape[1]))
    ok = np.empty(shape[0], np.bool_)
    _assembler()(tuple(np.broadcast_to(row, shape) for row in rows), m, ok)
    bad = np.flatnonzero(~ok)
    if bad.size:
        _explain(planner, m[bad[0]], int(bad[0]))
    return m


def _assembler() -> Any:
    """The kernel that fills and checks a batch, for one signature only.

    Its rows are read-only broadcast views, contiguous or not: the copy compiled
    for strided views takes them all (a contiguous one converts).
    """
    global _assemble
    if _assemble is None:
        from trajkit.profiles._kernels.admissible import assemble_batch

        _assemble = engine.single_signature("assemble_batch", assemble_batch, _assemble_signature)
    return _assemble


def _assemble_signature(numba: Any) -> tuple:
    row = numba.types.Array(numba.float64, 2, "A", readonly=True)
    return (numba.types.UniTuple(row, 11), numba.float64[:, :, ::1], numba.boolean[::1])


_assemble: Any = None


def _explain(planner: str, m: FloatArray, i: int) -> None:
    """Raise the single-problem validators' error for problem ``i``, naming it."""
    try:
        limited.read_matrix(planner, m)
    except TrajkitError as error:
        raise type(error)(f"problem {i}: {error}") from None
    raise AssertionError(f"problem {i} refused by the fast check but not by the validators")


def _sync_codes(sync: object, ndof: int, count: int) -> tuple[np.ndarray, tuple]:
    codes, names = limited.read_sync(sync, ndof)
    # A copy, always: for one problem the broadcast view is already contiguous, and
    # ascontiguousarray would hand the kernel that read-only view, a type it has not
    # been compiled for (a minute's compilation for a one-problem batch).
    return np.broadcast_to(codes, (count, ndof)).copy(), names


def _plan(
    planner: str,
    m: FloatArray,
    sync: object,
    min_duration: ArrayLike | None,
    period: float | None,
    grid: str,
    velocity_only: bool = False,
) -> tuple[engine.EngineResult, tuple, float | None]:
    """Plan the batch ``m`` (its rows as the engine reads them).

    ``velocity_only`` plans to the target velocities; row qf of ``m`` then takes
    each joint's end position.
    """
    count, _, ndof = m.shape
    codes, names = _sync_codes(sync, ndof, count)
    floor = None
    if min_duration is not None:
        floor = finite_array("min_duration", min_duration, unit="s")
        if floor.ndim > 1 or (floor.ndim == 1 and floor.size != count):
            raise InvalidInputError(f"min_duration must be a number or one per problem ({count})")
        if np.any(floor <= 0):
            raise InvalidInputError("min_duration must be > 0 s")
    step = None if period is None else positive_scalar("period", period, unit="s")
    grid = choice("grid", grid, limited.GRIDS)
    control = np.full((count, ndof), int(velocity_only), np.int64)  # 0 position, 1 velocity
    result = engine.solve(
        planner, m, control=control, sync=codes, min_duration=floor, period=step, grid=grid
    )
    return result, names, step


def _common_info(planner: str, result: engine.EngineResult, names: tuple, step: float | None):
    return {
        "planner": planner,
        "continuity": 1 if result.second_order.any() else 2,
        "sync": names[0] if len(set(names)) == 1 else names,
        "period": step,
        "minimum_durations": result.own,
        "limiting_joint": result.limiting,
        "brake_times": result.t[..., :2],
    }


@renamed_keywords(dt="period")
@with_sections
def trapezoidal(
    q0: ArrayLike,
    qf: ArrayLike,
    vmax: LimitSpec,
    amax: LimitSpec,
    *,
    v0: ArrayLike = 0.0,
    vf: ArrayLike = 0.0,
    sync: object = "time",
    min_duration: ArrayLike | None = None,
    period: float | None = None,
    grid: str = "switches",
) -> BatchTrajectory:
    """Time-optimal trapezoid profiles for ``B`` problems at once.

    Same meaning as :func:`trajkit.trapezoidal` (limit mode).
    {batch_arguments}
    With ``period``, ``grid`` puts every switching time (``"switches"``) or only the
    duration (``"duration"``) on the period grid.

    Returns
    -------
    BatchTrajectory
        ``durations`` (B,); ``info`` with ``minimum_durations`` (B, ndof),
        ``limiting_joint`` (B,), ``phase_times`` (B, ndof, 3), ``peak_velocity``
        (B, ndof), ``accelerations`` (B, ndof, 2), ``brake_times`` (B, ndof, 2).
    """
    values = {"q0": q0, "qf": qf, "v0": v0, "vf": vf, "a0": 0.0, "af": 0.0}
    m = _matrix("trapezoidal", values, vmax, amax, np.inf)
    result, names, step = _plan("trapezoidal", m, sync, min_duration, period, grid)

    def info() -> dict[str, Any]:
        from trajkit.profiles._kernels.tables import stretches_batch

        times = np.empty((*result.t.shape[:2], 3))
        accelerations = np.empty((*result.t.shape[:2], 2))
        ok = np.empty(result.t.shape[:2], np.bool_)
        engine.run("stretches_batch", stretches_batch, result.t, result.u, times, accelerations, ok)
        if not ok.all():
            raise AssertionError("an acceleration-limited profile of more than three stretches")
        after_brake = m[:, 2] + result.t[..., 0] * result.u[..., 0]
        return _common_info("trapezoidal", result, names, step) | {
            "phase_times": times,
            "peak_velocity": after_brake + times[..., 0] * accelerations[..., 0],
            "accelerations": accelerations,
        }

    return BatchTrajectory("trapezoidal", m, result, info)


@renamed_keywords(dt="period")
@with_sections
def scurve(
    q0: ArrayLike,
    qf: ArrayLike,
    vmax: LimitSpec,
    amax: LimitSpec,
    jmax: ArrayLike,
    *,
    v0: ArrayLike = 0.0,
    vf: ArrayLike = 0.0,
    a0: ArrayLike = 0.0,
    af: ArrayLike = 0.0,
    sync: object = "time",
    min_duration: ArrayLike | None = None,
    period: float | None = None,
    grid: str = "switches",
) -> BatchTrajectory:
    """Time-optimal jerk-limited profiles for ``B`` problems at once, state to state.

    Same meaning as :func:`trajkit.scurve`.
    {batch_arguments}
    ``grid`` as in :func:`trapezoidal`.

    Returns
    -------
    BatchTrajectory
        ``durations`` (B,); ``info`` with ``minimum_durations`` (B, ndof),
        ``limiting_joint`` (B,), ``phase_times`` and ``jerks`` (B, ndof, 7),
        ``brake_times`` (B, ndof, 2), ``peak_velocity`` (B, ndof).
    """
    values = {"q0": q0, "qf": qf, "v0": v0, "vf": vf, "a0": a0, "af": af}
    m = _matrix("scurve", values, vmax, amax, jmax)
    result, names, step = _plan("scurve", m, sync, min_duration, period, grid)
    return BatchTrajectory("scurve", m, result, _jerk_info("scurve", m, result, names, step))


@renamed_keywords(dt="period")
@with_sections
def velocity_change(
    v0: ArrayLike,
    vf: ArrayLike,
    amax: LimitSpec,
    jmax: ArrayLike,
    *,
    q0: ArrayLike = 0.0,
    a0: ArrayLike = 0.0,
    af: ArrayLike = 0.0,
    sync: object = "time",
    min_duration: ArrayLike | None = None,
    period: float | None = None,
    grid: str = "switches",
) -> BatchTrajectory:
    """Time-optimal changes of velocity for ``B`` problems at once, no position target.

    Same meaning as :func:`trajkit.velocity_change`.
    {batch_arguments}
    The velocity law puts only the duration on a period grid: with ``period``, pass
    ``grid="duration"``.

    Returns
    -------
    BatchTrajectory
        ``durations`` (B,); ``info`` as :func:`scurve`'s, plus ``end_position``
        (B, ndof), where each joint's motion ends (rad).
    """
    rows = [_problem_array(n, x, u) for n, x, u in (
        ("v0", v0, "rad/s"), ("vf", vf, "rad/s"), ("a0", a0, "rad/s^2"), ("af", af, "rad/s^2"),
    )]  # fmt: skip
    jerk = np.array(as_float_array("jmax", jmax), dtype=float)
    try:
        start, end, a_start, a_end, j_max = np.broadcast_arrays(*rows, jerk)
    except ValueError:
        raise InvalidInputError(
            "v0, vf, a0, af and jmax must broadcast to one (B, ndof) shape, got "
            + ", ".join(f"{n} {r.shape}" for n, r in zip(("v0", "vf", "a0", "af", "jmax"),
                                                          (*rows, jerk), strict=True))
        ) from None  # fmt: skip
    wide = velocity_room("velocity_change", start, end, a_start, a_end, j_max)
    values = {"q0": q0, "qf": q0, "v0": v0, "vf": vf, "a0": a0, "af": af}
    m = _matrix("velocity_change", values, (-wide, wide), amax, jmax)
    result, names, step = _plan(
        "velocity_change", m, sync, min_duration, period, grid, velocity_only=True
    )
    jerk_info = _jerk_info("velocity_change", m, result, names, step)
    return BatchTrajectory(
        "velocity_change", m, result, lambda: jerk_info() | {"end_position": m[:, 1].copy()}
    )


def _jerk_info(
    planner: str, m: FloatArray, result: engine.EngineResult, names: tuple, step: float | None
) -> Callable[[], dict[str, Any]]:
    """The ``info`` builder of a batch planned by the jerk-limited law."""

    def info() -> dict[str, Any]:
        from trajkit.profiles._kernels.tables import velocities_at_phases

        v = np.empty(result.t.shape)
        start = np.ascontiguousarray(m[:, [0, 2, 4]])
        engine.run(
            "velocities_at_phases",
            velocities_at_phases,
            start,
            result.t,
            result.u,
            result.second_order,
            v,
        )
        return _common_info(planner, result, names, step) | {
            "phase_times": result.t[..., 2:],
            "jerks": np.where(result.second_order[..., np.newaxis], 0.0, result.u[..., 2:]),
            "peak_velocity": v[..., 2 + 3],
        }

    return info
