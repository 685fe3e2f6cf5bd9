"""Acceleration-limited law on problems where the reference's closed forms fail.

ruckig's tolerances are absolute (1e-8 in position): a long coast back at a low
speed limit, a duration that dwarfs the ramps, or rounding of a peak velocity onto
a boundary velocity make every reference candidate fail although a profile exists
(ruckig fails on these too). :mod:`trajkit.profiles._kernels.acceleration_limited`
then builds the profiles again in the move's own units, polished; accepted
profiles of a given duration are polished too. Each test calls the kernels on
records directly and checks success, durations, targets (to about 1e-12 of the
move's size) and limits.
"""

import math

import numpy as np
import pytest

from trajkit.profiles._kernels import acceleration_limited as al
from trajkit.profiles._kernels.jerk_fastest import is_blocked
from trajkit.profiles._kernels.layout import PF, SIZE, T_SUM, A, P, T, V
from trajkit.profiles._kernels.profile import set_boundary

INF = math.inf


def record(p0, v0, pf, vf):
    prof = np.zeros(SIZE)
    set_boundary(prof, float(p0), float(v0), 0.0, float(pf), float(vf), 0.0)
    return prof


def fastest(p0, v0, pf, vf, v_max, v_min, a_max, a_min):
    prof = record(p0, v0, pf, vf)
    valid = np.zeros((6, SIZE))
    block = np.zeros((3, SIZE))
    block_times = np.zeros(5)
    limits = (float(v_max), float(v_min), float(a_max), float(a_min))
    ok = al.fastest(prof, *limits, valid, block, block_times)
    return ok, block, block_times


def timed(p0, v0, pf, vf, tf, v_max, v_min, a_max, a_min):
    prof = record(p0, v0, pf, vf)
    limits = (float(v_max), float(v_min), float(a_max), float(a_min))
    return al.timed(prof, float(tf), *limits), prof


def assert_profile(prof, p0, v0, pf, vf, v_max, v_min, a_max, a_min, tf=None, rel=1e-12):
    """Targets exact to ``rel`` of the move's size, limits kept, states consistent."""
    t = prof[T : T + 7]
    assert np.all(t >= 0.0)
    total = prof[T_SUM + 6]
    assert total == pytest.approx(t.sum(), rel=1e-14)
    if tf is not None:
        assert total == pytest.approx(tf, rel=1e-14)
    positions = prof[P : P + 8]
    velocities = prof[V : V + 8]
    size = max(abs(pf - p0), float(np.max(np.abs(positions - p0))), 1e-300)
    speed = max(abs(v0), abs(vf), float(np.max(np.abs(velocities))), 1e-300)
    assert prof[P] == p0
    assert abs(prof[P + 7] - pf) <= rel * size
    assert abs(prof[V + 7] - vf) <= rel * speed
    tol_v = 1e-12 * max(abs(v_max), abs(v_min))
    tol_a = 1e-12 * max(abs(a_max), abs(a_min))
    for k in range(8):
        assert v_min - tol_v <= velocities[k] <= v_max + tol_v
    p, v = p0, v0
    for i in range(7):
        a = prof[A + i]
        assert a_min - tol_a <= a <= a_max + tol_a
        # Integrating each phase independently lands on the next edge.
        p, v = p + t[i] * (v + t[i] * a / 2.0), v + t[i] * a
        assert abs(p - prof[P + i + 1]) <= 1e-12 * size
        assert abs(v - prof[V + i + 1]) <= 1e-12 * speed


def test_brake_past_the_target_and_come_back_slowly():
    # From 70 rad/s at 0.125 rad/s^2: 560 s and 19600 rad of braking, then back at
    # the 0.01 rad/s the lower limit allows: 1.96e6 s. The reference misses the
    # target by 1.0025e-8 rad (its tolerance: 1e-8).
    pb = (0.0, 70.0, 0.0, 0.0, 70.0, -0.01, 0.125, -0.125)
    ok, block, bt = fastest(*pb)
    assert ok
    expected = 70.01 / 0.125 + 0.01 / 0.125 + 19600.0 / 0.01 - 0.01 / 0.125
    assert bt[0] == pytest.approx(expected, rel=1e-12)
    assert math.isinf(bt[1]) and math.isinf(bt[3])  # ending at rest blocks nothing
    assert_profile(block[0], *pb)
    assert block[0, V + 1] == pytest.approx(-0.01, rel=1e-14)


