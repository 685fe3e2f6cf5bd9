"""Several joints to a common end: each joint's fastest profile, then one duration for all.

Per joint (step 1): a brake pre-profile if the start state is beyond the limits,
then the fastest profile and the durations it cannot take (blocked intervals).
Then the common duration: the smallest candidate (a joint's minimum, the right end
of a blocked interval, ``min_duration``; rounded up to whole periods for discrete
durations) that no synchronized joint is blocked at. Each synchronized joint is
then re-planned to take exactly that duration (step 2), or, under phase
synchronization, follows the limiting joint's phase times scaled to its own move.

:func:`plan` solves one problem (the entry points of :mod:`.solve` run it over
batches). It writes into caller-provided arrays and return status
codes (numba raises no helpful errors); :mod:`trajkit.profiles.engine` turns
those into exceptions that name the joint and the cause.
"""

import math

import numpy as np
from numba import njit

from trajkit.profiles._kernels import (
    acceleration_limited,
    brake,
    jerk_fastest,
    jerk_timed,
    rest_to_rest,
    velocity_target,
)
from trajkit.profiles._kernels import layout as L
from trajkit.profiles._kernels.admissible import (
    A0,
    A_MAX,
    A_MIN,
    AF,
    J_MAX,
    Q0,
    QF,
    V0,
    V_MAX,
    V_MIN,
    VF,
)
from trajkit.profiles._kernels.codes import (  # noqa: F401 (the entry points' codes)
    OK,
    OUT_DURATION,
    OUT_JOINT,
    OUT_LIMITING,
    OUT_PHASE,
    OUT_SIZE,
    POSITION,
    STEP1_FAILED,
    STEP2_FAILED,
    SYNC_FAILED,
    SYNC_NONE,
    SYNC_PHASE,
    SYNC_TIME,
    SYNC_TIME_IF_NECESSARY,
    VELOCITY,
    ZERO_LIMITS,
)
from trajkit.profiles._kernels.profile import (
    REUSE_WITHIN,
    finalize_brake,
    finalize_brake_second_order,
    integrate,
    power_of_two,
    round_up,
    set_boundary,
)

_LAW = 4  # a phase-synchronized joint following the shared law (beside the SYNC_ codes)

_EPS = 2.220446049250313e-16
#: Boundary states of phase-synchronized joints count as collinear up to this (relative).
_COLLINEAR_RTOL = 1e-13


@njit(cache=True, error_model="numpy")
def _step1_raw(prof, args, valid, block, block_times):
    """Brake, then the fastest profile and blocked intervals of one joint.

    ``args`` are :func:`_step1`'s boundary, limits and control, as it packs them.
    """
    p0, v0, a0, pf, vf, af, v_max, v_min, a_max, a_min, j_max, control = args
    for k in range(L.SIZE):
        prof[k] = 0.0
    third = not math.isinf(j_max)
    if control == POSITION:
        if third:
            brake.position_brake(prof, v0, a0, v_max, v_min, a_max, a_min, j_max)
        elif not math.isinf(a_max):
            brake.second_order_position_brake(prof, v0, v_max, v_min, a_max, a_min)
    elif third:
        brake.velocity_brake(prof, a0, a_max, a_min, j_max)
    set_boundary(prof, p0, v0, a0, pf, vf, af)
    if third:
        finalize_brake(prof)
    else:
        finalize_brake_second_order(prof)
    if control == POSITION:
        if third:
            return jerk_fastest.fastest(
                prof, v_max, v_min, a_max, a_min, j_max, valid, block, block_times
            )
        return acceleration_limited.fastest(
            prof, v_max, v_min, a_max, a_min, valid, block, block_times
        )
    if third:
        return velocity_target.jerk_fastest(prof, a_max, a_min, j_max, valid, block, block_times)
    return velocity_target.acceleration_fastest(prof, a_max, a_min, valid, block, block_times)


@njit(cache=True, error_model="numpy")
def _step2_raw(prof, tf, v_max, v_min, a_max, a_min, j_max, control):
    """Re-plan one joint (its boundary and brake already in ``prof``) to take ``tf``."""
    third = not math.isinf(j_max)
    if control == POSITION:
        if third:
            return jerk_timed.timed(prof, tf, v_max, v_min, a_max, a_min, j_max)
        return acceleration_limited.timed(prof, tf, v_max, v_min, a_max, a_min)
    if third:
        return velocity_target.jerk_timed(prof, tf, a_max, a_min, j_max)
    return velocity_target.acceleration_timed(prof, tf, a_max, a_min)


# Problems whose time or length scale lies outside this range are planned in rescaled units.
_ORDINARY_LOW = 2.0**-10
_ORDINARY_HIGH = 2.0**10
# ... and planned in rescaled units first beyond this range.
_EXTREME_LOW = 2.0**-40
_EXTREME_HIGH = 2.0**40


@njit(cache=True, error_model="numpy")
def _ordinary_unit(x):
    """The power of two nearest ``x > 0`` (1 for ordinary ``x``)."""
    if _ORDINARY_LOW <= x <= _ORDINARY_HIGH:
        return 1.0
    return power_of_two(x)


