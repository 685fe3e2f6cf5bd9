"""Entry points: one problem to its pieces, a batch of problems to phase tables.

Each runs the whole pipeline in one compiled call (the cost of a call from Python
is paid once): plan every joint (:mod:`.synchronize`), write each joint's phase
table (:mod:`.tables`), and for one problem build the piecewise cubic.
"""

import numpy as np
from numba import njit, prange

from trajkit.profiles._kernels import profile, quantize, synchronize, tables
from trajkit.profiles._kernels.admissible import A0, A_MAX, A_MIN, J_MAX, Q0, V0, V_MIN, admissible
from trajkit.profiles._kernels.layout import BRAKE_DURATION, SIZE, T_SUM, P
from trajkit.profiles._kernels.synchronize import POSITION

# Status of one(): the plan is found but its pieces cannot keep it in absolute time.
UNRESOLVED = 7
# Status of quick(): the problem is not one the planners accept (the validators say why).
INADMISSIBLE = 8
# quick()'s flags: the rows v_min, a_min hold magnitudes, to be negated.
NEGATE_V_MIN = 1
NEGATE_A_MIN = 2


@njit(cache=True, error_model="numpy")
def _plan(m, control, sync, enabled, min_duration, dt, switches, records, own, out):
    if switches and dt > 0.0:
        return quantize.plan_on_grid(m, control, sync, enabled, min_duration, dt, records, own, out)
    return synchronize.plan(m, control, sync, enabled, min_duration, dt, records, own, out)


@njit(cache=True, error_model="numpy")
def one(
    m,
    control,
    sync,
    enabled,
    min_duration,
    dt,
    switches,
    records,
    own,
    out,
    t,
    u,
    breakpoints,
    coefficients,
    end,
):
    """Plan one problem and build its pieces; returns ``(status, number of pieces)``.

    Arguments as :func:`synchronize.plan`, plus ``switches`` (with ``dt > 0``:
    every switching time on the period grid, :func:`quantize.plan_on_grid`; else
    only the duration), the phase tables ``t``, ``u`` (ndof, 9) and the piece
    arrays of :func:`tables.pieces` to fill.
    """
    status = _plan(m, control, sync, enabled, min_duration, dt, switches, records, own, out)
    if status != synchronize.OK:
        return status, 0
    ndof = m.shape[1]
    second = np.empty(ndof, np.bool_)
    for d in range(ndof):
        second[d] = np.isinf(m[J_MAX, d])
        tables.compact(records[d], second[d], t[d], u[d])
    start = np.empty((3, ndof))
    target = np.empty((3, ndof))
    for d in range(ndof):
        start[0, d] = m[0, d]
        start[1, d] = m[2, d]
        start[2, d] = m[4, d]
        target[0, d] = m[1, d]
        target[1, d] = m[3, d]
        target[2, d] = m[5, d]
    for d in range(ndof):
        if not (switches and dt > 0.0):  # on the grid every switch stays a whole period
            tables.polish(
                start[:, d],
                target[:, d],
                t[d],
                u[d],
                second[d],
                control[d] == POSITION,
                m[V_MIN : A_MAX + 1, d],
            )
        if control[d] != POSITION:
            # No position target: the motion ends wherever its (polished) phases take it.
            target[0, d] = tables.end_position(start[:, d], t[d], u[d], second[d])
    count = tables.pieces(
        start, target, t, u, second, out[synchronize.OUT_DURATION], breakpoints, coefficients, end
    )
    if count < 0:
        return UNRESOLVED, -count
    return status, count


def plan_layout(ndof):
    """Offsets in :func:`quick`'s flat plan: matrix, records, own, out, t, u; its size."""
    matrix = 0
    records = matrix + 11 * ndof
    own = records + ndof * SIZE
    out = own + ndof
    t = out + synchronize.OUT_SIZE
    u = t + ndof * tables.PHASES
    return matrix, records, own, out, t, u, u + ndof * tables.PHASES


plan_layout_compiled = njit(cache=True)(plan_layout)


