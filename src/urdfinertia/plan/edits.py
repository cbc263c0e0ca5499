"""The text edits ``fix`` makes for the links whose slip it undoes (SARIF's ``fix`` objects).

An edit is what the writer gives for one link alone, every other byte kept, widened to
whole attribute values.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from urdfinertia.errors import UrdfInertiaError

if TYPE_CHECKING:
    from urdfinertia.descriptions.model import Robot
    from urdfinertia.plan.results import LinkResult


@dataclass(frozen=True)
class TextEdit:
    """One replacement in a description's text: lines and columns 1-based, columns in
    Unicode code points, the end exclusive (SARIF's ``deletedRegion`` and
    ``insertedContent``)."""

    start_line: int
    start_column: int
    end_line: int
    end_column: int
    text: str


def slip_text_edit(original: bytes, output: bytes) -> TextEdit | None:
    """The one span ``output`` differs from ``original`` in, widened to whole attribute
    values (from the quote before the first change to the quote after the last)."""
    if original == output:
        return None
    n = min(len(original), len(output))
    start = next((i for i in range(n) if original[i] != output[i]), n)
    tail = 0
    while tail < n - start and original[-1 - tail] == output[-1 - tail]:
        tail += 1
    while start > 0 and original[start - 1:start] not in (b'"', b"'"):
        start -= 1
    while tail > 0 and original[len(original) - tail:len(original) - tail + 1] not in (
            b'"', b"'"):
        tail -= 1
    end_old, end_new = len(original) - tail, len(output) - tail
    line, column = _position(original, start)
    end_line, end_column = _position(original, end_old)
    return TextEdit(line, column, end_line, end_column,
                    output[start:end_new].decode("utf-8", "replace"))


def _position(data: bytes, offset: int) -> tuple[int, int]:
    line = data.count(b"\n", 0, offset) + 1
    begin = data.rfind(b"\n", 0, offset) + 1
    return line, len(data[begin:offset].decode("utf-8", "replace")) + 1


def slip_fixes(robot: Robot, data: bytes, verdicts: Sequence[LinkResult],
               ) -> dict[str, TextEdit]:
    """The text edit ``fix`` makes for each link whose slip it undoes, by link name (SARIF's
    ``fix`` objects): what the writer gives for that link alone, every other byte kept."""
    from urdfinertia.descriptions.formats import NewInertial, format_of

    out = {}
    for r in verdicts:
        if r.slip is None or not r.changed or r.assembly is None:
            continue
        try:
            output = format_of(robot).patch(data, {r.name: NewInertial(
                r.assembly.total, r.size, frozenset(r.derived))})
        except UrdfInertiaError:
            continue
        edit = slip_text_edit(data, output)
        if edit is not None:
            out[r.name] = edit
    return out
