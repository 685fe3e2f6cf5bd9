"""Kinematic limits and their exact verification on a trajectory's polynomial pieces."""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from trajkit._validation import FloatArray, as_float_array, finite_array, positive_scalar
from trajkit.errors import InvalidInputError
from trajkit.tolerances import LIMIT_RTOL

if TYPE_CHECKING:
    from trajkit.trajectory import Extrema, Trajectory

__all__ = [
    "Bounds",
    "Discontinuity",
    "Limits",
    "Report",
    "Violation",
    "check",
    "compare",
    "parse_bounds",
]

QUANTITIES = ("position", "velocity", "acceleration", "jerk")
UNIT_SUFFIX = ("", "/s", "/s^2", "/s^3")

LimitSpec = ArrayLike | tuple[ArrayLike, ArrayLike] | None


@dataclass(frozen=True)
class Bounds:
    """Lower and upper bounds of one quantity, each broadcastable to ``(ndof,)``."""

    lower: FloatArray
    upper: FloatArray

    def __post_init__(self) -> None:
        for value in (self.lower, self.upper):
            value.setflags(write=False)

    def for_ndof(self, name: str, ndof: int) -> tuple[FloatArray, FloatArray]:
        """Bounds broadcast to ``(ndof,)``; refuses a per-joint length that differs."""
        out = []
        for side, value in (("lower", self.lower), ("upper", self.upper)):
            if value.ndim == 1 and value.size != ndof:
                raise InvalidInputError(
                    f"{name} {side} bounds give {value.size} joints but the trajectory has {ndof}"
                )
            out.append(value if value.ndim == 1 else np.full(ndof, value))
        return out[0], out[1]


def _bound_side(name: str, value: Any, unbounded: float, open_allowed: bool) -> FloatArray:
    """One side of a range; a position range may be open (``-inf`` below, ``inf`` above)."""
    if not open_allowed:
        array = finite_array(name, value)
    else:
        array = np.array(as_float_array(name, value))
        finite_array(name, np.where(array == unbounded, 0.0, array))
    if array.size == 0:
        raise InvalidInputError(f"{name} must be a number or one number per joint, got []")
    return array


def parse_bounds(name: str, spec: LimitSpec, *, quantity: str | None = None) -> Bounds | None:
    """Read one limit: a magnitude (symmetric), or a tuple ``(lower, upper)``.

    ``name`` is the argument name used in messages (``"vmax"``, ``"velocity"``);
    ``quantity`` (default ``name``) says whether it is a position range, which must
    be a tuple, or a derivative bound, whose range must contain 0.
    """
    quantity = quantity or name
    if spec is None:
        return None
    if isinstance(spec, tuple):
        if len(spec) != 2:
            raise InvalidInputError(
                f"{name} given as a tuple must be (lower, upper), got {len(spec)} items; "
                "pass a list or array for per-joint symmetric limits"
            )
        lower = _bound_side(f"{name} lower bound", spec[0], -np.inf, quantity == "position")
        upper = _bound_side(f"{name} upper bound", spec[1], np.inf, quantity == "position")
        for side, value in (("lower", lower), ("upper", upper)):
            if value.ndim > 1:
                raise InvalidInputError(
                    f"{name} {side} bound must be a number or one number per joint, "
                    f"got shape {value.shape}"
                )
        if lower.ndim == 1 and upper.ndim == 1 and lower.size != upper.size:
            raise InvalidInputError(
                f"{name} lower bounds give {lower.size} joints but upper bounds {upper.size}"
            )
        if np.any(lower >= upper):
            raise InvalidInputError(
                f"{name} lower bound must be below the upper bound, got ({lower}, {upper})"
            )
        if quantity != "position" and (np.any(lower > 0) or np.any(upper < 0)):
            raise InvalidInputError(
                f"{name}=({lower}, {upper}): a tuple is read as (lower, upper) and must "
                "contain 0 (a robot at rest must be within its limits); pass a list or "
                "array for per-joint symmetric limits"
            )
        return Bounds(np.array(lower), np.array(upper))
    if quantity == "position":
        raise InvalidInputError(
            f"{name} limits must be a tuple (lower, upper) of numbers or per-joint arrays"
        )
    magnitude = finite_array(name, spec)
    if magnitude.size == 0:
        raise InvalidInputError(f"{name} must be a number or one number per joint, got []")
    if magnitude.ndim > 1:
        raise InvalidInputError(
            f"{name} must be a number or one number per joint, got shape {magnitude.shape}"
        )
    if np.any(magnitude <= 0):
        raise InvalidInputError(f"{name} limits must be > 0, got {magnitude}")
    return Bounds(-magnitude, np.array(magnitude))


