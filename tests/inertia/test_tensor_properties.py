"""Property tests of the validity test and the tensor repair at any magnitude (hypothesis).

:mod:`test_massprops_properties` draws real bodies of ordinary size; here the tensors are
any finite symmetric matrices, over float64's whole range, because the fuzzer found
finite values near its limit (a moment of 1e308) crashing the maths: ``t + t.T``
overflowed and LAPACK answered "Eigenvalues did not converge". Examples are
derandomized: CI and local runs draw the same cases.

Tolerances: a rescaling by a power of two is exact, so a diagnosis must not change under
it (bit for bit, as long as no entry leaves float64's normal range); a rotation changes
round-off only, so moments agree to ``RTOL`` of the largest.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from urdfinertia.inertia.massprops import MassProperties, combine
from urdfinertia.inertia.tensor_repair import MIN_MOMENT_RTOL, REPAIR_MARGIN, repair_tensor
from urdfinertia.inertia.validity import diagnose_tensor, is_valid_tensor

RTOL = 1e-9
#: sums near float64's limit overflow on purpose (``massprops._finite`` then checks each
#: entry): the warning is the point of these inputs, not a finding
pytestmark = pytest.mark.filterwarnings("ignore:overflow encountered:RuntimeWarning")
PROFILE = settings(max_examples=200, derandomize=True, deadline=None,
                   suppress_health_check=[HealthCheck.too_slow])

any_float = st.floats(allow_nan=False, allow_infinity=False)
unit_float = st.floats(-1.0, 1.0)


@st.composite
def symmetric(draw, entries=any_float) -> np.ndarray:
    """Any finite symmetric (3, 3) matrix."""
    a, b, c, d, e, f = (draw(entries) for _ in range(6))
    return np.array([[a, d, e], [d, b, f], [e, f, c]])


@st.composite
def rotations(draw) -> np.ndarray:
    q = np.array(draw(st.tuples(*[unit_float] * 4)))
    norm = float(np.linalg.norm(q))
    assume(norm > 1e-3)
    w, x, y, z = q / norm
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])


@st.composite
def moment_tensors(draw) -> np.ndarray:
    """A rotated diagonal tensor with moments of any sign and ratio, largest positive."""
    m = np.array([draw(st.floats(-1.0, 1.0)), draw(st.floats(-1.0, 1.0)), 1.0])
    m = m * draw(st.floats(1e-6, 1e6))
    r = draw(rotations())
    return r @ np.diag(m) @ r.T


@PROFILE
@given(symmetric())
def test_diagnosis_and_construction_never_fail_on_finite_input(t):
    d = diagnose_tensor(t)
    assert d.finite == bool(np.all(np.isfinite(d.moments)))
    if d.finite:  # moments ascending, and the verdict is a verdict
        assert d.moments[0] <= d.moments[1] <= d.moments[2]
        assert d.valid in (True, False)
    for mass in (1.0, -1.0, 0.0):
        try:
            MassProperties(mass, np.zeros(3), t)
        except ValueError:  # the documented refusal, never another exception
            pass


@PROFILE
@given(moment_tensors(), st.integers(-1000, 1000))
def test_validity_does_not_depend_on_the_unit(t, power):
    """An exact rescaling (a power of two) never changes the verdict or the ratios."""
    scaled = np.ldexp(t, power)
    assume(np.all(np.isfinite(scaled)) and np.all((scaled == 0) | (np.abs(scaled) > 1e-300)))
    a, b = diagnose_tensor(t), diagnose_tensor(scaled)
    assert b.finite
    assert a.valid == b.valid
    assert a.triangle_excess == pytest.approx(b.triangle_excess, abs=1e-12)
    np.testing.assert_allclose(np.ldexp(a.moments, power), b.moments,
                               rtol=RTOL, atol=RTOL * abs(b.moments[2]))


@PROFILE
@given(moment_tensors(), rotations())
def test_validity_does_not_depend_on_the_axes(t, r):
    a, b = diagnose_tensor(t), diagnose_tensor(r @ t @ r.T)
    np.testing.assert_allclose(a.moments, b.moments, rtol=0, atol=RTOL * a.moments[2])
    if abs(a.triangle_excess) > 1e-9 and a.moments[0] / a.moments[2] not in \
            (pytest.approx(0.0, abs=1e-9),):
        assert a.valid == b.valid


@PROFILE
@given(moment_tensors())
def test_repair_is_minimal_valid_and_idempotent(t):
    d = diagnose_tensor(t)
    fixed = repair_tensor(t)
    assert is_valid_tensor(fixed.tensor)
    if d.valid:
        np.testing.assert_array_equal(fixed.tensor, t)
        assert not fixed.changed
    # no moment decreases, the largest two stay, the axes are kept
    np.testing.assert_array_less(fixed.moments_before - RTOL * d.moments[2],
                                 fixed.moments_after)
    assert fixed.moments_after[2] == d.moments[2]
    in_axes = d.axes.T @ fixed.tensor @ d.axes
    np.testing.assert_allclose(in_axes, np.diag(fixed.moments_after), rtol=0,
                               atol=RTOL * d.moments[2])
    # just enough: a moment that moved is at the floor, or lifted to meet A + B >= C
    # with the stated margin
    before, after = fixed.moments_before, fixed.moments_after
    c = after[2]
    for i in (0, 1):
        if after[i] != before[i]:
            lift = c * (1 + REPAIR_MARGIN) - after[1 - i]
            assert after[i] == pytest.approx(MIN_MOMENT_RTOL * c, rel=1e-12) \
                or after[i] == pytest.approx(lift, rel=1e-12), (before, after)
    again = repair_tensor(fixed.tensor)
    assert not again.changed


@PROFILE
@given(moment_tensors(), rotations())
def test_repair_turns_with_the_tensor(t, r):
    d = diagnose_tensor(t)
    assume(abs(d.triangle_excess) > 1e-6)  # not on the boundary
    # two equal smaller moments span a plane: which axis of it is lifted is arbitrary
    assume(d.moments[1] - d.moments[0] > 1e-6 * d.moments[2])
    turned = repair_tensor(r @ t @ r.T).tensor
    np.testing.assert_allclose(turned, r @ repair_tensor(t).tensor @ r.T, rtol=0,
                               atol=1e-7 * np.abs(t).max())


@PROFILE
@given(st.lists(moment_tensors(), min_size=1, max_size=4),
       st.lists(st.floats(1e-3, 1e3), min_size=4, max_size=4))
def test_repaired_parts_combine_into_a_valid_body(tensors, masses):
    """A link assembled from repaired parts is valid (sums of physical bodies are)."""
    bodies = [MassProperties(m, np.full(3, i, dtype=float), repair_tensor(t).tensor)
              for i, (t, m) in enumerate(zip(tensors, masses, strict=False))]
    assert combine(bodies).is_physical()


@pytest.mark.parametrize("value", [1e308, 1.7976931348623157e308, 1e-320, 5e-324])
def test_extreme_diagonal_tensors_are_judged_not_crashed(value):
    d = diagnose_tensor(np.diag([value, value, value]))
    assert d.finite and d.valid
    assert math.isclose(d.moments[2], value)
    assert MassProperties(1.0, np.zeros(3), np.diag([value] * 3)).is_physical()


@PROFILE
@given(st.lists(moment_tensors(), min_size=2, max_size=4),
       st.lists(st.floats(1e-3, 1e3), min_size=4, max_size=4),
       st.lists(st.tuples(unit_float, unit_float, unit_float), min_size=4, max_size=4),
       rotations(), st.tuples(unit_float, unit_float, unit_float))
def test_combine_turns_and_shifts_with_its_parts(tensors, masses, coms, r, shift):
    """Combining then moving rigidly equals moving each part then combining: the link's
    tensor does not depend on the frame its parts were summed in."""
    parts = [MassProperties(m, np.array(c) * 10, repair_tensor(t).tensor)
             for t, m, c in zip(tensors, masses, coms, strict=False)]
    offset = np.array(shift) * 5
    whole = combine(parts).rotated(r).translated(offset)
    moved = combine(p.rotated(r).translated(offset) for p in parts)
    scale = max(masses) * 300 + max(np.abs(t).max() for t in tensors)
    np.testing.assert_allclose(moved.mass, whole.mass, rtol=1e-12)
    np.testing.assert_allclose(moved.com, whole.com, atol=1e-9 * 20)
    np.testing.assert_allclose(moved.inertia, whole.inertia, rtol=0, atol=RTOL * scale)
