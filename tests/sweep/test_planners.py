"""Each planner of a sweep: rows equal to planning each problem alone, failures as rows.

Trapezoid and S-curve rows are planned in batches; their peaks are read off the phases
and must equal the exact extrema of the single problem's Trajectory. A problem that
cannot be planned is a row with its error, never an exception; the others are untouched.
"""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import numpy as np
import pytest

import trajkit as tk
from trajkit import batch, mobile, sweep
from trajkit.kinematics import BUILTIN
from trajkit.taskspace import Line, time_optimal

from .helpers import matrix, rows

PEAKS = 1e-9  # relative: peaks read off the phases against Trajectory.extrema
SAME_CODE = 1e-12  # relative: the sweep against the same planner called directly
ROUNDING_OVER = 1e-14  # a peak at its bound may exceed it by a few ulps: peak / bound - 1


def planned(data: dict, out: Path, workers: int = 1) -> tuple[sweep.Summary, object]:
    summary = sweep.run(sweep.parse(data), out, workers=workers)
    return summary, rows(out)


# ------------------------------------------------------------------ failures as rows
def test_failed_problems_are_rows_and_the_others_are_planned_alone(tmp_path):
    joints = 3
    data = {
        "sweep": {"planner": "trapezoid", "problems": 2000, "chunk": 1000, "seed": 1},
        "robot": {"joints": joints},
        "fixed": {"amax": 2.0},
        "swept": {"q0": {"uniform": [-1, 1]}, "qf": {"uniform": [-1, 1]},
                  "vmax": {"normal": [1.0, 1.0]}},
    }  # fmt: skip
    summary, table = planned(data, tmp_path)
    q0, qf, vmax, amax = (matrix(table, n, joints) for n in ("q0", "qf", "vmax", "amax"))
    bad = (vmax <= 0).any(axis=1)
    assert 600 < bad.sum() < 1000  # 1 - P(z > -1)^3 = 40 % of 2000
    errors = np.array(table["error"].to_pylist(), dtype=object)
    np.testing.assert_array_equal(errors != "", bad)
    assert summary.failed == bad.sum()
    for message in errors[bad]:
        assert message.startswith("InvalidInputError: vmax must allow motion both ways")
    feasible = table["feasible"].to_numpy(zero_copy_only=False)
    assert not feasible[bad].any()
    for name in ("duration", "worst_violation"):
        assert np.isnan(table[name].to_numpy()[bad]).all()
    for name in ("peak_velocity", "peak_acceleration"):
        assert np.isnan(matrix(table, name, joints)[bad]).all()
    # Every other row: bit for bit the batch planned without the failing problems.
    good = ~bad
    alone = batch.trapezoidal(q0[good], qf[good], vmax[good], amax[good])
    np.testing.assert_array_equal(table["duration"].to_numpy()[good], alone.durations)
    assert feasible[good].all()
    assert summary.infeasible == bad.sum()
    for i in np.flatnonzero(good)[::40]:
        single = tk.trapezoidal(q0[i], qf[i], vmax=vmax[i], amax=amax[i])
        assert table["duration"][int(i)].as_py() == pytest.approx(single.duration, rel=PEAKS)


def test_an_error_never_names_another_problem(tmp_path):
    data = {"sweep": {"planner": "trapezoid", "problems": 6, "chunk": 6},
            "robot": {"joints": 1}, "fixed": {"q0": 0.0, "qf": 1.0, "vmax": 1.0, "amax": 2.0},
            "swept": {"vf": {"values": [0.0, 2.0]}}}  # fmt: skip
    _, table = planned(data, tmp_path)
    for row in table.to_pylist():
        if row["problem"] % 2:
            assert row["error"].startswith("InfeasibleError: vf=2 rad/s is beyond")
            named = re.findall(r"problem (\d+)", row["error"])
            assert all(int(number) == row["problem"] for number in named), row


def test_a_failed_polynomial_row_keeps_its_swept_duration(tmp_path):
    data = {"sweep": {"planner": "quintic", "problems": 2, "chunk": 2},
            "robot": {"joints": 1}, "fixed": {"q0": 0.0, "qf": 1.0, "vmax": 1.0, "amax": 2.0},
            "swept": {"duration": {"values": [-1.5, 2.0]}}}  # fmt: skip
    _, table = planned(data, tmp_path)
    failed = table.to_pylist()[0]
    assert failed["error"] == "InvalidInputError: duration must be > 0, got -1.5 s"
    assert -1.5 in [value for key, value in failed.items() if key != "problem"]


