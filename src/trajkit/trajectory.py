"""The core object: an immutable N-DoF piecewise polynomial in time."""

from __future__ import annotations

import itertools
import math
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from trajkit import _poly
from trajkit._validation import (
    FloatArray,
    as_float_array,
    finite_array,
    finite_result,
    increasing_times,
    joint_vector,
    positive_scalar,
)
from trajkit.curve import Curve, check_order
from trajkit.errors import ContinuityWarning, InvalidInputError
from trajkit.renamed import renamed_keywords
from trajkit.tolerances import BOUNDARY_ATOL, BOUNDARY_RTOL, JUMP_RTOL

if TYPE_CHECKING:
    from trajkit.limits import Limits, Report
    from trajkit.samples import Samples

__all__ = ["Extrema", "State", "Trajectory"]

_QUANTITY = ("position", "velocity", "acceleration", "jerk")


@dataclass(frozen=True)
class State:
    """Kinematic state of every joint at one instant (arrays of shape ``(ndof,)``)."""

    position: FloatArray
    velocity: FloatArray
    acceleration: FloatArray
    jerk: FloatArray


@dataclass(frozen=True)
class Extrema:
    """Exact per-joint minima and maxima of one derivative order over the whole trajectory.

    Attributes
    ----------
    order : int
        Derivative order (0 position, 1 velocity, 2 acceleration, 3 jerk).
    minimum, maximum : ndarray, shape (ndof,)
        Extreme values (units of the trajectory per second**order).
    time_of_minimum, time_of_maximum : ndarray, shape (ndof,)
        Times (s) at which they occur (the earliest, if several pieces tie).
    """

    order: int
    minimum: FloatArray
    time_of_minimum: FloatArray
    maximum: FloatArray
    time_of_maximum: FloatArray

    @property
    def peak(self) -> FloatArray:
        """Largest magnitude per joint, ``max(|minimum|, |maximum|)``."""
        return np.maximum(np.abs(self.minimum), np.abs(self.maximum))


