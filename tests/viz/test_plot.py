"""Plots: panels, labels with units, limits drawn, files saved (the lazy matplotlib import:
test_imports)."""

from __future__ import annotations

import numpy as np
import pytest

import trajkit as tk


@pytest.fixture
def move() -> tk.Trajectory:
    return tk.cubic(np.radians([0, 0]), np.radians([67, -45]), vmax=np.radians([9, 11]))


def test_profiles_panels_labels_and_limits(move):
    limits = tk.Limits(velocity=np.radians([9, 11]), acceleration=0.1)
    figure = tk.plot.profiles(move, limits, orders=(0, 1, 2, 3), title="seed 000")
    axes = figure.get_axes()
    assert [ax.get_ylabel() for ax in axes] == [
        "position [rad]",
        "velocity [rad/s]",
        "acceleration [rad/s²]",
        "jerk [rad/s³]",
    ]
    assert axes[-1].get_xlabel() == "time [s]"
    assert figure._suptitle.get_text() == "seed 000"
    # Velocity panel: two joint curves and four dashed per-joint bounds (joint colours).
    velocity = axes[1]
    solid = [line for line in velocity.get_lines() if line.get_linestyle() == "-"]
    dashed = [line for line in velocity.get_lines() if line.get_linestyle() == "--"]
    assert len(solid) == 2 and len(dashed) == 4
    assert sorted(line.get_ydata()[0] for line in dashed) == pytest.approx(
        sorted(np.radians([-11, -9, 9, 11]))
    )
    # Shared acceleration bound: one black line per side.
    acceleration_dashed = [ln for ln in axes[2].get_lines() if ln.get_linestyle() == "--"]
    assert len(acceleration_dashed) == 2
    # The curve reaches the exact peak velocity (breakpoints and dense samples drawn).
    assert np.max(solid[0].get_ydata()) == pytest.approx(np.radians(9), rel=1e-6)


def test_profiles_degrees_and_samples(move):
    samples = move.sample(0.5)
    figure = tk.plot.profiles(samples, degrees=True, names=["shoulder", "elbow"])
    axes = figure.get_axes()
    assert axes[0].get_ylabel() == "position [deg]"
    lines = axes[0].get_lines()
    assert lines[0].get_ydata()[-1] == pytest.approx(67.0, rel=1e-12)
    assert [t.get_text() for t in axes[0].get_legend().get_texts()] == ["shoulder", "elbow"]


@pytest.mark.parametrize("suffix", [".png", ".svg", ".pdf"])
def test_save_formats(move, tmp_path, suffix):
    path = tk.plot.save(tk.plot.profiles(move), tmp_path / f"p{suffix}")
    head = path.read_bytes()[:5]
    assert head == {".png": b"\x89PNG\r", ".svg": b"<?xml", ".pdf": b"%PDF-"}[suffix]
    assert [p.name for p in tmp_path.iterdir()] == [f"p{suffix}"]


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"orders": (0, 4)}, "orders must be distinct values among 0, 1, 2, 3"),
        ({"orders": ()}, "orders must be distinct"),
        ({"names": ["a"]}, "names gives 1 labels for 2 joints"),
        ({"limits": {"velocity": 1}}, "limits must be a trajkit.Limits"),
        ({"unit": "m", "degrees": True}, "degrees=True needs angles in rad"),
        ({"width": 0}, "width must be > 0"),
    ],
)
def test_profiles_bad_input(move, kwargs, message):
    with pytest.raises(tk.InvalidInputError, match=message):
        tk.plot.profiles(move, **kwargs)


def test_profiles_rejects_other_objects():
    with pytest.raises(tk.InvalidInputError, match=r"data must be a trajkit curve .* or Samples"):
        tk.plot.profiles(np.zeros(3))


def test_profiles_refuses_a_batch_and_names_the_way():
    batch = tk.batch.trapezoidal([[0.0], [1.0]], [[1.0], [2.0]], 1.0, 1.0)
    with pytest.raises(tk.InvalidInputError, match=r"plot one of them, batch\[i\]"):
        tk.plot.profiles(batch)
    assert tk.plot.profiles(batch[1]).get_axes()[0].get_ylabel() == "position [rad]"


def test_profiles_of_a_task_trajectory_in_metres_to_any_order():
    from trajkit.taskspace import Line, timed

    task = timed(Line([0, 0, 0], [0.3, 0.4, 0]), "trapezoid", vmax=0.5, amax=1.0)
    figure = tk.plot.profiles(task)
    axes = figure.get_axes()
    assert [ax.get_ylabel() for ax in axes] == [
        "position [m]",
        "velocity [m/s]",
        "acceleration [m/s²]",
    ]
    assert [t.get_text() for t in axes[0].get_legend().get_texts()] == ["x", "y", "z"]
    # Drawn from the curve itself: the speed along x peaks at 0.3 / 0.5 of 0.5 m/s.
    x_speed = axes[1].get_lines()[0].get_ydata()
    assert np.max(x_speed) == pytest.approx(0.5 * 0.3 / 0.5, rel=1e-12)
    assert tk.plot.profiles(task, orders=(3,)).get_axes()[0].get_ylabel() == "jerk [m/s³]"


