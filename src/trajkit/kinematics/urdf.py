"""Serial chains from URDF robot descriptions.

:func:`from_urdf` reads a URDF file (or its XML text) with the optional
dependency `yourdfpy <https://github.com/clemense/yourdfpy>`_ and extracts the
kinematic path between two links as a :class:`~trajkit.kinematics.SerialChain`.
The kinematics, the joints' effort limits and the links' ``<inertial>`` elements
are read (for :func:`~trajkit.kinematics.inverse_dynamics`); meshes and collision
geometry are ignored and no mesh file is opened.

Files are treated as untrusted: documents that declare a DTD or entities are
refused before any parser sees them, so no external entity or DTD is ever
resolved; xacro sources must be expanded to plain URDF first.

Examples
--------
>>> from trajkit.kinematics import from_urdf
>>> arm = from_urdf('''
... <robot name="slider">
...   <link name="base"/><link name="carriage"/>
...   <joint name="x" type="prismatic">
...     <parent link="base"/><child link="carriage"/>
...     <limit lower="0" upper="0.5" velocity="0.2" effort="10"/>
...   </joint>
... </robot>''')
>>> arm.name, arm.names, arm.fk([0.25])[:3, 3].tolist()
('slider', ['x'], [0.25, 0.0, 0.0])
"""

from __future__ import annotations

import io
import math
import os
import re
from collections.abc import Container
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from trajkit.errors import InvalidInputError, MissingDependencyError
from trajkit.kinematics.chain import Joint, SerialChain
from trajkit.kinematics.physical import Physical
from trajkit.rotations import homogeneous, rpy_matrix

if TYPE_CHECKING:
    from lxml import etree

FloatArray = NDArray[np.float64]

__all__ = ["from_urdf"]

_MOVABLE = ("revolute", "continuous", "prismatic")
_KNOWN_TYPES = (*_MOVABLE, "fixed", "floating", "planar")
# DTDs and entity declarations (XXE, "billion laughs") are refused outright.
_DECLARATION = re.compile(rb"<!\s*(DOCTYPE|ENTITY)", re.IGNORECASE)
_XACRO_PREFIX = re.compile(rb"<\s*/?\s*xacro:|\sxacro:[A-Za-z_]")
_MAX_NAMES_LISTED = 12


@dataclass(frozen=True)
class _JointGeometry:
    """A joint's fixed transform and axis, read from its XML element."""

    origin: FloatArray  # (4, 4)
    axis: FloatArray  # (3,)


