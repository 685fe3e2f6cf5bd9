"""The fastest jerk-limited position move of one axis, and the durations it cannot take.

Any start state ``(p0, v0, a0)`` to any target ``(pf, vf, af)`` under the limits
``v_min <= v <= v_max``, ``a_min <= a <= a_max`` and ``|j| <= j_max``. A time-optimal
profile is bang-bang in jerk with at most seven phases; which limits it reaches
(velocity, the first acceleration plateau, the second one) and the sign pattern of
its jerk (UDDU or UDUD) select one of a few closed-form or polynomial laws. Every
law is tried in both directions (the limits swapped and the jerk negated) and
each solution is accepted only if :func:`~trajkit.profiles._kernels.profile.check`
confirms it reaches the target within the limits.

With a non-zero target velocity or acceleration, several profiles can be valid,
and the durations between some of them are impossible for this axis (its
*blocked intervals*): a multi-axis synchronisation must then avoid them.
:func:`calculate_block` turns the candidates into the minimum duration, up to two
blocked intervals and the profiles at their right ends.

The mathematics, the order in which the laws are tried and the numerical
safeguards follow the reference implementation (ruckig, ``PositionThirdOrderStep1``
and ``Block``), so that the durations agree with it to rounding.

Scratch and result arrays are preallocated by the caller; nothing here allocates
a Python object (only the quartics' root buffers, four floats each, are
allocated, by numba's runtime). Compiled with ``error_model="numpy"``: the laws divide by limits
and states that may be zero (``v_max = 0``, ``a0 = 0``), and the resulting ``inf``
or ``nan`` must simply fail the check, as in IEEE arithmetic, instead of raising.
"""

import math

import numpy as np
from numba import njit

from trajkit.profiles._kernels import layout as L
from trajkit.profiles._kernels.profile import (
    EPS,
    check,
    copy_boundary,
    duration,
    keep,
    set_phase_times,
)
from trajkit.profiles._kernels.roots import solve_quart_monic

# Block times: minimum duration, then the two blocked intervals (left, right).
T_MIN = 0
A_LEFT = 1
A_RIGHT = 2
B_LEFT = 3
B_RIGHT = 4


@njit(cache=True, error_model="numpy")
def _sqrt(x):
    """Square root that is ``nan`` for a negative argument, as in C.

    Compiled code already behaves so; this keeps the module correct when numba's
    JIT is disabled (plain Python raises on ``math.sqrt(-1)``).
    """
    return math.sqrt(x) if x >= 0.0 else math.nan


@njit(cache=True, error_model="numpy")
def _pre(prof):
    """Displacement, boundary states and their powers, shared by every law."""
    pd = prof[L.PF] - prof[L.P]
    v0 = prof[L.V]
    a0 = prof[L.A]
    vf = prof[L.VF]
    af = prof[L.AF]
    a0_a0 = a0 * a0
    af_af = af * af
    # The powers are formed exactly as in the reference, so the laws round alike.
    return (
        pd,
        v0,
        a0,
        vf,
        af,
        v0 * v0,
        vf * vf,
        a0_a0,
        a0 * a0_a0,
        a0_a0 * a0_a0,
        af_af,
        af * af_af,
        af_af * af_af,
    )


@njit(cache=True, error_model="numpy")
def _copy(dst, src):
    """Copy a whole record (a loop: slice assignment costs seconds of compilation)."""
    for k in range(L.SIZE):
        dst[k] = src[k]


