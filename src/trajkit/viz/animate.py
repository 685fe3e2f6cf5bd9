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
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, TextIO

import numpy as np
from matplotlib.figure import Figure

from trajkit._validation import FloatArray, positive_scalar
from trajkit.errors import InvalidInputError, MissingDependencyError
from trajkit.io.atomic import atomic_path, final_name
from trajkit.progress import ProgressBar

if TYPE_CHECKING:
    from matplotlib.artist import Artist

    from trajkit.kinematics.chain import SerialChain
    from trajkit.mobile.simulate import SimulationLog
    from trajkit.mobile.trajectory import MobileTrajectory
    from trajkit.taskspace.joint_space import JointSpacePlan
    from trajkit.trajectory import Trajectory

__all__ = ["AnimationUnavailable", "arm", "mobile"]

_VIEWS = {"xy": (0, 1), "xz": (0, 2), "yz": (1, 2)}
#: More frames than this need an explicit, lower ``fps`` or a higher ``speed``.
MAX_FRAMES = 20_000
#: More frames than this are drawn at a lower frame rate, said on stderr: about 10 s of
#: rendering and 400 MB of GIF frames held until the file is written.
LONG_FRAMES = 1_500
#: Renders of at least this many frames show a progress bar.
PROGRESS_FROM = 50


class AnimationUnavailable(MissingDependencyError):
    """The writer a format needs (ffmpeg for MP4) is not installed."""


def _frame_times(start: float, end: float, fps: float, speed: float,
                 path: Path) -> tuple[FloatArray, float]:  # fmt: skip
    """The frames' times and the frame rate; a long render's rate is lowered (said on stderr).

    More than :data:`LONG_FRAMES` frames would take a minute or more and hold every
    frame in memory: the rate drops to fit them, and standard error says so.
    """
    fps = positive_scalar("fps", fps, unit="frames/s")
    speed = positive_scalar("speed", speed)
    span = (end - start) / speed  # seconds of animation
    count = int(np.floor(span * fps + 1e-9)) + 1
    if count > MAX_FRAMES:
        raise InvalidInputError(
            f"{span:g} s at {fps:g} frames/s is {count} frames; at most {MAX_FRAMES} are drawn "
            "(lower fps or raise speed)"
        )
    if count > LONG_FRAMES:
        lowered = np.floor(10.0 * (LONG_FRAMES - 1) / span) / 10.0
        if lowered > 0.0:
            print(f"trajkit: note: {final_name(path)}: {span:g} s at {fps:g} frames/s would be "
                  f"{count} frames; drawn at {lowered:g} frames/s instead (pass a lower fps "
                  "or a higher speed to choose)", file=sys.stderr)  # fmt: skip
            fps = float(lowered)
            count = int(np.floor(span * fps + 1e-9)) + 1
    times = start + speed * np.arange(count) / fps
    times = np.append(times, end) if end - times[-1] > 1e-9 * max(1.0, end) else times
    return times, fps


def _writer(path: Path, fps: float) -> type[_Frames]:
    """The frame writer of ``path``'s format (checked before any work)."""
    kind = path.suffix.lower()
    if kind == ".gif":
        return _GifFrames
    if kind == ".mp4":
        if shutil.which("ffmpeg") is None:
            raise AnimationUnavailable(
                "MP4 needs the ffmpeg program, which is not on PATH (Debian: apt install "
                "ffmpeg); write a .gif instead",
                install="apt install ffmpeg",
            )
        return _Mp4Frames
    raise InvalidInputError(f"an animation must end in .gif or .mp4, got {path.name!r}")


class _Frames:
    """Frames (RGBA arrays) into a file: ``add`` each, then ``finish``."""

    def __init__(self, path: Path, fps: float, width: int, height: int) -> None:
        self.path, self.fps, self.width, self.height = path, fps, width, height

    def prepare(self, rgba: np.ndarray) -> None:
        """See the last frame first (the one with the most drawn): a GIF's palette."""

    def add(self, rgba: np.ndarray) -> None:  # pragma: no cover - abstract
        raise NotImplementedError

    def finish(self) -> None:  # pragma: no cover - abstract
        raise NotImplementedError

    def abort(self) -> None:
        """Give up (an error or Ctrl-C): release what is held, write nothing."""


