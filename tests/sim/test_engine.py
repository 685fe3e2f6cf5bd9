"""Tests of trajkit.sim.engine: the optional MuJoCo import, compiling scenes, the
control grid and the open-loop rollout.

The rollout is checked against a plain Python loop of ``mj_step`` on a fresh
``MjData``: MuJoCo's ``rollout`` runs the same C steps, so the two agree bit for bit.
"""

from __future__ import annotations

import functools
import os
import re
import sys

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import trajkit as tk
from support import ROUNDING
from trajkit import sim
from trajkit.errors import InvalidInputError, TrajkitError
from trajkit.mobile import constant_twist
from trajkit.sim import engine
from trajkit.sim.engine import SimulationUnavailableError, compile_scene, control_grid, open_loop

mujoco = pytest.importorskip("mujoco", reason="MuJoCo is not installed: pip install 'trajkit[sim]'")

FEW = settings(max_examples=25, deadline=None)
INSTALL = re.escape('pip install "trajkit[sim]"')


# The optional dependency ----------------------------------------------------------
def test_without_mujoco_every_entry_point_names_the_install_command(monkeypatch):
    # None in sys.modules makes `import mujoco` raise ImportError, as an absent package does.
    monkeypatch.setitem(sys.modules, "mujoco", None)
    with pytest.raises(SimulationUnavailableError, match=INSTALL):
        engine.mujoco_module()
    assert sim.mujoco_available() is False
    plan = tk.cubic([0.0, 0.0], [0.1, 0.2], duration=1.0)
    with pytest.raises(SimulationUnavailableError, match=INSTALL):
        sim.run(sim.rrbot_scene(), plan)  # a fresh scene: nothing compiled yet
    with pytest.raises(SimulationUnavailableError, match=INSTALL):
        sim.run(sim.jackal_scene(), constant_twist(0.1, 0.0, 1.0))
    with pytest.raises(SimulationUnavailableError, match=INSTALL):
        compile_scene(sim.rrbot_scene().mjcf())


def test_simulation_unavailable_is_a_trajkit_error():
    assert issubclass(SimulationUnavailableError, TrajkitError)


def test_mujoco_is_available_here():
    assert sim.mujoco_available() is True
    assert engine.mujoco_module() is mujoco


# compile_scene ----------------------------------------------------------------------
@pytest.mark.parametrize(
    "xml",
    [
        "<mujoco><worldbody><body>",  # not well-formed
        "this is not MJCF",
        # Well-formed, but a moving body without mass.
        '<mujoco><worldbody><body><joint type="hinge"/></body></worldbody></mujoco>',
        '<mujoco><worldbody><geom type="sphere" size="0.1" nonsense="1"/></worldbody></mujoco>',
    ],
)
def test_compile_scene_refuses_malformed_mjcf_with_one_line_message(xml):
    with pytest.raises(InvalidInputError, match="MuJoCo cannot compile the scene") as caught:
        compile_scene(xml)
    assert "\n" not in str(caught.value)


def test_compile_scene_gives_a_model():
    model = compile_scene(sim.rrbot_scene().mjcf())
    assert isinstance(model, mujoco.MjModel)
    assert (model.nq, model.nu, model.nsensordata) == (2, 2, 6)


# control_grid -----------------------------------------------------------------------
@pytest.mark.parametrize(
    ("timestep", "end", "rate", "count", "substeps"),
    [
        (0.001, 2.0, 1000.0, 2001, 1),
        (0.001, 2.0, 500.0, 1001, 2),
        (0.001, 15.0, 10.0, 151, 100),
        (0.002, 1.0, 50.0, 51, 10),
        (0.001, 1.0005, 100.0, 102, 10),  # the grid covers the end: one more period
        (0.001, 1e-4, 1000.0, 2, 1),  # shorter than a period: still one period
    ],
)
def test_control_grid_times_are_k_over_rate(timestep, end, rate, count, substeps):
    times, steps = control_grid(timestep, end, rate)
    assert steps == substeps
    assert times.shape == (count,)
    expected = np.arange(count) / rate
    assert np.all(np.abs(times - expected) <= ROUNDING * np.maximum(1.0, expected))
    assert times[0] == 0.0
    assert times[-1] >= end - 1e-12
    assert times[-2] < end


@pytest.mark.parametrize(
    ("timestep", "rate"),
    [(0.001, 300.0), (0.001, 3000.0), (0.002, 1000.0), (0.001, 30.0), (0.003, 1000.0)],
)
def test_control_grid_refuses_periods_that_are_not_whole_steps(timestep, rate):
    with pytest.raises(InvalidInputError, match="whole number of physics steps"):
        control_grid(timestep, 1.0, rate)


@pytest.mark.parametrize("rate", [0.0, -10.0, np.nan, np.inf])
def test_control_grid_refuses_bad_rates(rate):
    with pytest.raises(InvalidInputError, match="control_rate_hz"):
        control_grid(0.001, 1.0, rate)


def test_control_grid_refuses_runs_over_1e8_steps():
    with pytest.raises(InvalidInputError, match=r"at most 1e\+08"):
        control_grid(0.001, 1.0e6, 1000.0)


# open_loop --------------------------------------------------------------------------
@functools.cache
def velocity_servo_model():
    """RRBot with VelocityServo's actuators: position and velocity loops, one activation each."""
    scene = sim.rrbot_scene()
    return compile_scene(scene.mjcf(sim.VelocityServo()))


