"""The compiled polynomial roots against numpy.roots and hand-made adversaries.

Tolerances (relative to the scale of the roots): 1e-12 for cubics with separated
roots, 1e-9 for quartics (Ferrari loses a few more digits through the resolvent),
and sqrt(eps)-sized for double roots, whose position is ill-conditioned anyway.
The solvers' degeneracy thresholds are absolute (as in the reference): a cubic's
roots are reliable for magnitudes >= ~0.1, which is what the random cases draw.
"""

import math

import numpy as np
import pytest

from trajkit.profiles._kernels.roots import (
    poly_derivative,
    poly_derivative_eval,
    poly_eval,
    poly_monic_derivative,
    shrink_interval,
    solve_cubic,
    solve_quart_monic,
    solve_resolvent,
)

SEED = 20240611


def _cubic(coeffs):
    out = np.full(3, np.nan)
    n = solve_cubic(*(float(c) for c in coeffs), out)
    return out[:n].copy()


def _quartic(coeffs):
    """Roots of a monic quartic given with its leading 1."""
    assert coeffs[0] == 1.0
    out = np.full(4, np.nan)
    n = solve_quart_monic(*(float(c) for c in coeffs[1:]), out)
    return out[:n].copy()


def _check_shape(found):
    assert np.all(np.isfinite(found))
    assert np.all(found >= 0.0)
    assert np.all(np.diff(found) >= 0.0)
    assert not np.any(np.signbit(found)), "-0.0 must be reported as +0.0"


def _distinct(values, tol):
    """Cluster sorted values closer than tol (a double root may come once or twice)."""
    out = []
    for v in np.sort(values):
        if not out or v - out[-1] > tol:
            out.append(v)
    return np.array(out)


def _separated_roots(rng, k, scale, lo=0.05, gap=0.1):
    """k real roots in [-2, 2] * scale, apart from 0 and from each other."""
    while True:
        r = rng.uniform(-2.0, 2.0, k) * scale
        if np.min(np.abs(r)) > lo * scale and np.min(np.diff(np.sort(r))) > gap * scale:
            return r


@pytest.mark.parametrize("scale", [0.1, 1.0, 10.0, 1e3])
def test_cubic_three_real_roots_match_numpy(scale):
    rng = np.random.default_rng(SEED)
    for _ in range(500):
        r = _separated_roots(rng, 3, scale)
        lead = 10.0 ** rng.uniform(-6.0, 6.0) * rng.choice([-1.0, 1.0])
        coeffs = np.poly(r) * lead
        found = _cubic(coeffs)
        _check_shape(found)
        ref = np.sort(np.roots(coeffs).real)
        expected = ref[ref >= 0.0]
        assert found.shape == expected.shape, (r, lead, found)
        np.testing.assert_allclose(found, expected, rtol=0.0, atol=1e-12 * scale)


@pytest.mark.parametrize("scale", [0.1, 1.0, 10.0, 1e3])
def test_cubic_one_real_root_and_complex_pair(scale):
    rng = np.random.default_rng(SEED + 1)
    for _ in range(500):
        r = rng.uniform(-2.0, 2.0) * scale
        if abs(r) < 0.05 * scale:
            continue
        re, im = rng.uniform(-2.0, 2.0) * scale, rng.uniform(0.1, 2.0) * scale
        coeffs = np.polymul([1.0, -r], [1.0, -2.0 * re, re * re + im * im])
        coeffs = coeffs * 10.0 ** rng.uniform(-6.0, 6.0)
        found = _cubic(coeffs)
        _check_shape(found)
        if r >= 0.0:
            assert found.shape == (1,)
            assert abs(found[0] - r) <= 1e-12 * scale
        else:
            assert found.shape == (0,)


def test_cubic_random_coefficients_match_numpy_real_roots():
    rng = np.random.default_rng(SEED + 2)
    checked = 0
    for _ in range(3000):
        coeffs = rng.normal(size=4) * 10.0 ** rng.uniform(-2.0, 2.0, size=4)
        ref = np.roots(coeffs)
        # Skip the ambiguous: nearly real complex pairs, roots near 0, near-double roots.
        if np.any((np.abs(ref.imag) > 0.0) & (np.abs(ref.imag) < 1e-3)):
            continue
        real = np.sort(ref[ref.imag == 0.0].real)
        scale = max(1.0, float(np.max(np.abs(real)))) if real.size else 1.0
        if np.any(np.abs(real) < 0.05) or np.any(np.diff(real) < 1e-3 * scale):
            continue
        expected = real[real >= 0.0]
        found = _cubic(coeffs)
        _check_shape(found)
        assert found.shape == expected.shape, (coeffs, found, expected)
        np.testing.assert_allclose(found, expected, rtol=1e-9, atol=1e-9 * scale)
        checked += 1
    assert checked > 1000  # the filter must leave most cases in


