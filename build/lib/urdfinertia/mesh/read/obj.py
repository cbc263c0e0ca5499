"""Read Wavefront OBJ like ``trimesh.exchange.obj.load_obj`` (``skip_materials=True``).

trimesh's layout is reproduced exactly: face lines are grouped by ``usemtl`` name (one
mesh per material, taken last group first), a mesh keeps only the vertices its faces
use, in order, and splits a vertex used with several texture or normal indices into
copies (trimesh's ``unmerge_faces``); quads become two triangles and larger polygons
fans. Positive indices are 1-based, negative ones count from the end of the file's
vertex list (numpy indexing), as in trimesh.

Vertex lines are parsed as trimesh does (one ``np.fromstring`` per kind); face lines
are split with numpy on the bytes, without a Python loop over lines.
"""

from __future__ import annotations

import itertools
import re

import numpy as np

from urdfinertia.mesh.read.common import (
    NeedsTrimesh,
    Piece,
    hashable_rows,
    parse_floats,
    parse_ints,
)

_FACE_LINE = re.compile(r"^f([^\n]*)", re.MULTILINE)
_STARTERS = ("\nusemtl ", "\no ", "\nf ", "\ng ", "\ns ")
#: Bytes a face line may hold for the vectorised split: digits, signs, '/', blanks.
_FACE_BYTES = b"0123456789+-/ \t\n"
_NEWLINE, _SLASH, _PLUS, _MINUS = (ord(c) for c in "\n/+-")
_BLANK = np.zeros(256, dtype=bool)
_BLANK[[ord(" "), ord("\t"), _NEWLINE]] = True
_CUT = _BLANK.copy()
_CUT[_SLASH] = True
#: Longest index accepted (int64 parses it exactly).
_MAX_DIGITS = 18


def read_obj(data: bytes) -> list[Piece]:
    """The meshes of an OBJ file's bytes, in trimesh's scene order.

    Raises
    ------
    NeedsTrimesh
        Input trimesh reads differently from this module: non-UTF-8 text, ragged
        vertex rows, face lines with anything but integers, ``/`` and
        blanks, an object named ``world`` (trimesh's scene root).
    ValueError, IndexError
        Malformed numbers or indices (trimesh fails on them as well).
    """
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        raise NeedsTrimesh("not UTF-8 text") from None
    text = "\n{}\n".format(text.strip().replace("\r\n", "\n"))
    text = text.replace("\\\n", "")
    v, has_vn = _parse_vertices(text)
    groups = _group_by_material(_preprocess_faces(text))
    if v is None or not groups:
        return []  # no vertices, or a point cloud: no triangles either way
    pieces = []
    for obj_name, chunk in reversed(groups):  # trimesh pops the groups from the end
        if obj_name == "world":
            raise NeedsTrimesh("an object named 'world' collides with trimesh's root")
        faces, faces_tex, faces_norm = _chunk_faces(chunk)
        vertices, faces = _mesh_arrays(v, has_vn, faces, faces_tex, faces_norm)
        pieces.append(Piece(vertices, _triangulate(faces)))
    return pieces


# --- vertices ----------------------------------------------------------------------------

def _parse_vertices(text: str) -> tuple[np.ndarray | None, bool]:
    """``v`` positions (or None) and whether ``vn`` lines exist (trimesh's _parse_vertices).

    ``vt`` and ``vn`` rows are parsed as well, because trimesh fails on malformed ones.
    """
    starts = {k: text.find(f"\n{k} ") for k in ("v", "vt", "vn")}
    if not any(s >= 0 for s in starts.values()):
        return None, False
    ends = {k: text.find("\n", text.rfind(f"\n{k} ") + 2 + len(k))
            for k, s in starts.items() if s >= 0}
    start = min(s for s in starts.values() if s >= 0)
    end = max(e for e in ends.values() if e >= 0)
    chunk = text[start:end].replace("+e", "e").replace("-e", "e")
    result = {}
    for k, s in starts.items():
        if s < 0:
            continue
        rows = re.findall(f"\n{k} ([^\n]*)", chunk)
        array = parse_floats(" ".join(rows))
        shape = (len(rows), len(rows[0].split()))
        if len(array) != np.prod(shape):
            raise NeedsTrimesh(f"'{k}' rows of different lengths")
        result[k] = array.reshape(shape)
    v = result.get("v")
    if v is not None:
        if v.shape[1] < 3:
            raise NeedsTrimesh("vertices with fewer than three coordinates")
        v = v[:, :3]  # what follows is a weight or a colour (trimesh keeps it aside)
    return v, "vn" in result


# --- face groups -----------------------------------------------------------------------

