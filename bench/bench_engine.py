"""trajkit's compiled profile engine beside ruckig, in one process, on the same problems.

Run: python bench/bench_engine.py [--problems 2000] [--batch 20000] [--dt-batch 5000]
     [--repeats 5] [--moves 10] [--cycles 5000]

Random 6-DoF moves (fixed seed, per-joint limits as in bench_batch.py), each planned
by trajkit and by ruckig, timed side by side; ratio = ruckig time / trajkit time
(> 1: trajkit faster). Every case also compares the durations (or, online, the
states), so it is the same work that is timed.

1-3. One planning call per problem: ``tk.scurve`` rest to rest, ``tk.trapezoidal``
     (ruckig with infinite jerk), ``tk.scurve`` from and to random velocities;
     ruckig's ``calculate`` with one Ruckig, InputParameter and Trajectory reused,
     the problem's fields set each call (from lists: ruckig converts a NumPy row
     about 15x slower than a list). Each call timed alone, the two libraries
     interleaved problem by problem; median us per call over problems x repeats.
4.   ``tk.batch.scurve`` (random velocities) on B problems in one call (all numba
     threads, and one thread) vs ruckig in a Python loop: problems per second.
5.   As 4 with ``period=0.001``, beside ruckig's discrete durations
     (``Ruckig(6, 0.001)``, ``DurationDiscretization.Discrete``). The batch
     planner puts every switching time on the grid (``grid="switches"``), which
     may cost whole periods over ruckig's duration-only grid: the difference is
     printed in periods, and single ``tk.scurve(..., period=dt, grid="duration")`` calls
     on a sample are checked against ruckig to ~1e-6.
6.   Online, period 1 ms: ``tk.online.Generator.update`` vs ruckig's ``update`` +
     ``pass_to_input``, us per control cycle, the states compared cycle by cycle.
     Both plan when the target changes and sample their plan otherwise. Fixed
     targets (move j from rest at q0[j] to qf[j], stepped until reached): each
     plans once per move. A target that moves every cycle (a sine per joint):
     both plan every cycle. A move trajkit fails on is reported and left out of
     the timing.

The first trajkit call of each kind compiles the numba kernels (or loads them from
the cache): that warm-up is timed apart, before everything else.
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable

import numpy as np

import trajkit as tk
from timing import median_seconds
from trajkit.errors import TrajkitError

NDOF = 6
DT = 0.001  # control period of the discrete and online cases (s)


def random_problems(count: int, seed: int = 20261122) -> dict[str, np.ndarray]:
    """Limits per joint as bench_batch.py's; moves in [-3, 3] rad and boundary
    velocities within half the velocity limits. Problem i is the same for every count."""
    rng = np.random.default_rng(seed)
    p = {
        "vmax": rng.uniform(0.5, 3.0, NDOF),
        "amax": rng.uniform(1.0, 10.0, NDOF),
        "jmax": rng.uniform(5.0, 100.0, NDOF),
    }
    u = np.moveaxis(rng.random((count, 4, NDOF)), 1, 0)
    p["q0"], p["qf"] = -3.0 + 6.0 * u[0], -3.0 + 6.0 * u[1]  # new arrays, C-contiguous
    p["v0"], p["vf"] = (u[2] - 0.5) * p["vmax"], (u[3] - 0.5) * p["vmax"]
    return p


def ruckig_planner(
    p: dict[str, np.ndarray], *, jerk: bool = True, moving: bool = False, dt: float | None = None
) -> Callable[[int], float]:
    """Problem index -> ruckig's duration: one Ruckig, input and trajectory reused."""
    from ruckig import DurationDiscretization, InputParameter, Result, Ruckig, Trajectory

    otg = Ruckig(NDOF) if dt is None else Ruckig(NDOF, dt)
    inp, out = InputParameter(NDOF), Trajectory(NDOF)
    inp.max_velocity = p["vmax"].tolist()
    inp.max_acceleration = p["amax"].tolist()
    inp.max_jerk = p["jmax"].tolist() if jerk else [float("inf")] * NDOF
    if dt is not None:
        inp.duration_discretization = DurationDiscretization.Discrete
    q0, qf, v0, vf = (p[k].tolist() for k in ("q0", "qf", "v0", "vf"))
    working = Result.Working

    def rest(i: int) -> float:
        inp.current_position = q0[i]
        inp.target_position = qf[i]
        if otg.calculate(inp, out) != working:
            raise RuntimeError(f"ruckig failed on problem {i}")
        return out.duration

    def with_velocities(i: int) -> float:
        inp.current_position = q0[i]
        inp.target_position = qf[i]
        inp.current_velocity = v0[i]
        inp.target_velocity = vf[i]
        if otg.calculate(inp, out) != working:
            raise RuntimeError(f"ruckig failed on problem {i}")
        return out.duration

    return with_velocities if moving else rest


