"""Close the holes of an oriented surface with caps, and estimate what that costs.

A boundary loop is a set of directed edges where the surface is not closed, grouped by
shared vertices. Capping every loop makes the surface closed, so the polyhedral integrals
are well defined. Up to three caps are built per loop:

* a fan about the loop's perimeter centroid (one new vertex);
* for a simple loop of at most ``TRIANGULATE_MAX`` vertices, the triangulation of the
  loop's own vertices that continues the surrounding surface best: dynamic programming
  over the polygon (as in Liepa 2003, "Filling holes in meshes"), minimising the angle
  between each cap triangle and the face across its rim edge. This restores a lost
  triangle pair across a sharp CAD edge, which a fan would cut off;
* for a larger loop, a cap through the level set ``w = 1/2`` of the surface's
  generalized winding number (:mod:`level_caps`), independent of the rim's
  triangulation; it is used where it meets the rim at a smaller angle than the fan.
  Its search costs (ring points x faces) per step, so it is skipped beyond
  ``LEVEL_BUDGET``.

The triangulation is used where it exists. A planar loop is closed exactly by any of
them (every planar cap on the same loop has the same flux integral) and states no error.
Otherwise a loop's stated uncertainty is the larger of:

* the spread of the candidate caps' volumes (how much the answer depends on the cap), and
* the volume of a tent over the cap, continuing the rim faces at the angle ``theta``
  at which the chosen cap meets them (length-weighted mean, at most ``TENT_MAX_ANGLE``):
  ``A r tan(theta) / 2``, with ``A`` the cap's area and ``r = 2 A / P`` its half-width
  (``P`` the loop's perimeter). A cap that continues the surface smoothly states little;
  one that cuts across a lost corner or edge states about the volume that was lost.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from urdfinertia.inertia.polyhedron import cross_rows, face_volumes
from urdfinertia.mesh.repair.graph import EdgeTable, boundary_edges, sort_order
from urdfinertia.mesh.repair.level_caps import level_caps, level_caps_points
from urdfinertia.mesh.repair.loops import boundary_cycles, ordered_cycles
from urdfinertia.mesh.repair.winding import RayCounter, winding_numbers
from urdfinertia.timing import Deadline


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
    level : (k,) bool
        Loops closed by a winding-number level cap (:mod:`level_caps`).
    dependence : (k,) float
        m^3, how much the volume depends on the cap where there is a choice of caps
        (triangulation against fan for loops of at most ``PLAN_CACHE_MAX`` edges), or a
        spherical cap's volume over a larger loop at the fan's rim angle: the figure by
        which two whole repairs of one mesh are compared (see ``pipeline``).
    """

    vertex: np.ndarray
    area: np.ndarray
    uncertainty: np.ndarray
    planar: np.ndarray
    level: np.ndarray
    dependence: np.ndarray

    @classmethod
    def none(cls) -> HoleCaps:
        return cls(np.zeros(0, dtype=np.int64), np.zeros(0), np.zeros(0),
                   np.zeros(0, dtype=bool), np.zeros(0, dtype=bool), np.zeros(0))

    def subset(self, mask: np.ndarray) -> HoleCaps:
        return HoleCaps(self.vertex[mask], self.area[mask], self.uncertainty[mask],
                        self.planar[mask], self.level[mask], self.dependence[mask])

    @property
    def loops(self) -> int:
        return len(self.vertex)

    def widened(self) -> HoleCaps:
        """These caps (fans) with ``dependence`` added to each uncertainty: what a refined
        cap, not computed, might have moved the volume (a spherical cap at the rim angle).
        """
        return HoleCaps(self.vertex, self.area, self.uncertainty + self.dependence,
                        self.planar, self.level, self.dependence)


