"""``trajkit demo``: every shipped example scenario, and the coursework's worked examples.

The demo runs each example scenario (``examples/*.toml``) exactly as ``trajkit run``
does. The worked examples are studies of those scenarios: they read the robot, the
move and the limits from the scenario and its result, and add what a scenario file
cannot say (the hand solutions checked, sync modes and controllers compared). No
example is written twice.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

import trajkit as tk
from trajkit import mobile
from trajkit.errors import InvalidInputError
from trajkit.io.atomic import StagedFiles, staged_files
from trajkit.mobile import MobileTrajectory, SimulationLog
from trajkit.scenario import Outcome, Scenario, robot_of
from trajkit.taskspace import Line, time_optimal, timed

__all__ = ["STUDIES", "run"]

Log = Callable[[str], None]
Study = Callable[[Scenario, Outcome, Path, StagedFiles, Log], None]
#: The title of the demo's index.html, by which a rerun recognises its own page.
DEMO_TITLE = "trajkit demo"


def _arm_limits(scenario: Scenario) -> tk.Limits:
    limits = scenario.limits
    return tk.Limits(velocity=limits.get("vmax"), acceleration=limits.get("amax"),
                     jerk=limits.get("jmax"))  # fmt: skip


def hand_durations(scenario: Scenario, outcome: Outcome, out: Path, stage: StagedFiles,
                   log: Log) -> None:  # fmt: skip
    """Seed 000 §3.1: the cubic's exact minimum duration, and the hand solutions checked."""
    plan, task, limits = outcome.plan, scenario.task, _arm_limits(scenario)
    own = plan.info["minimum_durations"]
    log(
        f"seed 000 cubic: exact common minimum duration {plan.duration:.12g} s "
        f"(joint 1 alone {own[0]:.12g} s, joint 2 alone {own[1]:.12g} s)"
    )
    for guess in (11.0, 6.0):
        report = tk.cubic(task["q0"], task["qf"], guess).check(limits)
        worst = ", ".join(
            f"joint {v.joint + 1} peaks at {np.degrees(abs(v.value)):.4g} °/s > "
            f"{np.degrees(abs(v.bound)):.4g} °/s"
            for v in report.violations
        )
        log(f"  the hand solution's {guess:g} s breaks the velocity limit: {worst}")


def sync_modes(scenario: Scenario, outcome: Outcome, out: Path, stage: StagedFiles,
               log: Log) -> None:  # fmt: skip
    """Seed 001: the six-joint move as trapezoid and S-curve, phase and time synchronized.

    Each continuous and on the scenario's controller period.
    """
    task, limits = scenario.task, scenario.limits
    q0, qf, vmax, amax = task["q0"], task["qf"], limits["vmax"], limits["amax"]
    jmax = 4.0 * amax  # the coursework gives no jerk limit: a quarter second to full acceleration
    names = [f"joint {j + 1}" for j in range(q0.size)]
    period = scenario.period
    for label, kwargs in (
        ("continuous", {}),
        (f"on {period * 1e3:g} ms ticks", {"period": period}),
    ):
        for sync in ("phase", "time"):
            for profile in ("trapezoid", "scurve"):
                if profile == "trapezoid":
                    trajectory = tk.trapezoidal(q0, qf, vmax, amax, sync=sync, **kwargs)
                    bounds = tk.Limits(velocity=vmax, acceleration=amax)
                else:
                    trajectory = tk.scurve(q0, qf, vmax, amax, jmax, sync=sync, **kwargs)
                    bounds = tk.Limits(velocity=vmax, acceleration=amax, jerk=jmax)
                report = trajectory.check(bounds)
                log(
                    f"seed 001 {profile}, sync={sync}, {label}: duration "
                    f"{trajectory.duration:.12g} s, limits {'OK' if report.ok else 'VIOLATED'}"
                )
                v = np.degrees(trajectory.info["peak_velocity"])
                log("  peak velocity [deg/s]: " + ", ".join(f"{x:.6g}" for x in v))
                if profile == "trapezoid":
                    a = np.degrees([acc[0] for acc in trajectory.info["accelerations"]])
                    log("  acceleration [deg/s^2]: " + ", ".join(f"{x:.6g}" for x in a))
                stem = f"seed001_{profile}_{sync}" + ("_dt" if kwargs else "")
                figure = tk.plot.profiles(
                    trajectory, bounds, degrees=True, names=names,
                    orders=(0, 1, 2, 3) if profile == "scurve" else (0, 1, 2),
                    title=f"Seed 001: {profile}, sync={sync}, {label}, "
                    f"{trajectory.duration:.6g} s",
                )  # fmt: skip
                tk.plot.save(figure, stage.path(out / f"{stem}.png"))


