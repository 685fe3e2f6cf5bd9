"""Tests of trajkit.mobile.time_optimal: a wheeled base driven along a fixed curve, fastest.

Curves: a natural cubic spline (a 2-DoF Trajectory, moving at its ends) and seed
002's figure eight, on a unicycle (symmetric and asymmetric limits), the Jackal, and
a differential drive bounded by its wheels alone. Checked: the plan's own limit
check, the tightest limit reached with no slow-down, at rest at both ends, never
backwards, on the curve (at the grid's path parameters and densely, against the
curve sampled on its own), and faster than the curve scaled uniformly to its limits
(``flat_trajectory(timing="fastest")``), strictly where the curvature varies.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial import cKDTree

import trajkit as tk
from support import LIMIT_TOUCH
from trajkit import InvalidInputError
from trajkit.mobile import (
    DiffDrive,
    FigureEight,
    MobileLimits,
    MobileTrajectory,
    Unicycle,
    flat_trajectory,
    jackal,
    spline_output,
    time_optimal,
)

# Tolerances ---------------------------------------------------------------------
ON_CURVE = 1e-6  # m: a sampled position from the densely sampled curve
AT_GRID = 1e-9  # m: positions at the grid's path parameters against the curve there
REST = 1e-9  # m/s, rad/s: the twist at both ends
KEPT = 1e-9  # relative: the check's slack on a bound
DENSE_CURVE = 400_001  # samples of the curve on its own (chords within ~1e-9 m of it)
DENSE_PLAN = 4001  # samples of the plan

# A natural cubic spline moves at its ends (no stop inside): a 2-DoF Trajectory in m.
SPLINE = tk.cubic_spline(np.arange(5.0), [[0, 0], [2, 1], [3, 3], [1, 4], [0, 2.5]],
                         bc="natural")  # fmt: skip
FIGURE_EIGHT = FigureEight(4.0, 2.0, 10.0)
SYMMETRIC = MobileLimits(velocity=1.0, angular_velocity=2.0, acceleration=1.0,
                         angular_acceleration=3.0)  # fmt: skip
ASYMMETRIC = MobileLimits(velocity=(-0.5, 1.5), angular_velocity=1.0, acceleration=(-2.0, 1.0))
WHEELS_ONLY = DiffDrive(
    wheel_radius=0.1,
    track_width=0.5,
    wheel_speed_limit=10.0,
    limits=MobileLimits(acceleration=1.0, angular_acceleration=2.0),
)

# name: (curve, model, limits, at most this fraction of the uniformly scaled duration)
CASES = {
    # Measured 9.903 s vs 10.394 s (0.953).
    "spline_unicycle": (SPLINE, Unicycle(), SYMMETRIC, 0.97),
    # Measured 7.829 s vs 9.979 s (0.785).
    "spline_asymmetric": (SPLINE, Unicycle(), ASYMMETRIC, 0.8),
    # Measured 5.132 s vs 5.715 s (0.898): the Jackal's own limits, wheels included.
    "spline_jackal": (SPLINE, jackal(), None, 0.92),
    # Measured 10.919 s vs 11.304 s (0.966): rates bounded by the wheels alone.
    "spline_wheels_only": (SPLINE, WHEELS_ONLY, None, 0.98),
    # Measured 13.447 s vs 17.772 s (0.757).
    "eight_unicycle": (FIGURE_EIGHT, Unicycle(), SYMMETRIC, 0.78),
    # Measured 7.525 s vs 8.926 s (0.843).
    "eight_jackal": (FIGURE_EIGHT, jackal(), None, 0.86),
}

_PLANS: dict[str, MobileTrajectory] = {}


def plan_for(name: str) -> MobileTrajectory:
    """The time-optimal plan of a case, made once (several tests read it)."""
    if name not in _PLANS:
        curve, model, limits, _ = CASES[name]
        _PLANS[name] = time_optimal(curve, model=model, limits=limits)
    return _PLANS[name]


def curve_points(curve, s: np.ndarray) -> np.ndarray:
    if isinstance(curve, tk.Trajectory):
        return curve(s)
    return curve.evaluate(s, 0)


def curve_span(curve) -> tuple[float, float]:
    if isinstance(curve, tk.Trajectory):
        return curve.start_time, curve.end_time
    return 0.0, curve.duration


def distance_to(points: np.ndarray, dense: np.ndarray) -> np.ndarray:
    """Distance of each point from the polyline through ``dense`` (the two chords at the
    nearest vertex; the chords stray from the curve by h²κ/8, ~1e-9 m here)."""
    _, nearest = cKDTree(dense).query(points)
    best = np.full(points.shape[0], np.inf)
    for first in (nearest - 1, nearest):
        valid = (first >= 0) & (first + 1 < dense.shape[0])
        a = dense[np.clip(first, 0, dense.shape[0] - 2)]
        b = dense[np.clip(first + 1, 1, dense.shape[0] - 1)]
        chord = b - a
        along = np.einsum("ij,ij->i", points - a, chord) / np.einsum("ij,ij->i", chord, chord)
        foot = a + np.clip(along, 0.0, 1.0)[:, None] * chord
        best = np.where(valid, np.minimum(best, np.linalg.norm(points - foot, axis=1)), best)
    return best


def peak_ratio(report: tk.Report) -> float:
    worst = 0.0
    for quantity, (low, high) in report.peaks.items():
        lower, upper = report.bounds[quantity]
        worst = max(worst, float(np.max(np.maximum(high / upper, low / lower))))
    return worst


# ----------------------------------------------------------------------- properties
@pytest.mark.parametrize("name", sorted(CASES))
def test_the_plan_keeps_its_limits_and_reaches_the_tightest(name):
    plan = plan_for(name)
    report = plan.check()
    assert report.ok, str(report)
    assert plan.info["plan"] == "time_optimal"
    # The reachability timing kept every limit: the final check slowed nothing down...
    assert plan.info["time_scale"] == pytest.approx(1.0, abs=KEPT)
    # ... and the tightest limit is reached: the plan is not needlessly slow.
    assert 1.0 - LIMIT_TOUCH <= peak_ratio(report) <= 1.0 + KEPT, str(report)
    _, model, limits, _ = CASES[name]
    assert plan.limits == (model.limits if limits is None else limits)


@pytest.mark.parametrize("name", sorted(CASES))
def test_at_rest_at_both_ends_and_never_backwards(name):
    plan = plan_for(name)
    np.testing.assert_allclose(plan.twist(np.array([0.0, plan.duration])), 0.0, atol=REST)
    t = np.linspace(0.0, plan.duration, DENSE_PLAN)
    assert plan.state(t).v.min() >= -1e-12


@pytest.mark.parametrize("name", sorted(CASES))
def test_the_base_follows_the_curve(name):
    curve, _, _, _ = CASES[name]
    plan = plan_for(name)
    start, end = curve_span(curve)
    # At the grid's path parameters: the timed curve's breakpoints are the grid points.
    (segment,) = plan.segments
    s = plan.info["grid_points"]
    drive = segment.output.trajectory
    assert drive.breakpoints.size == s.size
    reached = plan.pose(drive.breakpoints * segment.scale)[:, :2]
    np.testing.assert_allclose(reached, curve_points(curve, s + start), rtol=0, atol=AT_GRID)
    # Densely, with no knowledge of the timing: every position lies on the curve.
    dense = curve_points(curve, np.linspace(start, end, DENSE_CURVE))
    positions = plan.pose(np.linspace(0.0, plan.duration, DENSE_PLAN))[:, :2]
    assert distance_to(positions, dense).max() <= ON_CURVE  # measured 6e-11 to 1.3e-10 m
    np.testing.assert_allclose(plan.start_pose[:2], dense[0], atol=AT_GRID)
    np.testing.assert_allclose(plan.end_pose[:2], dense[-1], atol=AT_GRID)


@pytest.mark.parametrize("name", sorted(CASES))
def test_faster_than_the_curve_scaled_uniformly_to_its_limits(name):
    curve, model, limits, at_most = CASES[name]
    plan = plan_for(name)
    uniform = flat_trajectory(curve, model=model, limits=limits, timing="fastest")
    assert uniform.check().ok
    # Both curves vary in curvature: a speed profile beats any single time scale.
    assert plan.duration <= at_most * uniform.duration


@pytest.mark.parametrize("name", ["spline_jackal", "spline_wheels_only", "eight_jackal"])
def test_wheel_speed_limits_hold_and_bind_on_a_differential_drive(name):
    _, model, _, _ = CASES[name]
    plan = plan_for(name)
    limit = model.wheel_speed_limit
    report = plan.check()
    low, high = report.peaks["wheel speed"]
    assert max(-low.min(), high.max()) <= limit * (1.0 + KEPT)
    sampled = np.abs(plan.wheel_speeds(np.linspace(0.0, plan.duration, 20_001)))
    assert sampled.max() <= limit * (1.0 + KEPT)
    assert sampled.max() >= limit * (1.0 - 1e-6)  # the wheels bind: measured 1 - 2e-9


def test_a_trajectory_starting_late_is_read_from_its_start():
    late = tk.Trajectory(SPLINE.breakpoints + 5.0, SPLINE.coefficients)
    plan = time_optimal(late, model=Unicycle(), limits=SYMMETRIC)
    reference = plan_for("spline_unicycle")
    assert plan.duration == pytest.approx(reference.duration, rel=1e-12)
    t = np.linspace(0.0, plan.duration, 101)
    np.testing.assert_allclose(plan.pose(t), reference.pose(t), atol=1e-12)


def test_a_finer_grid_is_not_slower():
    coarse = time_optimal(FIGURE_EIGHT, model=Unicycle(), limits=SYMMETRIC, grid=100)
    assert coarse.check().ok
    # Measured 13.505 s on 100 intervals, 13.447 s on 500.
    fine = plan_for("eight_unicycle").duration
    assert fine <= coarse.duration <= 1.01 * fine


# --------------------------------------------------------- curves at rest at their ends
REST_TO_REST = spline_output([[0, 0], [2, 1], [3, 3], [1, 4]])


def test_a_curve_at_rest_at_its_ends_is_not_slower_than_uniform_scaling():
    limits = MobileLimits(velocity=1.0, acceleration=1.0)
    plan = time_optimal(REST_TO_REST, model=Unicycle(), limits=limits)
    uniform = flat_trajectory(REST_TO_REST, model=Unicycle(), limits=limits, timing="fastest")
    assert plan.check().ok
    assert plan.duration <= uniform.duration


def test_the_jackal_on_a_curve_at_rest_at_its_ends_needs_no_slow_down():
    plan = time_optimal(REST_TO_REST, model=jackal())
    uniform = flat_trajectory(REST_TO_REST, model=jackal(), timing="fastest")
    assert plan.info["time_scale"] == pytest.approx(1.0, abs=KEPT)
    assert plan.duration <= uniform.duration


# ------------------------------------------------------------------------- bad input
@pytest.mark.parametrize(
    ("output", "message"),
    [
        ([[0.0, 0.0], [1.0, 1.0]], "output must be a FlatOutput or a 2-DoF Trajectory, got list"),
        (np.zeros((3, 2)), "output must be a FlatOutput or a 2-DoF Trajectory, got ndarray"),
        (tk.cubic_spline([0.0, 1.0], [0.0, 1.0]), "must be a 2-DoF Trajectory (x, y)"),
    ],
)
def test_output_must_be_a_flat_output(output, message):
    with pytest.raises(InvalidInputError) as e:
        time_optimal(output, limits=SYMMETRIC)
    assert message in str(e.value)


NEEDS = "a time-optimal timing needs a bound on a rate"


@pytest.mark.parametrize(
    ("limits", "parts"),
    [
        (MobileLimits(velocity=1.0), [NEEDS, "and on an acceleration", "velocity=(-1, 1)"]),
        (MobileLimits(velocity=1.0, angular_velocity=2.0), [NEEDS, "angular_velocity=(-2, 2)"]),
        (MobileLimits(acceleration=1.0), [NEEDS, "wheel_speed", "acceleration=(-1, 1)"]),
        (MobileLimits(angular_acceleration=1.0), [NEEDS, "angular_acceleration=(-1, 1)"]),
        (MobileLimits(velocity=1.0, acceleration=(0.0, 1.0)), ["allow slowing down", "< 0"]),
        (
            MobileLimits(velocity=1.0, acceleration=1.0, angular_acceleration=(0.0, 2.0)),
            ["acceleration bounds must allow slowing down (lower side < 0)"],
        ),
        ({"velocity": 1.0}, ["limits must be a trajkit.mobile.MobileLimits, got dict"]),
    ],
)
def test_limits_need_a_rate_and_a_braking_acceleration(limits, parts):
    with pytest.raises(InvalidInputError) as e:
        time_optimal(SPLINE, model=Unicycle(), limits=limits)
    for part in parts:
        assert part in str(e.value)


def test_a_unicycle_has_no_wheels_to_limit():
    with pytest.raises(InvalidInputError, match="wheel_speed limit needs a DiffDrive model"):
        time_optimal(SPLINE, model=Unicycle(),
                     limits=MobileLimits(wheel_speed=1.0, acceleration=1.0))  # fmt: skip


def test_the_model_must_be_a_mobile_model():
    with pytest.raises(InvalidInputError, match=r"model must be a trajkit\.mobile Unicycle or"):
        time_optimal(SPLINE, model="jackal", limits=SYMMETRIC)


@pytest.mark.parametrize("grid", [100, 500])
@pytest.mark.parametrize(
    "waypoints",
    [[[0, 0], [2, 1], [4, 0], [5, 2]], [[0, 0], [3, 1]], [[0, 0], [1, 0], [2, 1]]],
    ids=["readme", "straight", "bend"],
)
def test_curves_at_rest_need_no_slow_down_on_coarse_and_fine_grids(waypoints, grid):
    """Regression: heading rates near a stop at the curve's end were rounding noise."""
    curve = spline_output(waypoints)
    plan = time_optimal(curve, model=jackal(), grid=grid)
    uniform = flat_trajectory(curve, model=jackal(), timing="fastest")
    assert plan.check().ok
    assert plan.info["time_scale"] == pytest.approx(1.0, abs=1e-9)
    assert plan.duration < uniform.duration
