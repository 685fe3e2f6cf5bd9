"""Mutated example files through the CLI: an exit status, one error line, never a traceback.

Every example scenario (and sweep) file is mutated by a seeded generator: one key
replaced by an extreme number (0, -1, a denormal, 1e12 ... 1e308, nan, inf), a
wrong type (strings, booleans, arrays, tables, empty and ragged arrays), deleted,
joined by an unknown key; or the file's bytes made non-UTF-8 or truncated. Each
mutant runs through ``trajkit run`` (``trajkit sweep``) in-process, and a few in a
real subprocess. A run must exit 0, 1 or 2; on 2 with exactly one stderr line
``trajkit: error: ...``, no traceback, nothing left in ``--out``, and no
RuntimeWarning from the scenario, mobile, task-space, sweep or CLI modules.

``TRAJKIT_FUZZ_RUNS`` sets the number of scenario mutants (default 320, about
10 s on 2 cores); ``TRAJKIT_FUZZ_OUTPUTS=1`` keeps the plots, animations and
simulations of the examples (much slower, for a full sweep by hand).
"""

from __future__ import annotations

import copy
import os
import random
import subprocess
import sys
import tomllib
import warnings
from pathlib import Path

import pytest
from scenario_mutations import mutated, places, to_toml

from trajkit.cli import main

