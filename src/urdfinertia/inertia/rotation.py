"""Rotation matrices from URDF roll-pitch-yaw angles (paper eqs. 14-17).

Pure numpy. The seed paper composes a frame's orientation from rotations about x
(gamma), then y (alpha), then z (delta): `A_o = A_delta A_alpha A_gamma` (eq. 15).
That is exactly URDF's `rpy="roll pitch yaw"` convention, `R = Rz(yaw) Ry(pitch) Rx(roll)`,
so one function serves both.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike


def rot_x(angle: float) -> np.ndarray:
    """The elementary rotation about x (A_gamma of eq. 16).

    Parameters
    ----------
    angle : float
        rad, right-handed.

    Returns
    -------
    (3, 3) float
        The rotation matrix.
    """
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def rot_y(angle: float) -> np.ndarray:
    """The elementary rotation about y (A_alpha of eq. 16).

    Parameters
    ----------
    angle : float
        rad, right-handed.

    Returns
    -------
    (3, 3) float
        The rotation matrix.
    """
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def rot_z(angle: float) -> np.ndarray:
    """The elementary rotation about z (A_delta of eq. 16).

    Parameters
    ----------
    angle : float
        rad, right-handed.

    Returns
    -------
    (3, 3) float
        The rotation matrix.
    """
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rpy_matrix(rpy: ArrayLike) -> np.ndarray:
    """Rotation matrix of URDF angles `(roll, pitch, yaw)`: `Rz(yaw) Ry(pitch) Rx(roll)`.

    Parameters
    ----------
    rpy : (3,) float
        Roll (gamma), pitch (alpha) and yaw (delta) in radians.

    Returns
    -------
    (3, 3) float
        `A_o` of eq. 15; its columns are the child frame's axes in the parent frame,
        so a point's coordinates map as `r_parent = A_o @ r_child` (eq. 23).
    """
    roll, pitch, yaw = _vector3(rpy, "rpy")
    matrix: np.ndarray = rot_z(yaw) @ rot_y(pitch) @ rot_x(roll)
    return matrix


def pose_matrix(xyz: ArrayLike, rpy: ArrayLike) -> np.ndarray:
    """The homogeneous transform of a URDF `<origin xyz=".." rpy=".."/>`.

    Parameters
    ----------
    xyz : (3,) float
        The translation, m.
    rpy : (3,) float
        Roll, pitch, yaw, rad (see `rpy_matrix`).

    Returns
    -------
    (4, 4) float
        The child frame's pose in the parent frame.
    """
    t = np.eye(4)
    t[:3, :3] = rpy_matrix(rpy)
    t[:3, 3] = _vector3(xyz, "xyz")
    return t


def _vector3(value: ArrayLike, name: str) -> np.ndarray:
    v = np.asarray(value, dtype=np.float64)
    if v.shape != (3,):
        raise ValueError(f"{name} must have shape (3,), got {v.shape}")
    return v
