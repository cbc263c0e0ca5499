"""Whether a body's mass properties can come from a nonnegative density inside the convex
hull of a link's geometry: a linear programme (HiGHS, through ``scipy.optimize.linprog``)
whose answer is a proof either way.

Per unit mass, in coordinates ``y = (x - g) / L`` about the hull's centroid ``g`` (``L``:
the largest distance of a hull vertex from it), a body has ten moments ``b``: 1, its CoM
``mu`` and its second moments about ``g`` ``M = Sigma + mu mu^T``. A density on the hull
``H`` has them iff ``b`` lies in the cone of ``a(y) = (1, y, y y^T)`` over ``y`` in ``H``
(the moment cone; the ellipsoid test of :mod:`urdfinertia.inertia.realizable` is the same
question for an ellipsoid, where it has a closed form).

* **Realizable** (an inner approximation, exact when it succeeds): nonnegative weights on
  finitely many points of ``H`` with the ten moments, to :data:`FEASIBLE_TOL` in the L1
  norm of the normalised moments. Found by phase one of the LP
  ``min sum(p + n) : sum_i w_i a(y_i) + p - n = b, w, p, n >= 0``.
* **Not realizable** (a certificate): when that minimum is positive, the LP's duals ``l``
  (``|l| <= 1``) give the quadratic ``q(y) = -l . a(y)``, which is ``>= 0`` on the LP's
  points while ``integral q dm = -l . b < 0``. Were ``q >= 0`` on all of ``H``, no density
  on ``H`` could have the moments (Farkas). The minimum of a quadratic over a polytope is
  not at a vertex in general, so it is found exactly: it lies at a vertex, at the
  stationary point of ``q`` on an edge or a triangle of the hull's triangulated boundary,
  or at the interior stationary point (:func:`quadratic_minimum`). A minimum ``-d < 0``
  shifts ``q`` by ``d``: still a certificate while ``d < l . b``. Otherwise the points
  where ``q`` is most negative join the LP and it is solved again (column generation, the
  exchange method of semi-infinite programming), until one of the two proofs is found or
  :data:`MAX_ROUNDS` pass (undecided: reported as realizable, never as a finding).

The scale of the hull about its centroid that would just hold the body is bracketed by
bisection (a body realizable in ``sH`` is realizable in any larger ``s'H``, since ``g`` is
in ``H``): :class:`HullScale` ``low`` is proved too small, ``high`` proved enough.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from urdfinertia.inertia.realizable import central_second_moment, centred_points

#: The normalised moments (coordinates of size <= 1, unit mass) are met to this, L1. The
#: LP solver's own feasibility tolerance is 1e-7.
FEASIBLE_TOL = 1e-7
#: Column-generation rounds per scale before giving up (undecided).
MAX_ROUNDS = 60
#: Points added to the LP per round: the most negative of the certificate's minima.
_ADD = 24
#: Bisection of the scale stops when ``high / low - 1`` is below this.
SCALE_RTOL = 1e-3
#: The largest scale tried: a body needing more is reported with ``high = inf``.
MAX_SCALE = 1024.0


@dataclass(frozen=True, eq=False)
class Hull:
    """A convex hull, normalised: ``y = (x - centroid) / size``.

    vertices : (n, 3) float, normalised; triangles : (f, 3) int, its triangulated boundary;
    edges : (e, 2) int; equations : (f, 4) float, ``[n, o]`` with ``n . y + o <= 0``
    inside; centroid : (3,) m, the solid hull's centre of volume; size : m.
    """

    vertices: np.ndarray
    triangles: np.ndarray
    edges: np.ndarray
    equations: np.ndarray
    centroid: np.ndarray
    size: float

    def contains(self, y: np.ndarray, tol: float = 1e-12) -> np.ndarray:
        """(k,) bool: each of the (k, 3) normalised points inside (to ``tol``)."""
        e = self.equations
        return np.asarray(np.all(y @ e[:, :3].T + e[:, 3] <= tol, axis=1))


@dataclass(frozen=True, eq=False)
class HullScale:
    """The scale ``s`` of a hull about its centroid that would just hold a body.

    low : proved too small (a certificate: no nonnegative density in ``low`` x the hull
        has the moments); 0 when none was sought (the body is realizable in the hull).
    high : proved enough (weights on points of ``high`` x the hull have the moments);
        ``inf`` when none was found up to :data:`MAX_SCALE`.
    decided : False when some LP stayed undecided (then ``low`` and ``high`` hold what was
        proved before it).
    lps : LPs solved.
    """

    low: float
    high: float
    decided: bool
    lps: int

    @property
    def realizable(self) -> bool:
        """Not proved to need more than the hull itself."""
        return self.low < 1.0

    @property
    def scale(self) -> float:
        """The bracket's upper end (its lower one when no upper was found)."""
        return self.high if np.isfinite(self.high) else self.low


