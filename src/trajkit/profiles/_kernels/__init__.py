"""The compiled profile engine: every one-axis law as scalar code compiled by numba.

Importing this package imports numba (slow): planners import it inside their
functions, so ``import trajkit`` stays fast. Modules:

* :mod:`.layout` — where each field of a one-axis profile record lives;
* :mod:`.profile` — checking a candidate profile and integrating its states;
* :mod:`.roots` — closed-form and bracketed polynomial roots;
* :mod:`.brake` — the pre-profile that brings a state beyond the limits back;
* :mod:`.jerk_fastest`, :mod:`.jerk_timed` — jerk-limited position moves, fastest
  and of a given duration;
* :mod:`.acceleration_limited` — the same for ``jmax = inf`` (trapezoids);
* :mod:`.velocity_target` — reaching a velocity and acceleration, no position;
* :mod:`.block` — a joint's minimum duration and the durations it cannot take;
* :mod:`.synchronize` — several joints (and batches of problems) to a common end.

The mathematics follows Berscheid and Kröger, "Jerk-limited Real-time Trajectory
Generation with Arbitrary Target States" (RSS 2021), whose reference
implementation (ruckig) serves as the test oracle.
"""

import os

import numba

# numba's default OpenMP layer dies in a process forked after it ran (the sweep's
# worker pool forks); the workqueue layer does not. A user's own choice (the
# environment variable) stands. Set on numba's config, not the environment: numba
# may have been imported before, and it reads the layer at the first parallel call.
if "NUMBA_THREADING_LAYER" not in os.environ:
    numba.config.THREADING_LAYER = "workqueue"
