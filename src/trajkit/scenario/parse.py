"""Scenario files: what a TOML scenario says, parsed into plain objects.

A scenario names the robot, the task, the limits, the controller period, the
simulation and the outputs; see ``examples/`` and the README for the format.
Parsing never runs code from the file and refuses unknown keys; every error is a
:class:`~trajkit.scenario.reader.ScenarioError` naming the key path.
"""

from __future__ import annotations

import datetime
import math
import os
import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from trajkit.kinematics.robots import BUILTIN
from trajkit.mobile.limits import KEYWORDS
from trajkit.mobile.models import BASES
from trajkit.mobile.plans import MAX_TRAVEL
from trajkit.planners import CATALOG, LIMITS, OPTIONS, QUANTITIES
from trajkit.samples import DEFAULT_STEP
from trajkit.scenario.reader import ScenarioError, Table

__all__ = ["ARM_ROBOTS", "MOBILE_ROBOTS", "TASKS", "Scenario", "from_data", "load", "parse"]

ARM_ROBOTS = tuple(BUILTIN)
MOBILE_ROBOTS = tuple(BASES)
ARM_TASKS = ("joint_move", "waypoints", "polynomial", "line", "ellipse", "poses")
#: Tasks planned in joint space alone: they need no robot unless simulated or animated.
JOINT_TASKS = ("joint_move", "waypoints", "polynomial")
MOBILE_TASKS = ("twist", "goto", "figure8")
TASKS = ARM_TASKS + MOBILE_TASKS
#: The largest time (s) a polynomial task names, some 31,700 years.
MAX_TIME = 1e12
#: A base's jerk limits: not MobileLimits; they shape a goto's S-curves, and the scenario's
#: limit check verifies them on those phases (MobileTrajectory.check's jerk arguments).
MOBILE_JERKS = ("jmax", "angular_jmax")
MOBILE_LIMITS = (*KEYWORDS, *MOBILE_JERKS)
#: The base's limits on turning: given in degrees as ``wmax_deg`` and so on.
MOBILE_ANGULAR = ("wmax", "alpha_max", "angular_jmax")
#: A time-optimal timing's limits on the tool (m/s, m/s²), beside joint limits and torque.
TOOL_LIMITS = ("tool_speed", "tool_acceleration")
#: The limits' names before they were the planners' keywords, still read with a warning.
OLD_ARM_LIMITS = {"velocity": "vmax", "acceleration": "amax", "jerk": "jmax"}
OLD_MOBILE_LIMITS = {"velocity": "vmax", "angular_velocity": "wmax", "acceleration": "amax",
                     "angular_acceleration": "alpha_max", "jerk": "jmax",
                     "angular_jerk": "angular_jmax"}  # fmt: skip
ANIMATIONS = ("none", "gif", "mp4")


