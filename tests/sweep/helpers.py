"""Shared helpers of the sweep tests: specs in memory, columns as arrays, exact row equality."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest

from trajkit import sweep

NEEDS = 'sweeps store rows with pyarrow: pip install "trajkit[scale]"'
pa = pytest.importorskip("pyarrow", reason=NEEDS)
pc = pytest.importorskip("pyarrow.compute", reason=NEEDS)


def trapezoid_file(problems: int = 3000, chunk: int = 500, *, seed: int = 5, joints: int = 6,
                   **swept: Any) -> dict[str, Any]:  # fmt: skip
    """A trapezoid sweep file as a dict: random q0/qf, vmax normal (some rows fail)."""
    return {
        "sweep": {"name": "trapezoids", "planner": "trapezoid", "problems": problems,
                  "chunk": chunk, "seed": seed},
        "robot": {"joints": joints},
        "fixed": {"amax": 2.0},
        "swept": {"q0": {"uniform": [-1.0, 1.0]}, "qf": {"uniform": [-1.0, 1.0]},
                  "vmax": {"normal": [1.5, 0.5]}, **swept},
    }  # fmt: skip


def rows(out: str | Path) -> pa.Table:
    """Every row of the sweep in ``out``, in problem order."""
    return sweep.read(out).to_table().sort_by("problem")


def chunk_rows(table: pa.Table, chunk: int) -> pa.Table:
    """The rows of one chunk."""
    return table.filter(pc.equal(table["chunk"], chunk))


def matrix(table: pa.Table, name: str, width: int) -> np.ndarray:
    """Input or peak ``name`` as an ``(n, width)`` array (columns name_1..name_width)."""
    if width == 1 and name in table.column_names:
        return table[name].to_numpy()[:, None]
    return np.column_stack([table[f"{name}_{j + 1}"].to_numpy() for j in range(width)])


def assert_same_rows(first: pa.Table, second: pa.Table) -> None:
    """Same columns, types and values, bit for bit (NaN equal to NaN, unlike Table.equals)."""
    assert first.schema.equals(second.schema), (first.schema, second.schema)
    assert first.num_rows == second.num_rows
    for name in first.column_names:
        a, b = first[name].to_numpy(), second[name].to_numpy()
        if a.dtype.kind == "f":
            assert np.array_equal(a.view(np.int64), b.view(np.int64)), name
        else:
            assert a.tolist() == b.tolist(), name


def data_files(out: str | Path) -> list[str]:
    """Every file name in ``out/data``, hidden temporaries included."""
    return sorted(path.name for path in (Path(out) / "data").iterdir())


def parts(count: int) -> list[str]:
    """The names of the part files of chunks 0..count-1."""
    return [f"part-{k:06d}.parquet" for k in range(count)]
