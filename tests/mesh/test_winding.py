"""winding.py: the ray-crossing winding number agrees with the solid-angle one."""

import numpy as np
import pytest
import trimesh

from urdfinertia.mesh.repair.winding import closed_winding_numbers, winding_numbers


def shapes():
    box = trimesh.creation.box([1.0, 2.0, 0.5])
    yield "box", box  # faces parallel to the axes: grazing rays are likely
    yield "icosphere", trimesh.creation.icosphere(subdivisions=2, radius=0.7)
    yield "annulus", trimesh.creation.annulus(0.3, 0.6, 0.4, sections=24)


@pytest.mark.parametrize("name, mesh", list(shapes()))
@pytest.mark.parametrize("inverted", [False, True])
def test_agrees_with_solid_angles(name, mesh, inverted, rng):
    faces = mesh.faces[:, ::-1] if inverted else mesh.faces
    v = mesh.vertices
    lo, hi = v.min(axis=0), v.max(axis=0)
    random_points = rng.uniform(lo - 0.2, hi + 0.2, size=(300, 3))
    centroids = v[faces].mean(axis=1)[:20]  # on the surface: the fallback path
    points = np.concatenate([random_points, centroids, v[:20]])
    fast = closed_winding_numbers(points, v, faces)
    slow = winding_numbers(points, v, faces)
    inside_fast = np.abs(fast) > 0.5
    inside_slow = np.abs(slow) > 0.5
    np.testing.assert_array_equal(inside_fast[:300], inside_slow[:300])
    # off the surface the values are the same integers (+1 inside, -1 inside an inverted one)
    np.testing.assert_allclose(fast[:300], np.round(slow[:300]), atol=1e-9)
    assert inside_slow[:300].any() and (~inside_slow[:300]).any()
