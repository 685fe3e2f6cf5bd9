"""Arm geometry over time for drawing: link_positions."""

from __future__ import annotations

import numpy as np
import pytest

import trajkit as tk
from trajkit.kinematics import Planar2R, Spatial3R, link_positions


def test_planar_arm_points_over_time():
    arm = Planar2R(1.0, 0.5)
    move = tk.cubic([0.0, 0.0], [np.pi / 2, -np.pi / 2], 2.0)
    points = link_positions(arm, move, [0.0, 2.0, 5.0])
    assert points.shape == (3, 4, 3)  # base, joint 1, joint 2, tool
    np.testing.assert_allclose(
        points[0], [[0, 0, 0], [0, 0, 0], [1, 0, 0], [1.5, 0, 0]], atol=1e-12
    )
    np.testing.assert_allclose(
        points[1], [[0, 0, 0], [0, 0, 0], [0, 1, 0], [0.5, 1, 0]], atol=1e-12
    )
    np.testing.assert_allclose(points[2], points[1], atol=0)  # clamped after the end


def test_tool_point_is_forward_kinematics():
    arm = Spatial3R()
    move = tk.quintic([0.1, -0.4, 0.9], [0.7, 0.3, 0.2], 3.0)
    t = np.linspace(0, 3, 50)
    points = link_positions(arm, move, t)
    np.testing.assert_allclose(points[:, -1], arm.fk(move.position(t))[:, :3, 3], atol=1e-12)
    # Link lengths are preserved at every instant: l0, l1, l2, l3.
    lengths = np.linalg.norm(np.diff(points, axis=1), axis=2)
    np.testing.assert_allclose(lengths, np.tile([5.0, 10.0, 8.0, 12.0], (50, 1)), rtol=1e-12)


def test_bad_input():
    arm = Planar2R(1.0, 0.5)
    with pytest.raises(tk.InvalidInputError, match="trajectory must be a Trajectory with 2 joints"):
        link_positions(arm, tk.cubic([0.0], [1.0], 1.0), [0.0])
    with pytest.raises(tk.InvalidInputError, match="robot must be a trajkit SerialChain"):
        link_positions("arm", tk.cubic([0.0, 0.0], [1.0, 1.0], 1.0), [0.0])  # type: ignore[arg-type]
    with pytest.raises(tk.InvalidInputError, match="t must be finite"):
        link_positions(arm, tk.cubic([0.0, 0.0], [1.0, 1.0], 1.0), [np.nan])