@njit(cache=True, error_model="numpy")
def _units(pd, v0, a0, vf, af, v_max, v_min, a_max, a_min, j_max):
    """Units of time and length (powers of two) in which a joint's problem is ordinary.

    The laws' tolerances are absolute (1e-8 in position, 1e-12 in velocity, 2e-16 in
    time), so a move of 1e-40 rad, or one lasting a microsecond or a day, is planned
    in units where its duration and magnitudes are near 1: time ``tau`` (s), length
    ``lam``. Rescaling by powers of two is exact, and a profile's shape does not
    depend on the units. Ordinary problems keep ``(1, 1)``, as the reference plans
    them.
    """
    distance = abs(pd)
    change = max(abs(v0), abs(vf), abs(vf - v0))
    speed = min(v_max, -v_min)
    push = min(a_max, -a_min)
    duration = 0.0
    # Roots taken before the quotients: a subnormal distance over a jerk limit of 10
    # would underflow to 0 (and a huge one over a small limit overflow), losing the
    # time the move takes.
    if speed > 0.0:
        duration = max(duration, distance / speed)
    if push > 0.0:
        duration = max(duration, math.sqrt(distance) / math.sqrt(push), change / push)
    if math.isfinite(j_max) and j_max > 0.0:
        duration = max(
            duration,
            distance ** (1.0 / 3.0) / j_max ** (1.0 / 3.0),
            math.sqrt(change) / math.sqrt(j_max),
            max(abs(a0), abs(af)) / j_max,
        )
    tau = _ordinary_unit(duration)
    size = max(distance, abs(v0) * tau, abs(vf) * tau, abs(a0) * tau * tau, abs(af) * tau * tau)
    lam = _ordinary_unit(size)
    if tau == 1.0 and lam == 1.0:
        return 1.0, 1.0
    # The limits in the new units must stay finite and normal (an infinite jerk
    # limit means something else); where they would not, plan as given. Scaled by
    # exponents: tau**3 of a tiny unit underflows where the limit it scales does not.
    et = math.frexp(tau)[1] - 1
    el = math.frexp(lam)[1] - 1
    for limit in (
        math.ldexp(v_max, et - el),
        math.ldexp(-v_min, et - el),
        math.ldexp(a_max, 2 * et - el),
        math.ldexp(-a_min, 2 * et - el),
    ):
        if not (1e-300 < limit < 1e300):
            return 1.0, 1.0
    if math.isfinite(j_max) and not (1e-300 < math.ldexp(j_max, 3 * et - el) < 1e300):
        return 1.0, 1.0
    return tau, lam


@njit(cache=True, error_model="numpy")
def ordinary(m):
    """Whether every joint's problem is planned in its own units (see :func:`_units`)."""
    for d in range(m.shape[1]):
        tau, lam = _units(
            m[QF, d] - m[Q0, d],
            m[V0, d],
            m[A0, d],
            m[VF, d],
            m[AF, d],
            m[V_MAX, d],
            m[V_MIN, d],
            m[A_MAX, d],
            m[A_MIN, d],
            m[J_MAX, d],
        )
        if not (tau == 1.0 and lam == 1.0):
            return False
    return True


@njit(cache=True, error_model="numpy")
def _rescale(prof, tau, lam, origin, new_origin, inverse=False):
    """A record in units ``tau`` times and ``lam`` times larger, positions about ``origin``.

    Times are multiplied by ``tau``, lengths by ``lam`` (velocities by ``lam /
    tau``...): the same motion described in other units. ``inverse`` divides
    instead (the reciprocal of a subnormal unit would overflow).
    """
    v = lam / tau
    a = v / tau
    j = a / tau
    if inverse:
        tau, lam, v, a, j = 1.0 / tau, lam, 1.0 / v, 1.0 / a, 1.0 / j
    _scale_rates(prof, tau, v, a, j)
    for i in range(8):
        prof[L.P + i] = new_origin + _scaled(prof[L.P + i] - origin, lam, inverse)
    prof[L.PF] = new_origin + _scaled(prof[L.PF] - origin, lam, inverse)
    for k in range(2):
        prof[L.BRAKE_P + k] = new_origin + _scaled(prof[L.BRAKE_P + k] - origin, lam, inverse)


@njit(cache=True, error_model="numpy")
def _scale_rates(prof, tau, v, a, j):
    """Multiply the times of a record by ``tau``, its rates by ``v``, ``a`` and ``j`` (per order).

    Positions are left to the caller, which either scales them or integrates them anew.
    """
    for i in range(7):
        prof[L.T + i] *= tau
        prof[L.T_SUM + i] *= tau
        prof[L.J + i] *= j
    for i in range(8):
        prof[L.V + i] *= v
        prof[L.A + i] *= a
    prof[L.VF] *= v
    prof[L.AF] *= a
    prof[L.BRAKE_DURATION] *= tau
    for k in range(2):
        prof[L.BRAKE_T + k] *= tau
        prof[L.BRAKE_V + k] *= v
        prof[L.BRAKE_A + k] *= a
        prof[L.BRAKE_J + k] *= j


@njit(cache=True, error_model="numpy")
def _scaled(x, factor, inverse):
    return x / factor if inverse else x * factor


