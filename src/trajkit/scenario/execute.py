"""Carrying out a scenario: plan, check, optionally simulate, and write every output.

Files are written all together or not at all (staged, then renamed); a ROS 2 bag,
a folder, is renamed into place after them.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

import trajkit as tk
from trajkit import mobile
from trajkit.errors import TrajkitError
from trajkit.io.atomic import StagedFiles, staged_files
from trajkit.kinematics import BUILTIN, DHRow, SerialChain, from_mjcf, from_urdf
from trajkit.mobile.limits import KEYWORDS
from trajkit.mobile.models import BASES
from trajkit.planners import CATALOG
from trajkit.samples import DEFAULT_STEP
from trajkit.scenario.parse import MOBILE_ANGULAR, MOBILE_JERKS, Scenario
from trajkit.scenario.reader import ScenarioError
from trajkit.trajectory import Trajectory

__all__ = ["Outcome", "execute", "preflight", "report_entry", "robot_of"]

Log = Callable[[str], None]


@dataclass(frozen=True)
class Outcome:
    """What a scenario run produced.

    Attributes
    ----------
    plan : Trajectory or MobileTrajectory
    report : trajkit.Report
        The limit check of the plan.
    log : object or None
        The simulation log, when the scenario simulates.
    files : list of Path
        Every file and folder written.
    lines : list of str
        The summary printed and saved.
    """

    plan: Any
    report: Any
    log: Any
    files: list[Path]
    lines: list[str]


def sample_step(scenario: Scenario) -> float:
    """The data files' sampling step (s): as given, else the controller period, else 10 ms."""
    return scenario.outputs["sample_step"] or scenario.period or DEFAULT_STEP


def robot_of(scenario: Scenario) -> Any:
    """The robot a scenario describes: a SerialChain, a wheeled model, or None."""
    robot = scenario.robot
    if not robot:
        return None
    if "builtin" in robot:
        name = robot["builtin"]
        return (BASES[name] if scenario.mobile else BUILTIN[name])()
    if "dh" in robot:
        rows = [DHRow(r["a"], r["alpha"], r["d"], r["theta"], r["kind"], r["lower"], r["upper"])
                for r in robot["dh"]]  # fmt: skip
        return SerialChain.from_dh(rows, convention=robot["convention"], name=scenario.name)
    if "mjcf" in robot:
        return from_mjcf(robot["mjcf"], tip_body=robot["tip_body"])
    return from_urdf(robot["urdf"], base_link=robot["base_link"], tip_link=robot["tip_link"])