@dataclass(frozen=True, init=False)
class Limits:
    """Kinematic limits of a robot's joints (SI units: rad or m, per second...).

    Parameters
    ----------
    position : tuple (lower, upper), optional
        Joint range; each side a number or one number per joint. A joint without
        a range (a continuous joint) has ``-inf`` and ``inf``.
    velocity, acceleration, jerk : number, sequence or tuple, optional
        A number or a list/array (one per joint) means the symmetric bound
        ``-v <= q' <= v``; a ``tuple`` ``(lower, upper)`` gives asymmetric bounds,
        each side a number or per-joint array, with ``lower <= 0 <= upper``.

    Examples
    --------
    >>> Limits(velocity=[1.0, 2.0], acceleration=(-3.0, 5.0))  # doctest: +ELLIPSIS
    Limits(...)
    """

    position: Bounds | None
    velocity: Bounds | None
    acceleration: Bounds | None
    jerk: Bounds | None

    def __init__(
        self,
        position: LimitSpec = None,
        velocity: LimitSpec = None,
        acceleration: LimitSpec = None,
        jerk: LimitSpec = None,
    ) -> None:
        for name, spec in zip(QUANTITIES, (position, velocity, acceleration, jerk), strict=True):
            object.__setattr__(self, name, parse_bounds(name, spec))

    def __repr__(self) -> str:
        parts = []
        for name in QUANTITIES:
            bounds = getattr(self, name)
            if bounds is not None:
                parts.append(f"{name}=({bounds.lower.tolist()}, {bounds.upper.tolist()})")
        return f"Limits({', '.join(parts)})"


@dataclass(frozen=True)
class Violation:
    """The worst excursion of one quantity of one joint past one of its bounds.

    ``joint`` counts from 0; ``time`` (s) is where ``value`` occurs; ``bound`` is the
    limit it passes (the lower bound when ``value`` is below it). ``channel`` names
    what is checked when it is not a joint ("base", "left wheel"...).

    ``value`` is ``inf`` or ``-inf`` where a lower derivative jumps: a step in
    position is an unbounded velocity (and acceleration, jerk), a step in velocity
    an unbounded acceleration, a jump in acceleration an unbounded jerk. ``cause``
    then says which quantity jumps and by how much, and ``time`` is the first
    breakpoint where it does.
    """

    quantity: str
    joint: int
    time: float
    value: float
    bound: float
    channel: str = ""
    cause: str = ""

    @property
    def excess(self) -> float:
        """How far past the bound, >= 0, in the quantity's unit."""
        return abs(self.value - self.bound)

    def __str__(self) -> str:
        what = self.channel or f"joint {self.joint + 1}"
        if self.cause:
            return (
                f"{self.quantity} of {what} is unbounded ({self.value:g}) at "
                f"t={self.time:.6g} s, beyond the bound {self.bound:.6g}: {self.cause}"
            )
        return (
            f"{self.quantity} of {what} reaches {self.value:.6g} "
            f"at t={self.time:.6g} s, beyond the bound {self.bound:.6g}"
        )


@dataclass(frozen=True)
class Discontinuity:
    """The largest jump of one quantity of one joint at a breakpoint.

    ``jump`` is the value after minus the value before (units of the quantity),
    at ``time`` (s); ``joint`` counts from 0.
    """

    quantity: str
    joint: int
    time: float
    jump: float

    def __str__(self) -> str:
        return (
            f"{self.quantity} of joint {self.joint + 1} jumps by {self.jump:.6g} "
            f"at t={self.time:.6g} s"
        )


