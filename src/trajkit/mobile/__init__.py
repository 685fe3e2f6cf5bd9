"""Wheeled mobile robots: models, motion plans, tracking control and simulation.

SI units and radians: poses ``(x, y, θ)`` in m, m, rad; twists ``(v, ω)`` in m/s
and rad/s; wheel speeds in rad/s.
"""

from trajkit.mobile.control import (
    ControlLaw,
    Controller,
    FeedbackLinearization,
    Feedforward,
    Kanayama,
    PurePursuit,
    saturate,
)
from trajkit.mobile.fastest import time_optimal
from trajkit.mobile.flatness import (
    FigureEight,
    FlatOutput,
    TrajectoryOutput,
    flat_trajectory,
    spline_output,
)
from trajkit.mobile.limits import MobileLimits
from trajkit.mobile.models import (
    DiffDrive,
    Unicycle,
    arc_pose,
    jackal,
    propagate,
    rk4_step,
    wrap_angle,
)
from trajkit.mobile.plans import constant_twist, rotate_translate_rotate
from trajkit.mobile.simulate import SimulationLog, simulate
from trajkit.mobile.trajectory import Arc, MobileState, MobileTrajectory, Segment, Straight, Turn

__all__ = [
    "Arc",
    "ControlLaw",
    "Controller",
    "DiffDrive",
    "FeedbackLinearization",
    "Feedforward",
    "FigureEight",
    "FlatOutput",
    "Kanayama",
    "MobileLimits",
    "MobileState",
    "MobileTrajectory",
    "PurePursuit",
    "Segment",
    "SimulationLog",
    "Straight",
    "TrajectoryOutput",
    "Turn",
    "Unicycle",
    "arc_pose",
    "constant_twist",
    "flat_trajectory",
    "jackal",
    "propagate",
    "rk4_step",
    "rotate_translate_rotate",
    "saturate",
    "simulate",
    "spline_output",
    "time_optimal",
    "wrap_angle",
]