# ---------------------------------------------------------------- exact peaks
CASES = {
    "trapezoid-time": ("trapezoid", "time", {}),
    "trapezoid-phase": ("trapezoid", "phase", {}),
    "trapezoid-moving-ends": (
        "trapezoid", "time",
        {"v0": {"uniform": [-0.4, 0.4]}, "vf": {"uniform": [-0.4, 0.4]}},
    ),
    "scurve-time": ("scurve", "time", {"jmax": {"uniform": [5.0, 50.0]}}),
    "scurve-phase": ("scurve", "phase", {"jmax": {"uniform": [5.0, 50.0]}}),
}  # fmt: skip


@pytest.mark.parametrize("case", list(CASES))
def test_peaks_are_the_exact_extrema_of_each_problem(tmp_path, case):
    planner, sync, extra = CASES[case]
    joints = 3
    data = {
        "sweep": {"planner": planner, "problems": 400, "chunk": 150, "seed": 9, "sync": sync},
        "robot": {"joints": joints},
        "swept": {"q0": {"uniform": [-2, 2]}, "qf": {"uniform": [-2, 2]},
                  "vmax": {"uniform": [0.5, 2.0]}, "amax": {"uniform": [1.0, 5.0]}, **extra},
    }  # fmt: skip
    summary, table = planned(data, tmp_path)
    assert summary.failed == 0 and summary.infeasible == 0
    values = {name: matrix(table, name, joints) for name in ("q0", "qf", "vmax", "amax")}
    if planner == "trapezoid":
        v0, vf = matrix(table, "v0", joints), matrix(table, "vf", joints)
        plans = batch.trapezoidal(values["q0"], values["qf"], values["vmax"], values["amax"],
                                  v0=v0, vf=vf, sync=sync)  # fmt: skip
        quantities = ("velocity", "acceleration")
    else:
        values["jmax"] = matrix(table, "jmax", joints)
        plans = batch.scurve(values["q0"], values["qf"], values["vmax"], values["amax"],
                             values["jmax"], sync=sync)  # fmt: skip
        quantities = ("velocity", "acceleration", "jerk")
    np.testing.assert_array_equal(table["duration"].to_numpy(), plans.durations)
    peaks = {q: matrix(table, f"peak_{q}", joints) for q in quantities}
    for i in range(0, 400, 3):
        trajectory = plans[i]
        for order, quantity in enumerate(quantities, start=1):
            np.testing.assert_allclose(peaks[quantity][i], trajectory.extrema(order).peak,
                                       rtol=PEAKS, atol=0, err_msg=f"{quantity} {i}")  # fmt: skip
    bounds = {"velocity": values["vmax"], "acceleration": values["amax"]}
    if planner == "scurve":
        bounds["jerk"] = values["jmax"]
    worst = np.max([(peaks[q] / bounds[q] - 1).max(axis=1) for q in quantities], axis=0)
    np.testing.assert_allclose(table["worst_violation"].to_numpy(), np.maximum(worst, 0.0),
                               rtol=0, atol=1e-15)  # fmt: skip
    assert table["worst_violation"].to_numpy().max() <= ROUNDING_OVER
    assert all(table["feasible"].to_pylist())
    # Against the single-problem planners too (no batch code involved).
    for i in range(0, 400, 50):
        args = [values[n][i] for n in ("q0", "qf", "vmax", "amax")]
        if planner == "trapezoid":
            single = tk.trapezoidal(args[0], args[1], vmax=args[2], amax=args[3], v0=v0[i],
                                    vf=vf[i], sync=sync)  # fmt: skip
        else:
            single = tk.scurve(*args, values["jmax"][i], sync=sync)
        assert table["duration"][i].as_py() == pytest.approx(single.duration, rel=PEAKS)
        for order, quantity in enumerate(quantities, start=1):
            np.testing.assert_allclose(peaks[quantity][i], single.extrema(order).peak,
                                       rtol=PEAKS, atol=1e-12)  # fmt: skip


