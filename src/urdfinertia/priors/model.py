"""The mass prior: a link's effective density from what is known without CAD, with its band.

The effective density of a link is its mass over the volume of the geometry the tool
integrates. Its log10 is modelled as a sum of terms (`urdfinertia.priors.terms`), each
weighted by a coefficient of the data file (`urdfinertia.priors.data`); the band is
the interval of the held-out ratio CAD/predicted that held for the stated share of the
measured links (``scripts/bench_priors.py`` fits both, leaving one package out at a time).

Pure numpy and plain Python: no file access beyond the packaged data file.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from urdfinertia.priors.data import PriorTable, load_table
from urdfinertia.priors.features import LinkFeatures
from urdfinertia.priors.terms import term_values


@dataclass(frozen=True)
class MassPrior:
    """A link's predicted mass and its band.

    density : predicted effective density, kg/m^3; mass : density times the volume, kg.
    low, high : the band, kg (``level`` of the measured links had their CAD mass inside).
    contributions : (term, log10 contribution) of every term used, largest first: the
        table ``explain`` can show ("robot:humanoid +0.21").
    """

    density: float
    mass: float
    low: float
    high: float
    level: float
    contributions: tuple[tuple[str, float], ...]

    def describe(self) -> str:
        return (f"{self.mass:.3g} kg ({self.low:.3g}-{self.high:.3g} kg, "
                f"{100 * self.level:.0f} %) at a predicted {self.density:.0f} kg/m³")


@dataclass(frozen=True)
class TotalPrior:
    """A robot's predicted total over the links given, with its band, kg.

    water : the same links at 1000 kg/m^3 (what a constant density gives), kg.
    links : how many links the total sums.
    """

    mass: float
    low: float
    high: float
    level: float
    water: float
    links: int

    def describe(self) -> str:
        return (f"{self.water:.3g} kg at 1000 kg/m³; the prior gives {self.mass:.3g} kg "
                f"({self.low:.3g}-{self.high:.3g}, {100 * self.level:.0f} %)")


def log_density(features: LinkFeatures, table: PriorTable | None = None,
                ) -> tuple[float, tuple[tuple[str, float], ...]]:
    """log10 of the predicted effective density (kg/m^3) and each term's contribution."""
    coefficients = (table or load_table()).mass["coefficients"]
    parts = [(name, coefficients[name] * value) for name, value in term_values(features).items()
             if name in coefficients and value]
    parts.sort(key=lambda kv: -abs(kv[1]))
    return float(sum(v for _, v in parts)), tuple(parts)


def _band(table: PriorTable, key: str = "band") -> tuple[float, float, float]:
    band = table.mass[key]
    return float(band["low"]), float(band["high"]), float(band["level"])


def mass_prior(features: LinkFeatures, table: PriorTable | None = None) -> MassPrior:
    """The predicted mass of a link with no written mass, over ``features.volume``.

    Parts whose description states their own mass or density keep it: ``features.volume``
    is then the volume of the others only, and the caller adds the stated masses.
    """
    table = table or load_table()
    value, contributions = log_density(features, table)
    density = 10.0 ** value
    mass = density * features.volume
    lo, hi, level = _band(table)
    return MassPrior(density, mass, mass * 10.0 ** lo, mass * 10.0 ** hi, level,
                     contributions)


def robot_total(priors: Sequence[MassPrior], table: PriorTable | None = None,
                water_density: float = 1000.0) -> TotalPrior:
    """The robot's total over ``priors`` (each link with no written mass), with its band.

    The band is that of measured robots' totals (``robot_band``: robots with at least
    ``min_links`` links, whose link errors partly cancel); a robot of fewer links takes
    the link band.
    """
    table = table or load_table()
    if not priors:
        raise ValueError("no links to sum")
    total = math.fsum(p.mass for p in priors)
    water = math.fsum(p.mass / p.density * water_density for p in priors)
    band = table.mass["robot_band"]
    key = "robot_band" if len(priors) >= int(band.get("min_links", 1)) else "band"
    lo, hi, level = _band(table, key)
    return TotalPrior(total, total * 10.0 ** lo, total * 10.0 ** hi, level, water, len(priors))
