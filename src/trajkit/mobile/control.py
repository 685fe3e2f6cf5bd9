"""Tracking controllers for a unicycle, and saturation of commands to the limits.

A controller is a small immutable object of gains. :func:`trajkit.mobile.simulate`
asks it for a *law* bound to one plan and start pose; the law maps the measured
pose and the desired state to a twist command ``(v, ω)``, and may carry an
internal state of its own (the dynamic feedback linearization integrates v).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from trajkit._validation import FloatArray, positive_scalar
from trajkit.errors import InvalidInputError
from trajkit.limits import Bounds
from trajkit.mobile.limits import MobileLimits
from trajkit.mobile.models import DiffDrive, Model
from trajkit.mobile.trajectory import MobileTrajectory

__all__ = [
    "ControlLaw",
    "Controller",
    "FeedbackLinearization",
    "Feedforward",
    "Kanayama",
    "PurePursuit",
    "saturate",
]

# The desired state handed to a law: x, y, θ, v, ω, dv/dt, dω/dt.
Desired = tuple[float, float, float, float, float, float, float]


class ControlLaw(Protocol):
    """A controller bound to one run: ``initial_state`` and the command function."""

    initial_state: FloatArray

    def advance(self, t: float, pose: FloatArray) -> None:
        """Called once at the start of every step with the measured pose."""

    def __call__(
        self, t: float, pose: FloatArray, desired: Desired, internal: FloatArray
    ) -> tuple[float, float, FloatArray]:
        """Command ``(v, ω)`` and the rate of the internal state."""


class Controller(Protocol):
    """Anything that can make a :class:`ControlLaw` for a plan."""

    name: str

    def law(self, plan: MobileTrajectory, start: FloatArray) -> ControlLaw:
        """A fresh law for one run of ``plan`` from the pose ``start``."""


_NO_STATE = np.zeros(0)


def _wrap(angle: float) -> float:
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


class _StatelessLaw:
    """Base of laws without internal state."""

    initial_state = _NO_STATE

    def advance(self, t: float, pose: FloatArray) -> None:
        """Nothing to update."""


@dataclass(frozen=True)
class Feedforward:
    """Open loop: send the plan's own twist, ignoring the measured pose."""

    name: str = "feedforward"

    def law(self, plan: MobileTrajectory, start: FloatArray) -> ControlLaw:  # noqa: D102
        return _FeedforwardLaw()


class _FeedforwardLaw(_StatelessLaw):
    def __call__(self, t, pose, desired, internal):  # type: ignore[no-untyped-def]
        return desired[3], desired[4], _NO_STATE


def _gain(name: str, value: float, unit: str) -> float:
    return positive_scalar(name, value, unit=unit)


@dataclass(frozen=True)
class Kanayama:
    """Kanayama et al. (1990) tracking law on the error in the robot's frame.

    With ``e_x, e_y`` the position error in the robot frame and ``e_θ`` the
    heading error: ``v = v_d cos e_θ + k_x e_x``,
    ``ω = ω_d + v_d k_y e_y + |v_d| k_θ sin e_θ`` (the absolute value makes it
    work driving backwards too). The position error converges while the plan
    moves (``v_d ≠ 0``); in a turn in place only the heading is corrected.

    Parameters
    ----------
    kx : float
        Along-track gain (1/s).
    ky : float
        Cross-track gain (1/m²).
    ktheta : float
        Heading gain (1/m).
    """

    kx: float = 2.0
    ky: float = 16.0
    ktheta: float = 6.0
    name: str = "kanayama"

    def __post_init__(self) -> None:
        for attribute, unit in (("kx", "1/s"), ("ky", "1/m^2"), ("ktheta", "1/m")):
            object.__setattr__(self, attribute, _gain(attribute, getattr(self, attribute), unit))

    def law(self, plan: MobileTrajectory, start: FloatArray) -> ControlLaw:  # noqa: D102
        return _KanayamaLaw(self.kx, self.ky, self.ktheta)


class _KanayamaLaw(_StatelessLaw):
    def __init__(self, kx: float, ky: float, ktheta: float) -> None:
        self.kx, self.ky, self.ktheta = kx, ky, ktheta

    def __call__(self, t, pose, desired, internal):  # type: ignore[no-untyped-def]
        x, y, theta = pose
        xd, yd, thd, vd, wd = desired[:5]
        c, s = math.cos(theta), math.sin(theta)
        dx, dy = xd - x, yd - y
        ex, ey = c * dx + s * dy, -s * dx + c * dy
        eth = _wrap(thd - theta)
        v = vd * math.cos(eth) + self.kx * ex
        # |v_d| on the heading term keeps the law stable when driving backwards.
        w = wd + vd * self.ky * ey + abs(vd) * self.ktheta * math.sin(eth)
        return v, w, _NO_STATE


