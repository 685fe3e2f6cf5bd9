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

import numpy as np
from numba import njit

from trajkit.profiles._kernels.jerk_fastest import calculate_block
from trajkit.profiles._kernels.layout import (
    ACC0,
    AF,
    BRAKE_DURATION,
    DIRECTION,
    DOWN,
    LIMITS,
    NONE,
    PF,
    SIGNS,
    SIZE,
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
    keep,
    power_of_two,
    set_times,
    single_profile,
)


@njit(cache=True, error_model="numpy")
def _accept(valid, count, limits, a_up, a_down, v_max, v_min):
    """Check the candidate in ``valid[count]``; return the new number of profiles (:func:`keep`)."""
    row = valid[count]
    if not check_second_order(row, UDDU, limits, a_up, a_down, v_max, v_min):
        return count
    if row[T_SUM + 6] == 0.0 and (row[PF] != row[P] or row[VF] != row[V]):
        # No time to change the state: a rounding of a ramp to nothing, which the
        # position tolerance (1e-8 absolute) would accept as reaching the target.
        # Unless no time can: a change of velocity of 5e-324 rad/s takes less than
        # the smallest positive duration at any finite acceleration.
        push = max(abs(a_up), abs(a_down))
        if not (row[PF] == row[P] and abs(row[VF] - row[V]) / push == 0.0):
            return count
    return keep(valid, count)


# --------------------------------------------------------------------------- robustness
#
# The reference's closed forms are exact in exact arithmetic, but its acceptance
# tolerances are absolute (1e-8 in position): a long coast at a low speed, or a
# duration that dwarfs the ramps, lose the target to rounding (ruckig fails
# there too). Where the reference's candidates all fail, the same profiles are
# built again in units in which the problem's magnitudes are near 1 (powers of
# two, so the change of units is exact), with stable root formulas, and each is
# corrected by the position its record misses before it is checked. Accepted
# reference profiles of a given duration get the same correction (their duration
# is the prescribed one: only where the peak velocity sits moves, by rounding).


@njit(cache=True, error_model="numpy")
def _scalable(limit, factor):
    """Whether ``limit`` stays a usable number in units scaled by ``factor``.

    Zero and infinite limits do; a finite one must not under- or overflow (a unit
    of 1e-200 s makes 1 rad/s^2 a zero, and the laws would divide by it).
    """
    if limit == 0.0 or math.isinf(limit):
        return True
    return 1e-300 < abs(limit * factor) < 1e300


@njit(cache=True, error_model="numpy")
def _units(duration, size, v_max, v_min, a_max, a_min):
    """Units of time ``tau`` and length ``lam`` (powers of two) near a move's own.

    ``(1, 1)`` where a limit would leave the range of normal numbers.
    """
    tau = power_of_two(duration)
    lam = power_of_two(size)
    v = tau / lam
    a = v * tau
    if not (
        _scalable(v_max, v) and _scalable(v_min, v) and _scalable(a_max, a) and _scalable(a_min, a)
    ):
        return 1.0, 1.0
    return tau, lam


@njit(cache=True, error_model="numpy")
def _to_units(dst, src, tau, lam):
    """``src``'s boundary in units ``tau``, ``lam``, starting at position 0; no brake."""
    for k in range(SIZE):
        dst[k] = 0.0
    v = tau / lam
    dst[V] = src[V] * v
    dst[PF] = (src[PF] - src[P]) / lam
    dst[VF] = src[VF] * v
    dst[AF] = src[AF] * v * tau


@njit(cache=True, error_model="numpy")
def _from_units(dst, src, tau, lam):
    """The phases of ``src`` (units ``tau``, ``lam``, from 0) into ``dst``'s units.

    ``dst`` keeps its boundary and brake: the phases start at its ``p[0], v[0]``.
    """
    v = lam / tau
    a = v / tau
    for i in range(7):
        dst[T + i] = src[T + i] * tau
        dst[T_SUM + i] = src[T_SUM + i] * tau
        dst[J + i] = 0.0
        dst[A + i] = src[A + i] * a
    for i in range(1, 8):
        dst[V + i] = src[V + i] * v
        dst[P + i] = dst[P] + src[P + i] * lam
    dst[A + 7] = dst[AF]
    dst[LIMITS] = src[LIMITS]
    dst[SIGNS] = src[SIGNS]
    dst[DIRECTION] = src[DIRECTION]


