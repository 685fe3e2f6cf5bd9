"""keep = "samples": each problem's trajectory, sampled every period, in Zarr beside the rows.

The samples are exactly the planned trajectory at t = 0, period, 2 period, ... up to
its duration, found by problem number whichever chunk holds it.
"""

from __future__ import annotations

import json
import shutil
import tracemalloc
import warnings

import numpy as np
import pytest

import trajkit as tk
from trajkit import batch, sweep
from trajkit.errors import InvalidInputError

from .helpers import data_files, matrix, parts, rows

JOINTS, PROBLEMS, CHUNK, PERIOD = 3, 600, 200, 0.01
SAMPLED = 1e-12  # absolute (rad): samples against the trajectory evaluated directly


def scurve_file(**swept) -> dict:
    return {
        "sweep": {"planner": "scurve", "problems": PROBLEMS, "chunk": CHUNK, "seed": 3,
                  "keep": "samples", "sample_step": PERIOD},
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
    with pytest.raises(
        sweep.SweepError, match=r"problem must be a whole number from 0 to 599, got 600"
    ):
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


def samples_file(planner: str, fixed: dict, swept: dict, period: float) -> dict:
    return {"sweep": {"planner": planner, "problems": 4, "chunk": 4, "keep": "samples",
                      "sample_step": period},
            "robot": {"joints": 2}, "fixed": fixed, "swept": swept}  # fmt: skip


TRAPEZOID = {"q0": 0.0, "qf": 1.0, "amax": 2.0}
POLYNOMIAL = {"q0": 0.0, "qf": 1.0, "amax": 2.0, "vmax": 1.0}


@pytest.mark.parametrize(
    ("planner", "fixed", "swept", "period", "samples"),
    [
        # A failed row (vmax < 0) has 1 sample; 1e300 samples used to wrap round to a
        # negative int64 length, stored and read back as an empty trajectory.
        ("trapezoid", TRAPEZOID, {"vmax": {"values": [-1.0, 1.0]}}, 1e-300, "1.5e+300 samples"),
        ("trapezoid", TRAPEZOID | {"vmax": 1.0}, {}, 5e-324, "inf samples"),
        ("quintic", POLYNOMIAL, {"duration": {"values": [-1.0, 1.0]}}, 1e-300,
         "1e+300 samples"),
    ],
    ids=["batch-1e-300", "batch-denormal", "one-by-one-1e-300"],
)  # fmt: skip
def test_a_sample_count_past_int64_is_refused_not_stored(tmp_path, planner, fixed, swept,
                                                         period, samples):  # fmt: skip
    spec = sweep.parse(samples_file(planner, fixed, swept, period))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no RuntimeWarning of an overflowing cast either
        with pytest.raises(InvalidInputError) as caught:
            sweep.run(spec, tmp_path, workers=1)
    message = str(caught.value)
    assert message.startswith(f'keep = "samples" with sample_step = {period:.6g} s: ')
    assert samples in message and "more than the 2 GiB allowed" in message
    assert data_files(tmp_path) == []  # nothing stored for the chunk
    assert not (tmp_path / "samples").exists() or not any((tmp_path / "samples").iterdir())


@pytest.mark.parametrize(
    ("planner", "fixed"),
    [("trapezoid", TRAPEZOID | {"qf": 1e6, "vmax": 1e-3}),  # a 1e9 s move
     ("quintic", POLYNOMIAL | {"duration": 1e9})],
    ids=["batch", "one-by-one"],
)  # fmt: skip
def test_huge_samples_are_refused_before_anything_is_allocated(tmp_path, planner, fixed):
    # 1e11 samples of 2 joints for each of 4 problems: 6,000 GiB. The batch planners
    # made the 745 GiB time grid before the 2 GiB check (a MemoryError at best).
    spec = sweep.parse(samples_file(planner, fixed, {}, 0.01))
    tracemalloc.start()
    try:
        with pytest.raises(InvalidInputError, match=r"1e\+09 s trajectory has 1e\+11 samples"):
            sweep.run(spec, tmp_path, workers=1)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 2**25  # 32 MiB: planning 4 problems, nothing of the samples' size
    assert data_files(tmp_path) == []


def _zarr_json(store, change) -> None:
    meta = json.loads((store / "zarr.json").read_text(encoding="utf-8"))
    change(meta["attributes"])
    (store / "zarr.json").write_text(json.dumps(meta), encoding="utf-8")


def _set_lengths(store, value: int) -> None:
    import zarr

    zarr.open_group(str(store), mode="a")["length"][:] = value


DAMAGES = {
    "empty-folder": lambda store: (shutil.rmtree(store), store.mkdir()),
    "a-file": lambda store: (shutil.rmtree(store), store.write_bytes(b"")),
    "metadata-not-json": lambda store: (store / "zarr.json").write_text("{", encoding="utf-8"),
    "no-length-array": lambda store: shutil.rmtree(store / "length"),
    "no-step": lambda store: _zarr_json(store, lambda attrs: attrs.pop("sample_step")),
    "step-not-a-number": lambda store: _zarr_json(store, lambda a: a.update(sample_step=None)),
    "values-garbled": lambda store: (store / "values" / "c" / "0" / "0" / "0").write_bytes(b"xx"),
    # These two read back without any error before: zeros, and 146 samples at 0 times.
    "values-lost": lambda store: shutil.rmtree(store / "values" / "c"),
    "negative-length": lambda store: _set_lengths(store, -5),
    "rows-shifted": lambda store: _zarr_json(store, lambda a: a.update(first_problem=-100)),
}  # fmt: skip


@pytest.fixture(scope="module")
def small_samples(tmp_path_factory):
    out = tmp_path_factory.mktemp("small")
    data = {
        "sweep": {"planner": "trapezoid", "problems": 4, "chunk": 4, "keep": "samples"},
        "robot": {"joints": 2},
        "fixed": {"q0": 0.0, "qf": 1.0, "amax": 2.0, "vmax": 1.0},
    }
    sweep.run(sweep.parse(data), out, workers=1)
    return out


@pytest.mark.parametrize("damage", list(DAMAGES))
def test_a_damaged_samples_store_is_a_sweep_error_naming_it(small_samples, tmp_path, damage):
    out = tmp_path / "out"
    shutil.copytree(small_samples, out)
    t, q = sweep.read_samples(out, 1)
    assert t.size == q.shape[0] > 100 and np.isfinite(q).all()  # intact before
    store = out / "samples" / "chunk-000000.zarr"
    DAMAGES[damage](store)
    with pytest.raises(sweep.SweepError) as caught:  # an InvalidInputError, a TrajkitError
        sweep.read_samples(out, 1)
    message = str(caught.value)
    assert message.startswith(f"the samples of chunk 0 in {store} are damaged (")
    assert message.endswith(f"delete {out / 'data' / 'part-000000.parquet'} and run the sweep "
                            "again to redo the chunk")  # fmt: skip
    assert isinstance(caught.value, InvalidInputError)


@pytest.mark.parametrize("problem", [1.5, "1", True, None])
def test_a_problem_number_must_be_a_whole_number(small_samples, problem):
    with pytest.raises(sweep.SweepError, match=r"problem must be a whole number from 0 to 3, got "):
        sweep.read_samples(small_samples, problem)
