"""Boolean union of closed bodies with manifold3d, so overlapping volume counts once."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Protocol

import numpy as np


class _Closed(Protocol):
    @property
    def vertices(self) -> np.ndarray: ...

    @property
    def faces(self) -> np.ndarray: ...


def union_bodies(bodies: Sequence[_Closed]) -> tuple[np.ndarray, np.ndarray] | None:
    """Vertices and faces of the union of closed, oriented bodies.

    Each body (an outward shell with its inward cavities) must be an oriented
    2-manifold; returns None when manifold3d rejects one, so the caller can say so.
    """
    import manifold3d

    parts = []
    for body in bodies:
        # the Mesh64 is a temporary: manifold3d keeps its own copy
        parts.append(manifold3d.Manifold(manifold3d.Mesh64(
            vert_properties=np.ascontiguousarray(body.vertices, dtype=np.float64),
            tri_verts=np.ascontiguousarray(body.faces, dtype=np.uint64),
        )))
        if parts[-1].status() != manifold3d.Error.NoError or parts[-1].is_empty():
            return None
    result = manifold3d.Manifold.batch_boolean(parts, manifold3d.OpType.Add)
    if result.status() != manifold3d.Error.NoError:
        return None
    # the operands (evaluated into the result by status()) and then the result are freed
    # as soon as they are no longer needed: the union is the memory peak of a large mesh
    del parts
    out = result.to_mesh64()
    del result
    vertices = np.asarray(out.vert_properties, dtype=np.float64)[:, :3]
    faces = np.asarray(out.tri_verts, dtype=np.int64)
    return vertices, faces
