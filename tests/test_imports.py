"""`import trajkit` and `trajkit --help` stay light: no heavy library is imported.

scipy, matplotlib, numba and MuJoCo take from a tenth of a second to seconds to
import; each is imported by the function that needs it, on first use.
"""

from __future__ import annotations

import subprocess
import sys

import pytest

HEAVY = ("scipy", "matplotlib", "numba", "mujoco")

_IMPORT = "import trajkit"
_HELP = """
import trajkit.cli
try:
    trajkit.cli.main(["--help"])
except SystemExit:
    pass
"""


@pytest.mark.parametrize("code", [_IMPORT, _HELP], ids=["import trajkit", "trajkit --help"])
def test_no_heavy_library_is_imported(code: str) -> None:
    probe = f"{code}\nimport sys\nprint('imported:', *(m for m in {HEAVY!r} if m in sys.modules))"
    result = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert result.stdout.splitlines()[-1] == "imported:", result.stdout
