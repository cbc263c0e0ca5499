"""Topology of triangle meshes: vertex welding, edges, orientation and boundary loops.

Vectorised with numpy and scipy's sparse graph routines (connected components run in C);
no Python loop visits a triangle. A mesh here is a pair `vertices (n, 3) float`,
`faces (m, 3) int`.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from urdfinertia.inertia.polyhedron import cross_rows, used_vertices


def unique_rows(rows: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """`np.unique(rows, axis=0, return_inverse=True, return_counts=True)`, fast.

    numpy's row-wise unique sorts a structured view element by element, which dominated
    repair time on real meshes; a lexicographic sort of the columns (or of one packed
    integer key) gives the same groups in the same lexicographic order.
    """
    rows = np.asarray(rows)
    if len(rows) == 0:
        return rows.copy(), np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    if rows.dtype.kind in "iu" and rows.min() >= 0:
        base = int(rows.max()) + 1
        if base ** rows.shape[1] < 2**62:
            key = np.zeros(len(rows), dtype=np.int64)
            for col in rows.T.astype(np.int64):
                key = key * base + col
            return _unique_keys(rows, key)
    order = np.lexsort(rows.T[::-1])
    ordered = rows[order]
    new = np.concatenate([[True], np.any(ordered[1:] != ordered[:-1], axis=1)])
    group = np.cumsum(new) - 1
    inverse = np.empty(len(rows), dtype=np.int64)
    inverse[order] = group
    return ordered[new], inverse, np.bincount(group)


_MIX = np.array([0xBF58476D1CE4E5B9, 0x94D049BB133111EB], dtype=np.uint64)


def first_occurrences(rows: np.ndarray) -> np.ndarray:
    """Ascending indices of the first occurrence of each distinct float row (exact;
    `-0.0` and `0.0` are one value): one sort of a 64-bit hash, checked row by row
    (a collision falls back to the lexicographic sort)."""
    rows = np.asarray(rows, dtype=np.float64)
    if len(rows) == 0:
        return np.zeros(0, dtype=np.int64)
    columns, key = _row_keys(rows)
    order = np.argsort(key, kind="stable")
    ordered = key[order]
    new = np.empty(len(key), dtype=bool)
    new[0] = True
    np.not_equal(ordered[1:], ordered[:-1], out=new[1:])
    group = np.cumsum(new) - 1
    first = order[new]  # stable sort: the smallest index of each key comes first
    for column in columns:
        if not np.array_equal(column[order], column[first][group]):
            _, first = np.unique(rows + 0.0, axis=0, return_index=True)  # a collision
            break
    return np.sort(first)



def _row_keys(rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """`(columns, key)`: the rows' columns as 64-bit patterns (`-0.0` as `0.0`) and
    a 64-bit hash of each row (splitmix64's finaliser: float bits end in zeros, so they
    are mixed column by column)."""
    columns = np.ascontiguousarray((rows + 0.0).T).view(np.uint64)  # -0.0 + 0.0 is 0.0
    key = np.zeros(len(rows), dtype=np.uint64)
    for column in columns:
        key ^= column
        key ^= key >> np.uint64(30)
        key *= _MIX[0]
        key ^= key >> np.uint64(27)
        key *= _MIX[1]
        key ^= key >> np.uint64(31)
    return columns, key

def _unique_float_rows(rows: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """`unique_rows` of float rows by hashing their bits; None on a hash collision.

    Equal rows are found by one sort of a hash (the top bits of a 64-bit one; then
    checked row by row, so a collision falls back to the lexicographic sort); only the
    distinct rows are sorted lexicographically. For an STL triangle soup, which repeats
    each vertex about six times, that is several times cheaper than sorting every row on
    every column. The first occurrence of each row represents it (`-0.0` and `0.0`
    are one value), as in the stable lexicographic sort.
    """
    columns, key = _row_keys(rows)
    # the hash's top bits, leaving room to pack each row's position beside them
    # (:func:`sort_order`): a shorter hash only makes the check below fail more often
    keep = 63 - max(1, (len(key) - 1).bit_length())
    order, ordered = _sorted_keys((key >> np.uint64(64 - keep)).astype(np.int64))
    new = np.empty(len(key), dtype=bool)
    new[0] = True
    np.not_equal(ordered[1:], ordered[:-1], out=new[1:])
    starts = np.flatnonzero(new)
    group = np.cumsum(new) - 1
    first = np.minimum.reduceat(order, starts)  # first occurrence of each distinct row
    for column in columns:
        if not np.array_equal(column[order], column[first][group]):
            return None  # a hash collision (rare): sort instead
    distinct = rows[first]
    lex = np.lexsort(distinct.T[::-1])
    rank = np.empty(len(lex), dtype=np.int64)
    rank[lex] = np.arange(len(lex))
    inverse = np.empty(len(rows), dtype=np.int64)
    inverse[order] = rank[group]
    counts = np.diff(np.append(starts, len(rows)))[lex]
    return distinct[lex], inverse, counts


def _unique_keys(rows: np.ndarray, key: np.ndarray, order: np.ndarray | None = None,
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Groups of equal integer keys, as `unique_rows` returns them.

    Any member of a group represents it (its rows are equal), so one sort of the keys
    (`sort_order`, several times faster than the argsort `np.unique` uses) gives
    the same answer. `order` is `sort_order(key)` when the caller has it already.
    """
    if order is None:
        order, ordered = _sorted_keys(key)
    else:
        ordered = key[order]
    new = np.empty(len(key), dtype=bool)
    new[0] = True
    np.not_equal(ordered[1:], ordered[:-1], out=new[1:])
    group = np.cumsum(new) - 1
    inverse = np.empty(len(key), dtype=np.int64)
    inverse[order] = group
    starts = np.flatnonzero(new)
    counts = np.diff(np.append(starts, len(key)))
    return np.take(rows, order[starts], axis=0), inverse, counts


