"""A test of an optional library skips, with a reason, where that library is missing.

A module that imports an optional library (an oracle, MuJoCo, the sweep stores,
the bag libraries) at its top would fail to collect, taking the whole run down;
it first asks ``pytest.importorskip`` for it, with a reason that says what is
missing. Read from the test files themselves.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

TESTS = Path(__file__).resolve().parent
OPTIONAL = {
    "mcap", "mcap_ros2", "modern_robotics", "mujoco", "pyarrow", "ray", "roboticstoolbox",
    "rosbags", "ruckig", "spatialmath", "toppra", "yourdfpy", "zarr",
}  # fmt: skip


def _importorskip(node: ast.AST) -> tuple[str, bool] | None:
    """``(library, has a reason)`` if ``node`` is a ``pytest.importorskip`` call."""
    if (
        isinstance(node, ast.Call)
        and ast.unparse(node.func) == "pytest.importorskip"
        and node.args
        and isinstance(node.args[0], ast.Constant)
    ):
        has_reason = any(k.arg == "reason" for k in node.keywords) or len(node.args) > 2
        return str(node.args[0].value).split(".")[0], has_reason
    return None


def _problems(path: Path) -> list[str]:
    tree = ast.parse(path.read_text())
    found = [
        f"line {node.lineno}: importorskip({call[0]!r}) without reason="
        for node in ast.walk(tree)
        if (call := _importorskip(node)) is not None and not call[1]
    ]
    skipped: set[str] = set()
    for statement in tree.body:
        value = getattr(statement, "value", None)
        if isinstance(statement, ast.Expr | ast.Assign) and (call := _importorskip(value)):
            skipped.add(call[0])
            continue
        if isinstance(statement, ast.Import):
            names = [alias.name for alias in statement.names]
        elif isinstance(statement, ast.ImportFrom) and statement.level == 0 and statement.module:
            names = [statement.module]
        else:
            continue
        for name in names:
            library = name.split(".")[0]
            if library in OPTIONAL and library not in skipped:
                found.append(f"line {statement.lineno}: imports {name} before importorskip")
    return found


@pytest.mark.parametrize(
    "path", sorted(TESTS.rglob("*.py")), ids=lambda p: str(p.relative_to(TESTS))
)
def test_optional_libraries_are_skipped_with_a_reason(path: Path) -> None:
    assert _problems(path) == []
