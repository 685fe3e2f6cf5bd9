"""Jerk-limited position moves of a prescribed duration (step 2), compiled.

Given a start state ``(p0, v0, a0)``, a target ``(pf, vf, af)``, asymmetric
limits and a duration ``tf`` no shorter than the joint's fastest move, find seven
phase durations of constant jerk that take exactly ``tf``. This is the
mathematics of ruckig's ``PositionThirdOrderStep2`` (Berscheid and Kröger, RSS
2021): a fixed list of profile shapes, each named by the limits it reaches, is
tried in a fixed order and the first shape that :func:`~.profile.check` accepts
wins. Keeping the reference's order, branches and floating-point expressions is
deliberate: the first accepted shape is then the same one, to the last bit in
almost every case, so the reference serves as a test oracle.

Most shapes have jerk ``±j_max`` and unknown phase durations; a few keep the
acceleration limits reached and trade the jerk for the time instead (their jerk
``jf`` is an unknown, bounded by ``j_max``).

Notation in the formulas follows the reference (snake case): ``pd = pf - p0``,
``vd = vf - v0``, ``ad = af - a0``, ``x_x`` and ``x_pN`` are the square and
N-th power of ``x``, ``jj = j_max**2``, ``g1 = tf v0 - pd`` and
``g2 = tf (v0 + vf) - 2 pd``. Inside one direction's attempt, ``v_max`` ...
``j_max`` are the limits of that direction (for the DOWN attempt the caller
swaps the maxima with the minima and negates the jerk), as in the reference.

Everything is compiled with ``error_model="numpy"``: the closed forms divide by
quantities that vanish for degenerate inputs, and the reference lets those give
``inf``/``nan``, which the check then rejects; raising instead would abort the
search before a later shape could succeed.
"""

import math

import numpy as np
from numba import njit

# The reference's std::min and std::max, NaN handling included.
from trajkit.profiles._kernels.brake import _max, _min
from trajkit.profiles._kernels.layout import (
    ACC0,
    ACC0_ACC1,
    ACC0_ACC1_VEL,
    ACC0_VEL,
    ACC1,
    ACC1_VEL,
    AF,
    NONE,
    PF,
    UDDU,
    UDUD,
    VEL,
    VF,
    A,
    P,
    V,
)
from trajkit.profiles._kernels.profile import EPS, check, check_with_timing, set_phase_times
from trajkit.profiles._kernels.roots import (
    TOLERANCE,
    poly_derivative_eval,
    poly_eval,
    shrink_interval,
    solve_cubic,
    solve_quart_monic,
)

# The layout's codes as int64 values: numba types a global Python int as a literal,
# so passing them as they are would compile _accept (and check) once per pair of
# codes; as int64 values every call shares one compilation (a third of the time).
_UDDU = np.int64(UDDU)
_UDUD = np.int64(UDUD)
_ACC0_ACC1_VEL = np.int64(ACC0_ACC1_VEL)
_ACC0_ACC1 = np.int64(ACC0_ACC1)
_ACC0_VEL = np.int64(ACC0_VEL)
_ACC1_VEL = np.int64(ACC1_VEL)
_ACC0 = np.int64(ACC0)
_ACC1 = np.int64(ACC1)
_VEL = np.int64(VEL)
_NONE = np.int64(NONE)


@njit(cache=True, error_model="numpy")
def _sq(x):
    """Square (the reference's ``pow2``)."""
    return x * x


@njit(cache=True, error_model="numpy")
def _accept(prof, signs, limits, j_max, v_max, v_min, a_max, a_min, t0, t1, t2, t3, t4, t5, t6):
    """Try a candidate of jerk ``±j_max``.

    Calls :func:`check` directly, not ``check_with_timing``: the jerk is the limit
    itself, and ``|j| < |j| + 1e-12`` is false in floating point once
    ``|j| >= 2**14``, which would reject every such profile of a stiff axis.
    """
    set_phase_times(prof, t0, t1, t2, t3, t4, t5, t6)
    return check(prof, signs, limits, j_max, v_max, v_min, a_max, a_min, False)


@njit(cache=True, error_model="numpy")
def _accept_jerk(prof, signs, limits, jf, j_max, v_max, v_min, a_max, a_min,
                 t0, t1, t2, t3, t4, t5, t6):  # fmt: skip
    """Try a candidate whose jerk ``jf`` is an unknown: it must keep ``|jf| <= j_max``."""
    set_phase_times(prof, t0, t1, t2, t3, t4, t5, t6)
    return check_with_timing(prof, signs, limits, jf, v_max, v_min, a_max, a_min, j_max)


@njit(cache=True, error_model="numpy")
def _givens(prof, tf):
    """Boundary differences and powers shared by all shapes (the reference's members)."""
    v0 = prof[V]
    a0 = prof[A]
    vf = prof[VF]
    af = prof[AF]
    pd = prof[PF] - prof[P]
    tf_tf = tf * tf
    tf_p3 = tf_tf * tf
    tf_p4 = tf_tf * tf_tf
    vd = vf - v0
    vd_vd = vd * vd
    v0_v0 = v0 * v0
    vf_vf = vf * vf
    ad = af - a0
    ad_ad = ad * ad
    a0_a0 = a0 * a0
    af_af = af * af
    a0_p3 = a0 * a0_a0
    a0_p4 = a0_a0 * a0_a0
    a0_p5 = a0_p3 * a0_a0
    a0_p6 = a0_p4 * a0_a0
    af_p3 = af * af_af
    af_p4 = af_af * af_af
    af_p5 = af_p3 * af_af
    af_p6 = af_p4 * af_af
    g1 = -pd + tf * v0
    g2 = -2 * pd + tf * (v0 + vf)
    return (tf, v0, a0, vf, af, pd, tf_tf, tf_p3, tf_p4, vd, vd_vd, v0_v0, vf_vf, ad,
            ad_ad, a0_a0, a0_p3, a0_p4, a0_p5, a0_p6, af_af, af_p3, af_p4, af_p5, af_p6,
            g1, g2)  # fmt: skip


# fmt: off
# The formulas below are the reference's, term by term and in its evaluation
# order (which fixes the rounding); the formatter would spread each over dozens
# of lines and hide that correspondence.


@njit(cache=True, error_model="numpy")
def _time_acc0_acc1_vel(prof, k, v_max, v_min, a_max, a_min, j_max):
    """Both acceleration limits and the velocity limit reached (jerk ``±j_max``)."""
    (tf, _, a0, vf, af, pd, _, _, _, vd, vd_vd, _, _, ad, _, a0_a0, a0_p3, a0_p4, _, _, af_af,
     af_p3, af_p4, _, _, g1, _) = k
    jj = j_max * j_max

    # UDDU
    if (2*(a_max - a_min) + ad)/j_max < tf:
        h1 = (
            math.sqrt((a0_p4 + af_p4 - 4*a0_p3*(2*a_max + a_min)/3 - 4*af_p3*(a_max + 2*a_min)/3
            + 2*(a0_a0 - af_af)*a_max*a_max + (4*a0*a_max - 2*a0_a0)*(af_af - 2*af*a_min
            + (a_min - a_max)*a_min + 2*j_max*(a_min*tf - vd)) + 2*af_af*(a_min*a_min
            + 2*j_max*(a_max*tf - vd)) + 4*j_max*(2*a_min*(af*vd + j_max*g1)
            + (a_max*a_max - a_min*a_min)*vd + j_max*vd_vd) + 8*a_max*jj*(pd
            - tf*vf))/(a_max*a_min) + 4*af_af + 2*a0_a0 + (4*af + a_max - a_min)*(a_max - a_min)
            + 4*j_max*(a_min - a_max + j_max*tf - 2*af)*tf) * abs(j_max)/j_max
        )
        t0 = (-a0 + a_max)/j_max
        t1 = (
            (-(af_af - a0_a0 + 2*a_max*a_max + a_min*(a_min - 2*ad - 3*a_max)
            + 2*j_max*(a_min*tf - vd)) + a_min*h1)/(2*(a_max - a_min)*j_max)
        )
        t2 = a_max/j_max
        t3 = (a_min - a_max + h1)/(2*j_max)
        t4 = -a_min/j_max
        t5 = tf - (t0 + t1 + t2 + t3 + 2*t4 + af/j_max)
        t6 = t4 + af/j_max
        if _accept(prof, _UDDU, _ACC0_ACC1_VEL, j_max, v_max, v_min, a_max, a_min,
                   t0, t1, t2, t3, t4, t5, t6):
            return True

    # UDUD
    if (-a0 + 4*a_max - af)/j_max < tf:
        t0 = (-a0 + a_max)/j_max
        t1 = (
            (3*(a0_p4 + af_p4) - 4*(a0_p3 + af_p3)*a_max - 4*af_p3*a_max
            + 24*(a0 + af)*a_max*a_max*a_max - 6*(af_af + a0_a0)*(a_max*a_max - 2*j_max*vd)
            + 6*a0_a0*(af_af - 2*af*a_max - 2*a_max*j_max*tf) - 12*a_max*a_max*(2*a_max*a_max
            - 2*a_max*j_max*tf + j_max*vd) - 24*af*a_max*j_max*vd
            + 12*jj*(2*a_max*g1 + vd_vd))/(12*a_max*j_max*(a0_a0 + af_af - 2*(a0 + af)*a_max
            + 2*(a_max*a_max - a_max*j_max*tf + j_max*vd)))
        )
        t2 = a_max/j_max
        t3 = (-a0_a0 - af_af + 2*a_max*(a0 + af - 2*a_max) - 2*j_max*vd)/(2*a_max*j_max) + tf
        t4 = t2
        t5 = tf - (t0 + t1 + t2 + t3 + 2*t4 - af/j_max)
        t6 = t4 - af/j_max
        if _accept(prof, _UDUD, _ACC0_ACC1_VEL, j_max, v_max, v_min, a_max, a_min,
                   t0, t1, t2, t3, t4, t5, t6):
            return True

    return False


