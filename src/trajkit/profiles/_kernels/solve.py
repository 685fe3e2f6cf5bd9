"""Entry points: one problem to its pieces, a batch of problems to phase tables.

Each runs the whole pipeline in one compiled call (the cost of a call from Python
is paid once): plan every joint (:mod:`.synchronize`), write each joint's phase
table (:mod:`.tables`), and for one problem build the piecewise cubic.
"""

import numpy as np
from numba import njit, prange

from trajkit.profiles._kernels import synchronize, tables
from trajkit.profiles._kernels.admissible import J_MAX
from trajkit.profiles._kernels.layout import SIZE


@njit(cache=True, error_model="numpy")
def one(
    m,
    control,
    sync,
    enabled,
    min_duration,
    dt,
    records,
    own,
    out,
    t,
    u,
    breakpoints,
    coefficients,
    end,
):
    """Plan one problem and build its pieces; returns ``(status, number of pieces)``.

    Arguments as :func:`synchronize.plan`, plus the phase tables ``t``, ``u``
    (ndof, 9) and the piece arrays of :func:`tables.pieces` to fill.
    """
    status = synchronize.plan(m, control, sync, enabled, min_duration, dt, records, own, out)
    if status != synchronize.OK:
        return status, 0
    ndof = m.shape[1]
    second = np.empty(ndof, np.bool_)
    for d in range(ndof):
        second[d] = np.isinf(m[J_MAX, d])
        tables.compact(records[d], second[d], t[d], u[d])
    start = np.empty((3, ndof))
    target = np.empty((3, ndof))
    for d in range(ndof):
        start[0, d] = m[0, d]
        start[1, d] = m[2, d]
        start[2, d] = m[4, d]
        target[0, d] = m[1, d]
        target[1, d] = m[3, d]
        target[2, d] = m[5, d]
    count = tables.pieces(
        start, target, t, u, second, out[synchronize.OUT_DURATION], breakpoints, coefficients, end
    )
    return status, count


@njit(cache=True, error_model="numpy", parallel=True)
def batch(m, control, sync, enabled, min_duration, dt, t, u, own, out, status):
    """Plan ``B`` problems in parallel into phase tables ``t``, ``u`` (B, ndof, 9)."""
    count = m.shape[0]
    ndof = m.shape[2]
    for i in prange(count):
        records = np.empty((ndof, SIZE))
        status[i] = synchronize.plan(
            m[i], control[i], sync[i], enabled[i], min_duration[i], dt, records, own[i], out[i]
        )
        if status[i] == synchronize.OK:
            for d in range(ndof):
                tables.compact(records[d], np.isinf(m[i, J_MAX, d]), t[i, d], u[i, d])
