"""Tests of trajkit.blended: linear segments through waypoints joined by blends.

Independent facts used: between blends each joint moves on the straight line through
consecutive waypoints (interior segment velocity dq / T); a parabolic blend of duration
|dv| / amax centred on a waypoint passes it at distance dv |dv| / (8 amax); jerk-limited
blends keep |jerk| <= jmax and a continuous acceleration.
"""

from __future__ import annotations

import re
import warnings

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import support
import trajkit as tk
from support import CLOSED_FORM, ROUNDING

THROUGH = CLOSED_FORM  # relative to max(1, |waypoint|): through=True hits every waypoint
DEVIATION = ROUNDING  # absolute: info["via_deviation"] is position(times) - waypoints
SEGMENT = ROUNDING  # relative: interior segment velocity is dq / T

WAYPOINTS = np.array([[0.0, 0.0], [1.0, 2.0], [3.0, 1.0], [2.0, -1.0]])
VMAX, AMAX, JMAX = np.array([1.0, 2.0]), np.array([2.0, 3.0]), np.array([10.0, 10.0])


def limits(vmax, amax, jmax=None):
    return tk.Limits(velocity=vmax, acceleration=amax, jerk=jmax)


def pieces(tr):
    """``tr`` without its exact boundary states: what its polynomial pieces give."""
    return tk.Trajectory(tr.breakpoints, tr.coefficients)


def assert_starts_and_ends_at_rest(tr, waypoints):
    for plan in (tr, pieces(tr)):
        support.assert_state(plan.position(0.0), waypoints[0])
        support.assert_state(plan.position(plan.duration), waypoints[-1])
        for t in (0.0, plan.duration):
            support.assert_state(plan.velocity(t), np.zeros(waypoints.shape[1]))
    # The end is held: standing still afterwards.
    support.assert_state(tr.position(tr.duration + 1.0), waypoints[-1])


def assert_deviation_is_reported(tr, waypoints):
    times = np.array(tr.info["times"])
    measured = tr.position(times) - waypoints
    assert np.max(np.abs(tr.info["via_deviation"] - measured)) <= DEVIATION
    assert tr.info["via_distance"] == pytest.approx(np.linalg.norm(measured, axis=1), abs=1e-12)


def assert_schedule(tr, n):
    durations = np.array(tr.info["durations"])
    times = np.array(tr.info["times"])
    assert durations.shape == (n - 1,) and np.all(durations > 0)
    assert times[0] == 0.0
    assert times == pytest.approx(np.concatenate([[0.0], np.cumsum(durations)]), rel=ROUNDING)
    assert tr.duration == pytest.approx(times[-1], rel=ROUNDING)


# ----------------------------------------------------------------------------- examples
def test_parabolic_blends_closed_forms():
    tr = tk.blended(WAYPOINTS, VMAX, AMAX)
    assert tr.info["planner"] == "blended"
    assert tr.info["jerk_limited"] is False
    assert tr.info["through"] is False
    assert tr.info["pseudo_waypoints"] is None
    assert_schedule(tr, 4)
    assert_starts_and_ends_at_rest(tr, WAYPOINTS)
    assert_deviation_is_reported(tr, WAYPOINTS)
    assert tr.check(limits(VMAX, AMAX)).ok
    support.assert_continuous(tr, 1)
    durations = np.array(tr.info["durations"])
    v = tr.info["segment_velocities"]
    # The interior segment moves on the line through its waypoints.
    expected = (WAYPOINTS[2] - WAYPOINTS[1]) / durations[1]
    assert v[1] == pytest.approx(expected, rel=SEGMENT)
    # End segments start/stop inside: |dq| = |v| (T - tb / 2), tb = |v| / amax.
    for row, (a, b) in ((0, (0, 1)), (2, (2, 3))):
        covered = np.abs(v[row]) * (durations[row] - np.abs(v[row]) / AMAX / 2)
        assert covered == pytest.approx(np.abs(WAYPOINTS[b] - WAYPOINTS[a]), rel=CLOSED_FORM)
    # Parabolic blends: |dv| / amax long, passing each via point at dv |dv| / (8 amax).
    padded = np.vstack([np.zeros(2), v, np.zeros(2)])
    dv = np.diff(padded, axis=0)
    assert tr.info["blend_times"] == pytest.approx(np.abs(dv) / AMAX, rel=CLOSED_FORM)
    corner = dv[1:-1] * np.abs(dv[1:-1]) / (8 * AMAX)
    assert tr.info["via_deviation"][1:-1] == pytest.approx(corner, rel=CLOSED_FORM, abs=1e-12)
    assert np.all(tr.info["via_distance"][1:-1] > 0.01)  # passes near, not through
    # The velocity limit binds somewhere: joint 1 runs at 1 rad/s in segment 1.
    assert tr.extrema(1).peak[0] == pytest.approx(1.0, rel=CLOSED_FORM)


