"""Phase tables: the compact form of planned motions that everything downstream reads.

A joint's plan is its start state ``(p0, v0, a0)`` and nine phases (two of brake,
seven of profile), each a duration ``t`` and a control ``u``: the jerk of a
jerk-limited joint, the (constant) acceleration of an acceleration-limited one.
Integrating the phases from the start state gives every phase's start state; a
joint whose phases end before the common duration continues from its target
position and velocity with zero acceleration.

One problem's tables become a :class:`trajkit.Trajectory` (:func:`pieces`); a
batch's tables are evaluated in place (:func:`evaluate_batch`) and problem ``i``
of a batch is the same conversion of its slice.
"""

import math

import numpy as np
from numba import njit, prange

from trajkit.profiles._kernels.layout import BRAKE_A, BRAKE_J, BRAKE_T, A, J, T
from trajkit.profiles._kernels.profile import EPS, P_PRECISION, REUSE_WITHIN, integrate

PHASES = 9  # two brake phases, seven profile phases
# Breakpoints closer than this (relative to the duration) are one switch computed
# along two roundings (as in trajkit.profiles._phases).
MERGE = 4e-16
# An exact end value is kept where it agrees with the pieces to this (relative to
# the size of the terms summed, plus an absolute floor): Trajectory's own rule.
BOUNDARY_RTOL = 1e-6
BOUNDARY_ATOL = 1e-9


@njit(cache=True, error_model="numpy")
def compact(record, second_order, t, u):
    """A profile record's nine phases as durations ``t`` and controls ``u``."""
    for k in range(2):
        t[k] = record[BRAKE_T + k]
        u[k] = record[BRAKE_A + k] if second_order else record[BRAKE_J + k]
    for i in range(7):
        t[2 + i] = record[T + i]
        u[2 + i] = record[A + i] if second_order else record[J + i]


# A polish may change a phase's duration by at most this fraction of it. The laws'
# precision (1e-8 in position) can be a 1e-4 share of a short jerk phase of a tiny
# move; a correction beyond this is not a polish.
POLISH_MAX_CHANGE = 1e-3
# Jerk phases take a correction at this weight beside holds and coasts: stretching a
# hold keeps the acceleration and velocity levels (and so the limits) as planned.
JERK_PHASE_WEIGHT = 1e-3
POLISH_ITERATIONS = 3
# A miss of this relative size is the rounding of integrating the phases (a duration
# an ulp off its exact value, summed with the others): the pieces absorb it, and a
# polish would cost more than the plan.
ROUNDING_MISS = 64.0 * EPS


@njit(cache=True, error_model="numpy")
def _control(u_k, a, second_order):
    """A phase's start acceleration and jerk from its control ``u_k``.

    An acceleration-limited joint's control is its (held) acceleration, jerk 0; a
    jerk-limited joint's is its jerk, the acceleration carried on from ``a``.
    """
    if second_order:
        return u_k, 0.0
    return a, u_k


@njit(cache=True, error_model="numpy")
def _advance(p, v, a, tk, u_k, second_order):
    """The state after a phase of ``tk`` s (> 0) with control ``u_k``, from ``(p, v, a)``."""
    a, j = _control(u_k, a, second_order)
    return (
        p + tk * (v + tk * (a / 2.0 + tk * j / 6.0)),
        v + tk * (a + tk * j / 2.0),
        a + tk * j,
    )


@njit(cache=True, error_model="numpy")
def _phase_ends(start, t, u, second_order, ends):
    """``ends[k]`` = (p, v, a) at the end of phase ``k``, integrated from ``start``."""
    p, v, a = start[0], start[1], start[2]
    for k in range(PHASES):
        if t[k] > 0.0:
            p, v, a = _advance(p, v, a, t[k], u[k], second_order)
        ends[k, 0] = p
        ends[k, 1] = v
        ends[k, 2] = a


@njit(cache=True, error_model="numpy")
def end_position(start, t, u, second_order):
    """Where the nine phases from ``start`` (p, v, a) end (a motion with no position target).

    The last row :func:`_phase_ends` would write, integrated in the same order.
    """
    p, v, a = start[0], start[1], start[2]
    for k in range(PHASES):
        if t[k] > 0.0:
            p, v, a = _advance(p, v, a, t[k], u[k], second_order)
    return p


