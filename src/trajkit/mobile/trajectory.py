"""The motion of a wheeled base in time: pose, twist and wheel speeds, checked exactly.

A :class:`MobileTrajectory` is a sequence of segments, each one kind of motion:
a turn in place or a straight drive (a 1-D time law from :mod:`trajkit.profiles`),
a constant-twist arc, or a flat-output curve (:mod:`trajkit.mobile.flatness`).
Every plan in :mod:`trajkit.mobile` returns one.
"""

from __future__ import annotations

import dataclasses
import math
import os
from abc import ABC, abstractmethod
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from trajkit._validation import FloatArray, finite_array, positive_scalar
from trajkit.curve import MAX_SAMPLES, Segmented, check_order, sample_times
from trajkit.errors import InvalidInputError
from trajkit.io.table import write_csv
from trajkit.limits import Bounds, Report, Violation, compare
from trajkit.mobile.limits import QUANTITIES, MobileLimits, check_limits
from trajkit.mobile.models import (
    DiffDrive,
    Model,
    constant_twist_pose,
    pose_array,
    resolve_model,
)
from trajkit.renamed import renamed_keywords
from trajkit.trajectory import Extrema, Trajectory

__all__ = ["MobileState", "MobileTrajectory", "Segment"]


@dataclass(frozen=True)
class MobileState:
    """Pose, twist and twist rates at times ``t`` (each an array of shape ``(n,)``).

    Attributes
    ----------
    t : time (s)
    x, y : position (m)
    theta : heading (rad), continuous (not wrapped)
    v, omega : forward speed (m/s) and turn rate (rad/s)
    acceleration, angular_acceleration : dv/dt (m/s²) and dω/dt (rad/s²)
    """

    t: FloatArray
    x: FloatArray
    y: FloatArray
    theta: FloatArray
    v: FloatArray
    omega: FloatArray
    acceleration: FloatArray
    angular_acceleration: FloatArray

    @property
    def pose(self) -> FloatArray:
        """``(x, y, θ)`` stacked, shape ``(n, 3)``."""
        return np.stack([self.x, self.y, self.theta], axis=-1)

    @property
    def twist(self) -> FloatArray:
        """``(v, ω)`` stacked, shape ``(n, 2)``."""
        return np.stack([self.v, self.omega], axis=-1)

    @property
    def world_velocity(self) -> FloatArray:
        """``(ẋ, ẏ)`` in the world frame, shape ``(n, 2)``."""
        return world_velocity(self.v, self.theta)


def world_velocity(v: FloatArray, theta: FloatArray) -> FloatArray:
    """``(ẋ, ẏ) = v (cos θ, sin θ)`` (m/s) for speeds and headings of shape (n,): (n, 2)."""
    return np.stack([v * np.cos(theta), v * np.sin(theta)], axis=-1)


def command_times(duration: float, rate_hz: float) -> FloatArray:
    """Times ``k / rate_hz`` (s) before ``duration``: when commands at that rate are sent.

    At least one (``t = 0``); an end that falls on a command time, up to rounding,
    gets no command of its own.
    """
    return (1.0 / rate_hz) * np.arange(command_count(duration, rate_hz))


def command_count(duration: float, rate_hz: float) -> int:
    """How many commands :func:`command_times` gives, without making them.

    A command within a billionth of a period of the end is not sent.
    """
    periods = duration * rate_hz
    if not periods <= MAX_SAMPLES:
        raise InvalidInputError(
            f"rate_hz={rate_hz:g} Hz over {duration:g} s gives {periods:.3g} commands; at most "
            f"{MAX_SAMPLES:.0e} are made"
        )
    return max(int(np.ceil(periods - 1e-9)), 1)


# The local state of a segment: x, y, θ, v, ω, dv/dt, dω/dt at each local time.
LocalState = tuple[FloatArray, ...]


