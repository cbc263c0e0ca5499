#!/usr/bin/env bash
# The GitHub Action's check step (action.yml runs exactly this; tests/ci runs it too).
# Inputs come as environment variables, as the action passes them:
#   INPUT_PATHS     files, folders (searched for *.urdf *.xacro *.sdf *.xml *.usd *.usda
#                   *.usdc *.usdz) or globs;
#                   whitespace-separated (default: .)
#   INPUT_OPTIONS   more `urdf-inertia check` options, e.g. "--strict --engines mujoco"
#   INPUT_BASELINE  a baseline file: findings recorded there do not fail the run
#   INPUT_SARIF     where the SARIF log goes (default: urdf-inertia.sarif)
#   URDF_INERTIA    the command to run (default: urdf-inertia)
# Prints GitHub annotations; writes sarif=PATH and exit-code=N to $GITHUB_OUTPUT when set;
# exits with check's code (0 clean or only known findings, 1 new findings, 2 bad input).
set -uo pipefail
shopt -s nullglob globstar

paths=${INPUT_PATHS:-.}
sarif=${INPUT_SARIF:-urdf-inertia.sarif}
read -r -a command <<< "${URDF_INERTIA:-urdf-inertia}"
read -r -a options <<< "${INPUT_OPTIONS:-}"

files=()
for pattern in $paths; do
  for item in $pattern; do  # a glob expands here; a plain name stays itself
    if [ -d "$item" ]; then
      while IFS= read -r -d '' f; do files+=("$f"); done < <(
        find "$item" -type d \( -name .git -o -name node_modules \) -prune -o -type f \
          \( -name '*.urdf' -o -name '*.xacro' -o -name '*.sdf' -o -name '*.xml' \
             -o -name '*.usd' -o -name '*.usda' -o -name '*.usdc' -o -name '*.usdz' \) \
          -print0 | sort -z)
    else
      files+=("$item")
    fi
  done
done
if [ ${#files[@]} -eq 0 ]; then
  echo "::error title=urdf-inertia::no description files found in: $paths"
  exit 2
fi

baseline=()
if [ -n "${INPUT_BASELINE:-}" ]; then baseline=(--baseline "$INPUT_BASELINE"); fi

# files found in folders include every *.xml: only those a registered format takes are read;
# a xacro macro file is checked through the robots that include it (--includers)
"${command[@]}" check "${files[@]}" --skip-unknown-formats --includers --format github \
  --sarif "$sarif" "${baseline[@]}" "${options[@]}"
code=$?
if [ -n "${GITHUB_OUTPUT:-}" ]; then
  { echo "sarif=$sarif"; echo "exit-code=$code"; } >> "$GITHUB_OUTPUT"
fi
exit "$code"
