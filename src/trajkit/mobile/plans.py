"""Motion plans for a wheeled base: constant twist, and rotate–translate–rotate."""

from __future__ import annotations

from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from trajkit._validation import finite_array, finite_scalar, positive_scalar
from trajkit.errors import InvalidInputError
from trajkit.mobile.limits import MobileLimits
from trajkit.mobile.models import DiffDrive, Model, Unicycle, pose_array, wrap_angle
from trajkit.mobile.trajectory import (
    Arc,
    MobileTrajectory,
    Segment,
    Straight,
    Turn,
    command_times,
)
from trajkit.profiles import scurve, trapezoidal
from trajkit.trajectory import Trajectory

__all__ = ["constant_twist", "phase_law", "resolve_model", "rotate_translate_rotate"]

Profile = Literal["trapezoid", "scurve"]


def resolve_model(model: Model | None) -> Model:
    """``model``, checked, or a plain :class:`Unicycle` when it is None."""
    if model is None:
        return Unicycle()
    if not isinstance(model, Unicycle | DiffDrive):
        raise InvalidInputError(
            f"model must be a trajkit.mobile Unicycle or DiffDrive, got {type(model).__name__}"
        )
    return model


def constant_twist(
    v: float,
    omega: float,
    duration: float,
    *,
    rate_hz: float | None = None,
    start: ArrayLike = (0.0, 0.0, 0.0),
    model: Model | None = None,
) -> MobileTrajectory:
    """Drive one twist ``(v, ω)`` for ``duration``: the arc it traces, exactly.

    Parameters
    ----------
    v : float
        Forward speed (m/s); negative drives backwards.
    omega : float
        Turn rate (rad/s), counter-clockwise positive.
    duration : float
        Time (s), > 0.
    rate_hz : float, optional
        Rate at which the command is sent (Hz), as a base controller receives it;
        :meth:`MobileTrajectory.commands` gives that stream. It does not change the
        motion: every command is the same twist.
    start : array_like
        Start pose ``(x, y, θ)`` (m, m, rad).
    model : Unicycle or DiffDrive, optional
        Default: a plain unicycle.

    Returns
    -------
    MobileTrajectory
        One arc; ``info`` holds ``radius`` (m, ``inf`` for a line, 0 for a spin),
        ``turned`` (rad), ``distance`` (m, along the path), ``rate_hz`` and
        ``command_count``.

    Notes
    -----
    The twist applies from ``t = 0``: the step from rest is not part of the plan,
    so it has no acceleration to check.
    """
    speed = finite_scalar("v", v, unit="m/s")
    turn_rate = finite_scalar("omega", omega, unit="rad/s")
    seconds = positive_scalar("duration", duration, unit="s")
    rate = None if rate_hz is None else positive_scalar("rate_hz", rate_hz, unit="Hz")
    arc = Arc(pose_array("start", start), speed, turn_rate, seconds)
    radius = np.inf if turn_rate == 0.0 else abs(speed / turn_rate)
    info = {
        "plan": "constant_twist",
        "radius": radius,
        "turned": turn_rate * seconds,
        "distance": abs(speed) * seconds,
        "rate_hz": rate,
        "command_count": None if rate is None else command_times(seconds, rate).size,
    }
    return MobileTrajectory([arc], resolve_model(model), info=info)


def phase_law(
    name: str,
    distance: float,
    speed: float | None,
    acceleration: float | None,
    jerk: float | None,
    profile: Profile,
    blend_ratio: float | None,
    dt: float | None,
    units: tuple[str, str, str],
    names: tuple[str, str, str] = ("a speed limit", "an acceleration limit", "a jerk limit"),
) -> Trajectory:
    """The 1-D time law of one phase (a turn or a drive) from 0 to ``distance``.

    ``blend_ratio`` selects the coursework's LSPB rule ``t_b = ratio * t_f``
    (shortest duration under ``speed`` and, if given, ``acceleration``);
    otherwise ``profile`` gives the time-optimal trapezoid or S-curve.
    ``units`` names the position, speed and acceleration units for messages,
    ``names`` the arguments that give the speed, acceleration and jerk limits.
    """
    _, speed_unit, acceleration_unit = units
    speed_name, acceleration_name, jerk_name = names
    if speed is None:
        raise InvalidInputError(f"the {name} needs {speed_name} ({speed_unit})")
    if blend_ratio is not None:
        if profile != "trapezoid":
            raise InvalidInputError("blend_ratio describes the LSPB (trapezoid) rule only")
        return trapezoidal(0.0, distance, speed, acceleration, blend_ratio=blend_ratio, dt=dt)
    if acceleration is None:
        raise InvalidInputError(
            f"the {name} needs {acceleration_name} ({acceleration_unit}) for a time-optimal "
            f"{profile}, or a blend_ratio"
        )
    if profile == "trapezoid":
        return trapezoidal(0.0, distance, speed, acceleration, dt=dt)
    if profile == "scurve":
        if jerk is None:
            raise InvalidInputError(f"the {name} needs {jerk_name} for an S-curve")
        return scurve(0.0, distance, speed, acceleration, jerk, dt=dt)
    raise InvalidInputError(f"profile must be 'trapezoid' or 'scurve', got {profile!r}")


def _limit(
    given: float | None, limits: MobileLimits, attribute: str, name: str, unit: str
) -> float | None:
    if given is not None:
        return positive_scalar(name, given, unit=unit)
    return limits.magnitude(attribute)


# Below this a move has no length: the robot only turns (m), or does not turn (rad).
_NO_MOTION = 1e-12


