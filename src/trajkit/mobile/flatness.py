"""Differential flatness: a unicycle's twist from any smooth path ``(x(t), y(t))``.

The position of a unicycle is a flat output: from it and its derivatives,

    θ = atan2(ẏ, ẋ),   v = √(ẋ² + ẏ²),   ω = (ẋ ÿ − ẏ ẍ) / (ẋ² + ẏ²),

and ``dv/dt``, ``dω/dt`` follow with the third derivatives. Where the speed
vanishes the heading is undefined: at the ends of the curve it is the limit of
the direction of travel; inside, :func:`flat_trajectory` refuses the curve
unless asked to stop and turn in place there, or to drive on in reverse.

Limits on curves are checked on a dense grid (4,001 points per segment plus
the output's breakpoints) whose extreme points are refined by bounded scalar
search to about 1e-12 of the segment's duration: a curve is not a polynomial
in general, so there are no closed-form extrema.
"""

from __future__ import annotations

from abc import abstractmethod
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from trajkit._validation import FloatArray, finite_array, increasing_times, positive_scalar
from trajkit.curve import Curve
from trajkit.errors import InfeasibleError, InvalidInputError
from trajkit.mobile.limits import MobileLimits, check_limits
from trajkit.mobile.models import Model, resolve_model, wrap_angle
from trajkit.mobile.plans import plan_phase
from trajkit.mobile.trajectory import (
    LocalState,
    MobileTrajectory,
    Segment,
    Turn,
    limited_channels,
)
from trajkit.profiles import cubic_spline
from trajkit.trajectory import Trajectory

__all__ = [
    "FigureEight",
    "FlatOutput",
    "TrajectoryOutput",
    "flat_trajectory",
    "spline_output",
]

Timing = Literal["as_given", "within_limits", "fastest"]
Stops = Literal["error", "turn", "reverse"]

_GRID = 4001  # grid points per curve segment for stops and extrema
_REFINED_PEAKS = 8  # how many of the grid's best local extrema are refined
_STOP = 1e-9  # a speed below this fraction of the peak speed is a stop
_NEAR_STOP = 1e-4  # near a stop and below this fraction of the peak speed, use its series
_SERIES_TERMS = 12  # derivatives of the output in the series at a stop
_ONE_SIDED = 1e-13  # the series at a stop is taken this fraction of the span inside
_INWARD = 1e-7  # directions of travel around a stop are read this fraction of the span away
# A figure eight's slowest speed (at its turns) is about 2 min(W, H) / max(W, H) of its
# peak: past this ratio it nears the stop threshold, where the heading is ill-conditioned.
_MAX_ASPECT = 1e6
# The twist of a flat output multiplies up to four of its derivatives (|ṗ|⁴ divides
# dω/dt): beyond this magnitude such products overflow float64 (or vanish below its
# reciprocal), and the result would be inf or NaN.
_LARGEST = 1e60


class FlatOutput(Curve):
    """A smooth planar curve in time, ``p(t) = (x(t), y(t))`` for ``t`` in [0, duration]."""

    @property
    @abstractmethod
    def duration(self) -> float:
        """Length of the time interval (s)."""

    @property
    def end_time(self) -> float:
        """The duration (s): flat outputs start at 0."""
        return self.duration

    components = (("x", "m"), ("y", "m"))

    @abstractmethod
    def evaluate(self, t: FloatArray, order: int = 0) -> FloatArray:
        """The ``order``-th time derivative (any order >= 0) at times ``t`` (n,): (n, 2)."""


