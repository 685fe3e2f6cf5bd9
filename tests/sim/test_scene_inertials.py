"""Scenes carry the links' own inertia: a URDF's ``<inertial>`` elements, the UR5's data.

The check is MuJoCo's own inverse dynamics (``mj_inverse``) of the compiled scene
against trajkit's recursive Newton–Euler with the same inertials: equal to rounding
(1e-9 of the largest torque) at random states inside the joint ranges. The URDFs are
those Robotics Toolbox's data package ships (a test dependency): a KUKA KR16 and a
Lynxmotion AL5D, both with inertials.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from trajkit import sim
from trajkit.errors import InvalidInputError
from trajkit.kinematics import UR5, Inertials, RRBot, inverse_dynamics
from trajkit.kinematics.urdf import from_urdf

mujoco = pytest.importorskip("mujoco", reason="MuJoCo is not installed: pip install 'trajkit[sim]'")


def _rtbdata(relative: str) -> Path:
    rtbdata = pytest.importorskip(
        "rtbdata", reason="Robotics Toolbox's URDFs: pip install roboticstoolbox-python"
    )
    return Path(rtbdata.__file__).parent / "xacro" / relative


ROBOTS = {
    "ur5": lambda: UR5(),
    "kr16": lambda: from_urdf(
        _rtbdata("kuka_description/kuka_kr16/urdf/kr16_2.urdf"), tip_link="tool0"
    ),
    "al5d": lambda: from_urdf(_rtbdata("lynxmotion_al5d_description/urdf/al5d_robot.urdf")),
}


@pytest.mark.parametrize("name", sorted(ROBOTS))
def test_the_scenes_dynamics_are_the_robots_own(name: str) -> None:
    robot = ROBOTS[name]()
    scene = sim.ArmScene(robot, damping=0.0, armature=0.0)
    own = robot.physical.inertials(robot.ndof)
    np.testing.assert_array_equal(scene.inertials.mass, own.mass)
    model = scene.compiled("computed_torque")
    np.testing.assert_allclose(model.body_mass[-robot.ndof :], np.maximum(own.mass, 1e-9))
    data = mujoco.MjData(model)
    rng = np.random.default_rng(7)
    low, high = np.maximum(robot.lower, -np.pi), np.minimum(robot.upper, np.pi)
    for _ in range(25):
        q = rng.uniform(low + 0.02, high - 0.02)  # inside the ranges: no limit forces
        qd, qdd = rng.uniform(-1.5, 1.5, (2, robot.ndof))
        data.qpos[:], data.qvel[:], data.qacc[:] = q, qd, qdd
        mujoco.mj_inverse(model, data)
        ours = inverse_dynamics(robot, q, qd, qdd, inertials=own, gravity=model.opt.gravity)
        scale = max(1.0, float(np.abs(ours).max()))
        np.testing.assert_allclose(data.qfrc_inverse, ours, rtol=0, atol=1e-9 * scale)


def test_a_robot_without_inertials_keeps_the_capsules_masses() -> None:
    scene = sim.ArmScene(RRBot())  # rrbot.xacro gives masses, no inertia tensors
    assert scene.inertials is None
    assert "<inertial" not in scene.mjcf()
    capsules = sim.ArmScene(UR5(), link_mass=2.0)  # masses given: capsules, as asked
    assert capsules.inertials is None and "<inertial" not in capsules.mjcf()


def test_inertials_given_to_a_scene_are_checked() -> None:
    robot = RRBot()
    rod = Inertials([1.0, 1.0], [[0.5, 0, 0], [0.5, 0, 0]], np.stack([np.diag([0, 0.1, 0.1])] * 2))
    scene = sim.ArmScene(robot, inertials=rod)
    assert scene.mjcf().count("<inertial") == 2
    with pytest.raises(InvalidInputError, match="inertials give 1 links but RRBot has 2 joints"):
        sim.ArmScene(robot, inertials=Inertials([1.0], [[0, 0, 0]], [np.eye(3) * 0.1]))
    with pytest.raises(InvalidInputError, match=r"inertials must be a trajkit\.kinematics\."):
        sim.ArmScene(robot, inertials={"mass": [1.0, 1.0]})
