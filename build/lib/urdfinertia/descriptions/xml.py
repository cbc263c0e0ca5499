"""The one hardened XML parsing path: refuse hostile XML before any parser sees it.

lxml is already configured not to resolve entities or load DTDs (:func:`safe_parser`), but
a document that *declares* entities or points at an external DTD has no legitimate use in
a robot description, so it is refused outright: no parser runs, nothing is read or fetched,
and the answer is immediate whatever the expansion factor of a "billion laughs" bomb.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import BinaryIO

from lxml import etree

from urdfinertia.errors import UrdfError

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
#: libxml2's nesting limit without XML_PARSE_HUGE (documented in README).
MAX_XML_DEPTH = 256
#: Largest description accepted, bytes (the biggest real ones are a few MB).
MAX_DOCUMENT_BYTES = 64 * 1024 * 1024
#: Encodings the byte-level patchers can splice safely.
_ENCODINGS = {"utf-8", "utf8", "us-ascii", "ascii"}


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


class _DenyResolver(etree.Resolver):
    """Answers every external-resource request with an empty document (defence in depth)."""

    def resolve(self, url, pubid, context):  # noqa: ANN001 - lxml's signature
        return self.resolve_string("", context)


def safe_parser() -> etree.XMLParser:
    """The only XML parser this package uses: no entities, no DTD, no network, no files.

    ``huge_tree=False`` keeps libxml2's limits: nesting depth 256, text nodes and
    attribute values 10 MB, entity amplification checks.
    """
    parser = etree.XMLParser(
        resolve_entities=False,
        no_network=True,
        load_dtd=False,
        dtd_validation=False,
        attribute_defaults=False,
        huge_tree=False,
        remove_comments=False,
        remove_pis=False,
        strip_cdata=False,
    )
    parser.resolvers.add(_DenyResolver())
    return parser


def parse_document(data: bytes, file: str | Path, roots: tuple[str, ...]) -> etree._Element:
    """Parse a description's bytes into an lxml root element, refusing hostile constructs.

    The one parsing path of every description format. Checked before lxml runs: size
    (:data:`MAX_DOCUMENT_BYTES`), entity declarations, external DTDs and UTF-16/32
    encodings (:func:`hostile_xml_cause`). lxml then runs with :func:`safe_parser`
    (libxml2's default limits: nesting depth :data:`MAX_XML_DEPTH`). The root element
    must be one of ``roots``.
    """
    if len(data) > MAX_DOCUMENT_BYTES:
        raise UrdfError(f"file is larger than the limit of {MAX_DOCUMENT_BYTES} bytes",
                        file=file)
    cause = hostile_xml_cause(data)
    if cause:
        raise UrdfError(cause, file=file)
    try:
        root = etree.fromstring(data, parser=safe_parser())
    except etree.XMLSyntaxError as exc:
        line = exc.lineno if getattr(exc, "lineno", None) else None
        msg = getattr(exc, "msg", None) or str(exc)
        if "Excessive depth" in msg:
            msg = f"elements nested deeper than {MAX_XML_DEPTH} levels"
        raise UrdfError(f"malformed XML: {msg}", file=file, line=line) from None
    except ValueError as exc:  # lxml refuses e.g. a str with an encoding declaration
        raise UrdfError(f"malformed XML: {exc}", file=file) from None
    encoding = (root.getroottree().docinfo.encoding or "utf-8").lower()
    if encoding not in _ENCODINGS:
        raise UrdfError(f"encoding '{encoding}' is not supported: convert the file to UTF-8",
                        file=file)
    if not isinstance(root.tag, str) or root.tag not in roots:
        expected = " or ".join(f"<{r}>" for r in roots)
        raise UrdfError(f"root element is <{root.tag}>, expected {expected}", file=file,
                        line=root.sourceline)
    return root
