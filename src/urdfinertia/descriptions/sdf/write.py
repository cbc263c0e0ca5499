"""Write new inertials into an SDFormat document, leaving every other byte alone.

As for URDF (`urdfinertia.descriptions.urdf.write`), the output is made by splicing
the original bytes: a scanner finds the byte spans of every element (comments, CDATA and
declarations skipped), and inside each link's `<inertial>` only `<pose>`, `<mass>`
and `<inertia>` are replaced; other children (`<density>`, `<fluid_added_mass>`,
comments) stay where they are. `auto="true"` is removed from the `<inertial>` start tag,
since Gazebo ignores explicit values while it is set. The written `<pose>` is the centre
of mass in the link frame with no rotation and no `relative_to` (the inertial pose is
defined relative to the link; the tensor is written along the link's axes). A link without
an `<inertial>` gets one as its first child, indented like its siblings.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from urdfinertia.descriptions.formats import NewInertial, NewInertials, new_inertial
from urdfinertia.descriptions.splice import (
    NAME_ATTR,
    Edit,
    attribute_text,
    clean,
    format_float,
    line_indent,
    next_tag,
    splice_edits,
)
from urdfinertia.errors import UrdfError
from urdfinertia.inertia.massprops import MassProperties

_AUTO_ATTR = re.compile(rb"\s+auto\s*=\s*(?:\"[^\"]*\"|'[^']*')")
_REPLACED = (b"pose", b"mass", b"inertia")


@dataclass(eq=False)
class _Node:
    """One element's byte spans: `<tag ...>` is [lt, start_end), the element [lt, end)."""

    tag: bytes
    lt: int
    start_end: int
    attrs: bytes
    self_closing: bool
    parent: _Node | None
    end: int = -1
    children: list[_Node] = field(default_factory=list)

    def name(self) -> str:
        m = NAME_ATTR.search(self.attrs)
        raw = (m.group(1) if m.group(1) is not None else m.group(2)) if m else b""
        return attribute_text(raw)

    def kids(self, tag: bytes) -> list[_Node]:
        return [c for c in self.children if c.tag == tag]


def _local(tag: bytes) -> bytes:
    return tag.rpartition(b":")[2] if b":" in tag else tag


def scan_elements(data: bytes) -> _Node:
    """The document's element tree with byte spans (a root node holding the top element)."""
    top = _Node(b"", 0, 0, b"", False, None)
    cur = top
    pos = 0
    while True:
        m = next_tag(data, pos)
        if m is None:
            break
        lt = m.start()
        closing, name, attrs, selfclose = m.group(5, 6, 7, 8)
        pos = m.end()
        if closing:
            if cur.parent is not None and cur.tag == name:
                cur.end = pos
                cur = cur.parent
            continue
        node = _Node(name, lt, pos, attrs or b"", bool(selfclose), cur)
        cur.children.append(node)
        if selfclose:
            node.end = pos
        else:
            cur = node
    return top


def link_nodes(data: bytes) -> dict[str, _Node]:
    """Every `<model>`'s `<link>` by the name `.read` gives it."""
    top = scan_elements(data)
    roots = [c for c in top.children if _local(c.tag) == b"sdf"]
    models: list[_Node] = []
    for root in roots:
        for el in root.children:
            if el.tag == b"model":
                models.append(el)
            elif el.tag == b"world":
                models.extend(el.kids(b"model"))
    found: dict[str, _Node] = {}
    several = len(models) > 1

    def walk(model: _Node, prefix: str) -> None:
        for el in model.children:
            if el.tag == b"link":
                found.setdefault(prefix + el.name(), el)
            elif el.tag == b"model":
                walk(el, f"{prefix}{el.name()}::")

    for model in models:
        walk(model, f"{model.name()}::" if several else "")
    return found


def _step(data: bytes, outer: bytes, node: _Node) -> bytes:
    for child in node.children:
        indent = line_indent(data, child.lt)
        if len(indent) > len(outer) and indent.startswith(outer):
            return indent[len(outer):]
    return b"  "


def inertial_lines(props: MassProperties, size: float, step: bytes) -> list[bytes]:
    """`<pose>`, `<mass>` and `<inertia>` lines, relative indents included."""
    com, i = clean(props, size)
    f = format_float
    s = step.decode()
    lines = [f"<pose>{f(com[0])} {f(com[1])} {f(com[2])} 0 0 0</pose>",
             f"<mass>{f(props.mass)}</mass>", "<inertia>"]
    for key, value in (("ixx", i[0, 0]), ("ixy", i[0, 1]), ("ixz", i[0, 2]),
                       ("iyy", i[1, 1]), ("iyz", i[1, 2]), ("izz", i[2, 2])):
        lines.append(f"{s}<{key}>{f(value)}</{key}>")
    lines.append("</inertia>")
    return [line.encode() for line in lines]


def _removal(data: bytes, node: _Node) -> tuple[int, int]:
    """Span of a child element, with its own line's indent and line break when alone."""
    indent = line_indent(data, node.lt)
    start = node.lt - len(indent)
    line_start = data.rfind(b"\n", 0, node.lt) + 1
    if start == line_start and line_start > 0:
        start = line_start - 1
        if start > 0 and data[start - 1:start] == b"\r":
            start -= 1
    return start, node.end


