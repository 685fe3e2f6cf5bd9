#!/usr/bin/env bash
# The whole test suite, as the README's quick start and CI run it: one source of truth.
set -euo pipefail
cd "$(dirname "$0")/.."
python -m pip install --quiet -e ".[test,sim,scale]"
# The same hypothesis examples on every run (tests/conftest.py's "ci" profile).
export HYPOTHESIS_PROFILE="${HYPOTHESIS_PROFILE:-ci}"
python -m pytest "$@"
