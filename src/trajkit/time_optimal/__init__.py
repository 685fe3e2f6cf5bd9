"""Time-optimal path parameterization: the fastest timing of a fixed path.

Given a geometric path ``q(s)`` and per-joint velocity and acceleration bounds,
:func:`topp` (also ``trajkit.topp``) finds the fastest ``s(t)`` by reachability
analysis (Pham & Pham, 2018) on a grid in ``s``, each stage solved in closed form
(:mod:`trajkit.time_optimal.reachability`). The result is exact between
grid points too (:mod:`trajkit.time_optimal.timing`): ``q(s(t))`` is a Trajectory of
polynomials whose limits :meth:`~trajkit.Trajectory.check` verifies exactly.

Why the result keeps every limit everywhere, not only at the grid points: the
stage constraints bound the Bernstein coefficients of every joint's acceleration
and squared velocity over each interval, whose hull contains the whole curve
(:class:`~trajkit.time_optimal.reachability.Stages`). The timed polynomials'
extrema are then computed exactly before returning. Should an interval still pass
a bound, that bound is tightened locally (its acceleration bounds scaled by the
ratio, the velocity caps at its ends lowered to the speed that would have kept it)
and the problem re-solved; failing that, the whole motion is slowed uniformly by
``max(v_peak / v_max, sqrt(a_peak / a_max))`` (rest-to-rest motions only, as
slowing would change non-zero boundary speeds). Jerk limits: see
:mod:`trajkit.time_optimal.jerk`.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from functools import cache
from math import comb
from types import MappingProxyType

import numpy as np
from numpy.typing import ArrayLike

from trajkit._validation import FloatArray, as_float_array, finite_result, finite_scalar
from trajkit.curve import Segmented
from trajkit.errors import InfeasibleError, InvalidInputError
from trajkit.limits import Limits, Report
from trajkit.time_optimal.constraints import (
    COLLOCATION,
    SAMPLES,
    PathLimit,
    ToolLimit,
    TorqueLimit,
    checked_limits,
    measure,
    refuse_unheld,
)
from trajkit.time_optimal.reachability import Channels, Rows, Stages
from trajkit.time_optimal.retime import blended_path, retime
from trajkit.time_optimal.timing import (
    GeometricPath,
    as_polynomial,
    interval_peaks,
    rest_states,
    timed,
)
from trajkit.tolerances import JUMP_RTOL, LIMIT_RTOL, ROUNDING_RTOL
from trajkit.trajectory import Trajectory

__all__ = [
    "GeometricPath",
    "PathLimit",
    "ToolLimit",
    "TorqueLimit",
    "blended_path",
    "retime",
    "topp",
]

#: Largest boundary path speed whose square is a finite float64 (1/s).
_MAX_SPEED = float(np.sqrt(np.finfo(np.float64).max))
#: Most grid intervals a timing accepts: far finer than any path needs, and small
#: enough for the solver's per-interval arrays to fit in memory.
MAX_GRID = 100_000
#: Grid intervals given to a stretch between two of the path's breakpoints that has
#: no grid point inside.
_SPLIT = 4
#: Rounds of local tightening before the uniform slow-down.
_ROUNDS = 12
#: Tightened bounds aim this fraction inside the bound, so a round rarely falls short.
_MARGIN = 1e-6
#: A torque or tool bound passed on an interval is moved in by the excess and this
#: fraction of the bound: its neighbours, re-timed, then rarely pass it in turn.
_INSIDE = 1e-6


def topp(
    path: Trajectory | GeometricPath,
    limits: Limits,
    *,
    grid: int | ArrayLike = 500,
    start_speed: float = 0.0,
    end_speed: float = 0.0,
    constraints: PathLimit | Sequence[PathLimit] | None = None,
) -> Trajectory:
    """The time-optimal timing of ``path`` under velocity and acceleration limits.

    Parameters
    ----------
    path : Trajectory or GeometricPath
        The geometric path ``q(s)``: a Trajectory (its time axis read as the path
        parameter ``s``), or any object with ``evaluate(s, order)`` (orders 0–2)
        and ``breakpoints`` (the range of ``s``), which is first replaced by the
        quintic Hermite spline through its derivatives at the grid points.
    limits : Limits
        ``velocity`` and ``acceleration`` bounds per joint (rad/s, rad/s² or m/s,
        m/s²; asymmetric allowed, each lower bound < 0 < upper bound). A ``jerk``
        bound switches to the jerk-limited timing of :func:`trajkit.time_optimal.jerk.smoothed`.
        Position limits are not the timing's business and are ignored.
    grid : int or array_like
        Number of grid intervals (uniform in ``s``; the path's breakpoints are
        added), or the grid points themselves; at most ``MAX_GRID`` (100,000)
        intervals. More points, a shorter timing.
    start_speed, end_speed : float
        Path speeds ``ṡ`` at the start and at the end (units of ``s`` per second),
        >= 0. A jerk-limited timing holds a non-zero one for a moment (zero path
        acceleration at that end).
    constraints : TorqueLimit, ToolLimit or a list of them, optional
        Further limits along the path: actuator torques
        (:class:`~trajkit.time_optimal.TorqueLimit`), the tool's speed,
        acceleration or turn rate (:class:`~trajkit.time_optimal.ToolLimit`). They
        are kept at the ends and middle of every grid interval and then measured
        on 16 samples of every timed piece with a curvature margin (see
        :mod:`trajkit.time_optimal.constraints`); an interval that passes is
        tightened and solved again. With a jerk bound they are measured on the
        smoothed timing and, where it passes one, tightened everywhere along the path
        and the timing made again (see :mod:`trajkit.time_optimal.jerk`).

    Returns
    -------
    Trajectory
        ``q(t)`` from t = 0: the path timed, one polynomial piece per grid
        interval, of twice the path's degree. ``info`` holds ``grid_points``,
        ``path_speed`` (ṡ at each), ``rounds`` (solves needed), ``slow_down`` (the
        uniform factor, 1 if none), ``path_error`` (0 for a Trajectory path) and,
        with ``constraints``, ``constraint_checks`` (a
        :class:`~trajkit.Report` of the result for each, from its ``check``).
        With a jerk bound the pieces are those of the smoothed timing (three times
        the path's degree, about two per grid interval) and ``info`` holds
        ``jerk_limited``, ``grid_points``, ``rests`` (where it stops), ``windows``
        (the averaging window of each stretch, s), ``rounds``, ``path_error`` and,
        with ``constraints``, ``constraint_checks``.

    Raises
    ------
    InvalidInputError
        Malformed path, limits, grid or speeds, a path that never moves, or one
        whose position jumps (no timing can follow a step).
    InfeasibleError
        The boundary speeds cannot be met within the limits (the message says the
        fastest that can), or no timing keeps every limit between grid points with
        the non-zero boundary speeds asked for; gravity beyond a torque limit where
        the path rests (its ends, its corners), or torque limits that no speed
        along the path keeps.

    Examples
    --------
    >>> import numpy as np, trajkit as tk
    >>> path = tk.cubic_spline([0, 0.5, 1], [[0, 0], [1, -0.5], [0.5, 1]], bc="natural")
    >>> limits = tk.Limits(velocity=1.0, acceleration=2.0)
    >>> timed = tk.topp(path, limits, grid=200)
    >>> timed.check(limits).ok
    True
    """
    limits = _checked_limits(limits)
    if isinstance(path, Segmented):
        # Curves in time already, of the tool or the base: timed as joints they would
        # be wrong without an error.
        raise InvalidInputError(
            f"path must be a joint path, got a {type(path).__name__} (a motion in time "
            "of the tool or the base): time a task-space path with "
            "trajkit.taskspace.time_optimal, a base's with trajkit.mobile"
        )
    if not isinstance(path, Trajectory) and not hasattr(path, "breakpoints"):
        raise InvalidInputError(
            "path must be a Trajectory or have evaluate(s, order) and breakpoints, got "
            f"{type(path).__name__}"
        )
    points = grid_points(np.asarray(path.breakpoints, dtype=float), grid)
    polynomial, stray = as_polynomial(path, points)
    steps = breakpoint_steps(polynomial, 0)
    if steps.any():  # timed, it would jump too, with its info claiming C1
        i, j = (int(k[0]) for k in np.nonzero(steps))
        where = float(polynomial.breakpoints[i + 1])
        raise InvalidInputError(
            f"the path's position jumps by {steps[i, j]:.6g} at s={where:.6g} (joint {j + 1}): "
            "a path to time must be continuous"
        )
    ndof = polynomial.ndof
    if not np.any(polynomial.coefficients[:-1]):  # every piece of every joint constant
        raise InvalidInputError("the path never moves (every joint is constant): nothing to time")
    speeds = (finite_scalar("start_speed", start_speed, unit="1/s"),
              finite_scalar("end_speed", end_speed, unit="1/s"))  # fmt: skip
    if min(speeds) < 0.0:
        raise InvalidInputError(f"start_speed and end_speed must be >= 0, got {list(speeds)}")
    for name, speed in zip(("start_speed", "end_speed"), speeds, strict=True):
        # The timing works with the squared speed, which must stay a float64.
        if speed > _MAX_SPEED:
            raise InvalidInputError(
                f"{name} must be at most {_MAX_SPEED:.4g} 1/s (its square must be a finite "
                f"float64), got {speed:g} 1/s"
            )
    velocity = _sides(limits, "velocity", ndof)
    acceleration = _sides(limits, "acceleration", ndof)
    extra = checked_limits(constraints, ndof)
    if extra:  # where gravity alone passes a torque limit, no timing is found: say so
        ends = [i for i, speed in zip((0, points.size - 1), speeds, strict=True) if speed == 0]
        # The path rests where its tangent jumps; jerk-limited, where its curvature does too.
        stops = [jumps(polynomial, order) for order in (1, 2)[: 1 + (limits.jerk is not None)]]
        rests = np.union1d(ends, np.searchsorted(points, np.concatenate(stops))).astype(int)
        refuse_unheld(extra, polynomial.evaluate(points), points, points[rests])
    if limits.jerk is not None:
        from trajkit.time_optimal.jerk import smoothed

        return smoothed(polynomial, points, limits, stray, speeds, extra)
    # Limits near the float64 range overflow in the solve; the result is checked below.
    with np.errstate(over="ignore", invalid="ignore"):
        x, rounds, slow, checks = optimal_x(polynomial, points, velocity, acceleration, speeds,
                                            constraints=extra)  # fmt: skip
    try:
        with np.errstate(all="ignore"):
            result = timed(polynomial, points, x)
            if slow != 1.0:
                result = result.time_scaled(slow)
    except InvalidInputError:
        # Everything was validated above: only an overflow of the timed pieces is
        # left (limits near 1e308 make intervals of 1e-300 s).
        arguments = {"velocity": velocity[1], "acceleration": acceleration[1]}
        finite_result("topp", np.inf, {**arguments, "grid": points.size - 1})
        raise
    info = {"planner": "topp", "continuity": 1, "grid_points": points,
            "path_speed": np.sqrt(x) / slow, "rounds": rounds, "slow_down": slow,
            "path_error": stray}  # fmt: skip
    if extra:  # measured on the same timing in the last round (no slow-down with them)
        info["constraint_checks"] = checks
    # The pieces were built from the path at its ends: their ends are the states.
    ends = rest_states(polynomial, points, speeds)
    # The timed pieces are this function's own: the result takes them over, not a copy.
    return Trajectory._trusted(result.breakpoints, result.coefficients, MappingProxyType(info),
                               ends["end"], ends["start"])  # fmt: skip


def optimal_x(
    path: Trajectory,
    s: FloatArray,
    velocity: tuple[FloatArray, FloatArray],
    acceleration: tuple[FloatArray, FloatArray],
    speeds: tuple[float, float] = (0.0, 0.0),
    stops: ArrayLike = (),
    constraints: tuple[PathLimit, ...] = (),
    ceiling: FloatArray | None = None,
    bands: list[_Band] | None = None,
) -> tuple[FloatArray, int, float, list[Report]]:
    """``x = ṡ²`` at the grid points, tightened until the timed path keeps every limit.

    Parameters
    ----------
    path : Trajectory
        The path ``q(s)`` (a polynomial).
    s : ndarray, shape (N + 1,)
        Grid points, the path's breakpoints among them.
    velocity, acceleration : tuple of ndarray, shape (ndof,)
        ``(lower, upper)`` bounds per joint (per second, per second squared).
    speeds : tuple of float
        Path speeds ``ṡ`` at the start and the end (1/s).
    stops : array_like of int
        Grid indices where the path must come to rest besides its corners.
    constraints : tuple of PathLimit
        Torque and tool limits, measured on the timed pieces and tightened per
        interval until kept; no uniform slow-down with them.
    ceiling : ndarray, shape (N + 1,), optional
        The most ``x`` may be at each grid point (1/s²; ``inf`` where free).
    bands : list of _Band, optional
        The constraints' bounds per interval to start from (and to tighten, in
        place): a caller that measures a later timing (a smoothed one) moves them
        in between calls. By default the constraints' own bounds.

    Returns
    -------
    x : ndarray, shape (N + 1,)
        ``ṡ²`` at the grid points (1/s²).
    rounds : int
        Solves needed (1 unless an interval passed a bound).
    slow_down : float
        The uniform slow-down still needed (1 unless the local tightening did not
        converge).
    checks : list of Report
        The constraints' reports of the timing returned (empty without constraints).
    """
    channels = path_channels(path, s, velocity, acceleration)
    if len(stops):
        corners = np.union1d(channels.corners, np.asarray(stops, dtype=int))
        channels = dataclasses.replace(channels, corners=corners)
    if bands is None:
        bands = [_Band.of(limit, s.size - 1) for limit in constraints]
    states = _collocated(path, s) if constraints else None
    stages = Stages(channels, _rows(constraints, bands, states, s))
    n = s.size
    acceleration_scale = np.ones(n - 1)
    # The most x may be at each point, as tightened: kept in x, not as a factor on the
    # velocity caps, which change when the stages are built again.
    x_cap = np.full(n, np.inf) if ceiling is None else np.array(ceiling, dtype=float)
    x_start, x_end = speeds[0] ** 2, speeds[1] ** 2
    for rounds in range(1, _ROUNDS + 1):
        x = stages.solve(x_start, x_end, _factor(x_cap, stages.velocity_cap),
                         acceleration_scale)  # fmt: skip
        ratio_v, ratio_a = interval_peaks(path, s, x, velocity, acceleration)
        over_v, over_a = ratio_v > 1.0 + LIMIT_RTOL, ratio_a > 1.0 + LIMIT_RTOL
        checks = _tighten(constraints, bands, _timed_within(path, s, x)) if constraints else []
        passed = not all(check.ok for check in checks)
        if not (over_v.any() or over_a.any() or passed):
            return x, rounds, 1.0, checks
        if passed:
            stages = Stages(channels, _rows(constraints, bands, states, s))
        acceleration_scale[over_a] /= ratio_a[over_a] * (1.0 + _MARGIN)
        # The ends of an interval that ran too fast may carry at most the speed that
        # would have kept it: x / ratio², as a factor on the velocity cap.
        factor = (1.0 - _MARGIN) / ratio_v**2
        target = np.full(n, np.inf)
        target[:-1] = np.where(over_v, x[:-1] * factor, np.inf)
        target[1:] = np.minimum(target[1:], np.where(over_v, x[1:] * factor, np.inf))
        target[0], target[-1] = max(target[0], x_start), max(target[-1], x_end)
        x_cap = np.minimum(x_cap, target)
    if constraints:  # no uniform slow-down: it would not keep gravity's share of a torque
        missed = [str(v) for check in checks for v in check.violations]
        what = "; ".join(missed) or "the joint limits were still passed between grid points"
        raise InfeasibleError(
            f"no timing on this grid keeps the torque and tool limits after {_ROUNDS} "
            f"rounds of tightening: {what}; try another grid"
        )
    if x_start > 0.0 or x_end > 0.0:
        raise InfeasibleError(
            "the timing could not be made to keep every limit between grid points with "
            "non-zero boundary speeds: use a finer grid or lower boundary speeds"
        )
    slow = float(max(ratio_v.max(), np.sqrt(ratio_a.max()), 1.0) * (1 + ROUNDING_RTOL))
    return x, _ROUNDS, slow, checks


def _factor(x_cap: FloatArray, velocity_cap: FloatArray) -> FloatArray:
    """``x_cap`` as a factor (at most 1) on the stages' velocity caps; 1 where both are inf."""
    with np.errstate(divide="ignore", invalid="ignore"):
        below = x_cap / velocity_cap
    return np.minimum(1.0, np.where(np.isnan(below), 1.0, below))


