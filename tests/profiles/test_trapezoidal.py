"""Tests of trajkit.trapezoidal: time-optimal LSPB, synchronization, dt, the blend rule.

Every expected value here is computed independently of trajkit: closed forms of the
bang-coast-bang move (triangle below D = v^2/a, trapezoid above), an obviously-correct
piecewise evaluator, and, for the controller period (dt), a brute-force search over
whole-step phase counts that proves whether a quantized profile exists.
"""

from __future__ import annotations

import re
import warnings
from math import atan2, isclose, radians, sqrt

import numpy as np
import pytest
from hypothesis import given, reject
from hypothesis import strategies as st

import support
import trajkit as tk
from support import CLOSED_FORM, ROUNDING, joint_arrays, limits_positive, ndofs

# Tolerances -------------------------------------------------------------------------
DT_MULTIPLE = 1e-9  # relative: a switching time counts as a whole multiple of dt
NO_OVERSHOOT = 1e-9  # relative to the size of the motion: positions stay within [q0, qf]
STRAIGHT_LINE = 1e-9  # relative to max(1, |qf - q0|): phase sync stays on the segment
REQUESTED = ROUNDING  # relative: a requested duration is returned as given
SYNC_MODES = ("time", "phase", None)
# trajkit treats distances up to 1e-150 as no motion where limit / distance would
# overflow (phase sync's shared law, dt quantization); documented, far below resolution.
NEGLIGIBLE = 1e-150


# Independent reference formulas ---------------------------------------------------------
def direction_limits(distance, vpos, vneg, apos, aneg):
    """Speed, rise and fall acceleration magnitudes of a rest-to-rest move (one joint)."""
    if distance >= 0:
        return vpos, apos, aneg
    return vneg, aneg, apos


def rest_minimum(distance, vpos, vneg, apos, aneg):
    """Shortest rest-to-rest duration: trapezoid when |D| >= V^2 (1/rise + 1/fall) / 2."""
    if distance == 0:
        return 0.0
    speed, rise, fall = direction_limits(distance, vpos, vneg, apos, aneg)
    d = abs(distance)
    k = 0.5 / rise + 0.5 / fall  # distance covered by rise + fall is k vp^2
    if d >= k * speed**2:
        return d / speed + k * speed
    return 2.0 * sqrt(k * d)


def rest_peak(distance, vpos, vneg, apos, aneg):
    """Signed peak velocity of the time-optimal rest-to-rest move."""
    speed, rise, fall = direction_limits(distance, vpos, vneg, apos, aneg)
    k = 0.5 / rise + 0.5 / fall
    return np.sign(distance) * min(speed, sqrt(abs(distance) / k))


def lspb_position(t, q0, v0, phases, accelerations):
    """Slow, obviously-correct evaluator of one joint's three constant-acceleration phases."""
    t1, t2, t3 = phases
    a1, a3 = accelerations
    v1 = v0 + a1 * t1
    q1 = q0 + v0 * t1 + a1 * t1**2 / 2
    q2 = q1 + v1 * t2
    if t <= t1:
        return q0 + v0 * t + a1 * t**2 / 2
    if t <= t1 + t2:
        return q1 + v1 * (t - t1)
    s = min(t - t1 - t2, t3)
    return q2 + v1 * s + a3 * s**2 / 2


def position_scale(trajectory):
    """Size of a motion: the largest |position| it reaches (at least 1)."""
    extrema = trajectory.extrema(0)
    return max(1.0, float(np.max(np.abs(extrema.minimum))), float(np.max(np.abs(extrema.maximum))))


def velocity_scale(trajectory):
    return max(1.0, float(np.max(trajectory.extrema(1).peak)))


def assert_close(actual, expected, scale, rtol, what):
    error = np.max(np.abs(np.asarray(actual, float) - np.asarray(expected, float))) / scale
    assert error <= rtol, f"{what}: error {error:.3g} (scaled by {scale:.3g}) > {rtol:g}"


def assert_whole_multiples(values, dt, what):
    values = np.asarray(values, float).ravel()
    steps = np.round(values / dt)
    error = np.abs(values - steps * dt) / np.maximum(np.abs(values), dt)
    assert np.all(error <= DT_MULTIPLE), f"{what} not whole multiples of dt={dt}: {values}"


def whole_step_profiles(distance, v0, vf, vpos, vneg, apos, aneg, dt, steps, n1_range, n3_range):
    """Brute force: every (n1, n2, n3) with n1 + n2 + n3 = steps whose phases keep the limits.

    For whole-step phase counts the peak velocity follows from the distance,
    D = dt (n1 (v0 + vp) / 2 + n2 vp + n3 (vp + vf) / 2), and the accelerations from
    the velocity changes; a phase of zero steps cannot change the velocity (vp must
    then equal v0, or vf). Returns rows (n1, n2, n3, vp, a1, a3), limits kept exactly.
    """
    n1, n3 = np.meshgrid(np.arange(*n1_range), np.arange(*n3_range), indexing="ij")
    n1, n3 = n1.ravel().astype(float), n3.ravel().astype(float)
    n2 = steps - n1 - n3
    keep = (n1 >= 0) & (n3 >= 0) & (n2 >= 0) & (n1 / 2 + n2 + n3 / 2 > 0)
    n1, n2, n3 = n1[keep], n2[keep], n3[keep]
    vp = (distance / dt - v0 * n1 / 2 - vf * n3 / 2) / (n1 / 2 + n2 + n3 / 2)
    with np.errstate(divide="ignore", invalid="ignore"):
        a1 = np.where(n1 > 0, (vp - v0) / (n1 * dt), 0.0)
        a3 = np.where(n3 > 0, (vf - vp) / (n3 * dt), 0.0)
    scale = 1e-12 * max(abs(v0), abs(vf), vpos, vneg)
    ok = (
        (vp <= vpos) & (vp >= -vneg)
        & (a1 <= apos) & (a1 >= -aneg) & (a3 <= apos) & (a3 >= -aneg)
        & ((n1 > 0) | (np.abs(vp - v0) <= scale)) & ((n3 > 0) | (np.abs(vp - vf) <= scale))
    )  # fmt: skip
    return np.stack([n1, n2, n3, vp, a1, a3], axis=-1)[ok]


# Strategies -----------------------------------------------------------------------------
fractions = st.one_of(st.just(0.0), st.just(1.0), st.just(-1.0), st.floats(-1.0, 1.0))


@st.composite
def problems(draw, *, boundary="rest", still=True, asymmetric_a=True, asymmetric_v=True):
    """A random N-DoF trapezoid problem; limits in [1e-2, 100], asymmetric or symmetric.

    boundary: "rest" (v0 = vf = 0), "any" (each joint's v0, vf anywhere within its limits,
    exact zeros and exact limits included) or "parallel" (v0, vf proportional to qf - q0,
    as phase sync needs). still: whether joints with q0 == qf may be drawn.
    """
    ndof = draw(ndofs)
    q0 = draw(joint_arrays(ndof))
    qf = draw(joint_arrays(ndof))
    if still:
        same = draw(joint_arrays(ndof, st.booleans()).map(lambda a: a.astype(bool)))
        qf = np.where(same, q0, qf)
    else:
        qf = np.where(qf == q0, q0 + 1.0, qf)
    vpos = draw(joint_arrays(ndof, limits_positive))
    apos = draw(joint_arrays(ndof, limits_positive))
    asym_v = asymmetric_v and draw(st.booleans())
    asym_a = asymmetric_a and draw(st.booleans())
    vneg = draw(joint_arrays(ndof, limits_positive)) if asym_v else vpos
    aneg = draw(joint_arrays(ndof, limits_positive)) if asym_a else apos
    v0 = vf = np.zeros(ndof)
    if boundary == "any":
        f0 = draw(joint_arrays(ndof, fractions))
        f1 = draw(joint_arrays(ndof, fractions))
        v0 = np.where(f0 >= 0, f0 * vpos, f0 * vneg)
        vf = np.where(f1 >= 0, f1 * vpos, f1 * vneg)
    elif boundary == "parallel" and np.any(np.abs(qf - q0) > NEGLIGIBLE):
        qf = np.where(np.abs(qf - q0) > NEGLIGIBLE, qf, q0)
        D = qf - q0
        moving = D != 0
        with np.errstate(divide="ignore", over="ignore"):
            up = np.min(np.where(D > 0, vpos / np.abs(D), vneg / np.abs(D))[moving])
            down = np.min(np.where(D > 0, vneg / np.abs(D), vpos / np.abs(D))[moving])
        c0, c1 = draw(fractions), draw(fractions)
        v0 = (c0 * up if c0 >= 0 else c0 * down) * D
        vf = (c1 * up if c1 >= 0 else c1 * down) * D
        # Keep the scaled values inside the limits despite rounding.
        v0, vf = (np.clip(v, -vneg, vpos) for v in (v0, vf))
    return {
        "q0": q0,
        "qf": qf,
        "v0": v0,
        "vf": vf,
        "vmax": (-vneg, vpos) if asym_v else vpos,
        "amax": (-aneg, apos) if asym_a else apos,
        "limits": tk.Limits(velocity=(-vneg, vpos), acceleration=(-aneg, apos)),
        "bounds": (vpos, vneg, apos, aneg),
    }


def plan(problem, **kwargs):
    return tk.trapezoidal(
        problem["q0"],
        problem["qf"],
        problem["vmax"],
        problem["amax"],
        v0=problem["v0"],
        vf=problem["vf"],
        **kwargs,
    )


def assert_phases_consistent(tr, problem):
    """The reported phases integrate to the reported peak and to vf: vp = v0 + a1 t1, ..."""
    phases = np.array(tr.info["phase_times"])
    accelerations = np.array(tr.info["accelerations"])
    peak = np.array(tr.info["peak_velocity"])
    scale = velocity_scale(tr)
    rise = problem["v0"] + accelerations[:, 0] * phases[:, 0]
    fall = peak + accelerations[:, 1] * phases[:, 2]
    assert_close(rise, peak, scale, CLOSED_FORM, "v0 + a1 t1 vs peak")
    assert_close(fall, problem["vf"], scale, CLOSED_FORM, "peak + a3 t3 vs vf")


def has_negligible_move(problem):
    """Whether some joint moves by at most NEGLIGIBLE (treated as no motion at times)."""
    distance = np.abs(problem["qf"] - problem["q0"])
    return bool(np.any((distance > 0) & (distance <= NEGLIGIBLE)))


