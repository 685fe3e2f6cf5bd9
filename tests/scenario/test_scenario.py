"""Scenario files: every example runs; strict parsing with key paths; fuzzing; the CLI."""

from __future__ import annotations

import math
import os
import tomllib
import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from scenario_mutations import mutated, places

import trajkit as tk
from trajkit import scenario
from trajkit.cli import main
from trajkit.errors import InvalidInputError, TrajkitError
from trajkit.scenario import ScenarioError
from trajkit.scenario.execute import _limits_text
from trajkit.scenario.parse import from_data

EXAMPLES = sorted((Path(__file__).parents[2] / "examples").glob("*.toml"))

ARM = """
name = "arm"
[robot]
builtin = "rrbot"
[task]
kind = "joint_move"
q0_deg = [0, 0]
qf_deg = [67, -45]
[limits]
vmax_deg = [9, 11]
"""


def needs_mujoco(path: Path) -> bool:
    return 'engine = "mujoco"' in path.read_text(encoding="utf-8")


def test_there_is_an_example_per_coursework_task():
    names = {path.stem for path in EXAMPLES}
    for expected in ("seed000_rrbot_cubic", "seed000_jackal_twist", "seed000_jackal_goto",
                     "seed001_six_joint_trapezoid", "seed001_via_points", "seed002_figure8",
                     "seed003_arm3_line", "seed002_two_link_ellipse",
                     "seed004_example1_via_velocity", "seed004_example2_continuous_via",
                     "ur5_pose_path",
                     "jerk_limited_waypoints"):  # fmt: skip
        assert expected in names


@pytest.mark.parametrize("path", EXAMPLES, ids=[path.stem for path in EXAMPLES])
def test_every_example_runs_and_writes_its_outputs(path, tmp_path):
    if needs_mujoco(path):
        pytest.importorskip("mujoco", reason="MuJoCo is not installed: pip install 'trajkit[sim]'")
    spec = scenario.load(path)
    lines: list[str] = []
    outcome = scenario.run(path, tmp_path, log=lines.append)
    assert outcome.report.ok
    assert lines == outcome.lines and lines[0].startswith(f"scenario {spec.name}")
    names = sorted(p.name for p in tmp_path.iterdir())
    assert names == sorted(p.name for p in outcome.files)
    assert f"{spec.name}_summary.txt" in names
    assert (tmp_path / f"{spec.name}_summary.txt").read_text(encoding="utf-8") == "\n".join(
        lines
    ) + "\n"
    if spec.outputs["csv"]:
        assert f"{spec.name}.csv" in names
    if spec.outputs["plot"]:
        assert f"{spec.name}.png" in names
    if spec.outputs["animation"] != "none":
        assert f"{spec.name}.{spec.outputs['animation']}" in names
    if spec.outputs["ros2_bag"]:
        assert (tmp_path / f"{spec.name}_bag" / "metadata.yaml").is_file()
    if spec.simulation["engine"] == "mujoco" and not spec.mobile:
        assert f"{spec.name}_sim.png" in names and f"{spec.name}_sim.csv" in names
    assert not [name for name in names if name.startswith(".")]  # no temporaries


def test_examples_reproduce_the_coursework_figures(tmp_path):
    folder = Path(__file__).parents[2] / "examples"
    trapezoid = scenario.run(folder / "seed001_six_joint_trapezoid.toml", tmp_path, log=len)
    assert trapezoid.plan.duration == pytest.approx(14.608, abs=1e-12)
    line = scenario.run(folder / "seed003_arm3_line.toml", tmp_path, log=len)
    assert "path error" in line.lines[1] and line.report.ok
    goto = scenario.load(folder / "seed000_jackal_goto.toml")
    plan = scenario.execute(
        scenario.Scenario(**{**goto.__dict__, "simulation": {"engine": "kinematic"},
                             "outputs": {**goto.outputs, "animation": "none"}}),
        tmp_path, log=len,
    ).plan  # fmt: skip
    np.testing.assert_allclose(plan.info["phase_durations"], [1.1468058, 32.3941772, 2.03629306],
                               rtol=1e-8)  # fmt: skip


def test_seed004_polynomial_is_the_lecture_solution(tmp_path):
    folder = Path(__file__).parents[2] / "examples"
    outcome = scenario.run(folder / "seed004_example2_continuous_via.toml", tmp_path, log=len)
    expected = tk.polynomial(
        [[(0, 0, 0.0), (0, 1, 0.0), (1, 0, 0.5)], [(1, 0, 0.5), (3, 0, 1.0), (3, 1, 0.0)]],
        segments=[0, 1, 3], continuity=[(1, 2)],
    )  # fmt: skip
    np.testing.assert_array_equal(outcome.plan.coefficients, expected.coefficients)
    assert "piece 1: a0..a3 = [0.0, 0.0, 0.875, -0.375]" in "\n".join(outcome.lines)


