"""Reading an expansion: its elements in order, the inertial values of each link, and the
token stream that perturbed expansions are compared on."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from lxml import etree

from urdfinertia.descriptions.xml import parse_document

if TYPE_CHECKING:
    from urdfinertia.descriptions.xacro.expand import Expansion

SLOTS = (
    ("mass", "mass", "value", 0, None),
    ("com x", "origin", "xyz", 0, "0"), ("com y", "origin", "xyz", 1, "0"),
    ("com z", "origin", "xyz", 2, "0"),
    ("roll", "origin", "rpy", 0, "0"), ("pitch", "origin", "rpy", 1, "0"),
    ("yaw", "origin", "rpy", 2, "0"),
    ("ixx", "inertia", "ixx", 0, None), ("ixy", "inertia", "ixy", 0, None),
    ("ixz", "inertia", "ixz", 0, None), ("iyy", "inertia", "iyy", 0, None),
    ("iyz", "inertia", "iyz", 0, None), ("izz", "inertia", "izz", 0, None),
)
"""The ten values of an inertial (plus rpy): (name, element under <inertial>, attribute, token
index, value when the element or attribute is absent).
"""

Position = tuple[int, str, int]
"""A position in an expansion: (element index in document order, attribute, token index)."""


@dataclass(frozen=True)
class SlotValue:
    text: str | None  # the token as expanded (None: absent)
    position: Position | None  # where it is (None: absent)


@dataclass(frozen=True)
class LinkInertial:
    link_index: int
    inertial_index: int | None
    slots: dict[str, SlotValue]


def elements(document: bytes) -> list[etree._Element]:
    """Every element of an expanded document, in document order.

    Parameters
    ----------
    document : bytes
        The URDF xacro made.

    Returns
    -------
    list of lxml elements
        In document order.
    """
    root = parse_document(document, "<xacro expansion>", ("robot",))
    return list(root.iter(etree.Element))


def index_of(els: list[etree._Element]) -> dict[etree._Element, int]:
    """Each element's position in `els`.

    Parameters
    ----------
    els : list of lxml elements
        Elements in document order.

    Returns
    -------
    dict
        Element -> index.
    """
    return {el: i for i, el in enumerate(els)}


def link_inertials(els: list[etree._Element]) -> dict[str, LinkInertial]:
    """Each `<robot>`-level link's inertial values and their positions."""
    index = index_of(els)
    out: dict[str, LinkInertial] = {}
    root = els[0]
    for link in root:
        if not isinstance(link.tag, str) or link.tag != "link":
            continue
        inertial = next((c for c in link if c.tag == "inertial"), None)
        slots: dict[str, SlotValue] = {}
        for name, tag, attr, tok, default in SLOTS:
            el = next((c for c in inertial if c.tag == tag), None) if inertial is not None \
                else None
            value = el.get(attr) if el is not None else None
            tokens = value.split() if value is not None else []
            if tok < len(tokens):
                slots[name] = SlotValue(tokens[tok], (index[el], attr, tok))
            else:
                slots[name] = SlotValue(default if inertial is not None else None, None)
        out.setdefault(link.get("name", ""), LinkInertial(
            index[link], index[inertial] if inertial is not None else None, slots))
    return out


def token_stream(els: list[etree._Element]) -> tuple[tuple, dict[Position, str]]:
    """(structure, tokens): two expansions with equal structure differ only in values."""
    structure = []
    tokens: dict[Position, str] = {}
    for i, el in enumerate(els):
        shape = []
        items = list(el.attrib.items())
        if el.text and el.text.strip():
            items.append(("#text", el.text))
        for name, value in items:
            parts = value.split()
            shape.append((name, len(parts)))
            for j, part in enumerate(parts):
                tokens[(i, name, j)] = part
        structure.append((el.tag, tuple(shape)))
    return tuple(structure), tokens


def describe(els: list[etree._Element], position: Position) -> str:
    """A position in words: `joint 'j1' origin@xyz[2]`."""
    i, attr, tok = position
    el = els[i]
    path = []
    node = el
    while node is not None and node.getparent() is not None:
        path.append(node)
        node = node.getparent()
    top = path[-1] if path else el
    rest = "/".join(n.tag for n in reversed(path[:-1]))
    where = f"{top.tag} '{top.get('name', '')}'" + (f" {rest}" if rest else "")
    count = len((el.text if attr == "#text" else el.get(attr, "")).split())
    return f"{where}@{attr}" + (f"[{tok}]" if count > 1 else "")


def source_of_line(exp: Expansion, line: int) -> tuple[Path, int] | None:
    """The source file and line of the element at `line` of the expansion."""
    from urdfinertia.descriptions.xacro.expand import line_of

    try:
        els = elements(exp.document)
    except Exception:  # noqa: BLE001 - best effort for an error message
        return None
    for el, location in zip(els, exp.locations, strict=False):
        if el.sourceline == line and location is not None:
            index, offset = location
            return exp.sources[index], line_of(exp.source_bytes[index], offset)
    return None