#: A loop is planar when no vertex leaves its plane by more than this fraction of its size.
PLANAR_RTOL = 1e-9
#: Largest simple loop (vertices) triangulated by dynamic programming (time and memory
#: grow as its cube); larger ones get fans or level caps.
TRIANGULATE_MAX = 200
#: Largest loop whose programme's index arrays are kept for reuse.
PLAN_CACHE_MAX = 40
#: Candidate triangles (s^3 / 6 per loop of s edges) the programme may cost, per surface,
#: for loops longer than ``PLAN_CACHE_MAX``: about seven loops of 150 edges, ~1.5 s. The
#: loops left over get fans or level caps.
WIDE_TRIANGULATION_BUDGET = 1_000_000
#: Candidate cap triangles costed at once (polygons x triangles), to bound memory.
TRIANGULATE_BATCH = 200_000
#: Weight of a cap triangle's relative area against its rim angle (radians): a tie-break.
AREA_WEIGHT = 1e-3
#: Steepest rim continuation the tent of the stated uncertainty assumes (radians).
TENT_MAX_ANGLE = np.radians(60.0)
#: Grid points per axis, and the fewest disputed points, of the winding-number vote on a
#: long loop's triangulation (:func:`_winding_refutes`).
VOTE_GRID = 10
VOTE_MIN = 8
#: Point-face pairs all votes on one surface may evaluate (~3 s at the limit).
VOTE_BUDGET = 100_000_000
#: Largest (ring points x faces) a surface's level caps may evaluate per search step
#: (about 30 steps, ~0.1 s each at the limit); beyond it the fans stand (a large visual
#: mesh with long open rims).
LEVEL_BUDGET = 2_000_000
#: Loops of at least this many edges are also bounded by their fan's tent (smaller ones
#: are a few lost triangles, which the triangulation restores).
FAN_TENT_MIN = 12
#: A level cap replaces the fan only if it meets the rim at least this much flatter.
LEVEL_MIN_GAIN = 1e-3