def test_jerk_limited_blends():
    tr = tk.blended(WAYPOINTS, VMAX, AMAX, jmax=JMAX)
    assert tr.info["jerk_limited"] is True
    assert_schedule(tr, 4)
    assert_starts_and_ends_at_rest(tr, WAYPOINTS)
    assert_deviation_is_reported(tr, WAYPOINTS)
    assert tr.check(limits(VMAX, AMAX, JMAX)).ok
    support.assert_continuous(tr, 2)  # position, velocity and acceleration
    support.assert_state(tr.acceleration(np.array([0.0, tr.duration])), np.zeros((2, 2)))
    assert tr.extrema(3).peak == pytest.approx(JMAX, rel=CLOSED_FORM)


def test_jerk_limited_blends_last_longer_for_the_same_durations():
    durations = [3.0, 3.0, 3.0]
    parabolic = tk.blended(WAYPOINTS, VMAX, AMAX, durations=durations)
    smooth = tk.blended(WAYPOINTS, VMAX, AMAX, jmax=JMAX, durations=durations)
    # Same interior velocities (dq / T); a jerk-limited change of |dv| takes longer.
    interior = slice(1, -1)
    assert smooth.info["segment_velocities"][interior] == pytest.approx(
        parabolic.info["segment_velocities"][interior], rel=SEGMENT
    )
    assert np.all(smooth.info["blend_times"][interior] >= parabolic.info["blend_times"][interior])
    # ... and cuts its corners by more.
    assert np.all(smooth.info["via_distance"][interior] >= parabolic.info["via_distance"][interior])


def test_through_passes_every_waypoint_exactly():
    for jmax in (None, JMAX):
        tr = tk.blended(WAYPOINTS, VMAX, AMAX, jmax=jmax, through=True)
        assert tr.info["through"] is True
        times = np.array(tr.info["times"])
        error = np.abs(tr.position(times) - WAYPOINTS) / np.maximum(1.0, np.abs(WAYPOINTS))
        assert np.max(error) <= THROUGH
        assert np.max(np.abs(tr.info["via_deviation"])) <= THROUGH * 3.0
        pseudo = tr.info["pseudo_waypoints"]
        # Pseudo via points are pushed outwards; the ends stay.
        assert np.array_equal(pseudo[[0, -1]], WAYPOINTS[[0, -1]])
        assert np.any(np.abs(pseudo[1:-1] - WAYPOINTS[1:-1]) > 0.01)
        assert tr.check(limits(VMAX, AMAX, jmax)).ok
        assert_starts_and_ends_at_rest(tr, WAYPOINTS)


