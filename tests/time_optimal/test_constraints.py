"""Torque and tool limits in the time-optimal timing (``topp(..., constraints=...)``).

What is pinned here:

* a torque- or tool-limited timing keeps its bounds on a dense, independent
  sampling of the result (200 samples per piece; the tool's speed also by finite
  differences of its position), keeps the joint limits exactly, and is no faster
  than the timing without them;
* ``PathLimit.check`` says what passes its bound, where, and by how much;
* where the arm must rest (its ends, a corner) and gravity alone passes a torque
  limit, the timing is refused by name;
* bad input: the exact error type and the part of the message that helps.

The comparison with toppra's ``JointTorqueConstraint`` is in
``tests/oracles/test_oracle_topp_constraints.py``.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import trajkit as tk
from trajkit.errors import InfeasibleError, InvalidInputError
from trajkit.kinematics import UR5, DHRow, Inertials, SerialChain, inertials_from_dh
from trajkit.time_optimal import ToolLimit, TorqueLimit

#: The checks below sample each piece 200 times, the solver's measure 16 times with a
#: curvature margin: the dense samples may not pass a bound by more than rounding.
DENSE = 200
ROUNDING = 1e-9
GRAVITY_Y = (0.0, -9.81, 0.0)


def two_link(l1=0.7, l2=0.5, m1=2.0, m2=1.5):
    """A planar 2R arm in the vertical xy plane (gravity along -y), rod-like links."""
    chain = SerialChain.from_dh([DHRow(a=l1), DHRow(a=l2)], names=["shoulder", "elbow"])
    inertia = np.stack([np.diag([0.0, m * length**2 / 12, m * length**2 / 12])
                        for m, length in ((m1, l1), (m2, l2))])  # fmt: skip
    com = [[-l1 / 2, 0.0, 0.0], [-l2 / 2, 0.0, 0.0]]
    return chain, inertials_from_dh(chain, [m1, m2], com, inertia)


def spline(seed: int, ndof: int, spread: float = 1.5, points: int = 5) -> tk.Trajectory:
    way = np.random.default_rng(seed).uniform(-spread, spread, (points, ndof))
    return tk.cubic_spline(np.linspace(0.0, 1.0, points), way, bc="natural")


def dense(trajectory: tk.Trajectory, per_piece: int = DENSE) -> np.ndarray:
    """Times: ``per_piece`` samples in every piece, both ends included."""
    b = trajectory.breakpoints
    t = (b[:-1, None] + np.diff(b)[:, None] * np.linspace(0, 1, per_piece + 1)).ravel()
    return np.clip(t, b[0], b[-1])


def dense_ratio(limit, trajectory: tk.Trajectory) -> np.ndarray:
    """The largest ratio of each component to the bound of its side, on the dense samples."""
    t = dense(trajectory)
    values = limit.values(trajectory(t), trajectory.velocity(t), trajectory.acceleration(t))
    lower, upper = limit.bounds()
    with np.errstate(divide="ignore"):
        return np.maximum(values / upper, np.where(np.isfinite(lower), values / lower, 0)).max(0)


TWO_LINK, TWO_LINK_INERTIALS = two_link()
LIMITS = tk.Limits(velocity=3.0, acceleration=30.0)


def torque(limit=(40.0, 12.0)) -> TorqueLimit:
    return TorqueLimit(TWO_LINK, list(limit), inertials=TWO_LINK_INERTIALS, gravity=GRAVITY_Y)


# ------------------------------------------------------------------- torque limits


@pytest.mark.parametrize("grid", [100, 500])
def test_a_torque_limited_timing_keeps_its_torques_and_is_slower(grid):
    path, limit = spline(0, 2), torque()
    free = tk.topp(path, LIMITS, grid=grid)
    timed = tk.topp(path, LIMITS, grid=grid, constraints=limit)
    assert dense_ratio(limit, free).max() > 1.0  # the torque limit binds
    ratio = dense_ratio(limit, timed)
    assert ratio.max() <= 1.0 + ROUNDING
    assert ratio.max() > 0.999  # and is used: the timing is at its limit somewhere
    assert timed.check(LIMITS).ok
    assert timed.duration > free.duration
    (check,) = timed.info["constraint_checks"]
    assert isinstance(check, tk.Report) and check.ok
    np.testing.assert_array_equal(check.ratios("torque"), limit.check(timed).ratios("torque"))
    assert check.ratios("torque").max() > 0.999
    np.testing.assert_allclose(timed(timed.breakpoints), path(timed.info["grid_points"]),
                               atol=1e-9)  # fmt: skip


def test_asymmetric_torque_limits_are_kept_per_side():
    limit = TorqueLimit(TWO_LINK, ([-45.0, -9.0], [30.0, 14.0]), inertials=TWO_LINK_INERTIALS,
                        gravity=GRAVITY_Y)  # fmt: skip
    timed = tk.topp(spline(3, 2), LIMITS, grid=300, constraints=[limit])
    t = dense(timed)
    tau = limit.values(timed(t), timed.velocity(t), timed.acceleration(t))
    assert np.all(tau <= np.array([30.0, 14.0]) * (1 + ROUNDING))
    assert np.all(tau >= np.array([-45.0, -9.0]) * (1 + ROUNDING))


def test_the_ur5_carries_its_inertias_and_torque_limits():
    arm = UR5()
    physical = arm.physical
    np.testing.assert_array_equal(physical.effort_limit, [150, 150, 150, 28, 28, 28])
    inertials = physical.inertials(6)
    assert np.all(np.linalg.eigvalsh(inertials.inertia) > 0)
    # A fast move that its joint limits allow but its torques do not.
    path = spline(1, 6, spread=1.2)
    limits = tk.Limits(velocity=np.pi, acceleration=200.0)
    limit = TorqueLimit(arm)
    free = tk.topp(path, limits, grid=200)
    timed = tk.topp(path, limits, grid=200, constraints=limit)
    assert dense_ratio(limit, free).max() > 1.0
    assert dense_ratio(limit, timed).max() <= 1.0 + ROUNDING
    assert timed.duration > free.duration


@st.composite
def torque_problems(draw):
    """A random 2- or 3-joint arm, path and torque limits above what holds it still."""
    ndof = draw(st.integers(2, 3))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    rows = [DHRow(a=rng.uniform(0.2, 0.8), alpha=rng.choice([0.0, np.pi / 2]))
            for _ in range(ndof)]  # fmt: skip
    chain = SerialChain.from_dh(rows)
    inertia = np.stack([np.eye(3) * rng.uniform(0.01, 0.1) for _ in range(ndof)])
    inertials = Inertials(rng.uniform(0.5, 4.0, ndof), rng.uniform(-0.1, 0.1, (ndof, 3)), inertia)
    path = spline(int(rng.integers(2**31)), ndof, spread=draw(st.floats(0.3, 2.0)),
                  points=draw(st.integers(3, 6)))  # fmt: skip
    hold = TorqueLimit(chain, 1e6, inertials=inertials).holding(path(np.linspace(0, 1, 50)))
    margin = np.abs(hold).max(axis=0) + draw(st.floats(0.5, 20.0))
    limit = TorqueLimit(chain, margin, inertials=inertials)
    limits = tk.Limits(velocity=draw(st.floats(0.5, 5.0)), acceleration=draw(st.floats(2.0, 50.0)))
    return path, limits, limit


@settings(max_examples=25, deadline=None)
@given(problem=torque_problems(), grid=st.integers(30, 300))
def test_property_no_torque_or_joint_limit_is_ever_exceeded(problem, grid):
    path, limits, limit = problem
    timed = tk.topp(path, limits, grid=grid, constraints=limit)
    assert timed.check(limits).ok
    assert dense_ratio(limit, timed).max() <= 1.0 + ROUNDING
    assert timed.info["constraint_checks"][0].ok
    assert timed.duration >= tk.topp(path, limits, grid=grid).duration * (1 - 1e-12)


# ------------------------------------------------------------------- tool limits


@settings(max_examples=25, deadline=None)
@given(problem=torque_problems(), grid=st.integers(10, 400), speed=st.floats(0.05, 3.0),
       acceleration=st.one_of(st.none(), st.floats(0.5, 30.0)),
       with_torque=st.booleans())  # fmt: skip
def test_property_no_tool_limit_is_ever_exceeded(problem, grid, speed, acceleration, with_torque):
    # Random arms put directions across the tool's path, where a row's u term is
    # rounding: such rows once had garbage slopes and stopped the timing.
    path, limits, torque_limit = problem
    tool = ToolLimit(torque_limit.chain, speed=speed, acceleration=acceleration)
    both = [tool, torque_limit] if with_torque else [tool]
    timed = tk.topp(path, limits, grid=grid, constraints=both)
    assert timed.check(limits).ok
    for limit in both:
        assert dense_ratio(limit, timed).max() <= 1.0 + ROUNDING


def tool_speed_by_differences(chain, trajectory) -> float:
    """Largest tool speed from central differences of the tool's position (m/s)."""
    t = np.linspace(0.0, trajectory.end_time, 40001)
    p = chain.fk(trajectory(t))[:, :3, 3]
    step = t[1] - t[0]
    return float(np.linalg.norm((p[2:] - p[:-2]) / (2 * step), axis=1).max())


