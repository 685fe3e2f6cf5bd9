"""Tests of trajkit.sim: a package, like tests/mobile, so its module names never clash."""