def test_unsynchronised_sweeps_plan(tmp_path):
    data = {"sweep": {"planner": "trapezoid", "problems": 20, "chunk": 10, "sync": "none"},
            "robot": {"joints": 2}, "fixed": {"vmax": 1.0, "amax": 2.0},
            "swept": {"q0": {"uniform": [-1, 1]}, "qf": {"uniform": [-1, 1]}}}  # fmt: skip
    summary, table = planned(data, tmp_path)
    assert summary.failed == 0, table["error"][0]
    q0, qf = matrix(table, "q0", 2), matrix(table, "qf", 2)
    alone = batch.trapezoidal(q0, qf, 1.0, 2.0, sync=None)
    np.testing.assert_array_equal(table["duration"].to_numpy(), alone.durations)


# ------------------------------------- boundary states, floors and sync modes reach the planners
OPTION_CASES = {
    "scurve-moving-ends": ("scurve", "time", {
        "v0": {"uniform": [-0.3, 0.3]}, "vf": {"uniform": [-0.3, 0.3]},
        "a0": {"uniform": [-0.5, 0.5]}, "af": {"uniform": [-0.5, 0.5]}}),
    "scurve-min-duration": ("scurve", "time", {"min_duration": {"values": [0.5, 3.0, 6.0]}}),
    "trapezoid-min-duration": ("trapezoid", "phase", {"min_duration": {"uniform": [1.0, 5.0]}}),
    "scurve-time-if-necessary": ("scurve", "time_if_necessary",
                                 {"vf": {"values": [[0.0, 0.0, 0.0], [0.2, 0.0, -0.2]]}}),
    "trapezoid-time-if-necessary": ("trapezoid", "time_if_necessary",
                                    {"vf": {"values": [[0.0, 0.0, 0.0], [0.2, 0.0, -0.2]]}}),
}  # fmt: skip


@pytest.mark.parametrize("case", list(OPTION_CASES))
def test_boundary_states_floors_and_sync_modes_reach_the_planner(tmp_path, case):
    planner, sync, extra = OPTION_CASES[case]
    joints = 3
    data = {
        "sweep": {"planner": planner, "problems": 60, "chunk": 25, "seed": 4, "sync": sync},
        "robot": {"joints": joints},
        "fixed": {"vmax": 1.0, "amax": 2.0, **({"jmax": 10.0} if planner == "scurve" else {})},
        "swept": {"q0": {"uniform": [-2, 2]}, "qf": {"uniform": [-2, 2]}, **extra},
    }  # fmt: skip
    summary, table = planned(data, tmp_path)
    assert summary.failed == 0, table["error"].to_pylist()
    names = ["q0", "qf", "v0", "vf"] + (["a0", "af"] if planner == "scurve" else [])
    values = {name: matrix(table, name, joints) for name in names}
    floors = (table["min_duration"].to_numpy() if "min_duration" in extra
              else np.full(table.num_rows, None))  # fmt: skip
    durations = table["duration"].to_numpy()
    for i in range(table.num_rows):
        kwargs = {name: values[name][i] for name in names[2:]}
        floor = None if floors[i] is None else float(floors[i])
        if planner == "scurve":
            single = tk.scurve(values["q0"][i], values["qf"][i], 1.0, 2.0, 10.0, sync=sync,
                               min_duration=floor, **kwargs)  # fmt: skip
        else:
            single = tk.trapezoidal(values["q0"][i], values["qf"][i], 1.0, 2.0, sync=sync,
                                    min_duration=floor, **kwargs)  # fmt: skip
        assert durations[i] == pytest.approx(single.duration, rel=SAME_CODE), i
        if floor is not None:
            assert durations[i] >= floor * (1 - 1e-12)
    if "min_duration" in extra:  # a floor above the fastest move sets the duration
        assert np.any(np.isclose(durations, floors.astype(float), rtol=1e-12, atol=0.0))


def test_without_min_duration_the_rows_have_no_such_input(tmp_path):
    data = {"sweep": {"planner": "scurve", "problems": 4, "chunk": 4},
            "robot": {"joints": 1}, "fixed": {"q0": 0.0, "qf": 1.0, "vmax": 1.0, "amax": 2.0,
                                              "jmax": 10.0}}  # fmt: skip
    spec = sweep.parse(data)
    assert "min_duration" not in spec.parameters
    assert sorted(spec.parameters) == ["a0", "af", "amax", "jmax", "q0", "qf", "v0", "vf",
                                       "vmax"]  # fmt: skip
    _, table = planned(data, tmp_path)
    assert "min_duration" not in table.column_names


