"""The fastest timing of a wheeled base along a fixed curve, under its twist and wheel limits.

The curve ``p(s)`` is a flat output read with its own time as the path parameter.
Along it, the base's speed, turn rate and wheel speeds are rates of *channels*
whose path derivatives follow from the curve's:

    v = σ'(s) ṡ,  ω = θ'(s) ṡ,  wheel = (v ± ω b/2) / r,

with ``σ' = |p'|`` (distance per unit of s) and ``θ' = (p' × p'') / |p'|²`` (turn per
unit of s), and ``dv/dt = σ'' ṡ² + σ' s̈`` likewise: exactly the structure of joint
limits, so :mod:`trajkit.time_optimal`'s reachability analysis times the curve. The
channels are not polynomials in ``s``; on each grid interval their rate is the
cubic Hermite interpolant of ``c'`` and ``c''`` at its ends.

The timed curve ``p(s(t))`` is an exact polynomial (the curve is replaced by its
quintic Hermite spline in ``s`` first when it is not a polynomial), driven by
:func:`flat_trajectory` with ``timing="within_limits"``: its own check of every
limit, on a dense grid refined at the peaks, slows the motion uniformly if the
interpolated channels let any limit pass by a hair, so the result keeps them.
"""

from __future__ import annotations

import numpy as np

from trajkit._validation import FloatArray
from trajkit.errors import InfeasibleError, InvalidInputError
from trajkit.mobile.flatness import (
    FlatOutput,
    Stops,
    TrajectoryOutput,
    _flat_state,
    flat_trajectory,
)
from trajkit.mobile.limits import MobileLimits, check_limits
from trajkit.mobile.models import Model, resolve_model
from trajkit.mobile.trajectory import MobileTrajectory, limited_channels
from trajkit.time_optimal import grid_points
from trajkit.time_optimal.reachability import Channels, Stages
from trajkit.time_optimal.timing import as_polynomial, timed
from trajkit.trajectory import Trajectory

__all__ = ["time_optimal"]


class _Curve:
    """A flat output as a path in ``s`` (what :func:`as_polynomial` reads)."""

    def __init__(self, output: FlatOutput) -> None:
        self.output = output
        self.breakpoints = output.breakpoints

    def evaluate(self, s: FloatArray, order: int) -> FloatArray:
        return self.output.evaluate(np.asarray(s, dtype=float), order)


def time_optimal(
    output: FlatOutput | Trajectory,
    *,
    model: Model | None = None,
    limits: MobileLimits | None = None,
    grid: int = 500,
    stops: Stops = "error",
) -> MobileTrajectory:
    """Drive along ``output``'s curve as fast as the base's limits allow, rest to rest.

    Parameters
    ----------
    output : FlatOutput or Trajectory
        The curve (its timing is ignored): :func:`spline_output`, a
        :class:`FigureEight`, any :class:`FlatOutput`, or a 2-DoF Trajectory (m).
    model : Unicycle or DiffDrive, optional
        Default: a plain unicycle.
    limits : MobileLimits, optional
        Default: the model's. Needs at least one of velocity or angular velocity
        (or wheel speed) and one of acceleration or angular acceleration; the
        lower side of each acceleration must be < 0 (the base has to stop).
    grid : int
        Grid intervals along the curve.
    stops : {"error", "turn", "reverse"}
        What to do where the curve stops inside, as in :func:`flat_trajectory`.

    Returns
    -------
    MobileTrajectory
        ``info`` holds ``plan`` ("time_optimal"), ``time_scale`` (the uniform
        slow-down the final check needed, 1 if none), ``grid_points`` (in the curve's
        own time) and ``path_error`` (how far the polynomial the timing follows
        strays from the curve, m).
    """
    if isinstance(output, Trajectory):
        output = TrajectoryOutput(output)
    if not isinstance(output, FlatOutput):
        raise InvalidInputError(
            f"output must be a FlatOutput or a 2-DoF Trajectory, got {type(output).__name__}"
        )
    base = resolve_model(model)
    limits = check_limits(base.limits if limits is None else limits)
    breakpoints = np.asarray(output.breakpoints, dtype=float)
    if isinstance(grid, bool) or not isinstance(grid, int) or grid < 2:
        raise InvalidInputError(f"grid must be a whole number of intervals >= 2, got {grid!r}")
    s = grid_points(breakpoints, grid)
    if isinstance(output, TrajectoryOutput):
        own = output.trajectory
        curve = Trajectory(own.breakpoints - own.start_time, own.coefficients)
        stray = 0.0
    else:
        curve, stray = as_polynomial(_Curve(output), s)
    channels = _channels(curve, s, base, limits)
    x = Stages(channels).solve(0.0, 0.0)
    drive = timed(curve, s, x)
    plan = flat_trajectory(drive, model=base, limits=limits, timing="within_limits", stops=stops)
    info = dict(plan.info) | {"plan": "time_optimal", "grid_points": s, "path_error": stray}
    return MobileTrajectory(plan.segments, base, limits=limits, info=info)


