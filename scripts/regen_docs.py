"""Rewrite the printed output of the runnable examples in README.md and docs/*.md.

Runs every ```console block as ``tests/test_docs.py`` does (a fresh folder with a copy of
``robots/``, ``ERD`` = example-robot-data's robots folder) and replaces each command's
documented output with what it printed now, whole (a command that should show less cuts its
own output, visibly: ``| head -n 12``). A command whose exit code differs from the page's
stops the script.

    python scripts/regen_docs.py              # every page
    python scripts/regen_docs.py README.md docs/check.md
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from support.doc_examples import ROOT, doc_files, regenerate  # noqa: E402


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("pages", nargs="*", type=Path, help="default: README.md, docs/*.md")
    parser.add_argument("--absolute-package-dirs", action="store_true",
                        help="run with relative --package-dir folders made absolute (the "
                             "pages keep them as written)")
    args = parser.parse_args(argv)
    pages = [p.resolve() for p in args.pages] or doc_files()
    for page in pages:
        count = regenerate(page, absolute_dirs=args.absolute_package_dirs)
        print(f"{page.relative_to(ROOT)}: {count} command(s) rerun")
    return 0


if __name__ == "__main__":
    sys.exit(main())
