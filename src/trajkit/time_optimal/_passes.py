"""The reachability passes, compiled: scalar loops over stages and their lines.

Importing this module imports numba (slow): :mod:`.reachability` imports it inside
its functions, so ``import trajkit`` stays fast.
"""

import numpy as np
from numba import njit


@njit(cache=True)
def recurrence(a, b, high, y0):  # pragma: no cover - compiled; tested through reachability
    """``y_{k+1} = clip(min_j (a_kj y_k + b_kj), 0, high_k)``; a NaN line never binds."""
    n, m = a.shape
    out = np.empty(n)
    y = y0
    for k in range(n):
        best = high[k]
        for j in range(m):
            offset = b[k, j]
            if offset == np.inf:
                continue
            value = a[k, j] * y + offset
            if value < best:
                best = value
        y = best if best > 0.0 else 0.0
        out[k] = y
    return out
