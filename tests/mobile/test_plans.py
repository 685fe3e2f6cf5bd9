"""Tests of trajkit.mobile.plans: constant twist (seed 000's Jackal arc) and
rotate–translate–rotate (seed 000's wheeled robot), with their closed forms.

Random starts and goals include exact zeros, goals equal to the start, goals
behind the robot and headings at and near ±π, for LSPB (blend ratio),
time-optimal trapezoid and S-curve phases.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import support
import trajkit as tk
from support import CLOSED_FORM, limits_positive
from trajkit import InvalidInputError
from trajkit.mobile import (
    DiffDrive,
    MobileLimits,
    Straight,
    Turn,
    Unicycle,
    constant_twist,
    jackal,
    rotate_translate_rotate,
)
from trajkit.mobile.models import resolve_model
from trajkit.mobile.plans import phase_law

# Tolerances ---------------------------------------------------------------------
SEED_ARC = 1e-12  # absolute (m, rad): seed 000's 15 s arc against its closed form
GOAL = 1e-9  # relative to max(1, |goal|): where rotate-translate-rotate ends
PROPERTY = settings(max_examples=100, deadline=None)

# Seed 000 -------------------------------------------------------------------------
SEED_V, SEED_W, SEED_T, SEED_RATE = 0.1, math.radians(10.0), 15.0, 10.0
RTR_GOAL, RTR_VMAX, RTR_WMAX, RTR_RATIO = (5.0, 3.0, 1.5), 0.2, math.radians(30.0), 0.1


def test_seed000_constant_twist_ends_exactly_on_the_arc():
    plan = constant_twist(SEED_V, SEED_W, SEED_T, rate_hz=SEED_RATE, model=jackal())
    radius, theta = SEED_V / SEED_W, SEED_W * SEED_T
    expected = [radius * math.sin(theta), radius * (1.0 - math.cos(theta)), theta]
    assert np.abs(plan.end_pose - expected).max() <= SEED_ARC
    assert np.abs(plan.pose(SEED_T) - expected).max() <= SEED_ARC
    times, twists = plan.commands(SEED_RATE)
    assert times.size == 150 and plan.info["command_count"] == 150
    support.assert_state(times, np.arange(150) / 10.0, rtol=support.ROUNDING)
    np.testing.assert_array_equal(twists, np.tile([SEED_V, SEED_W], (150, 1)))
    assert plan.info["radius"] == pytest.approx(radius, rel=CLOSED_FORM)
    assert plan.info["turned"] == pytest.approx(theta, rel=CLOSED_FORM)
    assert plan.info["distance"] == pytest.approx(1.5, rel=CLOSED_FORM)
    assert plan.info["rate_hz"] == 10.0 and plan.info["plan"] == "constant_twist"
    assert plan.model.name == "jackal"
    assert plan.check().ok  # 0.1 m/s and 10 deg/s are well inside the Jackal's limits


def test_constant_twist_lines_spins_and_reverse():
    line = constant_twist(-0.5, 0.0, 4.0, start=(1.0, 1.0, math.pi / 2))
    assert line.info["radius"] == math.inf
    assert line.info["distance"] == 2.0  # along the path, whatever the direction
    support.assert_state(line.end_pose, [1.0, -1.0, math.pi / 2], rtol=CLOSED_FORM)
    spin = constant_twist(0.0, -1.0, 2.0)
    assert spin.info["radius"] == 0.0 and spin.info["turned"] == -2.0
    np.testing.assert_array_equal(spin.end_pose, [0.0, 0.0, -2.0])
    assert spin.info["rate_hz"] is None and spin.info["command_count"] is None
    assert isinstance(spin.model, Unicycle)
    assert [s.kind for s in spin.segments] == ["arc"]


@given(
    st.integers(1, 100_000),
    st.sampled_from([1.0, 3.0, 7.0, 10.0, 30.0, 50.0, 100.0, 1000.0]),
    st.sampled_from([0.0, 1e-15, -1e-15, 1e-13, -1e-13, 1e-11, -1e-11, 0.3, -0.3]),
)
def test_command_count_is_the_number_of_commands(count, rate, perturbation):
    # Durations at and within rounding of a whole number of periods.
    duration = count / rate * (1.0 + perturbation)
    plan = constant_twist(0.1, 0.1, duration, rate_hz=rate)
    assert plan.info["command_count"] == plan.commands(rate)[0].size


@pytest.mark.parametrize(
    ("args", "kwargs", "match"),
    [
        ((0.1, 0.1, 0.0), {}, r"duration must be > 0, got 0 s"),
        ((0.1, 0.1, -2.0), {}, r"duration must be > 0, got -2 s"),
        ((np.nan, 0.1, 1.0), {}, r"v must be finite"),
        ((0.1, np.inf, 1.0), {}, r"omega must be finite"),
        (([0.1, 0.2], 0.1, 1.0), {}, r"v must be a single number"),
        ((0.1, 0.1, 1.0), {"rate_hz": 0.0}, r"rate_hz must be > 0, got 0 Hz"),
        ((0.1, 0.1, 1.0), {"start": (0.0,)}, r"start must be a pose"),
        ((0.1, 0.1, 1.0), {"model": "jackal"}, r"model must be a trajkit.mobile Unicycle"),
    ],
)
def test_constant_twist_refuses_bad_input(args, kwargs, match):
    with pytest.raises(InvalidInputError, match=match):
        constant_twist(*args, **kwargs)


# rotate-translate-rotate: seed 000 -------------------------------------------------
def test_seed000_rotate_translate_rotate_phases():
    plan = rotate_translate_rotate(RTR_GOAL, vmax=RTR_VMAX, wmax=RTR_WMAX, blend_ratio=RTR_RATIO)
    first = math.atan2(3.0, 5.0)
    expected = (
        first / (RTR_WMAX * 0.9),
        math.sqrt(34.0) / (RTR_VMAX * 0.9),
        (1.5 - first) / (RTR_WMAX * 0.9),
    )
    durations = plan.info["phase_durations"]
    for found, want in zip(durations, expected, strict=True):
        assert found == pytest.approx(want, rel=CLOSED_FORM)
    for found, rounded, digits in zip(durations, (1.1468, 32.394, 2.0363), (4, 3, 4), strict=True):
        assert round(found, digits) == rounded
    assert plan.duration == pytest.approx(sum(expected), rel=CLOSED_FORM)
    assert [s.kind for s in plan.segments] == ["turn", "straight", "turn"]
    assert plan.info["phases"] == (
        "turn to face the goal", "drive to the goal", "turn to the final heading"
    )  # fmt: skip
    assert plan.info["turns"] == pytest.approx((first, 1.5 - first), rel=CLOSED_FORM)
    assert plan.info["distance"] == pytest.approx(math.sqrt(34.0), rel=CLOSED_FORM)
    assert plan.info["profile"] == "lspb blend_ratio"
    support.assert_state(plan.end_pose, RTR_GOAL, rtol=GOAL)
    report = plan.check(MobileLimits(velocity=RTR_VMAX, angular_velocity=RTR_WMAX))
    assert report.ok
    # The LSPB cruises exactly at the limits.
    assert report.peaks["velocity"][1][0] == pytest.approx(RTR_VMAX, rel=CLOSED_FORM)
    assert report.peaks["angular velocity"][1][0] == pytest.approx(RTR_WMAX, rel=CLOSED_FORM)


def test_seed000_on_the_jackal_keeps_its_wheels_within_limits():
    plan = rotate_translate_rotate(RTR_GOAL, vmax=RTR_VMAX, wmax=RTR_WMAX, blend_ratio=RTR_RATIO,
                                   model=jackal())  # fmt: skip
    report = plan.check()
    assert report.ok and "left wheel" in str(report)
    assert report.peaks["wheel speed"][1].max() == pytest.approx(RTR_VMAX / 0.098, rel=CLOSED_FORM)


# rotate-translate-rotate: closed forms and cases -----------------------------------
def trapezoid_time(distance: float, vmax: float, amax: float) -> float:
    """Time-optimal rest-to-rest trapezoid (or triangle)."""
    distance = abs(distance)
    if distance >= vmax**2 / amax:
        return distance / vmax + vmax / amax
    return 2.0 * math.sqrt(distance / amax)


def test_time_optimal_phases_are_trapezoids():
    plan = rotate_translate_rotate((3.0, 4.0, 0.0), (0.0, 0.0, math.pi / 2),
                                   vmax=1.0, wmax=2.0, amax=0.5, alpha_max=4.0)  # fmt: skip
    first = math.atan2(4.0, 3.0) - math.pi / 2
    expected = (trapezoid_time(first, 2.0, 4.0), trapezoid_time(5.0, 1.0, 0.5),
                trapezoid_time(math.atan2(4.0, 3.0), 2.0, 4.0))  # fmt: skip
    assert plan.info["phase_durations"] == pytest.approx(expected, rel=CLOSED_FORM)
    assert plan.info["turns"] == pytest.approx((first, -math.atan2(4.0, 3.0)), rel=CLOSED_FORM)
    assert plan.info["profile"] == "trapezoid"


def test_goal_behind_with_reverse_drives_backwards():
    plan = rotate_translate_rotate((-2.0, 0.0, 0.0), vmax=1, wmax=1, amax=1, alpha_max=1,
                                   reverse=True)  # fmt: skip
    assert [s.kind for s in plan.segments] == ["straight"]
    assert plan.info["distance"] == -2.0
    t = np.linspace(0.0, plan.duration, 101)
    assert np.all(plan.twist(t)[:, 0] <= 0.0) and plan.twist(plan.duration / 2)[0] == -1.0
    support.assert_state(plan.end_pose, [-2.0, 0.0, 0.0], rtol=GOAL)
    forwards = rotate_translate_rotate((-2.0, 0.0, 0.0), vmax=1, wmax=1, amax=1, alpha_max=1)
    assert [s.kind for s in forwards.segments] == ["turn", "straight", "turn"]
    assert abs(forwards.info["turns"][0]) == pytest.approx(math.pi, rel=CLOSED_FORM)


def test_goal_without_heading_has_no_final_turn():
    plan = rotate_translate_rotate((1.0, 1.0), vmax=1, wmax=1, amax=1, alpha_max=1)
    assert plan.info["phases"] == ("turn to face the goal", "drive to the goal")
    assert len(plan.info["turns"]) == 1
    support.assert_state(plan.end_pose, [1.0, 1.0, math.pi / 4], rtol=GOAL)


def test_goal_at_the_start_position_only_turns():
    plan = rotate_translate_rotate((1.0, 2.0, -3.0), (1.0, 2.0, 3.0), wmax=1, alpha_max=1)
    assert [s.kind for s in plan.segments] == ["turn"]
    # The short way: from 3 to -3 rad is +0.283 rad through π, not -6 rad.
    assert plan.info["turns"] == pytest.approx((2 * math.pi - 6.0,), rel=CLOSED_FORM)
    assert plan.info["distance"] == 0.0


def test_goal_equal_to_start_is_a_standstill():
    plan = rotate_translate_rotate((0.5, 0.5, 1.0), (0.5, 0.5, 1.0))  # needs no limits at all
    assert plan.duration == 0.0 and plan.info["phases"] == ()
    np.testing.assert_array_equal(plan.end_pose, [0.5, 0.5, 1.0])
    np.testing.assert_array_equal(plan.twist(0.0), [0.0, 0.0])


def test_limits_default_to_the_models():
    model = DiffDrive(0.1, 0.4, wheel_speed_limit=12.0,
                      limits=MobileLimits(velocity=1.0, angular_velocity=2.0, acceleration=0.5,
                                          angular_acceleration=1.0))  # fmt: skip
    plan = rotate_translate_rotate((2.0, 0.0, 0.0), model=model)
    assert plan.duration == pytest.approx(trapezoid_time(2.0, 1.0, 0.5), rel=CLOSED_FORM)
    assert plan.check().ok
    faster = rotate_translate_rotate((2.0, 0.0, 0.0), model=model, amax=1.0)
    assert faster.duration == pytest.approx(trapezoid_time(2.0, 1.0, 1.0), rel=CLOSED_FORM)


def test_controller_period_rounds_phases_up():
    plan = rotate_translate_rotate((3.0, 1.0, 2.0), vmax=0.7, wmax=1.1, amax=0.9, alpha_max=1.3,
                                   period=0.01)  # fmt: skip
    for duration in plan.info["phase_durations"]:
        periods = duration / 0.01
        assert periods == pytest.approx(round(periods), rel=CLOSED_FORM)
    assert plan.check(MobileLimits(0.7, 1.1, 0.9, 1.3)).ok
    support.assert_state(plan.end_pose[:2], [3.0, 1.0], rtol=GOAL)


def test_scurve_phases_keep_their_jerk():
    limits = {"vmax": 1, "wmax": 1, "amax": 1, "alpha_max": 1, "jmax": 2, "angular_jmax": 3}
    plan = rotate_translate_rotate((3.0, 4.0, 2.0), (1.0, 1.0, -3.0), profile="scurve", **limits)
    assert plan.info["profile"] == "scurve"
    for segment in plan.segments:
        jerk = 2.0 if isinstance(segment, Straight) else 3.0
        assert segment.law.check(tk.Limits(velocity=1, acceleration=1, jerk=jerk)).ok
    assert plan.check(MobileLimits(1, 1, 1, 1)).ok


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"wmax": 1, "amax": 1, "alpha_max": 1}, r"the drive to the goal needs vmax \(m/s\)"),
        ({"vmax": 1, "amax": 1, "alpha_max": 1}, r"the turn to face the goal needs wmax \(rad/s\)"),
        ({"vmax": 1, "wmax": 1, "alpha_max": 1},
         r"drive to the goal needs amax \(m/s\^2\) for a time-optimal trapezoid, or a blend_ratio"),
        ({"vmax": 1, "wmax": 1, "amax": 1}, r"turn to face the goal needs alpha_max \(rad/s\^2\)"),
        ({"vmax": 1, "wmax": 1, "amax": 1, "alpha_max": 1, "profile": "scurve",
          "angular_jmax": 1}, r"the drive to the goal needs jmax for an S-curve"),
        ({"vmax": 1, "wmax": 1, "amax": 1, "alpha_max": 1, "profile": "scurve", "jmax": 1},
         r"the turn to face the goal needs angular_jmax for an S-curve"),
        ({"vmax": 1, "wmax": 1, "blend_ratio": 0.1, "profile": "scurve"},
         r"blend_ratio describes the LSPB \(trapezoid\) rule only"),
        ({"vmax": 1, "wmax": 1, "profile": "lspb"},
         r"profile must be 'trapezoid' or 'scurve', got 'lspb'"),
        ({"vmax": -1, "wmax": 1, "blend_ratio": 0.1}, r"vmax must be > 0, got -1 m/s"),
        ({"vmax": 1, "wmax": np.nan, "blend_ratio": 0.1}, r"wmax must be finite"),
        ({"vmax": 1, "wmax": 1, "amax": 0}, r"amax must be > 0, got 0 m/s\^2"),
        ({"vmax": 1, "wmax": 1, "alpha_max": -2}, r"alpha_max must be > 0, got -2 rad/s\^2"),
        ({"vmax": 1, "wmax": 1, "jmax": 0}, r"jmax must be > 0, got 0 m/s\^3"),
        ({"vmax": 1, "wmax": 1, "angular_jmax": -1}, r"angular_jmax must be > 0, got -1 rad/s\^3"),
        ({"vmax": 1, "wmax": 1, "period": 0}, r"period must be > 0, got 0 s"),
        ({"vmax": 1, "wmax": 1, "blend_ratio": 0.7}, r"blend_ratio must be in \(0, 0.5\]"),
        ({"vmax": 1, "wmax": 1, "blend_ratio": 0.1, "model": "jackal"},
         r"model must be a trajkit.mobile Unicycle or DiffDrive, got str"),
    ],
)  # fmt: skip
def test_rotate_translate_rotate_bad_limits_name_the_argument(kwargs, match):
    with pytest.raises(InvalidInputError, match=match):
        rotate_translate_rotate((3.0, 4.0, 2.0), **kwargs)


@pytest.mark.parametrize(
    ("goal", "start", "match"),
    [
        ((1.0,), (0, 0, 0), r"goal must be \(x, y\) or \(x, y, theta\).*shape \(1,\)"),
        ((1.0, 2.0, 3.0, 4.0), (0, 0, 0), r"goal must be \(x, y\) or \(x, y, theta\)"),
        ((1.0, np.nan), (0, 0, 0), r"goal must be finite"),
        ((1.0, 2.0), (0, 0, 0, 0), r"start must be a pose"),
        ((1.0, 2.0), (0, np.inf, 0), r"start must be finite"),
    ],
)
def test_rotate_translate_rotate_bad_poses(goal, start, match):
    with pytest.raises(InvalidInputError, match=match):
        rotate_translate_rotate(goal, start, vmax=1, wmax=1, blend_ratio=0.1)


def test_profile_is_checked_even_without_motion():
    with pytest.raises(InvalidInputError, match=r"profile must be 'trapezoid' or 'scurve'"):
        rotate_translate_rotate((0.0, 0.0, 0.0), profile="bang-bang")


# rotate-translate-rotate: properties ------------------------------------------------
@st.composite
def start_and_goal(draw: st.DrawFn) -> tuple[np.ndarray, np.ndarray]:
    """A start pose and a goal: anywhere, the start itself, behind it, or in place."""
    start = draw(support.poses())
    kind = draw(st.sampled_from(["any", "same", "behind", "in place", "position only"]))
    if kind == "same":
        goal = start.copy()
    elif kind == "behind":
        back = draw(st.floats(1e-3, 10.0))
        goal = np.array([start[0] - back * math.cos(start[2]), start[1] - back * math.sin(start[2]),
                         draw(support.headings)])  # fmt: skip
    elif kind == "in place":
        goal = np.array([start[0], start[1], draw(support.headings)])
    else:
        goal = draw(support.poses())
    if kind == "position only":
        goal = goal[:2]
    return start, goal


def phases(plan):
    """(is a turn, amount, duration) of every phase, amounts from the plan's info."""
    if not plan.info["phases"]:  # already there: one standstill of zero length
        assert plan.duration == 0.0 and len(plan.segments) == 1
        return []
    turns = iter(plan.info["turns"])
    out = []
    for phase, duration, segment in zip(plan.info["phases"], plan.info["phase_durations"],
                                        plan.segments, strict=True):  # fmt: skip
        turning = phase.startswith("turn")
        assert isinstance(segment, Turn if turning else Straight)
        # A turn left out (no amount) still has its entry in "turns".
        amount = next(a for a in turns if abs(a) > 1e-12) if turning else plan.info["distance"]
        out.append((turning, amount, duration))
    return out


