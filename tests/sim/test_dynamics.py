"""Tests of trajkit.sim.dynamics: the vectorized Newton–Euler inverse dynamics that
feed-forward uses, against MuJoCo's own ``mj_inverse`` one state at a time.

Both use the masses and inertias MuJoCo compiled from the scene and discrete-time
inverse dynamics for ``implicitfast`` (joint damping and actuator velocity gains
times ``h q̈``), so they agree to rounding: measured 7e-16 of the largest torque.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from trajkit import sim
from trajkit.kinematics import UR5, DHRow, RRBot, SerialChain, Spatial3R
from trajkit.sim.dynamics import inverse_dynamics
from trajkit.sim.engine import compile_scene

mujoco = pytest.importorskip("mujoco", reason="MuJoCo is not installed: pip install 'trajkit[sim]'")

NEWTON_EULER = 1e-12  # relative to the largest torque: two evaluations of the same equations
FEW = settings(max_examples=25, deadline=None)


def prismatic_chain() -> SerialChain:
    rows = [
        DHRow(a=0.3, alpha=np.pi / 2, d=0.1, theta=0.4, lower=-2.0, upper=2.5),
        DHRow(a=0.2, alpha=-0.3, d=0.05, theta=-0.7, kind="prismatic", lower=-0.2, upper=0.3),
        DHRow(a=0.1, alpha=-np.pi / 3, d=0.02, theta=1.1),
    ]
    base = np.eye(4)
    base[:3, 3] = 0.1, -0.2, 0.5
    return SerialChain.from_dh(rows, base=base, name="RPR")


CHAINS = {"RRBot": RRBot, "UR5": UR5, "Spatial3R": Spatial3R, "RPR": prismatic_chain}
CONTROLLERS = {
    "pd_feedforward": sim.PDFeedforward(kp=80.0, kv=12.0),  # velocity gains: implicit terms
    "computed_torque": sim.ComputedTorque(),  # motors only
    "position": sim.PositionServo(kp=50.0, kv=7.0),
}


@functools.cache
def setting(chain: str, controller: str, compensate: bool):
    robot = CHAINS[chain]()
    scene = sim.arm_scene(
        robot,
        damping=0.3,
        armature=0.02,
        link_mass=np.linspace(0.5, 2, robot.ndof),
        gravity_compensation=compensate,
    )
    # Torque controllers never get gravity compensation; the position servo does here.
    return robot, compile_scene(scene.mjcf(CONTROLLERS[controller]))


@pytest.mark.parametrize("chain", list(CHAINS))
@pytest.mark.parametrize("controller", list(CONTROLLERS))
@FEW
@given(compensate=st.booleans(), seed=st.integers(0, 2**32 - 1), count=st.integers(1, 20))
def test_newton_euler_is_mj_inverse(chain, controller, compensate, seed, count):
    robot, model = setting(chain, controller, compensate)
    rng = np.random.default_rng(seed)
    lower = np.where(np.isfinite(robot.lower), robot.lower, -np.pi)
    upper = np.where(np.isfinite(robot.upper), robot.upper, np.pi)
    q = rng.uniform(lower, upper, (count, robot.ndof))
    qd = rng.uniform(-2.0, 2.0, (count, robot.ndof))
    qdd = rng.uniform(-5.0, 5.0, (count, robot.ndof))
    torque = inverse_dynamics(robot, model, q, qd, qdd)
    assert torque.shape == (count, robot.ndof)
    data = mujoco.MjData(model)
    expected = np.empty_like(torque)
    for k in range(count):
        data.qpos[:], data.qvel[:], data.qacc[:] = q[k], qd[k], qdd[k]
        mujoco.mj_inverse(model, data)
        expected[k] = data.qfrc_inverse
    scale = max(1.0, np.abs(expected).max())
    assert np.abs(torque - expected).max() <= NEWTON_EULER * scale


def test_static_torque_is_each_links_weight_on_its_lever():
    # RRBot stretched out along +x (q1 = 90 deg). Link 1 is an L: 0.1 m along its axis
    # (lever 0), then 0.9 m across (lever 0.45 m); link 2 runs 0.95 m from the elbow at
    # 0.9 m. Each link's 1 kg is spread evenly along its length.
    robot = RRBot()
    model = compile_scene(sim.rrbot_scene(gravity_compensation=False).mjcf())
    q = np.array([[np.pi / 2, 0.0]])
    torque = inverse_dynamics(robot, model, q, np.zeros((1, 2)), np.zeros((1, 2)))
    g = 9.81
    shoulder = g * (0.1 * 0.0 + 0.9 * 0.45 + 1.0 * (0.9 + 0.95 / 2))
    elbow = g * 1.0 * 0.95 / 2
    np.testing.assert_allclose(np.abs(torque[0]), [shoulder, elbow], rtol=1e-12)
    assert np.sign(torque[0, 0]) == np.sign(torque[0, 1])  # both hold the arm up