def test_a_joint_task_needs_no_robot_unless_simulated_or_animated(tmp_path):
    text = ARM.replace('[robot]\nbuiltin = "rrbot"\n', "")
    assert scenario.parse(text).robot == {}
    outcome = scenario.execute(scenario.parse(text), tmp_path, log=len)
    assert outcome.report.ok
    with pytest.raises(ScenarioError, match=r"outputs\.animation: animating needs a \[robot\]"):
        scenario.parse(text + '[outputs]\nanimation = "gif"\n')
    with pytest.raises(ScenarioError, match=r"simulation\.engine: simulating needs a \[robot\]"):
        scenario.parse(text + '[simulation]\nengine = "mujoco"\n')
    with pytest.raises(ScenarioError, match=r"robot: required table is missing"):
        scenario.parse(text.replace('kind = "joint_move"', 'kind = "line"'))


def test_degrees_are_converted_exactly():
    spec = scenario.parse(ARM.replace("qf_deg = [67, -45]", "qf_deg = [180, -90]"))
    np.testing.assert_array_equal(spec.task["qf"], [math.pi, -math.pi / 2])
    np.testing.assert_array_equal(spec.limits["vmax"], np.radians([9, 11]))


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (("qf_deg = [67, -45]", "qf_deg = [67, -45, 3]"), "task.qf_deg: expected 2 numbers, got 3"),
        (("[limits]", "[limits]\nvelocty = 1"), "limits.velocty: unknown key"),
        (('name = "arm"', 'name = "arm"\ncolour = "red"'), "colour: unknown key"),
        (("q0_deg = [0, 0]", "q0_deg = [0, 0]\nq0 = [0, 0]"), "task.q0: give q0 or q0_deg"),
        (('kind = "joint_move"', 'kind = "joint_move"\nduration = "ten"'),
         "task.duration: expected a finite number, got 'ten'"),
        (('kind = "joint_move"', 'kind = "joint_move"\nduration = -1'),
         "task.duration: expected a number > 0, got -1"),
        (('kind = "joint_move"', 'kind = "joint_move"\nduration = nan'),
         "task.duration: expected a finite number, got nan"),
        (('kind = "joint_move"', 'kind = "joint_move"\nprofile = "linear"'),
         "task.profile: expected one of 'cubic', 'quintic', 'septic', 'trapezoid', 'scurve'"),
        (('kind = "joint_move"', 'kind = "fly"'), "task.kind: expected one of"),
        (('builtin = "rrbot"', 'builtin = "jackal"'),
         "robot.builtin: expected one of 'rrbot', 'ur5', 'arm3', 'planar2r', got 'jackal'"),
        (('builtin = "rrbot"', ""),
         "robot: give exactly one of builtin, dh, urdf or mjcf, got none"),
        (('name = "arm"', 'name = "../arm"'), "name: expected letters, digits"),
        (("vmax_deg = [9, 11]", "vmax_deg = [9, true]"),
         "limits.vmax_deg[1]: expected a finite number, got True"),
        (("vmax_deg = [9, 11]", "vmax_deg = [9, -1]"),
         "limits.vmax_deg[1]: expected a number > 0, got -1"),
        (("[limits]", "[simulation]\nengine = 'bullet'\n[limits]"),
         "simulation.engine: expected one of 'kinematic', 'mujoco', got 'bullet'"),
        (("[limits]", "[outputs]\nanimation = true\n[limits]"),
         "outputs.animation: expected a string, got a boolean"),
        (("[limits]", "[controller]\nperiod = 0\n[limits]"),
         "controller.period: expected a number > 0, got 0"),
        (("q0_deg = [0, 0]", 'q0_deg = "__import__(\'os\').system(\'false\')"'),
         "task.q0_deg: expected a list of numbers, got a string"),
        (("[task]", "[taskk]\n[task]"), "taskk: unknown key"),
        (("[task]", "[task]\n[task]"), "not valid TOML"),
    ],
)  # fmt: skip
def test_errors_name_the_key_path_and_the_rule(change, message):
    text = ARM.replace(*change)
    with pytest.raises(ScenarioError) as caught:
        scenario.parse(text)
    assert message in str(caught.value)
    assert isinstance(caught.value, InvalidInputError)


def test_waypoint_rows_are_checked_one_by_one():
    text = ARM.replace('kind = "joint_move"\nq0_deg = [0, 0]\nqf_deg = [67, -45]',
                       'kind = "waypoints"\npoints = [[0, 0], [1, 1], [2]]')  # fmt: skip
    with pytest.raises(ScenarioError, match=r"task.points\[2\]: expected 2 numbers, got 1"):
        scenario.parse(text)


def test_dh_rows_and_missing_tables():
    text = ARM.replace('builtin = "rrbot"', "[[robot.dh]]\na = 0.3\nspeed = 1\n")
    with pytest.raises(ScenarioError, match=r"robot.dh\[0\].speed: unknown key"):
        scenario.parse(text)
    with pytest.raises(ScenarioError, match="task: required table is missing"):
        scenario.parse('name = "x"\n[robot]\nbuiltin = "rrbot"\n')


def test_parts_that_do_not_fit_are_named(tmp_path):
    wrong_count = scenario.parse(ARM.replace('builtin = "rrbot"', 'builtin = "ur5"'))
    with pytest.raises(ScenarioError, match=r"task\.q0: expected 6 numbers for UR5, got 2"):
        scenario.execute(wrong_count, tmp_path, log=len)
    trapezoid = scenario.parse(ARM.replace("[limits]", "[limits]").replace(
        "qf_deg = [67, -45]", 'qf_deg = [67, -45]\nprofile = "trapezoid"'))  # fmt: skip
    with pytest.raises(ScenarioError, match=r"limits\.amax: required by the trapezoid"):
        scenario.execute(trapezoid, tmp_path, log=len)
    assert os.listdir(tmp_path) == []