@njit(cache=True, error_model="numpy")
def _time_acc1_vel(prof, k, roots, v_max, v_min, a_max, a_min, j_max):
    """Second acceleration limit and the velocity limit reached."""
    (tf, v0, a0, _, af, pd, _, _, _, vd, vd_vd, _, _, ad, _, a0_a0, a0_p3, a0_p4, _, _, af_af,
     af_p3, af_p4, _, _, g1, _) = k
    jj = j_max * j_max

    # UDDU: a quartic in the duration of the first phase.
    ph1 = a0_a0 + af_af - a_min*(a0 + 2*af - a_min) - 2*j_max*(vd - a_min*tf)
    ph2 = 2*a_min*(j_max*g1 + af*vd) - a_min*a_min*vd + j_max*vd_vd
    ph3 = af_af + a_min*(a_min - 2*af) - 2*j_max*(vd - a_min*tf)
    c0 = (2*(2*a0 - a_min))/j_max
    c1 = (4*a0_a0 + ph1 - 3*a0*a_min)/jj
    c2 = (2*a0*ph1)/(jj*j_max)
    c3 = (
        (3*(a0_p4 + af_p4) - 4*(a0_p3 + 2*af_p3)*a_min + 6*af_af*(a_min*a_min - 2*j_max*vd)
        + 12*j_max*ph2 + 6*a0_a0*ph3)/(12*jj*jj)
    )
    t_min = -a0/j_max
    t_max = _min((tf + 2*a_min/j_max - (a0 + af)/j_max)/2, (a_max - a0)/j_max)
    n = solve_quart_monic(c0, c1, c2, c3, roots)
    for i in range(n):
        t = roots[i]
        if t < t_min or t > t_max:
            continue
        # One Newton step on the position error polishes the closed-form root.
        if abs(a0 + j_max*t) > 16*EPS:
            h0 = j_max*t*t
            orig = (
                -pd + (3*(a0_p4 + af_p4) - 8*af_p3*a_min - 4*a0_p3*a_min
                + 6*af_af*(a_min*a_min + 2*j_max*(h0 - vd)) + 6*a0_a0*(af_af - 2*af*a_min
                + a_min*a_min + 2*a_min*j_max*(-2*t + tf) + 2*j_max*(5*h0 - vd))
                + 24*a0*j_max*t*(a0_a0 + af_af - 2*af*a_min + a_min*a_min
                + 2*j_max*(a_min*(-t + tf) + h0 - vd)) - 24*af*a_min*j_max*(h0 - vd)
                + 12*j_max*(a_min*a_min*(h0 - vd) + j_max*(h0 - vd)*(h0 - vd)))/(24*a_min*jj)
                + h0*(tf - t) + tf*v0
            )
            deriv = (
                (a0 + j_max*t)*((a0_a0 + af_af)/(a_min*j_max) + (a_min - a0 - 2*af)/j_max
                + (4*a0*t + 2*h0 - 2*vd)/a_min + 2*tf - 3*t)
            )
            t -= orig / deriv
        h1 = -((a0_a0 + af_af)/2 + j_max*(-vd + 2*a0*t + j_max*t*t))/a_min
        t0 = t
        t1 = 0.0
        t2 = a0/j_max + t
        t3 = tf - (h1 - a_min + a0 + af)/j_max - 2*t
        t4 = -a_min/j_max
        t5 = (h1 + a_min)/j_max
        t6 = t4 + af/j_max
        if _accept(prof, _UDDU, _ACC1_VEL, j_max, v_max, v_min, a_max, a_min,
                   t0, t1, t2, t3, t4, t5, t6):
            return True

    # UDUD
    ph1 = a0_a0 - af_af + (2*af - a0)*a_max - a_max*a_max - 2*j_max*(vd - a_max*tf)
    ph2 = a_max*a_max + 2*j_max*vd
    ph3 = af_af + ph2 - 2*a_max*(af + j_max*tf)
    ph4 = 2*a_max*j_max*g1 + a_max*a_max*vd + j_max*vd_vd
    c0 = (4*a0 - 2*a_max)/j_max
    c1 = (4*a0_a0 - 3*a0*a_max + ph1)/jj
    c2 = (2*a0*ph1)/(jj*j_max)
    c3 = (
        (3*(a0_p4 + af_p4) - 4*(a0_p3 + 2*af_p3)*a_max - 24*af*a_max*j_max*vd + 12*j_max*ph4
        - 6*a0_a0*ph3 + 6*af_af*ph2)/(12*jj*jj)
    )
    t_min = -a0/j_max
    t_max = _min((tf + ad/j_max - 2*a_max/j_max)/2, (a_max - a0)/j_max)
    n = solve_quart_monic(c0, c1, c2, c3, roots)
    for i in range(n):
        t = roots[i]
        if t > t_max or t < t_min:
            continue
        h1 = ((a0_a0 - af_af)/2 + jj*t*t - j_max*(vd - 2*a0*t))/a_max
        t0 = t
        t1 = 0.0
        t2 = t + a0/j_max
        t3 = tf + (h1 + ad - a_max)/j_max - 2*t
        t4 = a_max/j_max
        t5 = -(h1 + a_max)/j_max
        t6 = t4 - af/j_max
        if _accept(prof, _UDUD, _ACC1_VEL, j_max, v_max, v_min, a_max, a_min,
                   t0, t1, t2, t3, t4, t5, t6):
            return True

    return False


@njit(cache=True, error_model="numpy")
def _time_acc0_vel(prof, k, roots, v_max, v_min, a_max, a_min, j_max):
    """First acceleration limit and the velocity limit reached."""
    (tf, _, a0, vf, af, pd, _, _, _, vd, vd_vd, _, _, ad, _, a0_a0, a0_p3, a0_p4, _, _, af_af,
     af_p3, af_p4, _, _, _, _) = k
    jj = j_max * j_max

    # Reaching the first acceleration limit and leaving it already takes this long.
    if tf < _max((-a0 + a_max)/j_max, 0.0) + _max(a_max/j_max, 0.0):
        return False

    ph1 = 12*j_max*(-a_max*a_max*vd - j_max*vd_vd + 2*a_max*j_max*(-pd + tf*vf))

    # UDDU: a quartic in the duration of the fifth phase.
    c0 = (2*a_max)/j_max
    c1 = (a0_a0 - af_af + 2*ad*a_max + a_max*a_max + 2*j_max*(vd - a_max*tf))/jj
    c2 = 0.0
    c3 = (
        -(-3*(a0_p4 + af_p4) + 4*(af_p3 + 2*a0_p3)*a_max - 12*a0*a_max*(af_af - 2*j_max*vd)
        + 6*a0_a0*(af_af - a_max*a_max - 2*j_max*vd) + 6*af_af*(a_max*a_max - 2*a_max*j_max*tf
        + 2*j_max*vd) + ph1)/(12*jj*jj)
    )
    t_min = -af/j_max
    t_max = _min(tf - (2*a_max - a0)/j_max, -a_min/j_max)
    n = solve_quart_monic(c0, c1, c2, c3, roots)
    for i in range(n):
        t = roots[i]
        if t < t_min or t > t_max:
            continue
        if t > EPS:
            h1 = j_max*t*t + vd
            orig = (
                (-3*(a0_p4 + af_p4) + 4*(af_p3 + 2*a0_p3)*a_max - 24*af*a_max*jj*t*t
                - 12*a0*a_max*(af_af - 2*j_max*h1) + 6*a0_a0*(af_af - a_max*a_max - 2*j_max*h1)
                + 6*af_af*(a_max*a_max - 2*a_max*j_max*tf + 2*j_max*h1)
                - 12*j_max*(a_max*a_max*h1 + j_max*h1*h1 + 2*a_max*j_max*(pd + j_max*t*t*(t - tf)
                - tf*vf)))/(24*a_max*jj)
            )
            deriv = (
                -t*(a0_a0 - af_af + 2*a_max*(ad - j_max*tf) + a_max*a_max + 3*a_max*j_max*t
                + 2*j_max*h1)/a_max
            )
            t -= orig / deriv
        h1 = ((a0_a0 - af_af)/2 + j_max*(j_max*t*t + vd))/a_max
        t0 = (-a0 + a_max)/j_max
        t1 = (h1 - a_max)/j_max
        t2 = a_max/j_max
        t3 = tf - (h1 + ad + a_max)/j_max - 2*t
        t4 = t
        t5 = 0.0
        t6 = af/j_max + t
        if _accept(prof, _UDDU, _ACC0_VEL, j_max, v_max, v_min, a_max, a_min,
                   t0, t1, t2, t3, t4, t5, t6):
            return True

    # UDUD
    c0 = (-2*a_max)/j_max
    c1 = -(a0_a0 + af_af - 2*(a0 + af)*a_max + a_max*a_max + 2*j_max*(vd - a_max*tf))/jj
    c2 = 0.0
    c3 = (
        (3*(a0_p4 + af_p4) - 4*(af_p3 + 2*a0_p3)*a_max + 6*a0_a0*(af_af + a_max*a_max + 2*j_max*vd)
        - 12*a0*a_max*(af_af + 2*j_max*vd) + 6*af_af*(a_max*a_max - 2*a_max*j_max*tf + 2*j_max*vd)
        - ph1)/(12*jj*jj)
    )
    t_min = af/j_max
    t_max = _min(tf - a_max/j_max, a_max/j_max)
    n = solve_quart_monic(c0, c1, c2, c3, roots)
    for i in range(n):
        t = roots[i]
        if t < t_min or t > t_max:
            continue
        h1 = j_max*t*t - vd
        orig = (
            -(3*(a0_p4 + af_p4) - 4*(2*a0_p3 + af_p3)*a_max + 24*af*a_max*jj*t*t
            - 12*a0*a_max*(af_af - 2*j_max*h1) + 6*a0_a0*(af_af + a_max*a_max - 2*j_max*h1)
            + 6*af_af*(a_max*a_max - 2*j_max*(tf*a_max + h1)) + 12*j_max*(-a_max*a_max*h1
            + j_max*h1*h1 - 2*a_max*j_max*(-pd + j_max*t*t*(t - tf) + tf*vf)))/(24*a_max*jj)
        )
        deriv = (
            t*(a0_a0 + af_af - 2*j_max*h1 - 2*(a0 + af + j_max*tf)*a_max + a_max*a_max
            + 3*a_max*j_max*t)/a_max
        )
        t -= orig / deriv
        h1 = ((a0_a0 + af_af)/2 + j_max*(vd - j_max*t*t))/a_max
        t0 = (-a0 + a_max)/j_max
        t1 = (h1 - a_max)/j_max
        t2 = a_max/j_max
        t3 = tf - (h1 - a0 - af + a_max)/j_max - 2*t
        t4 = t
        t5 = 0.0
        t6 = -(af/j_max) + t
        if _accept(prof, _UDUD, _ACC0_VEL, j_max, v_max, v_min, a_max, a_min,
                   t0, t1, t2, t3, t4, t5, t6):
            return True

    return False


