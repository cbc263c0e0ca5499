"""Minimum-cost triangulations of polygons whose edges continue a surface.

The interval dynamic programme of Liepa (2003, "Filling holes in meshes") over the
polygon's corners `0 .. s-1`: the best triangulation of the interval `(i, j)` splits
it at the corner `k` minimising `cost(i, k) + cost(k, j) + triangle(i, k, j)`. It runs
width by width (`j - i = 2 .. s-1`): all intervals of one width, all their splits and
all polygons of one batch in a few vectorised operations on strided views of the cost
table, so nothing of size `s^3` is ever held. Polygons of different sizes share a batch,
padded to the largest: an interval of a polygon only ever reads its own sub-intervals, so
the padding changes none of its costs. A triangle's cost is the angle between it and the
surface face across each of its polygon edges, plus a small area term.

The costs are those of a triangle-by-triangle evaluation bit for bit (the same products,
differences and sums, in the same order), and ties go to the smallest split, so the
choice does not depend on how the polygons are batched.
"""

from __future__ import annotations

import numpy as np

AREA_WEIGHT = 1e-3
"""Weight of a cap triangle's relative area against its rim angle (radians): a tie-break."""
ALL_AT_ONCE_MAX = 40
"""Polygons of at most this many corners are solved all at once, however many there are (their
widest step holds `s^2 / 4` candidates per polygon).
"""
BATCH_CANDIDATES = 2_000_000
"""Candidate triangles per width step (polygons x intervals x splits) for larger polygons, to bound
the temporaries.
"""
STEP_CANDIDATES = 4_000
"""The fixed cost of one width step, in candidate triangles: what padding smaller polygons to a
larger size may spend to save steps (`size_bands`).
"""


