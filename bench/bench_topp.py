"""Time-optimal path parameterization beside toppra, same paths, same grids, one process.

Run: python bench/bench_topp.py [--paths 10] [--repeats 7]

6-DOF paths through 5 random waypoints (natural cubic spline in s on [0, 1]),
velocity limit 1 rad/s and acceleration limit 2 rad/s² on every joint. For grids of
100, 500 and 1000 intervals: the median time per call, the resulting duration, and
the largest limit violation of each result sampled at 500 Hz (as a ratio of value to
bound minus one; 0 when every sample keeps its limit). toppra uses its
interpolation discretization and the constant-acceleration parametrizer.
"""

from __future__ import annotations

import argparse

import numpy as np
import toppra as ta
import toppra.algorithm as algo
import toppra.constraint as constraint

import trajkit as tk
from timing import median_seconds
from trajkit.time_optimal import topp

VMAX, AMAX = 1.0, 2.0


def violation(positions_velocities_accelerations) -> float:
    _, qd, qdd = positions_velocities_accelerations
    return max(float(np.abs(qd).max() / VMAX - 1.0), float(np.abs(qdd).max() / AMAX - 1.0), 0.0)


def ours_sampled(trajectory: tk.Trajectory) -> tuple:
    t = np.arange(0.0, trajectory.end_time, 1.0 / 500.0)
    return tuple(trajectory.evaluate(t, order) for order in range(3))


def toppra_sampled(result) -> tuple:
    t = np.arange(0.0, result.duration, 1.0 / 500.0)
    return result(t), result(t, 1), result(t, 2)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--paths", type=int, default=10)
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args()
    ta.setup_logging("WARNING")
    limits = tk.Limits(velocity=VMAX, acceleration=AMAX)
    rng = np.random.default_rng(20261201)
    waypoints = [rng.uniform(-1.0, 1.0, (5, 6)) for _ in range(args.paths)]
    knots = np.linspace(0.0, 1.0, 5)
    print(f"{'grid':>5} {'trajkit [ms]':>13} {'toppra [ms]':>12} {'speed-up':>9} "
          f"{'duration ratio':>15} {'trajkit excess':>15} {'toppra excess':>14}")  # fmt: skip
    for grid in (100, 500, 1000):
        ours_t, theirs_t, ratios, ours_x, theirs_x = [], [], [], [], []
        for way in waypoints:
            path = tk.cubic_spline(knots, way, bc="natural")
            spline = ta.SplineInterpolator(knots, way, bc_type="natural")
            constraints = [
                constraint.JointVelocityConstraint(np.array([[-VMAX, VMAX]] * 6)),
                constraint.JointAccelerationConstraint(
                    np.array([[-AMAX, AMAX]] * 6),
                    discretization_scheme=constraint.DiscretizationType.Interpolation,
                ),
            ]
            points = np.linspace(0.0, 1.0, grid + 1)

            def theirs(constraints=constraints, spline=spline, points=points):
                instance = algo.TOPPRA(constraints, spline, gridpoints=points,
                                       parametrizer="ParametrizeConstAccel")  # fmt: skip
                return instance.compute_trajectory()

            mine = topp(path, limits, grid=grid)
            other = theirs()
            ours_t.append(median_seconds(lambda path=path, grid=grid: topp(path, limits, grid=grid),
                                         args.repeats))  # fmt: skip
            theirs_t.append(median_seconds(theirs, args.repeats))
            ratios.append(mine.duration / other.duration)
            ours_x.append(violation(ours_sampled(mine)))
            theirs_x.append(violation(toppra_sampled(other)))
        ours_ms, theirs_ms = 1e3 * np.median(ours_t), 1e3 * np.median(theirs_t)
        print(
            f"{grid:>5} {ours_ms:>13.2f} {theirs_ms:>12.2f} {theirs_ms / ours_ms:>8.2f}x "
            f"{np.median(ratios):>15.5f} {max(ours_x):>15.2e} {max(theirs_x):>14.2e}"
        )


if __name__ == "__main__":
    main()
