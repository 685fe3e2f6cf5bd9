"""The engine's kernels run as plain Python too (``NUMBA_DISABLE_JIT=1``), with the same plans.

The kernels are scalar Python compiled by numba; with the compiler disabled they
stay debuggable line by line. A subprocess plans a few ordinary moves of every law
that way, and the numbers must equal the compiled engine's here.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys

import numpy as np

# Plans of every law through the public API, and the numbers compared.
CASES = r"""
import numpy as np
import trajkit as tk
import trajkit.batch

def cases():
    scurve = tk.scurve([0.0, 0.5, -1.0], [1.0, -0.5, 2.0], 1.0, (-2.0, 3.0), 10.0,
                       v0=[0.2, 0.0, -0.3], a0=[0.0, 0.5, 0.0], sync="time")
    phase = tk.scurve([0.0, 0.0], [1.0, 2.0], 1.0, 2.0, 10.0, sync="phase")
    trapezoid = tk.trapezoidal([0.0, 0.0], [1.0, -3.0], 1.0, 2.0, v0=[0.5, 0.0], vf=[0.0, -0.5])
    beyond = tk.scurve([0.0], [1.0], 1.0, 2.0, 10.0, v0=[1.5])
    grid = tk.trapezoidal([0.0, 0.0], [1.0, 2.0], 1.0, 1.0, period=0.01)
    batch = trajkit.batch.scurve([[0.0, 0.0], [0.5, -0.5]], [[1.0, 2.0], [-1.0, 0.0]],
                                 1.0, 2.0, 8.0)
    generator = tk.online.Generator(2, 0.01, 1.0, 2.0, 10.0)
    for _ in range(5):
        state, _ = generator.update([1.0, -1.0])
    t = np.linspace(0.0, scurve.duration, 7)
    return {
        "scurve": [scurve.duration, *scurve.position(t).ravel(), *scurve.velocity(t).ravel()],
        "phase": [phase.duration, *phase.position(np.linspace(0, phase.duration, 5)).ravel()],
        "trapezoid": [trapezoid.duration, *np.ravel(trapezoid.info["phase_times"])],
        "beyond": [beyond.duration, *beyond.velocity([0.0, 0.1, beyond.duration]).ravel()],
        "grid": [grid.duration, *np.ravel(grid.info["phase_times"])],
        "batch": [float(d) for d in batch.durations],
        "online": [*state.position, *state.velocity, *state.acceleration],
    }
"""


def numbers() -> dict[str, list[float]]:
    namespace: dict = {}
    exec(CASES, namespace)
    return {k: [float(x) for x in v] for k, v in namespace["cases"]().items()}


def test_the_kernels_run_as_plain_python_with_the_same_plans() -> None:
    script = (
        "import json, sys, numba\n"
        "assert numba.config.DISABLE_JIT\n"
        "sys.path.insert(0, sys.argv[1])\n"
        "from test_engine_without_jit import numbers\n"
        "json.dump(numbers(), sys.stdout)\n"
    )
    done = subprocess.run(
        [sys.executable, "-W", "ignore", "-c", script, os.path.dirname(__file__)],
        env={**os.environ, "NUMBA_DISABLE_JIT": "1"},
        capture_output=True,
        text=True,
        timeout=600,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    plain, compiled = json.loads(done.stdout), numbers()
    assert plain.keys() == compiled.keys()
    for name in compiled:
        # The same operations, compiled or not: equal but for the fused
        # multiply-adds and the like the compiler may choose.
        np.testing.assert_allclose(plain[name], compiled[name], rtol=1e-12, atol=1e-12,
                                   err_msg=name)  # fmt: skip
