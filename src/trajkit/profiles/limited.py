"""State-to-state profiles under velocity, acceleration and jerk limits, through the engine.

The shared front end of :func:`trajkit.scurve` and :func:`trajkit.trapezoidal`
(and of their batch versions): reads and checks the problem, runs the compiled
engine (:mod:`trajkit.profiles.engine`), and builds the
:class:`~trajkit.Trajectory` and its ``info``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from trajkit._validation import (
    FloatArray,
    as_float_array,
    choice,
    count_dof,
    finite_result,
    joint_vector,
    positive_scalar,
)
from trajkit.errors import InfeasibleError, InvalidInputError
from trajkit.limits import LimitSpec, parse_bounds
from trajkit.profiles import engine
from trajkit.profiles._phases import PhasePlan
from trajkit.tolerances import ROUNDING_RTOL
from trajkit.trajectory import Trajectory

__all__ = [
    "Problem",
    "quick_trajectory",
    "read_matrix",
    "read_problem",
    "read_sync",
    "solve",
    "to_trajectory",
    "trajectory",
]

#: The sync modes; ``"none"`` is ``None`` spelled as files and the command line spell it.
SYNC_NAMES = ("time", "phase", "time_if_necessary", "none", None)
GRIDS = ("switches", "duration")


@dataclass(frozen=True)
class Problem:
    """One validated problem: the (11, ndof) matrix the engine reads, and sync codes.

    Rows (see :mod:`trajkit.profiles._kernels.admissible`): q0, qf, v0, vf, a0, af,
    v_min, v_max, a_min, a_max, j_max; the named attributes are views of them.
    """

    matrix: FloatArray
    sync: np.ndarray  # int64 codes per joint
    sync_names: tuple[str | None, ...]

    @property
    def ndof(self) -> int:
        """Number of joints."""
        return int(self.matrix.shape[1])

    def __getattr__(self, name: str) -> FloatArray:
        try:
            return self.matrix[_ROWS.index(name)]
        except ValueError:
            raise AttributeError(name) from None


_ROWS = ("q0", "qf", "v0", "vf", "a0", "af", "v_min", "v_max", "a_min", "a_max", "j_max")


def read_bounds(name: str, spec: LimitSpec, ndof: int, unit: str) -> tuple[FloatArray, FloatArray]:
    """``(lower, upper)`` of a symmetric or ``(lower, upper)`` limit: finite, lower < 0 < upper."""
    bounds = parse_bounds(name, spec, quantity="velocity")
    if bounds is None:
        raise InvalidInputError(f"{name} is required ({unit})")
    lower, upper = bounds.for_ndof(name, ndof)
    if np.any(lower >= 0) or np.any(upper <= 0):
        raise InvalidInputError(f"{name} must allow motion both ways: lower < 0 < upper ({unit})")
    return np.array(lower, dtype=float), np.array(upper, dtype=float)


def read_jerk(jmax: ArrayLike, ndof: int) -> FloatArray:
    """Jerk limits per joint, each > 0; ``inf`` means acceleration-limited (no jerk limit)."""
    value = np.array(as_float_array("jmax", jmax), dtype=float)
    if value.ndim == 0:
        value = np.full(ndof, float(value))
    if value.shape != (ndof,):
        raise InvalidInputError(
            f"jmax must be a number or {ndof} numbers (one per joint), got shape {value.shape}"
        )
    bad = np.flatnonzero(~(value > 0))  # NaN too
    if bad.size:
        raise InvalidInputError(
            f"jmax must be > 0 (inf for no jerk limit) for every joint, got {value[bad[0]]:g} "
            f"rad/s^3 for joint {bad[0] + 1}"
        )
    return value


def read_sync(sync: object, ndof: int) -> tuple[np.ndarray, tuple[str | None, ...]]:
    """Sync codes per joint from one mode for all or one per joint.

    Modes: ``"time"``, ``"phase"``, ``"time_if_necessary"`` or ``None`` (left out
    of synchronization; ``"none"`` is the same).
    """
    if isinstance(sync, str) or sync is None:
        names = (choice("sync", sync, SYNC_NAMES),) * ndof
    elif isinstance(sync, Sequence) and not isinstance(sync, bytes):
        if len(sync) != ndof:
            raise InvalidInputError(
                f"sync given per joint must have {ndof} entries (one per joint), got {len(sync)}"
            )
        names = tuple(choice(f"sync[{i}]", s, SYNC_NAMES) for i, s in enumerate(sync))
    else:
        raise InvalidInputError(
            f"sync must be one of {SYNC_NAMES} or a sequence of them per joint, got {sync!r}"
        )
    names = tuple(None if name == "none" else name for name in names)
    return np.array([engine.SYNC_MODES[n] for n in names], dtype=np.int64), names


def _v_at_a_zero(v: FloatArray, a: FloatArray, j: FloatArray) -> FloatArray:
    """The velocity reached when an acceleration ``a`` is brought to zero at jerk ``j``."""
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(np.isinf(j), v, v + a * np.abs(a) / (2.0 * j))


def _check_target(p: Problem) -> None:
    """Refuse a target state beyond the limits, or one that cannot be arrived at."""
    for name, value, low, high, unit, quantity in (
        ("vf", p.vf, p.v_min, p.v_max, "rad/s", "velocity"),
        ("af", p.af, p.a_min, p.a_max, "rad/s^2", "acceleration"),
    ):
        bad = np.flatnonzero((value > high) | (value < low))
        if bad.size:
            j = bad[0]
            bound = high[j] if value[j] > 0 else low[j]
            raise InfeasibleError(
                f"{name}={value[j]:.6g} {unit} is beyond the {quantity} limit {bound:.6g} {unit} "
                f"(joint {j + 1})"
            )
    # Arriving while decelerating means having been faster just before.
    before = p.vf - p.af * np.abs(p.af) / np.where(np.isinf(p.j_max), np.inf, 2.0 * p.j_max)
    bad = np.flatnonzero(
        (before > p.v_max * (1 + ROUNDING_RTOL)) | (before < p.v_min * (1 + ROUNDING_RTOL))
    )
    if bad.size:
        j = bad[0]
        raise InfeasibleError(
            f"vf={p.vf[j]:.6g} rad/s with af={p.af[j]:.6g} rad/s^2 cannot be arrived at: the "
            f"velocity just before would be {before[j]:.6g} rad/s, beyond the limits "
            f"({p.v_min[j]:.6g}, {p.v_max[j]:.6g}) with jmax={p.j_max[j]:.6g} rad/s^3 "
            f"(joint {j + 1})"
        )


_FAST_SCALARS = (float, int, np.float64)
_FLOAT64 = np.dtype(np.float64)


def _fast_row(value: object, ndof: int) -> FloatArray | None:
    """``value`` as a float64 vector of the problem's rows if it is plainly numbers.

    A number becomes a (cached, only ever read) vector of ``ndof`` copies, a list
    or tuple of numbers a new vector; a float64 array is taken as it is (its
    length is checked where it is read). Bools, strings, NaN keys and other
    dtypes are left to the validators (None).
    """
    kind = type(value)
    if kind is np.ndarray:
        return value if value.dtype is _FLOAT64 else None  # type: ignore[union-attr,return-value]
    if kind in _FAST_SCALARS:
        key = (value, ndof)
        row = _CONSTANT_ROWS.get(key)
        if row is None:
            if value != value or len(_CONSTANT_ROWS) >= 4096:  # NaN, or a flood of values
                return None
            try:
                row = _CONSTANT_ROWS[key] = np.full(ndof, float(value))  # type: ignore[arg-type]
            except OverflowError:  # a Python int beyond float64
                return None
        return row
    if kind is list or kind is tuple:
        for x in value:  # type: ignore[union-attr]
            if type(x) not in _FAST_SCALARS:
                return None
        try:
            return np.array(value, dtype=np.float64)
        except OverflowError:
            return None
    return None


_CONSTANT_ROWS: dict[tuple[object, int], FloatArray] = {}


def _ndof_of(*values: object) -> int | None:
    for value in values:
        kind = type(value)
        if kind is np.ndarray:
            return value.shape[0] if value.ndim == 1 else None  # type: ignore[union-attr]
        if kind is list:
            return len(value)  # type: ignore[arg-type]
    return 1


def _plain_rows(q0, qf, vmax, amax, jmax, v0, vf, a0, af) -> tuple[int, list, int] | None:
    """The problem matrix's rows if every argument is plainly numbers, else None.

    Returns ``(ndof, rows, negate)``: symmetric limits give their magnitude for the
    lower bound too, flagged in ``negate`` (the kernels' ``NEGATE_*`` bits).
    """
    ndof = _ndof_of(q0, qf, v0, vf, a0, af, jmax, vmax, amax)
    if ndof is None or ndof == 0:
        return None
    rows = []
    for value in (q0, qf, v0, vf, a0, af):
        row = _fast_row(value, ndof)
        if row is None:
            return None
        rows.append(row)
    negate = 0
    for spec, bit in ((vmax, 1), (amax, 2)):
        if type(spec) is tuple and len(spec) == 2:
            pair = [_fast_row(spec[0], ndof), _fast_row(spec[1], ndof)]
        else:
            pair = [_fast_row(spec, ndof)] * 2
            negate |= bit
        if pair[0] is None or pair[1] is None:
            return None
        rows += pair
    row = _fast_row(jmax, ndof)
    if row is None:
        return None
    rows.append(row)
    return ndof, rows, negate


def _matrix(rows: list, ndof: int) -> FloatArray | None:
    try:
        m = np.array(rows, dtype=np.float64)
    except (OverflowError, TypeError, ValueError):
        return None  # (a Python int beyond float64, ...) the validators explain
    return m if m.shape == (len(_ROWS), ndof) else None


def _sync_codes(sync: object, ndof: int) -> tuple[NDArray[np.int64], tuple[str | None, ...]] | None:
    """Rows control (position), sync and enabled for one sync mode, cached; None if odd."""
    if not (isinstance(sync, str) or sync is None):
        return None
    key = (sync, ndof)
    codes = _SYNC_CACHE.get(key)
    if codes is None:
        if sync not in SYNC_NAMES:
            return None
        packed = np.zeros((3, ndof), np.int64)
        name = None if sync == "none" else sync
        packed[1] = engine.SYNC_MODES[name]
        packed[2] = 1
        codes = _SYNC_CACHE[key] = (packed, (name,) * ndof)
    return codes


_SYNC_CACHE: dict[tuple[object, int], tuple[NDArray[np.int64], tuple[str | None, ...]]] = {}


def _read_fast(q0, qf, vmax, amax, jmax, v0, vf, a0, af, sync) -> Problem | None:
    """The problem, if every argument is plainly well formed and admissible; else None."""
    from trajkit.profiles._kernels.admissible import admissible

    plain = _plain_rows(q0, qf, vmax, amax, jmax, v0, vf, a0, af)
    if plain is None:
        return None
    ndof, rows, negate = plain
    codes = _sync_codes(sync, ndof)
    m = _matrix(rows, ndof)
    if codes is None or m is None:
        return None
    if negate & 1:
        m[6] *= -1.0
    if negate & 2:
        m[8] *= -1.0
    if not engine.run("admissible", admissible, m):
        return None
    return Problem(m, codes[0][1], codes[1])


def _run_quick(*args: object) -> tuple:
    """Call the kernels' ``quick``, compiled for contiguous float64 vectors only."""
    global _quick
    if _quick is None:
        _quick = engine.single_signature("quick", engine.kernels().quick, _quick_signature)
    return _quick(*args)


def _quick_signature(numba: Any) -> tuple:
    vector = numba.float64[::1]
    return (vector,) * 11 + (numba.int64, numba.int64[:, ::1])


_quick: Any = None  # the compiled kernel, once it has run


def quick_trajectory(
    planner: str,
    q0: ArrayLike,
    qf: ArrayLike,
    vmax: LimitSpec,
    amax: LimitSpec,
    jmax: ArrayLike,
    *,
    v0: ArrayLike,
    vf: ArrayLike,
    a0: ArrayLike,
    af: ArrayLike,
    sync: object,
    info: Callable[[dict[str, Any], PhasePlan], dict[str, Any]] | None = None,
) -> Trajectory | None:
    """The planned Trajectory by the shortest road, or None to take the full one.

    For plainly numeric arguments and default options (no duration, no ``period``):
    one compiled call checks, plans and builds the pieces; ``info`` and the
    engine's result are unpacked only when read. None where anything is unusual
    (malformed or inadmissible input, a failed plan): the full road then names
    the problem or plans it.
    """
    plain = _plain_rows(q0, qf, vmax, amax, jmax, v0, vf, a0, af)
    if plain is None:
        return None
    ndof, rows, negate = plain
    codes = _sync_codes(sync, ndof)
    if codes is None:
        return None
    try:
        status, _, breakpoints, coefficients, end, flat = _run_quick(*rows, negate, codes[0])
    except TypeError:  # a vector the compiled kernel does not take: the full road copies it
        return None
    if status != engine.STATUS_OK:
        return None

    def build() -> dict[str, Any]:
        m, result = engine.unpack(flat, ndof)
        return _info(planner, Problem(m, codes[0][1], codes[1]), result, None, info)

    return Trajectory._trusted(breakpoints, coefficients, LazyInfo(build), end)


def read_problem(
    planner: str,
    q0: ArrayLike,
    qf: ArrayLike,
    vmax: LimitSpec,
    amax: LimitSpec,
    jmax: ArrayLike,
    *,
    v0: ArrayLike,
    vf: ArrayLike,
    a0: ArrayLike,
    af: ArrayLike,
    sync: object,
) -> Problem:
    """Validate one problem (per-joint vectors; limits symmetric, per joint or tuples)."""
    fast = _read_fast(q0, qf, vmax, amax, jmax, v0, vf, a0, af, sync)
    if fast is not None:
        return fast
    ndof = count_dof(q0=q0, qf=qf, v0=v0, vf=vf, a0=a0, af=af)
    limits = (("vmax", vmax), ("amax", amax), ("jmax", jmax))
    missing = [name for name, spec in limits if spec is None]
    if missing:
        raise InvalidInputError(
            f"{' and '.join(missing)} {'is' if len(missing) == 1 else 'are'} required: "
            f"{planner} needs vmax, amax and jmax (a number, one per joint or a "
            "(lower, upper) tuple each)"
        )
    for name, spec in limits:
        if not isinstance(spec, tuple):
            ndof = max(ndof, count_dof(q0=q0, qf=qf, v0=v0, vf=vf, **{name: spec}))
    start = joint_vector("q0", q0, ndof, unit="rad")
    end = joint_vector("qf", qf, ndof, unit="rad")
    v_min, v_max = read_bounds("vmax", vmax, ndof, "rad/s")
    a_min, a_max = read_bounds("amax", amax, ndof, "rad/s^2")
    j_max = read_jerk(jmax, ndof)
    codes, names = read_sync(sync, ndof)
    matrix = np.stack(
        [
            start,
            end,
            joint_vector("v0", v0, ndof, unit="rad/s"),
            joint_vector("vf", vf, ndof, unit="rad/s"),
            joint_vector("a0", a0, ndof, unit="rad/s^2"),
            joint_vector("af", af, ndof, unit="rad/s^2"),
            v_min,
            v_max,
            a_min,
            a_max,
            j_max,
        ]
    )
    problem = Problem(matrix, codes, names)
    second = np.isinf(j_max)
    for name, value in (("a0", problem.a0), ("af", problem.af)):
        bad = np.flatnonzero(second & (value != 0))
        if bad.size:
            raise InvalidInputError(
                f"{name}={value[bad[0]]:.6g} rad/s^2 needs a jerk limit (joint {bad[0] + 1}): "
                "without one (jmax=inf) the acceleration jumps, and a boundary acceleration "
                "means nothing"
            )
    _check_target(problem)
    with np.errstate(over="ignore"):
        distance = end - start
    finite_result(planner, distance, {"q0": start, "qf": end})
    with np.errstate(all="ignore"):
        # A lower bound on each joint's duration: beyond float64, no plan can hold it.
        speed, push = np.minimum(v_max, -v_min), np.minimum(a_max, -a_min)
        scale = np.abs(distance) / speed + (speed + np.abs(problem.v0) + np.abs(problem.vf)) / push
    finite_result(planner, scale, {"vmax": vmax, "amax": amax, "v0": v0, "vf": vf})
    return problem


def read_matrix(planner: str, m: FloatArray) -> Problem:
    """Validate a problem given as the engine reads it, ``(11, ndof)`` (rows as :class:`Problem`).

    Where the compiled check refused a matrix, this names what is wrong in it
    (time-synchronized), as :func:`read_problem` does for the same arguments.
    """
    row = dict(zip(_ROWS, m, strict=True))
    return read_problem(
        planner,
        row["q0"],
        row["qf"],
        (row["v_min"], row["v_max"]),
        (row["a_min"], row["a_max"]),
        row["j_max"],
        v0=row["v0"],
        vf=row["vf"],
        a0=row["a0"],
        af=row["af"],
        sync="time",
    )


def solve(
    planner: str,
    p: Problem,
    *,
    duration: float | None = None,
    min_duration: float | None = None,
    period: float | None = None,
    grid: str = "switches",
    velocity_only: bool = False,
) -> engine.EngineResult:
    """Plan ``p``; ``duration`` exact (refused if impossible), ``min_duration`` a floor.

    With ``period``, ``grid`` puts every switching time (``"switches"``) or only the
    duration (``"duration"``) on the period grid. ``velocity_only`` plans to the
    target velocity and acceleration with no position target (``qf`` unused).
    """
    grid = choice("grid", grid, GRIDS)
    if duration is not None and min_duration is not None:
        raise InvalidInputError("give duration (exact) or min_duration (a floor), not both")
    floor = None
    if duration is not None:
        floor = positive_scalar("duration", duration, unit="s")
    elif min_duration is not None:
        floor = positive_scalar("min_duration", min_duration, unit="s")
    step = None if period is None else positive_scalar("period", period, unit="s")
    control = np.full(p.ndof, int(velocity_only), np.int64)  # 0 position, 1 velocity
    codes = p.sync
    if duration is not None:
        # An exact duration is every joint's: none is left to move on its own.
        codes = np.where(codes == engine.SYNC_MODES[None], engine.SYNC_MODES["time"], codes)
    result = engine.solve(
        planner, p.matrix, control=control, sync=codes, min_duration=floor, period=step, grid=grid
    )
    total = float(result.duration)
    if not math.isfinite(total):  # the check itself costs more than a plan
        finite_result(planner, np.array([total]), {"duration": duration})
    if duration is not None:
        fastest = float(result.own.max())
        if floor < fastest * (1 - ROUNDING_RTOL):
            joint = int(np.argmax(result.own))
            raise InfeasibleError(
                f"duration {floor:.6g} s is below the minimum {fastest:.6g} s set by "
                f"{_limits_text(p, joint)} (joint {joint + 1})"
            )
        if total > floor * (1 + ROUNDING_RTOL) + (0.0 if step is None else step):
            joint = _blocked_joint(planner, p, floor, int(velocity_only))
            raise InfeasibleError(
                f"duration {floor:.6g} s cannot be met exactly: joint {joint + 1} cannot take "
                f"it with its boundary velocities; the next duration that works is "
                f"{total:.6g} s"
            )
    return result


def _limits_text(p: Problem, joint: int) -> str:
    """The limits that set a joint's minimum, as a message names them."""
    down = p.qf[joint] < p.q0[joint]
    speed = p.v_min[joint] if down else p.v_max[joint]
    low, high = p.a_min[joint], p.a_max[joint]
    acceleration = f"{high:.6g}" if low == -high else f"({low:.6g}, {high:.6g})"
    if np.isinf(p.j_max[joint]):
        return f"vmax={speed:.6g} rad/s and amax={acceleration} rad/s^2"
    return (
        f"vmax={speed:.6g} rad/s, amax={acceleration} rad/s^2 and jmax={p.j_max[joint]:.6g} rad/s^3"
    )


def _blocked_joint(planner: str, p: Problem, duration: float, control: int = 0) -> int:
    """The first joint that cannot take ``duration`` on its own (for a message)."""
    for joint in range(p.ndof):
        alone = np.ascontiguousarray(p.matrix[:, joint : joint + 1])
        result = engine.solve(
            planner,
            alone,
            control=np.full(1, control, np.int64),
            sync=np.zeros(1, np.int64),
            min_duration=duration,
        )
        if float(result.duration) > duration * (1 + ROUNDING_RTOL):
            return joint
    return 0


class LazyInfo(Mapping):
    """A read-only ``info`` mapping whose values are built on first access.

    Planning one move is a few microseconds; turning every phase table into
    tuples of Python floats would cost more than the planning, so it waits
    until somebody reads ``info``.
    """

    __slots__ = ("_build", "_data")

    def __init__(self, build: Callable[[], dict[str, Any]]) -> None:
        self._build: Callable[[], dict[str, Any]] | None = build
        self._data: dict[str, Any] | None = None

    def _items(self) -> dict[str, Any]:
        if self._data is None:
            self._data = self._build()  # type: ignore[misc]
            self._build = None
        return self._data

    def __getitem__(self, key: str) -> Any:
        return self._items()[key]

    def __iter__(self) -> Iterator[str]:
        return iter(self._items())

    def __len__(self) -> int:
        return len(self._items())

    def __repr__(self) -> str:
        return f"mappingproxy({self._items()!r})"


PHASE_FALLBACK = (
    "phase synchronization is impossible for this move (the joints' boundary velocities "
    "and accelerations are not all parallel to it, or the shared law would break a "
    "joint's limits): the joints are time-synchronized instead"
)


def plan_info(
    planner: str, p: Problem, result: engine.EngineResult, period: float | None
) -> dict[str, Any]:
    """What a limit-driven plan reports in ``info`` (plain Python numbers)."""
    from trajkit.profiles._kernels import layout as L

    r = result.records
    assert r is not None  # one problem
    limiting = int(result.limiting)
    rows = lambda x: tuple(tuple(float(v) for v in row) for row in x)  # noqa: E731
    info: dict[str, Any] = {
        "planner": planner,
        "continuity": 1 if np.any(result.second_order) else 2,
        "sync": p.sync_names[0] if len(set(p.sync_names)) == 1 else p.sync_names,
        "period": period,
        "duration": float(result.duration),
        "minimum_durations": tuple(float(x) for x in result.own),
        "limiting_joint": None if limiting < 0 else limiting,
        "phase_times": rows(r[:, L.T : L.T + 7]),
        "brake_times": rows(r[:, L.BRAKE_T : L.BRAKE_T + 2]),
        "jerks": rows(r[:, L.J : L.J + 7]),
        "peak_velocity": tuple(float(x) for x in r[:, L.V + 3]),
        "peak_acceleration": rows(r[:, [L.A + 1, L.A + 5]]),
    }
    if "phase" in p.sync_names:
        info["phase_synchronized"] = bool(result.phase_synchronized)
        if not result.phase_synchronized:
            info["phase_note"] = PHASE_FALLBACK
    return info


def to_trajectory(
    planner: str,
    p: Problem,
    result: engine.EngineResult,
    *,
    period: float | None,
    info: Callable[[dict[str, Any], PhasePlan], dict[str, Any]] | None = None,
) -> Trajectory:
    """The planned motion as a Trajectory (one piecewise cubic), the plan in ``info``.

    ``info(fields, plan)``, if given, adapts the planner's ``info`` fields (it is
    called on first access, with the nine-phase plan).
    """
    breakpoints, coefficients, end = result.pieces  # type: ignore[misc]
    build = lambda: _info(planner, p, result, period, info)  # noqa: E731
    return Trajectory._trusted(breakpoints, coefficients, LazyInfo(build), end)


def trajectory(
    planner: str,
    q0: ArrayLike,
    qf: ArrayLike,
    vmax: LimitSpec,
    amax: LimitSpec,
    jmax: ArrayLike,
    *,
    v0: ArrayLike,
    vf: ArrayLike,
    a0: ArrayLike,
    af: ArrayLike,
    sync: object,
    duration: float | None,
    min_duration: float | None,
    period: float | None,
    grid: str,
    info: Callable[[dict[str, Any], PhasePlan], dict[str, Any]] | None = None,
) -> Trajectory:
    """One problem validated, planned and built: the limit-driven planners' front end.

    With default options (no ``duration``, ``min_duration`` or ``period``) plainly
    numeric input takes the short road (:func:`quick_trajectory`); everything
    else, and whatever the short road hands back, the full one (:func:`read_problem`,
    :func:`solve`, :func:`to_trajectory`). ``info`` adapts the planner's ``info``.
    """
    if duration is None and min_duration is None and period is None and grid in GRIDS:
        quick = quick_trajectory(
            planner, q0, qf, vmax, amax, jmax, v0=v0, vf=vf, a0=a0, af=af, sync=sync, info=info
        )
        if quick is not None:
            return quick
    problem = read_problem(planner, q0, qf, vmax, amax, jmax, v0=v0, vf=vf, a0=a0, af=af, sync=sync)
    result = solve(
        planner, problem, duration=duration, min_duration=min_duration, period=period, grid=grid
    )
    return to_trajectory(planner, problem, result, period=period, info=info)


def _info(
    planner: str,
    p: Problem,
    result: engine.EngineResult,
    period: float | None,
    adapt: Callable[[dict[str, Any], PhasePlan], dict[str, Any]] | None,
) -> dict[str, Any]:
    fields = plan_info(planner, p, result, period)
    if adapt is None:
        return fields
    return adapt(fields, engine.phase_plan(result, p.q0, p.v0, p.a0))
