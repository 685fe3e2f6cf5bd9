"""Sweep files: a problem's inputs depend only on the file and its number.

Random parameters come from a generator seeded with (seed, chunk index), grids and value
lists combine as a Cartesian product cycling with the problem number, and what the
engines wrote is exactly what :meth:`SweepSpec.inputs` says.
"""

from __future__ import annotations

import itertools
import tracemalloc

import numpy as np
import pytest

from trajkit import sweep

from .helpers import chunk_rows, matrix, rows

JOINTS = 3
GRID_QF = np.linspace(-1.0, 1.0, 3)
GRID_VMAX = np.linspace(1.0, 2.0, 2)
VALUES_AMAX = [[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]]


def mixed_file(problems: int | None = 1100, chunk: int = 250, seed: int = 3) -> dict:
    """Every kind of parameter: uniform, normal, grid, values, fixed, default."""
    head = {"planner": "trapezoid", "chunk": chunk, "seed": seed}
    if problems is not None:
        head["problems"] = problems
    return {
        "sweep": head,
        "robot": {"joints": JOINTS},
        "fixed": {"vf": [0.0, 0.0, 0.0]},
        "swept": {
            "q0": {"uniform": [[-1.0, 0.0, 2.0], [0.0, 1.0, 2.5]]},
            "qf": {"grid": [-1.0, 1.0, 3]},
            "vmax": {"grid": [1.0, 2.0, 2]},
            "amax": {"values": VALUES_AMAX},
            "v0": {"normal": [[0.0, 0.0, 0.0], [0.1, 0.0, 0.2]]},
        },
    }


NAMES = ("q0", "qf", "vmax", "amax", "v0", "vf")


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    spec = sweep.parse(mixed_file())
    out = tmp_path_factory.mktemp("mixed")
    sweep.run(spec, out, workers=2)
    return spec, rows(out)


def test_chunk_inputs_are_the_rows_the_engines_wrote(written):
    spec, table = written
    assert spec.chunks == 5
    for k in range(spec.chunks):
        ids, values = spec.inputs(k)
        part = chunk_rows(table, k)
        np.testing.assert_array_equal(part["problem"].to_numpy(), ids)
        np.testing.assert_array_equal(ids, np.arange(250 * k, min(250 * (k + 1), 1100)))
        assert sorted(values) == sorted(NAMES)
        for name in NAMES:
            assert values[name].shape == (ids.size, JOINTS)
            np.testing.assert_array_equal(matrix(part, name, JOINTS), values[name], err_msg=name)


def test_chunk_inputs_depend_only_on_seed_and_chunk():
    small, large = sweep.parse(mixed_file(1000)), sweep.parse(mixed_file(2000))
    assert small.digest != large.digest
    for k in (3, 0, 2, 1):  # any order: no state carries from one chunk to the next
        ids_small, small_values = small.inputs(k)
        ids_large, large_values = large.inputs(k)
        np.testing.assert_array_equal(ids_small, ids_large)
        for name in NAMES:
            np.testing.assert_array_equal(small_values[name], large_values[name])
    first, again = small.inputs(2), sweep.parse(mixed_file(1000)).inputs(2)
    for name in NAMES:
        np.testing.assert_array_equal(first[1][name], again[1][name])


def test_another_seed_draws_other_random_inputs_only():
    one, other = sweep.parse(mixed_file(seed=3)), sweep.parse(mixed_file(seed=4))
    assert one.digest != other.digest
    for k in (0, 4):
        _, a = one.inputs(k)
        _, b = other.inputs(k)
        assert not np.any(a["q0"] == b["q0"])
        random_v0 = [0, 2]  # joint 2's std is 0: v0_2 is its mean, whatever the seed
        assert not np.any(a["v0"][:, random_v0] == b["v0"][:, random_v0])
        for name in ("qf", "vmax", "amax", "vf"):
            np.testing.assert_array_equal(a[name], b[name])
        np.testing.assert_array_equal(a["v0"][:, 1], 0.0)


def test_chunks_draw_independently():
    spec = sweep.parse(mixed_file())
    _, first = spec.inputs(0)
    _, second = spec.inputs(1)
    assert not np.any(first["q0"] == second["q0"])


def test_grids_and_values_combine_as_a_cartesian_product(written):
    spec, table = written
    assert spec.combinations() == 3 * 2 * 2
    # Planner order (q0, qf, vmax, amax, ...), the last varying fastest.
    product = list(itertools.product(range(3), range(2), range(2)))
    qf, vmax, amax = (matrix(table, name, JOINTS) for name in ("qf", "vmax", "amax"))
    for i in [0, 1, 2, 5, 11, 12, 13, 249, 250, 251, 777, 1099]:
        a, b, c = product[i % 12]
        np.testing.assert_array_equal(qf[i], np.full(JOINTS, GRID_QF[a]), err_msg=str(i))
        np.testing.assert_array_equal(vmax[i], np.full(JOINTS, GRID_VMAX[b]), err_msg=str(i))
        np.testing.assert_array_equal(amax[i], VALUES_AMAX[c], err_msg=str(i))
    combos = {(tuple(qf[i]), tuple(vmax[i]), tuple(amax[i])) for i in range(12)}
    assert len(combos) == 12
    for i in range(12, 1100):
        assert (qf[i] == qf[i % 12]).all() and (amax[i] == amax[i % 12]).all()
        assert (vmax[i] == vmax[i % 12]).all()


