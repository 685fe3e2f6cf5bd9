"""Tests of mobile runs in MuJoCo: the Jackal scene driving a constant twist and a
rotate–translate–rotate move, feedback from ground truth or odometry, the log's
kinematic prediction and odometry, determinism, CSV, plots and bad input.

Bounds are the measured values (MuJoCo 4.0, 1 ms steps) times about 1.5, with the
measured value beside each. The kinematic prediction chains exact arcs of the held
commands, so it matches the closed-form circle to rounding.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp
from matplotlib.figure import Figure

import support
import trajkit as tk
from support import ROUNDING, WORLD_ROUNDING
from trajkit import sim
from trajkit.errors import InvalidInputError
from trajkit.mobile import (
    Feedforward,
    Kanayama,
    MobileLimits,
    arc_pose,
    constant_twist,
    rotate_translate_rotate,
)
from trajkit.mobile.models import chain_arcs, jackal

mujoco = pytest.importorskip("mujoco", reason="MuJoCo is not installed: pip install 'trajkit[sim]'")

FEW = settings(max_examples=50, deadline=None)
ARC_CHAIN = 1e-12  # relative to the chain's length: chain_arcs against arc_pose in turn

V, OMEGA, DURATION = 0.1, np.radians(10.0), 15.0
RADIUS = V / OMEGA
TURN = OMEGA * DURATION
ARC_END = np.array([RADIUS * np.sin(TURN), RADIUS * (1.0 - np.cos(TURN)), TURN])
GOAL = (5.0, 3.0, 1.5)


def twist_plan():
    return constant_twist(V, OMEGA, DURATION, rate_hz=10)


def rtr_plan():
    return rotate_translate_rotate(GOAL, (0, 0, 0), vmax=0.2, wmax=np.radians(30), blend_ratio=0.1)


@pytest.fixture(scope="module")
def twist_log() -> sim.PhysicsLog:
    return sim.run(sim.jackal_scene(), twist_plan(), control_rate_hz=10)


@pytest.fixture(scope="module")
def rtr_logs() -> dict[tuple[str, str], sim.PhysicsLog]:
    scene, plan = sim.jackal_scene(), rtr_plan()
    return {
        (name, feedback): sim.run(scene, plan, controller=controller, feedback=feedback)
        for name, controller in (("feedforward", Feedforward()), ("kanayama", Kanayama()))
        for feedback in ("ground_truth", "odometry")
    }


def log_arrays(log: sim.PhysicsLog) -> dict[str, np.ndarray]:
    names = ("t", "desired", "actual", "desired_twist", "commands", "wheel_speeds",
             "path_distance", "odometry", "kinematic", "measured_wheel_speeds",
             "wheel_torques")  # fmt: skip
    return {name: getattr(log, name) for name in names}


# A constant twist: one circular arc ------------------------------------------------------
def test_constant_twist_ends_near_the_exact_arc(twist_log):
    end = twist_log.actual[-1]
    assert np.hypot(*(end[:2] - ARC_END[:2])) <= 6e-3  # measured 3.7 mm
    assert np.degrees(abs(end[2] - ARC_END[2])) <= 0.3  # measured 0.196 deg


def test_kinematic_prediction_is_the_closed_form_arc(twist_log):
    scale = RADIUS + V * DURATION
    assert np.abs(twist_log.kinematic[-1] - ARC_END).max() <= 1e-12 * scale  # measured 5e-15
    # Every row: the arc so far, R (sin ωt, 1 − cos ωt), ωt.
    t = twist_log.t
    expected = np.column_stack([RADIUS * np.sin(OMEGA * t), RADIUS * (1 - np.cos(OMEGA * t)),
                                OMEGA * t])  # fmt: skip
    assert np.abs(twist_log.kinematic - expected).max() <= 1e-12 * scale
    np.testing.assert_allclose(twist_log.desired, expected, rtol=0, atol=1e-12 * scale)


def test_odometry_follows_ground_truth(twist_log):
    assert twist_log.odometry_drift <= 6e-3  # measured 3.8 mm
    assert twist_log.kinematic_gap <= 6e-3  # measured 3.7 mm
    np.testing.assert_array_equal(twist_log.odometry[0], [0.0, 0.0, 0.0])


def test_constant_twist_log_grid_and_fields(twist_log):
    log = twist_log
    assert log.t.shape == (151,)
    np.testing.assert_allclose(log.t, np.arange(151) / 10.0, rtol=ROUNDING, atol=0.0)
    for name in ("desired", "actual", "odometry", "kinematic"):
        assert getattr(log, name).shape == (151, 3), name
    for name in ("desired_twist", "commands", "wheel_speeds", "measured_wheel_speeds",
                 "wheel_torques"):  # fmt: skip
        assert getattr(log, name).shape == (151, 2), name
    assert log.path_distance.shape == (151,)
    assert (log.controller, log.feedback) == ("feedforward", "ground_truth")
    robot = sim.jackal_scene().model
    np.testing.assert_array_equal(log.wheel_speeds, robot.wheel_speeds(*log.commands.T))
    np.testing.assert_array_equal(log.commands[:-1], np.tile([V, OMEGA], (150, 1)))


def test_wheel_servos_hold_their_speeds(twist_log):
    log = twist_log
    steady = log.t >= 0.5
    gap = np.abs(log.measured_wheel_speeds[steady] - log.wheel_speeds[steady]).max()
    assert gap <= 3e-5  # rad/s; measured 1.5e-5
    # The peak is the start: from rest, the right wheel's servo sees its whole commanded
    # speed as error, kv (10 N·m·s/rad) times 1.522 rad/s.
    assert log.peak_wheel_torque == pytest.approx(10.0 * log.wheel_speeds[0, 1], rel=1e-12)
    assert log.peak_wheel_torque == np.abs(log.wheel_torques).max()
    assert np.abs(log.wheel_torques[steady]).max() <= 0.5  # N·m rolling on; measured 0.37


def test_summary_adds_the_physics_metrics(twist_log):
    text = twist_log.summary()
    assert text.startswith("feedforward: RMS error")
    for fragment in ("odometry drift", "kinematic model off by", "peak wheel torque"):
        assert fragment in text


# Rotate, translate, rotate ---------------------------------------------------------------
def test_feedforward_ends_within_a_centimetre(rtr_logs):
    log = rtr_logs["feedforward", "ground_truth"]
    assert log.final_position_error <= 0.01  # measured 6.6 mm
    assert np.degrees(log.final_heading_error) <= 0.12  # measured 0.077 deg
    np.testing.assert_allclose(log.desired[-1], GOAL, rtol=0, atol=WORLD_ROUNDING * 10)


def test_kanayama_ends_closer_than_feedforward(rtr_logs):
    feedback = rtr_logs["kanayama", "ground_truth"]
    open_loop = rtr_logs["feedforward", "ground_truth"]
    assert feedback.final_position_error <= 4e-4  # measured 0.22 mm
    assert feedback.final_position_error < open_loop.final_position_error / 10
    assert feedback.max_error <= 6e-3  # measured 4.0 mm


def test_odometry_feedback_runs_and_differs(rtr_logs):
    truth, odometry = rtr_logs["kanayama", "ground_truth"], rtr_logs["kanayama", "odometry"]
    assert odometry.feedback == "odometry"
    assert not np.array_equal(odometry.actual, truth.actual)
    # Feedback on odometry corrects only what the encoders see: it ends about where dead
    # reckoning does, 5.8 mm off (feedforward 6.6 mm), not 0.2 mm as on ground truth.
    assert 2e-3 <= odometry.final_position_error <= 1e-2
    assert odometry.odometry_drift <= 0.015  # measured 9.5 mm


def test_feedback_source_does_not_matter_to_feedforward(rtr_logs):
    for name, array in log_arrays(rtr_logs["feedforward", "ground_truth"]).items():
        np.testing.assert_array_equal(getattr(rtr_logs["feedforward", "odometry"], name), array)


@pytest.mark.parametrize("key", [("feedforward", "ground_truth"), ("kanayama", "odometry")])
def test_mobile_runs_are_bit_for_bit_repeatable(rtr_logs, key):
    name, feedback = key
    controller = Kanayama() if name == "kanayama" else None
    again = sim.run(sim.jackal_scene(), rtr_plan(), controller=controller, feedback=feedback)
    for field, array in log_arrays(rtr_logs[key]).items():
        np.testing.assert_array_equal(getattr(again, field), array, err_msg=field)


@pytest.mark.parametrize("controller", [Feedforward(), Kanayama()])
@pytest.mark.parametrize("pose", [(0.05, -0.03, 0.1), (0.05, -0.03)])
def test_initial_pose_is_where_the_run_starts(controller, pose):
    plan = rtr_plan()
    log = sim.run(sim.jackal_scene(), plan, controller=controller, initial_pose=pose)
    start = np.array([*pose, plan.start_pose[2]][:3]) if len(pose) == 2 else np.array(pose)
    assert np.abs(log.actual[0] - start).max() <= 1e-9
    np.testing.assert_array_equal(log.odometry[0], start)
    np.testing.assert_array_equal(log.kinematic[0], start)
    if isinstance(controller, Kanayama):
        assert log.final_position_error <= 4e-4  # the offset is corrected: measured 0.22 mm


def test_limits_option_saturates_the_commands(twist_log):
    log = sim.run(sim.jackal_scene(), twist_plan(), control_rate_hz=10,
                  limits=MobileLimits(velocity=0.05))  # fmt: skip
    assert log.commands[:, 0].max() <= 0.05 * (1 + ROUNDING)
    assert log.final_position_error > twist_log.final_position_error


def test_longer_duration_stands_still_at_the_end():
    log = sim.run(sim.jackal_scene(), twist_plan(), control_rate_hz=10, duration=20.0)
    assert log.t[-1] == pytest.approx(20.0, rel=ROUNDING)
    late = log.t > DURATION
    np.testing.assert_array_equal(log.commands[late], 0.0)
    np.testing.assert_allclose(log.desired[late], np.tile(ARC_END, (late.sum(), 1)),
                               rtol=0, atol=1e-12)  # fmt: skip
    # Stopped within a few mm of where the twist took it: measured 3.7 mm, still.
    assert np.hypot(*(log.actual[-1, :2] - ARC_END[:2])) <= 6e-3
    assert np.abs(log.actual[-1] - log.actual[-5]).max() <= 1e-6


# Bad input ---------------------------------------------------------------------------------
class NoLaw:
    name = "no law"


@pytest.mark.parametrize(
    ("plan", "kwargs", "match"),
    [
        (tk.cubic([0.0, 0.0], [1.0, 1.0], 1.0), {},
         r"a mobile scene runs a MobileTrajectory, got Trajectory"),
        (None, {"noise": (0.01, 0.01)}, r"unknown option\(s\) for a mobile run: \['noise'\]"),
        (None, {"seed": 1, "dt": 0.1}, r"unknown option\(s\) for a mobile run: \['dt', 'seed'\]"),
        (None, {"feedback": "gps"}, r"feedback must be 'ground_truth' or 'odometry', got 'gps'"),
        (None, {"controller": NoLaw()}, r"controller must be a name or have a law\(plan, start\)"),
        (None, {"controller": "kanaiama"}, r"controller must be one of feedforward, kanayama"),
        (None, {"control_rate_hz": 30.0}, r"whole number of physics steps"),
        (None, {"control_rate_hz": 3000.0}, r"whole number of physics steps"),
        (None, {"control_rate_hz": -50.0}, r"control_rate_hz must be > 0"),
        (None, {"duration": 0.0}, r"duration must be > 0"),
        (None, {"initial_pose": (1.0, 2.0, 3.0, 4.0)}, r"initial_pose must be a pose"),
        (None, {"initial_pose": (np.nan, 0.0)}, r"initial_pose must be finite"),
    ],
)  # fmt: skip
def test_mobile_run_refuses_bad_input(plan, kwargs, match):
    with pytest.raises(InvalidInputError, match=match):
        sim.run(sim.jackal_scene(), twist_plan() if plan is None else plan, **kwargs)


# CSV and plots -----------------------------------------------------------------------------
def test_to_csv_round_trips_at_full_precision(twist_log, tmp_path):
    path = twist_log.to_csv(tmp_path / "base.csv")
    header = path.read_text(encoding="utf-8").splitlines()[0].split(",")
    assert len(header) == 24
    assert header[:4] == ["t [s]", "x_desired [m]", "y_desired [m]", "theta_desired [rad]"]
    assert header[7:10] == ["x_odometry [m]", "y_odometry [m]", "theta_odometry [rad]"]
    assert header[-3:] == ["torque_left [N·m]", "torque_right [N·m]", "path_distance [m]"]
    table = np.loadtxt(path, skiprows=1, delimiter=",", encoding="utf-8")
    log = twist_log
    expected = np.column_stack([log.t, log.desired, log.actual, log.odometry, log.kinematic,
                                log.desired_twist, log.commands, log.wheel_speeds,
                                log.measured_wheel_speeds, log.wheel_torques,
                                log.path_distance])  # fmt: skip
    np.testing.assert_array_equal(table, expected)
    back = sim.PhysicsLog.from_csv(path)  # read back, bit for bit, to plot or check again
    fields = (
        "t",
        "desired",
        "actual",
        "odometry",
        "kinematic",
        "desired_twist",
        "commands",
        "wheel_speeds",
        "measured_wheel_speeds",
        "wheel_torques",
        "path_distance",
    )
    for name in fields:
        np.testing.assert_array_equal(getattr(back, name), getattr(log, name))
    assert back.controller == "base" and back.odometry_drift == log.odometry_drift
    with pytest.raises(InvalidInputError, match="no column 'x_odometry \\[m\\]'"):
        sim.PhysicsLog.from_csv(tk.mobile.simulate(twist_plan(), sample_step=0.1).to_csv(
            tmp_path / "kinematic.csv"))  # fmt: skip


def test_mobile_plots_take_a_physics_log(twist_log):
    figure = tk.plot.mobile(twist_log)
    assert isinstance(figure, Figure)
    assert len(figure.get_axes()) == 6  # v, ω, world velocity, position, heading, errors
    path = tk.plot.mobile_path(twist_log)
    assert isinstance(path, Figure)
    assert len(path.get_axes()) == 1
    # Planned and actual paths are drawn.
    assert len(path.get_axes()[0].get_lines()) >= 2


# chain_arcs, which the log's odometry and prediction are built with ---------------------------
@FEW
@given(
    start=support.poses(),
    arcs=st.integers(1, 25).flatmap(
        lambda n: st.tuples(
            hnp.arrays(np.float64, n, elements=st.one_of(st.just(0.0), st.floats(-2.0, 2.0))),
            hnp.arrays(np.float64, n, elements=st.one_of(st.just(0.0), st.floats(-4.0, 4.0))),
        )
    ),
)
def test_chain_arcs_is_arc_pose_in_turn(start, arcs):
    distances, turns = arcs
    poses = chain_arcs(start, distances, turns)
    assert poses.shape == (distances.size + 1, 3)
    expected = [start]
    for distance, turn in zip(distances, turns, strict=True):
        expected.append(arc_pose(expected[-1], distance, turn, 1.0))
    expected = np.array(expected)
    scale = max(1.0, np.abs(start[:2]).max() + np.abs(distances).sum())
    assert np.abs(poses[:, :2] - expected[:, :2]).max() <= ARC_CHAIN * scale
    heading_scale = max(1.0, abs(start[2]) + np.abs(turns).sum())
    assert np.abs(poses[:, 2] - expected[:, 2]).max() <= ARC_CHAIN * heading_scale


def test_mobile_controllers_by_name():
    plan = constant_twist(0.1, 0.2, 2.0)
    by_name = sim.run(sim.jackal_scene(), plan, controller="kanayama")
    by_object = sim.run(sim.jackal_scene(), plan, controller=Kanayama())
    assert by_name.controller == "kanayama"
    np.testing.assert_array_equal(by_name.actual, by_object.actual)


def test_the_four_wheel_skid_steer_jackal_beside_the_differential_one():
    differential, skid = sim.jackal_scene(), sim.MobileScene(jackal(), drive="skid_steer")
    model = skid.compiled()
    # Four wheels, no casters; the rear wheels follow the front ones (one drive a side).
    assert model.nu == 2 and model.neq == 2 and model.njnt == 5
    assert "caster" not in skid.mjcf() and "rear_left_wheel" in skid.mjcf()
    straight = constant_twist(0.5, 0.0, 4.0, rate_hz=20)
    runs = [sim.run(scene, straight, control_rate_hz=20) for scene in (differential, skid)]
    np.testing.assert_allclose(runs[1].actual[-1], runs[0].actual[-1], atol=0.01)  # 1 cm
    wheels = sim.run(skid, straight, control_rate_hz=20)
    np.testing.assert_allclose(wheels.measured_wheel_speeds[-40:], wheels.wheel_speeds[-40:],
                               rtol=0.05)  # fmt: skip
    # Turning in place it skids: measured 0.47 of the planned rate at 1 rad/s.
    spin = sim.run(skid, constant_twist(0.0, 1.0, 4.0, rate_hz=20), control_rate_hz=20)
    share = spin.actual[-1, 2] / spin.desired[-1, 2]
    assert 0.35 < share < 0.65 and abs(spin.actual[-1, 0]) < 0.1
    with pytest.raises(InvalidInputError, match="drive must be 'differential' or 'skid_steer'"):
        sim.MobileScene(jackal(), drive="tracks")
    with pytest.raises(InvalidInputError, match="four wheels of 4 kg leave no chassis"):
        sim.MobileScene(jackal(), drive="skid_steer", wheel_mass=4.0)
