"""The planner catalog: every entry reachable from the command line, scenario files and
sweeps, the same input giving the same trajectory through each, and the same refusals."""

from __future__ import annotations

import numpy as np
import pytest

import trajkit as tk
from trajkit import sweep
from trajkit.cli import _build_parser, main
from trajkit.errors import InvalidInputError
from trajkit.planners import CATALOG, LIMITS, OPTIONS, QUANTITIES
from trajkit.scenario import execute
from trajkit.scenario.parse import from_data
from trajkit.scenario.reader import ScenarioError

STEP = 0.01  # s, the sampling step of every front end's samples here
#: One two-joint problem's values for every quantity a planner may take (SI units).
VALUES = {
    "q0": [0.0, 0.5], "qf": [1.0, -0.5], "v0": [0.1, -0.05], "vf": [0.0, 0.05],
    "a0": [0.2, 0.0], "af": [0.0, -0.1], "vmax": [1.0, 1.2], "amax": [2.0, 2.5],
    "jmax": [10.0, 12.0],
}  # fmt: skip


def problem(name: str) -> dict[str, object]:
    """The entry's inputs and limits from VALUES; a polynomial gets an exact duration."""
    entry = CATALOG[name]
    values = {key: VALUES[key] for key in ("q0", "qf", *entry.inputs, *entry.limits)
              if key in VALUES}  # fmt: skip
    if not entry.needs:
        values["duration"] = 3.0  # well above the limits' minimum
    return values


def by_python(name: str) -> tk.Trajectory:
    return CATALOG[name].plan({k: np.asarray(v) if isinstance(v, list) else v
                               for k, v in problem(name).items()})  # fmt: skip


def by_cli(name: str, tmp_path, capsys) -> tk.Samples:
    csv = tmp_path / f"{name}.csv"
    argv = ["plan", name, "--sample-step", str(STEP), "--csv", str(csv)]
    for key, value in problem(name).items():
        flag = "--" + key.replace("_", "-")
        argv += [flag, ",".join(map(str, value)) if isinstance(value, list) else str(value)]
    status = main(argv)
    assert status == 0, capsys.readouterr().err
    return tk.Samples.from_csv(csv)


def by_scenario(name: str, tmp_path) -> tk.Trajectory:
    values = problem(name)
    limits = {key: values.pop(key) for key in LIMITS if key in values}
    data = {"name": name, "task": {"kind": "joint_move", "profile": name, **values},
            "limits": limits, "outputs": {"csv": False, "plot": False}}  # fmt: skip
    return execute(from_data(data), tmp_path / "scenario").plan


def by_sweep(name: str, tmp_path) -> tuple[float, np.ndarray]:
    data = {"sweep": {"planner": name, "problems": 1, "keep": "samples", "sample_step": STEP},
            "robot": {"joints": 2}, "fixed": problem(name)}  # fmt: skip
    out = tmp_path / "sweep"
    sweep.run(sweep.parse(data), out, workers=1)
    rows = sweep.read(out).to_table().to_pylist()
    assert rows[0]["error"] == "", rows[0]["error"]
    times, values = sweep.read_samples(out, 0)
    np.testing.assert_allclose(times, np.arange(times.size) * STEP, rtol=0, atol=1e-12)
    return rows[0]["duration"], values


@pytest.mark.parametrize("name", list(CATALOG))
def test_the_same_input_gives_the_same_trajectory_through_every_front_end(name, tmp_path,
                                                                          capsys):  # fmt: skip
    direct = by_python(name)
    scenario = by_scenario(name, tmp_path)
    assert scenario.duration == pytest.approx(direct.duration, rel=1e-12)
    t = np.linspace(0.0, direct.duration, 57)
    for order in range(3):
        np.testing.assert_allclose(scenario.evaluate(t, order), direct.evaluate(t, order),
                                   rtol=0, atol=1e-12)  # fmt: skip
    samples = by_cli(name, tmp_path, capsys)
    assert samples.t[-1] == pytest.approx(direct.duration, rel=1e-12)
    np.testing.assert_allclose(samples.q, direct.position(samples.t), rtol=0, atol=1e-12)
    np.testing.assert_allclose(samples.qd, direct.velocity(samples.t), rtol=0, atol=1e-12)
    duration, values = by_sweep(name, tmp_path)
    assert duration == pytest.approx(direct.duration, rel=1e-12)
    grid = np.arange(values.shape[0]) * STEP
    assert grid[-1] <= direct.duration < grid[-1] + STEP * (1 + 1e-9)
    np.testing.assert_allclose(values, direct.position(grid), rtol=0, atol=1e-12)