def execute(
    scenario: Scenario, out: str | Path, log: Log = print, *, report: bool = False
) -> Outcome:
    """Run ``scenario`` and write its outputs into the folder ``out`` (created if needed).

    Every output (files, the ROS 2 bag folder, with ``report`` the ``index.html``
    page) appears together or not at all; the folder is made only when there is
    something to write.

    Raises
    ------
    ScenarioError
        When the scenario's parts do not fit together (a joint count, a missing limit),
        or planning refuses the task (the message starts with ``task:``).
    TrajkitError
        When a library the outputs need is missing, or simulating fails.
    """
    preflight(scenario)
    robot = robot_of(scenario)
    lines = [f"scenario {scenario.name}" + (f": {scenario.description}" if scenario.description
                                            else "")]  # fmt: skip
    try:
        plan, extra = (_mobile_plan if scenario.mobile else _arm_plan)(scenario, robot, lines)
    except ScenarioError:
        raise
    except TrajkitError as exc:
        raise ScenarioError(f"task: {exc}") from None
    if not scenario.mobile and robot is not None and plan.ndof != robot.ndof:
        raise ScenarioError(f"task: the plan has {plan.ndof} joint(s) but {robot.name} has "
                            f"{robot.ndof}")  # fmt: skip
    if scenario.mobile:  # a goto's S-curve phases answer to the base's jerk limits too
        jerks = {"jerk": scenario.limits.get("jmax"),
                 "angular_jerk": scenario.limits.get("angular_jmax")}  # fmt: skip
        checked = plan.check(**jerks)
    else:
        # Torque and tool limits count too, as the timing measured them on this plan.
        checked = plan.check(_arm_limits(scenario, robot)).merged(
            *plan.info.get("constraint_checks", ()))  # fmt: skip
    lines.append(f"  limit check: {'OK' if checked.ok else 'FAILED'}")
    for quantity in ("torque", "tool speed", "tool acceleration"):
        if quantity in checked.peaks:
            lines.append(f"    {quantity}: at most {checked.ratios(quantity).max():.6g} of its "
                         "limit")  # fmt: skip
    lines += [f"    {violation}" for violation in checked.violations]
    run = _simulate(scenario, robot, plan, extra, lines)
    # The plan and its check are said before the outputs are drawn (an animation may
    # take a while), not after.
    for line in lines:
        log(line)
    folder = Path(out)
    folder.mkdir(parents=True, exist_ok=True)
    stem = folder / scenario.name
    with staged_files() as stage:
        _write(scenario, robot, plan, run, extra, stem, stage)
        summary = stage.path(stem.with_name(f"{scenario.name}_summary.txt"))
        summary.write_text("\n".join(lines) + "\n", encoding="utf-8")
        if scenario.outputs["ros2_bag"]:
            _write_bag(scenario, robot, plan, run,
                       stage.folder(stem.with_name(f"{scenario.name}_bag")))  # fmt: skip
        outcome = Outcome(plan, checked, run, list(stage.targets), lines)
        if report:
            from trajkit.viz.report import write_report

            page = folder / "index.html"
            write_report(stage.path(page), [report_entry(scenario, outcome)],
                         title=f"trajkit: {scenario.name}", sources=stage.sources)  # fmt: skip
    return Outcome(plan, checked, run, list(stage.targets), lines)


def preflight(scenario: Scenario) -> None:
    """Refuse at once what the outputs need and this machine lacks, before any work."""
    outputs = scenario.outputs
    if outputs["ros2_bag"]:
        from trajkit.io.ros2 import require_rosbags

        require_rosbags()
    if outputs["animation"] == "mp4":
        import shutil

        from trajkit.viz.animate import AnimationUnavailable

        if shutil.which("ffmpeg") is None:
            raise AnimationUnavailable("outputs.animation: mp4 needs the ffmpeg program, which "
                                       "is not on PATH (Debian: apt install ffmpeg)",
                                       install="apt install ffmpeg")  # fmt: skip
    if scenario.simulation["engine"] == "mujoco":
        from trajkit.sim.engine import mujoco_module

        mujoco_module()


def _write_bag(scenario: Scenario, robot: Any, plan: Any, run: Any, path: Path) -> None:
    """The plan's bag and, after a simulation, what the simulated robot did.

    With a simulated arm, ``/joint_states`` is the simulated joints' (parsing refuses a
    ``joint_state`` stream of the plan there).
    """
    from trajkit.io.ros2 import write_bag

    stream = scenario.outputs["ros2_stream"]
    arm_stream = None if scenario.mobile or stream == "none" else stream
    rate = None
    if arm_stream is not None and scenario.period:
        rate = 1.0 / scenario.period  # the controller's rate
    if scenario.mobile:
        rate = scenario.simulation.get("rate_hz") or scenario.task.get("rate_hz")
    names = None if scenario.mobile or robot is None else robot.names
    mobile = ({"cmd_vel": scenario.outputs["ros2_cmd_vel"]} if scenario.mobile
              else {"controller": scenario.outputs["ros2_controller"]})  # fmt: skip
    write_bag(path, plan, joint_names=names, stream=arm_stream, rate_hz=rate,
              storage=scenario.outputs["storage"], start_ns=scenario.outputs["ros2_start_ns"],
              run=run, **mobile)  # fmt: skip


