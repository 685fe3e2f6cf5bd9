"""The fastest timing of a tool path under the joints' velocity and acceleration limits.

The tool path is first mapped to joint space at a uniform pace (inverse kinematics
at every sample, a quintic Hermite spline through them: :func:`to_joint_space`);
that joint curve, read with its time as the path parameter, is then timed by
:func:`trajkit.topp`. Retiming a joint curve does not move it, so the tool
follows the same path, within the mapping's ``path_error``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from numpy.typing import ArrayLike

from trajkit.errors import InvalidInputError
from trajkit.kinematics.chain import SerialChain
from trajkit.limits import Limits
from trajkit.taskspace.joint_space import JointSpacePlan, to_joint_space
from trajkit.taskspace.motion import TaskTrajectory, timed
from trajkit.taskspace.paths import Path
from trajkit.time_optimal import PathLimit, topp
from trajkit.trajectory import Trajectory

__all__ = ["TimeOptimalMove", "time_optimal"]


@dataclass(frozen=True)
class TimeOptimalMove:
    """A tool path timed as fast as the joint limits allow.

    Attributes
    ----------
    trajectory : Trajectory
        The joints in time, from t = 0; its limits hold exactly (``check``).
    geometry : JointSpacePlan
        The joint path at a uniform pace that was timed (its ``path_error`` is how
        far its tool strays from the task path).
    """

    trajectory: Trajectory
    geometry: JointSpacePlan

    @property
    def duration(self) -> float:
        """Duration of the move (s)."""
        return self.trajectory.duration

    @property
    def path_error(self) -> float:
        """Largest distance of the tool from the task path (length unit of the robot)."""
        return self.geometry.path_error


def time_optimal(
    robot: SerialChain,
    path: Path | TaskTrajectory,
    limits: Limits,
    *,
    q_start: ArrayLike | None = None,
    branch: int | str | None = None,
    samples: int = 200,
    grid: int = 500,
    tolerance: float = 1e-6,
    constraints: PathLimit | Sequence[PathLimit] | None = None,
) -> TimeOptimalMove:
    """Move the tool along ``path`` as fast as the joint limits allow, at rest at both ends.

    Parameters
    ----------
    robot : SerialChain
    path : Path or TaskTrajectory
        The tool path; a TaskTrajectory's timing is ignored, only its geometry
        (and orientation) is kept.
    limits : Limits
        Joint velocity and acceleration bounds (rad/s, rad/s² or m/s, m/s²), and
        optionally jerk (then the jerk-limited timing of :func:`trajkit.topp`).
    q_start, branch
        Select the inverse-kinematics solution, as in :func:`to_joint_space`.
    samples : int
        Inverse-kinematics samples along the path (>= 2).
    grid : int
        Grid intervals of the time-optimal parameterization.
    tolerance : float
        Largest allowed distance of the joint curve's tool from the path (length
        unit of the robot).
    constraints : TorqueLimit, ToolLimit or a list of them, optional
        Further limits of the timing, as for :func:`trajkit.topp`: the tool's
        speed along the path (``ToolLimit(robot, speed=...)``), actuator torques.

    Returns
    -------
    TimeOptimalMove

    Examples
    --------
    >>> import trajkit as tk
    >>> from trajkit.kinematics import Spatial3R
    >>> from trajkit.taskspace import Line, time_optimal
    >>> arm = Spatial3R(5.0, 10.0, 8.0, 12.0)
    >>> move = time_optimal(arm, Line([0, -12, 20], [10, 12, 20]),
    ...                     tk.Limits(velocity=1.0, acceleration=2.0))
    >>> move.trajectory.check(tk.Limits(velocity=1.0, acceleration=2.0)).ok
    True
    """
    if isinstance(samples, bool) or not isinstance(samples, int) or samples < 2:
        raise InvalidInputError(f"samples must be an integer >= 2, got {samples!r}")
    if isinstance(path, Path):
        motion = timed(path, "linear", duration=1.0)
    elif isinstance(path, TaskTrajectory):
        motion = path
    else:
        raise InvalidInputError(
            f"path must be a taskspace Path or TaskTrajectory, got {type(path).__name__}"
        )
    geometry = to_joint_space(robot, motion, ik_step=motion.duration / samples, q_start=q_start,
                              branch=branch, tolerance=tolerance)  # fmt: skip
    result = topp(geometry.trajectory, limits, grid=grid, constraints=constraints)
    info = dict(result.info) | {"planner": "time_optimal", "path_error": geometry.path_error}
    return TimeOptimalMove(result.with_info(info), geometry)
