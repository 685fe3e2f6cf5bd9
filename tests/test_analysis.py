"""Controller discretization error in task space (seed 001, task 4)."""

from __future__ import annotations

import numpy as np
import pytest

import trajkit as tk
from trajkit.analysis import DiscretizationError, discretization_error, quantized_duration
from trajkit.errors import InvalidInputError
from trajkit.kinematics import UR5, Planar2R

EXACT = 1e-12  # closed-form comparisons, relative to the arm's size


def constant_rate(rate: float, duration: float) -> tk.Trajectory:
    """Joint 1 turns at ``rate`` rad/s, joint 2 stays at 0: the tool runs on a circle."""
    return tk.Trajectory([0.0, duration], [[[rate, 0.0]], [[0.0, 0.0]]])


@pytest.mark.parametrize(
    ("duration", "period", "expected"),
    [(1.0, 0.25, 1.0), (1.1, 0.25, 1.25), (14.607142857142858, 0.002, 14.608), (0.001, 0.5, 0.5)],
)
def test_quantized_duration_rounds_up_to_whole_periods(duration, period, expected):
    assert quantized_duration(duration, period) == pytest.approx(expected, rel=EXACT)


def test_quantized_duration_keeps_a_whole_number_of_periods_despite_rounding():
    assert quantized_duration(0.3, 0.1) == pytest.approx(0.3, rel=EXACT)  # 0.3/0.1 = 2.9999...


def test_whole_number_of_periods_has_no_timing_error():
    arm = Planar2R(1.0, 0.5)
    result = discretization_error(arm, constant_rate(0.5, 2.0), 0.01)
    assert result.quantized_duration == pytest.approx(2.0, rel=EXACT)
    assert result.max_timing_error <= EXACT
    assert result.final_error <= EXACT
    assert result.t[0] == 0.0 and result.t[-1] == pytest.approx(2.0, rel=EXACT)


def test_zero_order_hold_error_is_the_chord_of_the_last_sub_sample():
    # The tool runs on a circle of radius R at rate w; holding q(kTs) for a period,
    # the largest gap inside it is the chord over (N-1)/N of a period.
    l1, l2, rate, period, oversample = 1.0, 0.5, 0.8, 0.05, 16
    arm = Planar2R(l1, l2)
    result = discretization_error(
        arm, constant_rate(rate, 1.0), period, oversample=oversample, hold="zero"
    )
    radius = l1 + l2
    chord = 2 * radius * np.sin(rate * period * (oversample - 1) / oversample / 2)
    moving = result.t < 1.0 - period  # the last period holds the end pose
    np.testing.assert_allclose(result.sampling_error[moving], chord, rtol=1e-9)
    assert result.max_sampling_error == pytest.approx(chord, rel=1e-9)


def test_linear_hold_of_a_linear_joint_motion_is_exact():
    arm = Planar2R(1.0, 0.5)
    result = discretization_error(arm, constant_rate(0.8, 1.0), 0.05, hold="linear")
    assert result.max_sampling_error <= EXACT


def test_seed001_quantized_trapezoid_on_a_six_joint_arm():
    qf = np.radians([90.0, 75.0, 60.0, 45.0, 30.0, 15.0])
    vmax = np.radians([7.0, 7.0, 7.0, 3.5, 3.5, 3.5])
    amax = np.radians([4.0, 4.0, 4.0, 2.0, 2.0, 2.0])
    planned = tk.trapezoidal(np.zeros(6), qf, vmax, amax, sync="phase")
    on_grid = tk.trapezoidal(np.zeros(6), qf, vmax, amax, sync="phase", period=0.002)
    result = discretization_error(UR5(), planned, 0.002, quantized=on_grid)
    assert isinstance(result, DiscretizationError)
    assert result.quantized_duration == pytest.approx(14.608, rel=EXACT)
    # Same end pose (the coursework's "no error"), but a small lag along the way.
    assert result.final_error <= 1e-12
    assert 0.0 < result.max_timing_error < 1e-3
    text = str(result)
    assert "14.608 s" in text and "timing error" in text and "sampling error" in text


def test_defaults_stretch_the_plan_uniformly():
    arm = Planar2R(1.0, 0.5)
    plan = tk.cubic([0.0, 0.0], [1.0, -0.5], 1.03)
    result = discretization_error(arm, plan, 0.1)
    assert result.quantized_duration == pytest.approx(1.1, rel=EXACT)
    assert result.final_error <= EXACT
    assert result.max_timing_error > 0.0


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"period": 0.0}, "period must be > 0"),
        ({"period": np.nan}, "period must be finite"),
        ({"period": 0.1, "hold": "cubic"}, "hold must be 'zero' or 'linear'"),
        ({"period": 0.1, "oversample": 1}, "oversample must be an integer >= 2"),
        ({"period": 0.1, "quantized": tk.cubic([0.0], [1.0], 1.0)}, "quantized must be"),
    ],
)
def test_bad_input(kwargs, message):
    with pytest.raises(InvalidInputError, match=message) as excinfo:
        discretization_error(Planar2R(1.0, 0.5), constant_rate(1.0, 1.0), **kwargs)
    assert type(excinfo.value) is InvalidInputError


def test_wrong_robot_or_joint_count():
    with pytest.raises(InvalidInputError, match="robot must be a trajkit SerialChain"):
        discretization_error("arm", constant_rate(1.0, 1.0), 0.1)  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match="trajectory must be a Trajectory with 6 joints"):
        discretization_error(UR5(), constant_rate(1.0, 1.0), 0.1)
