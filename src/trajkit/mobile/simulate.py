"""Kinematic simulation of a wheeled base following a plan, with or without feedback."""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from trajkit._validation import FloatArray, finite_array, positive_scalar
from trajkit.curve import sample_times
from trajkit.errors import InvalidInputError
from trajkit.io.table import write_csv
from trajkit.limits import Bounds
from trajkit.mobile.control import (
    ControlLaw,
    Controller,
    Feedforward,
    nearest_path_distance,
    saturate,
)
from trajkit.mobile.limits import MobileLimits, check_limits
from trajkit.mobile.models import (
    DiffDrive,
    Model,
    constant_twist_pose,
    pose_array,
    resolve_model,
    rk4_step,
    wrap_angle,
)
from trajkit.mobile.plans import MAX_TRAVEL
from trajkit.mobile.trajectory import MobileState, MobileTrajectory, command_count
from trajkit.renamed import renamed_keywords

__all__ = ["HeldCommands", "SimulationLog", "log_fields", "simulate"]

_PATH_POINTS = 20_000  # samples of the desired path for the distance-to-path metric


@dataclass(frozen=True, eq=False)
class SimulationLog:
    """What a simulated run did, sample by sample, and how well it tracked.

    Attributes
    ----------
    t : ndarray, shape (n,)
        Times (s).
    desired, actual : ndarray, shape (n, 3)
        Planned and simulated poses ``(x, y, θ)``.
    desired_twist, commands : ndarray, shape (n, 2)
        The plan's twist and the (saturated) command sent, ``(v, ω)``.
    wheel_speeds : ndarray, shape (n, 2), or None
        Left and right wheel speeds of the commands (rad/s); None for a unicycle.
    path_distance : ndarray, shape (n,)
        Distance from the actual position to the desired path, wherever along it (m),
        measured on a polyline of 20,000 points of the path: accurate to its sagitta
        (about 2e-8 m on a few metres of gently curved path).
    controller : str
        The controller's name.
    """

    t: FloatArray
    desired: FloatArray
    actual: FloatArray
    desired_twist: FloatArray
    commands: FloatArray
    wheel_speeds: FloatArray | None
    path_distance: FloatArray
    controller: str

    @property
    def position_error(self) -> FloatArray:
        """``|p(t) - p_d(t)|`` at every sample (m): the error against the clock."""
        return np.hypot(*(self.actual[:, :2] - self.desired[:, :2]).T)

    @property
    def heading_error(self) -> FloatArray:
        """``θ(t) - θ_d(t)`` wrapped to [-π, π) (rad)."""
        return wrap_angle(self.actual[:, 2] - self.desired[:, 2])

    @property
    def rms_error(self) -> float:
        """Root mean square of the position error over the samples (m)."""
        return float(np.sqrt(np.mean(self.position_error**2)))

    @property
    def max_error(self) -> float:
        """Largest position error (m)."""
        return float(self.position_error.max())

    @property
    def final_position_error(self) -> float:
        """Position error at the last sample (m)."""
        return float(self.position_error[-1])

    @property
    def final_heading_error(self) -> float:
        """Magnitude of the heading error at the last sample (rad)."""
        return float(abs(self.heading_error[-1]))

    @property
    def max_path_distance(self) -> float:
        """Largest distance from the desired path (m): pure pursuit's measure."""
        return float(self.path_distance.max())

    def error_after(self, t: float, *, along_path: bool = False) -> float:
        """Largest error from time ``t`` on (m), e.g. once a start offset has decayed.

        The position error against the clock, or with ``along_path`` the distance
        from the path (for a path follower such as pure pursuit, which may lag).
        """
        late = self.t >= t
        if not late.any():
            raise InvalidInputError(f"no samples at or after t={t:g} s (the log ends at "
                                    f"{self.t[-1]:g} s)")  # fmt: skip
        error = self.path_distance if along_path else self.position_error
        return float(error[late].max())

    def summary(self) -> str:
        """One line of the metrics."""
        return (
            f"{self.controller}: RMS error {self.rms_error:.3g} m, max {self.max_error:.3g} m, "
            f"final {self.final_position_error:.3g} m / {np.degrees(self.final_heading_error):.3g}"
            f" deg, max distance from the path {self.max_path_distance:.3g} m"
        )

    def to_csv(self, path: str | os.PathLike[str]) -> Path:
        """Write every sample: time, desired and actual poses, twists and wheel speeds."""
        header = [
            "t [s]", "x_desired [m]", "y_desired [m]", "theta_desired [rad]",
            "x [m]", "y [m]", "theta [rad]", "v_desired [m/s]", "omega_desired [rad/s]",
            "v_command [m/s]", "omega_command [rad/s]",
        ]  # fmt: skip
        columns = [self.t[:, None], self.desired, self.actual, self.desired_twist, self.commands]
        if self.wheel_speeds is not None:
            header += ["wheel_left [rad/s]", "wheel_right [rad/s]"]
            columns.append(self.wheel_speeds)
        header.append("path_distance [m]")
        columns.append(self.path_distance[:, None])
        return write_csv(path, header, np.concatenate(columns, axis=1))

    @classmethod
    def from_csv(cls, path: str | os.PathLike[str]) -> SimulationLog:
        """Read a log written by :meth:`to_csv`, bit for bit (the controller: the file's name).

        Raises
        ------
        InvalidInputError
            A file without :meth:`to_csv`'s columns (the message names the first
            missing), or a malformed row.
        """
        from trajkit.io.table import named_columns, read_csv

        source = Path(path)
        header, table = read_csv(source)
        column = named_columns(source, header, table, LOG_COLUMNS)
        return cls(**csv_fields(column), **cls._csv_extras(source, header, table),
                   controller=source.stem)  # fmt: skip

    @classmethod
    def _csv_extras(cls, source: Path, header: list[str], table: FloatArray) -> dict:
        """The fields beyond :data:`LOG_COLUMNS` (a subclass's own), from the CSV table."""
        if "wheel_left [rad/s]" not in header:
            return {"wheel_speeds": None}
        wheels = ("wheel_left [rad/s]", "wheel_right [rad/s]")
        return {"wheel_speeds": csv_block(source, header, table, wheels)}


