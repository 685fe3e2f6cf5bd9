"""Geometric paths in the workspace, parameterized by ``u`` in [0, 1].

Each path gives its point and its derivatives of any order with respect to ``u``, plus
upper bounds on ``|dp/du|`` and ``|d²p/du²|`` over the whole path: the bounds
turn Cartesian speed and acceleration limits into limits on ``u`` that are
guaranteed, not sampled.
"""

from __future__ import annotations

from abc import abstractmethod

import numpy as np
from numpy.typing import ArrayLike, NDArray

from trajkit._validation import finite_array, finite_scalar, positive_scalar
from trajkit.curve import Curve, check_order
from trajkit.errors import InvalidInputError

FloatArray = NDArray[np.float64]

__all__ = ["Arc", "Ellipse", "FigureEight", "Line", "Path", "Polyline"]


def _point(name: str, value: ArrayLike) -> FloatArray:
    array = finite_array(name, value)
    if array.shape == (2,):
        array = np.append(array, 0.0)
    if array.shape != (3,):
        raise InvalidInputError(f"{name} must be a point (x, y, z) or (x, y), got {array.tolist()}")
    return np.array(array)


def _unit(name: str, value: ArrayLike) -> FloatArray:
    vector = _point(name, value)
    norm = float(np.linalg.norm(vector))
    if norm == 0.0:
        raise InvalidInputError(f"{name} must be a non-zero vector")
    return vector / norm


def _plane(normal: ArrayLike, x_axis: ArrayLike | None) -> tuple[FloatArray, FloatArray]:
    """Orthonormal in-plane axes (e1, e2) with e1 x e2 = normal."""
    n = _unit("normal", normal)
    if x_axis is None:
        helper = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        e1 = helper - n * (helper @ n)
    else:
        e1 = _point("x_axis", x_axis)
        e1 = e1 - n * (e1 @ n)
        if np.linalg.norm(e1) < 1e-12:
            raise InvalidInputError("x_axis must not be parallel to the plane's normal")
    e1 = e1 / np.linalg.norm(e1)
    return e1, np.cross(n, e1)


class Path(Curve):
    """A curve ``p(u)``, ``u`` in [0, 1], in the workspace (length unit of the robot).

    As a :class:`~trajkit.curve.Curve` its "time" is the parameter ``u``: it starts at 0
    and ends at 1, and derivatives are taken with respect to ``u`` (any order).
    """

    parameter = ("path parameter u", "")
    components = (("x", "m"), ("y", "m"), ("z", "m"))

    @property
    def end_time(self) -> float:
        """The path parameter's end, 1."""
        return 1.0

    @abstractmethod
    def evaluate(self, u: ArrayLike, order: int = 0) -> FloatArray:
        """Point (order 0) or derivative ``d^k p / du^k`` (order ``k``) at each ``u``: (m, 3)."""

    @property
    @abstractmethod
    def speed_bound(self) -> float:
        """An upper bound on ``|dp/du|`` over ``u`` in [0, 1]."""

    @property
    @abstractmethod
    def curvature_bound(self) -> float:
        """An upper bound on ``|d²p/du²|`` over ``u`` in [0, 1]."""

    @property
    def start(self) -> FloatArray:
        """The point at ``u = 0``."""
        return self.evaluate(0.0)[0]

    @property
    def end(self) -> FloatArray:
        """The point at ``u = 1``."""
        return self.evaluate(1.0)[0]

    def _parameters(self, u: ArrayLike, order: int) -> FloatArray:
        check_order(order, where=" for a path")
        return np.atleast_1d(finite_array("u", u)).reshape(-1)


class Line(Path):
    """Straight segment from ``start`` to ``end``: ``p(u) = start + u (end - start)``."""

    def __init__(self, start: ArrayLike, end: ArrayLike) -> None:
        self._start = _point("start", start)
        self._delta = _point("end", end) - self._start

    def evaluate(self, u: ArrayLike, order: int = 0) -> FloatArray:  # noqa: D102
        u = self._parameters(u, order)
        if order == 0:
            return self._start + u[:, np.newaxis] * self._delta
        if order == 1:
            return np.broadcast_to(self._delta, (u.size, 3)).copy()
        return np.zeros((u.size, 3))  # straight: no second or higher derivative

    @property
    def speed_bound(self) -> float:  # noqa: D102
        return float(np.linalg.norm(self._delta))

    @property
    def curvature_bound(self) -> float:  # noqa: D102
        return 0.0