class Segment(ABC):
    """One kind of motion over ``[0, duration]`` in local time, from ``start_pose``."""

    kind: str
    duration: float
    start_pose: FloatArray

    @abstractmethod
    def local_state(self, tau: FloatArray) -> LocalState:
        """``(x, y, θ, v, ω, dv/dt, dω/dt)`` at local times ``tau`` in [0, duration]."""

    @abstractmethod
    def extrema(self, order: int, cv: float, cw: float) -> tuple[float, float, float, float]:
        """Min, its time, max, its time of ``cv v + cw ω`` (order 1) or of their rates (2).

        Times are local. Exact for the polynomial segments.
        """

    @property
    def end_pose(self) -> FloatArray:
        """The pose at the segment's end."""
        return np.array([s[0] for s in self.local_state(np.array([self.duration]))[:3]])


def _law_extrema(law: Trajectory, order: int, factor: float) -> tuple[float, float, float, float]:
    """Extrema of ``factor * law^(order)``, exact from the law's polynomial pieces.

    Where a lower derivative of the law jumps between its pieces, the quantity is
    unbounded: ``±inf`` at the first such breakpoint (as :func:`trajkit.check`).
    """
    if factor == 0.0:
        return 0.0, 0.0, 0.0, 0.0
    found = law.extrema(order)
    low, t_low = float(found.minimum[0]) * factor, float(found.time_of_minimum[0])
    high, t_high = float(found.maximum[0]) * factor, float(found.time_of_maximum[0])
    if factor < 0:
        low, t_low, high, t_high = high, t_high, low, t_low
    times = law.breakpoints[1:-1]
    for k in range(order):
        jumps = law.jumps(k)[:, 0] * factor
        # The next derivative of a step has the step's sign; higher ones both.
        up, down = (jumps > 0, jumps < 0) if k == order - 1 else (jumps != 0, jumps != 0)
        if up.any() and (high != np.inf or times[np.argmax(up)] < t_high):
            high, t_high = np.inf, float(times[np.argmax(up)])
        if down.any() and (low != -np.inf or times[np.argmax(down)] < t_low):
            low, t_low = -np.inf, float(times[np.argmax(down)])
    return low, t_low, high, t_high


class _LawSegment(Segment):
    """A turn or a drive along a 1-D time law (a 1-DoF Trajectory starting at t = 0)."""

    turning: bool  # the law moves θ (a turn) or the distance along the heading (a drive)

    def __init__(self, start_pose: ArrayLike, law: Trajectory) -> None:
        if not isinstance(law, Trajectory) or law.ndof != 1:
            raise InvalidInputError("law must be a 1-DoF trajkit Trajectory")
        if law.start_time != 0.0:
            raise InvalidInputError(f"law must start at t=0, got {law.start_time:g} s")
        self.start_pose = pose_array("start_pose", start_pose)
        self.law = law
        self.duration = law.duration
        self._origin = float(law.position(0.0)[0])

    def extrema(self, order: int, cv: float, cw: float) -> tuple[float, float, float, float]:
        return _law_extrema(self.law, order, cw if self.turning else cv)


class Turn(_LawSegment):
    """Turn in place: ``θ(τ) = θ0 + law(τ) - law(0)``; position fixed, ``v = 0``."""

    kind = "turn"
    turning = True

    def local_state(self, tau: FloatArray) -> LocalState:
        x0, y0, theta0 = self.start_pose
        zero = np.zeros(tau.size)
        return (
            zero + x0,
            zero + y0,
            theta0 + self.law.position(tau)[:, 0] - self._origin,
            zero,
            self.law.velocity(tau)[:, 0],
            zero,
            self.law.acceleration(tau)[:, 0],
        )


class Straight(_LawSegment):
    """Drive straight along the start heading: ``s(τ) = law(τ) - law(0)`` metres."""

    kind = "straight"
    turning = False

    def local_state(self, tau: FloatArray) -> LocalState:
        x0, y0, theta0 = self.start_pose
        s = self.law.position(tau)[:, 0] - self._origin
        zero = np.zeros(tau.size)
        return (
            x0 + s * np.cos(theta0),
            y0 + s * np.sin(theta0),
            zero + theta0,
            self.law.velocity(tau)[:, 0],
            zero,
            self.law.acceleration(tau)[:, 0],
            zero,
        )


