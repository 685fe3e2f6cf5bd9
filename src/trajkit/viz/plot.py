"""Plots of trajectories: stacked position / velocity / acceleration (/ jerk) panels.

This module imports matplotlib; ``import trajkit`` does not, and loads this module
on first use of ``trajkit.viz.plot``. Figures are built with the object-oriented API
(no pyplot state), so they can be made in threads and in scripts without a screen.
"""

from __future__ import annotations

import io
import os
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from matplotlib.figure import Figure

from trajkit._validation import positive_scalar
from trajkit.batch import BatchTrajectory
from trajkit.curve import Curve, check_order
from trajkit.errors import InvalidInputError
from trajkit.io.atomic import atomic_write
from trajkit.limits import Limits
from trajkit.samples import Samples
from trajkit.trajectory import Trajectory

if TYPE_CHECKING:
    from trajkit.io.ros2_read import JointStates
    from trajkit.kinematics.chain import SerialChain
    from trajkit.mobile.limits import MobileLimits
    from trajkit.mobile.simulate import SimulationLog
    from trajkit.mobile.trajectory import MobileTrajectory
    from trajkit.sim.arm import ArmLog
    from trajkit.taskspace.motion import TaskTrajectory
    from trajkit.time_optimal.constraints import PathLimit

__all__ = [
    "arm",
    "constraints",
    "mobile",
    "mobile_path",
    "profiles",
    "recorded",
    "save",
    "task_space",
    "tracking",
]

_QUANTITIES = ("position", "velocity", "acceleration", "jerk")
_FIELDS = ("q", "qd", "qdd", "qddd")
_CURVE_POINTS = 1500  # enough for smooth curves on any screen


def _dense_times(curve: Curve) -> np.ndarray:
    """Evenly spaced times plus every breakpoint, so corners are drawn."""
    return np.union1d(
        np.linspace(curve.start_time, curve.end_time, _CURVE_POINTS), curve.breakpoints
    )


def _series(
    data: Curve | Samples, orders: list[int], unit: str | None
) -> tuple[np.ndarray, dict[int, np.ndarray], list[str], list[str], tuple[str, str]]:
    """Times, the values of each order, column names and units, and the parameter."""
    if isinstance(data, Samples):
        present = {order: getattr(data, _FIELDS[order]) for order in orders}
        units = [unit or data.unit] * data.ndof
        return data.t, present, list(data.names), units, ("time", "s")
    if isinstance(data, BatchTrajectory):
        raise InvalidInputError("a BatchTrajectory holds many problems: plot one of them, batch[i]")
    if not isinstance(data, Curve):
        raise InvalidInputError(
            f"data must be a trajkit curve (Trajectory, TaskTrajectory, "
            f"MobileTrajectory, a path...) or Samples, got {type(data).__name__}"
        )
    where = f" for a {type(data).__name__}"
    for order in orders:
        check_order(order, data.highest_order, where)
    times = _dense_times(data)
    present = {order: np.asarray(data.evaluate(times, order)) for order in orders}
    names = [name for name, _ in data.components]
    units = [unit or column_unit for _, column_unit in data.components]
    return times, present, names, units, data.parameter


def _axis_label(quantity: str, units: list[str], parameter_unit: str, order: int) -> str:
    # Per unit of the parameter: nothing to add for a dimensionless one (a path's u).
    per = ("", f"/{parameter_unit}", f"/{parameter_unit}²", f"/{parameter_unit}³")[order]
    per = per if parameter_unit else ""
    # A column of unknown unit (a bare Curve's) labels nothing rather than a guess.
    shown = [f"{u}{per}" for u in dict.fromkeys(units) if u]
    return f"{quantity} [{', '.join(shown)}]" if shown else quantity


