"""Animation frames: trajkit's renderer beside Matplotlib's FuncAnimation, same figures.

Run: python bench/bench_animate.py [--repeats 5]

Matplotlib's usual way to write an animation (``FuncAnimation.save`` with its
``PillowWriter``, as trajkit did before) draws the whole figure for every frame,
twice (once to update, once to grab it) and lays it out again each time. trajkit
draws the figure once and then only the moving artists of each frame (blitting),
and quantizes the GIF frames with Pillow's fast octree. Both write the same GIF of
a UR5 move (3-D and a 2-D view) and of a base's figure eight; the table gives the
median milliseconds per frame and the ratio.
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

import numpy as np

import trajkit as tk
from timing import median_seconds
from trajkit import mobile
from trajkit.kinematics import UR5
from trajkit.viz import animate


def matplotlib_save(figure, draw, count, path, fps, progress, moving):
    """The previous writer: FuncAnimation.save with PillowWriter, no blitting."""
    from matplotlib import animation
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(figure).draw()  # the 3-D view's projection, which the frames use
    movie = animation.FuncAnimation(figure, draw, frames=count, blit=False, repeat=False)
    movie.save(path, writer=animation.PillowWriter(fps=fps))
    return path


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    plan = tk.cubic(np.zeros(6), np.ones(6), duration=4.0)
    eight = mobile.flat_trajectory(mobile.FigureEight(2.0, 1.0, 20.0), model=mobile.jackal())
    cases = {
        "UR5, 3-D": (lambda path: animate.arm(UR5(), plan, path, fps=10, progress=False), 41),
        "UR5, xz": (
            lambda path: animate.arm(UR5(), plan, path, fps=10, view="xz", progress=False),
            41,
        ),
        "figure eight": (lambda path: animate.mobile(eight, path, fps=5, progress=False), 101),
    }
    ours_save = animate._save
    print(f"{'animation':>14} {'frames':>7} {'trajkit [ms/frame]':>19} "
          f"{'matplotlib [ms/frame]':>22} {'speed-up':>9}")  # fmt: skip
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "bench.gif"
        for name, (render, frames) in cases.items():
            timings = []
            for save in (ours_save, matplotlib_save):
                animate._save = save
                try:
                    seconds = median_seconds(lambda render=render: render(path), args.repeats)
                    timings.append(seconds / frames)
                finally:
                    animate._save = ours_save
            print(f"{name:>14} {frames:>7} {timings[0] * 1e3:>19.1f} {timings[1] * 1e3:>22.1f} "
                  f"{timings[1] / timings[0]:>8.1f}x")  # fmt: skip


if __name__ == "__main__":
    main()
