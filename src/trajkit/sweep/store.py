"""Where a sweep's results go: a Parquet dataset, one file per chunk, and its samples.

Layout of an output folder::

    sweep.json              what was swept (the resume check compares it)
    data/part-000042.parquet   chunk 42's rows
    samples/chunk-000042.zarr  chunk 42's sampled trajectories (keep = "samples")

Each chunk's file is written to a temporary name, flushed to the disk (``fsync``)
and renamed, and the rename flushed too, so a chunk is either complete or absent,
even after a power loss: an interrupted sweep resumes by planning the chunks whose
file is missing or does not read back whole, and can never hold a row twice. The
temporaries a killed run leaves (hidden ``.part-*`` files, ``.chunk-*`` folders)
are removed by the next run in the folder; one run at a time may write there
(``.lock``).
"""

from __future__ import annotations

import contextlib
import json
import os
import re
import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np

from trajkit.errors import MissingDependencyError
from trajkit.sweep.planners import ChunkResult
from trajkit.sweep.spec import SweepError, SweepSpec

__all__ = ["ScaleUnavailableError", "done_chunks", "encode_chunk", "lock", "prepare", "read",
           "read_samples", "remove_temporaries", "require", "write_chunk"]  # fmt: skip


class ScaleUnavailableError(MissingDependencyError):
    """A library the sweep needs (pyarrow, zarr or ray) is not installed."""


def require(module: str) -> Any:
    """Import ``module`` or say which extra installs it."""
    import importlib

    try:
        return importlib.import_module(module)
    except ImportError:
        raise ScaleUnavailableError.absent("sweeps", module.split(".")[0], "scale") from None


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
        if not isinstance(found, dict) or found.get("digest") != spec.digest:
            name = found.get("name", "?") if isinstance(found, dict) else "?"
            raise SweepError(
                f"{out} holds a different sweep ({name!r}); use another --out "
                "or delete it to start over"
            )
        return
    _durable_write(meta, json.dumps(record, indent=2, sort_keys=True).encode())


@contextlib.contextmanager
def lock(out: Path) -> Iterator[None]:
    """Hold ``out/.lock`` while a run writes there: a second run at once is refused.

    Without ``fcntl`` (Windows), or on a file system without locks, nothing is locked.
    """
    try:
        import fcntl
    except ImportError:
        yield
        return
    with open(out / ".lock", "a+b") as handle:
        locked = True
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise SweepError(f"another trajkit sweep is writing to {out}: wait for it to end, "
                             "or use another --out") from None  # fmt: skip
        except OSError:  # a file system without locks (some network mounts): go on
            locked = False
        try:
            yield
        finally:
            if locked:
                fcntl.flock(handle, fcntl.LOCK_UN)


#: What a run killed midway leaves: the temporaries of _durable_write and _write_samples.
_TEMPORARY_FILES = re.compile(r"\.(part-\d+\.parquet|sweep\.json)\..+\.tmp")
_TEMPORARY_FOLDERS = re.compile(r"\.chunk-\d+\.zarr\..+")


def remove_temporaries(out: Path) -> list[Path]:
    """Remove what an earlier run, killed while writing, left in ``out``; return it.

    Only call it holding :func:`lock`: a live run's temporaries look the same.
    """
    removed = []
    for folder, pattern in ((out, _TEMPORARY_FILES), (out / "data", _TEMPORARY_FILES),
                            (out / "samples", _TEMPORARY_FOLDERS)):  # fmt: skip
        if not folder.is_dir():
            continue
        for path in folder.iterdir():
            if not pattern.fullmatch(path.name):
                continue
            if path.is_dir() and not path.is_symlink():
                shutil.rmtree(path, ignore_errors=True)
            else:
                with contextlib.suppress(FileNotFoundError):
                    path.unlink()
            removed.append(path)
    return removed


def done_chunks(out: Path, spec: SweepSpec | None = None) -> set[int]:
    """Chunks whose file is complete.

    With ``spec``, a chunk counts only if its file reads back with the chunk's number
    of rows (and its samples exist, with ``keep = "samples"``): a file emptied or cut
    short (a power loss before its data reached the disk) is removed, to be redone,
    not skipped on every resume.
    """
    found = set()
    for path in (out / "data").glob("part-*.parquet"):
        with contextlib.suppress(ValueError):
            chunk = int(path.stem.split("-")[1])
            if spec is None or _whole(spec, out, chunk, path):
                found.add(chunk)
    return found


def _whole(spec: SweepSpec, out: Path, chunk: int, path: Path) -> bool:
    pq = require("pyarrow.parquet")
    if not 0 <= chunk < spec.chunks:
        return False
    expected = min(spec.chunk, spec.problems - chunk * spec.chunk)
    try:
        whole = pq.read_metadata(str(path)).num_rows == expected
    except Exception:  # whatever pyarrow makes of a truncated or garbled file
        whole = False
    if whole and spec.keep == "samples":
        whole = (out / "samples" / f"chunk-{chunk:06d}.zarr" / "zarr.json").is_file()
    if not whole:
        with contextlib.suppress(FileNotFoundError):
            path.unlink()
    return whole


def _fsync_folder(folder: Path) -> None:
    """Flush a folder's entries (a rename into it) to the disk, where the OS allows."""
    try:
        descriptor = os.open(folder, os.O_RDONLY)
    except OSError:  # Windows cannot open a folder: its renames need no flush
        return
    try:
        os.fsync(descriptor)
    except OSError:
        pass  # some file systems refuse to flush a folder; nothing more can be done
    finally:
        os.close(descriptor)


