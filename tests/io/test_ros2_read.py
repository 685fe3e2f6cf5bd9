"""Bags read back: the controller's interpolation, plan round trips, simulated runs, the CLI.

``controller_trajectory`` is checked against a transcription of ros2_controllers'
``interpolate_between_points`` formulas (a plain re-implementation); bags written by
trajkit are read back by trajkit's reader and, for the run topics, by the independent
MCAP reader too.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

pytest.importorskip("rosbags", reason="rosbags is not installed: pip install 'trajkit[ros]'")
pytest.importorskip(
    "mcap", reason="bags are read back by the independent MCAP reader: pip install mcap"
)
pytest.importorskip(
    "mcap_ros2",
    reason="bags are read back by the independent MCAP reader: pip install mcap-ros2-support",
)

from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory

import trajkit as tk
from trajkit.cli import main
from trajkit.errors import InvalidInputError
from trajkit.io.ros2 import write_bag
from trajkit.io.ros2_read import JointStates, read_bag
from trajkit.io.trajectory_controller import controller_trajectory
from trajkit.mobile import constant_twist, simulate
from trajkit.mobile.control import controller_named

START = 1_796_634_000 * 1_000_000_000  # 2026-12-07T09:00:00Z


# ------------------------------------------------------ the controller's interpolation
def jtc_sample(t0, a, t1, b, t):
    """ros2_controllers' interpolate_between_points, transcribed: one joint, one time."""
    T, s = t1 - t0, t - t0
    if "v" not in a:
        return a["p"] + s * (b["p"] - a["p"]) / T
    if "a" not in a:
        c2 = (-3.0 * a["p"] + 3.0 * b["p"] - 2.0 * a["v"] * T - b["v"] * T) / T**2
        c3 = (2.0 * a["p"] - 2.0 * b["p"] + a["v"] * T + b["v"] * T) / T**3
        return a["p"] + a["v"] * s + c2 * s**2 + c3 * s**3
    c3 = (-20.0 * a["p"] + 20.0 * b["p"] - 3.0 * a["a"] * T**2 + b["a"] * T**2
          - 12.0 * a["v"] * T - 8.0 * b["v"] * T) / (2.0 * T**3)  # fmt: skip
    c4 = (30.0 * a["p"] - 30.0 * b["p"] + 3.0 * a["a"] * T**2 - 2.0 * b["a"] * T**2
          + 16.0 * a["v"] * T + 14.0 * b["v"] * T) / (2.0 * T**4)  # fmt: skip
    c5 = (-12.0 * a["p"] + 12.0 * b["p"] - a["a"] * T**2 + b["a"] * T**2
          - 6.0 * a["v"] * T - 6.0 * b["v"] * T) / (2.0 * T**5)  # fmt: skip
    return a["p"] + a["v"] * s + 0.5 * a["a"] * s**2 + c3 * s**3 + c4 * s**4 + c5 * s**5


@settings(max_examples=60, deadline=None)
@given(st.integers(2, 6), st.integers(1, 3), st.integers(1, 3), st.integers(0, 2**32 - 1))
def test_the_interpolation_is_the_controllers(points, orders, ndof, seed):
    rng = np.random.default_rng(seed)
    times = np.cumsum(np.r_[rng.uniform(0, 1), rng.uniform(0.05, 2.0, points - 1)])
    fields = [rng.normal(size=(points, ndof)) for _ in range(orders)]
    curve = controller_trajectory(times, *fields)
    assert curve.info["interpolation"] == ("linear", "cubic", "quintic")[orders - 1]
    assert curve.start_time == times[0] and curve.end_time == times[-1]
    t = np.sort(rng.uniform(times[0], times[-1], 50))
    k = np.clip(np.searchsorted(times, t, side="right") - 1, 0, points - 2)
    for j in range(ndof):
        expected = []
        for time, i in zip(t, k, strict=True):
            ends = [dict(zip("pva", (f[i + e, j] for f in fields), strict=False)) for e in (0, 1)]
            expected.append(jtc_sample(times[i], ends[0], times[i + 1], ends[1], time))
        scale = max(1.0, float(np.abs(fields[0]).max()))
        np.testing.assert_allclose(curve.evaluate(t)[:, j], expected, rtol=0, atol=1e-9 * scale)
    # Every point passed with what it carries.
    for order, values in enumerate(fields):
        np.testing.assert_allclose(curve.evaluate(times, order), values, rtol=0, atol=1e-9)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (([0.0], [[1.0]]), "at least 2 points"),
        (([0.0, 0.0], [[1.0], [2.0]]), "times must increase strictly"),
        (([0.0, 1.0], [[1.0], [np.nan]]), "positions must be finite"),
        (([0.0, 1.0], [[1.0], [2.0]], None, [[0.0], [0.0]]), "accelerations but no velocities"),
        (([0.0, 1.0], [[1.0], [2.0]], [[0.0, 1.0], [0.0, 1.0]]), "must have one shape"),
        (([0.0, 1.0, 2.0], [[1.0], [2.0]]), r"positions must have shape \(3, ndof\)"),
        (([0.0, np.inf], [[1.0], [2.0]]), "times must be finite"),
    ],
)
def test_bad_points_are_refused(args, message):
    with pytest.raises(InvalidInputError, match=message):
        controller_trajectory(*args)


