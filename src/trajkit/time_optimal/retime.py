"""Retiming a planner's waypoint list: blend its corners within a tolerance, then time it.

A sampling planner (MoveIt's OMPL, say) hands over a dense list of joint-space
waypoints joined by straight segments. Timed as it is, the path must stop at every
corner, where its direction jumps. :func:`retime` replaces each corner by a
parabolic blend that stays within ``path_tolerance`` of the waypoint, so the path
has a continuous tangent and need not stop, and then times it with
:func:`~trajkit.time_optimal.topp`.

The blend at a corner ``C`` with unit directions ``y_in``, ``y_out`` leaves the
incoming segment at ``C - ℓ y_in`` and joins the outgoing one at ``C + ℓ y_out``
along the quadratic Bézier curve with control point ``C``. With ``s`` the polyline's
arc length and the blend spanning ``2ℓ`` of it, ``q'(s)`` is continuous (unit length
at both ends) and ``q'' = (y_out - y_in) / (2ℓ)`` on the blend. The blend comes
closest to ``C`` at its middle, at the corner's own ``s``, a distance
``ℓ |y_out - y_in| / 4`` from it; so ``ℓ = 4 δ / |y_out - y_in|`` for a tolerance
``δ``, but at most half of each segment, so that neighbouring blends never overlap.
(MoveIt's TOTG blends with circular arcs instead; a parabola keeps the path a
piecewise polynomial, which the timing keeps its limits on exactly.)
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

from trajkit._validation import FloatArray, finite_array, finite_scalar
from trajkit.errors import InvalidInputError
from trajkit.limits import Limits
from trajkit.time_optimal.constraints import PathLimit
from trajkit.trajectory import Trajectory

__all__ = ["blended_path", "retime"]

#: Blends shorter than this fraction of the path are left out (the corner stays).
_SHORTEST = 1e-9
#: Grid intervals inside each half of a blend, beside the uniform grid.
_PER_BLEND_HALF = 4


def blended_path(
    waypoints: ArrayLike, path_tolerance: float
) -> tuple[Trajectory, FloatArray, FloatArray]:
    """The polyline through ``waypoints`` with its corners blended within the tolerance.

    Parameters
    ----------
    waypoints : array_like, shape (m, ndof)
        Joint positions (rad or m), m >= 2; repeated consecutive points are merged.
    path_tolerance : float
        Largest distance of a blend from its waypoint (Euclidean, joint units), >= 0;
        0 keeps the corners (the timing then stops at each).

    Returns
    -------
    path : Trajectory
        ``q(s)`` with ``s`` the polyline's arc length: straight pieces and parabolic
        blends, each blend split at its middle; C1 wherever a corner is blended.
    at_waypoint : ndarray, shape (m,)
        The ``s`` of each input waypoint: for a corner, the middle of its blend,
        the path's closest point to it.
    deviation : ndarray, shape (m,)
        The distance from each waypoint to the path (0 at the ends and at corners
        not blended).

    Raises
    ------
    InvalidInputError
        Waypoints that are not a finite (m, ndof) matrix with two distinct points, or a
        negative or non-finite tolerance.
    """
    points = finite_array("waypoints", waypoints, unit="rad or m")
    if points.ndim != 2 or points.shape[0] < 2 or points.shape[1] < 1:
        raise InvalidInputError(
            f"waypoints must be a matrix of m >= 2 rows of joint positions, got shape "
            f"{points.shape}"
        )
    tolerance = finite_scalar("path_tolerance", path_tolerance, unit="rad or m")
    if tolerance < 0.0:
        raise InvalidInputError(f"path_tolerance must be >= 0, got {tolerance:g}")
    with np.errstate(over="ignore", invalid="ignore"):  # refused just below, by name
        steps = np.linalg.norm(np.diff(points, axis=0), axis=1)
    if not np.all(np.isfinite(steps)):
        raise InvalidInputError("waypoints are too far apart: their distances overflow float64")
    scale = max(float(np.abs(points).max()), 1.0)
    moving = steps > 1e-12 * scale
    if not moving.any():
        raise InvalidInputError("the waypoints never move (all the same point): nothing to time")
    # Merged points share their s; `keep` indexes the distinct ones.
    keep = np.concatenate([[0], np.flatnonzero(moving) + 1])
    distinct, lengths = points[keep], steps[moving]
    corner_s = np.concatenate([[0.0], np.cumsum(lengths)])
    direction = np.diff(distinct, axis=0) / lengths[:, None]
    turn = np.linalg.norm(direction[1:] - direction[:-1], axis=1)  # |y_out - y_in| per corner
    with np.errstate(divide="ignore", invalid="ignore"):
        reach = np.where(turn > 0.0, 4.0 * tolerance / turn, np.inf)
    half = np.minimum(lengths[:-1], lengths[1:]) / 2.0
    ell = np.minimum(reach, half)
    # Straight on, no blend is needed; one too short for float64 to place is no blend.
    ell = np.where((turn > 1e-12) & (ell > _SHORTEST * corner_s[-1]), ell, 0.0)
    # Three slots a segment: its straight middle, then the two halves of the blend at
    # its end (none after the last segment, nor where a corner is not blended).
    segments, ndof = direction.shape
    before = np.concatenate([[0.0], ell])[:, None]  # blend lengths at each segment's ends
    after = np.concatenate([ell, [0.0]])
    following = np.concatenate([direction[1:], np.zeros((1, ndof))])
    turning = following - direction
    with np.errstate(divide="ignore", invalid="ignore"):
        curve = np.where(after[:, None] > 0, turning / (2.0 * after[:, None]), 0.0)  # q''
    half_curve = curve / 2.0
    corner = distinct[1:]
    slots = np.zeros((segments, 3, 3, ndof))  # (segment, slot, power 2..0, joint)
    slots[:, 0, 1], slots[:, 0, 2] = direction, distinct[:-1] + before * direction
    slots[:, 1:, 0] = half_curve[:, None]
    slots[:, 1, 1], slots[:, 1, 2] = direction, corner - after[:, None] * direction
    slots[:, 2, 1] = (direction + following) / 2.0
    slots[:, 2, 2] = corner + after[:, None] * turning / 4.0  # the blend's middle
    ends = np.stack([corner_s[1:] - after, corner_s[1:], corner_s[1:] + after], axis=1)
    used = np.stack([ends[:, 0] > corner_s[:-1] + before[:, 0], after > 0, after > 0], axis=1)
    breaks = np.concatenate([[0.0], ends[used]])
    # (pieces, 3, ndof) as (3, pieces, ndof): highest power first.
    path = Trajectory(breaks, slots[used].transpose(1, 0, 2))
    deviation_distinct = np.concatenate([[0.0], ell * turn / 4.0, [0.0]])
    # Each input waypoint takes the s and deviation of the distinct point it merged into.
    owner = np.cumsum(np.concatenate([[True], moving])) - 1
    return path, corner_s[owner], deviation_distinct[owner]


def retime(
    waypoints: ArrayLike,
    limits: Limits,
    *,
    path_tolerance: float = 0.01,
    grid: int = 500,
    constraints: PathLimit | Sequence[PathLimit] | None = None,
) -> Trajectory:
    """Time a waypoint list as fast as the limits allow, cutting corners within a tolerance.

    Parameters
    ----------
    waypoints : array_like, shape (m, ndof)
        Joint positions (rad or m), as a planner returns them; m >= 2.
    limits : Limits
        Joint velocity and acceleration bounds, as for :func:`~trajkit.topp` (no jerk).
    path_tolerance : float
        Largest distance of the path from each waypoint (Euclidean in joint space,
        rad or m), >= 0. 0 keeps the polyline and stops at every corner.
    grid : int
        Uniform grid intervals along the path; each blend adds 8 of its own.
    constraints : TorqueLimit, ToolLimit or a list of them, optional
        Further limits, as for :func:`~trajkit.topp`.

    Returns
    -------
    Trajectory
        The timed path from t = 0, at rest at both ends. Its ``info`` holds, beside
        :func:`~trajkit.topp`'s, ``planner`` ("retime"), ``waypoint_times`` (s, when
        the motion passes each waypoint or the closest point to it),
        ``waypoint_deviation`` (the distance to each, rad or m) and
        ``path_tolerance``.

    Raises
    ------
    InvalidInputError
        Malformed waypoints (NaN, ragged, one row, all the same), tolerance, limits or grid.
    InfeasibleError
        As :func:`~trajkit.topp`.

    Examples
    --------
    >>> import numpy as np, trajkit as tk
    >>> corners = [[0, 0], [1, 0], [1, 1], [2, 1]]
    >>> limits = tk.Limits(velocity=1.0, acceleration=2.0)
    >>> motion = tk.retime(corners, limits, path_tolerance=0.05)
    >>> bool(motion.info["waypoint_deviation"].max() <= 0.05)
    True
    >>> motion.check(limits).ok
    True
    """
    from trajkit.time_optimal import grid_points, topp

    path, at_waypoint, deviation = blended_path(waypoints, path_tolerance)
    if isinstance(limits, Limits) and limits.jerk is not None:
        raise InvalidInputError(
            "retime takes velocity and acceleration bounds, not jerk: time the blended path "
            "(trajkit.time_optimal.blended_path) with trajkit.topp for a jerk-limited timing"
        )
    if isinstance(grid, bool) or not isinstance(grid, (int, np.integer)) or grid < 2:
        raise InvalidInputError(f"grid must be a whole number of intervals >= 2, got {grid!r}")
    # Each blend half gets a few grid intervals of its own: its curvature is the point.
    b = path.breakpoints
    blend = np.flatnonzero(np.abs(path.coefficients[0]).max(axis=1) > 0.0)
    inner = (b[blend, None] + np.diff(b)[blend, None] * np.linspace(0, 1, _PER_BLEND_HALF + 1)
             ).ravel()  # fmt: skip
    points = grid_points(b, int(grid))
    points = np.union1d(points, inner[(inner > b[0]) & (inner < b[-1])])
    timed = topp(path, limits, grid=points, constraints=constraints)
    s = timed.info["grid_points"]
    index = np.clip(np.searchsorted(s, at_waypoint), 0, s.size - 1)
    if not np.allclose(s[index], at_waypoint, rtol=0.0, atol=1e-9 * s[-1]):
        raise AssertionError("a waypoint's parameter is not a grid point")  # pragma: no cover
    return timed.with_info({
        **timed.info,
        "planner": "retime",
        "waypoint_times": timed.breakpoints[index],
        "waypoint_deviation": deviation,
        "path_tolerance": float(path_tolerance),
    })  # fmt: skip