@dataclass(frozen=True)
class Report:
    """Outcome of :func:`check`: ``ok`` and the violations, plus the peaks it saw.

    ``peaks[quantity]`` is ``(minimum, maximum)`` per joint for every quantity that
    had a limit (``-inf`` / ``inf`` where a lower derivative jumps, see
    :class:`Violation`); ``bounds[quantity]`` the ``(lower, upper)`` arrays checked
    against; ``channels[quantity]``, where given, names each entry instead of a
    joint number. ``discontinuities`` lists, per quantity (position, velocity,
    acceleration) and joint, the largest jump at a breakpoint, whether or not a
    limit makes it a violation (a trapezoid's acceleration jumps by design).
    """

    violations: tuple[Violation, ...]
    peaks: dict[str, tuple[FloatArray, FloatArray]] = field(default_factory=dict)
    bounds: dict[str, tuple[FloatArray, FloatArray]] = field(default_factory=dict)
    channels: dict[str, tuple[str, ...]] = field(default_factory=dict)
    discontinuities: tuple[Discontinuity, ...] = ()

    @property
    def ok(self) -> bool:
        """True when no limit is exceeded."""
        return not self.violations

    def __bool__(self) -> bool:
        return self.ok

    def ratios(self, quantity: str) -> FloatArray:
        """How close each joint (or channel) comes to its bound: ``peak / bound``.

        The larger of ``maximum / upper`` and ``minimum / lower``: 1 at the bound,
        above 1 past it, 0 for a side never reached. A bound of 0 that is passed
        gives ``inf``, and so does a quantity made unbounded by a jump of a lower
        derivative.

        Parameters
        ----------
        quantity : str
            One of the checked quantities (a key of :attr:`peaks`).

        Returns
        -------
        ndarray
            One ratio per joint (or channel).
        """
        if quantity not in self.peaks:
            raise InvalidInputError(
                f"{quantity!r} was not checked; checked: {', '.join(self.peaks) or 'nothing'}"
            )
        low, high = self.peaks[quantity]
        lower, upper = self.bounds[quantity]
        with np.errstate(divide="ignore", invalid="ignore"):
            up = np.where(upper > 0, high / upper, np.where(high > 0, np.inf, 0.0))
            down = np.where(lower < 0, low / lower, np.where(low < 0, np.inf, 0.0))
        return np.maximum(np.maximum(up, down), 0.0)

    def merged(self, *others: Report) -> Report:
        """One report of this check and ``others`` (of other quantities, e.g. torque)."""
        out = self
        for other in others:
            out = Report(out.violations + other.violations, {**out.peaks, **other.peaks},
                         {**out.bounds, **other.bounds}, {**out.channels, **other.channels},
                         out.discontinuities + other.discontinuities)  # fmt: skip
        return out

    def __str__(self) -> str:
        lines = [f"limit check: {'OK' if self.ok else f'{len(self.violations)} violation(s)'}"]
        if self.peaks:
            width = max([13, *(len(q) + 1 for q in self.peaks)])
            names = [n for q in self.peaks for n in self.channels.get(q, ())]
            column = max([6, *(len(n) + 1 for n in names)])
            header = (
                f"{'quantity':<{width}}{'joint' if not names else 'of':>{column}}"
                f"{'min':>14}{'max':>14}{'lower':>14}{'upper':>14}"
            )
            lines += [header, "-" * len(header)]
            for quantity, (low, high) in self.peaks.items():
                lower, upper = self.bounds[quantity]
                labels = self.channels.get(quantity) or [str(j + 1) for j in range(low.size)]
                for j in range(low.size):
                    flag = ""
                    if any(v.quantity == quantity and v.joint == j for v in self.violations):
                        flag = "  <-- exceeds"
                    lines.append(
                        f"{quantity:<{width}}{labels[j]:>{column}}{low[j]:>14.6g}{high[j]:>14.6g}"
                        f"{lower[j]:>14.6g}{upper[j]:>14.6g}{flag}"
                    )
        lines += [f"  {v}" for v in self.violations]
        return "\n".join(lines)


#: Units in the last place of the end time by which a check lets breakpoints shift.
TIME_ULPS = 8.0


def check(trajectory: Trajectory, limits: Limits, *, rtol: float = LIMIT_RTOL) -> Report:
    """Verify ``limits`` on ``trajectory`` exactly, from its polynomial pieces.

    The extrema of every piece come from the roots of the next derivative, so an
    excursion between two samples is found. A value counts as a violation when it
    passes its bound by more than ``rtol`` times the larger of
    ``|lower|`` and ``|upper|``: time-optimal trajectories touch
    their limits, and the last bits of floating point must not flag them. Nor
    must the resolution of absolute time: a value may also pass its bound, and
    jump, by the next derivative's peak times ``8 eps`` times the end time (a
    1e-9 s ramp at t = 1e3 s is placed to about 1e-13 s).

    Between pieces, a jump of derivative ``k`` (beyond ``rtol`` relative to the
    size of the values, see :meth:`Trajectory.jumps`) makes every derivative above
    ``k`` unbounded: a limit on one of them is violated with the value ``inf`` or
    ``-inf`` (the sign of the jump for derivative ``k + 1``; both signs for higher
    ones, the derivative of an impulse going both ways) at the breakpoint.

    Parameters
    ----------
    trajectory : Trajectory
    limits : Limits
    rtol : float
        Relative tolerance on each bound (default 1e-9).

    Returns
    -------
    Report
        At most one violation per quantity, joint and side: the worst one (an
        unbounded value first, at its earliest time).
    """
    if not isinstance(limits, Limits):
        raise InvalidInputError(f"limits must be a trajkit.Limits, got {type(limits).__name__}")
    tolerance = positive_scalar("rtol", rtol)
    violations: list[Violation] = []
    peaks: dict[str, tuple[FloatArray, FloatArray]] = {}
    checked: dict[str, tuple[FloatArray, FloatArray]] = {}
    # Breakpoints in absolute time are resolved to an ulp of the end time: a value
    # may pass its bound, or jump, by what shifting a phase's ends that much explains
    # (the next derivative's peak times TIME_ULPS * eps * end time).
    resolution = TIME_ULPS * np.finfo(float).eps * abs(trajectory.end_time)
    slacks = [np.zeros(trajectory.ndof) for _ in QUANTITIES]
    for order in range(len(QUANTITIES) - 1):
        rate = trajectory.extrema(order + 1)
        slacks[order] = resolution * np.maximum(np.abs(rate.minimum), np.abs(rate.maximum))
    jumps = [
        np.where(np.abs(jump) <= slacks[order], 0.0, jump)
        for order, jump in enumerate(
            trajectory.jumps(order, rtol=tolerance) for order in range(len(QUANTITIES) - 1)
        )
    ]
    times = trajectory.breakpoints[1:-1]
    for order, quantity in enumerate(QUANTITIES):
        bounds: Bounds | None = getattr(limits, quantity)
        if bounds is None:
            continue
        lower, upper = bounds.for_ndof(quantity, trajectory.ndof)
        found, causes = _unbounded_at_jumps(trajectory.extrema(order), jumps[:order], times)
        peaks[quantity] = (found.minimum, found.maximum)
        checked[quantity] = (lower, upper)
        slack = slacks[order]
        for violation in compare(quantity, found, lower, upper, tolerance, slack=slack):
            cause = causes.get((violation.joint, violation.value > 0))
            violations.append(replace(violation, cause=cause) if cause else violation)
    return Report(tuple(violations), peaks, checked, discontinuities=_largest(jumps, times))