def test_a_tool_speed_limit_is_kept_and_binds():
    limit = ToolLimit(TWO_LINK, speed=0.6)
    path = spline(0, 2)
    free = tk.topp(path, LIMITS, grid=400)
    timed = tk.topp(path, LIMITS, grid=400, constraints=limit)
    assert tool_speed_by_differences(TWO_LINK, free) > 0.6
    measured = tool_speed_by_differences(TWO_LINK, timed)
    assert 0.599 < measured <= 0.6 * (1 + 1e-6)  # differences: O(step²) of the true speed
    assert dense_ratio(limit, timed).max() <= 1.0 + ROUNDING
    assert timed.check(LIMITS).ok


@pytest.mark.parametrize("kind, bound", [("acceleration", 2.0), ("angular_speed", 1.0),
                                         ("angular_acceleration", 3.0)])  # fmt: skip
def test_tool_acceleration_and_turn_rate_limits_are_kept(kind, bound):
    limit = ToolLimit(TWO_LINK, **{kind: bound})
    path = spline(2, 2)
    timed = tk.topp(path, LIMITS, grid=300, constraints=limit)
    ratio = dense_ratio(limit, timed).max()
    assert ratio <= 1.0 + ROUNDING
    # The acceleration polygons sit 1.9% inside the disc; the turn rate is exact.
    assert ratio > (0.999 if kind == "angular_speed" else 0.97)