@dataclass(frozen=True, eq=False)
class Scenario:
    """A parsed scenario: each section as a dictionary of checked values.

    Attributes
    ----------
    name, description : str
    robot : dict
        ``builtin`` (a name), or ``dh`` (rows) with ``convention``, or ``mjcf`` (a path,
        with ``tip_body``), or ``urdf`` (a path
        resolved against the scenario's folder); empty for a joint-space task
        without a robot.
    task : dict
        ``kind`` and its parameters, angles in radians; a joint move's only as given
        (the catalog planner's defaults apply to the others).
    limits : dict
        Named as the planners' keywords. Arm: vmax, amax, jmax (per joint); base:
        vmax, wmax, amax, alpha_max, and jmax (m/s³) and angular_jmax (rad/s³) for a
        goto task with ``profile = "scurve"``.
    period : float or None
        The controller period (s): switching times on its multiples; also the data
        files' sampling step unless ``outputs.sample_step`` sets one.
    simulation : dict
        ``engine`` (kinematic or mujoco), ``controller``, ``rate_hz``.
    outputs : dict
        ``csv``, ``json``, ``npz`` (samples), ``plot``, ``animation`` (none, gif or
        mp4) with ``animation_view``, ``animation_fps`` and ``animation_speed``,
        ``ros2_bag``, ``ros2_stream``, ``ros2_cmd_vel`` (Twist or TwistStamped),
        ``ros2_controller`` (an arm's controller: ``/<name>/joint_trajectory``),
        ``ros2_start_ns`` (the bag time of the plan's start, from ``ros2_start``: a
        date-time or seconds since 1970), ``storage`` (mcap or sqlite3), ``sample_step``
        (s, the data files' sampling step; None: the controller period, else 10 ms).
    source : Path or None
        The file it was read from.
    text : str
        The scenario's text, as read (echoed by reports).
    """

    name: str
    description: str
    robot: dict[str, Any]
    task: dict[str, Any]
    limits: dict[str, Any]
    period: float | None
    simulation: dict[str, Any]
    outputs: dict[str, Any]
    source: Path | None = field(default=None, compare=False)
    text: str = ""

    @property
    def mobile(self) -> bool:
        """True for a wheeled robot's scenario."""
        return self.task["kind"] in MOBILE_TASKS

    @property
    def degrees(self) -> bool:
        """True when an arm's scenario gives angles in degrees: its plots show degrees.

        Degrees are given as a ``*_deg`` key of the task or the limits.
        """
        if self.mobile or not self.text:
            return False
        data = tomllib.loads(self.text)
        return any(key.endswith("_deg") for section in ("task", "limits")
                   for key in data.get(section, {}))  # fmt: skip


def load(path: str | os.PathLike[str]) -> Scenario:
    """Read and check a scenario file.

    Raises
    ------
    ScenarioError
        For a file that is not valid TOML or breaks the format (the message names
        the key path); ``OSError`` if it cannot be read.
    """
    source = Path(path)
    try:
        text = source.read_text(encoding="utf-8")
    except UnicodeDecodeError as exc:
        raise ScenarioError(f"{source.name}: not UTF-8 text ({exc.reason})") from None
    return parse(text, folder=source.parent, source=source)


