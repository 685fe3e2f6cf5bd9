"""The velocity interface (reach vf, af; no target position) against ruckig.

Problems are drawn as ruckig's own test randomizer draws them (test/randomizer.hpp,
test/test_target.cpp "velocity-random-3" and "velocity-second-random-3"):
velocities and accelerations normal (sigma 0.8) or exactly zero with some
probability, limits uniform on [0.08, 16] (the acceleration limit offset by |af|).
The start acceleration is kept within the limits, so no brake pre-profile is
involved.

Step 1 (``*_fastest``) is compared with ruckig's duration of the one-DoF problem;
step 2 (``*_timed``) and the blocked intervals through a two-DoF problem whose
second DoF is a velocity change from rest of chosen duration: ruckig then
synchronizes the first DoF to that duration or, if our blocked interval says it
cannot take it, to the interval's right end. Durations must agree to 1e-9
(relative), phase durations too.

Last full run: ``TRAJKIT_ORACLE_PROBLEMS=300000`` (slow sweeps), plus scratch
families with limits on [10, 1e6], states exactly on a limit, pure coasts,
limit ratios of 1e5 and limits near 1e-3 (4000 each): no difference.

Where one library succeeds and the other fails: none met in the draws below (the
tests assert so, and the sweeps report any they meet). The ruckig Python package
(0.19) keeps stale state the tests avoid by building a fresh ``Ruckig`` per
problem: its acceleration-limited step 1 (and the ``jmax = 0`` branch of the
jerk-limited one) sets the minimum profile but not the blocked intervals, so a
reused ``Ruckig`` synchronizes around intervals left by an earlier problem (met:
a problem whose own minimum was 1.43 s synchronized to 9.21 s, an earlier
problem's interval end). Our kernels write every output field each call. By
construction we keep ruckig's behaviour where it is questionable:

* with ``a_max = 0`` (or ``a_min = 0``) the acceleration-limited fastest law
  divides 0/0 for ``vf == v0`` and fails, as ruckig does, although standing
  still would do (see ``test_zero_limits``).
"""

import math
import os

import numpy as np
import pytest

from trajkit.profiles._kernels import velocity_target as vt
from trajkit.profiles._kernels.jerk_fastest import is_blocked
from trajkit.profiles._kernels.layout import PF, SIZE, T_SUM, A, J, P, T, V
from trajkit.profiles._kernels.profile import duration, set_boundary, state_at

ruckig = pytest.importorskip("ruckig", reason="ruckig (test oracle) is not installed")
from ruckig import (  # noqa: E402
    ControlInterface,
    InputParameter,
    Result,
    Ruckig,
    RuckigError,
    Trajectory,
)

INF = math.inf
EPS = 2.220446049250313e-16
SEED = 20240612
N_PROBLEMS = 3000
MAX_DURATION = 7.6e3  # ruckig refuses longer trajectories
N_SLOW = int(os.environ.get("TRAJKIT_ORACLE_PROBLEMS", "20000"))


def close(ours, theirs, rel=1e-9, abs_tol=1e-12):
    return math.isclose(ours, theirs, rel_tol=rel, abs_tol=abs_tol)


def same_times(ours, theirs, tf):
    """Phase durations equal to 1e-9 of the duration (plain loop: this is hot)."""
    tol = 1e-9 * (1.0 + tf)
    return all(abs(a - b) <= tol for a, b in zip(ours, theirs, strict=True))


# --------------------------------------------------------------------------- problems


def draw(rng, asymmetric, jerk=True, moving=False):
    """One velocity-interface problem ``(v0, a0, vf, af, a_max, a_min, j_max)``.

    ``moving`` draws large target accelerations under low limits instead, where
    blocked intervals are common.
    """
    hi = 4.0 if moving else 16.0
    while True:
        if moving:
            v0 = rng.normal(0.0, 0.8)
            vf = v0 + rng.normal(0.0, 0.3)
            a0, af = rng.normal(0.0, 1.5, 2)
        else:
            v0 = rng.normal(0.0, 0.8) if rng.random() < 0.9 else 0.0
            a0 = rng.normal(0.0, 0.8) if rng.random() < 0.8 else 0.0
            vf = rng.normal(0.0, 0.8) if rng.random() < 0.7 else 0.0
            af = rng.normal(0.0, 0.8) if rng.random() < 0.6 else 0.0
        if not jerk:
            a0 = af = 0.0
        a_max = rng.uniform(0.08, hi) + abs(af)
        a_min = -(rng.uniform(0.08, hi) + abs(af)) if asymmetric else -a_max
        j_max = rng.uniform(0.08, hi) if jerk else INF
        if a_min <= a0 <= a_max:
            return (v0, a0, vf, af, a_max, a_min, j_max)


