"""Linear segments through waypoints joined by blends (Craig's LSPB through via points).

Between waypoints every joint moves at constant velocity; around each interior
waypoint its velocity changes from one segment's to the next's in a blend centred
on the waypoint's time, so the motion does not stop there. The blends are
parabolic (constant acceleration) or, with ``jmax``, jerk-limited (acceleration
ramps at ``jmax``, holds at most ``amax``, ramps back: an S-shaped velocity change).
Both are symmetric in time, so a blend of duration ``tb`` from ``v1`` to ``v2``
covers ``(v1 + v2) tb / 2``, the same as the two straight lines it replaces: the
segment arithmetic is shared.

All joints share the waypoint times (synchronized per segment); each joint's
blends last as long as its own velocity change needs.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from trajkit._validation import FloatArray, finite_array, positive_joint_vector
from trajkit.errors import InfeasibleError, InvalidInputError
from trajkit.profiles._phases import PhasePlan, plan_to_trajectory
from trajkit.trajectory import Trajectory

__all__ = ["blended"]

_ITERATIONS = 200  # fixed-point passes when searching segment durations


def _change_time(dv: FloatArray, amax: FloatArray, jmax: FloatArray | None) -> FloatArray:
    """Shortest time to change velocity by ``|dv|`` with zero end accelerations."""
    size = np.abs(dv)
    if jmax is None:
        return size / amax
    saturated = size >= amax**2 / jmax
    return np.where(saturated, size / amax + amax / jmax, 2.0 * np.sqrt(size / jmax))


def _fastest_change(T: FloatArray, amax: FloatArray, jmax: FloatArray | None) -> FloatArray:
    """Largest velocity change that fits in ``T`` seconds (inverse of :func:`_change_time`)."""
    if jmax is None:
        return amax * T
    return np.where(T >= 2 * amax / jmax, amax * (T - amax / jmax), jmax * (T / 2) ** 2)


def _velocities(
    q: FloatArray, durations: FloatArray, amax: FloatArray, jmax: FloatArray | None
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Segment velocities (n - 1, ndof), blend times (n, ndof), end feasibility (2, ndof).

    Interior segments: ``v = dq / T``. The first and last blends start (end) at
    rest inside their segment, so there ``|dq| = |v| (T - tb(|v|) / 2)``. On
    ``0 <= |v| <= v_hi`` (the largest change that fits in ``T``) the right side
    increases, so bisection finds ``|v|``; when even ``v_hi`` falls short of
    ``|dq|`` the segment is too short (feasibility False).
    """
    dq = np.diff(q, axis=0)
    T = durations[:, np.newaxis]
    v = dq / T
    feasible = np.ones((2, q.shape[1]), bool)
    for row, end in enumerate((0, -1)):
        d, t = np.abs(dq[end]), T[end]
        high = _fastest_change(t, amax, jmax)
        covered_high = high * (t - _change_time(high, amax, jmax) / 2.0)
        feasible[row] = covered_high >= d * (1 - 1e-12)
        low = np.zeros_like(d)
        for _ in range(100):
            mid = 0.5 * (low + high)
            covered = mid * (t - _change_time(mid, amax, jmax) / 2.0)
            above = covered >= d
            high = np.where(above, mid, high)
            low = np.where(above, low, mid)
        v[end] = np.sign(dq[end]) * high
    padded = np.concatenate([np.zeros((1, q.shape[1])), v, np.zeros((1, q.shape[1]))])
    blends = _change_time(np.diff(padded, axis=0), amax, jmax)
    return v, blends, feasible


def _room(durations: FloatArray, blends: FloatArray) -> FloatArray:
    """Linear time left in every segment (n - 1, ndof) once the blends take theirs."""
    share = blends.copy()
    share[1:-1] /= 2.0  # interior blends straddle their waypoint; end blends lie inside
    return durations[:, np.newaxis] - share[:-1] - share[1:]