@njit(cache=True, error_model="numpy")
def _bounds_by_direction(up, v_max, v_min):
    """Velocity limits in the order :func:`.profile.check_second_order` reads them.

    Its direction is the sign of the first: ``(v_max, v_min)`` for a profile
    that starts at ``a_max`` (when ``v_max > 0``), else ``(v_min, v_max)``.
    """
    if up and v_max > 0.0:
        return v_max, v_min
    return v_min, v_max


@njit(cache=True, error_model="numpy")
def _miss(prof, limits, a_up, a_down, v_max, v_min):
    """Integrate the record (by the check) and return the position it misses.

    NaN where a phase duration is negative (the record is then not integrated).
    """
    for i in range(7):
        if not prof[T + i] >= 0.0:
            return math.nan
    check_second_order(prof, UDDU, limits, a_up, a_down, v_max, v_min)
    return prof[PF] - prof[P + 7]


@njit(cache=True, error_model="numpy")
def _polish_coast(prof, a_up, a_down, v_max, v_min):
    """Correct the coast (phase 1) of a ramp-coast-ramp record by the missed position."""
    r = _miss(prof, ACC0, a_up, a_down, v_max, v_min)
    for _ in range(3):
        v_coast = prof[V + 1]
        if r == 0.0 or not math.isfinite(r) or v_coast == 0.0:
            return
        old = prof[T + 1]
        t_coast = old + r / v_coast
        if not t_coast >= 0.0:
            return
        prof[T + 1] = t_coast
        r_new = _miss(prof, ACC0, a_up, a_down, v_max, v_min)
        if not abs(r_new) < abs(r):
            prof[T + 1] = old
            _miss(prof, ACC0, a_up, a_down, v_max, v_min)
            return
        r = r_new


@njit(cache=True, error_model="numpy")
def _polish_ramps(prof, tf, a_up, a_down, limits, v_max, v_min):
    """Correct the peak velocity of a ramp(-coast)-ramp record by the missed position.

    The first ramp is phase 0 (at ``a_up``), the last phase 2 (at ``a_down``) or,
    ramping on in the same direction, phase 6 (at ``a_up``). With a duration
    ``tf`` the coast takes what the ramps leave and the position moves by the
    coast duration per unit of peak velocity; without (``tf = inf``) there is no
    coast and it moves by ``v_peak (1/a1 - 1/a3)``. Newton steps, kept while they
    reduce the miss.
    """
    last = 6 if prof[T + 6] > 0.0 else 2
    a1 = a_up
    a3 = a_up if last == 6 else a_down
    v0 = prof[V]
    vf = prof[VF]
    r = _miss(prof, limits, a_up, a_down, v_max, v_min)
    for _ in range(3):
        if r == 0.0 or not math.isfinite(r):
            return
        t0 = prof[T]
        t1 = prof[T + 1]
        t3 = prof[T + last]
        v_peak = v0 + a1 * t0
        slope = t1 if math.isfinite(tf) else v_peak * (1.0 / a1 - 1.0 / a3)
        if not abs(slope) > 0.0:
            return
        v_peak += r / slope
        n0 = (v_peak - v0) / a1
        n3 = (vf - v_peak) / a3
        n1 = tf - n0 - n3 if math.isfinite(tf) else 0.0
        if not (n0 >= 0.0 and n3 >= 0.0 and n1 >= 0.0):
            return
        prof[T] = n0
        prof[T + 1] = n1
        prof[T + last] = n3
        r_new = _miss(prof, limits, a_up, a_down, v_max, v_min)
        if not abs(r_new) < abs(r):
            prof[T] = t0
            prof[T + 1] = t1
            prof[T + last] = t3
            _miss(prof, limits, a_up, a_down, v_max, v_min)
            return
        r = r_new


