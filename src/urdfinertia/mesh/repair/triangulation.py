"""Minimum-cost triangulations of polygons whose edges continue a surface.

The interval dynamic programme of Liepa (2003, "Filling holes in meshes") over the
polygon's corners ``0 .. s-1``: the best triangulation of the interval ``(i, j)`` splits
it at the corner ``k`` minimising ``cost(i, k) + cost(k, j) + triangle(i, k, j)``. It runs
width by width (``j - i = 2 .. s-1``): all intervals of one width, all their splits and
all polygons of one batch in a few vectorised operations on strided views of the cost
table, so nothing of size ``s^3`` is ever held. A triangle's cost is the angle between it
and the surface face across each of its polygon edges, plus a small area term.

The costs are those of a triangle-by-triangle evaluation bit for bit (the same products,
differences and sums, in the same order), and ties go to the smallest split, so the
choice does not depend on how the polygons are batched.
"""

from __future__ import annotations

import numpy as np

#: Weight of a cap triangle's relative area against its rim angle (radians): a tie-break.
AREA_WEIGHT = 1e-3
#: Polygons of at most this many corners are solved all at once, however many there are
#: (their widest step holds ``s^2 / 4`` candidates per polygon).
ALL_AT_ONCE_MAX = 40
#: Candidate triangles per width step (polygons x intervals x splits) for larger
#: polygons, to bound the temporaries.
BATCH_CANDIDATES = 2_000_000


def best_triangulations(points: np.ndarray, rim: np.ndarray) -> np.ndarray:
    """Triangulations of polygons minimising rim angles (interval dynamic programme).

    Parameters
    ----------
    points : (L, s, 3) float
        Polygon corners in the order the surface runs along its boundary.
    rim : (L, s, 3) float
        Unit normal of the surface face along edge ``i -> i+1`` (``s-1 -> 0`` last).

    Returns
    -------
    (L, s - 2, 3) int
        Corner positions of each cap triangle ``(j, k, i)``, oriented against the
        boundary, in breadth-first order of the triangulation's tree.
    """
    points = np.ascontiguousarray(points, dtype=np.float64)
    rim = np.ascontiguousarray(rim, dtype=np.float64)
    if points.ndim != 3 or points.shape[2] != 3 or rim.shape != points.shape:
        raise ValueError(f"points and rim must have one shape (L, s, 3), got {points.shape}"
                         f" and {rim.shape}")
    n_poly, s, _ = points.shape
    if s < 3:
        raise ValueError(f"a polygon needs at least 3 corners, got {s}")
    step = n_poly if s <= ALL_AT_ONCE_MAX else max(1, BATCH_CANDIDATES // (s * s // 4 + 1))
    if n_poly > step:  # the polygons are independent: batches bound the temporaries
        return np.concatenate([best_triangulations(points[a:a + step], rim[a:a + step])
                               for a in range(0, n_poly, step)])
    return _unfold(_choices(points, rim))


def _choices(points: np.ndarray, rim: np.ndarray) -> np.ndarray:
    """(L, s, s) best split ``k`` of each interval ``(i, j)``, ``j - i >= 2``."""
    n_poly, s, _ = points.shape
    scale = np.maximum(np.sum(np.linalg.norm(np.diff(points, axis=1), axis=2), axis=1), 1e-300)
    area_scale = scale[:, None, None] ** 2
    cost = np.full((n_poly, s * s), np.inf)
    cost[:, np.arange(s - 1) * (s + 1) + 1] = 0.0  # the polygon's edges (i, i+1)
    choice = np.zeros((n_poly, s * s), dtype=np.int64)
    lp, sp, cp = points.strides
    lc, cc = cost.strides
    for gap in range(2, s):
        n_int, n_split = s - gap, gap - 1
        # corners i, k = i + m (m = 1 .. gap-1) and j = i + gap of every candidate
        p_i = points[:, :n_int, None, :]
        p_j = points[:, gap:, None, :]
        p_k = _view(points, sp, (n_poly, n_int, n_split, 3), (lp, sp, sp, cp))
        cost_tri, cross, safe, degenerate = _triangle_costs(p_i, p_k, p_j, area_scale)
        # the rim angles, only where a triangle has a polygon edge (adding nothing
        # elsewhere changes no bit): edge i -> i+1 at m = 1, edge k -> j at m = gap - 1
        _add_angle(cost_tri, cross, safe, degenerate, 0, rim[:, :n_int])
        _add_angle(cost_tri, cross, safe, degenerate, n_split - 1, rim[:, gap - 1:s - 1])
        if gap == s - 1:  # the closing edge s-1 -> 0 borders every split of (0, s-1)
            _add_angle(cost_tri, cross, safe, degenerate, slice(None),
                       rim[:, s - 1:s, None, :])
        # cost(i, k) and cost(k, j): flat (s, s) positions i (s + 1) + m and
        # (i + m) s + i + gap, strided in i and m
        ik = _view(cost, cc, (n_poly, n_int, n_split), (lc, (s + 1) * cc, cc))
        kj = _view(cost, (s + gap) * cc, (n_poly, n_int, n_split), (lc, (s + 1) * cc, s * cc))
        c = ik + kj + cost_tri
        ij = np.arange(n_int) * (s + 1) + gap
        # the smallest cost is the chosen split's (no -0.0 arises; NaN wins in both)
        cost[:, ij] = c.min(axis=2)
        choice[:, ij] = np.arange(1, n_int + 1) + c.argmin(axis=2)
    return choice.reshape(n_poly, s, s)


def _triangle_costs(p_i: np.ndarray, p_k: np.ndarray, p_j: np.ndarray,
                    area_scale: np.ndarray,
                    ) -> tuple[np.ndarray, list[np.ndarray], np.ndarray, np.ndarray]:
    """Area term, normal components, safe norm and degeneracy of triangles ``(j, k, i)``.

    The arithmetic of ``np.cross(pk - pj, pi - pj)`` and ``np.linalg.norm`` per triangle,
    component by component on broadcast arrays (their sums of three run left to right).
    """
    a = p_k - p_j
    b = p_i - p_j
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    cross = [a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0]
    norm = np.sqrt(cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2])
    degenerate = norm <= 1e-12 * area_scale
    cost = AREA_WEIGHT * 0.5 * norm / area_scale
    return cost, cross, np.maximum(norm, 1e-300), degenerate


