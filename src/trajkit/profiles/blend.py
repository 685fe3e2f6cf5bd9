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

from trajkit._validation import FloatArray, finite_array, flag, positive_joint_vector
from trajkit.errors import InfeasibleError, InvalidInputError
from trajkit.profiles._phases import PhasePlan, plan_to_trajectory
from trajkit.tolerances import LIMIT_RTOL, ROUNDING_RTOL
from trajkit.trajectory import Trajectory

__all__ = ["blended"]

_ITERATIONS = 200  # fixed-point passes when searching segment durations
_NEWTON = 60  # Newton steps when placing pseudo via points at fixed durations
_LENGTHEN = 100  # schedules through=True tries, each longer than the last, before giving up
_SHORTEST = 1e-9  # s: a segment without motion still needs some time to be a segment


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


def _ramp_and_hold(
    size: FloatArray, amax: FloatArray, jmax: FloatArray | None
) -> tuple[FloatArray, FloatArray]:
    """Jerk ramp time and acceleration hold time (s) of a velocity change of ``size``."""
    if jmax is None:
        return np.zeros_like(size), size / amax
    saturated = size >= amax**2 / jmax
    ramp = np.where(saturated, amax / jmax, np.sqrt(size / jmax))
    hold = np.where(saturated, size / amax - amax / jmax, 0.0)
    return ramp, hold


def _corner(
    dv: FloatArray, amax: FloatArray, jmax: FloatArray | None
) -> tuple[FloatArray, FloatArray]:
    """Where an interior blend passes its waypoint (rad), and the rate of that in ``dv`` (s).

    A blend centred on the waypoint's time leaves the incoming line half a blend
    before it, so at the waypoint's time it is ahead of the line by the integral
    of the velocity change over its first half: with ramp ``r`` and hold ``h``
    (peak acceleration ``|dv| / (r + h)``) that is
    ``dv (r^2/6 + r h/4 + h^2/8) / (r + h)`` (``dv |dv| / (8 amax)`` for a
    parabolic blend); its derivative in ``dv`` is ``(r + h) / 4``.
    """
    size = np.abs(dv)
    ramp, hold = _ramp_and_hold(size, amax, jmax)
    width = ramp + hold
    shape = ramp**2 / 6.0 + ramp * hold / 4.0 + hold**2 / 8.0
    safe = np.where(width > 0.0, width, 1.0)
    return np.where(width > 0.0, dv * shape / safe, 0.0), width / 4.0


