"""The trajkit command: plan summaries, files, errors (one line, exit 2, no partial files)."""

from __future__ import annotations

import dataclasses
import errno
import os
import subprocess
import sys

import numpy as np
import pytest

import trajkit as tk
from trajkit import cli
from trajkit.cli import main
from trajkit.planners import CATALOG


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    status = main(list(argv))
    captured = capsys.readouterr()
    return status, captured.out, captured.err


def test_plan_cubic_degrees_prints_exact_minimum_and_writes_files(tmp_path, capsys):
    csv, png = tmp_path / "move.csv", tmp_path / "move.png"
    status, out, err = run(
        capsys,
        "plan", "cubic", "--q0", "0", "0", "--qf", "67", "-45", "--vmax", "9,11", "--deg",
        "--csv", str(csv), "--plot", str(png),
    )  # fmt: skip
    assert status == 0, err
    assert err == ""
    assert "duration 11.1666667 s (set by vmax of joint 1)" in out
    assert "limit check (SI units): OK" in out
    samples = tk.Samples.from_csv(csv)
    assert samples.t[-1] == pytest.approx(67 * 1.5 / 9, rel=1e-12)
    np.testing.assert_allclose(samples.q[-1], np.radians([67, -45]), rtol=1e-12)
    assert np.allclose(np.diff(samples.t)[:-1], 0.01)  # samples.DEFAULT_STEP
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["move.csv", "move.png"]


@pytest.mark.parametrize("profile", ["cubic", "quintic", "septic"])
def test_plan_each_profile_with_duration(profile, capsys):
    status, out, _ = run(capsys, "plan", profile, "--q0", "0", "--qf", "1.2", "--duration", "2")
    assert status == 0
    assert f"{profile} move: 1 joint(s), duration 2 s" in out


def test_plan_quintic_boundary_accelerations(capsys, tmp_path):
    csv = tmp_path / "q.csv"
    status, _, err = run(
        capsys, "plan", "quintic", "--q0", "0", "--qf", "1", "--duration", "2",
        "--a0", "0.5", "--af", "-0.25", "--csv", str(csv), "--sample-step", "0.5",
    )  # fmt: skip
    assert status == 0, err
    samples = tk.Samples.from_csv(csv)
    np.testing.assert_array_equal(samples.t, [0, 0.5, 1.0, 1.5, 2.0])
    assert samples.qdd[0, 0] == pytest.approx(0.5, abs=1e-12)
    assert samples.qdd[-1, 0] == pytest.approx(-0.25, abs=1e-12)


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["plan", "cubic", "--q0", "0", "--qf", "1", "--duration", "1", "--vmax", "1"],
         "duration 1 s is below the minimum 1.5 s set by vmax=1 rad/s (joint 1)"),
        (["plan", "cubic", "--q0", "0", "--qf", "nan", "--duration", "1"], "qf must be finite"),
        (["plan", "cubic", "--q0", "0", "--qf", "1"], "give duration, or at least one of vmax"),
        (["plan", "cubic", "--q0", "0", "--qf", "1", "--duration", "-1"], "duration must be > 0"),
        (["plan", "cubic", "--q0", "0", "--qf", "1", "--vmax", "-2"], "vmax must be > 0"),
        (["plan", "cubic", "--q0", "0", "0", "--qf", "1", "1", "1", "--duration", "1"],
         "qf has 3 joints but q0 has 2"),
        (["plan", "cubic", "--q0", "0", "--qf", "1", "--duration", "1", "--a0", "1"],
         "--a0 applies to the quintic, septic and scurve planners, not cubic"),
        (["plan", "cubic", "--qf", "1", "--duration", "1"], "plan needs --q0 and --qf"),
        (["plan", "cubic", "--q0", "x", "--qf", "1"], "expected numbers"),
        (["plan", "trapezium", "--q0", "0", "--qf", "1"], "invalid choice"),
        (["plan", "cubic", "--q0", "0", "--qf", "1", "--duration", "1", "--sample-step", "0"],
         "--sample-step must be a time > 0 s, got 0"),
        (["plan", "cubic", "--q0", "0", "--qf", "1", "--duration", "1", "--dt", "0.1"],
         "--dt is now two flags: --period (the controller period"),
    ],
)  # fmt: skip
def test_errors_are_one_line_with_status_2(argv, message, capsys, tmp_path):
    csv = tmp_path / "out.csv"
    status, out, err = run(capsys, *argv, "--csv", str(csv))
    assert status == 2
    assert err.count("\n") == 1, err
    assert err.startswith("trajkit: error: ")
    assert message in err
    assert "Traceback" not in err
    assert out == ""
    assert list(tmp_path.iterdir()) == []