def per_call(
    ours: Callable[[int], float], theirs: Callable[[int], float], count: int, repeats: int
) -> tuple[float, float, np.ndarray, np.ndarray]:
    """Median seconds per call of each, interleaved problem by problem, and the durations."""
    clock = time.perf_counter
    ours_t, theirs_t = np.empty((repeats, count)), np.empty((repeats, count))
    ours_d, theirs_d = np.empty(count), np.empty(count)
    sides = ((ours, ours_t, ours_d), (theirs, theirs_t, theirs_d))
    for r in range(repeats):
        for i in range(count):
            for plan, times, durations in sides[::-1] if (r + i) % 2 else sides:
                start = clock()  # the two alternate going first
                durations[i] = plan(i)
                times[r, i] = clock() - start
    return float(np.median(ours_t)), float(np.median(theirs_t)), ours_d, theirs_d


def max_rel_diff(ours: np.ndarray, theirs: np.ndarray) -> float:
    return float(np.max(np.abs(ours - theirs) / np.maximum(np.abs(theirs), 1e-300)))


def warm_up(p: dict[str, np.ndarray]) -> None:
    """First call of every trajkit path timed here (numba compiles or loads its cache)."""
    lim = (p["vmax"], p["amax"], p["jmax"])
    few = {k: p[k][:4] for k in ("q0", "qf", "v0", "vf")}
    calls = [
        ("tk.scurve", lambda: tk.scurve(p["q0"][0], p["qf"][0], *lim)),
        ("tk.trapezoidal", lambda: tk.trapezoidal(p["q0"][0], p["qf"][0], *lim[:2])),
        (
            "tk.scurve grid=duration",
            lambda: tk.scurve(p["q0"][0], p["qf"][0], *lim, period=DT, grid="duration"),
        ),
        ("tk.batch.scurve", lambda: tk.batch.scurve(few["q0"], few["qf"], *lim)),
        ("tk.batch.scurve period", lambda: tk.batch.scurve(few["q0"], few["qf"], *lim, period=DT)),
        ("online update", lambda: tk.online.Generator(NDOF, DT, *lim).update(p["qf"][0])),
    ]
    total = 0.0
    parts = []
    for name, call in calls:
        start = time.perf_counter()
        call()
        seconds = time.perf_counter() - start
        total += seconds
        parts.append(f"{name} {seconds:.2f}")
    ruckig_planner(p)(0)
    print(f"warm-up (numba compile or cache load): {total:.1f} s  ({', '.join(parts)} s)")


def header(first: str, unit: str) -> None:
    print(f"\n{first:<44}{'trajkit':>10}{'ruckig':>10}{'ratio':>8}{'max rel diff':>14}  ({unit})")


def row(name: str, ours: float, theirs: float, diff: float | str) -> None:
    text = diff if isinstance(diff, str) else f"{diff:.2e}"
    print(f"{name:<44}{ours:>10.2f}{theirs:>10.2f}{theirs / ours:>8.2f}{text:>14}")


