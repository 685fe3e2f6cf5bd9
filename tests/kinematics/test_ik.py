"""Inverse kinematics: closed-form branches, the batched numerical solver, ik_path, failures.

Targets are made as FK of random configurations, so every one is reachable; they
are kept away from singularities (by manipulability) where a test compares joint
values, since there the joint values are ill-conditioned while FK(IK(x)) is not.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from trajkit.errors import InvalidInputError, UnreachableError
from trajkit.kinematics import (
    UR5,
    DHRow,
    IKSolution,
    Planar2R,
    RRBot,
    SerialChain,
    Spatial3R,
)

# Tolerances ------------------------------------------------------------------------
ROUND_TRIP = 1e-9  # FK(IK(x)) = x, relative to the arm's size
SAME_BRANCH = 1e-7  # joint values recovered away from singularities (rad)
AT_SINGULARITY = 1e-7  # joints at a singular target: arccos(1 - eps) ~ sqrt(eps); see
# singular_tolerance for arms of very unequal links
BATCH = 1e-12  # a batch against one-by-one solves of the same targets
WELL_CONDITIONED = 0.05  # minimum manipulability relative to its largest value

# Strategies ------------------------------------------------------------------------
angles = st.floats(-np.pi, np.pi, allow_nan=False)
lengths = st.one_of(st.floats(0.05, 1.0), st.floats(1.0, 50.0))


def wrapped(angle):
    """Angles in (-π, π]."""
    return np.pi - np.mod(np.pi - np.asarray(angle), 2 * np.pi)


def assert_same_angles(actual, expected, atol):
    np.testing.assert_allclose(wrapped(np.asarray(actual) - np.asarray(expected)), 0.0, atol=atol)


def singular_tolerance(l1: float, l2: float) -> float:
    """Joint error of a 2R at a workspace boundary (rad).

    There cos q2 = ±1 - O(eps (l1 + l2)² / (l1 l2)), so q2 is off by the square root.
    """
    return float(np.sqrt(16 * np.finfo(float).eps * (l1 + l2) ** 2 / (l1 * l2)))


def ur5_configurations(count: int, seed: int, minimum: float = 1e-3) -> np.ndarray:
    """Random UR5 configurations away from singularities."""
    ur5 = UR5()
    q = np.random.default_rng(seed).uniform(-np.pi, np.pi, (4 * count, 6))
    return q[ur5.manipulability(q) > minimum][:count]


class LimitedPlanar2R(Planar2R):
    """A Planar2R whose joints have position ranges (the built-ins have none)."""

    def __init__(self, l1, l2, lower, upper):
        super().__init__(l1, l2, name="limited 2R")
        joints = [
            dataclasses.replace(j, lower=lo, upper=up)
            for j, lo, up in zip(self.joints, lower, upper, strict=True)
        ]
        SerialChain.__init__(self, joints, base=self.base, tool=self.tool, name=self.name)


# ------------------------------------------------------------------------ Planar2R
@given(q1=angles, q2=angles, l1=lengths, l2=lengths)
def test_planar2r_both_branches_round_trip(q1, q2, l1, l2):
    assume(abs(np.sin(q2)) > WELL_CONDITIONED)
    arm = Planar2R(l1, l2)
    target = arm.fk([q1, q2])[:3, 3]
    atol = ROUND_TRIP * (l1 + l2)
    branches = arm.ik_branches(target)
    assert branches.shape == (2, 2)
    for index, name, sign in ((0, "elbow_positive", 1.0), (1, "elbow_negative", -1.0)):
        by_name, by_index = arm.ik(target, branch=name), arm.ik(target, branch=index)
        np.testing.assert_array_equal(by_name.q, by_index.q)
        np.testing.assert_array_equal(by_name.q, branches[index])
        assert by_name.success is True and by_name.method == "analytic"
        assert by_name.iterations == 0 and by_name.orientation_error == 0.0
        assert sign * by_name.q[1] >= 0
        np.testing.assert_allclose(arm.fk(by_name.q)[:3, 3], target, rtol=0, atol=atol)
        assert by_name.position_error <= atol
    # The branch with the sign of q2 is the configuration the target came from.
    assert_same_angles(branches[0 if q2 > 0 else 1], [q1, q2], SAME_BRANCH)
    # 2-D targets are points in the arm's plane.
    np.testing.assert_array_equal(arm.ik(target[:2], branch=1).q, branches[1])
    assert arm.ik(target).q.tolist() == branches[0].tolist()  # default: branch 0


@given(q1=angles, q2=angles, turns=st.integers(-3, 3))
def test_planar2r_seed_picks_the_nearest_branch_and_turn(q1, q2, turns):
    # The two elbows lie at least 2 |q2| apart; the seed is 0.07 off.
    assume(abs(np.sin(q2)) > 0.3)
    arm = Planar2R(1.0, 0.6)
    q = np.array([q1, q2])
    target = arm.fk(q)
    seed = q + np.array([2 * np.pi * turns + 0.05, -0.05])
    solution = arm.ik(target, q_seed=seed)
    # The joints are continuous: the solution lies by the seed, on the seed's turn.
    np.testing.assert_allclose(solution.q, q + np.array([2 * np.pi * turns, 0.0]), atol=SAME_BRANCH)
    other = arm.ik(target, q_seed=[q1, -q2])  # the mirrored elbow's seed
    assert np.sign(other.q[1]) == -np.sign(q2)


@given(
    l1=lengths,
    l2=lengths,
    phi=angles,
    excess=st.sampled_from([0.5, 0.125, 1.5, 3.0]),
)
def test_planar2r_unreachable_says_how_far(l1, l2, phi, excess):
    arm = Planar2R(l1, l2)
    distance = l1 + l2 + excess
    target = [distance * np.cos(phi), distance * np.sin(phi), 0.0]
    with pytest.raises(UnreachableError, match=f"{excess:g} m beyond the annulus") as excinfo:
        arm.ik(target)
    assert type(excinfo.value) is UnreachableError
    assert "out of reach of planar 2R" in str(excinfo.value)
    assert np.all(np.isnan(arm.ik_branches(target)))


def test_planar2r_unreachable_by_exactly_half_a_metre():
    with pytest.raises(UnreachableError, match=r"0\.5 m beyond") as excinfo:
        Planar2R(1.0, 0.7).ik([0.0, 2.2, 0.0])
    assert type(excinfo.value) is UnreachableError


@pytest.mark.parametrize("phi", [0.0, 1.0, -2.5])
def test_planar2r_inner_hole_is_unreachable(phi):
    arm = Planar2R(1.0, 0.4)  # reaches 0.6 m <= r <= 1.4 m
    r = 0.6 - 0.25
    with pytest.raises(UnreachableError, match=r"0\.25 m beyond the annulus 0\.6 m <= r <= 1\.4 m"):
        arm.ik([r * np.cos(phi), r * np.sin(phi), 0.0])
    with pytest.raises(UnreachableError, match="beyond the annulus"):
        arm.ik([0.0, 0.0])  # the base itself


def test_planar2r_target_off_its_plane():
    arm = Planar2R(1.0, 0.5, axis_offsets=(0.1, 0.0, 0.0))
    with pytest.raises(UnreachableError, match=r"0\.3 m beyond"):
        arm.ik([1.0, 0.0, 0.4])  # the plane is at z = 0.1
    assert arm.ik([1.0, 0.0, 0.1]).success


@given(phi=angles, l1=lengths, l2=lengths)
def test_planar2r_full_stretch_is_reachable_and_both_branches_meet(phi, l1, l2):
    arm = Planar2R(l1, l2)
    size = l1 + l2
    at_singularity = singular_tolerance(l1, l2)
    for target in (
        [size * np.cos(phi), size * np.sin(phi), 0.0],  # exactly on the boundary
        arm.fk([phi, 0.0])[:3, 3],  # on it up to FK's rounding
    ):
        branches = arm.ik_branches(target)
        np.testing.assert_allclose(branches[:, 1], 0.0, atol=at_singularity)
        assert_same_angles(branches[:, 0], [phi, phi], at_singularity)
        solution = arm.ik(target)
        assert solution.success
        np.testing.assert_allclose(arm.fk(solution.q)[:3, 3], target, atol=ROUND_TRIP * size)


@given(phi=angles, l1=lengths, l2=lengths)
def test_planar2r_inner_boundary_folds_the_elbow(phi, l1, l2):
    assume(abs(l1 - l2) > 1e-3 * (l1 + l2))
    arm = Planar2R(l1, l2)
    r = abs(l1 - l2)
    target = [r * np.cos(phi), r * np.sin(phi), 0.0]
    branches = arm.ik_branches(target)
    np.testing.assert_allclose(np.abs(branches[:, 1]), np.pi, atol=singular_tolerance(l1, l2))
    np.testing.assert_allclose(
        arm.fk(branches)[:, :3, 3], [target] * 2, atol=ROUND_TRIP * (l1 + l2)
    )


@pytest.mark.parametrize("length", [0.3, 1.0, 7.0])
def test_planar2r_base_is_reachable_when_links_are_equal(length):
    arm = Planar2R(length, length)
    solution = arm.ik([0.0, 0.0, 0.0])
    assert solution.success
    assert abs(solution.q[1]) == pytest.approx(np.pi, abs=AT_SINGULARITY)
    np.testing.assert_allclose(arm.fk(solution.q)[:3, 3], 0.0, atol=ROUND_TRIP * length)


def test_planar2r_with_a_base_takes_world_or_plane_targets():
    base = np.eye(4)
    base[:3, :3] = [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
    base[:3, 3] = [0.5, -1.0, 2.0]
    arm = Planar2R(1.0, 0.5, base=base, axis_offsets=(0.0, 0.2, 0.0))
    q = np.array([0.4, 1.2])
    world = arm.fk(q)[:3, 3]
    plane = np.linalg.solve(base[:3, :3], world - base[:3, 3])
    assert plane[2] == pytest.approx(0.2, abs=1e-12)
    for target in (world, arm.fk(q), plane[:2]):
        np.testing.assert_allclose(arm.ik(target).q, q, atol=SAME_BRANCH)


# ------------------------------------------------------------------------ RRBot
@given(q1=angles, q2=angles)
def test_rrbot_round_trip_and_seeded_recovery(q1, q2):
    assume(abs(np.sin(q2)) > WELL_CONDITIONED)
    bot = RRBot()
    q = np.array([q1, q2])
    target = bot.fk(q)
    for branch in (0, 1):
        solution = bot.ik(target, branch=branch)
        np.testing.assert_allclose(bot.fk(solution.q)[:3, 3], target[:3, 3], atol=ROUND_TRIP * 4)
    np.testing.assert_allclose(bot.ik(target, q_seed=q + 0.1).q, q, atol=SAME_BRANCH)
    np.testing.assert_allclose(bot.ik(target[:3, 3], q_seed=q - 0.1).q, q, atol=SAME_BRANCH)


def test_rrbot_unreachable_above_its_reach():
    with pytest.raises(UnreachableError, match=r"0\.2 m beyond") as excinfo:
        RRBot().ik([0.0, 0.2, 1.95 + 1.85 + 0.2])
    assert "RRBot" in str(excinfo.value)


# ------------------------------------------------------------------------ Spatial3R
@given(q=st.tuples(angles, angles, angles), l0=lengths, l1=lengths, l2=lengths, l3=lengths)
def test_spatial3r_all_four_branches_round_trip(q, l0, l1, l2, l3):
    arm = Spatial3R(l0, l1, l2, l3)
    q = np.array(q)
    reach = l2 * np.cos(q[1]) + l3 * np.cos(q[1] + q[2])
    # Singular where the elbow is straight or folded, or the wrist is on joint 1's plane.
    assume(abs(np.sin(q[2])) > WELL_CONDITIONED and abs(reach) > WELL_CONDITIONED * (l2 + l3))
    target = arm.fk(q)[:3, 3]
    size = l0 + l1 + l2 + l3
    branches = arm.ik_branches(target)
    assert branches.shape == (4, 3)
    np.testing.assert_allclose(arm.fk(branches)[:, :3, 3], [target] * 4, atol=ROUND_TRIP * size)
    # Branch signs as named: forward/backward reach, elbow q3 >= 0 / <= 0.
    forward = l2 * np.cos(branches[:, 1]) + l3 * np.cos(branches[:, 1] + branches[:, 2])
    assert np.all(forward[:2] > 0) and np.all(forward[2:] < 0)
    assert np.all(branches[[0, 2], 2] > 0) and np.all(branches[[1, 3], 2] < 0)
    # Four different solutions, one of them the configuration the target came from.
    distances = [np.abs(wrapped(b - q)).max() for b in branches]
    assert sorted(distances)[0] < SAME_BRANCH and sorted(distances)[1] > 1e-3
    home = int(np.argmin(distances))
    assert arm.ik(target, branch=home).q.tolist() == branches[home].tolist()
    np.testing.assert_allclose(arm.ik(target, q_seed=q).q, q, atol=SAME_BRANCH)


def test_spatial3r_seed_selects_each_branch():
    arm = Spatial3R()
    target = arm.fk([0.3, 0.5, 1.0])
    branches = arm.ik_branches(target)
    for index, branch in enumerate(branches):
        chosen = arm.ik(target, q_seed=branch + 0.05)
        np.testing.assert_allclose(chosen.q, branch, atol=SAME_BRANCH)
        by_name = arm.ik(target, branch=arm.branch_names[index])
        np.testing.assert_array_equal(by_name.q, branch)


def test_spatial3r_singular_targets_are_reachable():
    arm = Spatial3R()
    stretched = arm.fk([0.3, 0.4, 0.0])  # elbow straight: on the outer shell
    branches = arm.ik_branches(stretched)
    np.testing.assert_allclose(branches[:, 2], 0.0, atol=AT_SINGULARITY)
    np.testing.assert_allclose(arm.fk(branches)[:, :3, 3], [stretched[:3, 3]] * 4, atol=35e-9)
    # Wrist in joint 1's plane: forward and backward coincide.
    q2 = 0.5
    q3 = np.pi - np.arccos(8 * np.cos(q2) / 12) - q2  # l2 cos q2 + l3 cos(q2 + q3) = 0
    flat = arm.fk([0.2, q2, q3])
    solution = arm.ik(flat)
    assert solution.success
    np.testing.assert_allclose(arm.fk(solution.q)[:3, 3], flat[:3, 3], atol=35 * ROUND_TRIP)


@pytest.mark.parametrize(
    ("target", "message"),
    [
        ([8.0, 12.0, 5.0], r"2 beyond the workspace .*at least 10 from joint 1's axis"),
        ([0.0, 15.0, 5.0], r"10 beyond"),  # on joint 1's axis
        ([0.0, 40.0, 5.0], r"17\.6393 beyond the workspace \(distance from joint 1 between "
                           r"10\.7703 and 22\.3607"),
        ([1.0, 0.0, 5.0], r"9\.77033 beyond"),  # next to joint 1: inside the inner shell
    ],
)  # fmt: skip
def test_spatial3r_unreachable_targets(target, message):
    arm = Spatial3R()
    with pytest.raises(UnreachableError, match=message) as excinfo:
        arm.ik(target)
    assert type(excinfo.value) is UnreachableError
    assert np.all(np.isnan(arm.ik_branches(target)))


# ------------------------------------------------------------------------ analytic: batches
@pytest.mark.parametrize("arm", [Planar2R(1.0, 0.5), RRBot(), Spatial3R()], ids=repr)
def test_analytic_batch_matches_single_targets(arm):
    rng = np.random.default_rng(41)
    q = rng.uniform(-np.pi, np.pi, (25, arm.ndof))
    targets = arm.fk(q)[:, :3, 3]
    batch = arm.ik(targets)
    assert batch.q.shape == (25, arm.ndof) and batch.success.shape == (25,)
    seeded = arm.ik(targets, q_seed=q)
    branch = arm.ik(targets, branch=1)
    every = arm.ik_branches(targets)
    assert every.shape == (25, len(arm.branch_names), arm.ndof)
    for k in range(25):
        np.testing.assert_array_equal(arm.ik(targets[k]).q, batch.q[k])
        np.testing.assert_array_equal(arm.ik(targets[k], q_seed=q[k]).q, seeded.q[k])
        np.testing.assert_array_equal(arm.ik(targets[k], branch=1).q, branch.q[k])
        np.testing.assert_array_equal(arm.ik_branches(targets[k]), every[k])
    np.testing.assert_allclose(seeded.q, q, atol=1e-6)  # near-singular draws lose digits
    one_seed = arm.ik(targets, q_seed=q[0])  # one seed for every target
    assert one_seed.q.shape == (25, arm.ndof)


def test_analytic_failures_without_raising():
    arm = Planar2R(1.0, 0.5)
    targets = np.array([[1.0, 0.5, 0.0], [3.0, 0.0, 0.0], [0.1, 0.0, 0.0]])
    result = arm.ik(targets, raise_on_failure=False)
    assert result.success.tolist() == [True, False, False]
    assert np.all(np.isfinite(result.q[0])) and np.all(np.isnan(result.q[1:]))
    assert np.all(np.isinf(result.position_error[1:])) and result.position_error[0] < 1e-12
    assert np.all(np.isnan(arm.ik_branches(targets)[1:]))
    with pytest.raises(UnreachableError, match=r"target 1 \[3\. 0\. 0\.\] is out of reach"):
        arm.ik(targets)
    single = arm.ik(targets[1], raise_on_failure=False)
    assert single.success is False and np.all(np.isnan(single.q))
    assert single.position_error == np.inf


def test_analytic_unreachable_error_carries_the_index():
    targets = np.array([[1.0, 0.5, 0.0], [3.0, 0.0, 0.0]])
    with pytest.raises(UnreachableError) as excinfo:
        Planar2R(1.0, 0.5).ik(targets)
    assert excinfo.value.index == 1


def test_analytic_joint_ranges_pick_the_branch_inside_them():
    arm = LimitedPlanar2R(1.0, 0.5, lower=[-np.pi, -np.pi], upper=[np.pi, 0.0])
    target = arm.fk([0.3, 0.8])  # elbow_positive is out of q2's range
    solution = arm.ik(target)
    assert solution.q[1] <= 0.0 and solution.success
    np.testing.assert_allclose(arm.fk(solution.q)[:3, 3], target[:3, 3], atol=ROUND_TRIP)
    with pytest.raises(UnreachableError, match="no solution of limited 2R within its joint ranges"):
        arm.ik(target, branch=0)
    assert arm.ik(target, branch=0, raise_on_failure=False).success is False


def test_analytic_joint_ranges_are_searched_modulo_a_turn():
    arm = LimitedPlanar2R(1.0, 0.5, lower=[np.pi / 2, -np.pi], upper=[3 * np.pi / 2, np.pi])
    q = np.array([np.pi + 0.3, 0.8])  # inside the ranges; arctan2 returns q1 - 2π
    solution = arm.ik(arm.fk(q))
    assert solution.success
    np.testing.assert_allclose(solution.q, q, atol=SAME_BRANCH)


# ------------------------------------------------------------------------ UR5 (numerical)
# Configurations near a singularity are filtered out by design (about a third); the
# derandomized CI profile once drew a run of them, failing the filter health check.
@settings(max_examples=40, suppress_health_check=[HealthCheck.filter_too_much])
@given(
    q=st.tuples(*[st.floats(-np.pi, np.pi)] * 6),
    noise=st.tuples(*[st.floats(-0.05, 0.05)] * 6),
)
def test_ur5_full_pose_from_a_nearby_seed(q, noise):
    ur5 = UR5()
    q = np.array(q)
    # Far enough from the elbow, wrist and shoulder singularities that the seed lies
    # nearer this configuration than any of the other seven solutions.
    shoulder = (
        -0.425 * np.cos(q[1]) - 0.39225 * np.cos(q[1] + q[2]) + 0.09465 * np.sin(q[1:4].sum())
    )
    assume(abs(np.sin(q[2])) > 0.2 and abs(np.sin(q[4])) > 0.2 and abs(shoulder) > 0.1)
    target = ur5.fk(q)
    solution = ur5.ik(target, q_seed=q + np.array(noise))
    assert solution.success is True and solution.method == "numerical"
    assert 1 <= solution.iterations <= 50
    np.testing.assert_allclose(ur5.fk(solution.q), target, rtol=0, atol=ROUND_TRIP)
    assert solution.position_error <= ROUND_TRIP and solution.orientation_error <= ROUND_TRIP
    assert solution.residual == solution.position_error + solution.orientation_error
    np.testing.assert_allclose(solution.q, q, atol=1e-6)  # the seed's branch


def test_ur5_full_pose_cold():
    ur5 = UR5()
    q = ur5_configurations(60, seed=43)
    targets = ur5.fk(q)
    solution = ur5.ik(targets)
    assert solution.q.shape == (60, 6) and np.all(solution.success)
    np.testing.assert_allclose(ur5.fk(solution.q), targets, rtol=0, atol=ROUND_TRIP)
    assert np.all(solution.q >= ur5.lower) and np.all(solution.q <= ur5.upper)
    assert np.all(solution.position_error <= ROUND_TRIP)
    assert np.all(solution.orientation_error <= ROUND_TRIP)


def test_ur5_position_only():
    ur5 = UR5()
    q = ur5_configurations(40, seed=47)
    points = ur5.fk(q)[:, :3, 3]
    cold = ur5.ik(points, position_only=True)
    warm = ur5.ik(ur5.fk(q), q_seed=q + 0.05, position_only=True)  # poses: position taken
    for solution in (cold, warm):
        assert np.all(solution.success)
        np.testing.assert_array_equal(solution.orientation_error, 0.0)
        np.testing.assert_allclose(ur5.fk(solution.q)[:, :3, 3], points, atol=ROUND_TRIP)
    single = ur5.ik(points[0], position_only=True)
    assert single.success is True and single.orientation_error == 0.0


def test_ur5_batch_matches_single_solves():
    ur5 = UR5()
    q = ur5_configurations(12, seed=53)
    seeds = q + np.random.default_rng(1).normal(0.0, 0.05, q.shape)
    targets = ur5.fk(q)
    batch = ur5.ik(targets, q_seed=seeds)
    for k in range(12):
        single = ur5.ik(targets[k], q_seed=seeds[k])
        np.testing.assert_allclose(single.q, batch.q[k], atol=BATCH)
        assert single.success == batch.success[k]
    # One seed for all targets broadcasts.
    assert ur5.ik(targets, q_seed=seeds[0]).q.shape == (12, 6)


def test_ur5_tolerance_controls_the_residual():
    ur5 = UR5()
    q = ur5_configurations(10, seed=59)
    targets = ur5.fk(q)
    loose = ur5.ik(targets, q_seed=q + 0.1, tolerance=1e-3)
    assert np.all(loose.position_error <= 1e-3 * ur5.reach())
    assert np.all(loose.orientation_error <= 1e-3)
    tight = ur5.ik(targets, q_seed=q + 0.1, tolerance=1e-13)
    assert np.all(tight.position_error <= 1e-12)


def test_ur5_unreachable_target_five_metres_away():
    ur5 = UR5()
    far = np.eye(4)
    far[:3, 3] = [5.0, 0.0, 0.0]
    with pytest.raises(
        UnreachableError, match=r"closest tool pose found is [0-9.]+ m and"
    ) as excinfo:
        ur5.ik(far, restarts=2)
    assert type(excinfo.value) is UnreachableError and excinfo.value.index == 0
    assert "after 3 attempts" in str(excinfo.value)
    result = ur5.ik(far, restarts=2, raise_on_failure=False)
    assert result.success is False and result.position_error > 4.0
    assert np.all(np.isfinite(result.q))  # the closest configuration found
    mixed = np.stack([ur5.fk(np.full(6, 0.4)), far, far])
    with pytest.raises(UnreachableError, match=r"\(target 1, 2 of 3 failed\)") as excinfo:
        ur5.ik(mixed, restarts=1)
    assert excinfo.value.index == 1
    result = ur5.ik(mixed, restarts=1, raise_on_failure=False)
    assert result.success.tolist() == [True, False, False]


# ------------------------------------------------------------------------ joint ranges
LIMITED = SerialChain.from_dh(
    [
        DHRow(a=1.0, lower=-0.5, upper=1.5),
        DHRow(a=0.8, lower=0.2, upper=2.5),  # elbow up only
        DHRow(a=0.3, lower=-1.0, upper=1.0),
    ]
)


@given(q=st.tuples(st.floats(-0.5, 1.5), st.floats(0.2, 2.5), st.floats(-1.0, 1.0)))
def test_numerical_ik_respects_joint_ranges(q):
    target = LIMITED.fk(q)
    solution = LIMITED.ik(target, raise_on_failure=False)
    assert np.all(solution.q >= LIMITED.lower) and np.all(solution.q <= LIMITED.upper)
    if solution.success:
        np.testing.assert_allclose(LIMITED.fk(solution.q), target, atol=ROUND_TRIP * 2.1)
    # A seed outside the ranges is moved inside them first.
    seeded = LIMITED.ik(target, q_seed=[3.0, -3.0, 3.0], raise_on_failure=False)
    assert np.all(seeded.q >= LIMITED.lower) and np.all(seeded.q <= LIMITED.upper)


def test_numerical_ik_solves_inside_ranges_from_the_middle():
    q = np.random.default_rng(61).uniform(LIMITED.lower, LIMITED.upper, (40, 3))
    targets = LIMITED.fk(q)
    solution = LIMITED.ik(targets)
    assert np.all(solution.success)
    assert np.all(solution.q >= LIMITED.lower) and np.all(solution.q <= LIMITED.upper)
    np.testing.assert_allclose(LIMITED.fk(solution.q), targets, atol=ROUND_TRIP * 2.1)


def test_numerical_ik_refuses_solutions_outside_ranges():
    chain = SerialChain.from_dh(
        [DHRow(a=1.0, lower=-0.5, upper=0.5), DHRow(a=1.0, lower=0.0, upper=1.0)]
    )
    # Both solutions of this point, (0, -0.9) and (-0.9, 0.9), leave a range.
    target = chain.fk([0.0, -0.9])[:3, 3]  # FK does not check ranges
    with pytest.raises(UnreachableError, match="outside the joint ranges"):
        chain.ik(target, position_only=True, restarts=3)
    result = chain.ik(target, position_only=True, restarts=3, raise_on_failure=False)
    assert result.success is False
    assert chain.lower[0] <= result.q[0] <= chain.upper[0]
    assert chain.lower[1] <= result.q[1] <= chain.upper[1]


def test_numerical_ik_wraps_unbounded_joints_near_the_seed():
    chain = SerialChain.from_dh([DHRow(a=1.0), DHRow(a=0.5)])  # continuous joints
    q = np.array([0.4, 1.0])
    target = chain.fk(q)[:3, 3]
    solution = chain.ik(target, q_seed=q + np.array([4 * np.pi + 0.1, 0.1]), position_only=True)
    np.testing.assert_allclose(solution.q, q + np.array([4 * np.pi, 0.0]), atol=1e-8)


# ------------------------------------------------------------------------ ik_path
def straight_line(samples: int) -> tuple[np.ndarray, np.ndarray]:
    start = np.array([0.3, -1.2, 1.5, -1.9, -1.57, 0.2])
    poses = np.repeat(UR5().fk(start)[np.newaxis], samples, axis=0)
    poses[:, :3, 3] += np.linspace(0.0, 1.0, samples)[:, np.newaxis] * [0.1, 0.15, -0.1]
    return start, poses


def test_ik_path_follows_one_branch():
    ur5 = UR5()
    start, poses = straight_line(300)
    solution = ur5.ik_path(poses, start)
    assert np.all(solution.success) and solution.q.shape == (300, 6)
    np.testing.assert_allclose(solution.q[0], start, atol=1e-8)
    assert np.abs(np.diff(solution.q, axis=0)).max() < 0.01
    np.testing.assert_allclose(ur5.fk(solution.q), poses, atol=ROUND_TRIP)
    points = ur5.ik_path(poses[:, :3, 3], start, position_only=True)
    np.testing.assert_allclose(ur5.fk(points.q)[:, :3, 3], poses[:, :3, 3], atol=ROUND_TRIP)


def test_ik_path_reports_an_unreachable_target():
    ur5 = UR5()
    start, poses = straight_line(40)
    poses[25:, :3, 3] += [5.0, 0.0, 0.0]
    with pytest.raises(UnreachableError, match=r"target \d+ is not reached") as excinfo:
        ur5.ik_path(poses, start)
    assert type(excinfo.value) is UnreachableError
    assert excinfo.value.index >= 25
    assert f"target {excinfo.value.index} is not reached" in str(excinfo.value)


def test_ik_path_index_is_the_first_unreachable_target():
    # 40 targets give knots 0, 3, 5, ..., 23, 26, ...: target 25 is no knot.
    start, poses = straight_line(40)
    poses[25:, :3, 3] += [5.0, 0.0, 0.0]
    with pytest.raises(UnreachableError) as excinfo:
        UR5().ik_path(poses, start)
    assert excinfo.value.index == 25


def test_ik_path_refuses_one_target():
    with pytest.raises(InvalidInputError, match="sequence of poses or positions") as excinfo:
        UR5().ik_path(np.eye(4))
    assert type(excinfo.value) is InvalidInputError


# ------------------------------------------------------------------------ IKSolution
def test_ik_solution_residual():
    solution = IKSolution(
        np.zeros(2), np.array([True, False]), np.array([1e-3, 2.0]), np.array([0.5, 0.0])
    )
    np.testing.assert_array_equal(solution.residual, [0.501, 2.0])
    assert solution.method == "numerical" and solution.iterations == 0


# ------------------------------------------------------------------------ bad input
def _bad_ik_input():
    ur5, planar, spatial = UR5(), Planar2R(1.0, 0.5), Spatial3R()
    pose = ur5.fk(np.full(6, 0.3))
    scaled = pose.copy()
    scaled[:3, :3] *= 2.0
    mirrored = pose.copy()
    mirrored[:3, 0] *= -1.0  # orthonormal, determinant -1
    return [
        pytest.param(
            lambda: ur5.ik(np.full((4, 4), np.nan)),
            InvalidInputError,
            "target must be finite",
            id="ur5 NaN target",
        ),
        pytest.param(
            lambda: ur5.ik([np.inf, 0, 0], position_only=True),
            InvalidInputError,
            "target must be finite",
            id="ur5 inf position",
        ),
        pytest.param(
            lambda: ur5.ik(np.zeros(5)),
            InvalidInputError,
            r"target must be a 4x4 pose, a 3-vector position, or a stack of them, got shape \(5,\)",
            id="ur5 target (5,)",
        ),
        pytest.param(
            lambda: ur5.ik(np.zeros((3, 4))),
            InvalidInputError,
            r"got shape \(3, 4\)",
            id="ur5 target (3, 4)",
        ),
        pytest.param(
            lambda: ur5.ik("pose"),
            InvalidInputError,
            "target must be numeric",
            id="ur5 target text",
        ),
        pytest.param(
            lambda: ur5.ik([0.1, 0.2, 0.3]),
            InvalidInputError,
            "pass position_only=True",
            id="ur5 position without flag",
        ),
        pytest.param(
            lambda: ur5.ik(scaled),
            InvalidInputError,
            "not a rotation matrix",
            id="ur5 scaled rotation",
        ),
        pytest.param(
            lambda: ur5.ik(mirrored), InvalidInputError, "determinant", id="ur5 reflection"
        ),
        pytest.param(
            lambda: ur5.ik(pose, q_seed=np.zeros(5)),
            InvalidInputError,
            r"q_seed must have shape \(6,\)",
            id="ur5 seed length",
        ),
        pytest.param(
            lambda: ur5.ik(pose, q_seed=[np.nan] * 6),
            InvalidInputError,
            "q_seed must be finite",
            id="ur5 seed NaN",
        ),
        pytest.param(
            lambda: ur5.ik(np.stack([pose] * 3), q_seed=np.zeros((2, 6))),
            InvalidInputError,
            "q_seed gives 2 seeds for 3 targets",
            id="ur5 seed count",
        ),
        pytest.param(
            lambda: ur5.ik(pose, tolerance=0.0),
            InvalidInputError,
            "tolerance must be > 0",
            id="ur5 tolerance zero",
        ),
        pytest.param(
            lambda: ur5.ik(pose, tolerance=np.nan),
            InvalidInputError,
            "tolerance must be finite",
            id="ur5 tolerance NaN",
        ),
        pytest.param(
            lambda: ur5.ik(pose, max_iterations=0),
            InvalidInputError,
            "max_iterations must be >= 1",
            id="ur5 iterations",
        ),
        pytest.param(
            lambda: ur5.ik(pose, restarts=-1), InvalidInputError, "restarts >= 0", id="ur5 restarts"
        ),
        pytest.param(
            lambda: ur5.ik_path(np.stack([pose] * 2), np.zeros(4)),
            InvalidInputError,
            r"q_seed must have shape \(6,\)",
            id="ur5 path seed",
        ),
        pytest.param(
            lambda: planar.ik([np.nan, 0.0, 0.0]),
            InvalidInputError,
            "target must be finite",
            id="planar NaN target",
        ),
        pytest.param(
            lambda: planar.ik([np.inf, 0.0]),
            InvalidInputError,
            "target must be finite",
            id="planar inf 2-D target",
        ),
        pytest.param(
            lambda: planar.ik(np.zeros(5)),
            InvalidInputError,
            r"got shape \(5,\)",
            id="planar target (5,)",
        ),
        pytest.param(
            lambda: planar.ik(np.zeros((2, 4, 3))),
            InvalidInputError,
            r"got shape \(2, 4, 3\)",
            id="planar target (2, 4, 3)",
        ),
        pytest.param(
            lambda: planar.ik(scaled),
            InvalidInputError,
            "not a rotation matrix",
            id="planar rotation",
        ),
        pytest.param(
            lambda: planar.ik([1.0, 0.5, 0.0], branch="up"),
            InvalidInputError,
            r"branch must be one of \['elbow_positive', 'elbow_negative'\], got 'up'",
            id="planar branch name",
        ),
        pytest.param(
            lambda: planar.ik([1.0, 0.5, 0.0], branch=2),
            InvalidInputError,
            "branch must be an index 0..1",
            id="planar branch index",
        ),
        pytest.param(
            lambda: planar.ik([1.0, 0.5, 0.0], branch=-1),
            InvalidInputError,
            "branch must be an index 0..1",
            id="planar branch negative",
        ),
        pytest.param(
            lambda: planar.ik([1.0, 0.5, 0.0], branch=1.0),
            InvalidInputError,
            "branch must be an index",
            id="planar branch float",
        ),
        pytest.param(
            lambda: planar.ik(np.eye(4), position_only=False),
            InvalidInputError,
            "Planar2R sets only its tool position; call ik with position_only=True",
            id="planar full pose",
        ),
        pytest.param(
            lambda: planar.ik([1.0, 0.5, 0.0], q_seed=[0.0] * 3),
            InvalidInputError,
            r"q_seed must have shape \(2,\)",
            id="planar seed length",
        ),
        pytest.param(
            lambda: planar.ik([1.0, 0.5, 0.0], q_seed=[np.inf, 0.0]),
            InvalidInputError,
            "q_seed must be finite",
            id="planar seed inf",
        ),
        pytest.param(
            lambda: planar.ik(np.ones((3, 3)), q_seed=np.zeros((2, 2))),
            InvalidInputError,
            "q_seed gives 2 seeds for 3 targets",
            id="planar seed count",
        ),
        pytest.param(
            lambda: planar.ik_branches([0.0, np.nan, 0.0]),
            InvalidInputError,
            "target must be finite",
            id="planar branches NaN",
        ),
        pytest.param(
            lambda: spatial.ik(np.eye(4), position_only=False),
            InvalidInputError,
            "Spatial3R sets only its tool position",
            id="spatial full pose",
        ),
        pytest.param(
            lambda: spatial.ik([20.0, 0.0, 15.0], branch="forward"),
            InvalidInputError,
            "branch must be one of",
            id="spatial branch",
        ),
        pytest.param(
            lambda: spatial.ik([20.0, 0.0, 15.0], branch=4),
            InvalidInputError,
            "branch must be an index 0..3",
            id="spatial branch index",
        ),
        pytest.param(
            lambda: spatial.ik([1.0, 2.0]),
            InvalidInputError,
            r"got shape \(2,\)",
            id="spatial target (2,)",
        ),
        pytest.param(
            lambda: spatial.ik_branches(np.zeros((2, 2))),
            InvalidInputError,
            r"got shape \(2, 2\)",
            id="spatial branches shape",
        ),
        pytest.param(
            lambda: RRBot().ik(np.eye(4), position_only=False),
            InvalidInputError,
            "position_only=True",
            id="rrbot full pose",
        ),
    ]


BAD_IK = _bad_ik_input()


@pytest.mark.parametrize(("call", "error", "message"), BAD_IK)
def test_bad_ik_input(call, error, message):
    # Planar2R maps an inf 2-D point into the world before checking it (a NaN warning).
    with np.errstate(invalid="ignore"), pytest.raises(error, match=message) as excinfo:
        call()
    assert type(excinfo.value) is error


@pytest.mark.parametrize("target", ["abc", [[1.0, 2.0], [3.0]]], ids=["text", "ragged"])
def test_planar2r_refuses_non_numeric_targets(target):
    with pytest.raises(InvalidInputError, match="target must be numeric") as excinfo:
        Planar2R(1.0, 0.5).ik(target)
    assert type(excinfo.value) is InvalidInputError


def test_ik_refuses_a_target_that_is_not_homogeneous():
    ur5 = UR5()
    target = ur5.fk(np.full(6, 0.3))
    target[3] = [1.0, 1.0, 1.0, 5.0]
    with pytest.raises(InvalidInputError) as excinfo:
        ur5.ik(target)
    assert type(excinfo.value) is InvalidInputError
