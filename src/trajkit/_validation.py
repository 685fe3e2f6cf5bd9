"""Argument checks shared by every public function.

Each helper names the argument in its error message, so a user learns which
value was wrong and what rule it broke.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from trajkit.errors import InvalidInputError

FloatArray = NDArray[np.float64]


def _describe(value: Any) -> str:
    text = np.array2string(np.asarray(value), precision=6, threshold=8)
    return text if len(text) < 80 else text[:77] + "..."


def finite_array(name: str, value: ArrayLike, *, unit: str = "") -> FloatArray:
    """Return ``value`` as a float64 array, refusing NaN, inf and non-numbers.

    The result may share memory with ``value``: callers that keep it copy it.
    """
    try:
        array = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InvalidInputError(f"{name} must be numeric, got {value!r}") from exc
    if not np.all(np.isfinite(array)):
        unit_text = f" {unit}" if unit else ""
        raise InvalidInputError(f"{name} must be finite, got {_describe(array)}{unit_text}")
    return array


def finite_scalar(name: str, value: Any, *, unit: str = "") -> float:
    """Return ``value`` as a finite float."""
    array = finite_array(name, value, unit=unit)
    if array.ndim != 0:
        raise InvalidInputError(f"{name} must be a single number, got shape {array.shape}")
    return float(array)


def positive_scalar(name: str, value: Any, *, unit: str = "") -> float:
    """Return ``value`` as a finite float > 0."""
    number = finite_scalar(name, value, unit=unit)
    if number <= 0.0:
        unit_text = f" {unit}" if unit else ""
        raise InvalidInputError(f"{name} must be > 0, got {number:g}{unit_text}")
    return number


def joint_vector(name: str, value: ArrayLike, ndof: int, *, unit: str = "") -> FloatArray:
    """Return ``value`` broadcast to shape ``(ndof,)``; a scalar applies to every joint."""
    array = finite_array(name, value, unit=unit)
    if array.ndim == 0:
        return np.full(ndof, float(array))
    if array.shape != (ndof,):
        raise InvalidInputError(
            f"{name} must be a number or {ndof} numbers (one per joint), got shape {array.shape}"
        )
    return array


def joint_parameter(
    name: str, value: ArrayLike, ndof: int, unit: str, *, zero_ok: bool
) -> FloatArray:
    """One number or one per joint, broadcast to ``(ndof,)``: each ``>= 0`` or ``> 0``."""
    array = finite_array(name, value, unit=unit)
    if array.ndim == 0:
        array = np.full(ndof, float(array))
    if array.shape != (ndof,):
        raise InvalidInputError(
            f"{name} must be one number or one per joint ({ndof}), got shape {array.shape}"
        )
    if np.any(array < 0.0) or (not zero_ok and np.any(array == 0.0)):
        rule = ">= 0" if zero_ok else "> 0"
        raise InvalidInputError(f"{name} must be {rule} {unit}, got {array.tolist()}")
    return array


def positive_joint_vector(name: str, value: ArrayLike, ndof: int, *, unit: str = "") -> FloatArray:
    """Return ``value`` broadcast to ``(ndof,)``, every entry finite and > 0."""
    array = joint_vector(name, value, ndof, unit=unit)
    bad = np.flatnonzero(array <= 0.0)
    if bad.size:
        unit_text = f" {unit}" if unit else ""
        raise InvalidInputError(
            f"{name} must be > 0 for every joint, got {array[bad[0]]:g}{unit_text}"
            f" for joint {bad[0] + 1}"
        )
    return array


def count_dof(**values: ArrayLike | None) -> int:
    """Return the number of joints implied by the given per-joint arguments.

    Scalars fit any count; 1-D arrays must agree on their length.
    """
    ndof: int | None = None
    first = ""
    for name, value in values.items():
        if value is None:
            continue
        shape = np.shape(value)
        if len(shape) > 1:
            raise InvalidInputError(
                f"{name} must be a number or a 1-D sequence (one per joint), got shape {shape}"
            )
        if len(shape) == 1:
            if shape[0] == 0:
                raise InvalidInputError(f"{name} must not be empty")
            if ndof is None:
                ndof, first = shape[0], name
            elif shape[0] != ndof:
                raise InvalidInputError(
                    f"{name} has {shape[0]} joints but {first} has {ndof}; they must match"
                )
    return 1 if ndof is None else ndof


def increasing_times(name: str, value: ArrayLike, *, minimum_count: int = 2) -> FloatArray:
    """Return a strictly increasing 1-D array of times in seconds."""
    times = finite_array(name, value, unit="s")
    if times.ndim != 1:
        raise InvalidInputError(f"{name} must be a 1-D sequence of times, got shape {times.shape}")
    if times.size < minimum_count:
        raise InvalidInputError(f"{name} needs at least {minimum_count} times, got {times.size}")
    steps = np.diff(times)
    bad = np.flatnonzero(steps <= 0.0)
    if bad.size:
        i = bad[0]
        rule = "repeated" if steps[i] == 0.0 else "decreasing"
        raise InvalidInputError(
            f"{name} must be strictly increasing, but {name}[{i}]={times[i]:g} s and "
            f"{name}[{i + 1}]={times[i + 1]:g} s are {rule}"
        )
    return times
