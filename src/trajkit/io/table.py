"""CSV tables of numbers, written atomically and read back bit for bit."""

from __future__ import annotations

import io
import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from trajkit._validation import FloatArray
from trajkit.io.atomic import atomic_write

__all__ = ["write_csv"]


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
