"""Serial arms read from MuJoCo's MJCF files: kinematics, ranges and inertia.

:func:`from_mjcf` compiles the file with MuJoCo (the ``sim`` extra) and follows the
bodies from the first moving one to a tip, one hinge or slide joint each. Each
joint's frame sits at its anchor (MJCF's ``joint pos``) in its body's frame, so the
chain's forward kinematics are MuJoCo's own; each body's mass, centre of mass and
inertia tensor (and those of bodies welded to it) become the chain's
:class:`~trajkit.kinematics.Physical` data, so :class:`trajkit.sim.ArmScene` and
the torque limits of time-optimal timing use them. Geometry (meshes) is not
carried: trajkit's scenes draw links as capsules.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np

from trajkit._validation import FloatArray
from trajkit.errors import InvalidInputError, MissingDependencyError
from trajkit.kinematics.chain import Joint, SerialChain
from trajkit.kinematics.physical import Physical

__all__ = ["from_mjcf"]

_HINGE, _SLIDE = 3, 2  # mjtJoint


def from_mjcf(path: str | os.PathLike[str], *, tip_body: str | None = None) -> SerialChain:
    """A serial arm from an MJCF file.

    Parameters
    ----------
    path : path-like
        The MJCF (``.xml``) file; its includes and assets are found beside it.
    tip_body : str, optional
        The body the chain ends at (its frame is the tool); default the last body of
        the only branch.

    Returns
    -------
    SerialChain
        One joint per hinge (revolute) or slide (prismatic) joint from the base to
        ``tip_body``, named as in the file, with its range (``limited`` joints) and
        the bodies' inertia as ``physical`` data.

    Raises
    ------
    MissingDependencyError
        MuJoCo is not installed.
    InvalidInputError
        A file MuJoCo refuses (its message), no moving body, a branching tree with no
        ``tip_body``, a body with several joints or a ball or free joint on the way.
    """
    try:
        import mujoco
    except ImportError as exc:
        raise MissingDependencyError.absent("MJCF files", "MuJoCo", "sim", exc) from None
    source = Path(path)
    try:
        model = mujoco.MjModel.from_xml_path(str(source))
    except (ValueError, OSError) as exc:  # MuJoCo's own words: what and where
        raise InvalidInputError(f"{source}: not an MJCF MuJoCo can load ({exc})") from None
    body_kind, joint_kind = mujoco.mjtObj.mjOBJ_BODY, mujoco.mjtObj.mjOBJ_JOINT

    def name(kind: Any, k: int) -> str:  # unnamed elements get body3, joint2...
        return mujoco.mj_id2name(model, kind, k) or f"{'body' if kind == body_kind else 'joint'}{k}"

    path_bodies = _branch(model, source, tip_body, lambda k: name(body_kind, k))
    joints, frames = [], []
    pose = np.eye(4)  # the last joint's frame (or the world), as bodies are walked
    for body in path_bodies:
        pose = pose @ _body_frame(model, body)
        count, first = int(model.body_jntnum[body]), int(model.body_jntadr[body])
        if count == 0:
            continue
        kind = int(model.jnt_type[first])
        if count > 1 or kind not in (_HINGE, _SLIDE):
            raise InvalidInputError(
                f"{source}: body {name(body_kind, body)!r} moves by "
                f"{'several joints' if count > 1 else 'a ball or free joint'}: a serial arm "
                "has one hinge or slide joint per body"
            )
        anchor = np.eye(4)
        anchor[:3, 3] = model.jnt_pos[first]
        limited = bool(model.jnt_limited[first])
        lower, upper = model.jnt_range[first] if limited else (-np.inf, np.inf)
        # The file's body pose is the joint at its reference ``ref`` (qpos0): q moves the
        # joint by q - ref, trajkit's q + offset.
        reference = float(model.qpos0[model.jnt_qposadr[first]])
        joints.append(Joint(name(joint_kind, first), "revolute" if kind == _HINGE else "prismatic",
                            origin=pose @ anchor, axis=np.array(model.jnt_axis[first]),
                            lower=float(lower), upper=float(upper), offset=-reference))  # fmt: skip
        frames.append((body, anchor))
        pose = np.linalg.inv(anchor)  # the next body is placed relative to this body
    if not joints:
        raise InvalidInputError(f"{source}: no body moves by a hinge or slide joint")
    tool = pose
    chain = SerialChain(joints, tool=tool, name=source.stem)
    return chain.with_physical(_physical(model, frames, source))


def _branch(model: Any, source: Path, tip: str | None, name: Any) -> list[int]:
    """Bodies from the world's child to the tip, in order."""
    children: dict[int, list[int]] = {}
    for body in range(1, model.nbody):
        children.setdefault(int(model.body_parentid[body]), []).append(body)
    if tip is not None:
        found = [b for b in range(model.nbody) if name(b) == tip]
        if not found:
            raise InvalidInputError(f"{source}: no body named {tip!r}")
        chain, body = [], found[0]
        while body != 0:
            chain.append(body)
            body = int(model.body_parentid[body])
        return chain[::-1]
    chain, body = [], 0
    while children.get(body):
        moving = [c for c in children[body] if _moves(model, c, children)]
        if len(moving) > 1:
            raise InvalidInputError(
                f"{source}: the tree branches below body {name(body)!r} into "
                f"{[name(c) for c in moving]}; pass tip_body to choose"
            )
        if not moving:
            break
        body = moving[0]
        chain.append(body)
    return chain


