"""Which closed surfaces lie inside which: cavities and solids nested in solids.

Decided by winding numbers (`winding`) at one probe point per surface, so the
answer does not depend on how the surfaces are triangulated.
"""

from __future__ import annotations

import numpy as np

from urdfinertia.inertia.polyhedron import cross_rows
from urdfinertia.mesh.repair.graph import sort_order
from urdfinertia.mesh.repair.winding import closed_winding_numbers


def nest_signs(vertices: np.ndarray, faces: np.ndarray, label: np.ndarray,
                size: np.ndarray, given: np.ndarray, skip: np.ndarray) -> np.ndarray:
    """Wanted sign of each labelled closed surface's volume (+1 solid, -1 cavity).

    A surface in no other is a solid. A nested one keeps its `given` orientation
    relative to its innermost container: opposite is a cavity, same is a solid.
    Surfaces marked `skip` take part in nothing and get +1.
    """
    k = len(size)
    final = np.ones(k)
    live = np.flatnonzero(~skip)
    if len(live) < 2:
        return final
    order = sort_order(label)
    bounds = np.searchsorted(label[order], np.arange(k + 1))
    tri = np.take(vertices, faces, axis=0)  # vertices[faces], a faster gather
    corner_lo = np.minimum(np.minimum(tri[:, 0], tri[:, 1]), tri[:, 2])
    corner_hi = np.maximum(np.maximum(tri[:, 0], tri[:, 1]), tri[:, 2])
    lo = np.minimum.reduceat(corner_lo[order], bounds[:-1])  # every label has faces
    hi = np.maximum.reduceat(corner_hi[order], bounds[:-1])
    cand = (np.all(lo[:, None] >= lo[None], axis=2) & np.all(hi[:, None] <= hi[None], axis=2)
            & (size[:, None] < size[None]) & ~skip[:, None] & ~skip[None])
    inside = np.zeros((k, k), dtype=bool)  # inside[p, q]: surface p lies in surface q
    probes = _probe_points(tri[order], bounds) if cand.any() else np.zeros((0, 3))
    del tri, corner_lo, corner_hi  # freed before the winding numbers (memory)
    for q in np.flatnonzero(cand.any(axis=0)):  # one winding evaluation per container
        ps = np.flatnonzero(cand[:, q])
        mine = order[bounds[q]:bounds[q + 1]]
        w = closed_winding_numbers(probes[ps], vertices, faces[mine])
        inside[ps, q] = np.abs(w) > 0.5
    for p in live[np.argsort(-size[live])]:  # containers are larger: settled first
        qs = np.flatnonzero(inside[p])
        if len(qs):
            q = qs[np.argmin(size[qs])]
            final[p] = final[q] if given[p] == given[q] else -final[q]
    return final


def _probe_points(triangles: np.ndarray, bounds: np.ndarray) -> np.ndarray:
    """`probe_point` of each group `triangles[bounds[i]:bounds[i + 1]]` at once."""
    area = np.linalg.norm(cross_rows(triangles[:, 1] - triangles[:, 0],
                                   triangles[:, 2] - triangles[:, 0]), axis=1)
    best = np.maximum.reduceat(area, bounds[:-1])  # every group has triangles
    at_best = np.flatnonzero(area == np.repeat(best, np.diff(bounds)))
    first = at_best[np.searchsorted(at_best, bounds[:-1])]  # argmax: the first largest
    return triangles[first].mean(axis=1)


def probe_point(triangles: np.ndarray) -> np.ndarray:
    """The centroid of the largest of `triangles`, for inside/outside tests."""
    area = np.linalg.norm(cross_rows(triangles[:, 1] - triangles[:, 0],
                                   triangles[:, 2] - triangles[:, 0]), axis=1)
    return triangles[int(np.argmax(area))].mean(axis=0)
