"""Exact mass properties of closed triangle meshes (signed-tetrahedron integrals).

Pure numpy, vectorised over faces. For an oriented closed surface every face spans a
tetrahedron with the origin; summing their signed volume, first and second moments gives
the exact integrals of the enclosed solid (divergence theorem). The origin is moved to the
vertex centroid first so that large offsets do not cost precision.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from .massprops import MassProperties


def face_moments(triangles: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Signed volume, first and second moments of each face's tetrahedron with the origin.

    Parameters
    ----------
    triangles : (n, 3, 3) float
        Vertex coordinates per face, counter-clockwise seen from outside.

    Returns
    -------
    volume : (n,) float
    first : (n, 3) float
        ``integral(x dV)`` per tetrahedron.
    second : (n, 3, 3) float
        ``integral(x x^T dV)`` per tetrahedron.
    """
    tri = np.asarray(triangles, dtype=np.float64)
    if tri.ndim != 3 or tri.shape[1:] != (3, 3):
        raise ValueError(f"triangles must have shape (n, 3, 3), got {tri.shape}")
    v0, v1, v2 = tri[:, 0], tri[:, 1], tri[:, 2]
    det = np.einsum("ij,ij->i", v0, np.cross(v1, v2))
    total = v0 + v1 + v2
    volume = det / 6.0
    first = det[:, None] * total / 24.0
    # integral over tetra (0, v0, v1, v2) of x x^T = det/120 (sum v v^T + s s^T)
    second = (det / 120.0)[:, None, None] * (
        np.einsum("fki,fkj->fij", tri, tri) + np.einsum("fi,fj->fij", total, total)
    )
    return volume, first, second


def solid_integrals(vertices: ArrayLike, faces: ArrayLike) -> tuple[float, np.ndarray, np.ndarray]:
    """Volume, ``integral(x dV)`` and ``integral(x x^T dV)`` of a closed oriented mesh.

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
    centre = v[np.unique(f)].mean(axis=0)
    vol, first, second = face_moments(v[f] - centre)
    volume = float(vol.sum())
    first_c = first.sum(axis=0)
    second_c = second.sum(axis=0)
    # shift moments back from the centroid to the origin
    first_o = first_c + volume * centre
    second_o = (second_c + np.outer(first_c, centre) + np.outer(centre, first_c)
                + volume * np.outer(centre, centre))
    return volume, first_o, second_o


def mass_properties_from_integrals(
    volume: float, first: ArrayLike, second: ArrayLike, density: float
) -> MassProperties:
    """Mass properties of a solid from its volume integrals about the origin.

    ``volume`` must be positive (an outward-oriented solid).
    """
    if not volume > 0:
        raise ValueError(f"solid volume must be positive, got {volume!r}")
    first = np.asarray(first, dtype=np.float64)
    second = np.asarray(second, dtype=np.float64)
    com = first / volume
    # central covariance, then the URDF tensor tr(C) E - C
    cov = second - volume * np.outer(com, com)
    cov = 0.5 * (cov + cov.T)
    inertia = density * (np.trace(cov) * np.eye(3) - cov)
    return MassProperties(density * volume, com, inertia)


def mesh_mass_properties(vertices: ArrayLike, faces: ArrayLike, density: float) -> MassProperties:
    """Exact mass properties of a closed, outward-oriented triangle mesh."""
    volume, first, second = solid_integrals(vertices, faces)
    return mass_properties_from_integrals(volume, first, second, density)
