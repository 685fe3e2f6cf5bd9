"""Docstring sections that several planners share, each written once.

A planner's docstring names a shared section by a line that holds only
``{name}``; :func:`with_sections` replaces that line with the section, indented as
the line is, when the module is imported. ``help()`` and ``__doc__`` then read the
whole text, as if it were written out. Braces inside a line (a choice such as
``{"switches", "duration"}``) are left alone.

Examples
--------
>>> from trajkit.profiles._docstrings import with_sections
>>> @with_sections
... def move(q0, qf):
...     '''A move.
...
...     Parameters
...     ----------
...     {positions}
...     '''
>>> print(move.__doc__.splitlines()[4])
    q0, qf : float or array_like, shape (ndof,)
"""

from __future__ import annotations

import re
import textwrap
from typing import TypeVar

__all__ = ["SECTIONS", "compose", "with_sections"]

T = TypeVar("T")

#: numpy-doc entries by name, each at the indentation of its section's entries.
SECTIONS: dict[str, str] = {
    # Parameters of the limit-driven state-to-state planners.
    "positions": """
        q0, qf : float or array_like, shape (ndof,)
            Start and target positions (rad, or m).
    """,
    "limits": """
        vmax, amax : float, sequence or tuple
            Velocity (rad/s) and acceleration (rad/s^2) limits: a number or one per
            joint for symmetric limits, a tuple ``(lower, upper)`` for asymmetric ones
            (``lower < 0 < upper``).
    """,
    "grid": """
        grid : {"switches", "duration"}
            With ``period``: ``"switches"`` puts every switching time (each phase a whole
            number of periods) and the duration on the grid, re-timing the phases so
            the target is still reached exactly within every limit; ``"duration"``
            only the duration (ruckig's discrete durations: every synchronized joint
            re-planned to take it).
    """,
    # Raises: what the jerk-limited planners refuse as malformed.
    "jerk_limited_invalid": """
        InvalidInputError
            NaN/inf, wrong shapes, limits that do not allow motion both ways,
            ``jmax <= 0``, an unknown sync mode.
    """,
    # How a batch planner reads the arguments of its single-problem planner.
    "batch_arguments": """
        Every argument has shape ``(B, ndof)`` or broadcasts to it: limits may be per
        joint ``(ndof,)``, per problem, or a ``(lower, upper)`` tuple of such arrays;
        ``min_duration`` is one number or one per problem.
    """,
}

_PLACEHOLDER = re.compile(r"^(?P<indent>[ \t]*)\{(?P<name>\w+)\}[ \t]*$", re.MULTILINE)


def compose(doc: str) -> str:
    """``doc`` with every placeholder line replaced by its section.

    Raises
    ------
    KeyError
        A placeholder names no section (at import, so a misspelt one never ships).
    """

    def section(match: re.Match[str]) -> str:
        name = match["name"]
        if name not in SECTIONS:
            raise KeyError(f"no shared docstring section {name!r} (known: {sorted(SECTIONS)})")
        return textwrap.indent(textwrap.dedent(SECTIONS[name]).strip("\n"), match["indent"])

    return _PLACEHOLDER.sub(section, doc)


def with_sections(documented: T) -> T:
    """Compose the shared sections into a function's or class's docstring; return it.

    Put it below any wrapping decorator, so that the wrapper copies the composed text.
    """
    documented.__doc__ = compose(documented.__doc__ or "")
    return documented