def draw_blocked(rng, asymmetric):
    """A moving draw for which our step 1 reports a blocked interval (resampled)."""
    while True:
        pb = draw(rng, asymmetric, moving=True)
        if not math.isinf(ours_fastest(pb)[2][2]):
            return pb


def scaled(pb, s):
    """Velocities and accelerations scaled by ``s`` (durations are unchanged)."""
    v0, a0, vf, af, a_max, a_min, j_max = pb
    return (v0 * s, a0 * s, vf * s, af * s, a_max * s, a_min * s, j_max * s)


def record(pb):
    v0, a0, vf, af = pb[:4]
    prof = np.zeros(SIZE)
    # No position target: pf is left at zero and never checked.
    set_boundary(prof, 0.0, v0, a0, 0.0, vf, af)
    return prof


def ours_fastest(pb):
    prof = record(pb)
    valid = np.zeros((6, SIZE))
    block = np.zeros((3, SIZE))
    block_times = np.zeros(5)
    _v0, _a0, _vf, _af, a_max, a_min, j_max = pb
    if math.isinf(j_max):
        ok = vt.acceleration_fastest(prof, a_max, a_min, valid, block, block_times)
    else:
        ok = vt.jerk_fastest(prof, a_max, a_min, j_max, valid, block, block_times)
    return ok, block, block_times


def ours_timed(prof, tf, pb):
    a_max, a_min, j_max = pb[4:]
    if math.isinf(j_max):
        return vt.acceleration_timed(prof, tf, a_max, a_min)
    return vt.jerk_timed(prof, tf, a_max, a_min, j_max)


def ruckig_solve(pbs):
    """Ruckig's trajectory for problems (one per DoF); None where it fails."""
    n = len(pbs)
    inp = InputParameter(n)
    inp.control_interface = ControlInterface.Velocity
    cols = list(zip(*pbs, strict=True))
    inp.current_position = [0.0] * n
    inp.current_velocity = list(cols[0])
    inp.current_acceleration = list(cols[1])
    inp.target_velocity = list(cols[2])
    inp.target_acceleration = list(cols[3])
    inp.max_velocity = [1e9] * n
    inp.max_acceleration = list(cols[4])
    inp.min_acceleration = list(cols[5])
    inp.max_jerk = list(cols[6])
    traj = Trajectory(n)
    try:
        result = Ruckig(n).calculate(inp, traj)
    except RuckigError:
        return None
    except ValueError:
        # Durations beyond ruckig's cap (7.6e3 s) return a code its enum lacks.
        return None
    return traj if result == Result.Working else None


def from_rest(t1, jerk):
    """A second DoF whose fastest velocity change from rest takes ``t1``."""
    if jerk:
        # Triangle in acceleration at j = 1 reaching t1/2: vd = t1^2 / 4.
        return (0.0, 0.0, t1 * t1 / 4.0, 0.0, 1e6, -1e6, 1.0)
    return (0.0, 0.0, t1, 0.0, 1.0, -1.0, INF)