def test_a_failing_plan_writes_nothing(tmp_path):
    text = ARM.replace("qf_deg = [67, -45]", "qf_deg = [67, -45]\nduration = 1.0")
    with pytest.raises(TrajkitError):
        scenario.execute(scenario.parse(text), tmp_path, log=len)  # 1 s is below 11.17 s
    assert os.listdir(tmp_path) == []


# Trapezoid and S-curve options: each reaches the planner ------------------------------
MOVE = """
name = "move"
[task]
kind = "joint_move"
q0 = [0.0, 0.5]
qf = [1.0, -0.5]
profile = "scurve"
[limits]
vmax = 1.0
amax = 2.0
jmax = 10.0
[outputs]
csv = false
plot = false
"""
MOVE_ENDS = ([0.0, 0.5], [1.0, -0.5])
MOVE_LIMITS = {"trapezoid": (1.0, 2.0), "scurve": (1.0, 2.0, 10.0)}
PERIOD = "[controller]\nperiod = 0.01\n"


@pytest.mark.parametrize(
    ("profile", "keys", "controller", "kwargs"),
    [
        ("scurve", "a0 = [0.5, -0.2]\naf = [-0.3, 0.2]", "",
         {"a0": [0.5, -0.2], "af": [-0.3, 0.2]}),
        ("scurve", "a0_deg = 20\naf_deg = [-10, 5]", "",
         {"a0": np.radians(20), "af": np.radians([-10, 5])}),
        ("scurve", "min_duration = 3.5", "", {"min_duration": 3.5}),
        ("trapezoid", "min_duration = 3.5", "", {"min_duration": 3.5}),
        ("scurve", 'sync = "time_if_necessary"', "", {"sync": "time_if_necessary"}),
        ("trapezoid", 'sync = "time_if_necessary"\nvf = [0.2, 0]', "",
         {"sync": "time_if_necessary", "vf": [0.2, 0.0]}),
        ("scurve", 'grid = "duration"', PERIOD, {"grid": "duration", "period": 0.01}),
        ("trapezoid", 'grid = "duration"\nmin_duration = 2.345', PERIOD,
         {"grid": "duration", "min_duration": 2.345, "period": 0.01}),
        ("scurve", 'grid = "switches"', PERIOD, {"grid": "switches", "period": 0.01}),
    ],
)  # fmt: skip
def test_trapezoid_and_scurve_options_reach_the_planner(profile, keys, controller, kwargs,
                                                        tmp_path):  # fmt: skip
    text = MOVE.replace('profile = "scurve"', f'profile = "{profile}"\n{keys}') + controller
    if profile == "trapezoid":
        text = text.replace("jmax = 10.0\n", "")
    outcome = scenario.execute(scenario.parse(text), tmp_path, log=len)
    planner = {"trapezoid": tk.trapezoidal, "scurve": tk.scurve}[profile]
    direct = planner(*MOVE_ENDS, *MOVE_LIMITS[profile], **kwargs)
    assert outcome.plan.duration == pytest.approx(direct.duration, rel=1e-12)
    t = np.linspace(0.0, direct.duration, 41)
    np.testing.assert_allclose(outcome.plan.position(t), direct.position(t), rtol=0, atol=1e-12)
    if "min_duration" in kwargs:
        assert outcome.plan.duration >= kwargs["min_duration"]
    if kwargs.get("grid") == "duration":
        ticks = outcome.plan.duration / 0.01
        assert ticks == pytest.approx(round(ticks), abs=1e-6)


@pytest.mark.parametrize("profile", ["quintic", "septic"])
def test_polynomial_moves_take_their_boundary_accelerations(profile, tmp_path):
    text = MOVE.replace('profile = "scurve"', f'profile = "{profile}"\nduration = 4.0\n'
                        "a0 = 0.5\naf = [-0.25, 0.1]")  # fmt: skip
    outcome = scenario.execute(scenario.parse(text), tmp_path, log=len)
    np.testing.assert_allclose(outcome.plan.start_state.acceleration, [0.5, 0.5], atol=1e-12)
    np.testing.assert_allclose(outcome.plan.end_state.acceleration, [-0.25, 0.1], atol=1e-12)


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (('profile = "scurve"', 'profile = "cubic"\nmin_duration = 2'),
         "task.min_duration: applies to the trapezoid and scurve planners, not cubic"),
        (('profile = "scurve"', 'profile = "quintic"\ngrid = "duration"'),
         "task.grid: applies to the trapezoid and scurve planners, not quintic"),
        (('profile = "scurve"', 'profile = "trapezoid"\naf = 0.1'),
         "task.af: applies to the quintic, septic and scurve planners, not trapezoid"),
        (('profile = "scurve"', 'profile = "cubic"\na0_deg = 1'),
         "task.a0_deg: applies to the quintic, septic and scurve planners, not cubic"),
        (('profile = "scurve"', 'profile = "scurve"\nduration = 3\nmin_duration = 2'),
         "task.min_duration: give duration (exact) or min_duration (a floor), not both"),
        (('profile = "scurve"', 'profile = "scurve"\nmin_duration = 0'),
         "task.min_duration: expected a number > 0, got 0"),
        (('profile = "scurve"', 'profile = "scurve"\ngrid = "ticks"'),
         "task.grid: expected one of 'switches', 'duration', got 'ticks'"),
        (('profile = "scurve"', 'profile = "scurve"\ngrid = "duration"'),
         "task.grid: only used with a controller period ([controller] period)"),
        (('profile = "scurve"', 'profile = "scurve"\nsync = "sometimes"'),
         "task.sync: expected one of 'time', 'phase', 'time_if_necessary', 'none', got "
         "'sometimes'"),
        (('profile = "scurve"', 'profile = "scurve"\na0 = [1, 2, 3]'),
         "task.a0: expected 2 numbers, got 3"),
        (('profile = "scurve"', 'profile = "scurve"\naf = "up"'),
         "task.af: expected 2 numbers, got a string"),
    ],
)  # fmt: skip
def test_trapezoid_and_scurve_option_errors_name_the_key(change, message):
    with pytest.raises(ScenarioError) as caught:
        scenario.parse(MOVE.replace(*change))
    assert message in str(caught.value)


