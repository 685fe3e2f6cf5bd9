"""Animations: real-time frames, GIF files read back, progress, errors, no partial files."""

from __future__ import annotations

import io
import os
import stat

import numpy as np
import pytest
from PIL import Image

import trajkit as tk
from trajkit import mobile
from trajkit.errors import InvalidInputError
from trajkit.kinematics import RRBot, Spatial3R
from trajkit.viz import animate
from trajkit.viz.animate import AnimationUnavailable

PLAN = tk.cubic(np.radians([0.0, 0.0]), np.radians([60.0, -40.0]), duration=2.0)


def frames_of(path) -> tuple[int, list[int]]:
    with Image.open(path) as image:
        durations = []
        for index in range(image.n_frames):
            image.seek(index)
            durations.append(image.info["duration"])
        return image.n_frames, durations


@pytest.mark.parametrize("view", ["xz", "3d"])
def test_arm_gif_plays_in_real_time(tmp_path, view):
    path = animate.arm(RRBot(), PLAN, tmp_path / "arm.gif", view=view, fps=5, size=2.0)
    assert path == tmp_path / "arm.gif"
    count, durations = frames_of(path)
    assert count == 11  # t = 0, 0.2, ..., 2.0 s
    assert set(durations) == {200}  # ms per frame: 1 / 5 fps
    assert os.listdir(tmp_path) == ["arm.gif"]  # no temporary left beside it


def test_speed_plays_faster_and_the_end_is_always_shown(tmp_path):
    plan = tk.cubic([0.0, 0.0, 0.0], [0.4, 0.3, -0.2], duration=2.1)
    path = animate.arm(Spatial3R(), plan, tmp_path / "fast.gif", fps=4, speed=2.0, size=2.0)
    count, _ = frames_of(path)
    # 1.05 s of animation at 4 frames/s: t = 0, 0.5, 1.0, 1.5, 2.0, then the end 2.1 s.
    assert count == 6


def test_arm_from_a_mujoco_log_draws_what_the_simulated_arm_did(tmp_path, monkeypatch):
    pytest.importorskip("mujoco", reason="MuJoCo is not installed: pip install 'trajkit[sim]'")
    from trajkit import sim
    from trajkit.kinematics import drawing

    robot = RRBot()
    log = sim.run(sim.arm_scene(robot), PLAN, control_rate_hz=100.0)
    drawn = []
    original = drawing.link_positions

    def spy(chain, trajectory, t):
        drawn.append(trajectory(t))
        return original(chain, trajectory, t)

    monkeypatch.setattr(drawing, "link_positions", spy)
    path = animate.arm(robot, log, tmp_path / "run.gif", fps=5, size=2.0)
    assert frames_of(path)[0] == 11
    # The frames show the simulated joints at their own samples (0.2 s apart), not the plan.
    np.testing.assert_allclose(drawn[0], log.actual[::20], rtol=0, atol=1e-12)
    assert np.abs(drawn[0] - PLAN(log.t[::20])).max() > 1e-4


def test_arm_axes_are_in_metres(tmp_path, monkeypatch):
    from matplotlib.figure import Figure

    figures = []

    made = Figure.add_subplot

    def keep(self, *args, **kwargs):
        figures.append(made(self, *args, **kwargs))
        return figures[-1]

    monkeypatch.setattr(Figure, "add_subplot", keep)
    animate.arm(RRBot(), PLAN, tmp_path / "arm.gif", view="3d", fps=2, size=2.0)
    ax = figures[-1]
    assert (ax.get_xlabel(), ax.get_ylabel(), ax.get_zlabel()) == ("x [m]", "y [m]", "z [m]")


def test_mobile_from_a_plan_and_from_a_log(tmp_path):
    plan = mobile.constant_twist(0.2, 0.5, 3.0)
    count, _ = frames_of(animate.mobile(plan, tmp_path / "plan.gif", fps=3, size=2.0))
    assert count == 10
    log = mobile.simulate(plan, sample_step=0.01, initial_pose=(0.05, 0.0, 0.0))
    count, _ = frames_of(animate.mobile(log, tmp_path / "log.gif", fps=3, speed=1.5, size=2.0))
    assert count == 7  # 2 s of animation: t = 0, 0.5, ..., 3.0 s


def test_progress_bar_on_a_given_stream(tmp_path):
    stream = io.StringIO()
    plan = tk.cubic([0.0, 0.0], [0.2, 0.1], duration=5.0)
    animate.arm(RRBot(), plan, tmp_path / "long.gif", view="xz", fps=10, size=1.0,
                progress=stream)  # fmt: skip
    text = stream.getvalue()
    assert text.startswith("\ranimating long.gif [")
    assert text.endswith("[####################] 100%\n")  # the shared bar, 20 wide
    assert text.count("\r") <= 101  # redrawn only when its line changes


