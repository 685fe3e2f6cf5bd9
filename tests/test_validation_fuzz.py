"""Fuzz of the public Python API: only documented exceptions ever escape.

Every public function and constructor is called with valid arguments in which
hypothesis swaps some for hostile ones: every dtype (int, float32, bool,
complex, object, str), odd shapes, ragged lists, None, text, NaN, inf,
subnormals and +-1e308. Whatever happens, the only exceptions allowed out are
:class:`trajkit.TrajkitError` subclasses (the documented ones); any other fails
the test with the call that raised it. A call that runs longer than a few
seconds fails too: a hostile number must not start an unbounded computation.
"""

from __future__ import annotations

import math
import os
import resource
import signal
import warnings
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import trajkit as tk
import trajkit.batch
import trajkit.mobile as mobile
import trajkit.taskspace as taskspace

#: Seconds one call may take before it counts as a runaway computation.
CALL_TIMEOUT = 10
#: Hostile calls per public function: about 25 s for the whole file on one core.
EXAMPLES = 80
#: Memory one call may add (bytes): a hostile number must not start a huge allocation.
CALL_MEMORY = 2**29

# ------------------------------------------------------------------ hostile values
SPECIAL_FLOATS = [
    0.0,
    -0.0,
    1.0,
    -1.0,
    0.5,
    2.0,
    np.nan,
    np.inf,
    -np.inf,
    1e-320,  # subnormal
    5e-324,  # the smallest subnormal
    -1e-310,
    1e-300,
    1e308,
    -1e308,
    1.7976931348623157e308,
    1e154,
    1e-154,
]

scalar = st.one_of(
    st.sampled_from(SPECIAL_FLOATS),
    st.floats(allow_nan=True, allow_infinity=True, width=64),
    st.integers(min_value=-(10**400), max_value=10**400),
    st.integers(min_value=-3, max_value=3),
)

odd_object = st.sampled_from(
    [
        None,
        "1.5",
        "",
        "abc",
        b"2",
        True,
        False,
        np.True_,
        1j,
        1 + 0j,
        np.complex128(2),
        {"a": 1},
        {1.0},
        object(),
        [],
        [[]],
        (),
        [[1.0], [1.0, 2.0]],  # ragged
        [1.0, [2.0]],
        [1.0, None],
        [1.0, "2"],
        [1.0, True],
        [0.0, 1j],
        [[0.0, 0.0], [1.0]],
        np.array([]),
        np.zeros((0, 2)),
        np.zeros((2, 0)),
        np.array([True, False]),
        np.array([1 + 2j, 3 + 0j]),
        np.array([1.0, "a"], dtype=object),
        np.array([1.0, None], dtype=object),
        np.array([1.0, 2.0], dtype=object),
        np.array(["1", "2"]),
        np.array([1.0, 2.0], dtype=np.float32),
        np.array([1, 2], dtype=np.int8),
        np.array([1, 2], dtype=np.uint64),
        np.array([1.0, 2.0], dtype=np.float16),
        np.array([np.datetime64("2024-01-01")] * 2),
        np.float32(0.5),
        np.int64(2),
    ]
)

DTYPES = [np.float64, np.float32, np.float16, np.int64, np.int32, np.uint8, np.bool_,
          np.complex128, object, str]  # fmt: skip


@st.composite
def arrays(draw: st.DrawFn) -> Any:
    """An array of any small shape and dtype, filled with special numbers."""
    shape = draw(st.sampled_from([(), (0,), (1,), (2,), (3,), (4,), (2, 2), (3, 2), (2, 3),
                                  (1, 3), (2, 4, 4), (2, 3, 1), (1, 1, 1)]))  # fmt: skip
    dtype = draw(st.sampled_from(DTYPES))
    size = int(np.prod(shape))
    values = draw(st.lists(st.sampled_from(SPECIAL_FLOATS), min_size=size, max_size=size))
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore")
        return np.array(values, dtype=np.float64).astype(dtype).reshape(shape)


@st.composite
def nested_lists(draw: st.DrawFn) -> Any:
    """Python lists, possibly ragged, possibly holding odd leaves."""
    leaf = st.one_of(scalar, odd_object)
    rows = draw(st.integers(0, 4))
    if draw(st.booleans()):
        return [draw(leaf) for _ in range(rows)]
    return [[draw(leaf) for _ in range(draw(st.integers(0, 4)))] for _ in range(rows)]


hostile = st.one_of(scalar, odd_object, arrays(), nested_lists())