@njit(cache=True, error_model="numpy")
def _time_all_vel(valid, count, v_max, v_min, a_max, a_min, j_max):
    """Profiles that coast at ``v_max``: with both, one or no acceleration plateau.

    At most one is added: they exclude each other.
    """
    if count >= valid.shape[0]:
        return count
    prof = valid[count]
    pre = _pre(prof)
    pd, v0, a0, vf, af, v0_v0, vf_vf, a0_a0, a0_p3, a0_p4, af_af, af_p3, af_p4 = pre
    jj = j_max * j_max

    # ACC0_ACC1_VEL
    prof[L.T] = (-a0 + a_max) / j_max
    prof[L.T + 1] = (a0_a0 / 2 - a_max * a_max - j_max * (v0 - v_max)) / (a_max * j_max)
    prof[L.T + 2] = a_max / j_max
    prof[L.T + 3] = (
        3 * (a0_p4 * a_min - af_p4 * a_max)
        + 8 * a_max * a_min * (af_p3 - a0_p3 + 3 * j_max * (a0 * v0 - af * vf))
        + 6 * a0_a0 * a_min * (a_max * a_max - 2 * j_max * v0)
        - 6 * af_af * a_max * (a_min * a_min - 2 * j_max * vf)
        - 12
        * j_max
        * (
            a_max * a_min * (a_max * (v0 + v_max) - a_min * (vf + v_max) - 2 * j_max * pd)
            + (a_min - a_max) * j_max * v_max * v_max
            + j_max * (a_max * vf_vf - a_min * v0_v0)
        )
    ) / (24 * a_max * a_min * jj * v_max)
    prof[L.T + 4] = -a_min / j_max
    prof[L.T + 5] = -(af_af / 2 - a_min * a_min - j_max * (vf - v_max)) / (a_min * j_max)
    prof[L.T + 6] = prof[L.T + 4] + af / j_max
    if check(prof, L.UDDU, L.ACC0_ACC1_VEL, j_max, v_max, v_min, a_max, a_min, False):
        return keep(valid, count)

    # ACC1_VEL: the decelerating half (t[4..6]) is the one just computed.
    t_acc0 = _sqrt(a0_a0 / (2 * jj) + (v_max - v0) / j_max)
    prof[L.T] = t_acc0 - a0 / j_max
    prof[L.T + 1] = 0.0
    prof[L.T + 2] = t_acc0
    ramp = a_min * t_acc0 * (a0_a0 - 2 * j_max * (v0 + v_max))
    prof[L.T + 3] = _acc1_vel_coast(pre, v_max, a_min, j_max, ramp)
    if check(prof, L.UDDU, L.ACC1_VEL, j_max, v_max, v_min, a_max, a_min, False):
        return keep(valid, count)

    # ACC0_VEL
    t_acc1 = _sqrt(af_af / (2 * jj) + (v_max - vf) / j_max)
    prof[L.T] = (-a0 + a_max) / j_max
    prof[L.T + 1] = (a0_a0 / 2 - a_max * a_max - j_max * (v0 - v_max)) / (a_max * j_max)
    prof[L.T + 2] = a_max / j_max
    prof[L.T + 3] = (
        3 * a0_p4
        + 8 * a_max * (af_p3 - a0_p3)
        + 24 * a_max * j_max * (a0 * v0 - af * vf)
        + 6 * a0_a0 * (a_max * a_max - 2 * j_max * v0)
        - 12
        * j_max
        * (
            -2 * a_max * j_max * pd
            + a_max * a_max * (v0 + v_max)
            + j_max * (v_max * v_max - v0_v0)
            + a_max * t_acc1 * (-af_af + 2 * (vf + v_max) * j_max)
        )
    ) / (24 * a_max * jj * v_max)
    prof[L.T + 4] = t_acc1
    prof[L.T + 5] = 0.0
    prof[L.T + 6] = t_acc1 + af / j_max
    if check(prof, L.UDDU, L.ACC0_VEL, j_max, v_max, v_min, a_max, a_min, False):
        return keep(valid, count)

    # VEL: the accelerating half of ACC1_VEL, the decelerating half of ACC0_VEL.
    prof[L.T] = t_acc0 - a0 / j_max
    prof[L.T + 1] = 0.0
    prof[L.T + 2] = t_acc0
    prof[L.T + 3] = (
        (af_p3 - a0_p3) / (3 * jj * v_max)
        + (a0 * v0 - af * vf + (af_af * t_acc1 + a0_a0 * t_acc0) / 2) / (j_max * v_max)
        - (v0 / v_max + 1.0) * t_acc0
        - (vf / v_max + 1.0) * t_acc1
        + pd / v_max
    )
    if check(prof, L.UDDU, L.VEL, j_max, v_max, v_min, a_max, a_min, False):
        return keep(valid, count)
    return count


@njit(cache=True, error_model="numpy")
def _acc1_vel_coast(pre, v_max, a_min, j_max, ramp):
    """Coast duration of an ACC1_VEL profile from :func:`_pre`'s ``pre``.

    ``ramp`` is ``a_min t2 (a0^2 - 2 j_max (v0 + v_max))``, ``t2`` the duration of
    the third phase, which each law forms (and rounds) its own way.
    """
    pd, v0, a0, vf, af, _, vf_vf, _, a0_p3, _, af_af, af_p3, af_p4 = pre
    jj = j_max * j_max
    return -(
        3 * af_p4
        - 8 * a_min * (af_p3 - a0_p3)
        - 24 * a_min * j_max * (a0 * v0 - af * vf)
        + 6 * af_af * (a_min * a_min - 2 * j_max * vf)
        - 12
        * j_max
        * (
            2 * a_min * j_max * pd
            + a_min * a_min * (vf + v_max)
            + j_max * (v_max * v_max - vf_vf)
            + ramp
        )
    ) / (24 * a_min * jj * v_max)


@njit(cache=True, error_model="numpy")
def _time_acc0_acc1(valid, count, v_max, v_min, a_max, a_min, j_max, return_after_found):
    """Profiles with both acceleration plateaus and no coasting (two roots)."""
    if count >= valid.shape[0]:
        return count
    prof = valid[count]
    pd, v0, a0, vf, af, v0_v0, vf_vf, a0_a0, a0_p3, a0_p4, af_af, af_p3, af_p4 = _pre(prof)
    jj = j_max * j_max

    h1 = (
        3 * (af_p4 * a_max - a0_p4 * a_min)
        + a_max
        * a_min
        * (
            8 * (a0_p3 - af_p3)
            + 3 * a_max * a_min * (a_max - a_min)
            + 6 * a_min * af_af
            - 6 * a_max * a0_a0
        )
        + 12
        * j_max
        * (
            a_max * a_min * ((a_max - 2 * a0) * v0 - (a_min - 2 * af) * vf)
            + a_min * a0_a0 * v0
            - a_max * af_af * vf
        )
    ) / (3 * (a_max - a_min) * jj) + 4 * (
        a_max * vf_vf - a_min * v0_v0 - 2 * a_min * a_max * pd
    ) / (a_max - a_min)
    if not h1 >= 0:
        return count
    h1 = math.sqrt(h1) / 2
    h2 = a0_a0 / (2 * a_max * j_max) + (a_min - 2 * a_max) / (2 * j_max) - v0 / a_max
    h3 = -af_af / (2 * a_min * j_max) - (a_max - 2 * a_min) / (2 * j_max) + vf / a_min

    # UDDU: solution 2
    if h2 > h1 / a_max and h3 > -h1 / a_min:
        t4 = -a_min / j_max
        set_phase_times(
            prof,
            (-a0 + a_max) / j_max,
            h2 - h1 / a_max,
            a_max / j_max,
            0.0,
            t4,
            h3 + h1 / a_min,
            t4 + af / j_max,
        )
        if check(prof, L.UDDU, L.ACC0_ACC1, j_max, v_max, v_min, a_max, a_min, True):
            count = keep(valid, count)
            if return_after_found or count >= valid.shape[0]:
                return count
            prof = valid[count]

    # UDDU: solution 1
    if h2 > -h1 / a_max and h3 > h1 / a_min:
        t4 = -a_min / j_max
        set_phase_times(
            prof,
            (-a0 + a_max) / j_max,
            h2 + h1 / a_max,
            a_max / j_max,
            0.0,
            t4,
            h3 - h1 / a_min,
            t4 + af / j_max,
        )
        if check(prof, L.UDDU, L.ACC0_ACC1, j_max, v_max, v_min, a_max, a_min, True):
            count = keep(valid, count)
    return count


