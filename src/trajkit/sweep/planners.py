"""What each planner of a sweep takes, and how a chunk of its problems is planned.

Every planner turns one chunk's inputs into the same kind of rows: ``duration``
(s), ``feasible`` (planned and every limit kept), ``worst_violation`` (the largest
``peak / bound - 1`` over the checked limits, 0 when no peak passes its bound,
``inf`` for an unbounded derivative), the peaks per joint (or per base quantity:
``v`` and ``ω``, and the left and right wheel speeds of a base with a wheel limit)
and ``error`` (the message, empty when planned). A problem that cannot be planned
is a row with its error, never an exception.

The problem-by-problem planners take ``feasible`` from the limit check the Python
API runs (``Report.ok`` of the plan's ``check``, which allows ``rtol`` = 1e-9 of
each bound for rounding); a mobile base is planned and checked with its own
limits, wheel speeds included, the sweep's ``vmax``, ``wmax``, ``amax`` and
``alpha_max`` replacing those four.

The trapezoid and S-curve planners plan a whole chunk in one batch call
(:mod:`trajkit.batch`) and read the peaks off the phases exactly; if the batch
refuses, the chunk is halved until the refusing problems stand alone. The
others plan problem by problem: they are not batch planners.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass
from functools import partial
from typing import Any

import numpy as np

from trajkit._validation import FloatArray
from trajkit.errors import InvalidInputError, TrajkitError
from trajkit.limits import Report
from trajkit.planners import CATALOG, OPTIONS, QUANTITIES
from trajkit.planners import Planner as CatalogPlanner
from trajkit.scenario.reader import ScenarioError, Table
from trajkit.tolerances import LIMIT_RTOL, ROUNDING_RTOL

__all__ = ["OPTIONAL", "PLANNERS", "ChunkResult", "Planner"]

#: The default of a parameter left out (of the inputs and the rows) unless the file gives it.
OPTIONAL = "optional"


@dataclass
class ChunkResult:
    """A chunk's rows, as columns, and optionally its sampled trajectories.

    ``samples`` is ``(values, lengths)``: ``values`` of shape ``(n, T, width)``
    sampled every ``step`` from t = 0 (NaN past each problem's end) and the
    number of valid samples of each.
    """

    columns: dict[str, np.ndarray]
    samples: tuple[FloatArray, np.ndarray] | None = None


Run = Callable[[dict[str, Any], dict[str, Any], dict[str, FloatArray], float | None], ChunkResult]


@dataclass(frozen=True)
class Planner:
    """One planner's parameters (name → default; None = required), options and runner.

    A parameter whose default is :data:`OPTIONAL` is in a chunk's values only when the
    sweep file gives it.
    """

    parameters: dict[str, Any]
    options: dict[str, Any]
    robot: Callable[[Table], dict[str, Any]]
    widths: Callable[[dict[str, Any], dict[str, Any]], dict[str, int]]
    run: Run


# --------------------------------------------------------------------------- rows
def _empty(n: int, width: int, quantities: tuple[str, ...],
           widths: dict[str, int] | None = None) -> dict[str, np.ndarray]:  # fmt: skip
    """Empty rows; ``widths`` gives a quantity's entries where they are not ``width``."""
    columns: dict[str, np.ndarray] = {
        "duration": np.full(n, np.nan),
        "feasible": np.zeros(n, dtype=bool),
        "worst_violation": np.full(n, np.nan),
    }
    for quantity in quantities:
        for j in range((widths or {}).get(quantity, width)):
            columns[f"peak_{_column(quantity)}_{j + 1}"] = np.full(n, np.nan)
    columns["error"] = np.full(n, "", dtype=object)
    return columns


def _fill(columns: dict[str, np.ndarray], where: np.ndarray, duration: FloatArray,
          peaks: dict[str, FloatArray], ratios: dict[str, FloatArray],
          verdict: np.ndarray | None = None) -> None:  # fmt: skip
    """Rows ``where``: durations, peaks ``(k, width)``, and their worst ``peak / bound``.

    ``verdict`` is each row's limit check (``Report.ok``); without it a row is
    feasible when no ratio passes 1 by more than
    :data:`~trajkit.tolerances.LIMIT_RTOL`, the check's own rule
    for symmetric bounds.
    """
    columns["duration"][where] = duration
    worst = np.zeros(where.size)
    for quantity, peak in peaks.items():
        for j in range(peak.shape[1]):
            columns[f"peak_{_column(quantity)}_{j + 1}"][where] = peak[:, j]
        worst = np.maximum(worst, (ratios[quantity] - 1.0).max(axis=1))
    columns["worst_violation"][where] = np.maximum(worst, 0.0)
    # NaN (a peak that is not a number) is no proof of feasibility: `<=` says False;
    # nor is a plan without a finite duration.
    kept = worst <= LIMIT_RTOL if verdict is None else verdict
    columns["feasible"][where] = kept & np.isfinite(duration)


def _column(quantity: str) -> str:
    """A quantity's name in column names: "tool speed" is ``peak_tool_speed_1``."""
    return quantity.replace(" ", "_")


def _failed(columns: dict[str, np.ndarray], index: int, error: Exception,
            *, batched: bool = False) -> None:  # fmt: skip
    message = f"{type(error).__name__}: {error}".replace("\n", " ")
    if batched:  # a batch planner numbers problems within the batch it was given:
        # the row is the problem, so its position in some batch would only mislead.
        message = re.sub(r" \(problem \d+\)| in problem \d+|\bproblem \d+[,:] ", "", message)
    columns["error"][index] = message


# ---------------------------------------------------------------- batch planners
def _joints_robot(table: Table) -> dict[str, Any]:
    joints = table.number("joints", 6)
    if joints != int(joints) or not 1 <= joints <= 64:
        raise ScenarioError(f"{table.where('joints')}: expected a whole number from 1 to 64")
    return {"joints": int(joints)}


def _joint_widths(names: tuple[str, ...], **fixed: int) -> Callable[[dict, dict], dict[str, int]]:
    """One number per joint for each of ``names``; ``fixed`` names those of a set width."""
    return lambda robot, options: dict.fromkeys(names, robot["joints"]) | fixed


def _phase_peaks(plan: Any) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Exact peaks of |velocity|, |acceleration|, |jerk| per problem and joint."""
    d, a, j = plan.durations, plan.accelerations, plan.jerks
    used = d > 0.0
    # Terms of a zero jerk or acceleration are left out, not computed: a phase of
    # 1e300 s (vmax = 1e-300) would make them 0 * inf = NaN.
    dv = np.where(a != 0.0, a * d, 0.0) + np.where(j != 0.0, j * d**2 / 2.0, 0.0)
    v = plan.velocity[..., np.newaxis] + np.concatenate(
        [np.zeros_like(dv[..., :1]), np.cumsum(dv[..., :-1], axis=-1)], axis=-1
    )  # each phase's starting velocity
    v_end = v + dv
    with np.errstate(divide="ignore", invalid="ignore"):
        vertex = np.where(j != 0.0, -a / j, -1.0)
    inside = used & (vertex > 0.0) & (vertex < d)
    v_mid = np.where(inside, v + a * vertex + j * vertex**2 / 2.0, 0.0)
    speed = np.max(np.where(used, np.maximum(np.abs(v), np.abs(v_end)), 0.0), axis=-1)
    speed = np.maximum(speed, np.max(np.abs(v_mid), axis=-1))
    accel = np.max(np.where(used, np.maximum(np.abs(a), np.abs(a + j * d)), 0.0), axis=-1)
    jerk = np.max(np.where(used, np.abs(j), 0.0), axis=-1)
    return speed, accel, jerk


def _batched(
    plan_batch: Callable[[np.ndarray], Any],
    n: int,
    columns: dict[str, np.ndarray],
    bounds_of: Callable[[np.ndarray], dict[str, FloatArray]],
    quantities: tuple[str, ...],
) -> list[tuple[np.ndarray, Any]]:
    """Plan rows ``0..n-1`` in batches, halving a refused batch down to single problems."""
    done: list[tuple[np.ndarray, Any]] = []
    pending = [np.arange(n)]
    while pending:
        rows = pending.pop()
        try:
            plans = plan_batch(rows)
        except TrajkitError as exc:
            if rows.size == 1:
                _failed(columns, int(rows[0]), exc, batched=True)
                continue
            half = rows.size // 2
            pending += [rows[half:], rows[:half]]
            continue
        peaks = dict(zip(("velocity", "acceleration", "jerk"), _phase_peaks(plans.plan),
                         strict=True))  # fmt: skip
        bounds = bounds_of(rows)  # symmetric magnitudes
        with np.errstate(divide="ignore", invalid="ignore"):
            ratios = {q: np.where(bounds[q] > 0, peaks[q] / bounds[q], np.inf)
                      for q in quantities}  # fmt: skip
        _fill(columns, rows, plans.durations, {q: peaks[q] for q in quantities}, ratios)
        done.append((rows, plans))
    return done


#: The most memory one chunk's samples may take (bytes).
MAX_SAMPLE_BYTES = 2**31

#: About how much of the samples one evaluation of a batch makes at once (bytes): its
#: temporaries are several times that, so the chunk's buffer is filled in slices.
_EVALUATION_BYTES = 2**26


def _sample_counts(durations: FloatArray, step: float, width: int) -> np.ndarray:
    """How many samples at ``0, step, ...`` fit each duration (1 if not planned).

    Rounded as ``Trajectory.sample`` rounds its grid. The counts are found in floating
    point and the chunk's room for them is checked before anything is allocated:
    a count past ``int64`` must be refused, not wrapped round to a negative length.

    Raises
    ------
    InvalidInputError
        The chunk's samples would take more than :data:`MAX_SAMPLE_BYTES`.
    """
    finite = np.where(np.isfinite(durations), durations, 0.0)
    with np.errstate(over="ignore"):  # a denormal step: inf samples, refused below
        counts = np.floor(finite / step * (1.0 + ROUNDING_RTOL)) + 1.0
    longest = int(np.argmax(counts)) if counts.size else 0
    largest = float(counts[longest]) if counts.size else 1.0
    size = float(counts.size) * largest * width * 8.0
    if not size <= MAX_SAMPLE_BYTES:
        raise InvalidInputError(
            f'keep = "samples" with sample_step = {step:.6g} s: a {finite[longest]:.6g} s '
            f"trajectory has {largest:.6g} samples, and {counts.size} problems of up to "
            f"that many need {size / 2**30:.3g} GiB per chunk, more than the "
            f"{MAX_SAMPLE_BYTES / 2**30:g} GiB allowed: use a smaller chunk or a longer sample_step"
        )
    return counts.astype(np.int64)


def _sample_buffer(n: int, count: int, width: int) -> tuple[FloatArray, np.ndarray]:
    """NaN-filled room for ``n`` problems of ``count`` samples each, and their lengths.

    Only called with counts :func:`_sample_counts` has checked.
    """
    return np.full((n, count, width), np.nan), np.zeros(n, dtype=np.int64)


def _batch_samples(done: list[tuple[np.ndarray, Any]], n: int, width: int, step: float,
                   durations: FloatArray) -> tuple[FloatArray, np.ndarray]:  # fmt: skip
    counts = _sample_counts(durations, step, width)
    count = int(counts.max())
    times = np.arange(count) * step
    values, lengths = _sample_buffer(n, count, width)
    for rows, plans in done:  # one evaluation per planned batch and slice of times
        own = counts[rows]
        step = max(1, _EVALUATION_BYTES // max(1, rows.size * width * 8))
        for first in range(0, count, step):
            block = slice(first, min(first + step, count))
            mask = np.arange(block.start, block.stop)[None, :] < own[:, None]
            values[rows, block] = np.where(mask[:, :, None], plans.evaluate(times[block]), np.nan)
        lengths[rows] = own
    return values, lengths


#: The batch rows' name of each catalog limit's quantity.
_QUANTITY = {"vmax": "velocity", "amax": "acceleration", "jmax": "jerk"}


def _row_values(entry: CatalogPlanner, values: dict, rows: np.ndarray | int) -> dict[str, Any]:
    """The catalog planner's inputs for ``rows``: per-joint columns, one number per move."""
    return {name: values[name][rows] if QUANTITIES[name].per_joint else values[name][rows, 0]
            for name in values}  # fmt: skip


def _run_catalog(entry: CatalogPlanner, robot: dict, options: dict, values: dict,
                 step: float | None) -> ChunkResult:  # fmt: skip
    """A catalog planner's chunk: one batch call where it has one, else problem by problem.

    An exact ``duration`` is no batch planner's input: such moves are planned one by one.
    Every limit given is checked; the peaks kept are those of the limited quantities.
    A polynomial of a given duration is planned without its (optional) limits and then
    checked against them, so that a move too fast for them is a row with its peaks
    and worst violation rather than an error.
    """
    n, width = values["q0"].shape
    given = [name for name in entry.limits if name in values]
    quantities = tuple(_QUANTITY[name] for name in given)
    if entry.batch is None or "duration" in values:
        import trajkit as tk

        check_only = set(given) - set(entry.needs) if "duration" in values else set()

        def plan_one(i: int) -> tuple[Any, Report]:
            inputs = _row_values(entry, values, i)
            plan = entry.plan({k: v for k, v in inputs.items() if k not in check_only} | options)
            limits = tk.Limits(**{_QUANTITY[name]: values[name][i] for name in given})
            return plan, plan.check(limits)

        return _one_by_one(n, width, quantities, plan_one, step, lambda p, t: p.position(t))

    from trajkit import batch

    columns = _empty(n, width, quantities)
    planner = getattr(batch, entry.batch)

    def plan(rows: np.ndarray) -> Any:
        return planner(**_row_values(entry, values, rows), **options)

    def bounds(rows: np.ndarray) -> dict[str, FloatArray]:
        return {_QUANTITY[name]: values[name][rows] for name in given}

    done = _batched(plan, n, columns, bounds, quantities)
    samples = None
    if step is not None:
        samples = _batch_samples(done, n, width, step, columns["duration"])
    return ChunkResult(columns, samples)


def _catalog_planner(entry: CatalogPlanner) -> Planner:
    """The sweep's side of a catalog planner: its parameters, defaults and widths.

    ``q0``, ``qf`` and the limits the planner needs are required; an input with a
    default takes it; the others are left out unless the sweep file gives them. A
    sweep has no controller period, so the ``grid`` option is not offered.
    """
    names = ("q0", "qf", *entry.inputs, *entry.limits)
    parameters: dict[str, Any] = {}
    for name in names:
        default = QUANTITIES[name].default
        required = name in ("q0", "qf", *entry.needs)
        parameters[name] = None if required else OPTIONAL if default is None else default
    options = {name: (OPTIONS[name].default, OPTIONS[name].choices)
               for name in entry.options if name != "grid"}  # fmt: skip

    def widths(robot: dict, options: dict) -> dict[str, int]:
        return {name: robot["joints"] if QUANTITIES[name].per_joint else 1 for name in names}

    return Planner(parameters, options, _joints_robot, widths, partial(_run_catalog, entry))


# ------------------------------------------------------- problem-by-problem planners
def _one_by_one(
    n: int,
    width: int,
    quantities: tuple[str, ...],
    plan_one: Callable[[int], tuple[Any, Report]],
    step: float | None,
    sample: Callable[[Any, FloatArray], FloatArray],
    widths: dict[str, int] | None = None,
) -> ChunkResult:
    """Plan each problem: ``plan_one(i)`` gives the plan and its limit check.

    A row is feasible exactly when its check is ``ok``; its worst violation also
    counts the check's violations (an unbounded derivative where two pieces meet
    is a violation of value ``inf`` whatever the peaks say). ``widths`` gives a
    quantity's entries where they are not ``width`` (a tool speed has one).
    """
    columns = _empty(n, width, quantities, widths)
    plans: dict[int, Any] = {}
    peaks: dict[str, list[FloatArray]] = {q: [] for q in quantities}
    ratios: dict[str, list[FloatArray]] = {q: [] for q in quantities}
    verdicts: list[bool] = []
    for i in range(n):
        try:
            plan, report = plan_one(i)
        except TrajkitError as exc:
            _failed(columns, i, exc)
            continue
        plans[i] = plan
        verdicts.append(report.ok)
        beyond = _violation_ratio(report)
        for quantity in quantities:
            low, high = report.peaks[quantity]
            peaks[quantity].append(np.maximum(np.abs(low), np.abs(high)))
            ratios[quantity].append(np.maximum(report.ratios(quantity), beyond))
    if plans:  # the rows of every planned problem at once
        where = np.fromiter(plans, dtype=np.int64)
        _fill(columns, where, np.array([plan.duration for plan in plans.values()]),
              {q: np.array(peaks[q]) for q in quantities},
              {q: np.array(ratios[q]) for q in quantities}, np.array(verdicts))  # fmt: skip
    if step is None:
        return ChunkResult(columns)
    counts = _sample_counts(columns["duration"], step, width)
    values, lengths = _sample_buffer(n, int(counts.max()), width)
    for i, plan in plans.items():
        values[i, : counts[i]] = sample(plan, np.arange(counts[i]) * step)
        lengths[i] = counts[i]
    return ChunkResult(columns, (values, lengths))


def _violation_ratio(report: Report) -> float:
    """The largest ``|value| / |bound|`` of the check's violations (0 without any).

    A violation passes its bound by more than the tolerance, so this is above 1
    for every report that is not ``ok``: the row's worst violation cannot be 0
    while it is infeasible.
    """
    worst = 0.0
    with np.errstate(divide="ignore", invalid="ignore"):
        for violation in report.violations:
            bound = abs(violation.bound)
            ratio = abs(violation.value) / bound if bound > 0 else np.inf
            worst = max(worst, float(ratio) if ratio == ratio else np.inf)  # NaN: unbounded
    return worst


def _run_topp(robot: dict, options: dict, values: dict, step: float | None) -> ChunkResult:
    import trajkit as tk

    n, width = values["vmax"].shape
    points = options["points"]
    knots = np.linspace(0.0, 1.0, points)
    quantities = ("velocity", "acceleration")

    def plan_one(i: int) -> tuple[Any, Report]:
        way = values["waypoints"][i].reshape(points, width)
        path = tk.cubic_spline(knots, way, bc="natural")
        limits = tk.Limits(velocity=values["vmax"][i], acceleration=values["amax"][i])
        timed = tk.topp(path, limits, grid=options["grid"])
        return timed, timed.check(limits)

    return _one_by_one(n, width, quantities, plan_one, step, lambda p, t: p.position(t))


def _arm_robot(table: Table) -> dict[str, Any]:
    from trajkit.kinematics import BUILTIN

    name = table.string("name", "ur5", choices=sorted(BUILTIN))
    arm = BUILTIN[name]()
    return {"name": name, "joints": arm.ndof, "arm": arm}


def _run_task_space(robot: dict, options: dict, values: dict, step: float | None
                    ) -> ChunkResult:  # fmt: skip
    import trajkit as tk
    from trajkit.taskspace import Line, time_optimal

    arm = robot["arm"]
    n = values["p0"].shape[0]
    width = arm.ndof
    # Torque and tool speed limits, when the sweep gives them, are kept by the timing
    # and counted in each row's check.
    extra = [name for name in ("torque", "tool_speed") if name in values]
    quantities = ("velocity", "acceleration", *(name.replace("_", " ") for name in extra))

    def plan_one(i: int) -> tuple[Any, Report]:
        limits = tk.Limits(velocity=values["vmax"][i], acceleration=values["amax"][i])
        path_limits = []
        if "torque" in values:
            path_limits.append(tk.TorqueLimit(arm, values["torque"][i]))
        if "tool_speed" in values:
            path_limits.append(tk.ToolLimit(arm, speed=float(values["tool_speed"][i, 0])))
        move = time_optimal(arm, Line(values["p0"][i], values["pf"][i]), limits,
                            samples=options["samples"], grid=options["grid"],
                            constraints=path_limits)  # fmt: skip
        plan = move.trajectory  # its torque and tool reports: the timing's own measure
        return plan, plan.check(limits).merged(*plan.info.get("constraint_checks", ()))

    return _one_by_one(n, width, quantities, plan_one, step, lambda p, t: p.position(t),
                       {"tool speed": 1})  # fmt: skip


def _base_robot(table: Table) -> dict[str, Any]:
    from trajkit.mobile.models import BASES

    name = table.string("name", "jackal", choices=sorted(BASES))
    return {"name": name, "model": BASES[name]()}


def _run_mobile(robot: dict, options: dict, values: dict, step: float | None) -> ChunkResult:
    from trajkit import mobile

    model = robot["model"]
    n = values["goal"].shape[0]
    # The base's own limits, wheel speeds included; the sweep's numbers replace only
    # the four it names, as the same keywords do in the Python API.
    wheels = getattr(model.limits, "wheel_speed", None) is not None
    quantities = ("velocity", "acceleration", *(("wheel_speed",) if wheels else ()))

    def plan_one(i: int) -> tuple[Any, Report]:
        plan = mobile.rotate_translate_rotate(
            values["goal"][i], values["start"][i], model=model,
            vmax=float(values["vmax"][i, 0]), wmax=float(values["wmax"][i, 0]),
            amax=float(values["amax"][i, 0]), alpha_max=float(values["alpha_max"][i, 0]),
            profile=options["profile"],
        )  # fmt: skip
        return plan, _base_report(plan.check())  # checked against the limits it was planned for

    def sample(plan: Any, t: FloatArray) -> FloatArray:  # the base's position (x, y)
        state = plan.state(t)
        return np.stack([state.x, state.y], axis=1)

    return _one_by_one(n, 2, quantities, plan_one, step, sample)


def _base_report(report: Report) -> Report:
    """A base's check with (v, ω) as the two channels of velocity, and of acceleration.

    The wheel speeds, when checked, stay one quantity of two channels (left, right);
    the violations and so the verdict are the check's own.
    """
    pairs = {"velocity": ("velocity", "angular velocity"),
             "acceleration": ("acceleration", "angular acceleration")}  # fmt: skip
    peaks, bounds = {}, {}
    for quantity, names in pairs.items():
        peaks[quantity] = tuple(np.concatenate([report.peaks[n][k] for n in names])
                                for k in (0, 1))  # fmt: skip
        bounds[quantity] = tuple(np.concatenate([report.bounds[n][k] for n in names])
                                 for k in (0, 1))  # fmt: skip
    if "wheel speed" in report.peaks:
        peaks["wheel_speed"] = report.peaks["wheel speed"]
        bounds["wheel_speed"] = report.bounds["wheel speed"]
    return Report(report.violations, peaks, bounds)


def _mobile_widths(robot: dict, options: dict) -> dict[str, int]:
    return {"goal": 3, "start": 3, "vmax": 1, "wmax": 1, "amax": 1, "alpha_max": 1}


def _model_limit(attribute: str, key: str) -> Callable[[dict], float]:
    def default(robot: dict) -> float:
        value = robot["model"].limits.magnitude(attribute)
        if value is None:
            raise ScenarioError(
                f"fixed.{key}: required ({robot['name']} has no default {attribute} limit)"
            )
        return value

    return default


#: The planners a sweep can name: the catalog's, and three of its own.
PLANNERS: dict[str, Planner] = {
    **{name: _catalog_planner(entry) for name, entry in CATALOG.items()},
    "topp": Planner(
        {"waypoints": None, "vmax": None, "amax": None},
        {"points": 5, "grid": 200}, _joints_robot,
        lambda robot, options: {"waypoints": options["points"] * robot["joints"],
                                "vmax": robot["joints"], "amax": robot["joints"]},
        _run_topp,
    ),
    "task_space": Planner(
        {"p0": None, "pf": None, "vmax": None, "amax": None, "torque": OPTIONAL,
         "tool_speed": OPTIONAL},
        {"samples": 100, "grid": 200}, _arm_robot,
        lambda robot, options: {"p0": 3, "pf": 3, "vmax": robot["joints"],
                                "amax": robot["joints"], "torque": robot["joints"],
                                "tool_speed": 1},
        _run_task_space,
    ),
    "mobile": Planner(
        {"goal": None, "start": 0.0, "vmax": _model_limit("velocity", "vmax"),
         "wmax": _model_limit("angular_velocity", "wmax"),
         "amax": _model_limit("acceleration", "amax"),
         "alpha_max": _model_limit("angular_acceleration", "alpha_max")},
        {"profile": ("trapezoid", ("trapezoid",))}, _base_robot, _mobile_widths,
        _run_mobile,
    ),
}  # fmt: skip
