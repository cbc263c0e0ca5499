"""Byte-level refusals of hostile XML, before any parser runs (descriptions and COLLADA).

A document that *declares* entities or points at an external DTD has no legitimate use in
a robot description or a mesh, so it is refused outright: no parser runs, nothing is read
or fetched, and the answer is immediate whatever the expansion factor of a "billion
laughs" bomb. A regular-expression scan of the bytes: no lxml, importable from anywhere.
"""

from __future__ import annotations

import re
from typing import BinaryIO

_ENTITY_DECL = re.compile(rb"<!ENTITY", re.IGNORECASE)
_EXTERNAL_DTD = re.compile(rb"<!DOCTYPE[^>\[]*\b(?:SYSTEM|PUBLIC)\b", re.IGNORECASE)
_BOMS = (
    (b"\x00\x00\xfe\xff", "UTF-32"),
    (b"\xff\xfe\x00\x00", "UTF-32"),
    (b"\xfe\xff", "UTF-16"),
    (b"\xff\xfe", "UTF-16"),
)
#: Bytes kept from the end of one chunk when scanning a stream (longest pattern + slack).
_OVERLAP = 64
def hostile_xml_cause(head: bytes) -> str | None:
    """Why ``head`` (a whole document or one chunk of it) must not be parsed, or None.

    Refused: any ``<!ENTITY`` declaration (XXE, entity bombs), a ``<!DOCTYPE`` naming an
    external DTD, and UTF-16/32 documents (the checks here and the byte-level URDF patcher
    need an ASCII-compatible encoding).
    """
    for bom, name in _BOMS:
        if head.startswith(bom):
            return f"{name} encoded XML is not supported: convert the file to UTF-8"
    if head[:4].count(b"\x00"):
        return "UTF-16/32 encoded XML is not supported: convert the file to UTF-8"
    if _ENTITY_DECL.search(head):
        return "XML entity declarations are not allowed (possible XXE or entity bomb)"
    if _EXTERNAL_DTD.search(head):
        return "external DTD references (<!DOCTYPE ... SYSTEM/PUBLIC) are not allowed"
    return None


def hostile_xml_stream_cause(stream: BinaryIO, chunk_size: int = 1 << 20) -> str | None:
    """:func:`hostile_xml_cause` over a file read in chunks (bounded memory)."""
    tail = b""
    first = True
    while True:
        chunk = stream.read(chunk_size)
        if not chunk:
            return None
        window = tail + chunk
        cause = hostile_xml_cause(window) if first else _declaration_cause(window)
        if cause:
            return cause
        first = False
        tail = window[-_OVERLAP:]


def _declaration_cause(window: bytes) -> str | None:
    if _ENTITY_DECL.search(window):
        return "XML entity declarations are not allowed (possible XXE or entity bomb)"
    if _EXTERNAL_DTD.search(window):
        return "external DTD references (<!DOCTYPE ... SYSTEM/PUBLIC) are not allowed"
    return None
