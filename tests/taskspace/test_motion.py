"""Tests of trajkit.taskspace.motion: time laws, timed paths, SLERP orientation, poses.

Cartesian limits are checked on the tool itself (dense samples plus the law's own
breakpoints and extrema), derivatives against central differences, the seed-003
cubic line against its closed form.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import support
import trajkit as tk
from support import CLOSED_FORM, FINITE_DIFFERENCE
from trajkit.errors import InfeasibleError, InvalidInputError
from trajkit.rotations import axis_rotation, rotation_error
from trajkit.taskspace import (
    Arc,
    Ellipse,
    FigureEight,
    Line,
    Polyline,
    TaskSegment,
    TaskTrajectory,
    path_law,
    through_poses,
    timed,
)

# Tolerances ---------------------------------------------------------------------
SEED003 = 1e-12  # absolute: the seed's cubic line, coordinates up to 20
EXACT = 1e-12  # absolute: end points and rests of O(1) motions
LIMIT_RTOL = 1e-9  # relative: a limit is met or reached
FD_STEP = 1e-5  # time step (s) of the central differences
DENSE = 20001  # samples of a whole motion
FEW = settings(max_examples=25, deadline=None)

PROFILES = ("linear", "cubic", "quintic", "septic", "trapezoid", "scurve")
REST_PROFILES = ("cubic", "quintic", "septic", "trapezoid")

SEED_LINE = ((0.0, -12.0, 20.0), (10.0, 12.0, 20.0))  # seed 003, 10 s, cubic


def curved_paths():
    return {
        "arc": Arc([1.0, 0.0, 0.0], [2.0, 0.0, 0.5], 1.5 * np.pi, normal=[0.0, 1.0, 1.0]),
        "ellipse": Ellipse([0.0, 1.0, 0.0], 0.8, 0.3, turns=1.5, phase=0.4),
        "eight": FigureEight([0.5, 0.0, 0.0], 2.0, 1.0),
    }


def rotation(rotvec) -> np.ndarray:
    rotvec = np.asarray(rotvec, dtype=float)
    angle = np.linalg.norm(rotvec)
    return axis_rotation(rotvec / angle, angle)


def pose(rotvec, position) -> np.ndarray:
    out = np.eye(4)
    out[:3, :3] = np.eye(3) if np.linalg.norm(rotvec) == 0 else rotation(rotvec)
    out[:3, 3] = position
    return out


def law_times(motion: TaskTrajectory) -> np.ndarray:
    """Every segment's breakpoints and velocity/acceleration extrema, in motion time."""
    times = [motion.breakpoints]
    for start, segment in zip(motion.breakpoints[:-1], motion.segments, strict=True):
        law = segment.law
        times.append(start + law.breakpoints)
        for order in (1, 2):
            extrema = law.extrema(order)
            times.append(start + np.concatenate([extrema.time_of_minimum, extrema.time_of_maximum]))
    return np.concatenate(times)


def dense_state(motion: TaskTrajectory):
    """The motion at dense samples plus the times where its peaks occur."""
    t = np.sort(np.concatenate([np.linspace(0.0, motion.duration, DENSE), law_times(motion)]))
    return motion.state(np.clip(t, 0.0, motion.duration))


def peak(values: np.ndarray) -> float:
    return float(np.linalg.norm(values, axis=1).max())


def interior_times(motion: TaskTrajectory, count: int) -> np.ndarray:
    """Times at least 10 FD steps away from every segment boundary and law breakpoint."""
    t = np.linspace(0.0, motion.duration, count)
    corners = law_times(motion)
    keep = np.abs(t[:, np.newaxis] - corners[np.newaxis, :]).min(axis=1) > 10 * FD_STEP
    return t[keep]


def law_kwargs(profile: str) -> dict:
    return {
        "linear": {"duration": 2.0},
        "cubic": {"duration": 2.0},
        "quintic": {"vmax": 1.5},
        "septic": {"amax": 3.0},
        "trapezoid": {"vmax": 1.0, "amax": 2.0},
        "scurve": {"vmax": 1.0, "amax": 2.0, "jmax": 10.0},
    }[profile]


