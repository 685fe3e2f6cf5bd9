"""MoveIt's time-optimal trajectory generation (TOTG), in numpy, as a benchmark reference.

This follows Kunz & Stilman, "Time-Optimal Trajectory Generation for Path Following
with Bounded Acceleration and Velocity" (RSS 2012), as MoveIt implements it in
``time_optimal_trajectory_generation.cpp``: the same path, the same phase-plane
integration, the same switching-point searches and the same tolerances (``EPS`` =
1e-6, a 1e-3 scan step along the path), step by step, so that its durations and its
limit violations are MoveIt's, only slower (pure Python instead of C++): against
MoveIt's C++ built from source, on 6-D random walks of 39 waypoints, the durations
agree to 1e-12 s. It is a reference for ``bench_retime.py``, not part of trajkit. The
algorithm's steps:

1. **Path**. Repeated waypoints are dropped (no joint moving more than
   ``min_angle_change``). Each interior waypoint's corner is replaced by a circular
   arc tangent to both neighbouring segments: with ``α`` the angle between the two
   directions, the arc starts and ends a distance
   ``d = min(ℓ_prev / 2, ℓ_next / 2, δ sin(α/2) / (1 - cos(α/2)))`` from the corner
   (``δ`` = ``max_deviation``, the arc's largest distance from the corner) and has the
   radius ``d / tan(α/2)``. Straight pieces join the arcs; ``s`` is arc length, so
   ``|q'(s)| = 1`` and ``q''(s)`` is 0 on lines and the centripetal vector on arcs.
   A 180° turn is refused, as MoveIt does.
2. **Limit curves**. Per joint ``|q̇_i| = |q'_i| ṡ <= v_i`` gives the velocity
   limit curve ``ṡ_max,v(s) = min_i v_i / |q'_i(s)|``;
   ``|q''_i ṡ² + q'_i s̈| <= a_i`` bounds ``s̈`` between ``s̈_min(s, ṡ)`` and
   ``s̈_max(s, ṡ)``, and these cross (no ``s̈`` left) above the acceleration limit
   curve ``ṡ_max,a(s)``, the minimum over joint pairs of
   ``sqrt((a_i/|q'_i| + a_j/|q'_j|) / |q''_i/q'_i - q''_j/q'_j|)`` (and of
   ``sqrt(a_i / |q''_i|)`` where ``q'_i = 0``).
3. **Forward integration**. From ``(s, ṡ) = (0, 0)`` at ``s̈_max`` with time step
   ``time_step`` (trapezoidal in ``ṡ``), following the velocity limit curve where the
   trajectory can slide along it, until the end of the path or a limit curve is hit
   (the crossing found by bisection to ``EPS``).
4. **Switching points**. On the acceleration limit curve: at the arcs' ends, where
   ``q''`` jumps (discontinuity points), and where some ``q'_i`` is 0 on an arc (the
   curve has a kink or a minimum there); on the velocity limit curve: where the
   minimum phase slope ``s̈_min / ṡ`` crosses the curve's own slope from above,
   scanned every 1e-3 of ``s`` and refined by bisection. The first usable one after
   the point where forward integration stopped is taken.
5. **Backward integration**. From that switching point at ``s̈_min`` back in ``s``
   until it meets the forward trajectory; the forward trajectory is cut there and
   continued by the backward one, and forward integration resumes from the switching
   point. The final backward integration starts from ``(L, 0)``. Unlike the forward
   pass, it does not stop at the arcs' ends: a step across one uses the ``s̈_min`` of
   the side it starts on, which can break the acceleration bounds on the rest of that
   step (less than one ``time_step``), as in MoveIt.
6. **Timing**. Each step of the phase-plane curve takes
   ``Δs / ((ṡ_k + ṡ_{k+1}) / 2)``; between steps ``s̈`` is constant.

Sampling: :meth:`Trajectory.evaluate` returns the position, velocity and acceleration
of the timed path exactly (``q̈ = q' s̈ + q'' ṡ²`` with each step's constant ``s̈``),
for checking limits; MoveIt's own resampler differences velocities instead.
"""

from __future__ import annotations

import bisect
import math

import numpy as np

__all__ = ["Path", "Trajectory", "totg"]

