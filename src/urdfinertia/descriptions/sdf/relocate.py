"""Keep an SDFormat document's relative `<uri>` references working from another folder.

libsdformat and Gazebo resolve a relative URI (a mesh's, a heightmap's, a material
script's, an `<include>`'s) against the document's folder, and so do the PBR texture
maps (`<albedo_map>` ...). When the document is written elsewhere each such text is
rewritten to name the same file from the output's folder; `model://`, `package://`,
`file://` and other schemes, absolute paths and texts holding a reference or markup are
left as they are. Only the element text changes; its surrounding whitespace stays.
"""

from __future__ import annotations

from pathlib import Path

from urdfinertia.descriptions.references import (
    is_relative_ref,
    relocated,
    same_folder,
    splice_edits,
)
from urdfinertia.descriptions.splice import next_tag

PATH_ELEMENTS = frozenset({
    b"uri", b"albedo_map", b"normal_map", b"roughness_map", b"metalness_map",
    b"emissive_map", b"light_map", b"environment_map", b"ambient_occlusion_map",
})
"""Elements whose text is a path relative to the document's folder."""


def relocate_sdf_refs(data: bytes, source_dir: Path, output_dir: Path,
                      ) -> tuple[bytes, int]:
    """`data` with its relative URIs rewritten to resolve from `output_dir` as they did
    from `source_dir`; and how many were rewritten."""
    if same_folder(source_dir, output_dir):
        return data, 0
    edits: list[tuple[int, int, bytes]] = []
    pos = 0
    while True:
        m = next_tag(data, pos)
        if m is None:
            break
        pos = m.end()
        closing, name, selfclose = m.group(5), m.group(6), m.group(8)
        if closing or selfclose or name.rpartition(b":")[2] not in PATH_ELEMENTS:
            continue
        end = data.find(b"<", pos)
        if end < 0 or not data.startswith(b"</" + name, end):
            continue  # markup inside: not a plain path
        raw = data[pos:end]
        try:
            text = raw.decode("utf-8")
        except UnicodeDecodeError:
            continue
        uri = text.strip()
        if not is_relative_ref(uri):
            continue
        new = relocated(uri, source_dir, output_dir)
        if new != uri:
            lead = len(text) - len(text.lstrip())
            start = pos + len(text[:lead].encode())
            edits.append((start, start + len(uri.encode()), new.encode("utf-8")))
    return splice_edits(data, edits), len(edits)
