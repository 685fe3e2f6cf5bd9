"""One protocol for every curve: evaluate(t, order) on [start_time, end_time]."""

from __future__ import annotations

import numpy as np
import pytest

import trajkit as tk
from trajkit import batch, mobile
from trajkit.curve import Segmented
from trajkit.taskspace import Arc, Ellipse, FigureEight, Line, Polyline, timed


def curves() -> dict[str, tk.Curve]:
    return {
        "trajectory": tk.quintic([0.0, 1.0], [1.0, -1.0], 2.0),
        "batch": batch.trapezoidal([[0.0], [0.0]], [[1.0], [2.0]], 1.0, 2.0),
        "flat output": mobile.FigureEight(2.0, 1.0, 20.0),
        "line": Line([0.0, 0.0, 0.0], [1.0, 2.0, 3.0]),
        "ellipse": Ellipse([0.0, 0.0, 0.0], 1.0, 0.5),
        "task trajectory": task_motion(),
        "mobile trajectory": mobile_plan(),
    }


def task_motion():
    return timed(Ellipse([0.0, 0.0, 1.0], 1.0, 0.5), "quintic", duration=4.0)


def mobile_plan():
    return mobile.flat_trajectory(mobile.FigureEight(2.0, 1.0, 20.0))


@pytest.mark.parametrize("name", list(curves()))
def test_every_curve_answers_the_one_protocol(name):
    curve = curves()[name]
    assert isinstance(curve, tk.Curve)
    start, end = curve.start_time, curve.end_time
    assert curve.duration == pytest.approx(end - start, rel=1e-15)
    breakpoints = curve.breakpoints
    assert breakpoints[0] == start and breakpoints[-1] == end
    t = np.linspace(start, end, 7)
    for order, named in enumerate((curve.position, curve.velocity, curve.acceleration)):
        np.testing.assert_array_equal(named(t), curve.evaluate(t, order))
    # The first derivative is the derivative of the value (central differences).
    h = 1e-6 * (end - start)
    inner = np.linspace(start + 0.1 * (end - start), end - 0.1 * (end - start), 5)
    slope = (curve.evaluate(inner + h, 0) - curve.evaluate(inner - h, 0)) / (2 * h)
    np.testing.assert_allclose(slope, curve.evaluate(inner, 1), rtol=1e-6, atol=1e-6)


def test_the_ends_of_each_kind_of_curve():
    c = curves()
    assert (c["trajectory"].start_time, c["trajectory"].end_time) == (0.0, 2.0)
    assert c["batch"].end_time == pytest.approx(max(c["batch"].durations), rel=0)
    assert c["flat output"].end_time == 20.0
    assert (c["line"].start_time, c["line"].end_time) == (0.0, 1.0)  # the parameter u


@pytest.mark.parametrize("path", [Line([0, 0, 0], [1, 2, 3]), Polyline([[0, 0], [1, 0], [1, 2]])])
def test_a_straight_path_has_no_second_or_higher_derivative(path):
    for order in (2, 3, 6):
        np.testing.assert_array_equal(path.evaluate([0.2, 0.7], order), np.zeros((2, 3)))
    with pytest.raises(tk.InvalidInputError, match="order must be a whole number >= 0 for a path"):
        path.evaluate([0.5], -1)


@pytest.mark.parametrize(
    "path",
    [Arc([0, 0, 0], [2, 0, 0], 1.5), Ellipse([1, 0, 0], 1.0, 0.5, turns=2, phase=0.3),
     FigureEight([0, 0, 1], 2.0, 1.0)],
    ids=["arc", "ellipse", "figure eight"],
)  # fmt: skip
def test_a_curved_path_has_every_derivative(path):
    assert_each_order_is_the_slope_of_the_one_below(path, np.linspace(0.1, 0.9, 5), 1e-6)


