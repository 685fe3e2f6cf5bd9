"""trajkit's cubic and quintic against peer libraries (Robotics Toolbox, Modern Robotics).

Both peers implement the same closed forms, so agreement is expected to the last digits:
ORACLE_RTOL (1e-9) relative to the size of the terms involved, i.e. position errors are
scaled by max(1, |q0|, |qf|, |v0| T, |vf| T), velocity errors by that over T, acceleration
errors by that over T**2.
"""

from __future__ import annotations

import numpy as np
import pytest

import trajkit as tk
from support import CLOSED_FORM

rtb = pytest.importorskip(
    "roboticstoolbox",
    reason="roboticstoolbox-python (the quintic/jtraj oracle) is not installed; "
    "pip install roboticstoolbox-python",
)
mr = pytest.importorskip(
    "modern_robotics",
    reason="modern_robotics (the time-scaling oracle) is not installed; "
    "pip install modern-robotics",
)

ORACLE_RTOL = CLOSED_FORM  # closed forms on both sides: 1e-9, scaled as described above


def _draw_values(rng: np.random.Generator, size: int) -> np.ndarray:
    """Values that deliberately include exact zeros, small and large magnitudes."""
    kind = rng.integers(0, 4, size)
    values = np.where(
        kind == 0,
        0.0,
        np.where(
            kind == 1,
            rng.uniform(-1.0, 1.0, size),
            np.where(kind == 2, rng.uniform(-1e3, 1e3, size), rng.uniform(-1e-3, 1e-3, size)),
        ),
    )
    return values


def _draw_duration(rng: np.random.Generator) -> float:
    return float(10 ** rng.uniform(-2.0, 2.0))


def _assert_agree(actual, expected, scale, what):
    actual, expected = np.asarray(actual, float), np.asarray(expected, float)
    error = np.abs(actual - expected) / scale
    assert np.all(error <= ORACLE_RTOL), (
        f"{what}: max scaled error {error.max():.3g} > {ORACLE_RTOL:g}"
    )


def _compare_quintic(q0, qf, qd0, qdf, T, m=51):
    t = np.linspace(0.0, T, m)
    t[-1] = T
    peer = rtb.quintic(q0, qf, t, qd0, qdf)
    ours = tk.quintic(q0, qf, T, v0=qd0, vf=qdf)
    scale = max(1.0, abs(q0), abs(qf), abs(qd0) * T, abs(qdf) * T)
    _assert_agree(ours.position(t)[:, 0], peer.q.ravel(), scale, "q")
    _assert_agree(ours.velocity(t)[:, 0], peer.qd.ravel(), scale / T, "qd")
    _assert_agree(ours.acceleration(t)[:, 0], peer.qdd.ravel(), scale / T**2, "qdd")


def _compare_jtraj(q0, qf, qd0, qd1, T, m=41):
    t = np.linspace(0.0, T, m)
    peer = rtb.jtraj(q0, qf, t, qd0, qd1)
    ours = tk.quintic(q0, qf, T, v0=qd0, vf=qd1)
    scale = np.maximum.reduce([np.ones_like(q0), abs(q0), abs(qf), abs(qd0) * T, abs(qd1) * T])
    _assert_agree(ours.position(t), peer.q, scale, "q")
    _assert_agree(ours.velocity(t), peer.qd, scale / T, "qd")
    _assert_agree(ours.acceleration(t), peer.qdd, scale / T**2, "qdd")


def _compare_time_scaling(Tf, t):
    cubic = tk.cubic(0.0, 1.0, Tf)
    quintic = tk.quintic(0.0, 1.0, Tf)
    s3 = np.array([mr.CubicTimeScaling(Tf, x) for x in t])
    s5 = np.array([mr.QuinticTimeScaling(Tf, x) for x in t])
    _assert_agree(cubic.position(t)[:, 0], s3, 1.0, "cubic s(t)")
    _assert_agree(quintic.position(t)[:, 0], s5, 1.0, "quintic s(t)")


# --------------------------------------------------------------------------------- tests
def test_oracles_agree_on_a_hand_case():
    # Both documented examples: quintic_func(1, 2, ...) and MR's Tf = 2, t = 0.6.
    _compare_quintic(1.0, 2.0, 0.0, 0.0, 10.0)
    assert mr.CubicTimeScaling(2, 0.6) == pytest.approx(0.216)
    assert tk.cubic(0.0, 1.0, 2.0).position(0.6)[0] == pytest.approx(0.216, rel=1e-15)
    assert tk.quintic(0.0, 1.0, 2.0).position(0.6)[0] == pytest.approx(0.16308, rel=1e-14)


@pytest.mark.parametrize("seed", range(10))
def test_quintic_matches_rtb_quintic(seed):
    rng = np.random.default_rng(seed)
    for _ in range(20):
        q0, qf, qd0, qdf = _draw_values(rng, 4)
        _compare_quintic(q0, qf, qd0, qdf, _draw_duration(rng))


@pytest.mark.parametrize(
    ("q0", "qf", "qd0", "qdf", "T"),
    [
        (0.0, 0.0, 0.0, 0.0, 1.0),  # no move at all
        (0.0, 0.0, 1.0, -1.0, 2.0),  # back to the start with velocities
        (5.0, 5.0, 0.0, 0.0, 0.01),  # a hold, very short
        (-1e3, 1e3, 0.0, 0.0, 100.0),  # large range, long move
        (1e-3, -1e-3, 0.0, 0.0, 0.01),  # tiny range, short move
        (0.0, 1.0, 1e3, 0.0, 0.5),  # large start velocity
    ],
)
def test_quintic_matches_rtb_quintic_edge_cases(q0, qf, qd0, qdf, T):
    _compare_quintic(q0, qf, qd0, qdf, T)


@pytest.mark.parametrize("seed", range(10))
def test_quintic_matches_rtb_jtraj(seed):
    rng = np.random.default_rng(100 + seed)
    for _ in range(10):
        ndof = int(rng.integers(1, 7))
        q0, qf = _draw_values(rng, ndof), _draw_values(rng, ndof)
        qd0, qd1 = _draw_values(rng, ndof), _draw_values(rng, ndof)
        _compare_jtraj(q0, qf, qd0, qd1, _draw_duration(rng))


@pytest.mark.parametrize("seed", range(5))
def test_normalized_cubic_and_quintic_match_modern_robotics(seed):
    rng = np.random.default_rng(200 + seed)
    for _ in range(20):
        Tf = _draw_duration(rng)
        t = np.concatenate([[0.0, Tf / 2, Tf], rng.uniform(0.0, Tf, 20)])
        _compare_time_scaling(Tf, t)


@pytest.mark.slow
def test_oracle_sweep():
    rng = np.random.default_rng(20240607)
    for _ in range(1500):
        q0, qf, qd0, qdf = _draw_values(rng, 4)
        _compare_quintic(q0, qf, qd0, qdf, _draw_duration(rng), m=21)
    for _ in range(1000):
        ndof = int(rng.integers(1, 7))
        values = _draw_values(rng, 4 * ndof).reshape(4, ndof)
        _compare_jtraj(*values, _draw_duration(rng), m=21)
    for _ in range(1000):
        Tf = _draw_duration(rng)
        _compare_time_scaling(Tf, np.concatenate([[0.0, Tf], rng.uniform(0.0, Tf, 10)]))
