"""Tests of trajkit.mobile.simulate: RK4 and held-command simulation, saturation and
acceleration limits on the commands, measurement noise, the log's metrics and CSV.

The figure eight's feedforward alone, integrated by RK4 at 1 kHz from the plan's
start pose, stays on the curve to TRACKING (measured 4e-14 m over the period).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import support
from support import EPS, ROUNDING, TRACKING, WORLD_ROUNDING
from trajkit import InvalidInputError
from trajkit.mobile import (
    Arc,
    DiffDrive,
    Feedforward,
    FigureEight,
    Kanayama,
    MobileLimits,
    MobileTrajectory,
    SimulationLog,
    Unicycle,
    arc_pose,
    constant_twist,
    flat_trajectory,
    jackal,
    rotate_translate_rotate,
    simulate,
)

# Tolerances ---------------------------------------------------------------------
HELD_ARC = 1e-12  # relative: held constant commands compose exact arcs
RATE_LIMIT = 1e-12  # relative: a rate-limited change against acceleration × period
FEW = settings(max_examples=20, deadline=None)

EIGHT = FigureEight(2.0, 1.0, 20.0)


def two_arcs(model) -> MobileTrajectory:
    """Straight at 0.5 m/s for 1 s, then at once turning at 3 rad/s: a step in ω."""
    first = Arc((0.0, 0.0, 0.0), 0.5, 0.0, 1.0)
    return MobileTrajectory([first, Arc(first.end_pose, 0.5, 3.0, 1.0)], model)


def tight_diff_drive() -> DiffDrive:
    limits = MobileLimits(velocity=1.0, angular_velocity=4.0, acceleration=1.0,
                          angular_acceleration=10.0)  # fmt: skip
    return DiffDrive(0.1, 0.5, wheel_speed_limit=5.5, limits=limits)


def assert_commands_within(log: SimulationLog, model, limits: MobileLimits) -> None:
    for index, attribute in ((0, "velocity"), (1, "angular_velocity")):
        bounds = getattr(limits, attribute)
        if bounds is not None:
            values = log.commands[:, index]
            assert values.max() <= float(bounds.upper) * (1 + RATE_LIMIT)
            assert values.min() >= float(bounds.lower) * (1 + RATE_LIMIT)
    if isinstance(model, DiffDrive):
        np.testing.assert_array_equal(log.wheel_speeds, model.wheel_speeds(*log.commands.T))
        if limits.wheel_speed is not None:
            assert log.wheel_speeds.max() <= float(limits.wheel_speed.upper) * (1 + RATE_LIMIT)
            assert log.wheel_speeds.min() >= float(limits.wheel_speed.lower) * (1 + RATE_LIMIT)


def held_commands(log: SimulationLog, rate_hz: float) -> np.ndarray:
    """The command held at each command time k / rate_hz, read back from the log."""
    period = 1.0 / rate_hz
    index = np.searchsorted(log.t, np.arange(0.0, log.t[-1], period) - 1e-9)
    return log.commands[index]


# The figure eight at 1 kHz ---------------------------------------------------------
def test_figure_eight_feedforward_tracks_the_curve():
    plan = flat_trajectory(EIGHT)
    default = simulate(plan, None, sample_step=0.001)
    explicit = simulate(plan, Feedforward(), sample_step=0.001)
    np.testing.assert_array_equal(default.actual, explicit.actual)
    assert default.controller == "feedforward"
    assert default.t.size == 20_001 and default.t[-1] == 20.0
    off_curve = np.hypot(*(default.actual[:, :2] - EIGHT.evaluate(default.t, 0)).T)
    assert off_curve.max() <= TRACKING
    assert default.max_error <= TRACKING
    assert np.abs(default.heading_error).max() <= TRACKING
    np.testing.assert_array_equal(default.actual[0], plan.start_pose)
    # Nothing saturates: the commands are the plan's twist (read just after each step's start).
    support.assert_state(default.commands, default.desired_twist, rtol=ROUNDING)
    assert default.wheel_speeds is None


# RK4 and held commands ---------------------------------------------------------------
@FEW
@given(support.poses(), st.floats(-2.0, 2.0), st.floats(-3.0, 3.0))
def test_constant_twist_by_rk4_is_the_arc(start, v, omega):
    plan = constant_twist(v, omega, 2.0, start=start)
    log = simulate(plan, sample_step=0.01)
    scale = 1.0 + np.abs(start[:2]).max() + abs(v) * 2.0
    bound = support.rk4_constant_twist_bound(v, omega, 0.01, 2.0, scale)
    exact = arc_pose(start, v, omega, log.t)
    assert np.abs(log.actual[:, :2] - exact[:, :2]).max() <= bound
    assert np.abs(log.actual[:, 2] - exact[:, 2]).max() <= 8 * log.t.size * EPS * (
        1 + abs(start[2]) + 6
    )


@FEW
@given(
    support.poses(), st.floats(-2.0, 2.0), st.floats(-3.0, 3.0), st.sampled_from([5.0, 10.0, 20.0])
)
def test_held_constant_commands_are_exact_arcs(start, v, omega, rate):
    plan = constant_twist(v, omega, 2.0, start=start, rate_hz=rate)
    log = simulate(plan, sample_step=0.01, command_rate_hz=rate)
    exact = arc_pose(start, v, omega, log.t)
    scale = (1.0 + np.abs(start[:2]).max() + abs(v) * 2.0) * (1 + abs(start[2]) + abs(omega) * 2.0)
    assert np.abs(log.actual - exact).max() <= HELD_ARC * 10 * scale
    np.testing.assert_array_equal(log.commands, np.tile([v, omega], (log.t.size, 1)))


def test_held_commands_between_command_times_follow_the_arc():
    plan = rotate_translate_rotate((2.0, 1.0, 0.0), vmax=0.5, wmax=1.0, amax=1.0, alpha_max=2.0)
    log = simulate(plan, sample_step=0.01, command_rate_hz=4.0)
    k = np.floor(log.t * 4.0 + 1e-9).astype(int)
    command_time = k / 4.0
    first = np.searchsorted(log.t, command_time - 1e-12)  # the log sample at each command time
    expected = arc_pose(log.actual[first], log.commands[:, 0], log.commands[:, 1],
                        log.t - command_time)  # fmt: skip
    support.assert_state(log.actual, expected, rtol=WORLD_ROUNDING)
    np.testing.assert_array_equal(log.commands, log.commands[first])  # held in between


# Limits on the commands ------------------------------------------------------------
def test_held_commands_respect_acceleration_and_wheel_limits():
    model = tight_diff_drive()
    plan = two_arcs(model)
    assert not plan.check().ok  # the step needs 12.5 rad/s on the right wheel
    log = simulate(plan, sample_step=0.01, command_rate_hz=20.0)
    assert_commands_within(log, model, model.limits)
    held = held_commands(log, 20.0)
    steps = np.abs(np.diff(held, axis=0)) * 20.0  # rate of change between commands
    assert steps[:, 0].max() <= 1.0 * (1 + RATE_LIMIT)
    assert steps[:, 1].max() <= 10.0 * (1 + RATE_LIMIT)
    # The right wheel rises to its limit and stays there while the step is followed.
    assert log.wheel_speeds[:, 1].max() == pytest.approx(5.5, rel=RATE_LIMIT)


def test_held_commands_in_a_closed_loop_respect_every_limit():
    robot = jackal()
    limits = robot.limits.replace(velocity=0.6, angular_velocity=1.0, acceleration=0.5,
                                  angular_acceleration=2.0, wheel_speed=7.0)  # fmt: skip
    plan = flat_trajectory(EIGHT, model=robot, limits=limits, timing="within_limits")
    start = support.offset_pose(plan.start_pose, 0.5, math.radians(30.0))
    log = simulate(plan, Kanayama(kx=3, ky=30, ktheta=8), sample_step=0.01, initial_pose=start,
                   command_rate_hz=20.0, limits=limits)  # fmt: skip
    assert_commands_within(log, robot, limits)
    held = held_commands(log, 20.0)
    steps = np.abs(np.diff(held, axis=0)) * 20.0
    assert steps[:, 0].max() <= 0.5 * (1 + RATE_LIMIT)
    assert steps[:, 1].max() <= 2.0 * (1 + RATE_LIMIT)
    assert steps[:, 1].max() == pytest.approx(2.0, rel=RATE_LIMIT)  # the rate limit acts


def test_continuous_commands_are_saturated():
    model = tight_diff_drive()
    plan = two_arcs(model)
    log = simulate(plan, sample_step=0.01)
    assert_commands_within(log, model, model.limits)
    # After the step the command is the plan's, scaled to the wheel limit: (0.5, 3) * 0.44.
    factor = 5.5 / 12.5
    late = log.t > 1.0
    scaled = np.tile([0.5 * factor, 3.0 * factor], (late.sum(), 1))
    np.testing.assert_allclose(log.commands[late], scaled, rtol=RATE_LIMIT)
    np.testing.assert_allclose(log.wheel_speeds[late, 1], 5.5, rtol=RATE_LIMIT)


def test_explicit_limits_replace_the_models():
    plan = constant_twist(1.0, 0.0, 1.0)
    log = simulate(plan, sample_step=0.1, limits=MobileLimits(velocity=0.25))
    np.testing.assert_array_equal(log.commands[:, 0], 0.25)
    support.assert_state(log.actual[-1], [0.25, 0.0, 0.0], rtol=ROUNDING)


# Noise ----------------------------------------------------------------------------
def test_noise_is_reproducible_with_a_seed():
    plan = flat_trajectory(EIGHT)
    runs = [simulate(plan, Kanayama(), sample_step=0.01, duration=5.0,
                     noise=(0.01, 0.02), seed=seed)
            for seed in (7, 7, 8)]  # fmt: skip
    np.testing.assert_array_equal(runs[0].actual, runs[1].actual)
    np.testing.assert_array_equal(runs[0].commands, runs[1].commands)
    assert np.abs(runs[0].actual - runs[2].actual).max() > 1e-4
    quiet = simulate(plan, Kanayama(), sample_step=0.01, duration=5.0)
    assert np.abs(runs[0].actual - quiet.actual).max() > 1e-4
    silent = simulate(plan, Kanayama(), sample_step=0.01, duration=5.0, noise=(0.0, 0.0), seed=3)
    np.testing.assert_array_equal(silent.actual, quiet.actual)


def test_held_noise_is_reproducible_too():
    plan = flat_trajectory(EIGHT)
    a, b = (simulate(plan, Kanayama(), sample_step=0.01, duration=3.0, command_rate_hz=10.0,
                     noise=(0.02, 0.0), seed=1) for _ in range(2))  # fmt: skip
    np.testing.assert_array_equal(a.actual, b.actual)
    c = simulate(plan, Kanayama(), sample_step=0.01, duration=3.0, command_rate_hz=10.0,
                 noise=(0.02, 0.0), seed=2)  # fmt: skip
    assert np.abs(a.actual - c.actual).max() > 1e-4


# Duration, start and controllers ----------------------------------------------------
def test_after_the_plan_the_desired_state_stands_still():
    plan = constant_twist(0.5, 0.5, 2.0)
    log = simulate(plan, sample_step=0.1, duration=4.0)
    assert log.t[-1] == 4.0
    after = log.t > 2.0
    np.testing.assert_array_equal(log.desired[after], np.tile(plan.end_pose, (after.sum(), 1)))
    np.testing.assert_array_equal(log.commands[after], 0.0)
    support.assert_state(log.actual[after], np.tile(log.actual[log.t == 2.0], (after.sum(), 1)),
                         rtol=ROUNDING)  # fmt: skip


def test_seed000_held_commands_stop_where_the_plan_ends():
    # Seed 000's Jackal arc sent at 10 Hz and simulated for 5 s longer: the base stops
    # on the arc's end after the plan's 150 commands, as a base controller would.
    w = math.radians(10.0)
    plan = constant_twist(0.1, w, 15.0, rate_hz=10.0, model=jackal())
    log = simulate(plan, sample_step=0.01, duration=20.0, command_rate_hz=10.0)
    held = held_commands(log, 10.0)
    assert np.count_nonzero(np.any(held != 0.0, axis=1)) == 150 == plan.info["command_count"]
    after = log.t >= 15.0
    radius, theta = 0.1 / w, 15.0 * w
    end = [radius * math.sin(theta), radius * (1.0 - math.cos(theta)), theta]
    assert np.abs(log.actual[after] - end).max() <= 1e-12
    np.testing.assert_array_equal(log.commands[log.t > 15.0], 0.0)


def test_a_step_in_the_twist_on_a_step_boundary_is_integrated_on_its_side():
    # ω jumps from 0 to 3 rad/s at t = 1 s, a step boundary: each RK4 step sees one arc.
    plan = two_arcs(Unicycle())
    log = simulate(plan, sample_step=0.01)
    exact = plan.pose(log.t)  # arcs are exact
    bound = support.rk4_constant_twist_bound(0.5, 3.0, 0.01, 2.0, 2.0)
    assert np.abs(log.actual[:, :2] - exact[:, :2]).max() <= bound
    assert np.abs(log.actual[:, 2] - exact[:, 2]).max() <= 8 * log.t.size * EPS * 4.0


def test_a_plan_of_zero_length_needs_a_duration():
    still = rotate_translate_rotate((1.0, 1.0, 0.0), (1.0, 1.0, 0.0))
    with pytest.raises(
        InvalidInputError, match=r"the plan has no duration to simulate; pass duration="
    ):
        simulate(still)
    log = simulate(still, Kanayama(), sample_step=0.5, duration=1.0, initial_pose=(1.0, 1.2, 0.0))
    assert log.t.tolist() == [0.0, 0.5, 1.0]


def test_custom_controllers():
    class Creep:
        """Drives at 0.1 m/s whatever the plan says, and counts its calls."""

        def __init__(self):
            self.advanced = 0

        def law(self, plan, start):
            controller = self

            class Law:
                initial_state = np.zeros(0)

                def advance(self, t, pose):
                    controller.advanced += 1

                def __call__(self, t, pose, desired, internal):
                    return 0.1, 0.0, np.zeros(0)

            return Law()

    creep = Creep()
    log = simulate(constant_twist(1.0, 0.0, 1.0), creep, sample_step=0.25)
    assert log.controller == "Creep"  # no name: the class name
    assert creep.advanced == 5  # once per logged step
    support.assert_state(log.actual[-1], [0.1, 0.0, 0.0], rtol=ROUNDING)


# The log --------------------------------------------------------------------------
@pytest.fixture(scope="module")
def log() -> SimulationLog:
    plan = rotate_translate_rotate((1.0, 1.0, 2.0), (0.0, 0.0, 3.0), vmax=0.5, wmax=1.0,
                                   amax=1.0, alpha_max=2.0, model=DiffDrive(0.1, 0.4))  # fmt: skip
    return simulate(plan, Kanayama(), sample_step=0.05, initial_pose=(0.1, -0.1, -3.0))


def test_log_shapes(log):
    n = log.t.size
    assert log.desired.shape == log.actual.shape == (n, 3)
    assert log.desired_twist.shape == log.commands.shape == log.wheel_speeds.shape == (n, 2)
    assert log.path_distance.shape == (n,)


def test_log_metrics_are_numpy_computations(log):
    error = np.sqrt((log.actual[:, 0] - log.desired[:, 0]) ** 2
                    + (log.actual[:, 1] - log.desired[:, 1]) ** 2)  # fmt: skip
    heading = np.angle(np.exp(1j * (log.actual[:, 2] - log.desired[:, 2])))
    support.assert_state(log.position_error, error, rtol=ROUNDING)
    assert log.rms_error == pytest.approx(np.sqrt(np.mean(error**2)), rel=ROUNDING)
    assert log.max_error == pytest.approx(error.max(), rel=ROUNDING)
    assert log.final_position_error == pytest.approx(error[-1], rel=ROUNDING)
    assert log.final_heading_error == pytest.approx(abs(heading[-1]), rel=ROUNDING, abs=1e-15)
    support.assert_heading(log.heading_error, heading, atol=1e-12)
    assert np.all((-np.pi <= log.heading_error) & (log.heading_error < np.pi))
    assert log.heading_error[0] == pytest.approx(math.tau - 6.0, rel=ROUNDING)  # -3 vs 3 rad
    assert log.max_path_distance == log.path_distance.max()
    assert log.error_after(2.0) == pytest.approx(error[log.t >= 2.0].max(), rel=ROUNDING)
    assert log.error_after(0.0) == log.max_error
    with pytest.raises(InvalidInputError, match=r"no samples at or after t=100 s \(the log ends"):
        log.error_after(100.0)


def test_path_distance_is_the_distance_to_the_whole_path(log):
    # The plan's path is the line from (0, 0) to (1, 1) (the turns stay on its ends).
    p = log.actual[:, :2]
    u = np.clip((p[:, 0] + p[:, 1]) / 2.0, 0.0, 1.0)
    expected = np.hypot(p[:, 0] - u, p[:, 1] - u)
    np.testing.assert_allclose(log.path_distance, expected, rtol=0, atol=1e-12)
    assert log.path_distance.max() > 0.05  # the robot starts off the path and comes back


def test_summary_mentions_the_metrics(log):
    text = log.summary()
    assert text.startswith("kanayama: RMS error ")
    assert f"{log.rms_error:.3g} m" in text and f"max {log.max_error:.3g} m" in text
    assert f"{np.degrees(log.final_heading_error):.3g} deg" in text
    assert f"max distance from the path {log.max_path_distance:.3g} m" in text


HEADER = (
    "t [s],x_desired [m],y_desired [m],theta_desired [rad],x [m],y [m],theta [rad],"
    "v_desired [m/s],omega_desired [rad/s],v_command [m/s],omega_command [rad/s]"
)


def test_log_to_csv_reads_back_exactly(log, tmp_path):
    path = log.to_csv(tmp_path / "log.csv")
    assert path.read_text().splitlines()[0] == (
        HEADER + ",wheel_left [rad/s],wheel_right [rad/s],path_distance [m]")  # fmt: skip
    table = np.loadtxt(path, delimiter=",", skiprows=1)
    expected = np.column_stack([log.t, log.desired, log.actual, log.desired_twist, log.commands,
                                log.wheel_speeds, log.path_distance])  # fmt: skip
    np.testing.assert_array_equal(table, expected)
    back = SimulationLog.from_csv(path)
    for name in ("t", "desired", "actual", "desired_twist", "commands", "wheel_speeds",
                 "path_distance"):  # fmt: skip
        np.testing.assert_array_equal(getattr(back, name), getattr(log, name))
    assert back.controller == "log" and back.rms_error == log.rms_error


def test_unicycle_log_to_csv_has_no_wheels(tmp_path):
    log = simulate(constant_twist(0.2, 0.1, 1.0), sample_step=0.25)
    path = log.to_csv(tmp_path / "unicycle.csv")
    assert path.read_text().splitlines()[0] == HEADER + ",path_distance [m]"
    table = np.loadtxt(path, delimiter=",", skiprows=1)
    assert table.shape == (5, 12)
    np.testing.assert_array_equal(table[:, 4:7], log.actual)
    assert SimulationLog.from_csv(path).wheel_speeds is None


def test_files_that_are_not_base_logs_are_refused(tmp_path):
    from trajkit import quintic

    plan = quintic(0.0, 1.0, 1.0).sample(0.1).to_csv(tmp_path / "plan.csv")
    with pytest.raises(InvalidInputError, match=r"plan\.csv: no column 'x_desired \[m\]'"):
        SimulationLog.from_csv(plan)


# Bad input ------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"sample_step": 0.0}, r"sample_step must be > 0, got 0 s"),
        ({"sample_step": np.nan}, r"sample_step must be finite"),
        ({"duration": -1.0}, r"duration must be > 0, got -1 s"),
        ({"initial_pose": (0.0, 0.0, 0.0, 0.0)}, r"initial_pose must be a pose"),
        ({"initial_pose": (0.0, np.nan)}, r"initial_pose must be finite"),
        ({"command_rate_hz": 0.0}, r"command_rate_hz must be > 0, got 0 Hz"),
        ({"limits": {"velocity": 1.0}}, r"limits must be a trajkit.mobile.MobileLimits, got dict"),
        ({"noise": (0.1,)}, r"noise must be \(position_sigma, heading_sigma\)"),
        ({"noise": (0.1, -0.1)}, r"noise must be .*both >= 0, got \[0.1, -0.1\]"),
        ({"noise": (0.1, np.inf)}, r"noise must be finite"),
        ({"controller": "kanayama"}, r"controller must have a law\(plan, start\) method, got str"),
    ],
)
def test_bad_input_names_the_argument(kwargs, match):
    with pytest.raises(InvalidInputError, match=match):
        simulate(constant_twist(0.1, 0.1, 1.0), **kwargs)


def test_plan_must_be_a_mobile_trajectory():
    with pytest.raises(
        InvalidInputError, match=r"plan must be a MobileTrajectory, got FigureEight"
    ):
        simulate(EIGHT)  # type: ignore[arg-type]
    assert isinstance(
        simulate(constant_twist(0.1, 0.0, 0.5, model=Unicycle()), sample_step=0.5), SimulationLog
    )


def test_a_unicycle_plan_driven_on_a_base_whose_wheels_saturate():
    import trajkit.mobile as m

    plan = m.flat_trajectory(m.FigureEight(2.0, 1.0, 10.0))  # a bare unicycle: no limits
    base = m.DiffDrive(0.1, 0.4, wheel_speed_limit=5.0)
    free = m.simulate(plan, m.Kanayama(), sample_step=0.01)
    run = m.simulate(plan, m.Kanayama(), sample_step=0.01, model=base)
    assert free.wheel_speeds is None
    assert np.abs(run.wheel_speeds).max() <= 5.0 * (1 + 1e-12)
    # The plan needs up to 7.4 rad/s on these wheels: saturation makes the robot lag.
    assert np.abs(base.wheel_speeds(*plan.twist(np.linspace(0, 10, 2001)).T)).max() > 7.0
    assert free.max_error < 1e-8 < 1e-3 < run.max_error  # RK4 at 100 Hz: ~1e-9 m
    with pytest.raises(InvalidInputError, match=r"model must be a trajkit\.mobile"):
        m.simulate(plan, model="jackal")


def test_error_after_against_the_clock_or_along_the_path():
    import trajkit.mobile as m

    plan = m.flat_trajectory(m.FigureEight(2.0, 1.0, 20.0))
    run = m.simulate(plan, m.PurePursuit(), sample_step=0.02)
    late = run.t >= 10.0
    assert run.error_after(10.0) == run.position_error[late].max()
    assert run.error_after(10.0, along_path=True) == run.path_distance[late].max()
    # Pure pursuit follows the path, not the clock: it lags far more than it strays.
    assert run.error_after(10.0, along_path=True) < 0.05 < run.error_after(10.0)


def test_a_position_alone_starts_with_the_plans_heading():
    import trajkit.mobile as m

    plan = m.flat_trajectory(m.FigureEight(2.0, 1.0, 20.0))
    run = m.simulate(plan, m.Kanayama(), sample_step=0.05, duration=1.0, initial_pose=(0.1, 0.0))
    np.testing.assert_array_equal(run.actual[0], [0.1, 0.0, plan.start_pose[2]])


def test_simulation_defaults_to_the_plans_limits():
    import trajkit.mobile as m

    slow = m.MobileLimits(velocity=0.3, angular_velocity=1.0)
    plan = m.flat_trajectory(m.FigureEight(2.0, 1.0, 20.0), model=m.jackal(), limits=slow,
                             timing="within_limits")  # fmt: skip
    run = m.simulate(plan, m.Kanayama(), sample_step=0.02, initial_pose=(0.3, 0.3, 1.3))
    assert np.abs(run.commands[:, 0]).max() <= 0.3 * (1 + 1e-12)  # not the Jackal's 2 m/s


def test_too_many_samples_are_refused():
    import trajkit.mobile as m

    plan = m.constant_twist(0.1, 0.1, 20.0)
    with pytest.raises(InvalidInputError, match=r"gives 2e\+10 samples; at most 1e\+08"):
        m.simulate(plan, sample_step=1e-9)
    with pytest.raises(InvalidInputError, match=r"commands; at most 1e\+08"):
        m.constant_twist(0.1, 0.1, 1e9, rate_hz=10.0).commands(10.0)