class _GifFrames(_Frames):
    """A GIF by Pillow, one frame every ``1000 / fps`` ms, looping."""

    def __init__(self, path: Path, fps: float, width: int, height: int) -> None:
        super().__init__(path, fps, width, height)
        self.frames: list[Any] = []
        self.palette: Any = None

    @staticmethod
    def _image(rgba: np.ndarray) -> Any:
        from PIL import Image

        height, width = rgba.shape[:2]
        return Image.frombuffer("RGBA", (width, height), rgba, "raw", "RGBA", 0, 1).convert("RGB")

    def prepare(self, rgba: np.ndarray) -> None:
        from PIL import Image

        # One palette for every frame, from the last (its whole trace drawn): mapping a
        # frame onto it takes 0.3 ms where finding each frame's own palette takes 2.
        self.palette = self._image(rgba).quantize(method=Image.Quantize.FASTOCTREE,
                                                  dither=Image.Dither.NONE)  # fmt: skip

    def add(self, rgba: np.ndarray) -> None:
        from PIL import Image

        # Kept as palette images: a quarter of an RGBA frame's memory.
        self.frames.append(self._image(rgba).quantize(palette=self.palette,
                                                      dither=Image.Dither.NONE))  # fmt: skip

    def finish(self) -> None:
        first, *rest = self.frames
        first.save(self.path, format="GIF", save_all=True, append_images=rest,
                   duration=int(1000 / self.fps), loop=0)  # fmt: skip


class _Mp4Frames(_Frames):
    """An H.264 MP4 by ffmpeg, fed the raw frames on its standard input."""

    def __init__(self, path: Path, fps: float, width: int, height: int) -> None:
        import subprocess

        super().__init__(path, fps, width, height)
        command = ["ffmpeg", "-y", "-loglevel", "error", "-f", "rawvideo", "-pix_fmt", "rgba",
                   "-s", f"{width}x{height}", "-r", f"{fps:g}", "-i", "-",
                   # yuv420p needs even sides: the last odd row or column is cut.
                   "-vf", "crop=trunc(iw/2)*2:trunc(ih/2)*2", "-c:v", "libx264",
                   "-pix_fmt", "yuv420p", "-f", "mp4", str(path)]  # fmt: skip
        self.process = subprocess.Popen(command, stdin=subprocess.PIPE, stderr=subprocess.PIPE)

    def add(self, rgba: np.ndarray) -> None:
        assert self.process.stdin is not None
        self.process.stdin.write(np.ascontiguousarray(rgba).tobytes())

    def finish(self) -> None:
        assert self.process.stdin is not None
        self.process.stdin.close()
        error = self.process.stderr.read().decode(errors="replace") if self.process.stderr else ""
        if self.process.wait() != 0:
            raise OSError(f"ffmpeg failed: {' '.join(error.split())[:300]}")

    def abort(self) -> None:
        self.process.kill()
        self.process.wait()


