"""Write new ``<inertial>`` elements into a URDF, leaving every other byte alone.

lxml reads the document (:mod:`urdf_read`); re-serialising it would still rewrite quoting,
``<tag />`` spacing and the XML declaration, so the output is made by splicing: a small
scanner finds the byte span of each ``<link>``'s ``<inertial>`` in the original text and
only those spans are replaced (or one is inserted after the ``<link>`` start tag).
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from urdfinertia.errors import UrdfError
from urdfinertia.inertia.massprops import MassProperties

_TAG = re.compile(
    rb"<(/?)([^\s/>!?]+)((?:\s+[^\s=/>]+\s*=\s*(?:\"[^\"]*\"|'[^']*'))*)\s*(/?)>", re.DOTALL
)
_NAME_ATTR = re.compile(rb"(?:^|\s)name\s*=\s*(?:\"([^\"]*)\"|'([^']*)')")
#: XML's predefined entities (xml.sax.saxutils would import urllib and http on every run)
_ENTITIES = {"lt": "<", "gt": ">", "quot": '"', "apos": "'", "amp": "&"}
_REFERENCE = re.compile(r"&(#x[0-9a-fA-F]+|#[0-9]+|lt|gt|quot|apos|amp);")


def _decode_reference(match: re.Match[str]) -> str:
    ref = match.group(1)
    if ref.startswith("#x"):
        return chr(int(ref[2:], 16))
    if ref.startswith("#"):
        return chr(int(ref[1:]))
    return _ENTITIES[ref]


def _attribute_text(raw: bytes) -> str:
    """An attribute value as lxml reports it: character and entity references decoded in
    one pass (so ``&#38;lt;`` stays ``&lt;``)."""
    return _REFERENCE.sub(_decode_reference, raw.decode("utf-8"))


_OFF_DIAGONAL = ~np.eye(3, dtype=bool)
_OFF_DIAGONAL.setflags(write=False)

#: Off-diagonal products and CoM components smaller than this fraction of the largest
#: principal moment (or of the geometry's size) are round-off and written as 0.
NOISE_RTOL = 1e-12


@dataclass(frozen=True)
class LinkSpan:
    """Byte offsets of one ``<link>`` in the document."""

    name: str
    start_tag_end: int  # offset just after the link's start tag '>'
    inertial: tuple[int, int] | None  # [start, end) of its <inertial> element
    first_child_indent: bytes | None
    link_indent: bytes
    self_closing: bool


def _line_indent(data: bytes, pos: int) -> bytes:
    line_start = data.rfind(b"\n", 0, pos) + 1
    prefix = data[line_start:pos]
    return prefix if prefix.strip() == b"" else b""


#: The next markup at or after a position, classified in the order the scanner tests:
#: 1 comment, 2 CDATA, 3 processing instruction, 4 other declaration, 5-8 a tag (as
#: ``_TAG``); nothing captured: a ``<`` that starts none of them.
_TOKEN = re.compile(
    rb"<(?:(!--)|(!\[CDATA\[)|(\?)|(!)"
    rb"|(/?)([^\s/>!?]+)((?:\s+[^\s=/>]+\s*=\s*(?:\"[^\"]*\"|'[^']*'))*)\s*(/?)>)?",
    re.DOTALL,
)


def scan_links(data: bytes) -> dict[str, LinkSpan]:
    """Find every ``<robot>``-level ``<link>`` and its ``<inertial>`` span.

    One regular-expression search per piece of markup (``_TOKEN``) finds the next ``<`` and
    what it starts; comments, CDATA, processing instructions and declarations are skipped.
    """
    spans: dict[str, LinkSpan] = {}
    stack: list[bytes] = []
    pos = 0
    n = len(data)
    current: dict | None = None
    search = _TOKEN.search
    while True:
        m = search(data, pos)
        if m is None:
            break
        lt = m.start()
        comment, cdata, pi, declaration, closing, name, attrs, selfclose = m.groups()
        if name is None:
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
                pos = _skip_declaration(data, lt)
            else:
                raise UrdfError(f"cannot locate tag at byte {lt}")
            continue
        pos = m.end()
        if closing:
            if stack and stack[-1] == name:
                stack.pop()
            if current is not None and name == b"link" and len(stack) == 1:
                _finish(spans, current)
                current = None
            continue
        depth = len(stack)
        if depth == 1 and name == b"link":
            am = _NAME_ATTR.search(attrs)
            raw = (am.group(1) if am.group(1) is not None else am.group(2)) if am else b""
            current = {
                "name": _attribute_text(raw),
                "start_tag_end": pos,
                "inertial": None,
                "first_child_indent": None,
                "link_indent": _line_indent(data, lt),
                "self_closing": bool(selfclose),
            }
            if selfclose:
                _finish(spans, current)
                current = None
                continue
        elif depth == 2 and current is not None:
            if current["first_child_indent"] is None:
                current["first_child_indent"] = _line_indent(data, lt)
            if name == b"inertial" and current["inertial"] is None:
                if selfclose:
                    current["inertial"] = (lt, pos)
                else:
                    close = data.find(b"</inertial", pos)
                    end = data.find(b">", close) + 1
                    if close < 0 or end <= 0:
                        raise UrdfError("unterminated <inertial>")
                    current["inertial"] = (lt, end)
                    pos = end
                    continue
        if not selfclose:
            stack.append(name)
    return spans


def _finish(spans: dict[str, LinkSpan], current: dict) -> None:
    spans.setdefault(current["name"], LinkSpan(**current))


def _skip_declaration(data: bytes, lt: int) -> int:
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
    """Shortest text that reads back to the same float (``repr``), never ``-0``."""
    value = float(value)
    if value == 0.0:
        return "0"
    text = repr(value)
    return text[:-2] if text.endswith(".0") else text


def clean(props: MassProperties, size: float) -> tuple[np.ndarray, np.ndarray]:
    """CoM and tensor with round-off noise set to exactly 0 (see ``NOISE_RTOL``)."""
    com = np.array(props.com)
    com[np.abs(com) < NOISE_RTOL * max(size, 1e-300)] = 0.0
    inertia = np.array(props.inertia)
    scale = float(np.abs(np.diag(inertia)).max())
    off = _OFF_DIAGONAL
    inertia[off & (np.abs(inertia) < NOISE_RTOL * scale)] = 0.0
    return com, inertia


_COMMENT = re.compile(rb"<!--.*?-->", re.DOTALL)
_CHILD = re.compile(rb"<(origin|mass|inertia)\b")
_SLOTS = {b"origin": 0, b"mass": 1, b"inertia": 2}


def inertial_comments(old: bytes) -> dict[int, list[bytes]]:
    """Comments inside an old ``<inertial>``, by the line of the new one they come before.

    A comment stays in front of the child it preceded (1 origin, 2 mass, 3 inertia) or,
    after the last child, before ``</inertial>`` (4). Only comments are carried over: the
    values and their formatting are what is being replaced.
    """
    out: dict[int, list[bytes]] = {}
    for m in _COMMENT.finditer(old):
        nxt = _CHILD.search(old, m.end())
        slot = 1 + _SLOTS[nxt.group(1)] if nxt is not None else 4
        out.setdefault(slot, []).append(m.group(0))
    return out


def inertial_xml(props: MassProperties, size: float, indent: bytes, step: bytes,
                 newline: bytes, comments: Mapping[int, list[bytes]] | None = None) -> bytes:
    """``<inertial>`` text; the first line has no indent (it replaces one in place).

    ``comments`` (from :func:`inertial_comments`) are written, one a line, before the line
    of their slot.
    """
    com, i = clean(props, size)
    f = format_float
    lines = [
        "<inertial>",
        f'{step.decode()}<origin xyz="{f(com[0])} {f(com[1])} {f(com[2])}" rpy="0 0 0"/>',
        f'{step.decode()}<mass value="{f(props.mass)}"/>',
        f'{step.decode()}<inertia ixx="{f(i[0, 0])}" ixy="{f(i[0, 1])}" ixz="{f(i[0, 2])}" '
        f'iyy="{f(i[1, 1])}" iyz="{f(i[1, 2])}" izz="{f(i[2, 2])}"/>',
        "</inertial>",
    ]
    encoded = [line.encode() for line in lines]
    for slot in sorted(comments or {}, reverse=True):
        pad = step if slot < 4 else b""
        encoded[slot:slot] = [pad + c for c in comments[slot]]  # type: ignore[index]
    return (newline + indent).join(encoded)


def _step(data: bytes, span: LinkSpan) -> bytes:
    """Indentation step used by the document (from the link's own children)."""
    if span.first_child_indent is not None and len(span.first_child_indent) > len(
        span.link_indent
    ):
        return span.first_child_indent[len(span.link_indent):]
    return b"  "


def patch_inertials(data: bytes, new: Mapping[str, tuple[MassProperties, float]]) -> bytes:
    """Replace (or add) the ``<inertial>`` of each link named in ``new``.

    Parameters
    ----------
    data : bytes
        The original document.
    new : mapping of link name to (mass properties in the link frame, link size in m)
        The size sets the scale below which CoM components count as round-off.
    """
    spans = scan_links(data)
    newline = b"\r\n" if b"\r\n" in data else b"\n"
    edits: list[tuple[int, int, bytes]] = []
    for name, (props, size) in new.items():
        span = spans.get(name)
        if span is None:
            raise UrdfError(f"cannot locate <link name='{name}'> in the text", link=name)
        step = _step(data, span)
        if span.self_closing:
            # <link name="x"/> becomes <link name="x"> + inertial + </link>
            slash = data.rfind(b"/", 0, span.start_tag_end)
            indent = span.link_indent + step
            text = (b">" + newline + indent + inertial_xml(props, size, indent, step, newline)
                    + newline + span.link_indent + b"</link>")
            edits.append((slash, span.start_tag_end, text))
        elif span.inertial is not None:
            start, end = span.inertial
            indent = _line_indent(data, start)
            comments = inertial_comments(data[start:end])
            edits.append((start, end, inertial_xml(props, size, indent, step, newline,
                                                   comments)))
        else:
            indent = span.first_child_indent if span.first_child_indent is not None else (
                span.link_indent + step)
            text = newline + indent + inertial_xml(props, size, indent, step, newline)
            edits.append((span.start_tag_end, span.start_tag_end, text))
    out = bytearray()
    pos = 0
    for start, end, text in sorted(edits):
        out += data[pos:start]
        out += text
        pos = end
    out += data[pos:]
    return bytes(out)
