"""Assemble a link's mass properties from its parts (paper sections 2-3, eqs. 3-5, 43-46).

Each part gets a mass (its own known mass, its density times its volume, or a share of
what is left of a pinned link mass), is moved into the link frame (``A I A^T`` and the
part frame's offset) and the parts are summed about the link's centre of mass with the
Huygens-Steiner theorem.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from urdfinertia.errors import UrdfInertiaError
from urdfinertia.inertia.massprops import MassProperties, combine
from urdfinertia.link.parts import Part

#: Relative mismatch tolerated between a pinned link mass and fully known part masses.
PINNED_MASS_RTOL = 1e-9


@dataclass(frozen=True, eq=False)
class PartResult:
    """A part with its mass, in the link frame."""

    part: Part
    mass_properties: MassProperties  # negative mass for a cavity
    density: float  # kg/m^3 actually used


@dataclass(frozen=True, eq=False)
class Assembly:
    """A link's total and the contribution of each part."""

    total: MassProperties
    parts: tuple[PartResult, ...]
    mass_source: str  # e.g. "kept 2.5 kg", "density 1000 kg/m^3"


def _scaled_to(parts: Sequence[Part], mass: float) -> list[Part]:
    """Parts whose stated masses and densities are weights, scaled to sum to ``mass``.

    A factor within round-off of 1 is taken as 1, so that a mass written from these very
    parts reads back to the same parts (``fix`` stays idempotent).
    """
    import dataclasses

    weight = sum(_signed(p, p.mass if p.mass is not None else (p.density or 0.0) * p.volume)
                 for p in parts)
    if not weight > 0:
        raise UrdfInertiaError("the parts' stated masses and densities weigh nothing: the "
                               f"kept link mass {mass:.6g} kg cannot be shared")
    k = mass / weight
    if abs(k - 1.0) < 1e-12:
        return list(parts)
    return [dataclasses.replace(p, mass=None if p.mass is None else p.mass * k,
                                density=None if p.density is None else p.density * k)
            for p in parts]


def _signed(part: Part, value: float) -> float:
    return -value if part.cavity else value


def assemble(parts: Sequence[Part], *, density: float, pinned_mass: float | None,
             pinned_reason: str = "pinned") -> Assembly:
    """Give each part its mass and sum them in the link frame.

    Parameters
    ----------
    parts
        The link's parts, each at unit density in its own frame.
    density : float
        kg/m^3 for parts with neither a known mass nor a density, when no mass is pinned.
    pinned_mass : float or None
        The link's total mass, kg. Parts with no known mass or density share what is left
        uniformly by volume.
    """
    if not parts:
        raise UrdfInertiaError("link has no parts")
    if pinned_mass is not None and all(p.relative for p in parts):
        parts = _scaled_to(parts, pinned_mass)
    known = 0.0
    free_volume = 0.0
    for p in parts:
        if p.mass is not None:
            known += _signed(p, p.mass)
        elif p.density is not None:
            known += _signed(p, p.density * p.volume)
        else:
            free_volume += _signed(p, p.volume)
    has_free = any(p.mass is None and p.density is None for p in parts)
    if pinned_mass is not None and has_free:
        left = pinned_mass - known
        if not free_volume > 0:
            raise UrdfInertiaError("parts without a known mass have no net volume to share "
                                   f"the remaining {left:.6g} kg")
        if not left > 0:
            raise UrdfInertiaError(f"known part masses ({known:.6g} kg) reach or exceed the "
                                   f"{pinned_reason} link mass {pinned_mass:.6g} kg")
        free_density = left / free_volume
        source = f"{pinned_reason} {pinned_mass:.6g} kg"
    else:
        free_density = density
        source = f"density {density:g} kg/m^3"
        if not has_free:
            source = "known part masses/densities"
        elif len(parts) > sum(p.mass is None and p.density is None for p in parts):
            source += " for parts without a known mass"
        if pinned_mass is not None and abs(known - pinned_mass) > PINNED_MASS_RTOL * pinned_mass:
            raise UrdfInertiaError(f"part masses sum to {known:.6g} kg but the link mass is "
                                   f"{pinned_reason} at {pinned_mass:.6g} kg")
    if all(p.mass is None and p.density is None and not p.cavity for p in parts):
        # The uniform case: combine at unit density, then scale once. Scaling one total
        # keeps ``fix`` idempotent bit for bit (the written mass gives the same tensor).
        unit_total = combine(p.unit.transformed(p.pose) for p in parts)
        target = pinned_mass if pinned_mass is not None else free_density * unit_total.mass
        total = unit_total.with_mass(target)
        k = target / unit_total.mass
        results = tuple(PartResult(p, p.in_link(p.volume * k), k) for p in parts)
        return Assembly(total, results, source)
    results = []
    for p in parts:
        if p.mass is not None:
            mass, rho = p.mass, p.mass / p.volume
        else:
            rho = p.density if p.density is not None else free_density
            mass = rho * p.volume
        results.append(PartResult(p, p.in_link(_signed(p, mass)), rho))
    total = combine(r.mass_properties for r in results)
    if not total.mass > 0:
        raise UrdfInertiaError(f"link mass comes out as {total.mass:.6g} kg (cavities larger "
                               "than the material around them?)")
    if not total.is_physical():
        raise UrdfInertiaError("assembled inertia is not physical (cavity outside its body?)")
    return Assembly(total, tuple(results), source)