def test_no_partial_files_when_the_plot_cannot_be_written(tmp_path, capsys):
    csv = tmp_path / "out.csv"
    status, _, err = run(
        capsys, "plan", "cubic", "--q0", "0", "--qf", "1", "--duration", "1",
        "--csv", str(csv), "--plot", str(tmp_path / "missing" / "p.png"),
    )  # fmt: skip
    assert status == 2
    assert "does not exist" in err
    assert list(tmp_path.iterdir()) == []


def test_bad_plot_suffix(tmp_path, capsys):
    status, _, err = run(
        capsys, "plan", "cubic", "--q0", "0", "--qf", "1", "--duration", "1",
        "--plot", str(tmp_path / "p.txt"),
    )  # fmt: skip
    assert status == 2
    assert "--plot must end in .png, .svg or .pdf" in err
    assert list(tmp_path.iterdir()) == []


def test_no_command_prints_help(capsys):
    status, out, _ = run(capsys)
    assert status == 2
    assert "plan" in out and "demo" in out


def test_console_script_version_and_error_without_traceback(tmp_path):
    version = subprocess.run(
        [sys.executable, "-m", "trajkit.cli", "--version"], capture_output=True, text=True
    )
    assert version.returncode == 0
    assert version.stdout.strip() == f"trajkit {tk.__version__}"
    bad = subprocess.run(
        [sys.executable, "-m", "trajkit.cli", "plan", "cubic", "--q0", "0", "--qf", "inf"],
        capture_output=True,
        text=True,
    )
    assert bad.returncode == 2
    assert bad.stderr.strip().count("\n") == 0
    assert "qf must be finite" in bad.stderr


def test_demo_writes_every_output_and_reports_exact_values(tmp_path, capsys):
    out_dir = tmp_path / "demo"
    status, out, err = run(capsys, "demo", "--out", str(out_dir))
    assert status == 0, err
    names = sorted(p.name for p in out_dir.iterdir())
    # The scenarios' own outputs are in scenarios/; the worked examples add only what
    # the scenarios do not write: no example is written twice.
    expected = {
        "seed003_time_optimal_joints.png", "seed003_time_optimal_joints.csv",
        "seed003_time_optimal_jerk_limited_joints.png",
        "seed003_time_optimal_jerk_limited_joints.csv",
        "summary.txt",
    }  # fmt: skip
    for profile in ("trapezoid", "scurve"):
        for sync in ("phase", "time"):
            for suffix in ("", "_dt"):
                expected.add(f"seed001_{profile}_{sync}{suffix}.png")
    mobile_stems = [
        "seed000_jackal_goto_10hz",
        *(f"seed002_figure8_{name}" for name in
          ("feedforward", "kanayama", "feedback_linearization", "pure_pursuit")),
    ]  # fmt: skip
    for stem in mobile_stems:
        expected |= {f"{stem}.png", f"{stem}_path.png", f"{stem}.csv"}
    expected |= {
        "seed000_rrbot_mujoco.png", "seed000_rrbot_mujoco.csv",
        "seed000_jackal_goto_mujoco.png", "seed000_jackal_goto_mujoco_path.png",
        "seed000_jackal_goto_mujoco.csv",
    }  # fmt: skip
    expected |= {"index.html", "scenarios"}  # the example scenarios and their report
    if "no frames rendered" not in out:  # frames need an OpenGL backend
        for stem in ("seed000_rrbot_mujoco", "seed000_jackal_goto_mujoco"):
            expected |= {f"{stem}_frame{i}.png" for i in range(3)}
    assert set(names) == expected
    assert not [name for name in names if name.startswith(".")]  # no temporaries left
    # The via-point polynomials are the seed004 scenarios' own lines.
    assert "piece 1: a0..a3 = [0.0, 0.0, 1.3, -0.8]" in out
    assert "piece 2: a0..a3 = [0.55, -0.375, 0.4, -0.075]" in out
    assert "exact common minimum duration 11.1666666667 s" in out
    assert "11 s breaks the velocity limit: joint 1" in out
    summary = (out_dir / "summary.txt").read_text()
    assert "the hand solution's 6 s breaks the velocity limit" in summary
    from trajkit import scenario

    scenario_files = sorted(p.name for p in (out_dir / "scenarios").iterdir())
    for path in scenario.examples():
        assert f"{path.stem}_summary.txt" in scenario_files
    assert f"wrote {len(names) - 1 + len(scenario_files)} files" in out
    assert "open " in out and "index.html" in out
    assert "trapezoid, sync=phase, continuous: duration 14.6071428571 s, limits OK" in out
    assert "trapezoid, sync=phase, on 2 ms ticks: duration 14.608 s, limits OK" in out
    assert "scurve, sync=time, on 2 ms ticks: duration 14.858 s, limits OK" in out
    assert "drive to the goal: minimum duration 32.3941772 s" in out
    assert "the hand value 32 s breaks the limit" in out
    assert "ends at (0.286479 m, 1.06915 m, 2.61799 rad)" in out
    assert "feedback linearization: RMS error" in out
    assert "seed 003 3-DOF spatial arm, cubic line in 10 s: FK of the joint trajectory" in out
    assert "linear ellipse on planar 2R in 5 s: path error" in out
    assert "position servo with gravity compensation: max error 0.963° / 0.649°" in out
    assert "computed torque (ω = 30 rad/s): max error 0.000106° / 7.14e-05°" in out
    assert "kanayama at 50 Hz: ends at (4.9998 m, 3.0000 m, 1.5021 rad)" in out
    seed000 = tk.Samples.from_csv(out_dir / "scenarios" / "seed000_rrbot_cubic.csv")
    assert seed000.t[-1] == pytest.approx(11.1666666666666667, rel=1e-12)


