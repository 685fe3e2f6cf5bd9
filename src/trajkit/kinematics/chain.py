"""Serial kinematic chains: joints, Denavit–Hartenberg tables, forward kinematics, Jacobians.

A chain is a list of :class:`Joint` s. Each joint has a fixed ``origin`` transform
from the previous joint's frame (or the base) and moves along or about its
``axis`` in its own frame, as in URDF. Standard and modified DH tables are
converted to this form, so every chain shares one forward-kinematics code path,
evaluated for a whole batch of configurations at once.

Jacobians are geometric, in the base (world) frame, with the linear rows first:
``[v; ω] = J(q) q̇``, the convention of Robotics Toolbox's ``jacob0``.
"""

from __future__ import annotations

import copy
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Literal, Self

import numpy as np
from numpy.typing import ArrayLike, NDArray

from trajkit._validation import finite_array
from trajkit.errors import InvalidInputError
from trajkit.kinematics.physical import Physical
from trajkit.limits import Limits
from trajkit.rotations import axis_rotation, cross_columns, homogeneous

if TYPE_CHECKING:
    from trajkit.kinematics.ik import IKSolution

FloatArray = NDArray[np.float64]
JointKind = Literal["revolute", "prismatic"]

__all__ = ["DHRow", "Joint", "SerialChain"]


@dataclass(frozen=True)
class Joint:
    """One joint of a serial chain.

    Parameters
    ----------
    name : str
    kind : {"revolute", "prismatic"}
    origin : array_like, shape (4, 4)
        Fixed transform from the parent frame to this joint's frame at ``q = 0``.
    axis : array_like, shape (3,)
        Unit axis of motion in the joint's frame.
    lower, upper : float
        Position range (rad or m); ``-inf``/``inf`` for none (a continuous joint).
    velocity : float
        Speed limit (rad/s or m/s); ``inf`` for none.
    offset : float
        Added to the joint variable before it moves the joint (rad or m), as the
        constant ``θ`` or ``d`` of a DH row.
    """

    name: str
    kind: JointKind
    origin: FloatArray = field(default_factory=lambda: np.eye(4))
    axis: FloatArray = field(default_factory=lambda: np.array([0.0, 0.0, 1.0]))
    lower: float = -np.inf
    upper: float = np.inf
    velocity: float = np.inf
    offset: float = 0.0

    def __post_init__(self) -> None:
        if self.kind not in ("revolute", "prismatic"):
            raise InvalidInputError(
                f"joint {self.name!r}: kind must be 'revolute' or 'prismatic', got {self.kind!r}"
            )
        origin = _transform(f"joint {self.name!r} origin", self.origin)
        axis = finite_array(f"joint {self.name!r} axis", self.axis)
        norm = float(np.linalg.norm(axis)) if axis.shape == (3,) else 0.0
        if norm == 0.0:
            raise InvalidInputError(
                f"joint {self.name!r} axis must be a non-zero 3-vector, got {axis.tolist()}"
            )
        for name in ("lower", "upper", "velocity"):
            if np.isnan(getattr(self, name)):
                raise InvalidInputError(f"joint {self.name!r} {name} is NaN")
        if not self.lower < self.upper:
            raise InvalidInputError(
                f"joint {self.name!r}: lower limit {self.lower} must be below upper {self.upper}"
            )
        if not self.velocity > 0:
            raise InvalidInputError(
                f"joint {self.name!r}: velocity limit must be > 0, got {self.velocity}"
            )
        object.__setattr__(self, "origin", np.array(origin))
        object.__setattr__(self, "axis", np.array(axis) / norm)
        object.__setattr__(
            self, "offset", float(finite_array(f"joint {self.name!r} offset", self.offset))
        )

    @property
    def revolute(self) -> bool:
        """True for a revolute (or continuous) joint."""
        return self.kind == "revolute"