def from_urdf(
    source: str | os.PathLike[str],
    *,
    base_link: str | None = None,
    tip_link: str | None = None,
    name: str | None = None,
) -> SerialChain:
    """A serial chain from a URDF robot description.

    The joints on the kinematic path from ``base_link`` to ``tip_link`` become
    the chain's joints, in order. ``revolute`` and ``continuous`` joints become
    revolute joints (a continuous joint has no position limits), ``prismatic``
    joints prismatic ones. ``fixed`` joints are folded into the next movable
    joint's origin, or into the chain's tool transform after the last movable
    joint; the chain's base is the identity, i.e. poses are expressed in the
    frame of ``base_link``.

    Parameters
    ----------
    source : str or os.PathLike
        Path of a ``.urdf`` file, or the URDF XML text itself (a string whose
        first non-blank character is ``<``).
    base_link : str, optional
        Link the chain starts from (default: the root link of the tree).
    tip_link : str, optional
        Link the chain ends at; its frame is the tool frame. Default: the only
        leaf link below ``base_link``; required when the tree branches there.
    name : str, optional
        Name of the chain (default: the robot's name in the file).

    Returns
    -------
    SerialChain
        Joint origins and tool transform in metres, joint positions in rad
        (revolute) or m (prismatic), speed limits in rad/s or m/s. Limits come
        from each joint's ``<limit>``; a ``velocity`` of 0 or none means no
        speed limit (``inf``). Its ``physical`` (when the file gives them) holds
        each joint's ``effort`` limit (N·m or N) and the mass, centre of mass and
        inertia of what each joint moves: its child link and every link fixed to
        it (a link without ``<inertial>`` is massless). Moving branches off the
        path (a gripper's fingers) are not part of the chain and are left out.

    Raises
    ------
    InvalidInputError
        The file cannot be read, is not well-formed XML, declares a DTD or
        entities, is an unexpanded xacro file, is not a valid URDF tree (missing
        or unknown links, a cycle, several roots), names unknown links, has no
        path from ``base_link`` to ``tip_link``, or the path holds a joint a
        serial chain cannot represent (``floating``, ``planar``, ``mimic``) or a
        revolute/prismatic joint without ``<limit>``. The one-line message names
        the file and the problem.
    TrajkitError
        The optional dependency yourdfpy is not installed.

    Notes
    -----
    URDF origins are ``xyz`` (m) plus ``rpy`` (rad): roll, pitch and yaw about
    the fixed x, y and z axes, i.e. ``R = Rz(yaw) Ry(pitch) Rx(roll)``. A
    missing ``<axis>`` means ``1 0 0``, and missing ``lower``/``upper``
    attributes of a ``<limit>`` mean 0, as the URDF specification defines.
    """
    try:
        import yourdfpy
    except ImportError as exc:
        raise MissingDependencyError.absent("reading URDF", "yourdfpy", "urdf", exc) from None

    label, data = _read_source(source)
    root = _parse_xml(label, data)
    geometry = _check_structure(label, root)
    try:
        model = yourdfpy.URDF.load(
            io.BytesIO(_serialize(root)),
            build_scene_graph=False,
            build_collision_scene_graph=False,
            load_meshes=False,
            load_collision_meshes=False,
        )
    except Exception as exc:  # yourdfpy raises bare KeyError, AttributeError, ValueError...
        raise InvalidInputError(
            f"{label}: not a valid URDF: {_one_line(type(exc).__name__ + ': ' + str(exc))}"
        ) from exc

    robot = model.robot
    joints_by_child = {j.child: j for j in robot.joints}
    children: dict[str, list[Any]] = {link.name: [] for link in robot.links}
    for joint in robot.joints:
        children[joint.parent].append(joint)
    root_link = _root_of(label, [link.name for link in robot.links], joints_by_child)

    links = list(children)
    base = root_link if base_link is None else _known_link(label, "base_link", base_link, links)
    if tip_link is None:
        leaves = _leaves_below(base, children)
        if len(leaves) != 1:
            raise InvalidInputError(
                f"{label}: the tree branches below link {base!r} into leaf links "
                f"{_list(leaves)}; pass tip_link to choose one"
            )
        tip = leaves[0]
    else:
        tip = _known_link(label, "tip_link", tip_link, links)
    path = _path(label, base, tip, joints_by_child)

    try:
        joints, tool = _chain_joints(label, path, geometry)
        chain = SerialChain(joints, tool=tool, name=robot.name if name is None else name)
        physical = _physical(label, path, children, {link.name: link for link in robot.links},
                             geometry)  # fmt: skip
        return chain if physical is None else chain.with_physical(physical)
    except InvalidInputError as exc:
        if str(exc).startswith(label):
            raise
        raise InvalidInputError(f"{label}: {exc}") from exc


# ---------------------------------------------------------------------- reading
def _read_source(source: str | os.PathLike[str]) -> tuple[str, bytes]:
    """A label naming the source for messages, and the document's bytes."""
    if isinstance(source, str) and source.lstrip(" \t\r\n\ufeff").startswith("<"):
        return "URDF text", source.lstrip(" \t\r\n\ufeff").encode("utf-8")
    if not isinstance(source, str | os.PathLike):
        raise InvalidInputError(
            "source must be a path to a URDF file or the URDF XML text, "
            f"got {type(source).__name__}"
        )
    path = Path(source)
    label = f"URDF file {str(path)!r}"
    if path.suffix.lower() == ".xacro":
        raise InvalidInputError(
            f"{label}: is a xacro file; expand it to plain URDF first "
            "(e.g. `xacro model.urdf.xacro > model.urdf`)"
        )
    if not path.exists():
        raise InvalidInputError(f"{label}: no such file")
    if not path.is_file():
        raise InvalidInputError(f"{label}: not a regular file")
    try:
        return label, path.read_bytes()
    except OSError as exc:
        raise InvalidInputError(f"{label}: cannot be read: {exc.strerror or exc}") from exc