@njit(cache=True, error_model="numpy")
def _time_all_none_acc0_acc1(valid, count, v_max, v_min, a_max, a_min, j_max, return_after_found):
    """Profiles without coasting and at most one acceleration plateau.

    Each family is a quartic in one phase duration; its roots are polished by a
    Newton step on the position equation (the quartic's coefficients lose digits).
    The family without a plateau is the most prone to numerical trouble.
    """
    if count >= valid.shape[0]:
        return count
    pd, v0, a0, vf, af, v0_v0, vf_vf, a0_a0, a0_p3, a0_p4, af_af, af_p3, af_p4 = _pre(valid[count])
    jj = j_max * j_max

    # NONE (UDDU and UDUD coincide with t[6] = 0 here)
    h2_none = (a0_a0 - af_af) / (2 * j_max) + (vf - v0)
    h2_h2 = h2_none * h2_none
    t_min_none = (a0 - af) / j_max
    t_max_none = (a_max - a_min) / j_max
    roots_none = np.empty(4)
    n_none = solve_quart_monic(
        0.0,
        -2 * (a0_a0 + af_af - 2 * j_max * (v0 + vf)) / jj,
        4 * (a0_p3 - af_p3 + 3 * j_max * (af * vf - a0 * v0)) / (3 * j_max * jj) - 4 * pd / j_max,
        -h2_h2 / jj,
        roots_none,
    )

    # ACC0
    h3_acc0 = (a0_a0 - af_af) / (2 * a_max * j_max) + (vf - v0) / a_max
    t_min_acc0 = (a_max - af) / j_max
    t_max_acc0 = (a_max - a_min) / j_max
    h0_acc0 = (
        3 * (af_p4 - a0_p4)
        + 8 * (a0_p3 - af_p3) * a_max
        + 24 * a_max * j_max * (af * vf - a0 * v0)
        - 6 * a0_a0 * (a_max * a_max - 2 * j_max * v0)
        + 6 * af_af * (a_max * a_max - 2 * j_max * vf)
        + 12 * j_max * (j_max * (vf_vf - v0_v0 - 2 * a_max * pd) - a_max * a_max * (vf - v0))
    )
    h2_acc0 = -af_af + a_max * a_max + 2 * j_max * vf
    roots_acc0 = np.empty(4)
    n_acc0 = solve_quart_monic(
        -2 * a_max / j_max, h2_acc0 / jj, 0.0, h0_acc0 / (12 * jj * jj), roots_acc0
    )

    # ACC1
    h3_acc1 = -(a0_a0 + af_af) / (2 * j_max * a_min) + a_min / j_max + (vf - v0) / a_min
    t_min_acc1 = (a_min - a0) / j_max
    t_max_acc1 = (a_max - a0) / j_max
    h0_acc1 = (
        (a0_p4 - af_p4) / 4
        + 2 * (af_p3 - a0_p3) * a_min / 3
        + (a0_a0 - af_af) * a_min * a_min / 2
        + j_max
        * (
            af_af * vf
            + a0_a0 * v0
            + 2 * a_min * (j_max * pd - a0 * v0 - af * vf)
            + a_min * a_min * (v0 + vf)
            + j_max * (v0_v0 - vf_vf)
        )
    )
    h2_acc1 = a0_a0 - a0 * a_min + 2 * j_max * v0
    roots_acc1 = np.empty(4)
    n_acc1 = solve_quart_monic(
        2 * (2 * a0 - a_min) / j_max,
        (5 * a0_a0 + a_min * (a_min - 6 * a0) + 2 * j_max * v0) / jj,
        2 * (a0 - a_min) * h2_acc1 / (jj * j_max),
        h0_acc1 / (jj * jj),
        roots_acc1,
    )

    # The families in the reference's order; each is polished and timed by its own law.
    for family in range(3):
        if family == 0:
            roots, n, t_min, t_max, limits = roots_none, n_none, t_min_none, t_max_none, L.NONE
        elif family == 1:
            roots, n, t_min, t_max, limits = roots_acc0, n_acc0, t_min_acc0, t_max_acc0, L.ACC0
        else:
            roots, n, t_min, t_max, limits = roots_acc1, n_acc1, t_min_acc1, t_max_acc1, L.ACC1
        for k in range(n):
            t = roots[k]
            if t < t_min or t > t_max:
                continue
            if count >= valid.shape[0]:
                return count
            prof = valid[count]
            if family == 0:
                _none_times(prof, t, pd, v0, a0, af, a0_a0, a0_p3, af_p3, j_max, h2_none)
            elif family == 1:
                _acc0_times(prof, t, a0, af, a_max, j_max, h0_acc0, h2_acc0, h3_acc0)
            else:
                _acc1_times(
                    prof, t, v0, a0, af, a0_a0, a0_p3, a_min, j_max, h0_acc1, h2_acc1, h3_acc1
                )
            # Only the second plateau's acceleration is set to its limit exactly.
            if check(prof, L.UDDU, limits, j_max, v_max, v_min, a_max, a_min, family == 2):
                count = keep(valid, count)
                if return_after_found:
                    return count
    return count


