"""The one place trajkit touches MuJoCo: importing it, compiling scenes, stepping physics.

MuJoCo is an optional dependency (``pip install "trajkit[sim]"``); every other
module of :mod:`trajkit.sim` goes through :func:`mujoco_module`, so a missing
install gives one clear message instead of an ``ImportError`` deep in a call.
"""

from __future__ import annotations

import importlib.util
import os
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from types import ModuleType
from typing import Any

import numpy as np

from trajkit._validation import FloatArray, positive_scalar
from trajkit.errors import InfeasibleError, InvalidInputError, MissingDependencyError
from trajkit.mobile.trajectory import command_count

__all__ = [
    "SimulationUnavailableError",
    "choose_gl_backend",
    "compile_scene",
    "control_grid",
    "mujoco_available",
    "mujoco_module",
    "open_loop",
    "stability_watch",
]

INSTALL_HINT = 'pip install "trajkit[sim]"'


class SimulationUnavailableError(MissingDependencyError):
    """MuJoCo, or the OpenGL backend that off-screen rendering needs, is not available."""


def choose_gl_backend() -> None:
    """On Linux without a display, have MuJoCo render with EGL unless told otherwise.

    MuJoCo picks its OpenGL backend when it is first imported, from the
    ``MUJOCO_GL`` environment variable; its default (GLFW) needs a screen. This
    sets ``MUJOCO_GL=egl`` (and ``PYOPENGL_PLATFORM=egl``) in this process's
    environment when neither is set, so that importing :mod:`trajkit.sim` first
    makes off-screen rendering work. Elsewhere (macOS, Windows, a desktop) the
    environment is left alone.
    """
    if (
        sys.platform.startswith("linux")
        and "MUJOCO_GL" not in os.environ
        and not os.environ.get("DISPLAY")
        and not os.environ.get("WAYLAND_DISPLAY")
    ):
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
        if _gl_selected() and importlib.util.find_spec("mujoco") is not None:
            # Installed, but the chosen OpenGL backend's library is missing.
            fallback = _import_without_gl(exc)
            if fallback is not None:
                return fallback
        raise SimulationUnavailableError.absent(
            "physics simulation", "MuJoCo", "sim", exc
        ) from None
    except Exception as exc:  # MuJoCo loads its OpenGL backend on import, which can fail
        fallback = _import_without_gl(exc) if _gl_selected() else None
        if fallback is not None:
            return fallback
        reason = " ".join(str(exc).split()) or type(exc).__name__
        raise SimulationUnavailableError(
            f"MuJoCo failed to import with MUJOCO_GL={os.environ.get('MUJOCO_GL', '')!r} "
            f"({reason}); set MUJOCO_GL=egl, osmesa or disable (simulation needs no OpenGL)"
        ) from None
    return mujoco


#: Why MuJoCo's OpenGL backend failed to load, when it was imported without one.
gl_failure: str | None = None


def _gl_selected() -> bool:
    return os.environ.get("MUJOCO_GL", "").lower() not in ("", "disable", "disabled", "off")


def _import_without_gl(exc: BaseException) -> ModuleType | None:
    """Import MuJoCo with rendering disabled after its OpenGL backend failed to load.

    Simulation needs no OpenGL: only frames are then unavailable (the renderer
    raises :class:`SimulationUnavailableError` saying why), as documented.
    """
    global gl_failure
    backend = os.environ.get("MUJOCO_GL", "")
    reason = " ".join(str(exc).split()) or type(exc).__name__
    for name in [m for m in sys.modules if m.split(".")[0] in ("mujoco", "OpenGL")]:
        del sys.modules[name]  # the half-imported modules of the failed attempt
    os.environ["MUJOCO_GL"] = "disable"
    try:
        import mujoco
    except Exception:
        return None
    finally:
        os.environ["MUJOCO_GL"] = backend
    gl_failure = f"MUJOCO_GL={backend!r} failed to load when MuJoCo was imported ({reason})"
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


def open_loop(
    model: Any, data: Any, controls: FloatArray, substeps: int, final: FloatArray
) -> FloatArray:
    """Hold each row of ``controls`` for ``substeps`` physics steps; sensors at period starts.

    Runs inside MuJoCo (its ``rollout`` module, one thread), in chunks of about
    50,000 steps so memory stays bounded however long the run: no Python work per
    step. ``data`` is left at the final state, with ``final`` applied.

    Parameters
    ----------
    controls : ndarray, shape (periods, nu)
    substeps : int
    final : ndarray, shape (nu,)
        The control applied at the final state (for its sensor row).

    Returns
    -------
    ndarray, shape (periods + 1, nsensordata)
        Row ``k`` is read at the start of period ``k`` with control ``k`` applied
        (the last row: after the last period, with ``final``).
    """
    mujoco = mujoco_module()
    from mujoco import rollout

    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    state = np.empty(mujoco.mj_stateSize(model, spec))
    chunk = max(1, 50_000 // substeps)
    rows = []
    for first in range(0, controls.shape[0], chunk):
        block = np.repeat(np.ascontiguousarray(controls[first : first + chunk]), substeps, axis=0)
        mujoco.mj_getState(model, data, state, spec)
        # MuJoCo computes sensors in the forward pass at the start of each step, so the
        # readings a step returns belong to the state it started from.
        states, sensors = rollout.rollout(
            model, data, state[None, :], block[None, :, :], nstep=block.shape[0],
            initial_warmstart=np.array(data.qacc_warmstart)[None, :],
        )  # fmt: skip
        rows.append(sensors[0, ::substeps])
        mujoco.mj_setState(model, data, states[0, -1], spec)
    data.ctrl[:] = final
    mujoco.mj_forward(model, data)
    rows.append(np.array(data.sensordata)[None, :])
    return np.concatenate(rows)


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
            f"physics steps of {timestep:g} s: rates of {1.0 / timestep:g} Hz divided by a "
            f"whole number work (or choose the scene's timestep)"
        )
    count = command_count(end, rate)  # the count HeldCommands makes, by the same rule
    if count * substeps > 10**8:
        raise InvalidInputError(
            f"{end:g} s at {timestep:g} s per step is {count * substeps:.3g} physics steps; "
            "at most 1e8 are simulated"
        )
    return period * np.arange(count + 1), substeps


_UNSTABLE = ("mjWARN_BADQACC", "mjWARN_BADQPOS", "mjWARN_BADQVEL", "mjWARN_BADCTRL")


@contextmanager
def stability_watch(data: Any, advice: str) -> Iterator[None]:
    """Raise if the physics diverged while the block ran, instead of returning garbage.

    When a simulation blows up MuJoCo resets its state and carries on, printing a
    warning and appending it to ``MUJOCO_LOG.TXT`` in the working directory. Here
    its warnings are collected instead (nothing printed or written) and any
    divergence in ``data`` becomes an :class:`~trajkit.errors.InfeasibleError`
    quoting MuJoCo, followed by ``advice``.
    """
    mujoco = mujoco_module()
    messages: list[str] = []
    previous = mujoco.get_mju_user_warning()
    mujoco.set_mju_user_warning(messages.append)
    try:
        yield
    finally:
        mujoco.set_mju_user_warning(previous)
    diverged = [
        getattr(mujoco.mjtWarning, name)
        for name in _UNSTABLE
        if data.warning[getattr(mujoco.mjtWarning, name)].number > 0
    ]
    if diverged:
        said = messages[0].strip() if messages else "an unstable simulation"
        raise InfeasibleError(f"the simulation diverged (MuJoCo: {said}); {advice}")