def test_a_floor_that_is_not_positive_is_a_row_with_its_error(tmp_path):
    data = {"sweep": {"planner": "scurve", "problems": 2, "chunk": 2},
            "robot": {"joints": 1}, "fixed": {"q0": 0.0, "qf": 1.0, "vmax": 1.0, "amax": 2.0,
                                              "jmax": 10.0},
            "swept": {"min_duration": {"values": [-1.0, 4.0]}}}  # fmt: skip
    _, table = planned(data, tmp_path)
    first, second = table.to_pylist()
    assert first["error"] == "InvalidInputError: min_duration must be > 0 s"
    assert np.isnan(first["duration"])
    assert second["error"] == "" and second["duration"] == pytest.approx(4.0, rel=1e-12)


# ------------------------------------------------------------ the other planners
@pytest.mark.parametrize(
    ("profile", "speed", "acceleration"),
    [("cubic", 1.5, 6.0), ("quintic", 15 / 8, 10 / np.sqrt(3))],
)
def test_polynomial_rows_have_closed_form_peaks(tmp_path, profile, speed, acceleration):
    # q(t) = q0 + (qf - q0) s(t / T): peak |v| = speed |dq| / T, peak |a| = acc |dq| / T^2.
    data = {"sweep": {"planner": profile, "chunk": 5},
            "robot": {"joints": 2},
            "fixed": {"q0": [0.0, 1.0], "qf": [1.0, -1.0], "vmax": 1.0, "amax": [2.0, 3.0]},
            "swept": {"duration": {"grid": [0.75, 5.25, 10]}}}  # fmt: skip
    summary, table = planned(data, tmp_path)
    T = np.linspace(0.75, 5.25, 10)
    np.testing.assert_array_equal(table["duration"].to_numpy(), T)
    assert table["error"].to_pylist() == [""] * 10
    distance = np.array([1.0, 2.0])
    v = speed * distance / T[:, None]
    a = acceleration * distance / T[:, None] ** 2
    np.testing.assert_allclose(matrix(table, "peak_velocity", 2), v, rtol=PEAKS)
    np.testing.assert_allclose(matrix(table, "peak_acceleration", 2), a, rtol=PEAKS)
    worst = np.maximum(np.maximum((v / 1.0).max(axis=1), (a / [2.0, 3.0]).max(axis=1)) - 1, 0)
    got = table["worst_violation"].to_numpy()
    np.testing.assert_allclose(got, worst, rtol=PEAKS, atol=0)
    feasible = np.array(table["feasible"].to_pylist())
    np.testing.assert_array_equal(feasible, worst == 0)
    assert 0 < (~feasible).sum() < 10  # too short: infeasible rows, still no error
    assert (got[~feasible] > 0).all()
    assert summary.failed == 0 and summary.infeasible == (~feasible).sum()


def test_topp_rows_and_samples_match_planning_alone(tmp_path):
    joints, points, grid = 2, 4, 100
    data = {"sweep": {"planner": "topp", "problems": 4, "chunk": 2, "seed": 4,
                      "points": points, "grid": grid, "keep": "samples", "sample_step": 0.05},
            "robot": {"joints": joints}, "fixed": {"vmax": [1.0, 1.5], "amax": 2.0},
            "swept": {"waypoints": {"uniform": [-1.0, 1.0]}}}  # fmt: skip
    summary, table = planned(data, tmp_path)
    assert summary.failed == 0 and summary.infeasible == 0
    way = matrix(table, "waypoints", points * joints)
    limits = tk.Limits(velocity=[1.0, 1.5], acceleration=[2.0, 2.0])
    for i in range(4):
        # waypoints_(p * joints + j + 1) is point p, joint j.
        path = tk.cubic_spline(np.linspace(0, 1, points), way[i].reshape(points, joints),
                               bc="natural")  # fmt: skip
        timed = tk.topp(path, limits, grid=grid)
        assert table["duration"][i].as_py() == pytest.approx(timed.duration, rel=SAME_CODE)
        np.testing.assert_allclose(matrix(table, "peak_velocity", joints)[i],
                                   timed.extrema(1).peak, rtol=PEAKS)  # fmt: skip
        t, q = sweep.read_samples(tmp_path, i)
        np.testing.assert_allclose(q, timed.position(t), rtol=0, atol=1e-12)
        np.testing.assert_allclose(q[0], way[i, :joints], rtol=0, atol=1e-12)
    assert table["worst_violation"].to_numpy().max() <= 1e-12
    assert all(table["feasible"].to_pylist())


