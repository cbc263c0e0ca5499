"""Read mesh files (STL, OBJ, DAE, PLY, GLB/glTF, OFF) into plain vertex/face arrays.

A scene's node transforms are applied and every piece is concatenated into one array pair;
splitting into bodies happens later (:mod:`urdfinertia.solids`). COLLADA ``<unit meter>``
is honoured, as RViz and Gazebo do.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .errors import MeshError

SUPPORTED_SUFFIXES = (".stl", ".obj", ".dae", ".ply", ".glb", ".gltf", ".off")
#: Largest mesh accepted by default (faces); ``--max-faces`` raises it.
DEFAULT_MAX_FACES = 5_000_000


@dataclass(frozen=True, eq=False)
class TriangleMesh:
    """Triangles of one mesh file in the file's own frame (metres after unit scaling)."""

    vertices: np.ndarray  # (n, 3) float64
    faces: np.ndarray  # (m, 3) int64


def load_mesh(path: str | Path, max_faces: int = DEFAULT_MAX_FACES) -> TriangleMesh:
    """Load ``path`` without any repair or vertex merging.

    Raises
    ------
    MeshError
        Unsupported format, unreadable or corrupt file, no triangles, or more than
        ``max_faces`` faces.
    """
    import trimesh

    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in SUPPORTED_SUFFIXES:
        raise MeshError(f"unsupported mesh format '{suffix}' ({path}); "
                        f"supported: {', '.join(SUPPORTED_SUFFIXES)}")
    try:
        loaded = trimesh.load(str(path), force="scene", process=False,
                              file_type=suffix.lstrip("."))
    except MeshError:
        raise
    except Exception as exc:  # trimesh raises many types for corrupt bytes
        raise MeshError(f"cannot read mesh {path}: {type(exc).__name__}: {exc}") from None
    vertices, faces = _flatten_scene(loaded)
    if len(faces) == 0:
        raise MeshError(f"mesh {path} holds no triangles")
    if len(faces) > max_faces:
        raise MeshError(f"mesh {path} has {len(faces)} faces, more than the limit "
                        f"{max_faces} (raise it with --max-faces)")
    unit = loaded.metadata.get("unit_meter") if hasattr(loaded, "metadata") else None
    if suffix == ".dae":
        unit = _collada_unit(path)
    if unit and not np.isclose(unit, 1.0):
        vertices = vertices * unit
    if not np.all(np.isfinite(vertices)):
        raise MeshError(f"mesh {path} has non-finite vertex coordinates")
    return TriangleMesh(vertices, faces)


def _flatten_scene(scene) -> tuple[np.ndarray, np.ndarray]:
    import trimesh

    verts: list[np.ndarray] = []
    faces: list[np.ndarray] = []
    offset = 0
    for node in scene.graph.nodes_geometry:
        transform, name = scene.graph[node]
        geom = scene.geometry[name]
        if not isinstance(geom, trimesh.Trimesh) or len(geom.faces) == 0:
            continue
        v = np.asarray(geom.vertices, dtype=np.float64)
        v = v @ transform[:3, :3].T + transform[:3, 3]
        f = np.asarray(geom.faces, dtype=np.int64)
        if np.linalg.det(transform[:3, :3]) < 0:
            f = f[:, ::-1]  # a mirroring node transform turns the faces inside out
        verts.append(v)
        faces.append(f + offset)
        offset += len(v)
    if not faces:
        return np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)
    return np.concatenate(verts), np.concatenate(faces)


def _collada_unit(path: Path) -> float | None:
    import re

    head = path.read_bytes()[:65536]
    match = re.search(rb"<unit\b[^>]*\bmeter\s*=\s*[\"']([0-9.eE+-]+)[\"']", head)
    if not match:
        return None
    try:
        value = float(match.group(1))
    except ValueError:
        return None
    return value if np.isfinite(value) and value > 0 else None
