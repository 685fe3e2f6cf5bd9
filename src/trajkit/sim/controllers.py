"""How a simulated arm's joints are driven: servos and torque controllers.

Each controller names the MuJoCo actuators it needs on every joint and, for the
open-loop ones, the control columns it sends for the plan's desired states:

* :class:`PositionServo` — a PD servo on position (Gazebo's
  ``effort_controllers/JointPositionController``); the setpoint is the plan's
  position, held over each control period.
* :class:`VelocityServo` — the plan's velocity is the command; the drive
  integrates it into a position setpoint (``kp``) and damps the velocity error
  (``kv``), as a velocity interface over a position loop does.
* :class:`PDFeedforward` — the torque of the inverse dynamics along the plan
  (from its accelerations, for all control times at once) plus PD on the
  position and velocity errors.
* :class:`ComputedTorque` — inverse dynamics at the *measured* state with the
  plan's acceleration corrected by the errors: ``τ = M(q)(q̈_d + K_d ė + K_p e) + h(q, q̇)``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from trajkit._validation import FloatArray, joint_parameter, positive_scalar
from trajkit.errors import InvalidInputError
from trajkit.sim.mjcf import Actuator

__all__ = [
    "ArmController",
    "ComputedTorque",
    "PDFeedforward",
    "PositionServo",
    "VelocityServo",
    "arm_controller",
    "is_torque_control",
]


@dataclass(frozen=True)
class _GainController:
    """A controller with gains ``kp`` (N·m/rad) and ``kv`` (N·m·s/rad) on every joint.

    Subclasses list in ``_ACTUATORS`` the MuJoCo actuators they put on each joint,
    in order: the actuator kind and which of the two gains it takes.
    """

    kp: Any = 100.0
    kv: Any = 10.0

    _ACTUATORS: ClassVar[tuple[tuple[str, tuple[str, ...]], ...]] = ()

    def actuators(self, ndof: int) -> list[Actuator]:
        """The actuators of ``_ACTUATORS``, with the gains checked for ``ndof`` joints."""
        gains = {
            "kp": joint_parameter("kp", self.kp, ndof, "N·m/rad", zero_ok=True),
            "kv": joint_parameter("kv", self.kv, ndof, "N·m·s/rad", zero_ok=True),
        }
        return [Actuator(kind, **{g: gains[g] for g in uses}) for kind, uses in self._ACTUATORS]


@dataclass(frozen=True)
class PositionServo(_GainController):
    """PD position servo: ``τ = kp (q_d − q) − kv q̇`` (N·m/rad, N·m·s/rad).

    The defaults are the gains of Gazebo's RRBot position controllers (p 100, d 10).
    One MuJoCo position actuator per joint.
    """

    name: str = "position servo"

    _ACTUATORS = (("position", ("kp", "kv")),)

    def inputs(self, q: FloatArray, qd: FloatArray, torque: FloatArray | None) -> FloatArray:
        """The control columns for desired states (one row per control time)."""
        return q


@dataclass(frozen=True)
class VelocityServo(_GainController):
    """Velocity command ``u = q̇_d``: ``τ = kp (∫u dt − q) + kv (u − q̇)``.

    An integrated-velocity (position loop) and a velocity actuator per joint.
    """

    name: str = "velocity servo"

    _ACTUATORS = (("intvelocity", ("kp",)), ("velocity", ("kv",)))

    def inputs(self, q: FloatArray, qd: FloatArray, torque: FloatArray | None) -> FloatArray:  # noqa: D102
        return np.concatenate([qd, qd], axis=1)


@dataclass(frozen=True)
class PDFeedforward(_GainController):
    """Inverse-dynamics feed-forward plus PD: ``τ = τ_ID(q_d, q̇_d, q̈_d) + kp e + kv ė``.

    A motor, a position and a velocity actuator per joint.
    """

    name: str = "PD + feed-forward"

    _ACTUATORS = (("motor", ()), ("position", ("kp",)), ("velocity", ("kv",)))

    def inputs(self, q: FloatArray, qd: FloatArray, torque: FloatArray | None) -> FloatArray:  # noqa: D102
        return np.concatenate([torque, q, qd], axis=1)


@dataclass(frozen=True)
class ComputedTorque:
    """Computed torque with error dynamics ``ë + 2ζω ė + ω² e = 0``.

    Parameters
    ----------
    frequency : float
        Natural frequency ``ω`` of the error dynamics (rad/s).
    damping_ratio : float
        ``ζ``; 1 is critically damped.
    """

    frequency: float = 30.0
    damping_ratio: float = 1.0
    name: str = "computed torque"

    def actuators(self, ndof: int) -> list[Actuator]:
        """One motor per joint."""
        return [Actuator("motor")]

    def gains(self) -> tuple[float, float]:
        """``(ω², 2ζω)``."""
        omega = positive_scalar("frequency", self.frequency, unit="rad/s")
        zeta = positive_scalar("damping_ratio", self.damping_ratio)
        return omega**2, 2.0 * zeta * omega


ArmController = PositionServo | VelocityServo | PDFeedforward | ComputedTorque

_NAMED: dict[str, type] = {
    "position": PositionServo,
    "velocity": VelocityServo,
    "pd_feedforward": PDFeedforward,
    "computed_torque": ComputedTorque,
}


def arm_controller(controller: str | ArmController) -> ArmController:
    """A controller object from itself or its name, with default gains.

    Names: ``"position"``, ``"velocity"``, ``"pd_feedforward"``, ``"computed_torque"``.
    """
    if isinstance(controller, str):
        if controller not in _NAMED:
            raise InvalidInputError(
                f"unknown arm controller {controller!r}; choose one of {sorted(_NAMED)}"
            )
        return _NAMED[controller]()
    if not isinstance(controller, (PositionServo, VelocityServo, PDFeedforward, ComputedTorque)):
        raise InvalidInputError(
            "controller must be a name or a PositionServo, VelocityServo, PDFeedforward or "
            f"ComputedTorque, got {type(controller).__name__}"
        )
    return controller


def is_torque_control(controller: ArmController) -> bool:
    """True for controllers that command torques (and compute gravity themselves)."""
    return isinstance(controller, (PDFeedforward, ComputedTorque))
