"""Motion plans for a wheeled base: constant twist, and rotate–translate–rotate."""

from __future__ import annotations

import math
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from trajkit._validation import finite_array, finite_scalar, positive_scalar
from trajkit.errors import InfeasibleError, InvalidInputError
from trajkit.mobile.limits import KEYWORDS, UNITS, MobileLimits, check_limits
from trajkit.mobile.models import (
    DiffDrive,
    Model,
    pose_array,
    resolve_model,
    wrap_angle,
)
from trajkit.mobile.trajectory import (
    Arc,
    MobileTrajectory,
    Segment,
    Straight,
    Turn,
    command_count,
)
from trajkit.profiles import scurve, trapezoidal
from trajkit.renamed import renamed_keywords
from trajkit.trajectory import Trajectory

__all__ = [
    "MAX_TRAVEL",
    "constant_twist",
    "phase_law",
    "phase_limits",
    "plan_phase",
    "rotate_translate_rotate",
]

#: The longest distance (m) or turn (rad) one plan covers, some 2.6 times the distance to
#: the Moon: beyond it a plan's times (distance / speed) grow so large that float64 loses
#: the motion within them, and past float range its poses would be inf.
MAX_TRAVEL = 1e9

Profile = Literal["trapezoid", "scurve"]


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
    origin = pose_array("start", start)
    # Past float range the arc's end pose is inf or NaN: refused, never returned.
    with np.errstate(over="ignore", invalid="ignore"):
        distance, turned = abs(speed) * seconds, turn_rate * seconds
    for what, amount, unit in (("distance v * duration", distance, "m"),
                               ("turn omega * duration", turned, "rad")):  # fmt: skip
        if not abs(amount) <= MAX_TRAVEL:
            raise InvalidInputError(
                f"the {what} is {amount:.3g} {unit} (v={speed:g} m/s, omega={turn_rate:g} rad/s, "
                f"duration={seconds:g} s); at most {MAX_TRAVEL:g} {unit} are planned"
            )
    arc = Arc(origin, speed, turn_rate, seconds)
    radius = np.inf if turn_rate == 0.0 else abs(speed / turn_rate)
    info = {
        "plan": "constant_twist",
        "radius": radius,
        "turned": turn_rate * seconds,
        "distance": abs(speed) * seconds,
        "rate_hz": rate,
        "command_count": None if rate is None else command_count(seconds, rate),
        "continuity": math.inf,  # one constant twist
    }
    return MobileTrajectory([arc], resolve_model(model), info=info)