class FigureEight(FlatOutput):
    """The figure-eight of seed 002: ``x = W/2 sin(2πt/T)``, ``y = H/2 sin(4πt/T)``.

    Parameters
    ----------
    width, height : float
        Extent W and H of the curve (m), > 0.
    period : float
        Time T of one loop (s), > 0.
    center : array_like
        Where the curve crosses itself (m).
    cycles : float
        How many periods the output lasts (> 0).
    """

    def __init__(
        self,
        width: float,
        height: float,
        period: float,
        *,
        center: ArrayLike = (0.0, 0.0),
        cycles: float = 1.0,
    ) -> None:
        self.width = positive_scalar("width", width, unit="m")
        self.height = positive_scalar("height", height, unit="m")
        self.period = positive_scalar("period", period, unit="s")
        self.cycles = positive_scalar("cycles", cycles)
        middle = finite_array("center", center)
        if middle.shape != (2,):
            raise InvalidInputError(f"center must be (x, y) in m, got shape {middle.shape}")
        self.center = np.array(middle)
        size = f"width {self.width:g} m and height {self.height:g} m"
        if max(self.width, self.height) > _MAX_ASPECT * min(self.width, self.height):
            raise InvalidInputError(
                f"{size}: one may be at most {_MAX_ASPECT:g} times the other (a flatter "
                "figure eight all but stops at its turns, where its heading is undefined)"
            )
        # Checked on the parameters, before any sampling: the peak of the k-th
        # derivative is w^k sqrt((W/2)^2 + (2^k H/2)^2), for the orders flatness uses.
        w = 2.0 * np.pi / self.period
        with np.errstate(over="ignore", under="ignore"):
            orders = np.arange(1, _SERIES_TERMS + 1, dtype=float)
            peaks = w**orders * np.hypot(self.width / 2.0, 2.0**orders * self.height / 2.0)
        if not (np.all(peaks <= _LARGEST) and peaks[0] >= 1.0 / _LARGEST):
            raise InvalidInputError(
                f"a figure eight of {size} and period {self.period:g} s moves too fast or too "
                f"slowly for float arithmetic (its peak speed is {peaks[0]:.3g} m/s; derivatives "
                f"up to order {_SERIES_TERMS} must stay within {1.0 / _LARGEST:g} to "
                f"{_LARGEST:g}): change the size or the period"
            )

    @property
    def duration(self) -> float:  # noqa: D102
        return self.period * self.cycles

    def evaluate(self, t: FloatArray, order: int) -> FloatArray:  # noqa: D102
        w = 2.0 * np.pi / self.period
        shift = order * np.pi / 2.0  # d^k/dt^k sin(c t) = c^k sin(c t + k π/2)
        x = self.width / 2.0 * w**order * np.sin(w * t + shift)
        y = self.height / 2.0 * (2.0 * w) ** order * np.sin(2.0 * w * t + shift)
        out = np.stack([x, y], axis=-1)
        return out + self.center if order == 0 else out


class TrajectoryOutput(FlatOutput):
    """A 2-DoF :class:`~trajkit.Trajectory` read as ``(x(t), y(t))`` in metres."""

    def __init__(self, trajectory: Trajectory) -> None:
        if not isinstance(trajectory, Trajectory) or trajectory.ndof != 2:
            raise InvalidInputError("a flat output trajectory must be a 2-DoF Trajectory (x, y)")
        if trajectory.duration <= 0.0:
            raise InvalidInputError("a flat output trajectory must last longer than 0 s")
        self.trajectory = trajectory

    @property
    def duration(self) -> float:  # noqa: D102
        return self.trajectory.duration

    @property
    def breakpoints(self) -> FloatArray:  # noqa: D102
        return self.trajectory.breakpoints - self.trajectory.start_time

    def evaluate(self, t: FloatArray, order: int) -> FloatArray:  # noqa: D102
        return self.trajectory.evaluate(self.trajectory.start_time + t, order)


