"""Keywords that were renamed: the old name still works for a while, with a warning.

``dt`` used to name both the controller period and the sampling step; they are now
``period`` and ``sample_step`` (``ik_step`` for a task's inverse-kinematics step).
"""

from __future__ import annotations

import functools
import warnings
from collections.abc import Callable
from typing import Any, TypeVar

from trajkit.errors import InvalidInputError

__all__ = ["renamed_keywords"]

F = TypeVar("F", bound=Callable[..., Any])


def renamed_keywords(**new_names: str) -> Callable[[F], F]:
    """Accept each old keyword (``old="new"``) as the new one, with a FutureWarning.

    Giving both the old and the new name is refused: which one was meant is unknown.
    """

    def wrap(function: F) -> F:
        # Generator(...) rather than __init__(...): the name a user calls.
        where = function.__qualname__.removesuffix(".__init__")

        @functools.wraps(function)
        def accepting_old_names(*args: Any, **kwargs: Any) -> Any:
            for old, new in new_names.items():
                if old in kwargs:
                    if new in kwargs:
                        raise InvalidInputError(f"give {new}= only: {old}= is its old name")
                    warnings.warn(
                        f"{where}: {old}= is renamed {new}=; the old name will be removed",
                        FutureWarning,
                        stacklevel=2,
                    )
                    kwargs[new] = kwargs.pop(old)
            return function(*args, **kwargs)

        return accepting_old_names  # type: ignore[return-value]

    return wrap