def parse(text: str, *, folder: Path | None = None, source: Path | None = None) -> Scenario:
    """Parse scenario text; relative file names are taken from ``folder``."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError(f"not valid TOML: {exc}") from None
    return from_data(data, folder=folder, source=source, text=text)


def from_data(
    data: dict[str, Any],
    *,
    folder: Path | None = None,
    source: Path | None = None,
    text: str = "",
) -> Scenario:
    """Check a scenario already read from TOML (a dictionary of its tables)."""
    root = Table(data, "")
    name = root.string("name")
    if not name.replace("_", "").replace("-", "").isalnum():
        raise ScenarioError(f"name: expected letters, digits, '_' or '-' (it names files), "
                            f"got {name!r}")  # fmt: skip
    description = root.string("description", "")
    task_table = root.table("task", required=True)
    kind = task_table.string("kind", choices=TASKS)
    robot_table = root.table("robot", required=kind not in JOINT_TASKS)
    robot = {} if robot_table is None else _robot(robot_table, kind, folder or Path("."))
    task = _task(task_table, kind)
    limits = _limits(root.table("limits"), kind in MOBILE_TASKS)
    _check_jerk(limits, task, kind)
    _check_timing_limits(limits, task, robot)
    controller = root.table("controller")
    period = None
    if controller is not None:
        period = controller.number("period", None, positive=True)
        controller.done()
    if task.get("grid") is not None and period is None:
        raise ScenarioError("task.grid: only used with a controller period ([controller] "
                            "period): the grid is its ticks")  # fmt: skip
    simulation = _simulation(root.table("simulation"), kind in MOBILE_TASKS)
    outputs = _outputs(root.table("outputs"))
    root.done()
    if outputs["ros2_stream"] == "joint_state" and simulation.get("engine") == "mujoco":
        raise ScenarioError("outputs.ros2_stream: with a MuJoCo simulation the bag's "
                            "/joint_states is the simulated arm's; the plan's stream would "
                            "pass for it: use 'point' or 'none'")  # fmt: skip
    if outputs["ros2_controller"] is not None and kind in MOBILE_TASKS:
        raise ScenarioError("outputs.ros2_controller: an arm's joint trajectory controller; a "
                            "base's bag holds /cmd_vel")  # fmt: skip
    if outputs["ros2_cmd_vel"] != "Twist" and kind not in MOBILE_TASKS:
        raise ScenarioError("outputs.ros2_cmd_vel: a base's commands (/cmd_vel); an arm's bag "
                            "holds /joint_trajectory")  # fmt: skip
    if not robot:
        if outputs["animation"] != "none":
            raise ScenarioError("outputs.animation: animating needs a [robot] table")
        if simulation["engine"] == "mujoco":
            raise ScenarioError("simulation.engine: simulating needs a [robot] table")
    return Scenario(name, description, robot, task, limits, period, simulation, outputs, source,
                    text)  # fmt: skip


def _robot(table: Table, kind: str, folder: Path) -> dict[str, Any]:
    mobile = kind in MOBILE_TASKS
    given = [key for key in ("builtin", "dh", "urdf", "mjcf") if table.has(key)]
    if len(given) != 1:
        raise ScenarioError(f"{table.path}: give exactly one of builtin, dh, urdf or mjcf, got "
                            f"{', '.join(given) or 'none'}")  # fmt: skip
    robot: dict[str, Any]
    if given == ["builtin"]:
        choices = MOBILE_ROBOTS if mobile else ARM_ROBOTS
        robot = {"builtin": table.string("builtin", choices=choices)}
    elif mobile:
        raise ScenarioError(f"{table.where(given[0])}: a {kind} task needs a wheeled builtin "
                            f"robot ({', '.join(MOBILE_ROBOTS)})")  # fmt: skip
    elif given == ["dh"]:
        rows = []
        for row in table.tables("dh"):
            rows.append({
                "a": row.number("a", 0.0),
                "alpha": row.number("alpha", 0.0, angles=True),
                "d": row.number("d", 0.0),
                "theta": row.number("theta", 0.0, angles=True),
                "kind": row.string("kind", "revolute", choices=("revolute", "prismatic")),
                "lower": row.number("lower", float("-inf"), angles=True),
                "upper": row.number("upper", float("inf"), angles=True),
            })  # fmt: skip
            row.done()
        conventions = ("standard", "modified")
        robot = {"dh": rows, "convention": table.string("convention", "standard",
                                                        choices=conventions)}  # fmt: skip
    elif given == ["mjcf"]:
        robot = {"mjcf": (folder / table.string("mjcf")).resolve(),
                 "tip_body": table.string("tip_body", None)}  # fmt: skip
    else:
        urdf = table.string("urdf")
        robot = {
            "urdf": (folder / urdf).resolve(),
            "base_link": table.string("base_link", None),
            "tip_link": table.string("tip_link", None),
        }
    table.done()
    return robot


def _task(table: Table, kind: str) -> dict[str, Any]:
    task: dict[str, Any] = {"kind": kind}
    if kind in ("line", "ellipse", "poses"):
        table = table.renamed({"dt": "ik_step"})
    if kind == "joint_move":
        task["profile"] = table.string("profile", "cubic", choices=tuple(CATALOG))
        entry = CATALOG[task["profile"]]
        task["q0"] = table.numbers("q0", angles=True)
        for quantity in QUANTITIES.values():
            key = quantity.name
            if key in LIMITS or key == "q0" or not table.has(key, angles=quantity.angular):
                continue  # a limit is in [limits]; one left out takes the planner's default
            if not entry.takes(key):
                given = key if key in table.data else f"{key}_deg"
                raise ScenarioError(f"{table.where(given)}: {entry.refusal(key)}")
            task[key] = (
                table.numbers(key, count=task["q0"].size, angles=quantity.angular,
                              scalar_ok=key != "qf")
                if quantity.per_joint else table.number(key, positive=True)
            )  # fmt: skip
        if "qf" not in task:
            task["qf"] = table.numbers("qf", angles=True)  # required: says so
        for option in OPTIONS.values():
            if table.has(option.name):
                if not entry.takes(option.name):
                    raise ScenarioError(f"{table.where(option.name)}: "
                                        f"{entry.refusal(option.name)}")  # fmt: skip
                task[option.name] = table.string(option.name, choices=option.choices)
        if "duration" in task and "min_duration" in task:
            raise ScenarioError(f"{table.where('min_duration')}: give duration (exact) or "
                                "min_duration (a floor), not both")  # fmt: skip
    elif kind == "waypoints":
        task["points"] = table.matrix("points", angles=True, minimum_rows=2)
        task["timing"] = table.string("timing", "blended", choices=("blended", "time_optimal"))
        task["time_optimal"] = task["timing"] == "time_optimal"
        if task["time_optimal"]:
            # A planner's waypoint list: corners cut within the tolerance, timed fastest.
            for key in ("through", "durations"):
                if table.has(key):
                    raise ScenarioError(f"{table.where(key)}: not used with timing = "
                                        "'time_optimal' (it passes near every waypoint "
                                        "as fast as the limits allow)")  # fmt: skip
            task["path_tolerance"] = table.number("path_tolerance", 0.01, angles=True)
            if task["path_tolerance"] < 0:
                raise ScenarioError(f"{table.where('path_tolerance')}: expected >= 0, got "
                                    f"{task['path_tolerance']:g}")  # fmt: skip
            task["timing_grid"] = _timing_grid(table)
        else:
            task["through"] = table.boolean("through", False)
            task["durations"] = table.numbers("durations", None,
                                              count=task["points"].shape[0] - 1,
                                              positive=True)  # fmt: skip
    elif kind == "polynomial":
        task["times"] = table.numbers("times")
        if task["times"].size < 2 or np.any(np.diff(task["times"]) <= 0):
            raise ScenarioError(f"{table.where('times')}: expected at least 2 increasing times")
        if np.abs(task["times"]).max() > MAX_TIME:
            # Powers of time up to the 7th build the system A a = b: they must stay finite.
            raise ScenarioError(f"{table.where('times')}: expected times within ±{MAX_TIME:g} "
                                f"s, got {task['times'].tolist()}")  # fmt: skip
        segments = table.tables("segments")
        if len(segments) != task["times"].size - 1:
            wanted = task["times"].size - 1
            raise ScenarioError(f"{table.where('segments')}: expected {wanted} segments (one "
                                f"per interval of times), got {len(segments)}")  # fmt: skip
        task["conditions"] = []
        for segment in segments:
            rows = segment.matrix("conditions", columns=3)
            orders = rows[:, 1]
            if np.any(orders != np.round(orders)) or np.any(orders < 0) or np.any(orders > 7):
                raise ScenarioError(f"{segment.where('conditions')}: each row is (time, order, "
                                    "value) with a whole order from 0 to 7")  # fmt: skip
            task["conditions"].append([(t, int(order), value) for t, order, value in rows])
            segment.done()
        continuity = table.matrix("continuity", columns=2) if table.has("continuity") else None
        if continuity is not None:
            inner, orders = continuity[:, 0], continuity[:, 1]
            whole = np.all(continuity == np.round(continuity))
            if not whole or np.any(inner < 1) or np.any(inner > task["times"].size - 2) or \
                    np.any(orders < 0) or np.any(orders > 6):  # fmt: skip
                raise ScenarioError(f"{table.where('continuity')}: each row is (interior "
                                    f"breakpoint 1..{task['times'].size - 2}, whole order "
                                    "0..6)")  # fmt: skip
        task["continuity"] = None if continuity is None else [
            (int(index), int(order)) for index, order in continuity
        ]  # fmt: skip
    elif kind == "ellipse":
        task["center"] = table.numbers("center", count=3)
        task["a"] = table.number("a", positive=True)
        task["b"] = table.number("b")
        if task["b"] < 0:
            raise ScenarioError(f"{table.where('b')}: expected a semi-axis >= 0, got {task['b']:g}")
        task["duration"] = table.number("duration", positive=True)
        task["law"] = table.string(
            "law", "linear", choices=("linear", "cubic", "quintic", "septic")
        )
        task["ik_step"] = table.number("ik_step", DEFAULT_STEP, positive=True)
        task["branch"] = table.string("branch", None)
    elif kind == "poses":
        task["poses"] = table.matrix("poses_xyz_rpy_deg", columns=6, minimum_rows=2)
        task["profile"] = table.string("profile", "quintic", choices=("cubic", "quintic",
                                                                      "septic"))  # fmt: skip
        task["durations"] = table.numbers("durations", count=task["poses"].shape[0] - 1,
                                          positive=True)  # fmt: skip
        task["ik_step"] = table.number("ik_step", DEFAULT_STEP, positive=True)
    elif kind == "line":
        task["start"] = table.numbers("start", count=3)
        task["end"] = table.numbers("end", count=3)
        task["law"] = table.string("law", "cubic", choices=("cubic", "quintic", "septic",
                                                            "time_optimal"))  # fmt: skip
        task["time_optimal"] = task["law"] == "time_optimal"
        if task["time_optimal"]:
            if table.has("duration"):
                raise ScenarioError(f"{table.where('duration')}: not used with law = "
                                    "'time_optimal' (the limits set the duration)")  # fmt: skip
            task["timing_grid"] = _timing_grid(table)
        else:
            task["duration"] = table.number("duration", positive=True)
        task["ik_step"] = table.number("ik_step", DEFAULT_STEP, positive=True)
    elif kind == "twist":
        task["v"] = table.number("v")
        task["omega"] = table.number("omega", angles=True)
        task["duration"] = table.number("duration", positive=True)
        task["rate_hz"] = table.number("rate_hz", None, positive=True)
    elif kind == "goto":
        task["goal"] = table.numbers("goal", count=2)
        task["heading"] = table.number("heading", None, angles=True)
        task["start"] = table.numbers("start", (0.0, 0.0), count=2)
        task["start_heading"] = table.number("start_heading", 0.0, angles=True)
        task["profile"] = table.string("profile", "trapezoid", choices=("trapezoid", "scurve"))
        task["blend_ratio"] = table.number("blend_ratio", None, positive=True)
        task["reverse"] = table.boolean("reverse", False)
    else:  # figure8
        task["width"] = table.number("width", 2.0, positive=True)
        task["height"] = table.number("height", 1.0, positive=True)
        task["period"] = table.number("period", 20.0, positive=True)
        task["controller"] = table.string(
            "controller", "feedforward",
            choices=("feedforward", "kanayama", "linearization", "pure-pursuit"),
        )  # fmt: skip
        task["offset"] = table.numbers("offset", (0.0, 0.0), count=2)
        with np.errstate(over="ignore"):  # [1.7e308, 1.7e308]: inf, refused below
            away = float(np.hypot(*task["offset"]))
        if not away <= MAX_TRAVEL:
            raise ScenarioError(f"{table.where('offset')}: expected at most {MAX_TRAVEL:g} m "
                                "from the curve's start, got "
                                f"{task['offset'].tolist()}")  # fmt: skip
        task["offset_heading"] = table.number("offset_heading", 0.0, angles=True)
        task["fit"] = table.boolean("fit", False)
    table.done()
    return task


def _limits(table: Table | None, mobile: bool) -> dict[str, Any]:
    if table is None:
        return {}
    table = table.renamed(OLD_MOBILE_LIMITS if mobile else OLD_ARM_LIMITS)
    keys = MOBILE_LIMITS if mobile else LIMITS
    limits: dict[str, Any] = {}
    for key in keys:
        angular = not mobile or key in MOBILE_ANGULAR
        if table.has(key, angles=angular):
            limits[key] = (table.number(key, angles=angular, positive=True) if mobile
                           else table.numbers(key, angles=angular, scalar_ok=True,
                                              positive=True))  # fmt: skip
    if not mobile:
        if table.has("torque"):
            # true: the robot's own effort limits; else N·m per joint (or one for all).
            given = table.value("torque")
            if given is False:
                raise ScenarioError(f"{table.where('torque')}: expected true (the robot's "
                                    "effort limits) or N·m per joint, got false")  # fmt: skip
            limits["torque"] = True if given is True else table.numbers(
                "torque", scalar_ok=True, positive=True)  # fmt: skip
        for key in TOOL_LIMITS:
            if table.has(key):
                limits[key] = table.number(key, positive=True)
    table.done()
    return limits


def _timing_grid(table: Table) -> int:
    """A time-optimal timing's grid intervals: a whole number, 2 to 100,000."""
    value = table.number("timing_grid", 500)
    if value != round(value) or not 2 <= value <= 100_000:
        raise ScenarioError(f"{table.where('timing_grid')}: expected a whole number of grid "
                            f"intervals from 2 to 100000, got {value:g}")  # fmt: skip
    return int(value)


