"""Named tolerances, hypothesis strategies and assertion helpers for the whole suite."""

from __future__ import annotations

import numpy as np
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import trajkit as tk

# Tolerances ---------------------------------------------------------------------
CLOSED_FORM = 1e-9  # relative: closed-form values (boundary conditions, durations)
COEFFICIENT = 1e-12  # absolute: coefficients of small exact examples
ROUNDING = 1e-12  # relative: pure floating-point rearrangements (scaling, shifting)
FINITE_DIFFERENCE = 1e-5  # relative: central differences against analytic derivatives

# Strategies -----------------------------------------------------------------------
# Values span several magnitudes and draw exact zeros deliberately.
magnitudes = st.one_of(
    st.just(0.0),
    st.floats(min_value=-10.0, max_value=10.0),
    st.floats(min_value=1e-3, max_value=1e3),
    st.floats(min_value=-1e3, max_value=-1e-3),
)
positions = st.floats(min_value=-10.0, max_value=10.0, allow_nan=False, allow_infinity=False)
durations = st.floats(min_value=1e-2, max_value=100.0)
limits_positive = st.floats(min_value=1e-2, max_value=100.0)
ndofs = st.integers(min_value=1, max_value=6)


def joint_arrays(ndof: int, elements: st.SearchStrategy[float] = positions) -> st.SearchStrategy:
    """Arrays of shape (ndof,) drawn from ``elements``."""
    return hnp.arrays(np.float64, (ndof,), elements=elements)


@st.composite
def piecewise_trajectories(
    draw: st.DrawFn, max_degree: int = 7, max_pieces: int = 5
) -> tk.Trajectory:
    """Arbitrary Trajectory objects: random breakpoints, degree and coefficients."""
    ndof = draw(ndofs)
    pieces = draw(st.integers(1, max_pieces))
    degree = draw(st.integers(0, max_degree))
    start = draw(st.floats(min_value=-5.0, max_value=5.0))
    steps = draw(hnp.arrays(np.float64, (pieces,), elements=st.floats(0.05, 3.0)))
    breakpoints = start + np.concatenate([[0.0], np.cumsum(steps)])
    coefficients = draw(
        hnp.arrays(
            np.float64,
            (degree + 1, pieces, ndof),
            elements=st.one_of(st.just(0.0), st.floats(-5.0, 5.0)),
        )
    )
    return tk.Trajectory(breakpoints, coefficients)


# Assertion helpers --------------------------------------------------------------
def assert_state(actual: np.ndarray, expected: np.ndarray, *, rtol: float = CLOSED_FORM) -> None:
    """``actual`` equals ``expected`` to ``rtol`` relative to max(1, |expected|)."""
    actual, expected = np.asarray(actual, float), np.asarray(expected, float)
    scale = np.maximum(1.0, np.abs(expected))
    error = np.abs(actual - expected) / scale
    assert np.all(error <= rtol), (
        f"max scaled error {error.max():.3g} > {rtol:g}: {actual} vs {expected}"
    )


def slow_evaluate(trajectory: tk.Trajectory, t: float, order: int = 0) -> np.ndarray:
    """Obviously-correct scalar evaluator: find the piece by a linear scan, sum the powers."""
    bp = trajectory.breakpoints
    t = min(max(t, bp[0]), bp[-1])
    piece = 0
    while piece < len(bp) - 2 and t >= bp[piece + 1]:
        piece += 1
    x = t - bp[piece]
    k = trajectory.degree
    total = np.zeros(trajectory.ndof)
    for j in range(k + 1):
        power = k - j
        if power < order:
            continue
        factor = 1.0
        for i in range(order):
            factor *= power - i
        total += trajectory.coefficients[j, piece] * factor * x ** (power - order)
    return total


def assert_continuous(
    trajectory: tk.Trajectory, up_to_order: int, *, rtol: float = CLOSED_FORM
) -> None:
    """Derivatives 0..up_to_order agree on both sides of every interior breakpoint."""
    bp = trajectory.breakpoints
    c = trajectory.coefficients
    for i in range(1, len(bp) - 1):
        h = bp[i] - bp[i - 1]
        for order in range(up_to_order + 1):
            left = _piece_derivative(c[:, i - 1], order, h)
            right = _piece_derivative(c[:, i], order, 0.0)
            assert_state(right, left, rtol=rtol)