def test_profiles_of_a_base_stop_at_its_highest_order():
    from trajkit import mobile

    plan = mobile.rotate_translate_rotate((1.0, 0.0, 0.0), vmax=0.5, amax=1.0, wmax=1.0)
    with pytest.raises(tk.InvalidInputError, match="order must be 0, 1 or 2 for a MobileTraj"):
        tk.plot.profiles(plan, orders=(0, 3))


def test_profiles_of_a_base_labels_each_unit_and_turns_only_angles_to_degrees():
    from trajkit import mobile

    plan = mobile.rotate_translate_rotate(
        (1.0, 1.0, np.pi / 2), vmax=0.5, amax=1.0, wmax=1.0, alpha_max=2.0
    )
    axes = tk.plot.profiles(plan, degrees=True).get_axes()
    assert axes[0].get_ylabel() == "position [m, deg]"
    assert axes[1].get_ylabel() == "velocity [m/s, deg/s]"
    heading = axes[0].get_lines()[2]
    assert heading.get_label() == "θ"
    assert heading.get_ydata()[-1] == pytest.approx(90.0, abs=1e-9)
    assert axes[0].get_lines()[0].get_ydata()[-1] == pytest.approx(1.0, abs=1e-9)


def test_profiles_of_a_geometric_path_is_drawn_against_its_parameter():
    from trajkit.taskspace import Arc

    arc = Arc(center=[0, 0, 0], start=[2, 0, 0], angle=np.pi / 2)
    axes = tk.plot.profiles(arc, orders=(0, 1)).get_axes()
    assert axes[-1].get_xlabel() == "path parameter u"
    assert [ax.get_ylabel() for ax in axes] == ["position [m]", "velocity [m]"]
    assert axes[0].get_lines()[0].get_xdata()[-1] == 1.0


def test_profiles_of_a_flat_output_has_any_order():
    from trajkit.mobile.flatness import FigureEight

    eight = FigureEight(width=2.0, height=1.0, period=10.0)
    axes = tk.plot.profiles(eight, orders=(0, 3)).get_axes()
    assert [ax.get_ylabel() for ax in axes] == ["position [m]", "jerk [m/s³]"]


def test_save_bad_suffix(move, tmp_path):
    with pytest.raises(tk.InvalidInputError, match=r"\.png, \.svg or \.pdf"):
        tk.plot.save(tk.plot.profiles(move), tmp_path / "p.bmp")
    assert list(tmp_path.iterdir()) == []


def test_limit_with_wrong_joint_count(move):
    with pytest.raises(tk.InvalidInputError, match="velocity"):
        tk.plot.profiles(move, tk.Limits(velocity=[1.0, 2.0, 3.0]))


def arm_move():
    from trajkit.kinematics import Spatial3R
    from trajkit.taskspace import Line, timed, to_joint_space

    robot = Spatial3R()
    motion = timed(Line([0, -12, 20], [10, 12, 20]), "cubic", duration=10.0)
    return robot, motion, to_joint_space(robot, motion, ik_step=0.1)


@pytest.mark.parametrize("view", ["3d", "xy", "xz", "yz"])
def test_arm_draws_each_instant_and_the_tool_path(view):
    robot, _, plan = arm_move()
    figure = tk.plot.arm(robot, plan.trajectory, instants=4, view=view, title="seed 003")
    (ax,) = figure.get_axes()
    lines = ax.get_lines()
    assert len(lines) == 1 + 4  # the tool path, then one polyline per instant
    assert lines[0].get_label() == "tool path"
    assert ax.get_title() == "seed 003"
    # The last drawn pose ends at the tool's final position.
    end = robot.fk(plan.trajectory.position(plan.trajectory.end_time))[:3, 3]
    if view == "3d":
        xs, ys, zs = lines[-1].get_data_3d()
        np.testing.assert_allclose([xs[-1], ys[-1], zs[-1]], end, atol=1e-9)
    else:
        a, b = {"xy": (0, 1), "xz": (0, 2), "yz": (1, 2)}[view]
        xs, ys = lines[-1].get_data()
        np.testing.assert_allclose([xs[-1], ys[-1]], end[[a, b]], atol=1e-9)


