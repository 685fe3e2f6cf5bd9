"""End-to-end S-curve durations against ruckig on problems drawn as ruckig draws its own.

Problems come from ruckig's test randomizer (test/randomizer.hpp, test/test_target.cpp
"random_3", "random-3-high"): three joints; positions normal (sigma 4); start and
target velocities and accelerations normal (sigma 0.8), each exactly zero with
probability 0.1/0.2/0.3/0.4 (v0, a0, vf, af; 0.9 for all on the high range);
limits uniform on [0.08, 16] (high range [10, 1e6]), the velocity and acceleration
limits offset by |vf| and |af|; the "asymmetric" family draws independent lower
limits the same way. Problems ruckig's ``validate_input`` refuses (a target it
cannot arrive at) are redrawn, as ruckig's tests do. Starts beyond the limits are
kept: both libraries brake first.

Every problem is planned once by ``tk.batch.scurve`` (time synchronized) and once by
ruckig's ``calculate``; the test asserts, for every problem:

- both succeed (a failure on either side is reported with its problem);
- durations agree to ``DURATION_RTOL`` relative;
- the phase tables, integrated independently here, end in the target state
  (position and velocity to ``END_RTOL`` of the move's scale, acceleration to
  ``END_RTOL`` of its limit, plus the rounding of this integration: see
  :func:`end_errors`);
- after the brake, no phase exceeds a velocity or acceleration limit by more than
  ``LIMIT_RTOL`` (extrema inside phases included, exactly: velocity is quadratic
  within a phase, so its peak is at an end or where the acceleration crosses zero).

CI runs ``TRAJKIT_RUCKIG_PROBLEMS`` problems per family (default 40,000: 120,000 in
all); ``TRAJKIT_RUCKIG_PROBLEMS=340000`` runs more than 10^6.
"""

from __future__ import annotations

import os

import numpy as np
import pytest

import trajkit as tk

ruckig = pytest.importorskip("ruckig", reason="ruckig (test oracle) is not installed")

NDOF = 3
PROBLEMS = int(os.environ.get("TRAJKIT_RUCKIG_PROBLEMS", "40000"))
CHUNK = 50_000  # problems planned per batch call: bounds the check's temporaries
DURATION_RTOL = 1e-9
END_RTOL = 1e-10
LIMIT_RTOL = 1e-9
BRAKE_PHASES = 2  # the phase tables' first two phases are the brake


def draw(rng: np.random.Generator, count: int, family: str) -> dict[str, np.ndarray]:
    """``count`` problems of ``NDOF`` joints as ruckig's randomizer draws them."""
    low, high = (10.0, 1e6) if family == "high" else (0.08, 16.0)
    shape = (count, NDOF)

    def dynamic(nonzero: float) -> np.ndarray:
        if family == "high":
            nonzero = 0.1
        return np.where(rng.random(shape) < nonzero, rng.normal(0.0, 0.8, shape), 0.0)

    p = {"q0": rng.normal(0.0, 4.0, shape), "v0": dynamic(0.9), "a0": dynamic(0.8)}
    p |= {"qf": rng.normal(0.0, 4.0, shape), "vf": dynamic(0.7), "af": dynamic(0.6)}
    p["V"] = rng.uniform(low, high, shape) + np.abs(p["vf"])
    p["A"] = rng.uniform(low, high, shape) + np.abs(p["af"])
    p["J"] = rng.uniform(low, high, shape)
    if family == "asymmetric":
        p["Vmin"] = -(rng.uniform(low, high, shape) + np.abs(p["vf"]))
        p["Amin"] = -(rng.uniform(low, high, shape) + np.abs(p["af"]))
    else:
        p["Vmin"], p["Amin"] = -p["V"], -p["A"]
    return p


def ruckig_input(p: dict[str, np.ndarray], i: int, inp) -> None:
    inp.current_position, inp.target_position = p["q0"][i], p["qf"][i]
    inp.current_velocity, inp.target_velocity = p["v0"][i], p["vf"][i]
    inp.current_acceleration, inp.target_acceleration = p["a0"][i], p["af"][i]
    inp.max_velocity, inp.max_acceleration, inp.max_jerk = p["V"][i], p["A"][i], p["J"][i]
    inp.min_velocity, inp.min_acceleration = p["Vmin"][i], p["Amin"][i]


