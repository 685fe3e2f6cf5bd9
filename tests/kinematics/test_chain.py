"""SerialChain, Joint and DHRow: FK, frames, Jacobians, manipulability, limits, bad input.

Every reference here is written out independently of trajkit: chains are multiplied
joint by joint as 4x4 matrices (rotations from scipy's rotation vectors), DH rows
as the textbook products, and derivatives as central finite differences.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from trajkit.errors import InvalidInputError
from trajkit.kinematics import UR5, DHRow, Joint, Planar2R, RRBot, SerialChain, Spatial3R
from trajkit.limits import Limits
from trajkit.rotations import rotation_error

# Tolerances ------------------------------------------------------------------------
EXACT = 1e-12  # the same product evaluated two ways, relative to the chain's size
FD_STEP = 1e-6  # central-difference step (rad or m)
FD_TOL = 1e-6  # truncation + rounding of central differences at that step, relative
LINEAR = 1e-12  # J̇ is linear in q̇: rounding only, relative

# Strategies ------------------------------------------------------------------------
angles = st.floats(-np.pi, np.pi, allow_nan=False)
wide_angles = st.floats(-2 * np.pi, 2 * np.pi, allow_nan=False)
coordinates = st.floats(-1.0, 1.0, allow_nan=False)
vectors = st.tuples(coordinates, coordinates, coordinates)


def rigid(rotvec, translation) -> np.ndarray:
    out = np.eye(4)
    out[:3, :3] = Rotation.from_rotvec(np.asarray(rotvec, dtype=float)).as_matrix()
    out[:3, 3] = translation
    return out


rigid_transforms = st.builds(rigid, vectors, vectors)


@st.composite
def joint_lists(draw, min_joints: int = 1, max_joints: int = 7) -> list[Joint]:
    count = draw(st.integers(min_joints, max_joints))
    joints = []
    for i in range(count):
        kind = draw(st.sampled_from(["revolute", "revolute", "prismatic"]))
        axis = np.array(draw(vectors))
        assume(np.linalg.norm(axis) > 0.1)  # not unit on purpose: Joint normalises it
        joints.append(
            Joint(
                f"j{i}",
                kind,
                origin=draw(rigid_transforms),
                axis=axis,
                offset=draw(st.floats(-1.0, 1.0)),
            )
        )
    return joints


@st.composite
def chains(draw, min_joints: int = 1, max_joints: int = 7) -> SerialChain:
    joints = draw(joint_lists(min_joints, max_joints))
    return SerialChain(joints, base=draw(rigid_transforms), tool=draw(rigid_transforms))


@st.composite
def chains_and_configurations(draw, count: int | None = None):
    chain = draw(chains())
    m = draw(st.integers(1, 6)) if count is None else count
    q = np.array(
        [[draw(st.floats(-3.0, 3.0)) for _ in range(chain.ndof)] for _ in range(m)], dtype=float
    )
    return chain, q


def size_of(chain: SerialChain) -> float:
    """A length scale for absolute tolerances: every offset plus slider travel (<= 4 m)."""
    offsets = sum(np.linalg.norm(j.origin[:3, 3]) + abs(j.offset) for j in chain.joints)
    return 1.0 + offsets + np.linalg.norm(chain.base[:3, 3]) + np.linalg.norm(chain.tool[:3, 3])


# Independent references -----------------------------------------------------------
def joint_motion(joint: Joint, value: float) -> np.ndarray:
    unit = np.asarray(joint.axis) / np.linalg.norm(joint.axis)
    if joint.kind == "revolute":
        return rigid(unit * (value + joint.offset), [0.0, 0.0, 0.0])
    return rigid([0.0, 0.0, 0.0], unit * (value + joint.offset))


def reference_frames(chain: SerialChain, q) -> tuple[list[np.ndarray], np.ndarray]:
    """Joint frames as ``frames`` documents them (origin, turned by the joint) and the tool."""
    transform = chain.base
    frames = []
    for joint, value in zip(chain.joints, q, strict=True):
        at_joint = transform @ joint.origin
        moved = at_joint @ joint_motion(joint, value)
        frame = moved.copy()
        frame[:3, 3] = at_joint[:3, 3]  # at the joint's position (a slider's start)
        frames.append(frame)
        transform = moved
    return frames, transform @ chain.tool


def rz(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])


def rx(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]])


def tz(d: float) -> np.ndarray:
    out = np.eye(4)
    out[2, 3] = d
    return out


def tx(a: float) -> np.ndarray:
    out = np.eye(4)
    out[0, 3] = a
    return out


def dh_product(rows, q, convention: str) -> np.ndarray:
    out = np.eye(4)
    for row, value in zip(rows, q, strict=True):
        theta = row.theta + (value if row.kind == "revolute" else 0.0)
        d = row.d + (value if row.kind == "prismatic" else 0.0)
        if convention == "standard":
            out = out @ rz(theta) @ tz(d) @ tx(row.a) @ rx(row.alpha)
        else:
            out = out @ rx(row.alpha) @ tx(row.a) @ rz(theta) @ tz(d)
    return out


def finite_difference_jacobian(chain: SerialChain, q: np.ndarray) -> np.ndarray:
    """(6, ndof) from central differences of the tool pose, for one configuration."""
    out = np.zeros((6, chain.ndof))
    for j in range(chain.ndof):
        step = np.zeros(chain.ndof)
        step[j] = FD_STEP
        plus, minus = chain.fk(q + step), chain.fk(q - step)
        out[:3, j] = (plus[:3, 3] - minus[:3, 3]) / (2 * FD_STEP)
        out[3:, j] = rotation_error(plus[:3, :3], minus[:3, :3]) / (2 * FD_STEP)
    return out


DH_ROWS = [
    DHRow(a=0.3, alpha=0.4, d=0.1, theta=0.2),
    DHRow(kind="prismatic", a=0.2, alpha=-1.0, theta=0.3, d=0.05),
    DHRow(a=0.1, alpha=0.7, d=0.2, theta=-0.4),
]
BUILT_INS = {
    "planar2r": Planar2R(1.0, 0.5),
    "planar2r_offsets": Planar2R(
        0.7, 1.3, axis_offsets=(0.1, -0.2, 0.3), base=rigid([0.1, 0.2, 0.3], [1, 2, 3])
    ),
    "rrbot": RRBot(),
    "spatial3r": Spatial3R(),
    "ur5": UR5(),
    "dh_rpr": SerialChain.from_dh(DH_ROWS, base=rigid([0.3, -0.2, 0.5], [0.1, 0.2, 0.3])),
    "mdh_rpr": SerialChain.from_dh(
        DH_ROWS, convention="modified", tool=rigid([0, 0.4, 0], [0, 0, 0.1])
    ),
}


# ------------------------------------------------------------------------ Joint
def test_joint_normalises_its_axis_and_copies_its_origin():
    origin = rigid([0.1, 0.2, 0.3], [1.0, 2.0, 3.0])
    joint = Joint("j", "prismatic", origin=origin, axis=[0.0, 3.0, 4.0], offset=2)
    np.testing.assert_allclose(joint.axis, [0.0, 0.6, 0.8], rtol=EXACT)
    assert joint.offset == 2.0 and isinstance(joint.offset, float)
    origin[0, 3] = 99.0  # the joint keeps its own copy
    assert joint.origin[0, 3] == 1.0
    assert not joint.revolute and Joint("r", "revolute").revolute
    defaults = Joint("d", "revolute")
    np.testing.assert_array_equal(defaults.origin, np.eye(4))
    np.testing.assert_array_equal(defaults.axis, [0.0, 0.0, 1.0])
    assert (defaults.lower, defaults.upper, defaults.velocity) == (-np.inf, np.inf, np.inf)


# ------------------------------------------------------------------------ FK
@given(chain_and_q=chains_and_configurations(count=1))
def test_fk_frames_and_points_match_the_joint_by_joint_product(chain_and_q):
    chain, q = chain_and_q
    q = q[0]
    frames, tool = reference_frames(chain, q)
    atol = EXACT * size_of(chain)
    pose = chain.fk(q)
    assert pose.shape == (4, 4)
    np.testing.assert_allclose(pose, tool, atol=atol)
    got = chain.frames(q)
    assert got.shape == (chain.ndof + 2, 4, 4)
    np.testing.assert_array_equal(got[0], chain.base)
    np.testing.assert_allclose(got[1:-1], np.stack(frames), atol=atol)
    np.testing.assert_array_equal(got[-1], pose)
    points = chain.points(q)
    assert points.shape == (chain.ndof + 2, 3)
    np.testing.assert_array_equal(points, got[:, :3, 3])


@given(chain_and_q=chains_and_configurations())
def test_batches_equal_single_configurations(chain_and_q):
    chain, q = chain_and_q
    m, n = q.shape
    qd = np.cos(3 * q + 1)  # any rates
    pose, jacobian = chain.fk_and_jacobian(q)
    assert pose.shape == (m, 4, 4) and jacobian.shape == (m, 6, n)
    np.testing.assert_array_equal(chain.fk(q), pose)
    np.testing.assert_array_equal(chain.jacobian(q), jacobian)
    frames = chain.frames(q)
    assert frames.shape == (m, n + 2, 4, 4)
    assert chain.points(q).shape == (m, n + 2, 3)
    dots = chain.jacobian_dot(q, qd)
    assert dots.shape == (m, 6, n)
    manip = chain.manipulability(q)
    assert isinstance(manip, np.ndarray) and manip.shape == (m,)
    for k in range(m):
        np.testing.assert_array_equal(chain.fk(q[k]), pose[k])
        np.testing.assert_array_equal(chain.jacobian(q[k]), jacobian[k])
        single_pose, single_jacobian = chain.fk_and_jacobian(q[k])
        np.testing.assert_array_equal(single_pose, pose[k])
        np.testing.assert_array_equal(single_jacobian, jacobian[k])
        np.testing.assert_array_equal(chain.frames(q[k]), frames[k])
        np.testing.assert_array_equal(chain.jacobian_dot(q[k], qd[k]), dots[k])
        value = chain.manipulability(q[k])
        assert isinstance(value, float)
        assert value == pytest.approx(manip[k], rel=EXACT, abs=EXACT)


def test_fk_accepts_lists_and_integers_and_does_not_modify_q():
    chain = UR5()
    q = np.array([0.1, -0.2, 0.3, 0.4, -0.5, 0.6])
    kept = q.copy()
    np.testing.assert_array_equal(chain.fk(q.tolist()), chain.fk(q))
    np.testing.assert_array_equal(q, kept)
    np.testing.assert_array_equal(chain.fk([0, 0, 0, 0, 0, 0]), chain.fk(np.zeros(6)))
    assert chain.fk(np.zeros((0, 6))).shape == (0, 4, 4)


def test_configurations_reports_single_or_batch():
    chain = UR5()
    configs, single = chain.configurations(np.zeros(6))
    assert configs.shape == (1, 6) and single
    configs, single = chain.configurations(np.zeros((3, 6)))
    assert configs.shape == (3, 6) and not single
    configs, single = chain.configurations(np.zeros((1, 6)))
    assert configs.shape == (1, 6) and not single


@pytest.mark.parametrize("name", list(BUILT_INS))
def test_base_and_tool_are_applied(name):
    chain = BUILT_INS[name]
    base = rigid([0.2, -0.4, 0.9], [0.5, -1.0, 2.0])
    tool = rigid([-0.3, 0.1, 0.2], [0.05, 0.0, 0.12])
    moved = SerialChain(chain.joints, base=base @ chain.base, tool=chain.tool @ tool)
    q = np.random.default_rng(5).uniform(-2, 2, (20, chain.ndof))
    scale = 4.0 + min(chain.reach(), 30.0)  # a free slider has unbounded reach
    np.testing.assert_allclose(moved.fk(q), base @ chain.fk(q) @ tool, atol=EXACT * scale)
    frames, plain = moved.frames(q), chain.frames(q)
    np.testing.assert_allclose(frames[:, 0], np.broadcast_to(base @ chain.base, (20, 4, 4)))
    np.testing.assert_allclose(frames[:, 1:-1], base @ plain[:, 1:-1], atol=EXACT * scale)
    # The tool does not move the joints; the world velocity of the tool point changes.
    jacobian = moved.jacobian(q)
    rotation = base[:3, :3]
    np.testing.assert_allclose(
        jacobian[:, 3:], rotation @ chain.jacobian(q)[:, 3:], atol=EXACT * scale
    )


def test_base_and_tool_properties_are_copies():
    base = rigid([0, 0, 0.3], [1, 2, 3])
    chain = SerialChain([Joint("a", "revolute")], base=base, tool=base)
    chain.base[0, 3] = 50.0
    chain.tool[0, 3] = 50.0
    chain.lower[0] = 7.0
    chain.revolute[0] = False
    np.testing.assert_array_equal(chain.base, base)
    np.testing.assert_array_equal(chain.tool, base)
    assert chain.lower[0] == -np.inf and chain.revolute[0]


# ------------------------------------------------------------------------ DH tables
@st.composite
def dh_tables(draw):
    count = draw(st.integers(1, 6))
    rows = []
    for _ in range(count):
        rows.append(
            DHRow(
                a=draw(coordinates),
                alpha=draw(angles),
                d=draw(coordinates),
                theta=draw(angles),
                kind=draw(st.sampled_from(["revolute", "prismatic"])),
            )
        )
    q = [draw(st.floats(-3.0, 3.0)) for _ in range(count)]
    return rows, np.array(q)


@pytest.mark.parametrize("convention", ["standard", "modified"])
@given(table=dh_tables(), base=rigid_transforms, tool=rigid_transforms)
def test_dh_tables_match_the_textbook_row_products(convention, table, base, tool):
    rows, q = table
    chain = SerialChain.from_dh(rows, convention=convention, base=base, tool=tool)
    assert chain.ndof == len(rows)
    assert chain.revolute.tolist() == [r.kind == "revolute" for r in rows]
    expected = base @ dh_product(rows, q, convention) @ tool
    scale = 3.0 + sum(abs(r.a) + abs(r.d) for r in rows) + np.abs(q).sum()
    np.testing.assert_allclose(chain.fk(q), expected, atol=EXACT * scale)
    np.testing.assert_allclose(chain.fk(q[np.newaxis])[0], expected, atol=EXACT * scale)


@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_dh_offsets_are_theta_for_revolute_and_d_for_prismatic(convention):
    rows = [
        DHRow(a=0.5, alpha=0.3, d=0.2, theta=0.7),
        DHRow(a=0.1, alpha=-0.4, d=0.6, theta=-0.2, kind="prismatic"),
    ]
    chain = SerialChain.from_dh(rows, convention=convention)
    assert [j.offset for j in chain.joints] == [0.7, 0.6]
    # q = 0 is the table itself: theta and d act as given.
    np.testing.assert_allclose(
        chain.fk([0.0, 0.0]), dh_product(rows, [0.0, 0.0], convention), atol=EXACT
    )
    # Moving a joint by q adds to its offset, nothing else.
    shifted = [dataclasses.replace(rows[0], theta=0.7 + 0.25), dataclasses.replace(rows[1], d=0.85)]
    np.testing.assert_allclose(
        chain.fk([0.25, 0.25]), dh_product(shifted, [0.0, 0.0], convention), atol=EXACT
    )


def test_dh_single_rows_by_hand():
    # Standard: Rz(θ) Tz(d) Tx(a) Rx(α) puts the next frame at (a cos θ, a sin θ, d).
    chain = SerialChain.from_dh([DHRow(a=2.0, alpha=np.pi / 2, d=0.5)])
    pose = chain.fk([np.pi / 2])
    np.testing.assert_allclose(pose[:3, 3], [0.0, 2.0, 0.5], atol=EXACT)
    np.testing.assert_allclose(pose[:3, 2], [1.0, 0.0, 0.0], atol=EXACT)  # new z = old x turned
    # Modified: Rx(α) Tx(a) Rz(θ) Tz(d): the joint turns about the x-shifted, α-tilted z.
    chain = SerialChain.from_dh([DHRow(a=2.0, alpha=np.pi / 2, d=0.5)], convention="modified")
    pose = chain.fk([np.pi / 2])
    np.testing.assert_allclose(pose[:3, 3], [2.0, -0.5, 0.0], atol=EXACT)
    # Prismatic: the joint variable adds to d.
    slider = SerialChain.from_dh([DHRow(a=0.1, d=0.2, theta=np.pi / 2, kind="prismatic")])
    np.testing.assert_allclose(slider.fk([0.3])[:3, 3], [0.0, 0.1, 0.5], atol=EXACT)


def test_dh_names_limits_and_chain_name():
    rows = [
        DHRow(a=1.0, lower=-1.0, upper=2.0, velocity=3.0),
        DHRow(kind="prismatic", lower=0.0, upper=0.5, velocity=0.25),
    ]
    chain = SerialChain.from_dh(rows, name="arm")
    assert chain.names == ["q1", "q2"] and chain.name == "arm"
    np.testing.assert_array_equal(chain.lower, [-1.0, 0.0])
    np.testing.assert_array_equal(chain.upper, [2.0, 0.5])
    np.testing.assert_array_equal(chain.velocity_limits, [3.0, 0.25])
    named = SerialChain.from_dh(rows, names=("shoulder", "slide"))
    assert named.names == ["shoulder", "slide"]
    assert [j.name for j in named.joints] == ["shoulder", "slide"]
    assert repr(named) == "SerialChain(name='chain', joints=RP)"


# ------------------------------------------------------------------------ Jacobians
@pytest.mark.parametrize("name", list(BUILT_INS))
def test_built_in_jacobians_against_finite_differences(name):
    chain = BUILT_INS[name]
    rng = np.random.default_rng(17)
    scale = 1.0 + min(chain.reach(), 30.0)
    for q in rng.uniform(-2.5, 2.5, (25, chain.ndof)):
        np.testing.assert_allclose(
            chain.jacobian(q), finite_difference_jacobian(chain, q), atol=FD_TOL * scale
        )


@given(chain_and_q=chains_and_configurations(count=1))
def test_random_chain_jacobians_against_finite_differences(chain_and_q):
    chain, q = chain_and_q
    q = q[0]
    np.testing.assert_allclose(
        chain.jacobian(q), finite_difference_jacobian(chain, q), atol=FD_TOL * size_of(chain)
    )


@given(table=dh_tables(), base=rigid_transforms)
def test_dh_jacobians_with_prismatic_joints_against_finite_differences(table, base):
    rows, q = table
    rows = [*rows, DHRow(kind="prismatic", a=0.2, alpha=0.9, theta=-0.3, d=0.1)]
    q = np.append(q, 0.4)
    chain = SerialChain.from_dh(rows, base=base)
    jacobian = chain.jacobian(q)
    scale = 3.0 + sum(abs(r.a) + abs(r.d) for r in rows) + np.abs(q).sum()
    np.testing.assert_allclose(jacobian, finite_difference_jacobian(chain, q), atol=FD_TOL * scale)
    # A slider moves the tool along its axis and does not turn it.
    for j in np.flatnonzero(~chain.revolute):
        np.testing.assert_allclose(jacobian[3:, j], 0.0, atol=0.0)
        assert np.linalg.norm(jacobian[:3, j]) == pytest.approx(1.0, rel=EXACT)


def test_jacobian_columns_of_a_planar_arm_by_hand():
    l1, l2, q1, q2 = 1.0, 0.5, 0.3, 1.1
    jacobian = Planar2R(l1, l2).jacobian([q1, q2])
    s1, c1, s12, c12 = np.sin(q1), np.cos(q1), np.sin(q1 + q2), np.cos(q1 + q2)
    expected = np.array(
        [
            [-l1 * s1 - l2 * s12, -l2 * s12],
            [l1 * c1 + l2 * c12, l2 * c12],
            [0.0, 0.0],
            [0.0, 0.0],
            [0.0, 0.0],
            [1.0, 1.0],
        ]
    )
    np.testing.assert_allclose(jacobian, expected, atol=EXACT)


@given(chain_and_q=chains_and_configurations())
def test_jacobian_dot_against_finite_differences_along_qd(chain_and_q):
    chain, q = chain_and_q
    qd = np.sin(5 * q - 2)  # rates in [-1, 1]
    numeric = (chain.jacobian(q + FD_STEP * qd) - chain.jacobian(q - FD_STEP * qd)) / (2 * FD_STEP)
    scale = size_of(chain)
    np.testing.assert_allclose(chain.jacobian_dot(q, qd), numeric, atol=FD_TOL * scale)


@given(chain_and_q=chains_and_configurations(count=1), factor=st.floats(-3.0, 3.0))
def test_jacobian_dot_is_linear_in_qd_and_zero_at_rest(chain_and_q, factor):
    chain, q = chain_and_q
    q = q[0]
    qd = np.cos(q)
    base = chain.jacobian_dot(q, qd)
    scale = size_of(chain) * (1.0 + abs(factor))
    np.testing.assert_allclose(
        chain.jacobian_dot(q, factor * qd), factor * base, atol=LINEAR * scale
    )
    np.testing.assert_array_equal(chain.jacobian_dot(q, np.zeros(chain.ndof)), 0.0)


@pytest.mark.parametrize("name", list(BUILT_INS))
def test_built_in_jacobian_dot_against_finite_differences(name):
    chain = BUILT_INS[name]
    rng = np.random.default_rng(23)
    q = rng.uniform(-2.5, 2.5, (30, chain.ndof))
    qd = rng.uniform(-1.5, 1.5, (30, chain.ndof))
    numeric = (chain.jacobian(q + FD_STEP * qd) - chain.jacobian(q - FD_STEP * qd)) / (2 * FD_STEP)
    scale = 1.0 + min(chain.reach(), 30.0)
    np.testing.assert_allclose(chain.jacobian_dot(q, qd), numeric, atol=FD_TOL * scale)


# ------------------------------------------------------------------------ manipulability
lengths = st.floats(0.05, 5.0)


@given(q1=angles, q2=wide_angles, l1=lengths, l2=lengths)
def test_planar_manipulability_closed_forms(q1, q2, l1, l2):
    arm = Planar2R(l1, l2)
    scale = (l1 + l2 + 1.0) ** 2
    # Position rows: a 3x2 Jacobian, sqrt(det(JᵀJ)) = l1 l2 |sin q2|.
    position = arm.manipulability([q1, q2], part="position")
    assert position == pytest.approx(l1 * l2 * abs(np.sin(q2)), abs=EXACT * scale)
    jacobian = arm.jacobian([q1, q2])[:3]
    gram = np.linalg.det(jacobian.T @ jacobian)
    assert position == pytest.approx(np.sqrt(max(gram, 0.0)), abs=1e-7 * scale)
    # All six rows add the two unit angular columns: det(JᵀJ) = (l1 l2 sin q2)² + l1².
    everything = arm.manipulability([q1, q2])
    expected = np.sqrt((l1 * l2 * np.sin(q2)) ** 2 + l1**2)
    assert everything == pytest.approx(expected, abs=EXACT * scale)
    # The angular rows have rank one: both joints turn about z.
    assert arm.manipulability([q1, q2], part="orientation") == pytest.approx(0.0, abs=EXACT)


def ur5_determinant(q: np.ndarray) -> np.ndarray:
    """|det J| of the UR5 in closed form: a2 a3 s3 s5 (a2 c2 + a3 c23 + d5 s234)."""
    a2, a3, d5 = -0.425, -0.39225, 0.09465
    q2, q3, q4, q5 = q[..., 1], q[..., 2], q[..., 3], q[..., 4]
    shoulder = a2 * np.cos(q2) + a3 * np.cos(q2 + q3) + d5 * np.sin(q2 + q3 + q4)
    return np.abs(a2 * a3 * np.sin(q3) * np.sin(q5) * shoulder)


def test_ur5_manipulability_is_the_determinant():
    ur5 = UR5()
    q = np.random.default_rng(29).uniform(-np.pi, np.pi, (300, 6))
    np.testing.assert_allclose(ur5.manipulability(q), ur5_determinant(q), rtol=1e-9, atol=EXACT)
    np.testing.assert_allclose(
        ur5.manipulability(q), np.abs(np.linalg.det(ur5.jacobian(q))), rtol=1e-9, atol=EXACT
    )


def shoulder_singular(q3: float) -> np.ndarray:
    """A UR5 configuration with the wrist centre on joint 1's axis (q2 = π/2)."""
    a3, d5 = -0.39225, 0.09465
    # a2 c2 + a3 c23 + d5 s234 = 0 with c2 = 0, c23 = -s3: s234 = a3 sin(q3) / d5.
    q2 = np.pi / 2
    q4 = np.arcsin(a3 * np.sin(q3) / d5) - q2 - q3
    return np.array([0.4, q2, q3, q4, 0.9, -0.3])


