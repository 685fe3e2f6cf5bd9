"""Tests of trajkit.sim scenes and their MJCF: parameter checks, what the compiled
MuJoCo model holds (joints, ranges, masses, gravity compensation, effort limits,
wheel placement), and that it describes exactly the kinematics trajkit plans with.

MuJoCo's tool site is compared with ``SerialChain.fk`` for random configurations:
the MJCF carries 17 significant digits, so the two agree to rounding (measured
~1e-15 m and ~1e-15 in the rotation matrices; bound FK = 1e-9).
"""

from __future__ import annotations

import functools
from pathlib import Path as FilePath

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import trajkit as tk
from support import ROUNDING
from trajkit import sim
from trajkit.errors import InvalidInputError
from trajkit.kinematics import UR5, DHRow, Joint, Physical, RRBot, SerialChain, Spatial3R
from trajkit.mobile import DiffDrive, Unicycle, jackal
from trajkit.sim.engine import compile_scene

mujoco = pytest.importorskip("mujoco", reason="MuJoCo is not installed: pip install 'trajkit[sim]'")

FK = 1e-9  # m and rotation-matrix entries: MuJoCo's site pose against SerialChain.fk
FEW = settings(max_examples=30, deadline=None)
URDF = FilePath(__file__).resolve().parents[1] / "kinematics" / "data" / "two_link.urdf"


def rot_z(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0, 0.0], [s, c, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0, 0, 0, 1.0]])


def rot_x(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[1.0, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]])


def translation(x: float, y: float, z: float) -> np.ndarray:
    out = np.eye(4)
    out[:3, 3] = x, y, z
    return out


def dh_chain(convention: str) -> SerialChain:
    """Nonzero θ offsets, a bounded prismatic joint, a base and a tilted tool."""
    rows = [
        DHRow(a=0.3, alpha=np.pi / 2, d=0.1, theta=0.4, lower=-2.0, upper=2.5),
        DHRow(a=0.2, alpha=-0.3, d=0.05, theta=-0.7, kind="prismatic", lower=-0.2, upper=0.3),
        DHRow(a=0.1, alpha=-np.pi / 3, d=0.02, theta=1.1),
        DHRow(a=0.0, alpha=np.pi / 2, d=0.15, theta=-2.0),
    ]
    base = translation(0.1, -0.2, 0.5) @ rot_z(0.3)
    tool = translation(0.0, 0.02, 0.08) @ rot_x(0.5)
    return SerialChain.from_dh(rows, convention=convention, base=base, tool=tool,
                               name=f"dh-{convention}")  # fmt: skip


def urdf_chain() -> SerialChain:
    pytest.importorskip("yourdfpy", reason="yourdfpy (URDF reader) is not installed")
    return tk.kinematics.from_urdf(URDF)


CHAINS = {
    "RRBot": RRBot,
    "UR5": UR5,
    "Spatial3R": Spatial3R,
    "DH standard": functools.partial(dh_chain, "standard"),
    "DH modified": functools.partial(dh_chain, "modified"),
    "URDF two_link": urdf_chain,
}


@functools.cache
def chain_and_model(name: str):
    robot = CHAINS[name]()
    return robot, compile_scene(sim.arm_scene(robot).mjcf())


def within_range(robot: SerialChain, unit: np.ndarray) -> np.ndarray:
    """Map draws in [0, 1] into each joint's range (±π where a joint has none)."""
    lower = np.where(np.isfinite(robot.lower), robot.lower, -np.pi)
    upper = np.where(np.isfinite(robot.upper), robot.upper, np.pi)
    return lower + unit * (upper - lower)


