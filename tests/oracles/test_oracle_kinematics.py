"""Kinematics against the peers: Robotics Toolbox (DH robots) and modern_robotics (screws).

The peers are test oracles only, built from trajkit's own parameters: Robotics
Toolbox's ``models.DH.UR5`` uses d1 = 0.089459 m where the manufacturer (and
trajkit) give 0.089159 m. Screw axes for modern_robotics come from the chain's
joint frames at q = 0, not from trajkit's Jacobian.
"""

from __future__ import annotations

import numpy as np
import pytest

from trajkit.kinematics import UR5, DHRow, Planar2R, SerialChain

rtb = pytest.importorskip(
    "roboticstoolbox", reason="roboticstoolbox (test oracle) is not installed"
)
mr = pytest.importorskip("modern_robotics", reason="modern-robotics (test oracle) is not installed")

# Tolerances ------------------------------------------------------------------------
EXACT = 1e-12  # the same DH products evaluated by two codes (m, rad)
SCREWS = 1e-10  # product of exponentials against DH products: different rounding paths
COUNT = 200  # configurations per quick comparison
SWEEP = 5000  # configurations per slow sweep

UR5_TABLE = (  # a, alpha, d: the manufacturer's standard DH parameters
    (0.0, np.pi / 2, 0.089159),
    (-0.425, 0.0, 0.0),
    (-0.39225, 0.0, 0.0),
    (0.0, np.pi / 2, 0.10915),
    (0.0, -np.pi / 2, 0.09465),
    (0.0, 0.0, 0.0823),
)
MIXED_ROWS = (  # revolute and prismatic rows, with offsets
    DHRow(a=0.05, alpha=0.0, d=0.3, theta=0.1),
    DHRow(a=0.1, alpha=-np.pi / 2, d=0.05, theta=-0.4),
    DHRow(a=0.4, alpha=0.3, d=0.0, theta=0.3),
    DHRow(a=0.02, alpha=-np.pi / 2, d=0.35, theta=0.1, kind="prismatic"),
    DHRow(a=0.0, alpha=np.pi / 2, d=0.12, theta=0.0),
    DHRow(a=0.07, alpha=0.9, d=-0.1, theta=0.7, kind="prismatic"),
)


def pose(rotvec, translation) -> np.ndarray:
    from scipy.spatial.transform import Rotation

    out = np.eye(4)
    out[:3, :3] = Rotation.from_rotvec(rotvec).as_matrix()
    out[:3, 3] = translation
    return out


BASE = pose([0.2, -0.1, 0.4], [0.3, -0.2, 0.5])
TOOL = pose([0.0, 0.5, -0.2], [0.01, 0.02, 0.15])


def configurations(count: int, ndof: int, seed: int) -> np.ndarray:
    return np.random.default_rng(seed).uniform(-np.pi, np.pi, (count, ndof))


def rtb_ur5():
    return rtb.DHRobot([rtb.RevoluteDH(a=a, alpha=alpha, d=d) for a, alpha, d in UR5_TABLE])


def rtb_chain(rows, convention: str, base=None, tool=None):
    links = []
    for row in rows:
        if convention == "standard":
            revolute, prismatic = rtb.RevoluteDH, rtb.PrismaticDH
        else:
            revolute, prismatic = rtb.RevoluteMDH, rtb.PrismaticMDH
        if row.kind == "revolute":
            links.append(revolute(a=row.a, alpha=row.alpha, d=row.d, offset=row.theta))
        else:
            links.append(prismatic(a=row.a, alpha=row.alpha, theta=row.theta, offset=row.d))
    kwargs = {}
    if base is not None:
        kwargs["base"] = base
    if tool is not None:
        kwargs["tool"] = tool
    return rtb.DHRobot(links, **kwargs)


def mixed_configurations(count: int, seed: int) -> np.ndarray:
    q = configurations(count, len(MIXED_ROWS), seed)
    for j, row in enumerate(MIXED_ROWS):
        if row.kind == "prismatic":
            q[:, j] *= 0.1  # slider travel (m)
    return q