# -------------------------------------------------------------------------- time laws
@pytest.mark.parametrize("profile", PROFILES)
@pytest.mark.parametrize("with_duration", [False, True])
def test_every_law_goes_from_0_to_1(profile, with_duration):
    kwargs = law_kwargs(profile)
    if with_duration:
        kwargs = {**kwargs, "duration": 7.5}
    law = path_law(profile, **kwargs)
    assert law.ndof == 1 and law.start_time == 0.0
    if with_duration:
        assert law.duration == pytest.approx(7.5, rel=CLOSED_FORM)
    assert law.position(0.0)[0] == pytest.approx(0.0, abs=EXACT)
    assert law.position(law.end_time)[0] == pytest.approx(1.0, abs=EXACT)
    if profile in REST_PROFILES or profile == "scurve":
        np.testing.assert_allclose(law.velocity([0.0, law.end_time]), 0.0, atol=EXACT)
    else:
        np.testing.assert_allclose(
            law.velocity([0.0, law.end_time]), 1.0 / law.duration, rtol=CLOSED_FORM
        )


def test_linear_law_from_vmax_alone_is_uniform():
    law = path_law("linear", speed_bound=4.0, vmax=2.0)
    assert law.duration == pytest.approx(2.0, rel=CLOSED_FORM)
    np.testing.assert_allclose(law.velocity(np.linspace(0.0, 2.0, 9)), 0.5, rtol=CLOSED_FORM)


def test_a_trajectory_law_is_used_as_given_and_shifted_to_start_at_zero():
    law = tk.quintic(0.0, 1.0, 3.0)
    assert path_law(law) is law
    late = tk.Trajectory(law.breakpoints + 2.0, law.coefficients)
    shifted = path_law(late)
    assert shifted.start_time == 0.0 and shifted.duration == pytest.approx(3.0, rel=CLOSED_FORM)
    t = np.linspace(0.0, 3.0, 31)
    np.testing.assert_allclose(shifted.position(t), law.position(t), atol=EXACT)
    motion = timed(Line([0.0, 0.0, 0.0], [2.0, 0.0, 0.0]), late)
    np.testing.assert_allclose(
        motion.state(t).position[:, 0], 2.0 * law.position(t)[:, 0], atol=EXACT
    )


# ------------------------------------------------------------------ Cartesian limits
@pytest.mark.parametrize(("length", "vmax", "amax"), [(26.0, 2.0, 1.5), (1.0, 3.0, 2.0)])
def test_trapezoid_on_a_line_is_time_optimal(length, vmax, amax):
    direction = np.array([3.0, 4.0, 12.0]) / 13.0
    line = Line([1.0, -1.0, 0.5], np.array([1.0, -1.0, 0.5]) + length * direction)
    motion = timed(line, "trapezoid", vmax=vmax, amax=amax)
    state = dense_state(motion)
    # Bang-coast-bang: amax always reached; vmax reached when the line is long enough.
    reachable = min(vmax, np.sqrt(length * amax))
    assert peak(state.velocity) == pytest.approx(reachable, rel=LIMIT_RTOL)
    assert peak(state.acceleration) == pytest.approx(amax, rel=LIMIT_RTOL)
    if length >= vmax**2 / amax:
        expected = length / vmax + vmax / amax
    else:
        expected = 2.0 * np.sqrt(length / amax)
    assert motion.duration == pytest.approx(expected, rel=CLOSED_FORM)
    # The tool moves along the line direction only (beyond rounding at the stops).
    moving = np.linalg.norm(state.velocity, axis=1) > 1e-9
    np.testing.assert_allclose(
        state.velocity[moving] / np.linalg.norm(state.velocity[moving], axis=1)[:, None],
        np.tile(direction, (moving.sum(), 1)),
        atol=EXACT,
    )


@FEW
@given(
    start=hnp.arrays(np.float64, (3,), elements=st.floats(-5.0, 5.0)),
    end=hnp.arrays(np.float64, (3,), elements=st.floats(-5.0, 5.0)),
    vmax=support.limits_positive,
    amax=support.limits_positive,
)
def test_property_trapezoid_on_a_line_reaches_its_limits(start, end, vmax, amax):
    length = float(np.linalg.norm(end - start))
    if length < 1e-3:
        return
    motion = timed(Line(start, end), "trapezoid", vmax=vmax, amax=amax)
    state = dense_state(motion)
    assert peak(state.velocity) == pytest.approx(min(vmax, np.sqrt(length * amax)), rel=LIMIT_RTOL)
    assert peak(state.acceleration) == pytest.approx(amax, rel=LIMIT_RTOL)


@pytest.mark.parametrize("profile", ["cubic", "quintic", "septic"])
def test_polynomial_laws_on_a_line_reach_the_binding_limit(profile):
    line = Line(*SEED_LINE)
    motion = timed(line, profile, vmax=2.0, amax=1.5)
    state = dense_state(motion)
    ratios = peak(state.velocity) / 2.0, peak(state.acceleration) / 1.5
    assert max(ratios) == pytest.approx(1.0, rel=LIMIT_RTOL)


