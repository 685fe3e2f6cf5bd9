"""One mutation helper for both scenario fuzzers (test_scenario.py, test_scenario_fuzz.py).

A scenario (or sweep) file is read into its TOML data; :func:`mutated` changes one
key there (replaces, deletes, or joins it with an unknown sibling); :func:`to_toml`
writes the data back as TOML text, so the mutated file can go through the CLI.
"""

from __future__ import annotations

import copy
import datetime
import json
import math
import re
from collections.abc import Iterator

__all__ = ["mutated", "places", "to_toml"]


def places(data: dict, prefix: tuple = ()) -> Iterator[tuple]:
    """Every key path in ``data``; arrays of tables are entered at their first table."""
    for key, value in data.items():
        yield (*prefix, key)
        if isinstance(value, dict):
            yield from places(value, (*prefix, key))
        elif isinstance(value, list) and value and isinstance(value[0], dict):
            yield from places(value[0], (*prefix, key))


def mutated(base: dict, place: tuple, value: object, extra: bool, *, delete: bool = False) -> dict:
    """A copy of ``base`` with the key at ``place`` replaced by ``value``, removed
    (``delete``, or a ``value`` of None), or joined by an unknown sibling (``extra``)."""
    data = copy.deepcopy(base)
    target = data
    for key in place[:-1]:
        target = target[key]
        if isinstance(target, list):
            target = target[0]
    if delete or value is None:
        target.pop(place[-1], None)
    elif extra:
        target[f"{place[-1]}_x"] = value
    else:
        target[place[-1]] = value
    return data


_BARE = re.compile(r"[A-Za-z0-9_-]+")


def _key(key: str) -> str:
    return key if _BARE.fullmatch(key) else json.dumps(key)


def _value(value: object) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value)  # a TOML basic string: the same escapes
    if isinstance(value, list):
        return "[" + ", ".join(_value(item) for item in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{_key(k)} = {_value(v)}" for k, v in value.items()) + "}"
    if isinstance(value, datetime.date | datetime.time):  # TOML's own date-times
        return value.isoformat()
    raise TypeError(f"no TOML for {type(value).__name__}")


def to_toml(data: dict) -> str:
    """TOML text for ``data``: one ``key = value`` line per root key, tables inline."""
    return "".join(f"{_key(key)} = {_value(value)}\n" for key, value in data.items())
