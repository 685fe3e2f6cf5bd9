"""The mass distribution of a serial arm's links, as rigid-body dynamics needs it."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from trajkit._validation import FloatArray, finite_array
from trajkit.errors import InvalidInputError

__all__ = ["Inertials"]

#: How far from symmetric (relative to the tensor's largest entry) an inertia may be.
_SYMMETRY_RTOL = 1e-9


@dataclass(frozen=True, init=False)
class Inertials:
    """The mass distribution of each link of a serial chain (SI units).

    Parameters
    ----------
    mass : array_like, shape (ndof,)
        Mass of the link each joint moves (kg), >= 0.
    center_of_mass : array_like, shape (ndof, 3)
        Its centre of mass in the link's frame (m): the frame of the joint that
        moves it, after the motion.
    inertia : array_like, shape (ndof, 3, 3)
        Its inertia tensor about the centre of mass, in the link's frame (kg·m²):
        symmetric and positive semi-definite, whose principal moments satisfy the
        triangle inequality (as every rigid body's do).
    """

    mass: FloatArray
    center_of_mass: FloatArray
    inertia: FloatArray

    def __init__(self, mass: ArrayLike, center_of_mass: ArrayLike, inertia: ArrayLike) -> None:
        mass = finite_array("mass", mass, unit="kg")
        if mass.ndim != 1 or mass.size == 0:
            raise InvalidInputError(
                f"mass must be one number per link, shape (ndof,), got shape {mass.shape}"
            )
        n = mass.size
        bad = np.flatnonzero(mass < 0.0)
        if bad.size:
            raise InvalidInputError(
                f"mass must be >= 0 kg, got {mass[bad[0]]:g} for link {bad[0] + 1}"
            )
        com = finite_array("center_of_mass", center_of_mass, unit="m")
        if com.shape != (n, 3):
            raise InvalidInputError(
                f"center_of_mass must have shape ({n}, 3) for {n} links, got {com.shape}"
            )
        tensor = finite_array("inertia", inertia, unit="kg·m²")
        if tensor.shape != (n, 3, 3):
            raise InvalidInputError(
                f"inertia must have shape ({n}, 3, 3) for {n} links, got {tensor.shape}"
            )
        for i, matrix in enumerate(tensor):
            _check_inertia(i, matrix)
        # Exactly symmetric, so M(q) is too.
        tensor = 0.5 * (tensor + tensor.transpose(0, 2, 1))
        for name, value in (("mass", mass), ("center_of_mass", com), ("inertia", tensor)):
            value = np.array(value)  # our own copy, frozen
            value.setflags(write=False)
            object.__setattr__(self, name, value)

    @property
    def ndof(self) -> int:
        """Number of links."""
        return self.mass.size


def _check_inertia(link: int, matrix: FloatArray) -> None:
    scale = float(np.abs(matrix).max())
    where = f"inertia of link {link + 1}"
    if np.abs(matrix - matrix.T).max() > _SYMMETRY_RTOL * scale:
        raise InvalidInputError(f"{where} must be symmetric, got {matrix.tolist()}")
    moments = np.linalg.eigvalsh(0.5 * (matrix + matrix.T))
    slack = _SYMMETRY_RTOL * scale
    if moments[0] < -slack:
        raise InvalidInputError(
            f"{where} must be positive semi-definite, got principal moments "
            f"{moments.tolist()} kg·m²"
        )
    # A rigid body's principal moments: the largest is at most the sum of the others.
    if moments[2] > moments[0] + moments[1] + slack:
        raise InvalidInputError(
            f"{where} is not a rigid body's: principal moments {moments.tolist()} kg·m² "
            "break the triangle inequality (largest > sum of the other two)"
        )