@njit(cache=True, error_model="numpy")
def _none_times(prof, t, pd, v0, a0, af, a0_a0, a0_p3, af_p3, j_max, h2_none):
    """Phase times of the family without a plateau from a root ``t`` of its quartic.

    A single Newton step on the position equation polishes the root first.
    """
    if t > EPS:
        jj = j_max * j_max
        h2_h2 = h2_none * h2_none
        h1 = j_max * t * t
        orig = (
            -h2_h2 / (4 * j_max * t)
            + h2_none * (af / j_max + t)
            + (
                4 * a0_p3
                + 2 * af_p3
                - 6 * a0_a0 * (af + 2 * j_max * t)
                + 12 * (af - a0) * j_max * v0
                + 3 * jj * (-4 * pd + (h1 + 8 * v0) * t)
            )
            / (12 * jj)
        )
        deriv = h2_none + 2 * v0 - a0_a0 / j_max + h2_h2 / (4 * h1) + (3 * h1) / 4
        t -= orig / deriv
    h0 = h2_none / (2 * j_max * t)
    set_phase_times(prof, h0 + t / 2 - a0 / j_max, 0.0, t, 0.0, 0.0, 0.0, -h0 + t / 2 + af / j_max)


@njit(cache=True, error_model="numpy")
def _acc0_times(prof, t, a0, af, a_max, j_max, h0_acc0, h2_acc0, h3_acc0):
    """Phase times of the family with the first plateau from a root ``t`` (one Newton step)."""
    if t > EPS:
        jj = j_max * j_max
        h1 = j_max * t
        orig = h0_acc0 / (12 * jj * t) + t * (h2_acc0 + h1 * (h1 - 2 * a_max))
        deriv = 2 * (h2_acc0 + h1 * (2 * h1 - 3 * a_max))
        t -= orig / deriv
    set_phase_times(
        prof,
        (-a0 + a_max) / j_max,
        h3_acc0 - 2 * t + j_max / a_max * t * t,
        t,
        0.0,
        0.0,
        0.0,
        (af - a_max) / j_max + t,
    )


@njit(cache=True, error_model="numpy")
def _acc1_times(prof, t, v0, a0, af, a0_a0, a0_p3, a_min, j_max, h0_acc1, h2_acc1, h3_acc1):
    """Phase times of the family with the second plateau from a root ``t``.

    Up to three Newton steps polish the root; the first may not overshoot ``t = 0``.
    """
    if t > EPS:
        h5 = a0_p3 + 2 * j_max * a0 * v0
        h1 = j_max * t
        orig = _acc1_residual(h0_acc1, h5, h1, t, a0, a0_a0, a_min, v0, j_max)
        deriv = (a_min - a0 - h1) * (h2_acc1 + h1 * (4 * a0 - a_min + 2 * h1))
        step = orig / deriv
        # std::min(step, t) of the reference: t only if strictly smaller.
        if t < step:
            step = t
        t -= step

        h1 = j_max * t
        orig = _acc1_residual(h0_acc1, h5, h1, t, a0, a0_a0, a_min, v0, j_max)
        if abs(orig) > 1e-9:
            deriv = (a_min - a0 - h1) * (h2_acc1 + h1 * (4 * a0 - a_min + 2 * h1))
            t -= orig / deriv

            h1 = j_max * t
            orig = _acc1_residual(h0_acc1, h5, h1, t, a0, a0_a0, a_min, v0, j_max)
            if abs(orig) > 1e-9:
                deriv = (a_min - a0 - h1) * (h2_acc1 + h1 * (4 * a0 - a_min + 2 * h1))
                t -= orig / deriv
    set_phase_times(
        prof,
        t,
        0.0,
        (a0 - a_min) / j_max + t,
        0.0,
        0.0,
        h3_acc1 - (2 * a0 + j_max * t) * t / a_min,
        (af - a_min) / j_max,
    )


@njit(cache=True, error_model="numpy")
def _acc1_residual(h0_acc1, h5, h1, t, a0, a0_a0, a_min, v0, j_max):
    """Position residual of the ACC1 family at first-phase duration ``t``."""
    return (
        -(
            h0_acc1 / 2
            + h1
            * (
                h5
                + a0 * (a_min - 2 * h1) * (a_min - h1)
                + a0_a0 * (5 * h1 / 2 - 2 * a_min)
                + a_min * a_min * h1 / 2
                + j_max * (h1 / 2 - a_min) * (h1 * t + 2 * v0)
            )
        )
        / j_max
    )


@njit(cache=True, error_model="numpy")
def _time_acc1_vel_two_step(prof, v_max, v_min, a_max, a_min, j_max):
    """Numerical fallback: ACC1_VEL starting straight with the jerk-down phase."""
    pre = _pre(prof)
    _, v0, a0, vf, af, _, _, a0_a0, _, _, af_af, _, _ = pre
    t4 = -a_min / j_max
    ramp = a_min * a0 * (a0_a0 - 2 * j_max * (v0 + v_max)) / j_max
    set_phase_times(
        prof,
        0.0,
        0.0,
        a0 / j_max,
        _acc1_vel_coast(pre, v_max, a_min, j_max, ramp),
        t4,
        -(af_af / 2 - a_min * a_min + j_max * (v_max - vf)) / (a_min * j_max),
        t4 + af / j_max,
    )
    return check(prof, L.UDDU, L.ACC1_VEL, j_max, v_max, v_min, a_max, a_min, False)


