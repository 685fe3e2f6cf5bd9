"""Closed forms of the acceleration-limited (infinite-jerk) one-axis move.

A move from velocity ``v0`` to ``vf`` over the signed distance ``D`` is three
phases: constant acceleration ``a1`` up to the peak velocity ``vp``, a coast at
``vp``, constant acceleration ``a3`` to ``vf``. With ``a1 = s1 * A`` and
``a3 = s3 * A`` (signs fixed by whether the velocity rises or falls), the duration
for a given ``vp`` is

    T(vp) = c2 vp + b + c0 / vp,   c2 = 1/(2 a1) - 1/(2 a3),
    b = vf / a3 - v0 / a1,         c0 = D + v0^2 / (2 a1) - vf^2 / (2 a3),

and the coast lasts ``(c0 - c2 vp^2) / vp``. Every function here is vectorized
over the broadcast shape of its arguments; candidate solutions stack on a new last
axis and the best valid one is chosen per element, with no Python loop per move.

Limits are magnitudes: ``vpos`` (upper velocity), ``vneg`` (minus the lower
velocity bound), ``apos``, ``aneg`` likewise, all > 0.
"""

from __future__ import annotations

from functools import cached_property

import numpy as np

from trajkit._validation import FloatArray

__all__ = ["Phases", "duration_candidates", "fixed_duration", "minimum_time"]

# Slack on the validity tests of the closed forms (relative), so that a profile
# exactly at a limit is not rejected for its last bit of rounding.
_SLACK = 1e-12

# The four (s1, s3) sign patterns: rise-fall, fall-rise, rise-rise, fall-fall.
_S1 = np.array([1.0, -1.0, 1.0, -1.0])
_S3 = np.array([-1.0, 1.0, 1.0, -1.0])


class Phases:
    """Three phases per move: durations ``t1, t2, t3``, accelerations ``a1, a3``, ``vp``."""

    __slots__ = ("a1", "a3", "t1", "t2", "t3", "valid", "vp")

    def __init__(self, t1, t2, t3, a1, a3, vp, valid) -> None:
        self.t1, self.t2, self.t3 = t1, t2, t3
        self.a1, self.a3, self.vp = a1, a3, vp
        self.valid = valid

    @property
    def duration(self) -> FloatArray:
        return self.t1 + self.t2 + self.t3

    def pick(self, index: FloatArray) -> Phases:
        """Select candidate ``index`` along the last axis of every field."""
        take = lambda x: np.take_along_axis(x, index[..., np.newaxis], axis=-1)[..., 0]  # noqa: E731
        return Phases(
            *(take(getattr(self, n)) for n in ("t1", "t2", "t3", "a1", "a3", "vp", "valid"))
        )


def _accelerations(apos, aneg):
    a1 = np.where(_S1 > 0, apos[..., np.newaxis], -aneg[..., np.newaxis])
    a3 = np.where(_S3 > 0, apos[..., np.newaxis], -aneg[..., np.newaxis])
    return a1, a3


def _quadratic_terms(D, v0, vf, a1, a3):
    """``c2`` and ``c0`` of the module docstring, per sign pattern (last axis)."""
    c2 = 1.0 / (2 * a1) - 1.0 / (2 * a3)
    c0 = (
        D[..., np.newaxis]
        + v0[..., np.newaxis] ** 2 / (2 * a1)
        - vf[..., np.newaxis] ** 2 / (2 * a3)
    )
    return c2, c0


def _phases(D, v0, vf, vp, a1, a3, vpos, vneg, extra_valid) -> Phases:
    """Phase times of candidate peak velocities ``vp`` (last axis = candidates)."""
    D, v0, vf = D[..., np.newaxis], v0[..., np.newaxis], vf[..., np.newaxis]
    vpos, vneg = vpos[..., np.newaxis], vneg[..., np.newaxis]
    scale = np.maximum(np.maximum(np.abs(v0), np.abs(vf)), np.maximum(vpos, vneg))
    with np.errstate(divide="ignore", invalid="ignore"):
        t1 = (vp - v0) / a1
        t3 = (vf - vp) / a3
        coast_distance = D - (vp**2 - v0**2) / (2 * a1) - (vf**2 - vp**2) / (2 * a3)
        t2 = np.where(vp != 0, coast_distance / vp, 0.0)
    tiny_t = _SLACK * (np.abs(t1) + np.abs(t3) + np.abs(np.nan_to_num(t2)) + 1e-300)
    valid = (
        extra_valid
        & np.isfinite(vp)
        & (t1 >= -tiny_t)
        & (t3 >= -tiny_t)
        & (t2 >= -tiny_t)
        & (vp <= vpos + _SLACK * scale)
        & (vp >= -vneg - _SLACK * scale)
    )
    fields = np.broadcast_arrays(
        np.maximum(t1, 0.0), np.maximum(np.nan_to_num(t2), 0.0), np.maximum(t3, 0.0),
        a1, a3, np.clip(vp, -vneg, vpos), valid,
    )  # fmt: skip
    return Phases(*fields)


