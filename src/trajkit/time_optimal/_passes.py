"""The time-optimal solver's hot loops, compiled: scalar code over stages and rows.

* :func:`channel_rows` — each stage's Bernstein rows of the path's channels, and
  the caps at each grid point;
* :func:`stage_setup` — each stage's rows as bounds on ``u``, its maximum velocity
  curve (:func:`feasible_below`, :func:`maximum_velocity_curve`) and the passes'
  terms; :func:`rate_ratios` — the squared-rate hull behind the velocity caps;
* :func:`recurrence` — the backward and forward passes;
* :func:`local_slopes` and :func:`interval_terms` — the path's slope re-expanded on
  every interval;
* :func:`cubic_ratios`, :func:`timed_pieces` and :func:`compose` — the timed path's
  exact peaks against the bounds, and its polynomials (:func:`phases`,
  :func:`pieces_of`);
* :func:`merged_grid` and :func:`breakpoint_steps` — the grid, and where the path's
  position or tangent jumps.

Each replaces the NumPy code that was here before it, with the same results up to
rounding (the tests compare them with plain re-implementations and with toppra).
Compiled for one problem as much as for many: at 100 grid points a call's fixed
cost, a few dozen small NumPy operations, was as large as the solve. Importing this
module imports numba (slow): :mod:`.reachability` and :mod:`.timing` import it inside
their functions, so ``import trajkit`` stays fast.
"""

import numpy as np
from numba import njit


@njit(cache=True)
def recurrence(a, b, high, y0):  # pragma: no cover - compiled; tested through reachability
    """``y_{k+1} = clip(min_j (a_kj y_k + b_kj), 0, high_k)``; a NaN line never binds."""
    n, m = a.shape
    out = np.empty(n)
    y = y0
    for k in range(n):
        best = high[k]
        for j in range(m):
            offset = b[k, j]
            if offset == np.inf:
                continue
            value = a[k, j] * y + offset
            if value < best:
                best = value
        y = best if best > 0.0 else 0.0
        out[k] = y
    return out


@njit(cache=True)
def maximum_velocity_curve(valid, r, hi, lo, d1, d2, acc_lo, acc_hi, threshold):  # pragma: no cover
    """The largest x at each point with ``max_j L_j(x) <= min_k U_k(x)``; all (n, m)."""
    n = r.shape[0]
    out = np.empty(n)
    for i in range(n):
        out[i] = _one_curve(valid[i], r[i], hi[i], lo[i], d1[i], d2[i], acc_lo[i], acc_hi[i],
                            threshold[i])  # fmt: skip
    return out


@njit(cache=True)
def feasible_below(cap, valid, rate, high, low, rounding):  # pragma: no cover
    """Each stage's ``cap`` lowered to the largest x where its rows leave room for u.

    Newton steps from the right on the concave room ``min_k U_k(x) - max_j L_j(x)``
    (see :func:`trajkit.time_optimal.reachability._feasible_below`); returns the caps
    and the stages left in doubt.
    """
    n, m = rate.shape
    out = cap.copy()
    doubt = np.zeros(n, dtype=np.bool_)
    for i in range(n):
        x = out[i]
        if not np.isfinite(x):
            continue
        settled = False
        for _ in range(8):
            u_hi, k = np.inf, 0
            u_lo, jj = -np.inf, 0
            for j in range(m):
                grow = rate[i, j] if valid[i, j] else 0.0
                top = (high[i, j] if valid[i, j] else np.inf) + grow * x
                bottom = (low[i, j] if valid[i, j] else -np.inf) + grow * x
                if top < u_hi:
                    u_hi, k = top, j
                if bottom > u_lo:
                    u_lo, jj = bottom, j
            room = u_hi - u_lo
            short = room < -rounding * max(abs(u_hi), 1e-300)
            if not short:
                settled = True
                break
            grow_j = rate[i, jj] if valid[i, jj] else 0.0
            grow_k = rate[i, k] if valid[i, k] else 0.0
            fall = grow_j - grow_k  # how fast the room shrinks with x
            root = x + room / fall if fall > 0.0 else 0.0
            # room < 0 cannot grow toward x = 0; a step to a millionth of x has lost the
            # root's digits in the subtraction.
            sound = fall > 0.0 and root > 1e-6 * x
            x = root if root > 0.0 else 0.0
            if not sound:
                doubt[i] = True
                settled = True
                break
        if not settled:
            doubt[i] = True
        out[i] = x if x > 0.0 else 0.0
    return out, doubt


@njit(cache=True)
def _clip(value, high):  # pragma: no cover
    """``value`` within ``[0, high]``; NaN stays NaN (as numpy's clip)."""
    if value < 0.0:
        return 0.0
    if value > high:
        return high
    return value


