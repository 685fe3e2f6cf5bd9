"""Scenario files: a robot, a task, limits, simulation and outputs in one TOML file.

``trajkit run scenario.toml --out DIR`` plans, checks, optionally simulates, and
writes every output the scenario asks for. From Python::

    from trajkit import scenario
    outcome = scenario.run("examples/seed000_rrbot_cubic.toml", "results")
"""

from __future__ import annotations

import os
from pathlib import Path

from trajkit.scenario.execute import Outcome, execute, robot_of
from trajkit.scenario.parse import Scenario, load, parse
from trajkit.scenario.reader import ScenarioError

__all__ = ["Outcome", "Scenario", "ScenarioError", "execute", "load", "parse", "robot_of", "run"]


def run(path: str | os.PathLike[str], out: str | os.PathLike[str], log=print) -> Outcome:
    """Load the scenario file at ``path`` and carry it out into the folder ``out``."""
    return execute(load(path), Path(out), log=log)