#: MoveIt's tolerance for bisections and one-sided evaluations (``EPS``).
EPS = 1e-6
#: Step along ``s`` of the velocity-switching-point scan (MoveIt's DEFAULT_TIMESTEP).
SCAN_STEP = 1e-3
#: MoveIt's default: a waypoint is kept if some joint moves more than this.
MIN_ANGLE_CHANGE = 1e-3
#: Smallest segment length MoveIt keeps (and smallest corner leg it blends).
_SHORT = 1e-6


def _divide(a: float, b: float) -> float:
    """``a / b`` with IEEE results for ``b == 0`` (inf or nan), as C++ gives them."""
    if b != 0.0:
        return a / b
    if a == 0.0 or math.isnan(a):
        return math.nan
    return math.copysign(math.inf, a) * math.copysign(1.0, b)


class Path:
    """Straight segments joined by circular blends, parameterized by arc length.

    Parameters
    ----------
    waypoints : array_like, shape (m, n)
        Distinct consecutive waypoints, m >= 2.
    max_deviation : float
        Largest distance of a blend from its corner (MoveIt's ``path_tolerance``), > 0.
    """

    def __init__(self, waypoints, max_deviation: float) -> None:
        points = np.asarray(waypoints, dtype=float)
        if points.ndim != 2 or points.shape[0] < 2:
            raise ValueError("a path needs at least 2 waypoints")
        if not max_deviation > 0.0:
            raise ValueError("max_deviation must be > 0")
        self.dof = points.shape[1]
        self.segments: list[dict] = []
        start = points[0]
        for k in range(1, points.shape[0]):
            corner = points[k]
            if k + 1 < points.shape[0]:
                after = points[k + 1]
                incoming, outgoing = corner - points[k - 1], after - corner
                n_in, n_out = np.linalg.norm(incoming), np.linalg.norm(outgoing)
                if n_in > np.finfo(float).eps and n_out > np.finfo(float).eps:
                    if incoming @ outgoing / (n_in * n_out) <= -1.0 + 1e-5:
                        raise ValueError("the path turns by 180°, which TOTG cannot blend")
                arc = self._arc(0.5 * (points[k - 1] + corner), corner, 0.5 * (corner + after),
                                max_deviation)  # fmt: skip
                arc_start = self._arc_config(arc, 0.0)
                if np.linalg.norm(arc_start - start) > _SHORT:
                    self.segments.append(self._line(start, arc_start))
                self.segments.append(arc)
                start = self._arc_config(arc, arc["length"])
            else:
                self.segments.append(self._line(start, corner))
                start = corner
        # Positions along the path and the switching points: (s, is a discontinuity).
        self.length = 0.0
        switching: list[tuple[float, bool]] = []
        for segment in self.segments:
            segment["position"] = self.length
            switching += [(self.length + p, False) for p in self._local_switching(segment)]
            self.length += segment["length"]
            while switching and switching[-1][0] >= self.length:
                switching.pop()
            switching.append((self.length, True))
        switching.pop()  # the end of the path is no switching point
        self.switching_s = [p for p, _ in switching]
        self.switching_discontinuity = [d for _, d in switching]
        # Arrays for evaluating many s at once.
        self._positions = [segment["position"] for segment in self.segments]
        self._position_array = np.array(self._positions)
        self._is_arc = np.array([segment["arc"] for segment in self.segments])
        zeros = np.zeros(self.dof)
        self._start = np.array([seg.get("start", zeros) for seg in self.segments])
        self._end = np.array([seg.get("end", zeros) for seg in self.segments])
        self._center = np.array([seg.get("center", zeros) for seg in self.segments])
        self._x = np.array([seg.get("x", zeros) for seg in self.segments])
        self._y = np.array([seg.get("y", zeros) for seg in self.segments])
        self._length = np.array([segment["length"] for segment in self.segments])
        self._radius = np.array([segment.get("radius", 1.0) for segment in self.segments])

    # -- segments ------------------------------------------------------------------

    @staticmethod
    def _line(start, end) -> dict:
        length = float(np.linalg.norm(end - start))
        return {"arc": False, "start": start, "end": end, "length": length,
                "tangent": (end - start) / length}  # fmt: skip

    @staticmethod
    def _arc(start, corner, end, max_deviation: float) -> dict:
        """The circular blend of ``corner`` between the legs' midpoints ``start``, ``end``."""
        degenerate = {"arc": True, "length": 0.0, "radius": 1.0, "center": corner,
                      "x": np.zeros_like(corner), "y": np.zeros_like(corner)}  # fmt: skip
        if np.linalg.norm(corner - start) < _SHORT or np.linalg.norm(end - corner) < _SHORT:
            return degenerate
        y_in = (corner - start) / np.linalg.norm(corner - start)
        y_out = (end - corner) / np.linalg.norm(end - corner)
        cosine = float(y_in @ y_out)
        if abs(cosine) > 0.999999:  # straight on (or back): no arc
            return degenerate
        angle = math.acos(cosine)
        reach = max_deviation * math.sin(angle / 2) / (1.0 - math.cos(angle / 2))
        distance = min(float(np.linalg.norm(start - corner)), float(np.linalg.norm(end - corner)),
                       reach)  # fmt: skip
        radius = distance / math.tan(angle / 2)
        bisector = (y_out - y_in) / np.linalg.norm(y_out - y_in)
        center = corner + bisector * radius / math.cos(angle / 2)
        x = corner - distance * y_in - center
        return {"arc": True, "length": angle * radius, "radius": radius, "center": center,
                "x": x / np.linalg.norm(x), "y": y_in}  # fmt: skip

    @staticmethod
    def _arc_config(arc: dict, s: float):
        angle = s / arc["radius"]
        return arc["center"] + arc["radius"] * (arc["x"] * math.cos(angle)
                                                + arc["y"] * math.sin(angle))  # fmt: skip

    @staticmethod
    def _local_switching(segment: dict) -> list[float]:
        """On an arc, the s (from its start) where a joint's tangent component is 0."""
        if not segment["arc"]:
            return []
        points = []
        for xi, yi in zip(segment["x"], segment["y"], strict=True):
            angle = math.atan2(yi, xi)
            if angle < 0.0:
                angle += math.pi
            if angle * segment["radius"] < segment["length"]:
                points.append(angle * segment["radius"])
        return sorted(points)

    # -- evaluation ----------------------------------------------------------------

    def segment_at(self, s: float) -> tuple[dict, float]:
        """The segment holding ``s`` (the last one starting at or before it) and the local s."""
        index = max(bisect.bisect_right(self._positions, s) - 1, 0)
        segment = self.segments[index]
        return segment, s - segment["position"]

    def next_switching_point(self, s: float) -> tuple[float, bool]:
        """The first switching point after ``s``: (s, is a discontinuity); else (L, True)."""
        index = bisect.bisect_right(self.switching_s, s)
        if index == len(self.switching_s):
            return self.length, True
        return self.switching_s[index], self.switching_discontinuity[index]

    def evaluate(self, s, order: int = 0) -> np.ndarray:
        """``q(s)``, ``q'(s)`` or ``q''(s)`` at arc lengths ``s``: shape ``s.shape + (n,)``."""
        s = np.asarray(s, dtype=float)
        flat = s.ravel()
        index = np.maximum(np.searchsorted(self._position_array, flat, side="right") - 1, 0)
        local = (flat - self._position_array[index])[:, None]
        radius = self._radius[index][:, None]
        angle = local / radius
        cos, sin = np.cos(angle), np.sin(angle)
        x, y = self._x[index], self._y[index]
        if order == 0:
            fraction = np.clip(local / np.where(self._length[index] > 0, self._length[index],
                                                1.0)[:, None], 0.0, 1.0)  # fmt: skip
            line = (1.0 - fraction) * self._start[index] + fraction * self._end[index]
            arc = self._center[index] + radius * (x * cos + y * sin)
        elif order == 1:
            with np.errstate(divide="ignore", invalid="ignore"):
                line = (self._end[index] - self._start[index]) / self._length[index][:, None]
            arc = -x * sin + y * cos
        elif order == 2:
            line = np.zeros_like(x)
            arc = -(x * cos + y * sin) / radius
        else:
            raise ValueError("order must be 0, 1 or 2")
        out = np.where(self._is_arc[index][:, None], arc, line)
        return out.reshape((*s.shape, self.dof))


