"""The ``trajkit`` command.

Errors end the program with one line on stderr and exit status 2; output files are
rendered in memory first and then written atomically, so a failed run leaves none.
"""

from __future__ import annotations

import argparse
import contextlib
import errno
import os
import re
import sys
import warnings
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np

import trajkit
from trajkit.cli.bag import add_bag_command, run_bag
from trajkit.cli.mobile import add_mobile_commands, run_mobile
from trajkit.cli.sim import (
    add_sim_options,
    check_sim_options,
    render_or_note,
    simulate_arm,
    write_frames,
)
from trajkit.cli.sweep import add_sweep_command, run_sweep
from trajkit.errors import TrajkitError
from trajkit.io.atomic import staged_files
from trajkit.limits import Limits
from trajkit.planners import CATALOG, OPTIONS, QUANTITIES, Quantity
from trajkit.samples import DEFAULT_STEP
from trajkit.trajectory import Trajectory

__all__ = ["main"]

EXIT_USAGE = 2
EXIT_LIMITS_BROKEN = 1  # trajkit run: the plan was written but breaks a limit
EXIT_INTERRUPTED = 130  # Ctrl-C, as shells report it


class CommandError(Exception):
    """A problem to report on one line with exit status 2."""


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # type: ignore[override]
        raise CommandError(message)


def _numbers(text: str) -> list[float]:
    """Parse ``1,2,3`` or a single number into floats (NaN and inf are refused later)."""
    try:
        return [float(part) for part in text.split(",") if part.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"expected numbers like 0.5 or 1,-2,3, got {text!r}"
        ) from None


def _vector(values: list[list[float]] | None) -> np.ndarray | None:
    """Flatten ``--x 1 2`` / ``--x 1,2`` / ``--x 1 --x 2`` style inputs."""
    if values is None:
        return None
    flat = [v for group in values for v in group]
    return np.array(flat[0] if len(flat) == 1 else flat, dtype=float)


def _listed(names: list[str]) -> str:
    return ", ".join(names[:-1]) + f" and {names[-1]}" if len(names) > 1 else names[0]


def _takers(name: str) -> str:
    """The planners that take ``name``, for a help text ("cubic, quintic" or "all")."""
    users = [entry.name for entry in CATALOG.values() if entry.takes(name)]
    return "all" if len(users) == len(CATALOG) else ", ".join(users)


def _add_quantity(parser: argparse.ArgumentParser, quantity: Quantity) -> None:
    """The flag of a catalog quantity: ``--min-duration 2``, ``--vmax 1,2``."""
    degrees = quantity.unit.replace("rad", "deg")
    unit = f"{quantity.unit}, or {degrees} with --deg" if quantity.angular else quantity.unit
    default = "" if quantity.default is None else f"; default {quantity.default:g}"
    text = f"{_takers(quantity.name)}: {quantity.meaning} ({unit}{default})"
    flag = "--" + quantity.name.replace("_", "-")
    if quantity.per_joint:
        parser.add_argument(flag, type=_numbers, nargs="+", metavar="X", help=text)
    else:
        parser.add_argument(flag, type=float, help=text)


