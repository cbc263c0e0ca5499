"""Close the holes of an oriented surface with caps, and estimate what that costs.

A boundary loop is a set of directed edges where the surface is not closed, grouped by
shared vertices. Capping every loop makes the surface closed, so the polyhedral integrals
are well defined. Up to three caps are built per loop:

* a fan about the loop's perimeter centroid (one new vertex);
* for a simple loop of at most `TRIANGULATE_MAX` vertices, the triangulation of the
  loop's own vertices that continues the surrounding surface best: dynamic programming
  over the polygon (as in Liepa 2003, "Filling holes in meshes"), minimising the angle
  between each cap triangle and the face across its rim edge. This restores a lost
  triangle pair across a sharp CAD edge, which a fan would cut off;
* for a larger loop, a cap through the level set `w = 1/2` of the surface's
  generalized winding number (`level_caps`), independent of the rim's
  triangulation; it is used where it meets the rim at a smaller angle than the fan.
  Its search costs (ring points x faces) per step, so it is skipped beyond
  `LEVEL_BUDGET`.

The triangulation is used where it exists. A planar loop is closed exactly by any of
them (every planar cap on the same loop has the same flux integral) and states no error.
Otherwise a loop's stated uncertainty is the larger of:

* the spread of the candidate caps' volumes (how much the answer depends on the cap), and
* the volume of a tent over the cap, continuing the rim faces at the angle `theta`
  at which the chosen cap meets them (length-weighted mean, at most `TENT_MAX_ANGLE`):
  `A r tan(theta) / 2`, with `A` the cap's area and `r = 2 A / P` its half-width
  (`P` the loop's perimeter). A cap that continues the surface smoothly states little;
  one that cuts across a lost corner or edge states about the volume that was lost.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from urdfinertia.inertia.polyhedron import cross_rows, face_volumes
from urdfinertia.mesh.repair.graph import EdgeTable, boundary_edges, sort_order
from urdfinertia.mesh.repair.level_caps import level_caps, level_caps_points
from urdfinertia.mesh.repair.loops import boundary_cycles, ordered_cycles
from urdfinertia.mesh.repair.triangulation import best_triangulations, size_bands
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
        Loops closed by a winding-number level cap (`level_caps`).
    dependence : (k,) float
        m^3, how much the volume depends on the cap where there is a choice of caps
        (triangulation against fan for loops of at most `SHORT_LOOP_MAX` edges), or a
        spherical cap's volume over a larger loop at the fan's rim angle: the figure by
        which two whole repairs of one mesh are compared (see `pipeline`).
    """

    vertex: np.ndarray
    area: np.ndarray
    uncertainty: np.ndarray
    planar: np.ndarray
    level: np.ndarray
    dependence: np.ndarray

    @classmethod
    def none(cls) -> HoleCaps:
        """No caps.

        Returns
        -------
        HoleCaps
            Empty.
        """
        return cls(np.zeros(0, dtype=np.int64), np.zeros(0), np.zeros(0),
                   np.zeros(0, dtype=bool), np.zeros(0, dtype=bool), np.zeros(0))

    def subset(self, mask: np.ndarray) -> HoleCaps:
        """The caps `mask` selects.

        Parameters
        ----------
        mask : (n,) bool
            One entry per cap.

        Returns
        -------
        HoleCaps
            Those caps.
        """
        return HoleCaps(self.vertex[mask], self.area[mask], self.uncertainty[mask],
                        self.planar[mask], self.level[mask], self.dependence[mask])

    @property
    def loops(self) -> int:
        """How many holes are capped."""
        return len(self.vertex)

    def widened(self) -> HoleCaps:
        """These caps (fans) with `dependence` added to each uncertainty: what a refined
        cap, not computed, might have moved the volume (a spherical cap at the rim angle).
        """
        return HoleCaps(self.vertex, self.area, self.uncertainty + self.dependence,
                        self.planar, self.level, self.dependence)


