"""Polynomial time laws: cubic, quintic and septic moves, and the general ``A a = b`` solver.

Positions are in rad (or m for prismatic joints), times in s; every argument that
is per joint may be a scalar, which then applies to all joints.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from fractions import Fraction
from functools import cache
from math import factorial

import numpy as np
from numpy.typing import ArrayLike

from trajkit import _poly
from trajkit._validation import (
    FloatArray,
    count_dof,
    finite_array,
    finite_result,
    finite_scalar,
    increasing_times,
    joint_vector,
    positive_joint_vector,
    positive_scalar,
)
from trajkit.errors import InfeasibleError, InvalidInputError
from trajkit.tolerances import LIMIT_RTOL
from trajkit.trajectory import Trajectory

__all__ = ["cubic", "hermite_pieces", "polynomial", "quintic", "septic"]

_LIMIT_NAMES = ("vmax", "amax", "jmax")
_LIMIT_UNITS = ("rad/s", "rad/s^2", "rad/s^3")
_BOUNDARY_NAMES = (("q0", "v0", "a0", "j0"), ("qf", "vf", "af", "jf"))


@cache
def _hermite_inverse(derivatives: int) -> FloatArray:
    """Inverse of the map from unit-interval coefficients to boundary derivatives.

    For ``n = derivatives`` values at each end (position, velocity, ...), the
    polynomial has degree ``2n - 1``; rows of the matrix are ``p^(r)(0)`` and
    ``p^(r)(1)``, columns the coefficients, highest power first.
    """
    degree = 2 * derivatives - 1
    powers = np.arange(degree, -1, -1)
    matrix = np.zeros((2 * derivatives, degree + 1))
    for r in range(derivatives):
        falling = np.array([factorial(p) // factorial(p - r) if p >= r else 0 for p in powers])
        matrix[r] = np.where(powers == r, falling, 0.0)  # at u = 0 only the u**r term survives
        matrix[derivatives + r] = falling  # at u = 1 every term contributes its factor
    inverse = np.array(_exact_inverse(matrix.astype(int).tolist()), dtype=np.float64)
    inverse.setflags(write=False)
    return inverse


def _exact_inverse(matrix: list[list[int]]) -> list[list[float]]:
    """Gauss-Jordan inverse in rational arithmetic.

    The entries are small fractions (2, -15/2, ...); exact ones keep boundary
    values exact to the last bit.
    """
    size = len(matrix)
    rows = [
        [Fraction(x) for x in row] + [Fraction(int(i == j)) for j in range(size)]
        for i, row in enumerate(matrix)
    ]
    for col in range(size):
        pivot = next(r for r in range(col, size) if rows[r][col] != 0)
        rows[col], rows[pivot] = rows[pivot], rows[col]
        lead = rows[col][col]
        rows[col] = [x / lead for x in rows[col]]
        for r in range(size):
            if r != col and rows[r][col] != 0:
                factor = rows[r][col]
                rows[r] = [x - factor * y for x, y in zip(rows[r], rows[col], strict=True)]
    return [[float(x) for x in row[size:]] for row in rows]


def hermite_pieces(start: FloatArray, end: FloatArray, durations: FloatArray) -> FloatArray:
    """Coefficients of the polynomials that meet given derivatives at both ends.

    Parameters
    ----------
    start, end : ndarray, shape (n, ...)
        Position, velocity, ... (``n`` orders) at the start and end of each piece.
    durations : ndarray
        Piece durations (s), broadcast against ``start[0]``.

    Returns
    -------
    ndarray, shape (2n, ...)
        Local power-basis coefficients (highest power first) of degree ``2n - 1``.
    """
    n = start.shape[0]
    # Solve for the displacement and add the start position back last: with absolute
    # positions, a small move far from zero would drown in their rounding.
    origin = start[0]
    start, end = start.copy(), end.copy()
    start[0] = 0.0
    end[0] = end[0] - origin
    scale = durations ** np.arange(n).reshape((-1,) + (1,) * (start.ndim - 1))
    boundary = np.concatenate([start * scale, end * scale], axis=0)
    unit = np.tensordot(_hermite_inverse(n), boundary, axes=(1, 0))  # p(u), u in [0, 1]
    c = _poly.scale_argument(unit, 1.0 / durations)
    c[-1] = c[-1] + origin
    return c


def _peak_ratios(
    start: FloatArray, end: FloatArray, durations: FloatArray, limits: list[FloatArray | None]
) -> FloatArray:
    """Largest ``|derivative| / limit`` over each move, shape ``(len(durations), 3, ndof)``.

    ``start``/``end`` have shape (n, ndof); ``durations`` shape (T,). Orders
    without a limit get ``-inf``, so they never count as binding.
    """
    ndof = start.shape[1]
    T = durations[:, np.newaxis]
    c = hermite_pieces(start[:, np.newaxis, :], end[:, np.newaxis, :], T)  # (2n, T, ndof)
    ratios = np.full((durations.size, len(limits), ndof), -np.inf)
    for index, limit in enumerate(limits):
        if limit is None:
            continue
        d = _poly.derivative(c, index + 1)
        lengths = np.broadcast_to(T, d.shape[1:]).ravel()
        low, _, high, _ = _poly.extrema_on_intervals(d.reshape(d.shape[0], -1), lengths)
        peak = np.maximum(np.abs(low), np.abs(high)).reshape(durations.size, ndof)
        ratios[:, index, :] = peak / limit
    return ratios


def _minimum_duration(
    start: FloatArray, end: FloatArray, limits: list[FloatArray | None]
) -> tuple[float, FloatArray, int, int]:
    """Smallest common duration keeping every joint within every given limit.

    Returns the duration, each joint's own minimum, and the (limit index, joint)
    that binds at the common minimum.

    At rest at both ends the peaks scale as ``|D| / T**r`` and the minimum is closed
    form. Otherwise see :func:`_search_minimum`.
    """
    rest = not np.any(start[1:]) and not np.any(end[1:])
    n = start.shape[0]
    if rest:
        distance = np.abs(end[0] - start[0])
        unit_peaks = _unit_rest_peaks(n)
        per_limit = np.full((len(limits), start.shape[1]), -np.inf)
        for index, limit in enumerate(limits):
            if limit is not None:
                r = index + 1
                per_limit[index] = (unit_peaks[r - 1] * distance / limit) ** (1.0 / r)
        own = per_limit.max(axis=0)
        joint = int(np.argmax(own))
        return float(own[joint]), own, int(np.argmax(per_limit[:, joint])), joint
    own = np.array(
        [
            _search_minimum(
                start[:, [j]], end[:, [j]], [None if x is None else x[[j]] for x in limits],
                unbounded_is_zero=True,
            )
            for j in range(start.shape[1])
        ]
    )  # fmt: skip
    if not np.any(own > 0):
        raise InfeasibleError(
            "the limits do not bound the duration from below (the move stays within "
            "them however fast it is); give a duration"
        )
    common = _search_minimum(start, end, limits, lower=float(own.max()))
    ratios = _peak_ratios(start, end, np.array([common]), limits)[0]
    binding, joint = np.unravel_index(int(np.argmax(ratios)), ratios.shape)
    return common, own, int(binding), int(joint)


@cache
def _unit_rest_peaks(derivatives: int) -> tuple[float, ...]:
    """Peak |p^(r)| on [0, 1] of the rest-to-rest unit move, for r = 1, 2, 3."""
    start = np.zeros((derivatives, 1))
    end = np.zeros((derivatives, 1))
    end[0] = 1.0
    c = hermite_pieces(start, end, np.ones(1))
    peaks = []
    for r in (1, 2, 3):
        d = _poly.derivative(c, r)
        low, _, high, _ = _poly.extrema_on_intervals(d, np.ones(1))
        peaks.append(float(max(abs(low[0]), abs(high[0]))))
    return tuple(peaks)


def _endpoint_crossings(
    start: FloatArray, end: FloatArray, limits: list[FloatArray | None]
) -> FloatArray:
    """Durations at which a limited derivative at either end of the move is critical.

    At ``u = t / T`` fixed, the ``r``-th time derivative is ``sum_i k_i T**(i - r)``
    (boundary value ``i`` enters scaled by ``T**i``), so "value = +-L" is a
    polynomial equation in ``T``. Feasible windows bounded by an end value start
    and stop exactly at these roots. So do the windows where an interior peak just
    reaches an end (the limit touched tangentially there): the next derivative is
    zero at that end, again a polynomial equation in ``T``.
    """
    n, ndof = start.shape
    inverse = _hermite_inverse(n)  # coefficients (highest first) per boundary value
    degree = 2 * n - 1
    powers = np.arange(degree, -1, -1)
    found = [np.empty(0)]
    for index, limit in enumerate(limits):
        if limit is None:
            continue
        # (order, level per joint): the value at the limit; its slope at zero.
        for r, levels in ((index + 1, (limit, -limit)), (index + 2, (np.zeros(ndof),))):
            if r > degree:
                continue
            falling = np.array([factorial(p) // factorial(p - r) if p >= r else 0 for p in powers])
            for u in (0.0, 1.0):
                basis = np.array(
                    [falling[k] * u ** max(powers[k] - r, 0) for k in range(degree + 1)]
                )
                weight = basis @ inverse  # d^r p / du^r at u per boundary value
                for j in range(ndof):
                    values = np.concatenate([start[:, j], end[:, j]])
                    values[n] -= values[0]  # the displacement, not absolute positions
                    values[0] = 0.0
                    k = np.zeros(n)
                    for i in range(2 * n):
                        k[i % n] += weight[i] * values[i]  # coefficient of T**(i % n)
                    for level in levels:
                        poly = np.zeros(max(n, r + 1))
                        poly[:n] += k
                        poly[r] -= level[j]
                        # Terms below 1e-300 of the largest (a subnormal v0 = 1e-320)
                        # only add roots past 1e40 s, but overflow np.roots' companion
                        # matrix into a LinAlgError: drop them.
                        poly[np.abs(poly) * 1e300 < np.abs(poly).max()] = 0.0
                        roots = np.roots(poly[::-1]) if np.any(poly) else np.empty(0)
                        real = roots[np.abs(roots.imag) <= 1e-9 * np.abs(roots)].real
                        found.append(real[real > 0])
    return np.concatenate(found)


_SCAN_DECADES = 12  # the scan covers [high * 1e-12, high]


def _search_minimum(
    start: FloatArray,
    end: FloatArray,
    limits: list[FloatArray | None],
    lower: float = 0.0,
    unbounded_is_zero: bool = False,
) -> float:
    """Smallest feasible duration >= ``lower`` when the ends are not at rest.

    Feasibility need not be monotonic in ``T`` (a window of durations may work
    around the one that makes the move a straight line), so the candidates are the
    exact durations where an end value meets a limit (:func:`_endpoint_crossings`)
    and a dense logarithmic scan; the first feasible candidate is refined by
    bisection against its predecessor to the last bits of ``T``. A window bounded only by
    interior peaks and narrower than the scan's spacing (0.6 %) can be missed.

    Raises
    ------
    InfeasibleError
        No duration works, or every duration down to the scan's floor works (the
        limits do not bound the duration from below; with ``unbounded_is_zero`` the
        answer is then 0).
    """

    def feasible(durations: FloatArray) -> FloatArray:
        ratios = _peak_ratios(start, end, durations, limits)
        # No slack: where a limit is touched tangentially, a slack of e would move
        # the minimum by sqrt(e).
        return ratios.reshape(durations.size, -1).max(axis=1) <= 1.0

    high = max(lower, 1e-6)
    for _ in range(200):
        if feasible(np.array([high]))[0]:
            break
        high *= 2.0
    else:
        raise InfeasibleError(
            "no duration keeps the move within the limits; check the boundary velocities "
            "and accelerations against the limits"
        )
    floor = lower if lower > 0 else high * 10.0**-_SCAN_DECADES
    exact = _endpoint_crossings(start, end, limits)
    candidates = np.concatenate(
        [np.geomspace(floor, high, 400 * _SCAN_DECADES // 2), exact, [floor, high]]
    )
    candidates = np.unique(candidates[(candidates >= floor) & (candidates <= high)])
    ok = feasible(candidates)
    first = int(np.argmax(ok))
    if first == 0:
        if lower > 0:
            return float(candidates[0])
        if unbounded_is_zero:
            return 0.0  # this joint alone would take no time; others set the duration
        raise InfeasibleError(
            "the limits do not bound the duration from below (the move stays within "
            "them however fast it is); give a duration"
        )
    a, b = candidates[first - 1], candidates[first]
    for _ in range(200):
        middle = 0.5 * (a + b)
        if feasible(np.array([middle]))[0]:
            b = middle
        else:
            a = middle
        # To the last bits: where a peak depends steeply on T (boundary velocities
        # with little room), 1e-13 relative in T can still be 1e-9 in the peak.
        if b - a <= 4 * np.spacing(b):
            break
    # Where the limit is touched tangentially the ratio exceeds 1 only quadratically,
    # so bisection stops up to ~1e-8 early; an exact critical duration nearby is the
    # true minimum.
    near = exact[(np.abs(exact - b) <= 1e-6 * b) & (exact >= lower)]
    if near.size:
        snapped = near[feasible(near)]
        if snapped.size:
            return float(snapped.min())
    return float(b)


def _boundary_polynomial(
    derivatives: int,
    name: str,
    boundary: tuple[ArrayLike, ...],
    duration: float | None,
    maxima: tuple[ArrayLike | None, ...],
) -> Trajectory:
    """Shared body of :func:`cubic`, :func:`quintic` and :func:`septic`."""
    names = _BOUNDARY_NAMES[0][:derivatives] + _BOUNDARY_NAMES[1][:derivatives]
    ndof = count_dof(
        **dict(zip(names, boundary, strict=True)), **dict(zip(_LIMIT_NAMES, maxima, strict=True))
    )
    values = [
        joint_vector(n, v, ndof, unit=("rad", "rad/s", "rad/s^2", "rad/s^3")[i % derivatives])
        for i, (n, v) in enumerate(zip(names, boundary, strict=True))
    ]
    start = np.array(values[:derivatives])
    end = np.array(values[derivatives:])
    limits: list[FloatArray | None] = [
        None if value is None else positive_joint_vector(lim, value, ndof, unit=unit)
        for lim, value, unit in zip(_LIMIT_NAMES, maxima, _LIMIT_UNITS, strict=True)
    ]
    _check_boundary_within_limits(start, end, limits, names, derivatives)
    given = any(limit is not None for limit in limits)
    info: dict[str, object] = {"planner": name, "continuity": math.inf}  # one polynomial
    if duration is None:
        if not given:
            raise InvalidInputError(
                f"{name}: give duration, or at least one of vmax, amax, jmax to find the "
                "shortest duration"
            )
        T, own, binding, joint = _minimum_duration(start, end, limits)
    else:
        T = positive_scalar("duration", duration, unit="s")
        if given:
            ratios = _peak_ratios(start, end, np.array([T]), limits)[0]
            binding, joint = np.unravel_index(int(np.argmax(ratios)), ratios.shape)
            if ratios[binding, joint] > 1.0 + LIMIT_RTOL:
                minimum, own, _, _ = _minimum_duration(start, end, limits)
                limit = limits[binding]
                raise InfeasibleError(
                    f"duration {T:.6g} s is below the minimum {minimum:.6g} s set by "
                    f"{_LIMIT_NAMES[binding]}={limit[joint]:.6g} "  # type: ignore[index]
                    f"{_LIMIT_UNITS[binding]} (joint {joint + 1})"
                )
            _, own, _, _ = _minimum_duration(start, end, limits)
    if given:
        info.update(
            minimum_durations=tuple(float(x) for x in own),
            limiting_joint=int(joint),
            limiting=_LIMIT_NAMES[int(binding)],
        )
    if T == 0.0:
        # Nothing moves and the limits ask for no time: a zero-duration standstill.
        coefficients = np.zeros((2 * derivatives, 1, ndof))
        coefficients[-1, 0] = start[0]
    else:
        with np.errstate(over="ignore", invalid="ignore"):
            coefficients = hermite_pieces(start, end, np.full(ndof, T))[:, np.newaxis, :]
        finite_result(name, coefficients, {**dict(zip(names, boundary, strict=True)),
                                           "duration": T})  # fmt: skip
    info["duration"] = T
    # The boundary conditions are the exact start and end states (the Hermite
    # polynomial reproduces them only up to rounding at T).
    exact = {} if T == 0.0 else {"start": start, "end": end}
    return Trajectory([0.0, T], coefficients, info=info, **exact)


def _check_boundary_within_limits(
    start: FloatArray,
    end: FloatArray,
    limits: list[FloatArray | None],
    names: tuple[str, ...],
    derivatives: int,
) -> None:
    for r in range(1, derivatives):
        limit = limits[r - 1] if r - 1 < len(limits) else None
        if limit is None:
            continue
        for side, values in ((0, start[r]), (1, end[r])):
            bad = np.flatnonzero(np.abs(values) > limit)
            if bad.size:
                j = bad[0]
                raise InfeasibleError(
                    f"{names[side * derivatives + r]}={values[j]:.6g} {_LIMIT_UNITS[r - 1]} "
                    f"exceeds {_LIMIT_NAMES[r - 1]}={limit[j]:.6g} {_LIMIT_UNITS[r - 1]} "
                    f"(joint {j + 1})"
                )


def cubic(
    q0: ArrayLike,
    qf: ArrayLike,
    duration: float | None = None,
    *,
    v0: ArrayLike = 0.0,
    vf: ArrayLike = 0.0,
    vmax: ArrayLike | None = None,
    amax: ArrayLike | None = None,
    jmax: ArrayLike | None = None,
) -> Trajectory:
    """Third-order polynomial move from ``(q0, v0)`` to ``(qf, vf)``.

    Parameters
    ----------
    q0, qf : float or array_like, shape (ndof,)
        Start and end positions (rad, or m for prismatic joints).
    duration : float, optional
        Move time (s). When omitted, the shortest duration keeping every joint
        within ``vmax``/``amax``/``jmax`` is used, common to all joints (the slowest
        joint sets it). When given together with limits, they are verified.
    v0, vf : float or array_like
        Start and end velocities (rad/s).
    vmax, amax, jmax : float or array_like, optional
        Velocity (rad/s), acceleration (rad/s^2) and jerk (rad/s^3) magnitude limits.

    Returns
    -------
    Trajectory
        One piece of degree 3 on ``[0, duration]``. ``info`` holds the duration and,
        with limits, each joint's own minimum duration and the limiting joint.

    Raises
    ------
    InvalidInputError
        Malformed arguments (NaN, wrong shapes, limits <= 0, no duration and no limit).
    InfeasibleError
        ``duration`` too short for the limits (the message gives the minimum), or a
        boundary velocity beyond ``vmax``.

    Examples
    --------
    >>> import numpy as np, trajkit as tk
    >>> tr = tk.cubic(np.radians([0, 0]), np.radians([67, -45]), vmax=np.radians([9, 11]))
    >>> round(tr.duration, 6)
    11.166667
    """
    return _boundary_polynomial(2, "cubic", (q0, v0, qf, vf), duration, (vmax, amax, jmax))


def quintic(
    q0: ArrayLike,
    qf: ArrayLike,
    duration: float | None = None,
    *,
    v0: ArrayLike = 0.0,
    vf: ArrayLike = 0.0,
    a0: ArrayLike = 0.0,
    af: ArrayLike = 0.0,
    vmax: ArrayLike | None = None,
    amax: ArrayLike | None = None,
    jmax: ArrayLike | None = None,
) -> Trajectory:
    """Fifth-order polynomial move matching position, velocity and acceleration at both ends.

    Parameters are those of :func:`cubic`, plus ``a0``, ``af``: start and end
    accelerations (rad/s^2). Returns one piece of degree 5.
    """
    return _boundary_polynomial(
        3, "quintic", (q0, v0, a0, qf, vf, af), duration, (vmax, amax, jmax)
    )


def septic(
    q0: ArrayLike,
    qf: ArrayLike,
    duration: float | None = None,
    *,
    v0: ArrayLike = 0.0,
    vf: ArrayLike = 0.0,
    a0: ArrayLike = 0.0,
    af: ArrayLike = 0.0,
    j0: ArrayLike = 0.0,
    jf: ArrayLike = 0.0,
    vmax: ArrayLike | None = None,
    amax: ArrayLike | None = None,
    jmax: ArrayLike | None = None,
) -> Trajectory:
    """Seventh-order polynomial move matching position to jerk at both ends.

    Parameters are those of :func:`quintic`, plus ``j0``, ``jf``: start and end
    jerks (rad/s^3). Returns one piece of degree 7.
    """
    return _boundary_polynomial(
        4, "septic", (q0, v0, a0, j0, qf, vf, af, jf), duration, (vmax, amax, jmax)
    )


Condition = tuple[float, int, ArrayLike]


def polynomial(
    conditions: Sequence[Condition] | Sequence[Sequence[Condition]],
    segments: ArrayLike | None = None,
    *,
    continuity: Sequence[Sequence[int]] | None = None,
    degrees: int | Sequence[int] | None = None,
) -> Trajectory:
    """Piecewise polynomial from boundary, interior and continuity conditions (``A a = b``).

    Every condition ``(time, order, value)`` says "the ``order``-th derivative at
    ``time`` (s, absolute) equals ``value``" (a number, or one per joint). The
    conditions become the rows of a square linear system whose unknowns are the
    coefficients of every piece; it is solved exactly once.

    Parameters
    ----------
    conditions : sequence
        With ``segments=None``: a flat sequence of conditions for one polynomial
        spanning the earliest to the latest condition time. With ``segments``: one
        sequence of conditions per segment, each time inside that segment.
    segments : array_like, shape (m + 1,), optional
        Breakpoints (s) of ``m`` segments, strictly increasing.
    continuity : sequence of sequences of int, optional
        For each of the ``m - 1`` interior breakpoints, the derivative orders that
        must be equal on both sides, e.g. ``[(1, 2)]`` for continuous velocity and
        acceleration at the one interior breakpoint. Positions are usually fixed by
        conditions on both sides and need not be listed.
    degrees : int or sequence of int, optional
        Polynomial degree of each segment. By default every segment gets the same,
        minimal degree that makes the system square (``equations / m - 1``); when the
        equations do not divide evenly among the segments, ``degrees`` must be given.

    Returns
    -------
    Trajectory
        ``m`` pieces on ``segments`` (or one piece), storage degree the largest.

    Raises
    ------
    InvalidInputError
        Malformed conditions, a time outside its segment, a system with more
        unknowns than equations (under-determined) or fewer (over-determined), or a
        singular system (the message says whether the conditions repeat each other
        or contradict each other).

    Examples
    --------
    Seed 004, example 1: 0 -> 0.5 rad on [0, 1] s, 0.5 -> 1 rad on [1, 3] s, at rest
    at both ends, passing t = 1 s at 0.2 rad/s.

    >>> import trajkit as tk
    >>> tr = tk.polynomial(
    ...     [[(0, 0, 0), (0, 1, 0), (1, 0, 0.5), (1, 1, 0.2)],
    ...      [(1, 0, 0.5), (1, 1, 0.2), (3, 0, 1), (3, 1, 0)]],
    ...     segments=[0, 1, 3])
    >>> tr.absolute_coefficients()[::-1, 1, 0].round(6).tolist()  # a0..a3 of piece 2
    [0.55, -0.375, 0.4, -0.075]
    """
    if isinstance(conditions, str | bytes) or not isinstance(conditions, Sequence):
        raise InvalidInputError("conditions must be a sequence of (time, order, value) tuples")
    if segments is None:
        per_segment = [_read_conditions("conditions", conditions)]
        times = [c[0] for c in per_segment[0]]
        if not times or min(times) == max(times):
            raise InvalidInputError(
                "conditions must span an interval: give conditions at two different times "
                "(or pass segments)"
            )
        breakpoints = np.array([min(times), max(times)])
    else:
        breakpoints = increasing_times("segments", segments)
        if len(conditions) != breakpoints.size - 1:
            raise InvalidInputError(
                f"conditions must hold one sequence per segment: {breakpoints.size - 1} "
                f"segments but {len(conditions)} sequences"
            )
        per_segment = [
            _read_conditions(f"conditions[{i}]", group) for i, group in enumerate(conditions)
        ]
    m = breakpoints.size - 1
    for i, group in enumerate(per_segment):
        for time, order, _ in group:
            if not breakpoints[i] <= time <= breakpoints[i + 1]:
                raise InvalidInputError(
                    f"condition (t={time:g} s, order {order}) lies outside segment {i} "
                    f"[{breakpoints[i]:g}, {breakpoints[i + 1]:g}] s"
                )
    joins = _read_continuity(continuity, m)
    equations = sum(len(g) for g in per_segment) + sum(len(j) for j in joins)
    ndof = count_dof(
        **{f"value {k}": v for k, (_, _, v) in enumerate(c for g in per_segment for c in g)}
    )
    degree_of = _segment_degrees(degrees, m, equations)
    unknowns = sum(d + 1 for d in degree_of)
    if unknowns != equations:
        kind = "under-determined" if unknowns > equations else "over-determined"
        raise InvalidInputError(
            f"the system is {kind}: {equations} equations (conditions + continuity) for "
            f"{unknowns} unknown coefficients (degrees {list(degree_of)}); "
            + (
                "add conditions or lower the degrees"
                if kind == "under-determined"
                else "remove conditions or raise the degrees"
            )
        )
    offsets = np.concatenate([[0], np.cumsum([d + 1 for d in degree_of])])
    A = np.zeros((equations, unknowns))
    b = np.zeros((equations, ndof))
    row = 0
    for i, group in enumerate(per_segment):
        for time, order, value in group:
            A[row, offsets[i] : offsets[i + 1]] = _derivative_row(
                degree_of[i], order, time - breakpoints[i]
            )
            b[row] = joint_vector(f"value at t={time:g} s", value, ndof)
            row += 1
    for j, orders in enumerate(joins):
        left, right = j, j + 1
        h = breakpoints[right] - breakpoints[left]
        for order in orders:
            A[row, offsets[left] : offsets[right]] = _derivative_row(degree_of[left], order, h)
            A[row, offsets[right] : offsets[right + 1]] -= _derivative_row(
                degree_of[right], order, 0.0
            )
            row += 1
    solution = _solve_square(A, b)
    finite_result("polynomial", solution, {"segments": breakpoints})
    storage = max(degree_of)
    c = np.zeros((storage + 1, m, ndof))
    for i, d in enumerate(degree_of):
        c[storage - d :, i, :] = solution[offsets[i] : offsets[i + 1]]
    info = {
        "planner": "polynomial",
        "degrees": tuple(degree_of),
        "equations": equations,
        "continuity": _claimed_continuity(joins, degree_of),
    }
    return Trajectory(breakpoints, c, info=info)


def _read_conditions(name: str, group: object) -> list[tuple[float, int, ArrayLike]]:
    if isinstance(group, str | bytes) or not isinstance(group, Sequence):
        raise InvalidInputError(f"{name} must be a sequence of (time, order, value) tuples")
    out = []
    for k, item in enumerate(group):
        if not isinstance(item, Sequence) or len(item) != 3:
            raise InvalidInputError(
                f"{name}[{k}] must be a (time, order, value) tuple, got {item!r}"
            )
        time, order, value = item
        time = finite_scalar(f"{name}[{k}] time", time, unit="s")
        if isinstance(order, bool) or not isinstance(order, int | np.integer) or order < 0:
            raise InvalidInputError(
                f"{name}[{k}] derivative order must be a whole number >= 0, got {order!r}"
            )
        finite_array(f"{name}[{k}] value", value)
        out.append((time, int(order), value))
    return out


def _claimed_continuity(joins: list[tuple[int, ...]], degrees: tuple[int, ...]) -> float:
    """The derivative order up to which every join is continuous by construction."""
    claim = math.inf
    for j, orders in enumerate(joins):
        k = -1
        while k + 1 in orders:
            k += 1
        # Equal up to both degrees: the same polynomial, every derivative continuous.
        if k < max(degrees[j], degrees[j + 1]):
            claim = min(claim, k)
    return claim


def _read_continuity(continuity: Sequence[Sequence[int]] | None, m: int) -> list[tuple[int, ...]]:
    if continuity is None:
        return [() for _ in range(m - 1)]
    if isinstance(continuity, str | bytes) or not isinstance(continuity, Sequence):
        raise InvalidInputError(
            "continuity must be a sequence of sequences of derivative orders, one per interior "
            f"breakpoint, got {continuity!r}"
        )
    if len(continuity) != m - 1:
        raise InvalidInputError(
            f"continuity must give one sequence of derivative orders per interior "
            f"breakpoint: {m - 1} expected, got {len(continuity)}"
        )
    joins = []
    for j, orders in enumerate(continuity):
        if isinstance(orders, str | bytes) or not isinstance(orders, Sequence):
            raise InvalidInputError(
                f"continuity[{j}] must be a sequence of derivative orders, got {orders!r}"
            )
        orders = tuple(orders)
        for order in orders:
            if isinstance(order, bool) or not isinstance(order, int | np.integer) or order < 0:
                raise InvalidInputError(
                    f"continuity[{j}] must hold derivative orders (whole numbers >= 0), "
                    f"got {order!r}"
                )
        if len(set(orders)) != len(orders):
            raise InvalidInputError(f"continuity[{j}] repeats an order: {orders}")
        joins.append(tuple(int(o) for o in orders))
    return joins


def _segment_degrees(
    degrees: int | Sequence[int] | None, m: int, equations: int
) -> tuple[int, ...]:
    if degrees is None:
        if equations % m:
            raise InvalidInputError(
                f"{equations} equations do not divide evenly among {m} segments; "
                "pass degrees= to say each segment's polynomial degree"
            )
        return (equations // m - 1,) * m
    if isinstance(degrees, int | np.integer):
        values = (degrees,) * m
    elif isinstance(degrees, Sequence | np.ndarray) and not isinstance(degrees, str | bytes):
        values = tuple(degrees)
    else:
        values = ()  # refused below, by the same message
    if len(values) != m or any(
        isinstance(d, bool) or not isinstance(d, int | np.integer) or d < 0 for d in values
    ):
        raise InvalidInputError(
            f"degrees must be a whole number >= 0 or one per segment ({m}), got {degrees!r}"
        )
    return tuple(int(d) for d in values)


def _derivative_row(degree: int, order: int, x: float) -> FloatArray:
    """Row of ``A``: the ``order``-th derivative of each basis power at local ``x``."""
    powers = np.arange(degree, -1, -1)
    row = np.zeros(degree + 1)
    alive = powers >= order
    p = powers[alive]
    falling = np.array([factorial(int(k)) // factorial(int(k) - order) for k in p], dtype=float)
    row[alive] = falling * np.power(x, p - order)
    return row


def _solve_square(A: FloatArray, b: FloatArray) -> FloatArray:
    """Solve ``A a = b``, naming the trouble when ``A`` is singular.

    Rows and columns are scaled to unit largest entry first: powers of long or
    short segments span many decades, and an unscaled rank test would call a
    well-posed 1000 s quintic singular.
    """
    column_scale = np.abs(A).max(axis=0)
    column_scale[column_scale == 0] = 1.0
    A = A / column_scale
    row_scale = np.abs(A).max(axis=1)
    row_scale[row_scale == 0] = 1.0
    A, b = A / row_scale[:, np.newaxis], b / row_scale[:, np.newaxis]
    singular_values = np.linalg.svd(A, compute_uv=False)
    if singular_values[-1] <= 1e-12 * singular_values[0]:
        solution, *_ = np.linalg.lstsq(A, b, rcond=None)
        residual = np.abs(A @ solution - b).max()
        scale = max(np.abs(b).max(), 1.0)
        what = (
            "contradict each other (no polynomial meets them all)"
            if residual > 1e-9 * scale
            else "repeat each other (some say nothing new), so the solution is not unique"
        )
        raise InvalidInputError(
            f"the system is singular: the conditions {what}; "
            f"rank {int(np.sum(singular_values > 1e-12 * singular_values[0]))} of {A.shape[0]}"
        )
    return np.linalg.solve(A, b) / column_scale[:, np.newaxis]