def test_task_space_panels():
    _, motion, _ = arm_move()
    figure = tk.plot.task_space(motion, unit="cm")  # seed 003's arm is in cm
    axes = figure.get_axes()
    assert [ax.get_ylabel() for ax in axes] == [
        "position [cm]",
        "velocity [cm/s]",
        "acceleration [cm/s²]",
    ]
    # Velocity panel: x, y, z and the magnitude, whose peak is the cubic's 1.5 L / T.
    magnitude = axes[1].get_lines()[-1].get_ydata()
    assert magnitude.max() == pytest.approx(1.5 * np.hypot(10, 24) / 10, rel=1e-6)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [({"view": "top"}, "view must be"), ({"instants": 0}, "instants must be an integer >= 1")],
)
def test_arm_bad_input(kwargs, message):
    robot, _, plan = arm_move()
    with pytest.raises(tk.InvalidInputError, match=message):
        tk.plot.arm(robot, plan.trajectory, **kwargs)


# ---------------------------------------------------------------------- mobile
@pytest.fixture(scope="module")
def drive():
    from trajkit import mobile

    return mobile.rotate_translate_rotate(
        (2.0, 1.0, 1.0), vmax=0.5, wmax=1.0, amax=1.0, alpha_max=2.0, model=mobile.jackal()
    )


@pytest.fixture(scope="module")
def tracked(drive):
    from trajkit import mobile

    plan = mobile.flat_trajectory(mobile.FigureEight(2.0, 1.0, 20.0))
    return mobile.simulate(plan, mobile.Kanayama(), sample_step=0.05, initial_pose=(0.2, -0.1, 0.5))


def test_mobile_panels_of_a_plan(drive):
    figure = tk.plot.mobile(drive, title="goto")
    axes = figure.get_axes()
    assert [ax.get_ylabel() for ax in axes] == [
        "forward speed v [m/s]",
        "turn rate ω [rad/s]",
        "world velocity [m/s]",
        "position [m]",
        "heading [rad]",
    ]
    assert figure._suptitle.get_text() == "goto"
    heading = axes[4].get_lines()[0]
    assert heading.get_ydata()[-1] == pytest.approx(1.0, abs=1e-12)
    # The drive's x velocity peaks at the speed limit times cos(heading).
    x_speed = axes[2].get_lines()[0].get_ydata()
    assert x_speed.max() == pytest.approx(0.5 * np.cos(np.arctan2(1.0, 2.0)), rel=1e-9)
    # The plan's own limits, named and in view: its speed reaches the 0.5 m/s bound.
    legend = [t.get_text() for t in axes[0].get_legend().get_texts()]
    assert legend == ["v planned", "speed limit"]
    assert axes[0].get_ylim()[1] > 0.5 and axes[0].get_lines()[0].get_ydata().max() == (
        pytest.approx(0.5, rel=1e-9))  # fmt: skip


def test_mobile_panels_of_a_run_draw_planned_commanded_measured_and_errors(tracked):
    axes = tk.plot.mobile(tracked).get_axes()
    labels = [line.get_label() for line in axes[3].get_lines()]
    assert labels == ["x planned", "y planned", "x actual", "y actual"]
    assert [line.get_linestyle() for line in axes[3].get_lines()] == ["--", "--", "-", "-"]
    np.testing.assert_array_equal(axes[3].get_lines()[2].get_ydata(), tracked.actual[:, 0])
    speed = {line.get_label(): line for line in axes[0].get_lines()}
    assert list(speed) == ["v planned", "v commanded", "v measured"]
    np.testing.assert_array_equal(speed["v commanded"].get_ydata(), tracked.commands[:, 0])
    # Measured: the change of the simulated pose, close to what was commanded.
    np.testing.assert_allclose(speed["v measured"].get_ydata()[50:], tracked.commands[50:-1, 0],
                               atol=0.02)  # fmt: skip
    assert axes[5].get_ylabel() == "error [m | rad]"
    np.testing.assert_array_equal(axes[5].get_lines()[0].get_ydata(), tracked.position_error)
    assert not axes[0].get_legend().get_texts()[-1].get_text().endswith("limit")  # a log: none


def test_mobile_path_draws_the_robot(drive, tracked, tmp_path):
    figure = tk.plot.mobile_path(drive, robots=5)
    ax = figure.get_axes()[0]
    assert len(ax.patches) == 5
    assert ax.get_xlabel() == "x [m]" and ax.get_ylabel() == "y [m]"
    # The first triangle's tip points along the start heading (0 rad): to +x.
    tip = ax.patches[0].get_xy()[0]
    assert tip[1] == pytest.approx(0.0, abs=1e-12) and tip[0] > 0
    run = tk.plot.mobile_path(tracked, robots=0)
    assert [line.get_label() for line in run.get_axes()[0].get_lines()][:2] == [
        "planned",
        "actual",
    ]
    assert not run.get_axes()[0].patches
    tk.plot.save(run, tmp_path / "path.png")
    assert (tmp_path / "path.png").read_bytes()[:4] == b"\x89PNG"