@njit(cache=True, error_model="numpy")
def _residual(start, target, t, u, second_order, with_position, ends):
    """Integrate the phases into ``ends``; return the scales (p, v, a) of the target's miss.

    Each scale is the largest magnitude of its quantity along the motion (the
    position's only with a position target).
    """
    _phase_ends(start, t, u, second_order, ends)
    sp = max(abs(start[0]), abs(target[0])) if with_position else 1.0
    sv = max(abs(start[1]), abs(target[1]), 1e-300)
    sa = max(abs(start[2]), abs(target[2]), 1e-300)
    for k in range(PHASES):
        if with_position:
            sp = max(sp, abs(ends[k, 0]))
        sv = max(sv, abs(ends[k, 1]))
        sa = max(sa, abs(ends[k, 2]))
    return sp, sv, sa


@njit(cache=True, error_model="numpy")
def _end_miss(start, target, t, u, second_order, with_position):
    """The largest relative miss of the target by the phases (the scales of :func:`_residual`)."""
    p, v, a = start[0], start[1], start[2]
    sp = max(abs(p), abs(target[0]))
    sv = max(abs(v), abs(target[1]), 1e-300)
    sa = max(abs(a), abs(target[2]), 1e-300)
    for k in range(PHASES):
        if t[k] > 0.0:
            p, v, a = _advance(p, v, a, t[k], u[k], second_order)
        sp = max(sp, abs(p))
        sv = max(sv, abs(v))
        sa = max(sa, abs(a))
    miss = abs(target[0] - p) / sp if with_position else 0.0
    miss = max(miss, abs(target[1] - v) / sv)
    if not second_order:
        miss = max(miss, abs(target[2] - a) / sa)
    return miss


@njit(cache=True, error_model="numpy")
def _excess(start, t, u, second_order, limits):
    """Largest excess of the profile phases' velocity and acceleration over ``limits``.

    Relative to the limit exceeded. ``limits`` = (v_min, v_max, a_min, a_max); the
    velocity's turning points inside jerk phases count. Negative where every value
    is inside.
    """
    v_min, v_max, a_min, a_max = limits[0], limits[1], limits[2], limits[3]
    worst = -math.inf
    v, a = start[1], start[2]
    for k in range(PHASES):
        tk = t[k]
        if not tk > 0.0:
            continue
        a, j = _control(u[k], a, second_order)
        v_end = v + tk * (a + tk * j / 2.0)
        a_end = a + tk * j
        if k >= 2:
            hi = max(v, v_end)
            lo = min(v, v_end)
            if j != 0.0 and 0.0 < -a / j < tk:
                turn = v - a * a / (2.0 * j)
                hi = max(hi, turn)
                lo = min(lo, turn)
            worst = max(worst, (hi - v_max) / v_max, (lo - v_min) / v_min)
            worst = max(worst, (max(a, a_end) - a_max) / a_max, (min(a, a_end) - a_min) / a_min)
        v, a = v_end, a_end
    return worst


