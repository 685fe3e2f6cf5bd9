"""Limits of a timing beyond the joints' own: actuator torque, and the tool's speed.

Along a path ``q(s)`` timed with ``u = s̈`` and ``x = ṡ²``, a joint's torque and
the tool's squared speed are affine in ``(u, x)`` at every point of the path,
with coefficients that depend on the point only::

    y(s) = A(s) u + B(s) x + C(s),      lower <= y <= upper

(torque: ``A = M q'``, ``B = M q'' + C(q, q') q'``, ``C = g(q)``; squared tool
speed: ``B = |J q'|²``). Within a grid interval ``u`` is constant and ``x`` grows
as ``x_i + 2 u σ``, so at each point ``σ`` of the interval such a bound is a row
``A u + B (x_i + 2uσ) + C``, linear in ``(x_i, u)`` like the joints' rows. Unlike
those, ``A, B, C`` are not polynomials in ``s`` (sines of the joint angles), so
no Bernstein hull bounds them between points. What is guaranteed, and how:

* the solver keeps every bound at :data:`COLLOCATION` points of each interval
  (its ends and its middle);
* the timed result is then measured: at ``samples`` points of every piece, the
  value plus one eighth of the largest second difference between neighbouring
  samples (for a function whose second derivative varies little between samples,
  the most it can rise between two of them). An interval whose measure passes a
  bound has that bound moved in by the excess and the timing solved again.

So the stated guarantee is that measure: every piece's values at its samples,
corrected for curvature, are within the bounds. :meth:`PathLimit.check` gives the
same measure for any trajectory.

A bound is a :class:`PathLimit`; :class:`TorqueLimit` and :class:`ToolLimit` are the
two kinds. They are data plus two functions each (rows along a path, values of a
motion), which the reachability solver consumes without knowing their physics.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from trajkit._validation import FloatArray, finite_array
from trajkit.errors import InfeasibleError, InvalidInputError
from trajkit.kinematics.chain import SerialChain
from trajkit.kinematics.dynamics import STANDARD_GRAVITY, inverse_dynamics, path_dynamics
from trajkit.kinematics.inertials import Inertials
from trajkit.limits import Report, Violation, compare, parse_bounds
from trajkit.tolerances import LIMIT_RTOL
from trajkit.trajectory import Extrema, Trajectory

__all__ = ["COLLOCATION", "PathLimit", "ToolLimit", "TorqueLimit"]

#: Where in each grid interval (fraction of its length) the solver keeps the bounds.
COLLOCATION = (0.0, 0.5, 1.0)
#: Directions of the polygon that stands for the tool acceleration's disc: the
#: polygon's bound is the disc's times cos(π / 16), 1.9% inside it.
_DIRECTIONS = 16
#: Samples per timed piece at which the bounds are measured.
SAMPLES = 16


class PathLimit:
    """A bound on a quantity affine in ``(s̈, ṡ²)`` along a path; see the module notes.

    Subclasses give the quantity's name, unit, components and bounds, its rows
    along a path (:meth:`rows`) and its values on a motion (:meth:`values`).
    """

    quantity: str

    def components(self) -> list[tuple[str, str]]:
        """Each component's name and unit, for messages."""
        raise NotImplementedError

    def bounds(self) -> tuple[FloatArray, FloatArray]:
        """``(lower, upper)`` per component, in its unit; ``-inf`` where unbounded."""
        raise NotImplementedError

    def rows(
        self, q: FloatArray, dq: FloatArray, ddq: FloatArray, lower: FloatArray,
        upper: FloatArray,
    ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:  # fmt: skip
        """``A, B, C, low, high``, each (n, r): ``low <= A u + B x + C <= high`` at n points.

        ``lower`` and ``upper`` (n, k) are the bounds at each point, as tightened.
        """
        raise NotImplementedError

    def values(self, q: FloatArray, qd: FloatArray, qdd: FloatArray) -> FloatArray:
        """The measured quantity (n, k) at joint states (n, ndof)."""
        raise NotImplementedError

    def check(self, trajectory: Trajectory, *, samples: int = SAMPLES) -> Report:
        """Measure a joint trajectory against this bound, as :func:`~trajkit.topp` does.

        Parameters
        ----------
        trajectory : Trajectory
            Joint positions in time, of the chain's joints.
        samples : int
            Sample intervals per piece (>= 2). Each piece's values at its samples,
            widened by one eighth of their largest second difference, are compared
            with the bounds (see the module notes).

        Returns
        -------
        Report
            As :meth:`Trajectory.check <trajkit.Trajectory.check>`'s: ``ok``, the
            violations (relative tolerance 1e-9), and per quantity (``torque``,
            ``tool speed``...) the peaks and bounds.
        """
        if not isinstance(trajectory, Trajectory):
            raise InvalidInputError(
                f"trajectory must be a trajkit.Trajectory, got {type(trajectory).__name__}"
            )
        if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)) or samples < 2:
            raise InvalidInputError(f"samples must be a whole number >= 2, got {samples!r}")
        return self.report(measure(self, trajectory, int(samples)))

    def report(self, measured: tuple[FloatArray, ...]) -> Report:
        """The :class:`~trajkit.Report` of a measure (:func:`measure`'s four arrays)."""
        high, low, when_high, when_low = measured
        lower, upper = self.bounds()
        violations: list[Violation] = []
        peaks, bounds, channels = {}, {}, {}
        for quantity, entries, labels in self.quantities():
            k = np.asarray(entries)
            top, bottom = high[:, k].argmax(axis=0), low[:, k].argmin(axis=0)
            found = Extrema(1, low[bottom, k], when_low[bottom, k], high[top, k],
                            when_high[top, k])  # fmt: skip
            peaks[quantity] = (found.minimum, found.maximum)
            bounds[quantity] = (lower[k], upper[k])
            if labels:
                channels[quantity] = labels
            violations += compare(quantity, found, lower[k], upper[k], LIMIT_RTOL, labels)
        return Report(tuple(violations), peaks, bounds, channels)

    def quantities(self) -> list[tuple[str, list[int], tuple[str, ...]]]:
        """Each quantity checked: its name, its components, and their labels (or joints)."""
        raise NotImplementedError


