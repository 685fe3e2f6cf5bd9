"""The fastest jerk-limited position move (ruckig's step 1) against ruckig, and its promises.

Problems are drawn as ruckig's own randomizer draws them (``test/randomizer.hpp``,
``test/test_target.cpp``): positions normal (sigma 4); boundary velocities and
accelerations normal (sigma 0.8) but exactly zero with some probability; limits
uniform on [0.08, 16] (or [10, 1e6]) plus the target's magnitude, negative
limits independently drawn for the asymmetric family; and ruckig's discrete
family (integers in {-1, 0, 1}, limits in {1, 2}), which hits exact ties and the
numerical fallbacks. Start states that would need a brake are redrawn (the brake
has its own module and a test of it with the brake is below), as are targets
ruckig's input validation rejects.

Checked: the minimum duration equals ruckig's (1e-9 relative; measured: equal to
the last bit on every problem so far, the formulas and their order of evaluation
being the same); the profile reaches the target (p 1e-8, v 1e-8, a 1e-10); the
jerks are within +-j_max and the accelerations and velocities within the limits
over the whole profile, including extrema inside phases, integrated here
independently of ``profile.check``; the profiles at the ends of blocked intervals
are valid and of the stated duration; and a duration inside a blocked interval
is refused as ruckig refuses it (``minimum_duration`` inside the interval moves
ruckig to the interval's right end, which must be ours).

Problems where one library succeeds and the other fails: none found. Last full
run (TRAJKIT_ORACLE_PROBLEMS=300000 per family, plus 100000 with the brake and
100000 scaled by 10^U(-4, 4)): 0 disagreements, 0 duration differences. Both
fail together on some problems scaled by >= 1e3 (their absolute position
tolerance of 1e-8 is then below rounding), and on zero-limit problems whose
target cannot be drifted to.
"""

import math
import os

import numpy as np
import pytest

ruckig = pytest.importorskip("ruckig", reason="ruckig (test oracle) is not installed")

from trajkit.profiles._kernels.jerk_fastest import (  # noqa: E402
    calculate_block,
    fastest,
    is_blocked,
    profile_at,
)
from trajkit.profiles._kernels.layout import (  # noqa: E402
    AF,
    BRAKE_DURATION,
    DIRECTION,
    DOWN,
    PF,
    SIZE,
    T_SUM,
    UP,
    VF,
    A,
    J,
    P,
    T,
    V,
)
from trajkit.profiles._kernels.profile import duration, new_profile  # noqa: E402

N_SLOW = int(os.environ.get("TRAJKIT_ORACLE_PROBLEMS", "20000"))
REL = 1e-9  # duration agreement with ruckig
NO_BLOCK = np.zeros((3, SIZE))  # profile_at only reads the times

# One problem: (p0, v0, a0, pf, vf, af, v_max, v_min, a_max, a_min, j_max).


def needs_brake(v0, a0, v_max, v_min, a_max, a_min, j_max):
    """Ruckig's condition for a position brake pre-profile (brake.cpp)."""

    def v_at_a_zero(v, a, j):
        return v + a * a / (2 * j)

    return (
        a0 > a_max
        or a0 < a_min
        or (v0 > v_max and v_at_a_zero(v0, a0, -j_max) > v_min)
        or (a0 > 0 and v_at_a_zero(v0, a0, j_max) > v_max)
        or (v0 < v_min and v_at_a_zero(v0, a0, j_max) < v_max)
        or (a0 < 0 and v_at_a_zero(v0, a0, -j_max) < v_min)
    )


def target_valid(vf, af, v_max, v_min, a_max, a_min, j_max):
    """Ruckig's validation of the target state (input_parameter.hpp)."""
    if not (a_min <= af <= a_max and v_min <= vf <= v_max):
        return False
    if af < 0 and j_max > 0 and vf + af * af / (2 * j_max) > v_max:
        return False
    return not (af > 0 and j_max > 0 and vf - af * af / (2 * j_max) < v_min)