@njit(cache=True, error_model="numpy")
def _jumps(minimum, p0, v0, a0, pf, vf, af, a_max, a_min, j_max):
    """Whether a joint's fastest profile (``minimum`` s long) takes no time to change the state.

    The laws accept moves below their absolute precision (1e-8) as done at once; in
    the move's own units they get a true profile. A change of velocity alone that no
    positive duration can hold (5e-324 rad/s at 2 rad/s^2 and no jerk limit takes
    2.5e-324 s, which rounds to 0) is no jump: taking no time is its exact answer in
    float64. So is a change of acceleration alone, or with it (5e-324 rad/s^2 at
    2 rad/s^3, found by a randomized hypothesis run).
    """
    if minimum != 0.0:
        return False
    if pf == p0:
        change = abs(vf - v0)
        time = change / max(a_max, -a_min)
        if math.isfinite(j_max):
            time = max(time, math.sqrt(change / j_max), abs(af - a0) / j_max)
        elif af != a0:
            time = math.inf  # without a jerk limit the acceleration cannot move at all
        if time == 0.0:
            return False
    return pf != p0 or vf != v0 or af != a0


@njit(cache=True, error_model="numpy")
def _step1(
    prof,
    p0,
    v0,
    a0,
    pf,
    vf,
    af,
    v_max,
    v_min,
    a_max,
    a_min,
    j_max,
    control,
    valid,
    block,
    block_times,
):
    """Brake, then the fastest profile and blocked intervals of one joint (any scale).

    Ordinary problems are tried as given first (so they are planned as the
    reference plans them), then in units that make them ordinary (:func:`_units`);
    extreme ones (a unit beyond 2**40), whose answers the laws' absolute tolerances
    would accept at any precision, the other way round.
    """
    args = (p0, v0, a0, pf, vf, af, v_max, v_min, a_max, a_min, j_max, control)
    tau, lam = _units(pf - p0, v0, a0, vf, af, v_max, v_min, a_max, a_min, j_max)
    scaled = not (tau == 1.0 and lam == 1.0)
    if _extreme(tau, lam):
        if _step1_in_units(prof, tau, lam, args, valid, block, block_times):
            return True
        if _step1_raw(prof, args, valid, block, block_times):
            return True
        return _step1_in_place(prof, args, valid, block, block_times)
    if _step1_raw(prof, args, valid, block, block_times) and not _jumps(
        block_times[0], p0, v0, a0, pf, vf, af, a_max, a_min, j_max
    ):
        return True
    if scaled and _step1_in_units(prof, tau, lam, args, valid, block, block_times):
        return True
    return _step1_in_place(prof, args, valid, block, block_times)


# Limits far beyond a vanishing motion's magnitudes bind nothing; they are capped to
# stay finite in its units.
_FAR = 1e300


@njit(cache=True, error_model="numpy")
def _step1_in_place(prof, args, valid, block, block_times):
    """The fastest profile of a joint whose target is its start, only its velocity changing.

    Where the velocities and accelerations are so small that no length unit makes
    the move ordinary (braking from 1e-300 rad/s at 1 rad/s^3 takes 2e-150 s and
    moves 1e-450 rad, below the smallest float64), the velocity change is planned
    in a unit of velocity instead, as a velocity-interface move; its displacement
    then rounds to nothing, so the position stays exactly at the target. Refused
    (False) where it would not.
    """
    p0, v0, a0, pf, vf, af, v_max, v_min, a_max, a_min, j_max, control = args
    if control != POSITION or pf != p0:
        return False
    third = math.isfinite(j_max)
    change = max(abs(v0), abs(vf), abs(vf - v0))
    push = min(a_max, -a_min)
    duration = change / push
    if third:
        duration = max(duration, math.sqrt(change / j_max), abs(a0) / j_max, abs(af) / j_max)
    tau = power_of_two(duration)
    nu = power_of_two(max(change, abs(a0) * tau, abs(af) * tau))
    a_unit = nu / tau
    j_unit = a_unit / tau
    in_units = (
        0.0,
        v0 / nu,
        a0 / a_unit,
        0.0,
        vf / nu,
        af / a_unit,
        min(v_max / nu, _FAR),
        max(v_min / nu, -_FAR),
        min(a_max / a_unit, _FAR),
        max(a_min / a_unit, -_FAR),
        min(j_max / j_unit, _FAR) if third else j_max,
        VELOCITY,
    )
    found = _step1_raw(prof, in_units, valid, block, block_times)
    if not found:
        return False
    _from_velocity_units(prof, tau, nu, p0, pf)
    for k in range(3):
        _from_velocity_units(block[k], tau, nu, p0, pf)
    for k in range(5):
        block_times[k] *= tau
    return prof[L.P + 7] == pf and block_times[0] > 0.0