class Arc(Segment):
    """A constant twist ``(v, ω)`` for ``duration``: a circular arc, a line or a spin."""

    kind = "arc"

    def __init__(self, start_pose: ArrayLike, v: float, omega: float, duration: float) -> None:
        self.start_pose = pose_array("start_pose", start_pose)
        self.v = float(finite_array("v", v, unit="m/s"))
        self.omega = float(finite_array("omega", omega, unit="rad/s"))
        self.duration = positive_scalar("duration", duration, unit="s")

    def local_state(self, tau: FloatArray) -> LocalState:
        pose = constant_twist_pose(self.start_pose, self.v, self.omega, tau)
        zero = np.zeros(tau.size)
        return (*pose.T, zero + self.v, zero + self.omega, zero, zero)

    def extrema(self, order: int, cv: float, cw: float) -> tuple[float, float, float, float]:
        value = cv * self.v + cw * self.omega if order == 1 else 0.0
        return value, 0.0, value, 0.0


# Each checked quantity: limit attribute, derivative order, and the (cv, cw) weights of
# v and ω per channel; wheel weights come from the model.
def channel_weights(attribute: str, model: Model) -> tuple[int, list[tuple[str, float, float]]]:
    if attribute == "wheel_speed":
        if not isinstance(model, DiffDrive):
            raise InvalidInputError(
                "a wheel_speed limit needs a DiffDrive model: a unicycle has no wheels"
            )
        r, half = model.wheel_radius, model.effective_track / 2.0
        return 1, [("left wheel", 1 / r, -half / r), ("right wheel", 1 / r, half / r)]
    order = 2 if "acceleration" in attribute else 1
    linear = not attribute.startswith("angular")
    return order, [("base", 1.0 if linear else 0.0, 0.0 if linear else 1.0)]


def limited_channels(
    limits: MobileLimits, model: Model
) -> Iterator[tuple[str, Bounds, int, list[tuple[str, float, float]]]]:
    """Each limit set in ``limits``, in :data:`QUANTITIES` order, and what it bounds.

    Yields ``(quantity, bounds, order, weights)``: the quantity's name, its bounds,
    the derivative of the pose it bounds (1 or 2) and the channels'
    ``(name, cv, cw)`` weights of v and ω (:func:`channel_weights`).
    """
    for attribute, quantity, _ in QUANTITIES:
        bounds = getattr(limits, attribute)
        if bounds is not None:
            order, weights = channel_weights(attribute, model)
            yield quantity, bounds, order, weights


def _segment_continuity(part: Segment) -> float:
    """How many derivatives of the pose are continuous inside one segment (never more)."""
    if isinstance(part, Arc):
        return math.inf
    if isinstance(part, _LawSegment):
        # A law with k continuous derivatives moves the pose with k continuous derivatives.
        return part.law.continuity
    output = getattr(part, "output", None)  # a flat-output curve (trajkit.mobile.flatness)
    curve = getattr(output, "trajectory", None)
    if isinstance(curve, Trajectory):
        # The heading is the direction of the curve's velocity: one derivative is spent.
        return curve.continuity - 1
    breakpoints = np.asarray(getattr(output, "breakpoints", ()), dtype=float)
    if output is not None and breakpoints.size <= 2:
        return math.inf  # an analytic curve (a figure eight)
    return 0.0  # a kind of segment this cannot see into: claim no more than the pose