def _build_parser() -> _Parser:
    parser = _Parser(
        prog="trajkit",
        description="Plan, check, plot and export robot trajectories.",
    )
    parser.add_argument("--version", action="version", version=f"trajkit {trajkit.__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)

    plan = commands.add_parser(
        "plan",
        help="plan one joint-space move and print its summary",
        description="Plan a move for one or more joints and print its plan and limit "
        "check. Lists are given as '0 1.5' or '0,1.5'; a single number applies to every "
        "joint. Planners: "
        + "; ".join(f"{entry.name}: {entry.summary}" for entry in CATALOG.values())
        + ".",
    )
    plan.add_argument("profile", choices=list(CATALOG), help="the planner (time law)")
    for quantity in QUANTITIES.values():
        _add_quantity(plan, quantity)
    plan.add_argument("--deg", action="store_true", help="angles and limits in degrees")
    for option in OPTIONS.values():
        plan.add_argument(f"--{option.name}", choices=option.choices,
                          help=f"{_takers(option.name)}: {option.meaning} (default "
                          f"{option.default})")  # fmt: skip
    plan.add_argument(
        "--period",
        type=float,
        help=f"{_takers('period')}: the controller period (s); switching times become "
        "its multiples (see --grid)",
    )
    plan.add_argument("--dt", type=float, help=argparse.SUPPRESS)  # the old name of two flags
    plan.add_argument(
        "--sample-step",
        type=float,
        help=f"--csv: the sampling step (s); default the controller period, or {DEFAULT_STEP:g}",
    )
    plan.add_argument("--csv", type=Path, help="write samples (SI units) to this CSV file")
    plan.add_argument("--plot", type=Path, help="write a profile plot (.png, .svg or .pdf)")
    add_sim_options(plan, arm=True)

    add_mobile_commands(commands)

    scenario = commands.add_parser(
        "run", help="carry out a scenario file (TOML) and write its outputs",
        description="Plan, check, optionally simulate, and write every output a scenario "
        "file asks for.",
    )  # fmt: skip
    scenario.add_argument("scenario", type=Path, help="the scenario file (.toml)")
    scenario.add_argument("--out", type=Path, default=Path("trajkit-out"),
                          help="output folder (default ./trajkit-out)")  # fmt: skip
    scenario.add_argument("--report", action="store_true",
                          help="also write a self-contained index.html of the run")  # fmt: skip

    add_sweep_command(commands)
    add_bag_command(commands, _numbers)

    demo = commands.add_parser("demo", help="run the worked examples and write their outputs")
    demo.add_argument(
        "--out",
        type=Path,
        default=Path("trajkit-demo"),
        help="output folder (default ./trajkit-demo)",
    )
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status.

    Statuses: 0 done; 1 (``run``, ``mobile``) the outputs were written but the plan
    breaks a limit; 2 an error, reported on one line of stderr; 130 interrupted
    (Ctrl-C); 141 standard output was closed early (``trajkit plan ... | head``),
    as a program killed by SIGPIPE reports it, and without a message.
    """
    parser = _build_parser()
    args: argparse.Namespace | None = None
    made: list[Path] = []
    # Warnings (numpy's overflow notes, say) are held back: on an error only the
    # one-line message is printed; on success each distinct warning is shown once.
    with warnings.catch_warnings(record=True) as caught:
        try:
            args = parser.parse_args(argv)
            if args.command is None:
                parser.print_help()
                return EXIT_USAGE
            handlers: dict[str, Callable[[argparse.Namespace], int]] = {
                "plan": _plan,
                "mobile": run_mobile,
                "run": _run_scenario,
                "sweep": run_sweep,
                "bag": run_bag,
                "demo": _demo,
            }
            handler = handlers[args.command]
            made = _missing_output_folders(args)
            status = handler(args)
            sys.stdout.flush()  # a closed pipe shows here, not at exit as a traceback
        except BrokenPipeError:
            _silence_stdout()
            return EXIT_BROKEN_PIPE
        except (CommandError, TrajkitError, OSError) as exc:
            _remove_empty(made)
            message = _message(exc, args)
            print(f"trajkit: error: {message}", file=sys.stderr)
            return EXIT_USAGE
        except KeyboardInterrupt:
            _remove_empty(made)
            # Outputs are staged: an interrupted run leaves none of them.
            print("trajkit: interrupted; nothing was written", file=sys.stderr)
            return EXIT_INTERRUPTED
        except BaseException:
            _remove_empty(made)
            raise
    _show_once(caught)
    return status


EXIT_BROKEN_PIPE = 128 + 13  # 128 + SIGPIPE: what a shell reports for `yes | head -1`

# errno -> the reason in plain words ("[Errno 28] No space left on device" -> these)
_REASONS: dict[int, str] = {
    errno.ENOSPC: "no space left on device",
    errno.EIO: "input/output error (the disk or the network share failed)",
    errno.EACCES: "permission denied",
    errno.EPERM: "permission denied",
    errno.EROFS: "the file system is read-only",
    errno.ENOENT: "no such file or folder",
    errno.EEXIST: "it already exists",
    errno.ENOTDIR: "a part of the path is a file, not a folder",
    errno.EISDIR: "it is a folder",
    errno.ENAMETOOLONG: "the name is too long",
    errno.EFBIG: "the file is too large",
    errno.ELOOP: "too many symbolic links",
}
if hasattr(errno, "EDQUOT"):
    _REASONS[errno.EDQUOT] = "disk quota exceeded"


def _message(exc: BaseException, args: argparse.Namespace | None) -> str:
    """The one-line text of an error, in the user's words and units."""
    if isinstance(exc, OSError):
        message = _os_message(exc, args)
    else:
        message = str(exc)
    message = " ".join(message.split())
    if args is not None and getattr(args, "deg", False) and isinstance(exc, TrajkitError):
        message = _in_degrees(message, args)
    return message


def _os_message(exc: OSError, args: argparse.Namespace | None) -> str:
    """``cannot write FILE: no space left on device``, with no ``[Errno N]``."""
    if exc.errno is None or exc.strerror is None:
        return str(exc)  # trajkit's own message, already in words
    reason = _REASONS.get(exc.errno) or exc.strerror[:1].lower() + exc.strerror[1:]
    if exc.filename is None:
        return reason
    name = os.fsdecode(exc.filename)
    inputs = {
        os.fspath(getattr(args, flag))
        for flag in ("scenario", "sweep")
        if args is not None and isinstance(getattr(args, flag, None), Path)
    }
    verb = "read" if name in inputs else "write"
    return f"cannot {verb} {name}: {reason}"


# A number (or a bracketed list of them) followed by an angular SI unit.
_NUMBER = r"[-+]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?|[-+]?inf|nan"
_ANGULAR = re.compile(
    rf"(?P<value>\[[^\]]*\]|{_NUMBER})(?P<space>\s*)(?P<unit>rad(?:/s(?:\^[23]|²|³)?)?)"
    r"(?![A-Za-z])"
)
_ANGLE_FLAGS = ("q0", "qf", "v0", "vf", "a0", "af", "vmax", "amax", "jmax")


def _in_degrees(message: str, args: argparse.Namespace) -> str:
    """Quote a message's radian quantities in degrees, as the user gave them with ``--deg``.

    A converted value that matches, to the 6 digits messages carry, a number the
    user typed is written exactly as typed (10 rather than 9.99999).
    """
    typed = [
        value
        for flag in _ANGLE_FLAGS
        for group in getattr(args, flag, None) or []
        for value in group
    ]

    def degrees(text: str) -> str:
        value = float(text) * 180.0 / np.pi
        if not np.isfinite(value):
            return text
        for number in typed:
            if abs(number - value) <= 1e-5 * abs(number):
                return f"{number:.15g}"
        return f"{value:.6g}"

    def convert(match: re.Match[str]) -> str:
        value = match.group("value")
        if value.startswith("["):
            value = re.sub(_NUMBER, lambda m: degrees(m.group(0)), value)
        else:
            value = degrees(value)
        return value + match.group("space") + "deg" + match.group("unit")[3:]

    return _ANGULAR.sub(convert, message)


def _missing_output_folders(args: argparse.Namespace) -> list[Path]:
    """The output folders of this command that do not exist yet, deepest first.

    Those the command creates are removed again if it fails before writing into them.
    """
    if args.command not in ("plan", "mobile", "run", "demo", "bag"):
        return []
    missing: list[Path] = []
    for flag in ("out", "frames"):
        folder = getattr(args, flag, None)
        if not isinstance(folder, Path):
            continue
        path = folder.absolute()
        while not path.exists() and path != path.parent:
            missing.append(path)
            path = path.parent
    return sorted(set(missing), key=lambda p: len(p.parts), reverse=True)


def _remove_empty(folders: list[Path]) -> None:
    for folder in folders:  # deepest first, so that parents can go too
        with contextlib.suppress(OSError):
            folder.rmdir()  # only if still empty


def _silence_stdout() -> None:
    """Point stdout at the null device, so that the exit flush cannot fail again."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (OSError, ValueError, AttributeError):  # stdout is no real file (a test's)
        pass


def _show_once(caught: list[warnings.WarningMessage]) -> None:
    seen: set[tuple[type[Warning], str]] = set()
    for item in caught:
        key = (item.category, str(item.message))
        if key not in seen:
            seen.add(key)
            warnings.showwarning(item.message, item.category, item.filename, item.lineno)


def _plan(args: argparse.Namespace) -> int:
    if args.q0 is None or args.qf is None:
        raise CommandError("plan needs --q0 and --qf")
    to_si = np.pi / 180.0 if args.deg else 1.0
    unit = "deg" if args.deg else "rad"
    if args.dt is not None:
        raise CommandError(
            "--dt is now two flags: --period (the controller period: switching "
            "times on its multiples) and --sample-step (the --csv step)"
        )
    entry = CATALOG[args.profile]
    values: dict[str, object] = {}
    for quantity in QUANTITIES.values():
        given = getattr(args, quantity.name)
        if given is None:
            continue
        flag = "--" + quantity.name.replace("_", "-")
        if not entry.takes(quantity.name):
            raise CommandError(f"{flag} {entry.refusal(quantity.name)}")
        if quantity.per_joint:
            given = _vector(given)
        values[quantity.name] = given * to_si if quantity.angular else given
    for name in (*OPTIONS, "period"):
        if getattr(args, name) is not None and not entry.takes(name):
            raise CommandError(f"--{name} {entry.refusal(name)}")
        if getattr(args, name) is not None and name != "period":
            values[name] = getattr(args, name)
    if args.grid is not None and args.period is None:
        raise CommandError("--grid needs --period (the controller period it puts times on)")
    if args.duration is not None and args.min_duration is not None:
        raise CommandError("give --duration (exact) or --min-duration (a floor), not both")
    missing = [f"--{name}" for name in entry.needs if name not in values]
    if missing:
        verb = "is" if len(missing) == 1 else "are"
        raise CommandError(
            f"{' and '.join(missing)} {verb} required by the {entry.name} "
            f"planner (it needs {_listed(['--' + n for n in entry.needs])})"
        )
    trajectory = entry.plan(values, period=args.period)
    limits = Limits(velocity=values.get("vmax"), acceleration=values.get("amax"),
                    jerk=values.get("jmax"))  # fmt: skip
    for flag, path in (("--plot", args.plot), ("--sim-plot", args.sim_plot)):
        if path is not None and path.suffix.lower() not in {".png", ".svg", ".pdf"}:
            raise CommandError(f"{flag} must end in .png, .svg or .pdf, got {path.name!r}")
    check_sim_options(args)
    summary = _summary(trajectory, limits, args.profile, unit, to_si, grid=args.grid)
    scene = log = None
    if args.sim == "mujoco":
        scene, log = simulate_arm(args, trajectory)
        summary += f"\nsimulated on {scene.robot.name} in MuJoCo, {log.summary()}"
    images = render_or_note(scene, log, args.frames)
    with staged_files() as stage:
        if args.csv is not None:
            trajectory.sample(_sample_step(args)).to_csv(stage.path(args.csv))
        if args.plot is not None:
            from trajkit.viz.plot import profiles, save

            figure = profiles(trajectory, limits, degrees=args.deg, title=f"{args.profile} move")
            save(figure, stage.path(args.plot))
        if log is not None and args.sim_csv is not None:
            log.to_csv(stage.path(args.sim_csv))
        if log is not None and args.sim_plot is not None:
            from trajkit.viz.plot import save, tracking

            title = f"{args.profile} move on {scene.robot.name}, {log.controller}"
            save(tracking(log, degrees=args.deg, title=title), stage.path(args.sim_plot))
        write_frames(images, args.frames, stage)
    print(summary)
    for path in stage.targets:
        print(f"wrote {path}")
    return 0


def _sample_step(args: argparse.Namespace) -> float:
    """The CSV's sampling step (s): as given, else the controller period, else the default."""
    for step in (args.sample_step, args.period):
        if step is not None:
            if not (np.isfinite(step) and step > 0.0):
                raise CommandError(f"--sample-step must be a time > 0 s, got {step:g}")
            return step
    return DEFAULT_STEP


def _summary(trajectory: Trajectory, limits: Limits, profile: str, unit: str, to_si: float,
             *, grid: str | None = None) -> str:  # fmt: skip
    info = trajectory.info
    lines = [f"{profile} move: {trajectory.ndof} joint(s), duration {trajectory.duration:.9g} s"]
    if info.get("limiting_joint") is not None:
        what = f"{info['limiting']} of " if "limiting" in info else ""
        lines[0] += f" (set by {what}joint {info['limiting_joint'] + 1})"
    if info.get("sync"):
        lines[0] += f", sync={info['sync']}"
    if info.get("period") and grid == "duration":
        lines[0] += f", duration a multiple of period={info['period']:g} s"
    elif info.get("period"):
        lines[0] += f", switching on multiples of period={info['period']:g} s"
    start, end = trajectory.start_state, trajectory.end_state
    with np.errstate(over="ignore"):  # a peak past 1.8e308 in degrees is shown as inf
        peaks = [trajectory.extrema(order).peak / to_si for order in (1, 2)]
    own = info.get("minimum_durations")
    phases = info.get("phase_times")
    header = f"{'joint':>5} {'q0':>12} {'qf':>12} {'peak |v|':>12} {'peak |a|':>12}"
    header += f" {'own min [s]':>12}" if own else ""
    header += "  phase times [s]" if phases else ""
    lines += [
        f"units: positions {unit}, velocities {unit}/s, accelerations {unit}/s^2",
        header,
    ]
    for j in range(trajectory.ndof):
        row = (
            f"{j + 1:>5} {start.position[j] / to_si:>12.6g} {end.position[j] / to_si:>12.6g}"
            f" {peaks[0][j]:>12.6g} {peaks[1][j]:>12.6g}"
        )
        if own:
            row += f" {own[j]:>12.6g}"
        if phases:
            row += "  " + " ".join(f"{t:.6g}" for t in phases[j])
        lines.append(row)
    if any(getattr(limits, q) is not None for q in ("velocity", "acceleration", "jerk")):
        report = trajectory.check(limits)
        lines.append(f"limit check (SI units): {'OK' if report.ok else 'FAILED'}")
        lines += [f"  {v}" for v in report.violations]
    return "\n".join(lines)


def _run_scenario(args: argparse.Namespace) -> int:
    from trajkit.scenario import execute, load

    _check_out_folder(args.out)
    if args.report:
        from trajkit.viz.report import page_title

        title = page_title(args.out / "index.html")
        if title is not None and not title.startswith("trajkit: "):
            page = f"the index.html of {title!r}" if title else "an index.html of another kind"
            raise CommandError(
                f"--out {args.out} already holds {page}; --report would replace it: choose "
                "another folder or remove that file"
            )
    outcome = execute(load(args.scenario), args.out, report=args.report)
    for path in outcome.files:
        print(f"wrote {path}")
    if not outcome.report.ok:
        print("trajkit: the plan breaks a limit (see the limit check above)", file=sys.stderr)
        return EXIT_LIMITS_BROKEN
    return 0


def _check_out_folder(folder: Path) -> None:
    if folder.exists() and not folder.is_dir():
        raise CommandError(f"--out {folder} is a file, not a folder")


def _demo(args: argparse.Namespace) -> int:
    from trajkit.demo import run

    _check_out_folder(args.out)
    written = run(args.out, log=print)
    print(f"trajkit demo: wrote {len(written)} files to {args.out}")
    return 0
