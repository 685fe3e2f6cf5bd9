"""Inverse kinematics: the solution type and a batched Levenberg–Marquardt solver.

The numerical solver works on any :class:`~trajkit.kinematics.SerialChain` and on
many targets at once: each iteration is one batched Jacobian and one batched
``ndof × ndof`` solve for every target still unsolved. Damping follows
Sugihara (2011): ``λ = E + w`` with ``E`` the weighted squared error, which keeps
steps short far from a solution and lets Newton's method take over close to it.
Joint ranges are respected by projecting every step onto them.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from trajkit._validation import finite_array, positive_scalar
from trajkit.errors import InvalidInputError, UnreachableError
from trajkit.rotations import as_rotation_matrices, rotation_error

if TYPE_CHECKING:
    from trajkit.kinematics.chain import SerialChain

FloatArray = NDArray[np.float64]

__all__ = ["IKSolution", "solve_along_path", "solve_numerical"]

#: Knots solved one after another before the whole path is solved at once.
_CONTINUATION_KNOTS = 16

#: Damping added to Sugihara's error term, relative to the chain's scale squared: it
#: bounds the step at a singularity and vanishes in effect as the error goes to 0.
_DAMPING_FLOOR = 1e-9


@dataclass(frozen=True)
class IKSolution:
    """Result of an inverse-kinematics call.

    Attributes
    ----------
    q : ndarray, shape (ndof,) or (m, ndof)
        Joint positions (rad or m).
    success : bool or ndarray of bool, shape (m,)
        Whether each target was reached within the tolerance.
    position_error : float or ndarray, shape (m,)
        Distance from the tool to the target position (m).
    orientation_error : float or ndarray, shape (m,)
        Angle between tool and target orientations (rad); 0 when position only.
    iterations : int
        Iterations used (the largest over the batch; 0 for closed forms).
    method : str
        ``"analytic"`` or ``"numerical"``.
    """

    q: FloatArray
    success: NDArray[np.bool_] | bool
    position_error: FloatArray | float
    orientation_error: FloatArray | float
    iterations: int = 0
    method: str = "numerical"

    @property
    def residual(self) -> FloatArray | float:
        """Position error (m) plus orientation error (rad), as one number per target."""
        return self.position_error + self.orientation_error


def parse_targets(
    target: ArrayLike, position_only: bool
) -> tuple[FloatArray, FloatArray | None, bool]:
    """Read IK targets as positions ``(m, 3)``, rotations ``(m, 3, 3)`` or None, and single-ness."""
    array = finite_array("target", target)
    if array.shape[-2:] == (4, 4):
        single = array.ndim == 2
        poses = array.reshape(-1, 4, 4)
        if not np.allclose(poses[:, 3], [0.0, 0.0, 0.0, 1.0]):
            raise InvalidInputError("target poses must have the last row 0 0 0 1")
        rotations = as_rotation_matrices("target rotation", poses[:, :3, :3])
        return poses[:, :3, 3].copy(), (None if position_only else rotations), single
    if array.ndim in (1, 2) and array.shape[-1] == 3:
        if not position_only:
            raise InvalidInputError(
                "target is a position: pass position_only=True, or give 4x4 poses"
            )
        return array.reshape(-1, 3).copy(), None, array.ndim == 1
    raise InvalidInputError(
        f"target must be a 4x4 pose, a 3-vector position, or a stack of them, got shape "
        f"{array.shape}"
    )


def _errors(
    chain: SerialChain, q: FloatArray, points: FloatArray, rotations: FloatArray | None
) -> tuple[FloatArray, FloatArray]:
    """Stacked error vectors (m, 3 or 6) and Jacobians (m, 3 or 6, ndof)."""
    tool, jacobian = chain.fk_and_jacobian(q)
    position_error = points - tool[:, :3, 3]
    if rotations is None:
        return position_error, jacobian[:, :3]
    angle_error = rotation_error(rotations, tool[:, :3, :3])
    return np.concatenate([position_error, angle_error], axis=1), jacobian


def solve_numerical(
    chain: SerialChain,
    target: ArrayLike,
    q_seed: ArrayLike | None = None,
    *,
    position_only: bool = False,
    tolerance: float = 1e-10,
    max_iterations: int = 50,
    restarts: int = 30,
    raise_on_failure: bool = True,
) -> IKSolution:
    """Batched damped-least-squares IK; see :meth:`SerialChain.ik` for the parameters."""
    tolerance = positive_scalar("tolerance", tolerance)
    if int(max_iterations) < 1 or int(restarts) < 0:
        raise InvalidInputError(
            f"max_iterations must be >= 1 and restarts >= 0, got {max_iterations}, {restarts}"
        )
    points, rotations, single = parse_targets(target, position_only)
    m, n = points.shape[0], chain.ndof
    lower, upper = chain.lower, chain.upper
    bounded = np.isfinite(lower) & np.isfinite(upper)
    middle = np.where(
        bounded, 0.5 * (np.where(bounded, lower, 0.0) + np.where(bounded, upper, 0.0)), 0.0
    )
    if q_seed is None:
        q = np.broadcast_to(middle, (m, n)).copy()
    else:
        seeds, _ = chain.configurations(q_seed, "q_seed")
        if seeds.shape[0] not in (1, m):
            raise InvalidInputError(f"q_seed gives {seeds.shape[0]} seeds for {m} targets")
        q = np.clip(np.broadcast_to(seeds, (m, n)), lower, upper)
    seed_copy = q.copy()
    scale = max(chain.reach(), 1e-9) if np.isfinite(chain.reach()) else 1.0
    position_tolerance = tolerance * max(scale, 1.0)
    weights = np.ones(3 if rotations is None else 6)
    if rotations is not None:
        weights[3:] = scale**2  # an error of 1 rad counts like one chain length
    rng = np.random.default_rng(0)

    def converged(error: FloatArray) -> NDArray[np.bool_]:
        ok = np.linalg.norm(error[:, :3], axis=1) <= position_tolerance
        if error.shape[1] == 6:
            ok &= np.linalg.norm(error[:, 3:], axis=1) <= tolerance
        return ok

    best_q = q.copy()
    best_cost = np.full(m, np.inf)
    best_error = np.full((m, weights.size), np.inf)  # the error at best_q: no pass at the end
    done = np.zeros(m, dtype=bool)
    used = 0
    for attempt in range(int(restarts) + 1):
        todo = np.flatnonzero(~done)
        if todo.size == 0:
            break
        if attempt:
            span = np.where(bounded, upper - lower, 2 * np.pi)
            low = np.where(bounded, lower, -np.pi)
            q[todo] = low + rng.random((todo.size, n)) * span
        active = todo
        for iteration in range(int(max_iterations)):
            used = max(used, iteration + 1)
            qa = q[active]
            target_points = points[active]
            target_rot = None if rotations is None else rotations[active]
            error, jacobian = _errors(chain, qa, target_points, target_rot)
            cost = 0.5 * np.einsum("mk,k,mk->m", error, weights, error)
            finished = converged(error)
            improved = (cost < best_cost[active]) | finished
            best_cost[active[improved]] = cost[improved]
            best_q[active[improved]] = qa[improved]
            best_error[active[improved]] = error[improved]
            done[active[finished]] = True
            keep = ~finished
            if not keep.any():
                break
            active, qa, error, jacobian, cost = (
                active[keep],
                qa[keep],
                error[keep],
                jacobian[keep],
                cost[keep],
            )
            weighted = jacobian * weights[np.newaxis, :, np.newaxis]
            normal = np.swapaxes(jacobian, 1, 2) @ weighted
            damping = cost + _DAMPING_FLOOR * scale**2
            normal += damping[:, np.newaxis, np.newaxis] * np.eye(n)
            gradient = np.einsum("mkj,mk->mj", weighted, error)
            step = np.linalg.solve(normal, gradient[..., np.newaxis])[..., 0]
            q[active] = np.clip(qa + step, lower, upper)
    q_final = chain.wrap_near(best_q, seed_copy)
    error = best_error
    position_error = np.linalg.norm(error[:, :3], axis=1)
    orientation_error = np.linalg.norm(error[:, 3:], axis=1) if error.shape[1] == 6 else np.zeros(m)
    success = converged(error)
    if raise_on_failure and not success.all():
        worst = int(np.flatnonzero(~success)[0])
        where = "" if single else f" (target {worst}, {int((~success).sum())} of {m} failed)"
        raise UnreachableError(
            f"IK did not reach the target{where}: the closest tool pose found is "
            f"{position_error[worst]:.6g} m and {orientation_error[worst]:.6g} rad away "
            f"after {restarts + 1} attempts; the target is out of reach or outside the "
            "joint ranges",
            index=worst,
        )
    if single:
        return IKSolution(
            q_final[0],
            bool(success[0]),
            float(position_error[0]),
            float(orientation_error[0]),
            used,
        )
    return IKSolution(q_final, success, position_error, orientation_error, used)


def _not_reached(index: int, position_error: float, orientation_error: float) -> UnreachableError:
    return UnreachableError(
        f"target {index} is not reached: the closest tool pose found is "
        f"{position_error:.6g} m and {orientation_error:.6g} rad away",
        index=index,
    )


def solve_along_path(
    chain: SerialChain,
    targets: ArrayLike,
    q_start: ArrayLike | None = None,
    *,
    position_only: bool = False,
    tolerance: float = 1e-10,
    knots: int = _CONTINUATION_KNOTS,
) -> IKSolution:
    """IK for a sequence of nearby targets, staying on one solution branch.

    A coarse set of ``knots`` targets is solved in order, each warm-started from
    the previous one (so the solution follows the branch ``q_start`` picks);
    every target is then solved at once from seeds interpolated between the
    knots, which converge in a few Newton steps. No random restarts are made,
    since a restart could land on another branch.

    Parameters
    ----------
    chain : SerialChain
    targets : array_like, shape (m, 4, 4) or (m, 3)
        Tool poses, or positions with ``position_only``, in path order.
    q_start : array_like, shape (ndof,), optional
        Seed of the first target (default: the middle of the joint ranges).
    position_only : bool
    tolerance : float
        As in :meth:`SerialChain.ik`.
    knots : int
        Targets solved one after another (>= 2).

    Returns
    -------
    IKSolution
        Every target reached.

    Raises
    ------
    UnreachableError
        With ``index`` set to the first target not reached.
    """
    points, _, single = parse_targets(targets, position_only)
    if single:
        raise InvalidInputError("targets must be a sequence of poses or positions, not one")
    m = points.shape[0]
    if int(knots) < 2:
        raise InvalidInputError(f"knots must be >= 2, got {knots}")
    array = np.asarray(targets, dtype=np.float64)
    knot_index = np.unique(np.linspace(0, m - 1, min(m, int(knots))).round().astype(int))
    q_knots = np.empty((knot_index.size, chain.ndof))
    seed = q_start
    for i, k in enumerate(knot_index):
        solution = solve_numerical(
            chain, array[k], seed, position_only=position_only, tolerance=tolerance,
            restarts=0 if i else 30, raise_on_failure=False,
        )  # fmt: skip
        if not solution.success:
            # Name the first target not reached since the last good knot, not the knot.
            previous = knot_index[i - 1] if i else -1
            between = np.arange(previous + 1, k + 1)
            trial = solve_numerical(
                chain, array[between], seed, position_only=position_only,
                tolerance=tolerance, restarts=0, raise_on_failure=False,
            )  # fmt: skip
            failed = int(np.argmax(~np.asarray(trial.success)))
            raise _not_reached(
                int(between[failed]),
                trial.position_error[failed],
                trial.orientation_error[failed],
            )
        q_knots[i] = solution.q
        seed = solution.q
    # Refine level by level, each solved at once from seeds interpolated between the
    # level before: seeds stay close, so each level takes a few Newton steps.
    while True:
        count = knot_index.size * 16
        count = m if count * 4 > m else count  # a last short level costs a whole pass
        finer = np.unique(np.linspace(0, m - 1, count).round().astype(int))
        seeds = np.stack(
            [np.interp(finer, knot_index, q_knots[:, j]) for j in range(chain.ndof)], axis=1
        )
        batch = solve_numerical(
            chain, array[finer], seeds, position_only=position_only, tolerance=tolerance,
            restarts=0, raise_on_failure=False,
        )  # fmt: skip
        if finer.size == m:
            break
        ok = np.asarray(batch.success)
        knot_index, q_knots = finer[ok], np.asarray(batch.q)[ok]
    q = np.array(batch.q)
    success = np.array(batch.success)
    position_error = np.array(batch.position_error)
    orientation_error = np.array(batch.orientation_error)
    for k in np.flatnonzero(~success):  # rare: targets the interpolated seed did not lead home
        previous = q[k - 1] if k > 0 else seeds[k]
        retry = solve_numerical(
            chain, array[k], previous, position_only=position_only, tolerance=tolerance,
            restarts=0, raise_on_failure=False,
        )  # fmt: skip
        if not retry.success:
            raise _not_reached(int(k), retry.position_error, retry.orientation_error)
        q[k], success[k] = retry.q, True
        position_error[k], orientation_error[k] = retry.position_error, retry.orientation_error
    return IKSolution(q, success, position_error, orientation_error, batch.iterations)