def sync_time(block_times):
    """Ruckig's synchronization: the first candidate duration no DoF blocks."""
    n = len(block_times)
    cands = sorted((bt[k], k // 2, d) for d, bt in enumerate(block_times) for k in (0, 2, 4))
    for t, kind, d in cands[n - 1 :]:
        if math.isinf(t) or any(is_blocked(bt, t) for bt in block_times):
            continue
        return t, kind, d
    return None


# --------------------------------------------------------------------------- checks


def assert_valid(prof, pb, tf=None):
    """Targets reached and limits kept at every phase edge and inside the phases."""
    v0, a0, vf, af, a_max, a_min, j_max = pb
    jerk = not math.isinf(j_max)
    t = prof[T : T + 7]
    assert np.all(t >= 0.0)
    assert close(prof[T_SUM + 6], t.sum(), 1e-12, 1e-15)
    if tf is not None:
        assert close(prof[T_SUM + 6], tf)
    assert prof[V] == v0
    assert abs(prof[V + 7] - vf) < 1e-8
    tol_a = 1e-12 + 1e-12 * max(abs(a_max), abs(a_min))
    if jerk:
        assert prof[A] == a0
        assert abs(prof[A + 7] - af) < 1e-10
        # Acceleration is piecewise linear: its extremes sit at phase edges.
        for k in range(8):
            assert a_min - tol_a <= prof[A + k] <= a_max + tol_a
        for i in range(7):
            assert abs(prof[J + i]) <= j_max * (1.0 + 1e-12) + 1e-12
    else:
        # One phase of constant acceleration, a[1] (a[i] is held during phase i).
        assert np.count_nonzero(t) <= 1 and t[0] == 0.0
        assert a_min - tol_a <= prof[A + 1] <= a_max + tol_a
    total = prof[T_SUM + 6]
    if total > 0.0:
        for s in np.linspace(0.0, total, 11):
            _, _, a, j = state_at(prof, s)
            assert a_min - tol_a <= a <= a_max + tol_a
            assert abs(j) <= j_max * (1.0 + 1e-12) + 1e-12
    p, v, a, _ = state_at(prof, total)
    assert abs(v - vf) < 1e-8
    assert close(p, prof[P + 7], 1e-12)
    if jerk:
        assert abs(a - af) < 1e-10


# --------------------------------------------------------------------------- step 1


def run_fastest(n, seed, jerk):
    rng = np.random.default_rng(seed)
    one_sided = []
    intervals = 0
    for i in range(n):
        if jerk and i % 4 == 3:
            pb = draw_blocked(rng, asymmetric=i % 2 == 1)
        else:
            pb = draw(rng, asymmetric=i % 2 == 1, jerk=jerk, moving=jerk and i % 4 == 2)
        ok, block, bt = ours_fastest(pb)
        traj = ruckig_solve([pb])
        if traj is None and ok and bt[0] > MAX_DURATION:
            continue
        if traj is None or not ok:
            one_sided.append((pb, ok, traj is not None))
            continue
        assert close(bt[0], traj.duration), (pb, bt[0], traj.duration)
        assert same_times(block[0, T : T + 7], traj.profiles[0][0].t, bt[0]), pb
        assert_valid(block[0], pb)
        # The same profile, hence the same position reached.
        theirs = traj.profiles[0][0]
        assert close(block[0, P + 7], theirs.p[7], 1e-9, 1e-9)
        if not math.isinf(bt[2]):
            intervals += 1
            assert bt[0] <= bt[1] <= bt[2]
            assert_valid(block[1], pb)
            assert close(duration(block[1]), bt[2])
            # Blocked means no profile of that duration exists: step 2 agrees.
            assert not ours_timed(block[0].copy(), (bt[1] + bt[2]) / 2.0, pb)
    return one_sided, intervals


@pytest.mark.parametrize("jerk", [True, False], ids=["jerk", "acceleration"])
def test_fastest_matches_ruckig(jerk):
    one_sided, intervals = run_fastest(N_PROBLEMS, SEED + jerk, jerk)
    assert one_sided == []
    if jerk:
        # Target accelerations make blocked intervals: both paths run.
        assert intervals > N_PROBLEMS // 5
    else:
        assert intervals == 0


@pytest.mark.slow
@pytest.mark.parametrize("jerk", [True, False], ids=["jerk", "acceleration"])
def test_fastest_matches_ruckig_sweep(jerk):
    one_sided, _ = run_fastest(N_SLOW, SEED + 10 + jerk, jerk)
    assert one_sided == []


# --------------------------------------------------------------------------- step 2


def run_synchronized(n, seed, jerk):
    """Two DoFs: our blocks and timed profiles against ruckig's synchronization."""
    rng = np.random.default_rng(seed)
    one_sided = []
    counts = {"timed": 0, "timed_rest": 0, "interval_end": 0}
    for i in range(n):
        if jerk and i % 4 == 3:
            pb = draw_blocked(rng, asymmetric=i % 2 == 0)
        else:
            pb = draw(rng, asymmetric=i % 2 == 0, jerk=jerk, moving=jerk and i % 4 == 2)
        ok, block, bt = ours_fastest(pb)
        assert ok
        if not math.isinf(bt[2]) and rng.random() < 0.6:
            t1 = rng.uniform(bt[1], bt[2])
        else:
            t1 = bt[0] * rng.uniform(1.0, 4.0) + rng.uniform(0.0, 0.5)
        pb1 = from_rest(t1, jerk)
        ok1, block1, bt1 = ours_fastest(pb1)
        assert ok1
        assert close(bt1[0], t1, 1e-12)
        traj = ruckig_solve([pb, pb1])
        sync = sync_time([bt, bt1])
        if traj is None and sync is not None and sync[0] > MAX_DURATION:
            continue
        if traj is None or sync is None:
            one_sided.append((pb, t1, sync is not None, traj is not None))
            continue
        tf, kind, limiting = sync
        assert close(tf, traj.duration), (pb, t1, tf, traj.duration)
        independent = traj.independent_min_durations
        assert close(independent[0], bt[0]) and close(independent[1], bt1[0])
        for d, (problem, blk, btd) in enumerate(((pb, block, bt), (pb1, block1, bt1))):
            theirs = traj.profiles[0][d]
            if d == limiting:
                ours = blk[kind]
                counts["interval_end"] += kind > 0
            elif any(abs(tf - btd[k]) < 2 * EPS for k in (0, 2, 4)):
                continue
            else:
                ours = blk[0].copy()
                assert ours_timed(ours, tf, problem), (problem, tf)
                assert ours[PF] == ours[P + 7]
                counts["timed" if d == 0 else "timed_rest"] += 1
            assert_valid(ours, problem, tf)
            assert same_times(ours[T : T + 7], theirs.t, tf), (problem, tf)
            assert close(ours[P + 7], theirs.p[7], 1e-9, 1e-9)
    return one_sided, counts


@pytest.mark.parametrize("jerk", [True, False], ids=["jerk", "acceleration"])
def test_timed_and_intervals_match_ruckig(jerk):
    one_sided, counts = run_synchronized(N_PROBLEMS, SEED + 2 + jerk, jerk)
    assert one_sided == []
    assert counts["timed"] > 0.6 * N_PROBLEMS
    if jerk:
        assert counts["interval_end"] > N_PROBLEMS // 10


@pytest.mark.slow
@pytest.mark.parametrize("jerk", [True, False], ids=["jerk", "acceleration"])
def test_timed_and_intervals_match_ruckig_sweep(jerk):
    one_sided, _ = run_synchronized(N_SLOW, SEED + 20 + jerk, jerk)
    assert one_sided == []


# --------------------------------------------------------------------------- special cases


@pytest.mark.parametrize("scale", [1e-3, 1e3, 1e5])
@pytest.mark.parametrize("jerk", [True, False], ids=["jerk", "acceleration"])
def test_scales(scale, jerk):
    rng = np.random.default_rng(SEED + 4)
    for i in range(200):
        pb = scaled(draw(rng, asymmetric=i % 2 == 0, jerk=jerk), scale)
        ok, _, bt = ours_fastest(pb)
        traj = ruckig_solve([pb])
        assert ok == (traj is not None), pb
        if ok:
            assert close(bt[0], traj.duration), (pb, bt[0], traj.duration)


@pytest.mark.parametrize("jerk", [True, False], ids=["jerk", "acceleration"])
def test_tiny_scale_same_outcome_as_ruckig(jerk):
    # At 1e-7 the absolute 1e-8 velocity tolerance is a sizeable fraction of the
    # change: both libraries must still agree on success and duration.
    rng = np.random.default_rng(SEED + 5)
    for i in range(200):
        pb = scaled(draw(rng, asymmetric=i % 2 == 0, jerk=jerk), 1e-7)
        ok, _, bt = ours_fastest(pb)
        traj = ruckig_solve([pb])
        assert ok == (traj is not None), pb
        if ok:
            assert close(bt[0], traj.duration, 1e-6), (pb, bt[0], traj.duration)


@pytest.mark.parametrize("jerk", [True, False], ids=["jerk", "acceleration"])
def test_zero_change(jerk):
    j_max = 2.0 if jerk else INF
    for pb in [(0.7, 0.0, 0.7, 0.0, 1.0, -1.0, j_max), (0.0, 0.0, 0.0, 0.0, 3.0, -0.5, j_max)]:
        ok, _block, bt = ours_fastest(pb)
        assert ok
        assert bt[0] == 0.0
        assert np.all(np.isinf(bt[1:]))
        traj = ruckig_solve([pb])
        assert traj is not None and traj.duration == 0.0
        prof = record(pb)
        assert ours_timed(prof, 1.5, pb)
        assert_valid(prof, pb, 1.5)
        assert np.all(prof[A : A + 8] == 0.0)


def test_textbook_profiles():
    # 0 -> 2 m/s at a = 1, j = 1: 1 s ramps (0.5 m/s each), 1 s hold, 3 s in all.
    pb = (0.0, 0.0, 2.0, 0.0, 1.0, -1.0, 1.0)
    ok, block, bt = ours_fastest(pb)
    assert ok
    np.testing.assert_allclose(block[0, T : T + 7], [1.0, 1.0, 1.0, 0, 0, 0, 0], atol=1e-14)
    np.testing.assert_allclose(block[0, J : J + 7], [1.0, 0.0, -1.0, 0, 0, 0, 0])
    # Downwards with an asymmetric limit: the hold is at a_min = -0.5.
    pb = (2.0, 0.0, 0.0, 0.0, 1.0, -0.5, 1.0)
    ok, block, bt = ours_fastest(pb)
    assert ok
    np.testing.assert_allclose(block[0, T : T + 3], [0.5, 3.5, 0.5], atol=1e-14)
    assert block[0, A + 1] == pytest.approx(-0.5)
    # Acceleration-limited: 2 m/s at 0.5 takes 4 s.
    pb = (0.0, 0.0, -2.0, 0.0, 1.0, -0.5, INF)
    ok, block, bt = ours_fastest(pb)
    assert ok and bt[0] == pytest.approx(4.0)
    assert block[0, A + 1] == -0.5
    # Timed too short fails; longer succeeds at a lower acceleration.
    assert not ours_timed(record(pb), 3.9, pb)
    prof = record(pb)
    assert ours_timed(prof, 8.0, pb)
    assert prof[A + 1] == pytest.approx(-0.25)


def test_zero_limits():
    # j_max = 0: only holding a0 works; vf is reached at one instant, every later
    # duration is blocked (as in ruckig).
    pb = (0.0, 0.5, 1.0, 0.5, 1.0, -1.0, 0.0)
    ok, _block, bt = ours_fastest(pb)
    traj = ruckig_solve([pb])
    assert ok and traj is not None
    assert bt[0] == pytest.approx(2.0) and close(bt[0], traj.duration)
    assert bt[1] == bt[0] and math.isinf(bt[2])
    assert is_blocked(bt, 3.0) and not is_blocked(bt, bt[0])
    # j_max = 0 with a change of acceleration: impossible for both.
    pb = (0.0, 0.5, 1.0, 0.0, 1.0, -1.0, 0.0)
    assert not ours_fastest(pb)[0]
    assert ruckig_solve([pb]) is None
    # a_min = 0 (acceleration-limited) forbids slowing down; a zero change fails
    # too, in both libraries (0/0 in the law).
    for pb in [(1.0, 0.0, 0.5, 0.0, 1.0, 0.0, INF), (1.0, 0.0, 1.0, 0.0, 1.0, 0.0, INF)]:
        assert not ours_fastest(pb)[0]
        assert ruckig_solve([pb]) is None
