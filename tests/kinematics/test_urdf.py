"""Tests for trajkit.kinematics.from_urdf: real robot files, handwritten URDFs, malformed input."""

from __future__ import annotations

import os
import re
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

from trajkit.errors import InvalidInputError, MissingDependencyError
from trajkit.kinematics import SerialChain, from_urdf
from trajkit.kinematics import urdf as urdf_module

pytest.importorskip("yourdfpy", reason='URDF is read with yourdfpy: pip install "trajkit[urdf]"')

DATA = Path(__file__).resolve().parent / "data"
TWO_LINK = DATA / "two_link.urdf"
KUKA = "xacro/kuka_description/kuka_lbr_iiwa/urdf/lbr_iiwa_14_r820.urdf"
PUMA = "xacro/unimation_puma560_description/urdf/puma560_robot.urdf"


# --------------------------------------------------------------------- helpers
def rot_x(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def rot_y(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def rot_z(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def transform(rotation=None, translation=(0.0, 0.0, 0.0)) -> np.ndarray:
    out = np.eye(4)
    if rotation is not None:
        out[:3, :3] = rotation
    out[:3, 3] = translation
    return out


def axis_angle(axis, angle: float) -> np.ndarray:
    """Rotation about a unit axis (Rodrigues), written out independently of trajkit."""
    x, y, z = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    k = np.array([[0, -z, y], [z, 0, -x], [-y, x, 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def urdf_fk(path_or_text, tip: str, q) -> np.ndarray:
    """FK by composing joint transforms read straight from the XML (ElementTree).

    An oracle independent of yourdfpy and trajkit: origin = T(xyz) Rz Ry Rx, then
    the joint's motion about/along its axis; from the root link to ``tip``.
    """
    text = Path(path_or_text).read_text() if isinstance(path_or_text, Path) else path_or_text
    root = ET.fromstring(text)
    by_child = {j.find("child").get("link"): j for j in root.findall("joint")}
    path = []
    link = tip
    while link in by_child:
        path.append(by_child[link])
        link = by_child[link].find("parent").get("link")
    path.reverse()
    pose = np.eye(4)
    values = iter(q)
    for joint in path:
        origin = joint.find("origin")
        xyz = (
            [0.0] * 3 if origin is None else [float(v) for v in origin.get("xyz", "0 0 0").split()]
        )
        rpy = (
            [0.0] * 3 if origin is None else [float(v) for v in origin.get("rpy", "0 0 0").split()]
        )
        pose = pose @ transform(rot_z(rpy[2]) @ rot_y(rpy[1]) @ rot_x(rpy[0]), xyz)
        axis_el = joint.find("axis")
        axis = np.array([1.0, 0, 0] if axis_el is None else axis_el.get("xyz").split(), float)
        kind = joint.get("type")
        if kind in ("revolute", "continuous"):
            pose = pose @ transform(axis_angle(axis, next(values)))
        elif kind == "prismatic":
            pose = pose @ transform(translation=axis / np.linalg.norm(axis) * next(values))
    return pose


def urdf_robot(name: str, body: str) -> str:
    return f'<?xml version="1.0"?>\n<robot name="{name}">\n{body}\n</robot>\n'


def links(*names: str) -> str:
    return "".join(f'<link name="{n}"/>' for n in names)


def joint(
    name: str,
    kind: str,
    parent: str,
    child: str,
    *,
    xyz: str | None = None,
    rpy: str | None = None,
    axis: str | None = None,
    limit: str | None = '<limit lower="-1" upper="1" velocity="1" effort="1"/>',
    extra: str = "",
) -> str:
    origin = ""
    if xyz is not None or rpy is not None:
        attrs = (f' xyz="{xyz}"' if xyz else "") + (f' rpy="{rpy}"' if rpy else "")
        origin = f"<origin{attrs}/>"
    axis_el = f'<axis xyz="{axis}"/>' if axis is not None else ""
    return (
        f'<joint name="{name}" type="{kind}"><parent link="{parent}"/>'
        f'<child link="{child}"/>{origin}{axis_el}{limit or ""}{extra}</joint>'
    )


def raises_invalid(match: str, source, **kwargs) -> InvalidInputError:
    with pytest.raises(InvalidInputError, match=match) as info:
        from_urdf(source, **kwargs)
    assert type(info.value) is InvalidInputError
    message = str(info.value)
    assert "\n" not in message, message
    return info.value


# ------------------------------------------------------------- real robot files
@pytest.fixture(scope="module")
def rtbdata_dir() -> Path:
    rtbdata = pytest.importorskip(
        "rtbdata", reason="rtb-data (the oracle's robot files) is not installed"
    )
    return Path(os.path.dirname(rtbdata.__file__))


def rtb_robot(path: Path):
    """Robotics Toolbox's own model of a URDF file (visual/collision stripped:
    the mesh packages of some files are not shipped, and rtb needs no meshes)."""
    rtb = pytest.importorskip(
        "roboticstoolbox", reason="roboticstoolbox (test oracle) is not installed"
    )
    from roboticstoolbox.models.URDF.URDFRobot import URDF_read

    def strip(text: str) -> str:
        return re.sub(r"<(visual|collision)>.*?</\1>", "", text, flags=re.S)

    elinks, name, _ = URDF_read(path, patch=strip)
    return rtb.Robot(elinks, name=name)


def random_configs(chain: SerialChain, count: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return rng.uniform(chain.lower, chain.upper, size=(count, chain.ndof))


class TestKukaIiwa:
    @pytest.fixture(scope="class")
    def path(self, rtbdata_dir: Path) -> Path:
        return rtbdata_dir / KUKA

    @pytest.fixture(scope="class")
    def chain(self, path: Path) -> SerialChain:
        return from_urdf(path, tip_link="tool0")

    def test_description(self, chain: SerialChain) -> None:
        assert chain.name == "kuka_lbr_iiwa_14_r820"
        assert chain.ndof == 7
        assert chain.names == [f"joint_a{i}" for i in range(1, 8)]
        assert chain.revolute.all()
        np.testing.assert_array_equal(
            chain.upper, [2.9668, 2.0942, 2.9668, 2.0942, 2.9668, 2.0942, 3.0541]
        )
        np.testing.assert_array_equal(chain.lower, -chain.upper)
        np.testing.assert_array_equal(
            chain.velocity_limits, [1.4834, 1.4834, 1.7452, 1.3089, 2.2688, 2.356, 2.356]
        )
        # The fixed joint_a7-tool0 becomes the tool transform.
        np.testing.assert_array_equal(chain.tool, transform(translation=(0, 0, 0.126)))
        np.testing.assert_array_equal(chain.base, np.eye(4))
        np.testing.assert_array_equal(chain.joints[3].axis, [0, -1, 0])

    def test_branching_tree_needs_tip_link(self, path: Path) -> None:
        # base_link has two children: the arm (ending at tool0) and the fixed "base" frame.
        error = raises_invalid("leaf links", path)
        assert "'tool0'" in str(error) and "'base'" in str(error)
        assert str(path) in str(error)

    def test_pathlike_and_str_and_text_agree(self, path: Path, chain: SerialChain) -> None:
        q = random_configs(chain, 3, seed=1)
        for source in (str(path), path.read_text()):
            other = from_urdf(source, tip_link="tool0")
            np.testing.assert_array_equal(other.fk(q), chain.fk(q))

    def test_fk_and_jacobian_match_robotics_toolbox(self, path: Path, chain: SerialChain) -> None:
        robot = rtb_robot(path)
        np.testing.assert_array_equal(robot.qlim, np.stack([chain.lower, chain.upper]))
        q = random_configs(chain, 20, seed=7)
        poses, jacobians = chain.fk_and_jacobian(q)
        for qi, pose, jac in zip(q, poses, jacobians, strict=True):
            np.testing.assert_allclose(pose, robot.fkine(qi, end="tool0").A, rtol=0, atol=1e-9)
            np.testing.assert_allclose(jac, robot.jacob0(qi, end="tool0"), rtol=0, atol=1e-9)

    def test_fk_matches_xml_composition(self, path: Path, chain: SerialChain) -> None:
        for qi in random_configs(chain, 5, seed=3):
            np.testing.assert_allclose(chain.fk(qi), urdf_fk(path, "tool0", qi), rtol=0, atol=1e-12)

    def test_sub_chain_between_inner_links(self, path: Path, chain: SerialChain) -> None:
        sub = from_urdf(path, base_link="link_2", tip_link="link_5")
        assert sub.names == ["joint_a3", "joint_a4", "joint_a5"]
        q = random_configs(chain, 4, seed=5)
        # Frame of link_5 relative to link_2 from the full chain's joint frames.
        frames = chain.frames(q)  # base, joints 1..7, tool
        expected = np.linalg.inv(frames[:, 2]) @ frames[:, 5]
        np.testing.assert_allclose(sub.fk(q[:, 2:5]), expected, rtol=0, atol=1e-12)

    def test_tip_above_base_has_no_path(self, path: Path) -> None:
        raises_invalid("no kinematic path", path, base_link="link_5", tip_link="link_2")

    def test_side_branch_from_base(self, path: Path) -> None:
        # base_link -> base is a single fixed joint: nothing to move.
        raises_invalid("no movable joint", path, tip_link="base")


class TestPuma560:
    @pytest.fixture(scope="class")
    def path(self, rtbdata_dir: Path) -> Path:
        return rtbdata_dir / PUMA

    @pytest.fixture(scope="class")
    def chain(self, path: Path) -> SerialChain:
        return from_urdf(path)

    def test_description(self, chain: SerialChain) -> None:
        assert chain.name == "Puma560"
        assert chain.names == ["j1", "j2", "j3", "j4", "j5", "j6"]
        np.testing.assert_array_equal(chain.lower, [-3.14159265] + [-1.570796325] * 5)
        np.testing.assert_array_equal(chain.upper, [3.14159265] + [1.570796325] * 5)
        # velocity="0" in the file means no speed limit.
        assert np.all(np.isinf(chain.velocity_limits))
        assert chain.limits().velocity is None
        np.testing.assert_array_equal(chain.tool, np.eye(4))

    def test_name_override(self, path: Path) -> None:
        assert from_urdf(path, name="puma").name == "puma"

    def test_fk_and_jacobian_match_robotics_toolbox(self, path: Path, chain: SerialChain) -> None:
        robot = rtb_robot(path)
        q = random_configs(chain, 20, seed=11)
        for qi in q:
            np.testing.assert_allclose(chain.fk(qi), robot.fkine(qi).A, rtol=0, atol=1e-9)
            np.testing.assert_allclose(chain.jacobian(qi), robot.jacob0(qi), rtol=0, atol=1e-9)

    def test_fk_matches_xml_composition(self, path: Path, chain: SerialChain) -> None:
        for qi in random_configs(chain, 5, seed=13):
            np.testing.assert_allclose(chain.fk(qi), urdf_fk(path, "link7", qi), rtol=0, atol=1e-12)


# ---------------------------------------------------------- handwritten URDFs
class TestTwoLink:
    @pytest.fixture(scope="class")
    def chain(self) -> SerialChain:
        return from_urdf(TWO_LINK)

    def test_description(self, chain: SerialChain) -> None:
        assert chain.name == "two_link"
        assert chain.names == ["shoulder_yaw", "elbow_yaw"]
        np.testing.assert_array_equal(chain.lower, [-2.5, -3.0])
        np.testing.assert_array_equal(chain.upper, [2.0, 3.0])
        np.testing.assert_array_equal(chain.velocity_limits, [1.5, 2.5])
        # The mount (0.1) and the joint's own origin (0.2) fold into joint 1's origin.
        np.testing.assert_allclose(
            chain.joints[0].origin, transform(translation=(0, 0, 0.3)), rtol=0, atol=1e-15
        )
        np.testing.assert_array_equal(chain.joints[1].origin, transform(translation=(0.5, 0, 0)))
        np.testing.assert_array_equal(chain.tool, transform(translation=(0.3, 0, 0)))
        np.testing.assert_array_equal(chain.base, np.eye(4))

    @pytest.mark.parametrize("q", [(0.0, 0.0), (0.3, -1.1), (-2.4, 2.9), (1.9, 0.5)])
    def test_fk_by_hand(self, chain: SerialChain, q) -> None:
        q1, q2 = q
        expected = transform(
            rot_z(q1 + q2),
            (
                0.5 * np.cos(q1) + 0.3 * np.cos(q1 + q2),
                0.5 * np.sin(q1) + 0.3 * np.sin(q1 + q2),
                0.3,
            ),
        )
        np.testing.assert_allclose(chain.fk(q), expected, rtol=0, atol=1e-12)

    def test_tip_link_at_a_fixed_frame(self) -> None:
        # Ending at "elbow": the spacer after the last movable joint is the tool.
        chain = from_urdf(TWO_LINK, tip_link="elbow")
        assert chain.names == ["shoulder_yaw"]
        np.testing.assert_array_equal(chain.tool, transform(translation=(0.5, 0, 0)))

    def test_base_link_below_a_fixed_joint(self) -> None:
        chain = from_urdf(TWO_LINK, base_link="shoulder")
        np.testing.assert_array_equal(chain.joints[0].origin, transform(translation=(0, 0, 0.2)))

    def test_meshes_are_not_read(self, chain: SerialChain) -> None:
        # The file references meshes that do not exist; loading succeeded anyway.
        assert chain.ndof == 2


def test_rpy_origin_is_fixed_axis_roll_pitch_yaw() -> None:
    roll, pitch, yaw = 0.3, -0.7, 1.2
    text = urdf_robot(
        "rpy",
        links("a", "b")
        + joint(
            "j", "revolute", "a", "b", xyz="0.1 -0.2 0.3", rpy=f"{roll} {pitch} {yaw}", axis="0 1 0"
        ),
    )
    chain = from_urdf(text)
    origin = transform(rot_z(yaw) @ rot_y(pitch) @ rot_x(roll), (0.1, -0.2, 0.3))
    np.testing.assert_allclose(chain.joints[0].origin, origin, rtol=0, atol=1e-15)
    for q in (0.0, 0.4, -0.9):
        expected = origin @ transform(rot_y(q))
        np.testing.assert_allclose(chain.fk([q]), expected, rtol=0, atol=1e-12)
        np.testing.assert_allclose(chain.fk([q]), urdf_fk(text, "b", [q]), rtol=0, atol=1e-12)


def test_rpy_quarter_turn_about_x_maps_y_to_z() -> None:
    text = urdf_robot(
        "r", links("a", "b") + joint("j", "revolute", "a", "b", rpy=f"{np.pi / 2} 0 0")
    )
    origin = from_urdf(text).joints[0].origin
    np.testing.assert_allclose(origin[:3, :3] @ [0, 1, 0], [0, 0, 1], atol=1e-15)


def test_missing_axis_defaults_to_x() -> None:
    chain = from_urdf(
        urdf_robot(
            "r",
            links("a", "b", "c")
            + joint("j", "revolute", "a", "b")
            + joint("t", "fixed", "b", "c", xyz="0 1 0", limit=None),
        )
    )
    np.testing.assert_array_equal(chain.joints[0].axis, [1, 0, 0])
    q = 0.6
    # The tool sits 1 m along y; turning about x moves it to (0, cos q, sin q).
    np.testing.assert_allclose(chain.fk([q])[:3, 3], [0, np.cos(q), np.sin(q)], atol=1e-15)


def test_continuous_joint_has_no_position_limits() -> None:
    with_limit = joint(
        "spin",
        "continuous",
        "a",
        "b",
        axis="0 0 1",
        limit='<limit lower="-1" upper="1" velocity="4" effort="1"/>',
    )
    chain = from_urdf(urdf_robot("r", links("a", "b") + with_limit))
    assert chain.lower.tolist() == [-np.inf]
    assert chain.upper.tolist() == [np.inf]
    assert chain.velocity_limits.tolist() == [4.0]
    assert chain.revolute.tolist() == [True]

    bare = from_urdf(
        urdf_robot("r", links("a", "b") + joint("spin", "continuous", "a", "b", limit=None))
    )
    assert bare.lower.tolist() == [-np.inf] and bare.upper.tolist() == [np.inf]
    assert bare.velocity_limits.tolist() == [np.inf]
    np.testing.assert_allclose(bare.fk([7.0])[:3, :3], rot_x(7.0), atol=1e-14)


def test_prismatic_joint() -> None:
    text = urdf_robot(
        "slide",
        links("a", "b", "c")
        + joint(
            "lift",
            "prismatic",
            "a",
            "b",
            xyz="0 0 0.5",
            axis="0 0 2",
            limit='<limit lower="-0.1" upper="0.4" velocity="0.25" effort="100"/>',
        )
        + joint("turn", "revolute", "b", "c", axis="0 0 1", xyz="0.2 0 0"),
    )
    chain = from_urdf(text)
    assert chain.revolute.tolist() == [False, True]
    assert chain.joints[0].kind == "prismatic"
    np.testing.assert_array_equal(chain.joints[0].axis, [0, 0, 1])  # normalised
    np.testing.assert_array_equal(chain.lower, [-0.1, -1])
    np.testing.assert_array_equal(chain.upper, [0.4, 1])
    np.testing.assert_array_equal(chain.velocity_limits, [0.25, 1])
    for d, th in [(0.0, 0.0), (0.3, 0.5), (-0.1, -0.8)]:
        expected = transform(rot_z(th), (0.2, 0, 0.5 + d))
        np.testing.assert_allclose(chain.fk([d, th]), expected, rtol=0, atol=1e-12)
        np.testing.assert_allclose(chain.fk([d, th]), urdf_fk(text, "c", [d, th]), atol=1e-12)
    jac = chain.jacobian([0.1, 0.2])
    np.testing.assert_allclose(jac[:, 0], [0, 0, 1, 0, 0, 0], atol=1e-15)


def test_velocity_absent_or_zero_means_unlimited() -> None:
    body = (
        links("a", "b", "c")
        + joint("j1", "revolute", "a", "b", limit='<limit lower="-1" upper="1" effort="1"/>')
        + joint(
            "j2",
            "prismatic",
            "b",
            "c",
            limit='<limit lower="0" upper="1" velocity="0" effort="1"/>',
        )
    )
    chain = from_urdf(urdf_robot("r", body))
    assert np.isinf(chain.velocity_limits).all()


def test_text_source_with_leading_whitespace_and_name() -> None:
    text = "\n   " + urdf_robot("r", links("a", "b") + joint("j", "revolute", "a", "b"))
    chain = from_urdf(text, name="custom")
    assert chain.name == "custom" and chain.names == ["j"]


def test_joint_order_in_file_does_not_matter() -> None:
    body = (
        joint("j2", "revolute", "b", "c", xyz="1 0 0", axis="0 0 1")
        + links("c", "b", "a")
        + joint("j1", "revolute", "a", "b", axis="0 0 1")
    )
    chain = from_urdf(urdf_robot("r", body))
    assert chain.names == ["j1", "j2"]


def test_floating_joint_off_the_path_is_ignored() -> None:
    body = (
        links("world", "arm", "hand", "box")
        + joint("j", "revolute", "world", "arm")
        + joint("k", "revolute", "arm", "hand")
        + joint("loose", "floating", "world", "box", limit=None)
    )
    chain = from_urdf(urdf_robot("r", body), tip_link="hand")
    assert chain.names == ["j", "k"]


def test_exported_from_package() -> None:
    assert from_urdf is urdf_module.from_urdf


# -------------------------------------------------------------- malformed input
SIMPLE = links("a", "b") + joint("j", "revolute", "a", "b")


@pytest.mark.parametrize(
    ("text", "fragment"),
    [
        ('<robot name="r"><link name="a">', "not well-formed XML"),
        ("<robot name='r'></robt>", "not well-formed XML"),
        ("<", "not well-formed XML"),
        ('<model name="r"><link name="a"/></model>', "root element is <model>, expected <robot>"),
        ("<robot>" + SIMPLE + "</robot>", "<robot> has no name"),
    ],
)
def test_not_a_urdf_document(text: str, fragment: str) -> None:
    raises_invalid(re.escape(fragment), text)


def test_not_xml_file(tmp_path: Path) -> None:
    path = tmp_path / "robot.urdf"
    path.write_bytes(b"\x89PNG\r\n\x1a\n binary junk")
    error = raises_invalid("not well-formed XML", path)
    assert str(path) in str(error)


def test_revolute_without_limit_names_the_joint() -> None:
    text = urdf_robot("r", links("a", "b") + joint("elbow", "revolute", "a", "b", limit=None))
    raises_invalid(r"joint 'elbow' is revolute but has no <limit>", text)


def test_prismatic_without_limit_names_the_joint() -> None:
    text = urdf_robot("r", links("a", "b") + joint("slide", "prismatic", "a", "b", limit=None))
    raises_invalid(r"joint 'slide' is prismatic but has no <limit>", text)


@pytest.mark.parametrize(
    ("limit", "fragment"),
    [
        (
            '<limit lower="1" upper="-1" velocity="1" effort="1"/>',
            "lower 1.0 must be below upper -1.0",
        ),
        ('<limit velocity="1" effort="1"/>', "lower 0.0 must be below upper 0.0"),
        ('<limit lower="-1" upper="1" velocity="-2" effort="1"/>', "velocity must be >= 0"),
        ('<limit lower="-1" upper="nan" velocity="1" effort="1"/>', "joint 'j'"),
        ('<limit lower="-1" upper="one" velocity="1" effort="1"/>', "could not convert"),
    ],
)
def test_bad_limits(limit: str, fragment: str) -> None:
    text = urdf_robot("r", links("a", "b") + joint("j", "revolute", "a", "b", limit=limit))
    raises_invalid(re.escape(fragment), text)


@pytest.mark.parametrize(
    ("kwargs", "fragment"),
    [
        ({"xyz": "1 2"}, "<origin xyz=...> must be three finite numbers"),
        ({"xyz": "1 2 3 4"}, "<origin xyz=...> must be three finite numbers"),
        ({"rpy": "0 0 inf"}, "<origin rpy=...> must be three finite numbers"),
        ({"axis": "0 0 x"}, "<axis xyz=...> must be three finite numbers"),
        ({"axis": "0 0 0"}, "axis must be a non-zero 3-vector"),
    ],
)
def test_bad_joint_geometry(kwargs: dict, fragment: str) -> None:
    text = urdf_robot("r", links("a", "b") + joint("j", "revolute", "a", "b", **kwargs))
    error = raises_invalid(re.escape(fragment), text)
    assert "joint 'j'" in str(error)


def test_unknown_tip_and_base_link() -> None:
    text = urdf_robot("r", SIMPLE)
    raises_invalid(
        r"tip_link 'hand' is not a link of the robot \(links: \['a', 'b'\]\)", text, tip_link="hand"
    )
    raises_invalid(r"base_link 'world' is not a link", text, base_link="world")


def test_base_equals_tip() -> None:
    raises_invalid(
        "base_link and tip_link are both 'a'", urdf_robot("r", SIMPLE), base_link="a", tip_link="a"
    )


def test_branching_tree_without_tip_link_lists_leaves() -> None:
    body = (
        links("torso", "left", "right", "left_hand")
        + joint("l", "revolute", "torso", "left")
        + joint("lh", "revolute", "left", "left_hand")
        + joint("r", "revolute", "torso", "right")
    )
    error = raises_invalid(r"leaf links \['left_hand', 'right'\]", urdf_robot("r", body))
    assert "tip_link" in str(error)
    assert from_urdf(urdf_robot("r", body), tip_link="right").names == ["r"]
    # Below "left" the tree does not branch.
    assert from_urdf(urdf_robot("r", body), base_link="left").names == ["lh"]


@pytest.mark.parametrize("kind", ["floating", "planar"])
def test_unsupported_joint_on_path(kind: str) -> None:
    body = (
        links("world", "base", "arm")
        + joint("free", kind, "world", "base", limit=None)
        + joint("j", "revolute", "base", "arm")
    )
    raises_invalid(rf"joint 'free' is '{kind}'", urdf_robot("r", body))
    # Starting above it is fine.
    assert from_urdf(urdf_robot("r", body), base_link="base").names == ["j"]


@pytest.mark.parametrize(
    ("kind", "fragment"), [("hinge", "unknown type 'hinge'"), (None, "no type attribute")]
)
def test_unknown_joint_type(kind: str | None, fragment: str) -> None:
    element = joint("j", "revolute", "a", "b")
    element = element.replace('type="revolute"', "" if kind is None else f'type="{kind}"')
    raises_invalid(rf"joint 'j' has {fragment}", urdf_robot("r", links("a", "b") + element))


def test_mimic_joint_on_path() -> None:
    body = (
        links("a", "b", "c")
        + joint("j", "revolute", "a", "b")
        + joint("k", "revolute", "b", "c", extra='<mimic joint="j" multiplier="2"/>')
    )
    raises_invalid("joint 'k' mimics joint 'j'", urdf_robot("r", body))


def test_only_fixed_joints() -> None:
    body = links("a", "b") + joint("weld", "fixed", "a", "b", limit=None)
    raises_invalid("no movable joint between 'a' and 'b'", urdf_robot("r", body))


@pytest.mark.parametrize(
    ("body", "fragment"),
    [
        (
            links("a", "b") + '<joint name="j" type="revolute"><child link="b"/></joint>',
            "joint 'j' has no <parent link=...>",
        ),
        (
            links("a", "b") + '<joint name="j" type="revolute"><parent link="a"/><child/></joint>',
            "joint 'j' has no <child link=...>",
        ),
        (
            links("a") + joint("j", "revolute", "a", "ghost"),
            "child link 'ghost', which is not defined",
        ),
        (links("a", "b") + joint("j", "revolute", "nowhere", "b"), "parent link 'nowhere'"),
        (
            links("a", "b", "c")
            + joint("j", "revolute", "a", "b")
            + joint("k", "revolute", "c", "b"),
            "link 'b' is the child of two joints, 'j' and 'k'",
        ),
        (
            links("a", "b") + joint("j", "revolute", "a", "b") + joint("j", "revolute", "b", "a"),
            "joint 'j' is defined twice",
        ),
        (links("a", "a"), "link 'a' is defined twice"),
        ("<link/>" + links("b"), "a <link> has no name"),
        (
            links("a", "b") + '<joint type="fixed"><parent link="a"/><child link="b"/></joint>',
            "a <joint> has no name",
        ),
        (
            links("a", "b", "c")
            + joint("j", "revolute", "a", "b")
            + joint("k", "revolute", "b", "c")
            + joint("back", "revolute", "c", "a"),
            "cycle through links",
        ),
        (links("a") + joint("self", "revolute", "a", "a"), "cycle through links a -> a"),
        (
            links("root", "a", "b", "c")
            + joint("j", "revolute", "root", "a")
            + joint("k", "revolute", "b", "c")
            + joint("back", "revolute", "c", "b"),
            "cycle through links",
        ),
        (links("a", "b", "c") + joint("j", "revolute", "a", "b"), "found 2 root links ['a', 'c']"),
        (
            links("a", "b")
            + joint("j", "revolute", "a", "b")
            + '<link name="c"><inertial><mass value="heavy"/></inertial></link>'
            + joint("k", "fixed", "b", "c", limit=None),
            "not a valid URDF: ValueError",
        ),
        (
            links("a", "b")
            + joint("j", "revolute", "a", "b")
            + '<link name="c"><visual/></link>'
            + joint("k", "fixed", "b", "c", limit=None),
            "not a valid URDF",
        ),
    ],
)
def test_invalid_tree(body: str, fragment: str) -> None:
    raises_invalid(re.escape(fragment), urdf_robot("r", body))


def test_file_name_in_every_message() -> None:
    error = raises_invalid("tip_link", TWO_LINK, tip_link="nope")
    assert str(error).startswith(f"URDF file {str(TWO_LINK)!r}: ")


# ------------------------------------------------------------------- security
def _passwd_lines() -> list[str]:
    try:
        text = Path("/etc/passwd").read_text()
    except OSError:
        return []
    return [line for line in text.splitlines() if line.strip()]


def _assert_no_leak(error: BaseException) -> None:
    chain: BaseException | None = error
    while chain is not None:
        message = str(chain)
        assert "root:x" not in message and "/bin/" not in message, message
        for line in _passwd_lines():
            assert line not in message
        chain = chain.__cause__ or chain.__context__


@pytest.mark.parametrize("name", ["xxe_file.urdf", "xxe_parameter.urdf"])
def test_xxe_file_is_refused(name: str) -> None:
    path = DATA / name
    error = raises_invalid(
        re.escape(f"URDF file {str(path)!r}: DTD/entity declarations are not allowed"), path
    )
    _assert_no_leak(error)


@pytest.mark.parametrize(
    "text",
    [
        '<?xml version="1.0"?>\n<!DOCTYPE robot [<!ENTITY x SYSTEM "file:///etc/passwd">]>\n'
        '<robot name="&x;"><link name="a"/></robot>',
        '<!DOCTYPE robot SYSTEM "file:///etc/passwd"><robot name="r"/>',
        # Billion laughs: internal entities only.
        '<!DOCTYPE lolz [<!ENTITY lol "lol"><!ENTITY lol2 "&lol;&lol;&lol;&lol;">]>'
        '<robot name="&lol2;"/>',
        '<!doctype robot><robot name="r"/>',
        '<!DOCTYPE robot><robot name="r"/>',
    ],
)
def test_dtd_in_text_is_refused(text: str) -> None:
    error = raises_invalid("URDF text: DTD/entity declarations are not allowed", text)
    _assert_no_leak(error)


@pytest.mark.parametrize("encoding", ["utf-16", "utf-16-be", "utf-32"])
def test_dtd_in_other_encodings_is_refused(tmp_path: Path, encoding: str) -> None:
    text = (
        f'<?xml version="1.0" encoding="{encoding.upper()}"?>\n'
        '<!DOCTYPE robot [<!ENTITY x SYSTEM "file:///etc/passwd">]>\n'
        '<robot name="&x;"><link name="a"/></robot>'
    )
    path = tmp_path / "wide.urdf"
    data = text.encode(encoding)
    if encoding == "utf-16-be":
        data = b"\xfe\xff" + data
    path.write_bytes(data)
    error = raises_invalid("DTD/entity declarations are not allowed", path)
    _assert_no_leak(error)


def test_utf16_urdf_without_dtd_loads(tmp_path: Path) -> None:
    path = tmp_path / "wide.urdf"
    path.write_bytes(
        urdf_robot("wide", SIMPLE).replace('"1.0"?>', '"1.0" encoding="UTF-16"?>').encode("utf-16")
    )
    assert from_urdf(path).names == ["j"]


def test_xacro_suffix_is_refused() -> None:
    path = DATA / "arm.urdf.xacro"
    error = raises_invalid("is a xacro file; expand it to plain URDF first", path)
    assert str(path) in str(error)


def test_xacro_content_is_refused() -> None:
    raises_invalid("uses xacro; expand it", DATA / "unexpanded_xacro.urdf")
    text = (DATA / "arm.urdf.xacro").read_text()
    raises_invalid("URDF text: uses xacro", text)
    # An undeclared xacro: prefix is not even well-formed XML; still say what it is.
    raises_invalid("uses xacro", '<robot name="r"><xacro:macro name="m"/></robot>')


def test_unused_xacro_namespace_is_fine() -> None:
    # Files generated by xacro often keep the namespace declaration.
    text = urdf_robot("r", SIMPLE).replace(
        '<robot name="r">', '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">'
    )
    assert from_urdf(text).names == ["j"]


def test_nonexistent_path(tmp_path: Path) -> None:
    path = tmp_path / "missing.urdf"
    error = raises_invalid("no such file", path)
    assert str(path) in str(error)
    raises_invalid("no such file", str(path))
    # A short string that is not XML is taken for a path.
    raises_invalid("URDF file 'robot name=r': no such file", "robot name=r")


def test_directory_path(tmp_path: Path) -> None:
    raises_invalid("not a regular file", tmp_path)


@pytest.mark.parametrize("source", [42, None, b"<robot/>"])
def test_source_of_wrong_type(source) -> None:
    raises_invalid("source must be a path to a URDF file or the URDF XML text", source)


def test_missing_yourdfpy(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "yourdfpy", None)  # makes `import yourdfpy` fail
    with pytest.raises(MissingDependencyError) as info:
        from_urdf(TWO_LINK)
    assert re.fullmatch(
        r"reading URDF: yourdfpy is not installed \(.+\); install it with: "
        r'pip install "trajkit\[urdf\]"',
        str(info.value),
    ), str(info.value)
    assert info.value.install == 'pip install "trajkit[urdf]"'


@pytest.mark.parametrize(
    "text",
    [
        '<!DOCTYPE robot [<!ENTITY x SYSTEM "file:///etc/passwd">]>'
        '<robot name="r"><link name="a">&x;</link></robot>',
        '<!DOCTYPE robot><robot name="r"/>',
    ],
)
def test_parser_backstop_refuses_dtd(monkeypatch: pytest.MonkeyPatch, text: str) -> None:
    # Should the byte scan ever miss a declaration, the parsed document is checked too.
    monkeypatch.setattr(urdf_module, "_has_declaration", lambda data: False)
    error = raises_invalid("DTD/entity declarations are not allowed", text)
    _assert_no_leak(error)


# ------------------------------------------------------------------- inertials
ENTRIES = [("x", "x", 0, 0), ("x", "y", 0, 1), ("x", "z", 0, 2), ("y", "y", 1, 1),
           ("y", "z", 1, 2), ("z", "z", 2, 2)]  # fmt: skip


def inertial_urdf(seed: int) -> str:
    """A spatial R-P-R arm whose links carry rotated, offset inertials; the last has a
    tool link fixed to it with its own mass (lumped into the link the joint moves)."""
    rng = np.random.default_rng(seed)

    def inertial() -> str:
        a, b = rng.uniform(0.01, 0.2, 2)
        c = rng.uniform(abs(a - b) + 1e-3, a + b)
        axes = rot_z(rng.uniform(-3, 3)) @ rot_y(rng.uniform(-1.5, 1.5)) @ rot_x(rng.uniform(-3, 3))
        t = axes @ np.diag([a, b, c]) @ axes.T
        xyz = " ".join(f"{v:.6f}" for v in rng.uniform(-0.2, 0.2, 3))
        rpy = " ".join(f"{v:.6f}" for v in rng.uniform(-1, 1, 3))
        return (
            f'<inertial><origin xyz="{xyz}" rpy="{rpy}"/><mass value="{rng.uniform(0.5, 4):.6f}"/>'
            "<inertia "
            + " ".join(f'i{u}{v}="{float(t[i, j])!r}"' for u, v, i, j in ENTRIES)
            + "/></inertial>"
        )

    return f"""<robot name="rpr">
  <link name="base"/>
  <link name="l1">{inertial()}</link>
  <link name="l2">{inertial()}</link>
  <link name="l3">{inertial()}</link>
  <link name="tool">{inertial()}</link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0.3" rpy="0.1 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" velocity="2" effort="80"/></joint>
  <joint name="j2" type="prismatic"><parent link="l1"/><child link="l2"/>
    <origin xyz="0.2 0.05 0.1" rpy="0 0.7 0"/><axis xyz="0.6 0 0.8"/>
    <limit lower="-0.5" upper="0.5" velocity="1" effort="200"/></joint>
  <joint name="j3" type="revolute"><parent link="l2"/><child link="l3"/>
    <origin xyz="0.3 0 0" rpy="0 0 0.4"/><axis xyz="0 1 0"/>
    <limit lower="-3" upper="3" velocity="2" effort="40"/></joint>
  <joint name="flange" type="fixed"><parent link="l3"/><child link="tool"/>
    <origin xyz="0.1 0.02 0" rpy="0.3 0.2 0.1"/></joint>
</robot>"""


@pytest.mark.parametrize("seed", range(5))
def test_urdf_inertials_give_mujocos_inverse_dynamics(seed):
    """MuJoCo reads the same file with its own URDF importer; mj_inverse is the oracle."""
    mujoco = pytest.importorskip(
        "mujoco", reason="MuJoCo is not installed: pip install 'trajkit[sim]'"
    )
    from trajkit.kinematics import inverse_dynamics

    text = inertial_urdf(seed)
    arm = from_urdf(text)
    np.testing.assert_array_equal(arm.physical.effort_limit, [80.0, 200.0, 40.0])
    model = mujoco.MjModel.from_xml_string(text)
    data = mujoco.MjData(model)
    rng = np.random.default_rng(seed + 100)
    # Inside the joint ranges: beyond them MuJoCo adds the limits' constraint forces.
    q = rng.uniform(-1.0, 1.0, (20, 3)) * [2.9, 0.49, 2.9]
    qd, qdd = rng.normal(size=(2, 20, 3))
    ours = inverse_dynamics(arm, q, qd, qdd, gravity=model.opt.gravity)
    for k in range(20):
        data.qpos[:], data.qvel[:], data.qacc[:] = q[k], qd[k], qdd[k]
        mujoco.mj_inverse(model, data)
        scale = max(1.0, np.abs(data.qfrc_inverse).max())
        # MuJoCo stores the inertias it read as principal moments in float64 after an
        # eigendecomposition: rounding only.
        np.testing.assert_allclose(ours[k], data.qfrc_inverse, rtol=0, atol=1e-9 * scale)


def test_a_fixed_links_mass_is_lumped_into_the_link_it_is_fixed_to():
    text = """<robot name="lump">
      <link name="base"/>
      <link name="arm"><inertial><mass value="2"/>
        <inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial></link>
      <link name="weight"><inertial><origin xyz="0.5 0 0"/><mass value="2"/>
        <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
      <joint name="q" type="continuous"><parent link="base"/><child link="arm"/>
        <axis xyz="0 0 1"/></joint>
      <joint name="bolt" type="fixed"><parent link="arm"/><child link="weight"/>
        <origin xyz="0.5 0 0"/></joint>
    </robot>"""
    physical = from_urdf(text).physical
    np.testing.assert_array_equal(physical.link_mass, [4.0])
    np.testing.assert_allclose(physical.center_of_mass, [[0.5, 0.0, 0.0]], rtol=0, atol=1e-15)
    # Two 2 kg points 1 m apart about their middle: 2 * 2 * 0.5² about y and z.
    np.testing.assert_allclose(physical.inertia, [np.diag([0.1, 1.1, 1.1])], rtol=0, atol=1e-15)
    assert physical.effort_limit is None  # a continuous joint without <limit>


def test_a_urdf_without_inertials_refuses_dynamics_by_name():
    from trajkit.kinematics import inverse_dynamics

    arm = from_urdf(TWO_LINK)
    np.testing.assert_array_equal(arm.physical.effort_limit, [30.0, 20.0])
    with pytest.raises(InvalidInputError, match=r"no link_mass, center_of_mass, inertia"):
        inverse_dynamics(arm, [0.0, 0.0], [0.0, 0.0], [0.0, 0.0])


@pytest.mark.parametrize(
    ("inertial", "message"),
    [
        ('<mass value="-1"/>', r"link 'arm' <inertial>: mass must be a finite number >= 0 kg"),
        ('<mass value="nan"/>', r"link 'arm' <inertial>: mass must be a finite number"),
        ('<mass value="1"/><inertia ixx="inf" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/>',
         r"link 'arm' <inertial>: origin and inertia must be finite"),
    ],
)  # fmt: skip
def test_bad_inertials_are_refused_naming_the_link(inertial, message):
    text = f"""<robot name="bad">
      <link name="base"/><link name="arm"><inertial>{inertial}</inertial></link>
      <joint name="q" type="continuous"><parent link="base"/><child link="arm"/></joint>
    </robot>"""
    with pytest.raises(InvalidInputError, match=message):
        from_urdf(text)