@njit(cache=True, error_model="numpy")
def _vel_uddu_root(prof, k, t, v_max, v_min, a_max, a_min, j_max):
    """Polish and try one root of the quintic of :func:`_time_vel` (UDDU)."""
    (tf, v0, a0, _, af, pd, _, _, _, vd, _, _, _, _, _, a0_a0, a0_p3, _, _, _, af_af, af_p3, _, _,
     _, _, _) = k
    jj = j_max * j_max

    # One Newton step on the position error, skipped where it is undefined.
    h1 = math.sqrt((a0_a0 + af_af)/(2*jj) + (2*a0*t + j_max*t*t - vd)/j_max)
    orig = (
        -pd - (2*a0_p3 + 4*af_p3 + 24*a0*j_max*t*(af + j_max*(h1 + t - tf))
        + 6*a0_a0*(af + j_max*(2*t - tf)) + 6*(a0_a0 + af_af)*j_max*h1
        + 12*af*j_max*(j_max*t*t - vd) + 12*jj*(j_max*t*t*(h1 + t - tf) - tf*v0 - h1*vd))/(12*jj)
    )
    deriv_newton = -(a0 + j_max*t)*(3*(h1 + t) - 2*tf + (a0 + 2*af)/j_max)
    if not math.isnan(orig) and not math.isnan(deriv_newton) and abs(deriv_newton) > EPS:
        t -= orig / deriv_newton

    if t > tf or math.isnan(t):
        return False

    h1 = math.sqrt((a0_a0 + af_af)/(2*jj) + (t*(2*a0 + j_max*t) - vd)/j_max)
    t0 = t
    t1 = 0.0
    t2 = t + a0/j_max
    t3 = tf - 2*(t + h1) - (a0 + af)/j_max
    t4 = h1
    t5 = 0.0
    t6 = h1 + af/j_max
    return _accept(prof, _UDDU, _VEL, j_max, v_max, v_min, a_max, a_min,
                   t0, t1, t2, t3, t4, t5, t6)


@njit(cache=True, error_model="numpy")
def _vel_udud_root(prof, k, t, v_max, v_min, a_max, a_min, j_max):
    """Polish and try one root of the sextic of :func:`_time_vel` (UDUD)."""
    (tf, v0, a0, _, af, pd, _, _, _, vd, _, _, _, ad, _, a0_a0, a0_p3, _, _, _, af_af, af_p3, _, _,
     _, _, _) = k
    jj = j_max * j_max

    # Two Newton steps on the position error (the second only if still needed).
    h1 = math.sqrt((af_af - a0_a0)/(2*jj) - ((2*a0 + j_max*t)*t - vd)/j_max)
    orig = (
        -pd + (af_p3 - a0_p3 + 3*a0_a0*j_max*(tf - 2*t))/(6*jj) + (2*a0 + j_max*t)*t*(tf - t)
        + (j_max*h1 - af)*h1*h1 + tf*v0
    )
    deriv_newton = (a0 + j_max*t)*(2*(af + j_max*tf) - 3*j_max*(h1 + t) - a0)/j_max
    t -= orig / deriv_newton
    h1 = math.sqrt((af_af - a0_a0)/(2*jj) - ((2*a0 + j_max*t)*t - vd)/j_max)
    orig = (
        -pd + (af_p3 - a0_p3 + 3*a0_a0*j_max*(tf - 2*t))/(6*jj) + (2*a0 + j_max*t)*t*(tf - t)
        + (j_max*h1 - af)*h1*h1 + tf*v0
    )
    if abs(orig) > 1e-9:
        deriv_newton = (a0 + j_max*t)*(2*(af + j_max*tf) - 3*j_max*(h1 + t) - a0)/j_max
        t -= orig / deriv_newton

    h1 = math.sqrt((af_af - a0_a0)/(2*jj) - ((2*a0 + j_max*t)*t - vd)/j_max)
    t0 = t
    t1 = 0.0
    t2 = t + a0/j_max
    t3 = tf - 2*(t + h1) + ad/j_max
    t4 = h1
    t5 = 0.0
    t6 = h1 - af/j_max
    return _accept(prof, _UDUD, _VEL, j_max, v_max, v_min, a_max, a_min,
                   t0, t1, t2, t3, t4, t5, t6)


@njit(cache=True, error_model="numpy")
def _time_vel(prof, k, roots, bounds, v_max, v_min, a_max, a_min, j_max):
    """Only the velocity limit reached.

    With a moving boundary the first phase's duration solves a quintic (UDDU) or
    a sextic (UDUD); their roots are bracketed between the extrema, found from
    the derivative (a quartic, solved in closed form, or bracketed in turn via
    the second derivative), then shrunk by safeguarded Newton.
    """
    (tf, v0, a0, vf, af, pd, tf_tf, _, _, vd, vd_vd, _, _, ad, _, a0_a0, a0_p3, a0_p4, a0_p5,
     a0_p6, af_af, af_p3, af_p4, _, af_p6, g1, _) = k
    jj = j_max * j_max

    tz_min = _max(0.0, -a0/j_max)
    tz_max = _min((tf - a0/j_max)/2, (a_max - a0)/j_max)

    # UDDU
    if abs(v0) < EPS and abs(a0) < EPS and abs(vf) < EPS and abs(af) < EPS:
        # Rest to rest: symmetric, a cubic in the jerk phase duration.
        n = solve_cubic(1.0, -tf/2, 0.0, pd/(2*j_max), roots)
        for i in range(n):
            t = roots[i]
            if t > tf/4:
                continue
            if t > EPS:
                orig = -pd + j_max*t*t*(tf - 2*t)
                deriv = 2*j_max*t*(tf - 3*t)
                t -= orig / deriv
            t0 = t
            t1 = 0.0
            t2 = t
            t3 = tf - 4*t
            t4 = t
            t5 = 0.0
            t6 = t
            if _accept(prof, _UDDU, _VEL, j_max, v_max, v_min, a_max, a_min,
                       t0, t1, t2, t3, t4, t5, t6):
                return True

    else:
        p1 = af_af - 2*j_max*(-2*af*tf + j_max*tf_tf + 3*vd)
        ph1 = af_p3 - 3*jj*g1 - 3*af*j_max*vd
        ph2 = (
            af_p4 + 8*af_p3*j_max*tf + 12*j_max*(3*j_max*vd_vd - af_af*vd + 2*af*j_max*(g1 - tf*vd)
            - 2*jj*tf*g1)
        )
        ph3 = a0*(af - j_max*tf)
        ph4 = j_max*(-ad + j_max*tf)
        c1 = (15*a0_a0 + af_af + 4*af*j_max*tf - 16*ph3 - 2*j_max*(j_max*tf_tf + 3*vd))/(4*ph4)
        c2 = (29*a0_p3 - 2*af_p3 - 33*a0*ph3 + 6*jj*g1 + 6*af*j_max*vd + 6*a0*p1)/(6*j_max*ph4)
        c3 = (61*a0_p4 - 76*a0_a0*ph3 - 16*a0*ph1 + 30*a0_a0*p1 + ph2)/(24*jj*ph4)
        c4 = (a0*(7*a0_p4 - 10*a0_a0*ph3 - 4*a0*ph1 + 6*a0_a0*p1 + ph2))/(12*jj*j_max*ph4)
        c5 = (
            (7*a0_p6 + af_p6 - 12*a0_p4*ph3 + 48*af_p3*jj*g1 - 8*a0_p3*ph1
            - 72*jj*j_max*(j_max*g1*g1 + vd_vd*vd + 2*af*g1*vd) - 6*af_p4*j_max*vd
            + 36*af_af*jj*vd_vd + 9*a0_p4*p1 + 3*a0_a0*ph2)/(144*jj*jj*ph4)
        )
        polynom = (1.0, c1, c2, c3, c4, c5)
        # The derivative scaled to be monic (as poly_monic_derivative): a quartic.
        deriv = (1.0, 4*c1/5, 3*c2/5, 2*c3/5, 1*c4/5)
        n = solve_quart_monic(deriv[1], deriv[2], deriv[3], deriv[4], roots)

        tz_current = tz_min
        for i in range(n):
            tz = roots[i]
            if tz >= tz_max:
                continue
            # One Newton step on the derivative refines the extremum.
            orig = poly_eval(deriv, tz)
            if abs(orig) > TOLERANCE:
                tz -= orig / poly_derivative_eval(deriv, tz)

            val_new = poly_eval(polynom, tz)
            if abs(val_new) < 64 * abs(poly_derivative_eval(deriv, tz)) * TOLERANCE:
                # A double root sits at the extremum itself.
                if _vel_uddu_root(prof, k, tz, v_max, v_min, a_max, a_min, j_max):
                    return True
            elif poly_eval(polynom, tz_current) * val_new < 0:
                t = shrink_interval(polynom, tz_current, tz)
                if _vel_uddu_root(prof, k, t, v_max, v_min, a_max, a_min, j_max):
                    return True
            tz_current = tz
        val_max = poly_eval(polynom, tz_max)
        if poly_eval(polynom, tz_current) * val_max < 0:
            t = shrink_interval(polynom, tz_current, tz_max)
            if _vel_uddu_root(prof, k, t, v_max, v_min, a_max, a_min, j_max):
                return True
        elif abs(val_max) < 8 * EPS:
            if _vel_uddu_root(prof, k, tz_max, v_max, v_min, a_max, a_min, j_max):
                return True

    # UDUD
    ph1 = af_af - 2*j_max*(2*af*tf + j_max*tf_tf - 3*vd)
    ph2 = af_p3 - 3*jj*g1 + 3*af*j_max*vd
    ph3 = 2*j_max*tf*g1 + 3*vd_vd
    ph4 = af_p4 - 8*af_p3*j_max*tf + 12*j_max*(j_max*ph3 + af_af*vd + 2*af*j_max*(g1 - tf*vd))
    ph5 = af + j_max*tf
    c1 = (5*a0 - ph5)/j_max
    c2 = (39*a0_a0 - ph1 - 16*a0*ph5)/(4*jj)
    c3 = (55*a0_p3 - 33*a0_a0*ph5 - 6*a0*ph1 + 2*ph2)/(6*jj*j_max)
    c4 = (101*a0_p4 + ph4 - 76*a0_p3*ph5 - 30*a0_a0*ph1 + 16*a0*ph2)/(24*jj*jj)
    c5 = (a0*(11*a0_p4 + ph4 - 10*a0_p3*ph5 - 6*a0_a0*ph1 + 4*a0*ph2))/(12*jj*jj*j_max)
    c6 = (
        (11*a0_p6 - af_p6 - 12*a0_p5*ph5 - 48*af_p3*jj*g1 - 9*a0_p4*ph1
        + 72*jj*j_max*(j_max*g1*g1 - vd_vd*vd - 2*af*g1*vd) - 6*af_p4*j_max*vd - 36*af_af*jj*vd_vd
        + 8*a0_p3*ph2 + 3*a0_a0*ph4)/(144*jj*jj*jj)
    )
    polynom6 = (1.0, c1, c2, c3, c4, c5, c6)
    # Monic first (a quintic) and second (a quartic) derivatives.
    d1 = 5*c1/6
    d2 = 4*c2/6
    d3 = 3*c3/6
    d4 = 2*c4/6
    d5 = 1*c5/6
    deriv6 = (1.0, d1, d2, d3, d4, d5)
    dderiv6 = (1.0, 4*d1/5, 3*d2/5, 2*d3/5, 1*d4/5)

    # Brackets of the derivative's roots, between the second derivative's roots.
    n = solve_quart_monic(dderiv6[1], dderiv6[2], dderiv6[3], dderiv6[4], roots)
    count = 0
    dd_tz_current = tz_min
    for i in range(n):
        tz = roots[i]
        if tz >= tz_max:
            continue
        orig = poly_eval(dderiv6, tz)
        if abs(orig) > TOLERANCE:
            tz -= orig / poly_derivative_eval(dderiv6, tz)
        if poly_eval(deriv6, dd_tz_current) * poly_eval(deriv6, tz) < 0:
            bounds[count, 0] = dd_tz_current
            bounds[count, 1] = tz
            count += 1
        dd_tz_current = tz
    if poly_eval(deriv6, dd_tz_current) * poly_eval(deriv6, tz_max) < 0:
        bounds[count, 0] = dd_tz_current
        bounds[count, 1] = tz_max
        count += 1
    # The reference keeps the brackets in a sorted set (lexicographic pairs).
    _sort_pairs(bounds, count)

    tz_current = tz_min
    for i in range(count):
        tz = shrink_interval(deriv6, bounds[i, 0], bounds[i, 1])
        if tz >= tz_max:
            continue
        p_val = poly_eval(polynom6, tz)
        if abs(p_val) < 64 * abs(poly_eval(dderiv6, tz)) * TOLERANCE:
            if _vel_udud_root(prof, k, tz, v_max, v_min, a_max, a_min, j_max):
                return True
        elif poly_eval(polynom6, tz_current) * p_val < 0:
            t = shrink_interval(polynom6, tz_current, tz)
            if _vel_udud_root(prof, k, t, v_max, v_min, a_max, a_min, j_max):
                return True
        tz_current = tz
    if poly_eval(polynom6, tz_current) * poly_eval(polynom6, tz_max) < 0:
        t = shrink_interval(polynom6, tz_current, tz_max)
        if _vel_udud_root(prof, k, t, v_max, v_min, a_max, a_min, j_max):
            return True

    return False


