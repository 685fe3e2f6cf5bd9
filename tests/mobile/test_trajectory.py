"""Tests of trajkit.mobile.trajectory: segments, MobileTrajectory evaluation, exact
limit checks with wheel channels, command streams and CSV export.

A three-segment plan (turn, straight drive, arc) with hand-computed peaks is the
reference for the exact checks.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import support
import trajkit as tk
from support import CLOSED_FORM, ROUNDING, WORLD_ROUNDING
from trajkit import InvalidInputError
from trajkit.mobile import (
    Arc,
    DiffDrive,
    MobileLimits,
    MobileState,
    MobileTrajectory,
    Segment,
    Straight,
    Turn,
    Unicycle,
    arc_pose,
    constant_twist,
    rotate_translate_rotate,
)
from trajkit.mobile.trajectory import command_times

# The reference plan --------------------------------------------------------------
START = np.array([1.0, -2.0, 0.25])
TURN = tk.trapezoidal(2.0, 3.2, 1.0, 2.0)  # starts at 2 rad: the turn is relative
DRIVE = tk.trapezoidal(0.0, 2.0, 0.5, 1.0)
ARC_V, ARC_W, ARC_T = 0.3, -0.4, 1.5
RADIUS, TRACK = 0.1, 0.5


def reference_segments() -> list[Segment]:
    turn = Turn(START, TURN)
    drive = Straight(turn.end_pose, DRIVE)
    arc = Arc(drive.end_pose, ARC_V, ARC_W, ARC_T)
    return [turn, drive, arc]


def reference(model=None) -> MobileTrajectory:
    return MobileTrajectory(reference_segments(), model or Unicycle(), info={"plan": "test"})


def diff_drive(**kwargs) -> DiffDrive:
    return DiffDrive(RADIUS, TRACK, **kwargs)


# MobileState ----------------------------------------------------------------------
def test_mobile_state_stacks():
    n = np.arange(3.0)
    state = MobileState(n, n + 1, n + 2, n * 0.5, n + 4, n + 5, n + 6, n + 7)
    np.testing.assert_array_equal(state.pose, np.stack([n + 1, n + 2, n * 0.5], 1))
    np.testing.assert_array_equal(state.twist, np.stack([n + 4, n + 5], 1))
    expected = np.stack([(n + 4) * np.cos(n * 0.5), (n + 4) * np.sin(n * 0.5)], 1)
    np.testing.assert_array_equal(state.world_velocity, expected)


# Segments -------------------------------------------------------------------------
def test_turn_is_the_law_added_to_the_start_heading():
    turn = Turn(START, TURN)
    tau = np.linspace(0.0, turn.duration, 9)
    x, y, theta, v, omega, dv, domega = turn.local_state(tau)
    np.testing.assert_array_equal(x, START[0])
    np.testing.assert_array_equal(y, START[1])
    np.testing.assert_array_equal(v, 0.0)
    np.testing.assert_array_equal(dv, 0.0)
    support.assert_state(theta, START[2] + TURN.position(tau)[:, 0] - 2.0, rtol=ROUNDING)
    np.testing.assert_array_equal(omega, TURN.velocity(tau)[:, 0])
    np.testing.assert_array_equal(domega, TURN.acceleration(tau)[:, 0])
    assert turn.kind == "turn" and turn.duration == TURN.duration
    support.assert_state(turn.end_pose, [START[0], START[1], START[2] + 1.2], rtol=CLOSED_FORM)


def test_straight_drives_along_the_start_heading():
    drive = Straight(START, DRIVE)
    tau = np.linspace(0.0, drive.duration, 9)
    x, y, theta, v, omega, dv, domega = drive.local_state(tau)
    s = DRIVE.position(tau)[:, 0]
    support.assert_state(x, START[0] + s * np.cos(START[2]), rtol=ROUNDING)
    support.assert_state(y, START[1] + s * np.sin(START[2]), rtol=ROUNDING)
    np.testing.assert_array_equal(theta, START[2])
    np.testing.assert_array_equal(v, DRIVE.velocity(tau)[:, 0])
    np.testing.assert_array_equal(dv, DRIVE.acceleration(tau)[:, 0])
    np.testing.assert_array_equal(omega, 0.0)
    np.testing.assert_array_equal(domega, 0.0)
    assert drive.kind == "straight"


def test_straight_law_not_starting_at_zero_is_relative():
    drive = Straight([0.0, 0.0, 0.0], tk.trapezoidal(5.0, 7.0, 1.0, 1.0))
    support.assert_state(drive.end_pose, [2.0, 0.0, 0.0], rtol=CLOSED_FORM)


def test_arc_segment_is_arc_pose():
    arc = Arc(START, ARC_V, ARC_W, ARC_T)
    tau = np.linspace(0.0, ARC_T, 7)
    state = arc.local_state(tau)
    np.testing.assert_array_equal(np.stack(state[:3], 1), arc_pose(START, ARC_V, ARC_W, tau))
    np.testing.assert_array_equal(state[3], ARC_V)
    np.testing.assert_array_equal(state[4], ARC_W)
    np.testing.assert_array_equal(state[5], 0.0)
    np.testing.assert_array_equal(state[6], 0.0)
    np.testing.assert_array_equal(arc.end_pose, arc_pose(START, ARC_V, ARC_W, ARC_T))
    assert arc.extrema(1, 2.0, 3.0) == (2 * ARC_V + 3 * ARC_W, 0.0, 2 * ARC_V + 3 * ARC_W, 0.0)
    assert arc.extrema(2, 2.0, 3.0) == (0.0, 0.0, 0.0, 0.0)


def test_law_segment_extrema_are_the_laws_scaled():
    drive = Straight(START, DRIVE)
    assert drive.extrema(1, 1.0, 0.0) == (0.0, 0.0, 0.5, 0.5)
    low, t_low, high, t_high = drive.extrema(1, -2.0, 5.0)  # a negative weight swaps the ends
    assert (low, high) == (-1.0, 0.0) and t_low == 0.5 and t_high == 0.0
    assert drive.extrema(2, 1.0, 0.0)[::2] == (-1.0, 1.0)
    assert drive.extrema(1, 0.0, 1.0) == (0.0, 0.0, 0.0, 0.0)  # a drive does not turn
    turn = Turn(START, TURN)
    assert turn.extrema(1, 0.0, 1.0)[::2] == (0.0, 1.0)
    assert turn.extrema(2, 0.0, 1.0)[::2] == (-2.0, 2.0)


@pytest.mark.parametrize("kind", [Turn, Straight])
def test_law_segments_refuse_bad_laws(kind):
    two = tk.trapezoidal([0.0, 0.0], [1.0, 1.0], 1.0, 1.0)
    late = tk.Trajectory([1.0, 2.0], np.array([[[1.0]], [[0.0]]]))
    with pytest.raises(InvalidInputError, match=r"law must be a 1-DoF trajkit Trajectory"):
        kind(START, two)
    with pytest.raises(InvalidInputError, match=r"law must be a 1-DoF trajkit Trajectory"):
        kind(START, lambda t: t)
    with pytest.raises(InvalidInputError, match=r"law must start at t=0, got 1 s"):
        kind(START, late)
    with pytest.raises(InvalidInputError, match=r"start_pose must be a pose"):
        kind([0.0, 0.0, 0.0, 0.0], DRIVE)


@pytest.mark.parametrize(
    ("args", "match"),
    [
        ((START, 1.0, 0.0, 0.0), r"duration must be > 0, got 0 s"),
        ((START, 1.0, 0.0, -1.0), r"duration must be > 0, got -1 s"),
        ((START, np.nan, 0.0, 1.0), r"v must be finite"),
        ((START, 1.0, np.inf, 1.0), r"omega must be finite"),
        (([0.0, 0.0, np.nan], 1.0, 0.0, 1.0), r"start_pose must be finite"),
    ],
)
def test_arc_refuses_bad_input(args, match):
    with pytest.raises(InvalidInputError, match=match):
        Arc(*args)


def test_segment_is_abstract():
    with pytest.raises(TypeError):
        Segment()  # type: ignore[abstract]


# MobileTrajectory: shape ----------------------------------------------------------
def test_breakpoints_duration_and_poses():
    plan = reference()
    durations = [TURN.duration, DRIVE.duration, ARC_T]
    np.testing.assert_array_equal(plan.breakpoints, np.concatenate([[0.0], np.cumsum(durations)]))
    assert plan.duration == pytest.approx(sum(durations), rel=ROUNDING)
    np.testing.assert_array_equal(plan.start_pose, START)
    np.testing.assert_array_equal(plan.end_pose, plan.segments[-1].end_pose)
    assert [s.kind for s in plan.segments] == ["turn", "straight", "arc"]
    assert isinstance(plan.model, Unicycle)
    assert repr(plan) == "MobileTrajectory(duration=7.7 s, segments=[turn, straight, arc])"


def test_read_only_parts():
    plan = reference()
    with pytest.raises(ValueError, match="read-only"):
        plan.breakpoints[0] = 1.0
    with pytest.raises(TypeError):
        plan.info["plan"] = "other"  # type: ignore[index]
    assert plan.info["plan"] == "test"
    pose = plan.start_pose
    pose[0] = 99.0
    assert plan.start_pose[0] == START[0]
    assert MobileTrajectory(reference_segments(), Unicycle()).info == {}


def test_segments_that_do_not_join_raise():
    turn = Turn(START, TURN)
    off = turn.end_pose + np.array([0.0, 1e-6, 0.0])
    with pytest.raises(InvalidInputError, match=r"segment 1 starts at .* but segment 0 ends at"):
        MobileTrajectory([turn, Straight(off, DRIVE)], Unicycle())
    twisted = turn.end_pose + np.array([0.0, 0.0, 1e-6])
    with pytest.raises(InvalidInputError, match=r"segment 1 starts at"):
        MobileTrajectory([turn, Straight(twisted, DRIVE)], Unicycle())
    # A gap within the 1e-9 join tolerance is accepted.
    close = turn.end_pose + np.array([1e-12, 0.0, 0.0])
    assert len(MobileTrajectory([turn, Straight(close, DRIVE)], Unicycle()).segments) == 2


@pytest.mark.parametrize(
    ("segments", "model", "match"),
    [
        ([], Unicycle(), r"segments must be a non-empty sequence of mobile Segments"),
        (["turn"], Unicycle(), r"segments must be a non-empty sequence"),
        (None, "jackal", r"model must be a trajkit.mobile Unicycle or DiffDrive, got str"),
    ],
)
def test_constructor_refuses_bad_input(segments, model, match):
    with pytest.raises(InvalidInputError, match=match):
        MobileTrajectory(reference_segments() if segments is None else segments, model)


# MobileTrajectory: evaluation ------------------------------------------------------
def test_evaluate_is_each_segments_local_state():
    plan = reference()
    t = np.linspace(0.0, plan.duration, 301)
    state = plan.state(t)
    assert isinstance(state, MobileState)
    np.testing.assert_array_equal(state.t, t)
    bp = plan.breakpoints
    for i, segment in enumerate(plan.segments):
        inside = (t >= bp[i]) & (t < bp[i + 1]) if i < 2 else t >= bp[i]
        local = np.stack(segment.local_state(t[inside] - bp[i]))
        columns = np.stack([state.x, state.y, state.theta, state.v, state.omega,
                            state.acceleration, state.angular_acceleration])[:, inside]  # fmt: skip
        support.assert_state(columns, local, rtol=ROUNDING)


def test_pose_is_continuous_at_the_joins():
    plan = reference()
    for t in plan.breakpoints[1:-1]:
        support.assert_state(plan.pose(t), plan.pose(t - 1e-12), rtol=1e-9)
    # The turn and the drive meet at rest; the arc starts with its twist at once.
    t_drive, t_arc = plan.breakpoints[1:3]
    np.testing.assert_array_equal(plan.twist(t_drive), [0.0, 0.0])
    assert np.abs(plan.twist(t_drive - 1e-12)).max() <= 1e-9
    np.testing.assert_array_equal(plan.twist(t_arc), [ARC_V, ARC_W])


def test_scalar_and_array_shapes():
    plan = reference(diff_drive())
    assert plan.pose(1.0).shape == (3,)
    assert plan.pose([1.0, 2.0]).shape == (2, 3)
    assert plan.twist(1.0).shape == (2,)
    assert plan.twist(np.array([1.0])).shape == (1, 2)
    assert plan.wheel_speeds(1.0).shape == (2,)
    assert plan.wheel_speeds([1.0, 2.0, 3.0]).shape == (3, 2)
    assert plan.state(2.0).x.shape == (1,)


def test_wheel_speeds_follow_the_twist():
    model = diff_drive()
    plan = reference(model)
    t = np.linspace(0.0, plan.duration, 50)
    twist = plan.twist(t)
    np.testing.assert_array_equal(
        plan.wheel_speeds(t), model.wheel_speeds(twist[:, 0], twist[:, 1])
    )
    with pytest.raises(InvalidInputError, match=r"wheel speeds need a DiffDrive model"):
        reference().wheel_speeds(1.0)


@given(st.one_of(st.floats(-1e3, -1e-9), st.floats(7.7 + 1e-9, 1e3)))
def test_outside_the_plan_the_pose_is_held_with_zero_twist(t):
    plan = reference()
    state = plan.state(t)
    end = plan.start_pose if t < 0 else plan.end_pose
    np.testing.assert_array_equal(state.pose[0], end)
    for rate in (state.v, state.omega, state.acceleration, state.angular_acceleration):
        assert rate[0] == 0.0
    np.testing.assert_array_equal(state.t, [t])


def test_ends_themselves_keep_their_twist():
    plan = reference()
    assert plan.twist(plan.duration)[0] == ARC_V  # the arc's twist at its last instant
    np.testing.assert_array_equal(plan.pose(0.0), START)


@pytest.mark.parametrize(
    ("t", "match"),
    [
        (np.zeros((2, 2)), r"t must be a number or a 1-D array, got shape \(2, 2\)"),
        ([0.0, np.nan], r"t must be finite"),
        ("soon", r"t must be numeric, got 'soon' \(a string\)"),
    ],
)
def test_evaluate_refuses_bad_times(t, match):
    with pytest.raises(InvalidInputError, match=match):
        reference().state(t)


def test_times_include_the_end():
    plan = reference()
    t = plan.times(0.5)
    support.assert_state(t[:-1], 0.5 * np.arange(t.size - 1), rtol=ROUNDING)
    assert t[-1] == plan.duration
    assert np.all(np.diff(t) > 0) and np.diff(t).max() <= 0.5 * (1 + ROUNDING)
    with pytest.raises(InvalidInputError, match=r"sample_step must be > 0, got 0 s"):
        plan.times(0.0)


# Commands -------------------------------------------------------------------------
def test_commands_at_a_rate():
    plan = reference()
    times, twists = plan.commands(4.0)
    support.assert_state(times, np.arange(times.size) / 4.0, rtol=ROUNDING)
    assert times.size == 31  # 7.7 s at 4 Hz: 0, 0.25, ..., 7.5
    np.testing.assert_array_equal(twists, plan.twist(times))
    # An end on a command time gets no command of its own: 7.7 s at 10 Hz, 0 to 7.6 s.
    assert plan.commands(10.0)[0].size == 77
    with pytest.raises(InvalidInputError, match=r"rate_hz must be > 0, got -1 Hz"):
        plan.commands(-1.0)


def test_command_times_count():
    np.testing.assert_array_equal(command_times(1.0, 4.0), [0.0, 0.25, 0.5, 0.75])
    np.testing.assert_array_equal(command_times(0.0, 10.0), [0.0])
    np.testing.assert_array_equal(command_times(0.01, 10.0), [0.0])
    assert command_times(1.0 + 1e-13, 10.0).size == 10  # an end on a command time, rounded
    assert command_times(1.0 + 1e-9, 10.0).size == 11


# check ----------------------------------------------------------------------------
def expected_peaks(b: float = TRACK, r: float = RADIUS) -> dict[str, tuple[list, list]]:
    """Each channel's exact minimum and maximum over turn (ω to 1), drive (v to 0.5), arc."""
    left = [(-1.0 * b / 2) / r, 0.0, 0.5 / r, (ARC_V - ARC_W * b / 2) / r]
    right = [(1.0 * b / 2) / r, 0.0, 0.5 / r, (ARC_V + ARC_W * b / 2) / r]
    return {
        "velocity": ([0.0], [0.5]),
        "angular velocity": ([ARC_W], [1.0]),
        "acceleration": ([-1.0], [1.0]),
        "angular acceleration": ([-2.0], [2.0]),
        "wheel speed": ([min(left), min(right)], [max(left), max(right)]),
    }