class Trajectory(Curve):
    """An N-DoF piecewise polynomial ``q(t)``, the object every trajkit planner returns.

    Piece ``i`` covers ``breakpoints[i] <= t <= breakpoints[i + 1]`` and is the
    polynomial ``sum_j coefficients[j, i, :] * (t - breakpoints[i]) ** (k - j)``:
    the local power basis, highest power first, as in :class:`scipy.interpolate.PPoly`.

    Parameters
    ----------
    breakpoints : array_like, shape (m + 1,)
        Strictly increasing times (s) bounding the ``m`` pieces; ``[t, t]`` (one
        piece of zero length) describes a standstill of zero duration.
    coefficients : array_like, shape (k + 1, m, ndof) or (k + 1, m)
        Local power-basis coefficients; a 2-D array means one joint.
    info : mapping, optional
        Plan data a planner attaches (phase times, limiting joint, ...). Read-only.
    start, end : array_like, shape (r, ndof), optional
        The exact state at ``start_time`` / ``end_time``: row ``i`` is derivative
        ``i`` (position, velocity, ...), one column per joint; a 1-D array is the
        position alone. ``NaN`` means "the polynomial's own value". Planners pass the
        boundary conditions they were given (``qf``, ``vf``...), so that the end of a
        rest-to-rest move reads ``v = 0.0`` exactly rather than a rounding residue
        such as ``-1.4e-10`` (a sign flip a controller sees). Each value must agree
        with the polynomial to ``1e-6 * (1 + scale)``, ``scale`` the size of the
        terms that make up the polynomial's value there.

    Notes
    -----
    Times outside ``[start_time, end_time]`` are clamped: position and every
    derivative take their value at the nearest end (the end state is held). For a
    trajectory that starts and ends at rest this is the same as standing still.
    At ``t <= start_time`` and ``t >= end_time`` the exact ``start`` / ``end``
    values are returned where given; without them, the polynomial's.

    The object never changes after construction; methods return new trajectories.
    """

    __slots__ = ("_breakpoints", "_coefficients", "_derivatives", "_end", "_info", "_start")

    def __init__(
        self,
        breakpoints: ArrayLike,
        coefficients: ArrayLike,
        *,
        info: Mapping[str, Any] | None = None,
        start: ArrayLike | None = None,
        end: ArrayLike | None = None,
    ) -> None:
        raw = finite_array("breakpoints", breakpoints, unit="s")
        if raw.shape == (2,) and raw[0] == raw[1]:
            times = raw  # a zero-duration standstill: what a move of zero length needs
        else:
            times = increasing_times("breakpoints", raw)
        times = np.array(times)  # own copies: they are made read-only below
        c = np.array(finite_array("coefficients", coefficients))
        if c.ndim == 2:
            c = c[:, :, np.newaxis]
        if c.ndim != 3:
            raise InvalidInputError(
                f"coefficients must have shape (k + 1, m, ndof), got shape {c.shape}"
            )
        if c.shape[0] == 0 or c.shape[2] == 0:
            raise InvalidInputError(
                f"coefficients must have at least one order and one joint, got shape {c.shape}"
            )
        if c.shape[1] != times.size - 1:
            raise InvalidInputError(
                f"coefficients describe {c.shape[1]} pieces but breakpoints bound "
                f"{times.size - 1}; coefficients.shape[1] must equal len(breakpoints) - 1"
            )
        times.setflags(write=False)
        c.setflags(write=False)
        self._breakpoints = times
        self._coefficients = c
        self._derivatives: dict[int, FloatArray] = {0: c}
        self._info: Mapping[str, Any] = MappingProxyType(dict(info or {}))
        self._start = self._boundary("start", start, at_end=False)
        self._end = self._boundary("end", end, at_end=True)

    @classmethod
    def _trusted(
        cls,
        breakpoints: FloatArray,
        coefficients: FloatArray,
        info: Mapping[str, Any],
        end: FloatArray | None = None,
        start: FloatArray | None = None,
    ) -> Trajectory:
        """A trajectory from arrays a planner has built and checked (nothing re-validated).

        For planners' hot paths, as :meth:`scipy.interpolate.PPoly.construct_fast`:
        ``breakpoints`` increasing, ``coefficients`` (k + 1, m, ndof) finite, ``start``
        and ``end`` (r, ndof) agreeing with the pieces up to rounding (NaN: the
        polynomial's), all owned by the new object; ``info`` any read-only mapping (it
        may build its values on first access).
        """
        self = object.__new__(cls)
        breakpoints.setflags(write=False)
        coefficients.setflags(write=False)
        self._breakpoints = breakpoints
        self._coefficients = coefficients
        self._derivatives = {0: coefficients}
        self._info = info
        for state in (start, end):
            if state is not None:
                state.setflags(write=False)
        self._start, self._end = start, end
        return self

    def _boundary(self, name: str, value: ArrayLike | None, *, at_end: bool) -> FloatArray | None:
        """The exact boundary state ``value`` as ``(r, ndof)``, checked against the pieces."""
        if value is None:
            return None
        state = self._state_rows(name, value)
        for order, (row, value, off) in enumerate(
            zip(state, *self._boundary_misses(state, at_end), strict=True)
        ):
            if off.any():
                j = int(np.flatnonzero(off)[0])
                where = "end_time" if at_end else "start_time"
                raise InvalidInputError(
                    f"{name}[{order}]: the {_quantity(order)} of joint {j + 1} at the "
                    f"{where.replace('_', ' ')} "
                    f"{float(self._breakpoints[-1 if at_end else 0]):.6g} s is given as "
                    f"{row[j]:.9g} but the polynomial pieces give {value[j]:.9g}; an exact "
                    "boundary state must agree with the pieces up to rounding (a plan ends "
                    "this way when its durations and values are beyond what float64 can "
                    "resolve: too long a duration or too wide a range of magnitudes)"
                )
        state.setflags(write=False)
        return state

    def _state_rows(self, name: str, value: ArrayLike) -> FloatArray:
        """A boundary state as ``(r, ndof)``: row ``i`` is derivative ``i``, NaN allowed."""
        state = np.array(as_float_array(name, value), dtype=np.float64)
        ndof = self.ndof
        if state.ndim == 1:
            state = state[np.newaxis, :]
        if state.ndim != 2 or state.shape[0] == 0 or state.shape[1] != ndof:
            raise InvalidInputError(
                f"{name} must have shape (r, ndof) = (r, {ndof}) with r >= 1 (row i: "
                f"derivative i), got shape {state.shape}"
            )
        if np.isinf(state).any():
            raise InvalidInputError(f"{name} must be finite or NaN, got {state.tolist()}")
        return state

    def _boundary_misses(self, state: FloatArray, at_end: bool) -> tuple[FloatArray, FloatArray]:
        """The pieces' own values at the start or end, and where ``state`` misses them."""
        piece = -1 if at_end else 0
        x = float(self._breakpoints[-1] - self._breakpoints[-2]) if at_end else 0.0
        lengths = np.diff(self._breakpoints)
        values, misses = [], []
        for order, row in enumerate(state):
            every = self._coefficients_of(order)
            c = every[:, piece, :]
            value = _poly.horner(c, x)
            # The size of this derivative's terms anywhere in the motion (what a planner's
            # rounding scales with), not only in the last piece: a joint whose last piece
            # is a short coast near 0 is rounded at the size of its whole move.
            with np.errstate(over="ignore", invalid="ignore"):  # h**k of a 1e300 s piece
                powers = lengths[np.newaxis, :] ** np.arange(every.shape[0] - 1, -1, -1)[:, None]
                product = np.where(every == 0.0, 0.0, np.abs(every) * powers[..., np.newaxis])
                scale = product.sum(axis=0).max(axis=0) + np.abs(row)  # inf near 1e308
            values.append(value)
            miss = np.abs(row - value) > BOUNDARY_RTOL * scale + BOUNDARY_ATOL
            misses.append(miss)  # NaN: no miss
        return np.array(values), np.array(misses)

    def with_info(self, info: Mapping[str, Any]) -> Trajectory:
        """The same motion (pieces and exact boundary states) with ``info`` in place."""
        return Trajectory(self._breakpoints, self._coefficients, info=info, start=self._start,
                          end=self._end)  # fmt: skip

    def with_boundaries_where_they_agree(
        self, *, start: ArrayLike | None = None, end: ArrayLike | None = None
    ) -> Trajectory:
        """A copy with exact boundary states, each value kept only where the pieces agree.

        For planners: a target the pieces reach up to rounding becomes the exact
        boundary value; where the pieces miss it (float64 could not resolve the plan's
        phases, e.g. 1e-9 s phases at t = 1000 s) the polynomial's own value stands,
        so the result never claims a state its pieces do not reach. Entries given as
        NaN are the polynomial's too.
        """
        kept = {}
        for name, value, at_end in (("start", start, False), ("end", end, True)):
            if value is None:
                kept[name] = None
                continue
            state = self._state_rows(name, value)
            _, misses = self._boundary_misses(state, at_end)
            kept[name] = np.where(misses, np.nan, state)
        return Trajectory(self._breakpoints, self._coefficients, info=self._info, **kept)

    # ------------------------------------------------------------------ shape
    @property
    def breakpoints(self) -> FloatArray:
        """Piece boundaries (s), shape ``(m + 1,)``, read-only."""
        return self._breakpoints

    @property
    def coefficients(self) -> FloatArray:
        """Local power-basis coefficients, shape ``(k + 1, m, ndof)``, read-only."""
        return self._coefficients

    @property
    def ndof(self) -> int:
        """Number of joints (degrees of freedom)."""
        return int(self._coefficients.shape[2])

    @property
    def components(self) -> tuple[tuple[str, str], ...]:
        """``(q1, rad), (q2, rad), ...``: joints, in radians unless told otherwise."""
        return tuple((f"q{j + 1}", "rad") for j in range(self.ndof))

    @property
    def degree(self) -> int:
        """Polynomial degree ``k`` of the storage (some pieces may be of lower degree)."""
        return int(self._coefficients.shape[0] - 1)

    @property
    def start_time(self) -> float:
        """First breakpoint (s)."""
        return float(self._breakpoints[0])

    @property
    def end_time(self) -> float:
        """Last breakpoint (s)."""
        return float(self._breakpoints[-1])

    @property
    def duration(self) -> float:
        """``end_time - start_time`` (s)."""
        return float(self._breakpoints[-1] - self._breakpoints[0])

    @property
    def info(self) -> Mapping[str, Any]:
        """Plan data attached by the planner (read-only mapping; may be empty).

        It describes the plan as made: trajectories derived by :meth:`then`,
        :meth:`time_scaled` or :meth:`derivative` carry none.
        """
        return self._info

    @property
    def start_state(self) -> State:
        """Position, velocity, acceleration and jerk at ``start_time``."""
        return self._state_at(self.start_time)

    @property
    def end_state(self) -> State:
        """Position, velocity, acceleration and jerk at ``end_time``."""
        return self._state_at(self.end_time)

    def _end_positions(self) -> FloatArray:
        """Positions at ``start_time`` and ``end_time``, (2, ndof), as :meth:`evaluate` gives them.

        For planners' hot paths: the same values without the call cost.
        """
        c = self._coefficients
        last = self._breakpoints[-1] - self._breakpoints[-2]
        out = np.stack([c[-1, 0], _poly.horner(c[:, -1], last)])
        for row, state in enumerate((self._start, self._end)):
            if state is not None:
                out[row] = np.where(np.isnan(state[0]), out[row], state[0])
        return out

    def _state_at(self, t: float) -> State:
        return State(*(self.evaluate(t, order) for order in range(4)))

    def __repr__(self) -> str:
        return (
            f"Trajectory(ndof={self.ndof}, duration={self.duration:.6g} s, "
            f"pieces={self._coefficients.shape[1]}, degree={self.degree})"
        )

    # ------------------------------------------------------------- evaluation
    def _coefficients_of(self, order: int) -> FloatArray:
        """Coefficients of the ``order``-th derivative, ``(k' + 1, m, ndof)``, cached."""
        cached = self._derivatives.get(order)
        if cached is None:
            cached = _poly.derivative(self._coefficients, order)
            cached.setflags(write=False)
            self._derivatives[order] = cached
        return cached

    def _joint_major(self, order: int) -> FloatArray:
        """The same, laid out ``(k' + 1, ndof, m)`` for evaluation, cached.

        With time as the last (longest) axis, numpy's inner loops run over the
        samples instead of over the few joints; that makes evaluation several
        times faster than the PPoly layout.
        """
        key = -1 - order  # negative keys: joint-major copies
        cached = self._derivatives.get(key)
        if cached is None:
            cached = np.ascontiguousarray(self._coefficients_of(order).transpose(0, 2, 1))
            cached.setflags(write=False)
            self._derivatives[key] = cached
        return cached

    def evaluate(self, t: ArrayLike, order: int = 0) -> FloatArray:
        """Evaluate the ``order``-th time derivative.

        Parameters
        ----------
        t : float or array_like, shape (n,)
            Time(s) in seconds. Values outside ``[start_time, end_time]`` are clamped.
        order : int
            0 position, 1 velocity, 2 acceleration, 3 jerk, any higher order allowed.

        Returns
        -------
        ndarray
            Shape ``(ndof,)`` for a scalar ``t``, ``(n, ndof)`` for a 1-D ``t``.
        """
        check_order(order)
        times = finite_array("t", t, unit="s")
        if times.ndim > 1:
            raise InvalidInputError(f"t must be a number or a 1-D array, got shape {times.shape}")
        c = self._joint_major(int(order))
        bp = self._breakpoints
        # minimum/maximum, not np.clip: the same values at a fraction of the call cost.
        clamped = np.minimum(np.maximum(np.atleast_1d(times), bp[0]), bp[-1])
        if c.shape[2] == 1:
            x = clamped - bp[0]
            result = np.empty((c.shape[1], x.size))
            result[...] = c[0]
            for row in c[1:]:
                result *= x
                result += row
        else:
            piece = np.searchsorted(bp[1:-1], clamped, side="right")
            x = clamped - bp[piece]
            result = np.take(c[0], piece, axis=1)
            for row in c[1:]:
                result *= x
                result += np.take(row, piece, axis=1)
        # The exact boundary states where given: the polynomial there is rounding.
        for state, at_end in ((self._start, False), (self._end, True)):
            if state is None or order >= state.shape[0]:
                continue
            at = np.flatnonzero(clamped >= bp[-1] if at_end else clamped <= bp[0])
            if at.size:
                row = state[order, :, np.newaxis]
                result[:, at] = np.where(np.isnan(row), result[:, at], row)
        # Joint-major result transposed: a (n, ndof) view, no copy.
        return result[:, 0] if times.ndim == 0 else result.T

    def __call__(self, t: ArrayLike) -> FloatArray:
        """Position at ``t``; the same as :meth:`position`."""
        return self.evaluate(t, 0)

    @renamed_keywords(dt="sample_step")
    def sample(self, sample_step: float, *, unit: str | None = "rad") -> Samples:
        """Sample position to jerk every ``sample_step`` seconds; see :meth:`Curve.sample`.

        ``unit`` (default rad) is written into the file headers; the plan's ``info``
        goes into the Samples' metadata.
        """
        return super().sample(sample_step, unit=unit)

    def _metadata(self) -> dict:
        return dict(self.info)

    # ---------------------------------------------------------------- algebra
    def derivative(self, order: int = 1) -> Trajectory:
        """The ``order``-th time derivative as a new Trajectory on the same breakpoints."""
        check_order(order)
        order = int(order)
        return Trajectory(
            self._breakpoints,
            self._coefficients_of(order),
            start=_shift_rows(self._start, order),
            end=_shift_rows(self._end, order),
        )

    def time_scaled(self, factor: float) -> Trajectory:
        """Slow down (``factor > 1``) or speed up (``< 1``) about ``start_time``.

        The result ``r`` satisfies ``r(start + factor * s) == self(start + s)``: the
        duration is multiplied by ``factor``, velocities divided by it, accelerations
        by its square, jerks by its cube.
        """
        scale = positive_scalar("factor", factor)
        bp = self._breakpoints
        with np.errstate(all="ignore"):
            times = bp[0] + (bp - bp[0]) * scale
            coefficients = _poly.scale_argument(self._coefficients, 1.0 / scale)
        # A factor like 1e-300 overflows the scaled rates: name the factor, not them.
        finite_result("time_scaled", times, {"factor": scale})
        finite_result("time_scaled", coefficients, {"factor": scale})
        return Trajectory(
            times,
            coefficients,
            start=_scale_rows(self._start, scale),
            end=_scale_rows(self._end, scale),
        )

    def then(self, other: Trajectory, *, atol: float = 1e-9) -> Trajectory:
        """Concatenate in time: ``other`` starts where this trajectory ends.

        ``other`` is shifted so its ``start_time`` equals this ``end_time``.

        Parameters
        ----------
        other : Trajectory
            Must have the same ``ndof`` and start where this one ends.
        atol : float
            Allowed position mismatch at the junction, relative: joint ``j`` may
            differ by ``atol * (1 + |q_j|)``. Velocity and acceleration jumps above
            ``1e-9 * (1 + |value|)`` are warned about.

        Raises
        ------
        InvalidInputError
            Different joint counts, or the positions do not meet.

        Warns
        -----
        ContinuityWarning
            When velocity or acceleration jump at the junction.
        """
        if not isinstance(other, Trajectory):
            raise InvalidInputError(f"other must be a Trajectory, got {type(other).__name__}")
        if other.ndof != self.ndof:
            raise InvalidInputError(
                f"other has {other.ndof} joints but this trajectory has {self.ndof}"
            )
        tol = positive_scalar("atol", atol)
        end, start = self.end_state, other.start_state
        for order, name in enumerate(_QUANTITY[:3]):
            a, b = getattr(end, name), getattr(start, name)
            # Each joint against its own allowance: a large joint must not hide a small one.
            excess = np.abs(b - a) / ((tol if order == 0 else 1e-9) * (1.0 + np.abs(a)))
            worst = int(np.argmax(excess))
            if excess[worst] <= 1.0:
                continue
            message = (
                f"{name} jumps by {b[worst] - a[worst]:.6g} at joint {worst + 1} "
                f"(from {a[worst]:.6g} to {b[worst]:.6g}) at t={self.end_time:.6g} s"
            )
            if order == 0:
                raise InvalidInputError(f"cannot join trajectories: {message}")
            warnings.warn(message, ContinuityWarning, stacklevel=2)
        # A zero-duration standstill adds no piece.
        if other.duration == 0.0:
            return Trajectory(
                self._breakpoints, self._coefficients, start=self._start, end=self._end
            )
        if self.duration == 0.0:
            offset = self.end_time - other.start_time
            return Trajectory(
                other._breakpoints + offset, other._coefficients, start=other._start,
                end=other._end,
            )  # fmt: skip
        degree = max(self.degree, other.degree)
        c = np.concatenate([_pad(self._coefficients, degree), _pad(other._coefficients, degree)], 1)
        offset = self.end_time - other.start_time
        bp = np.concatenate([self._breakpoints, other._breakpoints[1:] + offset])
        return Trajectory(bp, c, start=self._start, end=other._end)

    def absolute_coefficients(self) -> FloatArray:
        """Coefficients in powers of absolute time ``t`` instead of ``t - breakpoints[i]``.

        Same layout as :attr:`coefficients` (highest power first). This is the form
        hand calculations use (``q(t) = a0 + a1 t + ...``); prefer the local form for
        computation, it is better conditioned.
        """
        shift = self._breakpoints[:-1][:, np.newaxis]
        return _poly.shift_origin(self._coefficients, shift)

    # ---------------------------------------------------------------- queries
    def extrema(self, order: int = 0) -> Extrema:
        """Exact per-joint minimum and maximum of the ``order``-th derivative.

        Found from the roots of the next derivative on every piece (not by sampling),
        together with the piece ends. Each piece counts on its closed interval, so at
        a jump the values approached from both sides are considered.
        """
        check_order(order)
        c = self._coefficients_of(int(order))
        k1, m, ndof = c.shape
        lengths = np.repeat(np.diff(self._breakpoints), ndof)
        low, x_low, high, x_high = _poly.extrema_on_intervals(c.reshape(k1, m * ndof), lengths)
        low, x_low = low.reshape(m, ndof), x_low.reshape(m, ndof)
        high, x_high = high.reshape(m, ndof), x_high.reshape(m, ndof)
        joints = np.arange(ndof)
        i_low, i_high = np.argmin(low, axis=0), np.argmax(high, axis=0)
        starts, stops = self._breakpoints[:-1], self._breakpoints[1:]
        # Clip: start + length can round one ulp past the piece's end.
        return Extrema(
            order=int(order),
            minimum=low[i_low, joints],
            time_of_minimum=np.minimum(starts[i_low] + x_low[i_low, joints], stops[i_low]),
            maximum=high[i_high, joints],
            time_of_maximum=np.minimum(starts[i_high] + x_high[i_high, joints], stops[i_high]),
        )

    def first_time_at(self, value: ArrayLike, order: int = 0) -> FloatArray:
        """Earliest time at which each joint's ``order``-th derivative equals ``value``.

        Parameters
        ----------
        value : float or array_like, shape (ndof,)
            The value sought (units of the trajectory per second**order), one for
            every joint or one per joint.
        order : int
            Derivative order: 0 position (the default), 1 velocity, ...

        Returns
        -------
        ndarray, shape (ndof,)
            Time (s) of the first crossing or touch per joint; NaN where the joint
            never takes the value.

        Notes
        -----
        Exact up to rounding: the first piece whose exact range (see
        :meth:`extrema`) contains the value is split at its turning points and the
        first monotone part containing it is solved by bracketing (Brent). The
        exact start and end states count, so a joint's own target position is
        found at its end even where the pieces stop one rounding short of it.
        """
        from scipy.optimize import brentq

        check_order(order)
        target = joint_vector("value", value, self.ndof)
        c = self._coefficients_of(int(order))
        k1, m, ndof = c.shape
        shifted = c.copy()
        shifted[-1] -= target  # roots of q(t) - value
        lengths = np.diff(self._breakpoints)
        low, _, high, _ = _poly.extrema_on_intervals(
            shifted.reshape(k1, m * ndof), np.repeat(lengths, ndof)
        )
        # The exact range is computed with rounding: a value at an extreme is in it
        # up to a few ulps of the terms (the root search then finds the touch).
        size = (
            np.abs(shifted)
            * lengths[np.newaxis, :, np.newaxis]
            ** np.arange(k1 - 1, -1, -1)[:, np.newaxis, np.newaxis]
        )
        slack = _TOUCH_ULPS * np.finfo(float).eps * (size.sum(axis=0) + np.abs(target))
        contains = (low.reshape(m, ndof) <= slack) & (high.reshape(m, ndof) >= -slack)
        times = np.full(ndof, np.nan)
        ends = (self.evaluate(self.start_time, order), self.evaluate(self.end_time, order))
        for d in range(ndof):
            if ends[0][d] == target[d]:
                times[d] = self.start_time
                continue
            found = np.flatnonzero(contains[:, d])
            if found.size:
                i = int(found[0])
                x = _first_root(shifted[:, i, d], float(lengths[i]), brentq)
                times[d] = min(self._breakpoints[i] + x, self._breakpoints[i + 1])
            elif ends[1][d] == target[d]:
                times[d] = self.end_time
        return times

    def jumps(self, order: int = 0, *, rtol: float = JUMP_RTOL) -> FloatArray:
        """Jump of the ``order``-th derivative at each interior breakpoint.

        The jump is the value the next piece starts with minus the value the
        previous piece ends with, computed exactly from the coefficients. A jump no
        larger than ``rtol * (1 + scale)`` is rounding and reported as 0, ``scale``
        being the size of the terms that make up the two values (the sum of the
        absolute terms of the ending piece, or the starting value).

        Parameters
        ----------
        order : int
            0 position, 1 velocity, 2 acceleration, 3 jerk, any higher order allowed.
        rtol : float
            Relative tolerance (default 1e-9, that of :func:`trajkit.check`).

        Returns
        -------
        ndarray, shape (m - 1, ndof)
            Row ``i`` is the jump at ``breakpoints[i + 1]`` (units of the trajectory
            per second**order); empty for a single piece.
        """
        check_order(order)
        tolerance = positive_scalar("rtol", rtol)
        c = self._coefficients_of(int(order))
        if c.shape[1] < 2:
            return np.zeros((0, self.ndof))
        lengths = np.diff(self._breakpoints)[:-1, np.newaxis]  # (m - 1, 1)
        ending = c[:, :-1, :]
        left = _poly.horner(ending, lengths)
        right = c[-1, 1:, :]
        scale = np.maximum(_poly.horner(np.abs(ending), lengths), np.abs(right))
        jump = right - left
        return np.where(np.abs(jump) > tolerance * (1.0 + scale), jump, 0.0)

    @property
    def continuity(self) -> float:
        """Highest derivative order continuous everywhere, measured from the pieces.

        ``-1`` when the position itself jumps, ``0`` when only the position is
        continuous, ``1`` for continuous velocity (C1), ``2`` for continuous
        acceleration (C2)...; ``math.inf`` when no derivative jumps (a single
        polynomial). Jumps are judged as in :meth:`jumps` (relative tolerance
        1e-9). A planner's claim is in ``info["continuity"]``.
        """
        if self._coefficients.shape[1] < 2:
            return math.inf
        for order in range(self.degree + 1):
            if self.jumps(order).any():
                return order - 1
        return math.inf

    def check(self, limits: Limits, *, rtol: float = 1e-9) -> Report:
        """Verify ``limits`` exactly on the polynomial pieces; see :func:`trajkit.check`."""
        from trajkit.limits import check

        return check(self, limits, rtol=rtol)