def _call(function: Callable[..., Any], args: tuple[Any, ...], kwargs: dict[str, Any]) -> Any:
    """Call, letting TrajkitError through silently and failing on anything else."""
    with _time_limit(CALL_TIMEOUT), warnings.catch_warnings():
        # Warnings are not exceptions escaping: keep them out of the verdict.
        warnings.simplefilter("ignore")
        try:
            return function(*args, **kwargs)
        except tk.TrajkitError:
            return None
        except _Runaway:
            pytest.fail(f"{_show(function, args, kwargs)} ran longer than {CALL_TIMEOUT} s")
        except MemoryError:
            pytest.fail(f"{_show(function, args, kwargs)} tried to allocate over 512 MiB")
        except Exception as exc:  # any other exception is the defect this test looks for
            pytest.fail(
                f"{_show(function, args, kwargs)} raised {type(exc).__name__}: {exc}",
                pytrace=True,
            )


class _Runaway(Exception):
    pass


@contextmanager
def _time_limit(seconds: int) -> Iterator[None]:
    def alarm(signum: int, frame: Any) -> None:
        raise _Runaway

    previous = signal.signal(signal.SIGALRM, alarm)
    limits = resource.getrlimit(resource.RLIMIT_AS)
    with open(f"/proc/{os.getpid()}/statm") as statm:
        mapped = int(statm.read().split()[0]) * resource.getpagesize()
    cap = mapped + CALL_MEMORY
    if limits[1] != resource.RLIM_INFINITY:
        cap = min(cap, limits[1])
    resource.setrlimit(resource.RLIMIT_AS, (cap, limits[1]))
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        resource.setrlimit(resource.RLIMIT_AS, limits)
        signal.signal(signal.SIGALRM, previous)


def _show(function: Callable[..., Any], args: tuple[Any, ...], kwargs: dict[str, Any]) -> str:
    parts = [repr(a) for a in args] + [f"{k}={v!r}" for k, v in kwargs.items()]
    return f"{getattr(function, '__qualname__', function)}({', '.join(parts)})"


# ------------------------------------------------------------------ the API under test
def _path() -> tk.Trajectory:
    return tk.cubic_spline([0.0, 0.5, 1.0], [[0.0, 0.0], [1.0, -0.5], [0.5, 1.0]], bc="natural")


def _trajectory() -> tk.Trajectory:
    return tk.quintic([0.0, 1.0], [1.0, -1.0], 2.0)


def _sample(**kwargs: Any) -> Any:
    """``_trajectory().sample(**kwargs)``, except grids too big for this test's memory cap.

    A period of 1e-7 s over the 2 s move is a legitimate 2e7-sample request (under
    ``MAX_SAMPLES``) that needs about 1.4 GB: a MemoryError under the 512 MiB cap would
    say nothing about input handling, so such periods are left out, not called.
    """
    try:
        dt = np.asarray(kwargs.get("sample_step"))
        period = float(dt) if dt.dtype.kind in "fiu" and dt.size == 1 else math.nan
    except (TypeError, ValueError, OverflowError):
        period = math.nan
    # 9 float64 columns per sample (t and four orders of two joints), with room to spare.
    if 0.0 < period < math.inf and _trajectory().duration / period * 9 * 8 > CALL_MEMORY / 8:
        return None
    return _trajectory().sample(**kwargs)


def _mobile_plan() -> mobile.MobileTrajectory:
    return mobile.constant_twist(0.5, 0.2, 2.0, model=mobile.jackal())


