"""What a digital controller does to a joint trajectory, seen at the tool.

A controller with period ``Ts`` changes a planned trajectory in two ways:

* **Timing quantization.** Phase times are rounded up to whole periods, so the
  motion runs a little slower and ends later (the coursework's "numerical
  control"). Compared at the same instants, the tool is behind where the plan
  puts it; the final pose is unchanged.
* **Sampling.** The controller sends ``q(k Ts)`` and holds it (zero-order hold)
  or interpolates linearly in joint space until the next period, so between
  samples the commanded tool pose departs from the continuous one.

:func:`discretization_error` measures both in task space, per sample.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from trajkit._periods import whole_periods
from trajkit._validation import positive_scalar
from trajkit.errors import InvalidInputError
from trajkit.kinematics.chain import SerialChain
from trajkit.trajectory import Trajectory

FloatArray = NDArray[np.float64]

__all__ = ["DiscretizationError", "discretization_error", "quantized_duration"]


@dataclass(frozen=True)
class DiscretizationError:
    """Task-space errors of a trajectory run by a controller of period ``period``.

    Attributes
    ----------
    t : ndarray, shape (K,)
        Controller sample times ``k * period`` (s), up to the later of the two ends.
    timing_error : ndarray, shape (K,)
        Tool position distance between the quantized and the planned trajectory
        at each sample (length unit of the robot).
    sampling_error : ndarray, shape (K,)
        Largest tool position distance, over the period after each sample,
        between the continuous trajectory and what the controller commands.
    final_error : float
        Tool position distance between the two trajectories' end poses.
    period : float
        Controller period (s).
    duration, quantized_duration : float
        Planned and quantized durations (s).
    """

    t: FloatArray
    timing_error: FloatArray
    sampling_error: FloatArray
    final_error: float
    period: float
    duration: float
    quantized_duration: float

    @property
    def max_timing_error(self) -> float:
        """Largest timing error over the motion."""
        return float(self.timing_error.max())

    @property
    def max_sampling_error(self) -> float:
        """Largest sampling error over the motion."""
        return float(self.sampling_error.max())

    def __str__(self) -> str:
        k_t = int(np.argmax(self.timing_error))
        k_s = int(np.argmax(self.sampling_error))
        return "\n".join(
            [
                f"controller period {self.period:g} s: duration {self.duration:.6g} s -> "
                f"{self.quantized_duration:.6g} s",
                f"timing error: max {self.max_timing_error:.6g} at t={self.t[k_t]:.6g} s, "
                f"final {self.final_error:.3g}",
                f"sampling error: max {self.max_sampling_error:.6g} at t={self.t[k_s]:.6g} s",
            ]
        )


def quantized_duration(duration: float, period: float) -> float:
    """``duration`` rounded up to a whole number of periods (s).

    A duration already a whole number of periods, up to rounding, is kept.
    """
    duration = positive_scalar("duration", duration, unit="s")
    period = positive_scalar("period", period, unit="s")
    count = whole_periods(duration, period)
    return float(max(count, 1.0) * period)


def discretization_error(
    robot: SerialChain,
    trajectory: Trajectory,
    period: float,
    *,
    quantized: Trajectory | None = None,
    hold: Literal["zero", "linear"] = "zero",
    oversample: int = 16,
) -> DiscretizationError:
    """Tool-position errors from quantizing a trajectory's timing and from sampling it.

    Parameters
    ----------
    robot : SerialChain
    trajectory : Trajectory
        The planned (continuous-time) joint trajectory.
    period : float
        Controller period ``Ts`` (s).
    quantized : Trajectory, optional
        The trajectory as the controller runs it, e.g. the same planner called
        with ``period=period``. Default: ``trajectory`` slowed uniformly so that
        its duration is a whole number of periods.
    hold : {"zero", "linear"}
        Between samples the controller holds the last command, or interpolates
        linearly in joint space to the next one.
    oversample : int
        Points per period at which the sampling error is evaluated.

    Returns
    -------
    DiscretizationError
    """
    if not isinstance(robot, SerialChain):
        raise InvalidInputError(f"robot must be a trajkit SerialChain, got {type(robot).__name__}")
    for name, value in (("trajectory", trajectory), ("quantized", quantized)):
        if value is not None and (not isinstance(value, Trajectory) or value.ndof != robot.ndof):
            raise InvalidInputError(
                f"{name} must be a Trajectory with {robot.ndof} joints, like the robot"
            )
    period = positive_scalar("period", period, unit="s")
    if hold not in ("zero", "linear"):
        raise InvalidInputError(f"hold must be 'zero' or 'linear', got {hold!r}")
    if not isinstance(oversample, int) or oversample < 2:
        raise InvalidInputError(f"oversample must be an integer >= 2, got {oversample!r}")
    duration = trajectory.duration
    if quantized is None:
        target = quantized_duration(duration, period) if duration > 0 else 0.0
        quantized = trajectory.time_scaled(target / duration) if duration > 0 else trajectory
    start = trajectory.start_time
    end = max(duration, quantized.duration)
    count = int(whole_periods(end, period))
    t = start + np.arange(count + 1) * period

    def tool(traj: Trajectory, times: FloatArray) -> FloatArray:
        return robot.fk(traj.position(times))[:, :3, 3]

    q_start = quantized.start_time
    timing = np.linalg.norm(tool(quantized, t - start + q_start) - tool(trajectory, t), axis=1)
    final = float(
        np.linalg.norm(
            tool(quantized, np.array([quantized.end_time]))
            - tool(trajectory, np.array([trajectory.end_time]))
        )
    )
    # Sub-samples inside each period: what the controller commands against the plan.
    fraction = np.arange(oversample) / oversample
    inside = t[:, np.newaxis] + period * fraction  # (K, oversample)
    actual = tool(trajectory, inside.reshape(-1)).reshape(t.size, oversample, 3)
    q_now = trajectory.position(t)
    if hold == "zero":
        commanded_q = np.repeat(q_now[:, np.newaxis], oversample, axis=1)
    else:
        q_next = trajectory.position(t + period)
        commanded_q = (
            q_now[:, np.newaxis] + fraction[:, np.newaxis] * (q_next - q_now)[:, np.newaxis]
        )
    commanded = robot.fk(commanded_q.reshape(-1, robot.ndof))[:, :3, 3]
    sampling = np.linalg.norm(actual - commanded.reshape(t.size, oversample, 3), axis=2).max(axis=1)
    return DiscretizationError(
        t=t,
        timing_error=timing,
        sampling_error=sampling,
        final_error=final,
        period=period,
        duration=duration,
        quantized_duration=quantized.duration,
    )
