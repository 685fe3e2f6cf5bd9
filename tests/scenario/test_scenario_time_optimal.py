"""Scenario files that time a path time-optimally, under torque and tool limits.

The examples ``ur5_tool_speed_line`` and ``ur5_torque_limited`` run in
``test_scenario.py`` with every other example; here: what they promise (the limit
kept on the plan, its plot written, the summary naming the binding limit) and the
refusals of the new keys.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import trajkit as tk
from trajkit import scenario
from trajkit.kinematics import UR5
from trajkit.scenario import ScenarioError

EXAMPLES = Path(__file__).parents[2] / "examples"

WAYPOINTS = """
name = "fast"
[robot]
builtin = "ur5"
[task]
kind = "waypoints"
timing = "time_optimal"
points_deg = [[0, -90, 0, -90, 0, 0], [40, -60, 60, -90, -30, 0], [0, -90, 0, -90, 0, 0]]
[limits]
vmax_deg = 180
amax_deg = 3000
torque = true
"""

LINE = """
name = "line"
[robot]
builtin = "ur5"
[task]
kind = "line"
start = [-0.5, -0.2, 0.3]
end = [-0.3, 0.25, 0.45]
law = "time_optimal"
[limits]
vmax_deg = 180
amax_deg = 360
tool_speed = 0.25
"""


def test_the_tool_speed_line_keeps_its_speed(tmp_path):
    lines: list[str] = []
    outcome = scenario.run(EXAMPLES / "ur5_tool_speed_line.toml", tmp_path, log=lines.append)
    plan = outcome.plan
    t = np.linspace(0, plan.end_time, 20001)
    ur5 = UR5()
    speed = np.linalg.norm(np.einsum("nkj,nj->nk", ur5.jacobian(plan(t))[:, :3],
                                     plan.velocity(t)), axis=1)  # fmt: skip
    assert 0.2499 < speed.max() <= 0.25 * (1 + 1e-9)
    tool = ur5.fk(plan([0.0, plan.end_time]))[:, :3, 3]
    np.testing.assert_allclose(tool, [[-0.5, -0.2, 0.3], [-0.3, 0.25, 0.45]], atol=1e-9)
    assert "    tool speed: at most 1 of its limit" in lines
    assert outcome.report.ok and "tool speed" in outcome.report.peaks
    assert (tmp_path / "ur5_tool_speed_line_limits.png").stat().st_size > 10_000


def test_the_torque_limited_move_keeps_the_ur5s_torques(tmp_path):
    lines: list[str] = []
    outcome = scenario.run(EXAMPLES / "ur5_torque_limited.toml", tmp_path, log=lines.append)
    limit = tk.TorqueLimit(UR5())
    plan = outcome.plan
    t = np.linspace(0, plan.end_time, 40001)
    tau = limit.values(plan(t), plan.velocity(t), plan.acceleration(t))
    assert np.abs(tau).max(axis=0)[1] > 149.9  # the shoulder lift's 150 N·m binds
    assert np.all(np.abs(tau) <= np.array([150, 150, 150, 28, 28, 28]) * (1 + 1e-9))
    assert plan.info["waypoint_deviation"].max() <= 0.05
    assert "    torque: at most 1 of its limit" in lines
    assert (tmp_path / "ur5_torque_limited_limits.png").is_file()


def test_torque_limits_in_n_m_per_joint_and_the_tool_acceleration():
    text = WAYPOINTS.replace("torque = true", "torque = [150, 150, 150, 28, 28, 28]\n"
                             "tool_acceleration = 5.0")  # fmt: skip
    spec = scenario.parse(text)
    np.testing.assert_array_equal(spec.limits["torque"], [150, 150, 150, 28, 28, 28])
    assert spec.limits["tool_acceleration"] == 5.0


@pytest.mark.parametrize(
    ("text", "change", "message"),
    [
        (WAYPOINTS, ('timing = "time_optimal"', ""),
         "limits.torque: only kept by a time-optimal timing"),
        (WAYPOINTS, ('timing = "time_optimal"', 'timing = "fastest"'),
         "task.timing: expected one of 'blended', 'time_optimal'"),
        (WAYPOINTS, ('timing = "time_optimal"', 'timing = "time_optimal"\nthrough = true'),
         "task.through: not used with timing = 'time_optimal'"),
        (WAYPOINTS, ('timing = "time_optimal"', 'timing = "time_optimal"\npath_tolerance = -1'),
         "task.path_tolerance: expected >= 0, got -1"),
        (WAYPOINTS, ('timing = "time_optimal"', 'timing = "time_optimal"\ntiming_grid = 2.5'),
         "task.timing_grid: expected a whole number of grid intervals from 2 to 100000"),
        (WAYPOINTS, ("torque = true", "torque = false"), "limits.torque: expected true"),
        (WAYPOINTS, ("torque = true", "torque = -3"),
         "limits.torque[0]: expected a number > 0, got -3"),
        (WAYPOINTS, ("torque = true", "tool_speed = 0"),
         "limits.tool_speed: expected a number > 0"),
        (WAYPOINTS, ('[robot]\nbuiltin = "ur5"', ""), "limits.torque: needs a [robot] table"),
        (LINE, ('law = "time_optimal"', 'law = "time_optimal"\nduration = 2'),
         "task.duration: not used with law = 'time_optimal'"),
        (LINE, ('law = "time_optimal"', 'law = "cubic"\nduration = 2'),
         "limits.tool_speed: only kept by a time-optimal timing"),
        (WAYPOINTS, ("torque = true", "torque = true\njmax_deg = 9000"),
         "limits.jmax: a time-optimal retiming of waypoints keeps velocity"),
    ],
)  # fmt: skip
def test_refusals_name_the_key(text, change, message):
    with pytest.raises(ScenarioError) as caught:
        scenario.parse(text.replace(*change))
    assert message in str(caught.value)


def test_a_jerk_limited_time_optimal_line_keeps_its_tool_speed_and_jerk(tmp_path):
    text = LINE.replace("tool_speed = 0.25", "tool_speed = 0.25\njmax_deg = 3600\ntorque = true")
    path = tmp_path / "smooth_line.toml"
    path.write_text(text, encoding="utf-8")
    outcome = scenario.run(path, tmp_path / "out", log=lambda line: None)
    plan = outcome.plan
    assert plan.info["jerk_limited"] and outcome.report.ok
    assert plan.check(tk.Limits(velocity=np.pi, acceleration=2 * np.pi,
                                jerk=np.radians(3600))).ok  # fmt: skip
    for limit in (tk.ToolLimit(UR5(), speed=0.25), tk.TorqueLimit(UR5())):
        assert limit.check(plan).ok
    t = np.linspace(0, plan.end_time, 20001)
    speed = np.linalg.norm(np.einsum("nkj,nj->nk", UR5().jacobian(plan(t))[:, :3],
                                     plan.velocity(t)), axis=1)  # fmt: skip
    assert speed.max() <= 0.25 * (1 + 1e-9)
    np.testing.assert_allclose(plan.acceleration([0.0, plan.end_time]), 0.0, atol=1e-9)


def test_gravity_beyond_the_torque_limit_is_a_one_line_error(tmp_path, capsys):
    path = tmp_path / "weak.toml"
    path.write_text(WAYPOINTS.replace("torque = true", "torque = 20"), encoding="utf-8")
    from trajkit.cli import main

    assert main(["run", str(path), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "N·m to hold the arm at s=" in err[0]
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


def test_the_report_names_torque_and_tool_limits_in_their_units():
    from trajkit.scenario.execute import _limits_text

    text = WAYPOINTS.replace("torque = true", "torque = [150, 150, 150, 28, 28, 28]\n"
                             "tool_speed = 0.25")  # fmt: skip
    assert _limits_text(scenario.parse(text)) == (
        "velocity 180 deg/s; acceleration 3000 deg/s²; torque 150, 150, 150, 28, 28, 28 N·m; "
        "tool speed 0.25 m/s"
    )
    assert "torque the robot's own" in _limits_text(scenario.parse(WAYPOINTS))