def convex_hull(points: ArrayLike) -> Hull:
    """The convex hull of ``points``, (n, 3) m; a set spanning fewer than three dimensions
    is padded by ``1e-9`` of its extent across (as the bounding ellipsoid is).

    Raises ``ValueError`` for no points or non-finite ones.
    """
    from scipy.spatial import ConvexHull, QhullError

    mean, centred = centred_points(points)
    try:
        qh = ConvexHull(centred)
    except QhullError:  # nearly flat beyond the padding's reach: joggle it
        qh = ConvexHull(centred, qhull_options="QJ")
    tri = qh.simplices
    pts = qh.points
    # centre of volume: tetrahedra from an inner point to each boundary triangle
    inner = pts[qh.vertices].mean(axis=0)
    a, b, c = pts[tri[:, 0]] - inner, pts[tri[:, 1]] - inner, pts[tri[:, 2]] - inner
    vol = np.abs(np.einsum("ij,ij->i", a, np.cross(b, c))) / 6.0
    centroid = inner + (vol @ ((a + b + c) / 4.0)) / vol.sum()
    verts = np.unique(tri)
    size = float(np.linalg.norm(pts[verts] - centroid, axis=1).max())
    remap = np.full(len(pts), -1)
    remap[verts] = np.arange(len(verts))
    tri = remap[tri]
    edges = np.unique(np.sort(np.vstack([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [0, 2]]]),
                              axis=1), axis=0)
    eq = qh.equations.copy()
    eq[:, 3] = (eq[:, 3] + eq[:, :3] @ centroid) / size  # in normalised coordinates
    return Hull((pts[verts] - centroid) / size, tri, edges, eq, centroid + mean, size)


def moments(y: np.ndarray) -> np.ndarray:
    """(k, 10) ``a(y) = (1, y, y1^2, y2^2, y3^2, y1 y2, y1 y3, y2 y3)`` of (k, 3) points."""
    y = np.asarray(y, dtype=np.float64).reshape(-1, 3)
    return np.column_stack([np.ones(len(y)), y, y * y, y[:, 0] * y[:, 1],
                            y[:, 0] * y[:, 2], y[:, 1] * y[:, 2]])


def body_moments(mass: float, com: ArrayLike, inertia: ArrayLike, hull: Hull,
                 scale: float = 1.0) -> np.ndarray:
    """(10,) a body's moments per unit mass in ``hull``'s coordinates, the body shrunk by
    ``scale`` about the centroid (the same as the hull grown by it)."""
    mu = (np.asarray(com, dtype=np.float64).reshape(3) - hull.centroid) / (hull.size * scale)
    sigma = central_second_moment(inertia) / (mass * (hull.size * scale) ** 2)
    m2 = sigma + np.outer(mu, mu)
    return np.array([1.0, *mu, m2[0, 0], m2[1, 1], m2[2, 2], m2[0, 1], m2[0, 2], m2[1, 2]])


