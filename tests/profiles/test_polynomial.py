"""Tests of trajkit.profiles.polynomial: cubic, quintic, septic and the general A a = b solver."""

from __future__ import annotations

from fractions import Fraction
from math import factorial, sqrt

import numpy as np
import numpy.polynomial.polynomial as npoly
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

import support
import trajkit as tk
from support import CLOSED_FORM, COEFFICIENT

# ----------------------------------------------------------------------------- planners
# name -> (function, number of boundary derivatives matched at each end)
PLANNERS = {"cubic": (tk.cubic, 2), "quintic": (tk.quintic, 3), "septic": (tk.septic, 4)}
START_NAMES = ("q0", "v0", "a0", "j0")
END_NAMES = ("qf", "vf", "af", "jf")
LIMIT_NAMES = ("vmax", "amax", "jmax")


def _unit_rest_move(derivatives: int) -> np.ndarray:
    """Ascending coefficients of the rest-to-rest unit move on [0, 1], solved in fractions.

    Independent of trajkit: the 2n x 2n Hermite system is solved here by exact Gauss-Jordan
    elimination in Python fractions.
    """
    n = derivatives
    size = 2 * n
    rows = []
    for side, u in ((0, 0), (1, 1)):
        for r in range(n):
            row = []
            for p in range(size):
                if p < r:
                    row.append(Fraction(0))
                else:
                    row.append(Fraction(factorial(p) // factorial(p - r)) * Fraction(u) ** (p - r))
            rows.append([*row, Fraction(1 if side == 1 and r == 0 else 0)])
    for col in range(size):
        pivot = next(i for i in range(col, size) if rows[i][col] != 0)
        rows[col], rows[pivot] = rows[pivot], rows[col]
        rows[col] = [x / rows[col][col] for x in rows[col]]
        for i in range(size):
            if i != col and rows[i][col] != 0:
                f = rows[i][col]
                rows[i] = [a - f * b for a, b in zip(rows[i], rows[col], strict=True)]
    return np.array([float(row[-1]) for row in rows])


def _peak_on_unit(coefficients: np.ndarray, order: int) -> float:
    """max |s^(order)(u)| over [0, 1] from the roots of the next derivative (numpy.polynomial)."""
    d = npoly.polyder(coefficients, order)
    candidates = [0.0, 1.0]
    for root in npoly.polyroots(npoly.polyder(d)):
        if abs(root.imag) < 1e-12 and 0.0 <= root.real <= 1.0:
            candidates.append(root.real)
    return float(max(abs(npoly.polyval(u, d)) for u in candidates))


SEPTIC_UNIT = _unit_rest_move(4)
# Peak |s^(r)| of the unit rest-to-rest move for r = 1 (velocity), 2 (acceleration), 3 (jerk).
UNIT_PEAKS = {
    "cubic": (1.5, 6.0, 12.0),
    "quintic": (15.0 / 8.0, 10.0 / sqrt(3.0), 60.0),
    "septic": (35.0 / 16.0, _peak_on_unit(SEPTIC_UNIT, 2), _peak_on_unit(SEPTIC_UNIT, 3)),
}


def test_independent_unit_moves_are_the_textbook_ones():
    # Guards the oracle above: s(u) = 3u^2 - 2u^3, 10u^3 - 15u^4 + 6u^5, 35u^4 - 84u^5 + ...
    np.testing.assert_allclose(_unit_rest_move(2), [0, 0, 3, -2], atol=COEFFICIENT)
    np.testing.assert_allclose(_unit_rest_move(3), [0, 0, 0, 10, -15, 6], atol=COEFFICIENT)
    np.testing.assert_allclose(SEPTIC_UNIT, [0, 0, 0, 0, 35, -84, 70, -20], atol=COEFFICIENT)
    assert _peak_on_unit(_unit_rest_move(2), 1) == pytest.approx(1.5, rel=1e-14)
    assert _peak_on_unit(_unit_rest_move(3), 2) == pytest.approx(10 / sqrt(3), rel=1e-13)
    assert _peak_on_unit(SEPTIC_UNIT, 1) == pytest.approx(35 / 16, rel=1e-13)
    # The septic's acceleration peak 84 sqrt(5)/25 at u = 1/2 - sqrt(5)/10, by hand:
    # s'' = 420 u^2 (1 - u)^2 (1 - 2u), s''' = 840 u (1 - u) (5u^2 - 5u + 1).
    assert UNIT_PEAKS["septic"][1] == pytest.approx(84 * sqrt(5) / 25, rel=1e-12)
    # Jerk: s'''' = 840 (1 - 2u)(10u^2 - 10u + 1); |s'''| is 52.5 at u = 1/2 (and 42 at
    # u = 1/2 +- sqrt(15)/10), so the peak is 52.5.
    assert UNIT_PEAKS["septic"][2] == pytest.approx(52.5, rel=1e-12)


# ----------------------------------------------------------------------------- helpers
def _assert_boundary(
    trajectory: tk.Trajectory, start: np.ndarray, end: np.ndarray, duration: float
) -> None:
    """Every given derivative matches at both ends to CLOSED_FORM.

    The error of a closed form is relative to the size of the terms it adds up: order r at
    either end combines every boundary value b_k times duration**(k - r), so the scale is
    the largest of those (and 1). For moderate data this is max(1, |expected|).
    """
    n = start.shape[0]
    powers = duration ** (np.arange(n) - np.arange(n)[:, None])  # [r, k] = T**(k - r)
    magnitudes = np.maximum(np.abs(start), np.abs(end))  # (n, ndof)
    for r in range(n):
        scale = np.maximum(1.0, (magnitudes * powers[r][:, None]).max(axis=0))
        for t, expected in ((0.0, start[r]), (duration, end[r])):
            actual = trajectory.evaluate(t, r)
            error = np.abs(actual - expected) / scale
            assert np.all(error <= CLOSED_FORM), (
                f"order {r} at t={t}: {actual} vs {expected} (scaled error {error.max():.3g})"
            )


def _scalar_or_array(ndof: int, elements: st.SearchStrategy[float]) -> st.SearchStrategy:
    return st.one_of(elements, support.joint_arrays(ndof, elements))


# Numbers near the subnormal range (|x| < 2.2e-308, reached by x / T**3 from |x| ~ 1e-302)
# carry fewer significant bits than CLOSED_FORM asks for; they say nothing about trajkit,
# so the strategies here draw exact zeros or magnitudes >= 1e-200.
positions = st.one_of(st.just(0.0), st.floats(1e-200, 10.0), st.floats(-10.0, -1e-200))
velocities = positions


@st.composite
def boundary_problems(draw: st.DrawFn, derivatives: int):
    """Keyword arguments (scalars and per-joint arrays mixed) and the broadcast arrays."""
    ndof = draw(support.ndofs)
    names = START_NAMES[:derivatives] + END_NAMES[:derivatives]
    kwargs = {}
    for name in names:
        elements = positions if name in ("q0", "qf") else velocities
        kwargs[name] = draw(_scalar_or_array(ndof, elements))
    out_ndof = ndof if any(np.ndim(v) == 1 for v in kwargs.values()) else 1
    start = np.array([np.broadcast_to(kwargs[n], (out_ndof,)) for n in names[:derivatives]])
    end = np.array([np.broadcast_to(kwargs[n], (out_ndof,)) for n in names[derivatives:]])
    return kwargs, start, end


def _call(planner: str, kwargs: dict, duration=None, **limits) -> tk.Trajectory:
    function = PLANNERS[planner][0]
    kwargs = dict(kwargs)
    q0, qf = kwargs.pop("q0"), kwargs.pop("qf")
    return function(q0, qf, duration, **kwargs, **limits)


# ----------------------------------------------------------------------- boundary values
@pytest.mark.parametrize("planner", list(PLANNERS))
@given(data=st.data(), duration=support.durations)
def test_boundary_conditions_hold_at_both_ends(planner, data, duration):
    derivatives = PLANNERS[planner][1]
    kwargs, start, end = data.draw(boundary_problems(derivatives))
    tr = _call(planner, kwargs, duration)
    assert tr.ndof == start.shape[1]
    assert tr.degree == 2 * derivatives - 1
    assert tr.start_time == 0.0
    assert tr.duration == duration
    np.testing.assert_array_equal(tr.breakpoints, [0.0, duration])
    assert tr.info["duration"] == duration
    _assert_boundary(tr, start, end, duration)


@pytest.mark.parametrize(("planner", "degree"), [("cubic", 3), ("quintic", 5), ("septic", 7)])
def test_degree_and_shape(planner, degree):
    tr = _call(planner, {"q0": [0.0, 1.0, 2.0], "qf": 1.0}, 2.0)
    assert tr.degree == degree
    assert tr.coefficients.shape == (degree + 1, 1, 3)
    assert tr.position(1.0).shape == (3,)
    assert tr.position(np.linspace(0, 2, 7)).shape == (7, 3)
    assert tr.info["planner"] == planner


@given(
    q0=positions,
    qf=positions,
    v0=velocities,
    vf=velocities,
    T=support.durations,
    u=st.floats(0.0, 1.0),
)
def test_cubic_matches_textbook_coefficients_inside(q0, qf, v0, vf, T, u):
    # Craig (7.11): a2 = 3D/T^2 - 2v0/T - vf/T, a3 = -2D/T^3 + (v0 + vf)/T^2.
    D = qf - q0
    a = [q0, v0, 3 * D / T**2 - (2 * v0 + vf) / T, -2 * D / T**3 + (v0 + vf) / T**2]
    tr = tk.cubic(q0, qf, T, v0=v0, vf=vf)
    t = u * T
    scale = max(1.0, abs(q0), abs(qf), abs(v0) * T, abs(vf) * T)
    expected = npoly.polyval(t, a)
    assert abs(tr.position(t)[0] - expected) <= CLOSED_FORM * scale
    expected_v = npoly.polyval(t, npoly.polyder(a))
    assert abs(tr.velocity(t)[0] - expected_v) <= CLOSED_FORM * scale / T


@given(
    q0=positions,
    qf=positions,
    v0=velocities,
    vf=velocities,
    a0=velocities,
    af=velocities,
    T=support.durations,
    u=st.floats(0.0, 1.0),
)
def test_quintic_matches_textbook_coefficients_inside(q0, qf, v0, vf, a0, af, T, u):
    # Biagiotti & Melchiorri (2.5), written here in full.
    D = qf - q0
    a = [
        q0,
        v0,
        a0 / 2,
        (20 * D - (8 * vf + 12 * v0) * T - (3 * a0 - af) * T**2) / (2 * T**3),
        (-30 * D + (14 * vf + 16 * v0) * T + (3 * a0 - 2 * af) * T**2) / (2 * T**4),
        (12 * D - 6 * (vf + v0) * T + (af - a0) * T**2) / (2 * T**5),
    ]
    tr = tk.quintic(q0, qf, T, v0=v0, vf=vf, a0=a0, af=af)
    t = u * T
    scale = max(1.0, abs(q0), abs(qf), abs(v0) * T, abs(vf) * T, abs(a0) * T**2, abs(af) * T**2)
    assert abs(tr.position(t)[0] - npoly.polyval(t, a)) <= CLOSED_FORM * scale


def test_hold_when_start_equals_end_with_a_duration():
    tr = tk.quintic([0.3, -1.0], [0.3, -1.0], 2.0)
    t = np.linspace(0, 2, 11)
    # Holding still, up to the rounding of the Hermite combination.
    support.assert_state(tr.position(t), np.tile([0.3, -1.0], (11, 1)), rtol=support.ROUNDING)
    support.assert_state(tr.velocity(t), np.zeros((11, 2)), rtol=support.ROUNDING)


# -------------------------------------------------------------- rest-to-rest peaks / minimum
@pytest.mark.parametrize("planner", list(PLANNERS))
@given(q0=positions, qf=positions, T=support.durations)
def test_rest_to_rest_peaks_are_closed_form(planner, q0, qf, T):
    D = abs(qf - q0)
    tr = _call(planner, {"q0": q0, "qf": qf}, T)
    for r, unit_peak in enumerate(UNIT_PEAKS[planner], start=1):
        peak = tr.extrema(r).peak[0]
        expected = unit_peak * D / T**r
        # Relative to the terms combined: |q0|, |qf| over T**r (matters when D is ~0).
        scale = max(expected, max(abs(q0), abs(qf)) / T**r)
        assert abs(peak - expected) <= CLOSED_FORM * scale, (r, peak, expected)


def _expected_minimum(planner: str, D: np.ndarray, limits: dict) -> tuple[np.ndarray, dict]:
    """Per-joint minimum durations and the per-limit minima, from the closed form."""
    per_limit = {}
    for r, name in enumerate(LIMIT_NAMES, start=1):
        if name in limits:
            peak = UNIT_PEAKS[planner][r - 1]
            per_limit[name] = (peak * D / np.broadcast_to(limits[name], D.shape)) ** (1.0 / r)
    own = np.max(np.array(list(per_limit.values())), axis=0)
    return own, per_limit


@pytest.mark.parametrize("planner", list(PLANNERS))
@pytest.mark.parametrize("name", LIMIT_NAMES)
def test_single_joint_minimum_duration_is_closed_form(planner, name):
    r = LIMIT_NAMES.index(name) + 1
    limit = 0.7
    tr = _call(planner, {"q0": -0.4, "qf": 1.1}, **{name: limit})
    expected = (UNIT_PEAKS[planner][r - 1] * 1.5 / limit) ** (1.0 / r)
    assert tr.duration == pytest.approx(expected, rel=CLOSED_FORM)
    assert tr.info["limiting"] == name
    assert tr.info["limiting_joint"] == 0
    assert tr.info["minimum_durations"] == pytest.approx((expected,), rel=CLOSED_FORM)
    assert tr.extrema(r).peak[0] / limit == pytest.approx(1.0, abs=1e-9)


def test_cubic_velocity_limited_minimum_is_one_and_a_half_distance_over_vmax():
    tr = tk.cubic(0.0, 2.0, vmax=0.5)
    assert tr.duration == pytest.approx(1.5 * 2.0 / 0.5, rel=CLOSED_FORM)
    assert tr.extrema(1).maximum[0] == pytest.approx(0.5, rel=CLOSED_FORM)
    assert tr.extrema(1).time_of_maximum[0] == pytest.approx(3.0, rel=CLOSED_FORM)


@st.composite
def synchronized_problems(draw: st.DrawFn):
    ndof = draw(support.ndofs)
    q0 = draw(_scalar_or_array(ndof, positions))
    qf = draw(support.joint_arrays(ndof, positions))
    names = draw(st.sets(st.sampled_from(LIMIT_NAMES), min_size=1))
    limits = {n: draw(_scalar_or_array(ndof, support.limits_positive)) for n in sorted(names)}
    return q0, qf, limits


@pytest.mark.parametrize("planner", list(PLANNERS))
@given(problem=synchronized_problems())
def test_synchronized_minimum_duration(planner, problem):
    q0, qf, limits = problem
    D = np.abs(np.asarray(qf) - np.asarray(q0))
    assume(np.any(D > 1e-6))
    tr = _call(planner, {"q0": q0, "qf": qf}, **limits)
    own, per_limit = _expected_minimum(planner, D, limits)

    # The common duration is the slowest joint's own minimum.
    assert tr.duration == pytest.approx(own.max(), rel=CLOSED_FORM)
    np.testing.assert_allclose(tr.info["minimum_durations"], own, rtol=CLOSED_FORM, atol=0)
    joint = tr.info["limiting_joint"]
    limiting = tr.info["limiting"]
    assert own[joint] == pytest.approx(own.max(), rel=CLOSED_FORM)
    assert per_limit[limiting][joint] == pytest.approx(own[joint], rel=CLOSED_FORM)

    # The move respects every limit, exactly, and the limiting one is touched.
    check_limits = tk.Limits(
        velocity=limits.get("vmax"), acceleration=limits.get("amax"), jerk=limits.get("jmax")
    )
    report = tr.check(check_limits)
    assert report.ok, str(report)
    r = LIMIT_NAMES.index(limiting) + 1
    bound = np.broadcast_to(limits[limiting], (tr.ndof,))[joint]
    assert tr.extrema(r).peak[joint] / bound == pytest.approx(1.0, abs=1e-9)


def test_synchronized_two_joints_by_hand():
    # Joint 1: D=2, vmax=1 -> 3 s (cubic); joint 2: D=1, amax=0.5 -> sqrt(6*1/0.5)=3.4641 s.
    tr = tk.cubic([0.0, 0.0], [2.0, -1.0], vmax=[1.0, 10.0], amax=[100.0, 0.5])
    assert tr.duration == pytest.approx(sqrt(12.0), rel=CLOSED_FORM)
    assert tr.info["limiting_joint"] == 1
    assert tr.info["limiting"] == "amax"
    assert tr.info["minimum_durations"] == pytest.approx((3.0, sqrt(12.0)), rel=CLOSED_FORM)
    assert tr.extrema(2).peak[1] == pytest.approx(0.5, rel=CLOSED_FORM)
    assert tr.extrema(1).peak[0] < 1.0  # joint 1 is slowed down below its limit


# ------------------------------------------------------------ non-zero boundary velocities
@st.composite
def moving_boundary_problems(draw: st.DrawFn, derivatives: int):
    ndof = draw(st.integers(1, 3))
    vmax = draw(support.joint_arrays(ndof, st.floats(0.1, 10.0)))
    # |v| <= 0.8 vmax: beyond vmax/1.1875 a septic with D = 0 overshoots vmax at every
    # duration, which is a true infeasibility and not what this test is about.
    # Fractions are 0 or at least 1 %: a subnormal v0 is the unbounded case again.
    fraction = st.one_of(st.just(0.0), st.floats(0.01, 0.8), st.floats(-0.8, -0.01))
    v0 = draw(support.joint_arrays(ndof, fraction)) * vmax
    vf = draw(support.joint_arrays(ndof, fraction)) * vmax
    q0 = draw(support.joint_arrays(ndof, positions))
    qf = draw(support.joint_arrays(ndof, positions))
    limits = {"vmax": vmax}
    if draw(st.booleans()):
        limits["amax"] = draw(support.joint_arrays(ndof, st.floats(0.1, 10.0)))
    assume(np.any(v0) or np.any(vf))
    # Every joint needs time on its own: it moves (|D| > 1e-3; a distance of 1e-300 is
    # degenerate), or amax meets its non-zero boundary velocity. A joint with D = 0 under
    # vmax alone keeps the same velocity shape at every duration, so its own minimum is
    # unbounded (test_unbounded_minimum_duration_is_refused); when another joint bounds
    # the common duration, trajkit still refuses the move: a bug, pinned by
    # test_a_joint_that_needs_no_time_does_not_block_the_others.
    moving = np.abs(qf - q0) > 1e-3
    braked = ("amax" in limits) & ((v0 != 0) | (vf != 0))
    assume(np.all(moving | braked))
    # A joint that does not move is put at 0: at q0 = qf != 0 a small boundary velocity is
    # lost to rounding at tiny trial durations, a bug pinned by
    # test_minimum_duration_does_not_depend_on_where_the_joint_is.
    q0 = np.where(moving, q0, 0.0)
    qf = np.where(moving, qf, 0.0)
    return {"q0": q0, "qf": qf, "v0": v0, "vf": vf}, limits


@pytest.mark.parametrize("planner", list(PLANNERS))
@given(data=st.data())
def test_minimum_duration_with_boundary_velocities(planner, data):
    kwargs, limits = data.draw(moving_boundary_problems(PLANNERS[planner][1]))
    tr = _call(planner, kwargs, **limits)
    T = tr.duration
    check_limits = tk.Limits(velocity=limits["vmax"], acceleration=limits.get("amax"))
    report = tr.check(check_limits)
    assert report.ok, str(report)
    support.assert_state(tr.velocity(0.0), kwargs["v0"])
    support.assert_state(tr.velocity(T), kwargs["vf"])
    # The duration is minimal: a limit is touched, and a little faster breaks one.
    ratios = [tr.extrema(1).peak / limits["vmax"]]
    if "amax" in limits:
        ratios.append(tr.extrema(2).peak / limits["amax"])
    assert np.max(ratios) == pytest.approx(1.0, abs=1e-9)
    # The same duration given explicitly is accepted; 0.1 % less is refused.
    _call(planner, kwargs, T, **limits)
    with pytest.raises(tk.InfeasibleError, match="duration"):
        _call(planner, kwargs, 0.999 * T, **limits)


def test_minimum_duration_is_not_beaten_by_a_feasible_shorter_duration():
    # v0 = vf = D / T at T = 1 s makes the cubic a straight line: acceleration 0 <= amax,
    # but only in a narrow window of durations around 1 s (|a(0)| = 6 |D - v T| / T^2), and
    # 1.5 v^2 / D = 1.5 > amax in between that window and the slow moves. (Until 8d95155 the
    # duration scan missed the window and returned 599 s.)
    line = tk.cubic(0.0, 1.0, 1.0, v0=1.0, vf=1.0, amax=0.01)
    assert line.check(tk.Limits(acceleration=0.01)).ok
    fastest = tk.cubic(0.0, 1.0, v0=1.0, vf=1.0, amax=0.01)
    assert fastest.duration <= 1.0
    # The window's lower end solves 6 (v T - D) = -amax T^2 (a(0) = +amax, T < 1).
    amax = 0.01
    lower = (-6.0 + sqrt(36.0 + 24.0 * amax)) / (2.0 * amax)
    assert fastest.duration == pytest.approx(lower, rel=CLOSED_FORM)
    assert fastest.check(tk.Limits(acceleration=amax)).ok
    assert fastest.info["minimum_durations"] == pytest.approx((lower,), rel=CLOSED_FORM)


def test_limiting_names_a_given_limit():
    # Every peak ratio is 0 (nothing moves); the limit named must still be one that was
    # given. (Until 8d95155 it was argmax of zeros -> "vmax".)
    tr = tk.cubic(0.0, 0.0, 2.0, amax=1.0)
    assert tr.info["limiting"] == "amax"
    tr = tk.quintic([0.0, 0.0], [0.0, 1.0], 10.0, jmax=[1.0, 2.0])
    assert tr.info["limiting"] == "jmax"
    assert tr.info["limiting_joint"] == 1


def test_unbounded_minimum_duration_is_refused():
    # q0 == qf and only vmax: the velocity profile v0 * h'(t / T) is the same for every T,
    # so every T > 0 is feasible and there is no shortest one. The infimum 0 cannot be
    # taken either (unlike the standstill at rest): the velocity would jump 0.5 -> 0.
    # (Until 8d95155 this returned a 1e-12 s move with acceleration ~1e12 rad/s^2.)
    with pytest.raises(tk.InfeasibleError, match="do not bound the duration") as raised:
        tk.cubic(0.0, 0.0, v0=0.5, vmax=1.0)
    assert "give a duration" in str(raised.value)


@pytest.mark.parametrize("still_v0", [0.0, 0.5], ids=["standing-still", "unbounded-alone"])
def test_a_joint_that_needs_no_time_does_not_block_the_others(still_v0):
    alone = tk.cubic(0.0, 1.0, v0=0.5, vmax=1.0)  # joint 2 on its own
    tr = tk.cubic([0.0, 0.0], [0.0, 1.0], v0=[still_v0, 0.5], vmax=1.0)
    assert tr.duration == pytest.approx(alone.duration, rel=CLOSED_FORM)
    assert tr.info["limiting_joint"] == 1
    assert tr.check(tk.Limits(velocity=1.0)).ok


@pytest.mark.parametrize("planner", ["cubic", "quintic"])
@pytest.mark.parametrize("where", [1.0, -3.0, 10.0])
def test_minimum_duration_does_not_depend_on_where_the_joint_is(planner, where):
    # At q0 = qf = 0 the answer is right: |a| peaks at the start, 4 v0 / T (cubic), so
    # T = 4 v0 / amax = 0.016 s. Moving the joint elsewhere must not change it.
    at_zero = _call(planner, {"q0": 0.0, "qf": 0.0, "v0": 0.004}, amax=1.0)
    if planner == "cubic":
        assert at_zero.duration == pytest.approx(0.016, rel=CLOSED_FORM)
    elsewhere = _call(planner, {"q0": where, "qf": where, "v0": 0.004}, amax=1.0)
    assert elsewhere.duration == pytest.approx(at_zero.duration, rel=CLOSED_FORM)


def test_tangential_minimum_is_exact():
    # See test_boundary_velocity_at_its_limit_is_allowed for the hand solution T = 1.5 s.
    assert tk.cubic(0.0, 1.0, v0=1.0, vmax=1.0).duration == pytest.approx(1.5, rel=CLOSED_FORM)


# ------------------------------------------------------------------------- infeasibility
@pytest.mark.parametrize("planner", list(PLANNERS))
@pytest.mark.parametrize("name", LIMIT_NAMES)
def test_duration_too_short_names_duration_minimum_and_limit(planner, name):
    r = LIMIT_NAMES.index(name) + 1
    minimum = (UNIT_PEAKS[planner][r - 1] * 2.0 / 0.5) ** (1.0 / r)
    with pytest.raises(tk.InfeasibleError) as raised:
        _call(planner, {"q0": 1.0, "qf": -1.0}, 0.9 * minimum, **{name: 0.5})
    message = str(raised.value)
    assert "duration" in message
    assert "minimum" in message
    assert f"{name}=0.5" in message
    assert f"{minimum:.6g}" in message  # the minimum it reports is the right one
    assert f"{0.9 * minimum:.6g}" in message  # and so is the duration refused
    # A duration just at the minimum is accepted.
    _call(planner, {"q0": 1.0, "qf": -1.0}, minimum, **{name: 0.5})


def test_duration_too_short_names_the_joint():
    with pytest.raises(tk.InfeasibleError, match=r"joint 2"):
        tk.cubic([0.0, 0.0], [0.1, 3.0], 1.0, vmax=1.0)


@pytest.mark.parametrize(
    ("planner", "argument", "limit", "value"),
    [
        ("cubic", "v0", "vmax", 1.5),
        ("cubic", "vf", "vmax", -1.5),
        ("quintic", "v0", "vmax", 2.0),
        ("quintic", "a0", "amax", 1.01),
        ("quintic", "af", "amax", -3.0),
        ("septic", "j0", "jmax", 1.2),
        ("septic", "jf", "jmax", -1.2),
        ("septic", "a0", "amax", 5.0),
    ],
)
def test_boundary_value_beyond_its_limit(planner, argument, limit, value):
    kwargs = {"q0": [0.0, 0.0], "qf": [1.0, 1.0], argument: [0.0, value]}
    with pytest.raises(tk.InfeasibleError) as raised:
        _call(planner, kwargs, **{"vmax": 1.0, "amax": 1.0, "jmax": 1.0})
    message = str(raised.value)
    assert message.startswith(f"{argument}={value:.6g}")
    assert f"{limit}=1" in message
    assert "joint 2" in message


def test_boundary_velocity_at_its_limit_is_allowed():
    tr = tk.cubic(0.0, 1.0, v0=1.0, vmax=1.0)
    assert tr.velocity(0.0)[0] == pytest.approx(1.0, rel=support.ROUNDING)
    assert tr.check(tk.Limits(velocity=1.0)).ok
    # By hand, with k = D / T: v(u) = 1 + (6k - 4) u + (3 - 6k) u^2 stays <= 1 on [0, 1]
    # iff k <= 2/3, so T >= 1.5 s. At T = 1.5 s the velocity leaves u = 0 with zero slope:
    # the limit is touched tangentially, the peak exceeds it only quadratically below
    # 1.5 s, so a bisection on "peak <= limit (1 + slack)" can place T only to about
    # sqrt(slack): test_tangential_minimum_is_exact asks for CLOSED_FORM.
    assert 1.5 * (1 - 1e-6) <= tr.duration <= 1.5 * (1 + CLOSED_FORM)
    with pytest.raises(tk.InfeasibleError, match="duration"):
        tk.cubic(0.0, 1.0, 1.5 * 0.999, v0=1.0, vmax=1.0)
    assert tr.check(tk.Limits(velocity=1.0)).ok


@pytest.mark.parametrize("planner", list(PLANNERS))
def test_identical_start_and_end_with_limits_only_is_a_zero_duration_standstill(planner):
    # Nothing moves and the limits ask for no time (commit edf6ad3 replaced the former
    # InfeasibleError by a zero-duration standstill).
    tr = _call(planner, {"q0": [0.5, -1.0], "qf": [0.5, -1.0]}, vmax=1.0, amax=[2.0, 3.0])
    assert tr.duration == 0.0
    np.testing.assert_array_equal(tr.breakpoints, [0.0, 0.0])
    assert tr.degree == 2 * PLANNERS[planner][1] - 1
    assert tr.info["duration"] == 0.0
    assert tr.info["minimum_durations"] == (0.0, 0.0)
    t = np.array([-1.0, 0.0, 1.0])  # clamped to the single instant
    np.testing.assert_array_equal(tr.position(t), np.tile([0.5, -1.0], (3, 1)))
    for order in (1, 2, 3):
        np.testing.assert_array_equal(tr.evaluate(t, order), np.zeros((3, 2)))
    assert tr.check(tk.Limits(velocity=1.0, acceleration=[2.0, 3.0])).ok


# ------------------------------------------------------------------------------ bad input
BAD_INPUTS = [
    ({"q0": np.nan, "qf": 1.0, "duration": 1.0}, r"^q0 must be finite"),
    ({"q0": 0.0, "qf": [1.0, np.inf], "duration": 1.0}, r"^qf must be finite"),
    ({"q0": 0.0, "qf": 1.0, "duration": 1.0, "v0": -np.inf}, r"^v0 must be finite"),
    ({"q0": 0.0, "qf": 1.0, "duration": np.nan}, r"^duration must be finite"),
    ({"q0": 0.0, "qf": 1.0, "duration": 0.0}, r"^duration must be > 0, got 0 s"),
    ({"q0": 0.0, "qf": 1.0, "duration": -2.0}, r"^duration must be > 0, got -2 s"),
    ({"q0": 0.0, "qf": 1.0, "vmax": 0.0}, r"^vmax must be > 0 .*joint 1"),
    ({"q0": 0.0, "qf": 1.0, "amax": -1.0}, r"^amax must be > 0"),
    ({"q0": [0.0, 0.0], "qf": 1.0, "jmax": [1.0, -1.0]}, r"^jmax must be > 0 .*joint 2"),
    ({"q0": [0.0, 0.0], "qf": 1.0, "vmax": np.nan}, r"^vmax must be finite"),
    ({"q0": [0.0, 1.0], "qf": [1.0, 2.0, 3.0], "duration": 1.0}, r"qf has 3 joints.*q0 has 2"),
    ({"q0": [0.0, 1.0], "qf": 1.0, "vmax": [1.0, 2.0, 3.0]}, r"vmax has 3 joints.*q0 has 2"),
    ({"q0": 0.0, "qf": 1.0, "v0": [0.0, 1.0], "duration": 1.0, "vf": [1.0]}, r"vf has 1"),
    ({"q0": [[0.0, 1.0]], "qf": 1.0, "duration": 1.0}, r"^q0 must be a number or a 1-D"),
    ({"q0": [], "qf": 1.0, "duration": 1.0}, r"^q0 must not be empty"),
    ({"q0": "a", "qf": 1.0, "duration": 1.0}, r"^q0 must be numeric"),
    ({"q0": 0.0, "qf": 1.0}, r"give duration, or at least one of vmax, amax, jmax"),
]


@pytest.mark.parametrize("planner", list(PLANNERS))
@pytest.mark.parametrize(("kwargs", "pattern"), BAD_INPUTS)
def test_bad_input_is_invalid_input_naming_the_argument(planner, kwargs, pattern):
    kwargs = dict(kwargs)
    duration = kwargs.pop("duration", None)
    with pytest.raises(tk.InvalidInputError, match=pattern) as raised:
        _call(planner, kwargs, duration)
    assert isinstance(raised.value, ValueError)
    if "give duration" in pattern:
        assert str(raised.value).startswith(f"{planner}:")


# ============================================================================ polynomial()
def _ascending(tr: tk.Trajectory) -> np.ndarray:
    """Absolute-time coefficients per piece, ascending powers: shape (m, k + 1, ndof)."""
    return np.moveaxis(tr.absolute_coefficients()[::-1], 1, 0)


SEED_004_EXAMPLE_1 = [
    [(0, 0, 0.0), (0, 1, 0.0), (1, 0, 0.5), (1, 1, 0.2)],
    [(1, 0, 0.5), (1, 1, 0.2), (3, 0, 1.0), (3, 1, 0.0)],
]
SEED_004_EXAMPLE_2 = [
    [(0, 0, 0.0), (0, 1, 0.0), (1, 0, 0.5)],
    [(1, 0, 0.5), (3, 0, 1.0), (3, 1, 0.0)],
]


def test_seed_004_example_1_coefficients():
    tr = tk.polynomial(SEED_004_EXAMPLE_1, segments=[0, 1, 3])
    a = _ascending(tr)[:, :, 0]
    np.testing.assert_allclose(a[0], [0.0, 0.0, 1.3, -0.8], rtol=0, atol=COEFFICIENT)
    np.testing.assert_allclose(a[1], [0.55, -0.375, 0.4, -0.075], rtol=0, atol=COEFFICIENT)
    assert tr.degree == 3
    assert tr.info["degrees"] == (3, 3)
    assert tr.info["equations"] == 8
    np.testing.assert_array_equal(tr.breakpoints, [0.0, 1.0, 3.0])
    # C1 at t = 1 but the acceleration jumps (the point of example 2).
    support.assert_continuous(tr, 1)
    left, right = tr.coefficients[:, 0, 0], tr.coefficients[:, 1, 0]
    assert abs(6 * left[0] * 1.0 + 2 * left[1] - 2 * right[1]) > 0.1


def _example_2_by_hand() -> np.ndarray:
    """Seed 004 example 2 as the 8 x 8 system in absolute time, a = [a10..a13, a20..a23]."""

    def p(t, order):
        row = np.zeros(4)
        for k in range(order, 4):
            row[k] = factorial(k) // factorial(k - order) * t ** (k - order)
        return row

    z = np.zeros(4)
    A = np.array(
        [
            [*p(0, 0), *z],  # q1(0) = 0
            [*p(0, 1), *z],  # q1'(0) = 0
            [*p(1, 0), *z],  # q1(1) = 0.5
            [*z, *p(1, 0)],  # q2(1) = 0.5
            [*z, *p(3, 0)],  # q2(3) = 1
            [*z, *p(3, 1)],  # q2'(3) = 0
            [*p(1, 1), *(-p(1, 1))],  # q1'(1) = q2'(1)
            [*p(1, 2), *(-p(1, 2))],  # q1''(1) = q2''(1)
        ]
    )
    b = np.array([0.0, 0.0, 0.5, 0.5, 1.0, 0.0, 0.0, 0.0])
    return np.linalg.solve(A, b)


def test_seed_004_example_2_continuous_velocity_and_acceleration():
    tr = tk.polynomial(SEED_004_EXAMPLE_2, segments=[0, 1, 3], continuity=[(1, 2)])
    expected = _example_2_by_hand()
    a = _ascending(tr)[:, :, 0]
    np.testing.assert_allclose(a.ravel(), expected, rtol=0, atol=COEFFICIENT)
    # Exact rational solution: a1 = (0, 0, 7/8, -3/8), a2 = (-13/32, 39/32, -11/32, 1/32).
    np.testing.assert_allclose(
        a.ravel(), [0, 0, 7 / 8, -3 / 8, -13 / 32, 39 / 32, -11 / 32, 1 / 32], atol=COEFFICIENT
    )
    # All eight equations, evaluated on the trajectory itself.
    for t, order, value in [(0, 0, 0), (0, 1, 0), (1, 0, 0.5), (3, 0, 1), (3, 1, 0)]:
        assert tr.evaluate(t, order)[0] == pytest.approx(value, abs=COEFFICIENT)
    left, right = tr.coefficients[:, 0, 0], tr.coefficients[:, 1, 0]
    assert right[3] == pytest.approx(0.5, abs=COEFFICIENT)  # q2(1) from the right
    support.assert_continuous(tr, 2, rtol=COEFFICIENT)
    for order in range(3):
        left_value = support._piece_derivative(left[:, None], order, 1.0)[0]
        right_value = support._piece_derivative(right[:, None], order, 0.0)[0]
        assert left_value == pytest.approx(right_value, abs=COEFFICIENT)
    # The jerk is not asked to be continuous and is not.
    assert abs(6 * left[0] - 6 * right[0]) > 0.1


def test_flat_conditions_reproduce_cubic():
    q0, qf, v0, vf, T = 0.3, -1.2, 0.5, -0.25, 2.5
    tr = tk.polynomial([(1.0, 0, q0), (1.0, 1, v0), (1.0 + T, 0, qf), (1.0 + T, 1, vf)])
    reference = tk.cubic(q0, qf, T, v0=v0, vf=vf)
    np.testing.assert_array_equal(tr.breakpoints, [1.0, 1.0 + T])
    assert tr.degree == 3
    np.testing.assert_allclose(
        tr.coefficients, reference.coefficients, rtol=CLOSED_FORM, atol=COEFFICIENT
    )


def test_vector_values():
    tr = tk.polynomial(
        [(0, 0, [0.0, 1.0, -2.0]), (0, 1, 0.0), (2, 0, [1.0, 1.0, 2.0]), (2, 1, [0.0, 0.5, 0.0])]
    )
    assert tr.ndof == 3
    support.assert_state(tr.position(0.0), [0.0, 1.0, -2.0])
    support.assert_state(tr.position(2.0), [1.0, 1.0, 2.0])
    support.assert_state(tr.velocity(0.0), [0.0, 0.0, 0.0])
    support.assert_state(tr.velocity(2.0), [0.0, 0.5, 0.0])
    reference = tk.cubic([0.0, 1.0, -2.0], [1.0, 1.0, 2.0], 2.0, vf=[0.0, 0.5, 0.0])
    np.testing.assert_allclose(tr.coefficients, reference.coefficients, atol=COEFFICIENT)


def test_linear_segment_and_given_degrees():
    # Mixed degrees: a line then a cubic with C1 at t = 1 (3 + ... equations).
    tr = tk.polynomial(
        [[(0, 0, 0.0), (1, 0, 1.0)], [(1, 0, 1.0), (2, 0, 0.0), (2, 1, 0.0)]],
        segments=[0, 1, 2],
        continuity=[(1,)],
        degrees=[1, 3],
    )
    assert tr.info["degrees"] == (1, 3)
    assert tr.degree == 3
    np.testing.assert_array_equal(tr.coefficients[:2, 0, 0], [0.0, 0.0])  # padded line
    assert tr.velocity(0.5)[0] == pytest.approx(1.0, abs=COEFFICIENT)
    support.assert_continuous(tr, 1, rtol=COEFFICIENT)
    assert tr.position(2.0)[0] == pytest.approx(0.0, abs=COEFFICIENT)
    assert tr.velocity(2.0)[0] == pytest.approx(0.0, abs=COEFFICIENT)


POLYNOMIAL_ERRORS = [
    (dict(conditions=[(0, 0, 0), (1, 0, 1)], degrees=3), r"under-determined: 2 equations.*4 unk"),
    (dict(conditions=[(0, 0, 0), (1, 0, 1), (1, 1, 0)], degrees=1), r"over-determined: 3 eq"),
    (
        dict(
            conditions=[[(0, 0, 0), (1, 0, 1), (1, 1, 0)], [(1, 0, 1), (2, 0, 0)]],
            segments=[0, 1, 2],
        ),
        r"5 equations do not divide evenly among 2 segments; pass degrees=",
    ),
    (
        dict(conditions=[(0, 0, 0), (1, 0, 1), (1, 0, 1), (0, 1, 0)]),
        r"singular.*repeat each other",
    ),
    (
        dict(conditions=[(0, 0, 0), (1, 0, 1), (1, 0, 2), (0, 1, 0)]),
        r"singular.*contradict each other",
    ),
    (
        dict(conditions=[[(0, 0, 0), (2, 0, 1)], [(1, 0, 1), (2, 0, 0)]], segments=[0, 1, 2]),
        r"\(t=2 s, order 0\) lies outside segment 0 \[0, 1\] s",
    ),
    (
        dict(conditions=[[(0, 0, 0), (1, 0, 1)], [(0.5, 0, 1), (2, 0, 0)]], segments=[0, 1, 2]),
        r"\(t=0.5 s, order 0\) lies outside segment 1 \[1, 2\] s",
    ),
    (dict(conditions=[(0, 0, 0), (1, 0)]), r"conditions\[1\] must be a \(time, order, value\)"),
    (dict(conditions=[(0, 0, 0), (1, 0, 1, 2)]), r"conditions\[1\] must be a \(time, order"),
    (dict(conditions=[(0, 0, 0), 5]), r"conditions\[1\] must be a \(time, order, value\)"),
    (dict(conditions="abc"), r"conditions must be a sequence"),
    (dict(conditions=[(0, -1, 0), (1, 0, 1)]), r"conditions\[0\] derivative order must be"),
    (dict(conditions=[(0, 0.5, 0), (1, 0, 1)]), r"conditions\[0\] derivative order must be"),
    (dict(conditions=[(0, True, 0), (1, 0, 1)]), r"conditions\[0\] derivative order must be"),
    (dict(conditions=[(np.nan, 0, 0), (1, 0, 1)]), r"conditions\[0\] time must be finite"),
    (dict(conditions=[(0, 0, 0), (1, 0, np.inf)]), r"conditions\[1\] value must be finite"),
    (dict(conditions=[(0, 0, 0), (0, 1, 1)]), r"conditions must span an interval"),
    (dict(conditions=[]), r"conditions must span an interval"),
    (
        dict(
            conditions=[[(0, 0, 0), (1, 0, 1)], [(1, 0, 1), (2, 0, 0)]],
            segments=[0, 1, 2],
            continuity=[(1,), (2,)],
        ),
        r"continuity must give one sequence .* 1 expected, got 2",
    ),
    (
        dict(
            conditions=[[(0, 0, 0), (1, 0, 1)], [(1, 0, 1), (2, 0, 0)]],
            segments=[0, 1, 2],
            continuity=[(-1,)],
        ),
        r"continuity\[0\] must hold derivative orders",
    ),
    (
        dict(
            conditions=[[(0, 0, 0), (1, 0, 1)], [(1, 0, 1), (2, 0, 0)]],
            segments=[0, 1, 2],
            continuity=[(1, 1)],
        ),
        r"continuity\[0\] repeats an order",
    ),
    (dict(conditions=[(0, 0, 0), (1, 0, 1)], degrees=-1), r"degrees must be a whole number >= 0"),
    (
        dict(
            conditions=[[(0, 0, 0), (1, 0, 1)], [(1, 0, 1), (2, 0, 0)]],
            segments=[0, 1, 2],
            degrees=[1],
        ),
        r"degrees must be .* one per segment \(2\)",
    ),
    (dict(conditions=[[(0, 0, 0), (1, 0, 1)]], segments=[0, 1, 2]), r"2 segments but 1 seq"),
    (dict(conditions=[[(0, 0, 0), (1, 0, 1)]], segments=[1, 0]), r"segments must be strictly"),
    (dict(conditions=[(0, 0, [0, 1]), (1, 0, [1, 2, 3])]), r"value 1 has 3 joints.*value 0"),
]


@pytest.mark.parametrize(("kwargs", "pattern"), POLYNOMIAL_ERRORS)
def test_polynomial_errors(kwargs, pattern):
    with pytest.raises(tk.InvalidInputError, match=pattern):
        tk.polynomial(**kwargs)


def test_under_and_over_determined_advice():
    with pytest.raises(tk.InvalidInputError, match="add conditions or lower the degrees"):
        tk.polynomial([(0, 0, 0), (1, 0, 1)], degrees=3)
    with pytest.raises(tk.InvalidInputError, match="remove conditions or raise the degrees"):
        tk.polynomial([(0, 0, 0), (1, 0, 1), (1, 1, 0)], degrees=1)


def test_singular_reports_rank():
    with pytest.raises(tk.InvalidInputError, match=r"rank 3 of 4"):
        tk.polynomial([(0, 0, 0), (1, 0, 1), (1, 0, 1), (0, 1, 0)])
    # Third derivative of a cubic twice is fine (constant); twice contradicting is not.
    with pytest.raises(tk.InvalidInputError, match="contradict"):
        tk.polynomial([(0, 0, 0), (1, 0, 1), (0, 3, 1.0), (1, 3, 2.0)])
    tr = tk.polynomial([(0, 0, 0), (1, 0, 1), (0, 3, 6.0), (1, 1, 0.0)])
    assert tr.jerk(0.5)[0] == pytest.approx(6.0, abs=COEFFICIENT)


@st.composite
def hermite_multisegment(draw: st.DrawFn):
    """Hermite data (orders 0..n-1) at every breakpoint: one well-posed problem per draw."""
    ndof = draw(st.integers(1, 3))
    m = draw(st.integers(1, 4))
    n = draw(st.integers(1, 4))
    start = draw(st.floats(-5.0, 5.0))
    steps = [draw(st.floats(0.01, 100.0)) for _ in range(m)]
    bp = start + np.concatenate([[0.0], np.cumsum(steps)])
    assume(np.all(np.diff(bp) > 0.009))  # rounding of start + cumsum
    values = draw(
        support.joint_arrays(
            ndof * n * (m + 1),
            st.one_of(st.just(0.0), st.floats(-5, 5, allow_subnormal=False)),
        )
    ).reshape(m + 1, n, ndof)
    return bp, values


@given(problem=hermite_multisegment())
def test_random_hermite_problems_are_satisfied(problem):
    bp, values = problem
    m, n = bp.size - 1, values.shape[1]
    conditions = [
        [(bp[i + side], r, values[i + side, r]) for side in (0, 1) for r in range(n)]
        for i in range(m)
    ]
    tr = tk.polynomial(conditions, segments=bp)
    assert tr.info["degrees"] == (2 * n - 1,) * m
    for piece in range(m):
        h = bp[piece + 1] - bp[piece]
        ends = np.maximum(np.abs(values[piece]), np.abs(values[piece + 1]))  # (n, ndof)
        for r in range(n):
            # As in _assert_boundary: order r adds up the data b_k times h**(k - r).
            scale = np.maximum(1.0, (ends * h ** (np.arange(n) - r)[:, None]).max(axis=0))
            # The piece meets the data at both of its ends; so, the pieces that meet at a
            # breakpoint agree there (continuity up to order n - 1).
            for side in (0, 1):
                got = support._piece_derivative(tr.coefficients[:, piece], r, side * h)
                error = np.abs(got - values[piece + side, r]) / scale
                assert np.all(error <= CLOSED_FORM), (piece, side, r, got, error.max())


@pytest.mark.parametrize(
    ("segments", "derivatives"),
    [
        ([0.0, 0.01], 4),  # a 10 ms septic; tk.septic(0, 1, 0.01) is fine
        ([0.0, 100.0], 4),  # a 100 s septic
        ([0.0, 1000.0], 3),  # a 1000 s quintic
        ([0.0, 3.0, 3.125], 4),  # two septic pieces of different lengths
    ],
)
def test_well_posed_problem_is_not_called_singular(segments, derivatives):
    # Hermite data at both ends of every piece always has exactly one solution; here every
    # piece is a rest-to-rest move 0 -> 1. (Until 8d95155 the rank test ran on the unscaled
    # A and called these singular, even "contradicting".)
    conditions = [
        [
            (segments[i + side], r, 1.0 if (side, r) == (1, 0) else 0.0)
            for side in (0, 1)
            for r in range(derivatives)
        ]
        for i in range(len(segments) - 1)
    ]
    tr = tk.polynomial(conditions, segments=segments)
    for i in range(len(segments) - 1):
        start = segments[i]
        T = segments[i + 1] - start
        reference = tk.septic if derivatives == 4 else tk.quintic
        expected = reference(0.0, 1.0, T).position(T / 3)
        support.assert_state(tr.position(start + T / 3), expected)


@given(problem=hermite_multisegment())
def test_random_spline_problems_match_cubic_spline(problem):
    # positions at both ends of every piece, end velocities, C1 and C2 at the interior
    # breakpoints: the clamped cubic spline, an independent construction (scipy).
    bp, values = problem
    q, v = values[:, 0], values[:, -1]
    m = bp.size - 1
    conditions = [[(bp[i], 0, q[i]), (bp[i + 1], 0, q[i + 1])] for i in range(m)]
    conditions[0].append((bp[0], 1, v[0]))
    conditions[-1].append((bp[-1], 1, v[-1]))
    tr = tk.polynomial(conditions, segments=bp, continuity=[(1, 2)] * (m - 1), degrees=3)
    spline = tk.cubic_spline(bp, q, v0=v[0], vf=v[-1])
    t = np.concatenate([bp, np.linspace(bp[0], bp[-1], 23)])
    h = np.diff(bp).min()
    for order in range(3):
        # Order-r values are made of the data over h**r (velocities over h**(r - 1)).
        scale = max(1.0, np.abs(q).max() / h**order, np.abs(v).max() / h ** max(order - 1, 0))
        err = np.abs(tr.evaluate(t, order) - spline.evaluate(t, order)) / scale
        assert err.max() <= CLOSED_FORM, (order, err.max())


def test_absolute_coefficients_of_a_line():
    # Sanity of the helper used for seed 004: q = 1 + 2 (t - 2) = -3 + 2 t on [2, 4].
    tr = tk.polynomial([(2, 0, 1.0), (4, 0, 5.0)])
    np.testing.assert_allclose(_ascending(tr)[0, :, 0], [-3.0, 2.0], atol=COEFFICIENT)
    np.testing.assert_allclose(tr.coefficients[:, 0, 0], [2.0, 1.0], atol=COEFFICIENT)
    assert tr.info["planner"] == "polynomial"
