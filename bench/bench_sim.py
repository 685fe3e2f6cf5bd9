"""What trajkit's simulation loop costs on top of MuJoCo's own stepping.

Run: python bench/bench_sim.py [--repeats 15]

For every case, the same compiled MuJoCo model takes the same number of physics
steps twice in one process:

* **MuJoCo alone** — ``mj_step(model, data, nstep=N)``: the physics in one C call,
  no Python per step, the floor any wrapper is measured against. For computed
  torque, whose law needs MuJoCo's inverse dynamics at the measured state once
  per control period, the floor also makes those ``mj_inverse`` calls, in the
  tightest Python loop.
* **plain loop** — what one writes by hand around MuJoCo: per control period, set
  the controls from a precomputed array, ``mj_step`` the period, copy ``qpos``
  (for computed torque, also one ``mj_inverse`` per period).
* **trajkit** — ``trajkit.sim.run(scene, plan, ...)``: evaluating the plan at every
  control time, the controller, the stepping and the log.

Overhead = trajkit / MuJoCo alone - 1 (and against the plain loop), medians over
repetitions (the scene is compiled once, before timing, as ``run`` caches it).
"""

from __future__ import annotations

import argparse

import mujoco
import numpy as np

import trajkit as tk
from timing import median_seconds
from trajkit import mobile, sim
from trajkit.kinematics import UR5


def arm_case(label, scene, plan, controller, rate_hz):
    run = lambda: sim.run(scene, plan, controller=controller, control_rate_hz=rate_hz)  # noqa: E731
    log = run()  # compiles and caches the model
    model = scene.compiled(controller)
    data = mujoco.MjData(model)
    steps = (log.t.size - 1) * round(1.0 / (rate_hz * scene.timestep))
    periods = log.t.size

    substeps = steps // max(periods - 1, 1)
    if controller == "computed_torque":
        # Its law needs MuJoCo's inverse dynamics once per control period: that is
        # MuJoCo's own work too, timed here in the tightest Python loop.
        def alone() -> None:
            mujoco.mj_resetData(model, data)
            for _ in range(periods - 1):
                mujoco.mj_inverse(model, data)
                mujoco.mj_step(model, data, substeps)
    else:

        def alone() -> None:
            mujoco.mj_resetData(model, data)
            mujoco.mj_step(model, data, steps)

    plain = _plain_loop(model, periods, substeps, inverse=controller == "computed_torque")
    return label, run, alone, plain, steps


def _plain_loop(model, periods: int, substeps: int, *, inverse: bool = False):
    data = mujoco.MjData(model)
    controls = np.random.default_rng(0).uniform(-0.01, 0.01, (periods, model.nu))
    log = np.empty((periods, model.nq))

    def loop() -> None:
        mujoco.mj_resetData(model, data)
        for k in range(periods):
            if inverse:
                mujoco.mj_inverse(model, data)
            data.ctrl[:] = controls[k]
            mujoco.mj_step(model, data, substeps)
            log[k] = data.qpos

    return loop


def mobile_case(label, scene, plan, controller, rate_hz):
    run = lambda: sim.run(scene, plan, controller=controller, control_rate_hz=rate_hz)  # noqa: E731
    log = run()
    model = scene.compiled()
    data = mujoco.MjData(model)
    steps = (log.t.size - 1) * round(1.0 / (rate_hz * scene.timestep))

    def alone() -> None:
        mujoco.mj_resetData(model, data)
        data.ctrl[:] = 1.0
        mujoco.mj_step(model, data, steps)

    substeps = round(1.0 / (rate_hz * scene.timestep))
    return label, run, alone, _plain_loop(model, log.t.size - 1, substeps), steps


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=15)
    args = parser.parse_args()

    cubic = tk.cubic(np.radians([0, 0]), np.radians([67, -45]), vmax=np.radians([9, 11]))
    rrbot = sim.rrbot_scene()
    ur5_plan = tk.scurve(np.zeros(6), np.array([0.8, -0.6, 1.0, -0.5, 0.7, 1.2]), 1.0, 2.0, 10.0)
    ur5 = sim.arm_scene(UR5())
    goto = mobile.rotate_translate_rotate(
        (5.0, 3.0, 1.5), vmax=0.2, wmax=np.radians(30.0), blend_ratio=0.1, model=mobile.jackal()
    )
    jackal = sim.jackal_scene()
    cases = [
        arm_case("RRBot cubic, position servo, 1 kHz", rrbot, cubic, "position", 1000.0),
        arm_case("RRBot cubic, velocity servo, 1 kHz", rrbot, cubic, "velocity", 1000.0),
        arm_case("RRBot cubic, PD + feed-forward, 1 kHz", rrbot, cubic, "pd_feedforward", 1000.0),
        arm_case("RRBot cubic, computed torque, 1 kHz", rrbot, cubic, "computed_torque", 1000.0),
        arm_case("RRBot cubic, computed torque, 250 Hz", rrbot, cubic, "computed_torque", 250.0),
        arm_case("UR5 S-curve, position servo, 1 kHz", ur5, ur5_plan, "position", 1000.0),
        arm_case("UR5 S-curve, computed torque, 1 kHz", ur5, ur5_plan, "computed_torque", 1000.0),
        mobile_case("Jackal goto, feedforward, 10 Hz", jackal, goto, mobile.Feedforward(), 10.0),
        mobile_case("Jackal goto, feedforward, 50 Hz", jackal, goto, mobile.Feedforward(), 50.0),
        mobile_case("Jackal goto, Kanayama, 50 Hz", jackal, goto, mobile.Kanayama(), 50.0),
    ]
    print(
        f"{'case':<40} {'steps':>6} {'MuJoCo':>8} {'plain':>8} {'trajkit':>8} "
        f"{'overhead vs MuJoCo':>19} {'vs plain':>9}"
    )
    for label, run, alone, plain, steps in cases:
        floor = median_seconds(alone, args.repeats)
        hand = median_seconds(plain, args.repeats)
        ours = median_seconds(run, args.repeats)
        print(
            f"{label:<40} {steps:>6} {floor * 1e3:>6.1f}ms {hand * 1e3:>6.1f}ms "
            f"{ours * 1e3:>6.1f}ms {(ours / floor - 1) * 100:>18.1f}% "
            f"{(ours / hand - 1) * 100:>8.1f}%"
        )


if __name__ == "__main__":
    main()