def minimum_time(D, v0, vf, vpos, vneg, apos, aneg) -> Phases:
    """Time-optimal phases (bang-coast-bang) for every move.

    Candidates: coast at either velocity limit, or no coast with the peak velocity
    solving ``c2 vp^2 = c0`` for the rise-fall and fall-rise patterns.
    """
    a1, a3 = _accelerations(apos, aneg)
    c2, c0 = _quadratic_terms(D, v0, vf, a1, a3)
    with np.errstate(divide="ignore", invalid="ignore"):
        root = np.sqrt(np.where(c2 != 0, c0 / c2, np.nan))
    # Rise-fall and fall-rise (columns 0, 1), each with both roots, plus the two coasts.
    vp = np.concatenate(
        [root[..., :2], -root[..., :2], vpos[..., np.newaxis], -vneg[..., np.newaxis]], axis=-1
    )
    pattern = np.array([0, 1, 0, 1, 0, 1])
    coast = np.array([False, False, False, False, True, True])
    phases = _phases(
        D, v0, vf, vp, a1[..., pattern], a3[..., pattern], vpos, vneg,
        extra_valid=np.ones(6, bool),
    )  # fmt: skip
    # Without a coast the peak comes from the closed form: drop the coast time it
    # leaves as rounding; with a coast the coast time is the unknown.
    phases.t2 = np.where(coast, phases.t2, 0.0)
    duration = np.where(phases.valid, phases.duration, np.inf)
    return phases.pick(np.argmin(duration, axis=-1))


def duration_candidates(D, v0, vf, vpos, vneg, apos, aneg) -> FloatArray:
    """Durations at which a move's set of reachable durations may resume after a gap.

    With accelerations at their limits, each sign pattern and sign of ``vp`` gives
    an interval of valid peak velocities on which ``T(vp)`` is continuous; its
    smallest duration lies at an end of that interval or where ``dT/dvp = 0``, and
    both are among ``v0, vf, vpos, -vneg, +-sqrt(c0 / c2)``. Returns the valid
    durations at those points, shape ``(..., K)``, ``inf`` where invalid. (With
    nonzero boundary velocities some durations cannot be met exactly: the next
    reachable one is among these.)
    """
    a1, a3 = _accelerations(apos, aneg)
    c2, c0 = _quadratic_terms(D, v0, vf, a1, a3)
    with np.errstate(divide="ignore", invalid="ignore"):
        root = np.sqrt(np.where((c2 != 0) & (c0 / c2 > 0), c0 / c2, np.nan))
    shared = np.stack([v0, vf, vpos, -vneg], axis=-1)  # (..., 4)
    points = []
    for pattern in range(4):
        vp = np.concatenate([shared, root[..., [pattern]], -root[..., [pattern]]], axis=-1)
        count = vp.shape[-1]
        phases = _phases(
            D, v0, vf, vp,
            np.repeat(a1[..., [pattern]], count, axis=-1),
            np.repeat(a3[..., [pattern]], count, axis=-1),
            vpos, vneg, extra_valid=np.ones(count, bool),
        )  # fmt: skip
        points.append(np.where(phases.valid & (vp != 0), phases.duration, np.inf))
    return np.concatenate(points, axis=-1)