@njit(cache=True, error_model="numpy")
def _from_velocity_units(prof, tau, nu, p0, pf):
    """A record planned in units ``tau`` (s) and ``nu`` (rad/s), back in absolute ones.

    Positions are integrated anew from ``p0`` (a length unit ``nu * tau`` may not
    exist in float64).
    """
    a_unit = nu / tau
    _scale_rates(prof, tau, nu, a_unit, a_unit / tau)
    p = p0
    for k in range(2):
        prof[L.BRAKE_P + k] = p
        if prof[L.BRAKE_T + k] > 0.0:
            p = integrate(
                prof[L.BRAKE_T + k],
                p,
                prof[L.BRAKE_V + k],
                prof[L.BRAKE_A + k],
                prof[L.BRAKE_J + k],
            )[0]
    prof[L.P] = p
    for i in range(7):
        prof[L.P + i + 1] = integrate(
            prof[L.T + i], prof[L.P + i], prof[L.V + i], prof[L.A + i], prof[L.J + i]
        )[0]
    prof[L.PF] = pf


@njit(cache=True, error_model="numpy")
def _extreme(tau, lam):
    """Whether units are far enough from 1 that a problem is planned in them first."""
    return not (_EXTREME_LOW <= tau <= _EXTREME_HIGH and _EXTREME_LOW <= lam <= _EXTREME_HIGH)


@njit(cache=True, error_model="numpy")
def _step1_in_units(prof, tau, lam, args, valid, block, block_times):
    """:func:`_step1_raw` of ``args`` in units ``tau`` (s), ``lam``; records in the caller's."""
    p0, v0, a0, pf, vf, af, v_max, v_min, a_max, a_min, j_max, control = args
    v = tau / lam
    a = v * tau
    j = j_max * a * tau if math.isfinite(j_max) else j_max
    in_units = (
        0.0,
        v0 * v,
        a0 * a,
        (pf - p0) / lam,
        vf * v,
        af * a,
        v_max * v,
        v_min * v,
        a_max * a,
        a_min * a,
        j,
        control,
    )
    found = _step1_raw(prof, in_units, valid, block, block_times)
    _rescale(prof, tau, lam, 0.0, p0)
    for k in range(3):
        _rescale(block[k], tau, lam, 0.0, p0)
    for k in range(5):
        block_times[k] *= tau
    return found and not _jumps(block_times[0], p0, v0, a0, pf, vf, af, a_max, a_min, j_max)


@njit(cache=True, error_model="numpy")
def _step2(prof, tf, v_max, v_min, a_max, a_min, j_max, control):
    """Re-plan one joint (its boundary and brake already in ``prof``) to take ``tf``.

    As given first, then in ordinary units; extreme problems the other way round
    (see :func:`_step1`).
    """
    original = prof.copy()
    p0 = prof[L.P]
    tau, lam = _units(
        prof[L.PF] - p0,
        prof[L.V],
        prof[L.A],
        prof[L.VF],
        prof[L.AF],
        v_max,
        v_min,
        a_max,
        a_min,
        j_max,
    )
    scaled = not (tau == 1.0 and lam == 1.0)
    if scaled and _extreme(tau, lam):
        if _step2_in_units(prof, tf, tau, lam, v_max, v_min, a_max, a_min, j_max, control):
            return True
        prof[:] = original
        if _step2_raw(prof, tf, v_max, v_min, a_max, a_min, j_max, control):
            return True
        prof[:] = original
        return False
    if _step2_raw(prof, tf, v_max, v_min, a_max, a_min, j_max, control):
        return True
    prof[:] = original
    if scaled and _step2_in_units(prof, tf, tau, lam, v_max, v_min, a_max, a_min, j_max, control):
        return True
    prof[:] = original
    return False


@njit(cache=True, error_model="numpy")
def _step2_in_units(prof, tf, tau, lam, v_max, v_min, a_max, a_min, j_max, control):
    """:func:`_step2_raw` in units ``tau`` (s), ``lam``; the record back in the caller's."""
    origin = prof[L.BRAKE_P] if prof[L.BRAKE_DURATION] > 0.0 else prof[L.P]
    _rescale(prof, tau, lam, origin, 0.0, True)
    v = tau / lam
    a = v * tau
    j = j_max * a * tau if math.isfinite(j_max) else j_max
    found = _step2_raw(prof, tf / tau, v_max * v, v_min * v, a_max * a, a_min * a, j, control)
    _rescale(prof, tau, lam, 0.0, origin)
    return found


@njit(cache=True, error_model="numpy")
def _has_zero_limits(a_max, a_min, j_max):
    return a_max == 0.0 or a_min == 0.0 or j_max == 0.0


