"""Serial chains: FK against closed forms, Jacobians against finite differences, IK round trips."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

from trajkit.errors import InvalidInputError, UnreachableError
from trajkit.kinematics import UR5, DHRow, Joint, Planar2R, RRBot, SerialChain, Spatial3R
from trajkit.rotations import axis_rotation, rotation_error

EXACT = 1e-12  # closed forms, relative to the arm's size
FD_STEP = 1e-6  # central differences
FD_TOL = 1e-6  # their truncation and rounding error at that step
ROUND_TRIP = 1e-9  # FK(IK(x)) = x

angles = st.floats(-np.pi, np.pi, allow_nan=False)
lengths = st.floats(0.2, 3.0, allow_nan=False)


def random_dh_chain() -> SerialChain:
    rows = [
        DHRow(a=0.3, alpha=0.4, d=0.1, theta=0.2),
        DHRow(kind="prismatic", a=0.2, alpha=-1.0, theta=0.3, d=0.05),
        DHRow(a=0.1, alpha=0.7, d=0.2),
    ]
    return SerialChain.from_dh(rows, base=_pose([0.1, 0.2, 0.3], [0.3, -0.2, 0.5]))


def _pose(translation, rotvec) -> np.ndarray:
    out = np.eye(4)
    rotvec = np.asarray(rotvec, dtype=float)
    angle = np.linalg.norm(rotvec)
    out[:3, :3] = axis_rotation(rotvec / angle, angle) if angle else np.eye(3)
    out[:3, 3] = translation
    return out


ROBOTS = {
    "planar": Planar2R(1.0, 0.5),
    "rrbot": RRBot(),
    "spatial3r": Spatial3R(),
    "ur5": UR5(),
    "dh_rpr": random_dh_chain(),
}


def rot_z(angle):
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])


# ------------------------------------------------------------------------ FK


@given(q1=angles, q2=angles, q3=angles, l0=lengths, l1=lengths, l2=lengths, l3=lengths)
def test_spatial3r_matches_the_seed_formula(q1, q2, q3, l0, l1, l2, l3):
    arm = Spatial3R(l0, l1, l2, l3)
    c1, s1, c2, s2 = np.cos(q1), np.sin(q1), np.cos(q2), np.sin(q2)
    c3, s3 = np.cos(q3), np.sin(q3)
    expected = [
        l3 * c1 * c2 * c3 - l3 * c1 * s2 * s3 + l2 * c1 * c2 - l1 * s1,
        l3 * s2 * c3 + l3 * c2 * s3 + l2 * s2,
        l3 * s1 * c2 * c3 - l3 * s1 * s2 * s3 + l2 * s1 * c2 + l1 * c1 + l0,
    ]
    scale = l0 + l1 + l2 + l3
    np.testing.assert_allclose(arm.fk([q1, q2, q3])[:3, 3], expected, atol=EXACT * scale)


@given(q1=angles, q2=angles, l1=lengths, l2=lengths)
def test_planar_2r_closed_form(q1, q2, l1, l2):
    pose = Planar2R(l1, l2).fk([q1, q2])
    expected = [l1 * np.cos(q1) + l2 * np.cos(q1 + q2), l1 * np.sin(q1) + l2 * np.sin(q1 + q2), 0]
    np.testing.assert_allclose(pose[:3, 3], expected, atol=EXACT * (l1 + l2))
    np.testing.assert_allclose(pose[:3, :3], rot_z(q1 + q2), atol=EXACT)


def test_rrbot_geometry():
    bot = RRBot()
    np.testing.assert_allclose(bot.fk([0.0, 0.0])[:3, 3], [0.0, 0.2, 3.8], atol=EXACT)
    tipped = bot.fk([0.1, 0.0])[:3, 3]
    assert tipped[0] > 0  # positive angles tip the arm toward +x
    np.testing.assert_allclose(
        bot.points([0.0, 0.0]), [[0, 0, 1.95], [0, 0.1, 1.95], [0, 0.2, 2.85], [0, 0.2, 3.8]],
        atol=EXACT,
    )  # fmt: skip
    assert bot.ndof == 2 and np.all(np.isinf(bot.upper))


@pytest.mark.parametrize("name", list(ROBOTS))
def test_batch_and_single_agree_and_frames_end_at_the_tool(name):
    robot = ROBOTS[name]
    q = np.random.default_rng(3).uniform(-2, 2, (7, robot.ndof))
    batch = robot.fk(q)
    assert batch.shape == (7, 4, 4)
    for k in range(7):
        np.testing.assert_array_equal(robot.fk(q[k]), batch[k])
    frames = robot.frames(q)
    assert frames.shape == (7, robot.ndof + 2, 4, 4)
    np.testing.assert_array_equal(frames[:, -1], batch)
    np.testing.assert_array_equal(frames[:, 0], np.broadcast_to(robot.base, (7, 4, 4)))
    assert robot.points(q).shape == (7, robot.ndof + 2, 3)


def dh_reference(rows, q, convention):
    out = np.eye(4)
    for row, value in zip(rows, q, strict=True):
        theta = row.theta + (value if row.kind == "revolute" else 0.0)
        d = row.d + (value if row.kind == "prismatic" else 0.0)
        rz = np.eye(4)
        rz[:3, :3] = rot_z(theta)
        tz, tx, rx = np.eye(4), np.eye(4), np.eye(4)
        tz[2, 3], tx[0, 3] = d, row.a
        rx[:3, :3] = axis_rotation(np.array([1.0, 0, 0]), row.alpha)
        out = out @ (rz @ tz @ tx @ rx if convention == "standard" else rx @ tx @ rz @ tz)
    return out


@pytest.mark.parametrize("convention", ["standard", "modified"])
@given(q=st.lists(angles, min_size=3, max_size=3))
def test_dh_tables_against_the_row_product(convention, q):
    rows = [
        DHRow(a=0.3, alpha=0.4, d=0.1, theta=0.2),
        DHRow(kind="prismatic", a=0.2, alpha=-1.0, theta=0.3, d=0.05),
        DHRow(a=0.1, alpha=0.7, d=0.2, theta=-0.4),
    ]
    chain = SerialChain.from_dh(rows, convention=convention)
    np.testing.assert_allclose(chain.fk(q), dh_reference(rows, q, convention), atol=EXACT)


def test_base_and_tool_transforms():
    base, tool = _pose([1, 2, 3], [0, 0, 0.5]), _pose([0, 0, 0.1], [0.2, 0, 0])
    plain = Planar2R(1.0, 0.5)
    moved = Planar2R(1.0, 0.5, base=base)
    q = [0.3, -0.7]
    np.testing.assert_allclose(moved.fk(q), base @ plain.fk(q), atol=EXACT)
    chain = SerialChain(plain.joints, tool=plain.tool @ tool)
    np.testing.assert_allclose(chain.fk(q), plain.fk(q) @ tool, atol=EXACT)


# -------------------------------------------------------------- Jacobians


def finite_difference_jacobian(robot, q):
    out = np.zeros((q.shape[0], 6, robot.ndof))
    for j in range(robot.ndof):
        step = np.zeros(robot.ndof)
        step[j] = FD_STEP
        plus, minus = robot.fk(q + step), robot.fk(q - step)
        out[:, :3, j] = (plus[:, :3, 3] - minus[:, :3, 3]) / (2 * FD_STEP)
        out[:, 3:, j] = rotation_error(plus[:, :3, :3], minus[:, :3, :3]) / (2 * FD_STEP)
    return out


@pytest.mark.parametrize("name", list(ROBOTS))
def test_jacobian_and_its_derivative_against_finite_differences(name):
    robot = ROBOTS[name]
    rng = np.random.default_rng(7)
    q = rng.uniform(-2, 2, (40, robot.ndof))
    qd = rng.uniform(-1, 1, (40, robot.ndof))
    scale = 1.0 + min(robot.reach(), 2.0)  # the RPR chain's slider is unbounded
    jacobian = robot.jacobian(q)
    np.testing.assert_allclose(jacobian, finite_difference_jacobian(robot, q), atol=FD_TOL * scale)
    numeric = (robot.jacobian(q + FD_STEP * qd) - robot.jacobian(q - FD_STEP * qd)) / (2 * FD_STEP)
    np.testing.assert_allclose(robot.jacobian_dot(q, qd), numeric, atol=FD_TOL * scale)
    pose, both = robot.fk_and_jacobian(q)
    np.testing.assert_array_equal(both, jacobian)
    np.testing.assert_array_equal(pose, robot.fk(q))


@given(q2=angles, l1=lengths, l2=lengths)
def test_planar_manipulability(q2, l1, l2):
    arm = Planar2R(l1, l2)
    value = arm.manipulability([0.4, q2], part="position")
    assert value == pytest.approx(l1 * l2 * abs(np.sin(q2)), abs=EXACT * (l1 + l2) ** 2)


def test_manipulability_vanishes_at_singularities():
    ur5 = UR5()
    assert ur5.manipulability([0.3, -1.0, 1.2, 0.4, 0.0, 0.2]) < 1e-12  # wrist: q5 = 0
    assert ur5.manipulability([0.3, -1.0, 1.2, 0.4, 1.0, 0.2]) > 1e-4
    assert Planar2R(1, 1).manipulability(np.array([[0.2, 0.0], [0.2, 1.0]]), part="position")[
        0
    ] == pytest.approx(0.0, abs=EXACT)


# ------------------------------------------------------------------------ IK


@given(q1=angles, q2=st.floats(0.05, np.pi - 0.05), l1=lengths, l2=lengths)
def test_planar_ik_both_branches_round_trip(q1, q2, l1, l2):
    arm = Planar2R(l1, l2)
    target = arm.fk([q1, q2])[:3, 3]
    for branch, sign in (("elbow_positive", 1), ("elbow_negative", -1)):
        solution = arm.ik(target, branch=branch)
        assert solution.success and solution.method == "analytic"
        assert sign * solution.q[1] >= 0
        np.testing.assert_allclose(arm.fk(solution.q)[:3, 3], target, atol=ROUND_TRIP)
    np.testing.assert_allclose(arm.ik(target[:2], branch=0).q[1], q2, atol=1e-7)


@given(q=st.lists(st.floats(-3.0, 3.0), min_size=3, max_size=3))
def test_spatial3r_every_branch_round_trips(q):
    arm = Spatial3R()
    assume(arm.manipulability(q, part="position") > 1.0)
    target = arm.fk(q)[:3, 3]
    branches = arm.ik_branches(target)
    assert branches.shape == (4, 3)
    np.testing.assert_allclose(arm.fk(branches)[:, :3, 3], np.tile(target, (4, 1)), atol=1e-9 * 35)
    nearest = arm.ik(target, q_seed=q)
    np.testing.assert_allclose(nearest.q, q, atol=1e-7)


def test_rrbot_ik_round_trip():
    bot = RRBot()
    q = np.array([0.7, -1.1])
    solution = bot.ik(bot.fk(q), q_seed=[0.5, -1.0])
    np.testing.assert_allclose(solution.q, q, atol=1e-9)


def test_ur5_full_pose_round_trip_warm_and_cold():
    ur5 = UR5()
    rng = np.random.default_rng(11)
    q = rng.uniform(-2.5, 2.5, (200, 6))
    q = q[ur5.manipulability(q) > 1e-3]
    targets = ur5.fk(q)
    warm = ur5.ik(targets, q_seed=q + rng.normal(0, 0.2, q.shape))
    cold = ur5.ik(targets[:40])
    for solution, goal in ((warm, targets), (cold, targets[:40])):
        assert np.all(solution.success)
        np.testing.assert_allclose(ur5.fk(solution.q), goal, atol=ROUND_TRIP)
        assert np.all(solution.position_error < ROUND_TRIP)


def test_ur5_position_only():
    ur5 = UR5()
    target = ur5.fk([0.3, -1.2, 1.5, -1.9, -1.57, 0.2])[:3, 3]
    solution = ur5.ik(target, position_only=True)
    assert solution.success and solution.orientation_error == 0.0
    np.testing.assert_allclose(ur5.fk(solution.q)[:3, 3], target, atol=ROUND_TRIP)


def test_numerical_ik_respects_joint_ranges():
    rows = [DHRow(a=1.0, lower=-0.5, upper=0.5), DHRow(a=1.0, lower=0.0, upper=1.0)]
    chain = SerialChain.from_dh(rows)
    target = chain.fk([0.2, 0.6])[:3, 3]
    solution = chain.ik(target, position_only=True, q_seed=[0.0, 0.5])
    assert chain.lower[1] <= solution.q[1] <= chain.upper[1]
    np.testing.assert_allclose(solution.q, [0.2, 0.6], atol=1e-8)
    # Both solutions of this target, (0, -0.9) and (-0.9, 0.9), leave a joint's range.
    mirrored = chain.fk([0.0, -0.9])[:3, 3]
    with pytest.raises(UnreachableError, match="joint ranges"):
        chain.ik(mirrored, position_only=True)


def test_ik_path_follows_one_branch():
    ur5 = UR5()
    start = np.array([0.3, -1.2, 1.5, -1.9, -1.57, 0.2])
    poses = np.repeat(ur5.fk(start)[np.newaxis], 500, axis=0)
    poses[:, :3, 3] += np.linspace(0, 1, 500)[:, np.newaxis] * [0.1, 0.15, -0.1]
    solution = ur5.ik_path(poses, start)
    assert np.all(solution.success)
    np.testing.assert_allclose(solution.q[0], start, atol=1e-8)
    assert np.abs(np.diff(solution.q, axis=0)).max() < 0.01  # no branch jumps
    np.testing.assert_allclose(ur5.fk(solution.q), poses, atol=ROUND_TRIP)


def test_singular_targets_are_solved():
    arm = Planar2R(1.0, 0.5)
    stretched = arm.ik([1.5, 0.0, 0.0])  # on the outer boundary: both branches meet
    np.testing.assert_allclose(stretched.q, [0.0, 0.0], atol=1e-7)
    equal = Planar2R(1.0, 1.0)
    origin = equal.ik([0.0, 0.0, 0.0])  # any q1 works; q2 = ±π
    np.testing.assert_allclose(equal.fk(origin.q)[:3, 3], 0.0, atol=ROUND_TRIP)


@pytest.mark.parametrize(
    ("robot", "target", "message"),
    [
        (Planar2R(1.0, 0.5), [2.0, 0.0, 0.0], r"0\.5 m beyond the annulus"),
        (Planar2R(1.0, 0.5), [0.2, 0.0, 0.0], r"0\.3 m beyond the annulus"),
        (Planar2R(1.0, 0.5), [1.0, 0.0, 0.4], "out of reach"),
        (Spatial3R(), [0.0, 0.0, 5.0], "at least 10 from joint 1's axis"),
        (Spatial3R(), [0.0, 40.0, 5.0], "out of reach"),
    ],
)
def test_unreachable_targets_say_how_far(robot, target, message):
    with pytest.raises(UnreachableError, match=message):
        robot.ik(target)
    solution = robot.ik(target, raise_on_failure=False)
    assert not solution.success and np.all(np.isnan(solution.q))


def test_numerical_unreachable():
    ur5 = UR5()
    far = np.eye(4)
    far[:3, 3] = [5.0, 0.0, 0.0]
    with pytest.raises(UnreachableError, match="closest tool pose found is") as excinfo:
        ur5.ik(far, restarts=2)
    assert excinfo.value.index == 0
    result = ur5.ik(np.stack([ur5.fk(np.zeros(6)), far]), restarts=2, raise_on_failure=False)
    assert result.success.tolist() == [True, False]
    assert result.position_error[1] > 4.0


# ------------------------------------------------------------- bad input


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: UR5().fk([0.0] * 5), r"q must have shape \(6,\) or \(m, 6\)"),
        (lambda: UR5().fk([np.nan] * 6), "q must be finite"),
        (lambda: UR5().ik(np.zeros(5)), "target must be a 4x4 pose"),
        (lambda: UR5().ik([0.1, 0.2, 0.3]), "pass position_only=True"),
        (lambda: UR5().ik(np.diag([2.0, 1, 1, 1])), "not a rotation matrix"),
        (lambda: UR5().ik([np.inf, 0, 0], position_only=True), "target must be finite"),
        (lambda: UR5().ik(np.eye(4), tolerance=-1), "tolerance must be > 0"),
        (lambda: Planar2R(1, 1).ik([1, 0, 0], branch="up"), "branch must be one of"),
        (lambda: Planar2R(1, 1).ik([1, 0, 0], branch=2), "branch must be an index 0..1"),
        (lambda: Planar2R(1, 1).ik(np.eye(4), position_only=False), "position_only=True"),
        (lambda: Planar2R(0, 1), "l1 must be > 0"),
        (lambda: Joint("j", "revolute", axis=[0, 0, 0]), "axis must be a non-zero 3-vector"),
        (lambda: Joint("j", "revolute", lower=1, upper=0), "lower limit 1 must be below"),
        (lambda: Joint("j", "revolute", velocity=-1), "velocity limit must be > 0"),
        (lambda: Joint("j", "spherical"), "kind must be 'revolute' or 'prismatic'"),
        (lambda: Joint("j", "revolute", origin=np.eye(3)), "origin must be a 4x4"),
        (lambda: SerialChain([]), "at least one joint"),
        (lambda: SerialChain([Joint("a", "revolute")] * 2), "joint names must be unique"),
        (lambda: SerialChain.from_dh([]), "non-empty sequence of DHRow"),
        (lambda: SerialChain.from_dh([DHRow()], convention="craig"), "convention must be"),
        (lambda: SerialChain.from_dh([DHRow(a=np.nan)]), "DH row 1 must be finite"),
        (lambda: SerialChain([Joint("a", "revolute")], base=np.ones((4, 4))), "rigid transform"),
        (lambda: UR5().manipulability(np.zeros(6), part="twist"), "part must be"),
        (lambda: UR5().jacobian_dot(np.zeros(6), np.zeros((2, 6))), "qd has shape"),
        (lambda: UR5().ik_path(np.eye(4)), "sequence of poses"),
    ],
)
def test_bad_input(call, message):
    with pytest.raises(InvalidInputError, match=message) as excinfo:
        call()
    assert type(excinfo.value) is InvalidInputError


def test_limits_and_reach():
    ur5 = UR5()
    limits = ur5.limits()
    np.testing.assert_allclose(limits.position.upper, 2 * np.pi)
    np.testing.assert_allclose(limits.velocity.upper, np.pi)
    assert RRBot().limits().velocity is None  # continuous joints without speed limits
    assert Planar2R(1.0, 0.5).reach() == pytest.approx(1.5)
    assert repr(ur5) == "SerialChain(name='UR5', joints=RRRRRR)"
    assert ur5.names[0] == "shoulder_pan"