def spline_output(waypoints: ArrayLike, times: ArrayLike | None = None) -> TrajectoryOutput:
    """A C2 cubic spline through ``waypoints`` (n, 2), at rest at both ends.

    Parameters
    ----------
    waypoints : array_like, shape (n, 2)
        Points (m), n >= 2; consecutive points must differ.
    times : array_like, shape (n,), optional
        When each point is passed (s). Default: the cumulative chord length in
        metres read as seconds (1 m/s on average); :func:`flat_trajectory` with
        ``timing="fastest"`` then rescales it to the limits.
    """
    points = finite_array("waypoints", waypoints)
    if points.ndim != 2 or points.shape[1] != 2 or points.shape[0] < 2:
        raise InvalidInputError(
            f"waypoints must have shape (n, 2) with n >= 2 (x, y in m), got shape {points.shape}"
        )
    chords = np.hypot(*np.diff(points, axis=0).T)
    if np.any(chords == 0.0):
        i = int(np.flatnonzero(chords == 0.0)[0])
        raise InvalidInputError(f"waypoints {i} and {i + 1} are the same point")
    if times is None:
        when = np.concatenate([[0.0], np.cumsum(chords)])
    else:
        when = increasing_times("times", times)
        if when.size != points.shape[0]:
            raise InvalidInputError(
                f"times must give one time per waypoint ({points.shape[0]}), got {when.size}"
            )
    return TrajectoryOutput(cubic_spline(when, points, v0=0.0, vf=0.0))