@njit(cache=True, error_model="numpy")
def _time_acc0_acc1(prof, k, v_max, v_min, a_max, a_min, j_max):
    """Both acceleration limits reached, no velocity plateau; the jerk is the unknown."""
    (tf, v0, a0, vf, af, pd, tf_tf, _, _, vd, vd_vd, _, _, ad, _, a0_a0, a0_p3, _, _, _, af_af,
     af_p3, _, _, _, g1, g2) = k

    if abs(a0) < EPS and abs(af) < EPS:
        # From and to zero acceleration the jerk has a closed form, and the
        # reference decides on this shape alone. Its t1 does not solve the shape's
        # equations, though (the a_max**2 (2 pd + a_min tf**2 - 2 tf vf) term is
        # doubled), so this branch accepts next to nothing; kept as is, early
        # return included, to stay in step with the reference.
        h1 = 2*a_min*g1 + vd_vd + a_max*(2*pd + a_min*tf_tf - 2*tf*vf)
        h2 = ((a_max - a_min)*(-a_min*vd + a_max*(a_min*tf - vd)))
        jf = h2/h1
        t0 = a_max/jf
        t1 = (-2*a_max*h1 + a_min*a_min*g2)/h2
        t2 = t0
        t3 = 0.0
        t4 = -a_min/jf
        t5 = tf - (2*t0 + t1 + 2*t4)
        t6 = t4
        return _accept_jerk(prof, _UDDU, _ACC0_ACC1, jf, j_max, v_max, v_min, a_max, a_min,
                            t0, t1, t2, t3, t4, t5, t6)

    # UDDU
    h1 = (
        math.sqrt(144*_sq((a_max - a_min)*(-a_min*vd + a_max*(a_min*tf - vd))
        - af_af*(a_max*tf - vd) + 2*af*a_min*(a_max*tf - vd) + a0_a0*(a_min*tf + v0 - vf)
        - 2*a0*a_max*(a_min*tf - vd)) + 48*ad*(3*a0_p3 - 3*af_p3 + 12*a_max*a_min*(-a_max + a_min)
        + 4*af_af*(a_max + 2*a_min) + a0*(-3*af_af + 8*af*(a_min - a_max)
        + 6*(a_max*a_max + 2*a_max*a_min - a_min*a_min)) + 6*af*(a_max*a_max - 2*a_max*a_min
        - a_min*a_min) + a0_a0*(3*af - 4*(2*a_max + a_min)))*(2*a_min*g1 + vd*vd
        + a_max*(2*pd + a_min*tf*tf - 2*tf*vf)))
    )
    jf = (
        -(3*af_af*a_max*tf - 3*a0_a0*a_min*tf - 6*ad*a_max*a_min*tf
        + 3*a_max*a_min*(a_min - a_max)*tf + 3*(a0_a0 - af_af)*vd + 6*vd*(af*a_min - a0*a_max)
        + 3*(a_max*a_max - a_min*a_min)*vd + h1/4)/(6*(2*a_min*g1 + vd*vd
        + a_max*(2*pd + a_min*tf_tf - 2*tf*vf)))
    )
    t0 = (a_max - a0)/jf
    t1 = (
        (a0_a0 - af_af + 2*ad*a_min - 2*(a_max*a_max - 2*a_max*a_min + a_min*a_min + a_min*jf*tf
        - jf*vd))/(2*(a_max - a_min)*jf)
    )
    t2 = a_max/jf
    t3 = 0.0
    t4 = -a_min/jf
    t5 = tf - (t0 + t1 + t2 + 2*t4 + af/jf)
    t6 = t4 + af/jf
    if _accept_jerk(prof, _UDDU, _ACC0_ACC1, jf, j_max, v_max, v_min, a_max, a_min,
                    t0, t1, t2, t3, t4, t5, t6):
        return True

    return False


