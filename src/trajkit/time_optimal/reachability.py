"""Reachability analysis in the phase plane ``(s, x = ṡ²)``, stage problems in closed form.

The constraints are *channels*: quantities whose rate is ``c'(s) ṡ`` and whose
second time derivative is ``c'(s) u + c''(s) x`` with ``u = s̈`` — joint angles,
but also a wheeled base's travelled distance and heading. Each channel may bound
its rate, its acceleration, or both.

On the grid ``s_0 < ... < s_N``, ``u`` is constant on each interval and every
interval keeps the acceleration bounds at both of its ends (the "interpolation"
discretization). Every bound is then affine in the interval's start ``x_i``:
``L_j(x_i) <= u <= U_k(x_i)``, and both passes are recurrences of the form

    y_next = clip(min_j (a_j y + b_j), 0, h)

(the backward pass: the largest ``x_i`` from which ``x_{i+1}`` can still be
reached; the forward pass: accelerate as hard as the bounds and the reachable set
allow). Each pass is sequential along the path, so it is a loop over stages; all
the work per stage is prepared for every stage at once beforehand (the rows, each
stage's maximum velocity curve, and the lower envelope of its lines over the
inputs it can receive, :func:`recurrence`), and the loop evaluates one line per
stage.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache
from math import comb

import numpy as np

from trajkit._validation import FloatArray
from trajkit.errors import InfeasibleError
from trajkit.tolerances import LIMIT_RTOL, ROUNDING_RTOL

__all__ = ["Channels", "Rows", "Stages"]

#: A channel whose path derivative is below this (relative) does not bound ``u``.
_FLAT = 1e-12
#: A further row whose u term is below this (relative) bounds x alone.
_FLAT_ROW = 1e-9


@dataclass(frozen=True)
class Channels:
    """What the timing must respect: each channel's path derivative and its bounds.

    Attributes
    ----------
    s : ndarray, shape (N + 1,)
        Grid points.
    slope : ndarray, shape (K + 1, N, m)
        On each interval, ``c'(σ)`` of each of the ``m`` channels as a polynomial in
        ``σ = s - s_i`` (descending powers, :mod:`trajkit._poly` layout).
    velocity, acceleration : tuple of ndarray, shape (m,)
        ``(lower, upper)`` bounds on ``ċ`` and ``c̈`` (units of the channel per
        second and per second squared); ``-inf`` / ``inf`` where unbounded.
    corners : ndarray of int
        Grid indices where the path's tangent jumps: the path must stop there.
    """

    s: FloatArray
    slope: FloatArray
    velocity: tuple[FloatArray, FloatArray]
    acceleration: tuple[FloatArray, FloatArray]
    corners: np.ndarray


@dataclass(frozen=True)
class Rows:
    """Further bounds of each stage, given as data: ``lower <= on_u u + on_x x_i <= upper``.

    Each array has shape (N, r): one row per bound and stage, ``x_i`` the stage's
    entering ``ṡ²`` and ``u`` its ``s̈`` (see :mod:`trajkit.time_optimal.constraints`,
    which builds them for torque and tool limits). Unlike the channels' rows they
    are not scaled by the solver's acceleration scale.
    """

    on_u: FloatArray
    on_x: FloatArray
    lower: FloatArray
    upper: FloatArray


@cache
def _bernstein(degree: int) -> FloatArray:
    """``B`` with ``b = B @ a``: Bernstein coefficients on [0, 1] from ascending powers.

    Cached, shared by every solve: the kernels only read it.
    """
    out = np.zeros((degree + 1, degree + 1))
    for c in range(degree + 1):
        for j in range(c + 1):
            out[c, j] = comb(c, j) / comb(degree, j)
    return out


class Stages:
    """The per-stage coefficients of both passes, computed once for a grid.

    Every interval's rows bound the *Bernstein coefficients* of the channels'
    acceleration and squared rate over the interval, not only their values at the
    ends. A polynomial lies within the hull of its Bernstein coefficients, and both
    quantities are linear in ``(x_i, u)`` with polynomial coefficients in ``σ``:

    * acceleration ``c̈(σ) = c''(σ) x_i + (c'(σ) + 2σ c''(σ)) u``;
    * squared rate ``ċ(σ)² = c'(σ)² ((1 - τ) x_i + τ x_{i+1})`` with ``τ = σ / Δ``,
      bounded by the rate bound of the side the channel moves to.

    So a timing that keeps every row keeps the limits on the whole interval, for
    polynomial channels exactly; the hull overestimates by ``O(Δ²)`` only. The
    first and last coefficients are the values at the interval's ends.

    Limits can then be tightened per grid point (velocity) and per interval
    (acceleration) and the problem re-solved cheaply: only the bounds' offsets scale.
    """

    def __init__(self, channels: Channels, extra: Rows | None = None) -> None:
        from trajkit.time_optimal import _passes

        slope = channels.slope
        vel_lo, vel_hi = channels.velocity
        acc_lo, acc_hi = channels.acceleration
        delta = np.diff(channels.s)
        self.delta = delta
        degree = max(slope.shape[0] - 1, 1)
        # Acceleration rows: Bernstein coefficients of c'' (on x_i) and c' + 2σ c'' (on u),
        # and any further rows (a row whose u term is negligible beside its x term, as
        # x ~ 2Δu, or beside that row's largest along the path, bounds x alone: a row
        # flat by construction, a direction across the tool's path say, then never has
        # rounding for a u term); each stage's own maximum velocity curve, found by
        # Newton steps from the points' curve; the passes' terms; the velocity caps.
        contiguous = np.ascontiguousarray
        if extra is None:
            nothing = np.zeros((delta.size, 0))
            extra = Rows(nothing, nothing, nothing, nothing)
        built = _passes.build_stages(
            contiguous(slope, dtype=float), _bernstein(degree), _bernstein(2 * degree),
            *(contiguous(side, dtype=float) for side in (vel_lo, vel_hi, acc_lo, acc_hi)),
            _FLAT,
            *(contiguous(part, dtype=float) for part in (extra.on_u, extra.on_x, extra.lower,
                                                         extra.upper)),
            _FLAT_ROW, delta, ROUNDING_RTOL)  # fmt: skip
        self._rows = built[:9]
        (self._grow, self._push, self._shrink, self._pull, self._usable, self.acceleration_cap,
         self.velocity_cap) = built[9:]  # fmt: skip
        self._scaled = np.arange(built[0].shape[1]) < (degree + 1) * slope.shape[2]
        self._exact = np.zeros(delta.size + 1, dtype=bool)
        self._rests = np.zeros(delta.size + 1, dtype=bool)
        self._rests[channels.corners] = True

    def solve(
        self,
        x_start: float,
        x_end: float,
        velocity_factor: FloatArray | None = None,
        acceleration_scale: FloatArray | None = None,
    ) -> FloatArray:
        """The time-optimal ``x`` at every grid point.

        ``velocity_factor`` (per grid point) multiplies the velocity caps on x;
        ``acceleration_scale`` (per interval) multiplies the interval's acceleration
        bounds. Both default to 1.
        """
        from trajkit.time_optimal import _passes

        n = self.delta.size + 1
        if velocity_factor is None:
            velocity_factor = np.ones(n)
        if acceleration_scale is None:
            acceleration_scale = np.ones(n - 1)
        valid, rate, _, low = self._rows[:4]
        cap, reach, x, last, stuck_stages = _passes.passes(
            self._shrink, self._pull, self._usable, self._grow, self._push, valid, rate, low,
            self._scaled, np.ascontiguousarray(acceleration_scale, dtype=float),
            self.velocity_cap, np.ascontiguousarray(velocity_factor, dtype=float),
            self.acceleration_cap, self._rests, float(x_start), float(x_end),
            self.delta)  # fmt: skip
        for name, wanted, allowed in (("start_speed", x_start, cap[0]),
                                      ("end_speed", x_end, cap[-1])):  # fmt: skip
            if wanted > allowed * (1 + LIMIT_RTOL):
                raise InfeasibleError(
                    f"{name} {np.sqrt(wanted):g} breaks the limits there: at most "
                    f"{np.sqrt(allowed):.6g} (path parameter per second)"
                )
        if x_start > reach[0] * (1 + LIMIT_RTOL):
            raise InfeasibleError(
                f"start_speed {np.sqrt(x_start):g} is too fast to keep the limits along the path"
            )
        if last < x_end * (1 - LIMIT_RTOL):
            raise InfeasibleError(
                f"end_speed {np.sqrt(x_end):g} is too fast to reach within the limits: at most "
                f"{np.sqrt(last):.6g} (path parameter per second)"
            )
        stuck = np.flatnonzero(stuck_stages)
        if stuck.size and not self._exact[stuck].all():
            # A stage with no u between its rows at the x it was given: its own
            # maximum velocity curve, from all pairs of rows, and solve again.
            pick = stuck[~self._exact[stuck]]
            exact = _maximum_velocity_curve(*(r[pick] for r in self._rows))
            self.acceleration_cap[pick] = np.minimum(self.acceleration_cap[pick], exact)
            self._exact[pick] = True
            return self.solve(x_start, x_end, velocity_factor, acceleration_scale)
        return x


def _maximum_velocity_curve(
    valid: FloatArray,
    r: FloatArray,
    hi: FloatArray,
    lo: FloatArray,
    d1: FloatArray,
    d2: FloatArray,
    acc_lo: FloatArray,
    acc_hi: FloatArray,
    threshold: FloatArray,
) -> FloatArray:
    """The largest x at each grid point with ``max_j L_j(x) <= min_k U_k(x)``.

    ``L_j = lo_j + r_j x`` and ``U_k = hi_k + r_k x`` are the rows' bounds on u (of
    the valid rows); a row whose u term is below ``threshold`` (a still channel)
    bounds x itself, ``acc_lo <= d2 x <= acc_hi``. Every pair of rows, compiled.
    """
    from trajkit.time_optimal import _passes

    shape = np.shape(r)
    arrays = (np.ascontiguousarray(np.broadcast_to(value, shape), dtype=dtype)
              for value, dtype in ((valid, np.bool_), (r, float), (hi, float), (lo, float),
                                   (d1, float), (d2, float), (acc_lo, float), (acc_hi, float),
                                   (threshold, float)))  # fmt: skip
    return _passes.maximum_velocity_curve(*arrays)


def recurrence(a: FloatArray, b: FloatArray, high: FloatArray, y0: float) -> FloatArray:
    """``y_{k+1} = clip(min_j (a_kj y_k + b_kj), 0, high_k)`` for every stage ``k``.

    Parameters
    ----------
    a, b : ndarray, shape (n, m)
        The terms of each stage; a term with ``b = inf`` never binds.
    high : ndarray, shape (n,)
        Each stage's upper clip; ``y_k`` lies in ``[0, high_{k-1}]``.
    y0 : float
        The value entering the first stage.

    Returns
    -------
    ndarray, shape (n,)
        ``y_1 ... y_n``.

    Notes
    -----
    Sequential along the path, so one compiled loop over the stages, each through
    all of its lines (a few dozen): no Python loop per stage.
    """
    from trajkit.time_optimal import _passes

    as_array = np.ascontiguousarray
    return _passes.recurrence(as_array(a, dtype=np.float64), as_array(b, dtype=np.float64),
                              as_array(high, dtype=np.float64), float(y0))  # fmt: skip
