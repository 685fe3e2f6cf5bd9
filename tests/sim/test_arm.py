"""Tests of arm runs in MuJoCo: the four controllers on seed 000's RRBot move, pose
holds on the UR5, the log's grid, metrics and CSV, determinism and bad input.

Bounds are the measured errors (MuJoCo 4.0, 1 ms steps, 1 kHz control) times
about 1.5, with the measured value beside each. Two have a closed form:

* A PD position servo ``τ = kp (q_d − q) − kv q̇`` with exact gravity compensation
  lags a cruising joint by ``(kv + b) q̇_d / kp`` (``b`` the joint damping): on
  seed 000 that is 0.963° and 0.647°, the measured maxima to 0.3%.
* Held still without gravity compensation, the servo settles where its torque
  ``kp (q_d − q)`` equals gravity at the sagged pose (MuJoCo's inverse dynamics).
"""

from __future__ import annotations

import numpy as np
import pytest
from matplotlib.figure import Figure

import trajkit as tk
from support import ROUNDING
from trajkit import sim
from trajkit.errors import InfeasibleError, InvalidInputError
from trajkit.kinematics import UR5, DHRow, Physical, SerialChain
from trajkit.mobile import constant_twist
from trajkit.sim.engine import compile_scene

mujoco = pytest.importorskip("mujoco", reason="MuJoCo is not installed: pip install 'trajkit[sim]'")

CONTROLLERS = ["position", "velocity", "pd_feedforward", "computed_torque"]
#: Largest tracking error on seed 000 (deg): bound, and measured.
SEED_000_BOUND_DEG = {
    "position": 1.2,  # measured 0.963
    "velocity": 0.12,  # measured 0.080
    "pd_feedforward": 5e-4,  # measured 2.8e-4
    "computed_torque": 2e-4,  # measured 1.1e-4
}
#: Columns of ``commands`` per joint: setpoint; velocity twice; torque, q, q̇; torque.
COMMAND_COLUMNS = {"position": 1, "velocity": 2, "pd_feedforward": 3, "computed_torque": 1}
HOLD = 1e-9  # rad: a pose held under exact gravity compensation (measured 0 exactly)
LAG = 0.02  # relative: servo lag against (kv + b) q̇_d / kp (measured 0.1% and 0.3%)
STATIC = 1e-9  # N·m: settled servo torque against gravity (measured 5e-13)

UR5_POSE = np.array([0.3, -1.2, 1.5, -0.8, 1.2, 0.4])


def seed_000() -> tk.Trajectory:
    return tk.cubic(np.radians([0, 0]), np.radians([67, -45]), vmax=np.radians([9, 11]))


@pytest.fixture(scope="module")
def logs() -> dict[str, sim.ArmLog]:
    return {name: sim.run(sim.rrbot_scene(), seed_000(), controller=name) for name in CONTROLLERS}


def log_arrays(log: sim.ArmLog) -> dict[str, np.ndarray]:
    names = ("t", "desired", "desired_velocity", "desired_acceleration", "actual",
             "actual_velocity", "commands", "efforts")  # fmt: skip
    return {name: getattr(log, name) for name in names}


# Seed 000 on RRBot ---------------------------------------------------------------------
@pytest.mark.parametrize("controller", CONTROLLERS)
def test_seed_000_tracking_error_within_bound(logs, controller):
    log = logs[controller]
    assert np.degrees(log.max_error.max()) <= SEED_000_BOUND_DEG[controller]
    assert log.controller == sim.arm_controller(controller).name


def test_controllers_rank_as_their_information(logs):
    # Position only < plus velocity < plus the dynamics (open loop) < the dynamics closed loop.
    errors = [logs[name].max_error.max() for name in CONTROLLERS]
    assert errors == sorted(errors, reverse=True)


def test_position_servo_lag_is_the_pd_steady_state():
    scene = sim.rrbot_scene()
    log = sim.run(scene, seed_000(), controller="position")
    servo = sim.PositionServo()
    expected = (servo.kv + scene.damping) * np.abs(log.desired_velocity).max(axis=0) / servo.kp
    np.testing.assert_allclose(log.max_error, expected, rtol=LAG)


