"""Tests of trajkit.kinematics.dynamics: recursive Newton–Euler inverse dynamics.

Closed forms (the planar two-link arm of every textbook), the structure every
rigid chain's equations have (``M(q)`` symmetric positive definite, linear in
``q̈``, Coriolis terms from the Christoffel symbols of ``M``, gravity the gradient
of the potential energy), and refusals. The comparison with Robotics Toolbox is in
``tests/oracles/test_oracle_dynamics.py``, with MuJoCo in ``tests/sim``.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from support import CLOSED_FORM, FINITE_DIFFERENCE
from trajkit import InvalidInputError
from trajkit.kinematics import (
    UR5,
    DHRow,
    Inertials,
    Physical,
    SerialChain,
    inertials_from_dh,
    inverse_dynamics,
    path_dynamics,
)

ROUNDING = 1e-12  # relative to the largest torque: the same sums in another order
FEW = settings(max_examples=30, deadline=None)


def random_inertia(rng: np.random.Generator) -> np.ndarray:
    """A rigid body's inertia tensor: random principal moments and axes."""
    a, b = rng.uniform(0.01, 0.5, 2)
    c = rng.uniform(abs(a - b), a + b)  # the triangle inequality
    axes, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    return axes @ np.diag([a, b, c]) @ axes.T


def random_arm(rng: np.random.Generator, ndof: int, prismatic: bool = True):
    """A random standard-DH chain with random inertial data (in trajkit's link frames)."""
    rows = []
    for _ in range(ndof):
        kind = "prismatic" if prismatic and rng.random() < 0.3 else "revolute"
        rows.append(
            DHRow(
                a=rng.uniform(-0.5, 0.5),
                alpha=rng.uniform(-np.pi, np.pi),
                d=rng.uniform(-0.3, 0.3),
                theta=rng.uniform(-np.pi, np.pi),
                kind=kind,
            )
        )
    base = np.eye(4)
    base[:3, 3] = rng.uniform(-1, 1, 3)
    chain = SerialChain.from_dh(rows, base=base)
    inertials = Inertials(
        rng.uniform(0.2, 5.0, ndof),
        rng.uniform(-0.2, 0.2, (ndof, 3)),
        np.stack([random_inertia(rng) for _ in range(ndof)]),
    )
    return chain, inertials


def mass_matrix(chain, inertials, q):
    """``M(q)``: the torques of unit accelerations, without gravity or velocity."""
    n = chain.ndof
    zero = np.zeros(n)
    columns = [
        inverse_dynamics(chain, q, zero, np.eye(n)[k], inertials=inertials, gravity=(0, 0, 0))
        for k in range(n)
    ]
    return np.stack(columns, axis=1)


def two_link(l1=0.7, l2=0.5, lc1=0.3, lc2=0.2, m1=2.0, m2=1.5, i1=0.05, i2=0.03):
    """The planar arm in the vertical xy plane, gravity along -y (standard DH frames)."""
    chain = SerialChain.from_dh([DHRow(a=l1), DHRow(a=l2)])
    # In a standard DH frame the link ends at the origin: its centre is lc - l along x.
    inertia = np.zeros((2, 3, 3))
    inertia[0] = np.diag([0.0, i1, i1])
    inertia[1] = np.diag([0.0, i2, i2])
    com = [[lc1 - l1, 0.0, 0.0], [lc2 - l2, 0.0, 0.0]]
    return chain, inertials_from_dh(chain, [m1, m2], com, inertia)


def two_link_closed_form(q, qd, qdd, g0=9.81, l1=0.7, lc1=0.3, lc2=0.2, m1=2.0, m2=1.5, i1=0.05,
                         i2=0.03):  # fmt: skip
    c1, c2, c12, s2 = np.cos(q[0]), np.cos(q[1]), np.cos(q[0] + q[1]), np.sin(q[1])
    m11 = m1 * lc1**2 + m2 * (l1**2 + lc2**2 + 2 * l1 * lc2 * c2) + i1 + i2
    m12 = m2 * (lc2**2 + l1 * lc2 * c2) + i2
    m22 = m2 * lc2**2 + i2
    h = m2 * l1 * lc2 * s2
    tau1 = m11 * qdd[0] + m12 * qdd[1] - h * (2 * qd[0] * qd[1] + qd[1] ** 2)
    tau2 = m12 * qdd[0] + m22 * qdd[1] + h * qd[0] ** 2
    tau1 += (m1 * lc1 + m2 * l1) * g0 * c1 + m2 * lc2 * g0 * c12
    tau2 += m2 * lc2 * g0 * c12
    return np.array([tau1, tau2])