def test_check_is_exact_on_every_channel():
    model = diff_drive()
    limits = MobileLimits(velocity=1, angular_velocity=2, acceleration=3, angular_acceleration=4,
                          wheel_speed=10)  # fmt: skip
    report = reference(model).check(limits)
    # The drive stops and the arc starts at once: v and ω step there, an unbounded
    # acceleration, reported as ±inf at the junction (and nothing else is violated).
    junction = TURN.duration + DRIVE.duration
    assert {(v.quantity, v.time, v.value) for v in report.violations} == {
        ("acceleration", junction, np.inf),
        ("angular acceleration", junction, -np.inf),
    }
    smooth = MobileTrajectory(reference_segments()[:2], model).check(limits)
    assert smooth.ok
    expected = expected_peaks()
    expected["acceleration"] = ([-1.0], [np.inf])
    expected["angular acceleration"] = ([-np.inf], [2.0])
    for quantity, (low, high) in expected.items():
        found_low, found_high = report.peaks[quantity]
        np.testing.assert_allclose(found_low, low, rtol=CLOSED_FORM, atol=CLOSED_FORM)
        np.testing.assert_allclose(found_high, high, rtol=CLOSED_FORM, atol=CLOSED_FORM)
    assert report.channels["wheel speed"] == ("left wheel", "right wheel")
    assert report.channels["velocity"] == ("base",)
    np.testing.assert_array_equal(report.bounds["wheel speed"][0], [-10.0, -10.0])