def close_holes(vertices: np.ndarray, faces: np.ndarray, triangulate: bool = True,
                deadline: Deadline | None = None, table: EdgeTable | None = None,
                ) -> tuple[np.ndarray, np.ndarray, HoleCaps]:
    """Cap every boundary loop of an oriented surface (see the module docstring).

    Parameters
    ----------
    vertices : (n, 3) float
    faces : (m, 3) int
        Consistently oriented.
    triangulate : bool
        False caps every loop with a fan only: cheaper, for a first look at the volume.
    deadline : Deadline, optional
        Checked between the steps of triangulations, votes and level caps.
    table : EdgeTable, optional
        Half-edges of ``faces`` grouped by edge, as :func:`~.graph.boundary_edges` reads
        them (``edge_table(faces)``, or a table of the same edges whose half-edges run
        as ``faces`` do), when the caller has it already.

    Raises
    ------
    OverBudget
        ``deadline`` expired (the caller falls back to ``triangulate=False``).

    Returns
    -------
    vertices : (n + q, 3) float
        Input vertices, then the new vertices of the caps (fan apexes, level caps).
    faces : (m + caps, 3) int
    caps : HoleCaps
    """
    edges = boundary_edges(faces, table)
    if len(edges) == 0:
        return vertices, faces, HoleCaps.none()
    n = len(vertices)
    succ, loop = boundary_cycles(vertices, faces, edges)
    n_loops = int(loop.max() + 1)
    rim_normal = _rim_normals(vertices, faces, edges)
    fan_v, fan_f, fan_loop = _fans(vertices, edges, loop, n_loops)
    a = vertices[edges[:, 0]]
    length = np.linalg.norm(vertices[edges[:, 1]] - a, axis=1)
    perimeter = np.bincount(loop, weights=length, minlength=n_loops)
    centre = fan_v[n:]
    fan_tri = fan_v[fan_f]
    cross = cross_rows(fan_tri[:, 1] - fan_tri[:, 0], fan_tri[:, 2] - fan_tri[:, 0])
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
    three = np.bincount(loop, minlength=n_loops) == 3
    flat = three | (depth <= PLANAR_RTOL * np.maximum(diameter, 1e-300))

    empty = np.zeros((0, 3), dtype=np.int64), np.zeros(0, dtype=np.int64)
    deadline = deadline if deadline is not None else Deadline(None)
    tri_f, tri_loop = (_triangulations(vertices, edges, succ, loop, rim_normal, deadline)
                       if triangulate else empty)
    has_tri = np.zeros(n_loops, dtype=bool)
    has_tri[tri_loop] = True
    # a long loop's triangulation can fold out towards the hull on a real open mesh:
    # it stands only where the open surface's winding numbers side with it
    tri_all = _loop_volumes(fan_v, tri_f, tri_loop, n_loops)
    loop_size = np.bincount(loop, minlength=n_loops)
    long_tri = has_tri & (loop_size > PLAN_CACHE_MAX)
    if long_tri.any():
        ids = np.flatnonzero(long_tri)
        refuted = _winding_refutes(fan_v, faces, fan_f, fan_loop, tri_f, tri_loop,
                                   ids[np.argsort(loop_size[ids], kind="stable")], deadline)
        has_tri[refuted] = False
        tri_f, tri_loop = tri_f[has_tri[tri_loop]], tri_loop[has_tri[tri_loop]]
    wide = triangulate & ~has_tri & ~flat  # loops that get a level cap as a candidate
    # each search step evaluates every ring point against the whole capped surface
    sizes = np.bincount(loop, minlength=n_loops)[wide]
    work = level_caps_points(sizes) * (len(faces) + len(fan_f)) + int(
        sum(level_caps_points(sizes[k:k + 1]) * int(sizes[k]) for k in range(len(sizes))))
    if wide.any() and work <= LEVEL_BUDGET:
        corners = [(int(i), edges[row, 0])
                   for ids, order in ordered_cycles(succ, loop, len(edges))
                   for i, row in zip(ids, order, strict=True) if wide[i]]
        lev = level_caps(len(fan_v), corners, centre, normal, fan_v,
                         np.concatenate([faces, fan_f]), fan_f, fan_loop, deadline)
        all_v = np.concatenate([fan_v, lev.vertices])
        lev_f, lev_loop = lev.faces, lev.loop
    else:
        all_v, (lev_f, lev_loop) = fan_v, empty
    has_lev = np.zeros(n_loops, dtype=bool)
    has_lev[lev_loop] = True

    rim = _Rim(edges, loop, length, rim_normal, n_loops)
    candidates = {"fan": (fan_f, fan_loop), "tri": (tri_f, tri_loop),
                  "level": (lev_f, lev_loop)}
    volume = {k: _loop_volumes(all_v, f, lp, n_loops) for k, (f, lp) in candidates.items()}
    angle = {k: _rim_mean(all_v, f, lp, rim, lambda t: t)
             for k, (f, lp) in candidates.items()}
    use_level = has_lev & (angle["level"] < angle["fan"] - LEVEL_MIN_GAIN)
    use_fan = ~has_tri & ~use_level
    fan_use, lev_use = use_fan[fan_loop], use_level[lev_loop]
    cap_faces = np.concatenate([tri_f, fan_f[fan_use], lev_f[lev_use]]).astype(np.int64)
    cap_loop = np.concatenate([tri_loop, fan_loop[fan_use], lev_loop[lev_use]])
    chosen = np.where(has_tri, volume["tri"], np.where(use_level, volume["level"],
                                                        volume["fan"]))
    others = np.stack([volume["fan"], np.where(has_lev, volume["level"], chosen), chosen,
                       np.where(long_tri, tri_all, chosen)])
    spread = others.max(axis=0) - others.min(axis=0)
    # the tent: rim faces continued over the cap at their mean slope to it
    tent_base = loop_area * 2.0 * loop_area / np.maximum(perimeter, 1e-300)  # A r
    slope = _rim_mean(all_v, cap_faces, cap_loop, rim, _slope)
    # a wide loop's cap may fold to meet its rim and still miss a dome or a lost corner:
    # the flat fan's tent, less what the chosen cap already moved, bounds it too
    fan_slope = _rim_mean(all_v, fan_f, fan_loop, rim, _slope)
    moved = np.abs(chosen - volume["fan"]) / np.maximum(tent_base, 1e-300)
    wide_loop = np.bincount(loop, minlength=n_loops) >= FAN_TENT_MIN
    slope = np.where(wide_loop, np.maximum(slope, fan_slope - moved), slope)
    uncertainty = np.maximum(spread, tent_base * slope)
    uncertainty[flat] = 0.0
    # the comparison figure: a sagitta from the rim's angle to the loop's mean plane
    plane_cos = np.clip(np.abs(np.einsum("ij,ij->i", rim_normal, normal[loop])), 0.0, 1.0)
    plane_angle = np.bincount(loop, weights=np.arccos(plane_cos) * length,
                              minlength=n_loops) / np.maximum(perimeter, 1e-300)
    sagitta = 0.5 * diameter * np.tan(0.5 * np.minimum(plane_angle, 0.5 * np.pi))
    short_tri = has_tri & (np.bincount(loop, minlength=n_loops) <= PLAN_CACHE_MAX)
    dependence = np.where(short_tri, np.abs(volume["tri"] - volume["fan"]),
                          0.5 * loop_area * np.maximum(depth, sagitta))
    dependence[flat] = 0.0

    extra = np.unique(cap_faces[cap_faces >= n])  # appended vertices the caps use
    remap = np.full(len(all_v), -1, dtype=np.int64)
    remap[:n] = np.arange(n)
    remap[extra] = n + np.arange(len(extra))
    first = np.zeros(n_loops, dtype=np.int64)
    first[loop] = edges[:, 0]
    caps = HoleCaps(first, loop_area, uncertainty, flat, use_level, dependence)
    return (np.concatenate([vertices, all_v[extra]]),
            np.concatenate([faces, remap[cap_faces]]), caps)


