"""How far a tensor derived from geometry may be from what CAD would give: an error bar.

The homogeneous solid of a link's outer geometry is a model: real links are hollow, hold
motors and cables, and their mass sits unevenly. Measured over real robots with their CAD
tensors withheld (`scripts/bench_cad.py`), the relative Frobenius error of the solid's
tensor about the CoM grows with the distance between the solid's centroid and the CAD CoM
(a CoM far from the centroid means uneven mass, which the solid cannot see). So:

- when the CoM is known (kept from the description), the band is read from the kind of
  geometry integrated (primitive stand-ins, convex hull, detailed mesh), its role
  (collision or visual) and the centroid-to-CoM offset, as a fraction of the geometry's
  bounding-box diagonal;
- when the geometry needs an implied density (kept mass over its volume) above
  `urdfinertia.body.geometry_choice.DENSE` (solid titanium) to hold the kept mass,
  it likely misses volume (open shells, parts not drawn) and the band is that of such
  links, whatever the offset (`DENSE_CELL`);
- when the CoM is derived too, nothing tells how uneven the link is, and the band is the
  spread of the homogeneous model over all links.

Each band is fitted so that the true tensor is within it for about 80 % of links of a
package the fit has not seen (cross-validated by package; coverage per package in the
docs, "The error bar").
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from urdfinertia.body.geometry_choice import DENSE

#: Upper edges of the centroid-to-CoM offset bins, fractions of the box diagonal. The
#: first bin is a centroid on the kept CoM (the tensor was likely computed from this very
#: geometry, :data:`urdfinertia.body.geometry_choice.CENTROID_MATCH`).
OFFSET_EDGES = (0.001, 0.03, 0.08)
#: The band of the relative tensor error by (kind of geometry, role, offset bin): kind as
#: :data:`urdfinertia.body.geometry_choice.KINDS`, role "collision" or "visual" (None:
#: every role), bin as :func:`offset_bin`; (None, None, bin) is every kind;
#: :data:`DENSE_CELL` is every dense geometry. Fitted by ``scripts/bench_cad.py
#: --calibrate`` on 668 CAD links of 10 packages at the lowest quantile (p85) whose
#: coverage, cross-validated by package, meets the targets (83.1 % pooled, no package of
#: 10 links or more below 60 %; docs: the error bar). Cells with fewer than 12 links are
#: left out and take the coarser cell's band.
BANDS: dict[tuple[str | None, str | None, int | None], float] = {
    ("dense", None, None): 1.43,
    ("hull", "collision", 1): 0.58,
    ("hull", "collision", 2): 0.58,
    ("hull", None, 1): 0.58,
    ("hull", None, 2): 0.43,
    ("hull", None, 3): 0.46,
    ("mesh", "collision", 0): 0.18,
    ("mesh", "collision", 1): 0.74,
    ("mesh", "collision", 2): 0.67,
    ("mesh", "collision", 3): 0.79,
    ("mesh", "visual", 0): 0.69,
    ("mesh", "visual", 1): 0.48,
    ("mesh", "visual", 2): 0.69,
    ("mesh", "visual", 3): 0.90,
    ("mesh", None, 0): 0.46,
    ("mesh", None, 1): 0.60,
    ("mesh", None, 2): 0.68,
    ("mesh", None, 3): 0.89,
    ("primitive", "collision", 0): 0.58,
    ("primitive", "collision", 3): 0.73,
    ("primitive", None, 0): 0.57,
    ("primitive", None, 3): 0.73,
    (None, None, 0): 0.50,
    (None, None, 1): 0.58,
    (None, None, 2): 0.68,
    (None, None, 3): 0.78,
}
#: The :data:`BANDS` key of links whose implied density is above :data:`DENSE`.
DENSE_CELL: tuple[str | None, str | None, int | None] = ("dense", None, None)
#: 80th percentile of the error when the CoM is derived too (only 6 such links measured;
#: a wider set of 846 links gave p75 47 %, p90 76 %).
MODEL_P80 = 0.81
#: The coverage the bands are calibrated for.
BAND_LEVEL = 0.80


@dataclass(frozen=True)
class MassBand:
    """The calibrated band of a mass the prior derived (`urdfinertia.priors`).

    Attributes
    ----------
    low, high : float
        kg: `level` of the measured CAD links had their mass inside the band.
    level : float
        The share of measured links the band held for.
    density : float
        The effective density the prior predicted, kg/m^3.
    water : float
        The same geometry at 1000 kg/m^3, kg (what a constant density gives).
    """

    low: float
    high: float
    level: float
    density: float
    water: float

    def __str__(self) -> str:
        return (f"mass {self.low:.3g}-{self.high:.3g} kg ({100 * self.level:.0f} %: the "
                f"mass prior's {self.density:.0f} kg/m³; {self.water:.3g} kg at 1000)")

    def as_dict(self) -> dict[str, object]:
        return {"low": self.low, "high": self.high, "level": self.level,
                "density": self.density, "at_1000": self.water}


@dataclass(frozen=True)
class ErrorBar:
    """Expected relative error of a derived tensor against CAD (Frobenius, about the CoM).

    Attributes
    ----------
    band : float
        The error stays below this fraction for `BAND_LEVEL` of links.
    basis : {"offset", "density", "model"}
        "offset" (from the kind of geometry and the centroid-to-CoM offset), "density"
        (an implied density above `urdfinertia.body.geometry_choice.DENSE`: the geometry
        may miss volume) or "model" (CoM not known).
    offset : float or None
        Centroid-to-CoM offset as a fraction of the box diagonal (None for "model").
    kind : str or None
        The kind of geometry the tensor came from ("primitive", "hull", "mesh"; None
        when not known).
    density : float or None
        The kept mass over the geometry's volume, kg/m^3; None when no mass is kept.
    mass : MassBand or None
        The band of a mass the prior derived (None: the mass was kept or given).
    """

    band: float
    basis: str
    offset: float | None = None
    kind: str | None = None
    density: float | None = None
    mass: MassBand | None = None

    def __str__(self) -> str:
        from urdfinertia.body.geometry_choice import KIND_WORDS

        what = f"{KIND_WORDS[self.kind]}, " if self.kind is not None else ""
        if self.basis == "density" and self.density is not None:
            why = (f"{what}implied density {self.density:.0f} kg/m³: the geometry may miss "
                   "volume")
        elif self.offset is not None:
            why = f"{what}centroid {100 * self.offset:.1f} % of the box diagonal from the " \
                "kept CoM"
        else:
            why = "homogeneous model, CoM not known"
        text = f"tensor within ±{100 * self.band:.0f} % of CAD ({100 * BAND_LEVEL:.0f} %: {why})"
        return text if self.mass is None else f"{text}; {self.mass}"

    def as_dict(self) -> dict[str, object]:
        return {"band": self.band, "level": BAND_LEVEL, "basis": self.basis,
                "offset": self.offset, "kind": self.kind, "density": self.density,
                "mass": None if self.mass is None else self.mass.as_dict()}


def offset_bin(offset: float) -> int:
    """The index of the offset bin holding ``offset`` (fraction of the box diagonal)."""
    for i, edge in enumerate(OFFSET_EDGES):
        if offset < edge:
            return i
    return len(OFFSET_EDGES)


def band_key(kind: str | None, role: str | None) -> tuple[str | None, str | None]:
    """(kind, role) as :data:`BANDS` keys them: MuJoCo's counted geoms are "collision"."""
    return kind, None if role is None else ("visual" if role == "visual" else "collision")


