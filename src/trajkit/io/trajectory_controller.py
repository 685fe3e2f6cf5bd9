"""Exported points as ROS 2's ``joint_trajectory_controller`` plays them.

Its spline interpolator joins consecutive ``JointTrajectoryPoint`` messages by the
polynomial their fields determine: a line between positions alone, a cubic through
positions and velocities, a quintic through positions, velocities and
accelerations (ros2_controllers, ``Trajectory::interpolate_between_points``).
:func:`controller_trajectory` builds that curve as a trajkit
:class:`~trajkit.Trajectory`, so what a robot will execute can be checked, plotted
and simulated before it is sent, and compared with the plan the points came from.

Points that carry accelerations but no velocities are refused: the controller
interpolates nothing from them. Before the first point the controller moves from
wherever the robot is; the curve here starts at the first point.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from trajkit._validation import FloatArray, finite_array
from trajkit.errors import InvalidInputError
from trajkit.profiles.polynomial import hermite_pieces
from trajkit.trajectory import Trajectory

__all__ = ["controller_trajectory"]


def controller_trajectory(
    times: ArrayLike,
    positions: ArrayLike,
    velocities: ArrayLike | None = None,
    accelerations: ArrayLike | None = None,
) -> Trajectory:
    """The curve a joint trajectory controller follows through ``points``.

    Parameters
    ----------
    times : array_like, shape (n,)
        Each point's ``time_from_start`` (s), strictly increasing, n >= 2.
    positions : array_like, shape (n, ndof)
        Joint positions (rad or m).
    velocities, accelerations : array_like, shape (n, ndof), optional
        What the points carry besides positions (per second, per second squared).

    Returns
    -------
    Trajectory
        On the points' own times, from ``times[0]``: lines (positions only),
        cubics (with velocities) or quintics (with accelerations too), one piece
        between each two points,
        passing every point's values exactly up to rounding. ``info`` holds
        ``interpolation`` (``"linear"``, ``"cubic"`` or ``"quintic"``).

    Raises
    ------
    InvalidInputError
        Shapes that disagree, fewer than 2 points, times not increasing, values not
        finite, or accelerations without velocities.

    Examples
    --------
    >>> from trajkit.io.trajectory_controller import controller_trajectory
    >>> curve = controller_trajectory([0.0, 1.0], [[0.0], [1.0]], [[0.0], [0.0]])
    >>> round(float(curve.evaluate(0.5)[0]), 12), curve.info["interpolation"]
    (0.5, 'cubic')
    """
    t = finite_array("times", times, unit="s")
    if t.ndim != 1 or t.size < 2:
        raise InvalidInputError(f"times must hold at least 2 points in a 1-D array, got {t.shape}")
    if np.any(np.diff(t) <= 0.0):
        raise InvalidInputError("times must increase strictly from point to point")
    if velocities is None and accelerations is not None:
        raise InvalidInputError(
            "the points carry accelerations but no velocities: a joint trajectory controller "
            "interpolates nothing from them (give velocities too, or drop the accelerations)"
        )
    orders = [_values(name, value, t.size) for name, value in (
        ("positions", positions), ("velocities", velocities), ("accelerations", accelerations))
        if value is not None]  # fmt: skip
    shapes = {order.shape for order in orders}
    if len(shapes) != 1:
        raise InvalidInputError(
            f"positions, velocities and accelerations must have one shape, got {sorted(shapes)}"
        )
    stacked = np.stack(orders)  # (orders, n, ndof)
    durations = np.diff(t)[:, None]
    pieces = hermite_pieces(stacked[:, :-1], stacked[:, 1:], durations)
    kind = ("linear", "cubic", "quintic")[len(orders) - 1]
    return Trajectory(t, pieces, info={"interpolation": kind})


def _values(name: str, value: ArrayLike, count: int) -> FloatArray:
    array = finite_array(name, value)
    if array.ndim != 2 or array.shape[0] != count or array.shape[1] == 0:
        raise InvalidInputError(
            f"{name} must have shape ({count}, ndof), one row per point, got {array.shape}"
        )
    return array
