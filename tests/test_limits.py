"""Tests of trajkit.Limits and trajkit.check: limit specs, exact verification, reports."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import trajkit as tk
from support import CLOSED_FORM, ROUNDING, piecewise_trajectories
from trajkit import InvalidInputError, Limits, Report, Trajectory, Violation, check
from trajkit.limits import parse_bounds

QUANTITIES = ("position", "velocity", "acceleration", "jerk")
# Absolute floor for relative bounds (hypothesis draws subnormal coefficients).
UNDERFLOW = 1e-300


def cubic_rest_to_rest(q0: list[float], distance: list[float], duration: float) -> Trajectory:
    """q(t) = q0 + D (3 (t/T)^2 - 2 (t/T)^3): peak velocity 1.5 D / T at T / 2,
    acceleration 6 D / T^2 at 0 and -6 D / T^2 at T, jerk -12 D / T^3."""
    q0_, d = np.asarray(q0, float), np.asarray(distance, float)
    c = np.stack([-2.0 * d / duration**3, 3.0 * d / duration**2, np.zeros_like(d), q0_])
    return Trajectory([0.0, duration], c[:, np.newaxis, :])


def ramp(velocity: float, duration: float = 1.0) -> Trajectory:
    """q(t) = velocity * t: constant, exactly representable velocity."""
    return Trajectory([0.0, duration], [[velocity], [0.0]])


# --------------------------------------------------------------------- Limits


def test_symmetric_scalar_limit() -> None:
    limits = Limits(velocity=2.0)
    assert limits.velocity is not None
    np.testing.assert_array_equal(limits.velocity.lower, -2.0)
    np.testing.assert_array_equal(limits.velocity.upper, 2.0)
    assert limits.position is None
    assert limits.acceleration is None
    assert limits.jerk is None
    lower, upper = limits.velocity.for_ndof("velocity", 3)
    np.testing.assert_array_equal(lower, [-2.0, -2.0, -2.0])
    np.testing.assert_array_equal(upper, [2.0, 2.0, 2.0])


def test_per_joint_list_is_symmetric() -> None:
    limits = Limits(velocity=[1.0, 2.5], jerk=np.array([10.0, 20.0]))
    assert limits.velocity is not None and limits.jerk is not None
    np.testing.assert_array_equal(limits.velocity.lower, [-1.0, -2.5])
    np.testing.assert_array_equal(limits.velocity.upper, [1.0, 2.5])
    np.testing.assert_array_equal(limits.jerk.upper, [10.0, 20.0])


def test_asymmetric_tuple_and_position_range() -> None:
    limits = Limits(
        position=([-1.0, -2.0], 3.0),
        acceleration=(-3.0, 5.0),
        velocity=([-1.0, 0.0], [2.0, 4.0]),
    )
    assert limits.position is not None
    lower, upper = limits.position.for_ndof("position", 2)
    np.testing.assert_array_equal(lower, [-1.0, -2.0])
    np.testing.assert_array_equal(upper, [3.0, 3.0])
    assert limits.acceleration is not None
    np.testing.assert_array_equal(limits.acceleration.lower, -3.0)
    np.testing.assert_array_equal(limits.acceleration.upper, 5.0)
    assert limits.velocity is not None
    np.testing.assert_array_equal(limits.velocity.lower, [-1.0, 0.0])  # 0 is allowed
    # A position range need not contain 0.
    shifted = Limits(position=(1.0, 2.0))
    assert shifted.position is not None
    np.testing.assert_array_equal(shifted.position.lower, 1.0)


def test_limits_keep_their_own_copies() -> None:
    magnitude = np.array([1.0, 2.0])
    lower, upper = np.array([-1.0, -1.0]), np.array([1.0, 1.0])
    limits = Limits(velocity=magnitude, acceleration=(lower, upper))
    magnitude[:] = 100.0
    lower[:] = -100.0
    upper[:] = 100.0
    assert limits.velocity is not None and limits.acceleration is not None
    np.testing.assert_array_equal(limits.velocity.upper, [1.0, 2.0])
    np.testing.assert_array_equal(limits.velocity.lower, [-1.0, -2.0])
    np.testing.assert_array_equal(limits.acceleration.lower, [-1.0, -1.0])
    np.testing.assert_array_equal(limits.acceleration.upper, [1.0, 1.0])


def test_parse_bounds_names_the_argument_it_was_given() -> None:
    with pytest.raises(InvalidInputError, match=r"^vmax=.*must contain 0"):
        parse_bounds("vmax", (0.5, 2.0), quantity="velocity")
    with pytest.raises(InvalidInputError, match=r"^vmax limits must be > 0"):
        parse_bounds("vmax", -1.0, quantity="velocity")
    with pytest.raises(InvalidInputError, match=r"^range limits must be a tuple"):
        parse_bounds("range", 1.0, quantity="position")
    assert parse_bounds("vmax", None) is None
    bounds = parse_bounds("vmax", [1.0, 3.0], quantity="velocity")
    assert bounds is not None
    np.testing.assert_array_equal(bounds.lower, [-1.0, -3.0])


def test_limits_repr_lists_the_given_bounds() -> None:
    text = repr(Limits(velocity=[1.0, 2.0], acceleration=(-3.0, 5.0)))
    assert text == "Limits(velocity=([-1.0, -2.0], [1.0, 2.0]), acceleration=(-3.0, 5.0))"
    assert repr(Limits()) == "Limits()"


def test_limits_are_frozen() -> None:
    limits = Limits(velocity=1.0)
    with pytest.raises(AttributeError):
        limits.velocity = None  # type: ignore[misc]


@pytest.mark.parametrize(
    ("spec", "match"),
    [
        ({"velocity": -1.0}, r"velocity limits must be > 0"),
        ({"velocity": 0.0}, r"velocity limits must be > 0"),
        ({"acceleration": [1.0, 0.0]}, r"acceleration limits must be > 0"),
        ({"jerk": [2.0, -1.0]}, r"jerk limits must be > 0"),
        ({"velocity": np.nan}, r"velocity must be finite"),
        ({"velocity": [1.0, np.inf]}, r"velocity must be finite"),
        ({"velocity": "fast"}, r"velocity must be numeric, got 'fast' \(a string\)"),
        ({"velocity": [[1.0, 2.0]]}, r"velocity must be a number or one number per joint"),
        # A 2-tuple is (lower, upper): per-joint symmetric limits must be a list.
        ({"velocity": (0.5, 2.0)}, r"must contain 0.*pass a list"),
        ({"acceleration": (-2.0, -0.5)}, r"acceleration=.*must contain 0"),
        ({"velocity": (1.0, 2.0, 3.0)}, r"velocity given as a tuple must be \(lower, upper\)"),
        ({"velocity": (2.0, -2.0)}, r"velocity lower bound must be below the upper bound"),
        ({"jerk": (np.nan, 1.0)}, r"jerk lower bound must be finite"),
        ({"jerk": (-1.0, np.inf)}, r"jerk upper bound must be finite"),
        ({"velocity": ([[-1.0]], 1.0)}, r"velocity lower bound must be a number or one"),
        ({"position": [0.0, 1.0]}, r"position limits must be a tuple \(lower, upper\)"),
        ({"position": 1.0}, r"position limits must be a tuple"),
        ({"position": (1.0, 1.0)}, r"position lower bound must be below the upper bound"),
        ({"position": ([0.0, 0.0], [1.0, 1.0, 1.0])}, r"lower bounds give 2 joints but upper"),
    ],
)
def test_invalid_limit_specs_are_refused_helpfully(spec: dict, match: str) -> None:
    with pytest.raises(InvalidInputError, match=match) as excinfo:
        Limits(**spec)
    assert type(excinfo.value) is InvalidInputError


# ---------------------------------------------------------------------- check


def test_check_finds_a_velocity_peak_between_samples() -> None:
    # Velocity peaks at 6.0 at t = 0.125 s; the 0.1 s samples see at most 5.76.
    tr = cubic_rest_to_rest([0.0], [1.0], 0.25)
    limit = 5.9
    samples = tr.sample(0.1)
    np.testing.assert_array_equal(samples.t, [0.0, 0.1, 0.2, 0.25])
    assert np.abs(samples.qd).max() < limit  # sampling alone would say "ok"
    report = check(tr, Limits(velocity=limit))
    assert not report.ok
    assert not report
    (violation,) = report.violations
    assert violation.quantity == "velocity"
    assert violation.joint == 0
    assert violation.time == pytest.approx(0.125, rel=CLOSED_FORM)
    assert violation.value == pytest.approx(6.0, rel=CLOSED_FORM)
    assert violation.bound == limit
    assert violation.excess == pytest.approx(0.1, rel=CLOSED_FORM)
    assert str(violation) == "velocity of joint 1 reaches 6 at t=0.125 s, beyond the bound 5.9"


def test_check_reports_the_joint_side_and_bound() -> None:
    # Joint 1 moves -2 in 1 s (velocity down to -3), joint 2 moves +1 (up to 1.5).
    tr = cubic_rest_to_rest([0.0, 0.0], [-2.0, 1.0], 1.0)
    report = check(tr, Limits(velocity=[2.5, 2.0]))
    (violation,) = report.violations
    assert (violation.quantity, violation.joint) == ("velocity", 0)
    assert violation.value == pytest.approx(-3.0, rel=CLOSED_FORM)
    assert violation.bound == -2.5  # the lower bound it passes
    assert violation.time == pytest.approx(0.5, rel=CLOSED_FORM)
    assert violation.excess == pytest.approx(0.5, rel=CLOSED_FORM)
    # Same trajectory, only joint 2 too fast.
    report = check(tr, Limits(velocity=[4.0, 1.0]))
    (violation,) = report.violations
    assert violation.joint == 1
    assert violation.bound == 1.0
    assert violation.value == pytest.approx(1.5, rel=CLOSED_FORM)


def test_check_asymmetric_bounds_and_both_sides() -> None:
    # Acceleration goes from +6 at t = 0 to -6 at t = 1.
    tr = cubic_rest_to_rest([0.0], [1.0], 1.0)
    report = check(tr, Limits(acceleration=(-3.0, 10.0)))
    (violation,) = report.violations
    assert violation.quantity == "acceleration"
    assert violation.bound == -3.0
    assert violation.value == pytest.approx(-6.0, rel=CLOSED_FORM)
    assert violation.time == pytest.approx(1.0, rel=CLOSED_FORM)
    # Both sides exceeded: one violation per side, lower first.
    report = check(tr, Limits(acceleration=(-5.0, 5.0)))
    assert [v.bound for v in report.violations] == [-5.0, 5.0]
    assert report.violations[1].time == 0.0
    assert report.violations[1].value == pytest.approx(6.0, rel=CLOSED_FORM)


def test_check_position_and_jerk_limits() -> None:
    tr = cubic_rest_to_rest([0.5], [1.0], 2.0)  # from 0.5 to 1.5, jerk -1.5
    report = check(tr, Limits(position=(0.0, 1.2), jerk=1.0))
    assert [(v.quantity, v.bound) for v in report.violations] == [
        ("position", 1.2),
        ("jerk", -1.0),
    ]
    position = report.violations[0]
    assert position.value == pytest.approx(1.5, rel=CLOSED_FORM)
    assert position.time == pytest.approx(2.0, rel=CLOSED_FORM)
    assert report.violations[1].value == pytest.approx(-1.5, rel=CLOSED_FORM)
    assert check(tr, Limits(position=(0.5, 1.5), jerk=1.5)).ok


def test_check_peaks_and_bounds_cover_only_the_limited_quantities() -> None:
    tr = cubic_rest_to_rest([0.0, 1.0], [1.0, -2.0], 1.0)
    report = check(tr, Limits(velocity=10.0, jerk=(-30.0, 25.0)))  # jerk -12 and 24
    assert report.ok
    assert list(report.peaks) == ["velocity", "jerk"]
    assert list(report.bounds) == ["velocity", "jerk"]
    low, high = report.peaks["velocity"]
    np.testing.assert_allclose(low, [0.0, -3.0], atol=1e-12)
    np.testing.assert_allclose(high, [1.5, 0.0], atol=1e-12)
    lower, upper = report.bounds["jerk"]
    np.testing.assert_array_equal(lower, [-30.0, -30.0])
    np.testing.assert_array_equal(upper, [25.0, 25.0])


def test_touching_a_limit_exactly_is_ok_and_rtol_is_relative_to_the_bound() -> None:
    tr = ramp(1.0)  # velocity exactly 1.0 everywhere
    assert check(tr, Limits(velocity=1.0)).ok
    # Within rtol * bound of the limit: still ok.
    assert check(tr, Limits(velocity=1.0 - 0.5e-9)).ok
    # Beyond it: a violation, unless rtol is widened.
    assert not check(tr, Limits(velocity=1.0 - 2e-9)).ok
    assert check(tr, Limits(velocity=1.0 - 2e-9), rtol=1e-8).ok
    assert not check(tr, Limits(velocity=0.99), rtol=1e-3).ok
    # The slack is rtol times the larger of |lower| and |upper|.
    down = ramp(-1.0)
    assert check(down, Limits(velocity=(-1.0 + 5e-8, 100.0))).ok  # slack 1e-7
    assert not check(down, Limits(velocity=(-1.0 + 5e-8, 1.0))).ok  # slack 1e-9


def test_time_optimal_cubic_touches_its_limit_without_a_violation() -> None:
    # Peak velocity 1.5 D / T computed in floating point lands within rounding of 1.5.
    for duration in (0.3, 1.0, 7.0, 13.0):
        tr = cubic_rest_to_rest([0.1], [duration], duration)
        assert check(tr, Limits(velocity=1.5, acceleration=6.0 / duration)).ok


@pytest.mark.parametrize("rtol", [0.0, -1e-9, np.nan])
def test_check_refuses_a_bad_rtol(rtol: float) -> None:
    with pytest.raises(InvalidInputError, match=r"^rtol must"):
        check(ramp(1.0), Limits(velocity=2.0), rtol=rtol)


def test_check_refuses_something_else_than_limits() -> None:
    with pytest.raises(InvalidInputError, match=r"limits must be a trajkit.Limits, got dict"):
        check(ramp(1.0), {"velocity": 1.0})  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("limits", "match"),
    [
        (Limits(velocity=[1.0, 2.0, 3.0]), r"velocity lower bounds give 3 joints but the traj"),
        (Limits(position=(0.0, [1.0, 2.0, 3.0])), r"position upper bounds give 3 joints"),
        (Limits(jerk=[1.0]), r"jerk lower bounds give 1 joints but the trajectory has 2"),
    ],
)
def test_check_refuses_a_joint_count_mismatch(limits: Limits, match: str) -> None:
    tr = cubic_rest_to_rest([0.0, 0.0], [1.0, 1.0], 1.0)
    with pytest.raises(InvalidInputError, match=match):
        check(tr, limits)


def test_trajectory_check_method_is_check() -> None:
    tr = cubic_rest_to_rest([0.0], [1.0], 0.25)
    limits = Limits(velocity=5.9, acceleration=200.0)
    assert tr.check(limits).violations == check(tr, limits).violations
    assert tr.check(limits, rtol=0.1).ok  # 6.0 is within 10 % of 5.9


def test_report_ok_and_bool() -> None:
    good = Report(())
    assert good.ok is True
    assert bool(good) is True
    bad = Report((Violation("velocity", 0, 0.5, 2.0, 1.0),))
    assert bad.ok is False
    assert bool(bad) is False
    assert bad.violations[0].excess == 1.0


def test_report_str_is_a_readable_table() -> None:
    tr = cubic_rest_to_rest([0.0, 0.0], [1.0, -4.0], 1.0)
    report = check(tr, Limits(velocity=[2.0, 3.0], acceleration=100.0))
    text = str(report)
    lines = text.splitlines()
    assert lines[0] == "limit check: 1 violation(s)"
    assert lines[1].split() == ["quantity", "joint", "min", "max", "lower", "upper"]
    assert set(lines[2]) == {"-"}
    rows = [line.split() for line in lines[3:7]]
    assert [row[:2] for row in rows] == [
        ["velocity", "1"],
        ["velocity", "2"],
        ["acceleration", "1"],
        ["acceleration", "2"],
    ]
    assert float(rows[1][2]) == pytest.approx(-6.0)  # min of joint 2
    assert [float(x) for x in rows[1][4:6]] == [-3.0, 3.0]
    flagged = [line for line in lines if "<-- exceeds" in line]
    assert len(flagged) == 1
    assert flagged[0].split()[:2] == ["velocity", "2"]
    assert lines[-1].strip() == "velocity of joint 2 reaches -6 at t=0.5 s, beyond the bound -3"
    ok_text = str(check(tr, Limits(velocity=10.0)))
    assert ok_text.splitlines()[0] == "limit check: OK"
    assert "<-- exceeds" not in ok_text
    assert str(Report(())) == "limit check: OK"


# ---------------------------------------------------- property: exact vs dense


def _dense(tr: Trajectory, order: int) -> np.ndarray:
    bp = tr.breakpoints
    t = np.concatenate([np.linspace(bp[i], bp[i + 1], 301) for i in range(len(bp) - 1)])
    return tr.evaluate(t, order)


def _piece_scale(tr: Trajectory, order: int) -> float:
    c = np.abs(tr.derivative(order).coefficients)
    h = np.diff(tr.breakpoints)[:, np.newaxis]
    k = c.shape[0] - 1
    return float(np.max(sum(c[j] * h ** (k - j) for j in range(k + 1))))


@st.composite
def trajectories_and_limits(draw: st.DrawFn) -> tuple[Trajectory, Limits]:
    """A random trajectory and limits placed around its own range, so that some are
    exceeded and some are not."""
    tr = draw(piecewise_trajectories())
    fraction = st.floats(0.05, 1.5)
    specs: dict[str, object] = {}
    for order, quantity in enumerate(QUANTITIES):
        if not draw(st.booleans()):
            continue
        dense = _dense(tr, order)
        low, high = dense.min(axis=0), dense.max(axis=0)
        if quantity == "position":
            middle = (low + high) / 2.0
            half = np.maximum((high - low) / 2.0, 1e-3)
            a = draw(hnp.arrays(np.float64, (tr.ndof,), elements=fraction))
            b = draw(hnp.arrays(np.float64, (tr.ndof,), elements=fraction))
            specs[quantity] = (middle - a * half, middle + b * half)
        elif draw(st.booleans()):
            peak = np.maximum(np.maximum(np.abs(low), np.abs(high)), 1e-3)
            specs[quantity] = list(
                draw(hnp.arrays(np.float64, (tr.ndof,), elements=fraction)) * peak
            )
        else:
            a = draw(hnp.arrays(np.float64, (tr.ndof,), elements=fraction))
            b = draw(hnp.arrays(np.float64, (tr.ndof,), elements=fraction))
            lower = -a * np.maximum(-low, 1e-3)
            upper = b * np.maximum(high, 1e-3)
            specs[quantity] = (lower, upper)
    return tr, Limits(**specs)


@given(trajectories_and_limits(), st.sampled_from([1e-9, 1e-6, 1e-3]))
def test_check_agrees_with_dense_sampling(case: tuple[Trajectory, Limits], rtol: float) -> None:
    tr, limits = case
    report = check(tr, limits, rtol=rtol)
    reported = {(v.quantity, v.joint, v.bound) for v in report.violations}
    assert len(reported) == len(report.violations)  # at most one per quantity, joint, side
    assert report.ok == (not report.violations)
    for order, quantity in enumerate(QUANTITIES):
        bounds = getattr(limits, quantity)
        if bounds is None:
            assert quantity not in report.peaks
            continue
        lower, upper = bounds.for_ndof(quantity, tr.ndof)
        slack = rtol * np.maximum(np.abs(lower), np.abs(upper))
        rounding = ROUNDING * _piece_scale(tr, order) + UNDERFLOW
        dense = _dense(tr, order)
        for j in range(tr.ndof):
            # Dense sampling sees a clear excursion: check() must report it.
            if dense[:, j].max() > upper[j] + slack[j] + rounding:
                assert (quantity, j, upper[j]) in reported, (quantity, j, "upper")
            if dense[:, j].min() < lower[j] - slack[j] - rounding:
                assert (quantity, j, lower[j]) in reported, (quantity, j, "lower")
        # Every reported violation is genuine: beyond its bound by more than the slack,
        # inside the trajectory's time span.
        for v in report.violations:
            if v.quantity != quantity:
                continue
            j = v.joint
            assert v.bound in (lower[j], upper[j])
            assert v.excess > slack[j]
            if v.bound == upper[j]:
                assert v.value > upper[j]
                assert v.value >= dense[:, j].max() - rounding
            else:
                assert v.value < lower[j]
                assert v.value <= dense[:, j].min() + rounding
            span = 4.0 * np.spacing(np.abs(tr.breakpoints).max())
            assert tr.start_time - span <= v.time <= tr.end_time + span


def _jump_oracle(tr: Trajectory, order: int) -> tuple[np.ndarray, np.ndarray]:
    """Jumps of derivative ``order`` at the inner breakpoints by plain polyval, and the
    size of the terms they come from: ``(m - 1, ndof)`` each."""
    c = tr.derivative(order).coefficients
    h = np.diff(tr.breakpoints)
    jumps, scales = [], []
    for i in range(len(h) - 1):
        left = np.array([np.polyval(c[:, i, j], h[i]) for j in range(tr.ndof)])
        terms = np.array([np.polyval(np.abs(c[:, i, j]), h[i]) for j in range(tr.ndof)])
        right = c[-1, i + 1, :]
        jumps.append(right - left)
        scales.append(np.maximum(terms, np.abs(right)))
    shape = (len(h) - 1, tr.ndof)
    return np.array(jumps).reshape(shape), np.array(scales).reshape(shape)


@given(piecewise_trajectories())
def test_check_with_generous_limits_flags_only_the_jumps(tr: Trajectory) -> None:
    # Limits at twice every dense peak (plus a margin) are never exceeded by a value;
    # what remains are the unbounded derivatives above a jump between pieces (arbitrary
    # pieces rarely meet): a step in derivative k is an impulse in k + 1 (issue 16).
    specs = {}
    for order, quantity in enumerate(QUANTITIES):
        dense = _dense(tr, order)
        margin = 2.0 * np.abs(dense).max(axis=0) + 1.0 + _piece_scale(tr, order)
        specs[quantity] = (-margin, margin) if quantity == "position" else margin
    report = tk.check(tr, Limits(**specs))
    assert set(report.peaks) == set(QUANTITIES)
    assert all(np.isinf(v.value) and v.cause for v in report.violations), str(report)
    flagged = {(v.quantity, v.joint) for v in report.violations}
    clear = np.zeros(tr.ndof, bool)  # a clear jump below the current order
    tiny = np.ones(tr.ndof, bool)  # every jump below it is rounding-sized
    for order, quantity in enumerate(QUANTITIES):
        for j in range(tr.ndof):
            if clear[j]:
                assert (quantity, j) in flagged, (quantity, j)
            elif tiny[j]:
                assert (quantity, j) not in flagged, (quantity, j)
        jumps, scales = _jump_oracle(tr, order)
        clear |= (np.abs(jumps) > 1e-6 * (1.0 + scales)).any(axis=0)
        tiny &= (np.abs(jumps) <= 1e-12 * (1.0 + scales)).all(axis=0)
    assert report.ok == (not flagged)


def test_report_ratios_take_each_side_with_its_own_bound():
    # Joint 1 peaks at +1.0 (upper 2: ratio 0.5) and -0.6 (lower -0.5: ratio 1.2): the
    # smaller peak is the one past its bound. Joint 2 never moves down.
    report = Report((), {"velocity": (np.array([-0.6, 0.0]), np.array([1.0, 1.5]))},
                    {"velocity": (np.array([-0.5, -1.0]), np.array([2.0, 3.0]))})  # fmt: skip
    np.testing.assert_allclose(report.ratios("velocity"), [1.2, 0.5], rtol=1e-15)


def test_report_ratios_of_a_zero_bound_and_of_an_unchecked_quantity():
    report = Report((), {"velocity": (np.array([0.0, 0.0]), np.array([0.0, 0.1]))},
                    {"velocity": (np.array([-1.0, -1.0]), np.array([0.0, 0.0]))})  # fmt: skip
    np.testing.assert_array_equal(report.ratios("velocity"), [0.0, np.inf])
    with pytest.raises(InvalidInputError, match="'jerk' was not checked; checked: velocity"):
        report.ratios("jerk")


def test_report_ratios_equal_the_checked_trajectorys_peaks():
    trajectory = tk.trapezoidal([0.0, 0.0], [1.0, -2.0], vmax=1.0, amax=2.0)
    limits = tk.Limits(velocity=(-4.0, 2.0), acceleration=3.0)
    report = trajectory.check(limits)
    velocity = trajectory.extrema(1)  # joint 1 moves up (upper 2), joint 2 down (lower -4)
    expected = [velocity.maximum[0] / 2.0, velocity.minimum[1] / -4.0]
    np.testing.assert_allclose(report.ratios("velocity"), expected, rtol=1e-15)
    assert report.ratios("velocity")[1] == pytest.approx(0.25, rel=1e-12)
    np.testing.assert_allclose(report.ratios("acceleration"), [2 / 3, 2 / 3], rtol=1e-12)


# ------------------------------------------- jumps between pieces (issue 16, item 1)


def steps(values: list[list[float]]) -> Trajectory:
    """Three pieces on [0, 1], [1, 2], [2, 3]: piece i is ``values[i]`` (highest power
    first, one joint), so every jump at t = 1 and t = 2 is known exactly."""
    c = np.array(values, float).T[:, :, np.newaxis]
    return Trajectory([0.0, 1.0, 2.0, 3.0], c)


def test_trapezoid_breaks_a_jerk_limit_at_each_switch():
    # Its acceleration jumps from +2 to 0 (t = 0.5), from 0 to -2 (t = 1.0): the jerk is
    # unbounded there; check() used to report the pieces' jerk of 0 as within jerk=1.
    tr = tk.trapezoidal([0.0], [1.5], vmax=1.0, amax=2.0)
    np.testing.assert_allclose(tr.breakpoints, [0.0, 0.5, 1.5, 2.0], rtol=1e-15)
    report = tr.check(Limits(jerk=1.0))
    assert not report.ok
    (down,) = report.violations  # both jumps go down: only the lower side is passed
    assert (down.quantity, down.joint, down.value, down.bound) == ("jerk", 0, -np.inf, -1.0)
    assert down.time == pytest.approx(0.5, abs=1e-15)
    assert down.cause == "acceleration jumps by -2 at t=0.5 s"
    assert str(down) == (
        "jerk of joint 1 is unbounded (-inf) at t=0.5 s, beyond the bound -1: "
        "acceleration jumps by -2 at t=0.5 s"
    )
    assert report.peaks["jerk"][0][0] == -np.inf and report.peaks["jerk"][1][0] == 0.0
    np.testing.assert_array_equal(report.ratios("jerk"), [np.inf])
    # Velocity and acceleration stay within their (touched) limits.
    assert tr.check(Limits(velocity=1.0, acceleration=2.0)).ok


def test_topp_breaks_a_jerk_limit_its_timing_never_looked_at():
    # topp bounds velocity and acceleration only; its acceleration jumps at grid points.
    path = tk.cubic_spline([0.0, 1.0, 2.0, 3.0], [[0, 0], [1, 0.5], [0.3, 1.2], [1, 1]])
    tr = tk.topp(path, Limits(velocity=1.0, acceleration=2.0), grid=50)
    report = tr.check(Limits(velocity=1.0, acceleration=2.0, jerk=100.0))
    jerk = [v for v in report.violations if v.quantity == "jerk"]
    assert {v.joint for v in jerk} == {0, 1}
    assert all(np.isinf(v.value) and v.cause.startswith("acceleration jumps by") for v in jerk)
    assert all(tr.start_time < v.time < tr.end_time for v in jerk)
    assert [v.quantity for v in report.violations] == ["jerk"] * len(jerk)
    # Its largest jump is the report's discontinuity, ~1.4 rad/s^2 here.
    largest = max(np.abs(tr.jumps(2)).max(axis=0))
    listed = [d for d in report.discontinuities if d.quantity == "acceleration"]
    assert max(abs(d.jump) for d in listed) == largest > 0.5


def test_a_position_step_makes_every_higher_derivative_unbounded():
    # Position: 0 on [0, 1], 1 on [1, 2], then 1 - (t - 2): a step up at t = 1 and a
    # velocity step down (0 to -1) at t = 2.
    tr = steps([[0.0, 0.0], [0.0, 1.0], [-1.0, 1.0]])
    report = tr.check(Limits(velocity=5.0, acceleration=5.0, jerk=5.0))
    found = {(v.quantity, v.value): (v.time, v.cause) for v in report.violations}
    assert found == {
        # The step's own impulse goes up; the velocity step is within the velocity limit.
        ("velocity", np.inf): (1.0, "position jumps by 1 at t=1 s"),
        # Above it, the derivative of an impulse goes both ways.
        ("acceleration", np.inf): (1.0, "position jumps by 1 at t=1 s"),
        ("acceleration", -np.inf): (1.0, "position jumps by 1 at t=1 s"),
        ("jerk", np.inf): (1.0, "position jumps by 1 at t=1 s"),
        ("jerk", -np.inf): (1.0, "position jumps by 1 at t=1 s"),
    }
    # Both sides of the step are inside a position range: that alone is fine, and the
    # report still lists the step.
    within = tr.check(Limits(position=(-1.0, 2.0)))
    assert within.ok
    assert [str(d) for d in within.discontinuities] == [
        "position of joint 1 jumps by 1 at t=1 s",
        "velocity of joint 1 jumps by -1 at t=2 s",
    ]


def test_a_velocity_step_is_an_acceleration_impulse_of_its_sign():
    tr = steps([[1.0, 0.0], [1.0, 1.0], [-2.0, 2.0]])  # velocity 1, 1, -2: one step at t = 2
    report = tr.check(Limits(velocity=3.0, acceleration=1.0))
    (v,) = report.violations
    assert (v.quantity, v.value, v.bound, v.time) == ("acceleration", -np.inf, -1.0, 2.0)
    assert v.cause == "velocity jumps by -3 at t=2 s"
    # The earliest breakpoint is reported when several jump.
    zigzag = steps([[2.0, 0.0], [-1.0, 2.0], [1.0, 1.0]])  # up-down-up velocity
    sides = {v.value: v.time for v in zigzag.check(Limits(acceleration=1.0)).violations}
    assert sides == {-np.inf: 1.0, np.inf: 2.0}


def test_rounding_sized_jumps_are_not_flagged_and_rtol_sets_the_threshold():
    # A jump of 1e-12 relative to values of size 1 is rounding; one of 1e-6 is real.
    for size, flagged in ((1e-12, False), (1e-6, True)):
        tr = steps([[1.0, 0.0], [1.0 + size, 1.0], [1.0 + size, 2.0 + size]])
        assert tr.check(Limits(acceleration=1.0)).ok is not flagged
    tr = steps([[1.0, 0.0], [1.0 + 1e-6, 1.0], [1.0 + 1e-6, 2.0 + 1e-6]])
    assert tr.check(Limits(acceleration=1.0), rtol=1e-5).ok  # a looser tolerance
    # Relative to the size of the terms: a step of 1e-8 in values of 1e3 is rounding.
    big = steps([[1e3, 0.0], [1e3 + 1e-8, 1e3], [1e3, 2e3]])
    assert big.check(Limits(acceleration=1.0)).ok


def test_check_of_a_continuous_trajectory_lists_no_discontinuity():
    tr = tk.quintic(0.0, 1.0, duration=2.0)
    report = tr.check(Limits(velocity=1.0, acceleration=2.0, jerk=10.0))
    assert report.ok and report.discontinuities == ()
    sc = tk.scurve([0.0], [2.0], vmax=1.0, amax=2.0, jmax=4.0)
    assert sc.check(Limits(velocity=1.0, acceleration=2.0, jerk=4.0)).ok  # C2: jerk jumps only


def test_merged_reports_keep_every_quantity_and_violation():
    move = tk.cubic([0.0, 0.0], [1.0, 2.0], 1.0)
    first = move.check(tk.Limits(velocity=1.0))
    second = move.check(tk.Limits(acceleration=100.0))
    merged = first.merged(second)
    assert list(merged.peaks) == ["velocity", "acceleration"]
    assert merged.violations == first.violations + second.violations
    assert not merged.ok and second.ok and not first.ok
    np.testing.assert_array_equal(merged.ratios("acceleration"), second.ratios("acceleration"))
    assert first.merged() == first
