"""``trajkit demo``: the coursework's worked examples, computed exactly, with outputs.

Each example is one function that plans, checks, and writes its plots and CSVs;
the demo runs them all and writes every file or none.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np

import trajkit as tk
from trajkit import mobile
from trajkit.errors import InvalidInputError
from trajkit.io.atomic import StagedFiles, staged_files
from trajkit.kinematics import Planar2R, SerialChain, Spatial3R
from trajkit.mobile import MobileTrajectory, SimulationLog
from trajkit.taskspace import (
    Ellipse,
    JointSpacePlan,
    Line,
    TaskTrajectory,
    time_optimal,
    timed,
    to_joint_space,
)

__all__ = ["EXAMPLES", "run"]

Log = Callable[[str], None]
#: The title of the demo's index.html, by which a rerun recognises its own page.
DEMO_TITLE = "trajkit demo"


def _ascending(trajectory: tk.Trajectory, piece: int, joint: int = 0) -> str:
    coefficients = trajectory.absolute_coefficients()[::-1, piece, joint]
    # Rounding noise of the solve (~1e-17) would print as a spurious tiny number.
    coefficients[np.abs(coefficients) < 1e-12 * np.abs(coefficients).max()] = 0.0
    return "[" + ", ".join(f"{c:.6g}" for c in coefficients + 0.0) + "]"


def seed004_via_point_polynomials(out: Path, stage: StagedFiles, log: Log) -> None:
    """Lecture notes (seed 004): two cubics through a via point, solved as A a = b."""
    example1 = tk.polynomial(
        [
            [(0, 0, 0.0), (0, 1, 0.0), (1, 0, 0.5), (1, 1, 0.2)],
            [(1, 0, 0.5), (1, 1, 0.2), (3, 0, 1.0), (3, 1, 0.0)],
        ],
        segments=[0, 1, 3],
    )
    example2 = tk.polynomial(
        [
            [(0, 0, 0.0), (0, 1, 0.0), (1, 0, 0.5)],
            [(1, 0, 0.5), (3, 0, 1.0), (3, 1, 0.0)],
        ],
        segments=[0, 1, 3],
        continuity=[(1, 2)],
    )
    for name, trajectory, rule in (
        ("example1", example1, "velocity 0.2 rad/s at t = 1 s"),
        ("example2", example2, "continuous velocity and acceleration at t = 1 s"),
    ):
        log(f"seed 004 {name} ({rule}): coefficients a0..a3 in absolute time")
        for piece in range(2):
            log(f"  piece {piece + 1}: {_ascending(trajectory, piece)}")
        figure = tk.plot.profiles(trajectory, title=f"Seed 004 {name}: {rule}")
        tk.plot.save(figure, stage.path(out / f"seed004_{name}.png"))
        trajectory.sample(0.01).to_csv(stage.path(out / f"seed004_{name}.csv"))


def seed000_two_joint_cubic(out: Path, stage: StagedFiles, log: Log) -> None:
    """Seed 000 §3.1: RRBot joints 0 -> 67° and 0 -> -45°, cubic, vmax 9 and 11 °/s."""
    q0 = np.radians([0.0, 0.0])
    qf = np.radians([round(5351 / 80), -round(5351 / 120)])
    vmax = np.radians([9.0, 11.0])
    limits = tk.Limits(velocity=vmax)
    trajectory = tk.cubic(q0, qf, vmax=vmax)
    own = trajectory.info["minimum_durations"]
    log(
        f"seed 000 cubic: exact common minimum duration {trajectory.duration:.12g} s "
        f"(joint 1 alone {own[0]:.12g} s, joint 2 alone {own[1]:.12g} s)"
    )
    log("  " + str(trajectory.check(limits)).replace("\n", "\n  "))
    for guess in (11.0, 6.0):
        report = tk.cubic(q0, qf, guess).check(limits)
        worst = ", ".join(
            f"joint {v.joint + 1} peaks at {np.degrees(abs(v.value)):.4g} °/s > "
            f"{np.degrees(abs(v.bound)):.4g} °/s"
            for v in report.violations
        )
        log(f"  the hand solution's {guess:g} s breaks the velocity limit: {worst}")
    figure = tk.plot.profiles(
        trajectory,
        limits,
        degrees=True,
        names=["joint 1", "joint 2"],
        title=f"Seed 000: cubic, minimum duration {trajectory.duration:.4f} s",
    )
    tk.plot.save(figure, stage.path(out / "seed000_cubic.png"))
    trajectory.sample(0.002).to_csv(stage.path(out / "seed000_cubic.csv"))


def _arm_outputs(
    out: Path,
    stage: StagedFiles,
    stem: str,
    robot: SerialChain,
    motion: TaskTrajectory,
    plan: JointSpacePlan,
    title: str,
    view: str,
) -> None:
    """Plots of the task-space motion, the joint trajectory and the arm; joint samples CSV."""
    figure = tk.plot.task_space(motion, title=f"{title}: task space")
    tk.plot.save(figure, stage.path(out / f"{stem}_task.png"))
    figure = tk.plot.profiles(
        plan.trajectory, robot.limits(), names=robot.names, title=f"{title}: joint space"
    )
    tk.plot.save(figure, stage.path(out / f"{stem}_joints.png"))
    tk.plot.save(tk.plot.arm(robot, plan.trajectory, instants=6, view=view, title=title),
                 stage.path(out / f"{stem}_arm.png"))  # fmt: skip
    plan.trajectory.sample(0.01).to_csv(stage.path(out / f"{stem}_joints.csv"))


def seed003_task_space_line(out: Path, stage: StagedFiles, log: Log) -> None:
    """Seed 003: the 3-DOF arm's tool on a cubic-timed line from P_A to P_B in 10 s (cm)."""
    robot = Spatial3R(5.0, 10.0, 8.0, 12.0)
    motion = timed(Line([0.0, -12.0, 20.0], [10.0, 12.0, 20.0]), "cubic", duration=10.0)
    plan = to_joint_space(robot, motion, dt=0.01)
    check_times = np.linspace(0.0, 10.0, 10001)
    tool = robot.fk(plan.trajectory.position(check_times))[:, :3, 3]
    deviation = float(np.abs(tool - motion.evaluate(check_times).position).max())
    peak = np.degrees(plan.trajectory.extrema(1).peak)
    log(
        f"seed 003 3-DOF arm, cubic line (0, -12, 20) -> (10, 12, 20) cm in 10 s: "
        f"FK of the joint trajectory within {deviation:.2g} cm of the line"
    )
    log(
        f"  q(0) = {np.degrees(plan.q[0]).round(4).tolist()} deg, "
        f"q(10) = {np.degrees(plan.q[-1]).round(4).tolist()} deg, "
        f"peak rates {peak.round(4).tolist()} deg/s; {'OK' if plan.ok else plan.problems()}"
    )
    _arm_outputs(out, stage, "seed003_arm", robot, motion, plan, "Seed 003: 3-DOF arm", "3d")