def _edits_for(data: bytes, link: _Node, props: MassProperties, size: float,
               newline: bytes) -> list[tuple[int, int, bytes]]:
    link_indent = line_indent(data, link.lt)
    step = _step(data, link_indent, link)
    inertials = link.kids(b"inertial")
    if link.self_closing:
        slash = data.rfind(b"/", 0, link.start_end)
        indent = link_indent + step
        body = _whole(props, size, indent, step, newline)
        return [(slash, link.start_end, b">" + newline + indent + body + newline
                 + link_indent + b"</link>")]
    if not inertials:
        first = link.children[0] if link.children else None
        indent = line_indent(data, first.lt) if first is not None else b""
        if not indent:
            indent = link_indent + step
        return [(link.start_end, link.start_end,
                 newline + indent + _whole(props, size, indent, step, newline))]
    inertial = inertials[0]
    indent = line_indent(data, inertial.lt)
    if inertial.self_closing or not inertial.end > 0:
        return [(inertial.lt, inertial.end, _whole(props, size, indent, step, newline))]
    edits = []
    start_tag = data[inertial.lt:inertial.start_end]
    cleaned = _AUTO_ATTR.sub(b"", start_tag)
    inner = indent + step
    for child in inertial.children:
        if child.tag in _REPLACED:
            child_indent = line_indent(data, child.lt)
            if child_indent:
                inner = child_indent
            break
    for child in inertial.children:
        if child.tag in _REPLACED:
            start, end = _removal(data, child)
            edits.append((start, end, b""))
    text = b"".join(newline + inner + line for line in inertial_lines(props, size, step))
    edits.append((inertial.lt, inertial.start_end, cleaned + text))
    return edits


def _whole(props: MassProperties, size: float, indent: bytes, step: bytes,
           newline: bytes) -> bytes:
    """A complete `<inertial>` element; its first line carries no indent."""
    lines = [b"<inertial>", *(step + line for line in inertial_lines(props, size, step)),
             b"</inertial>"]
    return (newline + indent).join(lines)


_TOKEN = re.compile(rb"\S+")
_INERTIA_KEYS = (b"ixx", b"ixy", b"ixz", b"iyy", b"iyz", b"izz")


def _text_tokens(data: bytes, node: _Node) -> list[tuple[int, int]] | None:
    """Spans of the whitespace-separated words of a text-only element (None: not one)."""
    if node.self_closing or node.children or node.end <= 0:
        return None
    close = data.rfind(b"</", node.start_end, node.end)
    if close < 0 or b"<" in data[node.start_end:close] or b"&" in data[node.start_end:close]:
        return None
    return [(node.start_end + m.start(), node.start_end + m.end())
            for m in _TOKEN.finditer(data[node.start_end:close])]


def kept_value_edits(data: bytes, link: _Node, entry: NewInertial) -> list[Edit] | None:
    """Edits of the link's `<inertial>` that write only the derived values, the kept
    ones' text untouched; None when the element is not plain enough (`auto`, a
    `relative_to` or `rotation_format` pose, a missing value): it is then rewritten.

    A derived mass changes `<mass>`'s text, a derived CoM the first three words of
    `<pose>`, a derived tensor the six `<inertia>` values and sets a rotated pose's
    angles to 0 (the new tensor is along the link's axes).
    """
    inertials = link.kids(b"inertial")
    if not inertials or inertials[0].self_closing or _AUTO_ATTR.search(inertials[0].attrs):
        return None
    inertial = inertials[0]
    com, i = clean(entry.props, entry.size)
    f = format_float
    edits: list[Edit] = []
    poses = inertial.kids(b"pose")
    pose = None
    if poses:
        if b"relative_to" in poses[0].attrs or b"rotation_format" in poses[0].attrs:
            return None
        pose = _text_tokens(data, poses[0])
        if pose is None or len(pose) != 6:
            return None
    if "mass" in entry.derived:
        masses = inertial.kids(b"mass")
        words = _text_tokens(data, masses[0]) if masses else None
        if not words or len(words) != 1:
            return None
        edits.append((*words[0], f(entry.props.mass).encode()))
    if "com" in entry.derived:
        if pose is None:
            return None
        edits += [(*pose[k], f(com[k]).encode()) for k in range(3)]
    if "tensor" in entry.derived:
        tensors = inertial.kids(b"inertia")
        if not tensors:
            return None
        values = dict(zip(_INERTIA_KEYS, (i[0, 0], i[0, 1], i[0, 2], i[1, 1], i[1, 2],
                                          i[2, 2]), strict=True))
        for key, value in values.items():
            nodes = tensors[0].kids(key)
            words = _text_tokens(data, nodes[0]) if nodes else None
            if not words or len(words) != 1:
                return None
            edits.append((*words[0], f(value).encode()))
        if pose is not None:
            for start, end in pose[3:]:
                try:
                    rotated = float(data[start:end]) != 0.0
                except ValueError:
                    return None
                if rotated:
                    edits.append((start, end, b"0"))
    return edits


def patch_inertials(data: bytes, new: NewInertials) -> bytes:
    """Replace (or add) the inertial of each link named in `new` (names as `.read`).

    When some values were kept (`NewInertial`),
    only the derived ones are written into the existing element where it is plain enough
    (`kept_value_edits`).
    """
    links = link_nodes(data)
    newline = b"\r\n" if b"\r\n" in data else b"\n"
    edits: list[tuple[int, int, bytes]] = []
    for name, value in new.items():
        entry = new_inertial(value)
        link = links.get(name)
        if link is None:
            raise UrdfError(f"cannot locate <link name='{name}'> in the text", link=name)
        partial = kept_value_edits(data, link, entry) if entry.partial else None
        if partial is not None:
            edits.extend(partial)
            continue
        edits.extend(_edits_for(data, link, entry.props, entry.size, newline))
    return splice_edits(data, edits)