EXAMPLES = Path(__file__).parents[2] / "examples"
SCENARIOS = sorted(EXAMPLES.glob("*.toml"))
SWEEPS = sorted((EXAMPLES / "sweeps").glob("*.toml"))
RUNS = int(os.environ.get("TRAJKIT_FUZZ_RUNS", "320"))
SWEEP_RUNS = max(RUNS // 16, 4)
OUTPUTS = os.environ.get("TRAJKIT_FUZZ_OUTPUTS") == "1"
SEED = 20260516

NUMBERS = [0, -1, 1e-320, 1e12, 1e200, 1e308, -1e308, float("nan"), float("inf"),
           float("-inf"), 10**400, 2**63]  # fmt: skip
WRONG_TYPES = ["nan", "inf", "", "ten", True, False, [], [1, [2, 3]], [[1, 2], [3]], {},
               {"x": 1}, [1e308, -1e308, 1e-320], [float("nan")] * 6, [True] * 6,
               ["a"] * 3]  # fmt: skip
VALUES = NUMBERS + WRONG_TYPES
#: Modules that must not warn even for inputs they accept.
OWN_MODULES = r"trajkit\.(scenario|mobile|taskspace|sweep|cli)"


def _fast(data: dict) -> dict:
    """The example without plots, animations, bags and MuJoCo: hundreds of runs stay fast."""
    if OUTPUTS:
        return data
    data = {**data, "outputs": {**data.get("outputs", {}), "plot": False, "animation": "none",
                                "ros2_bag": False}}  # fmt: skip
    if data.get("simulation", {}).get("engine") == "mujoco":
        mobile = data.get("task", {}).get("kind") in ("twist", "goto", "figure8")
        # An arm's kinematic simulation takes neither a rate nor a controller.
        data["simulation"] = {"engine": "kinematic"} | (
            {"rate_hz": data["simulation"]["rate_hz"]}
            if mobile and "rate_hz" in data["simulation"] else {}
        )  # fmt: skip
    return data


def _small_sweep(data: dict) -> dict:
    """The sweep with 40 problems in chunks of 20: a mutant runs in about a second."""
    return {**data, "sweep": {**data["sweep"], "problems": 40, "chunk": 20}}


def _original(data: dict, place: tuple) -> object:
    target = data
    for key in place:
        target = target[key]
        if isinstance(target, list) and target and isinstance(target[0], dict):
            target = target[0]
    return target


def _numeric(value: object) -> bool:
    items = value if isinstance(value, list) else [value]
    return bool(items) and all(
        isinstance(x, (int, float)) and not isinstance(x, bool) for x in items
    )


def _numbers_in(data: dict):
    """Key paths with a list of numbers (and its length), for element-wise mutations."""
    for place in places(data):
        value = _original(data, place)
        if isinstance(value, list) and _numeric(value):
            yield place, len(value)


def _element(data: dict, place: tuple, index: int, value: object) -> dict:
    target = copy.deepcopy(data)
    holder = target
    for key in place[:-1]:
        holder = holder[key]
        if isinstance(holder, list):
            holder = holder[0]
    items = list(holder[place[-1]])
    items[index] = value
    holder[place[-1]] = items
    return target


def mutants(paths: list[Path], count: int, fit, seed: int) -> list[tuple[str, str, bytes]]:
    """``count`` mutants of the files at ``paths``: (file stem, what changed, file bytes).

    Keys that shape the plan (task, limits, controller, robot, sweep tables) are
    picked four times as often as names and output switches, and numbers are
    mostly replaced by extreme numbers, so most mutants get past the parser.
    """
    rng = random.Random(seed)
    bases = [(path, fit(tomllib.loads(path.read_text(encoding="utf-8")))) for path in paths]
    out = []
    for index in range(count):
        path, data = bases[index % len(bases)]
        text = to_toml(data)
        keys = list(places(data))
        weights = [1 if place[0] in ("name", "description", "outputs") else 4 for place in keys]
        numeric = list(_numbers_in(data))
        roll = rng.random()
        if roll < 0.05:
            cut = rng.randrange(len(text))
            what, content = f"truncated at {cut}", text[:cut].encode()
        elif roll < 0.09:
            at = rng.randrange(len(text))
            what = f"bytes ff fe at {at}"
            content = text[:at].encode() + b"\xff\xfe" + text[at:].encode()
        elif roll < 0.17:
            place = rng.choices(keys, weights)[0]
            what, content = (
                f"{'.'.join(place)} deleted",
                to_toml(mutated(data, place, None, False, delete=True)).encode(),
            )
        elif roll < 0.22:
            place, value = rng.choices(keys, weights)[0], rng.choice(VALUES)
            what = f"{'.'.join(place)}_x = {value!r} added"
            content = to_toml(mutated(data, place, value, True)).encode()
        elif roll < 0.55 and numeric:
            place, size = rng.choice(numeric)
            element, value = rng.randrange(size), rng.choice([*NUMBERS, "x", True, [1]])
            what = f"{'.'.join(place)}[{element}] = {value!r}"
            content = to_toml(_element(data, place, element, value)).encode()
        else:
            place = rng.choices(keys, weights)[0]
            numbers = _numeric(_original(data, place)) and rng.random() < 0.75
            value = rng.choice(NUMBERS if numbers else VALUES)
            what = f"{'.'.join(place)} = {value!r}"
            content = to_toml(mutated(data, place, value, False)).encode()
        out.append((path.stem, what, content))
    return out


def run_one(command: str, content: bytes, folder: Path, capsys) -> str | None:
    """Run one mutant in-process; a description of what went wrong, or None."""
    source, out = folder / "mutant.toml", folder / "out"
    source.write_bytes(content)
    argv = [command, str(source), "--out", str(out)]
    if command == "sweep":
        argv += ["--workers", "1", "--quiet"]
    with warnings.catch_warnings():
        # main() holds warnings back and drops them on an error, so they are made errors
        # where they arise: these modules never warn (a refused input least of all). The
        # profile engine's huge-limit arithmetic may (the engine issue's), not checked here.
        warnings.filterwarnings("error", category=RuntimeWarning, module=OWN_MODULES)
        try:
            status = main(argv)
        except BaseException as exc:  # any escape is the finding
            capsys.readouterr()
            return f"raised {type(exc).__name__}: {exc}"
    captured = capsys.readouterr()
    if status not in (0, 1, 2):
        return f"exit {status}: {captured.err!r}"
    if status == 2:
        if not (captured.err.startswith("trajkit: error: ") and captured.err.count("\n") == 1):
            return f"exit 2 with stderr {captured.err!r}"
        if "Traceback" in captured.err:
            return f"traceback: {captured.err!r}"
        left = sorted(p.name for p in out.rglob("*")) if out.exists() else []
        if left:
            return f"exit 2 left {left} in --out"
    if status == 1 and captured.err != (
        "trajkit: the plan breaks a limit (see the limit check above)\n"
    ):
        return f"exit 1 with stderr {captured.err!r}"
    return None


def _check(command: str, cases, tmp_path: Path, capsys) -> None:
    problems = []
    for number, (stem, what, content) in enumerate(cases):
        folder = tmp_path / f"m{number}"
        folder.mkdir()
        problem = run_one(command, content, folder, capsys)
        if problem is not None:
            problems.append(f"{stem}: {what}: {problem}")
    assert not problems, f"{len(problems)} of {len(cases)} mutants:\n" + "\n".join(problems)


SCENARIO_MUTANTS = mutants(SCENARIOS, RUNS, _fast, SEED)
GROUPS = 8  # the mutants in a few tests, so a failure points at a smaller batch


@pytest.mark.parametrize("group", range(GROUPS))
def test_mutated_example_scenarios_exit_cleanly(group, tmp_path, capsys):
    _check("run", SCENARIO_MUTANTS[group::GROUPS], tmp_path, capsys)


def test_mutated_sweep_files_exit_cleanly(tmp_path, capsys):
    _check("sweep", mutants(SWEEPS, SWEEP_RUNS, _small_sweep, SEED + 1), tmp_path, capsys)


@pytest.mark.parametrize("number", [0, 1, 2])
def test_mutants_in_a_real_process_print_one_line(number, tmp_path):
    # The interpreter's own warning and traceback printing, not the test's capture.
    _, what, content = mutants(SCENARIOS, 3, _fast, SEED + 2 + number)[number]
    source, out = tmp_path / "mutant.toml", tmp_path / "out"
    source.write_bytes(content)
    done = subprocess.run(
        [sys.executable, "-W", "default", "-m", "trajkit.cli", "run", str(source), "--out",
         str(out)],
        capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert done.returncode in (0, 1, 2), (what, done.stderr)
    assert "Traceback" not in done.stderr and "Warning" not in done.stderr, (what, done.stderr)
    if done.returncode == 2:
        assert done.stderr.startswith("trajkit: error: "), (what, done.stderr)
        assert done.stderr.count("\n") == 1, (what, done.stderr)
        assert not out.exists() or not any(out.iterdir()), what


def test_the_mutants_cover_every_example_and_every_kind_of_change():
    stems = {stem for stem, _, _ in SCENARIO_MUTANTS}
    assert stems == {path.stem for path in SCENARIOS}
    kinds = " ".join(what for _, what, _ in SCENARIO_MUTANTS)
    for kind in ("truncated", "bytes ff fe", "deleted", "added", "1e-320", "nan", "1e+308",
                 "[]"):  # fmt: skip
        assert kind in kinds