def test_linear_law_on_a_line_runs_at_vmax():
    motion = timed(Line(*SEED_LINE), "linear", vmax=2.0)
    speed = np.linalg.norm(motion.state(np.linspace(0, motion.duration, 101)).velocity, axis=1)
    np.testing.assert_allclose(speed, 2.0, rtol=LIMIT_RTOL)
    assert motion.duration == pytest.approx(13.0, rel=CLOSED_FORM)


def test_scurve_on_a_line_keeps_speed_acceleration_and_jerk():
    line = Line(*SEED_LINE)
    vmax, amax, jmax = 2.0, 1.5, 4.0
    motion = timed(line, "scurve", vmax=vmax, amax=amax, jmax=jmax)
    state = dense_state(motion)
    assert peak(state.velocity) == pytest.approx(vmax, rel=LIMIT_RTOL)  # 26 m is long enough
    assert peak(state.acceleration) == pytest.approx(amax, rel=LIMIT_RTOL)
    law = motion.segments[0].law
    assert np.abs(law.extrema(3).peak).max() * line.speed_bound <= jmax * (1 + LIMIT_RTOL)


@pytest.mark.parametrize("name", ["arc", "ellipse", "eight"])
@pytest.mark.parametrize("profile", REST_PROFILES)
def test_limits_are_never_exceeded_on_curved_paths(name, profile):
    vmax, amax = 0.7, 1.3
    motion = timed(curved_paths()[name], profile, vmax=vmax, amax=amax)
    state = dense_state(motion)
    assert peak(state.velocity) <= vmax * (1 + LIMIT_RTOL)
    assert peak(state.acceleration) <= amax * (1 + LIMIT_RTOL)


@pytest.mark.parametrize("name", ["arc", "eight"])
@pytest.mark.parametrize("limits", [{"vmax": 0.5}, {"amax": 0.8}])
def test_a_single_limit_on_a_curved_path_is_kept(name, limits):
    motion = timed(curved_paths()[name], "quintic", **limits)
    state = dense_state(motion)
    if "vmax" in limits:
        assert peak(state.velocity) <= limits["vmax"] * (1 + LIMIT_RTOL)
    else:
        assert peak(state.acceleration) <= limits["amax"] * (1 + LIMIT_RTOL)


@FEW
@given(
    radius=st.floats(0.05, 3.0),
    angle=st.one_of(st.floats(-7.0, -0.05), st.floats(0.05, 7.0)),
    vmax=support.limits_positive,
    amax=support.limits_positive,
    profile=st.sampled_from(REST_PROFILES),
)
def test_property_arc_limits_are_never_exceeded(radius, angle, vmax, amax, profile):
    arc = Arc([0.1, -0.2, 0.3], [0.1 + radius, -0.2, 0.3], angle, normal=[0.0, 0.6, 0.8])
    motion = timed(arc, profile, vmax=vmax, amax=amax)
    state = dense_state(motion)
    assert peak(state.velocity) <= vmax * (1 + LIMIT_RTOL)
    assert peak(state.acceleration) <= amax * (1 + LIMIT_RTOL)


# --------------------------------------------------------------------------- seed 003
def test_seed003_cubic_line_closed_form():
    (x0, x1), duration = (np.array(SEED_LINE[0]), np.array(SEED_LINE[1])), 10.0
    motion = timed(Line(x0, x1), "cubic", duration=duration)
    assert motion.duration == duration and not motion.has_orientation
    t = np.linspace(0.0, duration, 1001)
    s = t / duration
    delta = x1 - x0
    state = motion.state(t)
    np.testing.assert_allclose(
        state.position, x0 + (3 * s**2 - 2 * s**3)[:, None] * delta, rtol=0, atol=SEED003
    )
    np.testing.assert_allclose(
        state.velocity, (6 * s - 6 * s**2)[:, None] * delta / duration, rtol=0, atol=SEED003
    )
    np.testing.assert_allclose(
        state.acceleration, (6 - 12 * s)[:, None] * delta / duration**2, rtol=0, atol=SEED003
    )
    np.testing.assert_allclose(motion.state(5.0).position, [[5.0, 0.0, 20.0]], atol=SEED003)


# -------------------------------------------------------------- derivatives of motions
def motions():
    return {
        "line_cubic": timed(Line(*SEED_LINE), "cubic", duration=10.0),
        "arc_trapezoid": timed(curved_paths()["arc"], "trapezoid", vmax=0.7, amax=1.3),
        "ellipse_linear": timed(curved_paths()["ellipse"], "linear", duration=3.0),
        "eight_septic": timed(curved_paths()["eight"], "septic", duration=4.0),
        "polyline_quintic": timed(
            Polyline([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.5]]), "quintic", duration=2.0
        ),
        "through_points": through_poses(
            [[0.0, 0.0, 0.0], [1.0, 0.5, 0.0], [1.0, 0.5, 2.0]], "trapezoid", vmax=1.0, amax=2.0
        ),
    }


