"""The one hardened XML parsing path: refuse hostile XML before any parser sees it.

Safe, not strict: beyond the security refusals, a document is read the way urdfdom and the
TinyXML-based loaders read it (`parse_document`'s `notes`): an XML declaration of
any version or after leading whitespace, undeclared namespace prefixes (`drake:`) and
stray content after the root element are read past with a note. Only the bytes given to
lxml are adjusted (same line numbers); the writers splice the original bytes.

lxml is already configured not to resolve entities or load DTDs (`safe_parser`), but
a document that *declares* entities or points at an external DTD has no legitimate use in
a robot description, so it is refused outright: no parser runs, nothing is read or fetched,
and the answer is immediate whatever the expansion factor of a "billion laughs" bomb.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import TYPE_CHECKING

from lxml import etree

from urdfinertia.errors import UrdfError
from urdfinertia.hostile import hostile_xml_cause

if TYPE_CHECKING:
    from urdfinertia.findings import Finding

MAX_XML_DEPTH = 256
"""Libxml2's nesting limit without XML_PARSE_HUGE (documented in the safety guide)."""
MAX_DOCUMENT_BYTES = 64 * 1024 * 1024
"""Largest description accepted, bytes (the biggest real ones are a few MB)."""
_ENCODINGS = {"utf-8", "utf8", "us-ascii", "ascii"}
"""Encodings the byte-level patchers can splice safely."""


class _DenyResolver(etree.Resolver):
    """Answers every external-resource request with an empty document (defence in depth)."""

    def resolve(self, url, pubid, context):  # noqa: ANN001 - lxml's signature
        return self.resolve_string("", context)


