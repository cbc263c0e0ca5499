"""rotation.py: URDF rpy = Rz(yaw) Ry(pitch) Rx(roll) (paper eq. 15)."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from urdfinertia.inertia.rotation import pose_matrix, rpy_matrix


def test_rpy_matches_scipy_extrinsic_xyz(rng):
    # scipy's lowercase "xyz" = extrinsic rotations about x, then y, then z = Rz Ry Rx:
    # an independent implementation of the same convention.
    for _ in range(50):
        rpy = rng.uniform(-np.pi, np.pi, 3)
        expected = Rotation.from_euler("xyz", rpy).as_matrix()
        np.testing.assert_allclose(rpy_matrix(rpy), expected, atol=1e-14)


def test_rpy_is_proper_rotation(rng):
    r = rpy_matrix(rng.uniform(-np.pi, np.pi, 3))
    np.testing.assert_allclose(r @ r.T, np.eye(3), atol=1e-14)
    assert np.linalg.det(r) == pytest.approx(1.0, abs=1e-14)


def test_yaw_quarter_turn_maps_x_to_y():
    np.testing.assert_allclose(rpy_matrix([0, 0, np.pi / 2]) @ [1, 0, 0], [0, 1, 0], atol=1e-15)


def test_pose_matrix_places_translation():
    t = pose_matrix([1, 2, 3], [0.1, 0.2, 0.3])
    np.testing.assert_allclose(t[:3, 3], [1, 2, 3])
    np.testing.assert_allclose(t[3], [0, 0, 0, 1])


def test_bad_shape_raises():
    with pytest.raises(ValueError, match="shape"):
        rpy_matrix([0, 0])