def _sine_derivative(phi: FloatArray, order: int) -> FloatArray:
    """``d^order/dφ^order sin(φ)``: sin, cos, -sin, -cos in turn (exact zeros kept)."""
    return (np.sin, np.cos, lambda x: -np.sin(x), lambda x: -np.cos(x))[order % 4](phi)


class _Conic(Path):
    """``p = c + a cos(φ) e1 + b sin(k φ) e2`` with ``φ = φ0 + span u``."""

    def __init__(
        self,
        center: FloatArray,
        a: float,
        b: float,
        e1: FloatArray,
        e2: FloatArray,
        phase: float,
        span: float,
        harmonic: float = 1.0,
        sine_first: bool = False,
    ) -> None:
        self._center, self._a, self._b = center, a, b
        self._e1, self._e2 = e1, e2
        self._phase, self._span, self._k = phase, span, harmonic
        self._sine_first = sine_first

    def evaluate(self, u: ArrayLike, order: int = 0) -> FloatArray:
        u = self._parameters(u, order)
        phi = self._phase + self._span * u
        w = self._span
        k = self._k
        if self._sine_first:  # x = a sin(φ), y = b sin(kφ)
            first = w**order * _sine_derivative(phi, order)
        else:
            first = w**order * _sine_derivative(phi, order + 1)  # cos is sin's derivative
        second = (k * w) ** order * _sine_derivative(k * phi, order)
        out = (self._a * first)[:, np.newaxis] * self._e1 + (self._b * second)[
            :, np.newaxis
        ] * self._e2
        return out + self._center if order == 0 else out

    @property
    def speed_bound(self) -> float:
        w = abs(self._span)
        return float(np.hypot(self._a * w, self._b * self._k * w))

    @property
    def curvature_bound(self) -> float:
        w = abs(self._span)
        return float(np.hypot(self._a * w**2, self._b * (self._k * w) ** 2))


class Arc(_Conic):
    """Circular arc from ``start``, turning by ``angle`` about an axis through ``center``.

    Parameters
    ----------
    center : array_like, shape (3,) or (2,)
    start : array_like, shape (3,) or (2,)
        First point; its distance from the axis is the radius.
    angle : float
        Signed sweep (rad), right-handed about ``normal``; ``2π`` for a full circle.
    normal : array_like, shape (3,)
        Axis direction (default +z).
    """

    def __init__(
        self,
        center: ArrayLike,
        start: ArrayLike,
        angle: float,
        normal: ArrayLike = (0.0, 0.0, 1.0),
    ) -> None:
        c = _point("center", center)
        n = _unit("normal", normal)
        offset = _point("start", start) - c
        axial = n * (offset @ n)
        radial = offset - axial
        radius = float(np.linalg.norm(radial))
        if radius == 0.0:
            raise InvalidInputError("start lies on the arc's axis: the radius would be 0")
        sweep = finite_scalar("angle", angle, unit="rad")
        if sweep == 0.0:
            raise InvalidInputError("angle must be non-zero")
        e1 = radial / radius
        super().__init__(c + axial, radius, radius, e1, np.cross(n, e1), 0.0, sweep)
        self.radius = radius


