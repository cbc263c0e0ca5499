"""What a ``fix`` run tells the user it did: the exit code and the per-problem lines.

The one home of ``fix``'s exit codes (the batch summary sums them up the same way):

====  ==================================================================================
0     every link that should be computed was (elements read past are warnings)
1     the output was written, but some links were left exactly as they were (listed),
      or could not be verified (a mesh unresolved or unreadable: as ``check``)
2     nothing written: the file cannot be read as a whole, a security refusal, a bad
      option, or with ``--strict`` any element dropped, value ignored or link left
====  ==================================================================================
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from urdfinertia.plan.results import FixResult

EXIT_OK = 0
EXIT_PARTIAL = 1
EXIT_NOTHING_WRITTEN = 2


def fix_exit_code(links_left: int, links_unverified: int = 0) -> int:
    """1 (`EXIT_PARTIAL`) when a link was left as it was or could not be verified."""
    return EXIT_PARTIAL if links_left or links_unverified else EXIT_OK


def unverified_line(result: FixResult) -> str | None:
    """The one line of what could not be verified ("not verified: 1 mesh unresolved or
    unreadable in 1 link"), or None (``check`` says the same)."""
    from urdfinertia.render.decisions import unverified_summary

    return unverified_summary(result.links)


def left_lines(result: FixResult) -> list[str]:
    """One line per link left as it was: ``file:line: link 'x': reason``."""
    return [str(result.left_error(r)) for r in result.left]


def problem_lines(result: FixResult) -> list[str]:
    """One line per thing read past (:func:`urdfinertia.render.decisions.problem_lines`)."""
    from urdfinertia.render.decisions import problem_lines as lines

    return lines(result)
