"""Sweep files: which planner, which robot, fixed and swept parameters, what to keep.

A sweep file is TOML::

    [sweep]
    name = "six-joint trapezoids"
    planner = "trapezoid"   # cubic, quintic, septic, trapezoid, scurve (trajkit.planners),
                            # or topp, task_space, mobile
    problems = 100000       # default: one per combination of the grids and value lists
    chunk = 10000           # problems per output file (and per task)
    seed = 1
    keep = "summary"        # or "samples": also the sampled trajectories, every
    sample_step = 0.01      #   sample_step seconds

    [robot]
    joints = 6              # joint planners; task_space: name = "ur5"; mobile: name = "jackal"

    [fixed]
    vmax = 1.0              # a number, or one per component

    [swept]
    q0 = { uniform = [-3.14, 3.14] }   # drawn per problem and component
    qf = { normal = [0.0, 1.0] }
    amax = { grid = [1.0, 4.0, 4] }    # start, stop, count

The planner's options (``sync`` for trapezoid and S-curve: ``"time"``, ``"phase"``,
``"time_if_necessary"`` or ``"none"``; ``points`` and ``grid``, ``samples``) go in
``[sweep]`` too; they are fixed for the sweep.

A joint planner's parameters are those of its :data:`trajkit.planners.CATALOG`
entry, named as in Python: ``q0``, ``qf``, the limits ``vmax``, ``amax``, ``jmax``
(required where the planner needs them, checked wherever given), ``v0``, ``vf``
(default 0), ``a0``, ``af`` (default 0; quintic, septic, scurve), ``duration`` (s,
one number per problem: exact) and ``min_duration`` (trapezoid, scurve: a floor).
Trapezoids and S-curves without an exact duration are planned a chunk at a time.

Grids and value lists combine as a Cartesian product, problem ``i`` taking
combination ``i mod (their count)``; random parameters are drawn, for each chunk,
from a generator seeded with ``(seed, chunk index)``: a problem's inputs depend
only on the file and its number, never on the engine or the order of execution.
Every mistake in the file raises a :class:`SweepError` naming its key.
"""

from __future__ import annotations

import hashlib
import json
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from trajkit._validation import FloatArray
from trajkit.samples import DEFAULT_STEP
from trajkit.scenario.reader import ScenarioError, Table
from trajkit.sweep.planners import OPTIONAL, PLANNERS, Planner

__all__ = ["Distribution", "SweepError", "SweepSpec", "load", "parse"]

#: More problems than this in one sweep file are refused (a typo, not a plan).
MAX_PROBLEMS = 10**10

#: More chunks (output files) than this are refused: the run lists them all.
MAX_CHUNKS = 10**6

#: The most memory one chunk's inputs may take (bytes); the planners need several
#: times as much on top of them.
MAX_CHUNK_INPUT_BYTES = 2**28

#: The most points one grid may have.
MAX_GRID_POINTS = 10**6


class SweepError(ScenarioError):
    """A sweep file breaks a rule; the message names the key and the rule."""


@dataclass(frozen=True)
class Distribution:
    """How one parameter varies: ``fixed``, ``uniform``, ``normal``, ``grid`` or ``values``.

    ``arguments`` holds the numbers (``(low, high)``, ``(mean, std)``, the fixed
    value) as arrays broadcast to the parameter's width; ``choices`` the grid's or
    list's values, shape ``(count, width)``.
    """

    kind: str
    arguments: tuple[FloatArray, ...] = ()
    choices: FloatArray | None = None