def test_without_gravity_compensation_the_position_servo_sags(logs):
    sagging = sim.run(sim.rrbot_scene(gravity_compensation=False), seed_000())
    worst = np.degrees(sagging.max_error.max())
    assert 6.0 <= worst <= 12.0  # measured 8.53 deg
    assert sagging.max_error.max() > 5.0 * logs["position"].max_error.max()


@pytest.mark.parametrize("controller", ["pd_feedforward", "computed_torque"])
def test_torque_controllers_compute_gravity_themselves(logs, controller):
    # gravity_compensation is for servos; inverse dynamics includes gravity anyway.
    log = sim.run(sim.rrbot_scene(gravity_compensation=False), seed_000(), controller=controller)
    for name in ("actual", "efforts", "commands"):
        np.testing.assert_array_equal(getattr(log, name), getattr(logs[controller], name))


@pytest.mark.parametrize("controller", CONTROLLERS)
def test_log_grid_and_shapes(logs, controller):
    log = logs[controller]
    plan = seed_000()
    count = int(np.ceil(plan.duration * 1000.0)) + 1  # 11168: the grid covers the end
    assert log.t.shape == (count,)
    k = np.arange(count)
    assert np.all(np.abs(log.t - k / 1000.0) <= ROUNDING * np.maximum(1.0, log.t))
    for name in ("desired", "desired_velocity", "desired_acceleration", "actual",
                 "actual_velocity", "efforts"):  # fmt: skip
        assert getattr(log, name).shape == (count, 2), name
    assert log.commands.shape == (count, 2 * COMMAND_COLUMNS[controller])
    assert log.joint_names == ("q1", "q2")
    np.testing.assert_array_equal(log.desired, plan.evaluate(log.t, 0))
    # The plan's own derivatives up to its end; standing still at its end position after.
    during = log.t <= plan.end_time
    assert during.sum() == count - 1  # the last control time, 11.168 s, is past the end
    np.testing.assert_array_equal(log.desired_velocity[during], plan.evaluate(log.t[during], 1))
    np.testing.assert_array_equal(log.desired_acceleration[during], plan.evaluate(log.t[during], 2))
    np.testing.assert_array_equal(log.desired_velocity[~during], 0.0)
    np.testing.assert_array_equal(log.desired_acceleration[~during], 0.0)


@pytest.mark.parametrize("controller", CONTROLLERS)
def test_log_starts_exactly_at_the_plans_start_state(controller):
    plan = tk.cubic([0.1, 0.2], [0.5, -0.3], 2.0, v0=[0.3, -0.2])
    log = sim.run(sim.rrbot_scene(), plan, controller=controller)
    np.testing.assert_array_equal(log.actual[0], [0.1, 0.2])
    np.testing.assert_array_equal(log.actual_velocity[0], [0.3, -0.2])
    np.testing.assert_array_equal(log.error[0], [0.0, 0.0])


@pytest.mark.parametrize("controller", CONTROLLERS)
def test_runs_are_bit_for_bit_repeatable(logs, controller):
    again = sim.run(sim.rrbot_scene(), seed_000(), controller=controller)
    scene = sim.rrbot_scene()
    first, second = (sim.run(scene, seed_000(), controller=controller) for _ in range(2))
    for name, array in log_arrays(logs[controller]).items():
        for other in (again, first, second):
            np.testing.assert_array_equal(getattr(other, name), array, err_msg=name)


def test_same_scene_and_controller_give_the_same_log_whatever_ran_before():
    # Gains that numpy prints alike (8 digits) must still get their own compiled model.
    before = sim.PositionServo(kp=np.array([100.0, 100.0]))
    servo = sim.PositionServo(kp=np.array([100.000000001, 100.0]))
    scene = sim.rrbot_scene()
    first = sim.run(scene, seed_000(), controller=before)
    reused = sim.run(scene, seed_000(), controller=servo)
    fresh = sim.run(sim.rrbot_scene(), seed_000(), controller=servo)
    np.testing.assert_array_equal(reused.actual, fresh.actual)
    assert not np.array_equal(reused.actual, first.actual)  # the gains do differ (by 2e-13 rad)


