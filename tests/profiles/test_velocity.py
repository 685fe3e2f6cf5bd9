"""tk.velocity_change: reach a velocity and acceleration with no position target.

Durations against ruckig's velocity interface (ControlInterface.Velocity) to 1e-9
relative on problems drawn as ruckig's "velocity-random-3" draws them; the end
state exact; limits kept; closed forms; bad input.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import example, given
from hypothesis import strategies as st

import trajkit as tk
from trajkit import InfeasibleError, InvalidInputError

DURATION_RTOL = 1e-9
CLOSED_FORM = 1e-12


def test_a_ramp_without_jerk_limit_takes_the_closed_form_time() -> None:
    tr = tk.velocity_change([0.0, 1.0], [2.0, -1.0], 4.0, np.inf, q0=[1.0, 0.0])
    assert tr.duration == pytest.approx(0.5, rel=CLOSED_FORM)  # |dv| / amax, both joints
    np.testing.assert_allclose(tr.end_state.velocity, [2.0, -1.0], rtol=CLOSED_FORM)
    # Position: q0 + (v0 + vf) / 2 * T.
    np.testing.assert_allclose(tr.end_state.position, [1.5, 0.0], rtol=CLOSED_FORM, atol=1e-15)
    np.testing.assert_allclose(tr.start_state.position, [1.0, 0.0])


def test_a_jerk_limited_change_reaches_the_acceleration_limit() -> None:
    # dv = 3 with amax 1, jmax 2: ramp 0.5 s, hold 2.5 s, ramp 0.5 s.
    tr = tk.velocity_change(0.0, 3.0, 1.0, 2.0)
    assert tr.duration == pytest.approx(3.5, rel=CLOSED_FORM)
    assert tr.extrema(2).maximum[0] == pytest.approx(1.0, rel=CLOSED_FORM)
    assert tr.end_state.velocity[0] == 3.0
    assert tr.end_state.acceleration[0] == 0.0
    assert tr.end_state.position[0] == pytest.approx(3.0 * 3.5 / 2, rel=CLOSED_FORM)
    assert tr.check(tk.Limits(acceleration=1.0, jerk=2.0)).ok


def test_joints_finish_together_and_an_exact_duration_is_taken() -> None:
    tr = tk.velocity_change([0.0, 0.5, -1.0], [1.0, 0.5, 1.0], 2.0, 5.0, a0=[0.0, 1.0, -0.5])
    own = tr.info["minimum_durations"]
    assert tr.duration == pytest.approx(max(own), rel=CLOSED_FORM)
    np.testing.assert_array_equal(tr.end_state.velocity, [1.0, 0.5, 1.0])
    np.testing.assert_array_equal(tr.end_state.acceleration, [0.0, 0.0, 0.0])
    slow = tk.velocity_change([0.0, 0.5], [1.0, 0.5], 2.0, 5.0, duration=4.0)
    assert slow.duration == pytest.approx(4.0, rel=CLOSED_FORM)
    np.testing.assert_array_equal(slow.end_state.velocity, [1.0, 0.5])
    assert slow.check(tk.Limits(acceleration=2.0, jerk=5.0)).ok


def test_a_start_acceleration_beyond_the_limit_is_braked() -> None:
    tr = tk.velocity_change(0.0, 0.0, 1.0, 10.0, a0=3.0)
    assert tr.end_state.velocity[0] == 0.0
    # After the brake the acceleration stays within its limit.
    times = np.linspace(0.2, tr.duration, 500)
    assert np.abs(tr.acceleration(times)).max() <= 1.0 * (1 + 1e-9)


def test_refusals_name_the_quantity() -> None:
    with pytest.raises(InfeasibleError, match=r"af=3 rad/s\^2 is beyond the acceleration limit 2"):
        tk.velocity_change(0.0, 1.0, 2.0, 5.0, af=3.0)
    with pytest.raises(InvalidInputError, match=r"v0 must be finite"):
        tk.velocity_change(np.nan, 1.0, 2.0, 5.0)
    with pytest.raises(InvalidInputError, match=r"jmax must be > 0"):
        tk.velocity_change(0.0, 1.0, 2.0, 0.0)
    with pytest.raises(InvalidInputError, match=r"amax must allow motion both ways"):
        tk.velocity_change(0.0, 1.0, (0.0, 2.0), 5.0)
    with pytest.raises(InvalidInputError, match=r"vf has 3 joints but v0 has 2"):
        tk.velocity_change([0.0, 1.0], [1.0, 2.0, 3.0], 2.0, 5.0)
    with pytest.raises(InvalidInputError, match=r"a0=1 rad/s\^2 needs a jerk limit"):
        tk.velocity_change(0.0, 1.0, 2.0, np.inf, a0=1.0)
    with pytest.raises(InfeasibleError, match=r"below the minimum"):
        tk.velocity_change(0.0, 1.0, 2.0, 5.0, duration=0.1)


def _ruckig_draw(rng: np.random.Generator, count: int, ndof: int) -> dict[str, np.ndarray]:
    """As ruckig's "velocity-random-3": dynamics normal (sigma 0.8) or exactly zero."""
    shape = (count, ndof)

    def dynamic(nonzero: float) -> np.ndarray:
        return np.where(rng.random(shape) < nonzero, rng.normal(0.0, 0.8, shape), 0.0)

    p = {"q0": rng.normal(0.0, 4.0, shape), "v0": dynamic(0.9), "a0": dynamic(0.8)}
    p |= {"vf": dynamic(0.7), "af": dynamic(0.6)}
    p["A"] = rng.uniform(0.08, 16.0, shape) + np.abs(p["af"])
    p["J"] = rng.uniform(0.08, 16.0, shape)
    return p