def _end_speed(
    d: FloatArray, T: FloatArray, amax: FloatArray, jmax: FloatArray | None
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Speed of an end segment, whether it fits, and the rate of its step in the speed.

    The segment starts at rest with a blend lying inside it, then runs on the
    line that passes ``d >= 0`` past its start at its end time ``T``:
    ``d = v (T - tb(v) / 2)``. On ``tb(v) <= T`` the right side rises with ``v``
    (its derivative ``T - tb + r / 2``, ``r`` the ramp time, is positive), so
    there is one such ``v`` when ``d`` is at most its value at ``tb = T``.
    Elsewhere (the segment is too short) the speed is the largest change that
    fits, and ``fits`` is False.
    """
    high = _fastest_change(T, amax, jmax)
    reach = high * (T - _change_time(high, amax, jmax) / 2.0)
    fits = reach >= d * (1.0 - ROUNDING_RTOL)
    with np.errstate(divide="ignore", invalid="ignore"):
        if jmax is None:
            # d = v T - v^2 / (2 amax); the smaller root, written without cancellation.
            speed = 2.0 * d / (T + np.sqrt(np.maximum(T**2 - 2.0 * d / amax, 0.0)))
        else:
            b = amax / jmax
            edge = amax * b  # the smallest change that saturates the acceleration
            # Saturated: d = v T - v^2 / (2 amax) - v b / 2, again a quadratic.
            rest = T - b / 2.0
            saturated = 2.0 * d / (rest + np.sqrt(np.maximum(rest**2 - 2.0 * d / amax, 0.0)))
            # Below: d = v T - v^1.5 / sqrt(jmax). The right side is concave, so Newton
            # from the left climbs to the root without overshooting; at tb <= T its
            # slope stays >= T / 4, so the convergence is quadratic.
            use_saturated = (high >= edge) & (d >= edge * (T - b))
            below = fits & ~use_saturated
            speed = d / T
            for _ in range(50):
                root = np.sqrt(speed / jmax)
                step = (d - speed * (T - root)) / np.maximum(T - 1.5 * root, T / 4.0)
                speed = speed + step
                if np.all(np.abs(step[below]) <= 1e-16 * speed[below]):
                    break
            speed = np.where(use_saturated, saturated, speed)
        speed = np.where(fits, np.minimum(speed, high), high)
    speed = np.where(d > 0.0, speed, 0.0)
    ramp, _ = _ramp_and_hold(speed, amax, jmax)
    rate = T - _change_time(speed, amax, jmax) + ramp / 2.0
    return speed, fits, rate


def _velocities(
    q: FloatArray, durations: FloatArray, amax: FloatArray, jmax: FloatArray | None
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Segment velocities (n - 1, ndof), blend times (n, ndof), end fit (2, ndof), rates.

    Interior segments: ``v = dq / T``. The first and last blends start (end) at
    rest inside their segment (see :func:`_end_speed`). With two waypoints the
    start and the stop share the one segment: by symmetry each half of it covers
    half the step in half the time, so that is the end problem with ``dq / 2``
    and ``T / 2``. ``rates`` is ``dv / d(dq)`` of each segment (for
    :func:`_pseudo_waypoints`): ``1 / T`` inside, ``1 / (dq / dv)`` at the ends.
    """
    dq = np.diff(q, axis=0)
    T = durations[:, np.newaxis]
    v = dq / T
    rates = np.broadcast_to(1.0 / T, dq.shape).copy()
    fits = np.ones((2, q.shape[1]), bool)
    if q.shape[0] == 2:
        speed, fits[:], _ = _end_speed(np.abs(dq[0]) / 2.0, T[0] / 2.0, amax, jmax)
        v[0] = np.sign(dq[0]) * speed
    else:
        for row, end in enumerate((0, -1)):
            speed, fits[row], rate = _end_speed(np.abs(dq[end]), T[end], amax, jmax)
            v[end] = np.sign(dq[end]) * speed
            # The rate vanishes where the blend fills the segment (parabolic, tb = T).
            with np.errstate(divide="ignore"):
                rates[end] = np.where(
                    fits[row], 1.0 / np.maximum(rate, ROUNDING_RTOL * T[end]), 0.0
                )
    padded = np.concatenate([np.zeros((1, q.shape[1])), v, np.zeros((1, q.shape[1]))])
    blends = _change_time(np.diff(padded, axis=0), amax, jmax)
    return v, blends, fits, rates


def _room(durations: FloatArray, blends: FloatArray) -> FloatArray:
    """Linear time left in every segment (n - 1, ndof) once the blends take theirs."""
    share = blends.copy()
    share[1:-1] /= 2.0  # interior blends straddle their waypoint; end blends lie inside
    return durations[:, np.newaxis] - share[:-1] - share[1:]


def _end_minimum(
    d: FloatArray, vmax: FloatArray, amax: FloatArray, jmax: FloatArray | None
) -> FloatArray:
    """Shortest end segment (s) for a step ``d >= 0``: it starts at rest, ends on its line.

    ``T(v) = d / v + tb(v) / 2`` falls with ``v`` until the blend fills the
    segment (``tb(v) v = 2 d``), which is the fastest start; the velocity limit
    may stop it sooner.
    """
    if jmax is None:
        top = np.sqrt(2.0 * amax) * np.sqrt(d)  # 2 amax d underflows for a subnormal step
    else:
        b = amax / jmax
        unsaturated = np.cbrt(d) ** 2 * np.cbrt(jmax)  # 2 v sqrt(v / jmax) = 2 d
        saturated = 4.0 * d / (b + np.sqrt(b**2 + 8.0 * d / amax))  # (v / amax + b) v = 2 d
        top = np.where(unsaturated < amax * b, unsaturated, saturated)
    speed = np.minimum(vmax, top)
    safe = np.where(d > 0.0, speed, 1.0)
    return np.where(d > 0.0, d / safe + _change_time(speed, amax, jmax) / 2.0, 0.0)


def _own_minimum(
    q: FloatArray, vmax: FloatArray, amax: FloatArray, jmax: FloatArray | None
) -> FloatArray:
    """Shortest duration (s) of every segment alone, shape (n - 1,).

    Its velocity limit and, at the ends, its start or stop; not the blends it
    shares with its neighbours.
    """
    dq = np.abs(np.diff(q, axis=0))
    own = np.max(dq / vmax, axis=1)
    if q.shape[0] == 2:
        own[0] = max(own[0], 2.0 * np.max(_end_minimum(dq[0] / 2.0, vmax, amax, jmax)))
    else:
        for end in (0, -1):
            own[end] = max(own[end], np.max(_end_minimum(dq[end], vmax, amax, jmax)))
    return own


def _norms(rows: FloatArray) -> FloatArray:
    """Euclidean norm of every row, without overflowing for entries near 1e308."""
    largest = np.max(np.abs(rows), axis=1)
    safe = np.where(largest > 0.0, largest, 1.0)
    return largest * np.linalg.norm(rows / safe[:, np.newaxis], axis=1)


def _out_of_range(q: FloatArray, v_limit: FloatArray, a_limit: FloatArray) -> InfeasibleError:
    """The error for steps and limits whose arithmetic overflows or underflows."""
    return InfeasibleError(
        f"waypoint steps up to {float(np.max(np.abs(np.diff(q, axis=0)))):.3g} rad with "
        f"vmax down to {float(np.min(v_limit)):.3g} rad/s and amax down to "
        f"{float(np.min(a_limit)):.3g} rad/s^2 give times or speeds float64 cannot "
        "hold: use units that keep them within about 1e-150 to 1e150"
    )


def _extreme(q: FloatArray, v_limit: FloatArray, a_limit: FloatArray, duration: float) -> bool:
    """Whether steps, vmax, amax or the duration lie far from 1 (beyond 1e-100..1e100).

    There the arithmetic under- or overflows (1e-300 squared is 0), so a failed
    check means numbers float64 cannot plan with, not a planning defect.
    """
    sizes = np.concatenate([np.abs(np.diff(q, axis=0)).ravel(), v_limit, a_limit, [duration]])
    sizes = sizes[sizes > 0.0]
    return not bool(np.all((sizes >= 1e-100) & (sizes <= 1e100)))


def _plan(
    q: FloatArray,
    v_limit: FloatArray,
    a_limit: FloatArray,
    j_limit: FloatArray | None,
    given: FloatArray | None,
    through: bool,
) -> tuple[Trajectory, dict[str, FloatArray], FloatArray, FloatArray]:
    """Durations, pseudo waypoints and the checked trajectory of :func:`blended`."""
    if given is None:
        durations = _schedule(q, v_limit, a_limit, j_limit)
    else:
        problem = _shortfall(q, given, v_limit, a_limit, j_limit)
        if problem is not None:
            raise InfeasibleError(problem)
        durations = given
    targets = q
    if through:
        targets, durations = _pass_through(
            q, durations, v_limit, a_limit, j_limit, fixed=given is not None
        )
    out_of_range = _out_of_range(q, v_limit, a_limit)
    if not (np.all(np.isfinite(durations)) and np.all(np.isfinite(targets))):
        raise out_of_range
    try:
        trajectory, details = _build(targets, durations, a_limit, j_limit)
    except InvalidInputError as error:  # non-finite coefficients: the arithmetic overflowed
        raise out_of_range from error
    if not np.all(np.isfinite(details["via_position"])):
        raise out_of_range
    _verify(trajectory, details, q, through, v_limit, a_limit)
    return trajectory, details, targets, durations


def _schedule(
    q: FloatArray,
    v_limit: FloatArray,
    a_limit: FloatArray,
    j_limit: FloatArray | None,
    start: FloatArray | None = None,
) -> FloatArray:
    """The shortest segment durations the iterations reach, none below ``start``.

    Every segment starts at its own minimum (:func:`_own_minimum`), which keeps
    its velocity limit and, at the ends, its start or stop; lengthening a segment
    keeps both. Two rules then lengthen the segments whose blends do not fit
    (:func:`_lengthen_all`, :func:`_lengthen_faster`); neither is best
    everywhere, so the shorter schedule of the two is kept.
    """
    T = np.maximum(_own_minimum(q, v_limit, a_limit, j_limit), _SHORTEST)
    if start is not None:
        T = np.maximum(T, start)
    found = [rule(q, T, a_limit, j_limit) for rule in (_lengthen_all, _lengthen_faster)]
    found = [T for T in found if T is not None]
    if not found:
        if _extreme(q, v_limit, a_limit, float(np.sum(T))):
            raise _out_of_range(q, v_limit, a_limit)
        raise InfeasibleError("could not find segment durations that keep the limits")
    return min(found, key=lambda T: float(np.sum(T)))


def _blend_needs(
    q: FloatArray, T: FloatArray, a_limit: FloatArray, j_limit: FloatArray | None
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Segment velocities, the blend time each segment must hold (n - 1, ndof), shares."""
    v, blends, _, _ = _velocities(q, T, a_limit, j_limit)
    share = blends.copy()
    share[1:-1] /= 2.0  # interior blends straddle their waypoint; end blends lie inside
    return v, share[:-1] + share[1:], share


def _lengthen_all(
    q: FloatArray, T: FloatArray, a_limit: FloatArray, j_limit: FloatArray | None
) -> FloatArray | None:
    """Every segment as long as its blends need, until that holds (None: not settled)."""
    for _ in range(_ITERATIONS):
        _, need, _ = _blend_needs(q, T, a_limit, j_limit)
        need = np.max(need, axis=1)
        if not np.all(np.isfinite(need)):
            return None  # overflowed: no schedule to find
        if np.all(need <= T * (1 + 1e-13)):
            return T
        T = np.maximum(T, need)
    return None


def _lengthen_faster(
    q: FloatArray, T: FloatArray, a_limit: FloatArray, j_limit: FloatArray | None
) -> FloatArray | None:
    """Slow down the faster side of the blend that overflows a segment (None: not settled).

    A segment whose blend is too long because its neighbour runs too fast need
    not grow: the neighbour should slow down (:func:`_lengthen_all` once made a
    1e-6 rad start segment 0.5 s long for that). For each segment that overflows,
    the blend taking more of it is found and the faster of that blend's two
    sides grows, by at most 25 % a pass; an overflow under 1 % is closed by
    lengthening the segment itself. Still segments between fast ones are what
    this rule does badly: the fast side keeps slowing down.
    """
    columns = np.arange(q.shape[1])
    for _ in range(_ITERATIONS):
        v, need, share = _blend_needs(q, T, a_limit, j_limit)
        ratio = need / T[:, np.newaxis]
        if not np.all(np.isfinite(ratio)):
            return None  # overflowed: no schedule to find
        short = ratio > 1 + 1e-13
        if not short.any():
            return T
        speed = np.abs(v)
        padded = np.concatenate([np.zeros((1, q.shape[1])), speed, np.zeros((1, q.shape[1]))])
        grow = np.ones_like(T)
        for i in np.flatnonzero(short.any(axis=1)):  # segment i holds blends i and i + 1
            k = np.where(share[i] >= share[i + 1], i, i + 1)
            # The speeds of segments k - 1 and k, either side of blend k.
            left, right = padded[k, columns], padded[k + 1, columns]
            culprit = np.where(left >= right, k - 1, k)
            culprit = np.where((culprit < 0) | (culprit >= T.size), i, culprit)
            for c in np.unique(culprit[short[i]]):
                amount = np.max(np.minimum(ratio[i][short[i] & (culprit == c)], 1.25))
                grow[c] = max(grow[c], float(amount))
        close = (short & (ratio <= 1.01)).any(axis=1)
        T = np.where(close, np.maximum(T * grow, np.max(need, axis=1)), T * grow)
    return None


def _shortfall(
    q: FloatArray,
    T: FloatArray,
    v_limit: FloatArray,
    a_limit: FloatArray,
    j_limit: FloatArray | None,
) -> str | None:
    """Why the durations ``T`` do not fit the limits (naming a segment), or None.

    A segment shorter than it needs alone is the one to blame, even when a huge
    blend it causes eats a neighbour's time first; only when every segment is
    long enough alone is the blame on the first one whose blends overlap.
    """
    own = _own_minimum(q, v_limit, a_limit, j_limit)
    v, blends, fits, _ = _velocities(q, T, a_limit, j_limit)
    # Both follow from T >= own; checked again so rounding cannot slip through.
    alone = T < own * (1 - ROUNDING_RTOL)
    alone |= (np.abs(v) > v_limit * (1 + ROUNDING_RTOL)).any(axis=1)
    alone[0] |= not fits[0].all()
    alone[-1] |= not fits[1].all()
    if alone.any():
        k = int(np.flatnonzero(alone)[0])
        return (
            f"durations[{k}] = {T[k]:.6g} s is too short for the limits "
            f"(segment {k} alone needs at least {own[k]:.6g} s)"
        )
    room = _room(T, blends)
    overlap = (room < -ROUNDING_RTOL * T[:, np.newaxis]).any(axis=1)
    if overlap.any():
        k = int(np.flatnonzero(overlap)[0])
        need = float(np.max(T[k] - room[k]))
        return (
            f"durations[{k}] = {T[k]:.6g} s is too short for the limits: the blends at "
            f"waypoints {k} and {k + 1} need {need:.6g} s of it"
        )
    return None


def _pseudo_waypoints(
    q: FloatArray, T: FloatArray, a_limit: FloatArray, j_limit: FloatArray | None
) -> tuple[FloatArray, bool | None]:
    """Pseudo waypoints whose blends pass every interior waypoint at its time.

    For fixed durations each joint is its own problem: interior pseudo points
    ``p`` with ``p_i + corner(v_i - v_(i-1)) = q_i`` (:func:`_corner`), the
    velocities following from ``p`` (:func:`_velocities`). Its Jacobian is
    tridiagonal; Newton's method with a halving line search solves it. (Moving
    each point by its miss alone diverges once the blends take most of their
    segments: the rate of the miss in ``p`` then exceeds 1.) Returns the points
    and whether every joint converged (None: the miss overflows float64); the
    caller checks the limits.
    """
    ndof = q.shape[1]
    pseudo = q.copy()
    tolerance = 1e-12 * float(np.max(np.abs(q)))
    from scipy.linalg import solve_banded  # scipy is slow to import: only when blending through

    converged = True
    for joint in range(ndof):
        a = a_limit[joint : joint + 1]
        j = None if j_limit is None else j_limit[joint : joint + 1]
        target = q[1:-1, joint]

        x = q[:, joint : joint + 1].copy()
        miss, banded = _through_system(x, target, T, a, j)
        worst = float(np.max(np.abs(miss)))
        if not np.isfinite(worst):
            return pseudo, None  # overflowed: nothing to solve
        for _ in range(_NEWTON):
            if worst <= tolerance:
                break
            try:
                step = solve_banded((1, 1), banded, -miss)
            except (np.linalg.LinAlgError, ValueError):
                break  # singular: no Newton step; the caller lengthens the durations
            if not np.all(np.isfinite(step)):
                break
            fraction = 1.0
            for _ in range(40):
                trial = x.copy()
                trial[1:-1, 0] += fraction * step
                trial_miss, trial_banded = _through_system(trial, target, T, a, j)
                trial_worst = float(np.max(np.abs(trial_miss)))
                if trial_worst < worst:
                    break
                fraction /= 2.0
            else:
                break
            x, miss, banded, worst = trial, trial_miss, trial_banded, trial_worst
        converged &= worst <= tolerance
        pseudo[:, joint] = x[:, 0]
    return pseudo, converged


def _through_system(
    x: FloatArray, target: FloatArray, T: FloatArray, amax: FloatArray, jmax: FloatArray | None
) -> tuple[FloatArray, FloatArray]:
    """Miss of one joint's blends at its interior waypoints, and its banded Jacobian.

    ``x`` (n, 1) are the joint's (pseudo) waypoints, ``target`` (n - 2,) the real
    interior ones. With ``w`` the segment rates and ``s`` the corner slopes, row
    ``i`` of the Jacobian is ``s_i w_(i-1)``, ``1 - s_i (w_(i-1) + w_i)``,
    ``s_i w_i``, stored as :func:`scipy.linalg.solve_banded` wants it.
    """
    v, _, _, rates = _velocities(x, T, amax, jmax)
    corner, s = _corner(np.diff(v[:, 0]), amax, jmax)
    w = rates[:, 0]
    banded = np.zeros((3, target.size))
    banded[0, 1:] = (s * w[1:])[:-1]
    banded[1] = 1.0 - s * (w[:-1] + w[1:])
    banded[2, :-1] = (s * w[:-1])[1:]
    return x[1:-1, 0] + corner - target, banded


def _pass_through(
    q: FloatArray,
    T: FloatArray,
    v_limit: FloatArray,
    a_limit: FloatArray,
    j_limit: FloatArray | None,
    fixed: bool,
) -> tuple[FloatArray, FloatArray]:
    """Pseudo waypoints and durations with which the plan passes every waypoint.

    With ``fixed`` durations only the points move. Otherwise the durations only
    grow, so the search cannot oscillate (re-planning the shortest schedule for
    every new set of points did): when the points found need longer segments,
    the next try uses the shortest schedule that fits them, starting from the
    current one; when the points could not be placed, every segment also grows
    by at least 5 %.
    """
    for _ in range(_LENGTHEN):
        pseudo, converged = _pseudo_waypoints(q, T, a_limit, j_limit)
        if converged is None or not np.all(np.isfinite(T)):
            raise _out_of_range(q, v_limit, a_limit)
        problem = _shortfall(pseudo, T, v_limit, a_limit, j_limit) if converged else None
        if converged and problem is None:
            return pseudo, T
        if fixed:
            reason = (
                f"with them {problem}" if problem else "no such points exist for these durations"
            )
            raise InfeasibleError(
                "could not place pseudo via points so the motion passes through every "
                f"waypoint within the limits ({reason}); give longer durations"
            )
        longer = _schedule(pseudo, v_limit, a_limit, j_limit, start=T)
        # Points that were not placed are no measure of what is needed: grow by at
        # least 5 % then, so that the search ends in a few dozen tries.
        T = longer if converged else np.maximum(longer, 1.05 * T)
    raise InfeasibleError(
        "could not place pseudo via points so the motion passes through every waypoint "
        "within the limits; give durations"
    )


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
        Time (s) between consecutive waypoints. By default each segment starts
        at the shortest it can be alone (its velocity limit; at the ends, its
        start or stop) and the segments whose blends do not fit are lengthened
        until they do, so every limit holds (two lengthening rules are tried and
        the shorter schedule kept; with coupled blends this is a short schedule,
        not a global optimum). With two waypoints it is the time-optimal
        rest-to-rest move: the trapezoid's, or with ``jmax`` the S-curve's.
    through : bool
        Pass exactly through the interior waypoints. The blends cut the corners,
        so each interior waypoint is replaced by a pseudo waypoint pushed outwards
        until the blend passes the real one at its time (Craig's pseudo via
        points; found by Newton's method for the given durations). Without
        ``durations`` the schedule is lengthened, never shortened, until such
        points exist within the limits.

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
        Given durations too short for the limits: the message names the first
        segment shorter than it needs alone and that minimum, or, when each is
        long enough alone, the first one whose blends overlap and the time they
        need. With ``through``, durations for which no pseudo waypoints keep the
        limits. Steps and limits whose times or speeds float64 cannot hold.
    """
    q = finite_array("waypoints", waypoints, unit="rad")
    through = flag("through", through)
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
    # Extreme steps and limits (1e-300, 1e308) overflow or underflow on the way; no
    # warnings then, the result is checked for what it must be instead.
    with np.errstate(all="ignore"):
        trajectory, details, targets, segment_durations = _plan(
            q, v_limit, a_limit, j_limit, given, through and n > 2
        )
    deviation = details["via_position"] - q
    info = {
        "planner": "blended",
        "continuity": 1 if j_limit is None else 2,
        "jerk_limited": j_limit is not None,
        "through": through,
        "times": tuple(float(x) for x in details["times"]),
        "durations": tuple(float(x) for x in segment_durations),
        "segment_velocities": details["velocities"],
        "blend_times": details["blends"],
        "pseudo_waypoints": targets if through else None,
        "via_deviation": deviation,
        "via_distance": _norms(deviation),
    }
    # Exact boundary states: at rest at the first and last waypoints (and, jerk-limited,
    # at zero acceleration); the pieces' own end velocity is a residue such as -8e-11.
    rows = 2 if j_limit is None else 3
    start, end = np.zeros((rows, ndof)), np.zeros((rows, ndof))
    start[0], end[0] = q[0], q[-1]
    try:
        return Trajectory(
            trajectory.breakpoints, trajectory.coefficients, info=info, start=start, end=end
        )
    except InvalidInputError:
        # Pieces that do not start or end at rest to float64's resolution: a blend of
        # 1e-303 s (vmax = amax = 1e300) vanishes beside its 1e-9 s segment.
        if _extreme(q, v_limit, a_limit, trajectory.duration):
            raise _out_of_range(q, v_limit, a_limit) from None
        raise


def _build(
    q: FloatArray, T: FloatArray, a_limit: FloatArray, j_limit: FloatArray | None
) -> tuple[Trajectory, dict[str, FloatArray]]:
    """Phase plan of every joint, and the positions at the waypoint times."""
    n, ndof = q.shape
    v, blends, _, _ = _velocities(q, T, a_limit, j_limit)
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


def _verify(
    trajectory: Trajectory,
    details: dict[str, FloatArray],
    q: FloatArray,
    through: bool,
    v_limit: FloatArray,
    a_limit: FloatArray,
) -> None:
    """Refuse a plan that would look right and be wrong.

    It must keep its limits (exact extrema), land on the last waypoint and, with
    ``through``, pass the interior ones.
    """
    velocity, acceleration = trajectory.extrema(1).peak, trajectory.extrema(2).peak
    end = trajectory.position(trajectory.duration)
    # A failed check below is then the arithmetic's, not a planning defect.
    extreme = _extreme(q, v_limit, a_limit, trajectory.duration)
    finite = np.all(np.isfinite(velocity)) and np.all(np.isfinite(acceleration))
    if not (finite and np.all(np.isfinite(end))):
        raise _out_of_range(q, v_limit, a_limit)
    # Written so that NaN fails them too.
    if not (
        np.all(velocity <= v_limit * (1 + LIMIT_RTOL))
        and np.all(acceleration <= a_limit * (1 + LIMIT_RTOL))
    ):
        if extreme:
            raise _out_of_range(q, v_limit, a_limit)
        raise InfeasibleError(
            "the blends do not fit the given durations within the limits; give longer durations"
        )
    # Rounding: of positions of size |q|, and of the velocity after every blend (of
    # the size of the peak velocity) carried through the whole duration.
    scale = float(np.max(np.abs(q))) + float(np.max(velocity)) * trajectory.duration
    miss = np.abs(details["via_position"][1:-1] - q[1:-1]) if through else np.zeros(1)
    worst = max(float(np.max(np.abs(end - q[-1]))), float(np.max(miss) / 100.0))
    if not worst <= 1e-12 * scale:
        if extreme:
            raise _out_of_range(q, v_limit, a_limit)
        raise InfeasibleError(
            f"the blends miss the waypoints they must reach by {worst:.3g} rad, beyond "
            f"rounding ({1e-12 * scale:.3g} rad): trajkit cannot plan this move "
            "(please report it)"
        )
