"""Robot arms: serial chains (DH tables, URDF), kinematics, Jacobians, IK and dynamics.

Examples
--------
>>> from trajkit.kinematics import Planar2R
>>> arm = Planar2R(1.0, 1.0)
>>> arm.fk([0.0, 0.0])[:3, 3].round(12).tolist()
[2.0, 0.0, 0.0]
"""

from trajkit.kinematics.chain import DHRow, Joint, SerialChain
from trajkit.kinematics.drawing import link_positions
from trajkit.kinematics.dynamics import (
    STANDARD_GRAVITY,
    inertials_from_dh,
    inverse_dynamics,
    path_dynamics,
)
from trajkit.kinematics.ik import IKSolution
from trajkit.kinematics.inertials import Inertials
from trajkit.kinematics.mjcf import from_mjcf
from trajkit.kinematics.physical import Physical
from trajkit.kinematics.robots import BUILTIN, UR5, AnalyticChain, Planar2R, RRBot, Spatial3R
from trajkit.kinematics.urdf import from_urdf

__all__ = [
    "BUILTIN",
    "STANDARD_GRAVITY",
    "UR5",
    "AnalyticChain",
    "DHRow",
    "IKSolution",
    "Inertials",
    "Joint",
    "Physical",
    "Planar2R",
    "RRBot",
    "SerialChain",
    "Spatial3R",
    "from_mjcf",
    "from_urdf",
    "inertials_from_dh",
    "inverse_dynamics",
    "link_positions",
    "path_dynamics",
]
