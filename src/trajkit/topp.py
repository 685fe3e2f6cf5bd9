"""Time-optimal path parameterization: the fastest timing of a fixed joint path.

Given a geometric path ``q(s)`` (any :class:`~trajkit.Trajectory`, its time axis
read as the path parameter ``s``) and per-joint velocity and acceleration bounds,
:func:`topp` finds the fastest ``s(t)`` by reachability analysis on a grid
``s_0 < ... < s_N`` (Pham & Pham, 2018) with the path speed squared ``x = ṡ²`` and
a constant ``u = s̈`` on each interval:

* every stage's constraints are boxes, so each is solved in closed form: the
  acceleration bounds ``a_lo ≤ q'(s) u + q''(s) x ≤ a_hi`` give, per joint, one
  upper and one lower bound on ``u`` affine in ``x``, and the velocity bounds cap ``x``;
* a backward pass finds, at every grid point, the largest ``x`` from which the end
  can still be reached; a forward pass accelerates as hard as that allows.

The timing is exact between grid points too: on each interval ``s(t)`` is a
quadratic, so ``q(s(t))`` is a polynomial and the result is an ordinary
Trajectory whose :meth:`~trajkit.Trajectory.check` is exact. The stage constraints
hold at the grid points only; to make the whole curve keep every limit, the
result is checked exactly, and any excess is removed by re-solving with the
limits tightened by the measured ratio, and finally (if needed) by slowing the
whole motion uniformly by ``max(v_peak / v_max, sqrt(a_peak / a_max))``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from trajkit._validation import FloatArray, finite_scalar
from trajkit.errors import InfeasibleError, InvalidInputError
from trajkit.limits import Limits
from trajkit.trajectory import Trajectory

__all__ = ["topp"]

#: Joints whose path derivative is below this (relative) do not bound the path acceleration.
_FLAT = 1e-12
#: Re-solves with tightened limits before the uniform slow-down.
_TIGHTENINGS = 4


def topp(
    path: Trajectory,
    limits: Limits,
    *,
    grid: int | ArrayLike = 500,
    start_speed: float = 0.0,
    end_speed: float = 0.0,
) -> Trajectory:
    """The time-optimal timing of ``path`` under velocity and acceleration limits.

    Parameters
    ----------
    path : Trajectory
        The geometric path; its time axis is the path parameter ``s``.
    limits : Limits
        ``velocity`` and ``acceleration`` bounds per joint (asymmetric allowed; each
        lower bound < 0 < upper bound).
    grid : int or array_like
        Number of grid intervals (uniform in ``s``; the path's breakpoints are added),
        or the grid points themselves.
    start_speed, end_speed : float
        Path speeds ``ṡ`` at the start and the end (units of ``s`` per second).

    Returns
    -------
    Trajectory
        ``q(t)``: the path timed, its pieces polynomials of twice the path's degree.
        ``info`` holds ``grid_points``, ``path_speed`` (ṡ at each), ``slow_down``
        (the uniform factor applied at the end, 1 if none) and ``tightening``.

    Raises
    ------
    InfeasibleError
        If the boundary speeds cannot be met within the limits.
    """
    if not isinstance(path, Trajectory):
        raise InvalidInputError(f"path must be a Trajectory, got {type(path).__name__}")
    if not isinstance(limits, Limits) or limits.velocity is None or limits.acceleration is None:
        raise InvalidInputError("limits must be a Limits with velocity and acceleration bounds")
    for bounds, name in ((limits.velocity, "velocity"), (limits.acceleration, "acceleration")):
        lower = np.broadcast_to(bounds.lower, path.ndof)
        upper = np.broadcast_to(bounds.upper, path.ndof)
        if np.any(lower >= 0.0) or np.any(upper <= 0.0):
            raise InvalidInputError(f"{name} bounds must have lower < 0 < upper for every joint")
    points = _grid(path, grid)
    speeds = [finite_scalar("start_speed", start_speed, unit="1/s"),
              finite_scalar("end_speed", end_speed, unit="1/s")]  # fmt: skip
    if min(speeds) < 0.0:
        raise InvalidInputError(f"start_speed and end_speed must be >= 0, got {speeds}")
    vel = [np.broadcast_to(b, path.ndof).astype(float)
           for b in (limits.velocity.lower, limits.velocity.upper)]  # fmt: skip
    acc = [np.broadcast_to(b, path.ndof).astype(float)
           for b in (limits.acceleration.lower, limits.acceleration.upper)]  # fmt: skip
    scale_v = scale_a = 1.0
    attempts = 0
    for _ in range(_TIGHTENINGS + 1):
        attempts += 1
        x = _solve(path, points, [v * scale_v for v in vel], [a * scale_a for a in acc],
                   speeds[0] ** 2, speeds[1] ** 2)  # fmt: skip
        ratio_v, ratio_a = _peaks(path, points, x, vel, acc)
        if ratio_v <= 1.0 + 1e-9 and ratio_a <= 1.0 + 1e-9:
            break
        # Tighten each quantity by how far its peak passes its bound, with a small margin.
        scale_v /= max(ratio_v, 1.0) * (1 + 1e-9)
        scale_a /= max(ratio_a, 1.0) * (1 + 1e-9)
    result = _timed(path, points, x)
    slow = 1.0
    if ratio_v > 1.0 + 1e-9 or ratio_a > 1.0 + 1e-9:
        slow = max(ratio_v, np.sqrt(ratio_a), 1.0) * (1.0 + 1e-12)
        result = result.time_scaled(slow)
    info = {"planner": "topp", "grid_points": points, "path_speed": np.sqrt(x),
            "slow_down": slow, "tightening": (scale_v, scale_a), "attempts": attempts}  # fmt: skip
    return Trajectory(result.breakpoints, result.coefficients, info=info)


def _peaks(path: Trajectory, s: FloatArray, x: FloatArray, vel: list, acc: list
           ) -> tuple[float, float]:  # fmt: skip
    """How far the timed path's joint velocities and accelerations pass their bounds.

    Exact on the whole curve, without building the timed polynomials: on an interval
    of a cubic path ``x = ṡ²`` is linear in ``s``, so ``q̈ = q'' x + q' s̈`` is a
    quadratic in ``s`` (its extremes in closed form) and ``q̇ = q' ṡ`` peaks where
    ``q̈`` vanishes or at the ends. Paths of higher degree are checked on the timed
    Trajectory instead. Returns the largest ratio of value to bound for each.
    """
    if path.degree > 3:
        report = _timed(path, s, x).check(Limits(velocity=tuple(vel), acceleration=tuple(acc)))
        ratios = {"velocity": 1.0, "acceleration": 1.0}
        for violation in report.violations:
            ratio = abs(violation.value) / abs(violation.bound)
            ratios[violation.quantity] = max(ratios[violation.quantity], ratio)
        return ratios["velocity"], ratios["acceleration"]
    delta = np.diff(s)
    u = (x[1:] - x[:-1]) / (2.0 * delta)
    piece = np.clip(np.searchsorted(path.breakpoints, s[:-1], side="right") - 1, 0,
                    path.coefficients.shape[1] - 1)  # fmt: skip
    c = np.zeros((4, piece.size, path.ndof))
    c[4 - path.coefficients.shape[0] :] = path.coefficients[:, piece, :]
    a3, a2, a1 = c[0], c[1], c[2]  # q = a3 w^3 + a2 w^2 + a1 w + a0 in the piece's variable w
    w0 = (s[:-1] - path.breakpoints[piece])[:, None]
    # In sigma = s - s_i: q' = d0 + d1 sigma + d2 sigma^2, q'' = e0 + e1 sigma.
    d0 = 3 * a3 * w0**2 + 2 * a2 * w0 + a1
    d1 = 6 * a3 * w0 + 2 * a2
    d2 = 3 * a3
    e0, e1 = d1, 2 * d2
    xi, ui = x[:-1, None], u[:, None]
    # q̈(sigma) = (e0 + e1 sigma)(xi + 2 ui sigma) + (d0 + d1 sigma + d2 sigma^2) ui
    #          = A sigma^2 + B sigma + C
    big_a = 2 * ui * e1 + d2 * ui
    big_b = e0 * 2 * ui + e1 * xi + d1 * ui
    big_c = e0 * xi + d0 * ui
    width = np.broadcast_to(delta[:, None], big_a.shape)
    with np.errstate(divide="ignore", invalid="ignore"):
        vertex = np.where(big_a != 0, -big_b / (2 * big_a), 0.0)
        disc = big_b**2 - 4 * big_a * big_c
        root = np.sqrt(np.where(disc >= 0, disc, 0.0))
        flat = np.abs(big_a) <= 1e-300
        root1 = np.where(
            flat, np.where(big_b != 0, -big_c / big_b, 0.0), (-big_b + root) / (2 * big_a)
        )
        root2 = np.where(flat, 0.0, (-big_b - root) / (2 * big_a))
    candidates = [np.zeros_like(width), width, np.clip(vertex, 0, width)]
    accel = [big_a * t**2 + big_b * t + big_c for t in candidates]
    speeds = [np.clip(t, 0, width) for t in (root1, root2)] + [np.zeros_like(width), width]

    def joint_velocity(t: FloatArray) -> FloatArray:
        return (d0 + d1 * t + d2 * t**2) * np.sqrt(np.maximum(xi + 2 * ui * t, 0.0))

    velocity = [joint_velocity(t) for t in speeds]
    v_high, v_low = np.max(velocity, axis=(0, 1)), np.min(velocity, axis=(0, 1))
    a_high, a_low = np.max(accel, axis=(0, 1)), np.min(accel, axis=(0, 1))
    ratio_v = max(np.max(v_high / vel[1]), np.max(v_low / vel[0]))
    ratio_a = max(np.max(a_high / acc[1]), np.max(a_low / acc[0]))
    return float(ratio_v), float(ratio_a)


def _grid(path: Trajectory, grid: int | ArrayLike) -> FloatArray:
    start, end = path.start_time, path.end_time
    if end <= start:
        raise InvalidInputError("the path has no length to time")
    if isinstance(grid, (int, np.integer)) and not isinstance(grid, bool):
        if grid < 2:
            raise InvalidInputError(f"grid must be at least 2 intervals, got {grid}")
        points = np.linspace(start, end, int(grid) + 1)
    else:
        points = np.asarray(grid, dtype=float)
        if points.ndim != 1 or points.size < 3 or np.any(np.diff(points) <= 0):
            raise InvalidInputError("grid points must be at least 3 increasing numbers")
        if points[0] != start or points[-1] != end:
            raise InvalidInputError("grid points must start and end with the path")
    # The path's own breakpoints are grid points, so every interval lies in one piece.
    points = np.union1d(points, path.breakpoints)
    keep = np.append(np.diff(points) > 1e-12 * (end - start), True)
    return points[keep] if keep[-1] else points


def _solve(path: Trajectory, s: FloatArray, vel: list, acc: list, x_start: float,
           x_end: float) -> FloatArray:  # fmt: skip
    """The time-optimal ``x = ṡ²`` at the grid points ``s``."""
    d1, d2 = path.evaluate(s, 1), path.evaluate(s, 2)  # (N + 1, ndof)
    scale = np.abs(d1).max() or 1.0
    moving = np.abs(d1) > _FLAT * scale
    safe = np.where(moving, d1, 1.0)
    # Velocity caps on x: |q'| ṡ within the side the joint moves to.
    side = np.where(d1 > 0, vel[1], -vel[0])
    magnitude = np.where(moving, np.abs(d1), 1.0)
    cap = np.min(np.where(moving, (side / magnitude) ** 2, np.inf), axis=1)
    # Acceleration: u within [p_lo + r x, p_hi + r x] per moving joint.
    hi = np.where(d1 > 0, acc[1], acc[0]) / safe
    lo = np.where(d1 > 0, acc[0], acc[1]) / safe
    r = -d2 / safe
    # A still joint (q' = 0) bounds x itself: a_lo <= q'' x <= a_hi.
    bend = np.where(d2 > 0, acc[1] / np.where(d2 > 0, d2, 1.0),
                    np.where(d2 < 0, acc[0] / np.where(d2 < 0, d2, 1.0), np.inf))  # fmt: skip
    cap = np.minimum(cap, np.min(np.where(moving, np.inf, bend), axis=1))
    # The largest x with max_j L_j(x) <= min_k U_k(x) (the maximum velocity curve).
    hi_m = np.where(moving, hi, np.inf)
    lo_m = np.where(moving, lo, -np.inf)
    r_m = np.where(moving, r, 0.0)
    slope = r_m[:, :, None] - r_m[:, None, :]  # L_j rises faster than U_k
    room = hi_m[:, None, :] - lo_m[:, :, None]
    with np.errstate(divide="ignore", invalid="ignore"):
        crossing = np.where(slope > 0, room / np.where(slope > 0, slope, 1.0), np.inf)
    cap = np.minimum(cap, np.nanmin(np.where(np.isnan(crossing), np.inf, crossing), axis=(1, 2)))
    cap = np.maximum(cap, 0.0)
    # Where the path's tangent jumps (a corner), the joints' velocities would jump
    # unless the path stops there.
    inner = path.breakpoints[1:-1]
    if inner.size:
        left, right = path.evaluate(np.nextafter(inner, -np.inf), 1), path.evaluate(inner, 1)
        jumps = np.abs(left - right).max(axis=1) > 1e-9 * max(1.0, scale)
        cap[np.searchsorted(s, inner[jumps])] = 0.0
    delta = np.diff(s)
    # Per stage: forward x' = min_j ((1 + 2Δ r_j) x + 2Δ p_hi_j); backward from the
    # lower bounds. The passes are recurrences along the path: one loop over stages,
    # with every coefficient computed above for all stages at once.
    # Each interval's u keeps the acceleration bounds at both of its ends (toppra's
    # "interpolation" discretization): at the far end q̈ = q'(s+) u + q''(s+) (x + 2Δ u).
    far = d1[1:] + 2.0 * delta[:, None] * d2[1:]
    far_moving = np.abs(far) > _FLAT * scale
    far_safe = np.where(far_moving, far, 1.0)
    hi_far = np.where(far_moving, np.where(far > 0, acc[1], acc[0]) / far_safe, np.inf)
    lo_far = np.where(far_moving, np.where(far > 0, acc[0], acc[1]) / far_safe, -np.inf)
    r_far = np.where(far_moving, -d2[1:] / far_safe, 0.0)
    moves = np.concatenate([moving[:-1], far_moving], axis=1)
    rates = np.concatenate([r_m[:-1], r_far], axis=1)
    highs = np.concatenate([hi_m[:-1], hi_far], axis=1)
    lows = np.concatenate([lo_m[:-1], lo_far], axis=1)
    twice = 2.0 * delta[:, None]
    grow_f = (1.0 + twice * rates).tolist()
    add_f = np.where(moves, twice * highs, np.inf).tolist()
    denominator = 1.0 + twice * rates
    usable = moves & (denominator > 0)
    shrink_b = np.where(usable, 1.0 / np.where(usable, denominator, 1.0), 0.0).tolist()
    sub_b = np.where(usable, twice * np.where(usable, lows, 0.0), 0.0).tolist()
    caps = cap.tolist()
    n = len(caps)
    if x_end > caps[-1] * (1 + 1e-9) or x_start > caps[0] * (1 + 1e-9):
        raise InfeasibleError("the boundary path speeds break the limits at the path's ends")
    reach = [0.0] * n
    reach[-1] = min(x_end, caps[-1])
    for i in range(n - 2, -1, -1):  # backward: the largest x that can still stop in time
        after = reach[i + 1]
        best = caps[i]
        for shrink, sub, ok in zip(shrink_b[i], sub_b[i], usable[i], strict=True):
            if ok:
                bound = (after - sub) * shrink
                if bound < best:
                    best = bound
        reach[i] = best if best > 0.0 else 0.0
    if x_start > reach[0] * (1 + 1e-9):
        raise InfeasibleError(
            f"start_speed {np.sqrt(x_start):g} is too fast to keep the limits along the path"
        )
    x = [0.0] * n
    x[0] = min(x_start, reach[0])
    for i in range(n - 1):  # forward: as fast as the limits and the reachable set allow
        now = x[i]
        best = reach[i + 1]
        for grow, add in zip(grow_f[i], add_f[i], strict=True):
            bound = grow * now + add
            if bound < best:
                best = bound
        x[i + 1] = best if best > 0.0 else 0.0
    x[-1] = min(x_end, reach[-1]) if x_end <= reach[-1] * (1 + 1e-9) else x[-1]
    return np.array(x)


def _timed(path: Trajectory, s: FloatArray, x: FloatArray) -> Trajectory:
    """``q(s(t))`` as a Trajectory: ``s`` quadratic in ``t`` on every interval."""
    speed = np.sqrt(x)
    delta = np.diff(s)
    total = speed[:-1] + speed[1:]
    if np.any(total <= 0.0):
        raise InfeasibleError("the path speed vanishes on a whole interval: the path is not "
                              "traversable within the limits")  # fmt: skip
    durations = 2.0 * delta / total
    u = (x[1:] - x[:-1]) / (2.0 * delta)
    # The path piece of each interval, and its local coefficients (highest power first).
    piece = np.clip(np.searchsorted(path.breakpoints, s[:-1], side="right") - 1, 0,
                    path.coefficients.shape[1] - 1)  # fmt: skip
    local = path.coefficients[:, piece, :]  # (d + 1, M, ndof)
    offset = s[:-1] - path.breakpoints[piece]
    degree = local.shape[0] - 1
    # sigma(tau) = offset + speed tau + u tau^2 / 2, in ascending powers of tau.
    sigma = np.stack([offset, speed[:-1], u / 2.0], axis=1)  # (M, 3)
    result = np.zeros((local.shape[1], 2 * degree + 1, path.ndof))
    power = np.ones((local.shape[1], 1))
    for m in range(degree + 1):  # q = sum_m a_m sigma^m: degree + 1 terms, all intervals at once
        coefficient = local[degree - m]  # (M, ndof), the sigma^m coefficient
        result[:, : power.shape[1], :] += power[:, :, None] * coefficient[:, None, :]
        grown = np.zeros((power.shape[0], power.shape[1] + 2))
        for shift in range(3):  # power * sigma, for every interval at once
            grown[:, shift : shift + power.shape[1]] += power * sigma[:, shift : shift + 1]
        power = grown
    coefficients = result[:, ::-1, :].transpose(1, 0, 2)  # highest power first, (k + 1, M, ndof)
    breakpoints = np.concatenate([[0.0], np.cumsum(durations)])
    return Trajectory(breakpoints, np.ascontiguousarray(coefficients))
