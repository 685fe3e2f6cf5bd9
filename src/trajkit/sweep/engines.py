"""Running a sweep's chunks: in a local process pool, or as Ray tasks.

A chunk is planned by :func:`plan_chunk` wherever the engine puts it, and its
result comes back to this process, which writes it (:mod:`trajkit.sweep.store`).
So the workers need no shared file system (a Ray cluster's nodes do not have
one in general), a chunk's file has a single writer, and the rows are the same
bit for bit whichever engine planned them: they depend only on the sweep file
and the chunk's number.
"""

from __future__ import annotations

import logging
import os
import sys
import time
from collections.abc import Callable, Iterator
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from trajkit.errors import InvalidInputError
from trajkit.sweep.spec import SweepSpec
from trajkit.sweep.store import done_chunks, encode_chunk, prepare, require, write_chunk

__all__ = ["ENGINES", "Summary", "plan_chunk", "run"]


@dataclass(frozen=True)
class Outcome:
    """A planned chunk, ready to write: its rows as Parquet bytes, samples, counts."""

    chunk: int
    ids: np.ndarray
    rows: bytes
    samples: tuple[np.ndarray, np.ndarray] | None
    failed: int
    infeasible: int


def plan_chunk(spec: SweepSpec, chunk: int) -> Outcome:
    """Plan every problem of ``chunk`` and encode its rows (runs in a worker)."""
    ids, inputs = spec.inputs(chunk)
    period = spec.period if spec.keep == "samples" else None
    result = spec.plan.run(spec.robot, spec.options, inputs, period)
    failed = int(sum(1 for error in result.columns["error"] if error))
    infeasible = int((~result.columns["feasible"]).sum())
    rows = encode_chunk(spec, chunk, ids, inputs, result)
    return Outcome(chunk, ids, rows, result.samples, failed, infeasible)


@dataclass(frozen=True)
class Summary:
    """What a run did: chunks planned now and found done, problems, failures, time."""

    planned_chunks: int
    skipped_chunks: int
    problems: int
    failed: int
    infeasible: int
    seconds: float

    @property
    def rate(self) -> float:
        """Problems planned per second in this run."""
        return self.problems / self.seconds if self.seconds > 0 else float("nan")


def _local(spec: SweepSpec, todo: list[int], workers: int, address: str | None
           ) -> Iterator[Outcome]:  # fmt: skip
    if workers == 1:
        for chunk in todo:
            yield plan_chunk(spec, chunk)
        return
    pool = ProcessPoolExecutor(max_workers=workers)
    try:
        queue = iter(todo)
        running: set[Future] = set()
        for chunk in queue:  # a few chunks ahead of the workers, not all of them
            running.add(pool.submit(plan_chunk, spec, chunk))
            if len(running) >= 2 * workers:
                break
        while running:
            finished, running = wait(running, return_when=FIRST_COMPLETED)
            for future in finished:
                yield future.result()
                following = next(queue, None)
                if following is not None:
                    running.add(pool.submit(plan_chunk, spec, following))
    finally:
        pool.shutdown(wait=True, cancel_futures=True)


def _ray(spec: SweepSpec, todo: list[int], workers: int, address: str | None
         ) -> Iterator[Outcome]:  # fmt: skip
    ray = require("ray")
    started = False
    if not ray.is_initialized():
        # Ray's own notices would break the command line's one-line-on-stderr rule.
        options: dict[str, Any] = {"include_dashboard": False, "log_to_driver": False,
                                   "logging_level": logging.ERROR}  # fmt: skip
        if address is None:
            options["num_cpus"] = workers
        else:
            options["address"] = address
        ray.init(**options)
        started = True
    try:
        task = ray.remote(plan_chunk)
        shared = ray.put(spec)
        # Keep every CPU of the cluster busy, with a chunk queued behind each.
        window = 2 * max(workers, int(ray.cluster_resources().get("CPU", workers)))
        queue = iter(todo)
        running = {}
        for chunk in queue:
            running[task.remote(shared, chunk)] = chunk
            if len(running) >= window:
                break
        while running:
            finished, _ = ray.wait(list(running), num_returns=1)
            for reference in finished:
                del running[reference]
                yield ray.get(reference)
                following = next(queue, None)
                if following is not None:
                    running[task.remote(shared, following)] = following
    finally:
        if started:
            ray.shutdown()