def assert_start_and_end(tr, problem, *, own_end=False):
    """Boundary states: q0, v0 at 0; qf, vf at the end (each joint's own end if own_end)."""
    q_scale, v_scale = position_scale(tr), velocity_scale(tr)
    assert_close(tr.position(0.0), problem["q0"], q_scale, CLOSED_FORM, "start position")
    assert_close(tr.velocity(0.0), problem["v0"], v_scale, CLOSED_FORM, "start velocity")
    if own_end:
        ends = np.sum(tr.info["phase_times"], axis=1)
        at = np.array([tr.position(t)[j] for j, t in enumerate(ends)])
        vel = np.array([tr.velocity(t)[j] for j, t in enumerate(ends)])
        assert_close(at, problem["qf"], q_scale, CLOSED_FORM, "position at own end")
        assert_close(vel, problem["vf"], v_scale, CLOSED_FORM, "velocity at own end")
        # Early finishers continue at vf.
        held = problem["qf"] + problem["vf"] * (tr.duration - ends)
        assert_close(tr.position(tr.duration), held, q_scale, CLOSED_FORM, "held end")
    else:
        assert_close(tr.position(tr.duration), problem["qf"], q_scale, CLOSED_FORM, "end position")
    assert_close(tr.velocity(tr.duration), problem["vf"], v_scale, CLOSED_FORM, "end velocity")


def assert_no_overshoot(tr, q0, qf):
    extrema = tr.extrema(0)
    slack = NO_OVERSHOOT * position_scale(tr)
    assert np.all(extrema.minimum >= np.minimum(q0, qf) - slack), (extrema.minimum, q0, qf)
    assert np.all(extrema.maximum <= np.maximum(q0, qf) + slack), (extrema.maximum, q0, qf)


def assert_straight_line(tr, q0, qf, count=97):
    """q(t) - q0 = s(t) (qf - q0) for one common s(t), at many times."""
    distance = qf - q0
    times = np.linspace(0.0, tr.duration, count)
    moved = tr.position(times) - q0
    lead = int(np.argmax(np.abs(distance)))
    if distance[lead] == 0:
        assert np.all(moved == 0)
        return
    s = moved[:, lead] / distance[lead]
    error = np.abs(moved - s[:, np.newaxis] * distance) / np.maximum(1.0, np.abs(distance))
    assert np.max(error) <= STRAIGHT_LINE, f"off the line by {np.max(error):.3g}"


# ---------------------------------------------------------------- closed forms, rest to rest
TRAPEZOIDS = [  # (D, V, A): D > V^2 / A
    (10.0, 2.0, 1.0),
    (-10.0, 2.0, 1.0),
    (3.0, 0.5, 4.0),
    (-0.75, 0.1, 0.3),
    (1234.5, 17.0, 3.5),
]


@pytest.mark.parametrize("sync", SYNC_MODES)
@pytest.mark.parametrize(("D", "V", "A"), TRAPEZOIDS)
def test_trapezoid_closed_form(D, V, A, sync):
    q0 = 0.25
    tr = tk.trapezoidal(q0, q0 + D, V, A, sync=sync)
    tb = V / A
    coast = abs(D) / V - V / A
    T = abs(D) / V + V / A
    s = np.sign(D)
    assert tr.duration == pytest.approx(T, rel=CLOSED_FORM)
    assert tr.info["minimum_durations"] == pytest.approx((T,), rel=CLOSED_FORM)
    assert tr.info["phase_times"][0] == pytest.approx((tb, coast, tb), rel=CLOSED_FORM)
    assert tr.info["peak_velocity"][0] == pytest.approx(s * V, rel=CLOSED_FORM)
    assert tr.info["accelerations"][0] == pytest.approx((s * A, -s * A), rel=CLOSED_FORM)
    times = np.linspace(0.0, T, 101)
    expected = [lspb_position(t, q0, 0.0, (tb, coast, tb), (s * A, -s * A)) for t in times]
    assert_close(tr.position(times)[:, 0], expected, max(1.0, abs(D)), CLOSED_FORM, "q(t)")
    velocity = tr.extrema(1)
    assert velocity.peak[0] == pytest.approx(V, rel=CLOSED_FORM)
    assert tr.acceleration(tb / 2)[0] == pytest.approx(s * A, rel=CLOSED_FORM)
    assert tr.acceleration(T / 2)[0] == 0.0
    assert tr.acceleration(T - tb / 2)[0] == pytest.approx(-s * A, rel=CLOSED_FORM)
    assert tr.check(tk.Limits(velocity=V, acceleration=A)).ok


TRIANGLES = [  # (D, V, A): D < V^2 / A
    (1.0, 2.0, 1.0),
    (-1.0, 2.0, 1.0),
    (4.0, 10.0, 1.0),
    (0.2, 100.0, 1.0),
    (-0.5, 3.0, 5.0),
    (2.0, 7.0, 3.0),
]


@pytest.mark.parametrize("sync", SYNC_MODES)
@pytest.mark.parametrize(("D", "V", "A"), TRIANGLES)
def test_triangle_duration_and_limits(D, V, A, sync):
    tr = tk.trapezoidal(0.0, D, V, A, sync=sync)
    T = 2.0 * sqrt(abs(D) / A)
    assert tr.duration == pytest.approx(T, rel=CLOSED_FORM)
    assert tr.info["minimum_durations"] == pytest.approx((T,), rel=CLOSED_FORM)
    support.assert_state(tr.position(T), [D])
    support.assert_state(tr.velocity(np.array([0.0, T])), np.zeros((2, 1)))
    assert tr.check(tk.Limits(velocity=V, acceleration=A)).ok
    # A triangle never reaches vmax.
    assert tr.extrema(1).peak[0] < V


# The triangle's rise, fall and peak are closed forms too: t1 = t3 = sqrt(D / A),
# vp = sqrt(D A), no coast. Recomputing the peak as 2 d / (T + sqrt(T^2 - 4 k d)) at the
# minimum duration, where T^2 - 4 k d is 0 only up to rounding, once turned an error of
# 1e-16 into one of 1e-8 (a spurious coast, a peak low by ~1e-8): these cases showed it.
@pytest.mark.parametrize(
    ("D", "V", "A"),
    [
        (1.0, 2.0, 1.0),
        (-1.0, 2.0, 1.0),
        (4.0, 10.0, 1.0),
        (0.2, 100.0, 1.0),
        (-0.5, 3.0, 5.0),
        (0.1, 100.0, 2.0),
    ],
)
def test_triangle_phases_are_the_closed_form(D, V, A):
    tr = tk.trapezoidal(0.0, D, V, A)
    tb = sqrt(abs(D) / A)
    s = np.sign(D)
    assert tr.info["phase_times"][0] == pytest.approx((tb, 0.0, tb), rel=CLOSED_FORM, abs=1e-12)
    assert tr.info["peak_velocity"][0] == pytest.approx(s * sqrt(abs(D) * A), rel=CLOSED_FORM)
    assert tr.extrema(1).peak[0] == pytest.approx(sqrt(abs(D) * A), rel=CLOSED_FORM)


@pytest.mark.parametrize(("V", "A"), [(2.0, 4.0), (3.0, 1.5), (0.5, 0.25)])
def test_at_the_boundary_d_equals_v2_over_a_both_forms_agree(V, A):
    D = V * V / A
    tr = tk.trapezoidal(0.0, D, V, A, sync=None)
    T = 2.0 * V / A
    assert T == pytest.approx(2.0 * sqrt(D / A), rel=ROUNDING)  # triangle form
    assert T == pytest.approx(D / V + V / A, rel=ROUNDING)  # trapezoid form
    assert tr.duration == pytest.approx(T, rel=CLOSED_FORM)
    t1, coast, t3 = tr.info["phase_times"][0]
    assert (t1, t3) == pytest.approx((V / A, V / A), rel=CLOSED_FORM)
    assert coast == pytest.approx(0.0, abs=CLOSED_FORM * T)
    assert tr.extrema(1).peak[0] == pytest.approx(V, rel=CLOSED_FORM)


@pytest.mark.parametrize("sync", SYNC_MODES)
def test_negative_move_mirrors_the_positive_one(sync):
    q0 = np.array([0.5, -1.0, 2.0])
    D = np.array([3.0, 0.4, 7.5])
    vmax, amax = np.array([1.0, 2.0, 3.0]), np.array([2.0, 0.5, 1.0])
    up = tk.trapezoidal(q0, q0 + D, vmax, amax, sync=sync)
    down = tk.trapezoidal(q0, q0 - D, vmax, amax, sync=sync)
    assert down.duration == pytest.approx(up.duration, rel=ROUNDING)
    times = np.linspace(0.0, up.duration, 61)
    mirrored = q0 - (up.position(times) - q0)
    assert_close(down.position(times), mirrored, 10.0, CLOSED_FORM, "mirror")


def test_negative_triangle_peak_mirrors_the_positive_one():
    # Joint 2 is a triangle (0.4 < 2^2 / 0.5); its up move once got a peak low by 1.2e-8.
    q0 = np.array([0.5, -1.0, 2.0])
    D = np.array([3.0, 0.4, 7.5])
    vmax, amax = np.array([1.0, 2.0, 3.0]), np.array([2.0, 0.5, 1.0])
    up = tk.trapezoidal(q0, q0 + D, vmax, amax, sync=None)
    down = tk.trapezoidal(q0, q0 - D, vmax, amax, sync=None)
    assert down.info["peak_velocity"][1] == pytest.approx(-sqrt(0.2), rel=CLOSED_FORM)
    assert up.info["peak_velocity"][1] == pytest.approx(sqrt(0.2), rel=CLOSED_FORM)


@pytest.mark.parametrize("sync", SYNC_MODES)
@pytest.mark.parametrize("dt", [None, 0.002])
def test_no_motion_is_a_zero_duration_standstill(sync, dt):
    q = np.array([0.3, -1.2, 0.0])
    tr = tk.trapezoidal(q, q, 1.0, 2.0, sync=sync, period=dt)
    assert tr.duration == 0.0
    assert tr.info["minimum_durations"] == (0.0, 0.0, 0.0)
    assert np.all(np.array(tr.info["phase_times"]) == 0.0)
    for t in (-1.0, 0.0, 5.0):
        assert np.all(tr.position(t) == q)
        assert np.all(tr.velocity(t) == 0.0)
        assert np.all(tr.acceleration(t) == 0.0)


@pytest.mark.parametrize("sync", ["time", None])
def test_a_joint_that_does_not_move_stays_exactly_still(sync):
    q0 = np.array([0.0, 1.5, -2.0])
    qf = np.array([2.0, 1.5, 1.0])
    tr = tk.trapezoidal(q0, qf, 1.0, 1.0, sync=sync)
    times = np.linspace(-1.0, tr.duration + 1.0, 73)
    assert np.all(tr.position(times)[:, 1] == 1.5)
    assert np.all(tr.velocity(times)[:, 1] == 0.0)
    assert tr.info["minimum_durations"][1] == 0.0
    support.assert_state(tr.position(tr.duration), qf)


def test_phase_sync_with_a_still_joint():
    tr = tk.trapezoidal([0.0, 0.0], [1.0, 0.0], 1.0, 1.0, sync="phase")
    assert tr.duration == pytest.approx(2.0, rel=CLOSED_FORM)
    assert np.all(tr.position(np.linspace(0, 2, 11))[:, 1] == 0.0)
    support.assert_state(tr.position(2.0), [1.0, 0.0])