def assert_reaches(plan, start: np.ndarray, goal: np.ndarray, reverse: bool) -> None:
    end = plan.end_pose
    support.assert_state(end[:2], goal[:2], rtol=GOAL)
    if goal.size == 3:
        support.assert_heading(end[2], goal[2], atol=GOAL)
    turns = plan.info["turns"]
    assert all(abs(turn) <= math.pi * (1 + 1e-15) for turn in turns)  # the short way round
    if reverse and plan.info["distance"] < 0:
        assert abs(turns[0]) <= math.pi / 2 * (1 + 1e-15)
    kinds = [s.kind for s in plan.segments]
    assert len(kinds) <= 3 and all(kind in ("turn", "straight") for kind in kinds)
    assert len(plan.info["phase_durations"]) == len(plan.info["phases"])
    np.testing.assert_array_equal(plan.start_pose, start)


@PROPERTY
@given(start_and_goal(), limits_positive, limits_positive, st.floats(0.01, 0.5), st.booleans())
def test_lspb_reaches_the_goal_within_limits(poses, vmax, wmax, ratio, reverse):
    start, goal = poses
    plan = rotate_translate_rotate(goal, start, vmax=vmax, wmax=wmax, blend_ratio=ratio,
                                   reverse=reverse)  # fmt: skip
    assert_reaches(plan, start, goal, reverse)
    assert plan.check(MobileLimits(velocity=vmax, angular_velocity=wmax)).ok
    for turning, amount, duration in phases(plan):  # t_f = distance / (speed (1 - ratio))
        speed = wmax if turning else vmax
        assert duration == pytest.approx(abs(amount) / (speed * (1 - ratio)), rel=CLOSED_FORM)