@dataclass(frozen=True)
class FeedbackLinearization:
    """Dynamic feedback linearization (Oriolo, De Luca, Vendittelli 2002).

    The speed becomes a state ``ξ`` (``v = ξ``); with
    ``u = p̈_d + k_p (p_d - p) + k_d (ṗ_d - ṗ)`` the position obeys ``p̈ = u``:
    ``ξ̇ = u_1 cos θ + u_2 sin θ`` and ``ω = (u_2 cos θ - u_1 sin θ) / ξ``. The
    error then decays as a critically damped pair for ``k_d² = 4 k_p``.

    Parameters
    ----------
    kp : float
        Position gain (1/s²).
    kd : float
        Velocity gain (1/s).
    min_speed : float
        ``|ξ|`` is kept above this (m/s): the law is singular at ``ξ = 0``.

    Notes
    -----
    The law needs the robot to move: it cannot turn in place (use
    :class:`Kanayama` for plans with turns in place), and where a plan starts or
    ends at rest the heading there is whatever the position error leaves. From
    rest, ``ξ`` starts at ``min_speed`` in the direction of the plan's first motion.
    """

    kp: float = 4.0
    kd: float = 4.0
    min_speed: float = 1e-3
    name: str = "feedback linearization"

    def __post_init__(self) -> None:
        for attribute, unit in (("kp", "1/s^2"), ("kd", "1/s"), ("min_speed", "m/s")):
            object.__setattr__(self, attribute, _gain(attribute, getattr(self, attribute), unit))

    def law(self, plan: MobileTrajectory, start: FloatArray) -> ControlLaw:  # noqa: D102
        speeds = plan.twist(np.linspace(0.0, plan.duration, 1001))[:, 0]
        moving = np.flatnonzero(np.abs(speeds) >= self.min_speed)
        # From rest, ξ starts small in the direction the plan first drives.
        v0 = speeds[0] if abs(speeds[0]) >= self.min_speed else (
            math.copysign(self.min_speed, speeds[moving[0]]) if moving.size else self.min_speed
        )  # fmt: skip
        return _LinearizationLaw(self.kp, self.kd, self.min_speed, float(v0))


class _LinearizationLaw(_StatelessLaw):
    def __init__(self, kp: float, kd: float, min_speed: float, v0: float) -> None:
        self.kp, self.kd, self.min_speed = kp, kd, min_speed
        self.initial_state = np.array([v0])

    def __call__(self, t, pose, desired, internal):  # type: ignore[no-untyped-def]
        x, y, theta = pose
        xd, yd, thd, vd, wd, ad = desired[:6]
        xi = float(internal[0])
        if abs(xi) < self.min_speed:
            xi = math.copysign(self.min_speed, xi) if xi else self.min_speed
        c, s = math.cos(theta), math.sin(theta)
        cd, sd = math.cos(thd), math.sin(thd)
        u1 = (ad * cd - vd * wd * sd) + self.kp * (xd - x) + self.kd * (vd * cd - xi * c)
        u2 = (ad * sd + vd * wd * cd) + self.kp * (yd - y) + self.kd * (vd * sd - xi * s)
        return xi, (u2 * c - u1 * s) / xi, np.array([u1 * c + u2 * s])


_PATH_POINTS = 4000  # samples of the plan's path that pure pursuit steers along
_CRAWL = 0.05  # pure pursuit's least speed, a fraction of the plan's peak, until the end


@dataclass(frozen=True)
class PurePursuit:
    """Pure pursuit: steer along the arc to a point ``lookahead`` metres ahead on the path.

    The path is the plan's, sampled densely; the speed is the plan's at the
    nearest path point (at least 5 % of its peak, so that a plan from rest gets
    going), or ``speed``: the robot follows the path, not the clock, and stops
    at its end. It cannot turn in place. Curvature ``κ = 2 y_L / L²`` for the
    look-ahead point at distance ``L`` and lateral offset ``y_L`` in the robot frame; ``ω = v κ``.

    Parameters
    ----------
    lookahead : float
        Look-ahead distance (m).
    speed : float, optional
        Constant speed (m/s) instead of the plan's, in the plan's direction of travel.
    """

    lookahead: float = 0.3
    speed: float | None = None
    name: str = "pure pursuit"

    def __post_init__(self) -> None:
        object.__setattr__(self, "lookahead", _gain("lookahead", self.lookahead, "m"))
        if self.speed is not None:
            object.__setattr__(self, "speed", _gain("speed", self.speed, "m/s"))

    def law(self, plan: MobileTrajectory, start: FloatArray) -> ControlLaw:  # noqa: D102
        times = np.linspace(0.0, plan.duration, _PATH_POINTS)
        state = plan.state(times)
        return _PursuitLaw(np.stack([state.x, state.y], 1), state.v, self.lookahead, self.speed)


