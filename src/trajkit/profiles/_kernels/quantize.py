"""Profiles on a controller grid: every switching time a whole number of periods.

A controller that samples every ``dt`` seconds can only switch its jerk (second
order: its acceleration) at the grid points. Given a continuous profile record
(its boundary, brake pre-profile and structure), :func:`quantize_joint` finds a
profile of exactly ``n`` periods whose every phase, brake phases included, lasts
a whole number of periods, that reaches the target state exactly (to rounding:
1e-12 of the size of the terms that make it up) and keeps every limit over the
whole profile (velocity extrema inside phases included; relative slack 1e-12).
:func:`plan_on_grid` does that for all joints of a problem on top of
:func:`~trajkit.profiles._kernels.synchronize.plan`, :func:`plan_on_grid_batch`
for a batch of problems in parallel.

Third order. With the phase durations fixed as whole periods the end state is
affine in the jerks of the phases. The seven phases keep their roles: phases 0,
2, 4 and 6 ramp (each with a jerk of its own, the unknowns), phases 1, 3 and 5
hold their acceleration (jerk 0). The end position, velocity and acceleration
are three linear equations in the four ramp jerks, whose solutions form a line
``u_p + lam w``. Every edge acceleration and velocity is affine in ``lam`` too,
so the limits on them and on the jerks cut the line down to an interval; on it
the largest ``|jerk|`` is a convex piecewise-linear function of ``lam``, whose
minimum is found exactly. Velocity extrema inside ramps (where the acceleration
crosses zero) are not affine in ``lam``; where the gentlest jerks break one, the
``lam`` at which an edge acceleration vanishes (where such extrema appear and
vanish) and the interval's ends are tried. The phase counts come from two
continuous profiles: the one re-planned to take exactly ``n`` periods
(:func:`~trajkit.profiles._kernels.jerk_timed.timed`) and the given one. Ramps
are rounded up, holds to the nearest period, and the longest hold (the coast)
takes the rest; around that base every ramp moves by up to one period and
every other hold by up to two, in rings of growing total change (ring r: the
changes add up to r periods), and the search stops at the first ring that has a
valid candidate, keeping the one of smallest largest ``|jerk| / j_max``. Where
none is valid, a third centre splits a single ramp of a velocity change into
whole periods at full jerk followed by one period for the rest (a ramp tight on
a velocity limit then overshoots its grid by part of one period only).

Second order (``j_max = inf``): an acceleration phase, a coast, an acceleration
phase (record phases 0, 1, 2); with the counts fixed, the end velocity and
position are two linear equations in the two accelerations. Counts from -3 to
+8 periods around both continuous profiles' ramps are tried, the coast taking
the rest, and the valid candidate of smallest ``|coast velocity|`` is kept (the
peak velocity as low as the period allows, the accelerations as close to their
limits), as the numpy implementation before it did.

Brakes (a start beyond the limits). Third order: the brake ramp is rounded up
with its jerk eased to end at the continuous ramp's acceleration, or rounded up
or down at its jerk; its hold takes the periods that bring the velocity where
the continuous brake brings it (or one more or fewer). Second order: the brake
is rounded up and ends at the continuous brake's velocity. Before the third
switching time of the seven phases (for the acceleration: at their start) the
limits hold only as far as the continuous profile keeps them there: a brake
can leave the velocity beyond its limit, to be brought back by the first
phases, and the grid profile may then be beyond them as far as the continuous
one is, no further (the continuous check admits the same).

Measured excess of :func:`plan_on_grid` over the continuous optimum, in periods
(the slow tests of ``tests/kernels/test_quantize.py``; moving targets measured
from the end of a blocked interval the grid duration had to skip):

* trapezoids at rest: always ``N <= ceil(T / dt) + 1``, so under 2 periods
  (worst measured 1.92 of 6,000 single joints, 1.95 of 100,000 six-joint
  problems);
* S-curves at rest: under 3 periods. A move shorter than a period needs 3 (no
  two-period rest-to-rest move exists), so that bound is reached in the limit;
  otherwise never more than ``ceil(T / dt) + 2`` was found, worst measured 1.99
  (6,000 single joints, symmetric and asymmetric limits), 2.27 (100,000
  six-joint problems), 2.24 (20,000 single joints); the numpy implementation's
  case at 2.0022 stays at 2.0022;
* moving boundaries without a brake, S-curves: median 1.0, 99% 2.5 to 3.3,
  worst 9.5 (a period coarse against the profile: ramps of half a period that
  must take a whole one); 1 in 1,000 to 2,000 finds no grid profile
  (``GRID_FAILED``); trapezoids: worst 2.08;
* brakes (a start beyond the limits) can cost more, worst measured 17 periods
  and about 1 in 40 such S-curve problems failing: a brake cannot land on the
  grid where the continuous one ends, and the position it gains or loses at a
  velocity far beyond the limit is made up at the velocity limit.

Speed (``plan_on_grid_batch``, 100,000 rest-to-rest six-joint problems, 2
cores): about 2,900 problems/s for S-curves and 18,000/s for trapezoids.
"""

import math

import numpy as np
from numba import njit, prange

from trajkit.profiles._kernels import acceleration_limited, jerk_timed, synchronize
from trajkit.profiles._kernels import admissible as rows
from trajkit.profiles._kernels.layout import (
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
    UP,
    VF,
    A,
    J,
    P,
    T,
    V,
)

# Status codes beyond those of synchronize.plan (OK ... STEP2_FAILED = 4).
GRID_FAILED = 5  # no whole-period profile within MAX_EXTRA_PERIODS of the continuous one
VELOCITY_UNSUPPORTED = 6  # a joint under the velocity interface (not quantized)

#: How many periods past the continuous duration (rounded up) are tried.
MAX_EXTRA_PERIODS = 16
#: Rows of the scratch array :func:`quantize_joint` needs.
WORK_ROWS = 2

# Limits are kept to this relative slack (the search aims inside a tighter one,
# so that rounding cannot carry a chosen profile past the check), and the end
# state is reached to this fraction of the size of the terms that make it up.
_LIMIT_SLACK = 1e-12
_SEARCH_SLACK = 1e-13
_STATE_TOLERANCE = 1e-12
# A time within this many periods of a whole number is that number.
_ROUNDING = 1e-9
_EPS = 2.220446049250313e-16
# Second order: offsets (periods) tried around each continuous ramp.
_SECOND_LOW = -3
_SECOND_HIGH = 8

# Fields of a limits vector (bounds with their slack): velocity, acceleration,
# jerk; the "early" bounds hold at the first three edges of the seven phases
# (velocity) and at the first (acceleration), and admit a start that is beyond
# the limits because its brake could not bring it back (as the continuous check
# admits it).
_VH, _VL, _AH, _AL, _JH, _VHE, _VLE, _AHE, _ALE, _JMAX = range(10)
_LIM_SIZE = 10


# --------------------------------------------------------------------- small algebra
@njit(cache=True, error_model="numpy")
def _det3(a0, a1, a2, b0, b1, b2, c0, c1, c2):
    """Determinant of the 3x3 matrix of columns ``a``, ``b``, ``c``."""
    return a0 * (b1 * c2 - b2 * c1) - b0 * (a1 * c2 - a2 * c1) + c0 * (a1 * b2 - a2 * b1)


@njit(cache=True, error_model="numpy")
def _others(skip):
    """The three indices of 0..3 other than ``skip``, in order."""
    return (1 if skip == 0 else 0), (2 if skip <= 1 else 1), (3 if skip <= 2 else 2)


@njit(cache=True, error_model="numpy")
def _minor(col, skip):
    """Determinant of the three columns of ``col`` (4 x 3) other than ``skip``."""
    i0, i1, i2 = _others(skip)
    return _det3(col[i0, 0], col[i0, 1], col[i0, 2], col[i1, 0], col[i1, 1], col[i1, 2],
                 col[i2, 0], col[i2, 1], col[i2, 2])  # fmt: skip


