"""Limits of a wheeled base: speed, turn rate, their accelerations, wheel speeds."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from trajkit.errors import InvalidInputError
from trajkit.limits import Bounds, LimitSpec, parse_bounds

__all__ = ["KEYWORDS", "QUANTITIES", "UNITS", "MobileLimits", "check_limits"]

# Attribute, the name used in messages and reports, and the unit.
QUANTITIES = (
    ("velocity", "velocity", "m/s"),
    ("angular_velocity", "angular velocity", "rad/s"),
    ("acceleration", "acceleration", "m/s^2"),
    ("angular_acceleration", "angular acceleration", "rad/s^2"),
    ("wheel_speed", "wheel speed", "rad/s"),
)
UNITS = {attribute: unit for attribute, _, unit in QUANTITIES}
#: Each twist limit's keyword, as planners, scenario files, sweeps and the command line
#: name it, and the attribute of :class:`MobileLimits` that holds it.
KEYWORDS = {"vmax": "velocity", "wmax": "angular_velocity", "amax": "acceleration",
            "alpha_max": "angular_acceleration"}  # fmt: skip


@dataclass(frozen=True, init=False)
class MobileLimits:
    """Limits on a base's twist, its rate of change, and its wheels (SI units, rad).

    Parameters
    ----------
    velocity : float or tuple (lower, upper), optional
        Forward speed v (m/s): a number ``V`` means ``-V <= v <= V``; a tuple gives
        asymmetric bounds (e.g. slower in reverse), with ``lower <= 0 <= upper``.
    angular_velocity : float or tuple, optional
        Turn rate ω (rad/s).
    acceleration : float or tuple, optional
        Rate of change of v (m/s²).
    angular_acceleration : float or tuple, optional
        Rate of change of ω (rad/s²).
    wheel_speed : float or tuple, optional
        Every wheel's speed (rad/s); only a differential drive has wheels.
    """

    velocity: Bounds | None
    angular_velocity: Bounds | None
    acceleration: Bounds | None
    angular_acceleration: Bounds | None
    wheel_speed: Bounds | None

    def __init__(
        self,
        velocity: LimitSpec = None,
        angular_velocity: LimitSpec = None,
        acceleration: LimitSpec = None,
        angular_acceleration: LimitSpec = None,
        wheel_speed: LimitSpec = None,
    ) -> None:
        given = (velocity, angular_velocity, acceleration, angular_acceleration, wheel_speed)
        for (attribute, name, _), spec in zip(QUANTITIES, given, strict=True):
            # Messages name the argument (angular_velocity), not the quantity.
            bounds = (
                spec if isinstance(spec, Bounds) else parse_bounds(attribute, spec, quantity=name)
            )
            if bounds is not None and (bounds.lower.ndim or bounds.upper.ndim):
                raise InvalidInputError(
                    f"{attribute} limit must be one number or a (lower, upper) pair"
                )
            object.__setattr__(self, attribute, bounds)

    def replace(self, **changes: LimitSpec) -> MobileLimits:
        """A copy with some limits replaced (``None`` removes one)."""
        current = {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}
        return MobileLimits(**(current | changes))

    def magnitude(self, attribute: str) -> float | None:
        """The tighter side of a limit as a magnitude (``min(-lower, upper)``), or None."""
        bounds: Bounds | None = getattr(self, attribute)
        if bounds is None:
            return None
        return float(min(-bounds.lower, bounds.upper))

    def __repr__(self) -> str:
        parts = []
        for attribute, _, _ in QUANTITIES:
            bounds = getattr(self, attribute)
            if bounds is not None:
                parts.append(f"{attribute}=({float(bounds.lower):g}, {float(bounds.upper):g})")
        return f"MobileLimits({', '.join(parts)})"


def check_limits(limits: object) -> MobileLimits:
    """``limits`` itself, once it is known to be a :class:`MobileLimits`."""
    if not isinstance(limits, MobileLimits):
        raise InvalidInputError(
            f"limits must be a trajkit.mobile.MobileLimits, got {type(limits).__name__}"
        )
    return limits
