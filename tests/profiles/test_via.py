"""Tests of trajkit.profiles.via: cubic_via, quintic_via and cubic_spline through via points."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import support
import trajkit as tk
from support import CLOSED_FORM, COEFFICIENT


# --------------------------------------------------------------------------- helpers
def _heuristic(times: np.ndarray, positions: np.ndarray) -> np.ndarray:
    """The textbook rule, written out point by point and joint by joint (no vector tricks)."""
    n, ndof = positions.shape
    v = np.zeros((n, ndof))
    for j in range(ndof):
        for k in range(1, n - 1):
            before = (positions[k, j] - positions[k - 1, j]) / (times[k] - times[k - 1])
            after = (positions[k + 1, j] - positions[k, j]) / (times[k + 1] - times[k])
            if (before > 0 and after > 0) or (before < 0 and after < 0):
                v[k, j] = 0.5 * (before + after)
    return v


def _spline_velocities(times, positions, v0=None, vf=None):
    """Knot velocities of the C2 cubic spline, from its tridiagonal system (dense solve here).

    Clamped when v0/vf are given, natural (zero end acceleration) otherwise.
    """
    n = times.size
    h = np.diff(times)
    slopes = np.diff(positions, axis=0) / h[:, None]
    A = np.zeros((n, n))
    b = np.zeros((n, positions.shape[1]))
    for i in range(1, n - 1):
        # C2 at knot i: h_i v_{i-1} + 2 (h_{i-1} + h_i) v_i + h_{i-1} v_{i+1} = ...
        A[i, i - 1], A[i, i], A[i, i + 1] = h[i], 2 * (h[i - 1] + h[i]), h[i - 1]
        b[i] = 3 * (h[i] * slopes[i - 1] + h[i - 1] * slopes[i])
    if v0 is None:
        A[0, :2] = [2.0, 1.0]
        b[0] = 3 * slopes[0]
        A[-1, -2:] = [1.0, 2.0]
        b[-1] = 3 * slopes[-1]
    else:
        A[0, 0] = A[-1, -1] = 1.0
        b[0], b[-1] = v0, vf
    return np.linalg.solve(A, b)


def _assert_through(tr: tk.Trajectory, times: np.ndarray, values: np.ndarray, order: int):
    """Both pieces meeting at every via point take the given value there (each at its end)."""
    c = tr.coefficients
    m = times.size - 1
    for i in range(m + 1):
        for piece in {max(i - 1, 0), min(i, m - 1)}:
            got = support._piece_derivative(c[:, piece], order, times[i] - times[piece])
            support.assert_state(got, values[i])


# No subnormals: they carry fewer significant bits than CLOSED_FORM asks for.
position_values = st.one_of(st.just(0.0), st.floats(-10.0, 10.0, allow_subnormal=False))
velocity_arrays = st.one_of(st.just(0.0), st.floats(-5.0, 5.0, allow_subnormal=False))


@st.composite
def via_problems(draw: st.DrawFn, min_points: int = 2, max_points: int = 7):
    n = draw(st.integers(min_points, max_points))
    ndof = draw(st.integers(1, 3))
    start = draw(st.floats(-5.0, 5.0))
    steps = draw(hnp.arrays(np.float64, (n - 1,), elements=st.floats(0.1, 3.0)))
    times = start + np.concatenate([[0.0], np.cumsum(steps)])
    if np.any(np.diff(times) <= 0.05):  # rounding of start + cumsum
        times = start + np.arange(n, dtype=float)
    positions = draw(hnp.arrays(np.float64, (n, ndof), elements=position_values))
    return times, positions


# ------------------------------------------------------------------------ heuristic rule
@pytest.mark.parametrize(
    ("times", "positions", "expected"),
    [
        # slopes 1, 2, -1: same sign -> mean 1.5; sign change -> 0; ends 0
        ([0, 1, 2, 3], [0, 1, 3, 2], [0, 1.5, 0, 0]),
        # a flat segment (slope 0) has no sign: zero on both sides of it
        ([0, 1, 2, 3], [0, 1, 1, 2], [0, 0, 0, 0]),
        # uneven times: slopes 0.5 and 2 -> 1.25
        ([0, 2, 3], [0, 1, 3], [0, 1.25, 0]),
        # negative slopes -1 and -2 -> -1.5
        ([0, 1, 2], [0, -1, -3], [0, -1.5, 0]),
        # monotone with a turn: slopes 1, 1, -2, -2 -> 1, 0, -2
        ([0, 1, 2, 3, 4], [0, 1, 2, 0, -2], [0, 1, 0, -2, 0]),
    ],
)
def test_heuristic_velocities_by_hand(times, positions, expected):
    tr = tk.cubic_via(times, positions)
    got = tr.velocity(np.asarray(times, float))[:, 0]
    np.testing.assert_allclose(got, expected, rtol=0, atol=COEFFICIENT)


def test_heuristic_is_per_joint():
    times = [0.0, 1.0, 2.0]
    positions = [[0.0, 0.0], [1.0, 1.0], [3.0, 0.0]]  # joint 1 monotone, joint 2 turns
    tr = tk.cubic_via(times, positions)
    np.testing.assert_allclose(tr.velocity(1.0), [1.5, 0.0], atol=COEFFICIENT)


def test_two_points_is_a_rest_to_rest_cubic():
    tr = tk.cubic_via([1.0, 3.5], [0.2, -0.7])
    reference = tk.cubic(0.2, -0.7, 2.5)
    np.testing.assert_array_equal(tr.breakpoints, [1.0, 3.5])
    np.testing.assert_allclose(tr.coefficients, reference.coefficients, atol=COEFFICIENT)


# ----------------------------------------------------------------------------- cubic_via
@given(problem=via_problems())
def test_cubic_via_properties(problem):
    times, positions = problem
    tr = tk.cubic_via(times, positions)
    ndof = positions.shape[1]
    assert tr.ndof == ndof
    assert tr.degree == 3
    assert tr.info["planner"] == "cubic_via"
    np.testing.assert_array_equal(tr.breakpoints, times)
    _assert_through(tr, times, positions, 0)
    _assert_through(tr, times, _heuristic(times, positions), 1)
    support.assert_continuous(tr, 1)
    support.assert_state(tr.position(times), positions)


@given(problem=via_problems(), data=st.data())
def test_cubic_via_honours_given_velocities(problem, data):
    times, positions = problem
    velocities = data.draw(hnp.arrays(np.float64, positions.shape, elements=velocity_arrays))
    if positions.shape[1] == 1:  # one joint: the documented (n,) form of both arguments
        tr = tk.cubic_via(times, positions[:, 0], velocities[:, 0])
    else:
        tr = tk.cubic_via(times, positions, velocities)
    _assert_through(tr, times, positions, 0)
    _assert_through(tr, times, velocities, 1)
    support.assert_continuous(tr, 1)


def test_cubic_via_acceleration_may_jump():
    tr = tk.cubic_via([0, 1, 2], [0, 1, 0], [0, 1, 0])
    left = support._piece_derivative(tr.coefficients[:, 0], 2, 1.0)
    right = support._piece_derivative(tr.coefficients[:, 1], 2, 0.0)
    # Craig's a2 = 3D/T^2 - (2 v0 + vf)/T, a3 = -2D/T^3 + (v0 + vf)/T^2, T = 1:
    # piece 1 (D=1, v0=0, vf=1): a2 = 2, a3 = -1 -> q''(1) = 2 a2 + 6 a3 = -2;
    # piece 2 (D=-1, v0=1, vf=0): a2 = -5 -> q''(1+) = 2 a2 = -10.
    np.testing.assert_allclose([left[0], right[0]], [-2.0, -10.0], atol=COEFFICIENT)


# --------------------------------------------------------------------------- quintic_via
@given(problem=via_problems())
def test_quintic_via_properties(problem):
    times, positions = problem
    tr = tk.quintic_via(times, positions)
    assert tr.degree == 5
    assert tr.info["planner"] == "quintic_via"
    np.testing.assert_array_equal(tr.breakpoints, times)
    v = _heuristic(times, positions)
    a = np.zeros_like(positions)
    for k in range(1, times.size - 1):
        a[k] = (v[k + 1] - v[k - 1]) / (times[k + 1] - times[k - 1])
    _assert_through(tr, times, positions, 0)
    _assert_through(tr, times, v, 1)
    _assert_through(tr, times, a, 2)
    support.assert_continuous(tr, 2)


def test_quintic_via_default_accelerations_by_hand():
    # v = [0, 1.5, 0, 0] (see the heuristic examples); a1 = (0 - 0)/2 = 0,
    # a2 = (0 - 1.5)/(3 - 1) = -0.75.
    tr = tk.quintic_via([0, 1, 2, 3], [0, 1, 3, 2])
    np.testing.assert_allclose(
        tr.acceleration(np.array([0.0, 1.0, 2.0, 3.0]))[:, 0], [0, 0, -0.75, 0], atol=1e-12
    )


@given(problem=via_problems(), data=st.data())
def test_quintic_via_honours_given_velocities_and_accelerations(problem, data):
    times, positions = problem
    velocities = data.draw(hnp.arrays(np.float64, positions.shape, elements=velocity_arrays))
    accelerations = data.draw(hnp.arrays(np.float64, positions.shape, elements=velocity_arrays))
    tr = tk.quintic_via(times, positions, velocities, accelerations)
    _assert_through(tr, times, positions, 0)
    _assert_through(tr, times, velocities, 1)
    _assert_through(tr, times, accelerations, 2)
    support.assert_continuous(tr, 2)


def test_quintic_via_two_points_is_quintic():
    tr = tk.quintic_via([0.0, 2.0], [[1.0, 0.0], [-1.0, 2.0]])
    reference = tk.quintic([1.0, 0.0], [-1.0, 2.0], 2.0)
    np.testing.assert_allclose(tr.coefficients, reference.coefficients, atol=COEFFICIENT)


# --------------------------------------------------------------------------- cubic_spline
@given(problem=via_problems(), data=st.data())
def test_clamped_spline_properties(problem, data):
    times, positions = problem
    ndof = positions.shape[1]
    v0 = data.draw(st.one_of(velocity_arrays, support.joint_arrays(ndof, velocity_arrays)))
    vf = data.draw(st.one_of(velocity_arrays, support.joint_arrays(ndof, velocity_arrays)))
    tr = tk.cubic_spline(times, positions, v0=v0, vf=vf)
    assert tr.degree == 3
    assert tr.info["planner"] == "cubic_spline"
    assert tr.info["bc"] == "clamped"
    np.testing.assert_array_equal(tr.breakpoints, times)
    _assert_through(tr, times, positions, 0)
    support.assert_continuous(tr, 2)
    support.assert_state(tr.velocity(times[0]), np.broadcast_to(v0, (ndof,)))
    support.assert_state(tr.velocity(times[-1]), np.broadcast_to(vf, (ndof,)))
    expected = _spline_velocities(
        times, positions, np.broadcast_to(v0, (ndof,)), np.broadcast_to(vf, (ndof,))
    )
    _assert_through(tr, times, expected, 1)


@given(problem=via_problems())
def test_natural_spline_properties(problem):
    times, positions = problem
    tr = tk.cubic_spline(times, positions, bc="natural")
    assert tr.info["bc"] == "natural"
    _assert_through(tr, times, positions, 0)
    support.assert_continuous(tr, 2)
    ndof = positions.shape[1]
    # Zero end accelerations, relative to the accelerations' own size |q| / h**2.
    scale = max(1.0, np.abs(positions).max() / np.diff(times).min() ** 2)
    for t in (times[0], times[-1]):
        assert np.all(np.abs(tr.acceleration(t)) <= CLOSED_FORM * scale), t
    _assert_through(tr, times, _spline_velocities(times, positions), 1)
    assert tr.acceleration(times[0]).shape == (ndof,)


def test_clamped_spline_default_is_at_rest():
    tr = tk.cubic_spline([0, 1, 3], [0, 1, 0.5])
    np.testing.assert_allclose(tr.velocity(np.array([0.0, 3.0])), 0.0, atol=COEFFICIENT)


def test_clamped_spline_by_hand():
    # Knots 0, 1, 2 at 0, 1, 0, clamped at rest: C2 at t=1 gives 1*0 + 4 v1 + 1*0 = 3(1 - 1)
    # -> v1 = 0; piece 1 is then 3t^2 - 2t^3, so q''(1) = 6 - 12 = -6 from both sides.
    tr = tk.cubic_spline([0, 1, 2], [0, 1, 0])
    assert tr.velocity(1.0)[0] == pytest.approx(0.0, abs=COEFFICIENT)
    assert tr.acceleration(1.0)[0] == pytest.approx(-6.0, abs=COEFFICIENT)
    np.testing.assert_allclose(tr.coefficients[:, 0, 0], [-2.0, 3.0, 0.0, 0.0], atol=COEFFICIENT)


def test_two_point_clamped_spline_is_a_cubic():
    tr = tk.cubic_spline([0.5, 2.5], [[0.0, 1.0], [1.0, -1.0]], v0=[0.5, 0.0], vf=-0.25)
    reference = tk.cubic([0.0, 1.0], [1.0, -1.0], 2.0, v0=[0.5, 0.0], vf=-0.25)
    np.testing.assert_allclose(tr.coefficients, reference.coefficients, atol=COEFFICIENT)


def test_two_point_natural_spline_is_a_line():
    tr = tk.cubic_spline([0.0, 2.0], [1.0, 2.0], bc="natural")
    np.testing.assert_allclose(tr.velocity(np.linspace(0, 2, 5))[:, 0], 0.5, atol=COEFFICIENT)


# ------------------------------------------------------------------------------- errors
VIA_PLANNERS = {
    "cubic_via": tk.cubic_via,
    "quintic_via": tk.quintic_via,
    "cubic_spline": tk.cubic_spline,
}


@pytest.mark.parametrize("planner", list(VIA_PLANNERS))
@pytest.mark.parametrize(
    ("times", "positions", "pattern"),
    [
        ([0, 1, 1], [0, 1, 2], r"times must be strictly increasing.*times\[1\]=1 s.*repeated"),
        ([0, 2, 1], [0, 1, 2], r"times must be strictly increasing.*decreasing"),
        ([0, 1, 2], [0, 1], r"positions must have shape \(3,\) or \(3, ndof\).*got shape \(2,\)"),
        ([0, 1], [[0, 1, 2], [1, 2, 3], [2, 3, 4]], r"positions must have shape \(2,\)"),
        ([0, 1], [[[0.0]], [[1.0]]], r"positions must have shape"),
        ([0], [0], r"times needs at least 2 times, got 1"),
        ([0, np.nan], [0, 1], r"times must be finite"),
        ([0, 1, 2], [0, np.inf, 1], r"positions must be finite"),
        ([[0, 1]], [0, 1], r"times must be a 1-D sequence"),
    ],
)
def test_via_bad_points(planner, times, positions, pattern):
    with pytest.raises(tk.InvalidInputError, match=pattern):
        VIA_PLANNERS[planner](times, positions)


@pytest.mark.parametrize("planner", ["cubic_via", "quintic_via"])
def test_velocities_shape_must_match(planner):
    with pytest.raises(tk.InvalidInputError, match=r"velocities must have the shape of pos"):
        VIA_PLANNERS[planner]([0, 1, 2], [0, 1, 2], [0, 1])
    with pytest.raises(tk.InvalidInputError, match=r"velocities must have the shape .*\(3, 2\)"):
        VIA_PLANNERS[planner]([0, 1, 2], [[0, 1], [1, 2], [2, 3]], [0, 1, 2])
    with pytest.raises(tk.InvalidInputError, match=r"velocities must be finite"):
        VIA_PLANNERS[planner]([0, 1, 2], [0, 1, 2], [0, np.nan, 2])


def test_accelerations_shape_must_match():
    with pytest.raises(tk.InvalidInputError, match=r"accelerations must have the shape"):
        tk.quintic_via([0, 1, 2], [0, 1, 2], accelerations=[0, 1])


def test_spline_boundary_errors():
    with pytest.raises(tk.InvalidInputError, match=r"bc must be 'clamped' or 'natural'"):
        tk.cubic_spline([0, 1, 2], [0, 1, 2], bc="periodic")
    with pytest.raises(tk.InvalidInputError, match=r"bc='natural'.*use bc='clamped' to give"):
        tk.cubic_spline([0, 1, 2], [0, 1, 2], v0=1.0, bc="natural")
    with pytest.raises(tk.InvalidInputError, match=r"bc='natural'"):
        tk.cubic_spline([0, 1, 2], [[0, 0], [1, 1], [2, 2]], vf=[0.0, -0.5], bc="natural")
    with pytest.raises(tk.InvalidInputError, match=r"v0 must be a number or 2 numbers"):
        tk.cubic_spline([0, 1, 2], [[0, 1], [1, 2], [2, 3]], v0=[1, 2, 3])
    with pytest.raises(tk.InvalidInputError, match=r"vf must be finite"):
        tk.cubic_spline([0, 1, 2], [0, 1, 2], vf=np.nan)
