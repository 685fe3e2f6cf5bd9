"""Running a sweep's chunks: in a local process pool, or as Ray tasks.

A chunk is planned by :func:`plan_chunk` wherever the engine puts it, and its
result comes back to this process, which writes it (:mod:`trajkit.sweep.store`).
So the workers need no shared file system (a Ray cluster's nodes do not have
one in general), a chunk's file has a single writer, and the rows are the same
bit for bit whichever engine planned them: they depend only on the sweep file
and the chunk's number.
"""

from __future__ import annotations

import contextlib
import ctypes
import logging
import os
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterator
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from trajkit.errors import InvalidInputError
from trajkit.progress import ProgressBar
from trajkit.sweep.spec import SweepError, SweepSpec
from trajkit.sweep.store import (
    done_chunks,
    encode_chunk,
    lock,
    prepare,
    remove_temporaries,
    require,
    write_chunk,
)

__all__ = ["ENGINES", "Summary", "SweepProgress", "plan_chunk", "progress_bar", "run"]


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
    step = spec.sample_step if spec.keep == "samples" else None
    # Extreme inputs (1e308, 1e-300) overflow on the way; the rows say so (NaN or inf
    # peaks are infeasible), so numpy's warnings would only bury the one-line output.
    with np.errstate(all="ignore"):
        result = spec.plan.run(spec.robot, spec.options, inputs, step)
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


#: How often a worker without ``prctl`` looks whether the sweep's process is alive (s).
_WATCH_PERIOD = 0.5


def _join_the_sweep(sweep_pid: int) -> None:
    """Pool worker initializer: die with the sweep's process, leave Ctrl-C to it.

    A worker killed with its parent (SIGKILL of ``trajkit sweep``) would otherwise
    live on until its chunk is planned and then wait forever for the next one,
    holding the parent's stdout open (a ``| tee`` never ends). Workers write
    nothing, so killing them loses nothing but the chunk in progress. On Linux the
    kernel sends SIGKILL when the parent dies (``PR_SET_PDEATHSIG``); elsewhere a
    thread looks every :data:`_WATCH_PERIOD` s.

    Ctrl-C reaches every process of the terminal's group: the sweep's process
    handles it (keeping the finished chunks), so an idle worker must not die of it
    with a traceback of its own.
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    parent = os.getppid()  # the sweep's process, or a fork server started by it
    if sys.platform.startswith("linux") and parent == sweep_pid:
        with contextlib.suppress(OSError, AttributeError):
            libc = ctypes.CDLL(None, use_errno=True)
            if libc.prctl(1, signal.SIGKILL, 0, 0, 0) == 0:  # 1: PR_SET_PDEATHSIG
                if os.getppid() != parent:  # it died before the request took effect
                    os._exit(1)
                return
    if sys.platform == "win32":  # os.kill(pid, 0) would end the process there
        return
    threading.Thread(target=_watch_the_sweep, args=(parent, sweep_pid), daemon=True,
                     name="trajkit-sweep-watch").start()  # fmt: skip


def _watch_the_sweep(parent: int, sweep_pid: int) -> None:
    """End this worker once its parent is gone (re-parented) or the sweep has died."""
    while True:
        if os.getppid() != parent:
            os._exit(1)
        if sweep_pid != parent:
            try:
                os.kill(sweep_pid, 0)
            except ProcessLookupError:
                os._exit(1)
            except OSError:  # alive, but not ours to signal
                pass
        time.sleep(_WATCH_PERIOD)


def _local(spec: SweepSpec, todo: list[int], workers: int, address: str | None
           ) -> Iterator[Outcome]:  # fmt: skip
    if workers == 1:
        for chunk in todo:
            yield plan_chunk(spec, chunk)
        return
    pool = ProcessPoolExecutor(max_workers=workers, initializer=_join_the_sweep,
                               initargs=(os.getpid(),))  # fmt: skip
    finished_normally = False
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
        finished_normally = True
    finally:
        if not finished_normally:
            # Interrupted or failed: the chunks in progress will not be written, so
            # waiting for them (minutes, for a large chunk) would only delay the exit.
            # (The pool has no public way to stop running calls: its processes.)
            for process in dict(getattr(pool, "_processes", None) or {}).values():
                with contextlib.suppress(Exception):
                    process.terminate()
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

    A chunk counts as done when its file reads back whole; the temporaries of a run
    killed in that folder are removed first.

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
        ``out`` holds a different sweep, or another run is writing there, or is a file.
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
    if folder.exists() and not folder.is_dir():  # mkdir would say only "File exists"
        raise SweepError(f"{folder} is a file, not a folder: a sweep writes into a folder")
    folder.mkdir(parents=True, exist_ok=True)
    with lock(folder):  # before the record: two runs at once could both write one
        prepare(spec, folder)
        remove_temporaries(folder)  # of a run killed while writing
        finished = done_chunks(folder, spec)
        todo = [k for k in range(spec.chunks) if k not in finished]
        start = time.perf_counter()
        problems = failed = infeasible = 0
        done = len(finished)
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


class SweepProgress:
    """A sweep's progress, as :func:`run`'s ``progress``: chunks, problems, problems per second.

    Drawn by the one :class:`trajkit.progress.ProgressBar` (redrawn on a terminal,
    about twenty lines elsewhere); :meth:`close` ends a line left open.
    """

    def __init__(self, stream: Any = None) -> None:
        self.stream = sys.stderr if stream is None else stream
        self._bar: ProgressBar | None = None

    def __call__(self, done: int, total: int, problems: int, seconds: float) -> None:
        """Show ``done`` of ``total`` chunks and ``problems`` planned in ``seconds``."""
        if self._bar is None:
            self._bar = ProgressBar(total, stream=self.stream)
        rate = problems / seconds if seconds > 0 else 0.0
        self._bar(done, f"{done}/{total} chunks, {problems:,} problems, {rate:,.0f} problems/s")

    def close(self) -> None:
        """End the bar's line if it is still open (an interrupted or failed run)."""
        if self._bar is not None:
            self._bar.close()


def progress_bar(stream: Any = None) -> SweepProgress:
    """A one-line progress bar on ``stream`` (default stderr), redrawn on a terminal."""
    return SweepProgress(stream)
