"""Tests of trajkit.mobile.flatness: flat outputs, the unicycle's twist from them,
timing to the limits, and stops (reverse, turn, error).

The formulas are compared with a slow, obviously-correct evaluator: the heading
is atan2(ẏ, ẋ) of the output's own derivative, ω and dω/dt its finite differences,
v = |ṗ| and dv/dt its finite difference.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import support
import trajkit as tk
from support import CLOSED_FORM, FINITE_DIFFERENCE, LIMIT_TOUCH, ROUNDING
from trajkit import InfeasibleError, InvalidInputError
from trajkit.mobile import (
    DiffDrive,
    FigureEight,
    FlatOutput,
    MobileLimits,
    TrajectoryOutput,
    Unicycle,
    flat_trajectory,
    jackal,
    spline_output,
)
from trajkit.mobile.limits import QUANTITIES

# Tolerances and steps --------------------------------------------------------------
FD_FIRST = 1e-4  # step of five-point first differences, a fraction of the output's duration
FD_SECOND = 1e-4  # step of five-point second differences (rounding grows as 1/h²)
STOP_LIMIT = 1e-6  # relative: a stop's limits against the Richardson-extrapolated formulas
CHECK_GRID = 200_001  # samples of the dense grid that checks the reported extrema
EXPENSIVE = settings(max_examples=20, deadline=None)
MEDIUM = settings(max_examples=50, deadline=None)

EIGHT = FigureEight(2.0, 1.0, 20.0)
WAYPOINTS = [[0.0, 0.0], [1.0, 0.0], [2.0, 1.0], [1.0, 2.0]]
A, B, C = np.array([0.0, 0.0]), np.array([1.0, 0.5]), np.array([1.0, 1.5])
STOP_LIMITS = MobileLimits(velocity=2.0, angular_velocity=2.0, acceleration=5.0,
                           angular_acceleration=5.0)  # fmt: skip


class Cusp(FlatOutput):
    """``(u, u²)`` with ``u = sin(π t / T)``: out along a parabola and back, stopping
    at ``t = T/2`` with a deceleration (speed linear in ``t - T/2``), not at rest."""

    def __init__(self, period: float = 4.0) -> None:
        self.period = period

    @property
    def duration(self) -> float:
        return self.period

    def evaluate(self, t, order):
        c = math.pi / self.period
        t = np.asarray(t, float)
        x = c**order * np.sin(c * t + order * math.pi / 2)
        if order == 0:
            y = 0.5 - 0.5 * np.cos(2 * c * t)
        else:
            y = -0.5 * (2 * c) ** order * np.cos(2 * c * t + order * math.pi / 2)
        return np.stack([x, y], axis=-1)


def there_and_back() -> tk.Trajectory:
    return tk.quintic(A, B, 1).then(tk.quintic(B, A, 1))


# The slow evaluator ------------------------------------------------------------
def slow_state(output: FlatOutput, t: float, scale: float = 1.0, sign: float = 1.0):
    """θ, v, ω, dv/dt, dω/dt at plan time ``t`` of ``output`` slowed by ``scale``."""
    span = output.duration

    def p1(s: float) -> np.ndarray:
        return output.evaluate(np.array([s]), 1)[0]

    def heading(s: float) -> float:
        d = sign * p1(s)
        return math.atan2(d[1], d[0])

    def speed(s: float) -> float:
        return sign * math.hypot(*p1(s))

    def turn(a: float, b: float) -> float:  # b - a, the short way
        return (b - a + math.pi) % (2 * math.pi) - math.pi

    def around(f, s: float, h: float) -> np.ndarray:  # f at s - 2h ... s + 2h
        return np.array([f(s + k * h) for k in (-2, -1, 0, 1, 2)])

    def first(values: np.ndarray, h: float) -> float:  # five-point stencil, error O(h⁴)
        return float(values @ [1.0, -8.0, 0.0, 8.0, -1.0]) / (12.0 * h)

    def second(values: np.ndarray, h: float) -> float:
        return float(values @ [-1.0, 16.0, -30.0, 16.0, -1.0]) / (12.0 * h**2)

    s, h, h2 = t / scale, FD_FIRST * span, FD_SECOND * span
    # Headings unwrapped around the centre one: the short way from it.
    centre = heading(s)
    headings = [around(lambda x: centre + turn(centre, heading(x)), s, step) for step in (h, h2)]
    omega, angular = first(headings[0], h), second(headings[1], h2)
    acceleration = first(around(speed, s, h), h)
    return np.array([centre, speed(s) / scale, omega / scale, acceleration / scale**2,
                     angular / scale**2])  # fmt: skip


def plan_state(plan, t: float) -> np.ndarray:
    state = plan.state(t)
    return np.array([state.theta[0], state.v[0], state.omega[0], state.acceleration[0],
                     state.angular_acceleration[0]])  # fmt: skip


def assert_matches_slow(plan, output, times, *, scale=1.0, sign=1.0):
    for t in times:
        found, slow = plan_state(plan, t), slow_state(output, t, scale, sign)
        support.assert_heading(found[0], slow[0], atol=ROUNDING)
        support.assert_state(found[1:], slow[1:], rtol=FINITE_DIFFERENCE)


def away_from(knots: np.ndarray, times: np.ndarray, margin: float) -> np.ndarray:
    return times[np.min(np.abs(times[:, None] - knots[None, :]), axis=1) > margin]


# FigureEight ---------------------------------------------------------------------
def test_figure_eight_positions():
    eight = FigureEight(2.0, 1.0, 20.0, center=(0.5, -1.0))
    t = np.linspace(0.0, 20.0, 41)
    expected = np.stack(
        [0.5 + np.sin(2 * np.pi * t / 20), -1.0 + 0.5 * np.sin(4 * np.pi * t / 20)], 1
    )
    support.assert_state(eight.evaluate(t, 0), expected, rtol=ROUNDING)
    w = 2 * np.pi / 20
    velocity = np.stack([w * np.cos(w * t), w * np.cos(2 * w * t)], 1)
    support.assert_state(eight.evaluate(t, 1), velocity, rtol=ROUNDING)
    acceleration = np.stack([-(w**2) * np.sin(w * t), -2 * w**2 * np.sin(2 * w * t)], 1)
    support.assert_state(eight.evaluate(t, 2), acceleration, rtol=ROUNDING)
    assert eight.duration == 20.0
    np.testing.assert_array_equal(eight.breakpoints, [0.0, 20.0])
    assert FigureEight(2.0, 1.0, 20.0, cycles=2.5).duration == 50.0


@pytest.mark.parametrize("order", [1, 2, 3, 4, 5])
def test_figure_eight_derivatives_are_the_differences_of_the_last(order):
    eight = FigureEight(1.3, 0.7, 3.0, center=(2.0, 1.0))
    t = np.linspace(0.1, 2.9, 15)
    h = 1e-5
    difference = (eight.evaluate(t + h, order - 1) - eight.evaluate(t - h, order - 1)) / (2 * h)
    scale = max(1.0, np.abs(eight.evaluate(t, order)).max())
    assert np.abs(eight.evaluate(t, order) - difference).max() <= FINITE_DIFFERENCE * scale


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"width": 0.0}, r"width must be > 0, got 0 m"),
        ({"height": -1.0}, r"height must be > 0, got -1 m"),
        ({"period": 0.0}, r"period must be > 0, got 0 s"),
        ({"cycles": -1.0}, r"cycles must be > 0"),
        ({"center": (1.0, 2.0, 3.0)}, r"center must be \(x, y\) in m, got shape \(3,\)"),
        ({"center": (np.nan, 0.0)}, r"center must be finite"),
    ],
)
def test_figure_eight_refuses_bad_input(kwargs, match):
    arguments = {"width": 2.0, "height": 1.0, "period": 20.0} | kwargs
    center = arguments.pop("center", (0.0, 0.0))
    with pytest.raises(InvalidInputError, match=match):
        FigureEight(**arguments, center=center)


# TrajectoryOutput and spline_output --------------------------------------------------
def test_trajectory_output_reads_from_its_start_time():
    line = tk.quintic(A, B, 2.0)
    late = tk.Trajectory(line.breakpoints + 3.0, line.coefficients)
    output = TrajectoryOutput(late)
    assert output.duration == 2.0
    np.testing.assert_array_equal(output.breakpoints, [0.0, 2.0])
    t = np.linspace(0.0, 2.0, 9)
    for order in range(4):
        np.testing.assert_array_equal(output.evaluate(t, order), late.evaluate(t + 3.0, order))


@pytest.mark.parametrize(
    ("value", "match"),
    [
        (tk.quintic([0.0, 0.0, 0.0], [1.0, 1.0, 1.0], 1.0), r"must be a 2-DoF Trajectory \(x, y\)"),
        ("spline", r"must be a 2-DoF Trajectory"),
        (tk.trapezoidal([0.0, 0.0], [0.0, 0.0], 1.0, 1.0), r"must last longer than 0 s"),
    ],
)
def test_trajectory_output_refuses_bad_trajectories(value, match):
    with pytest.raises(InvalidInputError, match=match):
        TrajectoryOutput(value)


def test_spline_output_passes_the_waypoints_at_rest_at_the_ends():
    output = spline_output(WAYPOINTS)
    chords = np.hypot(*np.diff(np.array(WAYPOINTS), axis=0).T)
    times = np.concatenate([[0.0], np.cumsum(chords)])
    support.assert_state(output.breakpoints, times, rtol=ROUNDING)
    support.assert_state(output.evaluate(times, 0), WAYPOINTS, rtol=CLOSED_FORM)
    np.testing.assert_allclose(output.evaluate(np.array([0.0, times[-1]]), 1), 0.0, atol=1e-14)
    support.assert_continuous(output.trajectory, 2)
    timed = spline_output(WAYPOINTS, [0.0, 1.0, 3.0, 4.0])
    support.assert_state(timed.evaluate(np.array([0.0, 1.0, 3.0, 4.0]), 0), WAYPOINTS,
                         rtol=CLOSED_FORM)  # fmt: skip


@pytest.mark.parametrize(
    ("waypoints", "times", "match"),
    [
        ([0.0, 1.0], None, r"waypoints must have shape \(n, 2\) with n >= 2.*shape \(2,\)"),
        ([[0.0, 1.0]], None, r"waypoints must have shape \(n, 2\).*shape \(1, 2\)"),
        ([[0.0, 0.0, 0.0], [1.0, 1.0, 1.0]], None, r"waypoints must have shape \(n, 2\)"),
        ([[0.0, 0.0], [1.0, 1.0], [1.0, 1.0]], None, r"waypoints 1 and 2 are the same point"),
        ([[0.0, 0.0], [np.nan, 1.0]], None, r"waypoints must be finite"),
        ([[0.0, 0.0], [1.0, 1.0]], [0.0, 1.0, 2.0], r"times must give one time per waypoint"),
        ([[0.0, 0.0], [1.0, 1.0]], [1.0, 0.0], r"times must be strictly increasing"),
    ],
)
def test_spline_output_refuses_bad_input(waypoints, times, match):
    with pytest.raises(InvalidInputError, match=match):
        spline_output(waypoints, times)


# Formulas against the slow evaluator ------------------------------------------------
def test_figure_eight_twist_matches_the_slow_evaluator():
    plan = flat_trajectory(EIGHT)
    assert_matches_slow(plan, EIGHT, np.linspace(0.05, 19.95, 97))


@MEDIUM
@given(st.floats(0.01, 0.99))
def test_figure_eight_twist_matches_the_slow_evaluator_anywhere(fraction):
    eight = FigureEight(1.5, 2.5, 7.0, center=(1.0, -2.0))
    assert_matches_slow(flat_trajectory(eight), eight, [fraction * 7.0])


def test_spline_twist_matches_the_slow_evaluator_between_knots():
    output = spline_output(WAYPOINTS)
    plan = flat_trajectory(output)
    span = output.duration
    times = away_from(output.breakpoints, np.linspace(0.02, 0.98, 60) * span, 3 * FD_SECOND * span)
    assert times.size > 50
    assert_matches_slow(plan, output, times)


def test_slowed_plans_scale_twist_and_rates():
    plan = flat_trajectory(EIGHT, limits=MobileLimits(velocity=0.2), timing="within_limits")
    scale = plan.info["time_scale"]
    assert scale == pytest.approx(0.44428829381583665 / 0.2, rel=1e-9)  # peak |ṗ| = π/√20
    assert plan.duration == pytest.approx(20.0 * scale, rel=ROUNDING)
    assert_matches_slow(plan, EIGHT, np.linspace(0.05, 0.95, 19) * plan.duration, scale=scale)


@EXPENSIVE
@given(
    st.floats(0.2, 5.0), st.floats(0.2, 5.0), st.floats(1.0, 60.0),
    st.sampled_from(["as_given", "within_limits", "fastest"]),
)  # fmt: skip
def test_plans_drive_along_the_output(width, height, period, timing):
    eight = FigureEight(width, height, period, center=(0.3, -0.2))
    plan = flat_trajectory(eight, limits=MobileLimits(velocity=0.5, angular_acceleration=1.0),
                           timing=timing)  # fmt: skip
    scale = plan.info["time_scale"]
    t = np.linspace(0.0, plan.duration, 301)
    state = plan.state(t)
    # Positions are the output's; (v cos θ, v sin θ) is its velocity on the slowed clock.
    support.assert_state(np.stack([state.x, state.y], 1), eight.evaluate(t / scale, 0),
                         rtol=ROUNDING)  # fmt: skip
    support.assert_state(state.world_velocity, eight.evaluate(t / scale, 1) / scale,
                         rtol=ROUNDING)  # fmt: skip


def test_as_given_keeps_the_outputs_clock():
    plan = flat_trajectory(EIGHT)
    assert plan.duration == 20.0
    assert plan.info == {"plan": "flat_output", "time_scale": 1.0, "stops": (),
                         "limited_by": None, "stops_treatment": "error"}  # fmt: skip
    assert [s.kind for s in plan.segments] == ["flat"]
    # A Trajectory is read as its TrajectoryOutput.
    line = tk.quintic(A, B, 1.0)
    direct, wrapped = flat_trajectory(line), flat_trajectory(TrajectoryOutput(line))
    t = np.linspace(0, 1, 11)
    np.testing.assert_array_equal(direct.pose(t), wrapped.pose(t))


# Endpoints at rest -----------------------------------------------------------------
def richardson(values_at_d: np.ndarray, values_at_2d: np.ndarray) -> np.ndarray:
    return 2.0 * values_at_d - values_at_2d


def test_spline_ends_at_rest_have_finite_twist_and_the_direction_of_travel():
    output = spline_output(WAYPOINTS)
    plan = flat_trajectory(output)
    span = plan.duration
    ends = plan.state(np.array([0.0, span]))
    for column in (ends.theta, ends.omega, ends.acceleration, ends.angular_acceleration):
        assert np.all(np.isfinite(column))
    assert np.abs(ends.v).max() <= 1e-15
    # The heading of the direction of travel: leaving the first point, entering the last.
    # The direction of travel: ṗ(t) ≈ p̈(0) t leaving the first point, ≈ -p̈(T) (T - t)
    # entering the last, and the output's velocity an instant inside agrees.
    first, last = output.evaluate(np.array([0.0, span]), 2)
    support.assert_heading(ends.theta[0], math.atan2(first[1], first[0]), atol=CLOSED_FORM)
    support.assert_heading(ends.theta[1], math.atan2(-last[1], -last[0]), atol=CLOSED_FORM)
    leave, enter = output.evaluate(np.array([1e-7 * span, span * (1 - 1e-7)]), 1)
    support.assert_heading(ends.theta[0], math.atan2(leave[1], leave[0]), atol=1e-6)
    support.assert_heading(ends.theta[1], math.atan2(enter[1], enter[0]), atol=1e-6)
    # ω and the rates at the ends are the limits of the formulas: extrapolate the slow
    # evaluator from inside, where the speed is no longer tiny.
    d = 2e-3 * span
    for t, inward in ((0.0, 1.0), (span, -1.0)):
        near, far = slow_state(output, t + inward * d), slow_state(output, t + inward * 2 * d)
        limit = richardson(near, far)
        found = plan_state(plan, t)
        support.assert_heading(found[0], limit[0], atol=1e-4)
        support.assert_state(found[2:], limit[2:], rtol=1e-4)


# Timing ---------------------------------------------------------------------------
limit_values = st.floats(0.05, 5.0)


@st.composite
def some_limits(draw: st.DrawFn, wheels: bool) -> MobileLimits:
    """One to all of the limits (the wheel limit only for a diff drive), some asymmetric."""
    attributes = [a for a, _, _ in QUANTITIES if wheels or a != "wheel_speed"]
    chosen = draw(st.lists(st.sampled_from(attributes), min_size=1, unique=True))
    given_limits = {}
    for attribute in chosen:
        value = draw(limit_values) * (10.0 if attribute == "wheel_speed" else 1.0)
        if draw(st.booleans()):
            given_limits[attribute] = (-draw(limit_values), value)
        else:
            given_limits[attribute] = value
    return MobileLimits(**given_limits)


def peak_ratios(plan, limits: MobileLimits) -> dict[str, float]:
    """Largest |peak| / |bound| of every limited quantity, exact from check()."""
    report = plan.check(limits)
    ratios = {}
    for quantity, (low, high) in report.peaks.items():
        lower, upper = report.bounds[quantity]
        ratios[quantity] = float(
            max(np.max(high / upper), np.max(np.where(low < 0, low / lower, 0)))
        )
    return ratios


def sampled_excess(plan, limits: MobileLimits, count: int = 20_001) -> float:
    """Largest sampled value / bound over a uniform grid, independent of check()."""
    t = np.linspace(0.0, plan.duration, count)
    state = plan.state(t)
    sampled = {"velocity": state.v, "angular_velocity": state.omega,
               "acceleration": state.acceleration,
               "angular_acceleration": state.angular_acceleration}  # fmt: skip
    if limits.wheel_speed is not None:
        sampled["wheel_speed"] = plan.wheel_speeds(t).ravel()
    worst = 0.0
    for attribute, values in sampled.items():
        bounds = getattr(limits, attribute)
        if bounds is not None:
            lower, upper = float(bounds.lower), float(bounds.upper)
            worst = max(worst, values.max() / upper, values.min() / lower if lower else 0.0)
    return worst


def outputs() -> st.SearchStrategy:
    eights = st.builds(FigureEight, st.floats(0.2, 5.0), st.floats(0.2, 5.0), st.floats(1.0, 60.0))
    return st.one_of(eights, st.just(spline_output(WAYPOINTS)))


@MEDIUM
@given(outputs(), st.booleans(), st.data())
def test_within_limits_never_exceeds_them(output, wheels, data):
    model = DiffDrive(0.1, 0.4) if wheels else Unicycle()
    limits = data.draw(some_limits(wheels))
    plan = flat_trajectory(output, model=model, limits=limits, timing="within_limits")
    assert plan.check(limits).ok
    assert sampled_excess(plan, limits) <= 1.0 + 1e-9
    scale = plan.info["time_scale"]
    assert scale >= 1.0
    ratios = peak_ratios(plan, limits)
    if scale > 1.0:  # slowed just enough: the tightest limit is reached
        assert max(ratios.values()) == pytest.approx(1.0, rel=LIMIT_TOUCH)
        assert plan.info["limited_by"] in ratios
    else:
        assert plan.info["limited_by"] is None and plan.duration == output.duration


@MEDIUM
@given(outputs(), st.booleans(), st.data())
def test_fastest_touches_the_tightest_limit(output, wheels, data):
    model = DiffDrive(0.1, 0.4) if wheels else Unicycle()
    limits = data.draw(some_limits(wheels))
    plan = flat_trajectory(output, model=model, limits=limits, timing="fastest")
    assert plan.check(limits).ok
    assert sampled_excess(plan, limits) <= 1.0 + 1e-9
    ratios = peak_ratios(plan, limits)
    tightest = max(ratios, key=ratios.get)
    assert ratios[tightest] == pytest.approx(1.0, rel=LIMIT_TOUCH)
    assert ratios[plan.info["limited_by"]] == pytest.approx(1.0, rel=LIMIT_TOUCH)


def test_fastest_on_the_jackal_reaches_a_wheel_limit():
    robot = jackal()
    limits = robot.limits.replace(wheel_speed=3.0)
    plan = flat_trajectory(EIGHT, model=robot, limits=limits, timing="fastest")
    assert plan.info["limited_by"] == "wheel speed"
    report = plan.check(limits)
    assert report.ok
    assert np.abs(report.peaks["wheel speed"]).max() == pytest.approx(3.0, rel=LIMIT_TOUCH)
    assert plan.check().ok  # and the Jackal's own limits


def test_within_limits_leaves_an_easy_output_alone():
    plan = flat_trajectory(EIGHT, limits=MobileLimits(velocity=10.0), timing="within_limits")
    assert plan.info["time_scale"] == 1.0 and plan.info["limited_by"] is None
    assert plan.duration == 20.0
    fastest = flat_trajectory(EIGHT, limits=MobileLimits(velocity=10.0), timing="fastest")
    assert fastest.info["time_scale"] < 1.0 and fastest.info["limited_by"] == "velocity"


def test_reported_extrema_bound_a_dense_grid():
    output = spline_output(WAYPOINTS)
    plan = flat_trajectory(output, model=DiffDrive(0.1, 0.4), limits=MobileLimits(velocity=1.0),
                           timing="fastest")  # fmt: skip
    limits = MobileLimits(1.0, 10.0, 10.0, 10.0, 100.0)
    report = plan.check(limits)
    t = np.linspace(0.0, plan.duration, CHECK_GRID)
    state = plan.state(t)
    wheels = plan.wheel_speeds(t)
    sampled = {
        "velocity": state.v[:, None], "angular velocity": state.omega[:, None],
        "acceleration": state.acceleration[:, None],
        "angular acceleration": state.angular_acceleration[:, None], "wheel speed": wheels,
    }  # fmt: skip
    for quantity, values in sampled.items():
        low, high = report.peaks[quantity]
        scale = max(1.0, np.abs(values).max())
        # Never inside the sampled range, and no further out than the grid resolves: the
        # largest change between neighbouring samples (rates jump at the spline's knots).
        resolution = np.abs(np.diff(values, axis=0)).max(axis=0)
        assert np.all(low <= values.min(axis=0) + 1e-12 * scale)
        assert np.all(high >= values.max(axis=0) - 1e-12 * scale)
        assert np.all(values.min(axis=0) - low <= resolution)
        assert np.all(high - values.max(axis=0) <= resolution)


# Stops ----------------------------------------------------------------------------
def test_a_stop_is_an_error_by_default():
    with pytest.raises(InfeasibleError, match=r"the flat output stops at t=1 s .*stops='turn'"):
        flat_trajectory(there_and_back())
    with pytest.raises(InfeasibleError, match=r"stops at t=2 s"):
        flat_trajectory(Cusp())


def test_reversing_on_the_same_line_drives_backwards():
    plan = flat_trajectory(there_and_back(), stops="reverse", limits=STOP_LIMITS,
                           timing="within_limits")  # fmt: skip
    assert plan.check(STOP_LIMITS).ok
    assert [s.kind for s in plan.segments] == ["flat", "flat"]
    assert plan.info["stops"] == (1.0,) and plan.info["stops_treatment"] == "reverse"
    stop = plan.breakpoints[1]
    assert stop == pytest.approx(plan.info["time_scale"], rel=ROUNDING)
    before = np.linspace(0.01, 0.99, 50) * stop
    after = stop + np.linspace(0.01, 0.99, 50) * (plan.duration - stop)
    assert np.all(plan.twist(before)[:, 0] > 0) and np.all(plan.twist(after)[:, 0] < 0)
    # The heading is continuous: the base faces a -> b the whole way, backing up at the end.
    heading = math.atan2(0.5, 1.0)
    support.assert_heading(plan.pose(np.concatenate([before, [stop], after]))[:, 2], heading,
                           atol=CLOSED_FORM)  # fmt: skip
    support.assert_state(plan.end_pose, [0.0, 0.0, heading], rtol=CLOSED_FORM)
    assert_matches_slow(plan, there_and_back(), after[::7], scale=plan.info["time_scale"], sign=-1)


def test_reversing_at_a_cusp_keeps_the_heading_and_limits_of_the_formulas():
    cusp = Cusp()
    np.testing.assert_array_equal(cusp.breakpoints, [0.0, 4.0])  # FlatOutput's default
    plan = flat_trajectory(cusp, stops="reverse")
    assert plan.info["stops"] == pytest.approx((2.0,), rel=1e-12)
    t = np.array([1.999, 2.0, 2.001])
    state = plan.state(t)
    assert state.v[0] > 0 > state.v[2] and abs(state.v[1]) <= 1e-15
    support.assert_heading(state.theta, math.atan2(2.0, 1.0), atol=1e-5)  # along (1, 2u)
    # At the stop: ω = 2 u' / (1 + 4u²) = 0 and dω/dt = 2 u'' / 5 = -2 (π/4)² / 5.
    assert abs(state.omega[1]) <= 1e-12
    expected_rate = -2.0 * (math.pi / 4) ** 2 / 5.0
    assert state.angular_acceleration[1] == pytest.approx(expected_rate, rel=STOP_LIMIT)
    assert_matches_slow(plan, cusp, [0.5, 1.5, 1.9], sign=1)
    assert_matches_slow(plan, cusp, [2.1, 2.5, 3.5], sign=-1)


def test_turning_at_a_stop_inserts_a_turn():
    reverse = flat_trajectory(there_and_back(), stops="reverse", limits=STOP_LIMITS,
                              timing="within_limits")  # fmt: skip
    plan = flat_trajectory(there_and_back(), stops="turn", limits=STOP_LIMITS,
                           timing="within_limits")  # fmt: skip
    assert [s.kind for s in plan.segments] == ["flat", "turn", "flat"]
    turn = plan.segments[1]
    assert abs(turn.end_pose[2] - turn.start_pose[2]) == pytest.approx(math.pi, rel=CLOSED_FORM)
    # The turn is the time-optimal trapezoid of π under 2 rad/s and 5 rad/s².
    assert turn.duration == pytest.approx(math.pi / 2.0 + 2.0 / 5.0, rel=CLOSED_FORM)
    assert plan.duration == pytest.approx(reverse.duration + turn.duration, rel=CLOSED_FORM)
    assert plan.check(STOP_LIMITS).ok
    t = np.linspace(0.0, plan.duration, 401)
    assert np.all(plan.twist(t)[:, 0] >= 0.0)  # always forwards
    support.assert_state(plan.end_pose[:2], A, rtol=CLOSED_FORM)
    for i in (1, 2):  # poses join
        support.assert_state(plan.pose(plan.breakpoints[i]), plan.segments[i - 1].end_pose,
                             rtol=CLOSED_FORM)  # fmt: skip


def test_a_stop_that_turns_cannot_be_reversed():
    corner = tk.quintic(A, B, 1).then(tk.quintic(B, C, 1))
    with pytest.raises(
        InfeasibleError,
        match=r"at t=1 s the flat output turns by 63.43 deg.*"
        r"reversing cannot follow it, pass stops='turn'",
    ):
        flat_trajectory(corner, stops="reverse")
    plan = flat_trajectory(corner, stops="turn", limits=STOP_LIMITS, timing="within_limits")
    assert [s.kind for s in plan.segments] == ["flat", "turn", "flat"]
    turned = plan.segments[1].end_pose[2] - plan.segments[1].start_pose[2]
    assert turned == pytest.approx(math.atan2(1.0, 0.0) - math.atan2(0.5, 1.0), rel=CLOSED_FORM)
    assert plan.check(STOP_LIMITS).ok


def test_a_stop_in_the_same_direction_drives_on():
    line = tk.quintic(A, B, 1).then(tk.quintic(B, 2 * B, 1))
    plan = flat_trajectory(line, stops="reverse")
    assert [s.kind for s in plan.segments] == ["flat", "flat"]
    assert np.all(plan.twist(np.linspace(0, 2, 41))[:, 0] >= 0)
    turning = flat_trajectory(line, stops="turn", limits=STOP_LIMITS)
    assert [s.kind for s in turning.segments] == ["flat", "flat"]  # nothing to turn


def test_turning_at_a_stop_needs_angular_limits():
    with pytest.raises(
        InvalidInputError,
        match=r"stops='turn' turns in place at t=1 s, which "
        r"needs limits with angular_acceleration",
    ):
        flat_trajectory(there_and_back(), stops="turn", limits=MobileLimits(angular_velocity=1))
    with pytest.raises(InvalidInputError, match=r"angular_velocity and angular_acceleration"):
        flat_trajectory(there_and_back(), stops="turn")


# Bad input ------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"timing": "slow"}, r"timing must be 'as_given', 'within_limits' or 'fastest'"),
        ({"stops": "ignore"}, r"stops must be 'error', 'turn' or 'reverse', got 'ignore'"),
        ({"limits": tk.Limits(velocity=1.0)}, r"limits must be a trajkit.mobile.MobileLimits"),
        ({"model": "jackal"}, r"model must be a trajkit.mobile Unicycle or DiffDrive"),
        ({"limits": MobileLimits(wheel_speed=1.0), "timing": "fastest"},
         r"a wheel_speed limit needs a DiffDrive model"),
    ],
)  # fmt: skip
def test_bad_options_raise_invalid_input(kwargs, match):
    with pytest.raises(InvalidInputError, match=match):
        flat_trajectory(EIGHT, **kwargs)


def test_bad_outputs():
    with pytest.raises(
        InvalidInputError, match=r"output must be a FlatOutput or a 2-DoF Trajectory"
    ):
        flat_trajectory(np.zeros((10, 2)))  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match=r"must be a 2-DoF Trajectory"):
        flat_trajectory(tk.quintic(0.0, 1.0, 1.0))
    standing = tk.Trajectory([0.0, 1.0], np.array([[[1.0, 2.0]]]))
    with pytest.raises(InfeasibleError, match=r"the flat output never moves"):
        flat_trajectory(standing)


@pytest.mark.parametrize("timing", ["within_limits", "fastest"])
def test_timing_needs_a_limit(timing):
    with pytest.raises(
        InfeasibleError,
        match=r"timing='within_limits' or 'fastest' needs at least "
        r"one limit",
    ):
        flat_trajectory(EIGHT, timing=timing)


# Near a stop: the Taylor series of the output replace the closed forms -------------
def _power_output(px: int, py: int) -> tk.Trajectory:
    """x = t^px, y = t^py on [0, 1] as a one-piece polynomial Trajectory."""
    degree = max(px, py)
    c = np.zeros((degree + 1, 1, 2))
    c[degree - px, 0, 0] = c[degree - py, 0, 1] = 1.0
    return tk.Trajectory([0.0, 1.0], c)


@pytest.mark.parametrize(
    ("px", "py", "k"),
    [(2, 3, 1.5), (3, 4, 4.0 / 3.0)],  # a stop with acceleration (m = 1), one without (m = 2)
)
def test_heading_and_turn_rate_near_a_stop_match_the_exact_curve(px, py, k):
    # ẏ/ẋ = k t for both curves: θ = atan(k t), ω = k / (1 + k² t²), dω/dt = -2 k³ t / (...)².
    plan = flat_trajectory(_power_output(px, py))
    t = np.array([0.0, 1e-12, 1e-9, 1e-6, 1e-4, 1.7e-3, 5e-3, 2e-2, 0.5, 1.0])
    state = plan.state(t)
    np.testing.assert_allclose(state.theta, np.arctan(k * t), rtol=0, atol=1e-12)
    np.testing.assert_allclose(state.omega, k / (1 + (k * t) ** 2), rtol=1e-12)
    np.testing.assert_allclose(
        state.angular_acceleration, -2 * k**3 * t / (1 + (k * t) ** 2) ** 2, rtol=0, atol=1e-11
    )


def test_a_near_stop_is_not_a_stop_and_its_turn_rate_is_reported():
    # ṗ = (t - 1, 1e-5): the speed dips to 1e-5 m/s at t = 1 and |ω| peaks at 1e5 rad/s there.
    c = np.zeros((3, 1, 2))
    c[0, 0, 0], c[1, 0, 0], c[1, 0, 1] = 0.5, -1.0, 1e-5
    plan = flat_trajectory(tk.Trajectory([0.0, 2.0], c))
    assert plan.info["stops"] == ()
    report = plan.check(MobileLimits(angular_velocity=10.0))
    assert not report.ok
    assert report.peaks["angular velocity"][0][0] == pytest.approx(-1e5, rel=1e-6)


def test_fit_refuses_a_side_bounded_at_zero():
    out_and_back = tk.quintic(A, B, 1.0).then(tk.quintic(B, A, 1.0))
    with pytest.raises(InfeasibleError, match=r"needs velocity -\d.* limit is \(0, 1\)"):
        flat_trajectory(out_and_back, limits=MobileLimits(velocity=(0.0, 1.0)), stops="reverse",
                        timing="within_limits")  # fmt: skip


def test_fitted_curve_keeps_its_limits_for_check_and_simulation():
    limits = MobileLimits(velocity=0.3)
    plan = flat_trajectory(EIGHT, model=jackal(), limits=limits, timing="within_limits")
    assert plan.limits == limits
    assert plan.check().bounds["velocity"][1][0] == 0.3
    assert plan.info["time_scale"] == pytest.approx(0.444288293816 / 0.3, rel=1e-9)
    assert isinstance(plan.info["time_scale"], float)


def _from_velocity(vx: np.ndarray, vy: np.ndarray) -> tk.Trajectory:
    """The one-piece Trajectory whose velocity has these ascending polynomial coefficients."""
    poly = np.polynomial.polynomial
    x, y = poly.polyint(vx), poly.polyint(vy)
    degree = max(len(x), len(y))
    c = np.zeros((degree, 1, 2))
    c[degree - len(x) :, 0, 0], c[degree - len(y) :, 0, 1] = x[::-1], y[::-1]
    return tk.Trajectory([0.0, 1.0], c)


def test_a_near_stop_after_a_real_stop_keeps_the_closed_forms():
    # ṗ = t ((t - 0.4)² + 0.05²)³ (1, 1.5 t): a stop at 0, a dip to ~1e-7 of the peak at 0.4;
    # ẏ/ẋ = 1.5 t everywhere, so θ = atan(1.5 t) and ω = 1.5 / (1 + 2.25 t²) exactly.
    poly = np.polynomial.polynomial
    speed = poly.polymul([0.0, 1.0], poly.polypow(poly.polyadd(poly.polypow([-0.4, 1.0], 2),
                                                                [0.05**2]), 3))  # fmt: skip
    plan = flat_trajectory(_from_velocity(speed, poly.polymul(speed, [0.0, 1.5])))
    assert plan.info["stops"] == ()
    t = np.array([0.0, 1e-6, 0.3, 0.38, 0.4, 0.42, 0.6, 1.0])
    state = plan.state(t)
    np.testing.assert_allclose(state.theta, np.arctan(1.5 * t), rtol=0, atol=1e-9)
    np.testing.assert_allclose(state.omega, 1.5 / (1 + 2.25 * t**2), rtol=1e-6)


@pytest.mark.parametrize("px", [4, 5, 6])
def test_high_order_stops_from_the_series(px):
    # x = t^px, y = t^(px+1): ẏ/ẋ = k t with k = (px + 1) / px; a stop of order px - 1.
    k = (px + 1) / px
    plan = flat_trajectory(_power_output(px, px + 1))
    t = np.array([0.0, 1e-9, 1e-4, 1e-2, 0.1, 0.2, 0.5])
    state = plan.state(t)
    np.testing.assert_allclose(state.theta, np.arctan(k * t), rtol=0, atol=1e-11)
    np.testing.assert_allclose(state.omega, k / (1 + (k * t) ** 2), rtol=1e-9)


def test_a_high_order_rest_at_the_end_is_not_an_inner_stop():
    # A septic rest-to-rest time law: its speed creeps to 0 as (1 - t)^3 at the end,
    # with rounding ripples there; they must not count as a stop inside the curve.
    law = tk.septic(0.0, 1.0, 1.0)
    c = np.concatenate([law.coefficients, 0.5 * law.coefficients], axis=2)
    plan = flat_trajectory(tk.Trajectory(law.breakpoints, c))
    assert plan.info["stops"] == ()
    np.testing.assert_allclose(plan.state([0.0, 1.0]).theta, np.arctan(0.5), atol=1e-9)


def test_a_curve_that_turns_as_it_stops_meets_the_inserted_turn_with_a_jump():
    # A cubic arrives at rest at t = 1 still turning (ω = 1.5 rad/s), then leaves along +y.
    # The inserted turn starts at ω = 0: documented, and check() reports -inf there.
    c = np.zeros((4, 2, 2))
    c[:, 0, 0], c[:, 0, 1] = [0, -1, 2, -1], [-1, 3, -3, 1]
    c[:, 1, 1] = [0, 1, 0, 0]
    plan = flat_trajectory(tk.Trajectory([0.0, 1.0, 2.0], c), stops="turn", limits=STOP_LIMITS)
    assert [segment.kind for segment in plan.segments] == ["flat", "turn", "flat"]
    curve = plan.segments[0]
    assert curve.local_state(np.array([curve.duration]))[4][0] == pytest.approx(1.5, rel=1e-9)
    jumps = [v for v in plan.check().violations if v.quantity == "angular acceleration"]
    assert [(v.value, v.time) for v in jumps] == [(-np.inf, plan.breakpoints[1])]
