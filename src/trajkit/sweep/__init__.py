"""Sweeps: the same planning on millions of problems, as a Parquet dataset.

A sweep file (TOML, :mod:`trajkit.sweep.spec`) names a planner, a robot, fixed
parameters and swept ones (grids, value lists, random distributions with a seed).
:func:`run` plans it chunk by chunk, locally in a process pool or as Ray tasks
(:mod:`trajkit.sweep.engines`), and writes one Parquet file per chunk, plus the
sampled trajectories in Zarr if asked (:mod:`trajkit.sweep.store`). A failed
problem is a row with its error; a rerun resumes, skipping finished chunks.

Needs the extra ``scale``: ``pip install "trajkit[scale]"`` (pyarrow, zarr, ray).

Examples
--------
>>> from trajkit import sweep
>>> spec = sweep.parse({"sweep": {"planner": "trapezoid", "problems": 100, "chunk": 50},
...                     "fixed": {"vmax": 1.0, "amax": 2.0},
...                     "swept": {"q0": {"uniform": [-1, 1]}, "qf": {"uniform": [-1, 1]}}})
>>> spec.chunks
2
"""

from trajkit.sweep.engines import ENGINES, Summary, plan_chunk, progress_bar, run
from trajkit.sweep.planners import PLANNERS
from trajkit.sweep.spec import Distribution, SweepError, SweepSpec, load, parse
from trajkit.sweep.store import ScaleUnavailableError, read, read_samples

__all__ = [
    "ENGINES",
    "PLANNERS",
    "Distribution",
    "ScaleUnavailableError",
    "Summary",
    "SweepError",
    "SweepSpec",
    "load",
    "parse",
    "plan_chunk",
    "progress_bar",
    "read",
    "read_samples",
    "run",
]
