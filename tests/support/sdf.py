"""Helpers for SDFormat tests: documents from snippets, and the bytes outside inertials."""

from __future__ import annotations

import re

_INERTIAL = re.compile(rb"\s*<inertial\b[^>]*?/>|\s*<inertial\b.*?</inertial>", re.S)


def sdf_doc(body: str, version: str = "1.11") -> bytes:
    """A ``<sdf>`` document holding ``body`` (models, worlds)."""
    return f'<?xml version="1.0"?>\n<sdf version="{version}">\n{body}\n</sdf>\n'.encode()


def without_inertials(data: bytes) -> bytes:
    """The document with every ``<inertial>`` element (and the blank before it) removed."""
    return _INERTIAL.sub(b"", data)
