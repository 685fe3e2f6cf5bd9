"""Profiles on a controller grid (:mod:`trajkit.profiles._kernels.quantize`).

Every plan is checked here by an independent integration of its record: every
phase (brake phases included) a whole number of periods, the total the number of
periods reported, the target state reached (to 1e-11 of the size of the terms),
every limit kept: jerk, acceleration at the phase edges, velocity at the edges
and at its extrema inside phases (where the acceleration crosses zero). Where
the start is beyond the limits the continuous profile itself is beyond them
until its third switching time; there the grid profile may be as far beyond as
the continuous one is (no further).

Figures of the last full run (``pytest -m slow -s``, 2 cores), filled in by the
developer in the report, not here.
"""

import math

import numpy as np
import pytest

from trajkit.profiles._kernels import layout as L
from trajkit.profiles._kernels import quantize as q
from trajkit.profiles._kernels import synchronize as S

SYNC_TIME, SYNC_PHASE, SYNC_TIN, SYNC_NONE = 0, 1, 2, 3


# ------------------------------------------------------------------------- helpers
def matrix(q0, qf, v0, vf, a0, af, v_min, v_max, a_min, a_max, j_max):
    """The (11, ndof) problem matrix (rows as in _kernels.admissible)."""
    rows = (q0, qf, v0, vf, a0, af, v_min, v_max, a_min, a_max, j_max)
    ndof = max(np.size(r) for r in rows)
    return np.array([np.broadcast_to(np.asarray(r, float), (ndof,)) for r in rows])


def symmetric(q0, qf, v, a, j, v0=0.0, vf=0.0, a0=0.0, af=0.0):
    v, a = np.asarray(v, float), np.asarray(a, float)
    return matrix(q0, qf, v0, vf, a0, af, -v, v, -a, a, j)


def run(m, sync=SYNC_TIME, dt=0.002, enabled=None, control=None, min_duration=math.nan):
    ndof = m.shape[1]
    profiles = np.zeros((ndof, L.SIZE))
    own = np.zeros(ndof)
    out = np.zeros(S.OUT_SIZE)
    status = q.plan_on_grid(
        m,
        np.zeros(ndof, np.int64) if control is None else np.asarray(control, np.int64),
        np.broadcast_to(np.asarray(sync, np.int64), (ndof,)).copy(),
        np.ones(ndof, np.int64) if enabled is None else np.asarray(enabled, np.int64),
        min_duration,
        dt,
        profiles,
        own,
        out,
    )
    return status, profiles, out


def envelope(c, second):
    """Velocity and acceleration range of a continuous record before its limits hold."""
    vs = [c[L.V], c[L.V + 1], c[L.V + 2]]
    acc = [c[L.A]]
    if c[L.BRAKE_DURATION] > 0:
        for k in range(1 if second else 2):
            vs.append(c[L.BRAKE_V + k])
            acc.append(c[L.BRAKE_A + k])
            a, j, t = c[L.BRAKE_A + k], c[L.BRAKE_J + k], c[L.BRAKE_T + k]
            if not second and j != 0 and a * (a + j * t) < 0:
                vs.append(c[L.BRAKE_V + k] - a * a / (2 * j))
    if not second:
        for i in range(2):
            a, j = c[L.A + i], c[L.J + i]
            if j != 0 and a * c[L.A + i + 1] < 0:
                vs.append(c[L.V + i] - a * a / (2 * j))
    return min(vs), max(vs), min(acc), max(acc)


