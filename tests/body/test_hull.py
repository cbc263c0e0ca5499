"""hull.py: realizability inside the convex hull (an LP with HiGHS and an exact certificate),
against closed forms: Bhatia and Davis's bound (a distribution on [a, b] with mean mu has
variance at most (b - mu)(mu - a), reached by two point masses at the ends) gives the scale
of a box, or of a tetrahedron along its axis, that just holds a body."""

import json
from pathlib import Path

import numpy as np
import pytest
import trimesh
from scipy.spatial.transform import Rotation

import urdfinertia
from urdfinertia.body.hull import (
    SCALE_RTOL,
    convex_hull,
    hull_scale,
    quadratic_minimum,
)
from urdfinertia.cli import main
from urdfinertia.inertia.polyhedron import mesh_mass_properties
from urdfinertia.inertia.realizable import bounding_ellipsoid, ellipsoid_scale

FIXTURE = Path(__file__).resolve().parents[1] / "data" / "realizable" / "housing.urdf"
#: The regular tetrahedron of circumradius R about the origin; its axis through vertex 0.
R = 0.1
TETRA = np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]]) / np.sqrt(3) * R
AXIS = TETRA[0] / R


def inertia_of(sigma: np.ndarray) -> np.ndarray:
    """The tensor about the CoM of a body with central second moment ``sigma``."""
    return np.trace(sigma) * np.eye(3) - sigma


def axis_body(mass: float, spread: float) -> np.ndarray:
    """Mass spread 0.9 R (RMS) along the axis about the centroid, ``spread`` across."""
    u = np.outer(AXIS, AXIS)
    return inertia_of(mass * (0.81 * R ** 2 * u + spread ** 2 * (np.eye(3) - u)))


def assert_brackets(found, exact: float) -> None:
    """The certified lower end is below the exact scale, the proved upper end above it,
    and the bracket is as narrow as asked (plus round-off)."""
    assert found.decided
    assert found.low <= exact * (1 + 1e-9)
    assert found.high >= exact * (1 - 1e-9)
    assert found.high / found.low - 1 <= SCALE_RTOL * 1.01


@pytest.mark.parametrize("spread", [0.0, 0.1 * R])
def test_tetrahedron_fails_where_its_ellipsoid_passes(spread):
    """Along the axis the tetrahedron spans [-R/3, R] about its centroid: a variance of
    0.81 R^2 needs the scale sqrt(0.81 R^2 / (R R / 3)) = sqrt(2.43). The bounding sphere
    holds the body (mean squared radius 0.81 R^2 + 2 spread^2 < R^2)."""
    inertia = axis_body(2.0, spread)
    assert ellipsoid_scale(2.0, np.zeros(3), inertia, bounding_ellipsoid(TETRA)) < 0.95
    found = hull_scale(2.0, np.zeros(3), inertia, convex_hull(TETRA))
    assert not found.realizable
    bound = np.sqrt(2.43)
    if spread == 0.0:  # all the mass on the axis: the bound is the answer
        assert_brackets(found, bound)
    else:  # spread across can only need more
        assert found.low > 1.5 and found.high >= bound * (1 - 1e-9)


BOX = np.array([[x, y, z] for x in (-0.15, 0.15) for y in (-0.15, 0.15)
                for z in (-0.05, 0.05)])


@pytest.mark.parametrize(("com", "sigma", "exact"), [
    # isotropic 0.005 m^2 in a 0.3 x 0.3 x 0.1 m box: z needs (0.05 s)^2 >= 0.005
    ((0, 0, 0), np.eye(3) * 0.005, np.sqrt(2.0)),
    # CoM 4 cm off-centre along x: (0.15 s - 0.04)(0.15 s + 0.04) >= 0.03
    ((0.04, 0, 0), np.diag([0.03, 0.001, 0.0005]), np.sqrt((0.03 + 0.04 ** 2) / 0.15 ** 2)),
])
def test_box_in_closed_form(com, sigma, exact):
    """A product of two-point measures reaches each axis's bound: the exact scale is the
    largest of the three axes' bounds."""
    found = hull_scale(3.0, np.asarray(com, float), inertia_of(3.0 * sigma),
                       convex_hull(BOX))
    assert_brackets(found, exact)