@njit(cache=True)
def _extreme(values, smallest):  # pragma: no cover
    """The least (or greatest) of ``values``; NaN if one is (as numpy's min and max)."""
    best = values[0]
    for value in values:
        if np.isnan(value):
            return value
        if (value < best) if smallest else (value > best):
            best = value
    return best


@njit(cache=True)
def compose(local, sigma):  # pragma: no cover
    """``q(σ(τ))`` on every piece, as :func:`trajkit.time_optimal.timing.compose`.

    ``local`` (k + 1, M, ndof) is each piece's ``q`` in descending powers of σ,
    ``sigma`` (M, d + 1) its σ in ascending powers of τ; the result, (k d + 1, M,
    ndof), is in descending powers of τ.
    """
    k1, count, ndof = local.shape
    degree = k1 - 1
    order = sigma.shape[1] - 1
    size = degree * order + 1
    out = np.zeros((size, count, ndof))
    power = np.zeros(size)
    grown = np.zeros(size)
    for p in range(count):
        power[:] = 0.0
        power[0] = 1.0
        length = 1
        for m in range(degree + 1):  # q = sum_m a_m σ^m
            for c in range(length):
                for j in range(ndof):
                    out[size - 1 - c, p, j] += power[c] * local[degree - m, p, j]
            if m == degree:
                break
            grown[: length + order] = 0.0
            for shift in range(order + 1):
                for c in range(length):
                    grown[c + shift] += power[c] * sigma[p, shift]
            length += order
            power[:length] = grown[:length]
    return out


@njit(cache=True)
def _rate_cap(slope, lower, upper, threshold):  # pragma: no cover
    """The largest x with every ``slope_j ṡ`` within its side's bound, at one point."""
    cap = np.inf
    for j in range(slope.size):
        if abs(slope[j]) > threshold:
            side = upper[j] if slope[j] > 0.0 else -lower[j]
            value = (side / abs(slope[j])) ** 2
            if value < cap:
                cap = value
    return cap


@njit(cache=True)
def _on_u(slope, curve, lower, upper, threshold):  # pragma: no cover
    """``lower <= slope u + curve x <= upper`` as ``lo + r x <= u <= hi + r x``.

    Returns ``(valid, r, hi, lo)``; a row whose u term does not pass ``threshold`` is
    not valid (``r = 0``, no bound on u).
    """
    if not abs(slope) > threshold:
        return False, 0.0, np.inf, -np.inf
    top, bottom = (upper, lower) if slope > 0.0 else (lower, upper)
    return True, -curve / slope, top / slope, bottom / slope


@njit(cache=True)
def _point_curve(first, second, acc_lo, acc_hi, thresholds, valid, rate, high,
                 low):  # pragma: no cover  # fmt: skip
    """The maximum velocity curve of the acceleration rows at one point alone.

    ``valid``, ``rate``, ``high`` and ``low`` (m,) are work space, overwritten.
    """
    for j in range(first.size):
        valid[j], rate[j], high[j], low[j] = _on_u(first[j], second[j], acc_lo[j], acc_hi[j],
                                                   thresholds[j])  # fmt: skip
    return _one_curve(valid, rate, high, low, first, second, acc_lo, acc_hi, thresholds)


@njit(cache=True)
def _one_curve(valid, r, hi, lo, d1, d2, acc_lo, acc_hi, threshold):  # pragma: no cover
    """The largest x with ``max_j L_j(x) <= min_k U_k(x)`` for one set of rows."""
    m = r.size
    cap = np.inf
    for j in range(m):
        if not abs(d1[j]) > threshold[j]:
            bend = np.inf
            if d2[j] > 0.0:
                bend = acc_hi[j] / d2[j]
            elif d2[j] < 0.0:
                bend = acc_lo[j] / d2[j]
            if bend < cap:
                cap = bend
    for j in range(m):
        low = lo[j] if valid[j] else -np.inf
        for k in range(m):
            slope = r[j] - r[k]
            room = (hi[k] if valid[k] else np.inf) - low
            if slope > 0.0:
                crossing = room / slope
            elif room < 0.0:
                crossing = 0.0
            else:
                crossing = np.inf
            if crossing < cap:
                cap = crossing
    return cap if cap > 0.0 else 0.0


