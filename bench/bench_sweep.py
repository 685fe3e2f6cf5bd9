"""Sweep throughput: 10⁶ six-joint problems, local engine at 1 and 2 workers, and Ray.

Run: python bench/bench_sweep.py [--problems 1000000] [--chunk 20000]

For trapezoid and S-curve sweeps (rest to rest between random configurations):
problems per second of the local engine with 1 and 2 worker processes (their
ratio is the scaling), and of a local Ray instance with 2 CPUs, started before
the clock runs. Ray's overhead per chunk is its extra time over the local engine
with the same workers, divided by the number of chunks: on the big chunks, and on
400 chunks of 50 problems, where a chunk's own work is small. Each figure is the
median of --repeats runs, each into a fresh folder. Requires trajkit[scale].
"""

from __future__ import annotations

import argparse
import logging
import shutil
import tempfile
import time
from pathlib import Path

import numpy as np
import ray

from trajkit import sweep


def spec(planner: str, problems: int, chunk: int) -> sweep.SweepSpec:
    fixed = {"vmax": 2.0, "amax": 4.0} | ({"jmax": 20.0} if planner == "scurve" else {})
    return sweep.parse({
        "sweep": {"planner": planner, "problems": problems, "chunk": chunk, "seed": 1},
        "robot": {"joints": 6},
        "fixed": fixed,
        "swept": {"q0": {"uniform": [-3.1, 3.1]}, "qf": {"uniform": [-3.1, 3.1]}},
    })  # fmt: skip


def seconds(plan: sweep.SweepSpec, engine: str, workers: int, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        folder = Path(tempfile.mkdtemp(prefix="trajkit-bench-sweep-"))
        try:
            start = time.perf_counter()
            sweep.run(plan, folder, engine=engine, workers=workers)
            times.append(time.perf_counter() - start)
        finally:
            shutil.rmtree(folder, ignore_errors=True)
    return float(np.median(times))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--problems", type=int, default=1_000_000)
    parser.add_argument("--chunk", type=int, default=20_000)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    start = time.perf_counter()
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False,
             logging_level=logging.ERROR)  # fmt: skip
    print(f"ray.init: {time.perf_counter() - start:.2f} s (not counted below)")
    print(f"{'planner':>9} {'chunks':>6} {'local 1 [/s]':>13} {'local 2 [/s]':>13} "
          f"{'scaling':>8} {'ray 2 [/s]':>11} {'ray overhead/chunk':>19}")  # fmt: skip
    for planner in ("trapezoid", "scurve"):
        plan = spec(planner, args.problems, args.chunk)
        one = seconds(plan, "local", 1, args.repeats)
        two = seconds(plan, "local", 2, args.repeats)
        on_ray = seconds(plan, "ray", 2, args.repeats)
        overhead = (on_ray - two) / plan.chunks
        print(f"{planner:>9} {plan.chunks:>6} {args.problems / one:>13,.0f} "
              f"{args.problems / two:>13,.0f} {one / two:>7.2f}x {args.problems / on_ray:>11,.0f} "
              f"{1e3 * overhead:>16.1f} ms")  # fmt: skip
    # Per-chunk cost, where it shows: 400 chunks of 50 problems each.
    small = spec("trapezoid", 20_000, 50)
    local, on_ray = (seconds(small, engine, 2, args.repeats) for engine in ("local", "ray"))
    per = 1e3 / small.chunks
    print(f"{small.chunks} chunks of {small.chunk} problems: local {per * local:.2f} ms/chunk, "
          f"ray {per * on_ray:.2f} ms/chunk, ray's overhead {per * (on_ray - local):.2f} "
          "ms/chunk")  # fmt: skip
    ray.shutdown()


if __name__ == "__main__":
    main()
