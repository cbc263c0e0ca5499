"""The author's conventions, inferred once per file from all links jointly.

An exporter or an author who writes one link with the tensor about the joint origin, the
products of inertia with CAD's sign or the masses in grams usually writes every link so.
Judged link by link, only the links where the slip is blatant get corrected, and their
siblings keep the same mistake. So each convention (:data:`CONVENTIONS`: one edit of
:mod:`urdfinertia.inertia.slips` applied to the whole file) is scored on every link with a
body to hold it against, and it is inferred when:

- at least :data:`MIN_SUPPORT` links, and at least :data:`SUPPORT_SHARE` of the links it
  would change, support it: the edit makes them valid and plausible, or clearly likelier
  (by :data:`~urdfinertia.inertia.slips.MARGIN`) than as written;
- at most :data:`CONTRADICTION_SHARE` of the supporting count contradict it: a link valid
  and plausible as written that the edit makes clearly less likely or invalid.

An inferred convention is undone on every link where the edit gives values ``check``
accepts (:data:`APPLY_LIMITS`: the error bar of a stand-in geometry aside) and does not
lower the likelihood (links it leaves as good as written, a CoM at the origin for the
parallel axis, are unaffected); the robot finding says how many links.

A robot assembled from sub-assemblies (a humanoid's arms exported apart from its legs)
may follow a convention in one limb only: the whole file then contradicts it. So a
convention the file does not support is tried on each chain of the kinematic tree (the
links between two branching points, :func:`chains`) with the same thresholds, over the
links no file-wide convention covers.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass

from urdfinertia.inertia.slips import MARGIN, Scored, Solid, Written, rank_edits
from urdfinertia.judge.slips import LIMITS

#: The file-wide conventions tried: the edit's name in :mod:`urdfinertia.inertia.slips`,
#: and how the summary says it.
CONVENTIONS = {
    "parallel axis removed": "the tensors are written about the link origin (the joint), "
                             "not the CoM",
    "products negated": "the products of inertia are written with CAD's sign "
                        "(+integral xy dm)",
    "mass and tensor x1e-3": "masses and tensors are written in grams",
    "mass x1e-3": "masses are written in grams",
    "tensor x1e-6": "tensors are written in kg mm^2",
    "tensor x1e-9": "tensors are written in g mm^2",
}
#: Links that must support a convention, at least.
MIN_SUPPORT = 3
#: Share of the links a convention changes that must support it.
SUPPORT_SHARE = 0.4
#: Contradicting links allowed, as a share of the supporting ones.
CONTRADICTION_SHARE = 0.25
#: An edit whose score moves by less than this (chi-square units) changes nothing worth
#: counting: the link neither supports nor contradicts.
NEUTRAL = 1.0


@dataclass(frozen=True)
class Convention:
    """An inferred convention: the edit, its words, and the links it is undone on."""

    edit: str
    words: str
    support: int
    informative: int
    contradict: int
    links: tuple[str, ...]
    chain: str | None = None
    """The first link of the chain it holds in (None: the whole file)."""

    def summary(self) -> str:
        where = "" if self.chain is None else f" (in the chain from {self.chain})"
        return (f"{self.words}{where}: {self.support} of {self.informative} links it would "
                f"change support it, {self.contradict} contradict it; undone on "
                f"{len(self.links)} link(s)")


#: Where an inferred convention is undone: the edit must give values ``check`` accepts,
#: but not within the error bar of the link's stand-in geometry (a CAD value that differs
#: from its collision box by more than the bar is still the author's value).
APPLY_LIMITS = dataclasses.replace(LIMITS, band=math.inf)


def _scores(w: Written, solid: Solid) -> tuple[Scored, dict[str, Scored], dict[str, bool]]:
    """The value as written, each convention's edit, and whether each edit (and, under
    "none", the value as written) gives values ``check`` accepts (:data:`APPLY_LIMITS`)."""
    ranked = rank_edits(w, solid, LIMITS)
    none = next(s for s in ranked if s.edit.slip == "none")
    accepted = {s.edit.name: s.feasible for s in rank_edits(w, solid, APPLY_LIMITS)
                if s.edit.name in CONVENTIONS or s.edit.slip == "none"}
    return none, {s.edit.name: s for s in ranked if s.edit.name in CONVENTIONS}, accepted


def infer_conventions(written: Mapping[str, Written], solids: Mapping[str, Solid],
                      chains: Sequence[Sequence[str]] = ()) -> list[Convention]:
    """The conventions the links support (module doc); ``written`` and ``solids`` by link
    name (links without a body to hold them against are left out), ``chains`` the links of
    each chain of the tree, first link first."""
    scored = {name: _scores(w, solids[name]) for name, w in written.items()
              if name in solids}
    found = _infer(scored, None)
    covered = {n for c in found for n in c.links}
    for chain in chains:
        within = {n: scored[n] for n in chain if n in scored and n not in covered}
        if len(within) >= MIN_SUPPORT:
            found.extend(_infer(within, chain[0]))
    # best supported first: a link two conventions would edit takes the first (one edit)
    found.sort(key=lambda c: (c.chain is not None, -c.support, c.contradict, c.edit))
    return found


def _infer(scored: Mapping[str, tuple[Scored, dict[str, Scored], dict[str, bool]]],
           chain: str | None) -> list[Convention]:
    found = []
    for edit, words in CONVENTIONS.items():
        support = contradict = informative = 0
        apply: list[str] = []
        for name, (none, edits, accepted) in scored.items():
            s = edits.get(edit)
            if s is None:
                continue  # the edit does not change this link's values
            delta = s.score - none.score
            if abs(delta) < NEUTRAL and s.feasible == none.feasible:
                continue
            informative += 1
            if s.feasible and (not none.feasible or delta <= -MARGIN):
                support += 1
            elif none.feasible and (not s.feasible or delta >= MARGIN):
                contradict += 1
            # undone where the edit gives accepted values no less likely than as written
            # (or where only the edit's values are accepted: an invalid value as written)
            if accepted.get(edit, False) and (delta <= 0 or not accepted.get(none.edit.name,
                                                                              False)):
                apply.append(name)
        if support >= MIN_SUPPORT and support >= SUPPORT_SHARE * informative \
                and contradict <= CONTRADICTION_SHARE * support:
            found.append(Convention(edit, words, support, informative, contradict,
                                    tuple(apply), chain))
    return found


def chains(edges: Iterable[tuple[str, str]]) -> list[list[str]]:
    """The chains of a kinematic tree given as (parent, child) edges: the maximal paths
    whose links (but the last) have one child each, every chain starting at a child of
    the root or of a branching link."""
    children: dict[str, list[str]] = {}
    parents: set[str] = set()
    kids: set[str] = set()
    for parent, child in edges:
        children.setdefault(parent, []).append(child)
        parents.add(parent)
        kids.add(child)
    out = []
    starts = [c for p in children if p not in kids or len(children[p]) > 1
              for c in children[p]]
    for start in starts:
        chain, seen = [start], {start}
        # a cycle (a joint whose child is its parent, or a loop) ends the chain
        while len(children.get(chain[-1], ())) == 1 and children[chain[-1]][0] not in seen:
            chain.append(children[chain[-1]][0])
            seen.add(chain[-1])
        out.append(chain)
    return out
