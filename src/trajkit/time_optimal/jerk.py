"""Jerk-limited timing: the time-optimal profile, smoothed, then scaled to the limits.

A phase-plane timing has piecewise-constant ``s̈``, so its joint accelerations jump
at every grid point: unbounded jerk. This module makes an approximate but
guaranteed jerk-limited timing in three steps:

1. the velocity- and acceleration-optimal ``s(t)`` (:func:`trajkit.time_optimal.optimal_x`),
   at rest wherever the path's tangent or curvature jumps (there the jerk could
   not be bounded at speed);
2. between those rests, ``s`` is replaced by its moving average over a window
   ``w``: ``s_w(t) = (1/w) ∫ s`` over ``[t - w/2, t + w/2]`` (``s`` held at its end
   values outside). Then ``ṡ_w`` is the average of ``ṡ`` (still >= 0, so the path
   is kept and never run backwards), ``s̈_w`` is continuous and ``s⃛_w`` is bounded
   by the jumps of ``s̈`` over ``w``: the joint jerk
   ``q''' ṡ³ + 3 q'' ṡ s̈ + q' s⃛`` is bounded. ``s_w`` is a piecewise cubic, so
   ``q(s_w(t))`` is again an exact polynomial Trajectory, and it starts and ends at
   rest with zero acceleration;
3. its exact peaks of velocity, acceleration and jerk give the uniform time scale
   ``k = max(v / v_max, sqrt(a / a_max), cbrt(j / j_max))`` at which the tightest
   limit is just reached (velocity scales with ``1/k``, acceleration ``1/k²``,
   jerk ``1/k³``), so every limit holds by construction, checked exactly.

A few windows around ``a_max / j_max`` are tried, and the fastest result kept. The
result is not time-optimal under the jerk limit (that problem is not convex), but
it is feasible, smooth, and typically within tens of percent of the
velocity/acceleration optimum.
"""

from __future__ import annotations

import itertools

import numpy as np

from trajkit import _poly
from trajkit._validation import FloatArray
from trajkit.errors import InfeasibleError
from trajkit.limits import Limits
from trajkit.time_optimal.timing import compose, pieces_of, rest_states
from trajkit.tolerances import ROUNDING_RTOL
from trajkit.trajectory import Trajectory

__all__ = ["moving_average", "smoothed"]

#: Windows tried, as multiples of the typical a_max / j_max.
_WINDOWS = (0.5, 1.0, 2.0)


def smoothed(path: Trajectory, s: FloatArray, limits: Limits, stray: float) -> Trajectory:
    """The jerk-limited timing of ``path`` on the grid ``s`` (see the module notes).

    Parameters
    ----------
    path : Trajectory
        The path ``q(s)``, a polynomial.
    s : ndarray
        Grid points in ``s``.
    limits : Limits
        Velocity, acceleration and jerk bounds per joint.
    stray : float
        How far ``path`` strays from the user's path (recorded in ``info``).

    Returns
    -------
    Trajectory
        At rest with zero acceleration at both ends and at every rest; every limit
        holds exactly and the tightest is just reached.
    """
    from trajkit.time_optimal import _sides, jumps, optimal_x

    ndof = path.ndof
    velocity = _sides(limits, "velocity", ndof)
    acceleration = _sides(limits, "acceleration", ndof)
    jerk = _sides(limits, "jerk", ndof)
    rests = np.union1d(jumps(path, 1), jumps(path, 2))
    stops = np.searchsorted(s, rests)
    x, rounds, _ = optimal_x(path, s, velocity, acceleration, stops=stops)
    speed = np.sqrt(x)
    total = speed[:-1] + speed[1:]
    if np.any(total <= 0.0):
        raise InfeasibleError("the path speed vanishes on a whole interval: the path is not "
                              "traversable within the limits")  # fmt: skip
    durations = 2.0 * np.diff(s) / total
    u = (x[1:] - x[:-1]) / (2.0 * np.diff(s))
    # One rest-to-rest segment between consecutive stops.
    edges = np.union1d([0, s.size - 1], stops)
    typical = float(np.median(np.minimum(-acceleration[0], acceleration[1])
                              / np.minimum(-jerk[0], jerk[1])))  # fmt: skip
    checked = Limits(velocity=velocity, acceleration=acceleration, jerk=jerk)
    pieces: list[Trajectory] = []
    windows = []
    for first, last in itertools.pairwise(edges.tolist()):
        span = slice(first, last)
        best = None
        for factor in _WINDOWS:
            window = factor * typical
            curve = _segment(path, s[first : last + 1], speed[first:last], u[span],
                             durations[span], window)  # fmt: skip
            scale = _scale_to(curve, checked)
            if best is None or scale * curve.duration < best[0] * best[1].duration:
                best = (scale, curve, window)
        scale, curve, window = best
        pieces.append(curve.time_scaled(scale))
        windows.append(window * scale)
    result = pieces[0]
    for piece in pieces[1:]:
        result = result.then(piece)
    info = {"planner": "topp", "continuity": 2, "jerk_limited": True, "grid_points": s,
            "rests": rests, "windows": tuple(windows), "rounds": rounds,
            "path_error": stray}  # fmt: skip
    return Trajectory(result.breakpoints, result.coefficients, info=info,
                      **rest_states(path, s, (0.0, 0.0)))  # fmt: skip


def _scale_to(curve: Trajectory, limits: Limits) -> float:
    """The time scale at which the tightest of the limits is just reached."""
    report = curve.check(limits)
    need = 0.0
    for order, quantity in ((1, "velocity"), (2, "acceleration"), (3, "jerk")):
        need = max(need, float(report.ratios(quantity).max()) ** (1.0 / order))
    if not np.isfinite(need) or need <= 0.0:
        raise InfeasibleError("the smoothed timing has no finite peak to scale to the limits")
    return need * (1.0 + ROUNDING_RTOL)