def test_plan_trapezoid_phase_sync_on_controller_period(capsys, tmp_path):
    csv = tmp_path / "six.csv"
    status, out, err = run(
        capsys, "plan", "trapezoid", "--q0", "0", "--qf", "90,75,60,45,30,15",
        "--vmax", "7,7,7,3.5,3.5,3.5", "--amax", "4,4,4,2,2,2", "--deg",
        "--sync", "phase", "--period", "0.002", "--csv", str(csv),
    )  # fmt: skip
    assert status == 0, err
    first = out.splitlines()[0]
    assert first == (
        "trapezoid move: 6 joint(s), duration 14.608 s, sync=phase, "
        "switching on multiples of period=0.002 s"
    )
    assert "1.75 11.108 1.75" in out  # every joint's rise, coast and fall
    assert "limit check (SI units): OK" in out
    samples = tk.Samples.from_csv(csv)
    np.testing.assert_allclose(np.diff(samples.t), 0.002, rtol=1e-9)


def test_plan_trapezoid_time_sync_names_limiting_joint(capsys):
    status, out, _ = run(
        capsys, "plan", "trapezoid", "--q0", "0,0", "--qf", "1,3", "--vmax", "1", "--amax", "1"
    )
    assert status == 0
    assert "duration 4 s (set by joint 2), sync=time" in out


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (
            ["--vmax", "1"],
            "--amax is required by the trapezoid planner (it needs --vmax and --amax)",
        ),
        (
            ["--vmax", "1", "--amax", "1", "--jmax", "3"],
            "--jmax applies to the cubic, quintic, septic and scurve planners, not trapezoid",
        ),
        (["--vmax", "1", "--amax", "1", "--duration", "0.5"], "below the minimum 2 s"),
        (["--vmax", "1", "--amax", "1", "--vf", "2"], "vf=2 rad/s is beyond the velocity limit"),
    ],
)
def test_plan_trapezoid_errors(argv, message, capsys):
    status, _, err = run(capsys, "plan", "trapezoid", "--q0", "0", "--qf", "1", *argv)
    assert status == 2
    assert message in err
    assert err.count("\n") == 1


def test_plan_scurve_on_controller_period(capsys):
    status, out, err = run(
        capsys, "plan", "scurve", "--q0", "0", "--qf", "1,2", "--vmax", "1", "--amax", "2",
        "--jmax", "10", "--period", "0.002",
    )  # fmt: skip
    assert status == 0, err
    assert out.splitlines()[0] == (
        "scurve move: 2 joint(s), duration 2.7 s (set by joint 2), sync=time, "
        "switching on multiples of period=0.002 s"
    )
    assert "0.2 0.3 0.2 1.3 0.2 0.3 0.2" in out
    assert "limit check (SI units): OK" in out