@FEW
@given(st.lists(st.floats(-3, 3), min_size=6, max_size=6))
def test_the_planar_two_link_arm_matches_its_closed_form(values):
    q, qd, qdd = np.reshape(values, (3, 2))
    chain, inertials = two_link()
    tau = inverse_dynamics(chain, q, qd, qdd, inertials=inertials, gravity=(0, -9.81, 0))
    expected = two_link_closed_form(q, qd, qdd)
    scale = max(1.0, np.abs(expected).max())
    np.testing.assert_allclose(tau, expected, rtol=0, atol=CLOSED_FORM * scale)


@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_a_slider_holds_its_weight_along_its_axis(convention):
    """One prismatic joint at rest: the force is the weight's component along the axis."""
    chain = SerialChain.from_dh(
        [DHRow(a=0.3, alpha=0.7, d=0.1, theta=0.4, kind="prismatic")], convention=convention
    )
    inertials = inertials_from_dh(chain, [2.0], [[0.1, 0.0, 0.05]], [np.eye(3) * 0.1],
                                  convention=convention)  # fmt: skip
    gravity = np.array([0.5, -1.0, -9.81])
    q = np.array([0.2])
    axis = chain.jacobian(q)[:3, 0]
    force = inverse_dynamics(chain, q, [0.0], [0.0], inertials=inertials, gravity=gravity)
    np.testing.assert_allclose(force, [-2.0 * gravity @ axis], rtol=CLOSED_FORM)


def test_a_batch_equals_its_samples_one_at_a_time():
    rng = np.random.default_rng(1)
    chain, inertials = random_arm(rng, 5)
    q, qd, qdd = rng.normal(size=(3, 40, 5))
    batch = inverse_dynamics(chain, q, qd, qdd, inertials=inertials)
    assert batch.shape == (40, 5)
    single = np.stack(
        [inverse_dynamics(chain, *row, inertials=inertials) for row in zip(q, qd, qdd, strict=True)]
    )
    np.testing.assert_allclose(batch, single, rtol=0, atol=ROUNDING * np.abs(batch).max())


@FEW
@given(st.integers(0, 2**32 - 1), st.integers(1, 7))
def test_the_mass_matrix_is_symmetric_positive_definite_and_linear_in_acceleration(seed, ndof):
    rng = np.random.default_rng(seed)
    chain, inertials = random_arm(rng, ndof)
    q, qd, qdd = rng.normal(size=(3, ndof))
    m = mass_matrix(chain, inertials, q)
    scale = np.abs(m).max()
    np.testing.assert_allclose(m, m.T, rtol=0, atol=ROUNDING * scale)
    assert np.linalg.eigvalsh(m).min() > 0
    # τ(q, q̇, q̈) - τ(q, q̇, 0) = M(q) q̈
    with_qdd = inverse_dynamics(chain, q, qd, qdd, inertials=inertials)
    without = inverse_dynamics(chain, q, qd, np.zeros(ndof), inertials=inertials)
    np.testing.assert_allclose(
        with_qdd - without, m @ qdd, rtol=0, atol=ROUNDING * 10 * max(1.0, np.abs(with_qdd).max())
    )