# name -> (function, valid keyword arguments). Every keyword is a candidate for a
# hostile value; the valid ones keep the call going deep into the planner.
CASES: dict[str, tuple[Callable[..., Any], dict[str, Any]]] = {
    "cubic": (tk.cubic, {"q0": [0.0, 1.0], "qf": [1.0, 0.0], "duration": 1.0, "v0": 0.0,
                         "vf": 0.0, "vmax": None, "amax": None, "jmax": None}),
    "cubic_limits": (tk.cubic, {"q0": [0.0, 1.0], "qf": [1.0, 0.0], "v0": 0.1, "vf": 0.0,
                                "vmax": 2.0, "amax": 3.0}),
    "quintic": (tk.quintic, {"q0": 0.0, "qf": 1.0, "duration": 1.0, "v0": 0.0, "vf": 0.0,
                             "a0": 0.0, "af": 0.0, "vmax": 10.0}),
    "quintic_limits": (tk.quintic, {"q0": 0.0, "qf": 1.0, "v0": 0.0, "a0": 0.0, "af": 0.0,
                                    "amax": 2.0}),
    "septic": (tk.septic, {"q0": 0.0, "qf": 1.0, "duration": 1.0, "j0": 0.0, "jf": 0.0,
                           "a0": 0.0, "af": 0.0}),
    "polynomial": (tk.polynomial, {"conditions": [(0, 0, 0.0), (0, 1, 0.0), (1, 0, 1.0),
                                                  (1, 1, 0.0)]}),
    "polynomial_segments": (tk.polynomial, {
        "conditions": [[(0, 0, 0.0), (1, 0, 0.5)], [(1, 0, 0.5), (3, 0, 1.0)]],
        "segments": [0.0, 1.0, 3.0], "continuity": [(1,)], "degrees": [2, 1]}),
    "cubic_via": (tk.cubic_via, {"times": [0.0, 1.0, 2.0], "positions": [0.0, 1.0, 0.0],
                                 "velocities": None}),
    "quintic_via": (tk.quintic_via, {"times": [0.0, 1.0, 2.0], "positions": [[0.0], [1.0],
                                     [0.0]], "velocities": None, "accelerations": None}),
    "cubic_spline": (tk.cubic_spline, {"times": [0.0, 1.0, 2.0], "positions": [0.0, 1.0, 0.0],
                                       "v0": 0.0, "vf": 0.0, "bc": "clamped"}),
    "trapezoidal": (tk.trapezoidal, {"q0": [0.0, 1.0], "qf": [1.0, 0.0], "vmax": 1.0,
                                     "amax": 2.0, "v0": 0.0, "vf": 0.0, "sync": "time",
                                     "duration": None, "period": None}),
    "trapezoidal_blend": (tk.trapezoidal, {"q0": 0.0, "qf": 1.0, "duration": 2.0, "vmax": 2.0,
                                           "blend_ratio": 0.25, "blend_time": None}),
    "scurve": (tk.scurve, {"q0": [0.0, 1.0], "qf": [1.0, 0.0], "vmax": 1.0, "amax": 2.0,
                           "jmax": 5.0, "v0": 0.0, "vf": 0.0, "sync": "time",
                           "duration": None, "period": None}),
    "blended": (tk.blended, {"waypoints": [[0.0, 0.0], [1.0, 1.0], [2.0, 0.0]], "vmax": 1.0,
                             "amax": 2.0, "jmax": None, "durations": None, "through": False}),
    "batch_trapezoidal": (trajkit.batch.trapezoidal, {
        "q0": [[0.0, 0.0], [1.0, 1.0]], "qf": [[1.0, 1.0], [0.0, 2.0]], "vmax": 1.0,
        "amax": 2.0, "v0": 0.0, "vf": 0.0, "sync": "time", "period": None}),
    "batch_scurve": (trajkit.batch.scurve, {
        "q0": [[0.0, 0.0], [1.0, 1.0]], "qf": [[1.0, 1.0], [0.0, 2.0]], "vmax": 1.0,
        "amax": 2.0, "jmax": 5.0, "v0": 0.0, "vf": 0.0, "sync": "time", "period": None}),
    "topp": (lambda **kw: tk.topp(_path(), **kw), {
        "limits": tk.Limits(velocity=1.0, acceleration=2.0), "grid": 20, "start_speed": 0.0,
        "end_speed": 0.0}),
    "Limits": (tk.Limits, {"position": (-1.0, 1.0), "velocity": 1.0, "acceleration": 2.0,
                           "jerk": None}),
    "Trajectory": (tk.Trajectory, {"breakpoints": [0.0, 1.0], "coefficients": [[1.0], [0.0]]}),
    "evaluate": (lambda **kw: _trajectory().evaluate(**kw), {"t": [0.0, 1.0], "order": 1}),
    "sample": (lambda **kw: _sample(**kw), {"sample_step": 0.1, "unit": "rad"}),
    "check": (lambda **kw: tk.check(_trajectory(), **kw), {
        "limits": tk.Limits(velocity=1.0), "rtol": 1e-9}),
    "time_scaled": (lambda **kw: _trajectory().time_scaled(**kw), {"factor": 2.0}),
    "extrema": (lambda **kw: _trajectory().extrema(**kw), {"order": 1}),
    "derivative": (lambda **kw: _trajectory().derivative(**kw), {"order": 1}),
    "then": (lambda **kw: _trajectory().then(**kw), {"other": tk.quintic([1.0, -1.0], 0.0, 1.0),
                                                      "atol": 1e-9}),
    "constant_twist": (mobile.constant_twist, {"v": 0.5, "omega": 0.2, "duration": 2.0,
                                               "rate_hz": None, "start": (0.0, 0.0, 0.0)}),
    "rotate_translate_rotate": (mobile.rotate_translate_rotate, {
        "goal": (1.0, 1.0, 0.5), "start": (0.0, 0.0, 0.0), "vmax": 1.0, "wmax": 1.0,
        "amax": 1.0, "alpha_max": 1.0}),
    "MobileLimits": (mobile.MobileLimits, {"velocity": 1.0, "angular_velocity": 1.0,
                                           "acceleration": 1.0, "wheel_speed": 10.0}),
    "DiffDrive": (mobile.DiffDrive, {"wheel_radius": 0.1, "track_width": 0.4,
                                     "wheel_speed_limit": None}),
    "mobile_FigureEight": (mobile.FigureEight, {"width": 2.0, "height": 1.0, "period": 10.0,
                                                "center": (0.0, 0.0), "cycles": 1.0}),
    "spline_output": (mobile.spline_output, {"waypoints": [[0.0, 0.0], [1.0, 0.0], [2.0, 1.0]],
                                             "times": None}),
    "arc_pose": (mobile.arc_pose, {"pose": (0.0, 0.0, 0.0), "v": 1.0, "omega": 0.5,
                                   "duration": 1.0}),
    "mobile_evaluate": (lambda **kw: _mobile_plan().evaluate(**kw), {"t": [0.0, 1.0],
                                                                     "order": 1}),
    "mobile_state": (lambda **kw: _mobile_plan().state(**kw), {"t": [0.0, 1.0]}),
    "mobile_check": (lambda **kw: _mobile_plan().check(**kw), {
        "limits": mobile.MobileLimits(velocity=1.0), "rtol": 1e-9}),
    "mobile_commands": (lambda **kw: _mobile_plan().commands(**kw), {"rate_hz": 10.0}),
    "Line": (taskspace.Line, {"start": [0.0, 0.0, 0.0], "end": [1.0, 0.0, 0.0]}),
    "task_Arc": (taskspace.Arc, {"center": [0.0, 0.0, 0.0], "start": [1.0, 0.0, 0.0],
                                 "angle": 1.0, "normal": (0.0, 0.0, 1.0)}),
    "Ellipse": (taskspace.Ellipse, {"center": [0.0, 0.0, 0.0], "a": 2.0, "b": 1.0,
                                    "turns": 1.0, "phase": 0.0}),
    "task_FigureEight": (taskspace.FigureEight, {"center": [0.0, 0.0, 0.0], "width": 2.0,
                                                 "height": 1.0}),
    "Polyline": (taskspace.Polyline, {"waypoints": [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0],
                                                    [1.0, 1.0, 0.0]]}),
    "timed": (lambda **kw: taskspace.timed(taskspace.Line([0, 0, 0], [1, 0, 0]), **kw), {
        "profile": "quintic", "duration": 1.0, "vmax": None, "amax": None}),
    "path_law": (taskspace.path_law, {"profile": "trapezoid", "vmax": 1.0, "amax": 1.0,
                                      "speed_bound": 1.0}),
    "through_poses": (taskspace.through_poses, {"poses": [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]],
                                                "vmax": 1.0, "amax": 1.0, "durations": None}),
}  # fmt: skip


@st.composite
def hostile_call(draw: st.DrawFn, defaults: dict[str, Any]) -> dict[str, Any]:
    """The valid arguments with one to all of them replaced by hostile values."""
    names = sorted(defaults)
    chosen = draw(st.lists(st.sampled_from(names), min_size=1, max_size=len(names), unique=True))
    kwargs = dict(defaults)
    for name in chosen:
        kwargs[name] = draw(hostile)
    return kwargs


@pytest.mark.parametrize("case", sorted(CASES))
def test_only_documented_exceptions_escape(case: str) -> None:
    function, defaults = CASES[case]
    # The valid call itself must work: otherwise the fuzz would test nothing.
    assert _call(function, (), dict(defaults)) is not None

    @settings(max_examples=EXAMPLES, suppress_health_check=[HealthCheck.too_slow], deadline=None)
    @given(kwargs=hostile_call(defaults))
    def run(kwargs: dict[str, Any]) -> None:
        _call(function, (), kwargs)

    run()