def test_plan_scurve_needs_all_three_limits(capsys):
    status, _, err = run(capsys, "plan", "scurve", "--q0", "0", "--qf", "1", "--vmax", "1")
    assert status == 2
    assert (
        "--amax and --jmax are required by the scurve planner (it needs --vmax, --amax "
        "and --jmax)" in err
    )


SCURVE_ARGS = ("--q0", "0,0.5", "--qf", "1,-0.5", "--vmax", "1", "--amax", "2")


@pytest.mark.parametrize(
    ("profile", "argv", "kwargs"),
    [
        ("scurve", ["--a0", "0.5,-0.2", "--af=-0.3,0.2"],
         {"a0": [0.5, -0.2], "af": [-0.3, 0.2]}),
        ("scurve", ["--a0", "20", "--deg"], {"a0": np.radians(20), "deg": True}),
        ("scurve", ["--min-duration", "3.5"], {"min_duration": 3.5}),
        ("trapezoid", ["--min-duration", "3.5"], {"min_duration": 3.5}),
        ("scurve", ["--sync", "time_if_necessary"], {"sync": "time_if_necessary"}),
        ("trapezoid", ["--sync", "time_if_necessary", "--vf", "0.2,0"],
         {"sync": "time_if_necessary", "vf": [0.2, 0.0]}),
        ("scurve", ["--grid", "duration", "--period", "0.01"],
         {"grid": "duration", "period": 0.01}),
        ("trapezoid", ["--grid", "duration", "--period", "0.01", "--min-duration", "2.345"],
         {"grid": "duration", "period": 0.01, "min_duration": 2.345}),
        ("scurve", ["--grid", "switches", "--period", "0.01"],
         {"grid": "switches", "period": 0.01}),
    ],
)  # fmt: skip
def test_plan_trapezoid_and_scurve_options_reach_the_planner(profile, argv, kwargs, capsys,
                                                             monkeypatch):  # fmt: skip
    entry = CATALOG[profile]
    planned = []

    def spy(*args, **options):
        planned.append(entry.law(*args, **options))
        return planned[-1]

    monkeypatch.setitem(CATALOG, profile, dataclasses.replace(entry, law=spy))
    jerk = ["--jmax", "10"] if profile == "scurve" else []
    status, out, err = run(capsys, "plan", profile, *SCURVE_ARGS, *jerk, *argv)
    assert status == 0, err
    kwargs = dict(kwargs)
    scale = np.radians(1.0) if kwargs.pop("deg", False) else 1.0
    ends = (np.array([0.0, 0.5]) * scale, np.array([1.0, -0.5]) * scale)
    limits = (1.0 * scale, 2.0 * scale, *([10.0 * scale] if jerk else []))
    planner = {"trapezoid": tk.trapezoidal, "scurve": tk.scurve}[profile]
    direct = planner(*ends, *limits, **kwargs)
    assert planned[0].duration == pytest.approx(direct.duration, rel=1e-12)
    t = np.linspace(0.0, direct.duration, 41)
    np.testing.assert_allclose(planned[0].position(t), direct.position(t), rtol=0, atol=1e-12)
    assert f"duration {direct.duration:.9g} s" in out
    if kwargs.get("grid") == "duration":
        assert "duration a multiple of period=0.01 s" in out.splitlines()[0]


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["cubic", "--duration", "1", "--min-duration", "2"],
         "--min-duration applies to the trapezoid and scurve planners, not cubic"),
        (["quintic", "--duration", "1", "--grid", "duration", "--period", "0.01"],
         "--grid applies to the trapezoid and scurve planners, not quintic"),
        (["trapezoid", "--vmax", "1", "--amax", "2", "--a0", "0.1"],
         "--a0 applies to the quintic, septic and scurve planners, not trapezoid"),
        (["scurve", "--vmax", "1", "--amax", "2", "--jmax", "10", "--duration", "3",
          "--min-duration", "2"],
         "give --duration (exact) or --min-duration (a floor), not both"),
        (["scurve", "--vmax", "1", "--amax", "2", "--jmax", "10", "--min-duration", "0"],
         "min_duration must be > 0"),
        (["scurve", "--vmax", "1", "--amax", "2", "--jmax", "10", "--grid", "duration"],
         "--grid needs --period"),
        (["scurve", "--vmax", "1", "--amax", "2", "--jmax", "10", "--grid", "ticks"],
         "argument --grid: invalid choice: 'ticks'"),
        (["trapezoid", "--vmax", "1", "--amax", "2", "--sync", "sometimes"],
         "argument --sync: invalid choice: 'sometimes'"),
        (["scurve", "--vmax", "1", "--amax", "2", "--jmax", "10", "--af", "3"],
         "af=3 rad/s^2 is beyond"),
    ],
)  # fmt: skip
def test_plan_trapezoid_and_scurve_option_errors(argv, message, capsys):
    status, out, err = run(capsys, "plan", argv[0], "--q0", "0", "--qf", "1", *argv[1:])
    assert status == 2
    assert err.startswith("trajkit: error: ") and err.count("\n") == 1, err
    assert message in err
    assert out == ""


