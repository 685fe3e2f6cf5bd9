"""tk.velocity_change: reach a velocity and acceleration with no position target.

Durations against ruckig's velocity interface (ControlInterface.Velocity) to 1e-9
relative on problems drawn as ruckig's "velocity-random-3" draws them; the end
state exact; limits kept; closed forms; bad input.
"""

from __future__ import annotations

import numpy as np
import pytest

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


@pytest.mark.parametrize("ndof", [1, 3])
def test_durations_and_end_states_match_ruckigs_velocity_interface(ndof: int) -> None:
    ruckig = pytest.importorskip("ruckig", reason="ruckig (test oracle) is not installed")
    p = _ruckig_draw(np.random.default_rng(31 + ndof), 400, ndof)
    otg, inp, out = ruckig.Ruckig(ndof), ruckig.InputParameter(ndof), ruckig.Trajectory(ndof)
    inp.control_interface = ruckig.ControlInterface.Velocity
    compared = 0
    for i in range(len(p["v0"])):
        inp.current_position = p["q0"][i]
        inp.current_velocity, inp.current_acceleration = p["v0"][i], p["a0"][i]
        inp.target_velocity, inp.target_acceleration = p["vf"][i], p["af"][i]
        inp.max_velocity = np.full(ndof, 1e3)
        inp.max_acceleration, inp.max_jerk = p["A"][i], p["J"][i]
        if otg.calculate(inp, out) != ruckig.Result.Working:
            continue
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
