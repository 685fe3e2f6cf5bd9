"""Velocity interface: reach a target velocity and acceleration, with no position target.

The jog of a teach pendant, a conveyor that must match a speed, a stop from any
state: the motion ends wherever its phases take it. The mathematics is the
compiled engine's velocity law (:mod:`trajkit.profiles._kernels.velocity_target`);
this module is the public function and its validation.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from trajkit._validation import FloatArray, count_dof, joint_vector
from trajkit.errors import InfeasibleError
from trajkit.limits import LimitSpec
from trajkit.profiles import limited
from trajkit.profiles._docstrings import with_sections
from trajkit.renamed import renamed_keywords
from trajkit.trajectory import Trajectory

__all__ = ["velocity_change", "velocity_room"]


@renamed_keywords(dt="period")
@with_sections
def velocity_change(
    v0: ArrayLike,
    vf: ArrayLike,
    amax: LimitSpec,
    jmax: ArrayLike,
    *,
    q0: ArrayLike = 0.0,
    a0: ArrayLike = 0.0,
    af: ArrayLike = 0.0,
    duration: float | None = None,
    min_duration: float | None = None,
    sync: object = "time",
    period: float | None = None,
    grid: str = "switches",
) -> Trajectory:
    """Time-optimal change from velocity ``v0`` (and ``a0``) to ``vf`` (and ``af``).

    Each joint's jerk is at ``+-jmax`` except while it holds an acceleration
    limit; with ``jmax=inf`` the acceleration jumps (a ramp at ``+-amax``). There
    is no position target and no velocity limit: the positions start at ``q0``
    and end where the motion takes them (``end_state.position``). A start
    acceleration beyond ``amax`` is first braked back within it.

    Parameters
    ----------
    v0, vf : float or array_like, shape (ndof,)
        Start and target velocities (rad/s, or m/s).
    amax : float, sequence or tuple
        Acceleration limit (rad/s^2): a number or one per joint, or a tuple
        ``(lower, upper)`` for asymmetric limits (``lower < 0 < upper``).
    jmax : float or array_like
        Jerk limit (rad/s^3), > 0; ``inf`` for acceleration-limited ramps
        (``a0``, ``af`` must then be 0).
    q0 : float or array_like
        Start positions (rad); they only place the result.
    a0, af : float or array_like
        Start and target accelerations (rad/s^2); ``af`` within the limits.
    duration, min_duration, sync, period, grid
        As for :func:`trajkit.scurve`: an exact common duration (s) or a floor on
        it, the synchronization mode(s), the controller period and what it puts
        on its grid.

    Returns
    -------
    Trajectory
        Piecewise cubic ending exactly at ``(vf, af)``; ``info`` as
        :func:`trajkit.scurve`'s (``peak_velocity`` is then unused by the law).

    Raises
    ------
    {jerk_limited_invalid}
    InfeasibleError
        ``af`` beyond the acceleration limit, a duration below the minimum or one
        a joint cannot take exactly.

    Examples
    --------
    >>> import trajkit as tk
    >>> stop = tk.velocity_change([1.0, -0.5], 0.0, 2.0, 10.0, a0=[0.5, 0.0])
    >>> bool(abs(stop.end_state.velocity).max() == 0.0)
    True
    """
    ndof = count_dof(v0=v0, vf=vf, q0=q0, a0=a0, af=af)
    for name, spec in (("amax", amax), ("jmax", jmax)):
        if not isinstance(spec, tuple):
            ndof = max(ndof, count_dof(v0=v0, **{name: spec}))
    start = joint_vector("v0", v0, ndof, unit="rad/s")
    end = joint_vector("vf", vf, ndof, unit="rad/s")
    a_start = joint_vector("a0", a0, ndof, unit="rad/s^2")
    j_max = limited.read_jerk(jmax, ndof)
    a_min, a_max = limited.read_bounds("amax", amax, ndof, "rad/s^2")
    a_end = joint_vector("af", af, ndof, unit="rad/s^2")
    wide = velocity_room("velocity_change", start, end, a_start, a_end, j_max)
    problem = limited.read_problem(
        "velocity_change", q0, q0, (-wide, wide), (a_min, a_max), j_max,
        v0=start, vf=end, a0=a_start, af=a_end, sync=sync,
    )  # fmt: skip
    result = limited.solve(
        "velocity_change", problem, duration=duration, min_duration=min_duration, period=period,
        grid=grid, velocity_only=True,
    )  # fmt: skip
    return limited.to_trajectory("velocity_change", problem, result, period=period)


def velocity_room(
    planner: str,
    v0: FloatArray,
    vf: FloatArray,
    a0: FloatArray,
    af: FloatArray,
    j_max: FloatArray,
) -> FloatArray:
    """A velocity bound (rad/s) that the velocity law never reaches, per joint.

    The law has no velocity limit; the problem matrix still carries one (finite,
    as the engine's checks require), so it gets one beyond every speed the
    motion can take: the boundary speeds plus what the boundary accelerations add
    while the jerk takes them away. Arrays of one shape: ``(ndof,)`` for one
    problem, ``(B, ndof)`` for a batch.

    Raises
    ------
    InfeasibleError
        Speeds beyond float64, naming the joint (and the problem, in a batch).
    """
    with np.errstate(all="ignore"):
        # A jerk limit <= 0 or NaN is refused later, by name; it adds no speed here.
        push = np.where(j_max > 0.0, j_max, np.inf)
        reach = np.abs(v0) + np.abs(vf) + (a0**2 + af**2) / push
        wide = 2.0 * reach + 1.0
    if not np.all(np.isfinite(wide)):
        where = tuple(int(k) for k in np.argwhere(~np.isfinite(wide))[0])
        problem = f"problem {where[0]}, " if len(where) == 2 else ""
        raise InfeasibleError(
            f"{planner}: the speeds of {problem}joint {where[-1] + 1} are beyond float64 "
            f"(v0={float(v0[where]):.6g}, vf={float(vf[where]):.6g} rad/s, "
            f"a0={float(a0[where]):.6g}, af={float(af[where]):.6g} rad/s^2)"
        )
    return wide
