"""The velocity interface: reach a target velocity and acceleration, no target position.

Without a position target the problem drops one order: the acceleration plays the
role the velocity plays in a position move. A jerk-limited profile is a
"trapezoid in acceleration" (ramp at ``+jmax``, an optional hold at an
acceleration limit, ramp at ``-jmax``; ruckig's third-order velocity interface);
with unbounded jerk it is a single phase of constant acceleration (the
second-order velocity interface).

The record layout is that of :mod:`.layout`; jerk-limited profiles use phases 0,
1, 2 (ramp, hold, ramp) and 6 (a final ramp), the acceleration-limited one only
phase 1. Each law has a *fastest* function (step 1: minimum duration and
blocked durations) and a *timed* one (step 2: a prescribed duration ``tf``).

Compiled with ``error_model="numpy"``: the closed forms divide by limits and by
differences that may be zero; IEEE ``inf``/``nan`` then fail the candidate's
check, as in the C++ reference, instead of raising inside a compiled batch.
"""

import math

from numba import njit

from trajkit.profiles._kernels.jerk_fastest import calculate_block
from trajkit.profiles._kernels.layout import ACC0, AF, NONE, PF, UDDU, VF, A, P, T, V
from trajkit.profiles._kernels.profile import (
    EPS,
    check_second_order_velocity,
    check_second_order_velocity_with_timing,
    check_velocity,
    check_velocity_with_timing,
    copy_boundary,
    keep,
    set_times,
    single_profile,
)


@njit(cache=True, error_model="numpy")
def _accept(valid, count, limits, jf, a_max, a_min):
    """Check the candidate in ``valid[count]``; return the new number of profiles (:func:`keep`)."""
    row = valid[count]
    if not check_velocity(row, UDDU, limits, jf, a_max, a_min):
        return count
    return keep(valid, count)


@njit(cache=True, error_model="numpy")
def _fastest_hold(valid, count, a0, af, vd, a_max, a_min, j_max):
    """Ramp to the acceleration limit ``a_max``, hold it, ramp down to ``af``.

    The ramps take ``(a_max - a0)/j`` and ``(a_max - af)/j``; the hold gains at
    ``a_max`` the velocity the ramps leave of ``vd``.
    """
    if count >= valid.shape[0]:
        return count
    t_hold = (a0 * a0 + af * af) / (2.0 * a_max * j_max) - a_max / j_max + vd / a_max
    set_times(valid[count], (a_max - a0) / j_max, t_hold, (a_max - af) / j_max, 0.0)
    return _accept(valid, count, ACC0, j_max, a_max, a_min)


@njit(cache=True, error_model="numpy")
def _fastest_peak(valid, count, a0, af, vd, a_max, a_min, j_max, first_only):
    """Ramp at ``j`` to a peak acceleration and at once at ``-j`` to ``af``.

    Both ramps together gain ``vd``, which fixes the peak's square:
    ``a_peak^2 = (a0^2 + af^2)/2 + j vd``. Both signs are candidates; with
    ``first_only`` the search stops at the first accepted.
    """
    square = (a0 * a0 + af * af) / 2.0 + j_max * vd
    if not square >= 0.0:
        return count
    peak = math.sqrt(square)
    for sign in (-1.0, 1.0):
        if count >= valid.shape[0]:
            return count
        a_peak = sign * peak
        set_times(valid[count], (a_peak - a0) / j_max, 0.0, (a_peak - af) / j_max, 0.0)
        before = count
        count = _accept(valid, count, NONE, j_max, a_max, a_min)
        if first_only and count > before:
            return count
    return count


@njit(cache=True, error_model="numpy")
def jerk_fastest_candidates(prof, a_max, a_min, j_max, valid):
    """All extremal jerk-limited velocity-interface profiles; returns their number.

    Parameters
    ----------
    prof : ndarray
        Record holding ``p[0], v[0], a[0]`` (after any brake) and ``vf, af``.
    a_max, a_min, j_max : float
        Limits (``a_min <= 0``).
    valid : ndarray
        As for :func:`.acceleration_limited.fastest_candidates`.

    Returns
    -------
    int
        Number of accepted profiles.
    """
    a0 = prof[A]
    af = prof[AF]
    vd = prof[VF] - prof[V]
    copy_boundary(valid[0], prof)
    if abs(af) < EPS:
        # Ending at zero acceleration blocks no duration, so the first profile
        # found is the fastest; the direction of the velocity change goes first.
        if vd >= 0.0:
            hi_a, lo_a, j = a_max, a_min, j_max
        else:
            hi_a, lo_a, j = a_min, a_max, -j_max
        count = _fastest_peak(valid, 0, a0, af, vd, hi_a, lo_a, j, True)
        if count == 0:
            count = _fastest_hold(valid, 0, a0, af, vd, hi_a, lo_a, j)
        if count == 0:
            count = _fastest_peak(valid, 0, a0, af, vd, lo_a, hi_a, -j, True)
        if count == 0:
            count = _fastest_hold(valid, 0, a0, af, vd, lo_a, hi_a, -j)
        return count
    # A target acceleration can make an interval of durations unreachable: every
    # extremal profile is needed to find it.
    count = _fastest_peak(valid, 0, a0, af, vd, a_max, a_min, j_max, False)
    count = _fastest_peak(valid, count, a0, af, vd, a_min, a_max, -j_max, False)
    count = _fastest_hold(valid, count, a0, af, vd, a_max, a_min, j_max)
    return _fastest_hold(valid, count, a0, af, vd, a_min, a_max, -j_max)