def check_record(rec, m, d, dt, periods, continuous):
    """Independent check of joint ``d``'s grid record; returns a list of faults."""
    p0, pf, v0, vf, a0, af, v_min, v_max, a_min, a_max, j_max = m[:, d]
    second = math.isinf(j_max)
    braked = 1 if second else 2
    t = np.concatenate([rec[L.BRAKE_T : L.BRAKE_T + braked], rec[L.T : L.T + 7]])
    if second:
        x = np.concatenate([rec[L.BRAKE_A : L.BRAKE_A + 1], rec[L.A : L.A + 7]])
    else:
        x = np.concatenate([rec[L.BRAKE_J : L.BRAKE_J + 2], rec[L.J : L.J + 7]])
    faults = []
    k = np.round(t / dt)
    if np.any(np.abs(t - k * dt) > 1e-9 * dt * np.maximum(1.0, k)):
        faults.append(("phases not whole periods", t / dt))
    if periods is not None and k.sum() != periods:
        faults.append(("periods", k.sum(), periods))
    low_v, high_v, low_a, high_a = envelope(continuous, second)
    sv = 1e-12 * max(v_max, -v_min)
    sa = 1e-12 * max(a_max, -a_min)
    p, v, a = p0, v0, a0
    size_p, size_v, size_a = abs(p0) + abs(pf), abs(v0) + abs(vf), abs(a0) + abs(af)
    for i, (ti, xi) in enumerate(zip(t, x, strict=True)):
        edge = i - braked + 1  # edge of the seven phases after phase i
        in_brake = edge <= 0
        vh = max(v_max, high_v) if edge <= 2 else v_max
        vl = min(v_min, low_v) if edge <= 2 else v_min
        ah = max(a_max, high_a) if edge <= 0 else a_max
        al = min(a_min, low_a) if edge <= 0 else a_min
        if second:
            if ti > 0 and not in_brake and not (a_min - sa <= xi <= a_max + sa):
                faults.append(("acceleration", i, xi))
            p, v = p + ti * v + ti * ti * xi / 2, v + ti * xi
            size_p = max(size_p, abs(p) + abs(v) * ti)
            size_v = max(size_v, abs(v) + abs(xi) * ti)
        else:
            j = xi if ti > 0 else 0.0
            if abs(j) > j_max * (1 + 1e-12):
                faults.append(("jerk", i, j))
            a1 = a + j * ti
            if j != 0 and a * a1 < 0 and not in_brake:
                extremum = v - a * a / (2 * j)
                inner_h = max(v_max, high_v) if edge <= 2 else v_max
                inner_l = min(v_min, low_v) if edge <= 2 else v_min
                if not (inner_l - sv <= extremum <= inner_h + sv):
                    faults.append(("velocity inside", i, extremum))
            p, v, a = (p + ti * v + ti**2 * a / 2 + ti**3 * j / 6, v + ti * a + ti**2 * j / 2,
                       a1)  # fmt: skip
            size_p = max(size_p, abs(p) + abs(v) * ti + abs(a) * ti * ti)
            size_v = max(size_v, abs(v) + abs(a) * ti)
            size_a = max(size_a, abs(a) + abs(j) * ti)
        if edge >= 0:
            if not (vl - sv <= v <= vh + sv):
                faults.append(("velocity", i, v))
            if not second and not (al - sa <= a <= ah + sa):
                faults.append(("acceleration", i, a))
    if abs(p - pf) > 1e-11 * size_p + 1e-300:
        faults.append(("position", p, pf))
    if abs(v - vf) > 1e-11 * size_v + 1e-300:
        faults.append(("velocity at the end", v, vf))
    if not second and abs(a - af) > 1e-11 * size_a + 1e-300:
        faults.append(("acceleration at the end", a, af))
    return faults


def random_problem(rng, ndof, kind, second=False):
    """Random limits and boundaries; ``kind`` holds "asym", "moving", "brake"."""
    v = 10 ** rng.uniform(-1, 1, ndof)
    a = 10 ** rng.uniform(-1, 1, ndof)
    j = np.full(ndof, np.inf) if second else 10 ** rng.uniform(-0.5, 2, ndof)
    if "asym" in kind:
        v_min, a_min = (
            -v * 10 ** rng.uniform(-0.5, 0.5, ndof),
            -a * 10 ** rng.uniform(-0.5, 0.5, ndof),
        )
    else:
        v_min, a_min = -v, -a
    q0 = rng.normal(0, 1, ndof)
    qf = q0 + rng.normal(0, 2, ndof) * 10 ** rng.uniform(-3, 0.5, ndof)
    v0, vf, a0, af = (np.zeros(ndof) for _ in range(4))
    if "moving" in kind:
        v0 = rng.uniform(v_min, v) * (rng.random(ndof) < 0.7)
        vf = rng.uniform(v_min, v) * (rng.random(ndof) < 0.7)
        if not second:
            a0 = rng.uniform(a_min, a) * (rng.random(ndof) < 0.5)
            af = rng.uniform(a_min, a) * (rng.random(ndof) < 0.5)
            before = vf - af * np.abs(af) / (2 * j)
            af[(before > v) | (before < v_min)] = 0.0
    if "brake" in kind:
        pick = rng.random(ndof) < 0.5
        beyond = np.where(rng.random(ndof) < 0.5, v, v_min) * rng.uniform(1.0, 1.5, ndof)
        v0 = np.where(pick, beyond, v0)
        if not second:
            pick = rng.random(ndof) < 0.3
            beyond = np.where(rng.random(ndof) < 0.5, a, a_min) * rng.uniform(1.0, 1.5, ndof)
            a0 = np.where(pick, beyond, a0)
    return matrix(q0, qf, v0, vf, a0, af, v_min, v, a_min, a, j)


