"""Built-in robots: a planar 2R arm, ROS's RRBot, the 3-DOF arm of the course, and the UR5.

The 2R and 3R arms have closed-form inverse kinematics with every solution branch;
the UR5 uses the numerical solver of :class:`~trajkit.kinematics.SerialChain`.
"""

from __future__ import annotations

from abc import abstractmethod
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from trajkit._validation import finite_array, positive_scalar
from trajkit.errors import InvalidInputError, UnreachableError
from trajkit.kinematics.chain import DHRow, Joint, SerialChain, _translation
from trajkit.kinematics.dynamics import inertials_from_dh
from trajkit.kinematics.ik import IKSolution, parse_targets
from trajkit.kinematics.physical import Physical
from trajkit.rotations import homogeneous

FloatArray = NDArray[np.float64]

__all__ = ["BUILTIN", "UR5", "AnalyticChain", "Planar2R", "RRBot", "Spatial3R"]

#: How far (relative to the arm's size) a target may lie outside the workspace
#: and still count as on its boundary: rounding in the caller's own arithmetic.
_BOUNDARY_RTOL = 1e-12


class AnalyticChain(SerialChain):
    """A chain whose inverse kinematics is solved in closed form, all branches at once."""

    #: Names of the solution branches, in index order.
    branch_names: tuple[str, ...] = ()
    #: Unit of lengths in messages ("" when the arm takes any unit).
    length_unit: str = "m"

    @abstractmethod
    def _branches(self, local: FloatArray) -> tuple[FloatArray, FloatArray, str]:
        """All branches for tool positions in the base frame.

        Returns ``q`` of shape ``(m, nbranch, ndof)`` (NaN where unreachable), how far
        outside the workspace each target lies (m, 0 inside) and what bounds it.
        """

    def ik_branches(self, target: ArrayLike) -> FloatArray:
        """Every closed-form solution for tool positions (m).

        Parameters
        ----------
        target : array_like, shape (3,) or (m, 3)
            Tool positions in the world frame (a 4x4 pose gives its position).

        Returns
        -------
        ndarray, shape (nbranch, ndof) or (m, nbranch, ndof)
            Branch ``b`` is named ``branch_names[b]``; NaN where a target is unreachable.
        """
        points, _, single = parse_targets(target, True)
        q, _, _ = self._branches(self._to_base(points))
        return q[0] if single else q

    def _to_base(self, points: FloatArray) -> FloatArray:
        inverse = np.linalg.inv(self._base)
        return points @ inverse[:3, :3].T + inverse[:3, 3]

    def ik(
        self,
        target: ArrayLike,
        q_seed: ArrayLike | None = None,
        *,
        branch: int | str | None = None,
        position_only: bool = True,
        raise_on_failure: bool = True,
    ) -> IKSolution:
        """Closed-form inverse kinematics for tool positions.

        Parameters
        ----------
        target : array_like, shape (3,) or (m, 3)
            Tool positions (m) in the world frame; a 4x4 pose gives its position.
        q_seed : array_like, shape (ndof,) or (m, ndof), optional
            Without ``branch``, the branch closest to the seed is chosen; unbounded
            revolute joints are shifted by whole turns to lie near the seed.
        branch : int or str, optional
            Index or name in :attr:`branch_names` (default: nearest to ``q_seed``,
            else branch 0).
        position_only : bool
            Must be True: these arms cannot choose their tool orientation.
        raise_on_failure : bool
            Raise :class:`~trajkit.UnreachableError` for a target outside the
            workspace or the joint ranges (default); otherwise return NaN there
            with ``success`` False.

        Returns
        -------
        IKSolution
        """
        if not position_only:
            raise InvalidInputError(
                f"{type(self).__name__} sets only its tool position; call ik with "
                "position_only=True"
            )
        points, _, single = parse_targets(target, True)
        solutions, outside, bound = self._branches(self._to_base(points))
        m = points.shape[0]
        if q_seed is not None:
            seeds, _ = self.configurations(q_seed, "q_seed")
            if seeds.shape[0] not in (1, m):
                raise InvalidInputError(f"q_seed gives {seeds.shape[0]} seeds for {m} targets")
            seeds = np.broadcast_to(seeds, (m, self.ndof))
            solutions = self.wrap_near(solutions, seeds[:, np.newaxis, :])
        solutions = self._into_ranges(solutions)
        in_range = np.all((solutions >= self._lower) & (solutions <= self._upper), axis=2)
        if branch is not None:
            index = self.branch_index(branch)
            q = solutions[:, index]
            valid = in_range[:, index]
        elif q_seed is not None:
            distance = np.linalg.norm(solutions - seeds[:, np.newaxis, :], axis=2)
            distance = np.where(in_range, distance, np.inf)
            choice = np.argmin(np.nan_to_num(distance, nan=np.inf), axis=1)
            q = solutions[np.arange(m), choice]
            valid = in_range[np.arange(m), choice]
        else:
            # First branch that is inside the joint ranges.
            choice = np.argmax(in_range, axis=1)
            q = solutions[np.arange(m), choice]
            valid = in_range[np.arange(m), choice]
        success = valid & (outside == 0.0)
        if raise_on_failure and not success.all():
            worst = int(np.flatnonzero(~success)[0])
            where = "" if single else f"target {worst} "
            point = np.array2string(points[worst], precision=6)
            if outside[worst] > 0:
                unit = f" {self.length_unit}" if self.length_unit else ""
                raise UnreachableError(
                    f"{where}{point} is out of reach of {self.name}: {outside[worst]:.6g}{unit} "
                    f"beyond {bound}",
                    index=worst,
                )
            raise UnreachableError(
                f"{where}{point}: no solution of {self.name} within its joint ranges",
                index=worst,
            )
        q = np.where(success[:, np.newaxis], q, np.nan)
        error = np.where(success, self._position_error(q, points), np.inf)
        if single:
            return IKSolution(q[0], bool(success[0]), float(error[0]), 0.0, 0, "analytic")
        return IKSolution(q, success, error, np.zeros(m), 0, "analytic")

    def _position_error(self, q: FloatArray, points: FloatArray) -> FloatArray:
        ok = np.all(np.isfinite(q), axis=1)
        error = np.full(q.shape[0], np.inf)
        if ok.any():
            error[ok] = np.linalg.norm(self.fk(q[ok])[:, :3, 3] - points[ok], axis=1)
        return error

    def _into_ranges(self, solutions: FloatArray) -> FloatArray:
        """Shift bounded revolute joints by whole turns into their range where one fits."""
        bounded = self._revolute & np.isfinite(self._lower) & np.isfinite(self._upper)
        if not bounded.any():
            return solutions
        with np.errstate(invalid="ignore"):
            turns = np.ceil((self._lower - solutions) / (2 * np.pi))
            shifted = solutions + 2 * np.pi * turns
            fits = (
                bounded
                & (shifted <= self._upper)
                & ~((solutions >= self._lower) & (solutions <= self._upper))
            )
        return np.where(fits, shifted, solutions)

    def branch_index(self, branch: int | str) -> int:
        """Index of a branch given by index or by name (see :attr:`branch_names`)."""
        if isinstance(branch, str):
            if branch not in self.branch_names:
                raise InvalidInputError(
                    f"branch must be one of {list(self.branch_names)}, got {branch!r}"
                )
            return self.branch_names.index(branch)
        if not isinstance(branch, int | np.integer) or not 0 <= branch < len(self.branch_names):
            raise InvalidInputError(
                f"branch must be an index 0..{len(self.branch_names) - 1} or one of "
                f"{list(self.branch_names)}, got {branch!r}"
            )
        return int(branch)