@njit(cache=True, error_model="numpy")
def polish(start, target, t, u, second_order, with_position, limits):
    """Correct the profile phases' durations so the phases end on the target to rounding.

    The laws accept a profile that reaches the target within their absolute
    precision (1e-8 in position, as ruckig's); their durations are then a few ulps
    of a root away from exact. A Gauss-Newton step on the durations of the seven
    profile phases, their sum held (the common duration stays), removes that miss:
    the minimum-norm correction, relative to each phase's length, preferring holds
    and coasts over jerk phases. Corrections larger than ``POLISH_MAX_CHANGE`` of a
    phase, that do not reduce the miss, or that would take a velocity or an
    acceleration past ``limits`` (v_min, v_max, a_min, a_max) further than the plan
    did, are not applied.
    """
    if _end_miss(start, target, t, u, second_order, with_position) <= ROUNDING_MISS:
        return  # most plans: no allocation
    ends = np.empty((PHASES, 3))
    rows = np.zeros((4, PHASES))
    factor = np.zeros(PHASES)  # each phase's weight per unit of its duration
    allowed = -1.0  # found on the first correction (most plans need none)
    for _ in range(POLISH_ITERATIONS):
        sp, sv, sa = _residual(start, target, t, u, second_order, with_position, ends)
        finish = 0.0
        for k in range(PHASES):
            finish += t[k] if t[k] > 0.0 else 0.0
        last = PHASES - 1
        miss = np.zeros(4)
        miss[0] = (target[0] - ends[last, 0]) / sp if with_position else 0.0
        miss[1] = (target[1] - ends[last, 1]) / sv
        miss[2] = 0.0 if second_order else (target[2] - ends[last, 2]) / sa
        before = max(abs(miss[0]), abs(miss[1]), abs(miss[2]))
        if before <= 4.0 * EPS or not finish > 0.0:
            return
        if allowed < 0.0:
            # Rounding may move a value held at its limit by an ulp or two either way.
            allowed = max(_excess(start, t, u, second_order, limits), 0.0) + 16.0 * EPS
        rows[:, :] = 0.0
        clock = 0.0
        for k in range(PHASES):
            tk = t[k]
            if not tk > 0.0:
                continue
            clock += tk
            if k < 2:
                continue  # the brake is fixed by the start state
            tau = finish - clock
            # Lengthening phase k by dt adds (v, a, j) dt to the state at its end.
            lift, j = _control(u[k], ends[k, 2], second_order)
            factor[k] = 1.0 if j == 0.0 else JERK_PHASE_WEIGHT
            weight = tk * factor[k]
            if with_position:
                rows[0, k] = weight * (ends[k, 1] + tau * (lift + tau * j / 2.0)) / sp
            rows[1, k] = weight * (lift + tau * j) / sv
            if not second_order:
                rows[2, k] = weight * j / sa
            rows[3, k] = weight / finish
        # Minimum-norm x with rows @ x = miss: x = rows.T @ y, (rows @ rows.T) y = miss.
        gram = rows @ rows.T
        y = miss.copy()
        if not _solve_in_place(gram, y):
            return
        x = rows.T @ y
        changed = t.copy()
        for k in range(2, PHASES):
            if t[k] > 0.0:
                change = x[k] * factor[k]
                if not abs(change) <= POLISH_MAX_CHANGE:
                    return
                changed[k] = t[k] * (1.0 + change)
        sp, sv, sa = _residual(start, target, changed, u, second_order, with_position, ends)
        after = max(
            abs(target[0] - ends[last, 0]) / sp if with_position else 0.0,
            abs(target[1] - ends[last, 1]) / sv,
            0.0 if second_order else abs(target[2] - ends[last, 2]) / sa,
        )
        if not after < before or _excess(start, changed, u, second_order, limits) > allowed:
            return
        t[:] = changed


@njit(cache=True, error_model="numpy")
def _solve_in_place(a, b):
    """Solve the small system ``a x = b`` into ``b`` (Gaussian elimination, partial pivoting).

    An equation no phase can move (a zero row and column) keeps its unknown at 0.
    Returns False where the system is singular otherwise (fewer phases than
    equations): the phases are then left as planned.
    """
    n = b.shape[0]
    scale = 0.0
    for i in range(n):
        scale = max(scale, a[i, i])
    if not scale > 0.0:
        return False
    for i in range(n):
        if a[i, i] == 0.0:
            a[i, i] = scale
            b[i] = 0.0
    for col in range(n):
        best = col
        for r in range(col + 1, n):
            if abs(a[r, col]) > abs(a[best, col]):
                best = r
        if not abs(a[best, col]) > 1e-12 * scale:
            return False
        for c in range(n):
            a[col, c], a[best, c] = a[best, c], a[col, c]
        b[col], b[best] = b[best], b[col]
        for r in range(col + 1, n):
            f = a[r, col] / a[col, col]
            for c in range(col, n):
                a[r, c] -= f * a[col, c]
            b[r] -= f * b[col]
    for col in range(n - 1, -1, -1):
        total = b[col]
        for c in range(col + 1, n):
            total -= a[col, c] * b[c]
        b[col] = total / a[col, col]
    return True


@njit(cache=True, error_model="numpy")
def phase_states(p0, v0, a0, t, u, second_order, starts, states):
    """Start time and state (p, v, a, j) of each of the nine phases; returns the end time.

    Empty phases get the state where they stand (their successors start there).
    """
    return _integrate_from(0, p0, v0, a0, 0.0, t, u, second_order, starts, states)


