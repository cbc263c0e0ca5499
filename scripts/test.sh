#!/usr/bin/env bash
# Run the test suite: creates .venv and installs everything it needs on first use.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup_venv.sh
.venv/bin/ruff check src tests scripts
# the layout's rules ([tool.importlinter] in pyproject.toml) and the type hints
.venv/bin/lint-imports --no-cache
.venv/bin/mypy
# the report's browser tests need Debian's chromium + chromedriver; installing them here,
# once, avoids two test workers racing for apt's lock (the tests skip only if this fails)
bash scripts/install_chromium.sh || echo "warning: chromium could not be installed" >&2
# the documentation site: broken links, anchors and API references fail the build
NO_MKDOCS_2_WARNING=1 .venv/bin/mkdocs build --strict --quiet --site-dir "$(mktemp -d)"
# Drake (pydrake, in the dev extra) reads our SDFormat output: a missing Drake fails, not skips
export URDFINERTIA_REQUIRE_DRAKE=1
set +e
.venv/bin/python -m pytest -n 2 -q "$@"
rc=$?
set -e
# pytest exits 5 when no test was collected: that is a failure of this script's purpose.
if [ "$rc" -eq 5 ]; then echo "no tests were collected" >&2; exit 1; fi
exit "$rc"
