"""Time synchronization: the smallest duration every joint can take exactly."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from trajkit._validation import FloatArray
from trajkit.errors import InfeasibleError

__all__ = ["common_duration"]

_SCAN = np.geomspace(1e-9, 1e3, 240)  # relative steps past T tried when a joint is blocked
_BISECTIONS = 60


def common_duration(
    T: FloatArray,
    args: tuple[FloatArray, ...],
    exact: Callable[[FloatArray, tuple[FloatArray, ...]], Any],
    candidates: Callable[..., FloatArray] | None = None,
) -> tuple[FloatArray, Any]:
    """Smallest duration >= ``T`` that every joint can take exactly, and its profiles.

    Parameters
    ----------
    T : ndarray
        Lower bound per problem (leading shape), usually the slowest joint's minimum.
    args : tuple of ndarray
        Per-joint problem arrays (joints on the last axis), passed to ``exact``.
    exact : callable
        ``exact(durations[..., None], args)`` returns profiles with a boolean
        ``valid`` of the joints' shape: True where a joint can take that duration.
    candidates : callable, optional
        ``candidates(*args)`` gives durations (..., K) where a joint's set of
        reachable durations may resume after a gap; tried before the scan.

    Notes
    -----
    At rest at both ends every duration above a joint's minimum is reachable. With
    moving boundaries a joint may be unable to take some durations (a blocked
    interval); for the problems where that happens the candidates and a
    logarithmic scan past ``T`` locate the first feasible duration, and bisection
    against the last infeasible one refines it to 1e-13 relative.
    """
    profiles = exact(T[..., np.newaxis], args)
    blocked = ~profiles.valid.all(axis=-1)
    if not blocked.any():
        return T, profiles
    shape = profiles.valid.shape  # leading + joints
    flat_T = np.array(np.broadcast_to(T, shape[:-1]), dtype=float).reshape(-1)
    flat_blocked = blocked.reshape(-1)
    sub = tuple(np.broadcast_to(a, shape).reshape(-1, shape[-1])[flat_blocked] for a in args)
    start = flat_T[flat_blocked]
    trials = [start[:, np.newaxis] * (1.0 + _SCAN)]
    if candidates is not None:
        trials.append(candidates(*sub).reshape(start.size, -1))
    trial = np.concatenate(trials, axis=-1)
    trial = np.sort(np.where(trial >= start[:, np.newaxis], trial, np.inf), axis=-1)

    def feasible(durations: FloatArray) -> FloatArray:
        with np.errstate(all="ignore"):
            found = exact(durations[..., np.newaxis], tuple(a[:, np.newaxis, :] for a in sub))
        return found.valid.all(axis=-1) & np.isfinite(durations)

    works = feasible(trial)
    if not works.any(axis=-1).all():
        raise InfeasibleError(
            "no common duration lets every joint meet its boundary velocities exactly; "
            "try sync=None or different boundary velocities"
        )
    first = np.argmax(works, axis=-1)
    rows = np.arange(first.size)
    high = trial[rows, first]
    low = np.where(first > 0, trial[rows, np.maximum(first - 1, 0)], start)
    for _ in range(_BISECTIONS):
        middle = 0.5 * (low + high)
        ok = feasible(middle[:, np.newaxis])[:, 0]
        high = np.where(ok, middle, high)
        low = np.where(ok, low, middle)
        if np.all(high - low <= 1e-13 * high):
            break
    flat_T[flat_blocked] = high
    T = flat_T.reshape(shape[:-1])
    return T, exact(T[..., np.newaxis], args)