def _arm_limits(scenario: Scenario, robot: SerialChain | None = None) -> tk.Limits:
    """The scenario's limits, with the robot's joint ranges (positions) when it has some."""
    limits = scenario.limits
    position = None
    if robot is not None and np.any(np.isfinite(robot.lower) | np.isfinite(robot.upper)):
        position = (robot.lower, robot.upper)
    return tk.Limits(position=position, velocity=limits.get("vmax"),
                     acceleration=limits.get("amax"), jerk=limits.get("jmax"))  # fmt: skip


def _arm_plan(scenario: Scenario, robot: SerialChain, lines: list[str]) -> tuple[Trajectory, Any]:
    task, limits = scenario.task, scenario.limits
    kind = task["kind"]
    extra = None
    if kind == "joint_move":
        if robot is not None and task["q0"].size != robot.ndof:
            raise ScenarioError(f"task.q0: expected {robot.ndof} numbers for {robot.name}, got "
                                f"{task['q0'].size}")  # fmt: skip
        profile = task["profile"]
        entry = CATALOG[profile]
        for key in entry.needs:
            if key not in limits:
                raise ScenarioError(f"limits.{key}: required by the {profile} planner")
        values = {key: value for key, value in task.items() if entry.takes(key)}
        values |= {key: limits[key] for key in entry.limits if key in limits}
        plan = entry.plan(values, period=scenario.period if entry.period else None)
        on = f" on {robot.name}" if robot is not None else ""
        lines.append(f"  {profile} joint move{on}: {plan.duration:.9g} s")
    elif kind == "polynomial":
        plan = tk.polynomial(task["conditions"], segments=task["times"],
                             continuity=task["continuity"])  # fmt: skip
        lines.append(
            f"  polynomial through {len(task['conditions'])} segment(s), solved as A a = b"
        )
        for piece in range(len(task["conditions"])):
            ascending = plan.absolute_coefficients()[::-1, piece, 0]
            ascending[np.abs(ascending) < 1e-12 * np.abs(ascending).max()] = 0.0
            lines.append(f"    piece {piece + 1}: a0..a{ascending.size - 1} = "
                         f"{[float(f'{c:.6g}') for c in ascending + 0.0]}")  # fmt: skip
    elif kind == "waypoints":
        points = task["points"]
        if robot is not None and points.shape[1] != robot.ndof:
            raise ScenarioError(f"task.points[0]: expected {robot.ndof} numbers for "
                                f"{robot.name}, got {points.shape[1]}")  # fmt: skip
        for key in ("vmax", "amax"):
            if key not in limits:
                raise ScenarioError(f"limits.{key}: required by a waypoints task")
        if task["time_optimal"]:
            plan = tk.retime(points, _timing_limits(scenario),
                             path_tolerance=task["path_tolerance"], grid=task["timing_grid"],
                             constraints=_path_limits(scenario, robot))  # fmt: skip
            deviation = plan.info["waypoint_deviation"].max()
            lines.append(f"  time-optimal retiming through {points.shape[0]} waypoints: "
                         f"{plan.duration:.9g} s, at most {deviation:.3g} from a waypoint "
                         f"(tolerance {task['path_tolerance']:g})")  # fmt: skip
        else:
            plan = tk.blended(points, limits["vmax"], limits["amax"],
                              jmax=limits.get("jmax"), durations=task["durations"],
                              through=task["through"])  # fmt: skip
            lines.append(
                f"  blended move through {points.shape[0]} waypoints: {plan.duration:.9g} s"
            )
    else:
        from trajkit.rotations import homogeneous, rpy_matrix
        from trajkit.taskspace import Ellipse, Line, through_poses, timed, to_joint_space

        branch = None
        if kind == "line" and task["time_optimal"]:
            from trajkit.taskspace import time_optimal

            for key in ("vmax", "amax"):
                if key not in limits:
                    raise ScenarioError(f"limits.{key}: required by a time-optimal line")
            line = Line(task["start"], task["end"])
            move = time_optimal(robot, line, _timing_limits(scenario), grid=task["timing_grid"],
                                constraints=_path_limits(scenario, robot))  # fmt: skip
            plan, extra = move.trajectory, None
            lines.append(f"  time-optimal line on {robot.name}: {plan.duration:.9g} s, path "
                         f"error {move.path_error:.2g}")  # fmt: skip
            return plan, extra
        if kind == "line":
            motion = timed(Line(task["start"], task["end"]), task["law"], duration=task["duration"])
            what = f"{task['law']} line"
        elif kind == "ellipse":
            path = Ellipse(task["center"], task["a"], task["b"])
            motion = timed(path, task["law"], duration=task["duration"])
            what, branch = f"{task['law']} ellipse", task["branch"]
        else:
            poses = np.stack([homogeneous(rpy_matrix(np.radians(row[3:])), row[:3])
                              for row in task["poses"]])  # fmt: skip
            motion = through_poses(poses, task["profile"], durations=task["durations"])
            what = f"{task['profile']} moves through {len(poses)} poses"
        mapped = to_joint_space(robot, motion, ik_step=task["ik_step"], branch=branch)
        plan, extra = mapped.trajectory, motion
        lines.append(
            f"  {what} on {robot.name} in {motion.duration:g} s: path error "
            f"{mapped.path_error:.2g}; {'OK' if mapped.ok else mapped.problems()}"
        )
    if plan.info.get("phase_times") is not None and kind == "joint_move":
        lines.append(f"  phase times: {np.round(plan.info['phase_times'], 9).tolist()}")
    return plan, extra