@pytest.mark.parametrize("name", list(motions()))
def test_velocity_and_acceleration_are_derivatives_of_the_motion(name):
    motion = motions()[name]
    t = interior_times(motion, 157)
    if name == "polyline_quintic":  # the direction jumps at the inner waypoint
        knot = motion.segments[0].path.knots[1]
        u = motion.segments[0].law.position(t)[:, 0]
        t = t[np.abs(u - knot) > 1e-3]
    now, plus, minus = (motion.state(t + d) for d in (0.0, FD_STEP, -FD_STEP))
    support.assert_state(
        now.velocity, (plus.position - minus.position) / (2 * FD_STEP), rtol=FINITE_DIFFERENCE
    )
    support.assert_state(
        now.acceleration, (plus.velocity - minus.velocity) / (2 * FD_STEP), rtol=FINITE_DIFFERENCE
    )


def test_motion_follows_its_path_through_the_law():
    motion = motions()["eight_septic"]
    segment = motion.segments[0]
    t = np.linspace(0.0, motion.duration, 201)
    u = segment.law.position(t)[:, 0]
    np.testing.assert_allclose(motion.state(t).position, segment.path.evaluate(u), atol=EXACT)
    assert repr(motion).startswith("TaskTrajectory(segments=1")


# --------------------------------------------------------------------------- SLERP
ROTATION_PAIRS = {
    "small": ([0.3, -0.2, 0.1], [-0.5, 1.0, 0.4]),
    "large": ([0.0, 0.0, 0.1], [0.0, 0.0, 3.0]),  # a turn of 2.9 rad
    "tilted": ([1.0, 1.0, 0.0], [-0.2, 0.4, 1.5]),
}


@pytest.mark.parametrize("pair", list(ROTATION_PAIRS))
@pytest.mark.parametrize("profile", ["quintic", "trapezoid"])
def test_slerp_orientation(pair, profile):
    start, end = (rotation(v) for v in ROTATION_PAIRS[pair])
    kwargs = {"duration": 4.0} if profile == "quintic" else {"vmax": 5.0, "amax": 4.0}
    motion = timed(Line(*SEED_LINE), profile, orientation=(start, end), **kwargs)
    assert motion.has_orientation
    duration = motion.duration
    ends = motion.state([0.0, duration])
    np.testing.assert_allclose(ends.rotation[0], start, atol=EXACT)
    np.testing.assert_allclose(ends.rotation[1], end, atol=EXACT)
    np.testing.assert_allclose(ends.angular_velocity, 0.0, atol=EXACT)
    t = interior_times(motion, 101)
    now, plus, minus = (motion.state(t + d) for d in (0.0, FD_STEP, -FD_STEP))
    # Proper rotations all along.
    gram = now.rotation @ np.swapaxes(now.rotation, 1, 2)
    np.testing.assert_allclose(gram, np.broadcast_to(np.eye(3), gram.shape), atol=EXACT)
    np.testing.assert_allclose(np.linalg.det(now.rotation), 1.0, atol=EXACT)
    # Angular velocity (world frame) and acceleration are the derivatives.
    numeric = rotation_error(plus.rotation, minus.rotation) / (2 * FD_STEP)
    support.assert_state(now.angular_velocity, numeric, rtol=FINITE_DIFFERENCE)
    numeric = (plus.angular_velocity - minus.angular_velocity) / (2 * FD_STEP)
    support.assert_state(now.angular_acceleration, numeric, rtol=FINITE_DIFFERENCE)
    # One fixed axis: the shortest rotation from start to end.
    total = rotation_error(end, start)
    axis = total / np.linalg.norm(total)
    moving = np.linalg.norm(now.angular_velocity, axis=1) > 1e-9
    directions = (
        now.angular_velocity[moving]
        / np.linalg.norm(now.angular_velocity[moving], axis=1)[:, np.newaxis]
    )
    np.testing.assert_allclose(directions, np.tile(axis, (moving.sum(), 1)), atol=EXACT)
    # The angle turned so far is the total angle times u(t).
    u = motion.segments[0].law.position(t)[:, 0]
    turned = rotation_error(now.rotation, np.broadcast_to(start, now.rotation.shape))
    np.testing.assert_allclose(turned, np.outer(u, total), atol=EXACT)
    # Poses put the rotation and position together.
    poses = now.poses()
    np.testing.assert_array_equal(poses[:, :3, :3], now.rotation)
    np.testing.assert_array_equal(poses[:, :3, 3], now.position)
    np.testing.assert_array_equal(poses[:, 3], np.tile([0.0, 0.0, 0.0, 1.0], (t.size, 1)))