@njit(cache=True, error_model="numpy")
def _norm3(col, k):
    return math.sqrt(col[k, 0] * col[k, 0] + col[k, 1] * col[k, 1] + col[k, 2] * col[k, 2])


@njit(cache=True, error_model="numpy")
def _solve_three(col, k0, k1, k2, b, x):
    """Solve with columns ``k0, k1, k2`` of ``col`` (Cramer); False if singular."""
    d = _det3(col[k0, 0], col[k0, 1], col[k0, 2], col[k1, 0], col[k1, 1], col[k1, 2],
              col[k2, 0], col[k2, 1], col[k2, 2])  # fmt: skip
    scale = _norm3(col, k0) * _norm3(col, k1) * _norm3(col, k2)
    if not abs(d) > 1e-13 * scale:
        return False
    x[k0] = _det3(b[0], b[1], b[2], col[k1, 0], col[k1, 1], col[k1, 2],
                  col[k2, 0], col[k2, 1], col[k2, 2]) / d  # fmt: skip
    x[k1] = _det3(col[k0, 0], col[k0, 1], col[k0, 2], b[0], b[1], b[2],
                  col[k2, 0], col[k2, 1], col[k2, 2]) / d  # fmt: skip
    x[k2] = _det3(col[k0, 0], col[k0, 1], col[k0, 2], col[k1, 0], col[k1, 1], col[k1, 2],
                  b[0], b[1], b[2]) / d  # fmt: skip
    return True


@njit(cache=True, error_model="numpy")
def _particular(col, active, count, b, x, w):
    """A solution ``x`` of ``sum_k x_k col[k] = b`` over the active columns; null vector ``w``.

    ``w`` is the null direction where all four columns are active (normalized to
    a largest entry of 1), else 0. With fewer than three active columns the
    least-squares solution is taken and its residual must vanish. False where
    there is no solution (or the system is singular).
    """
    for k in range(4):
        x[k] = 0.0
        w[k] = 0.0
    if count == 4:
        best = -1
        big = 0.0
        for k in range(4):
            m = _minor(col, k)
            w[k] = -m if k % 2 == 1 else m
            if abs(w[k]) > big:
                big = abs(w[k])
                best = k
        if best < 0:
            return False
        for k in range(4):
            w[k] /= big
        i0, i1, i2 = _others(best)
        return _solve_three(col, i0, i1, i2, b, x)
    if count == 3:
        skip = 0
        for k in range(4):
            if not active[k]:
                skip = k
        i0, i1, i2 = _others(skip)
        return _solve_three(col, i0, i1, i2, b, x)
    # Overdetermined: least squares, then the residual must vanish.
    if count == 2:
        k0 = -1
        k1 = -1
        for k in range(4):
            if active[k]:
                if k0 < 0:
                    k0 = k
                else:
                    k1 = k
        g00 = col[k0, 0] ** 2 + col[k0, 1] ** 2 + col[k0, 2] ** 2
        g11 = col[k1, 0] ** 2 + col[k1, 1] ** 2 + col[k1, 2] ** 2
        g01 = col[k0, 0] * col[k1, 0] + col[k0, 1] * col[k1, 1] + col[k0, 2] * col[k1, 2]
        r0 = col[k0, 0] * b[0] + col[k0, 1] * b[1] + col[k0, 2] * b[2]
        r1 = col[k1, 0] * b[0] + col[k1, 1] * b[1] + col[k1, 2] * b[2]
        det = g00 * g11 - g01 * g01
        if not abs(det) > 1e-15 * g00 * g11:
            return False
        x[k0] = (r0 * g11 - r1 * g01) / det
        x[k1] = (g00 * r1 - g01 * r0) / det
    elif count == 1:
        for k in range(4):
            if active[k]:
                g = col[k, 0] ** 2 + col[k, 1] ** 2 + col[k, 2] ** 2
                x[k] = (col[k, 0] * b[0] + col[k, 1] * b[1] + col[k, 2] * b[2]) / g
    for i in range(3):
        r = b[i]
        size = abs(b[i])
        for k in range(4):
            r -= col[k, i] * x[k]
            size += abs(col[k, i] * x[k])
        if not abs(r) <= 1e-9 * size + 1e-300:
            return False
    return True


@njit(cache=True, error_model="numpy")
def _cut(lo, hi, x0, x1, low, high):
    """Narrow ``[lo, hi]`` to the ``lam`` where ``low <= x0 + lam x1 <= high``."""
    if x1 > 0.0:
        lo = max(lo, (low - x0) / x1)
        hi = min(hi, (high - x0) / x1)
    elif x1 < 0.0:
        lo = max(lo, (high - x0) / x1)
        hi = min(hi, (low - x0) / x1)
    elif not (low <= x0 <= high):
        lo = math.inf
    return lo, hi


@njit(cache=True, error_model="numpy")
def _max_abs(u, w, active, lam):
    worst = 0.0
    for k in range(4):
        if active[k]:
            worst = max(worst, abs(u[k] + lam * w[k]))
    return worst


@njit(cache=True, error_model="numpy")
def _minimax(u, w, active):
    """The ``lam`` that minimizes ``max_k |u_k + lam w_k|`` (exact: at a kink)."""
    best = 0.0
    value = _max_abs(u, w, active, 0.0)
    for k in range(4):
        if not active[k] or w[k] == 0.0:
            continue
        trial = -u[k] / w[k]
        f = _max_abs(u, w, active, trial)
        if f < value:
            value = f
            best = trial
        for m in range(k + 1, 4):
            if not active[m]:
                continue
            for sign in (1.0, -1.0):
                den = w[k] - sign * w[m]
                if den == 0.0:
                    continue
                trial = -(u[k] - sign * u[m]) / den
                f = _max_abs(u, w, active, trial)
                if f < value:
                    value = f
                    best = trial
    return best


# ------------------------------------------------------------------ records and checks
@njit(cache=True, error_model="numpy")
def _fill_limits(lim, v_max, v_min, a_max, a_min, j_max, envelope, slack):
    """Bounds with ``slack`` (relative); the early ones widened to ``envelope``.

    ``envelope`` is ``(v_low, v_high, a_low, a_high)`` of a profile's start (see
    :func:`_envelope`).
    """
    sv = slack * max(abs(v_max), abs(v_min))
    sa = slack * max(abs(a_max), abs(a_min))
    lim[_VH] = v_max + sv
    lim[_VL] = v_min - sv
    lim[_AH] = a_max + sa
    lim[_AL] = a_min - sa
    lim[_JH] = j_max * (1.0 + slack)
    lim[_VLE] = min(v_min, envelope[0]) - sv
    lim[_VHE] = max(v_max, envelope[1]) + sv
    lim[_ALE] = min(a_min, envelope[2]) - sa
    lim[_AHE] = max(a_max, envelope[3]) + sa
    lim[_JMAX] = j_max


