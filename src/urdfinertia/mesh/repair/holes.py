"""Close the holes of an oriented surface with caps, and estimate what that costs.

A boundary loop is a set of directed edges where the surface is not closed, grouped by
shared vertices. Capping every loop makes the surface closed, so the polyhedral integrals
are well defined. Two caps are built per loop:

* a fan about the loop's perimeter centroid (one new vertex), and
* for a simple loop of at most ``TRIANGULATE_MAX`` vertices, the triangulation of the
  loop's own vertices that continues the surrounding surface best: dynamic programming
  over the polygon (as in Liepa 2003, "Filling holes in meshes"), minimising the angle
  between each cap triangle and the face across its rim edge. This restores a lost
  triangle pair across a sharp CAD edge, which a fan would cut off.

The triangulation is used where it exists, the fan otherwise. A planar loop is closed
exactly by either (every planar cap on the same loop has the same flux integral). The
volume between the two caps is the loop's stated uncertainty: how much the answer
depends on the cap chosen. Loops with only a fan (large or pinched ones) are given the
volume of a spherical cap of the loop's area ``A`` and the sagitta ``s = D tan(theta/2)/2``
implied by the mean angle ``theta`` between cap and rim faces (``D`` the loop's diameter),
``A s / 2``.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from urdfinertia.inertia.polyhedron import face_volumes
from urdfinertia.mesh.repair.graph import boundary_edges
from urdfinertia.mesh.repair.loops import boundary_cycles, ordered_cycles


@dataclass(frozen=True, eq=False)
class HoleCaps:
    """What closing the holes did, per boundary loop.

    Attributes
    ----------
    vertex : (k,) int
        One boundary vertex of each loop (to tell which body it belongs to).
    area : (k,) float
        m^2, area of each loop's cap.
    uncertainty : (k,) float
        m^3, estimated volume between each cap and the lost surface.
    planar : (k,) bool
        Loops closed exactly (three edges, or planar within round-off).
    """

    vertex: np.ndarray
    area: np.ndarray
    uncertainty: np.ndarray
    planar: np.ndarray

    @classmethod
    def none(cls) -> HoleCaps:
        return cls(np.zeros(0, dtype=np.int64), np.zeros(0), np.zeros(0),
                   np.zeros(0, dtype=bool))

    def subset(self, mask: np.ndarray) -> HoleCaps:
        return HoleCaps(self.vertex[mask], self.area[mask], self.uncertainty[mask],
                        self.planar[mask])

    @property
    def loops(self) -> int:
        return len(self.vertex)


#: A loop is planar when no vertex leaves its plane by more than this fraction of its size.
PLANAR_RTOL = 1e-9
#: Largest simple loop (vertices) triangulated by dynamic programming; larger ones get fans.
TRIANGULATE_MAX = 40
#: Candidate cap triangles costed at once (polygons x triangles), to bound memory.
TRIANGULATE_BATCH = 200_000
#: Weight of a cap triangle's relative area against its rim angle (radians): a tie-break.
AREA_WEIGHT = 1e-3


def close_holes(vertices: np.ndarray, faces: np.ndarray, triangulate: bool = True,
                ) -> tuple[np.ndarray, np.ndarray, HoleCaps]:
    """Cap every boundary loop of an oriented surface (see the module docstring).

    Parameters
    ----------
    vertices : (n, 3) float
    faces : (m, 3) int
        Consistently oriented.
    triangulate : bool
        False caps every loop with a fan only: cheaper, for a first look at the volume.

    Returns
    -------
    vertices : (n + k, 3) float
        Input vertices, then one centroid per loop capped by a fan.
    faces : (m + caps, 3) int
    caps : HoleCaps
    """
    edges = boundary_edges(faces)
    if len(edges) == 0:
        return vertices, faces, HoleCaps.none()
    n = len(vertices)
    succ, loop = boundary_cycles(vertices, faces, edges)
    n_loops = int(loop.max() + 1)
    rim_normal = _rim_normals(vertices, faces, edges)
    fan_v, fan_f, fan_loop = _fans(vertices, edges, loop, n_loops)
    fan_vol = _loop_volumes(fan_v, fan_f, fan_loop, n_loops)
    if triangulate:
        tri_f, tri_loop = _triangulations(vertices, edges, succ, loop, rim_normal)
    else:
        tri_f, tri_loop = np.zeros((0, 3), dtype=np.int64), np.zeros(0, dtype=np.int64)
    has_tri = np.zeros(n_loops, dtype=bool)
    has_tri[tri_loop] = True
    tri_vol = _loop_volumes(vertices, tri_f, tri_loop, n_loops)
    use_fan = ~has_tri[fan_loop]
    # fans only for loops without a triangulation; their apexes are appended vertices
    apex_used = np.unique(fan_f[use_fan, 2] - n)
    remap = np.full(n_loops, -1, dtype=np.int64)
    remap[apex_used] = n + np.arange(len(apex_used))
    fan_keep = fan_f[use_fan].copy()
    fan_keep[:, 2] = remap[fan_keep[:, 2] - n]
    new_vertices = np.concatenate([vertices, fan_v[n + apex_used]])
    cap_faces = np.concatenate([tri_f, fan_keep]).astype(np.int64)

    a = vertices[edges[:, 0]]
    length = np.linalg.norm(vertices[edges[:, 1]] - a, axis=1)
    centre = fan_v[n:]
    fan_tri = fan_v[fan_f]
    cross = np.cross(fan_tri[:, 1] - fan_tri[:, 0], fan_tri[:, 2] - fan_tri[:, 0])
    loop_area = np.bincount(fan_loop, weights=0.5 * np.linalg.norm(cross, axis=1),
                            minlength=n_loops)
    vec = np.stack([np.bincount(fan_loop, weights=cross[:, k], minlength=n_loops)
                    for k in range(3)], axis=1)
    normal = vec / np.maximum(np.linalg.norm(vec, axis=1), 1e-300)[:, None]
    off = np.abs(np.einsum("ij,ij->i", a - centre[loop], normal[loop]))
    depth = np.zeros(n_loops)
    np.maximum.at(depth, loop, off)
    diameter = np.zeros(n_loops)
    np.maximum.at(diameter, loop, 2.0 * np.linalg.norm(a - centre[loop], axis=1))
    cos = np.clip(np.abs(np.einsum("ij,ij->i", rim_normal, normal[loop])), 0.0, 1.0)
    theta: np.ndarray = np.bincount(loop, weights=np.arccos(cos) * length, minlength=n_loops)
    theta = theta / np.maximum(np.bincount(loop, weights=length, minlength=n_loops), 1e-300)
    sagitta = 0.5 * diameter * np.tan(0.5 * np.minimum(theta, 0.5 * np.pi))
    three = np.bincount(loop, minlength=n_loops) == 3
    flat = three | (depth <= PLANAR_RTOL * np.maximum(diameter, 1e-300))
    uncertainty = np.where(has_tri, np.abs(tri_vol - fan_vol),
                           0.5 * loop_area * np.maximum(depth, sagitta))
    uncertainty[flat] = 0.0
    first = np.zeros(n_loops, dtype=np.int64)
    first[loop] = edges[:, 0]
    caps = HoleCaps(first, loop_area, uncertainty, flat)
    return new_vertices, np.concatenate([faces, cap_faces]), caps


def cap_with_fans(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The surface of ``close_holes(vertices, faces, triangulate=False)``, without the
    statistics of its caps: a fan about every loop's perimeter centroid."""
    edges = boundary_edges(faces)
    if len(edges) == 0:
        return vertices, faces
    _, loop = boundary_cycles(vertices, faces, edges)
    fan_v, fan_f, _ = _fans(vertices, edges, loop, int(loop.max() + 1))
    return fan_v, np.concatenate([faces, fan_f.astype(np.int64)])


