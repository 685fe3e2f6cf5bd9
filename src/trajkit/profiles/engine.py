"""The compiled profile engine seen from Python: validated arrays in, phase tables out.

Every limit-driven one-axis law (jerk-limited, acceleration-limited, the velocity
interface) runs in the compiled kernels of :mod:`trajkit.profiles._kernels`. This
module imports them on first use (numba is slow to import), announces a first
compilation that takes long, runs one problem or a batch, and turns the kernels'
status codes into errors that name the joint and the cause.

Arrays are ``(ndof,)`` for one problem or ``(B, ndof)`` for a batch; limits are
given as bounds ``v_min < 0 < v_max`` and ``a_min < 0 < a_max``, ``j_max > 0``
(``inf``: acceleration-limited, a trapezoid).
"""

from __future__ import annotations

import sys
import threading
import time
from dataclasses import dataclass
from types import ModuleType
from typing import Any

import numpy as np
from numpy.typing import NDArray

from trajkit._validation import FloatArray
from trajkit.errors import InfeasibleError
from trajkit.profiles._phases import PhasePlan

__all__ = [
    "STATUS_OK",
    "SYNC_MODES",
    "EngineResult",
    "kernels",
    "phase_plan",
    "prepare",
    "single_signature",
    "solve",
    "unpack",
    "warm",
]

#: Synchronization modes and the kernels' codes for them.
SYNC_MODES: dict[str | None, int] = {"time": 0, "phase": 1, "time_if_necessary": 2, None: 3}
POSITION, VELOCITY = 0, 1

# A first compilation of the kernels takes this long before it is announced (s).
_ANNOUNCE_AFTER = 1.0
_warm: set[str] = set()
_lock = threading.Lock()


def kernels() -> ModuleType:
    """The entry kernels (importing numba and the compiled laws on first use)."""
    global _checked
    if not _checked:
        _checked = True
        _drop_stale_cache()
    from trajkit.profiles._kernels import solve

    return solve


_checked = False


def _drop_stale_cache() -> None:
    """Delete compiled kernels cached next to sources that changed since.

    Numba keys a cached function on its own file only: a kernel whose callee in
    another file changed would load the old callee compiled into it. An installed
    release replaces every file at once (all keys change), but a working copy
    edits one file at a time, so the kernels' in-tree cache is dropped whenever
    any kernel source is newer than the stamp left by the last check.
    """
    import pathlib

    folder = pathlib.Path(__file__).with_name("_kernels")
    cache = folder / "__pycache__"
    stamp = cache / "kernels.stamp"
    try:
        newest = max(p.stat().st_mtime_ns for p in folder.glob("*.py"))
        if stamp.exists() and stamp.read_text() == str(newest):
            return
        for stale in (*cache.glob("*.nbi"), *cache.glob("*.nbc")):
            stale.unlink(missing_ok=True)
        cache.mkdir(exist_ok=True)
        stamp.write_text(str(newest))
    except OSError:
        pass  # a read-only install: numba keeps its cache elsewhere, per release


def run(name: str, kernel: Any, *args: Any) -> Any:
    """Call ``kernel``; on its first call, say on stderr if compiling takes a while.

    Numba compiles (or loads from its cache) each kernel on its first call; a
    compilation takes tens of seconds, a cached load a fraction of one. The note
    appears at most once per process, only when a first call outlasts
    ``_ANNOUNCE_AFTER``.
    """
    if name not in _warm:
        # Compile (or load) for these argument types before running, so that only
        # compiling is timed: a long first batch is no compilation.
        prepare(name, kernel, lambda numba: tuple(numba.typeof(a) for a in args))
    return kernel(*args)


def prepare(name: str, kernel: Any, signature: Any) -> None:
    """Compile (or load) ``kernel`` for ``signature(numba)`` (its argument types), announced.

    Without numba's JIT (``NUMBA_DISABLE_JIT=1``) there is nothing to compile.
    """
    with _lock:
        timer = threading.Timer(_ANNOUNCE_AFTER, _announce)
        timer.daemon = True
        timer.start()
        started = time.perf_counter()
        try:
            if hasattr(kernel, "compile"):
                import numba

                kernel.compile(signature(numba))
        finally:
            timer.cancel()
            _warm.add(name)
            _compile_times[name] = time.perf_counter() - started