def _unbounded_at_jumps(
    found: Extrema, jumps: list[FloatArray], times: FloatArray
) -> tuple[Extrema, dict[tuple[int, bool], str]]:
    """``found`` with ``±inf`` where a lower derivative jumps, and what jumps there.

    ``jumps[k]`` holds derivative ``k``'s jumps, shape ``(m - 1, ndof)``. The causes
    are keyed by joint and side (True for the upper one).
    """
    minimum, maximum = found.minimum.copy(), found.maximum.copy()
    t_min, t_max = found.time_of_minimum.copy(), found.time_of_maximum.copy()
    causes: dict[tuple[int, bool], str] = {}
    last = len(jumps) - 1
    for j in range(minimum.size):
        for upper in (False, True):
            best: tuple[float, str] | None = (
                None  # earliest breakpoint that makes this side unbounded
            )
            for k, table in enumerate(jumps):
                column = table[:, j]
                # The next derivative of a step has the step's sign; higher ones both.
                hit = column != 0.0 if k < last else (column > 0 if upper else column < 0)
                if hit.any():
                    i = int(np.argmax(hit))
                    if best is None or times[i] < best[0]:
                        text = f"{QUANTITIES[k]} jumps by {column[i]:.6g} at t={times[i]:.6g} s"
                        best = (float(times[i]), text)
            if best is None:
                continue
            if upper:
                maximum[j], t_max[j] = np.inf, best[0]
            else:
                minimum[j], t_min[j] = -np.inf, best[0]
            causes[(j, upper)] = best[1]
    return (
        type(found)(found.order, minimum, t_min, maximum, t_max),
        causes,
    )


def _largest(jumps: list[FloatArray], times: FloatArray) -> tuple[Discontinuity, ...]:
    """The largest jump per quantity and joint, for the report."""
    out = []
    for k, table in enumerate(jumps):
        for j in range(table.shape[1]):
            column = table[:, j]
            if column.any():
                i = int(np.argmax(np.abs(column)))
                out.append(Discontinuity(QUANTITIES[k], j, float(times[i]), float(column[i])))
    return tuple(out)


def compare(
    quantity: str,
    found: Extrema,
    lower: FloatArray,
    upper: FloatArray,
    rtol: float,
    channels: tuple[str, ...] = (),
    *,
    slack: float | FloatArray = 0.0,
) -> list[Violation]:
    """The worst violation per entry and side of ``found`` against ``(lower, upper)``.

    A value is a violation when it passes its bound by more than ``rtol`` times the
    larger finite magnitude of the two bounds, plus ``slack`` (absolute, per entry
    or one for all). ``channels`` labels the entries (default: joints).
    """
    finite = np.where(np.isfinite(lower), np.abs(lower), 0.0)
    slack = rtol * np.maximum(finite, np.where(np.isfinite(upper), np.abs(upper), 0.0)) + slack
    violations = []
    for j in range(found.minimum.size):
        label = channels[j] if channels else ""
        if found.minimum[j] < lower[j] - slack[j]:
            time, value = float(found.time_of_minimum[j]), float(found.minimum[j])
            violations.append(Violation(quantity, j, time, value, float(lower[j]), label))
        if found.maximum[j] > upper[j] + slack[j]:
            time, value = float(found.time_of_maximum[j]), float(found.maximum[j])
            violations.append(Violation(quantity, j, time, value, float(upper[j]), label))
    return violations
