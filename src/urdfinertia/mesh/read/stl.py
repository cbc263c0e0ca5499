"""Read binary and ASCII STL like `trimesh.exchange.stl` with `process=False`.

Every facet gets its own three vertices, in file order (no merging): vertex `3 i + k`
is corner `k` of facet `i`. A file whose size matches the facet count of its binary
header is binary, whatever its first bytes say; any other file is read as ASCII.
"""

from __future__ import annotations

import re

import numpy as np

from urdfinertia.mesh.read.common import NeedsTrimesh, Piece, parse_floats

_HEADER = 84
_RECORD = np.dtype([("normals", "<f4", (3,)), ("vertices", "<f4", (3, 3)),
                    ("attributes", "<u2")])
_VERTEX_LINE = re.compile(rb"vertex([^\n]*)")


def read_stl(data: bytes) -> list[Piece]:
    """The triangles of an STL file's bytes (an empty list when it holds none).

    Raises
    ------
    NeedsTrimesh
        Non-ASCII text, several solids (trimesh merges their vertices) or text laid
        out so that trimesh's line slicing differs from a plain line split.
    ValueError
        Malformed numbers (trimesh fails on them as well).
    """
    if len(data) >= _HEADER:
        count = int.from_bytes(data[80:_HEADER], "little")
        if len(data) - _HEADER == count * _RECORD.itemsize:
            if count == 0:
                return []
            blob = np.frombuffer(data, dtype=_RECORD, offset=_HEADER)
            vertices = np.asarray(blob["vertices"].reshape((-1, 3)), order="C",
                                  dtype=np.float64)
            faces = np.arange(count * 3, dtype=np.int64).reshape((-1, 3))
            return [Piece(vertices, faces)]
    return _read_ascii(data)


def _read_ascii(data: bytes) -> list[Piece]:
    """`load_stl_ascii`: every `solid ... endsolid` block with three or more numbers.

    trimesh strips and lower-cases the decoded text; for ASCII text the lower-cased
    bytes hold the same blocks (stripping only moves them), without two more copies.
    """
    if not data.isascii():
        raise NeedsTrimesh("non-ASCII text STL")
    raw = data.lower()
    solids = []
    position = 0
    for _ in range(len(raw)):
        start = raw.find(b"solid", position)
        end = raw.find(b"endsolid", position)
        position = end + len(b"endsolid")
        if end < 0 or start < 0:
            break
        if start > end:
            raise NeedsTrimesh("'endsolid' before 'solid'")
        vertices = _vertex_numbers(raw, start, end)
        if len(vertices) < 3:
            continue
        if len(vertices) % 3 != 0:
            raise NeedsTrimesh("vertex coordinates not in threes")
        solids.append(vertices.reshape((-1, 3)))
    if not solids:
        return []
    if len(solids) > 1:
        raise NeedsTrimesh("several solids (trimesh processes and merges them)")
    vertices = solids[0]
    faces = np.arange(len(vertices), dtype=np.int64).reshape((-1, 3))
    return [Piece(vertices, faces)]


def _vertex_numbers(raw: bytes, start: int, end: int) -> np.ndarray:
    """The numbers after each `vertex` keyword of `raw[start:end]` up to its line's end.

    trimesh splits the block on `vertex` and cuts each piece at its first newline; that
    is one regular-expression capture per keyword as long as no line holds two keywords
    and the last one is followed by a newline.
    """
    captures = _VERTEX_LINE.findall(raw, start, end)
    if len(captures) != raw.count(b"vertex", start, end):
        raise NeedsTrimesh("two 'vertex' keywords on one line")
    if captures and raw.find(b"\n", raw.rfind(b"vertex", start, end), end) < 0:
        raise NeedsTrimesh("last 'vertex' line has no newline")
    return parse_floats(b" ".join(captures))