def draw_random(rng, asymmetric=False, high=False, within=True):
    """ruckig's position-random-3 / random-direction-3 / random-3-high families."""
    probs = (0.1, 0.1, 0.1, 0.1) if high else (0.9, 0.8, 0.7, 0.6)
    lo, hi = (10.0, 1e6) if high else (0.08, 16.0)
    while True:
        p0, pf = rng.normal(0.0, 4.0, 2)
        v0, a0, vf, af = (rng.normal(0.0, 0.8) if rng.random() < q else 0.0 for q in probs)
        v_max = rng.uniform(lo, hi) + abs(vf)
        a_max = rng.uniform(lo, hi) + abs(af)
        j_max = rng.uniform(lo, hi)
        if asymmetric:
            v_min = rng.uniform(-16.0, -0.08) - abs(vf)
            a_min = rng.uniform(-16.0, -0.08) - abs(af)
        else:
            v_min, a_min = -v_max, -a_max
        if within and needs_brake(v0, a0, v_max, v_min, a_max, a_min, j_max):
            continue
        if not target_valid(vf, af, v_max, v_min, a_max, a_min, j_max):
            continue
        return (p0, v0, a0, pf, vf, af, v_max, v_min, a_max, a_min, j_max)


def draw_discrete(rng):
    """ruckig's random-discrete-3 family: exact small integers, many ties."""
    while True:
        p0, pf, v0, a0, vf, af = (float(x) for x in rng.integers(-1, 2, 6))
        v_max = float(rng.integers(1, 3)) + abs(vf)
        a_max = float(rng.integers(1, 3)) + abs(af)
        j_max = float(rng.integers(1, 3))
        if needs_brake(v0, a0, v_max, -v_max, a_max, -a_max, j_max):
            continue
        if not target_valid(vf, af, v_max, -v_max, a_max, -a_max, j_max):
            continue
        return (p0, v0, a0, pf, vf, af, v_max, -v_max, a_max, -a_max, j_max)


def draw_scaled(rng, scale):
    """An asymmetric problem with every quantity multiplied by ``scale``.

    Durations are invariant: the same problem in other units.
    """
    return tuple(x * scale for x in draw_random(rng, asymmetric=True))


FAMILIES = {
    "random": lambda rng: draw_random(rng),
    "direction": lambda rng: draw_random(rng, asymmetric=True),
    "high": lambda rng: draw_random(rng, high=True),
    "discrete": draw_discrete,
    "scaled": lambda rng: draw_scaled(rng, 10.0 ** rng.uniform(-3, 3)),
}


class Solver:
    """Preallocated arrays around :func:`fastest`."""

    def __init__(self):
        self.prof = new_profile()
        self.valid = np.zeros((6, SIZE))
        self.block = np.zeros((3, SIZE))
        self.times = np.zeros(5)

    def __call__(self, problem, brake=False):
        p0, v0, a0, pf, vf, af, v_max, v_min, a_max, a_min, j_max = problem
        prof = self.prof
        prof[:] = 0.0
        prof[P], prof[V], prof[A], prof[PF], prof[VF], prof[AF] = p0, v0, a0, pf, vf, af
        if brake:
            from trajkit.profiles._kernels.brake import position_brake
            from trajkit.profiles._kernels.profile import finalize_brake

            position_brake(prof, v0, a0, v_max, v_min, a_max, a_min, j_max)
            finalize_brake(prof)
        self.valid[:] = np.nan  # stale scratch must never leak into a result
        return fastest(prof, v_max, v_min, a_max, a_min, j_max, self.valid, self.block, self.times)


