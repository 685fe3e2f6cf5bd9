"""Tests of trajkit.batch: many trapezoid problems planned at once.

The single-problem planner trajkit.trapezoidal is the reference: every batch result
(durations, plan info, evaluation) must equal planning the problems one by one, to
BATCH_RTOL (1e-12: the same closed forms, only vectorized differently).
"""

from __future__ import annotations

import re

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import trajkit as tk
from support import CLOSED_FORM

BATCH_RTOL = 1e-12  # relative: batch and one-by-one planning run the same closed forms
DT_MULTIPLE = 1e-9  # relative: a phase time counts as a whole multiple of dt
INFO_SHAPES = {  # key -> shape for B problems of ndof joints (plus trailing axes)
    "minimum_durations": lambda b, n: (b, n),
    "limiting_joint": lambda b, n: (b,),
    "phase_times": lambda b, n: (b, n, 3),
    "peak_velocity": lambda b, n: (b, n),
    "accelerations": lambda b, n: (b, n, 2),
}


def random_problems(rng, B, ndof, *, moving=True, asymmetric=False, still=0.2):
    """B problems: limits over two decades, some still joints, v0/vf within limits."""
    q0 = rng.uniform(-5.0, 5.0, (B, ndof))
    qf = rng.uniform(-5.0, 5.0, (B, ndof))
    qf = np.where(rng.random((B, ndof)) < still, q0, qf)
    vpos = 10.0 ** rng.uniform(-1.0, 1.0, (B, ndof))
    apos = 10.0 ** rng.uniform(-1.0, 1.0, (B, ndof))
    vneg = vpos * 10.0 ** rng.uniform(-0.5, 0.5, (B, ndof)) if asymmetric else vpos
    aneg = apos * 10.0 ** rng.uniform(-0.5, 0.5, (B, ndof)) if asymmetric else apos
    v0 = np.zeros((B, ndof))
    vf = np.zeros((B, ndof))
    if moving:
        v0 = np.where(rng.random((B, ndof)) < 0.3, 0.0, rng.uniform(-vneg, vpos))
        vf = np.where(rng.random((B, ndof)) < 0.3, 0.0, rng.uniform(-vneg, vpos))
    vmax = (-vneg, vpos) if asymmetric else vpos
    amax = (-aneg, apos) if asymmetric else apos
    return {"q0": q0, "qf": qf, "v0": v0, "vf": vf, "vmax": vmax, "amax": amax}


def pick(limit, i):
    """Problem i's limits from a (B, ndof) array or a tuple of them."""
    if isinstance(limit, tuple):
        return tuple(np.broadcast_to(side, np.shape(side))[i] for side in limit)
    return limit[i]


def plan_batch(p, **kwargs):
    return tk.batch.trapezoidal(
        p["q0"], p["qf"], p["vmax"], p["amax"], v0=p["v0"], vf=p["vf"], **kwargs
    )


def plan_one(p, i, **kwargs):
    return tk.trapezoidal(
        p["q0"][i], p["qf"][i], pick(p["vmax"], i), pick(p["amax"], i),
        v0=p["v0"][i], vf=p["vf"][i], **kwargs,
    )  # fmt: skip


def assert_relative(actual, expected, rtol, what):
    actual, expected = np.asarray(actual, float), np.asarray(expected, float)
    assert actual.shape == expected.shape, (what, actual.shape, expected.shape)
    error = np.abs(actual - expected) / np.maximum(1.0, np.abs(expected))
    assert np.all(error <= rtol), f"{what}: worst {error.max():.3g} > {rtol:g}"


# --------------------------------------------------------------------------- shapes
@pytest.mark.parametrize(("B", "ndof"), [(1, 1), (1, 6), (7, 1), (50, 3)])
def test_shapes(B, ndof):
    p = random_problems(np.random.default_rng(B * 10 + ndof), B, ndof, moving=False)
    plans = plan_batch(p)
    assert len(plans) == B
    assert plans.ndof == ndof
    assert repr(plans) == f"BatchTrajectory(problems={B}, ndof={ndof})"
    assert plans.durations.shape == (B,)
    assert plans.position(0.3).shape == (B, ndof)
    assert plans.velocity(np.float64(0.3)).shape == (B, ndof)
    t = np.linspace(0.0, 1.0, 5)
    for values in (plans.position(t), plans.velocity(t), plans.acceleration(t), plans.jerk(t)):
        assert values.shape == (B, 5, ndof)
    for key, shape in INFO_SHAPES.items():
        assert np.shape(plans.info[key]) == shape(B, ndof), key
    assert plans.info["planner"] == "trapezoidal"
    assert plans.info["sync"] == "time"
    assert plans.info["period"] is None