@njit(cache=True, error_model="numpy")
def _synchronize(block_times, sync, min_duration, dt, candidates, order):
    """The common duration and where it comes from.

    Returns ``(duration, source)``: ``source`` indexes ``candidates`` laid out as
    ruckig's (``k * ndof + joint`` for the joint's minimum, k = 0, and the right
    ends of its blocked intervals, k = 1, 2; ``3 * ndof`` for ``min_duration``), or
    -1 when no duration works.
    """
    ndof = block_times.shape[0]
    any_interval = False
    for d in range(ndof):
        if sync[d] == SYNC_NONE:
            candidates[d] = -1.0  # sorts first, never chosen
            candidates[ndof + d] = math.inf
            candidates[2 * ndof + d] = math.inf
            continue
        candidates[d] = block_times[d, 0]
        candidates[ndof + d] = block_times[d, 2]
        candidates[2 * ndof + d] = block_times[d, 4]
        if not math.isinf(block_times[d, 2]) or not math.isinf(block_times[d, 4]):
            any_interval = True
    has_minimum = not math.isnan(min_duration)
    candidates[3 * ndof] = min_duration if has_minimum else math.inf
    any_interval = any_interval or has_minimum
    if dt > 0.0:
        for k in range(3 * ndof + 1):
            if not math.isinf(candidates[k]):
                candidates[k] = round_up(candidates[k], dt)
    count = 3 * ndof + 1 if any_interval else ndof
    for k in range(count):
        order[k] = k
    # Insertion sort: a handful of entries, stable like the reference's std::sort
    # on distinct values.
    for k in range(1, count):
        key = order[k]
        m = k - 1
        while m >= 0 and candidates[order[m]] > candidates[key]:
            order[m + 1] = order[m]
            m -= 1
        order[m + 1] = key
    floor = min_duration if has_minimum else 0.0
    for k in range(ndof - 1, count):
        t = candidates[order[k]]
        if math.isinf(t) or t < floor:
            continue
        blocked = False
        for d in range(ndof):
            if sync[d] != SYNC_NONE and jerk_fastest.is_blocked(block_times[d], t):
                blocked = True
                break
        if blocked:
            continue
        source = order[k]
        if source < ndof:
            # Of joints whose minimum ties, the first is named the limiting one.
            for d in range(ndof):
                if sync[d] != SYNC_NONE and candidates[d] == t:
                    return t, d
        return t, source
    everyone_free = True
    for d in range(ndof):
        if sync[d] != SYNC_NONE:
            everyone_free = False
    if everyone_free:
        return 0.0, 3 * ndof  # the joints' own durations decide (see plan)
    return math.nan, -1


@njit(cache=True, error_model="numpy")
def _collinear(x, y, ratio):
    """``x == ratio * y`` up to rounding (both sides computed from user numbers)."""
    return abs(x - ratio * y) <= _COLLINEAR_RTOL * (abs(x) + abs(ratio * y)) + 1e-300


@njit(cache=True, error_model="numpy")
def _onto_bounds(x, lower, upper):
    """``x``, or the bound it passes by no more than the rounding collinearity allows.

    The law's boundary rates and its bounds are different joints' numbers over their
    scales: a joint's target speed at its limit (``vf = vmax``) can come out an ulp
    past the bound another joint's limit sets (found by a randomized hypothesis run:
    ``vf`` 0.01 rad/s at ``vmax`` 0.01 beside a parallel joint's -0.0080402 rad/s).
    """
    if x > upper and x - upper <= _COLLINEAR_RTOL * abs(upper):
        return upper
    if x < lower and lower - x <= _COLLINEAR_RTOL * abs(lower):
        return lower
    return x


@njit(cache=True, error_model="numpy")
def _phase_law(m, control, sync, enabled, scale, law):
    """The shared time law of the phase-synchronized joints, if their boundaries allow one.

    Phase synchronization moves every such joint as ``q0 + scale[d] * s(t)``: one
    law ``s`` for all, so they switch phases together and move on a straight line
    in joint space. That needs their boundary states collinear: every joint's move,
    start and target velocity and acceleration the same multiple of ``scale``.
    Writes ``scale`` and the law's problem (a one-joint matrix ``law`` (11, 1),
    limits the tightest of the joints' limits divided by their scale) and returns
    True; False where the boundaries are not collinear. Joints that all stand
    still share the law of standing still.
    """
    ndof = m.shape[1]
    reference = -1
    row = -1
    for d in range(ndof):
        if sync[d] != SYNC_PHASE or enabled[d] == 0 or control[d] != POSITION:
            continue
        if m[QF, d] - m[Q0, d] != 0.0:
            row = 0
        elif m[V0, d] != 0.0:
            row = V0
        elif m[A0, d] != 0.0:
            row = A0
        elif m[VF, d] != 0.0:
            row = VF
        elif m[AF, d] != 0.0:
            row = AF
        else:
            continue
        reference = d
        break
    if reference < 0:
        for d in range(ndof):
            scale[d] = 0.0
        for r in range(11):
            law[r, 0] = 0.0
        law[V_MIN, 0], law[V_MAX, 0], law[A_MIN, 0], law[A_MAX, 0], law[J_MAX, 0] = (
            -1.0,
            1.0,
            -1.0,
            1.0,
            1.0,
        )
        return True
    for d in range(ndof):
        scale[d] = 0.0
        if sync[d] == SYNC_PHASE and enabled[d] != 0 and control[d] == POSITION:
            scale[d] = m[QF, d] - m[Q0, d] if row == 0 else m[row, d]
    # Scales far from 1 (a subnormal move, one of 1e300) would overflow the law's
    # limits (a joint's limit over its scale); in a power-of-two unit they stay
    # ordinary and the law's own move takes the extreme magnitude instead.
    unit = _ordinary_unit(abs(scale[reference]))
    if unit != 1.0:
        for d in range(ndof):
            scale[d] /= unit
    c_ref = scale[reference]
    ratios = (
        (m[QF, reference] - m[Q0, reference]) / c_ref,
        m[V0, reference] / c_ref,
        m[A0, reference] / c_ref,
        m[VF, reference] / c_ref,
        m[AF, reference] / c_ref,
    )
    v_upper = math.inf
    v_lower = -math.inf
    a_upper = math.inf
    a_lower = -math.inf
    j_bound = math.inf
    for d in range(ndof):
        if sync[d] != SYNC_PHASE or enabled[d] == 0 or control[d] != POSITION:
            continue
        c = scale[d]
        if not (
            _collinear(m[QF, d] - m[Q0, d], ratios[0], c)
            and _collinear(m[V0, d], ratios[1], c)
            and _collinear(m[A0, d], ratios[2], c)
            and _collinear(m[VF, d], ratios[3], c)
            and _collinear(m[AF, d], ratios[4], c)
        ):
            return False
        if c == 0.0:
            continue  # at rest throughout: no bound on the law
        high_v, low_v = m[V_MAX, d] / c, m[V_MIN, d] / c
        high_a, low_a = m[A_MAX, d] / c, m[A_MIN, d] / c
        if c < 0.0:
            high_v, low_v = low_v, high_v
            high_a, low_a = low_a, high_a
        v_upper = min(v_upper, high_v)
        v_lower = max(v_lower, low_v)
        a_upper = min(a_upper, high_a)
        a_lower = max(a_lower, low_a)
        j_bound = min(j_bound, m[J_MAX, d] / abs(c))
    law[Q0, 0] = 0.0
    law[QF, 0] = ratios[0]
    law[V0, 0] = _onto_bounds(ratios[1], v_lower, v_upper)
    law[A0, 0] = _onto_bounds(ratios[2], a_lower, a_upper)
    law[VF, 0] = _onto_bounds(ratios[3], v_lower, v_upper)
    law[AF, 0] = _onto_bounds(ratios[4], a_lower, a_upper)
    law[V_MIN, 0] = v_lower
    law[V_MAX, 0] = v_upper
    law[A_MIN, 0] = a_lower
    law[A_MAX, 0] = a_upper
    law[J_MAX, 0] = j_bound
    return True


