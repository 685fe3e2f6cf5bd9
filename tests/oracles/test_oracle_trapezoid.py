"""trajkit's trapezoid planner against ruckig with infinite jerk (acceleration-limited).

ruckig solves the same problem (bang-coast-bang under velocity and acceleration limits,
time synchronization with blocked intervals) by an independent implementation, so the
durations must agree to ORACLE_RTOL (1e-9) relative: the synchronized duration
(Synchronization.Time against sync="time"), each joint's own minimum
(independent_min_durations against info["minimum_durations"]) and the unsynchronized
duration (Synchronization.No against sync=None).

Problems are seeded and random: 1-6 joints, exact zeros (positions, distances, boundary
velocities), boundary velocities exactly at a limit, limits over four decades. Distances
scale with the limits so durations stay below ruckig's own ceiling (~7.6e3 s); a problem
ruckig itself refuses (its ErrorTrajectoryDuration has no Python enum member and surfaces
as ValueError; RuckigError for internal failures) is counted and skipped, and may be at
most SKIP_FRACTION of a sweep.
"""

from __future__ import annotations

import numpy as np
import pytest

import trajkit as tk
from support import CLOSED_FORM

ruckig = pytest.importorskip(
    "ruckig",
    reason="ruckig (the time-optimal trapezoid oracle) is not installed; pip install ruckig",
)

ORACLE_RTOL = CLOSED_FORM  # 1e-9 relative on durations
DURATION_ATOL = 1e-14  # s: ruckig reports 3.6e-15 s where a joint is already at its target
SKIP_FRACTION = 0.01  # at most 1 % of a sweep may be problems ruckig cannot solve
INF = float("inf")


def draw_problem(rng: np.random.Generator, *, asymmetric: bool = False) -> dict:
    """One random problem; "kind" says rest-to-rest or moving boundaries."""
    n = int(rng.integers(1, 7))
    vmax = 10.0 ** rng.uniform(-2.0, 2.0, n)
    amax = vmax * 10.0 ** rng.uniform(-1.5, 1.5, n)
    vmin = vmax * 10.0 ** rng.uniform(-1.0, 1.0, n) if asymmetric else vmax
    amin = amax * 10.0 ** rng.uniform(-1.0, 1.0, n) if asymmetric else amax
    q0 = np.where(rng.random(n) < 0.2, 0.0, rng.uniform(-10.0, 10.0, n))
    distance = rng.choice([-1.0, 1.0], n) * vmax * 10.0 ** rng.uniform(-3.0, 2.0, n)
    qf = np.where(rng.random(n) < 0.2, q0, q0 + distance)
    v0 = np.zeros(n)
    vf = np.zeros(n)
    rest = rng.random() < 1.0 / 3.0
    if not rest:
        for v in (v0, vf):
            choice = rng.random(n)
            v[:] = rng.uniform(-vmin, vmax)
            v[choice < 0.3] = 0.0
            v[(choice >= 0.3) & (choice < 0.4)] = vmax[(choice >= 0.3) & (choice < 0.4)]
            v[(choice >= 0.4) & (choice < 0.45)] = -vmin[(choice >= 0.4) & (choice < 0.45)]
    return {
        "q0": q0, "qf": qf, "v0": v0, "vf": vf,
        "vmax": vmax, "vmin": vmin, "amax": amax, "amin": amin,
        "asymmetric": asymmetric, "rest": rest,
    }  # fmt: skip


def ruckig_plan(problem: dict, synchronization, dt: float | None = None):
    """(duration, independent minimum durations) from ruckig, or None if it refuses."""
    n = problem["q0"].size
    inp = ruckig.InputParameter(n)
    inp.current_position = problem["q0"]
    inp.target_position = problem["qf"]
    inp.current_velocity = problem["v0"]
    inp.target_velocity = problem["vf"]
    inp.max_velocity = problem["vmax"]
    inp.max_acceleration = problem["amax"]
    inp.max_jerk = [INF] * n
    if problem["asymmetric"]:
        inp.min_velocity = -problem["vmin"]
        inp.min_acceleration = -problem["amin"]
    inp.synchronization = synchronization
    if dt is None:
        otg = ruckig.Ruckig(n)
    else:
        inp.duration_discretization = ruckig.DurationDiscretization.Discrete
        otg = ruckig.Ruckig(n, dt)
    trajectory = ruckig.Trajectory(n)
    try:
        result = otg.calculate(inp, trajectory)
    except (ValueError, ruckig.RuckigError):
        return None
    if result != ruckig.Result.Working:
        return None
    return trajectory.duration, np.array(trajectory.independent_min_durations)


def trajkit_plan(problem: dict, sync, dt: float | None = None) -> tk.Trajectory:
    if problem["asymmetric"]:
        vmax = (-problem["vmin"], problem["vmax"])
        amax = (-problem["amin"], problem["amax"])
    else:
        vmax, amax = problem["vmax"], problem["amax"]
    return tk.trapezoidal(
        problem["q0"], problem["qf"], vmax, amax,
        v0=problem["v0"], vf=problem["vf"], sync=sync, period=dt,
    )  # fmt: skip


def relative_error(actual, expected) -> float:
    """max |actual - expected| / expected, with differences below DURATION_ATOL as 0."""
    actual, expected = np.asarray(actual, float), np.asarray(expected, float)
    difference = np.maximum(np.abs(actual - expected) - DURATION_ATOL, 0.0)
    scale = np.where(expected > 0, expected, 1.0)
    return float(np.max(difference / scale))