def test_synchronized_to_a_much_longer_move():
    # Joint 2 (0 -> 0, rest -> 64 rad/s, a = 0.25) needs 33025 s; joint 1 (rest ->
    # 1 rad/s, v_min = -0.25) must take as long: it backs off at 6e-5 rad/s for
    # 33020 s first. The reference's coast quadratic loses 1.2e-8 rad to cancellation.
    ok, _block, bt = fastest(0.0, 0.0, 0.0, 64.0, 64.0, -0.25, 0.25, -0.25)
    assert ok
    assert bt[0] == pytest.approx(33025.0, rel=1e-12)
    pb = (0.0, 0.0, 0.0, 1.0, 1.0, -0.25, 0.25, -0.25)
    ok, _own, own_bt = fastest(*pb)
    assert ok and own_bt[0] == pytest.approx(13.0, rel=1e-12)
    assert not is_blocked(own_bt, bt[0])
    ok, prof = timed(*pb[:4], bt[0], *pb[4:])
    assert ok
    assert_profile(prof, *pb, tf=bt[0])
    assert prof[PF] == prof[P + 7]
    # The gentlest profile: back off at the slowest speed that fits.
    u = prof[V + 1]
    assert -1e-4 < u < 0.0
    assert -u * bt[0] == pytest.approx(2.0, rel=1e-3)


@pytest.mark.parametrize(
    "pb, stretch",
    [
        # Rest to rest, twice and 3.56 times the minimum: the reference's accepted
        # profile overshot by 1e-8 rad (its coast root cancels against tf).
        ((0.0, 0.0, 9.0, 0.0, 0.015625, -0.015625, 68.0, -68.0), 2.0),
        ((8.63256067573844, 0.0, 0.0, 0.0, 0.01, -0.01, 33.11591618, -11.33765701), 3.563585),
    ],
)
def test_given_duration_rest_to_rest_is_exact(pb, stretch):
    ok, _block, bt = fastest(*pb)
    assert ok
    tf = bt[0] * stretch
    ok, prof = timed(*pb[:4], tf, *pb[4:])
    assert ok
    assert_profile(prof, *pb, tf=tf, rel=4e-15)
    # Monotone: no overshoot of either end (beyond rounding).
    slack = 4e-15 * abs(pb[2] - pb[0])
    lo, hi = min(pb[0], pb[2]) - slack, max(pb[0], pb[2]) + slack
    assert np.all(prof[P : P + 8] >= lo) and np.all(prof[P : P + 8] <= hi)


def test_peak_rounded_onto_the_boundary_velocity():
    # 0 rad to go at the velocity limit at both ends: standing still for no time
    # is a profile; any other duration needs a reversal (208 s). The reference's
    # peak velocity sqrt(v^2) is off by an ulp, so its zero profile has a ramp of
    # -1e-14 s and its candidates no longer pair up.
    v = 25.885097933973803
    pb = (0.0, v, 0.0, v, v, -v, 53.1328125, -0.25)
    ok, block, bt = fastest(*pb)
    assert ok
    assert bt[0] == 0.0
    reversal = 2.0 * v / 0.25 + 2.0 * v / 53.1328125
    assert bt[2] == pytest.approx(reversal, rel=1e-12)
    assert is_blocked(bt, reversal / 2.0)
    assert not is_blocked(bt, reversal * 1.5)
    assert_profile(block[0], *pb)
    for k in (1, 2):
        if not math.isinf(bt[2 * k]):
            assert_profile(block[k], *pb)
    ok, prof = timed(*pb[:4], reversal * 1.5, *pb[4:])
    assert ok
    assert_profile(prof, *pb, tf=reversal * 1.5)


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_subnormal_distance_with_a_moving_end(sign):
    # 1e-313 rad to go, ending at 1e-3 rad/s: the magnitudes are planned in units of
    # their own (the rescaled record keeps every relation exact).
    pb = (0.0, 0.0, sign * 1e-313, sign * 1e-3, 1.0, -1.0, 1.0, -1.0)
    ok, block, bt = fastest(*pb)
    assert ok
    assert bt[0] > 0.0
    assert_profile(block[0], *pb)
    for tf in (bt[0] * 1.5, 10.0):
        if is_blocked(bt, tf):
            continue
        ok, prof = timed(*pb[:4], tf, *pb[4:])
        assert ok
        assert_profile(prof, *pb, tf=tf)