def phase_law(
    name: str,
    distance: float,
    speed: float | None,
    acceleration: float | tuple[float, float] | None,
    jerk: float | None,
    profile: Profile,
    blend_ratio: float | None,
    period: float | None,
    units: tuple[str, str, str],
    names: tuple[str, str, str] = ("a speed limit", "an acceleration limit", "a jerk limit"),
) -> Trajectory:
    """The 1-D time law of one phase (a turn or a drive) from 0 to ``distance``.

    ``blend_ratio`` selects the coursework's LSPB rule ``t_b = ratio * t_f``
    (shortest duration under ``speed`` and, if given, ``acceleration``);
    otherwise ``profile`` gives the time-optimal trapezoid or S-curve.
    ``speed`` is the bound in the direction of motion; ``acceleration`` a
    magnitude or a ``(lower, upper)`` pair (an S-curve takes the smaller side).
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
        return trapezoidal(
            0.0, distance, speed, acceleration, blend_ratio=blend_ratio, period=period
        )
    if acceleration is None:
        raise InvalidInputError(
            f"the {name} needs {acceleration_name} ({acceleration_unit}) for a time-optimal "
            f"{profile}, or a blend_ratio"
        )
    if profile == "trapezoid":
        return trapezoidal(0.0, distance, speed, acceleration, period=period)
    if profile == "scurve":
        if jerk is None:
            raise InvalidInputError(f"the {name} needs {jerk_name} for an S-curve")
        if isinstance(acceleration, tuple):
            acceleration = min(-acceleration[0], acceleration[1])
        return scurve(0.0, distance, speed, acceleration, jerk, period=period)
    raise InvalidInputError(f"profile must be 'trapezoid' or 'scurve', got {profile!r}")


def phase_limits(
    name: str, kind: str, amount: float, limits: MobileLimits, model: Model
) -> tuple[float | None, float | tuple[float, float] | None]:
    """The speed bound in the direction of a turn or a drive, and its acceleration bounds.

    Asymmetric limits count on the side the phase moves to; a differential
    drive's wheel limit caps the speed too (a drive turns both wheels forward or
    back, a turn in place one each way).

    Raises
    ------
    InfeasibleError
        The side the phase needs is bounded at 0 (e.g. a reverse drive under
        ``velocity=(0, 0.5)``), or a wheel limit forbids it.
    """
    rate = "velocity" if kind == "drive" else "angular_velocity"
    change = "acceleration" if kind == "drive" else "angular_acceleration"
    unit = "m/s" if kind == "drive" else "rad/s"
    bounds = getattr(limits, rate)
    speed = None
    if bounds is not None:
        speed = float(bounds.upper) if amount > 0 else -float(bounds.lower)
    if isinstance(model, DiffDrive) and limits.wheel_speed is not None:
        wheel_up, wheel_down = float(limits.wheel_speed.upper), -float(limits.wheel_speed.lower)
        if kind == "drive":
            cap = model.wheel_radius * (wheel_up if amount > 0 else wheel_down)
        else:
            cap = model.wheel_radius * min(wheel_up, wheel_down) / (model.effective_track / 2)
        speed = cap if speed is None else min(speed, cap)
    if speed is not None and speed <= 0.0:
        raise InfeasibleError(
            f"the {name} moves {'forwards' if amount > 0 else 'backwards'} "
            f"({amount:.6g} {unit[:-2]}) but the {rate.replace('_', ' ')} and wheel limits "
            f"allow no speed that way"
        )
    bounds = getattr(limits, change)
    if bounds is None:
        return speed, None
    lower, upper = float(bounds.lower), float(bounds.upper)
    if lower == 0.0 or upper == 0.0:
        raise InfeasibleError(
            f"the {name} must speed up and slow down, but the {change.replace('_', ' ')} "
            f"limit is ({lower:g}, {upper:g}): one side is 0"
        )
    return speed, (upper if -lower == upper else (lower, upper))


# Per kind of phase: the limits' argument names and the units of position, speed,
# acceleration and jerk, for messages.
_PHASE_TERMS = {
    "drive": (("vmax", "amax", "jmax"), ("m", "m/s", "m/s^2")),
    "turn": (("wmax", "alpha_max", "angular_jmax"), ("rad", "rad/s", "rad/s^2")),
}


@renamed_keywords(dt="period")
def plan_phase(
    label: str,
    kind: str,
    amount: float,
    limits: MobileLimits,
    model: Model,
    *,
    jerk: float | None = None,
    profile: Profile = "trapezoid",
    blend_ratio: float | None = None,
    period: float | None = None,
) -> Trajectory:
    """The time law of a turn in place or a straight drive by ``amount`` (rad or m).

    ``kind`` is "turn" or "drive"; the limits on the way it moves come from
    :func:`phase_limits`, the law from :func:`phase_law`.
    """
    speed, change = phase_limits(label, kind, amount, limits, model)
    names, units = _PHASE_TERMS[kind]
    return phase_law(label, amount, speed, change, jerk, profile, blend_ratio, period, units, names)


# Below this a move has no length: the robot only turns (m), or does not turn (rad).
_NO_MOTION = 1e-12


@renamed_keywords(dt="period")
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
    period: float | None = None,
    model: Model | None = None,
    limits: MobileLimits | None = None,
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
        Speed (m/s) and turn-rate (rad/s) limits; they replace those of ``limits``.
    amax, alpha_max : float, optional
        Linear (m/s²) and angular (rad/s²) acceleration limits, likewise. Needed
        for time-optimal profiles; with a ``blend_ratio`` they are only respected.
    jmax, angular_jmax : float, optional
        Jerk limits (m/s³, rad/s³) for ``profile="scurve"``.
    profile : {"trapezoid", "scurve"}
        Time-optimal trapezoid (LSPB) or jerk-limited S-curve phases.
    blend_ratio : float, optional
        The coursework rule: each phase blends for ``ratio * t_f`` (0 < ratio <= 0.5).
    reverse : bool
        Drive backwards when the goal lies behind (turns less than 90° first).
    period : float, optional
        Controller period (s): phase switching times become whole multiples of it.
    model : Unicycle or DiffDrive, optional
        Default: a plain unicycle.
    limits : MobileLimits, optional
        Default: the model's. Asymmetric limits count on the side each phase moves
        to; a DiffDrive's wheel limit caps the speeds too.

    Returns
    -------
    MobileTrajectory
        Up to three segments (phases of zero length are left out), carrying the
        limits it was planned for; ``info`` holds ``phases`` (names),
        ``phase_durations`` (s), ``turns`` (rad), ``distance`` (m, signed) and
        ``profile``.

    Raises
    ------
    InvalidInputError
        Malformed poses or limits, or a limit the profile needs is missing.
    InfeasibleError
        A limit allows no motion the way a phase must go.
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
    limits = check_limits(base.limits if limits is None else limits)
    given = {}
    for name, value in (("vmax", vmax), ("wmax", wmax), ("amax", amax), ("alpha_max", alpha_max)):
        if value is not None:
            attribute = KEYWORDS[name]
            given[attribute] = positive_scalar(name, value, unit=UNITS[attribute])
    limits = limits.replace(**given)
    if not isinstance(reverse, bool):
        raise InvalidInputError(f"reverse must be True or False, got {reverse!r}")
    j = None if jmax is None else positive_scalar("jmax", jmax, unit="m/s^3")
    wj = None
    if angular_jmax is not None:
        wj = positive_scalar("angular_jmax", angular_jmax, unit="rad/s^3")
    step = None if period is None else positive_scalar("period", period, unit="s")
    with np.errstate(over="ignore", invalid="ignore"):
        dx, dy = target[0] - origin[0], target[1] - origin[1]
        distance = float(np.hypot(dx, dy))
    if not distance <= MAX_TRAVEL:
        raise InvalidInputError(
            f"goal {tuple(float(g) for g in target[:2])} is {distance:.3g} m from start "
            f"{tuple(float(g) for g in origin[:2])}; at most {MAX_TRAVEL:g} m are planned "
            "(farther, a phase lasts so long that float64 times lose its motion)"
        )
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
    segments: list[Segment] = []
    phase_names, durations = [], []
    pose = origin.copy()
    for kind, label, amount in plan:
        if abs(amount) <= _NO_MOTION:
            continue
        law = plan_phase(label, kind, amount, limits, base, jerk=wj if kind == "turn" else j,
                         profile=profile, blend_ratio=blend_ratio, period=step)  # fmt: skip
        segment: Segment = Turn(pose, law) if kind == "turn" else Straight(pose, law)
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
        # Phases meet at rest: the twist is continuous; its rates as far as every
        # phase law keeps its acceleration continuous (2 at most: see continuity).
        "continuity": min(2.0, *(float(s.law.info["continuity"]) for s in segments)),
    }
    return MobileTrajectory(segments, base, limits=limits, info=info)