@njit(cache=True, error_model="numpy")
def _refine_timed(prof, tf, a_up, a_down, limits, v_max, v_min):
    """:func:`_polish_ramps` on an accepted profile, which stays accepted."""
    t0 = prof[T]
    t1 = prof[T + 1]
    t2 = prof[T + 2]
    t6 = prof[T + 6]
    _polish_ramps(prof, tf, a_up, a_down, limits, v_max, v_min)
    if not check_second_order(prof, UDDU, limits, a_up, a_down, v_max, v_min):
        set_times(prof, t0, t1, t2, t6)
        check_second_order(prof, UDDU, limits, a_up, a_down, v_max, v_min)


@njit(cache=True, error_model="numpy")
def _fastest_coast(valid, count, pd, v0, vf, v_max, v_min, a_max, a_min, polish):
    """Accelerate to the velocity limit ``v_max``, coast, brake to ``vf``.

    The ramps take ``(v_max - v0)/a_max`` and ``(vf - v_max)/a_min``; the coast
    covers what the ramps leave of ``pd`` at ``v_max``. With ``polish`` (the
    fallback) the coast is corrected by the position the record misses.
    """
    if count >= valid.shape[0]:
        return count
    # (pd - ramp distances) / v_max, expanded as the reference writes it so that
    # rounding, and hence acceptance at the margins, stays alike.
    first = (a_min * v0 * v0 - a_max * vf * vf) / (2.0 * a_max * a_min * v_max)
    second = v_max * (a_max - a_min) / (2.0 * a_max * a_min)
    t_coast = first + second + pd / v_max
    if abs(t_coast) <= 16.0 * EPS * max(abs(first), abs(second), abs(pd / v_max)):
        # Terms that cancel (standing at this very limit, in the target state): the
        # coast is empty, not a rounding's worth of time (7e-13 s of 2.7e3 s terms).
        t_coast = 0.0
    set_times(valid[count], (v_max - v0) / a_max, t_coast, (vf - v_max) / a_min, 0.0)
    if not polish:
        accepted = _accept(valid, count, ACC0, a_max, a_min, v_max, v_min)
        if accepted > count:
            return accepted
    # Polished (the fallback, or the reference's record rejected): a long coast
    # loses the target to the rounding of the speed it coasts at. Found by
    # hypothesis: 5.2e6 s at 0.01 rad/s, reached 5e-15 rad/s off after braking from
    # -32 rad/s, missed by 1.03e-8 rad, so the long way round went unseen and the
    # durations below it were taken as free.
    _polish_coast(valid[count], a_max, a_min, v_max, v_min)
    return _accept(valid, count, ACC0, a_max, a_min, v_max, v_min)


@njit(cache=True, error_model="numpy")
def _fastest_peak(valid, count, pd, v0, vf, v_max, v_min, a_max, a_min, first_only, polish):
    """Accelerate at ``a_max`` to a peak velocity and at once ``a_min`` to ``vf``.

    Both ramps together cover ``pd``, which fixes the peak velocity's square:
    ``v_peak^2 = (a_max vf^2 - a_min v0^2 - 2 a_max a_min pd) / (a_max - a_min)``.
    Both signs of ``v_peak`` are candidates (the negative one overshoots
    backwards first); with ``first_only`` the search stops at the first. With
    ``polish`` (the fallback) the peak is corrected by the position the record
    misses.
    """
    if pd == 0.0 and (v0 != 0.0 or vf != 0.0):
        # The velocities alone, in a unit of their own: the squares of 1e-310 rad/s
        # underflow to 0 (scaling by a power of two leaves every other case exact).
        unit = power_of_two(max(abs(v0), abs(vf)))
        r0, rf = v0 / unit, vf / unit
        square = (a_max * rf * rf - a_min * r0 * r0) / (a_max - a_min)
        if not square >= 0.0:
            return count
        peak = unit * math.sqrt(square)
    else:
        square = (a_max * vf * vf - a_min * v0 * v0 - 2.0 * a_max * a_min * pd) / (a_max - a_min)
        if not square >= 0.0:
            return count
        peak = math.sqrt(square)
    for sign in (-1.0, 1.0):
        if count >= valid.shape[0]:
            return count
        v_peak = sign * peak
        # A peak within rounding of a boundary velocity is that velocity: its ramp is
        # empty, not a rounding's worth of time (2e-14 s at a limit it rounds past).
        if abs(v_peak - v0) <= 4.0 * EPS * max(abs(v_peak), abs(v0)):
            v_peak = v0
        elif abs(v_peak - vf) <= 4.0 * EPS * max(abs(v_peak), abs(vf)):
            v_peak = vf
        set_times(valid[count], (v_peak - v0) / a_max, 0.0, (vf - v_peak) / a_min, 0.0)
        if polish:
            _polish_ramps(valid[count], math.inf, a_max, a_min, NONE, v_max, v_min)
        before = count
        count = _accept(valid, count, NONE, a_max, a_min, v_max, v_min)
        if first_only and count > before:
            return count
    return count