def profiles(
    data: Curve | Samples,
    limits: Limits | None = None,
    *,
    orders: Sequence[int] = (0, 1, 2),
    degrees: bool = False,
    unit: str | None = None,
    names: Sequence[str] | None = None,
    title: str | None = None,
    width: float = 8.0,
    panel_height: float = 2.2,
) -> Figure:
    """Stacked panels, one per derivative order, a line per joint, limits dashed.

    Parameters
    ----------
    data : Curve or Samples
        Any trajkit curve (a :class:`~trajkit.Trajectory`, a task or mobile
        trajectory, a flat output, a geometric path) is drawn from its exact
        ``evaluate``, breakpoints included; Samples as given.
    limits : Limits, optional
        Bounds drawn as dashed lines in the joint's colour (black when shared).
    orders : sequence of int
        Which panels: 0 position, 1 velocity, 2 acceleration, 3 jerk (those the
        curve has: a base's trajectory stops at 2).
    degrees : bool
        Show angles in degrees (the data stay in radians): the columns in rad.
    unit : str, optional
        Position unit of every column for the labels; default the curve's own
        (``Trajectory``: rad; task space: m; a base: m and rad) or the Samples'.
    names : sequence of str, optional
        Labels for the legend; default the curve's components (q1.., x y z, x y θ).
    title : str, optional
        Figure title.
    width, panel_height : float
        Figure size in inches.

    Returns
    -------
    matplotlib.figure.Figure
    """
    panels = list(orders)
    if not panels or any(o not in (0, 1, 2, 3) for o in panels) or len(set(panels)) != len(panels):
        raise InvalidInputError(f"orders must be distinct values among 0, 1, 2, 3, got {orders}")
    if limits is not None and not isinstance(limits, Limits):
        raise InvalidInputError(f"limits must be a trajkit.Limits, got {type(limits).__name__}")
    times, values, default_names, units, (parameter, parameter_unit) = _series(data, panels, unit)
    ndof = len(units)
    labels = list(names) if names is not None else default_names
    if len(labels) != ndof:
        raise InvalidInputError(f"names gives {len(labels)} labels for {ndof} joints")
    scale = np.ones(ndof)
    if degrees:
        angles = np.array([u == "rad" for u in units])
        if not angles.any():
            raise InvalidInputError(
                f"degrees=True needs angles in rad, but the unit is {units[0]!r}"
            )
        scale[angles] = 180.0 / np.pi
        units = ["deg" if angle else u for u, angle in zip(units, angles, strict=True)]
    positive_scalar("width", width)
    positive_scalar("panel_height", panel_height)

    figure, axes = _stacked(width, panel_height * len(panels), len(panels))
    colors = [f"C{j % 10}" for j in range(ndof)]
    for ax, order in zip(axes, panels, strict=True):
        shown = values[order] * scale
        for j in range(ndof):
            ax.plot(times, shown[:, j], color=colors[j], label=labels[j], linewidth=1.6)
        bounds = None if limits is None else getattr(limits, _QUANTITIES[order])
        if bounds is not None:
            lower, upper = bounds.for_ndof(_QUANTITIES[order], ndof)
            _draw_bounds(ax, lower * scale, upper * scale, colors, _QUANTITIES[order], labels)
        ax.set_ylabel(_axis_label(_QUANTITIES[order], units, parameter_unit, order))
        ax.grid(True, alpha=0.3)
        if ax is axes[0] or bounds is not None:  # the joints once, and every limit drawn
            ax.legend(loc="best", fontsize="small", ncols=min(ndof + 1, 6))
    axes[-1].set_xlabel(f"{parameter} [{parameter_unit}]" if parameter_unit else parameter)
    if title:
        figure.suptitle(title)
    return figure


def _stacked(width: float, height: float, count: int) -> tuple[Figure, np.ndarray]:
    """A figure of ``width`` by ``height`` inches and its ``count`` panels sharing x."""
    figure = Figure(figsize=(width, height), layout="constrained")
    return figure, figure.subplots(count, 1, sharex=True, squeeze=False)[:, 0]


def _label_time_panels(axes: np.ndarray, ylabels: Sequence[str], loc: str, columns: int) -> None:
    """Label each panel, grid it, give it a legend; the bottom one's x axis is time."""
    for ax, label in zip(axes, ylabels, strict=True):
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
        ax.legend(loc=loc, fontsize="small", ncols=columns)
    axes[-1].set_xlabel("time [s]")