def seed003_time_optimal_line(out: Path, stage: StagedFiles, log: Log) -> None:
    """Seed 003's line again, as fast as joint limits of 1 rad/s and 2 rad/s² allow."""
    robot = Spatial3R(5.0, 10.0, 8.0, 12.0)
    line = Line([0.0, -12.0, 20.0], [10.0, 12.0, 20.0])
    limits = tk.Limits(velocity=1.0, acceleration=2.0)
    move = time_optimal(robot, line, limits, grid=1000)
    smooth_limits = tk.Limits(velocity=1.0, acceleration=2.0, jerk=10.0)
    smooth = time_optimal(robot, line, smooth_limits, grid=1000)
    peak_v = move.trajectory.extrema(1).peak.max()
    peak_a = move.trajectory.extrema(2).peak.max()
    log(
        f"seed 003 time-optimal: the same line in {move.duration:.4f} s (instead of 10 s) under "
        f"|q'| <= 1 rad/s, |q''| <= 2 rad/s^2: peaks {peak_v:.6f} rad/s, {peak_a:.6f} rad/s^2, "
        f"limits {'kept' if move.trajectory.check(limits).ok else 'BROKEN'} (exact check); "
        f"tool within {move.path_error:.2g} cm of the line"
    )
    log(
        f"  with a jerk limit of 10 rad/s^3 as well: {smooth.duration:.4f} s, limits "
        f"{'kept' if smooth.trajectory.check(smooth_limits).ok else 'BROKEN'}"
    )
    stem = "seed003_time_optimal"
    runs = ((move.trajectory, "", limits), (smooth.trajectory, "_jerk_limited", smooth_limits))
    for trajectory, name, bounds in runs:
        title = f"Seed 003, time-optimal{name.replace('_', ' ')}"
        figure = tk.plot.profiles(
            trajectory, bounds, orders=(0, 1, 2, 3), names=robot.names, title=title
        )
        tk.plot.save(figure, stage.path(out / f"{stem}{name}_joints.png"))
        trajectory.sample(0.01).to_csv(stage.path(out / f"{stem}{name}_joints.csv"))


