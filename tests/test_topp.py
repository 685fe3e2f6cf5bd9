"""Time-optimal path parameterization: limits kept exactly, boundaries met, toppra as oracle.

Issue 8 is in progress: these pin down the core (velocity and acceleration limits,
boundary speeds, corners); the speed targets and extensions are still to come.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import trajkit as tk
from trajkit.errors import InfeasibleError, InvalidInputError
from trajkit.time_optimal import topp

LIMITS = tk.Limits(velocity=1.0, acceleration=2.0)


def spline(seed: int, ndof: int = 6, points: int = 5) -> tk.Trajectory:
    rng = np.random.default_rng(seed)
    return tk.cubic_spline(np.linspace(0, 1, points), rng.uniform(-1, 1, (points, ndof)),
                           bc="natural")  # fmt: skip


@pytest.mark.parametrize("grid", [100, 500])
def test_limits_hold_on_the_whole_curve_and_the_path_is_kept(grid):
    path = spline(0)
    timed = topp(path, LIMITS, grid=grid)
    assert timed.check(LIMITS).ok  # exact, on the polynomial pieces
    np.testing.assert_allclose(timed(timed.start_time), path(0.0), atol=1e-12)
    np.testing.assert_allclose(timed(timed.end_time), path(1.0), atol=1e-12)
    np.testing.assert_allclose(timed.velocity([0.0, timed.end_time]), 0.0, atol=1e-12)
    # The timed curve lies on the path: every sample is q(s) for its path parameter.
    t = np.linspace(0, timed.end_time, 201)
    s = np.interp(t, timed.breakpoints, timed.info["grid_points"])
    assert np.abs(timed(t) - path(s)).max() < 0.05  # s(t) is quadratic, not linear, inside


def test_duration_against_toppra():
    ta = pytest.importorskip("toppra", reason="toppra is the oracle: pip install toppra")
    import toppra.algorithm as algo
    import toppra.constraint as constraint

    ta.setup_logging("WARNING")
    rng = np.random.default_rng(3)
    way = rng.uniform(-1, 1, (5, 6))
    ours = topp(tk.cubic_spline(np.linspace(0, 1, 5), way, bc="natural"), LIMITS, grid=1000)
    path = ta.SplineInterpolator(np.linspace(0, 1, 5), way, bc_type="natural")
    instance = algo.TOPPRA(
        [constraint.JointVelocityConstraint(np.array([[-1.0, 1.0]] * 6)),
         constraint.JointAccelerationConstraint(np.array([[-2.0, 2.0]] * 6))],
        path, gridpoints=np.linspace(0, 1, 1001), parametrizer="ParametrizeConstAccel",
    )  # fmt: skip
    theirs = instance.compute_trajectory().duration
    # toppra's timing breaks the limits between grid points; ours keeps them exactly and
    # is at most 0.5% longer here (measured 0.14%; coarser grids still cost up to 1.5%).
    assert ours.check(LIMITS).ok
    assert theirs * 0.99 < ours.duration < theirs * 1.005


@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), ndof=st.integers(1, 4), grid=st.integers(20, 200))
def test_property_limits_never_exceeded(seed, ndof, grid):
    path = spline(seed, ndof)
    limits = tk.Limits(velocity=(-0.5, 1.5), acceleration=(-3.0, 1.0))
    timed = topp(path, limits, grid=grid)
    assert timed.check(limits).ok
    np.testing.assert_allclose(timed(timed.end_time), path(1.0), atol=1e-12)


def test_boundary_path_speeds_are_met():
    path = tk.Trajectory([0.0, 1.0], np.array([[[1.0, -0.5]], [[0.0, 0.0]]]))  # a line
    timed = topp(path, LIMITS, grid=200, start_speed=0.3, end_speed=0.2)
    np.testing.assert_allclose(timed.velocity(0.0), path.velocity(0.0) * 0.3, atol=1e-12)
    np.testing.assert_allclose(timed.velocity(timed.end_time), path.velocity(1.0) * 0.2,
                               atol=1e-12)  # fmt: skip
    assert timed.check(LIMITS).ok


def test_a_sharp_corner_stops_the_path():
    # Two straight segments meeting at a right angle: the path speed must vanish there.
    corner = tk.Trajectory([0.0, 1.0, 2.0], np.array([[[1.0, 0.0], [0.0, 1.0]],
                                                      [[0.0, 0.0], [1.0, 0.0]]]))  # fmt: skip
    timed = topp(corner, LIMITS, grid=200)
    assert timed.check(LIMITS).ok
    grid = timed.info["grid_points"]
    at_corner = np.argmin(np.abs(grid - 1.0))
    assert timed.info["path_speed"][at_corner] == pytest.approx(0.0, abs=1e-9)


@pytest.mark.parametrize(
    ("kwargs", "error", "match"),
    [
        ({"grid": 1}, InvalidInputError, "grid must be at least 2 intervals"),
        ({"grid": [0.0, 0.5]}, InvalidInputError, "at least 3 increasing numbers"),
        ({"start_speed": -1.0}, InvalidInputError, "must be >= 0"),
        ({"start_speed": np.nan}, InvalidInputError, "start_speed must be finite"),
        ({"start_speed": 100.0}, InfeasibleError, "break the limits|too fast"),
    ],
)
def test_bad_requests(kwargs, error, match):
    with pytest.raises(error, match=match):
        topp(spline(1, 2), LIMITS, **kwargs)


def test_limits_must_bound_velocity_and_acceleration_around_zero():
    with pytest.raises(InvalidInputError, match="velocity and acceleration bounds"):
        topp(spline(1, 2), tk.Limits(velocity=1.0))
    with pytest.raises(InvalidInputError, match="lower < 0 < upper"):
        topp(spline(1, 2), tk.Limits(velocity=(0.0, 1.0), acceleration=1.0))
    with pytest.raises(InvalidInputError, match="path must be a Trajectory"):
        topp("path", LIMITS)


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), grid=st.integers(5, 60))
def test_the_closed_form_peaks_equal_the_timed_trajectorys_extrema(seed, grid):
    from trajkit.time_optimal import _grid, _peaks, _timed

    rng = np.random.default_rng(seed)
    path = spline(seed, 3)
    points = _grid(path, grid)
    x = rng.uniform(0.05, 2.0, points.size)  # any speed profile, not only optimal ones
    vel, acc = [np.full(3, -1.0), np.full(3, 1.5)], [np.full(3, -2.0), np.full(3, 0.5)]
    ratio_v, ratio_a = _peaks(path, points, x, vel, acc)
    timed = _timed(path, points, x)
    v, a = timed.extrema(1), timed.extrema(2)
    expected_v = max(np.max(v.maximum / vel[1]), np.max(v.minimum / vel[0]))
    expected_a = max(np.max(a.maximum / acc[1]), np.max(a.minimum / acc[0]))
    assert ratio_v == pytest.approx(expected_v, rel=1e-9)
    assert ratio_a == pytest.approx(expected_a, rel=1e-9)