# MuJoCo's kinematics are trajkit's ---------------------------------------------------
@pytest.mark.parametrize("name", list(CHAINS))
@FEW
@given(unit=st.lists(st.floats(0.0, 1.0), min_size=6, max_size=6))
def test_tool_site_pose_is_fk(name, unit):
    robot, model = chain_and_model(name)
    q = within_range(robot, np.array(unit[: robot.ndof]))
    data = mujoco.MjData(model)
    data.qpos[:] = q
    mujoco.mj_kinematics(model, data)
    site = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, "tool")
    expected = robot.fk(q)
    assert np.max(np.abs(data.site_xpos[site] - expected[:3, 3])) <= FK
    assert np.max(np.abs(data.site_xmat[site].reshape(3, 3) - expected[:3, :3])) <= FK


@pytest.mark.parametrize("name", list(CHAINS))
def test_joints_in_order_with_trajkit_names_and_kinds(name):
    robot, model = chain_and_model(name)
    assert model.nq == model.nv == robot.ndof
    names = [mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, j) for j in range(model.njnt)]
    assert names == robot.names
    hinge, slide = mujoco.mjtJoint.mjJNT_HINGE, mujoco.mjtJoint.mjJNT_SLIDE
    np.testing.assert_array_equal(model.jnt_type, np.where(robot.revolute, hinge, slide))
    # Joint positions, velocities and actuator forces of every joint, in that order.
    assert model.nsensordata == 3 * robot.ndof


# Joint ranges ---------------------------------------------------------------------
def test_finite_limits_become_joint_ranges():
    robot, model = chain_and_model("UR5")
    assert model.jnt_limited.all()
    np.testing.assert_array_equal(model.jnt_range, np.stack([robot.lower, robot.upper], 1))


def test_dh_prismatic_range_and_unlimited_revolutes():
    _, model = chain_and_model("DH standard")
    np.testing.assert_array_equal(model.jnt_limited, [True, True, False, False])
    np.testing.assert_array_equal(model.jnt_range[:2], [[-2.0, 2.5], [-0.2, 0.3]])


def test_one_sided_limits_keep_their_side_and_no_limits_give_no_range():
    joints = [
        Joint("free", "revolute", origin=translation(0, 0, 0.1)),
        Joint("floor_only", "revolute", origin=translation(0.3, 0, 0), lower=-1.0),
        Joint("ceiling_only", "revolute", origin=translation(0.3, 0, 0), upper=1.0),
    ]
    model = compile_scene(sim.arm_scene(SerialChain(joints, tool=translation(0.2, 0, 0))).mjcf())
    np.testing.assert_array_equal(model.jnt_limited, [False, True, True])
    # The open side is far beyond any motion (1e6 rad).
    np.testing.assert_array_equal(model.jnt_range[1:], [[-1.0, 1e6], [-1e6, 1.0]])
    _, rrbot = chain_and_model("RRBot")
    assert not rrbot.jnt_limited.any()


# Masses, damping, armature, gravity compensation -----------------------------------
@pytest.mark.parametrize("name", ["RRBot", "UR5", "DH standard"])
def test_each_link_body_has_its_link_mass(name):
    robot = CHAINS[name]()
    masses = np.linspace(0.5, 2.0, robot.ndof)
    model = compile_scene(sim.arm_scene(robot, link_mass=masses).mjcf())
    links = [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, f"link{j + 1}")
             for j in range(robot.ndof)]  # fmt: skip
    np.testing.assert_allclose(model.body_mass[links], masses, rtol=ROUNDING, atol=0.0)


def test_damping_and_armature_reach_the_joints():
    scene = sim.arm_scene(UR5(), damping=np.arange(1.0, 7.0), armature=0.25)
    model = compile_scene(scene.mjcf())
    np.testing.assert_array_equal(model.dof_damping, np.arange(1.0, 7.0))
    np.testing.assert_array_equal(model.dof_armature, np.full(6, 0.25))


def test_rrbot_scene_is_the_xacro_robot():
    scene = sim.rrbot_scene()
    np.testing.assert_array_equal(scene.link_mass, [1.0, 1.0])
    np.testing.assert_array_equal(scene.damping, [0.7, 0.7])
    assert scene.link_radius == 0.05
    assert scene.timestep == 0.001
    assert scene.gravity_compensation is True
    model = compile_scene(scene.mjcf())
    assert model.opt.timestep == 0.001
    np.testing.assert_array_equal(model.opt.gravity, [0.0, 0.0, -9.81])


