"""Property tests of :mod:`urdfinertia.inertia.massprops` on random bodies (hypothesis).

Bodies are built from random boxes (mass, half extents, pose), so every input is a real
rigid body. Examples are derandomized: CI and local runs draw the same cases.

Tolerances: the quantities compared are sums and products of O(10) float64 terms of
magnitude up to ``SCALE = max(mass) * max(length)^2``; each step loses a few ulps, so
agreement is asserted to ``RTOL = 1e-9`` of that scale (a million ulps of headroom, yet
far below any physically meaningful difference).
"""

from __future__ import annotations

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from urdfinertia.inertia.massprops import MassProperties, combine, point_mass_inertia

RTOL = 1e-9

PROFILE = settings(max_examples=150, derandomize=True, deadline=None,
                   suppress_health_check=[HealthCheck.too_slow])

masses = st.floats(min_value=1e-3, max_value=1e3)
lengths = st.floats(min_value=1e-3, max_value=10.0)
coords = st.floats(min_value=-10.0, max_value=10.0)
vectors = st.tuples(coords, coords, coords).map(np.array)


@st.composite
def rotations(draw) -> np.ndarray:
    """A uniformly distributed proper rotation from a random unit quaternion."""
    q = np.array(draw(st.tuples(*[st.floats(-1.0, 1.0)] * 4)))
    norm = np.linalg.norm(q)
    if norm < 1e-3:
        q, norm = np.array([1.0, 0.0, 0.0, 0.0]), 1.0
    w, x, y, z = q / norm
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])


@st.composite
def boxes(draw) -> MassProperties:
    """A solid box of random mass and size, rotated and moved anywhere."""
    m = draw(masses)
    a, b, c = (draw(lengths) for _ in range(3))
    central = m / 12.0 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])
    body = MassProperties(m, np.zeros(3), central)
    return body.rotated(draw(rotations())).translated(draw(vectors))


def scale(*bodies: MassProperties) -> float:
    """Magnitude of the tensors involved (see module docstring)."""
    return max(abs(b.mass) for b in bodies) * 400.0  # |r| <= 10*sqrt(3) + box size


def assert_physical(body: MassProperties) -> None:
    """Positive mass, symmetric, positive definite, triangle inequality."""
    assert body.mass > 0
    np.testing.assert_array_equal(body.inertia, body.inertia.T)
    moments = np.linalg.eigvalsh(body.inertia)
    assert moments[0] > 0, moments
    assert moments[0] + moments[1] >= moments[2] * (1 - RTOL), moments
    assert body.is_physical()


@PROFILE
@given(boxes(), rotations())
def test_principal_moments_invariant_under_rotation(body, rot):
    before, _ = body.principal()
    after, axes = body.rotated(rot).principal()
    np.testing.assert_allclose(after, before, rtol=0, atol=RTOL * scale(body))
    np.testing.assert_allclose(np.linalg.det(axes), 1.0, atol=1e-12)  # right-handed


@PROFILE
@given(boxes(), rotations(), vectors)
def test_rotation_and_translation_keep_mass_and_trace(body, rot, offset):
    moved = body.rotated(rot).translated(offset)
    assert moved.mass == body.mass
    np.testing.assert_allclose(np.trace(moved.inertia), np.trace(body.inertia),
                               rtol=RTOL)
    np.testing.assert_allclose(moved.com, rot @ body.com + offset, atol=RTOL * 20)


@PROFILE
@given(boxes(), boxes(), boxes())
def test_sum_is_associative_and_commutative(a, b, c):
    left = (a + b) + c
    right = a + (b + c)
    swapped = c + (b + a)
    tol = RTOL * scale(a, b, c)
    for other in (right, swapped):
        np.testing.assert_allclose(other.mass, left.mass, rtol=RTOL)
        np.testing.assert_allclose(other.com, left.com, atol=RTOL * 20)
        np.testing.assert_allclose(other.inertia, left.inertia, atol=tol)
    flat = combine([a, b, c])
    np.testing.assert_allclose(flat.inertia, left.inertia, atol=tol)


@PROFILE
@given(boxes(), boxes())
def test_sum_equals_sum_of_inertias_about_any_point(a, b):
    """Huygens-Steiner: about a common point, inertias simply add (eq. 43)."""
    total = a + b
    for point in (np.zeros(3), total.com, a.com):
        np.testing.assert_allclose(total.about(point), a.about(point) + b.about(point),
                                   atol=RTOL * scale(a, b))


@PROFILE
@given(boxes(), vectors)
def test_parallel_axis_round_trip(body, point):
    about = body.about(point)
    back = MassProperties.from_inertia_about_point(body.mass, body.com, about, point)
    np.testing.assert_allclose(back.inertia, body.inertia, atol=RTOL * scale(body))
    shift = point_mass_inertia(body.mass, body.com - point)
    np.testing.assert_allclose(about - shift, body.inertia, atol=RTOL * scale(body))
    # about the centre of mass itself the shift vanishes exactly
    np.testing.assert_array_equal(body.about(body.com), body.inertia)


@PROFILE
@given(st.lists(boxes(), min_size=1, max_size=6), rotations(), vectors)
def test_every_result_is_positive_definite(bodies, rot, offset):
    for body in bodies:
        assert_physical(body)
        assert_physical(body.rotated(rot))
        assert_physical(body.translated(offset))
        assert_physical(body.with_mass(body.mass * 2.5))
    assert_physical(combine(bodies))
    moments = np.linalg.eigvalsh(combine(bodies).about(offset))
    assert moments[0] > 0


@PROFILE
@given(boxes(), boxes())
def test_cavity_subtraction_undoes_addition(a, b):
    """(a + b) - b == a: removing material is the inverse of adding it."""
    total = a + b
    back = combine([total, b.negated()])
    tol = RTOL * scale(a, b) * (total.mass / a.mass)  # cancellation loses mass ratio digits
    np.testing.assert_allclose(back.mass, a.mass, rtol=1e-9 * total.mass / a.mass)
    np.testing.assert_allclose(back.inertia, a.inertia, atol=tol)
