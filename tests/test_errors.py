"""One error for every missing optional dependency: MissingDependencyError."""

from __future__ import annotations

import pytest

import trajkit as tk
from trajkit.errors import MissingDependencyError, TrajkitError
from trajkit.io.ros2 import Ros2Unavailable
from trajkit.sim.engine import SimulationUnavailableError
from trajkit.sweep.store import ScaleUnavailableError, require
from trajkit.viz.animate import AnimationUnavailable


@pytest.mark.parametrize(
    "kind",
    [AnimationUnavailable, Ros2Unavailable, SimulationUnavailableError, ScaleUnavailableError],
)
def test_every_missing_dependency_is_one_catchable_error(kind: type) -> None:
    assert issubclass(kind, MissingDependencyError)
    assert issubclass(kind, TrajkitError)
    assert tk.MissingDependencyError is MissingDependencyError


def test_the_message_names_the_feature_the_package_and_the_install_command() -> None:
    error = MissingDependencyError.absent("physics simulation", "MuJoCo", "sim", "No module")
    assert str(error) == (
        "physics simulation: MuJoCo is not installed (No module); install it with: "
        'pip install "trajkit[sim]"'
    )
    assert error.install == 'pip install "trajkit[sim]"'
    bare = ScaleUnavailableError.absent("sweeps", "zarr", "scale")
    assert type(bare) is ScaleUnavailableError
    expected = 'sweeps: zarr is not installed; install it with: pip install "trajkit[scale]"'
    assert str(bare) == expected


def test_a_sweep_without_its_library_names_the_extra(monkeypatch: pytest.MonkeyPatch) -> None:
    import sys

    monkeypatch.setitem(sys.modules, "pyarrow.parquet", None)  # an import of it then fails
    with pytest.raises(ScaleUnavailableError, match=r'sweeps: pyarrow is not.*"trajkit\[scale\]"'):
        require("pyarrow.parquet")