def line_deviation(scenario: Scenario, outcome: Outcome, out: Path, stage: StagedFiles,
                   log: Log) -> None:  # fmt: skip
    """Seed 003: how closely the arm's tool follows the line between the IK samples."""
    robot, plan, task = robot_of(scenario), outcome.plan, scenario.task
    line = Line(task["start"], task["end"])
    times = np.linspace(0.0, plan.duration, 10001)
    tool = robot.fk(plan.position(times))[:, :3, 3]
    motion = timed(line, task["law"], duration=task["duration"])
    deviation = float(np.abs(tool - motion.state(times).position).max())
    peak = np.degrees(plan.extrema(1).peak)
    log(
        f"seed 003 {robot.name}, {task['law']} line in {task['duration']:g} s: FK of the "
        f"joint trajectory within {deviation:.2g} m of the line; peak rates "
        f"{peak.round(4).tolist()} deg/s"
    )


def time_optimal_line(scenario: Scenario, outcome: Outcome, out: Path, stage: StagedFiles,
                      log: Log) -> None:  # fmt: skip
    """Seed 003's line again, as fast as joint limits of 1 rad/s and 2 rad/s² allow."""
    robot, task = robot_of(scenario), scenario.task
    line = Line(task["start"], task["end"])
    stem = "seed003_time_optimal"
    bounds = "|q'| <= 1 rad/s, |q''| <= 2 rad/s^2"
    for name, limits, said in (
        ("", tk.Limits(velocity=1.0, acceleration=2.0), bounds),
        ("_jerk_limited", tk.Limits(velocity=1.0, acceleration=2.0, jerk=10.0),
         bounds + ", jerk <= 10 rad/s^3"),
    ):  # fmt: skip
        move = time_optimal(robot, line, limits, grid=1000)
        peaks = [move.trajectory.extrema(order).peak.max() for order in (1, 2)]
        log(
            f"seed 003 time-optimal{name.replace('_', ' ')}: the same line in "
            f"{move.duration:.4f} s (instead of {task['duration']:g} s) under {said}: peaks "
            f"{peaks[0]:.6f} rad/s, {peaks[1]:.6f} rad/s^2, limits "
            f"{'kept' if move.trajectory.check(limits).ok else 'BROKEN'} (exact check); tool "
            f"within {move.path_error:.2g} m of the line"
        )
        title = f"Seed 003, time-optimal{name.replace('_', ' ')}"
        figure = tk.plot.profiles(move.trajectory, limits, orders=(0, 1, 2, 3),
                                  names=robot.names, title=title)  # fmt: skip
        tk.plot.save(figure, stage.path(out / f"{stem}{name}_joints.png"))
        move.trajectory.sample(0.01).to_csv(stage.path(out / f"{stem}{name}_joints.csv"))