def test_phase_sync_with_a_still_joint_and_a_duration():
    tr = tk.trapezoidal([0.0, 0.0], [1.0, 0.0], 1.0, 1.0, sync="phase", duration=5.0)
    assert tr.duration == pytest.approx(5.0, rel=REQUESTED)


def test_phase_sync_with_a_still_joint_and_dt():
    tr = tk.trapezoidal([0.0, 0.0, 0.0], [1.0, 0.0, -2.0], 1.0, 1.0, sync="phase", period=0.01)
    assert tr.check(tk.Limits(velocity=1.0, acceleration=1.0)).ok
    support.assert_state(tr.position(tr.duration), [1.0, 0.0, -2.0])


@pytest.mark.parametrize("D", [1e-15, 1e-12, 3e-9, -2e-10])
@pytest.mark.parametrize("sync", SYNC_MODES)
def test_tiny_moves(D, sync):
    A, V = 2.0, 1.0
    tr = tk.trapezoidal(0.0, D, V, A, sync=sync)
    T = 2.0 * sqrt(abs(D) / A)
    assert tr.duration == pytest.approx(T, rel=CLOSED_FORM)
    # Relative to the move itself, not to 1: the end lands on qf to 1e-9 of |D|.
    assert abs(tr.position(T)[0] - D) <= CLOSED_FORM * abs(D)
    assert abs(tr.velocity(T)[0]) <= CLOSED_FORM * sqrt(abs(D) * A)
    assert tr.check(tk.Limits(velocity=V, acceleration=A)).ok
    assert_no_overshoot(tr, np.array([0.0]), np.array([D]))


@pytest.mark.parametrize(
    ("D", "sync"),
    [(D, sync) for D in (1e-24, 1e-30, 1e-100) for sync in SYNC_MODES]
    + [(1e-300, "time"), (1e-300, None)],
)
def test_very_tiny_moves(D, sync):
    # Trajectories far shorter than 1e-12 s (this once collapsed to one breakpoint).
    tr = tk.trapezoidal(0.0, D, 1.0, 2.0, sync=sync)
    assert tr.duration == pytest.approx(2.0 * sqrt(D / 2.0), rel=CLOSED_FORM)
    assert abs(tr.position(tr.duration)[0] - D) <= CLOSED_FORM * D
    assert tr.position(tr.duration / 2)[0] == pytest.approx(D / 2, rel=CLOSED_FORM)


def test_phase_sync_treats_negligible_distances_as_no_motion():
    # Below 1e-150 the shared law's limits (limit / |D|) would overflow: documented.
    tr = tk.trapezoidal([0.0, 0.0], [1e-300, 1.0], 1.0, 1.0, sync="phase")
    assert tr.duration == pytest.approx(2.0, rel=CLOSED_FORM)
    assert abs(tr.position(2.0)[0] - 1e-300) <= 1e-150


# -------------------------------------------------------------------- asymmetric limits
def test_asymmetric_limits_faster_up_than_down():
    vmax, amax = (-1.0, 2.0), (-0.5, 4.0)
    up = tk.trapezoidal(0.0, 10.0, vmax, amax)
    down = tk.trapezoidal(0.0, -10.0, vmax, amax)
    # Up: cruise at +2, rise at +4, brake at -0.5.  k = 1/8 + 1/1 = 1.125.
    assert up.duration == pytest.approx(10.0 / 2.0 + 1.125 * 2.0, rel=CLOSED_FORM)  # 7.25
    assert up.info["phase_times"][0] == pytest.approx((0.5, 2.75, 4.0), rel=CLOSED_FORM)
    assert up.info["accelerations"][0] == pytest.approx((4.0, -0.5), rel=CLOSED_FORM)
    assert up.info["peak_velocity"][0] == pytest.approx(2.0, rel=CLOSED_FORM)
    # Down: cruise at -1, rise at -0.5, brake at +4.
    assert down.duration == pytest.approx(10.0 / 1.0 + 1.125 * 1.0, rel=CLOSED_FORM)  # 11.125
    assert down.info["phase_times"][0] == pytest.approx((2.0, 8.875, 0.25), rel=CLOSED_FORM)
    assert down.info["accelerations"][0] == pytest.approx((-0.5, 4.0), rel=CLOSED_FORM)
    assert down.info["peak_velocity"][0] == pytest.approx(-1.0, rel=CLOSED_FORM)
    limits = tk.Limits(velocity=vmax, acceleration=amax)
    for tr in (up, down):
        assert tr.check(limits).ok
    # The asymmetry is used: the up move is beyond symmetric limits of the lower magnitudes.
    assert not up.check(tk.Limits(velocity=1.0, acceleration=0.5)).ok
    assert up.extrema(1).maximum[0] == pytest.approx(2.0, rel=CLOSED_FORM)
    assert down.extrema(1).minimum[0] == pytest.approx(-1.0, rel=CLOSED_FORM)


def test_asymmetric_triangle_duration():
    # k = 1/(2*3) + 1/(2*1) = 2/3; T = 2 sqrt(k D); peak sqrt(D / k) = sqrt(1.5) < 10.
    tr = tk.trapezoidal(0.0, 1.0, 10.0, (-1.0, 3.0))
    assert tr.duration == pytest.approx(2.0 * sqrt(2.0 / 3.0), rel=CLOSED_FORM)
    assert tr.check(tk.Limits(velocity=10.0, acceleration=(-1.0, 3.0))).ok
    support.assert_state(tr.position(tr.duration), [1.0])


def test_asymmetric_per_joint_tuples():
    lower, upper = np.array([-1.0, -3.0]), np.array([2.0, 0.5])
    tr = tk.trapezoidal([0.0, 0.0], [10.0, -10.0], (lower, upper), 1.0, sync=None)
    expected = (10.0 / 2.0 + 2.0, 10.0 / 3.0 + 3.0)
    assert tr.info["minimum_durations"] == pytest.approx(expected, rel=CLOSED_FORM)
    assert tr.check(tk.Limits(velocity=(lower, upper), acceleration=1.0)).ok


# -------------------------------------------------------------- nonzero boundary velocities
BOUNDARY_CASES = {
    # name: (D, v0, vf, V, A, T, phases (t1, t2, t3), peak)
    "faster start": (10.0, 1.0, 0.0, 2.0, 1.0, 6.25, (1.0, 3.25, 2.0), 2.0),
    "pure coast": (2.0, 2.0, 2.0, 2.0, 1.0, 1.0, (0.0, 1.0, 0.0), 2.0),
    "arrive moving": (4.0, 0.0, 1.0, 2.0, 1.0, 3.25, (2.0, 0.25, 1.0), 2.0),
    # Braking from 2 takes 2 m > 0.1 m: brake through zero to -sqrt(1.9), come back.
    "must overshoot": (
        0.1, 2.0, 0.0, 2.0, 1.0, 2.0 + 2.0 * sqrt(1.9),
        (2.0 + sqrt(1.9), 0.0, sqrt(1.9)), -sqrt(1.9),
    ),
    # v0 points away: (vp^2 - 0.25) / 2 + vp^2 / 2 = 1 -> vp = sqrt(1.125).
    "start backwards": (
        1.0, -0.5, 0.0, 2.0, 1.0, 0.5 + 2.0 * sqrt(1.125),
        (0.5 + sqrt(1.125), 0.0, sqrt(1.125)), sqrt(1.125),
    ),
}  # fmt: skip


@pytest.mark.parametrize("case", list(BOUNDARY_CASES))
@pytest.mark.parametrize("sync", SYNC_MODES)
def test_boundary_velocity_closed_forms(case, sync):
    D, v0, vf, V, A, T, phases, peak = BOUNDARY_CASES[case]
    tr = tk.trapezoidal(1.0, 1.0 + D, V, A, v0=v0, vf=vf, sync=sync)
    assert tr.duration == pytest.approx(T, rel=CLOSED_FORM)
    assert tr.info["minimum_durations"] == pytest.approx((T,), rel=CLOSED_FORM)
    support.assert_state(tr.position(np.array([0.0, T])), [[1.0], [1.0 + D]])
    support.assert_state(tr.velocity(np.array([0.0, T])), [[v0], [vf]])
    assert tr.check(tk.Limits(velocity=V, acceleration=A)).ok
    if sync is None:  # each joint alone: the time-optimal phases themselves
        assert tr.info["phase_times"][0] == pytest.approx(phases, rel=CLOSED_FORM, abs=1e-12)
        assert tr.info["peak_velocity"][0] == pytest.approx(peak, rel=CLOSED_FORM)
        times = np.linspace(0.0, T, 101)
        a1 = (peak - v0) / phases[0] if phases[0] else 0.0
        a3 = (vf - peak) / phases[2] if phases[2] else 0.0
        expected = [lspb_position(t, 1.0, v0, phases, (a1, a3)) for t in times]
        assert_close(tr.position(times)[:, 0], expected, 1.0 + abs(D), CLOSED_FORM, "q(t)")


def test_time_sync_of_a_single_joint_keeps_the_optimal_phases():
    # sync="time" with one joint must be the time-optimal profile itself.
    D, v0, vf, V, A, _, phases, peak = BOUNDARY_CASES["must overshoot"]
    tr = tk.trapezoidal(1.0, 1.0 + D, V, A, v0=v0, vf=vf)
    assert tr.info["phase_times"][0] == pytest.approx(phases, rel=CLOSED_FORM, abs=1e-12)
    assert tr.info["peak_velocity"][0] == pytest.approx(peak, rel=CLOSED_FORM)


def test_already_in_the_target_state_takes_no_time():
    # Start state == target state: nothing to do (sync=None agrees, so does ruckig).
    alone = tk.trapezoidal(0.0, 0.0, 1.0, 0.1, v0=0.1, vf=0.1, sync=None)
    assert alone.duration == 0.0
    tr = tk.trapezoidal(0.0, 0.0, 1.0, 0.1, v0=0.1, vf=0.1)
    assert tr.duration == 0.0


@pytest.mark.parametrize("sync", ["time", None])
@pytest.mark.parametrize(
    ("q", "speed", "amax"),
    [(1.0, 0.875, 0.01), (-3.0, 2.0, 0.5), (1e3, 1.0, 1e-4), (0.0, 0.875, 0.01)],
)
def test_standing_in_the_target_state_at_the_speed_limit_keeps_the_velocity(q, speed, amax,
                                                                            sync):  # fmt: skip
    # A found case (hypothesis): at vmax the peak of the fastest profile rounds up by a
    # unit, so it accelerates for 1e-14 s and moves 2e-14 rad too far. Landing that
    # "rounding" miss on the velocity took -1.75 rad/s off it: the move started at
    # -0.885 rad/s for a start velocity of 0.875. The miss now stays in the position.
    tr = tk.trapezoidal([q], [q], speed, amax, v0=speed, vf=speed, sync=sync)
    assert tr.duration < 1e-12
    limits = tk.Limits(velocity=speed, acceleration=amax)
    assert tr.check(limits).ok, tr.check(limits).violations
    t = np.linspace(0.0, tr.duration, 5)
    np.testing.assert_allclose(tr.velocity(t), speed, rtol=1e-12)
    np.testing.assert_allclose(tr.position(t), q, rtol=0, atol=1e-12 * max(1.0, abs(q)))
    assert tr.start_state.velocity[0] == speed and tr.end_state.velocity[0] == speed