def _ruckig_plans(p: dict[str, np.ndarray]):
    """``(i, ruckig's trajectory)`` for every problem of ``p`` ruckig's velocity interface plans."""
    ruckig = pytest.importorskip("ruckig", reason="ruckig (test oracle) is not installed")
    ndof = p["v0"].shape[1]
    otg, inp, out = ruckig.Ruckig(ndof), ruckig.InputParameter(ndof), ruckig.Trajectory(ndof)
    inp.control_interface = ruckig.ControlInterface.Velocity
    inp.max_velocity = np.full(ndof, 1e3)
    for i in range(len(p["v0"])):
        inp.current_position = p["q0"][i]
        inp.current_velocity, inp.current_acceleration = p["v0"][i], p["a0"][i]
        inp.target_velocity, inp.target_acceleration = p["vf"][i], p["af"][i]
        inp.max_acceleration, inp.max_jerk = p["A"][i], p["J"][i]
        if otg.calculate(inp, out) == ruckig.Result.Working:
            yield i, out


@pytest.mark.parametrize("ndof", [1, 3])
def test_durations_and_end_states_match_ruckigs_velocity_interface(ndof: int) -> None:
    p = _ruckig_draw(np.random.default_rng(31 + ndof), 400, ndof)
    compared = 0
    for i, out in _ruckig_plans(p):
        tr = tk.velocity_change(
            p["v0"][i], p["vf"][i], p["A"][i], p["J"][i],
            q0=p["q0"][i], a0=p["a0"][i], af=p["af"][i],
        )  # fmt: skip
        assert tr.duration == pytest.approx(out.duration, rel=DURATION_RTOL, abs=1e-14), i
        np.testing.assert_array_equal(tr.end_state.velocity, p["vf"][i])
        np.testing.assert_array_equal(tr.end_state.acceleration, p["af"][i])
        position, velocity, _ = out.at_time(out.duration)
        scale = np.abs(p["q0"][i]).max() + 1.0 + np.abs(velocity).max() * out.duration
        np.testing.assert_allclose(tr.end_state.position, position, atol=1e-9 * scale)
        within = np.abs(p["a0"][i]) <= p["A"][i]
        if within.all():
            limits = tk.Limits(acceleration=p["A"][i], jerk=p["J"][i])
            assert tr.check(limits).ok, i
        compared += 1
    assert compared >= 390