def test_trapezoid_jerk_is_zero():
    plans = tk.batch.trapezoidal([[0.0, 0.0], [1.0, -1.0]], [[1.0, 2.0], [0.0, 3.0]], 1.0, 1.0)
    t = np.linspace(-1.0, 10.0, 23)
    assert np.all(plans.jerk(t) == 0.0)
    assert np.all(plans.evaluate(t, 3) == 0.0)


# ----------------------------------------------- durations and plans equal one-by-one
CASES = {
    "rest, time": ({"moving": False}, {"sync": "time"}),
    "rest, none": ({"moving": False}, {"sync": None}),
    "rest, phase": ({"moving": False, "still": 0.0}, {"sync": "phase"}),
    "moving, time": ({}, {"sync": "time"}),
    "moving, none": ({}, {"sync": None}),
    "asymmetric, time": ({"asymmetric": True}, {"sync": "time"}),
    "asymmetric rest, phase": ({"asymmetric": True, "moving": False, "still": 0.0},
                               {"sync": "phase"}),
    "rest, time, dt": ({"moving": False}, {"sync": "time", "period": 0.01}),
    "rest, none, dt": ({"moving": False}, {"sync": None, "period": 0.002}),
    "rest, phase, dt": ({"moving": False, "still": 0.0}, {"sync": "phase", "period": 0.005}),
}  # fmt: skip


@pytest.mark.parametrize("case", list(CASES))
def test_durations_and_plans_equal_planning_one_by_one(case):
    draw, kwargs = CASES[case]
    rng = np.random.default_rng(sum(map(ord, case)))
    p = random_problems(rng, 40, 4, **draw)
    plans = plan_batch(p, **kwargs)
    for i in range(40):
        one = plan_one(p, i, **kwargs)
        assert_relative(plans.durations[i], one.duration, BATCH_RTOL, f"duration {i}")
        assert_relative(
            plans.info["minimum_durations"][i], one.info["minimum_durations"], BATCH_RTOL,
            f"minimum durations {i}",
        )  # fmt: skip
        assert_relative(
            plans.info["phase_times"][i], one.info["phase_times"], 1e-9, f"phase times {i}"
        )
        limiting = one.info["limiting_joint"]
        assert plans.info["limiting_joint"][i] == (-1 if limiting is None else limiting)
    if "period" in kwargs:
        dt = kwargs["period"]
        for values in (plans.durations, plans.info["phase_times"]):
            steps = np.round(values / dt)
            assert np.all(np.abs(values - steps * dt) <= DT_MULTIPLE * np.maximum(values, dt))
    if kwargs["sync"] == "phase":
        phases = plans.info["phase_times"]
        assert np.all(phases == phases[:, :1, :])  # one time law per problem


# ------------------------------------------------------------- evaluation one-by-one
@pytest.mark.parametrize("case", ["rest, time", "moving, time", "moving, none", "rest, phase"])
def test_evaluation_equals_the_single_trajectories(case):
    draw, kwargs = CASES[case]
    rng = np.random.default_rng(3 + len(case))
    p = random_problems(rng, 25, 3, **draw)
    plans = plan_batch(p, **kwargs)
    # Array times from before the start to just before the longest end, and scalars.
    t = np.concatenate([[-1.0, 0.0], np.linspace(0.0, plans.durations.min() * 0.999, 40)])
    for name in ("position", "velocity", "acceleration"):
        batch_values = getattr(plans, name)(t)
        for i in range(25):
            single = getattr(plans[i], name)(t)
            assert_relative(batch_values[i], single, BATCH_RTOL, f"{name} of problem {i}")
            for scalar in (0.0, 0.37 * plans.durations[i], 0.999 * plans.durations[i]):
                assert_relative(
                    getattr(plans, name)(scalar)[i], getattr(plans[i], name)(scalar),
                    BATCH_RTOL, f"{name}({scalar}) of problem {i}",
                )  # fmt: skip
    # Each problem's own trajectory from the batch is the single planner's trajectory.
    for i in range(25):
        one = plan_one(p, i, **kwargs)
        times = np.linspace(0.0, one.duration, 31)
        assert_relative(plans[i].position(times), one.position(times), BATCH_RTOL, f"q {i}")