def reference_duration(m, d, continuous_duration, periods, dt):
    """The continuous duration, or the end of a blocked interval the grid had to skip."""
    times = np.empty(5)
    prof, valid, blocks = np.empty(L.SIZE), np.empty((6, L.SIZE)), np.empty((3, L.SIZE))
    p0, pf, v0, vf, a0, af, v_min, v_max, a_min, a_max, j_max = m[:, d]
    S._step1(prof, p0, v0, a0, pf, vf, af, v_max, v_min, a_max, a_min, j_max, 0, valid, blocks,
             times)  # fmt: skip
    reference = continuous_duration
    for left, right in ((times[1], times[2]), (times[3], times[4])):
        if left < periods * dt and math.isfinite(right) and right > reference:
            reference = right
    return reference


def sweep(kind, count, seed, second=False, ndof=1, sync=SYNC_TIME):
    """Plan ``count`` random problems; check them; the excesses in periods and failures."""
    rng = np.random.default_rng(seed)
    excess, failed, faults = [], 0, []
    for _ in range(count):
        m = random_problem(rng, ndof, kind, second)
        dt = 10 ** rng.uniform(-3, -1.5)
        status_c, continuous, out_c = run(m, sync, 0.0)
        if status_c != S.OK:
            continue
        status, profiles, out = run(m, sync, dt)
        if status == q.GRID_FAILED:
            failed += 1
            continue
        assert status == S.OK
        n = round(out[S.OUT_DURATION] / dt)
        assert out[S.OUT_DURATION] == n * dt
        reference = out_c[S.OUT_DURATION]
        if ndof == 1:
            reference = reference_duration(m, 0, reference, n, dt)
        excess.append(n - reference / dt)
        for d in range(ndof):
            # Joints left out (and time-if-necessary ones ending at rest) keep their own.
            at_rest = m[3, d] == 0.0 and m[5, d] == 0.0
            own = None if sync == SYNC_NONE or (sync == SYNC_TIN and at_rest) else n
            found = check_record(profiles[d], m, d, dt, own, continuous[d])
            if found:
                faults.append((found, m[:, d].tolist(), dt))
    return np.array(excess), failed, faults


# ---------------------------------------------------------------------------- sweeps
@pytest.mark.parametrize("kind", ["rest", "rest-asym"])
def test_s_curves_at_rest_stay_within_three_periods(kind):
    excess, failed, faults = sweep(kind, 150, 1)
    assert not faults, faults[:3]
    assert failed == 0
    # Under 3 dt; a move shorter than a period needs three (no two-period move exists).
    assert excess.max() < 3.0
    assert np.mean(excess < 2.0) > 0.99


@pytest.mark.parametrize("kind", ["rest", "rest-asym"])
def test_trapezoids_at_rest_stay_within_two_periods(kind):
    excess, failed, faults = sweep(kind, 200, 2, second=True)
    assert not faults, faults[:3]
    assert failed == 0
    assert excess.max() < 2.0


@pytest.mark.parametrize("second", [False, True])
@pytest.mark.parametrize("kind", ["moving", "moving-asym", "brake"])
def test_moving_boundaries_and_brakes(kind, second):
    excess, failed, faults = sweep(kind, 120, 3, second=second)
    assert not faults, faults[:3]
    assert failed <= 3  # rare: brakes far beyond the limits, see the module's docstring
    assert np.median(excess) < 1.5


@pytest.mark.parametrize("sync", [SYNC_TIME, SYNC_PHASE, SYNC_TIN, SYNC_NONE])
def test_several_joints(sync):
    excess, failed, faults = sweep("moving", 25, 4, ndof=4, sync=sync)
    assert not faults, faults[:3]
    excess, failed, faults = sweep("rest-asym", 25, 5, ndof=4, sync=sync)
    assert not faults, faults[:3]
    assert failed == 0
    assert excess.max() < 3.0


