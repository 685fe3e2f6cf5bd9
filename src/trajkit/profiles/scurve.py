"""Jerk-limited (S-curve) profiles from any state to any state: time-optimal, synchronized.

The mathematics runs in the compiled engine (:mod:`trajkit.profiles.engine`); this
module is the public function and its documentation.
"""

from __future__ import annotations

from numpy.typing import ArrayLike

from trajkit.limits import LimitSpec
from trajkit.profiles import limited
from trajkit.profiles._docstrings import with_sections
from trajkit.renamed import renamed_keywords
from trajkit.trajectory import Trajectory

__all__ = ["scurve"]


@renamed_keywords(dt="period")
@with_sections
def scurve(
    q0: ArrayLike,
    qf: ArrayLike,
    vmax: LimitSpec,
    amax: LimitSpec,
    jmax: ArrayLike,
    *,
    v0: ArrayLike = 0.0,
    vf: ArrayLike = 0.0,
    a0: ArrayLike = 0.0,
    af: ArrayLike = 0.0,
    duration: float | None = None,
    min_duration: float | None = None,
    sync: object = "time",
    period: float | None = None,
    grid: str = "switches",
) -> Trajectory:
    """Time-optimal jerk-limited profile from ``(q0, v0, a0)`` to ``(qf, vf, af)``.

    Every joint moves with its jerk at ``+-jmax`` except while it holds an
    acceleration or velocity limit; all shapes are covered (limits reached or
    not, moves that must first brake, overshoot or reverse). A start state beyond
    the limits (``|v0| > vmax``, ``|a0| > amax``, or an ``a0`` that will carry the
    velocity past its limit) is first braked back within them at full jerk.

    Parameters
    ----------
    {positions}
    {limits}
    jmax : float or array_like
        Jerk limit (rad/s^3), > 0; ``inf`` plans acceleration-limited (trapezoidal)
        profiles, whose acceleration jumps (``a0``, ``af`` must then be 0).
    v0, vf, a0, af : float or array_like
        Boundary velocities (rad/s) and accelerations (rad/s^2). The target must be
        within the limits and arrivable (a target decelerating at ``af`` was faster
        just before); the start may be beyond them.
    duration : float, optional
        Exact common duration (s); refused when a synchronized joint cannot take it
        (below its minimum, or a duration its boundary state rules out).
    min_duration : float, optional
        The duration is at least this (s); longer where a joint needs it.
    sync : str, None or sequence
        ``"time"``: every joint ends together, at the slowest joint's minimum time
        (or ``duration``), each other joint re-planned to take exactly that.
        ``"phase"``: joints whose boundary states are collinear follow the limiting
        joint's phases scaled to their own move (a straight line in joint space);
        where that is impossible they are time-synchronized and
        ``info["phase_synchronized"]`` is False. ``"time_if_necessary"``: as
        ``"time"``, except joints that end at rest (``vf = af = 0``) move as fast
        as they can and wait. ``None`` (or ``"none"``): every joint as fast as it can; early ones
        continue from their target state at constant acceleration (``af``, as ruckig's
        do). A sequence gives one mode per joint.
    period : float, optional
        Controller period (s); see ``grid``. Every switch on the grid costs at most
        3 periods over the continuous optimum rest to rest (measured worst: 2.27),
        more for moving boundaries and brakes.
    {grid}

    Returns
    -------
    Trajectory
        Piecewise cubic. ``info``: ``phase_times`` (per joint the seven phase
        durations after the brake), ``brake_times`` (two per joint), ``jerks``,
        ``peak_velocity`` (velocity of the fourth phase), ``peak_acceleration``
        (the acceleration of the second and sixth phases), ``minimum_durations``
        (each joint alone, brake included), ``limiting_joint``, and with phase sync
        ``phase_synchronized``.

    Raises
    ------
    {jerk_limited_invalid}
    InfeasibleError
        A target beyond the limits, a duration below the minimum or one a joint
        cannot take exactly.
    """
    return limited.trajectory(
        "scurve", q0, qf, vmax, amax, jmax, v0=v0, vf=vf, a0=a0, af=af, sync=sync,
        duration=duration, min_duration=min_duration, period=period, grid=grid,
    )  # fmt: skip