def test_check_finds_each_violation_where_it_happens():
    report = reference(diff_drive()).check(MobileLimits(velocity=0.4, angular_velocity=(-0.3, 2.0),
                                                        wheel_speed=4.5))  # fmt: skip
    assert not report.ok
    found = {(v.quantity, v.channel, v.bound): v for v in report.violations}
    drive_start = TURN.duration
    speed = found[("velocity", "base", 0.4)]
    assert speed.value == pytest.approx(0.5, rel=CLOSED_FORM)
    assert drive_start + 0.5 <= speed.time <= drive_start + 4.0  # on the cruise
    turn_rate = found[("angular velocity", "base", -0.3)]
    assert turn_rate.value == pytest.approx(ARC_W, rel=CLOSED_FORM)
    assert turn_rate.time == pytest.approx(TURN.duration + DRIVE.duration, rel=CLOSED_FORM)
    for channel in ("left wheel", "right wheel"):  # both at 0.5 / 0.1 = 5 rad/s on the drive
        wheel = found[("wheel speed", channel, 4.5)]
        assert wheel.value == pytest.approx(5.0, rel=CLOSED_FORM)
        assert drive_start + 0.5 <= wheel.time <= drive_start + 4.0
    assert len(report.violations) == 4
    text = str(report)
    assert "left wheel" in text and "right wheel" in text and "<-- exceeds" in text
    assert "wheel speed of right wheel reaches" in text


