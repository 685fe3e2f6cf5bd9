"""Retiming planner waypoints: trajkit's retime beside MoveIt's TOTG, same lists, one process.

Run: python bench/bench_retime.py [--lists 10] [--repeats 5]

Planner-like waypoint lists (a 6-D random walk of 39 points from a random start,
steps uniform in [-0.15, 0.15] rad per joint, like a 38-segment OMPL path; fixed
seed), velocity limit 1 rad/s and acceleration limit 2 rad/s² on every joint. For
path tolerances of 0.01, 0.05 and 0.1 rad: ``tk.retime`` (parabolic blends, timed by
``tk.topp`` on its default grid) and TOTG (``totg.py``: circular blends and the
phase-plane integration of Kunz & Stilman 2012 as MoveIt implements it, 1 ms steps).
Per tolerance: the median time per call of each and their ratio, the median ratio
of the durations (trajkit / TOTG), the largest distance of each path from a waypoint
(each waypoint's closest sample, sampled at 5 kHz), and the largest limit violation
of each result sampled at 1 kHz (as a ratio of value to bound minus one; 0 when every
sample keeps its limit).

``totg.py`` is a step-by-step numpy port, some 30-40 times slower than MoveIt's C++,
so its time column measures the port, not MoveIt. Its excess comes from the 1 ms
backward-integration steps that cross a blend's end (see ``totg.py``).
"""

from __future__ import annotations

import argparse

import numpy as np

import trajkit as tk
from timing import median_seconds
from totg import totg

VMAX, AMAX = 1.0, 2.0
TOLERANCES = (0.01, 0.05, 0.1)


def excess(result) -> float:
    """The largest velocity or acceleration violation at 1 kHz, as a ratio minus one."""
    t = np.arange(0.0, result.duration, 1e-3)
    qd, qdd = result.evaluate(t, 1), result.evaluate(t, 2)
    return max(float(np.abs(qd).max() / VMAX - 1.0), float(np.abs(qdd).max() / AMAX - 1.0), 0.0)


def deviation(result, waypoints: np.ndarray) -> float:
    """The largest distance from a waypoint to the path, each to its closest sample."""
    q = result.evaluate(np.arange(0.0, result.duration, 2e-4))
    return max(float(np.linalg.norm(q - point, axis=1).min()) for point in waypoints)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--lists", type=int, default=10)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    limits = tk.Limits(velocity=VMAX, acceleration=AMAX)
    rng = np.random.default_rng(20261207)
    lists = [
        np.cumsum(np.vstack([rng.uniform(-1.0, 1.0, 6), rng.uniform(-0.15, 0.15, (38, 6))]), axis=0)
        for _ in range(args.lists)
    ]
    print(f"{'tolerance':>9} {'trajkit [ms]':>13} {'TOTG [ms]':>10} {'speed-up':>9} "
          f"{'duration ratio':>15} {'trajkit dev':>12} {'TOTG dev':>9} "
          f"{'trajkit excess':>15} {'TOTG excess':>12}")  # fmt: skip
    for tol in TOLERANCES:
        ours_t, theirs_t, ratios = [], [], []
        ours_dev, theirs_dev, ours_x, theirs_x = [], [], [], []
        for way in lists:

            def ours(way=way, tol=tol):
                return tk.retime(way, limits, path_tolerance=tol)

            def theirs(way=way, tol=tol):
                return totg(way, VMAX, AMAX, max_deviation=tol)

            mine, other = ours(), theirs()
            if not other.valid:
                raise RuntimeError(f"TOTG failed on a list at tolerance {tol}")
            ours_t.append(median_seconds(ours, args.repeats))
            theirs_t.append(median_seconds(theirs, args.repeats))
            ratios.append(mine.duration / other.duration)
            ours_dev.append(deviation(mine, way))
            theirs_dev.append(deviation(other, way))
            ours_x.append(excess(mine))
            theirs_x.append(excess(other))
        ours_ms, theirs_ms = 1e3 * np.median(ours_t), 1e3 * np.median(theirs_t)
        print(
            f"{tol:>9.2f} {ours_ms:>13.2f} {theirs_ms:>10.1f} {theirs_ms / ours_ms:>8.1f}x "
            f"{np.median(ratios):>15.4f} {max(ours_dev):>12.4f} {max(theirs_dev):>9.4f} "
            f"{max(ours_x):>15.2e} {max(theirs_x):>12.2e}"
        )


if __name__ == "__main__":
    main()
