"""Off-screen pictures of a simulated run: a few frames to PNG.

Rendering needs an OpenGL backend without a screen: EGL (the default here when
no display is set) or OSMesa (``MUJOCO_GL=osmesa``). Where neither works,
:func:`render_frames` raises :class:`SimulationUnavailableError` with what to
install; simulation itself never needs OpenGL.
"""

from __future__ import annotations

import numbers
import os
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from trajkit._validation import FloatArray, finite_array
from trajkit.errors import InvalidInputError
from trajkit.io.atomic import atomic_write, staged_files
from trajkit.sim import engine
from trajkit.sim.arm import ArmLog
from trajkit.sim.engine import SimulationUnavailableError, mujoco_module
from trajkit.sim.mjcf import arm_extent
from trajkit.sim.scenes import ArmScene, MobileScene
from trajkit.sim.wheeled import PhysicsLog, _Base

__all__ = ["frames", "render_frames", "write_png"]

GL_HINT = (
    "off-screen rendering needs an OpenGL backend: EGL (Debian package libegl1 with "
    "libgl1-mesa-dri, MUJOCO_GL=egl) or OSMesa (libosmesa6, MUJOCO_GL=osmesa), chosen "
    "before MuJoCo is first imported"
)


def _check_pair(scene: object, log: object) -> None:
    if not (
        (isinstance(scene, ArmScene) and isinstance(log, ArmLog))
        or (isinstance(scene, MobileScene) and isinstance(log, PhysicsLog))
    ):
        raise InvalidInputError(
            "frames need an ArmScene with its ArmLog or a MobileScene with its PhysicsLog, "
            f"got a {type(scene).__name__} and a {type(log).__name__}"
        )


def _bound_backend() -> str | None:
    """The OpenGL backend MuJoCo chose when it was imported, if it can be told."""
    for name in ("mujoco.rendering.classic.gl_context", "mujoco.gl_context"):
        module = sys.modules.get(name)
        if module is not None and hasattr(module, "_MUJOCO_GL"):
            return str(module._MUJOCO_GL)
    return None


def _renderer(model: Any, height: int, width: int) -> Any:
    mujoco = mujoco_module()
    if engine.gl_failure is not None:
        # MuJoCo was imported without OpenGL so that simulating still works.
        raise SimulationUnavailableError(f"{GL_HINT}; {engine.gl_failure}")
    glfw = ("", "glfw", "enable", "enabled", "on", "true", "1")
    if sys.platform == "linux" and not os.environ.get("DISPLAY") and _bound_backend() in glfw:
        # GLFW needs a screen; trying it anyway can abort the interpreter.
        raise SimulationUnavailableError(
            f"{GL_HINT}: MuJoCo was imported with its default GLFW backend and there is no "
            "display; set MUJOCO_GL=egl (or import trajkit.sim before mujoco)"
        )
    try:
        return mujoco.Renderer(model, height, width)
    except Exception as exc:  # GL backends fail with many exception types
        reason = " ".join(str(exc).split()) or type(exc).__name__
        raise SimulationUnavailableError(f"{GL_HINT}; MuJoCo said: {reason}") from None


def _camera(mujoco: Any, extent: float, lookat: FloatArray, azimuth: float) -> Any:
    camera = mujoco.MjvCamera()
    camera.lookat[:] = lookat
    camera.distance = 2.2 * extent
    camera.azimuth = azimuth
    camera.elevation = -20.0
    return camera