def _draw_bounds(ax, lower: np.ndarray, upper: np.ndarray, colors: list[str], quantity: str,
                 names: Sequence[str]) -> None:  # fmt: skip
    """Dashed bound lines, named once in the legend: ``velocity limit`` or ``q1 limit``.

    The y range grows to show them (a horizontal line alone does not widen it).
    """
    shared = np.all(lower == lower[0]) and np.all(upper == upper[0])
    finite = [float(v) for v in (*lower, *upper) if np.isfinite(v)]
    if finite:
        bottom, top = ax.get_ylim()
        bottom, top = min(bottom, *finite), max(top, *finite)
        pad = 0.05 * (top - bottom)
        ax.set_ylim(bottom - pad, top + pad)
    for k, side in enumerate((lower, upper)):
        if shared:
            ax.axhline(side[0], color="black", linestyle="--", linewidth=1.0, alpha=0.7,
                       label=f"{quantity} limit" if k == 0 else None)  # fmt: skip
        else:
            for j, value in enumerate(side):
                ax.axhline(value, color=colors[j], linestyle="--", linewidth=1.0, alpha=0.7,
                           label=f"{names[j]} limit" if k == 0 else None)  # fmt: skip


_VIEWS = {"xy": (0, 1), "xz": (0, 2), "yz": (1, 2)}


