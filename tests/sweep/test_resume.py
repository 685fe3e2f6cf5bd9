"""Interrupted sweeps resume: finished chunks are kept and skipped, none is written twice.

A chunk's Parquet file appears whole (written to a hidden temporary, then renamed) or
not at all; a folder holding another sweep is refused rather than mixed with it.
"""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path

import numpy as np
import pytest

from trajkit import sweep
from trajkit.sweep import store
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
    # With a pool the two chunks that finish first may be any two (never the same one
    # twice): exactly those are kept, whole, and their rows are those of the full run.
    kept = rows(out)
    chunks = kept["chunk"].to_pylist()
    finished = sorted(set(chunks))
    assert len(finished) == 2
    if workers == 1:
        assert finished == [0, 1]
    ids = kept["problem"].to_numpy()
    first, second = (problems for *_, problems in calls)
    assert np.unique(ids).size == ids.size == second
    assert first in (chunks.count(finished[0]), chunks.count(finished[1]))
    # Only complete part files: no temporary (hidden or not) is left in data/.
    assert data_files(out) == [f"part-{k:06d}.parquet" for k in finished]
    assert done_chunks(out) == done_chunks(out, spec) == set(finished)
    for k in finished:  # every problem of each kept chunk, once
        expected = np.arange(k * CHUNK, min((k + 1) * CHUNK, PROBLEMS))
        np.testing.assert_array_equal(np.sort(ids[np.array(chunks) == k]), expected)
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
    assert data_files(out) == parts(CHUNKS)  # and it is gone


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


def test_a_killed_run_s_temporaries_are_removed_by_the_next_run(spec, reference, tmp_path):
    out = tmp_path / "out"
    interrupted(spec, out)
    # What a SIGKILL mid-write leaves: a part file's temporary, a samples staging
    # folder, the record's temporary. A file of the user's is left alone.
    strays = [out / "data" / ".part-000003.parquet.a8f2k1.tmp",
              out / ".sweep.json.x1y2z3.tmp"]  # fmt: skip
    for stray in strays:
        stray.write_bytes(b"\0" * 4096)
    staging = out / "samples" / ".chunk-000003.zarr.q7w8e9"
    (staging / "values").mkdir(parents=True)
    (staging / "values" / "zarr.json").write_text("{}", encoding="utf-8")
    mine = [out / "data" / ".notes", out / "samples" / "chunk-notes.txt"]
    for path in mine:
        path.write_text("keep me", encoding="utf-8")
    summary = sweep.run(spec, out, workers=1)
    assert (summary.planned_chunks, summary.skipped_chunks) == (CHUNKS - 2, 2)
    assert not any(path.exists() for path in [*strays, staging])
    assert all(path.read_text(encoding="utf-8") == "keep me" for path in mine)
    assert sorted(p.name for p in (out / "samples").iterdir()) == ["chunk-notes.txt"]
    assert data_files(out) == sorted([".notes", *parts(CHUNKS)])


@pytest.mark.parametrize(
    "damage",
    [
        lambda path: path.write_bytes(b""),  # renamed before its data reached the disk
        lambda path: path.write_bytes(path.read_bytes()[: path.stat().st_size // 2]),
        lambda path: path.write_bytes(b"PAR1" + b"\0" * 64 + b"PAR1"),
    ],
    ids=["empty", "cut-short", "garbled"],
)
def test_a_chunk_file_that_does_not_read_back_is_redone(spec, reference, tmp_path, damage):
    out = tmp_path / "out"
    sweep.run(spec, out, workers=1)
    damage(out / "data" / "part-000003.parquet")
    damage(out / "data" / "part-000005.parquet")  # the short last chunk
    assert done_chunks(out, spec) == {0, 1, 2, 4}
    summary = sweep.run(spec, out, workers=1)
    assert (summary.planned_chunks, summary.skipped_chunks) == (2, CHUNKS - 2)
    assert summary.problems == CHUNK + PROBLEMS % CHUNK
    assert data_files(out) == parts(CHUNKS)
    assert_same_rows(rows(out), rows(reference))


def test_a_chunk_whose_samples_are_missing_is_redone(tmp_path):
    data = trapezoid_file(40, 10)
    data["sweep"].update(keep="samples", sample_step=0.1)
    spec = sweep.parse(data)
    out = tmp_path / "out"
    sweep.run(spec, out, workers=1)
    t, q = sweep.read_samples(out, 25)
    shutil.rmtree(out / "samples" / "chunk-000002.zarr")
    summary = sweep.run(spec, out, workers=1)
    assert (summary.planned_chunks, summary.skipped_chunks) == (1, 3)
    again = sweep.read_samples(out, 25)
    np.testing.assert_array_equal(again[0], t)
    np.testing.assert_array_equal(again[1], q)


def test_files_and_their_folders_reach_the_disk_around_the_rename(tmp_path, monkeypatch):
    # The order a power loss needs: the data flushed before the rename makes it
    # visible, and the folder flushed after it, so the name cannot outlive the data.
    events: list[tuple[str, ...]] = []
    fsync, replace = os.fsync, os.replace

    def recording_fsync(descriptor: int) -> None:
        events.append(("fsync", os.readlink(f"/proc/self/fd/{descriptor}")))
        fsync(descriptor)

    def recording_replace(source, target) -> None:
        events.append(("replace", str(source), str(target)))
        replace(source, target)

    if not Path("/proc/self/fd").is_dir():
        pytest.skip("names file descriptors through Linux's /proc")
    monkeypatch.setattr(store.os, "fsync", recording_fsync)
    monkeypatch.setattr(store.os, "replace", recording_replace)
    data = trapezoid_file(20, 10)
    data["sweep"].update(keep="samples", sample_step=0.1)
    out = (tmp_path / "out").resolve()
    sweep.run(sweep.parse(data), out, workers=1)
    monkeypatch.undo()
    # zarr renames files of its own inside the staging folder; these are the sweep's:
    renames = [e for e in events if e[0] == "replace"
               and Path(e[2]).parent in (out, out / "data", out / "samples")]  # fmt: skip
    assert [Path(e[2]).name for e in renames] == [
        "sweep.json", "chunk-000000.zarr", "part-000000.parquet",
        "chunk-000001.zarr", "part-000001.parquet",
    ]  # fmt: skip
    for rename in renames:
        at = events.index(rename)
        source, target = Path(rename[1]), Path(rename[2])
        flushed = [Path(e[1]) for e in events[:at] if e[0] == "fsync"]
        if source.is_dir() or target.is_dir():  # the staging folder: every file in it
            inside = [p for p in flushed if source in p.parents or p == source]
            assert source in inside and source / "values" / "zarr.json" in inside
        else:
            assert source in flushed, rename
        assert ("fsync", str(target.parent)) in events[at + 1 :], rename


def test_a_second_run_in_the_same_folder_at_once_is_refused(spec, tmp_path):
    out = tmp_path / "out"
    interrupted(spec, out)
    with store.lock(out):  # as a run in another process holds it
        with pytest.raises(sweep.SweepError, match="another trajkit sweep is writing to"):
            sweep.run(spec, out, workers=1)
    assert data_files(out) == parts(2)
    assert sweep.run(spec, out, workers=1).planned_chunks == CHUNKS - 2