@pytest.mark.parametrize(
    ("kind", "q"),
    [
        ("home", np.zeros(6)),
        ("wrist q5 = 0", np.array([0.3, -1.0, 1.2, 0.4, 0.0, 0.2])),
        ("wrist q5 = pi", np.array([0.3, -1.0, 1.2, 0.4, np.pi, 0.2])),
        ("elbow q3 = 0", np.array([0.3, -1.0, 0.0, 0.4, 1.0, 0.2])),
        ("elbow q3 = pi", np.array([-0.3, 0.5, np.pi, 0.4, 1.0, 0.2])),
        ("shoulder", shoulder_singular(0.1)),
    ],
)
def test_ur5_manipulability_vanishes_at_singularities(kind, q):
    ur5 = UR5()
    assert ur5_determinant(q) < 1e-15
    assert ur5.manipulability(q) < 1e-12
    assert np.linalg.matrix_rank(ur5.jacobian(q), tol=1e-9) < 6
    nudged = q + np.array([0.0, 0.05, 0.05, 0.05, 0.05, 0.0])
    assert ur5.manipulability(nudged) > 1e-5


def test_manipulability_of_a_redundant_chain_is_sqrt_det_j_jt():
    rng = np.random.default_rng(31)
    rows = [DHRow(a=a, alpha=al, d=d) for a, al, d in rng.uniform(-1, 1, (7, 3))]
    chain = SerialChain.from_dh(rows)
    for q in rng.uniform(-3, 3, (20, 7)):
        jacobian = chain.jacobian(q)
        expected = np.sqrt(np.linalg.det(jacobian @ jacobian.T))
        assert chain.manipulability(q) == pytest.approx(expected, rel=1e-9)
        position = jacobian[:3]
        assert chain.manipulability(q, part="position") == pytest.approx(
            np.sqrt(np.linalg.det(position @ position.T)), rel=1e-9
        )