#: The columns every base log's CSV has.
LOG_COLUMNS = ("t [s]", "x_desired [m]", "y_desired [m]", "theta_desired [rad]", "x [m]", "y [m]",
                "theta [rad]", "v_desired [m/s]", "omega_desired [rad/s]", "v_command [m/s]",
                "omega_command [rad/s]", "path_distance [m]")  # fmt: skip


def csv_block(source: Path, header: list[str], table: FloatArray,
              names: tuple[str, ...]) -> FloatArray:  # fmt: skip
    """The columns ``names`` of a CSV table, side by side, (n, len(names))."""
    from trajkit.io.table import named_columns

    return np.stack(list(named_columns(source, header, table, names).values()), axis=1)


def csv_fields(column: dict[str, FloatArray]) -> dict[str, FloatArray]:
    """A base log's fields from its CSV columns (:data:`LOG_COLUMNS`)."""

    def stacked(*names: str) -> FloatArray:
        return np.stack([column[name] for name in names], axis=1)

    return {"t": column["t [s]"],
            "desired": stacked("x_desired [m]", "y_desired [m]", "theta_desired [rad]"),
            "actual": stacked("x [m]", "y [m]", "theta [rad]"),
            "desired_twist": stacked("v_desired [m/s]", "omega_desired [rad/s]"),
            "commands": stacked("v_command [m/s]", "omega_command [rad/s]"),
            "path_distance": column["path_distance [m]"]}  # fmt: skip


def _desired_rows(state: MobileState) -> list[tuple[float, ...]]:
    columns = (state.x, state.y, state.theta, state.v, state.omega,
               state.acceleration, state.angular_acceleration)  # fmt: skip
    return list(zip(*(c.tolist() for c in columns), strict=True))


def _one_sided(plan: MobileTrajectory, times: FloatArray, side: float) -> list[tuple[float, ...]]:
    """The desired state just after (``side`` +1) or before (-1) each of ``times``."""
    return _desired_rows(plan.state(np.nextafter(times, side * np.inf)))