def seed002_two_link_tracking(out: Path, stage: StagedFiles, log: Log) -> None:
    """Seed 002: a 2-link arm tracks x = 0.9 cos(2πt/T) sqrt((L1+L2)² - h²), y = h."""
    l1, l2, period = 1.0, 0.8, 5.0
    h = 2.0 / 3.0 * (l1 + l2)
    robot = Planar2R(l1, l2)
    path = Ellipse([0.0, h, 0.0], 0.9 * np.sqrt((l1 + l2) ** 2 - h**2), 0.0)
    motion = timed(path, "linear", duration=period)
    plan = to_joint_space(robot, motion, dt=0.01, branch="elbow_positive")
    log(
        f"seed 002 two-link arm (L1 = {l1:g} m, L2 = {l2:g} m, T = {period:g} s): "
        f"FK within {plan.path_error:.2g} m of the path between samples; "
        f"peak joint rates {plan.trajectory.extrema(1).peak.round(4).tolist()} rad/s"
    )
    _arm_outputs(out, stage, "seed002_arm", robot, motion, plan, "Seed 002: 2-link arm", "xy")


def seed001_six_joint_synchronization(out: Path, stage: StagedFiles, log: Log) -> None:
    """Seed 001: six joints, trapezoid and S-curve side by side, synchronized.

    Each continuous and on a 2 ms controller period.
    """
    q0 = np.zeros(6)
    qf = np.radians([90.0, 75.0, 60.0, 45.0, 30.0, 15.0])
    vmax = np.radians([7.0, 7.0, 7.0, 3.5, 3.5, 3.5])
    amax = np.radians([4.0, 4.0, 4.0, 2.0, 2.0, 2.0])
    trapezoid_limits = tk.Limits(velocity=vmax, acceleration=amax)
    names = [f"joint {j + 1}" for j in range(6)]
    jmax = 4.0 * amax  # the coursework gives no jerk limit: a quarter second to full acceleration
    limits = tk.Limits(velocity=vmax, acceleration=amax, jerk=jmax)
    for label, kwargs in (("continuous", {}), ("dt 2 ms", {"dt": 0.002})):
        for sync in ("phase", "time"):
            for profile in ("trapezoid", "scurve"):
                if profile == "trapezoid":
                    trajectory = tk.trapezoidal(q0, qf, vmax, amax, sync=sync, **kwargs)
                else:
                    trajectory = tk.scurve(q0, qf, vmax, amax, jmax, sync=sync, **kwargs)
                report = trajectory.check(limits if profile == "scurve" else trapezoid_limits)
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
                    trajectory, limits, degrees=True, names=names,
                    orders=(0, 1, 2, 3) if profile == "scurve" else (0, 1, 2),
                    title=f"Seed 001: {profile}, sync={sync}, {label}, "
                    f"{trajectory.duration:.6g} s",
                )  # fmt: skip
                tk.plot.save(figure, stage.path(out / f"{stem}.png"))
                trajectory.sample(0.002).to_csv(stage.path(out / f"{stem}.csv"))


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


def seed000_jackal_twist(out: Path, stage: StagedFiles, log: Log) -> None:
    """Seed 000 §2.0 (move_jackal): constant twists sent at 10 Hz; the arcs they trace."""
    robot = mobile.jackal()
    for stem, v, omega_deg, duration in (("spin", 0.0, -15.0, 10.0), ("arc", 0.1, 10.0, 15.0)):
        plan = mobile.constant_twist(v, np.radians(omega_deg), duration, rate_hz=10.0, model=robot)
        x, y, theta = plan.end_pose
        log(
            f"seed 000 Jackal twist v = {v:g} m/s, ω = {omega_deg:g}°/s for {duration:g} s "
            f"({plan.info['command_count']} commands at 10 Hz): ends at ({x:.6g} m, {y:.6g} m, "
            f"{theta:.6g} rad), arc radius {plan.info['radius']:.6g} m; "
            f"{'within' if plan.check().ok else 'BEYOND'} the Jackal's limits"
        )
        title = f"Seed 000: Jackal twist ({v:g} m/s, {omega_deg:g}°/s, {duration:g} s)"
        _mobile_outputs(out, stage, f"seed000_jackal_twist_{stem}", plan, title)


def seed000_jackal_rotate_translate_rotate(out: Path, stage: StagedFiles, log: Log) -> None:
    """Seed 000 §2.1: rotate to face (5, 3), drive there, rotate to 1.5 rad; blend 0.1."""
    robot = mobile.jackal()
    limits = mobile.MobileLimits(velocity=0.2, angular_velocity=np.radians(30.0))
    plan = mobile.rotate_translate_rotate(
        (5.0, 3.0, 1.5), vmax=0.2, wmax=np.radians(30.0), blend_ratio=0.1, model=robot
    )
    for name, duration, hand in zip(
        plan.info["phases"], plan.info["phase_durations"], (1.2, 32.0, 2.02), strict=True
    ):
        verdict = "breaks" if hand < duration * (1 - 1e-12) else "keeps"
        log(
            f"seed 000 Jackal, {name}: minimum duration {duration:.9g} s; the hand value "
            f"{hand:g} s {verdict} the limit"
        )
    x, y, theta = plan.end_pose
    report = plan.check(limits)
    log(
        f"  total {plan.duration:.9g} s, ends at ({x:.6g} m, {y:.6g} m, {theta:.6g} rad); "
        f"v <= 0.2 m/s and ω <= 30°/s {'hold' if report.ok else 'BROKEN'}"
    )
    run = mobile.simulate(plan, dt=0.01, command_rate_hz=10.0)
    log(f"  the plan's twists sent at 10 Hz and held (zero-order hold): {run.summary()}")
    _mobile_outputs(out, stage, "seed000_jackal_goto", plan, "Seed 000: rotate, drive, rotate")
    _mobile_outputs(out, stage, "seed000_jackal_goto_10hz", run, "Seed 000: held at 10 Hz")


