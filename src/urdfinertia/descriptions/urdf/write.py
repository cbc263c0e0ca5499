"""Write new `<inertial>` elements into a URDF, leaving every other byte alone.

lxml reads the document (`urdf_read`); re-serialising it would still rewrite quoting,
`<tag />` spacing and the XML declaration, so the output is made by splicing: a small
scanner finds the byte span of each `<link>`'s `<inertial>` in the original text and
only those spans are replaced (or one is inserted after the `<link>` start tag).
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass

from urdfinertia.descriptions.formats import NewInertial, NewInertials, new_inertial
from urdfinertia.descriptions.splice import (
    NAME_ATTR,
    Edit,
    attribute_edits,
    attribute_spans,
    attribute_text,
    child_tags,
    clean,
    format_float,
    line_indent,
    next_tag,
    splice_edits,
)
from urdfinertia.errors import UrdfError
from urdfinertia.inertia.massprops import MassProperties


@dataclass(frozen=True)
class LinkSpan:
    """Byte offsets of one `<link>` in the document."""

    name: str
    start_tag_end: int  # offset just after the link's start tag '>'
    inertial: tuple[int, int] | None  # [start, end) of its <inertial> element
    first_child_indent: bytes | None
    link_indent: bytes
    self_closing: bool


def scan_links(data: bytes) -> dict[str, LinkSpan]:
    """Find every `<robot>`-level `<link>` and its `<inertial>` span.

    One regular-expression search per piece of markup (`TOKEN`) finds the next `<` and
    what it starts; comments, CDATA, processing instructions and declarations are skipped.
    """
    spans: dict[str, LinkSpan] = {}
    stack: list[bytes] = []
    pos = 0
    current: dict | None = None
    while True:
        m = next_tag(data, pos)
        if m is None:
            break
        lt = m.start()
        closing, name, attrs, selfclose = m.group(5, 6, 7, 8)
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
            am = NAME_ATTR.search(attrs)
            raw = (am.group(1) if am.group(1) is not None else am.group(2)) if am else b""
            current = {
                "name": attribute_text(raw),
                "start_tag_end": pos,
                "inertial": None,
                "first_child_indent": None,
                "link_indent": line_indent(data, lt),
                "self_closing": bool(selfclose),
            }
            if selfclose:
                _finish(spans, current)
                current = None
                continue
        elif depth == 2 and current is not None:
            if current["first_child_indent"] is None:
                current["first_child_indent"] = line_indent(data, lt)
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


_COMMENT = re.compile(rb"<!--.*?-->", re.DOTALL)
_CHILD = re.compile(rb"<(origin|mass|inertia)\b")
_SLOTS = {b"origin": 0, b"mass": 1, b"inertia": 2}


def inertial_comments(old: bytes) -> dict[int, list[bytes]]:
    """Comments inside an old `<inertial>`, by the line of the new one they come before.

    A comment stays in front of the child it preceded (1 origin, 2 mass, 3 inertia) or,
    after the last child, before `</inertial>` (4). Only comments are carried over: the
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
    """`<inertial>` text; the first line has no indent (it replaces one in place).

    `comments` (from `inertial_comments`) are written, one a line, before the line
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


def kept_value_edits(data: bytes, span: tuple[int, int], entry: NewInertial,
                     ) -> list[Edit] | None:
    """Edits of an existing `<inertial>` that write only the derived values.

    Kept values keep their bytes: a derived mass changes `<mass value>`, a derived CoM
    `<origin xyz>`, a derived tensor the six `<inertia>` attributes (and a rotated
    `<origin rpy>` becomes "0 0 0", the new tensor being along the link's axes). None
    when an element to change is missing: the whole element is then written.
    """
    start, end = span
    if data[start:end].rstrip().endswith(b"/>"):
        return None
    tags = child_tags(data, start, end)
    com, i = clean(entry.props, entry.size)
    f = format_float
    edits: list[Edit] = []
    origin = tags.get(b"origin")
    if "mass" in entry.derived:
        if b"mass" not in tags:
            return None
        edits += attribute_edits(data, tags[b"mass"], {"value": f(entry.props.mass)})
    if "com" in entry.derived:
        if origin is None:
            return None
        edits += attribute_edits(data, origin, {"xyz": f"{f(com[0])} {f(com[1])} {f(com[2])}"})
    if "tensor" in entry.derived:
        if b"inertia" not in tags:
            return None
        rpy = attribute_spans(data, origin).get("rpy") if origin is not None else None
        rotated = origin is not None and rpy is not None and not _zero(data[rpy[1]:rpy[2]])
        values = {"ixx": i[0, 0], "ixy": i[0, 1], "ixz": i[0, 2], "iyy": i[1, 1],
                  "iyz": i[1, 2], "izz": i[2, 2]}
        if not rotated:  # an entry whose number is unchanged keeps its text
            values = _changed(data, tags[b"inertia"], values)
        edits += attribute_edits(data, tags[b"inertia"], {k: f(v) for k, v in values.items()})
        if rotated:
            assert origin is not None
            edits += attribute_edits(data, origin, {"rpy": "0 0 0"})
    return edits


def _changed(data: bytes, tag: re.Match[bytes], values: dict[str, float]) -> dict[str, float]:
    """`values` without the attributes of `tag` that already hold the same number."""
    spans = attribute_spans(data, tag)
    out = {}
    for name, value in values.items():
        try:
            same = name in spans and float(data[spans[name][1]:spans[name][2]]) == value
        except ValueError:
            same = False
        if not same:
            out[name] = value
    return out


def _zero(text: bytes) -> bool:
    try:
        return all(float(t) == 0.0 for t in text.split())
    except ValueError:
        return False


def patch_inertials(data: bytes, new: NewInertials) -> bytes:
    """Replace (or add) the `<inertial>` of each link named in `new`.

    Parameters
    ----------
    data : bytes
        The original document.
    new : mapping of link name to `NewInertial`
        The mass properties in the link frame, the size below which CoM components count
        as round-off, and which values were derived: when some were kept, only the
        derived ones are written into the existing element (`kept_value_edits`).
    """
    spans = scan_links(data)
    newline = b"\r\n" if b"\r\n" in data else b"\n"
    edits: list[tuple[int, int, bytes]] = []
    for name, value in new.items():
        entry = new_inertial(value)
        props, size = entry.props, entry.size
        span = spans.get(name)
        if span is None:
            raise UrdfError(f"cannot locate <link name='{name}'> in the text", link=name)
        if entry.partial and span.inertial is not None:
            partial = kept_value_edits(data, span.inertial, entry)
            if partial is not None:
                edits.extend(partial)
                continue
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
            indent = line_indent(data, start)
            comments = inertial_comments(data[start:end])
            edits.append((start, end, inertial_xml(props, size, indent, step, newline,
                                                   comments)))
        else:
            indent = span.first_child_indent if span.first_child_indent is not None else (
                span.link_indent + step)
            text = newline + indent + inertial_xml(props, size, indent, step, newline)
            edits.append((span.start_tag_end, span.start_tag_end, text))
    return splice_edits(data, edits)
