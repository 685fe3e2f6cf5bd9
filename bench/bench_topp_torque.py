"""Torque- and tool-speed-limited time-optimal timing beside toppra, one process.

Run: python bench/bench_topp_torque.py [--paths 5] [--repeats 3]

The UR5 (trajkit's built-in, with its published masses, centres of mass and torque
limits: 150 N·m at the base, shoulder and elbow, 28 N·m at the wrist) along natural
cubic splines through 5 random waypoints in [-1.2, 1.2] rad, joint speed <= π rad/s,
joint acceleration <= 200 rad/s² (so that torque binds). trajkit: ``tk.topp`` with a
``TorqueLimit`` (and, in the last rows, a 0.5 m/s ``ToolLimit``). toppra 0.6:
``JointTorqueConstraint`` (interpolation discretization) with trajkit's own inverse
dynamics as its ``inv_dyn`` callback, called once per grid point and state as toppra
does; toppra has no tool-speed constraint. Per grid: median ms per call, the duration
ratio, and the worst torque-to-limit ratio sampled at 2 kHz minus one (0 if kept).
"""

from __future__ import annotations

import argparse

import numpy as np
import toppra as ta
import toppra.algorithm as algo
import toppra.constraint as constraint

import trajkit as tk
from timing import median_seconds
from trajkit.kinematics import UR5, inverse_dynamics

VMAX, AMAX = np.pi, 200.0


def torque_excess(limit: tk.TorqueLimit, q, qd, qdd) -> float:
    lower, upper = limit.bounds()
    tau = limit.values(q, qd, qdd)
    return max(float(np.maximum(tau / upper, tau / lower).max()) - 1.0, 0.0)


def toppra_timing(arm, limit, knots, way, grid):
    path = ta.SplineInterpolator(knots, way, bc_type="natural")
    lower, upper = limit.bounds()

    def dynamics(q, qd, qdd):
        return inverse_dynamics(arm, q, qd, qdd)

    interpolation = constraint.DiscretizationType.Interpolation
    constraints = [
        constraint.JointVelocityConstraint(np.tile([-VMAX, VMAX], (6, 1))),
        constraint.JointAccelerationConstraint(np.tile([-AMAX, AMAX], (6, 1)),
                                               discretization_scheme=interpolation),
        constraint.JointTorqueConstraint(dynamics, np.stack([lower, upper], axis=1), np.zeros(6),
                                         discretization_scheme=interpolation),
    ]  # fmt: skip
    instance = algo.TOPPRA(constraints, path, gridpoints=np.linspace(0, 1, grid + 1),
                           parametrizer="ParametrizeConstAccel")  # fmt: skip
    return instance.compute_trajectory()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--paths", type=int, default=5)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    ta.setup_logging("WARNING")
    arm = UR5()
    limit = tk.TorqueLimit(arm)
    tool = tk.ToolLimit(arm, speed=0.5)
    limits = tk.Limits(velocity=VMAX, acceleration=AMAX)
    rng = np.random.default_rng(20261207)
    knots = np.linspace(0.0, 1.0, 5)
    ways = [rng.uniform(-1.2, 1.2, (5, 6)) for _ in range(args.paths)]
    print(f"{'limits':>14} {'grid':>5} {'trajkit [ms]':>13} {'toppra [ms]':>12} "
          f"{'speed-up':>9} {'duration ratio':>15} {'trajkit excess':>15} "
          f"{'toppra excess':>14}")  # fmt: skip
    for grid in (100, 500, 1000):
        ours_t, theirs_t, ratios, ours_x, theirs_x = [], [], [], [], []
        for way in ways:
            path = tk.cubic_spline(knots, way, bc="natural")
            ours = tk.topp(path, limits, grid=grid, constraints=limit)
            theirs = toppra_timing(arm, limit, knots, way, grid)
            ours_t.append(median_seconds(
                lambda path=path, grid=grid: tk.topp(path, limits, grid=grid, constraints=limit),
                args.repeats))  # fmt: skip
            theirs_t.append(median_seconds(
                lambda way=way, grid=grid: toppra_timing(arm, limit, knots, way, grid),
                args.repeats))  # fmt: skip
            ratios.append(ours.duration / theirs.duration)
            t = np.arange(0.0, ours.end_time, 5e-4)
            ours_x.append(torque_excess(limit, ours(t), ours.velocity(t), ours.acceleration(t)))
            t = np.arange(0.0, theirs.duration, 5e-4)
            theirs_x.append(torque_excess(limit, theirs(t), theirs(t, 1), theirs(t, 2)))
        a, b = np.median(ours_t) * 1e3, np.median(theirs_t) * 1e3
        print(f"{'torque':>14} {grid:>5} {a:>13.2f} {b:>12.2f} {b / a:>8.2f}x "
              f"{np.median(ratios):>15.5f} {max(ours_x):>15.2e} "
              f"{max(theirs_x):>14.2e}")  # fmt: skip
    both = [limit, tool]
    for grid in (100, 500, 1000):
        times = []
        for way in ways:
            path = tk.cubic_spline(knots, way, bc="natural")
            times.append(median_seconds(
                lambda path=path, grid=grid: tk.topp(path, limits, grid=grid, constraints=both),
                args.repeats))  # fmt: skip
        print(f"{'torque + tool':>14} {grid:>5} {np.median(times) * 1e3:>13.2f} {'-':>12} "
              f"{'-':>9} {'-':>15} {'-':>15} {'-':>14}")  # fmt: skip


if __name__ == "__main__":
    main()