# ------------------------------------------------------------------------ limits and reach
def test_limits_collects_joint_ranges_and_speeds():
    rows = [
        DHRow(a=1.0, lower=-1.0, upper=2.0, velocity=3.0),
        DHRow(a=1.0, lower=-0.5, upper=0.5, velocity=4.0),
    ]
    limits = SerialChain.from_dh(rows).limits()
    assert isinstance(limits, Limits)
    np.testing.assert_array_equal(limits.position.lower, [-1.0, -0.5])
    np.testing.assert_array_equal(limits.position.upper, [2.0, 0.5])
    np.testing.assert_array_equal(limits.velocity.upper, [3.0, 4.0])
    partial = SerialChain.from_dh([rows[0], DHRow(a=1.0)]).limits()
    assert partial.velocity is None  # one joint has no speed limit
    np.testing.assert_array_equal(partial.position.upper, [2.0, np.inf])


def test_reach_of_built_ins():
    assert Planar2R(1.0, 0.5).reach() == pytest.approx(1.5, rel=EXACT)
    assert Planar2R(3.0, 4.0, axis_offsets=(9.0, 0.0, 0.0)).reach() == pytest.approx(7.0)
    assert Spatial3R(5, 10, 8, 12).reach() == pytest.approx(30.0)  # joint 1 to the tool
    slider = SerialChain.from_dh([DHRow(a=1.0), DHRow(kind="prismatic", lower=-2.0, upper=0.5)])
    assert slider.reach() == pytest.approx(3.0)
    assert SerialChain.from_dh([DHRow(a=1.0), DHRow(kind="prismatic")]).reach() == np.inf


