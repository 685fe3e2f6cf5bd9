"""The README is executable: every Python block runs as written and prints what it says.

The README's convention, checked here: a line that prints ends with ``# -> OUTPUT``,
where OUTPUT is exactly the line ``print`` writes (explanations go on a comment line
above it). Each block is self-contained: it runs alone, in a fresh interpreter, in an
empty working directory (so the files it writes land there), with Matplotlib off screen.
Its standard output must be exactly the announced lines, in order, its standard error
empty (no warning a newcomer would see), and its folder must then hold exactly the files
it names. A block that imports an optional part (``trajkit.sim`` needs MuJoCo,
``trajkit.io.ros2`` needs rosbags) is skipped only when that package is missing.
The shell blocks must name commands, options, extras and files that exist, and each
TOML block must show the example file it names, key for key.
"""

from __future__ import annotations

import ast
import importlib.util
import io
import os
import re
import shlex
import subprocess
import sys
import tokenize
import tomllib
from dataclasses import dataclass
from pathlib import Path

import pytest

from trajkit.cli import _build_parser

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
EXPECT = "# -> "
# What a block's imports need beyond the core install, and the extra that installs it.
OPTIONAL = {
    "trajkit.sim": ("mujoco", "sim"),
    "trajkit.io.ros2": ("rosbags", "ros"),
}
# File and folder names a block passes as string literals: it must write them.
WRITTEN = re.compile(r"^[\w-]+(\.(png|gif|mp4|csv|json|npz)|_bag)$")
# Generous: all eight blocks take about 15 s of CPU together (the animations most).
TIMEOUT_S = 300


@dataclass(frozen=True)
class Block:
    """A fenced code block of the README."""

    language: str
    heading: str  # the section it stands in
    line: int  # README line of its first code line (1-based)
    source: str
    ordinal: int  # 1 for the section's first block of this language, 2 for its second...

    @property
    def name(self) -> str:
        return f"{re.sub(r'[^a-z0-9]+', '-', self.heading.lower()).strip('-')}-{self.ordinal}"


def _blocks(language: str) -> list[Block]:
    blocks: list[Block] = []
    heading, fence, start, body = "", None, 0, []
    for number, line in enumerate(README.read_text(encoding="utf-8").splitlines(), 1):
        if fence is None:
            if line.startswith("```"):
                fence, start, body = line[3:].strip(), number + 1, []
            elif line.startswith("#"):
                heading = line.lstrip("#").strip()
        elif line.startswith("```"):
            if fence == language:
                ordinal = 1 + sum(b.heading == heading for b in blocks)
                blocks.append(Block(language, heading, start, "\n".join(body) + "\n", ordinal))
            fence = None
        else:
            body.append(line)
    return blocks


PYTHON = _blocks("python")
BASH = _blocks("bash")
TOML = _blocks("toml")


def _is_print(statement: ast.stmt) -> bool:
    return (
        isinstance(statement, ast.Expr)
        and isinstance(statement.value, ast.Call)
        and isinstance(statement.value.func, ast.Name)
        and statement.value.func.id == "print"
    )


def _announced_output(source: str) -> tuple[list[str], list[str]]:
    """The lines a block says it prints, and where it breaks the convention."""
    tree = ast.parse(source)
    comments = {
        token.start[0]: token.string
        for token in tokenize.generate_tokens(io.StringIO(source).readline)
        if token.type == tokenize.COMMENT
    }
    expected: list[str] = []
    problems: list[str] = []
    used: set[int] = set()
    for statement in tree.body:
        end = statement.end_lineno or statement.lineno
        if _is_print(statement):
            comment = comments.get(end, "")
            if not comment.startswith(EXPECT):
                problems.append(f"line {end}: a print without a '{EXPECT.strip()} OUTPUT' comment")
            else:
                expected.append(comment[len(EXPECT) :].rstrip())
                used.add(end)
        elif isinstance(statement, ast.Expr) and not isinstance(statement.value, ast.Call):
            # REPL style: in a script the value is shown nowhere, so its comment is unchecked.
            problems.append(f"line {statement.lineno}: a bare expression displays nothing")
    for node in ast.walk(tree):
        if isinstance(node, ast.stmt) and node not in tree.body and _is_print(node):
            problems.append(f"line {node.lineno}: print inside a compound statement")
    for number, comment in comments.items():
        if comment.startswith(EXPECT) and number not in used:
            problems.append(f"line {number}: '{EXPECT.strip()}' on a line that does not print")
    return expected, problems


