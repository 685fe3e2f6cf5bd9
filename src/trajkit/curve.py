"""The protocol every time-parametrized curve in trajkit answers.

A :class:`Curve` is evaluated by ``evaluate(t, order)``: the ``order``-th derivative
at each ``t`` of ``[start_time, end_time]``, one row per ``t``. Its ``breakpoints``
are where a derivative may jump. ``position``, ``velocity``, ``acceleration`` and
``jerk`` are ``evaluate`` of orders 0 to 3, written once here.

Joint trajectories (:class:`~trajkit.Trajectory`), batches of them, flat outputs of
wheeled bases and geometric paths (parametrized by ``u`` in [0, 1]) are curves.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Iterator
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike

from trajkit._validation import FloatArray, positive_scalar
from trajkit.errors import InvalidInputError

if TYPE_CHECKING:
    from trajkit.samples import Samples

__all__ = ["MAX_SAMPLES", "Curve", "Segmented", "check_order", "sample_count", "sample_times"]


class Curve(ABC):
    """A curve in time (or in a path parameter): ``evaluate(t, order)`` on its interval."""

    __slots__ = ()

    #: The highest derivative order :meth:`evaluate` answers (None: every order).
    highest_order: ClassVar[int | None] = None
    #: What the curve is a function of, and its unit: what plots put on the x axis.
    parameter: ClassVar[tuple[str, str]] = ("time", "s")

    @abstractmethod
    def evaluate(self, t: ArrayLike, order: int = 0) -> FloatArray:
        """The ``order``-th derivative at each ``t``."""

    @property
    def components(self) -> tuple[tuple[str, str], ...]:
        """A ``(name, unit)`` per column of :meth:`evaluate` (of its values, order 0).

        Plots label their lines and axes with them. Without a better name a
        column is ``c1, c2, ...`` and its unit unknown (``""``).
        """
        width = int(np.shape(self.evaluate(self.start_time))[-1])
        return tuple((f"c{k + 1}", "") for k in range(width))

    @property
    def start_time(self) -> float:
        """Where the curve starts (s, or the path parameter)."""
        return 0.0

    @property
    @abstractmethod
    def end_time(self) -> float:
        """Where the curve ends (s, or the path parameter)."""

    @property
    def duration(self) -> float:
        """``end_time - start_time``."""
        return self.end_time - self.start_time

    @property
    def breakpoints(self) -> FloatArray:
        """Where a derivative may jump; always includes both ends."""
        return np.array([self.start_time, self.end_time])

    def sample(self, sample_step: float, *, unit: str | None = None) -> Samples:
        """Sample position to jerk every ``sample_step`` seconds from start to end.

        The times are ``start_time + i * sample_step`` (no accumulated rounding) and the
        end time is always the last sample, exactly; when the duration is not a whole
        multiple of ``sample_step`` the last interval is shorter (a grid point within
        ``1e-9 sample_step`` of the end is moved onto it, so that interval may be longer
        by that much). The Samples write CSV, JSON and NPZ files.

        Parameters
        ----------
        sample_step : float
            Sampling period (s), > 0.
        unit : str, optional
            Position unit written into file headers; default the curve's own (rad
            for joints, m for a tool), which must be one for all columns.

        Raises
        ------
        InvalidInputError
            The curve is not a function of time (a path: time it first), has no
            jerk, or has columns in several units and no ``unit`` was given.
        """
        from trajkit.samples import Samples

        kind = type(self).__name__
        if self.parameter != ("time", "s"):
            raise InvalidInputError(
                f"a {kind} is a function of the {self.parameter[0]}, not of time: "
                "time it first (trajkit.taskspace.timed) and sample that"
            )
        if self.highest_order is not None and self.highest_order < 3:
            raise InvalidInputError(
                f"samples hold position to jerk, and a {kind} has derivatives up to "
                f"order {self.highest_order} only"
            )
        step = positive_scalar("sample_step", sample_step, unit="s")
        names, units = zip(*self.components, strict=True)
        if unit is None:
            known = list(dict.fromkeys(units))
            if known == [""]:
                raise InvalidInputError(
                    f"the unit of a {kind}'s values is not known: give it, unit='...'"
                )
            if len(known) != 1:
                raise InvalidInputError(
                    f"the columns of a {kind} are in {', '.join(repr(u) for u in known)}: "
                    "give the position unit, unit='...'"
                )
            unit = known[0]
        times = sample_times(self.start_time, self.end_time, step)
        derivatives = [self.evaluate(times, order) for order in range(4)]
        return Samples(times, *derivatives, unit=unit, names=names, metadata=self._metadata())

    def _metadata(self) -> dict:
        """What :meth:`sample` keeps of the plan in its Samples (JSON and NPZ files)."""
        return {}

    def position(self, t: ArrayLike) -> FloatArray:
        """The value at ``t`` (:meth:`evaluate` of order 0)."""
        return self.evaluate(t, 0)

    def velocity(self, t: ArrayLike) -> FloatArray:
        """The first derivative at ``t``."""
        return self.evaluate(t, 1)

    def acceleration(self, t: ArrayLike) -> FloatArray:
        """The second derivative at ``t``."""
        return self.evaluate(t, 2)

    def jerk(self, t: ArrayLike) -> FloatArray:
        """The third derivative at ``t``."""
        return self.evaluate(t, 3)


class Segmented(Curve):
    """A curve made of segments played one after another from ``t = 0``.

    Subclasses store their segments and the segments' durations (s) with
    :meth:`_store`; the segment boundaries are the breakpoints.
    """

    __slots__ = ()

    def _store(self, segments: tuple, durations: ArrayLike) -> None:
        self._segments = segments
        self._durations = np.array(durations, dtype=float)
        self._breakpoints = np.concatenate([[0.0], np.cumsum(self._durations)])
        self._breakpoints.setflags(write=False)

    @property
    def segments(self) -> tuple:
        """The segments, in order."""
        return self._segments

    @property
    def breakpoints(self) -> FloatArray:
        """Segment boundaries (s), shape ``(len(segments) + 1,)``, from 0 (read-only)."""
        return self._breakpoints

    @property
    def end_time(self) -> float:
        """The total duration (s): segmented curves start at 0."""
        return float(self._breakpoints[-1])

    def _pieces(self, times: FloatArray) -> Iterator[tuple[Any, np.ndarray, FloatArray]]:
        """``(segment, mask, local times)`` of each segment that holds one of ``times``.

        Times are clamped to ``[0, end_time]`` and each goes to the last segment
        starting at or before it; local times run from 0 to the
        segment's duration. A loop over segments, not samples.
        """
        bp = self._breakpoints
        clamped = np.clip(times, 0.0, bp[-1])
        index = np.clip(np.searchsorted(bp, clamped, side="right") - 1, 0, len(self._segments) - 1)
        for k, segment in enumerate(self._segments):
            mask = index == k
            if mask.any():
                # Its own duration, not bp[k + 1] - bp[k], which rounding can make longer.
                yield segment, mask, np.minimum(clamped[mask] - bp[k], self._durations[k])


def check_order(order: object, highest: int | None = None, where: str = "") -> int:
    """``order`` as an int if it is a derivative order a curve has (0 to ``highest``).

    Raises
    ------
    InvalidInputError
        Naming the orders allowed (and ``where``, e.g. " for a task trajectory").
    """
    whole = not isinstance(order, bool) and isinstance(order, int | np.integer) and order >= 0
    if highest is None:
        if not whole:
            raise InvalidInputError(f"order must be a whole number >= 0{where}, got {order!r}")
    elif not whole or order > highest:
        allowed = ", ".join(str(k) for k in range(highest)) + f" or {highest}" if highest else "0"
        raise InvalidInputError(f"order must be {allowed}{where}, got {order!r}")
    return int(order)  # type: ignore[arg-type]


MAX_SAMPLES = 100_000_000  # more would not fit in memory several times over: refused


def sample_count(span: float, step: float, name: str = "sample_step") -> int:
    """``floor(span / step)`` (up to rounding), refusing grids beyond :data:`MAX_SAMPLES`."""
    ratio = span / step
    if not ratio <= MAX_SAMPLES:
        raise InvalidInputError(
            f"{name}={step:g} s over {span:g} s gives {ratio:.3g} samples; at most "
            f"{MAX_SAMPLES:.0e} are made: use a longer {name}"
        )
    return int(np.floor(ratio * (1.0 + 1e-12)))


def sample_times(start: float, end: float, step: float, name: str = "sample_step") -> FloatArray:
    """``start + i * step`` up to ``end``, which is always the last time, exactly.

    A grid point within ``1e-9 step`` of the end is moved onto it; otherwise the
    end is appended and the last interval is shorter. ``name`` is what a refusal
    of too many samples calls the step.
    """
    count = sample_count(end - start, step, name)
    times = start + step * np.arange(count + 1)
    if end - times[-1] <= 1e-9 * step:
        times[-1] = end
    else:
        times = np.append(times, end)
    return times