def single_signature(name: str, kernel: Any, signature: Any) -> Any:
    """``kernel`` compiled (or loaded) for ``signature(numba)`` only, compiling disabled.

    For entry points whose arguments come straight from the caller: an argument
    of another type (a read-only or strided array) then raises TypeError at the
    call, for the caller to convert it, instead of compiling a second copy for
    minutes. Returns the kernel.
    """
    prepare(name, kernel, signature)
    if hasattr(kernel, "disable_compile"):  # not under NUMBA_DISABLE_JIT
        kernel.disable_compile()
    return kernel


def warm() -> float:
    """Compile (or load from the cache) every kernel the planners call.

    The first use of each kernel otherwise compiles it on the spot; ``trajkit
    demo`` and the test suite call this first, so later processes load the
    cache. Returns the seconds it took (s).
    """
    import trajkit as tk
    import trajkit.batch

    started = time.perf_counter()
    q0, qf = [0.0, 0.5], [1.0, -1.0]
    for jmax in (10.0, np.inf):
        for sync in ("time", "phase", None):
            for period in (None, 0.01):
                tk.scurve(q0, qf, 1.0, 2.0, jmax, v0=[0.1, 0.0], sync=sync, period=period).position(
                    0.5
                )
        tk.scurve(q0, qf, 1.0, 2.0, jmax, period=0.01, grid="duration")
        tk.scurve(q0, qf, 1.0, 2.0, jmax, duration=5.0)
        plans = trajkit.batch.scurve([q0, qf], [qf, q0], 1.0, 2.0, jmax, v0=0.1, period=0.01)
        plans.position(0.5)
        plans[1].position(0.5)
        trajkit.batch.scurve([q0, qf], [qf, q0], 1.0, 2.0, jmax, sync="phase").position(0.5)
        tk.online.Generator(2, 0.01, 1.0, 2.0, jmax).update(qf)
    return time.perf_counter() - started


def _announce() -> None:
    global _announced
    if not _announced:
        _announced = True
        print(
            "trajkit: compiling the profile engine (once: later runs load it from the cache)...",
            file=sys.stderr,
            flush=True,
        )


_announced = False
_compile_times: dict[str, float] = {}
# Constants of the kernels, here without importing them (a test checks they agree).
_SIZE = 64  # layout.SIZE
_PHASES = 9  # tables.PHASES
_OUT_SIZE = 4  # synchronize.OUT_SIZE; fields: duration, limiting joint, phase held, joint
_OK, _STEP1_FAILED, _ZERO_LIMITS, _SYNC_FAILED, _STEP2_FAILED = 0, 1, 2, 3, 4
_GRID_FAILED, _VELOCITY_UNSUPPORTED = 5, 6  # quantize.GRID_FAILED, VELOCITY_UNSUPPORTED
_UNRESOLVED = 7  # solve.UNRESOLVED
_MAX_EXTRA_PERIODS = 16  # quantize.MAX_EXTRA_PERIODS
#: The kernels' status of a problem planned.
STATUS_OK = _OK


@dataclass(frozen=True)
class EngineResult:
    """What the kernels planned.

    Attributes
    ----------
    duration : ndarray, shape (...)
        The common duration (s).
    limiting : ndarray of int, shape (...)
        The joint that set the duration, -1 where ``min_duration`` did.
    phase_synchronized : ndarray of bool, shape (...)
        Whether phase synchronization held (False where it was asked for and the
        joints fell back to time synchronization, and where it was not asked for).
    own : ndarray, shape (..., ndof)
        Each joint's own minimum duration (s), brake included.
    second_order : ndarray of bool, shape (..., ndof)
        Joints planned acceleration-limited (``j_max = inf``).
    t, u : ndarray, shape (..., ndof, 9)
        Phase tables (:mod:`trajkit.profiles._kernels.tables`): durations and
        controls (jerk, or acceleration for acceleration-limited joints).
    records : ndarray, shape (ndof, SIZE), or None
        One problem's profile records (see :mod:`trajkit.profiles._kernels.layout`).
    pieces : tuple or None
        One problem's breakpoints, coefficients and exact end state.
    """

    duration: FloatArray
    limiting: NDArray[np.int64]
    phase_synchronized: NDArray[np.bool_]
    own: FloatArray
    second_order: NDArray[np.bool_]
    t: FloatArray
    u: FloatArray
    records: FloatArray | None = None
    pieces: tuple[FloatArray, FloatArray, FloatArray] | None = None