def _needs(source: str) -> list[tuple[str, str]]:
    """The optional packages (and their extras) a block's imports need."""
    modules: set[str] = set()
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            modules.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module:
            modules.add(node.module)
            modules.update(f"{node.module}.{alias.name}" for alias in node.names)
    return [OPTIONAL[m] for m in sorted(modules) if m in OPTIONAL]


def _written(source: str) -> list[str]:
    return sorted(
        {
            node.value
            for node in ast.walk(ast.parse(source))
            if isinstance(node, ast.Constant)
            and isinstance(node.value, str)
            and WRITTEN.match(node.value)
        }
    )


def test_the_readme_has_its_blocks():
    # Guards the extraction itself: a changed fence style must not empty the suite.
    assert len(PYTHON) >= 8
    assert len(BASH) >= 4
    assert len(TOML) >= 2


@pytest.mark.parametrize("block", PYTHON, ids=lambda b: b.name)
def test_block_announces_what_it_prints(block: Block):
    expected, problems = _announced_output(block.source)
    assert problems == [], f"README line {block.line} ({block.heading})"
    # A block prints something, or writes files (checked when it runs).
    assert expected or _written(block.source), f"README line {block.line}: shows nothing"


def test_convention_checker_flags_unannounced_and_repl_style_lines():
    # The checker itself: a print without its output, a REPL-style bare value, a
    # stray arrow and a print hidden in a loop are all reported; a good line is read.
    source = (
        "x = 1\n"
        "print(x)  # -> 1\n"
        "print(x)\n"
        "x  # 1\n"
        "y = 2  # -> 2\n"
        "for _ in range(2):\n"
        "    print(x)  # -> 1\n"
    )
    expected, problems = _announced_output(source)
    assert expected == ["1"]
    assert problems == [
        "line 3: a print without a '# -> OUTPUT' comment",
        "line 4: a bare expression displays nothing",
        "line 7: print inside a compound statement",
        "line 5: '# ->' on a line that does not print",
        "line 7: '# ->' on a line that does not print",
    ]


def test_only_the_blocks_needing_an_extra_may_skip():
    needs = [(block.heading, _needs(block.source)) for block in PYTHON]
    assert [(heading, need) for heading, need in needs if need] == [
        ("Physics simulation (MuJoCo)", [("mujoco", "sim")]),
        ("Animations, data and ROS 2 bags", [("rosbags", "ros")]),
        ("Animations, data and ROS 2 bags", [("rosbags", "ros")]),  # reading bags back
    ]


@pytest.mark.parametrize("block", PYTHON, ids=lambda b: b.name)
def test_block_runs_and_prints_what_its_comments_say(block: Block, tmp_path: Path):
    for package, extra in _needs(block.source):
        if importlib.util.find_spec(package) is None:
            pytest.skip(f"{package} is not installed: pip install 'trajkit[{extra}]'")
    expected, _ = _announced_output(block.source)
    script = tmp_path / "block.py"
    script.write_text(block.source, encoding="utf-8")
    work = tmp_path / "work"
    work.mkdir()
    environment = {**os.environ, "MPLBACKEND": "Agg"}
    result = subprocess.run(
        [sys.executable, str(script)],
        cwd=work,
        env=environment,
        capture_output=True,
        text=True,
        timeout=TIMEOUT_S,
        check=False,
    )
    where = f"README line {block.line} ({block.heading})"
    assert result.returncode == 0, f"{where}:\n{result.stderr}"
    # A first Matplotlib import on a fresh machine announces its font cache: not the block's.
    stderr = [
        line
        for line in result.stderr.splitlines()
        if not line.startswith("Matplotlib is building the font cache")
    ]
    assert stderr == [], where
    assert [line.rstrip() for line in result.stdout.splitlines()] == expected, where
    written = _written(block.source)
    assert sorted(p.name for p in work.iterdir()) == written, where


