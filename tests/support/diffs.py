"""Assert that two URDF documents differ only inside <inertial> elements."""

from __future__ import annotations

import difflib
import re

from urdfinertia.descriptions.urdf.write import scan_links


def inertial_lines(data: bytes) -> set[int]:
    """0-based line numbers covered by any link's <inertial> element."""
    lines: set[int] = set()
    for span in scan_links(data).values():
        if span.inertial is not None:
            start, end = span.inertial
            first = data.count(b"\n", 0, start)
            last = data.count(b"\n", 0, end)
            lines.update(range(first, last + 1))
    return lines


def assert_only_inertials_differ(before: bytes, after: bytes) -> None:
    a, b = before.splitlines(), after.splitlines()
    in_a, in_b = inertial_lines(before), inertial_lines(after)
    matcher = difflib.SequenceMatcher(a=a, b=b, autojunk=False)
    # a self-closing <link .../> given an inertial opens and closes around it
    in_a |= {i for i, line in enumerate(a) if re.fullmatch(rb"\s*<link\b[^>]*/>\s*", line)}
    in_b |= {i for i, line in enumerate(b) if re.fullmatch(rb"\s*(<link\b[^>]*>|</link>)\s*",
                                                           line)}
    for tag, i1, i2, j1, j2 in matcher.get_opcodes():
        if tag == "equal":
            continue
        assert set(range(i1, i2)) <= in_a, f"removed non-inertial lines: {a[i1:i2]}"
        assert set(range(j1, j2)) <= in_b, f"added non-inertial lines: {b[j1:j2]}"