def test_fixed_orientation_holds():
    fixed = rotation([0.2, -0.4, 0.9])
    motion = timed(curved_paths()["arc"], "quintic", duration=2.0, orientation=fixed)
    state = motion.state(np.linspace(0.0, 2.0, 51))
    np.testing.assert_allclose(state.rotation, np.broadcast_to(fixed, (51, 3, 3)), atol=EXACT)
    np.testing.assert_array_equal(state.angular_velocity, 0.0)
    np.testing.assert_array_equal(state.angular_acceleration, 0.0)


def test_position_only_motion_has_no_orientation_fields():
    state = motions()["line_cubic"].state([0.0, 1.0])
    assert state.rotation is None and state.angular_velocity is None
    assert state.angular_acceleration is None
    poses = state.poses()
    np.testing.assert_array_equal(poses[:, :3, :3], np.broadcast_to(np.eye(3), (2, 3, 3)))


# ---------------------------------------------------------------------- through_poses
POINTS = np.array([[0.0, 0.0, 0.0], [1.0, 0.5, 0.0], [1.0, 0.5, 2.0], [-1.0, 0.5, 2.0]])


@pytest.mark.parametrize("profile", REST_PROFILES)
def test_through_points_with_durations_rests_at_every_point(profile):
    if profile == "trapezoid":  # a trapezoid law needs its limits even with a duration
        motion = through_poses(POINTS, profile, durations=[3.0, 4.0, 5.0], vmax=2.0, amax=2.0)
    else:
        motion = through_poses(POINTS, profile, durations=[3.0, 4.0, 5.0])
    assert not motion.has_orientation and len(motion.segments) == 3
    np.testing.assert_allclose(motion.breakpoints, [0.0, 3.0, 7.0, 12.0], rtol=CLOSED_FORM)
    rest = motion.state(motion.breakpoints)
    np.testing.assert_allclose(rest.position, POINTS, atol=EXACT)
    np.testing.assert_allclose(rest.velocity, 0.0, atol=EXACT)
    if profile in ("quintic", "septic"):
        np.testing.assert_allclose(rest.acceleration, 0.0, atol=EXACT)
    # Straight between the points: every sample of segment k is on its line.
    for k, start in enumerate(motion.breakpoints[:-1]):
        t = np.linspace(start, motion.breakpoints[k + 1], 41)
        position = motion.state(t).position
        chord = POINTS[k + 1] - POINTS[k]
        offset = position - POINTS[k]
        np.testing.assert_allclose(np.cross(offset, chord), 0.0, atol=EXACT)


def test_through_points_with_limits_is_time_optimal_per_segment():
    vmax, amax = 0.8, 1.1
    motion = through_poses(POINTS, "trapezoid", vmax=vmax, amax=amax)
    lengths = np.linalg.norm(np.diff(POINTS, axis=0), axis=1)
    for k, length in enumerate(lengths):
        expected = (
            length / vmax + vmax / amax if length >= vmax**2 / amax else 2 * np.sqrt(length / amax)
        )
        assert motion.segments[k].law.duration == pytest.approx(expected, rel=CLOSED_FORM)
    state = dense_state(motion)
    assert peak(state.velocity) == pytest.approx(vmax, rel=LIMIT_RTOL)
    assert peak(state.acceleration) == pytest.approx(amax, rel=LIMIT_RTOL)
    np.testing.assert_allclose(motion.state(motion.breakpoints).velocity, 0.0, atol=EXACT)


POSES = np.stack(
    [
        pose([0.0, 0.0, 0.0], [0.0, 0.0, 0.0]),
        pose([0.0, 0.0, 0.8], [0.3, 0.0, 0.1]),  # turn 0.8 rad while moving 0.32 m
        pose([0.0, 0.0, 0.8], [0.3, 0.4, 0.1]),  # move only
        pose([0.5, -0.3, 0.8], [0.3, 0.4, 0.1]),  # turn only
    ]
)