def test_given_durations_are_honoured():
    durations = [2.5, 4.0, 3.0]
    for jmax in (None, JMAX):
        tr = tk.blended(WAYPOINTS, VMAX, AMAX, jmax=jmax, durations=durations)
        assert tr.info["durations"] == tuple(durations)
        assert tr.info["times"] == pytest.approx((0.0, 2.5, 6.5, 9.5), rel=ROUNDING)
        assert tr.duration == pytest.approx(9.5, rel=ROUNDING)
        assert tr.check(limits(VMAX, AMAX, jmax)).ok
        assert_starts_and_ends_at_rest(tr, WAYPOINTS)
        v = tr.info["segment_velocities"]
        assert v[1] == pytest.approx((WAYPOINTS[2] - WAYPOINTS[1]) / 4.0, rel=SEGMENT)


# What a segment needs alone: 2 rad at <= 1 rad/s inside; at the ends a start (stop)
# from rest onto the segment's line, 1 rad at 1 rad/s and 2 rad at 2 rad/s:
# parabolic 2/2 + (2/3)/2 = 1.33333 s, jerk-limited 2/2 + (2/3 + 3/10)/2 = 1.48333 s.
END_ALONE = ("1.33333", "1.48333")


@pytest.mark.parametrize(
    ("durations", "fragment", "alone"),
    [
        # The 0.001 s segment breaks the velocity limit; its huge blend at waypoint 1
        # eats segment 0's time first, which once got segment 0 blamed.
        ([5.0, 0.001, 5.0], "durations[1] = 0.001 s is too short for the limits", ("2", "2")),
        ([5.0, 1.0, 5.0], "durations[1] = 1 s is too short for the limits", ("2", "2")),
        ([0.5, 5.0, 5.0], "durations[0] = 0.5 s is too short for the limits", END_ALONE),
        ([5.0, 5.0, 0.2], "durations[2] = 0.2 s is too short for the limits", END_ALONE),
    ],
)  # fmt: skip
@pytest.mark.parametrize("jmax", [None, JMAX])
def test_too_short_durations_name_the_segment(durations, fragment, alone, jmax):
    with pytest.raises(tk.InfeasibleError) as info:
        tk.blended(WAYPOINTS, VMAX, AMAX, jmax=jmax, durations=durations)
    message = str(info.value)
    segment = fragment[len("durations[")]
    needed = alone[0] if jmax is None else alone[1]
    assert message == f"{fragment} (segment {segment} alone needs at least {needed} s)"


def test_overlapping_blends_name_the_segment_and_what_they_need():
    # Each segment alone fits (1 rad from rest needs sqrt(2) s at 1 rad/s^2), but the
    # start blend (1 s, to 1 rad/s) and half the turn at waypoint 1 (2 s / 2) need
    # 2 s of segment 0's 1.5 s.
    with pytest.raises(tk.InfeasibleError) as info:
        tk.blended([0.0, 1.0, 0.0], 10.0, 1.0, durations=[1.5, 1.5])
    assert str(info.value) == (
        "durations[0] = 1.5 s is too short for the limits: the blends at waypoints 0 and 1 "
        "need 2 s of it"
    )
    assert tk.blended([0.0, 1.0, 0.0], 10.0, 1.0, durations=[2.0, 2.0]).duration == 4.0


def test_a_single_joint_as_a_1d_array():
    tr = tk.blended([0.0, 1.0, 3.0, 2.0], 1.0, 2.0)
    assert tr.ndof == 1
    assert_starts_and_ends_at_rest(tr, np.array([[0.0], [1.0], [3.0], [2.0]]))
    assert tr.check(limits(1.0, 2.0)).ok


def test_a_repeated_waypoint_is_a_stop():
    w = np.array([[0.0], [1.0], [1.0], [2.0]])
    tr = tk.blended(w, 1.0, 1.0)
    assert_starts_and_ends_at_rest(tr, w)
    assert tr.check(limits(1.0, 1.0)).ok
    assert tr.info["segment_velocities"][1] == pytest.approx([0.0], abs=1e-12)