@njit(cache=True, error_model="numpy")
def quick(q0, qf, v0, vf, a0, af, v_low, v_high, a_low, a_high, j_max, negate, codes):
    """One problem with default options, from its rows to its pieces in one call.

    The eleven rows of :func:`one`'s matrix come as vectors (not copied by the
    caller: they are only read), ``v_low`` and ``a_low`` as magnitudes where
    ``negate`` says so; ``codes`` (3, ndof) holds the rows control, sync,
    enabled. Checks the problem (lengths, :func:`.admissible.admissible`) and
    plans it: returns ``(status, count, breakpoints, coefficients, end, plan)``,
    ``plan`` the flat matrix, records, own durations, summary and phase tables at
    :func:`plan_layout`'s offsets.
    """
    ndof = q0.shape[0]
    o_m, o_records, o_own, o_out, o_t, o_u, size = plan_layout_compiled(ndof)
    plan = np.empty(size)
    pieces = tables.PHASES * ndof + 1
    breakpoints = np.empty(pieces + 1)
    coefficients = np.empty((4, pieces, ndof))
    end = np.empty((3, ndof))
    m = plan[o_m:o_records].reshape((11, ndof))
    rows = (q0, qf, v0, vf, a0, af, v_low, v_high, a_low, a_high, j_max)
    fits = codes.shape[1] == ndof
    for r in range(11):
        row = rows[r]
        if row.shape[0] != ndof:
            fits = False
            break
        for d in range(ndof):
            m[r, d] = row[d]
    if fits:
        for d in range(ndof):
            if negate & NEGATE_V_MIN:
                m[V_MIN, d] = -m[V_MIN, d]
            if negate & NEGATE_A_MIN:
                m[A_MIN, d] = -m[A_MIN, d]
    if not (fits and admissible(m)):
        return INADMISSIBLE, 0, breakpoints[:1], coefficients[:, :0], end, plan
    status, count = one(
        m,
        codes[0],
        codes[1],
        codes[2],
        np.nan,
        0.0,
        True,
        plan[o_records:o_own].reshape((ndof, SIZE)),
        plan[o_own:o_out],
        plan[o_out:o_t],
        plan[o_t:o_u].reshape((ndof, tables.PHASES)),
        plan[o_u:size].reshape((ndof, tables.PHASES)),
        breakpoints,
        coefficients,
        end,
    )
    return status, count, breakpoints[: count + 1], coefficients[:, :count], end, plan


# Problems per task of a batch: each task allocates its scratch records once.
CHUNK = 64


