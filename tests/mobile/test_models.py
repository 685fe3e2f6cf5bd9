"""Tests of trajkit.mobile.models: angles, poses, the unicycle and diff-drive models,
the exact constant-twist arc, and the RK4 integrator.

Wheel speeds are checked against the textbook formulas and their inverse, arcs
against the closed-form circle and line, and RK4 against Taylor's polynomial,
Simpson's rule and the Fresnel integrals of a clothoid.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.special import fresnel

import support
from support import CLOSED_FORM, EPS, ROUNDING, WORLD_ROUNDING
from trajkit import InvalidInputError
from trajkit.mobile import (
    DiffDrive,
    MobileLimits,
    Unicycle,
    arc_pose,
    jackal,
    propagate,
    rk4_step,
    wrap_angle,
)
from trajkit.mobile.models import pose_array

# Tolerances ---------------------------------------------------------------------
ROUND_TRIP = 1e-12  # relative: wheel speeds <-> twist, both ways
COMPOSITION = 1e-12  # relative to the motion's size: arc after arc = one longer arc
CLOTHOID_RK4 = 1e-10  # m: RK4 at 1 ms against the Fresnel integrals (measured ~1e-13)
FEW = settings(max_examples=40, deadline=None)

speeds = st.one_of(st.just(0.0), st.floats(-10.0, 10.0))
turn_rates = st.one_of(st.just(0.0), st.floats(-10.0, 10.0))
nonzero_turn_rates = st.one_of(st.floats(1e-3, 10.0), st.floats(-10.0, -1e-3))
times = st.one_of(st.just(0.0), st.floats(0.0, 10.0))


# wrap_angle ---------------------------------------------------------------------
@pytest.mark.parametrize(
    ("angle", "wrapped"),
    [
        (0.0, 0.0),
        (np.pi, -np.pi),
        (-np.pi, -np.pi),
        (1.5 * np.pi, -0.5 * np.pi),
        (-1.5 * np.pi, 0.5 * np.pi),
        (2.0 * np.pi, 0.0),
        (7.0, 7.0 - 2.0 * np.pi),
        (-7.0, -7.0 + 2.0 * np.pi),
    ],
)
def test_wrap_angle_known_values(angle, wrapped):
    assert wrap_angle(angle) == pytest.approx(wrapped, rel=0.0, abs=4 * EPS)


def test_wrap_angle_keeps_shape():
    angles = np.array([[0.0, 4.0], [-4.0, 10.0]])
    out = wrap_angle(angles)
    assert out.shape == (2, 2)
    np.testing.assert_allclose(out, [[0.0, 4.0 - 2 * np.pi], [-4.0 + 2 * np.pi, 10.0 - 4 * np.pi]],
                               rtol=0.0, atol=8 * EPS)  # fmt: skip


@given(st.floats(-1e3, 1e3))
def test_wrap_angle_range_and_whole_turns(angle):
    out = float(wrap_angle(angle))
    assert -np.pi <= out < np.pi
    turns = (angle - out) / (2.0 * np.pi)
    assert abs(turns - round(turns)) <= 4 * EPS * max(1.0, abs(angle))


# pose_array -----------------------------------------------------------------------
def test_pose_array_position_gets_heading_zero_and_is_a_copy():
    given_pose = np.array([1.0, 2.0, 3.0])
    out = pose_array("start", given_pose)
    given_pose[0] = 99.0
    np.testing.assert_array_equal(out, [1.0, 2.0, 3.0])
    np.testing.assert_array_equal(pose_array("start", (4, 5)), [4.0, 5.0, 0.0])


@pytest.mark.parametrize(
    ("value", "match"),
    [
        ([1.0], r"start must be a pose \(x, y, theta\).*shape \(1,\)"),
        ([1.0, 2.0, 3.0, 4.0], r"start must be a pose.*shape \(4,\)"),
        ([[0.0, 0.0, 0.0]], r"start must be a pose.*shape \(1, 3\)"),
        ([0.0, np.nan, 0.0], r"start must be finite"),
        ("abc", r"start must be numeric"),
    ],
)
def test_pose_array_refuses_bad_poses(value, match):
    with pytest.raises(InvalidInputError, match=match):
        pose_array("start", value)


# Unicycle -------------------------------------------------------------------------
def test_unicycle_defaults_and_frozen():
    model = Unicycle()
    assert model.name == "unicycle"
    assert model.limits == MobileLimits()
    with pytest.raises(dataclasses.FrozenInstanceError):
        model.name = "other"  # type: ignore[misc]


def test_unicycle_refuses_other_limits_and_wheel_limits():
    with pytest.raises(InvalidInputError, match=r"limits must be a trajkit.mobile.MobileLimits"):
        Unicycle(limits={"velocity": 1.0})  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match=r"wheel_speed limit.*needs a DiffDrive"):
        Unicycle(limits=MobileLimits(wheel_speed=5.0))


# DiffDrive ------------------------------------------------------------------------
def test_diff_drive_wheel_speeds_closed_form():
    model = DiffDrive(wheel_radius=0.1, track_width=0.5)
    # φ̇_L = (v - ω b/2) / r, φ̇_R = (v + ω b/2) / r with v = 1, ω = 2, b = 0.5, r = 0.1.
    support.assert_state(model.wheel_speeds(1.0, 2.0), [5.0, 15.0], rtol=ROUNDING)
    skid = DiffDrive(wheel_radius=0.1, track_width=0.5, track_multiplier=1.5)
    assert skid.effective_track == pytest.approx(0.75, rel=ROUNDING)
    support.assert_state(skid.wheel_speeds(1.0, 2.0), [2.5, 17.5], rtol=ROUNDING)
    support.assert_state(skid.twist([2.5, 17.5]), [1.0, 2.0], rtol=ROUNDING)


def test_diff_drive_shapes_broadcast():
    model = DiffDrive(0.1, 0.5)
    assert model.wheel_speeds(1.0, 0.0).shape == (2,)
    assert model.wheel_speeds([1.0, 2.0, 3.0], 0.5).shape == (3, 2)
    assert model.wheel_speeds(np.ones((4, 1)), np.ones(3)).shape == (4, 3, 2)
    assert model.twist(np.ones((5, 2))).shape == (5, 2)
    assert model.twist([1.0, 1.0]).shape == (2,)


@given(
    radius=st.floats(1e-3, 10.0),
    track=st.floats(1e-3, 10.0),
    multiplier=st.floats(1.0, 3.0),
    v=speeds,
    omega=turn_rates,
)
def test_wheel_speeds_and_twist_round_trip(radius, track, multiplier, v, omega):
    model = DiffDrive(radius, track, track_multiplier=multiplier)
    wheels = model.wheel_speeds(v, omega)
    back = model.twist(wheels)
    # Relative to the size of the twist's contributions to the wheels.
    scale = abs(v) + abs(omega) * model.effective_track
    assert abs(back[0] - v) <= ROUND_TRIP * max(scale, EPS)
    assert abs(back[1] - omega) * model.effective_track <= ROUND_TRIP * max(scale, EPS)
    again = model.wheel_speeds(*back)
    assert np.all(np.abs(again - wheels) <= ROUND_TRIP * max(np.abs(wheels).max(), EPS))


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"wheel_radius": 0.0}, r"wheel_radius must be > 0, got 0 m"),
        ({"wheel_radius": -0.1}, r"wheel_radius must be > 0, got -0.1 m"),
        ({"wheel_radius": np.nan}, r"wheel_radius must be finite"),
        ({"track_width": 0.0}, r"track_width must be > 0, got 0 m"),
        ({"track_width": -1.0}, r"track_width must be > 0"),
        ({"track_multiplier": 0.5}, r"track_multiplier must be >= 1"),
        ({"track_multiplier": -1.0}, r"track_multiplier must be > 0"),
        ({"wheelbase": -0.2}, r"wheelbase must be >= 0 m, got -0.2 m"),
        ({"wheelbase": np.inf}, r"wheelbase must be finite"),
        ({"mass": 0.0}, r"mass must be > 0, got 0 kg"),
        ({"wheel_speed_limit": -3.0}, r"wheel_speed_limit must be > 0, got -3 rad/s"),
        ({"wheel_speed_limit": np.nan}, r"wheel_speed_limit must be finite"),
        ({"limits": (1.0, 2.0)}, r"limits must be a trajkit.mobile.MobileLimits, got tuple"),
    ],
)
def test_diff_drive_refuses_bad_parameters(kwargs, match):
    arguments = {"wheel_radius": 0.1, "track_width": 0.5} | kwargs
    with pytest.raises(InvalidInputError, match=match):
        DiffDrive(**arguments)


def test_diff_drive_wheel_limit_joins_its_limits():
    base = MobileLimits(velocity=1.0)
    model = DiffDrive(0.1, 0.5, wheel_speed_limit=7, limits=base)
    assert isinstance(model.wheel_speed_limit, float)
    assert float(model.limits.wheel_speed.lower) == -7.0
    assert float(model.limits.wheel_speed.upper) == 7.0
    assert model.limits.velocity == base.velocity
    assert base.wheel_speed is None  # the given limits are not changed


def test_diff_drive_twist_refuses_bad_shapes():
    model = DiffDrive(0.1, 0.5)
    with pytest.raises(InvalidInputError, match=r"wheel_speeds must have shape \(..., 2\)"):
        model.twist([1.0, 2.0, 3.0])
    with pytest.raises(InvalidInputError, match=r"wheel_speeds must have shape"):
        model.twist(1.0)
    with pytest.raises(InvalidInputError, match=r"wheel_speeds must be finite"):
        model.twist([1.0, np.inf])
    with pytest.raises(InvalidInputError, match=r"omega must be finite"):
        model.wheel_speeds(1.0, np.nan)
    with pytest.raises(InvalidInputError, match=r"v must be finite"):
        model.wheel_speeds(np.inf, 0.0)


def test_jackal_published_figures():
    robot = jackal()
    assert (robot.wheel_radius, robot.track_width, robot.track_multiplier) == (0.098, 0.37559, 1.5)
    assert (robot.wheelbase, robot.mass, robot.name) == (0.262, 17.0, "jackal")
    assert robot.effective_track == pytest.approx(0.37559 * 1.5, rel=ROUNDING)
    assert robot.wheel_speed_limit == pytest.approx(2.0 / 0.098, rel=ROUNDING)
    for attribute, value in [("velocity", 2.0), ("angular_velocity", 4.0),
                             ("acceleration", 20.0), ("angular_acceleration", 25.0),
                             ("wheel_speed", 2.0 / 0.098)]:  # fmt: skip
        assert robot.limits.magnitude(attribute) == pytest.approx(value, rel=ROUNDING)
    # Driving straight at the speed limit puts both wheels exactly at theirs.
    support.assert_state(robot.wheel_speeds(2.0, 0.0), [2.0 / 0.098] * 2, rtol=ROUNDING)


# arc_pose -------------------------------------------------------------------------
def closed_form_arc(pose, v, omega, t):
    """The textbook circle: centre at R to the left, R = v / ω."""
    x, y, theta = pose
    radius = v / omega
    return np.array([
        x + radius * (np.sin(theta + omega * t) - np.sin(theta)),
        y - radius * (np.cos(theta + omega * t) - np.cos(theta)),
        theta + omega * t,
    ])  # fmt: skip


@given(support.poses(), speeds, nonzero_turn_rates, times)
def test_arc_pose_equals_the_closed_form_circle(pose, v, omega, t):
    out = arc_pose(pose, v, omega, t)
    expected = closed_form_arc(pose, v, omega, t)
    # The closed form itself rounds on the scale of its radius and coordinates.
    scale = 1.0 + np.abs(pose[:2]).max() + abs(v / omega)
    assert np.abs(out[:2] - expected[:2]).max() <= WORLD_ROUNDING * scale
    assert out[2] == pose[2] + omega * t  # the heading is not wrapped


@given(support.poses(), speeds, times)
def test_arc_pose_without_turning_is_the_straight_line(pose, v, t):
    out = arc_pose(pose, v, 0.0, t)
    expected = pose[:2] + v * t * np.array([np.cos(pose[2]), np.sin(pose[2])])
    assert np.abs(out[:2] - expected).max() <= WORLD_ROUNDING * (1.0 + np.abs(expected).max())
    assert out[2] == pose[2]


@given(support.poses(), turn_rates, times)
def test_arc_pose_spin_in_place_keeps_the_position(pose, omega, t):
    out = arc_pose(pose, 0.0, omega, t)
    np.testing.assert_array_equal(out[:2], pose[:2])
    assert out[2] == pose[2] + omega * t


@given(support.poses(), speeds, turn_rates, times, times)
def test_arc_pose_composes(pose, v, omega, t1, t2):
    twice = arc_pose(arc_pose(pose, v, omega, t1), v, omega, t2)
    once = arc_pose(pose, v, omega, t1 + t2)
    travel = abs(v) * (t1 + t2)
    turned = abs(omega) * (t1 + t2)
    # A heading rounded by ulps of its size moves the end by that much times the travel.
    scale = (1.0 + np.abs(pose[:2]).max() + travel) * (1.0 + turned + abs(pose[2]))
    assert np.abs(twice[:2] - once[:2]).max() <= COMPOSITION * scale
    assert abs(twice[2] - once[2]) <= COMPOSITION * (1.0 + abs(pose[2]) + turned)


def test_arc_pose_broadcasts_over_poses_and_times():
    poses = np.array([[0.0, 0.0, 0.0], [1.0, 2.0, np.pi / 2]])
    out = arc_pose(poses, 1.0, np.array([0.0, np.pi / 2]), np.array([2.0, 1.0]))
    assert out.shape == (2, 3)
    support.assert_state(out[0], [2.0, 0.0, 0.0], rtol=ROUNDING)
    # A quarter circle of radius 2/π from (1, 2) heading +y, turning left:
    # it ends at (1 - 2/π, 2 + 2/π) heading -x.
    radius = 2.0 / np.pi
    support.assert_state(out[1], [1.0 - radius, 2.0 + radius, np.pi], rtol=ROUNDING)
    assert arc_pose([0.0, 0.0, 0.0], 1.0, 1.0, np.linspace(0, 1, 5)).shape == (5, 3)


# rk4_step -------------------------------------------------------------------------
@given(st.floats(-2.0, 2.0), st.floats(1e-3, 1.0), st.floats(-10.0, 10.0))
def test_rk4_step_on_a_linear_ode_is_taylors_quartic(rate, h, start):
    def linear(stage, state):
        return rate * state

    out = rk4_step(linear, np.array([start]), h)
    z = rate * h
    expected = start * (1.0 + z + z**2 / 2.0 + z**3 / 6.0 + z**4 / 24.0)
    assert abs(out[0] - expected) <= ROUNDING * max(1.0, abs(start) * np.exp(abs(z)))


def test_rk4_step_stages_in_order_and_simpsons_rule():
    seen = []
    values = {0: 1.0, 1: 4.0, 2: 9.0}  # f(t) = (1 + t)² sampled at t = 0, 1, 2 by stage

    def rate(stage, state):
        seen.append(stage)
        return np.array([values[stage]])

    out = rk4_step(rate, np.array([0.5]), 2.0)
    assert seen == [0, 1, 1, 2]
    # Simpson: h/6 (f0 + 4 f_mid + f1) = 2/6 (1 + 16 + 9), exact for a quadratic.
    assert out[0] == pytest.approx(0.5 + 26.0 / 3.0, rel=ROUNDING)


# propagate ------------------------------------------------------------------------
@settings(max_examples=30, deadline=None)
@given(support.poses(), speeds, st.floats(-5.0, 5.0), st.sampled_from([1e-3, 1e-2]))
def test_propagate_matches_arc_pose_for_a_constant_twist(pose, v, omega, h):
    duration = 2.0
    t = np.linspace(0.0, duration, round(duration / h) + 1)
    out = propagate(pose, lambda tt: np.tile([v, omega], (tt.size, 1)), t)
    exact = arc_pose(pose, v, omega, t)
    scale = 1.0 + np.abs(pose[:2]).max() + abs(v) * duration
    bound = support.rk4_constant_twist_bound(v, omega, h, duration, scale)
    assert np.abs(out[:, :2] - exact[:, :2]).max() <= bound
    # θ̇ = ω is integrated exactly by RK4; only rounding accumulates.
    heading_rounding = 8 * t.size * EPS * (1 + np.abs(exact[:, 2]).max())
    assert np.abs(out[:, 2] - exact[:, 2]).max() <= heading_rounding


def test_propagate_clothoid_against_fresnel_integrals():
    # v constant and ω = c t: θ = θ0 + c t² / 2, a clothoid; x, y are Fresnel integrals.
    v, c, theta0 = 0.7, 0.9, 0.3
    t = np.linspace(0.0, 4.0, 4001)
    out = propagate([1.0, -2.0, theta0], lambda tt: np.stack([np.full(tt.size, v), c * tt], 1), t)
    s, cc = fresnel(t * np.sqrt(c / np.pi))
    k = v * np.sqrt(np.pi / c)
    x = 1.0 + k * (np.cos(theta0) * cc - np.sin(theta0) * s)
    y = -2.0 + k * (np.sin(theta0) * cc + np.cos(theta0) * s)
    assert np.abs(out[:, 0] - x).max() <= CLOTHOID_RK4
    assert np.abs(out[:, 1] - y).max() <= CLOTHOID_RK4
    assert np.abs(out[:, 2] - (theta0 + c * t**2 / 2)).max() <= CLOTHOID_RK4


def test_propagate_one_time_and_position_start():
    out = propagate((1.0, 2.0), lambda tt: np.ones((tt.size, 2)), [5.0])
    np.testing.assert_array_equal(out, [[1.0, 2.0, 0.0]])


def test_propagate_asks_for_starts_middles_and_ends_at_once():
    asked = []

    def twist(tt):
        asked.append(np.array(tt))
        return np.zeros((tt.size, 2))

    propagate([0, 0, 0], twist, [0.0, 1.0, 3.0])
    assert len(asked) == 1
    np.testing.assert_array_equal(asked[0], [0.0, 1.0, 3.0, 0.5, 2.0])


@pytest.mark.parametrize(
    ("start", "t", "match"),
    [
        ([0, 0, 0], [0.0, 1.0, 1.0], r"times must be a strictly increasing 1-D array"),
        ([0, 0, 0], [1.0, 0.0], r"times must be a strictly increasing"),
        ([0, 0, 0], [], r"times must be a strictly increasing"),
        ([0, 0, 0], [[0.0, 1.0]], r"times must be a strictly increasing"),
        ([0, 0, 0], [0.0, np.nan], r"times must be finite"),
        ([0, 0, 0, 0], [0.0, 1.0], r"start must be a pose"),
    ],
)
def test_propagate_refuses_bad_input(start, t, match):
    with pytest.raises(InvalidInputError, match=match):
        propagate(start, lambda tt: np.zeros((tt.size, 2)), t)


def test_closed_form_reference_is_the_textbook_circle():
    # Guard the test's own oracle: a half circle of radius 1 from the origin heading +x.
    support.assert_state(closed_form_arc([0, 0, 0], 1.0, 1.0, np.pi), [0.0, 2.0, np.pi],
                         rtol=CLOSED_FORM)  # fmt: skip


def test_wheel_limit_given_once_or_consistently():
    assert DiffDrive(0.1, 0.4, limits=MobileLimits(wheel_speed=5.0)).wheel_speed_limit == 5.0
    same = DiffDrive(0.1, 0.4, wheel_speed_limit=5.0, limits=MobileLimits(wheel_speed=5.0))
    assert same.wheel_speed_limit == 5.0
    with pytest.raises(InvalidInputError, match=r"wheel_speed_limit=7 rad/s disagrees .*\(-5, 5\)"):
        DiffDrive(0.1, 0.4, wheel_speed_limit=7.0, limits=MobileLimits(wheel_speed=5.0))


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda: DiffDrive(0.1, 0.4, wheelbase=[1.0, 2.0]), "wheelbase must be a single number"),
        (lambda: DiffDrive(0.1, 0.4).wheel_speeds([0.1, 0.2], [0.0, 1.0, 2.0]),
         "do not broadcast together"),
        (lambda: arc_pose((0.0, 0.0), 1.0, 1.0, 1.0), r"pose must have shape \(\.\.\., 3\)"),
        (lambda: arc_pose([[0.0, 0.0, 0.0]] * 2, [1.0, 2.0, 3.0], 1.0, 1.0),
         "do not broadcast together"),
        (lambda: arc_pose((0.0, 0.0, 0.0), np.nan, 1.0, 1.0), "v must be finite"),
    ],
)  # fmt: skip
def test_shape_and_value_errors_name_the_argument(call, match):
    with pytest.raises(InvalidInputError, match=match):
        call()


def test_arc_pose_broadcasts_twists_over_one_pose():
    poses = arc_pose((0.0, 0.0, 0.0), np.ones(4), 0.5, 1.0)
    assert poses.shape == (4, 3)
    np.testing.assert_array_equal(poses, np.tile(arc_pose((0.0, 0.0, 0.0), 1.0, 0.5, 1.0), (4, 1)))


def test_a_one_sided_wheel_limit_reports_its_largest_magnitude():
    model = DiffDrive(0.1, 0.4, limits=MobileLimits(wheel_speed=(0.0, 10.0)))
    assert model.wheel_speed_limit == 10.0
