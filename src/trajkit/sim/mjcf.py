"""MJCF text for trajkit's robots: serial chains and differential-drive bases.

MuJoCo reads its models from MJCF (XML). These writers turn a
:class:`~trajkit.kinematics.SerialChain` or a
:class:`~trajkit.mobile.DiffDrive` into a complete scene: a floor, a light, the
robot's bodies and joints, its actuators and the sensors the simulation logs.
Numbers are written with 17 significant digits, so the scene describes exactly
the kinematics trajkit plans with.
"""

from __future__ import annotations

import itertools
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.spatial.transform import Rotation

from trajkit._validation import FloatArray
from trajkit.kinematics.chain import SerialChain
from trajkit.kinematics.inertials import Inertials
from trajkit.mobile.models import DiffDrive

__all__ = ["Actuator", "arm_extent", "chain_mjcf", "diff_drive_mjcf"]

#: Below this (m) a link segment is not drawn: coincident joint origins.
_MIN_SEGMENT = 1e-9
#: The far end of a joint range open on one side (rad or m).
_OPEN_RANGE = 1e6


@dataclass(frozen=True)
class Actuator:
    """One MuJoCo actuator per joint: its element name and gain attributes."""

    kind: str  # "position", "velocity", "intvelocity" or "motor"
    kp: FloatArray | None = None
    kv: FloatArray | None = None

    def key(self) -> tuple:
        """A hashable value equal for actuators that write the same MJCF."""
        gains = [None if g is None else tuple(np.asarray(g, dtype=float).tolist())
                 for g in (self.kp, self.kv)]  # fmt: skip
        return (self.kind, *gains)


def arm_extent(robot: SerialChain) -> float:
    """A finite size of the arm (m), for link radii, the floor and the camera.

    The reach where it is finite; else (an unbounded prismatic joint) the farthest
    point of the arm at its middle configuration, at least 0.1 m.
    """
    reach = robot.reach()
    if np.isfinite(reach):
        return max(reach, 1e-3)
    lower, upper = robot.lower, robot.upper
    bounded = np.isfinite(lower) & np.isfinite(upper)
    middle = np.zeros(robot.ndof)
    middle[bounded] = (lower[bounded] + upper[bounded]) / 2.0
    middle = np.clip(middle, lower, upper)
    points = robot.points(middle)
    return max(float(np.linalg.norm(points - points[0], axis=1).max()), 0.1)


def _num(value: float) -> str:
    return f"{float(value):.17g}"


def _vec(values: Sequence[float] | FloatArray) -> str:
    return " ".join(_num(v) for v in np.asarray(values, dtype=float).ravel())


def _quat(rotation: FloatArray) -> str:
    x, y, z, w = Rotation.from_matrix(rotation).as_quat()
    return _vec([w, x, y, z])  # MuJoCo's order: scalar first


def _scene_root(name: str, timestep: float, extent: float) -> tuple[ET.Element, ET.Element]:
    root = ET.Element("mujoco", model=name)
    ET.SubElement(root, "compiler", angle="radian", autolimits="true")
    # implicitfast integrates joint damping and actuator velocity gains implicitly:
    # stiff servos stay stable at a millisecond step.
    option = ET.SubElement(root, "option", timestep=_num(timestep), integrator="implicitfast")
    # Inverse dynamics consistent with that discrete-time integrator, so computed
    # torque and feed-forward cancel the implicit damping exactly.
    ET.SubElement(option, "flag", invdiscrete="enable")
    visual = ET.SubElement(root, "visual")
    ET.SubElement(visual, "global", offwidth="1280", offheight="960")
    ET.SubElement(visual, "map", znear="0.01")
    asset = ET.SubElement(root, "asset")
    ET.SubElement(
        asset,
        "texture",
        type="skybox",
        builtin="gradient",
        rgb1="0.62 0.74 0.86",
        rgb2="0.95 0.96 0.98",
        width="256",
        height="256",
    )
    ET.SubElement(
        asset,
        "texture",
        name="grid",
        type="2d",
        builtin="checker",
        width="512",
        height="512",
        rgb1="0.82 0.84 0.86",
        rgb2="0.72 0.74 0.76",
    )
    ET.SubElement(
        asset,
        "material",
        name="grid",
        texture="grid",
        texrepeat="1 1",
        texuniform="true",
        reflectance="0.05",
    )
    ET.SubElement(asset, "material", name="link", rgba="0.93 0.55 0.16 1")
    ET.SubElement(asset, "material", name="joint", rgba="0.25 0.3 0.38 1")
    ET.SubElement(asset, "material", name="base", rgba="0.45 0.47 0.5 1")
    world = ET.SubElement(root, "worldbody")
    ET.SubElement(
        world,
        "light",
        pos=_vec([0, 0, 3 * extent]),
        dir="0 0 -1",
        directional="true",
        diffuse="0.8 0.8 0.8",
    )
    ET.SubElement(
        world,
        "geom",
        name="floor",
        type="plane",
        size=_vec([3 * extent] * 2 + [0.05]),
        material="grid",
        friction="1 0.005 0.0001",
    )
    return root, world


