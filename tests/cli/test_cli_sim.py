"""The --sim options of ``trajkit plan`` and ``trajkit mobile``: MuJoCo runs, outputs, errors."""

from __future__ import annotations

import sys

import numpy as np
import pytest

from trajkit.cli import main
from trajkit.errors import InvalidInputError

pytest.importorskip("mujoco", reason="MuJoCo is not installed: pip install 'trajkit[sim]'")

CUBIC = ["plan", "cubic", "--q0", "0", "0", "--qf", "67", "-45", "--vmax", "9", "11", "--deg"]


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    status = main(list(argv))
    captured = capsys.readouterr()
    return status, captured.out, captured.err


def test_plan_on_the_simulated_rrbot_writes_log_plot_and_frames(tmp_path, capsys):
    csv, plot, frames = tmp_path / "log.csv", tmp_path / "tracking.png", tmp_path / "frames"
    status, out, err = run(
        capsys, *CUBIC, "--sim", "mujoco", "--controller", "computed_torque",
        "--sim-csv", str(csv), "--sim-plot", str(plot), "--frames", str(frames),
    )  # fmt: skip
    assert status == 0, err
    assert "simulated on RRBot in MuJoCo, computed torque: 11168 control steps" in out
    assert "q1: RMS error" in out and "q2: RMS error" in out
    table = np.loadtxt(csv, delimiter=",", skiprows=1)
    assert table.shape == (11168, 13)  # t, then 2 each: q, q_d, q̇, q̇_d, q̈_d, efforts
    assert np.abs(table[:, 3:5] - table[:, 1:3]).max() < np.radians(2e-4)  # measured 1.9e-6 rad
    assert plot.stat().st_size > 10_000
    if "no frames rendered" in err:
        assert not frames.exists() or not list(frames.iterdir())
    else:
        assert sorted(p.name for p in frames.iterdir()) == [f"frame_{i}.png" for i in range(4)]


@pytest.mark.parametrize("controller", ["position", "velocity", "pd_feedforward"])
def test_plan_each_arm_controller_and_rate(controller, capsys):
    status, out, err = run(
        capsys, *CUBIC, "--sim", "mujoco", "--controller", controller, "--control-rate-hz", "500"
    )
    assert status == 0, err
    assert "5585 control steps over 11.168 s" in out


def test_plan_on_the_ur5(capsys):
    status, out, err = run(
        capsys, "plan", "quintic", "--q0", "0", "--qf", "0.2,-0.3,0.4,0.1,0.2,0.3",
        "--duration", "1", "--sim", "mujoco", "--robot", "ur5",
    )  # fmt: skip
    assert status == 0, err
    assert "simulated on UR5 in MuJoCo, position servo" in out
    assert out.count("RMS error") == 6


def test_frames_without_opengl_note_and_write_everything_else(tmp_path, capsys, monkeypatch):
    from trajkit.sim import render
    from trajkit.sim.engine import SimulationUnavailableError

    def no_gl(*args, **kwargs):
        raise SimulationUnavailableError(f"{render.GL_HINT}; MuJoCo said: no GL")

    monkeypatch.setattr(render, "_renderer", no_gl)
    plot, frames = tmp_path / "tracking.png", tmp_path / "frames"
    status, out, err = run(
        capsys, *CUBIC, "--sim", "mujoco", "--sim-plot", str(plot), "--frames", str(frames)
    )
    assert status == 0
    assert err.startswith("trajkit: note: no frames rendered: off-screen rendering needs an ")
    assert err.count("\n") == 1
    assert plot.exists() and not frames.exists()
    assert f"wrote {plot}" in out


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        ([*CUBIC, "--sim-plot", "x.png"], "--sim-plot need(s) --sim mujoco"),
        ([*CUBIC, "--frames", "f", "--control-rate-hz", "100"],
         "--control-rate-hz, --frames need(s) --sim mujoco"),
        ([*CUBIC, "--sim", "mujoco", "--robot", "ur5"],
         "--robot ur5 has 6 joints but the move has 2"),
        ([*CUBIC, "--sim", "mujoco", "--control-rate-hz", "300"],
         "must be a whole number of physics steps of 0.001 s"),
        ([*CUBIC, "--sim", "mujoco", "--control-rate-hz", "-5"], "control_rate_hz must be > 0"),
        ([*CUBIC, "--sim", "mujoco", "--sim-plot", "x.txt"], "--sim-plot must end in .png"),
        ([*CUBIC, "--sim", "bullet"], "invalid choice: 'bullet'"),
        (["mobile", "figure8", "--robot", "unicycle", "--sim", "mujoco"],
         "--sim mujoco needs a robot with wheels, not --robot unicycle"),
        (["mobile", "twist", "10", "0.1", "10", "1", "--frames", "f"],
         "--frames need(s) --sim mujoco"),
        (["mobile", "twist", "7", "0.1", "10", "1", "--sim", "mujoco"],
         "must be a whole number of physics steps"),
    ],
)  # fmt: skip
def test_sim_errors_are_one_line_with_status_2(argv, message, capsys):
    status, out, err = run(capsys, *argv)
    assert status == 2
    assert message in err
    assert err.count("\n") == 1 and err.startswith("trajkit: error: ")
    assert out == ""