@dataclass(frozen=True)
class DHRow:
    """One row of a Denavit–Hartenberg table (lengths in m, angles in rad).

    For a revolute joint ``theta`` is the joint's zero offset and ``d`` is fixed;
    for a prismatic joint ``d`` is the offset and ``theta`` is fixed.
    """

    a: float = 0.0
    alpha: float = 0.0
    d: float = 0.0
    theta: float = 0.0
    kind: JointKind = "revolute"
    lower: float = -np.inf
    upper: float = np.inf
    velocity: float = np.inf


def _rot_x(angle: float) -> FloatArray:
    return homogeneous(axis_rotation(np.array([1.0, 0.0, 0.0]), angle))


def _rot_z(angle: float) -> FloatArray:
    return homogeneous(axis_rotation(np.array([0.0, 0.0, 1.0]), angle))


def _translation(x: float = 0.0, y: float = 0.0, z: float = 0.0) -> FloatArray:
    return homogeneous(translation=[x, y, z])


class SerialChain:
    """A serial chain of revolute and prismatic joints.

    Parameters
    ----------
    joints : sequence of Joint
    base : array_like, shape (4, 4), optional
        Pose of the chain's base in the world frame.
    tool : array_like, shape (4, 4), optional
        Fixed transform from the last joint's frame to the tool (end effector).
    name : str
    """

    def __init__(
        self,
        joints: Sequence[Joint],
        *,
        base: ArrayLike | None = None,
        tool: ArrayLike | None = None,
        name: str = "chain",
    ) -> None:
        joints = tuple(joints)
        if not joints:
            raise InvalidInputError("a chain needs at least one joint")
        if not all(isinstance(j, Joint) for j in joints):
            raise InvalidInputError("joints must be trajkit.kinematics.Joint objects")
        names = [j.name for j in joints]
        if len(set(names)) != len(names):
            raise InvalidInputError(f"joint names must be unique, got {names}")
        self._joints = joints
        self._base = _transform("base", base)
        self._tool = _transform("tool", tool)
        self.name = name
        self._origins = np.stack([j.origin for j in joints])
        self._axes = np.stack([j.axis for j in joints])
        self._revolute = np.array([j.revolute for j in joints])
        self._offsets = np.array([j.offset for j in joints])
        self._lower = np.array([j.lower for j in joints])
        self._upper = np.array([j.upper for j in joints])
        self._velocity = np.array([j.velocity for j in joints])
        self._local = [_local_terms(j) for j in joints]

    # ----------------------------------------------------------------- description
    @classmethod
    def from_dh(
        cls,
        rows: Sequence[DHRow],
        *,
        convention: Literal["standard", "modified"] = "standard",
        base: ArrayLike | None = None,
        tool: ArrayLike | None = None,
        names: Sequence[str] | None = None,
        name: str = "chain",
    ) -> SerialChain:
        """Build a chain from a Denavit–Hartenberg table.

        Parameters
        ----------
        rows : sequence of DHRow
        convention : {"standard", "modified"}
            ``standard`` (Denavit–Hartenberg): ``Rz(θ) Tz(d) Tx(a) Rx(α)`` per row;
            ``modified`` (Craig): ``Rx(α) Tx(a) Rz(θ) Tz(d)``.
        base, tool : array_like, shape (4, 4), optional
        names : sequence of str, optional
            Joint names (default ``q1``, ``q2``...).
        name : str

        Returns
        -------
        SerialChain
        """
        rows = tuple(rows)
        if convention not in ("standard", "modified"):
            raise InvalidInputError(
                f"convention must be 'standard' or 'modified', got {convention!r}"
            )
        if not rows or not all(isinstance(r, DHRow) for r in rows):
            raise InvalidInputError("rows must be a non-empty sequence of DHRow")
        names = list(names) if names is not None else [f"q{i + 1}" for i in range(len(rows))]
        if len(names) != len(rows):
            raise InvalidInputError(f"{len(names)} names for {len(rows)} DH rows")
        for i, row in enumerate(rows):
            finite_array(f"DH row {i + 1}", [row.a, row.alpha, row.d, row.theta])
        # The joint moves along/about its own z; the rest of each row is a fixed
        # transform. Rz(θ) and Tz(d) commute, so the fixed part is split around it.
        joints = []
        pending = np.eye(4)  # fixed transform carried to the next joint's origin
        for i, row in enumerate(rows):
            offset = row.theta if row.kind == "revolute" else row.d
            if convention == "standard":
                origin = pending
                if row.kind == "revolute":
                    after = _translation(z=row.d) @ _translation(x=row.a) @ _rot_x(row.alpha)
                else:
                    after = _rot_z(row.theta) @ _translation(x=row.a) @ _rot_x(row.alpha)
            else:
                origin = pending @ _rot_x(row.alpha) @ _translation(x=row.a)
                if row.kind == "revolute":
                    origin = origin @ _translation(z=row.d)
                else:
                    origin = origin @ _rot_z(row.theta)
                after = np.eye(4)
            joints.append(
                Joint(
                    names[i],
                    row.kind,
                    origin=origin,
                    lower=row.lower,
                    upper=row.upper,
                    velocity=row.velocity,
                    offset=offset,
                )
            )
            pending = after
        tool_matrix = pending if tool is None else pending @ _transform("tool", tool)
        return cls(joints, base=base, tool=tool_matrix, name=name)

    @property
    def joints(self) -> tuple[Joint, ...]:
        """The joints, base to tool."""
        return self._joints

    @property
    def physical(self) -> Physical | None:
        """The arm's masses, sizes and friction, if its description gives them."""
        return getattr(self, "_physical", None)

    def with_physical(self, physical: Physical) -> Self:
        """A copy of the chain that carries ``physical`` (its kinematics unchanged)."""
        if not isinstance(physical, Physical):
            raise InvalidInputError(
                f"physical must be a trajkit.kinematics.Physical, got {type(physical).__name__}"
            )
        twin = copy.copy(self)
        twin._physical = physical
        return twin

    @property
    def ndof(self) -> int:
        """Number of joints."""
        return len(self._joints)

    @property
    def names(self) -> list[str]:
        """Joint names."""
        return [j.name for j in self._joints]

    @property
    def base(self) -> FloatArray:
        """Pose of the base in the world frame, 4x4 (a copy)."""
        return self._base.copy()

    @property
    def tool(self) -> FloatArray:
        """Transform from the last joint frame to the tool, 4x4 (a copy)."""
        return self._tool.copy()

    @property
    def revolute(self) -> NDArray[np.bool_]:
        """Per joint: True for revolute, False for prismatic."""
        return self._revolute.copy()

    @property
    def continuous(self) -> NDArray[np.bool_]:
        """Per joint: True for a revolute joint without any position limit.

        Only these may be moved by whole turns: the same joint angle modulo 2π.
        """
        return self._revolute & np.isinf(self._lower) & np.isinf(self._upper)

    def wrap_near(self, q: ArrayLike, reference: ArrayLike) -> FloatArray:
        """``q`` with continuous joints moved by whole turns to within π of ``reference``.

        Arrays broadcast against each other, joints on the last axis (rad); the
        other joints are returned unchanged.
        """
        q = np.asarray(q, dtype=np.float64)
        turns = np.round((q - reference) / (2 * np.pi))
        return np.where(self.continuous, q - 2 * np.pi * turns, q)

    @property
    def lower(self) -> FloatArray:
        """Lower position limits (rad or m; ``-inf`` for none)."""
        return self._lower.copy()

    @property
    def upper(self) -> FloatArray:
        """Upper position limits (rad or m; ``inf`` for none)."""
        return self._upper.copy()

    @property
    def velocity_limits(self) -> FloatArray:
        """Speed limits (rad/s or m/s; ``inf`` for none)."""
        return self._velocity.copy()

    def limits(self) -> Limits:
        """The chain's position and velocity limits as :class:`~trajkit.Limits`.

        Joints without a limit get an unbounded range; the velocity limit is
        left out unless every joint has one.
        """
        velocity = self._velocity if np.all(np.isfinite(self._velocity)) else None
        return Limits(position=(self._lower, self._upper), velocity=velocity)

    def reach(self) -> float:
        """An upper bound on the distance from the first joint to the tool (m).

        The sum of the fixed offsets along the chain; prismatic joints add the
        largest magnitude of their offset plus range (``inf`` when unbounded).
        """
        lengths = np.linalg.norm(self._origins[1:, :3, 3], axis=1).sum()
        lengths += np.linalg.norm(self._tool[:3, 3])
        # A slider moves its axis by offset + q, q within its range.
        offsets = self._offsets
        travel = np.where(
            self._revolute,
            0.0,
            np.maximum(np.abs(self._lower + offsets), np.abs(self._upper + offsets)),
        )
        return float(lengths + travel.sum())

    def __repr__(self) -> str:
        kinds = "".join("R" if r else "P" for r in self._revolute)
        return f"{type(self).__name__}(name={self.name!r}, joints={kinds})"

    # ------------------------------------------------------------------ kinematics
    def configurations(self, q: ArrayLike, name: str = "q") -> tuple[FloatArray, bool]:
        """``q`` as an ``(m, ndof)`` array, and whether a single configuration was given."""
        array = finite_array(name, q)
        if array.ndim == 1 and array.shape[0] == self.ndof:
            return array[np.newaxis, :], True
        if array.ndim == 2 and array.shape[1] == self.ndof:
            return array, False
        raise InvalidInputError(
            f"{name} must have shape ({self.ndof},) or (m, {self.ndof}) for this "
            f"{self.ndof}-joint chain, got shape {array.shape}"
        )

    def _pass(self, q: FloatArray, *, keep_rotations: bool = False) -> _ChainPass:
        """One batched pass from base to tool for configurations ``q`` (m, ndof).

        Joint rotations are stored only when asked for (drawing needs them; FK,
        Jacobians and IK do not).
        """
        m, n = q.shape[0], self.ndof
        value = np.ascontiguousarray((q + self._offsets).T)
        sines, versines = np.sin(value), 1.0 - np.cos(value)
        rotation = np.broadcast_to(self._base[:3, :3, np.newaxis], (3, 3, m))
        position = np.broadcast_to(self._base[:3, 3, np.newaxis], (3, m))
        rotations = np.empty((n, 3, 3, m)) if keep_rotations else None
        positions = np.empty((n, 3, m))
        axes = np.empty((n, 3, m))
        for j in range(n):
            fixed, k_term, k2_term, offset_and_axis = self._local[j]
            # Joint origin and axis in the world frame, in one product.
            moved = rotation[:, :, np.newaxis, :] * offset_and_axis[np.newaxis, :, :, np.newaxis]
            moved = moved.sum(axis=1)
            positions[j] = position + moved[:, 0]
            axes[j] = moved[:, 1]
            if self._revolute[j]:
                local = (fixed[..., np.newaxis] + sines[j] * k_term[..., np.newaxis]) + versines[
                    j
                ] * k2_term[..., np.newaxis]
                position = positions[j]
            else:
                local = fixed[..., np.newaxis]
                position = positions[j] + axes[j] * value[j]
            rotation = _multiply(rotation, local)
            if rotations is not None:
                rotations[j] = rotation
        tool_position = position + _apply(rotation, self._tool[:3, 3])
        tool_rotation = _multiply(rotation, self._tool[:3, :3, np.newaxis])
        return _ChainPass(rotations, positions, axes, tool_rotation, tool_position)

    def fk(self, q: ArrayLike) -> FloatArray:
        """Tool pose in the world frame for each configuration.

        Parameters
        ----------
        q : array_like, shape (ndof,) or (m, ndof)
            Joint positions (rad or m).

        Returns
        -------
        ndarray, shape (4, 4) or (m, 4, 4)
            Homogeneous transforms.
        """
        configs, single = self.configurations(q)
        chain_pass = self._pass(configs)
        tool = _homogeneous_stack(chain_pass.tool_rotation, chain_pass.tool_position)
        return tool[0] if single else tool

    def frames(self, q: ArrayLike) -> FloatArray:
        """Every frame along the chain, for drawing: base, each joint, tool.

        Returns
        -------
        ndarray, shape (ndof + 2, 4, 4) or (m, ndof + 2, 4, 4)
            The base pose; each joint's frame, at the joint's position and turned
            by the joint's own motion; the tool pose.
        """
        configs, single = self.configurations(q)
        chain_pass = self._pass(configs, keep_rotations=True)
        assert chain_pass.rotations is not None
        m = configs.shape[0]
        joints = _homogeneous_stack(
            chain_pass.rotations.transpose(1, 2, 0, 3).reshape(3, 3, -1),
            chain_pass.positions.transpose(1, 0, 2).reshape(3, -1),
        )
        joints = joints.reshape(self.ndof, m, 4, 4).transpose(1, 0, 2, 3)
        tool = _homogeneous_stack(chain_pass.tool_rotation, chain_pass.tool_position)
        base = np.broadcast_to(self._base, (m, 1, 4, 4))
        out = np.concatenate([base, joints, tool[:, np.newaxis]], axis=1)
        return out[0] if single else out

    def points(self, q: ArrayLike) -> FloatArray:
        """Positions of the base, each joint and the tool (m), shape ``(..., ndof + 2, 3)``."""
        return self.frames(q)[..., :3, 3]

    def _jacobian_of(self, chain_pass: _ChainPass) -> FloatArray:
        """Geometric Jacobian (m, 6, ndof) from a pass along the chain."""
        z, p = chain_pass.axes, chain_pass.positions
        arm = chain_pass.tool_position[np.newaxis] - p
        rev = self._revolute[:, np.newaxis, np.newaxis]
        linear = np.where(rev, cross_columns(z, arm), z)
        angular = np.where(rev, z, 0.0)
        return np.concatenate([linear, angular], axis=1).transpose(2, 1, 0)

    def jacobian(self, q: ArrayLike) -> FloatArray:
        """Geometric Jacobian in the world frame, linear rows first.

        Parameters
        ----------
        q : array_like, shape (ndof,) or (m, ndof)

        Returns
        -------
        ndarray, shape (6, ndof) or (m, 6, ndof)
            ``[v; ω] = J q̇`` with ``v`` the tool origin's velocity (m/s) and
            ``ω`` its angular velocity (rad/s), both in the world frame.
        """
        configs, single = self.configurations(q)
        jacobian = self._jacobian_of(self._pass(configs))
        return jacobian[0] if single else jacobian

    def fk_and_jacobian(self, q: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """Tool poses and Jacobians from one pass along the chain.

        See :meth:`fk` and :meth:`jacobian`; this costs little more than either.
        """
        configs, single = self.configurations(q)
        chain_pass = self._pass(configs)
        tool = _homogeneous_stack(chain_pass.tool_rotation, chain_pass.tool_position)
        jacobian = self._jacobian_of(chain_pass)
        return (tool[0], jacobian[0]) if single else (tool, jacobian)

    def jacobian_dot(self, q: ArrayLike, qd: ArrayLike) -> FloatArray:
        """Time derivative of the geometric Jacobian along the motion ``q̇``.

        The tool's acceleration is ``[a; α] = J q̈ + J̇ q̇``.

        Parameters
        ----------
        q, qd : array_like, shape (ndof,) or (m, ndof)
            Joint positions (rad or m) and velocities (rad/s or m/s).

        Returns
        -------
        ndarray, shape (6, ndof) or (m, 6, ndof)
        """
        configs, single = self.configurations(q)
        rates, _ = self.configurations(qd, "qd")
        if rates.shape != configs.shape:
            raise InvalidInputError(f"qd has shape {rates.shape} but q has {configs.shape}")
        chain_pass = self._pass(configs)
        z, p = chain_pass.axes, chain_pass.positions  # (ndof, 3, m)
        rates = rates.T[:, np.newaxis, :]  # (ndof, 1, m)
        rev = self._revolute[:, np.newaxis, np.newaxis]
        # Angular velocity of the link each joint axis is fixed to: the joints before it.
        spin = np.where(rev, z, 0.0) * rates
        link_rate = np.cumsum(spin, axis=0) - spin
        z_dot = cross_columns(link_rate, z)
        # Velocity of each joint's origin, from the joints before it.
        contribution = np.where(rev, -cross_columns(z, p), z) * rates
        p_dot = cross_columns(link_rate, p) + np.cumsum(contribution, axis=0) - contribution
        jacobian = self._jacobian_of(chain_pass)  # (m, 6, ndof)
        tool_velocity = np.einsum("mkj,jm->km", jacobian[:, :3], rates[:, 0, :])
        arm = chain_pass.tool_position[np.newaxis] - p
        linear = np.where(
            rev,
            cross_columns(z_dot, arm) + cross_columns(z, tool_velocity[np.newaxis] - p_dot),
            z_dot,
        )
        angular = np.where(rev, z_dot, 0.0)
        out = np.concatenate([linear, angular], axis=1).transpose(2, 1, 0)
        return out[0] if single else out

    def manipulability(
        self, q: ArrayLike, *, part: Literal["all", "position", "orientation"] = "all"
    ) -> FloatArray | float:
        """Yoshikawa's manipulability ``sqrt(det(J Jᵀ))`` of the chosen Jacobian rows.

        Parameters
        ----------
        q : array_like, shape (ndof,) or (m, ndof)
        part : {"all", "position", "orientation"}
            Which rows: all six, the linear three, or the angular three. For
            a chain with fewer joints than rows, ``sqrt(det(Jᵀ J))`` is used.
            Computed as the product of singular values.

        Returns
        -------
        float or ndarray, shape (m,)
            Zero at a singularity.
        """
        rows = _rows(part)
        configs, single = self.configurations(q)
        jacobian = self._jacobian_of(self._pass(configs))[:, rows]
        # The product of singular values equals sqrt(det(J Jᵀ)) but keeps its accuracy
        # near a singularity, where the determinant's rounding would dominate the root.
        value = np.prod(np.linalg.svd(jacobian, compute_uv=False), axis=1)
        return float(value[0]) if single else value

    # ------------------------------------------------------------------------- IK
    def ik(
        self,
        target: ArrayLike,
        q_seed: ArrayLike | None = None,
        *,
        position_only: bool = False,
        tolerance: float = 1e-10,
        max_iterations: int = 50,
        restarts: int = 30,
        raise_on_failure: bool = True,
    ) -> IKSolution:
        """Joint positions that put the tool at ``target`` (numerical, damped least squares).

        Parameters
        ----------
        target : array_like, shape (4, 4), (m, 4, 4), (3,) or (m, 3)
            Tool poses, or tool positions (m) when ``position_only``.
        q_seed : array_like, shape (ndof,) or (m, ndof), optional
            Start of the search (default: the middle of each joint's range, or 0).
        position_only : bool
            Match the tool position only.
        tolerance : float
            Converged when the position error is below ``tolerance`` times the
            chain's scale (m) and the orientation error below ``tolerance`` (rad).
        max_iterations, restarts : int
            Iterations per attempt; further attempts from random seeds (seeded,
            so results repeat).
        raise_on_failure : bool
            Raise :class:`~trajkit.UnreachableError` when a target is not reached
            (default); otherwise return with ``success`` False there.

        Returns
        -------
        IKSolution
        """
        from trajkit.kinematics.ik import solve_numerical

        return solve_numerical(
            self,
            target,
            q_seed,
            position_only=position_only,
            tolerance=tolerance,
            max_iterations=max_iterations,
            restarts=restarts,
            raise_on_failure=raise_on_failure,
        )

    def ik_path(
        self,
        targets: ArrayLike,
        q_start: ArrayLike | None = None,
        *,
        position_only: bool = False,
        tolerance: float = 1e-10,
    ) -> IKSolution:
        """IK for a sequence of nearby targets (a sampled path), on one solution branch.

        Parameters
        ----------
        targets : array_like, shape (m, 4, 4) or (m, 3)
            Tool poses, or positions (m) with ``position_only``, in path order.
        q_start : array_like, shape (ndof,), optional
            Seed of the first target; it selects the branch followed.
        position_only : bool
        tolerance : float
            As in :meth:`ik`.

        Returns
        -------
        IKSolution

        Raises
        ------
        UnreachableError
            Its ``index`` is the first target not reached.
        """
        from trajkit.kinematics.ik import solve_along_path

        return solve_along_path(
            self, targets, q_start, position_only=position_only, tolerance=tolerance
        )


@dataclass(frozen=True)
class _ChainPass:
    """Frames along a chain for m configurations, component-major (last axis m).

    ``rotations[j]`` is joint j's frame after its motion, ``positions[j]`` its
    origin and ``axes[j]`` its axis, all in the world frame.
    """

    rotations: FloatArray | None  # (ndof, 3, 3, m), when kept
    positions: FloatArray  # (ndof, 3, m)
    axes: FloatArray  # (ndof, 3, m)
    tool_rotation: FloatArray  # (3, 3, m)
    tool_position: FloatArray  # (3, m)


def _local_terms(joint: Joint) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Constant parts of ``origin @ motion(q)``, for Rodrigues' formula.

    With ``K`` the axis' cross-product matrix the joint's rotation is
    ``R_o + sin(q) R_o K + (1 - cos(q)) R_o K²``.
    """
    a = joint.axis
    k = np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])
    fixed = joint.origin[:3, :3]
    offset_and_axis = np.stack([joint.origin[:3, 3], fixed @ a], axis=1)  # (3, 2)
    return fixed, fixed @ k, fixed @ k @ k, offset_and_axis


def _multiply(a: FloatArray, b: FloatArray) -> FloatArray:
    """Products of component-major 3x3 stacks: (3, 3, m) @ (3, 3, m or 1)."""
    return (a[:, :, np.newaxis, :] * b[np.newaxis, :, :, :]).sum(axis=1)


def _apply(rotation: FloatArray, vector: FloatArray) -> FloatArray:
    """Component-major rotations (3, 3, m) applied to one constant 3-vector: (3, m)."""
    return (rotation * vector[np.newaxis, :, np.newaxis]).sum(axis=1)


def _homogeneous_stack(rotation: FloatArray, position: FloatArray) -> FloatArray:
    """(m, 4, 4) transforms from component-major rotations (3, 3, m) and positions (3, m)."""
    m = rotation.shape[-1]
    out = np.zeros((m, 4, 4))
    out[:, :3, :3] = rotation.transpose(2, 0, 1)
    out[:, :3, 3] = position.T
    out[:, 3, 3] = 1.0
    return out


def _rows(part: str) -> slice:
    if part == "all":
        return slice(0, 6)
    if part == "position":
        return slice(0, 3)
    if part == "orientation":
        return slice(3, 6)
    raise InvalidInputError(f"part must be 'all', 'position' or 'orientation', got {part!r}")


def _transform(name: str, value: ArrayLike | None) -> FloatArray:
    if value is None:
        return np.eye(4)
    matrix = finite_array(name, value)
    if matrix.shape != (4, 4):
        raise InvalidInputError(f"{name} must be a 4x4 transform, got shape {matrix.shape}")
    if not np.allclose(matrix[3], [0.0, 0.0, 0.0, 1.0]) or not np.allclose(
        matrix[:3, :3] @ matrix[:3, :3].T, np.eye(3), atol=1e-9
    ):
        raise InvalidInputError(
            f"{name} must be a rigid transform (orthonormal rotation, last row 0 0 0 1)"
        )
    return np.array(matrix)
