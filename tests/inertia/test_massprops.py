"""massprops.py: the value type and the paper's frame algebra."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from urdfinertia.inertia import primitives
from urdfinertia.inertia.massprops import MassProperties, combine, point_mass_inertia


def random_body(rng) -> MassProperties:
    a = rng.uniform(0.05, 1.0, 3)
    r = Rotation.random(random_state=int(rng.integers(1 << 31))).as_matrix()
    return primitives.box(a, rng.uniform(100, 8000)).rotated(r).translated(rng.normal(size=3))


def test_principal_moments_invariant_under_rotation(rng):
    body = random_body(rng)
    m0, _ = body.principal()
    for _ in range(20):
        r = Rotation.random(random_state=int(rng.integers(1 << 31))).as_matrix()
        m1, _ = body.rotated(r).principal()
        np.testing.assert_allclose(m1, m0, rtol=1e-12)


def test_translate_and_back_round_trip(rng):
    body = random_body(rng)
    d = rng.normal(size=3) * 5
    back = body.translated(d).translated(-d)
    np.testing.assert_allclose(back.com, body.com, atol=1e-14)
    np.testing.assert_array_equal(back.inertia, body.inertia)


def test_about_point_round_trip(rng):
    body = random_body(rng)
    p = rng.normal(size=3)
    again = MassProperties.from_inertia_about_point(body.mass, body.com, body.about(p), p)
    np.testing.assert_allclose(again.inertia, body.inertia, rtol=1e-10, atol=1e-12)


def test_parallel_axis_term_matches_definition():
    # a point mass at (1, 2, 0): ixx = m y^2, iyy = m x^2, ixy = -m x y (URDF sign)
    i = point_mass_inertia(2.0, [1.0, 2.0, 0.0])
    assert i[0, 0] == pytest.approx(8.0)
    assert i[1, 1] == pytest.approx(2.0)
    assert i[0, 1] == pytest.approx(-4.0)
    assert i[2, 2] == pytest.approx(10.0)


@pytest.mark.parametrize("splits", [(2, 1, 1), (2, 3, 4), (5, 2, 3)])
def test_box_split_into_parts_sums_to_whole(splits):
    size = np.array([0.3, 0.2, 0.5])
    density = 2700.0
    whole = primitives.box(size, density).translated([0.1, -0.2, 0.3])
    cell = size / np.array(splits)
    parts = []
    for idx in np.ndindex(*splits):
        centre = -size / 2 + cell * (np.array(idx) + 0.5) + [0.1, -0.2, 0.3]
        parts.append(primitives.box(cell, density).translated(centre))
    total = combine(parts)
    assert total.mass == pytest.approx(whole.mass, rel=1e-12)
    np.testing.assert_allclose(total.com, whole.com, atol=1e-14)
    np.testing.assert_allclose(total.inertia, whole.inertia, rtol=1e-10, atol=1e-14)


def test_add_is_combine_and_order_free(rng):
    a, b, c = (random_body(rng) for _ in range(3))
    left = (a + b) + c
    right = a + (b + c)
    np.testing.assert_allclose(left.inertia, right.inertia, rtol=1e-10)
    np.testing.assert_allclose(combine([c, a, b]).com, left.com, rtol=1e-12)


def test_cavity_gives_hollow_box():
    # hollow box = outer - inner, against the closed form of the difference
    outer, inner = np.array([0.4, 0.3, 0.2]), np.array([0.3, 0.2, 0.1])
    rho = 1000.0
    hollow = primitives.box(outer, rho) + primitives.box(inner, rho).negated()
    m = rho * (outer.prod() - inner.prod())
    assert hollow.mass == pytest.approx(m)
    ixx = rho / 12 * (outer.prod() * (outer[1] ** 2 + outer[2] ** 2)
                      - inner.prod() * (inner[1] ** 2 + inner[2] ** 2))
    assert hollow.inertia[0, 0] == pytest.approx(ixx)


def test_rotation_sign_convention_of_products():
    # A rod along x tilted by +pitch points its +x end to -z: integral(x z dm) < 0, so the
    # URDF product ixz = -integral(x z dm) must be positive.
    rod = primitives.box([1.0, 0.01, 0.01], 1000.0)
    tilted = rod.rotated(Rotation.from_euler("y", 0.3).as_matrix())
    assert tilted.inertia[0, 2] > 0


@pytest.mark.parametrize(
    "mass, inertia, match",
    [
        (1.0, [[1, 0.5, 0], [0, 1, 0], [0, 0, 1]], "symmetric"),
        (1.0, np.diag([1.0, 1.0, -1.0]), "semi-definite"),
        (float("nan"), np.eye(3), "finite"),
        (-1.0, np.eye(3), "cavity"),
    ],
)
def test_validation_at_construction(mass, inertia, match):
    with pytest.raises(ValueError, match=match):
        MassProperties(mass, np.zeros(3), inertia)


def test_is_physical_detects_triangle_inequality():
    assert MassProperties(1.0, np.zeros(3), np.diag([1.0, 1.0, 1.5])).is_physical()
    assert not MassProperties(1.0, np.zeros(3), np.diag([1.0, 1.0, 2.5])).is_physical()


def test_values_are_read_only():
    body = MassProperties(1.0, np.zeros(3), np.eye(3))
    with pytest.raises(ValueError):
        body.com[0] = 1.0


def _accepted_by_eigenvalues(mass: float, inertia: np.ndarray) -> bool:
    """The definiteness rule as specified: LAPACK's eigenvalues against the slack."""
    sym = 0.5 * (inertia + inertia.T)
    eig = np.linalg.eigvalsh(sym)
    slack = 1e-9 * abs(float(np.trace(sym)))
    return bool(eig[0] >= -slack) if mass >= 0 else bool(eig[-1] <= slack)


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_definiteness_check_agrees_with_the_eigenvalues_near_the_limit(rng, sign):
    """The fast factorisation path must accept exactly what eigvalsh accepts."""
    from scipy.spatial.transform import Rotation

    for k in range(3000):
        r = Rotation.random(random_state=int(rng.integers(1 << 31))).as_matrix()
        scale = 10.0 ** rng.uniform(-12, 3)
        moments = rng.uniform(0, 1, 3) * scale
        trace = moments.sum()
        # the smallest moment at, just inside or just outside -1e-9 trace, or far away
        edge = -1e-9 * trace * (1 + rng.choice([-1e-3, -1e-7, 0.0, 1e-7, 1e-3, -0.5, 2.0]))
        if k % 4 == 0:
            moments[0] = edge
        elif k % 4 == 1:
            moments[0] = 0.0
        inertia = sign * (r @ np.diag(moments) @ r.T)
        expected = _accepted_by_eigenvalues(sign, inertia)
        try:
            MassProperties(sign, np.zeros(3), inertia)
            accepted = True
        except ValueError:
            accepted = False
        assert accepted == expected, (sign, moments)


def test_transformed_is_rotated_then_translated_bit_for_bit(rng):
    body = random_body(rng)
    for _ in range(50):
        r = Rotation.random(random_state=int(rng.integers(1 << 31))).as_matrix()
        t = np.eye(4)
        t[:3, :3] = r
        t[:3, 3] = rng.normal(size=3)
        fused = body.transformed(t)
        steps = body.rotated(r).translated(t[:3, 3])
        assert fused.mass == steps.mass
        np.testing.assert_array_equal(fused.com, steps.com)
        np.testing.assert_array_equal(fused.inertia, steps.inertia)


def test_improper_or_skewed_rotations_are_refused():
    body = MassProperties(1.0, np.zeros(3), np.eye(3))
    with pytest.raises(ValueError, match="proper orthonormal"):
        body.rotated(np.diag([1.0, 1.0, -1.0]))
    with pytest.raises(ValueError, match="proper orthonormal"):
        body.rotated(np.diag([1.0, 1.0, 1.001]))
