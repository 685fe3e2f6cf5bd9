"""Animations of plans: an arm in 2-D or 3-D, a wheeled robot on the plane; GIF or MP4.

Frames are taken at the trajectory's own times, ``k / fps``, so the animation
plays in real time: its frame rate and length follow the motion (a long motion can
be sped up with ``speed``). GIF needs only Pillow (with matplotlib); MP4 needs the
``ffmpeg`` program. A progress bar on standard error follows long renders.
The file is written under a temporary name beside its destination and renamed
into place, so an error or Ctrl-C leaves no partial file.
"""

from __future__ import annotations

import os
import shutil
import sys
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any, TextIO

import numpy as np
from matplotlib.figure import Figure

from trajkit._validation import FloatArray, positive_scalar
from trajkit.errors import InvalidInputError, MissingDependencyError
from trajkit.io.atomic import atomic_path, final_name
from trajkit.progress import ProgressBar

if TYPE_CHECKING:
    from trajkit.kinematics.chain import SerialChain
    from trajkit.mobile.simulate import SimulationLog
    from trajkit.mobile.trajectory import MobileTrajectory
    from trajkit.taskspace.joint_space import JointSpacePlan
    from trajkit.trajectory import Trajectory

__all__ = ["AnimationUnavailable", "arm", "mobile"]

_VIEWS = {"xy": (0, 1), "xz": (0, 2), "yz": (1, 2)}
#: More frames than this need an explicit, lower ``fps`` or a higher ``speed``.
MAX_FRAMES = 20_000
#: Renders of at least this many frames show a progress bar.
PROGRESS_FROM = 50


class AnimationUnavailable(MissingDependencyError):
    """The writer a format needs (ffmpeg for MP4) is not installed."""


def _frame_times(start: float, end: float, fps: float, speed: float) -> FloatArray:
    fps = positive_scalar("fps", fps, unit="frames/s")
    speed = positive_scalar("speed", speed)
    span = (end - start) / speed  # seconds of animation
    count = int(np.floor(span * fps + 1e-9)) + 1
    if count > MAX_FRAMES:
        raise InvalidInputError(
            f"{span:g} s at {fps:g} frames/s is {count} frames; at most {MAX_FRAMES} are drawn "
            "(lower fps or raise speed)"
        )
    times = start + speed * np.arange(count) / fps
    return np.append(times, end) if end - times[-1] > 1e-9 * max(1.0, end) else times


def _writer(path: Path, fps: float) -> Any:
    from matplotlib import animation

    kind = path.suffix.lower()
    if kind == ".gif":
        return animation.PillowWriter(fps=fps)
    if kind == ".mp4":
        if shutil.which("ffmpeg") is None:
            raise AnimationUnavailable(
                "MP4 needs the ffmpeg program, which is not on PATH (Debian: apt install "
                "ffmpeg); write a .gif instead",
                install="apt install ffmpeg",
            )
        return animation.FFMpegWriter(fps=fps, codec="libx264", extra_args=["-pix_fmt", "yuv420p"])
    raise InvalidInputError(f"an animation must end in .gif or .mp4, got {path.name!r}")


def _save(
    figure: Figure,
    draw: Callable[[int], None],
    count: int,
    path: Path,
    fps: float,
    progress: bool | TextIO,
) -> Path:
    from matplotlib import animation

    writer = _writer(path, fps)
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise InvalidInputError(f"the animation's folder {folder} does not exist")
    # The default bar is drawn only on a terminal: redrawn lines would clutter a log.
    stream = progress if not isinstance(progress, bool) else sys.stderr if progress else None
    if count < PROGRESS_FROM or (progress is True and not sys.stderr.isatty()):
        stream = None
    # A path staged by trajkit.io.atomic is a temporary: the bar shows the name the user chose.
    bar = ProgressBar(count, f"animating {final_name(path)}", stream, live=True)

    def frame_written(done: int, _total: int | None = None) -> None:
        bar(done + 1, f"{int(100 * (done + 1) / count):3d}%")

    movie = animation.FuncAnimation(figure, draw, frames=count, blit=False, repeat=False)
    try:
        with atomic_path(path) as scratch:
            movie.save(scratch, writer=writer, progress_callback=frame_written)
    except BaseException as exc:
        bar.close()
        interrupt = _interrupt_behind(exc)
        if interrupt is not None and interrupt is not exc:
            # Ctrl-C before the first frame makes the GIF writer fail on closing (no
            # frames: IndexError); the interrupt, not that consequence, is what happened.
            raise interrupt.with_traceback(None) from None
        raise
    return path


