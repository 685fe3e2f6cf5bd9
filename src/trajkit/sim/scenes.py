"""Scenes: a robot plus the physical parameters MuJoCo needs to simulate it.

An :class:`ArmScene` wraps a :class:`~trajkit.kinematics.SerialChain` (built-in,
DH table or URDF) with link sizes and masses, joint damping and rotor inertia; a
:class:`MobileScene` wraps a :class:`~trajkit.mobile.DiffDrive` with its wheels,
casters and ground friction. Both write their MJCF on demand (``scene.mjcf()``), so
a scene can be inspected or saved and loaded in MuJoCo's own viewer.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from trajkit._validation import finite_array, joint_parameter, positive_scalar
from trajkit.errors import InvalidInputError
from trajkit.kinematics import UR5, Inertials, RRBot, SerialChain
from trajkit.mobile.models import DiffDrive, jackal
from trajkit.sim.controllers import ArmController, arm_controller, is_torque_control
from trajkit.sim.mjcf import Actuator, arm_extent, chain_mjcf, diff_drive_mjcf

__all__ = [
    "ArmScene",
    "MobileScene",
    "arm_scene",
    "jackal_scene",
    "rrbot_scene",
    "ur5_scene",
]

_CACHED_MODELS = 8


def _timestep(value: float) -> float:
    step = positive_scalar("timestep", value, unit="s")
    if step > 0.01:
        raise InvalidInputError(
            f"timestep must be at most 0.01 s for stable contacts, got {step:g} s"
        )
    return step


@dataclass(frozen=True, eq=False)
class ArmScene:
    """A serial arm on a floor, ready for MuJoCo.

    Parameters
    ----------
    robot : SerialChain
        Any chain of :mod:`trajkit.kinematics`; MuJoCo's joint positions equal its ``q``.
        The five values below, when left out, are the robot's own (``robot.physical``,
        as the built-in RRBot and UR5 carry them), else the defaults named here.
    link_radius : float, optional
        Radius of the links' capsules (m); default 3% of the arm's reach (of its size
        at mid-range with an unbounded prismatic joint), at least 1 cm.
    link_mass : float or array_like, shape (ndof,)
        Mass of the link each joint moves (kg), spread evenly along it; default 1.
    damping : float or array_like
        Viscous joint friction (N·m·s/rad, or N·s/m for a prismatic joint); default 0.1.
    armature : float or array_like
        Rotor inertia reflected through the gearbox (kg·m²), added to each joint;
        default 0.01.
    effort_limit : float or array_like, optional
        Largest total actuator torque (N·m) or force (N) per joint; none by default.
    gravity_compensation : bool
        Servo controllers (position and velocity) add a drive's gravity
        feed-forward. Torque controllers compute gravity in their own inverse
        dynamics and ignore this.
    timestep : float
        Physics step (s); control periods must be whole multiples of it.
    inertials : Inertials, optional
        Each link's mass, centre of mass and inertia tensor, written into the scene
        as its bodies' own inertia (the capsules then carry none). Default: the
        robot's own (a URDF's ``<inertial>`` elements, the built-in UR5's data)
        unless ``link_mass`` is given; a robot without them gets the capsules'
        masses.
    """

    robot: SerialChain
    link_radius: float | None = None
    link_mass: ArrayLike | None = None
    damping: ArrayLike | None = None
    armature: ArrayLike | None = None
    effort_limit: ArrayLike | None = None
    gravity_compensation: bool = True
    timestep: float = 0.001
    inertials: Inertials | None = None
    _compiled: dict = field(default_factory=dict, init=False, repr=False)

    def __post_init__(self) -> None:
        if not isinstance(self.robot, SerialChain):
            raise InvalidInputError(
                f"robot must be a trajkit.kinematics SerialChain, got {type(self.robot).__name__}"
            )
        n = self.robot.ndof
        own = self.robot.physical
        if self.inertials is None and self.link_mass is None and own is not None:
            try:
                object.__setattr__(self, "inertials", own.inertials(n))
            except InvalidInputError:  # no centres of mass or inertias: capsules
                pass
        if self.inertials is not None:
            if not isinstance(self.inertials, Inertials):
                raise InvalidInputError(
                    "inertials must be a trajkit.kinematics.Inertials, got "
                    f"{type(self.inertials).__name__}"
                )
            if self.inertials.mass.size != n:
                raise InvalidInputError(
                    f"inertials give {self.inertials.mass.size} links but {self.robot.name} "
                    f"has {n} joints"
                )
        defaults = {"link_radius": None, "link_mass": 1.0, "damping": 0.1, "armature": 0.01,
                    "effort_limit": None}  # fmt: skip
        for name, default in defaults.items():
            if getattr(self, name) is None:
                value = None if own is None else getattr(own, name)
                object.__setattr__(self, name, default if value is None else value)
        radius = (
            max(0.03 * arm_extent(self.robot), 0.01)
            if self.link_radius is None
            else positive_scalar("link_radius", self.link_radius, unit="m")
        )
        object.__setattr__(self, "link_radius", radius)
        object.__setattr__(
            self, "link_mass", joint_parameter("link_mass", self.link_mass, n, "kg", zero_ok=False)
        )
        object.__setattr__(
            self, "damping", joint_parameter("damping", self.damping, n, "N·m·s/rad", zero_ok=True)
        )
        object.__setattr__(
            self, "armature", joint_parameter("armature", self.armature, n, "kg·m²", zero_ok=True)
        )
        if self.effort_limit is not None:
            limit = joint_parameter("effort_limit", self.effort_limit, n, "N·m", zero_ok=False)
            object.__setattr__(self, "effort_limit", limit)
        object.__setattr__(self, "timestep", _timestep(self.timestep))
        if not isinstance(self.gravity_compensation, (bool, np.bool_)):
            raise InvalidInputError(
                f"gravity_compensation must be True or False, got {self.gravity_compensation!r}"
            )
        object.__setattr__(self, "gravity_compensation", bool(self.gravity_compensation))
        for name in ("link_mass", "damping", "armature", "effort_limit"):
            value = getattr(self, name)
            if value is not None:
                # A frozen scene: its compiled models must stay what its arrays say.
                value = value.copy()
                value.setflags(write=False)
                object.__setattr__(self, name, value)

    @property
    def ndof(self) -> int:
        """Number of joints."""
        return self.robot.ndof

    def mjcf(self, controller: str | ArmController = "position") -> str:
        """The scene as MJCF text, with ``controller``'s actuators on every joint."""
        actuators, gravity = self._actuation(controller)
        return self._mjcf(actuators, gravity)

    def compiled(self, controller: str | ArmController = "position") -> Any:
        """The compiled ``mujoco.MjModel`` with ``controller``'s actuators.

        Compiled once per scene and controller (the last eight are kept). Torque
        controllers compute gravity in their own inverse dynamics, so their model
        never adds the servos' gravity compensation.
        """
        from trajkit.sim.engine import compile_scene

        actuators, gravity = self._actuation(controller)
        key = (gravity, *(actuator.key() for actuator in actuators))
        if key not in self._compiled:
            if len(self._compiled) >= _CACHED_MODELS:
                self._compiled.pop(next(iter(self._compiled)))
            self._compiled[key] = compile_scene(self._mjcf(actuators, gravity))
        return self._compiled[key]

    def _actuation(self, controller: str | ArmController) -> tuple[list[Actuator], bool]:
        control = arm_controller(controller)
        gravity = self.gravity_compensation and not is_torque_control(control)
        return control.actuators(self.ndof), gravity

    def _mjcf(self, actuators: Sequence[Actuator], gravity_compensation: bool) -> str:
        return chain_mjcf(
            self.robot,
            actuators=actuators,
            link_radius=self.link_radius,
            link_mass=self.link_mass,
            damping=self.damping,
            armature=self.armature,
            effort_limit=self.effort_limit,
            gravity_compensation=gravity_compensation,
            timestep=self.timestep,
            inertials=self.inertials,
        )