# ------------------------------------------------------------------------ Robotics Toolbox
def compare_ur5_with_rtb(count: int, seed: int) -> None:
    ours, theirs = UR5(), rtb_ur5()
    q = configurations(count, 6, seed)
    poses, jacobians = ours.fk_and_jacobian(q)
    for k in range(count):
        np.testing.assert_allclose(poses[k], theirs.fkine(q[k]).A, rtol=0, atol=EXACT)
        np.testing.assert_allclose(jacobians[k], theirs.jacob0(q[k]), rtol=0, atol=EXACT)


def test_ur5_fk_and_jacobian_match_robotics_toolbox():
    compare_ur5_with_rtb(COUNT, seed=101)


@pytest.mark.slow
def test_ur5_fk_and_jacobian_sweep_against_robotics_toolbox():
    compare_ur5_with_rtb(SWEEP, seed=102)


def test_ur5_jacobian_dot_and_manipulability_match_robotics_toolbox():
    ours, theirs = UR5(), rtb_ur5()
    rng = np.random.default_rng(103)
    q = rng.uniform(-np.pi, np.pi, (COUNT, 6))
    qd = rng.uniform(-2.0, 2.0, (COUNT, 6))
    dots = ours.jacobian_dot(q, qd)
    manipulability = {
        part: ours.manipulability(q, part=part) for part in ("all", "position", "orientation")
    }
    axes = {"all": "all", "position": "trans", "orientation": "rot"}
    for k in range(COUNT):
        np.testing.assert_allclose(dots[k], theirs.jacob0_dot(q[k], qd[k]), rtol=0, atol=EXACT)
        for part, values in manipulability.items():
            expected = theirs.manipulability(q[k], axes=axes[part])
            assert values[k] == pytest.approx(expected, rel=1e-9, abs=EXACT)


@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_mixed_dh_chain_matches_robotics_toolbox(convention):
    ours = SerialChain.from_dh(MIXED_ROWS, convention=convention, base=BASE, tool=TOOL)
    theirs = rtb_chain(MIXED_ROWS, convention, base=BASE, tool=TOOL)
    rng = np.random.default_rng(104)
    q = mixed_configurations(COUNT, seed=105)
    qd = rng.uniform(-1.0, 1.0, q.shape)
    poses, jacobians = ours.fk_and_jacobian(q)
    dots = ours.jacobian_dot(q, qd)
    for k in range(COUNT):
        np.testing.assert_allclose(poses[k], theirs.fkine(q[k]).A, rtol=0, atol=EXACT)
        np.testing.assert_allclose(jacobians[k], theirs.jacob0(q[k]), rtol=0, atol=EXACT)
        np.testing.assert_allclose(dots[k], theirs.jacob0_dot(q[k], qd[k]), rtol=0, atol=EXACT)


def test_planar2r_matches_a_two_row_dh_robot():
    ours = Planar2R(0.8, 0.45)
    theirs = rtb.DHRobot([rtb.RevoluteDH(a=0.8), rtb.RevoluteDH(a=0.45)])
    for q in configurations(COUNT, 2, seed=106):
        np.testing.assert_allclose(ours.fk(q), theirs.fkine(q).A, rtol=0, atol=EXACT)
        np.testing.assert_allclose(ours.jacobian(q), theirs.jacob0(q), rtol=0, atol=EXACT)


@pytest.mark.slow
@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_mixed_dh_sweep_against_robotics_toolbox(convention):
    ours = SerialChain.from_dh(MIXED_ROWS, convention=convention, base=BASE, tool=TOOL)
    theirs = rtb_chain(MIXED_ROWS, convention, base=BASE, tool=TOOL)
    q = mixed_configurations(SWEEP, seed=107)
    poses, jacobians = ours.fk_and_jacobian(q)
    for k in range(SWEEP):
        np.testing.assert_allclose(poses[k], theirs.fkine(q[k]).A, rtol=0, atol=EXACT)
        np.testing.assert_allclose(jacobians[k], theirs.jacob0(q[k]), rtol=0, atol=EXACT)


