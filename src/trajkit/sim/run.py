"""``trajkit.sim.run``: one entry point for arm and mobile scenes."""

from __future__ import annotations

from typing import Any

from trajkit.errors import InvalidInputError
from trajkit.sim.arm import ArmLog, run_arm
from trajkit.sim.scenes import ArmScene, MobileScene
from trajkit.sim.wheeled import PhysicsLog, run_mobile

__all__ = ["DEFAULT_RATES_HZ", "run"]

#: Default control rates: a typical arm joint controller, the Jackal's base controller.
DEFAULT_RATES_HZ = {"arm": 1000.0, "mobile": 50.0}


def run(
    scene: ArmScene | MobileScene,
    plan: Any,
    *,
    control_rate_hz: float | None = None,
    duration: float | None = None,
    controller: Any = None,
    **options: Any,
) -> ArmLog | PhysicsLog:
    """Execute a plan on a simulated robot and log desired against actual.

    The robot starts from a reset state matching the plan's start (joint
    positions and velocities; or the base's pose at rest). The same inputs give
    the same log, bit for bit.

    Parameters
    ----------
    scene : ArmScene or MobileScene
    plan : Trajectory or MobileTrajectory
        A joint trajectory for an arm scene, a mobile plan for a mobile scene.
    control_rate_hz : float, optional
        How often commands are sent (Hz); the period must be a whole number of
        the scene's physics steps. Default 1000 Hz for arms, 50 Hz for bases.
    duration : float, optional
        How long to run (s); default the plan's duration. After the plan's end the
        robot is asked to stand still at its final position (or pose).
    controller : optional
        Arms: ``"position"`` (default), ``"velocity"``, ``"pd_feedforward"``,
        ``"computed_torque"`` or one of :class:`PositionServo`,
        :class:`VelocityServo`, :class:`PDFeedforward`, :class:`ComputedTorque`
        with its gains. Bases: any :mod:`trajkit.mobile` controller
        (:class:`~trajkit.mobile.Feedforward` by default,
        :class:`~trajkit.mobile.Kanayama`, ...).
    **options
        Mobile scenes only: ``initial_pose`` (x, y, θ), ``limits``
        (:class:`~trajkit.mobile.MobileLimits` the commands are saturated to;
        default the plan's) and ``feedback`` (``"ground_truth"``, the default, or
        ``"odometry"``: what the controller sees).

    Returns
    -------
    ArmLog or PhysicsLog
        One row per control time, with RMS / maximum errors and peak efforts.

    Raises
    ------
    SimulationUnavailableError
        If MuJoCo is not installed.
    InvalidInputError
        For a plan that does not fit the scene, a control period that is not a
        whole number of physics steps, unknown controllers or options.
    """
    if isinstance(scene, ArmScene):
        if options:
            raise InvalidInputError(
                f"arm scenes take no {', '.join(sorted(options))}; those are for mobile scenes"
            )
        return run_arm(
            scene,
            plan,
            control_rate_hz=DEFAULT_RATES_HZ["arm"] if control_rate_hz is None else control_rate_hz,
            duration=duration,
            controller="position" if controller is None else controller,
        )
    if isinstance(scene, MobileScene):
        unknown = set(options) - {"initial_pose", "limits", "feedback"}
        if unknown:
            raise InvalidInputError(f"unknown option(s) for a mobile run: {sorted(unknown)}")
        rate = DEFAULT_RATES_HZ["mobile"] if control_rate_hz is None else control_rate_hz
        return run_mobile(
            scene, plan, control_rate_hz=rate, duration=duration, controller=controller, **options
        )
    raise InvalidInputError(
        f"scene must be an ArmScene or a MobileScene, got {type(scene).__name__}"
    )
