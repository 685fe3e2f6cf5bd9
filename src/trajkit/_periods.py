"""Rounding times up to whole controller periods, shared by every planner with ``dt``."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from trajkit._validation import FloatArray

#: A time that passes a whole number of periods by less than this fraction of a
#: period is that number: the excess is rounding in the caller's arithmetic
#: (0.3 / 0.1 = 2.9999999999999996).
_ROUNDING = 1e-9


def whole_periods(duration: ArrayLike, period: float) -> FloatArray:
    """How many periods cover ``duration``: ``ceil(duration / period)``, forgiving rounding."""
    return np.ceil(np.asarray(duration, dtype=np.float64) / period - _ROUNDING)