@njit(cache=True, error_model="numpy")
def _time_acc0_two_step(prof, v_max, v_min, a_max, a_min, j_max):
    """Numerical fallback: ACC0 profiles of two and three phases."""
    pd, v0, a0, vf, af, v0_v0, vf_vf, a0_a0, a0_p3, a0_p4, af_af, af_p3, af_p4 = _pre(prof)
    jj = j_max * j_max
    limits = (v_max, v_min, a_max, a_min, j_max)

    # Two step
    t1 = (af_af - a0_a0 + 2 * j_max * (vf - v0)) / (2 * a0 * j_max)
    if _acc0_candidate(prof, limits, 0.0, t1, (a0 - af) / j_max, 0.0):
        return True

    # Three step, pf not used
    t1 = (a0_a0 + af_af - 2 * a_max * a_max + 2 * j_max * (vf - v0)) / (2 * a_max * j_max)
    if _acc0_candidate(prof, limits, (-a0 + a_max) / j_max, t1, (-af + a_max) / j_max, 0.0):
        return True

    # Three step, a_max not used
    h0 = 3 * (af_af - a0_a0 + 2 * j_max * (v0 + vf))
    h2 = a0_p3 + 2 * af_p3 + 6 * jj * pd + 6 * (af - a0) * j_max * vf - 3 * a0 * af_af
    h1 = (
        _sqrt(
            2
            * (
                2 * h2 * h2
                + h0
                * (
                    a0_p4
                    - 6 * a0_a0 * (af_af + 2 * j_max * vf)
                    + 8 * a0 * (af_p3 + 3 * jj * pd + 3 * af * j_max * vf)
                    - 3 * (af_p4 + 4 * af_af * j_max * vf + 4 * jj * (vf_vf - v0_v0))
                )
            )
        )
        * abs(j_max)
        / j_max
    )
    t0 = (
        4 * af_p3 + 2 * a0_p3 - 6 * a0 * af_af + 12 * jj * pd + 12 * (af - a0) * j_max * vf + h1
    ) / (2 * j_max * h0)
    t2 = (
        -4 * a0_p3 - 2 * af_p3 + 6 * a0_a0 * af + 12 * jj * pd - 12 * (af - a0) * j_max * v0 + h1
    ) / (2 * j_max * h0)
    if _acc0_candidate(prof, limits, t0, -h1 / (j_max * h0), t2, 0.0):
        return True

    # Three step, t = (a_max - a_min) / j_max
    t = (a_max - a_min) / j_max
    t1 = (a0_a0 - af_af) / (2 * a_max * j_max) + (vf - v0 + j_max * t * t) / a_max - 2 * t
    return _acc0_candidate(prof, limits, (-a0 + a_max) / j_max, t1, t, (af - a_min) / j_max)


@njit(cache=True, error_model="numpy")
def _acc0_candidate(prof, limits, t0, t1, t2, t6):
    """Whether the ACC0 profile of phases 0, 1, 2 and 6 (the others empty) is valid.

    ``limits`` are ``(v_max, v_min, a_max, a_min, j_max)``.
    """
    v_max, v_min, a_max, a_min, j_max = limits
    set_phase_times(prof, t0, t1, t2, 0.0, 0.0, 0.0, t6)
    return check(prof, L.UDDU, L.ACC0, j_max, v_max, v_min, a_max, a_min, False)


@njit(cache=True, error_model="numpy")
def _time_vel_two_step(prof, v_max, v_min, a_max, a_min, j_max):
    """Numerical fallback: VEL profiles that skip the jerk-up phase."""
    pd, v0, a0, vf, af, _v0_v0, _vf_vf, _a0_a0, a0_p3, _a0_p4, af_af, af_p3, _af_p4 = _pre(prof)
    jj = j_max * j_max
    h1 = _sqrt(af_af / (2 * jj) + (v_max - vf) / j_max)

    # Four step
    set_phase_times(
        prof,
        -a0 / j_max,
        0.0,
        0.0,
        (af_p3 - a0_p3) / (3 * jj * v_max)
        + (a0 * v0 - af * vf + (af_af * h1) / 2) / (j_max * v_max)
        - (vf / v_max + 1.0) * h1
        + pd / v_max,
        h1,
        0.0,
        h1 + af / j_max,
    )
    if check(prof, L.UDDU, L.VEL, j_max, v_max, v_min, a_max, a_min, False):
        return True

    # Four step
    set_phase_times(
        prof,
        0.0,
        0.0,
        a0 / j_max,
        (af_p3 - a0_p3) / (3 * jj * v_max)
        + (a0 * v0 - af * vf + (af_af * h1 + a0_p3 / j_max) / 2) / (j_max * v_max)
        - (v0 / v_max + 1.0) * a0 / j_max
        - (vf / v_max + 1.0) * h1
        + pd / v_max,
        h1,
        0.0,
        h1 + af / j_max,
    )
    return check(prof, L.UDDU, L.VEL, j_max, v_max, v_min, a_max, a_min, False)


