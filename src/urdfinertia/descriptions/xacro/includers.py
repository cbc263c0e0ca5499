"""The robots a xacro include belongs to: what to check when only a macro file changed.

A xacro file of macros (``arm.xacro`` with ``<xacro:macro name="arm">``) expands to a
``<robot>`` with no links: checking it alone checks nothing. :func:`checked_through`
replaces such a file by the top-level xacro files under a folder (the repository) that
include it, directly or through other includes, so that a pre-commit hook or CI job handed
the changed file checks the robots that change with it.

The includers are found in two steps: candidates by name (a file whose text names the
include's file name, or the name of a file that does, and so on: cheap, and it finds
``$(find pkg)/urdf/arm.xacro`` and ``package://pkg/urdf/arm.xacro`` alike), then each
candidate expanded with the run's xacro settings (:mod:`.settings`), and kept when the
expansion read the include and has links of its own. Of the candidates kept, those that
another kept one includes are dropped: the top-level robots remain.
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path

from urdfinertia.descriptions.xml import MAX_DOCUMENT_BYTES
from urdfinertia.errors import UrdfInertiaError

#: Folders never searched for includers (version control, build trees, dependencies).
SKIPPED_FOLDERS = frozenset({".git", ".hg", ".svn", "node_modules", "build", "install",
                             "log", "__pycache__", ".venv", "venv", ".tox"})
#: Suffixes of the files searched: xacro files, and URDF files that may use xacro.
SEARCHED_SUFFIXES = (".xacro", ".urdf")


@dataclass(frozen=True)
class Replacement:
    """A file given that has no links of its own and the robots checked instead."""

    include: Path
    robots: tuple[Path, ...]


def link_count(path: Path) -> int | None:
    """Links of the description at ``path`` as expanded, or None when it cannot be read
    on its own (a macro file that needs its includer's properties or arguments)."""
    from urdfinertia.descriptions.formats import read_bytes, robot_from_bytes

    try:
        return len(robot_from_bytes(read_bytes(path), path).links)
    except UrdfInertiaError:
        return None


def is_xacro(path: Path) -> bool:
    """Whether ``path`` is read as xacro (by suffix, or a ``<robot>`` using xacro)."""
    if path.suffix.lower() == ".xacro":
        return True
    from urdfinertia.descriptions.xacro import claims

    try:
        with open(path, "rb") as fh:
            return claims(fh.read(1 << 16), path)
    except OSError:
        return False


def candidate_files(root: Path) -> Iterator[Path]:
    """The xacro and URDF files under ``root`` (sorted, skipped folders left out)."""
    for folder, dirs, files in os.walk(root):
        dirs[:] = sorted(d for d in dirs if d not in SKIPPED_FOLDERS and not d.startswith("."))
        for name in sorted(files):
            if name.lower().endswith(SEARCHED_SUFFIXES):
                yield Path(folder) / name


def _text(path: Path) -> bytes:
    try:
        with open(path, "rb") as fh:
            return fh.read(MAX_DOCUMENT_BYTES)
    except OSError:
        return b""


def _names_pattern(names: Iterable[str]) -> re.Pattern[bytes]:
    """A file name as written in an include: after a separator, quote or the start."""
    alternatives = b"|".join(re.escape(n.encode()) for n in sorted(names))
    return re.compile(rb"(?:^|[/\\\"'=\s])(?:" + alternatives + rb")(?=[\"'\s<]|$)", re.M)


def includers(include: Path, root: Path) -> list[Path]:
    """The top-level robots under ``root`` whose expansion reads ``include``.

    Each is a file other than ``include`` that expands (with the run's xacro settings) to
    a robot with links, read ``include`` while expanding, and is not itself read by
    another such robot. Sorted by path.
    """
    from urdfinertia.descriptions.formats import read_bytes
    from urdfinertia.descriptions.xacro import expansion

    target = os.path.realpath(include)
    texts = {p: _text(p) for p in candidate_files(root)}
    names = {include.name}
    linked: set[Path] = set()
    while True:  # every file naming a named file, until no new name appears
        pattern = _names_pattern(names)
        found = {p for p, text in texts.items() if p not in linked and pattern.search(text)}
        if not found:
            break
        linked |= found
        names |= {p.name for p in found}
    robots: dict[Path, frozenset[str]] = {}
    for path in sorted(linked):
        if os.path.realpath(path) == target or not is_xacro(path):
            continue
        try:
            exp = expansion(read_bytes(path), path)
        except UrdfInertiaError:
            continue  # needs arguments it was not given, or broken: not a robot to check
        sources = frozenset(os.path.realpath(s) for s in exp.sources[1:])
        if target in sources and (link_count(path) or 0) > 0:
            robots[path] = sources
    read_by_others = set().union(*robots.values()) if robots else set()
    return [p for p in robots if os.path.realpath(p) not in read_by_others]


def checked_through(paths: Sequence[Path], root: Path,
                    ) -> tuple[list[Path], list[Replacement]]:
    """``paths`` with every xacro file that has no links of its own (or cannot be read on
    its own) replaced by its top-level includers under ``root``; duplicates dropped.

    A file no robot includes stays itself (checking it says what is wrong). Returns the
    paths to check, in order, and the replacements made.
    """
    out: dict[Path, None] = {}
    done: list[Replacement] = []
    for path in paths:
        if is_xacro(path) and not link_count(path):
            robots = tuple(_as_given(r, path) for r in includers(path, root))
            if robots:
                done.append(Replacement(path, robots))
                out.update(dict.fromkeys(robots))
                continue
        out[path] = None
    return list(out), done


def _as_given(robot: Path, given: Path) -> Path:
    """``robot`` relative to the working directory when ``given`` was (as a hook passes
    paths), so that messages and baselines name it the same way."""
    if given.is_absolute():
        return robot
    try:
        return Path(os.path.relpath(robot))
    except ValueError:  # another drive
        return robot
