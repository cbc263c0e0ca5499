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

#: The contraction orders ``optimize=True`` finds for the two second-moment sums, for
#: every face count (``(x x^T)`` first, then ``det``; ``det s`` first), given so that each
#: call does not search for them again.
_SECOND_PATH = ["einsum_path", (1, 2), (0, 1)]
_CENTRE_PATH = ["einsum_path", (0, 1), (0, 1)]


def used_vertices(n: int, faces: np.ndarray) -> np.ndarray:
    """(n,) bool: which of ``n`` vertices the faces use (O(n), no sort)."""
    used = np.zeros(n, dtype=bool)
    used[np.asarray(faces).reshape(-1)] = True
    return used


def face_volumes(triangles: np.ndarray) -> np.ndarray:
    """(n,) signed volume of each face's tetrahedron with the origin."""
    tri = np.asarray(triangles, dtype=np.float64)
    return np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])) / 6.0


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
    centre = v[used_vertices(len(v), f)].mean(axis=0)
    tri = v[f] - centre
    det = np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2]))
    total = tri.sum(axis=1)
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