# ---------------------------------------------------------------------------- cases
def test_a_tiny_move_under_a_long_common_duration_keeps_its_move():
    # tk.scurve([0, 0], [2.4e-9, 5.0], 1.0, 1.0, 10.0, period=0.002) ended at 0 (a bug).
    m = symmetric([0.0, 0.0], [2.4e-9, 5.0], 1.0, 1.0, 10.0)
    for sync in (SYNC_TIME, SYNC_PHASE, SYNC_TIN, SYNC_NONE):
        status, profiles, out = run(m, sync)
        assert status == S.OK
        assert out[S.OUT_DURATION] == pytest.approx(6.1, rel=1e-12)
        assert profiles[0, L.P + 7] == pytest.approx(2.4e-9, rel=1e-9)
        assert check_record(profiles[0], m, 0, 0.002, None, profiles[0]) == []
    m = symmetric([0.0, 0.0], [2.4e-9, 5.0], 1.0, 1.0, np.inf)
    status, profiles, out = run(m)
    assert status == S.OK
    assert abs(profiles[0, L.P + 7] - 2.4e-9) <= 1e-12 * 2.4e-9


def test_a_move_shorter_than_a_period_takes_three():
    m = symmetric(0.0, 1e-12, 1.0, 1.0, 10.0)
    _, continuous, _ = run(m, dt=0.0)
    status, profiles, out = run(m)
    assert status == S.OK
    assert round(out[S.OUT_DURATION] / 0.002) == 3
    assert check_record(profiles[0], m, 0, 0.002, 3, continuous[0]) == []


def test_the_case_where_two_periods_do_not_suffice():
    # The numpy implementation's documented worst: 2.0022 dt.
    m = symmetric(0.0, 2.0, 1.32662371, 1.9, 43.0)
    _, _, out_c = run(m, dt=0.0)
    status, _, out = run(m)
    assert status == S.OK
    assert 2.0 < (out[S.OUT_DURATION] - out_c[S.OUT_DURATION]) / 0.002 < 2.01


def test_seed_001_phase_synchronized_trapezoids_at_2_ms():
    qf = np.radians([90.0, 75.0, 60.0, 45.0, 30.0, 15.0])
    v = np.radians([7.0, 7.0, 7.0, 3.5, 3.5, 3.5])
    a = np.radians([4.0, 4.0, 4.0, 2.0, 2.0, 2.0])
    m = symmetric(np.zeros(6), qf, v, a, np.inf)
    status, profiles, out = run(m, SYNC_PHASE)
    assert status == S.OK
    assert out[S.OUT_DURATION] == pytest.approx(7304 * 0.002, rel=1e-12)
    assert out[S.OUT_PHASE] == 1.0
    phases = profiles[:, L.T : L.T + 7] / 0.002
    assert np.all(phases == phases[0])
    # The smallest whole-step blend keeping a = D / (tb (T - tb)) <= A: 875 periods.
    assert phases[0, 0] == pytest.approx(875)
    tb = phases[0, 0] * 0.002
    peaks = qf / (out[S.OUT_DURATION] - tb)
    np.testing.assert_allclose(profiles[:, L.V + 1], peaks, rtol=1e-12)
    continuous = qf / ((90.0 / 7.0) * 1.75)
    assert np.all(peaks / tb / continuous > 0.9999)


def test_phase_sync_with_a_still_joint():
    m = symmetric(np.zeros(3), [1.0, 0.0, -2.0], 1.0, 1.0, np.inf)
    status, profiles, out = run(m, SYNC_PHASE, dt=0.01)
    assert status == S.OK
    np.testing.assert_allclose(profiles[:, L.P + 7], [1.0, 0.0, -2.0], atol=1e-14)
    assert np.all(profiles[1, L.P : L.P + 8] == 0.0)
    for d in range(3):
        assert check_record(profiles[d], m, d, 0.01, round(out[0] / 0.01), profiles[d]) == []


def test_joints_left_out_take_their_own_periods():
    m = symmetric(np.zeros(3), [1.0, 2.0, 3.0], 1.0, 1.0, 10.0)
    status, profiles, out = run(m, SYNC_NONE)
    assert status == S.OK
    own = [round((r[L.T_SUM + 6] + r[L.BRAKE_DURATION]) / 0.002) for r in profiles]
    assert own[0] < own[1] < own[2]
    assert out[S.OUT_DURATION] == own[2] * 0.002