def test_check_tolerance():
    plan = reference()
    just_below = MobileLimits(velocity=0.5 * (1 - 1e-10))
    assert plan.check(just_below).ok  # default rtol 1e-9: a touch is not a violation
    assert not plan.check(just_below, rtol=1e-12).ok
    with pytest.raises(InvalidInputError, match=r"rtol must be > 0"):
        plan.check(just_below, rtol=0.0)


def test_check_defaults_to_the_model_limits():
    model = diff_drive(wheel_speed_limit=1.0, limits=MobileLimits(velocity=2.0))
    report = reference(model).check()
    assert set(report.peaks) == {"velocity", "wheel speed"}
    assert not report.ok and all(v.quantity == "wheel speed" for v in report.violations)
    assert reference().check().ok and reference().check().peaks == {}


def test_check_refuses_wheel_limits_on_a_unicycle_and_other_limits():
    with pytest.raises(InvalidInputError, match=r"a wheel_speed limit needs a DiffDrive model"):
        reference().check(MobileLimits(wheel_speed=1.0))
    with pytest.raises(InvalidInputError, match=r"limits must be a trajkit.mobile.MobileLimits"):
        reference().check(tk.Limits(velocity=1.0))


def test_zero_length_plan():
    still = Straight(START, tk.trapezoidal(0.0, 0.0, 1.0, 1.0))
    plan = MobileTrajectory([still], Unicycle())
    assert plan.duration == 0.0
    np.testing.assert_array_equal(plan.pose(3.0), START)
    assert plan.commands(10.0)[0].size == 1
    assert plan.check(MobileLimits(velocity=1.0, acceleration=1.0)).ok


