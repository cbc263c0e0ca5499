"""Whether a body's mass properties can come from a nonnegative density inside a region.

Pure numpy. The triangle inequality says only that *some* nonnegative density exists
somewhere; the test here says whether one exists inside a given ellipsoid, and so (since
the link's geometry lies in its bounding ellipsoid) it can prove that a written inertial
does not belong to its geometry.

The pseudo-inertia of a body about the frame's origin is the 4 x 4 matrix of its second
moments (Wensing, Kim and Slotine, "Linear Matrix Inequalities for Physically Consistent
Inertial Parameter Identification: A Statistical Perspective on the Mass Distribution",
IEEE RA-L 2017, eq. 6):

```text
J = integral [x; 1][x; 1]^T dm = [[S, m c], [m c^T, m]],   S = integral x x^T dm,
```

and `S = tr(I_o)/2 E - I_o` with `I_o` the inertia about the origin (their eq. 5; the URDF
sign convention of [`massprops`][urdfinertia.inertia.massprops]). A nonnegative density
exists at all iff `J` is positive semi-definite (the triangle inequality), and it exists
inside the ellipsoid `E = {x : (x - e)^T A (x - e) <= 1}` iff moreover `tr(J Q) >= 0` with
`Q = [[-A, A e], [e^T A, 1 - e^T A e]]` (their Theorem 1: the condition is necessary and
sufficient). Written out, `tr(J Q) / m = 1 - mean((x-e)^T A (x-e))`: the mean squared
ellipsoidal radius of the mass must not exceed one. So the test needs no solver, and the
scale of `E` about its centre that would just hold the body is
`sqrt(mean((x - e)^T A (x - e)))` (`ellipsoid_scale`).

The minimum-volume ellipsoid holding a set of points is found by Khachiyan's algorithm
(Khachiyan 1996; Todd and Yildirim's form, "On Khachiyan's algorithm for the computation
of minimum-volume enclosing ellipsoids", Discrete Applied Mathematics 2007):
`bounding_ellipsoid`. Its result is then grown just enough to hold every point, so
it always encloses them, and a body it cannot hold cannot lie among the points either.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

SCALE_RTOL = 1e-9
"""A body whose needed scale is at most this holds in the ellipsoid (round-off of the moments and of
the ellipsoid's last growth step only).
"""


@dataclass(frozen=True, eq=False)
class Ellipsoid:
    """The ellipsoid `{x : (x - centre)^T shape (x - centre) <= 1}`.

    Attributes
    ----------
    centre : (3,) float
        Its centre, m.
    shape : (3, 3) float
        Symmetric positive definite, 1/m^2.
    """

    centre: np.ndarray
    shape: np.ndarray

    @property
    def semi_axes(self) -> np.ndarray:
        """(3,) semi-axis lengths, ascending, m."""
        eig = np.linalg.eigvalsh(self.shape)
        return np.asarray(np.sort(1.0 / np.sqrt(eig)))

    @property
    def volume(self) -> float:
        """m^3."""
        return float(4.0 / 3.0 * np.pi * np.prod(self.semi_axes))

    def radii_squared(self, points: ArrayLike) -> np.ndarray:
        """`(x - centre)^T shape (x - centre)` of each point: <= 1 inside.

        Parameters
        ----------
        points : (n, 3) float
            m.

        Returns
        -------
        (n,) float
            Each point's squared ellipsoidal radius.
        """
        d = np.asarray(points, dtype=np.float64).reshape(-1, 3) - self.centre
        return np.asarray(np.einsum("ij,jk,ik->i", d, self.shape, d))

    def quadric(self) -> np.ndarray:
        """The quadric `Q` of the ellipsoid.

        Returns
        -------
        (4, 4) float
            `Q` with `[x; 1]^T Q [x; 1] = 1 - (x - e)^T A (x - e)` (>= 0 inside).
        """
        a, e = self.shape, self.centre
        q = np.empty((4, 4))
        q[:3, :3] = -a
        q[:3, 3] = q[3, :3] = a @ e
        q[3, 3] = 1.0 - float(e @ a @ e)
        return q


def pseudo_inertia(mass: float, com: ArrayLike, inertia: ArrayLike) -> np.ndarray:
    """The pseudo-inertia about the frame's origin (Wensing et al. 2017, eq. 6).

    Parameters
    ----------
    mass : float
        kg.
    com : (3,) float
        The centre of mass, m.
    inertia : (3, 3) float
        About the CoM along the frame's axes, URDF sign convention
        (`inertia[0, 1] = -integral(x y dm)`), kg m^2.

    Returns
    -------
    (4, 4) float
        `J = integral [x; 1][x; 1]^T dm`.
    """
    c = np.asarray(com, dtype=np.float64).reshape(3)
    i_c = np.asarray(inertia, dtype=np.float64).reshape(3, 3)
    i_c = 0.5 * (i_c + i_c.T)
    # second moment about the CoM, then Huygens-Steiner for the first-moment term
    s = 0.5 * np.trace(i_c) * np.eye(3) - i_c + mass * np.outer(c, c)
    j = np.empty((4, 4))
    j[:3, :3] = s
    j[:3, 3] = j[3, :3] = mass * c
    j[3, 3] = mass
    return j


def central_second_moment(inertia: ArrayLike) -> np.ndarray:
    """The central second moment `integral (x - c)(x - c)^T dm` from the inertia about the
    CoM `I_c`: `tr(I_c)/2 E - I_c`. Positive semi-definite iff the triangle inequality
    holds.

    Parameters
    ----------
    inertia : (3, 3) float
        About the CoM, kg m^2.

    Returns
    -------
    (3, 3) float
        kg m^2.
    """
    i_c = np.asarray(inertia, dtype=np.float64).reshape(3, 3)
    i_c = 0.5 * (i_c + i_c.T)
    return np.asarray(0.5 * np.trace(i_c) * np.eye(3) - i_c)


def ellipsoid_scale(mass: float, com: ArrayLike, inertia: ArrayLike,
                    ellipsoid: Ellipsoid) -> float:
    """The scale of `ellipsoid` about its centre that would just hold the body.

    `sqrt(mean((x - e)^T A (x - e)))` over the mass: <= 1 means a nonnegative density
    inside the ellipsoid has exactly these mass properties (the LMI `tr(J Q) >= 0` of
    Wensing et al. 2017, Theorem 1, with `J` semi-definite); > 1 means none has, however
    the mass is spread.

    Parameters
    ----------
    mass : float
        kg.
    com : (3,) float
        The centre of mass, m.
    inertia : (3, 3) float
        About the CoM along the frame's axes, kg m^2.
    ellipsoid : Ellipsoid
        The region the mass is to lie in.

    Returns
    -------
    float
        The scale; `inf` when no nonnegative density anywhere has these values
        (`mass <= 0` or the triangle inequality broken beyond round-off).
    """
    c = np.asarray(com, dtype=np.float64).reshape(3)
    sigma = central_second_moment(inertia)
    if not mass > 0:
        return float("inf")
    eig = np.linalg.eigvalsh(sigma)
    if eig[0] < -1e-9 * max(abs(eig[-1]), 1e-300):
        return float("inf")
    d = c - ellipsoid.centre
    mean_r2 = float(np.sum(ellipsoid.shape * sigma)) / mass + float(d @ ellipsoid.shape @ d)
    return float(np.sqrt(max(mean_r2, 0.0)))


def realizable_in(mass: float, com: ArrayLike, inertia: ArrayLike,
                  ellipsoid: Ellipsoid) -> bool:
    """Whether a nonnegative density inside `ellipsoid` has these mass properties: the LMI
    test `J >= 0` and `tr(J Q) >= 0` (up to `SCALE_RTOL`).

    Parameters
    ----------
    mass : float
        kg.
    com : (3,) float
        The centre of mass, m.
    inertia : (3, 3) float
        About the CoM along the frame's axes, kg m^2.
    ellipsoid : Ellipsoid
        The region the mass is to lie in.

    Returns
    -------
    bool
        True when some mass inside the ellipsoid has them.
    """
    return ellipsoid_scale(mass, com, inertia, ellipsoid) <= 1.0 + SCALE_RTOL


def bounding_ellipsoid(points: ArrayLike, tol: float = 1e-2) -> Ellipsoid:
    """The (near) minimum-volume ellipsoid holding `points`, (n, 3) m.

    Khachiyan's algorithm with Todd and Yildirim's updates, stopped when the largest
    weighted radius is within `tol` of optimal (the volume is then within
    `(1 + tol)^2` of the minimum: 2 % at the default, each semi-axis within about
    1.5 % of the minimum's; ten times tighter costs about four times the time, measured
    on the corpus). The result is grown to hold every point exactly, so it always
    encloses them.
    Points spanning less than three dimensions (a flat plate, a segment) are padded by
    `1e-9` of their extent in the missing directions, so the ellipsoid exists.

    Parameters
    ----------
    points : (n, 3) float
        m.
    tol : float
        The relative optimality at which the iteration stops.

    Returns
    -------
    Ellipsoid
        An ellipsoid holding every point.

    Raises
    ------
    ValueError
        For no points or non-finite ones.
    """
    mean, centred = centred_points(points)
    centre, shape = _khachiyan(centred, tol)
    r2 = _radii2(centred, centre, shape)
    shape = shape / max(float(r2.max()), 1e-300)  # grow (or shrink) to hold every point
    return Ellipsoid(centre + mean, 0.5 * (shape + shape.T))


def _radii2(points: np.ndarray, centre: np.ndarray, shape: np.ndarray) -> np.ndarray:
    d = points - centre
    return np.asarray(np.einsum("ij,jk,ik->i", d, shape, d))


def centred_points(points: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """The mean of `points` and the points about it, padded to span three dimensions.

    Parameters
    ----------
    points : (n, 3) float
        m.

    Returns
    -------
    mean : (3,) float
        Their mean, m.
    centred : (k, 3) float
        The points about it, with `full_dimensional`'s padding.

    Raises
    ------
    ValueError
        For no points or non-finite ones.
    """
    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    if p.shape[0] == 0 or not np.all(np.isfinite(p)):
        raise ValueError(f"need finite (n, 3) points, got shape {p.shape}")
    mean = p.mean(axis=0)
    return mean, full_dimensional(p - mean)


def full_dimensional(centred: np.ndarray) -> np.ndarray:
    """Points padded to a set with a full-dimensional hull.

    Parameters
    ----------
    centred : (n, 3) float
        Points about their mean, m.

    Returns
    -------
    (k, 3) float
        `centred`, plus points `1e-9` of their extent off their span when they span fewer
        than three dimensions.
    """
    extent = max(float(np.abs(centred).max()), 1e-12)
    eig, vec = np.linalg.eigh(centred.T @ centred)  # the spread along each direction
    thin = extent * 1e-9
    pads = [s * vec[:, k] for k in range(3) if np.sqrt(max(eig[k], 0.0)) <= thin * 10
            for s in (thin, -thin)]
    out = np.vstack([centred, np.asarray(pads)]) if pads else centred
    if len(out) < 4:  # too few points for a full-dimensional set: add their mirror images
        out = np.vstack([out, -out, np.eye(3) * thin])
    return out


def _khachiyan(points: np.ndarray, tol: float, max_iter: int = 100000,
               ) -> tuple[np.ndarray, np.ndarray]:
    """Centre and shape of the minimum ellipsoid of `points`: Todd and Yildirim 2007,
    Algorithm 4.1 (Khachiyan's steps toward the farthest point, "drop" steps away from the
    nearest supporting one), started from Kumar and Yildirim's core set, with the inverse
    moment matrix kept up to date by rank-one (Sherman-Morrison) updates."""
    n = len(points)
    lifted = np.hstack([points, np.ones((n, 1))])  # (n, 4)
    d = 4.0
    u = np.zeros(n)
    u[_core_set(points)] = 1.0
    u /= u.sum()
    xinv = np.linalg.inv(lifted.T @ (u[:, None] * lifted))
    m = np.einsum("ij,jk,ik->i", lifted, xinv, lifted)
    inf = np.full(n, np.inf)
    for it in range(max_iter):
        j = int(np.argmax(m))
        k = int(np.argmin(np.where(u > 0, m, inf)))
        kappa_j, kappa_k = float(m[j]), float(m[k])
        if kappa_j <= d * (1.0 + tol) and kappa_k >= d * (1.0 - tol):
            break
        if kappa_j / d - 1.0 >= 1.0 - kappa_k / d:
            i, kappa = j, kappa_j
            beta = (kappa - d) / (d * (kappa - 1.0))
        else:
            i, kappa = k, kappa_k
            # move weight off point k, never below zero
            beta = max(-(d - kappa) / (d * (kappa - 1.0)), -u[k] / (1.0 - u[k]))
        u *= 1.0 - beta
        u[i] += beta
        if it % 500 == 499:  # refresh against drift of the rank-one updates
            xinv = np.linalg.inv(lifted.T @ (u[:, None] * lifted))
            m = np.einsum("ij,jk,ik->i", lifted, xinv, lifted)
            continue
        # X' = (1 - beta) X + beta q q^T: Sherman-Morrison on X^-1 and on every m
        xq = xinv @ lifted[i]
        w = lifted @ xq
        denom = (1.0 - beta) + beta * kappa
        xinv = (xinv - (beta / denom) * np.outer(xq, xq)) / (1.0 - beta)
        m = (m - (beta / denom) * (w * w)) / (1.0 - beta)
    centre = points.T @ u
    cov = points.T @ (u[:, None] * points) - np.outer(centre, centre)
    return centre, np.linalg.inv(cov) / 3.0


def _core_set(points: np.ndarray) -> np.ndarray:
    """Kumar and Yildirim's initial set: the extreme points along 3 directions, each new
    direction orthogonal to the span of the differences found so far."""
    chosen: list[int] = []
    basis = np.zeros((0, 3))
    rng = np.random.default_rng(0)  # a fixed start: the result must not vary between runs
    for _ in range(3):
        v = rng.normal(size=3)
        for b in basis:
            v -= (v @ b) * b
        v /= np.linalg.norm(v)
        proj = points @ v
        lo, hi = int(np.argmin(proj)), int(np.argmax(proj))
        chosen += [lo, hi]
        diff = points[hi] - points[lo]
        for b in basis:
            diff -= (diff @ b) * b
        norm = np.linalg.norm(diff)
        basis = np.vstack([basis, diff / norm]) if norm > 0 else np.vstack([basis, v])
    return np.unique(np.asarray(chosen))
