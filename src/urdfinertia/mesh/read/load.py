"""Read mesh files (STL, OBJ, DAE, PLY, GLB/glTF, OFF) into plain vertex/face arrays.

A scene's node transforms are applied and every piece is concatenated into one array pair;
splitting into bodies happens later (`urdfinertia.mesh.solids`). COLLADA `<unit meter>`
is honoured, as RViz and Gazebo do.

The readers form a registry by suffix (`_NATIVE`): STL by this package's own reader
(`.stl`: trimesh's arrays, less memory on ASCII files), OBJ by trimesh's own loader
called directly (`.obj`), COLLADA by a direct reader of trimesh's arrays with
trimesh's loader behind it (`.dae`, `.collada`); PLY, GLB/glTF and OFF,
and the rare STL the native reader leaves aside, through `trimesh.load`. Every file is
size-checked, face-counted and (COLLADA) scanned for hostile XML before a parser runs.
"""

from __future__ import annotations

import io
import re
import stat
import struct
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any, BinaryIO

import numpy as np

from urdfinertia.errors import MeshError
from urdfinertia.hostile import hostile_xml_stream_cause
from urdfinertia.mesh.limits import BYTES_PER_FACE, DEFAULT_MAX_FACES, max_mesh_bytes
from urdfinertia.mesh.read.common import NeedsTrimesh, Piece, TooManyFaces
from urdfinertia.mesh.read.dae import read_dae
from urdfinertia.mesh.read.msh import msh_face_count, read_msh
from urdfinertia.mesh.read.obj import read_obj
from urdfinertia.mesh.read.stl import read_stl
from urdfinertia.quiet import library_output
from urdfinertia.rules import Rule

SUPPORTED_SUFFIXES = (".stl", ".obj", ".dae", ".ply", ".glb", ".gltf", ".off", ".msh")
_CHUNK = 1 << 20
MAX_COORDINATE = 1e9
"""Largest vertex coordinate accepted, m (after unit scaling): fifth powers stay finite."""
_UNIT_HEAD = 65536
"""Bytes of a COLLADA file searched for `<unit meter>`."""
_IDENTITY_BYTES = np.eye(4).tobytes()


@dataclass(frozen=True, eq=False)
class TriangleMesh:
    """Triangles of one mesh file in the file's own frame (metres after unit scaling)."""

    vertices: np.ndarray  # (n, 3) float64
    faces: np.ndarray  # (m, 3) int64


