"""trajkit: robot trajectories that are exact, checked and easy to export.

Every planner returns a :class:`Trajectory`, an N-DoF piecewise polynomial in
time. SI units and radians throughout.
"""

from __future__ import annotations

import importlib
from typing import Any

from trajkit import batch, online
from trajkit.curve import Curve
from trajkit.errors import (
    ContinuityWarning,
    InfeasibleError,
    InvalidInputError,
    MissingDependencyError,
    TrajkitError,
    UnreachableError,
)
from trajkit.limits import Limits, Report, Violation, check
from trajkit.profiles import (
    blended,
    cubic,
    cubic_spline,
    cubic_via,
    polynomial,
    quintic,
    quintic_via,
    scurve,
    septic,
    trapezoidal,
    velocity_change,
)
from trajkit.samples import Samples
from trajkit.time_optimal import ToolLimit, TorqueLimit, retime, topp
from trajkit.trajectory import Extrema, State, Trajectory

__version__ = "0.1.0"

__all__ = [
    "ContinuityWarning",
    "Curve",
    "Extrema",
    "InfeasibleError",
    "InvalidInputError",
    "Limits",
    "MissingDependencyError",
    "Report",
    "Samples",
    "State",
    "ToolLimit",
    "TorqueLimit",
    "Trajectory",
    "TrajkitError",
    "UnreachableError",
    "Violation",
    "__version__",
    "animate",
    "batch",
    "blended",
    "check",
    "cubic",
    "cubic_spline",
    "cubic_via",
    "online",
    "plot",
    "polynomial",
    "quintic",
    "quintic_via",
    "report",
    "retime",
    "scurve",
    "septic",
    "topp",
    "trapezoidal",
    "velocity_change",
]

# Submodules that pull in heavy libraries (matplotlib) load on first use only.
_LAZY = {name: f"trajkit.viz.{name}" for name in ("animate", "plot", "report")}


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        module = importlib.import_module(_LAZY[name])
        globals()[name] = module
        return module
    raise AttributeError(f"module 'trajkit' has no attribute {name!r}")
