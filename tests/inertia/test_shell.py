"""inertia/shell.py: walls and interiors against closed forms and independent references.

References: closed forms written out here (spherical and box shells), the inner parallel
body of a convex polyhedron as the intersection of its face half-spaces moved in by t
(scipy's Qhull, an independent construction), the L-prism and the hollow box as boxes by
hand, and a seeded Monte Carlo estimate for the ellipsoid.
"""

from __future__ import annotations

import numpy as np
import pytest
import trimesh
from scipy.spatial import ConvexHull, HalfspaceIntersection
from scipy.spatial.transform import Rotation

from urdfinertia.inertia import shell
from urdfinertia.inertia.polyhedron import mass_properties_from_integrals, solid_integrals

#: Differences of closed forms and exact polyhedral sums: round-off only.
RTOL = 1e-10


def _tensor(moments: shell.Moments) -> np.ndarray:
    return mass_properties_from_integrals(*moments, 1.0).inertia


def _box_moments(size: np.ndarray) -> tuple[float, np.ndarray]:
    a, b, c = size
    v = a * b * c
    return v, v / 12 * np.array([b * b + c * c, a * a + c * c, a * a + b * b])


def _halfspace_interior(vertices: np.ndarray, faces: np.ndarray, t: float) -> float:
    """Volume of a convex polyhedron's inner parallel body: its face planes moved in by
    t, intersected by Qhull (independent of the vertex offset under test)."""
    tri = vertices[faces]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    n /= np.linalg.norm(n, axis=1)[:, None]
    offset = -np.einsum("ij,ij->i", n, tri[:, 0]) + t  # n.x + offset <= 0 inside
    volume, first, _ = solid_integrals(vertices, faces)
    centre = first / volume  # the centroid: inside a convex body
    inner = HalfspaceIntersection(np.column_stack([n, offset]), centre)
    return float(ConvexHull(inner.intersections).volume)


# --- closed forms -----------------------------------------------------------------------

def test_box_primitive_is_the_difference_of_two_boxes() -> None:
    size, t = np.array([0.1, 0.06, 0.04]), 0.002
    found = shell.box_shell(size, t)
    v_out, i_out = _box_moments(size)
    v_in, i_in = _box_moments(size - 2 * t)
    assert found.wall[0] == pytest.approx(v_out - v_in, rel=RTOL)
    assert found.interior[0] == pytest.approx(v_in, rel=RTOL)
    np.testing.assert_allclose(np.diag(_tensor(found.wall)), i_out - i_in, rtol=RTOL)
    assert found.error == 0


def test_sphere_primitive_against_the_spherical_shell() -> None:
    r, t = 0.05, 0.002
    found = shell.sphere_shell(r, t)
    q = r - t
    assert found.wall[0] == pytest.approx(4 / 3 * np.pi * (r**3 - q**3), rel=RTOL)
    # I = 8 pi / 15 (R^5 - r^5) at unit density
    np.testing.assert_allclose(_tensor(found.wall), 8 * np.pi / 15 * (r**5 - q**5) * np.eye(3),
                               rtol=RTOL, atol=1e-20)


def test_cylinder_primitive_closed_form() -> None:
    r, h, t = 0.03, 0.1, 0.002
    found = shell.cylinder_shell(r, h, t)
    q, k = r - t, h - 2 * t
    assert found.wall[0] == pytest.approx(np.pi * (r * r * h - q * q * k), rel=RTOL)
    izz = np.pi / 2 * (r**4 * h - q**4 * k)
    assert _tensor(found.wall)[2, 2] == pytest.approx(izz, rel=RTOL)


def test_capsule_inner_body_is_the_thinner_capsule() -> None:
    r, h, t = 0.03, 0.08, 0.004
    found = shell.capsule_shell(r, h, t)
    volume = np.pi * (r * r * h + 4 / 3 * r**3) - np.pi * ((r - t) ** 2 * h + 4 / 3 * (r - t) ** 3)
    assert found.wall[0] == pytest.approx(volume, rel=RTOL)