def ruckig_solve(problem, minimum_duration=None):
    """Ruckig's duration (None if it fails) and its profile."""
    p0, v0, a0, pf, vf, af, v_max, v_min, a_max, a_min, j_max = problem
    inp = ruckig.InputParameter(1)
    inp.current_position, inp.current_velocity, inp.current_acceleration = [p0], [v0], [a0]
    inp.target_position, inp.target_velocity, inp.target_acceleration = [pf], [vf], [af]
    inp.max_velocity, inp.min_velocity = [v_max], [v_min]
    inp.max_acceleration, inp.min_acceleration = [a_max], [a_min]
    inp.max_jerk = [j_max]
    if minimum_duration is not None:
        inp.minimum_duration = minimum_duration
    traj = ruckig.Trajectory(1)
    try:
        result = ruckig.Ruckig(1).calculate(inp, traj)
    except ruckig.RuckigError:  # ruckig raises on some failures instead of returning one
        return None, None
    if result != ruckig.Result.Working:
        return None, None
    return traj.duration, traj.profiles[0][0]


def relative(ours, theirs):
    return abs(ours - theirs) / theirs if theirs > 0 else abs(ours)


def profile_errors(rec, problem):
    """Independent check of one profile: list of broken promises (empty if valid).

    Integrates the seven phases from the stored start state with the stored
    durations and jerks (not the stored edge states), and checks the velocity
    extremum inside every phase whose acceleration changes sign. The stored end
    state must meet the target to ruckig's absolute precision; the independent
    integration too, up to rounding relative to the magnitudes met on the way
    (``check`` sets accelerations on a limit exactly, this integration does not).
    """
    _, _, _, pf, vf, af, v_max, v_min, a_max, a_min, j_max = problem
    # Measured worst excursions: 6e-16 (a) and 1.2e-13 (v) of the limits' scale.
    tol_a = 1e-12 + 1e-12 * max(a_max, -a_min)
    tol_v = 1e-12 + 1e-11 * max(v_max, -v_min)
    errors = []
    p, v, a = rec[P], rec[V], rec[A]
    mag = [abs(p), abs(v), abs(a)]
    for i in range(7):
        t, j = rec[T + i], rec[J + i]
        if not t >= 0.0:
            errors.append(f"phase {i}: duration {t}")
        if abs(j) > j_max * (1 + 1e-12):
            errors.append(f"phase {i}: jerk {j} beyond {j_max}")
        if t > 0.0 and j != 0.0 and 0.0 < -a / j < t:
            v_ext = v - a * a / (2 * j)
            if not v_min - tol_v <= v_ext <= v_max + tol_v:
                errors.append(f"phase {i}: velocity extremum {v_ext}")
        p, v, a = (
            p + t * (v + t * (a / 2 + t * j / 6)),
            v + t * (a + t * j / 2),
            a + t * j,
        )
        mag = [max(m, abs(x)) for m, x in zip(mag, (p, v, a), strict=True)]
        if not a_min - tol_a <= a <= a_max + tol_a:
            errors.append(f"phase {i}: acceleration {a} at its end")
        if not v_min - tol_v <= v <= v_max + tol_v:
            errors.append(f"phase {i}: velocity {v} at its end")
    end = (rec[P + 7], rec[V + 7], rec[A + 7])
    if not (abs(end[0] - pf) < 1e-8 and abs(end[1] - vf) < 1e-8 and abs(end[2] - af) < 1e-10):
        errors.append(f"misses the target: {end} vs {(pf, vf, af)}")
    for x, target, precision, m in zip(
        (p, v, a), (pf, vf, af), (1e-8, 1e-8, 1e-10), mag, strict=True
    ):
        if not abs(x - target) < precision + 1e-13 * m:
            errors.append(f"integrated, misses the target: {(p, v, a)} vs {(pf, vf, af)}")
    return errors