@njit(cache=True)
def channel_rows(ascending, rate_of, hull, vel_lo, vel_hi, acc_lo, acc_hi,
                 threshold):  # pragma: no cover  # fmt: skip
    """The channels' rows of every stage and the caps at every grid point.

    ``ascending`` (K + 1, N, m) is each channel's ``c'`` on each interval in ascending
    powers of ``τ = σ / Δ``, ``rate_of`` its ``c''``; ``hull`` the Bernstein matrix.
    Returns the rows' u and x terms (N, (K + 1) m), row ``c m + j`` for coefficient
    ``c`` of channel ``j``; the velocity cap at each point (from both sides, as the
    tangent may jump) and the maximum velocity curve of the rows at each point alone.
    """
    size, n, m = ascending.shape
    on_u, on_x = np.empty((n, size * m)), np.empty((n, size * m))
    at_point, at_points = np.empty(n + 1), np.empty(n + 1)
    first, second, left = np.empty(m), np.empty(m), np.empty(m)
    thresholds = np.full(m, threshold)
    valid, rate, high, low = np.empty(m, dtype=np.bool_), np.empty(m), np.empty(m), np.empty(m)
    for i in range(n + 1):
        for j in range(m):
            if i < n:  # from the right
                first[j], second[j] = ascending[0, i, j], rate_of[0, i, j]
            else:  # the last point, from the left
                first[j], second[j] = 0.0, 0.0
                for c in range(size):
                    first[j] += ascending[c, n - 1, j]
                    second[j] += rate_of[c, n - 1, j]
            if i == 0:
                left[j] = ascending[0, 0, j]
            else:
                left[j] = 0.0
                for c in range(size):
                    left[j] += ascending[c, i - 1, j]
        at_point[i] = min(_rate_cap(first, vel_lo, vel_hi, threshold),
                          _rate_cap(left, vel_lo, vel_hi, threshold))  # fmt: skip
        at_points[i] = _point_curve(first, second, acc_lo, acc_hi, thresholds, valid, rate, high,
                                    low)  # fmt: skip
    for i in range(n):
        for c in range(size):
            for j in range(m):
                u_term, x_term = 0.0, 0.0
                for k in range(size):
                    u_term += hull[c, k] * ((1.0 + 2.0 * k) * ascending[k, i, j])
                    x_term += hull[c, k] * rate_of[k, i, j]
                on_u[i, c * m + j], on_x[i, c * m + j] = u_term, x_term
    return on_u, on_x, at_point, at_points


@njit(cache=True)
def _smaller(a, b):  # pragma: no cover
    """``np.minimum`` of two numbers: NaN if either is."""
    if np.isnan(a) or np.isnan(b):
        return np.nan
    return a if a < b else b


@njit(cache=True)
def stage_setup(on_u, on_x, lower, upper, threshold, start, delta, rounding):  # pragma: no cover
    """Every stage's rows as bounds on u, its maximum velocity curve, and both passes' terms.

    Row ``lower <= on_u u + on_x x <= upper`` becomes ``lo + r x <= u <= hi + r x``
    where its u term passes ``threshold`` (valid); otherwise it bounds x alone. The
    stage's cap is the largest x at most ``start`` where some u keeps every row
    (Newton steps from above, all pairs of rows where they leave doubt), and where a
    row falling with x (``1 + 2Δr < 0``) still lets ``x_{i+1} >= 0``. The forward
    pass's lines are ``grow x + push``; the backward pass's ``shrink (y - pull)`` on
    the usable rows (``grow > 0``, a finite lower bound).
    """
    n, rows = on_u.shape
    valid = np.empty((n, rows), dtype=np.bool_)
    rate, high, low = np.empty((n, rows)), np.empty((n, rows)), np.empty((n, rows))
    grow, push = np.empty((n, rows)), np.empty((n, rows))
    shrink, pull = np.zeros((n, rows)), np.zeros((n, rows))
    usable = np.zeros((n, rows), dtype=np.bool_)
    cap = start.copy()
    for i in range(n):
        flat = np.inf
        for j in range(rows):
            slope, curve = on_u[i, j], on_x[i, j]
            valid[i, j], rate[i, j], high[i, j], low[i, j] = _on_u(
                slope, curve, lower[i, j], upper[i, j], threshold[i, j])  # fmt: skip
            if not valid[i, j]:
                # A flat row bounds x alone: x <= bound / on_x on the side on_x points to.
                bound = np.inf
                if curve > 0.0:
                    bound = upper[i, j] / curve
                elif curve < 0.0:
                    bound = lower[i, j] / curve
                if not np.isnan(bound):
                    bound = bound if bound > 0.0 else 0.0
                    if bound < flat:
                        flat = bound
        if flat < cap[i]:  # a NaN cap stays NaN, as numpy's minimum keeps it
            cap[i] = flat
        if not np.isfinite(cap[i]):
            cap[i] = _one_curve(valid[i], rate[i], high[i], low[i], on_u[i], on_x[i], lower[i],
                                upper[i], threshold[i])  # fmt: skip
    newton, doubt = feasible_below(cap, valid, rate, high, low, rounding)
    for i in range(n):
        if doubt[i]:  # all pairs of rows, exactly
            exact = _one_curve(valid[i], rate[i], high[i], low[i], on_u[i], on_x[i], lower[i],
                               upper[i], threshold[i])  # fmt: skip
            newton[i] = _smaller(cap[i], exact)
        twice = 2.0 * delta[i]
        for j in range(rows):
            grow[i, j] = 1.0 + twice * rate[i, j]
            push[i, j] = twice * high[i, j] if valid[i, j] and np.isfinite(high[i, j]) else np.inf
            if valid[i, j] and grow[i, j] < 0.0 and np.isfinite(push[i, j]):
                # Falling with x: x_{i+1} >= 0 only up to where the line crosses 0.
                crossing = push[i, j] / -grow[i, j]
                crossing = crossing if crossing > 0.0 else 0.0
                if crossing < newton[i]:
                    newton[i] = crossing
            if valid[i, j] and grow[i, j] > 0.0 and np.isfinite(low[i, j]):
                usable[i, j] = True
                shrink[i, j] = 1.0 / grow[i, j]
                pull[i, j] = twice * low[i, j]
    return valid, rate, high, low, newton, grow, push, shrink, pull, usable


