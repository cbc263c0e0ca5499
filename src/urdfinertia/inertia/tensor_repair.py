"""The smallest correction that makes an inertia tensor valid for a simulator.

Pure numpy. What "valid" means is [`urdfinertia.inertia.validity`][urdfinertia.inertia.validity]'s
rule. The repair keeps the principal axes and never lowers a principal moment: a smaller moment
that is not above `MIN_MOMENT_RTOL` times the largest is raised to it, then, if `A + B < C`, the
smallest moment is lifted to `C - B` (plus `REPAIR_MARGIN` of C so the written decimal text still
passes after round-off). The two largest moments, which carry most of the dynamics, stay as the CAD
system wrote them.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from urdfinertia.inertia.validity import (
    TRIANGLE_RTOL,
    as_tensor,
    diagnose_tensor,
    symmetric_part,
)

MIN_MOMENT_RTOL = 1e-6
"""Smallest principal moment written by a repair, as a fraction of the largest."""
REPAIR_MARGIN = 1e-9
"""A repaired tensor meets `A + B >= C (1 + REPAIR_MARGIN)`."""


@dataclass(frozen=True, eq=False)
class TensorRepair:
    """A repaired tensor and what changed.

    Attributes
    ----------
    tensor : (3, 3) float
        The repaired tensor, along the same axes as the input, kg m^2.
    moments_before, moments_after : (3,) float
        The principal moments along the same axes, kg m^2.
    changes : tuple of str
        The steps taken, in words; empty when the input was already valid.
    """

    tensor: np.ndarray
    moments_before: np.ndarray
    moments_after: np.ndarray
    changes: tuple[str, ...]

    @property
    def changed(self) -> bool:
        """Whether the tensor had to be repaired."""
        return bool(self.changes)


def repair_tensor(inertia: ArrayLike) -> TensorRepair:
    """The smallest lift of principal moments that makes `inertia` valid (module doc).

    The input is first replaced by its symmetric part (the nearest symmetric matrix in the
    Frobenius norm). Axes are kept; no moment decreases.

    Parameters
    ----------
    inertia : (3, 3) array_like
        The tensor as written, kg m^2.

    Returns
    -------
    TensorRepair
        The repaired tensor, the principal moments before and after, and the steps taken
        (none when the input was valid).

    Raises
    ------
    ValueError
        When the tensor is not finite or has no positive principal moment: there is
        nothing to keep, so the geometry (`urdf-inertia fix`) must supply a tensor.
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
        # a positive moment below the floor is one round-off can turn negative once the
        # tensor is rebuilt (a moment of 1e-17 beside 1 was): raised the same way
        if m[i] < floor:
            why = "not positive definite" if m[i] <= 0 else "below round-off of the largest"
            changes.append(f"raised principal moment {m[i]:.6g} to {floor:.6g} ({why})")
            m[i] = floor
    target = c * (1 + REPAIR_MARGIN)
    if m[0] + m[1] < target and (d.triangle_excess > TRIANGLE_RTOL or len(changes) > 0):
        lifted = target - m[1]
        changes.append(f"lifted smallest principal moment {m[0]:.6g} to {lifted:.6g} "
                       f"(A + B >= C was broken by {max(d.triangle_excess, 0.0):.3g} of C)")
        m[0] = lifted
    axes = d.axes
    out = symmetric_part(axes @ np.diag(m) @ axes.T)
    return TensorRepair(out, d.moments, m, tuple(changes))
