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


def test_unsynchronized_joints_coast_on_at_their_target_acceleration_as_in_ruckig():
    """sync=None with target accelerations: a joint done early goes on from its target
    state at constant acceleration (ruckig's ``at_time``). Compared state by state, at
    times up to the end, for single plans, batch rows and batch evaluation."""
    rng = np.random.default_rng(505)
    count, ndof = 40, 3
    p = draw(rng, count, ndof, True)
    for a, v in (("a0", "v0"), ("af", "vf")):
        # Admissible: the velocity the acceleration ramps to or from stays within V.
        room = np.sqrt(2.0 * p["J"] * np.maximum(p["V"] - np.abs(p[v]), 0.0))
        p[a] = rng.uniform(-0.9, 0.9, (count, ndof)) * np.minimum(p["A"], room)
    otg, inp, out = ruckig.Ruckig(ndof), ruckig.InputParameter(ndof), ruckig.Trajectory(ndof)
    inp.synchronization = ruckig.Synchronization.No
    kw = {"v0": p["v0"], "vf": p["vf"], "a0": p["a0"], "af": p["af"], "sync": None}
    plans = tk.batch.scurve(p["q0"], p["qf"], p["V"], p["A"], p["J"], **kw)
    fractions = np.linspace(0.0, 1.0, 17)
    shared = fractions * plans.durations.max()  # batch evaluation: the same times for all
    evaluated = [plans.evaluate(shared, order) for order in range(3)]
    for i in range(count):
        inp.current_position, inp.target_position = p["q0"][i], p["qf"][i]
        inp.current_velocity, inp.target_velocity = p["v0"][i], p["vf"][i]
        inp.current_acceleration, inp.target_acceleration = p["a0"][i], p["af"][i]
        inp.max_velocity, inp.max_acceleration, inp.max_jerk = p["V"][i], p["A"][i], p["J"][i]
        assert otg.calculate(inp, out) == ruckig.Result.Working
        single = tk.scurve(p["q0"][i], p["qf"][i], p["V"][i], p["A"][i], p["J"][i],
                           **{k: v[i] if k != "sync" else v for k, v in kw.items()})  # fmt: skip
        assert single.duration == pytest.approx(out.duration, rel=MOVING)
        row = plans[i]
        np.testing.assert_array_equal(row.breakpoints, single.breakpoints)
        np.testing.assert_array_equal(row.coefficients, single.coefficients)
        for order in range(3):
            ours = single.evaluate(fractions * single.duration, order)
            theirs = np.array([out.at_time(t)[order] for t in fractions * single.duration])
            scale = max(1.0, np.abs(theirs).max())
            np.testing.assert_allclose(ours, theirs, rtol=0, atol=MOVING * scale)
            np.testing.assert_allclose(evaluated[order][i], single.evaluate(shared, order),
                                       rtol=0, atol=1e-12 * scale)  # fmt: skip


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
