"""Inverse dynamics of a simulated arm for a whole trajectory at once.

MuJoCo's ``mj_inverse`` takes one state per call; feed-forward torques along a
plan are needed at every control time, so this evaluates the recursive
Newton–Euler equations for all of them in one vectorized pass, with the link
masses and inertias MuJoCo compiled from the scene. The result equals
``mj_inverse`` with discrete-time inverse dynamics (``invdiscrete``) for the
scene's ``implicitfast`` integrator: joint damping and actuator velocity gains,
integrated implicitly, add ``h (damping + kv) q̈``.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation

from trajkit._validation import FloatArray
from trajkit.kinematics.chain import SerialChain
from trajkit.rotations import cross_columns
from trajkit.sim.engine import mujoco_module

__all__ = ["inverse_dynamics"]


def inverse_dynamics(
    robot: SerialChain, model: Any, q: FloatArray, qd: FloatArray, qdd: FloatArray
) -> FloatArray:
    """Joint torques (N·m, or N) that give accelerations ``qdd`` at states ``(q, qd)``.

    Parameters
    ----------
    robot : SerialChain
        The chain the MuJoCo ``model`` was written from (bodies ``link1`` ...).
    model : mujoco.MjModel
    q, qd, qdd : ndarray, shape (m, ndof)

    Returns
    -------
    ndarray, shape (m, ndof)
    """
    mujoco = mujoco_module()
    n = robot.ndof
    bodies = [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, f"link{i + 1}") for i in range(n)]
    mass = model.body_mass[bodies]  # (n,)
    com_local = model.body_ipos[bodies]  # (n, 3) in each body's frame
    # MuJoCo stores quaternions scalar first; scipy takes them scalar last.
    principal = Rotation.from_quat(model.body_iquat[bodies][:, [1, 2, 3, 0]]).as_matrix()
    inertia_local = principal @ (
        model.body_inertia[bodies][:, :, None] * principal.transpose(0, 2, 1)
    )
    dofs = model.jnt_dofadr[[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, j.name)
                             for j in robot.joints]]  # fmt: skip
    # Velocity-dependent forces that implicitfast integrates implicitly.
    implicit = model.dof_damping[dofs] + _velocity_gains(model, dofs)
    # The chain's own batched pass, component-major: (3, 3, m) rotations and (3, m)
    # vectors per link keep every product below contiguous.
    chain_pass = robot._pass(np.asarray(q, dtype=float), keep_rotations=True)
    rotations, axes = chain_pass.rotations, chain_pass.axes
    origins = chain_pass.positions.copy()
    value = (q + np.array([j.offset for j in robot.joints])).T
    for i in np.flatnonzero(~robot.revolute):
        # A slide joint carries its body along the axis; the pass gives where it starts.
        origins[i] += axes[i] * value[i]
    gravity_accel = np.broadcast_to(-model.opt.gravity[:, None], (3, q.shape[0]))
    omega = alpha = np.zeros((3, q.shape[0]))
    accel, previous = gravity_accel, robot.base[:3, 3, None]
    forces, moments = [], []
    for i in range(n):  # the recursion runs along the chain; every sample at once
        rotation, axis = rotations[i], axes[i]
        lever = origins[i] - previous
        accel = (
            accel + cross_columns(alpha, lever) + cross_columns(omega, cross_columns(omega, lever))
        )
        rate = axis * qd[:, i]
        if robot.revolute[i]:
            alpha = alpha + axis * qdd[:, i] + cross_columns(omega, rate)
            omega = omega + rate
        else:
            accel = accel + axis * qdd[:, i] + 2.0 * cross_columns(omega, rate)
        offset = _rotate(rotation, com_local[i])
        com_accel = (
            accel
            + cross_columns(alpha, offset)
            + cross_columns(omega, cross_columns(omega, offset))
        )
        forces.append(mass[i] * com_accel)
        spin = _inertia_times(rotation, inertia_local[i], omega)
        moment = _inertia_times(rotation, inertia_local[i], alpha) + cross_columns(omega, spin)
        moments.append(moment + cross_columns(offset, forces[i]))
        previous = origins[i]
    torque = np.empty(q.shape)
    force = moment = np.zeros((3, q.shape[0]))
    for i in reversed(range(n)):
        if i + 1 < n:
            moment = moment + cross_columns(origins[i + 1] - origins[i], force)
        force = force + forces[i]
        moment = moment + moments[i]
        along = moment if robot.revolute[i] else force
        torque[:, i] = (axes[i] * along).sum(axis=0)
    armature, damping = model.dof_armature[dofs], model.dof_damping[dofs]
    return torque + armature * qdd + damping * qd + model.opt.timestep * implicit * qdd


def _rotate(rotation: FloatArray, vector: FloatArray) -> FloatArray:
    """``R v`` for a (3, 3, m) stack of rotations and one vector (3,) or a (3, m) stack."""
    vector = vector.reshape(3, -1)
    return rotation[:, 0] * vector[0] + rotation[:, 1] * vector[1] + rotation[:, 2] * vector[2]


def _inertia_times(rotation: FloatArray, inertia: FloatArray, vector: FloatArray) -> FloatArray:
    """``R I Rᵀ v``: a body-frame inertia (3, 3) applied to world vectors (3, m)."""
    local = rotation[0] * vector[0] + rotation[1] * vector[1] + rotation[2] * vector[2]  # Rᵀ v
    return _rotate(rotation, inertia @ local)


def _velocity_gains(model: Any, dofs: FloatArray) -> FloatArray:
    """Sum of the actuators' ``-∂force/∂velocity`` on each joint (N·m·s/rad)."""
    gains = np.zeros(len(dofs))
    for actuator in range(model.nu):
        dof = model.jnt_dofadr[model.actuator_trnid[actuator, 0]]
        where = np.flatnonzero(dofs == dof)
        # Affine bias b0 + b1 q + b2 q̇: position and velocity servos have b2 = -kv.
        gains[where] -= model.actuator_biasprm[actuator, 2]
    return gains