def compare_family(draw, count, seed, brake=False):
    """Solve ``count`` problems with both libraries; return figures and failures."""
    rng = np.random.default_rng(seed)
    solve = Solver()
    worst = 0.0
    disagree, mismatch, invalid = [], [], []
    intervals = 0
    for _ in range(count):
        problem = draw(rng)
        ok = solve(problem, brake)
        theirs, _ = ruckig_solve(problem)
        if not ok or theirs is None:
            if ok != (theirs is not None):
                disagree.append((problem, ok, theirs))
            continue
        times, block = solve.times, solve.block
        rel = relative(times[0], theirs)
        worst = max(worst, rel)
        if rel > REL:
            mismatch.append((problem, times[0], theirs))
        rows = [0] + [k for k, left in ((1, times[1]), (2, times[3])) if left < math.inf]
        intervals += len(rows) - 1
        for row in rows:
            t_row = times[0] if row == 0 else times[2 * row]
            if duration(block[row]) != t_row:
                invalid.append((problem, row, "duration", duration(block[row]), t_row))
            if not brake:
                errors = profile_errors(block[row], problem)
                if errors:
                    invalid.append((problem, row, errors))
    return worst, disagree, mismatch, invalid, intervals


@pytest.mark.parametrize("family", sorted(FAMILIES))
def test_against_ruckig(family):
    count = 800 if family in ("high", "scaled") else 1500
    worst, disagree, mismatch, invalid, _ = compare_family(FAMILIES[family], count, seed=7)
    assert not disagree, f"{len(disagree)} problems solved by one library only: {disagree[:3]}"
    assert not mismatch, f"{len(mismatch)} durations differ (worst {worst:.2e}): {mismatch[:3]}"
    assert not invalid, f"{len(invalid)} invalid profiles: {invalid[:3]}"


def test_with_brake_against_ruckig():
    """Start states beyond the limits: the brake pre-profile, then the fastest move."""

    def draw(rng):
        problem = list(draw_random(rng, asymmetric=True, within=False))
        # Start velocities and accelerations well beyond the limits, half the time.
        if rng.random() < 0.5:
            problem[1] = rng.normal(0.0, 8.0)
            problem[2] = rng.normal(0.0, 8.0)
        return tuple(problem)

    worst, disagree, mismatch, invalid, _ = compare_family(draw, 1000, seed=11, brake=True)
    assert not disagree, disagree[:3]
    assert not mismatch, (worst, mismatch[:3])
    assert not invalid, invalid[:3]


@pytest.mark.parametrize("scale", [1e-6, 1e-3, 1e3, 1e5])
def test_tiny_and_huge_scales(scale):
    """Durations do not depend on units; both libraries agree on success and failure.

    At 1e5 the absolute position tolerance (1e-8) is below rounding for some
    problems and both libraries refuse them alike.
    """
    worst, disagree, mismatch, invalid, _ = compare_family(
        lambda rng: draw_scaled(rng, scale), 300, seed=3
    )
    assert not disagree, disagree[:3]
    assert not mismatch, (worst, mismatch[:3])
    assert not invalid, invalid[:3]


def _assert_refused_like_ruckig(problem, times):
    """Inside a blocked interval ruckig moves to its right end; before it, it stays."""
    t_min = times[0]
    for left, right in ((times[1], times[2]), (times[3], times[4])):
        if not left < math.inf:
            continue
        inside = 0.5 * (left + right)
        assert is_blocked(times, inside)
        assert not is_blocked(times, right)
        theirs, _ = ruckig_solve(problem, minimum_duration=inside)
        assert theirs is not None and relative(right, theirs) <= REL, (problem, list(times))
    before = times[1] if times[1] < math.inf else t_min + 1.0
    if times[3] < math.inf:
        before = min(before, times[3])
    if before > t_min + 1e-6:
        free = 0.5 * (t_min + before)
        assert not is_blocked(times, free)
        assert profile_at(NO_BLOCK, times, free) == 0
        theirs, _ = ruckig_solve(problem, minimum_duration=free)
        assert theirs is not None and relative(free, theirs) <= REL
    assert is_blocked(times, 0.5 * t_min) or t_min == 0.0


