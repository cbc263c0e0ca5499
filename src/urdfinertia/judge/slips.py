"""The slip search on a link: what the author meant, before any written value is thrown away.

For a link ``check`` flags (:data:`SLIP_TRIGGERS`), the written inertial and the
homogeneous solid of its geometry go to :func:`urdfinertia.inertia.slips.propose`; a
proposal is one edit of the written values (``izz x1e-3``) that makes the inertial valid and
plausible within the geometry's error bar and is clearly better than every other edit.
``fix``'s policy applies it instead of deriving the tensor from the geometry
(:mod:`urdfinertia.plan.policy`); ``--no-slips`` (``FixOptions.slips=False``) turns it off.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from urdfinertia.body.assemble import assemble
from urdfinertia.body.bounds import BoundsCache, link_bounds
from urdfinertia.body.errorbar import MODEL_P80
from urdfinertia.body.mass import MassSource
from urdfinertia.body.options import PLAUSIBLE_DENSITY, FixOptions, select_geometry
from urdfinertia.body.parts import MeshSource, geometry_parts
from urdfinertia.descriptions.model import Link
from urdfinertia.errors import UrdfInertiaError
from urdfinertia.inertia.massprops import MassProperties
from urdfinertia.inertia.slips import Limits, Proposal, Solid, Written, propose
from urdfinertia.judge.plausibility import (
    COM_OUTSIDE_ERROR,
    COM_OUTSIDE_WARN,
    INERTIA_RATIO_LIMIT,
)

#: Findings after which the slip search runs: the written values are invalid, or
#: implausible against the geometry.
SLIP_TRIGGERS = frozenset({
    "mass-absurd", "inertia-absurd", "inertia-not-symmetric", "inertia-not-positive-definite",
    "triangle-inequality", "implausible-density", "com-outside-geometry",
    "inertia-vs-geometry"})
#: What ``check`` accepts, with the error bar of a tensor whose CoM is not known (the
#: widest calibrated band): an edit outside it is not proposed.
LIMITS = Limits(PLAUSIBLE_DENSITY, COM_OUTSIDE_WARN, INERTIA_RATIO_LIMIT, MODEL_P80,
                COM_OUTSIDE_ERROR)


@dataclass(frozen=True, eq=False)
class SlipProposal:
    """A proposed one-edit correction of a link's written inertial.

    proposal : the ranked edit and its runner-up (:class:`~urdfinertia.inertia.slips.
        Proposal`). before : the written values as read (link frame). after : the values
        the edit gives (link frame, about the CoM).
    """

    link: str
    proposal: Proposal
    before: Written
    after: MassProperties

    @property
    def edit(self) -> str:
        return self.proposal.best.edit.name

    @property
    def slip(self) -> str:
        return self.proposal.best.edit.slip

    @property
    def changed(self) -> frozenset[str]:
        return self.proposal.best.edit.changed

    def values(self) -> str:
        """What the edit changes, "0.0123 -> 1.23e-05" for one value, else its name."""
        b, a = self.before, self.proposal.best.edit.written
        pairs = [(x, y) for x, y in zip(b.entries, a.entries, strict=True) if x != y]
        if b.mass != a.mass:
            pairs.insert(0, (b.mass, a.mass))
        if len(pairs) == 1 and not np.any(b.xyz != a.xyz):
            return f"{pairs[0][0]:.4g} -> {pairs[0][1]:.4g}"
        return ""

    def sentence(self) -> str:
        """The proposal in words, as ``check`` says it."""
        best = self.proposal.best
        values = self.values()
        head = f"{best.edit.words}: {best.edit.name}" + (f" ({values})" if values else "")
        runner = self.proposal.runner_up
        if runner is None:
            tail = "; no other edit"
        elif runner.feasible:
            tail = f"; the next best, {runner.edit.name}, scores {self.proposal.margin:.1f} more"
        else:
            tail = f"; no other edit fits (the next best, {runner.edit.name}: {runner.why_not})"
        return (f"{head} makes the inertial valid and plausible, its tensor within "
                f"{100 * best.tensor_error:.0f} % of the geometry's{tail}")

    def as_dict(self) -> dict[str, object]:
        best, runner = self.proposal.best, self.proposal.runner_up
        return {"edit": best.edit.name, "slip": best.edit.slip, "words": best.edit.words,
                "changed": sorted(best.edit.changed), "score": best.score,
                "tensor_error": best.tensor_error,
                "margin": self.proposal.margin if math.isfinite(self.proposal.margin) else None,
                "runner_up": None if runner is None else {
                    "edit": runner.edit.name, "slip": runner.edit.slip,
                    "score": runner.score, "tensor_error": runner.tensor_error,
                    "feasible": runner.feasible, "why_not": runner.why_not or None},
                "text": self.sentence()}


def written_of(link: Link) -> Written | None:
    """The link's inertial as written, in the terms a slip is made in."""
    i = link.inertial
    if i is None:
        return None
    return Written(i.mass, np.asarray(i.origin.xyz, dtype=np.float64),
                   np.asarray(i.origin.rpy, dtype=np.float64),
                   np.array([i.ixx, i.ixy, i.ixz, i.iyy, i.iyz, i.izz], dtype=np.float64))