# --------------------------------------------------------------------------- batch
BATCH_RTOL = 1e-12  # relative: batch and one-by-one planning run the same kernels


def _one(p: dict[str, np.ndarray], i: int, **kwargs) -> tk.Trajectory:
    return tk.velocity_change(
        p["v0"][i], p["vf"][i], p["A"][i], p["J"][i],
        q0=p["q0"][i], a0=p["a0"][i], af=p["af"][i], **kwargs,
    )  # fmt: skip


def _many(p: dict[str, np.ndarray], **kwargs) -> tk.batch.BatchTrajectory:
    return tk.batch.velocity_change(
        p["v0"], p["vf"], p["A"], p["J"], q0=p["q0"], a0=p["a0"], af=p["af"], **kwargs
    )


@pytest.mark.parametrize("ndof", [1, 3, 6])
def test_a_batch_plans_each_problem_as_the_single_planner_does(ndof: int) -> None:
    p = _ruckig_draw(np.random.default_rng(70 + ndof), 60, ndof)
    plans = _many(p)
    assert len(plans) == 60 and plans.ndof == ndof
    times = np.linspace(0.0, float(plans.durations.max()) + 0.5, 23)
    for order in range(4):
        values = plans.evaluate(times, order)
        assert values.shape == (60, times.size, ndof)
        for i in (0, 17, 59):
            np.testing.assert_allclose(values[i], _one(p, i).evaluate(times, order), rtol=1e-12,
                                       atol=1e-12 * (1 + np.abs(values[i]).max()))  # fmt: skip
    for i in range(60):
        one = _one(p, i)
        assert plans.durations[i] == pytest.approx(one.duration, rel=BATCH_RTOL, abs=1e-15)
        np.testing.assert_array_equal(plans.info["end_position"][i], one.end_state.position)
        np.testing.assert_allclose(
            plans.info["minimum_durations"][i], one.info["minimum_durations"], rtol=BATCH_RTOL
        )
        item = plans[i]
        np.testing.assert_array_equal(item.end_state.velocity, p["vf"][i])
        np.testing.assert_array_equal(item.end_state.acceleration, p["af"][i])
        np.testing.assert_array_equal(item.end_state.position, one.end_state.position)
        assert item.info["planner"] == "velocity_change"


def test_a_batch_reaches_ruckigs_durations_and_end_states() -> None:
    ndof = 3
    p = _ruckig_draw(np.random.default_rng(5), 300, ndof)
    plans = _many(p)
    ends = plans.evaluate(plans.durations.max() + 1.0, 0)  # clamped: each problem's end
    compared = 0
    for i, out in _ruckig_plans(p):
        assert plans.durations[i] == pytest.approx(out.duration, rel=DURATION_RTOL, abs=1e-14)
        position, _, _ = out.at_time(out.duration)
        scale = np.abs(p["q0"][i]).max() + 1.0 + np.abs(p["vf"][i]).max() * out.duration
        np.testing.assert_allclose(plans.info["end_position"][i], position, atol=1e-9 * scale)
        # Evaluated past its duration, a problem stays at its exact end state.
        np.testing.assert_array_equal(ends[i], plans.info["end_position"][i])
        compared += 1
    assert compared >= 290


def test_a_batch_takes_shared_limits_a_floor_per_problem_and_a_duration_grid() -> None:
    v0 = np.array([[0.0, 1.0], [2.0, -1.0], [0.5, 0.5]])
    plans = tk.batch.velocity_change(v0, 0.0, (-1.0, 2.0), [4.0, np.inf])
    for i in range(3):
        one = tk.velocity_change(v0[i], 0.0, (-1.0, 2.0), [4.0, np.inf])
        assert plans.durations[i] == pytest.approx(one.duration, rel=BATCH_RTOL)
    floors = np.array([0.5, 5.0, 0.1])
    slow = tk.batch.velocity_change(v0, 0.0, 2.0, 4.0, min_duration=floors)
    fast = tk.batch.velocity_change(v0, 0.0, 2.0, 4.0)
    np.testing.assert_allclose(slow.durations, np.maximum(floors, fast.durations), rtol=1e-12)
    np.testing.assert_array_equal(slow.velocity(slow.durations.max()), np.zeros((3, 2)))
    grid = tk.batch.velocity_change(v0, 0.0, 2.0, 4.0, period=0.01, grid="duration")
    periods = grid.durations / 0.01
    np.testing.assert_allclose(periods, np.round(periods), rtol=0, atol=1e-9 * periods.max())
    assert np.all(grid.durations >= fast.durations * (1 - 1e-12))