@njit(cache=True)
def _larger(a, b):  # pragma: no cover
    """``np.maximum`` of two numbers: NaN if either is."""
    if np.isnan(a) or np.isnan(b):
        return np.nan
    return a if a > b else b


@njit(cache=True)
def rate_ratios(ascending, w, vel_lo, vel_hi, square_hull, hull):  # pragma: no cover
    """Per interval, the largest ratio of a channel's squared rate to its bound squared.

    With ``x`` linear from ``w_i`` to ``w_{i+1}`` across the interval, the squared rate
    ``c'(τ)² x(τ)`` is bounded through the Bernstein coefficients of ``c'²`` (from
    ``square_hull``) raised one degree by the linear ``x``; the bound is that of the
    side the channel moves to (from ``hull``, the Bernstein matrix of ``c'``), the
    tighter of the two if it turns. At least 1; NaN propagates as in numpy.
    """
    size, n, m = ascending.shape
    top = 2 * size - 1
    out = np.empty(n)
    square = np.empty(top)
    g = np.empty(top)
    for i in range(n):
        best = 1.0
        for j in range(m):
            square[:] = 0.0
            for a in range(size):
                for b in range(size):
                    square[a + b] += ascending[a, i, j] * ascending[b, i, j]
            finite = True
            for k in range(top):
                finite = finite and np.isfinite(square[k])
            if not finite:  # NaN, as numpy's product with the hull's zeros gives
                best = np.nan
                continue
            for c in range(top):  # the Bernstein matrices are lower triangular
                total = 0.0
                for k in range(c + 1):
                    total += square_hull[c, k] * square[k]
                g[c] = total
            rate2 = _larger(g[0] * w[i], g[top - 1] * w[i + 1])
            for c in range(1, top):
                share = c / top
                rate2 = _larger(rate2, (1.0 - share) * g[c] * w[i] + share * g[c - 1] * w[i + 1])
            rising, falling = True, True
            for c in range(size):
                total = 0.0
                for k in range(c + 1):
                    total += hull[c, k] * ascending[k, i, j]
                if not total >= 0.0:
                    rising = False
                if not total <= 0.0:
                    falling = False
            if rising:
                side = vel_hi[j]
            elif falling:
                side = -vel_lo[j]
            else:
                side = min(vel_hi[j], -vel_lo[j])
            best = _larger(best, rate2 / side**2)
        out[i] = best
    return out


@njit(cache=True)
def local_slopes(coefficients, breakpoints, s, binomial):  # pragma: no cover
    """``d/dσ q(w0 + σ)`` on every interval of ``s``, descending in σ.

    Each interval's path piece (:func:`pieces_of`) is re-expanded at the interval's
    start ``w0`` and differentiated. ``coefficients`` (k + 1, P, m) descending,
    ``binomial[n, j]`` = C(n, j).
    """
    piece, offset = pieces_of(breakpoints, s)
    size, _, m = coefficients.shape
    k = size - 1
    n_intervals = piece.size
    out = np.zeros((max(k, 1), n_intervals, m))
    if k == 0:
        return out
    shifted = np.empty(size)
    powers = np.empty(size)
    for i in range(n_intervals):
        p = piece[i]
        for e in range(size):  # as numpy's power does it, for the same rounding
            powers[e] = offset[i] ** float(e)
        for j in range(m):
            shifted[:] = 0.0
            # (x + w0)**n = sum_l C(n, l) x**l w0**(n - l)
            for r in range(size):
                n = k - r
                for exponent in range(n + 1):
                    shifted[k - exponent] += (coefficients[r, p, j] * binomial[n, exponent]
                                              * powers[n - exponent])  # fmt: skip
            for r in range(k):
                out[r, i, j] = shifted[r] * (k - r)
    return out