def single_calls(p: dict[str, np.ndarray], count: int, repeats: int) -> None:
    q0, qf, v0, vf = p["q0"], p["qf"], p["v0"], p["vf"]
    vmax, amax, jmax = p["vmax"], p["amax"], p["jmax"]
    cases = [
        (
            "1 S-curve rest to rest",
            lambda i: tk.scurve(q0[i], qf[i], vmax, amax, jmax).duration,
            ruckig_planner(p),
        ),
        (
            "2 trapezoid (ruckig: infinite jerk)",
            lambda i: tk.trapezoidal(q0[i], qf[i], vmax, amax).duration,
            ruckig_planner(p, jerk=False),
        ),
        (
            "3 S-curve, random v0 and vf",
            lambda i: tk.scurve(q0[i], qf[i], vmax, amax, jmax, v0=v0[i], vf=vf[i]).duration,
            ruckig_planner(p, moving=True),
        ),
    ]
    header(f"one call per problem, {count} x {repeats}", "median us per call")
    for name, ours, theirs in cases:
        ours_s, theirs_s, ours_d, theirs_d = per_call(ours, theirs, count, repeats)
        row(name, ours_s * 1e6, theirs_s * 1e6, max_rel_diff(ours_d, theirs_d))


def ruckig_loop(plan: Callable[[int], float], count: int, repeats: int):
    durations = np.empty(count)

    def loop() -> None:
        for i in range(count):
            durations[i] = plan(i)

    return median_seconds(loop, repeats), durations


def batch_calls(p: dict[str, np.ndarray], count: int, dt_count: int, repeats: int) -> None:
    import numba

    lim = (p["vmax"], p["amax"], p["jmax"])

    def plan(n: int, dt: float | None, grid: str = "switches"):
        return lambda: tk.batch.scurve(
            p["q0"][:n], p["qf"][:n], *lim, v0=p["v0"][:n], vf=p["vf"][:n], period=dt, grid=grid
        )

    threads = numba.get_num_threads()
    header("batch, random v0 and vf", "problems per second, 1e3")
    cases = (
        ("4 tk.batch.scurve", count, None, "switches"),
        ("5 with period=0.001", dt_count, DT, "switches"),
        ("5b period, grid='duration'", count, DT, "duration"),  # ruckig's discrete durations
    )
    for label, n, dt, grid in cases:
        ours_d = plan(n, dt, grid)().durations
        speeds = []
        for k in sorted({threads, 1}, reverse=True):
            numba.set_num_threads(k)
            speeds.append((k, n / median_seconds(plan(n, dt, grid), repeats)))
        numba.set_num_threads(threads)
        seconds, theirs_d = ruckig_loop(ruckig_planner(p, moving=True, dt=dt), n, repeats)
        theirs = n / seconds
        if dt is None or grid == "duration":
            diff: float | str = max_rel_diff(ours_d, theirs_d)
            diff = f"{diff:.2e}"
        else:
            periods = np.round((ours_d - theirs_d) / dt).astype(int)
            diff = f"{periods.min()}..{periods.max()} dt"
        for k, speed in speeds:
            # Throughput ratio: ruckig's time over trajkit's = trajkit's speed over ruckig's.
            print(
                f"{label + f', B={n}, {k} thread(s)':<44}{speed / 1e3:>10.2f}"
                f"{theirs / 1e3:>10.2f}{speed / theirs:>8.2f}{diff:>14}"
            )
        if dt is not None and grid == "switches":
            grid_check(p, n, dt, ours_d, theirs_d, periods)