def test_cone_inner_body_against_its_polyhedral_approximation() -> None:
    """A 720-sided pyramid for the cone; its half-space offset is the reference, within
    the polygon's own discretisation (~3e-5 of the area)."""
    r, h, t = 0.04, 0.09, 0.003
    found = shell.cone_shell(r, h, t)
    mesh = trimesh.creation.cone(radius=r, height=h, sections=720)
    v = mesh.vertices - [0, 0, h / 2]  # trimesh: base at z = 0; ours: centred
    reference = _halfspace_interior(v, mesh.faces, t)
    assert found.interior[0] == pytest.approx(reference, rel=2e-4)


def test_ellipsoid_reduces_to_the_sphere_and_converges() -> None:
    exact = shell.sphere_shell(0.05, 0.002)
    found = shell.ellipsoid_shell([0.05, 0.05, 0.05], 0.002)
    assert found.wall[0] == pytest.approx(exact.wall[0], rel=1e-12)
    np.testing.assert_allclose(found.wall[2], exact.wall[2], rtol=1e-12, atol=1e-22)
    coarse = shell.ellipsoid_shell([0.08, 0.05, 0.03], 0.005)
    fine = shell.ellipsoid_shell([0.08, 0.05, 0.03], 0.005, nodes=(320, 640))
    assert coarse.wall[0] == pytest.approx(fine.wall[0], rel=1e-12)
    np.testing.assert_allclose(coarse.wall[2], fine.wall[2], rtol=1e-11, atol=1e-22)


def test_ellipsoid_against_monte_carlo() -> None:
    """A point is in the interior when the ball of radius t around it is inside the
    ellipsoid: u.x + t <= h(u) = |diag(radii) u| for every direction u (1500 of them,
    a Fibonacci sphere). 150 000 seeded points: ~0.7 % standard error on the wall."""
    radii, t = np.array([0.08, 0.05, 0.03]), 0.005
    found = shell.ellipsoid_shell(radii, t)
    rng = np.random.default_rng(7)
    points = rng.uniform(-radii, radii, size=(150_000, 3))
    points = points[np.sum((points / radii) ** 2, axis=1) <= 1]
    k = np.arange(1500) + 0.5
    z = 1 - 2 * k / 1500
    ring = np.sqrt(1 - z * z)
    u = np.column_stack([ring * np.cos(np.pi * (1 + 5**0.5) * k),
                         ring * np.sin(np.pi * (1 + 5**0.5) * k), z])
    support = np.linalg.norm(u * radii, axis=1)
    inner = np.concatenate([np.all(chunk @ u.T + t <= support, axis=1)
                            for chunk in np.array_split(points, 20)])
    box = 8 * np.prod(radii) / 150_000
    wall = box * np.count_nonzero(~inner)
    sigma = box * np.sqrt(np.count_nonzero(~inner))
    assert abs(found.wall[0] - wall) < 4 * sigma
    # and the wall's second moment about x, the same way
    second = box * np.sum(points[~inner, 0] ** 2)
    assert found.wall[2][0, 0] == pytest.approx(second, rel=0.03)


def test_ellipsoid_against_its_mesh() -> None:
    """The tube integral against the vertex offset of a 20 480-face ellipsoid mesh: they
    agree within the mesh's stated error plus its own discretisation (its volume error)."""
    radii, t = np.array([0.08, 0.05, 0.03]), 0.005
    ico = trimesh.creation.icosphere(subdivisions=5, radius=1.0)
    vertices = ico.vertices * radii
    mesh = shell.mesh_shell(vertices, ico.faces, t)
    tube = shell.ellipsoid_shell(radii, t)
    volume = solid_integrals(vertices, ico.faces)[0]
    discretisation = abs(volume / (4 / 3 * np.pi * np.prod(radii)) - 1)
    assert abs(mesh.wall[0] / tube.wall[0] - 1) < mesh.error + discretisation


# --- meshes -----------------------------------------------------------------------------