@njit(cache=True, error_model="numpy")
def _scaled_law(law, c, m, d, prof):
    """Joint ``d``'s record: the law's scaled by ``c`` from its start, targets exact."""
    q0 = m[Q0, d]
    for k in range(L.SIZE):
        prof[k] = law[k]
    for i in range(7):
        prof[L.J + i] = c * law[L.J + i]
    for i in range(8):
        prof[L.A + i] = c * law[L.A + i]
        prof[L.V + i] = c * law[L.V + i]
        prof[L.P + i] = q0 + c * law[L.P + i]
    for k in range(2):
        prof[L.BRAKE_J + k] = c * law[L.BRAKE_J + k]
        prof[L.BRAKE_A + k] = c * law[L.BRAKE_A + k]
        prof[L.BRAKE_V + k] = c * law[L.BRAKE_V + k]
        prof[L.BRAKE_P + k] = q0 + c * law[L.BRAKE_P + k]
    prof[L.PF] = m[QF, d]
    prof[L.VF] = m[VF, d]
    prof[L.AF] = m[AF, d]


@njit(cache=True, error_model="numpy")
def plan(m, control, sync, enabled, min_duration, dt, profiles, independent, out):
    """Plan one problem of ``ndof`` joints; returns a status code (``OK`` on success).

    ``m`` is the (11, ndof) problem matrix, rows as in
    :mod:`trajkit.profiles._kernels.admissible` (q0, qf, v0, vf, a0, af, v_min,
    v_max, a_min, a_max, j_max); ``control``, ``sync`` and ``enabled`` are int64
    vectors; ``j_max = inf`` plans acceleration-limited (second-order) profiles;
    ``min_duration`` is NaN for none; ``dt > 0`` rounds the duration up to whole
    periods (every joint is then re-planned to take it). Writes each joint's
    profile record into ``profiles`` (ndof, SIZE), each joint's own minimum
    duration into ``independent`` and the summary into ``out`` (``OUT_*`` fields).

    Phase-synchronized joints whose boundaries are collinear share one time law
    (:func:`_phase_law`), which takes part in the synchronization as one more
    joint; where they are not collinear they are time-synchronized and
    ``out[OUT_PHASE]`` stays 0.
    """
    if (
        rest_to_rest.applies(m, control, sync, enabled)
        and ordinary(m)
        and rest_to_rest.plan(m, sync, min_duration, dt, profiles, independent, out)
    ):
        return OK
    return general_plan(m, control, sync, enabled, min_duration, dt, profiles, independent, out)