def _flat_state(p1: FloatArray, p2: FloatArray, p3: FloatArray, sign: float) -> LocalState:
    """θ, v, ω, dv/dt, dω/dt from the output's derivatives; ``sign`` -1 drives backwards."""
    speed2 = np.einsum("ij,ij->i", p1, p1)
    speed = np.sqrt(speed2)
    cross = p1[:, 0] * p2[:, 1] - p1[:, 1] * p2[:, 0]
    dot = np.einsum("ij,ij->i", p1, p2)
    cross_rate = p1[:, 0] * p3[:, 1] - p1[:, 1] * p3[:, 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        omega = cross / speed2
        acceleration = sign * dot / speed
        angular_acceleration = (cross_rate * speed2 - 2.0 * cross * dot) / speed2**2
    theta = np.arctan2(sign * p1[:, 1], sign * p1[:, 0])
    return theta, sign * speed, omega, acceleration, angular_acceleration


class FlatSegment(Segment):
    """A piece ``[t_from, t_to]`` of a flat output, slowed by ``scale``, in one direction.

    Local time ``τ`` runs over ``[0, scale (t_to - t_from)]``; the output is read
    at ``t_from + τ / scale``. ``sign`` -1 drives it backwards; ``heading_near``
    picks the turn count of the heading at the start (continuity with the previous
    segment).
    """

    kind = "flat"

    def __init__(
        self,
        output: FlatOutput,
        t_from: float,
        t_to: float,
        scale: float,
        sign: float,
        heading_near: float | None,
    ) -> None:
        self.output, self.t_from, self.t_to = output, t_from, t_to
        self.scale, self.sign = scale, sign
        self.duration = scale * (t_to - t_from)
        inside = output.breakpoints[(output.breakpoints > t_from) & (output.breakpoints < t_to)]
        grid = np.union1d(np.linspace(t_from, t_to, _GRID), inside)
        self._grid = (grid - t_from) * scale  # local times
        self._theta_grid: FloatArray | None = None
        speeds = np.linalg.norm(output.evaluate(grid, 1), axis=1)
        self._peak_speed = float(speeds.max()) or 1.0
        span = t_to - t_from
        self._stops = []  # the ends where the output stops, with its series there
        fast = np.flatnonzero(speeds > _NEAR_STOP * self._peak_speed)
        for t_stop, side in ((t_from, 1.0), (t_to, -1.0)):
            near = np.array([t_stop + side * _ONE_SIDED * span])
            if np.linalg.norm(output.evaluate(near, 1)) <= _STOP * self._peak_speed:
                # The series serve up to where the speed first rises past the switch,
                # not a later dip (a near-stop), which the closed forms handle.
                edge = grid[fast[0]] if side > 0 else grid[fast[-1]]
                reach = abs(edge - t_stop) if fast.size else span / 2
                # ... and no further than the output's piece at the stop: past a
                # breakpoint the series of that piece does not describe it.
                pieces = np.abs(inside - t_stop)
                if pieces.size:
                    reach = min(reach, float(pieces.min()))
                self._stops.append(_StopSeries(output, t_stop, side, span, self._peak_speed, reach))
        raw = self._state(self._grid, unwrap=False)
        theta = np.unwrap(raw[2])
        if heading_near is not None:
            theta += 2.0 * np.pi * np.round((heading_near - theta[0]) / (2.0 * np.pi))
        self._theta_grid = theta
        self._table = (*raw[:2], theta, *raw[3:])
        self.start_pose = np.array([self._table[0][0], self._table[1][0], theta[0]])

    def _state(self, tau: FloatArray, *, unwrap: bool = True) -> LocalState:
        k = self.scale
        # Clipped: scaling by k and back can land an ulp outside the segment.
        t = np.clip(self.t_from + np.asarray(tau, dtype=float) / k, self.t_from, self.t_to)
        position = self.output.evaluate(t, 0)
        p1, p2, p3 = (self.output.evaluate(t, order) for order in (1, 2, 3))
        theta, v, omega, acceleration, angular_acceleration = _flat_state(p1, p2, p3, self.sign)
        slow = np.abs(v) <= _NEAR_STOP * self._peak_speed
        for stop in self._stops:
            # The formulas divide by the speed: near a stop its Taylor series replace them.
            after = (t - stop.time) * stop.side
            near = slow & (after >= 0.0) & (after <= stop.reach)
            if np.any(near):
                series = stop.state(t[near] - stop.time, self.sign)
                theta[near], omega[near] = series[0], series[1]
                acceleration[near], angular_acceleration[near] = series[2], series[3]
        if unwrap and self._theta_grid is not None:
            reference = np.interp(tau, self._grid, self._theta_grid)
            theta = theta + 2.0 * np.pi * np.round((reference - theta) / (2.0 * np.pi))
        return (
            position[:, 0],
            position[:, 1],
            theta,
            v / k,
            omega / k,
            acceleration / k**2,
            angular_acceleration / k**2,
        )

    def local_state(self, tau: FloatArray) -> LocalState:
        return self._state(tau)

    @property
    def end_pose(self) -> FloatArray:
        return np.array([self._table[0][-1], self._table[1][-1], self._theta_grid[-1]])

    def extrema(self, order: int, cv: float, cw: float) -> tuple[float, float, float, float]:
        from scipy.optimize import minimize_scalar  # slow to import: on first use

        index = (3, 4) if order == 1 else (5, 6)

        def value(tau: FloatArray) -> FloatArray:
            state = self._state(np.atleast_1d(tau))
            return cv * state[index[0]] + cw * state[index[1]]

        grid = self._grid
        values = cv * self._table[index[0]] + cw * self._table[index[1]]
        result = []
        for sign in (1.0, -1.0):  # minimum, then maximum
            best_t, best = float(grid[0]), float(values[0])
            # Symmetric curves have several near-equal peaks, and the grid may rank
            # them wrongly: refine the few best local extrema, not just the first.
            for i in _local_minima(sign * values)[:_REFINED_PEAKS]:
                lo, hi = grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]
                candidate_t, candidate = float(grid[i]), float(values[i])
                if hi > lo:
                    found = minimize_scalar(
                        lambda x, s=sign: s * float(value(x)[0]),
                        bounds=(lo, hi),
                        method="bounded",
                        options={"xatol": 1e-12 * max(self.duration, 1e-300)},
                    )
                    if found.fun < sign * candidate:  # found.fun is sign * value
                        candidate_t, candidate = float(found.x), float(sign * found.fun)
                if sign * candidate < sign * best:
                    best_t, best = candidate_t, candidate
            result.append((best, best_t))
        (low, t_low), (high, t_high) = result
        return low, t_low, high, t_high


