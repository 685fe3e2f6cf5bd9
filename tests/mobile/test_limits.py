"""Tests of trajkit.mobile.limits: MobileLimits parsing, replace, magnitude, repr."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from trajkit import InvalidInputError
from trajkit.limits import Bounds
from trajkit.mobile import MobileLimits
from trajkit.mobile.limits import QUANTITIES, UNITS

ATTRIBUTES = [attribute for attribute, _, _ in QUANTITIES]


def bounds_of(limits: MobileLimits, attribute: str) -> tuple[float, float]:
    bounds = getattr(limits, attribute)
    return float(bounds.lower), float(bounds.upper)


def test_quantities_and_units():
    assert ATTRIBUTES == [
        "velocity", "angular_velocity", "acceleration", "angular_acceleration", "wheel_speed"
    ]  # fmt: skip
    assert [name for _, name, _ in QUANTITIES] == [
        "velocity", "angular velocity", "acceleration", "angular acceleration", "wheel speed"
    ]  # fmt: skip
    assert UNITS == {
        "velocity": "m/s",
        "angular_velocity": "rad/s",
        "acceleration": "m/s^2",
        "angular_acceleration": "rad/s^2",
        "wheel_speed": "rad/s",
    }


def test_default_has_no_limits():
    limits = MobileLimits()
    for attribute in ATTRIBUTES:
        assert getattr(limits, attribute) is None
        assert limits.magnitude(attribute) is None
    assert repr(limits) == "MobileLimits()"


@pytest.mark.parametrize("attribute", ATTRIBUTES)
def test_a_number_is_a_symmetric_bound(attribute):
    limits = MobileLimits(**{attribute: 2.5})
    assert bounds_of(limits, attribute) == (-2.5, 2.5)
    assert limits.magnitude(attribute) == 2.5
    for other in ATTRIBUTES:
        if other != attribute:
            assert getattr(limits, other) is None


@pytest.mark.parametrize("attribute", ATTRIBUTES)
def test_a_tuple_is_asymmetric(attribute):
    limits = MobileLimits(**{attribute: (-0.5, 2.0)})
    assert bounds_of(limits, attribute) == (-0.5, 2.0)
    assert limits.magnitude(attribute) == 0.5  # the tighter side
    assert MobileLimits(**{attribute: (-3.0, 1.0)}).magnitude(attribute) == 1.0


def test_one_sided_tuple_with_zero_is_allowed():
    limits = MobileLimits(velocity=(0.0, 1.0))  # never reverse
    assert bounds_of(limits, "velocity") == (0.0, 1.0)
    assert limits.magnitude("velocity") == 0.0


def test_positional_order_follows_the_quantities():
    limits = MobileLimits(1.0, 2.0, 3.0, 4.0, 5.0)
    assert [limits.magnitude(a) for a in ATTRIBUTES] == [1.0, 2.0, 3.0, 4.0, 5.0]


def test_bounds_objects_pass_through():
    given_bounds = Bounds(np.array(-1.0), np.array(3.0))
    limits = MobileLimits(velocity=given_bounds)
    assert limits.velocity is given_bounds


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"velocity": -1.0}, r"velocity limits must be > 0, got -1"),
        ({"velocity": 0.0}, r"velocity limits must be > 0, got 0"),
        ({"angular_velocity": -1.0}, r"angular_velocity limits must be > 0"),
        ({"acceleration": np.nan}, r"acceleration must be finite, got nan"),
        ({"angular_acceleration": np.inf}, r"angular_acceleration must be finite"),
        ({"wheel_speed": -2.0}, r"wheel_speed limits must be > 0"),
        ({"wheel_speed": "fast"}, r"wheel_speed must be numeric"),
        ({"velocity": (1.0, 2.0)}, r"velocity=\(1.0, 2.0\): a tuple is read as \(lower, upper\) "
                                   r"and must contain 0"),
        ({"velocity": (-1.0, -0.5)}, r"velocity=.*must contain 0"),
        ({"velocity": (2.0, -1.0)}, r"velocity lower bound must be below the upper bound"),
        ({"velocity": (-1.0, np.nan)}, r"velocity upper bound must be finite"),
        ({"angular_velocity": (np.nan, 1.0)}, r"angular_velocity lower bound must be finite"),
        ({"acceleration": (1.0, 2.0, 3.0)}, r"acceleration given as a tuple must be "
                                            r"\(lower, upper\), got 3 items"),
        ({"velocity": [1.0, 2.0]}, r"velocity limit must be one number or a \(lower, upper\) pair"),
        ({"wheel_speed": ([-1, -2], [1, 2])}, r"wheel_speed limit must be one number"),
    ],
)  # fmt: skip
def test_bad_limits_name_the_argument(kwargs, match):
    with pytest.raises(InvalidInputError, match=match):
        MobileLimits(**kwargs)


def test_replace_changes_removes_and_keeps_the_original():
    limits = MobileLimits(velocity=1.0, angular_velocity=2.0)
    changed = limits.replace(velocity=(-0.5, 3.0), acceleration=4.0, angular_velocity=None)
    assert bounds_of(changed, "velocity") == (-0.5, 3.0)
    assert bounds_of(changed, "acceleration") == (-4.0, 4.0)
    assert changed.angular_velocity is None
    assert bounds_of(limits, "velocity") == (-1.0, 1.0)  # unchanged
    assert bounds_of(limits, "angular_velocity") == (-2.0, 2.0)
    assert limits.acceleration is None
    with pytest.raises(InvalidInputError, match=r"wheel_speed limits must be > 0"):
        limits.replace(wheel_speed=-1.0)
    with pytest.raises(TypeError):
        limits.replace(jerk=1.0)


def test_frozen_and_equal_by_value():
    limits = MobileLimits(velocity=1.0)
    with pytest.raises(dataclasses.FrozenInstanceError):
        limits.velocity = None  # type: ignore[misc]
    assert limits.replace() == MobileLimits(velocity=1.0)
    assert limits != MobileLimits(velocity=2.0)


def test_repr_lists_the_given_limits():
    limits = MobileLimits(velocity=1.5, wheel_speed=(-2.0, 3.0))
    assert repr(limits) == "MobileLimits(velocity=(-1.5, 1.5), wheel_speed=(-2, 3))"


@given(
    st.sampled_from(ATTRIBUTES),
    st.floats(min_value=1e-6, max_value=1e6),
    st.floats(min_value=1e-6, max_value=1e6),
)
def test_magnitude_is_the_tighter_side(attribute, lower, upper):
    limits = MobileLimits(**{attribute: (-lower, upper)})
    assert limits.magnitude(attribute) == min(lower, upper)
    assert MobileLimits(**{attribute: upper}).magnitude(attribute) == upper
