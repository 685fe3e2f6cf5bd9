"""Off-screen pictures of a simulated run: a few frames to PNG.

Rendering needs an OpenGL backend without a screen: EGL (the default here when
no display is set) or OSMesa (``MUJOCO_GL=osmesa``). Where neither works,
:func:`render_frames` raises :class:`SimulationUnavailableError` with what to
install; simulation itself never needs OpenGL.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from trajkit._validation import FloatArray, finite_array
from trajkit.errors import InvalidInputError
from trajkit.io.atomic import staged_files
from trajkit.sim.arm import ArmLog
from trajkit.sim.engine import SimulationUnavailableError, mujoco_module
from trajkit.sim.scenes import ArmScene, MobileScene
from trajkit.sim.wheeled import PhysicsLog, _Base

__all__ = ["render_frames"]

GL_HINT = (
    "off-screen rendering needs an OpenGL backend: EGL (Debian package libegl1 with "
    "libgl1-mesa-dri, MUJOCO_GL=egl) or OSMesa (libosmesa6, MUJOCO_GL=osmesa)"
)


def _renderer(model: Any, height: int, width: int) -> Any:
    mujoco = mujoco_module()
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

    Parameters
    ----------
    scene : ArmScene or MobileScene
        The scene the log was run in.
    log : ArmLog or PhysicsLog
    paths : sequence of path
        One PNG per frame.
    times : sequence of float, optional
        When (s); default evenly spread from start to end, one per path.
    width, height : int
        Image size in pixels (at most 1280 × 960).
    azimuth : float
        Camera azimuth (deg).

    Returns
    -------
    list of Path
        The files written (all of them, or none if rendering fails).
    """
    paths = [Path(p) for p in paths]
    if not paths or any(p.suffix.lower() != ".png" for p in paths):
        raise InvalidInputError("paths must be one or more .png files")
    if not (0 < width <= 1280 and 0 < height <= 960):
        raise InvalidInputError(f"width x height must be within 1280 x 960, got {width} x {height}")
    when = np.linspace(log.t[0], log.t[-1], len(paths)) if times is None else finite_array(
        "times", times, unit="s"
    )
    if when.shape != (len(paths),):
        raise InvalidInputError(f"times must give one time per path ({len(paths)})")
    rows = np.searchsorted(log.t, np.clip(when, log.t[0], log.t[-1]))
    mujoco = mujoco_module()
    if isinstance(scene, ArmScene) and isinstance(log, ArmLog):
        model = scene.compiled(("render",), [], scene.gravity_compensation)
        extent = scene.robot.reach()
        # Every frame looks at the middle of the arm's whole motion.
        centre = scene.robot.points(log.actual[rows]).reshape(-1, 3).mean(axis=0)

        def pose(data: Any, row: int) -> FloatArray:
            data.qpos[:] = log.actual[row]
            return centre
    elif isinstance(scene, MobileScene) and isinstance(log, PhysicsLog):
        model = scene.compiled()
        # The camera follows the base, a few robot lengths away.
        extent = 3.0 * max(scene.model.effective_track, scene.model.wheelbase)
        base = _Base(model)

        def pose(data: Any, row: int) -> FloatArray:
            base.place(data, log.actual[row], scene.model.wheel_radius)
            return np.append(log.actual[row, :2], 0.0)
    else:
        raise InvalidInputError(
            f"a {type(log).__name__} does not belong to a {type(scene).__name__}"
        )
    renderer = _renderer(model, height, width)
    data = mujoco.MjData(model)
    import matplotlib.image

    with staged_files() as stage:
        try:
            for path, row in zip(paths, rows, strict=True):
                lookat = pose(data, int(row))
                mujoco.mj_forward(model, data)
                renderer.update_scene(data, camera=_camera(mujoco, extent, lookat, azimuth))
                matplotlib.image.imsave(stage.path(path), renderer.render(), format="png")
        finally:
            renderer.close()
    return stage.targets