def load_mesh(path: str | Path, max_faces: int = DEFAULT_MAX_FACES) -> TriangleMesh:
    """Load `path` without any repair or vertex merging, within bounded memory.

    Before any parser runs, the file's size is checked against `max_mesh_bytes` and
    its face count, where the format declares or cheaply reveals it, against
    `max_faces` (`declared_faces`). COLLADA files are refused when they declare
    XML entities or an external DTD. STL, OBJ and COLLADA files are read once, and these
    checks scan the bytes read. After loading, the triangle count (with every scene
    instance expanded) is checked again before the arrays are built.

    Raises
    ------
    MeshError
        Unsupported format, unreadable or corrupt file, no triangles, too large a file or
        more than `max_faces` faces.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in SUPPORTED_SUFFIXES:
        raise MeshError(f"unsupported mesh format '{suffix}' ({path}); "
                        f"supported: {', '.join(SUPPORTED_SUFFIXES)}",
                        rule=Rule.GEOMETRY_UNREADABLE)
    data = _checked_bytes(path, suffix, max_faces)
    # trimesh logs (with tracebacks) what it cannot load of a file, pycollada warns: kept
    # off the terminal, as debug lines (urdfinertia.quiet)
    with library_output(str(path)):
        pieces = _native_pieces(path, suffix, data, max_faces) if data is not None else None
        loaded = _load_scene(path, suffix) if pieces is None else None
        try:
            if pieces is None:
                pieces = _scene_pieces(loaded)
            vertices, faces = _concatenate(pieces, path, max_faces)
        except MeshError:
            raise
        except Exception as exc:  # a scene graph trimesh built from corrupt data
            raise MeshError(f"cannot read mesh {path}: {type(exc).__name__}: {exc}"
                            ) from None
    if len(faces) == 0:
        raise MeshError(f"mesh {path} holds no triangles", of_bytes=True)
    if suffix == ".dae" and data is not None:
        unit = _collada_unit(data[:_UNIT_HEAD], path)
    else:
        metadata = getattr(loaded, "metadata", None)
        unit = metadata.get("unit_meter") if metadata is not None else None
        if unit is not None and not (np.isfinite(unit) and unit > 0):
            raise MeshError(f"mesh {path} states a unit of {unit} m: not a positive length, "
                            "and no unit is guessed", rule=Rule.GEOMETRY_UNREADABLE, of_bytes=True)
    if unit and not np.isclose(unit, 1.0):
        vertices = vertices * unit
    if not np.all(np.isfinite(vertices)):
        raise MeshError(f"mesh {path} has non-finite vertex coordinates", of_bytes=True)
    if np.abs(vertices).max() > MAX_COORDINATE:
        raise MeshError(f"mesh {path} has vertex coordinates beyond {MAX_COORDINATE:g} m",
                        of_bytes=True)
    return TriangleMesh(vertices, faces)


def _checked_bytes(path: Path, suffix: str, max_faces: int) -> bytes | None:
    """The checks made before any parser runs; the file's bytes for the native formats.

    Other formats are scanned in chunks and left for trimesh to read (None).
    """
    try:
        info = path.stat()
        if not stat.S_ISREG(info.st_mode):
            raise MeshError(f"mesh {path} is not a regular file")
        limit = max_mesh_bytes(max_faces)
        if info.st_size > limit:
            raise _too_large(path, info.st_size, limit, max_faces)
        data = None
        with open(path, "rb") as stream:
            if suffix in _NATIVE:
                # a read of the stated size (a read of limit + 1 bytes would reserve
                # that much memory first), then of the rest up to the limit
                data = stream.read(info.st_size + 1)
                if len(data) > info.st_size:
                    data += stream.read(limit + 1 - len(data))
                if len(data) > limit:  # the file grew since stat
                    raise _too_large(path, len(data), limit, max_faces)
                declared = declared_faces_in(data, suffix)
            else:
                declared = declared_faces(stream, suffix, info.st_size)
            if declared is not None and declared > max_faces:
                raise _too_many(path, declared, max_faces)
            if suffix == ".dae":
                stream.seek(0)
                cause = _collada_cause(io.BytesIO(data) if data is not None else stream)
                if cause:
                    rule = (Rule.GEOMETRY_UNREADABLE if cause == ZIPPED_COLLADA
                            else Rule.MESH_REFUSED)
                    raise MeshError(f"cannot read mesh {path}: {cause}", rule=rule)
                if data is not None and collada_non_finite(data):
                    raise MeshError(f"mesh {path} has non-finite vertex coordinates (nan or "
                                    "inf in a <source> of positions)", of_bytes=True)
    except OSError as exc:
        raise MeshError(f"cannot read mesh {path}: {exc.strerror or exc}") from None
    return data


#: How to change the face limit, said for command line and library callers alike.
RAISE_LIMIT = "raise it with --max-faces, in Python max_faces="
LOWER_LIMIT = "lower --max-faces, in Python max_faces="


def _too_large(path: Path, size: int, limit: int, max_faces: int) -> MeshError:
    return MeshError(f"mesh {path} is {size} bytes, more than the limit {limit} bytes "
                     f"({BYTES_PER_FACE} bytes per face of the face limit {max_faces}; "
                     f"{RAISE_LIMIT})", rule=Rule.MESH_TOO_LARGE, of_bytes=True)


def _native_pieces(path: Path, suffix: str, data: bytes, max_faces: int
                   ) -> list[Piece] | None:
    """The file's pieces from its format's reader; None to read it with `trimesh.load`.

    The STL reader hands what it does not reproduce (several solids, ...) to trimesh;
    the OBJ and COLLADA readers are trimesh's own loaders, whose failure is final.
    """
    reader = _NATIVE[suffix]
    try:
        return reader(data, max_faces)
    except TooManyFaces as exc:
        raise _too_many(path, exc.faces, max_faces) from None
    except MemoryError:
        raise MeshError(f"cannot read mesh {path}: out of memory ({LOWER_LIMIT})"
                        ) from None
    except RecursionError:
        raise MeshError(f"cannot read mesh {path}: nested too deeply") from None
    except NeedsTrimesh:
        return None
    except Exception as exc:  # trimesh and pycollada raise many types for corrupt bytes
        if suffix == ".stl":
            return None
        # OBJ and COLLADA: trimesh's own loaders; .msh: trimesh reads no MuJoCo meshes, this
        # reader is the reference
        raise MeshError(f"cannot read mesh {path}: {type(exc).__name__}: {exc}") from None


def _read_stl(data: bytes, max_faces: int) -> list[Piece]:
    return read_stl(data)


def _read_msh(data: bytes, max_faces: int) -> list[Piece]:
    return read_msh(data)


_NATIVE: dict[str, Callable[[bytes, int], list[Piece]]] = {
    ".stl": _read_stl, ".obj": read_obj, ".dae": read_dae, ".msh": _read_msh}
"""The reader registry by suffix: reader(bytes, max_faces) -> pieces."""


def _too_many(path: Path, faces: int, max_faces: int) -> MeshError:
    return MeshError(f"mesh {path} has {faces} faces, more than the limit "
                     f"{max_faces} ({RAISE_LIMIT})", rule=Rule.MESH_TOO_LARGE, of_bytes=True)


def _load_scene(path: Path, suffix: str) -> Any:
    import trimesh

    kwargs: dict[str, Any] = {"skip_materials": True} if suffix == ".obj" else {}
    try:
        # trimesh's default resolver reads only files under the mesh's folder and
        # allow_remote=False keeps it off the network.
        return trimesh.load(str(path), force="scene", process=False,
                            file_type=suffix.lstrip("."), allow_remote=False, **kwargs)
    except MeshError:
        raise
    except MemoryError:
        raise MeshError(f"cannot read mesh {path}: out of memory ({LOWER_LIMIT})"
                        ) from None
    except RecursionError:
        raise MeshError(f"cannot read mesh {path}: nested too deeply") from None
    except Exception as exc:  # trimesh raises many types for corrupt bytes
        raise MeshError(f"cannot read mesh {path}: {type(exc).__name__}: {exc}") from None


# --- face counts before parsing ---------------------------------------------------------

def declared_faces(stream: BinaryIO, suffix: str, size: int) -> int | None:
    """Triangles the file holds, found without parsing it, or None when unknown.

    Binary STL, PLY and OFF headers state the count; ASCII STL, OBJ and COLLADA are
    scanned in chunks of `_CHUNK` bytes (a lower bound for polygons of more than three
    corners, checked again after loading). glTF/GLB counts are taken after loading.
    """
    head = stream.read(4096)
    stream.seek(0)
    if suffix == ".stl":
        if len(head) >= 84:
            count = int(struct.unpack("<I", head[80:84])[0])
            if size == 84 + 50 * count:
                return count
        return _count_pattern(stream, re.compile(rb"endfacet", re.IGNORECASE), 16)
    if suffix == ".obj":
        first = 1 if re.match(rb"f[ \t]", head) else 0
        return first + _count_pattern(stream, re.compile(rb"\nf[ \t]"), 8)
    if suffix == ".ply":
        match = re.search(rb"\belement\s+face\s+([0-9]{1,19})\b", head)
        return int(match.group(1)) if match else None
    if suffix == ".off":
        text = re.sub(rb"#[^\n]*", b"", head)
        tokens = text.split()
        if tokens and tokens[0].upper().endswith(b"OFF"):
            tokens = tokens[1:]
        if len(tokens) >= 2 and tokens[1].isdigit():
            return int(tokens[1])
        return None
    if suffix == ".dae":
        pattern = re.compile(
            rb"<(?:triangles|polylist|polygons|trifans|tristrips)\b[^>]{0,400}?"
            rb"\bcount\s*=\s*[\"']([0-9]{1,19})[\"']")
        return _sum_pattern(stream, pattern, 512)
    return None


def declared_faces_in(data: bytes, suffix: str) -> int | None:
    """`declared_faces` of a whole file already in memory (same count, faster).

    The STL and OBJ patterns cannot overlap themselves, so counting them with
    `bytes.count` finds what the chunked scan finds.
    """
    if suffix == ".stl":
        if len(data) >= 84:
            count = int(struct.unpack("<I", data[80:84])[0])
            if len(data) == 84 + 50 * count:
                return count
        return data.lower().count(b"endfacet")
    if suffix == ".obj":
        first = 1 if re.match(rb"f[ \t]", data[:4096]) else 0
        return first + data.count(b"\nf ") + data.count(b"\nf\t")
    if suffix == ".msh":
        return msh_face_count(data)
    return declared_faces(io.BytesIO(data), suffix, len(data))


def _count_pattern(stream: BinaryIO, pattern: re.Pattern[bytes], width: int) -> int:
    return _sum_pattern(stream, pattern, width, count_only=True)


def _sum_pattern(stream: BinaryIO, pattern: re.Pattern[bytes], width: int,
                 count_only: bool = False) -> int:
    """Sum of group 1 (or number) of the matches of `pattern` over a stream.

    Matches are at most `width` bytes long; a match is taken only when it starts
    before the last `width` bytes of the window, the rest is carried over.
    """
    total = 0
    carry = b""
    stream.seek(0)
    while True:
        chunk = stream.read(_CHUNK)
        window = carry + chunk
        cut = len(window) if not chunk else max(len(window) - width, 0)
        for match in pattern.finditer(window):
            if match.start() >= cut:
                break
            total += 1 if count_only else int(match.group(1))
        if not chunk:
            return total
        carry = window[cut:]


ZIPPED_COLLADA = "zipped COLLADA is not supported"


def _collada_cause(stream: BinaryIO) -> str | None:
    head = stream.read(4)
    stream.seek(0)
    if head.startswith(b"PK"):
        return ZIPPED_COLLADA
    return hostile_xml_stream_cause(stream, _CHUNK)


def _scene_pieces(scene) -> list[Piece]:
    """Every geometry instance of a trimesh scene, with its node's transform."""
    import trimesh

    pieces = []
    for node in scene.graph.nodes_geometry:
        transform, name = scene.graph[node]
        geom = scene.geometry.get(name)
        if not isinstance(geom, trimesh.Trimesh) or len(geom.faces) == 0:
            continue
        pieces.append(Piece(geom.vertices, geom.faces, np.asarray(transform, dtype=np.float64)))
    return pieces