def solve(
    planner: str,
    m: FloatArray,
    *,
    control: NDArray[np.int64],
    sync: NDArray[np.int64],
    enabled: NDArray[np.int64] | None = None,
    min_duration: float | FloatArray | None = None,
    period: float | None = None,
    grid: str = "switches",
) -> EngineResult:
    """Plan one problem (``m`` of shape ``(11, ndof)``) or a batch (``(B, 11, ndof)``).

    ``m`` holds the rows of :mod:`trajkit.profiles._kernels.admissible` (q0, qf,
    v0, vf, a0, af, v_min, v_max, a_min, a_max, j_max); inputs are trusted
    (validated, float64, C-contiguous; the int arrays int64, ``(ndof,)`` or
    ``(B, ndof)``). ``min_duration`` (s) is a floor on the duration, ``period`` (s)
    puts every switching time on the period grid (``grid="switches"``) or only
    the duration (``grid="duration"``).

    Raises
    ------
    InfeasibleError
        A joint has no profile (a zero limit that rules its move out, or a
        numerical failure, named as such) or no common duration exists.
    """
    mod = kernels()
    batch = m.ndim == 3
    ndof = m.shape[-1]
    shape = (*m.shape[:-2], ndof)
    leading = shape[:-1]
    if enabled is None:
        enabled = np.ones(shape, np.int64)
    own = np.empty(shape)
    out = np.empty((*leading, _OUT_SIZE))
    t = np.empty((*shape, _PHASES))
    u = np.empty((*shape, _PHASES))
    step = 0.0 if period is None else float(period)
    switches = grid == "switches"
    records = pieces = None
    if batch:
        floor = (
            np.full(leading, np.nan)
            if min_duration is None
            else np.broadcast_to(np.asarray(min_duration, dtype=np.float64), leading).copy()
        )
    else:
        floor = np.nan if min_duration is None else float(min_duration)
    # The leading arguments of both entry kernels (see solve.one and solve.batch).
    problem = (m, control, sync, enabled, floor, step, switches)
    if batch:
        status = np.empty(leading, np.int64)
        run("batch", mod.batch, *problem, t, u, own, out, status)
        bad = np.flatnonzero(status != _OK)
        if bad.size:
            i = int(bad[0])
            raise _failure(planner, int(status[i]), out[i], m[i], f" in problem {i}", step)
    else:
        records = np.empty((ndof, _SIZE))
        breakpoints = np.empty(_PHASES * ndof + 2)
        coefficients = np.empty((4, _PHASES * ndof + 1, ndof))
        end = np.empty((3, ndof))
        code, count = run(
            "one", mod.one, *problem, records, own, out, t, u, breakpoints, coefficients, end
        )
        if code != _OK:
            raise _failure(planner, code, out, m, "", step)
        pieces = (breakpoints[: count + 1], coefficients[:, :count], end)
    return EngineResult(
        out[..., 0],
        out[..., 1].astype(np.int64),
        out[..., 2] == 1.0,
        own,
        np.isinf(m[..., -1, :]),
        t,
        u,
        records,
        pieces,
    )


def unpack(plan: FloatArray, ndof: int) -> tuple[FloatArray, EngineResult]:
    """The matrix and the result of one problem from the flat ``plan`` of ``quick``."""
    from trajkit.profiles._kernels.solve import plan_layout

    o_m, o_records, o_own, o_out, o_t, o_u, size = plan_layout(ndof)
    m = plan[o_m:o_records].reshape(11, ndof)
    out = plan[o_out:o_t]
    return m, EngineResult(
        out[0],
        np.int64(out[1]),
        np.bool_(out[2] == 1.0),
        plan[o_own:o_out],
        np.isinf(m[-1]),
        plan[o_t:o_u].reshape(ndof, _PHASES),
        plan[o_u:size].reshape(ndof, _PHASES),
        plan[o_records:o_own].reshape(ndof, _SIZE),
    )


def unresolved(planner: str, duration: float, where: str) -> InfeasibleError:
    """The error for a plan whose pieces cannot keep it in absolute time."""
    return InfeasibleError(
        f"{planner}: the motion lasts {duration:.6g} s, too long to keep its short phases "
        f"in absolute time (float64 resolves about {duration * 2.2e-16:.2g} s there), so "
        f"it would miss its target{where}; plan it in larger time units (scale the "
        "limits) or in parts"
    )


