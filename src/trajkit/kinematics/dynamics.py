"""Inverse dynamics of a serial chain: recursive Newton–Euler, every sample at once.

``τ = M(q) q̈ + C(q, q̇) q̇ + g(q)`` for a whole trajectory in one pass along the
chain: the outward recursion carries each link's angular velocity and
acceleration and its frame's linear acceleration (gravity enters as an upward
acceleration of the base), the inward one sums the forces and moments each joint
transmits and projects them on its axis. Every sample is a column of the same
vector operations, so there is no Python loop per sample, only per joint.

A link's inertial data (:class:`Inertials`) are given in its own frame, which is
the frame of the joint that moves it, after the motion (as a URDF child link's
frame): its mass, the position of its centre of mass, and its inertia tensor
about the centre of mass. :func:`inertials_from_dh` converts data published in
Denavit–Hartenberg link frames (as Robotics Toolbox and manufacturers give them).
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from trajkit._validation import FloatArray, finite_array
from trajkit.errors import InvalidInputError
from trajkit.kinematics.chain import SerialChain
from trajkit.kinematics.inertials import Inertials
from trajkit.rotations import cross_columns

__all__ = ["STANDARD_GRAVITY", "inertials_from_dh", "inverse_dynamics", "path_dynamics"]

#: Gravity in the world frame (m/s²): standard gravity along -z.
STANDARD_GRAVITY = (0.0, 0.0, -9.80665)


def inertials_from_dh(
    chain: SerialChain,
    mass: ArrayLike,
    center_of_mass: ArrayLike,
    inertia: ArrayLike,
    *,
    convention: Literal["standard", "modified"] = "standard",
) -> Inertials:
    """:class:`Inertials` from data given in a chain's DH link frames.

    In the standard convention link ``i``'s frame sits at the far end of its DH row
    (``Rz(θ) Tz(d) Tx(a) Rx(α)``), where Robotics Toolbox's ``r`` and ``I`` and the
    manufacturers' tables put them; trajkit's link frame is the joint's frame, the
    row's start. The fixed rest of the row is the next joint's origin (the tool
    transform for the last link), so the data are carried back through it. In the
    modified convention (Craig) the link frame is the joint's frame already.

    Parameters
    ----------
    chain : SerialChain
        The chain built with ``SerialChain.from_dh`` in the same ``convention``.
    mass : array_like, shape (ndof,)
        Link masses (kg).
    center_of_mass : array_like, shape (ndof, 3)
        Centres of mass in the DH link frames (m).
    inertia : array_like, shape (ndof, 3, 3)
        Inertia tensors about the centres of mass, in the DH link frames (kg·m²).
    convention : {"standard", "modified"}
        The DH convention the data's frames follow.

    Returns
    -------
    Inertials
    """
    given = Inertials(mass, center_of_mass, inertia)
    if given.ndof != chain.ndof:
        raise InvalidInputError(
            f"{given.ndof} links of inertial data for the {chain.ndof}-joint chain {chain.name!r}"
        )
    if convention == "modified":
        return given
    if convention != "standard":
        raise InvalidInputError(f"convention must be 'standard' or 'modified', got {convention!r}")
    rest = [j.origin for j in chain.joints[1:]] + [chain.tool]
    rotation = np.stack([t[:3, :3] for t in rest])
    shift = np.stack([t[:3, 3] for t in rest])
    com = shift + np.einsum("nij,nj->ni", rotation, given.center_of_mass)
    tensor = rotation @ given.inertia @ rotation.transpose(0, 2, 1)
    return Inertials(given.mass, com, tensor)


def inverse_dynamics(
    chain: SerialChain,
    q: ArrayLike,
    qd: ArrayLike,
    qdd: ArrayLike,
    *,
    inertials: Inertials | None = None,
    gravity: ArrayLike = STANDARD_GRAVITY,
) -> FloatArray:
    """Joint torques (N·m, or N for a prismatic joint) that give ``qdd`` at ``(q, qd)``.

    ``τ = M(q) q̈ + C(q, q̇) q̇ + g(q)`` of the rigid links alone: no friction, rotor
    inertia or contact.

    Parameters
    ----------
    chain : SerialChain
    q, qd, qdd : array_like, shape (ndof,) or (m, ndof)
        Joint positions (rad or m), velocities (per s) and accelerations (per s²).
    inertials : Inertials, optional
        The links' mass distribution; default the chain's own
        (``chain.physical.inertials()``).
    gravity : array_like, shape (3,)
        Gravity's acceleration in the world frame (m/s²); ``(0, 0, 0)`` leaves it out.

    Returns
    -------
    ndarray, shape (ndof,) or (m, ndof)
        One row per sample, as ``q`` was given.

    Raises
    ------
    InvalidInputError
        Shapes that do not match the chain, NaN/inf, or no inertial data.
    """
    inertials = _inertials_for(chain, inertials)
    configs, rates, accelerations, g, single = _states(chain, q, qd, qdd, gravity)
    torque = _newton_euler(chain, inertials, _frames(chain, configs), rates, accelerations, g)
    return torque[0] if single else torque


def path_dynamics(
    chain: SerialChain,
    q: ArrayLike,
    dq: ArrayLike,
    ddq: ArrayLike,
    *,
    inertials: Inertials | None = None,
    gravity: ArrayLike = STANDARD_GRAVITY,
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Torques along a path ``q(s)`` as ``τ = a(s) s̈ + b(s) ṡ² + c(s)``.

    With ``q̇ = q' ṡ`` and ``q̈ = q' s̈ + q'' ṡ²``, the torques are affine in the path
    acceleration ``s̈`` and the squared path speed ``ṡ²``: ``a = M q'``,
    ``b = M q'' + C(q, q') q'`` (the velocity terms are quadratic in the rate) and
    ``c = g(q)``. A timing keeps torque limits where ``τ_lo <= a u + b x + c <= τ_hi``.

    Parameters
    ----------
    chain : SerialChain
    q, dq, ddq : array_like, shape (ndof,) or (m, ndof)
        The path and its first and second derivatives in ``s``, at the same points.
    inertials, gravity
        As for :func:`inverse_dynamics`.

    Returns
    -------
    a, b, c : ndarray, shape (ndof,) or (m, ndof)
        N·m (or N) per unit of ``s̈``, of ``ṡ²`` and alone.
    """
    inertials = _inertials_for(chain, inertials)
    configs, rate, curve, g, single = _states(chain, q, dq, ddq, gravity, names=("dq", "ddq"))
    frames = _frames(chain, configs)  # one pass along the chain serves all three terms
    zero, still = np.zeros_like(rate), np.zeros(3)
    terms = (
        _newton_euler(chain, inertials, frames, zero, rate, still),
        _newton_euler(chain, inertials, frames, rate, curve, still),
        _newton_euler(chain, inertials, frames, zero, zero, g),
    )
    a, b, c = (term[0] if single else term for term in terms)
    return a, b, c


