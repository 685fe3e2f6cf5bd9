"""Arm kinematics against the peers: Robotics Toolbox (DH) and modern_robotics (screws).

The peers are test oracles only. Robotics Toolbox's own ``models.DH.UR5`` uses
d1 = 0.089459 m where the manufacturer (and trajkit) give 0.089159 m, so the
oracle robot is built from trajkit's table.
"""

from __future__ import annotations

import numpy as np
import pytest

from trajkit.kinematics import UR5, DHRow, SerialChain

rtb = pytest.importorskip("roboticstoolbox")
mr = pytest.importorskip("modern_robotics")

EXACT = 1e-12  # same closed form evaluated two ways
UR5_TABLE = (  # a, alpha, d
    (0.0, np.pi / 2, 0.089159),
    (-0.425, 0.0, 0.0),
    (-0.39225, 0.0, 0.0),
    (0.0, np.pi / 2, 0.10915),
    (0.0, -np.pi / 2, 0.09465),
    (0.0, 0.0, 0.0823),
)
MODIFIED_ROWS = (
    DHRow(a=0.0, alpha=0.0, d=0.3),
    DHRow(a=0.1, alpha=-np.pi / 2, d=0.05),
    DHRow(a=0.4, alpha=0.0, d=0.0, theta=0.3),
    DHRow(a=0.02, alpha=-np.pi / 2, d=0.35, kind="prismatic", theta=0.1),
)


def rtb_ur5():
    return rtb.DHRobot([rtb.RevoluteDH(a=a, alpha=alpha, d=d) for a, alpha, d in UR5_TABLE])


def configurations(count: int, ndof: int, seed: int = 5) -> np.ndarray:
    return np.random.default_rng(seed).uniform(-np.pi, np.pi, (count, ndof))


def compare_with_rtb(count: int) -> None:
    ours, theirs = UR5(), rtb_ur5()
    q = configurations(count, 6)
    poses, jacobians = ours.fk_and_jacobian(q)
    for k in range(count):
        np.testing.assert_allclose(poses[k], theirs.fkine(q[k]).A, atol=EXACT)
        np.testing.assert_allclose(jacobians[k], theirs.jacob0(q[k]), atol=EXACT)


def test_ur5_fk_and_jacobian_match_robotics_toolbox():
    compare_with_rtb(200)


@pytest.mark.slow
def test_ur5_fk_and_jacobian_sweep():
    compare_with_rtb(5000)


def test_modified_dh_matches_robotics_toolbox():
    ours = SerialChain.from_dh(MODIFIED_ROWS, convention="modified")
    links = []
    for row in MODIFIED_ROWS:
        if row.kind == "revolute":
            links.append(rtb.RevoluteMDH(a=row.a, alpha=row.alpha, d=row.d, offset=row.theta))
        else:
            links.append(rtb.PrismaticMDH(a=row.a, alpha=row.alpha, theta=row.theta, offset=row.d))
    theirs = rtb.DHRobot(links)
    q = configurations(100, 4)
    q[:, 3] = np.abs(q[:, 3]) * 0.1  # slider travel
    for k in range(q.shape[0]):
        np.testing.assert_allclose(ours.fk(q[k]), theirs.fkine(q[k]).A, atol=EXACT)
        np.testing.assert_allclose(ours.jacobian(q[k]), theirs.jacob0(q[k]), atol=EXACT)


def screw_description(chain: SerialChain) -> tuple[np.ndarray, np.ndarray]:
    """Space-frame screw axes and home pose of a revolute chain, from trajkit at q = 0."""
    home = chain.fk(np.zeros(chain.ndof))
    jacobian = chain.jacobian(np.zeros(chain.ndof))  # [v_tool; w] at the tool point
    frames = chain.frames(np.zeros(chain.ndof))[1:-1]
    screws = []
    for j in range(chain.ndof):
        w = jacobian[3:, j]
        point = frames[j, :3, 3]
        screws.append(np.concatenate([w, -np.cross(w, point)]))
    return np.array(screws).T, home


def test_ur5_matches_modern_robotics_product_of_exponentials():
    ours = UR5()
    screws, home = screw_description(ours)
    for q in configurations(100, 6, seed=9):
        np.testing.assert_allclose(ours.fk(q), mr.FKinSpace(home, screws, q), atol=1e-10)
        # mr's space Jacobian is [w; v] at the space origin; move v to the tool point.
        space = mr.JacobianSpace(screws, q)
        tool = ours.fk(q)[:3, 3]
        linear = space[3:] + np.cross(space[:3].T, tool).T
        np.testing.assert_allclose(ours.jacobian(q), np.vstack([linear, space[:3]]), atol=1e-10)