# Two waypoints: the start and the stop blend share the one segment. It once solved
# |dq| = |v| (T - tb / 2) as if each had a segment of its own and stopped short by
# |v| tb / 2 (16 % of the way here, up to 52 %), with check() saying OK.
@pytest.mark.parametrize(
    "kwargs",
    [{}, {"jmax": 10.0}, {"durations": [3.0]}, {"jmax": 10.0, "durations": [3.0]},
     {"through": True}, {"vmax": 0.5}, {"vmax": 0.5, "jmax": 10.0}],
)  # fmt: skip
def test_two_waypoints_reach_the_goal(kwargs):
    kwargs = {"vmax": 1.0, "amax": 1.0, **kwargs}
    tr = tk.blended([[0.0], [1.0]], **kwargs)
    assert tr.position(tr.duration)[0] == 1.0  # the exact end state
    assert tr.velocity(tr.duration)[0] == 0.0
    assert abs(pieces(tr).position(tr.duration)[0] - 1.0) <= 1e-15  # and the pieces'
    assert abs(pieces(tr).velocity(tr.duration)[0]) <= 1e-15
    assert tr.check(limits(kwargs["vmax"], 1.0, kwargs.get("jmax"))).ok
    if "durations" in kwargs:
        assert tr.duration == 3.0
    else:
        # Unhurried, a two-waypoint move is the time-optimal rest-to-rest move: the
        # trapezoid's (triangle's) or the S-curve's duration, an independent planner.
        jmax = kwargs.get("jmax")
        if jmax is None:
            fastest = tk.trapezoidal(0.0, 1.0, kwargs["vmax"], 1.0)
        else:
            fastest = tk.scurve(0.0, 1.0, kwargs["vmax"], 1.0, jmax)
        assert tr.duration == pytest.approx(fastest.duration, rel=CLOSED_FORM)


def test_two_waypoints_on_several_joints_share_the_duration():
    w = np.array([[0.0, 1.0, -2.0], [3.0, 1.0, -2.5]])
    tr = tk.blended(w, [1.0, 1.0, 0.1], [2.0, 1.0, 0.5], jmax=[5.0, 5.0, 5.0])
    assert np.max(np.abs(pieces(tr).position(tr.duration) - w[1])) <= 4e-16 * 3.0
    assert tr.check(limits([1.0, 1.0, 0.1], [2.0, 1.0, 0.5], [5.0, 5.0, 5.0])).ok
    slowest = max(
        tk.scurve(0.0, 3.0, 1.0, 2.0, 5.0).duration, tk.scurve(0.0, 0.5, 0.1, 0.5, 5.0).duration
    )
    assert tr.duration == pytest.approx(slowest, rel=CLOSED_FORM)


# through=True without durations once re-planned the shortest schedule for every new
# set of pseudo via points: longer segments, smaller corners, shorter segments, ... it
# oscillated and gave up, although longer durations work.
def test_through_without_durations_converges():
    w = np.array([[2.57728845, -0.02577305], [0.2931216, 2.85785701], [-0.85344151, 2.34483572]])
    vmax, amax = [2.64414797, 7.31340077], [0.16977169, 2.87098044]
    automatic = np.array(tk.blended(w, vmax, amax).info["durations"])
    feasible = tk.blended(w, vmax, amax, through=True, durations=1.2 * automatic)
    assert np.max(np.abs(feasible.info["via_deviation"])) <= THROUGH * 3.0  # so it exists
    tr = tk.blended(w, vmax, amax, through=True)
    times = np.array(tr.info["times"])
    assert np.max(np.abs(tr.position(times) - w)) <= 1e-12 * 3.0
    assert np.max(np.abs(tr.info["via_deviation"])) <= 1e-12 * 3.0
    assert tr.check(limits(vmax, amax)).ok
    assert_starts_and_ends_at_rest(tr, w)
    # Durations only grow from the plain schedule, which is never longer.
    assert np.all(np.array(tr.info["durations"]) >= automatic)