def seed002_figure_eight(out: Path, stage: StagedFiles, log: Log) -> None:
    """Seed 002: a turtle on a figure eight by differential flatness, tracked four ways."""
    robot = mobile.jackal()
    curve = mobile.FigureEight(2.0, 1.0, 20.0)
    plan = mobile.flat_trajectory(curve, model=robot)
    peak = plan.check(mobile.MobileLimits(velocity=1.0, angular_velocity=4.0)).peaks
    log(
        f"seed 002 figure eight W = 2 m, H = 1 m, T = 20 s by differential flatness: "
        f"peak v {peak['velocity'][1][0]:.6g} m/s, peak |ω| "
        f"{max(-peak['angular velocity'][0][0], peak['angular velocity'][1][0]):.6g} rad/s"
    )
    start = plan.start_pose + np.array([0.5 * np.cos(1.0), 0.5 * np.sin(1.0), np.radians(30.0)])
    log("  tracking from 0.5 m and 30° off the start, RK4 at 200 Hz:")
    controllers = (
        mobile.Feedforward(), mobile.Kanayama(), mobile.FeedbackLinearization(),
        mobile.PurePursuit(),
    )  # fmt: skip
    for controller in controllers:
        run = mobile.simulate(plan, controller, dt=0.005, initial_pose=start)
        log(
            f"    {run.summary()}; after 10 s at most {run.error_after(10.0):.3g} m "
            f"({run.error_after(10.0, along_path=True):.3g} m from the path)"
        )
        stem = "seed002_figure8_" + controller.name.replace(" ", "_")
        _mobile_outputs(out, stage, stem, run, f"Seed 002: figure eight, {controller.name}")
    exact = mobile.simulate(plan, dt=0.001)
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


def seed000_rrbot_in_mujoco(out: Path, stage: StagedFiles, log: Log) -> None:
    """Seed 000 §3.1 executed: the RRBot's cubic move on the simulated arm, four controllers."""
    log("seed 000 RRBot cubic move in MuJoCo (1 kg links, damping 0.7, 1 kHz control):")
    if not _simulation_ready(log):
        return
    from trajkit import sim

    vmax = np.radians([9.0, 11.0])
    plan = tk.cubic(np.radians([0.0, 0.0]), np.radians([67.0, -45.0]), vmax=vmax)
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


def seed000_jackal_in_mujoco(out: Path, stage: StagedFiles, log: Log) -> None:
    """Seed 000 §2.1 executed: rotate–translate–rotate on a simulated Jackal."""
    log("seed 000 Jackal rotate–translate–rotate in MuJoCo (17 kg, wheel velocity servos):")
    if not _simulation_ready(log):
        return
    from trajkit import sim

    plan = mobile.rotate_translate_rotate(
        (5.0, 3.0, 1.5), vmax=0.2, wmax=np.radians(30.0), blend_ratio=0.1, model=mobile.jackal()
    )
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


EXAMPLES: tuple[Callable[[Path, StagedFiles, Log], None], ...] = (
    seed004_via_point_polynomials,
    seed000_two_joint_cubic,
    seed003_task_space_line,
    seed003_time_optimal_line,
    seed002_two_link_tracking,
    seed001_six_joint_synchronization,
    seed000_jackal_twist,
    seed000_jackal_rotate_translate_rotate,
    seed002_figure_eight,
    seed000_rrbot_in_mujoco,
    seed000_jackal_in_mujoco,
)


def run(out: str | Path, log: Log = print) -> list[Path]:
    """Run every worked example and every example scenario into ``out``; return the files.

    The worked examples' files are written all together or not at all; each
    scenario's likewise. ``index.html`` gathers the scenarios' results.

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

    with staged_files() as stage:
        for example in EXAMPLES:
            example(folder, stage, record)
        summary = stage.path(folder / "summary.txt")
        summary.write_text("\n".join(lines) + "\n", encoding="utf-8")
    written = list(stage.targets)
    entries = []
    files = scenario.examples()
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