def _piece_derivative(c: np.ndarray, order: int, x: float) -> np.ndarray:
    k = c.shape[0] - 1
    total = np.zeros(c.shape[1])
    for j in range(k + 1 - order):
        power = k - j
        factor = np.prod(np.arange(power, power - order, -1)) if order else 1.0
        total += c[j] * factor * x ** (power - order)
    return total


# Mobile robots ------------------------------------------------------------------
# Tolerances of trajkit.mobile, on top of the ones above.
TRACKING = 1e-6  # m: the feedforward alone on the figure eight, RK4 at 1 kHz
LIMIT_TOUCH = 1e-6  # relative: the tightest peak of a timing="fastest" plan vs its bound
WORLD_ROUNDING = 1e-12  # relative: poses built from a few trigonometric operations
EPS = float(np.finfo(float).eps)

# Headings: exact zeros, ±π and its neighbours, any angle, and unwrapped ones.
headings = st.one_of(
    st.sampled_from([0.0, np.pi, -np.pi, np.nextafter(np.pi, 0.0), np.nextafter(-np.pi, 0.0)]),
    st.floats(min_value=np.pi - 1e-6, max_value=np.pi),
    st.floats(min_value=-np.pi, max_value=-np.pi + 1e-6),
    st.floats(min_value=-np.pi, max_value=np.pi),
    st.floats(min_value=-10.0, max_value=10.0),
)
coordinates = st.one_of(st.just(0.0), positions)


@st.composite
def poses(draw: st.DrawFn) -> np.ndarray:
    """Poses (x, y, θ) with exact zeros and headings at and near ±π."""
    return np.array([draw(coordinates), draw(coordinates), draw(headings)])


def heading_difference(actual: np.ndarray, expected: np.ndarray) -> np.ndarray:
    """|actual - expected| modulo 2π, in [0, π] (rad)."""
    difference = np.asarray(actual, float) - np.asarray(expected, float)
    return np.abs(np.remainder(difference + np.pi, 2.0 * np.pi) - np.pi)


def assert_heading(actual: np.ndarray, expected: np.ndarray, *, atol: float = CLOSED_FORM) -> None:
    """Headings agree modulo whole turns, to ``atol`` rad."""
    error = heading_difference(actual, expected)
    assert np.all(error <= atol), f"heading error {np.max(error):.3g} rad > {atol:g}"


def rk4_constant_twist_bound(v: float, omega: float, h: float, duration: float, scale: float):
    """Bound on RK4's position error for a constant twist over ``duration`` in steps ``h``.

    With θ linear in t, each RK4 step of ``ẋ = v cos θ`` is Simpson's rule, whose error
    is ``h⁵ max|f⁗| / 2880`` with ``|f⁗| <= |v| ω⁴``; over ``duration / h`` steps that is
    ``duration h⁴ |v| ω⁴ / 2880``. Rounding adds a few ulps of ``scale`` (the largest
    coordinate) per step.
    """
    steps = duration / h
    return duration * h**4 * abs(v) * omega**4 / 2880.0 + 8.0 * steps * EPS * scale


def offset_pose(pose: np.ndarray, lateral: float, turn: float) -> np.ndarray:
    """``pose`` moved ``lateral`` m to its left and turned ``turn`` rad."""
    x, y, theta = pose
    return np.array([x - lateral * np.sin(theta), y + lateral * np.cos(theta), theta + turn])


def phased_eight(width: float, height: float, period: float, phase: float):
    """Seed 002's figure eight whose clock starts ``phase`` periods in (a FlatOutput).

    ``phase=0.125`` starts at the top of the right lobe, heading +x, where a lateral
    offset moves the robot away from the whole curve (not onto its other branch).
    """
    from trajkit.mobile import FigureEight

    class PhasedEight(FigureEight):
        def evaluate(self, t: np.ndarray, order: int) -> np.ndarray:
            return super().evaluate(np.asarray(t, float) + phase * self.period, order)

    return PhasedEight(width, height, period)
