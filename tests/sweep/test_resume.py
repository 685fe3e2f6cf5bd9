"""Interrupted sweeps resume: finished chunks are kept and skipped, none is written twice.

A chunk's Parquet file appears whole (written to a hidden temporary, then renamed) or
not at all; a folder holding another sweep is refused rather than mixed with it.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from trajkit import sweep
from trajkit.sweep.store import done_chunks

from .helpers import assert_same_rows, data_files, parts, rows, trapezoid_file

PROBLEMS, CHUNK, CHUNKS = 2600, 500, 6  # the last chunk holds 100 problems


def stop_after(chunks: int) -> tuple[object, list]:
    """A progress callback that records its calls and presses Ctrl-C after ``chunks``."""
    calls: list[tuple[int, int, int]] = []

    def progress(done: int, total: int, problems: int, seconds: float) -> None:
        assert seconds >= 0.0
        calls.append((done, total, problems))
        if done == chunks:
            raise KeyboardInterrupt

    return progress, calls


@pytest.fixture(scope="module")
def spec() -> sweep.SweepSpec:
    return sweep.parse(trapezoid_file(PROBLEMS, CHUNK))


@pytest.fixture(scope="module")
def reference(spec, tmp_path_factory) -> Path:
    """The same sweep, uninterrupted."""
    out = tmp_path_factory.mktemp("reference")
    summary = sweep.run(spec, out, workers=1)
    assert (summary.planned_chunks, summary.skipped_chunks, summary.problems) == (
        CHUNKS, 0, PROBLEMS,
    )  # fmt: skip
    return out


def interrupted(spec: sweep.SweepSpec, out: Path, workers: int = 1) -> list:
    progress, calls = stop_after(2)
    with pytest.raises(KeyboardInterrupt):
        sweep.run(spec, out, workers=workers, progress=progress)
    return calls


@pytest.mark.parametrize("workers", [1, 2])
def test_interrupted_run_keeps_exactly_the_finished_chunks(spec, reference, tmp_path, workers):
    out = tmp_path / "out"
    calls = interrupted(spec, out, workers)
    assert [(done, total) for done, total, _ in calls] == [(1, CHUNKS), (2, CHUNKS)]
    assert [problems for *_, problems in calls] == [CHUNK, 2 * CHUNK]
    # Only complete part files: no temporary (hidden or not) is left in data/.
    assert data_files(out) == parts(2)
    assert done_chunks(out) == {0, 1}
    kept = rows(out)
    assert sorted(set(kept["chunk"].to_pylist())) == [0, 1]
    ids = kept["problem"].to_numpy()
    # With a pool the two chunks may be any two; their rows are those of the full run.
    assert_same_rows(kept, rows(reference).take(ids))


def test_rerun_resumes_skipping_finished_chunks(spec, reference, tmp_path):
    out = tmp_path / "out"
    interrupted(spec, out)
    summary = sweep.run(spec, out, workers=2)
    assert summary.skipped_chunks == 2
    assert summary.planned_chunks == CHUNKS - 2
    assert summary.problems == PROBLEMS - 2 * CHUNK
    assert data_files(out) == parts(CHUNKS)
    table = rows(out)
    problems = table["problem"].to_numpy()
    assert np.unique(problems).size == problems.size == PROBLEMS
    assert_same_rows(table, rows(reference))
    again = sweep.run(spec, out, workers=1)
    assert (again.planned_chunks, again.skipped_chunks, again.problems) == (0, CHUNKS, 0)
    assert_same_rows(rows(out), rows(reference))


def test_a_stray_temporary_file_is_not_a_chunk(spec, reference, tmp_path):
    out = tmp_path / "out"
    interrupted(spec, out)
    # What a writer killed mid-file leaves (atomic_write's name for part-000002's temporary).
    stray = out / "data" / ".part-000002.parquet.k3j2x9.tmp"
    stray.write_bytes(b"PAR1\x00\x00truncated")
    assert done_chunks(out) == {0, 1}
    summary = sweep.run(spec, out, workers=1)
    assert (summary.planned_chunks, summary.skipped_chunks) == (CHUNKS - 2, 2)
    assert (out / "data" / "part-000002.parquet").exists()
    assert_same_rows(rows(out), rows(reference))  # the stray file is not read as rows


@pytest.mark.parametrize(
    "change",
    [
        {"seed": 6},
        {"chunk": 400},
        {"problems": 3000},
    ],
    ids=["seed", "chunk", "problems"],
)
def test_a_folder_holding_another_sweep_is_refused(spec, tmp_path, change):
    out = tmp_path / "out"
    sweep.run(spec, out, workers=1)
    before = {name: (out / "data" / name).read_bytes() for name in data_files(out)}
    record = (out / "sweep.json").read_bytes()
    other = trapezoid_file(PROBLEMS, CHUNK)
    other["sweep"].update(change, name="another sweep")
    with pytest.raises(sweep.SweepError) as caught:
        sweep.run(sweep.parse(other), out, workers=1)
    message = str(caught.value)
    assert str(out) in message
    assert "'trapezoids'" in message  # the name of the sweep found there
    assert {name: (out / "data" / name).read_bytes() for name in data_files(out)} == before
    assert (out / "sweep.json").read_bytes() == record


def test_another_changed_parameter_is_another_sweep(spec, tmp_path):
    out = tmp_path / "out"
    sweep.run(spec, out, workers=1)
    other = trapezoid_file(PROBLEMS, CHUNK)
    other["fixed"]["amax"] = 2.5
    with pytest.raises(sweep.SweepError, match="holds a different sweep"):
        sweep.run(sweep.parse(other), out, workers=1)


def test_the_record_names_the_sweep_it_holds(spec, tmp_path):
    out = tmp_path / "out"
    sweep.run(spec, out, workers=1)
    record = json.loads((out / "sweep.json").read_text(encoding="utf-8"))
    assert record["digest"] == spec.digest
    assert (record["problems"], record["chunk"], record["chunks"]) == (PROBLEMS, CHUNK, CHUNKS)
    assert record["name"] == "trapezoids"


def test_an_unreadable_record_is_refused(spec, tmp_path):
    out = tmp_path / "out"
    (out / "data").mkdir(parents=True)
    (out / "sweep.json").write_text("{not json", encoding="utf-8")
    with pytest.raises(sweep.SweepError, match="unreadable"):
        sweep.run(spec, out, workers=1)
    assert data_files(out) == []


def test_reading_a_folder_without_results_is_an_error(tmp_path):
    with pytest.raises(sweep.SweepError, match="no sweep results"):
        sweep.read(tmp_path)