def test_rotated_and_moved_alike():
    """A rigid motion of geometry and body together leaves the scale unchanged."""
    rot = Rotation.random(random_state=5).as_matrix()
    shift = np.array([0.3, -0.2, 1.0])
    sigma = np.eye(3) * 0.005
    found = hull_scale(3.0, shift, inertia_of(3.0 * rot @ sigma @ rot.T),
                       convex_hull(BOX @ rot.T + shift))
    assert_brackets(found, np.sqrt(2.0))


def _solid(seed: int) -> tuple[np.ndarray, tuple[float, np.ndarray, np.ndarray]]:
    pts = np.random.default_rng(seed).normal(size=(40, 3)) * [0.1, 0.05, 0.2]
    hull = trimesh.Trimesh(pts).convex_hull
    mp = mesh_mass_properties(hull.vertices, hull.faces, 2700.0)
    return np.asarray(hull.vertices), (mp.mass, mp.com, mp.inertia)


@pytest.mark.parametrize("seed", range(4))
def test_a_homogeneous_solid_is_realizable_in_its_hull(seed):
    points, (mass, com, inertia) = _solid(seed)
    found = hull_scale(mass, com, inertia, convex_hull(points))
    assert found.realizable and found.high == 1.0 and found.decided


def test_mass_at_the_vertices_is_realizable():
    """The extreme case: equal point masses at the tetrahedron's vertices (on the boundary
    of what the hull allows)."""
    sigma = 2.0 * TETRA.T @ TETRA / 4
    found = hull_scale(2.0, np.zeros(3), inertia_of(sigma), convex_hull(TETRA))
    assert found.realizable and found.high == 1.0


@pytest.mark.parametrize("seed", range(5))
def test_quadratic_minimum_holds_over_the_hull(seed):
    """No point of the hull (sampled on its faces, edges and inside) is below the minimum
    found, and the minimiser is in the hull."""
    rng = np.random.default_rng(seed)
    points, _ = _solid(seed)
    hull = convex_hull(points)
    a = rng.normal(size=(3, 3))
    a = a + a.T
    beta, gamma = rng.normal(size=3), float(rng.normal())
    pts, vals = quadratic_minimum(a, beta, gamma, hull)
    best = pts[np.argmin(vals)]
    assert hull.contains(best[None], tol=1e-9)[0]
    v = hull.vertices
    tri = v[hull.triangles]
    w = rng.dirichlet(np.ones(3), size=(len(tri), 50))  # 50 points on every triangle
    on_faces = np.einsum("fkj,fjd->fkd", w, tri).reshape(-1, 3)
    inside = rng.dirichlet(np.ones(len(v)), size=20000) @ v
    sample = np.vstack([on_faces, inside])
    q = np.einsum("ij,jk,ik->i", sample, a, sample) + 2 * sample @ beta + gamma
    assert q.min() >= vals.min() - 1e-12


def test_check_names_the_method(capsys):
    """check --realizable hull: the flat base of the fixture (isotropic 0.005 m^2 in a box
    0.1 m high: sqrt(2) in closed form) fails the hull and passes the ellipsoid."""
    hull = {f.link: f for f in urdfinertia.check(FIXTURE, realizable="hull").findings
            if f.code == "not-realizable"}
    plain = {f.link for f in urdfinertia.check(FIXTURE).findings
             if f.code == "not-realizable"}
    assert "base" in hull and "base" not in plain
    assert "convex hull" in hull["base"].message and hull["base"].rule.id == "UI210"
    assert "1.414" in hull["base"].message
    assert main(["check", str(FIXTURE), "--realizable", "hull", "--format", "json"]) == 0
    rows = json.loads(capsys.readouterr().out)["files"][0]["findings"]
    base = [r for r in rows if r["link"] == "base" and r["rule"] == "UI210"]
    assert base and "method: convex hull" in base[0]["message"]


def test_a_compact_body_deep_inside_is_decided():
    """A body 1/40 of the part's size off its centroid (Baxter's gripper bases are such):
    its sigma points prove it with one LP (column generation alone needs about 25 here,
    and left Baxter's undecided after 60)."""
    inertia = inertia_of(2.0 * np.diag([1.0, 2.0, 3.0]) * (R / 40) ** 2)
    found = hull_scale(2.0, np.array([0.01, -0.005, 0.0]), inertia, convex_hull(TETRA))
    assert found.decided and found.realizable and found.high == 1.0
    assert found.lps == 1