def measure(limit: PathLimit, trajectory: Trajectory, samples: int
            ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:  # fmt: skip
    """Per piece and component, the largest and least values with the curvature margin.

    Returns ``high``, ``low`` (pieces, k) and the times of the samples they come from.
    """
    start = trajectory.breakpoints[:-1]
    length = np.diff(trajectory.breakpoints)
    fractions = np.linspace(0.0, 1.0, samples + 1)
    t = start[:, None] + length[:, None] * fractions
    # The last sample of a piece is its own end, not the next piece's start.
    t[:, -1] = np.maximum(np.nextafter(t[:, -1], -np.inf), t[:, -2])
    flat = t.ravel()
    q, qd, qdd = (trajectory.evaluate(flat, order) for order in range(3))
    values = limit.values(q, qd, qdd).reshape(t.shape[0], samples + 1, -1)
    # Between two samples a smooth function rises at most |f''| h² / 8 above them.
    bend = np.abs(values[:, :-2] - 2.0 * values[:, 1:-1] + values[:, 2:]).max(axis=1) / 8.0
    top, bottom = values.argmax(axis=1), values.argmin(axis=1)  # (pieces, k)
    rows = np.arange(t.shape[0])[:, None]
    return (values.max(axis=1) + bend, values.min(axis=1) - bend, t[rows, top], t[rows, bottom])


def _chain(chain: object) -> SerialChain:
    if not isinstance(chain, SerialChain):
        raise InvalidInputError(
            f"chain must be a trajkit.kinematics.SerialChain, got {type(chain).__name__}"
        )
    return chain


@dataclass(frozen=True)
class TorqueLimit(PathLimit):
    """Actuator torque (force for a prismatic joint) within bounds along the path.

    Parameters
    ----------
    chain : SerialChain
        The arm whose joints the path moves, with its inertial data
        (``chain.physical``) unless ``inertials`` is given.
    limit : float, array_like or (lower, upper), optional
        Torque bound per joint (N·m, N for a prismatic joint): a magnitude
        (symmetric) or ``(lower, upper)`` with lower <= 0 <= upper. Default the
        chain's ``physical.effort_limit``.
    inertials : Inertials, optional
        The links' mass distribution; default the chain's own.
    gravity : array_like, shape (3,)
        Gravity in the world frame (m/s²), default standard gravity along -z.

    Notes
    -----
    Rigid-body torques only: no friction, rotor inertia or payload (add the payload
    to the last link's inertials).
    """

    chain: SerialChain
    limit: ArrayLike | tuple[ArrayLike, ArrayLike] | None = None
    inertials: Inertials | None = None
    gravity: ArrayLike = STANDARD_GRAVITY
    quantity: str = field(default="torque", init=False)
    _bounds: tuple[FloatArray, FloatArray] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        chain = _chain(self.chain)
        spec = self.limit
        if spec is None:
            physical = chain.physical
            spec = None if physical is None else physical.effort_limit
            if spec is None:
                raise InvalidInputError(
                    f"no torque limit given and the chain {chain.name!r} has no effort_limit "
                    "in its physical data: pass limit="
                )
        bounds = parse_bounds("torque limit", spec)
        assert bounds is not None
        for side in (bounds.lower, bounds.upper):
            if side.ndim == 1 and side.size != chain.ndof:
                raise InvalidInputError(
                    f"torque limit gives {side.size} joints but the chain {chain.name!r} has "
                    f"{chain.ndof}"
                )
        lower, upper = (np.array(side, dtype=float) for side in bounds.for_ndof(
            "torque limit", chain.ndof))  # fmt: skip
        gravity = finite_array("gravity", self.gravity, unit="m/s^2")
        if gravity.shape != (3,):
            raise InvalidInputError(f"gravity must be 3 numbers (m/s^2), got shape {gravity.shape}")
        # Refuse missing inertial data now, by name, not in the middle of a solve.
        probe = np.zeros(chain.ndof)
        inverse_dynamics(chain, probe, probe, probe, inertials=self.inertials, gravity=gravity)
        object.__setattr__(self, "gravity", gravity)
        object.__setattr__(self, "_bounds", (lower, upper))

    def components(self) -> list[tuple[str, str]]:  # noqa: D102 - see PathLimit
        chain = self.chain
        return [(f"torque of joint {name}", "N·m" if revolute else "N")
                for name, revolute in zip(chain.names, chain.revolute, strict=True)]  # fmt: skip

    def bounds(self) -> tuple[FloatArray, FloatArray]:  # noqa: D102 - see PathLimit
        return self._bounds

    def quantities(self) -> list[tuple[str, list[int], tuple[str, ...]]]:  # noqa: D102
        return [("torque", list(range(self.chain.ndof)), ())]

    def rows(  # noqa: D102 - see PathLimit.rows
        self, q: FloatArray, dq: FloatArray, ddq: FloatArray, lower: FloatArray,
        upper: FloatArray,
    ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:  # fmt: skip
        a, b, c = path_dynamics(self.chain, q, dq, ddq, inertials=self.inertials,
                                gravity=self.gravity)  # fmt: skip
        return a, b, c, lower, upper

    def values(self, q: FloatArray, qd: FloatArray, qdd: FloatArray) -> FloatArray:  # noqa: D102
        return inverse_dynamics(self.chain, q, qd, qdd, inertials=self.inertials,
                                gravity=self.gravity)  # fmt: skip

    def holding(self, q: FloatArray) -> FloatArray:
        """Torque that holds the arm still at ``q`` (n, ndof): gravity's alone."""
        still = np.zeros_like(q)
        return inverse_dynamics(self.chain, q, still, still, inertials=self.inertials,
                                gravity=self.gravity)  # fmt: skip


@dataclass(frozen=True)
class ToolLimit(PathLimit):
    """The tool's speed, acceleration or turn rate within bounds along the path.

    Parameters
    ----------
    chain : SerialChain
        The arm whose joints the path moves; the tool is its tool frame's origin.
    speed : float, optional
        Largest linear speed of the tool (m/s).
    acceleration : float, optional
        Largest norm of the tool's linear acceleration (m/s²). The solver keeps it
        through a 16-sided polygon inside the disc of allowed accelerations, so
        timings may fall 1.9% short of this bound where it alone binds.
    angular_speed : float, optional
        Largest angular speed of the tool (rad/s).
    angular_acceleration : float, optional
        Largest norm of the tool's angular acceleration (rad/s²), kept through the
        same polygon as ``acceleration``.

    At least one must be given; each > 0.
    """

    chain: SerialChain
    speed: float | None = None
    acceleration: float | None = None
    angular_speed: float | None = None
    angular_acceleration: float | None = None
    quantity: str = field(default="tool", init=False)
    _kinds: tuple[str, ...] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        _chain(self.chain)
        kinds = []
        for name, unit in _UNITS.items():
            value = getattr(self, name)
            if value is None:
                continue
            number = finite_array(f"tool {name}", value, unit=unit)
            if number.ndim != 0 or number <= 0.0:
                raise InvalidInputError(
                    f"tool {name} must be a single number > 0 ({unit}), got {value!r}"
                )
            if number < _SMALLEST:  # its square, which the rows bound, would be 0
                raise InvalidInputError(
                    f"tool {name} must be at least {_SMALLEST:.3g} {unit} (its square must "
                    f"be a normal float64), got {float(number):.3g}"
                )
            object.__setattr__(self, name, float(number))
            kinds.append(name)
        if not kinds:
            raise InvalidInputError(
                "a ToolLimit needs at least one of speed, acceleration, angular_speed, "
                "angular_acceleration"
            )
        object.__setattr__(self, "_kinds", tuple(kinds))

    def components(self) -> list[tuple[str, str]]:  # noqa: D102 - see PathLimit
        return [(f"tool {kind.replace('_', ' ')}", _UNITS[kind]) for kind in self._kinds]

    def bounds(self) -> tuple[FloatArray, FloatArray]:  # noqa: D102 - see PathLimit
        upper = np.array([getattr(self, kind) for kind in self._kinds])
        return np.full(upper.size, -np.inf), upper

    def quantities(self) -> list[tuple[str, list[int], tuple[str, ...]]]:  # noqa: D102
        return [(f"tool {kind.replace('_', ' ')}", [k], ("tool",))
                for k, kind in enumerate(self._kinds)]  # fmt: skip

    def rows(  # noqa: D102 - see PathLimit.rows
        self, q: FloatArray, dq: FloatArray, ddq: FloatArray, lower: FloatArray,
        upper: FloatArray,
    ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:  # fmt: skip
        jacobian = self.chain.jacobian(q)  # (n, 6, ndof)
        tangent = np.einsum("nkj,nj->nk", jacobian, dq)  # d(tool)/ds, linear then angular
        parts: list[tuple[FloatArray, ...]] = []
        for k, kind in enumerate(self._kinds):
            bound = np.maximum(upper[:, k], 0.0)
            if kind in ("speed", "angular_speed"):
                # |v|² = |p'|² x: a bound on x at each point, squared.
                rate = tangent[:, _ROWS[kind]]
                b = (rate**2).sum(axis=1)
                none = np.zeros_like(b)
                parts.append((none, b, none, np.full_like(b, -np.inf), bound**2))
            else:
                part = _ROWS[kind]
                parts.append(self._acceleration_rows(jacobian, q, dq, ddq, tangent[:, part],
                                                     bound, part))  # fmt: skip
        # Each part's terms are a column (speeds) or a block of columns (directions).
        return tuple(np.column_stack([part[i] for part in parts])
                     for i in range(5))  # type: ignore[return-value]  # fmt: skip

    def _acceleration_rows(
        self, jacobian: FloatArray, q: FloatArray, dq: FloatArray, ddq: FloatArray,
        linear: FloatArray, bound: FloatArray, part: slice,
    ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:  # fmt: skip
        """The polygon inside the disc ``|p' u + p'' x| <= bound`` in their plane.

        ``p`` is the tool's position (``part`` the Jacobian's linear rows) or, for
        the turn, its rotation vector's rate (the angular rows); ``linear`` is ``p'``.
        """
        curve = self._tool_acceleration(jacobian, q, dq, ddq, part)
        # An orthonormal pair spanning p' and p'' (any pair where they vanish).
        first = _unit(linear, np.array([1.0, 0.0, 0.0]))
        rest = curve - (curve * first).sum(axis=1, keepdims=True) * first
        fallback = np.cross(first, np.array([0.0, 0.0, 1.0]))
        fallback = np.where(np.linalg.norm(fallback, axis=1, keepdims=True) > 0.5, fallback,
                            np.cross(first, np.array([0.0, 1.0, 0.0])))  # fmt: skip
        second = _unit(rest, fallback)
        angle = 2.0 * np.pi * np.arange(_DIRECTIONS) / _DIRECTIONS
        directions = (
            np.cos(angle)[None, :, None] * first[:, None, :]
            + np.sin(angle)[None, :, None] * second[:, None, :]
        )  # (n, K, 3)
        on_u = np.einsum("nkd,nd->nk", directions, linear)
        on_x = np.einsum("nkd,nd->nk", directions, curve)
        high = np.repeat((bound * np.cos(np.pi / _DIRECTIONS))[:, None], _DIRECTIONS, axis=1)
        return on_u, on_x, np.zeros_like(on_u), np.full_like(on_u, -np.inf), high

    def _tool_acceleration(self, jacobian: FloatArray, q: FloatArray, rate: FloatArray,
                           second: FloatArray, part: slice) -> FloatArray:  # fmt: skip
        """``J q̈ + J̇ q̇`` (the rows ``part``): the tool's acceleration, linear or angular.

        Along a path (``q'`` and ``q''`` for ``q̇`` and ``q̈``) it is ``p''``.
        """
        jacobian_dot = self.chain.jacobian_dot(q, rate)[:, part]
        return (np.einsum("nkj,nj->nk", jacobian[:, part], second)
                + np.einsum("nkj,nj->nk", jacobian_dot, rate))  # fmt: skip

    def values(self, q: FloatArray, qd: FloatArray, qdd: FloatArray) -> FloatArray:  # noqa: D102
        jacobian = self.chain.jacobian(q)
        twist = np.einsum("nkj,nj->nk", jacobian, qd)
        out = []
        for kind in self._kinds:
            part = _ROWS[kind]
            if kind in ("speed", "angular_speed"):
                out.append(np.linalg.norm(twist[:, part], axis=1))
            else:
                acc = self._tool_acceleration(jacobian, q, qd, qdd, part)
                out.append(np.linalg.norm(acc, axis=1))
        return np.column_stack(out)


#: The least tool bound whose square is a normal float64.
_SMALLEST = float(np.sqrt(np.finfo(np.float64).tiny))
#: Each tool quantity's unit, and the rows of the geometric Jacobian it comes from.
_UNITS = {"speed": "m/s", "acceleration": "m/s^2", "angular_speed": "rad/s",
          "angular_acceleration": "rad/s^2"}  # fmt: skip
_ROWS = {"speed": slice(0, 3), "acceleration": slice(0, 3), "angular_speed": slice(3, 6),
         "angular_acceleration": slice(3, 6)}  # fmt: skip


def _unit(vectors: FloatArray, fallback: FloatArray) -> FloatArray:
    norm = np.linalg.norm(vectors, axis=1, keepdims=True)
    scale = max(float(norm.max(initial=0.0)), 1e-300)
    small = norm <= 1e-12 * scale
    return np.where(small, np.broadcast_to(fallback, vectors.shape),
                    vectors / np.where(small, 1.0, norm))  # fmt: skip


def checked_limits(extra: object, ndof: int) -> tuple[PathLimit, ...]:
    """``extra`` as a tuple of PathLimits whose chains have ``ndof`` joints."""
    if extra is None:
        return ()
    items = (extra,) if isinstance(extra, PathLimit) else extra
    try:
        items = tuple(items)  # type: ignore[arg-type]
    except TypeError:
        raise InvalidInputError(
            f"constraints must be a TorqueLimit, a ToolLimit or a list of them, got "
            f"{type(extra).__name__}"
        ) from None
    for item in items:
        if not isinstance(item, PathLimit):
            raise InvalidInputError(
                f"constraints must be TorqueLimit or ToolLimit objects, got {type(item).__name__}"
            )
        if item.chain.ndof != ndof:  # type: ignore[attr-defined]
            raise InvalidInputError(
                f"the {item.quantity} limit's chain {item.chain.name!r} has "  # type: ignore[attr-defined]
                f"{item.chain.ndof} joints but the path has {ndof}"  # type: ignore[attr-defined]
            )
    return items


def refuse_unheld(
    limits: tuple[PathLimit, ...], q: FloatArray, where: FloatArray, rests: FloatArray
) -> None:
    """Refuse by name a path point where gravity alone passes a torque limit.

    The arm cannot hold such a pose, so it cannot rest there (its ends, a corner);
    nor does this timing pass through one on momentum: its stages assume that
    standing still is within the limits.

    Parameters
    ----------
    q : ndarray, shape (n, ndof)
        The path at the points ``where`` (its parameter values).
    rests : ndarray
        The parameter values among ``where`` at which the path rests.
    """
    for limit in limits:
        if not isinstance(limit, TorqueLimit):
            continue
        lower, upper = limit.bounds()
        hold = limit.holding(q)
        excess = np.maximum(hold - upper, lower - hold)
        if np.any(excess > 1e-9 * np.maximum(np.abs(upper), np.abs(lower))):
            i, j = np.unravel_index(int(np.argmax(excess)), excess.shape)
            bound = upper[j] if hold[i, j] > upper[j] else lower[j]
            unit = limit.components()[j][1]
            what = ("no timing can stop there" if where[i] in rests
                    else "the timing cannot pass through a pose the arm cannot hold")  # fmt: skip
            raise InfeasibleError(
                f"joint {limit.chain.names[j]} needs {hold[i, j]:.6g} {unit} to hold the arm "
                f"at s={where[i]:.6g} (gravity alone), beyond its torque limit {bound:.6g} "
                f"{unit}: {what}"
            )