def _local_minima(values: FloatArray) -> FloatArray:
    """Indices of the grid's local minima (ends included), lowest first."""
    left = np.concatenate([[True], values[1:] <= values[:-1]])
    right = np.concatenate([values[:-1] <= values[1:], [True]])
    found = np.flatnonzero(left & right)
    return found[np.argsort(values[found], kind="stable")]


class _StopSeries:
    """The output's motion around a stop, from its Taylor series there.

    With ``τ`` the time from the stop, ``ṗ(τ) = Σ c_j τ^j`` (``c_0 = 0``; the
    first nonzero ``c_m`` gives the order: ``m = 1`` for a stop with
    acceleration). ``ω = (ṗ × p̈) / |ṗ|²`` is then a ratio of two series with the
    same leading power ``τ^(2m)``, which cancels: evaluating the ratio of the
    remaining series avoids the 0/0 and the cancellation of the closed forms.
    Derivatives 1 to 12 are used, so ``ω`` is exact to ``O(τ^(11-m))`` (exactly
    for a polynomial output of degree up to 12).

    ``side`` is +1 for a stop at the start of a segment (the motion after it), -1
    for one at the end (the motion before it); the derivatives are taken on that
    side, since a stop at a breakpoint of a piecewise output has two series.
    """

    def __init__(
        self,
        output: FlatOutput,
        time: float,
        side: float,
        span: float,
        peak: float,
        reach: float,
    ) -> None:
        self.time, self.side, self.reach = time, side, reach
        near = np.array([time + side * _ONE_SIDED * span])
        derivatives = np.array(
            [output.evaluate(near, order)[0] for order in range(1, _SERIES_TERMS + 1)]
        )
        factorials = np.cumprod([1.0, *range(1, derivatives.shape[0])])
        series = derivatives / factorials[:, np.newaxis]
        series[0] = 0.0  # the speed vanishes here by definition
        # A coefficient counts when its term reaches 1e-9 of the peak speed over the
        # segment (the same rule whatever the unit of time), and 1e-11 of the largest
        # term: below that it is the rounding of the others (an output composed with a
        # timing, say), and would set the stop's order wrongly.
        size = np.linalg.norm(series, axis=1) * span ** np.arange(series.shape[0])
        nonzero = np.flatnonzero(size > max(1e-9 * peak, 1e-11 * size.max()))
        if nonzero.size == 0 or nonzero[0] > _SERIES_TERMS - 4:
            raise InfeasibleError(
                f"the flat output rests at t={time:.6g} s with no derivative up to the "
                f"{_SERIES_TERMS - 2}th "
                "to give a heading (does it stand still for a while?); remove the pause"
            )
        m = int(nonzero[0])
        series[:m] = 0.0  # lower orders are rounding noise that would steer the heading
        self.series, self.order = series, m
        self.rate = series[1:] * np.arange(1, series.shape[0])[:, np.newaxis]  # p̈(τ)
        numerator = np.convolve(series[:, 0], self.rate[:, 1]) - np.convolve(
            series[:, 1], self.rate[:, 0]
        )
        denominator = np.convolve(series[:, 0], series[:, 0]) + np.convolve(
            series[:, 1], series[:, 1]
        )
        reliable = _SERIES_TERMS - 1 - m  # terms of the reduced series the derivatives fix
        self.numerator = numerator[2 * m : 2 * m + reliable]
        self.denominator = denominator[2 * m : 2 * m + reliable]

    def state(self, tau: FloatArray, sign: float) -> LocalState:
        """θ, ω, dv/dt, dω/dt at times ``tau`` from the stop (before time scaling)."""
        poly = np.polynomial.polynomial
        p1 = poly.polyval(tau, self.series).T  # (n, 2)
        p2 = poly.polyval(tau, self.rate).T
        # At the stop itself the direction of travel is that of c_m τ^m.
        lead = sign * self.side**self.order * self.series[self.order]
        at_stop = tau == 0.0
        direction = np.where(at_stop[:, np.newaxis], lead, sign * p1)
        theta = np.arctan2(direction[:, 1], direction[:, 0])
        speed = np.linalg.norm(p1, axis=1)
        with np.errstate(divide="ignore", invalid="ignore"):
            acceleration = sign * np.einsum("ij,ij->i", p1, p2) / speed
        first = self.series[1]
        at_rest = sign * self.side * float(np.linalg.norm(first)) if self.order == 1 else 0.0
        acceleration = np.where(at_stop, at_rest, acceleration)
        n, d = poly.polyval(tau, self.numerator), poly.polyval(tau, self.denominator)
        dn = poly.polyval(tau, poly.polyder(self.numerator))
        dd = poly.polyval(tau, poly.polyder(self.denominator))
        return theta, n / d, acceleration, (dn * d - n * dd) / d**2