# CSV ------------------------------------------------------------------------------
UNICYCLE_HEADER = ("t [s],x [m],y [m],theta [rad],v [m/s],omega [rad/s],v_rate [m/s^2],"
                   "omega_rate [rad/s^2]")  # fmt: skip


def test_to_csv_reads_back_exactly(tmp_path):
    plan = reference()
    path = plan.to_csv(tmp_path / "plan.csv", 0.1)
    assert path == tmp_path / "plan.csv"
    lines = path.read_text().splitlines()
    assert lines[0] == UNICYCLE_HEADER
    table = np.loadtxt(path, delimiter=",", skiprows=1)
    state = plan.state(plan.times(0.1))
    expected = np.stack([state.t, state.x, state.y, state.theta, state.v, state.omega,
                         state.acceleration, state.angular_acceleration], 1)  # fmt: skip
    np.testing.assert_array_equal(table, expected)


def test_to_csv_adds_wheels_for_a_diff_drive(tmp_path):
    plan = constant_twist(0.5, 0.2, 2.0, model=diff_drive())
    path = plan.to_csv(tmp_path / "arc.csv", 0.25)
    header = path.read_text().splitlines()[0]
    assert header == UNICYCLE_HEADER + ",wheel_left [rad/s],wheel_right [rad/s]"
    table = np.loadtxt(path, delimiter=",", skiprows=1)
    assert table.shape == (9, 10)
    np.testing.assert_array_equal(table[:, 8:], plan.wheel_speeds(plan.times(0.25)))
    support.assert_state(table[-1, 1:4], arc_pose([0, 0, 0], 0.5, 0.2, 2.0), rtol=WORLD_ROUNDING)
    with pytest.raises(InvalidInputError, match=r"sample_step must be > 0"):
        plan.to_csv(tmp_path / "bad.csv", -0.1)