# --------------------------------------------------------------------- mobile


def test_mobile_twist_is_move_jackal(tmp_path, capsys):
    csv, png, path_png = tmp_path / "t.csv", tmp_path / "t.png", tmp_path / "p.png"
    status, out, err = run(
        capsys, "mobile", "twist", "10", "0.1", "10", "15",
        "--csv", str(csv), "--plot", str(png), "--path-plot", str(path_png),
    )  # fmt: skip
    assert status == 0, err
    assert "constant_twist on jackal: duration 15 s" in out
    assert "150 commands at 10 Hz" in out
    assert "limit check: OK" in out
    table = np.loadtxt(csv, delimiter=",", skiprows=1)
    radius, turned = 0.1 / np.radians(10), np.radians(150)
    np.testing.assert_allclose(
        table[-1, 1:4], [radius * np.sin(turned), radius * (1 - np.cos(turned)), turned],
        rtol=1e-12, atol=1e-15,
    )  # fmt: skip
    assert png.read_bytes()[:4] == b"\x89PNG" and path_png.read_bytes()[:4] == b"\x89PNG"


def test_mobile_goto_reproduces_seed000(capsys):
    status, out, err = run(
        capsys, "mobile", "goto", "5", "3", "1.5", "--vmax", "0.2", "--wmax-deg", "30",
        "--blend-ratio", "0.1",
    )  # fmt: skip
    assert status == 0, err
    assert "turn to face the goal: 1.1468058 s" in out
    assert "drive to the goal: 32.3941772 s" in out
    assert "turn to the final heading: 2.03629306 s" in out
    assert "to (5 m, 3 m, 1.5 rad)" in out
    assert "limit check: OK" in out


def test_mobile_figure8_with_a_controller_reports_tracking(capsys, tmp_path):
    csv = tmp_path / "run.csv"
    status, out, err = run(
        capsys, "mobile", "figure8", "--controller", "linearization", "--offset", "0.3", "0",
        "20", "--sample-step", "0.01", "--csv", str(csv),
    )  # fmt: skip
    assert status == 0, err
    assert "feedback linearization: RMS error" in out
    header = csv.read_text().splitlines()[0]
    assert header.startswith("t [s],x_desired [m]")
    table = np.loadtxt(csv, delimiter=",", skiprows=1)
    assert np.hypot(*(table[-1, 4:6] - table[-1, 1:3])) < 1e-6  # converged by the end


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["twist", "10", "0.1", "10", "-1"], "duration must be > 0, got -1 s"),
        (["twist", "0", "0.1", "10", "1"], "rate_hz must be > 0"),
        (["goto", "1", "1", "--robot", "unicycle"], "needs wmax"),
        (["figure8", "--width", "0"], "width must be > 0, got 0 m"),
        (["figure8", "--plot", "x.txt"], "--plot must end in .png, .svg or .pdf"),
        (["goto", "nan", "1", "--vmax", "1", "--wmax-deg", "1", "--blend-ratio", "0.1"],
         "goal must be finite"),
    ],
)  # fmt: skip
def test_mobile_errors_are_one_line(argv, message, capsys):
    status, out, err = run(capsys, "mobile", *argv)
    assert status == 2
    assert message in err
    assert err.count("\n") == 1
    assert out == ""