@pytest.mark.parametrize("seed", [0, 1])
def test_box_mesh_is_exact(seed: int) -> None:
    """Three planes at every corner: the vertex offset is exact, under any rotation."""
    size, t = np.array([0.1, 0.06, 0.04]), 0.002
    rot = Rotation.random(random_state=seed).as_matrix()
    mesh = trimesh.creation.box(extents=size)
    found = shell.mesh_shell(mesh.vertices @ rot.T + [0.3, -0.2, 0.1], mesh.faces, t)
    reference = shell.box_shell(size, t)
    assert found.error == 0
    assert found.wall[0] == pytest.approx(reference.wall[0], rel=RTOL)
    wall = mass_properties_from_integrals(*found.wall, 1.0)
    np.testing.assert_allclose(wall.com, [0.3, -0.2, 0.1], rtol=RTOL)
    np.testing.assert_allclose(rot.T @ wall.inertia @ rot, _tensor(reference.wall),
                               rtol=1e-9, atol=1e-18)


def test_cylinder_mesh_is_exact_against_half_spaces() -> None:
    mesh = trimesh.creation.cylinder(radius=0.03, height=0.1, sections=48)
    found = shell.mesh_shell(mesh.vertices, mesh.faces, 0.002)
    assert found.error == 0
    assert found.interior[0] == pytest.approx(
        _halfspace_interior(mesh.vertices, mesh.faces, 0.002), rel=RTOL)


@pytest.mark.parametrize("subdivisions", [3, 4])
def test_icosphere_within_its_stated_error(subdivisions: int) -> None:
    """Five or six triangles meet at an icosphere's vertices: the least-squares offset is
    not exact, and its stated error must cover the difference to the half-space body."""
    ico = trimesh.creation.icosphere(subdivisions=subdivisions, radius=0.05)
    t = 0.002
    found = shell.mesh_shell(ico.vertices, ico.faces, t)
    reference_wall = ico.volume - _halfspace_interior(ico.vertices, ico.faces, t)
    assert 0 < found.error < 1e-3
    assert abs(found.wall[0] - reference_wall) <= found.error * found.wall[0]
    # and the icosphere's shell is the sphere's within the icosphere's own discretisation
    sphere = shell.sphere_shell(0.05, t)
    solid_error = abs(ico.volume / (4 / 3 * np.pi * 0.05**3) - 1)
    assert abs(found.wall[0] / sphere.wall[0] - 1) < solid_error


def _l_prism(a: float, b: float, notch: tuple[float, float], depth: float,
             ) -> trimesh.Trimesh:
    """The L of [0, a] x [0, b] minus [notch_x, a] x [notch_y, b], extruded along z."""
    nx, ny = notch
    polygon = [(0, 0), (a, 0), (a, ny), (nx, ny), (nx, b), (0, b)]
    from shapely.geometry import Polygon
    return trimesh.creation.extrude_polygon(Polygon(polygon), depth)


def test_concave_l_prism_against_boxes_by_hand() -> None:
    """The wall of an L-prism (one concave edge) as boxes: the inner body is the L with
    every face moved in by t, i.e. two boxes by hand."""
    a, b, nx, ny, d, t = 0.1, 0.08, 0.03, 0.025, 0.04, 0.004
    mesh = _l_prism(a, b, (nx, ny), d)
    found = shell.mesh_shell(mesh.vertices, mesh.faces, t)
    # inner L: [t, a-t] x [t, ny-t] plus [t, nx-t] x [ny-t, b-t], z in [t, d-t]
    h = d - 2 * t
    boxes = [((t, t), (a - t, ny - t)), ((t, ny - t), (nx - t, b - t))]
    v_in = sum((x1 - x0) * (y1 - y0) * h for (x0, y0), (x1, y1) in boxes)
    first_in = sum((x1 - x0) * (y1 - y0) * h * np.array([(x0 + x1) / 2, (y0 + y1) / 2, d / 2])
                   for (x0, y0), (x1, y1) in boxes)
    v_out = a * ny * d + nx * (b - ny) * d
    assert found.error == 0
    assert found.interior[0] == pytest.approx(v_in, rel=RTOL)
    assert found.wall[0] == pytest.approx(v_out - v_in, rel=RTOL)
    np.testing.assert_allclose(found.interior[1], first_in, rtol=RTOL)