@dataclass(frozen=True, eq=False)
class MobileScene:
    """A differential-drive base on flat ground, ready for MuJoCo.

    The base has **two driven wheels and two casters** (front and rear, frictionless).
    The wheels sit the kinematic model's *effective* track apart
    (``track_width × track_multiplier``): a four-wheel skid-steer robot such as the
    Jackal turns like a two-wheeled one of that track, which is what its ROS
    controller and trajkit's plans assume, while how much a skid-steer base
    skids depends on tyre and ground properties that a rigid-contact simulator
    does not represent faithfully. The wheels are tyre-shaped ellipsoids with one
    contact point below the axle.

    Parameters
    ----------
    model : DiffDrive
        Wheel radius, effective track, wheelbase (the casters' spacing, with the
        chassis length) and mass (17 kg if the model has none).
    wheel_width : float
        Tyre width (m).
    wheel_mass : float
        Mass of each wheel (kg). Wheels, casters (1% of the mass each) and chassis add
        up to the model's mass (the chassis keeps at least 10% of it).
    caster_radius : float
        Radius of the caster spheres (m).
    wheel_friction : float
        Coulomb friction coefficient of tyre on ground.
    wheel_gain : float
        Velocity-servo gain of each wheel motor (N·m·s/rad): torque per rad/s of
        speed error.
    wheel_damping : float
        Viscous friction of each wheel's bearing (N·m·s/rad).
    timestep : float
        Physics step (s); command periods must be whole multiples of it.
    drive : {"differential", "skid_steer"}
        ``"skid_steer"``: the real four-wheel base instead, its wheels at the corners
        of the real track and wheelbase, no casters, each side's rear wheel turning
        with its front one (one drive a side). It skids in turns as MuJoCo's point
        contacts let it: the Jackal turns in place at about half the rate its
        controller's track multiplier (1.5, measured on the robot) predicts, as if
        the multiplier were about 2.9; driving straight it matches the differential
        scene. The log's kinematic gap says how far a run strays from the plan.
    """

    model: DiffDrive = field(default_factory=jackal)
    wheel_width: float = 0.04
    wheel_mass: float = 0.477
    caster_radius: float = 0.03
    wheel_friction: float = 1.0
    wheel_gain: float = 10.0
    wheel_damping: float = 0.0
    timestep: float = 0.001
    drive: str = "differential"
    _compiled: dict = field(default_factory=dict, init=False, repr=False)

    def __post_init__(self) -> None:
        if self.drive not in ("differential", "skid_steer"):
            raise InvalidInputError(
                f"drive must be 'differential' or 'skid_steer', got {self.drive!r}"
            )
        if not isinstance(self.model, DiffDrive):
            raise InvalidInputError(
                "a mobile scene needs a DiffDrive model (wheels to drive), got "
                f"{type(self.model).__name__}"
            )
        for name, unit in (
            ("wheel_width", "m"),
            ("wheel_mass", "kg"),
            ("caster_radius", "m"),
            ("wheel_friction", ""),
            ("wheel_gain", "N·m·s/rad"),
        ):
            object.__setattr__(self, name, positive_scalar(name, getattr(self, name), unit=unit))
        damping = finite_array("wheel_damping", self.wheel_damping, unit="N·m·s/rad")
        if damping.ndim != 0 or damping < 0.0:
            raise InvalidInputError(f"wheel_damping must be one number >= 0, got {damping}")
        object.__setattr__(self, "wheel_damping", float(damping))
        mass = 17.0 if self.model.mass is None else self.model.mass
        wheels = 4 if self.drive == "skid_steer" else 2
        if wheels * self.wheel_mass + (0.0 if wheels == 4 else 0.02 * mass) > 0.9 * mass:
            raise InvalidInputError(
                f"{'four' if wheels == 4 else 'two'} wheels of {self.wheel_mass:g} kg leave no "
                f"chassis in a {mass:g} kg robot; wheels and casters must weigh less than 90% "
                "of the model's mass"
            )
        if self.caster_radius >= self.model.wheel_radius:
            raise InvalidInputError(
                f"caster_radius {self.caster_radius:g} m must be below the wheel radius "
                f"{self.model.wheel_radius:g} m"
            )
        object.__setattr__(self, "timestep", _timestep(self.timestep))

    def mjcf(self, pose: ArrayLike = (0.0, 0.0, 0.0)) -> str:
        """The scene as MJCF text, the base starting at ``pose`` ``(x, y, θ)`` (m, m, rad)."""
        start = finite_array("pose", pose)
        if start.shape != (3,):
            raise InvalidInputError(f"pose must be (x, y, theta), got shape {start.shape}")
        return diff_drive_mjcf(
            self.model,
            pose=start,
            wheel_width=self.wheel_width,
            wheel_mass=self.wheel_mass,
            caster_radius=self.caster_radius,
            wheel_friction=self.wheel_friction,
            wheel_gain=self.wheel_gain,
            wheel_damping=self.wheel_damping,
            timestep=self.timestep,
            drive=self.drive,
        )

    def compiled(self) -> Any:
        """The ``mujoco.MjModel`` (with the base at the origin), compiled once per scene."""
        from trajkit.sim.engine import compile_scene

        if "model" not in self._compiled:
            self._compiled["model"] = compile_scene(self.mjcf())
        return self._compiled["model"]


def arm_scene(robot: SerialChain, **parameters: object) -> ArmScene:
    """An :class:`ArmScene` for ``robot``; keyword arguments as :class:`ArmScene`'s."""
    return ArmScene(robot, **parameters)  # type: ignore[arg-type]


def rrbot_scene(**parameters: object) -> ArmScene:
    """ROS/Gazebo's RRBot with the physical data of ``rrbot.xacro`` (``RRBot().physical``).

    1 kg links 0.1 m thick on a 2 m post, damping 0.7 N·m·s/rad; keyword arguments
    override any :class:`ArmScene` parameter.
    """
    return ArmScene(RRBot(), **parameters)  # type: ignore[arg-type]


def ur5_scene(**parameters: object) -> ArmScene:
    """The UR5 with the link masses of Universal Robots' description (``UR5().physical``).

    Keyword arguments override any :class:`ArmScene` parameter.
    """
    return ArmScene(UR5(), **parameters)  # type: ignore[arg-type]


def jackal_scene(**parameters: object) -> MobileScene:
    """A :class:`MobileScene` of :func:`~trajkit.mobile.jackal` (17 kg, 0.098 m wheels)."""
    return MobileScene(jackal(), **parameters)  # type: ignore[arg-type]