def test_standing_still_at_a_velocity_limit_leaves_room_for_the_long_way_round():
    # Found by hypothesis: joint 1 stands in its target state at its lower velocity
    # limit, joint 2 needs 2.7e6 s. Joint 1 can take no duration between 0 and the
    # 5.3e6 s of braking, coasting back at +0.01 rad/s and returning: three formulas
    # found "stand still" and filled the candidates' room before that profile was
    # tried, so nothing was blocked, and step 2 failed at 2.7e6 s.
    vmax, amax = ((-25.0, -25.0), (0.01, 0.01)), 0.01171875
    tr = tk.trapezoidal([0.0, 0.0], [0.0, 0.0], vmax, amax, v0=[-25.0, 0.0], vf=[-25.0, -25.0])
    around = 2 * (25.01 / amax) + (25.0**2 / amax) / 0.01 - 0.01 / amax  # ramps + coast
    assert tr.duration == pytest.approx(around, rel=1e-12)
    assert tr.info["minimum_durations"][0] == 0.0
    assert tr.check(tk.Limits(velocity=vmax, acceleration=amax)).ok
    np.testing.assert_allclose(tr.end_state.velocity, [-25.0, -25.0], rtol=1e-12)
    np.testing.assert_allclose(tr.position(tr.duration), [0.0, 0.0], atol=1e-8)


@pytest.mark.parametrize("side", [-1.0, 1.0])
@pytest.mark.parametrize(
    ("speed", "back", "amax"),
    [(25.0, 0.01, 0.01171875), (27.0, 0.01, 0.01), (1.0, 0.5, 2.0), (3.0, 3.0, 0.25)],
)
def test_standing_at_either_velocity_limit_synchronizes_the_long_way_round(side, speed, back,
                                                                           amax):  # fmt: skip
    # The family of the case above, on both sides and with a partner needing less time
    # than the long way round: brake to the other limit, coast back, speed up again.
    low, high = (-speed, back) if side < 0 else (-back, speed)
    vmax = ((low, low), (high, high))
    v = side * speed
    tr = tk.trapezoidal([0.0, 0.0], [0.0, 0.0], vmax, amax, v0=[v, 0.0], vf=[v, v])
    ramp = (speed + back) / amax
    coast = ((speed - back) * (speed + back) / amax) / back
    assert tr.duration == pytest.approx(2 * ramp + coast, rel=1e-11)
    assert tr.check(tk.Limits(velocity=vmax, acceleration=amax)).ok
    np.testing.assert_allclose(tr.velocity(tr.duration), [v, v], rtol=1e-12)
    np.testing.assert_allclose(tr.position(tr.duration), [0.0, 0.0], atol=1e-8)
    alone = tk.trapezoidal([0.0], [0.0], (low, high), amax, v0=v, vf=v)
    assert alone.duration == 0.0  # in the target state already: nothing to do


@pytest.mark.parametrize("law", ["trapezoid", "scurve"])
@pytest.mark.parametrize("v0", [0.0, 5e-324, -1e-310, 0.7])
@pytest.mark.parametrize("vf", [0.0, 5e-324, -1e-310, 0.5])
@pytest.mark.parametrize("qf", [0.0, 5e-324, 1.0])
def test_subnormal_boundary_velocities_end_exactly(law, v0, vf, qf):
    # Found by hypothesis: from rest to 5e-324 rad/s in place was "no fastest
    # profile": the squares of such speeds underflow, and the 2.5e-324 s the change
    # takes rounds to no time, which the engine read as a jump of the state.
    if v0 == vf == qf == 0.0:
        return
    limits = tk.Limits(velocity=1.0, acceleration=(-1.0, 2.0))
    if law == "trapezoid":
        tr = tk.trapezoidal([0.0], [qf], 1.0, (-1.0, 2.0), v0=[v0], vf=[vf], sync=None)
    else:
        tr = tk.scurve([0.0], [qf], 1.0, (-1.0, 2.0), 10.0, v0=[v0], vf=[vf], sync=None)
    assert tr.check(limits).ok
    assert (tr.end_state.position[0], tr.end_state.velocity[0]) == (qf, vf)
    if tr.duration > 0.0:
        assert (tr.start_state.position[0], tr.start_state.velocity[0]) == (0.0, v0)
    else:  # a change no duration can hold: the start is the end, one subnormal away
        assert abs(v0 - vf) <= 5e-324 and qf == 0.0


def test_a_long_way_round_with_a_long_slow_coast_blocks_the_durations_below_it():
    # Found by hypothesis: joint 1 rides at -32 rad/s (its lower limit) from 1 to 0 rad
    # and ends so; the other joint must stop, which takes 5.1e6 s at 0.01 rad/s^2.
    # Joint 1 can only take that long the long way round (brake to +0.01 rad/s, coast
    # back 5.2e6 s, speed up again), whose record missed its target by 1.03e-8 rad to
    # rounding: the durations between were taken as free, and the plan failed.
    vmax, amax = ((-32.0, -32.0), (0.01, 0.01)), ((-1.0, -1.0), (0.01, 0.01))
    tr = tk.trapezoidal([1.0, 1.0], [0.0, 0.0], vmax, amax, v0=[-32.0, -32.0], vf=[-32.0, 0.0])
    brake, ramp = 32.01 / 0.01, 32.01 / 1.0
    # The coast covers what the ramps leave of the -1 rad, at +0.01 rad/s.
    coast = (-1.0 - (0.01**2 - 32.0**2) / 0.02 - (32.0**2 - 0.01**2) / -2.0) / 0.01
    assert tr.duration == pytest.approx(brake + coast + ramp, rel=1e-12)
    assert tr.check(tk.Limits(velocity=vmax, acceleration=amax)).ok
    assert tr.end_state.velocity.tolist() == [-32.0, 0.0]
    np.testing.assert_allclose(tr.end_state.position, [0.0, 0.0], rtol=0, atol=1e-8)


@pytest.mark.parametrize("law", ["trapezoid", "scurve"])
@pytest.mark.parametrize("speed", [1e-300, 7.09155576e-258, 1e-200, 1e-162, 1e-17])
@pytest.mark.parametrize("period", [None, 0.01])
@pytest.mark.parametrize("sync", ["time", None])
def test_standing_in_a_tiny_moving_target_state(law, speed, period, sync):
    # Found by hypothesis: standing in place at 7e-258 rad/s (the target state) was
    # "no fastest profile": the speed counts as rest, yet the engine then sought the
    # long way round (4e-258 s) in units of 1e-258 s, where 1 rad/s^2 underflows to 0.
    kwargs = {"v0": [speed, 0.0], "vf": [speed, 0.0], "period": period, "sync": sync}
    if law == "trapezoid":
        tr = tk.trapezoidal([0.0, 0.0], [0.0, 1.0], 1.0, 1.0, **kwargs)
    else:
        tr = tk.scurve([0.0, 0.0], [0.0, 1.0], 1.0, 1.0, 10.0, **kwargs)
    jerk = None if law == "trapezoid" else 10.0
    assert tr.check(tk.Limits(velocity=1.0, acceleration=1.0, jerk=jerk)).ok
    assert tr.end_state.velocity[0] == speed
    assert abs(tr.end_state.position[0]) <= 1e-8  # the laws' position tolerance
    assert tr.end_state.position[1] == 1.0
    if period is not None:
        assert_whole_multiples([tr.duration], period, "duration")


def test_a_long_coast_lands_its_end_state_exactly():
    # Found by hypothesis: an 8.4e6 s move whose second joint coasts at -1.4e-13 rad/s
    # missed its end velocity by 4.6e-8 rad/s: its last ramp, 9e-5 s at 55 rad/s^2, was
    # placed in absolute time (1.9e-9 s apart there), since the coast's 1.7e-13 rad miss
    # counted as a lost target instead of a rounding the velocity can take.
    vmax = ((-41.0, -41.0), (0.01, 0.01))
    tr = tk.trapezoidal([0.0, 0.0], [0.0, 0.0], vmax, [0.01, 55.0], v0=[-41.0, 0.01],
                        vf=[0.005, 0.005])  # fmt: skip
    assert tr.duration == pytest.approx(8409100.625001673, rel=1e-12)
    assert tr.velocity(tr.duration).tolist() == [0.005, 0.005]
    assert tr.position(tr.duration).tolist() == [0.0, 0.0]
    assert tr.check(tk.Limits(velocity=vmax, acceleration=[0.01, 55.0])).ok


# ------------------------------------------------------------------------- allow_overshoot
@pytest.mark.parametrize(
    ("qf", "v0", "vf", "reaches"),
    [
        (0.1, 2.0, 0.0, "2 rad"),  # cannot brake in time: the fastest profile reaches 2
        (1.0, -0.5, 0.0, "-0.125 rad"),  # v0 points away from the target
        (1.0, 0.0, -0.5, "1.125 rad"),  # vf points back: must pass qf first
    ],
)
def test_allow_overshoot_false_refuses(qf, v0, vf, reaches):
    with pytest.raises(tk.InfeasibleError, match="overshoot") as info:
        tk.trapezoidal(0.0, qf, 2.0, 1.0, v0=v0, vf=vf, allow_overshoot=False)
    message = str(info.value)
    assert "joint 1" in message
    assert f"qf={qf:g} rad" in message
    assert reaches in message
    assert "allow_overshoot=True" in message
    # Allowed, the same request plans and really leaves [q0, qf].
    tr = tk.trapezoidal(0.0, qf, 2.0, 1.0, v0=v0, vf=vf)
    extrema = tr.extrema(0)
    assert extrema.minimum[0] < min(0.0, qf) or extrema.maximum[0] > max(0.0, qf)


def test_allow_overshoot_false_names_the_joint_that_overshoots():
    with pytest.raises(tk.InfeasibleError, match=r"joint 2 cannot reach qf=0\.1 rad"):
        tk.trapezoidal(
            [0.0, 0.0], [10.0, 0.1], 2.0, 1.0, v0=[1.0, 2.0], sync=None, allow_overshoot=False
        )


def test_allow_overshoot_false_ignores_the_continuation_after_a_joint_finishes():
    # Joint 2 alone: up to sqrt(1.125) and down to 0.5, never past qf = 1 (1.62 s);
    # then it continues at vf = 0.5 until joint 1 finishes at 7 s, as documented.
    tr = tk.trapezoidal(
        [0.0, 0.0], [10.0, 1.0], 2.0, 1.0, vf=[0.0, 0.5], sync=None, allow_overshoot=False
    )
    assert tr.duration == pytest.approx(7.0, rel=CLOSED_FORM)


