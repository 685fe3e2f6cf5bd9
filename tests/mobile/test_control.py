"""Tests of trajkit.mobile.control: saturation, each control law against its formula,
pure pursuit's geometry, the distance to a path, and convergence of every feedback
tracker on the figure eight from a 0.5 m, 30° offset (RK4 at 1 kHz).

Convergence criteria (measured figures in brackets, for the offset to the left and
turned left / to the right and turned right):

- Kanayama: largest position error from t = 10 s on <= 1e-2 m [1.4e-3, 3.2e-3];
  final position error <= 1e-4 m [8.9e-6, 3.0e-6] and heading error <= 1e-4 rad.
- Feedback linearization (k_p = k_d = 4, critically damped, e ~ (1 + 2t) e^(-2t)):
  from 5 s on <= 1e-3 m [2.8e-4], from 10 s on <= 1e-6 m [2.4e-8], final <= 1e-10 m.
- Pure pursuit follows the path, not the clock: its distance from the path from
  10 s on <= 0.05 m [0.033, 0.028] (the corner cutting of a 0.3 m look-ahead),
  from 0.5 m [0.29 m to the right, nearer the other lobe] at the start.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import support
from support import CLOSED_FORM, ROUNDING
from trajkit import InvalidInputError
from trajkit.mobile import (
    DiffDrive,
    FeedbackLinearization,
    Feedforward,
    Kanayama,
    MobileLimits,
    PurePursuit,
    Unicycle,
    constant_twist,
    flat_trajectory,
    saturate,
    simulate,
)
from trajkit.mobile.control import controller_named, nearest_path_distance

# Tolerances and criteria -----------------------------------------------------------
SATURATED = 1e-12  # relative: a saturated command against its bound
DISTANCE = 1e-12  # m: the path distance against a brute-force polyline distance
OFFSET, TURN = 0.5, math.radians(30.0)
KANAYAMA_AFTER_10S, KANAYAMA_FINAL, KANAYAMA_HEADING = 1e-2, 1e-4, 1e-4
LINEARIZATION_AFTER_5S, LINEARIZATION_AFTER_10S, LINEARIZATION_FINAL = 1e-3, 1e-6, 1e-10
PURSUIT_PATH_AFTER_10S = 0.05

bound_values = st.floats(0.05, 10.0)
commands = st.one_of(st.just(0.0), st.floats(-50.0, 50.0))


def figure_eight_plan():
    return flat_trajectory(support.phased_eight(2.0, 1.0, 20.0, 0.125))


# saturate -------------------------------------------------------------------------
def test_saturate_clips_speed_and_turn_rate():
    limits = MobileLimits(velocity=(-0.5, 1.0), angular_velocity=2.0)
    assert saturate(3.0, 0.0, Unicycle(), limits) == (1.0, 0.0)
    assert saturate(-3.0, -5.0, Unicycle(), limits) == (-0.5, -2.0)
    assert saturate(0.3, 1.5, Unicycle(), limits) == (0.3, 1.5)
    assert saturate(7.0, -9.0, Unicycle(), MobileLimits()) == (7.0, -9.0)


def test_saturate_scales_both_to_the_wheel_limit_keeping_the_curvature():
    model = DiffDrive(0.1, 0.5)
    limits = MobileLimits(wheel_speed=5.0)
    # Wheels (v ∓ ω b/2) / r = (5, 15) rad/s: the right wheel needs a factor 1/3.
    v, omega = saturate(1.0, 2.0, model, limits)
    assert v == pytest.approx(1.0 / 3.0, rel=SATURATED)
    assert omega == pytest.approx(2.0 / 3.0, rel=SATURATED)
    assert max(np.abs(model.wheel_speeds(v, omega))) == pytest.approx(5.0, rel=SATURATED)
    # An asymmetric wheel limit: slower backwards.
    back = saturate(-1.0, 0.0, model, MobileLimits(wheel_speed=(-2.0, 5.0)))
    assert back[0] == pytest.approx(-0.2, rel=SATURATED) and back[1] == 0.0
    # Clipped first, then scaled: v 2 -> 1 m/s, then wheels (1 + 0.75) / 0.1 = 17.5 rad/s.
    v, omega = saturate(2.0, 3.0, model, MobileLimits(velocity=1.0, wheel_speed=5.0))
    assert v == pytest.approx(5.0 / 17.5, rel=SATURATED)
    assert omega == pytest.approx(3.0 * 5.0 / 17.5, rel=SATURATED)


@given(
    commands, commands, st.one_of(st.none(), bound_values), st.one_of(st.none(), bound_values),
    st.one_of(st.none(), st.tuples(bound_values, bound_values)), st.booleans(),
)  # fmt: skip
def test_saturated_commands_are_within_every_limit(v, omega, vmax, wmax, wheel, diff_drive):
    model = DiffDrive(0.1, 0.5) if diff_drive else Unicycle()
    wheel_limit = None if wheel is None or not diff_drive else (-wheel[0], wheel[1])
    limits = MobileLimits(velocity=vmax, angular_velocity=wmax, wheel_speed=wheel_limit)
    out_v, out_w = saturate(v, omega, model, limits)
    if vmax is not None:
        assert abs(out_v) <= vmax * (1 + SATURATED)
    if wmax is not None:
        assert abs(out_w) <= wmax * (1 + SATURATED)
    if wheel_limit is not None:
        left, right = model.wheel_speeds(out_v, out_w)
        for speed in (left, right):
            assert -wheel[0] * (1 + SATURATED) <= speed <= wheel[1] * (1 + SATURATED)
    # Nothing changes inside the limits, and the wheel scaling keeps the curvature.
    clipped_v = v if vmax is None else min(max(v, -vmax), vmax)
    clipped_w = omega if wmax is None else min(max(omega, -wmax), wmax)
    assert out_v * clipped_w == pytest.approx(out_w * clipped_v, rel=1e-12, abs=1e-300)
    assert abs(out_v) <= abs(clipped_v) and abs(out_w) <= abs(clipped_w)
    if wheel_limit is None:
        assert (out_v, out_w) == (clipped_v, clipped_w)


# Feedforward ----------------------------------------------------------------------
def test_feedforward_sends_the_plans_twist():
    law = Feedforward().law(figure_eight_plan(), np.zeros(3))
    assert law.initial_state.shape == (0,)
    desired = (1.0, 2.0, 0.3, 0.7, -0.2, 0.1, 0.0)
    law.advance(0.0, np.array([5.0, 5.0, 1.0]))
    v, omega, rate = law(0.0, np.array([5.0, 5.0, 1.0]), desired, law.initial_state)
    assert (v, omega) == (0.7, -0.2) and rate.shape == (0,)
    assert Feedforward().name == "feedforward"


# Kanayama -------------------------------------------------------------------------
def kanayama_reference(pose, desired, kx, ky, ktheta):
    """Kanayama et al. (1990), eq. (9), written out."""
    x, y, theta = pose
    xd, yd, thd, vd, wd = desired[:5]
    ex = math.cos(theta) * (xd - x) + math.sin(theta) * (yd - y)
    ey = -math.sin(theta) * (xd - x) + math.cos(theta) * (yd - y)
    eth = math.atan2(math.sin(thd - theta), math.cos(thd - theta))
    # |v_d| on the heading term: the law stays stable driving backwards.
    return vd * math.cos(eth) + kx * ex, wd + vd * ky * ey + abs(vd) * ktheta * math.sin(eth)


@given(support.poses(), support.poses(), st.floats(-2.0, 2.0), st.floats(-2.0, 2.0))
def test_kanayama_law_is_the_formula(pose, target, vd, wd):
    gains = Kanayama(kx=1.5, ky=7.0, ktheta=2.5)
    law = gains.law(figure_eight_plan(), pose)
    desired = (*target, vd, wd, 0.0, 0.0)
    v, omega, _ = law(0.0, pose, desired, law.initial_state)
    expected = kanayama_reference(pose, desired, 1.5, 7.0, 2.5)
    support.assert_state([v, omega], expected, rtol=ROUNDING)


def test_kanayama_by_hand():
    law = Kanayama(kx=1.0, ky=6.0, ktheta=3.0).law(figure_eight_plan(), np.zeros(3))
    # The target is 1 m ahead and 0.5 m to the left, turned 0.2 rad, of a robot at the origin.
    v, omega, _ = law(0.0, np.zeros(3), (1.0, 0.5, 0.2, 0.8, 0.1, 0.0, 0.0), law.initial_state)
    assert v == pytest.approx(0.8 * math.cos(0.2) + 1.0, rel=CLOSED_FORM)
    assert omega == pytest.approx(0.1 + 0.8 * (6.0 * 0.5 + 3.0 * math.sin(0.2)), rel=CLOSED_FORM)
    # On target: the plan's twist. Across ±π the heading error is the short way (-0.083 rad).
    on_target = law(0.0, np.array([1.0, 2.0, 3.0]), (1.0, 2.0, 3.0, 0.5, 0.4, 0, 0), np.zeros(0))
    assert on_target[:2] == (0.5, 0.4)
    _, omega, _ = law(0.0, np.array([0.0, 0.0, -3.1]), (0.0, 0.0, 3.1, 1.0, 0.0, 0, 0), np.zeros(0))
    assert omega == pytest.approx(3.0 * math.sin(6.2 - 2 * math.pi), rel=CLOSED_FORM)
    # Backwards the heading term keeps its sign, the cross-track term follows v_d.
    _, omega, _ = law(0.0, np.zeros(3), (0.0, 0.5, 0.2, -0.8, 0.0, 0.0, 0.0), np.zeros(0))
    assert omega == pytest.approx(-0.8 * 6.0 * 0.5 + 0.8 * 3.0 * math.sin(0.2), rel=CLOSED_FORM)


# Feedback linearization -------------------------------------------------------------
def test_linearization_on_target_reproduces_the_plan():
    law = FeedbackLinearization(kp=2.0, kd=3.0).law(figure_eight_plan(), np.zeros(3))
    theta, vd, wd, ad = 0.7, 0.4, -0.3, 0.25
    desired = (1.0, 2.0, theta, vd, wd, ad, 0.0)
    v, omega, rate = law(0.0, np.array([1.0, 2.0, theta]), desired, np.array([vd]))
    assert v == vd
    assert omega == pytest.approx(wd, rel=CLOSED_FORM)
    assert rate[0] == pytest.approx(ad, rel=CLOSED_FORM)  # ξ̇ = the plan's acceleration


def test_linearization_by_hand():
    law = FeedbackLinearization(kp=4.0, kd=4.0).law(figure_eight_plan(), np.zeros(3))
    # Robot at the origin heading +x at ξ = 0.5; target at (1, 0.5) heading +y at 1 m/s.
    v, omega, rate = law(0.0, np.zeros(3), (1.0, 0.5, math.pi / 2, 1.0, 0.0, 0.0, 0.0),
                         np.array([0.5]))  # fmt: skip
    u1 = 4.0 * 1.0 + 4.0 * (0.0 - 0.5)  # ẍ_d + k_p e_x + k_d (ẋ_d - ẋ)
    u2 = 4.0 * 0.5 + 4.0 * (1.0 - 0.0)
    assert v == 0.5
    assert omega == pytest.approx(u2 / 0.5, rel=CLOSED_FORM)
    assert rate[0] == pytest.approx(u1, rel=CLOSED_FORM)


def test_linearization_keeps_away_from_zero_speed():
    gains = FeedbackLinearization(min_speed=0.01)
    at_rest = flat_trajectory(support.phased_eight(2.0, 1.0, 20.0, 0.0))
    law = gains.law(at_rest, np.zeros(3))
    # |ṗ(0)| = √((W/2 · 2π/T)² + (H/2 · 4π/T)²) = (π/10) √2 for W = 2, H = 1, T = 20.
    assert law.initial_state[0] == pytest.approx(math.pi / 10 * math.sqrt(2.0), rel=CLOSED_FORM)
    spline_law = gains.law(constant_twist(0.0, 1.0, 1.0), np.zeros(3))
    assert spline_law.initial_state[0] == 0.01  # the plan starts at rest: ξ starts at min_speed
    desired = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    for xi, expected in ((0.0, 0.01), (1e-5, 0.01), (-1e-5, -0.01), (-0.3, -0.3)):
        v, _, _ = law(0.0, np.zeros(3), desired, np.array([xi]))
        assert v == expected


# Pure pursuit ---------------------------------------------------------------------
def straight_plan():
    # 4000 path samples 1 mm apart along +x at 1 m/s.
    return constant_twist(1.0, 0.0, 3.999)


def test_pure_pursuit_steers_on_the_arc_to_the_look_ahead_point():
    lookahead = 0.3005  # between samples: the look-ahead point is the one at x = 1.301
    law = PurePursuit(lookahead=lookahead).law(straight_plan(), np.zeros(3))
    pose = np.array([1.0, -0.2, 0.0])
    law.advance(0.0, pose)
    v, omega, _ = law(0.0, pose, (0.0,) * 7, law.initial_state)
    dx, dy = 1.301 - 1.0, 0.2
    assert v == 1.0  # the plan's speed at the nearest path point
    assert omega == pytest.approx(2.0 * dy / (dx**2 + dy**2), rel=1e-9)
    on_path = np.array([1.0, 0.0, 0.0])
    assert law(0.0, on_path, (0.0,) * 7, law.initial_state)[1] == 0.0


def test_pure_pursuit_never_goes_back_and_stops_at_the_end():
    law = PurePursuit(lookahead=0.2, speed=0.5).law(straight_plan(), np.zeros(3))
    law.advance(0.0, np.array([0.5, 0.0, 0.0]))
    reached = law.nearest
    assert reached == 500  # the sample at x = 0.5 m
    law.advance(0.1, np.array([0.0, 0.0, 0.0]))
    assert law.nearest == reached
    assert law(0.0, np.array([0.5, 0.1, 0.0]), (0.0,) * 7, law.initial_state)[0] == 0.5
    for x in np.arange(0.5, 4.2, 0.1):  # drive to the end, one window at a time
        law.advance(0.0, np.array([x, 0.0, 0.0]))
    assert law.nearest == 3999
    assert law(0.0, np.array([4.0, 0.0, 0.0]), (0.0,) * 7, law.initial_state)[:2] == (0.0, 0.0)


@pytest.mark.parametrize(
    ("make", "match"),
    [
        (lambda: PurePursuit(lookahead=0.0), r"lookahead must be > 0, got 0 m"),
        (lambda: PurePursuit(speed=-1.0), r"speed must be > 0, got -1 m/s"),
        (lambda: Kanayama(kx=0.0), r"kx must be > 0, got 0 1/s"),
        (lambda: Kanayama(ky=-1.0), r"ky must be > 0, got -1 1/m\^2"),
        (lambda: Kanayama(ktheta=np.nan), r"ktheta must be finite"),
        (lambda: FeedbackLinearization(kp=-4.0), r"kp must be > 0, got -4 1/s\^2"),
        (lambda: FeedbackLinearization(kd=0.0), r"kd must be > 0, got 0 1/s"),
        (lambda: FeedbackLinearization(min_speed=0.0), r"min_speed must be > 0, got 0 m/s"),
    ],
)
def test_bad_gains_name_the_argument(make, match):
    with pytest.raises(InvalidInputError, match=match):
        make()


def test_controller_names():
    assert isinstance(controller_named("feedforward"), Feedforward)
    assert isinstance(controller_named("kanayama"), Kanayama)
    assert isinstance(controller_named("linearization"), FeedbackLinearization)
    assert isinstance(controller_named("pure-pursuit"), PurePursuit)
    assert controller_named("kanayama") == Kanayama()  # default gains
    with pytest.raises(
        InvalidInputError,
        match=r"controller must be one of feedforward, "
        r"kanayama, linearization, pure-pursuit, got 'pid'",
    ):
        controller_named("pid")


# nearest_path_distance ---------------------------------------------------------------
def brute_force_distance(path: np.ndarray, point: np.ndarray) -> float:
    """The smallest distance from ``point`` to any of the polyline's segments."""
    a, along = path[:-1], np.diff(path, axis=0)
    length2 = np.einsum("ij,ij->i", along, along)
    safe = np.where(length2 > 0.0, length2, 1.0)
    u = np.clip(np.einsum("ij,ij->i", point - a, along) / safe, 0.0, 1.0)
    u = np.where(length2 > 0.0, u, 0.0)
    return float(np.linalg.norm(point - (a + u[:, None] * along), axis=1).min())