def _channels(curve: Trajectory, s: FloatArray, model: Model, limits: MobileLimits) -> Channels:
    """The base's limited quantities as channels of the curve ``p(s)``."""
    first = curve.evaluate(s, 1)
    peak = float(np.linalg.norm(first, axis=1).max())
    if peak <= 0.0:
        raise InfeasibleError("the curve never moves: there is nothing to time")
    still = np.linalg.norm(first, axis=1) <= 1e-9 * peak
    p1, p2, p3 = first, curve.evaluate(s, 2), curve.evaluate(s, 3)
    with np.errstate(divide="ignore", invalid="ignore"):
        _, sigma_1, theta_1, sigma_2, theta_2 = _flat_state(p1, p2, p3, 1.0)
    if still.any():
        # Where the curve stops (p' = 0: a spline at rest at its end) the formulas are
        # 0/0. Their limits, as p' ~ p'' σ there: |p'| grows at |p''|, the heading turns
        # at cross(p'', p''') / (2 |p''|²) per unit of s, and its second derivative
        # comes from the heading rate at the neighbouring grid point.
        k = np.flatnonzero(still)
        bend = p2[k, 0] * p3[k, 1] - p2[k, 1] * p3[k, 0]
        sigma_1[k], sigma_2[k] = 0.0, np.linalg.norm(p2[k], axis=1)
        with np.errstate(divide="ignore", invalid="ignore"):
            theta_1[k] = bend / (2.0 * sigma_2[k] ** 2)
        neighbour = np.where(k + 1 < s.size, k + 1, k - 1)
        theta_2[k] = (theta_1[neighbour] - theta_1[k]) / (s[neighbour] - s[k])
    slopes, curves, velocity, acceleration = [], [], [[], []], [[], []]
    for _, bounds, order, weights in limited_channels(limits, model):
        for _, cv, cw in weights:
            slopes.append(cv * sigma_1 + cw * theta_1)
            curves.append(cv * sigma_2 + cw * theta_2)
            given, free = (velocity, acceleration) if order == 1 else (acceleration, velocity)
            given[0].append(float(bounds.lower))
            given[1].append(float(bounds.upper))
            free[0].append(-np.inf)
            free[1].append(np.inf)
    if not any(np.isfinite(velocity[1])) or not any(np.isfinite(acceleration[1])):
        raise InvalidInputError(
            "a time-optimal timing needs a bound on a rate (velocity, angular_velocity or "
            "wheel_speed) and on an acceleration (acceleration or angular_acceleration); got "
            f"{limits!r}"
        )
    lower_acc = np.array(acceleration[0])
    if np.any(np.isfinite(lower_acc) & (lower_acc >= 0.0)):
        raise InvalidInputError("acceleration bounds must allow slowing down (lower side < 0)")
    d1, d2 = np.stack(slopes, axis=1), np.stack(curves, axis=1)
    if not (np.all(np.isfinite(d1)) and np.all(np.isfinite(d2))):
        raise InfeasibleError(
            "the curve's heading is undefined inside (its speed vanishes): pass stops= or "
            "split the curve there"
        )
    # c'(σ) on each interval: the cubic Hermite interpolant of c' and c'' at its ends.
    h = np.diff(s)[:, None]
    a0, a1 = d1[:-1], d2[:-1]
    c2 = (3 * (d1[1:] - d1[:-1]) - h * (2 * d2[:-1] + d2[1:])) / h**2
    c3 = (2 * (d1[:-1] - d1[1:]) + h * (d2[:-1] + d2[1:])) / h**3
    slope = np.stack([c3, c2, a1, a0])  # descending powers of σ
    bounds = [tuple(np.array(side) for side in pair) for pair in (velocity, acceleration)]
    return Channels(s, slope, bounds[0], bounds[1], np.zeros(0, dtype=int))