def _parse_xml(label: str, data: bytes) -> etree._Element:
    """The root element of a well-formed document without DTD, entities or xacro."""
    from lxml import etree

    if _has_declaration(data):
        raise InvalidInputError(f"{label}: DTD/entity declarations are not allowed")
    parser = etree.XMLParser(
        resolve_entities=False,
        no_network=True,
        load_dtd=False,
        dtd_validation=False,
        huge_tree=False,
        remove_comments=True,
        remove_pis=True,
    )
    try:
        tree = etree.fromstring(data, parser).getroottree()
    except etree.XMLSyntaxError as exc:
        if _XACRO_PREFIX.search(data):
            raise InvalidInputError(
                f"{label}: uses xacro; expand it to plain URDF first (e.g. `xacro model.xacro`)"
            ) from exc
        raise InvalidInputError(f"{label}: not well-formed XML: {_one_line(str(exc))}") from exc
    if tree.docinfo.internalDTD is not None or tree.docinfo.doctype:
        raise InvalidInputError(f"{label}: DTD/entity declarations are not allowed")
    root = tree.getroot()
    if _uses_xacro(root):
        raise InvalidInputError(
            f"{label}: uses xacro; expand it to plain URDF first (e.g. `xacro model.xacro`)"
        )
    if root.tag != "robot":
        raise InvalidInputError(
            f"{label}: the root element is <{_one_line(str(root.tag))}>, expected <robot>"
        )
    return root


def _has_declaration(data: bytes) -> bool:
    """Whether the document declares a DTD or entities, in any encoding lxml reads."""
    if _DECLARATION.search(data):
        return True
    for bom, encoding in (
        (b"\xff\xfe\x00\x00", "utf-32-le"),
        (b"\x00\x00\xfe\xff", "utf-32-be"),
        (b"\xff\xfe", "utf-16-le"),
        (b"\xfe\xff", "utf-16-be"),
    ):
        if data.startswith(bom):
            text = data[len(bom) :].decode(encoding, errors="replace")
            return _DECLARATION.search(text.encode("utf-8")) is not None
    return False


def _uses_xacro(root: etree._Element) -> bool:
    """Whether any element or attribute lives in the xacro namespace.

    Expanded files often keep an unused ``xmlns:xacro`` declaration; that is fine.
    """
    from lxml import etree

    for element in root.iter():
        if not isinstance(element.tag, str):
            continue
        names = [element.tag, *element.attrib.keys()]
        for qualified in names:
            namespace = etree.QName(qualified).namespace
            if namespace is not None and "xacro" in namespace.lower():
                return True
    return False


def _serialize(root: etree._Element) -> bytes:
    """The checked root element alone (no prolog, no DTD) as UTF-8 XML."""
    from lxml import etree

    return etree.tostring(root, encoding="utf-8", xml_declaration=True)


# -------------------------------------------------------------------- structure
def _check_structure(label: str, root: etree._Element) -> dict[str, _JointGeometry]:
    """Check names and joint references; read each joint's origin and axis."""
    if not root.get("name"):
        raise InvalidInputError(f"{label}: <robot> has no name attribute")
    links: set[str] = set()
    for element in root.findall("link"):
        links.add(_new_name(label, element, "link", links))
    geometry: dict[str, _JointGeometry] = {}
    parent_joint: dict[str, str] = {}
    for element in root.findall("joint"):
        joint = _new_name(label, element, "joint", geometry)
        for role in ("parent", "child"):
            ref = element.find(role)
            link = None if ref is None else ref.get("link")
            if not link:
                raise InvalidInputError(f"{label}: joint {joint!r} has no <{role} link=...>")
            if link not in links:
                raise InvalidInputError(
                    f"{label}: joint {joint!r} names {role} link {link!r}, which is not defined"
                )
            if role == "child":
                if link in parent_joint:
                    raise InvalidInputError(
                        f"{label}: link {link!r} is the child of two joints, "
                        f"{parent_joint[link]!r} and {joint!r}"
                    )
                parent_joint[link] = joint
        origin = element.find("origin")
        axis = element.find("axis")
        xyz = _triple(label, joint, origin, "origin", "xyz", (0.0, 0.0, 0.0))
        rpy = _triple(label, joint, origin, "origin", "rpy", (0.0, 0.0, 0.0))
        geometry[joint] = _JointGeometry(
            origin=homogeneous(rpy_matrix(rpy), xyz),
            axis=_triple(label, joint, axis, "axis", "xyz", (1.0, 0.0, 0.0)),
        )
    return geometry


def _new_name(label: str, element: etree._Element, kind: str, taken: Container[str]) -> str:
    """The ``name`` of a ``<link>`` or ``<joint>`` element, which no other one of its kind has."""
    name = element.get("name")
    if not name:
        raise InvalidInputError(f"{label}: a <{kind}> has no name attribute")
    if name in taken:
        raise InvalidInputError(f"{label}: {kind} {name!r} is defined twice")
    return name