def test_a_closed_paths_start_is_seen_over_its_end():
    from trajkit import mobile

    eight = mobile.flat_trajectory(mobile.FigureEight(2.0, 1.0, 20.0), model=mobile.jackal())
    ax = tk.plot.mobile_path(eight, robots=0).get_axes()[0]
    marks = {line.get_label(): line for line in ax.get_lines()}
    start, end = marks["start"], marks["end"]
    np.testing.assert_allclose(start.get_xydata(), end.get_xydata(), atol=1e-9)  # closed
    assert start.get_zorder() > end.get_zorder()  # the dot on top
    assert end.get_markerfacecolor() == "none"  # the square hollow around it
    assert end.get_markersize() > start.get_markersize()


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda d: tk.plot.mobile("not a plan"), "MobileTrajectory or a SimulationLog"),
        (lambda d: tk.plot.mobile_path(d, robots=-1), "robots must be an integer >= 0"),
        (lambda d: tk.plot.mobile(d, width=0), "width must be > 0"),
    ],
)
def test_mobile_plot_bad_input(drive, call, message):
    with pytest.raises(tk.InvalidInputError, match=message):
        call(drive)


class _Bare(tk.Curve):
    """A curve known to the protocol only: names c1, c2 and no unit."""

    end_time = 2.0

    def evaluate(self, t, order=0):
        t = np.atleast_1d(t)
        values = [np.stack([t, t**2], axis=1), np.stack([np.ones_like(t), 2 * t], axis=1)]
        return values[order] if order < 2 else np.zeros((t.size, 2))


def test_profiles_of_a_bare_curve_label_no_unit_they_do_not_know():
    axes = tk.plot.profiles(_Bare()).get_axes()
    assert [ax.get_ylabel() for ax in axes] == ["position", "velocity", "acceleration"]
    assert [t.get_text() for t in axes[0].get_legend().get_texts()] == ["c1", "c2"]
    assert axes[1].get_lines()[1].get_ydata()[-1] == 4.0
    assert tk.plot.profiles(_Bare(), unit="V").get_axes()[1].get_ylabel() == "velocity [V/s]"


def test_constraints_draw_torques_and_tool_speed_against_their_limits():
    from trajkit.kinematics import UR5

    ur5 = UR5()
    path = tk.cubic_spline([0, 1], [[0, -1.5, 0, -1.5, 0, 0], [0.5, -1.0, 0.8, -1.5, 0.3, 0]],
                           bc="natural")  # fmt: skip
    limits = tk.Limits(velocity=3.0, acceleration=50.0)
    both = [tk.TorqueLimit(ur5), tk.ToolLimit(ur5, speed=0.3, acceleration=4.0)]
    timed = tk.topp(path, limits, grid=100, constraints=both)
    figure = tk.plot.constraints(timed, both)
    axes = figure.axes
    assert [ax.get_ylabel() for ax in axes] == [
        "torque [N·m]", "tool speed [m/s]", "tool acceleration [m/s^2]"
    ]  # fmt: skip
    labels = [[t.get_text() for t in ax.get_legend().get_texts()] for ax in axes]
    assert labels[0][:6] == list(ur5.names) and labels[0][-1] == "limits (dashed)"
    assert labels[1] == ["tool speed", "upper limit"]
    assert axes[-1].get_xlabel() == "time [s]"
    # The dashed lines are the limits: ±150 N·m and ±28 N·m, 0.3 m/s.
    dashed = {round(float(line.get_ydata()[0]), 6) for line in axes[0].lines
              if line.get_linestyle() == "--" and len(line.get_ydata())}  # fmt: skip
    assert {150.0, -150.0, 28.0, -28.0} <= dashed
    assert "at most" in axes[0].get_title()


def test_constraints_bad_input():
    from trajkit.kinematics import UR5

    ur5 = UR5()
    with pytest.raises(tk.InvalidInputError, match=r"trajectory must be a trajkit\.Trajectory"):
        tk.plot.constraints(np.zeros(3), tk.TorqueLimit(ur5))
    move = tk.cubic(np.zeros(6), np.ones(6), 2.0)
    with pytest.raises(tk.InvalidInputError, match="at least one TorqueLimit or ToolLimit"):
        tk.plot.constraints(move, [])
    with pytest.raises(tk.InvalidInputError, match="has 6 joints but the path has 2"):
        tk.plot.constraints(tk.cubic([0, 0], [1, 1], 2.0), tk.TorqueLimit(ur5))