def fixed_duration(T, D, v0, vf, vpos, vneg, apos, aneg) -> Phases:
    """Phases that take exactly ``T`` with accelerations at their limits.

    Solves ``c2 vp^2 + (b - T) vp + c0 = 0`` for every sign pattern and keeps the
    valid root of smallest ``|vp|`` (the gentlest motion: lowest peak speed). A
    standstill (``vp = 0``) is a candidate when the two velocity changes alone
    cover ``D``. ``valid`` is False where no profile takes exactly ``T``.
    """
    a1, a3 = _accelerations(apos, aneg)
    T_ = T[..., np.newaxis]
    D_, v0_, vf_ = D[..., np.newaxis], v0[..., np.newaxis], vf[..., np.newaxis]
    c2 = 1.0 / (2 * a1) - 1.0 / (2 * a3)
    c1 = vf_ / a3 - v0_ / a1 - T_
    c0 = D_ + v0_**2 / (2 * a1) - vf_**2 / (2 * a3)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        disc = np.sqrt(np.where(c1**2 - 4 * c2 * c0 >= 0, c1**2 - 4 * c2 * c0, np.nan))
        # Numerically stable quadratic roots; linear when c2 == 0.
        q = -0.5 * (c1 + np.copysign(disc, c1))
        root_a = np.where(c2 != 0, q / c2, -c0 / c1)
        root_b = np.where(c2 != 0, c0 / q, np.nan)
    vp = np.concatenate([root_a, root_b], axis=-1)
    a1c = np.concatenate([a1, a1], axis=-1)
    a3c = np.concatenate([a3, a3], axis=-1)
    phases = _phases(D, v0, vf, vp, a1c, a3c, vpos, vneg, extra_valid=np.ones(8, bool))
    # The coast time is what is left of T: exact total, no rounding drift.
    with np.errstate(invalid="ignore"):
        phases.t2 = np.maximum(T_ - phases.t1 - phases.t3, 0.0)
    phases.valid &= phases.t1 + phases.t3 <= T_ * (1 + _SLACK)
    # Standstill candidate: stop, wait, start again.
    stop_a1 = np.where(v0 > 0, -aneg, apos)
    stop_a3 = np.where(vf > 0, apos, -aneg)
    t1 = np.abs(v0) / np.abs(stop_a1)
    t3 = np.abs(vf) / np.abs(stop_a3)
    covered = v0 * t1 / 2 + vf * t3 / 2
    scale = np.abs(D) + np.abs(covered) + 1e-300
    still_ok = (np.abs(covered - D) <= 1e-12 * scale) & (t1 + t3 <= T * (1 + _SLACK))
    shape = phases.t1.shape[:-1]
    column = lambda x: np.broadcast_to(x, shape)[..., np.newaxis]  # noqa: E731
    still = Phases(
        column(t1), column(np.maximum(T - t1 - t3, 0.0)), column(t3),
        column(stop_a1), column(stop_a3), column(np.zeros_like(t1)), column(still_ok),
    )  # fmt: skip
    merged = Phases(
        *(np.concatenate([getattr(phases, n), getattr(still, n)], axis=-1)
          for n in ("t1", "t2", "t3", "a1", "a3", "vp", "valid"))
    )  # fmt: skip
    gentleness = np.where(merged.valid, np.abs(merged.vp), np.inf)
    return merged.pick(np.argmin(gentleness, axis=-1))


def fixed_duration_general(T, D, v0, vf, vpos, vneg, apos, aneg) -> Phases:
    """Phases that take exactly ``T`` with any accelerations within the limits.

    :func:`fixed_duration` keeps the accelerations at their limits; with moving
    boundaries some durations need gentler ones. For a peak velocity ``u`` the
    rise and fall times ``(t1, t3)`` must satisfy

        t1 (v0 - u) / 2 + t3 (vf - u) / 2 = D - u T,
        t1 >= m1 = |u - v0| / A1,  t3 >= m3 = |vf - u| / A3,  t1 + t3 <= T,

    a line through a triangle: feasible when ``D - u T`` lies between the values
    of the left side at the triangle's corners. The feasible ``u`` form intervals
    whose ends solve "left side at a corner = D - u T" or ``m1 + m3 = T`` (one
    quadratic and three linear equations per sign pattern); the gentlest profile
    (smallest ``|u|``) is at such an end or at ``u = 0``. For each candidate ``u``
    the rise time is taken as short as the line and the triangle allow.
    """
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        return _fixed_duration_general(T, D, v0, vf, vpos, vneg, apos, aneg)


