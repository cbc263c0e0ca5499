"""winding.py against closed forms, and its three evaluations against each other.

Oracles independent of the module: a point inside a closed outward surface has winding
number 1 and one outside 0; a square of half side ``a`` seen from distance ``d`` on its
axis subtends ``4 arcsin(a^2 / (a^2 + d^2))`` sr; a spherical cap of polar angle ``t``
subtends ``2 pi (1 - cos t)`` sr from the sphere's centre.
"""

import numpy as np
import pytest
import trimesh

from urdfinertia.mesh.repair import winding
from urdfinertia.mesh.repair.winding import (
    RayCounter,
    closed_winding_numbers,
    solid_angle_winding_numbers,
    winding_numbers,
)

EVALUATIONS = [winding_numbers, solid_angle_winding_numbers]


def shapes():
    box = trimesh.creation.box([1.0, 2.0, 0.5])
    yield "box", box  # faces parallel to the axes: grazing rays are likely
    yield "icosphere", trimesh.creation.icosphere(subdivisions=2, radius=0.7)
    yield "annulus", trimesh.creation.annulus(0.3, 0.6, 0.4, sections=24)
    # long thin faces across the ray: the grid hands each point many candidates
    yield "cylinder", trimesh.creation.cylinder(0.1, 3.0, sections=200)


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
    slow = solid_angle_winding_numbers(points, v, faces)
    inside_fast = np.abs(fast) > 0.5
    inside_slow = np.abs(slow) > 0.5
    np.testing.assert_array_equal(inside_fast[:300], inside_slow[:300])
    # off the surface the values are the same integers (+1 inside, -1 inside an inverted one)
    np.testing.assert_allclose(fast[:300], np.round(slow[:300]), atol=1e-9)
    assert inside_slow[:300].any() and (~inside_slow[:300]).any()


@pytest.mark.parametrize("evaluate", EVALUATIONS)
@pytest.mark.parametrize("name, mesh", list(shapes()))
def test_closed_surface_is_one_inside_and_zero_outside(evaluate, name, mesh, rng):
    v, f = mesh.vertices, mesh.faces
    lo, hi = v.min(axis=0), v.max(axis=0)
    points = rng.uniform(lo - 0.3, hi + 0.3, size=(400, 3))
    inside = mesh.contains(points)  # trimesh's own ray test, a third implementation
    w = evaluate(points, v, f)
    # 1e-9: round-off of a sum of a few hundred solid angles, far from the surface
    np.testing.assert_allclose(w, inside.astype(float), atol=1e-9)
    assert inside.any() and (~inside).any()


def _square(a: float) -> tuple[np.ndarray, np.ndarray]:
    v = np.array([[-a, -a, 0.0], [a, -a, 0.0], [a, a, 0.0], [-a, a, 0.0]])
    return v, np.array([[0, 1, 2], [0, 2, 3]])


@pytest.mark.parametrize("evaluate", EVALUATIONS)
@pytest.mark.parametrize("d", [0.1, 0.5, 1.0, 3.0])
def test_open_square_on_its_axis(evaluate, d):
    a = 0.4
    v, f = _square(a)
    expected = 4.0 * np.arcsin(a * a / (a * a + d * d)) / (4.0 * np.pi)
    w = evaluate(np.array([[0.0, 0.0, -d], [0.0, 0.0, d]]), v, f)
    # the normal points to +z: behind it (z < 0) the solid angle counts positive
    np.testing.assert_allclose(w, [expected, -expected], rtol=1e-12)


@pytest.mark.parametrize("evaluate", EVALUATIONS)
@pytest.mark.parametrize("polar_deg", [30.0, 90.0, 135.0])
def test_spherical_cap_from_the_centre(evaluate, polar_deg):
    sphere = trimesh.creation.uv_sphere(radius=1.0, count=[64, 64])
    v = sphere.vertices
    # whole latitude bands: every corner above the cut, so the rim is one planar ring
    keep = v[sphere.faces][:, :, 2].min(axis=1) >= np.cos(np.radians(polar_deg))
    f = sphere.faces[keep]
    # the triangulated cap's rim is the polygon through the rim vertices: its polar angle
    # is that of the kept faces' lowest vertex, exactly (the rim is planar)
    rim = v[np.unique(f)][:, 2].min()
    expected = 2.0 * np.pi * (1.0 - rim) / (4.0 * np.pi)
    w = evaluate(np.zeros((1, 3)), v, f)
    # the polygonal cap subtends the spherical one less the slivers between the chords
    # and the sphere: 64 sections, relative 1e-3
    np.testing.assert_allclose(w, [expected], rtol=1e-3)