def _timing_limits(scenario: Scenario) -> tk.Limits:
    """The joint velocity, acceleration and (a line's) jerk bounds a time-optimal timing keeps."""
    limits = scenario.limits
    return tk.Limits(velocity=limits["vmax"], acceleration=limits["amax"], jerk=limits.get("jmax"))


def _path_limits(scenario: Scenario, robot: SerialChain | None) -> list[Any]:
    """The scenario's torque and tool limits, as the timing's constraints."""
    limits, out = scenario.limits, []
    if "torque" in limits:
        assert robot is not None  # parse refuses torque limits without a robot
        out.append(tk.TorqueLimit(robot, None if limits["torque"] is True else limits["torque"]))
    if "tool_speed" in limits or "tool_acceleration" in limits:
        assert robot is not None
        out.append(tk.ToolLimit(robot, speed=limits.get("tool_speed"),
                                acceleration=limits.get("tool_acceleration")))  # fmt: skip
    return out


def _mobile_limits(scenario: Scenario, model: Any) -> Any:
    checked = {KEYWORDS[key]: value for key, value in scenario.limits.items()
               if key not in MOBILE_JERKS}  # fmt: skip
    return model.limits.replace(**checked)


def _mobile_plan(scenario: Scenario, model: Any, lines: list[str]) -> tuple[Any, Any]:
    task = scenario.task
    limits = _mobile_limits(scenario, model)
    kind = task["kind"]
    if kind == "twist":
        # The scenario's limits are what the twist is checked against.
        model = dataclasses.replace(model, limits=limits)
        plan = mobile.constant_twist(task["v"], task["omega"], task["duration"],
                                     rate_hz=task["rate_hz"], model=model)  # fmt: skip
    elif kind == "goto":
        goal = (
            (*task["goal"], task["heading"]) if task["heading"] is not None else tuple(task["goal"])
        )
        plan = mobile.rotate_translate_rotate(
            goal, (*task["start"], task["start_heading"]), limits=limits, profile=task["profile"],
            jmax=scenario.limits.get("jmax"), angular_jmax=scenario.limits.get("angular_jmax"),
            blend_ratio=task["blend_ratio"], reverse=task["reverse"], period=scenario.period,
            model=model,
        )  # fmt: skip
    else:
        curve = mobile.FigureEight(task["width"], task["height"], task["period"])
        timing = "within_limits" if task["fit"] else "as_given"
        plan = mobile.flat_trajectory(curve, model=model, limits=limits, timing=timing)
    lines += ["  " + line for line in plan.describe().splitlines()[:1]]
    for name, duration in zip(plan.info.get("phases", ()), plan.info.get("phase_durations", ()),
                              strict=True):  # fmt: skip
        lines.append(f"    {name}: {duration:.9g} s")
    return plan, None


