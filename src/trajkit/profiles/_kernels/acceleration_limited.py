"""Position moves with unbounded jerk: acceleration-limited and velocity-limited laws.

With ``jmax = inf`` the acceleration jumps, so a time-optimal one-axis move is a
trapezoid in velocity: a phase at one acceleration limit, an optional coast at
a velocity limit, a phase at the other acceleration limit (ruckig's second-order
position interface). With ``amax = inf`` as well the velocity jumps and a move is
a single coast (the first-order interface).

Phases are stored in the seven-phase record of :mod:`.layout` the way
:func:`.profile.check_second_order` reads them: phase 0 accelerates at ``a_up``,
phase 1 coasts, phase 2 accelerates at ``a_down``, phase 3 coasts, and for the
control signs UDDU phases 4 and 6 accelerate at ``a_down`` and ``a_up``. The
second-order laws use phases 0, 1, 2 and 6, the first-order law only phase 3
(its velocity jumps: ``v[3]`` is the coast velocity, the other edges zero). The
recorded ``LIMITS`` follow the reference's naming: ``ACC0`` marks ramps at the
acceleration limits with a coast between them (in step 1 a coast at a velocity
limit), ``NONE`` the others.

Each law comes as a *fastest* function (step 1: the minimum duration and the
durations the joint cannot take, passed to the shared blocked-interval logic)
and a *timed* one (step 2: a profile of a prescribed duration ``tf``).

Compiled with ``error_model="numpy"``: the closed forms divide by limits and by
differences that may be zero (zero limits are legal input); IEEE ``inf``/``nan``
then make the candidate fail its check, exactly as in the C++ reference, instead
of raising inside a compiled batch.
"""

import math

from numba import njit

from trajkit.profiles._kernels.jerk_fastest import calculate_block
from trajkit.profiles._kernels.layout import (
    ACC0,
    AF,
    DIRECTION,
    DOWN,
    LIMITS,
    NONE,
    PF,
    SIGNS,
    T_SUM,
    UDDU,
    UP,
    VEL,
    VF,
    A,
    J,
    P,
    T,
    V,
)
from trajkit.profiles._kernels.profile import (
    EPS,
    P_PRECISION,
    T_MAX,
    V_EPS,
    check_second_order,
    copy_boundary,
    duration,
)


@njit(cache=True, error_model="numpy")
def _set_times(prof, t0, t1, t2, t6):
    """Write a candidate's phase durations; phases 3 to 5 stay empty."""
    prof[T] = t0
    prof[T + 1] = t1
    prof[T + 2] = t2
    prof[T + 3] = 0.0
    prof[T + 4] = 0.0
    prof[T + 5] = 0.0
    prof[T + 6] = t6


@njit(cache=True, error_model="numpy")
def _no_blocks(block_times):
    """Mark both blocked intervals absent (a single profile blocks nothing)."""
    for k in range(1, 5):
        block_times[k] = math.inf


@njit(cache=True, error_model="numpy")
def _accept(valid, count, limits, a_up, a_down, v_max, v_min):
    """Check the candidate in ``valid[count]``; return the new number of profiles.

    An accepted profile keeps its row and the next row receives the boundary, so
    that the next candidate starts from the same state (rows are scratch).
    """
    row = valid[count]
    if not check_second_order(row, UDDU, limits, a_up, a_down, v_max, v_min):
        return count
    count += 1
    if count < valid.shape[0]:
        copy_boundary(valid[count], row)
    return count


@njit(cache=True, error_model="numpy")
def _fastest_coast(valid, count, pd, v0, vf, v_max, v_min, a_max, a_min):
    """Accelerate to the velocity limit ``v_max``, coast, brake to ``vf``.

    The ramps take ``(v_max - v0)/a_max`` and ``(vf - v_max)/a_min``; the coast
    covers what the ramps leave of ``pd`` at ``v_max``.
    """
    if count >= valid.shape[0]:
        return count
    # (pd - ramp distances) / v_max, expanded as the reference writes it so that
    # rounding, and hence acceptance at the margins, stays alike.
    t_coast = (
        (a_min * v0 * v0 - a_max * vf * vf) / (2.0 * a_max * a_min * v_max)
        + v_max * (a_max - a_min) / (2.0 * a_max * a_min)
        + pd / v_max
    )
    _set_times(valid[count], (v_max - v0) / a_max, t_coast, (vf - v_max) / a_min, 0.0)
    return _accept(valid, count, ACC0, a_max, a_min, v_max, v_min)