@njit(cache=True, error_model="numpy")
def fastest_candidates(prof, v_max, v_min, a_max, a_min, valid, polish=False):
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
    polish : bool
        Correct each candidate by the position its record misses (the fallback;
        the reference's candidates are taken as they are).

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
        count = _fastest_peak(valid, 0, pd, v0, vf, hi_v, lo_v, hi_a, lo_a, True, polish)
        if count == 0:
            count = _fastest_coast(valid, 0, pd, v0, vf, hi_v, lo_v, hi_a, lo_a, polish)
        if count == 0:
            count = _fastest_peak(valid, 0, pd, v0, vf, lo_v, hi_v, lo_a, hi_a, True, polish)
        if count == 0:
            count = _fastest_coast(valid, 0, pd, v0, vf, lo_v, hi_v, lo_a, hi_a, polish)
        return count
    # A moving target can make an interval of durations unreachable: every
    # extremal profile is needed to find it.
    count = _fastest_peak(valid, 0, pd, v0, vf, v_max, v_min, a_max, a_min, False, polish)
    count = _fastest_peak(valid, count, pd, v0, vf, v_min, v_max, a_min, a_max, False, polish)
    count = _fastest_coast(valid, count, pd, v0, vf, v_max, v_min, a_max, a_min, polish)
    return _fastest_coast(valid, count, pd, v0, vf, v_min, v_max, a_min, a_max, polish)


@njit(cache=True, error_model="numpy")
def _zero_velocity_limits(prof, v_max, v_min, block, block_times):
    """Both velocity limits zero: only standing still (or an unchanged coast) works."""
    p_min = block[0]
    copy_boundary(p_min, prof)
    v0 = prof[V]
    if abs(prof[VF] - v0) > EPS:
        return False
    set_times(p_min, 0.0, 0.0, 0.0, 0.0)
    if abs(v0) > EPS:
        p_min[T + 3] = (prof[PF] - prof[P]) / v0
    elif abs(prof[PF] - prof[P]) >= EPS:
        return False
    if not check_second_order(p_min, UDDU, NONE, 0.0, 0.0, v_max, v_min):
        return False
    # A coast has exactly one duration.
    single_profile(block_times, p_min, abs(v0) > EPS)
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
    if calculate_block(valid, count, block, block_times) and not _lone_standstill(
        prof, block_times
    ):
        return True
    if not _fastest_fallback(prof, v_max, v_min, a_max, a_min, valid, block, block_times):
        return False
    if _lone_standstill(prof, block_times):
        # No other profile at all (the speed limit allows no coming back): every
        # longer duration is blocked.
        block_times[1] = block_times[0]
        block_times[2] = math.inf
    return True


@njit(cache=True, error_model="numpy")
def _lone_standstill(prof, block_times):
    """Already in a moving target state, and no duration found blocked.

    Every duration above zero then needs the long way round (brake, come back,
    speed up again), so the durations below it are blocked: a missing profile, not
    a free choice. The reference's closed form can lose it to rounding (a 5e6 s
    coast back at 0.01 rad/s after braking from 25 rad/s misses by 3e-8 rad).
    """
    if abs(prof[VF]) < EPS or prof[VF] != prof[V] or block_times[0] != 0.0:
        # Below EPS the target velocity counts as rest, as the candidates take it
        # (the long way round from 1e-200 rad/s takes 4e-200 s and is not sought).
        return False
    # Standing still can be the minimum and the left end of a blocked interval at
    # once; an interval of no length blocks nothing.
    for k in (1, 3):
        if not math.isinf(block_times[k]) and block_times[k + 1] > block_times[k]:
            return False
    return True


@njit(cache=True, error_model="numpy")
def _fastest_fallback(prof, v_max, v_min, a_max, a_min, valid, block, block_times):
    """The reference's candidates again, in the move's own units and polished.

    Units: the longest of the times the move needs to cover its distance at the
    speed limit, at the acceleration limit, and to change its velocity; lengths
    the distance or the velocities over that time (a long coast back at a low
    speed limit covers no more than the braking did, within those).
    """
    pd = prof[PF] - prof[P]
    v0 = prof[V]
    vf = prof[VF]
    distance = abs(pd)
    speed = min(v_max, -v_min)
    push = min(a_max, -a_min)
    change = max(abs(v0), abs(vf), abs(vf - v0))
    estimate = 0.0
    if speed > 0.0:
        estimate = distance / speed
    if push > 0.0:
        estimate = max(estimate, math.sqrt(distance / push), change / push)
    tau = power_of_two(estimate)
    tau, lam = _units(
        estimate,
        max(distance, abs(v0) * tau, abs(vf) * tau),
        v_max,
        v_min,
        a_max,
        a_min,
    )
    v = tau / lam
    a = v * tau
    work = np.empty(SIZE)
    _to_units(work, prof, tau, lam)
    count = fastest_candidates(work, v_max * v, v_min * v, a_max * a, a_min * a, valid, True)
    if not calculate_block(valid, count, block, block_times):
        return False
    brake = prof[BRAKE_DURATION]
    for k in range(3):
        work[:] = block[k]
        copy_boundary(block[k], prof)
        _from_units(block[k], work, tau, lam)
    for k in range(5):
        block_times[k] = block_times[k] * tau + brake
    return True


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
        set_times(prof, t_up, t_coast, tf - (t_up + t_coast), 0.0)
        if check_second_order(prof, UDDU, ACC0, a_max, a_min, v_max, v_min):
            _refine_timed(prof, tf, a_max, a_min, ACC0, v_max, v_min)
            return True
    # Up-coast-up: the ramps share vd/a_max, the coast takes the rest of tf,
    # and the position is linear in how the ramps split.
    h = a_max * tf - vd
    t_up = -vd * vd / (2.0 * a_max * h) + (pd - v0 * tf) / h
    t_coast = tf - vd / a_max
    set_times(prof, t_up, t_coast, 0.0, tf - (t_up + t_coast))
    if check_second_order(prof, UDDU, ACC0, a_max, a_min, v_max, v_min):
        _refine_timed(prof, tf, a_max, a_min, ACC0, v_max, v_min)
        return True
    # Coast at v0, then the whole velocity change at a_max.
    set_times(prof, 0.0, tf - vd / a_max, 0.0, vd / a_max)
    return check_second_order(prof, UDDU, ACC0, a_max, a_min, v_max, v_min)


@njit(cache=True, error_model="numpy")
def _timed_free(prof, tf, pd, v0, vf, v_max, v_min, a_max, a_min):
    """Duration ``tf`` without a limit reached: stand still, or ramp then coast.

    The ramp's acceleration is the unknown: a ramp of ``t0`` then a coast at ``vf``
    cover ``pd = vf tf - vd t0 / 2``, so ``t0 = 2 (vf tf - pd) / vd`` and the
    acceleration is ``vd / t0``, which must lie within the limits.
    """
    if abs(v0) < EPS and abs(vf) < EPS and abs(pd) < EPS:
        set_times(prof, 0.0, tf, 0.0, 0.0)
        if check_second_order(prof, UDDU, NONE, a_max, a_min, v_max, v_min):
            return True
    vd = vf - v0
    h = 2.0 * (vf * tf - pd)
    t_ramp = h / vd
    set_times(prof, t_ramp, tf - t_ramp, 0.0, 0.0)
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
    # The direction of the displacement is the likely one: try it first. A profile
    # must land relative to its own excursion: the laws' absolute precision (1e-8)
    # accepts a joint that should creep 1.6e-9 forward and back standing still.
    found = False
    for up in (pd > 0.0, not pd > 0.0):
        if up:
            hi, lo, a_hi, a_lo = v_max, v_min, a_max, a_min
        else:
            hi, lo, a_hi, a_lo = v_min, v_max, a_min, a_max
        if _timed_all(prof, tf, pd, v0, vf, hi, lo, a_hi, a_lo) and _lands(prof, tf):
            found = True
            break
    if not found:
        found = _timed_fallback(prof, tf, v_max, v_min, a_max, a_min)
    if found:
        prof[PF] = prof[P + 7]
    return found


@njit(cache=True, error_model="numpy")
def _try_ramps(row, tf, v_peak, a1, a3, v_max, v_min, a_max, a_min):
    """Accept ``row`` as ramp at ``a1`` to ``v_peak``, coast, ramp at ``a3``, in ``tf``.

    Ramp durations within rounding of zero (8 ulp of ``tf``) count as empty.
    """
    slack = 8.0 * EPS * tf
    t1 = (v_peak - row[V]) / a1
    t3 = (row[VF] - v_peak) / a3
    if not (t1 >= -slack and t3 >= -slack):
        return False
    t1 = max(t1, 0.0)
    t3 = max(t3, 0.0)
    t2 = tf - t1 - t3
    if not t2 >= -slack:
        return False
    t2 = max(t2, 0.0)
    if a1 == a3:
        a_up = a1
        a_down = a_min if a1 == a_max else a_max
        set_times(row, t1, t2, 0.0, t3)
    else:
        a_up = a1
        a_down = a3
        set_times(row, t1, t2, t3, 0.0)
    hi, lo = _bounds_by_direction(a_up == a_max, v_max, v_min)
    _polish_ramps(row, tf, a_up, a_down, ACC0, hi, lo)
    return check_second_order(row, UDDU, ACC0, a_up, a_down, hi, lo)


@njit(cache=True, error_model="numpy")
def _try_free(row, tf, t_ramp, first, v_max, v_min, a_max, a_min):
    """Accept ``row`` as one ramp of ``t_ramp`` at a free acceleration and a coast.

    The ramp comes ``first`` (then the coast is at ``vf``) or last (the coast at
    ``v0``); its acceleration must lie within the limits.
    """
    vd = row[VF] - row[V]
    if not (0.0 < t_ramp <= tf) or vd == 0.0:
        return False
    a_ramp = vd / t_ramp
    if not (a_min - 1e-12 * abs(a_min) <= a_ramp <= a_max + 1e-12 * a_max):
        return False
    a_ramp = min(max(a_ramp, a_min), a_max)
    if first:
        set_times(row, t_ramp, tf - t_ramp, 0.0, 0.0)
    else:
        set_times(row, 0.0, tf - t_ramp, 0.0, t_ramp)
    hi, lo = _bounds_by_direction(a_ramp > 0.0, v_max, v_min)
    return check_second_order(row, UDDU, NONE, a_ramp, -a_ramp, hi, lo)


@njit(cache=True, error_model="numpy")
def _keep_gentlest(best, row, speed, best_speed):
    """Copy ``row`` into ``best`` if its coast is slower; return the best speed."""
    if speed < best_speed:
        best[:] = row
        return speed
    return best_speed


# The fallback's units come from the whole motion (|vf| * tf may be 100 rad while
# the joint stays within 1e-6 rad of its target): its candidates must also land
# within this fraction of the distance they actually travel.
EXCURSION_RTOL = 1e-9


@njit(cache=True, error_model="numpy")
def _lands(row, tf):
    """Whether a candidate ends on its target relative to its own excursion.

    Or within what its velocities' rounding (8 ulp over ``tf``) explains: a coast
    velocity reached from 1e6 by a ramp is resolved to 1e-9 only.
    """
    excursion = abs(row[PF] - row[P])
    speed = 0.0
    for i in range(1, 8):
        excursion = max(excursion, abs(row[P + i] - row[P]))
        speed = max(speed, abs(row[V + i - 1]))
    tolerance = EXCURSION_RTOL * excursion + 8.0 * EPS * speed * tf
    return abs(row[P + 7] - row[PF]) <= tolerance


@njit(cache=True, error_model="numpy")
def _timed_fallback(prof, tf, v_max, v_min, a_max, a_min):
    """A profile of duration ``tf`` by stable closed forms in the move's own units.

    For each pair of ramp accelerations at the limits the peak velocity solves
    ``c2 u^2 + c1 u + c0 = 0`` (``c2 = 1/(2 a1) - 1/(2 a3)``, ``c1 = vf/a3 - v0/a1 - tf``,
    ``c0 = pd + v0^2/(2 a1) - vf^2/(2 a3)``; roots without cancellation), each root
    polished; a standstill between the ramps (``u = 0``) and one ramp at a free
    acceleration next to a coast at ``v0`` or ``vf`` complete the shapes. Of the
    valid profiles the gentlest (slowest coast) is kept, as the numpy engine did.
    """
    pd = prof[PF] - prof[P]
    v0 = prof[V]
    vf = prof[VF]
    # Lengths of a coast at a boundary velocity, else of braking from it: a joint
    # that stops, creeps back and stops again travels only the latter.
    push = min(a_max, -a_min)
    braking = max(abs(pd), (v0 * v0 + vf * vf) / push)
    for size in (max(abs(pd), abs(v0) * tf, abs(vf) * tf), braking):
        if _timed_fallback_in(prof, tf, size, v_max, v_min, a_max, a_min):
            return True
    return False


@njit(cache=True, error_model="numpy")
def _timed_fallback_in(prof, tf, size, v_max, v_min, a_max, a_min):
    """:func:`_timed_fallback` in units of time ``tf`` and of length ``size``."""
    tau, lam = _units(tf, size, v_max, v_min, a_max, a_min)
    v = tau / lam
    a = v * tau
    vu, vl, au, al = v_max * v, v_min * v, a_max * a, a_min * a
    t = tf / tau
    work = np.empty(SIZE)
    _to_units(work, prof, tau, lam)
    row = work.copy()
    best = work.copy()
    best_speed = math.inf
    pd = work[PF]
    v0 = work[V]
    vf = work[VF]
    for k in range(4):
        a1 = au if k == 0 or k == 2 else al
        a3 = al if k == 0 or k == 3 else au
        c2 = 0.5 / a1 - 0.5 / a3
        c1 = vf / a3 - v0 / a1 - t
        c0 = pd + v0 * v0 / (2.0 * a1) - vf * vf / (2.0 * a3)
        roots = (math.nan, math.nan)
        if c2 == 0.0:
            roots = (-c0 / c1, math.nan)
        else:
            disc = c1 * c1 - 4.0 * c2 * c0
            if disc < 0.0 and disc > -1e-14 * c1 * c1:
                disc = 0.0  # a double root lost to rounding
            if disc >= 0.0:
                q = -0.5 * (c1 + math.copysign(math.sqrt(disc), c1))
                roots = (q / c2, c0 / q)
        for u in roots:
            if not math.isfinite(u):
                continue
            row[:] = work
            if _try_ramps(row, t, u, a1, a3, vu, vl, au, al) and _lands(row, t):
                best_speed = _keep_gentlest(best, row, abs(row[V + 1]), best_speed)
    # Stop, stand still, start again.
    row[:] = work
    a1 = al if v0 > 0.0 else au
    a3 = au if vf > 0.0 else al
    if _try_ramps(row, t, 0.0, a1, a3, vu, vl, au, al) and _lands(row, t):
        best_speed = _keep_gentlest(best, row, 0.0, best_speed)
    vd = vf - v0
    if vd != 0.0:
        row[:] = work
        if _try_free(row, t, 2.0 * (vf * t - pd) / vd, True, vu, vl, au, al) and _lands(row, t):
            best_speed = _keep_gentlest(best, row, abs(vf), best_speed)
        row[:] = work
        if _try_free(row, t, 2.0 * (pd - v0 * t) / vd, False, vu, vl, au, al) and _lands(row, t):
            best_speed = _keep_gentlest(best, row, abs(v0), best_speed)
    if math.isinf(best_speed):
        return False
    _from_units(prof, best, tau, lam)
    return True


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
    single_profile(block_times, p_min, False)
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