def test_the_default_problem_count_is_one_per_combination():
    spec = sweep.parse(mixed_file(problems=None))
    assert spec.problems == 12
    assert spec.chunk == 250 and spec.chunks == 1
    ids, values = spec.inputs(0)
    np.testing.assert_array_equal(ids, np.arange(12))
    unique = {(tuple(values["qf"][i]), tuple(values["vmax"][i]), tuple(values["amax"][i]))
              for i in range(12)}  # fmt: skip
    assert len(unique) == 12


def test_distributions_keep_their_bounds_and_moments(written):
    _, table = written
    q0 = matrix(table, "q0", JOINTS)
    for j, (low, high) in enumerate([(-1.0, 0.0), (0.0, 1.0), (2.0, 2.5)]):
        assert low <= q0[:, j].min() and q0[:, j].max() < high
        # 1100 uniform draws: the mean within 5 standard errors of the middle.
        assert abs(q0[:, j].mean() - (low + high) / 2) < 5 * (high - low) / np.sqrt(12 * 1100)
    v0 = matrix(table, "v0", JOINTS)
    np.testing.assert_array_equal(v0[:, 1], 0.0)  # std 0: exactly the mean
    for j, std in ((0, 0.1), (2, 0.2)):
        assert abs(v0[:, j].mean()) < 5 * std / np.sqrt(1100)
        assert abs(v0[:, j].std() / std - 1) < 5 / np.sqrt(2 * 1100)
    np.testing.assert_array_equal(matrix(table, "vf", JOINTS), 0.0)


def test_defaults_of_a_minimal_file():
    spec = sweep.parse({"sweep": {"planner": "trapezoid", "problems": 25_000},
                        "fixed": {"q0": 0.0, "qf": 1.0, "vmax": 1.0, "amax": 2.0}})  # fmt: skip
    assert (spec.name, spec.seed, spec.keep, spec.sample_step) == ("sweep", 0, "summary", 0.01)
    assert spec.robot["joints"] == 6
    assert spec.chunk == 10_000 and spec.chunks == 3
    assert spec.options == {"sync": "time"}
    for name in ("v0", "vf"):
        assert spec.parameters[name].kind == "fixed"
        np.testing.assert_array_equal(spec.parameters[name].arguments[0], np.zeros(6))
    ids, _ = spec.inputs(2)
    np.testing.assert_array_equal(ids, np.arange(20_000, 25_000))


def test_digest_ignores_the_name_and_key_order_only():
    base = mixed_file()
    renamed = mixed_file()
    renamed["sweep"]["name"] = "a new name"
    reordered = mixed_file()
    reordered["swept"] = dict(reversed(list(reordered["swept"].items())))
    digests = {sweep.parse(d).digest for d in (base, renamed, reordered)}
    assert len(digests) == 1
    widened = mixed_file()
    widened["swept"]["q0"] = {"uniform": [[-1.0, 0.0, 2.0], [0.0, 1.0, 2.6]]}
    assert sweep.parse(widened).digest not in digests


def test_missing_mobile_limit_names_the_sweep_key():
    with pytest.raises(sweep.SweepError) as caught:
        sweep.parse({"sweep": {"planner": "mobile", "problems": 3}, "robot": {"name": "unicycle"},
                     "fixed": {"goal": [1.0, 1.0, 0.0]}})  # fmt: skip
    assert str(caught.value).startswith("fixed.vmax:")


@pytest.mark.parametrize(
    ("planner", "option"), [("topp", "points"), ("topp", "grid"), ("task_space", "samples")]
)
def test_planner_options_below_two_are_refused_by_key(planner, option):
    with pytest.raises(sweep.SweepError, match=rf"sweep\.{option}: expected a whole number from 2"):
        sweep.parse({"sweep": {"planner": planner, option: 1}})


def _trapezoids(**head) -> dict:
    return {"sweep": {"planner": "trapezoid", **head}, "robot": {"joints": 2},
            "fixed": {"qf": 1.0, "vmax": 1.0, "amax": 1.0},
            "swept": {"q0": {"uniform": [-1.0, 1.0]}}}  # fmt: skip


@pytest.mark.parametrize(
    ("data", "message"),
    [
        # A run lists every chunk: 1e10 of them took all the memory before a row.
        (_trapezoids(problems=10**10, chunk=1),
         r"^sweep\.chunk: 10000000000 problems in chunks of 1 make 10000000000 chunks \(files\), "
         r"more than 1e\+06: use a larger chunk$"),
        # One chunk's inputs: 1e9 problems of 12 numbers, 89 GiB (a MemoryError before).
        (_trapezoids(problems=10**9, chunk=10**9),
         r"^sweep\.chunk: 1000000000 problems of 12 numbers each take 91553 MiB of inputs per "
         r"chunk, more than 256 MiB: use a smaller chunk$"),
        (_trapezoids() | {"swept": {"q0": {"grid": [0.0, 1.0, 1e9]}}},
         r"^swept\.q0\.grid: a count of 1000000000 points is more than 1e\+06$"),
    ],
    ids=["chunks", "chunk-memory", "grid-points"],
)  # fmt: skip
def test_sizes_that_cannot_run_are_refused_by_key(data, message):
    tracemalloc.start()
    try:
        with pytest.raises(sweep.SweepError, match=message):
            sweep.parse(data)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 2**24  # 16 MiB: refused before anything of that size is made


def test_the_largest_sizes_allowed_still_parse():
    assert sweep.parse(_trapezoids(problems=10**10)).chunks == 10**6  # the default chunk
    spec = sweep.parse(_trapezoids(problems=2 * 10**6, chunk=2**28 // 96))
    assert spec.chunk == 2796202  # 12 numbers of 8 bytes: 256 MiB per chunk
    assert sweep.parse(_trapezoids() | {"swept": {"q0": {"grid": [0, 1, 10**6]}}}).problems == (
        10**6
    )
