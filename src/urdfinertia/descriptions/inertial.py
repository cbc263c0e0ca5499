"""An inertial as written, in the link frame, before any validation (any format).

`RawInertial` holds arrays, so that an invalid inertial (NaN, negative mass, a tensor
that breaks the triangle inequality, a mass of 1e307) can be compared and reported instead
of crashing [`MassProperties`][urdfinertia.inertia.massprops.MassProperties]'s checks. Its
`*_ok` tests are the one gate for computing with a written value: finite, and within the
readers' range ([`in_range`][urdfinertia.descriptions.urdf.read.in_range]), which the
readers let through for the linters to judge; past it, products of the maths overflow (a
kept mass of 1e307 did, in `check`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from urdfinertia.descriptions.model import Inertial
from urdfinertia.descriptions.urdf.read import MAX_MAGNITUDE, MIN_MAGNITUDE, in_range
from urdfinertia.inertia.massprops import MassProperties
from urdfinertia.inertia.rotation import rpy_matrix
from urdfinertia.inertia.validity import TensorDiagnosis, diagnose_tensor


@dataclass(frozen=True, eq=False)
class RawInertial:
    """A link's inertial in the link frame, unvalidated.

    Attributes
    ----------
    mass : float
        kg; may be NaN, zero or negative.
    com : (3,) float
        In the link frame, m.
    inertia : (3, 3) float
        About `com` along the link frame's axes, kg m^2.
    """

    mass: float
    com: np.ndarray
    inertia: np.ndarray

    @classmethod
    def from_inertial(cls, inertial: Inertial) -> RawInertial:
        """The inertial as written, in the link frame (its origin's rotation applied).

        Parameters
        ----------
        inertial : Inertial
            An `<inertial>` as read.

        Returns
        -------
        RawInertial
            Its values, unvalidated.
        """
        rot = rpy_matrix(inertial.origin.rpy)
        return cls(float(inertial.mass), np.asarray(inertial.origin.xyz, dtype=np.float64),
                   rot @ inertial.tensor() @ rot.T)

    @classmethod
    def from_mass_properties(cls, mp: MassProperties) -> RawInertial:
        """The values of a validated body.

        Parameters
        ----------
        mp : MassProperties
            In the link frame.

        Returns
        -------
        RawInertial
            The same values.
        """
        return cls(mp.mass, np.array(mp.com), np.array(mp.inertia))

    def diagnosis(self) -> TensorDiagnosis:
        """What is wrong with the tensor, if anything.

        Returns
        -------
        TensorDiagnosis
            Its principal moments, symmetry and triangle-inequality margin.
        """
        return diagnose_tensor(self.inertia)

    @property
    def mass_ok(self) -> bool:
        """Positive, finite and within the readers' range (not subnormal): a mass to
        compute with."""
        return bool(np.isfinite(self.mass) and self.mass > 0 and in_range(float(self.mass)))

    @property
    def com_ok(self) -> bool:
        """Finite and within the readers' range (not subnormal)."""
        return _in_range(self.com)

    @property
    def tensor_in_range(self) -> bool:
        """Every entry finite and within the readers' range (not subnormal)."""
        return _in_range(self.inertia)

    def mass_properties(self) -> MassProperties | None:
        """The validated value type, or None when the values are not physical or not
        within the readers' range."""
        if not (self.mass_ok and self.com_ok and self.tensor_in_range
                and self.diagnosis().valid):
            return None
        try:
            return MassProperties(self.mass, self.com, self.inertia)
        except ValueError:
            return None


def _in_range(values: np.ndarray) -> bool:
    """Every entry zero or finite between the readers' smallest normal and largest
    magnitude ([`in_range`][urdfinertia.descriptions.urdf.read.in_range], elementwise)."""
    a = np.abs(np.asarray(values, dtype=np.float64))
    with np.errstate(invalid="ignore"):
        return bool(np.all((a == 0) | ((a >= MIN_MAGNITUDE) & (a <= MAX_MAGNITUDE))))