def _triple(
    label: str,
    joint: str,
    element: etree._Element | None,
    tag: str,
    attribute: str,
    default: tuple[float, float, float],
) -> FloatArray:
    """Three finite numbers from ``<tag attribute="x y z">``, or the default."""
    text = None if element is None else element.get(attribute)
    if text is None:
        return np.array(default)
    try:
        values = [float(part) for part in text.split()]
    except ValueError:
        values = []
    if len(values) != 3 or not all(math.isfinite(v) for v in values):
        raise InvalidInputError(
            f"{label}: joint {joint!r} <{tag} {attribute}=...> must be three finite "
            f"numbers, got {_one_line(text)[:60]!r}"
        )
    return np.array(values)


def _root_of(label: str, links: list[str], joints_by_child: dict[str, Any]) -> str:
    """The root link of the tree, after checking it has no cycle and a single root."""
    for link in links:
        visited = [link]
        current = link
        while current in joints_by_child:
            current = joints_by_child[current].parent
            if current in visited:
                cycle = [*visited[visited.index(current) :], current]
                raise InvalidInputError(
                    f"{label}: the joints form a cycle through links {' -> '.join(cycle)}"
                )
            visited.append(current)
    roots = [link for link in links if link not in joints_by_child]
    if len(roots) != 1:
        raise InvalidInputError(
            f"{label}: a URDF must be one tree with a single root link, found "
            f"{len(roots)} root links {_list(roots)}"
        )
    return roots[0]


def _known_link(label: str, role: str, link: str, links: list[str]) -> str:
    if link not in links:
        raise InvalidInputError(
            f"{label}: {role} {link!r} is not a link of the robot (links: {_list(links)})"
        )
    return link


def _leaves_below(base: str, children: dict[str, list[Any]]) -> list[str]:
    leaves, stack = [], [base]
    while stack:
        link = stack.pop()
        below = children[link]
        if not below:
            leaves.append(link)
        stack.extend(joint.child for joint in reversed(below))
    return leaves


def _path(label: str, base: str, tip: str, joints_by_child: dict[str, Any]) -> list[Any]:
    """The joints from ``base`` down to ``tip``, in order."""
    if base == tip:
        raise InvalidInputError(f"{label}: base_link and tip_link are both {base!r}")
    path = []
    link = tip
    while link != base:
        joint = joints_by_child.get(link)
        if joint is None:
            raise InvalidInputError(
                f"{label}: there is no kinematic path from base_link {base!r} down to "
                f"tip_link {tip!r} (tip_link is not below base_link)"
            )
        path.append(joint)
        link = joint.parent
    return path[::-1]


# ------------------------------------------------------------------------ chain
def _chain_joints(
    label: str, path: list[Any], geometry: dict[str, _JointGeometry]
) -> tuple[list[Joint], FloatArray]:
    """Chain joints along ``path`` with fixed joints folded in, and the tool transform."""
    joints: list[Joint] = []
    pending = np.eye(4)  # fixed transform carried to the next movable joint
    for urdf_joint in path:
        joint_name, kind = urdf_joint.name, urdf_joint.type
        where = f"{label}: joint {joint_name!r}"
        if kind not in _KNOWN_TYPES:
            shown = "no type attribute" if kind is None else f"unknown type {kind!r}"
            raise InvalidInputError(f"{where} has {shown}")
        if kind not in (*_MOVABLE, "fixed"):
            raise InvalidInputError(
                f"{where} is {kind!r}; a serial chain takes only revolute, continuous, "
                "prismatic and fixed joints"
            )
        shape = geometry[joint_name]
        if kind == "fixed":
            pending = pending @ shape.origin
            continue
        if urdf_joint.mimic is not None:
            raise InvalidInputError(
                f"{where} mimics joint {urdf_joint.mimic.joint!r}; mimic joints are not supported"
            )
        limit = urdf_joint.limit
        if limit is None and kind != "continuous":
            raise InvalidInputError(
                f"{where} is {kind} but has no <limit>, which URDF requires for "
                "revolute and prismatic joints"
            )
        if kind == "continuous":
            lower, upper = -np.inf, np.inf
        else:
            # URDF: missing lower/upper attributes default to 0.
            lower = 0.0 if limit.lower is None else float(limit.lower)
            upper = 0.0 if limit.upper is None else float(limit.upper)
            if not lower < upper:
                raise InvalidInputError(
                    f"{where}: <limit> lower {lower} must be below upper {upper} "
                    "(missing values count as 0)"
                )
        velocity = np.inf
        if limit is not None and limit.velocity is not None:
            velocity = float(limit.velocity)
            if velocity < 0 or math.isnan(velocity):
                raise InvalidInputError(f"{where}: <limit> velocity must be >= 0, got {velocity}")
            if velocity == 0:
                velocity = np.inf
        joints.append(
            Joint(
                joint_name,
                "prismatic" if kind == "prismatic" else "revolute",
                origin=pending @ shape.origin,
                axis=shape.axis,
                lower=lower,
                upper=upper,
                velocity=velocity,
            )
        )
        pending = np.eye(4)
    if not joints:
        first, last = path[0].parent, path[-1].child
        raise InvalidInputError(f"{label}: no movable joint between {first!r} and {last!r}")
    return joints, pending


