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

**Moving ends.** A non-zero start (or end) speed ``ṡ_0`` cannot survive a uniform
time scale, which would change it, nor an average that holds ``s`` at its end. So
there the profile is held at ``ṡ_0`` (``x <= ṡ_0²``) for the first half window
of time, ``s`` is continued before the start as ``s_0 + ṡ_0 t``, and the average,
which leaves a straight line unchanged, is cut at the start: it begins exactly at
``(s_0, ṡ_0, s̈ = 0)``. The limits are then met by tightening the velocity and
acceleration bounds the profile is computed under (by ``1/k`` and ``1/k²`` for
the scale ``k`` the peaks ask for) and computing it again, a few rounds at most.

**Torque and tool limits.** Step 1 keeps them as :func:`trajkit.time_optimal.topp`
does; the average then moves speed onto neighbouring stretches of the path, where a
torque or the tool's speed may pass its bound. So the smoothed result is measured
against them (16 samples a piece and a curvature margin, as ``check``), and a bound it
passes is moved in along the whole path, by the excess divided by the share of the
last move that reached the peak, and the timing made again. Step 3 then only slows
down: faster than the profile computed within those bounds would pass them again. A
uniform slow-down keeps them: the tool's speed and acceleration shrink with it, and a
torque ``g + d / k²`` moves from its value toward gravity's, which holds at every grid
point (or the timing is refused by name).
"""

from __future__ import annotations

import itertools

import numpy as np

from trajkit import _poly
from trajkit._validation import FloatArray
from trajkit.errors import InfeasibleError
from trajkit.limits import Limits
from trajkit.time_optimal.constraints import PathLimit
from trajkit.time_optimal.timing import compose, phases, pieces_of, rest_states
from trajkit.tolerances import ROUNDING_RTOL
from trajkit.trajectory import Trajectory

__all__ = ["moving_average", "smoothed"]

#: Windows tried, as multiples of the typical a_max / j_max.
_WINDOWS = (0.5, 1.0, 2.0)
#: Rounds of tightening the bounds for a timing with moving ends.
_ROUNDS = 8
#: A torque or tool bound moved in along the path keeps at least this share of the
#: room between the value at rest and the bound on every interval.
_KEEP = 0.01


def smoothed(path: Trajectory, s: FloatArray, limits: Limits, stray: float,
             speeds: tuple[float, float] = (0.0, 0.0),
             constraints: tuple[PathLimit, ...] = ()) -> Trajectory:  # fmt: skip
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
    speeds : tuple of float
        Path speeds at the start and the end (1/s).
    constraints : tuple of PathLimit
        Torque and tool limits, measured on the smoothed timing (module notes).

    Returns
    -------
    Trajectory
        With zero acceleration at both ends and at every rest, at rest there unless
        ``speeds`` says otherwise; every limit holds exactly, and at rest to rest
        the tightest is just reached.
    """
    from trajkit.time_optimal import _Band, _sides, jumps

    ndof = path.ndof
    velocity = _sides(limits, "velocity", ndof)
    acceleration = _sides(limits, "acceleration", ndof)
    jerk = _sides(limits, "jerk", ndof)
    rests = np.union1d(jumps(path, 1), jumps(path, 2))
    # The constraints' bounds, moved in along the whole path where a smoothed timing
    # passed them: one row, repeated on whatever grid the profile is computed on.
    moved = [_Band.of(limit, 1) for limit in constraints]
    if max(speeds) > 0.0:
        return _moving_ends(path, s, (velocity, acceleration, jerk), rests, stray, speeds,
                            constraints, moved)  # fmt: skip
    solves = 0
    for _ in range(_ROUNDS):
        result, windows, rounds = _rest_to_rest(path, s, (velocity, acceleration, jerk), rests,
                                                constraints, moved)  # fmt: skip
        solves += rounds
        checks = _measured(constraints, moved, result)
        if all(check.ok for check in checks):
            break
    else:
        _refuse(checks)
    info = {"planner": "topp", "continuity": 2, "jerk_limited": True, "grid_points": s,
            "rests": rests, "windows": windows, "rounds": solves, "path_error": stray}  # fmt: skip
    if constraints:
        info["constraint_checks"] = checks
    return Trajectory(result.breakpoints, result.coefficients, info=info,
                      **rest_states(path, s, (0.0, 0.0)))  # fmt: skip


