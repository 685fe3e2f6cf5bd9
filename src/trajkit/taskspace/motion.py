"""Task-space motions: paths timed by a 1-D profile, with optional SLERP orientation.

A :class:`TaskTrajectory` is a sequence of segments. Each segment follows a
:class:`~trajkit.taskspace.paths.Path` with a time law ``u(t)`` (any trajkit 1-D
profile from 0 to 1) and turns the tool at a rate set by the same law, about one
fixed axis (SLERP), so velocity, acceleration, angular velocity and angular
acceleration all follow in closed form from the chain rule.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from trajkit._validation import choice, finite_array, finite_scalar, positive_scalar
from trajkit.curve import Segmented, check_order
from trajkit.errors import InvalidInputError
from trajkit.profiles import cubic, quintic, scurve, septic, trapezoidal
from trajkit.rotations import as_rotation_matrices, axis_rotation, rotation_error, slerp_axis
from trajkit.taskspace.paths import Line, Path
from trajkit.trajectory import Trajectory

FloatArray = NDArray[np.float64]
Profile = Literal["linear", "cubic", "quintic", "septic", "trapezoid", "scurve"]
PROFILES: tuple[str, ...] = ("linear", "cubic", "quintic", "septic", "trapezoid", "scurve")

__all__ = [
    "TaskSegment",
    "TaskState",
    "TaskTrajectory",
    "path_law",
    "through_poses",
    "timed",
]


@dataclass(frozen=True)
class TaskState:
    """Tool motion at sample times; orientation fields are None without orientation.

    Units: positions in the path's length unit (m), times in s, angles in rad.
    """

    t: FloatArray
    position: FloatArray  # (m, 3)
    velocity: FloatArray  # (m, 3)
    acceleration: FloatArray  # (m, 3)
    rotation: FloatArray | None = None  # (m, 3, 3)
    angular_velocity: FloatArray | None = None  # (m, 3)
    angular_acceleration: FloatArray | None = None  # (m, 3)

    def poses(self) -> FloatArray:
        """Homogeneous tool poses (m, 4, 4); identity rotation without orientation."""
        out = np.zeros((self.t.size, 4, 4))
        out[:, :3, :3] = np.eye(3) if self.rotation is None else self.rotation
        out[:, :3, 3] = self.position
        out[:, 3, 3] = 1.0
        return out


@dataclass(frozen=True)
class TaskSegment:
    """One path with its time law ``u(t)`` (a 1-D Trajectory from 0 to 1, starting at t=0).

    ``rotation`` is the tool orientation at ``u = 0``; it turns by ``angle * u``
    about the world-frame unit ``axis``. Without ``rotation`` the segment is
    position only.
    """

    path: Path
    law: Trajectory
    rotation: FloatArray | None = None
    axis: FloatArray | None = None
    angle: float = 0.0


def _check_law(law: Trajectory) -> Trajectory:
    if not isinstance(law, Trajectory) or law.ndof != 1:
        raise InvalidInputError("a time law must be a 1-joint trajkit.Trajectory from u=0 to u=1")
    start, end = law.position(law.start_time)[0], law.position(law.end_time)[0]
    if abs(start) > 1e-12 or abs(end - 1.0) > 1e-12:
        raise InvalidInputError(f"a time law must go from u=0 to u=1, got {start:g} to {end:g}")
    if law.start_time != 0.0:
        law = Trajectory(law.breakpoints - law.start_time, law.coefficients)
    return law


#: The longest time law (s), some 31,700 years: a septic's coefficients, 1/duration^7,
#: stay far inside float range, and past it a law's motion vanishes in its rounding.
MAX_LAW_DURATION = 1e12
#: The shortest time law (s): shorter, the joint splines' coefficients (1/duration^5)
#: overflow float64 and the error would name internals instead of the duration.
MIN_LAW_DURATION = 1e-9


def path_law(
    profile: Profile | Trajectory = "quintic",
    *,
    duration: float | None = None,
    speed_bound: float = 1.0,
    curvature_bound: float = 0.0,
    vmax: float | None = None,
    amax: float | None = None,
    jmax: float | None = None,
) -> Trajectory:
    """A time law ``u(t)`` from 0 to 1 for a path, from a profile and Cartesian limits.

    Parameters
    ----------
    profile : {"linear", "cubic", "quintic", "septic", "trapezoid", "scurve"} or Trajectory
        The shape of ``u(t)``; a 1-D Trajectory from 0 to 1 is used as given.
        ``linear`` is constant rate (a periodic curve traced uniformly).
    duration : float, optional
        Time (s) for the whole path, from 1e-9 s (:data:`MIN_LAW_DURATION`) to 1e12 s
        (:data:`MAX_LAW_DURATION`). Without it, the shortest duration the limits allow.
    speed_bound, curvature_bound : float
        Bounds on ``|dp/du|`` and ``|d²p/du²|`` over the path (see
        :attr:`Path.speed_bound`).
    vmax, amax, jmax : float, optional
        Cartesian speed (m/s), acceleration (m/s²) and jerk (m/s³) limits on the tool.

    Returns
    -------
    Trajectory
        One joint, ``u`` from 0 to 1.

    Notes
    -----
    With ``|p'| <= S`` and ``|p''| <= C``, the tool's speed is at most ``S u̇`` and
    its acceleration at most ``C u̇² + S |ü|``. On a straight path (``C = 0``)
    the limits map exactly to ``u̇ <= vmax/S``, ``|ü| <= amax/S``; on a curved
    path half of ``amax`` goes to each term, which guarantees the limit at the
    price of some time (the time-optimal parameterization does better).
    """
    if isinstance(profile, Trajectory):
        return _check_law(profile)
    # isinstance first: `array in PROFILES` compares elementwise, an ambiguous truth value.
    if not isinstance(profile, str) or profile not in PROFILES:
        raise InvalidInputError(f"profile must be one of {list(PROFILES)}, got {profile!r}")
    if duration is not None:
        duration = positive_scalar("duration", duration, unit="s")
        if duration > MAX_LAW_DURATION:
            raise InvalidInputError(
                f"duration must be at most {MAX_LAW_DURATION:g} s, got {duration:g} s (a time "
                "law's coefficients scale as 1/duration^k: longer, they lose the motion)"
            )
        if duration < MIN_LAW_DURATION:
            raise InvalidInputError(
                f"duration must be at least {MIN_LAW_DURATION:g} s, got {duration:g} s (a time "
                "law's coefficients scale as 1/duration^k: shorter, they overflow)"
            )
    limits = {"vmax": vmax, "amax": amax, "jmax": jmax}
    given = {k: positive_scalar(k, v) for k, v in limits.items() if v is not None}
    if duration is None and not given:
        raise InvalidInputError("give a duration or Cartesian limits (vmax, amax, jmax)")
    s = finite_scalar("speed_bound", speed_bound)
    c = finite_scalar("curvature_bound", curvature_bound)
    if s <= 0.0:
        raise InvalidInputError("the path has zero length: nothing to time")
    if "jmax" in given and c > 0.0:
        raise InvalidInputError(
            "a Cartesian jerk limit is supported on straight paths only; give a duration"
        )
    # Limits on u that guarantee the Cartesian ones (see Notes).
    u_limits: dict[str, float] = {}
    if "vmax" in given:
        u_limits["vmax"] = given["vmax"] / s
    if "amax" in given:
        share = 1.0 if c == 0.0 else 0.5
        u_limits["amax"] = share * given["amax"] / s
        if c > 0.0:
            cap = np.sqrt(0.5 * given["amax"] / c)
            u_limits["vmax"] = min(u_limits.get("vmax", np.inf), cap)
    if "jmax" in given:
        u_limits["jmax"] = given["jmax"] / s
    if profile == "linear":
        if duration is None:
            if "vmax" not in u_limits or set(given) - {"vmax"}:
                raise InvalidInputError("a linear law needs a duration or vmax alone")
            duration = 1.0 / u_limits["vmax"]
        return Trajectory([0.0, duration], [[[1.0 / duration]], [[0.0]]])
    if profile in ("cubic", "quintic", "septic"):
        make = {"cubic": cubic, "quintic": quintic, "septic": septic}[profile]
        return make(0.0, 1.0, duration, **u_limits)
    if profile == "trapezoid":
        if "vmax" not in u_limits or "amax" not in u_limits:
            raise InvalidInputError("a trapezoid law needs vmax and amax")
        return trapezoidal(0.0, 1.0, u_limits["vmax"], u_limits["amax"], duration=duration)
    if set(u_limits) != {"vmax", "amax", "jmax"}:
        raise InvalidInputError("an scurve law needs vmax, amax and jmax")
    return scurve(0.0, 1.0, u_limits["vmax"], u_limits["amax"], u_limits["jmax"], duration=duration)


class TaskTrajectory(Segmented):
    """Tool motion over time: segments played one after another.

    As a :class:`~trajkit.curve.Curve`, :meth:`evaluate` gives the tool position and
    its time derivatives of any order; :meth:`state` gives position to acceleration
    at once, with the orientation, angular velocity and angular acceleration. Past
    either end the times are clamped, as a :class:`~trajkit.Trajectory`'s are.

    Parameters
    ----------
    segments : sequence of TaskSegment
        Either all with orientation or none; each starts where the previous ends.
    """

    def __init__(self, segments: Sequence[TaskSegment]) -> None:
        segments = tuple(segments)
        if not segments:
            raise InvalidInputError("a task trajectory needs at least one segment")
        oriented = {s.rotation is not None for s in segments}
        if len(oriented) != 1:
            raise InvalidInputError("either every segment has an orientation or none has")
        segments = tuple(_checked_segment(i, s) for i, s in enumerate(segments))
        for i in range(1, len(segments)):
            gap = np.linalg.norm(segments[i].path.start - segments[i - 1].path.end)
            scale = max(1.0, float(np.linalg.norm(segments[i].path.start)))
            if gap > 1e-9 * scale:
                raise InvalidInputError(
                    f"segment {i + 1} starts {gap:.3g} away from where segment {i} ends"
                )
            previous, current = segments[i - 1], segments[i]
            if current.rotation is not None:
                assert previous.rotation is not None and previous.axis is not None
                end = axis_rotation(previous.axis, previous.angle) @ previous.rotation
                turn = float(np.linalg.norm(rotation_error(current.rotation, end)))
                if turn > 1e-9:
                    raise InvalidInputError(
                        f"segment {i + 1} starts turned {turn:.3g} rad from where segment {i} ends"
                    )
        self._store(segments, [s.law.duration for s in segments])

    @property
    def has_orientation(self) -> bool:
        """True when the tool orientation is prescribed."""
        return self._segments[0].rotation is not None

    def __repr__(self) -> str:
        return (
            f"TaskTrajectory(segments={len(self._segments)}, duration={self.duration:.6g} s, "
            f"orientation={self.has_orientation})"
        )

    components = (("x", "m"), ("y", "m"), ("z", "m"))

    def evaluate(self, t: ArrayLike, order: int = 0) -> FloatArray:
        """The tool position (m) or its ``order``-th time derivative (any order).

        Shape ``(3,)`` for a number ``t``, ``(n, 3)`` for an array; times outside
        ``[0, duration]`` are clamped, as in :meth:`state`.
        """
        order = check_order(order, where=" for a task trajectory")
        times = np.atleast_1d(finite_array("t", t)).reshape(-1)
        value = np.empty((times.size, 3))
        for segment, mask, local in self._pieces(times):
            value[mask] = _tool_derivatives(segment, local, order)[0][order]
        return value[0] if np.ndim(t) == 0 else value

    def state(self, t: ArrayLike) -> TaskState:
        """Position, velocity, acceleration (and orientation, ω, α) at times ``t`` (s).

        Times outside ``[0, duration]`` are clamped, so the end pose holds.
        """
        times = np.atleast_1d(finite_array("t", t)).reshape(-1)
        m = times.size
        position, velocity, acceleration = (np.empty((m, 3)) for _ in range(3))
        oriented = self.has_orientation
        if oriented:
            rotation = np.empty((m, 3, 3))
            omega, alpha = np.empty((m, 3)), np.empty((m, 3))
        for segment, mask, local in self._pieces(times):
            tool, (u, ud, udd) = _tool_derivatives(segment, local, 2)
            position[mask], velocity[mask], acceleration[mask] = tool
            if oriented:
                assert segment.rotation is not None and segment.axis is not None
                turn = axis_rotation(segment.axis, segment.angle * u)
                rotation[mask] = turn @ segment.rotation
                omega[mask] = np.outer(segment.angle * ud, segment.axis)
                alpha[mask] = np.outer(segment.angle * udd, segment.axis)
        if not oriented:
            return TaskState(times, position, velocity, acceleration)
        return TaskState(times, position, velocity, acceleration, rotation, omega, alpha)


def _tool_derivatives(
    segment: TaskSegment, local: FloatArray, highest: int
) -> tuple[list[FloatArray], list[FloatArray]]:
    """The tool position and its time derivatives up to ``highest`` along a segment.

    Returned with the law's ``u`` and its derivatives up to ``highest``, which the
    orientation reuses.

    ``p(u(t))`` differentiated by Faà di Bruno's formula: the ``n``-th derivative is
    ``sum_k p^(k)(u) B_{n,k}(u^(1), u^(2), ...)`` with the partial Bell polynomials
    ``B_{n,k}``; for ``n = 2`` that is ``p^(2) (u^(1))^2 + p^(1) u^(2)``.
    """
    law = [segment.law.evaluate(local, n)[:, 0] for n in range(highest + 1)]
    path = [segment.path.evaluate(law[0], k) for k in range(highest + 1)]
    # bell[n][k] = B_{n,k}(law[1], law[2], ...), by B_{n,k} = sum_i C(n-1, i-1)
    # law[i] B_{n-i,k-1}, with B_{0,0} = 1 and B_{n,0} = B_{0,k} = 0 otherwise.
    zero, one = np.zeros_like(law[0]), np.ones_like(law[0])
    bell = [[one] + [zero] * highest]
    for n in range(1, highest + 1):
        row = [zero] * (highest + 1)
        for k in range(1, n + 1):
            terms = (
                math.comb(n - 1, i - 1) * law[i] * bell[n - i][k - 1] for i in range(1, n - k + 2)
            )
            row[k] = sum(terms, zero)
        bell.append(row)
    derivatives = [path[0]]
    for n in range(1, highest + 1):
        derivatives.append(sum(path[k] * bell[n][k][:, np.newaxis] for k in range(n, 0, -1)))
    return derivatives, law


def _checked_segment(index: int, segment: TaskSegment) -> TaskSegment:
    """A segment with its law checked (1-D, 0 to 1, from t = 0) and its turn well formed."""
    if not isinstance(segment, TaskSegment) or not isinstance(segment.path, Path):
        raise InvalidInputError(f"segment {index + 1} must be a TaskSegment with a Path")
    law = _check_law(segment.law)
    if segment.rotation is None:
        return TaskSegment(segment.path, law)
    rotation = as_rotation_matrices(f"segment {index + 1} rotation", segment.rotation)
    axis = finite_array(f"segment {index + 1} axis", segment.axis)
    if axis.shape != (3,) or abs(float(np.linalg.norm(axis)) - 1.0) > 1e-9:
        raise InvalidInputError(f"segment {index + 1} axis must be a unit 3-vector")
    angle = float(finite_array(f"segment {index + 1} angle", segment.angle))
    return TaskSegment(segment.path, law, np.array(rotation), np.array(axis), angle)


def _orientation(
    orientation: ArrayLike | tuple[ArrayLike, ArrayLike] | None,
) -> tuple[FloatArray | None, FloatArray | None, float]:
    """(start rotation, axis, angle) from None, a fixed 3x3 rotation, or a (start, end) pair."""
    if orientation is None:
        return None, None, 0.0
    if not isinstance(orientation, tuple) and np.shape(orientation) == (2, 3, 3):
        orientation = (np.asarray(orientation)[0], np.asarray(orientation)[1])
    if isinstance(orientation, tuple):
        if len(orientation) != 2:
            raise InvalidInputError("orientation must be a 3x3 rotation or a (start, end) pair")
        start = as_rotation_matrices("orientation start", orientation[0])
        end = as_rotation_matrices("orientation end", orientation[1])
        axis, angle = slerp_axis(start, end)
        return np.array(start), axis, angle
    fixed = as_rotation_matrices("orientation", orientation)
    return np.array(fixed), np.array([1.0, 0.0, 0.0]), 0.0


def timed(
    path: Path,
    profile: Profile | Trajectory = "quintic",
    *,
    duration: float | None = None,
    vmax: float | None = None,
    amax: float | None = None,
    jmax: float | None = None,
    orientation: ArrayLike | tuple[ArrayLike, ArrayLike] | None = None,
) -> TaskTrajectory:
    """Time a path with a 1-D profile, by duration or by Cartesian limits.

    Parameters
    ----------
    path : Path
    profile : str or Trajectory
        See :func:`path_law`.
    duration : float, optional
        Time for the whole path (s).
    vmax, amax, jmax : float, optional
        Tool speed (m/s), acceleration (m/s²), jerk (m/s³) limits; without
        ``duration``, the shortest time under them.
    orientation : 3x3 rotation or (start, end) pair, optional
        A fixed tool orientation, or one turned from ``start`` to ``end`` by SLERP
        with the same time law.

    Returns
    -------
    TaskTrajectory

    Examples
    --------
    >>> from trajkit.taskspace import Line, timed
    >>> motion = timed(Line([0, -12, 20], [10, 12, 20]), "cubic", duration=10.0)
    >>> motion.state(5.0).position.round(9).tolist()
    [[5.0, 0.0, 20.0]]
    """
    if not isinstance(path, Path):
        raise InvalidInputError(f"path must be a trajkit.taskspace Path, got {type(path).__name__}")
    law = path_law(
        profile,
        duration=duration,
        speed_bound=path.speed_bound,
        curvature_bound=path.curvature_bound,
        vmax=vmax,
        amax=amax,
        jmax=jmax,
    )
    rotation, axis, angle = _orientation(orientation)
    return TaskTrajectory([TaskSegment(path, law, rotation, axis, angle)])


def through_poses(
    poses: ArrayLike,
    profile: Profile = "quintic",
    *,
    durations: ArrayLike | None = None,
    vmax: float | None = None,
    amax: float | None = None,
    wmax: float | None = None,
    alpha_max: float | None = None,
) -> TaskTrajectory:
    """Straight lines (and SLERP turns) through poses or points, stopping at each one.

    Parameters
    ----------
    poses : array_like, shape (k, 4, 4) or (k, 3)
        Tool poses, or tool positions for a position-only motion; ``k >= 2``.
    profile : {"cubic", "quintic", "septic", "trapezoid"}
        Rest-to-rest law of each segment; a trapezoid needs the speed and
        acceleration limits (with ``durations`` too, which it then stretches to).
    durations : array_like, shape (k - 1,), optional
        Time of each segment (s); otherwise the shortest under the limits.
    vmax, amax : float, optional
        Tool speed (m/s) and acceleration (m/s²) limits.
    wmax, alpha_max : float, optional
        Angular speed (rad/s) and acceleration (rad/s²) limits on the tool.

    Returns
    -------
    TaskTrajectory
        Position and orientation along each segment are driven by one law, so both
        start and stop together; the tool rests at every pose.
    """
    array = finite_array("poses", poses)
    if array.ndim == 3 and array.shape[1:] == (4, 4):
        if not np.allclose(array[:, 3], [0.0, 0.0, 0.0, 1.0]):
            raise InvalidInputError("poses must have the last row 0 0 0 1")
        points = array[:, :3, 3]
        rotations = as_rotation_matrices("poses rotation", array[:, :3, :3])
    elif array.ndim == 2 and array.shape[1] == 3:
        points, rotations = array, None
    else:
        raise InvalidInputError(f"poses must have shape (k, 4, 4) or (k, 3), got {array.shape}")
    k = points.shape[0]
    if k < 2:
        raise InvalidInputError(f"at least 2 poses are needed, got {k}")
    choice("profile", profile, ("cubic", "quintic", "septic", "trapezoid"))
    if durations is not None:
        times = finite_array("durations", durations)
        if times.shape != (k - 1,) or np.any(times <= 0):
            raise InvalidInputError(
                f"durations must be {k - 1} positive numbers (one per segment), got {times}"
            )
    elif vmax is None and amax is None and wmax is None and alpha_max is None:
        raise InvalidInputError("give durations or limits (vmax, amax, wmax, alpha_max)")
    segments = []
    for i in range(k - 1):
        line = Line(points[i], points[i + 1])
        rotation = axis = None
        angle = 0.0
        if rotations is not None:
            axis, angle = slerp_axis(rotations[i], rotations[i + 1])
            rotation = rotations[i]
        length = line.speed_bound
        if length == 0.0 and angle == 0.0:
            raise InvalidInputError(f"poses {i} and {i + 1} coincide")
        duration = None if durations is None else float(times[i])
        # u-limits from linear and angular limits; each scales u's derivatives by a constant.
        u_limits: dict[str, float] = {}
        for key, linear, angular in (("vmax", vmax, wmax), ("amax", amax, alpha_max)):
            candidates = []
            if linear is not None and length > 0:
                candidates.append(positive_scalar(key, linear) / length)
            if angular is not None and angle > 0:
                name = "wmax" if key == "vmax" else "alpha_max"
                candidates.append(positive_scalar(name, angular) / angle)
            if candidates:
                u_limits[key] = min(candidates)
        if duration is None and not u_limits:
            moving = "only turns" if length == 0.0 else "only moves"
            needed = "wmax/alpha_max" if length == 0.0 else "vmax/amax"
            raise InvalidInputError(
                f"segment {i + 1} {moving}: give {needed} or durations to time it"
            )
        law = path_law(profile, duration=duration, speed_bound=1.0, **u_limits)
        segments.append(TaskSegment(line, law, rotation, axis, angle))
    return TaskTrajectory(segments)