@pytest.mark.parametrize(
    ("sync", "v0", "vf"),
    [
        ("time", [1.0, 0.5], [0.0, 0.25]),
        (None, [1.0, 0.5], [0.0, 0.0]),
        ("phase", [0.0, 0.0], [0.0, 0.0]),
        ("phase", [0.4, 0.2], [0.0, 0.0]),
    ],
)
def test_allow_overshoot_false_is_silent_when_not_needed(sync, v0, vf):
    kwargs = {"v0": v0, "vf": vf, "sync": sync}
    strict = tk.trapezoidal([0.0, 0.0], [10.0, 5.0], 2.0, 1.0, allow_overshoot=False, **kwargs)
    loose = tk.trapezoidal([0.0, 0.0], [10.0, 5.0], 2.0, 1.0, **kwargs)
    assert strict.duration == loose.duration
    assert np.array_equal(strict.coefficients, loose.coefficients)
    assert_no_overshoot(strict, np.zeros(2), np.array([10.0, 5.0]))


# -------------------------------------------------------------------------- given duration
@pytest.mark.parametrize("sync", SYNC_MODES)
@pytest.mark.parametrize("factor", [1.0, 1.001, 1.5, 4.0])
def test_given_duration_is_exact(sync, factor):
    q0, qf = np.array([0.0, 1.0, -1.0]), np.array([3.0, -1.0, 0.5])
    vmax, amax = np.array([1.0, 2.0, 0.5]), np.array([1.0, 3.0, 0.25])
    fastest = tk.trapezoidal(q0, qf, vmax, amax, sync=sync)
    T = fastest.duration * factor
    tr = tk.trapezoidal(q0, qf, vmax, amax, sync=sync, duration=T)
    assert tr.duration == pytest.approx(T, rel=REQUESTED)
    assert tr.info["duration"] == pytest.approx(T, rel=REQUESTED)
    support.assert_state(tr.position(T), qf)
    support.assert_state(tr.velocity(np.array([0.0, T])), np.zeros((2, 3)))
    assert tr.check(tk.Limits(velocity=vmax, acceleration=amax)).ok
    assert np.sum(tr.info["phase_times"], axis=1) == pytest.approx([T] * 3, rel=CLOSED_FORM)
    if sync == "phase":
        assert_straight_line(tr, q0, qf)


@pytest.mark.parametrize("sync", ["time", "phase"])
@given(data=st.data(), stretch=st.floats(0.0, 3.0))
def test_property_given_duration_rest_to_rest(data, stretch, sync):
    problem = data.draw(problems())
    if sync == "phase" and has_negligible_move(problem):
        reject()  # no motion: test_phase_sync_treats_negligible_distances_as_no_motion
    fastest = plan(problem, sync=sync)
    T = max(fastest.duration, 1e-3) * (1.0 + stretch)
    tr = plan(problem, sync=sync, duration=T)
    assert tr.duration == pytest.approx(T, rel=REQUESTED)
    assert tr.check(problem["limits"]).ok
    assert_start_and_end(tr, problem)
    assert_no_overshoot(tr, problem["q0"], problem["qf"])


@pytest.mark.parametrize("sync", SYNC_MODES)
def test_too_short_a_duration_names_the_minimum(sync):
    # Joint 2 alone needs 3 / 1 + 1 / 1 = 4 s (phase sync: the same law, also 4 s).
    with pytest.raises(tk.InfeasibleError) as info:
        tk.trapezoidal([0.0, 0.0], [1.0, 3.0], 1.0, 1.0, duration=3.5, sync=sync)
    message = str(info.value)
    assert "duration 3.5 s is below the minimum 4 s" in message
    assert "vmax=1 rad/s" in message
    assert "joint 2" in message


def test_duration_just_below_the_minimum_is_refused():
    T = tk.trapezoidal(0.0, 3.0, 1.0, 1.0).duration  # 4 s
    with pytest.raises(tk.InfeasibleError, match="minimum 4 s"):
        tk.trapezoidal(0.0, 3.0, 1.0, 1.0, duration=T * (1 - 1e-9))


@pytest.mark.parametrize("sync", ["time", None])
def test_requested_duration_in_a_blocked_interval_is_refused(sync):
    # v0 = vf = 1, D = 0.5, |a| <= 1: the shortest distance coverable in T while returning
    # to v = 1 is T - T^2 / 4, so 0.5 m is reachable only for T <= 2 - sqrt(2) or
    # T >= 2 + sqrt(2). T = 1 s lies in the gap (it was once silently replaced by 3.414 s).
    assert 1.0 - 1.0**2 / 4 > 0.5
    with pytest.raises(tk.InfeasibleError) as info:
        tk.trapezoidal(0.0, 0.5, 2.0, 1.0, v0=1.0, vf=1.0, duration=1.0, sync=sync)
    message = str(info.value)
    assert message.startswith("duration 1 s cannot be met exactly")
    assert "joint 1" in message
    assert f"{2 + sqrt(2):.6g} s" in message  # the next duration that works
    # Either side of the gap works exactly.
    for T in (2.0 - sqrt(2.0), 2.0 + sqrt(2.0), 5.0):
        tr = tk.trapezoidal(0.0, 0.5, 2.0, 1.0, v0=1.0, vf=1.0, duration=T, sync=sync)
        assert tr.duration == pytest.approx(T, rel=REQUESTED)
        support.assert_state(tr.position(T), [0.5])
        support.assert_state(tr.velocity(T), [1.0])
        assert tr.check(tk.Limits(velocity=2.0, acceleration=1.0)).ok


def test_blocked_interval_under_time_sync_takes_the_next_feasible_duration():
    # Joint 2 alone needs 2 s, inside joint 1's blocked interval (0.586 s, 3.414 s):
    # the common duration is the end of the gap, 2 + sqrt(2).
    tr = tk.trapezoidal([0.0, 0.0], [0.5, 1.0], 2.0, 1.0, v0=[1.0, 0.0], vf=[1.0, 0.0])
    assert tr.info["minimum_durations"] == pytest.approx((sqrt(6.0) - 2.0, 2.0), rel=CLOSED_FORM)
    assert tr.duration == pytest.approx(2.0 + sqrt(2.0), rel=CLOSED_FORM)
    support.assert_state(tr.position(tr.duration), [0.5, 1.0])
    support.assert_state(tr.velocity(tr.duration), [1.0, 0.0])
    assert tr.check(tk.Limits(velocity=2.0, acceleration=1.0)).ok


def test_too_short_message_names_the_lower_velocity_bound_of_a_negative_move():
    # Moving down at most 1 rad/s: 10 s coast + 1 s of ramps; the upper bound 2 is
    # irrelevant (the message once named it).
    with pytest.raises(tk.InfeasibleError, match="minimum 11 s") as info:
        tk.trapezoidal(0.0, -10.0, (-1.0, 2.0), (-1.0, 1.0), duration=5.0)
    assert "vmax=2" not in str(info.value)
    assert "vmax=-1 rad/s" in str(info.value)


# ----------------------------------------------------------------------- hypothesis sweeps
@pytest.mark.parametrize("sync", ["time", None])
@given(problem=problems())
def test_property_rest_to_rest(problem, sync):
    tr = plan(problem, sync=sync)
    q0, qf = problem["q0"], problem["qf"]
    vpos, vneg, apos, aneg = problem["bounds"]
    own = [rest_minimum(d, *b) for d, *b in zip(qf - q0, vpos, vneg, apos, aneg, strict=True)]
    assert tr.info["minimum_durations"] == pytest.approx(own, rel=CLOSED_FORM)
    assert tr.duration == pytest.approx(max(own), rel=CLOSED_FORM)
    assert tr.check(problem["limits"]).ok
    assert_start_and_end(tr, problem)
    assert_no_overshoot(tr, q0, qf)
    sums = np.sum(tr.info["phase_times"], axis=1)
    if sync == "time":
        assert sums == pytest.approx([tr.duration] * q0.size, rel=CLOSED_FORM)
        assert tr.info["limiting_joint"] == int(np.argmax(tr.info["minimum_durations"]))
    else:
        assert sums == pytest.approx(own, rel=CLOSED_FORM)


@pytest.mark.parametrize("sync", ["time", None])
@given(problem=problems())
def test_property_rest_to_rest_peak_velocity_is_the_closed_form(problem, sync):
    tr = plan(problem, sync=sync)
    distance = problem["qf"] - problem["q0"]
    peaks = [rest_peak(d, *b) for d, *b in zip(distance, *problem["bounds"], strict=True)]
    # Alone every joint runs its optimum; under time sync only the limiting one does.
    joints = range(distance.size) if sync is None else [tr.info["limiting_joint"]]
    for j in joints:
        assert tr.info["peak_velocity"][j] == pytest.approx(peaks[j], rel=CLOSED_FORM)


@given(problem=problems())
def test_property_phase_sync_rest_to_rest(problem):
    if has_negligible_move(problem):
        reject()  # no motion: test_phase_sync_treats_negligible_distances_as_no_motion
    tr = plan(problem, sync="phase")
    q0, qf = problem["q0"], problem["qf"]
    own = tk.trapezoidal(q0, qf, problem["vmax"], problem["amax"], sync=None)
    # One law for all joints: at least as long as the slowest joint alone.
    assert tr.duration >= own.duration * (1 - ROUNDING)
    assert tr.info["limiting_joint"] is None
    assert tr.check(problem["limits"]).ok
    assert_start_and_end(tr, problem)
    assert_no_overshoot(tr, q0, qf)
    assert_straight_line(tr, q0, qf)
    phases = np.array(tr.info["phase_times"])
    assert np.all(phases == phases[0])  # every joint switches at the same times
    assert np.sum(phases[0]) == pytest.approx(tr.duration, rel=CLOSED_FORM)
    # Time optimal among straight-line moves: some joint touches a velocity or
    # acceleration bound (else the law could go faster).
    if np.all(qf == q0):
        assert tr.duration == 0.0
        return
    report = tr.check(problem["limits"])
    vpos, vneg, apos, aneg = problem["bounds"]
    v_lo, v_hi = report.peaks["velocity"]
    a_lo, a_hi = report.peaks["acceleration"]
    touches = np.concatenate([v_hi / vpos, -v_lo / vneg, a_hi / apos, -a_lo / aneg])
    assert np.max(touches) == pytest.approx(1.0, rel=CLOSED_FORM)


@given(problem=problems(still=False))
def test_property_phase_sync_nothing_moves(problem):
    problem = {**problem, "qf": problem["q0"]}
    tr = plan(problem, sync="phase")
    assert tr.duration == 0.0
    assert tr.check(problem["limits"]).ok
    assert_start_and_end(tr, problem)
    assert_straight_line(tr, problem["q0"], problem["qf"])


