"""realizable.py: the pseudo-inertia LMI against closed forms and constructed bodies."""

import numpy as np
import pytest
import trimesh

from urdfinertia.inertia import primitives
from urdfinertia.inertia.massprops import MassProperties, combine
from urdfinertia.inertia.realizable import (
    Ellipsoid,
    bounding_ellipsoid,
    ellipsoid_scale,
    pseudo_inertia,
    realizable_in,
)

RNG = np.random.default_rng(7)


def random_rotation() -> np.ndarray:
    q, r = np.linalg.qr(RNG.normal(size=(3, 3)))
    return q * np.sign(np.diag(r))


def box_corners(size):
    h = np.asarray(size) / 2
    return np.array([[x, y, z] for x in (-h[0], h[0]) for y in (-h[1], h[1])
                     for z in (-h[2], h[2])])


def test_pseudo_inertia_is_the_second_moment_of_point_masses():
    pts = RNG.normal(size=(5, 3))
    masses = RNG.uniform(0.5, 2.0, size=5)
    body = combine([MassProperties(m, p, np.zeros((3, 3)))
                    for m, p in zip(masses, pts, strict=True)])
    lifted = np.hstack([pts, np.ones((5, 1))])
    expected = (lifted * masses[:, None]).T @ lifted
    np.testing.assert_allclose(pseudo_inertia(body.mass, body.com, body.inertia), expected,
                               rtol=1e-12, atol=1e-12)


def test_bounding_ellipsoid_of_a_box_is_root_three_times_its_half_sizes():
    # the minimum ellipsoid of a box is axis-aligned with semi-axes sqrt(3) x half-sizes
    size = np.array([0.1, 0.4, 0.25])
    rot = random_rotation()
    region = bounding_ellipsoid(box_corners(size) @ rot.T + [1.0, -2.0, 0.5])
    np.testing.assert_allclose(region.semi_axes, np.sort(np.sqrt(3) * size / 2), rtol=5e-3)
    np.testing.assert_allclose(region.centre, [1.0, -2.0, 0.5], atol=1e-3 * size.max())


def test_bounding_ellipsoid_holds_every_point():
    pts = RNG.normal(size=(3000, 3)) * [0.02, 0.3, 0.1]
    region = bounding_ellipsoid(pts)
    assert region.radii_squared(pts).max() == pytest.approx(1.0, abs=1e-9)


def test_bounding_ellipsoid_of_a_sphere_mesh_is_the_sphere():
    mesh = trimesh.creation.icosphere(subdivisions=4, radius=0.3)
    # the stopping tolerance bounds the volume: (1 + tol)^2 over the minimum (Todd and
    # Yildirim 2007: (1 + tol)^(d/2) in the lifted dimension d = 4)
    for tol, rtol in ((1e-2, 2e-2), (1e-4, 1e-3)):
        region = bounding_ellipsoid(mesh.vertices, tol=tol)
        np.testing.assert_allclose(region.semi_axes, 0.3, rtol=rtol)
        assert region.volume <= (1 + tol) ** 2 * 4 / 3 * np.pi * 0.3 ** 3


def test_flat_and_tiny_point_sets_still_give_an_ellipsoid():
    flat = bounding_ellipsoid(box_corners([0.2, 0.2, 0.0]))
    assert flat.semi_axes[0] < 1e-6 and flat.semi_axes[2] == pytest.approx(0.1 * np.sqrt(2),
                                                                           rel=5e-3)
    single = bounding_ellipsoid([[1.0, 2.0, 3.0]])
    np.testing.assert_allclose(single.centre, [1.0, 2.0, 3.0])
    with pytest.raises(ValueError):
        bounding_ellipsoid(np.zeros((0, 3)))