def _save(
    figure: Figure,
    draw: Callable[[int], None],
    count: int,
    path: Path,
    fps: float,
    progress: bool | TextIO,
    moving: Sequence[Artist],
) -> Path:
    """Render ``count`` frames of ``figure`` into ``path``, each drawn once.

    The figure is drawn in full once, without the ``moving`` artists; each frame
    then restores that picture and draws only what ``draw(k)`` moved (blitting), so
    a frame costs a few artists, not a figure and its layout.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    kind = _writer(path, fps)
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise InvalidInputError(f"the animation's folder {folder} does not exist")
    stream = _progress_stream(progress, count)
    # A stream given is drawn on in place; standard error too, when it is a terminal.
    live = stream is not None and (progress is not True or sys.stderr.isatty())
    bar = ProgressBar(count, f"animating {final_name(path)}", stream, live=live)
    canvas = FigureCanvasAgg(figure)
    for artist in moving:
        artist.set_animated(True)
    canvas.draw()
    figure.set_layout_engine("none")  # laid out once: the frames only move artists
    background = canvas.copy_from_bbox(figure.bbox)
    width, height = (int(v) for v in canvas.get_width_height())
    try:
        with atomic_path(path) as scratch:
            frames = kind(Path(scratch), fps, width, height)
            try:
                draw(count - 1)
                for artist in moving:
                    figure.draw_artist(artist)
                frames.prepare(np.asarray(canvas.buffer_rgba()))
                for k in range(count):
                    canvas.restore_region(background)
                    draw(k)
                    for artist in moving:
                        figure.draw_artist(artist)
                    frames.add(np.asarray(canvas.buffer_rgba()))
                    bar(k + 1, f"{int(100 * (k + 1) / count):3d}%")
                frames.finish()
            except BaseException:
                frames.abort()
                raise
    except BaseException:
        bar.close()
        raise
    return path


def _progress_stream(progress: bool | TextIO, count: int) -> TextIO | None:
    """Where the bar goes: a given stream, or (``True``) standard error for long renders.

    On a terminal (or a stream given) the bar is redrawn in place; elsewhere (a log)
    it writes a line each twentieth of the render.
    """
    if progress is False or count < PROGRESS_FROM:
        return None
    return sys.stderr if progress is True else progress


def _clock(figure: Figure) -> Any:
    """The frame's time, top right of the figure: its own few glyphs drawn each frame."""
    return figure.text(0.98, 0.985, "", ha="right", va="top", family="monospace")


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
        A progress bar for renders of 50 frames or more: on standard error
        (``True``; redrawn in place on a terminal, else a line each twentieth), on the
        given stream, or none (``False``).

    Notes
    -----
    Each frame draws only what moved (about 6 ms for a GIF frame here, ten times less
    than a full redraw). Renders of more than 1,500 frames are drawn at a lower frame
    rate, said on standard error; more than 20,000 are refused.

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
    times, fps = _frame_times(trajectory.start_time, trajectory.end_time, fps, speed, target)
    poses = link_positions(robot, trajectory, times)  # (frames, ndof + 2, 3)
    tool = poses[:, -1]
    figure = Figure(figsize=(size, size), layout="constrained")
    every = poses.reshape(-1, 3)
    low, high = every.min(axis=0), every.max(axis=0)
    span = max(float((high - low).max()) / 2.0, 1e-6) * 1.1
    middle = (high + low) / 2.0
    if view == "3d":
        from matplotlib.lines import Line2D
        from mpl_toolkits.mplot3d import proj3d

        ax = figure.add_subplot(projection="3d")
        # The moving lines are plain 2-D lines of the projected points: the view never
        # changes, so projecting a frame's few points beats drawing 3-D lines.
        # (Axes3D.plot would make 3-D lines: these are added as they are.)
        links = ax.add_line(Line2D([], [], marker="o", color="tab:blue", lw=3, ms=5))
        trace = ax.add_line(Line2D([], [], color="tab:red", lw=1.2))
        for setter, m in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), middle, strict=True):
            setter(m - span, m + span)
        ax.set_zlabel("z [m]")
        # Room for the z label, which the constrained layout otherwise cuts off.
        ax.set_box_aspect(None, zoom=0.85)
        axes = (0, 1)

        def place(line: Any, points: FloatArray) -> None:
            # ax.M, the projection, is the one the figure's first full draw computed.
            x, y, _ = proj3d.proj_transform(points[:, 0], points[:, 1], points[:, 2], ax.M)
            line.set_data(x, y)
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
    ax.set_title(title or robot.name)
    clock = _clock(figure)

    def draw(frame: int) -> None:
        place(links, poses[frame])
        place(trace, tool[: frame + 1])
        clock.set_text(f"t = {times[frame]:.2f} s")

    return _save(figure, draw, times.size, target, fps, progress, (links, trace, clock))


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
        times, fps = _frame_times(0.0, data.duration, fps, speed, target)
        poses, planned = data.pose(times), data.pose(np.linspace(0.0, data.duration, 600))
    elif isinstance(data, SimulationLog):
        times, fps = _frame_times(float(data.t[0]), float(data.t[-1]), fps, speed, target)
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
    ax.set_title(title or "wheeled robot")
    clock = _clock(figure)
    shape = np.array([[1.6, 0.0], [-0.8, 0.7], [-0.8, -0.7]]) * body

    def draw(frame: int) -> None:
        x, y, theta = poses[frame]
        c, s = np.cos(theta), np.sin(theta)
        robot.set_xy(shape @ np.array([[c, s], [-s, c]]) + [x, y])
        trace.set_data(poses[: frame + 1, 0], poses[: frame + 1, 1])
        clock.set_text(f"t = {times[frame]:.2f} s")

    return _save(figure, draw, times.size, target, fps, progress, (trace, robot, clock))
