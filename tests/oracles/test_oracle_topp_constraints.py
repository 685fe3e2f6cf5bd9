"""Torque-limited time-optimal timing beside toppra's ``JointTorqueConstraint``.

Same paths (natural cubic splines through random waypoints), same joint limits,
the same inverse dynamics (trajkit's, itself checked against Robotics Toolbox and
MuJoCo in ``test_oracle_dynamics.py`` and ``tests/kinematics/test_urdf.py``).
toppra runs on a fine grid (its converged optimum) with the interpolation
discretization; trajkit on the grids users pick. trajkit keeps the torques between
grid points too, toppra only at them: trajkit may be slightly longer, never shorter
by more than toppra's own grid error, and its dense torques never pass the limit.
"""

from __future__ import annotations

import numpy as np
import pytest

import trajkit as tk
from trajkit.kinematics import UR5, DHRow, SerialChain, inertials_from_dh, inverse_dynamics
from trajkit.time_optimal import TorqueLimit

ta = pytest.importorskip("toppra", reason="toppra is the oracle: pip install toppra")
algo = pytest.importorskip("toppra.algorithm", reason="toppra is the oracle: pip install toppra")
constraint = pytest.importorskip("toppra.constraint",
                                 reason="toppra is the oracle: pip install toppra")  # fmt: skip

#: toppra's grid for its converged optimum (its durations change by < 0.01% past it).
CONVERGED = 3000
#: How much longer than toppra's optimum trajkit may be on its grid (measured on these
#: families: at most 0.06% at 500 intervals, 0.07% for the UR5).
WITHIN = {500: 5e-3, 1000: 5e-3}


def toppra_timing(chain, inertials, gravity, knots, way, limits, torque, grid):
    """toppra's duration and its largest torque-to-limit ratio sampled at 5000 points."""
    ta.setup_logging("WARNING")
    path = ta.SplineInterpolator(knots, way, bc_type="natural")
    ndof = chain.ndof
    velocity = np.stack(limits.velocity.for_ndof("velocity", ndof), axis=1)
    acceleration = np.stack(limits.acceleration.for_ndof("acceleration", ndof), axis=1)
    lower, upper = torque

    def dynamics(q, qd, qdd):
        return inverse_dynamics(chain, q, qd, qdd, inertials=inertials, gravity=gravity)

    interpolation = constraint.DiscretizationType.Interpolation
    constraints = [
        constraint.JointVelocityConstraint(velocity),
        constraint.JointAccelerationConstraint(acceleration, discretization_scheme=interpolation),
        constraint.JointTorqueConstraint(dynamics, np.stack([lower, upper], axis=1),
                                         np.zeros(ndof), discretization_scheme=interpolation),
    ]  # fmt: skip
    instance = algo.TOPPRA(constraints, path, gridpoints=np.linspace(0, knots[-1], grid + 1),
                           parametrizer="ParametrizeConstAccel")  # fmt: skip
    result = instance.compute_trajectory()
    t = np.linspace(0.0, result.duration, 5001)
    tau = dynamics(result(t), result(t, 1), result(t, 2))
    return float(result.duration), float(np.maximum(tau / upper, tau / lower).max())


def compare(chain, inertials, gravity, way, limits, limit, grid):
    knots = np.linspace(0.0, 1.0, len(way))
    path = tk.cubic_spline(knots, way, bc="natural")
    ours = tk.topp(path, limits, grid=grid, constraints=limit)
    theirs, their_ratio = toppra_timing(chain, inertials, gravity, knots, way, limits,
                                        limit.bounds(), CONVERGED)  # fmt: skip
    t = np.linspace(0.0, ours.end_time, 20001)
    tau = limit.values(ours(t), ours.velocity(t), ours.acceleration(t))
    lower, upper = limit.bounds()
    our_ratio = float(np.maximum(tau / upper, tau / lower).max())
    assert ours.check(limits).ok
    assert our_ratio <= 1.0 + 1e-9
    assert theirs * (1 - 1e-3) < ours.duration <= theirs * (1 + WITHIN[grid])
    return ours.duration / theirs - 1, our_ratio, their_ratio


def two_link():
    chain = SerialChain.from_dh([DHRow(a=0.7), DHRow(a=0.5)])
    inertia = np.stack([np.diag([0.0, m * length**2 / 12, m * length**2 / 12])
                        for m, length in ((2.0, 0.7), (1.5, 0.5))])  # fmt: skip
    return chain, inertials_from_dh(chain, [2.0, 1.5], [[-0.35, 0, 0], [-0.25, 0, 0]], inertia)


@pytest.mark.parametrize("grid", [500, 1000])
def test_a_2r_arm_against_toppra(grid):
    chain, inertials = two_link()
    gravity = (0.0, -9.81, 0.0)
    limit = TorqueLimit(chain, [40.0, 12.0], inertials=inertials, gravity=gravity)
    limits = tk.Limits(velocity=3.0, acceleration=30.0)
    way = np.random.default_rng(0).uniform(-1.5, 1.5, (5, 2))
    _, ours, theirs = compare(chain, inertials, gravity, way, limits, limit, grid)
    assert ours > 0.999  # the torque limit binds
    assert theirs > 1.0  # toppra's sampled torque passes it between its grid points


@pytest.mark.slow
def test_2r_arms_against_toppra_on_many_paths():
    chain, inertials = two_link()
    gravity = (0.0, -9.81, 0.0)
    limit = TorqueLimit(chain, [40.0, 12.0], inertials=inertials, gravity=gravity)
    limits = tk.Limits(velocity=3.0, acceleration=30.0)
    gaps = [compare(chain, inertials, gravity,
                    np.random.default_rng(100 + seed).uniform(-1.5, 1.5, (5, 2)), limits, limit,
                    500)[0] for seed in range(8)]  # fmt: skip
    assert np.median(gaps) < 1e-3


@pytest.mark.slow
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_ur5_against_toppra(seed):
    arm = UR5()
    limit = TorqueLimit(arm)  # its own effort limits: 150 N·m, 28 N·m at the wrist
    limits = tk.Limits(velocity=np.pi, acceleration=200.0)
    way = np.random.default_rng(seed).uniform(-1.5, 1.5, (5, 6))
    inertials = arm.physical.inertials(6)
    _, ours, _ = compare(arm, inertials, (0.0, 0.0, -9.80665), way, limits, limit, 500)
    assert ours > 0.999