def _check_timing_limits(limits: dict[str, Any], task: dict[str, Any], robot: dict) -> None:
    """Where torque, tool and jerk limits are kept.

    Torque and tool limits by a time-optimal timing only, of a robot; a jerk limit by a
    time-optimal line's, not by a waypoint list's retiming.
    """
    if task.get("time_optimal") and task.get("kind") == "waypoints" and "jmax" in limits:
        raise ScenarioError("limits.jmax: a time-optimal retiming of waypoints keeps velocity "
                            "and acceleration (and torque and tool) limits, not jerk: remove "
                            "jmax, or use timing = 'blended'")  # fmt: skip
    given = [key for key in ("torque", *TOOL_LIMITS) if key in limits]
    if not given:
        return
    if not task.get("time_optimal"):
        raise ScenarioError(f"limits.{given[0]}: only kept by a time-optimal timing: a "
                            "waypoints task with timing = 'time_optimal' or a line task with "
                            "law = 'time_optimal'")  # fmt: skip
    if not robot:
        raise ScenarioError(f"limits.{given[0]}: needs a [robot] table (its dynamics or its "
                            "tool)")  # fmt: skip


def _check_jerk(limits: dict[str, Any], task: dict[str, Any], kind: str) -> None:
    """A base's jerk limits belong to, and are required by, a goto task's S-curve phases."""
    if kind not in MOBILE_TASKS:
        return
    scurve = kind == "goto" and task["profile"] == "scurve" and task["blend_ratio"] is None
    for key in MOBILE_JERKS:
        if key in limits and not scurve:
            raise ScenarioError(f"limits.{key}: only used by the S-curve phases of a goto "
                                "task (profile = 'scurve', no blend_ratio); remove it")  # fmt: skip
        if scurve and key not in limits:
            phases = "turns" if key in MOBILE_ANGULAR else "drive"
            raise ScenarioError(f"limits.{key}: required by the scurve profile of a goto task "
                                f"(the jerk limit of its {phases})")  # fmt: skip


