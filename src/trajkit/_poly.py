"""Vectorized arithmetic on stacks of polynomials in the descending power basis.

A stack ``c`` of shape ``(k + 1, ...)`` holds one polynomial per trailing index:
``p(x) = c[0] x**k + c[1] x**(k-1) + ... + c[k]`` (scipy's PPoly layout).
"""

from __future__ import annotations

from math import comb

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

# A leading coefficient this small against the largest one (on the unit interval)
# is rounding noise, not a real degree: trimming it changes values by < 1e-13 relative.
DEGREE_TRIM = 1e-13


def derivative(c: FloatArray, order: int = 1) -> FloatArray:
    """Coefficients of the ``order``-th derivative; shape ``(max(k + 1 - order, 1), ...)``."""
    k = c.shape[0] - 1
    if order <= 0:
        return c
    if order > k:
        return np.zeros((1, *c.shape[1:]))
    powers = np.arange(k, order - 1, -1)  # exponents of the surviving terms
    factor = np.ones_like(powers, dtype=np.float64)
    for j in range(order):
        factor *= powers - j
    shape = (-1,) + (1,) * (c.ndim - 1)
    return c[: k + 1 - order] * factor.reshape(shape)


def horner(c: FloatArray, x: FloatArray) -> FloatArray:
    """Evaluate every polynomial of ``c`` at ``x`` (broadcast against ``c[0]``)."""
    if c.shape[0] == 1:
        return np.broadcast_to(c[0], np.broadcast_shapes(c.shape[1:], np.shape(x))).copy()
    result = c[0] * x + c[1]  # a new array of the broadcast shape, at less call cost
    for coefficient in c[2:]:
        result *= x
        result += coefficient
    return result


def scale_argument(c: FloatArray, factor: FloatArray | float) -> FloatArray:
    """Coefficients of ``p(factor * x)`` (``factor`` broadcasts against ``c[0]``)."""
    k = c.shape[0] - 1
    exponents = np.arange(k, -1, -1).reshape((-1,) + (1,) * (c.ndim - 1))
    return c * np.power(factor, exponents)


def shift_origin(c: FloatArray, shift: FloatArray | float) -> FloatArray:
    """Coefficients of ``p(x - shift)``: re-expand around a new origin."""
    k = c.shape[0] - 1
    out = np.zeros_like(c)
    # (x - s)**n = sum_j C(n, j) x**j (-s)**(n - j); each power of -s computed once.
    powers = [np.power(-shift, n) for n in range(k + 1)]
    for i in range(k + 1):
        n = k - i
        for j in range(n + 1):
            out[k - j] += c[i] * comb(n, j) * powers[n - j]
    return out


def extrema_on_intervals(
    c: FloatArray, lengths: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Exact minimum and maximum of each polynomial over ``[0, lengths]``.

    Parameters
    ----------
    c : ndarray, shape (k + 1, P)
        One polynomial per column, in the local variable ``x``.
    lengths : ndarray, shape (P,)
        Interval length of each polynomial (> 0).

    Returns
    -------
    minimum, x_of_minimum, maximum, x_of_maximum : ndarray, shape (P,)

    Notes
    -----
    Candidates are the interval ends and the real parts of all roots of the
    derivative (eigenvalues of batched companion matrices, one batch per effective
    degree). Extra candidates never change the answer because the polynomial itself
    is evaluated at each, so nearly-real complex root pairs are kept, not filtered.
    """
    k = c.shape[0] - 1
    count = c.shape[1]
    unit = scale_argument(c, lengths[np.newaxis, :])  # p(h u), u in [0, 1]
    candidates = np.zeros((max(k - 1, 0) + 2, count))
    candidates[1] = 1.0
    if k >= 2:
        slope = derivative(unit, 1)  # degree k - 1 in u
        magnitude = np.max(np.abs(slope), axis=0)
        significant = np.abs(slope) > DEGREE_TRIM * magnitude
        # Index of the first significant coefficient gives the effective degree.
        first = np.where(significant.any(axis=0), significant.argmax(axis=0), k - 1)
        degree = (k - 1) - first
        for g in range(1, k):
            columns = np.flatnonzero(degree == g)
            if columns.size == 0:
                continue
            rows = first[columns][np.newaxis, :] + np.arange(g + 1)[:, np.newaxis]
            poly = slope[rows, columns[np.newaxis, :]]  # (g + 1, n)
            monic = poly[1:] / poly[0]
            if g == 1:
                roots = -monic.T
            else:
                companion = np.zeros((columns.size, g, g))
                companion[:, 0, :] = -monic.T
                companion[:, np.arange(1, g), np.arange(g - 1)] = 1.0
                roots = np.linalg.eigvals(companion)
            candidates[2 : 2 + g, columns] = np.clip(np.real(roots).T, 0.0, 1.0)
    values = horner(unit[:, np.newaxis, :], candidates)
    low = np.argmin(values, axis=0)
    high = np.argmax(values, axis=0)
    columns = np.arange(count)
    return (
        values[low, columns],
        candidates[low, columns] * lengths,
        values[high, columns],
        candidates[high, columns] * lengths,
    )
