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

from trajkit.profiles._kernels import layout as L
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
    return np.zeros(L.SIZE)


@njit(cache=True, error_model="numpy")
def integrate(t, p0, v0, a0, j):
    """State after ``t`` s of constant jerk ``j`` from ``(p0, v0, a0)``."""
    return (
        p0 + t * (v0 + t * (a0 / 2.0 + t * j / 6.0)),
        v0 + t * (a0 + t * j / 2.0),
        a0 + j * t,
    )


@njit(cache=True, error_model="numpy")
def _integrate_phase(prof, i):
    """The state at the end of phase ``i`` of a jerk-limited record, from its start."""
    p, v, a = integrate(prof[L.T + i], prof[L.P + i], prof[L.V + i], prof[L.A + i], prof[L.J + i])
    prof[L.P + i + 1] = p
    prof[L.V + i + 1] = v
    prof[L.A + i + 1] = a


@njit(cache=True, error_model="numpy")
def set_boundary(prof, p0, v0, a0, pf, vf, af):
    """Start and target state of a position move."""
    prof[L.P] = p0
    prof[L.V] = v0
    prof[L.A] = a0
    prof[L.PF] = pf
    prof[L.VF] = vf
    prof[L.AF] = af


@njit(cache=True, error_model="numpy")
def copy_boundary(dst, src):
    """Start, target and brake pre-profile of ``src`` into ``dst``."""
    dst[L.P] = src[L.P]
    dst[L.V] = src[L.V]
    dst[L.A] = src[L.A]
    dst[L.PF] = src[L.PF]
    dst[L.VF] = src[L.VF]
    dst[L.AF] = src[L.AF]
    for k in range(L.BRAKE_DURATION, L.BRAKE_P + 2):
        dst[k] = src[k]


@njit(cache=True, error_model="numpy")
def keep(valid, count):
    """Keep the candidate in row ``count`` of ``valid``; return the new number of candidates.

    The next row (scratch) receives the boundary, so that the next candidate
    starts from the same state.
    """
    count += 1
    if count < valid.shape[0]:
        copy_boundary(valid[count], valid[count - 1])
    return count


@njit(cache=True, error_model="numpy")
def duration(prof):
    """Total duration: the brake pre-profile plus the seven phases (s)."""
    return prof[L.T_SUM + 6] + prof[L.BRAKE_DURATION]


@njit(cache=True, error_model="numpy")
def _running_sums(prof):
    """Fill ``t_sum``; False if a duration is negative or the total absurd."""
    total = 0.0
    for i in range(7):
        if prof[L.T + i] < 0.0:
            return False
        total += prof[L.T + i]
        prof[L.T_SUM + i] = total
    return total <= T_MAX