def test_nearest_path_distance_by_hand():
    path = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    points = np.array([[0.5, 1.0], [3.0, 0.0], [-1.0, -1.0], [1.5, -0.25], [1.0, 0.0]])
    expected = [1.0, 1.0, math.sqrt(2.0), 0.25, 0.0]
    np.testing.assert_allclose(nearest_path_distance(path, points), expected, rtol=0, atol=DISTANCE)
    # Standing still (repeated vertices) hides no segment: (0.5, 1) is 1 m from the path,
    # though its nearest vertices are the copies of (0, 0) and (1, 0), 1.118 m away.
    still = np.array([[0.0, 0.0]] * 5 + [[1.0, 0.0]] * 5 + [[2.0, 0.0]])
    np.testing.assert_allclose(
        nearest_path_distance(still, points), expected, rtol=0, atol=DISTANCE
    )
    only = nearest_path_distance(np.array([[1.0, 1.0]] * 3), np.array([[4.0, 5.0]]))
    np.testing.assert_allclose(only, [5.0], rtol=0, atol=DISTANCE)


@given(st.lists(st.tuples(st.floats(-3.0, 3.0), st.floats(-3.0, 3.0)), min_size=1, max_size=20))
def test_nearest_path_distance_on_a_dense_path_is_the_polyline_distance(points):
    # A circle of radius 2 in 2000 segments; any point's nearest vertex borders its nearest segment.
    angle = np.linspace(0.0, 2 * np.pi, 2001)
    path = 2.0 * np.stack([np.cos(angle), np.sin(angle)], 1)
    query = np.array(points)
    found = nearest_path_distance(path, query)
    expected = [brute_force_distance(path, p) for p in query]
    np.testing.assert_allclose(found, expected, rtol=0, atol=DISTANCE)


