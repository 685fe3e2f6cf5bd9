"""Kinematic models of wheeled robots: the unicycle and the differential drive.

A pose is ``(x, y, θ)`` in metres and radians in the world frame; a twist is
``(v, ω)``: forward speed (m/s) and turn rate (rad/s) in the body frame. Both
models move by ``ẋ = v cos θ``, ``ẏ = v sin θ``, ``θ̇ = ω``; a differential drive
adds wheels, whose speeds (rad/s) follow from the twist exactly.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import InitVar, dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from trajkit._validation import FloatArray, finite_array, finite_scalar, positive_scalar
from trajkit.errors import InvalidInputError
from trajkit.mobile.limits import MobileLimits, check_limits

__all__ = [
    "DiffDrive",
    "Model",
    "Unicycle",
    "arc_pose",
    "constant_twist_pose",
    "jackal",
    "pose_array",
    "propagate",
    "resolve_model",
    "rk4_step",
    "wrap_angle",
]


def wrap_angle(angle: ArrayLike) -> FloatArray:
    """Angle(s) wrapped to ``[-π, π)`` (rad): the short way round."""
    return np.mod(np.asarray(angle, dtype=float) + np.pi, 2.0 * np.pi) - np.pi


def pose_array(name: str, value: ArrayLike) -> FloatArray:
    """A pose ``(x, y, θ)`` or a position ``(x, y)`` (heading 0) as a float array (3,)."""
    array = finite_array(name, value)
    if array.shape == (2,):
        array = np.append(array, 0.0)
    if array.shape != (3,):
        raise InvalidInputError(
            f"{name} must be a pose (x, y, theta) in m, m, rad, got shape {array.shape}"
        )
    return np.array(array)


@dataclass(frozen=True)
class Unicycle:
    """The kinematic unicycle: pose ``(x, y, θ)``, inputs ``(v, ω)``; no wheels.

    Parameters
    ----------
    limits : MobileLimits, optional
        Default limits for plans and controllers using this model; no wheel
        speed limit (a unicycle has no wheels).
    name : str
        Label for plots and summaries.
    """

    limits: MobileLimits = field(default_factory=MobileLimits)
    name: str = "unicycle"

    def __post_init__(self) -> None:
        check_limits(self.limits)
        if self.limits.wheel_speed is not None:
            raise InvalidInputError(
                "limits has a wheel_speed limit, which needs a DiffDrive model: "
                "a unicycle has no wheels"
            )


@dataclass(frozen=True)
class DiffDrive:
    """A differential-drive (or skid-steer) base: two wheel sides driven independently.

    Parameters
    ----------
    wheel_radius : float
        Wheel radius r (m), > 0.
    track_width : float
        Distance between the left and right wheel contact lines (m), > 0.
    wheel_speed_limit : float, optional
        Largest wheel speed magnitude (rad/s); checked by every plan and enforced
        by the controllers' saturation.
    track_multiplier : float
        Skid-steer correction (>= 1): four wheels that skid turn as if the track
        were this many times wider (ROS diff_drive_controller's
        ``wheel_separation_multiplier``). 1 for a true differential drive.
    wheelbase : float
        Front-to-rear axle distance (m), for drawing and simulation (0: two wheels).
    mass : float, optional
        Total mass (kg), for simulation.
    limits : MobileLimits, optional
        Limits on v, ω and their accelerations (the wheel speed limit is added).
    name : str
        Label for plots and summaries.

    Notes
    -----
    With the effective track ``b = track_width * track_multiplier`` the wheel
    speeds are ``φ̇_L = (v - ω b / 2) / r`` and ``φ̇_R = (v + ω b / 2) / r``, and
    back ``v = r (φ̇_R + φ̇_L) / 2``, ``ω = r (φ̇_R - φ̇_L) / b``.
    """

    wheel_radius: float
    track_width: float
    # Stored once, in ``limits.wheel_speed``; read back by the property set below the class.
    wheel_speed_limit: InitVar[float | None] = None
    track_multiplier: float = 1.0
    wheelbase: float = 0.0
    mass: float | None = None
    limits: MobileLimits = field(default_factory=MobileLimits)
    name: str = "diff-drive"

    def __post_init__(self, wheel_speed_limit: float | None) -> None:
        check_limits(self.limits)
        for attribute in ("wheel_radius", "track_width"):
            object.__setattr__(
                self, attribute, positive_scalar(attribute, getattr(self, attribute), unit="m")
            )
        multiplier = positive_scalar("track_multiplier", self.track_multiplier)
        if multiplier < 1.0:
            raise InvalidInputError(
                f"track_multiplier must be >= 1 (skidding widens the effective track), "
                f"got {multiplier:g}"
            )
        object.__setattr__(self, "track_multiplier", multiplier)
        wheelbase = finite_scalar("wheelbase", self.wheelbase, unit="m")
        if wheelbase < 0.0:
            raise InvalidInputError(f"wheelbase must be >= 0 m, got {wheelbase:g} m")
        object.__setattr__(self, "wheelbase", wheelbase)
        if self.mass is not None:
            object.__setattr__(self, "mass", positive_scalar("mass", self.mass, unit="kg"))
        if wheel_speed_limit is not None:
            limit = positive_scalar("wheel_speed_limit", wheel_speed_limit, unit="rad/s")
            given = self.limits.wheel_speed
            if given is not None and (float(given.lower), float(given.upper)) != (-limit, limit):
                raise InvalidInputError(
                    f"wheel_speed_limit={limit:g} rad/s disagrees with limits.wheel_speed "
                    f"({float(given.lower):g}, {float(given.upper):g}); give the wheel limit once"
                )
            object.__setattr__(self, "limits", self.limits.replace(wheel_speed=limit))

    @property
    def effective_track(self) -> float:
        """``track_width * track_multiplier`` (m): the track the kinematics use."""
        return self.track_width * self.track_multiplier

    def wheel_speeds(self, v: ArrayLike, omega: ArrayLike) -> FloatArray:
        """Left and right wheel speeds (rad/s) for twists ``(v, ω)``: shape ``(..., 2)``."""
        v = finite_array("v", v, unit="m/s")
        omega = finite_array("omega", omega, unit="rad/s")
        try:
            np.broadcast_shapes(v.shape, omega.shape)
        except ValueError:
            raise InvalidInputError(
                f"v (shape {v.shape}) and omega (shape {omega.shape}) do not broadcast together"
            ) from None
        half = 0.5 * self.effective_track * omega
        return np.stack([(v - half) / self.wheel_radius, (v + half) / self.wheel_radius], axis=-1)

    def wheel_pair(self, v: float, omega: float) -> tuple[float, float]:
        """:meth:`wheel_speeds` of one twist as two floats, unchecked: for control loops."""
        half = 0.5 * self.effective_track * omega
        return (v - half) / self.wheel_radius, (v + half) / self.wheel_radius

    def twist(self, wheel_speeds: ArrayLike) -> FloatArray:
        """Twists ``(v, ω)`` for wheel speeds ``(..., 2)`` = (left, right) in rad/s."""
        speeds = finite_array("wheel_speeds", wheel_speeds, unit="rad/s")
        if speeds.ndim == 0 or speeds.shape[-1] != 2:
            raise InvalidInputError(
                f"wheel_speeds must have shape (..., 2) (left, right), got shape {speeds.shape}"
            )
        left, right = speeds[..., 0], speeds[..., 1]
        r = self.wheel_radius
        return np.stack([r * (right + left) / 2.0, r * (right - left) / self.effective_track], -1)


def _wheel_speed_limit(self: DiffDrive) -> float | None:
    """The largest wheel speed magnitude (rad/s), or None: ``limits.wheel_speed`` read back."""
    bounds = self.limits.wheel_speed
    return None if bounds is None else max(-float(bounds.lower), float(bounds.upper))


# A property of the same name as the constructor's argument: set after the dataclass is
# made, which has taken the argument's default of None already.
DiffDrive.wheel_speed_limit = property(_wheel_speed_limit)  # type: ignore[assignment]


Model = Unicycle | DiffDrive


def resolve_model(model: object) -> Model:
    """``model``, once known to be a Unicycle or DiffDrive; a plain Unicycle for None."""
    if model is None:
        return Unicycle()
    if not isinstance(model, Unicycle | DiffDrive):
        raise InvalidInputError(
            f"model must be a trajkit.mobile Unicycle or DiffDrive, got {type(model).__name__}"
        )
    return model


def jackal() -> DiffDrive:
    """Clearpath Jackal: a four-wheel skid-steer base, with its published figures.

    Wheel radius 0.098 m, wheel separation 0.37559 m with the skid-steer
    multiplier 1.5 of its ROS controller configuration, wheelbase 0.262 m,
    17 kg. Limits from the same configuration: 2.0 m/s and 20 m/s², 4.0 rad/s
    and 25 rad/s²; wheel speeds up to 2.0 m/s over the radius (20.4 rad/s).
    """
    return DiffDrive(
        wheel_radius=0.098,
        track_width=0.37559,
        wheel_speed_limit=2.0 / 0.098,
        track_multiplier=1.5,
        wheelbase=0.262,
        mass=17.0,
        limits=MobileLimits(
            velocity=2.0, angular_velocity=4.0, acceleration=20.0, angular_acceleration=25.0
        ),
        name="jackal",
    )


#: The wheeled robots known by name on the command line and in scenario files.
BASES = {"jackal": jackal, "unicycle": Unicycle}


def arc_pose(pose: ArrayLike, v: ArrayLike, omega: ArrayLike, duration: ArrayLike) -> FloatArray:
    """Pose(s) after driving a constant twist for ``duration`` (exact: a line or an arc).

    Parameters
    ----------
    pose : array_like, shape (..., 3)
        Start pose(s) (m, m, rad).
    v, omega, duration : array_like
        Forward speed (m/s), turn rate (rad/s) and time (s), broadcast with the poses.

    Returns
    -------
    ndarray, shape (..., 3)
        The end pose, heading not wrapped.

    Notes
    -----
    With ``Δθ = ω t`` the chord has length ``v t sinc(Δθ / 2)`` along the mean
    heading ``θ + Δθ / 2``; this is exact for any ``ω`` and has no 0/0 at ``ω = 0``.
    """
    pose = finite_array("pose", pose)
    if pose.ndim == 0 or pose.shape[-1] != 3:
        raise InvalidInputError(
            f"pose must have shape (..., 3): x, y, theta in m, m, rad; got shape {pose.shape}"
        )
    v = finite_array("v", v, unit="m/s")
    omega = finite_array("omega", omega, unit="rad/s")
    duration = finite_array("duration", duration, unit="s")
    try:
        np.broadcast_shapes(pose.shape[:-1], v.shape, omega.shape, duration.shape)
    except ValueError:
        raise InvalidInputError(
            f"pose (shape {pose.shape}), v {v.shape}, omega {omega.shape} and duration "
            f"{duration.shape} do not broadcast together"
        ) from None
    shape = np.broadcast_shapes(pose.shape[:-1], v.shape, omega.shape, duration.shape)
    v, omega, duration = (np.broadcast_to(x, shape) for x in (v, omega, duration))
    return constant_twist_pose(np.broadcast_to(pose, (*shape, 3)), v, omega, duration)


def constant_twist_pose(
    pose: FloatArray, v: ArrayLike, omega: ArrayLike, duration: ArrayLike
) -> FloatArray:
    """:func:`arc_pose` without its checks, for callers whose inputs are already valid.

    The inputs must broadcast to the poses' leading shape.
    """
    turn = omega * duration
    chord = v * duration * np.sinc(turn / (2.0 * np.pi))  # np.sinc(x) = sin(πx)/(πx)
    middle = pose[..., 2] + turn / 2.0
    return np.stack(
        [
            pose[..., 0] + chord * np.cos(middle),
            pose[..., 1] + chord * np.sin(middle),
            pose[..., 2] + turn,
        ],
        axis=-1,
    )


def chain_arcs(start: FloatArray, distances: FloatArray, turns: FloatArray) -> FloatArray:
    """Poses along a chain of arcs: dead reckoning from odometry or held commands.

    Arc ``k`` covers ``distances[k]`` (m) along the path while turning by
    ``turns[k]`` (rad); the chord formula of :func:`arc_pose` makes every arc
    exact, and the whole chain is one vectorized pass.

    Returns
    -------
    ndarray, shape (n + 1, 3)
        The start pose and the pose after every arc (heading not wrapped).
    """
    theta = start[2] + np.concatenate([[0.0], np.cumsum(turns)])
    chord = distances * np.sinc(turns / (2.0 * np.pi))
    middle = theta[:-1] + turns / 2.0
    x = start[0] + np.concatenate([[0.0], np.cumsum(chord * np.cos(middle))])
    y = start[1] + np.concatenate([[0.0], np.cumsum(chord * np.sin(middle))])
    return np.stack([x, y, theta], axis=1)


StageRate = Callable[[int, FloatArray], FloatArray]


def rk4_step(rate: StageRate, state: FloatArray, h: float) -> FloatArray:
    """One classic Runge–Kutta step of length ``h`` (s).

    ``rate(stage, state)`` gives the state's time derivative at the step's start
    (stage 0), middle (1) or end (2), so callers can look up inputs they computed
    for those three instants beforehand.
    """
    k1 = rate(0, state)
    k2 = rate(1, state + h / 2 * k1)
    k3 = rate(1, state + h / 2 * k2)
    k4 = rate(2, state + h * k3)
    return state + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)


def propagate(
    start: ArrayLike, twist: Callable[[FloatArray], FloatArray], times: ArrayLike
) -> FloatArray:
    """Poses driven by a time-varying twist, by one RK4 step between consecutive ``times``.

    Parameters
    ----------
    start : array_like
        Pose ``(x, y, θ)`` at ``times[0]``.
    twist : callable
        ``twist(t) -> (n, 2)`` array of ``(v, ω)`` for an array of times ``t`` (n,).
    times : array_like, shape (n,)
        Increasing times (s).

    Returns
    -------
    ndarray, shape (n, 3)
        The pose at every time (heading not wrapped). For a constant twist use
        :func:`arc_pose`, which is exact.
    """
    t = finite_array("times", times, unit="s")
    if t.ndim != 1 or t.size < 1 or np.any(np.diff(t) <= 0.0):
        raise InvalidInputError("times must be a strictly increasing 1-D array")
    pose = pose_array("start", start)
    # Every twist the steps need, in one vectorized call: starts, middles and ends.
    inputs = np.asarray(twist(np.concatenate([t, (t[:-1] + t[1:]) / 2.0])), dtype=float)
    ends, middles = inputs[: t.size], inputs[t.size :]
    out = np.empty((t.size, 3))
    out[0] = pose
    for i in range(t.size - 1):  # sequential by nature: each step starts where the last ended
        stage_twist = (ends[i], middles[i], ends[i + 1])

        def rate(stage: int, state: FloatArray, inputs: tuple = stage_twist) -> FloatArray:
            v, w = inputs[stage]
            return np.array([v * np.cos(state[2]), v * np.sin(state[2]), w])

        pose = rk4_step(rate, pose, float(t[i + 1] - t[i]))
        out[i + 1] = pose
    return out