def safe_parser() -> etree.XMLParser:
    """The only XML parser this package uses: no entities, no DTD, no network, no files.

    `huge_tree=False` keeps libxml2's limits: nesting depth 256, text nodes and
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


def parse_document(data: bytes, file: str | Path, roots: tuple[str, ...],
                   notes: list[Finding] | None = None) -> etree._Element:
    """Parse a description's bytes into an lxml root element, refusing hostile constructs.

    The one parsing path of every description format. Checked before lxml runs: size
    (`MAX_DOCUMENT_BYTES`), entity declarations, external DTDs and UTF-16/32
    encodings (`hostile_xml_cause`). lxml then runs with `safe_parser`
    (libxml2's default limits: nesting depth `MAX_XML_DEPTH`). The root element
    must be one of `roots`.

    What urdfdom reads is read (see the module docstring); each such leniency is appended
    to `notes` as a [`Finding`][urdfinertia.findings.Finding] (`xml-read-leniently`).
    A document that is not XML, or is cut off inside its root element, stays an error.
    """
    if len(data) > MAX_DOCUMENT_BYTES:
        raise UrdfError(f"file is larger than the limit of {MAX_DOCUMENT_BYTES} bytes",
                        file=file)
    cause = hostile_xml_cause(data)
    if cause:
        raise UrdfError(cause, file=file)
    found: list[tuple[str, str, int | None]] = []
    text, declared = _plain_declaration(data, found)
    root = _parse_leniently(text, file, found)
    encoding = (declared or root.getroottree().docinfo.encoding or "utf-8").lower()
    if encoding not in _ENCODINGS:
        raise UrdfError(f"encoding '{encoding}' is not supported: convert the file to UTF-8",
                        file=file)
    if not isinstance(root.tag, str) or root.tag not in roots:
        expected = " or ".join(f"<{r}>" for r in roots)
        raise UrdfError(f"root element is <{root.tag}>, expected {expected}", file=file,
                        line=root.sourceline)
    if notes is not None and found:
        from urdfinertia.findings import Finding
        from urdfinertia.rules import Rule

        notes.extend(Finding(Rule.XML_READ_LENIENTLY, None, cause, line)
                     for _, cause, line in found)
    return root


_DECLARATION = re.compile(
    rb"\A(\xef\xbb\xbf)?((?:\s|<!--(?:(?!-->).)*-->)*)(<\?xml(?=\s)(.{0,400}?)\?>)", re.S)
r"""An XML declaration anywhere in the prolog (after a BOM, whitespace, comments or nothing:
Cassie's .world puts a licence comment first, which TinyXML-based loaders accept). Each repetition
has one way to match (one whitespace character, or one comment up to its first `-->`): nested `\s+`
or a lazy comment body that may run on to a later `-->` backtrack exponentially on a file with no
declaration and many comments.
"""
_DECLARED_VERSION = re.compile(rb"""\bversion\s*=\s*["']1\.[0-9]+["']""")
_DECLARED_ENCODING = re.compile(rb"""\bencoding\s*=\s*["']([A-Za-z0-9._-]{1,40})["']""")
_ERR_UNDEFINED_PREFIX = 201
"""Libxml2 error codes read past: undefined namespace prefix, content after the root."""
_ERR_EXTRA_CONTENT = 5
UNDECLARED_NAMESPACE = "urn:urdfinertia:undeclared:"
"""Namespace given to undeclared prefixes (never a real one; tags become unknown names)."""
_PREFIX_USE = re.compile(rb"[<\s/]([A-Za-z_][\w.-]*):[A-Za-z_][\w.-]*")
_PREFIX_DECL = re.compile(rb"\bxmlns:([A-Za-z_][\w.-]*)\s*=")
_ROOT_TAG = re.compile(rb"<([A-Za-z_][\w.:-]*)")


def _plain_declaration(data: bytes, found: list) -> tuple[bytes, str | None]:
    """`data` with an XML declaration lxml refuses (version other than 1.x, or after
    whitespace) blanked out with spaces, and the encoding it declares (or None)."""
    m = _DECLARATION.match(data)
    if m is None:
        return data, None
    decl = m.group(3)
    enc = _DECLARED_ENCODING.search(decl)
    declared = enc.group(1).decode("ascii") if enc else None
    at_start = not m.group(2)
    if at_start and _DECLARED_VERSION.search(decl):
        return data, None  # lxml reads it as it is
    line = data.count(b"\n", 0, m.start(3)) + 1
    why = ("is not at the very start of the file" if not at_start
           else "declares an XML version other than 1.x")
    found.append(("xml-declaration", f"the XML declaration {why}: read as XML 1.0", line))
    blank = bytes(c if c in b"\r\n" else 32 for c in decl)
    return data[:m.start(3)] + blank + data[m.end(3):], declared


def _parse_leniently(text: bytes, file: str | Path, found: list) -> etree._Element:
    """lxml on `text`; undeclared prefixes and content after the root are read past
    (each at most once), anything else is the error it is."""
    declared_prefixes = False
    cut = False
    while True:
        try:
            return etree.fromstring(text, parser=safe_parser())
        except etree.XMLSyntaxError as exc:
            code = getattr(exc, "code", None)
            if code == _ERR_UNDEFINED_PREFIX and not declared_prefixes:
                declared_prefixes = True
                fixed = _declare_prefixes(text, found)
                if fixed is not None:
                    text = fixed
                    continue
            if code == _ERR_EXTRA_CONTENT and not cut and exc.position:
                cut = True
                end = _offset(text, *exc.position)
                if end is not None and text[end:].strip():
                    found.append(("trailing-content", "content after the root element "
                                  "is ignored", exc.position[0]))
                    text = text[:end]
                    continue
            raise _syntax_error(exc, file) from None
        except ValueError as exc:  # lxml refuses e.g. a str with an encoding declaration
            raise UrdfError(f"malformed XML: {exc}", file=file) from None


def _declare_prefixes(text: bytes, found: list) -> bytes | None:
    """`text` with every undeclared prefix declared on the root start tag (same line,
    so line numbers hold), or None when there is nothing to declare."""
    declared = set(_PREFIX_DECL.findall(text)) | {b"xml", b"xmlns"}
    used = dict.fromkeys(p for p in _PREFIX_USE.findall(text) if p not in declared)
    root = _ROOT_TAG.search(text, _prolog_end(text))
    if not used or root is None:
        return None
    names = ", ".join(p.decode() for p in used)
    found.append(("undeclared-prefix", f"undeclared namespace prefix(es) {names}: "
                  "elements and attributes so named are ignored", None))
    extra = b"".join(b' xmlns:' + p + b'="' + UNDECLARED_NAMESPACE.encode() + p + b'"'
                     for p in used)
    return text[:root.end()] + extra + text[root.end():]


_PROLOG_ITEM = re.compile(rb"\s+|<\?.*?\?>|<!--.*?-->|<![^>]*>", re.S)


def _prolog_end(text: bytes) -> int:
    pos = 3 if text.startswith(b"\xef\xbb\xbf") else 0
    while m := _PROLOG_ITEM.match(text, pos):
        pos = m.end()
    return pos


def _offset(text: bytes, line: int, column: int) -> int | None:
    """Byte offset of libxml2's (line, column), both 1-based."""
    pos = 0
    for _ in range(line - 1):
        pos = text.find(b"\n", pos) + 1
        if pos == 0:
            return None
    return min(pos + max(column - 1, 0), len(text))


def _syntax_error(exc: etree.XMLSyntaxError, file: str | Path) -> UrdfError:
    line = exc.lineno if getattr(exc, "lineno", None) else None
    msg = getattr(exc, "msg", None) or str(exc)
    if "Excessive depth" in msg:
        msg = f"elements nested deeper than {MAX_XML_DEPTH} levels"
    return UrdfError(f"malformed XML: {msg}", file=file, line=line)