@njit(cache=True, error_model="numpy")
def _integrate_from(first, p, v, a, clock, t, u, second_order, starts, states):
    """:func:`phase_states` from phase ``first`` on, starting at ``(p, v, a)`` at ``clock``."""
    for k in range(first, PHASES):
        tk = t[k]
        # An empty phase of a trapezoid holds no acceleration; a jerk phase keeps its jerk.
        a, j = _control(u[k] if (tk > 0.0 or not second_order) else 0.0, a, second_order)
        starts[k] = clock
        states[k, 0] = p
        states[k, 1] = v
        states[k, 2] = a
        states[k, 3] = j
        if tk > 0.0:
            p = p + tk * (v + tk * (a / 2.0 + tk * j / 6.0))
            v = v + tk * (a + tk * j / 2.0)
            a = a + tk * j
            clock += tk
    return clock


# Misses of the target position up to this fraction of the positions' size on the way
# are rounding (a velocity of size 16 carries 4e-15 rad/s of it over a 1e6 s coast).
ROUNDING_MISS_RTOL = 1e-12


@njit(cache=True, error_model="numpy")
def _land(pf, t, u, second_order, starts, states):
    """Absorb a rounding-level miss of ``pf`` in the velocity of the longest phase.

    Returns False where the phases miss ``pf`` by more than rounding (or than the
    laws' precision), or where taking it would change a velocity by more than its
    own rounding.

    Integrating the phases accumulates rounding over long phases (1e-9 rad after a
    1e6 s coast that began at 16 rad/s); the longest phase's velocity takes the
    correction (by 1e-15 rad/s there), and the phases after it end on ``pf``. The
    first phase starts in the boundary state, which stays exact: the longest of the
    others takes it (none: nothing lands).
    """
    longest = -1
    first = -1
    size = 0.0
    speed = 0.0
    last = -1
    for k in range(PHASES):
        if t[k] > 0.0:
            last = k
            if first < 0:
                first = k
            elif longest < 0 or t[k] > t[longest]:
                longest = k
            size = max(size, abs(states[k, 0]), abs(states[k, 1]) * t[k])
            speed = max(speed, abs(states[k, 1]), abs(states[k, 2]) * t[k])
    if last < 0:
        return True
    p, v, a, j = states[last, 0], states[last, 1], states[last, 2], states[last, 3]
    tk = t[last]
    miss = pf - (p + tk * (v + tk * (a / 2.0 + tk * j / 6.0)))
    if miss == 0.0:
        return True
    if longest < 0:
        return False
    # A miss the laws accept (their absolute precision) or a rounding of the positions;
    # an 8e6 s coast at -1.4e-13 rad/s misses by 1.7e-13 rad, above the rounding of its
    # 2e-6 rad excursion but far inside the 1e-8 rad the law accepted.
    if not abs(miss) <= max(ROUNDING_MISS_RTOL * (size + abs(pf)), P_PRECISION):
        return False
    correction = miss / t[longest]
    # The velocity must take a rounding of itself, too: a move of 2e-14 s planned at
    # 0.875 rad/s (a peak rounded up by one unit) misses by 2e-14 rad, rounding for the
    # positions, but would need -1.75 rad/s of correction.
    if not abs(correction) <= ROUNDING_MISS_RTOL * speed:
        return False
    states[longest, 1] += correction
    tl = t[longest]
    p, v, a, j = states[longest, 0], states[longest, 1], states[longest, 2], states[longest, 3]
    _integrate_from(
        longest + 1,
        p + tl * (v + tl * (a / 2.0 + tl * j / 6.0)),
        v + tl * (a + tl * j / 2.0),
        a + tl * j,
        starts[longest] + tl,
        t,
        u,
        second_order,
        starts,
        states,
    )
    return True


@njit(cache=True, error_model="numpy")
def _anchor_ends(target, t, u, second_order, finish, states, anchors):
    """Re-express the phases after the longest one from the end state backwards.

    ``states[k]`` of those phases becomes their end state and ``anchors[k]`` their
    end time (NaN elsewhere: phases described from their start). In absolute time
    a short last ramp at t = 1e4 s is resolved to about 1e-12 s only; described
    from its end it still ends exactly in the target state (a velocity limit
    reached exactly there is not overshot), and the rounding moves to where it
    meets the long phase, a jump far below any tolerance.
    """
    longest = 0
    for k in range(PHASES):
        anchors[k] = math.nan
        if t[k] > t[longest]:
            longest = k
    p, v, a = target[0], target[1], target[2]
    clock = finish
    for k in range(PHASES - 1, longest, -1):
        tk = t[k]
        if not tk > 0.0:
            continue
        a, j = _control(u[k], a, second_order)
        states[k, 0] = p
        states[k, 1] = v
        states[k, 2] = a
        states[k, 3] = j
        anchors[k] = clock
        p, v, a = integrate(-tk, p, v, a, j)
        clock -= tk