class Ellipse(_Conic):
    """Ellipse ``c + a cos(φ) e1 + b sin(φ) e2``, ``φ = phase + 2π turns u`` (seed 002's family).

    ``b = 0`` gives a segment traced back and forth harmonically, as seed 002's arm
    does with ``x = 0.9 cos(2πt/T) sqrt((L1+L2)² - h²), y = h``.

    Parameters
    ----------
    center : array_like
    a, b : float
        Semi-axes along ``x_axis`` and the in-plane perpendicular (>= 0, a > 0).
    turns : float
        Revolutions over ``u`` in [0, 1] (default 1).
    phase : float
        Start angle (rad).
    normal, x_axis : array_like
        Plane normal (default +z) and the direction of ``a`` (default: +x
        projected on the plane).
    """

    def __init__(
        self,
        center: ArrayLike,
        a: float,
        b: float,
        *,
        turns: float = 1.0,
        phase: float = 0.0,
        normal: ArrayLike = (0.0, 0.0, 1.0),
        x_axis: ArrayLike | None = (1.0, 0.0, 0.0),
    ) -> None:
        a = positive_scalar("a", a)
        b = finite_scalar("b", b)
        if b < 0:
            raise InvalidInputError(f"b must be >= 0, got {b:g}")
        e1, e2 = _plane(normal, x_axis)
        span = 2 * np.pi * finite_scalar("turns", turns)
        if span == 0.0:
            raise InvalidInputError("turns must be non-zero")
        super().__init__(
            _point("center", center), a, b, e1, e2, finite_scalar("phase", phase), span
        )


class FigureEight(_Conic):
    """Figure eight ``x = (W/2) sin(2πu), y = (H/2) sin(4πu)`` about ``center`` (seed 002).

    Parameters
    ----------
    center : array_like
    width, height : float
        Overall width ``W`` and height ``H`` (> 0).
    normal, x_axis : array_like
        Plane normal (default +z) and the width direction (default +x).
    """

    def __init__(
        self,
        center: ArrayLike,
        width: float,
        height: float,
        *,
        normal: ArrayLike = (0.0, 0.0, 1.0),
        x_axis: ArrayLike | None = (1.0, 0.0, 0.0),
    ) -> None:
        w = positive_scalar("width", width)
        h = positive_scalar("height", height)
        e1, e2 = _plane(normal, x_axis)
        super().__init__(
            _point("center", center), w / 2, h / 2, e1, e2, 0.0, 2 * np.pi, 2.0, sine_first=True
        )


class Polyline(Path):
    """Straight segments through waypoints, ``u`` proportional to distance travelled.

    The velocity direction jumps at each inner waypoint; to pass them without a
    jump, time the path with a law that stops there
    (:func:`~trajkit.taskspace.through_waypoints`).
    """

    def __init__(self, waypoints: ArrayLike) -> None:
        points = finite_array("waypoints", waypoints)
        if points.ndim != 2 or points.shape[1] not in (2, 3) or points.shape[0] < 2:
            raise InvalidInputError(
                f"waypoints must have shape (k, 3) or (k, 2) with k >= 2, got {points.shape}"
            )
        if points.shape[1] == 2:
            points = np.concatenate([points, np.zeros((points.shape[0], 1))], axis=1)
        lengths = np.linalg.norm(np.diff(points, axis=0), axis=1)
        if np.any(lengths == 0.0):
            i = int(np.flatnonzero(lengths == 0.0)[0])
            raise InvalidInputError(f"waypoints {i} and {i + 1} coincide")
        self.waypoints = np.array(points)
        self.length = float(lengths.sum())
        self.knots = np.concatenate([[0.0], np.cumsum(lengths)]) / self.length

    def evaluate(self, u: ArrayLike, order: int = 0) -> FloatArray:  # noqa: D102
        u = np.clip(self._parameters(u, order), 0.0, 1.0)
        segment = np.clip(np.searchsorted(self.knots, u, side="right") - 1, 0, len(self.knots) - 2)
        delta = self.waypoints[segment + 1] - self.waypoints[segment]
        width = (self.knots[segment + 1] - self.knots[segment])[:, np.newaxis]
        if order == 0:
            return (
                self.waypoints[segment]
                + (u[:, np.newaxis] - self.knots[segment, np.newaxis]) / width * delta
            )
        if order == 1:
            return delta / width
        return np.zeros((u.size, 3))  # straight pieces: no higher derivative

    @property
    def speed_bound(self) -> float:  # noqa: D102
        return self.length

    @property
    def curvature_bound(self) -> float:  # noqa: D102
        return 0.0