def _stops(output: FlatOutput) -> tuple[list[float], float]:
    """Interior times where the output's speed vanishes, and its peak speed (m/s)."""
    from scipy.optimize import minimize_scalar  # slow to import: on first use

    grid = np.union1d(np.linspace(0.0, output.duration, 4 * _GRID), output.breakpoints)
    with np.errstate(over="ignore", invalid="ignore"):
        speed = np.linalg.norm(output.evaluate(grid, 1), axis=1)
    peak = float(speed.max())
    if not (np.all(np.isfinite(speed)) and peak <= _LARGEST):
        raise InvalidInputError(
            f"the flat output's speed reaches {peak:.3g} m/s: beyond {_LARGEST:g} m/s its "
            "twist cannot be computed in float arithmetic"
        )
    if peak == 0.0:
        raise InfeasibleError("the flat output never moves: a unicycle's heading is undefined")
    lows = np.flatnonzero(
        (speed[1:-1] <= speed[:-2]) & (speed[1:-1] <= speed[2:]) & (speed[1:-1] < 1e-3 * peak)
    )
    stops = []
    for i in lows + 1:
        found = minimize_scalar(
            lambda t: float(np.linalg.norm(output.evaluate(np.array([t]), 1))),
            bounds=(grid[i - 1], grid[i + 1]),
            method="bounded",
            options={"xatol": 1e-14 * output.duration},
        )
        t, low = _refine_stop(output, float(found.x), float(found.fun), grid[i - 1], grid[i + 1])
        # A dip inside an end's own slow approach (a high-order rest, where rounding
        # makes ripples) is that end's stop, not one inside the curve.
        before, after = speed[: i + 1], speed[i:]
        inside = before.max() > _NEAR_STOP * peak and after.max() > _NEAR_STOP * peak
        if low <= _STOP * peak and inside:
            # Near a breakpoint the search ends a little off it (|ṗ| is flat there):
            # the stop is at the breakpoint, where the output's pieces meet.
            closest = output.breakpoints[np.argmin(np.abs(output.breakpoints - t))]
            near = abs(closest - t) <= 1e-6 * output.duration
            stops.append(float(closest if near else t))
    return stops, peak


def _refine_stop(
    output: FlatOutput, t: float, speed: float, lo: float, hi: float
) -> tuple[float, float]:
    """Gauss–Newton steps on ``ṗ(t) = 0`` from a bounded search's ``t`` (s) and ``|ṗ|``.

    The bounded search stops about ``√eps |t|`` from the minimum, where a stop
    with ``p̈ ≠ 0`` (a cusp, or a stop with deceleration) still has a speed of
    ``√eps |t| |p̈|``; each step ``t -= (ṗ · p̈) / |p̈|²`` then squares the error.
    """
    for _ in range(8):
        p1 = output.evaluate(np.array([t]), 1)[0]
        p2 = output.evaluate(np.array([t]), 2)[0]
        curvature = float(p2 @ p2)
        if curvature == 0.0:
            break
        candidate = min(max(t - float(p1 @ p2) / curvature, lo), hi)
        lower = float(np.linalg.norm(output.evaluate(np.array([candidate]), 1)))
        if not lower < speed:
            break
        t, speed = candidate, lower
    return t, speed


