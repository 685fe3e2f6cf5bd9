"""Reading TOML tables strictly: every value checked, every unknown key an error.

A :class:`Table` wraps one table of a scenario file and its key path
(``task.waypoints``). Each accessor takes a key, checks the value's type and
shape, and marks the key as read; :meth:`Table.done` then refuses whatever was
not read, naming it. A key ending in ``_deg`` gives the same quantity in degrees
(``qf_deg`` for ``qf``), converted to radians on reading. Every problem is a
:class:`ScenarioError` whose message starts with the key path.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from trajkit._validation import FloatArray
from trajkit.errors import InvalidInputError

__all__ = ["ScenarioError", "Table"]

_MISSING = object()


class ScenarioError(InvalidInputError):
    """A scenario file breaks a rule; the message names the key path and the rule."""


def _kind(value: object) -> str:
    names = {bool: "a boolean", int: "a number", float: "a number", str: "a string",
             list: "a list", dict: "a table"}  # fmt: skip
    return names.get(type(value), type(value).__name__)


def _is_number(value: object) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


class Table:
    """One TOML table being read; see the module docstring."""

    def __init__(self, data: Mapping[str, Any], path: str) -> None:
        if not isinstance(data, Mapping):
            raise ScenarioError(f"{path}: expected a table, got {_kind(data)}")
        self.data, self.path = data, path
        self._read: set[str] = set()

    def where(self, key: str) -> str:
        """The key path of ``key`` in this table."""
        return f"{self.path}.{key}" if self.path else key

    def has(self, key: str, *, angles: bool = False) -> bool:
        """True when ``key`` (or, for an angle, ``key_deg``) is given."""
        return key in self.data or (angles and f"{key}_deg" in self.data)

    def _take(
        self, key: str, default: Any, *, angles: bool = False, expected: str = ""
    ) -> tuple[Any, str, float]:
        """The value of ``key`` (or of ``key_deg``), its key path, and its scale to radians.

        An absent key's value is ``_MISSING``; without a ``default`` (``_MISSING``) it
        is refused as required, ``expected`` ending the message.
        """
        degrees = f"{key}_deg"
        if angles and key in self.data and degrees in self.data:
            raise ScenarioError(f"{self.where(key)}: give {key} or {degrees}, not both")
        if angles and degrees in self.data:
            self._read.add(degrees)
            return self.data[degrees], self.where(degrees), math.pi / 180.0
        if key in self.data:
            self._read.add(key)
            return self.data[key], self.where(key), 1.0
        if default is _MISSING:
            raise ScenarioError(f"{self.where(key)}: required{expected}")
        return _MISSING, self.where(key), 1.0

    def value(self, key: str) -> Any:
        """The raw value of ``key`` (marked as read); the caller checks it."""
        value, _, _ = self._take(key, _MISSING)
        return value

    def number(self, key: str, default: Any = _MISSING, *, angles: bool = False,
               positive: bool = False) -> Any:  # fmt: skip
        """A finite number (radians for ``key_deg``), or ``default`` when absent."""
        value, where, scale = self._take(
            key, default, angles=angles, expected=", expected a number"
        )
        if value is _MISSING:
            return default
        number = _finite(value, where)
        if positive and number <= 0:
            raise ScenarioError(f"{where}: expected a number > 0, got {value!r}")
        return number * scale

    def numbers(self, key: str, default: Any = _MISSING, *, count: int | None = None,
                angles: bool = False, scalar_ok: bool = False,
                positive: bool = False) -> Any:  # fmt: skip
        """A list of finite numbers (or one number if ``scalar_ok``) as an array."""
        value, where, scale = self._take(
            key, default, angles=angles, expected=", expected a list of numbers"
        )
        if value is _MISSING:
            return default
        return _vector(value, where, scale, count=count, scalar_ok=scalar_ok, positive=positive)

    def matrix(self, key: str, *, columns: int | None = None, angles: bool = False,
               minimum_rows: int = 1) -> FloatArray:  # fmt: skip
        """A list of equally long lists of numbers, as a 2-D array."""
        value, where, scale = self._take(
            key, _MISSING, angles=angles, expected=", expected a list of lists of numbers"
        )
        if not isinstance(value, list) or len(value) < minimum_rows:
            raise ScenarioError(f"{where}: expected a list of at least {minimum_rows} lists of "
                                f"numbers, got {_describe(value)}")  # fmt: skip
        width = columns
        rows = []
        for index, row in enumerate(value):
            if width is None and isinstance(row, list):
                width = len(row)
            rows.append(_vector(row, f"{where}[{index}]", scale, count=width))
        return np.array(rows)

    def string(self, key: str, default: Any = _MISSING, *,
               choices: Sequence[str] | None = None) -> Any:  # fmt: skip
        """A string, one of ``choices`` if given."""
        value, where, _ = self._take(key, default, expected=", expected a string")
        if value is _MISSING:
            return default
        if not isinstance(value, str):
            raise ScenarioError(f"{where}: expected a string, got {_describe(value)}")
        if choices is not None and value not in choices:
            raise ScenarioError(
                f"{where}: expected one of {', '.join(repr(c) for c in choices)}, got {value!r}"
            )
        return value

    def boolean(self, key: str, default: bool) -> bool:
        """``true`` or ``false``."""
        value, where, _ = self._take(key, default)
        if value is _MISSING:
            return default
        if not isinstance(value, bool):
            raise ScenarioError(f"{where}: expected true or false, got {_describe(value)}")
        return value

    def table(self, key: str, *, required: bool = False) -> Table | None:
        """A sub-table, or None when absent and not required."""
        value, where, _ = self._take(
            key, _MISSING if required else None, expected=" table is missing"
        )
        if value is _MISSING:
            return None
        if not isinstance(value, Mapping):
            raise ScenarioError(f"{where}: expected a table, got {_describe(value)}")
        return Table(value, where)

    def tables(self, key: str) -> list[Table]:
        """An array of tables (``[[key]]``)."""
        value, where, _ = self._take(key, _MISSING, expected=", expected an array of tables")
        if not isinstance(value, list) or not value:
            raise ScenarioError(f"{where}: expected a non-empty array of tables, got "
                                f"{_describe(value)}")  # fmt: skip
        return [Table(item, f"{where}[{index}]") for index, item in enumerate(value)]

    def renamed(self, names: Mapping[str, str]) -> Table:
        """A copy of the table that reads keys under their old ``names`` as the new ones.

        Each old name read gives a ``FutureWarning`` naming the new one; both at once
        are refused.
        """
        data = dict(self.data)
        for old, new in names.items():
            for suffix in ("", "_deg"):
                if old + suffix not in data:
                    continue
                if new in data or f"{new}_deg" in data:
                    raise ScenarioError(f"{self.where(old + suffix)}: the old name of {new}; "
                                        "give one of them")  # fmt: skip
                warnings.warn(f"{self.where(old + suffix)} is now named {new + suffix}; the "
                              "old name will stop working in a later release", FutureWarning,
                              stacklevel=3)  # fmt: skip
                data[new + suffix] = data.pop(old + suffix)
        table = Table(data, self.path)
        table._read = set(self._read)
        return table

    def done(self) -> None:
        """Refuse every key that was not read."""
        unknown = sorted(set(self.data) - self._read)
        if unknown:
            raise ScenarioError(
                f"{self.where(unknown[0])}: unknown key"
                + (f" (and {', '.join(unknown[1:])})" if len(unknown) > 1 else "")
            )


def _finite(value: object, where: str) -> float:
    """``value`` as a finite float; TOML integers of any size are refused past float range."""
    if not _is_number(value):
        raise ScenarioError(f"{where}: expected a finite number, got {_short(value)}")
    try:
        number = float(value)  # type: ignore[arg-type]
    except OverflowError:
        number = math.inf
    if not math.isfinite(number):
        raise ScenarioError(f"{where}: expected a finite number, got {_short(value)}")
    return number


def _short(value: object) -> str:
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


def _describe(value: object) -> str:
    if isinstance(value, list):
        return f"a list of {len(value)}"
    return (
        f"{_kind(value)} {value!r}" if _is_number(value) or isinstance(value, str) else _kind(value)
    )


def _vector(value: object, where: str, scale: float, *, count: int | None,
            scalar_ok: bool = False, positive: bool = False) -> Any:  # fmt: skip
    if scalar_ok and _is_number(value):
        items = [value]
    elif isinstance(value, list):
        items = value
    else:
        expected = f"{count} numbers" if count else "a list of numbers"
        raise ScenarioError(f"{where}: expected {expected}, got {_describe(value)}")
    if count is not None and not (scalar_ok and len(items) == 1) and len(items) != count:
        raise ScenarioError(f"{where}: expected {count} numbers, got {len(items)}")
    if not items:
        raise ScenarioError(f"{where}: expected at least one number, got an empty list")
    numbers = [_finite(item, f"{where}[{index}]") for index, item in enumerate(items)]
    for index, item in enumerate(numbers):
        if positive and item <= 0:
            raise ScenarioError(f"{where}[{index}]: expected a number > 0, got {items[index]!r}")
    array = np.array(numbers, dtype=float) * scale
    return float(array[0]) if scalar_ok and _is_number(value) else array
