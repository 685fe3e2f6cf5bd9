"""Arms read from MJCF: MuJoCo's own kinematics and dynamics of the file are the oracle.

``data/four_joint_arm.xml`` holds joint anchors off the body origins, rotated bodies
(quaternions and Euler angles in degrees), a body welded between two moving ones, a
slide joint and limited and unlimited ranges. Its chain's ``fk`` equals MuJoCo's body
pose, and trajkit's Newton-Euler with the chain's inertia equals ``mj_inverse`` of the
file, both to rounding; a scene built from the chain has the file's dynamics.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from trajkit.errors import InvalidInputError
from trajkit.kinematics import from_mjcf, inverse_dynamics

mujoco = pytest.importorskip("mujoco", reason="MuJoCo is not installed: pip install 'trajkit[sim]'")

ARM = Path(__file__).resolve().parent / "data" / "four_joint_arm.xml"


def _states(chain, rng, count):
    low, high = np.maximum(chain.lower, -3.0), np.minimum(chain.upper, 3.0)
    for _ in range(count):  # inside the ranges: no limit forces
        yield rng.uniform(low * 0.95, high * 0.95), *rng.uniform(-1.0, 1.0, (2, chain.ndof))


def test_the_chain_is_the_files_arm():
    chain = from_mjcf(ARM)
    assert chain.name == "four_joint_arm"
    assert chain.names == ["shoulder", "elbow", "extend", "wrist"]
    assert list(chain.revolute) == [True, True, False, True]
    # MJCF ranges are in degrees unless the file says otherwise: ±2° here.
    np.testing.assert_allclose(chain.lower, [-np.radians(2), -np.inf, -0.1, -np.inf])
    np.testing.assert_allclose(chain.upper, [np.radians(2), np.inf, 0.1, np.inf])
    np.testing.assert_allclose(chain.physical.link_mass, [2.7, 1.2, 0.4, 0.3])  # welded lumped


def test_forward_kinematics_and_dynamics_are_mujocos():
    chain = from_mjcf(ARM)
    inertials = chain.physical.inertials(chain.ndof)
    model = mujoco.MjModel.from_xml_path(str(ARM))
    data = mujoco.MjData(model)
    hand = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "hand")
    for q, qd, qdd in _states(chain, np.random.default_rng(3), 40):
        data.qpos[:], data.qvel[:], data.qacc[:] = q, qd, qdd
        mujoco.mj_inverse(model, data)
        pose = chain.fk(q)
        np.testing.assert_allclose(pose[:3, 3], data.xpos[hand], rtol=0, atol=1e-12)
        np.testing.assert_allclose(pose[:3, :3], data.xmat[hand].reshape(3, 3), atol=1e-12)
        ours = inverse_dynamics(chain, q, qd, qdd, inertials=inertials, gravity=model.opt.gravity)
        np.testing.assert_allclose(ours, data.qfrc_inverse, rtol=0, atol=1e-10)


def test_a_scene_of_the_chain_has_the_files_dynamics():
    from trajkit import sim

    chain = from_mjcf(ARM)
    scene = sim.ArmScene(chain, damping=0.0, armature=0.0)
    ours = scene.compiled("computed_torque")
    theirs = mujoco.MjModel.from_xml_path(str(ARM))
    mine, original = mujoco.MjData(ours), mujoco.MjData(theirs)
    for q, qd, qdd in _states(chain, np.random.default_rng(4), 20):
        for model, data in ((ours, mine), (theirs, original)):
            data.qpos[:], data.qvel[:], data.qacc[:] = q, qd, qdd
            mujoco.mj_inverse(model, data)
        np.testing.assert_allclose(mine.qfrc_inverse, original.qfrc_inverse, rtol=0, atol=1e-9)


def test_the_tip_body_chooses_a_branch_and_bad_files_are_refused(tmp_path):
    short = from_mjcf(ARM, tip_body="fore")
    assert short.names == ["shoulder", "elbow"]
    with pytest.raises(InvalidInputError, match="no body named 'palm'"):
        from_mjcf(ARM, tip_body="palm")
    broken = tmp_path / "broken.xml"
    broken.write_text("<mujoco><worldbody><body><joint type='hinge'/>", encoding="utf-8")
    with pytest.raises(InvalidInputError, match="not an MJCF MuJoCo can load"):
        from_mjcf(broken)
    ball = tmp_path / "ball.xml"
    ball.write_text(
        "<mujoco><worldbody><body name='b'><joint type='ball'/><geom size='0.1' mass='1'/>"
        "</body></worldbody></mujoco>",
        encoding="utf-8",
    )
    with pytest.raises(InvalidInputError, match="body 'b' moves by a ball or free joint"):
        from_mjcf(ball)
    fixed = tmp_path / "fixed.xml"
    fixed.write_text("<mujoco><worldbody><body><geom size='0.1'/></body></worldbody></mujoco>",
                     encoding="utf-8")  # fmt: skip
    with pytest.raises(InvalidInputError, match="no body moves by a hinge or slide joint"):
        from_mjcf(fixed)
    fork = tmp_path / "fork.xml"
    fork.write_text(
        "<mujoco><worldbody><body name='root'>"
        + "".join(f"<body name='{n}'><joint type='hinge'/><geom size='0.1' mass='1'/></body>"
                  for n in ("left", "right"))
        + "</body></worldbody></mujoco>", encoding="utf-8")  # fmt: skip
    with pytest.raises(InvalidInputError, match="branches below body 'root' into"):
        from_mjcf(fork)
    assert from_mjcf(fork, tip_body="left").names == ["joint0"]


def test_a_joints_reference_position_is_kept(tmp_path):
    # MJCF draws a body at its joint's ``ref``: MuJoCo's qpos moves it by qpos - ref.
    arm = tmp_path / "ref.xml"
    arm.write_text(
        "<mujoco><compiler angle='radian'/><worldbody><body name='a'>"
        "<joint name='j1' type='hinge' axis='0 0 1' ref='0.4'/><geom size='0.05' mass='1'/>"
        "<body name='b' pos='0.3 0 0'><joint name='j2' type='slide' axis='1 0 0' ref='0.1'/>"
        "<geom size='0.05' mass='1'/></body></body></worldbody></mujoco>",
        encoding="utf-8",
    )
    chain = from_mjcf(arm)
    model = mujoco.MjModel.from_xml_path(str(arm))
    data = mujoco.MjData(model)
    tip = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "b")
    for q in ([0.0, 0.0], [0.4, 0.1], [1.3, -0.2]):
        data.qpos[:] = q
        mujoco.mj_kinematics(model, data)
        np.testing.assert_allclose(chain.fk(np.array(q))[:3, 3], data.xpos[tip], atol=1e-12)