PLANAR_RTOL = 1e-9
"""A loop is planar when no vertex leaves its plane by more than this fraction of its size."""
TRIANGULATE_MAX = 200
"""Largest simple loop (vertices) triangulated by dynamic programming (time and memory grow as its
cube); larger ones get fans or level caps.
"""
SHORT_LOOP_MAX = 40
"""Loops of at most this many edges are short: always triangulated (a few lost triangles), without a
winding-number vote; longer ones are wide.
"""
WIDE_TRIANGULATION_BUDGET = 1_000_000
"""Candidate triangles (s^3 / 6 per loop of s edges) the programme may cost, per surface, for loops
longer than `SHORT_LOOP_MAX`: about seven loops of 150 edges. The loops left over get fans or
level caps.
"""
TENT_MAX_ANGLE = np.radians(60.0)
"""Steepest rim continuation the tent of the stated uncertainty assumes (radians)."""
VOTE_GRID = 10
"""Grid points per axis, and the fewest disputed points, of the winding-number vote on a long loop's
triangulation (`_winding_refutes`).
"""
VOTE_MIN = 8
VOTE_BUDGET = 100_000_000
"""Point-face pairs all votes on one surface may evaluate (~3 s at the limit)."""
LEVEL_BUDGET = 2_000_000
"""Largest (ring points x faces) a surface's level caps may evaluate per search step (about 30
steps, ~0.1 s each at the limit); beyond it the fans stand (a large visual mesh with long open
rims).
"""
FAN_TENT_MIN = 12
"""Loops of at least this many edges are also bounded by their fan's tent (smaller ones are a few
lost triangles, which the triangulation restores).
"""
LEVEL_MIN_GAIN = 1e-3
"""A level cap replaces the fan only if it meets the rim at least this much flatter."""


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
        Half-edges of `faces` grouped by edge, as `boundary_edges` reads
        them (`edge_table(faces)`, or a table of the same edges whose half-edges run
        as `faces` do), when the caller has it already.

    Raises
    ------
    OverBudget
        `deadline` expired (the caller falls back to `triangulate=False`).

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
    long_tri = has_tri & (loop_size > SHORT_LOOP_MAX)
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
    short_tri = has_tri & (np.bincount(loop, minlength=n_loops) <= SHORT_LOOP_MAX)
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
    """The loops among `loops` whose triangulation the winding numbers refute.

    Per loop, points on a `VOTE_GRID`^3 grid over its bounding box (both caps lie in
    the convex hull of its vertices) are classed inside or outside the surface closed by
    the loop's fan and by its triangulation. Where the two disagree, the generalized
    winding number of the surface without the loop's cap (every other loop fan-capped)
    says which side the open surface puts the point on. The triangulation is refuted
    when fewer than half of the disputed points side with it; with fewer than
    `VOTE_MIN` disputed points the caps barely differ and it stands. Loops beyond
    `VOTE_BUDGET` get no vote and are refuted: an unchecked long triangulation is not
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
        own = np.arange(len(fan_tri)).reshape(-1, 3)
        w_fan = winding_numbers(grid, fan_tri, own)
        w_tri_cap = winding_numbers(grid, tri_tri, np.arange(len(tri_tri)).reshape(-1, 3))
        # the surface's count w is an integer: where the caps' winding numbers differ by
        # at most 1/4, w - w_fan + w_tri_cap lies on w's side of 1/2 and nothing is
        # disputed, so rays are counted only elsewhere (NaN included)
        moved = ~(np.abs(w_tri_cap - w_fan) <= 0.25)
        if np.count_nonzero(moved) < VOTE_MIN:
            continue
        w_fanned = counter(grid, exact_on_graze=False, only=moved)
        w_open = w_fanned - w_fan
        w_tri = w_open + w_tri_cap
        in_fan, in_tri = w_fanned > 0.5, w_tri > 0.5
        disputed = (in_fan != in_tri) & moved
        if np.count_nonzero(disputed) < VOTE_MIN:
            continue
        with_tri = np.count_nonzero((w_open[disputed] > 0.5) == in_tri[disputed])
        if 2 * with_tri < np.count_nonzero(disputed):
            refuted.append(k)
    return np.array(refuted, dtype=np.int64)


def cap_with_fans(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The surface of `close_holes(vertices, faces, triangulate=False)`, without the
    statistics of its caps: a fan about every loop's perimeter centroid."""
    edges = boundary_edges(faces)
    if len(edges) == 0:
        return vertices, faces
    _, loop = boundary_cycles(vertices, faces, edges)
    fan_v, fan_f, _ = _fans(vertices, edges, loop, int(loop.max() + 1))
    return fan_v, np.concatenate([faces, fan_f.astype(np.int64)])