def quadric(duals: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """``(A, beta, gamma)`` with ``q(y) = -duals . a(y) = y^T A y + 2 beta . y + gamma``."""
    lam = -np.asarray(duals, dtype=np.float64)
    a = np.array([[lam[4], lam[7] / 2, lam[8] / 2],
                  [lam[7] / 2, lam[5], lam[9] / 2],
                  [lam[8] / 2, lam[9] / 2, lam[6]]])
    return a, lam[1:4] / 2, float(lam[0])


def _q(a: np.ndarray, beta: np.ndarray, gamma: float, y: np.ndarray) -> np.ndarray:
    return np.asarray(np.einsum("ij,jk,ik->i", y, a, y) + 2 * y @ beta + gamma)


def quadratic_minimum(a: np.ndarray, beta: np.ndarray, gamma: float, hull: Hull,
                      ) -> tuple[np.ndarray, np.ndarray]:
    """Candidate minimisers of ``q(y) = y^T a y + 2 beta . y + gamma`` over ``hull`` and
    their values: ``(k, 3)`` points, ``(k,)`` values. The minimum over the polytope is
    among them: it lies at a vertex, or in the relative interior of an edge or triangle of
    its triangulated boundary, or inside, where ``q`` restricted to that cell is stationary
    (and convex: a cell whose restriction is not strictly convex holds its minimum on its
    boundary, a lower cell)."""
    v = hull.vertices
    out = [v]
    # edges: q(p + t d) = t^2 d.A.d + 2 t d.(A p + beta) + q(p)
    p, d = v[hull.edges[:, 0]], v[hull.edges[:, 1]] - v[hull.edges[:, 0]]
    curv = np.einsum("ij,jk,ik->i", d, a, d)
    slope = np.einsum("ij,ij->i", d, p @ a + beta)
    ok = curv > 0
    t = np.where(ok, -slope / np.where(ok, curv, 1.0), -1.0)
    inside = (t > 0) & (t < 1)
    out.append(p[inside] + t[inside, None] * d[inside])
    # triangles: y = p0 + u e1 + v e2, a 2 x 2 stationary point
    tri = hull.triangles
    p0, e1, e2 = v[tri[:, 0]], v[tri[:, 1]] - v[tri[:, 0]], v[tri[:, 2]] - v[tri[:, 0]]
    h11 = np.einsum("ij,jk,ik->i", e1, a, e1)
    h22 = np.einsum("ij,jk,ik->i", e2, a, e2)
    h12 = np.einsum("ij,jk,ik->i", e1, a, e2)
    grad = p0 @ a + beta
    g1, g2 = np.einsum("ij,ij->i", e1, grad), np.einsum("ij,ij->i", e2, grad)
    det = h11 * h22 - h12 * h12
    ok = (h11 > 0) & (det > 1e-300)
    safe = np.where(ok, det, 1.0)
    u = np.where(ok, (-h22 * g1 + h12 * g2) / safe, -1.0)
    w = np.where(ok, (h12 * g1 - h11 * g2) / safe, -1.0)
    inside = (u > 0) & (w > 0) & (u + w < 1)
    out.append(p0[inside] + u[inside, None] * e1[inside] + w[inside, None] * e2[inside])
    # inside the hull: the stationary point of a strictly convex q
    eig = np.linalg.eigvalsh(a)
    if eig[0] > 0:
        centre = np.linalg.solve(a, -beta).reshape(1, 3)
        if hull.contains(centre)[0]:
            out.append(centre)
    pts = np.vstack(out)
    return pts, _q(a, beta, gamma, pts)


class _Programme:
    """The LP over a growing set of points of one hull (kept across scales)."""

    def __init__(self, hull: Hull) -> None:
        self.hull = hull
        self.points = np.vstack([hull.vertices, np.zeros((1, 3))])
        self.columns = moments(self.points)
        self.lps = 0

    def _seed(self, b: np.ndarray) -> None:
        """Add the body's sigma points where the hull holds them: ``mu +- sqrt(3 l_k) v_k``
        (``l_k``, ``v_k`` the central second moment's eigenpairs) with equal weights have
        exactly the body's moments, so a body they fit is proved at once (a compact body
        deep inside, which column generation alone reaches slowly)."""
        mu = b[1:4]
        m2 = np.array([[b[4], b[7], b[8]], [b[7], b[5], b[9]], [b[8], b[9], b[6]]])
        lam, vec = np.linalg.eigh(m2 - np.outer(mu, mu))
        arm = vec * np.sqrt(3.0 * np.maximum(lam, 0.0))
        pts = np.vstack([mu + arm.T, mu - arm.T])
        pts = pts[self.hull.contains(pts)]
        if len(pts):
            self.points = np.vstack([self.points, pts])
            self.columns = np.vstack([self.columns, moments(pts)])

    def decide(self, b: np.ndarray) -> bool | None:
        """True: realizable (weights found); False: a certificate; None: undecided."""
        # imported here: scipy.optimize takes longer to import than a warm check's work
        from scipy.optimize import linprog

        self._seed(b)
        for _ in range(MAX_ROUNDS):
            n = len(self.columns)
            a_eq = np.hstack([self.columns.T, np.eye(10), -np.eye(10)])
            cost = np.concatenate([np.zeros(n), np.ones(20)])
            res = linprog(cost, A_eq=a_eq, b_eq=b, bounds=(0, None), method="highs")
            self.lps += 1
            if res.status != 0:
                return None
            if res.fun <= FEASIBLE_TOL:
                return True
            duals = np.asarray(res.eqlin.marginals)
            a, beta, gamma = quadric(duals)
            pts, vals = quadratic_minimum(a, beta, gamma, self.hull)
            shift = max(0.0, -float(vals.min()))
            gap = float(duals @ b)  # = res.fun: the certificate's margin, integral -q dm
            if shift < 0.5 * gap:  # q + shift >= 0 on the hull, integral still negative
                return False
            worst = np.argsort(vals)[:_ADD]
            worst = worst[vals[worst] < 0]
            self.points = np.vstack([self.points, pts[worst]])
            self.columns = np.vstack([self.columns, moments(pts[worst])])
        return None


def hull_scale(mass: float, com: ArrayLike, inertia: ArrayLike, hull: Hull,
               rtol: float = SCALE_RTOL) -> HullScale:
    """The scale of ``hull`` about its centroid that would just hold the body, bracketed
    (:class:`HullScale`); a body realizable in the hull itself is not bracketed further
    (``low = 0``, ``high = 1``).

    mass : kg, > 0; com : (3,) m; inertia : (3, 3) kg m^2 about the CoM (URDF signs),
    meeting the triangle inequality (the ellipsoid test's ``inf`` case is the caller's).
    """
    prog = _Programme(hull)

    def decide(s: float) -> bool | None:
        return prog.decide(body_moments(mass, com, inertia, hull, s))

    first = decide(1.0)
    if first is not False:
        return HullScale(0.0, 1.0 if first else float("inf"), first is not None, prog.lps)
    low, high, s = 1.0, float("inf"), 2.0
    while s <= MAX_SCALE:
        found = decide(s)
        if found is None:
            return HullScale(low, high, False, prog.lps)
        if found:
            high = s
            break
        low, s = s, 2 * s
    while np.isfinite(high) and high / low - 1 > rtol:
        mid = float(np.sqrt(low * high))
        found = decide(mid)
        if found is None:
            return HullScale(low, high, False, prog.lps)
        if found:
            high = mid
        else:
            low = mid
    return HullScale(low, high, True, prog.lps)
