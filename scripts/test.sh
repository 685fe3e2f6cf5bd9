#!/usr/bin/env bash
# The whole test suite, as the README's quick start and CI run it: one source of truth.
set -euo pipefail
cd "$(dirname "$0")/.."
python -m pip install --quiet -e ".[test,sim,scale]"
# The same hypothesis examples on every run (tests/conftest.py's "ci" profile).
export HYPOTHESIS_PROFILE="${HYPOTHESIS_PROFILE:-ci}"
# Compile the profile engine once (minutes on a fresh clone); the test workers then
# load it from numba's cache instead of each compiling it again.
python -c "from trajkit.profiles import engine; print(f'engine ready in {engine.warm():.0f} s')"
python -m pytest -n auto "$@"
