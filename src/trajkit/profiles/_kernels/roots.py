"""Closed-form and bracketed real polynomial roots, compiled.

A port of the mathematics of ruckig's ``roots.hpp``: Cardano for cubics, Ferrari
(via the resolvent cubic) for monic quartics, and a safeguarded Newton iteration
for one root in a bracket. Profile laws only ever need non-negative roots
(durations), so the solvers report the real roots ``>= 0``, sorted ascending,
written into a caller-supplied buffer; the return value is their count.

Polynomials are given by their coefficients, highest power first, as a 1-D
float64 array or a homogeneous tuple of floats (numba types the two apart, and
the code indexes generically so that both compile).

All functions are compiled with ``error_model="numpy"``: a division by zero gives
``inf``/``nan`` as in the C++ reference instead of raising, so degenerate inputs
degrade the same way (and no exception check sits in the inner loops).
"""

import math

import numpy as np
from numba import njit

DBL_EPSILON = 2.220446049250313e-16
COS120 = -0.5
SIN120 = 0.866025403784438646764
# Newton/bisection stops once a step is below this (absolute, like the reference).
TOLERANCE = 1e-14
MAX_ITS = 128


@njit(cache=True, error_model="numpy")
def _cbrt(x):
    """Real cube root (``math`` has none in numba; ``np.cbrt`` maps to libm's)."""
    return np.cbrt(x)


@njit(cache=True, error_model="numpy")
def _insert_positive(out, n, value):
    """Append ``value`` to ``out[:n]`` if it is ``>= 0`` and finite; return the new count.

    The reference keeps every ``value >= 0``; also dropping ``+inf`` (which only
    non-finite coefficients produce) means no caller ever sees a root that is no
    duration. A NaN fails the comparison and is dropped too. Adding 0.0 turns a
    ``-0.0`` into ``+0.0``.
    """
    if 0.0 <= value < math.inf:
        out[n] = value + 0.0
        return n + 1
    return n


@njit(cache=True, error_model="numpy")
def _sort(out, n):
    """Insertion sort of ``out[:n]`` (n <= 4: cheaper than anything general)."""
    for i in range(1, n):
        v = out[i]
        k = i - 1
        while k >= 0 and out[k] > v:
            out[k + 1] = out[k]
            k -= 1
        out[k + 1] = v


@njit(cache=True, error_model="numpy")
def solve_cubic(a, b, c, d, out):
    """Non-negative real roots of ``a x^3 + b x^2 + c x + d``.

    Parameters
    ----------
    a, b, c, d : float
        Coefficients, highest power first. A leading coefficient below machine
        epsilon in magnitude drops the degree (quadratic, then linear); a
        constant term below it reports the root 0 and divides it out.
    out : ndarray of float64, length >= 3
        Receives the roots in ``out[:count]``, sorted ascending.

    Returns
    -------
    int
        The number of roots written. The zero polynomial reports the single root
        0 (the constant term vanishes, and what remains is no equation at all).
        A double root may be reported once or twice. Non-finite coefficients
        give no root, or finite ones only.

    Notes
    -----
    The degeneracy thresholds are absolute (``DBL_EPSILON``), as in the
    reference: the discriminant scales like the sixth power of the roots, so
    three real roots much smaller than ~0.1 may be mistaken for a double root.
    Profile laws call it with durations of ordinary magnitude.
    """
    n = 0
    if abs(d) < DBL_EPSILON:
        # x = 0 solves it; the rest is the quadratic a x^2 + b x + c.
        n = _insert_positive(out, n, 0.0)
        d = c
        c = b
        b = a
        a = 0.0

    if abs(a) < DBL_EPSILON:
        if abs(b) < DBL_EPSILON:
            if abs(c) > DBL_EPSILON:
                n = _insert_positive(out, n, -d / c)
        else:
            discriminant = c * c - 4.0 * b * d
            if discriminant >= 0.0:
                inv2b = 1.0 / (2.0 * b)
                y = math.sqrt(discriminant)
                n = _insert_positive(out, n, (-c + y) * inv2b)
                n = _insert_positive(out, n, (-c - y) * inv2b)
    else:
        # Depressed cubic t^3 + p t + q with x = t - b / (3a).
        inva = 1.0 / a
        invaa = inva * inva
        bb = b * b
        bover3a = b * inva / 3.0
        p = (a * c - bb / 3.0) * invaa
        halfq = (2.0 * bb * b - 9.0 * a * b * c + 27.0 * a * a * d) / 54.0 * invaa * inva
        yy = p * p * p / 27.0 + halfq * halfq

        if yy > DBL_EPSILON:
            # One real root (Cardano). Taking the larger-magnitude branch of the
            # square root avoids cancellation in the cube root.
            y = math.sqrt(yy)
            uuu = -halfq + y
            vvv = -halfq - y
            www = uuu if abs(uuu) > abs(vvv) else vvv
            w = _cbrt(www)
            n = _insert_positive(out, n, w - p / (3.0 * w) - bover3a)
        elif yy < -DBL_EPSILON:
            # Three real roots: the cube root of a complex number, in polar form.
            x = -halfq
            y = math.sqrt(-yy)
            if abs(x) > DBL_EPSILON:
                theta = math.atan(y / x) if x > 0.0 else math.atan(y / x) + math.pi
                r = math.sqrt(x * x - yy)
            else:
                theta = math.pi / 2.0
                r = y
            theta /= 3.0
            r = 2.0 * _cbrt(r)
            ux = math.cos(theta) * r
            uyi = math.sin(theta) * r
            n = _insert_positive(out, n, ux - bover3a)
            n = _insert_positive(out, n, ux * COS120 - uyi * SIN120 - bover3a)
            n = _insert_positive(out, n, ux * COS120 + uyi * SIN120 - bover3a)
        else:
            # Discriminant zero: a simple and a double root.
            www = -halfq
            w = 2.0 * _cbrt(www)
            n = _insert_positive(out, n, w - bover3a)
            n = _insert_positive(out, n, w * COS120 - bover3a)

    _sort(out, n)
    return n