def _failure(
    planner: str, code: int, out: FloatArray, m: FloatArray, where: str, period: float = 0.0
) -> Exception:
    """The error for a failed problem, naming the joint and its numbers."""
    joint = int(out[3])
    names = ("q0", "qf", "v0", "vf", "a0", "af", "v_min", "v_max", "a_min", "a_max", "j_max")

    def state(d: int) -> str:
        return ", ".join(f"{n}={float(v):.9g}" for n, v in zip(names, m[:, d], strict=True))

    if code == _ZERO_LIMITS:
        if joint >= 0:
            return InfeasibleError(
                f"{planner}: joint {joint + 1}{where} cannot reach its target: a zero limit "
                f"rules the move out ({state(joint)})"
            )
        return InfeasibleError(
            f"{planner}: a joint with a zero limit cannot take the duration the others need{where}"
        )
    if code == _GRID_FAILED:
        return InfeasibleError(
            f"{planner}: no profile with every phase in whole multiples of period={period:g} s "
            f"keeps the limits within {_MAX_EXTRA_PERIODS} periods of the continuous "
            f"optimum{where}; pass grid='duration' to put only the duration on the grid"
        )
    if code == _VELOCITY_UNSUPPORTED:
        return InfeasibleError(
            f"{planner}: the velocity interface puts only the duration on the period "
            f"grid{where}; pass grid='duration'"
        )
    if code == _UNRESOLVED:
        return unresolved(planner, float(out[0]), where)
    if code == _SYNC_FAILED:
        return InfeasibleError(
            f"{planner}: no common duration suits every synchronized joint{where}; "
            "leave some out of synchronization (sync=None for them)"
        )
    if code == _STEP1_FAILED and joint >= 0:
        q0, qf, *_, v_min, v_max, a_min, a_max, j_max = (float(x) for x in m[:, joint])
        cruise = abs(qf - q0) / min(v_max, -v_min)
        push = min(a_max, -a_min)
        ramp, what = (
            (push / j_max, "acceleration")
            if j_max < np.inf
            else (min(v_max, -v_min) / push, "velocity")
        )
        if cruise * 2.2e-16 > ramp:
            return InfeasibleError(
                f"{planner}: joint {joint + 1}{where} needs about {cruise:.3g} s at its velocity "
                f"limit but ramps its {what} in {ramp:.3g} s: beyond what float64 "
                "resolves in one motion; plan it in larger time units (scale the limits) or "
                "in parts"
            )
    step = "fastest profile" if code == _STEP1_FAILED else "profile of the common duration"
    if joint < 0:  # the shared time law of the phase-synchronized joints
        every = "; ".join(f"joint {d + 1}: {state(d)}" for d in range(m.shape[1]))
        return InfeasibleError(
            f"{planner}: the engine found no {step} for the phase-synchronized joints' shared "
            f"time law{where} (a numerical failure of the engine; please report it with these "
            f"numbers: {every})"
        )
    return InfeasibleError(
        f"{planner}: the engine found no {step} for joint {joint + 1}{where} (a numerical failure "
        f"of the engine; please report it with these numbers: {state(joint)})"
    )


def phase_plan(result: EngineResult, p0: FloatArray, v0: FloatArray, a0: FloatArray) -> PhasePlan:
    """The phase tables as a :class:`PhasePlan` of nine phases: two of brake, seven of profile.

    A phase plan carries each phase's start acceleration and jerk: a jerk-limited
    joint's accelerations are integrated from ``a0``; an acceleration-limited
    joint's phases hold their acceleration (jerk 0).
    """
    t, u = result.t, result.u
    second = result.second_order[..., np.newaxis]
    steps = np.where(second, 0.0, u * t)
    integrated = np.asarray(a0)[..., np.newaxis] + np.concatenate(
        [np.zeros_like(steps[..., :1]), np.cumsum(steps[..., :-1], axis=-1)], axis=-1
    )
    accelerations = np.where(second, np.where(t > 0, u, 0.0), integrated)
    jerks = np.where(second, 0.0, u)
    return PhasePlan(p0, v0, t, accelerations, jerks)
