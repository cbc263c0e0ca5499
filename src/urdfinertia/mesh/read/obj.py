"""Wavefront OBJ through trimesh's own loader (`trimesh.exchange.obj.load_obj`).

Called directly, without `trimesh.load`'s scene machinery (which was most of its cost),
with `skip_materials=True` and no resolver: an `.mtl` or texture is never opened.
OBJ has no scene graph: every geometry sits at the identity.
"""

from __future__ import annotations

import io

import numpy as np

from urdfinertia.mesh.read.common import Piece


def read_obj(data: bytes, max_faces: int) -> list[Piece]:
    """The meshes of an OBJ file's bytes (the face limit was checked on the bytes)."""
    from trimesh.exchange.obj import load_obj
    from trimesh.geometry import triangulate_quads

    loaded = load_obj(io.BytesIO(data), skip_materials=True)
    geometry = loaded.get("geometry", {"": loaded}) if isinstance(loaded, dict) else {}
    pieces = []
    for kwargs in geometry.values():
        vertices, faces = kwargs.get("vertices"), kwargs.get("faces")
        if vertices is None or faces is None or len(faces) == 0:
            continue
        # what trimesh.Trimesh's faces setter does with quads and polygons (fans)
        faces = np.asarray(faces, dtype=np.int64) if _regular(faces) else faces
        if not (isinstance(faces, np.ndarray) and faces.ndim == 2 and faces.shape[1] == 3):
            faces = triangulate_quads(faces)
        pieces.append(Piece(np.asarray(vertices, dtype=np.float64),
                            np.asarray(faces, dtype=np.int64)))
    return pieces


def _regular(faces: object) -> bool:
    """Faces of one polygon size (an array, or a list of equal-length rows)."""
    if isinstance(faces, np.ndarray):
        return faces.dtype != object
    rows = list(faces)  # type: ignore[call-overload]
    return len({len(r) for r in rows}) <= 1