@njit(cache=True, error_model="numpy")
def _envelope(prof, third):
    """Velocity and acceleration range of an integrated record before its limits hold.

    That is the brake, the first two of the seven phases and the edge after them
    for the velocity, the brake and the start of the seven phases for the
    acceleration: where the start is beyond the limits, the continuous profile
    itself is beyond them there. Returns ``(v_low, v_high, a_low, a_high)``.
    """
    v_lo = prof[V]
    v_hi = prof[V]
    a_lo = prof[A]
    a_hi = prof[A]
    if prof[BRAKE_DURATION] > 0.0:
        phases = 2 if third else 1
        for k in range(phases):
            v = prof[BRAKE_V + k]
            v_lo = min(v_lo, v)
            v_hi = max(v_hi, v)
            a = prof[BRAKE_A + k]
            a_lo = min(a_lo, a)
            a_hi = max(a_hi, a)
            if third:
                t = prof[BRAKE_T + k]
                j = prof[BRAKE_J + k]
                if j != 0.0 and a * (a + j * t) < 0.0:
                    v_ext = v - a * a / (2.0 * j)
                    v_lo = min(v_lo, v_ext)
                    v_hi = max(v_hi, v_ext)
    for i in range(3):
        v = prof[V + i]
        v_lo = min(v_lo, v)
        v_hi = max(v_hi, v)
        if third and i < 2:
            a = prof[A + i]
            j = prof[J + i]
            if j != 0.0 and a * prof[A + i + 1] < 0.0:
                v_ext = v - a * a / (2.0 * j)
                v_lo = min(v_lo, v_ext)
                v_hi = max(v_hi, v_ext)
    return v_lo, v_hi, a_lo, a_hi


@njit(cache=True, error_model="numpy")
def _integrate_third(rec):
    """Edge states of the brake and the seven phases from the start and the jerks."""
    braked = rec[BRAKE_DURATION] > 0.0
    p = rec[BRAKE_P] if braked else rec[P]
    v = rec[BRAKE_V] if braked else rec[V]
    a = rec[BRAKE_A] if braked else rec[A]
    if braked:
        for k in range(2):
            t = rec[BRAKE_T + k]
            j = rec[BRAKE_J + k]
            rec[BRAKE_P + k] = p
            rec[BRAKE_V + k] = v
            rec[BRAKE_A + k] = a
            p, v, a = (p + t * (v + t * (a / 2.0 + t * j / 6.0)), v + t * (a + t * j / 2.0),
                       a + j * t)  # fmt: skip
    rec[P] = p
    rec[V] = v
    rec[A] = a
    for i in range(7):
        t = rec[T + i]
        j = rec[J + i]
        p, v, a = (p + t * (v + t * (a / 2.0 + t * j / 6.0)), v + t * (a + t * j / 2.0),
                   a + j * t)  # fmt: skip
        rec[P + i + 1] = p
        rec[V + i + 1] = v
        rec[A + i + 1] = a


@njit(cache=True, error_model="numpy")
def _integrate_second(rec):
    """Edge velocities and positions of a second-order record (``a[i]`` during phase i)."""
    braked = rec[BRAKE_DURATION] > 0.0
    p = rec[BRAKE_P] if braked else rec[P]
    v = rec[BRAKE_V] if braked else rec[V]
    if braked:
        t = rec[BRAKE_T]
        a = rec[BRAKE_A]
        p, v = p + t * (v + t * a / 2.0), v + t * a
    rec[P] = p
    rec[V] = v
    for i in range(7):
        t = rec[T + i]
        a = rec[A + i]
        p, v = p + t * (v + t * a / 2.0), v + t * a
        rec[P + i + 1] = p
        rec[V + i + 1] = v


@njit(cache=True, error_model="numpy")
def _reached(rec, sa):
    """Whether the record ends at its target velocity and position, to the size of their terms.

    ``sa`` bounds the size of the acceleration's contribution to the velocity.
    """
    sv = 0.0
    sp = 0.0
    for i in range(8):
        sv = max(sv, abs(rec[V + i]))
        sp = max(sp, abs(rec[P + i]))
    total = rec[T_SUM + 6]
    sv += sa * total
    sp += sv * total
    return (
        abs(rec[V + 7] - rec[VF]) <= _STATE_TOLERANCE * sv + 1e-300
        and abs(rec[P + 7] - rec[PF]) <= _STATE_TOLERANCE * sp + 1e-300
    )


@njit(cache=True, error_model="numpy")
def _reached_third(rec):
    """Whether the record ends at its target, to the size of the terms that make the end up."""
    sa = 0.0
    jmax = 0.0
    for i in range(8):
        sa = max(sa, abs(rec[A + i]))
    for i in range(7):
        jmax = max(jmax, abs(rec[J + i]))
    sa += jmax * rec[T_SUM + 6]
    return abs(rec[A + 7] - rec[AF]) <= _STATE_TOLERANCE * sa + 1e-300 and _reached(rec, sa)


@njit(cache=True, error_model="numpy")
def _edges_within(rec, at, early_low, early_high, low, high):
    """Whether the edges of the quantity at ``at`` keep the bounds (the early ones at the start)."""
    if not (early_low <= rec[at] <= early_high):
        return False
    for i in range(1, 8):
        if not (low <= rec[at + i] <= high):
            return False
    return True


@njit(cache=True, error_model="numpy")
def _check_third(rec, lim):
    """Target reached and every limit kept by an integrated third-order record.

    Velocity extrema inside ramps (the acceleration crossing zero) count. The
    brake is exempt; the early bounds apply to the velocity at the first three
    edges and inside the first two phases, and to the acceleration at the start.
    """
    if not _reached_third(rec):
        return False
    if not _edges_within(rec, A, lim[_ALE], lim[_AHE], lim[_AL], lim[_AH]):
        return False
    for i in range(8):
        high = lim[_VHE] if i < 3 else lim[_VH]
        low = lim[_VLE] if i < 3 else lim[_VL]
        if not (low <= rec[V + i] <= high):
            return False
    for i in range(7):
        j = rec[J + i]
        if not abs(j) <= lim[_JH]:
            return False
        a0 = rec[A + i]
        if j != 0.0 and a0 * rec[A + i + 1] < 0.0:
            v_ext = rec[V + i] - a0 * a0 / (2.0 * j)
            high = lim[_VHE] if i < 2 else lim[_VH]
            low = lim[_VLE] if i < 2 else lim[_VL]
            if not (low <= v_ext <= high):
                return False
    return True


@njit(cache=True, error_model="numpy")
def _check_second(rec, lim):
    """:func:`_check_third` for a second-order record (``a[i]`` during phase i)."""
    amax_abs = 0.0
    for i in range(7):
        amax_abs = max(amax_abs, abs(rec[A + i]))
    if not _reached(rec, amax_abs):
        return False
    for i in range(7):
        if rec[T + i] > 0.0 and not (lim[_AL] <= rec[A + i] <= lim[_AH]):
            return False
    return _edges_within(rec, V, lim[_VLE], lim[_VHE], lim[_VL], lim[_VH])


@njit(cache=True, error_model="numpy")
def check_grid_record(rec, v_max, v_min, a_max, a_min, j_max):
    """Whether an integrated record reaches its target and keeps every limit.

    ``j_max = inf`` for a second-order record. Limits hold to a relative slack
    of 1e-12 (after any brake; where the brake leaves the velocity beyond its
    limit, up to the third edge it may stay within the range the record itself
    covers there, see :func:`_envelope`), and the end state matches to 1e-12 of
    the size of its terms.
    """
    lim = np.empty(_LIM_SIZE)
    third = not math.isinf(j_max)
    _fill_limits(lim, v_max, v_min, a_max, a_min, j_max, _envelope(rec, third), _LIMIT_SLACK)
    if not third:
        return _check_second(rec, lim)
    return _check_third(rec, lim)


@njit(cache=True, error_model="numpy")
def _set_times(rec, n, dt):
    """Phase durations ``n[i] dt`` and their running sums (whole periods times dt)."""
    total = 0
    for i in range(7):
        rec[T + i] = n[i] * dt
        total += n[i]
        rec[T_SUM + i] = total * dt