@njit(cache=True)
def cubic_ratios(coefficients, breakpoints, s, x, v_lo, v_hi, a_lo, a_hi):  # pragma: no cover
    """Per interval of ``s``, the largest ratio of joint velocity and of acceleration to its bound.

    The path is cubic at most (``coefficients``: (k + 1, P, m), descending, k <= 3). In
    ``σ = s - s_i``, ``q̈ = A σ² + B σ + C`` has its extremes at the ends and the
    vertex, and ``q̇ = q' ṡ`` peaks at the ends or where ``q̈`` vanishes. A value's
    ratio is to the bound of its side; NaN propagates as in numpy.
    """
    piece, w0 = pieces_of(breakpoints, s)
    n, m = piece.size, coefficients.shape[2]
    pad = 4 - coefficients.shape[0]  # missing leading powers
    c4 = np.zeros((4, coefficients.shape[1], m))
    c4[pad:] = coefficients
    ratio_v, ratio_a = np.empty(n), np.empty(n)
    accel, speed, where = np.empty(3), np.empty(4), np.empty(4)
    for i in range(n):
        xi = x[i]
        width = s[i + 1] - s[i]
        ui = (x[i + 1] - x[i]) / (2.0 * width)
        w = w0[i]
        p = piece[i]
        worst_v, worst_a = -np.inf, -np.inf
        for j in range(m):
            a3, a2, a1 = c4[0, p, j], c4[1, p, j], c4[2, p, j]
            d0 = 3.0 * a3 * w**2 + 2.0 * a2 * w + a1
            d1 = 6.0 * a3 * w + 2.0 * a2
            d2 = 3.0 * a3
            big_a = 5.0 * d2 * ui
            big_b = 3.0 * d1 * ui + 2.0 * d2 * xi
            big_c = d1 * xi + d0 * ui
            vertex = -big_b / (2.0 * big_a) if big_a != 0.0 else 0.0
            root = np.sqrt(max(big_b**2 - 4.0 * big_a * big_c, 0.0))
            if abs(big_a) <= 1e-300:
                root1 = -big_c / big_b if big_b != 0.0 else 0.0
                root2 = 0.0
            else:
                root1 = (-big_b + root) / (2.0 * big_a)
                root2 = (-big_b - root) / (2.0 * big_a)
            middle = _clip(vertex, width)
            accel[0] = big_c
            accel[1] = big_a * width**2 + big_b * width + big_c
            accel[2] = big_a * middle**2 + big_b * middle + big_c
            where[0], where[1] = _clip(root1, width), _clip(root2, width)
            where[2], where[3] = 0.0, width
            for k in range(4):
                t = where[k]
                speed[k] = (d0 + d1 * t + d2 * t**2) * np.sqrt(max(xi + 2.0 * ui * t, 0.0))
            v = _larger(_extreme(speed, False) / v_hi[j], _extreme(speed, True) / v_lo[j])
            a = _larger(_extreme(accel, False) / a_hi[j], _extreme(accel, True) / a_lo[j])
            worst_v = v if j == 0 else _larger(worst_v, v)
            worst_a = a if j == 0 else _larger(worst_a, a)
        ratio_v[i], ratio_a[i] = worst_v, worst_a
    return ratio_v, ratio_a


