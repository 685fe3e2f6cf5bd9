"""Time laws: polynomial moves, via-point interpolation, limit-driven profiles."""

from trajkit.profiles.blend import blended
from trajkit.profiles.polynomial import cubic, polynomial, quintic, septic
from trajkit.profiles.scurve import scurve
from trajkit.profiles.trapezoidal import trapezoidal
from trajkit.profiles.velocity import velocity_change
from trajkit.profiles.via import cubic_spline, cubic_via, quintic_via

__all__ = [
    "blended",
    "cubic",
    "cubic_spline",
    "cubic_via",
    "polynomial",
    "quintic",
    "quintic_via",
    "scurve",
    "septic",
    "trapezoidal",
    "velocity_change",
]