def sweep(
    seed: int, count: int, *, asymmetric: bool = False, unsynced_every: int = 1
) -> dict[str, float]:
    """Compare ``count`` problems; returns the worst relative differences and counts.

    Every problem is compared under time sync; every ``unsynced_every``-th also under
    sync=None (the slow sweep halves that to stay within its time budget).
    """
    rng = np.random.default_rng(seed)
    worst = {"time": 0.0, "own": 0.0, "none": 0.0, "ruckig_no": 0.0, "own_none": 0.0}
    skipped = arrived = unsynced_count = 0
    for index in range(count):
        problem = draw_problem(rng, asymmetric=asymmetric)
        if already_there(problem):
            arrived += 1  # test_already_at_the_target_state_takes_no_time
            continue
        timed = ruckig_plan(problem, ruckig.Synchronization.Time)
        unsynced = ruckig_plan(problem, ruckig.Synchronization.No)
        if timed is None or unsynced is None:
            skipped += 1
            continue
        duration, own = timed
        synced = trajkit_plan(problem, "time")
        errors = {
            "time": relative_error(synced.duration, duration),
            "own": relative_error(synced.info["minimum_durations"], own),
        }
        if index % unsynced_every == 0:
            alone = trajkit_plan(problem, None)
            errors["none"] = relative_error(alone.duration, own.max())
            errors["ruckig_no"] = relative_error(alone.duration, unsynced[0])
            # Each joint alone needs the same time in both trajkit calls.
            errors["own_none"] = relative_error(alone.info["minimum_durations"], own)
            unsynced_count += 1
        for key, error in errors.items():
            assert error <= ORACLE_RTOL, (
                f"problem {index} (seed {seed}): {key} differs by {error:.3g}: {problem}"
            )
            worst[key] = max(worst[key], error)
    assert skipped <= SKIP_FRACTION * count, f"ruckig refused {skipped} of {count} problems"
    compared = count - skipped - arrived
    return {**worst, "skipped": skipped, "arrived": arrived, "compared": compared,
            "compared_unsynced": unsynced_count}  # fmt: skip


def already_there(problem: dict) -> bool:
    """Every joint starts in its target state (q0 == qf, v0 == vf) and some joint moves."""
    return bool(
        np.all(problem["q0"] == problem["qf"])
        and np.all(problem["v0"] == problem["vf"])
        and np.any(problem["v0"] != 0)
    )


@pytest.mark.parametrize(("v", "a"), [(0.1, 0.1), (0.03457013, 0.09659326)])
def test_already_at_the_target_state_takes_no_time(v, a):
    problem = {
        "q0": np.array([8.33595485]), "qf": np.array([8.33595485]),
        "v0": np.array([v]), "vf": np.array([v]),
        "vmax": np.array([1.0]), "vmin": np.array([1.0]),
        "amax": np.array([a]), "amin": np.array([a]), "asymmetric": False,
    }  # fmt: skip
    duration, own = ruckig_plan(problem, ruckig.Synchronization.Time)
    assert duration == 0.0 and own[0] == 0.0
    assert trajkit_plan(problem, None).duration == 0.0
    assert trajkit_plan(problem, "time").duration == 0.0


def test_symmetric_limits_agree_with_ruckig():
    result = sweep(seed=20240501, count=400)
    assert result["compared"] >= 396


def test_asymmetric_limits_agree_with_ruckig():
    result = sweep(seed=20240502, count=400, asymmetric=True)
    assert result["compared"] >= 396


def test_the_sweep_draws_the_cases_it_claims():
    rng = np.random.default_rng(20240501)
    problems = [draw_problem(rng) for _ in range(400)]
    still = sum(int(np.any(p["q0"] == p["qf"])) for p in problems)
    rest = sum(p["rest"] for p in problems)
    at_limit = sum(int(np.any(np.abs(p["v0"]) == p["vmax"])) for p in problems)
    zero_start = sum(int(np.any(p["q0"] == 0.0)) for p in problems)
    assert still > 50 and rest > 100 and 400 - rest > 200 and at_limit > 20 and zero_start > 50


@pytest.mark.parametrize("dt", [0.001, 0.002, 0.01])
def test_quantized_rest_to_rest_is_within_one_period_of_ruckigs_discrete_duration(dt):
    # ruckig Discrete: the shortest whole-period duration with any (continuous) phase
    # times. trajkit also makes every phase whole periods: at most one period more.
    rng = np.random.default_rng(7)
    compared = 0
    for _ in range(150):
        problem = draw_problem(rng)
        problem.update(v0=np.zeros_like(problem["v0"]), vf=np.zeros_like(problem["vf"]))
        reference = ruckig_plan(problem, ruckig.Synchronization.Time, dt=dt)
        if reference is None:
            continue
        tr = trajkit_plan(problem, "time", dt=dt)
        extra = (tr.duration - reference[0]) / dt
        assert extra == pytest.approx(0.0, abs=1e-6) or extra == pytest.approx(1.0, abs=1e-6), (
            f"{extra} periods more than ruckig: {problem}"
        )
        compared += 1
    assert compared >= 148


@pytest.mark.slow
def test_sweep_of_20000_problems():
    symmetric = sweep(seed=1, count=15_000, unsynced_every=2)
    asymmetric = sweep(seed=2, count=5_000, asymmetric=True, unsynced_every=2)
    print(f"\nruckig oracle, symmetric: {symmetric}\nruckig oracle, asymmetric: {asymmetric}")
    assert symmetric["compared"] + asymmetric["compared"] >= 19_800
