"""``trajkit sweep``: one summary line on success; one error line, exit 2, nothing written.

Every broken rule of a sweep file is reported on one line naming the key, before any
output folder is made; Ctrl-C keeps the finished chunks and exits 130.
"""

from __future__ import annotations

import io
import re
import sys
import tomllib
import warnings
from importlib import resources
from pathlib import Path

import numpy as np
import pytest

from trajkit import sweep
from trajkit.cli import main

from .helpers import data_files, parts, rows

EXAMPLES = sorted(
    Path(str(path))
    for path in (resources.files("trajkit") / "examples" / "sweeps").iterdir()
    if path.name.endswith(".toml")
)

GOOD = """\
[sweep]
name = "cli trapezoids"
planner = "trapezoid"
problems = 10
chunk = 5
{sweep}
[robot]
joints = 2
{robot}
[fixed]
amax = 2.0
{fixed}
[swept]
q0 = {{ uniform = [-1, 1] }}
qf = {{ uniform = [-1, 1] }}
{swept}
"""


def good(sweep: str = "", robot: str = "", fixed: str = "vmax = 1.0", swept: str = "") -> str:
    return GOOD.format(sweep=sweep, robot=robot, fixed=fixed, swept=swept)


def cli(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    status = main(list(argv))
    captured = capsys.readouterr()
    return status, captured.out, captured.err


def assert_one_error_line(err: str, *names: str) -> None:
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("trajkit: error: "), err
    assert "Traceback" not in err
    for name in names:
        assert name in lines[0], (name, err)


BAD_FILES = {
    "invalid-toml": ("[sweep\nplanner = ", ["bad.toml", "is not valid TOML"]),
    "unknown-planner": (good().replace('"trapezoid"', '"warp"'), ["sweep.planner", "'warp'"]),
    "unknown-sweep-key": (good(sweep="speed = 3"), ["sweep.speed", "unknown key"]),
    "unknown-fixed-key": (good(fixed="vmax = 1.0\njmax = 3.0"), ["fixed.jmax", "unknown key"]),
    "unknown-swept-key": (good(swept="jmax = { uniform = [1, 2] }"), ["swept.jmax", "unknown"]),
    "unknown-robot-key": (good(robot="arms = 2"), ["robot.arms", "unknown key"]),
    "fixed-and-swept": (good(swept="vmax = { uniform = [1, 2] }"), ["vmax", "not both"]),
    "required-missing": (good(fixed=""), ["fixed.vmax", "required"]),
    "two-kinds": (good(fixed="", swept="vmax = { uniform = [1, 2], normal = [1, 0.1] }"),
                  ["swept.vmax", "exactly one of", "normal, uniform"]),
    "no-kind": (good(fixed="", swept="vmax = {}"), ["swept.vmax", "got nothing"]),
    "unknown-kind": (good(fixed="", swept="vmax = { lognormal = [1, 2] }"),
                     ["swept.vmax", "lognormal"]),
    "uniform-high-below-low": (good(fixed="", swept="vmax = { uniform = [2, 1] }"),
                               ["swept.vmax.uniform", "high end is below the low end"]),
    "uniform-three-numbers": (good(fixed="", swept="vmax = { uniform = [1, 2, 3] }"),
                              ["swept.vmax.uniform", "[low, high]"]),
    "normal-negative-std": (good(fixed="", swept="vmax = { normal = [2, -1] }"),
                            ["swept.vmax.normal", "standard deviation"]),
    "grid-count-0": (good(fixed="", swept="vmax = { grid = [1, 2, 0] }"),
                     ["swept.vmax.grid", "whole count >= 1"]),
    "grid-count-fraction": (good(fixed="", swept="vmax = { grid = [1, 2, 2.5] }"),
                            ["swept.vmax.grid", "whole count >= 1"]),
    "values-empty": (good(fixed="", swept="vmax = { values = [] }"), ["swept.vmax.values"]),
    "fixed-wrong-width": (good(fixed="vmax = [1, 2, 3]"), ["fixed.vmax", "one number or 2"]),
    "values-wrong-width": (good(swept="v0 = { values = [[0, 0, 0]] }"),
                           ["swept.v0.values[0]", "one number or 2, got 3"]),
    "uniform-wrong-width": (good(fixed="", swept="vmax = { uniform = [[1, 1, 1], [2, 2, 2]] }"),
                            ["swept.vmax.uniform", "one number or 2, got 3"]),
    "not-a-number": (good(fixed='vmax = "fast"'), ["fixed.vmax"]),
    "problems-0": (good().replace("problems = 10", "problems = 0"), ["sweep.problems", "0"]),
    "problems-fraction": (good().replace("problems = 10", "problems = 1.5"),
                          ["sweep.problems", "1.5"]),
    "chunk-0": (good().replace("chunk = 5", "chunk = 0"), ["sweep.chunk"]),
    "seed-negative": (good(sweep="seed = -1"), ["sweep.seed"]),
    "step-0": (good(sweep="sample_step = 0"), ["sweep.sample_step"]),
    "keep-everything": (good(sweep='keep = "everything"'), ["sweep.keep", "'everything'"]),
    "unknown-sync": (good(sweep='sync = "fast"'), ["sweep.sync", "'fast'"]),
    "min-duration-wrong-width": (good(fixed="vmax = 1.0\nmin_duration = [1, 2]"),
                                 ["fixed.min_duration", "one number or 1, got 2"]),
    "min-duration-not-a-number": (good(fixed='vmax = 1.0\nmin_duration = "long"'),
                                  ["fixed.min_duration", "expected a list of numbers"]),
    "a0-of-a-trapezoid": (good(fixed="vmax = 1.0\na0 = 0.5"), ["fixed.a0", "unknown key"]),
    "joints-0": (good().replace("joints = 2", "joints = 0"), ["robot.joints"]),
    "no-sweep-table": ("[fixed]\nvmax = 1.0\n", ["sweep", "required table is missing"]),
}  # fmt: skip


@pytest.mark.parametrize("case", list(BAD_FILES))
def test_a_bad_sweep_file_is_one_error_line_and_writes_nothing(tmp_path, capsys, case):
    text, names = BAD_FILES[case]
    path = tmp_path / "bad.toml"
    path.write_text(text, encoding="utf-8")
    out = tmp_path / "out"
    status, stdout, err = cli(capsys, "sweep", str(path), "--out", str(out), "--quiet")
    assert status == 2
    assert stdout == ""
    assert_one_error_line(err, *names)
    assert not out.exists()


def test_a_missing_sweep_file_is_one_error_line(tmp_path, capsys):
    out = tmp_path / "out"
    status, stdout, err = cli(capsys, "sweep", str(tmp_path / "nope.toml"), "--out", str(out))
    assert (status, stdout) == (2, "")
    assert_one_error_line(err, "cannot read the sweep file", "nope.toml")
    assert not out.exists()


def test_an_out_that_is_a_file_is_one_error_line_naming_it(tmp_path, capsys):
    source, out = tmp_path / "ok.toml", tmp_path / "taken"
    source.write_text(good(), encoding="utf-8")
    out.write_text("mine", encoding="utf-8")
    status, stdout, err = cli(capsys, "sweep", str(source), "--out", str(out))
    assert (status, stdout) == (2, "")
    assert_one_error_line(err, f"{out} is a file, not a folder")  # not "it already exists"
    assert out.read_text(encoding="utf-8") == "mine"


@pytest.mark.parametrize(
    ("content", "names"),
    [
        # Latin-1 text: a UnicodeDecodeError traceback before.
        (good().replace('"cli trapezoids"', '"caf\xe9"').encode("latin-1"),
         ["cannot read the sweep file", "odd.toml", "not UTF-8", "0xe9"]),
        (b"\x89PNG\r\n\x1a\n\x00\x00", ["cannot read the sweep file", "odd.toml", "not UTF-8"]),
        (b"\x00\x01 plain bytes", ["odd.toml", "is not valid TOML"]),
        (None, ["cannot read the sweep file", "odd.toml", "a folder, not a file"]),
    ],
    ids=["latin-1", "binary", "nul-bytes", "folder"],
)  # fmt: skip
def test_an_unreadable_sweep_file_is_one_error_line(tmp_path, capsys, content, names):
    path = tmp_path / "odd.toml"
    if content is None:
        path.mkdir()
    else:
        path.write_bytes(content)
    out = tmp_path / "out"
    status, stdout, err = cli(capsys, "sweep", str(path), "--out", str(out), "--quiet")
    assert (status, stdout) == (2, "")
    assert_one_error_line(err, *names)
    assert not out.exists()


@pytest.mark.parametrize(
    ("argv", "names"),
    [
        (["--workers", "0"], ["workers must be a whole number >= 1"]),
        (["--engine", "spark"], ["--engine", "spark"]),
        (["--workers", "two"], ["--workers", "two"]),
    ],
)
def test_bad_options_are_one_error_line_and_write_nothing(tmp_path, capsys, argv, names):
    path = tmp_path / "ok.toml"
    path.write_text(good(), encoding="utf-8")
    out = tmp_path / "out"
    status, stdout, err = cli(capsys, "sweep", str(path), "--out", str(out), "--quiet", *argv)
    assert (status, stdout) == (2, "")
    assert_one_error_line(err, *names)
    assert not out.exists()


def test_address_with_the_local_engine_is_one_error_line(tmp_path, capsys):
    path = tmp_path / "ok.toml"
    path.write_text(good(), encoding="utf-8")
    status, stdout, err = cli(capsys, "sweep", str(path), "--out", str(tmp_path / "out"),
                              "--quiet", "--address", "auto")  # fmt: skip
    assert (status, stdout) == (2, "")
    assert_one_error_line(err, "--address is for the ray engine")


def test_address_with_the_local_engine_writes_nothing(tmp_path, capsys):
    path = tmp_path / "ok.toml"
    path.write_text(good(), encoding="utf-8")
    out = tmp_path / "out"
    status, _, _ = cli(capsys, "sweep", str(path), "--out", str(out), "--address", "auto")
    assert status == 2
    assert not out.exists()


def test_a_folder_of_another_sweep_is_one_error_line(tmp_path, capsys):
    first, second = tmp_path / "first.toml", tmp_path / "second.toml"
    first.write_text(good(), encoding="utf-8")
    second.write_text(good(sweep="seed = 9"), encoding="utf-8")
    out = tmp_path / "out"
    assert cli(capsys, "sweep", str(first), "--out", str(out), "--quiet")[0] == 0
    before = {name: (out / "data" / name).read_bytes() for name in data_files(out)}
    status, stdout, err = cli(capsys, "sweep", str(second), "--out", str(out), "--quiet")
    assert (status, stdout) == (2, "")
    assert_one_error_line(err, str(out), "holds a different sweep", "'cli trapezoids'")
    assert {name: (out / "data" / name).read_bytes() for name in data_files(out)} == before


def test_ctrl_c_keeps_the_finished_chunks_and_exits_130(tmp_path, capsys, monkeypatch):
    from trajkit.sweep import engines

    path = tmp_path / "ok.toml"
    path.write_text(good().replace("problems = 10", "problems = 20"), encoding="utf-8")
    out = tmp_path / "out"
    real = engines.plan_chunk

    def plan_chunk(spec, chunk):
        if chunk == 2:
            raise KeyboardInterrupt
        return real(spec, chunk)

    monkeypatch.setattr(engines, "plan_chunk", plan_chunk)
    status, stdout, err = cli(capsys, "sweep", str(path), "--out", str(out), "--quiet",
                              "--workers", "1")  # fmt: skip
    assert (status, stdout) == (130, "")
    lines = err.splitlines()
    assert len(lines) == 1 and lines[0].startswith("trajkit: interrupted"), err
    assert "Traceback" not in err
    assert data_files(out) == parts(2)
    monkeypatch.setattr(engines, "plan_chunk", real)
    status, stdout, err = cli(capsys, "sweep", str(path), "--out", str(out), "--quiet",
                              "--workers", "1")  # fmt: skip
    assert (status, err) == (0, "")
    assert "planned 2 chunks (10 problems)" in stdout
    assert "2 chunks were already done" in stdout
    assert rows(out)["problem"].to_pylist() == list(range(20))


@pytest.mark.parametrize("stop", [KeyboardInterrupt, sweep.SweepError("disk trouble")],
                         ids=["ctrl-c", "error"])  # fmt: skip
def test_a_message_after_a_live_progress_bar_starts_its_own_line(tmp_path, capsys, monkeypatch,
                                                                 stop):  # fmt: skip
    # On a terminal the bar is redrawn with \r and no newline until the last chunk: the
    # interruption or error line used to be glued to it.
    from trajkit.sweep import engines

    path = tmp_path / "ok.toml"
    path.write_text(good().replace("problems = 10", "problems = 20"), encoding="utf-8")
    real = engines.plan_chunk

    def plan_chunk(spec, chunk):
        if chunk == 2:
            raise stop
        return real(spec, chunk)

    monkeypatch.setattr(engines, "plan_chunk", plan_chunk)
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True)
    status, stdout, err = cli(capsys, "sweep", str(path), "--out", str(tmp_path / "out"),
                              "--workers", "1")  # fmt: skip
    assert (status, stdout) == ((130, "") if stop is KeyboardInterrupt else (2, ""))
    bar, message, end = err.split("\n")
    assert bar.startswith("\r[#####...............] 1/4 chunks, 5 problems, ")
    assert "\r[##########..........] 2/4 chunks, 10 problems, " in bar and bar.count("\r") == 2
    assert message.startswith("trajkit: interrupted; " if stop is KeyboardInterrupt
                              else "trajkit: error: disk trouble")  # fmt: skip
    assert end == ""