def test_blocked_intervals_against_ruckig():
    """Every blocked interval found in the discrete and random families."""
    solve = Solver()
    rng = np.random.default_rng(5)
    found = 0
    for k in range(4000):
        problem = draw_discrete(rng) if k % 2 else draw_random(rng, asymmetric=True)
        if not solve(problem) or not solve.times[1] < math.inf:
            continue
        found += 1
        times = solve.times.copy()
        assert times[0] <= times[1] < times[2]
        assert profile_at(solve.block, times, times[2]) == 1
        assert profile_errors(solve.block[1], problem) == []
        _assert_refused_like_ruckig(problem, times)
    assert found > 30


# Five valid candidates, hence two blocked intervals (about 1 problem in 10^6 of a
# wide random family has them). Ruckig: minimum_duration 2.3 -> 2.7987, 3.3 -> 3.8182.
TWO_INTERVALS = (
    0.0,
    -3.3791852259864195,
    3.4614503538771726,
    -1.520244396906135,
    0.9342943361635205,
    1.4155987394373932,
    4.107228617324886,
    -5.178410347960769,
    4.481401933386264,
    -0.6199883395699824,
    1.6463975570277207,
)


def test_two_blocked_intervals():
    solve = Solver()
    assert solve(TWO_INTERVALS)
    times = solve.times.copy()
    theirs, _ = ruckig_solve(TWO_INTERVALS)
    assert relative(times[0], theirs) <= REL
    assert times[0] < times[3] < times[4] < times[1] < times[2]  # b before a here
    for row in (0, 1, 2):
        assert profile_errors(solve.block[row], TWO_INTERVALS) == []
    assert duration(solve.block[1]) == times[2]
    assert duration(solve.block[2]) == times[4]
    assert profile_at(solve.block, times, times[4]) == 2
    assert profile_at(solve.block, times, 0.5 * (times[4] + times[1])) == 2
    # Past both: a's profile (a lies above b here; ruckig's get_profile would say b).
    assert profile_at(solve.block, times, times[2]) == 1
    _assert_refused_like_ruckig(TWO_INTERVALS, times)


def test_two_candidates_of_equal_duration():
    """The same profile found in both directions: one profile, nothing blocked.

    (Two candidates of different durations, ruckig's numerically robust case of a
    lost third one, never occurred in 8e5 problems; a unit test below covers it.)
    """
    problem = (-1.0, 0.0, -1.0, -1.0, 0.0, -1.0, 2.0, -2.0, 3.0, -3.0, 2.0)
    solve = Solver()
    assert solve(problem)
    theirs, _ = ruckig_solve(problem)
    assert solve.times[0] == theirs
    assert all(solve.times[1:] == math.inf)
    assert profile_errors(solve.block[0], problem) == []


@pytest.mark.parametrize(
    "problem",
    [
        (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, -1.0, 1.0, -1.0, 1.0),
        (2.5, 0.0, 0.0, 2.5, 0.0, 0.0, 3.0, -0.5, 2.0, -7.0, 5.0),
        (1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, -1.0, 1.0, -1.0, 2.0),
    ],
)
def test_zero_move(problem):
    solve = Solver()
    assert solve(problem)
    assert solve.times[0] == 0.0
    assert all(solve.times[1:] == math.inf)
    assert ruckig_solve(problem)[0] == 0.0


def test_returns_to_the_same_state():
    """Same position, same nonzero velocity: a loop, not a zero move."""
    problem = (0.0, 0.5, 0.0, 0.0, 0.5, 0.0, 1.0, -1.0, 1.0, -1.0, 1.0)
    solve = Solver()
    assert solve(problem)
    theirs, _ = ruckig_solve(problem)
    assert solve.times[0] > 0.0 and relative(solve.times[0], theirs) <= REL
    assert profile_errors(solve.block[0], problem) == []


