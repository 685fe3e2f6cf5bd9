"""The old name ``dt=`` still works where it became ``period``, ``sample_step`` or ``ik_step``."""

from __future__ import annotations

import numpy as np
import pytest

import trajkit as tk
from trajkit import batch, mobile, online
from trajkit.kinematics import Spatial3R
from trajkit.taskspace import Line, timed, to_joint_space

PLAN = tk.quintic([0.0], [1.0], 2.0)
BASE = mobile.rotate_translate_rotate((1.0, 1.0, 0.0), vmax=1.0, wmax=1.0, amax=1.0,
                                      alpha_max=1.0)  # fmt: skip
MOTION = timed(Line([0, -12, 20], [10, 12, 20]), "quintic", duration=1.0)

# (call with a keyword, its new name, a value): each call must give the same result
# under the old name and the new one.
CALLS = {
    "scurve": (lambda **kw: tk.scurve([0.0], [1.0], 1.0, 2.0, 10.0, **kw), "period", 0.01),
    "trapezoidal": (lambda **kw: tk.trapezoidal([0.0], [1.0], 1.0, 2.0, **kw), "period", 0.01),
    "velocity_change": (lambda **kw: tk.velocity_change([0.0], [1.0], 2.0, 10.0,
                                                        grid="duration", **kw),
                        "period", 0.01),
    "batch.scurve": (lambda **kw: batch.scurve([[0.0]], [[1.0]], 1.0, 2.0, 10.0, **kw),
                     "period", 0.01),
    "batch.trapezoidal": (lambda **kw: batch.trapezoidal([[0.0]], [[1.0]], 1.0, 2.0, **kw),
                          "period", 0.01),
    "rotate_translate_rotate": (
        lambda **kw: mobile.rotate_translate_rotate(
            (1.0, 1.0, 0.0), vmax=1.0, wmax=1.0, amax=1.0, alpha_max=1.0, **kw
        ),
        "period", 0.01,
    ),
    "Generator": (lambda **kw: online.Generator(1, vmax=1.0, amax=2.0, jmax=10.0, **kw),
                  "period", 0.01),
    "Trajectory.sample": (lambda **kw: PLAN.sample(**kw), "sample_step", 0.1),
    "MobileTrajectory.times": (lambda **kw: BASE.times(**kw), "sample_step", 0.1),
    "mobile.simulate": (lambda **kw: mobile.simulate(BASE, **kw), "sample_step", 0.05),
    "to_joint_space": (lambda **kw: to_joint_space(Spatial3R(), MOTION, **kw), "ik_step", 0.01),
}  # fmt: skip


def _fingerprint(result: object) -> np.ndarray:
    """Numbers that differ when the keyword was not taken as its new name."""
    if isinstance(result, np.ndarray):
        return result
    if isinstance(result, online.Generator):
        return np.array([result.period])
    if isinstance(result, tk.Samples):
        return result.t
    if isinstance(result, mobile.SimulationLog):
        return result.t
    if hasattr(result, "trajectory"):  # a joint-space plan: its IK sample times
        return result.t
    if isinstance(result, batch.BatchTrajectory):
        return result.durations
    return np.asarray(result.breakpoints)


@pytest.mark.parametrize("name", list(CALLS))
def test_the_old_name_gives_what_the_new_name_gives_with_a_warning(name):
    call, new, value = CALLS[name]
    expected = _fingerprint(call(**{new: value}))
    with pytest.warns(FutureWarning, match=rf"dt= is renamed {new}=") as caught:
        old = _fingerprint(call(dt=value))
    assert "__init__" not in str(caught[0].message)  # the name called: Generator, not __init__
    np.testing.assert_array_equal(old, expected)
    # The grid or step was taken: a different value gives a different answer.
    assert not np.array_equal(_fingerprint(call(**{new: value * 3})), expected)


@pytest.mark.parametrize("name", ["scurve", "Trajectory.sample", "to_joint_space"])
def test_both_names_at_once_are_refused(name):
    call, new, value = CALLS[name]
    with pytest.raises(tk.InvalidInputError, match=rf"give {new}= only: dt= is its old name"):
        call(**{new: value, "dt": value})


def test_the_generators_old_attribute_reads_the_period_with_a_warning():
    generator = online.Generator(1, 0.004, 1.0, 2.0, 10.0)
    with pytest.warns(FutureWarning, match="Generator.dt is renamed Generator.period"):
        assert generator.dt == 0.004 == generator.period


def test_renamed_functions_keep_their_signature_for_help_and_the_catalog():
    import inspect

    assert "period" in inspect.signature(tk.scurve).parameters
    assert "dt" not in inspect.signature(tk.scurve).parameters
    assert tk.scurve.__name__ == "scurve" and "jerk-limited" in tk.scurve.__doc__
