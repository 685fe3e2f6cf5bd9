"""Sampled trajectories and their files (CSV, JSON, NPZ), written atomically."""

from __future__ import annotations

import csv
import io
import json
import os
import re
import zipfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from trajkit._validation import FloatArray, finite_array
from trajkit.errors import InvalidInputError
from trajkit.io.atomic import atomic_write
from trajkit.io.table import write_csv

__all__ = ["DEFAULT_STEP", "Samples"]

#: The sampling step (s) of data files when the user names neither a step nor a
#: controller period: the command line, scenario files and sweeps all use it.
DEFAULT_STEP = 0.01

_FIELDS = ("q", "qd", "qdd", "qddd")
_SUFFIX = ("", "_vel", "_acc", "_jerk")  # CSV column suffix of each derivative order
_PER_SECOND = ("", "/s", "/s^2", "/s^3")
_FORMAT = "trajkit.samples"
_VERSION = 1
_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_.-]*$")
_HEADER_CELL = re.compile(r"^(?P<label>\S+) \[(?P<unit>[^\]]+)\]$")


@dataclass(frozen=True, eq=False)
class Samples:
    """A trajectory sampled at times ``t``.

    Attributes
    ----------
    t : ndarray, shape (n,)
        Sample times (s), strictly increasing.
    q, qd, qdd, qddd : ndarray, shape (n, ndof)
        Position (``unit``), velocity (``unit``/s), acceleration (``unit``/s^2)
        and jerk (``unit``/s^3).
    unit : str
        Position unit, e.g. "rad" or "m"; written into file headers.
    names : tuple of str
        One label per joint; defaults to ``q1, q2, ...``.
    metadata : dict
        The plan that was sampled (``Trajectory.info``: phase times, limits, the
        limiting joint...) as plain JSON values; kept by JSON and NPZ files.
    """

    t: FloatArray
    q: FloatArray
    qd: FloatArray
    qdd: FloatArray
    qddd: FloatArray
    unit: str = "rad"
    names: tuple[str, ...] = field(default=())
    metadata: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        t = np.array(finite_array("t", self.t, unit="s"))  # own copy, made read-only
        if t.ndim != 1 or t.size == 0:
            raise InvalidInputError(f"t must be a non-empty 1-D array, got shape {t.shape}")
        if np.any(np.diff(t) <= 0):
            raise InvalidInputError("t must be strictly increasing")
        object.__setattr__(self, "t", t)
        ndof = None
        for name in _FIELDS:
            array = np.array(finite_array(name, getattr(self, name)))
            if array.ndim == 1:
                array = array[:, np.newaxis]
            if array.ndim != 2 or array.shape[0] != t.size:
                raise InvalidInputError(
                    f"{name} must have shape ({t.size}, ndof), got shape {array.shape}"
                )
            if ndof is not None and array.shape[1] != ndof:
                raise InvalidInputError(f"{name} has {array.shape[1]} joints but q has {ndof}")
            ndof = array.shape[1]
            array.setflags(write=False)
            object.__setattr__(self, name, array)
        t.setflags(write=False)
        if ndof == 0:
            raise InvalidInputError("samples need at least one joint, got q of shape (n, 0)")
        if (
            not isinstance(self.unit, str)
            or not self.unit
            or not self.unit.isprintable()
            or any(c in self.unit for c in "[],")
        ):
            raise InvalidInputError(
                f"unit must be a short text like 'rad' or 'm', got {self.unit!r}"
            )
        names = tuple(self.names) or tuple(f"q{j + 1}" for j in range(ndof or 0))
        if len(names) != ndof:
            raise InvalidInputError(f"names gives {len(names)} labels for {ndof} joints")
        for label in names:
            if not isinstance(label, str) or not _NAME.fullmatch(label):
                raise InvalidInputError(
                    f"joint name {label!r} must start with a letter and hold only letters, "
                    "digits, '_', '.' or '-'"
                )
        object.__setattr__(self, "names", names)

    @property
    def ndof(self) -> int:
        """Number of joints."""
        return int(self.q.shape[1])

    def __len__(self) -> int:
        return int(self.t.size)

    def _columns(self) -> tuple[list[str], FloatArray]:
        header = ["t [s]"]
        blocks = [self.t[:, np.newaxis]]
        for name, suffix, per_second in zip(_FIELDS, _SUFFIX, _PER_SECOND, strict=True):
            header += [f"{label}{suffix} [{self.unit}{per_second}]" for label in self.names]
            blocks.append(getattr(self, name))
        return header, np.hstack(blocks)

    # ------------------------------------------------------------------ CSV
    def to_csv(self, path: str | os.PathLike[str]) -> Path:
        """Write a CSV file: a header with units, then one row per sample.

        Numbers are written with 17 significant digits, so :meth:`from_csv` gives
        back the same floats bit for bit.
        """
        header, table = self._columns()
        return write_csv(path, header, table)

    @classmethod
    def from_csv(cls, path: str | os.PathLike[str]) -> Samples:
        """Read a CSV file written by :meth:`to_csv`.

        Raises
        ------
        InvalidInputError
            The header or a row does not have the expected form; the message names
            the line.
        """
        source = Path(path)
        try:
            lines = source.read_text(encoding="utf-8").splitlines()
        except (OSError, UnicodeDecodeError) as exc:
            raise InvalidInputError(f"cannot read samples file {source}: {exc}") from exc
        rows = list(csv.reader(lines[:1]))
        if not rows:
            raise InvalidInputError(f"{source}: empty file, expected a header line")
        header = rows[0]
        if (len(header) - 1) % 4 != 0 or len(header) < 5 or header[0] != "t [s]":
            raise InvalidInputError(
                f"{source}, line 1: expected 't [s]' then 4 columns per joint "
                f"(position, _vel, _acc, _jerk), got {len(header)} columns"
            )
        ndof = (len(header) - 1) // 4
        names, unit = [], None
        for column, cell in enumerate(header[1:]):
            order, joint = divmod(column, ndof)
            match = _HEADER_CELL.match(cell)
            label = match["label"] if match else ""
            expected_suffix = _SUFFIX[order]
            if (
                not match
                or not label.endswith(expected_suffix)
                or (order > 0 and label[: len(label) - len(expected_suffix)] != names[joint])
            ):
                raise InvalidInputError(
                    f"{source}, line 1: column {column + 2} header {cell!r} is not "
                    f"'<joint>{expected_suffix} [unit{_PER_SECOND[order]}]'"
                )
            if order == 0:
                names.append(label)
                unit = unit or match["unit"]
            if match["unit"] != f"{unit}{_PER_SECOND[order]}":
                raise InvalidInputError(
                    f"{source}, line 1: column {column + 2} has unit [{match['unit']}], "
                    f"expected [{unit}{_PER_SECOND[order]}]"
                )
        values = _parse_rows(source, lines[1:], len(header))
        if values.shape[0] == 0:
            raise InvalidInputError(f"{source}: no samples after the header")
        try:
            return cls._from_table(values, ndof, unit or "rad", tuple(names))
        except InvalidInputError as exc:
            raise InvalidInputError(f"{source}: {exc}") from exc

    @classmethod
    def _from_table(
        cls, table: FloatArray, ndof: int, unit: str, names: tuple[str, ...]
    ) -> Samples:
        blocks = [table[:, 1 + k * ndof : 1 + (k + 1) * ndof] for k in range(4)]
        return cls(table[:, 0], *blocks, unit=unit, names=names)

    # ----------------------------------------------------------------- JSON
    def to_json(self, path: str | os.PathLike[str]) -> Path:
        """Write a JSON document (floats round-trip exactly through :meth:`from_json`)."""
        document = {
            "format": _FORMAT,
            "version": _VERSION,
            "unit": self.unit,
            "names": list(self.names),
            "metadata": plain(self.metadata),
            "t": self.t.tolist(),
            **{name: getattr(self, name).tolist() for name in _FIELDS},
        }
        data = json.dumps(document, allow_nan=False).encode("utf-8")
        return atomic_write(path, lambda handle: handle.write(data))

    @classmethod
    def from_json(cls, path: str | os.PathLike[str]) -> Samples:
        """Read a JSON document written by :meth:`to_json`."""
        source = Path(path)
        try:
            document = json.loads(source.read_text(encoding="utf-8"))
        except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
            raise InvalidInputError(f"cannot read samples file {source}: {exc}") from exc
        if not isinstance(document, dict) or document.get("format") != _FORMAT:
            raise InvalidInputError(f"{source}: not a trajkit samples document (format key)")
        missing = [key for key in ("t", *_FIELDS, "unit", "names") if key not in document]
        if missing:
            raise InvalidInputError(f"{source}: missing key(s) {', '.join(missing)}")
        if not isinstance(document["names"], list):
            raise InvalidInputError(f"{source}: 'names' must be a list of joint names")
        try:
            return cls(
                document["t"],
                *(document[name] for name in _FIELDS),
                unit=document["unit"],
                names=tuple(document["names"]),
                metadata=dict(document.get("metadata", {})),
            )
        except InvalidInputError as exc:
            raise InvalidInputError(f"{source}: {exc}") from exc

    # ------------------------------------------------------------------ NPZ
    def to_npz(self, path: str | os.PathLike[str]) -> Path:
        """Write a compressed NumPy archive (exact)."""
        arrays = {name: getattr(self, name) for name in ("t", *_FIELDS)}

        def write(handle: io.BufferedWriter) -> None:
            np.savez_compressed(
                handle, **arrays, unit=np.array(self.unit), names=np.array(self.names),
                metadata=np.array(json.dumps(plain(self.metadata))),
            )  # fmt: skip

        return atomic_write(path, write)

    @classmethod
    def from_npz(cls, path: str | os.PathLike[str]) -> Samples:
        """Read an archive written by :meth:`to_npz`."""
        source = Path(path)
        try:
            with np.load(source, allow_pickle=False) as archive:
                content = {key: archive[key] for key in archive.files}
        except (OSError, ValueError, zipfile.BadZipFile, EOFError) as exc:
            raise InvalidInputError(f"cannot read samples file {source}: {exc}") from exc
        missing = [k for k in ("t", *_FIELDS, "unit", "names") if k not in content]
        if missing:
            raise InvalidInputError(f"{source}: missing array(s) {', '.join(missing)}")
        if content["names"].ndim != 1:
            raise InvalidInputError(f"{source}: 'names' must be a 1-D array of joint names")
        try:
            return cls(
                content["t"],
                *(content[name] for name in _FIELDS),
                unit=str(content["unit"]),
                names=tuple(str(n) for n in content["names"]),
                metadata=json.loads(str(content["metadata"])) if "metadata" in content else {},
            )
        except InvalidInputError as exc:
            raise InvalidInputError(f"{source}: {exc}") from exc