def test_an_infeasible_end_acceleration_is_one_line_at_the_command_line(tmp_path, capsys):
    path = tmp_path / "move.toml"
    path.write_text(MOVE.replace('profile = "scurve"', 'profile = "scurve"\naf = 3.0'),
                    encoding="utf-8")  # fmt: skip
    status = main(["run", str(path), "--out", str(tmp_path / "out")])
    captured = capsys.readouterr()
    assert status == 2 and captured.out == ""
    assert captured.err.startswith("trajkit: error: task: af=3 rad/s^2 is beyond")
    assert captured.err.count("\n") == 1


# Fuzzing: malformed values anywhere only ever raise the documented error -------------
VALUES = st.recursive(
    st.none() | st.booleans() | st.integers(-10**6, 10**6) | st.text(max_size=8)
    | st.floats(allow_nan=True, allow_infinity=True),
    lambda children: st.lists(children, max_size=4) | st.dictionaries(st.text(max_size=6),
                                                                       children, max_size=3),
    max_leaves=8,
)  # fmt: skip
BASE = tomllib.loads(ARM)
PLACES = list(places(BASE))


def assert_only_the_documented_error(data: dict) -> None:
    try:
        spec = from_data(data)
    except ScenarioError:
        return
    assert spec.name and spec.task["kind"]


EXAMPLE_DATA = [tomllib.loads(path.read_text(encoding="utf-8")) for path in EXAMPLES]
EXAMPLE_PLACES = [(index, place) for index, data in enumerate(EXAMPLE_DATA)
                  for place in places(data)]  # fmt: skip
HUGE = st.integers() | st.integers(min_value=10**300, max_value=10**400) | st.floats()


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(where=st.sampled_from(EXAMPLE_PLACES), value=VALUES | HUGE | st.lists(HUGE, max_size=4),
       extra=st.booleans())  # fmt: skip
def test_fuzzed_example_files_raise_only_the_documented_error(where, value, extra):
    index, place = where
    assert_only_the_documented_error(mutated(EXAMPLE_DATA[index], place, value, extra))


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(place=st.sampled_from(PLACES), value=VALUES, extra=st.booleans())
def test_fuzzed_scenarios_raise_only_the_documented_error(place, value, extra):
    assert_only_the_documented_error(mutated(BASE, place, value, extra))


@settings(max_examples=100, deadline=None)
@given(text=st.text(max_size=200))
def test_fuzzed_text_raises_only_the_documented_error(text):
    try:
        scenario.parse(text)
    except ScenarioError:
        pass


# Command line --------------------------------------------------------------------------
def test_trajkit_run_writes_and_lists_the_outputs(tmp_path, capsys):
    path = tmp_path / "arm.toml"
    path.write_text(ARM, encoding="utf-8")
    status = main(["run", str(path), "--out", str(tmp_path / "out")])
    captured = capsys.readouterr()
    assert status == 0, captured.err
    assert (
        "scenario arm" in captured.out and "cubic joint move on RRBot: 11.1666667 s" in captured.out
    )
    assert f"wrote {tmp_path / 'out' / 'arm.csv'}" in captured.out
    assert tk.Samples.from_csv(tmp_path / "out" / "arm.csv").t[-1] == pytest.approx(11.1666666667)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (ARM.replace("[limits]", "[limits]\nvelocty = 1"), "limits.velocty: unknown key"),
        ("name = [", "not valid TOML"),
    ],
)
def test_trajkit_run_errors_are_one_line(tmp_path, capsys, text, message):
    path = tmp_path / "bad.toml"
    path.write_text(text, encoding="utf-8")
    status = main(["run", str(path), "--out", str(tmp_path / "out")])
    captured = capsys.readouterr()
    assert status == 2 and captured.out == ""
    assert captured.err.startswith("trajkit: error: ") and message in captured.err
    assert captured.err.count("\n") == 1
    assert not (tmp_path / "out").exists() or not list((tmp_path / "out").iterdir())


