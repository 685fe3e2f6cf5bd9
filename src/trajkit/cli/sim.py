"""The ``--sim`` options shared by ``trajkit plan`` and ``trajkit mobile``.

``--sim kinematic`` (the default) takes the plan as the motion: ideal tracking.
``--sim mujoco`` runs it on a simulated robot in MuJoCo and reports the
tracking errors; ``--sim-plot``, ``--sim-csv`` and ``--frames`` write what it did.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

import numpy as np

from trajkit.errors import InvalidInputError
from trajkit.io.atomic import StagedFiles
from trajkit.kinematics import BUILTIN
from trajkit.trajectory import Trajectory

__all__ = [
    "add_sim_options",
    "check_sim_options",
    "render_or_note",
    "simulate_arm",
    "write_frames",
]

ARM_CONTROLLERS = ("position", "velocity", "pd_feedforward", "computed_torque")
FRAME_COUNT = 4


def add_sim_options(parser: argparse.ArgumentParser, *, arm: bool) -> None:
    """Add ``--sim``, ``--control-rate-hz``, ``--frames`` (and the arm's own options)."""
    parser.add_argument(
        "--sim",
        choices=["kinematic", "mujoco"],
        default="kinematic",
        help="kinematic: the plan is the motion (ideal tracking); mujoco: run "
        "it on a simulated robot (needs the sim extra)",
    )
    parser.add_argument(
        "--control-rate-hz",
        type=float,
        help="--sim mujoco: command rate (default 1000 Hz for arms, 50 Hz for bases)",
    )
    parser.add_argument(
        "--frames",
        type=Path,
        metavar="DIR",
        help=f"--sim mujoco: render {FRAME_COUNT} frames to DIR/frame_*.png "
        "(needs an OpenGL backend such as EGL)",
    )
    if arm:
        parser.add_argument(
            "--robot",
            choices=sorted(BUILTIN),
            default="rrbot",
            help="--sim mujoco: the simulated arm (default rrbot)",
        )
        parser.add_argument(
            "--controller",
            choices=ARM_CONTROLLERS,
            default="position",
            help="--sim mujoco: how the joints are driven",
        )
        parser.add_argument(
            "--sim-plot",
            type=Path,
            help="--sim mujoco: desired against actual (.png, .svg or .pdf)",
        )
        parser.add_argument("--sim-csv", type=Path, help="--sim mujoco: the simulation log")


def check_sim_options(args: argparse.Namespace) -> None:
    """Refuse simulation outputs without ``--sim mujoco``, before any work is done.

    Also a ``--frames`` that names a file: the frames go into a folder.
    """
    folder = getattr(args, "frames", None)
    if folder is not None and Path(folder).exists() and not Path(folder).is_dir():
        raise InvalidInputError(f"--frames {folder} is a file, not a folder")
    if args.sim == "mujoco":
        return
    given = [
        flag
        for flag, value in (
            ("--control-rate-hz", args.control_rate_hz),
            ("--frames", args.frames),
            ("--sim-plot", getattr(args, "sim_plot", None)),
            ("--sim-csv", getattr(args, "sim_csv", None)),
        )
        if value is not None
    ]
    if given:
        raise InvalidInputError(f"{', '.join(given)} need(s) --sim mujoco")


def simulate_arm(args: argparse.Namespace, trajectory: Trajectory) -> tuple[Any, Any]:
    """Run ``trajectory`` on the chosen arm in MuJoCo; the scene and the log."""
    from trajkit import sim

    robot = BUILTIN[args.robot]()
    if robot.ndof != trajectory.ndof:
        raise InvalidInputError(
            f"--robot {args.robot} has {robot.ndof} joints but the move has {trajectory.ndof}"
        )
    scene = sim.arm_scene(robot)
    log = sim.run(
        scene, trajectory, control_rate_hz=args.control_rate_hz, controller=args.controller
    )
    return scene, log


def render_or_note(scene: Any, log: Any, folder: Path | None) -> list[Any]:
    """Frames for ``--frames``; without an OpenGL backend, a note on stderr and none."""
    if folder is None:
        return []
    from trajkit.sim import SimulationUnavailableError, frames

    try:
        return frames(scene, log, np.linspace(log.t[0], log.t[-1], FRAME_COUNT))
    except SimulationUnavailableError as exc:
        print(f"trajkit: note: no frames rendered: {exc}", file=sys.stderr)
        return []


def write_frames(images: list[Any], folder: Path | None, stage: StagedFiles) -> None:
    """Stage ``images`` as ``folder/frame_0.png`` ... (the folder is made if needed)."""
    if not images or folder is None:
        return
    from trajkit.sim.render import write_png

    # Staged last, after every other output, so a failure before leaves no folder.
    folder.mkdir(parents=True, exist_ok=True)
    for index, image in enumerate(images):
        write_png(image, stage.path(folder / f"frame_{index}.png"))
