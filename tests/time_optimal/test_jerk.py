"""Jerk-limited time-optimal timing (trajkit.time_optimal.jerk): limits kept, tightest reached.

``tk.topp`` with a ``jerk`` bound smooths the velocity/acceleration-optimal s(t) by a
moving average and scales it uniformly to the tightest limit. Checked here: every
limit holds exactly (``check``), the tightest one is reached (not needlessly slow),
the motion is at rest with zero acceleration at both ends and wherever the path's
tangent or curvature jumps, it is never faster than the unlimited optimum and tends
to it as the jerk bound grows, and a straight leg is never faster than the exact
jerk-limited optimum (``tk.scurve``). With non-zero boundary speeds: the motion
starts and ends exactly at the path's ends, at those speeds, with zero path
acceleration, and keeps every limit. ``moving_average`` against numerical
quadrature.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp
from scipy.integrate import quad

import trajkit as tk
from support import assert_continuous
from trajkit.time_optimal import topp
from trajkit.time_optimal.jerk import moving_average

# Tolerances ---------------------------------------------------------------------
TOUCH = 1e-6  # relative: the tightest peak of the scaled timing vs its bound
KEPT = 1e-9  # relative: check()'s own slack on a bound
REST = 1e-9  # absolute (rad/s, rad/s²): velocity and acceleration at a rest
ENDS = 1e-9  # absolute (rad): positions at the ends against the path's ends
QUADRATURE = 1e-9  # relative to max(1, |f|): moving average against scipy's quad
FEW = settings(max_examples=15, deadline=None)

VA = tk.Limits(velocity=1.0, acceleration=2.0)


def with_jerk(jerk: float, velocity: float = 1.0, acceleration: float = 2.0) -> tk.Limits:
    return tk.Limits(velocity=velocity, acceleration=acceleration, jerk=jerk)


def spline(seed: int, ndof: int = 3, points: int = 5) -> tk.Trajectory:
    rng = np.random.default_rng(seed)
    return tk.cubic_spline(np.linspace(0, 1, points), rng.uniform(-1, 1, (points, ndof)),
                           bc="natural")  # fmt: skip


def peak_ratios(trajectory: tk.Trajectory, limits: tk.Limits) -> dict[str, float]:
    """Largest peak / bound of each limited quantity (both sides, every joint)."""
    report = trajectory.check(limits)
    out = {}
    for quantity, (low, high) in report.peaks.items():
        lower, upper = report.bounds[quantity]
        out[quantity] = float(np.max(np.maximum(high / upper, low / lower)))
    return out


def jerk_timed(path: tk.Trajectory, limits: tk.Limits, grid: int) -> tk.Trajectory:
    """``topp`` with a jerk bound (kept as one place to call it from the properties)."""
    return topp(path, limits, grid=grid)


def rest_time(timed: tk.Trajectory, point: np.ndarray) -> float:
    """The breakpoint of ``timed`` where it passes through ``point``."""
    distance = np.abs(timed(timed.breakpoints) - point).max(axis=1)
    k = int(np.argmin(distance))
    assert distance[k] <= ENDS, f"the timing never passes {point} (closest {distance[k]:.3g})"
    return float(timed.breakpoints[k])


def assert_at_rest(timed: tk.Trajectory, t: float) -> None:
    """Velocity and acceleration vanish at ``t`` from both sides."""
    for when in (np.nextafter(t, -np.inf), t):
        np.testing.assert_allclose(timed.velocity(when), 0.0, rtol=0, atol=REST)
        np.testing.assert_allclose(timed.acceleration(when), 0.0, rtol=0, atol=REST)


# Smooth random paths ------------------------------------------------------------------
@FEW
@given(
    ndof=st.integers(1, 4),
    steps=hnp.arrays(np.float64, (5,), elements=st.floats(0.2, 1.0)),
    data=st.data(),
    velocity=st.floats(0.5, 3.0),
    acceleration=st.floats(0.5, 5.0),
    jerk=st.floats(0.3, 1000.0),
)
def test_random_splines_keep_every_limit_and_reach_the_tightest(
    ndof, steps, data, velocity, acceleration, jerk
):
    points = data.draw(hnp.arrays(np.float64, (6, ndof), elements=st.floats(-1.0, 1.0),
                                   fill=st.nothing()))  # fmt: skip
    assume(np.abs(np.diff(points, axis=0)).max() > 0.05)  # the path moves
    knots = np.concatenate([[0.0], np.cumsum(steps)])
    path = tk.cubic_spline(knots, points, bc="natural")
    limits = with_jerk(jerk, velocity, acceleration)
    timed = jerk_timed(path, limits, grid=100)

    report = timed.check(limits)
    assert report.ok, str(report)
    ratios = peak_ratios(timed, limits)
    # Scaled to the tightest limit: reached, so the timing is not needlessly slow.
    assert 1.0 - TOUCH <= max(ratios.values()) <= 1.0 + KEPT, ratios
    # At rest with zero acceleration at both ends, on the path's ends.
    assert_at_rest(timed, timed.start_time)
    assert_at_rest(timed, timed.end_time)
    np.testing.assert_allclose(timed(timed.start_time), path(knots[0]), rtol=0, atol=ENDS)
    np.testing.assert_allclose(timed(timed.end_time), path(knots[-1]), rtol=0, atol=ENDS)
    assert timed.start_time == 0.0
    assert timed.info["jerk_limited"] is True
    assert timed.info["rests"].size == 0  # a cubic spline is C2: nowhere to stop inside
    # Never faster than the velocity/acceleration optimum on the same grid.
    unlimited = topp(path, tk.Limits(velocity=velocity, acceleration=acceleration), grid=100)
    assert timed.duration >= unlimited.duration * (1.0 - 1e-12)


def test_duration_tends_to_the_unlimited_optimum_as_the_jerk_bound_grows():
    path = spline(0)
    unlimited = topp(path, VA, grid=200).duration
    durations = []
    for jerk in (1.0, 10.0, 100.0, 1e3, 1e4):
        timed = topp(path, with_jerk(jerk), grid=200)
        assert timed.check(with_jerk(jerk)).ok
        durations.append(timed.duration)
    ratios = np.array(durations) / unlimited
    # Measured: 1.858, 1.064, 1.0029, 1.00029, 1.000029 (unlimited 6.822 s).
    assert np.all(ratios >= 1.0)
    assert np.all(np.diff(ratios) <= 0.0), ratios
    assert ratios[1] > 1.01  # a low bound does cost time
    assert ratios[-1] - 1.0 < 1e-3  # jerk 1e4: within 0.1% (the brief asks 1%)


# Where the path's curvature or tangent jumps ---------------------------------------------
C1_VELOCITIES = {
    "slow_start": [[0.5, 0.2], [1.0, 1.0], [0.3, 1.0]],
    "tilted": [[1.0, 0.5], [0.8, 0.7], [0.2, 1.0]],
}


def c1_path(velocities) -> tk.Trajectory:
    """Two cubics, C1 at s = 1, their second derivatives different there."""
    return tk.cubic_via([0.0, 1.0, 2.0], [[0.0, 0.0], [1.0, 0.5], [1.5, 2.0]], velocities)


@pytest.mark.parametrize("grid", [100, 200])
@pytest.mark.parametrize("name", sorted(C1_VELOCITIES))
def test_curvature_jump_brings_the_path_to_rest(name, grid):
    path = c1_path(C1_VELOCITIES[name])
    left, right = path.evaluate(np.nextafter(1.0, 0.0), 2), path.evaluate(1.0, 2)
    assert np.abs(left - right).max() > 0.1  # the curvature does jump
    np.testing.assert_allclose(path.evaluate(np.nextafter(1.0, 0.0), 1), path.evaluate(1.0, 1),
                               atol=1e-12)  # fmt: skip
    limits = with_jerk(10.0)
    timed = topp(path, limits, grid=grid)
    report = timed.check(limits)
    assert report.ok, str(report)
    assert max(peak_ratios(timed, limits).values()) >= 1.0 - TOUCH
    np.testing.assert_array_equal(timed.info["rests"], [1.0])
    assert_at_rest(timed, rest_time(timed, path(1.0)))
    assert_at_rest(timed, timed.end_time)
    # Without the jerk bound the timing passes s = 1 at speed: the stop is the jerk's.
    unlimited = topp(path, VA, grid=grid)
    (at_one,) = np.flatnonzero(unlimited.info["grid_points"] == 1.0)
    assert unlimited.info["path_speed"][at_one] > 0.1
    assert timed.duration > unlimited.duration


def corner_path() -> tk.Trajectory:
    """(0, 0) -> (1, 0) -> (1, 1): two straight legs meeting at a right angle."""
    return tk.Trajectory([0.0, 1.0, 2.0], np.array([[[1, 0], [0, 1]], [[0, 0], [1, 0]]], float))


@pytest.mark.parametrize("jerk", [1.0, 100.0, 1e4])
def test_sharp_corner_stops_and_no_leg_beats_the_exact_scurve(jerk):
    path = corner_path()
    limits = with_jerk(jerk)
    timed = topp(path, limits, grid=333)
    report = timed.check(limits)
    assert report.ok, str(report)
    np.testing.assert_array_equal(timed.info["rests"], [1.0])
    assert_at_rest(timed, rest_time(timed, [1.0, 0.0]))
    # Each leg moves one joint by 1 with the other still: a 1-D rest-to-rest move,
    # whose exact jerk-limited optimum is the double-S profile. Never faster than it;
    # measured 10.2% over at jerk 1 and 0.0008% over at jerk 100 and 1e4.
    optimum = 2.0 * tk.scurve(0.0, 1.0, 1.0, 2.0, jerk).duration
    assert optimum * (1.0 - 1e-12) <= timed.duration <= 1.11 * optimum


@pytest.mark.parametrize(
    "path", [corner_path(), c1_path([[1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])], ids=["corner", "c1"]
)
def test_jerk_limited_timing_does_not_crash_on_uniform_grid_steps(path):
    limits = with_jerk(10.0)
    timed = topp(path, limits, grid=200)
    assert timed.check(limits).ok


def assert_moving_ends(timed, path, speeds, limits):
    """Every limit kept; the ends at the path's ends, at their speeds, with s̈ = 0."""
    assert timed.check(limits).ok
    ends = [0.0, timed.end_time]
    s_ends = path.breakpoints[[0, -1]]
    np.testing.assert_allclose(timed(ends), path(s_ends), rtol=0, atol=ENDS)
    for k, (t, s, speed) in enumerate(zip(ends, s_ends, speeds, strict=True)):
        # q̇ = q' ṡ and q̈ = q'' ṡ² + q' s̈ with s̈ = 0: read a hair inside the end.
        side = np.nextafter(s, path.breakpoints[1 - k]) if k else s
        np.testing.assert_allclose(timed.velocity(t), path.evaluate(side, 1) * speed,
                                   rtol=0, atol=REST)  # fmt: skip
        np.testing.assert_allclose(timed.acceleration(t), path.evaluate(side, 2) * speed**2,
                                   rtol=0, atol=REST)  # fmt: skip


