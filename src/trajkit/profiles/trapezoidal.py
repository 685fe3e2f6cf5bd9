"""Trapezoidal / triangular (LSPB) velocity profiles under velocity and acceleration limits.

The vectorized cores here serve both :func:`trapezoidal` (one N-DoF move) and
:mod:`trajkit.batch` (many moves at once): arrays carry any leading axes and the
joints on the last axis.
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from trajkit._periods import whole_periods
from trajkit._validation import (
    FloatArray,
    choice,
    count_dof,
    finite_array,
    finite_result,
    flag,
    joint_vector,
    positive_scalar,
)
from trajkit.errors import InfeasibleError, InvalidInputError
from trajkit.limits import LimitSpec, parse_bounds
from trajkit.profiles import _trapezoid_math as math
from trajkit.profiles._phases import PhasePlan, plan_info, plan_to_trajectory
from trajkit.profiles._sync import common_duration
from trajkit.trajectory import Trajectory

__all__ = ["Sync", "TrapezoidSolution", "solve_trapezoid", "trapezoidal"]

Sync = Literal["time", "phase"] | None
SYNC_MODES = ("time", "phase", None)


class TrapezoidSolution:
    """Arrays of a solved (batch of) trapezoid problem(s); joints on the last axis.

    ``times`` and ``accelerations`` have a trailing phase axis of 3 (rise, coast,
    fall); ``duration`` is the common duration, ``own`` each joint's minimum alone,
    ``limiting`` the joint whose minimum sets ``duration`` (-1 under phase sync,
    where all joints share one time law). Built from ``phases`` on first use when
    not given: batch planning returns before any of them is needed.
    """

    __slots__ = (
        "_accelerations", "_joint_major", "_limiting", "_peak", "_phases", "_times", "duration",
        "own",
    )  # fmt: skip

    def __init__(
        self,
        times: FloatArray | None,
        accelerations: FloatArray | None,
        peak_velocity: FloatArray | None,
        duration: FloatArray,
        own: FloatArray,
        limiting: FloatArray | None,
        phases: math.Phases | None = None,
        joint_major: bool = False,
    ) -> None:
        # ``joint_major``: ``phases`` holds (ndof, ...) arrays (batch planning's layout);
        # the properties still present joints on the last axis, as transposed views.
        self._joint_major = joint_major
        self._times, self._accelerations, self._peak = times, accelerations, peak_velocity
        self.duration, self.own = duration, own
        self._limiting, self._phases = limiting, phases

    def _build(self) -> None:
        times, accelerations = _stack(self._phases)
        peak = self._phases.vp
        if self._joint_major:
            times, accelerations, peak = (
                np.swapaxes(x, 0, 1) for x in (times, accelerations, peak)
            )
        self._times, self._accelerations, self._peak = times, accelerations, peak

    @property
    def times(self) -> FloatArray:
        """Phase durations (s), shape ``(..., ndof, 3)``."""
        if self._times is None:
            self._build()
        return self._times

    @property
    def accelerations(self) -> FloatArray:
        """Phase accelerations, shape ``(..., ndof, 3)`` (the coast's is 0)."""
        if self._accelerations is None:
            self._build()
        return self._accelerations

    @property
    def peak_velocity(self) -> FloatArray:
        """Signed coast (peak) velocity of every joint."""
        if self._peak is None:
            self._build()
        return self._peak

    @property
    def limiting(self) -> FloatArray:
        """Index of the joint whose own minimum is the longest."""
        if self._limiting is None:
            self._limiting = np.argmax(self.own, axis=-1)
        return self._limiting


def _stack(phases: math.Phases) -> tuple[FloatArray, FloatArray]:
    times = np.stack([phases.t1, phases.t2, phases.t3], axis=-1)
    accelerations = np.stack([phases.a1, np.zeros_like(phases.a1), phases.a3], axis=-1)
    return times, accelerations


def _exact_duration(T: FloatArray, args: tuple[FloatArray, ...]) -> math.Phases:
    """Per-joint phases taking exactly ``T``.

    Accelerations stay at the limits where that works (the gentlest: lowest peak
    speed); gentler accelerations are used elsewhere.
    """
    phases = math.fixed_duration(T, *args)
    if not phases.valid.all():
        general = math.fixed_duration_general(T, *args)
        take = ~phases.valid & general.valid
        phases = math.Phases(
            *(np.where(take, getattr(general, n), getattr(phases, n)) for n in _PHASE_FIELDS)
        )
    # At a joint's own minimum the closed forms meet a double root (sqrt of rounding,
    # ~1e-8): the time-optimal phases are exact there.
    fastest = math.minimum_time(*args)
    at_minimum = fastest.valid & (np.abs(T - fastest.duration) <= 1e-12 * np.maximum(T, 1e-300))
    if np.any(at_minimum):
        shape = np.broadcast_shapes(phases.valid.shape, at_minimum.shape)
        phases = math.Phases(
            *(
                np.where(at_minimum, np.broadcast_to(getattr(fastest, n), shape),
                         np.broadcast_to(getattr(phases, n), shape))
                for n in _PHASE_FIELDS
            )
        )  # fmt: skip
    return phases


_PHASE_FIELDS = ("t1", "t2", "t3", "a1", "a3", "vp", "valid")


def _common_duration(T: FloatArray, args: tuple[FloatArray, ...]) -> tuple[FloatArray, math.Phases]:
    """Smallest duration >= ``T`` every joint can take exactly (see :func:`common_duration`).

    The trapezoid's profile families begin at known durations
    (:func:`math.duration_candidates`): they are tried first.
    """
    return common_duration(T, args, _exact_duration, math.duration_candidates)


def _at_rest(velocity: FloatArray) -> bool:
    """All zero; a broadcast view is tested through its base, without a full pass."""
    base = velocity
    while isinstance(base, np.ndarray) and base.base is not None and base.strides.count(0):
        base = base.base
    return not np.any(base if base.size < velocity.size else velocity)


def solve_trapezoid(
    distance: FloatArray,
    v0: FloatArray,
    vf: FloatArray,
    vpos: FloatArray,
    vneg: FloatArray,
    apos: FloatArray,
    aneg: FloatArray,
    sync: Sync,
    duration: FloatArray | None = None,
) -> TrapezoidSolution:
    """Vectorized trapezoid planning; every argument ``(..., ndof)`` except ``duration``.

    ``duration`` (shape ``(...)``) asks for that exact common duration instead of
    the shortest; it must be at least the shortest (the caller checks).
    """
    args = (distance, v0, vf, vpos, vneg, apos, aneg)
    if sync == "phase":
        return _solve_phase_synchronized(*args, duration=duration)
    if _at_rest(v0) and _at_rest(vf):
        return _solve_rest_to_rest(distance, vpos, vneg, apos, aneg, sync, duration)
    fastest = math.minimum_time(*args)
    own = fastest.duration
    limiting = np.argmax(own, axis=-1)
    if sync is None and duration is None:
        times, accelerations = _stack(fastest)
        return TrapezoidSolution(times, accelerations, fastest.vp, own.max(-1), own, limiting)
    T = own.max(axis=-1) if duration is None else duration
    T, phases = _common_duration(T, args)
    times, accelerations = _stack(phases)
    return TrapezoidSolution(times, accelerations, phases.vp, T, own, limiting)


# Distances below this are no motion for the shared time law of phase sync: the
# law's limits (limit / distance) would overflow. It is far below any resolution.
_NEGLIGIBLE = 1e-150


def _phase_law(
    distance: FloatArray,
    v0: FloatArray,
    vf: FloatArray,
    vpos: FloatArray,
    vneg: FloatArray,
    apos: FloatArray,
    aneg: FloatArray,
) -> tuple[FloatArray, ...]:
    """Problem of the shared time law ``s: 0 -> 1`` of a phase-synchronized move.

    Every joint follows ``q0 + D s(t)``, so ``s`` must respect each joint's limits
    divided by its distance (for a negative distance the lower and upper bounds
    swap): the tightest of them are the law's limits. Boundary velocities must be
    ``v0 = D s'(0)`` and ``vf = D s'(T)``. Returns the law's ``(D, v0, vf, vpos,
    vneg, apos, aneg)`` with the joint axis dropped (distance 0 when nothing moves).
    """
    moving = np.abs(distance) > _NEGLIGIBLE
    with np.errstate(divide="ignore", invalid="ignore"):
        s_v0 = np.where(moving, v0 / distance, -np.inf).max(axis=-1)
        s_vf = np.where(moving, vf / distance, -np.inf).max(axis=-1)
    s_v0 = np.where(np.isfinite(s_v0), s_v0, 0.0)
    s_vf = np.where(np.isfinite(s_vf), s_vf, 0.0)
    scale = np.maximum(np.abs(v0), np.abs(vf)).max(axis=-1, initial=0.0) + 1e-300
    off_line = np.maximum(
        np.abs(s_v0[..., np.newaxis] * distance - v0), np.abs(s_vf[..., np.newaxis] * distance - vf)
    ).max(axis=-1)
    if np.any(off_line > 1e-9 * scale):
        raise InvalidInputError(
            "sync='phase' needs boundary velocities parallel to the move (v0 and vf "
            "proportional to qf - q0, joint by joint); use sync='time' otherwise"
        )
    magnitude = np.where(moving, np.abs(distance), 1.0)
    positive = distance > 0
    limits = []
    for up, down in ((vpos, vneg), (apos, aneg)):
        # A joint that does not move puts no bound on the law.
        for along, against in ((up, down), (down, up)):
            ratio = np.where(moving, np.where(positive, along, against) / magnitude, np.inf)
            limits.append(ratio.min(axis=-1))
    still = ~moving.any(axis=-1)
    # Nothing moves: any positive limits will do for the (empty) law.
    limits = [np.where(still, 1.0, limit) for limit in limits]
    s_vpos, s_vneg, s_apos, s_aneg = limits
    return (np.where(still, 0.0, 1.0), s_v0, s_vf, s_vpos, s_vneg, s_apos, s_aneg)


def _law_distance(distance: FloatArray) -> FloatArray:
    """Each joint's share of the shared time law (negligible distances count as 0)."""
    return np.where(np.abs(distance) > _NEGLIGIBLE, distance, 0.0)


def _scale_law(
    law_times: FloatArray, law_acc: FloatArray, law_vp: FloatArray, distance: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Joint phases from the shared law's phases (law arrays have no joint axis)."""
    distance = _law_distance(distance)
    times = np.broadcast_to(law_times[..., np.newaxis, :], (*distance.shape, 3)).copy()
    accelerations = law_acc[..., np.newaxis, :] * distance[..., np.newaxis]
    return times, accelerations, law_vp[..., np.newaxis] * distance


def _solve_rest_to_rest(
    distance: FloatArray,
    vpos: FloatArray,
    vneg: FloatArray,
    apos: FloatArray,
    aneg: FloatArray,
    sync: Sync,
    duration: FloatArray | None,
) -> TrapezoidSolution:
    """All closed forms: at rest at both ends every duration above the minimum works."""
    own, phases_at = math.rest_plan(distance, vpos, vneg, apos, aneg)
    if sync is None and duration is None:
        T, target = own.max(axis=-1), own
    else:
        T = own.max(axis=-1) if duration is None else np.asarray(duration, dtype=float)
        target = T[..., np.newaxis]
    return TrapezoidSolution(None, None, None, T, own, None, phases=phases_at(target))


def _solve_phase_synchronized(*args: FloatArray, duration: FloatArray | None) -> TrapezoidSolution:
    """All joints follow one time law: see :func:`_phase_law`."""
    distance = args[0]
    law_args = _phase_law(*args)
    own = math.minimum_time(*args).duration
    if duration is None:
        law = math.minimum_time(*law_args)
        T = law.duration
    else:
        T, law = _common_duration(duration, tuple(a[..., np.newaxis] for a in law_args))
        law = math.Phases(
            *(getattr(law, n)[..., 0] for n in ("t1", "t2", "t3", "a1", "a3", "vp", "valid"))
        )
    law_times, law_acc = _stack(law)
    times, accelerations, peak = _scale_law(law_times, law_acc, law.vp, distance)
    return TrapezoidSolution(times, accelerations, peak, T, own, np.full(T.shape, -1))


# Whole periods tried around each continuous rise and fall time (more above: a
# rise rounded down needs a longer fall or coast to keep the distance).
_OFFSETS = np.arange(-3, 9)
_MAX_EXTRA_PERIODS = 16  # how far past the continuous optimum a quantized duration is sought


def _integer_phases(
    steps: FloatArray, dt: float, args: tuple[FloatArray, ...], centers: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Phases whose durations are whole multiples of ``dt`` and sum to ``steps * dt``.

    Around two continuous profiles — the gentlest of duration ``steps * dt`` and
    the plan being quantized (``centers``: its rise and fall times) — nearby pairs
    of rise and fall step counts are tried; the coast takes the rest. For given
    step counts the peak velocity follows from the distance (it is linear in
    ``vp``), and the accelerations from the velocity changes. Returns ``valid``
    (leading shape + joints), ``times``, ``accelerations`` (..., 3) and ``vp``.
    """
    D, v0, vf, vpos, vneg, apos, aneg = args
    total = steps * dt
    with np.errstate(all="ignore"):
        smooth = _exact_duration(np.broadcast_to(total, D.shape), args)
    pairs = []
    for rise, fall in (
        (np.nan_to_num(smooth.t1), np.nan_to_num(smooth.t3)),
        (centers[..., 0], centers[..., 1]),
    ):
        up = np.round(np.broadcast_to(rise, D.shape) / dt)[..., np.newaxis, np.newaxis]
        down = np.round(np.broadcast_to(fall, D.shape) / dt)[..., np.newaxis, np.newaxis]
        pair = np.broadcast_arrays(up + _OFFSETS[:, np.newaxis], down + _OFFSETS[np.newaxis, :])
        pairs.append([x.reshape(*D.shape, -1) for x in pair])
    n1 = np.concatenate([pair[0] for pair in pairs], axis=-1)
    n3 = np.concatenate([pair[1] for pair in pairs], axis=-1)
    N = np.broadcast_to(steps, D.shape)[..., np.newaxis]
    n2 = N - n1 - n3
    e = lambda x: x[..., np.newaxis]  # noqa: E731
    with np.errstate(divide="ignore", invalid="ignore"):
        vp = (e(D) / dt - e(v0) * n1 / 2 - e(vf) * n3 / 2) / (n1 / 2 + n2 + n3 / 2)
        # A phase of zero steps cannot change the velocity.
        vp = np.where(n1 == 0, e(v0), np.where(n3 == 0, e(vf), vp))
        a1 = np.where(n1 > 0, (vp - e(v0)) / (n1 * dt), 0.0)
        a3 = np.where(n3 > 0, (e(vf) - vp) / (n3 * dt), 0.0)
    with np.errstate(invalid="ignore", over="ignore"):
        covered = dt * ((e(v0) + vp) / 2 * n1 + vp * n2 + (vp + e(vf)) / 2 * n3)
    slack = 1e-12
    speed = np.maximum(e(vpos), e(vneg))
    scale_d = np.abs(e(D)) + np.abs(covered) + 1e-300
    valid = (
        (n1 >= 0) & (n3 >= 0) & (n2 >= 0)
        & np.isfinite(vp)
        & (np.abs(covered - e(D)) <= 1e-9 * scale_d)
        # With no rise (fall) the peak must already be the start (end) velocity.
        & ((n1 > 0) | (np.abs(vp - e(v0)) <= 1e-12 * speed))
        & ((n3 > 0) | (np.abs(vp - e(vf)) <= 1e-12 * speed))
        & (vp <= e(vpos) * (1 + slack)) & (vp >= -e(vneg) * (1 + slack))
        & (a1 <= e(apos) * (1 + slack)) & (a1 >= -e(aneg) * (1 + slack))
        & (a3 <= e(apos) * (1 + slack)) & (a3 >= -e(aneg) * (1 + slack))
    )  # fmt: skip
    choice = np.argmin(np.where(valid, np.abs(vp), np.inf), axis=-1)[..., np.newaxis]
    pick = lambda x: np.take_along_axis(x, choice, axis=-1)[..., 0]  # noqa: E731
    times = np.stack([pick(n1) * dt, pick(n2) * dt, pick(n3) * dt], axis=-1)
    accelerations = np.stack([pick(a1), np.zeros(D.shape), pick(a3)], axis=-1)
    return valid.any(axis=-1), times, accelerations, pick(vp)


def quantize_trapezoid(
    solution: TrapezoidSolution, dt: float, args: tuple[FloatArray, ...], sync: Sync
) -> TrapezoidSolution:
    """Re-plan so every switching time and the duration are whole multiples of ``dt``.

    Starts from the continuous optimum rounded up to the period and adds periods
    until whole-step phases exist that keep every limit (joint by joint for
    ``sync=None``; common to all joints otherwise). For moves at rest at both ends
    this takes at most one extra period, so the duration exceeds the continuous
    optimum by less than ``2 dt``.
    """
    if sync == "phase":
        law_args = tuple(a[..., np.newaxis] for a in _phase_law(*args))
        law_times, law_acc = _stack(math.minimum_time(*law_args))
        law = quantize_trapezoid(
            TrapezoidSolution(
                law_times, law_acc, None, None, np.asarray(solution.duration)[..., np.newaxis], None
            ),
            dt,
            law_args,
            sync=None,
        )
        times, accelerations, peak = _scale_law(
            law.times[..., 0, :], law.accelerations[..., 0, :], law.peak_velocity[..., 0], args[0]
        )
        return TrapezoidSolution(
            times, accelerations, peak, law.duration, solution.own, solution.limiting
        )
    per_joint = sync is None
    centers = solution.times[..., [0, 2]]
    target = solution.own if per_joint else solution.duration
    steps = whole_periods(target, dt)
    shape = args[0].shape
    times = np.zeros((*shape, 3))
    accelerations = np.zeros((*shape, 3))
    peak = np.zeros(shape)
    done = np.zeros(steps.shape, bool)
    for _ in range(_MAX_EXTRA_PERIODS):
        trial = steps if per_joint else steps[..., np.newaxis]
        valid, t, a, vp = _integer_phases(trial, dt, args, centers)
        ok = valid if per_joint else valid.all(axis=-1)
        new = ok & ~done
        mask = new if per_joint else np.broadcast_to(new[..., np.newaxis], shape)
        times[mask], accelerations[mask], peak[mask] = t[mask], a[mask], vp[mask]
        done |= ok
        if done.all():
            break
        steps = np.where(done, steps, steps + 1)
    else:
        raise InfeasibleError(
            f"no profile with phases in whole multiples of dt={dt:g} s keeps the limits "
            f"within {_MAX_EXTRA_PERIODS} periods of the continuous optimum"
        )
    duration = (steps.max(axis=-1) if per_joint else steps) * dt
    own = solution.own
    return TrapezoidSolution(times, accelerations, peak, duration, own, solution.limiting)


def _limit_magnitudes(
    name: str, spec: LimitSpec, ndof: int, unit: str
) -> tuple[FloatArray, FloatArray]:
    """``(upper, -lower)`` magnitudes of a symmetric or ``(lower, upper)`` limit."""
    bounds = parse_bounds(name, spec, quantity="velocity")
    if bounds is None:
        raise InvalidInputError(f"{name} is required ({unit})")
    lower, upper = bounds.for_ndof(name, ndof)
    if np.any(lower >= 0) or np.any(upper <= 0):
        raise InvalidInputError(f"{name} must allow motion both ways: lower < 0 < upper ({unit})")
    return np.array(upper, dtype=float), -np.array(lower, dtype=float)


def _read_sync(sync: object) -> Sync:
    return choice("sync", sync, SYNC_MODES)  # type: ignore[no-any-return]


def _check_boundary_velocities(
    name: str,
    values: FloatArray,
    vpos: FloatArray,
    vneg: FloatArray,
    label: str = "the velocity limit ",
    magnitude: bool = False,
) -> None:
    """Refuse a boundary velocity beyond its limit, naming the joint and the bound.

    The bound is the signed one it passes, or its ``magnitude`` for symmetric limits
    named as ``vmax``.
    """
    bad = np.flatnonzero((values > vpos) | (values < -vneg))
    if bad.size:
        j = bad[0]
        bound = vpos[j] if values[j] > 0 or magnitude else -vneg[j]
        raise InfeasibleError(
            f"{name}={values[j]:.6g} rad/s is beyond {label}{bound:.6g} rad/s (joint {j + 1})"
        )


def trapezoidal(
    q0: ArrayLike,
    qf: ArrayLike,
    vmax: LimitSpec = None,
    amax: LimitSpec = None,
    *,
    duration: float | None = None,
    blend_ratio: float | None = None,
    blend_time: float | None = None,
    v0: ArrayLike = 0.0,
    vf: ArrayLike = 0.0,
    sync: Sync = "time",
    dt: float | None = None,
    allow_overshoot: bool = True,
) -> Trajectory:
    """Trapezoidal (or triangular) velocity profile: linear segments with parabolic blends.

    Two ways to use it:

    * **Limits** (``vmax`` and ``amax``): the time-optimal bang-coast-bang profile of
      every joint, a triangle when the distance is too short to reach ``vmax``.
      ``duration`` asks for a longer, exact duration instead.
    * **Coursework rule** (``blend_ratio`` or ``blend_time``): rest to rest, every
      joint accelerates for ``t_b = blend_ratio * duration`` (or ``blend_time``),
      coasts, and decelerates for ``t_b``. With ``duration`` the limits are
      verified; without it, the shortest duration the rule allows is used.
      ``amax`` is optional here.

    Parameters
    ----------
    q0, qf : float or array_like, shape (ndof,)
        Start and end positions (rad, or m).
    vmax, amax : float, sequence or tuple
        Velocity (rad/s) and acceleration (rad/s^2) limits: a number or one per
        joint for symmetric limits, a tuple ``(lower, upper)`` for asymmetric ones.
    duration : float, optional
        Exact duration (s) for every joint.
    blend_ratio : float, optional
        ``t_b / duration``, in (0, 0.5].
    blend_time : float, optional
        ``t_b`` in s.
    v0, vf : float or array_like
        Boundary velocities (rad/s), within the velocity limits (limit mode only).
    sync : {"time", "phase", None}
        ``"time"``: all joints finish together at the slowest joint's minimum time;
        every other joint takes the common duration with its accelerations at the
        limit and the lowest peak velocity that fits (the gentlest profile).
        ``"phase"``: all joints follow one time law ``q0 + (qf - q0) s(t)``, so they
        move on a straight line in joint space and switch phases together; the law
        is the fastest one within every joint's limits (rest to rest, this is the
        coursework's common acceleration and total times, but never past a limit).
        ``None``: every joint moves as fast as it can on its own; the ones that
        finish early hold their end state (continuing at ``vf``).
    dt : float, optional
        Controller period (s): every switching time and the duration become whole
        multiples of it, all limits still hold (at most ``2 dt`` longer at rest).
    allow_overshoot : bool
        With ``False``, raise :class:`InfeasibleError` when the fastest profile
        leaves the interval between ``q0`` and ``qf`` (a boundary velocity that
        cannot be braked in time, or that points away from the target).

    Returns
    -------
    Trajectory
        Piecewise quadratic; ``info`` holds ``phase_times`` (per joint: rise,
        coast, fall in s), ``peak_velocity``, ``accelerations`` (rise, fall),
        ``minimum_durations`` (each joint alone) and ``limiting_joint``.

    Raises
    ------
    InvalidInputError
        Malformed input: NaN, wrong shapes, limits that are not > 0, a blend
        ratio outside (0, 0.5], an unknown sync mode.
    InfeasibleError
        A duration below the minimum (the message names the minimum and the
        limit that sets it), a boundary velocity beyond the limit, an overshoot
        that is not allowed.
    """
    ndof = count_dof(q0=q0, qf=qf, v0=v0, vf=vf)
    for name, spec in (("vmax", vmax), ("amax", amax)):
        if isinstance(spec, tuple):
            continue
        if spec is not None:
            ndof = max(ndof, count_dof(q0=q0, qf=qf, v0=v0, vf=vf, **{name: spec}))
    start = joint_vector("q0", q0, ndof, unit="rad")
    end = joint_vector("qf", qf, ndof, unit="rad")
    start_v = joint_vector("v0", v0, ndof, unit="rad/s")
    end_v = joint_vector("vf", vf, ndof, unit="rad/s")
    sync = _read_sync(sync)
    allow_overshoot = flag("allow_overshoot", allow_overshoot)
    step = None if dt is None else positive_scalar("dt", dt, unit="s")
    if blend_ratio is not None or blend_time is not None:
        if np.any(start_v) or np.any(end_v):
            raise InvalidInputError(
                "blend_ratio/blend_time describe rest-to-rest moves; v0 and vf must be 0"
            )
        return _blend_rule(start, end, vmax, amax, duration, blend_ratio, blend_time, step)
    if vmax is None or amax is None:
        raise InvalidInputError(
            "trapezoidal needs vmax and amax (or blend_ratio / blend_time with a duration)"
        )
    vpos, vneg = _limit_magnitudes("vmax", vmax, ndof, "rad/s")
    apos, aneg = _limit_magnitudes("amax", amax, ndof, "rad/s^2")
    _check_boundary_velocities("v0", start_v, vpos, vneg)
    _check_boundary_velocities("vf", end_v, vpos, vneg)
    arguments = {"q0": start, "qf": end, "v0": start_v, "vf": end_v, "vmax": vmax, "amax": amax}
    with np.errstate(over="ignore"):
        args = (end - start, start_v, end_v, vpos, vneg, apos, aneg)
    # Finite positions can still be an infinite move (qf=1e308, q0=-1e308).
    finite_result("trapezoidal", args[0], arguments)
    requested = None
    if duration is not None:
        requested = positive_scalar("duration", duration, unit="s")
        fastest = solve_trapezoid(*args, sync=sync if sync == "phase" else "time")
        if requested < fastest.duration * (1 - 1e-12):
            joint = int(fastest.limiting) if fastest.limiting >= 0 else int(np.argmax(fastest.own))
            # Name the bounds of the joint's direction of motion (the lower ones going down).
            speed = vpos[joint] if end[joint] >= start[joint] else -vneg[joint]
            brake = (
                f"{apos[joint]:.6g}"
                if apos[joint] == aneg[joint]
                else (f"({-aneg[joint]:.6g}, {apos[joint]:.6g})")
            )
            raise InfeasibleError(
                f"duration {requested:.6g} s is below the minimum {float(fastest.duration):.6g} s "
                f"set by vmax={speed:.6g} rad/s and amax={brake} rad/s^2 (joint {joint + 1})"
            )
        requested = max(requested, float(fastest.duration))
    solution = solve_trapezoid(
        *args,
        sync=sync if duration is None else (sync if sync == "phase" else "time"),
        duration=None if requested is None else np.array(requested),
    )
    if step is not None:
        solution = quantize_trapezoid(solution, step, args, sync if duration is None else "time")
    # A finite move can still take longer than float64 holds (vmax=1e-300 rad/s).
    finite_result("trapezoidal", solution.duration, {**arguments, "duration": duration})
    trajectory = _to_trajectory(start, start_v, solution, sync, step, target=(end, end_v))
    if requested is not None and float(solution.duration) > float(requested) * (1 + 1e-12):
        blocked = ~_exact_duration(np.asarray(requested)[..., np.newaxis], args).valid
        joint = int(np.flatnonzero(blocked)[0]) if blocked.any() else 0
        raise InfeasibleError(
            f"duration {float(requested):.6g} s cannot be met exactly: joint {joint + 1} cannot "
            f"take it with its boundary velocities; the next duration that works is "
            f"{float(solution.duration):.6g} s"
        )
    if not allow_overshoot:
        _refuse_overshoot(trajectory, start, end, start_v, end_v)
    return trajectory


def _to_trajectory(
    start: FloatArray,
    start_v: FloatArray,
    solution: TrapezoidSolution,
    sync: Sync,
    dt: float | None,
    extra: dict[str, object] | None = None,
    target: tuple[FloatArray, FloatArray] | None = None,
) -> Trajectory:
    # target: (qf, vf), the state the trajectory ends in exactly
    plan = PhasePlan(
        start, start_v, solution.times, solution.accelerations, np.zeros_like(solution.times),
        *(target or (None, None)),
    )  # fmt: skip
    info = plan_info(
        "trapezoidal", sync, dt, solution.duration, solution.own, solution.limiting,
        solution.times, solution.peak_velocity,
    )  # fmt: skip
    info |= {
        "accelerations": tuple((float(row[0]), float(row[2])) for row in solution.accelerations),
        **(extra or {}),
    }
    return plan_to_trajectory(plan, float(solution.duration), info)


def _truncated(trajectory: Trajectory, end: float) -> Trajectory:
    """The same motion on ``[start, end]`` only (``end`` inside the trajectory)."""
    bp = trajectory.breakpoints
    keep = int(np.searchsorted(bp, end, side="left"))  # pieces that start before end
    breakpoints = np.append(bp[:keep], end)
    return Trajectory(breakpoints, trajectory.coefficients[:, :keep])


def _refuse_overshoot(
    trajectory: Trajectory, start: FloatArray, end: FloatArray, v0: FloatArray, vf: FloatArray
) -> None:
    # Each joint up to its own arrival: with sync=None an early joint coasts on at vf.
    arrival = np.array([sum(times) for times in trajectory.info["phase_times"]])
    minimum, maximum = np.empty(start.size), np.empty(start.size)
    for j in range(start.size):  # a few joints; each an exact extremum search
        if arrival[j] >= trajectory.duration or arrival[j] <= 0:
            found = trajectory.extrema(0)
            minimum[j], maximum[j] = found.minimum[j], found.maximum[j]
        else:
            own = _truncated(trajectory, arrival[j]).extrema(0)
            minimum[j], maximum[j] = own.minimum[j], own.maximum[j]
    low, high = np.minimum(start, end), np.maximum(start, end)
    scale = 1e-9 * np.maximum(1.0, np.abs(high - low))
    outside = (minimum < low - scale) | (maximum > high + scale)
    if outside.any():
        j = int(np.flatnonzero(outside)[0])
        beyond = maximum[j] if maximum[j] > high[j] + scale[j] else minimum[j]
        raise InfeasibleError(
            f"joint {j + 1} cannot reach qf={end[j]:.6g} rad from v0={v0[j]:.6g} rad/s to "
            f"vf={vf[j]:.6g} rad/s without overshoot (the fastest profile reaches "
            f"{beyond:.6g} rad); pass allow_overshoot=True to accept it"
        )


def _blend_rule(
    start: FloatArray,
    end: FloatArray,
    vmax: LimitSpec,
    amax: LimitSpec,
    duration: float | None,
    blend_ratio: float | None,
    blend_time: float | None,
    dt: float | None,
) -> Trajectory:
    """Rest-to-rest LSPB with a given blend: ``v = D / (T - t_b)``, ``a = v / t_b``."""
    if blend_ratio is not None and blend_time is not None:
        raise InvalidInputError("give blend_ratio or blend_time, not both")
    ndof = start.size
    distance = end - start
    magnitude = np.abs(distance)
    if vmax is None:
        raise InvalidInputError("the blend rule needs vmax to check or find the duration")
    vpos, vneg = _limit_magnitudes("vmax", vmax, ndof, "rad/s")
    v_limit = np.where(distance >= 0, vpos, vneg)
    if amax is not None:
        apos, aneg = _limit_magnitudes("amax", amax, ndof, "rad/s^2")
        a_limit = np.minimum(apos, aneg)  # the rule accelerates and brakes equally hard
    else:
        a_limit = None
    if blend_ratio is not None:
        ratio = finite_array("blend_ratio", blend_ratio)
        if ratio.ndim != 0 or not 0.0 < float(ratio) <= 0.5:
            raise InvalidInputError(f"blend_ratio must be in (0, 0.5], got {blend_ratio!r}")
        r = float(ratio)
        # v = D / (T (1 - r)) <= V  and  a = D / (T^2 r (1 - r)) <= A
        by_v = magnitude / (v_limit * (1.0 - r))
        by_a = np.zeros(ndof) if a_limit is None else np.sqrt(magnitude / (a_limit * r * (1 - r)))
    else:
        tb = positive_scalar("blend_time", blend_time, unit="s")
        # T >= 2 tb;  v = D / (T - tb) <= V;  a = D / (tb (T - tb)) <= A
        by_v = tb + magnitude / v_limit
        by_a = np.zeros(ndof) if a_limit is None else tb + magnitude / (a_limit * tb)
        by_v = np.maximum(by_v, 2 * tb)
    minimum = np.maximum(by_v, by_a)
    joint = int(np.argmax(minimum))
    shortest = float(minimum[joint])
    if duration is None:
        T = shortest
    else:
        T = positive_scalar("duration", duration, unit="s")
        if T < shortest * (1 - 1e-12):
            which = "vmax" if by_v[joint] >= by_a[joint] else "amax"
            value = v_limit[joint] if which == "vmax" else a_limit[joint]  # type: ignore[index]
            unit = "rad/s" if which == "vmax" else "rad/s^2"
            raise InfeasibleError(
                f"duration {T:.6g} s is below the minimum {shortest:.6g} s set by "
                f"{which}={value:.6g} {unit} (joint {joint + 1})"
            )
    fixed_tb = None if blend_ratio is not None else float(tb)

    def blend_of(total: float) -> float:
        return total * float(blend_ratio) if fixed_tb is None else fixed_tb

    if dt is not None:
        # Whole periods for the duration and the blends; add periods until the
        # rounded blend keeps every joint within its limits.
        total = float(whole_periods(T, dt) * dt)
        for _ in range(_MAX_EXTRA_PERIODS):
            tb = max(float(whole_periods(blend_of(total), dt) * dt), dt)
            if 2 * tb <= total * (1 + 1e-12):
                velocity = magnitude / (total - tb)
                ok = np.all(velocity <= v_limit * (1 + 1e-12)) and (
                    a_limit is None or np.all(velocity / tb <= a_limit * (1 + 1e-12))
                )
                if ok:
                    break
            total += dt
        else:
            raise InfeasibleError(
                f"no blend in whole multiples of dt={dt:g} s keeps the limits near "
                f"the duration {T:.6g} s"
            )
        T = total
    else:
        tb = blend_of(T)
    if 2 * tb > T * (1 + 1e-12):
        raise InfeasibleError(f"blend_time {tb:.6g} s is more than half the duration {T:.6g} s")
    if T == 0.0:
        velocity = acceleration = np.zeros(ndof)
    else:
        velocity = distance / (T - tb)
        acceleration = velocity / tb
    times = np.tile([tb, T - 2 * tb, tb], (ndof, 1))
    accelerations = np.stack([acceleration, np.zeros(ndof), -acceleration], axis=-1)
    solution = TrapezoidSolution(
        times, accelerations, velocity, np.array(T), minimum, np.array(joint)
    )
    extra = {"blend_time": tb, "rule": "blend_ratio" if blend_ratio is not None else "blend_time"}
    target = (end, np.zeros(ndof))
    return _to_trajectory(start, np.zeros(ndof), solution, "phase", dt, extra, target)