def test_trajkit_run_on_a_missing_file(tmp_path, capsys):
    status = main(["run", str(tmp_path / "nope.toml")])
    assert status == 2
    err = capsys.readouterr().err
    assert err.startswith("trajkit: error: ") and "no such file" in err.lower()


def test_the_rrbot_example_bag_has_the_trajectory_and_the_simulated_joint_states(tmp_path):
    pytest.importorskip("rosbags", reason="rosbags is not installed: pip install 'trajkit[ros]'")
    pytest.importorskip("mujoco", reason="MuJoCo is not installed: pip install 'trajkit[sim]'")
    from trajkit.io.ros2_read import read_bag

    outcome = scenario.run(scenario.EXAMPLES / "seed000_rrbot_cubic.toml", tmp_path, log=len)
    bag = read_bag(tmp_path / "seed000_rrbot_cubic_bag")
    # /joint_states is the simulated arm's, at its 1 kHz control rate over 11.17 s (the
    # plan's own joint-state stream once stood there, passing for the robot's).
    run = outcome.log
    assert {topic: count for topic, (_, count) in bag.topics.items()} == {
        "/joint_trajectory": 1, "/joint_states": run.t.size,
        "/position_servo_controller/commands": run.t.size}  # fmt: skip
    states = bag.joint_states()
    np.testing.assert_array_equal(states.position, run.actual)
    np.testing.assert_array_equal(states.effort, run.efforts)
    assert np.abs(states.position - run.desired).max() > 1e-3  # the servo lags: not the plan
    assert outcome.report.ok


def test_an_interrupted_run_leaves_no_output(tmp_path, monkeypatch):
    import trajkit.viz.plot

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(trajkit.viz.plot, "save", interrupted)
    with pytest.raises(KeyboardInterrupt):
        scenario.execute(scenario.parse(ARM), tmp_path / "out", log=len)
    assert list((tmp_path / "out").iterdir()) == []


def test_trajkit_run_exits_1_when_the_plan_breaks_a_limit(tmp_path, capsys):
    path = tmp_path / "fast.toml"
    path.write_text(
        'name = "fast"\n[task]\nkind = "polynomial"\ntimes = [0.0, 1.0]\n'
        "[[task.segments]]\nconditions = [[0, 0, 0], [0, 1, 0], [1, 0, 1], [1, 1, 0]]\n"
        "[limits]\nvmax = 1.0\n",  # the cubic peaks at 1.5 rad/s
        encoding="utf-8",
    )
    status = main(["run", str(path), "--out", str(tmp_path / "out")])
    captured = capsys.readouterr()
    assert status == 1
    assert "limit check: FAILED" in captured.out
    assert captured.err == "trajkit: the plan breaks a limit (see the limit check above)\n"
    assert (tmp_path / "out" / "fast.csv").exists()  # the outputs are still written


def test_ctrl_c_is_one_line_and_leaves_nothing(tmp_path, capsys, monkeypatch):
    import trajkit.viz.plot

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(trajkit.viz.plot, "save", interrupted)
    path = tmp_path / "arm.toml"
    path.write_text(ARM, encoding="utf-8")
    status = main(["run", str(path), "--out", str(tmp_path / "out"), "--report"])
    captured = capsys.readouterr()
    # The plan and its check were said before the outputs were drawn; none was written.
    assert status == 130 and "limit check: OK" in captured.out and "wrote" not in captured.out
    assert captured.err == "trajkit: interrupted; nothing was written\n"
    assert not (tmp_path / "out").exists() or list((tmp_path / "out").iterdir()) == []


def test_report_and_bag_are_written_with_the_files_or_not_at_all(tmp_path, monkeypatch):
    pytest.importorskip("rosbags", reason="rosbags is not installed: pip install 'trajkit[ros]'")
    text = ARM + "[outputs]\nros2_bag = true\n"
    outcome = scenario.execute(scenario.parse(text), tmp_path, report=True, log=len)
    names = sorted(p.name for p in tmp_path.iterdir())
    assert names == ["arm.csv", "arm.png", "arm_bag", "arm_summary.txt", "index.html"]
    assert sorted(p.name for p in outcome.files) == names
    page = (tmp_path / "index.html").read_text(encoding="utf-8")
    assert '<a href="arm.csv">' in page and "data:image/png;base64," in page
    # A failure in the bag writer leaves the earlier outputs as they were.
    before = {p.name: p.stat().st_mtime_ns for p in tmp_path.iterdir()}
    import trajkit.io.ros2

    def broken(*args, **kwargs):
        raise RuntimeError("disk full")

    monkeypatch.setattr(trajkit.io.ros2, "write_bag", broken)
    with pytest.raises(RuntimeError, match="disk full"):
        scenario.execute(scenario.parse(text), tmp_path, report=True, log=len)
    assert {p.name: p.stat().st_mtime_ns for p in tmp_path.iterdir()} == before


@pytest.mark.parametrize(
    ("given", "expected_ns"),
    [
        ("2026-12-07T09:00:00Z", 1_796_634_000 * 10**9),
        ("2026-12-07T11:00:00.25+02:00", 1_796_634_000 * 10**9 + 250_000_000),
        ("1796634000", 1_796_634_000 * 10**9),
        ("1796634000.5", 1_796_634_000_500_000_000),
    ],
)
def test_a_bag_starts_when_the_scenario_says(given, expected_ns):
    spec = scenario.parse(ARM + f"[outputs]\nros2_bag = true\nros2_start = {given}\n")
    assert spec.outputs["ros2_start_ns"] == expected_ns