@njit(cache=True, error_model="numpy")
def _fastest_peak(valid, count, pd, v0, vf, v_max, v_min, a_max, a_min, first_only):
    """Accelerate at ``a_max`` to a peak velocity and at once ``a_min`` to ``vf``.

    Both ramps together cover ``pd``, which fixes the peak velocity's square:
    ``v_peak^2 = (a_max vf^2 - a_min v0^2 - 2 a_max a_min pd) / (a_max - a_min)``.
    Both signs of ``v_peak`` are candidates (the negative one overshoots
    backwards first); with ``first_only`` the search stops at the first.
    """
    square = (a_max * vf * vf - a_min * v0 * v0 - 2.0 * a_max * a_min * pd) / (a_max - a_min)
    if not square >= 0.0:
        return count
    peak = math.sqrt(square)
    for sign in (-1.0, 1.0):
        if count >= valid.shape[0]:
            return count
        v_peak = sign * peak
        _set_times(valid[count], (v_peak - v0) / a_max, 0.0, (vf - v_peak) / a_min, 0.0)
        before = count
        count = _accept(valid, count, NONE, a_max, a_min, v_max, v_min)
        if first_only and count > before:
            return count
    return count


@njit(cache=True, error_model="numpy")
def fastest_candidates(prof, v_max, v_min, a_max, a_min, valid):
    """All extremal acceleration-limited profiles; returns their number.

    Parameters
    ----------
    prof : ndarray
        Record holding the start ``p[0], v[0]`` (after any brake) and ``pf, vf``.
    v_max, v_min, a_max, a_min : float
        Limits (``v_min, a_min <= 0``).
    valid : ndarray
        Scratch ``(n, SIZE)`` with ``n >= 3``; the accepted profiles fill its first
        rows in the reference's order.

    Returns
    -------
    int
        Number of accepted profiles.
    """
    v0 = prof[V]
    vf = prof[VF]
    pd = prof[PF] - prof[P]
    copy_boundary(valid[0], prof)
    if abs(vf) < EPS:
        # Ending at rest blocks no duration (the move can always be slowed), so
        # the first profile found is the fastest; the direction of the
        # displacement is the likely one and goes first.
        if pd >= 0.0:
            hi_v, lo_v, hi_a, lo_a = v_max, v_min, a_max, a_min
        else:
            hi_v, lo_v, hi_a, lo_a = v_min, v_max, a_min, a_max
        count = _fastest_peak(valid, 0, pd, v0, vf, hi_v, lo_v, hi_a, lo_a, True)
        if count == 0:
            count = _fastest_coast(valid, 0, pd, v0, vf, hi_v, lo_v, hi_a, lo_a)
        if count == 0:
            count = _fastest_peak(valid, 0, pd, v0, vf, lo_v, hi_v, lo_a, hi_a, True)
        if count == 0:
            count = _fastest_coast(valid, 0, pd, v0, vf, lo_v, hi_v, lo_a, hi_a)
        return count
    # A moving target can make an interval of durations unreachable: every
    # extremal profile is needed to find it.
    count = _fastest_peak(valid, 0, pd, v0, vf, v_max, v_min, a_max, a_min, False)
    count = _fastest_peak(valid, count, pd, v0, vf, v_min, v_max, a_min, a_max, False)
    count = _fastest_coast(valid, count, pd, v0, vf, v_max, v_min, a_max, a_min)
    return _fastest_coast(valid, count, pd, v0, vf, v_min, v_max, a_min, a_max)


@njit(cache=True, error_model="numpy")
def _zero_velocity_limits(prof, v_max, v_min, block, block_times):
    """Both velocity limits zero: only standing still (or an unchanged coast) works."""
    p_min = block[0]
    copy_boundary(p_min, prof)
    v0 = prof[V]
    if abs(prof[VF] - v0) > EPS:
        return False
    _set_times(p_min, 0.0, 0.0, 0.0, 0.0)
    if abs(v0) > EPS:
        p_min[T + 3] = (prof[PF] - prof[P]) / v0
    elif abs(prof[PF] - prof[P]) >= EPS:
        return False
    if not check_second_order(p_min, UDDU, NONE, 0.0, 0.0, v_max, v_min):
        return False
    block_times[0] = duration(p_min)
    _no_blocks(block_times)
    if abs(v0) > EPS:
        # A coast has exactly one duration: every longer one is blocked.
        block_times[1] = block_times[0]
    return True


