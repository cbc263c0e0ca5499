"""Shells: a solid's wall of thickness `t` and the interior it encloses (pure numpy).

The wall is the outer solid minus its *inner parallel body*, the points at least `t`
inside the surface; the interior is that inner body (where a 3-D printer puts infill).
Both are returned as volume integrals at unit density, so the wall is exact whenever the
inner body is:

* box, sphere, cylinder, capsule, cone: the inner body is the same primitive, smaller
  (a cone's apex moves in by `t / sin(half-angle)`): exact closed forms;
* ellipsoid: the inner body is *not* an ellipsoid. The wall is integrated over the
  tube `x = p(u) - s n(u)`, `0 <= s <= t`, whose volume element is
  `(1 - 2 H s + K s^2) dA ds` (H, K: mean and Gaussian curvature). That is exact while
  `t` is below the smallest radius of curvature `c^2 / a` (Blaschke's rolling ball);
  the surface integral is done by Gauss-Legendre x trapezoid quadrature, converged to
  round-off for the resolutions used (see the tests);
* meshes: each vertex moves inward so that each adjacent face plane moves by `t`
  (least squares on the face normals, weighted by the corner angles). That is the exact
  inner offset wherever at most three distinct planes meet at a vertex (a box, any
  convex polyhedron with simple corners); elsewhere the planes miss the vertex by a
  residual, and `sum(face area x residual)` is the stated error of the wall volume.
  An offset that inverts a face, leaves the solid or comes closer than `t` to another
  part of the surface (a wall thicker than half the part) raises `ShellError`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from urdfinertia.inertia import primitives
from urdfinertia.inertia.massprops import _EYE, MassProperties
from urdfinertia.inertia.polyhedron import (
    cross_rows,
    mass_properties_from_integrals,
    solid_integrals,
)

_RANK_RTOL = 1e-9
"""Eigenvalues of a vertex's normal matrix below this fraction of its largest belong to directions
no adjacent face constrains (a flat or straight neighbourhood).
"""
_CHECK_PAIRS = 2_000_000
"""About this many vertex-face pairs are tested for the depth and containment checks (all vertices
of a mesh under ~2000 faces, an even sample of larger ones).
"""
CHECKED_FACES = int(np.sqrt(2 * _CHECK_PAIRS))
"""Meshes with more faces than this have only a sample of their vertices depth-checked."""
_ELLIPSOID_NODES = (160, 320)
"""Quadrature of the ellipsoid's wall: Gauss-Legendre nodes in the polar angle, trapezoid nodes in
the azimuth (exact for the cubic-in-s integrands with 3 nodes in s).
"""


class ShellError(ValueError):
    """The wall cannot be built: too thick for the part, or the offset is not valid."""


Moments = tuple[float, np.ndarray, np.ndarray]  # volume, integral(x dV), integral(x x^T dV)


@dataclass(frozen=True, eq=False)
class Shell:
    """A wall and its interior, as volume integrals about the solid's frame origin.

    Attributes
    ----------
    wall, interior : (volume, first (3,), second (3, 3))
        `integral(1, x, x x^T dV)` of the wall and of the inner body.
    error : float
        Stated relative error of the wall volume (0 for exact methods).
    method : str
        How the inner body was found.
    """

    wall: Moments
    interior: Moments
    error: float
    method: str

    def filled(self, weight: float) -> MassProperties:
        """The wall plus the interior at `weight` times the wall's density.

        Parameters
        ----------
        weight : float
            The infill: 0 hollow, 1 solid.

        Returns
        -------
        MassProperties
            At unit density of the wall.

        Raises
        ------
        ValueError
            When `weight` is negative or not finite.
        """
        if not (math.isfinite(weight) and weight >= 0):
            raise ValueError(f"infill weight must be >= 0 and finite, got {weight!r}")
        (v0, f0, s0), (v1, f1, s1) = self.wall, self.interior
        return mass_properties_from_integrals(v0 + weight * v1, f0 + weight * f1,
                                              s0 + weight * s1, 1.0)


def moments_of(body: MassProperties) -> Moments:
    """The volume integrals of a unit-density body (the inverse of
    [`mass_properties_from_integrals`][urdfinertia.inertia.polyhedron.mass_properties_from_integrals]).

    Parameters
    ----------
    body : MassProperties
        At unit density.

    Returns
    -------
    (float, (3,) float, (3, 3) float)
        `(volume, integral(x dV), integral(x x^T dV))` about the origin.
    """
    m, c = body.mass, body.com
    cov = 0.5 * np.trace(body.inertia) * _EYE - body.inertia  # central integral(x x^T)
    return m, m * c, cov + m * np.outer(c, c)


def _difference(outer: MassProperties, inner: MassProperties, method: str) -> Shell:
    (v0, f0, s0), (v1, f1, s1) = moments_of(outer), moments_of(inner)
    return Shell((v0 - v1, f0 - f1, s0 - s1), (v1, f1, s1), 0.0, method)


def _thickness(t: float) -> float:
    if not (math.isfinite(t) and t > 0):
        raise ShellError(f"shell thickness must be positive and finite, got {t!r}")
    return float(t)


def _too_thick(t: float, limit: float, what: str) -> ShellError:
    return ShellError(f"a {t * 1e3:.4g} mm wall leaves no interior: {what} is "
                      f"{limit * 1e3:.4g} mm")


# --- primitives -------------------------------------------------------------------------

def box_shell(size: ArrayLike, t: float) -> Shell:
    """A box's shell: the interior is the box `size - 2 t`.

    Parameters
    ----------
    size : (3,) float
        The full side lengths, m.
    t : float
        The wall thickness, m.

    Returns
    -------
    Shell
        The wall's and the interior's volume integrals (unit density).

    Raises
    ------
    ShellError
        When `t` is not positive, or the wall leaves no interior.
    """
    t = _thickness(t)
    s = np.asarray(size, dtype=np.float64)
    if not s.min() > 2 * t:
        raise _too_thick(t, s.min() / 2, "half the smallest side")
    return _difference(primitives.box(s, 1.0), primitives.box(s - 2 * t, 1.0),
                       "closed form box shell")


def sphere_shell(radius: float, t: float) -> Shell:
    """A sphere's shell: the interior is the sphere of radius `radius - t`.

    Parameters
    ----------
    radius : float
        m.
    t : float
        The wall thickness, m.

    Returns
    -------
    Shell
        The wall's and the interior's volume integrals (unit density).

    Raises
    ------
    ShellError
        When `t` is not positive, or the wall leaves no interior.
    """
    t = _thickness(t)
    if not radius > t:
        raise _too_thick(t, radius, "the radius")
    return _difference(primitives.sphere(radius, 1.0), primitives.sphere(radius - t, 1.0),
                       "closed form sphere shell")


def cylinder_shell(radius: float, length: float, t: float) -> Shell:
    """A closed cylinder's shell: walls and both end caps `t` thick.

    Parameters
    ----------
    radius : float
        m.
    length : float
        The full length along z, m.
    t : float
        The wall thickness, m.

    Returns
    -------
    Shell
        The wall's and the interior's volume integrals (unit density).

    Raises
    ------
    ShellError
        When `t` is not positive, or the wall leaves no interior.
    """
    t = _thickness(t)
    if not (radius > t and length > 2 * t):
        raise _too_thick(t, min(radius, length / 2), "the radius or half the length")
    return _difference(primitives.cylinder(radius, length, 1.0),
                       primitives.cylinder(radius - t, length - 2 * t, 1.0),
                       "closed form cylinder shell")


def capsule_shell(radius: float, length: float, t: float) -> Shell:
    """A capsule's shell: the inner body is the capsule of radius `r - t` on the same segment.

    Parameters
    ----------
    radius : float
        m.
    length : float
        The cylindrical section's length, m.
    t : float
        The wall thickness, m.

    Returns
    -------
    Shell
        The wall's and the interior's volume integrals (unit density).

    Raises
    ------
    ShellError
        When `t` is not positive, or the wall leaves no interior.
    """
    t = _thickness(t)
    if not radius > t:
        raise _too_thick(t, radius, "the radius")
    return _difference(primitives.capsule(radius, length, 1.0),
                       primitives.capsule(radius - t, length, 1.0),
                       "closed form capsule shell")


def cone_shell(radius: float, height: float, t: float) -> Shell:
    """A cone's shell, the cone as [`cone`][urdfinertia.inertia.primitives.cone]: the inner
    body is a cone of the same half-angle `a`, base raised by `t`, apex lowered by
    `t / sin a`.

    Parameters
    ----------
    radius : float
        The base's radius, m.
    height : float
        m.
    t : float
        The wall thickness, m.

    Returns
    -------
    Shell
        The wall's and the interior's volume integrals (unit density).

    Raises
    ------
    ShellError
        When `t` is not positive, or the wall leaves no interior.
    """
    t = _thickness(t)
    sin_a = radius / math.hypot(radius, height)
    inner_h = height - t - t / sin_a
    if not inner_h > 0:
        raise _too_thick(t, height / (1 + 1 / sin_a), "the cone's inradius")
    inner = primitives.cone(radius * inner_h / height, inner_h, 1.0)
    inner = inner.translated([0.0, 0.0, -height / 2 + t + inner_h / 2])
    return _difference(primitives.cone(radius, height, 1.0), inner,
                       "closed form cone shell")


def ellipsoid_shell(radii: ArrayLike, t: float,
                    nodes: tuple[int, int] = _ELLIPSOID_NODES) -> Shell:
    """An ellipsoid's shell: the wall as a tube integral (module docstring).

    Parameters
    ----------
    radii : (3,) float
        The semi-axes, m.
    t : float
        The wall thickness, m.
    nodes : (int, int)
        The quadrature's nodes along the two surface parameters.

    Returns
    -------
    Shell
        The wall's and the interior's volume integrals (unit density).

    Raises
    ------
    ShellError
        When `t` is not positive, or the wall leaves no interior.
    """
    t = _thickness(t)
    a, b, c = (float(r) for r in np.asarray(radii, dtype=np.float64))
    reach = min(a, b, c) ** 2 / max(a, b, c)
    if not t < reach:
        raise ShellError(f"a {t * 1e3:.4g} mm wall is thicker than the ellipsoid's "
                         f"smallest radius of curvature ({reach * 1e3:.4g} mm): its inner "
                         "body has edges this method does not integrate")
    n_theta, n_phi = nodes
    x, w = np.polynomial.legendre.leggauss(n_theta)
    theta = (x + 1) * np.pi / 2
    w_theta = w * np.pi / 2
    phi = np.arange(n_phi) * 2 * np.pi / n_phi
    th, ph = np.meshgrid(theta, phi, indexing="ij")
    st, ct, sp, cp = np.sin(th), np.cos(th), np.sin(ph), np.cos(ph)
    p = np.stack([a * st * cp, b * st * sp, c * ct], axis=-1)
    grad = p / np.array([a * a, b * b, c * c])
    g = np.linalg.norm(grad, axis=-1)
    n = grad / g[..., None]
    # |p_theta x p_phi| and the curvatures of the ellipsoid (outward normal, convex: > 0)
    da = st * np.sqrt((b * c * st * cp) ** 2 + (a * c * st * sp) ** 2 + (a * b * ct) ** 2)
    abc2 = (a * b * c) ** 2
    gauss = 1.0 / (abc2 * g**4)
    mean = (a * a + b * b + c * c - np.einsum("...i,...i", p, p)) / (2 * abc2 * g**3)
    weights = w_theta[:, None] * (2 * np.pi / n_phi) * da
    xs, ws = np.polynomial.legendre.leggauss(3)
    vol, first, second = 0.0, np.zeros(3), np.zeros((3, 3))
    for xi, wi in zip(xs, ws, strict=True):
        s = (xi + 1) * t / 2
        q = p - s * n
        jac = weights * (1 - 2 * mean * s + gauss * s * s) * wi * t / 2
        vol += float(jac.sum())
        first += np.einsum("ij,ijk->k", jac, q)
        second += np.einsum("ij,ijk,ijl->kl", jac, q, q)
    outer = moments_of(primitives.ellipsoid((a, b, c), 1.0))
    wall = (vol, first, 0.5 * (second + second.T))
    interior = (outer[0] - vol, outer[1] - first, outer[2] - wall[2])
    return Shell(wall, interior, 0.0, "ellipsoid shell (tube integral)")


# --- meshes -----------------------------------------------------------------------------

def mesh_shell(vertices: ArrayLike, faces: ArrayLike, t: float) -> Shell:
    """Wall of a closed, outward-oriented triangle mesh (cavity shells turned inward).

    Parameters
    ----------
    vertices : (n, 3) float
        m.
    faces : (m, 3) int
        Vertex indices, counter-clockwise seen from outside.
    t : float
        Wall thickness, m.

    Returns
    -------
    Shell
        The wall's and the interior's volume integrals (unit density).

    Raises
    ------
    ShellError
        The offset inverts faces, leaves the solid, comes closer than `t` to the
        surface elsewhere, or encloses no volume.
    """
    t = _thickness(t)
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    if v.ndim != 2 or v.shape[1] != 3 or f.ndim != 2 or f.shape[1] != 3 or not len(f):
        raise ValueError(f"need (n, 3) vertices and (m, 3) faces, got {v.shape}, {f.shape}")
    tri = v[f]
    cross = cross_rows(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    double_area = np.linalg.norm(cross, axis=1)
    live = double_area > 0
    normal = np.zeros_like(cross)
    normal[live] = cross[live] / double_area[live, None]
    weight = _corner_angles(tri) * live[:, None]
    matrix = np.zeros((len(v), 3, 3))
    rhs = np.zeros((len(v), 3))
    outer_nn = normal[:, :, None] * normal[:, None, :]
    for k in range(3):
        np.add.at(matrix, f[:, k], weight[:, k, None, None] * outer_nn)
        np.add.at(rhs, f[:, k], weight[:, k, None] * normal)
    values, vectors = np.linalg.eigh(matrix)
    keep = values > _RANK_RTOL * values[:, -1:]
    inverse = np.where(keep, 1.0 / np.where(keep, values, 1.0), 0.0)
    along = np.einsum("nji,nj->ni", vectors, rhs) * inverse
    move = -t * np.einsum("nij,nj->ni", vectors, along)
    inner = v + move
    # how far each face corner's plane misses its offset (0 where <= 3 planes meet)
    residual = np.abs(np.einsum("fj,fkj->fk", normal, move[f]) + t)
    _check_offset(v, f, inner, cross, live, t, residual)
    outer_m = solid_integrals(v, f)
    inner_m = solid_integrals(inner, f)
    if not 0 < inner_m[0] < outer_m[0]:
        raise ShellError(f"the offset by {t * 1e3:.4g} mm encloses no interior "
                         f"({inner_m[0]:.3g} m^3 of {outer_m[0]:.3g} m^3)")
    wall: Moments = (outer_m[0] - inner_m[0], outer_m[1] - inner_m[1],
                     outer_m[2] - inner_m[2])
    error = float((0.5 * double_area * residual.mean(axis=1)).sum()) / wall[0]
    method = ("mesh shell (exact offset: simple corners)" if error < 1e-12
              else "mesh shell (least-squares vertex offset)")
    return Shell(wall, inner_m, error if error >= 1e-12 else 0.0, method)


def _corner_angles(tri: np.ndarray) -> np.ndarray:
    """(m, 3) interior angle of each triangle at each corner."""
    out = np.empty(tri.shape[:2])
    for k in range(3):
        e1 = tri[:, (k + 1) % 3] - tri[:, k]
        e2 = tri[:, (k + 2) % 3] - tri[:, k]
        c = cross_rows(e1, e2)
        out[:, k] = np.arctan2(np.linalg.norm(c, axis=1), np.einsum("ij,ij->i", e1, e2))
    return out


def _check_offset(v: np.ndarray, f: np.ndarray, inner: np.ndarray, cross: np.ndarray,
                  live: np.ndarray, t: float, residual: np.ndarray) -> None:
    """Raise `ShellError` unless the offset surface is a valid inner body."""
    tri = inner[f]
    inner_cross = cross_rows(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    flipped = int(np.count_nonzero(np.einsum("ij,ij->i", inner_cross, cross)[live] <= 0))
    if flipped:
        raise ShellError(f"a {t * 1e3:.4g} mm wall inverts {flipped} of {len(f)} faces: "
                         "the part is thinner than two walls somewhere")
    used = np.unique(f)
    outer_tri = v[f]
    # every moved vertex (of an even sample of at most _CHECK_PAIRS / faces of them) at
    # least t, less its planes' residual, from every face, else walls from opposite
    # sides overlap; only faces whose box, grown by t, holds the vertex can be that near
    count = max(1, min(len(used), _CHECK_PAIRS // len(f)))
    used = used[np.unique(np.linspace(0, len(used) - 1, count).round().astype(np.int64))]
    slack = np.zeros(len(v))
    np.maximum.at(slack, f.reshape(-1), residual.reshape(-1))
    scale = float(np.ptp(v, axis=0).max())
    need = (t - slack - 1e-9 * scale) * (1 - 1e-6)
    low, high = outer_tri.min(axis=1) - t, outer_tri.max(axis=1) + t
    chunk = max(1, 250_000 // len(f))
    for start in range(0, len(used), chunk):
        ids = used[start:start + chunk]
        p = inner[ids]
        near = np.all((p[:, None] >= low[None]) & (p[:, None] <= high[None]), axis=2)
        which, face = np.nonzero(near)
        depth = _distances(p[which], outer_tri[face])
        close = depth < need[ids[which]]
        if np.any(close):
            worst = float(depth[close].min())
            raise ShellError(f"a {t * 1e3:.4g} mm wall overlaps the wall opposite it (an "
                             f"inner corner {worst * 1e3:.3g} mm from the surface): the "
                             "part is thinner than two walls somewhere")
    # and inside the solid (a smaller sample: a vertex pushed through a thin part and
    # out of it is also too near the far side, caught above)
    sample = used[::max(1, len(used) * len(f) // (_CHECK_PAIRS // 8))]
    if np.any(_winding_numbers(inner[sample], outer_tri) < 0.5):
        raise ShellError(f"a {t * 1e3:.4g} mm wall moves the surface out of the part: "
                         "the part is thinner than two walls somewhere")


def _winding_numbers(points: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """(k,) generalised winding number of a closed surface about each point
    (van Oosterom-Strackee solid angles)."""
    a = tri[None, :, 0] - points[:, None]
    b = tri[None, :, 1] - points[:, None]
    c = tri[None, :, 2] - points[:, None]
    la, lb, lc = (np.linalg.norm(x, axis=2) for x in (a, b, c))
    det = np.einsum("pfi,pfi->pf", a, np.cross(b, c))
    den = (la * lb * lc + np.einsum("pfi,pfi->pf", a, b) * lc
           + np.einsum("pfi,pfi->pf", a, c) * lb + np.einsum("pfi,pfi->pf", b, c) * la)
    result: np.ndarray = np.arctan2(det, den).sum(axis=1) / (2 * np.pi)
    return result


def _distances(p: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """(q,) distance from each point `p[i]` to the triangle `tri[i]`."""
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    n = cross_rows(b - a, c - a)
    nn = np.einsum("ij,ij->i", n, n)
    nn = np.where(nn > 0, nn, 1.0)
    plane = np.einsum("ij,ij->i", p - a, n) / nn
    foot = p - plane[:, None] * n
    # the foot is in the triangle when it is on the inner side of every edge
    inside = np.ones(len(p), dtype=bool)
    for x, y in ((a, b), (b, c), (c, a)):
        inside &= np.einsum("ij,ij->i", cross_rows(y - x, foot - x), n) >= 0
    best = np.where(inside, np.abs(plane) * np.sqrt(nn), np.inf)
    for x, y in ((a, b), (b, c), (c, a)):
        e = y - x
        ee = np.einsum("ij,ij->i", e, e)
        s = np.clip(np.einsum("ij,ij->i", p - x, e) / np.where(ee > 0, ee, 1.0), 0, 1)
        best = np.minimum(best, np.linalg.norm(p - x - s[:, None] * e, axis=1))
    result: np.ndarray = best
    return result