def test_a_subnormal_step_with_given_durations_is_planned() -> None:
    # 2 amax d underflowed to 0 for d = 5e-324 rad: the end segment's top speed was 0 and
    # its minimum duration inf, so 1e-9 s was refused as "needs at least inf s".
    tr = tk.blended([[5e-324], [0.0], [0.0]], vmax=1.0, amax=0.25, durations=[1e-9, 1e-9])
    assert tr.duration == 2e-9
    assert tr.position(0.0)[0] == 5e-324 and tr.position(tr.end_time)[0] == 0.0
    assert tr.check(tk.Limits(velocity=1.0, acceleration=0.25)).ok


# The schedule once started a still segment at 1e-9 s and grew an end segment by 1 %
# per pass: 200 passes (x7.3) could not reach the 2.8e-6 s of two 1e-12 rad steps.
@pytest.mark.parametrize("jmax", [None, 1.0])
@pytest.mark.parametrize("through", [False, True])
def test_tiny_waypoint_steps(jmax, through):
    w = np.array([[0.0], [1e-12], [2e-12]])
    tr = tk.blended(w, 1.0, 1.0, jmax=jmax, through=through)
    # Relative to the step, not to 1 rad: a 1e-12 rad move must end at 2e-12 rad.
    assert abs(pieces(tr).position(tr.duration)[0] - 2e-12) <= 1e-9 * 1e-12
    assert abs(pieces(tr).velocity(tr.duration)[0]) <= 1e-9 * 1e-12 / tr.duration
    assert tr.check(limits(1.0, 1.0, jmax)).ok
    if jmax is None and not through:
        # No corner at waypoint 1 (same speed on both sides): each end segment is
        # the fastest start from rest onto its line, 1e-12 = a T^2 / 2.
        assert tr.info["durations"] == pytest.approx([np.sqrt(2e-12)] * 2, rel=CLOSED_FORM)


# Numbers at the ends of float64: a plan that lands, or the documented error, and no
# numpy warning on the way. ([0, 1e308] at vmax 1e300, amax 1e12 once came back as a
# 1e288 s plan that never moved.)
@pytest.mark.parametrize("step", [1e-300, 1e-12, 1e300, 1e308])
@pytest.mark.parametrize("jmax", [None, 1e-300, 1e300])
@pytest.mark.parametrize("through", [False, True])
def test_extreme_numbers_plan_or_refuse(step, jmax, through):
    for vmax, amax in ((1e-300, 1e-300), (1e-300, 1e12), (1e300, 1e12), (1e300, 1e300)):
        for w in ([0.0, step], [0.0, step, -step], [-step, step, 0.0, step]):
            with warnings.catch_warnings():
                warnings.simplefilter("error")
                try:
                    tr = tk.blended(w, vmax, amax, jmax=jmax, through=through)
                except tk.InfeasibleError as error:
                    assert "give times or speeds float64 cannot hold" in str(error)
                    continue
                end = pieces(tr).position(tr.duration)[0]
            assert abs(end - w[-1]) <= 1e-9 * step
            assert np.isfinite(tr.duration) and tr.duration > 0.0


def test_short_blends_in_a_long_move_are_kept():
    # Joint 1 stops in 0.5 ns after 2000 s; merging short pieces once made it jump to
    # 5e-8 rad/s and end moving.
    w = np.array([[0.0, 0.0], [0.0, 1000.0], [5e-5, 2000.0]])
    tr = tk.blended(w, 1.0, 100.0)
    assert tr.info["blend_times"][2, 0] == pytest.approx(5e-10, rel=1e-4)  # 0.5 ns stop
    support.assert_continuous(tr, 1)
    assert tr.velocity(tr.duration)[0] == pytest.approx(0.0, abs=1e-12)