# ---------------------------------------------------------------- plan round trips
PLANS = {
    "quintic": lambda: tk.quintic(np.zeros(2), [1.0, 2.0], 1.5),
    "cubic": lambda: tk.cubic(np.radians([0, 0]), np.radians([67, -45]), duration=4.0),
    "scurve": lambda: tk.scurve(np.zeros(2), [1.0, -0.5], 1.0, 2.0, 10.0),
    "spline": lambda: tk.quintic_via([0.0, 1.0, 2.5, 3.0], [[0, 0], [1, -1], [0.5, 2], [0, 0]]),
}
#: Position, velocity and acceleration tolerances (relative to each one's peak, at least
#: 1). Points are stamped in whole nanoseconds. Where the plan's breakpoints are whole
#: nanoseconds the curve read back is the plan's to rounding; the S-curve's phase
#: times are not, and each point's state then sits up to 0.5 ns off its stamp, which
#: the position keeps within 1e-9 (measured 1.6e-10) and the velocity and acceleration
#: within 2e-8 and 1e-5 (measured 1.1e-8 and 3.7e-6).
ROUND_TRIP = {"quintic": (1e-9, 1e-12, 1e-12), "cubic": (1e-9, 1e-12, 1e-12),
              "spline": (1e-9, 1e-12, 1e-12), "scurve": (1e-9, 2e-8, 1e-5)}  # fmt: skip


@pytest.mark.parametrize("storage", ["mcap", "sqlite3"])
@pytest.mark.parametrize("name", sorted(PLANS))
def test_a_plan_read_back_is_the_plan(tmp_path: Path, name: str, storage: str) -> None:
    # Degree <= 5 with continuous acceleration: points at the breakpoints, and the
    # controller's quintics between them are the plan's own pieces.
    plan = PLANS[name]()
    bag = write_bag(tmp_path / "bag", plan, storage=storage, start_ns=START,
                    joint_names=["shoulder", "elbow"])  # fmt: skip
    back = read_bag(bag)
    assert back.origin_ns == START
    curve = back.joint_trajectory()
    assert curve.info["joint_names"] == ("shoulder", "elbow")
    assert curve.info["interpolation"] == "quintic"
    t = np.linspace(plan.start_time, plan.end_time, 2001)
    for order in range(3):
        scale = max(1.0, float(np.abs(plan.evaluate(t, order)).max()))
        np.testing.assert_allclose(curve.evaluate(t, order), plan.evaluate(t, order), rtol=0,
                                   atol=ROUND_TRIP[name][order] * scale)  # fmt: skip


def test_a_sampled_stream_is_read_back_at_its_stamps(tmp_path: Path) -> None:
    plan = PLANS["scurve"]()
    bag = read_bag(write_bag(tmp_path / "bag", plan, stream="joint_state", rate_hz=50.0))
    states = bag.joint_states()
    np.testing.assert_allclose(states.t, np.round(states.t * 50) / 50, atol=1e-12)
    np.testing.assert_allclose(states.position, plan.evaluate(states.t), rtol=0, atol=1e-12)
    np.testing.assert_allclose(states.velocity, plan.evaluate(states.t, 1), rtol=0, atol=1e-12)
    assert states.effort is None and states.names == ("joint1", "joint2")


