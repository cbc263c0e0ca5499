"""One answer on a hand-gathered corpus: ``fix`` and ``check`` agree link by link, and
``check --strict`` of what ``fix`` wrote, per file.

The corpus is a folder with a ``manifest.json`` (as ``scripts/changed_links.py`` reads it:
entries with ``file``, ``package`` and ``package_dirs``, paths relative to the folder).
Prints one line per file: the links on which ``fix`` and ``check`` disagree (action or
reason), and the findings that fail ``check --strict`` of the output, with their cause.

Usage: ``python scripts/strict_after_fix.py CORPUS``
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path


def main(argv: list[str] | None = None) -> int:
    import urdfinertia
    from urdfinertia.analysis.check import check_description
    from urdfinertia.cache.library import MeshLibrary
    from urdfinertia.descriptions.formats import robot_from_bytes

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("corpus", type=Path)
    args = ap.parse_args(argv)
    root = args.corpus
    problems = 0
    for e in json.loads((root / "manifest.json").read_text()):
        dirs = {k: str(root / v) for k, v in (e.get("package_dirs") or {}).items()}
        path = root / e["file"]
        fixed = urdfinertia.fix(str(path), package_dirs=dirs)
        checked = urdfinertia.check(str(path), package_dirs=dirs)
        disagree = [a.name for a, b in zip(fixed.links, checked.links, strict=True)
                    if a.action != b.action or a.why != b.why]
        after = check_description(robot_from_bytes(fixed.output, path),
                                  meshes=MeshLibrary(dirs))
        failing = after.failing(strict=True)
        causes = sorted({f.rule.value for f in failing})
        print(f"{e['file']}: fix/check disagree on {len(disagree)} link(s)"
              f"{' (' + ', '.join(disagree) + ')' if disagree else ''}; check --strict of "
              f"the output: exit {after.exit_code(strict=True)}"
              f"{', failing on ' + ', '.join(causes) if causes else ''}", flush=True)
        problems += bool(disagree)
    print(f"files where fix and check disagree: {problems}")
    return 1 if problems else 0


if __name__ == "__main__":
    raise SystemExit(main())