# Jumps inside a segment's time law (issue 16, item 1) -------------------------------
def _stepping_law(first: float, second: float) -> tk.Trajectory:
    """Distance (or angle) at speed ``first`` for 1 s, then ``second`` for 1 s: one
    velocity step at t = 1 s."""
    return tk.Trajectory([0.0, 1.0, 2.0], [[[first], [second]], [[0.0], [first]]])


def test_a_velocity_step_inside_a_drive_is_an_unbounded_acceleration():
    drive = Straight(START, _stepping_law(0.2, 0.5))  # speeds up at once at t = 1 s
    arc = Arc(drive.end_pose, 0.5, 0.0, 1.0)  # carries on at 0.5 m/s: no junction step
    plan = MobileTrajectory([drive, arc], Unicycle())
    report = plan.check(MobileLimits(velocity=1.0, acceleration=10.0))
    (violation,) = report.violations
    assert (violation.quantity, violation.time, violation.value, violation.bound) == (
        "acceleration", 1.0, np.inf, 10.0,
    )  # fmt: skip
    assert violation.cause == "the twist jumps there (a segment junction or a law's step)"
    assert "is unbounded (inf) at t=1 s" in str(violation)
    assert report.peaks["acceleration"][1][0] == np.inf
    assert report.peaks["velocity"][1][0] == pytest.approx(0.5, rel=CLOSED_FORM)