# ----------------------------------------------------------------------------- properties
@st.composite
def blend_problems(draw, min_points=3):
    n = draw(st.integers(min_points, 6))
    ndof = draw(st.integers(1, 3))
    waypoints = draw(hnp.arrays(np.float64, (n, ndof), elements=st.floats(-5.0, 5.0)))
    if draw(st.booleans()):  # a repeated waypoint (a stop) now and then
        i = draw(st.integers(1, n - 1))
        waypoints[i] = waypoints[i - 1]
    if draw(st.booleans()):  # a step far below a micro-radian, on some joints
        i = draw(st.integers(1, n - 1))
        tiny = draw(hnp.arrays(np.float64, (ndof,), elements=st.sampled_from([0.0, 1e-9, -1e-12])))
        waypoints[i] = np.where(tiny != 0.0, waypoints[i - 1] + tiny, waypoints[i])
    positive = st.floats(0.1, 10.0)
    vmax = draw(hnp.arrays(np.float64, (ndof,), elements=positive))
    amax = draw(hnp.arrays(np.float64, (ndof,), elements=positive))
    jmax = draw(st.none() | hnp.arrays(np.float64, (ndof,), elements=st.floats(0.1, 100.0)))
    return waypoints, vmax, amax, jmax


@given(problem=blend_problems())
def test_property_blended(problem):
    waypoints, vmax, amax, jmax = problem
    tr = tk.blended(waypoints, vmax, amax, jmax=jmax)
    assert_schedule(tr, len(waypoints))
    assert_starts_and_ends_at_rest(tr, waypoints)
    assert_deviation_is_reported(tr, waypoints)
    assert tr.check(limits(vmax, amax, jmax)).ok
    support.assert_continuous(tr, 1 if jmax is None else 2)
    # Interior segments move on the lines through their waypoints.
    durations = np.array(tr.info["durations"])
    dq = np.diff(waypoints, axis=0)[1:-1]
    v = tr.info["segment_velocities"][1:-1]
    assert v == pytest.approx(dq / durations[1:-1, np.newaxis], rel=SEGMENT, abs=1e-12)
    if jmax is None:
        padded = np.vstack([np.zeros(waypoints.shape[1]), tr.info["segment_velocities"]])
        padded = np.vstack([padded, np.zeros(waypoints.shape[1])])
        dv = np.diff(padded, axis=0)[1:-1]
        corner = dv * np.abs(dv) / (8 * amax)
        assert tr.info["via_deviation"][1:-1] == pytest.approx(corner, rel=CLOSED_FORM, abs=1e-9)


# Steps of every size: none, below a micro-radian (down to 1e-15 rad), and large.
STEPS = st.one_of(
    st.just(0.0),
    st.floats(1e-15, 1e-6),
    st.floats(-1e-6, -1e-15),
    st.floats(-5.0, 5.0, allow_subnormal=False),
)


@st.composite
def any_blend_problems(draw):
    n = draw(st.integers(2, 6))
    ndof = draw(st.integers(1, 3))
    # No subnormals: blended reads them as 0 (see trajkit._validation), not so this test.
    starts = st.just(0.0) | st.floats(-5.0, 5.0, allow_subnormal=False)
    start = draw(hnp.arrays(np.float64, (ndof,), elements=starts))
    steps = draw(hnp.arrays(np.float64, (n - 1, ndof), elements=STEPS))
    waypoints = start + np.concatenate([np.zeros((1, ndof)), np.cumsum(steps, axis=0)])
    positive = st.floats(0.1, 10.0)
    vmax = draw(hnp.arrays(np.float64, (ndof,), elements=positive))
    amax = draw(hnp.arrays(np.float64, (ndof,), elements=positive))
    jmax = draw(st.none() | hnp.arrays(np.float64, (ndof,), elements=st.floats(0.1, 100.0)))
    through = draw(st.booleans())
    stretch = draw(st.none() | st.floats(1.0, 3.0))  # given durations: the default ones x
    return waypoints, vmax, amax, jmax, through, stretch