def test_positions_and_velocities_are_held_after_the_end():
    p = random_problems(np.random.default_rng(11), 10, 3)
    plans = plan_batch(p)
    for i in range(10):
        T = plans.durations[i]
        late = np.array([T, T + 1.0, T + 100.0])
        for name in ("position", "velocity"):
            values = getattr(plans, name)(late)[i]
            assert_relative(values, getattr(plans[i], name)(late), BATCH_RTOL, name)
            assert_relative(values, np.broadcast_to(values[0], values.shape), BATCH_RTOL, name)
        assert_relative(plans.position(T)[i], p["qf"][i], CLOSED_FORM, "end position")
        assert_relative(plans.velocity(T)[i], p["vf"][i], CLOSED_FORM, "end velocity")


def test_acceleration_at_and_after_the_end_equals_the_single_trajectory():
    # Both hold the end state, acceleration included (the batch once gave 0 here).
    plans = tk.batch.trapezoidal([[0.0]], [[1.0]], 1.0, 1.0)
    for t in (2.0, 5.0):
        assert plans.acceleration(t)[0] == pytest.approx(plans[0].acceleration(t))
    p = random_problems(np.random.default_rng(12), 10, 3, moving=False)
    plans = plan_batch(p)
    late = plans.durations.max() + np.array([0.0, 1.0])
    for i in range(10):
        T = plans.durations[i]
        for t in (T, T + 1.0):
            assert_relative(plans.acceleration(t)[i], plans[i].acceleration(t), BATCH_RTOL, "a")
        assert_relative(plans.acceleration(late)[i], plans[i].acceleration(late), BATCH_RTOL, "a")


# ----------------------------------------------------------------------------- indexing
def test_indexing():
    p = random_problems(np.random.default_rng(5), 6, 2)
    plans = plan_batch(p)
    for i in range(6):
        one = plans[i]
        assert isinstance(one, tk.Trajectory)
        assert one.ndof == 2
        assert one.duration == pytest.approx(plans.durations[i], rel=BATCH_RTOL)
        assert one.info["limiting_joint"] == int(plans.info["limiting_joint"][i])
        assert np.array(one.info["phase_times"]) == pytest.approx(plans.info["phase_times"][i])
        assert np.array_equal(plans[i - 6].coefficients, one.coefficients)  # negative index
    assert np.array_equal(plans[np.int64(2)].coefficients, plans[2].coefficients)
    assert np.array_equal(plans[-1].breakpoints, plans[5].breakpoints)


@pytest.mark.parametrize("index", [6, 100, -7])
def test_index_out_of_range(index):
    plans = plan_batch(random_problems(np.random.default_rng(5), 6, 2))
    with pytest.raises(IndexError, match=f"problem {index} out of range for 6 problems"):
        plans[index]


@pytest.mark.parametrize("index", [1.0, True, "0", slice(0, 2), None, [0]])
def test_index_of_the_wrong_type(index):
    plans = plan_batch(random_problems(np.random.default_rng(5), 6, 2))
    with pytest.raises(tk.InvalidInputError, match="index must be an integer"):
        plans[index]


# --------------------------------------------------------------------- broadcasting
B, NDOF = 5, 3


def broadcast_reference(q0, qf, vmax_i, amax_i, **kwargs):
    """Durations from the single planner, problem by problem, limits given per problem."""
    return np.array(
        [tk.trapezoidal(q0[i], qf[i], vmax_i(i), amax_i(i), **kwargs).duration for i in range(B)]
    )


@pytest.fixture
def positions():
    rng = np.random.default_rng(9)
    return rng.uniform(-3, 3, (B, NDOF)), rng.uniform(-3, 3, (B, NDOF))