@njit(cache=True, error_model="numpy")
def _joint_tables(start, target, t, u, second, starts, states, finish, anchors):
    ndof = start.shape[1]
    for d in range(ndof):
        finish[d] = phase_states(
            start[0, d], start[1, d], start[2, d], t[d], u[d], second[d], starts[d], states[d]
        )
        if _land(target[0, d], t[d], u[d], second[d], starts[d], states[d]):
            _anchor_ends(target[:, d], t[d], u[d], second[d], finish[d], states[d], anchors[d])
        else:
            anchors[d, :] = math.nan  # described from the start: the end check sees the miss


@njit(cache=True, error_model="numpy")
def pieces(start, target, t, u, second, duration, breakpoints, coefficients, end):
    """One problem's tables as a piecewise cubic; returns the number of pieces ``m``.

    ``start`` and ``target`` are (3, ndof) (position, velocity, acceleration), ``t``
    and ``u`` (ndof, 9), ``second`` (ndof,) bool. Fills ``breakpoints`` (m + 1),
    ``coefficients`` (4, m, ndof) (local power basis, highest power first) and
    ``end`` (3, ndof): the exact target state where the pieces reach it up to
    rounding, NaN where the polynomial's own value must stand (a joint still
    coasting at the end, a trapezoid's acceleration). The arrays must hold
    ``PHASES * ndof + 2`` breakpoints. A negative count ``-m`` says the pieces miss
    a target (the motion is too long for its shortest phases in absolute time).
    """
    ndof = start.shape[1]
    starts = np.empty((ndof, PHASES))
    states = np.empty((ndof, PHASES, 4))
    finish = np.empty(ndof)
    anchors = np.empty((ndof, PHASES))
    _joint_tables(start, target, t, u, second, starts, states, finish, anchors)
    count = 0
    breakpoints[count] = 0.0
    count += 1
    for d in range(ndof):
        for k in range(PHASES):
            if t[d, k] > 0.0:
                edge = starts[d, k] + t[d, k]
                if 0.0 < edge < duration:
                    breakpoints[count] = edge
                    count += 1
    breakpoints[count] = duration
    count += 1
    # Sort (a few dozen entries, one sorted run per joint) and merge near-duplicates.
    breakpoints[:count].sort()
    merged = 1
    for k in range(1, count):
        if breakpoints[k] - breakpoints[merged - 1] > MERGE * duration:
            breakpoints[merged] = breakpoints[k]
            merged += 1
    if merged >= 2 and duration - breakpoints[merged - 2] <= MERGE * duration:
        merged -= 1
    breakpoints[merged - 1] = duration
    if merged < 2:
        breakpoints[0] = 0.0
        breakpoints[1] = duration
        merged = 2
    m = merged - 1
    # Each joint's phase covering the piece: the pieces come in time order, so a
    # cursor per joint only moves on.
    phase = np.zeros(ndof, np.int64)
    for k in range(m):
        left = breakpoints[k]
        middle = 0.5 * (left + breakpoints[k + 1])
        for d in range(ndof):
            if middle >= finish[d]:
                # Past its own end: on from the target state at constant acceleration,
                # as ruckig continues a finished joint (a trapezoid's target holds none).
                a = 0.0 if second[d] else target[2, d]
                p, v, j, x = target[0, d], target[1, d], 0.0, left - finish[d]
            else:
                q = phase[d]
                for r in range(q + 1, PHASES):
                    if starts[d, r] > middle:
                        break  # phases start in time order
                    if t[d, r] > 0.0:
                        q = r
                phase[d] = q
                p, v, a, j = states[d, q, 0], states[d, q, 1], states[d, q, 2], states[d, q, 3]
                anchor = anchors[d, q]
                x = left - (starts[d, q] if math.isnan(anchor) else anchor)
            coefficients[0, k, d] = j / 6.0
            coefficients[1, k, d] = (a + j * x) / 2.0
            coefficients[2, k, d] = v + x * (a + x * j / 2.0)
            coefficients[3, k, d] = p + x * (v + x * (a / 2.0 + x * j / 6.0))
    if not _end_state(target, breakpoints, coefficients, m, finish, duration, second, end):
        return -m
    return m


