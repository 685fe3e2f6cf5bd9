"""Scenario files: a robot, a task, limits, simulation and outputs in one TOML file.

``trajkit run scenario.toml --out DIR`` plans, checks, optionally simulates, and
writes every output the scenario asks for. From Python::

    from trajkit import scenario
    outcome = scenario.run("examples/seed000_rrbot_cubic.toml", "results")
"""

from __future__ import annotations

import os
from pathlib import Path

from trajkit.scenario.execute import Outcome, execute, report_entry, robot_of
from trajkit.scenario.parse import Scenario, load, parse
from trajkit.scenario.reader import ScenarioError

__all__ = [
    "EXAMPLES",
    "Outcome",
    "Scenario",
    "ScenarioError",
    "examples",
    "execute",
    "load",
    "parse",
    "report_entry",
    "robot_of",
    "run",
]

#: The folder of the example scenarios that ship with trajkit.
EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def examples() -> list[Path]:
    """The example scenario files, sorted by name."""
    return sorted(EXAMPLES.glob("*.toml"))


def run(path: str | os.PathLike[str], out: str | os.PathLike[str], log=print) -> Outcome:
    """Load the scenario file at ``path`` and carry it out into the folder ``out``."""
    return execute(load(path), Path(out), log=log)