def _preprocess_faces(text: str) -> list[tuple[str | None, str | None, str]]:
    """(material, object, face text) chunks split at every ``usemtl``, as trimesh does."""
    f_start = len(text)
    for starter in _STARTERS:
        found = text.find(starter, 0, f_start)
        if 0 <= found < f_start:
            f_start = found
    f_end = text.find("\n", text.rfind("\nf ") + 3)
    f_chunk = text[f_start:f_end] if f_end >= 0 else text[f_start:]
    idx_mtl = [m.start(0) for m in re.finditer("usemtl ", f_chunk)]
    splits = np.unique(np.concatenate(([0, len(f_chunk)], np.array(idx_mtl, dtype=int))))
    current_obj = current_mtl = None
    tuples = []
    for start, end in itertools.pairwise(splits):
        chunk = f_chunk[start:end].strip() + "\n"
        if chunk.startswith("o "):
            current_obj, chunk = chunk.split("\n", 1)
            current_obj = current_obj[2:].strip()
        elif chunk.startswith("usemtl"):
            current_mtl, chunk = chunk.split("\n", 1)
            current_mtl = current_mtl[6:].strip()
        elif chunk.startswith("g "):
            chunk = chunk.split("\n", 1)[1]
        if chunk.startswith("f ") or "\nf" in chunk:
            tuples.append((current_mtl, current_obj, chunk))
    return tuples


def _group_by_material(tuples: list[tuple[str | None, str | None, str]]
                       ) -> list[tuple[str | None, str]]:
    """(object name, joined face text) per material, in first-use order (trimesh _group_by).

    The object name is the last one seen for the material, as in trimesh.
    """
    grouped: dict[str | None, tuple[str | None, list[str]]] = {}
    for material, obj, chunk in tuples:
        chunks = grouped[material][1] if material in grouped else []
        chunks.append(chunk)
        grouped[material] = (obj, chunks)
    return [(obj, "\n".join(chunks)) for obj, chunks in grouped.values()]


# --- faces -----------------------------------------------------------------------------

def _chunk_faces(chunk: str) -> tuple[np.ndarray, np.ndarray | None, np.ndarray | None]:
    """Vertex, texture and normal indices of a chunk's face lines, 0-based where positive.

    Lines with the same number of integers take trimesh's vectorised route (the sample
    line decides what the columns mean); other chunks its per-line route (quads split
    0-1-2 / 2-3-0, polygons fanned, lines with fewer than three corners skipped). The
    byte scans keep one flag per byte at a time; positions are kept per index only.
    """
    lines = _FACE_LINE.findall(chunk)
    raw = "\n".join(lines)
    if not raw.isascii():
        raise NeedsTrimesh("non-ASCII face line")
    body = raw.encode("ascii")
    del raw
    if body.translate(None, _FACE_BYTES):
        raise NeedsTrimesh("face line with characters other than indices")
    buf = np.frombuffer(body, dtype=np.uint8)
    cut = _CUT[buf]  # blank or '/': ends an index
    starts = np.flatnonzero(~cut & np.concatenate(([True], cut[:-1])))
    ends = np.flatnonzero(~cut & np.concatenate((cut[1:], [True]))) + 1
    del cut
    if len(starts) == 0:
        raise NeedsTrimesh("face lines without indices")
    if np.max(ends - starts) > _MAX_DIGITS:
        raise NeedsTrimesh("index with too many digits")
    signs = np.flatnonzero((buf == _PLUS) | (buf == _MINUS))
    if len(signs):
        at_start = np.isin(signs, starts)
        next_byte = buf[np.minimum(signs + 1, len(buf) - 1)]
        if not (at_start & (signs + 1 < len(buf)) & (next_byte >= ord("0"))
                & (next_byte <= ord("9"))).all():
            raise NeedsTrimesh("sign inside an index")
    values = parse_ints(body.replace(b"/", b" "))
    if len(values) != len(starts):
        raise NeedsTrimesh("indices numpy splits differently")
    newlines = np.flatnonzero(buf == _NEWLINE)
    per_line = np.bincount(np.searchsorted(newlines, starts), minlength=len(lines))
    if np.all(per_line == per_line[0]):
        array = values.copy()
        array[array > 0] -= 1
        return _parse_faces_vectorized(array, int(per_line[0]), lines[0].strip())
    return _parse_faces_fallback(buf, newlines, starts, values, len(lines))


def _parse_faces_vectorized(array: np.ndarray, columns: int, sample_line: str
                            ) -> tuple[np.ndarray, np.ndarray | None, np.ndarray | None]:
    """trimesh's ``_parse_faces_vectorized``: columns read by the sample line's layout."""
    array = array.reshape((-1, columns))
    group_count = len(sample_line.split())
    per_ref = int(columns / group_count)
    index = np.arange(group_count) * per_ref
    faces = array[:, index]
    faces_tex = faces_norm = None
    if columns == group_count * 2:
        count = "".join(i.strip("/") for i in sample_line.split()).count("/")
        if count == columns:
            faces_norm = array[:, index + 1]
        elif count == int(columns / 2):
            faces_tex = array[:, index + 1]
    elif columns == group_count * 3:
        faces_tex = array[:, index + 1]
        faces_norm = array[:, index + 2]
    return faces, faces_tex, faces_norm