@PROPERTY
@given(start_and_goal(), *(limits_positive,) * 4, st.booleans())
def test_trapezoid_reaches_the_goal_within_limits(poses, vmax, wmax, amax, alpha, reverse):
    start, goal = poses
    plan = rotate_translate_rotate(goal, start, vmax=vmax, wmax=wmax, amax=amax, alpha_max=alpha,
                                   reverse=reverse)  # fmt: skip
    assert_reaches(plan, start, goal, reverse)
    assert plan.check(MobileLimits(vmax, wmax, amax, alpha)).ok
    for turning, amount, duration in phases(plan):  # each the time-optimal trapezoid
        limits = (wmax, alpha) if turning else (vmax, amax)
        assert duration == pytest.approx(trapezoid_time(amount, *limits), rel=CLOSED_FORM)


@settings(max_examples=50, deadline=None)
@given(start_and_goal(), *(limits_positive,) * 6, st.booleans(), st.sampled_from([None, 0.01]))
def test_scurve_reaches_the_goal_within_limits(poses, vmax, wmax, amax, alpha, jmax, wjmax,
                                               reverse, dt):  # fmt: skip
    start, goal = poses
    plan = rotate_translate_rotate(goal, start, vmax=vmax, wmax=wmax, amax=amax, alpha_max=alpha,
                                   jmax=jmax, angular_jmax=wjmax, profile="scurve", reverse=reverse,
                                   period=dt)  # fmt: skip
    assert_reaches(plan, start, goal, reverse)
    assert plan.check(MobileLimits(vmax, wmax, amax, alpha)).ok
    for segment in plan.segments:
        jerk = jmax if isinstance(segment, Straight) else wjmax
        assert segment.law.check(tk.Limits(jerk=jerk)).ok
        if dt is not None:
            assert segment.duration / dt == pytest.approx(round(segment.duration / dt), rel=1e-9)