def _mobile_outputs(
    out: Path, stage: StagedFiles, stem: str, data: MobileTrajectory | SimulationLog, title: str
) -> None:
    """Time panels and the XY path of a plan or a simulated run, and its CSV."""
    tk.plot.save(tk.plot.mobile(data, title=title), stage.path(out / f"{stem}.png"))
    tk.plot.save(tk.plot.mobile_path(data, title=title), stage.path(out / f"{stem}_path.png"))
    if isinstance(data, SimulationLog):
        data.to_csv(stage.path(out / f"{stem}.csv"))
    else:
        data.to_csv(stage.path(out / f"{stem}.csv"), 0.01)


def twist_arcs(scenario: Scenario, outcome: Outcome, out: Path, stage: StagedFiles,
               log: Log) -> None:  # fmt: skip
    """Seed 000 §2.0 (move_jackal): the scenario's twist, and a spin in place beside it."""
    task, model = scenario.task, robot_of(scenario)
    for name, v, omega, duration in (("the scenario's arc", task["v"], task["omega"],
                                      task["duration"]),
                                     ("a spin", 0.0, np.radians(-15.0), 10.0)):  # fmt: skip
        plan = mobile.constant_twist(v, omega, duration, rate_hz=task["rate_hz"], model=model)
        x, y, theta = plan.end_pose
        log(
            f"seed 000 Jackal twist, {name}: v = {v:g} m/s, ω = {np.degrees(omega):g}°/s for "
            f"{duration:g} s ({plan.info['command_count']} commands at {task['rate_hz']:g} Hz): "
            f"ends at ({x:.6g} m, {y:.6g} m, {theta:.6g} rad), arc radius "
            f"{plan.info['radius']:.6g} m; {'within' if plan.check().ok else 'BEYOND'} the "
            "Jackal's limits"
        )


def goto_phases(scenario: Scenario, outcome: Outcome, out: Path, stage: StagedFiles,
                log: Log) -> None:  # fmt: skip
    """Seed 000 §2.1: each phase's minimum duration against the hand values; commands held."""
    plan = outcome.plan
    for name, duration, hand in zip(
        plan.info["phases"], plan.info["phase_durations"], (1.2, 32.0, 2.02), strict=True
    ):
        verdict = "breaks" if hand < duration * (1 - 1e-12) else "keeps"
        log(
            f"seed 000 Jackal, {name}: minimum duration {duration:.9g} s; the hand value "
            f"{hand:g} s {verdict} the limit"
        )
    run = mobile.simulate(plan, sample_step=0.01, command_rate_hz=10.0)
    log(f"  the plan's twists sent at 10 Hz and held (zero-order hold): {run.summary()}")
    _mobile_outputs(out, stage, "seed000_jackal_goto_10hz", run, "Seed 000: held at 10 Hz")


def figure_eight_controllers(scenario: Scenario, outcome: Outcome, out: Path,
                             stage: StagedFiles, log: Log) -> None:  # fmt: skip
    """Seed 002: the figure eight tracked by four controllers from 0.5 m and 30° off."""
    plan = outcome.plan
    start = plan.start_pose + np.array([0.5 * np.cos(1.0), 0.5 * np.sin(1.0), np.radians(30.0)])
    log("seed 002 figure eight, tracking from 0.5 m and 30° off the start, RK4 at 200 Hz:")
    controllers = (
        mobile.Feedforward(), mobile.Kanayama(), mobile.FeedbackLinearization(),
        mobile.PurePursuit(),
    )  # fmt: skip
    for controller in controllers:
        run = mobile.simulate(plan, controller, sample_step=0.005, initial_pose=start)
        log(
            f"    {run.summary()}; after 10 s at most {run.error_after(10.0):.3g} m "
            f"({run.error_after(10.0, along_path=True):.3g} m from the path)"
        )
        stem = "seed002_figure8_" + controller.name.replace(" ", "_")
        _mobile_outputs(out, stage, stem, run, f"Seed 002: figure eight, {controller.name}")
    exact = mobile.simulate(plan, sample_step=0.001)
    log(f"  feedforward from the right pose, RK4 at 1 kHz: max error {exact.max_error:.2g} m")