# Servo algebra: efforts follow from the logged state ------------------------------------
def test_position_servo_effort_is_pd_on_the_logged_state():
    log = sim.run(sim.rrbot_scene(gravity_compensation=False), seed_000(),
                  controller=sim.PositionServo(kp=[100.0, 60.0], kv=[10.0, 4.0]))  # fmt: skip
    kp, kv = np.array([100.0, 60.0]), np.array([10.0, 4.0])
    expected = kp * (log.commands - log.actual) - kv * log.actual_velocity
    np.testing.assert_allclose(log.efforts, expected, rtol=0, atol=1e-9 * np.abs(expected).max())
    np.testing.assert_array_equal(log.commands, log.desired)


def test_pd_feedforward_effort_is_feedforward_plus_pd():
    log = sim.run(sim.rrbot_scene(), seed_000(), controller="pd_feedforward")
    torque, q, qd = log.commands[:, :2], log.commands[:, 2:4], log.commands[:, 4:]
    np.testing.assert_array_equal(q, log.desired)
    np.testing.assert_array_equal(qd, log.desired_velocity)
    expected = torque + 100.0 * (q - log.actual) + 10.0 * (qd - log.actual_velocity)
    np.testing.assert_allclose(log.efforts, expected, rtol=0, atol=1e-9 * np.abs(expected).max())


def test_velocity_servo_commands_the_plans_velocity():
    log = sim.run(sim.rrbot_scene(), seed_000(), controller="velocity")
    np.testing.assert_array_equal(log.commands[:, :2], log.desired_velocity)
    np.testing.assert_array_equal(log.commands[:, 2:], log.desired_velocity)


def test_computed_torque_efforts_are_its_commands(logs):
    log = logs["computed_torque"]
    np.testing.assert_array_equal(log.efforts, log.commands)


# UR5 from its DH table ------------------------------------------------------------------
@pytest.mark.parametrize("controller", CONTROLLERS)
def test_ur5_holds_a_pose_with_gravity_compensation(controller):
    plan = tk.cubic(UR5_POSE, UR5_POSE, duration=2.0)
    log = sim.run(sim.arm_scene(UR5()), plan, controller=controller)
    assert log.joint_names == tuple(UR5().names)
    assert np.abs(log.error).max() <= HOLD
    # The drives carry the arm's weight: shoulder and elbow measured 20.7 and 13.9 N·m.
    assert 15.0 <= log.peak_effort[1] <= 30.0


def _unit_mass_ur5() -> object:
    """The UR5's kinematics with 1 kg links (its own masses are 0.19 to 8.4 kg)."""
    return UR5().with_physical(Physical(link_mass=1.0))


def test_ur5_position_servo_sags_without_gravity_compensation():
    plan = tk.cubic(UR5_POSE, UR5_POSE, duration=2.0)
    log = sim.run(sim.arm_scene(_unit_mass_ur5(), gravity_compensation=False), plan)
    sag = np.degrees(log.max_error)
    # Visible on the shoulder and elbow (measured 15.9 and 8.1 deg), bounded by gravity / kp:
    # 30.4 N·m / 100 N·m/rad = 17.4 deg at the worst pose along the way.
    assert sag[1] >= 5.0 and sag[2] >= 3.0
    assert sag.max() <= 20.0


def test_ur5_servo_settles_where_its_torque_balances_gravity():
    plan = tk.cubic(UR5_POSE, UR5_POSE, duration=2.0)
    scene = sim.arm_scene(_unit_mass_ur5(), gravity_compensation=False)
    log = sim.run(scene, plan, duration=15.0)
    assert np.abs(log.actual_velocity[-1]).max() <= 1e-9  # measured 5e-14 rad/s: settled
    # Gravity at the sagged pose, from a model with the same links and no compensation.
    model = compile_scene(scene.mjcf())
    data = mujoco.MjData(model)
    data.qpos[:] = log.actual[-1]
    mujoco.mj_inverse(model, data)
    servo_torque = 100.0 * (log.desired[-1] - log.actual[-1])
    assert np.abs(servo_torque - data.qfrc_inverse).max() <= STATIC
    assert np.abs(log.efforts[-1] - data.qfrc_inverse).max() <= STATIC
    assert np.degrees(np.abs(log.final_error)).max() >= 5.0  # measured 12.5 deg