@PROPERTY
@given(support.poses(), st.floats(0.0, 10.0), limits_positive, limits_positive)
def test_goal_straight_ahead_needs_no_turn(start, distance, vmax, amax):
    assume(distance > 1e-9)
    goal = start[:2] + distance * np.array([math.cos(start[2]), math.sin(start[2])])
    plan = rotate_translate_rotate(goal, start, vmax=vmax, wmax=1.0, amax=amax, alpha_max=1.0)
    assert all(abs(turn) <= 1e-9 for turn in plan.info["turns"])
    assert plan.info["distance"] == pytest.approx(distance, rel=1e-9)


# Helpers of the module ------------------------------------------------------------
def test_resolve_model():
    assert resolve_model(None) == Unicycle()
    robot = jackal()
    assert resolve_model(robot) is robot
    with pytest.raises(InvalidInputError, match=r"model must be a trajkit.mobile Unicycle"):
        resolve_model(object())  # type: ignore[arg-type]


def test_phase_law():
    units = ("m", "m/s", "m/s^2")
    law = phase_law("drive", 2.0, 1.0, 0.5, None, "trapezoid", None, None, units)
    assert law.duration == pytest.approx(trapezoid_time(2.0, 1.0, 0.5), rel=CLOSED_FORM)
    lspb = phase_law("drive", -2.0, 1.0, None, None, "trapezoid", 0.25, None, units)
    assert lspb.duration == pytest.approx(2.0 / (1.0 * 0.75), rel=CLOSED_FORM)
    assert float(lspb.position(lspb.duration)[0]) == pytest.approx(-2.0, rel=CLOSED_FORM)
    curve = phase_law("drive", 2.0, 1.0, 0.5, 2.0, "scurve", None, None, units)
    assert curve.check(tk.Limits(velocity=1.0, acceleration=0.5, jerk=2.0)).ok
    with pytest.raises(InvalidInputError, match=r"the drive needs a speed limit \(m/s\)"):
        phase_law("drive", 2.0, None, 0.5, None, "trapezoid", None, None, units)
    with pytest.raises(InvalidInputError, match=r"the spin needs spin_rate \(m/s\)"):
        phase_law("spin", 2.0, None, 0.5, None, "trapezoid", None, None, units,
                  ("spin_rate", "spin_acceleration", "spin_jerk"))  # fmt: skip
    with pytest.raises(InvalidInputError, match=r"the drive needs a jerk limit for an S-curve"):
        phase_law("drive", 2.0, 1.0, 0.5, None, "scurve", None, None, units)
    with pytest.raises(InvalidInputError, match=r"profile must be 'trapezoid' or 'scurve'"):
        phase_law("drive", 2.0, 1.0, 0.5, None, "cubic", None, None, units)  # type: ignore[arg-type]


