#!/usr/bin/env bash
# The main job on the shipped robot: recompute the inertials of the paper's NM7MAR manipulator
# (robots/nm7mar.urdf) from its element/part decomposition (robots/nm7mar.inertia.toml),
# write out/nm7mar.fixed.urdf and show the per-link and per-element contributions, then
# break link 1 down part by part, as in section 5 of Szuminski & Kapitaniak (2006).
# Creates .venv with the package (no dev tools) when there is none.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ ! -x .venv/bin/urdf-inertia ]; then
    "${PYTHON:-python3}" -m venv .venv
    .venv/bin/python -m pip install --quiet -e .
fi
mkdir -p out
.venv/bin/urdf-inertia fix robots/nm7mar.urdf --spec robots/nm7mar.inertia.toml \
    -o out/nm7mar.fixed.urdf
echo
.venv/bin/urdf-inertia explain robots/nm7mar.urdf --link link1 --spec robots/nm7mar.inertia.toml
echo
echo "wrote out/nm7mar.fixed.urdf"
