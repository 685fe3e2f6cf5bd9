"""Rotations and rigid transforms, batched: axis-angle, homogeneous matrices, SLERP.

Conversions between rotation matrices, quaternions and rotation vectors are
delegated to :class:`scipy.spatial.transform.Rotation`; this module adds the
few batched operations trajkit needs around them. Quaternions are scalar-last
``(x, y, z, w)``, as scipy stores them.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from trajkit._validation import finite_array
from trajkit.errors import InvalidInputError

FloatArray = NDArray[np.float64]

__all__ = [
    "as_rotation_matrices",
    "axis_rotation",
    "cross_columns",
    "homogeneous",
    "rotation_error",
    "rpy_matrix",
    "slerp_axis",
]


def axis_rotation(axis: FloatArray, angle: FloatArray) -> FloatArray:
    """Rotation matrices about one unit ``axis`` by ``angle`` (rad), shape ``angle.shape + (3, 3)``.

    Rodrigues' formula, evaluated for every angle at once.
    """
    k = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    angle = np.asarray(angle, dtype=np.float64)[..., np.newaxis, np.newaxis]
    return np.eye(3) + np.sin(angle) * k + (1.0 - np.cos(angle)) * (k @ k)


def homogeneous(
    rotation: ArrayLike | None = None, translation: ArrayLike | None = None
) -> FloatArray:
    """A 4x4 homogeneous transform from a 3x3 rotation and a translation (defaults: identity)."""
    out = np.eye(4)
    if rotation is not None:
        out[:3, :3] = rotation
    if translation is not None:
        out[:3, 3] = translation
    return out


def rpy_matrix(rpy: ArrayLike) -> FloatArray:
    """Rotation from roll, pitch, yaw (rad) about fixed x, y, z axes, as URDF defines it."""
    from scipy.spatial.transform import Rotation  # slow to import: on first use

    return Rotation.from_euler("xyz", np.asarray(rpy, dtype=np.float64)).as_matrix()


def rotation_error(target: FloatArray, actual: FloatArray) -> FloatArray:
    """Rotation vector (rad) that turns ``actual`` into ``target``, in the world frame.

    ``log(target @ actual.T)`` for stacks of 3x3 matrices of shape ``(..., 3, 3)``;
    its norm is the angle between the two orientations.
    """
    relative = (target @ np.swapaxes(actual, -1, -2)).reshape(-1, 3, 3)
    # log map: the skew part gives sin(angle) * axis, the trace cos(angle).
    skew = 0.5 * np.stack(
        [
            relative[:, 2, 1] - relative[:, 1, 2],
            relative[:, 0, 2] - relative[:, 2, 0],
            relative[:, 1, 0] - relative[:, 0, 1],
        ],
        axis=1,
    )
    sine = np.linalg.norm(skew, axis=1)
    cosine = np.clip(0.5 * (np.trace(relative, axis1=1, axis2=2) - 1.0), -1.0, 1.0)
    angle = np.arctan2(sine, cosine)
    small = sine < 1e-12
    ratio = np.where(small, 1.0, angle / np.where(small, 1.0, sine))
    out = skew * ratio[:, np.newaxis]
    # Near a half turn the skew part vanishes and loses the axis: scipy's
    # quaternion route is exact there.
    flipped = cosine < -0.9
    if flipped.any():
        from scipy.spatial.transform import Rotation

        out[flipped] = Rotation.from_matrix(relative[flipped]).as_rotvec()
    return out.reshape((*np.shape(target)[:-2], 3))


def slerp_axis(start: FloatArray, end: FloatArray) -> tuple[FloatArray, float]:
    """World-frame unit axis and angle (rad) of the shortest rotation from ``start`` to ``end``.

    SLERP from ``start`` to ``end`` turns about this fixed axis at a rate
    ``angle * ds/dt``, so angular velocity and acceleration follow from the time law.
    A zero rotation returns the x axis and angle 0.
    """
    rotvec = rotation_error(end, start)
    angle = float(np.linalg.norm(rotvec))
    if angle == 0.0:
        return np.array([1.0, 0.0, 0.0]), 0.0
    return rotvec / angle, angle


def as_rotation_matrices(name: str, value: ArrayLike) -> FloatArray:
    """Check that ``value`` holds proper rotation matrices, shape ``(..., 3, 3)``."""
    array = finite_array(name, value)
    if array.ndim < 2 or array.shape[-2:] != (3, 3):
        raise InvalidInputError(f"{name} must be 3x3 rotation matrices, got shape {array.shape}")
    gram = array @ np.swapaxes(array, -1, -2)
    if not np.allclose(gram, np.eye(3), atol=1e-6) or np.any(np.linalg.det(array) < 0):
        raise InvalidInputError(f"{name} is not a rotation matrix (orthonormal, determinant +1)")
    return array


def cross_columns(a: FloatArray, b: FloatArray) -> FloatArray:
    """Cross products of component-major stacks, (..., 3, m) (np.cross's axis handling is slow)."""
    x0, x1, x2 = a[..., 0, :], a[..., 1, :], a[..., 2, :]
    y0, y1, y2 = b[..., 0, :], b[..., 1, :], b[..., 2, :]
    return np.stack([x1 * y2 - x2 * y1, x2 * y0 - x0 * y2, x0 * y1 - x1 * y0], axis=-2)
