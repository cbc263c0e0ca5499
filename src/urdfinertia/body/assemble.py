"""Assemble a link's mass properties from its parts (paper sections 2-3, eqs. 3-5, 43-46).

Each part gets a mass (its own known mass, its density times its volume, or a share of
what is left of a pinned link mass), is moved into the link frame (``A I A^T`` and the
part frame's offset) and the parts are summed about the link's centre of mass with the
Huygens-Steiner theorem.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from urdfinertia.body.mass import MassSource, share_mass, signed_mass
from urdfinertia.body.parts import Part
from urdfinertia.errors import UrdfInertiaError
from urdfinertia.inertia.massprops import MassProperties, combine


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
    mass_source: MassSource  # what the mass actually came from


def _scaled_to(parts: Sequence[Part], mass: float) -> list[Part]:
    """Parts whose stated masses and densities are weights, scaled to sum to ``mass``.

    A factor within round-off of 1 is taken as 1, so that a mass written from these very
    parts reads back to the same parts (``fix`` stays idempotent).
    """
    import dataclasses

    if all(p.mass is None for p in parts) and len({p.density for p in parts}) == 1:
        # equal densities: the mass spread by volume, on the exact uniform path
        return [dataclasses.replace(p, density=None, relative=False) for p in parts]
    weight = sum(signed_mass(p, p.mass if p.mass is not None else (p.density or 0.0) * p.volume)
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


def assemble(parts: Sequence[Part], source: MassSource) -> Assembly:
    """Give each part its mass and sum them in the link frame.

    Parameters
    ----------
    parts
        The link's parts, each at unit density in its own frame.
    source : MassSource
        What the link's mass is asked to be (:func:`urdfinertia.body.mass.link_mass_source`):
        a total (pinned or kept) that parts with no known mass or density share uniformly by
        volume, or the density of those parts.
    """
    if not parts:
        raise UrdfInertiaError("link has no parts")
    if source.total is not None and all(p.relative for p in parts):
        # stated densities/masses are weights of the parts against each other (MJCF geoms,
        # SDF collisions of a body whose mass is written): scaled to the link's total
        parts = _scaled_to(parts, source.total)
    free_density, source = share_mass(parts, source)
    pinned_mass = source.total
    if all(p.mass is None and p.density is None and not p.cavity for p in parts):
        # The uniform case: combine at unit density, then scale once. Scaling one total
        # keeps ``fix`` idempotent bit for bit (the written mass gives the same tensor).
        unit_total = combine(p.unit.transformed(p.pose) for p in parts)
        target = pinned_mass if pinned_mass is not None else free_density * unit_total.mass
        total = unit_total.with_mass(target)
        k = target / unit_total.mass
        uniform = tuple(PartResult(p, p.in_link(p.volume * k), k) for p in parts)
        return Assembly(total, uniform, source)
    results: list[PartResult] = []
    for p in parts:
        if p.mass is not None:
            # a point mass has no volume: no density (0 in the results)
            mass, rho = p.mass, p.mass / p.volume if p.volume else 0.0
        else:
            rho = p.density if p.density is not None else free_density
            mass = rho * p.volume
        results.append(PartResult(p, p.in_link(-mass if p.cavity else mass), rho))
    total = combine(r.mass_properties for r in results)
    if not total.mass > 0:
        raise UrdfInertiaError(f"link mass comes out as {total.mass:.6g} kg (cavities larger "
                               "than the material around them?)")
    if not total.is_physical():
        raise UrdfInertiaError("assembled inertia is not physical (cavity outside its body?)")
    return Assembly(total, tuple(results), source)
