"""Jerk-limited double-S (S-curve) profiles: time-optimal, synchronized, quantized.

The one-axis mathematics lives in :mod:`trajkit.profiles._scurve_math`; this
module validates input, synchronizes joints, quantizes to a controller period and
builds the :class:`~trajkit.Trajectory`. The vectorized core :func:`solve_scurve`
also serves :func:`trajkit.batch.scurve`.
"""

from __future__ import annotations

import itertools

import numpy as np
from numpy.typing import ArrayLike

from trajkit._periods import whole_periods
from trajkit._validation import (
    FloatArray,
    count_dof,
    finite_result,
    joint_vector,
    positive_joint_vector,
    positive_scalar,
)
from trajkit.errors import InfeasibleError, InvalidInputError
from trajkit.profiles import _scurve_math as smath
from trajkit.profiles._phases import PhasePlan, plan_info, plan_to_trajectory
from trajkit.profiles._sync import common_duration
from trajkit.profiles.trapezoidal import (
    Sync,
    _check_boundary_velocities,
    _law_distance,
    _phase_law,
    _read_sync,
)
from trajkit.trajectory import Trajectory

__all__ = ["SCurveSolution", "quantize_scurve", "scurve", "solve_scurve"]

# Whole periods tried around the continuous phase times: jerk phases near their
# value; holds mostly longer, since a shorter jerk phase needs a longer hold and the
# quantized profile keeps its peak speed high and lowers its jerk instead.
_JERK_OFFSETS = (-1, 0, 1, 2)
_HOLD_OFFSETS = tuple(range(-3, 10))
_COMBOS = 2 * (len(_JERK_OFFSETS) * len(_HOLD_OFFSETS)) ** 2  # per element, both centres
_CANDIDATES_PER_CHUNK = 1_000_000  # bounds the memory of one quantization step
_MAX_EXTRA_PERIODS = 16


class SCurveSolution:
    """Seven phases per joint (rise, hold, fall, coast, rise, hold, fall).

    ``durations`` and ``jerks`` have shape ``(..., ndof, 7)``; ``peak_velocity``
    ``(..., ndof)``; ``duration`` the common duration; ``own`` each joint's minimum
    alone; ``limiting`` the joint that sets the duration (-1 under phase sync).
    """

    __slots__ = ("_arrays", "_make", "duration", "limiting", "own")

    def __init__(self, durations, jerks, peak_velocity, duration, own, limiting, make=None) -> None:
        # ``make()`` may stand in for the three phase arrays: batch planning builds
        # them only when somebody asks.
        self._arrays = None if make is not None else (durations, jerks, peak_velocity)
        self._make = make
        self.duration, self.own, self.limiting = duration, own, limiting

    def _phase_arrays(self) -> tuple[FloatArray, FloatArray, FloatArray]:
        if self._arrays is None:
            self._arrays = self._make()
        return self._arrays

    @property
    def durations(self) -> FloatArray:
        """Phase durations (s), ``(..., ndof, 7)``."""
        return self._phase_arrays()[0]

    @property
    def jerks(self) -> FloatArray:
        """Phase jerks, ``(..., ndof, 7)``."""
        return self._phase_arrays()[1]

    @property
    def peak_velocity(self) -> FloatArray:
        """Signed coast (peak) velocity, ``(..., ndof)``."""
        return self._phase_arrays()[2]

    @property
    def accelerations(self) -> FloatArray:
        """Acceleration at the start of each phase (the profile starts at 0)."""
        arrays = self._phase_arrays()
        if len(arrays) > 3:
            return arrays[3]
        steps = self.durations * self.jerks
        return np.concatenate(
            [np.zeros_like(steps[..., :1]), np.cumsum(steps[..., :-1], axis=-1)], axis=-1
        )

    @property
    def peak_acceleration(self) -> FloatArray:
        """Signed peak acceleration of the first and second velocity change, (..., ndof, 2)."""
        a = self.accelerations
        return np.stack([a[..., 1], a[..., 5]], axis=-1)


def _from_phases(phases: smath.SCurvePhases) -> tuple[FloatArray, FloatArray]:
    return phases.to_phases()


_FIELDS = ("vp", "tj1", "ta1", "a1", "j1", "tv", "tj2", "ta2", "a2", "j2", "duration", "valid")