def test_disabled_joint_and_min_duration():
    m = symmetric(np.zeros(3), [1.0, 2.0, 3.0], 1.0, 1.0, 10.0)
    status, profiles, out = run(m, enabled=[1, 0, 1], min_duration=7.0)
    assert status == S.OK
    assert out[S.OUT_DURATION] == pytest.approx(7.0, rel=1e-12)
    assert np.all(profiles[1, L.T : L.T + 7] == 0.0)
    for d in (0, 2):
        assert check_record(profiles[d], m, d, 0.002, 3500, profiles[d]) == []


def test_durations_inside_a_blocked_interval_are_skipped():
    # Blocked between 3.30 and 16.21 periods: the first grid duration past it is 17.
    m = np.array([[1.2387613942549394], [1.206801724934997], [-0.6467759285068618],
                  [-0.30060216127737416], [6.507788899905859], [2.9658613778517635],
                  [-0.72899476951393], [0.72899476951393], [-7.573292314965129],
                  [7.573292314965129], [92.70441089305449]])  # fmt: skip
    dt = 0.02202440630224017
    _, continuous, _ = run(m, dt=0.0)
    status, profiles, out = run(m, dt=dt)
    assert status == S.OK
    assert round(out[S.OUT_DURATION] / dt) == 17
    assert check_record(profiles[0], m, 0, dt, 17, continuous[0]) == []


def test_velocity_interface_is_refused():
    m = symmetric(np.zeros(2), [1.0, 2.0], 1.0, 1.0, 10.0)
    status, _, out = run(m, control=[0, 1])
    assert status == q.VELOCITY_UNSUPPORTED
    assert out[S.OUT_JOINT] == 1


def test_no_period_plans_continuously():
    m = symmetric(np.zeros(2), [1.0, 2.0], 1.0, 1.0, 10.0)
    status, _, out = run(m, dt=0.0)
    assert status == S.OK
    assert out[S.OUT_DURATION] == pytest.approx(2.0 + 1.0 + 0.1, rel=1e-9)


def test_quantize_joint_alone():
    m = symmetric(0.0, 1.0, 1.0, 1.0, 10.0)
    _, continuous, out_c = run(m, dt=0.0)
    first = math.ceil(out_c[0] / 0.002)
    out, work = np.empty(L.SIZE), np.empty((q.WORK_ROWS, L.SIZE))
    args = (0.002, 1.0, -1.0, 1.0, -1.0, 10.0, out, work)
    assert not q.quantize_joint(continuous[0], first - 2, *args)
    found = [n for n in range(first, first + 3) if q.quantize_joint(continuous[0], n, *args)]
    assert found and found[0] <= first + 1
    assert q.quantize_joint(continuous[0], found[0], *args)
    assert check_record(out, m, 0, 0.002, found[0], continuous[0]) == []


def test_batch_matches_single_problems():
    rng = np.random.default_rng(6)
    problems = np.array([random_problem(rng, 3, "moving") for _ in range(40)])
    count = problems.shape[0]
    profiles = np.zeros((count, 3, L.SIZE))
    own = np.zeros((count, 3))
    out = np.zeros((count, S.OUT_SIZE))
    status = np.zeros(count, np.int64)
    ints = np.zeros((count, 3), np.int64)
    q.plan_on_grid_batch(problems, ints, ints, ints + 1, np.full(count, np.nan), 0.004,
                         profiles, own, out, status)  # fmt: skip
    for i in range(count):
        alone, records, summary = run(problems[i], dt=0.004)
        assert status[i] == alone
        if alone == S.OK:
            np.testing.assert_array_equal(profiles[i], records)
            np.testing.assert_array_equal(out[i], summary)


# ------------------------------------------------------------------------ slow sweeps
@pytest.mark.slow
def test_worst_excess_over_many_problems():
    lines = []
    for kind, second, count in [
        ("rest", False, 3000), ("rest-asym", False, 3000), ("rest", True, 3000),
        ("rest-asym", True, 3000), ("moving", False, 2000), ("moving-asym", False, 2000),
        ("moving", True, 2000), ("brake", False, 2000), ("brake", True, 2000),
    ]:  # fmt: skip
        excess, failed, faults = sweep(kind, count, 10, second=second)
        assert not faults, faults[:3]
        order = "second" if second else "third"
        lines.append(
            f"{kind:12s} {order}: {excess.size} planned, {failed} failed, excess (periods) "
            f"median {np.median(excess):.3f}, 99% {np.quantile(excess, 0.99):.3f}, "
            f"max {excess.max():.3f}"
        )
        if kind.startswith("rest"):
            assert excess.max() < (2.0 if second else 3.0)
    print("\n" + "\n".join(lines))
