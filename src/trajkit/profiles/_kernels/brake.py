"""The brake pre-profile: bringing a start state beyond the limits back inside.

A start state may violate the kinematic limits already (``v0`` beyond the
velocity limit, ``a0`` beyond the acceleration limit) or be bound to violate them
(``a0`` pointing outward so strongly that the velocity overshoots its limit even
while the jerk brings the acceleration to zero). Before the seven-phase profile
can start, up to two phases bring the state to one from which every limit can be
kept: a phase of maximal jerk, optionally followed by one of constant (limit)
acceleration. The mathematics follows ruckig's ``brake.cpp``.

Each function writes the phase durations ``BRAKE_T[0:2]`` and jerks
``BRAKE_J[0:2]`` of a profile record (and, second order, the brake acceleration
``BRAKE_A[0]``); zero durations mean no brake. Integrating the brake, setting
``BRAKE_DURATION`` and moving the start state to the brake's end is left to
:func:`~trajkit.profiles._kernels.profile.finalize_brake` (or its second-order
counterpart).

Phase durations carry the reference's margin of ``BRAKE_EPS`` (2.2e-14 s),
placed so that rounding cannot leave the braked acceleration beyond its limit;
a braked velocity may then sit up to about ``|a| * BRAKE_EPS`` beyond its limit,
far inside the tolerances of the profile checks.
"""

import math

from numba import njit

from trajkit.profiles._kernels.layout import BRAKE_A, BRAKE_J, BRAKE_T

BRAKE_EPS = 2.2e-14


@njit(cache=True, error_model="numpy")
def _min(a, b):
    """``std::min``: ``b`` only if strictly smaller (so a NaN in ``b`` loses)."""
    return b if b < a else a


@njit(cache=True, error_model="numpy")
def _max(a, b):
    """``std::max``, for the same reason as :func:`_min`."""
    return b if a < b else a


@njit(cache=True, error_model="numpy")
def _v_at_t(v0, a0, j, t):
    """Velocity after ``t`` s of jerk ``j`` from ``(v0, a0)``."""
    return v0 + t * (a0 + j * t / 2.0)


@njit(cache=True, error_model="numpy")
def _v_at_a_zero(v0, a0, j):
    """Velocity once the jerk ``-j`` has ramped ``a0`` to zero (``j`` of the sign of ``a0``).

    The reference's conditions also evaluate it with ``j`` of the other sign, where
    it is no reachable velocity, only a bound that decides the case; kept as is.
    """
    return v0 + (a0 * a0) / (2.0 * j)


@njit(cache=True, error_model="numpy")
def _reset(prof):
    """No brake: zero durations and jerks."""
    prof[BRAKE_T] = 0.0
    prof[BRAKE_T + 1] = 0.0
    prof[BRAKE_J] = 0.0
    prof[BRAKE_J + 1] = 0.0


@njit(cache=True, error_model="numpy")
def _velocity_brake(prof, v0, a0, v_max, v_min, a_max, a_min, j_max):
    """Brake a velocity that is (or will become) beyond ``v_max``.

    Written for the upward case; the downward one swaps the roles of the limits
    and negates ``j_max``. Jerk ``-j_max`` lowers the acceleration until either
    the velocity can come to rest at a limit or the acceleration reaches
    ``a_min``, after which ``a_min`` is held.
    """
    prof[BRAKE_J] = -j_max
    t_to_a_min = (a0 - a_min) / j_max
    # When v (still rising while a > 0) has come back down to v_max ...
    t_to_v_max = a0 / j_max + math.sqrt(a0 * a0 + 2.0 * j_max * (v0 - v_max)) / abs(j_max)
    # ... or when stopping the acceleration from here would just reach v_min:
    # braking any longer would then undershoot the other limit.
    t_to_v_min = a0 / j_max + math.sqrt(a0 * a0 / 2.0 + j_max * (v0 - v_min)) / abs(j_max)
    t_min_to_v_max = _min(t_to_v_max, t_to_v_min)

    if t_to_a_min < t_min_to_v_max:
        # The acceleration limit comes first: hold a_min until v reaches v_max,
        # or until v is low enough that releasing a_min just reaches v_min.
        v_at_a_min = _v_at_t(v0, a0, -j_max, t_to_a_min)
        t_to_v_max_with_constant = -(v_at_a_min - v_max) / a_min
        t_to_v_min_with_constant = a_min / (2.0 * j_max) - (v_at_a_min - v_min) / a_min
        # Stop a hair early so rounding cannot push a past a_min.
        prof[BRAKE_T] = _max(t_to_a_min - BRAKE_EPS, 0.0)
        prof[BRAKE_T + 1] = _max(_min(t_to_v_max_with_constant, t_to_v_min_with_constant), 0.0)
    else:
        prof[BRAKE_T] = _max(t_min_to_v_max - BRAKE_EPS, 0.0)


