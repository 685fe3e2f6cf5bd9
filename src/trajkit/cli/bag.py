"""``trajkit bag``: read a ROS 2 bag back, check it against limits, plot it against its plan."""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from trajkit.cli.sim import (
    add_sim_options,
    check_sim_options,
    render_or_note,
    simulate_arm,
    write_frames,
)
from trajkit.io.atomic import staged_files

__all__ = ["add_bag_command", "run_bag"]

#: Exit status when the recorded run or its trajectory breaks a limit (as ``run``).
EXIT_LIMITS = 1


def add_bag_command(commands: argparse._SubParsersAction, numbers: object) -> None:
    """Register ``trajkit bag``; ``numbers`` parses a list flag ("1,2" or "1 2")."""
    bag = commands.add_parser(
        "bag", help="read a ROS 2 bag: its topics, a check against limits, a plot",
        description="List a ROS 2 bag's topics and read its joint trajectory (as a joint "
        "trajectory controller interpolates its points) and joint states. With limits, "
        "check both: the trajectory exactly, the recorded states at their samples. "
        "Needs pip install \"trajkit[ros]\".",
    )  # fmt: skip
    bag.add_argument("bag", type=Path, help="the bag folder (with its metadata.yaml)")
    bag.add_argument("--trajectory", help="the JointTrajectory topic (default "
                     "/joint_trajectory, else the bag's one such topic)")  # fmt: skip
    bag.add_argument("--states", default="/joint_states",
                     help="the JointState topic (default /joint_states)")  # fmt: skip
    for flag, meaning in (("--vmax", "velocity bound (rad/s, or deg/s with --deg)"),
                          ("--amax", "acceleration bound of the trajectory (rad/s²)"),
                          ("--effort", "effort bound of the states (N·m)")):  # fmt: skip
        bag.add_argument(flag, type=numbers, nargs="+", metavar="X",
                         help=f"{meaning}; one number or one per joint")  # fmt: skip
    bag.add_argument("--deg", action="store_true", help="limits and the plot in degrees")
    bag.add_argument("--plot", type=Path, help="write the states against the trajectory "
                     "(.png, .svg or .pdf)")  # fmt: skip
    # --sim mujoco: the points executed as the controller plays them, on a simulated arm.
    add_sim_options(bag, arm=True)


def run_bag(args: argparse.Namespace) -> int:
    """Carry out ``trajkit bag``; errors propagate to the CLI's one-line handler."""
    import trajkit as tk
    from trajkit.errors import InvalidInputError
    from trajkit.io.ros2_read import read_bag

    for flag, path in (("--plot", args.plot), ("--sim-plot", args.sim_plot)):
        if path is not None and path.suffix.lower() not in {".png", ".svg", ".pdf"}:
            raise InvalidInputError(f"{flag} must end in .png, .svg or .pdf, got {path.name!r}")
    check_sim_options(args)
    bag = read_bag(args.bag)
    print(f"{args.bag}: {len(bag.topics)} topic(s)")
    for topic, (kind, count) in sorted(bag.topics.items()):
        print(f"  {topic}: {count} × {kind}")
    from trajkit.cli import _vector  # the flags' lists as `trajkit plan` reads them

    scale = np.pi / 180.0 if args.deg else 1.0

    def angular(values: list[list[float]] | None) -> object:
        flat = _vector(values)
        return None if flat is None else flat * scale

    limits = tk.Limits(velocity=angular(args.vmax), acceleration=angular(args.amax))
    effort = _vector(args.effort)
    plan = states = None
    ok = True
    # Default: /joint_trajectory, else the bag's one JointTrajectory topic.
    found = [t for t, (kind, _) in bag.topics.items() if kind.endswith("/JointTrajectory")]
    topic = args.trajectory
    if topic is None:
        single = len(found) == 1 and "/joint_trajectory" not in bag.topics
        topic = found[0] if single else "/joint_trajectory"
    if topic in bag.topics:
        plan = bag.joint_trajectory(topic)
        print(f"{topic}: {plan.breakpoints.size} points over {plan.duration:.6g} s, "
              f"{plan.info['interpolation']} interpolation")  # fmt: skip
        if args.vmax is not None or args.amax is not None:
            report = plan.check(limits)
            ok = ok and report.ok
            print(f"  trajectory limit check: {'OK' if report.ok else 'FAILED'}")
            for violation in report.violations:
                print(f"    {violation}")
    if args.states in bag.topics:
        states = bag.joint_states(args.states)
        print(f"{args.states}: {states.t.size} states of {len(states.names)} joint(s) over "
              f"{states.t[-1] - states.t[0]:.6g} s")  # fmt: skip
        if plan is not None and states.position is not None:
            inside = np.clip(states.t, plan.start_time, plan.end_time)
            error = np.abs(states.position - plan.evaluate(inside)).max(axis=0)
            unit = "deg" if args.deg else "rad"
            print("  largest |q − q_plan|: " + ", ".join(
                f"{name} {value / scale:.3g} {unit}" for name, value in zip(
                    states.names, error, strict=True)))  # fmt: skip
        if args.vmax is not None or effort is not None:
            report = states.check(limits, effort=effort)
            ok = ok and report.ok
            print(f"  recorded limit check (samples): {'OK' if report.ok else 'FAILED'}")
            for violation in report.violations:
                print(f"    {violation}")
    if plan is None and states is None:
        raise InvalidInputError(
            f"the bag has neither {topic} nor {args.states}: name the topics with "
            "--trajectory and --states"
        )
    if args.plot is not None and states is None:
        raise InvalidInputError(f"--plot draws the joint states: the bag has no {args.states}")
    scene = log = None
    if args.sim == "mujoco":
        if plan is None:
            raise InvalidInputError("--sim mujoco runs the bag's joint trajectory: the bag has "
                                    f"no {topic}")  # fmt: skip
        scene, log = simulate_arm(args, plan)
        print(f"executed on {scene.robot.name} in MuJoCo as the controller interpolates the "
              f"points, {log.summary()}")  # fmt: skip
    images = render_or_note(scene, log, args.frames)
    with staged_files() as stage:
        if args.plot is not None:
            figure = tk.plot.recorded(states, plan, degrees=args.deg,
                                      limits=limits if args.vmax is not None else None,
                                      title=str(args.bag.name))  # fmt: skip
            tk.plot.save(figure, stage.path(args.plot))
        if log is not None and args.sim_csv is not None:
            log.to_csv(stage.path(args.sim_csv))
        if log is not None and args.sim_plot is not None:
            title = f"{args.bag.name} on {scene.robot.name}, {log.controller}"
            tk.plot.save(tk.plot.tracking(log, degrees=args.deg, title=title),
                         stage.path(args.sim_plot))  # fmt: skip
        write_frames(images, args.frames, stage)
    for path in stage.targets:
        print(f"wrote {path}")
    return 0 if ok else EXIT_LIMITS