def _simulate(scenario: Scenario, robot: Any, plan: Any, extra: Any, lines: list[str]) -> Any:
    engine, rate = scenario.simulation["engine"], scenario.simulation.get("rate_hz")
    task = scenario.task
    if scenario.mobile:
        from trajkit.mobile.control import controller_named

        controller = controller_named(task.get("controller", "feedforward"))
        offset = (*task.get("offset", (0.0, 0.0)), task.get("offset_heading", 0.0))
        start = plan.start_pose + np.array(offset)
        if engine == "mujoco":
            from trajkit import sim

            if not isinstance(robot, mobile.DiffDrive):
                raise ScenarioError("simulation.engine: mujoco needs a wheeled robot (jackal)")
            rate = rate or task.get("rate_hz")
            scene = sim.MobileScene(robot, drive=scenario.simulation.get("drive", "differential"))
            run = sim.run(scene, plan, control_rate_hz=rate,
                          controller=controller, initial_pose=start)  # fmt: skip
        elif task["kind"] == "figure8" or rate is not None:
            run = mobile.simulate(plan, controller, sample_step=0.01, initial_pose=start,
                                  command_rate_hz=rate)  # fmt: skip
        else:
            return None
        lines.append(f"  simulated ({engine}): {run.summary()}")
        return run
    if engine == "kinematic":
        return None
    from trajkit import sim

    scene = sim.arm_scene(robot)
    run = sim.run(scene, plan, control_rate_hz=rate, controller=scenario.simulation["controller"])
    lines += ["  simulated in MuJoCo, " + line for line in run.summary().splitlines()[:1]]
    lines += ["  " + line for line in run.summary().splitlines()[1:]]
    return run


def _write(scenario: Scenario, robot: Any, plan: Any, run: Any, extra: Any, stem: Path,
           stage: StagedFiles) -> None:  # fmt: skip
    outputs = scenario.outputs
    name = stem.name

    def at(suffix: str) -> Path:
        return stage.path(stem.with_name(f"{name}{suffix}"))

    if scenario.mobile:
        if outputs["csv"]:
            if run is None:
                plan.to_csv(at(".csv"), sample_step(scenario))
            else:
                run.to_csv(at(".csv"))
        if outputs["plot"]:
            data = plan if run is None else run
            tk.plot.save(tk.plot.mobile(data, title=name), at(".png"))
            tk.plot.save(tk.plot.mobile_path(data, title=name), at("_path.png"))
        if outputs["animation"] != "none":
            from trajkit.viz import animate

            animate.mobile(plan if run is None else run, at(f".{outputs['animation']}"),
                           title=name, progress=True, fps=outputs["animation_fps"],
                           speed=outputs["animation_speed"], size=4.0)  # fmt: skip
        return
    samples = None
    if any(outputs[kind] for kind in ("csv", "json", "npz")):
        samples = plan.sample(sample_step(scenario))
        if robot is not None:
            samples = dataclasses.replace(samples, names=tuple(robot.names))
    for kind in ("csv", "json", "npz"):
        if outputs[kind]:
            getattr(samples, f"to_{kind}")(at(f".{kind}"))
    if outputs["plot"]:
        names = None if robot is None else robot.names
        # A jerk panel too when the scenario limits jerk.
        orders = (0, 1, 2, 3) if "jmax" in scenario.limits else (0, 1, 2)
        figure = tk.plot.profiles(plan, _arm_limits(scenario), names=names, title=name,
                                  degrees=scenario.degrees,
                                  orders=orders)  # fmt: skip
        tk.plot.save(figure, at(".png"))
        path_limits = _path_limits(scenario, robot)
        if path_limits:
            kinds = " and ".join(sorted({item.quantity for item in path_limits}, reverse=True))
            tk.plot.save(tk.plot.constraints(plan, path_limits, title=f"{name}: {kinds} limits"),
                         at("_limits.png"))  # fmt: skip
        if extra is not None:
            tk.plot.save(tk.plot.task_space(extra, title=f"{name}: task space"), at("_task.png"))
    if run is not None:
        run.to_csv(at("_sim.csv"))
        tk.plot.save(tk.plot.tracking(run, title=f"{name} in MuJoCo", degrees=scenario.degrees),
                     at("_sim.png"))  # fmt: skip
    if outputs["animation"] != "none":
        from trajkit.viz import animate

        animate.arm(
            robot,
            plan,
            at(f".{outputs['animation']}"),
            title=name,
            progress=True,
            view=outputs["animation_view"],
            fps=outputs["animation_fps"],
            speed=outputs["animation_speed"],
            size=4.0,
        )