def _rest_to_rest(
    path: Trajectory,
    s: FloatArray,
    bounds: tuple[tuple[FloatArray, FloatArray], ...],
    rests: FloatArray,
    constraints: tuple[PathLimit, ...],
    moved: list,
) -> tuple[Trajectory, tuple[float, ...], int]:
    """The smoothed timing from rest to rest, its windows (s) and the solves it took."""
    from trajkit.time_optimal import optimal_x

    velocity, acceleration, jerk = bounds
    limits = Limits(velocity=velocity, acceleration=acceleration, jerk=jerk)
    stops = np.searchsorted(s, rests)
    bands = _bands_on(constraints, moved, path, s)
    x, rounds, _, _ = optimal_x(path, s, velocity, acceleration, stops=stops,
                                constraints=constraints, bands=bands)  # fmt: skip
    speed, durations, u = phases(s, x)
    # One rest-to-rest segment between consecutive stops.
    edges = np.union1d([0, s.size - 1], stops)
    typical = _typical_window(acceleration, jerk)
    pieces: list[Trajectory] = []
    windows = []
    for first, last in itertools.pairwise(edges.tolist()):
        span = slice(first, last)
        best = None
        for factor in _WINDOWS:
            window = factor * typical
            curve = _segment(path, s[first : last + 1], speed[first:last], u[span],
                             durations[span], window)  # fmt: skip
            scale = _scale_to(curve, limits)
            if constraints:
                # Faster than the profile computed within the torque and tool bounds
                # would pass them again: slowed to the joint limits only.
                scale = max(scale, 1.0)
            if best is None or scale * curve.duration < best[0] * best[1].duration:
                best = (scale, curve, window)
        scale, curve, window = best
        pieces.append(curve.time_scaled(scale))
        windows.append(window * scale)
    result = pieces[0]
    for piece in pieces[1:]:
        result = result.then(piece)
    return result, tuple(windows), rounds


def _bands_on(constraints: tuple[PathLimit, ...], moved: list, path: Trajectory,
              s: FloatArray) -> list | None:  # fmt: skip
    """The moved bounds on every interval of the grid ``s`` (None without constraints).

    Moved along the whole path, a bound could pass what the arm needs at rest where it
    is far from binding (gravity's torque near its limit): no interval would then be
    crossed. So every interval keeps at least _KEEP of the room between the value at
    rest and the bound, at its ends and middle.
    """
    from trajkit.time_optimal import _Band, _collocated

    if not moved:
        return None
    q = _collocated(path, s)[1]
    still = np.zeros_like(q)
    out = []
    for limit, band in zip(constraints, moved, strict=True):
        lower, upper = limit.bounds()
        rest = limit.values(q, still, still).reshape(s.size - 1, -1, lower.size)
        # An unbounded side (the tool's lower) keeps its infinity.
        keep_hi = (rest + _KEEP * (upper - rest)).max(axis=1)
        keep_lo = (rest + _KEEP * (lower - rest)).min(axis=1)
        count = s.size - 1
        out.append(_Band(np.minimum(np.repeat(band.lower, count, axis=0), keep_lo),
                         np.maximum(np.repeat(band.upper, count, axis=0), keep_hi)))  # fmt: skip
    return out


def _measured(constraints: tuple[PathLimit, ...], moved: list, timing: Trajectory) -> list:
    """The constraints' reports of ``timing``; where one passes, its bounds move in."""
    from trajkit.time_optimal import _tighten

    if not constraints:
        return []
    return _tighten(constraints, moved, timing, per_interval=False)


def _refuse(checks: list) -> None:
    missed = "; ".join(str(v) for check in checks for v in check.violations)
    raise InfeasibleError(
        f"no jerk-limited timing on this grid keeps the torque and tool limits after "
        f"{_ROUNDS} rounds of tightening: {missed}; try another grid or looser limits"
    )