def test_cubic_is_invariant_to_scaling_the_coefficients():
    base = np.poly([-1.5, 0.25, 3.0])
    expected = _cubic(base)
    np.testing.assert_allclose(expected, [0.25, 3.0], atol=1e-14)
    for s in (1e-10, 1e-5, 1e5, 1e10, -1.0, -1e8):
        np.testing.assert_allclose(_cubic(base * s), expected, rtol=0.0, atol=1e-13)


def test_cubic_double_and_triple_roots():
    # A double root is found, once or twice, to about sqrt(eps).
    for roots, distinct in (
        ([1.0, 1.0, 2.0], [1.0, 2.0]),
        ([2.0, 2.0, 1.0], [1.0, 2.0]),
        ([0.5, 0.5, -1.0], [0.5]),
        ([-0.5, -0.5, 3.0], [3.0]),
    ):
        found = _cubic(np.poly(roots))
        _check_shape(found)
        np.testing.assert_allclose(_distinct(found, 1e-6), distinct, atol=1e-7)
    # A triple root only to about cbrt(eps).
    for r in (1.0, 3.0):
        found = _cubic(np.poly([r, r, r]))
        _check_shape(found)
        np.testing.assert_allclose(_distinct(found, 1e-4), [r], rtol=1e-5)


def test_cubic_degenerate_leading_coefficients():
    # Leading coefficient (below eps) dropped: the quadratic x^2 - 3x + 2.
    np.testing.assert_allclose(_cubic([0.0, 1.0, -3.0, 2.0]), [1.0, 2.0], atol=1e-15)
    np.testing.assert_allclose(_cubic([1e-17, 1.0, -3.0, 2.0]), [1.0, 2.0], atol=1e-15)
    # A quadratic with a negative discriminant: no root.
    assert _cubic([0.0, 1.0, 0.0, 1.0]).size == 0
    # Linear: 2x - 3.
    np.testing.assert_allclose(_cubic([0.0, 0.0, 2.0, -3.0]), [1.5], atol=1e-15)
    assert _cubic([0.0, 0.0, 2.0, 3.0]).size == 0  # its root is negative
    # A nonzero constant: no equation to solve, no root.
    assert _cubic([0.0, 0.0, 0.0, 5.0]).size == 0


def test_cubic_zero_constant_term_reports_zero():
    np.testing.assert_allclose(_cubic(np.poly([0.0, 1.0, 2.0])), [0.0, 1.0, 2.0], atol=1e-15)
    np.testing.assert_allclose(_cubic([1.0, 1.0, 1.0, 0.0]), [0.0])  # x (x^2 + x + 1)
    np.testing.assert_allclose(_cubic([1.0, 0.0, -4.0, 1e-17]), [0.0, 2.0])


def test_zero_polynomial_reports_the_single_root_zero():
    # The constant term vanishes, so x = 0 is reported; the remainder is empty.
    found = _cubic([0.0, 0.0, 0.0, 0.0])
    np.testing.assert_array_equal(found, [0.0])
    _check_shape(found)
    # x^4 = 0: the branch for d = c = 0 reports zero and the quadratic's double root.
    found = _quartic([1.0, 0.0, 0.0, 0.0, 0.0])
    np.testing.assert_array_equal(found, [0.0, 0.0])
    _check_shape(found)


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_non_finite_coefficients_report_no_root(bad):
    # NaN fails the >= 0 test and is never reported; infinities end in NaN.
    for k in range(4):
        coeffs = [1.0, -2.0, 0.5, -0.1]
        coeffs[k] = bad
        _check_shape(_cubic(coeffs))
        quart = [1.0, -1.0, -2.0, 0.5, -0.1]
        quart[k + 1] = bad
        _check_shape(_quartic(quart))


@pytest.mark.parametrize("scale", [0.01, 0.1, 1.0, 10.0, 100.0])
def test_quartic_four_real_roots_match_numpy(scale):
    rng = np.random.default_rng(SEED + 3)
    for _ in range(500):
        r = _separated_roots(rng, 4, scale)
        coeffs = np.poly(r)
        found = _quartic(coeffs)
        _check_shape(found)
        expected = np.sort(r[r >= 0.0])
        assert found.shape == expected.shape, (r, found)
        np.testing.assert_allclose(found, expected, rtol=0.0, atol=1e-9 * scale)


