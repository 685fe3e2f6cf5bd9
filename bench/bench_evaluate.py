"""Evaluation speed of Trajectory beside a plain numpy expression of the same polynomials.

Run: python bench/bench_evaluate.py. Prints ns per 6-DoF sample row (median over many
repetitions, each timing a whole call) for trajkit and for numpy written by hand, and
their ratio. The machines are noisy and shared: compare ratios, not absolute times.
"""

from __future__ import annotations

import timeit

import numpy as np

import trajkit as tk

NDOF = 6
SAMPLES = 5000
REPEATS = 300


def median_ns_per_row(function, rows: int) -> float:
    function()  # warm caches
    timer = timeit.Timer(function)
    loops, _ = timer.autorange()
    runs = timer.repeat(repeat=REPEATS // max(1, loops // 10) + 5, number=loops)
    return float(np.median(runs) / loops / rows * 1e9)


def quintic_case(rng: np.random.Generator) -> tuple[str, object, object]:
    q0, qf = rng.uniform(-3, 3, NDOF), rng.uniform(-3, 3, NDOF)
    duration = 2.5
    trajectory = tk.quintic(q0, qf, duration)
    t = np.linspace(0.0, duration, SAMPLES)
    distance = qf - q0

    def by_hand() -> np.ndarray:
        s = (t / duration)[:, np.newaxis]
        return q0 + distance * (10 * s**3 - 15 * s**4 + 6 * s**5)

    np.testing.assert_allclose(trajectory.position(t), by_hand(), rtol=1e-12, atol=1e-12)
    return "quintic, 1 piece", (lambda: trajectory.position(t)), by_hand


def spline_case(rng: np.random.Generator) -> tuple[str, object, object]:
    times = np.cumsum(rng.uniform(0.2, 1.0, 21)) - 0.2
    trajectory = tk.cubic_spline(times, rng.uniform(-3, 3, (times.size, NDOF)))
    t = np.linspace(times[0], times[-1], SAMPLES)
    c, bp = trajectory.coefficients, trajectory.breakpoints

    def by_hand() -> np.ndarray:
        piece = np.clip(np.searchsorted(bp, t, side="right") - 1, 0, bp.size - 2)
        x = (t - bp[piece])[:, np.newaxis]
        return c[0, piece] * x**3 + c[1, piece] * x**2 + c[2, piece] * x + c[3, piece]

    np.testing.assert_allclose(trajectory.position(t), by_hand(), rtol=1e-12, atol=1e-12)
    return "cubic spline, 20 pieces", (lambda: trajectory.position(t)), by_hand


def main() -> None:
    rng = np.random.default_rng(20261122)
    print(f"{SAMPLES} times x {NDOF} joints; ns per sample row (median)")
    print(f"{'case':<26}{'trajkit':>10}{'numpy':>10}{'numpy/trajkit':>15}")
    for make in (quintic_case, spline_case):
        name, ours, theirs = make(rng)
        a = median_ns_per_row(ours, SAMPLES)
        b = median_ns_per_row(theirs, SAMPLES)
        print(f"{name:<26}{a:>10.1f}{b:>10.1f}{b / a:>15.2f}")


if __name__ == "__main__":
    main()
