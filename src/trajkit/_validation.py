"""Argument checks shared by every public function.

Every user-facing number or array goes through :func:`as_float_array` (directly
or via :func:`finite_array` and the helpers built on it), the one place that
turns user input into float64. It refuses, naming the argument:

* ``None`` (a required argument left out, or a placeholder passed on);
* strings and bytes, even ``"1.5"``: numpy would parse them, a user passing
  text has a bug elsewhere;
* booleans (``True``, numpy bool arrays): numpy reads them as 1.0 and 0.0;
* complex numbers, even with a zero imaginary part: the conversion would drop
  the imaginary part silently;
* ragged sequences (``[[1], [1, 2]]``), object arrays holding non-numbers, and
  non-numeric dtypes (dates, records);
* integers beyond the float64 range.

Subnormal values (``0 < |x| < 2.2e-308``) are kept exactly as given, neither
flushed nor refused: they are valid float64 numbers, and changing them would
break exact round trips of stored samples and could turn strictly increasing
times (``[0, 5e-324]``) into repeated ones. Where one makes a result overflow
(a 1e-320 s duration), the planners refuse the result naming the arguments
(:func:`finite_result`); where it is a boundary rate, the result is the
rest-to-rest one up to that rate, as it should be.

Each helper names the argument in its error message, so a user learns which
value was wrong and what rule it broke.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from trajkit.errors import InvalidInputError

FloatArray = NDArray[np.float64]

_NUMERIC_KINDS = "iuf"  # signed and unsigned integers, floats


def _describe(value: Any) -> str:
    text = np.array2string(np.asarray(value), precision=6, threshold=8)
    return text if len(text) < 80 else text[:77] + "..."


def _short_repr(value: Any) -> str:
    text = repr(value)
    return text if len(text) < 80 else text[:77] + "..."


def _kind_problem(value: Any) -> str | None:
    """Why one leaf of a user's input is not a real number, or None when it is."""
    if value is None:
        return "None"
    if isinstance(value, str | bytes):
        return "a string"
    if isinstance(value, bool | np.bool_):
        return "a bool"
    if isinstance(value, np.ndarray | np.generic):
        return _dtype_problem(value.dtype)
    if isinstance(value, numbers.Real):
        return None
    if isinstance(value, numbers.Complex):
        return "complex"
    if isinstance(value, Mapping | set | frozenset):
        return f"a {type(value).__name__}"
    return None  # anything else: numpy decides below (e.g. objects with __array__)


def _dtype_problem(dtype: np.dtype[Any]) -> str | None:
    if dtype.kind in _NUMERIC_KINDS or dtype.kind == "O":
        return None
    return {
        "b": "a bool array",
        "c": "complex",
        "U": "a string",
        "S": "a string",
    }.get(dtype.kind, f"of non-numeric dtype {dtype}")


def _refuse(name: str, value: Any, problem: str, where: str = "") -> InvalidInputError:
    if not where:
        if problem == "None":
            return InvalidInputError(f"{name} is required: give a number or numbers, got None")
        return InvalidInputError(f"{name} must be numeric, got {_short_repr(value)} ({problem})")
    shown = "None" if problem == "None" else f"{_short_repr(value)} ({problem})"
    return InvalidInputError(f"{name} must be numeric: {name}{where} is {shown}")


def _check_leaves(name: str, value: Any, index: tuple[int, ...] = ()) -> None:
    """Refuse the first leaf of nested lists/tuples that is not a real number.

    numpy would read ``[1, True]`` as ``[1, 1]`` and ``[1, None]`` as an object
    array, so the leaves are checked one by one.
    """
    if isinstance(value, list | tuple):
        for i, item in enumerate(value):
            _check_leaves(name, item, (*index, i))
        return
    if isinstance(value, np.ndarray) and value.dtype.kind == "O":
        for i, item in enumerate(value.flat):
            problem = _kind_problem(item)
            if problem is not None:
                where = "".join(f"[{k}]" for k in (*index, *np.unravel_index(i, value.shape)))
                raise _refuse(name, item, problem, where)
        return
    problem = _kind_problem(value)
    if problem is not None:
        raise _refuse(name, value, problem, "".join(f"[{k}]" for k in index))


