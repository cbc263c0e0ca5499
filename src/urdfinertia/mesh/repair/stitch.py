"""Join boundary loops that run alongside each other before anything is capped as a hole.

CAD exporters that tessellate faces independently leave seams: two rims of the same
surface a tiny distance apart, sharing no vertex, often with the vertices of one rim
lying on the edges of the other (T-junctions). Welding at round-off scale misses them,
and capping each rim as a hole adds two large, wrong caps. Here, within a tolerance
scaled to the mesh, boundary vertices are merged with nearby boundary vertices (each
cluster moves to its mean, so errors on both rims cancel to first order) and then
inserted into nearby boundary edges, whose face is split into a fan. Only boundary
vertices and boundary edges take part: a closed body, however close to another, is
never touched, so no stitch crosses a real gap between two bodies.

The stated uncertainty bounds the volume the stitch changed: a vertex moved by `d`
sweeps at most `d` times a third of the area of its faces; an inserted vertex adds the
tetrahedron it forms with the split face. Which of two rims was the true surface is not
in the file, so the slab between them (the cut's area times the gap) is added too.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from urdfinertia.inertia.polyhedron import cross_rows
from urdfinertia.mesh.repair.graph import EdgeTable, components, edge_table
from urdfinertia.timing import Deadline

STITCH_RTOL = 1e-3
"""Stitch tolerance as a fraction of the bounding-box diagonal (seams of 1e-6 to 1e-4)."""
STITCH_EDGE_FRACTION = 0.25
"""... and at most this fraction of the median edge length, so no triangle collapses."""
SPLIT_PASSES = 3
"""T-junction passes: a face has three edges, each split in its own pass."""


@dataclass(frozen=True, eq=False)
class Stitch:
    """A stitched surface and what it took.

    Attributes
    ----------
    vertices : (n, 3) float
    faces : (m, 3) int
    merged : int
        Boundary vertices merged into a nearby boundary vertex.
    inserted : int
        Boundary vertices inserted into a nearby boundary edge (T-junctions).
    gap : float
        m, the largest distance bridged.
    boundary_before, boundary_after : int
        Boundary edges (used by one face) before and after.
    uncertainty : float
        m^3, bound on the volume the stitch changed.
    ambiguous : bool
        Boundary edges remain, or the stitch made edges shared by more than two faces:
        the caller should compare with the unstitched repair.
    table : EdgeTable
        `edge_table(faces)`, for the caller to reuse.
    skipped : str
        Why the T-junction search was not made (too many candidates), "" when it was.
    """

    vertices: np.ndarray
    faces: np.ndarray
    merged: int
    inserted: int
    gap: float
    boundary_before: int
    boundary_after: int
    uncertainty: float
    ambiguous: bool
    table: EdgeTable
    skipped: str = ""

    def provenance(self) -> str:
        """One line for the solid's provenance.

        Returns
        -------
        str
            How many boundary vertices were stitched, and across what gaps.
        """
        return (f"stitched {self.merged + self.inserted} boundary vertices "
                f"(gaps up to {self.gap:.2g} m)")

    def note(self) -> str:
        """The repair note of the stitch.

        Returns
        -------
        str
            What was merged, split and joined.
        """
        what = []
        if self.merged:
            what.append(f"merged {self.merged} boundary vertices")
        if self.inserted:
            what.append(f"split {self.inserted} T-junctions")
        skipped = f"; T-junctions not searched ({self.skipped})" if self.skipped else ""
        return (f"stitched seams: {' and '.join(what)} across gaps up to {self.gap:.2g} m; "
                f"{self.boundary_before - self.boundary_after} of {self.boundary_before} "
                f"open edges joined{skipped}")


def stitch_tolerance(vertices: np.ndarray, faces: np.ndarray, size: float) -> float:
    """The stitch distance: a fraction of the diagonal `size`, and of the typical edge."""
    a, b = vertices[faces], np.roll(vertices[faces], -1, axis=1)
    median_edge = float(np.median(np.linalg.norm(b - a, axis=2)))
    return min(STITCH_RTOL * size, STITCH_EDGE_FRACTION * median_edge)


def stitch_seams(vertices: np.ndarray, faces: np.ndarray, size: float,
                 table: EdgeTable | None = None, deadline: Deadline | None = None,
                 ) -> Stitch | None:
    """Merge and insert boundary vertices within `stitch_tolerance`; None if none.

    `faces` need not be oriented: a boundary edge is an edge used by one face.
    `table` is `edge_table(faces)` when the caller has it already. `deadline` is
    checked between the T-junction search's chunks (raises
    [`OverBudget`][urdfinertia.timing.OverBudget]). A search that would examine more pairs than
    any seam needs (`MAX_CANDIDATES_PER_EDGE`: a triangle soup) is not made, which
    [`Stitch.skipped`][Stitch.skipped] says.
    """
    table = table if table is not None else edge_table(faces)
    edges = _boundary(faces, table)
    if len(edges) == 0:
        return None
    tol = stitch_tolerance(vertices, faces, size)
    before = len(edges)
    vertices, stitched, merged, gap, moved = _merge_boundary_vertices(vertices, faces, edges,
                                                                      tol, table)
    if stitched is not faces:  # merged: the table is of the old faces
        faces, table = stitched, edge_table(stitched)
    inserted, swept = 0, 0.0
    skipped = ""
    for _ in range(SPLIT_PASSES):  # each pass splits at most one edge per face
        edges = _boundary(faces, table)
        try:
            split, count, dist, vol = _split_t_junctions(vertices, faces, edges, tol,
                                                         deadline)
        except TooManyCandidates as exc:
            skipped = str(exc)
            break
        if count == 0:
            break
        faces, table = split, edge_table(split)
        inserted += count
        gap = max(gap, dist)
        swept += vol
    if merged == 0 and inserted == 0:
        return None
    uses = np.bincount(table.edge_id, minlength=len(table.edges))
    after = int(np.count_nonzero(uses == 1))
    ambiguous = after > 0 or bool(np.any(uses > 2))
    return Stitch(vertices, faces, merged, inserted, gap, before, after, moved + swept,
                  ambiguous, table, skipped)


def _boundary(faces: np.ndarray, table: EdgeTable) -> np.ndarray:
    """Undirected edges used by exactly one face, and that face: (b, 3) `(lo, hi, face)`.

    `table` is `edge_table(faces)`.
    """
    if len(faces) == 0:
        return np.zeros((0, 3), dtype=np.int64)
    uses = np.bincount(table.edge_id, minlength=len(table.edges))
    half = np.flatnonzero(uses[table.edge_id] == 1)  # the half-edges of one-face edges
    lo_hi = table.edges[table.edge_id[half]]
    return np.column_stack([lo_hi, half // 3])


def _merge_boundary_vertices(vertices: np.ndarray, faces: np.ndarray, edges: np.ndarray,
                             tol: float, table: EdgeTable,
                             ) -> tuple[np.ndarray, np.ndarray, int, float, float]:
    """Cluster boundary vertices within `tol` (not joined by an edge) at their mean.

    `table` is `edge_table(faces)`. Returns vertices, faces (collapsed ones dropped;
    `faces` itself when nothing merged), how many vertices merged, the largest distance
    moved and the bound on the volume swept.
    """
    from scipy.spatial import cKDTree

    ids = np.unique(edges[:, :2])
    pairs = cKDTree(vertices[ids]).query_pairs(tol, output_type="ndarray")
    if len(pairs):  # two ends of one short edge are a triangle, not a seam
        a, b = ids[pairs[:, 0]], ids[pairs[:, 1]]
        n = len(vertices)
        key = table.edges[:, 0] * n + table.edges[:, 1]
        want = np.minimum(a, b) * n + np.maximum(a, b)
        at = np.clip(np.searchsorted(key, want), 0, len(key) - 1)
        pairs = pairs[key[at] != want]
    if len(pairs) == 0:
        return vertices, faces, 0, 0.0, 0.0
    count, label = components(len(ids), pairs[:, 0], pairs[:, 1])
    size = np.bincount(label, minlength=count)
    mean = np.stack([np.bincount(label, weights=vertices[ids, k], minlength=count)
                     for k in range(3)], axis=1) / size[:, None]
    moving = size[label] > 1
    shift = np.linalg.norm(mean[label] - vertices[ids], axis=1)
    rep = np.full(count, -1, dtype=np.int64)
    rep[label[::-1]] = ids[::-1]  # the lowest index of each cluster stands for it
    out = vertices.copy()
    out[rep] = mean
    remap = np.arange(len(vertices))
    remap[ids] = rep[label]
    star = _star_areas(vertices, faces)
    swept = float(np.sum(shift * star[ids]) / 3.0)
    # which rim was the true surface is unknown: the slab between the rims, the cut's
    # area times the distance each vertex moved, bounded with a fan about the rims'
    # centroid (a fan's area is at least that of any surface spanning the rims)
    moved_by = np.zeros(len(vertices))
    moved_by[ids] = np.where(moving, shift, 0.0)
    rim = edges[(moved_by[edges[:, 0]] > 0) & (moved_by[edges[:, 1]] > 0)]
    centre = vertices[ids[moving]].mean(axis=0)
    fan = 0.5 * np.linalg.norm(np.cross(vertices[rim[:, 0]] - centre,
                                        vertices[rim[:, 1]] - centre), axis=1)
    swept += float(np.sum(fan * 0.5 * (moved_by[rim[:, 0]] + moved_by[rim[:, 1]])))
    new = remap[faces]
    keep = (new[:, 0] != new[:, 1]) & (new[:, 1] != new[:, 2]) & (new[:, 0] != new[:, 2])
    gap = float(2.0 * shift[moving].max())
    return out, new[keep], int(np.count_nonzero(moving) - np.count_nonzero(size > 1)), gap, swept


def _star_areas(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    tri = np.take(vertices, faces, axis=0)
    area = 0.5 * np.linalg.norm(cross_rows(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    return np.bincount(faces.reshape(-1), weights=np.repeat(area, 3), minlength=len(vertices))


#: Candidate (edge, vertex) pairs examined at once by the T-junction search: its arrays
#: take about 100 bytes per pair, so a chunk stays near 100 MB whatever the mesh.
CANDIDATE_CHUNK = 1 << 20
#: More candidates than this per boundary edge on average (and more than
#: ``CANDIDATE_CHUNK`` in all) is no seam: a triangle soup's long random edges each pass
#: near most boundary vertices (3,000 such triangles took 26 s and 2.9 GB here). Seams of
#: real meshes stay below 20 on average (example-robot-data: at most 18, one edge 2,841).
MAX_CANDIDATES_PER_EDGE = 256


class TooManyCandidates(Exception):
    """The T-junction search would examine more pairs than any seam needs."""


def _split_t_junctions(vertices: np.ndarray, faces: np.ndarray, edges: np.ndarray,
                       tol: float, deadline: Deadline | None = None,
                       ) -> tuple[np.ndarray, int, float, float]:
    """Insert boundary vertices lying within `tol` of a boundary edge into that edge.

    The edge's face `(u, w, c)` becomes the fan `(u, p1, c), ..., (pk, w, c)` with
    the points sorted along the edge; at most one edge per face is split per call.
    Returns the faces, how many vertices were inserted, the largest distance bridged and
    the volume of the tetrahedra `(u, p, w, c)` added.

    Raises
    ------
    TooManyCandidates
        Past `MAX_CANDIDATES_PER_EDGE` (the caller leaves the seams alone).
    OverBudget
        `deadline` expired between chunks.
    """
    from scipy.spatial import cKDTree

    if len(edges) == 0:
        return faces, 0, 0.0, 0.0
    ids = np.unique(edges[:, :2])
    a, b = vertices[edges[:, 0]], vertices[edges[:, 1]]
    length = np.linalg.norm(b - a, axis=1)
    tree = cKDTree(vertices[ids])
    centre, radius = 0.5 * (a + b), 0.5 * length + tol
    counts = np.asarray(tree.query_ball_point(centre, radius, return_length=True),
                        dtype=np.int64)
    total = int(counts.sum())
    if total == 0:
        return faces, 0, 0.0, 0.0
    if total > max(CANDIDATE_CHUNK, MAX_CANDIDATES_PER_EDGE * len(edges)):
        raise TooManyCandidates(f"{total / len(edges):.0f} boundary vertices near each "
                                "boundary edge on average")
    found = []  # the pairs that pass, chunk by chunk of edges (bounded memory)
    ends = np.searchsorted(np.cumsum(counts), np.arange(CANDIDATE_CHUNK, total,
                                                         CANDIDATE_CHUNK), side="right")
    for lo, hi in zip(np.r_[0, ends], np.r_[ends, len(edges)], strict=True):
        if deadline is not None:
            deadline.check()
        if hi > lo:
            found.append(_near_edges(vertices, edges, ids, tree, a, b, length, centre, radius,
                                     tol, int(lo), int(hi)))
    e, p, t, dist = (np.concatenate(x) for x in zip(*found, strict=True))
    if len(e) == 0:
        return faces, 0, 0.0, 0.0
    # one edge per face in this pass: the lowest-numbered edge of each face
    face = edges[e, 2]
    first_edge = np.full(len(faces), len(edges), dtype=np.int64)
    np.minimum.at(first_edge, face, e)
    ok = first_edge[face] == e
    e, p, t, dist, face = e[ok], p[ok], t[ok], dist[ok], face[ok]
    order = np.lexsort((t, e))
    e, p, t, dist, face = e[order], p[order], t[order], dist[order], face[order]
    f = faces[face]
    lo = edges[e, 0]
    # the corner of each split face where its edge starts, as the face runs (u -> w)
    k = np.argmax(f == lo[:, None], axis=1)
    runs_up = f[np.arange(len(f)), (k + 1) % 3] == edges[e, 1]
    u = np.where(runs_up, lo, edges[e, 1])
    w = np.where(runs_up, edges[e, 1], lo)
    c = f[np.arange(len(f)), np.where(runs_up, (k + 2) % 3, (k + 1) % 3)]
    # points in the order the face runs: ascending t from lo, so reverse where u != lo
    t_run = np.where(runs_up, t, 1.0 - t)
    order = np.lexsort((t_run, e))
    e, p, u, w, c, dist, face = (x[order] for x in (e, p, u, w, c, dist, face))
    sliver = np.zeros(len(faces), dtype=bool)  # a face's own corner near its edge: leave it
    sliver[face[p == c]] = True
    ok = ~sliver[face]
    e, p, u, w, c, dist, face = (x[ok] for x in (e, p, u, w, c, dist, face))
    if len(e) == 0:
        return faces, 0, 0.0, 0.0
    start = np.r_[True, e[1:] != e[:-1]]
    stop = np.r_[e[1:] != e[:-1], True]
    prev = np.where(start, u, np.roll(p, 1))
    fan = np.stack([prev, p, c], axis=1)
    last = np.stack([p[stop], w[stop], c[stop]], axis=1)
    tet = np.einsum("ij,ij->i", vertices[u] - vertices[c],
                    np.cross(vertices[p] - vertices[c], vertices[w] - vertices[c]))
    keep = np.ones(len(faces), dtype=bool)
    keep[face] = False
    out = np.concatenate([faces[keep], fan, last])
    return out, len(p), float(dist.max()), float(np.abs(tet).sum() / 6.0)


def _near_edges(vertices: np.ndarray, edges: np.ndarray, ids: np.ndarray, tree, a, b,
                length, centre, radius, tol: float, lo: int, hi: int):  # noqa: ANN001
    """(edge, vertex, t along the edge, distance) of the boundary vertices within ``tol``
    of boundary edges ``lo..hi``, off both ends (what :func:`_split_t_junctions` splits)."""
    near = tree.query_ball_point(centre[lo:hi], radius[lo:hi])
    counts = np.fromiter((len(x) for x in near), dtype=np.int64, count=len(near))
    e = lo + np.repeat(np.arange(hi - lo), counts)
    p = ids[np.concatenate([np.asarray(x, dtype=np.int64) for x in near if len(x)]
                           or [np.zeros(0, dtype=np.int64)])]
    d = b[e] - a[e]
    t = np.einsum("ij,ij->i", vertices[p] - a[e], d) / np.maximum(length[e] ** 2, 1e-300)
    foot = a[e] + t[:, None] * d
    dist = np.linalg.norm(vertices[p] - foot, axis=1)
    end = np.minimum(np.linalg.norm(vertices[p] - a[e], axis=1),
                     np.linalg.norm(vertices[p] - b[e], axis=1))
    ok = ((p != edges[e, 0]) & (p != edges[e, 1]) & (t > 0) & (t < 1) & (dist <= tol)
          & (end > tol))
    return e[ok], p[ok], t[ok], dist[ok]