@FEW
@given(st.integers(0, 2**32 - 1), st.integers(1, 6))
def test_velocity_terms_are_the_christoffel_terms_of_the_mass_matrix(seed, ndof):
    """``C(q, q̇) q̇ = Ṁ q̇ − ½ ∂(q̇ᵀ M q̇)/∂q``, the Lagrangian's velocity terms."""
    rng = np.random.default_rng(seed)
    chain, inertials = random_arm(rng, ndof)
    q, qd = rng.normal(size=(2, ndof))
    zero = np.zeros(ndof)
    coriolis = inverse_dynamics(chain, q, qd, zero, inertials=inertials, gravity=(0, 0, 0))
    h = 1e-6
    dm = []  # ∂M/∂q_k by central differences
    for k in range(ndof):
        step = np.eye(ndof)[k] * h
        plus = mass_matrix(chain, inertials, q + step)
        minus = mass_matrix(chain, inertials, q - step)
        dm.append((plus - minus) / (2 * h))
    m_dot = sum(dm[k] * qd[k] for k in range(ndof))
    gradient = np.array([qd @ dm[k] @ qd for k in range(ndof)])
    expected = m_dot @ qd - 0.5 * gradient
    scale = max(1.0, np.abs(expected).max())
    np.testing.assert_allclose(coriolis, expected, rtol=0, atol=FINITE_DIFFERENCE * scale)


def test_gravity_torques_are_the_gradient_of_the_potential_energy():
    rng = np.random.default_rng(7)
    chain, inertials = random_arm(rng, 6)
    gravity = np.array([0.3, -1.2, -9.7])
    q = rng.normal(size=6)

    def potential(config):
        frames = chain._pass(config[np.newaxis], keep_rotations=True)
        energy = 0.0
        value = config + np.array([j.offset for j in chain.joints])
        for i in range(6):
            origin = frames.positions[i, :, 0]
            if not chain.revolute[i]:
                origin = origin + frames.axes[i, :, 0] * value[i]
            com = origin + frames.rotations[i, :, :, 0] @ inertials.center_of_mass[i]
            energy -= inertials.mass[i] * gravity @ com
        return energy

    h = 1e-6
    gradient = np.array(
        [(potential(q + h * e) - potential(q - h * e)) / (2 * h) for e in np.eye(6)]
    )
    tau = inverse_dynamics(chain, q, np.zeros(6), np.zeros(6), inertials=inertials, gravity=gravity)
    np.testing.assert_allclose(tau, gradient, rtol=0, atol=FINITE_DIFFERENCE * np.abs(tau).max())


def test_the_chains_own_physical_data_are_used():
    rng = np.random.default_rng(3)
    chain, inertials = random_arm(rng, 4)
    carrying = chain.with_physical(
        Physical(
            link_mass=inertials.mass,
            center_of_mass=inertials.center_of_mass,
            inertia=inertials.inertia,
        )
    )
    q, qd, qdd = rng.normal(size=(3, 4))
    np.testing.assert_array_equal(
        inverse_dynamics(carrying, q, qd, qdd),
        inverse_dynamics(chain, q, qd, qdd, inertials=inertials),
    )


def test_a_scalar_link_mass_is_every_links_mass():
    inertials = Physical(link_mass=2.0, center_of_mass=np.zeros((3, 3)),
                         inertia=np.zeros((3, 3, 3))).inertials(3)  # fmt: skip
    np.testing.assert_array_equal(inertials.mass, [2.0, 2.0, 2.0])


def test_inertials_are_frozen_copies():
    mass = np.array([1.0, 2.0])
    inertials = Inertials(mass, np.zeros((2, 3)), np.zeros((2, 3, 3)))
    mass[0] = 5.0
    assert inertials.mass[0] == 1.0
    with pytest.raises(ValueError, match="read-only"):
        inertials.mass[0] = 3.0


@FEW
@given(st.integers(0, 2**32 - 1), st.floats(0.0, 5.0), st.floats(-5.0, 5.0))
def test_path_torques_are_affine_in_path_acceleration_and_squared_speed(seed, speed, u):
    rng = np.random.default_rng(seed)
    chain, inertials = random_arm(rng, 5)
    q, dq, ddq = rng.normal(size=(3, 7, 5))
    a, b, c = path_dynamics(chain, q, dq, ddq, inertials=inertials)
    direct = inverse_dynamics(chain, q, dq * speed, dq * u + ddq * speed**2, inertials=inertials)
    scale = max(1.0, np.abs(direct).max())
    np.testing.assert_allclose(a * u + b * speed**2 + c, direct, rtol=0, atol=ROUNDING * 10 * scale)