@njit(cache=True, error_model="numpy")
def fastest(prof, v_max, v_min, a_max, a_min, valid, block, block_times):
    """Minimum-duration acceleration-limited move and the durations it blocks.

    Parameters
    ----------
    prof : ndarray
        Record holding the start ``p[0], v[0]`` (after any brake), ``pf, vf`` and
        the brake pre-profile.
    v_max, v_min, a_max, a_min : float
        Limits (``v_min, a_min <= 0``).
    valid : ndarray
        Scratch ``(n, SIZE)``, ``n >= 3``.
    block : ndarray
        ``(3, SIZE)`` output: the fastest profile, then the profiles at the right
        ends of blocked intervals a and b.
    block_times : ndarray
        ``float64[5]`` output: ``t_min, a_left, a_right, b_left, b_right`` (``inf``
        where an interval is absent).

    Returns
    -------
    bool
        False if no profile was found.

    Notes
    -----
    ``a_max = inf`` selects the first-order law (:func:`velocity_limited_fastest`),
    as the reference does; ``valid`` is then unused.
    """
    if math.isinf(a_max):
        return velocity_limited_fastest(prof, v_max, v_min, block, block_times)
    if v_max == 0.0 and v_min == 0.0:
        return _zero_velocity_limits(prof, v_max, v_min, block, block_times)
    count = fastest_candidates(prof, v_max, v_min, a_max, a_min, valid)
    return calculate_block(valid, count, block, block_times)


@njit(cache=True, error_model="numpy")
def _timed_coast(prof, tf, pd, v0, vf, v_max, v_min, a_max, a_min):
    """Duration ``tf`` with both ramps at the limits and a coast in between.

    Three shapes in the reference's order: ramp at ``a_max``, coast, ramp at
    ``a_min`` (the coast velocity from a quadratic); ramp, coast, ramp again at
    ``a_max`` (velocity change split around the coast, linear); and coast then
    one ramp at ``a_max``.
    """
    vd = vf - v0
    # Up-coast-down: t0 + t2 = tf - t1 and a_max t0 + a_min t2 = vd; the
    # position equation then is a quadratic in the coast duration t1.
    square = (2.0 * a_max * (pd - tf * vf) - 2.0 * a_min * (pd - tf * v0) + vd * vd) / (
        a_max * a_min
    ) + tf * tf
    if square >= 0.0:
        t_coast = math.sqrt(square)
        t_up = (a_max * vd - a_max * a_min * (tf - t_coast)) / (a_max * (a_max - a_min))
        _set_times(prof, t_up, t_coast, tf - (t_up + t_coast), 0.0)
        if check_second_order(prof, UDDU, ACC0, a_max, a_min, v_max, v_min):
            return True
    # Up-coast-up: the ramps share vd/a_max, the coast takes the rest of tf,
    # and the position is linear in how the ramps split.
    h = a_max * tf - vd
    t_up = -vd * vd / (2.0 * a_max * h) + (pd - v0 * tf) / h
    t_coast = tf - vd / a_max
    _set_times(prof, t_up, t_coast, 0.0, tf - (t_up + t_coast))
    if check_second_order(prof, UDDU, ACC0, a_max, a_min, v_max, v_min):
        return True
    # Coast at v0, then the whole velocity change at a_max.
    _set_times(prof, 0.0, tf - vd / a_max, 0.0, vd / a_max)
    return check_second_order(prof, UDDU, ACC0, a_max, a_min, v_max, v_min)


@njit(cache=True, error_model="numpy")
def _timed_free(prof, tf, pd, v0, vf, v_max, v_min, a_max, a_min):
    """Duration ``tf`` without a limit reached: stand still, or ramp then coast.

    The ramp's acceleration is the unknown: a ramp of ``t0`` then a coast at ``vf``
    cover ``pd = vf tf - vd t0 / 2``, so ``t0 = 2 (vf tf - pd) / vd`` and the
    acceleration is ``vd / t0``, which must lie within the limits.
    """
    if abs(v0) < EPS and abs(vf) < EPS and abs(pd) < EPS:
        _set_times(prof, 0.0, tf, 0.0, 0.0)
        if check_second_order(prof, UDDU, NONE, a_max, a_min, v_max, v_min):
            return True
    vd = vf - v0
    h = 2.0 * (vf * tf - pd)
    t_ramp = h / vd
    _set_times(prof, t_ramp, tf - t_ramp, 0.0, 0.0)
    a_ramp = vd * vd / h
    # Only a_ramp is bounded: the a_down phase is empty. In the mirrored call
    # the bounds are swapped and so exclude every a_ramp (as in the reference).
    if not (a_min - 1e-12 < a_ramp < a_max + 1e-12):
        return False
    return check_second_order(prof, UDDU, NONE, a_ramp, -a_ramp, v_max, v_min)


@njit(cache=True, error_model="numpy")
def _timed_all(prof, tf, pd, v0, vf, v_max, v_min, a_max, a_min):
    return _timed_coast(prof, tf, pd, v0, vf, v_max, v_min, a_max, a_min) or _timed_free(
        prof, tf, pd, v0, vf, v_max, v_min, a_max, a_min
    )