def _timed_within(path: Trajectory, s: FloatArray, x: FloatArray) -> Trajectory:
    """The timed path, or a refusal that says tightened torque or tool limits stopped it."""
    try:
        return timed(path, s, x)
    except InfeasibleError:
        raise InfeasibleError(
            "the torque and tool limits, kept between grid points, leave no speed on a "
            "whole interval of this grid: use a finer grid (they are kept at the ends and "
            "middle of each interval) or looser limits"
        ) from None


def _collocated(path: Trajectory, s: FloatArray) -> tuple[FloatArray, ...]:
    """``σ`` and ``q, q', q''`` at the collocation points of every interval, (N * F, ...)."""
    fractions = np.asarray(COLLOCATION)
    sigma = np.diff(s)[:, None] * fractions
    points = s[:-1, None] + sigma
    # An interval's own end is read from its side: the tangent may jump there.
    points[:, fractions == 1.0] = np.nextafter(s[1:, None], -np.inf)
    flat = points.ravel()
    return (sigma.ravel(), *(path.evaluate(flat, order) for order in range(3)))


@dataclasses.dataclass
class _Band:
    """A constraint's bounds per interval, as tightened round by round."""

    lower: FloatArray
    upper: FloatArray
    rounds: int = 0  # rounds in which some interval passed
    #: Moved along the whole path: the last move in and the excess it answered, per
    #: side and component, to learn how much of a move reaches the measured peak.
    moves: dict[str, tuple[FloatArray, FloatArray]] = dataclasses.field(default_factory=dict)

    @classmethod
    def of(cls, limit: PathLimit, intervals: int) -> _Band:
        lower, upper = (np.tile(side, (intervals, 1)) for side in limit.bounds())
        return cls(lower, upper)