def test_off_a_terminal_a_long_render_still_says_how_far_it_is(tmp_path, capsys):
    plan = tk.cubic([0.0, 0.0], [0.2, 0.1], duration=5.0)  # 51 frames: a long render
    animate.arm(RRBot(), plan, tmp_path / "logged.gif", view="xz", fps=10, size=1.0)
    lines = capsys.readouterr().err.splitlines()  # pytest's stderr is not a terminal
    assert 10 <= len(lines) <= 21 and "\r" not in "".join(lines)  # a line a twentieth
    assert lines[0].startswith("animating logged.gif [") and lines[-1].endswith("100%")
    animate.arm(RRBot(), plan, tmp_path / "off.gif", view="xz", fps=10, size=1.0,
                progress=False)  # fmt: skip
    animate.arm(RRBot(), PLAN, tmp_path / "short.gif", view="xz", fps=5, size=1.0)  # 11
    assert capsys.readouterr().err == ""


@pytest.mark.parametrize(
    ("path", "kwargs", "error", "match"),
    [
        ("arm.png", {}, InvalidInputError, r"must end in \.gif or \.mp4, got 'arm\.png'"),
        ("arm.gif", {"view": "top"}, InvalidInputError, r"view must be '3d', 'xy', 'xz' or 'yz'"),
        ("arm.gif", {"fps": 0}, InvalidInputError, r"fps must be > 0"),
        ("arm.gif", {"fps": np.nan}, InvalidInputError, r"fps must be finite"),
        ("arm.gif", {"speed": -1.0}, InvalidInputError, r"speed must be > 0"),
        ("arm.gif", {"fps": 20000}, InvalidInputError, r"40001 frames; at most 20000 are drawn"),
        ("missing/arm.gif", {}, InvalidInputError, r"folder .*missing does not exist"),
    ],
)
def test_bad_requests_are_refused_before_any_file(tmp_path, path, kwargs, error, match):
    with pytest.raises(error, match=match):
        animate.arm(RRBot(), PLAN, tmp_path / path, **kwargs)
    assert os.listdir(tmp_path) == []


def test_mp4_without_ffmpeg_says_what_to_install(tmp_path, monkeypatch):
    monkeypatch.setattr(animate.shutil, "which", lambda name: None)
    with pytest.raises(AnimationUnavailable, match="MP4 needs the ffmpeg program"):
        animate.arm(RRBot(), PLAN, tmp_path / "arm.mp4")
    with pytest.raises(AnimationUnavailable, match=r"write a \.gif instead"):
        animate.mobile(mobile.constant_twist(0.1, 0.1, 1.0), tmp_path / "base.mp4")
    assert os.listdir(tmp_path) == []


def test_not_a_mobile_plan_is_refused(tmp_path):
    with pytest.raises(InvalidInputError, match="MobileTrajectory or a SimulationLog, got Traj"):
        animate.mobile(PLAN, tmp_path / "x.gif")


@pytest.mark.parametrize("interruption", [KeyboardInterrupt, RuntimeError])
def test_an_interrupted_render_leaves_no_file(tmp_path, monkeypatch, interruption):
    calls = {"frames": 0}
    original = animate._GifFrames.add

    def grab(self, rgba):
        calls["frames"] += 1
        if calls["frames"] == 3:
            raise interruption("stop")
        return original(self, rgba)

    monkeypatch.setattr(animate._GifFrames, "add", grab)
    with pytest.raises(interruption):
        animate.arm(RRBot(), PLAN, tmp_path / "arm.gif", view="xz", fps=5, size=1.0)
    assert os.listdir(tmp_path) == []
    # An existing animation is left as it was.
    (tmp_path / "arm.gif").write_bytes(b"old")
    calls["frames"] = 0
    with pytest.raises(interruption):
        animate.arm(RRBot(), PLAN, tmp_path / "arm.gif", view="xz", fps=5, size=1.0)
    assert (tmp_path / "arm.gif").read_bytes() == b"old"
    assert os.listdir(tmp_path) == ["arm.gif"]


@pytest.mark.skipif(
    __import__("shutil").which("ffmpeg") is None,
    reason="ffmpeg is not installed (Debian: apt install ffmpeg); .ci/run installs it",
)
def test_mp4_with_ffmpeg(tmp_path):
    path = animate.mobile(mobile.constant_twist(0.2, 0.5, 2.0), tmp_path / "base.mp4", fps=5,
                          size=2.0)  # fmt: skip
    data = path.read_bytes()
    assert data[4:8] == b"ftyp"  # an MP4 container
    assert os.listdir(tmp_path) == ["base.mp4"]


LONG_PLAN = tk.cubic([0.0, 0.0], [1.0, -1.0], duration=2.0)  # 51 frames at 25 fps: a bar


