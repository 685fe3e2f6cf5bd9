"""Trapezoidal / triangular (LSPB) velocity profiles under velocity and acceleration limits.

Limit-driven profiles run in the compiled engine as acceleration-limited
(``jmax = inf``) state-to-state moves (:mod:`trajkit.profiles.limited`); the
coursework's blend rule (a given blend ratio or time) is a closed form here.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from trajkit._periods import whole_periods
from trajkit._validation import finite_array, flag, joint_vector, positive_scalar
from trajkit.errors import InfeasibleError, InvalidInputError
from trajkit.limits import LimitSpec
from trajkit.profiles import limited
from trajkit.profiles._docstrings import with_sections
from trajkit.profiles._phases import PhasePlan, plan_to_trajectory
from trajkit.renamed import renamed_keywords
from trajkit.tolerances import ROUNDING_RTOL
from trajkit.trajectory import Trajectory

__all__ = ["trapezoidal"]

_MAX_EXTRA_PERIODS = 16


@renamed_keywords(dt="period")
@with_sections
def trapezoidal(
    q0: ArrayLike,
    qf: ArrayLike,
    vmax: LimitSpec = None,
    amax: LimitSpec = None,
    *,
    duration: float | None = None,
    min_duration: float | None = None,
    blend_ratio: float | None = None,
    blend_time: float | None = None,
    v0: ArrayLike = 0.0,
    vf: ArrayLike = 0.0,
    sync: object = "time",
    period: float | None = None,
    grid: str = "switches",
    allow_overshoot: bool = True,
) -> Trajectory:
    """Trapezoidal (or triangular) velocity profile: linear segments with parabolic blends.

    Two ways to use it:

    * **Limits** (``vmax`` and ``amax``): the time-optimal bang-coast-bang profile of
      every joint, a triangle when the distance is too short to reach ``vmax``.
      ``duration`` asks for a longer, exact duration instead, ``min_duration`` for
      at least that long. A start velocity beyond ``vmax`` is first braked back at
      full deceleration.
    * **Coursework rule** (``blend_ratio`` or ``blend_time``): rest to rest, every
      joint accelerates for ``t_b = blend_ratio * duration`` (or ``blend_time``),
      coasts, and decelerates for ``t_b``. With ``duration`` the limits are
      verified; without it, the shortest duration the rule allows is used.
      ``amax`` is optional here.

    Parameters
    ----------
    {positions}
    {limits}
    duration : float, optional
        Exact duration (s) for every synchronized joint.
    min_duration : float, optional
        The duration is at least this (s) (limit mode only).
    blend_ratio : float, optional
        ``t_b / duration``, in (0, 0.5].
    blend_time : float, optional
        ``t_b`` in s.
    v0, vf : float or array_like
        Boundary velocities (rad/s) (limit mode only); ``vf`` within the limits.
    sync : str, None or sequence
        ``"time"``: all joints finish together at the slowest joint's minimum
        time; every other joint takes the common duration with its accelerations
        at the limit and the lowest peak velocity that fits, or where that cannot
        give the duration, lower accelerations. ``"phase"``: joints whose boundary
        velocities are collinear with their moves switch phases together, moving
        on a straight line in joint space (the others time-synchronized;
        ``info["phase_synchronized"]`` says whether it held). ``"time_if_necessary"``:
        time sync except for joints that end at rest, which move as fast as they
        can and wait. ``None`` (or ``"none"``): every joint as fast as it can; the ones that finish
        early hold their end state (continuing at ``vf``). A sequence gives one
        mode per joint.
    period : float, optional
        Controller period (s); see ``grid`` (at rest, every switch on the grid costs
        at most 2 periods over the continuous optimum).
    {grid}
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
        Malformed input: NaN, wrong shapes, limits that do not allow motion both
        ways, a blend ratio outside (0, 0.5], an unknown sync mode.
    InfeasibleError
        A duration below the minimum (the message names the minimum and the
        limits that set it), a target velocity beyond the limit, an overshoot
        that is not allowed.
    """
    allow_overshoot = flag("allow_overshoot", allow_overshoot)
    if blend_ratio is not None or blend_time is not None:
        return _blend_rule(q0, qf, vmax, amax, duration, blend_ratio, blend_time, period, v0, vf)
    if vmax is None or amax is None:
        raise InvalidInputError(
            "trapezoidal needs vmax and amax (or blend_ratio / blend_time with a duration)"
        )
    trajectory = limited.trajectory(
        "trapezoidal", q0, qf, vmax, amax, np.inf, v0=v0, vf=vf, a0=0.0, af=0.0, sync=sync,
        duration=duration, min_duration=min_duration, period=period, grid=grid, info=trapezoid_info,
    )  # fmt: skip
    if not allow_overshoot:
        # The strict check reads the boundary vectors back (validated already).
        problem = limited.read_problem(
            "trapezoidal", q0, qf, vmax, amax, np.inf, v0=v0, vf=vf, a0=0.0, af=0.0, sync=sync
        )
        _refuse_overshoot(trajectory, problem)
    return trajectory


def trapezoid_info(info: dict[str, object], plan: PhasePlan) -> dict[str, object]:
    """A trapezoid's plan as rise, coast and fall per joint (s) and their accelerations.

    A brake from beyond the velocity limit comes first (``brake_times``, at
    ``brake_acceleration``); see :func:`trajkit.profiles._kernels.tables.stretches`.
    """
    from trajkit.profiles._kernels.tables import stretches

    ndof = plan.durations.shape[0]
    times = np.empty((ndof, 3))
    accelerations = np.empty((ndof, 2))
    for d in range(ndof):  # a few joints, each a compiled call
        if not stretches(plan.durations[d], plan.accelerations[d], times[d], accelerations[d]):
            raise AssertionError(
                f"joint {d + 1}: an acceleration-limited profile of more than three stretches"
            )
    after_brake = plan.velocity + plan.durations[:, 0] * plan.accelerations[:, 0]
    peaks = after_brake + times[:, 0] * accelerations[:, 0]
    rows = lambda x: tuple(tuple(float(v) for v in row) for row in x)  # noqa: E731
    del info["jerks"], info["peak_acceleration"]
    return info | {
        "phase_times": rows(times),
        "peak_velocity": tuple(float(v) for v in peaks),
        "accelerations": rows(accelerations),
        "brake_times": tuple(float(t) for t in plan.durations[:, 0]),
        "brake_acceleration": tuple(float(a) for a in plan.accelerations[:, 0]),
    }


def _truncated(trajectory: Trajectory, end: float) -> Trajectory:
    """The same motion on ``[start, end]`` only (``end`` inside the trajectory)."""
    bp = trajectory.breakpoints
    keep = int(np.searchsorted(bp, end, side="left"))  # pieces that start before end
    breakpoints = np.append(bp[:keep], end)
    return Trajectory(breakpoints, trajectory.coefficients[:, :keep])


def _refuse_overshoot(trajectory: Trajectory, p: limited.Problem) -> None:
    start, end, v0, vf = p.q0, p.qf, p.v0, p.vf
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
    q0: ArrayLike,
    qf: ArrayLike,
    vmax: LimitSpec,
    amax: LimitSpec,
    duration: float | None,
    blend_ratio: float | None,
    blend_time: float | None,
    period: float | None,
    v0: ArrayLike,
    vf: ArrayLike,
) -> Trajectory:
    """Rest-to-rest LSPB with a given blend: ``v = D / (T - t_b)``, ``a = v / t_b``."""
    from trajkit._validation import count_dof

    if blend_ratio is not None and blend_time is not None:
        raise InvalidInputError("give blend_ratio or blend_time, not both")
    ndof = count_dof(q0=q0, qf=qf, v0=v0, vf=vf)
    for name, spec in (("vmax", vmax), ("amax", amax)):
        if spec is not None and not isinstance(spec, tuple):
            ndof = max(ndof, count_dof(q0=q0, qf=qf, **{name: spec}))
    start = joint_vector("q0", q0, ndof, unit="rad")
    end = joint_vector("qf", qf, ndof, unit="rad")
    if np.any(joint_vector("v0", v0, ndof, unit="rad/s")) or np.any(
        joint_vector("vf", vf, ndof, unit="rad/s")
    ):
        raise InvalidInputError(
            "blend_ratio/blend_time describe rest-to-rest moves; v0 and vf must be 0"
        )
    step = None if period is None else positive_scalar("period", period, unit="s")
    distance = end - start
    magnitude = np.abs(distance)
    if vmax is None:
        raise InvalidInputError("the blend rule needs vmax to check or find the duration")
    v_low, v_high = limited.read_bounds("vmax", vmax, ndof, "rad/s")
    v_limit = np.where(distance >= 0, v_high, -v_low)
    if amax is not None:
        a_low, a_high = limited.read_bounds("amax", amax, ndof, "rad/s^2")
        a_limit = np.minimum(a_high, -a_low)  # the rule accelerates and brakes equally hard
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
        if T < shortest * (1 - ROUNDING_RTOL):
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

    if step is not None:
        # Whole periods for the duration and the blends; add periods until the
        # rounded blend keeps every joint within its limits.
        total = float(whole_periods(T, step) * step)
        for _ in range(_MAX_EXTRA_PERIODS):
            tb = max(float(whole_periods(blend_of(total), step) * step), step)
            if 2 * tb <= total * (1 + ROUNDING_RTOL):
                velocity = magnitude / (total - tb)
                ok = np.all(velocity <= v_limit * (1 + ROUNDING_RTOL)) and (
                    a_limit is None or np.all(velocity / tb <= a_limit * (1 + ROUNDING_RTOL))
                )
                if ok:
                    break
            total += step
        else:
            raise InfeasibleError(
                f"no blend in whole multiples of period={step:g} s keeps the limits near "
                f"the duration {T:.6g} s"
            )
        T = total
    else:
        tb = blend_of(T)
    if 2 * tb > T * (1 + ROUNDING_RTOL):
        raise InfeasibleError(f"blend_time {tb:.6g} s is more than half the duration {T:.6g} s")
    if T == 0.0:
        velocity = acceleration = np.zeros(ndof)
    else:
        velocity = distance / (T - tb)
        acceleration = velocity / tb
    times = np.tile([tb, T - 2 * tb, tb], (ndof, 1))
    accelerations = np.stack([acceleration, np.zeros(ndof), -acceleration], axis=-1)
    plan = PhasePlan(
        start, np.zeros(ndof), times, accelerations, np.zeros_like(times), end, np.zeros(ndof)
    )
    info: dict[str, object] = {
        "planner": "trapezoidal",
        "continuity": 1,
        "sync": "phase",
        "period": step,
        "duration": float(T),
        "minimum_durations": tuple(float(x) for x in minimum),
        "limiting_joint": joint,
        "phase_times": tuple(tuple(float(x) for x in row) for row in times),
        "peak_velocity": tuple(float(x) for x in velocity),
        "accelerations": tuple((float(a), float(-a)) for a in acceleration),
        "blend_time": tb,
        "rule": "blend_ratio" if blend_ratio is not None else "blend_time",
    }
    return plan_to_trajectory(plan, float(T), info)