def test_task_space_rows_and_an_unreachable_line(tmp_path):
    p0 = [0.4, 0.0, 0.3]
    targets = [[0.45, 0.1, 0.35], [3.0, 0.0, 0.3], [0.35, -0.2, 0.25]]  # the 2nd: 3 m away
    data = {"sweep": {"planner": "task_space", "chunk": 3, "samples": 30, "grid": 60},
            "robot": {"name": "ur5"}, "fixed": {"p0": p0, "vmax": 3.0, "amax": 6.0},
            "swept": {"pf": {"values": targets}}}  # fmt: skip
    summary, table = planned(data, tmp_path)
    assert table.num_rows == 3
    assert summary.failed == 1
    errors = table["error"].to_pylist()
    assert errors[1].startswith("UnreachableError: ")
    assert np.isnan(table["duration"][1].as_py())
    assert not table["feasible"][1].as_py()
    arm = BUILTIN["ur5"]()
    limits = tk.Limits(velocity=np.full(6, 3.0), acceleration=np.full(6, 6.0))
    np.testing.assert_array_equal(matrix(table, "pf", 3), targets)
    for i in (0, 2):
        assert errors[i] == ""
        move = time_optimal(arm, Line(p0, targets[i]), limits, samples=30, grid=60)
        assert table["duration"][i].as_py() == pytest.approx(move.trajectory.duration,
                                                             rel=SAME_CODE)  # fmt: skip
        np.testing.assert_allclose(matrix(table, "peak_velocity", 6)[i],
                                   move.trajectory.extrema(1).peak, rtol=PEAKS)  # fmt: skip
        assert table["feasible"][i].as_py()


def test_task_space_rows_with_torque_and_tool_speed_limits(tmp_path):
    p0 = [0.4, 0.0, 0.3]
    targets = [[0.45, 0.3, 0.45], [0.3, -0.25, 0.25]]
    data = {"sweep": {"planner": "task_space", "chunk": 2, "samples": 30, "grid": 80},
            "robot": {"name": "ur5"},
            "fixed": {"p0": p0, "vmax": 3.0, "amax": 60.0, "tool_speed": 0.3,
                      "torque": [150, 150, 150, 28, 28, 28]},
            "swept": {"pf": {"values": targets}}}  # fmt: skip
    summary, table = planned(data, tmp_path)
    assert table.num_rows == 2 and summary.failed == 0 and summary.infeasible == 0
    arm = BUILTIN["ur5"]()
    limits = tk.Limits(velocity=np.full(6, 3.0), acceleration=np.full(6, 60.0))
    torque, tool = tk.TorqueLimit(arm), tk.ToolLimit(arm, speed=0.3)
    for i in range(2):
        move = time_optimal(arm, Line(p0, targets[i]), limits, samples=30, grid=80,
                            constraints=[torque, tool])  # fmt: skip
        assert table["duration"][i].as_py() == pytest.approx(move.trajectory.duration,
                                                             rel=SAME_CODE)  # fmt: skip
        speed = tool.check(move.trajectory).peaks["tool speed"][1][0]
        assert table["peak_tool_speed_1"][i].as_py() == pytest.approx(speed, rel=PEAKS)
        assert 0.299 < speed <= 0.3 * (1 + 1e-9)  # the tool speed binds
        low, high = torque.check(move.trajectory).peaks["torque"]
        np.testing.assert_allclose(matrix(table, "peak_torque", 6)[i],
                                   np.maximum(np.abs(low), np.abs(high)), rtol=PEAKS)  # fmt: skip
    assert all(table["feasible"].to_pylist())


