"""Field offsets of a one-axis profile record (a float64 vector of ``SIZE``).

A profile is up to two brake phases followed by seven phases of constant jerk.
Numba sees the offsets as compile-time integers. The codes (control signs,
reached limits, direction) are int64 values instead: as literals each would
compile its own copy of every function it is passed to.
"""

import numpy as np

# Seven main phases: durations, running sums, jerks; states at the 8 phase edges.
T = 0  # t[7], s
T_SUM = 7  # t_sum[7], s
J = 14  # j[7]
A = 21  # a[8]
V = 29  # v[8]
P = 37  # p[8]
# Target state.
PF = 45
VF = 46
AF = 47
# Classification (stored as floats): which limits are reached, jerk signs, direction.
LIMITS = 48
SIGNS = 49
DIRECTION = 50
# Brake pre-profile: total duration, then two phases' duration, jerk and start state.
BRAKE_DURATION = 51
BRAKE_T = 52  # [2]
BRAKE_J = 54  # [2]
BRAKE_A = 56  # [2]
BRAKE_V = 58  # [2]
BRAKE_P = 60  # [2]
SIZE = 64

# ControlSigns: jerk pattern of the seven phases.
UDDU = np.int64(0)  # +j, 0, -j, 0, -j, 0, +j
UDUD = np.int64(1)  # +j, 0, -j, 0, +j, 0, -j

# ReachedLimits.
ACC0_ACC1_VEL = np.int64(0)
VEL = np.int64(1)
ACC0 = np.int64(2)
ACC1 = np.int64(3)
ACC0_ACC1 = np.int64(4)
ACC0_VEL = np.int64(5)
ACC1_VEL = np.int64(6)
NONE = np.int64(7)

# Direction.
UP = np.int64(0)
DOWN = np.int64(1)
