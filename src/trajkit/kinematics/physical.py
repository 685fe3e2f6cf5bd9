"""What an arm is made of, kept with its kinematic chain: masses, sizes, friction.

A :class:`Physical` rides on a :class:`~trajkit.kinematics.SerialChain`
(``chain.physical``; ``chain.with_physical(...)`` attaches one). The built-in arms
carry their documented values, so that a MuJoCo scene, or any other reader, takes
them from the robot instead of keeping a second copy.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from trajkit._validation import finite_array
from trajkit.errors import InvalidInputError
from trajkit.kinematics.inertials import Inertials

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
    center_of_mass : array_like, shape (ndof, 3), optional
        Each link's centre of mass in its own frame, the frame of the joint that
        moves it after the motion (m).
    inertia : array_like, shape (ndof, 3, 3), optional
        Each link's inertia tensor about its centre of mass, in its own frame (kg·m²).
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
    center_of_mass: ArrayLike | None = None
    inertia: ArrayLike | None = None
    source: str = ""

    def inertials(self, ndof: int) -> Inertials:
        """The links' mass distribution for dynamics, or a refusal naming what is missing.

        A scalar ``link_mass`` is every link's mass.
        """
        missing = [
            name
            for name in ("link_mass", "center_of_mass", "inertia")
            if getattr(self, name) is None
        ]
        if missing:
            raise InvalidInputError(
                f"no {', '.join(missing)} in the arm's physical data "
                f"({self.source or 'no source'}): dynamics needs each link's mass, centre of "
                "mass and inertia"
            )
        mass = finite_array("link_mass", self.link_mass, unit="kg")
        if mass.ndim == 0:
            mass = np.full(ndof, float(mass))
        return Inertials(mass, self.center_of_mass, self.inertia)