@njit(cache=True, error_model="numpy")
def _acceleration_brake(prof, v0, a0, v_max, v_min, a_max, a_min, j_max):
    """Brake an acceleration beyond ``a_max`` (upward case; see :func:`_velocity_brake`).

    Jerk ``-j_max`` brings the acceleration back to ``a_max``. If even bringing it
    to zero would overshoot ``v_max`` this is a velocity brake instead; if the
    velocity is then still below ``v_min``, ``a_max`` is held until it is not.
    """
    prof[BRAKE_J] = -j_max

    t_to_a_max = (a0 - a_max) / j_max
    t_to_a_zero = a0 / j_max

    v_at_a_max = _v_at_t(v0, a0, -j_max, t_to_a_max)
    v_at_a_zero = _v_at_t(v0, a0, -j_max, t_to_a_zero)

    # The sign of j_max tells the upward (> 0) from the mirrored call (< 0).
    if (v_at_a_zero > v_max and j_max > 0.0) or (v_at_a_zero < v_max and j_max < 0.0):
        _velocity_brake(prof, v0, a0, v_max, v_min, a_max, a_min, j_max)
    elif (v_at_a_max < v_min and j_max > 0.0) or (v_at_a_max > v_min and j_max < 0.0):
        # Keep accelerating at a_max out of the region below v_min, but no
        # further than to where ramping a_max down to zero just reaches v_max.
        t_to_v_min = -(v_at_a_max - v_min) / a_max
        t_to_v_max = -a_max / (2.0 * j_max) - (v_at_a_max - v_max) / a_max
        # Overshoot a_max's time by a hair so the braked a is not above a_max.
        prof[BRAKE_T] = t_to_a_max + BRAKE_EPS
        prof[BRAKE_T + 1] = _max(_min(t_to_v_min, t_to_v_max - BRAKE_EPS), 0.0)
    else:
        prof[BRAKE_T] = t_to_a_max + BRAKE_EPS


@njit(cache=True, error_model="numpy")
def position_brake(prof, v0, a0, v_max, v_min, a_max, a_min, j_max):
    """Brake pre-profile of a jerk-limited (third-order) position move.

    Parameters
    ----------
    prof : ndarray of float64, length ``SIZE``
        Profile record; ``BRAKE_T[0:2]`` and ``BRAKE_J[0:2]`` are written
        (``BRAKE_J[1]`` is always 0: the second phase holds an acceleration
        limit). Nothing else is touched.
    v0, a0 : float
        Start velocity and acceleration.
    v_max, v_min, a_max, a_min : float
        Limits, ``v_min <= v_max`` and ``a_min < 0 < a_max``.
    j_max : float
        Jerk limit, ``> 0``.

    Notes
    -----
    Zero durations (no brake) if the state is, and stays, within the limits:
    ``a0`` within ``[a_min, a_max]``, ``v0`` within ``[v_min, v_max]`` and the
    velocity reached by ramping ``a0`` to zero at ``j_max`` within them too.
    A zero ``j_max``, ``a_max`` or ``a_min`` disables braking, as in the
    reference (the problem is then one of the zero-limit special cases).
    """
    _reset(prof)
    if j_max == 0.0 or a_max == 0.0 or a_min == 0.0:
        return

    if a0 > a_max:
        _acceleration_brake(prof, v0, a0, v_max, v_min, a_max, a_min, j_max)
    elif a0 < a_min:
        _acceleration_brake(prof, v0, a0, v_min, v_max, a_min, a_max, -j_max)
    elif (v0 > v_max and _v_at_a_zero(v0, a0, -j_max) > v_min) or (
        a0 > 0.0 and _v_at_a_zero(v0, a0, j_max) > v_max
    ):
        # Too fast, or about to be: unless a strongly negative a0 will take the
        # velocity below v_min anyway, which the next case brakes instead.
        _velocity_brake(prof, v0, a0, v_max, v_min, a_max, a_min, j_max)
    elif (v0 < v_min and _v_at_a_zero(v0, a0, j_max) < v_max) or (
        a0 < 0.0 and _v_at_a_zero(v0, a0, -j_max) < v_min
    ):
        _velocity_brake(prof, v0, a0, v_min, v_max, a_min, a_max, -j_max)


