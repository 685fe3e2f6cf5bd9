"""Tests of off-screen rendering: PNG frames of arm and mobile runs, bad input, and a
clear error (with no file left behind) where no OpenGL backend works.
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap

import matplotlib.image
import numpy as np
import pytest

import trajkit as tk
from trajkit import sim
from trajkit.errors import InvalidInputError
from trajkit.kinematics import UR5
from trajkit.mobile import constant_twist
from trajkit.sim.engine import SimulationUnavailableError

mujoco = pytest.importorskip("mujoco", reason="MuJoCo is not installed: pip install 'trajkit[sim]'")

WIDTH, HEIGHT = 160, 120


@pytest.fixture(scope="module")
def arm():
    scene = sim.rrbot_scene()
    plan = tk.cubic(np.radians([0, 0]), np.radians([67, -45]), vmax=np.radians([9, 11]))
    return scene, sim.run(scene, plan)


@pytest.fixture(scope="module")
def base():
    scene = sim.jackal_scene()
    return scene, sim.run(scene, constant_twist(0.1, np.radians(10), 15.0, rate_hz=10),
                          control_rate_hz=10)  # fmt: skip


def assert_picture(path, width: int, height: int) -> np.ndarray:
    image = matplotlib.image.imread(path)
    assert image.shape[:2] == (height, width)
    assert image.shape[2] in (3, 4)
    # Not a uniform fill: sky gradient, floor checker and robot give hundreds of colours.
    colours = np.unique(image.reshape(-1, image.shape[2]), axis=0)
    assert len(colours) >= 50  # measured 357 and 399 at 160 x 120
    assert image[..., :3].std() >= 0.03  # measured 0.12
    return image


def test_arm_frames_are_pngs_of_the_requested_size(arm, tmp_path):
    scene, log = arm
    paths = [tmp_path / "start.png", tmp_path / "end.png"]
    written = sim.render_frames(scene, log, paths, width=WIDTH, height=HEIGHT)
    assert written == paths
    start, end = (assert_picture(p, WIDTH, HEIGHT) for p in paths)
    # The arm moved 67 and -45 deg between the frames: some pixels change (measured 3%).
    changed = np.abs(start - end).sum(axis=-1) > 0.05
    assert changed.mean() >= 0.005
    assert sorted(os.listdir(tmp_path)) == ["end.png", "start.png"]  # no temporaries left


def test_mobile_frame_at_a_given_time(base, tmp_path):
    scene, log = base
    path = tmp_path / "base.PNG"
    written = sim.render_frames(scene, log, [path], times=[5.0], width=320, height=240)
    assert written == [path]
    assert_picture(path, 320, 240)


def test_frames_gives_rgb_arrays(arm):
    scene, log = arm
    images = sim.frames(scene, log, [0.0, 5.0, 1e6], width=64, height=48)
    assert len(images) == 3
    for image in images:
        assert image.shape == (48, 64, 3)
        assert image.dtype == np.uint8
    # Times past the end are clamped to the last row: the same pictures as at the end.
    at_end = sim.frames(scene, log, [0.0, 5.0, log.t[-1]], width=64, height=48)
    for image, expected in zip(images, at_end, strict=True):
        np.testing.assert_array_equal(image, expected)
    assert not np.array_equal(images[0], images[2])  # the arm moved


@pytest.mark.parametrize(
    ("paths", "kwargs", "match"),
    [
        (["frame.jpg"], {}, r"paths must be one or more .png files"),
        (["a.png", "b"], {}, r"paths must be one or more .png files"),
        ([], {}, r"paths must be one or more .png files"),
        (
            ["a.png"],
            {"width": 1281},
            r"width x height must be whole numbers of pixels within 1280 x 960, got 1281 x",
        ),
        (["a.png"], {"height": 961}, r"within 1280 x 960"),
        (["a.png"], {"width": 0}, r"within 1280 x 960"),
        (["a.png"], {"height": -5}, r"within 1280 x 960"),
        (["a.png", "b.png"], {"times": [0.0]}, r"times must give one time per path \(2\)"),
        (["a.png"], {"times": [0.0, 1.0]}, r"times must give one time per path \(1\)"),
        (["a.png"], {"times": [np.nan]}, r"times must be finite"),
    ],
)
def test_render_frames_refuses_bad_input(arm, tmp_path, paths, kwargs, match):
    scene, log = arm
    with pytest.raises(InvalidInputError, match=match):
        sim.render_frames(scene, log, [tmp_path / p for p in paths], **kwargs)
    assert os.listdir(tmp_path) == []


def test_largest_frame_is_allowed(arm, tmp_path):
    scene, log = arm
    (path,) = sim.render_frames(scene, log, [tmp_path / "big.png"], width=1280, height=960)
    assert matplotlib.image.imread(path).shape[:2] == (960, 1280)


def test_a_log_must_belong_to_its_scene(arm, base, tmp_path):
    (arm_scene, arm_log), (mobile_scene, mobile_log) = arm, base
    path = [tmp_path / "x.png"]
    pairing = "need an ArmScene with its ArmLog or a MobileScene with its PhysicsLog, got "
    with pytest.raises(InvalidInputError, match=pairing + "a MobileScene and a ArmLog"):
        sim.render_frames(mobile_scene, arm_log, path)
    with pytest.raises(InvalidInputError, match=pairing + "a ArmScene and a PhysicsLog"):
        sim.render_frames(arm_scene, mobile_log, path)
    with pytest.raises(InvalidInputError, match="the log has 2 joints, the scene 6"):
        sim.render_frames(sim.arm_scene(UR5()), arm_log, path)
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize("log", ["log", None, np.zeros((3, 2))])
def test_not_a_log_is_invalid_input(arm, tmp_path, log):
    scene, _ = arm
    with pytest.raises(InvalidInputError, match="got a ArmScene and a "):
        sim.render_frames(scene, log, [tmp_path / "x.png"])
    with pytest.raises(InvalidInputError, match="got a ArmScene and a "):
        sim.frames(scene, log, [0.0])


def test_without_opengl_a_clear_error_and_no_file(arm, tmp_path, monkeypatch):
    def no_gl(*args, **kwargs):
        raise RuntimeError("no GL")

    monkeypatch.setattr(mujoco, "Renderer", no_gl)
    scene, log = arm
    paths = [tmp_path / "a.png", tmp_path / "b.png"]
    with pytest.raises(SimulationUnavailableError, match=r"OpenGL backend.*MuJoCo said: no GL"):
        sim.render_frames(scene, log, paths, width=WIDTH, height=HEIGHT)
    assert os.listdir(tmp_path) == []


@pytest.mark.skipif(sys.platform != "linux", reason="only Linux's GLFW needs a DISPLAY")
def test_rendering_after_importing_mujoco_first_never_aborts(tmp_path):
    script = textwrap.dedent(
        f"""
        import mujoco  # before trajkit.sim picks the OpenGL backend
        import trajkit as tk
        from trajkit import sim

        scene = sim.rrbot_scene()
        log = sim.run(scene, tk.cubic([0.0, 0.0], [0.1, 0.1], 0.1))
        for name in ("a.png", "b.png"):
            try:
                sim.render_frames(scene, log, [{str(tmp_path)!r} + "/" + name], width=32, height=24)
                print("rendered")
            except sim.SimulationUnavailableError as error:
                print("unavailable:", error)
        """
    )
    environment = {k: v for k, v in os.environ.items()
                   if k not in ("DISPLAY", "MUJOCO_GL", "PYOPENGL_PLATFORM")}  # fmt: skip
    result = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                            env=environment, timeout=120)  # fmt: skip
    assert result.returncode == 0, result.stderr[-2000:]
    lines = result.stdout.splitlines()
    assert len(lines) == 2
    # Either both render, or both say what to do: set MUJOCO_GL before importing mujoco.
    assert all(line == "rendered" or "MUJOCO_GL" in line for line in lines)


def test_numpy_integer_sizes_are_accepted(arm):
    scene, log = arm
    (image,) = sim.frames(scene, log, [0.0], width=np.int64(64), height=np.int32(48))
    assert image.shape == (48, 64, 3)