@njit(cache=True, error_model="numpy")
def _end_state(target, breakpoints, coefficients, m, finish, duration, second, end):
    """The exact end state where the pieces agree with it (Trajectory's tolerance).

    Where they miss it by no more than a shift of their breakpoints by a few units
    in the last place explains (phases too short for absolute time at this
    duration), the pieces' own value stands. Returns False where they miss by
    more: they lost a target they must reach.
    """
    ndof = target.shape[1]
    resolved = True
    h = breakpoints[m] - breakpoints[m - 1]
    for d in range(ndof):
        c3 = coefficients[0, m - 1, d]
        c2 = coefficients[1, m - 1, d]
        c1 = coefficients[2, m - 1, d]
        c0 = coefficients[3, m - 1, d]
        values = (
            c0 + h * (c1 + h * (c2 + h * c3)),
            c1 + h * (2.0 * c2 + h * 3.0 * c3),
            2.0 * c2 + h * 6.0 * c3,
        )
        sizes = _sizes(breakpoints, coefficients, m, d)
        # A joint done early coasts on at constant acceleration: how far its position
        # and velocity move from the target state by the end.
        coast = duration - finish[d]
        early = coast > REUSE_WITHIN + _TIME_ULPS * EPS * duration
        carried = 0.0 if second[d] else abs(target[2, d]) * coast
        moved = (abs(target[1, d]) * coast + 0.5 * carried * coast, carried, 0.0)
        for order in range(3):
            scale = sizes[order]  # the size of this derivative's terms anywhere in the motion
            rate = sizes[order + 1]
            value = target[order, d]
            scale += abs(value)
            if order == 2 and second[d]:
                value = math.nan  # a trapezoid's acceleration jumps: no exact value
            elif early and moved[order] > _TIME_ULPS * EPS * scale:
                # Still coasting from its target state, elsewhere: done earlier than
                # a reused fastest profile and rounding explain, and moved on by more
                # than the rounding of values this large (the boundary tolerance
                # could hide a real coast). Found by hypothesis: a joint whose fastest
                # profile was reused for a duration set by another, 2.9e-17 rad longer,
                # move was done 1.5e-16 s early and had coasted 3.8e-17 rad on.
                value = math.nan
            miss = abs(value - values[order])
            if miss > BOUNDARY_RTOL * scale + BOUNDARY_ATOL:
                if not miss <= _TIME_ULPS * EPS * duration * rate:
                    resolved = False
                value = math.nan
            end[order, d] = value
    return resolved


# A miss of the end state this many units in the last place of the duration, times
# the next derivative, is the pieces' rounding in absolute time, not a lost target.
_TIME_ULPS = 16.0


@njit(cache=True, error_model="numpy")
def _sizes(breakpoints, coefficients, m, d):
    """The largest size of each derivative's terms (orders 0 to 3) on the ``m`` pieces."""
    p = v = a = j = 0.0
    for k in range(m):
        h = breakpoints[k + 1] - breakpoints[k]
        c3 = abs(coefficients[0, k, d])
        c2 = abs(coefficients[1, k, d])
        c1 = abs(coefficients[2, k, d])
        c0 = abs(coefficients[3, k, d])
        p = max(p, c0 + h * (c1 + h * (c2 + h * c3)))
        v = max(v, c1 + h * (2.0 * c2 + h * 3.0 * c3))
        a = max(a, 2.0 * c2 + h * 6.0 * c3)
        j = max(j, 6.0 * c3)
    return p, v, a, j


