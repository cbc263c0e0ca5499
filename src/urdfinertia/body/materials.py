"""Built-in material densities for decomposition specs (``material = "steel"``).

Pure data. Values are typical room-temperature densities in kg/m^3 of the common grade
named in each note (handbook and datasheet values, e.g. ASM/MatWeb, rounded): a real part
can differ by a few per cent, so a datasheet mass beats any of these.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType


@dataclass(frozen=True)
class Material:
    """A named density.

    name : str
        Canonical key (lower case, words joined by ``_``).
    density : float
        kg/m^3.
    note : str
        Which grade the value stands for.
    """

    name: str
    density: float
    note: str


_TABLE = (
    Material("steel", 7850.0, "carbon / low-alloy steel (S235, C45, 42CrMo4)"),
    Material("stainless_steel", 8000.0, "austenitic stainless (304, 316)"),
    Material("cast_iron", 7200.0, "grey cast iron (EN-GJL-250)"),
    Material("aluminium", 2700.0, "wrought aluminium alloys (6061, 6082); 7075 is 2810"),
    Material("cast_aluminium", 2680.0, "cast aluminium alloy (AlSi10Mg, A356)"),
    Material("magnesium", 1810.0, "magnesium alloy AZ91"),
    Material("titanium", 4430.0, "titanium alloy Ti-6Al-4V"),
    Material("brass", 8500.0, "brass CuZn37 / CuZn39Pb3"),
    Material("bronze", 8800.0, "tin bronze CuSn8"),
    Material("copper", 8960.0, "pure copper"),
    Material("abs", 1040.0, "ABS, moulded or fully dense print"),
    Material("pla", 1240.0, "PLA, fully dense (a print with infill is lighter)"),
    Material("petg", 1270.0, "PETG, fully dense"),
    Material("nylon", 1140.0, "polyamide PA6 / PA66 (PA12 is 1010)"),
    Material("pom", 1410.0, "acetal (POM, Delrin)"),
    Material("polycarbonate", 1200.0, "polycarbonate (PC)"),
    Material("carbon_fibre_composite", 1600.0, "CFRP, about 60 % fibre by volume, epoxy"),
    Material("glass_fibre_composite", 1900.0, "GFRP laminate, epoxy"),
    Material("rubber", 1200.0, "natural / NBR rubber"),
)

#: Canonical name -> material.
MATERIALS: Mapping[str, Material] = MappingProxyType({m.name: m for m in _TABLE})

#: Other spellings accepted for a canonical name.
ALIASES: Mapping[str, str] = MappingProxyType({
    "aluminum": "aluminium",
    "cast_aluminum": "cast_aluminium",
    "stainless": "stainless_steel",
    "carbon_fiber_composite": "carbon_fibre_composite",
    "carbon_fibre": "carbon_fibre_composite",
    "carbon_fiber": "carbon_fibre_composite",
    "cfrp": "carbon_fibre_composite",
    "glass_fiber_composite": "glass_fibre_composite",
    "gfrp": "glass_fibre_composite",
    "polyamide": "nylon",
    "pa6": "nylon",
    "acetal": "pom",
    "delrin": "pom",
    "pc": "polycarbonate",
})


def material_key(name: str) -> str:
    """Normalised spelling: lower case, spaces and hyphens as ``_``."""
    return "_".join(name.strip().lower().replace("-", " ").split())


def material_density(name: str, extra: Mapping[str, float] | None = None) -> float | None:
    """Density in kg/m^3 of material ``name``, or None when it is unknown.

    ``extra`` (a spec's own ``[materials]`` table, keys already normalised) is looked up
    first, so a spec can override a built-in value.
    """
    key = material_key(name)
    if extra and key in extra:
        return float(extra[key])
    key = ALIASES.get(key, key)
    found = MATERIALS.get(key)
    return found.density if found is not None else None
