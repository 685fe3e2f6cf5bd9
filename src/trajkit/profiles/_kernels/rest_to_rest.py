"""Moves from rest to rest under symmetric limits, in closed form.

The most common problem (every joint starts and ends at rest, ``v_min = -v_max``,
``a_min = -a_max``) needs none of the general laws' case search: each joint's
fastest profile is one of four shapes (velocity and acceleration limits reached
or not) and the profile that stretches it to a longer common duration keeps the
acceleration limit and lowers the coast velocity (a quadratic), or, where the
limit is no longer reached, solves a cubic. This is what the general laws find
for these moves (the reference's first valid candidates), at a small fraction of
their cost; :func:`plan` hands a problem back (returns False) where any joint
falls outside these shapes or a closed form fails its check, and the general
laws then plan it.

The records are those of :mod:`.layout`, accepted by the same checks as the
general laws' (:func:`.profile.check`, :func:`.profile.check_second_order`).
"""

import math

from numba import njit

from trajkit.profiles._kernels import admissible as rows
from trajkit.profiles._kernels import codes
from trajkit.profiles._kernels.layout import (
    ACC0,
    ACC0_ACC1,
    ACC0_ACC1_VEL,
    NONE,
    PF,
    SIZE,
    T_SUM,
    UDDU,
    VEL,
    P,
    T,
    V,
)
from trajkit.profiles._kernels.profile import (
    check,
    check_second_order,
    round_up,
    set_boundary,
    set_phase_times,
)

_EPS = 2.220446049250313e-16


@njit(cache=True, error_model="numpy")
def applies(m, control, sync, enabled):
    """Whether every joint moves from rest to rest under symmetric finite limits.

    Phase synchronization is left to the general laws (as are, by the caller,
    magnitudes that need a change of units).
    """
    for d in range(m.shape[1]):
        if enabled[d] == 0 or control[d] != codes.POSITION or sync[d] == codes.SYNC_PHASE:
            return False
        if (
            m[rows.V0, d] != 0.0
            or m[rows.VF, d] != 0.0
            or m[rows.A0, d] != 0.0
            or m[rows.AF, d] != 0.0
        ):
            return False
        v, a = m[rows.V_MAX, d], m[rows.A_MAX, d]
        if m[rows.V_MIN, d] != -v or m[rows.A_MIN, d] != -a:
            return False
        if not (0.0 < v < math.inf and 0.0 < a < math.inf and m[rows.J_MAX, d] > 0.0):
            return False
    return True


@njit(cache=True, error_model="numpy")
def _clear(prof, p0, pf):
    for k in range(SIZE):
        prof[k] = 0.0
    set_boundary(prof, p0, 0.0, 0.0, pf, 0.0, 0.0)


@njit(cache=True, error_model="numpy")
def _times(prof, t0, t1, t2, t3):
    """Phases 0 to 3 as given and 4 to 6 their mirror image (a rest-to-rest profile)."""
    set_phase_times(prof, t0, t1, t2, t3, t2, t1, t0)


@njit(cache=True, error_model="numpy")
def _peak(prof, ramp):
    """Jerk up, down through the peak velocity in one phase, up to rest (as the reference)."""
    _times(prof, ramp, 0.0, 2.0 * ramp, 0.0)
    prof[T + 4] = 0.0


@njit(cache=True, error_model="numpy")
def _accept(prof, distance, limits, v, a, j):
    """Check a third-order (finite ``j``) or second-order record in the move's direction."""
    s = 1.0 if distance >= 0.0 else -1.0
    if math.isinf(j):
        accepted = check_second_order(prof, UDDU, limits, s * a, -s * a, s * v, -s * v)
    else:
        accepted = check(prof, UDDU, limits, s * j, s * v, -s * v, s * a, -s * a, True)
    return accepted and _lands(prof)


# A closed form lands on its target to rounding: this share of the positions' size
# (the checks' absolute 1e-8 is far looser; the pieces absorb up to 1e-12).
LANDING_RTOL = 1e-13


@njit(cache=True, error_model="numpy")
def _lands(prof):
    size = abs(prof[PF])
    for i in range(8):
        size = max(size, abs(prof[P + i]), abs(prof[V + i]) * prof[T_SUM + 6])
    return abs(prof[P + 7] - prof[PF]) <= LANDING_RTOL * size