@pytest.mark.parametrize("compensate", [True, False])
def test_gravity_compensation_is_in_the_model(compensate):
    scene = sim.rrbot_scene(gravity_compensation=compensate)
    model = compile_scene(scene.mjcf())
    links = [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, f"link{j}") for j in (1, 2)]
    np.testing.assert_array_equal(model.body_gravcomp[links], [float(compensate)] * 2)
    np.testing.assert_array_equal(model.jnt_actgravcomp, [compensate] * 2)
    # Torque controllers compute gravity themselves: their models never compensate it.
    for controller in ("pd_feedforward", "computed_torque"):
        torque_model = scene.compiled(controller)
        np.testing.assert_array_equal(torque_model.body_gravcomp[links], [0.0, 0.0])
    assert scene.compiled("velocity") is scene.compiled(sim.VelocityServo())  # cached


def test_a_scene_takes_the_robots_physical_data_unless_told_otherwise():
    own = sim.arm_scene(UR5())  # the UR5 carries Universal Robots' link masses
    np.testing.assert_array_equal(own.link_mass, UR5().physical.link_mass)
    assert own.link_radius == 0.045 and own.damping.tolist() == [0.1] * 6  # no damping given
    assert sim.ur5_scene().link_mass.tolist() == own.link_mass.tolist()
    told = sim.arm_scene(UR5(), link_mass=2.0, damping=0.5)
    assert told.link_mass.tolist() == [2.0] * 6 and told.damping.tolist() == [0.5] * 6
    bare = sim.arm_scene(UR5().with_physical(Physical()))  # nothing given: the defaults
    assert bare.link_mass.tolist() == [1.0] * 6 and bare.armature.tolist() == [0.01] * 6
    with pytest.raises(InvalidInputError, match="link_mass"):
        sim.arm_scene(UR5().with_physical(Physical(link_mass=[1.0, 2.0])))


def test_default_link_radius_is_three_percent_of_reach():
    bare = UR5().with_physical(Physical())
    assert sim.arm_scene(bare).link_radius == pytest.approx(0.03 * UR5().reach(), rel=ROUNDING)
    tiny = SerialChain([Joint("j", "revolute")], tool=translation(0.05, 0, 0))
    assert sim.arm_scene(tiny).link_radius == 0.01


def test_per_joint_parameters_broadcast():
    scene = sim.arm_scene(UR5(), link_mass=2.0, damping=0.0, armature=0.0, effort_limit=50.0)
    for attribute, value in (("link_mass", 2.0), ("damping", 0.0), ("armature", 0.0),
                             ("effort_limit", 50.0)):  # fmt: skip
        np.testing.assert_array_equal(getattr(scene, attribute), np.full(6, value))
    assert scene.ndof == 6


# Effort limits --------------------------------------------------------------------
def test_effort_limit_is_the_joints_actuator_force_range():
    model = compile_scene(sim.rrbot_scene(effort_limit=[8.0, 1.0]).mjcf())
    np.testing.assert_array_equal(model.jnt_actfrclimited, [True, True])
    np.testing.assert_array_equal(model.jnt_actfrcrange, [[-8.0, 8.0], [-1.0, 1.0]])
    assert not compile_scene(sim.rrbot_scene().mjcf()).jnt_actfrclimited.any()


SEED_000 = tk.cubic(np.radians([0, 0]), np.radians([67, -45]), vmax=np.radians([9, 11]))


CONTROLLERS = ["position", "velocity", "pd_feedforward", "computed_torque"]


@pytest.mark.parametrize("controller", CONTROLLERS)
def test_effort_limit_clamps_every_controllers_efforts(controller):
    # Unlimited, seed 000 needs 13.6 and 1.8 N·m; the limits cut both.
    limit = np.array([8.0, 1.0])
    log = sim.run(sim.rrbot_scene(effort_limit=limit), SEED_000, controller=controller)
    assert np.all(np.abs(log.efforts) <= limit + 1e-9)
    # The limit is reached: the drive saturates instead of producing the torque.
    np.testing.assert_allclose(log.peak_effort, limit, rtol=1e-9)
    assert np.degrees(log.max_error.max()) > 10.0  # measured 140-149 deg: it cannot follow


