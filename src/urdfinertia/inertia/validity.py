"""The one definition of a physically valid inertia tensor, with every tolerance it uses.

Pure numpy. A rigid body's central inertia is symmetric, positive definite, and its
principal moments `A <= B <= C` meet the triangle inequality `A + B >= C` (each moment
is `integral(r_perp^2 dm)`, and `A + B - C = 2 integral(z^2 dm) >= 0` along C's axis).
MuJoCo refuses a body breaking either, with no tolerance (measured with mujoco 3: a
violation of 1e-12 relative is already refused), so the triangle test here allows round-off
only: `diag(1, 1, 2 + 2e-9)` is invalid everywhere (`MassProperties.is_physical`,
`check`, `fix --repair-only`, the report), because a simulator refuses it.

Two weaker notions live here too, so that no other module defines a tolerance:
`SYMMETRY_RTOL` (an asymmetry larger than this is not round-off) and
`SEMIDEFINITE_RTOL`, the slack of [`MassProperties`][urdfinertia.inertia.massprops.MassProperties]'
construction check, which admits the semi-definite tensors of intermediate bodies (a point
mass, a flat plate, a cavity) that are not themselves simulated.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

TRIANGLE_RTOL = 1e-12
"""A triangle-inequality excess `(C - A - B) / C` above this is a violation. Round-off of an
eigen-decomposition is ~1e-16; MuJoCo refuses anything above zero.
"""
SYMMETRY_RTOL = 1e-9
"""An entry asymmetry `max|I - I^T| / max|I|` above this is "not symmetric" (also the construction
check of `MassProperties`).
"""
SEMIDEFINITE_RTOL = 1e-9
"""Slack of the semi-definiteness test at construction, as a fraction of the trace."""
PLACEHOLDER_TINY = 1e-6
"""Placeholder magnitudes: a diagonal of all ones or of tiny equal values, no products."""


#: Tensors whose largest entry lies outside this range are scaled by a power of two (exact)
#: before their eigen-decomposition: ``t + t.T`` and LAPACK's iterations would overflow or
#: underflow (a finite 1e308 entry gave "Eigenvalues did not converge").
EIGEN_RANGE = (2.0 ** -500, 2.0 ** 500)


def symmetric_part(t: np.ndarray) -> np.ndarray:
    """``0.5 * (t + t.T)``; where that overflows (finite entries near float64's limit),
    halved first. Halving first everywhere would lose the last bit of subnormals."""
    with np.errstate(over="ignore"):  # an overflow is what the test below catches
        sym: np.ndarray = 0.5 * (t + t.T)
        if not math.isfinite(sym.sum()) and np.isfinite(t).all():
            sym = 0.5 * t + 0.5 * t.T
    return sym


def symmetric_eigh(sym: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``np.linalg.eigh`` of a finite symmetric (3, 3) tensor at any magnitude.

    Outside `EIGEN_RANGE` the tensor is scaled by a
    power of two (exact) and the
    moments scaled back; a moment beyond float64's range comes back infinite.
    """
    scale = float(np.abs(sym).max())
    if scale == 0.0 or EIGEN_RANGE[0] <= scale <= EIGEN_RANGE[1]:
        moments, axes = np.linalg.eigh(sym)
        return moments, axes
    k = math.frexp(scale)[1]
    scaled, axes = np.linalg.eigh(np.ldexp(sym, -k))
    with np.errstate(over="ignore"):
        moments = np.ldexp(scaled, k)
    return moments, axes


def symmetric_eigvalsh(sym: np.ndarray) -> np.ndarray:
    """``np.linalg.eigvalsh`` of a finite symmetric (3, 3) tensor at any magnitude (as
    `symmetric_eigh`)."""
    scale = float(np.abs(sym).max())
    if scale == 0.0 or EIGEN_RANGE[0] <= scale <= EIGEN_RANGE[1]:
        moments: np.ndarray = np.linalg.eigvalsh(sym)
        return moments
    k = math.frexp(scale)[1]
    with np.errstate(over="ignore"):
        scaled: np.ndarray = np.ldexp(np.linalg.eigvalsh(np.ldexp(sym, -k)), k)
    return scaled


def as_tensor(inertia: ArrayLike) -> np.ndarray:
    """`inertia` as a float (3, 3) array.

    Parameters
    ----------
    inertia : (3, 3) array_like
        An inertia tensor.

    Returns
    -------
    (3, 3) float
        The same values, as float64.

    Raises
    ------
    ValueError
        When the shape is not (3, 3).
    """
    t = np.asarray(inertia, dtype=np.float64)
    if t.shape != (3, 3):
        raise ValueError(f"inertia must have shape (3, 3), got {t.shape}")
    return t


@dataclass(frozen=True, eq=False)
class TensorDiagnosis:
    """What is wrong with a (3, 3) inertia tensor, if anything.

    Attributes
    ----------
    finite : bool
        Every entry and every principal moment is finite (a finite tensor of entries
        near float64's limit can have moments beyond it). When False the other fields
        are NaN.
    asymmetry : float
        `max|I - I^T| / max|I|` (0 for a URDF tensor, which is symmetric by construction).
    moments : (3,) float
        Principal moments of the symmetric part, ascending, kg m^2.
    axes : (3, 3) float
        Principal axes as columns, matching `moments`.
    triangle_excess : float
        `(C - A - B) / C`; positive means the triangle inequality is broken by that
        fraction of the largest moment.
    """

    finite: bool
    asymmetry: float
    moments: np.ndarray
    axes: np.ndarray
    triangle_excess: float

    @property
    def symmetric(self) -> bool:
        """Finite and symmetric up to `SYMMETRY_RTOL`."""
        return self.finite and self.asymmetry <= SYMMETRY_RTOL

    @property
    def zero(self) -> bool:
        """Finite and every principal moment exactly zero."""
        return self.finite and bool(np.all(self.moments == 0))

    @property
    def positive_definite(self) -> bool:
        """Finite and the smallest principal moment positive."""
        return self.finite and bool(self.moments[0] > 0)

    @property
    def triangle_ok(self) -> bool:
        """Finite and `A + B >= C` up to `TRIANGLE_RTOL`."""
        return self.finite and not self.triangle_excess > TRIANGLE_RTOL

    @property
    def valid(self) -> bool:
        """Symmetric, positive definite and `A + B >= C`: a body has it."""
        return self.symmetric and self.positive_definite and self.triangle_ok


def diagnose_tensor(inertia: ArrayLike) -> TensorDiagnosis:
    """The principal moments, symmetry and triangle-inequality margin of `inertia`.

    Parameters
    ----------
    inertia : (3, 3) array_like
        An inertia tensor, kg m^2.

    Returns
    -------
    TensorDiagnosis
        What is wrong with it, if anything (`.valid` says whether anything is).

    Raises
    ------
    ValueError
        When the shape is not (3, 3).
    """
    t = as_tensor(inertia)
    nan3 = np.full(3, np.nan)
    if not np.all(np.isfinite(t)):
        return TensorDiagnosis(False, np.nan, nan3, np.full((3, 3), np.nan), np.nan)
    scale = float(np.abs(t).max())
    if not EIGEN_RANGE[0] <= scale <= EIGEN_RANGE[1] and scale > 0:
        # the ratios below do not change under an exact rescaling; the moments do
        k = math.frexp(scale)[1]
        found = diagnose_tensor(np.ldexp(t, -k))
        with np.errstate(over="ignore"):
            moments = np.ldexp(found.moments, k)
        if not np.all(np.isfinite(moments)):
            return TensorDiagnosis(False, np.nan, nan3, np.full((3, 3), np.nan), np.nan)
        return TensorDiagnosis(True, found.asymmetry, moments, found.axes,
                               found.triangle_excess)
    asym = float(np.abs(t - t.T).max()) / scale if scale > 0 else 0.0
    moments, axes = np.linalg.eigh(symmetric_part(t))
    largest = float(moments[2])
    excess = (largest - moments[0] - moments[1]) / largest if largest > 0 else 0.0
    return TensorDiagnosis(True, asym, moments, axes, float(excess))


def is_placeholder(inertia: ArrayLike) -> bool:
    """True for the literal placeholders `diag(1, 1, 1)` and `diag(e, e, e)` with `e` a
    power of ten <= 1e-6, no products.

    Exporters and hand-written URDFs use these when no value is known; they are almost never
    a body's real inertia. Equal tiny moments that are not a round power of ten are left
    alone: a small sphere has them (allegro's finger tips: 9.68e-07 = 2/5 m r^2).

    Parameters
    ----------
    inertia : (3, 3) array_like
        An inertia tensor as written, kg m^2.

    Returns
    -------
    bool
        Whether it is one of those literal placeholders.
    """
    t = as_tensor(inertia)
    if not np.all(np.isfinite(t)):
        return False
    off = t[~np.eye(3, dtype=bool)]
    d = np.diag(t)
    if np.any(off != 0) or not (d[0] == d[1] == d[2]):
        return False
    if d[0] == 1.0:
        return True
    if not 0 < d[0] <= PLACEHOLDER_TINY:
        return False
    exponent = np.log10(d[0])
    return bool(abs(exponent - np.round(exponent)) < 1e-9)


def is_valid_tensor(inertia: ArrayLike) -> bool:
    """Whether a body can have `inertia`: symmetric, positive definite and `A + B >= C`,
    up to round-off (the tolerances above).

    Parameters
    ----------
    inertia : (3, 3) array_like
        An inertia tensor, kg m^2.

    Returns
    -------
    bool
        True when it is valid.
    """
    return diagnose_tensor(inertia).valid