def test_ur5_moves_with_computed_torque():
    goal = UR5_POSE + np.array([0.4, -0.3, 0.5, 0.2, -0.6, 0.8])
    plan = tk.cubic(UR5_POSE, goal, duration=2.0)
    log = sim.run(sim.arm_scene(UR5()), plan, controller="computed_torque")
    assert np.degrees(log.max_error.max()) <= 0.01
    assert np.degrees(np.abs(log.final_error).max()) <= 0.01


# Controller objects and their gains ---------------------------------------------------
@pytest.mark.parametrize(
    ("controller", "default"),
    [
        (sim.PositionServo(kp=400.0, kv=20.0), "position"),
        (sim.PositionServo(kp=[100.0, 50.0], kv=[10.0, 5.0]), "position"),
        (sim.VelocityServo(kp=0.0), "velocity"),
        (sim.PDFeedforward(kp=400.0, kv=40.0), "pd_feedforward"),
        (sim.ComputedTorque(frequency=60.0), "computed_torque"),
        (sim.ComputedTorque(damping_ratio=0.3), "computed_torque"),
    ],
)
def test_custom_gains_change_the_run(logs, controller, default):
    log = sim.run(sim.rrbot_scene(), seed_000(), controller=controller)
    assert not np.array_equal(log.actual, logs[default].actual)
    assert log.controller == logs[default].controller


def test_stiffer_servo_lags_less():
    log = sim.run(sim.rrbot_scene(), seed_000(), controller=sim.PositionServo(kp=400.0, kv=20.0))
    # (20 + 0.7) / 400 of the peak velocity: measured 0.468 deg, half the default's.
    expected = (20.0 + 0.7) * np.abs(log.desired_velocity).max(axis=0) / 400.0
    np.testing.assert_allclose(log.max_error, expected, rtol=LAG)


def test_faster_error_dynamics_track_closer(logs):
    fast = sim.run(sim.rrbot_scene(), seed_000(), controller=sim.ComputedTorque(frequency=60.0))
    slow = sim.run(sim.rrbot_scene(), seed_000(), controller=sim.ComputedTorque(frequency=10.0))
    # Measured 5.4e-5, 1.1e-4 and 3.1e-4 deg at 60, 30 and 10 rad/s.
    assert fast.max_error.max() < logs["computed_torque"].max_error.max() < slow.max_error.max()


def test_arm_controller_from_names_and_objects():
    for name, kind in (("position", sim.PositionServo), ("velocity", sim.VelocityServo),
                       ("pd_feedforward", sim.PDFeedforward),
                       ("computed_torque", sim.ComputedTorque)):  # fmt: skip
        assert sim.arm_controller(name) == kind()
    servo = sim.PositionServo(kp=5.0)
    assert sim.arm_controller(servo) is servo


@pytest.mark.parametrize(
    ("controller", "match"),
    [
        ("nope", r"unknown arm controller 'nope'; choose one of \['computed_torque'"),
        ("Position", r"unknown arm controller 'Position'"),
        (sim.PositionServo, r"controller must be a name or a PositionServo.* got type"),
        (42, r"controller must be a name or a PositionServo.* got int"),
    ],
)
def test_arm_controller_refuses_unknown_controllers(controller, match):
    with pytest.raises(InvalidInputError, match=match):
        sim.arm_controller(controller)
    with pytest.raises(InvalidInputError, match=match):
        sim.run(sim.rrbot_scene(), seed_000(), controller=controller)


