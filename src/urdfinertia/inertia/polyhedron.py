"""Exact mass properties of closed triangle meshes (signed-tetrahedron integrals).

Pure numpy, vectorised over faces. For an oriented closed surface every face spans a
tetrahedron with the origin; summing their signed volume, first and second moments gives
the exact integrals of the enclosed solid (divergence theorem). The origin is moved to the
vertex centroid first so that large offsets do not cost precision.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from urdfinertia.inertia.massprops import _EYE, MassProperties

_SECOND_PATH = ["einsum_path", (1, 2), (0, 1)]
"""The contraction orders `optimize=True` finds for the two second-moment sums, for every face
count (`(x x^T)` first, then `det`; `det s` first), given so that each call does not search
for them again.
"""
_CENTRE_PATH = ["einsum_path", (0, 1), (0, 1)]


def used_vertices(n: int, faces: np.ndarray) -> np.ndarray:
    """Which of `n` vertices the faces use (O(n), no sort).

    Parameters
    ----------
    n : int
        The number of vertices.
    faces : (m, 3) int
        Vertex indices.

    Returns
    -------
    (n,) bool
        True for a vertex some face uses.
    """
    used = np.zeros(n, dtype=bool)
    used[np.asarray(faces).reshape(-1)] = True
    return used


def cross_rows(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """`np.cross(a, b)` of two (n, 3) float64 arrays, bit for bit: the same products and
    differences (`a1 b2 - a2 b1`, ...), without its axis handling and temporaries.

    Parameters
    ----------
    a, b : (n, 3) float
        Row vectors.

    Returns
    -------
    (n, 3) float
        Their row-wise cross products.
    """
    a0, a1, a2 = a[:, 0], a[:, 1], a[:, 2]
    b0, b1, b2 = b[:, 0], b[:, 1], b[:, 2]
    out = np.empty((len(a), 3))
    tmp = np.empty(len(a))
    np.multiply(a1, b2, out=out[:, 0])
    out[:, 0] -= np.multiply(a2, b1, out=tmp)
    np.multiply(a2, b0, out=out[:, 1])
    out[:, 1] -= np.multiply(a0, b2, out=tmp)
    np.multiply(a0, b1, out=out[:, 2])
    out[:, 2] -= np.multiply(a1, b0, out=tmp)
    return out


def face_volumes(triangles: np.ndarray) -> np.ndarray:
    """The signed volume of each face's tetrahedron with the origin.

    Parameters
    ----------
    triangles : (n, 3, 3) float
        Each face's corners, m.

    Returns
    -------
    (n,) float
        m^3; positive for a face oriented counter-clockwise seen from outside.
    """
    tri = np.asarray(triangles, dtype=np.float64)
    volumes: np.ndarray = np.einsum("ij,ij->i", tri[:, 0], cross_rows(tri[:, 1], tri[:, 2]))
    return volumes / 6.0


def solid_integrals(vertices: ArrayLike, faces: ArrayLike) -> tuple[float, np.ndarray, np.ndarray]:
    """Volume, `integral(x dV)` and `integral(x x^T dV)` of a closed oriented mesh.

    Parameters
    ----------
    vertices : (n, 3) float
    faces : (m, 3) int

    Returns
    -------
    volume : float
        Signed: negative when the faces point inward.
    first : (3,) float
    second : (3, 3) float
        Both about the frame's origin.
    """
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    if v.ndim != 2 or v.shape[1] != 3:
        raise ValueError(f"vertices must have shape (n, 3), got {v.shape}")
    if f.ndim != 2 or f.shape[1] != 3:
        raise ValueError(f"faces must have shape (m, 3), got {f.shape}")
    if len(f) == 0:
        return 0.0, np.zeros(3), np.zeros((3, 3))
    used = used_vertices(len(v), f)
    # the mean of the used vertices (all of them, usually: no copy then)
    centre = (v if used.all() and v.flags.c_contiguous else v[used]).mean(axis=0)
    # the vertices moved once, then gathered: the same numbers as v[f] - centre
    tri = (v - centre)[f]
    t0, t1, t2 = tri[:, 0], tri[:, 1], tri[:, 2]
    det = np.einsum("ij,ij->i", t0, cross_rows(t1, t2))
    total = t0 + t1  # (t0 + t1) + t2, the order of tri.sum(axis=1)
    total += t2
    # Per tetrahedron (0, v0, v1, v2) with det = v0 . (v1 x v2): volume det/6,
    # integral(x dV) = det (v0+v1+v2)/24 and integral(x x^T dV) = det/120 (sum v v^T + s s^T);
    # summed over faces without building (m, 3, 3) intermediates.
    volume = float(det.sum()) / 6.0
    first_c = det @ total / 24.0
    second_c = (np.einsum("f,fki,fkj->ij", det, tri, tri, optimize=_SECOND_PATH)
                + np.einsum("f,fi,fj->ij", det, total, total, optimize=_CENTRE_PATH)) / 120.0
    # shift moments back from the centroid to the origin
    first_o = first_c + volume * centre
    second_o = (second_c + np.outer(first_c, centre) + np.outer(centre, first_c)
                + volume * np.outer(centre, centre))
    return volume, first_o, second_o


def mass_properties_from_integrals(
    volume: float, first: ArrayLike, second: ArrayLike, density: float
) -> MassProperties:
    """The mass properties of a homogeneous solid from its volume integrals.

    Parameters
    ----------
    volume : float
        m^3; positive (an outward-oriented solid).
    first : (3,) float
        `integral(x dV)` about the origin, m^4.
    second : (3, 3) float
        `integral(x x^T dV)` about the origin, m^5.
    density : float
        kg/m^3.

    Returns
    -------
    MassProperties
        Mass, CoM and the inertia about it, in the mesh's frame.

    Raises
    ------
    ValueError
        When `volume` is not positive.
    """
    if not volume > 0:
        raise ValueError(f"solid volume must be positive, got {volume!r}")
    first = np.asarray(first, dtype=np.float64)
    second = np.asarray(second, dtype=np.float64)
    com = first / volume
    # central covariance, then the URDF tensor tr(C) E - C
    cov = second - volume * np.outer(com, com)
    cov = 0.5 * (cov + cov.T)
    inertia = density * (np.trace(cov) * _EYE - cov)
    return MassProperties(density * volume, com, inertia)


def mesh_mass_properties(vertices: ArrayLike, faces: ArrayLike, density: float) -> MassProperties:
    """The exact mass properties of a closed, outward-oriented, homogeneous triangle mesh.

    Parameters
    ----------
    vertices : (n, 3) float
        m.
    faces : (m, 3) int
        Vertex indices, counter-clockwise seen from outside.
    density : float
        kg/m^3.

    Returns
    -------
    MassProperties
        In the mesh's frame.

    Raises
    ------
    ValueError
        When the enclosed volume is not positive (an open or inward-oriented mesh).
    """
    volume, first, second = solid_integrals(vertices, faces)
    return mass_properties_from_integrals(volume, first, second, density)
