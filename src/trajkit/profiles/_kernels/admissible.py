"""One compiled pass over a problem's numbers, answering whether the planners accept it.

The Python validators produce the helpful error messages; this pass only answers
yes or no, so that a well-formed problem (the common case) is accepted in well
under a microsecond. Anything it refuses goes through the validators, which then
name the argument and the rule.
"""

import math

from numba import njit, prange

# Rows of the problem matrix.
Q0, QF, V0, VF, A0, AF, V_MIN, V_MAX, A_MIN, A_MAX, J_MAX = range(11)
ROWS = 11


@njit(cache=True, error_model="numpy")
def admissible(m):
    """True if the (11, ndof) problem matrix passes every check of the validators."""
    ndof = m.shape[1]
    for d in range(ndof):
        for r in range(J_MAX):
            if not math.isfinite(m[r, d]):
                return False
        j = m[J_MAX, d]
        if not (j > 0.0):  # NaN too; inf is allowed (acceleration-limited)
            return False
        if not (m[V_MIN, d] < 0.0 < m[V_MAX, d] and m[A_MIN, d] < 0.0 < m[A_MAX, d]):
            return False
        if not math.isfinite(m[QF, d] - m[Q0, d]):
            return False
        # A lower bound on the duration (s): beyond float64, no plan can hold it.
        speed = min(m[V_MAX, d], -m[V_MIN, d])
        push = min(m[A_MAX, d], -m[A_MIN, d])
        scale = abs(m[QF, d] - m[Q0, d]) / speed + (speed + abs(m[V0, d]) + abs(m[VF, d])) / push
        if not math.isfinite(scale):
            return False
        vf = m[VF, d]
        af = m[AF, d]
        if not (m[V_MIN, d] <= vf <= m[V_MAX, d] and m[A_MIN, d] <= af <= m[A_MAX, d]):
            return False
        if math.isinf(j):
            if m[A0, d] != 0.0 or af != 0.0:
                return False
        else:
            before = vf - af * abs(af) / (2.0 * j)
            if not (m[V_MIN, d] * (1 + 1e-12) <= before <= m[V_MAX, d] * (1 + 1e-12)):
                return False
    return True


@njit(cache=True, error_model="numpy", parallel=True)
def assemble_batch(rows, m, ok):
    """Fill the (B, 11, ndof) batch ``m`` from its rows and check every problem.

    ``rows`` holds the eleven rows, each a (B, ndof) float64 view (broadcast:
    strides may be zero); ``ok[i]`` says whether problem ``i`` is :func:`admissible`.
    One parallel pass instead of eleven strided copies and a serial check.
    """
    ndof = m.shape[2]
    for i in prange(m.shape[0]):
        for r in range(ROWS):
            row = rows[r]
            for d in range(ndof):
                m[i, r, d] = row[i, d]
        ok[i] = admissible(m[i])