def _commands(block: Block) -> list[list[str]]:
    """A bash block's commands as words: continuation lines joined, comments dropped."""
    commands: list[list[str]] = []
    for line in block.source.replace("\\\n", " ").splitlines():
        words = shlex.split(line, comments=True)
        while words:
            cut = words.index("&&") if "&&" in words else len(words)
            commands.append(words[:cut])
            words = words[cut + 1 :]
    return commands


def _extras() -> set[str]:
    with (ROOT / "pyproject.toml").open("rb") as file:
        return set(tomllib.load(file)["project"]["optional-dependencies"])


def test_quick_start_commands_exist():
    quick_start = [b for b in BASH if b.heading == "Quick start"]
    assert len(quick_start) == 1
    assert _commands(quick_start[0]) == [
        ["pip", "install", ".[sim,ros]"],
        ["trajkit", "demo"],
        ["bash", "scripts/test.sh"],
    ]
    assert {"sim", "ros"} <= _extras()
    assert (ROOT / "scripts" / "test.sh").is_file()
    assert _build_parser().parse_args(["demo"]).command == "demo"
    # The suite's script installs what the README says: the test extras (and CI's).
    script = (ROOT / "scripts" / "test.sh").read_text(encoding="utf-8")
    assert 'pip install --quiet -e ".[test,sim,scale]"' in script
    assert 'python -m pytest -n auto "$@"' in script  # every core (pytest-xdist)
    assert "engine.warm()" in script  # compiled once, before the workers start


def test_every_shell_line_names_existing_commands_options_and_files(capsys):
    extras = _extras()
    checked = 0
    for block in BASH:
        for words in _commands(block):
            where = f"README line {block.line}: {shlex.join(words)}"
            if words[:2] == ["pip", "install"]:
                for word in words[2:]:
                    for listed in re.findall(r"\[([\w,-]+)\]", word):
                        assert set(listed.split(",")) <= extras, where
            elif words[0] in ("bash", "python") and not words[1].startswith("-"):
                assert (ROOT / words[1]).is_file(), where
            elif words[0] == "trajkit":
                if words[1:] == ["--version"]:
                    with pytest.raises(SystemExit) as exit_:
                        _build_parser().parse_args(words[1:])
                    assert exit_.value.code == 0, where
                    assert capsys.readouterr().out.startswith("trajkit "), where
                else:
                    # Raises CommandError on an unknown command, option or choice.
                    _build_parser().parse_args(words[1:])
                for word in words[2:]:
                    if word.startswith("examples/"):
                        assert (ROOT / word).is_file(), where
            else:
                continue
            checked += 1
    assert checked >= 25


@pytest.mark.parametrize("block", TOML, ids=lambda b: b.name)
def test_toml_block_is_an_excerpt_of_the_file_it_names(block: Block):
    # The README shows an annotated example file: every key it shows is the file's own.
    first = block.source.splitlines()[0]
    assert first.startswith("# examples/"), block.line
    shown = tomllib.loads(block.source)
    with (ROOT / first[2:]).open("rb") as file:
        actual = tomllib.load(file)

    def assert_within(part: dict, whole: dict, path: str) -> None:
        for key, value in part.items():
            assert key in whole, f"README line {block.line}: {path}{key} is not in {first[2:]}"
            if isinstance(value, dict):
                assert_within(value, whole[key], f"{path}{key}.")
            else:
                assert whole[key] == value, f"README line {block.line}: {path}{key}"

    assert_within(shown, actual, "")