@njit(cache=True, error_model="numpy")
def _time_acc1(prof, k, v_max, v_min, a_max, a_min, j_max):
    """The second acceleration limit reached."""
    (tf, _, a0, vf, af, pd, tf_tf, _, _, vd, vd_vd, _, _, ad, _, a0_a0, a0_p3, a0_p4, _, _, af_af,
     af_p3, af_p4, _, _, g1, g2) = k
    jj = j_max * j_max

    # UDDU, a3 != 0
    h0 = (
        math.sqrt(jj*(a0_p4 + af_p4 - 4*af_p3*j_max*tf + 6*af_af*jj*tf_tf - 4*a0_p3*(af - j_max*tf)
        + 6*a0_a0*(af - j_max*tf)*(af - j_max*tf) + 24*af*jj*g1
        - 4*a0*(af_p3 - 3*af_af*j_max*tf + 6*jj*(-pd + tf*vf)) - 12*jj*(-vd_vd
        + j_max*tf*g2))/3)/j_max
    )
    h1 = math.sqrt((a0_a0 + af_af - 2*a0*af - 2*ad*j_max*tf + 2*h0)/jj + tf_tf)
    t0 = -(a0_a0 + af_af + 2*a0*(j_max*tf - af) - 2*j_max*vd + h0)/(2*j_max*(-ad + j_max*tf))
    t1 = 0.0
    t2 = (tf - h1)/2 - ad/(2*j_max)
    t3 = 0.0
    t4 = 0.0
    t5 = h1
    t6 = tf - (t0 + t2 + t5)
    if _accept(prof, _UDDU, _ACC1, j_max, v_max, v_min, a_max, a_min,
               t0, t1, t2, t3, t4, t5, t6):
        return True

    # UDUD
    h0 = (
        math.sqrt(jj*(a0_p4 + af_p4 + 4*(af_p3 - a0_p3)*j_max*tf + 6*af_af*jj*tf_tf
        + 6*a0_a0*(af + j_max*tf)*(af + j_max*tf) + 24*af*jj*g1
        - 4*a0*(a0_a0*af + af_p3 + 3*af_af*j_max*tf + 6*jj*(-pd + tf*vf))
        + 12*jj*(vd_vd + j_max*tf*g2))/3)/j_max
    )
    h1 = math.sqrt((a0_a0 + af_af - 2*a0*af + 2*ad*j_max*tf + 2*h0)/jj + tf_tf)
    t0 = 0.0
    t1 = 0.0
    t2 = -(a0_a0 + af_af - 2*a0*af + 2*j_max*(vd - a0*tf) + h0)/(2*j_max*(ad + j_max*tf))
    t3 = 0.0
    t4 = ad/(2*j_max) + (tf - h1)/2
    t5 = h1
    t6 = tf - (t5 + t4 + t2)
    if _accept(prof, _UDUD, _ACC1, j_max, v_max, v_min, a_max, a_min,
               t0, t1, t2, t3, t4, t5, t6):
        return True

    # UDDU, solution 2
    h0a = (
        a0_p3 - af_p3 - 3*a0_a0*a_min + 3*a_min*a_min*(a0 + j_max*tf)
        + 3*af*a_min*(-a_min - 2*j_max*tf) - 3*af_af*(-a_min - j_max*tf)
        - 3*jj*(-2*pd - a_min*tf_tf + 2*tf*vf)
    )
    h0b = a0_a0 + af_af - 2*(a0 + af)*a_min + 2*(a_min*a_min - j_max*(-a_min*tf + vd))
    h0c = (
        a0_p4 + 3*af_p4 - 4*(a0_p3 + 2*af_p3)*a_min + 6*a0_a0*a_min*a_min
        + 6*af_af*(a_min*a_min - 2*j_max*vd) + 12*j_max*(2*a_min*j_max*g1 - a_min*a_min*vd
        + j_max*vd_vd) + 24*af*a_min*j_max*vd - 4*a0*(af_p3 - 3*af*a_min*(-a_min - 2*j_max*tf)
        + 3*af_af*(-a_min - j_max*tf) + 3*j_max*(-a_min*a_min*tf
        + j_max*(-2*pd - a_min*tf_tf + 2*tf*vf)))
    )
    h1 = abs(j_max)/j_max * math.sqrt(4*h0a*h0a - 6*h0b*h0c)
    h2 = 6*j_max*h0b
    t0 = 0.0
    t1 = 0.0
    t2 = (2*h0a + h1)/h2
    t3 = (
        -(a0_a0 + af_af - 2*(a0 + af)*a_min + 2*(a_min*a_min + a_min*j_max*tf
        - j_max*vd))/(2*j_max*(a0 - a_min - j_max*t2))
    )
    t4 = (a0 - a_min)/j_max - t2
    t5 = tf - (t2 + t3 + t4 + (af - a_min)/j_max)
    t6 = (af - a_min)/j_max
    if _accept(prof, _UDDU, _ACC1, j_max, v_max, v_min, a_max, a_min,
               t0, t1, t2, t3, t4, t5, t6):
        return True

    # UDUD, solution 1
    h0a = (
        -a0_p3 + af_p3 + 3*(a0_a0 - af_af)*a_max - 3*ad*a_max*a_max - 6*af*a_max*j_max*tf
        + 3*af_af*j_max*tf + 3*j_max*(a_max*a_max*tf + j_max*(-2*pd - a_max*tf_tf + 2*tf*vf))
    )
    h0b = a0_a0 - af_af + 2*ad*a_max + 2*j_max*(a_max*tf - vd)
    h0c = (
        a0_p4 + 3*af_p4 - 4*(a0_p3 + 2*af_p3)*a_max + 6*a0_a0*a_max*a_max - 24*af*a_max*j_max*vd
        + 12*j_max*(2*a_max*j_max*g1 + j_max*vd_vd + a_max*a_max*vd)
        + 6*af_af*(a_max*a_max + 2*j_max*vd) - 4*a0*(af_p3 + 3*af*a_max*(a_max - 2*j_max*tf)
        - 3*af_af*(a_max - j_max*tf) + 3*j_max*(a_max*a_max*tf + j_max*(-2*pd - a_max*tf_tf
        + 2*tf*vf)))
    )
    h1 = abs(j_max)/j_max * math.sqrt(4*h0a*h0a - 6*h0b*h0c)
    h2 = 6*j_max*h0b
    t0 = 0.0
    t1 = 0.0
    t2 = -(2*h0a + h1)/h2
    t3 = 2*h1/h2
    t4 = (a_max - a0)/j_max + t2
    t5 = tf - (t2 + t3 + t4 + (-af + a_max)/j_max)
    t6 = (-af + a_max)/j_max
    if _accept(prof, _UDUD, _ACC1, j_max, v_max, v_min, a_max, a_min,
               t0, t1, t2, t3, t4, t5, t6):
        return True

    return False


@njit(cache=True, error_model="numpy")
def _time_acc0(prof, k, v_max, v_min, a_max, a_min, j_max):
    """The first acceleration limit reached."""
    (tf, v0, a0, _, af, pd, tf_tf, _, _, vd, _, _, _, ad, ad_ad, a0_a0, a0_p3, _, _, _, af_af,
     af_p3, _, _, _, g1, g2) = k
    jj = j_max * j_max

    # UDUD (checked as NONE, as in the reference)
    h1 = math.sqrt(ad_ad/(2*jj) - ad*(a_max - a0)/(jj) + (a_max*tf - vd)/j_max)
    t0 = (a_max - a0)/j_max
    t1 = tf - ad/j_max - 2*h1
    t2 = h1
    t3 = 0.0
    t4 = (af - a_max)/j_max + h1
    t5 = 0.0
    t6 = 0.0
    if _accept(prof, _UDUD, _NONE, j_max, v_max, v_min, a_max, a_min,
               t0, t1, t2, t3, t4, t5, t6):
        return True

    # UDDU (checked as NONE, as in the reference)
    h0a = -a0_a0 + af_af - 2*ad*a_max + 2*j_max*(a_max*tf - vd)
    h0b = (
        a0_p3 + 2*af_p3 - 6*af_af*a_max - 3*a0_a0*(af - j_max*tf)
        - 3*a0*a_max*(a_max - 2*af + 2*j_max*tf) - 3*j_max*(j_max*(-2*pd + a_max*tf_tf + 2*tf*v0)
        + a_max*(a_max*tf - 2*vd)) + 3*af*(a_max*a_max + 2*a_max*j_max*tf - 2*j_max*vd)
    )
    h0 = abs(j_max) * math.sqrt(4*h0b*h0b - 18*h0a*h0a*h0a)
    h1 = 3*j_max*h0a
    t0 = (-a0 + a_max)/j_max
    t1 = (
        (-a0_p3 + af_p3 + af_af*(-6*a_max + 3*j_max*tf) + a0_a0*(-3*af + 6*a_max + 3*j_max*tf)
        + 6*af*(a_max*a_max - j_max*vd) + 3*a0*(af_af - 2*(a_max*a_max + j_max*vd))
        - 6*j_max*(a_max*(a_max*tf - 2*vd) + j_max*g2))/h1
    )
    t2 = -(ad + h0/h1)/(2*j_max) + tf/2 - t1/2
    t3 = h0/(j_max*h1)
    t4 = 0.0
    t5 = 0.0
    t6 = tf - (t0 + t1 + t2 + t3)
    if _accept(prof, _UDDU, _NONE, j_max, v_max, v_min, a_max, a_min,
               t0, t1, t2, t3, t4, t5, t6):
        return True

    # UDDU, solution 1, a3 != 0
    h0a = (
        a0_p3 + 2*af_p3 - 6*(af_af + a_max*a_max)*a_max - 6*(a0 + af)*a_max*j_max*tf
        + 9*a_max*a_max*(af + j_max*tf) + 3*a0*a_max*(-2*af + 3*a_max)
        + 3*a0_a0*(af - 2*a_max + j_max*tf) - 6*jj*g1 + 6*(af - a_max)*j_max*vd - 3*a_max*jj*tf_tf
    )
    h0b = a0_a0 + af_af + 2*(a_max*a_max - (a0 + af)*a_max + j_max*(vd - a_max*tf))
    h1 = abs(j_max)/j_max * math.sqrt(4*h0a*h0a - 18*h0b*h0b*h0b)
    h2 = 6*j_max*h0b
    t0 = (-a0 + a_max)/j_max
    t1 = ad/j_max - 2 * t0 - (2*h0a - h1)/h2 + tf
    t2 = -(2*h0a + h1)/h2
    t3 = (2*h0a - h1)/h2
    t4 = tf - (t0 + t1 + t2 + t3)
    t5 = 0.0
    t6 = 0.0
    if _accept(prof, _UDDU, _ACC0, j_max, v_max, v_min, a_max, a_min,
               t0, t1, t2, t3, t4, t5, t6):
        return True

    return False