@pytest.mark.parametrize(
    ("given", "message"),
    [
        ("2026-12-07T09:00:00", "a date-time needs its offset from UTC, e.g. 2026-12-07T09:00:00Z"),
        ("2026-12-07", "expected a date-time such as 2026-12-07T09:00:00Z or seconds"),
        ('"tomorrow"', "expected a date-time such as"),
        ("true", "expected a date-time such as"),
        ("-1", "expected a time from 1970 to 2038-01-19"),
        ("2040-01-01T00:00:00Z", "expected a time from 1970 to 2038-01-19"),
        ("nan", "expected a date-time such as"),
    ],
)
def test_a_bad_bag_start_is_refused_by_name(given, message):
    with pytest.raises(ScenarioError) as caught:
        scenario.parse(ARM + f"[outputs]\nros2_bag = true\nros2_start = {given}\n")
    assert "outputs.ros2_start" in str(caught.value) and message in str(caught.value)


def test_a_base_bag_with_twist_stamped_commands_from_its_start_time(tmp_path):
    pytest.importorskip("rosbags", reason="rosbags is not installed: pip install 'trajkit[ros]'")
    from rosbags.rosbag2 import Reader
    from rosbags.typesys import Stores, get_typestore

    text = GOTO_SCURVE + ('ros2_bag = true\nros2_cmd_vel = "TwistStamped"\n'
                          "ros2_start = 2026-12-07T09:00:00Z\ncsv = false\n")  # fmt: skip
    scenario.execute(scenario.parse(text), tmp_path, log=len)
    types = get_typestore(Stores.ROS2_JAZZY)
    with Reader(tmp_path / "goto_scurve_bag") as reader:
        connections = {c.topic: c for c in reader.connections}
        assert connections["/cmd_vel"].msgtype == "geometry_msgs/msg/TwistStamped"
        first = {}
        for connection, stamp, raw in reader.messages():
            message = types.deserialize_cdr(raw, connection.msgtype)
            first.setdefault(connection.topic, (stamp, message))
    start = 1_796_634_000 * 10**9
    assert first["/plan"][0] == start and first["/cmd_vel"][0] == start
    command = first["/cmd_vel"][1]
    assert command.header.stamp.sec == 1_796_634_000 and command.header.frame_id == "base_link"


def test_a_plan_stream_cannot_pass_for_the_simulated_arm():
    text = ARM + '[simulation]\nengine = "mujoco"\n[outputs]\nros2_bag = true\n'
    with pytest.raises(ScenarioError, match=r"outputs\.ros2_stream: with a MuJoCo simulation"):
        scenario.parse(text + 'ros2_stream = "joint_state"\n')
    assert scenario.parse(text + 'ros2_stream = "point"\n').outputs["ros2_stream"] == "point"


def test_an_arm_bag_for_a_named_trajectory_controller(tmp_path):
    pytest.importorskip("rosbags", reason="rosbags is not installed: pip install 'trajkit[ros]'")
    from trajkit.io.ros2_read import read_bag

    text = ARM + '[outputs]\nros2_bag = true\nros2_controller = "arm_controller"\n'
    scenario.execute(scenario.parse(text), tmp_path, log=len)
    assert list(read_bag(tmp_path / "arm_bag").topics) == ["/arm_controller/joint_trajectory"]
    for bad in ('"/arm"', '"two words"', "3"):
        with pytest.raises(ScenarioError, match=r"outputs\.ros2_controller"):
            scenario.parse(ARM + f"[outputs]\nros2_controller = {bad}\n")
    with pytest.raises(ScenarioError, match="an arm's joint trajectory controller"):
        scenario.parse(GOTO_SCURVE + 'ros2_controller = "jtc"\n')


def test_plots_are_in_degrees_where_the_scenario_is(tmp_path, monkeypatch):
    import trajkit.viz.plot as plot

    drawn = []
    original = plot.profiles

    def keep(*args, **kwargs):
        drawn.append(original(*args, **kwargs))
        return drawn[-1]

    monkeypatch.setattr(plot, "profiles", keep)
    radians = (
        ARM.replace("q0_deg = [0, 0]", "q0 = [0, 0]")
        .replace("qf_deg = [67, -45]", "qf = [1.17, -0.79]")
        .replace("vmax_deg = [9, 11]", "vmax = 0.2")
    )
    for text, degrees, unit, named in ((ARM, True, "deg", "q1 limit"),
                                       (radians, False, "rad", "velocity limit")):  # fmt: skip
        spec = scenario.parse(text)
        assert spec.degrees is degrees
        scenario.execute(spec, tmp_path / unit, log=len)
        assert [ax.get_ylabel() for ax in drawn[-1].axes][:2] == [
            f"position [{unit}]", f"velocity [{unit}/s]"]  # fmt: skip
        legend = [t.get_text() for t in drawn[-1].axes[1].get_legend().get_texts()]
        assert named in legend  # the velocity limits are named: per joint, or shared
    assert not scenario.parse(GOTO_SCURVE).degrees  # a base's angles stay in rad


