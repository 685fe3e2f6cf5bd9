"""The reachability passes, compiled: scalar loops over stages and their lines.

Importing this module imports numba (slow): :mod:`.reachability` imports it inside
its functions, so ``import trajkit`` stays fast.
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
    n, m = r.shape
    out = np.empty(n)
    for i in range(n):
        cap = np.inf
        for j in range(m):
            # A still channel (c' = 0) bounds x itself: a_lo <= c'' x <= a_hi.
            if not abs(d1[i, j]) > threshold[i, j]:
                curve = d2[i, j]
                bend = np.inf
                if curve > 0.0:
                    bend = acc_hi[i, j] / curve
                elif curve < 0.0:
                    bend = acc_lo[i, j] / curve
                if bend < cap:
                    cap = bend
        for j in range(m):  # L_j rising faster than U_k meets it at room / slope
            low = lo[i, j] if valid[i, j] else -np.inf
            for k in range(m):
                slope = r[i, j] - r[i, k]
                high = hi[i, k] if valid[i, k] else np.inf
                room = high - low
                if slope > 0.0:
                    crossing = room / slope
                elif room < 0.0:
                    crossing = 0.0
                else:
                    crossing = np.inf
                if crossing < cap:
                    cap = crossing
        out[i] = cap if cap > 0.0 else 0.0
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
def cubic_extremes(a3, a2, a1, w0, x, delta):  # pragma: no cover
    """Least and greatest joint velocity and acceleration per interval of a cubic path.

    ``q = a3 w³ + a2 w² + a1 w + a0`` in the piece's variable ``w``, which is ``w0``
    at the interval's start; ``x = ṡ²`` at the grid points, linear in between. In
    ``σ = s - s_i``: ``q̈ = A σ² + B σ + C`` (extremes at the ends and the vertex) and
    ``q̇ = q' ṡ`` peaks at the ends or where ``q̈`` vanishes.
    """
    n, ndof = a3.shape
    v_low, v_high = np.empty((n, ndof)), np.empty((n, ndof))
    a_low, a_high = np.empty((n, ndof)), np.empty((n, ndof))
    accel, speed, where = np.empty(3), np.empty(4), np.empty(4)
    for i in range(n):
        xi = x[i]
        ui = (x[i + 1] - x[i]) / (2.0 * delta[i])
        width = delta[i]
        for j in range(ndof):
            w = w0[i]
            d0 = 3.0 * a3[i, j] * w**2 + 2.0 * a2[i, j] * w + a1[i, j]
            d1 = 6.0 * a3[i, j] * w + 2.0 * a2[i, j]
            d2 = 3.0 * a3[i, j]
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
            v_low[i, j], v_high[i, j] = _extreme(speed, True), _extreme(speed, False)
            a_low[i, j], a_high[i, j] = _extreme(accel, True), _extreme(accel, False)
    return v_low, v_high, a_low, a_high


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
