"""Where a finding is in its file: line and column of the offending element's start tag.

lxml gives an element's ``sourceline`` only, and that is the line where the start tag
*ends* (``<link`` on one line and ``name="x">`` on the next gives the second). Code
scanning and editors want the start of the tag, so the tag is found in the document's
bytes: a link's ``<link name="X"`` (or ``<body name="X"`` / ``<model name="X"`` of the
other formats), then the first ``<inertial`` inside it. The model's line is the fallback
when the text cannot be matched (a name written with entities, a generated document).
Lines and columns are 1-based; a column counts Unicode code points (SARIF
``unicodeCodePoints``).
"""

from __future__ import annotations

import bisect
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

from urdfinertia.descriptions.model import Robot
from urdfinertia.findings import Finding
from urdfinertia.plan.edits import TextEdit
from urdfinertia.plan.results import LinkResult

#: Element names that carry a link's name in the registered formats (URDF/SDF ``link``,
#: MJCF ``body``).
_LINK_TAGS = (b"link", b"body")
_HIDDEN = re.compile(rb"<!--.*?-->|<!\[CDATA\[.*?\]\]>", re.S)
_NOT_NEWLINE = re.compile(rb"[^\n]")


@dataclass(frozen=True)
class Location:
    line: int
    column: int


@dataclass(frozen=True)
class CheckedFile:
    """One checked file: its findings, each one's location and whether a baseline knows it."""

    path: Path
    robot: Robot
    findings: list[Finding]
    locations: list[Location]
    known: list[bool]
    #: links some of whose geometry could not be read (not verified)
    unverified: frozenset[str] = frozenset()
    #: every link's verdict (what ``fix`` would do), when the geometry was read
    verdicts: tuple[LinkResult, ...] = ()
    #: the text edit that undoes a link's slip, by link (SARIF ``fixes``)
    fixes: Mapping[str, TextEdit] = field(default_factory=dict)

    def decision_of(self, link: str | None) -> str | None:
        """What ``fix`` would do with ``link``, in the words every command uses."""
        for r in self.verdicts:
            if r.name == link:
                return r.planned
        return None

    def keeps(self, finding: Finding) -> bool:
        """``fix`` keeps the value ``finding`` is about on purpose (it says why)."""
        for r in self.verdicts:
            if r.name == finding.link:
                return r.keeps(finding)
        return finding.severity == "info"

    @property
    def new(self) -> list[Finding]:
        return [f for f, k in zip(self.findings, self.known, strict=True) if not k]


class Locator:
    """Finds the start tags of one document's elements (the document is scanned lazily)."""

    def __init__(self, robot: Robot, data: bytes) -> None:
        self.robot = robot
        self.data = data
        self._line_starts: list[int] | None = None
        self._masked: bytes | None = None

    @property
    def text(self) -> bytes:
        """The document with comments and CDATA blanked (same offsets, newlines kept), so a
        commented-out ``<link name="x">`` is never taken for the element."""
        if self._masked is None:
            self._masked = _HIDDEN.sub(lambda m: _NOT_NEWLINE.sub(b" ", m.group()), self.data)
        return self._masked

    def locate(self, finding: Finding) -> Location:
        if finding.line is not None:  # the finding knows its element's line (a reader problem)
            return self._first_tag_on(finding.line)
        element = finding.rule.scope.value
        link = None
        if finding.link is not None:
            try:
                link = self.robot.link(finding.link)
            except KeyError:
                link = None
        if link is None:
            return self._root()
        start = self._link_start(link.name)
        if element == "inertial" and start is not None:
            inertial = self._inertial_start(start)
            if inertial is not None:
                return self._at(inertial)
        if start is not None:
            return self._at(start)
        line = (link.inertial.line if element == "inertial" and link.inertial is not None
                else None) or link.line
        return Location(line or 1, 1)

    def _first_tag_on(self, line: int) -> Location:
        """The first start tag on ``line`` (its column), or the line's start."""
        if self._line_starts is None:
            self._at(0)
        starts = self._line_starts or [0]
        if not 1 <= line <= len(starts):
            return Location(line, 1)
        begin = starts[line - 1]
        end = starts[line] if line < len(starts) else len(self.text)
        found = re.compile(rb"<(?![/?!])").search(self.text, begin, end)
        return self._at(found.start()) if found else Location(line, 1)

    def _root(self) -> Location:
        found = re.search(rb"<(?![?!])", self.text)
        return self._at(found.start()) if found else Location(1, 1)

    def _link_start(self, name: str) -> int | None:
        quoted = re.escape(name.encode("utf-8"))
        tags = b"|".join(_LINK_TAGS)
        pattern = (rb"<(?:" + tags + rb")\b[^>]*?\bname\s*=\s*(?:\"" + quoted + rb"\"|'"
                   + quoted + rb"')")
        found = re.search(pattern, self.text)
        return found.start() if found else None

    def _inertial_start(self, link_start: int) -> int | None:
        # the first <inertial before the element closes (or a sibling link begins)
        end = re.compile(rb"</(?:link|body)\s*>|<(?:link|body)\b")
        stop = end.search(self.text, link_start + 1)
        found = re.compile(rb"<inertial\b").search(
            self.text, link_start, stop.start() if stop else len(self.text))
        return found.start() if found else None

    def _at(self, offset: int) -> Location:
        if self._line_starts is None:
            self._line_starts = [0] + [m.end() for m in re.finditer(rb"\n", self.data)]
        starts = self._line_starts
        lo = bisect.bisect_right(starts, offset) - 1
        prefix = self.data[starts[lo]:offset].decode("utf-8", errors="replace")
        return Location(lo + 1, len(prefix) + 1)


def locate_all(robot: Robot, data: bytes, findings: list[Finding]) -> list[Location]:
    locator = Locator(robot, data)
    return [locator.locate(f) for f in findings]