def _clip_boundary(value: FloatArray, scale: float) -> FloatArray:
    """Clip a cosine to [-1, 1] when it passes by rounding only."""
    slack = _BOUNDARY_RTOL * max(scale, 1.0)
    return np.where(np.abs(value) <= 1.0 + slack, np.clip(value, -1.0, 1.0), value)


class Planar2R(AnalyticChain):
    """Two revolute joints about parallel z axes, links along x: the textbook planar arm.

    Parameters
    ----------
    l1, l2 : float
        Link lengths (m).
    base : array_like, shape (4, 4), optional
        Pose of the arm's base: its plane is the base's xy plane.
    axis_offsets : tuple of 3 floats
        Offsets along the joint axes (m) from base to joint 1, joint 1 to joint 2,
        and joint 2 to the tool; they shift the arm out of its plane.
    name : str

    Notes
    -----
    Branch ``"elbow_positive"`` has ``q2 >= 0``, ``"elbow_negative"`` ``q2 <= 0``.
    Targets may be given as 3-D world positions or, for convenience, as 2-D
    points ``(x, y)`` in the base plane.
    """

    branch_names = ("elbow_positive", "elbow_negative")

    def __init__(
        self,
        l1: float,
        l2: float,
        *,
        base: ArrayLike | None = None,
        axis_offsets: tuple[float, float, float] = (0.0, 0.0, 0.0),
        name: str = "planar 2R",
    ) -> None:
        self.l1 = positive_scalar("l1", l1, unit="m")
        self.l2 = positive_scalar("l2", l2, unit="m")
        a0, a1, a2 = (float(v) for v in axis_offsets)
        joints = [
            Joint("q1", "revolute", origin=_translation(z=a0)),
            Joint("q2", "revolute", origin=_translation(x=self.l1, z=a1)),
        ]
        super().__init__(joints, base=base, tool=_translation(x=self.l2, z=a2), name=name)
        self._plane_height = a0 + a1 + a2

    def ik_branches(self, target: ArrayLike) -> FloatArray:  # noqa: D102
        return super().ik_branches(self._as_points(target))

    def ik(self, target: ArrayLike, q_seed: ArrayLike | None = None, **kwargs: Any) -> IKSolution:  # noqa: D102
        return super().ik(self._as_points(target), q_seed, **kwargs)

    ik.__doc__ = AnalyticChain.ik.__doc__

    def _as_points(self, target: ArrayLike) -> FloatArray:
        array = finite_array("target", target)
        if array.ndim in (1, 2) and array.shape[-1] == 2:
            # 2-D points are coordinates in the base plane.
            plane = np.concatenate(
                [array.reshape(-1, 2), np.full((array.reshape(-1, 2).shape[0], 1), 0.0)], axis=1
            )
            plane[:, 2] = self._plane_height
            world = plane @ self._base[:3, :3].T + self._base[:3, 3]
            return world[0] if array.ndim == 1 else world
        return array

    def _branches(self, local: FloatArray) -> tuple[FloatArray, FloatArray, str]:
        l1, l2 = self.l1, self.l2
        x, y = local[:, 0], local[:, 1]
        off_plane = np.abs(local[:, 2] - self._plane_height)
        r = np.hypot(x, y)
        cos_q2 = _clip_boundary((r**2 - l1**2 - l2**2) / (2 * l1 * l2), l1 + l2)
        in_plane = off_plane <= _BOUNDARY_RTOL * max(l1 + l2, 1.0) * 10
        radial_out = np.where(
            np.abs(cos_q2) <= 1.0, 0.0, np.maximum(r - (l1 + l2), abs(l1 - l2) - r)
        )
        outside = np.where(in_plane, radial_out, np.hypot(off_plane, radial_out))
        with np.errstate(invalid="ignore"):
            q2 = np.arccos(cos_q2)
        out = np.empty((local.shape[0], 2, 2))
        for b, sign in enumerate((1.0, -1.0)):
            q2b = sign * q2
            out[:, b, 1] = q2b
            out[:, b, 0] = np.arctan2(y, x) - np.arctan2(l2 * np.sin(q2b), l1 + l2 * np.cos(q2b))
        out[outside > 0] = np.nan
        bound = f"the annulus {abs(l1 - l2):.6g} m <= r <= {l1 + l2:.6g} m in the arm's plane"
        return out, outside, bound