def test_joint_states_are_checked_at_their_samples(tmp_path: Path) -> None:
    plan = PLANS["scurve"]()  # peaks at 1 rad/s
    states = read_bag(write_bag(tmp_path / "bag", plan, stream="joint_state")).joint_states()
    assert states.check(tk.Limits(velocity=1.0 + 1e-6)).ok
    report = states.check(tk.Limits(velocity=0.9, position=(-1.0, 0.9)))
    assert not report.ok
    assert {(v.quantity, v.channel) for v in report.violations} == {
        ("velocity", "joint1"), ("position", "joint1")}  # fmt: skip
    with pytest.raises(InvalidInputError, match="carry no effort"):
        states.check(tk.Limits(velocity=1.0), effort=5.0)


# ---------------------------------------------------------------- simulated runs
def _mcap_topics(bag: Path) -> dict[str, list]:
    (file,) = bag.glob("*.mcap")
    topics: dict[str, list] = {}
    with file.open("rb") as handle:
        reader = make_reader(handle, decoder_factories=[DecoderFactory()])
        for schema, channel, message, decoded in reader.iter_decoded_messages():
            topics.setdefault(channel.topic, []).append((message.log_time, schema.name, decoded))
    return topics


def test_a_simulated_arm_run_is_in_the_bag(tmp_path: Path) -> None:
    pytest.importorskip("mujoco", reason="MuJoCo is not installed: pip install 'trajkit[sim]'")
    from trajkit import sim
    from trajkit.kinematics import RRBot

    robot = RRBot()
    plan = tk.quintic(np.zeros(2), [0.6, -0.4], 1.0)
    run = sim.run(sim.arm_scene(robot), plan, control_rate_hz=200.0)
    bag = write_bag(tmp_path / "bag", plan, run=run, start_ns=START, joint_names=robot.names,
                    stream="point")  # fmt: skip
    back = read_bag(bag)
    command_topic = "/position_servo_controller/commands"
    assert back.topics == {
        "/joint_trajectory": ("trajectory_msgs/msg/JointTrajectory", 1),
        "/joint_trajectory_point": ("trajectory_msgs/msg/JointTrajectoryPoint", 101),
        "/joint_states": ("sensor_msgs/msg/JointState", run.t.size),
        command_topic: ("std_msgs/msg/Float64MultiArray", run.t.size),
    }
    states = back.joint_states()
    np.testing.assert_allclose(states.t, run.t, rtol=0, atol=1e-9)
    for recorded, simulated in ((states.position, run.actual),
                                (states.velocity, run.actual_velocity),
                                (states.effort, run.efforts)):  # fmt: skip
        np.testing.assert_array_equal(recorded, simulated)
    independent = _mcap_topics(bag)
    stamps = [time for time, _, _ in independent["/joint_states"]]
    assert stamps == [START + round(t * 1e9) for t in run.t]
    decoded = [message for _, _, message in independent[command_topic]]
    np.testing.assert_array_equal([list(m.data) for m in decoded], run.commands)
    np.testing.assert_array_equal([list(m.position) for _, _, m in independent["/joint_states"]],
                                  run.actual)  # fmt: skip


def _base_run():
    plan = constant_twist(0.2, np.radians(20), 6.0, rate_hz=10)
    run = simulate(plan, controller_named("feedforward"), sample_step=0.01, command_rate_hz=10)
    return plan, run


@pytest.mark.parametrize("cmd_vel", ["Twist", "TwistStamped"])
def test_a_simulated_base_run_is_in_the_bag(tmp_path: Path, cmd_vel: str) -> None:
    plan, run = _base_run()
    bag = write_bag(tmp_path / "bag", plan, run=run, start_ns=START, cmd_vel=cmd_vel)
    back = read_bag(bag)
    assert sorted(back.topics) == ["/cmd_vel", "/odom", "/plan", "/tf"]
    twists = back.twists()
    np.testing.assert_allclose(twists.t, run.t, rtol=0, atol=1e-9)
    np.testing.assert_array_equal(twists.commands, run.commands)  # what was sent
    odometry = back.odometry()
    np.testing.assert_allclose(odometry.poses[:, :2], run.actual[:, :2], rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.cos(odometry.poses[:, 2] - run.actual[:, 2]), 1.0, atol=1e-12)
    assert (odometry.frame, odometry.child_frame) == ("odom", "base_link")
    # The twist from the change of pose: the commands, held over each step.
    np.testing.assert_allclose(odometry.twist[5:, 1], run.commands[4:-1, 1], rtol=1e-6, atol=1e-9)
    tf = _mcap_topics(bag)["/tf"]
    moved = [m.transforms[0] for _, _, m in tf]
    np.testing.assert_allclose([t.transform.translation.x for t in moved], run.actual[:, 0],
                               rtol=0, atol=1e-12)  # fmt: skip
    assert {t.child_frame_id for t in moved} == {"base_link"}