def _concatenate(pieces: list[Piece], path: Path, max_faces: int
                 ) -> tuple[np.ndarray, np.ndarray]:
    """Every piece in the scene's root frame, as one vertex and one face array.

    The total is checked against `max_faces` before anything is copied: a small file
    can instance one large mesh many times.
    """
    instances = [piece for piece in pieces if len(piece.faces) > 0]
    total = sum(len(piece.faces) for piece in instances)
    if total > max_faces:
        raise _too_many(path, total, max_faces)
    verts: list[np.ndarray] = []
    faces: list[np.ndarray] = []
    offset = 0
    for piece in instances:
        transform = np.asarray(piece.transform, dtype=np.float64)
        v = np.asarray(piece.vertices, dtype=np.float64)
        f = np.asarray(piece.faces, dtype=np.int64)
        if f.ndim != 2 or f.shape[1] != 3 or v.ndim != 2 or v.shape[1] != 3:
            raise MeshError(f"mesh {path} has malformed triangle arrays", of_bytes=True)
        if f.min() < 0 or f.max() >= len(v):
            raise MeshError(f"mesh {path} has faces that index missing vertices",
                            of_bytes=True)
        if transform.tobytes() == _IDENTITY_BYTES:
            # what ``v @ I + 0`` gives, bit for bit, for finite coordinates (-0.0 becomes
            # 0.0; inf and NaN stay non-finite and are refused below), without a BLAS call
            v = v + 0.0
        else:
            v = v @ transform[:3, :3].T + transform[:3, 3]
            if np.linalg.det(transform[:3, :3]) < 0:
                f = f[:, ::-1]  # a mirroring node transform turns the faces inside out
        verts.append(v)
        faces.append(f + offset)
        offset += len(v)
    if not faces:
        return np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)
    if len(faces) == 1:
        return np.ascontiguousarray(verts[0]), np.ascontiguousarray(faces[0])
    return np.concatenate(verts), np.concatenate(faces)