@njit(cache=True, error_model="numpy")
def fastest(prof, p0, pf, v, a, j):
    """Write the fastest rest-to-rest profile; returns its duration (s), or -1 if rejected."""
    _clear(prof, p0, pf)
    distance = pf - p0
    d = abs(distance)
    if d == 0.0:
        _running(prof)
        return 0.0
    if math.isinf(j):
        if d >= v * v / a:  # the velocity limit is reached: ramp, coast, ramp
            ramp = v / a
            prof[T] = ramp
            prof[T + 1] = d / v - ramp
            prof[T + 2] = ramp
            limits = ACC0
        else:
            ramp = math.sqrt(d / a)
            prof[T] = ramp
            prof[T + 2] = ramp
            limits = NONE
    else:
        jerk_ramp = a / j
        if v * j >= a * a:  # a velocity ramp long enough to reach the acceleration limit
            if d >= v * (v / a + jerk_ramp):
                _times(prof, jerk_ramp, v / a - jerk_ramp, jerk_ramp, d / v - (v / a + jerk_ramp))
                limits = ACC0_ACC1_VEL
            elif d >= 2.0 * a * jerk_ramp * jerk_ramp:
                # Peak velocity w: d = w (w / a + a / j), the root without cancellation.
                w = 2.0 * d / (jerk_ramp + math.sqrt(jerk_ramp * jerk_ramp + 4.0 * d / a))
                _times(prof, jerk_ramp, w / a - jerk_ramp, jerk_ramp, 0.0)
                limits = ACC0_ACC1
            else:
                _peak(prof, (d / (2.0 * j)) ** (1.0 / 3.0))
                limits = NONE
        else:
            ramp = math.sqrt(v / j)
            if d >= 2.0 * v * ramp:
                _times(prof, ramp, 0.0, ramp, d / v - 2.0 * ramp)
                limits = VEL
            else:
                _peak(prof, (d / (2.0 * j)) ** (1.0 / 3.0))
                limits = NONE
    if not _accept(prof, distance, limits, v, a, j):
        return -1.0
    return prof[T_SUM + 6]


@njit(cache=True, error_model="numpy")
def _running(prof):
    total = 0.0
    for i in range(7):
        total += prof[T + i]
        prof[T_SUM + i] = total


@njit(cache=True, error_model="numpy")
def _stretched_cubic(d, tf, j):
    """The jerk ramp ``s`` of a profile taking ``tf`` s without an acceleration hold.

    ``s`` is the root of ``2 j s^3 - j tf s^2 + d = 0`` in ``(0, tf / 4]``.
    """
    c = d / (2.0 * j)
    # Roots of s^3 - (tf/2) s^2 + c: one negative, two in (0, tf/2) when c < tf^3/54;
    # the smaller positive one, from the trigonometric form, then Newton's polish.
    shift = tf / 6.0
    p = -tf * tf / 12.0
    q = c - tf * tf * tf / 108.0
    r = math.sqrt(-p / 3.0)
    x = 1.5 * q / (p * r)
    if not -1.0 <= x <= 1.0:
        x = max(-1.0, min(1.0, x))
    s = shift + 2.0 * r * math.cos(math.acos(x) / 3.0 - 2.0 * math.pi / 3.0)
    for _ in range(3):
        f = s * s * (s - tf / 2.0) + c
        g = s * (3.0 * s - tf)
        if g == 0.0:
            break
        step = f / g
        s -= step
        if abs(step) <= 4.0 * _EPS * s:
            break
    return s