def grid_check(p, n: int, dt: float, ours_d, theirs_d, periods) -> None:
    """Case 5's durations: trajkit's switch grid against ruckig's duration-only grid."""
    lim = (p["vmax"], p["amax"], p["jmax"])
    off_grid = np.max(np.abs(ours_d / dt - np.round(ours_d / dt)))
    print(
        f"  trajkit - ruckig durations in periods: {np.mean(periods == 0):.0%} equal, "
        f"mean {periods.mean():.2f}; trajkit off the grid by {off_grid:.1e} dt"
    )
    sample = min(n, 200)
    grid_d = [
        tk.scurve(
            p["q0"][i], p["qf"][i], *lim, v0=p["v0"][i], vf=p["vf"][i], period=dt, grid="duration"
        ).duration
        for i in range(sample)
    ]
    print(
        f"  tk.scurve(dt, grid='duration') vs ruckig Discrete, {sample} problems: "
        f"max rel diff {max_rel_diff(np.array(grid_d), theirs_d[:sample]):.2e}"
    )


def online_targets(p: dict[str, np.ndarray], cycles: int) -> list:
    """A target moving every cycle: a sine per joint about the first start position."""
    k = np.arange(cycles)[:, np.newaxis]
    amplitude = 0.3 * p["vmax"]  # peak target speed 0.3 * 2 pi * 0.5 < vmax
    return (p["q0"][0] + amplitude * np.sin(2 * np.pi * 0.5 * DT * k)).tolist()


def trajkit_online(p, start: np.ndarray, targets: list, hold: bool, log: list | None) -> int:
    """Cycles from rest at ``start``: each target until reached (``hold``) or for one cycle."""
    gen = tk.online.Generator(NDOF, DT, p["vmax"], p["amax"], p["jmax"], position=start)
    update = gen.update
    cycles = 0
    for target in targets:
        reached = False
        while not reached:
            state, reached = update(target)
            cycles += 1
            if log is not None:
                log.append(state.position.copy())
            reached = reached or not hold
    return cycles


def ruckig_online(p, start: np.ndarray, targets: list, hold: bool, log: list | None):
    """As trajkit_online; also how many cycles ruckig planned in (counted when logging)."""
    from ruckig import InputParameter, OutputParameter, Result, Ruckig

    otg, inp, out = Ruckig(NDOF, DT), InputParameter(NDOF), OutputParameter(NDOF)
    inp.max_velocity = p["vmax"].tolist()
    inp.max_acceleration = p["amax"].tolist()
    inp.max_jerk = p["jmax"].tolist()
    inp.current_position = start.tolist()
    update, handoff, working = otg.update, out.pass_to_input, Result.Working
    cycles = calculations = 0
    for target in targets:
        inp.target_position = target
        reached = False
        while not reached:
            result = update(inp, out)
            if result < 0:
                raise RuntimeError(f"ruckig online failed: {result}")
            handoff(inp)
            cycles += 1
            if log is not None:
                log.append(np.array(out.new_position))
                calculations += out.new_calculation
            reached = result != working or not hold
    return cycles, calculations


