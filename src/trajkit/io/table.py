"""CSV tables of numbers, written atomically and read back bit for bit."""

from __future__ import annotations

import io
import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from trajkit._validation import FloatArray
from trajkit.io.atomic import atomic_write

__all__ = ["named_columns", "read_csv", "write_csv"]


def write_csv(path: str | os.PathLike[str], header: Sequence[str], table: FloatArray) -> Path:
    """Write ``header`` and one row per line of ``table`` (n, len(header)).

    Numbers carry 17 significant digits, so reading them gives back the same floats.
    """
    rows = np.asarray(table, dtype=float)

    def write(handle: io.BufferedWriter) -> None:
        text = io.TextIOWrapper(handle, encoding="utf-8", newline="")
        text.write(",".join(header) + "\n")
        np.savetxt(text, rows, delimiter=",", fmt="%.17g")
        text.flush()
        text.detach()

    return atomic_write(path, write)


def read_csv(path: str | os.PathLike[str]) -> tuple[list[str], FloatArray]:
    """The header and the rows of numbers of a CSV table written by :func:`write_csv`.

    Raises
    ------
    InvalidInputError
        An unreadable or empty file, or a row that is not ``len(header)`` finite
        numbers; the message names the line.
    """
    import csv

    from trajkit.errors import InvalidInputError

    source = Path(path)
    try:
        lines = source.read_text(encoding="utf-8").splitlines()
    except (OSError, UnicodeDecodeError) as exc:
        raise InvalidInputError(f"cannot read {source}: {exc}") from None
    if not lines or not lines[0].strip():
        raise InvalidInputError(f"{source}: empty file, expected a header line")
    header = next(csv.reader(lines[:1]))
    rows = []
    for number, line in enumerate(lines[1:], start=2):
        cells = line.split(",")
        try:
            values = [float(cell) for cell in cells]
        except ValueError:
            values = []
        if len(values) != len(header) or not np.all(np.isfinite(values)):
            raise InvalidInputError(
                f"{source}, line {number}: expected {len(header)} finite numbers, got {line!r:.80}"
            )
        rows.append(values)
    if not rows:
        raise InvalidInputError(f"{source}: no rows after the header")
    return header, np.array(rows)


def named_columns(source: os.PathLike[str] | str, header: Sequence[str], table: FloatArray,
                  names: Sequence[str]) -> dict[str, FloatArray]:  # fmt: skip
    """The columns ``names`` of a table read by :func:`read_csv`, by their header cells.

    Raises
    ------
    InvalidInputError
        A column missing: the message names it and the file.
    """
    from trajkit.errors import InvalidInputError

    where = {cell: k for k, cell in enumerate(header)}
    missing = [name for name in names if name not in where]
    if missing:
        shown = ", ".join(header[:4])
        raise InvalidInputError(f"{source}: no column {missing[0]!r} (its header has "
                                f"{len(header)} columns: {shown}, ...)")  # fmt: skip
    return {name: table[:, where[name]] for name in names}
