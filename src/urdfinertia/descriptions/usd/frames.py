"""Frames of a USD stage as numpy: prim transforms relative to their body, quaternions.

OpenUSD's `Gf.Matrix4d` acts on row vectors (`p' = p M`); everything here is the
transpose, acting on column vectors as the rest of the package does. Quaternions are
`(w, x, y, z)`, the order of `Gf.Quatf(real, i, j, k)` and of `physics:principalAxes`
as written in `.usda`.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from urdfinertia.descriptions.mjcf.orientation import matrix_rpy, quat_matrix

__all__ = ["matrix_quat", "matrix_rpy", "quat_matrix", "rigid_and_scale", "to_numpy", "vec3"]

AXIS_ROTATION = {
    "Z": np.eye(3),
    "X": np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]]),  # Ry(+90 deg)
    "Y": np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]]),  # Rx(-90 deg)
}
"""Axis tokens of `UsdGeom` cylinders, capsules and cones: the rotation taking the geometry
frame's z (the model's axis of round shapes) onto the prim's axis.
"""


def to_numpy(matrix: Any) -> np.ndarray:
    """(4, 4) column-vector transform of a `Gf.Matrix4d`."""
    return np.array([[matrix[i][j] for j in range(4)] for i in range(4)], dtype=np.float64).T


def rigid_and_scale(t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Split a transform without shear into a rigid (4, 4) and per-axis scale (3,).

    A mirroring transform keeps a proper rotation and carries the reflection as a negative
    z scale. Raises ValueError for a singular transform or one with shear.
    """
    linear = t[:3, :3]
    scale = np.linalg.norm(linear, axis=0)
    if not np.all(scale > 1e-12):
        raise ValueError("transform collapses an axis (zero scale)")
    rot = linear / scale
    if np.linalg.det(rot) < 0:
        rot[:, 2] *= -1.0
        scale[2] *= -1.0
    if not np.allclose(rot.T @ rot, np.eye(3), atol=1e-6):
        raise ValueError("transform has shear, which no shape here can take")
    rigid = np.eye(4)
    rigid[:3, :3] = rot
    rigid[:3, 3] = t[:3, 3]
    return rigid, scale


def matrix_quat(r: np.ndarray) -> tuple[float, float, float, float]:
    """Unit quaternion `(w, x, y, z)` of a rotation matrix, w >= 0 (Shepperd's method)."""
    m = np.asarray(r, dtype=np.float64)
    tr = float(np.trace(m))
    if tr > 0:
        s = 2.0 * math.sqrt(tr + 1.0)
        q = (0.25 * s, (m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s)
    else:
        i = int(np.argmax(np.diag(m)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2.0 * math.sqrt(max(1.0 + m[i, i] - m[j, j] - m[k, k], 0.0))
        v = [0.0, 0.0, 0.0]
        v[i] = 0.25 * s
        v[j] = (m[j, i] + m[i, j]) / s
        v[k] = (m[k, i] + m[i, k]) / s
        q = ((m[k, j] - m[j, k]) / s, v[0], v[1], v[2])
    qa = np.asarray(q, dtype=np.float64)
    qa /= np.linalg.norm(qa)
    if qa[0] < 0:
        qa = -qa
    return float(qa[0]), float(qa[1]), float(qa[2]), float(qa[3])


def vec3(v: Any) -> tuple[float, float, float]:
    """Three floats of any sequence (a numpy row, a `Gf.Vec3f`)."""
    return float(v[0]), float(v[1]), float(v[2])
