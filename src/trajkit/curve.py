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

import numpy as np
from numpy.typing import ArrayLike

from trajkit._validation import FloatArray
from trajkit.errors import InvalidInputError

__all__ = ["Curve", "check_order"]


class Curve(ABC):
    """A curve in time (or in a path parameter): ``evaluate(t, order)`` on its interval."""

    __slots__ = ()

    @abstractmethod
    def evaluate(self, t: ArrayLike, order: int = 0) -> FloatArray:
        """The ``order``-th derivative at each ``t``."""

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
        allowed = ", ".join(str(k) for k in range(highest)) + f" or {highest}"
        raise InvalidInputError(f"order must be {allowed}{where}, got {order!r}")
    return int(order)  # type: ignore[arg-type]