@pytest.mark.parametrize("speeds", [(0.05, 0.0), (0.0, 0.05), (0.04, 0.03)])
def test_non_zero_boundary_speeds_are_kept_with_a_jerk_bound(speeds):
    path, limits = spline(1), with_jerk(10.0)
    timed = topp(path, limits, start_speed=speeds[0], end_speed=speeds[1])
    assert_moving_ends(timed, path, speeds, limits)
    assert timed.info["jerk_limited"] and timed.info["continuity"] == 2
    assert_continuous(timed, 2)
    # Entering and leaving at speed is faster than from rest to rest.
    assert timed.duration < topp(path, limits).duration


def test_a_moving_start_and_a_corner_rest():
    path, limits = corner_path(), with_jerk(20.0)
    timed = topp(path, limits, grid=300, start_speed=0.1)
    assert_moving_ends(timed, path, (0.1, 0.0), limits)
    corner = timed.first_time_at([1.0, 0.0])[0]
    np.testing.assert_allclose(timed.velocity(corner), 0.0, atol=REST)


@FEW
@given(seed=st.integers(0, 2**31), fractions=st.tuples(st.floats(0.0, 0.8), st.floats(0.0, 0.8)),
       jerk=st.floats(2.0, 200.0))  # fmt: skip
def test_property_moving_ends_keep_every_limit(seed, fractions, jerk):
    path, limits = spline(seed), with_jerk(jerk)
    # The fastest ṡ each end allows under the velocity limit, times a fraction.
    fastest = [1.0 / np.abs(path.evaluate(s, 1)).max() for s in path.breakpoints[[0, -1]]]
    speeds = tuple(float(f * v) for f, v in zip(fractions, fastest, strict=True))
    try:
        timed = topp(path, limits, start_speed=speeds[0], end_speed=speeds[1])
    except tk.InfeasibleError as exc:  # too fast to hold for the window: said so
        assert "start_speed" in str(exc) and "end_speed" in str(exc)
        return
    assert_moving_ends(timed, path, speeds, limits)