@njit(cache=True, error_model="numpy")
def timed(prof, tf, v_max, v_min, a_max, a_min):
    """Acceleration-limited move of duration ``tf`` (time synchronization).

    Parameters
    ----------
    prof : ndarray
        Record holding the start ``p[0], v[0]`` (after any brake) and ``pf, vf``;
        on success it holds the profile, with ``pf`` set to the reached position.
    tf : float
        Duration of the seven phases (s), brake excluded.
    v_max, v_min, a_max, a_min : float
        Limits (``v_min, a_min <= 0``).

    Returns
    -------
    bool
        False if no profile of that duration was found.

    Notes
    -----
    ``a_max = inf`` selects the first-order law (:func:`velocity_limited_timed`).
    """
    if math.isinf(a_max):
        return velocity_limited_timed(prof, tf, v_max, v_min)
    v0 = prof[V]
    vf = prof[VF]
    pd = prof[PF] - prof[P]
    # The direction of the displacement is the likely one: try it first.
    if pd > 0.0:
        found = _timed_all(prof, tf, pd, v0, vf, v_max, v_min, a_max, a_min) or _timed_all(
            prof, tf, pd, v0, vf, v_min, v_max, a_min, a_max
        )
    else:
        found = _timed_all(prof, tf, pd, v0, vf, v_min, v_max, a_min, a_max) or _timed_all(
            prof, tf, pd, v0, vf, v_max, v_min, a_max, a_min
        )
    if found:
        prof[PF] = prof[P + 7]
    return found


@njit(cache=True, error_model="numpy")
def _check_first_order(prof, limits, v_up):
    """Accept a velocity-limited profile: one coast at ``v_up`` in phase 3.

    The velocity jumps, so ``v[3] = v_up`` and the other phase-edge velocities are
    zero (``v[7]`` the target's); only the position must match.
    """
    t = prof[T + 3]
    if t < 0.0:
        return False
    for i in range(7):
        prof[T_SUM + i] = 0.0 if i < 3 else t
        prof[J + i] = 0.0
        prof[A + i] = 0.0
        prof[V + i] = 0.0
    if not prof[T_SUM + 6] <= T_MAX:
        return False
    prof[V + 3] = v_up if t > 0.0 else 0.0
    prof[V + 7] = prof[VF]
    prof[A + 7] = prof[AF]
    for i in range(7):
        prof[P + i + 1] = prof[P + i] + prof[T + i] * prof[V + i]
    prof[SIGNS] = UDDU
    prof[LIMITS] = limits
    prof[DIRECTION] = UP if v_up > 0.0 else DOWN
    return abs(prof[P + 7] - prof[PF]) < P_PRECISION


@njit(cache=True, error_model="numpy")
def velocity_limited_fastest(prof, v_max, v_min, block, block_times):
    """Minimum-duration velocity-limited move (``amax = jmax = inf``): one coast.

    Parameters
    ----------
    prof : ndarray
        Record holding ``p[0]`` and ``pf``.
    v_max, v_min : float
        Velocity limits (``v_min <= 0``).
    block : ndarray
        ``(3, SIZE)`` output; row 0 receives the profile.
    block_times : ndarray
        ``float64[5]`` output; a coast blocks nothing longer (it can go slower).

    Returns
    -------
    bool
        False if no profile was found (a zero limit in the needed direction).
    """
    p_min = block[0]
    copy_boundary(p_min, prof)
    pd = prof[PF] - prof[P]
    v_up = v_max if pd > 0.0 else v_min
    for i in range(7):
        p_min[T + i] = 0.0
    p_min[T + 3] = pd / v_up
    if not _check_first_order(p_min, VEL, v_up):
        return False
    block_times[0] = duration(p_min)
    _no_blocks(block_times)
    return True


@njit(cache=True, error_model="numpy")
def velocity_limited_timed(prof, tf, v_max, v_min):
    """Velocity-limited move of duration ``tf``: one coast at ``pd / tf``.

    Parameters
    ----------
    prof : ndarray
        Record holding ``p[0]`` and ``pf``; on success it holds the profile.
    tf : float
        Duration (s).
    v_max, v_min : float
        Velocity limits (``v_min <= 0``).

    Returns
    -------
    bool
        False if the coast velocity breaks a limit.
    """
    v_up = (prof[PF] - prof[P]) / tf
    for i in range(7):
        prof[T + i] = 0.0
    prof[T + 3] = tf
    if not (v_min - V_EPS < v_up < v_max + V_EPS):
        return False
    return _check_first_order(prof, NONE, v_up)