def test_mobile_failure_writes_no_file(capsys, tmp_path):
    csv = tmp_path / "plan.csv"
    status, _, err = run(
        capsys, "mobile", "twist", "10", "0.1", "10", "5", "--csv", str(csv),
        "--plot", str(tmp_path / "missing" / "plot.png"),
    )  # fmt: skip
    assert status == 2
    assert "does not exist" in err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(("flag", "message"), [
    ("--sample-step", "--sample-step must be a time > 0 s, got -1"),
    ("--dt", "--dt is now named --sample-step (the sampling and simulation step)"),
])  # fmt: skip
def test_mobile_bad_step_fails_before_any_output(flag, message, capsys, tmp_path):
    csv = tmp_path / "plan.csv"
    status, out, err = run(capsys, "mobile", "twist", "10", "0.1", "10", "5", flag, "-1",
                           "--csv", str(csv))  # fmt: skip
    assert status == 2 and out == ""
    assert err == f"trajkit: error: {message}\n"
    assert not csv.exists()


# ------------------------------------------- one-line messages in the user's words and units

TINY_SCENARIO = """name = "tiny"

[robot]
builtin = "rrbot"

[task]
kind = "joint_move"
q0 = [0, 0]
qf = [1, -1]
profile = "cubic"
duration = 2.0

[outputs]
csv = true
plot = false
"""


def tiny_scenario(folder, *, animation: bool = False):
    path = folder / "tiny.toml"
    extra = '\nanimation = "gif"\nanimation_fps = 5\n' if animation else ""
    path.write_text(TINY_SCENARIO + extra, encoding="utf-8")
    return path


def test_numpy_warnings_never_precede_the_error_line(tmp_path, capsys):
    import warnings

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        status, out, err = run(capsys, "plan", "cubic", "--q0", "0", "--qf", "1", "--duration",
                               "1e308", "--csv", str(tmp_path / "x.csv"))  # fmt: skip
    # Which check refuses the overflow is the planners' business; here: one line only.
    assert status == 2
    assert out == ""
    assert err.startswith("trajkit: error: ") and err.count("\n") == 1, err
    assert "Warning" not in err
    assert [str(w.message) for w in caught] == []  # none escaped to be printed
    assert list(tmp_path.iterdir()) == []


def test_the_console_prints_exactly_one_line_for_an_overflowing_duration(tmp_path):
    result = subprocess.run(
        [sys.executable, "-c", "import sys; from trajkit.cli import main; sys.exit(main())",
         "plan", "cubic", "--q0", "0", "--qf", "1", "--duration", "1e308", "--csv", "x.csv"],
        capture_output=True, text=True, cwd=tmp_path, timeout=120,
    )  # fmt: skip
    assert result.returncode == 2
    assert result.stderr.count("\n") == 1, result.stderr
    assert result.stderr.startswith("trajkit: error: ")
    assert "Warning" not in result.stderr
    assert list(tmp_path.iterdir()) == []


def test_a_peak_beyond_float_range_in_degrees_is_inf_without_a_warning(capsys):
    import warnings

    # 1e308 deg/s is 1.7e306 rad/s: the plan is finite, its peak acceleration in deg/s^2 not.
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        status, out, err = run(capsys, "plan", "cubic", "--q0", "0", "--qf", "90",
                               "--duration", "1", "--v0", "1e308", "--deg")  # fmt: skip
    assert (status, err) == (0, "")
    assert [str(w.message) for w in caught] == []
    assert out.splitlines()[-1].split()[-2:] == ["1e+308", "inf"]


def test_warnings_of_a_successful_command_are_shown_once(capsys, monkeypatch):
    import warnings

    def noisy(args):
        for _ in range(3):
            warnings.warn("overflow encountered in power", RuntimeWarning, stacklevel=1)
        return 0

    monkeypatch.setattr(cli, "_plan", noisy)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        assert main(["plan", "cubic", "--q0", "0", "--qf", "1"]) == 0
    assert [(w.category, str(w.message)) for w in caught] == [
        (RuntimeWarning, "overflow encountered in power")
    ]