def _noise(noise: ArrayLike | None) -> FloatArray | None:
    if noise is None:
        return None
    sigma = finite_array("noise", noise)
    if sigma.shape != (2,) or np.any(sigma < 0.0):
        raise InvalidInputError(
            "noise must be (position_sigma, heading_sigma) in m and rad, both >= 0, "
            f"got {sigma.tolist()}"
        )
    return sigma


@renamed_keywords(dt="sample_step")
def simulate(
    plan: MobileTrajectory,
    controller: Controller | None = None,
    *,
    sample_step: float = 0.001,
    initial_pose: ArrayLike | None = None,
    duration: float | None = None,
    command_rate_hz: float | None = None,
    model: Model | None = None,
    limits: MobileLimits | None = None,
    noise: ArrayLike | None = None,
    seed: int | None = None,
) -> SimulationLog:
    """Drive a robot with a controller along a plan and record what happens.

    Parameters
    ----------
    plan : MobileTrajectory
        What to follow.
    controller : Controller, optional
        :class:`Feedforward` (the default), :class:`Kanayama`,
        :class:`FeedbackLinearization`, :class:`PurePursuit`, or your own.
    sample_step : float
        Integration and logging step (s).
    initial_pose : array_like, optional
        Where the robot starts, ``(x, y, θ)`` or ``(x, y)`` with the plan's start
        heading (default: the plan's start pose).
    duration : float, optional
        How long to simulate (s); default the plan's duration. After the plan's
        end the desired state stands still at its last pose.
    command_rate_hz : float, optional
        ``None``: the controller acts continuously and the motion is integrated
        with RK4. A rate: commands are computed at that rate, held in between
        (like a base controller receiving them) and the motion between them is
        the exact arc; commands are then also limited in their rate of change by
        the acceleration limits (while the wheels stay within theirs).
    model : Unicycle or DiffDrive, optional
        The simulated robot (default: the plan's model); e.g. a plan made for a
        bare unicycle, driven on a base whose wheels saturate.
    limits : MobileLimits, optional
        Commands are saturated to these (default: the limits the plan was made
        for, or the simulated model's when ``model`` is given).
    noise : (float, float), optional
        Standard deviations of the position (m) and heading (rad) measurement
        noise the controller sees, drawn anew every step.
    seed : int, optional
        Seed of the noise generator: the same seed gives the same run.

    Returns
    -------
    SimulationLog
    """
    if not isinstance(plan, MobileTrajectory):
        raise InvalidInputError(f"plan must be a MobileTrajectory, got {type(plan).__name__}")
    controller = Feedforward() if controller is None else controller
    if not callable(getattr(controller, "law", None)):
        raise InvalidInputError(
            f"controller must have a law(plan, start) method, got {type(controller).__name__}"
        )
    step = positive_scalar("sample_step", sample_step, unit="s")
    end = plan.duration if duration is None else positive_scalar("duration", duration, unit="s")
    if end <= 0.0:
        raise InvalidInputError("the plan has no duration to simulate; pass duration=")
    start = plan.start_pose
    if initial_pose is not None:
        given = finite_array("initial_pose", initial_pose)
        # A position alone starts with the plan's heading.
        start = pose_array("initial_pose", [*given, start[2]] if given.shape == (2,) else given)
        with np.errstate(over="ignore", invalid="ignore"):
            away = float(np.hypot(*(start[:2] - plan.start_pose[:2])))
        # Farther, the tracking errors overflow (and the path search finds no vertex).
        if not away <= MAX_TRAVEL:
            raise InvalidInputError(
                f"initial_pose is {away:.3g} m from the plan's start; at most {MAX_TRAVEL:g} m"
            )
    robot = plan.model if model is None else resolve_model(model)
    if limits is None:
        limits = plan.limits if model is None else robot.limits
    limits = check_limits(limits)
    sigma = _noise(noise)
    rng = np.random.default_rng(seed)
    law = controller.law(plan, start)
    times = sample_times(0.0, end, step)
    if command_rate_hz is None:
        actual, commands = _continuous(plan, law, start, times, robot, limits, sigma, rng)
    else:
        rate = positive_scalar("command_rate_hz", command_rate_hz, unit="Hz")
        actual, commands = _held(plan, law, start, times, rate, robot, limits, sigma, rng)
    fields = log_fields(plan, times, actual, commands, robot)
    return SimulationLog(
        **fields, controller=getattr(controller, "name", type(controller).__name__)
    )