# ------------------------------------------------------------------------ third order
@njit(cache=True, error_model="numpy")
def _columns(n, m_total, col, active):
    """Scaled effect of each ramp's jerk on the end (a, v, p); how many ramps are active."""
    inv = 1.0 / m_total
    start = 0
    count = 0
    for i in range(0, 7, 2):
        k = i // 2
        if i > 0:
            start += n[i - 2] + n[i - 1]
        nk = float(n[i])
        rk = float(m_total - start - n[i])
        col[k, 0] = nk * inv
        col[k, 1] = nk * (0.5 * nk + rk) * inv * inv
        col[k, 2] = nk * (nk * nk + 3.0 * nk * rk + 3.0 * rk * rk) / 6.0 * inv * inv * inv
        active[k] = n[i] > 0
        if active[k]:
            count += 1
    return count


@njit(cache=True, error_model="numpy")
def _rhs(m_total, dt, ps, vs, as_, pf, vf, af, b):
    """What the ramps' jerks must add to the end state, scaled like :func:`_columns`."""
    tm = m_total * dt
    b[0] = (af - as_) / tm
    b[1] = (vf - vs - as_ * tm) / (tm * tm)
    b[2] = (pf - ps - tm * (vs + tm * as_ / 2.0)) / (tm * tm * tm)