def test_the_tool_angular_acceleration_is_the_rate_of_its_angular_velocity():
    # On the UR5 the turn is three-dimensional: J_w q̈ + J̇_w q̇ against central
    # differences of J_w(q(t)) q̇(t) (the geometric Jacobian's angular rows).
    arm = UR5()
    limit = ToolLimit(arm, angular_speed=1.0, angular_acceleration=2.0)
    timed = tk.topp(spline(3, 6, spread=1.0), tk.Limits(velocity=2.0, acceleration=10.0),
                    grid=200, constraints=limit)  # fmt: skip
    t = np.linspace(0.0, timed.end_time, 20001)
    omega = np.einsum("nkj,nj->nk", arm.jacobian(timed(t))[:, 3:], timed.velocity(t))
    step = t[1] - t[0]
    by_differences = np.linalg.norm((omega[2:] - omega[:-2]) / (2 * step), axis=1)
    values = limit.values(timed(t), timed.velocity(t), timed.acceleration(t))
    np.testing.assert_allclose(values[1:-1, 0], np.linalg.norm(omega[1:-1], axis=1), atol=1e-12)
    # Acceleration jumps at grid points: compare away from them.
    away = np.min(np.abs(t[1:-1, None] - timed.breakpoints[None, :]), axis=1) > 2 * step
    np.testing.assert_allclose(values[1:-1, 1][away], by_differences[away], rtol=0, atol=2e-5)
    assert values[:, 1].max() <= 2.0 * (1 + 1e-9) and values[:, 0].max() <= 1.0 * (1 + 1e-9)
    assert limit.check(timed).ok