# Limits by direction, wheels and the plan's own limits --------------------------
def test_asymmetric_speed_limits_count_on_the_side_the_phase_moves():
    limits = MobileLimits(velocity=(-0.1, 0.5), acceleration=1.0, angular_velocity=1.0,
                          angular_acceleration=1.0)  # fmt: skip
    ahead = rotate_translate_rotate((1.0, 0.0), limits=limits)
    assert ahead.info["phase_durations"] == pytest.approx((trapezoid_time(1.0, 0.5, 1.0),),
                                                          rel=CLOSED_FORM)  # fmt: skip
    behind = rotate_translate_rotate((-1.0, 0.0), limits=limits, reverse=True)
    assert behind.info["phase_durations"] == pytest.approx((trapezoid_time(1.0, 0.1, 1.0),),
                                                           rel=CLOSED_FORM)  # fmt: skip
    assert ahead.check().ok and behind.check().ok


def test_forward_only_limits_refuse_a_reverse_drive_but_plan_forwards():
    limits = MobileLimits(velocity=(0.0, 0.5), acceleration=1.0, angular_velocity=1.0,
                          angular_acceleration=1.0)  # fmt: skip
    assert rotate_translate_rotate((1.0, 1.0), limits=limits).check().ok
    with pytest.raises(tk.InfeasibleError, match=r"moves backwards .* allow no speed that way"):
        rotate_translate_rotate((-1.0, 0.0), limits=limits, reverse=True)