@njit(cache=True, error_model="numpy")
def _zero_jerk_limit(prof, a_max, a_min, block, block_times):
    """``jmax = 0``: the acceleration cannot change, so only holding ``a0`` works."""
    p_min = block[0]
    copy_boundary(p_min, prof)
    a0 = prof[A]
    vd = prof[VF] - prof[V]
    if abs(prof[AF] - a0) > EPS:
        return False
    set_times(p_min, 0.0, 0.0, 0.0, 0.0)
    if abs(a0) > EPS:
        p_min[T + 3] = vd / a0
    elif abs(vd) >= EPS:
        return False
    if not check_velocity(p_min, UDDU, NONE, 0.0, a_max, a_min):
        return False
    # Holding a nonzero acceleration reaches vf at one instant only.
    single_profile(block_times, p_min, abs(a0) > EPS)
    return True


@njit(cache=True, error_model="numpy")
def jerk_fastest(prof, a_max, a_min, j_max, valid, block, block_times):
    """Minimum-duration jerk-limited velocity-interface profile and blocked durations.

    Parameters
    ----------
    prof : ndarray
        Record holding ``p[0], v[0], a[0]`` (after any brake), ``vf, af`` and the
        brake pre-profile.
    a_max, a_min, j_max : float
        Limits (``a_min <= 0``).
    valid, block, block_times : ndarray
        Scratch and outputs, as for :func:`.acceleration_limited.fastest`.

    Returns
    -------
    bool
        False if no profile was found.
    """
    if j_max == 0.0:
        return _zero_jerk_limit(prof, a_max, a_min, block, block_times)
    count = jerk_fastest_candidates(prof, a_max, a_min, j_max, valid)
    return calculate_block(valid, count, block, block_times)


@njit(cache=True, error_model="numpy")
def _timed_hold(prof, tf, a0, af, vd, a_max, a_min, j_max):
    """Duration ``tf`` with full-jerk ramps around a hold of constant acceleration.

    Three shapes in the reference's order: ramp up, hold, ramp down (the hold
    from a quadratic); ramp, hold, ramp again in the same sense (linear); and
    hold then one ramp.
    """
    ad = af - a0
    # Up-hold-down: t0 + t2 = tf - t1 and j (t0 - t2) = ad; the velocity
    # equation then is a quadratic in the hold duration t1.
    square = (-ad * ad + 2.0 * j_max * ((a0 + af) * tf - 2.0 * vd)) / (j_max * j_max) + tf * tf
    if square >= 0.0:
        t_hold = math.sqrt(square)
        t_up = ad / (2.0 * j_max) + (tf - t_hold) / 2.0
        set_times(prof, t_up, t_hold, tf - (t_up + t_hold), 0.0)
        if check_velocity(prof, UDDU, ACC0, j_max, a_max, a_min):
            return True
    # Up-hold-up: the ramps share ad/j, the hold takes the rest of tf, and the
    # velocity is linear in how the ramps split.
    h = j_max * tf - ad
    t_up = -ad * ad / (2.0 * j_max * h) + (vd - a0 * tf) / h
    t_hold = tf - ad / j_max
    set_times(prof, t_up, t_hold, 0.0, tf - (t_up + t_hold))
    if check_velocity(prof, UDDU, ACC0, j_max, a_max, a_min):
        return True
    # Hold a0, then the whole acceleration change in one ramp.
    set_times(prof, 0.0, tf - ad / j_max, 0.0, ad / j_max)
    return check_velocity(prof, UDDU, ACC0, j_max, a_max, a_min)


