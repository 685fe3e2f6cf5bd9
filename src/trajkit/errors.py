"""Exceptions and warnings raised by trajkit.

Every error trajkit raises on purpose derives from :class:`TrajkitError`, so a
caller can catch them all at once; the command-line tool turns them into one line
on stderr and exit status 2.
"""

from __future__ import annotations

__all__ = [
    "ContinuityWarning",
    "InfeasibleError",
    "InvalidInputError",
    "MissingDependencyError",
    "TrajkitError",
    "UnreachableError",
]


class TrajkitError(Exception):
    """Base class of every error trajkit raises on purpose."""


class InvalidInputError(TrajkitError, ValueError):
    """An argument is malformed: NaN or inf, wrong shape, wrong sign, unsorted times.

    The message names the argument, the offending value and the rule it breaks.
    """


class InfeasibleError(TrajkitError):
    """The request is well formed but cannot be met under the given limits.

    The message names the parameter, its value and the bound that rules it out,
    e.g. ``duration 1.0 s is below the minimum 1.147 s set by vmax=0.5236 rad/s``.
    """


class UnreachableError(TrajkitError):
    """A pose or point lies outside a robot's workspace.

    ``index`` is the position of the first unreachable target in a batch, when known.
    """

    def __init__(self, message: str, *, index: int | None = None) -> None:
        super().__init__(message)
        self.index = index


class MissingDependencyError(TrajkitError):
    """An optional library (or program) a feature needs is not installed or cannot load.

    Every such refusal is one of these (the simulator, sweeps, ROS 2 bags, URDF,
    MP4 animations each have a subclass), so ``except MissingDependencyError``
    catches them all; ``install`` is what makes the feature work (a ``pip install``
    of trajkit's extra, a system package), None where nothing can be installed.
    """

    def __init__(self, message: str, *, install: str | None = None) -> None:
        super().__init__(message)
        self.install = install

    @classmethod
    def absent(
        cls, feature: str, package: str, extra: str, reason: object = None
    ) -> MissingDependencyError:
        """The error for ``feature`` when ``package``, from trajkit's ``extra``, is absent."""
        install = f'pip install "trajkit[{extra}]"'
        detail = f" ({reason})" if reason else ""
        return cls(
            f"{feature}: {package} is not installed{detail}; install it with: {install}",
            install=install,
        )


class ContinuityWarning(UserWarning):
    """Two trajectories were joined with a jump in velocity or acceleration."""