# Convergence from an offset ---------------------------------------------------------
OFFSETS = [pytest.param(+1.0, id="left-turned-left"), pytest.param(-1.0, id="right-turned-right")]


def run_from_offset(controller, side: float):
    plan = figure_eight_plan()
    start = support.offset_pose(plan.start_pose, side * OFFSET, side * TURN)
    log = simulate(plan, controller, sample_step=0.001, initial_pose=start)
    assert log.position_error[0] == pytest.approx(OFFSET, rel=CLOSED_FORM)
    assert abs(log.heading_error[0]) == pytest.approx(TURN, rel=CLOSED_FORM)
    return log


@pytest.mark.parametrize("side", OFFSETS)
def test_kanayama_converges(side):
    log = run_from_offset(Kanayama(), side)
    assert log.error_after(10.0) <= KANAYAMA_AFTER_10S
    assert log.final_position_error <= KANAYAMA_FINAL
    assert log.final_heading_error <= KANAYAMA_HEADING


@pytest.mark.parametrize("side", OFFSETS)
def test_feedback_linearization_converges(side):
    log = run_from_offset(FeedbackLinearization(), side)
    assert log.error_after(5.0) <= LINEARIZATION_AFTER_5S
    assert log.error_after(10.0) <= LINEARIZATION_AFTER_10S
    assert log.final_position_error <= LINEARIZATION_FINAL
    assert log.final_heading_error <= LINEARIZATION_FINAL