def test_boundary_speeds_beyond_the_limits_are_refused_by_name():
    with pytest.raises(tk.InfeasibleError, match=r"start_speed 0\.2 .* breaks the limits there"):
        topp(spline(1), with_jerk(10.0), start_speed=0.2, end_speed=0.3)


# moving_average ----------------------------------------------------------------------
@st.composite
def piecewise_quadratics(draw: st.DrawFn) -> tuple[np.ndarray, np.ndarray]:
    """Continuous piecewise quadratics: breakpoints and ascending local coefficients."""
    pieces = draw(st.integers(1, 6))
    start = draw(st.floats(-2.0, 2.0))
    steps = draw(hnp.arrays(np.float64, (pieces,), elements=st.floats(0.05, 2.0)))
    times = start + np.concatenate([[0.0], np.cumsum(steps)])
    slopes = draw(hnp.arrays(np.float64, (pieces, 2), elements=st.floats(-3.0, 3.0)))
    sigma = np.zeros((pieces, 3))
    sigma[:, 1:] = slopes
    sigma[0, 0] = draw(st.floats(-2.0, 2.0))
    for i in range(1, pieces):  # continuous: each piece starts where the last ends
        sigma[i, 0] = np.polynomial.polynomial.polyval(steps[i - 1], sigma[i - 1])
    return times, sigma


