"""Tests of trajkit.profiles._scurve_math: jerk-limited (double S) one-axis closed forms."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from trajkit.profiles import _scurve_math as sc

# pytest puts this file's own folder (tests/profiles) on sys.path, not tests/, where the
# shared helpers live; add it explicitly so `import support` works from the subfolder.
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from support import CLOSED_FORM


# --------------------------------------------------------------------------- helpers
def _integrate(phases: sc.SCurvePhases, v0):
    """Integrate the 7 constant-jerk phases exactly, from rest acceleration.

    Returns the end position, velocity and acceleration, the largest |v| and |a|
    reached (both are monotone within a phase, so phase ends suffice) and the
    largest mismatch between the integrated acceleration and the stated starts.
    """
    durations, jerks = phases.to_phases()
    starts = phases.phase_accelerations()
    v = np.array(v0, dtype=float) + 0 * durations[..., 0]
    p, a = np.zeros_like(v), np.zeros_like(v)
    v_max, a_max, mismatch = np.abs(v), np.zeros_like(v), np.zeros_like(v)
    for k in range(7):
        t, j = durations[..., k], jerks[..., k]
        mismatch = np.maximum(mismatch, np.abs(a - starts[..., k]))
        p = p + v * t + a * t**2 / 2 + j * t**3 / 6
        v = v + a * t + j * t**2 / 2
        a = a + j * t
        v_max, a_max = np.maximum(v_max, np.abs(v)), np.maximum(a_max, np.abs(a))
    return p, v, a, v_max, a_max, mismatch


def _assert_profiles(phases, D, v0, vf, V, A, J, *, jerk_limit=None):
    """Every valid profile reaches D and vf at zero acceleration, within the limits."""
    ok = phases.valid
    durations, jerks = phases.to_phases()
    T = phases.duration
    p, v, a, v_max, a_max, mismatch = _integrate(phases, v0)
    scale_d = np.abs(D) + V * T
    assert np.all(durations[ok] >= 0)
    np.testing.assert_array_less(
        np.abs(durations.sum(axis=-1) - T)[ok], CLOSED_FORM * T[ok] + 1e-300
    )
    np.testing.assert_array_less(np.abs(p - D)[ok], CLOSED_FORM * scale_d[ok] + 1e-300)
    np.testing.assert_array_less(np.abs(v - vf)[ok], CLOSED_FORM * V[ok])
    np.testing.assert_array_less(np.abs(a)[ok], CLOSED_FORM * A[ok])
    np.testing.assert_array_less(np.abs(mismatch)[ok], CLOSED_FORM * A[ok])
    np.testing.assert_array_less(v_max[ok], V[ok] * (1 + CLOSED_FORM))
    np.testing.assert_array_less(a_max[ok], A[ok] * (1 + CLOSED_FORM))
    np.testing.assert_array_less(np.abs(jerks).max(axis=-1)[ok], J[ok] * (1 + CLOSED_FORM))
    if jerk_limit == "exact":  # every jerk phase at +-J
        ramps = [0, 2, 4, 6]
        used = (durations[..., ramps] > 0) & ok[..., np.newaxis]
        limit = np.broadcast_to(J[..., np.newaxis], used.shape)
        np.testing.assert_allclose(np.abs(jerks[..., ramps])[used], limit[used], rtol=1e-15)


def _draw(rng, n, *, rest=False, decades=2.0, distance_decades=(-4.0, 2.0)):
    """Random problems: limits over 2*decades decades, exact zeros, +-V, v0 = vf, v0 = -vf."""
    V, A, J = (10 ** rng.uniform(-decades, decades, n) for _ in range(3))
    natural = V * (V / A + A / J)  # about the distance of a rest-to-rest move at V
    D = rng.choice([-1.0, 1.0], n) * 10 ** rng.uniform(*distance_decades, n) * natural
    D[rng.random(n) < 0.05] = 0.0
    if rest:
        return D, np.zeros(n), np.zeros(n), V, A, J

    def velocity():
        v = rng.uniform(-1, 1, n) * V
        k = rng.random(n)
        v[k < 0.1] = 0.0
        v[(k >= 0.1) & (k < 0.15)] = V[(k >= 0.1) & (k < 0.15)]
        v[(k >= 0.15) & (k < 0.2)] = -V[(k >= 0.15) & (k < 0.2)]
        tiny = (k >= 0.2) & (k < 0.25)
        v[tiny] *= 10 ** rng.uniform(-8, -2, tiny.sum())
        return v

    v0, vf = velocity(), velocity()
    same = rng.random(n) < 0.05
    vf[same] = v0[same]
    opposite = rng.random(n) < 0.05
    vf[opposite] = -v0[opposite]
    return D, v0, vf, V, A, J


def _ruckig_durations(D, v0, vf, V, A, J, minimum_duration=None):
    """Ruckig's duration of each single-DoF problem, NaN where it reports an error or
    where its own trajectory misses the target state by more than 1e-9 (relative):
    with tiny distances ruckig's absolute tolerances take over (it may stop short).
    """
    ruckig = pytest.importorskip("ruckig")
    otg, trajectory = ruckig.Ruckig(1), ruckig.Trajectory(1)
    out = np.full(np.shape(D), np.nan)
    for i in range(out.size):
        inp = ruckig.InputParameter(1)
        inp.current_position = [0.0]
        inp.target_position = [float(D[i])]
        inp.current_velocity = [float(v0[i])]
        inp.target_velocity = [float(vf[i])]
        inp.max_velocity = [float(V[i])]
        inp.max_acceleration = [float(A[i])]
        inp.max_jerk = [float(J[i])]
        if minimum_duration is not None:
            inp.minimum_duration = float(minimum_duration[i])
        try:
            result = otg.calculate(inp, trajectory)
        except (ruckig.RuckigError, ValueError):  # numerically extreme inputs
            continue
        if result != ruckig.Result.Working:
            continue
        position, velocity, _ = trajectory.at_time(trajectory.duration)
        scale = abs(D[i]) + V[i] * trajectory.duration
        if abs(position[0] - D[i]) <= CLOSED_FORM * scale and abs(velocity[0] - vf[i]) <= (
            CLOSED_FORM * V[i]
        ):
            out[i] = trajectory.duration
    return out


def _relative(ours, reference):
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.abs(ours - reference) / reference
    return np.where((ours == 0) & (reference == 0), 0.0, rel)


def _compare_with_ruckig(D, v0, vf, V, A, J):
    """Relative duration differences vs ruckig where it answers (standstills aside).

    A standstill (D = 0, v0 = vf) needs no time here; ruckig moves away and back.
    Ours is never longer; with |D| < 1e-9 and |v0|, |vf| < 1e-6 ruckig's absolute
    tolerances can make its answer longer (seen up to 1e-3 relative), so those are
    left out of the returned differences (the profiles here are checked exact).
    """
    ours = sc.minimum_time(D, v0, vf, V, A, J)
    assert ours.valid.all()
    still = (D == 0) & (v0 == vf)
    assert np.all(ours.duration[still] == 0)
    reference = _ruckig_durations(D, v0, vf, V, A, J)
    known = ~still & np.isfinite(reference)
    assert np.all(ours.duration[known] <= reference[known] * (1 + CLOSED_FORM))
    tiny = (np.abs(D) < 1e-9) & (np.maximum(np.abs(v0), np.abs(vf)) < 1e-6)
    return ours, _relative(ours.duration, reference)[known & ~tiny]


# --------------------------------------------------------------------------- basics
def test_velocity_change_saturates_at_a_squared_over_j():
    A, J = 2.0, 4.0  # saturation at d = A^2 / J = 1
    time, tj, ta = sc.velocity_change([0.0, 0.25, 1.0, 3.0], A, J)
    np.testing.assert_allclose(tj, [0.0, 0.25, 0.5, 0.5])
    np.testing.assert_allclose(ta, [0.0, 0.0, 0.0, 1.0])
    np.testing.assert_allclose(time, [0.0, 0.5, 1.0, 2.0])
    # Continuous (with its slope 1/A) across the saturation threshold.
    below, _, _ = sc.velocity_change(1 - 1e-9, A, J)
    above, _, _ = sc.velocity_change(1 + 1e-9, A, J)
    assert abs((above - below) - 2e-9 / A) < 1e-15


def test_hand_computed_examples():
    # Rest to rest, never saturating: u^3 = 4 D with duration 2 u.
    ph = sc.minimum_time(1.0, 0.0, 0.0, 1.0, 1.0, 1.0)
    assert ph.duration == pytest.approx(2 * 4 ** (1 / 3), rel=1e-15)
    assert ph.tv == 0 and ph.ta1 == 0
    # Long move: reach V = 1 (change of A^2/J: just saturated, 2 s, 1 m each), coast 8 s.
    ph = sc.minimum_time(10.0, 0.0, 0.0, 1.0, 1.0, 1.0)
    assert ph.duration == pytest.approx(12.0, rel=1e-15)
    assert ph.vp == 1.0 and ph.tv == pytest.approx(8.0, rel=1e-15)
    # Both changes saturated, no coast: vp^2 + vp = D  ->  vp = 2 for D = 6.
    ph = sc.minimum_time(6.0, 0.0, 0.0, 10.0, 1.0, 1.0)
    assert ph.vp == pytest.approx(2.0, rel=1e-15)
    assert ph.duration == pytest.approx(6.0, rel=1e-15)
    assert (ph.tj1, ph.ta1, ph.a1, ph.j1) == pytest.approx((1.0, 1.0, 1.0, 1.0))
    assert (ph.tj2, ph.ta2, ph.a2, ph.j2) == pytest.approx((1.0, 1.0, -1.0, -1.0))


def test_standstills_and_exact_zeros():
    zero = sc.minimum_time(0.0, 0.0, 0.0, 1.0, 2.0, 3.0)
    assert zero.valid and zero.duration == 0.0
    durations, jerks = zero.to_phases()
    assert np.all(durations == 0) and durations.shape == (7,) and jerks.shape == (7,)
    # Already there, already moving: nothing to do either.
    moving = sc.minimum_time(0.0, 0.5, 0.5, 1.0, 2.0, 3.0)
    assert moving.valid and moving.duration == 0.0
    # v0 = V, vf = -V, D = 0: the direct reversal covers exactly zero distance.
    flip = sc.minimum_time(0.0, 1.0, -1.0, 1.0, 1.0, 1.0)
    assert flip.duration == pytest.approx(3.0, rel=1e-15)  # change of 2: 2/A + A/J


def test_symmetries():
    rng = np.random.default_rng(7)
    D, v0, vf, V, A, J = _draw(rng, 2000)
    ph = sc.minimum_time(D, v0, vf, V, A, J)
    mirrored = sc.minimum_time(-D, -v0, -vf, V, A, J)
    reversed_ = sc.minimum_time(D, vf, v0, V, A, J)
    np.testing.assert_allclose(mirrored.duration, ph.duration, rtol=1e-12)
    np.testing.assert_allclose(reversed_.duration, ph.duration, rtol=1e-12)
    coasting = ph.tv > 1e-9 * ph.duration  # the peak is unique then
    assert np.all(np.abs(mirrored.vp + ph.vp)[coasting] <= 1e-12 * V[coasting])


def test_broadcasting_and_scalars():
    ph = sc.minimum_time(np.array([[1.0], [-2.0], [0.0]]), 0.0, np.array([0.0, 0.5]), 1.0, 1.0, 1.0)
    assert ph.duration.shape == (3, 2)
    assert ph.to_phases()[0].shape == (3, 2, 7)
    scalar = sc.minimum_time(1.0, 0.0, 0.0, 1.0, 1.0, 1.0)
    assert np.ndim(scalar.duration) == 0 and scalar.to_phases()[1].shape == (7,)
    one = sc.minimum_time(-2.0, 0.0, 0.5, 1.0, 1.0, 1.0)
    assert ph.duration[1, 1] == one.duration
    # More elements than one block: same answers as element by element.
    rng = np.random.default_rng(3)
    args = _draw(rng, 3 * sc._BLOCK + 5)
    whole = sc.minimum_time(*args)
    part = sc.minimum_time(*(a[sc._BLOCK - 2 : sc._BLOCK + 3] for a in args))
    np.testing.assert_array_equal(whole.duration[sc._BLOCK - 2 : sc._BLOCK + 3], part.duration)


def test_overshoot_cases():
    # Braking distance (0.5 * 1 * Tc(1) = 1) longer than D: go past and come back.
    args = [np.array([x]) for x in (0.2, 1.0, 0.0, 1.0, 1.0, 1.0)]
    ph = sc.minimum_time(*args)
    assert ph.valid.all() and ph.vp[0] < 0
    _assert_profiles(ph, *args)
    # Final velocity pointing backwards with a forward move.
    ph = sc.minimum_time(1.0, 0.0, -0.5, 1.0, 1.0, 1.0)
    assert ph.valid and ph.vp > 0 and ph.a2 < 0


# ------------------------------------------------------------------ profile checks
@pytest.mark.parametrize("rest", [True, False])
def test_profiles_reach_the_target_within_the_limits(rest):
    rng = np.random.default_rng(11 if rest else 12)
    args = _draw(rng, 20000, rest=rest, decades=3.0, distance_decades=(-8.0, 3.0))
    ph = sc.minimum_time(*args)
    assert ph.valid.all()
    _assert_profiles(ph, *args, jerk_limit="exact")


@st.composite
def problems(draw):
    V = draw(st.floats(1e-2, 1e2))
    A = draw(st.floats(1e-2, 1e2))
    J = draw(st.floats(1e-2, 1e2))
    # Magnitudes from 1e-12 up, or exact zeros (see the module notes on ranges).
    edge = st.sampled_from([0.0, 1.0, -1.0])
    fraction = st.floats(1e-12, 1.0) | st.floats(-1.0, -1e-12)
    v0 = V * draw(edge | fraction)
    vf = V * draw(edge | fraction)
    D = draw(st.just(0.0) | st.floats(1e-12, 1e3) | st.floats(-1e3, -1e-12))
    return tuple(np.array([x]) for x in (D, v0, vf, V, A, J))


@given(problems())
def test_property_profiles_are_feasible(problem):
    ph = sc.minimum_time(*problem)
    assert ph.valid.all()
    _assert_profiles(ph, *problem)


def test_fast_path_matches_every_region():
    """The searched structures lose nothing against all 16 sign/saturation regions."""
    rng = np.random.default_rng(5)
    D, v0, vf, V, A, J = _draw(rng, 20000)
    ph = sc.minimum_time(D, v0, vf, V, A, J)
    vs, ds = A * A / J, A**3 / J**2
    every = sc._every_region_durations(D / ds, v0 / vs, vf / vs, V / vs).min(axis=-1) * (A / J)
    every = np.where((D == 0) & (v0 == vf), 0.0, every)
    assert np.all(np.isfinite(every))
    assert np.max(_relative(ph.duration, every)) < 1e-10


# --------------------------------------------------------------------- ruckig oracle
def test_rest_to_rest_matches_ruckig():
    rng = np.random.default_rng(21)
    _, rel = _compare_with_ruckig(*_draw(rng, 3000, rest=True))
    assert rel.size > 2700  # ruckig errs on a few percent of these draws
    assert rel.max() < CLOSED_FORM


def test_moving_boundaries_match_ruckig():
    rng = np.random.default_rng(22)
    _, rel = _compare_with_ruckig(*_draw(rng, 3000))
    assert rel.size > 2700
    assert rel.max() < CLOSED_FORM


def test_never_slower_than_ruckig_on_extreme_inputs():
    """Limits over 8 decades, distances over 11: ruckig sometimes errs or is slower.

    The profiles here are checked feasible and never longer than a ruckig trajectory
    that reaches its target (to 1e-8: ruckig's own target error of up to 1e-9 of
    ``|D| + V T`` moves its duration by as much when ``D`` is small beside ``v T``).
    """
    rng = np.random.default_rng(23)
    args = _draw(rng, 3000, decades=4.0, distance_decades=(-8.0, 3.0))
    ours = sc.minimum_time(*args)
    assert ours.valid.all()
    _assert_profiles(ours, *args)
    reference = _ruckig_durations(*args)
    still = (args[0] == 0) & (args[1] == args[2])
    known = np.isfinite(reference) & ~still
    assert known.sum() > 2500
    assert np.all(ours.duration[known] <= reference[known] * (1 + 1e-8))


@pytest.mark.slow
def test_sweep_matches_ruckig():
    rng = np.random.default_rng(24)
    rest = _draw(rng, 5000, rest=True)
    moving = _draw(rng, 15000)
    args = [np.concatenate([a, b]) for a, b in zip(rest, moving, strict=True)]
    ours, rel = _compare_with_ruckig(*args)
    _assert_profiles(ours, *args, jerk_limit="exact")
    assert rel.size > 18000
    assert rel.max() < CLOSED_FORM


# ------------------------------------------------------------------ fixed duration
def _stretched(rng, args):
    """Durations from the minimum (10 % exactly) up to 11 times it."""
    n = args[0].size
    minimum = sc.minimum_time(*args).duration
    factor = np.where(rng.random(n) < 0.1, 1.0, 1 + 10 ** rng.uniform(-6, 1, n))
    return minimum * factor


def test_fixed_duration_rest_to_rest_always_succeeds():
    rng = np.random.default_rng(31)
    args = _draw(rng, 20000, rest=True)
    T = _stretched(rng, args)
    ph = sc.fixed_duration(T, *args)
    assert ph.valid.all()
    np.testing.assert_array_equal(ph.duration, T)
    _assert_profiles(ph, *args, jerk_limit="exact")
    # Full jerk and acceleration limits, a lower peak velocity than the minimum time's.
    fastest = sc.minimum_time(*args)
    assert np.all(np.abs(ph.vp) <= np.abs(fastest.vp) * (1 + 1e-12) + 1e-300)


def test_fixed_duration_at_the_minimum_is_the_minimum_profile():
    rng = np.random.default_rng(32)
    args = _draw(rng, 5000)
    fastest = sc.minimum_time(*args)
    ph = sc.fixed_duration(fastest.duration, *args)
    assert ph.valid.all()
    _assert_profiles(ph, *args)


def test_fixed_duration_moving_boundaries():
    rng = np.random.default_rng(33)
    args = _draw(rng, 20000)
    T = _stretched(rng, args)
    ph = sc.fixed_duration(T, *args)
    assert ph.valid.mean() > 0.99
    _assert_profiles(ph, *args)


def test_fixed_duration_fails_only_where_ruckig_cannot_meet_the_duration():
    """Invalid elements: ruckig, asked for at least T, needs longer (a blocked interval)."""
    rng = np.random.default_rng(34)
    args = _draw(rng, 20000)
    T = _stretched(rng, args)
    ph = sc.fixed_duration(T, *args)
    failed = ~ph.valid
    reference = _ruckig_durations(*(a[failed] for a in args), minimum_duration=T[failed])
    known = np.isfinite(reference)
    assert np.all(reference[known] > T[failed][known] * (1 + 1e-6))


def test_fixed_duration_fills_the_gap_with_a_lower_jerk():
    # v0 = 0 -> vf = 1 (A = J = 1) over D = 1.2 in T = 2.5 s: the fastest changes to
    # any vp between 0 and 1 would leave a negative coast, so the jerk is lowered.
    args = [np.array([x]) for x in (1.2, 0.0, 1.0, 10.0, 1.0, 1.0)]
    assert sc.minimum_time(*args).duration < 2.5
    ph = sc.fixed_duration(2.5, *args)
    assert ph.valid.all() and np.all(ph.duration == 2.5)
    assert 0 < abs(ph.j1[0]) < 1 and abs(ph.j2[0]) == abs(ph.j1[0]) and ph.tv[0] == 0
    _assert_profiles(ph, *args)


def test_fixed_duration_below_the_minimum_is_invalid():
    args = (5.0, 0.0, 0.0, 1.0, 1.0, 1.0)
    T = sc.minimum_time(*args).duration
    assert not sc.fixed_duration(T * (1 - 1e-6), *args).valid
    assert sc.fixed_duration(0.0, 0.0, 0.3, 0.3, 1.0, 1.0, 1.0).valid  # standstill
    assert not sc.fixed_duration(0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 1.0).valid