def _inertials_for(chain: SerialChain, inertials: Inertials | None) -> Inertials:
    if inertials is None:
        physical = chain.physical
        if physical is None:
            raise InvalidInputError(
                f"the chain {chain.name!r} has no inertial data: give inertials= or attach a "
                "Physical with link_mass, center_of_mass and inertia (chain.with_physical)"
            )
        inertials = physical.inertials(chain.ndof)
    if not isinstance(inertials, Inertials):
        raise InvalidInputError(
            f"inertials must be a trajkit.kinematics.Inertials, got {type(inertials).__name__}"
        )
    if inertials.ndof != chain.ndof:
        raise InvalidInputError(
            f"{inertials.ndof} links of inertial data for the {chain.ndof}-joint chain "
            f"{chain.name!r}"
        )
    return inertials


def _states(
    chain: SerialChain,
    q: ArrayLike,
    rate: ArrayLike,
    second: ArrayLike,
    gravity: ArrayLike,
    names: tuple[str, str] = ("qd", "qdd"),
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, bool]:
    """``q`` and its two derivatives as (m, ndof) rows, gravity, and whether one was given."""
    configs, single = chain.configurations(q)
    first = _like(names[0], rate, configs.shape, single)
    other = _like(names[1], second, configs.shape, single)
    g = finite_array("gravity", gravity, unit="m/s²")
    if g.shape != (3,):
        raise InvalidInputError(f"gravity must be a 3-vector (m/s²), got shape {g.shape}")
    return configs, first, other, g, single