def arm(
    robot: SerialChain,
    trajectory: Trajectory,
    *,
    instants: int = 5,
    view: str = "3d",
    title: str | None = None,
    size: float = 6.0,
) -> Figure:
    """The arm drawn at a few instants, lighter to darker in time, with the tool path.

    Parameters
    ----------
    robot : SerialChain
    trajectory : Trajectory
        Joint trajectory of ``robot``.
    instants : int
        How many poses to draw, evenly spaced from start to end (>= 1).
    view : {"3d", "xy", "xz", "yz"}
        A 3-D view, or the projection onto two world axes.
    title : str, optional
        Axes title; default the robot's name, the number of poses and their time span.
    size : float
        Figure width and height (inches).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from trajkit.kinematics.drawing import link_positions

    if view not in ("3d", *_VIEWS):
        raise InvalidInputError(f"view must be '3d', 'xy', 'xz' or 'yz', got {view!r}")
    if not isinstance(instants, int) or instants < 1:
        raise InvalidInputError(f"instants must be an integer >= 1, got {instants!r}")
    times = np.linspace(trajectory.start_time, trajectory.end_time, instants)
    poses = link_positions(robot, trajectory, times)
    path = link_positions(
        robot, trajectory, np.linspace(trajectory.start_time, trajectory.end_time, 400)
    )[:, -1]
    figure = Figure(figsize=(size, size), layout="constrained")
    shades = np.linspace(0.35, 1.0, instants)
    if view == "3d":
        ax = figure.add_subplot(projection="3d")
        ax.plot(*path.T, color="tab:red", lw=1.5, label="tool path")
        for pose, shade in zip(poses, shades, strict=True):
            ax.plot(*pose.T, "-o", color=(0.1, 0.3, 0.6, shade), lw=3, ms=4)
        ax.set_zlabel("z")
        every = np.concatenate([poses.reshape(-1, 3), path])
        span = (every.max(axis=0) - every.min(axis=0)).max() / 2 or 1.0
        middle = (every.max(axis=0) + every.min(axis=0)) / 2
        ax.set_xlim(middle[0] - span, middle[0] + span)
        ax.set_ylim(middle[1] - span, middle[1] + span)
        ax.set_zlim(middle[2] - span, middle[2] + span)
        labels = ("x", "y")
    else:
        a, b = _VIEWS[view]
        ax = figure.add_subplot()
        ax.plot(path[:, a], path[:, b], color="tab:red", lw=1.5, label="tool path")
        for pose, shade in zip(poses, shades, strict=True):
            ax.plot(pose[:, a], pose[:, b], "-o", color=(0.1, 0.3, 0.6, shade), lw=3, ms=4)
        ax.set_aspect("equal", adjustable="datalim")
        ax.grid(True, alpha=0.3)
        labels = (view[0], view[1])
    ax.set_xlabel(labels[0])
    ax.set_ylabel(labels[1])
    ax.legend(loc="best")
    ax.set_title(title or f"{robot.name}: {instants} poses, t = {times[0]:g}..{times[-1]:g} s")
    return figure


def task_space(
    task: TaskTrajectory, *, unit: str = "m", title: str | None = None, width: float = 8.0
) -> Figure:
    """Tool position, velocity and acceleration components against time.

    Parameters
    ----------
    task : TaskTrajectory
    unit : str
        The path's length unit, for the labels (m by default; "cm" for seed 003).
    title : str, optional
        Title of the top panel; default "task space" and the duration.
    width : float
        Figure width (inches).

    Returns
    -------
    matplotlib.figure.Figure
        Three panels (x, y, z components and the magnitude of velocity and
        acceleration), plus angular velocity when the task has orientation.
    """
    times = _dense_times(task)
    state = task.state(times)
    panels = [
        ("position", state.position, unit),
        ("velocity", state.velocity, f"{unit}/s"),
        ("acceleration", state.acceleration, f"{unit}/s²"),
    ]
    if state.angular_velocity is not None:
        panels.append(("angular velocity", state.angular_velocity, "rad/s"))
    figure, axes = _stacked(width, 2.2 * len(panels), len(panels))
    for ax, (name, values, _) in zip(axes, panels, strict=True):
        for k, axis_name in enumerate("xyz"):
            ax.plot(times, values[:, k], label=axis_name)
        if name != "position":
            ax.plot(times, np.linalg.norm(values, axis=1), "k--", lw=1, label="magnitude")
    ylabels = [f"{name} [{label_unit}]" for name, _, label_unit in panels]
    _label_time_panels(axes, ylabels, "upper right", 4)
    axes[0].set_title(title or f"task space, {task.duration:.6g} s")
    return figure


def _mobile_series(data: MobileTrajectory | SimulationLog) -> tuple[np.ndarray, dict, dict | None]:
    """Times, the desired series and (for a simulation log) the actual ones."""
    from trajkit.mobile.simulate import SimulationLog
    from trajkit.mobile.trajectory import MobileTrajectory

    if isinstance(data, MobileTrajectory):
        times = np.union1d(np.linspace(0.0, data.duration, _CURVE_POINTS), data.breakpoints)
        state = data.state(times)
        desired = {"pose": state.pose, "twist": state.twist}
        return times, desired, None
    if isinstance(data, SimulationLog):
        desired = {"pose": data.desired, "twist": data.desired_twist}
        actual = {"pose": data.actual, "twist": data.commands}
        return data.t, desired, actual
    raise InvalidInputError(
        f"data must be a MobileTrajectory or a SimulationLog, got {type(data).__name__}"
    )


def mobile(
    data: MobileTrajectory | SimulationLog,
    *,
    limits: MobileLimits | None = None,
    title: str | None = None,
    width: float = 8.0,
) -> Figure:
    """A wheeled robot's run against time: its twist, velocity, pose and (a run's) errors.

    Panels: forward speed v and turn rate ω with their limits; the velocity in the
    world frame (ẋ, ẏ), as the coursework draws it; position (x, y); heading θ. For
    a :class:`~trajkit.mobile.SimulationLog` the plan is dashed, the commands sent
    solid and the measured twist (from the change of the simulated pose over each
    sample) dotted, and a last panel shows the tracking errors.

    Parameters
    ----------
    data : MobileTrajectory or SimulationLog
    limits : MobileLimits, optional
        Speed and turn-rate bounds drawn (and named in the legends); default a plan's
        own (:attr:`MobileTrajectory.limits`), none for a log.
    title : str, optional
        Figure title (none by default).
    width : float
        Figure width (inches).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from trajkit.io.ros2_run import body_twist
    from trajkit.mobile.simulate import SimulationLog
    from trajkit.mobile.trajectory import world_velocity

    times, desired, actual = _mobile_series(data)
    positive_scalar("width", width)
    if limits is None and not isinstance(data, SimulationLog):
        limits = data.limits
    count = 6 if actual is not None else 5
    figure, axes = _stacked(width, 2.0 * count + 0.4, count)

    planned = "--" if actual is not None else "-"
    twists = [("planned", desired["twist"], planned)]
    poses = [("planned", desired["pose"], desired["twist"], planned)]
    if actual is not None:
        measured = body_twist(times, actual["pose"])  # 0 at the first sample: dropped
        twists += [("commanded", actual["twist"], "-"), ("measured", measured, ":")]
        poses.append(("actual", actual["pose"], measured, "-"))
    for label, twist, style in twists:
        first = 1 if label == "measured" else 0
        for ax, k, color in ((axes[0], 0, "C0"), (axes[1], 1, "C2")):
            ax.plot(times[first:], twist[first:, k], style,
                    color="C3" if label == "measured" else color,
                    label=f"{'vω'[k]} {label}")  # fmt: skip
    for ax, bound, quantity in ((axes[0], getattr(limits, "velocity", None), "speed"),
                                (axes[1], getattr(limits, "angular_velocity", None),
                                 "turn-rate")):  # fmt: skip
        if bound is not None:
            lower, upper = bound.for_ndof(quantity, 1)
            _draw_bounds(ax, lower, upper, ["black"], quantity, [quantity])
    for label, pose, twist, style in poses:
        velocity = world_velocity(twist[:, 0], pose[:, 2])
        axes[2].plot(times, velocity[:, 0], style, color="C0", label=f"ẋ {label}")
        axes[2].plot(times, velocity[:, 1], style, color="C1", label=f"ẏ {label}")
        axes[3].plot(times, pose[:, 0], style, color="C0", label=f"x {label}")
        axes[3].plot(times, pose[:, 1], style, color="C1", label=f"y {label}")
        axes[4].plot(times, pose[:, 2], style, color="C3", label=f"θ {label}")
    ylabels = ["forward speed v [m/s]", "turn rate ω [rad/s]", "world velocity [m/s]",
               "position [m]", "heading [rad]"]  # fmt: skip
    if actual is not None:
        axes[5].plot(times, data.position_error, color="C0", label="position error [m]")
        axes[5].plot(times, data.heading_error, color="C3", label="heading error [rad]")
        ylabels.append("error [m | rad]")
    _label_time_panels(axes, ylabels, "best", 2)
    if title:
        figure.suptitle(title)
    return figure


