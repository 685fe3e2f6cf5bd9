"""The engine's one line on stderr: said while compiling, not while a long call runs."""

from __future__ import annotations

import time

import pytest

from trajkit.profiles import engine


class _Kernel:
    """Stands in for a numba dispatcher: ``compile`` and the call take given times."""

    def __init__(self, compiling: float, running: float) -> None:
        self.compiling, self.running = compiling, running

    def compile(self, signature: tuple) -> None:
        time.sleep(self.compiling)

    def __call__(self, *args: object) -> str:
        time.sleep(self.running)
        return "done"


@pytest.fixture
def fresh(monkeypatch):
    monkeypatch.setattr(engine, "_ANNOUNCE_AFTER", 0.05)
    monkeypatch.setattr(engine, "_announced", False)
    monkeypatch.setattr(engine, "_warm", set())


def test_a_slow_compilation_is_announced_once(fresh, capsys):
    assert engine.run("slow_compile", _Kernel(0.3, 0.0), 1.0) == "done"
    assert engine.run("slow_compile_2", _Kernel(0.3, 0.0), 1.0) == "done"
    err = capsys.readouterr().err
    assert err.count("trajkit: compiling the profile engine") == 1


def test_a_long_first_call_that_compiles_fast_says_nothing(fresh, capsys):
    assert engine.run("long_call", _Kernel(0.0, 0.3), 1.0) == "done"
    assert capsys.readouterr().err == ""
    assert engine._compile_times["long_call"] < 0.3