def _exact(T: FloatArray, args: tuple[FloatArray, ...]) -> smath.SCurvePhases:
    """Profiles taking exactly ``T``; at a joint's own minimum, its fastest profile.

    At the minimum the fixed-duration search meets a double root; the fastest
    profile is known exactly there (and for vanishing moves it is the only
    precise answer).
    """
    phases = smath.fixed_duration(T, *args)
    distance, v0, vf = args[:3]
    # Standing still takes any duration.
    still = (distance == 0) & (v0 == 0) & (vf == 0)
    if np.any(still):
        shape = np.broadcast_shapes(np.shape(phases.valid), np.shape(still))
        for name in _FIELDS:
            value = np.broadcast_to(getattr(phases, name), shape).copy()
            if name == "valid":
                value[np.broadcast_to(still, shape)] = True
            elif name == "tv":
                value = np.where(still, np.broadcast_to(T, shape), value)
            elif name != "duration":
                value[np.broadcast_to(still, shape)] = 0.0
            setattr(phases, name, value)
    fastest = smath.minimum_time(*args)
    phases = _stretched_where_unsolved(T, phases, fastest, v0, vf)
    at_minimum = (T <= fastest.duration * (1 + 1e-12)) & fastest.valid & ~still
    if not np.any(at_minimum):
        return phases
    shape = np.broadcast_shapes(np.shape(phases.valid), np.shape(at_minimum))
    pick = lambda name: np.where(  # noqa: E731
        at_minimum, np.broadcast_to(getattr(fastest, name), shape),
        np.broadcast_to(getattr(phases, name), shape),
    )  # fmt: skip
    merged = smath.SCurvePhases(*(pick(name) for name in _FIELDS))
    merged.duration = np.broadcast_to(T, shape).copy()
    return merged


_SCALING = {"vp": 1, "tj1": -1, "ta1": -1, "a1": 2, "j1": 3, "tv": -1, "tj2": -1, "ta2": -1,
            "a2": 2, "j2": 3}  # fmt: skip  # each field divided by k ** power when slowed by k


def _stretched_where_unsolved(
    T: FloatArray,
    phases: smath.SCurvePhases,
    fastest: smath.SCurvePhases,
    v0: FloatArray,
    vf: FloatArray,
) -> smath.SCurvePhases:
    """Rest-to-rest joints the fixed-duration search missed: the fastest profile slowed.

    Slowing a profile by ``k = T / T_min >= 1`` divides its speed by ``k``, its
    acceleration by ``k²`` and its jerk by ``k³``, so it stays within the limits
    and covers the same distance. The search can miss such a joint only at the
    edges of floating point (a move of 1e-220 rad, say).
    """
    shape = np.broadcast_shapes(np.shape(phases.valid), np.shape(T))
    missed = (
        ~np.broadcast_to(phases.valid, shape) & fastest.valid & (v0 == 0) & (vf == 0)
        & (T >= fastest.duration)
    )  # fmt: skip
    if not np.any(missed):
        return phases
    with np.errstate(divide="ignore", invalid="ignore"):
        k = np.broadcast_to(T, shape) / fastest.duration
    for name, power in _SCALING.items():
        slowed = np.broadcast_to(getattr(fastest, name), shape) / k**power
        kept = np.broadcast_to(getattr(phases, name), shape)
        setattr(phases, name, np.where(missed, slowed, kept))
    phases.valid = np.broadcast_to(phases.valid, shape) | missed
    phases.duration = np.where(missed, np.broadcast_to(T, shape), phases.duration)
    return phases


def solve_scurve(
    distance: FloatArray,
    v0: FloatArray,
    vf: FloatArray,
    V: FloatArray,
    A: FloatArray,
    J: FloatArray,
    sync: Sync,
    duration: FloatArray | None = None,
) -> SCurveSolution:
    """Vectorized S-curve planning; arguments ``(..., ndof)``, ``duration`` ``(...)``."""
    args = (distance, v0, vf, V, A, J)
    fastest = smath.minimum_time(*args)
    if not fastest.valid.all():
        raise InfeasibleError("no jerk-limited profile reaches the target within the limits")
    own = fastest.duration
    if sync == "phase":
        law_args = _scurve_law(*args)
        if duration is None:
            law = smath.minimum_time(*law_args)
            T = law.duration
        else:
            T, law = common_duration(
                np.asarray(duration, dtype=float),
                tuple(x[..., np.newaxis] for x in law_args),
                _exact,
            )
            law = _squeeze(law)
        durations, jerks = law.to_phases()
        return SCurveSolution(
            np.broadcast_to(durations[..., np.newaxis, :], (*distance.shape, 7)).copy(),
            jerks[..., np.newaxis, :] * _law_distance(distance)[..., np.newaxis],
            law.vp[..., np.newaxis] * _law_distance(distance),
            T,
            own,
            np.full(np.shape(T), -1),
        )
    limiting = np.argmax(own, axis=-1)
    if sync is None and duration is None:
        durations, jerks = fastest.to_phases()
        return SCurveSolution(durations, jerks, fastest.vp, own.max(axis=-1), own, limiting)
    T = own.max(axis=-1) if duration is None else np.asarray(duration, dtype=float)
    T, phases = common_duration(T, args, _exact)
    durations, jerks = phases.to_phases()
    return SCurveSolution(durations, jerks, phases.vp, T, own, limiting)