@njit(cache=True, error_model="numpy")
def general_plan(m, control, sync, enabled, min_duration, dt, profiles, independent, out):
    """:func:`plan` by the general laws (any problem)."""
    p0, pf, v0, vf, a0, af = m[Q0], m[QF], m[V0], m[VF], m[A0], m[AF]
    a_min, a_max, j_max = m[A_MIN], m[A_MAX], m[J_MAX]
    ndof = p0.shape[0]
    n = ndof + 1  # the joints and the phase law
    valid = np.empty((6, L.SIZE))
    blocks = np.empty((n, 3, L.SIZE))
    block_times = np.empty((n, 5))
    out[OUT_DURATION] = math.nan
    out[OUT_LIMITING] = -1.0
    out[OUT_PHASE] = 0.0
    out[OUT_JOINT] = -1.0
    for d in range(ndof):
        prof = profiles[d]
        if enabled[d] == 0:
            for k in range(L.SIZE):
                prof[k] = 0.0
            set_boundary(prof, p0[d], v0[d], a0[d], p0[d], v0[d], a0[d])
            prof[L.P + 7] = p0[d]
            prof[L.V + 7] = v0[d]
            prof[L.A + 7] = a0[d]
            block_times[d, 0] = 0.0
            for k in range(1, 5):
                block_times[d, k] = math.inf
            blocks[d, 0] = prof
            independent[d] = 0.0
            continue
        limits = _limits(m, d, control[d])
        found = _step1(
            prof,
            p0[d],
            v0[d],
            a0[d],
            pf[d],
            vf[d],
            af[d],
            *limits,
            valid,
            blocks[d],
            block_times[d],
        )
        if not found:
            out[OUT_JOINT] = d
            if _has_zero_limits(a_max[d], a_min[d], j_max[d]):
                return ZERO_LIMITS
            return STEP1_FAILED
        independent[d] = block_times[d, 0]

    # Which joints synchronize how: the law stands in for the phase joints.
    roles = np.empty(n, np.int64)
    for d in range(ndof):
        roles[d] = sync[d] if enabled[d] != 0 else SYNC_NONE
    roles[ndof] = SYNC_NONE
    scale = np.zeros(ndof)
    law_m = np.empty((11, 1))
    law = np.empty(L.SIZE)
    use_law = False
    for d in range(ndof):
        if roles[d] == SYNC_PHASE:
            use_law = True
    if use_law:
        use_law = _phase_law(m, control, roles, enabled, scale, law_m)
    if use_law:
        law_limits = _limits(law_m, 0, POSITION)
        found = _step1(
            law,
            0.0,
            law_m[V0, 0],
            law_m[A0, 0],
            law_m[QF, 0],
            law_m[VF, 0],
            law_m[AF, 0],
            *law_limits,
            valid,
            blocks[ndof],
            block_times[ndof],
        )
        if not found:
            out[OUT_JOINT] = -1
            return STEP1_FAILED
        for d in range(ndof):
            if roles[d] == SYNC_PHASE and control[d] == POSITION:
                roles[d] = _LAW
        roles[ndof] = SYNC_TIME
        out[OUT_PHASE] = 1.0
    else:
        for d in range(ndof):
            if roles[d] == SYNC_PHASE:
                roles[d] = SYNC_TIME  # not collinear: time-synchronized instead
        block_times[ndof, 0] = 0.0
        for k in range(1, 5):
            block_times[ndof, k] = math.inf

    discrete = dt > 0.0
    has_minimum = not math.isnan(min_duration)
    if ndof == 1 and not has_minimum and not discrete and not use_law:
        profiles[0] = blocks[0, 0]
        out[OUT_DURATION] = block_times[0, 0]
        out[OUT_LIMITING] = 0.0
        return OK

    candidates = np.empty(3 * n + 1)
    order = np.empty(3 * n + 1, np.int64)
    voting = np.empty(n, np.int64)
    for d in range(n):
        voting[d] = SYNC_NONE if roles[d] == _LAW else roles[d]
    # A joint whose laws miss the durations it cannot take (a move of 1e-115 rad at
    # full speed, whose slowed-down profiles tie with the fastest) fails step 2 at a
    # duration between its minimum and a blocked interval: that duration is then
    # blocked too, and the joints synchronize again.
    for _attempt in range(ndof + 1):
        retry = False
        duration, source = _synchronize(block_times, voting, min_duration, dt, candidates, order)
        if source < 0:
            for d in range(ndof):
                if _has_zero_limits(a_max[d], a_min[d], j_max[d]):
                    return ZERO_LIMITS
            return SYNC_FAILED
        limiting = -1
        if source < 3 * n:
            limiting = source % n
            if limiting < ndof:
                profiles[limiting] = blocks[limiting, source // n]
        # Joints left out of synchronization move as fast as they can; the longest of
        # them may set the duration.
        all_none = True
        for d in range(ndof):
            if roles[d] != SYNC_NONE:
                all_none = False
            if enabled[d] != 0 and roles[d] == SYNC_NONE:
                profiles[d] = blocks[d, 0]
                own = round_up(block_times[d, 0], dt) if discrete else block_times[d, 0]
                if own > duration:
                    duration = own
                    limiting = d
        out[OUT_DURATION] = duration
        out[OUT_LIMITING] = limiting if limiting < ndof else -1
        if duration == 0.0:
            for d in range(ndof):
                profiles[d] = blocks[d, 0]
            return OK
        if not discrete and all_none:
            return OK

        if use_law:
            law[:] = blocks[ndof, 0]
            if not _take_duration(
                law,
                blocks[ndof],
                block_times[ndof],
                duration,
                _limits(law_m, 0, POSITION),
                limiting == ndof and not discrete,
            ):
                out[OUT_JOINT] = -1
                return STEP2_FAILED
            for d in range(ndof):
                if roles[d] == _LAW:
                    _scaled_law(law, scale[d], m, d, profiles[d])

        for d in range(ndof):
            if enabled[d] == 0 or roles[d] == _LAW:
                continue
            if (d == limiting or roles[d] == SYNC_NONE) and not discrete:
                continue
            prof = profiles[d]
            if roles[d] == SYNC_TIME_IF_NECESSARY and abs(vf[d]) < _EPS and abs(af[d]) < _EPS:
                prof[:] = blocks[d, 0]
                continue
            if roles[d] == SYNC_NONE:
                # Discrete durations: a joint on its own still ends on the grid.
                own = round_up(block_times[d, 0], dt)
            else:
                own = duration
            limits = _limits(m, d, control[d])
            if not _take_duration(prof, blocks[d], block_times[d], own, limits, False):
                out[OUT_JOINT] = d
                if roles[d] != SYNC_NONE and _widen_blocked(block_times[d], duration):
                    retry = True
                    break
                return STEP2_FAILED
        if not retry:
            return OK
    return STEP2_FAILED


@njit(cache=True, error_model="numpy")
def _widen_blocked(times, duration):
    """Block ``duration`` for a joint that could not take it; False if it cannot be.

    Only a duration between the joint's minimum and the left end of one of its
    blocked intervals is: that interval then starts at the minimum.
    """
    for k in (1, 3):
        left = times[k]
        if not math.isinf(left) and times[0] < duration <= left:
            times[k] = times[0]
            return True
    return False


@njit(cache=True, error_model="numpy")
def _limits(m, d, control):
    """Joint ``d``'s limits in ``m`` and its ``control``, in the order of :func:`_step2`."""
    return m[V_MAX, d], m[V_MIN, d], m[A_MAX, d], m[A_MIN, d], m[J_MAX, d], control


@njit(cache=True, error_model="numpy")
def _take_duration(prof, block, times, duration, limits, is_minimum):
    """Write into ``prof`` the joint's profile of exactly ``duration`` (brake included).

    Step 1's profiles are reused where the duration is one of theirs (the
    minimum, or the right end of a blocked interval); otherwise step 2 (``limits``
    as :func:`_limits` gives them).
    """
    if is_minimum:
        prof[:] = block[0]
        return True
    t_profile = duration - block[0, L.BRAKE_DURATION]
    if abs(t_profile - (times[0] - block[0, L.BRAKE_DURATION])) < REUSE_WITHIN:
        prof[:] = block[0]
        return True
    for k in (1, 2):
        right = times[2 * k]
        if not math.isinf(right) and abs(duration - right) < REUSE_WITHIN:
            prof[:] = block[k]
            return True
    prof[:] = block[0]
    if _step2(prof, t_profile, *limits):
        return True
    # The closed forms can lose the move to cancellation when the duration dwarfs
    # the joint's own (a 1e-38 rad move stretched over seconds); a move between
    # states of rest is then its fastest profile slowed down.
    return _slowed_down(prof, block[0], t_profile, math.isinf(limits[4]))


@njit(cache=True, error_model="numpy")
def _slowed_down(prof, fastest, tf, second_order):
    """``fastest`` (rest to rest, no brake) slowed to take ``tf`` s; False if not at rest.

    Slowing a profile by ``k = tf / t`` divides its velocities by ``k``, its
    accelerations by ``k**2`` and its jerks by ``k**3``: the same path, within
    the same limits, taking ``k`` times as long.
    """
    if fastest[L.BRAKE_DURATION] != 0.0 or not _at_rest(fastest, second_order):
        return False
    own = fastest[L.T_SUM + 6]
    if not (own > 0.0 and tf >= own):
        return False
    k = tf / own
    prof[:] = fastest
    total = 0.0
    for i in range(7):
        prof[L.T + i] = fastest[L.T + i] * k
        total += prof[L.T + i]
        prof[L.T_SUM + i] = total
        if second_order:
            prof[L.A + i] = fastest[L.A + i] / (k * k)
        else:
            prof[L.J + i] = fastest[L.J + i] / (k * k * k)
    for i in range(7):
        t = prof[L.T + i]
        a = prof[L.A + i]
        v = prof[L.V + i]
        if second_order:
            prof[L.V + i + 1] = v + t * a
            prof[L.P + i + 1] = prof[L.P + i] + t * (v + t * a / 2.0)
        else:
            j = prof[L.J + i]
            prof[L.A + i + 1] = a + t * j
            prof[L.V + i + 1] = v + t * (a + t * j / 2.0)
            prof[L.P + i + 1] = prof[L.P + i] + t * (v + t * (a / 2.0 + t * j / 6.0))
    return True


@njit(cache=True, error_model="numpy")
def _at_rest(rec, second_order):
    """True if a record starts and ends at rest (zero velocity and acceleration).

    A second-order record's ``a[0]`` is its first phase's acceleration, not a state.
    """
    still = second_order or rec[L.A] == 0.0
    return still and rec[L.V] == 0.0 and rec[L.VF] == 0.0 and rec[L.AF] == 0.0