def _simulation_ready(log: Log) -> bool:
    from trajkit.sim import mujoco_available
    from trajkit.sim.engine import INSTALL_HINT

    if not mujoco_available():
        log(f"  (MuJoCo is not installed, so this runs without physics: {INSTALL_HINT})")
    return mujoco_available()


def _frames(scene: object, run: object, stem: Path, stage: StagedFiles, log: Log) -> None:
    """Three rendered frames (start, middle, end), or a note where no OpenGL works."""
    from trajkit import sim
    from trajkit.sim.render import write_png

    try:
        images = sim.frames(scene, run, np.linspace(run.t[0], run.t[-1], 3))  # type: ignore[arg-type]
    except sim.SimulationUnavailableError as exc:
        log(f"  no frames rendered: {exc}")
        return
    for index, image in enumerate(images):
        write_png(image, stage.path(stem.with_name(f"{stem.name}_frame{index}.png")))


def rrbot_controllers(scenario: Scenario, outcome: Outcome, out: Path, stage: StagedFiles,
                      log: Log) -> None:  # fmt: skip
    """Seed 000 §3.1 executed: the scenario's cubic move on the simulated RRBot, five ways."""
    log("seed 000 RRBot cubic move in MuJoCo (1 kg links, damping 0.7, 1 kHz control):")
    if not _simulation_ready(log):
        return
    from trajkit import sim

    plan = outcome.plan
    cases = (
        ("position servo, Gazebo's gains (p 100, d 10), no gravity compensation",
         sim.rrbot_scene(gravity_compensation=False), "position"),
        ("position servo with gravity compensation", sim.rrbot_scene(), "position"),
        ("velocity servo", sim.rrbot_scene(), "velocity"),
        ("PD + inverse-dynamics feed-forward", sim.rrbot_scene(), "pd_feedforward"),
        ("computed torque (ω = 30 rad/s)", sim.rrbot_scene(), "computed_torque"),
    )  # fmt: skip
    for label, scene, controller in cases:
        run = sim.run(scene, plan, controller=controller)
        error, effort = np.degrees(run.max_error), run.peak_effort
        log(
            f"  {label}: max error {error[0]:.3g}° / {error[1]:.3g}°, final "
            f"{abs(np.degrees(run.final_error[0])):.3g}° / "
            f"{abs(np.degrees(run.final_error[1])):.3g}°, peak torque {effort[0]:.3g} / "
            f"{effort[1]:.3g} N·m"
        )
        if controller == "position" and scene.gravity_compensation:
            stem = out / "seed000_rrbot_mujoco"
            figure = tk.plot.tracking(run, title="Seed 000: RRBot cubic move in MuJoCo, " + label)
            tk.plot.save(figure, stage.path(stem.with_suffix(".png")))
            run.to_csv(stage.path(stem.with_suffix(".csv")))
            _frames(scene, run, stem, stage, log)


def jackal_controllers(scenario: Scenario, outcome: Outcome, out: Path, stage: StagedFiles,
                       log: Log) -> None:  # fmt: skip
    """Seed 000 §2.1 executed: the scenario's rotate–translate–rotate on a simulated Jackal.

    By two controllers and at two command rates.
    """
    log("seed 000 Jackal rotate–translate–rotate in MuJoCo (17 kg, wheel velocity servos):")
    if not _simulation_ready(log):
        return
    from trajkit import sim

    plan = outcome.plan
    scene = sim.jackal_scene()
    for controller, rate in ((mobile.Feedforward(), 10.0), (mobile.Feedforward(), 50.0),
                             (mobile.Kanayama(), 50.0)):  # fmt: skip
        run = sim.run(scene, plan, control_rate_hz=rate, controller=controller)
        x, y, theta = run.actual[-1]
        log(
            f"  {controller.name} at {rate:g} Hz: ends at ({x:.4f} m, {y:.4f} m, {theta:.4f} "
            f"rad), {run.final_position_error * 1000:.3g} mm from the goal; max error "
            f"{run.max_error * 1000:.3g} mm; odometry drift {run.odometry_drift * 1000:.3g} mm; "
            f"peak wheel torque {run.peak_wheel_torque:.3g} N·m"
        )
        if controller.name == "kanayama":
            stem = "seed000_jackal_goto_mujoco"
            _mobile_outputs(out, stage, stem, run, "Seed 000: rotate, drive, rotate in MuJoCo")
            _frames(scene, run, out / stem, stage, log)