@pytest.mark.parametrize(
    ("controller", "match"),
    [
        (sim.PositionServo(kp=[1.0, 2.0, 3.0]), r"kp must be one number or one per joint \(2\)"),
        (sim.PositionServo(kp=-1.0), r"kp must be >= 0 N·m/rad, got \[-1.0, -1.0\]"),
        (sim.PositionServo(kv=[10.0, -1.0]), r"kv must be >= 0 N·m·s/rad, got \[10.0, -1.0\]"),
        (sim.PositionServo(kp=np.nan), r"kp must be finite"),
        (sim.VelocityServo(kv=[[1.0, 2.0]]), r"kv must be one number or one per joint \(2\)"),
        (sim.PDFeedforward(kp=-5.0), r"kp must be >= 0 N·m/rad"),
        (sim.ComputedTorque(frequency=0.0), r"frequency must be > 0"),
        (sim.ComputedTorque(frequency=-30.0), r"frequency must be > 0"),
        (sim.ComputedTorque(damping_ratio=-1.0), r"damping_ratio must be > 0"),
        (sim.ComputedTorque(frequency=np.inf), r"frequency must be finite"),
    ],
)
def test_bad_gains_are_refused(controller, match):
    with pytest.raises(InvalidInputError, match=match):
        sim.run(sim.rrbot_scene(), seed_000(), controller=controller)


# Rates, durations and plans that do not fit ---------------------------------------------
def test_control_rate_must_be_whole_physics_steps():
    with pytest.raises(InvalidInputError, match="whole number of physics steps"):
        sim.run(sim.rrbot_scene(), seed_000(), control_rate_hz=300.0)
    with pytest.raises(InvalidInputError, match="whole number of physics steps"):
        sim.run(sim.rrbot_scene(timestep=0.002), seed_000())  # 1 kHz is half a step


#: Largest tracking error on seed 000 at 250 Hz (deg): bound, and measured.
SEED_000_250_HZ_BOUND_DEG = {
    "position": 1.2,  # measured 0.976
    "velocity": 0.14,  # measured 0.090
    "pd_feedforward": 0.02,  # measured 0.0135
    "computed_torque": 8e-4,  # measured 4.7e-4
}


@pytest.mark.parametrize("controller", CONTROLLERS)
def test_slower_control_rate(controller):
    log = sim.run(sim.rrbot_scene(), seed_000(), controller=controller, control_rate_hz=250.0)
    assert np.all(np.abs(np.diff(log.t) - 0.004) <= 1e-12)
    assert log.t.size == int(np.ceil(seed_000().duration * 250.0)) + 1
    assert np.degrees(log.max_error.max()) <= SEED_000_250_HZ_BOUND_DEG[controller]


def test_pd_feedforward_lags_by_its_stale_setpoint():
    # A setpoint held for a period T of physics steps h is, on average over the steps,
    # (T - h) / 2 old; the feed-forward carries the motion, so the PD settles where its
    # mean torque is zero: an error of q̇_d (T - h) / 2 (measured to 0.05%).
    log = sim.run(sim.rrbot_scene(), seed_000(), controller="pd_feedforward", control_rate_hz=250.0)
    expected = np.abs(log.desired_velocity).max(axis=0) * (0.004 - 0.001) / 2.0
    np.testing.assert_allclose(log.max_error, expected, rtol=LAG)


@pytest.mark.parametrize(
    ("plan", "match"),
    [
        (tk.cubic([0.0, 0.0, 0.0], [0.1, 0.2, 0.3], 1.0),
         r"the plan has 3 joint\(s\) but RRBot has 2"),
        (tk.cubic(0.0, 0.1, 1.0), r"the plan has 1 joint\(s\) but RRBot has 2"),
        (constant_twist(0.1, 0.0, 1.0),
         r"an arm scene runs a joint Trajectory, got MobileTrajectory"),
        (np.zeros((10, 2)), r"an arm scene runs a joint Trajectory, got ndarray"),
    ],
)  # fmt: skip
def test_plans_that_do_not_fit_are_refused(plan, match):
    with pytest.raises(InvalidInputError, match=match):
        sim.run(sim.rrbot_scene(), plan)


@pytest.mark.parametrize(
    ("options", "match"),
    [
        ({"initial_pose": (0.0, 0.0, 0.0)}, r"arm scenes take no initial_pose"),
        ({"feedback": "odometry", "limits": None}, r"arm scenes take no feedback, limits"),
        ({"duration": 0.0}, r"duration must be > 0"),
        ({"duration": -1.0}, r"duration must be > 0"),
        ({"control_rate_hz": 0.0}, r"control_rate_hz must be > 0"),
    ],
)
def test_bad_run_options_are_refused(options, match):
    with pytest.raises(InvalidInputError, match=match):
        sim.run(sim.rrbot_scene(), seed_000(), **options)


