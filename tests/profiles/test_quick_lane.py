"""The single planners' short road (one compiled call) against their full road.

``tk.scurve`` and ``tk.trapezoidal`` with default options plan plainly numeric
input in one compiled call (:func:`trajkit.profiles.limited.quick_trajectory`);
anything unusual takes the full road, which validates, plans and explains. Both
must give the same trajectory and the same ``info``, and every kind of input the
short road hands back must still plan correctly.
"""

import numpy as np
import pytest

import trajkit as tk
from trajkit.errors import InfeasibleError, InvalidInputError
from trajkit.profiles import limited

Q0 = np.array([0.0, 0.5, -1.0])
QF = np.array([1.0, -1.0, 2.0])
LIMITS = (np.array([1.0, 2.0, 1.5]), np.array([2.0, 3.0, 4.0]), np.array([10.0, 20.0, 30.0]))


def full_road(planner, q0, qf, **options):
    # A min_duration far below the plan's takes the full road and changes nothing.
    return planner(q0, qf, *options.pop("limits"), min_duration=1e-9, **options)


@pytest.mark.parametrize(
    "options",
    [
        {},
        {"v0": [0.3, -0.2, 0.0], "vf": [0.1, 0.0, -0.5]},
        {"a0": [1.0, 0.0, -2.0], "sync": None},
        {"sync": "time_if_necessary"},
    ],
)
def test_the_short_road_plans_as_the_full_one(options):
    short = tk.scurve(Q0, QF, *LIMITS, **options)
    full = full_road(tk.scurve, Q0, QF, limits=LIMITS, **options)
    assert short.duration == full.duration
    np.testing.assert_array_equal(short.breakpoints, full.breakpoints)
    np.testing.assert_array_equal(short.coefficients, full.coefficients)
    assert dict(short.info) == dict(full.info)


def test_the_trapezoid_short_road_plans_as_the_full_one():
    short = tk.trapezoidal(Q0, QF, *LIMITS[:2], v0=[0.2, 0.0, 0.0])
    full = full_road(tk.trapezoidal, Q0, QF, limits=LIMITS[:2], v0=[0.2, 0.0, 0.0])
    np.testing.assert_array_equal(short.coefficients, full.coefficients)
    assert dict(short.info) == dict(full.info)


def readonly(x):
    x = np.array(x, dtype=float)
    x.setflags(write=False)
    return x


@pytest.mark.parametrize(
    "convert",
    [
        readonly,
        lambda x: np.repeat(np.asarray(x, dtype=float), 2)[::2],  # strided
        lambda x: [float(v) for v in x],
        lambda x: [round(float(v)) for v in x],
        lambda x: np.asarray(x, dtype=np.float32),
        lambda x: np.asarray(x, dtype=float).astype(">f8"),  # other byte order
    ],
)
def test_inputs_the_short_road_hands_back_plan_the_same(convert):
    q0, qf, limits = convert(Q0), convert(QF), [convert(x) for x in LIMITS]
    plain = [np.array(x, dtype=float) for x in limits]
    expected = full_road(
        tk.scurve, np.asarray(q0, dtype=float), np.asarray(qf, dtype=float), limits=plain
    )
    got = tk.scurve(q0, qf, *limits)
    assert got.duration == pytest.approx(expected.duration, rel=1e-15)
    np.testing.assert_allclose(got.position(got.duration), np.asarray(qf, dtype=float), 1e-12)


def test_a_read_only_vector_leaves_the_short_road_compiled_once():
    tk.scurve(readonly(Q0), QF, *LIMITS)
    kernel = limited._quick
    assert kernel is not None
    if hasattr(kernel, "signatures"):
        assert len(kernel.signatures) == 1


@pytest.mark.parametrize(
    ("q0", "error", "match"),
    [
        ([0.0, np.nan, 0.0], InvalidInputError, "q0"),
        ([0.0, 0.0], InvalidInputError, "3"),
        ([True, 0.0, 0.0], InvalidInputError, "q0"),
    ],
)
def test_bad_input_on_the_short_road_is_explained(q0, error, match):
    with pytest.raises(error, match=match):
        tk.scurve(q0, QF, *LIMITS)


def test_an_unreachable_target_on_the_short_road_is_refused_by_name():
    with pytest.raises(InfeasibleError, match="vf"):
        tk.scurve(Q0, QF, *LIMITS, vf=[5.0, 0.0, 0.0])


def test_the_short_road_returns_none_for_what_it_does_not_take():
    assert (
        limited.quick_trajectory(
            "scurve", Q0, QF, *LIMITS, v0=0.0, vf=0.0, a0=0.0, af=0.0, sync=["time"] * 3
        )
        is None
    )
    assert (
        limited.quick_trajectory(
            "scurve", "0", QF, *LIMITS, v0=0.0, vf=0.0, a0=0.0, af=0.0, sync="time"
        )
        is None
    )


@pytest.mark.parametrize("planner", [tk.scurve, tk.trapezoidal])
def test_an_unknown_grid_is_refused_on_either_road(planner):
    # Without dt the grid changes nothing, but a misspelt one is still refused.
    limits = LIMITS if planner is tk.scurve else LIMITS[:2]
    with pytest.raises(InvalidInputError, match="grid"):
        planner(Q0, QF, *limits, grid="switch")
