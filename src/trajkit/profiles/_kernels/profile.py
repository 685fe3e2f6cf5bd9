"""Checking a candidate one-axis profile, integrating its states, and queries on it.

A law proposes seven phase durations ``t`` (written into the record); a ``check``
function fills in the jerks by the control signs, integrates the states at the
phase edges and accepts the profile only if it reaches the target state and keeps
every limit. The tolerances are those of the reference implementation; callers
refine the accepted profile further where they promise more.
"""

import math

import numpy as np
from numba import njit

from trajkit.profiles._kernels.layout import (
    ACC0,
    ACC0_ACC1,
    ACC0_ACC1_VEL,
    ACC0_VEL,
    ACC1,
    ACC1_VEL,
    AF,
    BRAKE_A,
    BRAKE_DURATION,
    BRAKE_J,
    BRAKE_P,
    BRAKE_T,
    BRAKE_V,
    DIRECTION,
    DOWN,
    LIMITS,
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
from trajkit.profiles._kernels.roots import solve_cubic

V_EPS = 1e-12
A_EPS = 1e-12
J_EPS = 1e-12
P_PRECISION = 1e-8
V_PRECISION = 1e-8
A_PRECISION = 1e-10
T_MAX = 1e12
EPS = 2.220446049250313e-16
#: A common duration within this (s, absolute, as in the reference) of the duration
#: of one of a joint's step-1 profiles reuses that profile as it is: the joint may
#: then reach its target state up to this much before the common duration.
REUSE_WITHIN = 2.0 * EPS


@njit(cache=True, error_model="numpy")
def new_profile():
    """An empty record (all zero: no brake, at rest)."""
    return np.zeros(SIZE)


@njit(cache=True, error_model="numpy")
def integrate(t, p0, v0, a0, j):
    """State after ``t`` s of constant jerk ``j`` from ``(p0, v0, a0)``."""
    return (
        p0 + t * (v0 + t * (a0 / 2.0 + t * j / 6.0)),
        v0 + t * (a0 + t * j / 2.0),
        a0 + j * t,
    )


@njit(cache=True, error_model="numpy")
def set_boundary(prof, p0, v0, a0, pf, vf, af):
    """Start and target state of a position move."""
    prof[P] = p0
    prof[V] = v0
    prof[A] = a0
    prof[PF] = pf
    prof[VF] = vf
    prof[AF] = af


@njit(cache=True, error_model="numpy")
def copy_boundary(dst, src):
    """Start, target and brake pre-profile of ``src`` into ``dst``."""
    dst[P] = src[P]
    dst[V] = src[V]
    dst[A] = src[A]
    dst[PF] = src[PF]
    dst[VF] = src[VF]
    dst[AF] = src[AF]
    for k in range(BRAKE_DURATION, BRAKE_P + 2):
        dst[k] = src[k]


@njit(cache=True, error_model="numpy")
def duration(prof):
    """Total duration: the brake pre-profile plus the seven phases (s)."""
    return prof[T_SUM + 6] + prof[BRAKE_DURATION]


@njit(cache=True, error_model="numpy")
def _running_sums(prof):
    """Fill ``t_sum``; False if a duration is negative or the total absurd."""
    total = 0.0
    for i in range(7):
        if prof[T + i] < 0.0:
            return False
        total += prof[T + i]
        prof[T_SUM + i] = total
    return total <= T_MAX


@njit(cache=True, error_model="numpy")
def _set_jerks(prof, signs, jf):
    """Jerks of the seven phases by the control signs (zero on empty phases)."""
    third = -jf if signs == UDDU else jf
    pattern = (jf, 0.0, -jf, 0.0, third, 0.0, -third)
    for i in range(7):
        prof[J + i] = pattern[i] if prof[T + i] > 0.0 else 0.0


@njit(cache=True, error_model="numpy")
def _velocity_bounds(direction_limit, v_max, v_min):
    """(upper, lower) velocity bounds with slack, by the direction of the profile."""
    if direction_limit > 0.0:
        return v_max + V_EPS, v_min - V_EPS
    return v_min + V_EPS, v_max - V_EPS


@njit(cache=True, error_model="numpy")
def check(prof, signs, limits, jf, v_max, v_min, a_max, a_min, set_limits=False):
    """Accept a jerk-limited position profile (third order).

    ``limits`` names the limits the law assumes reached: phases that hold a limit
    must be non-empty. With ``set_limits``, accelerations that sit on a limit are
    set to it exactly (they are by construction, up to rounding).
    """
    if not _running_sums(prof):
        return False
    if limits == ACC0_ACC1_VEL or limits == ACC0_VEL or limits == ACC1_VEL or limits == VEL:
        if prof[T + 3] < EPS:
            return False
    if limits == ACC0 or limits == ACC0_ACC1:
        if prof[T + 1] < EPS:
            return False
    if limits == ACC1 or limits == ACC0_ACC1:
        if prof[T + 5] < EPS:
            return False
    _set_jerks(prof, signs, jf)
    up = v_max > 0.0
    prof[DIRECTION] = UP if up else DOWN
    v_upp, v_low = _velocity_bounds(v_max, v_max, v_min)
    coasts = (
        limits == ACC0_ACC1_VEL
        or limits == ACC0_ACC1
        or limits == ACC0_VEL
        or limits == ACC1_VEL
        or limits == VEL
    )
    for i in range(7):
        t = prof[T + i]
        j = prof[J + i]
        a = prof[A + i]
        v = prof[V + i]
        p = prof[P + i]
        prof[A + i + 1] = a + t * j
        prof[V + i + 1] = v + t * (a + t * j / 2.0)
        prof[P + i + 1] = p + t * (v + t * (a / 2.0 + t * j / 6.0))
        if coasts and i == 2:
            prof[A + 3] = 0.0
        if set_limits:
            if limits == ACC1 and i == 2:
                prof[A + 3] = a_min
            if limits == ACC0_ACC1:
                if i == 0:
                    prof[A + 1] = a_max
                if i == 4:
                    prof[A + 5] = a_min
        # A velocity extremum inside a phase whose acceleration changes sign.
        if i > 1 and prof[A + i + 1] * prof[A + i] < -EPS:
            v_a_zero = prof[V + i] - prof[A + i] * prof[A + i] / (2.0 * prof[J + i])
            if not (v_low <= v_a_zero <= v_upp):
                return False
    prof[SIGNS] = signs
    prof[LIMITS] = limits
    a_upp = (a_max if up else a_min) + A_EPS
    a_low = (a_min if up else a_max) - A_EPS
    if not (
        abs(prof[P + 7] - prof[PF]) < P_PRECISION
        and abs(prof[V + 7] - prof[VF]) < V_PRECISION
        and abs(prof[A + 7] - prof[AF]) < A_PRECISION
    ):
        return False
    for k in (1, 3, 5):
        if not (a_low <= prof[A + k] <= a_upp):  # NaN fails too
            return False
    # The start may be beyond the velocity limit (a brake pre-profile handles that).
    for k in (3, 4, 5, 6):
        if not (v_low <= prof[V + k] <= v_upp):  # NaN fails too
            return False
    return True


@njit(cache=True, error_model="numpy")
def check_with_timing(prof, signs, limits, jf, v_max, v_min, a_max, a_min, j_max):
    """:func:`check` for a profile of prescribed duration, whose jerk is an unknown."""
    # ``<=`` too: for j_max >= 2**14 the slack vanishes in rounding and a jerk exactly
    # at the limit must still pass.
    return (abs(jf) < abs(j_max) + J_EPS or abs(jf) <= abs(j_max)) and check(
        prof, signs, limits, jf, v_max, v_min, a_max, a_min, False
    )


@njit(cache=True, error_model="numpy")
def check_second_order(prof, signs, limits, a_up, a_down, v_max, v_min):
    """Accept an acceleration-limited position profile (second order, jerk unbounded).

    Phases have constant acceleration ``a_up`` or ``a_down`` (stored in ``a[i]``
    as the acceleration *during* phase i; ``a[7]`` is the target acceleration).
    """
    if not _running_sums(prof):
        return False
    for i in range(7):
        prof[J + i] = 0.0
    third = a_down if signs == UDDU else a_up
    pattern = (a_up, 0.0, a_down, 0.0, third, 0.0, a_up if signs == UDDU else a_down)
    for i in range(7):
        prof[A + i] = pattern[i] if prof[T + i] > 0.0 else 0.0
    prof[A + 7] = prof[AF]
    up = v_max > 0.0
    prof[DIRECTION] = UP if up else DOWN
    v_upp, v_low = _velocity_bounds(v_max, v_max, v_min)
    for i in range(7):
        t = prof[T + i]
        a = prof[A + i]
        v = prof[V + i]
        prof[V + i + 1] = v + t * a
        prof[P + i + 1] = prof[P + i] + t * (v + t * a / 2.0)
    prof[SIGNS] = signs
    prof[LIMITS] = limits
    if not (
        abs(prof[P + 7] - prof[PF]) < P_PRECISION and abs(prof[V + 7] - prof[VF]) < V_PRECISION
    ):
        return False
    for k in range(2, 7):
        if not (v_low <= prof[V + k] <= v_upp):  # NaN fails too
            return False
    return True


@njit(cache=True, error_model="numpy")
def check_second_order_with_timing(prof, signs, limits, a_up, a_down, v_max, v_min, a_max, a_min):
    """:func:`check_second_order` with the accelerations as unknowns (bounded)."""
    return (
        a_min - A_EPS < a_up < a_max + A_EPS
        and a_min - A_EPS < a_down < a_max + A_EPS
        and check_second_order(prof, signs, limits, a_up, a_down, v_max, v_min)
    )


@njit(cache=True, error_model="numpy")
def check_velocity(prof, signs, limits, jf, a_max, a_min):
    """Accept a jerk-limited velocity-interface profile (no position target)."""
    if not _running_sums(prof):
        return False
    if limits == ACC0 and prof[T + 1] < EPS:
        return False
    _set_jerks(prof, signs, jf)
    for i in range(7):
        t = prof[T + i]
        j = prof[J + i]
        a = prof[A + i]
        v = prof[V + i]
        prof[A + i + 1] = a + t * j
        prof[V + i + 1] = v + t * (a + t * j / 2.0)
        prof[P + i + 1] = prof[P + i] + t * (v + t * (a / 2.0 + t * j / 6.0))
    prof[SIGNS] = signs
    prof[LIMITS] = limits
    up = a_max > 0.0
    prof[DIRECTION] = UP if up else DOWN
    a_upp = (a_max if up else a_min) + A_EPS
    a_low = (a_min if up else a_max) - A_EPS
    if not (
        abs(prof[V + 7] - prof[VF]) < V_PRECISION and abs(prof[A + 7] - prof[AF]) < A_PRECISION
    ):
        return False
    for k in (1, 3, 5):
        if not (a_low <= prof[A + k] <= a_upp):  # NaN fails too
            return False
    return True


@njit(cache=True, error_model="numpy")
def check_velocity_with_timing(prof, signs, limits, jf, a_max, a_min, j_max):
    """:func:`check_velocity` with the jerk as an unknown (bounded by ``j_max``)."""
    return (abs(jf) < abs(j_max) + J_EPS or abs(jf) <= abs(j_max)) and check_velocity(
        prof, signs, limits, jf, a_max, a_min
    )


@njit(cache=True, error_model="numpy")
def check_second_order_velocity(prof, signs, limits, a_up):
    """Accept an acceleration-limited velocity-interface profile: one phase at ``a_up``."""
    if prof[T + 1] < 0.0:
        return False
    for i in range(7):
        prof[T_SUM + i] = 0.0 if i == 0 else prof[T + 1]
        prof[J + i] = 0.0
    if prof[T_SUM + 6] > T_MAX:
        return False
    for i in range(7):
        prof[A + i] = 0.0
    prof[A + 1] = a_up if prof[T + 1] > 0.0 else 0.0
    prof[A + 7] = prof[AF]
    for i in range(7):
        t = prof[T + i]
        prof[V + i + 1] = prof[V + i] + t * prof[A + i]
        prof[P + i + 1] = prof[P + i] + t * (prof[V + i] + t * prof[A + i] / 2.0)
    prof[SIGNS] = signs
    prof[LIMITS] = limits
    prof[DIRECTION] = UP if a_up > 0.0 else DOWN
    return abs(prof[V + 7] - prof[VF]) < V_PRECISION


@njit(cache=True, error_model="numpy")
def check_second_order_velocity_with_timing(prof, signs, limits, a_up, a_max, a_min):
    """:func:`check_second_order_velocity` with ``a_up`` as an unknown (bounded)."""
    return a_min - A_EPS < a_up < a_max + A_EPS and check_second_order_velocity(
        prof, signs, limits, a_up
    )


@njit(cache=True, error_model="numpy")
def state_at(prof, time):
    """Position, velocity, acceleration and jerk at ``time`` s after the start.

    Past the end the target state continues with constant velocity (and the
    target acceleration held, as the last phase leaves it).
    """
    t = time
    brake_duration = prof[BRAKE_DURATION]
    if brake_duration > 0.0 and t < brake_duration:
        k = 0
        if t >= prof[BRAKE_T]:
            t -= prof[BRAKE_T]
            k = 1
        p, v, a = integrate(
            t, prof[BRAKE_P + k], prof[BRAKE_V + k], prof[BRAKE_A + k], prof[BRAKE_J + k]
        )
        return p, v, a, prof[BRAKE_J + k]
    t -= brake_duration
    start = 0.0
    for i in range(7):
        end = prof[T_SUM + i]
        if t < end:
            p, v, a = integrate(t - start, prof[P + i], prof[V + i], prof[A + i], prof[J + i])
            return p, v, a, prof[J + i]
        start = end
    p, v, a = integrate(t - start, prof[P + 7], prof[V + 7], prof[A + 7], 0.0)
    return p, v, a, 0.0


@njit(cache=True, error_model="numpy")
def finalize_brake(prof):
    """Integrate the brake pre-profile; the seven phases start where it ends.

    Expects the start state in ``p[0], v[0], a[0]`` and the brake's phase
    durations and jerks; writes the brake's start states and total duration and
    moves the main profile's start to the brake's end.
    """
    t0 = prof[BRAKE_T]
    t1 = prof[BRAKE_T + 1]
    if t0 <= 0.0 and t1 <= 0.0:
        prof[BRAKE_DURATION] = 0.0
        return
    ps, vs, as_ = prof[P], prof[V], prof[A]
    prof[BRAKE_DURATION] = t0
    prof[BRAKE_P] = ps
    prof[BRAKE_V] = vs
    prof[BRAKE_A] = as_
    ps, vs, as_ = integrate(t0, ps, vs, as_, prof[BRAKE_J])
    if t1 > 0.0:
        prof[BRAKE_DURATION] += t1
        prof[BRAKE_P + 1] = ps
        prof[BRAKE_V + 1] = vs
        prof[BRAKE_A + 1] = as_
        ps, vs, as_ = integrate(t1, ps, vs, as_, prof[BRAKE_J + 1])
    prof[P] = ps
    prof[V] = vs
    prof[A] = as_


@njit(cache=True, error_model="numpy")
def finalize_brake_second_order(prof):
    """:func:`finalize_brake` for an acceleration-limited brake (one constant-a phase).

    The brake's acceleration is stored in ``brake.a[0]``.
    """
    t0 = prof[BRAKE_T]
    if t0 <= 0.0:
        prof[BRAKE_DURATION] = 0.0
        return
    prof[BRAKE_DURATION] = t0
    prof[BRAKE_P] = prof[P]
    prof[BRAKE_V] = prof[V]
    ps, vs, _ = integrate(t0, prof[P], prof[V], prof[BRAKE_A], 0.0)
    prof[P] = ps
    prof[V] = vs


@njit(cache=True, error_model="numpy")
def first_time_at_position(prof, position, time_after):
    """First time (s, from the start of the seven phases) the profile passes ``position``.

    Only times ``>= time_after`` count. Returns -1.0 where it never does.
    """
    t_cum = 0.0
    roots = np.empty(3)
    for i in range(7):
        ti = prof[T + i]
        if ti == 0.0:
            continue
        if abs(prof[P + i] - position) < EPS and t_cum >= time_after:
            return t_cum
        count = solve_cubic(
            prof[J + i] / 6.0, prof[A + i] / 2.0, prof[V + i], prof[P + i] - position, roots
        )
        best = math.inf
        for k in range(count):
            r = roots[k]
            if 0.0 < r and time_after - t_cum <= r and r <= ti and r < best:
                best = r
        if best < math.inf:
            return best + t_cum
        t_cum += ti
    total = prof[T_SUM + 6]
    if (
        (prof[T + 6] > 0.0 or total == 0.0)
        and abs(prof[PF] - position) < 1e-9
        and total >= time_after
    ):
        return total
    return -1.0


@njit(cache=True, error_model="numpy")
def set_phase_times(prof, t0, t1, t2, t3, t4, t5, t6):
    """Write the seven phase durations of a candidate."""
    prof[T] = t0
    prof[T + 1] = t1
    prof[T + 2] = t2
    prof[T + 3] = t3
    prof[T + 4] = t4
    prof[T + 5] = t5
    prof[T + 6] = t6


@njit(cache=True, error_model="numpy")
def set_times(prof, t0, t1, t2, t6):
    """Write a candidate's phase durations 0, 1, 2 and 6; phases 3 to 5 stay empty."""
    prof[T] = t0
    prof[T + 1] = t1
    prof[T + 2] = t2
    prof[T + 3] = 0.0
    prof[T + 4] = 0.0
    prof[T + 5] = 0.0
    prof[T + 6] = t6


@njit(cache=True, error_model="numpy")
def no_blocks(block_times):
    """Mark both blocked intervals absent (a single profile blocks nothing)."""
    for k in range(1, 5):
        block_times[k] = math.inf


@njit(cache=True, error_model="numpy")
def round_up(t, dt):
    """``t`` rounded up to a whole number of periods ``dt`` (exact multiples stay)."""
    remainder = np.fmod(t, dt)
    if remainder > EPS:
        # Never below t: a remainder of nearly dt (t a multiple but for rounding)
        # would otherwise round t down, below the joint's own minimum.
        return max(t, t + dt - remainder)
    return t


@njit(cache=True, error_model="numpy")
def power_of_two(x):
    """The power of two nearest ``x`` (1 for ``x`` zero, negative or not finite).

    Rescaling by a power of two is exact, subnormal ones included, so a length down
    to the smallest subnormal (2**-1074) gets a unit in which it is ordinary.
    """
    if not (x > 0.0) or not math.isfinite(x):
        return 1.0
    _, exponent = math.frexp(x)
    return math.ldexp(1.0, max(-1074, min(1000, exponent - 1)))