def rotate_translate_rotate(
    goal: ArrayLike,
    start: ArrayLike = (0.0, 0.0, 0.0),
    *,
    vmax: float | None = None,
    wmax: float | None = None,
    amax: float | None = None,
    alpha_max: float | None = None,
    jmax: float | None = None,
    angular_jmax: float | None = None,
    profile: Profile = "trapezoid",
    blend_ratio: float | None = None,
    reverse: bool = False,
    dt: float | None = None,
    model: Model | None = None,
) -> MobileTrajectory:
    """Turn to face the goal, drive straight to it, turn to the final heading.

    Each phase is a 1-D profile from :mod:`trajkit.profiles`, at rest at both
    ends, as fast as its limits allow; turns go the short way round.

    Parameters
    ----------
    goal : array_like
        ``(x, y)`` or ``(x, y, θ)`` (m, m, rad). Without ``θ`` there is no final turn.
    start : array_like
        Start pose ``(x, y, θ)``.
    vmax, wmax : float, optional
        Speed (m/s) and turn-rate (rad/s) limits; default the model's.
    amax, alpha_max : float, optional
        Linear (m/s²) and angular (rad/s²) acceleration limits; default the
        model's. Needed for time-optimal profiles; with a ``blend_ratio`` they
        are only respected.
    jmax, angular_jmax : float, optional
        Jerk limits (m/s³, rad/s³) for ``profile="scurve"``.
    profile : {"trapezoid", "scurve"}
        Time-optimal trapezoid (LSPB) or jerk-limited S-curve phases.
    blend_ratio : float, optional
        The coursework rule: each phase blends for ``ratio * t_f`` (0 < ratio <= 0.5).
    reverse : bool
        Drive backwards when the goal lies behind (turns less than 90° first).
    dt : float, optional
        Controller period (s): phase switching times become whole multiples of it.
    model : Unicycle or DiffDrive, optional
        Default: a plain unicycle. Its limits fill any limit not given.

    Returns
    -------
    MobileTrajectory
        Up to three segments (phases of zero length are left out); ``info`` holds
        ``phases`` (names), ``phase_durations`` (s), ``turns`` (rad),
        ``distance`` (m, signed) and ``profile``.

    Raises
    ------
    InvalidInputError
        Malformed poses or limits, or a limit the profile needs is missing.
    """
    if profile not in ("trapezoid", "scurve"):
        raise InvalidInputError(f"profile must be 'trapezoid' or 'scurve', got {profile!r}")
    base = resolve_model(model)
    origin = pose_array("start", start)
    target = finite_array("goal", goal)
    if target.shape not in ((2,), (3,)):
        raise InvalidInputError(
            f"goal must be (x, y) or (x, y, theta) in m, m, rad, got shape {target.shape}"
        )
    limits = base.limits
    v = _limit(vmax, limits, "velocity", "vmax", "m/s")
    w = _limit(wmax, limits, "angular_velocity", "wmax", "rad/s")
    a = _limit(amax, limits, "acceleration", "amax", "m/s^2")
    alpha = _limit(alpha_max, limits, "angular_acceleration", "alpha_max", "rad/s^2")
    j = None if jmax is None else positive_scalar("jmax", jmax, unit="m/s^3")
    wj = None
    if angular_jmax is not None:
        wj = positive_scalar("angular_jmax", angular_jmax, unit="rad/s^3")
    step = None if dt is None else positive_scalar("dt", dt, unit="s")
    dx, dy = target[0] - origin[0], target[1] - origin[1]
    distance = float(np.hypot(dx, dy))
    plan: list[tuple[str, str, float]] = []  # (kind, label, signed amount)
    facing = float(origin[2])
    scale = max(1.0, float(np.abs(target[:2]).max()), float(np.abs(origin[:2]).max()))
    if distance > _NO_MOTION * scale:
        heading = float(np.arctan2(dy, dx))
        first = float(wrap_angle(heading - facing))
        if reverse and abs(first) > np.pi / 2:
            first, distance = float(wrap_angle(heading + np.pi - facing)), -distance
        # A goal ahead up to rounding (a short move's direction is ~eps / distance off)
        # takes no turn: skipping it misses the goal by less than the rounding itself.
        if abs(np.sin(first)) * abs(distance) <= _NO_MOTION * scale and abs(first) < np.pi / 2:
            first = 0.0
        plan += [("turn", "turn to face the goal", first), ("drive", "drive to the goal", distance)]
        facing += first
    else:
        distance = 0.0
    if target.size == 3:
        plan.append(("turn", "turn to the final heading", float(wrap_angle(target[2] - facing))))
    angular = ("rad", "rad/s", "rad/s^2")
    linear = ("m", "m/s", "m/s^2")
    segments: list[Segment] = []
    phase_names, durations = [], []
    pose = origin.copy()
    for kind, label, amount in plan:
        if abs(amount) <= _NO_MOTION:
            continue
        if kind == "turn":
            law = phase_law(label, amount, w, alpha, wj, profile, blend_ratio, step, angular,
                            ("wmax", "alpha_max", "angular_jmax"))  # fmt: skip
            segment: Segment = Turn(pose, law)
        else:
            law = phase_law(label, amount, v, a, j, profile, blend_ratio, step, linear,
                            ("vmax", "amax", "jmax"))  # fmt: skip
            segment = Straight(pose, law)
        segments.append(segment)
        phase_names.append(label)
        durations.append(segment.duration)
        pose = segment.end_pose
    if not segments:  # already there: a standstill of zero length
        segments.append(Straight(origin, trapezoidal(0.0, 0.0, 1.0, 1.0)))
    info = {
        "plan": "rotate_translate_rotate",
        "profile": "lspb blend_ratio" if blend_ratio is not None else profile,
        "phases": tuple(phase_names),
        "phase_durations": tuple(durations),
        "turns": tuple(amount for kind, _, amount in plan if kind == "turn"),
        "distance": distance,
    }
    return MobileTrajectory(segments, base, info=info)