def _physical(
    label: str,
    path: list[Any],
    children: dict[str, list[Any]],
    links: dict[str, Any],
    geometry: dict[str, _JointGeometry],
) -> Physical | None:
    """Effort limits and lumped inertial data of the links each movable joint moves.

    None when the file gives neither.
    """
    movable = [j for j in path if j.type in _MOVABLE]
    efforts = [None if j.limit is None else j.limit.effort for j in movable]
    lumped = [_lumped(label, j.child, children, links, geometry) for j in movable]
    has_effort = all(e is not None and e > 0 for e in efforts)
    has_inertia = any(part is not None for part in lumped)
    if not has_effort and not has_inertia:
        return None
    values: dict[str, Any] = {"source": f"{label}: <limit effort> and <inertial> elements"}
    if has_effort:
        values["effort_limit"] = [float(e) for e in efforts]
    if has_inertia:
        zero = (0.0, np.zeros(3), np.zeros((3, 3)))
        mass, com, inertia = zip(*(zero if part is None else part for part in lumped), strict=True)
        values.update(link_mass=list(mass), center_of_mass=np.stack(com),
                      inertia=np.stack(inertia))  # fmt: skip
    return Physical(**values)


def _lumped(
    label: str,
    link: str,
    children: dict[str, list[Any]],
    links: dict[str, Any],
    geometry: dict[str, _JointGeometry],
) -> tuple[float, FloatArray, FloatArray] | None:
    """Mass, centre of mass and inertia about it of ``link`` and all links fixed to it.

    In ``link``'s frame; None when none of them has an ``<inertial>``.
    """
    parts = []  # (mass, centre in link's frame, inertia about it in link's frame)
    stack = [(link, np.eye(4))]
    while stack:
        name, pose = stack.pop()
        inertial = links[name].inertial
        if inertial is not None:
            parts.append(_inertial_in(label, name, inertial, pose))
        for joint in children[name]:
            if joint.type == "fixed":
                stack.append((joint.child, pose @ geometry[joint.name].origin))
    if not parts:
        return None
    masses = np.array([m for m, _, _ in parts])
    total = float(masses.sum())
    centres = np.stack([c for _, c, _ in parts])
    centre = masses @ centres / total if total > 0 else np.zeros(3)
    inertia = np.zeros((3, 3))
    for m, c, tensor in parts:
        d = c - centre  # the parallel-axis theorem, about the common centre
        inertia += tensor + m * (d @ d * np.eye(3) - np.outer(d, d))
    return total, centre, inertia


def _inertial_in(
    label: str, link: str, inertial: Any, pose: FloatArray
) -> tuple[float, FloatArray, FloatArray]:
    """One ``<inertial>``, checked, moved into the frame ``pose`` is relative to."""
    where = f"{label}: link {link!r} <inertial>"
    mass = 0.0 if inertial.mass is None else float(inertial.mass)
    if not math.isfinite(mass) or mass < 0:
        raise InvalidInputError(f"{where}: mass must be a finite number >= 0 kg, got {mass}")
    origin = np.eye(4) if inertial.origin is None else np.asarray(inertial.origin, dtype=float)
    tensor = np.zeros((3, 3)) if inertial.inertia is None else np.asarray(inertial.inertia, float)
    if not (np.all(np.isfinite(origin)) and np.all(np.isfinite(tensor))):
        raise InvalidInputError(f"{where}: origin and inertia must be finite numbers")
    frame = pose @ origin
    rotation = frame[:3, :3]
    return mass, frame[:3, 3], rotation @ tensor @ rotation.T


# ---------------------------------------------------------------------- helpers
def _list(names: list[str]) -> str:
    shown = ", ".join(repr(n) for n in names[:_MAX_NAMES_LISTED])
    more = len(names) - _MAX_NAMES_LISTED
    return f"[{shown}{f', ... {more} more' if more > 0 else ''}]"


def _one_line(text: str) -> str:
    return " ".join(text.split())