def test_a_base_run_in_mujoco_adds_its_true_pose_and_wheels(tmp_path: Path) -> None:
    pytest.importorskip("mujoco", reason="MuJoCo is not installed: pip install 'trajkit[sim]'")
    from trajkit import mobile, sim

    plan = constant_twist(0.2, np.radians(20), 3.0, rate_hz=20)
    run = sim.run(sim.MobileScene(mobile.jackal()), plan, control_rate_hz=20)
    back = read_bag(write_bag(tmp_path / "bag", plan, run=run))
    np.testing.assert_allclose(back.odometry().poses[:, :2], run.odometry[:, :2], atol=1e-12)
    np.testing.assert_allclose(back.odometry("/ground_truth").poses[:, :2], run.actual[:, :2],
                               atol=1e-12)  # fmt: skip
    wheels = back.joint_states()
    assert wheels.names == ("left_wheel", "right_wheel") and wheels.position is None
    np.testing.assert_array_equal(wheels.velocity, run.measured_wheel_speeds)
    np.testing.assert_array_equal(wheels.effort, run.wheel_torques)


@pytest.mark.parametrize(
    ("stream", "message"),
    [
        ("joint_state", "where the simulated run's joint states go"),
        (None, "run must be the simulated run of the plan"),  # a base's run, an arm's plan
    ],
)
def test_runs_that_do_not_fit_are_refused(tmp_path: Path, stream, message) -> None:
    _, base_run = _base_run()
    plan = tk.quintic(np.zeros(2), [0.6, -0.4], 1.0)
    with pytest.raises(InvalidInputError, match=message):
        write_bag(tmp_path / "bag", plan, run=base_run, stream=stream)
    assert not (tmp_path / "bag").exists()


# ---------------------------------------------------------------- bad bags
def test_reading_refuses_what_is_not_there(tmp_path: Path) -> None:
    with pytest.raises(InvalidInputError, match="is not a ROS 2 bag"):
        read_bag(tmp_path)
    bag = read_bag(write_bag(tmp_path / "bag", PLANS["quintic"]()))
    with pytest.raises(InvalidInputError, match=r"no topic '/joint_states'; it has \['/joint_tra"):
        bag.joint_states()
    with pytest.raises(InvalidInputError, match="holds trajectory_msgs/msg/JointTrajectory, not"):
        bag.odometry("/joint_trajectory")