def test_a_progress_bar_closes_once_and_only_an_open_line():
    stream = io.StringIO()
    stream.isatty = lambda: True
    bar = sweep.progress_bar(stream)
    bar.close()
    assert stream.getvalue() == ""
    bar(1, 2, 5, 1.0)
    bar.close()
    bar.close()
    assert stream.getvalue() == "\r[##########..........] 1/2 chunks, 5 problems, 5 problems/s\n"
    bar(2, 2, 10, 1.0)
    bar.close()
    assert stream.getvalue().endswith("2/2 chunks, 10 problems, 10 problems/s\n")
    assert stream.getvalue().count("\n") == 2


# ---------------------------------------------------------------------- success
def test_an_example_runs_with_one_summary_line(tmp_path, capsys):
    example = next(path for path in EXAMPLES if path.name == "scurve_samples.toml")
    out = tmp_path / "d"
    status, stdout, err = cli(capsys, "sweep", str(example), "--out", str(out), "--quiet")
    assert (status, err) == (0, "")
    lines = stdout.splitlines()
    assert len(lines) == 1
    assert lines[0].startswith("six-joint S-curves with samples: planned 4 chunks (2,000 problems)")
    assert "0 failed, 0 infeasible; 0 chunks were already done" in lines[0]
    assert lines[0].endswith(f"Rows in {out / 'data'}")
    assert rows(out).num_rows == 2000
    assert len(list((out / "samples").iterdir())) == 4