@pytest.mark.parametrize("sync", ["time", None])
@given(problem=problems(boundary="any"))
def test_property_moving_boundaries(problem, sync):
    tr = plan(problem, sync=sync)
    assert_phases_consistent(tr, problem)
    own = np.array(tr.info["minimum_durations"])
    assert tr.check(problem["limits"]).ok
    sums = np.sum(tr.info["phase_times"], axis=1)
    if sync == "time":
        # Blocked intervals may push the common duration past the slowest joint's minimum.
        assert tr.duration >= own.max() * (1 - ROUNDING)
        assert sums == pytest.approx([tr.duration] * own.size, rel=CLOSED_FORM)
        assert_start_and_end(tr, problem)
    else:
        assert tr.duration == pytest.approx(own.max(), rel=ROUNDING)
        assert sums == pytest.approx(own, rel=CLOSED_FORM)
        assert_start_and_end(tr, problem, own_end=True)


@given(problem=problems(boundary="parallel"))
def test_property_phase_sync_with_parallel_boundary_velocities(problem):
    tr = plan(problem, sync="phase")
    assert_phases_consistent(tr, problem)
    assert tr.check(problem["limits"]).ok
    assert_start_and_end(tr, problem)
    assert_straight_line(tr, problem["q0"], problem["qf"])


@pytest.mark.parametrize("jmax", [None, 10.0])
def test_phase_sync_with_a_target_speed_at_the_limit_beside_a_parallel_joint(jmax):
    """Found by a randomized hypothesis run: joint 2 ends at vmax; the law's target speed
    (joint 1's -0.0080402 over its scale) came out an ulp past the bound joint 2's limit
    sets, and the phase law had "no fastest profile"."""
    q0, qf = [5.0, 0.0], [0.0, 6.21875]
    vf = [-0.008040201005025126, 0.01]
    if jmax is None:
        tr = tk.trapezoidal(q0, qf, 0.01, 1.0, vf=vf, sync="phase")
    else:
        tr = tk.scurve(q0, qf, 0.01, 1.0, jmax, vf=vf, sync="phase")
    assert tr.info["phase_synchronized"] is True
    assert tr.check(tk.Limits(velocity=0.01, acceleration=1.0, jerk=jmax)).ok
    support.assert_state(tr.position(tr.duration), qf)
    support.assert_state(tr.velocity(tr.duration), vf)
    assert_straight_line(tr, np.array(q0), np.array(qf))


def test_long_move_with_a_tiny_reversal_keeps_its_boundary_states():
    # The rise is reported as exactly 0 s while the peak is -6.9e-9: the change is lost.
    # Stand still at 0, end at 0 moving at vmax after 400 s: dip to -6.9e-9 rad/s first.
    tr = tk.trapezoidal(0.0, 0.0, 0.01, 18.0, vf=0.01, duration=400.0)
    assert tr.check(tk.Limits(velocity=0.01, acceleration=18.0)).ok
    support.assert_state(tr.position(400.0), [0.0])
    assert abs(tr.velocity(400.0)[0] - 0.01) <= CLOSED_FORM * 0.01
    problem = {"v0": np.zeros(1), "vf": np.array([0.01])}
    assert_phases_consistent(tr, problem)


def test_short_ramps_of_a_small_joint_in_a_long_move_are_kept():
    # Joint 2 (5e-5 rad in 1000 s) ramps to 5e-8 rad/s in 0.5 ns at 100 rad/s^2.
    tr = tk.trapezoidal([0.0, 0.0], [10.0, 5e-5], 0.01, 100.0)
    assert tr.info["phase_times"][1][0] == pytest.approx(5e-10, rel=1e-6)
    # Joint 2 at rest at both ends (it once started and ended at 5e-8 rad/s).
    assert np.abs(tr.velocity(np.array([0.0, tr.duration]))[:, 1]).max() <= 1e-12
    assert tr.velocity(1.0)[1] == pytest.approx(5e-8, rel=1e-6)


def test_phase_sync_with_boundary_velocities_off_the_line_falls_back_to_time_sync():
    q0, qf, v0 = [0.0, 0.0], [1.0, 2.0], [0.5, 0.5]
    tr = tk.trapezoidal(q0, qf, 1.0, 1.0, v0=v0, sync="phase")
    assert tr.info["phase_synchronized"] is False
    assert "time-synchronized instead" in tr.info["phase_note"]
    timed = tk.trapezoidal(q0, qf, 1.0, 1.0, v0=v0, sync="time")
    assert tr.duration == timed.duration
    support.assert_state(tr.position(tr.duration), qf)
    assert tr.check(tk.Limits(velocity=1.0, acceleration=1.0)).ok


# ------------------------------------------------------------------- controller period dt
dts = st.one_of(st.just(0.002), st.floats(1e-3, 0.5))


@pytest.mark.parametrize("sync", SYNC_MODES)
@given(problem=problems(), dt=dts)
def test_property_dt_rest_to_rest(problem, dt, sync):
    if has_negligible_move(problem):
        reject()  # no motion under dt: test_dt_negligible_moves
    continuous = plan(problem, sync=sync)
    tr = plan(problem, sync=sync, period=dt)
    assert tr.info["period"] == dt
    assert_whole_multiples(tr.info["phase_times"], dt, "phase times")
    assert_whole_multiples([tr.duration], dt, "duration")
    # At most one period past the continuous optimum rounded up: less than 2 dt longer.
    assert tr.duration >= continuous.duration * (1 - ROUNDING)
    assert round(tr.duration / dt) <= np.ceil(continuous.duration / dt) + 1
    assert tr.check(problem["limits"]).ok
    assert_start_and_end(tr, problem)
    assert_no_overshoot(tr, problem["q0"], problem["qf"])
    if sync == "phase":
        assert_straight_line(tr, problem["q0"], problem["qf"])
    if sync == "time":
        sums = np.sum(tr.info["phase_times"], axis=1)
        assert sums == pytest.approx([tr.duration] * sums.size, rel=CLOSED_FORM)


@pytest.mark.parametrize("sync", ["time", None])
@given(problem=problems(boundary="any"), dt=dts)
def test_property_dt_moving_boundaries(problem, dt, sync):
    if has_negligible_move(problem):
        reject()  # no motion under dt: test_dt_negligible_moves
    try:
        tr = plan(problem, sync=sync, period=dt)
    except tk.InfeasibleError as error:
        # Moving boundaries can block every duration near the optimum (a joint that
        # cannot slow down in time): see test_dt_when_nearby_durations_are_blocked.
        assert "whole multiples of period=" in str(error)
        reject()
    assert_phases_consistent(tr, problem)
    assert_whole_multiples(tr.info["phase_times"], dt, "phase times")
    assert_whole_multiples([tr.duration], dt, "duration")
    assert tr.check(problem["limits"]).ok
    assert_start_and_end(tr, problem, own_end=sync is None)


# Whole-step profiles beyond a +-2 step window around the continuous phases: the
# quantization once missed them (asymmetric amax, moving boundaries). Each test first
# proves by brute force that such a profile exists.
def test_dt_asymmetric_acceleration_at_rest_stays_within_two_periods():
    D, V, lower, upper, dt = 0.31, 1.0, -0.5, 4.0, 0.002
    continuous = tk.trapezoidal(0.0, D, V, (lower, upper), sync=None)
    first = int(np.ceil(continuous.duration / dt))
    found = whole_step_profiles(D, 0.0, 0.0, V, V, upper, -lower, dt, first, (40, 90), (480, 540))
    assert len(found) > 0  # a whole-step profile exists at the first period after the optimum
    tr = tk.trapezoidal(0.0, D, V, (lower, upper), sync=None, period=dt)
    assert tr.duration < continuous.duration + 2 * dt  # documented: "at most 2 dt longer"


def test_dt_asymmetric_acceleration_at_rest_is_feasible():
    D, V, lower, upper, dt = 1.0, 100.0, -0.02, 1.0, 0.0005
    continuous = tk.trapezoidal(0.0, D, V, (lower, upper), sync=None)
    first = int(np.ceil(continuous.duration / dt))
    t1 = continuous.info["phase_times"][0][0] / dt
    n3 = continuous.info["phase_times"][0][2] / dt
    found = whole_step_profiles(
        D, 0.0, 0.0, V, V, upper, -lower, dt, first + 1,
        (int(t1) - 40, int(t1) + 40), (int(n3) - 40, int(n3) + 40),
    )  # fmt: skip
    assert len(found) > 0
    tr = tk.trapezoidal(0.0, D, V, (lower, upper), sync=None, period=dt)
    assert tr.duration <= (first + 1) * dt * (1 + ROUNDING)


def test_dt_with_a_moving_end_is_feasible():
    D, vf, V, A, dt = 0.0, 2.0, 3.0, 0.15, 0.005
    continuous = tk.trapezoidal(0.0, D, V, A, vf=vf, sync=None)
    first = int(np.ceil(continuous.duration / dt))
    # One period after the optimum: n1 = 1849, n2 = 75, n3 = 4515 keeps every limit.
    found = whole_step_profiles(D, 0.0, vf, V, V, A, A, dt, first + 1, (1840, 1860), (4505, 4525))
    assert [1849.0, 75.0, 4515.0] in found[:, :3].tolist()
    _, _, _, vp, a1, a3 = found[0]
    assert abs(a1) <= A and abs(a3) <= A and abs(vp) <= V
    tr = tk.trapezoidal(0.0, D, V, A, vf=vf, sync=None, period=dt)
    assert tr.duration <= (first + 1) * dt * (1 + ROUNDING)


@pytest.mark.parametrize("sync", ["time", None])
def test_dt_zero_step_phases_keep_the_end_velocity(sync):
    # Continuous: down for 3.3 ms, up for 7.9 ms (under 2 periods each). A zero-step
    # rise and fall once passed for a profile standing still and ending at v0, not vf.
    tr = tk.trapezoidal([0.0, 0.0], [0.0, 0.0], 0.25, [54.0, 1.0], vf=0.25, sync=sync, period=0.002)
    problem = {"q0": np.zeros(2), "qf": np.zeros(2), "v0": np.zeros(2), "vf": np.full(2, 0.25)}
    assert_start_and_end(tr, problem, own_end=sync is None)
    assert_phases_consistent(tr, problem)
    assert tr.check(tk.Limits(velocity=0.25, acceleration=[54.0, 1.0])).ok
    assert_whole_multiples(tr.info["phase_times"], 0.002, "phase times")


def test_dt_when_nearby_durations_are_blocked():
    # Moving at about -4 rad/s at both ends, 1.06 rad to go, |a| <= 0.155: changing the
    # speed by 1 rad/s takes 6.5 s, so only durations within a sliver above the optimum
    # (0.2616 s) or far longer ones work. No whole-step profile exists within 16 periods,
    # so the plan is one of the far longer ones: a slow reversal on the grid.
    q0, qf, v0, vf, V, A = (
        1.26570265268726,
        0.2084794786249491,
        -4.057077775092551,
        -4.0212046498840435,
        5.959604284707145,
        0.1550429572337289,
    )
    dt = 0.015174096390380996
    continuous = tk.trapezoidal(q0, qf, V, A, v0=v0, vf=vf, sync=None)
    first = int(np.ceil(continuous.duration / dt))
    for steps in range(first, first + 17):
        window = (0, steps + 1)  # every split, zero-step phases included
        found = whole_step_profiles(qf - q0, v0, vf, V, V, A, A, dt, steps, window, window)
        assert len(found) == 0
    tr = tk.trapezoidal(q0, qf, V, A, v0=v0, vf=vf, sync=None, period=dt)
    assert tr.duration > (first + 16) * dt
    assert_whole_multiples(tr.info["phase_times"], dt, "phase times")
    support.assert_state(tr.position(tr.duration), [qf])
    support.assert_state(tr.velocity(tr.duration), [vf])
    assert tr.check(tk.Limits(velocity=V, acceleration=A)).ok