@njit(cache=True, error_model="numpy")
def _time_none_two_step(prof, v_max, v_min, a_max, a_min, j_max):
    """Numerical fallback: NONE profiles of two phases and of one."""
    _, v0, a0, vf, af, _, _, a0_a0, _, _, af_af, _, _ = _pre(prof)

    # Two step
    h0 = _sqrt((a0_a0 + af_af) / 2 + j_max * (vf - v0)) * abs(j_max) / j_max
    set_phase_times(prof, (h0 - a0) / j_max, 0.0, (h0 - af) / j_max, 0.0, 0.0, 0.0, 0.0)
    if check(prof, L.UDDU, L.NONE, j_max, v_max, v_min, a_max, a_min, False):
        return True

    # Single step
    set_phase_times(prof, (af - a0) / j_max, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    return check(prof, L.UDDU, L.NONE, j_max, v_max, v_min, a_max, a_min, False)


@njit(cache=True, error_model="numpy")
def _time_all_single_step(prof, v_max, v_min, a_max, a_min):
    """Zero jerk or acceleration limits: the state can only drift, at constant acceleration."""
    pd = prof[L.PF] - prof[L.P]
    v0 = prof[L.V]
    a0 = prof[L.A]
    af = prof[L.AF]
    v0_v0 = v0 * v0
    if abs(af - a0) > EPS:
        return False
    set_phase_times(prof, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    if abs(a0) > EPS:
        q = _sqrt(2 * a0 * pd + v0_v0)
        # Solution 1
        prof[L.T + 3] = (-v0 + q) / a0
        if prof[L.T + 3] >= 0.0 and check(
            prof, L.UDDU, L.NONE, 0.0, v_max, v_min, a_max, a_min, False
        ):
            return True
        # Solution 2
        prof[L.T + 3] = -(v0 + q) / a0
        if prof[L.T + 3] >= 0.0 and check(
            prof, L.UDDU, L.NONE, 0.0, v_max, v_min, a_max, a_min, False
        ):
            return True
    elif abs(v0) > EPS:
        prof[L.T + 3] = pd / v0
        if check(prof, L.UDDU, L.NONE, 0.0, v_max, v_min, a_max, a_min, False):
            return True
    elif abs(pd) < EPS:
        if check(prof, L.UDDU, L.NONE, 0.0, v_max, v_min, a_max, a_min, False):
            return True
    return False


@njit(cache=True, error_model="numpy")
def _clear_intervals(block_times):
    """No blocked interval (ruckig's empty optionals)."""
    for k in range(A_LEFT, B_RIGHT + 1):
        block_times[k] = math.inf


@njit(cache=True, error_model="numpy")
def _set_min_profile(block, block_times, prof):
    """The minimum-duration profile; forgets any blocked interval."""
    _copy(block[0], prof)
    block_times[T_MIN] = duration(prof)
    _clear_intervals(block_times)


@njit(cache=True, error_model="numpy")
def _set_interval(block, block_times, slot, left, right):
    """Blocked interval ``slot`` (1: a, 2: b) between two candidates' durations.

    The longer candidate is the profile kept for the interval's right end.
    """
    d_left = duration(left)
    d_right = duration(right)
    k = A_LEFT if slot == 1 else B_LEFT
    if d_left < d_right:
        block_times[k] = d_left
        block_times[k + 1] = d_right
        _copy(block[slot], right)
    else:
        block_times[k] = d_right
        block_times[k + 1] = d_left
        _copy(block[slot], left)


@njit(cache=True, error_model="numpy")
def _remove(valid, count, index):
    """Drop candidate ``index``, shifting the later ones down."""
    for i in range(index, count - 1):
        _copy(valid[i], valid[i + 1])
    return count - 1


@njit(cache=True, error_model="numpy")
def _same_motion(valid, count):
    """The later of two candidates of one direction and one duration (to 256 eps), or -1."""
    for i in range(count):
        for k in range(i + 1, count):
            if (
                valid[i, L.DIRECTION] == valid[k, L.DIRECTION]
                and abs(valid[i, L.T_SUM + 6] - valid[k, L.T_SUM + 6]) < 256 * EPS
            ):
                return k
    return -1


@njit(cache=True, error_model="numpy")
def calculate_block(valid, count, block, block_times):
    """Minimum duration and blocked intervals from the valid candidates.

    Parameters
    ----------
    valid : ndarray, shape (>= count, SIZE)
        The valid candidate profiles in the order they were found. Reordered in
        place when numerical duplicates are dropped.
    count : int
        Number of valid candidates.
    block : ndarray, shape (3, SIZE)
        Receives the minimum-duration profile (row 0) and the profiles at the
        right ends of the blocked intervals a (row 1) and b (row 2).
    block_times : ndarray, shape (5,)
        Receives ``[t_min, a_left, a_right, b_left, b_right]``; an absent
        interval has both ends ``inf``.

    Returns
    -------
    bool
        False if the candidates do not form a consistent block (an even count
        that is no known numerical duplicate).

    Notes
    -----
    Candidates alternate between reachable and unreachable duration ranges, so
    a consistent set has an odd count; two candidates mean a numerically missed
    one and are kept as a single interval (the reference's numerically robust
    variant). Four are reduced to three when two of opposite direction have the
    same duration. The ranking uses the seven-phase durations, the reported times
    the full ones (the brake pre-profile is common to all candidates).
    """
    if count == 1:
        _set_min_profile(block, block_times, valid[0])
        return True
    elif count == 2:
        if abs(valid[0, L.T_SUM + 6] - valid[1, L.T_SUM + 6]) < 8 * EPS:
            _set_min_profile(block, block_times, valid[0])
            return True
        idx_min = 0 if valid[0, L.T_SUM + 6] < valid[1, L.T_SUM + 6] else 1
        idx_else = (idx_min + 1) % 2
        _set_min_profile(block, block_times, valid[idx_min])
        _set_interval(block, block_times, 1, valid[idx_min], valid[idx_else])
        return True
    elif count == 4:
        # Only from numerical issues: find the "identical" profiles.
        t0 = valid[0, L.T_SUM + 6]
        t1 = valid[1, L.T_SUM + 6]
        t2 = valid[2, L.T_SUM + 6]
        t3 = valid[3, L.T_SUM + 6]
        d0 = valid[0, L.DIRECTION]
        d1 = valid[1, L.DIRECTION]
        d2 = valid[2, L.DIRECTION]
        d3 = valid[3, L.DIRECTION]
        if abs(t0 - t1) < 32 * EPS and d0 != d1:
            count = _remove(valid, count, 1)
        elif abs(t2 - t3) < 256 * EPS and d2 != d3:
            count = _remove(valid, count, 3)
        elif abs(t0 - t3) < 256 * EPS and d0 != d3:
            count = _remove(valid, count, 3)
        else:
            # Two of one direction with one duration are one motion: a peak that
            # touches a limit is the profile holding it for no time.
            duplicate = _same_motion(valid, count)
            if duplicate < 0:
                return False
            count = _remove(valid, count, duplicate)
    elif count % 2 == 0:
        return False

    # The fastest candidate; the first one on ties.
    idx_min = 0
    for i in range(1, count):
        if valid[i, L.T_SUM + 6] < valid[idx_min, L.T_SUM + 6]:
            idx_min = i
    _set_min_profile(block, block_times, valid[idx_min])

    if count == 3:
        i1 = (idx_min + 1) % 3
        i2 = (idx_min + 2) % 3
        _set_interval(block, block_times, 1, valid[i1], valid[i2])
        return True
    elif count == 5:
        i1 = (idx_min + 1) % 5
        i2 = (idx_min + 2) % 5
        i3 = (idx_min + 3) % 5
        i4 = (idx_min + 4) % 5
        if valid[i1, L.DIRECTION] == valid[i2, L.DIRECTION]:
            _set_interval(block, block_times, 1, valid[i1], valid[i2])
            _set_interval(block, block_times, 2, valid[i3], valid[i4])
        else:
            _set_interval(block, block_times, 1, valid[i1], valid[i4])
            _set_interval(block, block_times, 2, valid[i2], valid[i3])
        return True
    return False


@njit(cache=True, error_model="numpy")
def is_blocked(block_times, t):
    """Whether the axis cannot take duration ``t`` (shorter than the minimum or blocked).

    Parameters
    ----------
    block_times : ndarray, shape (5,)
        ``[t_min, a_left, a_right, b_left, b_right]`` as written by :func:`fastest`.
    t : float
        A candidate duration (s).

    Returns
    -------
    bool
        True if ``t < t_min`` or ``t`` lies strictly inside a blocked interval.
    """
    return (
        t < block_times[T_MIN]
        or (block_times[A_LEFT] < t < block_times[A_RIGHT])
        or (block_times[B_LEFT] < t < block_times[B_RIGHT])
    )


@njit(cache=True, error_model="numpy")
def profile_at(block, block_times, t):
    """Which block profile belongs to a synchronised duration ``t``.

    Parameters
    ----------
    block : ndarray, shape (3, SIZE)
        The block's profiles (unused: the choice depends only on the times; it is
        taken so that callers pass the pair together).
    block_times : ndarray, shape (5,)
        ``[t_min, a_left, a_right, b_left, b_right]``.
    t : float
        The synchronised duration (s), not blocked.

    Returns
    -------
    int
        The row of the interval with the latest right end at or before ``t``
        (1 for a, 2 for b), or 0 (the minimum-duration profile) if there is none.

    Notes
    -----
    The reference's ``Block::get_profile`` tests b before a, which is the same
    whenever b lies above a; but the two intervals come in no particular order
    (b can lie below a), and then at a's right end it would return b's profile,
    of another duration. The reference never calls it (its synchroniser indexes
    the profiles directly); here the latest interval wins, b on a tie as there.
    """
    row = 0
    best = -math.inf
    # An absent interval has an infinite right end, which no finite t reaches;
    # checking the left end too keeps t = inf from selecting an absent profile.
    if block_times[A_LEFT] < math.inf and t >= block_times[A_RIGHT]:
        row = 1
        best = block_times[A_RIGHT]
    if block_times[B_LEFT] < math.inf and t >= block_times[B_RIGHT] >= best:
        row = 2
    return row


@njit(cache=True, error_model="numpy")
def _fastest(prof, v_max, v_min, a_max, a_min, j_max, valid, block, block_times):
    """:func:`fastest` with float limits."""
    _clear_intervals(block_times)
    block_times[T_MIN] = math.inf
    pd = prof[L.PF] - prof[L.P]
    v0 = prof[L.V]
    a0 = prof[L.A]
    vf = prof[L.VF]
    af = prof[L.AF]

    # Zero limits: only drifting at constant acceleration is possible.
    if j_max == 0.0 or a_max == 0.0 or a_min == 0.0:
        p = block[0]
        for k in range(L.SIZE):
            p[k] = 0.0
        copy_boundary(p, prof)
        if _time_all_single_step(p, v_max, v_min, a_max, a_min):
            block_times[T_MIN] = duration(p)
            # A moving axis cannot wait: every longer duration is blocked.
            if abs(v0) > EPS or abs(a0) > EPS:
                block_times[A_LEFT] = block_times[T_MIN]
                block_times[A_RIGHT] = math.inf
                _copy(block[1], p)
            return True
        return False

    copy_boundary(valid[0], prof)
    count = 0
    if abs(vf) < EPS and abs(af) < EPS:
        up = pd >= 0
        v_hi = v_max if up else v_min
        v_lo = v_min if up else v_max
        a_hi = a_max if up else a_min
        a_lo = a_min if up else a_max
        jf = j_max if up else -j_max

        if abs(v0) < EPS and abs(a0) < EPS and abs(pd) < EPS:
            count = _time_all_none_acc0_acc1(valid, count, v_hi, v_lo, a_hi, a_lo, jf, True)
        else:
            # No blocked interval to a target at rest: the first profile found is it.
            count = _time_all_vel(valid, count, v_hi, v_lo, a_hi, a_lo, jf)
            if count == 0:
                count = _time_all_none_acc0_acc1(valid, count, v_hi, v_lo, a_hi, a_lo, jf, True)
            if count == 0:
                count = _time_acc0_acc1(valid, count, v_hi, v_lo, a_hi, a_lo, jf, True)
            if count == 0:
                count = _time_all_vel(valid, count, v_lo, v_hi, a_lo, a_hi, -jf)
            if count == 0:
                count = _time_all_none_acc0_acc1(valid, count, v_lo, v_hi, a_lo, a_hi, -jf, True)
            if count == 0:
                count = _time_acc0_acc1(valid, count, v_lo, v_hi, a_lo, a_hi, -jf, True)
    else:
        count = _time_all_none_acc0_acc1(valid, count, v_max, v_min, a_max, a_min, j_max, False)
        count = _time_all_none_acc0_acc1(valid, count, v_min, v_max, a_min, a_max, -j_max, False)
        count = _time_acc0_acc1(valid, count, v_max, v_min, a_max, a_min, j_max, False)
        count = _time_acc0_acc1(valid, count, v_min, v_max, a_min, a_max, -j_max, False)
        count = _time_all_vel(valid, count, v_max, v_min, a_max, a_min, j_max)
        count = _time_all_vel(valid, count, v_min, v_max, a_min, a_max, -j_max)

    if count == 0:
        count = _two_step(valid, v_max, v_min, a_max, a_min, j_max)
    return calculate_block(valid, count, block, block_times)


@njit(cache=True, error_model="numpy")
def _two_step(valid, v_max, v_min, a_max, a_min, j_max):
    """The numerical fallbacks, each law up and then down, until one finds a profile.

    Returns the number of profiles found (0 or 1).
    """
    for law in range(4):
        for up in (True, False):
            if up:
                limits = (v_max, v_min, a_max, a_min, j_max)
            else:
                limits = (v_min, v_max, a_min, a_max, -j_max)
            if law == 0:
                found = _time_none_two_step(valid[0], *limits)
            elif law == 1:
                found = _time_acc0_two_step(valid[0], *limits)
            elif law == 2:
                found = _time_vel_two_step(valid[0], *limits)
            else:
                found = _time_acc1_vel_two_step(valid[0], *limits)
            if found:
                return keep(valid, 0)
    return 0


@njit(cache=True, error_model="numpy")
def fastest(prof, v_max, v_min, a_max, a_min, j_max, valid, block, block_times):
    """Time-optimal jerk-limited profile of one axis, and its blocked intervals.

    Parameters
    ----------
    prof : ndarray, shape (SIZE,)
        Holds the boundary: start state ``p[0], v[0], a[0]`` (after any brake
        pre-profile), target ``pf, vf, af`` and the brake fields, which every
        candidate carries along. Not modified; must not be a row of ``valid``
        or ``block``.
    v_max, v_min : float
        Velocity limits, ``v_min <= 0 <= v_max``.
    a_max, a_min : float
        Acceleration limits, ``a_min <= 0 <= a_max``.
    j_max : float
        Jerk limit, ``>= 0``.
    valid : ndarray, shape (6, SIZE)
        Scratch rows for the candidate profiles (at most five valid plus a spare).
    block : ndarray, shape (3, SIZE)
        Receives the minimum-duration profile (row 0) and the profiles at the
        right ends of the blocked intervals a and b (rows 1 and 2).
    block_times : ndarray, shape (5,)
        Receives ``[t_min, a_left, a_right, b_left, b_right]``; an absent
        interval has both ends ``inf``. ``t_min`` includes the brake duration.
        With a zero limit and a moving start, ``a = (t_min, inf)``: the axis can
        only drift, so no longer duration is possible (row 1 then repeats row 0).

    Returns
    -------
    bool
        Whether a profile was found (False: no solution, for example zero limits
        that cannot reach the target, or a numerical failure).

    Notes
    -----
    To a target at rest no duration beyond the minimum is blocked, so the laws
    are tried in a fixed order and the first valid profile is taken, first
    toward the target and then against it. Otherwise every law is tried in both
    directions and all valid profiles are collected for :func:`calculate_block`.
    Numerically delicate cases where nothing was found fall back to simplified
    laws with fewer phases.
    """
    # Integer limits would reach check() typed as integers, where its jerk pattern
    # becomes a mixed tuple that numba cannot index: make them floats once here.
    return _fastest(
        prof,
        float(v_max),
        float(v_min),
        float(a_max),
        float(a_min),
        float(j_max),
        valid,
        block,
        block_times,
    )