def test_long_move_with_a_tiny_reversal():
    # At rest at 0, end at 0 moving at v_max = 0.01 after 400 s: dip to -6.9e-9 rad/s.
    pb = (0.0, 0.0, 0.0, 0.01, 0.01, -0.01, 18.0, -18.0)
    ok, prof = timed(*pb[:4], 400.0, *pb[4:])
    assert ok
    assert_profile(prof, *pb, tf=400.0)
    assert prof[V + 1] == pytest.approx(-0.01 * 0.01 / (2 * 18.0) / 400.0, rel=1e-6)


def test_durations_near_a_blocked_interval():
    # Moving at about -4 rad/s at both ends, 1.06 rad to go, |a| <= 0.155: only a
    # sliver above the optimum (0.2616 s) or far longer durations work. Every
    # duration the blocked intervals allow has a profile; those inside do not.
    pb = (
        1.26570265268726,
        -4.057077775092551,
        0.2084794786249491,
        -4.0212046498840435,
        5.959604284707145,
        -5.959604284707145,
        0.1550429572337289,
        -0.1550429572337289,
    )
    ok, block, bt = fastest(*pb)
    assert ok
    assert bt[0] == pytest.approx(0.26160155153880055, rel=1e-12)
    assert bt[1] < bt[2] < INF
    for k in range(3):
        if k == 0 or not math.isinf(bt[2 * k]):
            assert_profile(block[k], *pb, rel=1e-11)
    dt = 0.015174096390380996
    checked = 0
    for tf in [bt[0], bt[1], bt[2], *(dt * n for n in range(17, 7000, 97))]:
        ok, prof = timed(*pb[:4], tf, *pb[4:])
        assert ok == (not is_blocked(bt, tf) or tf == bt[1]), tf
        if ok:
            assert_profile(prof, *pb, tf=tf, rel=1e-11)
            checked += 1
    assert checked > 3


@pytest.mark.parametrize(
    "pb",
    [
        (
            3350.57494461715,
            1746.2069507375686,
            -5651.5581499454165,
            1216.3585022366485,
            3869.342477705742,
            -6208.350596316244,
            5607.418173878758,
            -14470.89438787967,
        ),
        (
            408085.7492682311,
            134279.35187946382,
            -185765.34958836314,
            0.0,
            1143763.777747081,
            -13321.965759373961,
            827436.819771021,
            -1045516.0394853291,
        ),
    ],
)
def test_extra_successes_match_the_reference_in_other_units(pb):
    # Positions of 1e3 to 1e5 rad: ruckig fails (absolute tolerances), we succeed,
    # and ruckig agrees on the problem with lengths scaled by a power of two (an
    # exact change of units that leaves durations alone).
    ruckig = pytest.importorskip("ruckig", reason="ruckig (test oracle) is not installed")
    ok, block, bt = fastest(*pb)
    assert ok
    assert_profile(block[0], *pb, rel=1e-11)
    s = 2.0 ** -round(math.log2(abs(pb[2] - pb[0])))
    p0, v0, pf, vf, v_max, v_min, a_max, a_min = (x * s for x in pb)
    inp = ruckig.InputParameter(1)
    inp.current_position = [p0]
    inp.current_velocity = [v0]
    inp.current_acceleration = [0.0]
    inp.target_position = [pf]
    inp.target_velocity = [vf]
    inp.target_acceleration = [0.0]
    inp.max_velocity = [v_max]
    inp.min_velocity = [v_min]
    inp.max_acceleration = [a_max]
    inp.min_acceleration = [a_min]
    inp.max_jerk = [INF]
    traj = ruckig.Trajectory(1)
    assert ruckig.Ruckig(1).calculate(inp, traj) == ruckig.Result.Working
    assert bt[0] == pytest.approx(traj.duration, rel=1e-9)
