"""Online trajectory generation: plan from the current state whenever the target changes.

A :class:`Generator` is what a control loop calls once per period: it plans the
time-optimal jerk-limited (or acceleration-limited) motion from the current state
to the target, as :func:`trajkit.scurve` would, and returns the state one period
later. The target may change between calls (jogging, a moving goal): a changed
target is planned afresh from the state the previous cycle reached, so the motion
stays within the limits and continuous in acceleration; an unchanged one follows
the plan made for it (as ruckig's online update does), so a fixed target is
planned once.

Examples
--------
A jog whose target moves for a while, then holds:

>>> import trajkit as tk
>>> gen = tk.online.Generator(2, period=0.01, vmax=1.0, amax=2.0, jmax=10.0)
>>> state = gen.state  # at rest at 0
>>> for k in range(400):
...     target = [min(0.005 * k, 1.0), -0.5]
...     state, reached = gen.update(target)
>>> reached, [round(float(x), 9) for x in state.position]
(True, [1.0, -0.5])
"""

from __future__ import annotations

import warnings
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from trajkit._validation import FloatArray, joint_vector, positive_scalar
from trajkit.errors import InvalidInputError
from trajkit.limits import LimitSpec
from trajkit.profiles import engine, limited
from trajkit.profiles._docstrings import with_sections
from trajkit.renamed import renamed_keywords

__all__ = ["Generator", "OnlineState"]


class OnlineState(NamedTuple):
    """Position, velocity and acceleration of every joint (views; copy to keep them)."""

    position: FloatArray
    velocity: FloatArray
    acceleration: FloatArray