#: Engines by name: each yields the chunks' outcomes as they finish.
ENGINES: dict[str, Callable[[SweepSpec, list[int], int, str | None], Iterator[Outcome]]] = {
    "local": _local,
    "ray": _ray,
}


def run(
    spec: SweepSpec,
    out: str | Path,
    *,
    engine: str = "local",
    workers: int | None = None,
    address: str | None = None,
    progress: Callable[[int, int, int, float], None] | None = None,
) -> Summary:
    """Plan every chunk of ``spec`` not yet in ``out`` and write it there.

    Parameters
    ----------
    spec : SweepSpec
    out : path
        The output folder; rerunning on it resumes (finished chunks are skipped).
    engine : {"local", "ray"}
        A process pool on this machine, or Ray tasks (a local Ray instance, or the
        cluster at ``address``, e.g. ``"auto"`` or ``"ray://head:10001"``).
    workers : int, optional
        Processes (local) or CPUs for a local Ray instance; default: all cores. On a
        cluster (``address``) Ray uses every CPU it has.
    address : str, optional
        The Ray cluster to join; only with ``engine="ray"``.
    progress : callable, optional
        Called after each chunk with (chunks done, chunks in all, problems planned
        in this run, seconds so far).

    Returns
    -------
    Summary
        Chunks planned now and found done, problems planned now, failed and
        infeasible ones, and the wall time (s).

    Raises
    ------
    InvalidInputError
        An unknown engine, a bad ``workers``, or ``address`` with the local engine.
    SweepError
        ``out`` holds a different sweep.
    ScaleUnavailableError
        pyarrow (or zarr, or ray) is not installed.
    """
    if engine not in ENGINES:
        raise InvalidInputError(f"engine must be one of {', '.join(ENGINES)}, got {engine!r}")
    count = (os.cpu_count() or 1) if workers is None else workers
    if isinstance(count, bool) or not isinstance(count, int) or count < 1:
        raise InvalidInputError(f"workers must be a whole number >= 1, got {workers!r}")
    if engine == "local" and address is not None:
        raise InvalidInputError("--address is for the ray engine")
    require("pyarrow")
    if spec.keep == "samples":
        require("zarr")
    folder = Path(out)
    prepare(spec, folder)
    finished = done_chunks(folder)
    todo = [k for k in range(spec.chunks) if k not in finished]
    start = time.perf_counter()
    problems = failed = infeasible = 0
    done = len(finished & set(range(spec.chunks)))
    for outcome in ENGINES[engine](spec, todo, count, address):
        write_chunk(spec, folder, outcome.chunk, outcome.rows, outcome.ids, outcome.samples)
        problems += outcome.ids.size
        failed += outcome.failed
        infeasible += outcome.infeasible
        done += 1
        if progress is not None:
            progress(done, spec.chunks, problems, time.perf_counter() - start)
    return Summary(len(todo), spec.chunks - len(todo), problems, failed, infeasible,
                   time.perf_counter() - start)  # fmt: skip


def progress_bar(stream: Any = None) -> Callable[[int, int, int, float], None]:
    """A one-line progress bar on stderr: chunks, problems and problems per second."""
    stream = sys.stderr if stream is None else stream
    live = getattr(stream, "isatty", lambda: False)()
    last = [-1]

    def show(done: int, total: int, problems: int, seconds: float) -> None:
        filled = round(20 * done / max(total, 1))
        rate = problems / seconds if seconds > 0 else 0.0
        line = (f"[{'#' * filled}{'.' * (20 - filled)}] {done}/{total} chunks, "
                f"{problems:,} problems, {rate:,.0f} problems/s")  # fmt: skip
        if live:
            stream.write("\r" + line + ("\n" if done == total else ""))
            stream.flush()
        elif filled != last[0] or done == total:  # about 20 lines, not one per chunk
            stream.write(line + "\n")
            stream.flush()
        last[0] = filled

    return show
