"""``trajkit demo``: the coursework's worked examples, computed exactly, with outputs.

Each example is one function that plans, checks, and writes its plots and CSVs;
the demo runs them all and writes every file or none.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np

import trajkit as tk
from trajkit.io.atomic import StagedFiles, staged_files

__all__ = ["EXAMPLES", "run"]

Log = Callable[[str], None]


def _ascending(trajectory: tk.Trajectory, piece: int, joint: int = 0) -> str:
    coefficients = trajectory.absolute_coefficients()[::-1, piece, joint]
    # Rounding noise of the solve (~1e-17) would print as a spurious tiny number.
    coefficients[np.abs(coefficients) < 1e-12 * np.abs(coefficients).max()] = 0.0
    return "[" + ", ".join(f"{c:.6g}" for c in coefficients + 0.0) + "]"


def seed004_via_point_polynomials(out: Path, stage: StagedFiles, log: Log) -> None:
    """Lecture notes (seed 004): two cubics through a via point, solved as A a = b."""
    example1 = tk.polynomial(
        [
            [(0, 0, 0.0), (0, 1, 0.0), (1, 0, 0.5), (1, 1, 0.2)],
            [(1, 0, 0.5), (1, 1, 0.2), (3, 0, 1.0), (3, 1, 0.0)],
        ],
        segments=[0, 1, 3],
    )
    example2 = tk.polynomial(
        [
            [(0, 0, 0.0), (0, 1, 0.0), (1, 0, 0.5)],
            [(1, 0, 0.5), (3, 0, 1.0), (3, 1, 0.0)],
        ],
        segments=[0, 1, 3],
        continuity=[(1, 2)],
    )
    for name, trajectory, rule in (
        ("example1", example1, "velocity 0.2 rad/s at t = 1 s"),
        ("example2", example2, "continuous velocity and acceleration at t = 1 s"),
    ):
        log(f"seed 004 {name} ({rule}): coefficients a0..a3 in absolute time")
        for piece in range(2):
            log(f"  piece {piece + 1}: {_ascending(trajectory, piece)}")
        figure = tk.plot.profiles(trajectory, title=f"Seed 004 {name}: {rule}")
        tk.plot.save(figure, stage.path(out / f"seed004_{name}.png"))
        trajectory.sample(0.01).to_csv(stage.path(out / f"seed004_{name}.csv"))


def seed000_two_joint_cubic(out: Path, stage: StagedFiles, log: Log) -> None:
    """Seed 000 §3.1: RRBot joints 0 -> 67° and 0 -> -45°, cubic, vmax 9 and 11 °/s."""
    q0 = np.radians([0.0, 0.0])
    qf = np.radians([round(5351 / 80), -round(5351 / 120)])
    vmax = np.radians([9.0, 11.0])
    limits = tk.Limits(velocity=vmax)
    trajectory = tk.cubic(q0, qf, vmax=vmax)
    own = trajectory.info["minimum_durations"]
    log(
        f"seed 000 cubic: exact common minimum duration {trajectory.duration:.12g} s "
        f"(joint 1 alone {own[0]:.12g} s, joint 2 alone {own[1]:.12g} s)"
    )
    log("  " + str(trajectory.check(limits)).replace("\n", "\n  "))
    for guess in (11.0, 6.0):
        report = tk.cubic(q0, qf, guess).check(limits)
        worst = ", ".join(
            f"joint {v.joint + 1} peaks at {np.degrees(abs(v.value)):.4g} °/s > "
            f"{np.degrees(abs(v.bound)):.4g} °/s"
            for v in report.violations
        )
        log(f"  the hand solution's {guess:g} s breaks the velocity limit: {worst}")
    figure = tk.plot.profiles(
        trajectory,
        limits,
        degrees=True,
        names=["joint 1", "joint 2"],
        title=f"Seed 000: cubic, minimum duration {trajectory.duration:.4f} s",
    )
    tk.plot.save(figure, stage.path(out / "seed000_cubic.png"))
    trajectory.sample(0.002).to_csv(stage.path(out / "seed000_cubic.csv"))


def seed003_task_space_line(out: Path, stage: StagedFiles, log: Log) -> None:
    """Seed 003: cubic straight line from P_A to P_B in 10 s (the seed's cm, as metres)."""
    p_a = np.array([0.0, -12.0, 20.0]) / 100.0
    p_b = np.array([10.0, 12.0, 20.0]) / 100.0
    trajectory = tk.cubic(p_a, p_b, 10.0)
    speed = np.linalg.norm(trajectory.velocity(5.0))
    log(
        f"seed 003 task-space line: {np.linalg.norm(p_b - p_a):.6g} m in 10 s, "
        f"peak speed {speed:.6g} m/s at t = 5 s"
    )
    figure = tk.plot.profiles(
        trajectory, unit="m", names=["x", "y", "z"], title="Seed 003: cubic line P_A -> P_B"
    )
    tk.plot.save(figure, stage.path(out / "seed003_line.png"))
    trajectory.sample(0.01, unit="m").to_csv(stage.path(out / "seed003_line.csv"))


EXAMPLES: tuple[Callable[[Path, StagedFiles, Log], None], ...] = (
    seed004_via_point_polynomials,
    seed000_two_joint_cubic,
    seed003_task_space_line,
)


def run(out: str | Path, log: Log = print) -> list[Path]:
    """Run every example, writing into ``out`` (created if needed); return the files.

    Either every file is written or, if an example fails, none is.
    """
    folder = Path(out)
    folder.mkdir(parents=True, exist_ok=True)
    lines: list[str] = []

    def record(line: str) -> None:
        lines.append(line)
        log(line)

    with staged_files() as stage:
        for example in EXAMPLES:
            example(folder, stage, record)
        summary = stage.path(folder / "summary.txt")
        summary.write_text("\n".join(lines) + "\n", encoding="utf-8")
    for path in stage.targets:
        log(f"wrote {path}")
    return stage.targets