def frames(
    scene: ArmScene | MobileScene,
    log: ArmLog | PhysicsLog,
    times: Sequence[float] | FloatArray,
    *,
    width: int = 640,
    height: int = 480,
    azimuth: float = 90.0,
) -> list[np.ndarray]:
    """Images of the simulated robot at ``times`` (s) of ``log``, as RGB arrays.

    Parameters
    ----------
    scene : ArmScene or MobileScene
        The scene the log was run in.
    log : ArmLog or PhysicsLog
    times : sequence of float
        When (s); clamped to the log.
    width, height : int
        Image size in pixels (at most 1280 × 960).
    azimuth : float
        Camera azimuth (deg).

    Returns
    -------
    list of ndarray, shape (height, width, 3), uint8

    Raises
    ------
    SimulationUnavailableError
        If no OpenGL backend works here, with what to install.
    """
    whole = all(
        isinstance(n, numbers.Integral) and not isinstance(n, bool) for n in (width, height)
    )
    if not (whole and 0 < width <= 1280 and 0 < height <= 960):
        raise InvalidInputError(
            f"width x height must be whole numbers of pixels within 1280 x 960, got {width!r} x "
            f"{height!r}"
        )
    width, height = int(width), int(height)
    _check_pair(scene, log)
    when = np.atleast_1d(finite_array("times", times, unit="s"))
    if when.ndim != 1 or when.size == 0:
        raise InvalidInputError("times must be a non-empty list of times (s)")
    rows = np.searchsorted(log.t, np.clip(when, log.t[0], log.t[-1]))
    mujoco = mujoco_module()
    if isinstance(scene, ArmScene):
        if log.actual.shape[1] != scene.ndof:
            raise InvalidInputError(
                f"the log has {log.actual.shape[1]} joints, the scene {scene.ndof}"
            )
        model = scene.compiled()
        extent = arm_extent(scene.robot)
        # Every frame looks at the middle of the arm's whole motion.
        centre = scene.robot.points(log.actual[rows]).reshape(-1, 3).mean(axis=0)

        def pose(data: Any, row: int) -> FloatArray:
            data.qpos[:] = log.actual[row]
            return centre
    else:
        # The camera follows the base, a few robot lengths away.
        extent = 3.0 * max(scene.model.effective_track, scene.model.wheelbase)
        model = scene.compiled()
        base = _Base(model)

        def pose(data: Any, row: int) -> FloatArray:
            base.place(data, log.actual[row], scene.model.wheel_radius)
            return np.append(log.actual[row, :2], 0.0)

    renderer = _renderer(model, height, width)
    data = mujoco.MjData(model)
    images = []
    try:
        for row in rows:
            lookat = pose(data, int(row))
            mujoco.mj_forward(model, data)
            renderer.update_scene(data, camera=_camera(mujoco, extent, lookat, azimuth))
            images.append(renderer.render().copy())
    finally:
        renderer.close()
    return images


def write_png(image: np.ndarray, path: str | os.PathLike[str]) -> Path:
    """Write an RGB image atomically as PNG."""
    import io

    import matplotlib.image

    buffer = io.BytesIO()
    matplotlib.image.imsave(buffer, image, format="png")
    data = buffer.getvalue()
    return atomic_write(path, lambda handle: handle.write(data))


def render_frames(
    scene: ArmScene | MobileScene,
    log: ArmLog | PhysicsLog,
    paths: Sequence[str | os.PathLike[str]],
    *,
    times: Sequence[float] | None = None,
    width: int = 640,
    height: int = 480,
    azimuth: float = 90.0,
) -> list[Path]:
    """Render the simulated robot at a few instants of ``log`` to PNG files.

    ``paths`` gives one ``.png`` per frame; ``times`` (s) default to evenly spread
    from start to end. Every frame is rendered before any file is written, so a
    failure leaves none. Other parameters and errors as :func:`frames`.

    Returns
    -------
    list of Path
        The files written.
    """
    _check_pair(scene, log)
    paths = [Path(p) for p in paths]
    if not paths or any(p.suffix.lower() != ".png" for p in paths):
        raise InvalidInputError("paths must be one or more .png files")
    when = (
        np.linspace(log.t[0], log.t[-1], len(paths))
        if times is None
        else finite_array("times", times, unit="s")
    )
    if when.shape != (len(paths),):
        raise InvalidInputError(f"times must give one time per path ({len(paths)})")
    images = frames(scene, log, when, width=width, height=height, azimuth=azimuth)
    with staged_files() as stage:
        for path, image in zip(paths, images, strict=True):
            write_png(image, stage.path(path))
    return stage.targets