def _fixed_duration_general(T, D, v0, vf, vpos, vneg, apos, aneg) -> Phases:
    T = np.asarray(T, dtype=float)
    e = lambda x: np.asarray(x, dtype=float)[..., np.newaxis]  # noqa: E731
    T_, D_, v0_, vf_ = e(T), e(D), e(v0), e(vf)
    vpos_, vneg_, apos_, aneg_ = e(vpos), e(vneg), e(apos), e(aneg)
    roots = []
    for s1 in (1.0, -1.0):
        A1 = apos_ if s1 > 0 else aneg_
        for s3 in (1.0, -1.0):
            A3 = apos_ if s3 > 0 else aneg_
            # Corner 1 (both accelerations at the limit): quadratic.
            c2 = s1 / (2 * A1) - s3 / (2 * A3) + 0 * T_
            c1 = -T_ - s1 * v0_ / A1 + s3 * vf_ / A3
            c0 = D_ + s1 * v0_**2 / (2 * A1) - s3 * vf_**2 / (2 * A3)
            with np.errstate(divide="ignore", invalid="ignore"):
                disc = c1**2 - 4 * c2 * c0
                sq = np.sqrt(np.where(disc >= 0, disc, np.nan))
                q = -0.5 * (c1 + np.copysign(sq, c1))
                roots += [np.where(c2 != 0, q / c2, -c0 / c1), np.where(c2 != 0, c0 / q, np.nan)]
                # Corner 2 (rise takes the rest, fall at the limit): linear.
                k = -T_ / 2 + s3 * (vf_ - v0_) / (2 * A3)
                roots.append(-(D_ - T_ * v0_ / 2 - s3 * vf_ * (vf_ - v0_) / (2 * A3)) / k)
                # Corner 3 (rise at the limit, fall takes the rest): linear.
                k = -T_ / 2 + s1 * (v0_ - vf_) / (2 * A1)
                roots.append(-(D_ - T_ * vf_ / 2 + s1 * v0_ * (v0_ - vf_) / (2 * A1)) / k)
                # No coast at both limits: m1 + m3 = T.
                roots.append((T_ + s1 * v0_ / A1 - s3 * vf_ / A3) / (s1 / A1 - s3 / A3))
    fixed = [0 * T_ + 0 * D_, v0_ + 0 * T_, vf_ + 0 * T_, vpos_ + 0 * T_, -vneg_ + 0 * T_]
    shape = np.broadcast_shapes(*(r.shape for r in roots + fixed))
    u = np.concatenate([np.broadcast_to(r, shape) for r in roots + fixed], axis=-1)
    u = np.where(np.isfinite(u), u, np.nan)
    A1 = np.where(u >= v0_, apos_, aneg_)
    A3 = np.where(vf_ >= u, apos_, aneg_)
    m1 = np.abs(u - v0_) / A1
    m3 = np.abs(vf_ - u) / A3
    g = D_ - u * T_
    alpha = (v0_ - u) / 2
    beta = (vf_ - u) / 2
    scale = np.abs(D_) + (np.abs(u) + np.abs(v0_) + np.abs(vf_)) * T_ + 1e-300
    best = None
    with np.errstate(divide="ignore", invalid="ignore"):
        options = (
            (m1, (g - alpha * m1) / beta),
            (T_ - m3, (g - alpha * (T_ - m3)) / beta),
            ((g - beta * m3) / alpha, m3),
            ((g - beta * T_) / (alpha - beta), T_ - (g - beta * T_) / (alpha - beta)),
        )
        for t1, t3 in options:
            residual = np.abs(alpha * t1 + beta * t3 - g)
            ok = (
                np.isfinite(t1) & np.isfinite(t3) & np.isfinite(u)
                & (t1 >= m1 * (1 - _SLACK) - 1e-15 * T_)
                & (t3 >= m3 * (1 - _SLACK) - 1e-15 * T_)
                & (t1 + t3 <= T_ * (1 + _SLACK))
                & (residual <= 1e-9 * scale)
                & (u <= vpos_ * (1 + _SLACK)) & (u >= -vneg_ * (1 + _SLACK))
            )  # fmt: skip
            t1c, t3c = np.clip(t1, 0, None), np.clip(t3, 0, None)
            a1 = np.where(t1c > 0, (u - v0_) / t1c, 0.0)
            a3 = np.where(t3c > 0, (vf_ - u) / t3c, 0.0)
            candidate = Phases(
                *np.broadcast_arrays(t1c, np.clip(T_ - t1c - t3c, 0, None), t3c, a1, a3, u, ok)
            )
            if best is None:
                best = candidate
            else:
                take = ~best.valid & candidate.valid
                best = Phases(
                    *(np.where(take, getattr(candidate, n), getattr(best, n))
                      for n in ("t1", "t2", "t3", "a1", "a3", "vp", "valid"))
                )  # fmt: skip
    gentleness = np.where(best.valid, np.abs(best.vp), np.inf)
    return best.pick(np.argmin(gentleness, axis=-1))


