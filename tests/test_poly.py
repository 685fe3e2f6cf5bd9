"""Unit tests of trajkit._poly against numpy.polynomial reference computations."""

from __future__ import annotations

from math import comb

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from support import ROUNDING
from trajkit import _poly

# Absolute floor for relative bounds: hypothesis draws subnormal coefficients, whose
# products underflow to 0 in one computation and not in another.
UNDERFLOW = 1e-300

# Coefficients: exact zeros drawn deliberately, moderate magnitudes so that the
# reference computations themselves stay accurate.
coefficient_values = st.one_of(st.just(0.0), st.floats(-5.0, 5.0), st.floats(-1e-3, 1e-3))


@st.composite
def stacks(draw: st.DrawFn, max_degree: int = 7, max_columns: int = 5) -> np.ndarray:
    """Polynomial stacks of shape (k + 1, P), some with leading zero coefficients."""
    degree = draw(st.integers(0, max_degree))
    columns = draw(st.integers(1, max_columns))
    c = draw(hnp.arrays(np.float64, (degree + 1, columns), elements=coefficient_values))
    # Zero the leading rows of some columns: the effective degree is lower than k.
    leading = draw(hnp.arrays(np.int64, (columns,), elements=st.integers(0, degree)))
    for column, count in enumerate(leading):
        c[:count, column] = 0.0
    return c


def absolute_scale(c: np.ndarray, x: np.ndarray | float) -> np.ndarray:
    """sum_j |c_j| |x|**(k - j): the rounding-error scale of evaluating ``c`` at ``x``."""
    return _reference_polyval(np.abs(c), np.abs(x))


def _reference_polyval(c: np.ndarray, x: np.ndarray | float) -> np.ndarray:
    """Evaluate every column of ``c`` at ``x`` with numpy's polyval (shape broadcast)."""
    x = np.asarray(x, dtype=float)
    columns = c.reshape(c.shape[0], -1)
    out = np.stack([np.polyval(columns[:, p], x) for p in range(columns.shape[1])], axis=-1)
    return out.reshape(x.shape + c.shape[1:])


def _numpy_derivative(column: np.ndarray, order: int) -> np.ndarray:
    derived = np.polyder(column, order)
    return derived if derived.size else np.zeros(1)


# ---------------------------------------------------------------- derivative
@given(stacks(), st.integers(0, 9))
def test_derivative_matches_numpy_polyder(c: np.ndarray, order: int) -> None:
    k = c.shape[0] - 1
    out = _poly.derivative(c, order)
    assert out.shape == (max(k + 1 - order, 1), c.shape[1])
    for p in range(c.shape[1]):
        expected = _numpy_derivative(c[:, p], order)
        # Same power basis, padded on the left: exact integer factors, so exact equality
        # up to one rounding of the product.
        padded = np.concatenate([np.zeros(out.shape[0] - expected.size), expected])
        np.testing.assert_allclose(out[:, p], padded, rtol=ROUNDING, atol=UNDERFLOW)


def test_derivative_of_a_known_polynomial() -> None:
    # p = 2x^3 - x + 4 -> p' = 6x^2 - 1 -> p'' = 12x -> p''' = 12 -> p'''' = 0
    c = np.array([2.0, 0.0, -1.0, 4.0])
    np.testing.assert_array_equal(_poly.derivative(c, 1), [6.0, 0.0, -1.0])
    np.testing.assert_array_equal(_poly.derivative(c, 2), [12.0, 0.0])
    np.testing.assert_array_equal(_poly.derivative(c, 3), [12.0])
    np.testing.assert_array_equal(_poly.derivative(c, 4), [0.0])
    np.testing.assert_array_equal(_poly.derivative(c, 0), c)


def test_derivative_keeps_trailing_axes() -> None:
    c = np.arange(24, dtype=float).reshape(4, 3, 2)
    out = _poly.derivative(c, 2)
    assert out.shape == (2, 3, 2)
    np.testing.assert_array_equal(out[0], 6.0 * c[0])
    np.testing.assert_array_equal(out[1], 2.0 * c[1])
    assert _poly.derivative(c, 7).shape == (1, 3, 2)
    assert not _poly.derivative(c, 7).any()


def test_derivative_of_a_constant_is_zero() -> None:
    c = np.array([[3.0, -1.0]])
    out = _poly.derivative(c, 1)
    assert out.shape == (1, 2)
    np.testing.assert_array_equal(out, [[0.0, 0.0]])


# --------------------------------------------------------------------- horner
@given(
    stacks(),
    hnp.arrays(np.float64, st.integers(0, 6), elements=st.floats(-4.0, 4.0)),
)
def test_horner_matches_numpy_polyval(c: np.ndarray, x: np.ndarray) -> None:
    out = _poly.horner(c, x[:, np.newaxis])
    assert out.shape == (x.size, c.shape[1])
    expected = _reference_polyval(c, x)
    error = np.abs(out - expected)
    assert np.all(error <= ROUNDING * absolute_scale(c, x) + UNDERFLOW), error.max(initial=0.0)


