"""Read MuJoCo's binary `.msh` meshes (MJCF reference, `mesh/file`).

Layout, little-endian: four int32 counts (vertices, normals, texture coordinates, faces),
then float32 vertices (3 each), normals (3 each), texture coordinates (2 each) and int32
faces (3 vertex indices each). The size must match the counts exactly. A file without
faces stands for the convex hull of its vertices, as MuJoCo takes it.
"""

from __future__ import annotations

import numpy as np

from urdfinertia.mesh.read.common import Piece

_COUNTS = 16


def msh_face_count(data: bytes) -> int | None:
    """Faces the header declares (None when the header is short)."""
    if len(data) < _COUNTS:
        return None
    return int(np.frombuffer(data, "<i4", 4)[3])


def read_msh(data: bytes) -> list[Piece]:
    """The triangles of a `.msh` file's bytes.

    Raises
    ------
    ValueError
        Negative counts, a size that does not match them, or face indices out of range.
    """
    if len(data) < _COUNTS:
        raise ValueError("shorter than its header")
    nv, nn, nt, nf = (int(v) for v in np.frombuffer(data, "<i4", 4))
    if min(nv, nn, nt, nf) < 0:
        raise ValueError("negative counts in the header")
    size = _COUNTS + 4 * (3 * nv + 3 * nn + 2 * nt + 3 * nf)
    if len(data) != size:
        raise ValueError(f"{len(data)} bytes where the header needs {size}")
    vertices = np.frombuffer(data, "<f4", 3 * nv, _COUNTS).astype(np.float64).reshape(-1, 3)
    if nf == 0:
        return [Piece(vertices, _hull(vertices))] if nv >= 4 else []
    offset = _COUNTS + 4 * (3 * nv + 3 * nn + 2 * nt)
    faces = np.frombuffer(data, "<i4", 3 * nf, offset).astype(np.int64).reshape(-1, 3)
    if faces.size and (faces.min() < 0 or faces.max() >= nv):
        raise ValueError("face index out of range")
    return [Piece(vertices, faces)]


def _hull(vertices: np.ndarray) -> np.ndarray:
    """Outward-wound triangles of the convex hull of `vertices`."""
    from scipy.spatial import ConvexHull

    hull = ConvexHull(vertices)
    faces = hull.simplices.astype(np.int64)
    # each facet's plane normal (qhull's, pointing out) orders its corners
    corners = vertices[faces]
    normal = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    flip = np.einsum("ij,ij->i", normal, hull.equations[:, :3]) < 0
    faces[flip] = faces[flip][:, ::-1]
    return faces