@njit(cache=True, error_model="numpy")
def _inner_extrema_ok(n, dt, vs, as_, u, w, lam, lim):
    """Velocity extrema inside the ramps (where the acceleration crosses zero) in bounds."""
    a = as_
    v = vs
    for i in range(7):
        t = n[i] * dt
        j = u[i // 2] + lam * w[i // 2] if i % 2 == 0 else 0.0
        a_end = a + t * j
        if j != 0.0 and a * a_end < 0.0:
            v_ext = v - a * a / (2.0 * j)
            high = lim[_VHE] if i < 2 else lim[_VH]
            low = lim[_VLE] if i < 2 else lim[_VL]
            if not (low <= v_ext <= high):
                return False
        v += t * (a + t * j / 2.0)
        a = a_end
    return True


@njit(cache=True, error_model="numpy")
def _score(u, w, active, lam, j_max):
    worst = 0.0
    for k in range(4):
        if active[k]:
            worst = max(worst, abs(u[k] + lam * w[k]))
    return worst / j_max


@njit(cache=True, error_model="numpy")
def _third_candidate(n, m_total, dt, vs, as_, lim, col, active, b, u, w, edge_a):
    """Score of the counts ``n``: largest ``|jerk| / j_max``, inf where no jerks work.

    ``b`` holds :func:`_rhs`; on success ``u`` holds the chosen ramp jerks.
    ``edge_a`` (2, 6) is scratch.
    """
    count = _columns(n, m_total, col, active)
    if not _particular(col, active, count, b, u, w):
        return math.inf
    lo = -math.inf
    hi = math.inf
    for k in range(4):
        if active[k]:
            lo, hi = _cut(lo, hi, u[k], w[k], -lim[_JH], lim[_JH])
    if count < 4:
        if lo > 0.0 or hi < 0.0:
            return math.inf
        lo = 0.0
        hi = 0.0
    # Edge states, affine in lam: u's part from the start, w's part from zero.
    a0 = as_
    v0 = vs
    a1 = 0.0
    v1 = 0.0
    for i in range(6):
        t = n[i] * dt
        j0 = u[i // 2] if i % 2 == 0 else 0.0
        j1 = w[i // 2] if i % 2 == 0 else 0.0
        v0 += t * (a0 + t * j0 / 2.0)
        a0 += t * j0
        v1 += t * (a1 + t * j1 / 2.0)
        a1 += t * j1
        edge_a[0, i] = a0
        edge_a[1, i] = a1
        lo, hi = _cut(lo, hi, a0, a1, lim[_AL], lim[_AH])
        if i < 2:
            lo, hi = _cut(lo, hi, v0, v1, lim[_VLE], lim[_VHE])
        else:
            lo, hi = _cut(lo, hi, v0, v1, lim[_VL], lim[_VH])
        if lo > hi:
            return math.inf
    if count < 4:
        if not _inner_extrema_ok(n, dt, vs, as_, u, w, 0.0, lim):
            return math.inf
        for k in range(4):
            if not active[k]:
                u[k] = 0.0
        return _score(u, w, active, 0.0, lim[_JMAX])
    star = min(max(_minimax(u, w, active), lo), hi)
    best_lam = star
    best = math.inf
    if _inner_extrema_ok(n, dt, vs, as_, u, w, star, lim):
        best = _score(u, w, active, star, lim[_JMAX])
    else:
        # Velocity extrema inside ramps are not affine in lam; they appear and
        # vanish where an edge acceleration changes sign: try those lam (and the
        # ends of the interval), keeping the gentlest that works.
        for e in range(-1, 6):
            if e < 0:
                trials = 2
            elif edge_a[1, e] != 0.0:
                trials = 1
            else:
                continue
            for side in range(trials):
                if e < 0:
                    lam = lo if side == 0 else hi
                else:
                    lam = -edge_a[0, e] / edge_a[1, e]
                if not (lo <= lam <= hi):
                    continue
                score = _score(u, w, active, lam, lim[_JMAX])
                if score < best and _inner_extrema_ok(n, dt, vs, as_, u, w, lam, lim):
                    best = score
                    best_lam = lam
    if best < math.inf:
        for k in range(4):
            u[k] = u[k] + best_lam * w[k] if active[k] else 0.0
    return best


@njit(cache=True, error_model="numpy")
def _build_third(rec, n, dt, u, col, active, b, x, w):
    """Write the counts and jerks ``u`` into ``rec`` (start and brake set); integrate, refine.

    ``b``, ``x`` and ``w`` are scratch.
    """
    _set_times(rec, n, dt)
    for i in range(7):
        rec[J + i] = u[i // 2] if i % 2 == 0 and n[i] > 0 else 0.0
    _integrate_third(rec)
    m_total = 0
    for i in range(7):
        m_total += n[i]
    if m_total == 0:
        return
    # One step of refinement: the residual of the end state, solved like the state.
    tm = m_total * dt
    b[0] = (rec[AF] - rec[A + 7]) / tm
    b[1] = (rec[VF] - rec[V + 7]) / (tm * tm)
    b[2] = (rec[PF] - rec[P + 7]) / (tm * tm * tm)
    count = _columns(n, m_total, col, active)
    if _particular(col, active, count, b, x, w):
        for i in range(0, 7, 2):
            if n[i] > 0:
                rec[J + i] += x[i // 2]
        _integrate_third(rec)


def _ring_codes():
    """Offsets of the four ramps (0, -1, +1) and two free holds (0, -1, +1, -2, +2).

    Ordered by their L1 size (ring r: the offsets add up to r in magnitude).
    """
    codes = []
    for k in range(3**4 * 5**2):
        x = k
        digits = []
        for place in range(6):
            if place < 4:
                digits.append((0, -1, 1)[x % 3])
                x //= 3
            else:
                digits.append((0, -1, 1, -2, 2)[x % 5])
                x //= 5
        codes.append(digits)
    codes.sort(key=lambda c: sum(abs(d) for d in c))
    size = [sum(abs(d) for d in c) for c in codes]
    starts = [0] * (max(size) + 2)
    for ring in range(max(size) + 1):
        starts[ring + 1] = starts[ring] + size.count(ring)
    return np.array(codes, dtype=np.int64), np.array(starts, dtype=np.int64)


# Offsets around a centre's base counts, ring by ring (ring r: L1 size r).
_CODES, _RING_STARTS = _ring_codes()
#: How many rings of candidates are searched (all of them: ring r moves the phase
#: durations by r periods in all).
RINGS = _RING_STARTS.shape[0] - 2


@njit(cache=True, error_model="numpy")
def _centre_counts(tau, base, free):
    """Base counts of a centre (``tau``: phase durations in periods); the absorbing phase.

    Ramps are rounded up (a shorter ramp needs more jerk), holds to the nearest
    whole period; the longest hold (the coast on ties) absorbs the remainder.
    ``free`` receives the six other phases: the four ramps, then the other holds.
    """
    absorb = 3
    for i in (1, 5):
        if tau[i] > tau[absorb]:
            absorb = i
    for i in range(7):
        x = tau[i]
        r = math.floor(x + 0.5)
        if abs(x - r) <= _ROUNDING * max(1.0, abs(x)) or i % 2 == 1:
            base[i] = max(r, 0)
        else:
            base[i] = max(math.floor(x) + 1, 0)
    m = 4
    for i in range(7):
        if i % 2 == 0:
            free[i // 2] = i
        elif i != absorb:
            free[m] = i
            m += 1
    return absorb


@njit(cache=True, error_model="numpy")
def _split(tau, split):
    """A centre whose single ramps run at full jerk for whole periods, then one period less.

    Where a velocity change is one ramp (its first ramp and hold under a period,
    its second ramp longer), the ramp moves into the first ramp phase, rounded
    down, and the second ramp phase keeps one period for the remainder: a ramp
    tight on a velocity limit then overshoots by a partial period at its end
    only. Returns False if no change is like that.
    """
    changed = False
    for i in range(7):
        split[i] = tau[i]
    for first in (0, 4):
        if tau[first] < 1.0 and tau[first + 1] < 0.5 and tau[first + 2] >= 1.0:
            split[first] = math.floor(tau[first] + tau[first + 2])
            split[first + 1] = 0.0
            split[first + 2] = 1.0
            changed = True
    return changed


@njit(cache=True, error_model="numpy")
def _search_ring(rec, best_rec, best, ring, base, free, absorb, m_total, dt, vs, as_, lim,
                 check_lim, n, col, active, b, bb, u, w, x, edge_a):  # fmt: skip
    """Try every candidate of ``ring`` around ``base``; keep the best. Returns its score.

    ``b`` holds :func:`_rhs`; the rest is scratch.
    """
    for c in range(_RING_STARTS[ring], _RING_STARTS[ring + 1]):
        used = 0
        bad = False
        for k in range(6):
            i = free[k]
            n[i] = base[i] + _CODES[c, k]
            if n[i] < 0:
                bad = True
                break
            used += n[i]
        if bad:
            continue
        n[absorb] = m_total - used
        if n[absorb] < 0:
            continue
        score = _third_candidate(n, m_total, dt, vs, as_, lim, col, active, b, u, w, edge_a)
        if not score < best:
            continue
        _build_third(rec, n, dt, u, col, active, bb, x, w)
        if not _check_third(rec, check_lim):
            continue
        best_rec[:] = rec
        best = score
    return best


# ---------------------------------------------------------------------- brake rounding
@njit(cache=True, error_model="numpy")
def _whole(t, dt):
    """``t / dt`` rounded down and up (equal where ``t`` is a whole number of periods)."""
    x = t / dt
    r = math.floor(x + 0.5)
    if abs(x - r) <= _ROUNDING * max(1.0, abs(x)):
        return r, r
    return math.floor(x), math.floor(x) + 1


@njit(cache=True, error_model="numpy")
def _start_record(rec, prof, p0, v0, a0):
    """``rec`` emptied, with ``prof``'s target and classification and start ``(p0, v0, a0)``."""
    for k in range(SIZE):
        rec[k] = 0.0
    rec[P] = p0
    rec[V] = v0
    rec[A] = a0
    rec[PF] = prof[PF]
    rec[VF] = prof[VF]
    rec[AF] = prof[AF]
    rec[LIMITS] = prof[LIMITS]
    rec[SIGNS] = prof[SIGNS]
    rec[DIRECTION] = prof[DIRECTION]


@njit(cache=True, error_model="numpy")
def _brake_candidates(prof, dt, lim, brakes, jerks):
    """Whole-period brakes of the continuous one, most likely first; their number.

    The ramp is rounded up with its jerk eased so that it ends at the continuous
    ramp's acceleration, or rounded up or down at its jerk. The hold (at the
    acceleration the ramp reached) takes the periods that bring the velocity where
    the continuous brake brings it, or one more or fewer. A brake must end within
    the early bounds of ``lim`` (no further beyond the limits than the continuous
    profile is there). Writes ``brakes[c] = (ramp, hold)`` periods, ``jerks[c]``.
    """
    if not prof[BRAKE_DURATION] > 0.0:
        brakes[0, 0] = 0
        brakes[0, 1] = 0
        jerks[0] = 0.0
        return 1
    v0 = prof[BRAKE_V]
    a0 = prof[BRAKE_A]
    jb = prof[BRAKE_J]
    t0 = prof[BRAKE_T]
    a_goal = a0 + jb * t0
    v_goal = prof[V]
    f0, c0 = _whole(t0, dt)
    holds = np.empty(3, np.int64)
    count = 0
    for mode in range(3):
        if mode == 0:
            k0 = c0
            j0 = (a_goal - a0) / (k0 * dt) if k0 > 0 else 0.0
        elif mode == 1:
            if c0 == f0:
                continue
            k0 = c0
            j0 = jb
        else:
            if c0 == f0:
                continue
            k0 = f0
            j0 = jb
        t = k0 * dt
        a1 = a0 + j0 * t
        v1 = v0 + t * (a0 + j0 * t / 2.0)
        if not (lim[_ALE] <= a1 <= lim[_AHE]):
            continue
        holds[0] = 0
        holds[1] = 1
        options = 2
        if prof[BRAKE_T + 1] > 0.0 and a1 != 0.0:
            need = (v_goal - v1) / (a1 * dt)
            if need > 0.0:
                k = math.ceil(need - _ROUNDING)
                holds[0] = k
                holds[1] = k + 1
                holds[2] = k - 1
                options = 3 if k > 0 else 2
        for h in range(options):
            k1 = holds[h]
            if k0 + k1 == 0:
                continue
            v2 = v1 + a1 * k1 * dt
            if not (lim[_VLE] <= v2 <= lim[_VHE]):
                continue
            brakes[count, 0] = k0
            brakes[count, 1] = k1
            jerks[count] = j0
            count += 1
    return count


# ------------------------------------------------------------------------- entry points
@njit(cache=True, error_model="numpy")
def quantize_joint(prof, n, dt, v_max, v_min, a_max, a_min, j_max, out, work):
    """A profile of exactly ``n`` periods ``dt`` with whole-period phases, into ``out``.

    Parameters
    ----------
    prof : ndarray of float64, shape (SIZE,)
        A continuous profile record of the joint (any duration): its start (before
        the brake), brake pre-profile, target and phase structure are used.
    n : int
        Number of periods the profile must take, brake included.
    dt : float
        The period (s), > 0.
    v_max, v_min, a_max, a_min, j_max : float
        Limits (``v_min < 0 < v_max``, ``a_min < 0 < a_max``, ``j_max > 0``;
        ``j_max = inf`` for a second-order record).
    out : ndarray of float64, shape (SIZE,)
        Receives the profile (same layout as ``prof``; brake phases re-timed to
        whole periods). Scratch where none is found.
    work : ndarray of float64, shape (WORK_ROWS, SIZE)
        Scratch.

    Returns
    -------
    bool
        False if no such profile was found at this ``n``.
    """
    if math.isinf(j_max):
        return _quantize_second(prof, n, dt, v_max, v_min, a_max, a_min, out, work)
    return _quantize_third(prof, n, dt, v_max, v_min, a_max, a_min, j_max, out, work)


@njit(cache=True, error_model="numpy")
def _quantize_third(prof, n_total, dt, v_max, v_min, a_max, a_min, j_max, out, work):
    braked = prof[BRAKE_DURATION] > 0.0
    p0 = prof[BRAKE_P] if braked else prof[P]
    v0 = prof[BRAKE_V] if braked else prof[V]
    a0 = prof[BRAKE_A] if braked else prof[A]
    lim = np.empty(_LIM_SIZE)
    check_lim = np.empty(_LIM_SIZE)
    # Before its limits hold, no further beyond them than the continuous profile.
    envelope = _envelope(prof, True)
    _fill_limits(lim, v_max, v_min, a_max, a_min, j_max, envelope, _SEARCH_SLACK)
    _fill_limits(check_lim, v_max, v_min, a_max, a_min, j_max, envelope, _LIMIT_SLACK)
    col = np.empty((4, 3))
    active = np.empty(4, np.bool_)
    b = np.empty(3)
    bb = np.empty(3)
    u = np.empty(4)
    w = np.empty(4)
    x = np.empty(4)
    edge_a = np.empty((2, 6))
    n = np.empty(7, np.int64)
    base = np.empty(7, np.int64)
    base2 = np.empty(7, np.int64)
    free = np.empty(6, np.int64)
    free2 = np.empty(6, np.int64)
    tau = np.empty(7)
    tau2 = np.empty(7)
    brakes = np.empty((9, 2), np.int64)
    brake_jerks = np.empty(9)
    rec = work[0]
    centre = work[1]
    count = _brake_candidates(prof, dt, lim, brakes, brake_jerks)
    for c in range(count):
        nb0 = brakes[c, 0]
        nb1 = brakes[c, 1]
        m_total = n_total - nb0 - nb1
        if m_total < 0:
            continue
        _start_record(rec, prof, p0, v0, a0)
        if nb0 + nb1 > 0:
            rec[BRAKE_T] = nb0 * dt
            rec[BRAKE_T + 1] = nb1 * dt
            rec[BRAKE_J] = brake_jerks[c]
            rec[BRAKE_DURATION] = (nb0 + nb1) * dt
            rec[BRAKE_P] = p0
            rec[BRAKE_V] = v0
            rec[BRAKE_A] = a0
        _integrate_third(rec)
        vs = rec[V]
        as_ = rec[A]
        if m_total == 0:
            if _check_third(rec, check_lim):
                out[:] = rec
                return True
            continue
        _rhs(m_total, dt, rec[P], vs, as_, prof[PF], prof[VF], prof[AF], b)
        # Centre 1: the continuous profile re-planned to take exactly m_total periods;
        # centre 2: the given profile (its absorbing hold takes the difference).
        centre[:] = rec
        timed = jerk_timed.timed(centre, m_total * dt, v_max, v_min, a_max, a_min, j_max)
        for i in range(7):
            tau[i] = centre[T + i] / dt
            tau2[i] = prof[T + i] / dt
        absorb = _centre_counts(tau, base, free)
        absorb2 = _centre_counts(tau2, base2, free2)
        same = timed and absorb == absorb2
        for i in range(7):
            if i != absorb and base[i] != base2[i]:
                same = False
        best = math.inf
        for ring in range(RINGS + 1):
            if timed:
                best = _search_ring(rec, out, best, ring, base, free, absorb, m_total, dt, vs,
                                    as_, lim, check_lim, n, col, active, b, bb, u, w,
                                    x, edge_a)  # fmt: skip
            if not same:
                best = _search_ring(rec, out, best, ring, base2, free2, absorb2, m_total, dt,
                                    vs, as_, lim, check_lim, n, col, active, b, bb, u, w,
                                    x, edge_a)  # fmt: skip
            if best < math.inf:
                return True
        # Last resort: single ramps split into whole periods at full jerk and a rest.
        if _split(tau if timed else tau2, tau2):
            absorb2 = _centre_counts(tau2, base2, free2)
            for ring in range(RINGS + 1):
                best = _search_ring(rec, out, best, ring, base2, free2, absorb2, m_total, dt,
                                    vs, as_, lim, check_lim, n, col, active, b, bb, u, w,
                                    x, edge_a)  # fmt: skip
                if best < math.inf:
                    return True
    return False


# ----------------------------------------------------------------------- second order
@njit(cache=True, error_model="numpy")
def _second_solve(n0, n1, n2, dt, dv, dp, sol):
    """Accelerations of ramp ``n0``, coast ``n1``, ramp ``n2`` changing v by ``dv`` and p by ``dp``.

    ``dp`` is the displacement beyond coasting at the start velocity. False where
    no accelerations do it (a missing ramp leaves one unknown for two equations).
    """
    m_total = n0 + n1 + n2
    tm = m_total * dt
    inv = 1.0 / m_total
    # Scaled: the velocity equation by 1 / tm, the position equation by 1 / tm^2.
    c00 = n0 * inv
    c01 = n2 * inv
    c10 = n0 * (0.5 * n0 + n1 + n2) * inv * inv
    c11 = 0.5 * n2 * n2 * inv * inv
    r0 = dv / tm
    r1 = dp / (tm * tm)
    if n0 > 0 and n2 > 0:
        det = c00 * c11 - c01 * c10
        if not abs(det) > 1e-14 * (abs(c00 * c11) + abs(c01 * c10)):
            return False
        sol[0] = (r0 * c11 - c01 * r1) / det
        sol[1] = (c00 * r1 - c10 * r0) / det
        return True
    if n0 > 0:
        sol[0] = r0 / c00
        sol[1] = 0.0
        return abs(c10 * sol[0] - r1) <= 1e-9 * (abs(r1) + abs(c10 * sol[0])) + 1e-300
    if n2 > 0:
        sol[0] = 0.0
        sol[1] = r0 / c01
        return abs(c11 * sol[1] - r1) <= 1e-9 * (abs(r1) + abs(c11 * sol[1])) + 1e-300
    sol[0] = 0.0
    sol[1] = 0.0
    return r0 == 0.0 and r1 == 0.0


@njit(cache=True, error_model="numpy")
def _second_candidate(n0, n1, n2, dt, ps, vs, pf, vf, lim, sol):
    """Score of ramp ``n0``, coast ``n1``, ramp ``n2``: ``|coast velocity|``, or inf."""
    tm = (n0 + n1 + n2) * dt
    if not _second_solve(n0, n1, n2, dt, vf - vs, pf - ps - vs * tm, sol):
        return math.inf
    x0 = sol[0]
    x2 = sol[1]
    if not (lim[_AL] <= x0 <= lim[_AH] and lim[_AL] <= x2 <= lim[_AH]):
        return math.inf
    vp = vs + x0 * n0 * dt
    if not (lim[_VL] <= vp <= lim[_VH]):
        return math.inf
    return abs(vp)


@njit(cache=True, error_model="numpy")
def _build_second(rec, n0, n1, n2, dt, x0, x2, sol):
    """Write ramp, coast, ramp into ``rec`` (start and brake set), integrate and refine."""
    for i in range(7):
        rec[T + i] = 0.0
        rec[A + i] = 0.0
        rec[J + i] = 0.0
    rec[T] = n0 * dt
    rec[T + 1] = n1 * dt
    rec[T + 2] = n2 * dt
    rec[T_SUM] = n0 * dt
    rec[T_SUM + 1] = (n0 + n1) * dt
    for i in range(2, 7):
        rec[T_SUM + i] = (n0 + n1 + n2) * dt
    rec[A] = x0 if n0 > 0 else 0.0
    rec[A + 2] = x2 if n2 > 0 else 0.0
    rec[A + 7] = rec[AF]
    _integrate_second(rec)
    m_total = n0 + n1 + n2
    if m_total == 0:
        return
    # One step of refinement: the residual of the end state, solved like the state.
    dv = rec[VF] - rec[V + 7]
    dp = rec[PF] - rec[P + 7]
    if _second_solve(n0, n1, n2, dt, dv, dp, sol):
        if n0 > 0:
            rec[A] += sol[0]
        if n2 > 0:
            rec[A + 2] += sol[1]
        _integrate_second(rec)


@njit(cache=True, error_model="numpy")
def _quantize_second(prof, n_total, dt, v_max, v_min, a_max, a_min, out, work):
    p0 = prof[BRAKE_P] if prof[BRAKE_DURATION] > 0.0 else prof[P]
    v0 = prof[BRAKE_V] if prof[BRAKE_DURATION] > 0.0 else prof[V]
    rec = work[0]
    centre = work[1]
    sol = np.empty(2)
    spare = np.empty(2)
    lim = np.empty(_LIM_SIZE)
    check_lim = np.empty(_LIM_SIZE)
    envelope = _envelope(prof, False)
    _fill_limits(lim, v_max, v_min, a_max, a_min, math.inf, envelope, _SEARCH_SLACK)
    _fill_limits(check_lim, v_max, v_min, a_max, a_min, math.inf, envelope, _LIMIT_SLACK)
    _start_record(rec, prof, p0, v0, 0.0)
    nb = 0
    if prof[BRAKE_DURATION] > 0.0:
        # Whole periods; the brake ends at the same velocity, a little gentler.
        _, nb = _whole(prof[BRAKE_T], dt)
        nb = max(nb, 1)
        v_end = min(max(v0 + prof[BRAKE_T] * prof[BRAKE_A], v_min), v_max)
        rec[BRAKE_T] = nb * dt
        rec[BRAKE_A] = (v_end - v0) / (nb * dt)
        rec[BRAKE_DURATION] = nb * dt
        rec[BRAKE_P] = p0
        rec[BRAKE_V] = v0
    m_total = n_total - nb
    if m_total < 0:
        return False
    for i in range(7):
        rec[T + i] = 0.0
        rec[A + i] = 0.0
    _integrate_second(rec)
    ps = rec[P]
    vs = rec[V]
    if nb > 0 and not (check_lim[_VLE] <= vs <= check_lim[_VHE]):
        return False
    pf = prof[PF]
    vf = prof[VF]
    if m_total == 0:
        _build_second(rec, 0, 0, 0, dt, 0.0, 0.0, spare)
        if _check_second(rec, check_lim):
            out[:] = rec
            return True
        return False
    centre[:] = rec
    found_timed = acceleration_limited.timed(centre, m_total * dt, v_max, v_min, a_max, a_min)
    best = math.inf
    first0 = -(10**9)
    first2 = -(10**9)
    for which in range(2):
        if which == 0 and not found_timed:
            continue
        src = centre if which == 0 else prof
        base0 = math.floor(src[T] / dt + 0.5)
        base2 = math.floor((src[T + 2] + src[T + 4] + src[T + 6]) / dt + 0.5)
        for o0 in range(_SECOND_LOW, _SECOND_HIGH + 1):
            n0 = base0 + o0
            if n0 < 0:
                continue
            for o2 in range(_SECOND_LOW, _SECOND_HIGH + 1):
                n2 = base2 + o2
                if n2 < 0 or n0 + n2 > m_total:
                    continue
                if (
                    _SECOND_LOW <= n0 - first0 <= _SECOND_HIGH
                    and _SECOND_LOW <= n2 - first2 <= _SECOND_HIGH
                ):
                    continue  # tried around the first centre
                n1 = m_total - n0 - n2
                score = _second_candidate(n0, n1, n2, dt, ps, vs, pf, vf, lim, sol)
                if score < best:
                    _build_second(rec, n0, n1, n2, dt, sol[0], sol[1], spare)
                    if _check_second(rec, check_lim):
                        best = score
                        out[:] = rec
        if which == 0:
            first0 = base0
            first2 = base2
    return best < math.inf


# ------------------------------------------------------------------- several joints
@njit(cache=True, error_model="numpy")
def whole_periods(t, dt):
    """How many periods cover ``t``: ``ceil(t / dt)``, forgiving rounding (as trajkit's)."""
    return math.ceil(t / dt - _ROUNDING)


@njit(cache=True, error_model="numpy")
def _law_record(profiles, scale, law_m, law):
    """The shared phase law's continuous record, from the joint that moves the most."""
    best = -1
    for d in range(scale.shape[0]):
        if scale[d] != 0.0 and (best < 0 or abs(scale[d]) > abs(scale[best])):
            best = d
    prof = profiles[best]
    c = scale[best]
    q0 = prof[BRAKE_P] if prof[BRAKE_DURATION] > 0.0 else prof[P]
    law[:] = prof
    for i in range(7):
        law[J + i] = prof[J + i] / c
    for i in range(8):
        law[A + i] = prof[A + i] / c
        law[V + i] = prof[V + i] / c
        law[P + i] = (prof[P + i] - q0) / c
    for k in range(2):
        law[BRAKE_J + k] = prof[BRAKE_J + k] / c
        law[BRAKE_A + k] = prof[BRAKE_A + k] / c
        law[BRAKE_V + k] = prof[BRAKE_V + k] / c
        law[BRAKE_P + k] = (prof[BRAKE_P + k] - q0) / c
    if law[BRAKE_DURATION] > 0.0:
        law[BRAKE_P] = 0.0
        law[BRAKE_V] = law_m[rows.V0, 0]
        law[BRAKE_A] = law_m[rows.A0, 0]
    else:
        law[P] = 0.0
        law[V] = law_m[rows.V0, 0]
        law[A] = law_m[rows.A0, 0]
    law[PF] = law_m[rows.QF, 0]
    law[VF] = law_m[rows.VF, 0]
    law[AF] = law_m[rows.AF, 0]
    if c < 0.0:
        law[DIRECTION] = DOWN if prof[DIRECTION] == UP else UP


@njit(cache=True, error_model="numpy")
def _block_times(m, d, times):
    """Column ``d``'s minimum duration and blocked intervals (as in synchronize.plan)."""
    prof = np.empty(SIZE)
    valid = np.empty((6, SIZE))
    blocks = np.empty((3, SIZE))
    found = synchronize._step1(prof, m[rows.Q0, d], m[rows.V0, d], m[rows.A0, d],
                               m[rows.QF, d], m[rows.VF, d], m[rows.AF, d], m[rows.V_MAX, d],
                               m[rows.V_MIN, d], m[rows.A_MAX, d], m[rows.A_MIN, d],
                               m[rows.J_MAX, d], synchronize.POSITION, valid, blocks,
                               times)  # fmt: skip
    if not found:
        times[0] = 0.0
        for k in range(1, 5):
            times[k] = math.inf


@njit(cache=True, error_model="numpy")
def _past_blocks(times, n, dt):
    """The first number of periods from ``n`` on that lies in no blocked interval."""
    t = n * dt
    for k in (1, 3):
        if times[k] < t < times[k + 1] and not math.isinf(times[k + 1]):
            return max(n, whole_periods(times[k + 1], dt))
    return n


@njit(cache=True, error_model="numpy")
def _quantize_own(m, d, prof, first, dt, out, work):
    """The smallest ``n >= first`` that quantizes joint ``d`` (blocked intervals skipped).

    Up to MAX_EXTRA_PERIODS periods past ``first`` (or past a blocked interval);
    -1 if none.
    """
    v_max = m[rows.V_MAX, d]
    v_min = m[rows.V_MIN, d]
    a_max = m[rows.A_MAX, d]
    a_min = m[rows.A_MIN, d]
    j_max = m[rows.J_MAX, d]
    times = np.empty(5)
    known = False
    n = first
    last = first + MAX_EXTRA_PERIODS
    while n <= last:
        if quantize_joint(prof, n, dt, v_max, v_min, a_max, a_min, j_max, out, work):
            return n
        if not known:
            _block_times(m, d, times)
            known = True
        after = _past_blocks(times, n, dt)
        if after > n:
            n = after
            last = max(last, n + MAX_EXTRA_PERIODS)
        else:
            n += 1
    return -1


@njit(cache=True, error_model="numpy")
def plan_on_grid(m, control, sync, enabled, min_duration, dt, profiles, independent, out):
    """:func:`~trajkit.profiles._kernels.synchronize.plan` with every switching time on the grid.

    Same arguments, outputs and status codes as ``plan``, plus ``GRID_FAILED``
    (no whole-period profile within ``MAX_EXTRA_PERIODS`` periods past the
    continuous duration rounded up, or past the end of a blocked interval;
    ``out[OUT_JOINT]`` names the joint that failed last, -1 for the shared phase
    law) and ``VELOCITY_UNSUPPORTED`` (a joint under the velocity interface: not
    quantized). ``dt <= 0`` plans continuously (``plan`` itself).

    The continuous problem is planned first (``dt = 0``). Joints left out of
    synchronization and time-if-necessary ones ending at rest each take their own
    smallest number of periods from ``ceil(own / dt)``. The synchronized joints
    (time, phase, and time-if-necessary ones with a moving target) then take the
    smallest number of periods ``N`` at which every one of them quantizes, from
    ``ceil(T / dt)`` (``T`` the continuous common duration) or the longest of the
    former joints, whichever is more (both can set the common duration in
    ``plan``); a joint whose blocked interval holds ``N dt`` makes ``N`` skip past
    it. Phase-synchronized joints (where the continuous plan could phase-
    synchronize them) share one time law, which is quantized like a joint and
    scaled to each of them. ``out[OUT_DURATION]`` is ``N dt``; ``independent``
    keeps the continuous minima.
    continuous minima.
    """
    ndof = m.shape[1]
    out[synchronize.OUT_JOINT] = -1.0
    if dt > 0.0:
        for d in range(ndof):
            if enabled[d] != 0 and control[d] != synchronize.POSITION:
                out[synchronize.OUT_DURATION] = math.nan
                out[synchronize.OUT_JOINT] = d
                return VELOCITY_UNSUPPORTED
    status = synchronize.plan(
        m, control, sync, enabled, min_duration, 0.0, profiles, independent, out
    )
    if status != synchronize.OK or not dt > 0.0:
        return status
    duration = out[synchronize.OUT_DURATION]
    if duration == 0.0:
        return synchronize.OK
    limiting = int(out[synchronize.OUT_LIMITING])
    cont = profiles.copy()
    for d in range(ndof):
        # The continuous laws may store the position they reached as the target.
        cont[d, PF] = m[rows.QF, d]
        cont[d, VF] = m[rows.VF, d]
        cont[d, AF] = m[rows.AF, d]
    work = np.empty((WORK_ROWS, SIZE))
    v_max = m[rows.V_MAX]
    v_min = m[rows.V_MIN]
    a_max = m[rows.A_MAX]
    a_min = m[rows.A_MIN]
    j_max = m[rows.J_MAX]
    # The shared law of the phase-synchronized joints, as plan found it.
    roles = np.empty(ndof, np.int64)
    for d in range(ndof):
        roles[d] = sync[d] if enabled[d] != 0 else synchronize.SYNC_NONE
    scale = np.zeros(ndof)
    law_m = np.empty((11, 1))
    law = np.empty(SIZE)
    law_q = np.empty(SIZE)
    phase = out[synchronize.OUT_PHASE] == 1.0 and synchronize._phase_law(
        m, control, roles, enabled, scale, law_m
    )
    if phase:
        _law_record(cont, scale, law_m, law)
    followers = np.zeros(ndof, np.bool_)
    synced = np.zeros(ndof, np.bool_)
    n_sync = whole_periods(duration, dt)
    n_longest = 0
    any_synced = phase
    for d in range(ndof):
        if enabled[d] == 0:
            continue
        if phase and roles[d] == synchronize.SYNC_PHASE:
            followers[d] = True
            continue
        at_rest = abs(m[rows.VF, d]) < _EPS and abs(m[rows.AF, d]) < _EPS
        if roles[d] != synchronize.SYNC_NONE and not (
            roles[d] == synchronize.SYNC_TIME_IF_NECESSARY and at_rest
        ):
            synced[d] = True
            any_synced = True
            continue
        n = _quantize_own(m, d, cont[d], whole_periods(independent[d], dt), dt, profiles[d],
                          work)  # fmt: skip
        if n < 0:
            out[synchronize.OUT_JOINT] = d
            return GRID_FAILED
        # As in plan: the slowest unsynchronized joint can set the common duration, and
        # time-if-necessary joints ending at rest take part in choosing it.
        n_longest = max(n_longest, n)
        n_sync = max(n_sync, n)
    if not any_synced:
        out[synchronize.OUT_DURATION] = n_longest * dt
        return synchronize.OK
    block_times = np.empty((ndof + 1, 5))
    blocked_known = np.zeros(ndof + 1, np.bool_)
    # Quantized first: the limiting joint (the hardest), then the law, then the rest.
    order = np.empty(ndof + 1, np.int64)
    count = 0
    if limiting >= 0 and synced[limiting]:
        order[count] = limiting
        count += 1
    if phase:
        order[count] = -1
        count += 1
    for d in range(ndof):
        if synced[d] and d != limiting:
            order[count] = d
            count += 1
    failed = order[0]
    n = n_sync
    last = n_sync + MAX_EXTRA_PERIODS
    while n <= last:
        ok = True
        for k in range(count):
            d = order[k]
            if d < 0:
                ok = quantize_joint(law, n, dt, law_m[rows.V_MAX, 0], law_m[rows.V_MIN, 0],
                                    law_m[rows.A_MAX, 0], law_m[rows.A_MIN, 0],
                                    law_m[rows.J_MAX, 0], law_q, work)  # fmt: skip
            else:
                ok = quantize_joint(cont[d], n, dt, v_max[d], v_min[d], a_max[d], a_min[d],
                                    j_max[d], profiles[d], work)  # fmt: skip
            if not ok:
                failed = d
                break
        if ok and phase:
            # The law's limits are the tightest of the joints' (scaled): only
            # rounding could break one, which is checked.
            for d in range(ndof):
                if not followers[d]:
                    continue
                synchronize._scaled_law(law_q, scale[d], m, d, profiles[d])
                if not check_grid_record(profiles[d], v_max[d], v_min[d], a_max[d], a_min[d],
                                         j_max[d]):  # fmt: skip
                    ok = False
                    failed = d
                    break
        if ok:
            out[synchronize.OUT_DURATION] = n * dt
            return synchronize.OK
        # No joint takes a duration inside one of its blocked intervals: skip them.
        unit = ndof if failed < 0 else failed
        if not blocked_known[unit]:
            src = law_m if failed < 0 else m
            col_ = 0 if failed < 0 else failed
            _block_times(src, col_, block_times[unit])
            blocked_known[unit] = True
        after = _past_blocks(block_times[unit], n, dt)
        if after > n:
            n = after
            last = max(last, n + MAX_EXTRA_PERIODS)
        else:
            n += 1
    out[synchronize.OUT_JOINT] = failed
    out[synchronize.OUT_DURATION] = math.nan
    return GRID_FAILED


@njit(cache=True, error_model="numpy", parallel=True)
def plan_on_grid_batch(m, control, sync, enabled, min_duration, dt, profiles, independent, out,
                       status):  # fmt: skip
    """:func:`plan_on_grid` for ``B`` problems (every array with ``B`` first), in parallel."""
    for i in prange(m.shape[0]):
        status[i] = plan_on_grid(m[i], control[i], sync[i], enabled[i], min_duration[i], dt,
                                 profiles[i], independent[i], out[i])  # fmt: skip
