"""Retiming a waypoint list (``tk.retime``): corners blended within a tolerance, then timed.

Pinned here: the blended path's geometry (C1 where blended, the deviation at each
waypoint exactly ``ℓ |y_out - y_in| / 4`` and never above the tolerance, waypoints
passed at the reported times), the timing (limits kept exactly, no stop at a
blended corner, a stop at every corner with tolerance 0, the closed form on a
right angle), and refusals. The comparison with MoveIt's TOTG algorithm is
``bench/bench_retime.py``.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import trajkit as tk
from trajkit.errors import InvalidInputError
from trajkit.time_optimal import blended_path

LIMITS = tk.Limits(velocity=1.0, acceleration=2.0)
SQUARE = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [2.0, 1.0]]


def random_walk(seed: int, count: int = 39, ndof: int = 6, step: float = 0.15) -> np.ndarray:
    """A planner-like dense waypoint list: a random walk in joint space."""
    rng = np.random.default_rng(seed)
    return np.cumsum(rng.uniform(-step, step, (count, ndof)), axis=0)


def closest_distance(motion: tk.Trajectory, points: np.ndarray) -> np.ndarray:
    """Each point's distance to the motion's path, sampled densely (1e5 samples)."""
    q = motion(np.linspace(0.0, motion.end_time, 100_001))
    return np.array([np.linalg.norm(q - p, axis=1).min() for p in points])


def test_corners_are_cut_within_the_tolerance_and_passed_at_the_reported_times():
    motion = tk.retime(SQUARE, LIMITS, path_tolerance=0.05)
    assert motion.check(LIMITS).ok
    deviation = motion.info["waypoint_deviation"]
    # A right angle: |y_out - y_in| = sqrt(2), so ℓ = 4 * 0.05 / sqrt(2) < 0.5 per corner.
    np.testing.assert_allclose(deviation, [0.0, 0.05, 0.05, 0.0], rtol=1e-12, atol=1e-15)
    times = motion.info["waypoint_times"]
    assert times[0] == 0.0 and times[-1] == motion.end_time and np.all(np.diff(times) > 0)
    np.testing.assert_allclose(np.linalg.norm(motion(times) - SQUARE, axis=1), deviation,
                               rtol=1e-9, atol=1e-12)  # fmt: skip
    np.testing.assert_allclose(closest_distance(motion, np.array(SQUARE)), deviation, atol=1e-6)
    # No stop at a blended corner.
    assert np.all(np.linalg.norm(motion.velocity(times[1:-1]), axis=1) > 0.1)
    assert motion.info["planner"] == "retime" and motion.info["path_tolerance"] == 0.05


def test_a_zero_tolerance_stops_at_every_corner_as_two_closed_form_moves():
    motion = tk.retime(SQUARE[:3], LIMITS, path_tolerance=0.0, grid=400)
    # Two unit moves of one joint each, rest to rest: 1/v + v/a = 1.5 s each.
    assert motion.duration == pytest.approx(3.0, rel=1e-9)
    corner = motion.info["waypoint_times"][1]
    np.testing.assert_allclose(motion.velocity(corner), 0.0, atol=1e-12)
    np.testing.assert_array_equal(motion.info["waypoint_deviation"], 0.0)


def test_blending_is_faster_than_stopping_and_bounded_unlike_blended():
    way = random_walk(5)
    stopping = tk.retime(way, LIMITS, path_tolerance=0.0)
    cut = tk.retime(way, LIMITS, path_tolerance=0.02)
    assert cut.duration < 0.9 * stopping.duration
    assert cut.info["waypoint_deviation"].max() <= 0.02
    assert closest_distance(cut, way).max() <= 0.02 + 1e-6
    # tk.blended (parabolic blends sized by the limits) cuts further, with no bound.
    assert closest_distance(tk.blended(way, 1.0, 2.0), way).max() > 0.05


def test_collinear_and_repeated_waypoints():
    straight = tk.retime([[0.0], [0.4], [0.4], [1.0]], LIMITS, path_tolerance=0.1)
    direct = tk.topp(tk.Trajectory([0.0, 1.0], [[[1.0]], [[0.0]]]), LIMITS,
                     grid=straight.info["grid_points"])  # fmt: skip
    assert straight.duration == pytest.approx(direct.duration, rel=1e-12)
    times = straight.info["waypoint_times"]
    assert times[1] == times[2]  # a repeated waypoint is passed once
    np.testing.assert_array_equal(straight.info["waypoint_deviation"], 0.0)


def test_the_blended_path_is_c1_with_the_blend_curvature():
    path, at_waypoint, deviation = blended_path(SQUARE, 0.05)
    inner = path.breakpoints[1:-1]
    left = path.evaluate(np.nextafter(inner, -np.inf), 1)
    np.testing.assert_allclose(left, path.evaluate(inner, 1), atol=1e-12)
    # Unit speed in s on the straight pieces and at the blends' ends.
    ends = np.setdiff1d(path.breakpoints, at_waypoint[1:-1])
    np.testing.assert_allclose(np.linalg.norm(path.evaluate(ends, 1), axis=1), 1.0)
    np.testing.assert_allclose(at_waypoint, [0.0, 1.0, 2.0, 3.0])
    ell = 4 * 0.05 / np.sqrt(2)
    curvature = np.linalg.norm(path.evaluate([1.0], 2)) * 1.0
    assert curvature == pytest.approx(np.sqrt(2) / (2 * ell), rel=1e-12)
    assert deviation[1] == pytest.approx(0.05, rel=1e-12)


@st.composite
def waypoint_lists(draw):
    ndof = draw(st.integers(1, 6))
    count = draw(st.integers(2, 25))
    seed = draw(st.integers(0, 2**32 - 1))
    return random_walk(seed, count, ndof, step=draw(st.floats(0.01, 1.0)))


@settings(max_examples=30, deadline=None)
@given(way=waypoint_lists(), tolerance=st.floats(0.0, 0.3), grid=st.integers(20, 300))
def test_property_limits_kept_and_deviation_bounded_and_reported(way, tolerance, grid):
    motion = tk.retime(way, LIMITS, path_tolerance=tolerance, grid=grid)
    assert motion.check(LIMITS).ok
    deviation = motion.info["waypoint_deviation"]
    assert np.all(deviation <= tolerance * (1 + 1e-12))
    times = motion.info["waypoint_times"]
    assert np.all(np.diff(times) >= 0)
    np.testing.assert_allclose(np.linalg.norm(motion(times) - way, axis=1), deviation,
                               rtol=1e-9, atol=1e-9)  # fmt: skip
    np.testing.assert_allclose(motion([0.0, motion.end_time]), way[[0, -1]], atol=1e-9)
    np.testing.assert_allclose(motion.velocity([0.0, motion.end_time]), 0.0, atol=1e-9)


@pytest.mark.parametrize(
    ("waypoints", "tolerance", "match"),
    [
        ([[0.0, 0.0], [1.0, np.nan]], 0.1, "waypoints must be finite"),
        ([[0.0, 0.0], [1.0]], 0.1, "waypoints"),
        ([[0.0, 0.0]], 0.1, r"m >= 2 rows .* got shape \(1, 2\)"),
        ([0.0, 1.0, 2.0], 0.1, r"got shape \(3,\)"),
        (np.zeros((2, 2, 2)), 0.1, r"got shape \(2, 2, 2\)"),
        ([[1.0, 2.0], [1.0, 2.0]], 0.1, "never move"),
        ([[0.0], [1.0]], -0.1, "path_tolerance must be >= 0"),
        ([[0.0], [1.0]], np.inf, "path_tolerance must be finite"),
        ([[0.0], [1.0]], "big", "path_tolerance"),
        ([[0.0], [1e308], [-1e308]], 0.1, "overflow"),
    ],
)
def test_bad_waypoints_and_tolerances(waypoints, tolerance, match):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the refusal, and no RuntimeWarning before it
        with pytest.raises(InvalidInputError, match=match):
            tk.retime(waypoints, LIMITS, path_tolerance=tolerance)


def test_bad_limits_and_grid():
    with pytest.raises(InvalidInputError, match="not jerk"):
        tk.retime(SQUARE, tk.Limits(velocity=1, acceleration=2, jerk=5))
    with pytest.raises(InvalidInputError, match=r"limits must be a trajkit\.Limits"):
        tk.retime(SQUARE, {"velocity": 1})
    for grid in (1, 2.5, True, "fine"):
        with pytest.raises(InvalidInputError, match="grid must be a whole number"):
            tk.retime(SQUARE, LIMITS, grid=grid)


def test_retime_keeps_torque_and_tool_limits_too():
    from trajkit.kinematics import UR5

    ur5 = UR5()
    way = np.radians([[0, -90, 0, -90, 0, 0], [40, -60, 60, -90, -30, 0],
                      [70, -110, 100, -80, 0, 45], [0, -90, 0, -90, 0, 0]])  # fmt: skip
    fast = tk.Limits(velocity=np.pi, acceleration=50.0)
    limits = [tk.TorqueLimit(ur5), tk.ToolLimit(ur5, speed=0.8)]
    motion = tk.retime(way, fast, path_tolerance=0.05, constraints=limits)
    assert motion.check(fast).ok
    assert [report.ok for report in motion.info["constraint_checks"]] == [True, True]
    t = np.linspace(0.0, motion.end_time, 20001)
    speed = limits[1].values(motion(t), motion.velocity(t), motion.acceleration(t))
    assert 0.79 < speed.max() <= 0.8 * (1 + 1e-9)
    assert motion.duration > tk.retime(way, fast, path_tolerance=0.05).duration
