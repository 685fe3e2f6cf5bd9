"""Regression tests of the Python API's input checks (issue 16, "Python API").

Each test pins one way user input used to end in a raw numpy/Python exception,
or be read as something else, and asserts the documented error and its message
(the argument's public name, the value, the rule).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

import trajkit as tk
import trajkit.batch
import trajkit.taskspace as taskspace
from trajkit._validation import as_float_array, finite_array

RAGGED = [[1.0], [1.0, 2.0]]


# ------------------------------------------------------------------ ragged lists
@pytest.mark.parametrize(
    ("call", "name"),
    [
        (lambda: tk.cubic(RAGGED, 0.0, 1.0), "q0"),
        (lambda: tk.quintic(0.0, RAGGED, 1.0), "qf"),
        (lambda: tk.septic(0.0, 1.0, 1.0, v0=RAGGED), "v0"),
        (lambda: tk.cubic(0.0, 1.0, vmax=RAGGED), "vmax"),
        (lambda: tk.trapezoidal(RAGGED, 0.0, 1.0, 1.0), "q0"),
        (lambda: tk.scurve(0.0, RAGGED, 1.0, 1.0, 1.0), "qf"),
        (lambda: trajkit.batch.trapezoidal(RAGGED, 0.0, 1.0, 1.0), "q0"),
        (lambda: trajkit.batch.scurve([[0.0]], [[1.0]], 1.0, RAGGED, 1.0), "amax"),
        (lambda: tk.blended(RAGGED, 1.0, 1.0), "waypoints"),
        (lambda: tk.cubic_via([0.0, 1.0], RAGGED), "positions"),
        (lambda: tk.quintic_via(RAGGED, [0.0, 1.0]), "times"),
        (lambda: tk.cubic_spline([0.0, 1.0], [0.0, 1.0], v0=RAGGED), "v0"),
        (lambda: tk.Limits(velocity=RAGGED), "velocity"),
        (lambda: tk.Trajectory([0.0, 1.0], RAGGED), "coefficients"),
    ],
)
def test_ragged_sequences_are_refused_by_name(call: Any, name: str) -> None:
    # numpy's own "inhomogeneous shape" ValueError escaped from every planner.
    with pytest.raises(tk.InvalidInputError) as caught:
        call()
    message = str(caught.value)
    assert message.startswith(name)
    assert "rectangular array" in message and "ragged" in message
    assert "[[1.0], [1.0, 2.0]]" in message


# ------------------------------------------------------------------ choices given as arrays
@pytest.mark.parametrize(
    "call",
    [
        lambda: tk.trapezoidal(0.0, 1.0, 1.0, 1.0, sync=np.array([])),
        lambda: tk.scurve(0.0, 1.0, 1.0, 1.0, 1.0, sync=np.array(["time", "phase"])),
        lambda: trajkit.batch.trapezoidal([[0.0]], [[1.0]], 1.0, 1.0, sync=np.array([])),
    ],
)
def test_sync_given_as_an_array_is_refused_by_name(call: Any) -> None:
    # `sync not in (...)` compared the array elementwise: "truth value is ambiguous".
    expected = (
        r"^sync must be one of \('time', 'phase', 'time_if_necessary', 'none', None\) "
        r"or a sequence of them per joint, got array\("
    )
    with pytest.raises(tk.InvalidInputError, match=expected):
        call()


def test_bc_given_as_an_array_is_refused_by_name() -> None:
    with pytest.raises(
        tk.InvalidInputError,
        match=r"^bc must be 'clamped' or 'natural', got array\(\[0, 0\]\)",
    ):
        tk.cubic_spline([0.0, 1.0, 2.0], [0.0, 1.0, 0.0], bc=np.array([0, 0]))


@pytest.mark.parametrize("value", [np.array([]), np.array([True, False]), "no", 1, None])
@pytest.mark.parametrize(
    ("name", "call"),
    [
        ("through", lambda v: tk.blended([0.0, 1.0, 0.0], 1.0, 1.0, through=v)),
        ("allow_overshoot", lambda v: tk.trapezoidal(0.0, 1.0, 1.0, 1.0, allow_overshoot=v)),
    ],
)
def test_flags_given_as_non_booleans_are_refused_by_name(name: str, call: Any, value: Any) -> None:
    # `if through:` ended an empty array in "truth value is ambiguous" and read "no" as true.
    with pytest.raises(tk.InvalidInputError, match=rf"^{name} must be True or False, got "):
        call(value)
    assert call(np.bool_(True)).duration > 0.0


def test_profile_given_as_an_array_is_refused_by_name() -> None:
    with pytest.raises(tk.InvalidInputError, match=r"^profile must be one of \['linear', "):
        taskspace.path_law(np.array([1.0, 2.0]), duration=1.0)
    with pytest.raises(
        tk.InvalidInputError,
        match=r"^profile must be 'cubic', 'quintic', 'septic' or 'trapezoid', got array",
    ):
        taskspace.through_poses([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]], np.array([]), vmax=1.0)


# ------------------------------------------------------------------ what is not a number
@pytest.mark.parametrize(
    ("value", "shown", "problem"),
    [
        ("1.5", "'1.5'", "a string"),
        (b"1.5", "b'1.5'", "a string"),
        (True, "True", "a bool"),
        (np.True_, "np.True_", "a bool"),
        (np.array([True, False]), "array([ True, False])", "a bool array"),
        (1 + 0j, "(1+0j)", "complex"),
        (np.array([1.0 + 2.0j, 0.5 + 0.0j]), "array([1. +2.j, 0.5+0.j])", "complex"),
        (np.array(["1", "2"]), "array(['1', '2'], dtype='<U1')", "a string"),
    ],
)
def test_text_bools_and_complex_are_not_read_as_numbers(
    value: Any, shown: str, problem: str
) -> None:
    # numpy reads "1.5" as 1.5 and True as 1.0, and drops an imaginary part silently.
    with pytest.raises(tk.InvalidInputError) as caught:
        tk.cubic(value, 0.0, 1.0)
    assert str(caught.value) == f"q0 must be numeric, got {shown} ({problem})"


@pytest.mark.parametrize(
    ("value", "message"),
    [
        ([0.0, True], "qf must be numeric: qf[1] is True (a bool)"),
        ([0.0, None], "qf must be numeric: qf[1] is None"),
        ([0.0, "2"], "qf must be numeric: qf[1] is '2' (a string)"),
        ([0.0, 2j], "qf must be numeric: qf[1] is 2j (complex)"),
        (np.array([0.0, "a"], dtype=object), "qf must be numeric: qf[1] is 'a' (a string)"),
    ],
)
def test_a_bad_element_is_named_by_its_index(value: Any, message: str) -> None:
    # [0.0, True] used to be read as [0.0, 1.0]; [0.0, None] as "must be finite, got nan".
    with pytest.raises(tk.InvalidInputError) as caught:
        tk.cubic([0.0, 0.0], value, 1.0)
    assert str(caught.value) == message


def test_none_is_reported_as_missing_not_as_nan() -> None:
    with pytest.raises(tk.InvalidInputError) as caught:
        tk.cubic(None, 1.0, 1.0)
    assert str(caught.value) == "q0 is required: give a number or numbers, got None"
    assert "nan" not in str(caught.value)


def test_integers_beyond_float64_are_refused_by_name() -> None:
    with pytest.raises(tk.InvalidInputError, match=r"^duration must be within the float64 range"):
        tk.cubic(0.0, 1.0, 10**400)
    with pytest.raises(tk.InvalidInputError, match=r"^speed_bound must be within the float64"):
        taskspace.path_law("trapezoid", vmax=1.0, amax=1.0, speed_bound=10**400)


def test_real_numbers_of_every_numeric_dtype_are_accepted_unchanged() -> None:
    for value in (np.float32(0.5), np.int8(3), np.uint64(7), np.float16(0.25), 2, 0.5):
        assert as_float_array("x", value) == float(value)
    array = np.array([1, 2], dtype=np.int32)
    assert as_float_array("x", array).dtype == np.float64
    assert as_float_array("x", np.array([1.5, 2.0], dtype=object)).tolist() == [1.5, 2.0]
    reference = tk.cubic([0.0, 1.0], [1.0, 3.0], 2.0)
    converted = tk.cubic(np.array([0, 1], dtype=np.int64), np.array([1, 3], dtype=np.float32), 2)
    np.testing.assert_array_equal(converted.coefficients, reference.coefficients)


# ------------------------------------------------------------------ subnormals
def test_subnormals_are_kept_exactly() -> None:
    # Kept, not flushed: [0, 5e-324] are strictly increasing times, and stored
    # samples must round-trip bit for bit.
    assert finite_array("v0", [1e-320, -5e-324, 1.0]).tolist() == [1e-320, -5e-324, 1.0]
    trajectory = tk.Trajectory([5e-324, 1.0], [[0.0], [1.0]])
    assert trajectory.breakpoints.tolist() == [5e-324, 1.0]


@pytest.mark.parametrize(
    "planner",
    [
        lambda v0: tk.cubic(0.0, 1.0, 1.0, v0=v0),
        lambda v0: tk.cubic(0.0, 1.0, v0=v0, vmax=2.0),
        lambda v0: tk.quintic(0.0, 1.0, v0=v0, amax=2.0),
        lambda v0: tk.septic(0.0, 1.0, v0=v0, a0=v0, jmax=2.0),
        lambda v0: tk.trapezoidal(0.0, 1.0, 1.0, 2.0, v0=v0),
        lambda v0: tk.scurve(0.0, 1.0, 1.0, 2.0, 5.0, v0=v0),
    ],
)
def test_a_subnormal_boundary_velocity_plans_the_move_from_rest(planner: Any) -> None:
    # quintic(0, 1, v0=1e-320, amax=2) ended in numpy's LinAlgError ("Array must
    # not contain infs or NaNs"): the duration search's np.roots overflowed.
    with_subnormal, at_rest = planner(1e-320), planner(0.0)
    assert with_subnormal.velocity(0.0).tolist() == [1e-320]  # the exact boundary state
    # The minimum-duration search takes its non-rest branch: equal to rounding.
    assert abs(with_subnormal.duration - at_rest.duration) <= 4e-15 * at_rest.duration
    t = np.linspace(0.0, at_rest.duration, 21)
    np.testing.assert_allclose(with_subnormal.position(t), at_rest.position(t), rtol=0, atol=1e-14)


def test_a_subnormal_duration_is_refused_as_an_overflow() -> None:
    with pytest.raises(tk.InvalidInputError) as caught:
        tk.cubic(0.0, 1.0, 1e-320)
    assert str(caught.value) == (
        "cubic: the result overflows float64 (a coefficient or time beyond 1.8e308) for "
        "q0=0, v0=0, qf=1, vf=0, duration=9.99989e-321; use smaller values or longer times"
    )


# ------------------------------------------------------------------ overflow
@pytest.mark.parametrize(
    ("call", "shown"),
    [
        (lambda: tk.cubic(0.0, 1.0, 1e-300), "q0=0, v0=0, qf=1, vf=0, duration=1e-300"),
        (lambda: tk.cubic(1e308, -1e308, 1.0), "q0=1e+308, v0=0, qf=-1e+308, vf=0, duration=1"),
        (lambda: tk.quintic(0.0, 1e300, 1e-10), "qf=1e+300"),
        (lambda: tk.septic(0.0, 1.0, 1e-100), "duration=1e-100"),
    ],
)
def test_an_overflowing_polynomial_names_the_users_arguments(call: Any, shown: str) -> None:
    # Used to be "coefficients must be finite, got [[[-inf]] ...": an internal name.
    with pytest.raises(tk.InvalidInputError) as caught:
        call()
    message = str(caught.value)
    assert "overflows float64" in message and shown in message
    assert "coefficients must be finite" not in message


def test_topp_refuses_a_start_speed_whose_square_overflows() -> None:
    # speeds[0] ** 2 raised OverflowError (34, 'Numerical result out of range').
    path = tk.cubic(0.0, 1.0, 1.0)
    limits = tk.Limits(velocity=1.0, acceleration=1.0)
    with pytest.raises(tk.InvalidInputError) as caught:
        tk.topp(path, limits, start_speed=1e308)
    assert str(caught.value) == (
        "start_speed must be at most 1.341e+154 1/s (its square must be a finite float64), "
        "got 1e+308 1/s"
    )
    with pytest.raises(tk.InvalidInputError, match=r"^end_speed must be at most 1\.341e\+154"):
        tk.topp(path, limits, end_speed=1e200)


def test_topp_refuses_a_grid_too_fine_to_allocate() -> None:
    # grid=268434565 tried to allocate gigabytes before failing with MemoryError.
    path = tk.cubic(0.0, 1.0, 1.0)
    limits = tk.Limits(velocity=1.0, acceleration=1.0)
    with pytest.raises(tk.InvalidInputError) as caught:
        tk.topp(path, limits, grid=268_434_565)
    assert str(caught.value) == (
        "grid must be at most 100,000 intervals (each costs memory and time), got 268,434,565"
    )
    with pytest.raises(
        tk.InvalidInputError,
        match=(
            r"^grid must be a number of intervals or increasing points, got \[0\.0, True, 1\.0\]: "
            r"grid must be numeric: grid\[1\] is True"
        ),
    ):
        tk.topp(path, limits, grid=[0.0, True, 1.0])


# ------------------------------------------------------------------ limits
@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"velocity": []}, "velocity must be a number or one number per joint, got []"),
        ({"jerk": np.array([])}, "jerk must be a number or one number per joint, got []"),
        (
            {"acceleration": ([], [])},
            "acceleration lower bound must be a number or one number per joint, got []",
        ),
        (
            {"position": ([], 1.0)},
            "position lower bound must be a number or one number per joint, got []",
        ),
    ],
)
def test_empty_limits_are_refused(kwargs: dict[str, Any], message: str) -> None:
    # Limits(velocity=[]) was accepted and bounded nothing.
    with pytest.raises(tk.InvalidInputError) as caught:
        tk.Limits(**kwargs)
    assert str(caught.value) == message


def test_open_position_bounds_refuse_text_and_bools() -> None:
    # The open-range path converted with np.array(value, float): "1.5" and True passed.
    with pytest.raises(
        tk.InvalidInputError, match=r"^position upper bound must be numeric, got '1.5'"
    ):
        tk.Limits(position=(-np.inf, "1.5"))
    with pytest.raises(
        tk.InvalidInputError,
        match=r"^position lower bound must be numeric: position lower bound\[0\] is True",
    ):
        tk.Limits(position=([True, -1.0], np.inf))
    limits = tk.Limits(position=(-np.inf, [1.0, np.inf]))
    assert limits.position is not None
    assert limits.position.upper.tolist() == [1.0, np.inf]


# ------------------------------------------------------------------ polynomial options
def test_polynomial_refuses_continuity_and_degrees_that_are_not_sequences() -> None:
    conditions = [[(0, 0, 0.0), (1, 0, 0.5)], [(1, 0, 0.5), (3, 0, 1.0)]]
    with pytest.raises(tk.InvalidInputError, match=r"^continuity must be a sequence of sequences"):
        tk.polynomial(conditions, segments=[0.0, 1.0, 3.0], continuity=0.0, degrees=[2, 1])
    with pytest.raises(
        tk.InvalidInputError,
        match=r"^continuity\[0\] must be a sequence of derivative orders, got 1",
    ):
        tk.polynomial(conditions, segments=[0.0, 1.0, 3.0], continuity=[1], degrees=[2, 1])
    with pytest.raises(
        tk.InvalidInputError,
        match=r"^degrees must be a whole number >= 0 or one per segment \(2\), got 0\.0",
    ):
        tk.polynomial(conditions, segments=[0.0, 1.0, 3.0], continuity=[(1,)], degrees=0.0)


# ------------------------------------------------------------------ animate.arm
def test_animate_arm_draws_a_joint_space_plan(tmp_path: Any) -> None:
    # A JointSpacePlan (what taskspace.to_joint_space returns) raised AttributeError.
    from trajkit.kinematics import Spatial3R
    from trajkit.viz import animate

    robot = Spatial3R()
    motion = taskspace.timed(taskspace.Line([0, -12, 20], [10, 12, 20]), "cubic", duration=0.4)
    plan = taskspace.to_joint_space(robot, motion, ik_step=0.01)
    written = animate.arm(robot, plan, tmp_path / "plan.gif", fps=5, progress=False)
    assert written == tmp_path / "plan.gif"
    assert written.read_bytes()[:6] == b"GIF89a"


def test_animate_arm_refuses_what_is_not_a_joint_trajectory(tmp_path: Any) -> None:
    from trajkit.kinematics import Spatial3R
    from trajkit.viz import animate

    robot = Spatial3R()
    with pytest.raises(tk.InvalidInputError) as caught:
        animate.arm(robot, [0.0, 1.0], tmp_path / "x.gif")
    assert str(caught.value) == (
        "trajectory must be a trajkit Trajectory, a taskspace JointSpacePlan or a "
        "trajkit.sim.ArmLog, got list"
    )
    with pytest.raises(
        tk.InvalidInputError, match=r"^trajectory has 1 joints but the robot has 3$"
    ):
        animate.arm(robot, tk.cubic(0.0, 1.0, 1.0), tmp_path / "x.gif")
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize(
    ("call", "planner", "shown"),
    [
        (lambda: tk.cubic_via([0.0, 1e-300], [0.0, 1.0]), "cubic_via", "times=[0.e+000 1.e-300]"),
        (lambda: tk.quintic_via([0.0, 1.0, 2.0], [-1e308, 1e308, -1e308]), "quintic_via",
         "positions=[[-1.e+308] [ 1.e+308] [-1.e+308]]"),
        (lambda: tk.cubic_spline([0.0, 1.0, 2.0], [-1e308, 1e308, -1e308]), "cubic_spline",
         "positions=[[-1.e+308] [ 1.e+308] [-1.e+308]]"),
        (lambda: tk.cubic_spline([0.0, 1e-300, 1.0], [0.0, 1.0, 0.0]), "cubic_spline",
         "times=[0.e+000 1.e-300 1.e+000]"),
        (lambda: tk.trapezoidal(-1e308, 1e308, 1.0, 1.0), "trapezoidal",
         "q0=[-1.e+308], qf=[1.e+308]"),
        (lambda: tk.trapezoidal(0.0, 1e10, 1e-300, 1e-300), "trapezoidal",
         "vmax=1e-300, amax=1e-300"),
        (lambda: tk.scurve(-1e308, 1e308, 1.0, 1.0, 1.0), "scurve", "q0=[-1.e+308], qf=[1.e+308]"),
        (lambda: tk.topp(tk.cubic(0.0, 1.0, 1.0), tk.Limits(velocity=1e308, acceleration=1e308)),
         "topp", "velocity=[1.e+308], acceleration=[1.e+308], grid=500"),
        (lambda: tk.cubic(0.0, 1.0, 1.0).time_scaled(1e-300), "time_scaled", "factor=1e-300"),
    ],
)  # fmt: skip
def test_overflow_is_reported_in_the_users_terms(call: Any, planner: str, shown: str) -> None:
    # These ended in "coefficients must be finite" / "breakpoints must be finite"
    # (internal arrays), or scipy's bare ValueError "`dydx` must contain only finite values".
    with pytest.raises(tk.InvalidInputError) as caught:
        call()
    message = str(caught.value)
    assert message.startswith(f"{planner}: the result overflows float64")
    assert shown in message and "\n" not in message
