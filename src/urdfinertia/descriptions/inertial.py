"""An inertial as written, in the link frame, before any validation (any format).

`RawInertial` holds arrays, so that an invalid inertial (NaN, negative mass, a
tensor that breaks the triangle inequality) can be compared and reported instead of
crashing [`MassProperties`][urdfinertia.inertia.massprops.MassProperties]'s checks.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from urdfinertia.descriptions.model import Inertial
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
        """The mass is finite and positive."""
        return bool(np.isfinite(self.mass) and self.mass > 0)

    @property
    def com_ok(self) -> bool:
        """Every CoM coordinate is finite."""
        return bool(np.all(np.isfinite(self.com)))

    def mass_properties(self) -> MassProperties | None:
        """The validated value type, or None when the values are not physical."""
        if not (self.mass_ok and self.com_ok and self.diagnosis().valid):
            return None
        try:
            return MassProperties(self.mass, self.com, self.inertia)
        except ValueError:
            return None