def RRBot() -> Planar2R:
    """The two-link RRBot of ROS/Gazebo's demos (``rrbot.xacro``), in metres.

    Joint 1 sits 1.95 m above the ground on a 2 m post; links are 0.9 m (joint to
    joint) and 0.95 m (joint 2 to the tip of link 3); both joints are continuous
    and turn about the world y axis, so the arm moves in the xz plane at
    ``y = 0.2`` m. At ``q = 0`` the arm points straight up; positive angles tip it
    toward +x.
    """
    # The base plane's x axis is world z (up), its y axis world x: rotating about
    # the plane normal (world y) tips the arm from up toward +x, as the URDF does.
    base = homogeneous(
        np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]]), [0.0, 0.0, 1.95]
    )
    arm = Planar2R(0.9, 0.95, base=base, axis_offsets=(0.1, 0.1, 0.0), name="RRBot")
    # rrbot.xacro: 1 kg links 0.1 m thick, joint damping 0.7.
    return arm.with_physical(Physical(link_mass=1.0, link_radius=0.05, damping=0.7,
                                      source="rrbot.xacro"))  # fmt: skip


class Spatial3R(AnalyticChain):
    """The 3-DOF spatial arm of the course project (seed 003), lengths in any unit.

    Joint 1 sits ``l0`` above the base and turns about the world ``-y`` axis; link
    ``l1`` runs along joint 2's axis, and joints 2 and 3 turn links ``l2`` and ``l3``.
    The tool position is::

        x = cos q1 (l2 cos q2 + l3 cos(q2 + q3)) - l1 sin q1
        y = l2 sin q2 + l3 sin(q2 + q3)
        z = sin q1 (l2 cos q2 + l3 cos(q2 + q3)) + l1 cos q1 + l0

    Branches: ``q3 >= 0`` or ``<= 0`` (elbow), and the sign of
    ``l2 cos q2 + l3 cos(q2 + q3)`` (reach forward or backward); branch 0 is the
    course's choice (``q3 = +acos``, forward).

    Parameters
    ----------
    l0, l1, l2, l3 : float
        Link lengths (default 5, 10, 8, 12 cm as in the course; any length unit).
    """

    length_unit = ""
    branch_names = ("forward_elbow_positive", "forward_elbow_negative",
                    "backward_elbow_positive", "backward_elbow_negative")  # fmt: skip

    def __init__(
        self,
        l0: float = 5.0,
        l1: float = 10.0,
        l2: float = 8.0,
        l3: float = 12.0,
        *,
        name: str = "3-DOF spatial arm",
    ) -> None:
        self.l0 = positive_scalar("l0", l0)
        self.l1 = positive_scalar("l1", l1)
        self.l2 = positive_scalar("l2", l2)
        self.l3 = positive_scalar("l3", l3)
        joints = [
            Joint("q1", "revolute", origin=_translation(z=self.l0), axis=np.array([0, -1.0, 0])),
            Joint("q2", "revolute", origin=_translation(z=self.l1)),
            Joint("q3", "revolute", origin=_translation(x=self.l2)),
        ]
        super().__init__(joints, tool=_translation(x=self.l3), name=name)

    def _branches(self, local: FloatArray) -> tuple[FloatArray, FloatArray, str]:
        l0, l1, l2, l3 = self.l0, self.l1, self.l2, self.l3
        x, y, h = local[:, 0], local[:, 1], local[:, 2] - l0
        size = l1 + l2 + l3
        cos_q3 = _clip_boundary((x**2 + y**2 + h**2 - l1**2 - l2**2 - l3**2) / (2 * l2 * l3), size)
        radial_sq = x**2 + h**2 - l1**2
        slack = _BOUNDARY_RTOL * size**2
        radial_sq = np.where(radial_sq >= -slack, np.maximum(radial_sq, 0.0), radial_sq)
        distance = np.sqrt(x**2 + y**2 + h**2)
        shell = np.maximum(distance - np.hypot(l1, l2 + l3), np.hypot(l1, abs(l2 - l3)) - distance)
        cylinder = l1 - np.hypot(x, h)
        outside = np.where(np.abs(cos_q3) <= 1.0, 0.0, np.maximum(shell, 0.0))
        outside = np.where(radial_sq < 0, np.maximum(outside, cylinder), outside)
        with np.errstate(invalid="ignore"):
            q3 = np.arccos(cos_q3)
            radial = np.sqrt(radial_sq)
        out = np.empty((local.shape[0], 4, 3))
        for b, (reach, elbow) in enumerate(((1, 1), (1, -1), (-1, 1), (-1, -1))):
            q3b = elbow * q3
            r = reach * radial
            out[:, b, 2] = q3b
            out[:, b, 1] = np.arctan2(y, r) - np.arctan2(l3 * np.sin(q3b), l2 + l3 * np.cos(q3b))
            out[:, b, 0] = np.arctan2(h, x) - np.arctan2(l1, r)
        out[outside > 0] = np.nan
        bound = (
            f"the workspace (distance from joint 1 between {np.hypot(l1, abs(l2 - l3)):.6g} "
            f"and {np.hypot(l1, l2 + l3):.6g}, at least {l1:.6g} from joint 1's axis)"
        )
        return out, outside, bound


