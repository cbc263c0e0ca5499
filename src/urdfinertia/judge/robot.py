"""The judgement of a robot: every link judged with the whole robot as evidence.

:func:`judge_robot` is the one place a link's findings are made. Per link: what the reader
read past, the written values alone (:mod:`.values`), the values against the geometry that
represents the body (:mod:`.geometry`), a closed form computed on purpose
(:mod:`.closed_form`), realizability inside the geometry (:mod:`.realizability`) and the
slip search (:mod:`.slips`). Then the robot as evidence:

- **mass distribution**: a link heavier than the rest of the robot together, or ten times
  its mirror twin, whose mass a unit slip (grams) makes fit its body, is an error with
  that slip (a drone's body outweighing its rotors is a design: no slip fits it);
- **conventions** (:mod:`.conventions`): an author's convention inferred from all links
  jointly and undone on every link the evidence supports;
- **copies** (:mod:`.twins`): an inertial copied from another link whose geometry differs;
- **twins and identical values**: identical inputs get identical verdicts, and mirror
  twins that disagree say which side fits its geometry;
- **witnesses**: a correction that moves the robot's total mass by more than
  :data:`WITNESS_SHARE` needs a witness (the mass distribution, a convention, a mirror twin
  of the corrected mass, the robot's densities, or a total-mass target); without one it is
  proposed, not applied.

The result, a :class:`Judgement`, is what the plan (:mod:`urdfinertia.plan.policy`) decides
from. Nothing here writes or decides what ``fix`` does.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from urdfinertia.body.evidence import LinkEvidence, RobotEvidence
from urdfinertia.findings import Finding
from urdfinertia.inertia.massprops import MassProperties
from urdfinertia.inertia.slips import Proposal, Solid, Written, rank_edits
from urdfinertia.judge.closed_form import closed_form_factor, closed_form_finding
from urdfinertia.judge.conventions import Convention, chains, infer_conventions
from urdfinertia.judge.geometry import (
    AGAINST_CANDIDATE,
    GeometryJudgement,
    candidate_solid,
    judge_geometry,
)
from urdfinertia.judge.slips import LIMITS, SlipProposal, find_slip, finite_written
from urdfinertia.judge.twins import bodies_of, copy_findings, twin_findings, twin_names
from urdfinertia.judge.values import value_findings
from urdfinertia.rules import Rule

#: Findings that say some of a link's geometry could not be read: the link is not verified.
UNREAD = frozenset({Rule.MESH_UNRESOLVED, Rule.GEOMETRY_UNREADABLE, Rule.MESH_TOO_LARGE,
                    Rule.MESH_REFUSED, Rule.MESH_ABSURD})
#: A correction moving the robot's written mass by more than this share needs a witness.
WITNESS_SHARE = 0.01
#: A link this many times its mirror twin's mass is a slip, not a design.
TWIN_MASS_FACTOR = 10.0
#: Robots with fewer links of mass than this say nothing about one link's share.
MIN_MASSIVE_LINKS = 3
#: A link over this many times the median link mass is an outlier: not counted as the
#: "rest of the robot" another outlier is held against.
OUTLIER = 100.0
#: Two written masses within this relative difference are the same (a twin's witness).
SAME_MASS_RTOL = 0.05


@dataclass(frozen=True, eq=False)
class LinkJudgement:
    """Everything the judgement says about one link.

    Attributes
    ----------
    name : str
    findings : tuple of Finding
        What ``check`` reports about the link as written, in a stable order.
    geometry : GeometryJudgement
        The body the values were held against, and what it showed.
    slip : SlipProposal or None
        The one edit the judgement stands behind (a convention's, a witnessed slip's).
    convention : str or None
        The file convention ``slip`` undoes (its edit's name), if any.
    closed_form : float or None
        The factor by which the written tensor reproduces its own geometry's closed form.
    copy_of, copy_density : str or None, float or None
        The link this inertial was copied from, and that link's density (kg/m^3) over its
        own body: the copy's mass is derived at it.
    vouched_by : str or None
        The identical twin whose geometry the values fit (the values are kept as its are).
    unverified : tuple of Finding
        What of the link's geometry could not be read.
    """

    name: str
    findings: tuple[Finding, ...]
    geometry: GeometryJudgement
    slip: SlipProposal | None = None
    convention: str | None = None
    closed_form: float | None = None
    copy_of: str | None = None
    copy_density: float | None = None
    vouched_by: str | None = None
    unverified: tuple[Finding, ...] = ()

    @property
    def rules(self) -> frozenset[Rule]:
        return frozenset(f.rule for f in self.findings)


@dataclass(frozen=True, eq=False)
class Judgement:
    """The judgement of a robot: every link's, and what is said of the robot itself."""

    evidence: RobotEvidence
    links: Mapping[str, LinkJudgement]
    findings: tuple[Finding, ...] = ()
    conventions: tuple[Convention, ...] = ()

    def link(self, name: str) -> LinkJudgement:
        return self.links[name]


def judge_robot(evidence: RobotEvidence) -> Judgement:
    """Judge every link of the robot with the whole robot as evidence (module doc)."""
    per = {name: _judge_link(ev) for name, ev in evidence.links.items()}
    per = _mass_distribution(evidence, per)
    per = {name: _with_slip(evidence.links[name], j) for name, j in per.items()}
    conventions = _conventions(evidence, per)
    for c in conventions:
        for name in c.links:
            per[name] = _convention_slip(evidence.links[name], per[name], c)
    per = _copies_and_twins(evidence, per)
    per = _identical(evidence, per)
    per = {name: _witnessed(evidence, j, per, conventions) for name, j in per.items()}
    robot = tuple(Finding(Rule.CONVENTION_INFERRED, None, c.summary()) for c in conventions)
    return Judgement(evidence, per, robot, tuple(conventions))


def _judge_link(ev: LinkEvidence) -> LinkJudgement:
    from urdfinertia.judge.realizability import realizability_findings

    found: list[Finding] = list(ev.robot.robot.findings_of(ev.name))
    found += value_findings(ev)
    found += _implicit(ev)
    found += ev.unresolved
    geometry = GeometryJudgement()
    dropped: list[Finding] = []
    closed = None
    if ev.raw is not None and ev.has_geometry:
        geometry = judge_geometry(ev)
        found += geometry.findings
        if geometry.not_body is not None:
            found.append(Finding(Rule.GEOMETRY_NOT_BODY, ev.name, geometry.not_body,
                                 ev.link.line))
        if geometry.geometry_slip is not None:
            found.append(Finding(Rule.GEOMETRY_UNIT_SLIP, ev.name, "implausible density "
                                 f"explained by the geometry: {geometry.geometry_slip}",
                                 ev.link.line))
        primary = ev.primary
        if primary is not None:
            dropped = list(primary.dropped)
        elif ev.roles:  # the primary set exists but nothing of it could be read
            dropped = _unreadable(ev)
        said = {(f.rule, f.element) for f in ev.unresolved}
        found += [f for f in dropped if (f.rule, f.element) not in said]
        if geometry.rules & AGAINST_CANDIDATE:
            found_form = closed_form_factor(ev, ev.all_candidates())
            if found_form is not None:
                closed = found_form[0]
                if closed != 1.0:
                    found.append(closed_form_finding(ev, *found_form))
        found += realizability_findings(ev.link, ev.robot.bounds_cache, ev.robot.urdf_dir,
                                        ev.options.realizable)
    elif ev.raw is not None:
        found += realizability_findings(ev.link, ev.robot.bounds_cache, ev.robot.urdf_dir,
                                        ev.options.realizable)
    found = list(dict.fromkeys(found))
    unverified = tuple(f for f in found if f.rule in UNREAD)
    return LinkJudgement(ev.name, tuple(found), geometry, closed_form=closed,
                         unverified=unverified)


def _unreadable(ev: LinkEvidence) -> list[Finding]:
    """Why the primary set gave nothing: every element's error, as findings."""
    from urdfinertia.body.geometry_choice import usable_parts

    found: list[Finding] = []
    for role, refs in ev.roles:
        if role == ev.primary_role:
            usable_parts(ev.link, refs, ev.robot.meshes, ev.robot.urdf_dir, found)
    return found


def _implicit(ev: LinkEvidence) -> list[Finding]:
    """A link whose format's simulator computes its mass properties: judged on what it
    computes (MuJoCo from the geoms; a USD engine from the colliders, at the stated mass)."""
    implicit = ev.link.implicit
    if implicit is None or ev.link.inertial is not None:
        return []
    if implicit.mass is not None:
        return [Finding(Rule.USD_MASS_WITHOUT_TENSOR, ev.name, f"MassAPI states "
                        f"{implicit.mass:.6g} kg and no inertia: the engines derive CoM and "
                        "tensor from the colliders at that mass", ev.link.line, "inertial")]
    what = "its geoms" if implicit.source == "geoms" else "its colliders"
    engine = "MuJoCo" if implicit.source == "geoms" else "the engine"
    counted = ev.link.inertia_geometry if implicit.source == "geoms" else ev.link.collisions
    if ev.moves and not counted:
        return [Finding(Rule.MISSING_INERTIAL, ev.name, f"moving body without <inertial>, and "
                        f"{what} give {engine} no mass (none counts for inertia)",
                        ev.link.line)]
    if not counted:
        return []
    return [Finding(Rule.INERTIAL_FROM_GEOMS, ev.name, f"no <inertial>: {engine} computes mass, "
                    f"CoM and tensor from {what} ({len(counted)} element(s))", ev.link.line)]


def _mass_distribution(evidence: RobotEvidence, per: dict[str, LinkJudgement],
                       ) -> dict[str, LinkJudgement]:
    """A link heavier than the rest of the robot, or ten times its twin (module doc)."""
    masses = {name: evidence.usable_mass(name) for name in per}
    massive = [n for n, m in masses.items() if m > 0]
    median = float(np.median([masses[n] for n in massive])) if massive else 0.0
    # the rest of the robot: links that are no outliers themselves (two links in grams
    # would each hide the other's slip)
    ordinary = sum(m for m in masses.values() if 0 < m <= OUTLIER * median)
    out = dict(per)
    for name in massive:
        m = masses[name]
        others = ordinary - (m if m <= OUTLIER * median else 0.0)
        why = None
        if len(massive) >= MIN_MASSIVE_LINKS and m > others > 0:
            why = (f"{name} weighs {m:.4g} kg, more than the rest of the robot together "
                   f"({others:.4g} kg)")
        for twin in twin_names(name):
            t = masses.get(twin, 0.0)
            if t > 0 and m > TWIN_MASS_FACTOR * t:
                why = f"{name} weighs {m:.4g} kg, {m / t:.3g} times its mirror twin {twin}"
                break
        if why is None:
            continue
        edit = _mass_slip(evidence.robot.link(name), per[name].geometry.solid)
        if edit is None:
            continue
        inertial = evidence.robot.link(name).inertial
        line = inertial.line if inertial is not None else None
        found = Finding(Rule.MASS_DISTRIBUTION, name, f"{why}: {edit} makes it fit its body, "
                        "a slip, not a design", line, "inertial")
        out[name] = dataclasses.replace(per[name], findings=per[name].findings + (found,))
    return out


#: The edits of the mass a mass distribution's slip is sought among.
MASS_EDITS = ("mass x1e-3", "mass and tensor x1e-3")


def _mass_slip(link, solid: Solid | None) -> str | None:  # noqa: ANN001
    """The mass edit that makes the link's values fit its body (None: none does)."""
    w = finite_written(link)
    if w is None or solid is None:
        return None
    for s in rank_edits(w, solid, LIMITS):
        if s.edit.name in MASS_EDITS and s.feasible:
            return s.edit.name
    return None


def _with_slip(ev: LinkEvidence, j: LinkJudgement) -> LinkJudgement:
    if j.closed_form is not None:
        return j  # computed on purpose: no slip to undo
    found = find_slip(ev, j.rules, j.geometry)
    return j if found is None else dataclasses.replace(j, slip=found)


def _conventions(evidence: RobotEvidence, per: Mapping[str, LinkJudgement],
                 ) -> list[Convention]:
    if not evidence.options.slips or evidence.options.recompute != "needed":
        return []
    written: dict[str, Written] = {}
    solids: dict[str, Solid] = {}
    for name, j in per.items():
        w = finite_written(evidence.robot.link(name))
        solid = j.geometry.solid
        # a density a unit slip of the mass explains is evidence for a file in grams
        not_body = j.geometry.not_body is not None and j.geometry.mass_slip is None
        if w is None or solid is None or not_body or j.closed_form is not None:
            continue
        written[name], solids[name] = w, solid
    tree = chains((j.parent, j.child) for j in evidence.robot.joints)
    return infer_conventions(written, solids, tree)


def _convention_slip(ev: LinkEvidence, j: LinkJudgement, c: Convention) -> LinkJudgement:
    """The convention's edit of one link, as the slip the judgement stands behind (a link
    two conventions edit takes the first, the better supported)."""
    if j.convention is not None:
        return j
    w = finite_written(ev.link)
    solid = j.geometry.solid
    assert w is not None and solid is not None
    ranked = rank_edits(w, solid, LIMITS)
    best = next(s for s in ranked if s.edit.name == c.edit)
    none = next(s for s in ranked if s.edit.slip == "none")
    edit = best.edit
    after = MassProperties(edit.written.mass, edit.written.xyz, edit.tensor())
    margin = none.score - best.score if none.feasible else math.inf
    slip = SlipProposal(ev.name, Proposal(best, none, margin), w, after)
    return dataclasses.replace(j, slip=slip, convention=c.edit)


def _copies_and_twins(evidence: RobotEvidence, per: dict[str, LinkJudgement],
                      ) -> dict[str, LinkJudgement]:
    if not evidence.options.slips:
        return per
    robot = evidence.robot

    def solid_of(link):  # noqa: ANN001, ANN202
        j = per.get(link.name)
        if j is None or j.geometry.not_body is not None or j.geometry.geometry_slip:
            return None
        return j.geometry.solid

    def roles_of(link):  # noqa: ANN001, ANN202
        ev = evidence.links[link.name]
        bounds = ev.bounds
        out = {}
        if bounds is None:
            return out
        for role, _ in ev.roles:
            c = ev.candidate(role)
            if c is not None and not c.dropped:
                solid = candidate_solid(c, bounds)
                if solid is not None:
                    out[role] = solid
        return out

    bodies = bodies_of(robot, solid_of, roles_of)
    out = dict(per)
    for found, source in copy_findings(bodies):
        name = found.link
        assert name is not None
        src = per[source].geometry
        density = (evidence.usable_mass(source) / src.body.volume
                   if src.body is not None and src.body.volume > 0 else None)
        out[name] = dataclasses.replace(out[name], findings=out[name].findings + (found,),
                                        copy_of=source, copy_density=density)
    for found in twin_findings(bodies):
        name = found.link
        assert name is not None
        out[name] = dataclasses.replace(out[name], findings=out[name].findings + (found,))
    return out


def _key(ev: LinkEvidence) -> tuple | None:
    """What makes two links' written inertials identical: every value, as written (None:
    nothing written). Mirror twins differ in signs: they are judged each on its own."""
    i = ev.link.inertial
    if i is None:
        return None
    return (i.mass, i.ixx, i.iyy, i.izz, i.ixy, i.ixz, i.iyz, tuple(i.origin.xyz),
            tuple(i.origin.rpy))


def _identical(evidence: RobotEvidence, per: dict[str, LinkJudgement],
               ) -> dict[str, LinkJudgement]:
    """Identical inputs, identical verdicts (module doc): links with identical written
    values whose geometries mirror each other are judged as a group. When one member's
    own geometry agrees with the values, the others' geometric disagreement is no
    evidence (their geometry is the same, a mesh's round-off apart); when all disagree,
    the one edit that fits most of them is theirs."""
    groups: dict[tuple, list[str]] = {}
    for name, ev in evidence.links.items():
        key = _key(ev)
        if key is not None and not any(map(_nan, key[:7])):
            groups.setdefault(key, []).append(name)
    out = dict(per)
    for names in groups.values():
        if len(names) < 2:
            continue
        for group in _by_geometry(names, per):
            if len(group) < 2:
                continue
            agree = [n for n in group if not per[n].rules & (_GEOMETRIC | _INVALID)
                     and per[n].slip is None]
            if agree and len(agree) < len(group):
                for n in group:
                    if n not in agree and not per[n].rules & _INVALID:
                        out[n] = dataclasses.replace(
                            out[n], vouched_by=agree[0], slip=None, convention=None,
                            findings=out[n].findings + (Finding(
                                Rule.TWIN_VOUCHES, n, f"identical to {agree[0]}'s inertial, "
                                "which fits its geometry: kept as its twin is", None,
                                "inertial"),))
                continue
            edits = [s.edit for n in group if (s := per[n].slip) is not None]
            if edits and len(set(edits)) > 1:
                common = max(sorted(set(edits)), key=edits.count)
                for n in group:
                    slip = per[n].slip
                    if slip is not None and slip.edit != common:
                        out[n] = dataclasses.replace(out[n], slip=None)
    return out


_GEOMETRIC = frozenset({Rule.IMPLAUSIBLE_DENSITY, Rule.INERTIA_VS_GEOMETRY,
                        Rule.COM_OUTSIDE_GEOMETRY, Rule.COM_FAR_OUTSIDE_GEOMETRY})
_INVALID = frozenset({Rule.MASS_NOT_FINITE, Rule.MASS_NOT_POSITIVE, Rule.COM_NOT_FINITE,
                      Rule.INERTIA_NOT_FINITE, Rule.INERTIA_ZERO, Rule.INERTIA_NOT_SYMMETRIC,
                      Rule.INERTIA_NOT_POSITIVE_DEFINITE, Rule.TRIANGLE_INEQUALITY,
                      Rule.MASS_ABSURD, Rule.INERTIA_ABSURD, Rule.PLACEHOLDER_INERTIA,
                      Rule.MASS_DISTRIBUTION})


def _nan(x: float) -> bool:
    return isinstance(x, float) and not math.isfinite(x)


def _by_geometry(names: list[str], per: Mapping[str, LinkJudgement]) -> list[list[str]]:
    """``names`` split where their bodies' geometry differs (volume, or a corner of the box
    in the link frame, by more than 5 % of the box's size): identical values over the same
    geometry in the same place; links with no body each stand alone."""
    out: list[list[str]] = []
    for name in names:
        body = per[name].geometry.body
        sig = _signature(per[name].geometry)
        for group in out:
            other = _signature(per[group[0]].geometry)
            if body is not None and other is not None and sig is not None \
                    and abs(sig[0] - other[0]) <= 0.05 * max(sig[0], other[0]) \
                    and np.all(np.abs(sig[1:] - other[1:]) <= 0.05):
                group.append(name)
                break
        else:
            out.append([name])
    return out


def _signature(g: GeometryJudgement) -> np.ndarray | None:
    if g.body is None or g.bounds is None:
        return None
    lo, hi = np.asarray(g.bounds[0]), np.asarray(g.bounds[1])
    size = float(np.linalg.norm(hi - lo))
    return np.concatenate(([g.body.volume ** (1 / 3)], lo / size if size else lo,
                           hi / size if size else hi))


#: The robot's densities witness a mass correction when the corrected density lies within
#: this factor of the median of the other links' and the written one beyond its cube.
DENSITY_WITNESS = 3.0


def _density_witness(j: LinkJudgement, per: Mapping[str, LinkJudgement], after: float,
                     before: float) -> str | None:
    """The other links' implied densities (their written mass over their body's volume):
    a correction that brings the link among them, from far outside, is the robot's own
    evidence (a base written in grams among links in kilograms)."""
    body = j.geometry.body
    if body is None or not body.volume > 0:
        return None
    others = [d for n, o in per.items() if n != j.name and (d := o.geometry.density)
              is not None and o.geometry.not_body is None and math.isfinite(d) and d > 0]
    if len(others) < MIN_MASSIVE_LINKS:
        return None
    median = float(np.median(others))
    now, then = after / body.volume, before / body.volume
    near = max(now / median, median / now) <= DENSITY_WITNESS
    far = max(then / median, median / then) > DENSITY_WITNESS ** 3
    if near and far:
        return (f"the robot's densities (the corrected {now:.4g} kg/m^3 beside the other "
                f"{len(others)} links' median {median:.4g})")
    return None


def _witnessed(evidence: RobotEvidence, j: LinkJudgement, per: Mapping[str, LinkJudgement],
               conventions: tuple[Convention, ...] | list[Convention]) -> LinkJudgement:
    """A slip that moves the robot's mass by more than :data:`WITNESS_SHARE` stands only
    with a witness (module doc); either way it is said, as a ``slip-proposed`` finding."""
    if j.slip is None:
        return j
    slip = j.slip
    before = slip.before.mass
    after = float(slip.after.mass)
    total = evidence.total_mass
    line = j.findings[0].line if j.findings else None
    inertial = evidence.robot.link(j.name).inertial
    if inertial is not None:
        line = inertial.line
    moved = abs(after - before)
    witness = None
    if total > 0 and moved > WITNESS_SHARE * total:
        if j.convention is not None:
            witness = "a convention of the file"
        elif Rule.MASS_DISTRIBUTION in j.rules:
            witness = "the robot's mass distribution"
        else:
            for twin in twin_names(j.name):
                t = evidence.usable_mass(twin) if twin in per else 0.0
                if t > 0 and abs(t - after) <= SAME_MASS_RTOL * t:
                    witness = f"its mirror twin {twin} ({t:.4g} kg)"
                    break
            if witness is None:
                witness = _density_witness(j, per, after, before)
            target = evidence.options.total_mass
            if witness is None and target is not None \
                    and abs(total - moved * np.sign(before - after) - target) \
                    < abs(total - target):
                witness = f"the total-mass target {target:g} kg"
        if witness is None:
            note = Finding(Rule.SLIP_PROPOSED, j.name, slip.sentence() + (
                f"; not applied: it moves the robot's mass by {100 * moved / total:.3g} % "
                "and nothing witnesses it (a mirror twin, a convention of the file, the "
                "mass distribution, the robot's densities or --total-mass)"), line, "inertial")
            return dataclasses.replace(j, slip=None, convention=None,
                                       findings=j.findings + (note,))
    text = slip.sentence()
    if j.convention is not None:
        text = f"{text} (the file's convention: {slip.proposal.best.edit.words})"
    if witness is not None:
        text += f"; it moves the robot's mass by {100 * moved / total:.3g} %, witnessed by " \
                f"{witness}"
    return dataclasses.replace(j, findings=j.findings + (
        Finding(Rule.SLIP_PROPOSED, j.name, text, line, "inertial"),))
