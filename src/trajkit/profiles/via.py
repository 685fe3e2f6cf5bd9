"""Trajectories through via points: piecewise cubic/quintic and C2 cubic splines."""

from __future__ import annotations

from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from trajkit._validation import (
    FloatArray,
    choice,
    finite_array,
    finite_result,
    increasing_times,
    joint_vector,
)
from trajkit.errors import InvalidInputError
from trajkit.profiles.polynomial import hermite_pieces
from trajkit.trajectory import Trajectory

__all__ = ["cubic_spline", "cubic_via", "heuristic_velocities", "quintic_via"]


def _via_velocities(t: FloatArray, q: FloatArray, velocities: ArrayLike | None) -> FloatArray:
    """The velocities at the via points: as given, else the heuristic's."""
    with np.errstate(all="ignore"):  # an overflow is refused by _through, by name
        if velocities is None:
            return heuristic_velocities(t, q)
        return _per_point("velocities", velocities, q, "rad/s")


def _via_points(times: ArrayLike, positions: ArrayLike) -> tuple[FloatArray, FloatArray]:
    t = increasing_times("times", times)
    q = finite_array("positions", positions, unit="rad")
    if q.ndim == 1:
        q = q[:, np.newaxis]
    if q.ndim != 2 or q.shape[0] != t.size:
        raise InvalidInputError(
            f"positions must have shape ({t.size},) or ({t.size}, ndof) to match times, "
            f"got shape {np.shape(positions)}"
        )
    return t, q


def _per_point(name: str, value: ArrayLike, like: FloatArray, unit: str) -> FloatArray:
    array = finite_array(name, value, unit=unit)
    if array.ndim == 1 and like.shape[1] == 1:
        array = array[:, np.newaxis]
    if array.shape != like.shape:
        raise InvalidInputError(
            f"{name} must have the shape of positions {like.shape}, got shape {array.shape}"
        )
    return array


def heuristic_velocities(times: FloatArray, positions: FloatArray) -> FloatArray:
    """Via-point velocities by the textbook rule (Craig).

    Zero at both ends; inside, the mean of the two adjacent segment slopes when
    they have the same sign, else zero.

    Parameters
    ----------
    times : ndarray, shape (n,)
    positions : ndarray, shape (n, ndof)

    Returns
    -------
    ndarray, shape (n, ndof)
        Velocities (rad/s).
    """
    slopes = np.diff(positions, axis=0) / np.diff(times)[:, np.newaxis]
    velocities = np.zeros_like(positions)
    before, after = slopes[:-1], slopes[1:]
    same_sign = np.sign(before) * np.sign(after) > 0
    velocities[1:-1] = np.where(same_sign, 0.5 * (before + after), 0.0)
    return velocities


def _through(times: FloatArray, start: FloatArray, end: FloatArray, planner: str) -> Trajectory:
    """One Hermite piece per segment, from per-point boundary values (orders, n, ndof).

    The boundary values may hold inf where the heuristics overflowed; the
    coefficients are checked, and refused naming the user's arguments.
    """
    durations = np.diff(times)[:, np.newaxis]
    with np.errstate(all="ignore"):
        c = hermite_pieces(start, end, durations)
    # Finite inputs can still overflow (a 1e-300 s segment): say so in the user's terms.
    positions = np.concatenate([start[0], end[0][-1:]])
    finite_result(planner, c, {"times": times, "positions": positions})
    # Hermite pieces match the given orders at each via point: C(orders - 1). The
    # first and last points' values are the exact start and end states.
    info = {"planner": planner, "continuity": start.shape[0] - 1}
    return Trajectory(times, c, info=info, start=start[:, 0], end=end[:, -1])


