"""The slip search on a link: what the author meant, before any written value is thrown away.

For a link the judgement flags (:data:`SLIP_TRIGGERS`), the written inertial and the
homogeneous solid of the geometry that represents the body (:mod:`.geometry`) go to
:func:`urdfinertia.inertia.slips.propose`; a proposal is one edit of the written values
(``izz x1e-3``) that makes the inertial valid and fits the body (CoM inside, radius of
gyration within the part, a density a robot part has when the edit changes the mass, the
tensor within the geometry's error bar) and is clearly better than every other edit.
Whether a proposal that moves the robot's mass has a witness is the robot's judgement
(:mod:`.robot`). ``--no-slips`` (``FixOptions.slips=False``) turns the search off.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from urdfinertia.body.errorbar import MODEL_P80
from urdfinertia.body.evidence import LinkEvidence
from urdfinertia.body.options import PLAUSIBLE_DENSITY
from urdfinertia.descriptions.model import Link
from urdfinertia.inertia.massprops import MassProperties
from urdfinertia.inertia.slips import Limits, Proposal, Written, propose
from urdfinertia.judge.geometry import (
    COM_OUTSIDE_ERROR,
    COM_OUTSIDE_WARN,
    INERTIA_RATIO_LIMIT,
    GeometryJudgement,
)
from urdfinertia.rules import Rule

#: Findings after which the slip search runs: the written values are invalid, or
#: implausible against the body's geometry, or against the robot's masses.
SLIP_TRIGGERS = frozenset({
    Rule.MASS_ABSURD, Rule.INERTIA_ABSURD, Rule.INERTIA_NOT_SYMMETRIC,
    Rule.INERTIA_NOT_POSITIVE_DEFINITE, Rule.TRIANGLE_INEQUALITY, Rule.IMPLAUSIBLE_DENSITY,
    Rule.COM_OUTSIDE_GEOMETRY, Rule.COM_FAR_OUTSIDE_GEOMETRY, Rule.INERTIA_VS_GEOMETRY,
    Rule.MASS_DISTRIBUTION})
#: What ``check`` accepts, with the error bar of a tensor whose CoM is not known (the
#: widest calibrated band): an edit outside it is not proposed.
LIMITS = Limits(density=PLAUSIBLE_DENSITY, com_outside=COM_OUTSIDE_WARN,
                ratio=INERTIA_RATIO_LIMIT, band=MODEL_P80, com_slip=COM_OUTSIDE_ERROR)


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


def finite_written(link: Link) -> Written | None:
    """:func:`written_of` when every value is finite and the mass positive (a slip is
    searched in such values only)."""
    w = written_of(link)
    if w is None or not (math.isfinite(w.mass) and w.mass > 0) \
            or not np.all(np.isfinite(np.concatenate((w.xyz, w.rpy, w.entries)))):
        return None
    with np.errstate(all="ignore"):
        if not np.isfinite(w.mass * float(np.sum(w.entries ** 2))):
            return None
    return w


def find_slip(ev: LinkEvidence, rules: frozenset[Rule] | set[Rule],
              judged: GeometryJudgement) -> SlipProposal | None:
    """The slip proposal for a link flagged with ``rules``, when one is clear."""
    if not ev.options.slips or not rules & SLIP_TRIGGERS:
        return None
    w = finite_written(ev.link)
    solid = judged.solid
    if w is None or solid is None or not solid.volume > 0:
        return None
    found = propose(w, solid, LIMITS)
    if found is None:
        return None
    edit = found.best.edit
    after = MassProperties(edit.written.mass, edit.written.xyz, edit.tensor())
    return SlipProposal(ev.name, found, w, after)