def test_a_base_on_four_skid_steer_wheels(tmp_path):
    pytest.importorskip("mujoco", reason="MuJoCo is not installed: pip install 'trajkit[sim]'")
    text = GOTO_SCURVE.replace("[outputs]", '[simulation]\nengine = "mujoco"\nrate_hz = 50\n'
                               'drive = "skid_steer"\n[outputs]')  # fmt: skip
    spec = scenario.parse(text)
    assert spec.simulation["drive"] == "skid_steer"
    outcome = scenario.execute(spec, tmp_path, log=len)
    assert outcome.log.kinematic is not None and outcome.log.t.size > 10
    with pytest.raises(ScenarioError, match="only used with engine = 'mujoco'"):
        scenario.parse(GOTO_SCURVE.replace("[outputs]", '[simulation]\ndrive = "skid_steer"\n'
                                           "[outputs]"))  # fmt: skip
    with pytest.raises(ScenarioError, match=r"simulation\.drive: expected one of"):
        scenario.parse(text.replace('"skid_steer"', '"tracks"'))


def test_an_arm_from_an_mjcf_file(tmp_path):
    pytest.importorskip("mujoco", reason="MuJoCo is not installed: pip install 'trajkit[sim]'")
    import shutil

    arm = Path(__file__).parents[1] / "kinematics" / "data" / "four_joint_arm.xml"
    shutil.copy(arm, tmp_path / "arm.xml")
    text = (
        'name = "mjcf_arm"\n[robot]\nmjcf = "arm.xml"\ntip_body = "fore"\n[task]\n'
        'kind = "joint_move"\nq0 = [0, 0]\nqf = [0.03, 1.0]\nprofile = "quintic"\n'
        'duration = 2.0\n[simulation]\nengine = "mujoco"\n[outputs]\nplot = false\n'
    )
    (tmp_path / "arm.toml").write_text(text, encoding="utf-8")
    outcome = scenario.run(tmp_path / "arm.toml", tmp_path / "out", log=len)
    assert outcome.log.joint_names == ("shoulder", "elbow")
    # The default position servos follow the file's 2.7 kg upper arm within 6° (measured
    # 5.3°) and end within 0.3° of the goal.
    assert np.abs(outcome.log.error).max() < 0.1 and np.abs(outcome.log.final_error).max() < 0.01


def test_command_messages_are_a_bases_and_named():
    with pytest.raises(ScenarioError, match=r"outputs\.ros2_cmd_vel: expected one of"):
        scenario.parse(GOTO_SCURVE + 'ros2_cmd_vel = "Stamped"\n')
    with pytest.raises(ScenarioError, match=r"outputs\.ros2_cmd_vel: a base's commands"):
        scenario.parse(ARM + '[outputs]\nros2_cmd_vel = "TwistStamped"\n')


# Issue 16: goto's S-curve, extreme numbers ---------------------------------------------
GOTO_SCURVE = """
name = "goto_scurve"
[robot]
builtin = "jackal"
[task]
kind = "goto"
goal = [5.0, 3.0]
heading = 1.5
profile = "scurve"
[limits]
vmax = 0.5
wmax_deg = 30
amax = 1.0
alpha_max_deg = 60
jmax = 2.0
angular_jmax_deg = 120
[outputs]
plot = false
"""


def test_goto_with_an_scurve_profile_runs_within_its_jerk_limits(tmp_path):
    outcome = scenario.execute(scenario.parse(GOTO_SCURVE), tmp_path, log=len)
    assert outcome.report.ok
    plan = outcome.plan
    assert plan.info["profile"] == "scurve"
    np.testing.assert_allclose(plan.end_pose, [5.0, 3.0, 1.5], atol=1e-9)
    # Each phase's law is checked exactly on its pieces against the scenario's limits.
    bounds = {"drive": (0.5, 1.0, 2.0), "turn": tuple(np.radians([30.0, 60.0, 120.0]))}
    for name, segment in zip(plan.info["phases"], plan.segments, strict=True):
        v, a, j = bounds["turn" if name.startswith("turn") else "drive"]
        law = segment.law
        assert law.check(tk.Limits(velocity=v, acceleration=a, jerk=j)).ok, name
        # Time-optimal S-curve phases reach the jerk bound (within 1e-9 relative).
        assert np.abs(law.jerk(law.breakpoints[:-1] + 1e-9)).max() == pytest.approx(j, rel=1e-9)
    # The report's limits line names them too (it raised KeyError on angular_jerk).
    text = _limits_text(scenario.parse(GOTO_SCURVE))
    assert "jerk 2 m/s³" in text and "angular jerk 120 deg/s³" in text


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (("jmax = 2.0\n", ""), "limits.jmax: required by the scurve profile of a goto task"),
        (("angular_jmax_deg = 120\n", ""), "limits.angular_jmax: required by the scurve"),
        (('profile = "scurve"\n', ""), "limits.jmax: only used by the S-curve phases"),
        (("jmax = 2.0\n", "jmax = -2.0\n"), "limits.jmax: expected a number > 0, got -2.0"),
    ],
)
def test_goto_jerk_limits_are_checked_by_key(change, message):
    with pytest.raises(ScenarioError, match=message.replace(".", r"\.")):
        scenario.parse(GOTO_SCURVE.replace(*change))