def test_wheel_limit_caps_drive_and_turn_speeds():
    model = DiffDrive(0.1, 0.5, wheel_speed_limit=5.0,
                      limits=MobileLimits(velocity=1.0, angular_velocity=5.0, acceleration=1.0,
                                          angular_acceleration=50.0))  # fmt: skip
    plan = rotate_translate_rotate((2.0, 1.0, 1.0), model=model)
    report = plan.check()
    assert report.ok
    # Drive: both wheels at 5 rad/s -> 0.5 m/s; turns: one wheel each way -> 2 rad/s.
    assert report.peaks["velocity"][1][0] == pytest.approx(0.5, rel=CLOSED_FORM)
    assert report.peaks["angular velocity"][1][0] == pytest.approx(2.0, rel=CLOSED_FORM)
    assert report.peaks["wheel speed"][1].max() == pytest.approx(5.0, rel=CLOSED_FORM)


def test_a_plan_keeps_the_limits_it_was_made_for():
    limits = MobileLimits(velocity=0.3, angular_velocity=0.5, acceleration=0.2,
                          angular_acceleration=0.4)  # fmt: skip
    plan = rotate_translate_rotate((1.0, 1.0, 0.0), limits=limits, model=jackal())
    assert plan.limits == limits
    assert plan.check().bounds["velocity"][1][0] == 0.3  # not the Jackal's 2 m/s
    given = rotate_translate_rotate((1.0, 1.0), limits=limits, vmax=0.2)
    assert float(given.limits.velocity.upper) == 0.2
    with pytest.raises(InvalidInputError, match="reverse must be True or False"):
        rotate_translate_rotate((1.0, 1.0), limits=limits, reverse="no")


def test_absurd_command_counts_are_refused():
    with pytest.raises(InvalidInputError, match=r"gives 1e\+10 commands; at most 1e\+08"):
        constant_twist(0.1, 0.1, 1e9, rate_hz=10.0)
    with pytest.raises(InvalidInputError, match="commands; at most"):
        constant_twist(0.1, 0.1, 10.0, rate_hz=1e308)  # the product overflows to inf
