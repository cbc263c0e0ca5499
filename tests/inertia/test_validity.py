"""validity.py: one definition of a valid tensor, the same answer from every caller."""

import numpy as np
import pytest

from urdfinertia.descriptions.inertial import RawInertial
from urdfinertia.inertia.massprops import MassProperties
from urdfinertia.inertia.tensor_repair import repair_tensor
from urdfinertia.inertia.validity import TRIANGLE_RTOL, diagnose_tensor, is_valid_tensor

# A + B - C relative to C, from clearly fine to clearly broken, across the tolerance.
CASES = [
    (np.diag([1.0, 1.0, 1.5]), True),
    (np.diag([1.0, 1.0, 2.0]), True),  # a flat plate: A + B = C exactly
    (np.diag([1.0, 1.0, 2.0 * (1 + 0.5 * TRIANGLE_RTOL)]), True),  # round-off
    (np.diag([1.0, 1.0, 2.0 + 2e-9]), False),  # 1e-9 of C: MuJoCo refuses it
    (np.diag([1.0, 1.0, 2.5]), False),
    (np.diag([0.0, 1.0, 1.0]), False),  # not positive definite
]


@pytest.mark.parametrize(("tensor", "valid"), CASES)
def test_every_caller_decides_alike(tensor, valid):
    """MassProperties.is_physical, check's diagnosis and --repair-only agree, case by case."""
    assert is_valid_tensor(tensor) is valid
    assert diagnose_tensor(tensor).valid is valid
    assert MassProperties(2.0, np.zeros(3), tensor).is_physical() is valid
    assert RawInertial(2.0, np.zeros(3), tensor).diagnosis().valid is valid
    repaired = repair_tensor(tensor)
    assert repaired.changed is (not valid)
    assert is_valid_tensor(repaired.tensor)


def test_the_rule_holds_in_any_orientation(rng):
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    for tensor, valid in CASES:
        assert is_valid_tensor(q @ tensor @ q.T) is valid


def test_non_finite_and_negative_mass_are_not_physical():
    assert not is_valid_tensor(np.diag([np.nan, 1.0, 1.0]))
    assert not RawInertial(1.0, np.zeros(3), np.diag([np.nan, 1.0, 1.0])).diagnosis().valid
    assert not MassProperties(0.0, np.zeros(3), np.zeros((3, 3))).is_physical()