def valid_problems(rng: np.random.Generator, count: int, family: str) -> dict[str, np.ndarray]:
    """Draw until ``count`` problems pass ruckig's own input validation."""
    otg, inp = ruckig.Ruckig(NDOF), ruckig.InputParameter(NDOF)
    kept: list[dict[str, np.ndarray]] = []
    needed = count
    while needed:
        p = draw(rng, needed + needed // 20 + 10, family)
        ok = np.zeros(len(p["q0"]), dtype=bool)
        for i in range(len(ok)):
            ruckig_input(p, i, inp)
            try:
                ok[i] = otg.validate_input(inp, False, True)
            except ruckig.RuckigError:
                pass
        index = np.flatnonzero(ok)[:needed]
        kept.append({k: v[index] for k, v in p.items()})
        needed -= len(index)
    return {k: np.concatenate([c[k] for c in kept]) for k in kept[0]}


def ruckig_durations(p: dict[str, np.ndarray]) -> tuple[np.ndarray, list[str]]:
    """ruckig's durations (NaN where it fails) and a line per failure."""
    otg, inp, out = ruckig.Ruckig(NDOF), ruckig.InputParameter(NDOF), ruckig.Trajectory(NDOF)
    durations = np.full(len(p["q0"]), np.nan)
    failures = []
    for i in range(len(durations)):
        ruckig_input(p, i, inp)
        try:
            result = otg.calculate(inp, out)
        except ruckig.RuckigError as error:
            result = error
        if result == ruckig.Result.Working:
            durations[i] = out.duration
        else:
            failures.append(f"ruckig fails problem {i}: {result}")
    return durations, failures


def plan(p: dict[str, np.ndarray]) -> tk.batch.BatchTrajectory:
    return tk.batch.scurve(
        p["q0"], p["qf"], (p["Vmin"], p["V"]), (p["Amin"], p["A"]), p["J"],
        v0=p["v0"], vf=p["vf"], a0=p["a0"], af=p["af"],
    )  # fmt: skip


def phase_ends(plan: tk.batch.BatchTrajectory) -> dict[str, np.ndarray]:
    """Each phase's start and end state, integrated here from the phase tables."""
    pp = plan.plan
    d, a, j = pp.durations, pp.accelerations, pp.jerks
    dv = a * d + j * d**2 / 2
    v_start = pp.velocity[..., None] + np.concatenate(
        [np.zeros_like(dv[..., :1]), np.cumsum(dv[..., :-1], axis=-1)], axis=-1
    )
    dp = v_start * d + a * d**2 / 2 + j * d**3 / 6
    return {
        "d": d, "a": a, "j": j, "v": v_start,
        "p_end": pp.position + dp.sum(axis=-1),
        "v_end": v_start[..., -1] + dv[..., -1],
        "a_end": a[..., -1] + j[..., -1] * d[..., -1],
    }  # fmt: skip


def limit_excess(ends: dict[str, np.ndarray], p: dict[str, np.ndarray]) -> np.ndarray:
    """Worst excess over the limits, relative to the limit, per problem.

    A start beyond the limits is braked back within them: until the end of the
    first phase that ends within the limits, the bounds are widened to what the
    start state forces (its velocity plus the overshoot its acceleration carries
    at full jerk, its acceleration); from then on they are the limits.
    """
    d, a, j, v = ends["d"], ends["a"], ends["j"], ends["v"]
    a_end = a + j * d
    with np.errstate(divide="ignore", invalid="ignore"):
        tau = np.where(j != 0, -a / j, -1.0)  # where the acceleration crosses zero
    inside = (tau > 0) & (tau < d)
    v_turn = np.where(inside, v + a * tau + j * tau**2 / 2, v)
    v_end = v + a * d + j * d**2 / 2
    active = d > 0
    V, Vmin, A, Amin = (p[k][..., None] for k in ("V", "Vmin", "A", "Amin"))
    tol = 1 + LIMIT_RTOL
    within = (v_end <= V * tol) & (v_end >= Vmin * tol) & (a_end <= A * tol) & (a_end >= Amin * tol)
    settled = np.cumsum(active & within, axis=-1) > 0
    braking = ~np.concatenate([np.zeros_like(settled[..., :1]), settled[..., :-1]], axis=-1)
    v0, a0, J = p["v0"][..., None], p["a0"][..., None], p["J"][..., None]
    forced_hi = v0 + np.maximum(a0, 0) ** 2 / (2 * J)
    forced_lo = v0 - np.maximum(-a0, 0) ** 2 / (2 * J)
    v_hi_bound = np.where(braking, np.maximum(V, forced_hi), V)
    v_lo_bound = np.where(braking, np.minimum(Vmin, forced_lo), Vmin)
    a_hi_bound = np.where(braking, np.maximum(A, a0), A)
    a_lo_bound = np.where(braking, np.minimum(Amin, a0), Amin)
    v_hi = np.maximum.reduce([v, v_end, v_turn])
    v_lo = np.minimum.reduce([v, v_end, v_turn])
    excess = np.stack(
        [
            (v_hi - v_hi_bound) / V,
            (v_lo_bound - v_lo) / -Vmin,
            (np.maximum(a, a_end) - a_hi_bound) / A,
            (a_lo_bound - np.minimum(a, a_end)) / -Amin,
        ]
    )
    excess = np.where(active, excess, 0.0)
    return np.maximum(excess.max(axis=(0, 2, 3)), 0.0)


def end_errors(ends: dict[str, np.ndarray], p: dict[str, np.ndarray]) -> np.ndarray:
    """Worst end-state error per problem, in units of its tolerance (<= 1 passes).

    The tolerance is ``END_RTOL`` of the move's scale (positions: the larger of
    |q0|, |qf| and 1; velocities and accelerations: their limits) plus the rounding
    this integration itself carries: an acceleration held at zero is an integrated
    rounding (an ulp of the peak acceleration) and over a duration T it moves the
    end by ulp * T^2 / 2 (2.8e-10 rad after 1600 s at a 1.5 rad/s^2 peak).
    """
    duration = ends["d"].sum(axis=-1)
    a_peak = np.maximum(np.abs(ends["a"]), np.abs(ends["a"] + ends["j"] * ends["d"])).max(axis=-1)
    v_peak = np.abs(ends["v"]).max(axis=-1)
    ulp = 8 * np.finfo(float).eps
    scale_p = np.maximum.reduce([np.abs(p["q0"]), np.abs(p["qf"]), np.ones_like(p["q0"])])
    scale_v = np.maximum(p["V"], -p["Vmin"])
    scale_a = np.maximum(p["A"], -p["Amin"])
    errors = np.stack(
        [
            np.abs(ends["p_end"] - p["qf"])
            / (END_RTOL * scale_p + ulp * (a_peak * duration**2 + v_peak * duration)),
            np.abs(ends["v_end"] - p["vf"]) / (END_RTOL * scale_v + ulp * a_peak * duration),
            np.abs(ends["a_end"] - p["af"]) / (END_RTOL * scale_a),
        ]
    )
    return errors.max(axis=(0, 2))


def compare(p: dict[str, np.ndarray]) -> dict[str, object]:
    theirs, failures = ruckig_durations(p)
    worst = {"duration": 0.0, "end": 0.0, "limit": 0.0}
    for start in range(0, len(theirs), CHUNK):
        part = {k: v[start : start + CHUNK] for k, v in p.items()}
        ours = plan(part)
        ends = phase_ends(ours)
        reference = theirs[start : start + CHUNK]
        both = np.isfinite(reference)
        rel = np.abs(ours.durations[both] - reference[both]) / reference[both]
        figures = {
            "duration": rel,
            "end": end_errors(ends, part),
            "limit": limit_excess(ends, part),
        }
        for name, values in figures.items():
            if values.size:
                at = int(np.argmax(values))
                if values[at] > worst[name]:
                    worst[name] = float(values[at])
                    worst[name + "_problem"] = start + (
                        np.flatnonzero(both)[at] if name == "duration" else at
                    )
    worst["ruckig_failures"] = failures
    return worst


def assert_agrees(worst: dict[str, object]) -> None:
    assert worst["ruckig_failures"] == []
    assert worst["duration"] <= DURATION_RTOL, worst
    assert worst["end"] <= 1.0, worst
    assert worst["limit"] <= LIMIT_RTOL, worst


@pytest.mark.parametrize("family", ["random", "asymmetric", "high"])
def test_a_few_thousand_problems_agree_with_ruckig(family):
    p = valid_problems(np.random.default_rng(17), 3000, family)
    assert_agrees(compare(p))


@pytest.mark.slow
@pytest.mark.parametrize("family", ["random", "asymmetric", "high"])
def test_sweep_against_ruckig(family):
    p = valid_problems(np.random.default_rng(2026), PROBLEMS, family)
    worst = compare(p)
    print(f"{family}: {PROBLEMS} problems, worst {worst}")
    assert_agrees(worst)


def test_the_draw_has_what_it_claims():
    p = draw(np.random.default_rng(5), 20000, "random")
    assert 0.08 <= p["J"].min() and p["J"].max() <= 16.0
    assert abs(np.mean(p["v0"] == 0) - 0.1) < 0.01
    assert abs(np.mean(p["af"] == 0) - 0.4) < 0.01
    assert np.all(p["V"] >= np.abs(p["vf"])) and np.all(p["A"] >= np.abs(p["af"]))
    assert np.mean(np.abs(p["v0"]) > p["V"]) > 0.001  # starts beyond the limits occur
    high = draw(np.random.default_rng(5), 20000, "high")
    assert high["J"].max() > 9e5 and abs(np.mean(high["v0"] == 0) - 0.9) < 0.01