@pytest.mark.parametrize("side", OFFSETS)
def test_pure_pursuit_converges_to_the_path(side):
    log = run_from_offset(PurePursuit(), side)
    assert log.path_distance[0] >= 0.29  # it starts well off the path
    assert log.path_distance[log.t >= 10.0].max() <= PURSUIT_PATH_AFTER_10S


def test_pure_pursuit_gets_going_on_a_plan_from_rest_and_stops_at_its_end():
    from trajkit.mobile import rotate_translate_rotate, spline_output

    limits = MobileLimits(velocity=0.5, angular_velocity=1.0, acceleration=1.0,
                          angular_acceleration=1.0)  # fmt: skip
    plan = rotate_translate_rotate((3.0, 0.0), limits=limits)
    run = simulate(plan, PurePursuit(), sample_step=0.01, duration=plan.duration + 2.0)
    assert run.final_position_error < 1e-3
    curve = flat_trajectory(spline_output([[0.0, 0.0], [1.0, 0.0], [2.0, 1.0]]))
    run = simulate(
        curve, PurePursuit(lookahead=0.2), sample_step=0.01, duration=curve.duration + 5.0
    )
    assert run.final_position_error < 1e-3 and run.max_path_distance < 0.01


def test_pure_pursuit_does_not_stall_on_a_final_turn_in_place():
    from trajkit.mobile import rotate_translate_rotate

    limits = MobileLimits(velocity=0.5, angular_velocity=1.0, acceleration=1.0,
                          angular_acceleration=1.0)  # fmt: skip
    plan = rotate_translate_rotate((5.0, 3.0, 1.5), limits=limits)
    run = simulate(plan, PurePursuit(speed=0.2), sample_step=0.02, duration=60.0)
    # It stops at the goal instead of driving on past it (pure pursuit cannot turn in place).
    assert run.final_position_error < 0.01
    assert np.hypot(*(run.actual[:, :2] - [5.0, 3.0]).T).min() < 0.01


