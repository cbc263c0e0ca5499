"""Write new `<inertial>` elements into an MJCF document, leaving every other byte alone.

The same splicing as for URDF (`urdfinertia.descriptions.urdf.write`): a scanner finds
each `<body>` start tag and the span of its own `<inertial>` child, and only those
spans change (or one `<inertial>` is inserted as the body's first child, indented like
its siblings; MuJoCo does not care where among a body's children it stands). Unnamed
bodies are found by their position among the file's `<body>` tags (`body#K`, as the
reader names them).

What is written, one line: `<inertial pos="CoM" mass=".." diaginertia=".."/>` when the
tensor along the body's axes is diagonal, else `fullinertia="ixx iyy izz ixy ixz iyz"`:
the tensor about the CoM along the body frame's axes, products of inertia as the tensor's
own entries (MuJoCo's order and sign). No `quat`: the values are the tool's own numbers,
read back exactly, so `fix` on its own output changes nothing.
"""

from __future__ import annotations

from dataclasses import dataclass

from urdfinertia.descriptions.formats import NewInertial, NewInertials, new_inertial
from urdfinertia.descriptions.splice import (
    NAME_ATTR,
    Edit,
    attribute_edits,
    attribute_spans,
    attribute_text,
    clean,
    format_float,
    line_indent,
    next_tag,
    splice_edits,
)
from urdfinertia.errors import UrdfError
from urdfinertia.inertia.massprops import MassProperties


@dataclass(frozen=True)
class BodySpan:
    """Byte offsets of one `<body>` of the document."""

    name: str
    start_tag_end: int
    inertial: tuple[int, int] | None
    first_child_indent: bytes | None
    body_indent: bytes
    self_closing: bool
    first_child_inline: bool = False  # the first child starts on the body tag's line


def scan_bodies(data: bytes) -> dict[str, BodySpan]:
    """Every `<body>` of the document (at any depth) with its own `<inertial>` span."""
    spans: dict[str, BodySpan] = {}
    stack: list[tuple[bytes, dict | None]] = []
    ordinal = 0
    pos = 0
    while True:
        m = next_tag(data, pos)
        if m is None:
            break
        lt = m.start()
        closing, name, attrs, selfclose = m.group(5, 6, 7, 8)
        pos = m.end()
        if closing:
            if stack and stack[-1][0] == name:
                _, body = stack.pop()
                if body is not None:
                    _finish(spans, body)
            continue
        parent = stack[-1][1] if stack else None
        if parent is not None:
            if parent["first_child_indent"] is None:
                parent["first_child_indent"] = line_indent(data, lt)
                parent["first_child_inline"] = b"\n" not in data[parent["start_tag_end"]:lt]
            if name == b"inertial" and parent["inertial"] is None:
                if selfclose:
                    parent["inertial"] = (lt, pos)
                else:
                    close = data.find(b"</inertial", pos)
                    end = data.find(b">", close) + 1
                    if close < 0 or end <= 0:
                        raise UrdfError("unterminated <inertial>")
                    parent["inertial"] = (lt, end)
                    pos = end
                continue
        body = None
        if name == b"body":
            ordinal += 1
            am = NAME_ATTR.search(attrs)
            raw = (am.group(1) if am.group(1) is not None else am.group(2)) if am else b""
            body = {
                "name": attribute_text(raw) or f"body#{ordinal}",
                "start_tag_end": pos,
                "inertial": None,
                "first_child_indent": None,
                "body_indent": line_indent(data, lt),
                "self_closing": bool(selfclose),
                "first_child_inline": False,
            }
            if selfclose:
                _finish(spans, body)
                continue
        if not selfclose:
            stack.append((name, body))
    return spans


def _finish(spans: dict[str, BodySpan], body: dict) -> None:
    spans.setdefault(body["name"], BodySpan(**body))


def inertial_text(props: MassProperties, size: float) -> bytes:
    """The one-line `<inertial .../>` of `props` (see the module doc)."""
    com, i = clean(props, size)
    f = format_float
    pos = f"{f(com[0])} {f(com[1])} {f(com[2])}"
    key, value = _tensor_attribute(i)
    return f'<inertial pos="{pos}" mass="{f(props.mass)}" {key}="{value}"/>'.encode()