def cubic_via(
    times: ArrayLike, positions: ArrayLike, velocities: ArrayLike | None = None
) -> Trajectory:
    """One cubic per segment through via points, continuous in position and velocity.

    Parameters
    ----------
    times : array_like, shape (n,)
        Strictly increasing times (s) of the ``n >= 2`` via points.
    positions : array_like, shape (n,) or (n, ndof)
        Via-point positions (rad).
    velocities : array_like, same shape as positions, optional
        Via-point velocities (rad/s). ``None`` uses :func:`heuristic_velocities`:
        zero at the ends, the mean of adjacent slopes where they agree in sign.

    Returns
    -------
    Trajectory
        ``n - 1`` cubic pieces, C1 at the via points (acceleration may jump).
    """
    t, q = _via_points(times, positions)
    v = _via_velocities(t, q, velocities)
    start = np.stack([q[:-1], v[:-1]])
    end = np.stack([q[1:], v[1:]])
    return _through(t, start, end, "cubic_via")


def quintic_via(
    times: ArrayLike,
    positions: ArrayLike,
    velocities: ArrayLike | None = None,
    accelerations: ArrayLike | None = None,
) -> Trajectory:
    """One quintic per segment through via points, continuous up to acceleration.

    Parameters
    ----------
    times, positions, velocities
        As in :func:`cubic_via`.
    accelerations : array_like, same shape as positions, optional
        Via-point accelerations (rad/s^2). ``None``: zero at the ends; inside, the
        central difference of the via velocities,
        ``(v[k+1] - v[k-1]) / (t[k+1] - t[k-1])``.

    Returns
    -------
    Trajectory
        ``n - 1`` quintic pieces, C2 at the via points.
    """
    t, q = _via_points(times, positions)
    v = _via_velocities(t, q, velocities)
    if accelerations is None:
        a = np.zeros_like(q)
        with np.errstate(all="ignore"):
            a[1:-1] = (v[2:] - v[:-2]) / (t[2:] - t[:-2])[:, np.newaxis]
    else:
        a = _per_point("accelerations", accelerations, q, "rad/s^2")
    start = np.stack([q[:-1], v[:-1], a[:-1]])
    end = np.stack([q[1:], v[1:], a[1:]])
    return _through(t, start, end, "quintic_via")


def cubic_spline(
    times: ArrayLike,
    positions: ArrayLike,
    v0: ArrayLike = 0.0,
    vf: ArrayLike = 0.0,
    bc: Literal["clamped", "natural"] = "clamped",
) -> Trajectory:
    """C2-continuous cubic spline through all via points.

    Parameters
    ----------
    times, positions
        As in :func:`cubic_via`.
    v0, vf : float or array_like, shape (ndof,)
        End velocities (rad/s) for ``bc="clamped"``.
    bc : {"clamped", "natural"}
        ``"clamped"`` fixes the end velocities; ``"natural"`` makes the end
        accelerations zero (then ``v0``/``vf`` must be left at 0).

    Returns
    -------
    Trajectory
        ``n - 1`` cubic pieces, continuous in position, velocity and acceleration.
    """
    from scipy.interpolate import CubicSpline

    t, q = _via_points(times, positions)
    ndof = q.shape[1]
    start_velocity = joint_vector("v0", v0, ndof, unit="rad/s")
    end_velocity = joint_vector("vf", vf, ndof, unit="rad/s")
    choice("bc", bc, ("clamped", "natural"))
    arguments = {"times": t, "positions": q}
    # scipy refuses slopes that overflow with a bare ValueError: check them first.
    with np.errstate(all="ignore"):
        finite_result("cubic_spline", np.diff(q, axis=0) / np.diff(t)[:, np.newaxis], arguments)
    with np.errstate(all="ignore"):
        if bc == "clamped":
            spline = CubicSpline(t, q, bc_type=((1, start_velocity), (1, end_velocity)))
        else:
            if np.any(start_velocity) or np.any(end_velocity):
                raise InvalidInputError(
                    "bc='natural' sets the end accelerations to zero and leaves the end "
                    "velocities free; use bc='clamped' to give v0 or vf"
                )
            spline = CubicSpline(t, q, bc_type="natural")
    finite_result("cubic_spline", spline.c, arguments)
    info = {"planner": "cubic_spline", "bc": bc, "continuity": 2}
    exact = [q[0], start_velocity] if bc == "clamped" else [q[0]]
    final = [q[-1], end_velocity] if bc == "clamped" else [q[-1]]
    return Trajectory(t, spline.c, info=info, start=exact, end=final)