# ----------------------------------------------------------------------- refusals
def test_a_chain_without_inertial_data_is_refused_by_name():
    with pytest.raises(InvalidInputError, match=r"no inertial data.*inertials="):
        inverse_dynamics(SerialChain.from_dh([DHRow(a=1.0)]), [0.0], [0.0], [0.0])


def test_missing_inertias_are_named():
    arm = UR5()
    masses_only = arm.with_physical(Physical(link_mass=arm.physical.link_mass, source="UR5 masses"))
    with pytest.raises(InvalidInputError, match=r"no center_of_mass, inertia in .*UR5 masses"):
        inverse_dynamics(masses_only, np.zeros(6), np.zeros(6), np.zeros(6))


GOOD = {"mass": [1.0, 2.0], "center_of_mass": np.zeros((2, 3)), "inertia": np.zeros((2, 3, 3))}


@pytest.mark.parametrize(
    ("field", "value", "message"),
    [
        ("mass", [1.0, -2.0], r"mass must be >= 0 kg, got -2 for link 2"),
        ("mass", [[1.0, 2.0]], r"mass must be one number per link"),
        ("mass", [1.0, np.nan], r"mass"),
        ("mass", [1.0, 1e308 * 10], r"mass"),
        ("center_of_mass", np.zeros((2, 2)), r"center_of_mass must have shape \(2, 3\)"),
        ("center_of_mass", [[0, 0, 0], [0, 0, np.inf]], r"center_of_mass"),
        ("inertia", np.zeros((3, 3, 3)), r"inertia must have shape \(2, 3, 3\)"),
        ("inertia", [np.eye(3), [[1, 0.5, 0], [0, 1, 0], [0, 0, 1]]],
         r"inertia of link 2 must be symmetric"),
        ("inertia", [np.eye(3), np.diag([1.0, 1.0, -1.0])],
         r"inertia of link 2 must be positive semi-definite"),
        ("inertia", [np.diag([1.0, 1.0, 3.0]), np.eye(3)],
         r"inertia of link 1 is not a rigid body's.*triangle inequality"),
    ],
)  # fmt: skip
def test_bad_inertials_are_refused_by_name(field, value, message):
    with pytest.raises(InvalidInputError, match=message):
        Inertials(**{**GOOD, field: value})


def test_bad_states_and_gravity_are_refused():
    chain, inertials = two_link()
    zero = np.zeros(2)
    with pytest.raises(InvalidInputError, match=r"qd must have shape \(2,\) like q"):
        inverse_dynamics(chain, zero, np.zeros(3), zero, inertials=inertials)
    with pytest.raises(InvalidInputError, match=r"qdd must have shape \(4, 2\) like q"):
        inverse_dynamics(chain, np.zeros((4, 2)), np.zeros((4, 2)), zero, inertials=inertials)
    with pytest.raises(InvalidInputError, match="qd"):
        inverse_dynamics(chain, zero, [np.nan, 0.0], zero, inertials=inertials)
    with pytest.raises(InvalidInputError, match=r"gravity must be a 3-vector"):
        inverse_dynamics(chain, zero, zero, zero, inertials=inertials, gravity=(0, -9.81))
    with pytest.raises(InvalidInputError, match=r"3 links of inertial data for the 2-joint"):
        inverse_dynamics(chain, zero, zero, zero, inertials=Inertials(
            [1.0] * 3, np.zeros((3, 3)), np.zeros((3, 3, 3))))  # fmt: skip
    with pytest.raises(
        InvalidInputError, match=r"inertials must be a trajkit\.kinematics\.Inertials"
    ):
        inverse_dynamics(chain, zero, zero, zero, inertials={"mass": [1, 2]})
    with pytest.raises(InvalidInputError, match=r"3 links of inertial data for the 2-joint"):
        inertials_from_dh(chain, [1.0] * 3, np.zeros((3, 3)), np.zeros((3, 3, 3)))
    with pytest.raises(InvalidInputError, match=r"convention must be 'standard' or 'modified'"):
        inertials_from_dh(chain, [1.0] * 2, np.zeros((2, 3)), np.zeros((2, 3, 3)), convention="dh")
