"""Numeric literals of xacro and YAML sources that could carry an inertial value, with
their exact byte spans (write-back changes those bytes and nothing else)."""

from __future__ import annotations

import re
from dataclasses import dataclass

NUMBER = re.compile(rb"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?\Z")
_COMMENT = re.compile(rb"<!--.*?-->|<!\[CDATA\[.*?\]\]>", re.S)
_START_TAG = re.compile(
    rb"<([A-Za-z_][\w.:\-]*)((?:\s+[^\s=/>]+\s*=\s*(?:\"[^\"]*\"|'[^']*'))*)\s*(/?)>", re.S)
_ATTR = re.compile(rb"([^\s=/>]+)\s*=\s*(?:\"([^\"]*)\"|'([^']*)')")
_VALUE_TOKEN = re.compile(rb"(?:\$\{[^}]*\}|\$\([^)]*\)|[^\s])+")
"""A value's tokens: runs of non-space characters, ${...} and $(...) kept whole."""
_MACRO_DEFAULT = re.compile(rb"([^\s:=]+)\s*:?=\s*(?:\^\|?)?([^\s]+)")
_NOT_VALUES = {b"xacro:include", b"xacro:if", b"xacro:unless", b"xacro:insert_block",
               b"xacro:element", b"xacro:attribute", b"xacro:call"}
"""Xacro elements whose attributes are not values that flow into the document."""


@dataclass(frozen=True)
class Literal:
    """A number written in a source file: `source` indexes `Expansion.sources`."""

    source: int
    start: int
    end: int
    text: str
    kind: str  # "xml" | "yaml"
    context: str  # what holds it, in words

    @property
    def value(self) -> float:
        """The literal's number."""
        return float(self.text)


@dataclass(frozen=True)
class Attribute:
    name: str
    value: str  # raw, as written
    start: int  # byte span of the value (inside the quotes)
    end: int


def start_tag_at(data: bytes, offset: int) -> tuple[str, list[Attribute], int, bool] | None:
    """(name, attributes, end offset, self-closing) of the start tag at `offset`."""
    m = _START_TAG.match(data, offset)
    if m is None:
        return None
    return (m.group(1).decode(), _attributes(m), m.end(), bool(m.group(3)))


def _attributes(m: re.Match[bytes]) -> list[Attribute]:
    out = []
    base = m.start(2)
    for a in _ATTR.finditer(m.group(2)):
        group = 2 if a.group(2) is not None else 3
        out.append(Attribute(a.group(1).decode(), a.group(group).decode("utf-8", "replace"),
                             base + a.start(group), base + a.end(group)))
    return out


def value_tokens(data: bytes, attr: Attribute) -> list[tuple[int, int, bytes]]:
    """Whitespace-separated tokens of an attribute value, as (start, end, bytes)."""
    raw = data[attr.start:attr.end]
    return [(attr.start + t.start(), attr.start + t.end(), t.group())
            for t in _VALUE_TOKEN.finditer(raw)]


def xml_literals(data: bytes, source: int) -> list[Literal]:
    """Literals of a xacro file that can flow into the expansion: property and arg values
    and defaults, macro parameter defaults, the attributes of macro calls."""
    out: list[Literal] = []
    skip = [(m.start(), m.end()) for m in _COMMENT.finditer(data)]
    for m in _START_TAG.finditer(data):
        if any(a <= m.start() < b for a, b in skip):
            continue
        tag = m.group(1)
        if not tag.startswith(b"xacro:") or tag in _NOT_VALUES:
            continue
        name = tag.decode()
        for attr in _attributes(m):
            if attr.name.startswith("xmlns"):
                continue
            if tag == b"xacro:macro":
                if attr.name == "params":
                    out.extend(_macro_defaults(data, attr, source, _name_of(m)))
                continue
            if tag in (b"xacro:property", b"xacro:arg"):
                if attr.name not in ("value", "default"):
                    continue
                context = f"<{name} name=\"{_name_of(m)}\"> {attr.name}"
            else:
                context = f"<{name}> attribute {attr.name}"
            for start, end, tok in value_tokens(data, attr):
                if NUMBER.match(tok):
                    out.append(Literal(source, start, end, tok.decode(), "xml", context))
    return out


