"""S-curve durations against ruckig (the oracle): rest to rest and moving boundaries.

Tolerances: rest to rest 1e-9 relative; with nonzero boundary velocities 1e-6
relative (the issue's bound; measured worst differences are ~1e-11).
"""

from __future__ import annotations

import numpy as np
import pytest

import trajkit as tk

ruckig = pytest.importorskip("ruckig", reason="ruckig (test oracle) is not installed")

REST = 1e-9
MOVING = 1e-6


def draw(rng: np.random.Generator, count: int, ndof: int, moving: bool) -> dict[str, np.ndarray]:
    """Random problems over several decades, with exact zeros drawn on purpose."""
    scale = 10.0 ** rng.uniform(-2, 2, (count, 1))
    q0 = rng.uniform(-3, 3, (count, ndof)) * scale
    qf = rng.uniform(-3, 3, (count, ndof)) * scale
    same = rng.random((count, ndof)) < 0.03
    qf[same] = q0[same]
    V = 10.0 ** rng.uniform(-1, 1, (count, ndof))
    A = 10.0 ** rng.uniform(-1, 1.5, (count, ndof))
    J = 10.0 ** rng.uniform(-0.5, 2.5, (count, ndof))
    v0 = np.zeros((count, ndof))
    vf = np.zeros((count, ndof))
    if moving:
        v0 = rng.uniform(-1, 1, (count, ndof)) * V * (rng.random((count, ndof)) < 0.7)
        vf = rng.uniform(-1, 1, (count, ndof)) * V * (rng.random((count, ndof)) < 0.7)
        at_limit = rng.random((count, ndof)) < 0.05
        v0[at_limit] = V[at_limit] * np.sign(rng.uniform(-1, 1, at_limit.sum()))
    return {"q0": q0, "qf": qf, "v0": v0, "vf": vf, "V": V, "A": A, "J": J}


def ruckig_durations(p: dict[str, np.ndarray], synchronized: bool) -> tuple[np.ndarray, np.ndarray]:
    count, ndof = p["q0"].shape
    otg, inp, out = ruckig.Ruckig(ndof), ruckig.InputParameter(ndof), ruckig.Trajectory(ndof)
    inp.synchronization = ruckig.Synchronization.Time if synchronized else ruckig.Synchronization.No
    durations = np.empty(count)
    own = np.empty((count, ndof))
    for i in range(count):
        inp.current_position, inp.target_position = p["q0"][i], p["qf"][i]
        inp.current_velocity, inp.target_velocity = p["v0"][i], p["vf"][i]
        inp.max_velocity, inp.max_acceleration, inp.max_jerk = p["V"][i], p["A"][i], p["J"][i]
        result = otg.calculate(inp, out)
        assert result == ruckig.Result.Working, f"ruckig failed on problem {i}: {result}"
        durations[i] = out.duration
        own[i] = out.independent_min_durations
    return durations, own


def trajkit_durations(p: dict[str, np.ndarray], sync: str | None) -> tk.batch.BatchTrajectory:
    return tk.batch.scurve(
        p["q0"], p["qf"], p["V"], p["A"], p["J"], v0=p["v0"], vf=p["vf"], sync=sync
    )


def relative(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.abs(a - b) / np.maximum(np.abs(b), 1e-300)


@pytest.mark.parametrize("moving", [False, True], ids=["rest", "moving"])
def test_single_joint_minimum_time_matches_ruckig(moving):
    rng = np.random.default_rng(101 + moving)
    p = draw(rng, 3000, 1, moving)
    theirs, _ = ruckig_durations(p, synchronized=False)
    ours = trajkit_durations(p, None).durations
    assert relative(ours, theirs).max() <= (MOVING if moving else REST)


@pytest.mark.parametrize("moving", [False, True], ids=["rest", "moving"])
def test_time_synchronized_durations_match_ruckig(moving):
    rng = np.random.default_rng(202 + moving)
    p = draw(rng, 400, 3, moving)
    theirs, own = ruckig_durations(p, synchronized=True)
    plans = trajkit_durations(p, "time")
    assert relative(plans.durations, theirs).max() <= (MOVING if moving else REST)
    np.testing.assert_allclose(
        plans.info["minimum_durations"], own, rtol=MOVING if moving else REST, atol=1e-12
    )


def test_single_problem_planner_agrees_with_ruckig_and_keeps_limits():
    rng = np.random.default_rng(303)
    p = draw(rng, 60, 3, True)
    theirs, _ = ruckig_durations(p, synchronized=True)
    for i in range(60):
        tr = tk.scurve(
            p["q0"][i], p["qf"][i], p["V"][i], p["A"][i], p["J"][i], v0=p["v0"][i], vf=p["vf"][i]
        )
        assert tr.duration == pytest.approx(theirs[i], rel=MOVING)
        limits = tk.Limits(velocity=p["V"][i], acceleration=p["A"][i], jerk=p["J"][i])
        assert tr.check(limits).ok
        end = tr.end_state
        np.testing.assert_allclose(
            end.position, p["qf"][i], rtol=1e-9, atol=1e-9 * np.abs(p["qf"][i]).max()
        )
        np.testing.assert_allclose(end.velocity, p["vf"][i], atol=1e-9 * p["V"][i].max())


@pytest.mark.slow
def test_sweep_100k_problems_against_ruckig():
    """100,000 single-joint problems (half at rest, half moving) and 20,000
    three-joint time-synchronized problems with moving boundaries."""
    rng = np.random.default_rng(404)
    worst = {}
    for moving in (False, True):
        p = draw(rng, 50_000, 1, moving)
        theirs, _ = ruckig_durations(p, synchronized=False)
        worst[moving] = relative(trajkit_durations(p, None).durations, theirs).max()
    p = draw(rng, 20_000, 3, True)
    theirs, _ = ruckig_durations(p, synchronized=True)
    worst["synchronized"] = relative(trajkit_durations(p, "time").durations, theirs).max()
    print(f"worst relative duration differences: {worst}")
    assert worst[False] <= REST
    assert worst[True] <= MOVING
    assert worst["synchronized"] <= MOVING
