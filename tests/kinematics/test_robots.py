"""Built-in robots: Planar2R, RRBot, Spatial3R (seed 003) and UR5 against closed forms.

Inverse kinematics of these arms is tested in test_ik.py; here: geometry, forward
kinematics, branch bookkeeping and constructor checks.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from trajkit.errors import InvalidInputError
from trajkit.kinematics import UR5, AnalyticChain, Planar2R, RRBot, SerialChain, Spatial3R

# Tolerances ------------------------------------------------------------------------
EXACT = 1e-12  # closed forms, relative to the arm's size
TABLE = 1e-15  # printed constants (DH table, data sheet) compared as given

# Strategies ------------------------------------------------------------------------
angles = st.floats(-2 * np.pi, 2 * np.pi, allow_nan=False)
# Lengths over four orders of magnitude: the course uses cm, URDFs use m.
lengths = st.one_of(st.floats(0.01, 1.0), st.floats(1.0, 100.0))


def rz(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def ry(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def seed_formula(q, l0, l1, l2, l3) -> np.ndarray:
    """The course's (seed 003) closed form of the 3-DOF arm's tool position."""
    q1, q2, q3 = q[..., 0], q[..., 1], q[..., 2]
    reach = l2 * np.cos(q2) + l3 * np.cos(q2 + q3)
    return np.stack(
        [
            np.cos(q1) * reach - l1 * np.sin(q1),
            l2 * np.sin(q2) + l3 * np.sin(q2 + q3),
            np.sin(q1) * reach + l1 * np.cos(q1) + l0,
        ],
        axis=-1,
    )


# ------------------------------------------------------------------------ Spatial3R
@given(
    q=st.tuples(angles, angles, angles),
    l0=lengths,
    l1=lengths,
    l2=lengths,
    l3=lengths,
)
def test_spatial3r_matches_the_seed_formula(q, l0, l1, l2, l3):
    arm = Spatial3R(l0, l1, l2, l3)
    scale = l0 + l1 + l2 + l3
    np.testing.assert_allclose(
        arm.fk(q)[:3, 3], seed_formula(np.array(q), l0, l1, l2, l3), rtol=0, atol=EXACT * scale
    )


def test_spatial3r_batches_and_course_defaults():
    arm = Spatial3R()
    assert (arm.l0, arm.l1, arm.l2, arm.l3) == (5.0, 10.0, 8.0, 12.0)
    np.testing.assert_allclose(arm.fk([0.0, 0.0, 0.0])[:3, 3], [20.0, 0.0, 15.0], atol=EXACT)
    q = np.random.default_rng(2).uniform(-np.pi, np.pi, (50, 3))
    np.testing.assert_allclose(arm.fk(q)[:, :3, 3], seed_formula(q, 5, 10, 8, 12), atol=EXACT * 35)
    # Joint 1 turns about world -y through (0, 0, l0); the frames say so.
    frames = arm.frames(np.zeros(3))
    np.testing.assert_allclose(frames[1, :3, 3], [0.0, 0.0, 5.0], atol=EXACT)
    np.testing.assert_allclose(arm.jacobian(np.zeros(3))[3:, 0], [0.0, -1.0, 0.0], atol=EXACT)
    assert arm.ndof == 3 and arm.name == "3-DOF spatial arm" and np.all(arm.revolute)


def test_spatial3r_joint_axes_by_hand():
    arm = Spatial3R(1.0, 2.0, 3.0, 4.0)
    q = np.array([0.4, -0.7, 1.1])
    # Joints 2 and 3 are parallel, perpendicular to joint 1 at q1 = 0.
    jacobian = arm.jacobian(q)
    axis2 = jacobian[3:, 1]
    np.testing.assert_allclose(axis2, jacobian[3:, 2], atol=EXACT)
    assert abs(axis2 @ jacobian[3:, 0]) < EXACT
    # Joint 1 turns the tool about the -y axis through (0, 0, l0).
    tool = arm.fk(q)[:3, 3]
    np.testing.assert_allclose(
        jacobian[:3, 0], np.cross([0.0, -1.0, 0.0], tool - [0.0, 0.0, 1.0]), atol=EXACT * 10
    )


# ------------------------------------------------------------------------ Planar2R
@given(q1=angles, q2=angles, l1=lengths, l2=lengths)
def test_planar2r_closed_form(q1, q2, l1, l2):
    pose = Planar2R(l1, l2).fk([q1, q2])
    expected = [
        l1 * np.cos(q1) + l2 * np.cos(q1 + q2),
        l1 * np.sin(q1) + l2 * np.sin(q1 + q2),
        0.0,
    ]
    np.testing.assert_allclose(pose[:3, 3], expected, rtol=0, atol=EXACT * (l1 + l2))
    np.testing.assert_allclose(pose[:3, :3], rz(q1 + q2), rtol=0, atol=EXACT)
    np.testing.assert_array_equal(pose[3], [0.0, 0.0, 0.0, 1.0])


@given(
    q1=angles,
    q2=angles,
    offsets=st.tuples(*[st.floats(-1.0, 1.0)] * 3),
    rotvec=st.tuples(*[st.floats(-2.0, 2.0)] * 3),
    shift=st.tuples(*[st.floats(-5.0, 5.0)] * 3),
)
def test_planar2r_base_and_axis_offsets(q1, q2, offsets, rotvec, shift):
    base = np.eye(4)
    base[:3, :3] = Rotation.from_rotvec(rotvec).as_matrix()
    base[:3, 3] = shift
    l1, l2 = 1.2, 0.7
    arm = Planar2R(l1, l2, base=base, axis_offsets=offsets)
    local = np.eye(4)
    local[:3, :3] = rz(q1 + q2)
    local[:3, 3] = [
        l1 * np.cos(q1) + l2 * np.cos(q1 + q2),
        l1 * np.sin(q1) + l2 * np.sin(q1 + q2),
        sum(offsets),
    ]
    np.testing.assert_allclose(arm.fk([q1, q2]), base @ local, atol=EXACT * 10)
    # Joints sit at the base origin lifted by a0, and at link 1's end lifted by a0 + a1.
    points = arm.points([q1, q2])
    a0, a1, _ = offsets
    joint2 = [l1 * np.cos(q1), l1 * np.sin(q1), a0 + a1]
    np.testing.assert_allclose(points[1], base[:3, :3] @ [0.0, 0.0, a0] + shift, atol=EXACT * 10)
    np.testing.assert_allclose(points[2], base[:3, :3] @ joint2 + shift, atol=EXACT * 10)


def test_planar2r_description():
    arm = Planar2R(1.0, 0.5, name="arm")
    assert (arm.l1, arm.l2, arm.name, arm.ndof) == (1.0, 0.5, "arm", 2)
    assert isinstance(arm, AnalyticChain) and isinstance(arm, SerialChain)
    assert arm.branch_names == ("elbow_positive", "elbow_negative")
    assert arm.names == ["q1", "q2"]
    assert np.all(np.isinf(arm.upper)) and np.all(np.isinf(arm.lower))
    assert repr(arm) == "Planar2R(name='arm', joints=RR)"


# ------------------------------------------------------------------------ RRBot
def test_rrbot_geometry():
    bot = RRBot()
    assert bot.name == "RRBot" and (bot.l1, bot.l2) == (0.9, 0.95)
    np.testing.assert_allclose(
        bot.fk([0.0, 0.0])[:3, 3], [0.0, 0.2, 1.95 + 0.9 + 0.95], rtol=0, atol=EXACT
    )
    np.testing.assert_allclose(
        bot.points([0.0, 0.0]),
        [[0.0, 0.0, 1.95], [0.0, 0.1, 1.95], [0.0, 0.2, 2.85], [0.0, 0.2, 3.8]],
        rtol=0,
        atol=EXACT,
    )
    # Positive q1 tips the arm toward +x; a quarter turn lays it flat along +x.
    assert bot.fk([0.1, 0.0])[0, 3] > 0 and bot.fk([-0.1, 0.0])[0, 3] < 0
    np.testing.assert_allclose(bot.fk([np.pi / 2, 0.0])[:3, 3], [1.85, 0.2, 1.95], atol=EXACT)
    assert bot.fk([0.0, 0.2])[0, 3] > 0  # so does positive q2
    # Continuous joints, no limits of any kind.
    assert np.all(np.isinf(bot.lower)) and np.all(np.isinf(bot.upper))
    assert np.all(np.isinf(bot.velocity_limits)) and bot.limits().velocity is None


@given(q1=angles, q2=angles)
def test_rrbot_closed_form(q1, q2):
    bot = RRBot()
    pose = bot.fk([q1, q2])
    expected = [
        0.9 * np.sin(q1) + 0.95 * np.sin(q1 + q2),
        0.2,
        1.95 + 0.9 * np.cos(q1) + 0.95 * np.cos(q1 + q2),
    ]
    np.testing.assert_allclose(pose[:3, 3], expected, rtol=0, atol=EXACT * 4)
    # Both joints turn about +y: the arm's orientation is Ry(q1 + q2) from its home.
    home = bot.fk([0.0, 0.0])[:3, :3]
    np.testing.assert_allclose(pose[:3, :3], ry(q1 + q2) @ home, atol=EXACT)
    angular = bot.jacobian([q1, q2])[3:]
    np.testing.assert_allclose(angular, [[0.0, 0.0], [1.0, 1.0], [0.0, 0.0]], atol=EXACT)


# ------------------------------------------------------------------------ UR5
def test_ur5_table_and_data_sheet():
    ur5 = UR5()
    assert ur5.name == "UR5" and ur5.ndof == 6 and np.all(ur5.revolute)
    assert ur5.names == ["shoulder_pan", "shoulder_lift", "elbow", "wrist_1", "wrist_2", "wrist_3"]
    np.testing.assert_array_equal(ur5.lower, -2 * np.pi)
    np.testing.assert_array_equal(ur5.upper, 2 * np.pi)
    np.testing.assert_array_equal(ur5.velocity_limits, np.pi)
    limits = ur5.limits()
    np.testing.assert_array_equal(limits.position.upper, 2 * np.pi)
    np.testing.assert_array_equal(limits.velocity.upper, np.pi)
    assert repr(ur5) == "SerialChain(name='UR5', joints=RRRRRR)"


def test_ur5_home_pose():
    # Standard DH at q = 0: x = a2 + a3, y = -(d4 + d6), z = d1 - d5, tool z along -y.
    d1, a2, a3, d4, d5, d6 = 0.089159, -0.425, -0.39225, 0.10915, 0.09465, 0.0823
    expected = np.array(
        [
            [1.0, 0.0, 0.0, a2 + a3],
            [0.0, 0.0, -1.0, -(d4 + d6)],
            [0.0, 1.0, 0.0, d1 - d5],
            [0.0, 0.0, 0.0, 1.0],
        ]
    )
    np.testing.assert_allclose(UR5().fk(np.zeros(6)), expected, rtol=0, atol=EXACT)


@given(q=st.tuples(*[angles] * 6))
def test_ur5_pan_turns_the_whole_arm_about_z(q):
    ur5 = UR5()
    q = np.array(q)
    turned = q.copy()
    turned[0] += 0.7
    rotation = np.eye(4)
    rotation[:3, :3] = rz(0.7)
    np.testing.assert_allclose(ur5.fk(turned), rotation @ ur5.fk(q), atol=EXACT)
    # The last joint spins the flange about its own z: position unchanged.
    spun = q.copy()
    spun[5] += 1.3
    np.testing.assert_allclose(ur5.fk(spun)[:3, 3], ur5.fk(q)[:3, 3], atol=EXACT)
    np.testing.assert_allclose(ur5.fk(spun)[:3, :3], ur5.fk(q)[:3, :3] @ rz(1.3), atol=EXACT)


# ------------------------------------------------------------------------ branches
@pytest.mark.parametrize(
    ("arm", "names"),
    [
        (Planar2R(1.0, 0.5), ("elbow_positive", "elbow_negative")),
        (RRBot(), ("elbow_positive", "elbow_negative")),
        (
            Spatial3R(),
            (
                "forward_elbow_positive",
                "forward_elbow_negative",
                "backward_elbow_positive",
                "backward_elbow_negative",
            ),
        ),
    ],
)
def test_branch_index_by_name_and_number(arm, names):
    assert arm.branch_names == names
    for index, name in enumerate(names):
        assert arm.branch_index(name) == index
        assert arm.branch_index(index) == index
        assert arm.branch_index(np.int64(index)) == index
    for bad in ("up", -1, len(names), 0.5, None):
        with pytest.raises(InvalidInputError, match="branch must be") as excinfo:
            arm.branch_index(bad)
        assert type(excinfo.value) is InvalidInputError


def test_wrap_near_shifts_only_unbounded_revolute_joints():
    arm = Planar2R(1.0, 0.5)
    solutions = np.array([[0.1, -0.2]])
    seeds = np.array([[0.1 + 4 * np.pi + 0.3, -0.2 - 2 * np.pi]])
    np.testing.assert_allclose(
        arm.wrap_near(solutions, seeds), [[0.1 + 4 * np.pi, -0.2 - 2 * np.pi]], atol=EXACT * 10
    )
    # Within half a turn nothing moves.
    np.testing.assert_array_equal(arm.wrap_near(solutions, solutions + 3.0), solutions)


# ------------------------------------------------------------------------ constructors
@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: Planar2R(0, 1), "l1 must be > 0, got 0 m"),
        (lambda: Planar2R(1, -2), "l2 must be > 0, got -2 m"),
        (lambda: Planar2R(np.nan, 1), "l1 must be finite"),
        (lambda: Planar2R([1, 2], 1), "l1 must be a single number"),
        (lambda: Planar2R(1, 1, base=np.diag([1.0, 1, 2, 1])), "base must be a rigid transform"),
        (lambda: Planar2R(1, 1, axis_offsets=(0.0, np.nan, 0.0)), "finite"),
        (lambda: Spatial3R(0, 10, 8, 12), "l0 must be > 0"),
        (lambda: Spatial3R(5, 10, 8, np.inf), "l3 must be finite"),
    ],
)
def test_constructor_checks(call, message):
    with pytest.raises(InvalidInputError, match=message) as excinfo:
        call()
    assert type(excinfo.value) is InvalidInputError


# ------------------------------------------------------------------ physical data
def test_the_built_in_arms_carry_their_physical_data():
    from trajkit.kinematics import UR5, Physical, RRBot

    rrbot = RRBot().physical
    assert (rrbot.link_mass, rrbot.link_radius, rrbot.damping) == (1.0, 0.05, 0.7)
    ur5 = UR5().physical
    assert ur5.link_mass == [3.7, 8.393, 2.33, 1.219, 1.219, 0.1879]
    assert isinstance(ur5, Physical) and "UR5" in ur5.source


def test_with_physical_copies_the_chain_and_keeps_its_kinematics():
    from trajkit.kinematics import UR5, Physical

    arm = UR5()
    bare = UR5().with_physical(Physical(link_mass=2.0))
    assert bare.physical.link_mass == 2.0 and arm.physical.link_mass != 2.0
    q = np.linspace(-1.0, 1.0, 6)
    np.testing.assert_array_equal(bare.fk(q), arm.fk(q))
    with pytest.raises(InvalidInputError, match="^physical must be a trajkit.kinematics"
                       r"\.Physical, got dict$"):  # fmt: skip
        arm.with_physical({"link_mass": 1.0})
