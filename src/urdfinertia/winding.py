"""Generalized winding numbers of triangle surfaces (Jacobson et al. 2013).

Pure numpy. The winding number of an oriented triangle surface at a point is the sum of
the signed solid angles its triangles subtend there, divided by 4 pi: 1 inside and 0
outside a closed outward surface, -1 inside an inverted one, and a smooth value between
for an open surface. It decides whether one closed shell lies inside another (cavities,
nested bodies) independently of how the mesh is triangulated.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

#: Query points x triangles evaluated per chunk (bounds the temporary arrays to ~100 MB).
CHUNK = 1_000_000


def solid_angles(points: ArrayLike, triangles: ArrayLike) -> np.ndarray:
    """Signed solid angle of each triangle seen from each point.

    Van Oosterom & Strackee (1983): ``tan(omega / 2) = a.(b x c) / (|a||b||c| + (a.b)|c|
    + (b.c)|a| + (c.a)|b|)`` with ``a, b, c`` the corners relative to the point.

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
    """Generalized winding number of the surface ``(vertices, faces)`` at each point.

    Parameters
    ----------
    points : (p, 3) float
    vertices : (n, 3) float
    faces : (m, 3) int

    Returns
    -------
    (p,) float
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
