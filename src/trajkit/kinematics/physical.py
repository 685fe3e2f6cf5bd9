"""What an arm is made of, kept with its kinematic chain: masses, sizes, friction.

A :class:`Physical` rides on a :class:`~trajkit.kinematics.SerialChain`
(``chain.physical``; ``chain.with_physical(...)`` attaches one). The built-in arms
carry their documented values, so that a MuJoCo scene, or any other reader, takes
them from the robot instead of keeping a second copy.
"""

from __future__ import annotations

from dataclasses import dataclass

from numpy.typing import ArrayLike

__all__ = ["Physical"]


@dataclass(frozen=True)
class Physical:
    """A serial arm's physical data (SI units); None leaves a value to its reader's default.

    Parameters
    ----------
    link_mass : float or array_like, shape (ndof,), optional
        Mass of the link each joint moves (kg).
    link_radius : float, optional
        Radius of the links, modelled as capsules (m).
    damping : float or array_like, optional
        Viscous joint friction (N·m·s/rad, or N·s/m for a prismatic joint).
    armature : float or array_like, optional
        Rotor inertia reflected through the gearbox (kg·m²).
    effort_limit : float or array_like, optional
        Largest actuator torque (N·m) or force (N) per joint.
    source : str
        Where the values come from, in a few words.

    Values are checked against the chain's joints where they are used (a MuJoCo
    scene names the quantity, the value and the joint).
    """

    link_mass: ArrayLike | None = None
    link_radius: float | None = None
    damping: ArrayLike | None = None
    armature: ArrayLike | None = None
    effort_limit: ArrayLike | None = None
    source: str = ""