class _PursuitLaw(_StatelessLaw):
    def __init__(
        self, path: FloatArray, speeds: FloatArray, lookahead: float, speed: float | None
    ) -> None:
        steps = np.linalg.norm(np.diff(path, axis=0), axis=1)
        # Turns in place repeat a point: keep one, or the nearest point stalls there.
        keep = np.concatenate([[True], steps > 0.0])
        self.path, self.speeds = path[keep], speeds[keep]
        self.lookahead, self.speed = lookahead, speed
        self.crawl = _CRAWL * float(np.abs(speeds).max())
        self.arclength = np.concatenate([[0.0], np.cumsum(steps[keep[1:]])])
        self.nearest = 0
        # Search only a window ahead: a crossing curve (a figure eight) has two near points.
        self.window = max(int(np.searchsorted(self.arclength, 4.0 * lookahead)), 8)

    def advance(self, t: float, pose: FloatArray) -> None:
        """Move the nearest path point forward (never back) to the robot."""
        stop = min(self.nearest + self.window, len(self.path))
        ahead = self.path[self.nearest : stop]
        distance = np.hypot(ahead[:, 0] - pose[0], ahead[:, 1] - pose[1])
        self.nearest += int(np.argmin(distance))

    def __call__(self, t, pose, desired, internal):  # type: ignore[no-untyped-def]
        x, y, theta = pose
        last = len(self.path) - 1
        target_length = self.arclength[self.nearest] + self.lookahead
        index = min(int(np.searchsorted(self.arclength, target_length)), last)
        px, py = self.path[index]
        dx, dy = px - x, py - y
        lateral = -math.sin(theta) * dx + math.cos(theta) * dy
        distance2 = dx * dx + dy * dy
        if self.speed is not None:
            # Slow down over the last look-ahead so as to stop at the end of the path.
            remaining = self.arclength[-1] - self.arclength[self.nearest]
            here, there = float(self.speeds[self.nearest]), float(self.speeds[index])
            direction = here if here != 0.0 else there  # backwards where the plan reverses
            v = math.copysign(self.speed * min(1.0, remaining / self.lookahead), direction)
        else:
            # The plan's speed where the robot is on the path, but at least a crawl:
            # a plan that starts at rest would otherwise never get the robot going.
            here, there = float(self.speeds[self.nearest]), float(self.speeds[index])
            v = math.copysign(max(abs(here), self.crawl), here if here != 0.0 else there)
        if self.nearest >= last:
            v = 0.0  # the end of the path is reached
        curvature = 2.0 * lateral / distance2 if distance2 > 1e-18 else 0.0
        return v, v * curvature, _NO_STATE


def nearest_path_distance(path: FloatArray, points: FloatArray) -> FloatArray:
    """Distance from each of ``points`` (n, 2) to the polyline ``path`` (m, 2), in m.

    The nearest vertex is found with a k-d tree, then the point is projected onto
    the two segments beside it. Repeated consecutive vertices (the base standing
    still, turning in place) are dropped first: a segment of zero length beside the
    nearest vertex would hide the real one.
    """
    moves = np.concatenate([[True], np.any(np.diff(path, axis=0) != 0.0, axis=1)])
    path = path[moves]
    if len(path) == 1:
        return np.linalg.norm(points - path[0], axis=1)
    from scipy.spatial import cKDTree  # slow to import: on first use

    tree = cKDTree(path)
    _, index = tree.query(points)
    best = np.linalg.norm(points - path[index], axis=1)
    for offset in (-1, 0):  # the segment before and the segment after the vertex
        a = np.clip(index + offset, 0, len(path) - 2)
        start, stop = path[a], path[a + 1]
        along = stop - start
        length2 = np.einsum("ij,ij->i", along, along)
        with np.errstate(divide="ignore", invalid="ignore"):
            u = np.clip(np.einsum("ij,ij->i", points - start, along) / length2, 0.0, 1.0)
        u = np.where(length2 > 0.0, u, 0.0)
        foot = start + u[:, np.newaxis] * along
        best = np.minimum(best, np.linalg.norm(points - foot, axis=1))
    return best


def saturate(v: float, omega: float, model: Model, limits: MobileLimits) -> tuple[float, float]:
    """Clip a twist command to the speed and turn-rate limits, then to the wheel limit.

    When a wheel would pass its limit, both ``v`` and ``ω`` are scaled down by the
    same factor, which keeps the path's curvature.
    """
    v, omega = _clip(v, limits.velocity), _clip(omega, limits.angular_velocity)
    if isinstance(model, DiffDrive) and limits.wheel_speed is not None:
        half = model.effective_track / 2.0
        left = (v - omega * half) / model.wheel_radius
        right = (v + omega * half) / model.wheel_radius
        factor = 1.0
        lower, upper = float(limits.wheel_speed.lower), float(limits.wheel_speed.upper)
        for speed in (float(left), float(right)):
            # Only a wheel past its limit scales the command (and no tiny speed divides).
            if speed > upper:
                factor = min(factor, upper / speed)
            elif speed < lower:
                factor = min(factor, lower / speed)
        v, omega = v * factor, omega * factor
    return v, omega


def _clip(value: float, bounds: Bounds | None) -> float:
    if bounds is None:
        return value
    return min(max(value, float(bounds.lower)), float(bounds.upper))


def controller_named(name: str) -> Controller:
    """The controller with default gains for a name used on the command line."""
    controllers: dict[str, Controller] = {
        "feedforward": Feedforward(),
        "kanayama": Kanayama(),
        "linearization": FeedbackLinearization(),
        "pure-pursuit": PurePursuit(),
    }
    if name not in controllers:
        raise InvalidInputError(
            f"controller must be one of {', '.join(sorted(controllers))}, got {name!r}"
        )
    return controllers[name]
