"""The one place trajkit touches MuJoCo: importing it, compiling scenes, stepping physics.

MuJoCo is an optional dependency (``pip install "trajkit[sim]"``); every other
module of :mod:`trajkit.sim` goes through :func:`mujoco_module`, so a missing
install gives one clear message instead of an ``ImportError`` deep in a call.
"""

from __future__ import annotations

import os
from types import ModuleType
from typing import Any

import numpy as np

from trajkit._validation import FloatArray, positive_scalar
from trajkit.errors import InvalidInputError, TrajkitError

__all__ = [
    "SimulationUnavailableError",
    "choose_gl_backend",
    "compile_scene",
    "control_grid",
    "mujoco_available",
    "mujoco_module",
    "open_loop",
]

INSTALL_HINT = 'pip install "trajkit[sim]"'


class SimulationUnavailableError(TrajkitError):
    """MuJoCo, or the OpenGL backend that off-screen rendering needs, is not available."""


def choose_gl_backend() -> None:
    """Use EGL for rendering when no display is set and nothing else was chosen."""
    # MuJoCo picks its OpenGL backend when it is first imported. Without a screen
    # the default (GLFW) cannot open a context, while EGL renders off-screen.
    if "MUJOCO_GL" not in os.environ and not os.environ.get("DISPLAY"):
        os.environ["MUJOCO_GL"] = "egl"
        if "PYOPENGL_PLATFORM" not in os.environ:
            os.environ["PYOPENGL_PLATFORM"] = "egl"


def mujoco_module() -> ModuleType:
    """The imported ``mujoco`` package.

    Raises
    ------
    SimulationUnavailableError
        If MuJoCo is not installed, with the command that installs it.
    """
    choose_gl_backend()
    try:
        import mujoco
    except ImportError as exc:
        raise SimulationUnavailableError(
            f"physics simulation needs MuJoCo, which is not installed ({exc}); "
            f"install it with: {INSTALL_HINT}"
        ) from None
    return mujoco


def mujoco_available() -> bool:
    """True when MuJoCo can be imported."""
    try:
        mujoco_module()
    except SimulationUnavailableError:
        return False
    return True


def compile_scene(xml: str) -> Any:
    """Compile MJCF text into an ``mujoco.MjModel``.

    Raises
    ------
    InvalidInputError
        If MuJoCo refuses the model; the message is MuJoCo's own.
    """
    mujoco = mujoco_module()
    try:
        return mujoco.MjModel.from_xml_string(xml)
    except ValueError as exc:
        message = " ".join(str(exc).split())
        raise InvalidInputError(f"MuJoCo cannot compile the scene: {message}") from None


def open_loop(model: Any, data: Any, controls: FloatArray, final: FloatArray) -> FloatArray:
    """Step the physics once per row of ``controls`` from ``data``'s state; sensor rows.

    Runs inside MuJoCo (its ``rollout`` module, one thread): no Python work per
    step. ``data`` is left at the final state, with ``final`` applied.

    Parameters
    ----------
    controls : ndarray, shape (nstep, nu)
    final : ndarray, shape (nu,)
        The control applied at the final state (for its sensor row).

    Returns
    -------
    ndarray, shape (nstep + 1, nsensordata)
        Row ``k`` is read at the state before step ``k`` (the last row: after the
        last step), with control ``k`` applied (``final`` for the last row).
    """
    mujoco = mujoco_module()
    from mujoco import rollout

    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    state = np.empty(mujoco.mj_stateSize(model, spec))
    mujoco.mj_getState(model, data, state, spec)
    controls = np.ascontiguousarray(controls, dtype=np.float64)
    # MuJoCo computes sensors in the forward pass at the start of each step, so the
    # readings a step returns belong to the state it started from.
    states, sensors = rollout.rollout(
        model, data, state[None, :], controls[None, :, :], nstep=controls.shape[0]
    )
    mujoco.mj_setState(model, data, states[0, -1], spec)
    data.ctrl[:] = final
    mujoco.mj_forward(model, data)
    return np.concatenate([sensors[0], np.array(data.sensordata)[None, :]])


def control_grid(timestep: float, end: float, rate_hz: float) -> tuple[FloatArray, int]:
    """Control times from 0 to (at least) ``end`` (s) and the physics steps per period.

    Raises
    ------
    InvalidInputError
        If the control period is not a whole number of physics steps, or the run
        would take more than 1e8 of them.
    """
    rate = positive_scalar("control_rate_hz", rate_hz, unit="Hz")
    period = 1.0 / rate
    substeps = round(period / timestep)
    if substeps < 1 or abs(substeps * timestep - period) > 1e-9 * period:
        raise InvalidInputError(
            f"the control period 1/{rate:g} Hz = {period:g} s must be a whole number of "
            f"physics steps of {timestep:g} s; choose another rate or the scene's timestep"
        )
    count = max(int(np.ceil(end / period - 1e-9)), 1)
    if count * substeps > 10**8:
        raise InvalidInputError(
            f"{end:g} s at {timestep:g} s per step is {count * substeps:.3g} physics steps; "
            "at most 1e8 are simulated"
        )
    return period * np.arange(count + 1), substeps