def test_scalar_limits(positions):
    q0, qf = positions
    plans = tk.batch.trapezoidal(q0, qf, 1.5, 0.5)
    expected = broadcast_reference(q0, qf, lambda i: 1.5, lambda i: 0.5)
    assert_relative(plans.durations, expected, BATCH_RTOL, "durations")


def test_per_joint_limits(positions):
    q0, qf = positions
    vmax, amax = np.array([1.0, 2.0, 0.5]), np.array([0.3, 3.0, 1.0])
    plans = tk.batch.trapezoidal(q0, qf, vmax, amax)
    expected = broadcast_reference(q0, qf, lambda i: vmax, lambda i: amax)
    assert_relative(plans.durations, expected, BATCH_RTOL, "durations")


def test_per_problem_limits(positions):
    q0, qf = positions
    rng = np.random.default_rng(1)
    vmax, amax = rng.uniform(0.5, 2, (B, NDOF)), rng.uniform(0.5, 2, (B, NDOF))
    plans = tk.batch.trapezoidal(q0, qf, vmax, amax)
    expected = broadcast_reference(q0, qf, lambda i: vmax[i], lambda i: amax[i])
    assert_relative(plans.durations, expected, BATCH_RTOL, "durations")


def test_per_problem_column_limits(positions):
    q0, qf = positions
    vmax = np.array([[0.5], [1.0], [1.5], [2.0], [2.5]])  # (B, 1): one per problem
    plans = tk.batch.trapezoidal(q0, qf, vmax, 1.0)
    expected = broadcast_reference(q0, qf, lambda i: vmax[i, 0], lambda i: 1.0)
    assert_relative(plans.durations, expected, BATCH_RTOL, "durations")


def test_tuple_limits_mixing_shapes(positions):
    q0, qf = positions
    lower = np.array([-1.0, -0.5, -2.0])  # (ndof,)
    upper = np.random.default_rng(2).uniform(0.5, 3.0, (B, NDOF))  # (B, ndof)
    plans = tk.batch.trapezoidal(q0, qf, (lower, upper), (-0.5, 2.0), sync=None)
    expected = broadcast_reference(
        q0, qf, lambda i: (lower, upper[i]), lambda i: (-0.5, 2.0), sync=None
    )
    assert_relative(plans.durations, expected, BATCH_RTOL, "durations")
    for i in range(B):
        limits = tk.Limits(velocity=(lower, upper[i]), acceleration=(-0.5, 2.0))
        assert plans[i].check(limits).ok


def test_positions_broadcast_too(positions):
    q0, qf = positions
    plans = tk.batch.trapezoidal(q0[0], qf, 1.0, 1.0, v0=0.0)  # q0 shared by all problems
    expected = [tk.trapezoidal(q0[0], qf[i], 1.0, 1.0).duration for i in range(B)]
    assert_relative(plans.durations, expected, BATCH_RTOL, "durations")
    assert_relative(plans.position(0.0), np.broadcast_to(q0[0], (B, NDOF)), 0.0, "start")


@given(
    seed=st.integers(0, 2**32 - 1),
    B=st.integers(1, 8),
    ndof=st.integers(1, 5),
    sync=st.sampled_from(["time", None]),
    moving=st.booleans(),
    asymmetric=st.booleans(),
)
def test_property_batch_equals_one_by_one(seed, B, ndof, sync, moving, asymmetric):
    p = random_problems(np.random.default_rng(seed), B, ndof, moving=moving, asymmetric=asymmetric)
    plans = plan_batch(p, sync=sync)
    expected = [plan_one(p, i, sync=sync).duration for i in range(B)]
    assert_relative(plans.durations, expected, BATCH_RTOL, "durations")


def test_acceleration_after_a_zero_length_last_phase():
    # At t >= duration the batch once evaluated the last phase begun, even an empty one:
    # a pure coast reported its empty fall phase's acceleration (+1) instead of 0.
    one = np.ones((1, 1))
    # Coast at 2 rad/s for 1 s: rise and fall take 0 s (their accelerations are -1, +1).
    plans = tk.batch.trapezoidal([[0.0]], [[2.0]], 2 * one, one, v0=[[2.0]], vf=[[2.0]])
    assert plans.durations == pytest.approx([1.0], rel=CLOSED_FORM)
    t = np.array([0.5, 1.0, 2.0])
    assert np.all(plans[0].acceleration(t) == 0.0)
    assert np.all(plans.acceleration(t) == 0.0)