def test_an_interrupt_before_the_first_frame_stays_an_interrupt(tmp_path, monkeypatch):
    # A writer with no frame cannot finish; Ctrl-C, not that consequence, must show.
    def interrupted(self, rgba):
        raise KeyboardInterrupt

    monkeypatch.setattr(animate._GifFrames, "add", interrupted)
    with pytest.raises(KeyboardInterrupt) as excinfo:
        animate.arm(RRBot(), PLAN, tmp_path / "arm.gif", view="xz", fps=5, size=1.0)
    assert excinfo.value.__cause__ is None
    assert os.listdir(tmp_path) == []


def test_an_interrupted_progress_bar_ends_its_line(tmp_path, monkeypatch):
    original = animate._GifFrames.add
    calls = {"frames": 0}

    def grab(self, rgba):
        calls["frames"] += 1
        if calls["frames"] == 20:
            raise KeyboardInterrupt
        return original(self, rgba)

    monkeypatch.setattr(animate._GifFrames, "add", grab)
    stream = io.StringIO()
    with pytest.raises(KeyboardInterrupt):
        animate.arm(RRBot(), LONG_PLAN, tmp_path / "arm.gif", view="xz", size=1.0,
                    progress=stream)  # fmt: skip
    text = stream.getvalue()
    assert text.endswith("%\n")  # the next message starts on its own line
    assert text.count("\n") == 1
    assert "100%" not in text  # cut short
    assert os.listdir(tmp_path) == []


def test_the_progress_bar_shows_the_final_name_of_a_staged_file(tmp_path, monkeypatch):
    from trajkit.io import staged_files

    original = animate._GifFrames.add
    calls = {"frames": 0}

    def grab(self, rgba):  # a few frames are enough to see the bar's label
        calls["frames"] += 1
        if calls["frames"] == 3:
            raise KeyboardInterrupt
        return original(self, rgba)

    monkeypatch.setattr(animate._GifFrames, "add", grab)
    stream = io.StringIO()
    with pytest.raises(KeyboardInterrupt), staged_files() as stage:
        animate.arm(RRBot(), LONG_PLAN, stage.path(tmp_path / "arm.gif"), view="xz", size=1.0,
                    progress=stream)  # fmt: skip
    text = stream.getvalue()
    assert text.startswith("\ranimating arm.gif [")
    assert "trajkit-tmp" not in text
    assert os.listdir(tmp_path) == []


def test_animations_get_the_usual_permissions(tmp_path):
    old_umask = os.umask(0o022)
    try:
        gif = animate.arm(RRBot(), PLAN, tmp_path / "arm.gif", view="xz", fps=5, size=1.0)
    finally:
        os.umask(old_umask)
    assert stat.S_IMODE(gif.stat().st_mode) == 0o644  # 0666 less the umask, not 0600


def test_a_long_render_is_drawn_at_a_lower_rate_and_says_so(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(animate, "LONG_FRAMES", 30)
    plan = tk.cubic([0.0, 0.0], [0.2, 0.1], duration=5.0)  # 51 frames at 10 frames/s
    path = animate.arm(RRBot(), plan, tmp_path / "long.gif", view="xz", fps=10, size=1.0,
                       progress=False)  # fmt: skip
    count, durations = frames_of(path)
    note = capsys.readouterr().err
    assert note == (
        "trajkit: note: long.gif: 5 s at 10 frames/s would be 51 frames; drawn at 5.8 "
        "frames/s instead (pass a lower fps or a higher speed to choose)\n"
    )
    # 0 .. 5 s and the end; 1000 / 5.8 = 172 ms, which a GIF keeps in hundredths.
    assert count == 30 and set(durations[:-1]) == {170}


def test_each_frame_draws_only_what_moved(tmp_path, monkeypatch):
    # The figure is drawn once in full; frames draw their moving artists on a copy of it.
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    full = {"draws": 0}
    original = FigureCanvasAgg.draw

    def counted(self, *args, **kwargs):
        full["draws"] += 1
        return original(self, *args, **kwargs)

    monkeypatch.setattr(FigureCanvasAgg, "draw", counted)
    animate.arm(RRBot(), PLAN, tmp_path / "arm.gif", view="3d", fps=5, size=2.0)
    assert full["draws"] == 1


@pytest.mark.parametrize("view", ["3d", "xz"])
def test_every_frame_shows_the_arm_and_its_trace(tmp_path, view):
    # The moving lines are drawn on the figure drawn once: blue links, a red trace.
    path = animate.arm(RRBot(), PLAN, tmp_path / "arm.gif", view=view, fps=5, size=3.0)
    with Image.open(path) as image:
        for index in (3, image.n_frames - 1):
            image.seek(index)
            pixels = np.asarray(image.convert("RGB")).reshape(-1, 3).astype(int)
            blue = np.abs(pixels - [31, 119, 180]).sum(axis=1) < 40  # tab:blue
            red = np.abs(pixels - [214, 39, 40]).sum(axis=1) < 40  # tab:red
            assert blue.sum() > 100 and red.sum() > 10