@njit(cache=True, error_model="numpy")
def _set_jerks(prof, signs, jf):
    """Jerks of the seven phases by the control signs (zero on empty phases)."""
    third = -jf if signs == L.UDDU else jf
    pattern = (jf, 0.0, -jf, 0.0, third, 0.0, -third)
    for i in range(7):
        prof[L.J + i] = pattern[i] if prof[L.T + i] > 0.0 else 0.0


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
    if limits == L.ACC0_ACC1_VEL or limits == L.ACC0_VEL or limits == L.ACC1_VEL or limits == L.VEL:
        if prof[L.T + 3] < EPS:
            return False
    if limits == L.ACC0 or limits == L.ACC0_ACC1:
        if prof[L.T + 1] < EPS:
            return False
    if limits == L.ACC1 or limits == L.ACC0_ACC1:
        if prof[L.T + 5] < EPS:
            return False
    _set_jerks(prof, signs, jf)
    up = v_max > 0.0
    prof[L.DIRECTION] = L.UP if up else L.DOWN
    v_upp, v_low = _velocity_bounds(v_max, v_max, v_min)
    coasts = (
        limits == L.ACC0_ACC1_VEL
        or limits == L.ACC0_ACC1
        or limits == L.ACC0_VEL
        or limits == L.ACC1_VEL
        or limits == L.VEL
    )
    for i in range(7):
        _integrate_phase(prof, i)
        if coasts and i == 2:
            prof[L.A + 3] = 0.0
        if set_limits:
            if limits == L.ACC1 and i == 2:
                prof[L.A + 3] = a_min
            if limits == L.ACC0_ACC1:
                if i == 0:
                    prof[L.A + 1] = a_max
                if i == 4:
                    prof[L.A + 5] = a_min
        # A velocity extremum inside a phase whose acceleration changes sign.
        if i > 1 and prof[L.A + i + 1] * prof[L.A + i] < -EPS:
            v_a_zero = prof[L.V + i] - prof[L.A + i] * prof[L.A + i] / (2.0 * prof[L.J + i])
            if not (v_low <= v_a_zero <= v_upp):
                return False
    prof[L.SIGNS] = signs
    prof[L.LIMITS] = limits
    a_upp = (a_max if up else a_min) + A_EPS
    a_low = (a_min if up else a_max) - A_EPS
    if not (
        abs(prof[L.P + 7] - prof[L.PF]) < P_PRECISION
        and abs(prof[L.V + 7] - prof[L.VF]) < V_PRECISION
        and abs(prof[L.A + 7] - prof[L.AF]) < A_PRECISION
    ):
        return False
    for k in (1, 3, 5):
        if not (a_low <= prof[L.A + k] <= a_upp):  # NaN fails too
            return False
    # The start may be beyond the velocity limit (a brake pre-profile handles that).
    for k in (3, 4, 5, 6):
        if not (v_low <= prof[L.V + k] <= v_upp):  # NaN fails too
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
        prof[L.J + i] = 0.0
    third = a_down if signs == L.UDDU else a_up
    pattern = (a_up, 0.0, a_down, 0.0, third, 0.0, a_up if signs == L.UDDU else a_down)
    for i in range(7):
        prof[L.A + i] = pattern[i] if prof[L.T + i] > 0.0 else 0.0
    prof[L.A + 7] = prof[L.AF]
    up = v_max > 0.0
    prof[L.DIRECTION] = L.UP if up else L.DOWN
    v_upp, v_low = _velocity_bounds(v_max, v_max, v_min)
    for i in range(7):
        t = prof[L.T + i]
        a = prof[L.A + i]
        v = prof[L.V + i]
        prof[L.V + i + 1] = v + t * a
        prof[L.P + i + 1] = prof[L.P + i] + t * (v + t * a / 2.0)
    prof[L.SIGNS] = signs
    prof[L.LIMITS] = limits
    if not (
        abs(prof[L.P + 7] - prof[L.PF]) < P_PRECISION
        and abs(prof[L.V + 7] - prof[L.VF]) < V_PRECISION
    ):
        return False
    for k in range(2, 7):
        if not (v_low <= prof[L.V + k] <= v_upp):  # NaN fails too
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
    if limits == L.ACC0 and prof[L.T + 1] < EPS:
        return False
    _set_jerks(prof, signs, jf)
    for i in range(7):
        _integrate_phase(prof, i)
    prof[L.SIGNS] = signs
    prof[L.LIMITS] = limits
    up = a_max > 0.0
    prof[L.DIRECTION] = L.UP if up else L.DOWN
    a_upp = (a_max if up else a_min) + A_EPS
    a_low = (a_min if up else a_max) - A_EPS
    if not (
        abs(prof[L.V + 7] - prof[L.VF]) < V_PRECISION
        and abs(prof[L.A + 7] - prof[L.AF]) < A_PRECISION
    ):
        return False
    for k in (1, 3, 5):
        if not (a_low <= prof[L.A + k] <= a_upp):  # NaN fails too
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
    if prof[L.T + 1] < 0.0:
        return False
    for i in range(7):
        prof[L.T_SUM + i] = 0.0 if i == 0 else prof[L.T + 1]
        prof[L.J + i] = 0.0
    if prof[L.T_SUM + 6] > T_MAX:
        return False
    for i in range(7):
        prof[L.A + i] = 0.0
    prof[L.A + 1] = a_up if prof[L.T + 1] > 0.0 else 0.0
    prof[L.A + 7] = prof[L.AF]
    for i in range(7):
        t = prof[L.T + i]
        prof[L.V + i + 1] = prof[L.V + i] + t * prof[L.A + i]
        prof[L.P + i + 1] = prof[L.P + i] + t * (prof[L.V + i] + t * prof[L.A + i] / 2.0)
    prof[L.SIGNS] = signs
    prof[L.LIMITS] = limits
    prof[L.DIRECTION] = L.UP if a_up > 0.0 else L.DOWN
    return abs(prof[L.V + 7] - prof[L.VF]) < V_PRECISION


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
    brake_duration = prof[L.BRAKE_DURATION]
    if brake_duration > 0.0 and t < brake_duration:
        k = 0
        if t >= prof[L.BRAKE_T]:
            t -= prof[L.BRAKE_T]
            k = 1
        p, v, a = integrate(
            t, prof[L.BRAKE_P + k], prof[L.BRAKE_V + k], prof[L.BRAKE_A + k], prof[L.BRAKE_J + k]
        )
        return p, v, a, prof[L.BRAKE_J + k]
    t -= brake_duration
    start = 0.0
    for i in range(7):
        end = prof[L.T_SUM + i]
        if t < end:
            p, v, a = integrate(
                t - start, prof[L.P + i], prof[L.V + i], prof[L.A + i], prof[L.J + i]
            )
            return p, v, a, prof[L.J + i]
        start = end
    p, v, a = integrate(t - start, prof[L.P + 7], prof[L.V + 7], prof[L.A + 7], 0.0)
    return p, v, a, 0.0