def test_horner_of_a_constant_broadcasts_to_the_points() -> None:
    c = np.array([[2.0, -3.0]])  # two constant polynomials
    out = _poly.horner(c, np.array([[0.0], [1.0], [5.0]]))
    np.testing.assert_array_equal(out, [[2.0, -3.0]] * 3)


def test_horner_does_not_modify_its_input() -> None:
    c = np.array([[1.0], [2.0], [3.0]])
    copy = c.copy()
    assert _poly.horner(c, np.array([[2.0]]))[0, 0] == 11.0  # 4 + 4 + 3
    np.testing.assert_array_equal(c, copy)


# -------------------------------------------------------------- scale_argument
@given(
    stacks(),
    st.floats(0.05, 20.0),
    hnp.arrays(np.float64, 5, elements=st.floats(-2.0, 2.0)),
)
def test_scale_argument_is_composition_with_a_scaling(
    c: np.ndarray, factor: float, x: np.ndarray
) -> None:
    scaled = _poly.scale_argument(c, factor)
    assert scaled.shape == c.shape
    expected = _reference_polyval(c, factor * x)
    error = np.abs(_reference_polyval(scaled, x) - expected)
    assert np.all(error <= ROUNDING * absolute_scale(c, factor * x) + UNDERFLOW)


@given(stacks(max_columns=4), st.data())
def test_scale_argument_broadcasts_a_factor_per_column(c: np.ndarray, data: st.DataObject) -> None:
    factors = data.draw(hnp.arrays(np.float64, (c.shape[1],), elements=st.floats(0.1, 10.0)))
    scaled = _poly.scale_argument(c, factors[np.newaxis, :])
    for p, factor in enumerate(factors):
        np.testing.assert_allclose(
            scaled[:, p], _poly.scale_argument(c[:, p], factor), rtol=ROUNDING, atol=0.0
        )


def test_scale_argument_known_example() -> None:
    # p(x) = x^2 + x + 1 ; p(2x) = 4x^2 + 2x + 1
    np.testing.assert_array_equal(_poly.scale_argument(np.array([1.0, 1.0, 1.0]), 2.0), [4, 2, 1])


# ---------------------------------------------------------------- shift_origin
@given(stacks(), st.floats(-10.0, 10.0))
def test_shift_origin_matches_numpy_composition(c: np.ndarray, shift: float) -> None:
    out = _poly.shift_origin(c, shift)
    assert out.shape == c.shape
    k = c.shape[0] - 1
    for p in range(c.shape[1]):
        composed = np.poly1d(c[:, p])(np.poly1d([1.0, -shift])).coeffs
        expected = np.concatenate([np.zeros(k + 1 - composed.size), composed])
        # Each output coefficient sums terms |c_i| C(n, j) |s|^(n - j): that is its
        # rounding scale.
        scale = np.zeros(k + 1)
        for i in range(k + 1):
            n = k - i
            for j in range(n + 1):
                scale[k - j] += abs(c[i, p]) * comb(n, j) * abs(shift) ** (n - j)
        assert np.all(np.abs(out[:, p] - expected) <= ROUNDING * scale + UNDERFLOW), (
            out[:, p],
            expected,
        )


@given(stacks(), st.floats(-3.0, 3.0), hnp.arrays(np.float64, 4, elements=st.floats(-3.0, 3.0)))
def test_shift_origin_evaluates_like_the_shifted_argument(
    c: np.ndarray, shift: float, x: np.ndarray
) -> None:
    shifted = _poly.shift_origin(c, shift)
    expected = _reference_polyval(c, x - shift)
    bound = absolute_scale(c, np.abs(x) + abs(shift))
    assert np.all(np.abs(_reference_polyval(shifted, x) - expected) <= ROUNDING * bound + UNDERFLOW)


def test_shift_origin_known_example_and_zero_shift() -> None:
    # (x - 1)^2 = x^2 - 2x + 1
    np.testing.assert_array_equal(_poly.shift_origin(np.array([1.0, 0.0, 0.0]), 1.0), [1, -2, 1])
    c = np.array([[1.5, -2.0], [0.0, 3.0], [7.0, 0.25]])
    np.testing.assert_array_equal(_poly.shift_origin(c, 0.0), c)


def test_shift_origin_broadcasts_a_shift_per_column() -> None:
    c = np.array([[1.0, 1.0], [0.0, 0.0]])  # two copies of p(x) = x
    out = _poly.shift_origin(c, np.array([2.0, -3.0]))
    np.testing.assert_array_equal(out, [[1.0, 1.0], [-2.0, 3.0]])


# ---------------------------------------------------------- extrema_on_intervals
def _reference_extrema(column: np.ndarray, length: float) -> tuple[float, float]:
    """Min and max of one polynomial on [0, length] from numpy's roots and a dense grid."""
    slope = np.polyder(column)
    # Drop leading coefficients so small against the others that their roots would
    # overflow (subnormals): they cannot move an extremum inside [0, length].
    significant = np.abs(slope) > 1e-250 * np.abs(slope).max(initial=0.0)
    slope = slope[np.argmax(significant) :] if significant.any() else slope[:0]
    candidates = [0.0, length, *np.linspace(0.0, length, 2001)]
    if slope.size > 1:
        roots = np.roots(slope)
        candidates += [r.real for r in roots if abs(r.imag) < 1e-7 and 0.0 <= r.real <= length]
    values = np.polyval(column, np.asarray(candidates))
    return float(values.min()), float(values.max())