@njit(cache=True, error_model="numpy")
def timed(prof, p0, pf, tf, v, a, j):
    """Write the rest-to-rest profile taking ``tf`` s (at least the joint's minimum).

    Returns False where the closed forms fail their check.
    """
    _clear(prof, p0, pf)
    distance = pf - p0
    d = abs(distance)
    if d == 0.0:  # stand still
        prof[T + 1 if math.isinf(j) else T + 3] = tf
        return _accept(prof, distance, NONE, v, a, j)
    if math.isinf(j):
        # Full acceleration, a lower coast velocity w: d = w (tf - w / a).
        w = 2.0 * d / (tf + math.sqrt(max(tf * tf - 4.0 * d / a, 0.0)))
        ramp = w / a
        prof[T] = ramp
        prof[T + 1] = tf - 2.0 * ramp
        # The phases sum to tf exactly (as the general law's do): an ulp off, the last
        # ramp would end an ulp early or late, 1e-4 rad/s at t = 1000 s and 1e9 rad/s^2.
        prof[T + 2] = tf - (ramp + prof[T + 1])
        return _accept(prof, distance, ACC0, v, a, j)
    jerk_ramp = a / j
    # Acceleration limit held, coast lowered: d = w (tf - w / a - a / j).
    free = tf - jerk_ramp
    disc = free * free - 4.0 * d / a
    if free > 0.0 and disc >= 0.0:
        w = 2.0 * d / (free + math.sqrt(disc))
        hold = w / a - jerk_ramp
        coast = tf - 2.0 * (w / a + jerk_ramp)
        if hold >= 0.0 and coast >= 0.0:
            _times(prof, jerk_ramp, hold, jerk_ramp, coast)
            if _accept(prof, distance, ACC0_ACC1_VEL, v, a, j):
                return True
            _clear(prof, p0, pf)
    s = _stretched_cubic(d, tf, j)
    _times(prof, s, 0.0, s, tf - 4.0 * s)
    return _accept(prof, distance, VEL, v, a, j)


@njit(cache=True, error_model="numpy")
def plan(m, sync, min_duration, dt, profiles, independent, out):
    """Plan a problem :func:`applies` to, as :func:`.synchronize.plan` does.

    Returns False (the outputs then undefined) where a closed form fails: the
    general laws plan the problem instead.
    """
    ndof = m.shape[1]
    duration = -1.0  # below any joint's: the first synchronized one is named limiting
    limiting = -1
    for d in range(ndof):
        own = fastest(
            profiles[d],
            m[rows.Q0, d],
            m[rows.QF, d],
            m[rows.V_MAX, d],
            m[rows.A_MAX, d],
            m[rows.J_MAX, d],
        )
        if own < 0.0:
            return False
        independent[d] = own
        if sync[d] == codes.SYNC_TIME or sync[d] == codes.SYNC_TIME_IF_NECESSARY:
            if own > duration:  # of joints that tie, the first is the limiting one
                duration = own
                limiting = d
    duration = max(duration, 0.0)
    discrete = dt > 0.0
    if discrete:
        duration = round_up(duration, dt)
        for d in range(ndof):  # the first whose rounded minimum is the duration
            if sync[d] != codes.SYNC_NONE and round_up(independent[d], dt) == duration:
                limiting = d
                break
    if not math.isnan(min_duration):
        floor = round_up(min_duration, dt) if discrete else min_duration
        if floor > duration:
            duration = floor
            limiting = -1
    # Joints on their own move as fast as they can; the slowest may set the duration.
    for d in range(ndof):
        if sync[d] == codes.SYNC_NONE:
            own = round_up(independent[d], dt) if discrete else independent[d]
            if own > duration:
                duration = own
                limiting = d
    out[codes.OUT_DURATION] = duration
    out[codes.OUT_LIMITING] = limiting
    out[codes.OUT_PHASE] = 0.0
    out[codes.OUT_JOINT] = -1.0
    if duration == 0.0:
        return True
    # A joint synchronized only if necessary ends at rest: it votes for the duration
    # but moves as fast as it can (and waits), as a joint on its own does.
    for d in range(ndof):
        if sync[d] == codes.SYNC_TIME:
            target = duration
        elif discrete and sync[d] == codes.SYNC_NONE:
            target = round_up(independent[d], dt)
        else:
            continue
        if abs(target - independent[d]) < 2.0 * _EPS or (d == limiting and not discrete):
            continue  # its fastest profile takes the duration
        prof = profiles[d]
        if not timed(
            prof,
            m[rows.Q0, d],
            m[rows.QF, d],
            target,
            m[rows.V_MAX, d],
            m[rows.A_MAX, d],
            m[rows.J_MAX, d],
        ):
            return False
    return True