def test_hollow_box_mesh_offsets_its_cavity_outward() -> None:
    """A box with a box cavity: the walls grow into the material from both surfaces."""
    outer, cavity, t = np.array([0.1, 0.08, 0.06]), np.array([0.05, 0.04, 0.02]), 0.003
    o, c = trimesh.creation.box(extents=outer), trimesh.creation.box(extents=cavity)
    vertices = np.vstack([o.vertices, c.vertices])
    faces = np.vstack([o.faces, c.faces[:, ::-1] + len(o.vertices)])
    found = shell.mesh_shell(vertices, faces, t)
    interior = np.prod(outer - 2 * t) - np.prod(cavity + 2 * t)
    assert found.interior[0] == pytest.approx(interior, rel=RTOL)
    assert found.wall[0] == pytest.approx(np.prod(outer) - np.prod(cavity) - interior,
                                          rel=RTOL)


# --- walls that do not fit -----------------------------------------------------------------

@pytest.mark.parametrize(("make", "t"), [
    (lambda t: shell.box_shell([0.1, 0.06, 0.04], t), 0.02),
    (lambda t: shell.sphere_shell(0.05, t), 0.05),
    (lambda t: shell.cylinder_shell(0.03, 0.1, t), 0.03),
    (lambda t: shell.cylinder_shell(0.03, 0.01, t), 0.005),
    (lambda t: shell.capsule_shell(0.03, 0.1, t), 0.031),
    (lambda t: shell.cone_shell(0.03, 0.05, t), 0.02),
    (lambda t: shell.ellipsoid_shell([0.08, 0.05, 0.03], t), 0.0113),  # c^2/a = 11.25 mm
    (lambda t: shell.box_shell([0.1, 0.06, 0.04], t), 0.0),
    (lambda t: shell.box_shell([0.1, 0.06, 0.04], t), float("nan")),
])
def test_primitive_walls_too_thick(make, t: float) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(shell.ShellError):
        make(t)


@pytest.mark.parametrize("t", [0.0201, 0.05])
def test_box_mesh_wall_thicker_than_half_the_box(t: float) -> None:
    mesh = trimesh.creation.box(extents=[0.1, 0.06, 0.04])
    with pytest.raises(shell.ShellError, match="thinner than two walls"):
        shell.mesh_shell(mesh.vertices, mesh.faces, t)


def test_l_prism_with_one_thin_leg() -> None:
    """A 10 mm leg cannot hold two 6 mm walls, though the thick leg could."""
    mesh = _l_prism(0.1, 0.08, (0.01, 0.025), 0.04)
    with pytest.raises(shell.ShellError):
        shell.mesh_shell(mesh.vertices, mesh.faces, 0.006)
    assert shell.mesh_shell(mesh.vertices, mesh.faces, 0.004).error == 0


def test_a_wall_overlapping_through_a_pipe_is_caught() -> None:
    """A ring pipe without end faces (torus-like, square section 4 mm wide): a 3 mm
    wall flips no face, but the two sides' offsets cross; the depth check catches it."""
    outer = trimesh.creation.annulus(r_min=0.02, r_max=0.024, height=0.004, sections=64)
    with pytest.raises(shell.ShellError):
        shell.mesh_shell(outer.vertices, outer.faces, 0.003)
    assert shell.mesh_shell(outer.vertices, outer.faces, 0.0015).wall[0] > 0


def test_filled_weights_the_interior() -> None:
    found = shell.box_shell([0.1, 0.06, 0.04], 0.002)
    solid = found.filled(1.0)
    assert solid.mass == pytest.approx(0.1 * 0.06 * 0.04, rel=RTOL)
    assert found.filled(0.2).mass == pytest.approx(found.wall[0] + 0.2 * found.interior[0],
                                                   rel=RTOL)
    with pytest.raises(ValueError):
        found.filled(-0.1)


def test_solid_integrals_agree_with_the_parts() -> None:
    """The wall plus the interior is the solid (a mesh's own integrals)."""
    ico = trimesh.creation.icosphere(subdivisions=2, radius=0.04)
    found = shell.mesh_shell(ico.vertices, ico.faces, 0.003)
    volume, first, second = solid_integrals(ico.vertices, ico.faces)
    assert found.wall[0] + found.interior[0] == pytest.approx(volume, rel=RTOL)
    np.testing.assert_allclose(found.wall[2] + found.interior[2], second, rtol=1e-9)