def test_a_truncated_bag_is_one_clear_error(tmp_path: Path) -> None:
    bag = write_bag(tmp_path / "bag", PLANS["scurve"](), stream="joint_state")
    (file,) = bag.glob("*.mcap")
    data = file.read_bytes()
    file.write_bytes(data[: len(data) // 2])
    with pytest.raises(InvalidInputError, match="not a readable ROS 2 bag"):
        read_bag(bag)


# ---------------------------------------------------------------- the command line
def test_trajkit_bag_checks_and_plots(tmp_path: Path, capsys) -> None:
    plan = PLANS["scurve"]()  # peaks at 1 rad/s
    bag = write_bag(tmp_path / "bag", plan, stream="joint_state", start_ns=START)
    figure = tmp_path / "recorded.png"
    assert main(["bag", str(bag), "--vmax", "1.5", "--plot", str(figure)]) == 0
    out = capsys.readouterr().out
    assert "/joint_states: " in out and "trajectory limit check: OK" in out
    assert "recorded limit check (samples): OK" in out and "quintic interpolation" in out
    assert figure.stat().st_size > 10_000
    assert main(["bag", str(bag), "--vmax", "0.5"]) == 1
    assert "velocity of joint1 reaches" in capsys.readouterr().out
    assert main(["bag", str(bag), "--vmax", "57.3", "--deg"]) == 0


def test_trajkit_bag_errors_are_one_line(tmp_path: Path, capsys) -> None:
    assert main(["bag", str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "is not a ROS 2 bag" in err[0]
    bag = write_bag(tmp_path / "bag", PLANS["quintic"]())
    assert main(["bag", str(bag), "--trajectory", "/x", "--states", "/y"]) == 2
    assert "the bag has neither /x nor /y" in capsys.readouterr().err
    assert main(["bag", str(bag), "--plot", str(tmp_path / "p.png")]) == 2
    assert "--plot draws the joint states" in capsys.readouterr().err
    assert not (tmp_path / "p.png").exists()


@settings(
    max_examples=20, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(st.integers(0, 2**32 - 1))
def test_property_recorded_plot_has_units_and_both_curves(tmp_path: Path, seed: int) -> None:
    rng = np.random.default_rng(seed)
    t = np.cumsum(rng.uniform(0.01, 0.1, 30))
    ndof = int(rng.integers(1, 4))
    states = JointStates(t, tuple(f"j{k}" for k in range(ndof)), rng.normal(size=(30, ndof)),
                         rng.normal(size=(30, ndof)), None)  # fmt: skip
    plan = tk.quintic(np.zeros(ndof), np.ones(ndof), float(t[-1]))
    figure = tk.plot.recorded(states, plan, degrees=True, limits=tk.Limits(velocity=2.0))
    labels = [ax.get_ylabel() for ax in figure.axes]
    assert labels == ["position [deg]", "velocity [deg/s]", "error q − q_d [deg]"]
    legend = [text.get_text() for text in figure.axes[1].get_legend().get_texts()]
    assert "j0 plan" in legend and "j0 recorded" in legend and "velocity limit (upper)" in legend
    assert figure.axes[-1].get_xlabel() == "time [s]"


def test_trajkit_bag_executes_the_points_in_mujoco(tmp_path: Path, capsys) -> None:
    pytest.importorskip("mujoco", reason="MuJoCo is not installed: pip install 'trajkit[sim]'")
    plan = tk.quintic(np.zeros(2), [0.6, -0.4], 1.0)
    bag = write_bag(tmp_path / "bag", plan)
    outputs = [tmp_path / "tracking.png", tmp_path / "tracking.csv"]
    status = main(["bag", str(bag), "--sim", "mujoco", "--robot", "rrbot", "--control-rate-hz",
                   "500", "--sim-plot", str(outputs[0]), "--sim-csv", str(outputs[1])])  # fmt: skip
    out = capsys.readouterr().out
    assert status == 0
    assert "executed on RRBot in MuJoCo as the controller interpolates the points" in out
    assert "RMS error" in out and all(path.stat().st_size > 1000 for path in outputs)
    assert main(["bag", str(bag), "--sim-plot", str(tmp_path / "x.png")]) == 2
    assert "need(s) --sim mujoco" in capsys.readouterr().err
    assert main(["bag", str(bag), "--sim", "mujoco", "--robot", "ur5"]) == 2
    assert "--robot ur5 has 6 joints but the move has 2" in capsys.readouterr().err


def test_the_trajectory_on_the_topic_a_controller_subscribes_to(tmp_path: Path, capsys) -> None:
    plan = PLANS["quintic"]()
    bag = write_bag(tmp_path / "bag", plan, controller="joint_trajectory_controller")
    back = read_bag(bag)
    assert list(back.topics) == ["/joint_trajectory_controller/joint_trajectory"]
    curve = back.joint_trajectory()  # the bag's one JointTrajectory topic
    np.testing.assert_allclose(curve(plan.breakpoints), plan(plan.breakpoints), atol=1e-12)
    assert main(["bag", str(bag)]) == 0
    assert "/joint_trajectory_controller/joint_trajectory: 2 points" in capsys.readouterr().out
    for bad in ("/jtc", "2nd", "a b", ""):
        with pytest.raises(InvalidInputError, match="controller must be a ROS name"):
            write_bag(tmp_path / "bad", plan, controller=bad)
    with pytest.raises(InvalidInputError, match="are for arm plans"):
        write_bag(tmp_path / "bad", _base_run()[0], controller="jtc")