def test_known_duration():
    """Rest to rest over 1 with unit limits: 2 * 4^(1/3), reaching no limit."""
    solve = Solver()
    assert solve((0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, -1.0, 1.0, -1.0, 1.0))
    assert solve.times[0] == pytest.approx(2 * 4 ** (1 / 3), rel=1e-14)
    # Integer limits are accepted too (made floats before they reach the checks).
    assert fastest(solve.prof, 1, -1, 1, -1, 1, solve.valid, solve.block, solve.times)


def _zero_limit_problem(rng, kind):
    """A drift problem with one zero limit; reachable four times in five."""
    while True:
        problem = _zero_limit_draw(rng, kind)
        if target_valid(*problem[4:6], *problem[6:]):
            return problem


def _zero_limit_draw(rng, kind):
    p0 = rng.normal(0.0, 2.0)
    v0 = rng.normal(0.0, 0.5) if rng.random() < 0.7 else 0.0
    a0 = rng.normal(0.0, 0.5) if rng.random() < 0.5 else 0.0
    a_max, a_min, j_max = rng.uniform(0.1, 5.0), -rng.uniform(0.1, 5.0), rng.uniform(0.1, 5.0)
    if kind == "jerk":
        j_max = 0.0
        a0 = min(max(a0, a_min), a_max)
    elif kind == "a_max":  # the (constant) acceleration must then be <= 0
        a_max, a0 = 0.0, -abs(a0)
    else:
        a_min, a0 = 0.0, abs(a0)
    t = rng.uniform(0.0, 3.0)
    if rng.random() < 0.8:
        pf, vf = p0 + v0 * t + a0 * t * t / 2, v0 + a0 * t
    else:
        pf, vf = rng.normal(0.0, 2.0), rng.normal(0.0, 1.0)
    v_max = max(abs(v0), abs(vf)) + rng.uniform(0.1, 5.0)
    return (p0, v0, a0, pf, vf, a0, v_max, -v_max, a_max, a_min, j_max)


@pytest.mark.parametrize("kind", ["jerk", "a_max", "a_min"])
def test_zero_limits_against_ruckig(kind):
    """Zero jerk or acceleration limits: only a drift at constant acceleration."""
    rng = np.random.default_rng(13)
    solve = Solver()
    both = 0
    for _ in range(400):
        problem = _zero_limit_problem(rng, kind)
        ok = solve(problem)
        theirs, _ = ruckig_solve(problem)
        assert ok == (theirs is not None), problem
        if not ok:
            continue
        both += 1
        times = solve.times
        assert relative(times[0], theirs) <= REL, (problem, times[0], theirs)
        assert profile_errors(solve.block[0], problem) == []
        moving = abs(problem[1]) > 2.2e-16 or abs(problem[2]) > 2.2e-16
        # A moving axis cannot wait: every longer duration is blocked.
        assert (times[1], times[2]) == ((times[0], math.inf) if moving else (math.inf, math.inf))
        assert times[3] == times[4] == math.inf
    assert both > 200


def _candidates(durations, directions, brake=0.0):
    valid = np.zeros((6, SIZE))
    for k, (d, up) in enumerate(zip(durations, directions, strict=True)):
        valid[k, T_SUM + 6] = d
        valid[k, DIRECTION] = UP if up else DOWN
        valid[k, BRAKE_DURATION] = brake
        valid[k, T] = k  # a tag to tell the rows apart
    return valid


def _block(durations, directions, brake=0.0):
    valid = _candidates(durations, directions, brake)
    block = np.zeros((3, SIZE))
    times = np.zeros(5)
    ok = calculate_block(valid, len(durations), block, times)
    return ok, block[:, T].copy(), times


