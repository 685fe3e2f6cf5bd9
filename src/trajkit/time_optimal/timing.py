"""A path timed by a phase-plane profile: its exact polynomials and their peaks.

With ``x = ṡ²`` linear in ``s`` on each grid interval (``u = s̈`` constant there),
``s(t)`` is a quadratic in time, so a polynomial path ``q(s)`` timed by it is again
a polynomial, ``q(s(t))``, of twice the path's degree: the timed path is an
ordinary :class:`~trajkit.Trajectory` whose limits are checked exactly.
"""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType
from typing import Any, Protocol

import numpy as np

from trajkit import _poly
from trajkit._validation import FloatArray
from trajkit.errors import InfeasibleError, InvalidInputError
from trajkit.profiles.polynomial import hermite_pieces
from trajkit.trajectory import Trajectory

__all__ = [
    "GeometricPath",
    "as_polynomial",
    "compose",
    "interval_peaks",
    "phases",
    "pieces_of",
    "rest_states",
    "timed",
]

_NO_INFO: Mapping[str, Any] = MappingProxyType({})
#: Per interval and joint, shape (N, ndof): the least and the greatest joint velocity,
#: then the least and the greatest acceleration.
_Extremes = tuple[tuple[FloatArray, FloatArray], tuple[FloatArray, FloatArray]]


class GeometricPath(Protocol):
    """What :func:`~trajkit.time_optimal.topp` needs of a path that is not a Trajectory.

    ``breakpoints`` spans the path parameter's range (and marks where a derivative
    may jump); ``evaluate(s, order)`` gives the ``order``-th derivative in ``s``
    (orders 0 to 2) at the parameters ``s`` (n,), shape (n, ndof).
    """

    @property
    def breakpoints(self) -> FloatArray:
        """Parameters where a derivative may jump, from the first to the last."""
        ...

    def evaluate(self, s: FloatArray, order: int) -> FloatArray:
        """The ``order``-th derivative in ``s`` at the parameters ``s``, shape (n, ndof)."""
        ...


def as_polynomial(path: object, s: FloatArray) -> tuple[Trajectory, float]:
    """``path`` as a piecewise polynomial in ``s``, and how far it strays from it.

    A Trajectory is its own polynomial (stray 0). Any other path is replaced by the
    quintic Hermite spline through its position, first and second derivatives at
    the grid points ``s``; the stray is the largest distance between the two at
    the intervals' quarter and middle points (units of the path).

    Parameters
    ----------
    path : Trajectory or GeometricPath
    s : ndarray, shape (N + 1,)
        Grid points.

    Returns
    -------
    polynomial : Trajectory
    stray : float

    Raises
    ------
    InvalidInputError
        ``evaluate`` missing, failing, of the wrong shape, or not finite.
    """
    if isinstance(path, Trajectory):
        return path, 0.0
    if not callable(getattr(path, "evaluate", None)):
        raise InvalidInputError(
            "path must be a Trajectory or have evaluate(s, order) and breakpoints, got "
            f"{type(path).__name__}"
        )
    try:
        derivatives = np.stack([np.asarray(path.evaluate(s, k), dtype=float) for k in range(3)])
    except (TypeError, ValueError) as exc:
        raise InvalidInputError(f"path.evaluate(s, order) failed on the grid: {exc}") from None
    if derivatives.ndim != 3 or derivatives.shape[1] != s.size or derivatives.shape[2] == 0:
        raise InvalidInputError(
            f"path.evaluate(s, order) must return shape (len(s), ndof), got {derivatives.shape[1:]}"
        )
    if not np.all(np.isfinite(derivatives)):
        raise InvalidInputError("path.evaluate(s, order) returned NaN or inf on the grid")
    at_start, at_end = derivatives[:, :-1].copy(), derivatives[:, 1:].copy()
    # At the path's inner breakpoints a derivative may jump (a corner): there each
    # interval takes the derivatives of its own side, read a hair inside it.
    inner = np.asarray(path.breakpoints, dtype=float)[1:-1]
    where = np.flatnonzero(np.isin(s, inner))
    if where.size:
        hair = 1e-9 * (s[-1] - s[0])
        for k in (1, 2):
            after = np.asarray(path.evaluate(s[where] + hair, k), dtype=float)
            before = np.asarray(path.evaluate(s[where] - hair, k), dtype=float)
            size = max(float(np.abs(derivatives[k]).max()), 1.0)
            jump = np.abs(after - before).max(axis=1) > 1e-6 * size
            right, left = where[jump], where[jump]
            at_start[k, right[right < s.size - 1]] = after[jump][right < s.size - 1]
            at_end[k, left[left > 0] - 1] = before[jump][left > 0]
    pieces = hermite_pieces(at_start, at_end, np.diff(s)[:, None])
    polynomial = Trajectory(s, pieces)
    probes = (s[:-1, None] + np.diff(s)[:, None] * np.array([0.25, 0.5, 0.75])).ravel()
    stray = np.abs(polynomial.evaluate(probes) - np.asarray(path.evaluate(probes, 0))).max()
    return polynomial, float(stray)