def _simulation(table: Table | None, mobile: bool) -> dict[str, Any]:
    if table is None:
        return {"engine": "kinematic"}
    arm_controllers = ("position", "velocity", "pd_feedforward", "computed_torque")
    simulation = {
        "engine": table.string("engine", "kinematic", choices=("kinematic", "mujoco")),
        "rate_hz": table.number("rate_hz", None, positive=True),
    }
    if mobile:
        simulation["drive"] = table.string("drive", "differential",
                                           choices=("differential", "skid_steer"))  # fmt: skip
        if table.has("drive") and simulation["engine"] != "mujoco":
            raise ScenarioError(f"{table.where('drive')}: the wheels MuJoCo drives: only used "
                                "with engine = 'mujoco'")  # fmt: skip
    if not mobile:
        simulation["controller"] = table.string("controller", "position", choices=arm_controllers)
        if simulation["engine"] == "kinematic":
            for key in ("rate_hz", "controller"):
                if table.has(key):
                    raise ScenarioError(f"{table.where(key)}: only used with engine = 'mujoco' "
                                        "(a kinematic arm follows its plan exactly)")  # fmt: skip
    table.done()
    return simulation


def _controller_name(table: Table) -> str | None:
    """A joint trajectory controller's name (its topic ``/<name>/joint_trajectory``)."""
    name = table.string("ros2_controller", None)
    if name is not None and not re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", name):
        raise ScenarioError(f"{table.where('ros2_controller')}: expected a ROS name such as "
                            f"joint_trajectory_controller, got {name!r}")  # fmt: skip
    return name