def is_dense(density: float | None) -> bool:
    """Whether an implied density (kg/m^3; None: no mass kept) is above
    :data:`~urdfinertia.body.geometry_choice.DENSE`."""
    return density is not None and density > DENSE


def lookup_band(bands: dict[tuple[str | None, str | None, int | None], float],
                kind: str | None, role: str | None, offset: float,
                density: float | None = None) -> float:
    """The band of the finest cell of ``bands`` holding (kind, role, offset bin); a dense
    geometry (:func:`is_dense`) takes :data:`DENSE_CELL` when calibrated."""
    if is_dense(density) and DENSE_CELL in bands:
        return bands[DENSE_CELL]
    kind, role = band_key(kind, role)
    b = offset_bin(offset)
    for key in ((kind, role, b), (kind, None, b), (None, None, b)):
        if key in bands:
            return bands[key]
    return max(bands.values())


def tensor_error_bar(centroid_offset: float | None, diagonal: float | None,
                     kind: str | None = None, role: str | None = None,
                     density: float | None = None) -> ErrorBar:
    """The error bar of a derived tensor.

    Parameters
    ----------
    centroid_offset : float or None
        Distance between the solid's centroid and the kept CoM, m; None when the CoM is
        derived from the geometry too.
    diagonal : float or None
        The geometry's bounding-box diagonal, m.
    kind, role : str or None
        The kind of geometry integrated ("primitive", "hull", "mesh") and its role
        ("collision", "visual", "geom"); None when not known.
    density : float or None
        The kept mass over the geometry's volume, kg/m^3; None when no mass is kept.
    """
    if centroid_offset is None or diagonal is None or not (
            math.isfinite(diagonal) and diagonal > 0):
        return ErrorBar(MODEL_P80, "model", kind=kind, density=density)
    rel = centroid_offset / diagonal
    basis = "density" if is_dense(density) and DENSE_CELL in BANDS else "offset"
    return ErrorBar(lookup_band(BANDS, kind, role, rel, density), basis, rel, kind, density)
