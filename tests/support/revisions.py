"""Source trees of other git revisions, for scripts that compare two revisions' results."""

from __future__ import annotations

import contextlib
import subprocess
import tempfile
from collections.abc import Iterator, Mapping
from pathlib import Path


@contextlib.contextmanager
def revision_sources(root: Path, refs: Mapping[str, str | None]) -> Iterator[dict[str, Path]]:
    """The ``src`` folder of each revision of ``refs`` (tag -> git revision; None: this
    checkout's own), each checked out in a temporary git worktree removed on exit."""
    with tempfile.TemporaryDirectory(prefix="urdfinertia-revisions-") as tmp:
        trees: dict[str, Path] = {}
        made: list[Path] = []
        try:
            for tag, ref in refs.items():
                if ref is None:
                    trees[tag] = root / "src"
                    continue
                wt = Path(tmp) / tag
                subprocess.run(["git", "-C", str(root), "worktree", "add", "--detach", "-q",
                                str(wt), ref], check=True, capture_output=True)
                made.append(wt)
                trees[tag] = wt / "src"
            yield trees
        finally:
            for wt in made:
                subprocess.run(["git", "-C", str(root), "worktree", "remove", "--force",
                                str(wt)], check=False, capture_output=True)