ORIENTATION_ATTRS = ("quat", "axisangle", "xyaxes", "zaxis", "euler")
"""Attributes that orient the inertia frame (one at most is allowed)."""


def kept_value_edits(data: bytes, start: int, entry: NewInertial) -> list[Edit]:
    """Edits of the `<inertial>` start tag at `start` that write only derived values.

    Kept values keep their bytes: a derived mass changes `mass`, a derived CoM `pos`,
    a derived tensor `diaginertia` or `fullinertia` (the old one's place; the other
    is dropped) and drops the frame's orientation (the new tensor is along the body's
    axes).
    """
    tag = next_tag(data, start)
    if tag is None:
        return []
    com, i = clean(entry.props, entry.size)
    f = format_float
    values: dict[str, str] = {}
    remove: list[str] = []
    if "mass" in entry.derived:
        values["mass"] = f(entry.props.mass)
    if "com" in entry.derived:
        values["pos"] = f"{f(com[0])} {f(com[1])} {f(com[2])}"
    if "tensor" in entry.derived:
        key, value = _tensor_attribute(i)
        values[key] = value
        remove += [a for a in ("diaginertia", "fullinertia") if a != key]
        remove += ORIENTATION_ATTRS
        spans = attribute_spans(data, tag)
        other = next((a for a in ("diaginertia", "fullinertia") if a != key and a in spans),
                     None)
        if other is not None and key not in spans:
            # the new tensor takes the old one's place: name and value both change
            at, _, end = spans[other]
            rest = attribute_edits(data, tag, {k: v for k, v in values.items() if k != key},
                                   [a for a in remove if a != other])
            return [*rest, (at, end + 1, f' {key}="{value}"'.encode())]
    return attribute_edits(data, tag, values, remove)


def _tensor_attribute(i) -> tuple[str, str]:  # noqa: ANN001 - a (3, 3) array
    f = format_float
    if i[0, 1] == 0 and i[0, 2] == 0 and i[1, 2] == 0:
        return "diaginertia", f"{f(i[0, 0])} {f(i[1, 1])} {f(i[2, 2])}"
    return "fullinertia", (f"{f(i[0, 0])} {f(i[1, 1])} {f(i[2, 2])} {f(i[0, 1])} "
                           f"{f(i[0, 2])} {f(i[1, 2])}")


def patch_inertials(data: bytes, new: NewInertials) -> bytes:
    """Replace (or add) the `<inertial>` of each body named in `new`.

    When some values were kept (`NewInertial`)
    and the body has an `<inertial>`, only the derived attributes change
    (`kept_value_edits`). A name not found in `data` belongs to a body of an
    included file when the document has `<include>` elements (the reader has said so
    on the link): nothing is written for it. Otherwise it is an error.
    """
    spans = scan_bodies(data)
    newline = b"\r\n" if b"\r\n" in data else b"\n"
    has_includes = b"<include" in data
    edits: list[tuple[int, int, bytes]] = []
    for name, value in new.items():
        entry = new_inertial(value)
        props, size = entry.props, entry.size
        span = spans.get(name)
        if span is None:
            if has_includes:
                continue
            raise UrdfError(f"cannot locate <body name='{name}'> in the text", link=name)
        if entry.partial and span.inertial is not None:
            edits.extend(kept_value_edits(data, span.inertial[0], entry))
            continue
        text = inertial_text(props, size)
        if span.inertial is not None:
            start, end = span.inertial
            edits.append((start, end, text))
        elif span.self_closing:
            slash = data.rfind(b"/", 0, span.start_tag_end)
            step = b"  "
            edits.append((slash, span.start_tag_end, b">" + newline + span.body_indent + step
                          + text + newline + span.body_indent + b"</body>"))
        elif span.first_child_inline:  # <body name="a"><geom .../></body> stays one line
            edits.append((span.start_tag_end, span.start_tag_end, text))
        else:
            indent = span.first_child_indent
            if indent is None or len(indent) <= len(span.body_indent):
                indent = span.body_indent + b"  "
            edits.append((span.start_tag_end, span.start_tag_end, newline + indent + text))
    return splice_edits(data, edits)