@pytest.mark.parametrize("scene", [None, "rrbot", UR5()])
def test_run_needs_a_scene(scene):
    with pytest.raises(InvalidInputError, match="scene must be an ArmScene or a MobileScene"):
        sim.run(scene, seed_000())


def test_shorter_duration_stops_early(logs):
    log = sim.run(sim.rrbot_scene(), seed_000(), duration=3.0)
    assert log.t[-1] == pytest.approx(3.0, rel=ROUNDING)
    np.testing.assert_array_equal(log.actual, logs["position"].actual[: log.t.size])


def test_longer_duration_holds_the_final_state():
    plan = seed_000()
    log = sim.run(sim.rrbot_scene(), plan, duration=20.0)
    assert log.t[-1] == pytest.approx(20.0, rel=ROUNDING)
    after = log.t > plan.end_time
    goal = plan.evaluate(plan.end_time)
    np.testing.assert_array_equal(log.desired[after], np.tile(goal, (after.sum(), 1)))
    # The servo converges onto the held goal: measured 2e-13 rad after 8.8 s of holding.
    assert np.abs(log.final_error).max() <= 1e-9
    assert np.abs(log.actual_velocity[-1]).max() <= 1e-9


@pytest.mark.parametrize("controller", ["pd_feedforward", "computed_torque"])
def test_longer_duration_holds_the_final_state_with_torque_control(controller):
    plan = seed_000()
    log = sim.run(sim.rrbot_scene(), plan, duration=20.0, controller=controller)
    after = log.t > plan.end_time
    np.testing.assert_array_equal(log.desired_acceleration[after], 0.0)
    # Held still, the error decays at 30 rad/s (computed torque) or by the PD loop: it
    # should end well inside the error during the motion (measured 3.6e-3 and 5.7e-2 deg).
    assert np.degrees(np.abs(log.final_error).max()) <= SEED_000_BOUND_DEG[controller]


def test_longer_duration_holds_a_plan_that_ends_moving():
    plan = tk.cubic([0.0, 0.0], [0.5, 0.3], 2.0, vf=[0.2, 0.1])
    log = sim.run(sim.rrbot_scene(), plan, duration=6.0, controller="velocity")
    after = log.t > plan.end_time
    np.testing.assert_allclose(log.desired[after], [[0.5, 0.3]] * after.sum(), rtol=ROUNDING)
    np.testing.assert_array_equal(log.desired_velocity[after], 0.0)
    assert np.degrees(np.abs(log.final_error).max()) <= 1.0


# ArmLog metrics, summary, CSV and plot ---------------------------------------------------
@pytest.mark.parametrize("controller", CONTROLLERS)
def test_metrics_are_the_numpy_reductions(logs, controller):
    log = logs[controller]
    error = log.actual - log.desired
    np.testing.assert_array_equal(log.error, error)
    np.testing.assert_allclose(log.rms_error, np.sqrt((error**2).sum(0) / error.shape[0]),
                               rtol=ROUNDING)  # fmt: skip
    np.testing.assert_array_equal(log.max_error, np.max(np.abs(error), axis=0))
    np.testing.assert_array_equal(log.final_error, error[-1])
    np.testing.assert_array_equal(log.peak_effort, np.max(np.abs(log.efforts), axis=0))
    assert np.all(log.rms_error <= log.max_error)


def test_summary_mentions_controller_and_every_joint():
    log = sim.run(sim.arm_scene(UR5()), tk.cubic(UR5_POSE, UR5_POSE + 0.1, duration=0.5))
    text = log.summary()
    assert text.startswith("position servo: 501 control steps over 0.5 s")
    for name in UR5().names:
        assert f"  {name}: RMS error" in text
    assert len(text.splitlines()) == 1 + 6