def test_phase_sync_with_a_still_joint():
    limits = np.ones((1, 2))
    plans = tk.batch.trapezoidal([[0.0, 0.0]], [[1.0, 0.0]], limits, limits, sync="phase")
    assert plans.durations == pytest.approx([2.0], rel=CLOSED_FORM)
    assert np.all(plans.position(np.linspace(0.0, 2.0, 9))[0, :, 1] == 0.0)


# ------------------------------------------------ limits that are not (B, ndof) arrays
# Shared scalar, per-joint and tuple limits once reached the general solver unbroadcast
# and failed in its np.concatenate (moving boundaries, sync="phase").
LIMIT_SHAPES = {
    "scalar": (lambda B, n: 1.5, lambda B, n: 0.75),
    "per joint": (lambda B, n: np.linspace(1.0, 2.0, n), lambda B, n: np.linspace(0.5, 1.0, n)),
    "tuple": (lambda B, n: (-1.0, 2.0), lambda B, n: (-0.5, 1.0)),
}


@pytest.mark.parametrize("shape", list(LIMIT_SHAPES))
def test_moving_boundaries_with_shared_limits(shape):
    vmax_of, amax_of = LIMIT_SHAPES[shape]
    p = random_problems(np.random.default_rng(4), 6, 3, still=0.0)
    p["vmax"], p["amax"] = vmax_of(6, 3), amax_of(6, 3)
    p["v0"], p["vf"] = np.full((6, 3), 0.25), np.zeros((6, 3))
    plans = plan_batch(p)
    for i in range(6):
        one = tk.trapezoidal(p["q0"][i], p["qf"][i], p["vmax"], p["amax"], v0=0.25)
        assert_relative(plans.durations[i], one.duration, BATCH_RTOL, f"duration {i}")


@pytest.mark.parametrize("shape", list(LIMIT_SHAPES))
def test_phase_sync_with_shared_limits(shape):
    vmax_of, amax_of = LIMIT_SHAPES[shape]
    p = random_problems(np.random.default_rng(4), 6, 3, moving=False, still=0.0)
    plans = tk.batch.trapezoidal(p["q0"], p["qf"], vmax_of(6, 3), amax_of(6, 3), sync="phase")
    for i in range(6):
        one = tk.trapezoidal(p["q0"][i], p["qf"][i], vmax_of(6, 3), amax_of(6, 3), sync="phase")
        assert_relative(plans.durations[i], one.duration, BATCH_RTOL, f"duration {i}")


@pytest.mark.parametrize("shape", list(LIMIT_SHAPES))
@pytest.mark.parametrize("sync", ["time", None])
def test_rest_to_rest_with_shared_limits(shape, sync):
    vmax_of, amax_of = LIMIT_SHAPES[shape]
    p = random_problems(np.random.default_rng(4), 6, 3, moving=False)
    plans = tk.batch.trapezoidal(p["q0"], p["qf"], vmax_of(6, 3), amax_of(6, 3), sync=sync)
    for i in range(6):
        one = tk.trapezoidal(p["q0"][i], p["qf"][i], vmax_of(6, 3), amax_of(6, 3), sync=sync)
        assert_relative(plans.durations[i], one.duration, BATCH_RTOL, f"duration {i}")


