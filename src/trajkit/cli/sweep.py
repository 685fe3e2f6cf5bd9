"""``trajkit sweep``: plan a sweep file's problems into a Parquet dataset."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

__all__ = ["add_sweep_command", "run_sweep"]

#: Ctrl-C, as shells report it.
EXIT_INTERRUPTED = 130


def add_sweep_command(commands: argparse._SubParsersAction) -> None:
    """Register ``trajkit sweep``."""
    sweep = commands.add_parser(
        "sweep", help="plan and check many problems from a sweep file into a Parquet dataset",
        description="Plan every problem of a sweep file (TOML), check it, and write one row "
        "per problem to Parquet files in OUT/data, one per chunk. Rerunning the same "
        "command resumes: finished chunks are skipped. Needs pip install \"trajkit[scale]\".",
    )  # fmt: skip
    sweep.add_argument("sweep", type=Path, help="the sweep file (.toml)")
    sweep.add_argument("--out", type=Path, default=Path("trajkit-sweep"),
                       help="output folder (default ./trajkit-sweep)")  # fmt: skip
    sweep.add_argument("--engine", choices=["local", "ray"], default="local",
                       help="local process pool (default) or Ray tasks")  # fmt: skip
    sweep.add_argument("--workers", type=int, help="processes, or CPUs of a local Ray "
                       "instance (default: every core)")  # fmt: skip
    sweep.add_argument("--address", help="Ray cluster to join (e.g. auto, ray://head:10001); "
                       "default: start a local instance")  # fmt: skip
    sweep.add_argument("--quiet", action="store_true", help="no progress bar")


def run_sweep(args: argparse.Namespace) -> int:
    """Carry out ``trajkit sweep``; errors propagate to the CLI's one-line handler."""
    from trajkit import sweep

    spec = sweep.load(args.sweep)
    progress = None if args.quiet else sweep.progress_bar()
    try:
        try:
            summary = sweep.run(spec, args.out, engine=args.engine, workers=args.workers,
                                address=args.address, progress=progress)  # fmt: skip
        finally:
            if progress is not None:  # an error or interruption line must start a line
                progress.close()
    except KeyboardInterrupt:
        print("trajkit: interrupted; the finished chunks are kept: run the same command again "
              "to resume", file=sys.stderr)  # fmt: skip
        return EXIT_INTERRUPTED
    print(
        f"{spec.name}: planned {summary.planned_chunks} chunks ({summary.problems:,} problems) "
        f"in {summary.seconds:.3g} s, {summary.rate:,.0f} problems/s; {summary.failed} failed, "
        f"{summary.infeasible} infeasible; {summary.skipped_chunks} chunks were already done. "
        f"Rows in {args.out / 'data'}"
    )
    return 0