def report_entry(scenario: Scenario, outcome: Outcome) -> Any:
    """The :class:`trajkit.viz.report.Entry` of one run."""
    from trajkit.viz.report import Entry

    run = outcome.log
    tracking = ""
    if run is not None and hasattr(run, "joint_names"):
        tracking = f"max error {np.degrees(run.max_error).max():.3g} deg ({run.controller})"
    elif run is not None:
        tracking = f"final error {run.final_position_error * 1000:.3g} mm ({run.controller})"
    text = scenario.text
    return Entry(scenario.name, scenario.description, float(outcome.plan.duration),
                 bool(outcome.report.ok), _limits_text(scenario), tracking, outcome.lines,
                 outcome.files, text)  # fmt: skip


#: Each limit key in words, for the report, and its unit per second.
_LIMIT_WORDS = {"vmax": ("velocity", "/s"), "amax": ("acceleration", "/s²"),
                "jmax": ("jerk", "/s³"), "wmax": ("angular velocity", "/s"),
                "alpha_max": ("angular acceleration", "/s²"),
                "angular_jmax": ("angular jerk", "/s³")}  # fmt: skip


#: The same for a time-optimal timing's torque and tool limits.
_PATH_LIMIT_WORDS = {"torque": ("torque", "N·m"), "tool_speed": ("tool speed", "m/s"),
                     "tool_acceleration": ("tool acceleration", "m/s²")}  # fmt: skip


def _limits_text(scenario: Scenario) -> str:
    """The scenario's limits in words, angles in degrees: "velocity 9, 11 deg/s"."""
    parts = []
    for key, value in scenario.limits.items():
        if key in _PATH_LIMIT_WORDS:  # not angles: N·m, m/s, m/s²
            shown = "the robot's own" if value is True else ", ".join(
                f"{v:.4g}" for v in np.atleast_1d(value))  # fmt: skip
            words, unit = _PATH_LIMIT_WORDS[key]
            parts.append(f"{words} {shown}" + ("" if value is True else f" {unit}"))
            continue
        values = np.atleast_1d(value)
        angular = not scenario.mobile or key in MOBILE_ANGULAR
        words, unit = _LIMIT_WORDS[key]
        shown = np.degrees(values) if angular else values
        base = "deg" if angular else "m"
        parts.append(f"{words} {', '.join(f'{v:.4g}' for v in shown)} "
                     f"{base}{unit}")  # fmt: skip
    if not scenario.mobile or not parts:
        return "; ".join(parts) or "the robot's own"
    return "; ".join(parts)