@pytest.mark.parametrize("name", list(CATALOG))
def test_every_input_limit_and_option_is_reachable_from_every_front_end(name):
    entry = CATALOG[name]
    flags = {a.dest for a in _plan_parser()._actions}
    parameters = set(sweep.planners.PLANNERS[name].parameters)
    sweep_options = set(sweep.planners.PLANNERS[name].options)
    for key in ("q0", "qf", *entry.inputs, *entry.limits):
        assert key in flags, key
        assert key in parameters, key
    for key in entry.options:
        assert key in flags, key
        # A sweep has no controller period, so no grid to put times on.
        assert key in sweep_options or key == "grid", key
    for key in entry.inputs + entry.options:  # scenario files read each of them
        value = {"grid": "duration", "sync": "phase"}.get(key, VALUES.get(key, 1.0))
        task = {"kind": "joint_move", "profile": name, "q0": [0.0, 0.0], "qf": [1.0, 1.0],
                key: value}  # fmt: skip
        data = {"name": "n", "task": task, **({"controller": {"period": 0.01}}
                                              if key == "grid" else {})}  # fmt: skip
        if key == "min_duration":
            value = task[key] = 2.0
        assert np.all(from_data(data).task[key] == np.asarray(value)), key
    if entry.period:
        assert "period" in flags


def _plan_parser():
    commands = next(a for a in _build_parser()._actions if a.dest == "command")
    return commands.choices["plan"]


REFUSED = [(name, key) for name, entry in CATALOG.items()
           for key in (*QUANTITIES, *OPTIONS) if not entry.takes(key)]  # fmt: skip


@pytest.mark.parametrize(("name", "key"), REFUSED)
def test_what_a_planner_does_not_take_is_refused_by_name_everywhere(name, key, capsys):
    entry = CATALOG[name]
    users = [other for other, e in CATALOG.items() if e.takes(key)]
    reason = (
        f"applies to the {', '.join(users[:-1])} and {users[-1]} planners, not {name}"
        if len(users) > 1
        else f"applies to the {users[0]} planners, not {name}"
    )
    assert entry.refusal(key) == reason
    value = {"sync": "phase", "grid": "duration"}.get(key, "1")
    assert main(["plan", name, "--q0", "0", "--qf", "1", "--duration", "3",
                 f"--{key.replace('_', '-')}", value]) == 2  # fmt: skip
    assert capsys.readouterr().err == f"trajkit: error: --{key.replace('_', '-')} {reason}\n"
    if key not in LIMITS:  # limits are in [limits]: every one given is checked
        task = {"kind": "joint_move", "profile": name, "q0": [0.0], "qf": [1.0],
                key: value if key in OPTIONS else 1.0}  # fmt: skip
        with pytest.raises(ScenarioError, match=rf"^task\.{key}: {reason}$"):
            from_data({"name": "n", "task": task})
    with pytest.raises(InvalidInputError, match=rf"^{key} {reason}$"):
        entry.plan({"q0": 0.0, "qf": 1.0, key: 1.0})


def test_a_needed_limit_left_out_is_named_by_every_front_end(capsys):
    assert main(["plan", "scurve", "--q0", "0", "--qf", "1", "--vmax", "1"]) == 2
    assert "--amax and --jmax are required by the scurve planner" in capsys.readouterr().err
    data = {"name": "n", "task": {"kind": "joint_move", "profile": "trapezoid", "q0": [0.0],
                                  "qf": [1.0]}, "limits": {"vmax": 1.0}}  # fmt: skip
    with pytest.raises(ScenarioError, match=r"^limits\.amax: required by the trapezoid planner"):
        execute(from_data(data), "unused")
    with pytest.raises(sweep.SweepError, match=r"fixed\.amax: required by planner 'trapezoid'"):
        sweep.parse({"sweep": {"planner": "trapezoid"}, "fixed": {"q0": 0, "qf": 1, "vmax": 1}})
    with pytest.raises(InvalidInputError, match=r"^amax: required by the trapezoid planner$"):
        CATALOG["trapezoid"].plan({"q0": 0.0, "qf": 1.0, "vmax": 1.0})


def test_sync_none_is_the_same_as_none_in_python():
    args = ([0.0, 0.0], [1.0, 3.0], 1.0, 2.0)
    for law in (tk.trapezoidal, tk.scurve):
        extra = (10.0,) if law is tk.scurve else ()
        spelled, none = law(*args, *extra, sync="none"), law(*args, *extra, sync=None)
        assert spelled.info["sync"] is None and none.info["sync"] is None
        np.testing.assert_array_equal(spelled.coefficients, none.coefficients)


def test_old_names_are_read_with_a_warning_naming_the_new_one():
    data = {
        "name": "n",
        "task": {"kind": "joint_move", "profile": "trapezoid", "q0": [0.0], "qf": [1.0]},
        "limits": {"velocity": 1.0, "acceleration": 2.0},
    }
    with pytest.warns(FutureWarning) as caught:
        assert from_data(data).limits == {"vmax": 1.0, "amax": 2.0}
    assert [str(w.message).split(";")[0] for w in caught] == [
        "limits.velocity is now named vmax",
        "limits.acceleration is now named amax",
    ]
    data["limits"] = {"velocity": 1.0, "vmax": 1.0}
    with pytest.raises(ScenarioError, match=r"^limits\.velocity: the old name of vmax"):
        from_data(data)
    old = {
        "sweep": {"planner": "trapezoid", "period": 0.05},
        "fixed": {"q0": 0, "qf": 1, "vmax": 1, "amax": 1},
    }
    with pytest.warns(FutureWarning, match=r"sweep\.period is now named sample_step"):
        assert sweep.parse(old).sample_step == 0.05
    with pytest.raises(sweep.SweepError, match="'polynomial' is now named by its law"):
        sweep.parse({"sweep": {"planner": "polynomial"}})