def _direction(output: FlatOutput, t: float, side: float, span: float) -> float:
    """Direction of travel (rad) just after (``side`` +1) or before (-1) the time ``t``."""
    p1 = output.evaluate(np.array([t + side * _INWARD * span]), 1)[0]
    return float(np.arctan2(p1[1], p1[0]))


def flat_trajectory(
    output: FlatOutput | Trajectory,
    *,
    model: Model | None = None,
    limits: MobileLimits | None = None,
    timing: Timing = "as_given",
    stops: Stops = "error",
) -> MobileTrajectory:
    """Drive a unicycle (or differential drive) along the flat output ``(x(t), y(t))``.

    Parameters
    ----------
    output : FlatOutput or Trajectory
        The curve: :class:`FigureEight`, :func:`spline_output`, any
        :class:`FlatOutput`, or a 2-DoF Trajectory of ``(x, y)`` in metres.
    model : Unicycle or DiffDrive, optional
        Default: a plain unicycle.
    limits : MobileLimits, optional
        Default: the model's. Used by ``timing`` and for turns at stops.
    timing : {"as_given", "within_limits", "fastest"}
        ``"as_given"`` keeps the output's timing (check the result);
        ``"within_limits"`` slows it down uniformly, if needed, just enough for
        every limit to hold; ``"fastest"`` scales it (faster or slower) so the
        tightest limit is reached.
    stops : {"error", "turn", "reverse"}
        Where the speed vanishes inside the curve: raise, stop and turn in place
        to the new direction (needs angular velocity and acceleration limits),
        or drive on backwards (where the curve reverses on itself, a cusp).
        A curve that still turns as it stops (ω ≠ 0 there) meets the inserted
        turn, which starts and ends at ω = 0, with a jump in ω: :meth:`check`
        reports it as an unbounded angular acceleration, and no time scaling
        removes it.

    Returns
    -------
    MobileTrajectory
        ``info`` holds ``time_scale`` (the uniform slow-down factor), ``stops``
        (times on the output's own clock) and ``limited_by`` (the limit that set
        the scale, if any).

    Raises
    ------
    InfeasibleError
        The curve stops inside (with ``stops="error"``, or a stop that reversing
        cannot pass), never moves, or a timing needs a limit that is missing.
    InvalidInputError
        A malformed output or option, or ``stops="turn"`` at a stop without the
        angular velocity and acceleration limits its turn needs.
    """
    if isinstance(output, Trajectory):
        output = TrajectoryOutput(output)
    if not isinstance(output, FlatOutput):
        raise InvalidInputError(
            f"output must be a FlatOutput or a 2-DoF Trajectory, got {type(output).__name__}"
        )
    if timing not in ("as_given", "within_limits", "fastest"):
        raise InvalidInputError(
            f"timing must be 'as_given', 'within_limits' or 'fastest', got {timing!r}"
        )
    if stops not in ("error", "turn", "reverse"):
        raise InvalidInputError(f"stops must be 'error', 'turn' or 'reverse', got {stops!r}")
    base = resolve_model(model)
    limits = check_limits(base.limits if limits is None else limits)
    found, _ = _stops(output)
    span = output.duration
    interior = [t for t in found if _INWARD * span * 10 < t < span * (1 - _INWARD * 10)]
    if interior and stops == "error":
        raise InfeasibleError(
            f"the flat output stops at t={interior[0]:.6g} s (its speed vanishes), where a "
            "unicycle's heading is undefined; pass stops='turn' to stop and turn in place "
            "there, or stops='reverse' to drive on backwards"
        )
    if interior and stops == "turn":
        missing = [
            a for a in ("angular_velocity", "angular_acceleration") if getattr(limits, a) is None
        ]
        if missing:
            raise InvalidInputError(
                f"stops='turn' turns in place at t={interior[0]:.6g} s, which needs limits with "
                f"{' and '.join(missing)} (rad/s, rad/s^2); got {limits!r}"
            )
    edges = [0.0, *interior, span]
    signs = [1.0]
    for t in interior:
        before, after = _direction(output, t, -1.0, span), _direction(output, t, 1.0, span)
        jump = float(wrap_angle(after - before))
        if stops == "reverse":
            if abs(abs(jump) - np.pi) < 1e-3:
                signs.append(-signs[-1])
            elif abs(jump) < 1e-3:
                signs.append(signs[-1])
            else:
                raise InfeasibleError(
                    f"at t={t:.6g} s the flat output turns by {np.degrees(jump):.4g} deg while "
                    "stopped; reversing cannot follow it, pass stops='turn'"
                )
        else:
            signs.append(signs[-1])

    def build(scale: float) -> list[Segment]:
        segments: list[Segment] = []
        for i, sign in enumerate(signs):
            heading = segments[-1].end_pose[2] if segments else None
            curve = FlatSegment(output, edges[i], edges[i + 1], scale, sign, heading)
            # The curve's heading is the turn count nearest the last: turns go the short way.
            turn = 0.0 if heading is None else float(curve.start_pose[2] - heading)
            if stops == "turn" and abs(turn) > 1e-9:
                law = plan_phase(f"turn at the stop at t={edges[i]:.6g} s", "turn", turn, limits,
                                 base)  # fmt: skip
                segments.append(Turn(segments[-1].end_pose, law))
            segments.append(curve)
        return segments

    segments = build(1.0)
    scale, limited_by = 1.0, None
    if timing != "as_given":
        scale, limited_by = _uniform_scale(segments, base, limits)
        if timing == "within_limits":
            scale = max(scale, 1.0)
            limited_by = limited_by if scale > 1.0 else None
        if scale != 1.0:
            segments = build(scale)
    info = {
        "plan": "flat_output",
        "time_scale": float(scale),
        "stops": tuple(interior),
        "limited_by": limited_by,
        "stops_treatment": stops,
    }
    return MobileTrajectory(segments, base, limits=limits, info=info)