@given(problem=any_blend_problems())
def test_property_any_waypoints_reach_every_target(problem):
    waypoints, vmax, amax, jmax, through, stretch = problem
    durations = None
    if stretch is not None:
        default = tk.blended(waypoints, vmax, amax, jmax=jmax, through=through)
        durations = stretch * np.array(default.info["durations"])
    tr = tk.blended(waypoints, vmax, amax, jmax=jmax, durations=durations, through=through)
    n = waypoints.shape[0]
    assert_schedule(tr, n)
    assert_starts_and_ends_at_rest(tr, waypoints)  # to 1e-9 of max(1, |waypoint|)
    # ... and to rounding, so that a tiny move cannot stop short unseen: 1e-12 of the
    # largest |waypoint| plus the peak velocity times the duration (every blend's
    # velocity change rounds to that, and a long segment carries it on).
    peak = tr.extrema(1).peak
    scale = np.max(np.abs(waypoints)) + np.max(peak) * tr.duration
    for t, waypoint in ((0.0, waypoints[0]), (tr.duration, waypoints[-1])):
        assert np.all(np.abs(tr.position(t) - waypoint) <= 1e-12 * scale)
    # The end velocity to that, plus the rounding of the switch times (ulp(T) amax).
    rounding = 1e-12 * scale / tr.duration + 16 * np.finfo(float).eps * tr.duration * amax
    assert np.all(np.abs(tr.velocity(tr.duration)) <= rounding)
    assert_deviation_is_reported(tr, waypoints)
    assert tr.check(limits(vmax, amax, jmax)).ok
    support.assert_continuous(tr, 1 if jmax is None else 2)
    if durations is not None:
        assert tr.info["durations"] == tuple(durations)
    if through:
        times = np.array(tr.info["times"])
        miss = np.abs(tr.position(times) - waypoints)
        assert np.all(miss <= 1e-9 * np.maximum(1.0, np.abs(waypoints)))
        assert np.all(miss <= 1e-10 * scale)  # what blended itself guarantees
    else:
        assert tr.info["pseudo_waypoints"] is None


@given(problem=blend_problems())
def test_property_jerk_limited_schedules_given_to_parabolic_blends(problem):
    # A jerk-limited schedule is usually one parabolic blends can keep (a parabolic
    # change of velocity is never slower than a jerk-limited one), but not always:
    # the parabolic end blends are shorter, so the end segments' velocities differ
    # and interior waypoints the jerk-limited plan cruised through need blends (see
    # the test below). Given such a schedule, the parabolic planner keeps it exactly
    # or refuses it by naming the segment; it never returns a plan that breaks it.
    waypoints, vmax, amax, jmax = problem
    if jmax is None:
        jmax = np.full(waypoints.shape[1], 10.0)
    smooth = tk.blended(waypoints, vmax, amax, jmax=jmax)
    durations = np.array(smooth.info["durations"])
    try:
        parabolic = tk.blended(waypoints, vmax, amax, durations=durations)
    except tk.InfeasibleError as error:
        assert re.fullmatch(r"durations\[\d+\] = \S+ s is too short for the limits.*", str(error))
        return
    assert parabolic.duration == pytest.approx(smooth.duration, rel=ROUNDING)
    assert parabolic.check(limits(vmax, amax)).ok
    assert_starts_and_ends_at_rest(parabolic, waypoints)


def test_a_jerk_limited_schedule_parabolic_blends_cannot_keep_is_refused_by_segment():
    # The jerk-limited plan cruises at vmax through waypoints 1 and 2 (its segment 1
    # lasts exactly 0.0625 m / 1 m/s); its 1.1 s start blend leaves segment 0 at
    # -1 m/s, where a parabolic 1 s start blend would leave it at -0.949 m/s, so the
    # parabolic plan must blend at waypoints 1 and 2, inside segment 1.
    waypoints = np.array([[1.0], [0.0625], [0.0], [-1.0]])
    smooth = tk.blended(waypoints, 1.0, 1.0, jmax=10.0)
    assert smooth.info["durations"] == pytest.approx((1.4875, 0.0625, 1.55), rel=CLOSED_FORM)
    assert smooth.check(tk.Limits(velocity=1.0, acceleration=1.0, jerk=10.0)).ok
    with pytest.raises(tk.InfeasibleError, match=r"durations\[1\] = 0.0625 s is too short.*"
                       r"blends at waypoints 1 and 2 need"):  # fmt: skip
        tk.blended(waypoints, 1.0, 1.0, durations=smooth.info["durations"])