def held(times: np.ndarray, sigma: np.ndarray):
    """f(t), held at its end values outside [t_0, t_M]: an independent evaluator."""
    end = float(np.polynomial.polynomial.polyval(times[-1] - times[-2], sigma[-1]))

    def f(t: float) -> float:
        if t <= times[0]:
            return float(sigma[0, 0])
        if t >= times[-1]:
            return end
        k = int(np.searchsorted(times, t, side="right")) - 1
        return float(np.polynomial.polynomial.polyval(t - times[k], sigma[k]))

    return f, end


def as_trajectory(edges: np.ndarray, average: np.ndarray) -> tk.Trajectory:
    """The average as a Trajectory (its edges are distinct: no piece is dropped)."""
    return tk.Trajectory(edges, average[:, ::-1].T[:, :, None])


@FEW
@given(piecewise_quadratics(), st.floats(0.01, 6.0))
def test_moving_average_matches_quadrature(function, window):
    times, sigma = function
    f, _ = held(times, sigma)
    edges, average = moving_average(times, sigma, window)
    assert average.shape[1] == sigma.shape[1] + 1  # one degree more
    assert edges[0] == 0.0
    span = times[-1] - times[0] + window
    assert edges[-1] == pytest.approx(span, rel=1e-12)
    curve = as_trajectory(edges, average)
    t = np.linspace(0.0, edges[-1], 41)
    values = curve(t)[:, 0]
    worst = 0.0
    for local, value in zip(t, values, strict=True):
        centre = times[0] - window / 2.0 + local
        low, high = centre - window / 2.0, centre + window / 2.0
        inside = [float(p) for p in times if low < p < high]
        exact, _ = quad(f, low, high, points=inside or None, epsabs=1e-12, epsrel=1e-12,
                        limit=200)  # fmt: skip
        exact /= window
        worst = max(worst, abs(value - exact) / max(1.0, abs(exact)))
    assert worst <= QUADRATURE


@FEW
@given(piecewise_quadratics(), st.floats(0.01, 6.0))
def test_moving_average_is_c1_and_starts_and_ends_at_the_held_values(function, window):
    times, sigma = function
    _, end = held(times, sigma)
    edges, average = moving_average(times, sigma, window)
    scale = max(1.0, float(np.abs(sigma).max()) * max(1.0, times[-1] - times[0]))
    curve = as_trajectory(edges, average)
    # Value and first derivative continuous (the second jumps with f's first).
    assert_continuous(curve, 1, rtol=1e-10 * scale)
    f_start, f_end = curve(curve.start_time)[0], curve(curve.end_time)[0]
    assert f_start == pytest.approx(sigma[0, 0], abs=1e-12 * scale)
    assert f_end == pytest.approx(end, abs=1e-10 * scale)
    # f_w' = (f(t + w/2) - f(t - w/2)) / w: 0 at both ends, where f is held;
    # f_w'' = (f'(t + w/2) - f'(t - w/2)) / w: f'(t_0+) / w and -f'(t_M-) / w.
    np.testing.assert_allclose(curve.velocity([curve.start_time, curve.end_time]), 0.0,
                               atol=1e-10 * scale)  # fmt: skip
    slope_end = sigma[-1, 1] + 2.0 * sigma[-1, 2] * (times[-1] - times[-2])
    second = curve.acceleration([curve.start_time, curve.end_time])[:, 0]
    np.testing.assert_allclose(second, [sigma[0, 1] / window, -slope_end / window],
                               rtol=1e-9, atol=1e-10 * scale / window)  # fmt: skip


@pytest.mark.parametrize(
    ("times", "window"),
    [(np.arange(4) * 0.05, 0.1), (np.array([0.0, 0.05]), 2.0), (np.array([0.0, 0.1, 0.3]), 0.2)],
    ids=["uniform_steps", "one_piece", "knot_pair"],
)
def test_moving_average_edges_are_distinct(times, window):
    pieces = times.size - 1
    sigma = np.stack([times[:-1], np.ones(pieces), np.zeros(pieces)], axis=1)  # f(t) = t
    edges, _ = moving_average(times, sigma, window)
    assert np.all(np.diff(edges) > 1e-12 * edges[-1]), np.diff(edges)