@njit(cache=True, error_model="numpy")
def finalize_brake(prof):
    """Integrate the brake pre-profile; the seven phases start where it ends.

    Expects the start state in ``p[0], v[0], a[0]`` and the brake's phase
    durations and jerks; writes the brake's start states and total duration and
    moves the main profile's start to the brake's end.
    """
    t0 = prof[L.BRAKE_T]
    t1 = prof[L.BRAKE_T + 1]
    if t0 <= 0.0 and t1 <= 0.0:
        prof[L.BRAKE_DURATION] = 0.0
        return
    ps, vs, as_ = prof[L.P], prof[L.V], prof[L.A]
    prof[L.BRAKE_DURATION] = t0
    prof[L.BRAKE_P] = ps
    prof[L.BRAKE_V] = vs
    prof[L.BRAKE_A] = as_
    ps, vs, as_ = integrate(t0, ps, vs, as_, prof[L.BRAKE_J])
    if t1 > 0.0:
        prof[L.BRAKE_DURATION] += t1
        prof[L.BRAKE_P + 1] = ps
        prof[L.BRAKE_V + 1] = vs
        prof[L.BRAKE_A + 1] = as_
        ps, vs, as_ = integrate(t1, ps, vs, as_, prof[L.BRAKE_J + 1])
    prof[L.P] = ps
    prof[L.V] = vs
    prof[L.A] = as_


@njit(cache=True, error_model="numpy")
def finalize_brake_second_order(prof):
    """:func:`finalize_brake` for an acceleration-limited brake (one constant-a phase).

    The brake's acceleration is stored in ``brake.a[0]``.
    """
    t0 = prof[L.BRAKE_T]
    if t0 <= 0.0:
        prof[L.BRAKE_DURATION] = 0.0
        return
    prof[L.BRAKE_DURATION] = t0
    prof[L.BRAKE_P] = prof[L.P]
    prof[L.BRAKE_V] = prof[L.V]
    ps, vs, _ = integrate(t0, prof[L.P], prof[L.V], prof[L.BRAKE_A], 0.0)
    prof[L.P] = ps
    prof[L.V] = vs


@njit(cache=True, error_model="numpy")
def first_time_at_position(prof, position, time_after):
    """First time (s, from the start of the seven phases) the profile passes ``position``.

    Only times ``>= time_after`` count. Returns -1.0 where it never does.
    """
    t_cum = 0.0
    roots = np.empty(3)
    for i in range(7):
        ti = prof[L.T + i]
        if ti == 0.0:
            continue
        if abs(prof[L.P + i] - position) < EPS and t_cum >= time_after:
            return t_cum
        count = solve_cubic(
            prof[L.J + i] / 6.0, prof[L.A + i] / 2.0, prof[L.V + i], prof[L.P + i] - position, roots
        )
        best = math.inf
        for k in range(count):
            r = roots[k]
            if 0.0 < r and time_after - t_cum <= r and r <= ti and r < best:
                best = r
        if best < math.inf:
            return best + t_cum
        t_cum += ti
    total = prof[L.T_SUM + 6]
    if (
        (prof[L.T + 6] > 0.0 or total == 0.0)
        and abs(prof[L.PF] - position) < 1e-9
        and total >= time_after
    ):
        return total
    return -1.0


@njit(cache=True, error_model="numpy")
def set_phase_times(prof, t0, t1, t2, t3, t4, t5, t6):
    """Write the seven phase durations of a candidate."""
    prof[L.T] = t0
    prof[L.T + 1] = t1
    prof[L.T + 2] = t2
    prof[L.T + 3] = t3
    prof[L.T + 4] = t4
    prof[L.T + 5] = t5
    prof[L.T + 6] = t6


@njit(cache=True, error_model="numpy")
def set_times(prof, t0, t1, t2, t6):
    """Write a candidate's phase durations 0, 1, 2 and 6; phases 3 to 5 stay empty."""
    prof[L.T] = t0
    prof[L.T + 1] = t1
    prof[L.T + 2] = t2
    prof[L.T + 3] = 0.0
    prof[L.T + 4] = 0.0
    prof[L.T + 5] = 0.0
    prof[L.T + 6] = t6


@njit(cache=True, error_model="numpy")
def single_profile(block_times, prof, drifts):
    """Block times of a law whose only profile is ``prof``: its duration, no interval.

    A profile that ``drifts`` (a coast or a held acceleration, with no time to
    spare) reaches its target at one instant only: every longer duration is
    blocked then.
    """
    block_times[0] = duration(prof)
    for k in range(1, 5):
        block_times[k] = math.inf
    if drifts:
        block_times[1] = block_times[0]


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
