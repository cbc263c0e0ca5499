"""The byte-splicing writers' shared pieces: one scanner grammar, one number format.

Every description format writes new inertials by splicing the document's own bytes
(`.urdf.write`, `.mjcf.write`, `.sdf.write`): they find element spans with
`TOKEN` (comments, CDATA, processing instructions and declarations told apart from
tags), read a `name` attribute as lxml would (`attribute_text`), indent like the
surrounding lines (`line_indent`) and write each number in its shortest round-trip
form with round-off noise cleared (`format_float`, `clean`).
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping
from typing import TYPE_CHECKING

from urdfinertia.errors import UrdfError

if TYPE_CHECKING:
    import numpy as np

    from urdfinertia.inertia.massprops import MassProperties

# numpy is imported by :func:`clean` alone: writing a cached result, relocating mesh
# references or scanning tags (every warm run) needs none of it.

NAME_ATTR = re.compile(rb"(?:^|\s)name\s*=\s*(?:\"([^\"]*)\"|'([^']*)')")
_ENTITIES = {"lt": "<", "gt": ">", "quot": '"', "apos": "'", "amp": "&"}
"""XML's predefined entities (xml.sax.saxutils would import urllib and http on every run)"""
_REFERENCE = re.compile(r"&(#x[0-9a-fA-F]+|#[0-9]+|lt|gt|quot|apos|amp);")


def _decode_reference(match: re.Match[str]) -> str:
    ref = match.group(1)
    if ref.startswith("#x"):
        return chr(int(ref[2:], 16))
    if ref.startswith("#"):
        return chr(int(ref[1:]))
    return _ENTITIES[ref]


def attribute_text(raw: bytes) -> str:
    """An attribute value as lxml reports it: character and entity references decoded in
    one pass (so `&#38;lt;` stays `&lt;`)."""
    return _REFERENCE.sub(_decode_reference, raw.decode("utf-8"))


NOISE_RTOL = 1e-12
"""Off-diagonal products and CoM components smaller than this fraction of the largest principal
moment (or of the geometry's size) are round-off and written as 0.
"""


def line_indent(data: bytes, pos: int) -> bytes:
    """The indentation of the line holding byte `pos`, when only whitespace precedes it.

    Parameters
    ----------
    data : bytes
        The document.
    pos : int
        A byte offset.

    Returns
    -------
    bytes
        The whitespace before `pos` on its line, else b"".
    """
    line_start = data.rfind(b"\n", 0, pos) + 1
    prefix = data[line_start:pos]
    return prefix if prefix.strip() == b"" else b""


TOKEN = re.compile(
    rb"<(?:(!--)|(!\[CDATA\[)|(\?)|(!)"
    rb"|(/?)([^\s/>!?]+)((?:\s+[^\s=/>]+\s*=\s*(?:\"[^\"]*\"|'[^']*'))*)\s*(/?)>)?",
    re.DOTALL,
)
"""The next markup at or after a position, classified in the order the scanner tests: 1 comment, 2
CDATA, 3 processing instruction, 4 other declaration, 5-8 a tag (as a tag); nothing captured: a
`<` that starts none of them.
"""


def skip_declaration(data: bytes, lt: int) -> int:
    """The offset just past the declaration (`<!DOCTYPE ...>`, with its internal subset) starting at
    `lt`.

    Parameters
    ----------
    data : bytes
        The document.
    lt : int
        The offset of the declaration's `<`.

    Returns
    -------
    int
        The offset after its closing `>`.
    """
    depth = 0
    i = lt + 2
    while i < len(data):
        c = data[i : i + 1]
        if c == b"[":
            depth += 1
        elif c == b"]":
            depth -= 1
        elif c == b">" and depth <= 0:
            return i + 1
        i += 1
    return len(data)


def format_float(value: float) -> str:
    """Shortest text that reads back to the same float (`repr`), never `-0`."""
    value = float(value)
    if value == 0.0:
        return "0"
    text = repr(value)
    return text[:-2] if text.endswith(".0") else text


def clean(props: MassProperties, size: float) -> tuple[np.ndarray, np.ndarray]:
    """CoM and tensor with round-off noise set to exactly 0 (see `NOISE_RTOL`)."""
    import numpy as np

    com = np.array(props.com)
    com[np.abs(com) < NOISE_RTOL * max(size, 1e-300)] = 0.0
    inertia = np.array(props.inertia)
    scale = float(np.abs(np.diag(inertia)).max())
    off = ~np.eye(3, dtype=bool)
    inertia[off & (np.abs(inertia) < NOISE_RTOL * scale)] = 0.0
    return com, inertia