def _interrupt_behind(exc: BaseException) -> KeyboardInterrupt | None:
    """The KeyboardInterrupt that ``exc`` was raised while handling, if any."""
    seen: set[int] = set()
    current: BaseException | None = exc
    while current is not None and id(current) not in seen:
        if isinstance(current, KeyboardInterrupt):
            return current
        seen.add(id(current))
        current = current.__context__
    return None


def _joint_trajectory(robot: object, trajectory: object) -> Trajectory:
    """The joint trajectory to draw.

    A Trajectory, the one a JointSpacePlan holds, or the motion of a simulated arm (an
    ArmLog: cubics through its states).
    """
    from trajkit.io.trajectory_controller import controller_trajectory
    from trajkit.kinematics.chain import SerialChain
    from trajkit.sim.arm import ArmLog
    from trajkit.taskspace.joint_space import JointSpacePlan
    from trajkit.trajectory import Trajectory

    if not isinstance(robot, SerialChain):
        raise InvalidInputError(f"robot must be a trajkit SerialChain, got {type(robot).__name__}")
    if isinstance(trajectory, JointSpacePlan):
        trajectory = trajectory.trajectory  # what taskspace.to_joint_space plans
    if isinstance(trajectory, ArmLog):  # what the simulated arm did, between its samples too
        trajectory = controller_trajectory(trajectory.t, trajectory.actual,
                                           trajectory.actual_velocity)  # fmt: skip
    if not isinstance(trajectory, Trajectory):
        raise InvalidInputError(
            "trajectory must be a trajkit Trajectory, a taskspace JointSpacePlan or a "
            f"trajkit.sim.ArmLog, got {type(trajectory).__name__}"
        )
    if trajectory.ndof != robot.ndof:
        raise InvalidInputError(
            f"trajectory has {trajectory.ndof} joints but the robot has {robot.ndof}"
        )
    return trajectory


def arm(
    robot: SerialChain,
    trajectory: Trajectory | JointSpacePlan,
    path: str | os.PathLike[str],
    *,
    view: str = "3d",
    fps: float = 25.0,
    speed: float = 1.0,
    size: float = 5.0,
    title: str | None = None,
    progress: bool | TextIO = True,
) -> Path:
    """Animate an arm following a joint trajectory; write a GIF or MP4.

    Parameters
    ----------
    robot : SerialChain
    trajectory : Trajectory, JointSpacePlan or ArmLog
        Joint trajectory of ``robot``, the plan of
        :func:`trajkit.taskspace.to_joint_space` (its ``trajectory`` is drawn), or a
        simulated run of it (:class:`trajkit.sim.ArmLog`: the simulated joints, as
        cubics through their positions and velocities).
    path : path-like
        ``.gif`` (Pillow) or ``.mp4`` (needs ffmpeg).
    view : {"3d", "xy", "xz", "yz"}
        A 3-D view, or the projection onto two world axes.
    fps : float
        Frames per second of the animation.
    speed : float
        Playback speed: 1 is real time, 2 twice as fast.
    size : float
        Figure width and height (inches).
    title : str, optional
    progress : bool or text stream
        A progress bar for renders of 50 frames or more: on standard error when it
        is a terminal (``True``), on the given stream, or none (``False``).

    Returns
    -------
    Path
        The file written.
    """
    from trajkit.kinematics.drawing import link_positions

    trajectory = _joint_trajectory(robot, trajectory)
    if not isinstance(view, str) or view not in ("3d", *_VIEWS):
        raise InvalidInputError(f"view must be '3d', 'xy', 'xz' or 'yz', got {view!r}")
    target = Path(path)
    _writer(target, fps if isinstance(fps, (int, float)) else 25.0)  # the format, before any work
    times = _frame_times(trajectory.start_time, trajectory.end_time, fps, speed)
    poses = link_positions(robot, trajectory, times)  # (frames, ndof + 2, 3)
    tool = poses[:, -1]
    figure = Figure(figsize=(size, size), layout="constrained")
    every = poses.reshape(-1, 3)
    low, high = every.min(axis=0), every.max(axis=0)
    span = max(float((high - low).max()) / 2.0, 1e-6) * 1.1
    middle = (high + low) / 2.0
    if view == "3d":
        ax = figure.add_subplot(projection="3d")
        (links,) = ax.plot([], [], [], "-o", color="tab:blue", lw=3, ms=5)
        (trace,) = ax.plot([], [], [], color="tab:red", lw=1.2)
        for setter, m in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), middle, strict=True):
            setter(m - span, m + span)
        ax.set_zlabel("z [m]")
        # Room for the z label, which the constrained layout otherwise cuts off.
        ax.set_box_aspect(None, zoom=0.85)
        axes = (0, 1)

        def place(line: Any, points: FloatArray) -> None:
            line.set_data_3d(points[:, 0], points[:, 1], points[:, 2])
    else:
        axes = _VIEWS[view]
        ax = figure.add_subplot()
        (links,) = ax.plot([], [], "-o", color="tab:blue", lw=3, ms=5)
        (trace,) = ax.plot([], [], color="tab:red", lw=1.2)
        ax.set_xlim(middle[axes[0]] - span, middle[axes[0]] + span)
        ax.set_ylim(middle[axes[1]] - span, middle[axes[1]] + span)
        ax.set_aspect("equal")
        ax.grid(True, alpha=0.3)

        def place(line: Any, points: FloatArray) -> None:
            line.set_data(points[:, axes[0]], points[:, axes[1]])

    ax.set_xlabel(f"{'xyz'[axes[0]]} [m]")
    ax.set_ylabel(f"{'xyz'[axes[1]]} [m]")
    heading = title or robot.name
    label = ax.set_title(heading)

    def draw(frame: int) -> None:
        place(links, poses[frame])
        place(trace, tool[: frame + 1])
        label.set_text(f"{heading}   t = {times[frame]:.2f} s")

    return _save(figure, draw, times.size, target, fps, progress)