def _quantity(order: int) -> str:
    return _QUANTITY[order] if order < len(_QUANTITY) else f"derivative {order}"


def _shift_rows(state: FloatArray | None, order: int) -> FloatArray | None:
    """The boundary state of the ``order``-th derivative: the rows from ``order`` on."""
    return None if state is None or state.shape[0] <= order else state[order:]


def _scale_rows(state: FloatArray | None, factor: float) -> FloatArray | None:
    """The boundary state after slowing down by ``factor``: row ``i`` over ``factor**i``."""
    if state is None:
        return None
    return state / factor ** np.arange(state.shape[0])[:, np.newaxis]


# A value this many ulps (of the terms summed) outside a piece's computed range
# still counts as touched: the range and the value carry that much rounding.
_TOUCH_ULPS = 8


def _first_root(c: FloatArray, length: float, brentq: Any) -> float:
    """Smallest x in [0, length] where the polynomial ``c`` (highest power first) is 0.

    The caller knows the polynomial takes 0 there (up to rounding). Works on the unit
    interval (as :func:`trajkit._poly.extrema_on_intervals` does): split at the
    turning points, bracket the first sign change; where rounding keeps a touch
    at a turning point off zero, the point nearest zero is the answer.
    """
    unit = _poly.scale_argument(c[:, np.newaxis], np.array([length]))[:, 0]
    slope = _poly.derivative(unit[:, np.newaxis], 1)[:, 0]
    turns: list[float] = []
    magnitude = np.max(np.abs(slope)) if slope.size else 0.0
    if magnitude > 0.0 and slope.size > 1:
        significant = np.flatnonzero(np.abs(slope) > _poly.DEGREE_TRIM * magnitude)
        trimmed = slope[significant[0] :] / magnitude
        if trimmed.size > 1:
            roots = np.roots(trimmed)
            turns = sorted(float(r.real) for r in roots if abs(r.imag) <= 1e-9 and 0 < r.real < 1)
    edges = [0.0, *turns, 1.0]

    def f(u: float) -> float:
        return float(np.polyval(unit, u))

    for a, b in itertools.pairwise(edges):
        fa, fb = f(a), f(b)
        if fa == 0.0:
            return a * length
        if (fa < 0.0) != (fb < 0.0) and fb != 0.0:
            return float(brentq(f, a, b, xtol=1e-16, rtol=4 * np.finfo(float).eps)) * length
        if fb == 0.0:
            return b * length
    values = [abs(f(u)) for u in edges]
    return edges[int(np.argmin(values))] * length


def _pad(c: FloatArray, degree: int) -> FloatArray:
    """Prepend zero high-order rows so ``c`` is stored at ``degree``."""
    missing = degree + 1 - c.shape[0]
    if missing == 0:
        return c
    return np.concatenate([np.zeros((missing, *c.shape[1:])), c], axis=0)