def test_mobile_rows_with_the_base_default_limits(tmp_path):
    data = {"sweep": {"planner": "mobile", "problems": 6, "chunk": 3, "seed": 8},
            "robot": {"name": "jackal"},
            "swept": {"goal": {"uniform": [[-2.0, -2.0, -3.0], [2.0, 2.0, 3.0]]}}}  # fmt: skip
    summary, table = planned(data, tmp_path)
    assert summary.failed == 0 and summary.infeasible == 0
    model = mobile.jackal()
    # The jackal's own limits are the defaults, one column each; the start is the origin.
    for name, value in (("vmax", 2.0), ("wmax", 4.0), ("amax", 20.0), ("alpha_max", 25.0)):
        np.testing.assert_array_equal(table[name].to_numpy(), value, err_msg=name)
    np.testing.assert_array_equal(matrix(table, "start", 3), 0.0)
    goals = matrix(table, "goal", 3)
    limits = mobile.MobileLimits(velocity=2.0, angular_velocity=4.0, acceleration=20.0,
                                 angular_acceleration=25.0)  # fmt: skip
    for i in range(6):
        plan = mobile.rotate_translate_rotate(goals[i], [0.0, 0.0, 0.0], model=model,
                                              limits=limits, profile="trapezoid")  # fmt: skip
        assert table["duration"][i].as_py() == pytest.approx(plan.duration, rel=SAME_CODE)
        peaks = plan.check(model.limits).peaks
        expected = [np.abs(np.concatenate([np.ravel(x) for x in peaks[q]])).max()
                    for q in ("velocity", "angular velocity")]  # fmt: skip
        np.testing.assert_allclose(matrix(table, "peak_velocity", 2)[i], expected, rtol=PEAKS)
        assert plan.check(model.limits).ok
    assert table["peak_velocity_1"].to_numpy().max() <= 2.0 * (1 + ROUNDING_OVER)
    assert table["peak_velocity_2"].to_numpy().max() <= 4.0 * (1 + ROUNDING_OVER)


def test_mobile_swept_limits_and_start(tmp_path):
    data = {
        "sweep": {"planner": "mobile", "chunk": 4},
        "robot": {"name": "jackal"},
        "fixed": {"goal": [1.0, 0.5, 0.0], "start": [0.5, 0.0, 0.2]},
        "swept": {"vmax": {"grid": [0.5, 1.0, 2]}, "wmax": {"values": [1.0, 2.0]}},
    }
    summary, table = planned(data, tmp_path)
    assert table.num_rows == 4 and summary.failed == 0
    model = mobile.jackal()
    for row in table.to_pylist():
        limits = mobile.MobileLimits(velocity=row["vmax"], angular_velocity=row["wmax"],
                                     acceleration=20.0, angular_acceleration=25.0)  # fmt: skip
        plan = mobile.rotate_translate_rotate([1.0, 0.5, 0.0], [0.5, 0.0, 0.2], model=model,
                                              limits=limits)  # fmt: skip
        assert row["duration"] == pytest.approx(plan.duration, rel=SAME_CODE)
        assert row["peak_velocity_1"] <= row["vmax"] * (1 + ROUNDING_OVER)
        assert row["peak_velocity_2"] <= row["wmax"] * (1 + ROUNDING_OVER)
    assert sorted({(r["vmax"], r["wmax"]) for r in table.to_pylist()}) == [
        (0.5, 1.0), (0.5, 2.0), (1.0, 1.0), (1.0, 2.0),
    ]  # fmt: skip


WHEEL = 2.0 / 0.098  # the jackal's wheel speed limit (rad/s)