def test_to_csv_round_trips_at_full_precision(logs, tmp_path):
    log = logs["pd_feedforward"]
    path = log.to_csv(tmp_path / "run.csv")
    assert path == tmp_path / "run.csv"
    header = path.read_text(encoding="utf-8").splitlines()[0].split(",")
    assert header[:3] == ["t [s]", "q1_desired [rad]", "q2_desired [rad]"]
    assert header[-1] == "q2_effort [N·m]"
    assert "q1_desired_acceleration [rad/s^2]" in header
    assert len(header) == 1 + 6 * 2
    table = np.loadtxt(path, skiprows=1, delimiter=",", encoding="utf-8")
    expected = np.column_stack([log.t, log.desired, log.actual, log.desired_velocity,
                                log.actual_velocity, log.desired_acceleration,
                                log.efforts])  # fmt: skip
    np.testing.assert_array_equal(table, expected)


def test_a_log_read_back_from_its_csv_is_the_log(logs, tmp_path):
    log = logs["pd_feedforward"]
    back = sim.ArmLog.from_csv(log.to_csv(tmp_path / "run.csv"))
    for name in ("t", "desired", "desired_velocity", "desired_acceleration", "actual",
                 "actual_velocity", "efforts", "revolute"):  # fmt: skip
        np.testing.assert_array_equal(getattr(back, name), getattr(log, name))
    assert back.joint_names == log.joint_names and back.controller == "run"
    assert back.commands.shape == (log.t.size, 0)  # the file holds no commands
    np.testing.assert_array_equal(back.max_error, log.max_error)
    assert len(tk.plot.tracking(back).get_axes()) == 4  # plotted again


def test_files_that_are_not_arm_logs_are_refused(tmp_path):
    samples = tk.quintic(0.0, 1.0, 1.0).sample(0.1).to_csv(tmp_path / "plan.csv")
    with pytest.raises(InvalidInputError, match=r"not an arm log \(t \[s\], then 6 columns"):
        sim.ArmLog.from_csv(samples)
    broken = tmp_path / "broken.csv"
    broken.write_text("t [s]," + ",".join(f"q1_{k} [rad]" for k in "abcdef") + "\n0,1,2,3,4,5,6\n",
                      encoding="utf-8")  # fmt: skip
    with pytest.raises(InvalidInputError, match="column 2 'q1_a \\[rad\\]' is not"):
        sim.ArmLog.from_csv(broken)
    short = tmp_path / "short.csv"
    header = "t [s]," + ",".join(f"q1_{k}" for k in ("desired [rad]", "actual [rad]",
                                                      "desired_velocity [rad/s]",
                                                      "actual_velocity [rad/s]",
                                                      "desired_acceleration [rad/s^2]",
                                                      "effort [N·m]"))  # fmt: skip
    short.write_text(header + "\n0,1,2,3\n", encoding="utf-8")
    with pytest.raises(InvalidInputError, match="line 2: expected 7 finite numbers"):
        sim.ArmLog.from_csv(short)
    with pytest.raises(InvalidInputError, match="cannot read"):
        sim.ArmLog.from_csv(tmp_path / "missing.csv")


def test_tracking_plot_has_position_velocity_error_and_effort_panels(logs):
    log = logs["position"]
    figure = tk.plot.tracking(log)
    assert isinstance(figure, Figure)
    axes = figure.get_axes()
    assert [ax.get_ylabel() for ax in axes] == ["position [deg]", "velocity [deg/s]",
                                                "error q − q_d [deg]", "effort [N·m]"]  # fmt: skip
    # Positions and velocities: desired dashed and actual solid for every joint.
    for ax, (desired, actual) in zip(axes[:2], ((log.desired, log.actual),
                                               (log.desired_velocity, log.actual_velocity)),
                                     strict=True):  # fmt: skip
        lines = ax.get_lines()
        assert [line.get_linestyle() for line in lines] == ["--", "-"] * log.desired.shape[1]
        np.testing.assert_allclose(lines[1].get_ydata(), np.degrees(actual[:, 0]))
        np.testing.assert_allclose(lines[0].get_ydata(), np.degrees(desired[:, 0]))
    assert [len(ax.get_lines()) >= 2 for ax in axes] == [True] * 4


@pytest.mark.parametrize("log", [None, seed_000(), "log"])
def test_tracking_plot_refuses_other_logs(log):
    with pytest.raises(InvalidInputError, match=r"log must be a trajkit\.sim\.ArmLog"):
        tk.plot.tracking(log)