@njit(cache=True, error_model="numpy")
def solve_resolvent(x, a, b, c):
    """Real roots of the resolvent cubic ``y^3 + a y^2 + b y + c`` of a quartic.

    Parameters
    ----------
    x : ndarray of float64, length 3
        Receives the roots (not filtered by sign, not sorted).
    a, b, c : float
        Coefficients of the monic cubic.

    Returns
    -------
    int
        3 if three real roots are in ``x``; 2 if a double root (``x[1] == x[2]``)
        and a simple one ``x[0]``; 1 if only ``x[0]`` is real (``x[1]`` and
        ``x[2]`` then hold the real and imaginary part of the complex pair).
    """
    a /= 3.0
    a2 = a * a
    q = a2 - b / 3.0
    r = (a * (2.0 * a2 - b) + c) / 2.0
    r2 = r * r
    q3 = q * q * q

    if r2 < q3:
        # Three real roots (trigonometric form); the clamp guards acos against
        # rounding just outside [-1, 1].
        qsqrt = math.sqrt(q)
        t = min(max(r / (q * qsqrt), -1.0), 1.0)
        q = -2.0 * qsqrt
        theta = math.acos(t) / 3.0
        ux = math.cos(theta) * q
        uyi = math.sin(theta) * q
        x[0] = ux - a
        x[1] = ux * COS120 - uyi * SIN120 - a
        x[2] = ux * COS120 + uyi * SIN120 - a
        return 3

    big_a = -_cbrt(abs(r) + math.sqrt(r2 - q3))
    if r < 0.0:
        big_a = -big_a
    big_b = 0.0 if big_a == 0.0 else q / big_a
    x[0] = (big_a + big_b) - a
    x[1] = -(big_a + big_b) / 2.0 - a
    x[2] = math.sqrt(3.0) * (big_a - big_b) / 2.0
    if abs(x[2]) < DBL_EPSILON:
        x[2] = x[1]
        return 2
    return 1


