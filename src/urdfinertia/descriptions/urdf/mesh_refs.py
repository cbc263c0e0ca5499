"""Keep relative mesh references working when the output lands in another folder.

`fix robot.urdf -o elsewhere/robot.urdf` copies the document; a
`<mesh filename="meshes/arm.stl"/>` would then point at `elsewhere/meshes/arm.stl`, which does
not exist. `relocate_mesh_refs` rewrites each relative reference so that it resolves
from the output's folder to the same file, splicing only the attribute values (every other
byte stays). `package://`, `file://`, `model://`, other schemes, absolute paths and
values holding an unexpanded `$(...)` or an XML reference are left as they are
(`is_relative_ref`).
"""

from __future__ import annotations

import re
from pathlib import Path

from urdfinertia.descriptions.references import (
    is_relative_ref,
    relocated,
    same_folder,
    splice_edits,
)

_MESH_FILENAME = re.compile(
    rb"""<mesh\b[^>]*?\sfilename\s*=\s*(?:"([^"]*)"|'([^']*)')""", re.S)
_COMMENT = re.compile(rb"<!--.*?-->", re.S)

__all__ = ["is_relative_ref", "relocate_mesh_refs"]


def relocate_mesh_refs(data: bytes, source_dir: Path, output_dir: Path,
                       ) -> tuple[bytes, int]:
    """`data` with relative mesh references rewritten to resolve from `output_dir`
    as they did from `source_dir`; and how many were rewritten."""
    if same_folder(source_dir, output_dir):
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
        new = relocated(uri, source_dir, output_dir)
        if new != uri:
            edits.append((start, end, new.encode("utf-8")))
    return splice_edits(data, edits), len(edits)