@njit(cache=True)
def passes(shrink, pull, usable, grow, push, valid, rate, low, scaled, acc_scale, velocity_cap,
           velocity_factor, acceleration_cap, rests, x_start, x_end,
           delta):  # pragma: no cover  # fmt: skip
    """Both passes of one solve, and the stages left with no u between their rows.

    The maximum velocity curve is the lower of ``velocity_cap * velocity_factor``
    and ``acceleration_cap`` scaled by each interval's ``acc_scale`` (the last
    point's by the last interval's), 0 where ``rests``. Backward from the end,
    ``reach_i = clip(min_j shrink (reach_{i+1} - pull), 0, cap_i)`` over the usable
    rows; forward, ``x_{i+1} = clip(min_j (grow x_i + push), 0, reach_{i+1})``; each
    row's bounds scaled by ``acc_scale`` where ``scaled``.
    Returns the curve, ``reach``, ``x`` (its last value the end speed's square), the
    forward pass's own last value, and per stage whether ``u`` fell below its rows'
    least bound (by more than rounding amplified by ``1 / 2Δ``).
    """
    n = velocity_cap.size - 1
    cap = np.empty(n + 1)
    for i in range(n + 1):
        around = acc_scale[min(i, n - 1)]
        cap[i] = (
            0.0
            if rests[i]
            else _larger(
                _smaller(velocity_cap[i] * velocity_factor[i], acceleration_cap[i] * around), 0.0
            )
        )
    rows = shrink.shape[1]
    pulled, pushed = np.empty((n, rows)), np.empty((n, rows))
    for k in range(n):
        for j in range(rows):
            scale = acc_scale[k] if scaled[j] else 1.0
            pulled[k, j] = -shrink[k, j] * pull[k, j] * scale if usable[k, j] else np.inf
            pushed[k, j] = push[k, j] * scale
    reach = np.empty(n + 1)
    reach[n] = min(x_end, cap[n])
    reach[:n] = recurrence(shrink[::-1], pulled[::-1], cap[n - 1 :: -1], reach[n])[::-1]
    x = np.empty(n + 1)
    x[0] = min(x_start, reach[0])
    x[1:] = recurrence(grow, pushed, reach[1:], x[0])
    last = x[n]
    x[n] = min(x_end, reach[n])
    stuck = np.zeros(n, dtype=np.bool_)
    for k in range(n):
        u = (x[k + 1] - x[k]) / (2.0 * delta[k])
        need = -np.inf
        for j in range(rows):
            if valid[k, j] and np.isfinite(low[k, j]):
                scale = acc_scale[k] if scaled[j] else 1.0
                value = low[k, j] * scale + rate[k, j] * x[k]
                if np.isnan(value) or value > need:
                    need = value
                    if np.isnan(value):
                        break
        slack = 1e-10 * (abs(need) + x[k] / (2.0 * delta[k]))
        stuck[k] = u < need - slack
    return cap, reach, x, last, stuck


@njit(cache=True)
def interval_terms(slope, delta, degree):  # pragma: no cover
    """``c'`` and ``c''`` on every interval in ascending powers of ``τ = σ / Δ``.

    ``slope`` (K + 1, N, m) is ``c'(σ)`` in descending powers of σ; the results are
    (degree + 1, N, m), zero-padded, with ``degree >= K``. Also returns the size of
    ``c'`` at the grid points (at least 1), the scale of a "still" channel.
    """
    size, n, m = slope.shape
    ascending = np.zeros((degree + 1, n, m))
    rate_of = np.zeros((degree + 1, n, m))
    scale = 0.0
    for i in range(n):
        for j in range(m):
            end, power = 0.0, 1.0
            for c in range(size):
                ascending[c, i, j] = slope[size - 1 - c, i, j] * power
                end += ascending[c, i, j]
                power *= delta[i]
            for c in range(degree):
                rate_of[c, i, j] = (c + 1) * ascending[c + 1, i, j] / delta[i]
            scale = max(scale, abs(ascending[0, i, j]))
            if i == n - 1:
                scale = max(scale, abs(end))
    return ascending, rate_of, scale if scale > 0.0 else 1.0


@njit(cache=True)
def build_stages(slope, hull, square_hull, vel_lo, vel_hi, acc_lo, acc_hi, flat, extra_on_u,
                 extra_on_x, extra_lower, extra_upper, flat_row, delta,
                 rounding):  # pragma: no cover  # fmt: skip
    """Everything :class:`~trajkit.time_optimal.reachability.Stages` holds, in one call.

    The channels' rows (:func:`channel_rows`, ``slope`` as :func:`interval_terms`
    takes it, a channel still where its slope is below ``flat`` of the largest at the
    grid points) and any further rows (``extra_*``, (N, r), flat where their u term
    is below ``flat_row`` of the larger of their column's largest and their x term in
    u's units), each stage's cap and the passes' terms (:func:`stage_setup`), and the
    velocity caps that keep the rates inside every interval (:func:`rate_ratios`).
    """
    ascending, rate_of, scale = interval_terms(slope, delta, hull.shape[0] - 1)
    flat = flat * scale
    n, m = ascending.shape[1:]
    on_u0, on_x0, at_point, at_points = channel_rows(ascending, rate_of, hull, vel_lo, vel_hi,
                                                     acc_lo, acc_hi, flat)  # fmt: skip
    own, extra = on_u0.shape[1], extra_on_u.shape[1]
    rows = own + extra
    on_u, on_x = np.empty((n, rows)), np.empty((n, rows))
    lower, upper, threshold = np.empty((n, rows)), np.empty((n, rows)), np.empty((n, rows))
    column_max = np.zeros(extra)
    for i in range(n):
        for r in range(extra):
            column_max[r] = max(column_max[r], abs(extra_on_u[i, r]))
    for i in range(n):
        for r in range(own):
            on_u[i, r], on_x[i, r] = on_u0[i, r], on_x0[i, r]
            lower[i, r], upper[i, r] = acc_lo[r % m], acc_hi[r % m]
            threshold[i, r] = flat
        for r in range(extra):
            on_u[i, own + r], on_x[i, own + r] = extra_on_u[i, r], extra_on_x[i, r]
            lower[i, own + r], upper[i, own + r] = extra_lower[i, r], extra_upper[i, r]
            threshold[i, own + r] = flat_row * max(column_max[r], abs(extra_on_x[i, r]) * delta[i])
    start = np.empty(n)
    for i in range(n):
        start[i] = _smaller(4.0 * at_point[i], at_points[i])
    valid, rate, high, low, stage_cap, grow, push, shrink, pull, usable = stage_setup(
        on_u, on_x, lower, upper, threshold, start, delta, rounding)  # fmt: skip
    acceleration_cap = np.empty(n + 1)
    acceleration_cap[:n] = stage_cap
    acceleration_cap[n] = at_points[n]
    velocity_cap = _velocity_caps(ascending, at_point, acceleration_cap, vel_lo, vel_hi,
                                  square_hull, hull)  # fmt: skip
    return (valid, rate, high, low, on_u, on_x, lower, upper, threshold, grow, push, shrink,
            pull, usable, acceleration_cap, velocity_cap)  # fmt: skip