def _rows(
    constraints: tuple[PathLimit, ...],
    bands: list[_Band],
    states: tuple[FloatArray, ...] | None,
    s: FloatArray,
) -> Rows | None:
    """Every constraint's rows at the collocation points: ``A u + B (x_i + 2uσ) + C``."""
    if not constraints or states is None:
        return None
    sigma, q, dq, ddq = states
    count = s.size - 1
    columns: list[list[FloatArray]] = [[], [], [], []]
    for limit, band in zip(constraints, bands, strict=True):
        per_point = [np.repeat(side, len(COLLOCATION), axis=0) for side in (band.lower, band.upper)]
        a, b, c, low, high = limit.rows(q, dq, ddq, *per_point)
        for column, value in zip(columns, (a + 2.0 * sigma[:, None] * b, b, low - c, high - c),
                                 strict=True):  # fmt: skip
            column.append(value.reshape(count, -1))
    on_u, on_x, lower_rows, upper_rows = (np.concatenate(c, axis=1) for c in columns)
    return Rows(on_u, on_x, lower_rows, upper_rows)


def _tighten(
    constraints: tuple[PathLimit, ...],
    bands: list[_Band],
    timing: Trajectory,
    *,
    per_interval: bool = True,
) -> list[Report]:
    """Measure ``timing`` against each constraint, and move in the bands it passed.

    Returns each constraint's :class:`~trajkit.Report` of ``timing`` (the same as
    ``check``'s): where one is not ok, its bands moved.

    ``per_interval``: the timing's pieces are the grid's intervals, and each
    interval's side moves in by its own excess. The bound of an interval also rests
    on its neighbours' timing, and along a stretch at the bound an excess may move on
    to the next interval each round: from the second round on, every interval's side
    also moves in by the largest excess of that component (a few 1e-6 of the bound,
    by then). Otherwise (a smoothed timing, whose pieces are not the intervals) every
    interval's side moves in by the component's largest excess.
    """
    reports = []
    for limit, band in zip(constraints, bands, strict=True):
        measured = measure(limit, timing, SAMPLES)
        reports.append(limit.report(measured))
        if reports[-1].ok:
            continue
        high, low = measured[:2]
        bound_lo, bound_hi = limit.bounds()
        size = np.maximum(np.abs(np.where(np.isfinite(bound_lo), bound_lo, 0.0)),
                          np.abs(np.where(np.isfinite(bound_hi), bound_hi, 0.0)))  # fmt: skip
        over_hi = high - bound_hi
        over_lo = bound_lo - low
        slack = LIMIT_RTOL * size
        hit_hi, hit_lo = over_hi > slack, over_lo > slack
        if not (hit_hi.any() or hit_lo.any()):  # as the report says (the same rule as compare)
            continue
        # In by the excess and a little more (_INSIDE of the bound), so that the
        # neighbours' re-timing rarely needs another round.
        inside = slack + _INSIDE * size
        if per_interval:
            band.upper -= np.where(hit_hi, over_hi + inside, 0.0)
            band.lower += np.where(hit_lo, over_lo + inside, 0.0)
            if band.rounds:
                band.upper -= np.where(hit_hi.any(axis=0), np.maximum(over_hi, 0).max(axis=0), 0)
                band.lower += np.where(hit_lo.any(axis=0), np.maximum(over_lo, 0).max(axis=0), 0)
        else:
            band.upper -= _move(band, "upper", over_hi, hit_hi, inside)
            band.lower += _move(band, "lower", over_lo, hit_lo, inside)
        band.rounds += 1
    return reports