# ---------------------------------------------------------------------------- bad input
GOOD = {"q0": np.zeros((2, 3)), "qf": np.ones((2, 3)), "vmax": 1.0, "amax": 1.0}
INVALID = [
    ({"q0": np.zeros(3), "qf": np.ones(3)}, "shape (B, ndof) with B, ndof >= 1, got (3,)"),
    ({"q0": 0.0, "qf": 1.0}, "problems must have shape (B, ndof)"),
    ({"q0": np.zeros((2, 2, 2)), "qf": 0.0}, "q0 must have shape (B, ndof) or broadcast to it"),
    ({"qf": np.ones((3, 3))}, "q0, qf, v0, vf, a0, af must broadcast to one (B, ndof) shape"),
    ({"v0": np.zeros((2, 2))}, "got q0 (2, 3), qf (2, 3), v0 (2, 2)"),
    ({"q0": np.zeros((0, 3)), "qf": np.ones((0, 3))}, "with B, ndof >= 1, got (0, 3)"),
    ({"q0": np.full((2, 3), np.nan)}, "q0 must be finite"),
    ({"vmax": np.ones(2)}, "vmax must broadcast to the problems' shape (2, 3), got (2,)"),
    ({"amax": np.ones((3, 3))}, "amax must broadcast to the problems' shape (2, 3)"),
    ({"vmax": 0.0}, "vmax must allow motion both ways"),
    ({"amax": -1.0}, "amax must allow motion both ways"),
    ({"vmax": np.array([1.0, 0.0, 1.0])}, "vmax must allow motion both ways"),
    ({"vmax": (1.0, 2.0)}, "vmax must allow motion both ways"),
    ({"amax": (-1.0, 0.0)}, "amax must allow motion both ways"),
    ({"vmax": (-1.0, 1.0, 2.0)}, "vmax given as a tuple must be (lower, upper)"),
    ({"vmax": None}, "vmax is required"),
    ({"amax": float("inf")}, "amax must be finite"),
    ({"sync": "phases"},
     "sync must be 'time', 'phase', 'time_if_necessary', 'none' or None, got 'phases'"),
    ({"period": 0.0}, "period must be > 0"),
    ({"period": -1.0}, "period must be > 0"),
]  # fmt: skip


@pytest.mark.parametrize(("change", "fragment"), INVALID)
def test_invalid_input(change, fragment):
    with pytest.raises(tk.InvalidInputError) as info:
        tk.batch.trapezoidal(**{**GOOD, **change})
    assert fragment in str(info.value)


def test_target_velocity_beyond_the_limit_names_problem_and_joint():
    vf = np.zeros((2, 3))
    vf[1, 2] = 1.5
    with pytest.raises(tk.InfeasibleError, match=r"problem 1: vf=1\.5 rad/s .*\(joint 3\)"):
        tk.batch.trapezoidal(**GOOD, vf=vf)


def test_a_start_beyond_the_limit_is_braked_as_the_single_planner_brakes_it():
    v0 = np.zeros((2, 3))
    v0[1, 2] = 1.5
    plans = tk.batch.trapezoidal(**GOOD, v0=v0)
    single = tk.trapezoidal(GOOD["q0"][1], GOOD["qf"][1], 1.0, 1.0, v0=v0[1])
    assert plans.durations[1] == pytest.approx(single.duration, rel=1e-12)
    np.testing.assert_allclose(plans.position(single.duration)[1], [1.0, 1.0, 1.0], atol=1e-12)


@pytest.mark.parametrize(
    ("call", "fragment"),
    [
        (lambda p: p.evaluate(0.5, 4), "order must be 0, 1, 2 or 3, got 4"),
        (lambda p: p.evaluate(0.5, True), "order must be 0, 1, 2 or 3, got True"),
        (lambda p: p.position(np.zeros((2, 2))), "t must be a number or a 1-D array"),
        (lambda p: p.position(np.nan), "t must be finite"),
    ],
)
def test_invalid_evaluation(call, fragment):
    plans = tk.batch.trapezoidal(**GOOD)
    with pytest.raises(tk.InvalidInputError, match=re.escape(fragment)):
        call(plans)


@pytest.mark.parametrize("planner", ["trapezoidal", "scurve"])
def test_batch_evaluation_from_the_end_time_on_is_the_exact_end_state(planner) -> None:
    # Issue 16 item 6: with amax = 1e6 the phases' rounded sums leave |v(T)| ~ 1e-10
    # (either sign); the batch must give the planned end state, as batch[i] does.
    q0 = np.zeros((3, 2))
    qf = np.array([[1.0, 2.0], [0.3, -1.1], [-2.0, 0.7]])
    limits = {"vmax": 1.0, "amax": 1e6}
    if planner == "scurve":
        limits["jmax"] = 1e9
    plans = getattr(tk.batch, planner)(q0, qf, **limits)
    after = np.array([plans.durations.max(), plans.durations.max() + 1.0])
    # A trapezoid names no end acceleration: its last phase's -amax holds (as batch[i]).
    for order in (0, 1, 2) if planner == "scurve" else (0, 1):
        values = plans.evaluate(after, order)  # (B, 2, ndof)
        target = qf[:, np.newaxis, :] if order == 0 else np.zeros(1)
        np.testing.assert_array_equal(values, np.broadcast_to(target, values.shape))
        for i in range(len(plans)):
            np.testing.assert_array_equal(plans.evaluate(plans.durations[i], order)[i],
                                          plans[i].evaluate(plans[i].end_time, order))  # fmt: skip
    assert not np.signbit(plans.velocity(plans.durations.max())).any()