def test_quartic_random_coefficients_match_numpy_real_roots():
    rng = np.random.default_rng(SEED + 4)
    checked = 0
    for _ in range(3000):
        coeffs = np.concatenate(([1.0], rng.normal(size=4) * 10.0 ** rng.uniform(-1.0, 1.0, 4)))
        ref = np.roots(coeffs)
        if np.any((np.abs(ref.imag) > 0.0) & (np.abs(ref.imag) < 1e-2)):
            continue
        real = np.sort(ref[ref.imag == 0.0].real)
        scale = max(1.0, float(np.max(np.abs(ref))))
        if np.any(np.abs(real) < 0.05) or np.any(np.diff(real) < 1e-2 * scale):
            continue
        expected = real[real >= 0.0]
        found = _quartic(coeffs)
        _check_shape(found)
        assert found.shape == expected.shape, (coeffs, found, expected)
        np.testing.assert_allclose(found, expected, rtol=1e-8, atol=1e-8 * scale)
        checked += 1
    assert checked > 1000


def test_quartic_with_complex_pairs():
    # (x - 1)^2 (x^2 + 1) and (x - 2)(x + 1)(x^2 + 2x + 5).
    found = _quartic(np.polymul(np.poly([1.0, 1.0]), [1.0, 0.0, 1.0]))
    np.testing.assert_allclose(_distinct(found, 1e-6), [1.0], atol=1e-7)
    found = _quartic(np.polymul(np.poly([2.0, -1.0]), [1.0, 2.0, 5.0]))
    np.testing.assert_allclose(found, [2.0], atol=1e-12)
    assert _quartic(np.polymul([1.0, 0.0, 1.0], [1.0, 0.0, 4.0])).size == 0


def test_quartic_double_roots():
    for roots, distinct in (
        ([1.0, 1.0, 3.0, 3.0], [1.0, 3.0]),
        ([1.0, 1.0, 2.0, -1.0], [1.0, 2.0]),
        ([2.0, 2.0, 2.0, 5.0], [2.0, 5.0]),
        ([0.5, 1.0, 1.0, 4.0], [0.5, 1.0, 4.0]),
    ):
        found = _quartic(np.poly(roots))
        _check_shape(found)
        np.testing.assert_allclose(_distinct(found, 1e-3), distinct, atol=1e-5)


def test_quartic_zero_constant_term_branches():
    # d = c = 0: x^2 (x^2 - 3x + 2).
    np.testing.assert_allclose(_quartic([1.0, -3.0, 2.0, 0.0, 0.0]), [0.0, 1.0, 2.0], atol=1e-15)
    # d = c = 0 with a double root of the quadratic: x^2 (x - 1)^2.
    np.testing.assert_allclose(_quartic([1.0, -2.0, 1.0, 0.0, 0.0]), [0.0, 1.0], atol=1e-15)
    # d = a = b = 0: x (x^3 - 8).
    np.testing.assert_allclose(_quartic([1.0, 0.0, 0.0, -8.0, 0.0]), [0.0, 2.0], atol=1e-15)
    # d = 0 through the general path: x (x - 1)(x - 2)(x + 3).
    np.testing.assert_allclose(_quartic(np.poly([0.0, 1.0, 2.0, -3.0])), [0.0, 1.0, 2.0],
                               atol=1e-9)  # fmt: skip


def test_resolvent_roots_solve_the_cubic():
    rng = np.random.default_rng(SEED + 5)
    x = np.empty(3)
    counts = set()
    for _ in range(1000):
        a, b, c = rng.normal(size=3) * 3.0
        count = solve_resolvent(x, a, b, c)
        counts.add(count)
        real = np.sort(np.roots([1.0, a, b, c]))
        if count == 3:
            np.testing.assert_allclose(np.sort(x), np.sort(real.real), atol=1e-9)
        else:
            assert count == 1
            # x[0] real, x[1] +- i x[2] the complex pair (up to the sign of x[2]).
            idx = np.argmin(np.abs(real.imag))
            assert abs(x[0] - real[idx].real) < 1e-9
            pair = np.delete(real, idx)
            assert abs(x[1] - pair[0].real) < 1e-9
            assert abs(abs(x[2]) - abs(pair[0].imag)) < 1e-9
    assert counts == {1, 3}
    # A double root: (y - 1)^2 (y + 2) = y^3 - 3y + 2 reports 2, with x[1] == x[2].
    count = solve_resolvent(x, 0.0, -3.0, 2.0)
    assert count == 2
    assert x[1] == x[2]
    np.testing.assert_allclose(x, [-2.0, 1.0, 1.0], atol=1e-12)