def python_loop(model, qpos, qvel, act, controls, final):
    """Sensor rows and pre-step positions from one ``mj_step`` per control row, in Python."""
    data = mujoco.MjData(model)
    data.qpos[:], data.qvel[:], data.act[:] = qpos, qvel, act
    rows, before = [], []
    for control in controls:
        data.ctrl[:] = control
        mujoco.mj_forward(model, data)
        rows.append(data.sensordata.copy())
        before.append(data.qpos.copy())
        mujoco.mj_step(model, data)
    data.ctrl[:] = final
    mujoco.mj_forward(model, data)
    rows.append(data.sensordata.copy())
    before.append(data.qpos.copy())
    return np.array(rows), np.array(before), data


@FEW
@given(
    qpos=hnp.arrays(np.float64, 2, elements=st.floats(-np.pi, np.pi)),
    qvel=hnp.arrays(np.float64, 2, elements=st.floats(-1.0, 1.0)),
    act=hnp.arrays(np.float64, 2, elements=st.floats(-np.pi, np.pi)),
    steps=st.integers(1, 40),
    seed=st.integers(0, 2**32 - 1),
)
def test_open_loop_rows_are_the_states_before_each_step(qpos, qvel, act, steps, seed):
    model = velocity_servo_model()
    rng = np.random.default_rng(seed)
    controls = rng.uniform(-2.0, 2.0, (steps, model.nu))
    final = rng.uniform(-2.0, 2.0, model.nu)
    expected, before, reference = python_loop(model, qpos, qvel, act, controls, final)

    data = mujoco.MjData(model)
    data.qpos[:], data.qvel[:], data.act[:] = qpos, qvel, act
    mujoco.mj_forward(model, data)
    sensors = open_loop(model, data, controls, 1, final)

    assert sensors.shape == (steps + 1, model.nsensordata)
    np.testing.assert_array_equal(sensors, expected)
    # Row k's joint positions are the state before step k (the last: after the last step).
    np.testing.assert_array_equal(sensors[:, :2], before)
    np.testing.assert_array_equal(sensors[0, :2], qpos)
    # data is left at the final state, with the final control applied.
    np.testing.assert_array_equal(data.qpos, reference.qpos)
    np.testing.assert_array_equal(data.qvel, reference.qvel)
    np.testing.assert_array_equal(data.act, reference.act)
    np.testing.assert_array_equal(data.ctrl, final)
    assert data.time == reference.time


def test_open_loop_holds_each_control_for_its_substeps_in_chunks():
    # 3 substeps a period, and more steps than one rollout chunk (50,000): the rows at
    # period starts equal a plain per-step loop's, bit for bit.
    model = velocity_servo_model()
    rng = np.random.default_rng(7)
    periods, substeps = 17_000, 3
    controls = rng.uniform(-1.0, 1.0, (periods, model.nu))
    final = rng.uniform(-1.0, 1.0, model.nu)
    expected, _, _ = python_loop(model, np.zeros(2), np.zeros(2), np.zeros(2),
                                 np.repeat(controls, substeps, axis=0), final)  # fmt: skip
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    rows = open_loop(model, data, controls, substeps, final)
    assert rows.shape == (periods + 1, model.nsensordata)
    np.testing.assert_array_equal(rows, expected[::substeps])


def test_a_broken_opengl_setting_only_costs_the_frames(tmp_path):
    # Simulation needs no OpenGL: a backend that fails to load is reported when frames
    # are asked for, and the simulation itself still runs (issue 16).
    import subprocess

    script = (
        "import trajkit as tk\n"
        "from trajkit import sim\n"
        "from trajkit.sim import render\n"
        "scene = sim.rrbot_scene()\n"
        "log = sim.run(scene, tk.cubic([0, 0], [0.1, 0.1], 0.1))\n"
        "print(log.t.size)\n"
        "try:\n"
        "    render.frames(scene, log, [0.0])\n"
        "except sim.SimulationUnavailableError as error:\n"
        "    print('unavailable:', error)\n"
    )
    env = {**os.environ, "MUJOCO_GL": "bogus"}
    result = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                            env=env, timeout=120, cwd=tmp_path)  # fmt: skip
    assert result.returncode == 0, result.stderr[-2000:]
    size, message = result.stdout.strip().split("\n")
    assert size == "101"
    assert message.startswith("unavailable: off-screen rendering needs an OpenGL backend")
    assert "MUJOCO_GL='bogus' failed to load when MuJoCo was imported" in message
    env["MUJOCO_GL"] = "disable"
    script = "import trajkit as tk\nfrom trajkit import sim\n"
    script += "print(sim.run(sim.rrbot_scene(), tk.cubic([0, 0], [0.1, 0.1], 0.1)).t.size)\n"
    result = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                            env=env, timeout=120, cwd=tmp_path)  # fmt: skip
    assert result.stdout.strip() == "101", result.stderr[-2000:]


@pytest.mark.parametrize("platform", ["darwin", "win32"])
def test_the_opengl_backend_is_chosen_on_linux_only(platform, monkeypatch):
    from trajkit.sim.engine import choose_gl_backend

    monkeypatch.delenv("MUJOCO_GL", raising=False)
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.setattr(sys, "platform", platform)
    choose_gl_backend()
    assert "MUJOCO_GL" not in os.environ