@njit(cache=True, error_model="numpy")
def _time_none(prof, k, roots, v_max, v_min, a_max, a_min, j_max):
    """No limit reached."""
    (tf, v0, a0, vf, af, pd, tf_tf, tf_p3, tf_p4, vd, vd_vd, _, vf_vf, ad, ad_ad, a0_a0, a0_p3,
     a0_p4, a0_p5, a0_p6, af_af, af_p3, af_p4, af_p5, af_p6, g1, g2) = k
    jj = j_max * j_max

    if abs(v0) < EPS and abs(a0) < EPS and abs(af) < EPS:
        # From rest to zero acceleration: fixed phase durations, the jerk is the unknown.
        h1 = math.sqrt(tf_tf*vf_vf + _sq(4*pd - tf*vf))
        jf = 4*(4*pd - 2*tf*vf + h1)/tf_p3
        t0 = tf/4
        t1 = 0.0
        t2 = 2*t0
        t3 = 0.0
        t4 = 0.0
        t5 = 0.0
        t6 = t0
        if _accept_jerk(prof, _UDDU, _NONE, jf, j_max, v_max, v_min, a_max, a_min,
                        t0, t1, t2, t3, t4, t5, t6):
            return True

    if abs(a0) < EPS and abs(af) < EPS:
        # UDDU, a3 != 0: first accelerate, then constant.
        c0 = -2*tf
        c1 = 2*vd/j_max + tf_tf
        c2 = 4*(pd - tf*vf)/j_max
        c3 = (vd_vd + j_max*tf*g2)/(jj)
        n = solve_quart_monic(c0, c1, c2, c3, roots)
        for i in range(n):
            t = roots[i]
            if t > tf/2 or t > (a_max - a0)/j_max:
                continue
            h1 = (j_max*t*(t - tf) + vd)/(j_max*(2*t - tf))
            h2 = (2*j_max*t*(t - tf) + j_max*tf_tf - 2*vd)/(j_max*(2*t - tf)*(2*t - tf))
            orig = (
                (-2*pd + 2*tf*v0 + h1*h1*j_max*(tf - 2*t) + j_max*tf*(2*h1*t - t*t
                - (h1 - t)*tf))/2
            )
            deriv = (j_max*tf*(2*t - tf)*(h2 - 1))/2 + h1*j_max*(tf - (2*t - tf)*h2 - h1)
            t -= orig / deriv
            t0 = t
            t1 = 0.0
            t2 = (j_max*t*(t - tf) + vd)/(j_max*(2*t - tf))
            t3 = tf - 2*t
            t4 = t - t2
            t5 = 0.0
            t6 = 0.0
            if _accept(prof, _UDDU, _NONE, j_max, v_max, v_min, a_max, a_min,
                       t0, t1, t2, t3, t4, t5, t6):
                return True

    # UDUD, phases 0 2 4 6
    h0 = (
        math.sqrt(2*jj*(2*_sq(a0_p3 - af_p3 - 3*af_af*j_max*tf + 9*af*jj*tf_tf
        - 3*a0_a0*(af + j_max*tf) + 3*a0*_sq(af + j_max*tf) + 3*jj*(8*pd + j_max*tf_tf*tf
        - 8*tf*vf)) - 3*(a0_a0 + af_af - 2*af*j_max*tf - 2*a0*(af + j_max*tf)
        - j_max*(j_max*tf_tf + 4*v0 - 4*vf))*(a0_p4 + af_p4 + 4*af_p3*j_max*tf + 6*af_af*jj*tf_tf
        - 3*jj*jj*tf_tf*tf_tf - 4*a0_p3*(af + j_max*tf) + 6*a0_a0*_sq(af + j_max*tf)
        - 12*af*jj*(8*pd + j_max*tf_tf*tf - 8*tf*v0) + 48*jj*vd_vd + 48*jj*j_max*tf*g2
        - 4*a0*(af_p3 + 3*af_af*j_max*tf - 9*af*jj*tf_tf - 3*jj*(8*pd + j_max*tf_tf*tf
        - 8*tf*vf)))))/j_max
    )
    h1 = (
        12*j_max*(-a0_a0 - af_af + 2*af*j_max*tf + 2*a0*(af + j_max*tf)
        + j_max*(j_max*tf_tf + 4*v0 - 4*vf))
    )
    h2 = (
        -4*a0_p3 + 4*af_p3 + 12*a0_a0*af - 12*a0*af_af + 48*jj*pd + 12*(a0_a0 - af_af)*j_max*tf
        - 24*jj*tf*(v0 + vf) + 24*ad*j_max*vd
    )
    h3 = 2*a0_p3 - 2*af_p3 - 6*a0_a0*af + 6*a0*af_af
    t0 = (
        (h3 - 48*jj*(tf*vf - pd) - 6*(a0_a0 + af_af)*j_max*tf + 12*a0*af*j_max*tf
        + 6*(a0 + 3*af + j_max*tf)*tf_tf*jj - h0)/h1
    )
    t1 = 0.0
    t2 = (h2 + h0)/h1
    t3 = 0.0
    t4 = (-h2 + h0)/h1
    t5 = 0.0
    t6 = (
        (-h3 + 48*jj*(tf*v0 - pd) - 6*(a0_a0 + af_af)*j_max*tf + 12*a0*af*j_max*tf
        + 6*(af + 3*a0 + j_max*tf)*tf_tf*jj - h0)/h1
    )
    if _accept(prof, _UDUD, _NONE, j_max, v_max, v_min, a_max, a_min,
               t0, t1, t2, t3, t4, t5, t6):
        return True

    # UDDU, a3 != 0, phases 0 2 3 4
    ph1 = af + j_max*tf
    c0 = -2*(ad + j_max*tf)/j_max
    c1 = 2*(a0_a0 + af_af + j_max*(af*tf + vd) - 2*a0*ph1)/jj + tf_tf
    c2 = (
        2*(a0_p3 - af_p3 - 3*af_af*j_max*tf + 3*a0*ph1*(ph1 - a0)
        - 6*jj*(-pd + tf*vf))/(3*jj*j_max)
    )
    c3 = (
        (a0_p4 + af_p4 + 4*af_p3*j_max*tf - 4*a0_p3*ph1 + 6*a0_a0*ph1*ph1 + 24*jj*af*g1
        - 4*a0*(af_p3 + 3*af_af*j_max*tf + 6*jj*(-pd + tf*vf)) + 6*jj*af_af*tf_tf
        + 12*jj*(vd_vd + j_max*tf*g2))/(12*jj*jj)
    )
    t_min = ad/j_max
    t_max = _min((a_max - a0)/j_max, (ad/j_max + tf) / 2)
    n = solve_quart_monic(c0, c1, c2, c3, roots)
    for i in range(n):
        t = roots[i]
        if t < t_min or t > t_max:
            continue
        h0 = j_max*(2*t - tf) - ad
        h1 = (
            (ad_ad - 2*af*j_max*t + 2*a0*j_max*(t - tf) + 2*j_max*(j_max*t*(t - tf)
            + vd))/(2*j_max*h0)
        )
        h2 = (-ad_ad + 2*jj*(tf_tf + t*(t - tf)) + (a0 + af)*j_max*tf - ad*h0 - 2*j_max*vd)/(h0*h0)
        orig = (
            (-a0_p3 + af_p3 + 3*ad_ad*j_max*(h1 - t) + 3*ad*jj*(h1 - t)*(h1 - t) - 3*a0*af*ad
            + 3*jj*(a0*tf_tf - 2*pd + 2*tf*v0 + h1*h1*j_max*(tf - 2*t)
            + j_max*tf*(2*h1*t - t*t - (h1 - t)*tf)))/(6*jj)
        )
        deriv = (h0*(-ad + j_max*tf)*(h2 - 1))/(2*j_max) + h1*(-ad + j_max*(tf - h1) - h0*h2)
        t -= orig / deriv
        t0 = t
        t1 = 0.0
        t2 = (
            (ad_ad + 2*j_max*(-a0*tf - ad*t + j_max*t*(t - tf) + vd))/(2*j_max*(-ad
            + j_max*(2*t - tf)))
        )
        t3 = ad/j_max + tf - 2*t
        t4 = tf - (t + t2 + t3)
        t5 = 0.0
        t6 = 0.0
        if _accept(prof, _UDDU, _NONE, j_max, v_max, v_min, a_max, a_min,
                   t0, t1, t2, t3, t4, t5, t6):
            return True

    # UDDU, phases 3 4 5 6
    h1 = 3*j_max*(ad_ad + 2*j_max*(a0*tf - vd))
    h2 = ad_ad + 2*j_max*(a0*tf - vd)
    h0 = (
        math.sqrt(4*_sq(2*(a0_p3 - af_p3) - 6*a0_a0*(af - j_max*tf) + 6*jj*g1
        + 3*a0*(2*af_af - 2*j_max*af*tf + jj*tf_tf) + 6*ad*j_max*vd)
        - 18*h2*h2*h2)/h1 * abs(j_max)/j_max
    )
    t0 = 0.0
    t1 = 0.0
    t2 = 0.0
    t3 = (af_p3 - a0_p3 + 3*(af_af - a0_a0)*j_max*tf - 3*ad*(a0*af + 2*j_max*vd) - 6*jj*g2)/h1
    t4 = (tf - t3 - h0)/2 - ad/(2*j_max)
    t5 = h0
    t6 = (tf - t3 + ad/j_max - h0)/2
    if _accept(prof, _UDDU, _NONE, j_max, v_max, v_min, a_max, a_min,
               t0, t1, t2, t3, t4, t5, t6):
        return True

    # UDDU, phases 2 3 4 6
    ph1 = ad_ad + 2*(af + a0)*j_max*tf - j_max*(j_max*tf_tf + 4*vd)
    ph2 = j_max*tf_tf*g1 - vd*(-2*pd - tf*v0 + 3*tf*vf)
    ph3 = 5*af_af - 8*af*j_max*tf + 2*j_max*(2*j_max*tf_tf - vd)
    ph4 = jj*tf_p4 - 2*vd_vd + 8*j_max*tf*(-pd + tf*vf)
    ph5 = (
        5*af_p4 - 8*af_p3*j_max*tf - 12*af_af*j_max*(j_max*tf_tf + vd)
        + 24*af*jj*(-2*pd + j_max*tf_p3 + 2*tf*vf) - 6*jj*ph4
    )
    ph6 = -vd_vd + j_max*tf*(-2*pd + 3*tf*v0 - tf*vf) - af*g2
    c0 = (
        -(4*(a0_p3 - af_p3) - 12*a0_a0*(af - j_max*tf) + 6*a0*(2*af_af - 2*af*j_max*tf
        + j_max*(j_max*tf_tf - 2*vd)) + 6*af*j_max*(3*j_max*tf_tf + 2*vd)
        - 6*jj*(-4*pd + j_max*tf_p3 - 2*tf*v0 + 6*tf*vf))/(3*j_max*ph1)
    )
    c1 = (
        -(-a0_p4 - af_p4 + 4*a0_p3*(af - j_max*tf) + a0_a0*(-6*af_af + 8*af*j_max*tf
        - 4*j_max*(j_max*tf_tf - vd)) + 2*af_af*j_max*(j_max*tf_tf + 2*vd)
        - 4*af*jj*(-3*pd + j_max*tf_p3 + 2*tf*v0 + tf*vf) + jj*(jj*tf_p4 - 8*vd_vd
        + 4*j_max*tf*(-3*pd + tf*v0 + 2*tf*vf)) + 2*a0*(2*af_p3 - 2*af_af*j_max*tf
        + af*j_max*(-3*j_max*tf_tf - 4*vd) + jj*(-6*pd + j_max*tf_p3 - 4*tf*v0
        + 10*tf*vf)))/(jj*ph1)
    )
    c2 = (
        -(a0_p5 - af_p5 + af_p4*j_max*tf - 5*a0_p4*(af - j_max*tf) + 2*a0_p3*ph3
        + 4*af_p3*j_max*(j_max*tf_tf + vd) + 12*jj*af*ph6 - 2*a0_a0*(5*af_p3 - 9*af_af*j_max*tf
        - 6*af*j_max*vd + 6*jj*(-2*pd - tf*v0 + 3*tf*vf)) - 12*jj*j_max*ph2
        + a0*ph5)/(3*jj*j_max*ph1)
    )
    c3 = (
        -(-a0_p6 - af_p6 + 6*a0_p5*(af - j_max*tf) - 48*af_p3*jj*g1
        + 72*jj*j_max*(j_max*g1*g1 + vd_vd*vd + 2*af*g1*vd) - 3*a0_p4*ph3 - 36*af_af*jj*vd_vd
        + 6*af_p4*j_max*vd + 4*a0_p3*(5*af_p3 - 9*af_af*j_max*tf - 6*af*j_max*vd
        + 6*jj*(-2*pd - tf*v0 + 3*tf*vf)) - 3*a0_a0*ph5 + 6*a0*(af_p5 - af_p4*j_max*tf
        - 4*af_p3*j_max*(j_max*tf_tf + vd) + 12*jj*(-af*ph6 + j_max*ph2)))/(18*jj*jj*ph1)
    )
    t_max = (a0 - a_min)/j_max
    n = solve_quart_monic(c0, c1, c2, c3, roots)
    for i in range(n):
        t = roots[i]
        if t > t_max:
            continue
        h1 = ad_ad/2 + j_max*(af*t + (j_max*t - a0)*(t - tf) - vd)
        h2 = -ad + j_max*(tf - 2*t)
        h3 = math.sqrt(h1)
        orig = (
            (af_p3 - a0_p3 + 3*af*j_max*t*(af + j_max*t) + 3*a0_a0*(af + j_max*t)
            - 3*a0*(af_af + 2*af*j_max*t + jj*(t*t - tf_tf)) + 3*jj*(-2*pd + j_max*t*(t - tf)*tf
            + 2*tf*v0))/(6*jj) - h3*h3*h3/(j_max*abs(j_max)) + ((-ad - j_max*t)*h1)/(jj)
        )
        deriv = (
            (6*j_max*h2*h3/abs(j_max) + 2*(-ad - j_max*tf)*h2 - 2*(3*ad_ad + af*j_max*(8*t - 2*tf)
            + 4*a0*j_max*(-2*t + tf) + 2*j_max*(j_max*t*(3*t - 2*tf) - vd)))/(4*j_max)
        )
        t -= orig / deriv
        h1 = math.sqrt(2*ad_ad + 4*j_max*(ad*t + a0*tf + j_max*t*(t - tf) - vd))/abs(j_max)
        t0 = 0.0
        t1 = 0.0
        t2 = t
        t3 = tf - 2*t - ad/j_max - h1
        t4 = h1/2
        t5 = 0.0
        t6 = tf - (t + t3 + t4)
        if _accept(prof, _UDDU, _NONE, j_max, v_max, v_min, a_max, a_min,
                   t0, t1, t2, t3, t4, t5, t6):
            return True

    # UDUD, a3 != 0, phases 0 1 2 4
    ph0 = -2*pd - tf*v0 + 3*tf*vf
    ph1 = -ad + j_max*tf
    ph2 = j_max*tf_tf*g1 - vd*ph0
    ph3 = 5*af_af + 2*j_max*(2*j_max*tf_tf - vd - 4*af*tf)
    ph4 = jj*tf_p4 - 2*vd_vd + 8*j_max*tf*(-pd + tf*vf)
    ph5 = (
        5*af_p4 - 8*af_p3*j_max*tf - 12*af_af*j_max*(j_max*tf_tf + vd)
        + 24*af*jj*(-2*pd + j_max*tf_p3 + 2*tf*vf) - 6*jj*ph4
    )
    ph6 = -vd_vd + j_max*tf*(-2*pd + 3*tf*v0 - tf*vf)
    ph7 = 3*jj*ph1*ph1
    c0 = (4*af*tf - 2*j_max*tf_tf - 4*vd)/ph1
    c1 = (
        (-2*(a0_p4 + af_p4) + 8*af_p3*j_max*tf + 6*af_af*jj*tf_tf + 8*a0_p3*(af - j_max*tf)
        - 12*a0_a0*(af - j_max*tf)*(af - j_max*tf) - 12*af*jj*(-pd + j_max*tf_p3 - 2*tf*v0
        + 3*tf*vf) + 2*a0*(4*af_p3 - 12*af_af*j_max*tf + 9*af*jj*tf_tf
        - 3*jj*(2*pd + j_max*tf_p3 - 2*tf*vf)) + 3*jj*(jj*tf_p4 + 4*vd_vd
        - 4*j_max*tf*(pd + tf*v0 - 2*tf*vf)))/ph7
    )
    c2 = (
        (-a0_p5 + af_p5 - af_p4*j_max*tf + 5*a0_p4*(af - j_max*tf) - 2*a0_p3*ph3
        - 4*af_p3*j_max*(j_max*tf_tf + vd) + 12*af_af*jj*g2 - 12*af*jj*ph6
        + 2*a0_a0*(5*af_p3 - 9*af_af*j_max*tf - 6*af*j_max*vd + 6*jj*ph0) + 12*jj*j_max*ph2
        + a0*(-5*af_p4 + 8*af_p3*j_max*tf + 12*af_af*j_max*(j_max*tf_tf + vd)
        - 24*af*jj*(-2*pd + j_max*tf_p3 + 2*tf*vf) + 6*jj*ph4))/(j_max*ph7)
    )
    c3 = (
        -(a0_p6 + af_p6 - 6*a0_p5*(af - j_max*tf) + 48*af_p3*jj*g1
        - 72*jj*j_max*(j_max*g1*g1 + vd_vd*vd + 2*af*g1*vd) + 3*a0_p4*ph3 - 6*af_p4*j_max*vd
        + 36*af_af*jj*vd_vd - 4*a0_p3*(5*af_p3 - 9*af_af*j_max*tf - 6*af*j_max*vd + 6*jj*ph0)
        + 3*a0_a0*ph5 - 6*a0*(af_p5 - af_p4*j_max*tf - 4*af_p3*j_max*(j_max*tf_tf + vd)
        + 12*jj*(af_af*g2 - af*ph6 + j_max*ph2)))/(6*jj*ph7)
    )
    n = solve_quart_monic(c0, c1, c2, c3, roots)
    for i in range(n):
        t = roots[i]
        if t > tf or t > (a_max - a0)/j_max:
            continue
        h1 = math.sqrt(ad_ad/(2*jj) + (a0*(t + tf) - af*t + j_max*t*tf - vd)/j_max)
        t0 = t
        t1 = tf - ad/j_max - 2*h1
        t2 = h1
        t3 = 0.0
        t4 = ad/j_max + h1 - t
        t5 = 0.0
        t6 = 0.0
        if _accept(prof, _UDUD, _NONE, j_max, v_max, v_min, a_max, a_min,
                   t0, t1, t2, t3, t4, t5, t6):
            return True

    # Three phases up, zero, down (0 1 2): sometimes missed above by rounding.
    h1 = math.sqrt(-ad_ad + j_max*(2*(a0 + af)*tf - 4*vd + j_max*tf_tf)) / abs(j_max)
    t0 = (tf - h1 + ad/j_max)/2
    t1 = h1
    t2 = (tf - h1 - ad/j_max)/2
    t3 = 0.0
    t4 = 0.0
    t5 = 0.0
    t6 = 0.0
    if _accept(prof, _UDDU, _NONE, j_max, v_max, v_min, a_max, a_min,
               t0, t1, t2, t3, t4, t5, t6):
        return True

    # Three phases up, zero, up (0 1 6), the jerk as unknown: a cubic.
    c0 = ad_ad
    c1 = ad_ad*tf
    c2 = (a0_a0 + af_af + 10*a0*af)*tf_tf + 24*(tf*(af*v0 - a0*vf) - pd*ad) + 12*vd_vd
    c3 = -3*tf*((a0_a0 + af_af + 2*a0*af)*tf_tf - 4*vd*(a0 + af)*tf + 4*vd_vd)
    n = solve_cubic(c0, c1, c2, c3, roots)
    for i in range(n):
        t = roots[i]
        if t > tf:
            continue
        jf = ad/(tf - t)
        t0 = (2*(vd - a0*tf) + ad*(t - tf))/(2*jf*t)
        t1 = t
        t2 = 0.0
        t3 = 0.0
        t4 = 0.0
        t5 = 0.0
        t6 = tf - (t0 + t1)
        if _accept_jerk(prof, _UDDU, _NONE, jf, j_max, v_max, v_min, a_max, a_min,
                        t0, t1, t2, t3, t4, t5, t6):
            return True

    # Three phases up, down, up (0 2 6).
    t0 = (ad_ad/j_max + 2*(a0 + af)*tf - j_max*tf_tf - 4*vd)/(4*(ad - j_max*tf))
    t1 = 0.0
    t2 = -ad/(2*j_max) + tf/2
    t3 = 0.0
    t4 = 0.0
    t5 = 0.0
    t6 = tf - (t0 + t2)
    if _accept(prof, _UDDU, _NONE, j_max, v_max, v_min, a_max, a_min,
               t0, t1, t2, t3, t4, t5, t6):
        return True

    return False


