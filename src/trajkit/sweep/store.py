"""Where a sweep's results go: a Parquet dataset, one file per chunk, and its samples.

Layout of an output folder::

    sweep.json              what was swept (the resume check compares it)
    data/part-000042.parquet   chunk 42's rows
    samples/chunk-000042.zarr  chunk 42's sampled trajectories (keep = "samples")

Each chunk's file is written to a temporary name and renamed, so a chunk is
either complete or absent: an interrupted sweep resumes by planning the chunks
whose file is missing, and can never hold a row twice.
"""

from __future__ import annotations

import contextlib
import json
import os
import shutil
import tempfile
from pathlib import Path
from typing import Any

import numpy as np

from trajkit.errors import TrajkitError
from trajkit.io.atomic import atomic_write
from trajkit.sweep.planners import ChunkResult
from trajkit.sweep.spec import SweepError, SweepSpec

__all__ = ["ScaleUnavailableError", "done_chunks", "encode_chunk", "prepare", "read",
           "read_samples", "require", "write_chunk"]  # fmt: skip


class ScaleUnavailableError(TrajkitError):
    """A library the sweep needs (pyarrow, zarr or ray) is not installed."""


def require(module: str) -> Any:
    """Import ``module`` or say which extra installs it."""
    import importlib

    try:
        return importlib.import_module(module)
    except ImportError:
        raise ScaleUnavailableError(
            f'sweeps need {module.split(".")[0]}: pip install "trajkit[scale]"'
        ) from None


def prepare(spec: SweepSpec, out: Path) -> None:
    """Create the folder, or check that it holds this same sweep (to resume it)."""
    out.mkdir(parents=True, exist_ok=True)
    (out / "data").mkdir(exist_ok=True)
    meta = out / "sweep.json"
    record = {"name": spec.name, "digest": spec.digest, "problems": spec.problems,
              "chunk": spec.chunk, "chunks": spec.chunks,
              "spec": json.loads(spec.text)}  # fmt: skip
    if meta.exists():
        try:
            found = json.loads(meta.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            raise SweepError(
                f"{meta} is unreadable: delete the folder or use another --out"
            ) from None
        if found.get("digest") != spec.digest:
            raise SweepError(
                f"{out} holds a different sweep ({found.get('name', '?')!r}); use another --out "
                "or delete it to start over"
            )
        return
    text = json.dumps(record, indent=2, sort_keys=True).encode()
    atomic_write(meta, lambda handle: handle.write(text))


def done_chunks(out: Path) -> set[int]:
    """Chunks whose file is complete."""
    found = set()
    for path in (out / "data").glob("part-*.parquet"):
        with contextlib.suppress(ValueError):
            found.add(int(path.stem.split("-")[1]))
    return found


def _table(spec: SweepSpec, ids: np.ndarray, inputs: dict, result: ChunkResult, chunk: int
           ) -> Any:  # fmt: skip
    pa = require("pyarrow")
    columns: dict[str, Any] = {"problem": pa.array(ids, pa.int64()),
                               "chunk": pa.array(np.full(ids.size, chunk), pa.int32())}  # fmt: skip
    for name in sorted(inputs):
        values = np.asarray(inputs[name], dtype=float)
        # An input named like a result (the polynomial's duration) keeps both.
        label = f"{name}_given" if name in result.columns else name
        if values.shape[1] == 1:
            columns[label] = pa.array(values[:, 0])
        else:
            for j in range(values.shape[1]):
                columns[f"{label}_{j + 1}"] = pa.array(values[:, j])
    for name, values in result.columns.items():
        if name == "error":
            columns[name] = pa.array([str(v) for v in values], pa.string())
        else:
            columns[name] = pa.array(values)
    return pa.table(columns)


def encode_chunk(spec: SweepSpec, chunk: int, ids: np.ndarray, inputs: dict,
                 result: ChunkResult) -> bytes:  # fmt: skip
    """One chunk's rows as the bytes of a Parquet file (made where the chunk was planned)."""
    pa = require("pyarrow")
    pq = require("pyarrow.parquet")
    sink = pa.BufferOutputStream()
    pq.write_table(_table(spec, ids, inputs, result, chunk), sink, compression="zstd")
    return sink.getvalue().to_pybytes()


def write_chunk(spec: SweepSpec, out: Path, chunk: int, rows: bytes, ids: np.ndarray,
                samples: tuple[np.ndarray, np.ndarray] | None) -> None:  # fmt: skip
    """Write one chunk's samples, then its rows, each atomically: rows mean done."""
    if samples is not None:
        _write_samples(spec, out, chunk, ids, samples)
    atomic_write(out / "data" / f"part-{chunk:06d}.parquet", lambda handle: handle.write(rows))


def _write_samples(spec: SweepSpec, out: Path, chunk: int, ids: np.ndarray,
                   samples: tuple[np.ndarray, np.ndarray]) -> None:  # fmt: skip
    zarr = require("zarr")
    values, lengths = samples
    folder = out / "samples"
    folder.mkdir(exist_ok=True)
    target = folder / f"chunk-{chunk:06d}.zarr"
    staging = Path(tempfile.mkdtemp(dir=folder, prefix=f".{target.name}."))
    try:
        group = zarr.open_group(str(staging), mode="w")
        group.attrs.update({"period": spec.period, "first_problem": int(ids[0]) if ids.size else 0})
        group.create_array("problem", data=ids)
        group.create_array("length", data=lengths)
        rows = max(1, min(values.shape[0], 256))
        group.create_array("values", data=values, chunks=(rows, *values.shape[1:]))
        if target.exists():  # an earlier run died between the samples and the rows
            shutil.rmtree(target)
        os.replace(staging, target)
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise


def read(out: str | Path) -> Any:
    """The sweep's rows as a lazy :class:`pyarrow.dataset.Dataset`.

    ``read(out).to_table().to_pandas()`` loads everything; filters and column
    selections (``to_table(columns=[...], filter=...)``) read only what they need.
    """
    ds = require("pyarrow.dataset")
    folder = Path(out) / "data"
    if not folder.is_dir():
        raise SweepError(f"{out} holds no sweep results (no data folder)")
    return ds.dataset(str(folder), format="parquet")


def read_samples(out: str | Path, problem: int) -> tuple[np.ndarray, np.ndarray]:
    """Times (s) and sampled values ``(T, width)`` of one problem, by its number."""
    zarr = require("zarr")
    folder = Path(out)
    try:
        meta = json.loads((folder / "sweep.json").read_text(encoding="utf-8"))
    except (OSError, ValueError):
        raise SweepError(f"{out} holds no sweep (no readable sweep.json)") from None
    if isinstance(problem, bool) or not 0 <= int(problem) < int(meta["problems"]):
        raise SweepError(f"problem must be a number from 0 to {int(meta['problems']) - 1}, "
                         f"got {problem!r}")  # fmt: skip
    chunk = int(problem) // int(meta["chunk"])
    path = folder / "samples" / f"chunk-{chunk:06d}.zarr"
    if not path.exists():
        raise SweepError(f"no samples for problem {problem} (keep = \"samples\"? chunk {chunk} "
                         "not done?)")  # fmt: skip
    group = zarr.open_group(str(path), mode="r")
    row = int(problem) - int(group.attrs["first_problem"])
    length = int(group["length"][row])
    values = np.asarray(group["values"][row, :length])
    return np.arange(length) * float(group.attrs["period"]), values
