"""Test configuration shared by the whole suite."""

from __future__ import annotations

import os

import matplotlib
from hypothesis import HealthCheck, settings

from trajkit.sim.engine import choose_gl_backend

# Plots render off screen, in CI and on a developer's machine alike.
matplotlib.use("Agg")
# So do MuJoCo's frames: its OpenGL backend is fixed when a test module first imports it.
choose_gl_backend()

# CI must be reproducible: the same examples every run. Locally, explore new ones.
settings.register_profile(
    "ci",
    max_examples=200,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow],
    print_blob=True,
)
settings.register_profile(
    "dev",
    max_examples=100,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
    print_blob=True,
)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci" if os.environ.get("CI") else "dev"))

if settings().derandomize:
    # Hypothesis also draws constants found in the modules loaded so far: under
    # pytest-xdist which tests a worker ran before decides them, and with them the
    # "same" examples. CI keeps its examples independent of the scheduling.
    try:
        from hypothesis.internal.conjecture import providers

        providers._get_local_constants = lambda: providers._local_constants
    except (ImportError, AttributeError):  # a Hypothesis without the feature
        pass