def _fans(vertices: np.ndarray, edges: np.ndarray, loop: np.ndarray, n_loops: int,
          ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Fan caps about each loop's perimeter centroid (appended as vertex `n + loop`)."""
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
    than `SHORT_LOOP_MAX` edges smallest first within `WIDE_TRIANGULATION_BUDGET`.

    Returns the cap faces and the loop of each. Loops of similar sizes are solved
    together (`best_triangulations`: one step per interval width,
    vectorised over intervals, splits and loops; `size_bands`).
    """
    groups: list[tuple[np.ndarray, np.ndarray]] = []  # (loop ids, rows of their edges)
    budget = WIDE_TRIANGULATION_BUDGET
    for ids, order in ordered_cycles(succ, loop, TRIANGULATE_MAX):  # by size, ascending
        s = order.shape[1]
        if s < 4:
            continue
        if s > SHORT_LOOP_MAX:  # wide loops: the programme's work grows as s^3 / 6
            afford = min(len(ids), int(budget // (s ** 3 / 6)))
            if afford == 0:
                break
            ids, order = ids[:afford], order[:afford]
            budget -= afford * s ** 3 / 6
        groups.append((ids, order))
    faces_out: list[np.ndarray] = []
    loops_out: list[np.ndarray] = []
    for band in size_bands([g[1].shape[1] for g in groups], [len(g[0]) for g in groups]):
        deadline.check()
        part = [groups[g] for g in band]
        s = part[-1][1].shape[1]
        # the band's loops padded to its largest (the padding repeats a loop's last corner)
        order = np.concatenate([np.pad(o, ((0, 0), (0, s - o.shape[1])), mode="edge")
                                for _, o in part])
        sizes = np.concatenate([np.full(len(i), o.shape[1]) for i, o in part])
        corners = edges[order, 0]  # (L, s) vertex indices in boundary order
        tris, poly = best_triangulations(vertices[corners], rim_normal[order], sizes)
        faces_out.append(corners[poly[:, None], tris])
        loops_out.append(np.concatenate([i for i, _ in part])[poly])
    if not faces_out:
        return np.zeros((0, 3), dtype=np.int64), np.zeros(0, dtype=np.int64)
    return np.concatenate(faces_out), np.concatenate(loops_out)


@dataclass(frozen=True, eq=False)
class _Rim:
    """The boundary edges of a surface: loop, length and rim-face normal of each."""

    edges: np.ndarray
    loop: np.ndarray
    length: np.ndarray
    normal: np.ndarray
    loops: int


def _slope(theta: np.ndarray) -> np.ndarray:
    """Slope of a rim face continued over a cap it meets at `theta` (capped)."""
    return np.tan(np.minimum(theta, TENT_MAX_ANGLE))


def _rim_mean(vertices: np.ndarray, caps: np.ndarray, cap_loop: np.ndarray, rim: _Rim,
              of: Callable[[np.ndarray], np.ndarray]) -> np.ndarray:
    """Length-weighted mean of `of(angle between cap and rim face)` per loop.

    The cap face along boundary edge `tail -> head` runs `head -> tail`. Loops
    without a cap in `caps` get `of(pi / 2)`.
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

    With `missing_ok`, an edge no face runs along gets a zero vector.
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
