"""Every engine writes the same rows, bit for bit: one process, a process pool, Ray tasks.

The Ray test starts a real local Ray instance (about 10 s): CI must run one sweep on
Ray, so it is not marked slow. The runs are made once for the module.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from trajkit import sweep
from trajkit.errors import InvalidInputError

from .helpers import assert_same_rows, data_files, parts, pc, rows, trapezoid_file

ENGINES = [("local", 1), ("local", 2), ("ray", 2)]
PROBLEMS, CHUNK = 3000, 500


def _shutdown_ray() -> None:
    ray = sys.modules.get("ray")
    if ray is not None and ray.is_initialized():
        ray.shutdown()


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> dict:
    spec = sweep.parse(trapezoid_file(PROBLEMS, CHUNK))
    results = {}
    try:
        for engine, workers in ENGINES:
            out = tmp_path_factory.mktemp(f"{engine}-{workers}")
            summary = sweep.run(spec, out, engine=engine, workers=workers)
            left_running = "ray" in sys.modules and sys.modules["ray"].is_initialized()
            results[engine, workers] = (out, summary, left_running)
    finally:
        _shutdown_ray()
    return results


def test_every_engine_plans_every_chunk_once(runs):
    for (engine, workers), (out, summary, _) in runs.items():
        assert summary.planned_chunks == PROBLEMS // CHUNK, (engine, workers)
        assert summary.skipped_chunks == 0
        assert summary.problems == PROBLEMS
        assert data_files(out) == parts(PROBLEMS // CHUNK)
    counts = {(s.failed, s.infeasible) for _, s, _ in runs.values()}
    assert len(counts) == 1
    failed, infeasible = counts.pop()
    assert failed > 0  # vmax ~ normal(1.5, 0.5): a few negative limits, each a row
    assert infeasible >= failed


def test_engines_write_identical_rows(runs):
    tables = {key: rows(out) for key, (out, _, _) in runs.items()}
    reference = tables["local", 1]
    problems = reference["problem"].to_numpy()
    np.testing.assert_array_equal(problems, np.arange(PROBLEMS))
    np.testing.assert_array_equal(reference["chunk"].to_numpy(), problems // CHUNK)
    for table in tables.values():
        assert_same_rows(table, reference)
    # Table.equals agrees on the planned rows (the failed ones hold NaN, never equal to itself).
    planned = [table.filter(pc.equal(table["error"], "")) for table in tables.values()]
    assert planned[0].num_rows == PROBLEMS - runs["local", 1][1].failed
    assert all(table.equals(planned[0]) for table in planned)


def test_engines_write_identical_files(runs):
    folders = [out for out, _, _ in runs.values()]
    for name in parts(PROBLEMS // CHUNK):
        contents = {(Path(folder) / "data" / name).read_bytes() for folder in folders}
        assert len(contents) == 1, name


def test_ray_engine_shuts_down_the_instance_it_started(runs):
    assert runs["ray", 2][2] is False


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"engine": "spark"}, "engine must be one of local, ray"),
        ({"workers": 0}, "workers must be a whole number >= 1"),
        ({"workers": 1.5}, "workers must be a whole number >= 1"),
        ({"workers": True}, "workers must be a whole number >= 1"),
    ],
)
def test_bad_engine_options_are_refused_before_anything_is_written(tmp_path, options, message):
    spec = sweep.parse(trapezoid_file(10, 5))
    with pytest.raises(InvalidInputError, match=message):
        sweep.run(spec, tmp_path / "out", **options)
    assert not (tmp_path / "out").exists()