COEFF_SETS = [
    (1.0, -10.0, 35.0, -50.0, 24.0),
    (2.5, 0.0, -1.0),
    (-3.0, 1.0e3, 1.0e-3, 7.0, -2.0, 0.5),
    (4.0,),
]


@pytest.mark.parametrize("coeffs", COEFF_SETS)
def test_poly_eval_tuple_and_array_agree_with_numpy(coeffs):
    arr = np.array(coeffs)
    for x in (-2.5, -1.0, 0.3, 1.7, 12.0):
        ref = np.polyval(arr, x)
        for p in (coeffs, arr):
            assert poly_eval(p, x) == pytest.approx(ref, rel=1e-13, abs=1e-13)
    # The reference's special cases hold exactly.
    for p in (coeffs, arr):
        assert poly_eval(p, 0.0) == coeffs[-1]
        assert poly_eval(p, 1e-17) == coeffs[-1]
        assert poly_eval(p, 1.0) == sum(coeffs[::-1])


def test_poly_eval_empty_is_zero():
    assert poly_eval(np.empty(0), 3.0) == 0.0
    assert poly_derivative_eval(np.empty(0), 3.0) == 0.0
    assert poly_derivative_eval((5.0,), 3.0) == 0.0


@pytest.mark.parametrize("coeffs", COEFF_SETS)
def test_poly_derivative(coeffs):
    arr = np.array(coeffs)
    expected = np.polyder(arr) if len(coeffs) > 1 else np.empty(0)
    for p in (coeffs, arr):
        deriv = poly_derivative(p)
        np.testing.assert_array_equal(deriv, expected)
        for x in (-2.5, 0.0, 1e-17, 0.3, 1.0, 12.0):
            # Bit for bit the evaluation of the built derivative.
            assert poly_derivative_eval(p, x) == poly_eval(deriv, x)


def test_poly_monic_derivative():
    p = (1.0, -10.0, 35.0, -50.0, 24.0)
    expected = np.polyder(p) / 4.0
    for q in (p, np.array(p)):
        np.testing.assert_array_equal(poly_monic_derivative(q), expected)
    np.testing.assert_array_equal(poly_monic_derivative((1.0, 7.0)), [1.0])


def test_shrink_interval_finds_the_bracketed_root():
    rng = np.random.default_rng(SEED + 6)
    for _ in range(500):
        r = np.sort(_separated_roots(rng, 4, 1.0))
        coeffs = np.poly(r) * rng.choice([-1.0, 1.0]) * 10.0 ** rng.uniform(-3.0, 3.0)
        k = rng.integers(4)
        lo = r[k - 1] if k > 0 else r[0] - 1.0
        hi = r[k + 1] if k < 3 else r[3] + 1.0
        # A bracket strictly between the neighbours, containing exactly root k.
        lo = r[k] - rng.uniform(0.01, 0.99) * (r[k] - lo)
        hi = r[k] + rng.uniform(0.01, 0.99) * (hi - r[k])
        for p in (coeffs, tuple(float(c) for c in coeffs)):
            found = shrink_interval(p, lo, hi)
            assert lo <= found <= hi
            assert abs(found - r[k]) < 1e-12


def test_shrink_interval_endpoints_and_orientation():
    p = (1.0, 0.0, -2.0)  # x^2 - 2: increasing on [1, 2], root sqrt(2)
    assert shrink_interval(p, 1.0, 2.0) == pytest.approx(math.sqrt(2.0), abs=1e-14)
    q = (-1.0, 0.0, 2.0)  # decreasing there
    assert shrink_interval(q, 1.0, 2.0) == pytest.approx(math.sqrt(2.0), abs=1e-14)
    # A root on an end of the bracket is returned as is.
    assert shrink_interval((1.0, -1.0), 1.0, 3.0) == 1.0
    assert shrink_interval((1.0, -3.0), 1.0, 3.0) == 3.0
    # A double root has no sign change; the result stays inside the bracket, finite.
    found = shrink_interval((1.0, -2.0, 1.0), 0.0, 3.0)
    assert 0.0 <= found <= 3.0 and math.isfinite(found)