@given(stacks(), st.data())
def test_extrema_on_intervals_matches_roots_and_dense_sampling(
    c: np.ndarray, data: st.DataObject
) -> None:
    lengths = data.draw(hnp.arrays(np.float64, (c.shape[1],), elements=st.floats(0.05, 3.0)))
    low, x_low, high, x_high = _poly.extrema_on_intervals(c, lengths)
    for result in (low, x_low, high, x_high):
        assert result.shape == (c.shape[1],)
    for p in range(c.shape[1]):
        column, length = c[:, p], lengths[p]
        scale = float(absolute_scale(column[:, np.newaxis], length)[0])
        tol = ROUNDING * scale + UNDERFLOW
        # Locations lie in the interval and the reported values are attained there.
        assert 0.0 <= x_low[p] <= length
        assert 0.0 <= x_high[p] <= length
        assert abs(np.polyval(column, x_low[p]) - low[p]) <= tol
        assert abs(np.polyval(column, x_high[p]) - high[p]) <= tol
        # Never worse than the reference (roots + dense grid).
        ref_low, ref_high = _reference_extrema(column, length)
        assert low[p] <= ref_low + tol
        assert high[p] >= ref_high - tol
        assert low[p] <= high[p]


@pytest.mark.parametrize(
    ("coefficients", "length", "expected"),
    [
        # p(x) = -(x - 1)^2 + 2 on [0, 3]: max 2 at x=1, min -2 at x=3
        ([-1.0, 2.0, 1.0], 3.0, (-2.0, 3.0, 2.0, 1.0)),
        # p(x) = x^3 - 3x on [0, 2]: min -2 at x=1, max 2 at x=2
        ([1.0, 0.0, -3.0, 0.0], 2.0, (-2.0, 1.0, 2.0, 2.0)),
        # constant: min and max at the first candidate
        ([4.0], 1.5, (4.0, 0.0, 4.0, 0.0)),
        # linear, stored at degree 3 with leading zeros: min at 0, max at the end
        ([0.0, 0.0, 2.0, -1.0], 2.0, (-1.0, 0.0, 3.0, 2.0)),
        # (x - 0.5)^4: the derivative has a triple root at the minimum
        ([1.0, -2.0, 1.5, -0.5, 0.0625], 1.0, (0.0, 0.5, 0.0625, 0.0)),
    ],
)
def test_extrema_on_intervals_known_cases(
    coefficients: list[float], length: float, expected: tuple[float, float, float, float]
) -> None:
    c = np.array(coefficients)[:, np.newaxis]
    low, x_low, high, x_high = _poly.extrema_on_intervals(c, np.array([length]))
    exp_low, exp_x_low, exp_high, exp_x_high = expected
    assert low[0] == pytest.approx(exp_low, abs=1e-12)
    assert high[0] == pytest.approx(exp_high, abs=1e-12)
    # A triple root is only located to ~eps**(1/3); the value above is still exact.
    assert x_low[0] == pytest.approx(exp_x_low, abs=1e-4)
    assert x_high[0] == pytest.approx(exp_x_high, abs=1e-12)


def test_extrema_on_intervals_ignores_a_negligible_leading_coefficient() -> None:
    # 1e-30 x^3 - (x - 1)^2: the cubic term is rounding noise; max stays 0 at x = 1.
    c = np.array([[1e-30], [-1.0], [2.0], [-1.0]])
    low, _, high, x_high = _poly.extrema_on_intervals(c, np.array([2.0]))
    assert high[0] == pytest.approx(0.0, abs=1e-12)
    assert x_high[0] == pytest.approx(1.0, abs=1e-9)
    assert low[0] == pytest.approx(-1.0, abs=1e-12)


def test_extrema_on_intervals_handles_mixed_effective_degrees_in_one_batch() -> None:
    # Columns of effective degree 4, 2, 1 and 0 in one call.
    c = np.array(
        [
            [1.0, 0.0, 0.0, 0.0],
            [-2.0, 0.0, 0.0, 0.0],
            [1.5, -1.0, 0.0, 0.0],
            [-0.5, 1.0, 1.0, 0.0],
            [0.0625, 0.0, 0.0, 5.0],
        ]
    )
    lengths = np.array([1.0, 1.0, 1.0, 1.0])
    low, _, high, x_high = _poly.extrema_on_intervals(c, lengths)
    np.testing.assert_allclose(low, [0.0, 0.0, 0.0, 5.0], atol=1e-12)
    np.testing.assert_allclose(high, [0.0625, 0.25, 1.0, 5.0], atol=1e-12)
    np.testing.assert_allclose(x_high[1:3], [0.5, 1.0], atol=1e-12)