@njit(cache=True)
def _velocity_caps(ascending, at_point, acceleration_cap, vel_lo, vel_hi, square_hull,
                   hull):  # pragma: no cover  # fmt: skip
    """Velocity caps at the points that keep the rates on the whole of every interval.

    With ``x`` linear on an interval, ``ċ² = c'(τ)² ((1 - τ) x_i + τ x_{i+1})``. Let ``w``
    be the caps at the points and ``ρ`` the largest ratio of this rate² to its bound
    when ``x = w`` at both ends (an upper bound, from the Bernstein coefficients:
    :func:`rate_ratios`); then ``x <= w / ρ`` at both ends keeps the bound throughout.
    ``ρ`` exceeds 1 by ``O(Δ²)`` where the caps vary smoothly.
    """
    count = at_point.size
    w = np.empty(count)
    largest = -np.inf
    any_finite = False
    for p in range(count):
        w[p] = _smaller(at_point[p], acceleration_cap[p])
        if np.isfinite(w[p]):
            any_finite = True
            largest = max(largest, w[p])
    if not any_finite:
        return at_point.copy()
    for p in range(count):
        if not np.isfinite(w[p]):
            w[p] = largest
    # A cap far above its neighbours (where the path's tangent vanishes, at its end
    # say) would make the interpolated rate between them huge and crush the
    # neighbour's cap; no timing goes from one to the other within an interval.
    clamped = np.empty(count)
    for p in range(count):
        after = w[p + 1] if p + 1 < count else np.inf
        before = w[p - 1] if p > 0 else np.inf
        clamped[p] = _smaller(w[p], 4.0 * _smaller(after, before))
    rho = rate_ratios(ascending, clamped, vel_lo, vel_hi, square_hull, hull)
    out = np.empty(count)
    for p in range(count):
        after = rho[p] if p < count - 1 else 1.0
        before = rho[p - 1] if p > 0 else 1.0
        out[p] = _smaller(at_point[p], clamped[p] / _larger(after, before))
    return out


@njit(cache=True)
def merged_grid(points, breakpoints, close, split):  # pragma: no cover
    """:func:`trajkit.time_optimal.grid_points`'s merge, both inputs sorted.

    The union of ``points`` and ``breakpoints``; a point followed within ``close``
    by the next is dropped, the last is the last breakpoint, and the first is the
    first breakpoint unless a breakpoint took its place. An interval between
    two breakpoints gets ``split - 1`` points inside, at equal fractions.
    """
    merged = np.empty(points.size + breakpoints.size)
    count, a, b = 0, 0, 0
    while a < points.size or b < breakpoints.size:
        take_point = b >= breakpoints.size or (a < points.size and points[a] <= breakpoints[b])
        value = points[a] if take_point else breakpoints[b]
        if take_point:
            a += 1
        else:
            b += 1
        if count == 0 or value != merged[count - 1]:
            merged[count] = value
            count += 1
    kept = np.empty(count)
    on_break = np.zeros(count, dtype=np.bool_)
    size, b = 0, 0
    for k in range(count):
        if k == count - 1 or merged[k + 1] - merged[k] > close:
            kept[size] = merged[k]
            size += 1
    kept[size - 1] = breakpoints[-1]
    for k in range(size):  # exactly a breakpoint, as both are sorted
        while b < breakpoints.size and breakpoints[b] < kept[k]:
            b += 1
        on_break[k] = b < breakpoints.size and breakpoints[b] == kept[k]
    if not on_break[0]:
        # A point a hair after the start took its place: the grid starts with the path.
        # (A breakpoint there stays: the grid's first piece is then the path's second.)
        kept[0], on_break[0] = breakpoints[0], True
    inside = 0
    for k in range(size - 1):
        if on_break[k] and on_break[k + 1]:
            inside += split - 1
    out = np.empty(size + inside)
    n = 0
    for k in range(size):
        out[n] = kept[k]
        n += 1
        if k < size - 1 and on_break[k] and on_break[k + 1]:
            width = kept[k + 1] - kept[k]
            for j in range(1, split):
                out[n] = kept[k] + width * (j / split)
                n += 1
    return out