@njit(cache=True, error_model="numpy")
def _timed_free(prof, tf, a0, af, vd, a_max, a_min, j_max):
    """Duration ``tf`` without a limit reached: hold zero, or ramp then hold.

    The jerk is the unknown: a ramp of ``t0`` then a hold at ``af`` gain
    ``vd = af tf - ad t0 / 2``, so ``t0 = 2 (af tf - vd) / ad`` and the jerk is
    ``ad / t0``, bounded by ``jmax``.
    """
    if abs(a0) < EPS and abs(af) < EPS and abs(vd) < EPS:
        set_times(prof, 0.0, tf, 0.0, 0.0)
        if check_velocity(prof, UDDU, NONE, j_max, a_max, a_min):
            return True
    ad = af - a0
    h = 2.0 * (af * tf - vd)
    t_ramp = h / ad
    set_times(prof, t_ramp, tf - t_ramp, 0.0, 0.0)
    return check_velocity_with_timing(prof, UDDU, NONE, ad * ad / h, a_max, a_min, j_max)


@njit(cache=True, error_model="numpy")
def _timed_all(prof, tf, a0, af, vd, a_max, a_min, j_max):
    return _timed_hold(prof, tf, a0, af, vd, a_max, a_min, j_max) or _timed_free(
        prof, tf, a0, af, vd, a_max, a_min, j_max
    )


@njit(cache=True, error_model="numpy")
def jerk_timed(prof, tf, a_max, a_min, j_max):
    """Jerk-limited velocity-interface profile of duration ``tf``.

    Parameters
    ----------
    prof : ndarray
        Record holding ``p[0], v[0], a[0]`` (after any brake) and ``vf, af``; on
        success it holds the profile, with ``pf`` set to the reached position.
    tf : float
        Duration of the seven phases (s), brake excluded.
    a_max, a_min, j_max : float
        Limits (``a_min <= 0``).

    Returns
    -------
    bool
        False if no profile of that duration was found.
    """
    a0 = prof[A]
    af = prof[AF]
    vd = prof[VF] - prof[V]
    # The sense of the velocity change is the likely one: try it first.
    if vd > 0.0:
        found = _timed_all(prof, tf, a0, af, vd, a_max, a_min, j_max) or _timed_all(
            prof, tf, a0, af, vd, a_min, a_max, -j_max
        )
    else:
        found = _timed_all(prof, tf, a0, af, vd, a_min, a_max, -j_max) or _timed_all(
            prof, tf, a0, af, vd, a_max, a_min, j_max
        )
    if found:
        prof[PF] = prof[P + 7]
    return found


@njit(cache=True, error_model="numpy")
def acceleration_fastest(prof, a_max, a_min, valid, block, block_times):
    """Minimum-duration acceleration-limited velocity change: one phase at a limit.

    Parameters
    ----------
    prof : ndarray
        Record holding ``p[0], v[0]`` and ``vf``.
    a_max, a_min : float
        Acceleration limits (``a_min <= 0``).
    valid : ndarray
        Unused (one profile only); kept for a signature like the other laws'.
    block : ndarray
        ``(3, SIZE)`` output; row 0 receives the profile.
    block_times : ndarray
        ``float64[5]`` output; a constant-acceleration phase blocks nothing
        longer (a smaller acceleration takes longer).

    Returns
    -------
    bool
        False if no profile was found (a zero limit in the needed direction).
    """
    p_min = block[0]
    copy_boundary(p_min, prof)
    vd = prof[VF] - prof[V]
    a_up = a_max if vd > 0.0 else a_min
    set_times(p_min, 0.0, vd / a_up, 0.0, 0.0)
    if not check_second_order_velocity(p_min, UDDU, ACC0, a_up):
        return False
    single_profile(block_times, p_min, False)
    return True


@njit(cache=True, error_model="numpy")
def acceleration_timed(prof, tf, a_max, a_min):
    """Acceleration-limited velocity change of duration ``tf``: one phase at ``vd/tf``.

    Parameters
    ----------
    prof : ndarray
        Record holding ``p[0], v[0]`` and ``vf``; on success it holds the profile,
        with ``pf`` set to the reached position.
    tf : float
        Duration (s), brake excluded.
    a_max, a_min : float
        Acceleration limits (``a_min <= 0``).

    Returns
    -------
    bool
        False if ``vd/tf`` breaks a limit.
    """
    a_up = (prof[VF] - prof[V]) / tf
    set_times(prof, 0.0, tf, 0.0, 0.0)
    if not check_second_order_velocity_with_timing(prof, UDDU, NONE, a_up, a_max, a_min):
        return False
    prof[PF] = prof[P + 7]
    return True
