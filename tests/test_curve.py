"""One protocol for every curve: evaluate(t, order) on [start_time, end_time]."""

from __future__ import annotations

import numpy as np
import pytest

import trajkit as tk
from trajkit import batch, mobile
from trajkit.taskspace import Ellipse, Line, timed


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


def test_a_path_has_no_third_derivative_and_says_so():
    with pytest.raises(tk.InvalidInputError, match="order must be 0, 1 or 2, got 3"):
        curves()["line"].jerk([0.5])


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


@pytest.mark.parametrize("name", ["task trajectory", "mobile trajectory"])
@pytest.mark.parametrize("order", [3, -1, 1.5, True])
def test_task_and_mobile_trajectories_refuse_orders_they_do_not_have(name, order):
    with pytest.raises(tk.InvalidInputError, match=r"order must be 0, 1 or 2 for a .* trajectory"):
        curves()[name].evaluate([0.5], order)