def test_computed_torque_commands_more_than_the_limit_lets_through():
    limit = np.array([8.0, 1.0])
    log = sim.run(sim.rrbot_scene(effort_limit=limit), SEED_000, controller="computed_torque")
    assert np.all(np.abs(log.commands).max(axis=0) > 10.0 * limit)  # measured 5462, 1864 N·m
    np.testing.assert_array_equal(log.efforts, np.clip(log.commands, -limit, limit))


# ArmScene validation ----------------------------------------------------------------
@pytest.mark.parametrize("robot", ["RRBot", None, Unicycle(), jackal()])
def test_arm_scene_needs_a_serial_chain(robot):
    with pytest.raises(InvalidInputError, match=r"robot must be a trajkit\.kinematics SerialChain"):
        sim.ArmScene(robot)


@pytest.mark.parametrize(
    ("parameters", "match"),
    [
        ({"link_mass": -1.0}, r"link_mass must be > 0 kg"),
        ({"link_mass": 0.0}, r"link_mass must be > 0 kg"),
        ({"link_mass": [1.0, -0.5]}, r"link_mass must be > 0 kg, got \[1.0, -0.5\]"),
        ({"link_mass": np.nan}, r"link_mass must be finite"),
        ({"link_mass": [1.0, 2.0, 3.0]}, r"link_mass must be one number or one per joint \(2\)"),
        ({"link_mass": [[1.0, 2.0]]}, r"link_mass must be one number or one per joint \(2\)"),
        ({"damping": -0.1}, r"damping must be >= 0"),
        ({"damping": [np.inf, 0.0]}, r"damping must be finite"),
        ({"armature": -1e-3}, r"armature must be >= 0"),
        ({"armature": [0.1]}, r"armature must be one number or one per joint \(2\)"),
        ({"effort_limit": 0.0}, r"effort_limit must be > 0"),
        ({"effort_limit": [5.0, -5.0]}, r"effort_limit must be > 0"),
        ({"effort_limit": np.nan}, r"effort_limit must be finite"),
        ({"link_radius": -0.01}, r"link_radius must be > 0"),
        ({"link_radius": np.nan}, r"link_radius must be finite"),
        ({"timestep": 0.02}, r"timestep must be at most 0.01 s"),
        ({"timestep": 0.0}, r"timestep must be > 0"),
        ({"timestep": -0.001}, r"timestep must be > 0"),
        ({"timestep": np.nan}, r"timestep must be finite"),
        ({"link_mass": "heavy"}, r"link_mass must be numeric"),
    ],
)
def test_arm_scene_refuses_bad_parameters(parameters, match):
    with pytest.raises(InvalidInputError, match=match):
        sim.rrbot_scene(**parameters)


def test_timestep_of_one_hundredth_is_allowed():
    assert sim.rrbot_scene(timestep=0.01).timestep == 0.01


def test_unbounded_prismatic_chain_gets_a_finite_scene():
    robot = SerialChain.from_dh([DHRow(a=0.3, theta=0.4), DHRow(d=0.05, kind="prismatic")])
    scene = sim.arm_scene(robot)
    assert np.isfinite(scene.link_radius)
    assert "inf" not in scene.mjcf()
    log = sim.run(scene, tk.cubic([0.0, 0.0], [0.5, 0.1], duration=1.0),
                  controller="computed_torque")  # fmt: skip
    assert np.all(log.max_error < 1e-3)


# MobileScene -------------------------------------------------------------------------
def wheel_model(scene):
    model = compile_scene(scene.mjcf())
    body = [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, f"{side}_wheel")
            for side in ("left", "right")]  # fmt: skip
    return model, body