def mobile_path(
    data: MobileTrajectory | SimulationLog,
    *,
    robots: int = 8,
    title: str | None = None,
    size: float = 6.0,
) -> Figure:
    """The XY path, planned against actual for a simulation, with the robot drawn.

    Parameters
    ----------
    data : MobileTrajectory or SimulationLog
    robots : int
        How many times to draw the robot (a triangle pointing along its
        heading), evenly spaced in time (>= 0).
    title : str, optional
        Axes title; default "path" and the end time.
    size : float
        Figure width and height (inches).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.patches import Polygon

    times, desired, actual = _mobile_series(data)
    if not isinstance(robots, int) or robots < 0:
        raise InvalidInputError(f"robots must be an integer >= 0, got {robots!r}")
    figure = Figure(figsize=(size, size), layout="constrained")
    ax = figure.add_subplot()
    pose = desired["pose"]
    ax.plot(pose[:, 0], pose[:, 1], "--" if actual is not None else "-", color="C0",
            label="planned")  # fmt: skip
    drawn = pose if actual is None else actual["pose"]
    if actual is not None:
        ax.plot(drawn[:, 0], drawn[:, 1], color="C3", label="actual")
        odometry = getattr(data, "odometry", None)
        if odometry is not None:
            ax.plot(odometry[:, 0], odometry[:, 1], ":", color="C2", label="odometry")
    extent = np.ptp(np.concatenate([pose[:, :2], drawn[:, :2]]), axis=0).max() or 1.0
    body = 0.04 * extent
    if robots:
        for i in np.linspace(0, len(times) - 1, robots).round().astype(int):
            x, y, theta = drawn[i]
            c, s = np.cos(theta), np.sin(theta)
            corners = np.array([[1.6, 0.0], [-0.8, 0.6], [-0.8, -0.6]]) * body
            rotated = corners @ np.array([[c, s], [-s, c]]) + [x, y]
            ax.add_patch(Polygon(rotated, closed=True, facecolor="0.6", edgecolor="black"))
    # A closed path (a figure eight) ends where it starts: the end is a hollow square
    # around the start's dot, which is drawn on top.
    ax.plot(*drawn[-1, :2], "s", markersize=11, markerfacecolor="none", markeredgecolor="black",
            markeredgewidth=1.5, label="end", zorder=4)  # fmt: skip
    ax.plot(*drawn[0, :2], "o", color="green", markersize=6, label="start", zorder=5)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize="small")
    ax.set_title(title or f"path, {times[-1]:.6g} s")
    return figure


def tracking(
    log: ArmLog, *, degrees: bool = True, title: str | None = None, width: float = 8.0
) -> Figure:
    """A simulated arm run: desired against actual position, the error, the efforts.

    Parameters
    ----------
    log : trajkit.sim.ArmLog
    degrees : bool
        Angles in degrees (else radians).
    title : str, optional
        Title of the top panel; default the controller's name.
    width : float
        Figure width (inches).

    Returns
    -------
    matplotlib.figure.Figure
        Four panels against time: positions and velocities (desired dashed, actual
        solid), tracking error ``q − q_d``, and actuator torques, one color per joint.
    """
    from trajkit.sim.arm import ArmLog

    if not isinstance(log, ArmLog):
        raise InvalidInputError(f"log must be a trajkit.sim.ArmLog, got {type(log).__name__}")
    positive_scalar("width", width)
    figure, axes = _stacked(width, 9.4, 4)
    units: set[str] = set()
    efforts: set[str] = set()
    for j, name in enumerate(log.joint_names):
        color = f"C{j % 10}"
        # Angles in degrees (or radians), slides in metres; torques or forces.
        scale, unit = (180.0 / np.pi if degrees else 1.0, "deg" if degrees else "rad")
        if not log.revolute[j]:
            scale, unit = 1.0, "m"
        units.add(unit)
        efforts.add("N·m" if log.revolute[j] else "N")
        for ax, desired, actual in (
            (axes[0], log.desired, log.actual),
            (axes[1], log.desired_velocity, log.actual_velocity),
        ):
            ax.plot(log.t, desired[:, j] * scale, "--", color=color, label=f"{name} desired")
            ax.plot(log.t, actual[:, j] * scale, color=color, label=f"{name} actual")
        axes[2].plot(log.t, log.error[:, j] * scale, color=color, label=name)
        axes[3].plot(log.t, log.efforts[:, j], color=color, label=name)
    unit, effort = " | ".join(sorted(units)), " | ".join(sorted(efforts))
    speed = " | ".join(sorted(f"{u}/s" for u in units))
    ylabels = (f"position [{unit}]", f"velocity [{speed}]", f"error q − q_d [{unit}]",
               f"effort [{effort}]")  # fmt: skip
    _label_time_panels(axes, ylabels, "best", 2)
    axes[0].set_title(title or f"{log.controller}: desired against actual")
    return figure


def recorded(
    states: JointStates,
    plan: Trajectory | None = None,
    *,
    degrees: bool = False,
    limits: Limits | None = None,
    title: str | None = None,
    width: float = 8.0,
) -> Figure:
    """Recorded joint states (a bag's) against the plan they followed.

    Parameters
    ----------
    states : trajkit.io.ros2_read.JointStates
    plan : Trajectory, optional
        What was commanded (a bag's joint trajectory), on the same clock.
    degrees : bool
        Angles in degrees (else radians).
    limits : Limits, optional
        Velocity bounds drawn on the velocity panel, named in the legend.
    title : str, optional
    width : float
        Figure width (inches).

    Returns
    -------
    matplotlib.figure.Figure
        Panels against time: position and velocity (plan dashed, recorded solid),
        then the tracking error when there is a plan and the effort when the states
        carry it; one color per joint.
    """
    positive_scalar("width", width)
    scale, unit = (180.0 / np.pi, "deg") if degrees else (1.0, "rad")
    panels = [("position", f"position [{unit}]", states.position, 0),
              ("velocity", f"velocity [{unit}/s]", states.velocity, 1)]  # fmt: skip
    panels = [panel for panel in panels if panel[2] is not None]
    if plan is not None and states.position is not None:
        panels.append(("error", f"error q − q_d [{unit}]", None, 0))
    if states.effort is not None:
        panels.append(("effort", "effort [N·m | N]", states.effort, -1))
    if not panels:
        raise InvalidInputError("the joint states carry no positions, velocities or efforts")
    figure, axes = _stacked(width, 2.4 * len(panels) + 0.4, len(panels))
    dense = None if plan is None else np.clip(states.t, plan.start_time, plan.end_time)
    for ax, (kind, _, values, order) in zip(axes, panels, strict=True):
        for j, name in enumerate(states.names):
            color = f"C{j % 10}"
            if kind == "error":
                error = states.position[:, j] - plan.evaluate(dense, 0)[:, j]
                ax.plot(states.t, error * scale, color=color, label=name)
                continue
            factor = 1.0 if kind == "effort" else scale
            if plan is not None and order >= 0:
                t = _dense_times(plan)
                ax.plot(t, plan.evaluate(t, order)[:, j] * factor, "--", color=color,
                        label=f"{name} plan")  # fmt: skip
            both = plan is not None and order >= 0
            ax.plot(states.t, values[:, j] * factor, color=color,
                    label=f"{name} recorded" if both else name)  # fmt: skip
        if kind == "velocity" and limits is not None and limits.velocity is not None:
            lower, upper = limits.velocity.for_ndof("velocity", len(states.names))
            for side, text in ((lower, "lower"), (upper, "upper")):
                ax.axhline(float(np.min(side) if text == "lower" else np.max(side)) * scale,
                           color="black", linestyle=":", linewidth=1.0,
                           label=f"velocity limit ({text})")  # fmt: skip
    _label_time_panels(axes, [panel[1] for panel in panels], "best", 2)
    axes[0].set_title(title or ("recorded against the plan" if plan is not None else "recorded"))
    return figure


def constraints(
    trajectory: Trajectory,
    limits: PathLimit | Sequence[PathLimit],
    *,
    title: str | None = None,
    width: float = 8.0,
) -> Figure:
    """Torques and tool speeds of a joint trajectory against their limits.

    Parameters
    ----------
    trajectory : Trajectory
        Joint positions in time, of the limits' chain.
    limits : TorqueLimit, ToolLimit or a list of them
        What to draw: a TorqueLimit gives one panel with every joint's torque, a
        ToolLimit one panel per bounded quantity.
    title : str, optional
        Title of the top panel; default the largest ratio of a value to its bound.
    width : float
        Figure width (inches).

    Returns
    -------
    matplotlib.figure.Figure
        Panels against time; each limit dashed, in the color of its joint, and named
        in the legend.
    """
    from trajkit.time_optimal.constraints import checked_limits

    if not isinstance(trajectory, Trajectory):
        raise InvalidInputError(
            f"trajectory must be a trajkit.Trajectory, got {type(trajectory).__name__}"
        )
    items = checked_limits(limits, trajectory.ndof)
    if not items:
        raise InvalidInputError("limits must name at least one TorqueLimit or ToolLimit")
    positive_scalar("width", width)
    t = _dense_times(trajectory)
    q, qd, qdd = (trajectory.evaluate(t, order) for order in range(3))
    # One panel per torque limit, one per tool quantity.
    panels: list[tuple[PathLimit, list[int]]] = []
    for item in items:
        count = len(item.components())
        groups = [list(range(count))] if item.quantity == "torque" else [[k] for k in range(count)]
        panels += [(item, group) for group in groups]
    figure, axes = _stacked(width, 2.4 * len(panels) + 0.6, len(panels))
    ylabels, worst = [], 0.0
    for ax, (item, group) in zip(axes, panels, strict=True):
        values = item.values(q, qd, qdd)
        lower, upper = item.bounds()
        components = item.components()
        for k in group:
            color = f"C{k % 10}" if len(group) > 1 else "C0"
            name = components[k][0].removeprefix("torque of joint ")
            ax.plot(t, values[:, k], color=color, label=name)
            for side, bound in (("upper", upper[k]), ("lower", lower[k])):
                if np.isfinite(bound):
                    label = f"{side} limit" if len(group) == 1 else None
                    ax.axhline(bound, color=color, linestyle="--", linewidth=1.0, alpha=0.8,
                               label=label)  # fmt: skip
        if len(group) > 1:  # one legend entry says what the dashed lines are
            ax.plot([], [], color="black", linestyle="--", linewidth=1.0, label="limits (dashed)")
        units = sorted({components[k][1] for k in group})
        quantity = "torque" if item.quantity == "torque" else components[group[0]][0]
        ylabels.append(f"{quantity} [{' | '.join(units)}]")
        measured = item.check(trajectory)
        worst = max(worst, *(float(measured.ratios(q).max()) for q in measured.peaks))
    _label_time_panels(axes, ylabels, "best", 3)
    axes[0].set_title(title or f"against the limits: at most {worst:.4g} of a bound")
    return figure


def save(figure: Figure, path: str | os.PathLike[str], *, dpi: int = 120) -> Path:
    """Save ``figure`` atomically; the format follows the suffix (.png, .svg, .pdf)."""
    target = Path(path)
    kind = target.suffix.lower().lstrip(".")
    if kind not in {"png", "svg", "pdf"}:
        raise InvalidInputError(f"plot file must end in .png, .svg or .pdf, got {target.name!r}")
    buffer = io.BytesIO()
    figure.savefig(buffer, format=kind, dpi=dpi)
    data = buffer.getvalue()
    return atomic_write(target, lambda handle: handle.write(data))
