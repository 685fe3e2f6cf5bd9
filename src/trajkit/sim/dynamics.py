"""Inverse dynamics of a simulated arm for a whole trajectory at once.

MuJoCo's ``mj_inverse`` takes one state per call; feed-forward torques along a
plan are needed at every control time, so this evaluates the recursive
Newton–Euler equations (:func:`trajkit.kinematics.inverse_dynamics`) for all of
them in one vectorized pass, with the link masses and inertias MuJoCo compiled
from the scene. The result equals
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
from trajkit.kinematics.dynamics import inverse_dynamics as kinematic_dynamics
from trajkit.kinematics.inertials import Inertials
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
    inertials = Inertials(mass, com_local, inertia_local)
    rigid = kinematic_dynamics(
        robot, q, qd, qdd, inertials=inertials, gravity=np.array(model.opt.gravity)
    )
    armature, damping = model.dof_armature[dofs], model.dof_damping[dofs]
    return rigid + armature * qdd + damping * qd + model.opt.timestep * implicit * qdd


def _velocity_gains(model: Any, dofs: FloatArray) -> FloatArray:
    """Sum of the actuators' ``-∂force/∂velocity`` on each joint (N·m·s/rad)."""
    gains = np.zeros(len(dofs))
    for actuator in range(model.nu):
        dof = model.jnt_dofadr[model.actuator_trnid[actuator, 0]]
        where = np.flatnonzero(dofs == dof)
        # Affine bias b0 + b1 q + b2 q̇: position and velocity servos have b2 = -kv.
        gains[where] -= model.actuator_biasprm[actuator, 2]
    return gains