# ------------------------------------------------------------------------ modern_robotics
def screw_description(chain: SerialChain) -> tuple[np.ndarray, np.ndarray]:
    """Space-frame screw axes (6, ndof), [ω; v], and home pose M, from the joint frames at q = 0.

    A joint's axis at q = 0 is its frame's rotation applied to the joint's own axis
    (turning about an axis leaves it in place); its point is the frame's origin.
    """
    q0 = np.zeros(chain.ndof)
    frames = chain.frames(q0)[1:-1]
    screws = np.zeros((6, chain.ndof))
    for j, joint in enumerate(chain.joints):
        axis = frames[j, :3, :3] @ joint.axis
        point = frames[j, :3, 3]
        if joint.revolute:
            screws[:, j] = np.concatenate([axis, -np.cross(axis, point)])
        else:
            screws[:, j] = np.concatenate([np.zeros(3), axis])
    return screws, chain.fk(q0)


def compare_with_modern_robotics(chain: SerialChain, q: np.ndarray) -> None:
    screws, home = screw_description(chain)
    poses, jacobians = chain.fk_and_jacobian(q)
    for k in range(q.shape[0]):
        np.testing.assert_allclose(poses[k], mr.FKinSpace(home, screws, q[k]), atol=SCREWS)
        # mr's space Jacobian is [ω; v_s], v_s the velocity of the point at the space
        # origin: the tool point's velocity is v_tool = v_s + ω × p_tool.
        space = mr.JacobianSpace(screws, q[k])
        omega, linear = space[:3], space[3:]
        tool = poses[k, :3, 3]
        v_tool = linear + np.cross(omega.T, tool).T
        np.testing.assert_allclose(jacobians[k], np.vstack([v_tool, omega]), atol=SCREWS)
        # The body Jacobian, rotated into the world, gives the same twist.
        body = mr.JacobianBody(mr.Adjoint(mr.TransInv(home)) @ screws, q[k])
        rotation = poses[k, :3, :3]
        world = np.vstack([rotation @ body[3:], rotation @ body[:3]])
        np.testing.assert_allclose(jacobians[k], world, atol=SCREWS)


def test_ur5_matches_modern_robotics_product_of_exponentials():
    compare_with_modern_robotics(UR5(), configurations(COUNT, 6, seed=108))


def test_mixed_chain_matches_modern_robotics_product_of_exponentials():
    chain = SerialChain.from_dh(MIXED_ROWS, base=BASE, tool=TOOL)
    compare_with_modern_robotics(chain, mixed_configurations(COUNT, seed=109))
    modified = SerialChain.from_dh(MIXED_ROWS, convention="modified", base=BASE, tool=TOOL)
    compare_with_modern_robotics(modified, mixed_configurations(COUNT, seed=110))


def test_ur5_inverse_kinematics_agrees_with_modern_robotics():
    ours = UR5()
    screws, home = screw_description(ours)
    q = configurations(60, 6, seed=111)
    # Away from the elbow and wrist singularities both solvers stay on the seed's branch.
    q = q[(np.abs(np.sin(q[:, 2])) > 0.3) & (np.abs(np.sin(q[:, 4])) > 0.3)][:20]
    seeds = q + 0.03
    solution = ours.ik(ours.fk(q), q_seed=seeds)
    targets = ours.fk(q)
    for k in range(q.shape[0]):
        theirs, ok = mr.IKinSpace(screws, home, targets[k], seeds[k], 1e-12, 1e-12)
        assert ok
        np.testing.assert_allclose(solution.q[k], theirs, atol=1e-8)


@pytest.mark.slow
def test_ur5_sweep_against_modern_robotics():
    compare_with_modern_robotics(UR5(), configurations(SWEEP, 6, seed=112))