@with_sections
class Generator:
    """Plans from the current state to the target when it changes; returns the next state.

    Parameters
    ----------
    ndof : int
        Number of joints.
    period : float
        Control period (s).
    {limits}
    jmax : float or sequence
        Jerk limit (rad/s^3); ``inf`` for acceleration-limited motion.
    position, velocity, acceleration : array_like, optional
        The start state (default: at rest at 0).
    sync : str or None
        Synchronization, as in :func:`trajkit.scurve`.

    Notes
    -----
    Each :meth:`update` runs one compiled call (plan if the target, the state or
    the interface changed, then evaluate); no :class:`~trajkit.Trajectory` is
    built. The start state may be beyond the limits (it is braked back), the
    target must be within them. :attr:`duration` is the time the motion still
    needed when the last cycle began (s).
    """

    @renamed_keywords(dt="period")
    def __init__(
        self,
        ndof: int,
        period: float,
        vmax: LimitSpec,
        amax: LimitSpec,
        jmax: ArrayLike,
        *,
        position: ArrayLike = 0.0,
        velocity: ArrayLike = 0.0,
        acceleration: ArrayLike = 0.0,
        sync: object = "time",
    ) -> None:
        if isinstance(ndof, bool) or not isinstance(ndof, int | np.integer) or ndof < 1:
            raise InvalidInputError(f"ndof must be a positive integer, got {ndof!r}")
        self.ndof = int(ndof)
        self.period = positive_scalar("period", period, unit="s")
        # Validate once with a target at the start: limits, sync and the start state.
        start = joint_vector("position", position, self.ndof, unit="rad")
        problem = limited.read_problem(
            "online", start, start, vmax, amax, jmax, v0=velocity, vf=0.0, a0=acceleration,
            af=0.0, sync=sync,
        )  # fmt: skip
        self._m = np.ascontiguousarray(problem.matrix.copy())
        self._sync = problem.sync
        self._position_control = np.zeros(self.ndof, np.int64)
        self._velocity_control = np.ones(self.ndof, np.int64)
        self._enabled = np.ones(self.ndof, np.int64)
        from trajkit.profiles._kernels.layout import SIZE

        self._records = np.empty((self.ndof, SIZE))
        self._own = np.empty(self.ndof)
        self._out = np.empty(4)
        self._next = np.empty((3, self.ndof))
        # Acceleration-limited joints carry no acceleration state into the next plan
        # (theirs jumps): the reported acceleration is kept apart.
        self._acceleration = self._m[4].copy()
        self._state = OnlineState(self._m[0], self._m[2], self._acceleration)
        self.duration = 0.0  # the motion's time left when the last cycle began (s)
        self._held: list[float | int | None] = [None] * 11  # numbers in the target rows
        from trajkit.profiles._kernels import solve

        self._inadmissible = solve.INADMISSIBLE
        self._remaining = solve.MEMO_REMAINING
        self._memo = np.zeros(solve.memo_size(self.ndof))  # the plan held between cycles
        self._cycle = solve.online_cycle

    @property
    def dt(self) -> float:
        """The old name of :attr:`period` (s); reading it warns."""
        warnings.warn(
            "Generator.dt is renamed Generator.period; the old name will be removed",
            FutureWarning,
            stacklevel=2,
        )
        return self.period

    @property
    def state(self) -> OnlineState:
        """The current state (the one the next :meth:`update` starts from)."""
        return self._state

    def update(
        self, target: ArrayLike, velocity: ArrayLike = 0.0, acceleration: ArrayLike = 0.0
    ) -> tuple[OnlineState, bool]:
        """Plan to ``target`` (with target velocity and acceleration) and step one period.

        Returns the new current state and whether it is the target state.
        """
        try:
            self._put(1, target)
            self._put(3, velocity)
            self._put(5, acceleration)
        except (TypeError, ValueError):
            # Not plain numbers: the validators name the argument.
            self._put(1, joint_vector("target", target, self.ndof, unit="rad"))
            self._put(3, joint_vector("velocity", velocity, self.ndof, unit="rad/s"))
            self._put(5, joint_vector("acceleration", acceleration, self.ndof, unit="rad/s^2"))
        return self._step(self._position_control)

    def update_velocity(
        self, velocity: ArrayLike, acceleration: ArrayLike = 0.0
    ) -> tuple[OnlineState, bool]:
        """Plan to a target velocity (and acceleration), no position target; step one period.

        The velocity interface, as :func:`trajkit.velocity_change` plans it: a jog
        at a commanded speed, a stop from any state (``velocity=0``). The target
        must be within the velocity and acceleration limits. Returns the new state
        and whether its velocity and acceleration are the target's.
        """
        try:
            self._put(3, velocity)
            self._put(5, acceleration)
        except (TypeError, ValueError):
            self._put(3, joint_vector("velocity", velocity, self.ndof, unit="rad/s"))
            self._put(5, joint_vector("acceleration", acceleration, self.ndof, unit="rad/s^2"))
        self._put(1, self._m[0])  # unused by the velocity law; kept finite for the checks
        return self._step(self._velocity_control)

    def _put(self, row: int, value: ArrayLike) -> None:
        """Write a target row of the problem; a number the row already holds is skipped.

        Only the rows the caller sets (targets) are remembered this way: the
        kernel writes the state rows.
        """
        if type(value) is float or type(value) is int:
            if self._held[row] == value:
                return
            self._m[row] = value
            self._held[row] = value
        else:
            self._held[row] = None
            self._m[row] = value

    def _step(self, control: np.ndarray) -> tuple[OnlineState, bool]:
        code = engine.run(
            "online_cycle", self._cycle, self._m, control, self._sync, self._enabled,
            self.period, self._records, self._own, self._out, self._next, self._acceleration,
            self._memo,
        )  # fmt: skip
        if code != engine.STATUS_OK:
            if code == self._inadmissible:
                self._explain()
            raise engine._failure("online", code, self._out, self._m, "")
        self.duration = float(self._memo[self._remaining])
        return self._state, self.duration <= self.period

    def _explain(self) -> None:
        limited.read_matrix("online", self._m)
        raise InvalidInputError(f"online: target {self._m[1].tolist()} is not admissible")
