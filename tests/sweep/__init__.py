"""Tests of trajkit.sweep: a package, since its module names repeat some in tests/."""