@pytest.mark.parametrize("controller", [Kanayama(), FeedbackLinearization()])
def test_trackers_converge_driving_backwards(controller):
    from trajkit.mobile import rotate_translate_rotate

    limits = MobileLimits(velocity=0.5, angular_velocity=1.0, acceleration=1.0,
                          angular_acceleration=1.0)  # fmt: skip
    plan = rotate_translate_rotate((-3.0, 0.0), limits=limits, reverse=True)
    assert plan.twist(3.0)[0] < 0.0
    run = simulate(plan, controller, sample_step=0.01, initial_pose=(0.0, 0.1, 0.1))
    assert run.final_position_error < 5e-3
    assert run.final_heading_error < np.radians(1.0)


def test_pure_pursuit_at_a_constant_speed_follows_a_reverse_plan_backwards():
    from trajkit.mobile import rotate_translate_rotate

    limits = MobileLimits(velocity=0.5, angular_velocity=1.0, acceleration=1.0,
                          angular_acceleration=1.0)  # fmt: skip
    plan = rotate_translate_rotate((-2.0, 0.5, 0.0), limits=limits, reverse=True)
    run = simulate(plan, PurePursuit(speed=0.3), sample_step=0.01, duration=plan.duration + 5.0)
    assert run.commands[len(run.t) // 2, 0] == pytest.approx(-0.3)
    assert run.max_path_distance < 0.05 and run.final_position_error < 0.01