def _move(band: _Band, side: str, over: FloatArray, hit: FloatArray, inside: FloatArray
          ) -> FloatArray:  # fmt: skip
    """How far to move one side of ``band`` in along the whole path, per component.

    The largest excess, divided by the share of the last move that reached the
    measured peak (a smoothed timing's peak falls by less than its bound moved: the
    average spreads the speed onto its neighbours), between 1 and 1/10.
    """
    excess = np.where(hit.any(axis=0), np.maximum(over, 0.0).max(axis=0), 0.0)
    reach = np.ones_like(excess)
    if side in band.moves:
        moved, before = band.moves[side]
        with np.errstate(divide="ignore", invalid="ignore"):
            share = (before - excess) / moved
        reach = np.where((moved > 0) & np.isfinite(share), np.clip(share, 0.1, 1.0), 1.0)
    step = np.where(excess > 0, excess / reach + inside, 0.0)
    band.moves[side] = (step, excess)
    return step


def path_channels(
    path: Trajectory,
    s: FloatArray,
    velocity: tuple[FloatArray, FloatArray],
    acceleration: tuple[FloatArray, FloatArray],
) -> Channels:
    """A joint path's channels: one per joint, with corners where its tangent jumps.

    Parameters
    ----------
    path : Trajectory
    s : ndarray, shape (N + 1,)
        Grid points, the path's breakpoints among them.
    velocity, acceleration : tuple of ndarray, shape (ndof,)
        ``(lower, upper)`` bounds per joint.

    Returns
    -------
    Channels
        ``c'(σ)`` of every joint on every interval, with the bounds and corners.
    """
    from trajkit.time_optimal import _passes

    contiguous = np.ascontiguousarray
    slope = _passes.local_slopes(contiguous(path.coefficients, dtype=float),
                                 contiguous(path.breakpoints, dtype=float),
                                 contiguous(s, dtype=float),
                                 _binomials(path.coefficients.shape[0]))  # fmt: skip
    corners = np.searchsorted(s, jumps(path, 1))
    return Channels(s, slope, velocity, acceleration, corners)


