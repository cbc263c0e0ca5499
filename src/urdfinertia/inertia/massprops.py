"""The mass-properties value type and the paper's frame algebra (eqs. 21-23, 43-46).

Pure numpy. A [`MassProperties`][urdfinertia.inertia.massprops.MassProperties] is a rigid body's
mass, its centre of mass and its inertia tensor about that centre of mass, all expressed in one
frame F (the frame the object was built in or moved to). The inertia follows the URDF sign
convention: off-diagonal entries are `-integral(x y dm)` (paper eq. 21/22).

Moving a body between frames is explicit:
[`MassProperties.rotated`][urdfinertia.inertia.massprops.MassProperties.rotated] (`A I A^T`, eq. 23
applied inside eq. 22) and
[`MassProperties.translated`][urdfinertia.inertia.massprops.MassProperties.translated]; bodies
combine with `+` or [`combine`][urdfinertia.inertia.massprops.combine], which applies the
Huygens-Steiner theorem about the common centre of mass (eqs. 43-44).
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from urdfinertia.inertia.validity import (
    SEMIDEFINITE_RTOL,
    SYMMETRY_RTOL,
    is_valid_tensor,
    symmetric_eigh,
    symmetric_eigvalsh,
    symmetric_part,
)


def point_mass_inertia(mass: float, offset: ArrayLike) -> np.ndarray:
    """Inertia of a point mass at `offset` about the origin: `m (|r|^2 E - r r^T)`.

    This is the Huygens-Steiner term of eq. 43.

    Parameters
    ----------
    mass : float
        kg.
    offset : (3,) float
        Where the mass is, m.

    Returns
    -------
    (3, 3) float
        Its inertia about the origin, kg m^2, URDF sign convention.
    """
    r = np.asarray(offset, dtype=np.float64)
    term: np.ndarray = mass * (np.dot(r, r) * _EYE - np.outer(r, r))
    return term


@dataclass(frozen=True, eq=False)
class MassProperties:
    """Mass, centre of mass and central inertia of a body, expressed in one frame F.

    Attributes
    ----------
    mass : float
        kg. Negative only for a cavity (see `negated`).
    com : (3,) float
        Centre of mass in F, m.
    inertia : (3, 3) float
        Inertia about `com` along F's axes, kg m^2, URDF sign convention
        (`inertia[0, 1] == -integral(x y dm)`).
    """

    mass: float
    com: np.ndarray
    inertia: np.ndarray

    def __post_init__(self) -> None:
        mass = float(self.mass)
        com = np.array(self.com, dtype=np.float64).reshape(-1)
        inertia = np.array(self.inertia, dtype=np.float64)
        if com.shape != (3,):
            raise ValueError(f"com must have shape (3,), got {com.shape}")
        if inertia.shape != (3, 3):
            raise ValueError(f"inertia must have shape (3, 3), got {inertia.shape}")
        if not (math.isfinite(mass) and _finite(com) and _finite(inertia)):
            raise ValueError("mass properties must be finite")
        (a00, a01, a02), (a10, a11, a12), (a20, a21, a22) = inertia.tolist()
        scale = max(abs(a00), abs(a01), abs(a02), abs(a10), abs(a11), abs(a12), abs(a20),
                    abs(a21), abs(a22), _TINY)
        if max(abs(a01 - a10), abs(a02 - a20), abs(a12 - a21)) > SYMMETRY_RTOL * scale:
            raise ValueError("inertia tensor must be symmetric")
        inertia = symmetric_part(inertia)
        (s00, s01, s02), (_, s11, s12), (_, _, s22) = inertia.tolist()
        trace = s00 + s11 + s22
        slack = SEMIDEFINITE_RTOL * abs(trace)
        if not math.isfinite(slack):  # entries near float64's limit: the same sum, halved
            slack = 2.0 * SEMIDEFINITE_RTOL * abs(0.5 * s00 + 0.5 * s11 + 0.5 * s22)
        sign = 1.0 if mass >= 0 else -1.0
        if not _surely_semidefinite(sign * s00, sign * s01, sign * s02, sign * s11,
                                    sign * s12, sign * s22, slack):
            eig = symmetric_eigvalsh(inertia)  # near the limit: the test as specified
            if mass >= 0 and eig[0] < -slack:
                raise ValueError("inertia of a positive mass must be positive semi-definite: "
                                 f"{eig}")
            if mass < 0 and eig[-1] > slack:
                raise ValueError(f"inertia of a cavity must be negative semi-definite: {eig}")
        com.setflags(write=False)
        inertia.setflags(write=False)
        object.__setattr__(self, "mass", mass)
        object.__setattr__(self, "com", com)
        object.__setattr__(self, "inertia", inertia)

    @classmethod
    def _derived(cls, mass: float, com: np.ndarray, inertia: np.ndarray) -> MassProperties:
        """A valid body moved rigidly or rescaled: checked for shape and finiteness only.

        For the results of `rotated`, `translated` and `with_mass`: a
        proper rotation, a translation, or scaling mass and tensor by one factor keeps a
        valid body's tensor symmetric and its eigenvalues' signs matched to the mass's
        (up to round-off the symmetrisation removes), so the eigenvalue check of
        construction, the costly part of it, would only repeat itself.
        """
        mass = float(mass)
        com = np.array(com, dtype=np.float64).reshape(-1)
        if com.shape != (3,):
            raise ValueError(f"com must have shape (3,), got {com.shape}")
        inertia = np.asarray(inertia, dtype=np.float64)
        if not (math.isfinite(mass) and _finite(com) and _finite(inertia)):
            raise ValueError("mass properties must be finite")
        inertia = symmetric_part(inertia)  # a new array: nothing else refers to it
        com.setflags(write=False)
        inertia.setflags(write=False)
        body = object.__new__(cls)
        body.__dict__.update(mass=mass, com=com, inertia=inertia)  # frozen: no __setattr__
        return body

    # --- named constructors -------------------------------------------------------
    @classmethod
    def zero(cls) -> MassProperties:
        """The empty body, the neutral element of `+`.

        Returns
        -------
        MassProperties
            Zero mass, CoM at the origin, zero tensor.
        """
        return cls(0.0, np.zeros(3), np.zeros((3, 3)))

    @classmethod
    def from_inertia_about_point(
        cls, mass: float, com: ArrayLike, inertia: ArrayLike, point: ArrayLike
    ) -> MassProperties:
        """A body from an inertia given about `point` (the inverse of `about`).

        Parameters
        ----------
        mass : float
            kg.
        com : (3,) float
            The centre of mass in F, m.
        inertia : (3, 3) float
            The inertia about `point` along F's axes, kg m^2.
        point : (3,) float
            The point `inertia` is given about, m.

        Returns
        -------
        MassProperties
            The body, its inertia moved to the CoM (Huygens-Steiner).
        """
        com = np.asarray(com, dtype=np.float64)
        shift = point_mass_inertia(mass, com - np.asarray(point, dtype=np.float64))
        return cls(mass, com, np.asarray(inertia, dtype=np.float64) - shift)

    # --- frame changes -------------------------------------------------------------
    def rotated(self, rotation: ArrayLike) -> MassProperties:
        """The body rotated by `rotation` about F's origin: `c' = A c`, `I' = A I A^T`.

        Equivalently: the same body expressed in a parent frame whose axes relate to F's
        by `r_parent = A r_F` (eqs. 23-26).

        Parameters
        ----------
        rotation : (3, 3) float
            A proper rotation matrix `A`.

        Returns
        -------
        MassProperties
            The rotated body.

        Raises
        ------
        ValueError
            When `rotation` is not a proper rotation.
        """
        a = _rotation(rotation)
        return MassProperties._derived(self.mass, a @ self.com, a @ self.inertia @ a.T)

    def translated(self, offset: ArrayLike) -> MassProperties:
        """The body moved by `offset`; its central inertia is unchanged.

        Parameters
        ----------
        offset : (3,) float
            The translation, m.

        Returns
        -------
        MassProperties
            The moved body.
        """
        return MassProperties._derived(self.mass,
                                     self.com + np.asarray(offset, dtype=np.float64),
                                     self.inertia)

    def transformed(self, transform: ArrayLike) -> MassProperties:
        """The body under a rigid transform: rotated about F's origin, then translated.

        Parameters
        ----------
        transform : (4, 4) float
            A homogeneous transform (rotation and translation, m).

        Returns
        -------
        MassProperties
            The transformed body.

        Raises
        ------
        ValueError
            When `transform` is not (4, 4) or its rotation part not a proper rotation.
        """
        t = np.asarray(transform, dtype=np.float64)
        if t.shape != (4, 4):
            raise ValueError(f"transform must have shape (4, 4), got {t.shape}")
        # rotated(...).translated(...) without the body in between: the same operations
        # on the same values (the tensor is symmetrised after each step, as there)
        a = _rotation(t[:3, :3])
        inertia = symmetric_part(a @ self.inertia @ a.T)
        return MassProperties._derived(self.mass, a @ self.com + t[:3, 3], inertia)

    def about(self, point: ArrayLike) -> np.ndarray:
        """The inertia tensor about `point` along F's axes (Huygens-Steiner, eq. 43).

        Parameters
        ----------
        point : (3,) float
            The reference point in F, m.

        Returns
        -------
        (3, 3) float
            The inertia about `point`, kg m^2.
        """
        moved: np.ndarray = self.inertia + point_mass_inertia(
            self.mass, self.com - np.asarray(point, dtype=np.float64)
        )
        return moved

    # --- combination ---------------------------------------------------------------
    def __add__(self, other: MassProperties) -> MassProperties:
        if not isinstance(other, MassProperties):
            return NotImplemented
        return combine([self, other])

    def negated(self) -> MassProperties:
        """The same shape as a cavity: negative mass and inertia (removed material).

        Returns
        -------
        MassProperties
            The body with mass and tensor negated; adding it to a solid subtracts it.
        """
        return MassProperties(-self.mass, self.com, -self.inertia)

    def with_mass(self, mass: float) -> MassProperties:
        """The same geometry with its density scaled so that the mass is `mass`.

        Parameters
        ----------
        mass : float
            The new mass, kg.

        Returns
        -------
        MassProperties
            The same CoM, the tensor scaled by `mass / self.mass`.

        Raises
        ------
        ValueError
            When this body's mass is zero.
        """
        if self.mass == 0:
            raise ValueError("cannot rescale a body of zero mass")
        k = float(mass) / self.mass
        return MassProperties._derived(mass, self.com, self.inertia * k)

    # --- analysis --------------------------------------------------------------------
    def principal(self) -> tuple[np.ndarray, np.ndarray]:
        """The principal moments and axes of the central inertia.

        Returns
        -------
        moments : (3,) float
            Ascending, kg m^2.
        axes : (3, 3) float
            The principal axes as columns, right-handed, in F.
        """
        moments, axes = symmetric_eigh(self.inertia)
        if np.linalg.det(axes) < 0:
            axes[:, 2] *= -1
        return moments, axes

    def is_physical(self) -> bool:
        """Whether a positive mass has this tensor.

        Returns
        -------
        bool
            True when mass > 0 and the tensor is valid
            ([`is_valid_tensor`][urdfinertia.inertia.validity.is_valid_tensor]).
        """
        return self.mass > 0 and is_valid_tensor(self.inertia)

    def __repr__(self) -> str:
        d = np.diag(self.inertia)
        return (f"MassProperties(mass={self.mass:.6g}, com={np.round(self.com, 6).tolist()}, "
                f"diag={np.array2string(d, precision=4)})")


def combine(bodies: Iterable[MassProperties]) -> MassProperties:
    """Sum of bodies about their common centre of mass (eqs. 3, 43-44).

    Cavities (negative mass) subtract.

    Parameters
    ----------
    bodies : iterable of MassProperties
        The bodies, all expressed in the same frame.

    Returns
    -------
    MassProperties
        Their sum: total mass, common CoM, inertia about it (the empty body for none).

    Raises
    ------
    ValueError
        When the masses sum to zero and not every body is empty.
    """
    items = list(bodies)
    if not items:
        return MassProperties.zero()
    masses = np.array([b.mass for b in items])
    total = float(masses.sum())
    if total == 0.0:
        if np.all(masses == 0):
            return MassProperties.zero()
        raise ValueError("bodies sum to zero mass")
    coms = np.array([b.com for b in items])
    com = masses @ coms / total
    # the same left-to-right sum as Python's sum() from 0: 0.0 + x is x, bit for bit
    inertia: np.ndarray = sum((b.about(com) for b in items), np.zeros((3, 3)))
    return MassProperties(total, com, inertia)


_EYE = np.eye(3)
_EYE.setflags(write=False)
_ORTHONORMAL_TOLERANCE = 1e-9 + 1e-5 * _EYE
_TINY = float(np.finfo(float).tiny)


def _finite(a: np.ndarray) -> bool:
    """All entries finite (one reduction: a sum is finite only if every term is, and a
    sum that overflows is checked entry by entry)."""
    return math.isfinite(a.sum()) or bool(np.isfinite(a).all())


def _rotation(rotation: ArrayLike) -> np.ndarray:
    a = np.asarray(rotation, dtype=np.float64)
    if a.shape != (3, 3):
        raise ValueError(f"rotation must have shape (3, 3), got {a.shape}")
    # np.allclose(a a^T, E, atol=1e-9) spelt out: the same test at a tenth of the cost
    if not (np.abs(a @ a.T - _EYE) <= _ORTHONORMAL_TOLERANCE).all():
        raise ValueError("rotation must be a proper orthonormal matrix")
    # orthonormal to 1e-9, det(a) is +-1 to ~1e-9: the sign of the triple product is the
    # sign np.linalg.det finds
    (a00, a01, a02), (a10, a11, a12), (a20, a21, a22) = a.tolist()
    if a00 * (a11 * a22 - a12 * a21) - a01 * (a10 * a22 - a12 * a20) \
            + a02 * (a10 * a21 - a11 * a20) < 0:
        raise ValueError("rotation must be a proper orthonormal matrix")
    return a


_SEMIDEFINITE_MARGIN = 1e-12
"""Margin of `_surely_semidefinite`, relative to the tensor's largest entry: far above the
round-off of a 3 x 3 LDL^T factorisation (~1e-15) and of LAPACK's eigenvalues (~1e-14) both, far
below the tolerance itself (1e-9 of the trace).
"""
_SEMIDEFINITE_RANGE = (1e-150, 1e150)
"""Entries outside this range take the eigenvalue test: no underflow or overflow below."""


def _surely_semidefinite(s00: float, s01: float, s02: float, s11: float, s12: float,
                         s22: float, slack: float) -> bool:
    """True when the symmetric tensor's smallest eigenvalue is above `-slack` by a margin
    no round-off can cross, so that `np.linalg.eigvalsh` would find it above `-slack`
    too; False when in doubt (the caller then computes the eigenvalues).

    The tensor shifted by `slack - margin` is factorised as `L D L^T`: all pivots
    positive proves it positive definite up to the factorisation's round-off (backward
    stable for a positive definite matrix), far smaller than the margin.
    """
    scale = max(abs(s00), abs(s01), abs(s02), abs(s11), abs(s12), abs(s22))
    if not _SEMIDEFINITE_RANGE[0] < scale < _SEMIDEFINITE_RANGE[1]:
        return False
    # 3 x the largest entry bounds the spectral norm of a 3 x 3 matrix
    shift = slack - _SEMIDEFINITE_MARGIN * 3.0 * scale
    d0 = s00 + shift
    if not d0 > 0.0:
        return False
    l10 = s01 / d0
    l20 = s02 / d0
    d1 = s11 + shift - l10 * s01
    if not d1 > 0.0:
        return False
    r21 = s12 - l20 * s01
    d2 = s22 + shift - l20 * s02 - r21 * r21 / d1
    return d2 > 0.0  # False for nan (overflow) too
