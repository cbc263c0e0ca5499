"""primitives.py: closed forms against finely meshed primitives (trimesh.creation).

Meshed round shapes are inscribed polygons/polyhedra, so they fall short of the closed
form by a known O(h^2) amount; each tolerance below states that bound.
"""

import numpy as np
import pytest
import trimesh

from urdfinertia.inertia import primitives
from urdfinertia.inertia.polyhedron import mesh_mass_properties

RHO = 1234.0


def meshed(mesh: trimesh.Trimesh):
    return mesh_mass_properties(mesh.vertices, mesh.faces, RHO)


def test_box_equals_mesh_exactly():
    size = [0.3, 0.2, 0.7]
    closed = primitives.box(size, RHO)
    mesh = meshed(trimesh.creation.box(size))
    assert closed.mass == pytest.approx(mesh.mass, rel=1e-13)
    np.testing.assert_allclose(closed.inertia, mesh.inertia, rtol=1e-12, atol=1e-15)


def polygon_shortfall(n: int) -> float:
    """Relative area lost by a regular n-gon inscribed in a circle: 1 - sin(2pi/n) n / 2pi."""
    return 1.0 - np.sin(2 * np.pi / n) * n / (2 * np.pi)


@pytest.mark.parametrize("n", [256, 1024])
def test_cylinder_converges_to_closed_form(n):
    r, h = 0.08, 0.5
    closed = primitives.cylinder(r, h, RHO)
    mesh = meshed(trimesh.creation.cylinder(radius=r, height=h, sections=n))
    tol = 3 * polygon_shortfall(n)  # mass loses 1x, the r^2 moments at most ~2x
    assert mesh.mass == pytest.approx(closed.mass, rel=tol)
    np.testing.assert_allclose(np.diag(mesh.inertia), np.diag(closed.inertia), rtol=tol)
    # and the shortfall is real, so the tolerance is not hiding a wrong formula
    assert mesh.mass < closed.mass


def test_sphere_converges_to_closed_form():
    r = 0.1
    closed = primitives.sphere(r, RHO)
    errors = []
    for sub in (3, 4, 5):
        mesh = meshed(trimesh.creation.icosphere(subdivisions=sub, radius=r))
        errors.append(abs(mesh.mass / closed.mass - 1))
        np.testing.assert_allclose(np.diag(mesh.inertia) / closed.inertia[0, 0], 1,
                                   rtol=3 * errors[-1])
    # O(h^2): each subdivision halves h, so the error drops ~4x
    assert errors[1] < errors[0] / 3 and errors[2] < errors[1] / 3
    assert errors[2] < 1e-3


def test_capsule_converges_to_closed_form():
    r, h = 0.05, 0.3
    closed = primitives.capsule(r, h, RHO)
    mesh = meshed(trimesh.creation.capsule(height=h, radius=r, count=[256, 256]))
    # The caps are UV hemispheres: azimuthal and polar discretisations each lose about
    # one polygon shortfall in area, twice that in second moments.
    tol = 8 * polygon_shortfall(256)
    assert mesh.mass < closed.mass
    assert mesh.mass == pytest.approx(closed.mass, rel=tol)
    np.testing.assert_allclose(np.diag(mesh.inertia), np.diag(closed.inertia), rtol=tol)


def test_capsule_of_zero_length_is_a_sphere():
    np.testing.assert_allclose(primitives.capsule(0.2, 0.0, RHO).inertia,
                               primitives.sphere(0.2, RHO).inertia, rtol=1e-14)


@pytest.mark.parametrize("call", [
    lambda: primitives.box([0.1, 0.0, 0.1], RHO),
    lambda: primitives.cylinder(-0.1, 0.2, RHO),
    lambda: primitives.sphere(float("nan"), RHO),
    lambda: primitives.capsule(0.1, -1.0, RHO),
])
def test_invalid_sizes_raise(call):
    with pytest.raises(ValueError):
        call()


def test_ellipsoid_is_a_scaled_sphere_mesh():
    """A sphere mesh scaled by (a, b, c) is an ellipsoid mesh: same shortfall as the sphere."""
    radii = (0.3, 0.1, 0.05)
    closed = primitives.ellipsoid(radii, RHO)
    ball = trimesh.creation.icosphere(subdivisions=6, radius=1.0)
    ball.apply_scale(radii)
    mesh = meshed(ball)
    # subdivisions=6 loses about 3e-4 of the unit ball's volume (inscribed polyhedron)
    assert mesh.mass == pytest.approx(closed.mass, rel=1e-3)
    np.testing.assert_allclose(np.diag(mesh.inertia), np.diag(closed.inertia), rtol=2e-3)
    np.testing.assert_allclose(closed.com, 0.0)


def test_ellipsoid_with_equal_radii_is_the_sphere():
    a = primitives.ellipsoid((0.2, 0.2, 0.2), RHO)
    b = primitives.sphere(0.2, RHO)
    assert a.mass == pytest.approx(b.mass, rel=1e-15)
    np.testing.assert_allclose(a.inertia, b.inertia, rtol=1e-14)


def test_ellipsoid_refuses_a_zero_radius():
    with pytest.raises(ValueError, match="ellipsoid"):
        primitives.ellipsoid((0.1, 0.0, 0.1), RHO)
