"""Velocity interface: reach a target velocity and acceleration, with no position target.

The jog of a teach pendant, a conveyor that must match a speed, a stop from any
state: the motion ends wherever its phases take it. The mathematics is the
compiled engine's velocity law (:mod:`trajkit.profiles._kernels.velocity_target`);
this module is the public function and its validation.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from trajkit._validation import count_dof, joint_vector
from trajkit.errors import InfeasibleError
from trajkit.limits import LimitSpec
from trajkit.profiles import limited
from trajkit.trajectory import Trajectory

__all__ = ["velocity_change"]


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
    dt: float | None = None,
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
    duration, min_duration, sync, dt, grid
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
    InvalidInputError
        NaN/inf, wrong shapes, limits that do not allow motion both ways,
        ``jmax <= 0``, an unknown sync mode.
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
    # The law has no velocity limit; the problem matrix still carries one (finite,
    # as the engine's checks require), wide enough never to matter.
    a_end = joint_vector("af", af, ndof, unit="rad/s^2")
    with np.errstate(all="ignore"):
        push = np.where(np.isinf(j_max), np.inf, j_max)
        reach = np.abs(start) + np.abs(end) + (a_start**2 + a_end**2) / push
    wide = 2.0 * reach + 1.0
    if not np.all(np.isfinite(wide)):
        joint = int(np.flatnonzero(~np.isfinite(wide))[0])
        raise InfeasibleError(
            f"velocity_change: the speeds of joint {joint + 1} are beyond float64 "
            f"(v0={start[joint]:.6g}, vf={end[joint]:.6g} rad/s)"
        )
    problem = limited.read_problem(
        "velocity_change", q0, q0, (-wide, wide), (a_min, a_max), j_max,
        v0=start, vf=end, a0=a_start, af=a_end, sync=sync,
    )  # fmt: skip
    result = limited.solve(
        "velocity_change", problem, duration=duration, min_duration=min_duration, dt=dt,
        grid=grid, velocity_only=True,
    )  # fmt: skip
    return limited.to_trajectory("velocity_change", problem, result, dt=dt)
