"""Batch planning throughput beside ruckig called in a Python loop, same problems.

Run: python bench/bench_batch.py [--problems 100000] [--ruckig-sample 20000]

For each profile (acceleration-limited trapezoid = ruckig with infinite jerk;
jerk-limited S-curve) it plans B random rest-to-rest 6-DoF problems with
trajkit.batch in one call (median of several calls) and builds every problem's
full phase plan (what ruckig returns too), times ruckig on the same problems one by
one (median per-problem time over chunks of a sample), checks the durations agree,
and prints microseconds per problem and the ratio.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import trajkit as tk

NDOF = 6


def problems(count: int, seed: int = 20261122) -> dict[str, np.ndarray]:
    rng = np.random.default_rng(seed)
    return {
        "q0": rng.uniform(-3.0, 3.0, (count, NDOF)),
        "qf": rng.uniform(-3.0, 3.0, (count, NDOF)),
        "vmax": rng.uniform(0.5, 3.0, NDOF),
        "amax": rng.uniform(1.0, 10.0, NDOF),
        "jmax": rng.uniform(5.0, 100.0, NDOF),
    }


def time_trajkit(plan, repeats: int = 7) -> tuple[float, float, np.ndarray]:
    """Median seconds to solve (durations and every joint's profile parameters) and
    to solve and also expand the per-phase tables a BatchTrajectory evaluates."""
    durations = plan().durations
    solve, tables = [], []
    for _ in range(repeats):
        start = time.perf_counter()
        plan()
        solve.append(time.perf_counter() - start)
        start = time.perf_counter()
        plan().plan  # noqa: B018
        tables.append(time.perf_counter() - start)
    return float(np.median(solve)), float(np.median(tables)), durations


def time_ruckig(p: dict[str, np.ndarray], count: int, jerk: bool) -> tuple[float, np.ndarray]:
    from ruckig import InputParameter, Ruckig, Trajectory

    otg, inp, out = Ruckig(NDOF), InputParameter(NDOF), Trajectory(NDOF)
    inp.max_velocity = p["vmax"]
    inp.max_acceleration = p["amax"]
    inp.max_jerk = p["jmax"] if jerk else [float("inf")] * NDOF
    durations = np.empty(count)
    # Lists, not numpy rows: ruckig converts a numpy row about 15x slower (2 us).
    q0, qf = p["q0"][:count].tolist(), p["qf"][:count].tolist()
    chunk_times = []
    for begin in range(0, count, 1000):
        start = time.perf_counter()
        for i in range(begin, min(begin + 1000, count)):
            inp.current_position = q0[i]
            inp.target_position = qf[i]
            otg.calculate(inp, out)
            durations[i] = out.duration
        chunk_times.append((time.perf_counter() - start) / (min(begin + 1000, count) - begin))
    return float(np.median(chunk_times)), durations


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--problems", type=int, default=100_000)
    parser.add_argument("--ruckig-sample", type=int, default=20_000)
    args = parser.parse_args()
    p = problems(args.problems)
    cases = [("trapezoid (ruckig, infinite jerk)", False, lambda: tk.batch.trapezoidal(
        p["q0"], p["qf"], p["vmax"], p["amax"]))]  # fmt: skip
    cases.append(("S-curve (ruckig, jerk-limited)", True, lambda: tk.batch.scurve(
        p["q0"], p["qf"], p["vmax"], p["amax"], p["jmax"])))  # fmt: skip
    print(f"B = {args.problems} random rest-to-rest {NDOF}-DoF problems, time-synchronized")
    print("us per problem; 'solve' = durations and every joint's profile parameters,")
    print("'+tables' = also the per-phase arrays (7 phases x joints) that evaluation uses")
    print(f"{'profile':<34}{'solve':>8}{'+tables':>9}{'ruckig':>9}{'ratio':>8}{'ratio+t':>9}"
          f"{'max rel diff':>14}")  # fmt: skip
    for name, jerk, plan in cases:
        solve, tables, ours = time_trajkit(plan)
        solve_us, tables_us = (x / args.problems * 1e6 for x in (solve, tables))
        theirs_us, theirs = time_ruckig(p, args.ruckig_sample, jerk)
        theirs_us *= 1e6
        diff = np.max(np.abs(ours[: args.ruckig_sample] - theirs) / theirs)
        ratios = f"{theirs_us / solve_us:>8.1f}{theirs_us / tables_us:>9.1f}"
        print(f"{name:<34}{solve_us:>8.3f}{tables_us:>9.3f}{theirs_us:>9.3f}{ratios}{diff:>14.2e}")


if __name__ == "__main__":
    main()