@njit(cache=True, error_model="numpy")
def solve_quart_monic(a, b, c, d, out):
    """Non-negative real roots of ``x^4 + a x^3 + b x^2 + c x + d`` (Ferrari).

    Parameters
    ----------
    a, b, c, d : float
        Coefficients below the leading 1, highest power first.
    out : ndarray of float64, length >= 4
        Receives the roots in ``out[:count]``, sorted ascending.

    Returns
    -------
    int
        The number of roots written. A double root may be reported once or
        twice, depending on which branch finds it (``x^4`` reports 0 twice).
    """
    n = 0
    if abs(d) < DBL_EPSILON:
        if abs(c) < DBL_EPSILON:
            # x^2 (x^2 + a x + b): zero and the quadratic's roots.
            n = _insert_positive(out, n, 0.0)
            disc = a * a - 4.0 * b
            if abs(disc) < DBL_EPSILON:
                n = _insert_positive(out, n, -a / 2.0)
            elif disc > 0.0:
                sqrt_d = math.sqrt(disc)
                n = _insert_positive(out, n, (-a - sqrt_d) / 2.0)
                n = _insert_positive(out, n, (-a + sqrt_d) / 2.0)
            _sort(out, n)
            return n

        if abs(a) < DBL_EPSILON and abs(b) < DBL_EPSILON:
            # x (x^3 + c): zero and the real cube root of -c.
            n = _insert_positive(out, n, 0.0)
            n = _insert_positive(out, n, -_cbrt(c))
            _sort(out, n)
            return n

    # Factor into (x^2 + p1 x + q1)(x^2 + p2 x + q2) through a resolvent root y.
    a3 = -b
    b3 = a * c - 4.0 * d
    c3 = -a * a * d - c * c + 4.0 * b * d
    x3 = np.empty(3)
    number_zeroes = solve_resolvent(x3, a3, b3, c3)

    y = x3[0]
    # The root of largest magnitude keeps the factorization best conditioned.
    if number_zeroes != 1:
        if abs(x3[1]) > abs(y):
            y = x3[1]
        if abs(x3[2]) > abs(y):
            y = x3[2]

    disc = y * y - 4.0 * d
    if abs(disc) < DBL_EPSILON:
        q1 = y / 2.0
        q2 = q1
        disc = a * a - 4.0 * (b - y)
        if abs(disc) < DBL_EPSILON:
            p1 = a / 2.0
            p2 = p1
        else:
            sqrt_d = math.sqrt(disc)
            p1 = (a + sqrt_d) / 2.0
            p2 = (a - sqrt_d) / 2.0
    else:
        sqrt_d = math.sqrt(disc)
        q1 = (y + sqrt_d) / 2.0
        q2 = (y - sqrt_d) / 2.0
        p1 = (a * q1 - c) / (q1 - q2)
        p2 = (c - a * q2) / (q1 - q2)

    # A looser threshold here: the factor coefficients carry the resolvent's error.
    eps = 16.0 * DBL_EPSILON

    disc = p1 * p1 - 4.0 * q1
    if abs(disc) < eps:
        n = _insert_positive(out, n, -p1 / 2.0)
    elif disc > 0.0:
        sqrt_d = math.sqrt(disc)
        n = _insert_positive(out, n, (-p1 - sqrt_d) / 2.0)
        n = _insert_positive(out, n, (-p1 + sqrt_d) / 2.0)

    disc = p2 * p2 - 4.0 * q2
    if abs(disc) < eps:
        n = _insert_positive(out, n, -p2 / 2.0)
    elif disc > 0.0:
        sqrt_d = math.sqrt(disc)
        n = _insert_positive(out, n, (-p2 - sqrt_d) / 2.0)
        n = _insert_positive(out, n, (-p2 + sqrt_d) / 2.0)

    _sort(out, n)
    return n


@njit(cache=True, error_model="numpy")
def poly_eval(p, x):
    """Value at ``x`` of the polynomial with coefficients ``p`` (highest power first).

    Parameters
    ----------
    p : tuple of float or ndarray of float64
        Coefficients; an empty one is the zero polynomial.
    x : float
        Where to evaluate.

    Returns
    -------
    float
        The value. Summed from the constant term upward with running powers of
        ``x`` (not Horner), exactly as the reference does, so results agree to
        the last bit; ``|x| < eps`` returns the constant term and ``x == 1`` the
        plain sum of the coefficients.
    """
    n = len(p)
    ret = 0.0
    if n == 0:
        return ret
    if abs(x) < DBL_EPSILON:
        ret = p[n - 1]
    elif x == 1.0:
        for i in range(n - 1, -1, -1):
            ret += p[i]
    else:
        xn = 1.0
        for i in range(n - 1, -1, -1):
            ret += p[i] * xn
            xn *= x
    return ret