def _direction_limits(D, vpos, vneg, apos, aneg):
    """Speed, rise and fall acceleration limits in each move's direction."""
    if vpos is vneg and apos is aneg:  # symmetric limits: no selection needed
        return vpos, apos, aneg
    forward = D >= 0
    return (
        np.where(forward, vpos, vneg),
        np.where(forward, apos, aneg),
        np.where(forward, aneg, apos),
    )


def rest_plan(D, vpos, vneg, apos, aneg):
    """Shortest durations of moves at rest at both ends, and their phases for any ``T``.

    The rise and fall at full acceleration cover ``k vp^2`` with
    ``k = 1/(2 A_rise) + 1/(2 A_fall)``. Fastest: ``vp = min(V, sqrt(d / k))`` and
    the duration ``k vp + d / vp``. Exactly ``T`` (time synchronization): the
    lowest peak speed that fits, ``vp = 2 d / (T + sqrt(T^2 - 4 k d))`` (the
    gentlest profile; at the minimum duration, the fastest one).

    Returns ``(durations, phases_at)``; ``phases_at(T)`` gives :class:`RestPhases`.
    The shared terms are computed once: this is the batch planner's hot path.
    """
    speed, rise, fall = _direction_limits(D, vpos, vneg, apos, aneg)
    d = np.abs(D)
    k = 0.5 / rise + 0.5 / fall
    vp = np.sqrt(d / k)
    np.minimum(vp, speed, out=vp)
    duration = np.divide(d, vp, out=np.zeros_like(vp), where=vp > 0)
    duration += k * vp

    def phases_at(T: FloatArray) -> RestPhases:
        root = T * T - 4.0 * k * d
        np.maximum(root, 0.0, out=root)
        np.sqrt(root, out=root)
        root += T
        peak = np.divide(2.0 * d, root, out=np.zeros_like(root), where=root > 0)
        np.minimum(peak, speed, out=peak)
        # At the minimum duration the root is double and its square root amplifies
        # rounding to ~1e-8: the fastest peak is known exactly there.
        np.copyto(peak, vp, where=T <= duration * (1 + 1e-12))
        return RestPhases(D, peak, rise, fall, np.broadcast_to(T, peak.shape))

    return duration, phases_at


class RestPhases:
    """Phases of moves at rest at both ends, computed field by field on first use.

    Holds the peak speed magnitude ``speed`` and the limits; ``t1 ... vp`` follow
    the :class:`Phases` attributes. Planning many moves needs only the durations,
    so the rest waits until someone asks.
    """

    def __init__(self, D, speed, rise, fall, T) -> None:
        self._D, self._speed, self._rise, self._fall, self._T = D, speed, rise, fall, T

    @cached_property
    def t1(self) -> FloatArray:
        return self._speed / self._rise

    @cached_property
    def t3(self) -> FloatArray:
        return self._speed / self._fall

    @cached_property
    def t2(self) -> FloatArray:
        return np.maximum(self._T - self.t1 - self.t3, 0.0)

    @cached_property
    def _sign(self) -> FloatArray:
        return np.sign(self._D)

    @cached_property
    def a1(self) -> FloatArray:
        return self._sign * self._rise

    @cached_property
    def a3(self) -> FloatArray:
        return -self._sign * self._fall

    @cached_property
    def vp(self) -> FloatArray:
        return self._sign * self._speed

    @cached_property
    def valid(self) -> FloatArray:
        return np.ones(np.shape(self._D), bool)

    @property
    def duration(self) -> FloatArray:
        return self.t1 + self.t2 + self.t3

    def transposed(self) -> RestPhases:
        """The same phases with the two axes swapped (views, no copies)."""
        swap = lambda x: np.broadcast_to(x, self._speed.shape).T  # noqa: E731
        return RestPhases(
            *(swap(x) for x in (self._D, self._speed, self._rise, self._fall, self._T))
        )