def _parse_faces_fallback(buf: np.ndarray, newlines: np.ndarray, piece_starts: np.ndarray,
                          values: np.ndarray, n_lines: int
                          ) -> tuple[np.ndarray, np.ndarray | None, np.ndarray | None]:
    """trimesh's ``_parse_faces_fallback`` over the whole chunk at once.

    Each corner ``v/vt/vn`` must have its vertex index (trimesh calls ``int`` on it);
    texture and normal indices are kept only when every used corner has them.
    """
    blank = _BLANK[buf]
    ref_first = np.flatnonzero(~blank & np.concatenate(([True], blank[:-1])))
    del blank
    n_refs = len(ref_first)
    slashes = np.flatnonzero(buf == _SLASH)
    piece_ref = np.searchsorted(ref_first, piece_starts, side="right") - 1
    piece_field = (np.searchsorted(slashes, piece_starts)
                   - np.searchsorted(slashes, ref_first)[piece_ref])
    fields = []
    for k in range(3):
        has = np.zeros(n_refs, dtype=bool)
        val = np.zeros(n_refs, dtype=np.int64)
        pick = piece_field == k
        has[piece_ref[pick]] = True
        val[piece_ref[pick]] = values[pick]
        fields.append((has, val))
    if not fields[0][0].all():
        raise NeedsTrimesh("corner without a vertex index")
    refs_per_line = np.bincount(np.searchsorted(newlines, ref_first), minlength=n_lines)
    first_ref = np.concatenate(([0], np.cumsum(refs_per_line)[:-1]))
    used = np.flatnonzero(refs_per_line >= 3)
    n = refs_per_line[used]
    n_tri = n - 2
    tri_line = np.repeat(np.arange(len(used)), n_tri)
    local = np.arange(len(tri_line)) - np.repeat(np.cumsum(n_tri) - n_tri, n_tri)
    base = first_ref[used][tri_line]
    corners = np.stack((base, base + local + 1, base + local + 2), axis=1)
    quad_second = (n[tri_line] == 4) & (local == 1)
    corners[quad_second] = np.stack((base + 2, base + 3, base), axis=1)[quad_second]
    seq = corners.reshape(-1)
    out = []
    for k, (has, val) in enumerate(fields):
        if k > 0 and not has[seq].all():
            out.append(None)
            continue
        idx = val[seq].reshape((-1, 3))
        idx[idx > 0] -= 1
        out.append(idx)
    return out[0], out[1], out[2]


# --- meshes ----------------------------------------------------------------------------

def _mesh_arrays(v: np.ndarray, has_vn: bool, faces: np.ndarray,
                 faces_tex: np.ndarray | None, faces_norm: np.ndarray | None
                 ) -> tuple[np.ndarray, np.ndarray]:
    """The vertices one mesh keeps and its faces re-indexed (trimesh's load_obj)."""
    if faces_tex is not None:
        if faces_norm is not None and len(faces_norm) == len(faces):
            new_faces, mask_v = _unmerge_faces(faces, faces_tex, faces_norm)
        else:
            new_faces, mask_v = _unmerge_faces(faces, faces_tex)
    elif has_vn and np.shape(faces_norm) == faces.shape:
        new_faces, mask_v = _unmerge_faces(faces, faces_norm)
    else:
        mask_v = np.zeros(len(v), dtype=bool)
        mask_v[faces] = True
        inverse = np.zeros(len(v), dtype=np.int64)
        inverse[mask_v] = np.arange(mask_v.sum())
        new_faces = inverse[faces]
    return np.asarray(v[mask_v], order="C", dtype=np.float64), new_faces


def _unmerge_faces(faces: np.ndarray, *args: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """trimesh's ``unmerge_faces``: one vertex per distinct (v, vt, vn) index tuple."""
    stack = np.column_stack([np.asanyarray(faces).reshape(-1)]
                            + [np.asanyarray(a).reshape(-1) for a in args])
    unique, inverse = np.unique(hashable_rows(stack), return_index=True,
                                return_inverse=True)[1:]
    pairs = stack[unique]
    order = pairs[:, 0].argsort()
    pairs = pairs[order]
    remap = np.zeros(len(order), dtype=np.int64)
    remap[order] = np.arange(len(order))
    new_faces = remap[inverse].reshape((-1, faces.shape[1]))
    return new_faces, pairs[:, 0]


def _triangulate(faces: np.ndarray) -> np.ndarray:
    """Trimesh's ``faces`` setter: quads split 0-1-2 / 2-3-0 (all first halves first)."""
    faces = np.asanyarray(faces, dtype=np.int64)
    if faces.ndim != 2 or faces.shape[1] == 3:
        return faces
    if len(faces) == 0 or faces.shape[1] < 3:
        return np.zeros((0, 3), dtype=np.int64)
    if faces.shape[1] == 4:
        return np.vstack((faces[:, [0, 1, 2]], faces[:, [2, 3, 0]]))
    fan = [[0, i + 1, i + 2] for i in range(faces.shape[1] - 2)]
    return faces[:, fan].reshape((-1, 3))