@njit(cache=True, error_model="numpy", parallel=True)
def evaluate_batch(m, t, u, second, durations, times, order, out):
    """Derivative ``order`` of every problem at ``times``: ``out`` (B, m, ndof).

    ``m`` is the batch's problem matrix (B, 11, ndof), its rows q0, v0, a0 the
    start and qf, vf, af the target of each problem (read in place: copies of
    them would be a third of a large batch's memory). Each problem is turned into
    its pieces by :func:`pieces` and evaluated as its :class:`trajkit.Trajectory`
    would be: times clamped to ``[0, duration]``, the exact end state from the end
    on where the pieces reach it. A problem whose pieces miss a target (too long
    for its short phases in absolute time, which ``batch[i]`` refuses) gets NaN.
    """
    count = m.shape[0]
    ndof = m.shape[2]
    size = PHASES * ndof + 2
    for i in prange(count):
        breakpoints = np.empty(size)
        coefficients = np.empty((4, size - 1, ndof))
        end = np.empty((3, ndof))
        start = np.empty((3, ndof))
        target = np.empty((3, ndof))
        for k in range(3):
            for d in range(ndof):
                start[k, d] = m[i, 2 * k, d]
                target[k, d] = m[i, 2 * k + 1, d]
        duration = durations[i]
        n_pieces = pieces(
            start, target, t[i], u[i], second[i], duration, breakpoints, coefficients, end
        )
        if n_pieces < 0:  # pieces that miss a target (problem i refuses them): no values
            out[i] = math.nan
            continue
        for k in range(times.shape[0]):
            clock = min(max(times[k], 0.0), duration)
            piece = 0
            while piece < n_pieces - 1 and breakpoints[piece + 1] <= clock:
                piece += 1
            x = clock - breakpoints[piece]
            for d in range(ndof):
                if clock >= duration and order < 3 and not math.isnan(end[order, d]):
                    out[i, k, d] = end[order, d]
                    continue
                c3 = coefficients[0, piece, d]
                c2 = coefficients[1, piece, d]
                c1 = coefficients[2, piece, d]
                c0 = coefficients[3, piece, d]
                if order == 0:
                    value = c0 + x * (c1 + x * (c2 + x * c3))
                elif order == 1:
                    value = c1 + x * (2.0 * c2 + x * 3.0 * c3)
                elif order == 2:
                    value = 2.0 * c2 + x * 6.0 * c3
                else:
                    value = 6.0 * c3
                out[i, k, d] = value


@njit(cache=True, error_model="numpy")
def stretches(t, u, times, accelerations):
    """An acceleration-limited joint's profile as rise, coast and fall.

    ``t``, ``u`` are its nine phases (durations, accelerations); the brake phases
    (the first two) are left out. Acceleration-limited profiles accelerate in
    profile phase 0, coast in phases 1, 3 and 5 and accelerate again in phases 2,
    4 and 6, of which at most one is used: rise, coast and fall by the phases'
    roles (a joint following a phase-synchronized law keeps the law's phase times
    even where its own move is zero). Fills ``times`` (3,) and ``accelerations``
    (2,); returns False for a profile outside that pattern (which the engine
    never plans: a defect to report).
    """
    times[0] = t[2]
    times[1] = t[3] + t[5] + t[7]
    times[2] = 0.0
    accelerations[0] = u[2] if t[2] > 0.0 else 0.0
    accelerations[1] = 0.0
    falls = 0
    for k in (4, 6, 8):
        if t[k] > 0.0:
            falls += 1
            times[2] += t[k]
            accelerations[1] = u[k]
    return falls <= 1


@njit(cache=True, error_model="numpy", parallel=True)
def stretches_batch(t, u, times, accelerations, ok):
    """:func:`stretches` for (B, ndof) joints; ``ok`` (B, ndof) says where it fitted."""
    for i in prange(t.shape[0]):
        for d in range(t.shape[1]):
            ok[i, d] = stretches(t[i, d], u[i, d], times[i, d], accelerations[i, d])


@njit(cache=True, error_model="numpy", parallel=True)
def velocities_at_phases(start, t, u, second, v):
    """Velocity at the start of each of the nine phases: ``v`` (B, ndof, 9)."""
    for i in prange(t.shape[0]):
        for d in range(t.shape[1]):
            vel = start[i, 1, d]
            acc = start[i, 2, d]
            for k in range(PHASES):
                v[i, d, k] = vel
                tk = t[i, d, k]
                if tk <= 0.0:
                    continue
                if second[i, d]:
                    vel += tk * u[i, d, k]
                else:
                    vel += tk * (acc + tk * u[i, d, k] / 2.0)
                    acc += tk * u[i, d, k]