@given(chain_and_q=chains_and_configurations())
def test_reach_bounds_the_distance_from_the_first_joint_to_the_tool(chain_and_q):
    chain, q = chain_and_q
    # Sliders get a range and no offset here (offsets: test_reach_counts_a_sliders_offset).
    joints = [
        dataclasses.replace(j, lower=-1.5, upper=1.0, offset=0.0) if not j.revolute else j
        for j in chain.joints
    ]
    chain = SerialChain(joints, base=chain.base, tool=chain.tool)
    q = np.clip(q, chain.lower, chain.upper)
    points = chain.points(q)
    distance = np.linalg.norm(points[:, -1] - points[:, 1], axis=1)
    assert np.all(distance <= chain.reach() * (1 + EXACT) + EXACT)


def test_reach_counts_a_sliders_offset():
    chain = SerialChain.from_dh([DHRow(a=0.1), DHRow(kind="prismatic", d=5.0, lower=0, upper=0.1)])
    points = chain.points([0.0, 0.05])
    assert np.linalg.norm(points[-1] - points[1]) <= chain.reach()


# ------------------------------------------------------------------------ bad input
def _bad_input_cases():
    ur5 = UR5()
    joint = Joint("a", "revolute")
    return [
        pytest.param(
            lambda: Joint("j", "revolute", axis=[0, 0, 0]),
            "axis must be a non-zero 3-vector",
            id="joint zero axis",
        ),
        pytest.param(
            lambda: Joint("j", "revolute", axis=[1, 0]),
            "axis must be a non-zero 3-vector",
            id="joint 2-vector axis",
        ),
        pytest.param(
            lambda: Joint("j", "revolute", axis=[np.nan, 0, 1]),
            "axis must be finite",
            id="joint NaN axis",
        ),
        pytest.param(
            lambda: Joint("j", "revolute", lower=1, upper=0),
            "lower limit 1 must be below upper 0",
            id="joint lower > upper",
        ),
        pytest.param(
            lambda: Joint("j", "prismatic", lower=0.5, upper=0.5),
            "must be below upper",
            id="joint lower == upper",
        ),
        pytest.param(
            lambda: Joint("j", "revolute", lower=np.nan), "lower is NaN", id="joint NaN lower"
        ),
        pytest.param(
            lambda: Joint("j", "revolute", upper=np.nan), "upper is NaN", id="joint NaN upper"
        ),
        pytest.param(
            lambda: Joint("j", "revolute", velocity=-1),
            "velocity limit must be > 0, got -1",
            id="joint negative velocity",
        ),
        pytest.param(
            lambda: Joint("j", "revolute", velocity=0.0),
            "velocity limit must be > 0",
            id="joint zero velocity",
        ),
        pytest.param(
            lambda: Joint("j", "revolute", velocity=np.nan),
            "velocity is NaN",
            id="joint NaN velocity",
        ),
        pytest.param(
            lambda: Joint("j", "spherical"),
            "kind must be 'revolute' or 'prismatic'",
            id="joint kind",
        ),
        pytest.param(
            lambda: Joint("j", "revolute", origin=np.eye(3)),
            "origin must be a 4x4 transform",
            id="joint 3x3 origin",
        ),
        pytest.param(
            lambda: Joint("j", "revolute", origin=np.full((4, 4), np.inf)),
            "origin must be finite",
            id="joint inf origin",
        ),
        pytest.param(lambda: SerialChain([]), "at least one joint", id="chain empty"),
        pytest.param(
            lambda: SerialChain([DHRow()]), "must be trajkit.kinematics.Joint", id="chain non-joint"
        ),
        pytest.param(
            lambda: SerialChain([joint, joint]),
            "joint names must be unique",
            id="chain duplicate names",
        ),
        pytest.param(
            lambda: SerialChain([joint], base=np.diag([2.0, 1, 1, 1])),
            "base must be a rigid transform",
            id="chain base not rigid",
        ),
        pytest.param(
            lambda: SerialChain([joint], base=np.ones((4, 4))),
            "base must be a rigid transform",
            id="chain base last row",
        ),
        pytest.param(
            lambda: SerialChain([joint], tool=np.eye(3)),
            "tool must be a 4x4 transform",
            id="chain tool shape",
        ),
        pytest.param(
            lambda: SerialChain([joint], base=np.full((4, 4), np.nan)),
            "base must be finite",
            id="chain base NaN",
        ),
        pytest.param(lambda: SerialChain.from_dh([]), "non-empty sequence of DHRow", id="dh empty"),
        pytest.param(
            lambda: SerialChain.from_dh([(1.0, 0.0, 0.0, 0.0)]),
            "non-empty sequence of DHRow",
            id="dh not rows",
        ),
        pytest.param(
            lambda: SerialChain.from_dh([DHRow()], convention="craig"),
            "convention must be 'standard' or 'modified', got 'craig'",
            id="dh convention",
        ),
        pytest.param(
            lambda: SerialChain.from_dh([DHRow(a=np.nan)]), "DH row 1 must be finite", id="dh NaN"
        ),
        pytest.param(
            lambda: SerialChain.from_dh([DHRow(), DHRow(theta=np.inf)]),
            "DH row 2 must be finite",
            id="dh inf",
        ),
        pytest.param(
            lambda: SerialChain.from_dh([DHRow()], names=["a", "b"]),
            "2 names for 1 DH rows",
            id="dh names",
        ),
        pytest.param(
            lambda: SerialChain.from_dh([DHRow(kind="spherical")]),
            "kind must be 'revolute' or 'prismatic'",
            id="dh kind",
        ),
        pytest.param(
            lambda: SerialChain.from_dh([DHRow(lower=2.0, upper=1.0)]),
            "must be below upper",
            id="dh limits",
        ),
        pytest.param(
            lambda: SerialChain.from_dh([DHRow()], tool=np.zeros((4, 4))),
            "tool must be a rigid transform",
            id="dh tool",
        ),
        pytest.param(
            lambda: ur5.fk([0.0] * 5),
            r"q must have shape \(6,\) or \(m, 6\) for this 6-joint chain, got shape \(5,\)",
            id="fk short q",
        ),
        pytest.param(lambda: ur5.fk(np.zeros((2, 2, 6))), r"got shape \(2, 2, 6\)", id="fk 3-D q"),
        pytest.param(lambda: Planar2R(1, 1).fk(0.3), r"q must have shape \(2,\)", id="fk scalar q"),
        pytest.param(lambda: ur5.fk([np.nan] * 6), "q must be finite", id="fk NaN q"),
        pytest.param(lambda: ur5.fk([[0.0] * 5 + [np.inf]]), "q must be finite", id="fk inf q"),
        pytest.param(lambda: ur5.fk("abcdef"), "q must be numeric", id="fk text q"),
        pytest.param(
            lambda: ur5.frames([0.0] * 7), r"q must have shape \(6,\)", id="frames short q"
        ),
        pytest.param(lambda: ur5.points([np.nan] * 6), "q must be finite", id="points NaN q"),
        pytest.param(
            lambda: ur5.jacobian([0.0]), r"q must have shape \(6,\)", id="jacobian short q"
        ),
        pytest.param(
            lambda: ur5.fk_and_jacobian([np.inf] * 6), "q must be finite", id="fk_and_jacobian NaN"
        ),
        pytest.param(
            lambda: ur5.jacobian_dot(np.zeros(6), np.zeros((2, 6))),
            r"qd has shape \(2, 6\) but q has \(1, 6\)",
            id="jacobian_dot qd shape",
        ),
        pytest.param(
            lambda: ur5.jacobian_dot(np.zeros(6), np.zeros(5)),
            r"qd must have shape \(6,\)",
            id="jacobian_dot qd length",
        ),
        pytest.param(
            lambda: ur5.jacobian_dot(np.zeros(6), [np.nan] * 6),
            "qd must be finite",
            id="jacobian_dot qd NaN",
        ),
        pytest.param(
            lambda: ur5.manipulability(np.zeros(6), part="twist"),
            "part must be 'all', 'position' or 'orientation', got 'twist'",
            id="manipulability part",
        ),
        pytest.param(
            lambda: ur5.manipulability(np.zeros(3)),
            r"q must have shape \(6,\)",
            id="manipulability q",
        ),
    ]