def link_solid(link: Link, meshes: MeshSource, cache: BoundsCache, options: FixOptions,
               urdf_dir: Path) -> Solid | None:
    """The homogeneous solid of the link's geometry (None: none, or it cannot be read)."""
    _, refs = select_geometry(link, options.geometry)
    if not refs:
        return None
    try:
        bounds = link_bounds(link.collisions + link.visuals, cache, urdf_dir)
        parts = [p for ref in refs for p in geometry_parts(ref, meshes, urdf_dir)]
        if bounds is None or not parts:
            return None
        volume = sum(-p.volume if p.cavity else p.volume for p in parts)
        unit = assemble(parts, MassSource("kept", 1.0)).total
    except (UrdfInertiaError, ValueError):
        return None
    if not volume > 0:
        return None
    return Solid(volume, unit.com, unit.inertia, bounds[0], bounds[1])


def _mass_fits_other_geometry(link: Link, mass: float, meshes: MeshSource,
                              cache: BoundsCache, options: FixOptions, urdf_dir: Path) -> bool:
    """The written mass has a plausible density in the link's other geometry (visual when
    the collision was searched): the searched geometry is then not the body (contact
    spheres, a marker, an envelope) and a mass slip is not what the numbers say.

    A slip of the whole inertial (mass and tensor in grams) cannot be told from geometry
    that is not the body by the numbers alone; the other geometry can tell them apart."""
    role, _ = select_geometry(link, options.geometry)
    other = {"collision": "visual", "visual": "collision"}.get(role)
    if other is None:
        return False
    alternative = replace(options, geometry=other)
    solid = link_solid(link, meshes, cache, alternative, urdf_dir)
    if solid is None:
        return False
    lo, hi = PLAUSIBLE_DENSITY
    return lo <= mass / solid.volume <= hi


def find_slip(link: Link, codes: set[str], meshes: MeshSource, cache: BoundsCache,
              options: FixOptions, urdf_dir: Path) -> SlipProposal | None:
    """The slip proposal for a link flagged with ``codes``, when one is clear."""
    if not options.slips or not codes & SLIP_TRIGGERS:
        return None
    w = written_of(link)
    if w is None or not np.all(np.isfinite(np.concatenate((w.xyz, w.rpy, w.entries)))):
        return None
    solid = link_solid(link, meshes, cache, options, urdf_dir)
    if solid is None:
        return None
    found = propose(w, solid, LIMITS)
    if found is None:
        return None
    if "mass" in found.best.edit.changed and _mass_fits_other_geometry(
            link, w.mass, meshes, cache, options, urdf_dir):
        return None
    edit = found.best.edit
    after = MassProperties(edit.written.mass, edit.written.xyz, edit.tensor())
    return SlipProposal(link.name, found, w, after)