def best_triangulations(points: np.ndarray, rim: np.ndarray, sizes: np.ndarray,
                        ) -> tuple[np.ndarray, np.ndarray]:
    """Triangulations of polygons minimising rim angles (interval dynamic programme).

    Parameters
    ----------
    points : (L, s, 3) float
        Polygon corners in the order the surface runs along its boundary; polygon `p`
        uses its first `sizes[p]` rows (the rest are padding, any finite values).
    rim : (L, s, 3) float
        Unit normal of the surface face along edge `i -> i+1` (`size-1 -> 0` last).
    sizes : (L,) int
        Corners of each polygon, 3 .. s.

    Returns
    -------
    triangles : (T, 3) int
        Corner positions of each cap triangle `(j, k, i)`, oriented against the
        boundary: `sizes[p] - 2` per polygon, polygon by polygon, each in breadth-first
        order of its triangulation's tree.
    polygon : (T,) int
        The polygon of each triangle.
    """
    points = np.ascontiguousarray(points, dtype=np.float64)
    rim = np.ascontiguousarray(rim, dtype=np.float64)
    sizes = np.asarray(sizes, dtype=np.int64)
    if points.ndim != 3 or points.shape[2] != 3 or rim.shape != points.shape:
        raise ValueError(f"points and rim must have one shape (L, s, 3), got {points.shape}"
                         f" and {rim.shape}")
    n_poly, s, _ = points.shape
    if sizes.shape != (n_poly,) or (n_poly and (sizes.min() < 3 or sizes.max() > s)):
        raise ValueError(f"sizes must be (L,) = ({n_poly},) corner counts in 3..{s}")
    if n_poly == 0:
        return np.zeros((0, 3), dtype=np.int64), np.zeros(0, dtype=np.int64)
    s = int(sizes.max())
    points, rim = points[:, :s], rim[:, :s]
    step = n_poly if s <= ALL_AT_ONCE_MAX else max(1, BATCH_CANDIDATES // (s * s // 4 + 1))
    tris: list[np.ndarray] = []
    polys: list[np.ndarray] = []
    for a in range(0, n_poly, step):  # the polygons are independent: batches bound memory
        part = slice(a, a + step)
        t, p = _unfold(_choices(np.ascontiguousarray(points[part]),
                                np.ascontiguousarray(rim[part]), sizes[part]), sizes[part])
        tris.append(t)
        polys.append(p + a)
    return np.concatenate(tris), np.concatenate(polys)


def size_bands(sizes: list[int], counts: list[int]) -> list[range]:
    """Runs of consecutive groups (`counts[g]` polygons of `sizes[g]` corners, sizes
    ascending) to solve as one padded batch: a group joins the run before it while
    padding it costs less than the width steps it saves (`STEP_CANDIDATES` each)."""
    bands: list[range] = []
    first = 0
    for g in range(1, len(sizes) + 1):
        if g < len(sizes):
            s = sizes[g]
            alone = _work(sizes[first:g], counts[first:g]) + _work([s], [counts[g]])
            joined = _work([s] * (g + 1 - first), counts[first:g + 1])
            if joined <= alone:
                continue
        bands.append(range(first, g))
        first = g
    return bands


def _work(sizes: list[int], counts: list[int]) -> float:
    """Cost, in candidate triangles, of solving the groups padded to their largest size."""
    s = max(sizes)
    return STEP_CANDIDATES * (s - 2) + sum(counts) * s ** 3 / 6


def _choices(points: np.ndarray, rim: np.ndarray, sizes: np.ndarray) -> np.ndarray:
    """(L, s, s) best split `k` of each interval `(i, j)`, `j - i >= 2`."""
    n_poly, s, _ = points.shape
    # each polygon's perimeter without its closing edge, summed as np.sum sums one row
    scale = np.empty(n_poly)
    for size in np.unique(sizes).tolist():
        of = sizes == size
        scale[of] = np.sum(np.linalg.norm(np.diff(points[of, :size], axis=1), axis=2), axis=1)
    scale = np.maximum(scale, 1e-300)
    area_scale = scale[:, None, None] ** 2
    closing_gap = sizes - 1
    cost = np.full((n_poly, s * s), np.inf)
    cost[:, np.arange(s - 1) * (s + 1) + 1] = 0.0  # the polygon's edges (i, i+1)
    choice = np.zeros((n_poly, s * s), dtype=np.int64)
    # the corners' coordinates, one contiguous (L, s) array per axis
    axes = [np.ascontiguousarray(points[..., d]) for d in range(3)]
    lp, sp = axes[0].strides
    lc, cc = cost.strides
    for gap in range(2, s):
        n_int, n_split = s - gap, gap - 1
        # corners i, k = i + 1 .. i + gap - 1 (columns) and j = i + gap of every candidate
        p_i = [x[:, :n_int, None] for x in axes]
        p_j = [x[:, gap:, None] for x in axes]
        p_k = [_view(x, sp, (n_poly, n_int, n_split), (lp, sp, sp)) for x in axes]
        cost_tri, cross, norm = _triangle_costs(p_i, p_k, p_j, area_scale)
        # the rim angles, only where a triangle has a polygon edge (adding nothing
        # elsewhere changes no bit): edge i -> i+1 in the first column, k -> j in the last
        at: tuple[slice | int | np.ndarray, ...] = (slice(None), slice(None), 0)
        _add_angle(cost_tri, cross, norm, area_scale[:, 0], at, rim[:, :n_int])
        at = (slice(None), slice(None), n_split - 1)
        _add_angle(cost_tri, cross, norm, area_scale[:, 0], at, rim[:, gap - 1:s - 1])
        closes = np.flatnonzero(closing_gap == gap)
        if len(closes):  # the closing edge size-1 -> 0 borders every split of (0, size-1)
            at = (closes, 0)
            _add_angle(cost_tri, cross, norm, area_scale[closes, 0], at,
                       rim[closes, gap][:, None, :])
        # cost(i, k) and cost(k, j): flat (s, s) positions i (s + 1) + m and
        # (i + m) s + i + gap (m = k - i), strided in i and m
        ik = _view(cost, cc, (n_poly, n_int, n_split), (lc, (s + 1) * cc, cc))
        kj = _view(cost, (s + gap) * cc, (n_poly, n_int, n_split), (lc, (s + 1) * cc, s * cc))
        c = np.add(ik, kj, out=cross[0])  # (cost(i, k) + cost(k, j)) + triangle
        c += cost_tri
        ij = np.arange(n_int) * (s + 1) + gap
        best = c.argmin(axis=2)  # the first smallest, or the first NaN
        rows = c.reshape(-1, n_split)
        cost[:, ij] = rows[np.arange(len(rows)), best.reshape(-1)].reshape(best.shape)
        choice[:, ij] = np.arange(1, n_int + 1) + best
    return choice.reshape(n_poly, s, s)


def _triangle_costs(p_i: list[np.ndarray], p_k: list[np.ndarray], p_j: list[np.ndarray],
                    area_scale: np.ndarray,
                    ) -> tuple[np.ndarray, list[np.ndarray], np.ndarray]:
    """Area term, normal (cross product) components and their norm of the candidate
    triangles `(j, k, i)`, from the corners' coordinates (one array per axis).

    The arithmetic of `np.cross(pk - pj, pi - pj)` and `np.linalg.norm` per triangle,
    component by component and in place (their sums of three run left to right).
    """
    a = [k - j for k, j in zip(p_k, p_j, strict=True)]
    b = [i - j for i, j in zip(p_i, p_j, strict=True)]
    tmp = np.empty_like(a[0])
    cross = []
    for u, v in ((1, 2), (2, 0), (0, 1)):  # a_u b_v - a_v b_u
        out = np.multiply(a[u], b[v])
        out -= np.multiply(a[v], b[u], out=tmp)
        cross.append(out)
    norm = np.multiply(cross[0], cross[0], out=a[0])
    norm += np.multiply(cross[1], cross[1], out=tmp)
    norm += np.multiply(cross[2], cross[2], out=tmp)
    np.sqrt(norm, out=norm)
    cost = np.multiply(norm, AREA_WEIGHT * 0.5, out=a[1])
    cost /= area_scale
    return cost, cross, norm


def _add_angle(cost: np.ndarray, cross: list[np.ndarray], norm: np.ndarray,
               area_scale: np.ndarray, at: tuple[slice | int | np.ndarray, ...],
               rim: np.ndarray) -> None:
    """Add to the candidates `cost[at]` the angle between each triangle and the rim
    face (unit normals `rim`, broadcast to `cost[at]` plus an axis) across its edge;
    pi for a degenerate triangle. `area_scale` broadcasts to `cost[at]`."""
    n = norm[at]
    den = np.maximum(n, 1e-300)
    cos = (cross[0][at] / den * rim[..., 0] + cross[1][at] / den * rim[..., 1]
           + cross[2][at] / den * rim[..., 2])
    # np.clip(cos, -1, 1) bit for bit, without its wrapper's overhead
    angle = np.arccos(np.minimum(np.maximum(cos, -1.0), 1.0))
    cost[at] += np.where(n <= 1e-12 * area_scale, np.pi, angle)


def _view(base: np.ndarray, offset: int, shape: tuple[int, ...],
          strides: tuple[int, ...]) -> np.ndarray:
    """A read-only strided view into the contiguous array `base` (`as_strided`
    without its overhead, which the programme's many small steps would feel)."""
    view = np.ndarray(shape, base.dtype, buffer=base, offset=offset, strides=strides)
    view.flags.writeable = False
    return view


def _unfold(choice: np.ndarray, sizes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Triangles `(j, k, i)` of the chosen splits and their polygons, polygon by
    polygon, breadth-first: every interval of width >= 2 yields one triangle."""
    n_poly = len(choice)
    poly = np.arange(n_poly)
    lo = np.zeros(n_poly, dtype=np.int64)
    hi = sizes - 1
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
    return flat[:, 1:], flat[:, 0]
