"""Tests of trajkit.mobile: a package, since its module names repeat some in tests/."""