def test_progress_goes_to_stderr_unless_quiet(tmp_path, capsys):
    path = tmp_path / "ok.toml"
    path.write_text(good(), encoding="utf-8")
    status, stdout, err = cli(capsys, "sweep", str(path), "--out", str(tmp_path / "out"),
                              "--workers", "1")  # fmt: skip
    assert status == 0
    assert len(stdout.splitlines()) == 1 and "(10 problems)" in stdout
    lines = err.splitlines()
    assert lines and lines[-1].startswith("[####################] 2/2 chunks, 10 problems")
    assert all("error" not in line for line in lines)


def test_examples_ship_with_the_package():
    assert [path.name for path in EXAMPLES] == [
        "scurve_samples.toml", "trapezoid_6dof.toml", "ur5_lines.toml",
    ]  # fmt: skip


@pytest.mark.parametrize("example", EXAMPLES, ids=[path.stem for path in EXAMPLES])
def test_every_example_parses(example):
    spec = sweep.load(example)
    data = tomllib.loads(example.read_text(encoding="utf-8"))
    assert spec.planner == data["sweep"]["planner"]
    assert spec.problems == data["sweep"]["problems"]
    assert spec.chunk == data["sweep"]["chunk"]
    assert spec.name == data["sweep"]["name"]


@pytest.mark.parametrize("example", EXAMPLES, ids=[path.stem for path in EXAMPLES])
def test_a_reduced_copy_of_every_example_runs(tmp_path, capsys, example):
    text = example.read_text(encoding="utf-8")
    text, found = re.subn(r"(?m)^problems = \d+", "problems = 12", text)
    assert found == 1
    text, found = re.subn(r"(?m)^chunk = \d+", "chunk = 5", text)
    assert found == 1
    copy = tmp_path / example.name
    copy.write_text(text, encoding="utf-8")
    out = tmp_path / "out"
    status, stdout, err = cli(capsys, "sweep", str(copy), "--out", str(out), "--quiet",
                              "--workers", "1")  # fmt: skip
    assert (status, err) == (0, "")
    assert "planned 3 chunks (12 problems)" in stdout
    table = rows(out)
    assert table["problem"].to_pylist() == list(range(12))
    errors = [e for e in table["error"].to_pylist() if e]
    if sweep.load(copy).planner == "task_space":
        assert all(e.startswith("UnreachableError: ") for e in errors)  # rows, by design
        assert len(errors) < 12
    else:
        assert errors == []
        assert all(table["feasible"].to_pylist())
        assert np.isfinite(table["duration"].to_numpy()).all()


