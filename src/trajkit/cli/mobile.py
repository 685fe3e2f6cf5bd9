"""``trajkit mobile``: plan, check, simulate and plot a wheeled robot's motion.

Three commands: ``twist`` (seed 000's ``move_jackal``), ``goto`` (its
rotate–translate–rotate task) and ``figure8`` (seed 002's flat output, tracked
by a controller). Each prints a summary and writes what ``--csv``, ``--plot``
and ``--path-plot`` ask for, all together or not at all. Like ``trajkit run``,
a plan that breaks a limit is still printed and written, and the exit status is
1 (``EXIT_LIMITS_BROKEN``).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from trajkit.cli.sim import add_sim_options, check_sim_options, render_or_note, write_frames
from trajkit.errors import InvalidInputError
from trajkit.io.atomic import staged_files
from trajkit.mobile import (
    DiffDrive,
    MobileLimits,
    MobileTrajectory,
    SimulationLog,
    constant_twist,
    flat_trajectory,
    rotate_translate_rotate,
    simulate,
)
from trajkit.mobile.control import controller_named
from trajkit.mobile.flatness import FigureEight
from trajkit.mobile.models import BASES, Model
from trajkit.mobile.plans import MAX_TRAVEL
from trajkit.samples import DEFAULT_STEP

__all__ = ["add_mobile_commands", "run_mobile"]

CONTROLLERS = ("feedforward", "kanayama", "linearization", "pure-pursuit")
PLOT_SUFFIXES = {".png", ".svg", ".pdf"}


def _outputs(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--robot", choices=sorted(BASES), default="jackal",
                        help="base model and its default limits (default jackal)")  # fmt: skip
    parser.add_argument("--csv", type=Path, help="write the samples (SI units) to this CSV file")
    parser.add_argument("--plot", type=Path, help="velocities, position, heading against time")
    parser.add_argument("--path-plot", type=Path, help="the XY path with the robot drawn")
    parser.add_argument("--sample-step", type=float, default=DEFAULT_STEP,
                        help="the sampling and simulation step in s (default "
                        f"{DEFAULT_STEP:g})")  # fmt: skip
    parser.add_argument("--dt", type=float, help=argparse.SUPPRESS)  # the old name
    add_sim_options(parser, arm=False)


def add_mobile_commands(commands: argparse._SubParsersAction) -> None:
    """Register ``trajkit mobile twist|goto|figure8``."""
    mobile = commands.add_parser(
        "mobile", help="plan and simulate a wheeled robot's motion",
        description="Wheeled robots: a constant twist, a move to a pose, a figure eight. "
        "Every plan is checked against the robot's limits (and those given); a plan that "
        "breaks one is still printed and written, and the exit status is 1.",
    )  # fmt: skip
    kinds = mobile.add_subparsers(dest="mobile_command", metavar="MOTION")
    kinds.required = True

    twist = kinds.add_parser("twist", help="drive one twist for a while (move_jackal)")
    twist.add_argument("rate_hz", type=float, help="command rate (Hz)")
    twist.add_argument("v", type=float, help="forward speed (m/s)")
    twist.add_argument("omega_deg", type=float, help="turn rate (deg/s)")
    twist.add_argument("duration", type=float, help="how long (s)")
    _outputs(twist)

    goto = kinds.add_parser("goto", help="rotate, drive straight, rotate to a pose")
    goto.add_argument("x", type=float, help="goal x (m)")
    goto.add_argument("y", type=float, help="goal y (m)")
    goto.add_argument("theta", type=float, nargs="?", help="final heading (rad), optional")
    goto.add_argument("--start", type=float, nargs=3, metavar=("X", "Y", "THETA"),
                      default=(0.0, 0.0, 0.0), help="start pose (m, m, rad)")  # fmt: skip
    goto.add_argument("--vmax", type=float, help="speed limit (m/s)")
    goto.add_argument("--wmax-deg", type=float, help="turn-rate limit (deg/s)")
    goto.add_argument("--amax", type=float, help="acceleration limit (m/s^2)")
    goto.add_argument("--alpha-max-deg", type=float, help="angular acceleration limit (deg/s^2)")
    goto.add_argument("--jmax", type=float, help="jerk limit (m/s^3), scurve only")
    goto.add_argument("--angular-jmax-deg", type=float, help="angular jerk limit (deg/s^3)")
    goto.add_argument("--profile", choices=["trapezoid", "scurve"], default="trapezoid")
    goto.add_argument(
        "--blend-ratio", type=float, help="the LSPB rule t_b = ratio * t_f per phase (e.g. 0.1)"
    )
    goto.add_argument("--reverse", action="store_true", help="drive backwards to goals behind")
    _outputs(goto)

    eight = kinds.add_parser("figure8", help="follow a figure eight by differential flatness")
    eight.add_argument("--width", type=float, default=2.0, help="W (m), default 2")
    eight.add_argument("--height", type=float, default=1.0, help="H (m), default 1")
    eight.add_argument("--period", type=float, default=20.0, help="T (s), default 20")
    eight.add_argument("--controller", choices=CONTROLLERS, default="feedforward")
    eight.add_argument("--offset", type=float, nargs=3, metavar=("DX", "DY", "DTHETA_DEG"),
                       default=(0.0, 0.0, 0.0),
                       help="start this far from the curve's start (m, m, deg)")  # fmt: skip
    # Without --fit the curve keeps its timing and is checked against the limits: a
    # user who gives --vmax expects it enforced, so breaking it exits 1, never 0.
    eight.add_argument("--vmax", type=float,
                       help="speed limit (m/s); the plan is checked against it (exit 1 when "
                       "broken), and --fit slows the curve down to meet it")  # fmt: skip
    eight.add_argument("--wmax-deg", type=float,
                       help="turn-rate limit (deg/s), checked like --vmax")  # fmt: skip
    eight.add_argument("--fit", action="store_true",
                       help="slow the curve down uniformly until every limit holds")  # fmt: skip
    eight.add_argument(
        "--rate-hz", type=float, help="send held commands at this rate (default: continuous)"
    )
    _outputs(eight)


def _limits(model: Model, args: argparse.Namespace) -> MobileLimits:
    changes = {}
    if getattr(args, "vmax", None) is not None:
        changes["velocity"] = args.vmax
    if getattr(args, "wmax_deg", None) is not None:
        changes["angular_velocity"] = np.radians(args.wmax_deg)
    if getattr(args, "amax", None) is not None:
        changes["acceleration"] = args.amax
    if getattr(args, "alpha_max_deg", None) is not None:
        changes["angular_acceleration"] = np.radians(args.alpha_max_deg)
    return model.limits.replace(**changes)


def _check_suffix(path: Path | None, flag: str) -> None:
    if path is not None and path.suffix.lower() not in PLOT_SUFFIXES:
        raise InvalidInputError(f"{flag} must end in .png, .svg or .pdf, got {path.name!r}")


def _write(
    args: argparse.Namespace,
    plan: MobileTrajectory,
    log: SimulationLog | None,
    title: str,
    images: list,
) -> list[Path]:
    with staged_files() as stage:
        if args.csv is not None:
            if log is None:
                plan.to_csv(stage.path(args.csv), args.sample_step)
            else:
                log.to_csv(stage.path(args.csv))
        if args.plot is not None or args.path_plot is not None:
            from trajkit.viz import plot

            data = plan if log is None else log
            if args.plot is not None:
                plot.save(plot.mobile(data, title=title), stage.path(args.plot))
            if args.path_plot is not None:
                plot.save(plot.mobile_path(data, title=title), stage.path(args.path_plot))
        write_frames(images, args.frames, stage)
    return stage.targets


def run_mobile(args: argparse.Namespace) -> int:
    """Carry out one ``trajkit mobile`` command; returns the exit status."""
    _check_suffix(args.plot, "--plot")
    _check_suffix(args.path_plot, "--path-plot")
    if args.dt is not None:
        raise InvalidInputError("--dt is now named --sample-step (the sampling and simulation "
                                "step)")  # fmt: skip
    if not args.sample_step > 0.0 or not np.isfinite(args.sample_step):
        raise InvalidInputError(f"--sample-step must be a time > 0 s, got {args.sample_step:g}")
    check_sim_options(args)
    model = BASES[args.robot]()
    if args.sim == "mujoco" and not isinstance(model, DiffDrive):
        raise InvalidInputError(f"--sim mujoco needs a robot with wheels, not --robot {args.robot}")
    limits = _limits(model, args)
    log = None
    controller, start, rate = None, None, getattr(args, "rate_hz", None)
    if args.mobile_command == "twist":
        plan = constant_twist(
            args.v, np.radians(args.omega_deg), args.duration, rate_hz=args.rate_hz, model=model
        )
        title = f"twist v = {args.v:g} m/s, ω = {args.omega_deg:g} deg/s, {args.duration:g} s"
    elif args.mobile_command == "goto":
        goal = (args.x, args.y) if args.theta is None else (args.x, args.y, args.theta)
        plan = rotate_translate_rotate(
            goal,
            args.start,
            limits=limits,
            jmax=args.jmax,
            angular_jmax=None if args.angular_jmax_deg is None
            else np.radians(args.angular_jmax_deg),
            profile=args.profile,
            blend_ratio=args.blend_ratio,
            reverse=args.reverse,
            model=model,
        )  # fmt: skip
        title = f"rotate, drive, rotate to {goal}"
    else:
        output = FigureEight(args.width, args.height, args.period)
        plan = flat_trajectory(
            output, model=model, limits=limits, timing="within_limits" if args.fit else "as_given"
        )
        dx, dy, dtheta = args.offset
        with np.errstate(over="ignore"):
            away = float(np.hypot(dx, dy))
        if not (away <= MAX_TRAVEL and np.isfinite(dtheta)):
            raise InvalidInputError(f"--offset must be finite and at most {MAX_TRAVEL:g} m from "
                                    f"the curve's start, got {dx:g} {dy:g} {dtheta:g}")  # fmt: skip
        start = plan.start_pose + np.array([dx, dy, np.radians(dtheta)])
        controller = controller_named(args.controller)
        if args.sim == "kinematic":
            log = simulate(plan, controller, sample_step=args.sample_step, initial_pose=start,
                           command_rate_hz=args.rate_hz)  # fmt: skip
        title = f"figure eight {args.width:g} m x {args.height:g} m, {args.controller}"
    images: list = []
    report = plan.check()
    lines = [plan.describe(report)]
    if not report.ok and args.mobile_command == "figure8" and not args.fit:
        lines.append("  (--fit slows the curve down uniformly until every limit holds)")
    if args.sim == "mujoco":
        from trajkit import sim

        scene = sim.MobileScene(model)
        rate_hz = args.control_rate_hz or rate or sim.DEFAULT_RATES_HZ["mobile"]
        log = sim.run(scene, plan, control_rate_hz=rate_hz, controller=controller,
                      initial_pose=start)  # fmt: skip
        lines.append(f"simulated in MuJoCo at {rate_hz:g} Hz: {log.summary()}")
        images = render_or_note(scene, log, args.frames)
    elif log is not None:
        lines.append(f"tracking ({args.sample_step:g} s steps): {log.summary()}")
    written = _write(args, plan, log, title, images)
    # Printed once everything has been computed and written: a failure prints only its error.
    print("\n".join(lines))
    for path in written:
        print(f"wrote {path}")
    if not report.ok:
        from trajkit.cli import EXIT_LIMITS_BROKEN

        # The same verdict and line as ``trajkit run``: scripts can tell a plan that
        # breaks a limit (written, status 1) from a success and from an error (2).
        print("trajkit: the plan breaks a limit (see the limit check above)", file=sys.stderr)
        return EXIT_LIMITS_BROKEN
    return 0