def _uniform_scale(
    segments: list[Segment], model: Model, limits: MobileLimits
) -> tuple[float, str | None]:
    """Slow-down factor at which the curves' tightest limit is just reached.

    Rates (v, ω, wheel speeds) shrink with the factor, accelerations with its
    square; turns inserted at stops are planned at the limits and do not scale.
    """
    curves = [s for s in segments if isinstance(s, FlatSegment)]
    scale, which = 0.0, None
    for quantity, bounds, order, weights in limited_channels(limits, model):
        for _, cv, cw in weights:
            for curve in curves:
                low, t_low, high, t_high = curve.extrema(order, cv, cw)
                lower, upper = float(bounds.lower), float(bounds.upper)
                need = 0.0
                tiny = 1e-12 * max(abs(lower), abs(upper))
                for value, bound, when, side in ((high, upper, t_high, 1), (low, lower, t_low, -1)):
                    if side * value <= tiny:
                        continue  # the curve never goes this way
                    if side * bound <= 0.0:  # no slow-down reaches a side bounded at 0
                        raise InfeasibleError(
                            f"the curve needs {quantity} {value:.6g} (at t={when:.6g} s on its "
                            f"own clock) but the limit is ({lower:g}, {upper:g})"
                        )
                    need = max(need, value / bound)
                need = need if order == 1 else float(np.sqrt(need))
                if need > scale:
                    scale, which = need, quantity
    if which is None:
        raise InfeasibleError(
            "timing='within_limits' or 'fastest' needs at least one limit on velocity, angular "
            "velocity, their accelerations or the wheel speeds"
        )
    return scale, which