def test_calculate_block_counts():
    ok, tags, times = _block([2.0], [True], brake=0.5)
    assert ok and tags[0] == 0 and list(times) == [2.5, *[math.inf] * 4]

    # Two equal durations: one profile, nothing blocked.
    ok, tags, times = _block([2.0, 2.0 + 1e-16], [True, False])
    assert ok and tags[0] == 0 and times[1] == math.inf

    # Two different: the faster one, and the interval up to the other.
    ok, tags, times = _block([3.0, 2.0], [True, False])
    assert ok and tags[0] == 1 and tags[1] == 0 and list(times) == [2.0, 2.0, 3.0, *[math.inf] * 2]

    # Three: the interval between the two slower ones; its right end's profile.
    ok, tags, times = _block([4.0, 2.0, 3.0], [True, True, False])
    assert ok and tags[0] == 1 and tags[1] == 0 and list(times[:3]) == [2.0, 3.0, 4.0]

    # Four with a duplicate of opposite direction: three.
    ok, tags, times = _block([3.0, 3.0, 2.0, 4.0], [True, False, True, True])
    assert ok and tags[0] == 2 and list(times[:3]) == [2.0, 3.0, 4.0]
    ok, tags, times = _block([3.0, 2.0, 4.0, 4.0], [True, True, True, False])
    assert ok and tags[0] == 1 and tags[1] == 2 and list(times[:3]) == [2.0, 3.0, 4.0]
    # Two of one direction and one duration are one motion (a peak that touches a
    # limit, and the profile holding it for no time): the later is dropped.
    ok, tags, times = _block([3.0, 3.0, 4.0, 5.0], [True, True, True, True])
    assert ok and tags[0] == 0 and list(times[:3]) == [3.0, 4.0, 5.0]
    # Four without a duplicate, zero and six: inconsistent.
    assert not _block([3.0, 2.0, 4.0, 5.0], [True, True, True, False])[0]
    assert not _block([], [])[0]
    assert not _block([1.0, 2.0, 3.0, 4.0, 5.0, 6.0], [True] * 6)[0]


def test_calculate_block_five():
    # The candidates after the fastest pair by direction: (1, 2) share one.
    ok, tags, times = _block([1.0, 2.0, 3.0, 4.0, 5.0], [True, True, True, False, False])
    assert ok and list(tags) == [0, 2, 4] and list(times) == [1.0, 2.0, 3.0, 4.0, 5.0]
    # Otherwise (1, 4) and (2, 3).
    ok, tags, times = _block([1.0, 2.0, 3.0, 4.0, 5.0], [True, True, False, False, True])
    assert ok and list(tags) == [0, 4, 3] and list(times) == [1.0, 2.0, 5.0, 3.0, 4.0]


def test_is_blocked_and_profile_at():
    times = np.array([1.0, 2.0, 3.0, 4.0, 5.0])
    for t, blocked, row in [
        (0.5, True, 0),
        (1.0, False, 0),
        (2.0, False, 0),
        (2.5, True, 0),
        (3.0, False, 1),
        (4.5, True, 1),
        (5.0, False, 2),
        (9.0, False, 2),
    ]:
        assert is_blocked(times, t) == blocked, t
        assert profile_at(NO_BLOCK, times, t) == row, t
    # b below a: the latest right end at or before t wins.
    swapped = np.array([1.0, 4.0, 5.0, 2.0, 3.0])
    for t, row in [(1.5, 0), (3.0, 2), (3.5, 2), (5.0, 1), (9.0, 1)]:
        assert profile_at(NO_BLOCK, swapped, t) == row, t
    none = np.array([1.0, math.inf, math.inf, math.inf, math.inf])
    assert not is_blocked(none, 7.0)
    assert profile_at(NO_BLOCK, none, math.inf) == 0


@pytest.mark.slow
@pytest.mark.parametrize("family", sorted(FAMILIES))
def test_against_ruckig_sweep(family):
    worst, disagree, mismatch, invalid, intervals = compare_family(
        FAMILIES[family], N_SLOW, seed=2024
    )
    print(f"{family}: {N_SLOW} problems, worst relative duration error {worst:.2e}, "
          f"{intervals} blocked intervals")  # fmt: skip
    assert not disagree, disagree[:3]
    assert not mismatch, (worst, mismatch[:3])
    assert not invalid, invalid[:3]