FIGURE8 = 'name = "eight"\n[robot]\nbuiltin = "jackal"\n[task]\nkind = "figure8"\n'
ELLIPSE = (
    (Path(__file__).parents[2] / "examples" / "seed002_two_link_ellipse.toml")
    .read_text(encoding="utf-8")
    .replace('animation = "gif"', 'animation = "none"\nplot = false')
)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        # The curve is 1e12 times wider than high: it nears a stop at its turns (the old
        # message blamed a stop of the curve at t=5 s).
        (FIGURE8 + "width = 1e12\n", "task: width 1e+12 m and height 1 m: one may be at most"),
        (FIGURE8 + "width = 1e200\n", "task: width 1e+200 m and height 1 m"),  # IndexError
        (FIGURE8 + "width = 1e200\nheight = 1e200\n", "moves too fast or too slowly"),
        (FIGURE8 + "offset = [1e308, 0]\n", "task.offset: expected at most 1e+09 m"),
        (FIGURE8 + "offset = [1.7e308, 1.7e308]\n",  # once an overflow warning first
         "task.offset: expected at most 1e+09 m"),
        (ELLIPSE.replace("duration = 5.0", "duration = 1e12"),  # once a 728 TiB allocation
         "task: ik_step=0.01 s over 1e+12 s gives 1e+14 samples; at most 1e+06 are made"),
        (ELLIPSE.replace("duration = 5.0", "duration = 1e308"),  # once an OverflowError
         "task: duration must be at most 1e+12 s, got 1e+308 s"),
        (ELLIPSE.replace("duration = 5.0", "duration = 1e-300"),  # once "breakpoints needs
         "task: duration must be at least 1e-09 s, got 1e-300 s"),  # at least 2 times"
        (ELLIPSE.replace("duration = 5.0", "duration = 1e-9"),  # shorter than dt: start
         "task: the joint spline strays"),  # and end sampled, not the end alone
        (ELLIPSE.replace("duration = 5.0", "duration = 1e6"),
         "task: ik_step=0.01 s over 1e+06 s gives 1e+08 samples; at most 1e+06 are made"),
        ('name = "p"\n[task]\nkind = "polynomial"\ntimes = [-1e308, 1.0]\n'  # LinAlgError
         "[[task.segments]]\nconditions = [[0, 0, 0], [1, 0, 1]]\n",
         "task.times: expected times within ±1e+12 s"),
        (FIGURE8.replace('"figure8"', '"goto"') + "goal = [1e200, 1e200]\n",  # NaN speeds
         "task: goal (1e+200, 1e+200) is 1.41e+200 m from start (0.0, 0.0); at most 1e+09 m"),
        (FIGURE8.replace('"figure8"', '"twist"') + "v = 1e308\nomega = 0\nduration = 10\n",
         "task: the distance v * duration is inf m"),  # inf poses, once a RuntimeWarning
    ],
)  # fmt: skip
def test_extreme_numbers_are_one_line_errors_naming_the_key(tmp_path, capsys, text, message):
    path = tmp_path / "extreme.toml"
    path.write_text(text, encoding="utf-8")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no RuntimeWarning before the error
        status = main(["run", str(path), "--out", str(tmp_path / "out")])
    captured = capsys.readouterr()
    assert status == 2 and captured.out == ""
    assert captured.err.startswith("trajkit: error: ") and captured.err.count("\n") == 1
    assert message in captured.err
    assert not (tmp_path / "out").exists() or not list((tmp_path / "out").iterdir())


# ------------------------------------------------------------------ the reader
def _table(**data):
    from trajkit.scenario.reader import Table

    return Table(data, "task")


@pytest.mark.parametrize(
    ("read", "message"),
    [
        (lambda t: t.value("k"), "task.k: required"),
        (lambda t: t.number("k"), "task.k: required, expected a number"),
        (lambda t: t.number("k", angles=True), "task.k: required, expected a number"),
        (lambda t: t.numbers("k"), "task.k: required, expected a list of numbers"),
        (lambda t: t.matrix("k"), "task.k: required, expected a list of lists of numbers"),
        (lambda t: t.string("k"), "task.k: required, expected a string"),
        (lambda t: t.table("k", required=True), "task.k: required table is missing"),
        (lambda t: t.tables("k"), "task.k: required, expected an array of tables"),
    ],
)
def test_reader_names_a_missing_required_key(read, message):
    with pytest.raises(ScenarioError) as caught:
        read(_table())
    assert str(caught.value) == message


def test_reader_gives_the_default_of_a_missing_key_as_it_is():
    table = _table()
    marker = object()
    assert table.number("k", marker) is marker
    assert table.number("k", None, angles=True, positive=True) is None
    assert table.numbers("k", marker, count=3) is marker
    assert table.string("k", marker, choices=("a",)) is marker
    assert table.boolean("k", False) is False
    assert table.table("k") is None


def test_reader_refuses_an_angle_in_both_units_even_with_a_default():
    with pytest.raises(ScenarioError, match=r"^task\.q: give q or q_deg, not both$"):
        _table(q=1.0, q_deg=2.0).number("q", 0.0, angles=True)
    assert _table(q_deg=90.0).number("q", 0.0, angles=True) == pytest.approx(math.pi / 2)