def test_failed_simulation_writes_no_file(tmp_path, capsys):
    csv = tmp_path / "move.csv"
    status, _, err = run(
        capsys, *CUBIC, "--csv", str(csv), "--sim", "mujoco", "--control-rate-hz", "300"
    )
    assert status == 2 and "whole number" in err
    assert list(tmp_path.iterdir()) == []


def test_without_mujoco_the_error_says_how_to_install(capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "mujoco", None)
    status, out, err = run(capsys, *CUBIC, "--sim", "mujoco")
    assert status == 2 and out == ""
    assert 'install it with: pip install "trajkit[sim]"' in err
    assert err.count("\n") == 1


def test_mobile_twist_in_mujoco_matches_the_arc(tmp_path, capsys):
    csv, path_plot = tmp_path / "run.csv", tmp_path / "path.png"
    status, out, err = run(
        capsys, "mobile", "twist", "10", "0.1", "10", "15", "--sim", "mujoco",
        "--csv", str(csv), "--path-plot", str(path_plot),
    )  # fmt: skip
    assert status == 0, err
    assert "simulated in MuJoCo at 10 Hz: feedforward" in out
    table = np.loadtxt(csv, delimiter=",", skiprows=1)
    assert table.shape == (151, 24)
    # Ground truth against the exact arc (R sin θ, R (1 − cos θ)): measured 3.7 mm.
    radius, theta = 0.1 / np.radians(10.0), np.radians(150.0)
    arc_end = np.array([radius * np.sin(theta), radius * (1.0 - np.cos(theta))])
    assert np.hypot(*(table[-1, 4:6] - arc_end)) < 0.006
    # The kinematic prediction of the same commands is the exact arc.
    np.testing.assert_allclose(table[-1, 10:12], arc_end, atol=1e-12)
    assert path_plot.stat().st_size > 10_000


@pytest.mark.parametrize("command", [
    ["goto", "2", "1", "--vmax", "0.5", "--wmax-deg", "60", "--blend-ratio", "0.1"],
    ["figure8", "--controller", "kanayama", "--period", "30"],
])  # fmt: skip
def test_mobile_plans_in_mujoco_at_the_default_rate(command, capsys):
    status, out, err = run(capsys, "mobile", *command, "--sim", "mujoco")
    assert status == 0, err
    assert "simulated in MuJoCo at 50 Hz" in out
    assert "odometry drift" in out


def test_check_sim_options_accepts_mujoco_with_outputs():
    import argparse

    from trajkit.cli.sim import check_sim_options

    args = argparse.Namespace(sim="mujoco", control_rate_hz=100.0, frames="f", sim_plot="p.png",
                              sim_csv="c.csv")  # fmt: skip
    check_sim_options(args)  # no error
    args.sim = "kinematic"
    with pytest.raises(
        InvalidInputError, match="--control-rate-hz, --frames, --sim-plot, --sim-csv"
    ):
        check_sim_options(args)


def test_failed_mobile_write_leaves_no_frames_folder_and_prints_nothing(tmp_path, capsys):
    frames = tmp_path / "frames"
    status, out, err = run(
        capsys, "mobile", "twist", "10", "0.1", "10", "2", "--sim", "mujoco",
        "--frames", str(frames), "--csv", str(tmp_path / "missing" / "run.csv"),
    )  # fmt: skip
    assert status == 2 and out == ""
    assert "does not exist" in err
    assert list(tmp_path.iterdir()) == []


def test_ur5_on_the_command_line_has_its_real_link_masses(capsys):
    status, out, err = run(
        capsys, "plan", "quintic", "--q0", "0", "--qf", "0.2,-0.3,0.4,0.1,0.2,0.3",
        "--duration", "1", "--sim", "mujoco", "--robot", "ur5", "--controller", "pd_feedforward",
    )  # fmt: skip
    assert status == 0, err
    # Peak shoulder torque: the 8.4 kg upper arm and the rest held against gravity.
    shoulder = next(line for line in out.splitlines() if line.startswith("  shoulder_lift"))
    assert float(shoulder.split("peak effort ")[1].split()[0]) > 40.0


def test_a_gl_backend_that_fails_to_load_only_skips_the_frames(tmp_path):
    # MuJoCo loads MUJOCO_GL's library when it is imported, so this needs a fresh process.
    import os
    import subprocess

    ctypes_util = __import__("ctypes.util").util
    if ctypes_util.find_library("OSMesa") is not None:
        pytest.skip("OSMesa is installed here: MUJOCO_GL=osmesa would work")
    env = {**os.environ, "MUJOCO_GL": "osmesa"}
    env.pop("PYOPENGL_PLATFORM", None)
    result = subprocess.run(
        [sys.executable, "-c", "import sys; from trajkit.cli import main; sys.exit(main())",
         "plan", "cubic", "--q0", "0", "0", "--qf", "1", "1", "--duration", "0.2", "--sim",
         "mujoco", "--frames", "frames", "--sim-csv", "sim.csv"],
        capture_output=True, text=True, cwd=tmp_path, env=env, timeout=300,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    assert result.stderr.count("\n") == 1
    assert result.stderr.startswith("trajkit: note: no frames rendered: off-screen rendering ")
    assert "MUJOCO_GL='osmesa' failed to load when MuJoCo was imported" in result.stderr
    assert "wrote sim.csv" in result.stdout
    assert sorted(p.name for p in tmp_path.iterdir()) == ["sim.csv"]  # no frames folder