def _durable_write(target: Path, data: bytes) -> None:
    """Write ``data`` to ``target`` whole or not at all, flushed to the disk.

    A temporary beside it, fsynced, renamed over it, and the folder fsynced: after a
    crash the target is the old file or the new one, never an empty or short one.
    """
    folder = target.parent
    handle = tempfile.NamedTemporaryFile(mode="wb", dir=folder, prefix=f".{target.name}.",
                                         suffix=".tmp", delete=False)  # fmt: skip
    try:
        with handle:
            handle.write(data)
            handle.flush()
            os.fsync(handle.fileno())
        mask = os.umask(0)
        os.umask(mask)
        os.chmod(handle.name, 0o666 & ~mask)  # tempfile makes 0600; a file is 0666 - umask
        os.replace(handle.name, target)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(handle.name)
        raise
    _fsync_folder(folder)


def _fsync_tree(root: Path) -> None:
    """Flush every file and folder under ``root`` (and ``root``) to the disk."""
    for folder, _, files in os.walk(root):
        for name in files:
            descriptor = os.open(os.path.join(folder, name), os.O_RDONLY)
            try:
                os.fsync(descriptor)
            finally:
                os.close(descriptor)
        _fsync_folder(Path(folder))


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
    _durable_write(out / "data" / f"part-{chunk:06d}.parquet", rows)


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
        group.attrs.update(
            {"sample_step": spec.sample_step, "first_problem": int(ids[0]) if ids.size else 0}
        )
        group.create_array("problem", data=ids)
        group.create_array("length", data=lengths)
        rows = max(1, min(values.shape[0], 256))
        # NaN fill: a piece of the store lost later reads as NaN, which read_samples
        # refuses, never as zeros that look like samples.
        group.create_array("values", data=values, chunks=(rows, *values.shape[1:]),
                           fill_value=np.nan)  # fmt: skip
        _fsync_tree(staging)
        if target.exists():  # an earlier run died between the samples and the rows
            shutil.rmtree(target)
        os.replace(staging, target)
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise
    _fsync_folder(folder)


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
    """Times (s) and sampled values ``(T, width)`` of one problem, by its number.

    Parameters
    ----------
    out : path
        The sweep's output folder (``keep = "samples"``).
    problem : int
        The problem's number, from 0.

    Returns
    -------
    times, values : ndarray
        ``times`` of shape ``(T,)`` (s) from 0 every sample step; ``values`` ``(T, width)``.

    Raises
    ------
    SweepError
        No sweep in ``out``, a problem outside it, no samples of its chunk, or a
        chunk's store that is damaged or does not hold the problem (the message
        names the store and how to redo the chunk).
    """
    zarr = require("zarr")
    folder = Path(out)
    try:
        meta = json.loads((folder / "sweep.json").read_text(encoding="utf-8"))
        problems, per_chunk = int(meta["problems"]), int(meta["chunk"])
    except (OSError, ValueError, TypeError, KeyError):
        raise SweepError(f"{out} holds no sweep (no readable sweep.json)") from None
    if (isinstance(problem, bool) or not isinstance(problem, (int, np.integer))
            or not 0 <= int(problem) < problems):  # fmt: skip
        raise SweepError(f"problem must be a whole number from 0 to {problems - 1}, "
                         f"got {problem!r}")  # fmt: skip
    chunk = int(problem) // per_chunk
    path = folder / "samples" / f"chunk-{chunk:06d}.zarr"
    if not path.exists():
        raise SweepError(f"no samples for problem {problem} (keep = \"samples\"? chunk {chunk} "
                         "not done?)")  # fmt: skip
    try:
        return _read_problem(zarr, path, int(problem))
    except Exception as exc:  # whatever a damaged store makes zarr, numpy or json raise
        reason = str(exc) if isinstance(exc, _Damaged) else f"{type(exc).__name__}: {exc}"
        part = folder / "data" / f"part-{chunk:06d}.parquet"
        raise SweepError(
            f"the samples of chunk {chunk} in {path} are damaged ({reason}); delete {part} "
            "and run the sweep again to redo the chunk"
        ) from None


class _Damaged(Exception):
    """A chunk's samples store breaks the layout :func:`_write_samples` makes."""


def _read_problem(zarr: Any, path: Path, problem: int) -> tuple[np.ndarray, np.ndarray]:
    group = zarr.open_group(str(path), mode="r")
    # Stores written before the step had its own name call it "period".
    period = float(group.attrs.get("sample_step", group.attrs.get("period", np.nan)))
    first = int(group.attrs["first_problem"])
    ids, lengths, values = group["problem"], group["length"], group["values"]
    if not (np.isfinite(period) and period > 0):
        raise _Damaged(f"period {period!r}")
    if ids.ndim != 1 or lengths.shape != ids.shape or values.ndim != 3 or (
            values.shape[0] != ids.shape[0]):  # fmt: skip
        raise _Damaged(f"arrays of shapes {ids.shape}, {lengths.shape}, {values.shape}")
    row = problem - first
    if not 0 <= row < ids.shape[0] or int(ids[row]) != problem:
        raise _Damaged(f"problem {problem} is not where it belongs (row {row})")
    length = int(lengths[row])
    if not 0 <= length <= values.shape[1]:
        raise _Damaged(f"problem {problem} has {length} samples of at most {values.shape[1]}")
    found = np.asarray(values[row, :length], dtype=float)
    if not np.isfinite(found).all():  # a lost piece of the store reads as its fill, NaN
        raise _Damaged(f"problem {problem} has samples that are not numbers")
    return np.arange(length) * period, found
