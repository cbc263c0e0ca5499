"""MJCF's frame conventions as rotation matrices (pure numpy).

MuJoCo lets a frame's orientation be written five ways (`quat`, `axisangle`, `euler`,
`xyaxes`, `zaxis`; MJCF reference, "Frame orientations") and places capsules,
cylinders, boxes and ellipsoids with `fromto`. Each is converted here the way MuJoCo's
compiler converts it, so that a frame read from MJCF is the frame MuJoCo builds; the
tests compare with the compiled `geom_quat`/`body_quat` of hand-made models.
"""

from __future__ import annotations

import math

import numpy as np

_MINVAL = 1e-15
"""Below this norm a direction is taken as zero (MuJoCo's mjMINVAL)."""


def quat_matrix(quat: tuple[float, ...]) -> np.ndarray:
    """(3, 3) rotation of a quaternion `w x y z` (normalised first, as MuJoCo does)."""
    q = np.asarray(quat, dtype=np.float64)
    norm = float(np.linalg.norm(q))
    if norm < _MINVAL:
        raise ValueError("quaternion has zero norm")
    w, x, y, z = q / norm
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])


def _axis_quat(axis: np.ndarray, angle: float) -> np.ndarray:
    half = 0.5 * angle
    return np.concatenate(([math.cos(half)], math.sin(half) * axis))


def _quat_mul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return np.array([
        w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
        w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
        w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
        w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
    ])


def axisangle_matrix(axis: tuple[float, ...], angle: float) -> np.ndarray:
    """Rotation by `angle` rad about `axis` (normalised)."""
    a = np.asarray(axis, dtype=np.float64)
    norm = float(np.linalg.norm(a))
    if norm < _MINVAL:
        raise ValueError("axisangle has a zero axis")
    return quat_matrix(tuple(_axis_quat(a / norm, angle)))


def euler_matrix(angles: tuple[float, ...], seq: str) -> np.ndarray:
    """Rotation of Euler `angles` (rad) in MuJoCo's `eulerseq`.

    Lower-case axes rotate with the frame (intrinsic: the new rotation multiplies on the
    right), upper-case axes stay fixed (extrinsic: on the left), as MuJoCo's compiler
    accumulates them.
    """
    if len(seq) != 3 or any(c not in "xyzXYZ" for c in seq):
        raise ValueError(f"eulerseq '{seq}' must be three of x, y, z, X, Y, Z")
    q = np.array([1.0, 0.0, 0.0, 0.0])
    for angle, axis_name in zip(angles, seq, strict=True):
        axis = np.zeros(3)
        axis["xyz".index(axis_name.lower())] = 1.0
        rot = _axis_quat(axis, angle)
        q = _quat_mul(q, rot) if axis_name.islower() else _quat_mul(rot, q)
    return quat_matrix(tuple(q))


def xyaxes_matrix(values: tuple[float, ...]) -> np.ndarray:
    """Rotation whose x axis is the first vector and y the second (made orthogonal)."""
    x = np.asarray(values[:3], dtype=np.float64)
    y = np.asarray(values[3:], dtype=np.float64)
    nx = float(np.linalg.norm(x))
    if nx < _MINVAL:
        raise ValueError("xyaxes has a zero x axis")
    x = x / nx
    y = y - x * float(x @ y)
    ny = float(np.linalg.norm(y))
    if ny < _MINVAL:
        raise ValueError("xyaxes has a y axis parallel to x")
    y = y / ny
    return np.column_stack((x, y, np.cross(x, y)))


def zaxis_matrix(direction: tuple[float, ...] | np.ndarray) -> np.ndarray:
    """The smallest rotation taking (0, 0, 1) to `direction` (MuJoCo's quatZ2Vec)."""
    v = np.asarray(direction, dtype=np.float64)
    norm = float(np.linalg.norm(v))
    if norm < _MINVAL:
        raise ValueError("zaxis has zero length")
    v = v / norm
    axis = np.cross([0.0, 0.0, 1.0], v)
    s = float(np.linalg.norm(axis))
    if s < _MINVAL:
        # parallel: identity, or half a turn about x when pointing down
        return np.diag([1.0, -1.0, -1.0]) if v[2] < 0 else np.eye(3)
    return axisangle_matrix(tuple(axis / s), math.atan2(s, float(v[2])))


def fromto_frame(fromto: tuple[float, ...]) -> tuple[np.ndarray, np.ndarray, float]:
    """Centre, rotation and half length of a `fromto` segment (z along the segment)."""
    a = np.asarray(fromto[:3], dtype=np.float64)
    b = np.asarray(fromto[3:], dtype=np.float64)
    d = b - a
    half = 0.5 * float(np.linalg.norm(d))
    if half < _MINVAL:
        raise ValueError("fromto has zero length")
    return 0.5 * (a + b), zaxis_matrix(d), half


def matrix_rpy(r: np.ndarray) -> tuple[float, float, float]:
    """URDF `(roll, pitch, yaw)` of a rotation matrix (inverse of `rpy_matrix`)."""
    r = np.asarray(r, dtype=np.float64)
    pitch = math.atan2(-float(r[2, 0]), math.hypot(float(r[0, 0]), float(r[1, 0])))
    if math.hypot(float(r[0, 0]), float(r[1, 0])) < 1e-12:  # gimbal lock: roll absorbs yaw
        return math.atan2(-float(r[1, 2]), float(r[1, 1])), pitch, 0.0
    roll = math.atan2(float(r[2, 1]), float(r[2, 2]))
    yaw = math.atan2(float(r[1, 0]), float(r[0, 0]))
    return roll, pitch, yaw