#: The worked examples, by the shipped scenario each one studies (in this order).
STUDIES: dict[str, tuple[Study, ...]] = {
    "seed000_rrbot_cubic": (hand_durations, rrbot_controllers),
    "seed001_six_joint_trapezoid": (sync_modes,),
    "seed003_arm3_line": (line_deviation, time_optimal_line),
    "seed000_jackal_twist": (twist_arcs,),
    "seed000_jackal_goto": (goto_phases, jackal_controllers),
    "seed002_figure8": (figure_eight_controllers,),
}


def run(out: str | Path, log: Log = print) -> list[Path]:
    """Run every example scenario and its worked examples into ``out``; return the files.

    Each scenario's files are written all together or not at all, and so are the
    worked examples' (``summary.txt`` has what they computed). ``index.html``
    gathers the scenarios' results.

    Raises
    ------
    InvalidInputError
        If ``out`` holds an ``index.html`` that another command wrote (``trajkit run
        --report``): the demo refuses to replace it.
    """
    from trajkit import scenario
    from trajkit.viz.report import page_title, write_report

    folder = Path(out)
    index_page = folder / "index.html"
    title = page_title(index_page)
    if title is not None and title != DEMO_TITLE:
        # Another run's report (trajkit run --report): replacing it silently loses it.
        page = f"the index.html of {title!r}" if title else "an index.html of another kind"
        raise InvalidInputError(
            f"the folder {folder} already holds {page}, which the demo would replace: "
            "choose another folder or remove that file"
        )
    folder.mkdir(parents=True, exist_ok=True)
    lines: list[str] = []

    def record(line: str) -> None:
        lines.append(line)
        log(line)

    written: list[Path] = []
    entries: list[Any] = []
    files = scenario.examples()
    with staged_files() as stage:
        for index, path in enumerate(files, start=1):
            spec = scenario.load(path)
            if not _runnable(spec, log):
                continue
            done = round(20 * index / len(files))
            log(f"[{'#' * done}{'.' * (20 - done)}] {index}/{len(files)} scenario {spec.name}")
            outcome = scenario.execute(spec, folder / "scenarios", log=lambda line: None)
            for line in outcome.lines[1:]:
                log(line)
            entries.append(scenario.report_entry(spec, outcome))
            written += outcome.files
            for study in STUDIES.get(spec.name, ()):
                study(spec, outcome, folder, stage, record)
        summary = stage.path(folder / "summary.txt")
        summary.write_text("\n".join(lines) + "\n", encoding="utf-8")
    written += stage.targets
    written.append(write_report(
        index_page, entries, title=DEMO_TITLE,
        intro="Every example scenario that ships with trajkit, run by trajkit demo. The "
        "worked examples of the coursework are in summary.txt and the files beside it.",
    ))  # fmt: skip
    for path in written:
        log(f"wrote {path}")
    log(f"open {index_page} to see the scenarios; summary.txt has the worked examples")
    return written


def _runnable(spec: object, log: Log) -> bool:
    """Whether this machine has what the scenario needs; if not, say what to install."""
    from trajkit.errors import TrajkitError
    from trajkit.scenario.execute import preflight

    try:
        preflight(spec)  # type: ignore[arg-type]
    except TrajkitError as exc:
        log(f"  skipping {spec.name}: {exc}")  # type: ignore[attr-defined]
        return False
    return True
