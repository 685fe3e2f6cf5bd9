"""Task space: tool paths, their timing, and their mapping to joint space.

Examples
--------
The course's 3-DOF arm draws a straight line in 10 s with a cubic time law:

>>> from trajkit.kinematics import Spatial3R
>>> from trajkit.taskspace import Line, timed, to_joint_space
>>> motion = timed(Line([0, -12, 20], [10, 12, 20]), "cubic", duration=10.0)
>>> plan = to_joint_space(Spatial3R(), motion, ik_step=0.01)
>>> bool(plan.path_error < 1e-9)
True
"""

from trajkit.taskspace.fastest import TimeOptimalMove, time_optimal
from trajkit.taskspace.joint_space import JointSpacePlan, to_joint_space
from trajkit.taskspace.motion import (
    TaskSegment,
    TaskState,
    TaskTrajectory,
    path_law,
    through_poses,
    timed,
)
from trajkit.taskspace.paths import Arc, Ellipse, FigureEight, Line, Path, Polyline

__all__ = [
    "Arc",
    "Ellipse",
    "FigureEight",
    "JointSpacePlan",
    "Line",
    "Path",
    "Polyline",
    "TaskSegment",
    "TaskState",
    "TaskTrajectory",
    "TimeOptimalMove",
    "path_law",
    "through_poses",
    "time_optimal",
    "timed",
    "to_joint_space",
]
