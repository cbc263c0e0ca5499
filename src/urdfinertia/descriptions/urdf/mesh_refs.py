"""Keep relative mesh references working when the output lands in another folder.

``fix robot.urdf -o elsewhere/robot.urdf`` copies the document; a ``<mesh
filename="meshes/arm.stl"/>`` would then point at ``elsewhere/meshes/arm.stl``, which does
not exist. :func:`relocate_mesh_refs` rewrites each relative reference so that it resolves
from the output's folder to the same file, splicing only the attribute values (every other
byte stays). ``package://``, ``file://``, ``model://``, other schemes, absolute paths and
values holding an unexpanded ``$(...)`` or an XML reference are left as they are.
"""

from __future__ import annotations

import os
import re
from pathlib import Path, PurePosixPath

_MESH_FILENAME = re.compile(
    rb"""<mesh\b[^>]*?\sfilename\s*=\s*(?:"([^"]*)"|'([^']*)')""", re.S)
_COMMENT = re.compile(rb"<!--.*?-->", re.S)
_SCHEME = re.compile(r"[A-Za-z][A-Za-z0-9+.-]*:")


def is_relative_ref(uri: str) -> bool:
    """A plain relative path (what depends on the document's own folder)."""
    if not uri or _SCHEME.match(uri) or "$(" in uri or "&" in uri:
        return False
    return not (uri.startswith(("/", "\\")) or Path(uri).is_absolute())


def relocate_mesh_refs(data: bytes, source_dir: Path, output_dir: Path,
                       ) -> tuple[bytes, int]:
    """``data`` with relative mesh references rewritten to resolve from ``output_dir``
    as they did from ``source_dir``; and how many were rewritten."""
    source_dir = Path(os.path.abspath(source_dir))
    output_dir = Path(os.path.abspath(output_dir))
    if source_dir == output_dir:
        return data, 0
    comments = [m.span() for m in _COMMENT.finditer(data)]
    edits: list[tuple[int, int, bytes]] = []
    for m in _MESH_FILENAME.finditer(data):
        group = 1 if m.group(1) is not None else 2
        start, end = m.span(group)
        if any(a <= start < b for a, b in comments):
            continue
        try:
            uri = m.group(group).decode("utf-8")
        except UnicodeDecodeError:
            continue
        if not is_relative_ref(uri):
            continue
        target = os.path.normpath(source_dir / uri)
        new = PurePosixPath(*Path(os.path.relpath(target, output_dir)).parts).as_posix()
        if new != uri:
            edits.append((start, end, new.encode("utf-8")))
    if not edits:
        return data, 0
    out = bytearray()
    pos = 0
    for start, end, text in edits:
        out += data[pos:start] + text
        pos = end
    out += data[pos:]
    return bytes(out), len(edits)