def test_mobile_rows_keep_the_wheel_speed_limit_of_the_base(tmp_path):
    # vmax = 3 m/s is past what the jackal's wheels allow (2 m/s): the sweep used to
    # rebuild the limits without the wheels and call 30.6 rad/s wheels feasible.
    data = {"sweep": {"planner": "mobile", "problems": 8, "chunk": 4, "seed": 2},
            "robot": {"name": "jackal"}, "fixed": {"vmax": 3.0},
            "swept": {"goal": {"uniform": [[-3.0, -3.0, -3.0], [3.0, 3.0, 3.0]]}}}  # fmt: skip
    summary, table = planned(data, tmp_path)
    assert summary.failed == 0 and summary.infeasible == 0
    model = mobile.jackal()
    goals = matrix(table, "goal", 3)
    for i in range(8):
        # The same call in the Python API: the base's limits with vmax replaced.
        plan = mobile.rotate_translate_rotate(goals[i], [0.0, 0.0, 0.0], model=model, vmax=3.0)
        report = plan.check()
        assert report.ok
        assert table["duration"][i].as_py() == pytest.approx(plan.duration, rel=SAME_CODE)
        assert table["feasible"][i].as_py() is True
        # Without the wheel limit the drive would be shorter: the limit was applied.
        unwheeled = mobile.MobileLimits(velocity=3.0, angular_velocity=4.0, acceleration=20.0,
                                        angular_acceleration=25.0)  # fmt: skip
        fast = mobile.rotate_translate_rotate(goals[i], [0.0, 0.0, 0.0], model=model,
                                              limits=unwheeled)  # fmt: skip
        assert not fast.check(model.limits.replace(velocity=3.0)).ok
        assert table["duration"][i].as_py() > fast.duration
    wheels = matrix(table, "peak_wheel_speed", 2)  # the rows show the wheels, checked
    for i in range(8):
        plan = mobile.rotate_translate_rotate(goals[i], [0.0, 0.0, 0.0], model=model, vmax=3.0)
        expected = np.abs(plan.check().peaks["wheel speed"]).max(axis=0)
        np.testing.assert_allclose(wheels[i], expected, rtol=PEAKS)
    assert wheels.max() <= WHEEL * (1 + ROUNDING_OVER)
    assert wheels.max() >= WHEEL * (1 - 1e-12)  # the long drives run the wheels at their limit
    assert table["worst_violation"].to_numpy().max() <= ROUNDING_OVER


def test_a_row_is_feasible_exactly_when_its_check_is_ok():
    # A check may flag a jump where two pieces meet (an unbounded derivative, value
    # inf) while every peak stays inside its bound: the verdict is the check's.
    from trajkit.limits import Report, Violation
    from trajkit.sweep.planners import _one_by_one

    inside = (np.array([-0.5]), np.array([0.5]))
    bounds = (np.array([-1.0]), np.array([1.0]))
    jump = Violation("acceleration", 0, 0.25, np.inf, 1.0)
    over = Violation("velocity", 0, 0.5, 1.5, 1.0)
    reports = [
        Report((), {"velocity": inside, "acceleration": inside},
               {"velocity": bounds, "acceleration": bounds}),
        Report((jump,), {"velocity": inside, "acceleration": inside},
               {"velocity": bounds, "acceleration": bounds}),
        Report((over,), {"velocity": (np.array([0.0]), np.array([1.5])),
                         "acceleration": (np.array([0.0]), np.array([np.inf]))},
               {"velocity": bounds, "acceleration": bounds}),
    ]  # fmt: skip

    class Plan:
        duration = 1.0

    result = _one_by_one(3, 1, ("velocity", "acceleration"),
                         lambda i: (Plan(), reports[i]), None, lambda p, t: t)  # fmt: skip
    assert result.columns["feasible"].tolist() == [True, False, False]
    assert result.columns["worst_violation"].tolist() == [0.0, np.inf, np.inf]
    assert result.columns["peak_acceleration_1"].tolist() == [0.5, 0.5, np.inf]


@pytest.mark.parametrize(
    "fixed",
    [
        # 1e300 s at the velocity limit, ramps of 2.5e-301 s: 0 * inf = NaN peaks once
        # gave an infeasible row with a stack of overflow warnings. In absolute time the
        # last ramp rounds away (float64 resolves 1e284 s there), so no plan reaches
        # the target: the row says so.
        {"qf": 1.0, "vmax": 1e-300, "amax": 4.0},
        {"qf": 1e308, "vmax": 1.0, "amax": 4.0},
    ],
    ids=["vmax-1e-300", "qf-1e308"],
)
def test_extreme_moves_have_honest_rows_and_no_warnings(tmp_path, fixed):
    data = {"sweep": {"planner": "trapezoid", "problems": 2, "chunk": 2},
            "robot": {"joints": 2}, "fixed": {"q0": 0.0, **fixed}}  # fmt: skip
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        summary, table = planned(data, tmp_path)
    assert summary.failed == summary.infeasible == 2
    for row in table.to_pylist():
        assert row["error"].startswith("InfeasibleError: trapezoidal: joint 1 needs about 1e+30")
        assert "beyond what float64 resolves in one motion" in row["error"]
        assert not row["feasible"]