def test_torque_and_tool_limits_together():
    limits = [torque(), ToolLimit(TWO_LINK, speed=0.8, acceleration=6.0)]
    timed = tk.topp(spline(4, 2), LIMITS, grid=300, constraints=limits)
    for limit in limits:
        assert dense_ratio(limit, timed).max() <= 1.0 + ROUNDING
    assert [c.ok for c in timed.info["constraint_checks"]] == [True, True]
    assert list(timed.info["constraint_checks"][1].peaks) == ["tool speed", "tool acceleration"]


# ------------------------------------------------------------------- with a jerk bound


@settings(max_examples=12, deadline=None)
@given(problem=torque_problems(), grid=st.integers(40, 200), speed=st.floats(0.2, 3.0),
       jerk=st.floats(20.0, 500.0), start=st.sampled_from([0.0, 0.0, 0.02, 0.1]),
       end=st.sampled_from([0.0, 0.05]))  # fmt: skip
def test_property_jerk_limited_timing_keeps_torque_and_tool_limits(problem, grid, speed, jerk,
                                                                   start, end):  # fmt: skip
    path, limits, torque_limit = problem
    limits = tk.Limits(velocity=limits.velocity.upper, acceleration=limits.acceleration.upper,
                       jerk=jerk)  # fmt: skip
    both = [torque_limit, ToolLimit(torque_limit.chain, speed=speed)]
    try:
        timed = tk.topp(path, limits, grid=grid, constraints=both, start_speed=start,
                        end_speed=end)  # fmt: skip
    except InfeasibleError as exc:  # moving ends the limits cannot hold: said by name
        assert start or end
        assert "speed" in str(exc)
        return
    assert timed.info["jerk_limited"]
    assert timed.check(limits).ok  # velocity, acceleration and jerk, exactly
    for limit in both:
        assert dense_ratio(limit, timed).max() <= 1.0 + ROUNDING
    assert [c.ok for c in timed.info["constraint_checks"]] == [True, True]
    # The ends: the path's own positions, its tangent at the asked speeds, no acceleration.
    for t, s, speed_at in ((0.0, 0.0, start), (timed.end_time, 1.0, end)):
        np.testing.assert_allclose(timed(t), path(s), rtol=0, atol=1e-12)
        np.testing.assert_allclose(timed.velocity(t), path.velocity(s) * speed_at, rtol=0,
                                   atol=1e-9)  # fmt: skip
        np.testing.assert_allclose(timed.acceleration(t), 0.0, atol=1e-9)


def test_a_jerk_limited_ur5_move_keeps_its_torque_and_tool_speed():
    arm = UR5()
    path = spline(1, 6, spread=1.2)
    limits = tk.Limits(velocity=np.pi, acceleration=40.0, jerk=400.0)
    both = [TorqueLimit(arm), ToolLimit(arm, speed=1.0)]
    free = tk.topp(path, limits, grid=150)
    timed = tk.topp(path, limits, grid=150, constraints=both)
    assert max(dense_ratio(limit, free).max() for limit in both) > 1.05  # they bind
    for limit in both:
        assert dense_ratio(limit, timed).max() <= 1.0 + ROUNDING
    assert timed.check(limits).ok and timed.info["jerk_limited"]
    assert timed.duration > free.duration


