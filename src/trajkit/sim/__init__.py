"""Physics simulation in MuJoCo: run arm and mobile-robot plans on simulated robots.

MuJoCo runs in-process, with no server and no ROS install; it is the optional
extra ``sim`` (``pip install "trajkit[sim]"``). Without it, :func:`run` raises
:class:`SimulationUnavailableError` with that command.

Examples
--------
>>> import numpy as np, trajkit as tk
>>> from trajkit import sim
>>> plan = tk.cubic(np.radians([0, 0]), np.radians([67, -45]), vmax=np.radians([9, 11]))
>>> log = sim.run(sim.rrbot_scene(), plan, controller="computed_torque")  # doctest: +SKIP
>>> log.max_error  # rad, per joint                                        # doctest: +SKIP
"""

from trajkit.sim.arm import ArmLog
from trajkit.sim.controllers import (
    ComputedTorque,
    PDFeedforward,
    PositionServo,
    VelocityServo,
    arm_controller,
)
from trajkit.sim.engine import SimulationUnavailableError, choose_gl_backend, mujoco_available
from trajkit.sim.render import frames, render_frames
from trajkit.sim.run import DEFAULT_RATES_HZ, run
from trajkit.sim.scenes import (
    ArmScene,
    MobileScene,
    arm_scene,
    jackal_scene,
    rrbot_scene,
    ur5_scene,
)
from trajkit.sim.wheeled import PhysicsLog

# MuJoCo fixes its OpenGL backend when first imported: choose one that renders
# without a screen before anything imports it.
choose_gl_backend()

__all__ = [
    "DEFAULT_RATES_HZ",
    "ArmLog",
    "ArmScene",
    "ComputedTorque",
    "MobileScene",
    "PDFeedforward",
    "PhysicsLog",
    "PositionServo",
    "SimulationUnavailableError",
    "VelocityServo",
    "arm_controller",
    "arm_scene",
    "frames",
    "jackal_scene",
    "mujoco_available",
    "render_frames",
    "rrbot_scene",
    "run",
    "ur5_scene",
]