def test_a_turn_slowing_at_once_is_an_unbounded_angular_deceleration_after_a_drive():
    drive = Straight(START, DRIVE)  # a smooth trapezoid: no step, only bounded rates
    turn = Turn(drive.end_pose, _stepping_law(0.8, 0.3))
    # The turn starts at 0.8 rad/s from a stop (junction) and slows to 0.3 (law step).
    report = MobileTrajectory([drive, turn], Unicycle()).check(
        MobileLimits(angular_acceleration=5.0, acceleration=1.0)
    )
    found = {(v.quantity, v.value): v.time for v in report.violations}
    assert found == {
        ("angular acceleration", np.inf): DRIVE.duration,  # 0 -> 0.8 at the junction
        ("angular acceleration", -np.inf): DRIVE.duration + 1.0,  # 0.8 -> 0.3 in the law
    }
    # A trapezoid law (velocity continuous) stays within the acceleration limit.
    assert MobileTrajectory([drive], Unicycle()).check(MobileLimits(acceleration=1.0)).ok


# ------------------------------------ continuity claims (issue 16, item 1)

_BASE_LIMITS = {"vmax": 0.5, "wmax": 1.0, "amax": 1.0, "alpha_max": 2.0}


@pytest.mark.parametrize(
    ("options", "expected"),
    [
        ({"profile": "trapezoid"}, 1),
        ({"blend_ratio": 0.3}, 1),
        ({"profile": "scurve", "jmax": 3.0, "angular_jmax": 5.0}, 2),
    ],
)
def test_rotate_translate_rotate_claims_the_continuity_it_has(options, expected) -> None:
    plan = rotate_translate_rotate((2.0, 1.0, 1.0), **_BASE_LIMITS, **options)
    assert plan.info["continuity"] == plan.continuity == expected


def test_constant_twist_is_smooth_and_a_twist_step_between_segments_is_seen() -> None:
    arc = constant_twist(0.5, 0.2, 3.0)
    assert arc.info["continuity"] == arc.continuity == float("inf")
    first = Arc((0.0, 0.0, 0.0), 0.5, 0.2, 1.0)
    same = Arc(first.end_pose, 0.5, 0.2, 1.0)
    faster = Arc(first.end_pose, 0.7, 0.2, 1.0)
    assert MobileTrajectory([first, same], Unicycle()).continuity == 2  # rates 0 both sides
    assert MobileTrajectory([first, faster], Unicycle()).continuity == 0  # v steps
    # A drive whose law's acceleration jumps (a trapezoid): twist continuous, rates not.
    drive = Straight((0.0, 0.0, 0.0), tk.trapezoidal(0.0, 1.0, 0.5, 1.0))
    assert MobileTrajectory([drive], Unicycle()).continuity == 1


def test_check_verifies_jerk_limits_on_the_phase_laws() -> None:
    # A goto's S-curve phases are shaped by jerk limits; check() verifies them exactly
    # (the scenario's limit check passes the base's jerk and angular_jerk here).
    plan = rotate_translate_rotate((2.0, 1.0, 1.0), **_BASE_LIMITS, profile="scurve",
                                   jmax=3.0, angular_jmax=5.0)  # fmt: skip
    report = plan.check(jerk=3.0, angular_jerk=5.0)
    assert report.ok
    np.testing.assert_allclose(report.peaks["jerk"][1], [3.0], rtol=1e-12)
    np.testing.assert_allclose(report.peaks["angular jerk"][0], [-5.0], rtol=1e-12)
    tight = plan.check(jerk=2.0, angular_jerk=5.0)
    assert not tight.ok and {v.quantity for v in tight.violations} == {"jerk"}
    # A trapezoid drive's acceleration steps: its jerk is unbounded.
    steps = rotate_translate_rotate((2.0, 1.0, 1.0), **_BASE_LIMITS).check(jerk=3.0)
    assert not steps.ok and np.isinf(steps.violations[0].value)
    with pytest.raises(InvalidInputError, match="angular_jerk must be > 0"):
        plan.check(angular_jerk=-1.0)


def test_flat_output_plans_measure_the_continuity_of_their_curve() -> None:
    # The heading follows the curve's velocity: a C2 cubic spline gives a continuous twist
    # whose rates jump at the knots; an analytic figure eight is smooth (2: all it reads).
    from trajkit.mobile import FigureEight, flat_trajectory, spline_output

    assert flat_trajectory(FigureEight(2.0, 1.0, 20.0)).continuity == 2
    spline = spline_output([[0.0, 0.0], [1.0, 0.5], [2.0, 0.0], [3.0, 1.0]])
    assert spline.trajectory.continuity == 2
    assert flat_trajectory(spline).continuity == 1