def test_a_jerk_limited_timing_refuses_a_rest_the_arm_cannot_hold():
    # Gravity alone passes the limit on the way: refused by name before any smoothing.
    chain, inertials = TWO_LINK, TWO_LINK_INERTIALS
    path = tk.Trajectory([0.0, 0.5, 1.0], np.array([[[0.0, 0.0], [0.0, 0.0]],
                                                    [[1.0, 0.4], [1.0, 0.4]],
                                                    [[0.0, 0.0], [0.5, 0.2]]]))  # fmt: skip
    hold = TorqueLimit(chain, 1e6, inertials=inertials, gravity=GRAVITY_Y).holding(
        path(np.array([0.0, 0.5, 1.0])))  # fmt: skip
    limit = TorqueLimit(chain, float(np.abs(hold).max()) * 0.999, inertials=inertials,
                        gravity=GRAVITY_Y)  # fmt: skip
    limits = tk.Limits(velocity=1.0, acceleration=5.0, jerk=50.0)
    with pytest.raises(InfeasibleError, match="gravity alone"):
        tk.topp(path, limits, constraints=limit)


# --------------------------------------------------------------------------- check


def test_check_names_what_passes_its_bound_and_where():
    path = spline(0, 2)
    free = tk.topp(path, LIMITS, grid=200)
    limit = torque((40.0, 12.0))
    report = limit.check(free)
    assert not report.ok
    ratios = report.ratios("torque")
    assert ratios.shape == (2,) and ratios.max() > 1.0
    worst = max(report.violations, key=lambda v: abs(v.value / v.bound))
    assert abs(worst.value / worst.bound) == pytest.approx(ratios.max(), rel=1e-12)
    # The violation's time and value are a sample's: the torque there is that value.
    t = np.array([worst.time])
    at = limit.values(free(t), free.velocity(t), free.acceleration(t))[0, worst.joint]
    assert abs(at - worst.value) <= 0.01 * abs(worst.value)
    assert str(worst).startswith("torque of joint") and "beyond the bound" in str(worst)
    assert str(report).startswith("limit check:") and "violation" in str(report)
    assert torque((1e4, 1e4)).check(free).ok


# ------------------------------------------------------------------- refusals


def test_gravity_beyond_the_limit_at_rest_is_refused_by_name():
    # Held out horizontally the shoulder holds m1 g l1/2 + m2 g (l1 + l2/2) = 20.8463 N·m.
    path = tk.cubic_spline([0, 1], [[0.0, 0.0], [0.5, 0.2]], bc="natural")
    with pytest.raises(InfeasibleError, match=r"joint shoulder needs 20\.8463 N·m to hold the arm"):
        tk.topp(path, LIMITS, grid=50, constraints=torque((12.0, 12.0)))


def test_a_corner_is_a_rest_where_gravity_must_be_held():
    # A polyline rests at its corner, held out horizontally there.
    knots, points = np.array([0.0, 1.0, 2.0]), np.array([[-1.2, 0.0], [0.0, 0.0], [-1.2, 0.5]])
    slope = np.diff(points, axis=0) / np.diff(knots)[:, None]
    path = tk.Trajectory(knots, np.stack([slope, points[:-1]]))
    with pytest.raises(InfeasibleError, match=r"at s=1 \(gravity alone\).*can stop there"):
        tk.topp(path, LIMITS, grid=50, constraints=torque((15.0, 15.0)))


def test_a_pose_the_arm_cannot_hold_is_not_passed_through():
    # Raised from -1.2 rad to 1.2 rad, the arm passes horizontal (20.85 N·m) at s = 0.5.
    path = tk.cubic_spline([0, 1], [[-1.2, 0.0], [1.2, 0.0]], bc="natural")
    with pytest.raises(
        InfeasibleError,
        match=r"20\.8463 N·m to hold the arm at s=0\.5 .*"
        "cannot pass through a pose the arm cannot hold",
    ):
        tk.topp(path, LIMITS, grid=50, constraints=torque((15.0, 15.0)))