@pytest.mark.parametrize("grid", ["duration", "switches"])
def test_dt_when_the_minimum_is_a_multiple_but_for_rounding(grid):
    # fmod(2.0, 0.01) is 0.00999999999999989: rounding 2 s "up" to whole periods gave
    # 1.9999999999999998 s, below the slower joint's own minimum, so no common
    # duration was found.
    tr = tk.trapezoidal([0.0, 0.5], [1.0, -1.0], 1.0, 2.0, period=0.01, grid=grid)
    assert tr.duration == pytest.approx(2.0, rel=CLOSED_FORM)
    support.assert_state(tr.position(tr.duration), [1.0, -1.0])
    assert tr.check(tk.Limits(velocity=1.0, acceleration=2.0)).ok


@pytest.mark.parametrize("sync", SYNC_MODES)
def test_dt_negligible_moves(sync):
    tr = tk.trapezoidal([0.0, 0.0], [1e-200, 1.0], 1.0, 1.0, sync=sync, period=0.01)
    assert tr.duration == pytest.approx(2.0, rel=CLOSED_FORM)
    assert abs(tr.position(2.0)[0] - 1e-200) <= NEGLIGIBLE
    support.assert_state(tr.position(2.0), [0.0, 1.0])


def test_dt_planning_emits_no_runtime_warning():
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        tr = tk.trapezoidal([0.0, 0.0], [1e-3, 2.0], 1.0, 1.0, sync=None, period=0.01)
    assert_whole_multiples(tr.info["phase_times"], 0.01, "phase times")


def test_dt_with_a_given_duration():
    tr = tk.trapezoidal([0.0, 0.0], [1.0, 2.0], 1.0, 1.0, duration=5.0, period=0.01)
    assert tr.duration == pytest.approx(5.0, rel=CLOSED_FORM)
    assert_whole_multiples(tr.info["phase_times"], 0.01, "phase times")
    assert tr.check(tk.Limits(velocity=1.0, acceleration=1.0)).ok
    support.assert_state(tr.position(tr.duration), [1.0, 2.0])


# ----------------------------------------------------------------------------- seed 001
SEED_001_QF = np.array([90.0, 75.0, 60.0, 45.0, 30.0, 15.0])
SEED_001_V = np.array([7.0, 7.0, 7.0, 3.5, 3.5, 3.5])
SEED_001_A = np.array([4.0, 4.0, 4.0, 2.0, 2.0, 2.0])
SEED_001_T = 1.75 + 90.0 / 7.0  # rise 7/4, coast 90/7 - 7/4, fall 7/4
SEED_001_LIMITS = tk.Limits(velocity=SEED_001_V, acceleration=SEED_001_A)


def test_seed_001_phase_sync():
    tr = tk.trapezoidal(np.zeros(6), SEED_001_QF, SEED_001_V, SEED_001_A, sync="phase")
    assert tr.duration == pytest.approx(14.607142857142858, rel=CLOSED_FORM)
    assert tr.duration == pytest.approx(SEED_001_T, rel=CLOSED_FORM)
    phases = np.array(tr.info["phase_times"])
    assert phases == pytest.approx(np.tile([1.75, 11.107142857142858, 1.75], (6, 1)))
    # Every joint: v = D / (T - tb), a = v / tb (the seed's joint 2: 35/6 and 10/3).
    peaks = SEED_001_QF / (SEED_001_T - 1.75)
    assert tr.info["peak_velocity"] == pytest.approx(peaks, rel=CLOSED_FORM)
    assert tr.info["peak_velocity"][1] == pytest.approx(35.0 / 6.0, rel=CLOSED_FORM)
    assert tr.info["accelerations"][1] == pytest.approx((10.0 / 3.0, -10.0 / 3.0), rel=CLOSED_FORM)
    support.assert_state(tr.velocity(SEED_001_T / 2), peaks)
    support.assert_state(tr.acceleration(1.0), peaks / 1.75)
    support.assert_state(tr.position(SEED_001_T), SEED_001_QF)
    assert tr.check(SEED_001_LIMITS).ok
    assert_straight_line(tr, np.zeros(6), SEED_001_QF)


def test_seed_001_time_sync_uses_the_gentlest_profiles():
    tr = tk.trapezoidal(np.zeros(6), SEED_001_QF, SEED_001_V, SEED_001_A)
    assert tr.duration == pytest.approx(SEED_001_T, rel=CLOSED_FORM)
    own = SEED_001_QF / SEED_001_V + SEED_001_V / SEED_001_A
    assert tr.info["minimum_durations"] == pytest.approx(own, rel=CLOSED_FORM)
    assert tr.info["limiting_joint"] == 0
    # Accelerations at the limit and the lowest peak that fits: vp = 2D / (T + sqrt(T^2 - 4D/A)).
    T = SEED_001_T
    peaks = 2 * SEED_001_QF / (T + np.sqrt(T**2 - 4 * SEED_001_QF / SEED_001_A))
    assert tr.info["peak_velocity"] == pytest.approx(peaks, rel=CLOSED_FORM)
    accelerations = np.array(tr.info["accelerations"])
    assert accelerations == pytest.approx(np.stack([SEED_001_A, -SEED_001_A], axis=1))
    assert tr.check(SEED_001_LIMITS).ok
    support.assert_state(tr.position(T), SEED_001_QF)


def test_seed_001_at_a_2_ms_period():
    dt = 0.002
    tr = tk.trapezoidal(np.zeros(6), SEED_001_QF, SEED_001_V, SEED_001_A, sync="phase", period=dt)
    # 14.6071... rounds up to 7304 periods; the seed's hand sum 14.61 s is wrong.
    assert tr.duration == pytest.approx(7304 * dt, rel=ROUNDING)
    assert tr.duration == pytest.approx(14.608, rel=ROUNDING)
    phases = np.array(tr.info["phase_times"])
    assert_whole_multiples(phases, dt, "phase times")
    tb = phases[0, 0]
    # The smallest whole-step blend keeping a = D / (tb (T - tb)) <= A is 875 periods.
    assert tb == pytest.approx(875 * dt, rel=ROUNDING)
    assert np.all(phases == phases[0])
    # Recomputed with the quantized times (the seed's 0.479 ... 0.0798 are wrong).
    velocities = SEED_001_QF / (tr.duration - tb)
    accelerations = velocities / tb
    assert tr.info["peak_velocity"] == pytest.approx(velocities, rel=CLOSED_FORM)
    assert np.array(tr.info["accelerations"])[:, 0] == pytest.approx(accelerations, rel=CLOSED_FORM)
    assert accelerations[0] == pytest.approx(90.0 / (12.858 * 1.75), rel=CLOSED_FORM)
    continuous = SEED_001_QF / ((SEED_001_T - 1.75) * 1.75)
    assert np.all(accelerations / continuous > 0.9999)  # barely gentler; the seed's are 8x lower
    assert np.all(accelerations <= continuous)
    support.assert_state(tr.velocity(tr.duration / 2), velocities)
    support.assert_state(tr.acceleration(tb / 2), accelerations)
    support.assert_state(tr.position(tr.duration), SEED_001_QF)
    assert tr.check(SEED_001_LIMITS).ok


# ------------------------------------------------------------------ seed 000 §2.1 (blends)
W_MAX = radians(30.0)  # 30 deg/s
V_MAX = 0.2  # m/s
HEADING = atan2(3.0, 5.0)
DRIVE = sqrt(34.0)
WHEELED = {  # phase: (q0, qf, limit, hand duration from the seed)
    "rotate": (0.0, HEADING, W_MAX, 1.2),
    "drive": (0.0, DRIVE, V_MAX, 32.0),
    "turn": (HEADING, 1.5, W_MAX, 2.02),
}


@pytest.mark.parametrize("phase", list(WHEELED))
def test_seed_000_blend_ratio_minimal_durations(phase):
    q0, qf, limit, _ = WHEELED[phase]
    tr = tk.trapezoidal(q0, qf, vmax=limit, blend_ratio=0.1)
    T = abs(qf - q0) / (limit * (1 - 0.1))
    assert tr.duration == pytest.approx(T, rel=CLOSED_FORM)
    assert tr.info["blend_time"] == pytest.approx(0.1 * T, rel=CLOSED_FORM)
    assert tr.info["rule"] == "blend_ratio"
    assert tr.info["phase_times"][0] == pytest.approx((0.1 * T, 0.8 * T, 0.1 * T), rel=CLOSED_FORM)
    # At the minimum the coast runs exactly at the limit; a = v / tb.
    assert tr.info["peak_velocity"][0] == pytest.approx(limit, rel=CLOSED_FORM)
    assert tr.acceleration(0.05 * T)[0] == pytest.approx(limit / (0.1 * T), rel=CLOSED_FORM)
    assert tr.check(tk.Limits(velocity=limit)).ok
    support.assert_state(tr.position(np.array([0.0, T])), [[q0], [qf]])
    support.assert_state(tr.velocity(np.array([0.0, T])), [[0.0], [0.0]])


def test_seed_000_rotation_of_1_2_s_is_feasible():
    tr = tk.trapezoidal(0.0, HEADING, vmax=W_MAX, blend_ratio=0.1, duration=1.2)
    assert tr.duration == pytest.approx(1.2, rel=REQUESTED)
    assert tr.info["peak_velocity"][0] == pytest.approx(HEADING / (1.2 * 0.9), rel=CLOSED_FORM)
    assert tr.info["peak_velocity"][0] < W_MAX
    assert tr.check(tk.Limits(velocity=W_MAX)).ok


@pytest.mark.parametrize(("phase", "shown"), [("drive", "32.3942"), ("turn", "2.03629")])
def test_seed_000_hand_durations_break_the_velocity_limit(phase, shown):
    q0, qf, limit, hand = WHEELED[phase]
    with pytest.raises(tk.InfeasibleError) as info:
        tk.trapezoidal(q0, qf, vmax=limit, blend_ratio=0.1, duration=hand)
    message = str(info.value)
    assert message.startswith(f"duration {hand:g} s is below the minimum {shown} s")
    assert f"set by vmax={limit:.6g}" in message
    # The hand choice really is too fast: v = D / (0.9 T) exceeds the limit.
    assert abs(qf - q0) / (0.9 * hand) > limit