#: The last second ROS time holds (builtin_interfaces/Time counts seconds in 32 bits).
_LAST_SECOND = 2**31 - 1


def _bag_start(table: Table) -> int:
    """The bag time of the plan's start (ns): a TOML date-time with its offset, or seconds.

    ``ros2_start = 2026-12-07T09:00:00Z`` or ``ros2_start = 1796634000`` (seconds since
    1970, UTC); without it, 0 (1970-01-01).
    """
    if not table.has("ros2_start"):
        return 0
    given, where = table.value("ros2_start"), table.where("ros2_start")
    if isinstance(given, datetime.datetime):
        if given.tzinfo is None:
            raise ScenarioError(f"{where}: a date-time needs its offset from UTC, e.g. "
                                f"{given.isoformat()}Z")  # fmt: skip
        since = given - datetime.datetime(1970, 1, 1, tzinfo=datetime.UTC)
        nanoseconds = (since.days * 86_400 + since.seconds) * 10**9 + since.microseconds * 1000
    elif isinstance(given, (int, float)) and not isinstance(given, bool) and math.isfinite(given):
        nanoseconds = round(given * 10**9) if isinstance(given, float) else given * 10**9
    else:
        raise ScenarioError(f"{where}: expected a date-time such as 2026-12-07T09:00:00Z or "
                            f"seconds since 1970, got {given!r}")  # fmt: skip
    if not 0 <= nanoseconds <= _LAST_SECOND * 10**9:
        raise ScenarioError(f"{where}: expected a time from 1970 to 2038-01-19 (ROS time counts "
                            f"seconds in 32 bits), got {given!r}")  # fmt: skip
    return int(nanoseconds)