class MobileTrajectory(Segmented):
    """The planned motion of a wheeled base, segment after segment, from ``t = 0``.

    As a :class:`~trajkit.curve.Curve`, :meth:`evaluate` gives the pose ``(x, y, θ)``
    and its first two time derivatives in the world frame; :meth:`state` gives the
    pose with the twist ``(v, ω)`` and its rates.

    Parameters
    ----------
    segments : sequence of Segment
        Consecutive motions; each must start at the pose the previous one ends in
        (checked to 1e-9 m and rad).
    model : Unicycle or DiffDrive
        The base; wheel speeds need a DiffDrive.
    limits : MobileLimits, optional
        The limits the plan was made for (default: the model's); :meth:`check`
        and :func:`~trajkit.mobile.simulate` use them unless told otherwise.
    info : mapping, optional
        Plan data a planner attaches (phase times, scaling...). Read-only.

    Notes
    -----
    Outside ``[0, duration]`` the base stands still at its first or last pose:
    the pose is clamped and the twist and its rates are 0.
    """

    def __init__(
        self,
        segments: Sequence[Segment],
        model: Model,
        *,
        limits: MobileLimits | None = None,
        info: Mapping[str, Any] | None = None,
    ) -> None:
        if model is None:  # a trajectory has no default robot: say which one it drives
            raise InvalidInputError("model must be a trajkit.mobile Unicycle or DiffDrive")
        model = resolve_model(model)
        parts = tuple(segments)
        if not parts or not all(isinstance(s, Segment) for s in parts):
            raise InvalidInputError("segments must be a non-empty sequence of mobile Segments")
        for i in range(1, len(parts)):
            gap = np.abs(parts[i].start_pose - parts[i - 1].end_pose)
            if gap.max() > 1e-9 * (1.0 + np.abs(parts[i].start_pose).max()):
                raise InvalidInputError(
                    f"segment {i} starts at {parts[i].start_pose.round(9).tolist()} but segment "
                    f"{i - 1} ends at {parts[i - 1].end_pose.round(9).tolist()}"
                )
        self._store(parts, [s.duration for s in parts])
        self._model = model
        self._limits = check_limits(model.limits if limits is None else limits)
        self._info: Mapping[str, Any] = MappingProxyType(dict(info or {}))

    # ----------------------------------------------------------------- shape
    @property
    def model(self) -> Model:
        """The base this trajectory drives."""
        return self._model

    @property
    def limits(self) -> MobileLimits:
        """The limits the plan was made for."""
        return self._limits

    @property
    def start_pose(self) -> FloatArray:
        """``(x, y, θ)`` at ``t = 0``."""
        return self._segments[0].start_pose.copy()

    @property
    def end_pose(self) -> FloatArray:
        """``(x, y, θ)`` at the end (heading not wrapped)."""
        return self._segments[-1].end_pose

    @property
    def info(self) -> Mapping[str, Any]:
        """Plan data attached by the planner (read-only mapping; may be empty)."""
        return self._info

    def __repr__(self) -> str:
        kinds = ", ".join(s.kind for s in self._segments)
        return f"MobileTrajectory(duration={self.duration:.6g} s, segments=[{kinds}])"

    # ------------------------------------------------------------ evaluation
    highest_order = 2
    components = (("x", "m"), ("y", "m"), ("θ", "rad"))

    def evaluate(self, t: ArrayLike, order: int = 0) -> FloatArray:
        """The pose ``(x, y, θ)`` (m, rad) or its ``order``-th time derivative (1 or 2).

        Order 1 is ``(ẋ, ẏ, ω)`` and order 2 ``(ẍ, ÿ, dω/dt)`` in the world frame.
        Shape ``(3,)`` for a number ``t``, ``(n, 3)`` for an array.
        """
        order = check_order(order, self.highest_order, " for a mobile trajectory")
        s = self.state(t)
        if order == 0:
            value = s.pose
        else:
            cos, sin = np.cos(s.theta), np.sin(s.theta)
            if order == 1:
                value = np.stack([s.v * cos, s.v * sin, s.omega], axis=-1)
            else:
                turning = s.v * s.omega  # the centripetal part of the world acceleration
                value = np.stack(
                    [
                        s.acceleration * cos - turning * sin,
                        s.acceleration * sin + turning * cos,
                        s.angular_acceleration,
                    ],
                    axis=-1,
                )
        return value[0] if np.ndim(t) == 0 else value

    def state(self, t: ArrayLike) -> MobileState:
        """The state at times ``t`` (s): a number or a 1-D array; arrays of shape (n,)."""
        times = np.atleast_1d(finite_array("t", t, unit="s"))
        if times.ndim != 1:
            raise InvalidInputError(f"t must be a number or a 1-D array, got shape {times.shape}")
        columns = np.empty((7, times.size))
        for segment, mask, local in self._pieces(times):
            columns[:, mask] = np.stack(segment.local_state(local))
        outside = (times < 0.0) | (times > self.end_time)
        columns[3:, outside] = 0.0
        return MobileState(times, *columns)

    def pose(self, t: ArrayLike) -> FloatArray:
        """``(x, y, θ)`` at ``t``: shape (3,) for a number, (n, 3) for an array."""
        pose = self.state(t).pose
        return pose[0] if np.ndim(t) == 0 else pose

    def twist(self, t: ArrayLike) -> FloatArray:
        """``(v, ω)`` at ``t``: shape (2,) for a number, (n, 2) for an array."""
        twist = self.state(t).twist
        return twist[0] if np.ndim(t) == 0 else twist

    def wheel_speeds(self, t: ArrayLike) -> FloatArray:
        """Left and right wheel speeds (rad/s) at ``t``; needs a DiffDrive model."""
        if not isinstance(self._model, DiffDrive):
            raise InvalidInputError("wheel speeds need a DiffDrive model: a unicycle has no wheels")
        state = self.state(t)
        speeds = self._model.wheel_speeds(state.v, state.omega)
        return speeds[0] if np.ndim(t) == 0 else speeds

    @renamed_keywords(dt="sample_step")
    def times(self, sample_step: float) -> FloatArray:
        """``0, h, 2 h, ...`` for ``h = sample_step`` (s), and the end time exactly.

        The last step may be shorter.
        """
        return sample_times(
            0.0, self.duration, positive_scalar("sample_step", sample_step, unit="s")
        )

    def commands(self, rate_hz: float) -> tuple[FloatArray, FloatArray]:
        """The twist commands a base controller would be sent at ``rate_hz``.

        Returns the command times ``k / rate_hz`` before the end (s), and the twist
        ``(v, ω)`` at each, shape (n, 2): what to publish, each held until the next.
        """
        times = command_times(self.duration, positive_scalar("rate_hz", rate_hz, unit="Hz"))
        return times, self.twist(times)

    # ---------------------------------------------------------------- checks
    def check(
        self,
        limits: MobileLimits | None = None,
        *,
        jerk: float | None = None,
        angular_jerk: float | None = None,
        rtol: float = 1e-9,
    ) -> Report:
        """Verify speed, turn rate, accelerations and wheel speeds against ``limits``.

        Parameters
        ----------
        limits : MobileLimits, optional
            Default: the limits the plan was made for (:attr:`limits`).
        jerk, angular_jerk : float, optional
            Bounds on ``|dv²/dt²|`` (m/s³) and ``|dω²/dt²|`` (rad/s³), checked exactly on
            the time laws of the drives and of the turns (an S-curve goto's phases).
            Arcs have none; flat-output curves are not checked for jerk (refused).
        rtol : float
            Relative tolerance on each bound (default 1e-9).

        Returns
        -------
        Report
            One violation per quantity, channel and side at most: the worst one.
            Turns, straight drives and arcs are checked exactly (extrema of their
            polynomial laws); flat-output curves from a dense grid refined to
            about 1e-12 s by bounded scalar search (see :mod:`trajkit.mobile.flatness`).
            Where two segments meet with different twists (a curve into a turn
            at a stop, say) the acceleration is unbounded: ``±inf`` at that time;
            so is it where a turn's or a drive's time law has a velocity step
            between its pieces (and the twist itself where the law's position
            steps), as :func:`trajkit.check` reports jumps. Such a violation's
            ``cause`` says so.
            The plan's first and last twists are its boundary states and are not
            compared with rest.
        """
        limits = check_limits(self._limits if limits is None else limits)
        tolerance = positive_scalar("rtol", rtol)
        violations: list[Violation] = []
        peaks, bounds, channels = {}, {}, {}
        for quantity, limit, order, weights in limited_channels(limits, self._model):
            found = self._extrema(order, weights)
            lower = np.full(len(weights), float(limit.lower))
            upper = np.full(len(weights), float(limit.upper))
            names = tuple(name for name, _, _ in weights)
            peaks[quantity] = (found.minimum, found.maximum)
            bounds[quantity] = (lower, upper)
            channels[quantity] = names
            for violation in compare(quantity, found, lower, upper, tolerance, names):
                if np.isinf(violation.value):
                    lower_order = "pose" if order == 1 else "twist"
                    cause = f"the {lower_order} jumps there (a segment junction or a law's step)"
                    violation = dataclasses.replace(violation, cause=cause)
                violations.append(violation)
        for quantity, bound, kind in (("jerk", jerk, "straight"),
                                      ("angular jerk", angular_jerk, "turn")):  # fmt: skip
            if bound is None:
                continue
            found = self._law_jerk(quantity, kind)
            magnitude = positive_scalar(quantity.replace(" ", "_"), bound)
            lower, upper = np.array([-magnitude]), np.array([magnitude])
            peaks[quantity], bounds[quantity] = (found.minimum, found.maximum), (lower, upper)
            channels[quantity] = ("base",)
            violations += compare(quantity, found, lower, upper, tolerance, ("base",))
        return Report(tuple(violations), peaks, bounds, channels)

    def describe(self, report: Report | None = None) -> str:
        """A few lines about the plan: what it is, where it goes, and its limit check.

        Parameters
        ----------
        report : Report, optional
            ``self.check()``, when the caller has it already (checking a curve is the
            costly part).
        """
        info = self.info
        start, end = self.start_pose, self.end_pose
        lines = [
            f"{info.get('plan', 'mobile plan')} on {self.model.name}: duration "
            f"{self.duration:.9g} s, from ({start[0]:.6g} m, {start[1]:.6g} m, "
            f"{start[2]:.6g} rad) to ({end[0]:.6g} m, {end[1]:.6g} m, {end[2]:.6g} rad)"
        ]
        phases = zip(info.get("phases", ()), info.get("phase_durations", ()), strict=True)
        for name, duration in phases:
            lines.append(f"  {name}: {duration:.9g} s")
        if info.get("plan") == "constant_twist":
            line = (
                f"  arc radius {info['radius']:.6g} m, turned {info['turned']:.6g} rad, "
                f"{info['distance']:.6g} m along the path"
            )
            if info.get("rate_hz"):
                line += f", {info['command_count']} commands at {info['rate_hz']:g} Hz"
            lines.append(line)
        if info.get("plan") == "flat_output":
            line = f"  time scale {info['time_scale']:.6g}"
            if info.get("limited_by"):
                line += f" (set by the {info['limited_by']} limit)"
            lines.append(line)
        report = self.check() if report is None else report
        lines += ["  " + line for line in str(report).splitlines()]
        return "\n".join(lines)

    def _law_jerk(self, quantity: str, kind: str) -> Extrema:
        """Extrema of the jerk of every drive (or turn) law, exactly; 0 where none."""
        low = high = 0.0
        t_low = t_high = 0.0
        for start, part in zip(self._breakpoints[:-1], self._segments, strict=True):
            if not isinstance(part, _LawSegment):
                if isinstance(part, Arc):
                    continue  # a constant twist: no jerk
                raise InvalidInputError(
                    f"{quantity} can be checked on turns, drives and arcs only, not on a "
                    f"{part.kind} segment"
                )
            if part.kind != kind:
                continue
            lo, at_lo, hi, at_hi = _law_extrema(part.law, 3, 1.0)
            if lo < low:
                low, t_low = lo, float(start + at_lo)
            if hi > high:
                high, t_high = hi, float(start + at_hi)
        return Extrema(order=3, minimum=np.array([low]), time_of_minimum=np.array([t_low]),
                       maximum=np.array([high]), time_of_maximum=np.array([t_high]))  # fmt: skip

    def _extrema(self, order: int, weights: list[tuple[str, float, float]]) -> Extrema:
        values = np.array(
            [[part.extrema(order, cv, cw) for part in self._segments] for _, cv, cw in weights]
        )  # (channels, segments, 4)
        starts = self._breakpoints[:-1]
        low, high = np.argmin(values[..., 0], axis=1), np.argmax(values[..., 2], axis=1)
        rows = np.arange(len(weights))
        found = Extrema(
            order=order,
            minimum=values[rows, low, 0],
            time_of_minimum=starts[low] + values[rows, low, 1],
            maximum=values[rows, high, 2],
            time_of_maximum=starts[high] + values[rows, high, 3],
        )
        if order == 2:
            for i, (before, after) in enumerate(self._junction_twists(), start=1):
                for j, (_, cv, cw) in enumerate(weights):
                    jump = cv * (after[0] - before[0]) + cw * (after[1] - before[1])
                    size = abs(cv * before[0]) + abs(cw * before[1]) + abs(cv) + abs(cw)
                    if abs(jump) > 1e-9 * size:
                        extreme = found.maximum if jump > 0 else found.minimum
                        when = found.time_of_maximum if jump > 0 else found.time_of_minimum
                        extreme[j], when[j] = np.copysign(np.inf, jump), self._breakpoints[i]
        return found

    @property
    def continuity(self) -> float:
        """The highest derivative of the pose that is continuous everywhere.

        ``-1`` if the pose jumps (never, by construction), ``0`` if the twist
        ``(v, ω)`` jumps somewhere, ``1`` if only its rates jump, ``2`` if the twist
        and its rates are continuous at every junction and inside every turn or drive
        (the rates are the highest derivative a segment reports, so no more is
        claimed), ``math.inf`` for one arc of constant twist. Turns and drives are read
        exactly off their time laws (:attr:`Trajectory.continuity`); junctions compare
        the segments' ends to 1e-9 of the values' size. A planner's claim is in
        ``info["continuity"]`` where it makes one.
        """
        if len(self._segments) == 1 and isinstance(self._segments[0], Arc):
            return math.inf
        level = 2.0
        for part in self._segments:
            level = min(level, _segment_continuity(part))
        for left, right in zip(self._segments[:-1], self._segments[1:], strict=True):
            end = left.local_state(np.array([left.duration]))
            start = right.local_state(np.array([0.0]))
            twist = [(end[k][0], start[k][0]) for k in (3, 4)]
            rates = [(end[k][0], start[k][0]) for k in (5, 6)]
            for jumped_below, pairs in ((0.0, twist), (1.0, rates)):
                if any(abs(x - y) > 1e-9 * (1.0 + abs(x) + abs(y)) for x, y in pairs):
                    level = min(level, jumped_below)
        return level

    def _junction_twists(self) -> list[tuple[FloatArray, FloatArray]]:
        """``(v, ω)`` at the end of each segment and at the start of the next."""
        pairs = []
        for left, right in zip(self._segments[:-1], self._segments[1:], strict=True):
            end = left.local_state(np.array([left.duration]))
            start = right.local_state(np.array([0.0]))
            pairs.append((np.array([end[3][0], end[4][0]]), np.array([start[3][0], start[4][0]])))
        return pairs

    # ----------------------------------------------------------------- files
    @renamed_keywords(dt="sample_step")
    def to_csv(self, path: str | os.PathLike[str], sample_step: float) -> Path:
        """Write the state every ``sample_step`` seconds (and at the end) to a CSV file.

        Columns: time, x, y, theta, v, omega, their rates, and the wheel speeds for
        a DiffDrive; the header carries the units.
        """
        state = self.state(self.times(sample_step))
        header = [
            "t [s]", "x [m]", "y [m]", "theta [rad]", "v [m/s]", "omega [rad/s]",
            "v_rate [m/s^2]", "omega_rate [rad/s^2]",
        ]  # fmt: skip
        columns = [state.t, state.x, state.y, state.theta, state.v, state.omega,
                   state.acceleration, state.angular_acceleration]  # fmt: skip
        if isinstance(self._model, DiffDrive):
            speeds = self._model.wheel_speeds(state.v, state.omega)
            header += ["wheel_left [rad/s]", "wheel_right [rad/s]"]
            columns += [speeds[:, 0], speeds[:, 1]]
        return write_csv(path, header, np.stack(columns, axis=1))