@cache
def _binomials(size: int) -> FloatArray:
    """``C(n, j)`` for ``n, j < size``, as floats (cached and shared: kernels only read it)."""
    out = np.zeros((size, size))
    for n in range(size):
        for j in range(n + 1):
            out[n, j] = comb(n, j)
    return out


def jumps(path: Trajectory, order: int) -> FloatArray:
    """The path's inner breakpoints (s) where its ``order``-th derivative jumps."""
    return path.breakpoints[1:-1][breakpoint_steps(path, order).any(axis=1)]


def breakpoint_steps(path: Trajectory, order: int) -> FloatArray:
    """The jump of the path's ``order``-th derivative at each inner breakpoint, (P - 1, ndof).

    The value the next piece starts with minus the value the previous piece ends
    with; 0 where the jump is within 1e-9 of the derivative's largest value at the
    breakpoints (at least 1).
    """
    from trajkit.time_optimal import _passes

    return _passes.breakpoint_steps(np.ascontiguousarray(path.coefficients, dtype=float),
                                    np.ascontiguousarray(path.breakpoints, dtype=float),
                                    order, JUMP_RTOL)  # fmt: skip


def grid_points(breakpoints: FloatArray, grid: int | ArrayLike) -> FloatArray:
    """The grid in ``s``: ``grid`` uniform intervals or the given points, plus breakpoints.

    Parameters
    ----------
    breakpoints : ndarray
        The path's breakpoints, first to last (units of ``s``).
    grid : int or array_like
        Number of uniform intervals (>= 2), or increasing points from the first
        breakpoint to the last.

    Returns
    -------
    ndarray
        Increasing grid points; points closer than 1e-12 of the span are merged.

    Raises
    ------
    InvalidInputError
        A grid that is not a whole number >= 2 or such a list of points, or one
        finer than :data:`MAX_GRID` intervals.
    """
    if breakpoints.ndim != 1 or breakpoints.size < 2 or not np.all(np.isfinite(breakpoints)):
        raise InvalidInputError("the path's breakpoints must be at least 2 finite numbers")
    start, end = float(breakpoints[0]), float(breakpoints[-1])
    if end <= start:
        raise InvalidInputError("the path has no length to time")
    if isinstance(grid, (bool, str, float)):
        raise InvalidInputError(
            f"grid must be a whole number of intervals or an array of grid points, got {grid!r}"
        )
    if isinstance(grid, (int, np.integer)):
        if grid < 2:
            raise InvalidInputError(f"grid must be at least 2 intervals, got {grid}")
        if grid > MAX_GRID:
            raise InvalidInputError(
                f"grid must be at most {MAX_GRID:,} intervals (each costs memory and time), "
                f"got {grid:,}"
            )
        points = np.linspace(start, end, int(grid) + 1)
    else:
        try:
            points = as_float_array("grid", grid)
        except InvalidInputError as exc:
            raise InvalidInputError(
                f"grid must be a number of intervals or increasing points, got {grid!r}: {exc}"
            ) from None
        if points.size > MAX_GRID + 1:
            raise InvalidInputError(
                f"grid must hold at most {MAX_GRID + 1:,} points, got {points.size:,}"
            )
        if points.ndim != 1 or points.size < 3 or not np.all(np.diff(points) > 0):
            raise InvalidInputError("grid points must be at least 3 increasing numbers")
        if points[0] != start or points[-1] != end:
            raise InvalidInputError(
                f"grid points must start and end with the path, at {start:g} and {end:g}"
            )
    from trajkit.time_optimal import _passes

    # The path's own breakpoints are grid points, so every interval lies in one piece.
    # Points closer than ROUNDING_RTOL of the span are merged. An interval between two
    # breakpoints may lie between two rests (corners, where the path stops): one
    # interval with no speed at either end cannot be crossed, so such intervals get
    # _SPLIT of their own.
    return _passes.merged_grid(np.ascontiguousarray(points, dtype=float),
                               np.ascontiguousarray(breakpoints, dtype=float),
                               ROUNDING_RTOL * (end - start), _SPLIT)  # fmt: skip


def _checked_limits(limits: object) -> Limits:
    if not isinstance(limits, Limits) or limits.velocity is None or limits.acceleration is None:
        raise InvalidInputError(
            f"limits must be a trajkit.Limits with velocity and acceleration bounds, got {limits!r}"
        )
    return limits


def _sides(limits: Limits, quantity: str, ndof: int) -> tuple[FloatArray, FloatArray]:
    lower, upper = np.array(getattr(limits, quantity).for_ndof(quantity, ndof), dtype=float)
    if (lower >= 0.0).any() or (upper <= 0.0).any():
        raise InvalidInputError(
            f"{quantity} bounds must have lower < 0 < upper for every joint, got "
            f"({lower.tolist()}, {upper.tolist()})"
        )
    if not (np.isfinite(lower).all() and np.isfinite(upper).all()):
        raise InvalidInputError(f"{quantity} bounds must be finite for a time-optimal timing")
    return lower, upper
