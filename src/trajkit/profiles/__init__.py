"""Time laws: polynomial moves, via-point interpolation (and, later, limit-driven profiles)."""

from trajkit.profiles.polynomial import cubic, polynomial, quintic, septic
from trajkit.profiles.via import cubic_spline, cubic_via, quintic_via

__all__ = ["cubic", "cubic_spline", "cubic_via", "polynomial", "quintic", "quintic_via", "septic"]