def sort_order(key: np.ndarray) -> np.ndarray:
    """`np.argsort(key, kind="stable")` of non-negative integer keys, fast.

    Where the keys leave room, each is packed with its position into one 64-bit word and
    the words are sorted by value (numpy's SIMD sort, several times faster than an
    argsort); the positions read back in that order are the stable order. Otherwise the
    stable argsort itself.
    """
    return _sorted_keys(key)[0]


def _sorted_keys(key: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """`(sort_order(key), key[sort_order(key)])`, the second read back from the packed
    words where they were packed."""
    n = len(key)
    if n == 0:
        return np.zeros(0, dtype=np.int64), key.copy()
    bits = max(1, (n - 1).bit_length())
    if key.dtype.kind not in "iu" or int(key.min()) < 0 or int(key.max()) >= 1 << (63 - bits):
        order = np.argsort(key, kind="stable")
        return order, key[order]
    packed = key.astype(np.int64) << bits
    packed |= np.arange(n, dtype=np.int64)
    packed.sort()
    ordered = (packed >> bits).astype(key.dtype, copy=False)
    packed &= (1 << bits) - 1
    return packed, ordered


def components(n: int, a: np.ndarray, b: np.ndarray) -> tuple[int, np.ndarray]:
    """Connected components of the undirected graph on `n` nodes with edges `a[i]-b[i]`."""
    if n == 0:
        return 0, np.zeros(0, dtype=np.int64)
    # imported here: scipy.sparse costs ~0.25 s to import, which a warm (cached) run skips
    from scipy.sparse import csr_matrix
    from scipy.sparse.csgraph import connected_components

    # float64 CSR is the form connected_components works on: built directly, no copies
    graph = csr_matrix((np.ones(len(a)), (a, b)), shape=(n, n))
    count, labels = connected_components(graph, directed=False)
    return int(count), labels.astype(np.int64)


def weld_vertices(vertices: np.ndarray, faces: np.ndarray, tolerance: float,
                  ) -> tuple[np.ndarray, np.ndarray]:
    """Merge vertices closer than `tolerance` (chains merge transitively).

    Returns the used, merged vertices and the faces re-indexed into them.
    """
    from scipy.spatial import cKDTree

    # np.unique(faces, return_inverse=True) without sorting: the used indices ascending
    mask = used_vertices(len(vertices), faces)
    rank = np.cumsum(mask) - 1
    inverse = rank[faces.reshape(-1)]
    v = vertices[mask]
    # exact duplicates first (STL soup repeats each vertex ~6 times): cheap and lossless
    soup = len(v) > 1.5 * len(faces)  # about 3 vertices per face: hashing pays off
    hashed = _unique_float_rows(v) if soup and len(v) > 1 else None
    exact, exact_inv, _ = hashed if hashed is not None else unique_rows(v)
    exact_inv = exact_inv.reshape(-1)
    if tolerance > 0 and len(exact) > 1:
        pairs = cKDTree(exact).query_pairs(tolerance, output_type="ndarray")
    if tolerance > 0 and len(exact) > 1 and len(pairs):
        _, label = components(len(exact), pairs[:, 0], pairs[:, 1])
        first = np.full(label.max() + 1, -1, dtype=np.int64)
        order = np.arange(len(exact))[::-1]
        first[label[order]] = order  # lowest index of each cluster represents it
        keep, remap = np.unique(first[label], return_inverse=True)
        merged = exact[keep]
        exact_inv = remap.reshape(-1)[exact_inv]
    else:
        merged = exact
    new_faces = exact_inv[inverse].reshape(faces.shape)
    return merged, new_faces.astype(np.int64)


def drop_degenerate(vertices: np.ndarray, faces: np.ndarray, area_tol: float,
                    ) -> np.ndarray:
    """Faces with three distinct vertices and an area above `area_tol`."""
    distinct = ((faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2])
                & (faces[:, 0] != faces[:, 2]))
    tri = np.take(vertices, faces, axis=0)  # vertices[faces], a faster gather
    area = 0.5 * np.linalg.norm(cross_rows(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    return faces[distinct & (area > area_tol)]


def cancel_duplicate_faces(faces: np.ndarray) -> tuple[np.ndarray, int, int]:
    """Remove repeated triangles.

    Copies with the same orientation are kept once (a body exported twice); a pair with
    opposite orientation cancels (the shared wall of two touching bodies, whose integrals
    cancel anyway). Returns the faces and the counts of removed repeats and cancelled pairs.
    """
    if len(faces) == 0:
        return faces, 0, 0
    key = np.sort(faces, axis=1)
    # orientation parity relative to the sorted order: of three distinct corners, a
    # rotation of the ascending order has exactly two ascending steps (cyclically)
    ups = ((faces[:, 0] < faces[:, 1]).astype(np.int8) + (faces[:, 1] < faces[:, 2])
           + (faces[:, 2] < faces[:, 0]))
    parity = np.where(ups == 2, 1, -1)
    _, group, counts = unique_rows(key)
    group = group.reshape(-1)
    net = np.bincount(group, weights=parity).astype(np.int64)
    # keep the first face of each group whose orientation matches the net sign
    want = np.sign(net)[group]
    candidate = np.flatnonzero(parity == want)
    # the first candidate of each group: the least position among its candidates
    cand_group = group[candidate]
    order = sort_order(cand_group)  # only the least position of a group counts
    starts = np.flatnonzero(np.diff(cand_group[order], prepend=-1))
    out = faces[np.sort(candidate[np.minimum.reduceat(order, starts)])]
    cancelled = int(np.sum(counts[net == 0]) // 2)
    repeats = len(faces) - len(out) - 2 * cancelled
    return out, repeats, cancelled


class EdgeTable(NamedTuple):
    """Half-edges of a mesh grouped by undirected edge (`edge_table`).

    Attributes
    ----------
    edge_id : (3m,) int
        Undirected edge of half-edge `3 f + k` (from corner k to k+1 of face f).
    forward : (3m,) bool
        Whether the half-edge runs from the lower to the higher vertex index.
    edges : (e, 2) int
        The undirected edges, lower index first, ascending.
    order : (3m,) int
        The half-edges grouped by edge: `edge_id[order]` is ascending (ascending
        half-edges within a group; no caller depends on that order).
    """

    edge_id: np.ndarray
    forward: np.ndarray
    edges: np.ndarray
    order: np.ndarray


def edge_table(faces: np.ndarray) -> EdgeTable:
    """Half-edges of the faces grouped by undirected edge (see `EdgeTable`)."""
    tail = faces.reshape(-1)
    head = np.roll(faces, -1, axis=1).reshape(-1)
    lo, hi = np.minimum(tail, head), np.maximum(tail, head)
    if len(lo) == 0 or lo.min() < 0 or int(hi.max()) >= 2**31:
        edges, edge_id, _ = unique_rows(np.stack([lo, hi], axis=1))
        order = np.argsort(edge_id, kind="stable")
        return EdgeTable(edge_id.reshape(-1), tail < head, edges, order)
    # unique_rows' packed key, without its generic checks
    base = int(hi.max()) + 1
    key = lo.astype(np.int64) * base + hi
    order, ordered = _sorted_keys(key)
    new = np.empty(len(key), dtype=bool)
    new[0] = True
    np.not_equal(ordered[1:], ordered[:-1], out=new[1:])
    edge_id = np.empty(len(key), dtype=np.int64)
    edge_id[order] = np.cumsum(new) - 1
    first = order[new]
    edges = np.stack([lo[first], hi[first]], axis=1)
    return EdgeTable(edge_id, tail < head, edges, order)


def consistent_orientation(faces: np.ndarray, table: EdgeTable | None = None,
                           ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Flip faces so that neighbours across every two-sided edge agree.

    Orientation propagates across edges shared by exactly two faces, as a graph
    problem on the double cover (face, side): consistent neighbours link equal sides,
    inconsistent ones opposite sides; a face whose two sides fall in one component lies
    on a non-orientable patch.

    Returns
    -------
    flip : (m,) bool
        Faces to reverse.
    patch : (m,) int
        Orientation patch of each face (faces linked through two-sided edges).
    non_orientable : (m,) bool

    `table` is `edge_table(faces)` when the caller has it already.
    """
    m = len(faces)
    edge_id, forward, edges, order = table if table is not None else edge_table(faces)
    counts = np.bincount(edge_id, minlength=len(edges))
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    two = np.flatnonzero(counts == 2)
    h1, h2 = order[starts[two]], order[starts[two] + 1]
    f1, f2 = h1 // 3, h2 // 3
    same_side = forward[h1] != forward[h2]  # opposite directions: already consistent
    a = np.concatenate([f1, f1 + m])
    b = np.concatenate([np.where(same_side, f2, f2 + m), np.where(same_side, f2 + m, f2)])
    _, label = components(2 * m, a, b)
    plus, minus = label[:m], label[m:]
    non_orientable = plus == minus
    flip = plus > minus
    _, patch = components(m, f1, f2)
    return flip, patch, non_orientable


def boundary_edges(faces: np.ndarray, table: EdgeTable | None = None) -> np.ndarray:
    """Directed edges where the surface is not closed, as the faces run along them.

    An undirected edge is closed when it is used as often in each direction; otherwise
    the surplus direction is returned, repeated as often as it is in surplus.

    Returns
    -------
    (b, 2) int
        `(tail, head)` pairs.
    """
    edge_id, forward, edges, _ = table if table is not None else edge_table(faces)
    net = np.bincount(edge_id, weights=np.where(forward, 1.0, -1.0),
                      minlength=len(edges)).astype(np.int64)
    idx = np.flatnonzero(net)
    reps = np.abs(net[idx])
    e = np.repeat(edges[idx], reps, axis=0)
    backward = np.repeat(net[idx] < 0, reps)
    e[backward] = e[backward][:, ::-1]
    return e


def face_components(faces: np.ndarray, table: EdgeTable | None = None,
                    ) -> tuple[int, np.ndarray]:
    """Components of faces linked through shared edges: `(count, label per face)`.

    Bodies that merely touch at a vertex, or cross without sharing an edge, stay apart.
    """
    m = len(faces)
    if m == 0:
        return 0, np.zeros(0, dtype=np.int64)
    edge_id, _, _, order = table if table is not None else edge_table(faces)
    same = edge_id[order][1:] == edge_id[order][:-1]
    return components(m, order[:-1][same] // 3, order[1:][same] // 3)


def is_closed_oriented(table: EdgeTable) -> bool:
    """Whether every edge has exactly two faces, running along it in opposite directions.

    Such a surface needs no orientation fix and no hole caps: `consistent_orientation`
    flips nothing and its patches are the `face_components`.
    """
    edge_id, forward, edges, _ = table
    if len(edge_id) != 2 * len(edges):
        return False
    uses = np.bincount(edge_id, minlength=len(edges))
    ups = np.bincount(edge_id[forward], minlength=len(edges))
    return bool(np.all(uses == 2) and np.all(ups == 1))


def split_vertices(n: int, faces: np.ndarray, label: np.ndarray, count: int,
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Give each labelled group of faces its own vertices.

    The result equals `np.unique(label[:, None] * n + faces, return_inverse=True)`
    split by label: `vertex` lists each group's used vertices (group by group,
    ascending within one), `local` re-indexes the faces into `vertex` and
    `bounds[c]:bounds[c + 1]` is group c's slice of `vertex`. Groups that share no
    vertex (the usual case: edge-connected components) take a linear pass instead of
    a sort.

    Returns
    -------
    vertex : (k,) int
    local : (m, 3) int
    bounds : (count + 1,) int
    """
    corner_label = np.repeat(label, 3)
    flat = faces.reshape(-1)
    vertex_label = np.full(n, count, dtype=np.int64)  # unused vertices sort last
    vertex_label[flat] = corner_label
    if np.array_equal(vertex_label[flat], corner_label):  # no vertex in two groups
        if count == 1:
            vertex = np.flatnonzero(vertex_label == 0)
        else:  # a radix sort when the labels fit 16 bits
            small = vertex_label.astype(np.int16) if count < 2**15 - 1 else vertex_label
            vertex = np.argsort(small, kind="stable")
        sizes = np.bincount(vertex_label, minlength=count + 1)[:count]
        bounds = np.concatenate([[0], np.cumsum(sizes)])
        vertex = vertex[:bounds[-1]]
        rank = np.empty(n, dtype=np.int64)
        rank[vertex] = np.arange(len(vertex))
        return vertex, rank[faces], bounds
    key = label[:, None] * n + faces
    uniq, local = np.unique(key, return_inverse=True)
    bounds = np.searchsorted(uniq, np.arange(count + 1) * n)
    return uniq - np.repeat(np.arange(count), np.diff(bounds)) * n, local.reshape(-1, 3), bounds