@given(problem=blend_problems(), stretch=st.floats(1.0, 3.0))
def test_property_given_durations_are_honoured(problem, stretch):
    waypoints, vmax, amax, jmax = problem
    automatic = np.array(tk.blended(waypoints, vmax, amax, jmax=jmax).info["durations"])
    durations = automatic * stretch
    tr = tk.blended(waypoints, vmax, amax, jmax=jmax, durations=durations)
    assert np.array(tr.info["durations"]) == pytest.approx(durations, rel=ROUNDING)
    assert_schedule(tr, len(waypoints))
    assert_starts_and_ends_at_rest(tr, waypoints)
    assert tr.check(limits(vmax, amax, jmax)).ok


@given(problem=blend_problems())
def test_property_through_with_room_to_spare(problem):
    waypoints, vmax, amax, jmax = problem
    automatic = np.array(tk.blended(waypoints, vmax, amax, jmax=jmax).info["durations"])
    # A still segment gets 1e-9 s by default, yet its pseudo waypoints may have to move:
    # room to spare is twice the schedule plus its longest segment everywhere.
    durations = 2.0 * automatic + automatic.max()
    tr = tk.blended(waypoints, vmax, amax, jmax=jmax, durations=durations, through=True)
    times = np.array(tr.info["times"])
    error = np.abs(tr.position(times) - waypoints) / np.maximum(1.0, np.abs(waypoints))
    assert np.max(error) <= THROUGH
    assert_starts_and_ends_at_rest(tr, waypoints)
    assert tr.check(limits(vmax, amax, jmax)).ok
    support.assert_continuous(tr, 1 if jmax is None else 2)


# ---------------------------------------------------------------------------- bad input
INVALID = [
    ({"waypoints": [[0.0, 0.0]]}, "must have shape (n, ndof) with n >= 2, got shape (1, 2)"),
    ({"waypoints": np.zeros((2, 2, 2))}, "waypoints must have shape (n, ndof) with n >= 2"),
    ({"waypoints": [[0.0, np.nan], [1.0, 1.0]]}, "waypoints must be finite"),
    ({"waypoints": "abc"}, "waypoints must be numeric, got 'abc' (a string)"),
    ({"vmax": -1.0}, "vmax must be > 0 for every joint, got -1 rad/s for joint 1"),
    ({"vmax": [1.0, 2.0, 3.0]}, "vmax must be a number or 2 numbers (one per joint)"),
    ({"vmax": np.inf}, "vmax must be finite"),
    ({"amax": 0.0}, "amax must be > 0 for every joint"),
    ({"jmax": [1.0, -1.0]}, "jmax must be > 0 for every joint, got -1 rad/s^3 for joint 2"),
    ({"durations": [1.0]}, "durations must give one time per segment (2), got shape (1,)"),
    ({"durations": [[1.0, 1.0]]}, "durations must give one time per segment (2)"),
    ({"durations": [1.0, 0.0]}, "durations must all be > 0 s"),
    ({"durations": [1.0, -2.0]}, "durations must all be > 0 s"),
    ({"durations": [1.0, np.nan]}, "durations must be finite"),
]  # fmt: skip


@pytest.mark.parametrize(("change", "fragment"), INVALID)
def test_invalid_input(change, fragment):
    kwargs = {"waypoints": [[0.0, 0.0], [1.0, 1.0], [2.0, 0.0]], "vmax": 1.0, "amax": 1.0}
    with pytest.raises(tk.InvalidInputError) as info:
        tk.blended(**{**kwargs, **change})
    assert isinstance(info.value, ValueError)
    assert fragment in str(info.value)