@pytest.mark.parametrize(
    ("argv", "expected"),
    [
        (["plan", "cubic", "--q0", "0", "--qf", "90", "--duration", "0.1", "--vmax", "10",
          "--deg"],
         "duration 0.1 s is below the minimum 13.5 s set by vmax=10 deg/s (joint 1)"),
        (["plan", "trapezoid", "--q0", "0", "--qf", "90", "--vmax", "10", "--amax", "5",
          "--vf", "20", "--deg"],
         "vf=20 deg/s is beyond the velocity limit 10 deg/s (joint 1)"),
        (["plan", "cubic", "--q0", "0", "--qf", "90", "--vmax", "-12.345678", "--deg"],
         "vmax must be > 0 for every joint, got -12.345678 deg/s for joint 1"),
        (["plan", "cubic", "--q0", "0", "--qf", "90", "--duration", "0.5", "--vmax", "10",
          "--amax", "1", "--deg"],
         "duration 0.5 s is below the minimum 23.2379 s set by amax=1 deg/s^2 (joint 1)"),
        # Without --deg the same message stays in radians.
        (["plan", "cubic", "--q0", "0", "--qf", "1.5", "--duration", "0.1", "--vmax", "10"],
         "duration 0.1 s is below the minimum 0.225 s set by vmax=10 rad/s (joint 1)"),
    ],
)  # fmt: skip
def test_errors_quote_the_values_in_the_users_units(argv, expected, capsys):
    status, out, err = run(capsys, *argv)
    assert (status, out, err) == (2, "", f"trajkit: error: {expected}\n")


def test_os_errors_name_the_path_in_plain_words(tmp_path, capsys):
    (tmp_path / "afile").write_bytes(b"")
    cases = [
        (["run", str(tmp_path / "nothere.toml")],
         f"cannot read {tmp_path / 'nothere.toml'}: no such file or folder"),
        (["run", str(tiny_scenario(tmp_path)), "--out", str(tmp_path / "afile")],
         f"--out {tmp_path / 'afile'} is a file, not a folder"),
        (["demo", "--out", str(tmp_path / "afile")],
         f"--out {tmp_path / 'afile'} is a file, not a folder"),
        (["plan", "cubic", "--q0", "0", "--qf", "1", "--duration", "1", "--csv",
          str(tmp_path / "afile" / "m.csv")],
         f"cannot write {tmp_path / 'afile' / 'm.csv'}: {tmp_path / 'afile'} is a file, "
         "not a folder"),
    ]  # fmt: skip
    for argv, expected in cases:
        status, out, err = run(capsys, *argv)
        assert (status, out, err) == (2, "", f"trajkit: error: {expected}\n"), argv
        assert "Errno" not in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["afile", "tiny.toml"]


@pytest.mark.parametrize(
    ("code", "words"),
    [
        (errno.ENOSPC, "no space left on device"),
        (errno.EIO, "input/output error (the disk or the network share failed)"),
        (errno.EACCES, "permission denied"),
        (errno.EROFS, "the file system is read-only"),
    ],
)
def test_write_failures_name_the_file_and_the_reason(code, words, tmp_path, capsys, monkeypatch):
    import trajkit.io.table

    def failing(*args, **kwargs):
        raise OSError(code, os.strerror(code))  # what write() raises: no file named

    monkeypatch.setattr(trajkit.io.table.np, "savetxt", failing)
    csv, png = tmp_path / "m.csv", tmp_path / "m.png"
    png.write_bytes(b"old plot")
    status, out, err = run(capsys, "plan", "cubic", "--q0", "0", "--qf", "1", "--duration",
                           "1", "--csv", str(csv), "--plot", str(png))  # fmt: skip
    assert (status, out) == (2, "")
    assert err == f"trajkit: error: cannot write {csv}: {words}\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.png"]
    assert png.read_bytes() == b"old plot"