@njit(cache=True, error_model="numpy")
def second_order_position_brake(prof, v0, v_max, v_min, a_max, a_min):
    """Brake pre-profile of an acceleration-limited (second-order) position move.

    Parameters
    ----------
    prof : ndarray of float64, length ``SIZE``
        Profile record; writes ``BRAKE_T[0]`` (``BRAKE_T[1]`` = 0), the brake's
        constant acceleration ``BRAKE_A[0]`` (``BRAKE_A[1]`` = 0) and zero
        jerks, as :func:`~trajkit.profiles._kernels.profile.finalize_brake_second_order`
        expects.
    v0 : float
        Start velocity (the acceleration is no state in second order).
    v_max, v_min, a_max, a_min : float
        Limits, ``v_min <= v_max`` and ``a_min < 0 < a_max``.

    Notes
    -----
    A velocity beyond a limit is brought back at the full opposite acceleration;
    within the limits there is no brake. Zero acceleration limits disable it.
    """
    _reset(prof)
    prof[BRAKE_A] = 0.0
    prof[BRAKE_A + 1] = 0.0
    if a_max == 0.0 or a_min == 0.0:
        return

    if v0 > v_max:
        prof[BRAKE_A] = a_min
        prof[BRAKE_T] = (v_max - v0) / a_min + BRAKE_EPS
    elif v0 < v_min:
        prof[BRAKE_A] = a_max
        prof[BRAKE_T] = (v_min - v0) / a_max + BRAKE_EPS


@njit(cache=True, error_model="numpy")
def velocity_brake(prof, a0, a_max, a_min, j_max):
    """Brake pre-profile of a jerk-limited velocity-interface move.

    Without a position target only the acceleration limits matter: an ``a0``
    beyond one is ramped back to it at full jerk.

    Parameters
    ----------
    prof : ndarray of float64, length ``SIZE``
        Profile record; writes ``BRAKE_T[0:2]`` and ``BRAKE_J[0:2]``.
    a0 : float
        Start acceleration.
    a_max, a_min : float
        Acceleration limits.
    j_max : float
        Jerk limit, ``> 0``; zero disables braking.
    """
    _reset(prof)
    if j_max == 0.0:
        return

    if a0 > a_max:
        prof[BRAKE_J] = -j_max
        prof[BRAKE_T] = (a0 - a_max) / j_max + BRAKE_EPS
    elif a0 < a_min:
        prof[BRAKE_J] = j_max
        prof[BRAKE_T] = -(a0 - a_min) / j_max + BRAKE_EPS


@njit(cache=True, error_model="numpy")
def second_order_velocity_brake(prof):
    """Brake pre-profile of an acceleration-limited velocity-interface move: none.

    The acceleration jumps freely in second order and the velocity is the
    target, so no start state needs braking. Zeroes the brake's durations and
    jerks.
    """
    _reset(prof)