def online(p: dict[str, np.ndarray], moves: int, cycles: int, repeats: int) -> None:
    """Fixed targets: move j from rest at q0[j] to qf[j]; then a target moving every cycle."""
    runs = [(p["q0"][j], [p["qf"][j].tolist()], True) for j in range(moves)]
    cases = [
        (f"{moves} fixed targets", runs),
        ("target moving", [(p["q0"][0], online_targets(p, cycles), False)]),
    ]
    header(f"6 online, dt = {DT * 1e3:g} ms", "median us per control cycle")
    notes = []
    for name, all_runs in cases:
        # Untimed runs log both libraries' states to compare them cycle by cycle.
        good, gap, failures = [], 0.0, []
        ours_cycles = theirs_cycles = calculations = 0
        for run in all_runs:
            ours_log: list = []
            theirs_log: list = []
            theirs_n, planned = ruckig_online(p, *run, theirs_log)
            try:
                ours_n = trajkit_online(p, *run, ours_log)
            except TrajkitError as error:
                failures.append(f"cycle {len(ours_log) + 1} of {theirs_n}: {error}")
                continue
            good.append(run)
            n = min(ours_n, theirs_n)
            gap = max(gap, float(np.max(np.abs(np.array(ours_log[:n]) - theirs_log[:n]))))
            ours_cycles, theirs_cycles = ours_cycles + ours_n, theirs_cycles + theirs_n
            calculations += planned
        if failures:
            print(
                f"{name}: trajkit failed in {len(failures)} of {len(all_runs)} runs, first at "
                f"{failures[0]}"
            )
        if not good:
            continue

        def ours(runs=good) -> None:
            for run in runs:
                trajkit_online(p, *run, None)

        def theirs(runs=good) -> None:
            for run in runs:
                ruckig_online(p, *run, None)

        ours_us = median_seconds(ours, repeats) / ours_cycles * 1e6
        theirs_us = median_seconds(theirs, repeats) / theirs_cycles * 1e6
        label = name if not failures else f"{name} ({len(good)} timed)"
        row(label, ours_us, theirs_us, f"{gap:.1e} rad")
        notes.append(
            f"{label}: {ours_cycles} cycles trajkit, {theirs_cycles} ruckig, which planned "
            f"in {calculations}"
        )
    print(f"  {'; '.join(notes)}; last column: largest |q| gap")
    ours, theirs = cycle_times(p, online_targets(p, cycles))
    print(
        "  target moving, each cycle timed alone (us): trajkit median "
        f"{np.median(ours):.2f}, p99 {np.percentile(ours, 99):.2f}; ruckig median "
        f"{np.median(theirs):.2f}, p99 {np.percentile(theirs, 99):.2f}; p99 ratio "
        f"{np.percentile(theirs, 99) / np.percentile(ours, 99):.2f}"
    )


def cycle_times(p: dict[str, np.ndarray], targets: list) -> tuple[np.ndarray, np.ndarray]:
    """Each control cycle's update timed on its own (moving target), both libraries."""
    from ruckig import InputParameter, OutputParameter, Ruckig

    gen = tk.online.Generator(NDOF, DT, p["vmax"], p["amax"], p["jmax"], position=p["q0"][0])
    otg, inp, out = Ruckig(NDOF, DT), InputParameter(NDOF), OutputParameter(NDOF)
    inp.max_velocity = p["vmax"].tolist()
    inp.max_acceleration = p["amax"].tolist()
    inp.max_jerk = p["jmax"].tolist()
    inp.current_position = p["q0"][0].tolist()
    clock = time.perf_counter
    ours, theirs = np.empty(len(targets)), np.empty(len(targets))
    for k, target in enumerate(targets):
        start = clock()
        gen.update(target)
        middle = clock()
        inp.target_position = target
        otg.update(inp, out)
        out.pass_to_input(inp)
        ours[k], theirs[k] = middle - start, clock() - middle
    return ours * 1e6, theirs * 1e6


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--problems", type=int, default=2000, help="cases 1-3")
    parser.add_argument("--batch", type=int, default=20_000, help="B of case 4")
    parser.add_argument("--dt-batch", type=int, default=5000, help="B of case 5 (<= --batch)")
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--moves", type=int, default=10, help="online moves to a fixed target")
    parser.add_argument("--cycles", type=int, default=5000, help="moving-target cycles")
    args = parser.parse_args()
    p = random_problems(max(args.problems, args.batch, args.dt_batch, args.moves))
    print(
        f"trajkit vs ruckig, {NDOF}-DoF random moves, ratio = ruckig time / trajkit time "
        "(> 1: trajkit faster)"
    )
    warm_up(p)
    single_calls(p, args.problems, args.repeats)
    batch_calls(p, args.batch, min(args.dt_batch, args.batch), args.repeats)
    online(p, args.moves, args.cycles, args.repeats)


if __name__ == "__main__":
    main()