def test_a_batch_refuses_by_problem_and_by_name() -> None:
    with pytest.raises(InfeasibleError, match=r"problem 1: .*af=3 rad/s\^2 is beyond the acc"):
        tk.batch.velocity_change([[0.0], [0.0]], [[1.0], [1.0]], 2.0, 5.0, af=[[0.0], [3.0]])
    with pytest.raises(InvalidInputError, match=r"problem 0: .*a0=1 rad/s\^2 needs a jerk limit"):
        tk.batch.velocity_change([[0.0]], [[1.0]], 2.0, np.inf, a0=1.0)
    with pytest.raises(InvalidInputError, match=r"v0 must be finite"):
        tk.batch.velocity_change([[np.nan]], [[1.0]], 2.0, 5.0)
    with pytest.raises(InfeasibleError, match=r"problem 1, joint 2 are beyond float64 \(v0=1e.308"):
        tk.batch.velocity_change([[0.0, 0.0], [0.0, 1e308]], 1.0, 2.0, 5.0)
    with pytest.raises(InfeasibleError, match=r"joint 1 are beyond float64 .*a0=1e\+200"):
        tk.velocity_change(0.0, 1.0, 2.0, 5.0, a0=1e200)
    with pytest.raises(InvalidInputError, match=r"must broadcast to one \(B, ndof\) shape"):
        tk.batch.velocity_change(np.zeros((2, 3)), np.zeros((2, 2)), 2.0, 5.0)
    with pytest.raises(InvalidInputError, match=r"jmax must be > 0|jmax"):
        tk.batch.velocity_change([[0.0]], [[1.0]], 2.0, 0.0)
    with pytest.raises(InfeasibleError, match=r"pass grid='duration'"):
        tk.batch.velocity_change([[0.0]], [[1.0]], 2.0, 5.0, period=0.01)


_speed = st.floats(-5.0, 5.0, allow_nan=False)
_limit = st.floats(0.1, 20.0, allow_nan=False)


@given(
    st.lists(st.tuples(_speed, _speed, st.floats(-1.0, 1.0), _limit, _limit), min_size=1,
             max_size=8),
)  # fmt: skip
# A subnormal target acceleration: reaching it takes 2.5e-324 s, which rounds to no time.
@example(rows=[(2.0, 2.0, 5e-324, 1.0, 2.0)])
def test_a_batch_ends_exactly_on_its_targets_within_the_limits(rows: list) -> None:
    v0, vf, af, amax, jmax = (np.array(column)[:, np.newaxis] for column in zip(*rows, strict=True))
    af = np.clip(af, -0.9 * amax, 0.9 * amax)
    plans = tk.batch.velocity_change(v0, vf, amax, jmax, af=af)
    end = plans.durations.max()
    for i in range(len(rows)):
        item = plans[i]
        np.testing.assert_array_equal(item.end_state.velocity, vf[i])
        np.testing.assert_array_equal(item.end_state.acceleration, af[i])
        times = np.linspace(0.0, plans.durations[i], 64)
        a = plans.evaluate(times, 2)[i, :, 0]
        assert np.abs(a).max() <= amax[i, 0] * (1 + 1e-9)
        assert np.abs(plans.evaluate(times, 3)[i, :, 0]).max() <= jmax[i, 0] * (1 + 1e-9)
    assert np.all(np.isfinite(plans.position(end)))