def mobile(
    data: MobileTrajectory | SimulationLog,
    path: str | os.PathLike[str],
    *,
    fps: float = 25.0,
    speed: float = 1.0,
    size: float = 5.0,
    title: str | None = None,
    progress: bool | TextIO = True,
) -> Path:
    """Animate a wheeled robot on the plane: the planned path, the robot, its trace.

    ``data`` is a plan or a simulation log (the actual motion then moves, the plan
    is drawn dashed). Other parameters as :func:`arm`.
    """
    from trajkit.mobile.simulate import SimulationLog
    from trajkit.mobile.trajectory import MobileTrajectory

    target = Path(path)
    _writer(target, fps if isinstance(fps, (int, float)) else 25.0)
    if isinstance(data, MobileTrajectory):
        times = _frame_times(0.0, data.duration, fps, speed)
        poses, planned = data.pose(times), data.pose(np.linspace(0.0, data.duration, 600))
    elif isinstance(data, SimulationLog):
        times = _frame_times(float(data.t[0]), float(data.t[-1]), fps, speed)
        rows = np.minimum(np.searchsorted(data.t, times), data.t.size - 1)
        poses, planned = data.actual[rows], data.desired
    else:
        raise InvalidInputError(
            f"data must be a MobileTrajectory or a SimulationLog, got {type(data).__name__}"
        )
    every = np.concatenate([poses[:, :2], planned[:, :2]])
    low, high = every.min(axis=0), every.max(axis=0)
    span = max(float((high - low).max()) / 2.0, 0.25) * 1.15
    middle = (high + low) / 2.0
    figure = Figure(figsize=(size, size), layout="constrained")
    ax = figure.add_subplot()
    ax.plot(planned[:, 0], planned[:, 1], "--", color="0.5", lw=1.2, label="planned")
    (trace,) = ax.plot([], [], color="tab:red", lw=1.5, label="robot")
    body = 0.06 * span
    from matplotlib.patches import Polygon

    robot = Polygon(np.zeros((3, 2)), closed=True, facecolor="tab:blue", edgecolor="black")
    ax.add_patch(robot)
    ax.set_xlim(middle[0] - span, middle[0] + span)
    ax.set_ylim(middle[1] - span, middle[1] + span)
    ax.set_aspect("equal")
    ax.grid(True, alpha=0.3)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.legend(loc="upper right", fontsize="small")
    heading = title or "wheeled robot"
    label = ax.set_title(heading)
    shape = np.array([[1.6, 0.0], [-0.8, 0.7], [-0.8, -0.7]]) * body

    def draw(frame: int) -> None:
        x, y, theta = poses[frame]
        c, s = np.cos(theta), np.sin(theta)
        robot.set_xy(shape @ np.array([[c, s], [-s, c]]) + [x, y])
        trace.set_data(poses[: frame + 1, 0], poses[: frame + 1, 1])
        label.set_text(f"{heading}   t = {times[frame]:.2f} s")

    return _save(figure, draw, times.size, target, fps, progress)
