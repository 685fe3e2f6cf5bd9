"""Arm geometry over time, for drawing and animation: where every joint is at every instant."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from trajkit._validation import finite_array
from trajkit.errors import InvalidInputError
from trajkit.kinematics.chain import SerialChain
from trajkit.trajectory import Trajectory

FloatArray = NDArray[np.float64]

__all__ = ["link_positions"]


def link_positions(robot: SerialChain, trajectory: Trajectory, t: ArrayLike) -> FloatArray:
    """Positions of the base, every joint and the tool at times ``t``.

    Parameters
    ----------
    robot : SerialChain
    trajectory : Trajectory
        Joint trajectory of ``robot`` (one joint per robot joint).
    t : array_like, shape (m,)
        Times (s); clamped to the trajectory.

    Returns
    -------
    ndarray, shape (m, ndof + 2, 3)
        Polyline of the arm at each time (length unit of the robot): consecutive
        points are joined by links. Project onto two columns for a 2-D drawing.
    """
    if not isinstance(robot, SerialChain):
        raise InvalidInputError(f"robot must be a trajkit SerialChain, got {type(robot).__name__}")
    if not isinstance(trajectory, Trajectory) or trajectory.ndof != robot.ndof:
        raise InvalidInputError(f"trajectory must be a Trajectory with {robot.ndof} joints")
    times = np.atleast_1d(finite_array("t", t)).reshape(-1)
    return robot.points(trajectory.position(times)).reshape(times.size, robot.ndof + 2, 3)