def as_float_array(name: str, value: Any) -> FloatArray:
    """Return ``value`` as a float64 array; NaN and inf pass (see :func:`finite_array`).

    Parameters
    ----------
    name : str
        The argument's user-facing name, quoted in every message.
    value : array_like
        A real number or a rectangular (nested) sequence or array of real numbers.

    Returns
    -------
    ndarray of float64
        May share memory with ``value``: callers that keep it copy it.

    Raises
    ------
    InvalidInputError
        ``value`` is None, text, bool, complex, ragged, of a non-numeric dtype, or
        an integer beyond the float64 range (see the module docstring).
    """
    if isinstance(value, np.ndarray) and value.dtype.kind in "fiu":
        array = np.asarray(value, dtype=np.float64)  # the common case, kept fast
    else:
        _check_leaves(name, value)
        try:
            with np.errstate(over="ignore"):
                array = np.asarray(value, dtype=np.float64)
        except OverflowError as exc:
            raise InvalidInputError(
                f"{name} must be within the float64 range (|x| <= 1.8e308), "
                f"got {_short_repr(value)}"
            ) from exc
        except ValueError as exc:
            if isinstance(value, list | tuple):
                raise InvalidInputError(
                    f"{name} must be numeric: a rectangular array (every row the same "
                    f"length), got the ragged sequence {_short_repr(value)}"
                ) from exc
            raise InvalidInputError(f"{name} must be numeric, got {_short_repr(value)}") from exc
        except TypeError as exc:
            raise InvalidInputError(f"{name} must be numeric, got {_short_repr(value)}") from exc
    return array


def finite_array(name: str, value: ArrayLike, *, unit: str = "") -> FloatArray:
    """Return ``value`` as a float64 array, refusing NaN, inf and non-numbers.

    Conversion rules (what is refused) are those of :func:`as_float_array`. The
    result may share memory with ``value``: callers that keep it copy it.
    """
    array = as_float_array(name, value)
    if not np.isfinite(array).all():
        unit_text = f" {unit}" if unit else ""
        raise InvalidInputError(f"{name} must be finite, got {_describe(array)}{unit_text}")
    return array


def finite_scalar(name: str, value: Any, *, unit: str = "") -> float:
    """Return ``value`` as a finite float."""
    if type(value) is float and math.isfinite(value):  # the common case, kept fast
        return value
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
        shape = as_float_array(name, value).shape
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


def choice(name: str, value: object, options: tuple[str | None, ...]) -> Any:
    """Return ``value`` when it is one of ``options`` (strings, or None).

    ``value in options`` would compare an array elementwise (``sync=np.array([])``
    ended in numpy's "truth value is ambiguous"), so the type is checked first.
    """
    if (value is None and None in options) or (isinstance(value, str) and value in options):
        return value
    listed = ", ".join(repr(option) for option in options[:-1]) + f" or {options[-1]!r}"
    raise InvalidInputError(f"{name} must be {listed}, got {_short_repr(value)}")


def flag(name: str, value: object) -> bool:
    """Return ``value`` when it is ``True`` or ``False`` (a numpy bool too).

    ``if value:`` would read ``"no"`` as true and end an empty array in numpy's
    "truth value is ambiguous".
    """
    if isinstance(value, bool | np.bool_):
        return bool(value)
    raise InvalidInputError(f"{name} must be True or False, got {_short_repr(value)}")


def finite_result(planner: str, values: ArrayLike, arguments: Mapping[str, Any]) -> None:
    """Refuse a computed result that overflowed float64, naming the user's arguments.

    Inputs can each be finite and still combine into a result past float64
    (``qf=1e308`` with ``duration=1e-300``); the error then names the arguments
    the user gave, not the internal array that overflowed.

    Parameters
    ----------
    planner : str
        The public function's name.
    values : array_like
        The computed numbers (coefficients, times...) to check.
    arguments : mapping
        The user's arguments by their public names (None entries are left out).

    Raises
    ------
    InvalidInputError
        Some entry of ``values`` is inf or NaN.
    """
    with np.errstate(all="ignore"):
        ok = bool(np.all(np.isfinite(values)))
    if ok:
        return
    given = ", ".join(
        f"{name}={_compact(value)}" for name, value in arguments.items() if value is not None
    )
    raise InvalidInputError(
        f"{planner}: the result overflows float64 (a coefficient or time beyond 1.8e308) "
        f"for {given}; use smaller values or longer times"
    )


def _compact(value: Any) -> str:
    try:
        array = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError, OverflowError):
        return _short_repr(value)
    if array.ndim == 0:
        return f"{float(array):.6g}"
    return " ".join(_describe(array).split())  # one line, as every message is