def _to_text(root: ET.Element) -> str:
    ET.indent(root)
    return ET.tostring(root, encoding="unicode")


def _link_segments(axis: FloatArray, end: FloatArray) -> list[tuple[FloatArray, FloatArray]]:
    """A link from a joint (at the origin) to ``end``: along the axis, then across it.

    Denavit–Hartenberg links are such L shapes (an offset ``d`` along the joint
    axis, a length ``a`` across it), and drawing them so keeps a link's mass
    where the link is.
    """
    foot = axis * float(axis @ end)
    points = [np.zeros(3), foot, end]
    return [(a, b) for a, b in itertools.pairwise(points) if np.linalg.norm(b - a) > _MIN_SEGMENT]


def chain_mjcf(
    robot: SerialChain,
    *,
    actuators: Sequence[Actuator],
    link_radius: float,
    link_mass: FloatArray,
    damping: FloatArray,
    armature: FloatArray,
    effort_limit: FloatArray | None,
    gravity_compensation: bool,
    timestep: float,
    inertials: Inertials | None = None,
) -> str:
    """MJCF of ``robot`` on a floor, with ``actuators`` on every joint.

    Each joint's body frame is its trajkit frame at ``q = 0`` with the joint's
    offset applied, so MuJoCo's ``qpos`` is trajkit's ``q``. Links are capsules
    of ``link_radius`` from joint to joint (and to the tool); each body also has a
    sphere at its joint. Arm geoms collide with nothing: the scene is for
    tracking, not contact. Sensors: joint positions, velocities and the total
    actuator force of every joint, in that order.

    With ``inertials``, each body carries its link's mass, centre of mass and
    inertia tensor (in the joint's frame after its motion, which is the body's), and
    the geoms none; a massless link gets 1e-9 kg (MuJoCo moves no massless body),
    and every tensor 1e-12 kg·m² on its diagonal (a rod's is only semi-definite).
    """
    root, world = _scene_root(robot.name, timestep, max(arm_extent(robot), link_radius))
    base = robot.base
    parent = ET.SubElement(
        world, "body", name="base", pos=_vec(base[:3, 3]), quat=_quat(base[:3, :3])
    )
    if base[2, 3] > link_radius:
        # A pedestal from the floor up to the base, drawn in the base's frame.
        floor = base[:3, :3].T @ (np.array([base[0, 3], base[1, 3], 0.0]) - base[:3, 3])
        ET.SubElement(
            parent,
            "geom",
            type="cylinder",
            fromto=_vec([*floor, 0.0, 0.0, 0.0]),
            size=_num(1.5 * link_radius),
            material="base",
            contype="0",
            conaffinity="0",
        )
    joints = robot.joints
    for index, joint in enumerate(joints):
        frame = joint.origin.copy()
        if joint.revolute:
            frame[:3, :3] = (
                frame[:3, :3] @ Rotation.from_rotvec(joint.axis * joint.offset).as_matrix()
            )
        else:
            frame[:3, 3] = frame[:3, 3] + frame[:3, :3] @ (joint.axis * joint.offset)
        body = ET.SubElement(
            parent,
            "body",
            name=f"link{index + 1}",
            pos=_vec(frame[:3, 3]),
            quat=_quat(frame[:3, :3]),
        )
        if gravity_compensation:
            body.set("gravcomp", "1")
        attributes = {
            "name": joint.name,
            "type": "hinge" if joint.revolute else "slide",
            "axis": _vec(joint.axis),
            "damping": _num(damping[index]),
            "armature": _num(armature[index]),
        }
        if np.isfinite(joint.lower) or np.isfinite(joint.upper):
            # MJCF ranges have two ends: an open side becomes one no motion reaches.
            lower = joint.lower if np.isfinite(joint.lower) else -_OPEN_RANGE
            upper = joint.upper if np.isfinite(joint.upper) else _OPEN_RANGE
            attributes["range"] = _vec([lower, upper])
        if effort_limit is not None:
            # The drive's torque limit bounds the sum of all actuators on the joint.
            attributes["actuatorfrcrange"] = _vec([-effort_limit[index], effort_limit[index]])
        if gravity_compensation:
            # Gravity compensation acts through the joint's actuators, so it counts in
            # the efforts the log reports, as a drive's gravity feed-forward would.
            attributes["actuatorgravcomp"] = "true"
        ET.SubElement(body, "joint", attributes)
        if inertials is not None:
            tensor = inertials.inertia[index] + 1e-12 * np.eye(3)
            ET.SubElement(body, "inertial", pos=_vec(inertials.center_of_mass[index]),
                          mass=_num(max(float(inertials.mass[index]), 1e-9)),
                          fullinertia=_vec([tensor[0, 0], tensor[1, 1], tensor[2, 2], tensor[0, 1],
                                            tensor[0, 2], tensor[1, 2]]))  # fmt: skip
        end = joints[index + 1].origin[:3, 3] if index + 1 < len(joints) else robot.tool[:3, 3]
        segments = _link_segments(joint.axis, end)
        lengths = np.array([np.linalg.norm(b - a) for a, b in segments])
        ET.SubElement(
            body,
            "geom",
            type="sphere",
            size=_num(1.4 * link_radius),
            mass=_num(link_mass[index] if not segments else 0.0),
            material="joint",
            contype="0",
            conaffinity="0",
        )
        for (a, b), length in zip(segments, lengths, strict=True):
            ET.SubElement(
                body,
                "geom",
                type="capsule",
                fromto=_vec([*a, *b]),
                size=_num(link_radius),
                mass=_num(link_mass[index] * length / lengths.sum()),
                material="link",
                contype="0",
                conaffinity="0",
            )
        parent = body
    tool = robot.tool
    ET.SubElement(
        parent,
        "site",
        name="tool",
        pos=_vec(tool[:3, 3]),
        quat=_quat(tool[:3, :3]),
        size=_num(link_radius),
    )
    actuator = ET.SubElement(root, "actuator")
    for spec in actuators:
        for index, joint in enumerate(joints):
            element = ET.SubElement(
                actuator, spec.kind, name=f"{spec.kind}_{joint.name}", joint=joint.name
            )
            if spec.kp is not None:
                element.set("kp", _num(spec.kp[index]))
            if spec.kv is not None:
                element.set("kv", _num(spec.kv[index]))
    sensor = ET.SubElement(root, "sensor")
    for kind in ("jointpos", "jointvel", "jointactuatorfrc"):
        for joint in joints:
            ET.SubElement(sensor, kind, name=f"{kind}_{joint.name}", joint=joint.name)
    return _to_text(root)


