"""Batch planning throughput beside ruckig called in a Python loop, same problems.

Run: python bench/bench_batch.py [--problems 100000] [--ruckig-sample 20000]

For each profile (acceleration-limited trapezoid = ruckig with infinite jerk;
jerk-limited S-curve) it plans B random rest-to-rest 6-DoF problems with
trajkit.batch in one call (median of several calls) and builds every problem's
full phase plan (what ruckig returns too), times ruckig on the same problems one by
one (median per-problem time over chunks of a sample), checks the durations agree,
and prints microseconds per problem and the ratio. A last row does the same for the
velocity interface (random start velocities and accelerations to random target
velocities; ruckig's ControlInterface.Velocity).
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
        "v0": rng.uniform(-1.0, 1.0, (count, NDOF)),
        "a0": rng.uniform(-1.0, 1.0, (count, NDOF)),
        "vf": rng.uniform(-1.0, 1.0, (count, NDOF)),
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


def time_ruckig(
    p: dict[str, np.ndarray], count: int, jerk: bool, velocity: bool = False
) -> tuple[float, np.ndarray]:
    from ruckig import ControlInterface, InputParameter, Ruckig, Trajectory

    otg, inp, out = Ruckig(NDOF), InputParameter(NDOF), Trajectory(NDOF)
    inp.max_velocity = p["vmax"]
    inp.max_acceleration = p["amax"]
    inp.max_jerk = p["jmax"] if jerk else [float("inf")] * NDOF
    durations = np.empty(count)
    # Lists, not numpy rows: ruckig converts a numpy row about 15x slower (2 us).
    if velocity:
        inp.control_interface = ControlInterface.Velocity
        rows = ("v0", "a0", "vf")
        names = ("current_velocity", "current_acceleration", "target_velocity")
    else:
        rows, names = ("q0", "qf"), ("current_position", "target_position")
    columns = [p[row][:count].tolist() for row in rows]
    chunk_times = []
    for begin in range(0, count, 1000):
        start = time.perf_counter()
        for i in range(begin, min(begin + 1000, count)):
            for name, column in zip(names, columns, strict=True):
                setattr(inp, name, column[i])
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
    cases = [("trapezoid (ruckig, infinite jerk)", False, False, lambda: tk.batch.trapezoidal(
        p["q0"], p["qf"], p["vmax"], p["amax"]))]  # fmt: skip
    cases.append(("S-curve (ruckig, jerk-limited)", True, False, lambda: tk.batch.scurve(
        p["q0"], p["qf"], p["vmax"], p["amax"], p["jmax"])))  # fmt: skip
    cases.append(("velocity interface (S-curve)", True, True, lambda: tk.batch.velocity_change(
        p["v0"], p["vf"], p["amax"], p["jmax"], a0=p["a0"])))  # fmt: skip
    print(f"B = {args.problems} random {NDOF}-DoF problems, time-synchronized: rest to rest,")
    print("then velocity changes from a random (v0, a0) to a random vf")
    print("us per problem; 'solve' = durations and every joint's profile parameters,")
    print("'+tables' = also the per-phase arrays (7 phases x joints) that evaluation uses")
    print(f"{'profile':<34}{'solve':>8}{'+tables':>9}{'ruckig':>9}{'ratio':>8}{'ratio+t':>9}"
          f"{'max rel diff':>14}")  # fmt: skip
    for name, jerk, velocity, plan in cases:
        solve, tables, ours = time_trajkit(plan)
        solve_us, tables_us = (x / args.problems * 1e6 for x in (solve, tables))
        theirs_us, theirs = time_ruckig(p, args.ruckig_sample, jerk, velocity)
        theirs_us *= 1e6
        diff = np.max(np.abs(ours[: args.ruckig_sample] - theirs) / theirs)
        ratios = f"{theirs_us / solve_us:>8.1f}{theirs_us / tables_us:>9.1f}"
        print(f"{name:<34}{solve_us:>8.3f}{tables_us:>9.3f}{theirs_us:>9.3f}{ratios}{diff:>14.2e}")


if __name__ == "__main__":
    main()