def blended(
    waypoints: ArrayLike,
    vmax: ArrayLike,
    amax: ArrayLike,
    *,
    jmax: ArrayLike | None = None,
    durations: ArrayLike | None = None,
    through: bool = False,
) -> Trajectory:
    """Move through waypoints without stopping: linear segments joined by blends.

    Parameters
    ----------
    waypoints : array_like, shape (n, ndof) or (n,)
        Start, via points and goal (rad), ``n >= 2``.
    vmax, amax : float or array_like, shape (ndof,)
        Velocity (rad/s) and acceleration (rad/s^2) limits, symmetric.
    jmax : float or array_like, optional
        Jerk limit (rad/s^3): S-shaped (jerk-limited) blends instead of parabolic.
    durations : array_like, shape (n - 1,), optional
        Time (s) between consecutive waypoints. By default each segment is as
        short as its velocity limit and the blends at its ends allow (found by a
        fixed-point iteration that only lengthens segments, so every limit holds;
        with coupled blends this is the shortest such schedule it reaches, not a
        global optimum).
    through : bool
        Pass exactly through the interior waypoints. The blends cut the corners,
        so each interior waypoint is replaced by a pseudo waypoint pushed outwards
        until the blend passes the real one at its time (Craig's pseudo via
        points), then the plan is made again.

    Returns
    -------
    Trajectory
        ``info`` holds ``times`` (waypoint times, s), ``durations`` (per segment),
        ``segment_velocities`` (n - 1, ndof), ``blend_times`` (n, ndof),
        ``via_deviation`` (n, ndof: position at each waypoint's time minus the
        waypoint) and ``via_distance`` (n,: its Euclidean norm).

    Raises
    ------
    InvalidInputError
        Malformed waypoints or limits, durations of the wrong length.
    InfeasibleError
        Given durations too short for the limits (the message names the segment
        and the shortest duration that works for it alone).
    """
    q = finite_array("waypoints", waypoints, unit="rad")
    if q.ndim == 1:
        q = q[:, np.newaxis]
    if q.ndim != 2 or q.shape[0] < 2:
        raise InvalidInputError(
            f"waypoints must have shape (n, ndof) with n >= 2, got shape {np.shape(waypoints)}"
        )
    q = np.array(q)
    n, ndof = q.shape
    v_limit = positive_joint_vector("vmax", vmax, ndof, unit="rad/s")
    a_limit = positive_joint_vector("amax", amax, ndof, unit="rad/s^2")
    j_limit = None if jmax is None else positive_joint_vector("jmax", jmax, ndof, unit="rad/s^3")
    given = None
    if durations is not None:
        given = finite_array("durations", durations, unit="s")
        if given.shape != (n - 1,):
            raise InvalidInputError(
                f"durations must give one time per segment ({n - 1}), got shape {given.shape}"
            )
        if np.any(given <= 0):
            raise InvalidInputError("durations must all be > 0 s")
    targets = q
    for _ in range(60 if through and n > 2 else 1):
        segment_durations = _schedule(targets, v_limit, a_limit, j_limit, given)
        trajectory, details = _build(targets, segment_durations, a_limit, j_limit)
        if not (through and n > 2):
            break
        miss = details["via_position"][1:-1] - q[1:-1]
        if np.max(np.abs(miss)) <= 1e-12 * max(1.0, float(np.max(np.abs(q)))):
            break
        targets = targets.copy()
        targets[1:-1] -= miss
    else:
        raise InfeasibleError(
            "could not place pseudo via points so the motion passes through every waypoint "
            "within the limits; give longer durations"
        )
    _verify_limits(trajectory, details, v_limit, a_limit)
    deviation = details["via_position"] - q
    info = {
        "planner": "blended",
        "jerk_limited": j_limit is not None,
        "through": through,
        "times": tuple(float(x) for x in details["times"]),
        "durations": tuple(float(x) for x in segment_durations),
        "segment_velocities": details["velocities"],
        "blend_times": details["blends"],
        "pseudo_waypoints": targets if through else None,
        "via_deviation": deviation,
        "via_distance": np.linalg.norm(deviation, axis=1),
    }
    return Trajectory(trajectory.breakpoints, trajectory.coefficients, info=info)