def _moves(model: Any, body: int, children: dict[int, list[int]]) -> bool:
    """Whether ``body`` or a body below it has a joint."""
    stack = [body]
    while stack:
        current = stack.pop()
        if model.body_jntnum[current]:
            return True
        stack.extend(children.get(current, []))
    return False


def _body_frame(model: Any, body: int) -> FloatArray:
    from scipy.spatial.transform import Rotation  # not at import: trajkit loads fast

    frame = np.eye(4)
    w, x, y, z = model.body_quat[body]
    frame[:3, :3] = Rotation.from_quat([x, y, z, w]).as_matrix()
    frame[:3, 3] = model.body_pos[body]
    return frame


def _physical(model: Any, frames: list[tuple[int, FloatArray]], source: Path) -> Physical:
    """Each moving body's inertia, with the bodies welded to it, in its joint's frame."""
    from scipy.spatial.transform import Rotation

    moving = {body: k for k, (body, _) in enumerate(frames)}
    parts: list[list[tuple[float, FloatArray, FloatArray]]] = [[] for _ in frames]
    owner = {}  # every body: the moving body it rides on, and its pose in that body's frame
    for body in range(1, model.nbody):
        parent = int(model.body_parentid[body])
        if body in moving:
            owner[body] = (body, np.eye(4))
        elif parent in owner:
            ride, pose = owner[parent]
            owner[body] = (ride, pose @ _body_frame(model, body))
    for body, (ride, pose) in owner.items():
        mass = float(model.body_mass[body])
        if mass <= 0.0:
            continue
        k = moving[ride]
        to_joint = np.linalg.inv(frames[k][1]) @ pose  # body frame -> joint frame
        w, x, y, z = model.body_iquat[body]
        principal = to_joint[:3, :3] @ Rotation.from_quat([x, y, z, w]).as_matrix()
        tensor = principal @ np.diag(model.body_inertia[body]) @ principal.T
        centre = to_joint[:3, :3] @ model.body_ipos[body] + to_joint[:3, 3]
        parts[k].append((mass, centre, tensor))
    masses, centres, tensors = [], [], []
    for found in parts:
        total = sum(m for m, _, _ in found)
        centre = sum((m * c for m, c, _ in found), np.zeros(3)) / total if total else np.zeros(3)
        tensor = np.zeros((3, 3))
        for m, c, inertia in found:  # the parallel-axis theorem, about the common centre
            d = c - centre
            tensor += inertia + m * (d @ d * np.eye(3) - np.outer(d, d))
        masses.append(total)
        centres.append(centre)
        tensors.append(tensor)
    return Physical(link_mass=masses, center_of_mass=np.stack(centres), inertia=np.stack(tensors),
                    source=f"{source.name}: its bodies' inertia")  # fmt: skip