def log_fields(
    plan: MobileTrajectory,
    times: FloatArray,
    actual: FloatArray,
    commands: FloatArray,
    robot: Model,
) -> dict[str, FloatArray | None]:
    """The fields of a :class:`SimulationLog` that follow from the run's poses and commands."""
    desired = plan.state(times)
    path = plan.state(np.linspace(0.0, plan.duration, _PATH_POINTS))
    wheels = None
    if isinstance(robot, DiffDrive):
        wheels = robot.wheel_speeds(commands[:, 0], commands[:, 1])
    return {
        "t": times,
        "desired": desired.pose,
        "actual": actual,
        "desired_twist": desired.twist,
        "commands": commands,
        "wheel_speeds": wheels,
        "path_distance": nearest_path_distance(np.stack([path.x, path.y], 1), actual[:, :2]),
    }


def _measured(pose: FloatArray, sigma: FloatArray | None, rng: np.random.Generator) -> FloatArray:
    if sigma is None:
        return pose
    return pose + rng.normal(0.0, [sigma[0], sigma[0], sigma[1]])


def _continuous(
    plan: MobileTrajectory,
    law: ControlLaw,
    start: FloatArray,
    times: FloatArray,
    model: Model,
    limits: MobileLimits,
    sigma: FloatArray | None,
    rng: np.random.Generator,
) -> tuple[FloatArray, FloatArray]:
    """RK4 on ``(x, y, θ, internal)`` with the law evaluated at every stage."""
    # The desired state at every step's start, middle and end, in one vectorized call.
    middles = (times[:-1] + times[1:]) / 2.0
    # Each step follows the plan over its own interval: where the twist jumps at a step's
    # start or end (between arcs, at the plan's end) the step sees the side within it.
    starts = _one_sided(plan, times[:-1], 1.0) + _desired_rows(plan.state(times[-1:]))
    ends = [starts[0], *_one_sided(plan, times[1:], -1.0)]
    mids = _desired_rows(plan.state(middles))
    state = np.concatenate([start, law.initial_state])
    out = np.empty((times.size, 3))
    commands = np.empty((times.size, 2))
    for k in range(times.size):  # a closed loop is sequential by nature
        pose = state[:3]
        seen = _measured(pose, sigma, rng)
        law.advance(times[k], seen)
        v, w, _ = law(times[k], seen, starts[k], state[3:])
        commands[k] = saturate(v, w, model, limits)
        out[k] = pose
        if k == times.size - 1:
            break
        stages = (
            seen - pose,  # the same measurement error through the step
            (times[k], middles[k], times[k + 1]),
            (starts[k], mids[k], ends[k + 1]),
        )

        def rate(stage: int, s: FloatArray, step: tuple = stages) -> FloatArray:
            offset, when, wanted = step
            v, w, internal_rate = law(when[stage], s[:3] + offset, wanted[stage], s[3:])
            v, w = saturate(v, w, model, limits)
            return np.concatenate([[v * np.cos(s[2]), v * np.sin(s[2]), w], internal_rate])

        state = rk4_step(rate, state, float(times[k + 1] - times[k]))
    return out, commands


def _toward(
    previous: tuple[float, float], command: tuple[float, float], model: Model, limits: MobileLimits
) -> tuple[float, float]:
    """The command on the way from ``previous`` to ``command`` nearest it within the wheel limit.

    Limiting ``v`` and ``ω`` to their accelerations one at a time can leave a wheel
    past its limit: the box spanned by two commands within the wheel limit need not
    lie within it. Every point of the segment from ``previous`` (within every limit)
    keeps both acceleration bounds, and the wheel speeds are linear along it.
    """
    if not isinstance(model, DiffDrive) or limits.wheel_speed is None:
        return command
    lower, upper = float(limits.wheel_speed.lower), float(limits.wheel_speed.upper)
    fraction = 1.0
    for before, after in zip(model.wheel_pair(*previous), model.wheel_pair(*command), strict=True):
        bound = upper if after > upper else lower if after < lower else None
        if bound is not None:
            fraction = min(fraction, (bound - before) / (after - before))
    fraction = min(max(fraction, 0.0), 1.0)
    return (
        previous[0] + fraction * (command[0] - previous[0]),
        previous[1] + fraction * (command[1] - previous[1]),
    )