def plain(value: Any) -> Any:
    """``value`` as plain JSON: arrays and tuples as lists, non-finite floats as strings."""
    if isinstance(value, dict):
        return {str(key): plain(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(item) for item in value]
    if isinstance(value, np.ndarray):
        return plain(value.tolist())
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        return float(value) if np.isfinite(value) else str(float(value))
    if value is None or isinstance(value, str):
        return value
    return str(value)


def _parse_rows(source: Path, lines: list[str], width: int) -> FloatArray:
    """Parse the data lines in one vectorized call; on failure, name the bad line."""
    body = [line for line in lines if line.strip()]
    if not body:
        return np.empty((0, width))
    try:
        values = np.loadtxt(body, delimiter=",", ndmin=2, dtype=np.float64)
    except ValueError:
        values = None
    if values is not None and values.shape[1] == width:
        return values
    # Slow path only to write a helpful message.
    for number, line in enumerate(lines, start=2):
        if not line.strip():
            continue
        cells = line.split(",")
        if len(cells) != width:
            raise InvalidInputError(
                f"{source}, line {number}: {len(cells)} values, expected {width}"
            )
        for cell in cells:
            try:
                float(cell)
            except ValueError:
                raise InvalidInputError(
                    f"{source}, line {number}: {cell.strip()!r} is not a number"
                ) from None
    raise InvalidInputError(f"{source}: rows do not form a table of {width} columns")