@pytest.mark.parametrize(
    "robot",
    [jackal(), DiffDrive(0.1, 0.5), DiffDrive(0.05, 0.3, track_multiplier=1.2, wheelbase=0.2)],
)
def test_wheels_are_the_effective_track_apart(robot):
    scene = sim.MobileScene(robot)
    model, wheels = wheel_model(scene)
    left, right = model.body_pos[wheels]
    assert left[1] - right[1] == pytest.approx(robot.effective_track, rel=ROUNDING)
    assert left[1] == pytest.approx(robot.effective_track / 2, rel=ROUNDING)
    np.testing.assert_array_equal(left[[0, 2]], [0.0, 0.0])  # on the axle, under the chassis frame
    # The wheel joints turn about the axle (the chassis' y axis).
    for side in ("left", "right"):
        joint = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, f"{side}_wheel")
        np.testing.assert_array_equal(model.jnt_axis[joint], [0.0, 1.0, 0.0])


def test_mobile_scene_stands_on_wheels_and_casters():
    scene = sim.jackal_scene()
    model = compile_scene(scene.mjcf())
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    radius = scene.model.wheel_radius
    chassis = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "chassis")
    assert data.xpos[chassis][2] == pytest.approx(radius, rel=ROUNDING)  # axle at wheel height
    for end in ("front", "rear"):
        geom = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, f"{end}_caster")
        bottom = data.geom_xpos[geom][2] - model.geom_size[geom][0]
        assert abs(bottom) <= 1e-12  # the caster touches the floor
    assert model.nu == 2
    np.testing.assert_array_equal(model.actuator_gainprm[:, 0], [scene.wheel_gain] * 2)


def test_mobile_scene_starts_at_the_pose_given_to_mjcf():
    model = compile_scene(sim.jackal_scene().mjcf((1.0, -2.0, np.pi / 2)))
    chassis = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "chassis")
    np.testing.assert_allclose(model.body_pos[chassis], [1.0, -2.0, 0.098], rtol=0, atol=1e-15)
    np.testing.assert_allclose(model.body_quat[chassis], [np.sqrt(0.5), 0, 0, np.sqrt(0.5)],
                               rtol=0, atol=1e-15)  # fmt: skip


def test_simulated_base_weighs_the_models_mass():
    model = compile_scene(sim.jackal_scene().mjcf())
    assert model.body_subtreemass[0] == pytest.approx(jackal().mass, rel=1e-9)


@pytest.mark.parametrize(
    ("parameters", "match"),
    [
        ({"model": Unicycle()}, r"a mobile scene needs a DiffDrive model .* got Unicycle"),
        ({"model": UR5()}, r"needs a DiffDrive model"),
        ({"caster_radius": 0.098}, r"caster_radius 0.098 m must be below the wheel radius 0.098"),
        ({"caster_radius": 0.2}, r"must be below the wheel radius"),
        ({"caster_radius": 0.0}, r"caster_radius must be > 0"),
        ({"wheel_width": -0.04}, r"wheel_width must be > 0"),
        ({"wheel_mass": -1.0}, r"wheel_mass must be > 0"),
        ({"wheel_mass": np.nan}, r"wheel_mass must be finite"),
        ({"wheel_friction": 0.0}, r"wheel_friction must be > 0"),
        ({"wheel_gain": -10.0}, r"wheel_gain must be > 0"),
        ({"wheel_damping": -0.1}, r"wheel_damping must be one number >= 0"),
        ({"wheel_damping": [0.1, 0.1]}, r"wheel_damping must be one number >= 0"),
        ({"timestep": 0.05}, r"timestep must be at most 0.01 s"),
        ({"timestep": 0.0}, r"timestep must be > 0"),
    ],
)
def test_mobile_scene_refuses_bad_parameters(parameters, match):
    with pytest.raises(InvalidInputError, match=match):
        sim.MobileScene(**parameters)


