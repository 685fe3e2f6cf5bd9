"""Shared docstring sections: composed in whole, so help() reads as if written out."""

from __future__ import annotations

import inspect
import pydoc
import re

import pytest

import trajkit as tk
from trajkit import batch, online
from trajkit.profiles._docstrings import SECTIONS, compose, with_sections

COMPOSED = [
    tk.scurve,
    tk.trapezoidal,
    tk.velocity_change,
    batch.scurve,
    batch.trapezoidal,
    batch.velocity_change,
    online.Generator,
]


@pytest.mark.parametrize("documented", COMPOSED, ids=lambda f: f.__qualname__)
def test_no_placeholder_is_left_in_a_public_docstring(documented):
    doc = documented.__doc__
    assert not re.search(r"^\s*\{\w+\}\s*$", doc, re.MULTILINE), doc
    # help() shows the composed text, through the wrapper that renames dt= too.
    shown = pydoc.render_doc(documented, renderer=pydoc.plaintext)
    assert all(line.strip() in shown for line in inspect.getdoc(documented).splitlines())


def test_a_section_takes_the_indentation_of_its_placeholder():
    doc = compose("Summary.\n\n    Parameters\n    ----------\n    {positions}\n    jmax : float\n")
    assert doc == (
        "Summary.\n\n    Parameters\n    ----------\n"
        "    q0, qf : float or array_like, shape (ndof,)\n"
        "        Start and target positions (rad, or m).\n"
        "    jmax : float\n"
    )


def test_braces_inside_a_line_are_text():
    assert '{"switches", "duration"}' in tk.scurve.__doc__
    assert compose('    grid : {"a", "b"}\n    x {positions} y\n') == (
        '    grid : {"a", "b"}\n    x {positions} y\n'
    )


def test_a_misspelt_section_is_refused_at_definition():
    with pytest.raises(KeyError, match="positons"):

        @with_sections
        def move() -> None:
            """A move.

            {positons}
            """


def test_every_section_is_used():
    composed = "".join(f.__doc__ for f in COMPOSED)
    for name, text in SECTIONS.items():
        first = text.strip().splitlines()[0].strip()
        assert first in composed, name