def _moving_ends(
    path: Trajectory,
    s: FloatArray,
    bounds: tuple[tuple[FloatArray, FloatArray], ...],
    rests: FloatArray,
    stray: float,
    speeds: tuple[float, float],
    constraints: tuple[PathLimit, ...] = (),
    moved: list | None = None,
) -> Trajectory:
    """The jerk-limited timing with a non-zero start or end speed (module notes)."""
    velocity, acceleration, jerk = bounds
    checked = Limits(velocity=velocity, acceleration=acceleration, jerk=jerk)
    typical = _typical_window(acceleration, jerk)
    moved = moved or []
    scale, failure = 1.0, ""
    # Rounds that scale the joint limits, and rounds that move the constraints in.
    rounds = scaled = moves = 0
    while scaled < _ROUNDS and moves < _ROUNDS:
        rounds += 1
        best, need = None, np.inf
        for factor in _WINDOWS:
            tightened = (tuple(side * scale for side in velocity),
                         tuple(side * scale**2 for side in acceleration))  # fmt: skip
            try:
                curve, grid = _held_ends(path, s, tightened, rests, speeds, factor * typical,
                                         constraints, moved)  # fmt: skip
                ask = _scale_to(curve, checked)
            except InfeasibleError as exc:
                failure = str(exc)
                continue
            if ask <= 1.0 and (best is None or curve.duration < best[0].duration):
                best = (curve, grid, factor * typical)
            need = min(need, ask)
        if best is not None:
            curve, grid, window = best
            checks = _measured(constraints, moved, curve)
            if not all(check.ok for check in checks):
                # The same scale again, the constraints moved in where the curve passed.
                failure = "; ".join(str(v) for check in checks for v in check.violations)
                moves += 1
                continue
            info = {"planner": "topp", "continuity": 2, "jerk_limited": True,
                    "grid_points": grid, "rests": rests, "windows": (window,),
                    "rounds": rounds, "path_error": stray}  # fmt: skip
            if constraints:
                info["constraint_checks"] = checks
            return Trajectory(curve.breakpoints, curve.coefficients, info=info,
                              **rest_states(path, s, speeds))  # fmt: skip
        if not np.isfinite(need):
            break
        scale /= need * (1.0 + 1e-3)
        scaled += 1
    raise InfeasibleError(
        f"no jerk-limited timing found with start_speed {speeds[0]:g} and end_speed "
        f"{speeds[1]:g}: {failure or 'the limits could not be met'}; lower speeds at the "
        "ends leave the timing more room"
    )


def _held_ends(
    path: Trajectory,
    s: FloatArray,
    bounds: tuple[tuple[FloatArray, FloatArray], tuple[FloatArray, FloatArray]],
    rests: FloatArray,
    speeds: tuple[float, float],
    window: float,
    constraints: tuple[PathLimit, ...] = (),
    moved: list | None = None,
) -> tuple[Trajectory, FloatArray]:
    """The smoothed timing under ``bounds``, held at the end speeds for half a window."""
    from trajkit.time_optimal import optimal_x

    half = window / 2.0
    start, end = float(s[0]), float(s[-1])
    # An end speed that covers no resolvable stretch of s in half a window is a rest.
    speeds = tuple(v if v * half > 1e-9 * (end - start) else 0.0 for v in speeds)  # type: ignore[assignment]
    # The stretches of s covered at the end speeds in half a window; the grid gets
    # their edges, and x is capped at the end speed's square on them.
    reach = (start + speeds[0] * half, end - speeds[1] * half)
    inner = [value for value in reach if start < value < end]
    grid = np.union1d(s, inner)
    if reach[0] >= reach[1] or (rests.size and (reach[0] >= rests.min()
                                                or reach[1] <= rests.max())):  # fmt: skip
        raise InfeasibleError("the path is too short to hold its end speeds for the "
                              "jerk limit's smoothing window")  # fmt: skip
    ceiling = np.full(grid.size, np.inf)
    held_start = grid <= reach[0] if speeds[0] > 0 else np.zeros(grid.size, dtype=bool)
    held_end = grid >= reach[1] if speeds[1] > 0 else np.zeros(grid.size, dtype=bool)
    ceiling[held_start] = speeds[0] ** 2
    ceiling[held_end] = speeds[1] ** 2
    stops = np.searchsorted(grid, rests)
    bands = _bands_on(constraints, moved or [], path, grid)
    x, _, _, _ = optimal_x(path, grid, *bounds, speeds, stops=stops, ceiling=ceiling,
                           constraints=constraints, bands=bands)  # fmt: skip
    for held, speed in ((held_start, speeds[0]), (held_end, speeds[1])):
        if np.any(x[held] < speed**2 * (1.0 - 1e-9)):
            raise InfeasibleError(f"the end speed {speed:g} cannot be held for the jerk "
                                  "limit's smoothing window within the limits")  # fmt: skip
        x[held] = speed**2  # held: s̈ = 0 there, exactly
    speed, durations, u = phases(grid, x)
    edges = np.union1d([0, grid.size - 1], stops).tolist()
    pieces = []
    for k, (first, last) in enumerate(itertools.pairwise(edges)):
        span = slice(first, last)
        moving = (speeds[0] if k == 0 else 0.0, speeds[1] if last == grid.size - 1 else 0.0)
        pieces.append(_segment(path, grid[first : last + 1], speed[first:last], u[span],
                               durations[span], window, moving))  # fmt: skip
    result = pieces[0]
    for piece in pieces[1:]:
        result = result.then(piece)
    return result, grid