class HeldCommands:
    """The commands of a loop that sends one every ``1 / rate_hz`` s and holds it.

    Each call takes the pose the controller sees at the next command time and
    returns the command: the control law's output, saturated to the limits, then
    limited in its change by the acceleration limits (while the wheels stay
    within theirs). The plant between commands is the caller's: exact arcs here,
    physics in :mod:`trajkit.sim`.
    """

    def __init__(
        self,
        plan: MobileTrajectory,
        law: ControlLaw,
        end: float,
        rate_hz: float,
        model: Model,
        limits: MobileLimits,
    ) -> None:
        self.period = 1.0 / rate_hz
        # The commands sent before the end, and one more at the end that holds for no time.
        count = command_count(end, rate_hz) + 1
        self.times = self.period * np.arange(count)
        # Each command holds for the period after it (one at the end holds nothing).
        holding = self.times < end
        self._desired = _one_sided(plan, self.times[holding], 1.0)
        self._desired += _desired_rows(plan.state(self.times[~holding]))
        self._law, self._model, self._limits = law, model, limits
        self._internal = np.array(law.initial_state, dtype=float)
        self._previous: tuple[float, float] | None = None
        self._sent = 0

    def __call__(self, seen: FloatArray) -> tuple[float, float]:
        """The next command ``(v, ω)`` for the measured pose ``seen``."""
        k, law, limits = self._sent, self._law, self._limits
        law.advance(self.times[k], seen)
        v, w, internal_rate = law(self.times[k], seen, self._desired[k], self._internal)
        v, w = saturate(v, w, self._model, limits)
        if self._previous is not None:
            # A held command can only change as fast as the acceleration limits allow.
            v = _rate_limited(v, self._previous[0], limits.acceleration, self.period)
            w = _rate_limited(w, self._previous[1], limits.angular_acceleration, self.period)
            v, w = _toward(self._previous, (v, w), self._model, limits)
        self._previous = (v, w)
        self._internal = self._internal + self.period * internal_rate
        self._sent += 1
        return v, w


def _held(
    plan: MobileTrajectory,
    law: ControlLaw,
    start: FloatArray,
    times: FloatArray,
    rate_hz: float,
    model: Model,
    limits: MobileLimits,
    sigma: FloatArray | None,
    rng: np.random.Generator,
) -> tuple[FloatArray, FloatArray]:
    """Commands every ``1 / rate_hz`` s, held; exact arcs in between; log on ``times``."""
    commander = HeldCommands(plan, law, times[-1], rate_hz, model, limits)
    count, period = commander.times.size, commander.period
    pose = start.copy()
    held = np.empty((count, 2))
    poses = np.empty((count, 3))
    for k in range(count):  # a closed loop is sequential by nature
        held[k] = commander(_measured(pose, sigma, rng))
        poses[k] = pose
        pose = constant_twist_pose(pose, held[k, 0], held[k, 1], period)
    # The motion on the logging grid: the arc from the last command time.
    which = np.minimum(np.floor(times / period + 1e-9).astype(int), count - 1)
    since = times - commander.times[which]
    out = constant_twist_pose(poses[which], held[which, 0], held[which, 1], since)
    return out, held[which]


def _rate_limited(value: float, previous: float, bounds: Bounds | None, period: float) -> float:
    """``value`` moved no further from ``previous`` than ``bounds`` (per s) allow in ``period``."""
    if bounds is None:
        return value
    return min(max(value, previous + float(bounds.lower) * period),
               previous + float(bounds.upper) * period)  # fmt: skip