def _outputs(table: Table | None) -> dict[str, Any]:
    defaults = {"csv": True, "json": False, "npz": False, "plot": True, "animation": "none",
                "animation_view": "3d", "animation_fps": 10.0,
                "animation_speed": 1.0, "ros2_bag": False, "ros2_stream": "none",
                "ros2_cmd_vel": "Twist", "ros2_controller": None, "ros2_start_ns": 0,
                "storage": "mcap",
                "sample_step": None}  # fmt: skip
    if table is None:
        return defaults
    outputs = {
        "csv": table.boolean("csv", True),
        "json": table.boolean("json", False),
        "npz": table.boolean("npz", False),
        "plot": table.boolean("plot", True),
        "animation": table.string("animation", "none", choices=ANIMATIONS),
        "animation_view": table.string("animation_view", "3d", choices=("3d", "xy", "xz", "yz")),
        "animation_fps": table.number("animation_fps", 10.0, positive=True),
        "animation_speed": table.number("animation_speed", 1.0, positive=True),
        "ros2_bag": table.boolean("ros2_bag", False),
        "ros2_stream": table.string(
            "ros2_stream", "none", choices=("none", "joint_state", "point")
        ),
        "ros2_cmd_vel": table.string("ros2_cmd_vel", "Twist", choices=("Twist", "TwistStamped")),
        "ros2_controller": _controller_name(table),
        "ros2_start_ns": _bag_start(table),
        "storage": table.string("storage", "mcap", choices=("mcap", "sqlite3")),
        "sample_step": table.number("sample_step", None, positive=True),
    }
    if not 0.1 <= outputs["animation_fps"] <= 100.0:
        raise ScenarioError(f"{table.where('animation_fps')}: expected 0.1 to 100 frames/s, got "
                            f"{outputs['animation_fps']:g}")  # fmt: skip
    if not 1e-3 <= outputs["animation_speed"] <= 1e3:
        raise ScenarioError(f"{table.where('animation_speed')}: expected 0.001 to 1000, got "
                            f"{outputs['animation_speed']:g}")  # fmt: skip
    table.done()
    return outputs