@njit(cache=True)
def pieces_of(breakpoints, s):  # pragma: no cover
    """The path piece each interval of ``s`` starts in, and its offset into that piece."""
    count = s.size - 1
    piece = np.searchsorted(breakpoints, s[:-1], side="right") - 1
    offset = np.empty(count)
    last = breakpoints.size - 2
    for i in range(count):
        piece[i] = min(max(piece[i], 0), last)
        offset[i] = s[i] - breakpoints[piece[i]]
    return piece, offset


@njit(cache=True)
def phases(s, x):  # pragma: no cover
    """Path speed at the points, each interval's duration and ``s̈``; -1 or a stalled interval.

    With ``x = ṡ²`` linear in ``s`` on an interval, ``s̈`` is constant there and the
    interval takes ``2 Δs / (ṡ_i + ṡ_{i+1})``; an interval whose speed vanishes at
    both ends is never crossed, and its index is returned.
    """
    count = s.size - 1
    speed = np.sqrt(x)
    durations, u = np.empty(count), np.empty(count)
    stalled = -1
    for i in range(count):
        delta = s[i + 1] - s[i]
        total = speed[i] + speed[i + 1]
        if total <= 0.0 and stalled < 0:
            stalled = i
        durations[i] = 2.0 * delta / total if total != 0.0 else np.inf
        u[i] = (x[i + 1] - x[i]) / (2.0 * delta)
    return speed, durations, u, stalled


@njit(cache=True)
def timed_pieces(coefficients, breakpoints, s, x):  # pragma: no cover
    """``q(s(t))`` on every interval of ``s`` (:func:`trajkit.time_optimal.timing.timed`).

    Returns the breakpoints in time, the coefficients (:func:`compose`), and the
    first stalled interval (-1 if none: :func:`phases`).
    """
    speed, durations, u, stalled = phases(s, x)
    piece, offset = pieces_of(breakpoints, s)
    count = piece.size
    times = np.empty(count + 1)
    times[0] = 0.0
    sigma = np.empty((count, 3))
    local = np.empty((coefficients.shape[0], count, coefficients.shape[2]))
    for i in range(count):
        times[i + 1] = times[i] + durations[i]
        sigma[i, 0], sigma[i, 1], sigma[i, 2] = offset[i], speed[i], u[i] / 2.0
        local[:, i, :] = coefficients[:, piece[i], :]
    return times, compose(local, sigma), stalled


@njit(cache=True)
def breakpoint_steps(coefficients, breakpoints, order, rtol):  # pragma: no cover
    """:func:`trajkit.time_optimal.breakpoint_steps` of a path's coefficients (k + 1, P, m).

    The ``order``-th derivative's jump at each inner breakpoint, 0 within ``rtol`` of
    its largest value at the breakpoints (at least 1).
    """
    size, count, m = coefficients.shape
    degree = size - 1
    # The derivative's coefficients, descending: d^order/dσ^order of σ^(degree - c).
    rows = max(size - order, 1)
    c = np.zeros((rows, count, m))
    for r in range(size - order):
        power = degree - r
        factor = 1.0
        for step in range(order):
            factor *= power - step
        c[r] = coefficients[r] * factor
    starts, ends = np.empty((count, m)), np.empty((count, m))
    scale = 1.0
    for p in range(count):
        length = breakpoints[p + 1] - breakpoints[p]
        for j in range(m):
            value = c[0, p, j]
            for r in range(1, rows):
                value = value * length + c[r, p, j]
            starts[p, j], ends[p, j] = c[rows - 1, p, j], value
            scale = max(scale, abs(starts[p, j]))
            if p == count - 1:
                scale = max(scale, abs(value))
    steps = np.empty((count - 1, m))
    for p in range(count - 1):
        for j in range(m):
            step = starts[p + 1, j] - ends[p, j]
            steps[p, j] = step if abs(step) > rtol * scale else 0.0
    return steps