def _collada_unit(head: bytes, path: Path) -> float | None:
    """`<unit meter>` found in the first `_UNIT_HEAD` bytes of a COLLADA file (None
    without one: metres).

    Raises
    ------
    MeshError
        The value is not a positive finite length (`0`, `-1`, `nan`, empty): no unit is
        guessed, since every length and the mass would follow the guess.
    """
    match = re.search(rb"<unit\b[^>]*?\bmeter\s*=\s*([\"'])(.*?)\1", head, re.S)
    if not match:
        return None
    text = match.group(2).decode("utf-8", errors="replace").strip()
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not (np.isfinite(value) and value > 0):
        raise MeshError(f"mesh {path} has <unit meter=\"{text[:40]}\">: not a positive length, "
                        "and no unit is guessed", rule=Rule.GEOMETRY_UNREADABLE, of_bytes=True)
    return value


#: A ``nan`` or ``inf`` among the numbers of a COLLADA float array (pycollada reads NaN
#: as 0 without a word: one NaN coordinate moved a vertex to the origin, mass -18 %).
_NON_FINITE = re.compile(rb"(?i)(?<![\w.+-])[+-]?(?:nan|inf(?:inity)?)(?![\w.])")
_SOURCE = re.compile(rb"<source\b[^>]*?\bid\s*=\s*[\"']([^\"']*)[\"'][^>]*>(.*?)</source\s*>",
                     re.S)
_POSITION = re.compile(rb"<input\b(?=[^>]*\bsemantic\s*=\s*[\"']POSITION[\"'])[^>]*?"
                       rb"\bsource\s*=\s*[\"']#([^\"']*)[\"']")


def collada_non_finite(data: bytes) -> bool:
    """Whether a source of vertex positions of a COLLADA document holds ``nan`` or
    ``inf`` (in normals or texture coordinates they do not matter here)."""
    if not _NON_FINITE.search(data):
        return False
    positions = {m.group(1) for m in _POSITION.finditer(data)}
    return any(m.group(1) in positions and _NON_FINITE.search(m.group(2))
               for m in _SOURCE.finditer(data))