def test_through_poses_with_durations_rests_and_passes_every_pose():
    motion = through_poses(POSES, "quintic", durations=[2.0, 1.0, 1.5])
    assert motion.has_orientation
    rest = motion.state(motion.breakpoints)
    np.testing.assert_allclose(rest.poses(), POSES, atol=EXACT)
    np.testing.assert_allclose(rest.velocity, 0.0, atol=EXACT)
    np.testing.assert_allclose(rest.angular_velocity, 0.0, atol=EXACT)
    # Pure moves and pure turns: the other part holds still.
    state = motion.state(np.linspace(3.0, 4.5, 51))  # the turn-only segment
    np.testing.assert_allclose(state.position, np.tile(POSES[3, :3, 3], (51, 1)), atol=EXACT)
    np.testing.assert_allclose(state.velocity, 0.0, atol=EXACT)
    state = motion.state(np.linspace(2.0, 3.0, 51))  # the move-only segment
    np.testing.assert_allclose(
        state.rotation, np.broadcast_to(POSES[2, :3, :3], (51, 3, 3)), atol=EXACT
    )
    np.testing.assert_allclose(state.angular_velocity, 0.0, atol=EXACT)


def test_through_poses_honors_linear_and_angular_limits():
    vmax, amax, wmax, alpha_max = 0.2, 0.5, 0.3, 1.0
    motion = through_poses(POSES, "trapezoid", vmax=vmax, amax=amax, wmax=wmax, alpha_max=alpha_max)
    state = dense_state(motion)
    assert peak(state.velocity) <= vmax * (1 + LIMIT_RTOL)
    assert peak(state.acceleration) <= amax * (1 + LIMIT_RTOL)
    assert peak(state.angular_velocity) <= wmax * (1 + LIMIT_RTOL)
    assert peak(state.angular_acceleration) <= alpha_max * (1 + LIMIT_RTOL)
    # In each segment one of the two acceleration limits is reached (time-optimal law).
    index = np.clip(np.searchsorted(motion.breakpoints, state.t, side="right") - 1, 0, 2)
    for k in range(3):
        mine = index == k
        ratio = max(
            peak(state.acceleration[mine]) / amax,
            peak(state.angular_acceleration[mine]) / alpha_max,
        )
        assert ratio == pytest.approx(1.0, rel=LIMIT_RTOL)
    np.testing.assert_allclose(motion.state(motion.breakpoints).poses(), POSES, atol=EXACT)
    # The first segment turns 0.8 rad against moving 0.316 m: the turn sets its time.
    assert motion.breakpoints[1] == pytest.approx(0.8 / wmax + wmax / alpha_max, rel=CLOSED_FORM)


def test_a_turn_in_place_is_timed_by_the_angular_limits():
    poses = np.stack(
        [pose([0.0, 0.0, 0.0], [1.0, 2.0, 3.0]), pose([0.0, 1.2, 0.0], [1.0, 2.0, 3.0])]
    )
    motion = through_poses(poses, "trapezoid", wmax=0.5, alpha_max=2.0)
    assert motion.duration == pytest.approx(1.2 / 0.5 + 0.5 / 2.0, rel=CLOSED_FORM)
    state = dense_state(motion)
    assert peak(state.angular_velocity) == pytest.approx(0.5, rel=LIMIT_RTOL)
    np.testing.assert_allclose(state.velocity, 0.0, atol=EXACT)


# --------------------------------------------------------------------------- clamping
@pytest.mark.parametrize("name", ["line_cubic", "through_points"])
def test_times_outside_the_motion_are_clamped(name):
    motion = motions()[name]
    outside = motion.state([-5.0, -1e-9, motion.duration + 1e-9, motion.duration + 100.0])
    ends = motion.state([0.0, motion.duration])
    for field in ("position", "velocity", "acceleration"):
        values = getattr(outside, field)
        np.testing.assert_array_equal(values[:2], np.repeat(getattr(ends, field)[:1], 2, axis=0))
        np.testing.assert_array_equal(values[2:], np.repeat(getattr(ends, field)[1:], 2, axis=0))
    np.testing.assert_allclose(outside.velocity, 0.0, atol=EXACT)
    np.testing.assert_array_equal(
        outside.t, [-5.0, -1e-9, motion.duration + 1e-9, motion.duration + 100.0]
    )


def test_clamping_holds_the_end_orientation():
    start, end = rotation([0.1, 0.2, 0.3]), rotation([0.0, -0.5, 1.0])
    motion = timed(Line([0, 0, 0], [1, 0, 0]), "quintic", duration=2.0, orientation=(start, end))
    state = motion.state([-1.0, 3.0])
    np.testing.assert_allclose(state.rotation[0], start, atol=EXACT)
    np.testing.assert_allclose(state.rotation[1], end, atol=EXACT)
    np.testing.assert_allclose(state.angular_velocity, 0.0, atol=EXACT)