@pytest.mark.parametrize("planner", ["trapezoidal", "scurve"])
def test_grid_duration_puts_only_the_durations_on_the_period_grid(planner):
    rng = np.random.default_rng(5)
    q0, qf = rng.uniform(-2.0, 2.0, (2, 40, 3))
    v0 = rng.uniform(-0.4, 0.4, (40, 3))
    limits = (1.0, 2.0) if planner == "trapezoidal" else (1.0, 2.0, 10.0)
    plans = getattr(tk.batch, planner)(q0, qf, *limits, v0=v0, period=0.01, grid="duration")
    for i in (0, 17, 39):
        alone = getattr(tk, planner)(q0[i], qf[i], *limits, v0=v0[i], period=0.01, grid="duration")
        assert plans.durations[i] == pytest.approx(alone.duration, rel=CLOSED_FORM)
    steps = plans.durations / 0.01
    np.testing.assert_allclose(steps, np.round(steps), rtol=0, atol=1e-9 * steps.max())
    with pytest.raises(tk.InvalidInputError, match=r"^grid must be 'switches' or 'duration'"):
        getattr(tk.batch, planner)(q0, qf, *limits, period=0.01, grid="phases")


def test_a_batch_of_one_problem_runs_the_kernel_already_compiled() -> None:
    # The sync codes of one problem were a read-only broadcast view: the batch kernel
    # compiled a second copy for it (about a minute) on the first one-problem batch.
    from trajkit.profiles import engine

    kernel = engine.kernels().batch
    if not hasattr(kernel, "signatures"):
        pytest.skip("numba's JIT is disabled")
    for count in (3, 1):
        plans = tk.batch.scurve(np.zeros((count, 2)), np.ones((count, 2)), 1.0, 2.0, 10.0)
        assert plans.durations.shape == (count,)
        tk.batch.velocity_change(np.zeros((count, 2)), 1.0, 2.0, 10.0)
    assert len(kernel.signatures) == 1, kernel.signatures


def test_a_problem_too_long_for_absolute_time_is_refused_as_alone_and_evaluates_to_nan():
    """Found by a randomized hypothesis run: a 1.8e5 s move on a period grid whose pieces
    miss the target beyond rounding. Alone it is refused; in a batch its row is refused
    the same way and its values are NaN, never the unwritten memory they once were."""
    q0, qf = np.zeros((2, 2)), np.array([[0.0, 0.0], [0.5, 0.3]])
    v0, vf = np.array([[-73.0, 0.0], [0.0, 0.0]]), np.array([[0.01, 0.01], [0.0, 0.0]])
    vmax = (np.array([-73.0, -73.0]), np.array([0.01, 0.01]))
    amax = (np.array([-1.0, -1.0]), np.array([1.5, 1.0]))
    kw = {"sync": None, "period": 0.002}
    with pytest.raises(tk.InfeasibleError, match="too long to keep its short phases") as alone:
        tk.trapezoidal(q0[0], qf[0], vmax, amax, v0=v0[0], vf=vf[0], **kw)
    plans = tk.batch.trapezoidal(q0, qf, vmax, amax, v0=v0, vf=vf, **kw)
    with pytest.raises(tk.InfeasibleError, match=r"miss its target in problem 0;"):
        plans[0]
    assert "177682 s" in str(alone.value)
    values = plans.evaluate(np.array([0.0, 1.0, 60.0]), 1)
    assert np.isnan(values[0]).all()
    single = tk.trapezoidal(q0[1], qf[1], vmax, amax, v0=v0[1], vf=vf[1], **kw)
    np.testing.assert_array_equal(values[1], single.velocity(np.array([0.0, 1.0, 60.0])))