@njit(cache=True, error_model="numpy", parallel=True)
def batch(m, control, sync, enabled, min_duration, dt, switches, t, u, own, out, status):
    """Plan ``B`` problems in parallel into phase tables ``t``, ``u`` (B, ndof, 9).

    A joint under the velocity interface (``control`` 1) has its row qf of ``m``
    overwritten with the position its motion ends at.
    """
    count = m.shape[0]
    ndof = m.shape[2]
    for c in prange((count + CHUNK - 1) // CHUNK):
        records = np.empty((ndof, SIZE))
        for i in range(c * CHUNK, min(count, (c + 1) * CHUNK)):
            status[i] = _plan(
                m[i],
                control[i],
                sync[i],
                enabled[i],
                min_duration[i],
                dt,
                switches,
                records,
                own[i],
                out[i],
            )
            if status[i] != synchronize.OK:
                continue
            for d in range(ndof):
                second = np.isinf(m[i, J_MAX, d])
                tables.compact(records[d], second, t[i, d], u[i, d])
                if not (switches and dt > 0.0):
                    tables.polish(
                        m[i, 0:5:2, d],  # rows q0, v0, a0 (views: no allocation per joint)
                        m[i, 1:6:2, d],  # rows qf, vf, af
                        t[i, d],
                        u[i, d],
                        second,
                        control[i, d] == POSITION,
                        m[i, V_MIN : A_MAX + 1, d],
                    )
                if control[i, d] != POSITION:
                    # No position target: the row qf takes where the phases end, so that
                    # the batch evaluates (and `batch[i]` builds) as one problem does.
                    m[i, 1, d] = tables.end_position(m[i, 0:5:2, d], t[i, d], u[i, d], second)


@njit(cache=True, error_model="numpy")
def _plan_online(m, control, sync, enabled, records, own, out):
    """Plan from the current state; a joint that cannot take the common duration moves alone.

    The timed law fails near the end of some moves planned afresh from where an
    earlier plan left them; that joint moves on its own then, and the next plan
    synchronizes again.
    """
    status = synchronize.plan(m, control, sync, enabled, np.nan, 0.0, records, own, out)
    relaxed = sync
    copied = False
    for _ in range(m.shape[1]):
        if status != synchronize.STEP2_FAILED or out[synchronize.OUT_JOINT] < 0:
            break
        if not copied:
            relaxed = sync.copy()
            copied = True
        relaxed[int(out[synchronize.OUT_JOINT])] = synchronize.SYNC_NONE
        status = synchronize.plan(m, control, relaxed, enabled, np.nan, 0.0, records, own, out)
    return status


@njit(cache=True, error_model="numpy")
def _sample_online(m, control, records, duration, time, state):
    """The planned state ``time`` s after the plan's start into ``state`` (3, ndof).

    Past the end the target itself (a velocity target: coasting on at it).
    """
    for d in range(m.shape[1]):
        if time >= duration:
            state[1, d] = m[3, d]
            state[2, d] = m[5, d]
            if control[d] == POSITION:
                state[0, d] = m[1, d]
            else:
                rest = time - duration
                state[0, d] = records[d, P + 7] + rest * (m[3, d] + rest * m[5, d] / 2.0)
                state[1, d] = m[3, d] + rest * m[5, d]
            continue
        p, v, a, _ = profile.state_at(records[d], time)
        if np.isinf(m[J_MAX, d]) and time >= records[d, T_SUM + 6] + records[d, BRAKE_DURATION]:
            a = 0.0  # past a trapezoid's end it coasts
        state[0, d] = p
        state[1, d] = v
        state[2, d] = a


# Fields of an online generator's memo: whether it holds a plan, the plan's control
# interface, the time since the plan started, its duration left when the last cycle
# began; then the target rows it was planned for and the state the last cycle left
# (rows qf, vf, af and q0, v0, a0 of the problem, ndof each).
MEMO_HELD = 0
MEMO_CONTROL = 1
MEMO_ELAPSED = 2
MEMO_REMAINING = 3
MEMO_ROWS = 4
_TARGET_ROWS = (1, 3, 5)
_STATE_ROWS = (0, 2, 4)


def memo_size(ndof):
    """Length of an online generator's memo for ``ndof`` joints."""
    return MEMO_ROWS + 6 * ndof


@njit(cache=True, error_model="numpy")
def _memo_matches(m, rows, memo, offset):
    ndof = m.shape[1]
    for k in range(3):
        for d in range(ndof):
            if m[rows[k], d] != memo[offset + k * ndof + d]:
                return False
    return True


@njit(cache=True, error_model="numpy")
def _remember(m, rows, memo, offset):
    ndof = m.shape[1]
    for k in range(3):
        for d in range(ndof):
            memo[offset + k * ndof + d] = m[rows[k], d]


@njit(cache=True, error_model="numpy")
def online_cycle(m, control, sync, enabled, period, records, own, out, state, acceleration, memo):
    """One control cycle: the state one ``period`` on, made the current one.

    As ruckig's online update: a plan is made when the target (or the state, or
    the control interface) differs from what the held plan was made for, and
    followed otherwise, so that a fixed target is planned once and its motion is
    that one plan, sampled. ``m``'s rows q0, v0 and ``acceleration`` hold the
    current state and take the new one (row a0 follows ``acceleration``, except
    that an acceleration-limited joint carries no acceleration into a plan);
    ``records``, ``own``, ``out`` and ``memo`` (:func:`memo_size`) persist
    between cycles. Returns the status, ``INADMISSIBLE`` where the validators
    must say why; the state changes only on success.
    """
    ndof = m.shape[1]
    for d in range(ndof):  # the reported acceleration is the state (a caller may set it)
        if not np.isinf(m[J_MAX, d]):
            m[A0, d] = acceleration[d]
    held = (
        memo[MEMO_HELD] == 1.0
        and memo[MEMO_CONTROL] == control[0]
        and _memo_matches(m, _TARGET_ROWS, memo, MEMO_ROWS)
        and _memo_matches(m, _STATE_ROWS, memo, MEMO_ROWS + 3 * ndof)
    )
    elapsed = memo[MEMO_ELAPSED]
    if not held:
        memo[MEMO_HELD] = 0.0
        if not admissible(m):
            return INADMISSIBLE
        status = _plan_online(m, control, sync, enabled, records, own, out)
        if status != synchronize.OK:
            return status
        memo[MEMO_HELD] = 1.0
        memo[MEMO_CONTROL] = control[0]
        _remember(m, _TARGET_ROWS, memo, MEMO_ROWS)
        elapsed = 0.0
    duration = out[synchronize.OUT_DURATION]
    memo[MEMO_REMAINING] = duration - elapsed
    elapsed += period
    _sample_online(m, control, records, duration, elapsed, state)
    for d in range(ndof):
        m[Q0, d] = state[0, d]
        m[V0, d] = state[1, d]
        acceleration[d] = state[2, d]
        m[A0, d] = 0.0 if np.isinf(m[J_MAX, d]) else state[2, d]
    memo[MEMO_ELAPSED] = elapsed
    _remember(m, _STATE_ROWS, memo, MEMO_ROWS + 3 * ndof)
    return synchronize.OK