@njit(cache=True, error_model="numpy")
def _time_none_smooth(prof, k, v_max, v_min, a_max, a_min, j_max):
    """No limit reached, smooth shapes (three or four phases).

    Ported for completeness: the reference defines it but its ``get_profile``
    does not call it, and neither does :func:`timed` (to stay in step with it).
    """
    (tf, v0, a0, vf, af, pd, tf_tf, _, _, vd, vd_vd, _, _, ad, ad_ad, a0_a0, a0_p3, a0_p4, _, _,
     af_af, af_p3, af_p4, _, _, _, _) = k
    jj = j_max * j_max

    h0 = ad_ad + 2*j_max*(a0*tf - vd)
    h1a = (
        2*(a0_p3 - af_p3) - 6*a0_a0*(af - j_max*tf) + 6*jj*(-pd + tf*v0) + 6*a0*af_af
        + 3*a0*j_max*(j_max*tf_tf - 2*vd) + 6*af*j_max*(vd - tf*a0)
    )
    h1 = math.sqrt(4*h1a*h1a - 18*h0*h0*h0) * abs(j_max) / j_max
    t0 = 0.0
    t1 = (
        (-a0_p3 + af_p3 + 3*(af_af - a0_a0)*j_max*tf - 3*a0*af*ad - 6*j_max*ad*vd
        - 6*jj*(-2*pd + tf*(v0 + vf)))/(3*j_max*h0)
    )
    t2 = (
        (4*(a0_p3 - af_p3) + 6*jj*a0*tf_tf + 12*a0*af*ad + 12*j_max*(j_max*(tf*v0 - pd)
        + ad*(vd - a0*tf)) - h1)/(6*j_max*h0)
    )
    t3 = h1/(3*j_max*h0)
    t4 = 0.0
    t5 = 0.0
    t6 = tf - (t1 + t2 + t3)
    if _accept(prof, _UDDU, _NONE, j_max, v_max, v_min, a_max, a_min,
               t0, t1, t2, t3, t4, t5, t6):
        return True

    h0 = ad_ad + 2*j_max*(vd - af*tf)
    h0b = af_p3 - 3*jj*(af*tf_tf + 2*(pd - tf*vf))
    h1a = a0_p3 + 3*a0*af*ad - h0b
    h1 = (
        math.sqrt(4*h1a*h1a - 6*h0*(a0_p4 + af_p4 - 4*a0_p3*af + 6*a0_a0*af_af
        + 12*jj*(vd_vd - 2*af*(pd - tf*v0)) - 4*a0*h0b)) * abs(j_max) / j_max
    )
    t0 = -(2*h1a + h1)/(6*j_max*h0)
    t1 = h1/(3*j_max*h0)
    t2 = t0 - (af - a0)/j_max
    t3 = 0.0
    t4 = 0.0
    t5 = tf - (t0 + t1 + t2)
    t6 = 0.0
    if _accept(prof, _UDDU, _NONE, j_max, v_max, v_min, a_max, a_min,
               t0, t1, t2, t3, t4, t5, t6):
        return True

    # Solution 3
    h0 = (
        math.sqrt(3*(a0_p4 + af_p4 - 4*af_p3*j_max*tf + 6*af_af*jj*tf_tf - 4*a0_p3*(af - j_max*tf)
        + 6*a0_a0*(af - j_max*tf)*(af - j_max*tf) + 24*af*jj*(-pd + tf*v0)
        - 4*a0*(af_p3 - 3*af_af*j_max*tf + 6*jj*(-pd + tf*vf)) - 12*jj*(-vd_vd
        + j_max*tf*(-2*pd + tf*(v0 + vf))))) * abs(j_max) / j_max
    )
    h1 = (
        math.sqrt(3*(3*a0_a0 + 3*af_af - 6*a0*af - 6*ad*j_max*tf + 3*jj*tf_tf
        - 2*h0)) * abs(j_max) / j_max
    )
    t0 = (-3*(a0_a0 + af_af) + 6*a0*af + 6*j_max*(vd - a0*tf) + h0)/(6*j_max*(-ad + j_max*tf))
    t1 = 0.0
    t2 = (3*j_max*tf - 3*ad - h1)/(6*j_max)
    t3 = h1/(3*j_max)
    t4 = 0.0
    t5 = 0.0
    t6 = tf - (t0 + t2 + t3)
    if _accept(prof, _UDDU, _NONE, j_max, v_max, v_min, a_max, a_min,
               t0, t1, t2, t3, t4, t5, t6):
        return True

    # Solution 2
    h0 = 6*(ad_ad + 2*af*j_max*tf - 2*j_max*vd)
    h1a = 2*(a0_p3 - af_p3 + 3*a0*af*ad + 6*jj*(pd - tf*vf) + 3*jj*af*tf_tf)
    h1 = (
        math.sqrt(h1a*h1a - h0*(a0_p4 - 4*a0_p3*af + 6*a0_a0*af_af + af_p4 + 24*af*jj*(-pd + tf*v0)
        + 12*jj*vd_vd - 4*a0*(af_p3 - 3*af*jj*tf_tf + 6*jj*(-pd + tf*vf)))) * abs(j_max) / j_max
    )
    h2 = (
        4*a0_p3 - 4*af_p3 + 12*a0*af*ad - 12*jj*(pd - tf*vf) - 6*jj*af*tf_tf
        + 12*ad*j_max*(vd - af*tf)
    )
    h3 = j_max*h0
    t0 = 0.0
    t1 = 0.0
    t2 = (h1a + h1)/h3
    t3 = -(h2 + h1)/h3
    t4 = (h2 - h1)/h3
    t5 = tf - (t2 + t3 + t4)
    t6 = 0.0
    if _accept(prof, _UDDU, _NONE, j_max, v_max, v_min, a_max, a_min,
               t0, t1, t2, t3, t4, t5, t6):
        return True

    # Solution 1
    h0 = (
        math.sqrt((a0_p4 + af_p4 - 4*af_p3*j_max*tf + 6*af_af*jj*tf_tf - 4*a0_p3*(af - j_max*tf)
        + 6*a0_a0*(af - j_max*tf)*(af - j_max*tf) + 24*af*jj*(-pd + tf*v0)
        - 4*a0*(af_p3 - 3*af_af*j_max*tf + 6*jj*(-pd + tf*vf)) - 12*jj*(-vd_vd
        + j_max*tf*(-2*pd + tf*(v0 + vf)))) / 3) * abs(j_max) / j_max
    )
    h1 = math.sqrt(ad_ad - 2*ad*j_max*tf + jj*tf_tf + 2*h0) * abs(j_max) / j_max
    t0 = -(ad_ad + 2*j_max*(a0*tf - vd) + h0)/(2*j_max*(-ad + j_max*tf))
    t1 = 0.0
    t2 = 0.0
    t3 = 0.0
    t4 = (-ad + j_max*tf - h1)/(2*j_max)
    t5 = h1/j_max
    t6 = tf - (t0 + t4 + t5)
    if _accept(prof, _UDDU, _NONE, j_max, v_max, v_min, a_max, a_min,
               t0, t1, t2, t3, t4, t5, t6):
        return True

    return False