def pieces_of(path: Trajectory, s: FloatArray) -> tuple[np.ndarray, FloatArray]:
    """The path piece each interval lies in, and the interval's offset into it."""
    from trajkit.time_optimal import _passes

    return _passes.pieces_of(np.ascontiguousarray(path.breakpoints, dtype=float),
                             np.ascontiguousarray(s, dtype=float))  # fmt: skip


def phases(s: FloatArray, x: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Path speed at the grid points, and each interval's duration and ``s̈``.

    With ``x = ṡ²`` linear in ``s`` on an interval, ``s̈`` is constant there and the
    interval takes ``2 Δs / (ṡ_i + ṡ_{i+1})``.

    Raises
    ------
    InfeasibleError
        The speed vanishes at both ends of an interval: it is never crossed.
    """
    from trajkit.time_optimal import _passes

    speed, durations, u, stalled = _passes.phases(np.ascontiguousarray(s, dtype=float),
                                                  np.ascontiguousarray(x, dtype=float))  # fmt: skip
    if stalled >= 0:
        _stalled()
    return speed, durations, u


def _stalled() -> None:
    raise InfeasibleError("the path speed vanishes on a whole interval: the path is not "
                          "traversable within the limits")  # fmt: skip


def timed(path: Trajectory, s: FloatArray, x: FloatArray) -> Trajectory:
    """``q(s(t))`` as a Trajectory, one piece per grid interval, starting at t = 0."""
    from trajkit.time_optimal import _passes

    # s(tau) - s_piece = offset + speed tau + u tau^2 / 2 on each interval (compiled).
    times, coefficients, stalled = _passes.timed_pieces(
        np.ascontiguousarray(path.coefficients, dtype=float),
        *(np.ascontiguousarray(a, dtype=float) for a in (path.breakpoints, s, x)))  # fmt: skip
    if stalled >= 0:
        _stalled()
    return _trajectory(times, coefficients)


def compose(path: Trajectory, times: FloatArray, sigma: FloatArray, piece: np.ndarray
            ) -> Trajectory:  # fmt: skip
    """``q(σ(τ))`` on every time piece: ``σ`` is the piece's polynomial in the local time.

    Parameters
    ----------
    path : Trajectory
    times : ndarray, shape (M + 1,)
        Breakpoints of the result.
    sigma : ndarray, shape (M, d + 1)
        On each time piece, the path parameter relative to the start of path piece
        ``piece[i]``, in ascending powers of the local time.
    piece : ndarray of int, shape (M,)
        The path piece each time piece lies in.

    Returns
    -------
    Trajectory
        The composed pieces, of degree ``k d`` for a path of degree ``k``.
    """
    from trajkit.time_optimal import _passes

    local = np.ascontiguousarray(path.coefficients[:, piece, :], dtype=float)  # (k + 1, M, ndof)
    coefficients = _passes.compose(local, np.ascontiguousarray(sigma, dtype=float))
    return _trajectory(np.array(times, dtype=float), coefficients)


def _trajectory(times: FloatArray, coefficients: FloatArray) -> Trajectory:
    """Timed pieces as a Trajectory: trusted if finite and increasing, else refused."""
    if np.isfinite(coefficients).all() and (times[1:] > times[:-1]).all():
        return Trajectory._trusted(times, coefficients, _NO_INFO)
    return Trajectory(times, coefficients)  # refuses it, saying what overflowed


def rest_states(
    path: Trajectory, s: FloatArray, speeds: tuple[float, float]
) -> dict[str, FloatArray]:
    """``start`` and ``end`` for the timed :class:`Trajectory` of ``path`` on ``s``.

    The path's positions at ``s[0]`` and ``s[-1]``, and a velocity of 0 where the
    path speed there (``speeds``) is 0, ``NaN`` (the pieces' own value) otherwise:
    the timed pieces' own end velocity is a rounding residue such as 3e-14 rad/s.
    """
    ends = path._end_positions() if (s[0], s[-1]) == (path.start_time, path.end_time) else (
        path.evaluate(s[[0, -1]]))  # fmt: skip
    still = np.array(speeds)[:, None] == 0.0
    states = np.stack([ends, np.where(still, 0.0, np.full(ends.shape, np.nan))], axis=1)
    return {"start": states[0], "end": states[1]}


def interval_peaks(
    path: Trajectory,
    s: FloatArray,
    x: FloatArray,
    velocity: tuple[FloatArray, FloatArray],
    acceleration: tuple[FloatArray, FloatArray],
) -> tuple[FloatArray, FloatArray]:
    """The largest ratio of joint velocity and of acceleration to its bound, per interval.

    Exact on the whole interval, from the polynomials' extrema (the sign of each
    value is matched with its side's bound). Cubic paths have closed forms; others
    are timed and their extrema found from the roots of the next derivative.

    Parameters
    ----------
    path : Trajectory
    s : ndarray, shape (N + 1,)
        Grid points.
    x : ndarray, shape (N + 1,)
        ``ṡ²`` at the grid points (1/s²).
    velocity, acceleration : tuple of ndarray, shape (ndof,)
        ``(lower, upper)`` bounds per joint.

    Returns
    -------
    ratio_v, ratio_a : ndarray, shape (N,)
        Per interval, the largest value-to-bound ratio (1 at the bound).
    """
    if path.degree <= 3:
        # Closed forms, without building the timed polynomials: on an interval x is
        # linear in s, so q̈ = q'' x + q' s̈ is a quadratic in σ = s - s_i (extremes at
        # the ends and the vertex), and q̇ = q' ṡ peaks at the ends or where q̈ vanishes.
        from trajkit.time_optimal import _passes

        contiguous = np.ascontiguousarray
        return _passes.cubic_ratios(
            contiguous(path.coefficients, dtype=float),
            *(contiguous(a, dtype=float) for a in (path.breakpoints, s, x, *velocity,
                                                   *acceleration)))  # fmt: skip
    extremes = _timed_extremes(path, s, x)
    ratios = [
        np.maximum(high / upper, low / lower).max(axis=1)
        for (low, high), (lower, upper) in zip(extremes, (velocity, acceleration), strict=True)
    ]
    return ratios[0], ratios[1]


def _timed_extremes(path: Trajectory, s: FloatArray, x: FloatArray) -> _Extremes:
    """The timed path's least and greatest velocity and acceleration, from its polynomials."""
    curve = timed(path, s, x)
    lengths = np.diff(curve.breakpoints)
    extremes = []
    for order in (1, 2):
        c = curve._coefficients_of(order)
        k1, m, ndof = c.shape
        low, _, high, _ = _poly.extrema_on_intervals(c.reshape(k1, m * ndof),
                                                     np.repeat(lengths, ndof))  # fmt: skip
        extremes.append((low.reshape(m, ndof), high.reshape(m, ndof)))
    return extremes[0], extremes[1]