def next_tag(data: bytes, pos: int) -> re.Match[bytes] | None:
    """The next start or end tag at or after `pos` (None at the end of the document).

    Comments, CDATA sections, processing instructions and declarations (a DOCTYPE with its
    internal subset) are skipped whole, so a `<link>` inside any of them is not a tag.
    Groups 5-8 of the match: "/" of an end tag, the name, the attributes, "/" of an empty
    element tag.
    """
    n = len(data)
    while True:
        m = TOKEN.search(data, pos)
        if m is None:
            return None
        if m.group(6) is not None:
            return m
        lt = m.start()
        comment, cdata, pi, declaration = m.group(1, 2, 3, 4)
        if comment:
            end = data.find(b"-->", lt + 4)
            pos = n if end < 0 else end + 3
        elif cdata:
            end = data.find(b"]]>", lt)
            pos = n if end < 0 else end + 3
        elif pi:
            end = data.find(b"?>", lt)
            pos = n if end < 0 else end + 2
        elif declaration:
            pos = skip_declaration(data, lt)
        else:
            raise UrdfError(f"cannot locate tag at byte {lt}")


_ATTRIBUTE = re.compile(rb"""(\s+)([^\s=/>]+)\s*=\s*(?:"([^"]*)"|'([^']*)')""")
"""One attribute of a start tag: leading space, name, value in either quotes."""
Edit = tuple[int, int, bytes]


def attribute_spans(data: bytes, tag: re.Match[bytes]) -> dict[str, tuple[int, int, int]]:
    """Attributes of the start tag `tag` (a `next_tag` match): name -> (start of
    the attribute with its leading space, start of the value, end of the value)."""
    out: dict[str, tuple[int, int, int]] = {}
    base = tag.start(7)
    for m in _ATTRIBUTE.finditer(tag.group(7) or b""):
        group = 3 if m.group(3) is not None else 4
        out[m.group(2).decode("ascii", "replace")] = (base + m.start(), base + m.start(group),
                                                      base + m.end(group))
    return out


def attribute_edits(data: bytes, tag: re.Match[bytes], values: Mapping[str, str],
                    remove: Iterable[str] = ()) -> list[Edit]:
    """Edits that give start tag `tag` these attribute `values` and drop `remove`.

    An existing attribute keeps its place, quotes and spacing: only its value changes. A
    missing one is added after the last attribute (`name="value"`).
    """
    spans = attribute_spans(data, tag)
    edits: list[Edit] = []
    added = b""
    for name, value in values.items():
        if name in spans:
            _, start, end = spans[name]
            if data[start:end].decode("utf-8", "replace") != value:
                edits.append((start, end, value.encode()))
        else:
            added += f' {name}="{value}"'.encode()
    for name in remove:
        if name in spans and name not in values:
            start, _, end = spans[name]
            edits.append((start, end + 1, b""))  # the closing quote goes too
    if added:
        at = tag.end(7) if tag.group(7) else tag.end(6)
        edits.append((at, at, added))
    return edits


def child_tags(data: bytes, start: int, end: int) -> dict[bytes, re.Match[bytes]]:
    """The first start tag of each name directly inside the element `[start, end)`."""
    found: dict[bytes, re.Match[bytes]] = {}
    first = next_tag(data, start)
    if first is None or first.group(8):
        return found
    depth = 0
    pos = first.end()
    while True:
        m = next_tag(data, pos)
        if m is None or m.start() >= end:
            return found
        pos = m.end()
        if m.group(5):
            depth -= 1
            continue
        if depth == 0:
            found.setdefault(m.group(6), m)
        if not m.group(8):
            depth += 1


def splice_edits(data: bytes, edits: Iterable[tuple[int, int, bytes]]) -> bytes:
    """`data` with each `[start, end)` replaced by its text; overlapping spans are a
    writer's bug (`UrdfError`)."""
    out = bytearray()
    pos = 0
    for start, end, text in sorted(edits, key=lambda e: (e[0], e[1])):
        if start < pos:
            raise UrdfError(f"overlapping edits at byte {start}")
        out += data[pos:start]
        out += text
        pos = end
    out += data[pos:]
    return bytes(out)