def test_a_closed_pipe_ends_the_output_quietly(tmp_path):
    # Enough lines to fill the pipe, so that writing really fails once head has gone.
    goals = ",".join(str(k % 7) for k in range(5000))
    writer = subprocess.Popen(
        [sys.executable, "-c", "import sys; from trajkit.cli import main; sys.exit(main())",
         "plan", "cubic", "--q0", "0", "--qf", goals, "--duration", "1"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=tmp_path,
    )  # fmt: skip
    head = subprocess.Popen(["head", "-2"], stdin=writer.stdout, stdout=subprocess.PIPE)
    writer.stdout.close()  # head alone reads the pipe
    shown, _ = head.communicate(timeout=120)
    errors = writer.stderr.read()
    writer.stderr.close()
    assert writer.wait(timeout=120) == 141  # 128 + SIGPIPE, as for `yes | head -2`
    assert errors == b""
    assert shown.decode().splitlines() == [
        "cubic move: 5000 joint(s), duration 1 s",
        "units: positions rad, velocities rad/s, accelerations rad/s^2",
    ]


# --------------------------------------------------------------- output folders and reports


@pytest.mark.parametrize("failure", [KeyboardInterrupt, tk.InfeasibleError])
def test_a_failed_run_leaves_no_out_folder_it_created(failure, tmp_path, capsys, monkeypatch):
    import importlib

    execute = importlib.import_module("trajkit.scenario.execute")

    def stop(*args, **kwargs):
        raise failure("stop")

    monkeypatch.setattr(execute, "_write", stop)
    out = tmp_path / "new" / "deeper"
    status, _, err = run(capsys, "run", str(tiny_scenario(tmp_path)), "--out", str(out))
    assert status == (130 if failure is KeyboardInterrupt else 2)
    assert err.count("\n") == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == ["tiny.toml"]
    # A folder that existed before stays, even empty.
    out.mkdir(parents=True)
    assert run(capsys, "run", str(tiny_scenario(tmp_path)), "--out", str(out))[0] != 0
    assert out.is_dir() and list(out.iterdir()) == []


def test_an_interrupt_as_the_animation_starts_is_an_interrupt(tmp_path, capsys, monkeypatch):
    from trajkit.viz import animate

    def interrupted(self, rgba):
        raise KeyboardInterrupt

    monkeypatch.setattr(animate._GifFrames, "add", interrupted)
    out = tmp_path / "out"
    status, _, err = run(capsys, "run", str(tiny_scenario(tmp_path, animation=True)), "--out",
                         str(out))  # fmt: skip
    assert (status, err) == (130, "trajkit: interrupted; nothing was written\n")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["tiny.toml"]


def test_demo_and_run_never_replace_each_others_report(tmp_path, capsys):
    out = tmp_path / "shared"
    status, _, err = run(capsys, "run", str(tiny_scenario(tmp_path)), "--out", str(out),
                         "--report")  # fmt: skip
    assert status == 0, err
    page = (out / "index.html").read_bytes()
    status, out_text, err = run(capsys, "demo", "--out", str(out))
    assert (status, out_text) == (2, "")
    assert err == (
        f"trajkit: error: the folder {out} already holds the index.html of 'trajkit: tiny', "
        "which the demo would replace: choose another folder or remove that file\n"
    )
    assert (out / "index.html").read_bytes() == page
    assert sorted(p.name for p in out.iterdir()) == ["index.html", "tiny.csv", "tiny_summary.txt"]
    # The other way round: a demo's page is not replaced by a run's report either.
    (out / "index.html").write_text("<!DOCTYPE html><html><head><title>trajkit demo</title>")
    status, _, err = run(capsys, "run", str(tiny_scenario(tmp_path)), "--out", str(out),
                         "--report")  # fmt: skip
    assert status == 2
    assert err == (
        f"trajkit: error: --out {out} already holds the index.html of 'trajkit demo'; --report "
        "would replace it: choose another folder or remove that file\n"
    )
    # A page of someone else's without a title is not replaced by either command.
    (out / "index.html").write_text("<html><body>my notes</body></html>")
    for argv in (("run", str(tiny_scenario(tmp_path)), "--out", str(out), "--report"),
                 ("demo", "--out", str(out))):  # fmt: skip
        status, _, err = run(capsys, *argv)
        assert status == 2 and "already holds an index.html of another kind" in err, err
    assert (out / "index.html").read_text() == "<html><body>my notes</body></html>"
    # Rerunning into one's own folder replaces one's own page.
    (out / "index.html").write_text("<html><head><title>trajkit: tiny</title>")
    assert run(capsys, "run", str(tiny_scenario(tmp_path)), "--out", str(out), "--report")[0] == 0


def test_frames_naming_a_file_is_one_error_line_before_any_work(tmp_path, capsys):
    taken = tmp_path / "frames"
    taken.write_text("mine", encoding="utf-8")
    argv = ["plan", "cubic", "--q0", "0", "0", "--qf", "1", "1", "--duration", "0.2",
            "--sim", "mujoco", "--frames", str(taken)]  # fmt: skip
    status, out, err = run(capsys, *argv)
    assert (status, out) == (2, "")
    assert err == f"trajkit: error: --frames {taken} is a file, not a folder\n"  # not "exists"
    assert taken.read_text(encoding="utf-8") == "mine"