def _name_of(m: re.Match[bytes]) -> str:
    for a in _attributes(m):
        if a.name == "name":
            return a.value
    return ""


def _macro_defaults(data: bytes, attr: Attribute, source: int, macro: str) -> list[Literal]:
    out = []
    raw = data[attr.start:attr.end]
    for d in _MACRO_DEFAULT.finditer(raw):
        if NUMBER.match(d.group(2)):
            out.append(Literal(source, attr.start + d.start(2), attr.start + d.end(2),
                               d.group(2).decode(), "xml",
                               f"default of parameter {d.group(1).decode()} of macro "
                               f"\"{macro}\""))
    return out


def element_literals(data: bytes, offset: int, attr_name: str, source: int,
                     ) -> tuple[list[tuple[Literal | None, str]], str | None]:
    """Per token of attribute `attr_name` of the element whose start tag is at
    `offset`: the literal (or None and the token's text); and the whole raw value."""
    tag = start_tag_at(data, offset)
    if tag is None:
        return [], None
    name, attrs, _, _ = tag
    attr = next((a for a in attrs if a.name == attr_name), None)
    if attr is None:
        return [], None
    out: list[tuple[Literal | None, str]] = []
    for start, end, tok in value_tokens(data, attr):
        text = tok.decode("utf-8", "replace")
        if NUMBER.match(tok):
            out.append((Literal(source, start, end, text, "xml",
                                f"<{name}> attribute {attr_name}"), text))
        else:
            out.append((None, text))
    return out, attr.value


def yaml_literals(data: bytes, source: int) -> list[Literal]:
    """Plain int and float scalars of a YAML file with their byte spans."""
    import yaml

    text = data.decode("utf-8", "replace")
    try:
        root = yaml.compose(text, Loader=yaml.SafeLoader)
    except yaml.YAMLError:
        return []
    out: list[Literal] = []
    numeric = {"tag:yaml.org,2002:int", "tag:yaml.org,2002:float"}
    string = "tag:yaml.org,2002:str"
    stack: list[tuple[object, str]] = [(root, "")]
    while stack:
        node, path = stack.pop()
        if isinstance(node, yaml.MappingNode):
            for key, value in node.value:
                stack.append((value, f"{path}.{getattr(key, 'value', '?')}".lstrip(".")))
        elif isinstance(node, yaml.SequenceNode):
            stack.extend((v, f"{path}[{i}]") for i, v in enumerate(node.value))
        elif isinstance(node, yaml.ScalarNode) and node.style is None and node.tag in numeric:
            start = len(text[:node.start_mark.index].encode())
            end = start + len(text[node.start_mark.index:node.end_mark.index].encode())
            raw = data[start:end]
            if NUMBER.match(raw):
                out.append(Literal(source, start, end, raw.decode(), "yaml", f"YAML {path}"))
        elif isinstance(node, yaml.ScalarNode) and node.tag == string and node.style in (
                None, "'", '"') and "\\" not in node.value:
            # "xyz: 0.1 0 -0.02" (Franka's inertial.yaml): each number of the text
            start = len(text[:node.start_mark.index].encode())
            end = start + len(text[node.start_mark.index:node.end_mark.index].encode())
            for tok in re.finditer(rb"[^\s'\"]+", data[start:end]):
                if NUMBER.match(tok.group()):
                    out.append(Literal(source, start + tok.start(), start + tok.end(),
                                       tok.group().decode(), "yaml-text", f"YAML {path}"))
    return out


def yaml_number(text: str) -> str:
    """A float as YAML 1.1 (PyYAML) reads it back as a float: `1e-05` -> `1.0e-05`."""
    mantissa, e, exponent = text.lower().partition("e")
    if not e:
        return text
    if "." not in mantissa:
        mantissa += ".0"
    if exponent[:1] not in "+-":
        exponent = "+" + exponent
    return f"{mantissa}e{exponent}"