def _add_angle(cost: np.ndarray, cross: list[np.ndarray], safe: np.ndarray,
               degenerate: np.ndarray, m: int | slice, rim: np.ndarray) -> None:
    """Add to the candidates of split column(s) ``m`` the angle between each triangle
    and the rim face (unit normals ``rim``, broadcast to the columns) across its edge."""
    at = (slice(None), slice(None), m)
    den = safe[at]
    cos = (cross[0][at] / den * rim[..., 0] + cross[1][at] / den * rim[..., 1]
           + cross[2][at] / den * rim[..., 2])
    # np.clip(cos, -1, 1) bit for bit, without its wrapper's overhead
    angle = np.arccos(np.minimum(np.maximum(cos, -1.0), 1.0))
    cost[at] += np.where(degenerate[at], np.pi, angle)


def _view(base: np.ndarray, offset: int, shape: tuple[int, ...],
          strides: tuple[int, ...]) -> np.ndarray:
    """A read-only strided view into the contiguous array ``base`` (``as_strided``
    without its overhead, which the programme's many small steps would feel)."""
    view = np.ndarray(shape, base.dtype, buffer=base, offset=offset, strides=strides)
    view.flags.writeable = False
    return view


def _unfold(choice: np.ndarray) -> np.ndarray:
    """Triangles of the chosen splits, breadth-first: every interval of width >= 2
    yields one triangle ``(j, k, i)``."""
    n_poly, s, _ = choice.shape
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
    return flat[:, 1:].reshape(n_poly, s - 2, 3)