def test_a_chain_without_inertias_is_refused_by_name():
    chain = SerialChain.from_dh([DHRow(a=0.5), DHRow(a=0.4)], name="bare")
    with pytest.raises(InvalidInputError, match="'bare' has no inertial data"):
        TorqueLimit(chain, 10.0)
    with pytest.raises(InvalidInputError, match=r"no torque limit given .* pass limit="):
        TorqueLimit(chain)


@pytest.mark.parametrize(
    "limit, match",
    [
        ((np.nan, 10.0), "torque limit lower bound must be finite, got nan"),
        ([np.inf, 1.0], "torque limit must be finite"),
        ((5.0, -5.0), "lower bound must be below the upper bound"),
        ((1.0, 5.0), "must contain 0"),
        ([1.0, 2.0, 3.0], "torque limit gives 3 joints but the chain 'chain' has 2"),
        ([[1.0, 2.0]], "a number or one number per joint"),
        ("big", "torque limit"),
    ],
)
def test_bad_torque_limits(limit, match):
    with pytest.raises(InvalidInputError, match=match):
        TorqueLimit(TWO_LINK, limit, inertials=TWO_LINK_INERTIALS)


def test_bad_gravity_and_chain():
    with pytest.raises(InvalidInputError, match="gravity must be 3 numbers"):
        TorqueLimit(TWO_LINK, 10.0, inertials=TWO_LINK_INERTIALS, gravity=(0, 9.81))
    with pytest.raises(InvalidInputError, match="gravity must be finite"):
        TorqueLimit(TWO_LINK, 10.0, inertials=TWO_LINK_INERTIALS, gravity=(0, np.nan, 0))
    with pytest.raises(InvalidInputError, match=r"chain must be a trajkit\.kinematics\.SerialCh"):
        TorqueLimit("ur5", 10.0)
    with pytest.raises(InvalidInputError, match=r"chain must be a trajkit\.kinematics\.SerialCh"):
        ToolLimit(None, speed=1.0)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({}, "needs at least one of speed, acceleration, angular_speed, angular_acceleration"),
        (
            {"angular_acceleration": -2.0},
            r"tool angular_acceleration must be a single number "
            r"> 0 \(rad/s\^2\)",
        ),
        (
            {"angular_acceleration": 1e-320},
            r"tool angular_acceleration must be at least "
            r"1\.49e-154 rad/s\^2 \(its square",
        ),
        ({"speed": 1e-200}, "tool speed must be at least 1.49e-154 m/s"),
        ({"speed": 0.0}, "tool speed must be a single number > 0"),
        ({"speed": -1.0}, "tool speed must be a single number > 0"),
        ({"acceleration": np.nan}, "tool acceleration must be finite"),
        ({"angular_speed": np.inf}, "tool angular_speed must be finite"),
        ({"speed": [1.0, 2.0]}, "tool speed must be a single number"),
    ],
)
def test_bad_tool_limits(kwargs, match):
    with pytest.raises(InvalidInputError, match=match):
        ToolLimit(TWO_LINK, **kwargs)


def test_bad_constraints_in_topp():
    path = spline(0, 2)
    with pytest.raises(InvalidInputError, match="constraints must be TorqueLimit or ToolLimit"):
        tk.topp(path, LIMITS, constraints=[torque(), "speed"])
    with pytest.raises(InvalidInputError, match="constraints must be a TorqueLimit"):
        tk.topp(path, LIMITS, constraints=3.0)
    with pytest.raises(InvalidInputError, match="has 6 joints but the path has 2"):
        tk.topp(path, LIMITS, constraints=ToolLimit(UR5(), speed=1.0))


def test_bad_check_arguments():
    limit = torque()
    with pytest.raises(InvalidInputError, match=r"trajectory must be a trajkit\.Trajectory"):
        limit.check(np.zeros((3, 2)))
    timed = tk.topp(spline(0, 2), LIMITS, grid=50)
    for samples in (1, 2.5, True):
        with pytest.raises(InvalidInputError, match="samples must be a whole number >= 2"):
            limit.check(timed, samples=samples)