def _like(name: str, value: ArrayLike, shape: tuple[int, int], single: bool) -> FloatArray:
    array = finite_array(name, value)
    if single and array.shape == shape[1:]:
        return array[np.newaxis, :]
    if array.shape != shape:
        expected = shape[1:] if single else shape
        raise InvalidInputError(f"{name} must have shape {expected} like q, got {array.shape}")
    return array


def _frames(chain: SerialChain, q: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Each link's rotation (n, 3, 3, m), joint axis and frame origin (n, 3, m), world frame."""
    chain_pass = chain._pass(q, keep_rotations=True)
    origins = chain_pass.positions.copy()
    value = (q + chain._offsets).T
    for i in np.flatnonzero(~chain._revolute):
        # A slide joint carries its link along the axis; the pass gives where it starts.
        origins[i] += chain_pass.axes[i] * value[i]
    return chain_pass.rotations, chain_pass.axes, origins


def _newton_euler(
    chain: SerialChain,
    inertials: Inertials,
    frames: tuple[FloatArray, FloatArray, FloatArray],
    qd: FloatArray,
    qdd: FloatArray,
    gravity: FloatArray,
) -> FloatArray:
    """The recursion, component-major: every vector is (3, m), one column per sample."""
    m, n = qd.shape
    rotations, axes, origins = frames
    revolute = chain._revolute
    # Gravity acts as if the base accelerated upwards, so no link needs a weight term.
    accel = np.broadcast_to(-gravity[:, None], (3, m))
    omega = alpha = np.zeros((3, m))
    previous = chain.base[:3, 3, None]
    forces, moments = [], []
    for i in range(n):  # outwards along the chain; every sample at once
        rotation, axis = rotations[i], axes[i]
        lever = origins[i] - previous
        accel = (
            accel + cross_columns(alpha, lever) + cross_columns(omega, cross_columns(omega, lever))
        )
        rate = axis * qd[:, i]
        if revolute[i]:
            alpha = alpha + axis * qdd[:, i] + cross_columns(omega, rate)
            omega = omega + rate
        else:
            accel = accel + axis * qdd[:, i] + 2.0 * cross_columns(omega, rate)
        offset = _rotate(rotation, inertials.center_of_mass[i])
        com_accel = (
            accel
            + cross_columns(alpha, offset)
            + cross_columns(omega, cross_columns(omega, offset))
        )
        forces.append(inertials.mass[i] * com_accel)
        spin = _inertia_times(rotation, inertials.inertia[i], omega)
        moment = _inertia_times(rotation, inertials.inertia[i], alpha) + cross_columns(omega, spin)
        moments.append(moment + cross_columns(offset, forces[i]))
        previous = origins[i]
    torque = np.empty((m, n))
    force = moment = np.zeros((3, m))
    for i in reversed(range(n)):  # inwards: what each joint transmits
        if i + 1 < n:
            moment = moment + cross_columns(origins[i + 1] - origins[i], force)
        force = force + forces[i]
        moment = moment + moments[i]
        along = moment if revolute[i] else force
        torque[:, i] = (axes[i] * along).sum(axis=0)
    return torque


def _rotate(rotation: FloatArray, vector: FloatArray) -> FloatArray:
    """``R v`` for a (3, 3, m) stack of rotations and one vector (3,) or a (3, m) stack."""
    vector = vector.reshape(3, -1)
    return rotation[:, 0] * vector[0] + rotation[:, 1] * vector[1] + rotation[:, 2] * vector[2]


def _inertia_times(rotation: FloatArray, inertia: FloatArray, vector: FloatArray) -> FloatArray:
    """``R I Rᵀ v``: a link-frame inertia (3, 3) applied to world vectors (3, m)."""
    local = rotation[0] * vector[0] + rotation[1] * vector[1] + rotation[2] * vector[2]  # Rᵀ v
    return _rotate(rotation, inertia @ local)
