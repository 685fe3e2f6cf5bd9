"""The tolerances trajkit compares with, named once.

Each is relative unless its name says otherwise, and each says what it separates:
rounding from a real difference. The compiled kernels keep their own constants
(``profiles/_kernels``), which this module does not import, so that ``import trajkit``
stays free of numba.
"""

from __future__ import annotations

__all__ = ["BOUNDARY_ATOL", "BOUNDARY_RTOL", "JUMP_RTOL", "LIMIT_RTOL", "ROUNDING_RTOL"]

#: How far past its bound a peak may go and still count as kept (the default ``rtol``
#: of :func:`trajkit.check`): planners place peaks on their bounds to within rounding
#: of their own arithmetic, which is this far below any physical margin.
LIMIT_RTOL = 1e-9

#: Rounding in comparisons of durations, speeds and distances that were computed
#: along different routes (a duration against its minimum, a peak against its limit
#: inside a planner, grid points closer than this share of the span merged).
ROUNDING_RTOL = 1e-12

#: A jump at a breakpoint smaller than this, relative to the size of the terms that
#: make up the values on either side (plus 1), is rounding, not a discontinuity.
JUMP_RTOL = 1e-9

#: How far an exact boundary state given to a trajectory may differ from the
#: polynomial's own value there: relative to the size of that derivative's terms in
#: the whole motion and of the state itself, plus a floor of a nanometre or a
#: nanoradian (:data:`BOUNDARY_ATOL`) for motions that are tiny everywhere. Rounding of
#: the planner's arithmetic, never a different motion (5e-7 is not 1e-9 "up to
#: rounding").
BOUNDARY_RTOL = 1e-6
BOUNDARY_ATOL = 1e-9
