"""keep = "samples": each problem's trajectory, sampled every period, in Zarr beside the rows.

The samples are exactly the planned trajectory at t = 0, period, 2 period, ... up to
its duration, found by problem number whichever chunk holds it.
"""

from __future__ import annotations

import shutil

import numpy as np
import pytest

import trajkit as tk
from trajkit import batch, sweep

from .helpers import data_files, matrix, parts, rows

JOINTS, PROBLEMS, CHUNK, PERIOD = 3, 600, 200, 0.01
SAMPLED = 1e-12  # absolute (rad): samples against the trajectory evaluated directly


def scurve_file(**swept) -> dict:
    return {
        "sweep": {"planner": "scurve", "problems": PROBLEMS, "chunk": CHUNK, "seed": 3,
                  "keep": "samples", "period": PERIOD},
        "robot": {"joints": JOINTS},
        "fixed": {"vmax": 2.0, "amax": 5.0},
        "swept": {"q0": {"uniform": [-1, 1]}, "qf": {"uniform": [-1, 1]},
                  "jmax": {"values": [20.0, 50.0]}, **swept},
    }  # fmt: skip


@pytest.fixture(scope="module")
def sampled(tmp_path_factory):
    out = tmp_path_factory.mktemp("samples")
    summary = sweep.run(sweep.parse(scurve_file()), out, workers=2)
    assert summary.failed == 0
    table = rows(out)
    plans = batch.scurve(*(matrix(table, n, JOINTS) for n in ("q0", "qf", "vmax", "amax", "jmax")))
    return out, table, plans


def test_one_zarr_group_per_chunk_and_no_leftovers(sampled):
    out, _, _ = sampled
    assert sorted(p.name for p in (out / "samples").iterdir()) == [
        f"chunk-{k:06d}.zarr" for k in range(PROBLEMS // CHUNK)
    ]
    assert data_files(out) == parts(PROBLEMS // CHUNK)


@pytest.mark.parametrize("problem", [0, 1, 199, 200, 333, 400, 599])
def test_samples_are_the_planned_trajectory_every_period(sampled, problem):
    out, table, plans = sampled
    t, q = sweep.read_samples(out, problem)
    duration = table["duration"][problem].as_py()
    n = t.size
    np.testing.assert_array_equal(t, np.arange(n) * PERIOD)
    assert t[-1] <= duration < t[-1] + PERIOD  # every sample up to the end, none after
    assert q.shape == (n, JOINTS)
    np.testing.assert_allclose(q, plans[problem].position(t), rtol=0, atol=SAMPLED)
    single = tk.scurve(*(matrix(table, name, JOINTS)[problem]
                         for name in ("q0", "qf", "vmax", "amax", "jmax")))  # fmt: skip
    np.testing.assert_allclose(q, single.position(t), rtol=0, atol=SAMPLED)
    np.testing.assert_allclose(q[0], matrix(table, "q0", JOINTS)[problem], rtol=0, atol=SAMPLED)


def test_samples_of_a_failed_problem_are_empty(tmp_path):
    data = scurve_file(jmax={"normal": [20.0, 20.0]})
    data["sweep"].update(problems=40, chunk=20)
    summary = sweep.run(sweep.parse(data), tmp_path, workers=1)
    table = rows(tmp_path)
    failed = [i for i, e in enumerate(table["error"].to_pylist()) if e]
    assert summary.failed == len(failed) > 0
    for i in failed:
        t, q = sweep.read_samples(tmp_path, i)
        assert t.shape == (0,) and q.shape == (0, JOINTS)
    ok = next(i for i in range(40) if i not in failed)
    t, q = sweep.read_samples(tmp_path, ok)
    assert t.size > 1 and np.isfinite(q).all()


def test_stale_samples_of_an_unfinished_chunk_are_replaced(sampled, tmp_path):
    # A run that died between a chunk's samples and its rows: rows mean done.
    reference, _, plans = sampled
    out = tmp_path / "out"
    shutil.copytree(reference, out)
    (out / "data" / "part-000001.parquet").unlink()
    shutil.rmtree(out / "samples" / "chunk-000001.zarr")
    shutil.copytree(out / "samples" / "chunk-000000.zarr", out / "samples" / "chunk-000001.zarr")
    summary = sweep.run(sweep.parse(scurve_file()), out, workers=1)
    assert (summary.planned_chunks, summary.skipped_chunks) == (1, 2)
    for problem in (200, 311, 399):
        t, q = sweep.read_samples(out, problem)
        np.testing.assert_allclose(q, plans[problem].position(t), rtol=0, atol=SAMPLED)
    assert sorted(p.name for p in (out / "samples").iterdir()) == [
        f"chunk-{k:06d}.zarr" for k in range(PROBLEMS // CHUNK)
    ]


def test_no_samples_without_keep_samples_or_beyond_the_sweep(sampled, tmp_path):
    out, _, _ = sampled
    with pytest.raises(sweep.SweepError, match=r"problem must be a number from 0 to 599, got 600"):
        sweep.read_samples(out, PROBLEMS)
    with pytest.raises(sweep.SweepError, match=r"got -1"):
        sweep.read_samples(out, -1)
    with pytest.raises(sweep.SweepError, match="holds no sweep"):
        sweep.read_samples(tmp_path / "nowhere", 0)
    data = scurve_file()
    data["sweep"].update(keep="summary", problems=10, chunk=10)
    sweep.run(sweep.parse(data), tmp_path, workers=1)
    assert not (tmp_path / "samples").exists()
    with pytest.raises(sweep.SweepError, match="no samples for problem 3"):
        sweep.read_samples(tmp_path, 3)
