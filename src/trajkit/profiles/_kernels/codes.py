"""Codes the kernels share: control interfaces, synchronization modes, plan status.

Plain integers (numba sees them as compile-time constants).
"""

# Control interface of a joint.
POSITION = 0
VELOCITY = 1

# Synchronization of a joint.
SYNC_TIME = 0
SYNC_PHASE = 1
SYNC_TIME_IF_NECESSARY = 2
SYNC_NONE = 3

# Status codes of a plan; the failing joint is reported beside them.
OK = 0
STEP1_FAILED = 1  # no profile for this joint alone (numerical failure)
ZERO_LIMITS = 2  # a zero limit makes the joint's move impossible
SYNC_FAILED = 3  # no common duration every joint can take
STEP2_FAILED = 4  # a joint could not take the common duration

# Fields of the per-problem summary a plan writes.
OUT_DURATION = 0
OUT_LIMITING = 1  # joint index, -1 where min_duration set the duration
OUT_PHASE = 2  # 1 if phase synchronization held, 0 if it fell back to time sync
OUT_JOINT = 3  # the joint a failure is about, -1 otherwise
OUT_SIZE = 4