def UR5() -> SerialChain:
    """Universal Robots UR5, standard DH parameters from the manufacturer (m, rad).

    Joint ranges are ±2π and speed limits π rad/s (180°/s), as in the UR5 data sheet.
    """
    pi = np.pi
    table = [
        DHRow(d=0.089159, alpha=pi / 2),
        DHRow(a=-0.425),
        DHRow(a=-0.39225),
        DHRow(d=0.10915, alpha=pi / 2),
        DHRow(d=0.09465, alpha=-pi / 2),
        DHRow(d=0.0823),
    ]
    table = [
        DHRow(r.a, r.alpha, r.d, r.theta, lower=-2 * pi, upper=2 * pi, velocity=pi) for r in table
    ]
    names = [
        "shoulder_pan",
        "shoulder_lift",
        "elbow",
        "wrist_1",
        "wrist_2",
        "wrist_3",
    ]
    arm = SerialChain.from_dh(table, names=names, name="UR5")
    mass = [3.7, 8.393, 2.33, 1.219, 1.219, 0.1879]
    # Centres of mass in the DH link frames, as Universal Robots publishes them for
    # dynamics (Robotics Toolbox's UR5 has the same).
    com = [[0.0, -0.02561, 0.00193], [0.2125, 0.0, 0.11336], [0.15, 0.0, 0.0265],
           [0.0, -0.0018, 0.01634], [0.0, 0.0018, 0.01634], [0.0, 0.0, -0.001159]]  # fmt: skip
    # UR publishes no inertia tensors for the UR5: its ROS description models each
    # link as a solid cylinder (radius, length in m) along the link, as here: along
    # the joint's axis (the DH frame's y, or z for the last link) or the arm (x).
    cylinders = [(0.075, 0.178, 1), (0.06, 0.425, 0), (0.06, 0.39225, 0), (0.06, 0.095, 1),
                 (0.06, 0.085, 1), (0.0375, 0.0305, 2)]  # fmt: skip
    inertia = np.zeros((6, 3, 3))
    for link, (m, (radius, length, axis)) in enumerate(zip(mass, cylinders, strict=True)):
        across = m * (3.0 * radius**2 + length**2) / 12.0
        inertia[link] = np.diag([across] * 3)
        inertia[link, axis, axis] = m * radius**2 / 2.0
    inertials = inertials_from_dh(arm, mass, com, inertia)
    return arm.with_physical(Physical(
        link_mass=mass, link_radius=0.045, effort_limit=[150.0, 150.0, 150.0, 28.0, 28.0, 28.0],
        center_of_mass=inertials.center_of_mass, inertia=inertials.inertia,
        source="Universal Robots' UR5 data (masses, centres of mass, joint torque limits) and "
        "its ROS description's cylinder inertias",
    ))  # fmt: skip


#: The arms known by name on the command line and in scenario files.
BUILTIN = {
    "rrbot": RRBot,
    "ur5": UR5,
    # The course's 3-DOF arm (seed 003) with its 5, 10, 8 and 12 cm links in metres.
    "arm3": lambda: Spatial3R(0.05, 0.10, 0.08, 0.12),
    # Seed 002's two-link arm, L1 = 1 m and L2 = 0.8 m.
    "planar2r": lambda: Planar2R(1.0, 0.8),
}