BAD_INPUT = _bad_input_cases()


@pytest.mark.parametrize(("call", "message"), BAD_INPUT)
def test_bad_input_raises_invalid_input_error(call, message):
    with pytest.raises(InvalidInputError, match=message) as excinfo:
        call()
    assert type(excinfo.value) is InvalidInputError


@pytest.mark.parametrize("offset", [np.nan, np.inf])
def test_joint_refuses_a_non_finite_offset(offset):
    with pytest.raises(InvalidInputError, match="offset") as excinfo:
        Joint("j", "revolute", offset=offset)
    assert type(excinfo.value) is InvalidInputError


def test_joint_refuses_a_non_rigid_origin():
    scaled = np.diag([2.0, 1.0, 1.0, 1.0])
    with pytest.raises(InvalidInputError, match="rigid transform") as excinfo:
        Joint("j", "revolute", origin=scaled)
    assert type(excinfo.value) is InvalidInputError


def test_only_continuous_joints_wrap_by_whole_turns():
    chain = SerialChain.from_dh(
        [DHRow(a=1.0), DHRow(a=1.0, upper=1.0), DHRow(a=1.0, lower=-1.0, upper=1.0),
         DHRow(kind="prismatic")]
    )  # fmt: skip
    assert chain.continuous.tolist() == [True, False, False, False]
    q = np.array([0.2 + 4 * np.pi, 0.2 + 2 * np.pi, 0.5, 3.0])
    np.testing.assert_allclose(chain.wrap_near(q, np.zeros(4)), [0.2, q[1], 0.5, 3.0], atol=1e-12)