def assert_each_order_is_the_slope_of_the_one_below(curve, t, tolerance, highest=5):
    """Orders 1 to ``highest`` against central differences of the order below."""
    h = 1e-6
    for order in range(1, highest + 1):
        slope = (curve.evaluate(t + h, order - 1) - curve.evaluate(t - h, order - 1)) / (2 * h)
        exact = curve.evaluate(t, order)
        scale = np.max(np.abs(exact))
        np.testing.assert_allclose(exact, slope, rtol=0, atol=tolerance * scale)


def test_a_task_trajectory_at_a_constant_rate_on_an_arc_has_the_closed_form_jerk():
    # u = t / T on an arc of radius r sweeping A: the tool turns at w = A / T, and its
    # jerk is r w^3 (sin φ, -cos φ, 0) with φ = w t: to 1e-12.
    r, sweep, period = 2.0, 1.5, 3.0
    task = timed(Arc([0, 0, 0], [r, 0, 0], sweep), "linear", duration=period)
    t = np.linspace(0.0, period, 11)
    w = sweep / period
    phi = w * t
    zero = np.zeros_like(t)
    jerk = r * w**3 * np.stack([np.sin(phi), -np.cos(phi), zero], axis=1)
    np.testing.assert_allclose(task.jerk(t), jerk, rtol=0, atol=1e-12)
    snap = r * w**4 * np.stack([np.cos(phi), np.sin(phi), zero], axis=1)
    np.testing.assert_allclose(task.evaluate(t, 4), snap, rtol=0, atol=1e-12)


def test_a_task_trajectory_has_every_order_by_the_chain_rule():
    # A septic law on an ellipse: the law's fourth derivative is not zero, so every
    # Bell polynomial term counts.
    task = timed(Ellipse([0, 0, 0], 1.0, 0.5), "septic", duration=2.0)
    t = np.linspace(0.2, 1.8, 7)
    assert_each_order_is_the_slope_of_the_one_below(task, t, 1e-5)
    # On a line the jerk is the law's, along the line.
    line = timed(Line([0, 0, 0], [3, 4, 0]), "septic", duration=2.0)
    law = line.segments[0].law
    np.testing.assert_allclose(line.jerk(t), law.jerk(t) * [3, 4, 0], rtol=1e-15, atol=0)


