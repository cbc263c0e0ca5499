"""Is an inertia tensor valid for a simulator, and the smallest correction that makes it so.

Pure numpy. A rigid body's central inertia is symmetric, positive definite, and its
principal moments ``A <= B <= C`` meet the triangle inequality ``A + B >= C`` (each moment
is ``integral(r_perp^2 dm)``, and ``A + B - C = 2 integral(z^2 dm) >= 0`` along C's axis).
MuJoCo refuses a body breaking either, with no tolerance (measured with mujoco 3: a
violation of 1e-12 relative is already refused).

The repair keeps the principal axes and never lowers a principal moment: a smallest moment
that is not positive is raised to ``MIN_MOMENT_RTOL`` times the largest, then, if
``A + B < C``, the smallest moment is lifted to ``C - B`` (plus ``REPAIR_MARGIN`` of C so the
written decimal text still passes after round-off). The two largest moments, which carry
most of the dynamics, stay as the CAD system wrote them.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

#: A triangle-inequality excess ``(C - A - B) / C`` above this is a violation. Round-off of
#: an eigen-decomposition is ~1e-16; MuJoCo refuses anything above zero.
TRIANGLE_RTOL = 1e-12
#: An entry asymmetry ``max|I - I^T| / max|I|`` above this is "not symmetric".
SYMMETRY_RTOL = 1e-9
#: Smallest principal moment written by a repair, as a fraction of the largest.
MIN_MOMENT_RTOL = 1e-6
#: A repaired tensor meets ``A + B >= C (1 + REPAIR_MARGIN)``.
REPAIR_MARGIN = 1e-9
#: Placeholder magnitudes: a diagonal of all ones or of tiny equal values, no products.
PLACEHOLDER_TINY = 1e-6


def as_tensor(inertia: ArrayLike) -> np.ndarray:
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
        Every entry is finite. When False the other fields are NaN.
    asymmetry : float
        ``max|I - I^T| / max|I|`` (0 for a URDF tensor, which is symmetric by construction).
    moments : (3,) float
        Principal moments of the symmetric part, ascending, kg m^2.
    axes : (3, 3) float
        Principal axes as columns, matching ``moments``.
    triangle_excess : float
        ``(C - A - B) / C``; positive means the triangle inequality is broken by that
        fraction of the largest moment.
    """

    finite: bool
    asymmetry: float
    moments: np.ndarray
    axes: np.ndarray
    triangle_excess: float

    @property
    def symmetric(self) -> bool:
        return self.finite and self.asymmetry <= SYMMETRY_RTOL

    @property
    def zero(self) -> bool:
        return self.finite and bool(np.all(self.moments == 0))

    @property
    def positive_definite(self) -> bool:
        return self.finite and bool(self.moments[0] > 0)

    @property
    def triangle_ok(self) -> bool:
        return self.finite and not self.triangle_excess > TRIANGLE_RTOL

    @property
    def valid(self) -> bool:
        return self.symmetric and self.positive_definite and self.triangle_ok


def diagnose_tensor(inertia: ArrayLike) -> TensorDiagnosis:
    """Principal moments, symmetry and triangle-inequality margin of ``inertia``."""
    t = as_tensor(inertia)
    if not np.all(np.isfinite(t)):
        nan3 = np.full(3, np.nan)
        return TensorDiagnosis(False, np.nan, nan3, np.full((3, 3), np.nan), np.nan)
    scale = float(np.abs(t).max())
    asym = float(np.abs(t - t.T).max()) / scale if scale > 0 else 0.0
    moments, axes = np.linalg.eigh(0.5 * (t + t.T))
    largest = float(moments[2])
    excess = (largest - moments[0] - moments[1]) / largest if largest > 0 else 0.0
    return TensorDiagnosis(True, asym, moments, axes, float(excess))


def is_placeholder(inertia: ArrayLike) -> bool:
    """True for the literal placeholders ``diag(1, 1, 1)`` and ``diag(e, e, e)`` with ``e`` a
    power of ten <= 1e-6, no products.

    Exporters and hand-written URDFs use these when no value is known; they are almost never
    a body's real inertia. Equal tiny moments that are not a round power of ten are left
    alone: a small sphere has them (allegro's finger tips: 9.68e-07 = 2/5 m r^2).
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


@dataclass(frozen=True, eq=False)
class TensorRepair:
    """A repaired tensor and what changed.

    tensor : (3, 3) float, same axes as the input.
    moments_before, moments_after : (3,) float, principal moments along the same axes.
    changes : human-readable steps, empty when the input was already valid.
    """

    tensor: np.ndarray
    moments_before: np.ndarray
    moments_after: np.ndarray
    changes: tuple[str, ...]

    @property
    def changed(self) -> bool:
        return bool(self.changes)


def repair_tensor(inertia: ArrayLike) -> TensorRepair:
    """The smallest lift of principal moments that makes ``inertia`` valid (module doc).

    The input is first replaced by its symmetric part (the nearest symmetric matrix in the
    Frobenius norm). Axes are kept; no moment decreases.

    Raises
    ------
    ValueError
        When the tensor is not finite or has no positive principal moment: there is
        nothing to keep, so the geometry (``urdf-inertia fix``) must supply a tensor.
    """
    t = as_tensor(inertia)
    d = diagnose_tensor(t)
    if not d.finite:
        raise ValueError("tensor has non-finite entries")
    if not d.moments[2] > 0:
        raise ValueError("tensor has no positive principal moment")
    if d.valid:
        return TensorRepair(t.copy(), d.moments, d.moments, ())
    changes: list[str] = []
    if not d.symmetric:
        changes.append(f"symmetrised (asymmetry {d.asymmetry:.3g})")
    m = d.moments.copy()
    c = m[2]
    floor = MIN_MOMENT_RTOL * c
    for i in (0, 1):
        if m[i] <= 0:
            changes.append(f"raised principal moment {m[i]:.6g} to {floor:.6g} "
                           "(not positive definite)")
            m[i] = floor
    target = c * (1 + REPAIR_MARGIN)
    if m[0] + m[1] < target and (d.triangle_excess > TRIANGLE_RTOL or len(changes) > 0):
        lifted = target - m[1]
        changes.append(f"lifted smallest principal moment {m[0]:.6g} to {lifted:.6g} "
                       f"(A + B >= C was broken by {max(d.triangle_excess, 0.0):.3g} of C)")
        m[0] = lifted
    axes = d.axes
    out = axes @ np.diag(m) @ axes.T
    out = 0.5 * (out + out.T)
    return TensorRepair(out, d.moments, m, tuple(changes))