def test_seed_000_drive_message_exactly():
    with pytest.raises(
        tk.InfeasibleError,
        match=re.escape("duration 32 s is below the minimum 32.3942 s set by vmax=0.2"),
    ):
        tk.trapezoidal(0.0, DRIVE, vmax=V_MAX, blend_ratio=0.1, duration=32.0)


def test_seed_000_drive_with_a_blend_time():
    tr = tk.trapezoidal(0.0, DRIVE, vmax=V_MAX, blend_time=3.2)
    T = 3.2 + DRIVE / V_MAX  # v = D / (T - tb) = vmax
    assert tr.duration == pytest.approx(T, rel=CLOSED_FORM)
    assert tr.info["blend_time"] == 3.2
    assert tr.info["rule"] == "blend_time"
    assert tr.info["phase_times"][0] == pytest.approx((3.2, T - 6.4, 3.2), rel=CLOSED_FORM)
    assert tr.info["peak_velocity"][0] == pytest.approx(V_MAX, rel=CLOSED_FORM)
    assert tr.acceleration(1.0)[0] == pytest.approx(V_MAX / 3.2, rel=CLOSED_FORM)
    support.assert_state(tr.position(T), [DRIVE])
    with pytest.raises(tk.InfeasibleError, match=r"below the minimum 32\.3548 s set by vmax=0\.2"):
        tk.trapezoidal(0.0, DRIVE, vmax=V_MAX, blend_time=3.2, duration=32.0)


def test_seed_000_blend_rule_with_amax():
    A = 0.05
    tr = tk.trapezoidal(0.0, DRIVE, vmax=V_MAX, amax=A, blend_ratio=0.1)
    # a = D / (T^2 r (1 - r)) <= A binds before v = D / (T (1 - r)) <= V does.
    by_a = sqrt(DRIVE / (A * 0.1 * 0.9))
    assert by_a > DRIVE / (V_MAX * 0.9)
    assert tr.duration == pytest.approx(by_a, rel=CLOSED_FORM)
    assert tr.acceleration(0.01)[0] == pytest.approx(A, rel=CLOSED_FORM)
    assert tr.info["peak_velocity"][0] < V_MAX
    assert tr.check(tk.Limits(velocity=V_MAX, acceleration=A)).ok
    with pytest.raises(tk.InfeasibleError, match=r"set by amax=0\.05 rad/s\^2"):
        tk.trapezoidal(0.0, DRIVE, vmax=V_MAX, amax=A, blend_ratio=0.1, duration=35.0)


def test_blend_time_with_amax_and_two_joints():
    tb = 0.5
    tr = tk.trapezoidal([0.0, 0.0], [1.0, -4.0], vmax=[10.0, 10.0], amax=2.0, blend_time=tb)
    # a = D / (tb (T - tb)) <= A  ->  T >= tb + D / (A tb); joint 2 binds: 0.5 + 4 = 4.5 s.
    assert tr.duration == pytest.approx(4.5, rel=CLOSED_FORM)
    assert tr.info["limiting_joint"] == 1
    assert tr.info["accelerations"][1] == pytest.approx((-2.0, 2.0), rel=CLOSED_FORM)
    assert np.array(tr.info["phase_times"]) == pytest.approx(np.array([[tb, 3.5, tb]] * 2))
    assert_straight_line(tr, np.zeros(2), np.array([1.0, -4.0]))


def test_blend_rule_with_dt():
    dt = 0.01
    tr = tk.trapezoidal(0.0, DRIVE, vmax=V_MAX, blend_ratio=0.1, period=dt)
    assert_whole_multiples([tr.duration], dt, "duration")
    assert_whole_multiples(tr.info["phase_times"], dt, "phase times")
    assert DRIVE / (V_MAX * 0.9) <= tr.duration < DRIVE / (V_MAX * 0.9) + 2 * dt
    assert tr.check(tk.Limits(velocity=V_MAX)).ok
    support.assert_state(tr.position(tr.duration), [DRIVE])


# ------------------------------------------------------------------------------ bad input
INVALID = [
    ({"q0": float("nan")}, "q0 must be finite"),
    ({"qf": [1.0, float("inf")]}, "qf must be finite"),
    ({"vmax": -1.0}, "vmax limits must be > 0"),
    ({"vmax": 0.0}, "vmax limits must be > 0"),
    ({"amax": [1.0, 0.0]}, "amax limits must be > 0"),
    ({"amax": float("nan")}, "amax must be finite"),
    ({"vmax": (1.0, 2.0)}, "must contain 0"),
    ({"vmax": (-1.0, -0.5)}, "must contain 0"),
    ({"amax": (-1.0, 0.0)}, "amax must allow motion both ways"),
    ({"vmax": (-1.0, 1.0, 2.0)}, "must be (lower, upper), got 3 items"),
    ({"qf": [1.0, 2.0, 3.0]}, "qf has 3 joints but q0 has 2"),
    ({"vmax": [1.0, 2.0, 3.0]}, "vmax has 3 joints but q0 has 2"),
    ({"q0": [[0.0, 0.0]]}, "q0 must be a number or a 1-D sequence"),
    ({"q0": []}, "q0 must not be empty"),
    (
        {"sync": "Time"},
        "sync must be 'time', 'phase', 'time_if_necessary', 'none' or None, got 'Time'",
    ),
    ({"blend_ratio": 0.0}, "blend_ratio must be in (0, 0.5], got 0.0"),
    ({"blend_ratio": 0.6}, "blend_ratio must be in (0, 0.5], got 0.6"),
    ({"blend_ratio": -0.1}, "blend_ratio must be in (0, 0.5]"),
    ({"blend_ratio": [0.1, 0.2]}, "blend_ratio must be in (0, 0.5]"),
    ({"blend_ratio": 0.1, "blend_time": 1.0}, "give blend_ratio or blend_time, not both"),
    ({"blend_ratio": 0.1, "v0": 0.1}, "v0 and vf must be 0"),
    ({"blend_time": 1.0, "vf": [0.0, -0.1]}, "v0 and vf must be 0"),
    ({"blend_time": 0.0}, "blend_time must be > 0"),
    ({"duration": 0.0}, "duration must be > 0"),
    ({"duration": -1.0}, "duration must be > 0"),
    ({"duration": float("nan")}, "duration must be finite"),
    ({"period": 0.0}, "period must be > 0"),
    ({"period": -0.002}, "period must be > 0"),
    ({"vmax": None}, "trapezoidal needs vmax and amax"),
    ({"amax": None}, "trapezoidal needs vmax and amax"),
]


@pytest.mark.parametrize(("change", "fragment"), INVALID)
def test_invalid_input(change, fragment):
    kwargs = {"q0": [0.0, 0.0], "qf": [1.0, 2.0], "vmax": 1.0, "amax": 1.0, **change}
    with pytest.raises(tk.InvalidInputError) as info:
        tk.trapezoidal(**kwargs)
    assert isinstance(info.value, ValueError)
    assert fragment in str(info.value)


@pytest.mark.parametrize(
    ("change", "fragment"),
    [
        ({"vf": [0.0, -3.0]}, "vf=-3 rad/s is beyond the velocity limit -1 rad/s (joint 2)"),
        ({"vf": [2.5, 0.0], "vmax": (-1.0, 2.0)}, "vf=2.5 rad/s is beyond the velocity limit 2"),
    ],
)
def test_target_velocity_beyond_the_limit_is_infeasible(change, fragment):
    kwargs = {"q0": [0.0, 0.0], "qf": [1.0, 2.0], "vmax": 1.0, "amax": 1.0, **change}
    with pytest.raises(tk.InfeasibleError) as info:
        tk.trapezoidal(**kwargs)
    assert fragment in str(info.value)
    assert not isinstance(info.value, ValueError)


@pytest.mark.parametrize(
    ("v0", "vmax"), [([2.0, 0.0], 1.0), ([0.0, -1.5], (-1.0, 2.0)), ([3.0, -3.0], 1.0)]
)
def test_a_start_velocity_beyond_the_limit_is_braked_at_full_deceleration(v0, vmax):
    tr = tk.trapezoidal([0.0, 0.0], [1.0, 2.0], vmax, 1.0, v0=v0)
    lower, upper = (-vmax, vmax) if not isinstance(vmax, tuple) else vmax
    for j, brake in enumerate(tr.info["brake_times"]):
        excess = max(v0[j] - upper, lower - v0[j], 0.0)
        # Back within the limit at 1 rad/s^2 takes exactly the excess in seconds.
        assert brake == pytest.approx(excess, rel=CLOSED_FORM, abs=1e-15)
        t = np.linspace(brake, tr.duration, 201)
        v = tr.velocity(t)[:, j]
        assert np.all((v <= upper * (1 + 1e-12)) & (v >= lower * (1 + 1e-12)))
    support.assert_state(tr.position(tr.duration), [1.0, 2.0])
    support.assert_state(tr.velocity(tr.duration), [0.0, 0.0])


def test_boundary_velocity_exactly_at_the_limit_is_accepted():
    tr = tk.trapezoidal(0.0, 5.0, (-1.0, 2.0), 1.0, v0=2.0, vf=2.0)
    assert tr.duration == pytest.approx(2.5, rel=CLOSED_FORM)
    assert isclose(tr.velocity(1.0)[0], 2.0, rel_tol=CLOSED_FORM)


@pytest.mark.parametrize("sync", [None, "time"])
def test_subnormal_distance_with_a_moving_end(sync):
    tr = tk.trapezoidal(
        np.array([0.0, 0.0, 0.0, 1e-313]), np.zeros(4), 1.0, 0.03125, sync=sync,
        vf=np.array([1.0, 0.0, 0.0, 0.0]),
    )  # fmt: skip
    assert tr.check(tk.Limits(velocity=1.0, acceleration=0.03125)).ok
    np.testing.assert_allclose(tr.end_state.velocity, [1.0, 0.0, 0.0, 0.0], atol=1e-12)


def test_a_joint_that_must_end_moving_where_it_started_creeps_forward_first():
    # Found by hypothesis: joint 2 starts and ends at 0, ending at -1e-5 rad/s, within
    # the 11.3 s of joint 1. Standing still and then ramping down ends 1.6e-9 rad
    # short, inside the laws' absolute precision (1e-8), and the plan was refused as
    # "too long for absolute time". It must first creep forward for 4.5e-9 s.
    tr = tk.trapezoidal([0.0, 0.0], [1.0, 0.0], vmax=1.0, amax=0.03125, vf=[0.0, -1e-5])
    pieces = tk.Trajectory(tr.breakpoints, tr.coefficients)  # the polynomial alone
    T = tr.end_time
    np.testing.assert_allclose(pieces.position(T), [1.0, 0.0], rtol=0, atol=1e-15)
    np.testing.assert_allclose(pieces.velocity(T), [0.0, -1e-5], rtol=0, atol=1e-15)
    assert tr.extrema(0).maximum[1] > 0.0  # the creep forward
    assert tr.check(tk.Limits(velocity=1.0, acceleration=0.03125)).ok
