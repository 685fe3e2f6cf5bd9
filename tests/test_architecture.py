"""The layers of the package, read from its imports.

Floors, lowest first: core (trajectories, limits, errors, validation, file
infrastructure), domain (planners, kinematics, task space, wheeled bases,
simulation), outputs (plots, animations, reports, exporters), orchestration
(scenario files, sweeps, the demo) and the command line on top. A module imports
only from its own floor or below, at any depth (a lazy import inside a function
couples the floors as much as one at the top); module-level imports have no
cycle; a private name (``_x``) is not imported from another package.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src"

# Each module's floor is that of the longest prefix naming it. The CSV writer and
# the atomic file writes know nothing of trajectories: infrastructure, in core.
FLOORS = {
    "core": (
        "trajkit._poly", "trajkit._validation", "trajkit._periods", "trajkit.errors",
        "trajkit.limits", "trajkit.trajectory", "trajkit.samples", "trajkit.rotations",
        "trajkit.io.atomic", "trajkit.io.table", "trajkit.progress", "trajkit.tolerances",
        "trajkit.curve", "trajkit.renamed",
    ),
    "domain": (
        "trajkit.profiles", "trajkit.time_optimal", "trajkit.kinematics", "trajkit.taskspace",
        "trajkit.mobile", "trajkit.sim", "trajkit.batch", "trajkit.online", "trajkit.analysis",
        "trajkit.planners",
    ),
    "outputs": ("trajkit.viz", "trajkit.io"),
    "orchestration": ("trajkit.scenario", "trajkit.sweep", "trajkit.demo", "trajkit.examples"),
    "cli": ("trajkit.cli",),
}  # fmt: skip
ORDER = list(FLOORS)


def floor(module: str) -> str | None:
    """The floor of ``module`` (None for the package's facade, ``trajkit`` itself)."""
    best = (None, -1)
    for name, prefixes in FLOORS.items():
        for prefix in prefixes:
            if (module == prefix or module.startswith(prefix + ".")) and len(prefix) > best[1]:
                best = (name, len(prefix))
    return best[0]


def modules() -> dict[str, Path]:
    found = {}
    for path in sorted((SRC / "trajkit").rglob("*.py")):
        name = ".".join(path.relative_to(SRC).with_suffix("").parts)
        found[name.removesuffix(".__init__")] = path
    return found


def imports(path: Path) -> list[tuple[str, list[str], bool]]:
    """``(module, names, at module level at run time)`` for every trajkit import in ``path``."""
    tree = ast.parse(path.read_text())
    typing_only = {
        id(child)
        for node in tree.body
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test)
        for child in ast.walk(node)
    }
    top = {id(node) for node in tree.body}
    found = []
    for node in ast.walk(tree):
        if id(node) in typing_only:
            continue
        if isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            if node.module.split(".")[0] == "trajkit":
                found.append((node.module, [a.name for a in node.names], id(node) in top))
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.split(".")[0] == "trajkit":
                    found.append((alias.name, [], id(node) in top))
    return found


MODULES = modules()


def resolved(module: str, names: list[str]) -> list[str]:
    """The modules an import reads: ``from a import b`` reads ``a.b`` where that is one."""
    return [f"{module}.{n}" for n in names if f"{module}.{n}" in MODULES] or [module]


def test_every_module_has_a_floor() -> None:
    assert [m for m in MODULES if m != "trajkit" and floor(m) is None] == []


@pytest.mark.parametrize("module", [m for m in MODULES if m != "trajkit"])
def test_no_module_imports_from_a_floor_above_its_own(module: str) -> None:
    mine = ORDER.index(floor(module))
    upward = [
        f"{target} ({floor(target)})"
        for source, names, _ in imports(MODULES[module])
        for target in resolved(source, names)
        if target != "trajkit" and ORDER.index(floor(target)) > mine
    ]
    assert upward == [], f"{module} ({floor(module)}) imports from above: {upward}"


def test_module_level_imports_have_no_cycle() -> None:
    graph = {
        m: {t for s, names, top in imports(p) if top for t in resolved(s, names) if t in MODULES}
        for m, p in MODULES.items()
    }
    state: dict[str, int] = {}  # 1 on the path, 2 done

    def visit(node: str, path: list[str]) -> list[str] | None:
        state[node] = 1
        for nxt in sorted(graph[node]):
            if state.get(nxt) == 1:
                return [*path, node, nxt]
            if nxt not in state and (cycle := visit(nxt, [*path, node])):
                return cycle
        state[node] = 2
        return None

    for start in sorted(graph):
        if start not in state:
            cycle = visit(start, [])
            assert cycle is None, f"import cycle: {' -> '.join(cycle or [])}"


def test_no_private_name_is_imported_from_another_package() -> None:
    def package(module: str) -> str:
        return ".".join(module.split(".")[:2])

    crossing = [
        f"{module} imports {name} from {source}"
        for module, path in MODULES.items()
        for source, names, _ in imports(path)
        for name in names
        if name.startswith("_")
        and not name.startswith("__")
        # The root's private modules (trajkit._poly...) are the package's own helpers.
        and f"{source}.{name}" not in MODULES
        and package(source) != package(module)
    ]
    assert crossing == []