@njit(cache=True, error_model="numpy")
def poly_derivative_eval(p, x):
    """Derivative at ``x`` of the polynomial ``p`` (highest power first).

    Equal, bit for bit, to ``poly_eval(poly_derivative(p), x)`` but builds no
    array, so it works on tuples and allocates nothing in Newton loops.

    Parameters
    ----------
    p : tuple of float or ndarray of float64
        Coefficients of the polynomial (not of its derivative).
    x : float
        Where to evaluate.

    Returns
    -------
    float
        The derivative; 0.0 for a constant or empty polynomial.
    """
    n = len(p) - 1  # number of derivative coefficients
    ret = 0.0
    if n <= 0:
        return ret
    # Derivative coefficient k is (n - k) * p[k], k = 0 .. n - 1.
    if abs(x) < DBL_EPSILON:
        ret = 1.0 * p[n - 1]
    elif x == 1.0:
        for i in range(n - 1, -1, -1):
            ret += (n - i) * p[i]
    else:
        xn = 1.0
        for i in range(n - 1, -1, -1):
            ret += (n - i) * p[i] * xn
            xn *= x
    return ret


@njit(cache=True, error_model="numpy")
def poly_derivative(p):
    """Coefficients of the derivative of ``p`` (highest power first).

    Parameters
    ----------
    p : tuple of float or ndarray of float64
        Coefficients, length N >= 1.

    Returns
    -------
    ndarray of float64
        Length N - 1.
    """
    n = len(p) - 1
    deriv = np.empty(max(n, 0))
    for i in range(n):
        deriv[i] = (n - i) * p[i]
    return deriv


@njit(cache=True, error_model="numpy")
def poly_monic_derivative(p):
    """The derivative of a monic polynomial ``p``, scaled to be monic again.

    Dividing by the degree keeps the derivative's coefficients on the scale of
    the original's, which the bracketing of quartic roots relies on.

    Parameters
    ----------
    p : tuple of float or ndarray of float64
        Coefficients of a monic polynomial (``p[0] == 1`` is assumed, not read),
        length N >= 2.

    Returns
    -------
    ndarray of float64
        Length N - 1, with ``[0] == 1``.
    """
    n = len(p) - 1
    deriv = np.empty(n)
    deriv[0] = 1.0
    for i in range(1, n):
        deriv[i] = (n - i) * p[i] / n
    return deriv


@njit(cache=True, error_model="numpy")
def shrink_interval(p, l, h):  # noqa: E741 (the reference's names)
    """One root of ``p`` inside ``[l, h]``: Newton's method safeguarded by bisection.

    Parameters
    ----------
    p : tuple of float or ndarray of float64
        Coefficients, highest power first.
    l, h : float
        The bracket. The caller guarantees a sign change, ``p(l) p(h) < 0``, and
        ``l < h``; without one the result is merely some point of the bracket.

    Returns
    -------
    float
        The root, to within an absolute step of ``1e-14`` (or until the
        iterate stops moving, or 128 iterations).
    """
    lo, hi = l, h
    fl = poly_eval(p, lo)
    fh = poly_eval(p, hi)
    if fl == 0.0:
        return lo
    if fh == 0.0:
        return hi
    # Name the ends by sign, p(lo) < 0 < p(hi) (lo may then be the larger one).
    if fl > 0.0:
        lo, hi = hi, lo

    rts = (lo + hi) / 2.0
    dxold = abs(hi - lo)
    dx = dxold
    f = poly_eval(p, rts)
    df = poly_derivative_eval(p, rts)
    for _ in range(MAX_ITS):
        # Bisect where Newton would leave the bracket or is not halving the step.
        if ((rts - hi) * df - f) * ((rts - lo) * df - f) > 0.0 or abs(2.0 * f) > abs(dxold * df):
            dxold = dx
            dx = (hi - lo) / 2.0
            rts = lo + dx
            if lo == rts:
                break
        else:
            dxold = dx
            dx = f / df
            temp = rts
            rts -= dx
            if temp == rts:
                break

        if abs(dx) < TOLERANCE:
            break

        f = poly_eval(p, rts)
        df = poly_derivative_eval(p, rts)
        if f < 0.0:
            lo = rts
        else:
            hi = rts

    return rts
