"""Generalized winding numbers of triangle surfaces (Jacobson et al. 2013).

The winding number of an oriented triangle surface at a point is the sum of
the signed solid angles its triangles subtend there, divided by 4 pi: 1 inside and 0
outside a closed outward surface, -1 inside an inverted one, and a smooth value between
for an open surface. It decides whether one closed shell lies inside another (cavities,
nested bodies) independently of how the mesh is triangulated. `winding_numbers`
is libigl's compiled sum when libigl is installed (the `fast` extra), else
`solid_angle_winding_numbers`, the plain numpy sum it agrees with to round-off.
For closed surfaces, `closed_winding_numbers` gets the same integers by counting
ray crossings, at a fraction of the cost, and falls back to the solid angles where a ray
grazes an edge.
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from urdfinertia.mesh.repair.graph import sort_order

CHUNK = 1_000_000
"""Query points x triangles evaluated per chunk (bounds the temporary arrays to ~100 MB)."""


def solid_angles(points: ArrayLike, triangles: ArrayLike) -> np.ndarray:
    """Signed solid angle of each triangle seen from each point.

    Van Oosterom & Strackee (1983):
    `tan(omega / 2) = a.(b x c) / (|a||b||c| + (a.b)|c| + (b.c)|a| + (c.a)|b|)` with `a, b, c`
    the corners relative to the point.

    Parameters
    ----------
    points : (p, 3) float
    triangles : (t, 3, 3) float
        Counter-clockwise seen from outside.

    Returns
    -------
    (p, t) float
        Steradians; positive for a point behind the triangle (on the side its normal
        points away from).
    """
    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    tri = np.asarray(triangles, dtype=np.float64)
    if tri.ndim != 3 or tri.shape[1:] != (3, 3):
        raise ValueError(f"triangles must have shape (t, 3, 3), got {tri.shape}")
    a = tri[None, :, 0, :] - p[:, None, :]
    b = tri[None, :, 1, :] - p[:, None, :]
    c = tri[None, :, 2, :] - p[:, None, :]
    la = np.linalg.norm(a, axis=-1)
    lb = np.linalg.norm(b, axis=-1)
    lc = np.linalg.norm(c, axis=-1)
    num = np.einsum("ptk,ptk->pt", a, np.cross(b, c))
    den = (la * lb * lc + np.einsum("ptk,ptk->pt", a, b) * lc
           + np.einsum("ptk,ptk->pt", b, c) * la + np.einsum("ptk,ptk->pt", c, a) * lb)
    return 2.0 * np.arctan2(num, den)


def winding_numbers(points: ArrayLike, vertices: ArrayLike, faces: ArrayLike) -> np.ndarray:
    """Generalized winding number of the surface `(vertices, faces)` at each point.

    Computed by libigl when it is installed (`pip install 'urdfinertia[fast]'`;
    `igl.winding_number`: the same sum of solid angles, over a bounding-volume hierarchy
    that replaces a far cluster by its boundary's closure), else by
    `solid_angle_winding_numbers`, the plain numpy sum; the two agree to round-off.

    Parameters
    ----------
    points : (p, 3) float
    vertices : (n, 3) float
    faces : (m, 3) int

    Returns
    -------
    (p,) float
    """
    pts = np.ascontiguousarray(np.asarray(points, dtype=np.float64).reshape(-1, 3))
    v = np.ascontiguousarray(vertices, dtype=np.float64)
    f = np.ascontiguousarray(faces, dtype=np.int64).reshape(-1, 3)
    if len(pts) == 0 or len(f) == 0:
        return np.zeros(len(pts))
    igl = compiled()
    if igl is None:
        return solid_angle_winding_numbers(pts, v, f)
    return np.asarray(igl.winding_number(v, f, pts), dtype=np.float64)


#: libigl, imported on first use; False when it is not installed (or its use is switched
#: off by :data:`NO_COMPILED`).
_IGL: Any = None
#: Environment variable that, set to 1, makes :func:`winding_numbers` use the numpy sum
#: even where libigl is installed (to compare the two: scripts/bench_winding.py).
NO_COMPILED = "URDFINERTIA_NO_LIBIGL"


def compiled() -> Any:
    """The ``igl`` module, or None when libigl is not installed (or :data:`NO_COMPILED`)."""
    global _IGL
    if _IGL is None:
        _IGL = False
        if os.environ.get(NO_COMPILED, "") != "1":
            try:
                import igl
            except ImportError:
                pass
            else:
                _IGL = igl
    return _IGL or None


def solid_angle_winding_numbers(points: ArrayLike, vertices: ArrayLike,
                                faces: ArrayLike) -> np.ndarray:
    """`winding_numbers` as a plain sum of `solid_angles` (pure numpy).

    Quadratic in points x faces: the reference the compiled one is tested against.
    """
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    tri = np.asarray(vertices, dtype=np.float64)[np.asarray(faces, dtype=np.int64)]
    out = np.zeros(len(pts))
    if len(tri) == 0 or len(pts) == 0:
        return out
    step = max(1, CHUNK // len(tri))
    for start in range(0, len(pts), step):  # chunks of points, each vectorised over faces
        out[start:start + step] = solid_angles(pts[start:start + step], tri).sum(axis=1)
    return out / (4.0 * np.pi)


RAY_RTOL = 1e-9
"""Relative round-off within which a ray is taken to graze an edge, or a point to lie on the surface
(`closed_winding_numbers` then asks `winding_numbers`).
"""


def closed_winding_numbers(points: ArrayLike, vertices: ArrayLike, faces: ArrayLike,
                           exact_on_graze: bool = True) -> np.ndarray:
    """Winding numbers of a closed surface, counted along rays, with the same values.

    For a closed surface (every edge used equally often in each direction) the winding
    number at a point off the surface is the integer `winding_numbers` computes,
    and also the signed count of crossings of any ray from the point: +1 where the ray
    leaves through a face whose normal points along it, -1 where it enters. Counting
    along `RAY` needs only the few faces whose bounding box the ray meets (found through
    a grid across the ray, `RayCounter`) and no transcendental functions; an
    oblique ray rarely grazes the edges of CAD models, whose faces often lie parallel to
    the axes. A point whose ray grazes an edge or vertex, or which lies on a face, within
    `RAY_RTOL`, is evaluated with `winding_numbers` instead.

    Parameters
    ----------
    points : (p, 3) float
    vertices : (n, 3) float
    faces : (m, 3) int
        A closed surface.
    exact_on_graze : bool
        False counts grazing rays as they fall instead of asking
        `winding_numbers`: a point on or next to the surface may then be off by
        one, for callers that search along lines and reject such points anyway.

    Returns
    -------
    (p,) float
        Integers, except at points handed to `winding_numbers`.
    """
    return RayCounter(vertices, faces)(points, exact_on_graze)


class RayCounter:
    """`closed_winding_numbers` of one closed surface, for many calls.

    The surface is turned once into the ray's frame and its faces binned once on a grid
    across the ray (the faces' boxes, widened by the grazing slack, over the cells they
    cover); each call then tests a point only against the faces of its cell. The pairs
    tested are a superset of those whose boxes the ray meets, and each pair is decided by
    the same arithmetic as a test against every face, so the counts are the same.
    """

    def __init__(self, vertices: ArrayLike, faces: ArrayLike) -> None:
        self.vertices = np.asarray(vertices, dtype=np.float64)
        self.faces = np.asarray(faces, dtype=np.int64)
        v, f = self.vertices, self.faces
        if len(f) == 0:
            return
        # coordinates along the ray (x) and across it (y, z): a rotation, so each vertex
        # keeps one position and the surface stays closed
        # only the used vertices, in their order (the same product as rotating them in
        # place), so a few faces of a large vertex array cost no copy of all of it
        used = np.zeros(len(v), dtype=bool)
        used[f.reshape(-1)] = True
        rank = np.cumsum(used) - 1
        self.tri = tri = (v[used] @ _RAY_FRAME.T)[rank[f]]
        # elementwise over the corners: numpy's reduction along a length-3 axis is slow
        self.lo = np.minimum(np.minimum(tri[:, 0], tri[:, 1]), tri[:, 2])
        self.hi = np.maximum(np.maximum(tri[:, 0], tri[:, 1]), tri[:, 2])
        self._box = (self.lo.min(axis=0), self.hi.max(axis=0))  # every call's slack uses it
        self._grid_cache: tuple[float, tuple[np.ndarray, ...]] | None = None

    def __call__(self, points: ArrayLike, exact_on_graze: bool = True,
                 only: np.ndarray | None = None) -> np.ndarray:
        """Winding numbers at `points` (p, 3); with `only` (p,) bool, at those
        points only (0 elsewhere), with the counts a call on all of them gives (the
        grazing slack still scales with the extent of all the points; the values of
        grazing points handed to `winding_numbers` agree to round-off)."""
        pts_all = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        out = np.zeros(len(pts_all))
        if len(self.faces) == 0 or len(pts_all) == 0:
            return out
        pts = pts_all @ _RAY_FRAME.T
        box_lo, box_hi = self._box
        scale = float(np.linalg.norm(np.maximum(box_hi, pts.max(axis=0))
                                     - np.minimum(box_lo, pts.min(axis=0))))
        slack = RAY_RTOL * scale
        if only is not None:
            at = np.flatnonzero(only)
            if len(at):
                out[at] = self._count(pts[at], pts_all[at], slack, exact_on_graze)
            return out
        return self._count(pts, pts_all, slack, exact_on_graze)

    def _count(self, pts: np.ndarray, pts_all: np.ndarray, slack: float,
               exact_on_graze: bool) -> np.ndarray:
        """The counts at `pts` (in the ray's frame; `pts_all` as given)."""
        out = np.zeros(len(pts))
        tri = self.tri
        unsure = np.zeros(len(pts), dtype=bool)
        for first, last, pi, ti in self._pairs(pts, slack):
            p = pts[first:last]
            # (k, 3 corners, 3): tri[ti] - p[pi, None], with np.take's faster gathers
            rel = np.take(tri, ti, axis=0) - np.take(p, pi, axis=0)[:, None, :]
            y, z = rel[:, :, 1], rel[:, :, 2]
            nxt = [1, 2, 0]
            prv = [2, 0, 1]
            # twice the signed yz-area of (point, corner k+1, corner k+2): corner k's weight
            e = y[:, nxt] * z[:, prv] - z[:, nxt] * y[:, prv]
            r = np.hypot(y, z)
            tol = RAY_RTOL * r[:, nxt] * r[:, prv]
            pos, neg = e > tol, e < -tol
            strict = np.all(pos, axis=1) | np.all(neg, axis=1)
            apart = np.any(pos, axis=1) & np.any(neg, axis=1)
            area = e.sum(axis=1)  # twice the signed yz-area: the x component of the normal
            dx = np.einsum("kc,kc->k", e, rel[:, :, 0]) / np.where(strict, area, 1.0)
            hit = strict & (dx > slack)
            graze = (~strict & ~apart) | (strict & (np.abs(dx) <= slack))
            out[first:last] = np.bincount(pi[hit], weights=np.sign(area[hit]),
                                          minlength=len(p))
            unsure[first:last] = np.bincount(pi[graze], minlength=len(p)) > 0
        if exact_on_graze and unsure.any():
            out[unsure] = winding_numbers(pts_all[unsure], self.vertices, self.faces)
        return out

    def _pairs(self, pts: np.ndarray, slack: float,
               ) -> Iterator[tuple[int, int, np.ndarray, np.ndarray]]:
        """Chunks `(first, last, point, face)` of the pairs whose boxes the rays meet.

        Points `first:last` of a chunk, `point` indexing into the chunk. From the
        grid's candidates, or from every face where the grid would hand each point a
        large share of them anyway (long faces across the ray): the plain test is then
        cheaper per pair.
        """
        lo, hi = self.lo, self.hi

        def near(p: np.ndarray, f_lo: np.ndarray, f_hi: np.ndarray) -> np.ndarray:
            """Whether each point's ray meets each face's box (broadcast shapes)."""
            return ((f_lo[..., 1] <= p[..., 1] + slack) & (f_hi[..., 1] >= p[..., 1] - slack)
                    & (f_lo[..., 2] <= p[..., 2] + slack) & (f_hi[..., 2] >= p[..., 2] - slack)
                    & (f_hi[..., 0] >= p[..., 0] - slack))

        n_all = None
        if len(pts) > GRID_MIN_POINTS and len(pts) * len(lo) > BRUTE_PAIRS:
            cell, start, count, order = self._grid(slack, pts)
            n_all = count[cell]
        if n_all is None or n_all.sum() > GRID_SHARE * len(pts) * len(lo):
            # only the faces whose boxes the points' box meets (a superset of each point's:
            # rounding is monotonic)
            p_lo, p_hi = pts.min(axis=0), pts.max(axis=0)
            sel = np.flatnonzero((lo[:, 1] <= p_hi[1] + slack) & (hi[:, 1] >= p_lo[1] - slack)
                                 & (lo[:, 2] <= p_hi[2] + slack) & (hi[:, 2] >= p_lo[2] - slack)
                                 & (hi[:, 0] >= p_lo[0] - slack))
            if len(sel) == 0:
                return
            s_lo, s_hi = lo[sel], hi[sel]
            step = max(1, 8 * CHUNK // len(sel))
            for first in range(0, len(pts), step):  # chunks of points, vectorised over faces
                p = pts[first:first + step]
                pi, ti = np.nonzero(near(p[:, None], s_lo[None], s_hi[None]))
                yield first, first + len(p), pi, sel[ti]
            return
        bounds = np.concatenate([[0], np.cumsum(n_all)])
        first = 0
        while first < len(pts):  # chunks of points holding ~8 CHUNK candidate pairs
            last = int(np.searchsorted(bounds, bounds[first] + 8 * CHUNK, side="right")) - 1
            last = min(max(last, first + 1), len(pts))
            n = n_all[first:last]
            pi = np.repeat(np.arange(last - first), n)
            rank = np.arange(len(pi)) - np.repeat(np.cumsum(n) - n, n)
            ti = order[np.repeat(start[cell[first:last]], n) + rank]
            keep = near(np.take(pts[first:last], pi, axis=0), np.take(lo, ti, axis=0),
                        np.take(hi, ti, axis=0))
            yield first, last, pi[keep], ti[keep]
            first = last

    def _grid(self, slack: float, pts: np.ndarray,
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Each point's cell, and per cell the start and count of its faces in `order`.

        A face is listed in every cell its yz-box, widened by at least `slack`,
        overlaps; points and faces beyond the grid fall in its edge cells, so a face
        whose box may contain a point's yz is always listed in the point's cell. The grid
        is kept for later calls whose slack is no wider.
        """
        if self._grid_cache is None or self._grid_cache[0] < slack:
            self._grid_cache = (2.0 * slack, self._bins(2.0 * slack))
        origin, h, side, start, count, order = self._grid_cache[1]
        pc = np.clip(((pts[:, 1:] - origin) / h).astype(np.int64), 0, int(side) - 1)
        return pc[:, 0] * int(side) + pc[:, 1], start, count, order

    def _bins(self, slack: float) -> tuple[np.ndarray, ...]:
        """The grid of `_grid`: origin, cell size, cells per side, and per cell the
        start and count of its faces in `order`."""
        lo = self.lo[:, 1:] - slack
        hi = self.hi[:, 1:] + slack
        origin = lo.min(axis=0)
        extent = float(np.max(hi.max(axis=0) - origin))
        side = int(np.clip(np.sqrt(len(lo)), 1, GRID_MAX))
        while True:  # coarser until the faces' copies stay few (long thin faces)
            h = extent / side if extent > 0 else 1.0
            a = np.clip(((lo - origin) / h).astype(np.int64), 0, side - 1)
            b = np.clip(((hi - origin) / h).astype(np.int64), 0, side - 1)
            span = b - a + 1
            copies = span[:, 0] * span[:, 1]
            if side == 1 or copies.sum() <= GRID_COPIES * len(lo):
                break
            side = max(1, side // 2)
        # 32-bit indices where they fit: the listing is the grid's largest part, and kept
        index = np.int32 if max(int(copies.sum()), side * side) < 2 ** 31 else np.int64
        face = np.repeat(np.arange(len(lo), dtype=index), copies)
        k = np.arange(len(face), dtype=index) - np.repeat(
            (np.cumsum(copies) - copies).astype(index), copies)
        a, span = a.astype(index), span.astype(index)
        sy = span[face, 0]
        cy = a[face, 0] + k % sy
        cz = a[face, 1] + k // sy
        key = cy * index(side) + cz
        order = face[sort_order(key)]
        count = np.bincount(key, minlength=side * side)
        start = np.cumsum(count) - count
        return origin, np.asarray(h), np.asarray(side), start, count, order


GRID_MIN_POINTS = 64
"""Fewest points for which the grid is built (fewer are tested against every face)."""
BRUTE_PAIRS = 200_000
"""Point-face pairs below which every face is tested, without building the grid."""
GRID_MAX = 512
"""Most grid cells per axis across the ray (`RayCounter`)."""
GRID_SHARE = 0.2
"""Share of all point-face pairs beyond which the grid's candidates are not worth gathering
(`RayCounter._pairs`).
"""
GRID_COPIES = 8
"""Largest average number of cells a face may be listed in before the grid is coarsened."""


def _ray_frame() -> np.ndarray:
    """Rows: the ray direction, then two unit vectors across it (right-handed)."""
    ray = RAY / np.linalg.norm(RAY)
    across = np.cross(ray, [0.0, 0.0, 1.0])
    across /= np.linalg.norm(across)
    return np.stack([ray, across, np.cross(ray, across)])


RAY = np.array([0.8191520442889918, 0.4924038765061041, 0.2940315329861220])
"""Direction of the rays of `closed_winding_numbers`: oblique to every axis."""
_RAY_FRAME = _ray_frame()
