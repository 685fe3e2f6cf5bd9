"""The engine's errors for a numerical failure name what failed and give its numbers.

No planner known to fail reaches these messages (each failure found was fixed), so
they are built here from the codes and output row the kernels return.
"""

from __future__ import annotations

import numpy as np

from trajkit import InfeasibleError
from trajkit.profiles import engine


def problem(ndof: int) -> np.ndarray:
    m = np.zeros((11, ndof))
    m[1] = np.arange(1, ndof + 1)  # qf
    m[6:10] = [[-1.0] * ndof, [1.0] * ndof, [-2.0] * ndof, [2.0] * ndof]  # v, a bounds
    m[10] = 5.0  # j_max
    return m


def out_row(joint: int) -> np.ndarray:
    out = np.zeros(8)
    out[3] = joint
    return out


def test_a_joints_failure_names_the_joint_from_one_and_its_numbers():
    error = engine._failure("scurve", engine._STEP1_FAILED, out_row(1), problem(3), "")
    assert isinstance(error, InfeasibleError)
    text = str(error)
    assert "no fastest profile for joint 2 (" in text
    assert "q0=0, qf=2, v0=0" in text


def test_the_shared_phase_laws_failure_names_the_law_and_every_joints_numbers():
    """The law is no joint: its failure once read "joint 0" with the last joint's numbers."""
    error = engine._failure("trapezoidal", engine._STEP1_FAILED, out_row(-1), problem(2), "")
    text = str(error)
    assert "phase-synchronized joints' shared time law" in text
    assert "joint 0" not in text
    assert "joint 1: q0=0, qf=1," in text and "joint 2: q0=0, qf=2," in text