def test_segments_join_at_their_breakpoints():
    motion = through_poses(POINTS, "cubic", durations=[1.0, 2.0, 3.0])
    assert motion.duration == pytest.approx(6.0, rel=CLOSED_FORM)
    np.testing.assert_allclose(motion.breakpoints, [0.0, 1.0, 3.0, 6.0], rtol=CLOSED_FORM)
    # Just before and just after each inner pose the tool is at that pose.
    inner = motion.breakpoints[1:-1]
    before, after = motion.state(inner - 1e-12), motion.state(inner + 1e-12)
    np.testing.assert_allclose(before.position, POINTS[1:-1], atol=1e-9)
    np.testing.assert_allclose(after.position, POINTS[1:-1], atol=1e-9)


# -------------------------------------------------------------------------- bad input
LINE = Line([0.0, 0.0, 0.0], [1.0, 0.0, 0.0])
ARC = Arc([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], np.pi)
LAW = path_law("cubic", duration=1.0)


SCALED_ROTATION = np.block([[np.full((3, 3), 2.0), np.ones((3, 1))], [np.ones((1, 4))]])


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: path_law("bang", duration=1.0), "profile must be one of"),
        (lambda: path_law("cubic"), "give a duration or Cartesian limits"),
        (lambda: path_law("cubic", duration=0.0), "duration must be > 0"),
        (lambda: path_law("cubic", duration=np.nan), "duration must be finite"),
        (lambda: path_law("cubic", vmax=-1.0), "vmax must be > 0"),
        (lambda: path_law("cubic", amax=np.inf), "amax must be finite"),
        (lambda: path_law("cubic", duration=1.0, speed_bound=0.0), "zero length"),
        (lambda: path_law("scurve", vmax=1, amax=1, jmax=1, curvature_bound=1), "straight paths"),
        (lambda: path_law("trapezoid", vmax=1.0), "needs vmax and amax"),
        (lambda: path_law("trapezoid", duration=2.0), "needs vmax and amax"),
        (lambda: path_law("scurve", vmax=1.0, amax=1.0), "needs vmax, amax and jmax"),
        (lambda: path_law("linear", vmax=1.0, amax=1.0), "linear law needs a duration or vmax"),
        (lambda: path_law("linear", amax=1.0), "linear law needs a duration or vmax"),
        (lambda: path_law(tk.cubic(0.0, 2.0, 1.0)), "from u=0 to u=1, got 0 to 2"),
        (lambda: path_law(tk.cubic(0.5, 1.0, 1.0)), "from u=0 to u=1"),
        (lambda: path_law(tk.cubic([0.0, 0.0], [1.0, 1.0], 1.0)), "1-joint"),
        (lambda: timed(LINE, "bang", duration=1.0), "profile must be one of"),
        (lambda: timed(LINE, "cubic"), "give a duration or Cartesian limits"),
        (lambda: timed(ARC, "scurve", vmax=1, amax=1, jmax=1), "straight paths only"),
        (lambda: timed(ARC, "cubic", duration=1.0, jmax=1.0), "straight paths only"),
        (lambda: timed(Line([1, 1, 1], [1, 1, 1]), "cubic", duration=1.0), "zero length"),
        (lambda: timed("line", "cubic", duration=1.0), "path must be a trajkit.taskspace Path"),
        (lambda: timed(LINE, tk.cubic(1.0, 0.0, 1.0)), "from u=0 to u=1"),
        (
            lambda: timed(LINE, "cubic", duration=1.0, orientation=np.ones((3, 3))),
            "orientation is not a rotation matrix",
        ),
        (
            lambda: timed(LINE, "cubic", duration=1.0, orientation=np.diag([1.0, 1.0, -1.0])),
            "orientation is not a rotation matrix",
        ),
        (
            lambda: timed(LINE, "cubic", duration=1.0, orientation=(np.eye(3), 2 * np.eye(3))),
            "orientation end is not a rotation matrix",
        ),
        (
            lambda: timed(LINE, "cubic", duration=1.0, orientation=(np.eye(3),)),
            "a 3x3 rotation or a \\(start, end\\) pair",
        ),
        (
            lambda: timed(LINE, "cubic", duration=1.0, orientation=np.eye(4)),
            "orientation must be 3x3 rotation matrices",
        ),
        (
            lambda: timed(LINE, "cubic", duration=1.0, orientation=np.full((3, 3), np.nan)),
            "orientation must be finite",
        ),
        (lambda: through_poses([[0, 0, 0]], durations=[]), "at least 2 poses"),
        (lambda: through_poses(POINTS, "linear", durations=[1, 1, 1]), "profile must be 'cubic'"),
        (lambda: through_poses(POINTS, "scurve", vmax=1.0), "profile must be 'cubic'"),
        (lambda: through_poses(POINTS, durations=[1.0, 2.0]), "durations must be 3 positive"),
        (lambda: through_poses(POINTS, durations=[1.0, 0.0, 2.0]), "durations must be 3 positive"),
        (lambda: through_poses(POINTS, durations=[[1.0, 1.0, 1.0]]), "durations must be 3"),
        (lambda: through_poses(POINTS, durations=[1.0, np.nan, 1.0]), "durations must be finite"),
        (lambda: through_poses(POINTS), "give durations or limits"),
        (lambda: through_poses(POINTS, vmax=-1.0), "vmax must be > 0"),
        (lambda: through_poses(POSES, wmax=0.0), "wmax must be > 0"),
        (lambda: through_poses(POSES, vmax=1.0, alpha_max=-2.0), "alpha_max must be > 0"),
        (lambda: through_poses([[0, 0, 0], [0, 0, 0]], durations=[1]), "poses 0 and 1 coincide"),
        (lambda: through_poses(np.stack([POSES[0]] * 2), durations=[1]), "poses 0 and 1 coincide"),
        (lambda: through_poses(np.zeros((2, 2)), durations=[1]), "poses must have shape"),
        (lambda: through_poses(np.zeros((2, 3, 3)), durations=[1]), "poses must have shape"),
        (lambda: through_poses([[0, 0, np.nan], [1, 0, 0]], durations=[1]), "poses must be finite"),
        (
            lambda: through_poses(np.stack([POSES[0], SCALED_ROTATION * POSES[1]]), durations=[1]),
            "poses rotation is not a rotation matrix",
        ),
        (
            lambda: through_poses(np.stack([POSES[0], 2 * POSES[1]]), durations=[1]),
            "poses must have the last row 0 0 0 1",
        ),
        (lambda: TaskTrajectory([]), "at least one segment"),
        (
            lambda: TaskTrajectory(
                [TaskSegment(LINE, LAW), TaskSegment(Line([2, 0, 0], [3, 0, 0]), LAW)]
            ),
            "segment 2 starts 1 away from where segment 1 ends",
        ),
        (
            lambda: TaskTrajectory(
                [
                    TaskSegment(LINE, LAW, np.eye(3), np.array([1.0, 0.0, 0.0]), 0.0),
                    TaskSegment(Line([1, 0, 0], [2, 0, 0]), LAW),
                ]
            ),
            "either every segment has an orientation or none has",
        ),
        (lambda: motions()["line_cubic"].state([0.0, np.nan]), "t must be finite"),
    ],
)
def test_bad_input_raises_invalid_input_error(call, message):
    with pytest.raises(InvalidInputError, match=message) as excinfo:
        call()
    assert type(excinfo.value) is InvalidInputError