@pytest.mark.parametrize(
    ("pose", "match"),
    [((0.0, 0.0), r"pose must be \(x, y, theta\)"), ((0.0, np.nan, 0.0), "pose must be finite")],
)
def test_mobile_mjcf_refuses_bad_poses(pose, match):
    with pytest.raises(InvalidInputError, match=match):
        sim.jackal_scene().mjcf(pose)


def test_jackal_scene_overrides():
    scene = sim.jackal_scene(wheel_gain=20.0, timestep=0.002)
    assert (scene.wheel_gain, scene.timestep) == (20.0, 0.002)
    assert scene.model == jackal()


def test_scene_arrays_are_read_only_so_compiled_models_stay_true():
    scene = sim.rrbot_scene()
    for name in ("link_mass", "damping", "armature"):
        with pytest.raises(ValueError, match="read-only"):
            getattr(scene, name)[:] = 5.0
    given = np.array([1.0, 2.0])
    scene = sim.rrbot_scene(link_mass=given)
    given[:] = 9.0  # the caller's array is copied, not shared
    np.testing.assert_array_equal(scene.link_mass, [1.0, 2.0])


@pytest.mark.parametrize("value", ["no", 1, None])
def test_gravity_compensation_must_be_a_bool(value):
    with pytest.raises(InvalidInputError, match="gravity_compensation must be True or False"):
        sim.rrbot_scene(gravity_compensation=value)


def test_wheels_heavier_than_the_robot_are_refused():
    with pytest.raises(InvalidInputError, match="two wheels of 100 kg leave no chassis in a 17 kg"):
        sim.jackal_scene(wheel_mass=100.0)


def test_ur5_scene_has_universal_robots_link_masses():
    model = sim.ur5_scene().compiled()
    links = [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, f"link{j}") for j in range(1, 7)]
    np.testing.assert_allclose(model.body_mass[links], [3.7, 8.393, 2.33, 1.219, 1.219, 0.1879],
                               rtol=1e-12)  # fmt: skip


def test_pedestal_stands_straight_below_an_offset_base():
    base = np.eye(4)
    base[:3, 3] = [1.0, 0.5, 0.5]
    robot = SerialChain.from_dh([DHRow(a=0.3)], base=base)
    model = sim.arm_scene(robot).compiled()
    mujoco.mj_forward(model, data := mujoco.MjData(model))
    pedestal = next(
        g for g in range(model.ngeom) if model.geom_type[g] == mujoco.mjtGeom.mjGEOM_CYLINDER
    )
    np.testing.assert_allclose(data.geom_xpos[pedestal], [1.0, 0.5, 0.25], atol=1e-12)


def test_compiled_models_are_cached_and_bounded():
    scene = sim.rrbot_scene()
    first = scene.compiled(sim.PositionServo(kp=1.0))
    assert scene.compiled(sim.PositionServo(kp=1.0)) is first
    for kp in range(2, 12):
        scene.compiled(sim.PositionServo(kp=float(kp)))
    assert len(scene._compiled) <= 8


@pytest.mark.parametrize(
    ("controller", "kinds", "gains"),
    [
        (sim.PositionServo(kp=[1.0, 2.0], kv=3.0), ["position"], [([1, 2], [3, 3])]),
        (
            sim.VelocityServo(kp=4.0, kv=[5.0, 0.0]),
            ["intvelocity", "velocity"],
            [([4, 4], None), (None, [5, 0])],
        ),
        (
            sim.PDFeedforward(kp=0.0, kv=6.0),
            ["motor", "position", "velocity"],
            [(None, None), ([0, 0], None), (None, [6, 6])],
        ),
        (sim.ComputedTorque(), ["motor"], [(None, None)]),
    ],
)
def test_each_controller_puts_its_actuators_and_gains_on_every_joint(controller, kinds, gains):
    actuators = controller.actuators(2)
    assert [actuator.kind for actuator in actuators] == kinds
    for actuator, (kp, kv) in zip(actuators, gains, strict=True):
        for value, expected in ((actuator.kp, kp), (actuator.kv, kv)):
            if expected is None:
                assert value is None
            else:
                np.testing.assert_array_equal(value, expected)
