"""Boundary cycles of an oriented surface, split at pinch vertices.

A hole's boundary is a cycle of directed edges. Where two holes touch at one vertex (two
missing triangles that share only a corner) the vertex has two incoming and two outgoing
boundary edges; each incoming edge is paired with the outgoing edge that follows it
counter-clockwise about the vertex normal, which is the one across the same hole (the
faces around the vertex run counter-clockwise from an outgoing to an incoming boundary
edge, then the hole). Vectorised with numpy and scipy's connected components.
"""

from __future__ import annotations

import numpy as np

from urdfinertia.inertia.polyhedron import cross_rows
from urdfinertia.mesh.repair.graph import components


def boundary_cycles(vertices: np.ndarray, faces: np.ndarray, edges: np.ndarray,
                    ) -> tuple[np.ndarray, np.ndarray]:
    """Successor of each boundary edge in its cycle, and the cycle of each edge.

    Parameters
    ----------
    vertices : (n, 3) float
    faces : (m, 3) int
        Consistently oriented.
    edges : (b, 2) int
        Boundary edges `(tail, head)` as the faces run along them.

    Returns
    -------
    succ : (b,) int
    cycle : (b,) int
        Cycle labels `0 .. c-1`.
    """
    n, b = len(vertices), len(edges)
    tail, head = edges[:, 0], edges[:, 1]
    # records: one per (vertex, incident boundary edge), incoming or outgoing
    rec_v = np.concatenate([head, tail])
    rec_e = np.concatenate([np.arange(b), np.arange(b)])
    rec_in = np.concatenate([np.ones(b, bool), np.zeros(b, bool)])
    other = np.concatenate([tail, head])
    normal = _vertex_normals(vertices, faces)
    t1, t2 = _tangent_basis(normal[rec_v])
    d = vertices[other] - vertices[rec_v]
    angle = np.arctan2(np.einsum("ij,ij->i", d, t2), np.einsum("ij,ij->i", d, t1))
    order = np.lexsort((angle, rec_v))
    v_sorted, in_sorted = rec_v[order], rec_in[order]
    start = np.searchsorted(v_sorted, v_sorted, side="left")
    count = np.bincount(rec_v, minlength=n)[v_sorted]
    pos = np.arange(2 * b) - start
    nxt = start + (pos + 1) % count
    # alternating in/out about a vertex: pair each incoming with the next outgoing (ccw);
    # otherwise fall back to pairing by rank, which is still a valid decomposition
    alternate = np.ones(n, dtype=bool)
    np.logical_and.at(alternate, v_sorted, in_sorted != in_sorted[nxt])
    shift = np.where(alternate[v_sorted] & ~in_sorted[start], 1, 0)
    rank = _rank_within(v_sorted, in_sorted)
    k_in = np.bincount(v_sorted[in_sorted], minlength=n)[v_sorted]
    outs = order[~in_sorted]
    out_edge = np.full((2 * b,), -1, dtype=np.int64)
    key_out = v_sorted[~in_sorted] * (b + 1) + rank[~in_sorted]
    ins = np.flatnonzero(in_sorted)
    want = v_sorted[ins] * (b + 1) + (rank[ins] + shift[ins]) % np.maximum(k_in[ins], 1)
    at = np.searchsorted(key_out, want)
    out_edge[ins] = rec_e[outs[np.clip(at, 0, len(outs) - 1)]]
    succ = np.empty(b, dtype=np.int64)
    succ[rec_e[order[ins]]] = out_edge[ins]
    _, cycle = components(b, np.arange(b), succ)
    return succ, cycle


def ordered_cycles(succ: np.ndarray, cycle: np.ndarray, max_size: int,
                   ) -> list[tuple[np.ndarray, np.ndarray]]:
    """Edges of each cycle of at most `max_size` edges, in order.

    Returns `[(cycle ids (L,), edge indices (L, s))]`, one entry per cycle size `s`.
    """
    n_cycles = int(cycle.max() + 1) if len(cycle) else 0
    size = np.bincount(cycle, minlength=n_cycles)
    first = np.full(n_cycles, -1, dtype=np.int64)
    first[cycle[::-1]] = np.arange(len(cycle))[::-1]
    out = []
    for s in np.unique(size[size <= max_size]):  # one pass per cycle size
        ids = np.flatnonzero(size == s)
        order = np.empty((len(ids), s), dtype=np.int64)
        order[:, 0] = first[ids]
        for k in range(1, s):  # follow successors: s steps, each over all cycles
            order[:, k] = succ[order[:, k - 1]]
        out.append((ids, order))
    return out


def _rank_within(group_sorted: np.ndarray, flag: np.ndarray) -> np.ndarray:
    """Rank of each record among the records of its group with the same flag (sorted)."""
    rank = np.zeros(len(flag), dtype=np.int64)
    for value in (True, False):
        idx = np.flatnonzero(flag == value)
        g = group_sorted[idx]
        first = np.searchsorted(g, g, side="left")
        rank[idx] = np.arange(len(idx)) - first
    return rank


def _vertex_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    tri = np.take(vertices, faces, axis=0)  # vertices[faces], a faster gather
    cross = cross_rows(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    # np.add.at(normal, faces[:, k], cross) for k = 0, 1, 2, as three bincounts: the
    # same additions in the same order per vertex (corner by corner, face by face)
    corner = faces.T.reshape(-1)
    normal = np.stack([np.bincount(corner, weights=np.tile(cross[:, c], 3),
                                   minlength=len(vertices)) for c in range(3)], axis=1)
    return normal / np.maximum(np.linalg.norm(normal, axis=1), 1e-300)[:, None]


def _tangent_basis(normal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    helper = np.where(np.abs(normal[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    t1 = np.cross(normal, helper)
    t1 /= np.maximum(np.linalg.norm(t1, axis=1), 1e-300)[:, None]
    return t1, np.cross(normal, t1)