# fmt: on


@njit(cache=True, error_model="numpy")
def _sort_pairs(bounds, count):
    """Sort the first ``count`` rows of ``bounds`` lexicographically (insertion sort)."""
    for i in range(1, count):
        lo = bounds[i, 0]
        hi = bounds[i, 1]
        j = i - 1
        while j >= 0 and (bounds[j, 0] > lo or (bounds[j, 0] == lo and bounds[j, 1] > hi)):
            bounds[j + 1, 0] = bounds[j, 0]
            bounds[j + 1, 1] = bounds[j, 1]
            j -= 1
        bounds[j + 1, 0] = lo
        bounds[j + 1, 1] = hi


@njit(cache=True, error_model="numpy")
def timed(prof, tf, v_max, v_min, a_max, a_min, j_max):
    """A jerk-limited position profile that takes exactly ``tf``.

    Parameters
    ----------
    prof : ndarray of float64, shape (SIZE,)
        Profile record holding the boundary: ``p[0], v[0], a[0]`` (the state
        after any brake pre-profile) and ``pf, vf, af``. On success it holds the
        seven phases (durations, jerks, edge states, classification); the brake
        fields are left as they are. On failure its phase fields are scratch.
    tf : float
        Duration of the seven phases (s), at least the joint's minimum and not
        inside one of its blocked intervals.
    v_max, v_min, a_max, a_min : float
        Velocity and acceleration limits (``v_min < 0 < v_max`` etc.).
    j_max : float
        Jerk limit (> 0, finite).

    Returns
    -------
    bool
        Whether a profile was found.

    Notes
    -----
    The shapes are tried as the reference does: first those with a velocity
    plateau, then those without, each for the direction guessed from whether the
    target lies ahead of coasting at ``v0`` for ``tf`` (UP) before the other.
    """
    k = _givens(prof, tf)
    tf_v0 = tf * prof[V]
    pd = prof[PF] - prof[P]
    # The guess: the move has to go faster than coasting at v0 means UP first.
    up_first = pd > tf_v0
    vu = v_max if up_first else v_min
    vl = v_min if up_first else v_max
    au = a_max if up_first else a_min
    al = a_min if up_first else a_max
    ju = j_max if up_first else -j_max
    # Scratch for polynomial roots and root brackets, shared by all shapes.
    roots = np.empty(4)
    bounds = np.empty((5, 2))

    return (
        _time_acc0_acc1_vel(prof, k, vu, vl, au, al, ju)
        or _time_vel(prof, k, roots, bounds, vu, vl, au, al, ju)
        or _time_acc0_vel(prof, k, roots, vu, vl, au, al, ju)
        or _time_acc1_vel(prof, k, roots, vu, vl, au, al, ju)
        or _time_acc0_acc1_vel(prof, k, vl, vu, al, au, -ju)
        or _time_vel(prof, k, roots, bounds, vl, vu, al, au, -ju)
        or _time_acc0_vel(prof, k, roots, vl, vu, al, au, -ju)
        or _time_acc1_vel(prof, k, roots, vl, vu, al, au, -ju)
        or _time_acc0_acc1(prof, k, vu, vl, au, al, ju)
        or _time_acc0(prof, k, vu, vl, au, al, ju)
        or _time_acc1(prof, k, vu, vl, au, al, ju)
        or _time_none(prof, k, roots, vu, vl, au, al, ju)
        or _time_acc0_acc1(prof, k, vl, vu, al, au, -ju)
        or _time_acc0(prof, k, vl, vu, al, au, -ju)
        or _time_acc1(prof, k, vl, vu, al, au, -ju)
        or _time_none(prof, k, roots, vl, vu, al, au, -ju)
    )