class Trajectory:
    """The time-optimal timing of a :class:`Path` (MoveIt's ``Trajectory``).

    Parameters
    ----------
    path : Path
    max_velocity, max_acceleration : array_like, shape (n,)
        Symmetric per-joint bounds, > 0.
    time_step : float
        Integration step (s), MoveIt's default 1e-3.

    Attributes
    ----------
    valid : bool
        False when an integration failed (MoveIt then returns no trajectory).
    s, sdot, times : ndarray
        The phase-plane curve: path position, path velocity and time of each step.
    """

    def __init__(self, path: Path, max_velocity, max_acceleration, time_step: float = 1e-3):
        self.path = path
        self.vmax = np.broadcast_to(np.asarray(max_velocity, dtype=float), (path.dof,)).copy()
        self.amax = np.broadcast_to(np.asarray(max_acceleration, dtype=float), (path.dof,)).copy()
        self.time_step = float(time_step)
        self.valid = True
        self._line_cache: dict[int, tuple] = {}
        self._pos: list[float] = [0.0]
        self._vel: list[float] = [0.0]
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            self._run()
            self.s = np.array(self._pos)
            self.sdot = np.array(self._vel)
            steps = np.diff(self.s) / ((self.sdot[1:] + self.sdot[:-1]) / 2.0)
            self.times = np.concatenate([[0.0], np.cumsum(steps)])

    @property
    def duration(self) -> float:
        """Time of the motion (s)."""
        return float(self.times[-1])

    # -- the limit curves, at one s ------------------------------------------------

    def _local(self, s: float):
        """``q'`` and ``q''`` at ``s`` and whether it lies on a straight segment."""
        segment, local = self.path.segment_at(s)
        if not segment["arc"]:
            return segment["tangent"], None
        angle = local / segment["radius"]
        cos, sin = math.cos(angle), math.sin(angle)
        x, y = segment["x"], segment["y"]
        return -x * sin + y * cos, -(x * cos + y * sin) / segment["radius"]

    def _path_acceleration(self, s: float, sdot: float, maximum: bool) -> float:
        """``s̈_max`` (or ``s̈_min``) at ``(s, ṡ)``: MoveIt's getMinMaxPathAcceleration."""
        tangent, curvature = self._local(s)
        factor = 1.0 if maximum else -1.0
        moving = tangent != 0.0
        bound = self.amax[moving] / np.abs(tangent[moving])
        if curvature is not None:
            bound = bound - factor * curvature[moving] * sdot * sdot / tangent[moving]
        # C++'s running std::min skips nan terms (0 · inf on a blend at ṡ = inf).
        return factor * (float(np.fmin.reduce(bound)) if bound.size else np.finfo(float).max)

    def _phase_slope(self, s: float, sdot: float, maximum: bool) -> float:
        """``s̈ / ṡ``, the slope of the phase-plane curve at ``(s, ṡ)``."""
        return _divide(self._path_acceleration(s, sdot, maximum), sdot)

    def _velocity_limit(self, s: float) -> float:
        """The velocity limit curve ``min_i v_i / |q'_i|``."""
        tangent, _ = self._local(s)
        return float((self.vmax / np.abs(tangent)).min())

    def _velocity_limit_slope(self, s: float) -> float:
        """``d ṡ_max,v / ds`` from the active joint (MoveIt's analytic derivative)."""
        tangent, curvature = self._local(s)
        if curvature is None:
            return -0.0
        active = int(np.argmin(self.vmax / np.abs(tangent)))
        return -(self.vmax[active] * curvature[active]) / (tangent[active] * abs(tangent[active]))

    def _acceleration_limit(self, s: float) -> float:
        """The acceleration limit curve (inf on straight segments)."""
        tangent, curvature = self._local(s)
        if curvature is None:
            return math.inf
        moving = tangent != 0.0
        limit = math.inf
        if moving.any():
            t, c, a = tangent[moving], curvature[moving], self.amax[moving]
            ratio, reach = c / t, a / np.abs(t)
            gap = np.abs(ratio[:, None] - ratio[None, :])
            pair = gap != 0.0
            if pair.any():
                limit = float(np.sqrt((reach[:, None] + reach[None, :])[pair] / gap[pair]).min())
        still = ~moving & (curvature != 0.0)
        if still.any():
            limit = min(limit, float(np.sqrt(self.amax[still] / np.abs(curvature[still])).min()))
        return limit

    def _acceleration_limit_slope(self, s: float) -> float:
        """Central difference of the acceleration limit curve over ``±EPS`` (nan on lines)."""
        return (self._acceleration_limit(s + EPS) - self._acceleration_limit(s - EPS)) / (2 * EPS)

    # -- the algorithm -------------------------------------------------------------

    def _run(self) -> None:
        after = self._path_acceleration(0.0, 0.0, True)
        while self.valid and not self._integrate_forward(after) and self.valid:
            end, point, before, after = self._next_switching_point(self._pos[-1])
            if end:
                break
            self._integrate_backward(point[0], point[1], before)
        if not self.valid:
            return
        before = self._path_acceleration(self.path.length, 0.0, False)
        self._integrate_backward(self.path.length, 0.0, before)

    def _next_switching_point(self, s: float):
        """The next switching point after ``s``: (reached end, (s, ṡ), s̈ before, s̈ after)."""
        acc_point, acc_before, acc_after = (s, 0.0), 0.0, 0.0
        while True:
            acc_end, found = self._next_acceleration_switching_point(acc_point[0])
            if not acc_end:
                acc_point, acc_before, acc_after = found
            if acc_end or not acc_point[1] > self._velocity_limit(acc_point[0]):
                break
        vel_point, vel_before, vel_after = (s, 0.0), 0.0, 0.0
        while True:
            vel_end, found = self._next_velocity_switching_point(vel_point[0])
            if not vel_end:
                vel_point, vel_before, vel_after = found
            if vel_end or vel_point[0] > acc_point[0]:
                break
            if not (vel_point[1] > self._acceleration_limit(vel_point[0] - EPS)
                    or vel_point[1] > self._acceleration_limit(vel_point[0] + EPS)):  # fmt: skip
                break
        if acc_end and vel_end:
            return True, None, 0.0, 0.0
        if not acc_end and (vel_end or acc_point[0] <= vel_point[0]):
            return False, acc_point, acc_before, acc_after
        return False, vel_point, vel_before, vel_after

    def _next_acceleration_switching_point(self, s: float):
        """Discontinuity points and kinks/minima of the acceleration limit curve."""
        path = self.path
        while True:
            s, discontinuity = path.next_switching_point(s)
            if s > path.length - EPS:
                return True, None
            if discontinuity:
                before_v = self._acceleration_limit(s - EPS)
                after_v = self._acceleration_limit(s + EPS)
                sdot = min(before_v, after_v)
                before = self._path_acceleration(s - EPS, sdot, False)
                after = self._path_acceleration(s + EPS, sdot, True)
                if (before_v > after_v or self._phase_slope(s - EPS, sdot, False)
                        > self._acceleration_limit_slope(s - 2 * EPS)) and (
                        before_v < after_v or self._phase_slope(s + EPS, sdot, True)
                        < self._acceleration_limit_slope(s + 2 * EPS)):  # fmt: skip
                    return False, ((s, sdot), before, after)
            else:
                sdot = self._acceleration_limit(s)
                if (self._acceleration_limit_slope(s - EPS) < 0.0
                        and self._acceleration_limit_slope(s + EPS) > 0.0):  # fmt: skip
                    return False, ((s, sdot), 0.0, 0.0)

    def _velocity_curve_test(self, s: np.ndarray):
        """Minimum phase slope and slope of the velocity limit curve at many ``s``."""
        tangent, curvature = self.path.evaluate(s, 1), self.path.evaluate(s, 2)
        ratio = self.vmax / np.abs(tangent)
        limit = ratio.min(axis=1)
        moving = tangent != 0.0
        bound = np.where(moving, self.amax / np.abs(tangent)
                         + curvature * (limit * limit)[:, None] / tangent, np.inf)  # fmt: skip
        bound = bound.min(axis=1)
        slope = -np.where(np.isfinite(bound), bound, np.finfo(float).max) / limit
        active = np.argmin(ratio, axis=1)
        rows = np.arange(s.size)
        t_active = tangent[rows, active]
        curve_slope = -(self.vmax[active] * curvature[rows, active]) / (t_active * np.abs(t_active))
        return slope, curve_slope

    def _next_velocity_switching_point(self, s: float):
        """Where the minimum phase slope drops below the velocity limit curve's slope.

        MoveIt steps ``s`` by 1e-3 from ``s``: once the phase slope has been at or
        above the curve's slope, the first point where it is at or below ends the
        scan; bisection to ``EPS`` then places it. Done here a chunk at a time.
        """
        length = self.path.length
        started, first, chunk = False, 0, 64
        while True:
            grid = s + SCAN_STEP * np.arange(first, first + chunk)
            slope, curve_slope = self._velocity_curve_test(grid)
            started_at = started | np.logical_or.accumulate(slope >= curve_slope)
            stop = (started_at & ~(slope > curve_slope)) | (grid >= length)
            if stop.any():
                position = float(grid[np.argmax(stop)])
                break
            started, first, chunk = bool(started_at[-1]), first + chunk, min(4 * chunk, 4096)
        if position >= length:
            return True, None
        before, after = position - SCAN_STEP, position
        while after - before > EPS:
            middle = (before + after) / 2.0
            limit = self._velocity_limit(middle)
            if self._phase_slope(middle, limit, False) > self._velocity_limit_slope(middle):
                before = middle
            else:
                after = middle
        before_acc = self._path_acceleration(before, self._velocity_limit(before), False)
        after_acc = self._path_acceleration(after, self._velocity_limit(after), True)
        return False, ((after, self._velocity_limit(after)), before_acc, after_acc)

    def _can_slide(self, s: float) -> bool:
        """Whether a trajectory on the velocity limit curve at ``s`` can follow it."""
        limit = self._velocity_limit(s)
        return self._phase_slope(s, limit, False) <= self._velocity_limit_slope(s)

    def _integrate_forward(self, acceleration: float) -> bool:
        """Integrate at ``s̈_max`` from the last point; True at the path's end (or failure)."""
        pos, vel = self._pos, self._vel
        s, sdot = pos[-1], vel[-1]
        dt, length = self.time_step, self.path.length
        switching, discontinuity = self.path.switching_s, self.path.switching_discontinuity
        following = 0
        while True:
            while following < len(switching) and (switching[following] <= s
                                                  or not discontinuity[following]):  # fmt: skip
                following += 1
            next_s = switching[following] if following < len(switching) else None
            old_s, old_sdot = s, sdot
            sdot += dt * acceleration
            s += dt * 0.5 * (old_sdot + sdot)
            if next_s is not None and s > next_s:
                # Land on the discontinuity, unless that is within EPS (a near-duplicate).
                if s - next_s < EPS:
                    continue
                sdot = old_sdot + (next_s - old_s) * (sdot - old_sdot) / (s - old_s)
                s = next_s
            if s > length:
                pos.append(s)
                vel.append(sdot)
                return True
            if sdot < 0.0:
                self.valid = False
                return True
            if sdot > self._velocity_limit(s) and self._can_slide(old_s):
                sdot = self._velocity_limit(s)
            pos.append(s)
            vel.append(sdot)
            acceleration = self._path_acceleration(s, sdot, True)
            if sdot == 0.0 and acceleration == 0.0:
                self.valid = False
                return True
            if sdot > self._acceleration_limit(s) or sdot > self._velocity_limit(s):
                # Hit a limit curve: bisect for the crossing.
                over_s, over_sdot = pos.pop(), vel.pop()
                before, before_sdot, after, after_sdot = pos[-1], vel[-1], over_s, over_sdot
                while after - before > EPS:
                    middle = 0.5 * (before + after)
                    middle_sdot = 0.5 * (before_sdot + after_sdot)
                    if middle_sdot > self._velocity_limit(middle) and self._can_slide(before):
                        middle_sdot = self._velocity_limit(middle)
                    if (middle_sdot > self._acceleration_limit(middle)
                            or middle_sdot > self._velocity_limit(middle)):  # fmt: skip
                        after, after_sdot = middle, middle_sdot
                    else:
                        before, before_sdot = middle, middle_sdot
                pos.append(before)
                vel.append(before_sdot)
                if self._acceleration_limit(after) < self._velocity_limit(after):
                    if after > (next_s if next_s is not None else length):
                        return False
                    if self._phase_slope(before, before_sdot, True) > (
                        self._acceleration_limit_slope(before)
                    ):
                        return False
                elif self._phase_slope(before, before_sdot, False) > (
                    self._velocity_limit_slope(before)
                ):
                    return False
                # Otherwise MoveIt carries on from the overshooting step.

    def _integrate_backward(self, s: float, sdot: float, acceleration: float) -> None:
        """Integrate at ``s̈_min`` back from ``(s, ṡ)`` until it meets the forward curve."""
        pos, vel = self._pos, self._vel
        dt = self.time_step
        second = len(pos) - 1
        first = second - 1
        back_s: list[float] = []  # in reverse order: the latest step is the front
        back_sdot: list[float] = []
        slope = math.nan
        while first != 0 or s >= 0.0:
            if pos[first] <= s:
                back_s.append(s)
                back_sdot.append(sdot)
                sdot -= dt * acceleration
                s -= dt * 0.5 * (sdot + back_sdot[-1])
                acceleration = self._path_acceleration(s, sdot, False)
                slope = _divide(back_sdot[-1] - sdot, back_s[-1] - s)
                if sdot < 0.0:
                    self.valid = False
                    return
            else:
                first -= 1
                second -= 1
            forward_slope = _divide(vel[second] - vel[first], pos[second] - pos[first])
            crossing = _divide(vel[first] - sdot + slope * s - forward_slope * pos[first],
                               slope - forward_slope)  # fmt: skip
            front = back_s[-1] if back_s else math.nan
            if max(pos[first], s) - EPS <= crossing <= EPS + min(pos[second], front):
                crossing_sdot = vel[first] + forward_slope * (crossing - pos[first])
                del pos[second:], vel[second:]
                pos.append(crossing)
                vel.append(crossing_sdot)
                pos.extend(reversed(back_s))
                vel.extend(reversed(back_sdot))
                return
        self.valid = False

    # -- sampling ------------------------------------------------------------------

    def phase(self, t) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``s``, ``ṡ`` and ``s̈`` at times ``t`` (clamped to ``[0, duration]``)."""
        t = np.clip(np.asarray(t, dtype=float), 0.0, self.duration)
        step = np.clip(np.searchsorted(self.times, t, side="right"), 1, self.times.size - 1)
        previous = step - 1
        h = self.times[step] - self.times[previous]
        with np.errstate(divide="ignore", invalid="ignore"):
            sddot = np.where(h > 0.0, 2.0 * (self.s[step] - self.s[previous]
                                             - h * self.sdot[previous]) / (h * h), 0.0)  # fmt: skip
        tau = t - self.times[previous]
        s = self.s[previous] + tau * self.sdot[previous] + 0.5 * tau * tau * sddot
        return s, self.sdot[previous] + tau * sddot, sddot

    def evaluate(self, t, order: int = 0) -> np.ndarray:
        """Joint position (0), velocity (1) or acceleration (2) at times ``t``."""
        s, sdot, sddot = self.phase(t)
        if order == 0:
            return self.path.evaluate(s, 0)
        if order == 1:
            return self.path.evaluate(s, 1) * sdot[..., None]
        if order == 2:
            return (self.path.evaluate(s, 1) * sddot[..., None]
                    + self.path.evaluate(s, 2) * (sdot * sdot)[..., None])  # fmt: skip
        raise ValueError("order must be 0, 1 or 2")


def totg(waypoints, vmax, amax, max_deviation: float = 0.1, time_step: float = 1e-3,
         min_angle_change: float = MIN_ANGLE_CHANGE) -> Trajectory:  # fmt: skip
    """Time a waypoint list as MoveIt's TOTG does: blend, then integrate the phase plane.

    Parameters
    ----------
    waypoints : array_like, shape (m, n)
        Joint positions (rad).
    vmax, amax : float or array_like, shape (n,)
        Symmetric per-joint velocity (rad/s) and acceleration (rad/s²) bounds.
    max_deviation : float
        MoveIt's ``path_tolerance`` (rad), > 0.
    time_step : float
        Phase-plane integration step (s).
    min_angle_change : float
        Waypoints whose joints all move less than this from the last kept one are dropped
        (the last waypoint replaces the last kept one instead).

    Returns
    -------
    Trajectory
        ``duration`` and ``evaluate(t, order)``; ``valid`` is False where MoveIt fails.
    """
    points = np.asarray(waypoints, dtype=float)
    if points.ndim == 1:
        points = points[:, None]
    kept = [points[0]]
    for k in range(1, points.shape[0]):
        if np.any(np.abs(points[k] - kept[-1]) > min_angle_change):
            kept.append(points[k])
        elif k == points.shape[0] - 1:
            kept[-1] = points[k]
    if len(kept) < 2:
        raise ValueError("the waypoints never move: nothing to time")
    return Trajectory(Path(np.array(kept), max_deviation), vmax, amax, time_step)