def test_task_and_mobile_derivatives_are_their_states_in_the_world_frame():
    t = np.linspace(0.0, 4.0, 9)
    task = task_motion()
    state = task.state(t)
    for order, expected in enumerate((state.position, state.velocity, state.acceleration)):
        np.testing.assert_array_equal(task.evaluate(t, order), expected)
    plan = mobile_plan()
    t = np.linspace(0.0, plan.duration, 9)
    state = plan.state(t)
    np.testing.assert_array_equal(plan.evaluate(t), state.pose)
    velocity = plan.evaluate(t, 1)
    np.testing.assert_allclose(velocity[:, :2], state.world_velocity, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(velocity[:, 2], state.omega)
    # The flat output is the base's (x, y): the world acceleration is its second derivative.
    output = mobile.FigureEight(2.0, 1.0, 20.0)
    np.testing.assert_allclose(plan.evaluate(t, 2)[:, :2], output.evaluate(t, 2), atol=1e-12)


@pytest.mark.parametrize("name", ["task trajectory", "mobile trajectory"])
def test_a_number_gives_one_row_and_a_second_derivative_is_the_derivative_of_the_first(name):
    curve = curves()[name]
    assert curve.evaluate(1.0, 1).shape == (3,)
    np.testing.assert_array_equal(curve.evaluate(1.0, 2), curve.evaluate([1.0], 2)[0])
    h = 1e-6 * curve.duration
    inner = np.linspace(0.1, 0.9, 5) * curve.duration
    slope = (curve.evaluate(inner + h, 1) - curve.evaluate(inner - h, 1)) / (2 * h)
    np.testing.assert_allclose(slope, curve.evaluate(inner, 2), rtol=1e-6, atol=1e-6)


@pytest.mark.parametrize("order", [3, -1, 1.5, True])
def test_mobile_trajectories_refuse_orders_they_do_not_have(order):
    with pytest.raises(tk.InvalidInputError, match=r"order must be 0, 1 or 2 for a mobile traj"):
        curves()["mobile trajectory"].evaluate([0.5], order)


@pytest.mark.parametrize("order", [-1, 1.5, True, "2"])
def test_task_trajectories_refuse_what_is_not_an_order(order):
    with pytest.raises(tk.InvalidInputError, match="order must be a whole number >= 0 for a task"):
        task_motion().evaluate([0.5], order)


@pytest.mark.parametrize("name", ["trajectory", "flat output", "task trajectory"])
def test_every_timed_curve_samples_position_to_jerk_into_files(name, tmp_path):
    curve = curves()[name]
    samples = curve.sample(0.3)
    assert samples.t[0] == curve.start_time and samples.t[-1] == curve.end_time
    np.testing.assert_allclose(np.diff(samples.t)[:-1], 0.3, rtol=1e-12)
    for order, field in enumerate(("q", "qd", "qdd", "qddd")):
        np.testing.assert_array_equal(getattr(samples, field), curve.evaluate(samples.t, order))
    expected = {"trajectory": ("rad", ("q1", "q2")), "flat output": ("m", ("x", "y")),
                "task trajectory": ("m", ("x", "y", "z"))}[name]  # fmt: skip
    assert (samples.unit, samples.names) == expected
    back = tk.Samples.from_csv(samples.to_csv(tmp_path / "s.csv"))
    np.testing.assert_array_equal(back.qddd, samples.qddd)
    assert back.names == samples.names


@pytest.mark.parametrize(
    ("name", "message"),
    [
        ("line", r"a Line is a function of the path parameter u, not of time: time it first"),
        ("mobile trajectory", "position to jerk, and a MobileTrajectory has derivatives up to"),
        ("batch", r"holds 2 problems and Samples one: sample one of them, batch\[i\]"),
    ],
)
def test_sampling_what_samples_cannot_hold_is_refused_by_name(name, message):
    with pytest.raises(tk.InvalidInputError, match=message):
        curves()[name].sample(0.1)


class _Mixed(tk.Curve):
    """A curve in metres and radians, known to the protocol only."""

    end_time = 1.0
    components = (("x", "m"), ("heading", "rad"))

    def evaluate(self, t, order=0):
        t = np.atleast_1d(t)
        return np.stack([t**2 / 2, t], axis=1) if order == 0 else np.zeros((t.size, 2))


class _Unknown(_Mixed):
    components = (("a", ""), ("b", ""))


def test_a_curve_in_several_units_needs_the_unit_named():
    with pytest.raises(tk.InvalidInputError, match=r"in 'm', 'rad': give the position unit"):
        _Mixed().sample(0.5)
    with pytest.raises(tk.InvalidInputError, match=r"_Unknown's values is not known: give it"):
        _Unknown().sample(0.5)
    samples = _Mixed().sample(0.5, unit="mixed")
    assert samples.names == ("x", "heading") and samples.q[-1].tolist() == [0.5, 1.0]
    with pytest.raises(tk.InvalidInputError, match="sample_step must be > 0"):
        _Mixed().sample(0.0, unit="m")


@pytest.mark.parametrize("name", ["task trajectory", "mobile trajectory"])
def test_segmented_curves_hold_their_end_and_keep_their_breakpoints_read_only(name):
    curve = curves()[name]
    assert isinstance(curve, Segmented)
    np.testing.assert_array_equal(curve.breakpoints[[0, -1]], [0.0, curve.duration])
    with pytest.raises(ValueError, match="read-only"):
        curve.breakpoints[0] = 1.0
    # Past either end the end state holds (values; the world velocity of a base stops).
    np.testing.assert_array_equal(
        curve.evaluate([-1.0, 1e9]), curve.evaluate([0.0, curve.end_time])
    )