def test_compiled_equals_numpy_on_an_open_surface(rng):
    sphere = trimesh.creation.icosphere(subdivisions=3)
    f = sphere.faces[rng.random(len(sphere.faces)) > 0.2]  # many holes
    points = rng.uniform(-1.5, 1.5, size=(500, 3))
    # both sum the same solid angles: equal to round-off
    np.testing.assert_allclose(winding_numbers(points, sphere.vertices, f),
                               solid_angle_winding_numbers(points, sphere.vertices, f),
                               atol=1e-12)


@pytest.mark.parametrize("name, mesh", list(shapes()))
def test_grid_and_every_face_count_the_same(name, mesh, rng, monkeypatch):
    v, f = mesh.vertices, mesh.faces
    lo, hi = v.min(axis=0), v.max(axis=0)
    points = np.concatenate([rng.uniform(lo - 0.2, hi + 0.2, size=(500, 3)), v])
    monkeypatch.setattr(winding, "BRUTE_PAIRS", 0)  # the grid, however few the pairs
    monkeypatch.setattr(winding, "GRID_SHARE", np.inf)  # always the grid's candidates
    grid = RayCounter(v, f)(points, exact_on_graze=False)
    monkeypatch.setattr(winding, "GRID_SHARE", -1.0)  # always every face
    brute = RayCounter(v, f)(points, exact_on_graze=False)
    np.testing.assert_array_equal(grid, brute)  # the same pairs, the same arithmetic
    monkeypatch.setattr(winding, "CHUNK", 50)  # many small chunks
    np.testing.assert_array_equal(RayCounter(v, f)(points, exact_on_graze=False), brute)


@pytest.mark.parametrize("name, mesh", list(shapes()))
@pytest.mark.parametrize("exact", [False, True])
@pytest.mark.parametrize("brute_pairs", [0, 10**9])
def test_only_counts_those_points_as_a_call_on_all_does(name, mesh, exact, brute_pairs, rng,
                                                        monkeypatch):
    v, f = mesh.vertices, mesh.faces
    lo, hi = v.min(axis=0), v.max(axis=0)
    # points on the vertices graze; a far point widens the slack of every point's test
    points = np.concatenate([[hi + 50.0], rng.uniform(lo - 0.2, hi + 0.2, size=(400, 3)),
                             v[:60]])
    only = rng.random(len(points)) < 0.3
    only[0] = False
    monkeypatch.setattr(winding, "BRUTE_PAIRS", brute_pairs)
    full = RayCounter(v, f)(points, exact_on_graze=exact)
    part = RayCounter(v, f)(points, exact_on_graze=exact, only=only)
    if exact:  # grazing points go to libigl, whose last bit depends on the batch
        np.testing.assert_allclose(part[only], full[only], rtol=0, atol=1e-12)
        counted = (full == np.round(full)) & only
        np.testing.assert_array_equal(part[counted], full[counted])
    else:
        np.testing.assert_array_equal(part[only], full[only])
    assert not part[~only].any()
    none = RayCounter(v, f)(points, only=np.zeros(len(points), dtype=bool))
    assert none.shape == (len(points),) and not none.any()


def test_empty_inputs():
    v, f = _square(1.0)
    assert winding_numbers(np.zeros((0, 3)), v, f).shape == (0,)
    assert closed_winding_numbers(np.zeros((2, 3)), v, np.zeros((0, 3), int)).tolist() == [0, 0]


def test_kept_grid_serves_wider_calls(rng):
    mesh = trimesh.creation.annulus(0.3, 0.6, 0.4, sections=24)
    near = rng.uniform(-0.7, 0.7, size=(300, 3))
    far = rng.uniform(-7.0, 7.0, size=(300, 3))  # a wider slack than the first call's
    counter = RayCounter(mesh.vertices, mesh.faces)
    for points in (near, far, near):
        fresh = RayCounter(mesh.vertices, mesh.faces)(points, exact_on_graze=False)
        np.testing.assert_array_equal(counter(points, exact_on_graze=False), fresh)