def _squeeze(phases: smath.SCurvePhases) -> smath.SCurvePhases:
    return smath.SCurvePhases(*(getattr(phases, n)[..., 0] for n in _FIELDS))


def _scurve_law(distance, v0, vf, V, A, J):
    """The shared time law ``s: 0 -> 1`` of a phase-synchronized S-curve (symmetric limits)."""
    one, s_v0, s_vf, s_v, _, s_a, _ = _phase_law(distance, v0, vf, V, V, A, A)
    moving = _law_distance(distance) != 0
    s_j = np.where(moving, J / np.where(moving, np.abs(distance), 1.0), np.inf).min(axis=-1)
    s_j = np.where(moving.any(axis=-1), s_j, 1.0)
    return one, s_v0, s_vf, s_v, s_a, s_j


def _integer_phases(
    steps: FloatArray,
    dt: float,
    args: tuple[FloatArray, ...],
    centers: FloatArray,
    ramps: tuple[int, ...] = (0,),
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """:func:`_integer_phases_of` in chunks of elements, to bound the memory it takes."""
    shape = np.broadcast_shapes(np.shape(steps), *(np.shape(a) for a in args))
    flat = [np.broadcast_to(x, shape).reshape(-1) for x in (steps, *args)]
    flat_centers = np.broadcast_to(centers, (*shape, 4)).reshape(-1, 4)
    size = flat[0].size
    valid = np.zeros(size, bool)
    durations, jerks = np.zeros((size, 7)), np.zeros((size, 7))
    peak = np.zeros(size)
    chunk = max(1, _CANDIDATES_PER_CHUNK // (len(ramps) ** 2 * _COMBOS))
    for begin in range(0, size, chunk):
        part = slice(begin, begin + chunk)
        found = _integer_phases_of(
            flat[0][part], dt, tuple(x[part] for x in flat[1:]), flat_centers[part], ramps
        )
        valid[part], durations[part], jerks[part], peak[part] = found
    return (
        valid.reshape(shape), durations.reshape(*shape, 7), jerks.reshape(*shape, 7),
        peak.reshape(shape),
    )  # fmt: skip


def _excess_distance(t1: FloatArray, t2: FloatArray, t3: FloatArray) -> FloatArray:
    """Distance a velocity change covers beyond its start speed, per unit peak acceleration.

    Acceleration ramps up over ``t1``, holds over ``t2``, ramps down over ``t3``.
    """
    return t1 * t1 / 6 + t1 * t2 / 2 + t2 * t2 / 2 + (t1 / 2 + t2) * t3 + t3 * t3 / 3


def _integer_phases_of(
    steps: FloatArray,
    dt: float,
    args: tuple[FloatArray, ...],
    centers: FloatArray,
    ramps: tuple[int, ...],
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Seven phases in whole multiples of ``dt`` summing to ``steps * dt``.

    Around two continuous profiles — the gentlest of that duration, and the plan
    being quantized (``centers``: its ramp and hold times of both changes) —
    nearby step counts of each velocity change's ramp-up, hold and ramp-down are
    tried (the ramp-down differs from the ramp-up by one of ``ramps`` steps; the
    coast takes the rest). For given counts the peak velocity follows linearly
    from the distance (a change of peak acceleration ``a`` covers its start speed
    times its duration plus ``a`` times :func:`_excess_distance`), then the peak
    accelerations and the jerks of each ramp. The valid choice of smallest jerk
    is kept. Returns ``valid``, ``durations`` (..., 7), ``jerks`` (..., 7), ``vp``.
    """
    D, v0, vf, V, A, J = args
    total = np.broadcast_to(steps * dt, D.shape)
    smooth = _exact(total, args)
    gentle = np.stack([smooth.tj1, smooth.ta1, smooth.tj2, smooth.ta2], axis=-1)
    offsets = np.array(
        list(
            itertools.product(
                _JERK_OFFSETS, _HOLD_OFFSETS, ramps, _JERK_OFFSETS, _HOLD_OFFSETS, ramps
            )
        ),
        dtype=float,
    )  # (C, 6): ramp-up, hold, ramp-down minus ramp-up; for both changes
    e = lambda x: np.asarray(x)[..., np.newaxis]  # noqa: E731
    counts = []
    for base in (gentle, centers):
        b = np.round(np.nan_to_num(base) / dt)[..., np.newaxis, :]  # (..., 1, 4)
        counts.append(
            np.stack(
                [
                    b[..., 0] + offsets[:, 0], b[..., 1] + offsets[:, 1],
                    b[..., 0] + offsets[:, 0] + offsets[:, 2],
                    b[..., 2] + offsets[:, 3], b[..., 3] + offsets[:, 4],
                    b[..., 2] + offsets[:, 3] + offsets[:, 5],
                ],
                axis=-1,
            )
        )  # fmt: skip
    n = np.moveaxis(np.concatenate(counts, axis=-2), -1, 0)  # (6, ..., C)
    N = e(np.broadcast_to(steps, D.shape))
    nv = N - n.sum(axis=0)
    t = n * dt
    tv = nv * dt
    with np.errstate(all="ignore"):
        M1 = t[0] / 2 + t[1] + t[2] / 2  # velocity change per unit peak acceleration
        M2 = t[3] / 2 + t[4] + t[5] / 2
        E1, E2 = _excess_distance(t[0], t[1], t[2]), _excess_distance(t[3], t[4], t[5])
        T1, T2 = t[0] + t[1] + t[2], t[3] + t[4] + t[5]
        # D = v0 T1 + (vp - v0) E1 / M1 + vp (tv + T2) + (vf - vp) E2 / M2, linear in vp.
        r1 = np.where(M1 > 0, E1 / M1, 0.0)
        r2 = np.where(M2 > 0, E2 / M2, 0.0)
        vp = (e(D) - e(v0) * (T1 - r1) - e(vf) * r2) / (r1 + tv + T2 - r2)
        vp = np.where(M1 > 0, vp, e(v0))  # no first change: the coast is at v0
        a1 = np.where(M1 > 0, (vp - e(v0)) / M1, 0.0)
        a2 = np.where(M2 > 0, (e(vf) - vp) / M2, 0.0)
        jerks = [np.where(t[k] > 0, a / t[k], 0.0) for k, a in ((0, a1), (2, a1), (3, a2), (5, a2))]
        covered = e(v0) * T1 + a1 * E1 + vp * tv + vp * T2 + a2 * E2
    slack = 1 + 1e-12
    scale = np.abs(e(D)) + (np.abs(e(v0)) + np.abs(e(vf)) + e(V)) * e(total) + 1e-300
    valid = (n >= 0).all(axis=0) & (nv >= 0) & np.isfinite(vp)
    # A hold needs ramps around it; a change needs time unless it changes nothing.
    valid &= ((n[1] == 0) | ((n[0] > 0) & (n[2] > 0))) & ((n[4] == 0) | ((n[3] > 0) & (n[5] > 0)))
    valid &= ((n[0] > 0) == (n[2] > 0)) & ((n[3] > 0) == (n[5] > 0))
    valid &= (M1 > 0) | (np.abs(vp - e(v0)) <= 1e-12 * e(V))
    valid &= (M2 > 0) | (np.abs(e(vf) - vp) <= 1e-12 * e(V))
    valid &= np.abs(covered - e(D)) <= 1e-9 * scale
    valid &= np.abs(vp) <= e(V) * slack
    valid &= (np.abs(a1) <= e(A) * slack) & (np.abs(a2) <= e(A) * slack)
    steepest = np.maximum.reduce([np.abs(j) for j in jerks])
    valid &= steepest <= e(J) * slack
    score = np.where(valid, steepest, np.inf)
    pick = np.argmin(score, axis=-1)[..., np.newaxis]
    take = lambda x: np.take_along_axis(np.broadcast_to(x, score.shape), pick, axis=-1)[..., 0]  # noqa: E731
    durations = np.stack(
        [take(t[0]), take(t[1]), take(t[2]), take(tv), take(t[3]), take(t[4]), take(t[5])],
        axis=-1,
    )
    zero = np.zeros(durations.shape[:-1])
    j_up1, j_down1, j_up2, j_down2 = (take(j) for j in jerks)
    jerk_table = np.stack([j_up1, zero, -j_down1, zero, j_up2, zero, -j_down2], axis=-1)
    return valid.any(axis=-1), durations, jerk_table, take(vp)


def _select(x: FloatArray, mask: FloatArray, where: tuple[FloatArray, ...]) -> FloatArray:
    return np.broadcast_to(x, mask.shape)[where]


def quantize_scurve(
    solution: SCurveSolution, dt: float, args: tuple[FloatArray, ...], sync: Sync
) -> SCurveSolution:
    """Re-plan so every switching time and the duration are whole multiples of ``dt``.

    Starts from the continuous optimum rounded up to the period and adds periods
    until whole-step phases keep every limit (per joint for ``sync=None``, common
    otherwise; under phase sync the shared time law is quantized and scaled).
    """
    if sync == "phase":
        law_args = tuple(np.asarray(x)[..., np.newaxis] for x in _scurve_law(*args))
        law_durations, law_jerks = smath.minimum_time(*law_args).to_phases()
        law = quantize_scurve(
            SCurveSolution(
                law_durations, law_jerks, None, None,
                np.asarray(solution.duration)[..., np.newaxis], None,
            ),
            dt,
            law_args,
            None,
        )  # fmt: skip
        distance = args[0]
        return SCurveSolution(
            np.broadcast_to(law.durations, (*distance.shape, 7)).copy(),
            law.jerks * _law_distance(distance)[..., np.newaxis],
            law.peak_velocity * _law_distance(distance),
            law.duration,
            solution.own,
            solution.limiting,
        )
    per_joint = sync is None
    centers = solution.durations[..., [0, 1, 4, 5]]
    target = solution.own if per_joint else solution.duration
    steps = whole_periods(target, dt)
    shape = args[0].shape
    durations = np.zeros((*shape, 7))
    jerks = np.zeros((*shape, 7))
    peak = np.zeros(shape)
    done = np.zeros(np.shape(steps), bool)
    for _ in range(_MAX_EXTRA_PERIODS):
        trial = steps if per_joint else np.asarray(steps)[..., np.newaxis]
        valid, d, j, vp = _integer_phases(trial, dt, args, centers)
        retry = ~valid
        if retry.any():
            # Symmetric changes found no whole-period profile here: let each change's
            # ramp-down differ from its ramp-up by a step (each ramp its own jerk).
            where = np.nonzero(retry)
            found = _integer_phases(
                _select(trial, retry, where), dt, tuple(_select(a, retry, where) for a in args),
                np.broadcast_to(centers, (*retry.shape, 4))[where], ramps=(-1, 0, 1),
            )  # fmt: skip
            valid, d, j, vp = valid.copy(), d.copy(), j.copy(), vp.copy()
            valid[where], d[where], j[where], vp[where] = found
        ok = valid if per_joint else valid.all(axis=-1)
        new = ok & ~done
        mask = new if per_joint else np.broadcast_to(np.asarray(new)[..., np.newaxis], shape)
        durations[mask], jerks[mask], peak[mask] = d[mask], j[mask], vp[mask]
        done = done | ok
        if np.all(done):
            break
        steps = np.where(done, steps, steps + 1)
    else:
        raise InfeasibleError(
            f"no jerk-limited profile with phases in whole multiples of dt={dt:g} s keeps "
            f"the limits within {_MAX_EXTRA_PERIODS} periods of the continuous optimum"
        )
    duration = (np.max(steps, axis=-1) if per_joint else steps) * dt
    return SCurveSolution(durations, jerks, peak, duration, solution.own, solution.limiting)


def scurve(
    q0: ArrayLike,
    qf: ArrayLike,
    vmax: ArrayLike,
    amax: ArrayLike,
    jmax: ArrayLike,
    *,
    v0: ArrayLike = 0.0,
    vf: ArrayLike = 0.0,
    duration: float | None = None,
    sync: Sync = "time",
    dt: float | None = None,
) -> Trajectory:
    """Jerk-limited double-S profile: time-optimal, with zero boundary accelerations.

    Every joint changes velocity with its jerk at ``+-jmax``, its acceleration
    held at ``+-amax`` when the change is large, coasts at a peak velocity (at
    ``+-vmax`` when reached) and changes to ``vf``. All shapes are covered: peak
    velocity or acceleration reached or not, moves that must first brake or
    overshoot because of ``v0``/``vf``.

    Parameters
    ----------
    q0, qf : float or array_like, shape (ndof,)
        Start and end positions (rad, or m).
    vmax, amax, jmax : float or array_like
        Symmetric velocity (rad/s), acceleration (rad/s^2) and jerk (rad/s^3)
        limits, > 0.
    v0, vf : float or array_like
        Boundary velocities (rad/s), within ``vmax``; boundary accelerations are 0.
    duration : float, optional
        Exact common duration (s) instead of the shortest.
    sync : {"time", "phase", None}
        As in :func:`trajkit.trapezoidal`: ``"time"`` — all joints finish with the
        slowest (each other joint keeps its jerk and acceleration limits and
        lowers its peak velocity, or where that cannot give the duration exactly,
        lowers its jerk); ``"phase"`` — one time law for all joints (straight line
        in joint space); ``None`` — each joint alone.
    dt : float, optional
        Controller period (s): every switching time and the duration become whole
        multiples of it while all limits still hold. Usually within ``2 dt`` of the
        continuous optimum; a profile tight on velocity, acceleration and jerk at
        once can need slightly more (the worst found in testing: 2.002 dt).

    Returns
    -------
    Trajectory
        Piecewise cubic. ``info``: ``phase_times`` (per joint the 7 phase
        durations: rise, hold, fall, coast, rise, hold, fall), ``jerks``,
        ``peak_velocity``, ``peak_acceleration`` (each velocity change),
        ``minimum_durations``, ``limiting_joint``.

    Raises
    ------
    InvalidInputError
        NaN/inf, wrong shapes, limits <= 0, unknown sync.
    InfeasibleError
        A boundary velocity beyond ``vmax``, a duration below the minimum, or a
        common duration that no joint set can take.
    """
    missing = [n for n, x in (("vmax", vmax), ("amax", amax), ("jmax", jmax)) if x is None]
    if missing:
        raise InvalidInputError(f"scurve needs vmax, amax and jmax; missing {', '.join(missing)}")
    ndof = count_dof(q0=q0, qf=qf, v0=v0, vf=vf, vmax=vmax, amax=amax, jmax=jmax)
    start = joint_vector("q0", q0, ndof, unit="rad")
    end = joint_vector("qf", qf, ndof, unit="rad")
    start_v = joint_vector("v0", v0, ndof, unit="rad/s")
    end_v = joint_vector("vf", vf, ndof, unit="rad/s")
    V = positive_joint_vector("vmax", vmax, ndof, unit="rad/s")
    A = positive_joint_vector("amax", amax, ndof, unit="rad/s^2")
    J = positive_joint_vector("jmax", jmax, ndof, unit="rad/s^3")
    sync = _read_sync(sync)
    step = None if dt is None else positive_scalar("dt", dt, unit="s")
    for name, values in (("v0", start_v), ("vf", end_v)):
        _check_boundary_velocities(name, values, V, V, label="vmax=", magnitude=True)
    arguments = {"q0": start, "qf": end, "v0": start_v, "vf": end_v, "vmax": V, "amax": A,
                 "jmax": J}  # fmt: skip
    with np.errstate(over="ignore"):
        args = (end - start, start_v, end_v, V, A, J)
    # Finite positions can still be an infinite move (qf=1e308, q0=-1e308).
    finite_result("scurve", args[0], arguments)
    requested = None
    mode = sync
    if duration is not None:
        requested = positive_scalar("duration", duration, unit="s")
        mode = "phase" if sync == "phase" else "time"
        fastest = solve_scurve(*args, sync=mode)
        if requested < float(fastest.duration) * (1 - 1e-12):
            joint = int(np.argmax(fastest.own))
            raise InfeasibleError(
                f"duration {requested:.6g} s is below the minimum {float(fastest.duration):.6g} s "
                f"set by vmax={V[joint]:.6g} rad/s, amax={A[joint]:.6g} rad/s^2 and "
                f"jmax={J[joint]:.6g} rad/s^3 (joint {joint + 1})"
            )
        requested = np.array(max(requested, float(fastest.duration)))
    solution = solve_scurve(*args, sync=mode, duration=requested)
    if requested is not None and float(solution.duration) > float(requested) * (1 + 1e-12):
        raise InfeasibleError(
            f"duration {float(requested):.6g} s cannot be met exactly: some joint cannot take "
            f"it with its boundary velocities; the next duration that works is "
            f"{float(solution.duration):.6g} s"
        )
    if step is not None:
        solution = quantize_scurve(solution, step, args, mode)
    # A finite move can still take longer than float64 holds (vmax=1e-300 rad/s).
    finite_result("scurve", solution.duration, {**arguments, "duration": duration})
    plan = PhasePlan(
        start, start_v, solution.durations, solution.accelerations, solution.jerks, end, end_v,
        np.zeros(ndof),
    )  # fmt: skip
    info = plan_info(
        "scurve", sync, step, solution.duration, solution.own, solution.limiting,
        solution.durations, solution.peak_velocity,
    )  # fmt: skip
    info |= {
        "jerks": tuple(tuple(float(x) for x in row) for row in solution.jerks),
        "peak_acceleration": tuple(
            tuple(float(x) for x in row) for row in solution.peak_acceleration
        ),
    }
    return plan_to_trajectory(plan, float(solution.duration), info)


def _change_time(v: FloatArray, A: FloatArray, J: FloatArray) -> FloatArray:
    """Fastest change from rest to speed ``v >= 0`` (zero end accelerations)."""
    return np.where(v * J >= A * A, v / A + A / J, 2.0 * np.sqrt(v / J))


def _polish_by_bisection(peak, T, d, fastest, A, J):
    """Where the closed form lost precision, bisect instead (1-D arrays).

    On ``d / T < vp <= fastest`` the excess ``Tc(vp) + d / vp - T`` falls from
    positive to <= 0, so the gentlest peak is its only root there.
    """
    with np.errstate(all="ignore"):
        excess = _change_time(peak, A, J) + d / peak - T
    bad = ~(np.abs(excess) <= 1e-13 * T)
    if not bad.any():
        return peak
    A_, J_, d_, T_ = A[bad], J[bad], d[bad], T[bad]
    low, high = d_ / T_, fastest[bad].copy()
    for _ in range(200):
        middle = 0.5 * (low + high)
        above = _change_time(middle, A_, J_) + d_ / middle - T_ > 0
        low, high = np.where(above, middle, low), np.where(above, high, middle)
        if np.all(high - low <= 1e-15 * high):
            break
    peak = peak.copy()
    peak[bad] = high
    return peak


class RestProfile:
    """A rest-to-rest double S: jerk time ``tj``, hold ``ta``, coast ``tv``, ``jerk``, peak.

    Both velocity changes mirror each other; these four numbers per joint are the
    whole plan. :meth:`phases` expands them into the 7-phase tables.
    """

    __slots__ = ("jerk", "peak", "ta", "tj", "tv")

    def __init__(self, tj, ta, tv, jerk, peak) -> None:
        self.tj, self.ta, self.tv, self.jerk, self.peak = tj, ta, tv, jerk, peak

    def phases(self) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        """Durations, jerks, peak velocity and start accelerations, tables ``(..., 7)``."""
        tj, ta, tv, jerk = np.broadcast_arrays(self.tj, self.ta, self.tv, self.jerk)
        acceleration = jerk * tj
        zero = np.zeros(tj.shape)
        stack = lambda *columns: np.stack(columns, axis=-1)  # noqa: E731
        return (
            stack(tj, ta, tj, tv, tj, ta, tj),
            stack(jerk, zero, -jerk, zero, -jerk, zero, jerk),
            self.peak,
            stack(zero, acceleration, acceleration, zero, zero, -acceleration, -acceleration),
        )


def _free_peak(T, d, A, J, fastest):
    """Gentlest peak when the acceleration does not saturate: ``2 sqrt(vp/J) + d/vp = T``.

    With ``x = sqrt(vp)``: ``2 x^3 - c x^2 + e = 0`` (``c = T sqrt(J)``,
    ``e = d sqrt(J)``), one negative and two positive roots (trigonometric form);
    the smaller positive one lies on the branch where a longer duration means a
    lower peak. Two Newton steps polish it; where the closed form lost precision
    (extreme durations), bisection on ``d / T < vp <= fastest`` takes over.
    """
    with np.errstate(invalid="ignore", divide="ignore"):
        c, e = T * np.sqrt(J), d * np.sqrt(J)
        p2, p0 = -c / 2.0, e / 2.0
        P = -(p2**2) / 3.0
        Q = 2.0 * p2**3 / 27.0 + p0
        angle = np.arccos(np.clip(1.5 * Q / P * np.sqrt(-3.0 / P), -1.0, 1.0)) / 3.0
        radius = 2.0 * np.sqrt(-P / 3.0)
        # Roots radius * cos(angle - 2 pi k / 3) - p2 / 3 fall in the order k = 0, 1, 2
        # (angle lies in [0, pi / 3]); k = 2 is the negative one, k = 1 the one we want.
        x = radius * np.cos(angle - 2.0 * np.pi / 3.0) - p2 / 3.0
        for _ in range(2):
            slope = 6 * x**2 - 2 * c * x
            x = x - (2 * x**3 - c * x**2 + e) / np.where(slope != 0, slope, 1.0)
    return _polish_by_bisection(x * x, T, d, fastest, A, J)


def rest_plan(D, V, A, J):
    """Closed forms for moves at rest at both ends (the batch planner's hot path).

    With ``d = |D|`` and ``Tc(v)`` the fastest change from rest to ``v``, a profile
    of peak speed ``vp`` lasts ``T(vp) = Tc(vp) + d / vp``. Fastest: ``vp = V`` when
    ``d >= V Tc(V)`` (it coasts), else the ``vp`` with ``vp Tc(vp) = d`` (a
    quadratic when the acceleration saturates, ``vp = (d sqrt(J) / 2)^(2/3)``
    otherwise). Exactly ``T`` (time synchronization): the smallest ``vp`` with
    ``T(vp) = T`` — a quadratic when saturated, the smaller positive root of
    ``2 x^3 - T sqrt(J) x^2 + d sqrt(J) = 0`` (``x = sqrt(vp)``) otherwise.

    Returns ``(durations, phases_at)``; ``phases_at(T)`` gives a :class:`RestProfile`.
    """
    d = np.abs(D)
    knee = A * A / J  # the speed change at which the acceleration saturates
    saturated_peak = 0.5 * A * (np.sqrt((A / J) ** 2 + 4.0 * d / A) - A / J)
    free_peak = np.cbrt(d * np.sqrt(J) / 2.0) ** 2
    no_coast = np.where(saturated_peak >= knee, saturated_peak, free_peak)
    vp = np.minimum(no_coast, V)
    duration = np.divide(d, vp, out=np.zeros_like(vp), where=vp > 0)
    duration += _change_time(vp, A, J)

    def phases_at(T: FloatArray) -> RestProfile:
        shape = np.broadcast_shapes(np.shape(T), d.shape)
        T_full = np.broadcast_to(T, shape)
        with np.errstate(invalid="ignore", divide="ignore"):
            b = T - A / J
            # Smaller root of vp^2 / A - b vp + d = 0, in the form free of cancellation;
            # valid where the acceleration saturates (vp >= knee). d = 0 gives 0.
            discriminant = b * b - 4.0 * d / A
            root = np.sqrt(np.maximum(discriminant, 0.0))
            root += b
            # No real root (or b <= 0): no saturated profile; 0 sends it to the free case.
            peak = np.divide(
                2.0 * d, root, out=np.zeros(shape), where=(root > 0) & (discriminant >= 0)
            )
            # At the minimum duration itself the root is double: the fastest peak is known.
            at_minimum = T_full <= duration * (1 + 1e-12)
            np.copyto(peak, vp, where=at_minimum)
            free = (peak < knee * (1 - 1e-12)) & ~at_minimum & (d > 0)
            if free.any():
                sub = lambda x: np.broadcast_to(x, shape)[free]  # noqa: E731
                peak[free] = _free_peak(sub(T_full), sub(d), sub(A), sub(J), sub(vp))
        np.minimum(peak, V, out=peak)
        tj = np.sqrt(peak / J)
        np.minimum(tj, A / J, out=tj)
        ta = peak / A - A / J
        np.maximum(ta, 0.0, out=ta)
        tv = T - 4.0 * tj - 2.0 * ta
        np.maximum(tv, 0.0, out=tv)
        signed = np.copysign(peak, D)
        jerk = np.divide(signed, tj * (tj + ta), out=np.zeros(shape), where=tj > 0)
        return RestProfile(tj, ta, tv, jerk, signed)

    return duration, phases_at