def _schedule(
    q: FloatArray,
    v_limit: FloatArray,
    a_limit: FloatArray,
    j_limit: FloatArray | None,
    given: FloatArray | None,
) -> FloatArray:
    """Segment durations: the given ones (checked) or the shortest the iteration reaches."""
    dq = np.abs(np.diff(q, axis=0))
    if given is not None:
        v, blends, ends = _velocities(q, given, a_limit, j_limit)
        room = _room(given, blends)
        short = (np.abs(v) > v_limit * (1 + 1e-12)).any(axis=1)
        short |= (room < -1e-12 * given[:, np.newaxis]).any(axis=1)
        short[0] |= not ends[0].all()
        short[-1] |= not ends[1].all()
        if short.any():
            bad = int(np.flatnonzero(short)[0])
            alone = _schedule(q[bad : bad + 2], v_limit, a_limit, j_limit, None)[0]
            raise InfeasibleError(
                f"durations[{bad}] = {given[bad]:.6g} s is too short for the limits "
                f"(segment {bad} alone needs at least {alone:.6g} s)"
            )
        return given
    # Start from the velocity limit alone, then lengthen what the blends need.
    T = np.max(dq / v_limit, axis=1)
    T = np.maximum(T, 1e-9)
    for _ in range(_ITERATIONS):
        v, blends, ends = _velocities(q, T, a_limit, j_limit)
        share = blends.copy()
        share[1:-1] /= 2.0
        need = np.max(share[:-1] + share[1:], axis=1)
        speed = np.max(np.abs(v) / v_limit, axis=1)
        grown = np.maximum(T, np.maximum(need, T * np.minimum(np.maximum(speed, 1.0), 1.01)))
        # An end segment too short for its start or stop grows by 1 % at a time.
        grown[0] *= 1.0 if ends[0].all() else 1.01
        grown[-1] *= 1.0 if ends[1].all() else 1.01
        if np.all(grown <= T * (1 + 1e-13)):
            break
        T = grown
    else:
        raise InfeasibleError("could not find segment durations that keep the limits")
    # No motion at all in a segment: it still needs some time to be a segment.
    return np.where(T > 0, T, 1e-9)


def _build(
    q: FloatArray, T: FloatArray, a_limit: FloatArray, j_limit: FloatArray | None
) -> tuple[Trajectory, dict[str, FloatArray]]:
    """Phase plan of every joint, and the positions at the waypoint times."""
    n, ndof = q.shape
    v, blends, _ = _velocities(q, T, a_limit, j_limit)
    padded = np.concatenate([np.zeros((1, ndof)), v, np.zeros((1, ndof))])
    dv = np.diff(padded, axis=0)  # (n, ndof) velocity change of every blend
    times = np.concatenate([[0.0], np.cumsum(T)])
    # Each joint: blend 0, linear 0, blend 1, linear 1, ..., blend n-1.
    room = np.maximum(_room(T, blends), 0.0)
    if j_limit is None:
        blend_durations = blends[..., np.newaxis]  # one phase per blend, at +-amax
        blend_acc = (np.sign(dv) * a_limit)[..., np.newaxis]
        blend_jerk = np.zeros_like(blend_acc)
    else:
        # Ramp up, hold, ramp down at the jerk that makes the change take exactly tb.
        size = np.abs(dv)
        saturated = size >= a_limit**2 / j_limit
        ramp = np.where(saturated, a_limit / j_limit, np.sqrt(size / j_limit))
        hold = np.where(saturated, size / a_limit - a_limit / j_limit, 0.0)
        sign = np.sign(dv)
        blend_durations = np.stack([ramp, hold, ramp], axis=-1)
        peak = sign * np.where(saturated, a_limit, j_limit * ramp)
        blend_acc = np.stack([np.zeros_like(peak), peak, peak], axis=-1)
        blend_jerk = np.stack([sign * j_limit, np.zeros_like(peak), -sign * j_limit], axis=-1)
    k = blend_durations.shape[-1]
    count = n * k + (n - 1)
    durations = np.zeros((ndof, count))
    accelerations = np.zeros((ndof, count))
    jerks = np.zeros((ndof, count))
    for i in range(n):  # loop over waypoints (a handful), vectorized over joints
        at = i * (k + 1)
        durations[:, at : at + k] = blend_durations[i]
        accelerations[:, at : at + k] = blend_acc[i]
        jerks[:, at : at + k] = blend_jerk[i]
        if i < n - 1:
            durations[:, at + k] = room[i]
    plan = PhasePlan(q[0].copy(), np.zeros(ndof), durations, accelerations, jerks)
    trajectory = plan_to_trajectory(plan, float(times[-1]), {})
    details = {
        "times": times,
        "velocities": v,
        "blends": blends,
        "via_position": trajectory.position(times),
    }
    return trajectory, details


def _verify_limits(
    trajectory: Trajectory,
    details: dict[str, FloatArray],
    v_limit: FloatArray,
    a_limit: FloatArray,
) -> None:
    """The plan must land on the last waypoint and keep its limits (exact check)."""
    velocity, acceleration = trajectory.extrema(1).peak, trajectory.extrema(2).peak
    if np.any(velocity > v_limit * (1 + 1e-9)) or np.any(acceleration > a_limit * (1 + 1e-9)):
        raise InfeasibleError(
            "the blends do not fit the given durations within the limits; give longer durations"
        )
    del details
