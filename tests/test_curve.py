"""One protocol for every curve: evaluate(t, order) on [start_time, end_time]."""

from __future__ import annotations

import numpy as np
import pytest

import trajkit as tk
from trajkit import batch, mobile
from trajkit.taskspace import Ellipse, Line


def curves() -> dict[str, tk.Curve]:
    return {
        "trajectory": tk.quintic([0.0, 1.0], [1.0, -1.0], 2.0),
        "batch": batch.trapezoidal([[0.0], [0.0]], [[1.0], [2.0]], 1.0, 2.0),
        "flat output": mobile.FigureEight(2.0, 1.0, 20.0),
        "line": Line([0.0, 0.0, 0.0], [1.0, 2.0, 3.0]),
        "ellipse": Ellipse([0.0, 0.0, 0.0], 1.0, 0.5),
    }


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