def _winding_refutes(vertices: np.ndarray, faces: np.ndarray, fan_f: np.ndarray,
                     fan_loop: np.ndarray, tri_f: np.ndarray, tri_loop: np.ndarray,
                     loops: np.ndarray, deadline: Deadline) -> np.ndarray:
    """The loops among ``loops`` whose triangulation the winding numbers refute.

    Per loop, points on a ``VOTE_GRID``^3 grid over its bounding box (both caps lie in
    the convex hull of its vertices) are classed inside or outside the surface closed by
    the loop's fan and by its triangulation. Where the two disagree, the generalized
    winding number of the surface without the loop's cap (every other loop fan-capped)
    says which side the open surface puts the point on. The triangulation is refuted
    when fewer than half of the disputed points side with it; with fewer than
    ``VOTE_MIN`` disputed points the caps barely differ and it stands. Loops beyond
    ``VOTE_BUDGET`` get no vote and are refuted: an unchecked long triangulation is not
    trusted.
    """
    closed = np.concatenate([faces, fan_f])
    # each vote costs grid points x faces; the loops it cannot afford keep their fans
    afford = max(0, int(VOTE_BUDGET // (VOTE_GRID ** 3 * len(closed))))
    refuted = [int(k) for k in loops[afford:]]
    frac = (np.arange(VOTE_GRID) + 0.5) / VOTE_GRID
    counter = RayCounter(vertices, closed)  # one grid for every vote
    for k in loops[:afford].tolist():  # one vote per long loop
        deadline.check()
        fan_tri = vertices[fan_f[fan_loop == k]].reshape(-1, 3)
        tri_tri = vertices[tri_f[tri_loop == k]].reshape(-1, 3)
        lo, hi = tri_tri.min(axis=0), tri_tri.max(axis=0)
        grid = np.stack(np.meshgrid(*(lo[i] + frac * (hi[i] - lo[i]) for i in range(3)),
                                    indexing="ij"), axis=-1).reshape(-1, 3)
        w_fanned = counter(grid, exact_on_graze=False)
        own = np.arange(len(fan_tri)).reshape(-1, 3)
        w_open = w_fanned - winding_numbers(grid, fan_tri, own)
        w_tri = w_open + winding_numbers(grid, tri_tri, np.arange(len(tri_tri)).reshape(-1, 3))
        in_fan, in_tri = w_fanned > 0.5, w_tri > 0.5
        disputed = in_fan != in_tri
        if np.count_nonzero(disputed) < VOTE_MIN:
            continue
        with_tri = np.count_nonzero((w_open[disputed] > 0.5) == in_tri[disputed])
        if 2 * with_tri < np.count_nonzero(disputed):
            refuted.append(k)
    return np.array(refuted, dtype=np.int64)


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
                    loop: np.ndarray, rim_normal: np.ndarray, deadline: Deadline,
                    ) -> tuple[np.ndarray, np.ndarray]:
    """Best triangulation of each loop of 4..TRIANGULATE_MAX edges, the loops of more
    than ``PLAN_CACHE_MAX`` edges smallest first within ``WIDE_TRIANGULATION_BUDGET``.

    Returns the cap faces and the loop of each. Loops of equal size are solved together:
    the dynamic programme loops over polygon positions, never over loops or triangles.
    """
    faces_out: list[np.ndarray] = []
    loops_out: list[np.ndarray] = []
    budget = WIDE_TRIANGULATION_BUDGET
    for ids, order in ordered_cycles(succ, loop, TRIANGULATE_MAX):  # by size, ascending
        s = order.shape[1]
        if s < 4:
            continue
        if s > PLAN_CACHE_MAX:  # wide loops: the programme's work grows as s^3 / 6
            afford = min(len(ids), int(budget // (s ** 3 / 6)))
            if afford == 0:
                break
            ids, order = ids[:afford], order[:afford]
            budget -= afford * s ** 3 / 6
        deadline.check()
        corners = edges[order, 0]  # (L, s) vertex indices in boundary order
        tris = _best_triangulation(vertices[corners], rim_normal[order])
        faces_out.append(np.take_along_axis(corners[:, None, :].repeat(s - 2, axis=1),
                                            tris, axis=2).reshape(-1, 3))
        loops_out.append(np.repeat(ids, s - 2))
    if not faces_out:
        return np.zeros((0, 3), dtype=np.int64), np.zeros(0, dtype=np.int64)
    return np.concatenate(faces_out), np.concatenate(loops_out)


def _best_triangulation(points: np.ndarray, rim: np.ndarray,
                        plan: tuple[np.ndarray, np.ndarray, np.ndarray, list[tuple]] | None
                        = None) -> np.ndarray:
    """Triangulations of polygons minimising rim angles (interval dynamic programme).

    Parameters
    ----------
    points : (L, s, 3) float
        Polygon corners in the order the surface runs along its boundary.
    rim : (L, s, 3) float
        Unit normal of the surface face along edge ``i -> i+1``.
    plan : optional
        ``_interval_plan(s)``, when the caller has it (batches of wide loops share one).

    Returns
    -------
    (L, s - 2, 3) int
        Corner positions of each cap triangle, oriented against the boundary.
    """
    n_poly, s, _ = points.shape
    # every candidate triangle (i < k < j) is costed once, all in one vectorised call
    whole = plan if plan is not None else _interval_plan(s)
    tri_i, tri_k, tri_j, steps = whole
    step = max(1, TRIANGULATE_BATCH // len(tri_i))
    if n_poly > step:  # bound the temporaries: the polygons are independent (one plan)
        return np.concatenate([_best_triangulation(points[a:a + step], rim[a:a + step],
                                                   whole)
                               for a in range(0, n_poly, step)])
    scale = np.maximum(np.sum(np.linalg.norm(np.diff(points, axis=1), axis=2), axis=1), 1e-300)
    tri_cost = _triangle_cost(points, rim, tri_i, tri_k, tri_j, scale, s)
    cost = np.full((n_poly, s, s), np.inf)
    choice = np.zeros((n_poly, s, s), dtype=np.int64)
    idx = np.arange(s - 1)
    cost[:, idx, idx + 1] = 0.0
    flat_cost = cost.reshape(n_poly, s * s)  # views: one flat index per lookup
    flat_choice = choice.reshape(n_poly, s * s)
    for ik, kj, tri, ij, first_k in steps:  # by interval width: all i, splits, polygons
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


def _interval_plan(s: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[tuple]]:
    """:func:`_plan`, kept for reuse up to ``PLAN_CACHE_MAX`` corners (larger plans take
    tens of megabytes)."""
    return _cached_plan(s) if s <= PLAN_CACHE_MAX else _plan(s)


def _plan(s: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[tuple]]:
    """Index arrays of the interval programme on an ``s``-gon (the same for every loop).

    Returns the corner positions ``i < k < j`` of every candidate triangle, and per
    interval width ``gap = 2 .. s-1`` the flat ``(s, s)`` indices of the sub-intervals
    ``(i, k)`` and ``(k, j)``, each split's triangle, the intervals ``(i, j)`` and
    their first split ``i + 1``.
    """
    # the candidates in lexicographic order, and each one's rank in it by formula: the
    # pairs (i, k) in order, each followed by its s - 1 - k triangles (an (s, s, s)
    # table of ranks would take s^3 words)
    pair_i, pair_k = np.triu_indices(s, 1)
    per_pair = s - 1 - pair_k
    pair_start = np.zeros((s, s), dtype=np.int64)
    pair_start[pair_i, pair_k] = np.cumsum(per_pair) - per_pair
    n_tri = int(per_pair.sum())
    tri_i = np.repeat(pair_i, per_pair).astype(np.int64)
    tri_k = np.repeat(pair_k, per_pair).astype(np.int64)
    tri_j = (np.arange(n_tri) - np.repeat(pair_start[pair_i, pair_k], per_pair)
             + tri_k + 1)
    plan = []
    for gap in range(2, s):
        i = np.arange(s - gap)[:, None]
        j = i + gap
        k = i + np.arange(1, gap)[None, :]
        i, j, k = np.broadcast_arrays(i, j, k)
        plan.append((i * s + k, k * s + j, pair_start[i, k] + (j - k - 1),
                     i[:, 0] * s + j[:, 0], i[:, 0][None, :] + 1))
    for a in (tri_i, tri_k, tri_j, *(x for step in plan for x in step)):
        a.setflags(write=False)  # shared by every call through the cache
    return tri_i, tri_k, tri_j, plan


_cached_plan = functools.lru_cache(maxsize=PLAN_CACHE_MAX + 1)(_plan)


def _triangle_cost(points: np.ndarray, rim: np.ndarray, i: np.ndarray, k: np.ndarray,
                   j: np.ndarray, scale: np.ndarray, s: int) -> np.ndarray:
    """Rim angles of cap triangles (j, k, i) on boundary edges, plus a small area term.

    ``i, k, j`` are equal-shaped index arrays; the result has shape ``(L,) + i.shape``.
    """
    pi, pk, pj = (np.take(points, x, axis=1) for x in (i, k, j))  # points[:, x]
    # np.cross bit for bit, on the rows of the candidates
    cross = cross_rows((pk - pj).reshape(-1, 3), (pi - pj).reshape(-1, 3)).reshape(pk.shape)
    norm = np.linalg.norm(cross, axis=-1)
    area_scale = scale.reshape((-1,) + (1,) * i.ndim) ** 2
    degenerate = norm <= 1e-12 * area_scale
    cost = AREA_WEIGHT * 0.5 * norm / area_scale

    def add_angle(on: np.ndarray, edge_start: np.ndarray) -> None:
        """Add the rim angle of the triangles ``on`` (a mask over ``i``'s shape) along
        the boundary edge starting at ``edge_start``: only the O(s^2) triangles on a
        boundary edge are evaluated, not all O(s^3) candidates, and their unit normals
        only (the others would add 0, which changes no bit of the costs)."""
        unit = cross[:, on] / np.maximum(norm[:, on], 1e-300)[..., None]
        cos = np.sum(unit * rim[:, edge_start[on]], axis=-1)
        cost[:, on] += np.where(degenerate[:, on], np.pi,
                                np.arccos(np.clip(cos, -1.0, 1.0)))

    add_angle(k == i + 1, i)
    add_angle(j == k + 1, k)
    closing = (i == 0) & (j == s - 1)  # the polygon's own closing edge (s-1 -> 0)
    if closing.any():
        add_angle(closing, np.full_like(j, s - 1))
    return cost


@dataclass(frozen=True, eq=False)
class _Rim:
    """The boundary edges of a surface: loop, length and rim-face normal of each."""

    edges: np.ndarray
    loop: np.ndarray
    length: np.ndarray
    normal: np.ndarray
    loops: int


def _slope(theta: np.ndarray) -> np.ndarray:
    """Slope of a rim face continued over a cap it meets at ``theta`` (capped)."""
    return np.tan(np.minimum(theta, TENT_MAX_ANGLE))


def _rim_mean(vertices: np.ndarray, caps: np.ndarray, cap_loop: np.ndarray, rim: _Rim,
              of: Callable[[np.ndarray], np.ndarray]) -> np.ndarray:
    """Length-weighted mean of ``of(angle between cap and rim face)`` per loop.

    The cap face along boundary edge ``tail -> head`` runs ``head -> tail``. Loops
    without a cap in ``caps`` get ``of(pi / 2)``.
    """
    out = of(np.full(rim.loops, 0.5 * np.pi))
    if len(caps) == 0:
        return out
    has = np.zeros(rim.loops, dtype=bool)
    has[cap_loop] = True
    normal = _rim_normals(vertices, caps.astype(np.int64), rim.edges[:, ::-1],
                          missing_ok=True)
    found = np.linalg.norm(normal, axis=1) > 0.5
    cos = np.clip(np.einsum("ij,ij->i", normal, rim.normal), -1.0, 1.0)
    value = of(np.where(found, np.arccos(cos), 0.5 * np.pi))
    weight = np.where(has[rim.loop], rim.length, 0.0)
    total = np.bincount(rim.loop, weights=value * weight, minlength=rim.loops)
    mean = total / np.maximum(np.bincount(rim.loop, weights=weight, minlength=rim.loops),
                              1e-300)
    return np.where(has, mean, out)


def _rim_normals(vertices: np.ndarray, faces: np.ndarray, edges: np.ndarray,
                 missing_ok: bool = False) -> np.ndarray:
    """Unit normal of a face running along each boundary edge (tail -> head).

    With ``missing_ok``, an edge no face runs along gets a zero vector.
    """
    tail = faces.reshape(-1)
    head = np.roll(faces, -1, axis=1).reshape(-1)
    key_faces = tail.astype(np.int64) * (len(vertices) + 1) + head
    key_edges = edges[:, 0].astype(np.int64) * (len(vertices) + 1) + edges[:, 1]
    order = sort_order(key_faces)
    ordered = key_faces[order]
    if np.any(ordered[1:] == ordered[:-1]):  # a half-edge twice: which one is found
        order = np.argsort(key_faces)  # depends on the order within ties, kept as it was
    pos = np.searchsorted(key_faces[order], key_edges)
    at = order[np.clip(pos, 0, len(order) - 1)]
    face = at // 3
    tri = vertices[faces[face]]
    cross = cross_rows(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    unit = cross / np.maximum(np.linalg.norm(cross, axis=1), 1e-300)[:, None]
    if missing_ok:
        unit[key_faces[at] != key_edges] = 0.0
    return unit
