"""Where a link's mass comes from: the one home of the mass policy.

:func:`link_mass_source` says what the link's total mass is asked to be (a spec's pinned
mass, the description's own mass kept, or a density); :func:`share_mass` applies it to the
parts (parts with a known mass or density keep it, the others share what is left by
volume) and says what the mass actually came from. :mod:`urdfinertia.body.assemble` and
:mod:`urdfinertia.body.spec` both call :func:`share_mass`, so the rules and their failures
are written once; the spec names its TOML key in front of the same message.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from urdfinertia.errors import UrdfInertiaError

if TYPE_CHECKING:
    from urdfinertia.body.options import FixOptions
    from urdfinertia.body.parts import Part
    from urdfinertia.descriptions.model import Link

#: Relative mismatch tolerated between a pinned link mass and fully known part masses.
PINNED_MASS_RTOL = 1e-9
MASS_KINDS = ("pinned", "kept", "density", "parts", "parts+density")


@dataclass(frozen=True)
class MassSource:
    """What a link's mass is (or was) taken from.

    kind : "pinned" (a spec's total, ``value`` kg), "kept" (the description's own mass,
        ``value`` kg), "density" (every part at ``value`` kg/m^3), "parts" (every part has
        a known mass or density; ``value`` None) or "parts+density" (parts without a known
        mass at ``value`` kg/m^3).
    """

    kind: str
    value: float | None = None

    def __post_init__(self) -> None:
        if self.kind not in MASS_KINDS:
            raise ValueError(f"mass source kind must be one of {MASS_KINDS}")

    @property
    def total(self) -> float | None:
        """The link's total mass when the source fixes it, kg."""
        return self.value if self.kind in ("pinned", "kept") else None

    def __str__(self) -> str:
        if self.kind in ("pinned", "kept"):
            return f"{self.kind} {self.value:.6g} kg"
        if self.kind == "density":
            return f"density {self.value:g} kg/m^3"
        if self.kind == "parts":
            return "known part masses/densities"
        return f"density {self.value:g} kg/m^3 for parts without a known mass"


def existing_mass(link: Link) -> float | None:
    """The description's own mass when it is usable (finite and positive), kg."""
    import math

    if link.inertial is not None and math.isfinite(link.inertial.mass) and (
            link.inertial.mass > 0):
        return link.inertial.mass
    return None


def link_mass_source(link: Link, options: FixOptions, spec_mass: float | None = None,
                     spec_knows_parts: bool = False, *, trust_mass: bool = True,
                     ) -> MassSource:
    """What the link's total mass is asked to be.

    A spec's pinned mass wins; then, with ``options.mass == "keep"``, the description's own
    mass when it is usable and trusted (and the spec, if any, says nothing about masses);
    otherwise ``options.density``.
    """
    if spec_mass is not None:
        return MassSource("pinned", spec_mass)
    kept = existing_mass(link) if options.mass == "keep" and trust_mass else None
    if kept is not None and not spec_knows_parts:
        return MassSource("kept", kept)
    return MassSource("density", options.density)


class MassShareError(UrdfInertiaError):
    """The parts' known masses cannot make the link's total (message names the source)."""


def signed_mass(part: Part, value: float) -> float:
    return -value if part.cavity else value


def share_mass(parts: Sequence[Part], source: MassSource) -> tuple[float, MassSource]:
    """Density of the parts with neither a known mass nor a density, and the actual source.

    Raises :class:`MassShareError` when a total is fixed by ``source`` and the known parts
    reach it already, leave it to parts without net volume, or (all known) miss it.
    """
    known = 0.0
    free_volume = 0.0
    n_free = 0
    for p in parts:
        if p.mass is not None:
            known += signed_mass(p, p.mass)
        elif p.density is not None:
            known += signed_mass(p, p.density * p.volume)
        else:
            free_volume += signed_mass(p, p.volume)
            n_free += 1
    total = source.total
    if total is not None and n_free:
        left = total - known
        if not left > 0:
            raise MassShareError(f"parts with known mass or density already weigh {known:.6g} "
                                 f"kg, the {source.kind} total is {total:.6g} kg")
        if not free_volume > 0:
            raise MassShareError(f"the parts left to share {left:.6g} kg have no net volume "
                                 "(cavities only?)")
        return left / free_volume, source
    if total is not None and abs(known - total) > PINNED_MASS_RTOL * total:
        raise MassShareError(f"every part's mass is known and they sum to {known:.6g} kg, not "
                             f"the {source.kind} {total:.6g} kg (drop one or the other)")
    if not n_free:
        return 0.0, MassSource("parts")
    density = source.value if source.kind == "density" else None
    assert density is not None
    if n_free < len(parts):
        return density, MassSource("parts+density", density)
    return density, source