def _typical_window(acceleration: tuple[FloatArray, FloatArray],
                    jerk: tuple[FloatArray, FloatArray]) -> float:  # fmt: skip
    """The median ``a_max / j_max`` over the joints (s): the scale of the windows tried."""
    return float(np.median(np.minimum(-acceleration[0], acceleration[1])
                           / np.minimum(-jerk[0], jerk[1])))  # fmt: skip


def _scale_to(curve: Trajectory, limits: Limits) -> float:
    """The time scale at which the tightest of the limits is just reached."""
    report = curve.check(limits)
    need = 0.0
    for order, quantity in ((1, "velocity"), (2, "acceleration"), (3, "jerk")):
        need = max(need, float(report.ratios(quantity).max()) ** (1.0 / order))
    if not np.isfinite(need) or need <= 0.0:
        raise InfeasibleError("the smoothed timing has no finite peak to scale to the limits")
    return need * (1.0 + ROUNDING_RTOL)


def moving_average(times: FloatArray, sigma: FloatArray, window: float,
                   rates: tuple[float, float] = (0.0, 0.0)
                   ) -> tuple[FloatArray, FloatArray]:  # fmt: skip
    """The moving average over ``window`` of a piecewise polynomial continued at its ends.

    Parameters
    ----------
    times : ndarray, shape (M + 1,)
        Breakpoints of ``f``.
    sigma : ndarray, shape (M, d + 1)
        ``f`` on each piece, ascending powers of the local time.
    window : float
        Width ``w`` > 0 of the average.
    rates : tuple of float
        ``f`` is continued before its start and after its end as straight lines of
        these slopes (0: held at its end values).

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
    pieces[0, 0], pieces[-1, 0] = value_start - rates[0] * window, value_end
    pieces[0, 1], pieces[-1, 1] = rates
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


def _cut_to_ends(edges: FloatArray, average: FloatArray, half: float,
                 moving: tuple[float, float]) -> tuple[FloatArray, FloatArray]:  # fmt: skip
    """The average from the original start to the original end where that end moves.

    It covers half a window before the start and after the end; where ``s`` was
    continued as a straight line, that half is cut off, exactly at the end's time.
    """
    first = half if moving[0] > 0.0 else float(edges[0])
    last = float(edges[-1]) - half if moving[1] > 0.0 else float(edges[-1])
    tiny = ROUNDING_RTOL * (edges[-1] - edges[0])  # an edge a rounding from a cut is the cut
    inside = edges[(edges > first + tiny) & (edges < last - tiny)]
    kept = np.concatenate([[first], inside, [last]])
    where = np.clip(np.searchsorted(edges, kept[:-1] + tiny, side="right") - 1, 0,
                    average.shape[0] - 1)  # fmt: skip
    shift = kept[:-1] - edges[where]
    descending = _poly.shift_origin(average[where][:, ::-1].T, -shift)
    return kept - first, descending[::-1].T


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
             durations: FloatArray, window: float,
             moving: tuple[float, float] = (0.0, 0.0)) -> Trajectory:  # fmt: skip
    """One stretch of the path between rests, timed by the smoothed ``s(t)``.

    ``moving`` gives the path speed at an end that does not rest: there ``s`` goes
    on as a straight line, and the average is cut at the end itself.
    """
    times = np.concatenate([[0.0], np.cumsum(durations)])
    sigma = np.stack([s[:-1], speed, u / 2.0], axis=1)  # absolute s, ascending in tau
    edges, average = moving_average(times, sigma, window, moving)
    if max(moving) > 0.0:
        edges, average = _cut_to_ends(edges, average, window / 2.0, moving)
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