@pytest.mark.parametrize(
    "call",
    [
        lambda: path_law("cubic", duration=0.1, vmax=1.0),
        lambda: path_law("trapezoid", duration=0.1, vmax=1.0, amax=1.0),
        lambda: timed(Line(*SEED_LINE), "scurve", duration=1.0, vmax=1, amax=1, jmax=1),
    ],
)
def test_a_duration_below_the_limits_minimum_is_infeasible(call):
    with pytest.raises(InfeasibleError, match="below the minimum") as excinfo:
        call()
    assert type(excinfo.value) is InfeasibleError


# ---------------------------------------------------------------------- known bugs
def test_orientation_pair_given_as_a_list_is_a_pair_or_refused():
    start, end = np.eye(3), rotation([0.0, 0.0, 0.5])
    try:
        motion = timed(LINE, "cubic", duration=1.0, orientation=[start, end])
    except InvalidInputError:
        return  # refusing it is fine
    state = motion.state([0.0, 0.5, 1.0])
    np.testing.assert_allclose(state.rotation[0], start, atol=EXACT)
    np.testing.assert_allclose(state.rotation[-1], end, atol=EXACT)


def test_task_trajectory_refuses_a_segment_law_not_from_0_to_1():
    with pytest.raises(InvalidInputError, match="from u=0 to u=1"):
        TaskTrajectory([TaskSegment(LINE, tk.cubic(0.0, 2.0, 1.0))])


def test_task_trajectory_refuses_an_orientation_jump_between_segments():
    turned = rotation([0.0, 0.0, 1.0])
    first = TaskSegment(LINE, LAW, np.eye(3), np.array([1.0, 0.0, 0.0]), 0.0)
    second = TaskSegment(Line([1, 0, 0], [2, 0, 0]), LAW, turned, np.array([1.0, 0.0, 0.0]), 0.0)
    with pytest.raises(InvalidInputError):
        TaskTrajectory([first, second])