def _fans(vertices: np.ndarray, edges: np.ndarray, loop: np.ndarray, n_loops: int,
          ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Fan caps about each loop's perimeter centroid (appended as vertex ``n + loop``)."""
    a, b = vertices[edges[:, 0]], vertices[edges[:, 1]]
    length = np.linalg.norm(b - a, axis=1)
    mid = 0.5 * (a + b)
    weight = np.maximum(np.bincount(loop, weights=length, minlength=n_loops), 1e-300)
    centre = np.stack([np.bincount(loop, weights=length * mid[:, k], minlength=n_loops)
                       for k in range(3)], axis=1) / weight[:, None]
    cap = np.stack([edges[:, 1], edges[:, 0], len(vertices) + loop], axis=1)
    return np.concatenate([vertices, centre]), cap, loop


def _loop_volumes(vertices: np.ndarray, caps: np.ndarray, loop: np.ndarray, n_loops: int,
                  ) -> np.ndarray:
    """Signed volume swept by each loop's cap (about the origin; differences are exact)."""
    if len(caps) == 0:
        return np.zeros(n_loops)
    centre = vertices.mean(axis=0)
    vol = face_volumes(vertices[caps] - centre)
    return np.bincount(loop, weights=vol, minlength=n_loops)


def _triangulations(vertices: np.ndarray, edges: np.ndarray, succ: np.ndarray,
                    loop: np.ndarray, rim_normal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Best triangulation of each loop of 4..TRIANGULATE_MAX edges.

    Returns the cap faces and the loop of each. Loops of equal size are solved together:
    the dynamic programme loops over polygon positions, never over loops or triangles.
    """
    faces_out: list[np.ndarray] = []
    loops_out: list[np.ndarray] = []
    for ids, order in ordered_cycles(succ, loop, TRIANGULATE_MAX):
        s = order.shape[1]
        if s < 4:
            continue
        corners = edges[order, 0]  # (L, s) vertex indices in boundary order
        tris = _best_triangulation(vertices[corners], rim_normal[order])
        faces_out.append(np.take_along_axis(corners[:, None, :].repeat(s - 2, axis=1),
                                            tris, axis=2).reshape(-1, 3))
        loops_out.append(np.repeat(ids, s - 2))
    if not faces_out:
        return np.zeros((0, 3), dtype=np.int64), np.zeros(0, dtype=np.int64)
    return np.concatenate(faces_out), np.concatenate(loops_out)


def _best_triangulation(points: np.ndarray, rim: np.ndarray) -> np.ndarray:
    """Triangulations of polygons minimising rim angles (interval dynamic programme).

    Parameters
    ----------
    points : (L, s, 3) float
        Polygon corners in the order the surface runs along its boundary.
    rim : (L, s, 3) float
        Unit normal of the surface face along edge ``i -> i+1``.

    Returns
    -------
    (L, s - 2, 3) int
        Corner positions of each cap triangle, oriented against the boundary.
    """
    n_poly, s, _ = points.shape
    # every candidate triangle (i < k < j) is costed once, all in one vectorised call
    tri_i, tri_k, tri_j, plan = _interval_plan(s)
    step = max(1, TRIANGULATE_BATCH // len(tri_i))
    if n_poly > step:  # bound the temporaries: the polygons are independent
        return np.concatenate([_best_triangulation(points[a:a + step], rim[a:a + step])
                               for a in range(0, n_poly, step)])
    scale = np.maximum(np.sum(np.linalg.norm(np.diff(points, axis=1), axis=2), axis=1), 1e-300)
    tri_cost = _triangle_cost(points, rim, tri_i, tri_k, tri_j, scale, s)
    cost = np.full((n_poly, s, s), np.inf)
    choice = np.zeros((n_poly, s, s), dtype=np.int64)
    idx = np.arange(s - 1)
    cost[:, idx, idx + 1] = 0.0
    flat_cost = cost.reshape(n_poly, s * s)  # views: one flat index per lookup
    flat_choice = choice.reshape(n_poly, s * s)
    for ik, kj, tri, ij, first_k in plan:  # by interval width: all i, splits, polygons
        c = flat_cost[:, ik] + flat_cost[:, kj] + tri_cost[:, tri]
        best = np.argmin(c, axis=2)
        flat_cost[:, ij] = np.take_along_axis(c, best[..., None], axis=2)[..., 0]
        flat_choice[:, ij] = first_k + best
    # unfold the choices breadth-first: every interval of width >= 2 yields one triangle
    poly = np.arange(n_poly)
    lo = np.zeros(n_poly, dtype=np.int64)
    hi = np.full(n_poly, s - 1, dtype=np.int64)
    found: list[np.ndarray] = []
    while len(poly):  # one pass per level of the triangulation trees
        wide = hi - lo >= 2
        poly, lo, hi = poly[wide], lo[wide], hi[wide]
        mid = choice[poly, lo, hi]
        found.append(np.stack([poly, hi, mid, lo], axis=1))
        poly = np.concatenate([poly, poly])
        lo, hi = np.concatenate([lo, mid]), np.concatenate([mid, hi])
    flat = np.concatenate(found)
    flat = flat[np.argsort(flat[:, 0], kind="stable")]
    tris = flat[:, 1:].reshape(n_poly, s - 2, 3)
    return tris


@functools.lru_cache(maxsize=TRIANGULATE_MAX + 1)
def _interval_plan(s: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[tuple]]:
    """Index arrays of the interval programme on an ``s``-gon (the same for every loop).

    Returns the corner positions ``i < k < j`` of every candidate triangle, and per
    interval width ``gap = 2 .. s-1`` the flat ``(s, s)`` indices of the sub-intervals
    ``(i, k)`` and ``(k, j)``, each split's triangle, the intervals ``(i, j)`` and
    their first split ``i + 1``.
    """
    r = np.arange(s)
    tri_i, tri_k, tri_j = (t.astype(np.int64) for t in np.nonzero(
        (r[:, None, None] < r[None, :, None]) & (r[None, :, None] < r[None, None, :])))
    slot = np.zeros((s, s, s), dtype=np.int64)
    slot[tri_i, tri_k, tri_j] = np.arange(len(tri_i))
    plan = []
    for gap in range(2, s):
        i = np.arange(s - gap)[:, None]
        j = i + gap
        k = i + np.arange(1, gap)[None, :]
        i, j, k = np.broadcast_arrays(i, j, k)
        plan.append((i * s + k, k * s + j, slot[i, k, j], i[:, 0] * s + j[:, 0],
                     i[:, 0][None, :] + 1))
    for a in (tri_i, tri_k, tri_j, *(x for step in plan for x in step)):
        a.setflags(write=False)  # shared by every call through the cache
    return tri_i, tri_k, tri_j, plan


def _triangle_cost(points: np.ndarray, rim: np.ndarray, i: np.ndarray, k: np.ndarray,
                   j: np.ndarray, scale: np.ndarray, s: int) -> np.ndarray:
    """Rim angles of cap triangles (j, k, i) on boundary edges, plus a small area term.

    ``i, k, j`` are equal-shaped index arrays; the result has shape ``(L,) + i.shape``.
    """
    pi, pk, pj = points[:, i], points[:, k], points[:, j]
    cross = np.cross(pk - pj, pi - pj)
    norm = np.linalg.norm(cross, axis=-1)
    unit = cross / np.maximum(norm, 1e-300)[..., None]
    area_scale = scale.reshape((-1,) + (1,) * i.ndim) ** 2
    degenerate = norm <= 1e-12 * area_scale
    cost = AREA_WEIGHT * 0.5 * norm / area_scale

    def angle(edge_start: np.ndarray) -> np.ndarray:
        cos = np.sum(unit * rim[:, edge_start], axis=-1)
        return np.where(degenerate, np.pi, np.arccos(np.clip(cos, -1.0, 1.0)))

    cost = cost + np.where(k == i + 1, angle(i), 0.0) + np.where(j == k + 1, angle(k), 0.0)
    closing = (i == 0) & (j == s - 1)  # the polygon's own closing edge (s-1 -> 0)
    if closing.any():
        cost = cost + np.where(closing, angle(np.full_like(j, s - 1)), 0.0)
    return cost


def _rim_normals(vertices: np.ndarray, faces: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """Unit normal of a face running along each boundary edge (tail -> head)."""
    tail = faces.reshape(-1)
    head = np.roll(faces, -1, axis=1).reshape(-1)
    key_faces = tail.astype(np.int64) * (len(vertices) + 1) + head
    key_edges = edges[:, 0].astype(np.int64) * (len(vertices) + 1) + edges[:, 1]
    order = np.argsort(key_faces)
    pos = np.searchsorted(key_faces[order], key_edges)
    face = order[np.clip(pos, 0, len(order) - 1)] // 3
    tri = vertices[faces[face]]
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    return cross / np.maximum(np.linalg.norm(cross, axis=1), 1e-300)[:, None]