def moving_average(times: FloatArray, sigma: FloatArray, window: float
                   ) -> tuple[FloatArray, FloatArray]:  # fmt: skip
    """The moving average over ``window`` of a piecewise polynomial held at its ends.

    Parameters
    ----------
    times : ndarray, shape (M + 1,)
        Breakpoints of ``f``.
    sigma : ndarray, shape (M, d + 1)
        ``f`` on each piece, ascending powers of the local time.
    window : float
        Width ``w`` > 0 of the average.

    Returns
    -------
    times, sigma
        ``f_w(t) = (1/w) ∫ f`` over ``[t - w/2, t + w/2]`` for ``t`` in
        ``[t_0 - w/2, t_M + w/2]``, re-based to start at 0, as piecewise polynomials
        of degree ``d + 1`` (ascending powers, local time).
    """
    half = window / 2.0
    start, end = float(times[0]), float(times[-1])
    value_start = sigma[0, 0]
    value_end = float(np.polynomial.polynomial.polyval(times[-1] - times[-2], sigma[-1]))
    # f extended by its end values over a window on either side.
    knots = np.concatenate([[start - window], times, [end + window]])
    degree = sigma.shape[1] - 1
    pieces = np.zeros((sigma.shape[0] + 2, degree + 1))
    pieces[0, 0], pieces[-1, 0] = value_start, value_end
    pieces[1:-1] = sigma
    # Antiderivative on each piece (ascending), continuous across pieces.
    integral = np.zeros((pieces.shape[0], degree + 2))
    integral[:, 1:] = pieces / np.arange(1, degree + 2)
    lengths = np.diff(knots)
    areas = np.polynomial.polynomial.polyval(lengths, integral.T, tensor=False)
    integral[:, 0] = np.concatenate([[0.0], np.cumsum(areas)[:-1]])
    # The average's pieces: between every knot shifted by +-w/2, inside its span.
    edges = np.union1d(knots + half, knots - half)
    edges = edges[(edges >= start - half) & (edges <= end + half)]
    edges = _distinct(np.union1d(edges, [start - half, end + half]))
    middles = (edges[:-1] + edges[1:]) / 2.0
    out = np.zeros((middles.size, degree + 2))
    for sign in (1.0, -1.0):  # (F(t + w/2) - F(t - w/2)) / w
        where = np.clip(np.searchsorted(knots, middles + sign * half, side="right") - 1, 0,
                        pieces.shape[0] - 1)  # fmt: skip
        shift = edges[:-1] + sign * half - knots[where]  # local time of each piece's start
        descending = integral[where][:, ::-1].T  # (d + 2, P)
        moved = _poly.shift_origin(descending, -shift)  # F(tau + shift)
        out += sign * moved[::-1].T
    return edges - edges[0], out / window


def _distinct(edges: FloatArray) -> FloatArray:
    """Sorted edges without the near-duplicates that shifted knots leave (1e-12 of the span).

    ``knot + w/2`` and ``knot' - w/2`` can be equal but for rounding; a piece between
    them would have no length.
    """
    keep = np.append(True, np.diff(edges) > ROUNDING_RTOL * (edges[-1] - edges[0]))
    keep[-1] = True
    out = edges[keep]
    if out.size > 2 and out[-1] - out[-2] <= ROUNDING_RTOL * (out[-1] - out[0]):
        out = np.delete(out, -2)
    return out


def _segment(path: Trajectory, s: FloatArray, speed: FloatArray, u: FloatArray,
             durations: FloatArray, window: float) -> Trajectory:  # fmt: skip
    """One rest-to-rest stretch of the path, timed by the smoothed ``s(t)``."""
    times = np.concatenate([[0.0], np.cumsum(durations)])
    sigma = np.stack([s[:-1], speed, u / 2.0], axis=1)  # absolute s, ascending in tau
    edges, average = moving_average(times, sigma, window)
    # Split where the smoothed s crosses the path's breakpoints, so that each time
    # piece lies in one path piece.
    inner = path.breakpoints[(path.breakpoints > s[0]) & (path.breakpoints < s[-1])]
    lengths = np.diff(edges)
    ends = np.polynomial.polynomial.polyval(lengths, average.T, tensor=False)
    cuts = []
    for value in inner:
        k = int(np.searchsorted(ends, value, side="left"))
        k = min(k, average.shape[0] - 1)
        shifted = average[k].copy()
        shifted[0] -= value
        roots = np.polynomial.polynomial.polyroots(shifted)
        real = roots.real[(np.abs(roots.imag) <= 1e-9 * max(lengths[k], 1e-300))]
        inside = real[(real > 0.0) & (real < lengths[k])]
        if inside.size:
            cuts.append(edges[k] + float(inside.min()))
    if cuts:
        fine = _distinct(np.union1d(edges, cuts))
        where = np.clip(np.searchsorted(edges, fine[:-1], side="right") - 1, 0,
                        average.shape[0] - 1)  # fmt: skip
        shift = fine[:-1] - edges[where]
        descending = _poly.shift_origin(average[where][:, ::-1].T, -shift)
        edges, average = fine, descending[::-1].T
    starts = np.polynomial.polynomial.polyval(0.0, average.T)
    middles = np.polynomial.polynomial.polyval(np.diff(edges) / 2.0, average.T, tensor=False)
    piece, _ = pieces_of(path, np.append(middles, s[-1]))
    relative = average.copy()
    relative[:, 0] = starts - path.breakpoints[piece]
    return compose(path, edges, relative, piece)