def diff_drive_mjcf(
    model: DiffDrive,
    *,
    pose: FloatArray,
    wheel_width: float,
    wheel_mass: float,
    caster_radius: float,
    wheel_friction: float,
    wheel_gain: float,
    wheel_damping: float,
    timestep: float,
    drive: str = "differential",
) -> str:
    """MJCF of a wheeled base: two driven wheels and two casters, or four skid-steer wheels.

    The chassis frame sits on the wheel axle, midway between the wheels, at the
    start ``pose`` ``(x, y, θ)``. The wheels are ``model.effective_track`` apart,
    so that the physics and the kinematic model describe the same robot; the
    casters (frictionless spheres, front and rear) carry the chassis level.
    Actuators: a velocity servo per wheel (``wheel_gain`` N·m·s/rad). Sensors:
    the chassis position and orientation, wheel angles, wheel speeds and wheel
    torques.

    ``drive="skid_steer"``: four wheels at the corners of the real ``track_width`` by
    ``wheelbase``, no casters; the rear wheel of each side turns with the front one
    (a joint equality: one drive a side, as the Jackal's), so the actuators, sensors
    and wheel names are the same. How far it skids in a turn, and so its effective
    track, comes from the tyres' friction on the ground.
    """
    four = drive == "skid_steer"
    radius = model.wheel_radius
    track = model.track_width if four else model.effective_track
    length = max(model.wheelbase, 2.0 * radius) + 2.0 * caster_radius
    width = max(track - wheel_width - 0.02, 0.5 * track)
    height = max(0.5 * radius, 0.05)
    mass = 17.0 if model.mass is None else model.mass
    caster_mass = 0.01 * mass
    # Wheels and casters are part of the model's mass (when it leaves room for a chassis).
    wheels = 4 if four else 2
    chassis_mass = max(mass - wheels * wheel_mass - (0 if four else 2) * caster_mass, 0.1 * mass)
    root, world = _scene_root(model.name, timestep, max(length, track) * 4.0)
    x, y, theta = (float(v) for v in pose)
    chassis = ET.SubElement(
        world,
        "body",
        name="chassis",
        pos=_vec([x, y, radius]),
        quat=_vec([np.cos(theta / 2), 0.0, 0.0, np.sin(theta / 2)]),
    )
    ET.SubElement(chassis, "freejoint", name="chassis")
    ET.SubElement(
        chassis,
        "geom",
        name="chassis",
        type="box",
        size=_vec([length / 2, width / 2, height / 2]),
        pos=_vec([0, 0, height / 2]),
        mass=_num(chassis_mass),
        material="link",
    )
    ET.SubElement(chassis, "site", name="chassis", size="0.01")
    # The driven wheel of each side, and with four wheels its rear twin (one axle ahead).
    ahead = model.wheelbase / 2.0 if four else 0.0
    places = [(f"{side}_wheel", ahead, sign) for side, sign in (("left", 1.0), ("right", -1.0))]
    if four:
        places += [(f"rear_{side}_wheel", -ahead, sign)
                   for side, sign in (("left", 1.0), ("right", -1.0))]  # fmt: skip
    for name, forward, sign in places:
        wheel = ET.SubElement(chassis, "body", name=name, pos=_vec([forward, sign * track / 2, 0]))
        ET.SubElement(
            wheel,
            "joint",
            name=name,
            type="hinge",
            axis="0 1 0",
            damping=_num(wheel_damping),
        )
        # A tyre-shaped ellipsoid touches flat ground at one point below the axle; a
        # cylinder touches it along both rims, which scrub against each other in turns.
        ET.SubElement(
            wheel,
            "geom",
            name=name,
            type="ellipsoid",
            size=_vec([radius, wheel_width / 2, radius]),
            mass=_num(wheel_mass),
            material="joint",
            friction=_vec([wheel_friction, 0.005, 0.0001]),
        )
    if four:  # one drive a side: the rear wheel turns with the front one
        equality = ET.SubElement(root, "equality")
        for side in ("left", "right"):
            ET.SubElement(equality, "joint", joint1=f"rear_{side}_wheel", joint2=f"{side}_wheel",
                          polycoef="0 1 0 0 0")  # fmt: skip
    for end, sign in (("front", 1.0), ("rear", -1.0)) if not four else ():
        # Higher priority: the caster's own (frictionless) contact settings win.
        ET.SubElement(
            chassis,
            "geom",
            name=f"{end}_caster",
            type="sphere",
            size=_num(caster_radius),
            pos=_vec([sign * (length / 2 - caster_radius), 0, caster_radius - radius]),
            mass=_num(caster_mass),
            condim="1",
            priority="1",
            material="base",
        )
    actuator = ET.SubElement(root, "actuator")
    for side in ("left", "right"):
        ET.SubElement(
            actuator, "velocity", name=f"{side}_wheel", joint=f"{side}_wheel", kv=_num(wheel_gain)
        )
    sensor = ET.SubElement(root, "sensor")
    ET.SubElement(sensor, "framepos", name="chassis_position", objtype="site", objname="chassis")
    ET.SubElement(
        sensor, "framequat", name="chassis_orientation", objtype="site", objname="chassis"
    )
    for kind in ("jointpos", "jointvel", "jointactuatorfrc"):
        for side in ("left", "right"):
            ET.SubElement(sensor, kind, name=f"{kind}_{side}_wheel", joint=f"{side}_wheel")
    return _to_text(root)