#: What a mutated number of a sweep file becomes: extremes, wrong types, wrong shapes.
MUTATIONS = ["0", "-1", "1e308", "-1e308", "5e-324", "1e-300", "nan", "inf", "1e20",
             "1000000000000000000000000000000", '"x"', "true", "[]", "[1, 2]"]  # fmt: skip
NUMBER = re.compile(r"(?<![\w.])-?\d+(\.\d+)?(e-?\d+)?(?![\w.])")


def _mutants(count: int, seed: int = 16) -> list[tuple[str, int, str]]:
    """``count`` (example, number's position, replacement) triples, drawn once."""
    everything = []
    for example in EXAMPLES:
        text = example.read_text(encoding="utf-8")
        for found in NUMBER.finditer(text):
            everything += [(example.name, found.start(), value) for value in MUTATIONS]
    picks = np.random.default_rng(seed).choice(len(everything), count, replace=False)
    return [everything[i] for i in sorted(picks)]


@pytest.mark.parametrize(("name", "where", "value"), _mutants(24))
def test_a_mutated_example_is_a_summary_or_one_error_line(tmp_path, capsys, name, where, value):
    # Exit 0 with one summary line, or 2 with one error line: never a traceback, a
    # numpy warning, or a run that does not end (the whole campaign, 800 mutants of
    # every number of every example, ends the same way).
    text = next(p for p in EXAMPLES if p.name == name).read_text(encoding="utf-8")
    found = NUMBER.match(text, where)
    text = text[:where] + value + text[found.end() :]
    for key, small in (("problems", 12), ("chunk", 5)):  # a short run, unless mutated
        text = re.sub(rf"(?m)^{key} = \d+$", f"{key} = {small}", text)
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        status, stdout, err = cli(capsys, "sweep", str(path), "--out", str(tmp_path / "out"),
                                  "--quiet", "--workers", "1")  # fmt: skip
    if status == 0:
        assert err == "" and len(stdout.splitlines()) == 1 and "planned" in stdout
    else:
        assert (status, stdout) == (2, "")
        assert_one_error_line(err)