def test_tracking_plot_refuses_a_mobile_log():
    log = sim.run(sim.jackal_scene(), constant_twist(0.1, 0.1, 1.0), control_rate_hz=10)
    with pytest.raises(InvalidInputError, match=r"trajkit\.sim\.ArmLog, got PhysicsLog"):
        tk.plot.tracking(log)


# Divergence, joint ranges, plan time, slide joints ---------------------------------------
@pytest.mark.parametrize(
    ("controller", "rate_hz"),
    [("computed_torque", 20.0), (sim.PositionServo(kp=1e9, kv=1e3), 1000.0)],
)
def test_a_diverging_simulation_raises_and_writes_no_mujoco_log(
    controller, rate_hz, tmp_path, monkeypatch
):
    monkeypatch.chdir(tmp_path)  # MuJoCo's own handler would append to MUJOCO_LOG.TXT here
    with pytest.raises(InfeasibleError, match=r"the simulation diverged \(MuJoCo: Nan, Inf or "
                       r"huge value in QACC.*\); the .* is unstable on this arm"):  # fmt: skip
        sim.run(sim.rrbot_scene(), seed_000(), controller=controller, control_rate_hz=rate_hz)
    assert list(tmp_path.iterdir()) == []
    # MuJoCo's own warning handler is back afterwards.
    assert mujoco.get_mju_user_warning() is None


def test_computed_torque_is_stable_at_a_moderate_rate():
    log = sim.run(sim.rrbot_scene(), seed_000(), controller="computed_torque",
                  control_rate_hz=50.0)  # fmt: skip
    assert np.degrees(log.max_error).max() < 0.05  # measured 0.018 deg


def test_a_plan_outside_the_joint_ranges_is_refused():
    robot = SerialChain.from_dh(
        [DHRow(a=0.3, lower=-1.0, upper=1.0), DHRow(a=0.3, lower=-1.0, upper=1.0)]
    )
    with pytest.raises(
        InvalidInputError, match=r"takes joint q1 to 2, outside its range \[-1, 1\]"
    ):
        sim.run(sim.arm_scene(robot), tk.cubic([0.5, 0.0], [2.0, 0.5], 1.0))
    inside = sim.run(sim.arm_scene(robot), tk.cubic([0.5, 0.0], [1.0, -1.0], 1.0))
    assert inside.t.size == 1001


def test_log_times_are_the_plans_own():
    plan = tk.cubic([0.0, 0.0], [0.3, -0.2], 3.0)
    later = tk.Trajectory(plan.breakpoints + 5.0, plan.coefficients)
    log = sim.run(sim.rrbot_scene(), later, controller="computed_torque")
    assert log.t[0] == 5.0 and log.t[-1] == pytest.approx(8.0, rel=ROUNDING)
    np.testing.assert_array_equal(log.desired, later.evaluate(log.t))
    assert "3001 control steps over 3 s" in log.summary()


def test_slide_joints_are_reported_in_metres_and_newtons(tmp_path):
    robot = SerialChain.from_dh(
        [DHRow(a=0.3), DHRow(d=0.1, kind="prismatic", lower=-0.2, upper=0.2)],
        names=["turn", "slide"],
    )
    log = sim.run(sim.arm_scene(robot), tk.cubic([0.0, 0.0], [0.5, 0.1], 1.0),
                  controller="computed_torque")  # fmt: skip
    np.testing.assert_array_equal(log.revolute, [True, False])
    lines = log.summary().splitlines()
    assert " deg, " in lines[1] and "N·m" in lines[1]
    assert " mm, " in lines[2] and lines[2].endswith(" N")
    header = log.to_csv(tmp_path / "log.csv").read_text(encoding="utf-8").splitlines()[0]
    for column in ("slide_desired [m]", "slide_actual_velocity [m/s]", "slide_effort [N]",
                   "turn_effort [N·m]", "slide_desired_acceleration [m/s^2]"):  # fmt: skip
        assert column in header.split(",")
    figure = tk.plot.tracking(log)
    assert figure.get_axes()[0].get_ylabel() == "position [deg | m]"
    assert figure.get_axes()[1].get_ylabel() == "velocity [deg/s | m/s]"
    assert figure.get_axes()[3].get_ylabel() == "effort [N | N·m]"