@pytest.mark.parametrize("body, expected", [
    # mean of (x/a)^2 over a solid box is 1/3 per axis; the ellipsoid's semi-axes are
    # sqrt(3) a: 3 x 1/9 = 1/3, so the scale is sqrt(1/3)
    (primitives.box([0.1, 0.3, 0.2], 2700.0), np.sqrt(1 / 3)),
    # a solid ball in itself: mean r^2 = 3/5 R^2
    (primitives.sphere(0.2, 1000.0), np.sqrt(3 / 5)),
])
def test_solid_primitives_pass_in_closed_form(body, expected):
    if body.mass == primitives.sphere(0.2, 1000.0).mass:
        region = Ellipsoid(np.zeros(3), np.eye(3) / 0.2 ** 2)
    else:
        region = bounding_ellipsoid(box_corners([0.1, 0.3, 0.2]))
    assert ellipsoid_scale(body.mass, body.com, body.inertia, region) == pytest.approx(
        expected, rel=1e-2)
    assert realizable_in(body.mass, body.com, body.inertia, region)


def test_solid_cylinder_passes_in_its_meshed_bounding_ellipsoid():
    body = primitives.cylinder(0.05, 0.4, 7800.0)
    mesh = trimesh.creation.cylinder(radius=0.05, height=0.4, sections=64)
    scale = ellipsoid_scale(body.mass, body.com, body.inertia, bounding_ellipsoid(mesh.vertices))
    assert scale < 1.0


def test_mass_needed_outside_the_box_fails():
    """A 2 kg link in a 10 cm housing whose tensor needs mass a metre out: fails, and the
    scale is the RMS ellipsoidal radius of the body that does have that tensor."""
    region = bounding_ellipsoid(box_corners([0.1, 0.1, 0.1]))
    # two 1 kg points 1 m either side of the centre: realizable only that far out
    dumbbell = combine([MassProperties(1.0, [s, 0.0, 0.0], np.zeros((3, 3)))
                        for s in (-1.0, 1.0)])
    scale = ellipsoid_scale(dumbbell.mass, dumbbell.com, dumbbell.inertia, region)
    semi = 0.05 * np.sqrt(3)
    assert scale == pytest.approx(1.0 / semi, rel=1e-2)  # the points sit 1/semi radii out
    assert not realizable_in(dumbbell.mass, dumbbell.com, dumbbell.inertia, region)
    # the same tensor with a CoM well inside also fails; a tensor for mass near the faces
    # (not beyond the box) passes
    inside = combine([MassProperties(1.0, [s, 0.0, 0.0], np.zeros((3, 3)))
                      for s in (-0.05, 0.05)])
    assert realizable_in(inside.mass, inside.com, inside.inertia, region)


def test_com_outside_fails_even_with_a_small_tensor():
    region = bounding_ellipsoid(box_corners([0.1, 0.1, 0.1]))
    body = primitives.box([0.01, 0.01, 0.01], 1000.0).translated([0.3, 0.0, 0.0])
    assert ellipsoid_scale(body.mass, body.com, body.inertia, region) > 3.0


def test_scale_is_invariant_under_a_rigid_motion_of_body_and_region():
    body = primitives.box([0.1, 0.3, 0.2], 2700.0)
    pts = box_corners([0.1, 0.3, 0.2])
    rot, shift = random_rotation(), np.array([0.3, -0.1, 2.0])
    region = bounding_ellipsoid(pts)
    a = ellipsoid_scale(body.mass, body.com, body.inertia, region)
    moved = body.rotated(rot).translated(shift)
    # the test itself is exact: the region moved with the body gives the same scale
    same = Ellipsoid(rot @ region.centre + shift, rot @ region.shape @ rot.T)
    assert ellipsoid_scale(moved.mass, moved.com, moved.inertia, same) == pytest.approx(
        a, rel=1e-9)
    # the ellipsoid found for the moved points is the same up to the stopping tolerance
    b = ellipsoid_scale(moved.mass, moved.com, moved.inertia,
                        bounding_ellipsoid(pts @ rot.T + shift))
    assert a == pytest.approx(b, rel=1e-2)


def test_broken_triangle_inequality_is_realizable_nowhere():
    region = Ellipsoid(np.zeros(3), np.eye(3))
    assert ellipsoid_scale(1.0, np.zeros(3), np.diag([0.1, 0.1, 0.3]), region) == np.inf
    assert ellipsoid_scale(0.0, np.zeros(3), np.eye(3) * 0.1, region) == np.inf