@dataclass(frozen=True)
class SweepSpec:
    """A parsed sweep file.

    Attributes
    ----------
    name, planner : str
    options : dict
        The planner's string and integer options (``sync``, ``profile``, ``grid``...).
    robot : dict
        ``joints`` or ``name`` and the sizes derived from it (``widths``).
    parameters : dict of Distribution
        Every parameter of the planner, fixed or swept.
    problems, chunk, seed : int
    keep : {"summary", "samples"}
    sample_step : float
        The sampling step (s) when keeping samples.
    text : str
        The canonical form the resume check compares.
    """

    name: str
    planner: str
    options: dict[str, Any]
    robot: dict[str, Any]
    widths: dict[str, int]
    parameters: dict[str, Distribution]
    problems: int
    chunk: int
    seed: int
    keep: str
    sample_step: float
    text: str

    @property
    def chunks(self) -> int:
        """Number of chunks (output files)."""
        return -(-self.problems // self.chunk)

    @property
    def digest(self) -> str:
        """A fingerprint of everything that decides the rows (hex)."""
        return hashlib.sha256(self.text.encode()).hexdigest()[:16]

    @property
    def plan(self) -> Planner:
        """The planner's adapter."""
        return PLANNERS[self.planner]

    def combinations(self) -> int:
        """How many combinations the grids and value lists make (1 without any)."""
        count = 1
        for distribution in self.parameters.values():
            if distribution.choices is not None:
                count *= distribution.choices.shape[0]
        return count

    def inputs(self, chunk: int) -> tuple[np.ndarray, dict[str, FloatArray]]:
        """Problem numbers and parameter values of ``chunk``: each ``(n, width)``."""
        first = chunk * self.chunk
        ids = np.arange(first, min(first + self.chunk, self.problems), dtype=np.int64)
        rng = np.random.default_rng([self.seed, chunk])
        listed = [name for name, d in self.parameters.items() if d.choices is not None]
        sizes = [self.parameters[name].choices.shape[0] for name in listed]
        combination = ids % max(int(np.prod(sizes)), 1)
        picks = np.unravel_index(combination, sizes) if listed else ()
        values: dict[str, FloatArray] = {}
        for name, where in zip(listed, picks, strict=True):
            values[name] = self.parameters[name].choices[where]
        for name in sorted(self.parameters):  # a fixed order: the draws do not depend on it
            distribution = self.parameters[name]
            width = self.widths[name]
            if distribution.kind == "fixed":
                values[name] = np.broadcast_to(distribution.arguments[0], (ids.size, width))
            elif distribution.kind == "uniform":
                low, high = distribution.arguments
                values[name] = rng.uniform(low, high, (ids.size, width))
            elif distribution.kind == "normal":
                mean, std = distribution.arguments
                values[name] = rng.normal(mean, std, (ids.size, width))
        return ids, values


def load(path: str | Path) -> SweepSpec:
    """Read and check a sweep file.

    Raises
    ------
    SweepError
        Missing, unreadable (a folder, not UTF-8), not TOML, or any rule broken; the
        message names the file or the key.
    """
    source = Path(path)
    if source.is_dir():  # read_text would say "Is a directory" without the path
        raise SweepError(f"cannot read the sweep file {source}: it is a folder, not a file")
    try:
        raw = source.read_bytes()
    except OSError as exc:
        reason = exc.strerror or str(exc)
        raise SweepError(f"cannot read the sweep file {source}: {reason}") from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise SweepError(f"cannot read the sweep file {source}: it is not UTF-8 text (byte "
                         f"0x{raw[exc.start]:02x} at offset {exc.start}); TOML is UTF-8"
                         ) from None  # fmt: skip
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SweepError(f"{source} is not valid TOML: {exc}") from None
    return parse(data)


def parse(data: dict[str, Any]) -> SweepSpec:
    """Check a sweep file's parsed TOML (see the module notes for the format)."""
    try:
        return _parse(data)
    except ScenarioError as exc:
        if isinstance(exc, SweepError):
            raise
        raise SweepError(str(exc)) from None


def _parse(data: dict[str, Any]) -> SweepSpec:
    root = Table(data, "")
    head = root.table("sweep", required=True).renamed({"period": "sample_step"})
    name = head.string("name", "sweep")
    if head.data.get("planner") == "polynomial":  # its old name, with profile = "..."
        raise SweepError(f"{head.where('planner')}: 'polynomial' is now named by its law: "
                         "planner = 'cubic', 'quintic' or 'septic'")  # fmt: skip
    planner_name = head.string("planner", choices=sorted(PLANNERS))
    planner = PLANNERS[planner_name]
    options = {key: _option(head, key, default) for key, default in planner.options.items()}
    robot_table = root.table("robot")
    robot = (
        planner.robot(robot_table) if robot_table is not None else planner.robot(Table({}, "robot"))
    )
    if robot_table is not None:
        robot_table.done()
    widths = planner.widths(robot, options)
    fixed = root.table("fixed") or Table({}, "fixed")
    swept = root.table("swept") or Table({}, "swept")
    parameters: dict[str, Distribution] = {}
    for parameter, default in planner.parameters.items():
        width = widths[parameter]
        if fixed.has(parameter) and swept.has(parameter):
            raise SweepError(f"{parameter}: give it in [fixed] or in [swept], not both")
        if fixed.has(parameter):
            value = fixed.numbers(parameter, scalar_ok=True)
            value = _width(value, width, fixed.where(parameter))
            parameters[parameter] = Distribution("fixed", (value,))
        elif swept.has(parameter):
            table = swept.table(parameter)
            parameters[parameter] = _distribution(table, width)
        elif isinstance(default, str) and default == OPTIONAL:
            continue  # left out: the planner goes without it
        elif default is not None:
            parameters[parameter] = Distribution("fixed", (np.broadcast_to(
                np.asarray(default(robot) if callable(default) else default, dtype=float),
                (width,)).copy(),))  # fmt: skip
        else:
            raise SweepError(f"fixed.{parameter}: required by planner {planner_name!r} (give it "
                             "in [fixed] or [swept])")  # fmt: skip
    fixed.done()
    swept.done()
    combinations = 1
    for distribution in parameters.values():
        if distribution.choices is not None:
            combinations *= distribution.choices.shape[0]
    problems = _count(head, "problems", combinations)
    chunk = _count(head, "chunk", min(problems, 10_000))
    chunks = -(-problems // chunk)
    if chunks > MAX_CHUNKS:
        raise SweepError(f"{head.where('chunk')}: {problems} problems in chunks of {chunk} make "
                         f"{chunks} chunks (files), more than {MAX_CHUNKS:.0e}: use a larger "
                         "chunk")  # fmt: skip
    numbers = sum(widths[name] for name in parameters)
    size = min(chunk, problems) * numbers * 8
    if size > MAX_CHUNK_INPUT_BYTES:
        raise SweepError(f"{head.where('chunk')}: {min(chunk, problems)} problems of {numbers} "
                         f"numbers each take {size / 2**20:.0f} MiB of inputs per chunk, more "
                         f"than {MAX_CHUNK_INPUT_BYTES / 2**20:.0f} MiB: use a smaller chunk"
                         )  # fmt: skip
    seed = _count(head, "seed", 0, minimum=0)
    keep = head.string("keep", "summary", choices=("summary", "samples"))
    sample_step = head.number("sample_step", DEFAULT_STEP, positive=True)
    head.done()
    root.done()
    canonical = {
        "planner": planner_name,
        "options": options,
        "robot": {k: v for k, v in robot.items() if isinstance(v, (int, float, str))},
        "parameters": {
            key: [d.kind, [a.tolist() for a in d.arguments],
                  None if d.choices is None else d.choices.tolist()]
            for key, d in sorted(parameters.items())
        },
        "problems": problems, "chunk": chunk, "seed": seed, "keep": keep,
        "sample_step": sample_step,
    }  # fmt: skip
    return SweepSpec(name, planner_name, options, robot, widths, parameters, problems, chunk,
                     seed, keep, sample_step, json.dumps(canonical, sort_keys=True))  # fmt: skip


def _option(head: Table, key: str, default: Any) -> Any:
    if isinstance(default, bool):
        return head.boolean(key, default)
    if isinstance(default, int):  # points, grid, samples: at least 2 of each
        return _count(head, key, default, minimum=2)
    if isinstance(default, tuple):  # (default, choices)
        return head.string(key, default[0], choices=default[1])
    return head.number(key, default, positive=True)


def _count(table: Table, key: str, default: int, *, minimum: int = 1) -> int:
    value = table.number(key, default)
    if value != int(value) or value < minimum or value > MAX_PROBLEMS:
        raise SweepError(f"{table.where(key)}: expected a whole number from {minimum} to "
                         f"{MAX_PROBLEMS:.0e}, got {value!r}")  # fmt: skip
    return int(value)


def _width(value: FloatArray, width: int, where: str) -> FloatArray:
    value = np.atleast_1d(np.asarray(value, dtype=float))
    if value.size == 1:
        return np.full(width, float(value[0]))
    if value.shape != (width,):
        raise SweepError(f"{where}: expected one number or {width}, got {value.size}")
    return value


_KINDS = ("uniform", "normal", "grid", "values")


def _distribution(table: Table, width: int) -> Distribution:
    given = [kind for kind in _KINDS if table.has(kind)]
    if len(given) != 1:
        raise SweepError(f"{table.path}: expected exactly one of {', '.join(_KINDS)}, got "
                         f"{', '.join(sorted(table.data)) or 'nothing'}")  # fmt: skip
    kind = given[0]
    where = table.where(kind)
    if kind in ("uniform", "normal"):
        pair = table.matrix(kind, minimum_rows=2) if _nested(table.data[kind]) else None
        if pair is None:
            numbers = table.numbers(kind)
            if numbers.size != 2:
                pair = "low, high" if kind == "uniform" else "mean, std"
                raise SweepError(f"{where}: expected [{pair}], got {numbers.size} numbers")
            first, second = _width(numbers[0], width, where), _width(numbers[1], width, where)
        else:
            if pair.shape[0] != 2:
                raise SweepError(f"{where}: expected two lists, got {pair.shape[0]}")
            first, second = _width(pair[0], width, where), _width(pair[1], width, where)
        if kind == "uniform" and np.any(second < first):
            raise SweepError(f"{where}: the high end is below the low end")
        with np.errstate(over="ignore"):
            span = second - first  # numpy draws low + (high - low) u: it must be finite
        if kind == "uniform" and not np.all(np.isfinite(span)):
            raise SweepError(f"{where}: high - low overflows float64 (at most 1.8e308)")
        if kind == "normal" and np.any(second < 0):
            raise SweepError(f"{where}: the standard deviation must be >= 0")
        table.done()
        return Distribution(kind, (first, second))
    if kind == "grid":
        numbers = table.numbers(kind)
        if numbers.size != 3 or numbers[2] != int(numbers[2]) or numbers[2] < 1:
            raise SweepError(f"{where}: expected [start, stop, count] with a whole count >= 1")
        if numbers[2] > MAX_GRID_POINTS:
            raise SweepError(f"{where}: a count of {numbers[2]:.0f} points is more than "
                             f"{MAX_GRID_POINTS:.0e}")  # fmt: skip
        points = np.linspace(numbers[0], numbers[1], int(numbers[2]))
        table.done()
        return Distribution(kind, (), np.repeat(points[:, None], width, axis=1))
    raw = table.value(kind)
    if not isinstance(raw, list) or not raw:
        raise SweepError(f"{where}: expected a non-empty list of values")
    rows = []
    for index, item in enumerate(raw):
        row = Table({"value": item}, where).numbers("value", scalar_ok=True)
        rows.append(_width(row, width, f"{where}[{index}]"))
    table.done()
    return Distribution(kind, (), np.array(rows))


def _nested(value: object) -> bool:
    return isinstance(value, list) and any(isinstance(item, list) for item in value)
