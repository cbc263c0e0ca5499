"""Which links ``fix`` recomputes, and which of their values it keeps: the one home of that rule.

The default (``recompute="needed"``) recomputes only the links whose inertial is wrong, as
judged by the same rules ``check`` reports (:mod:`urdfinertia.judge.plausibility`): missing
on a moving link, invalid (NaN, non-positive mass, not positive definite, triangle
inequality, a zero tensor with a mass), a placeholder, or implausible against the geometry
(implied density, CoM outside the geometry, tensor size, unit slips). Every other link is
kept byte for byte. A recomputed link keeps what is trustworthy: a plausible mass, and a CoM
inside the geometry (the tensor is then the homogeneous solid's own central tensor written at
the kept CoM: measured, shifting it there with the parallel-axis term makes the tail worse).

Massless links stay massless: a link without ``<inertial>`` or with mass 0 that does not
move (on a fixed joint, or the root) is a frame whose mass is lumped elsewhere. A link
whose inertial is invalid but which has no geometry gets ``--repair-only``'s minimal lift.

Nothing is derived from geometry that is not the body (:func:`decide_from_findings`): a
link whose geometry could not be read, or whose implied density no material has, keeps a
valid inertial as written and gets the minimal repair of an invalid one.

``recompute="all"`` recomputes every link with geometry; ``recompute="links"`` the links
named. Links named in a spec are always recomputed. Every command renders the same
decision (:class:`~urdfinertia.plan.results.LinkResult`).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from urdfinertia.body.bounds import BoundsCache
from urdfinertia.body.options import PLAUSIBLE_DENSITY, FixOptions, select_geometry
from urdfinertia.cache.library import MeshLibrary
from urdfinertia.descriptions.inertial import RawInertial
from urdfinertia.descriptions.kinematics import Kinematics
from urdfinertia.descriptions.model import Link, Robot
from urdfinertia.judge.plausibility import (
    Bounds,
    Finding,
    geometry_judgement,
    reference_findings,
    unit_slip,
    value_findings,
)
from urdfinertia.judge.slips import SLIP_TRIGGERS, SlipProposal, find_slip
from urdfinertia.plan.results import Action

#: Findings that make ``fix`` recompute a link by default.
RECOMPUTE_CODES = (
    "missing-inertial", "mass-not-finite", "mass-not-positive", "com-not-finite",
    "inertia-not-finite", "inertia-zero", "inertia-not-symmetric",
    "inertia-not-positive-definite", "triangle-inequality", "placeholder-inertia",
    "com-outside-geometry", "implausible-density", "inertia-vs-geometry",
)
#: Findings after which the written mass is not kept (and with it the CoM). A usable mass is
#: always kept by default, even at an implausible density: in example-robot-data every such
#: density comes from collision geometry that is not the part (a 0.29 kg laser in a 3 cm^3
#: cylinder, a 1 g IMU in a 1 mm cube), never from a mass in grams; the robot's weighed
#: masses are the best values known and its total mass must not change silently.
MASS_DISTRUST = frozenset({"missing-inertial", "mass-not-finite", "mass-not-positive"})
#: Findings that a unit slip of the geometry (mesh in mm without scale) explains: the
#: geometry, not the inertial, is wrong, and recomputing from it would make things worse.
GEOMETRY_SLIP_CODES = frozenset({"implausible-density", "inertia-vs-geometry"})
#: Findings after which the written CoM is not kept.
COM_DISTRUST = frozenset({"com-not-finite", "com-outside-geometry"})
#: Findings a simulator refuses: what the minimal repair is for when nothing can be computed.
INVALID_CODES = frozenset({"mass-not-finite", "mass-not-positive", "com-not-finite",
                           "inertia-not-finite", "inertia-zero", "inertia-not-symmetric",
                           "inertia-not-positive-definite", "triangle-inequality"})
#: Findings that hold the inertial against the geometry: meaningless when the geometry is
#: not the body.
GEOMETRY_CODES = frozenset({"implausible-density", "com-outside-geometry",
                            "inertia-vs-geometry"})
#: Findings that say the geometry could not be read (the link was not verified).
UNREAD_CODES = frozenset({"geometry-unreadable", "mesh-unresolved"})
#: A kept CoM lies in the geometry's box grown by this fraction of its diagonal on every
#: side: collision geometry is often a simplified, slightly smaller hull of the CAD part.
COM_KEEP_MARGIN = 0.02
#: A link lighter than this share of the robot's mass is a frame body (ANYmal C's 1 g hips,
#: Baxter's 0.1 g sensor frames): a placeholder tensor there changes nothing a simulator
#: does, so with nothing to derive it from it is left as it is without failing the run.
NEGLIGIBLE_SHARE = 1e-3

ACTIONS = tuple(a.value for a in Action)


@dataclass(frozen=True)
class Decision:
    """What ``fix`` does with one link, and why.

    action : :class:`Action`: recompute (from geometry or spec), keep (byte for byte,
        plausible), repair (minimal lift of an invalid tensor: nothing trustworthy to
        recompute from) or leave (as it is, e.g. a massless frame).
    why : the reason in plain words, e.g. "inertia-zero, com-outside-geometry".
    keep_mass, keep_com : for "recompute", whether the written mass and CoM are trusted.
    bounds : the geometry's box in the link frame, when it was read.
    findings : what ``check`` reports about the link as written (the decision's grounds).
    unverified : what of the link's geometry could not be read.
    slip : for "correct", the one edit of the written values that undoes a slip.
    """

    link: str
    action: Action
    why: str
    keep_mass: bool = False
    keep_com: bool = False
    bounds: Bounds | None = None
    findings: tuple[Finding, ...] = ()
    unverified: tuple[str, ...] = ()
    #: "leave" of a link that needed recomputing (a placeholder): left, never silently
    unresolved: bool = False
    #: "recompute" only from geometry whose implied density is plausible (the first
    #: geometry judged is not the body; another may be), else left
    plausible_only: bool = False
    slip: SlipProposal | None = None

    def __post_init__(self) -> None:
        if self.action not in ACTIONS:
            raise ValueError(f"action must be one of {ACTIONS}")
        object.__setattr__(self, "action", Action(self.action))

    def describe(self, done: bool = True) -> str:
        """"kept: plausible" after a fix, "would be kept: plausible" before one."""
        if self.action == "leave":
            return self.why  # already says what happens ("... left as it is")
        past = {"recompute": "recomputed", "keep": "kept", "repair": "repaired",
                "correct": "corrected"}[self.action]
        return f"{past if done else 'would be ' + past}: {self.why}"


def every_link(options: FixOptions) -> FixOptions:
    """``options`` asking for every link with geometry (what ``compare`` shows as B)."""
    return replace(options, recompute="all", links=())


def plan_robot(robot: Robot, options: FixOptions, meshes: MeshLibrary,
               urdf_dir: Path | None = None) -> dict[str, Decision]:
    """The decision for every link of ``robot``, by name."""
    if urdf_dir is None:
        urdf_dir = robot.path.parent if robot.path is not None else Path(".")
    kin = Kinematics(robot)
    cache = BoundsCache(meshes)
    return {link.name: decide_link(link, robot, kin, options, meshes, cache, urdf_dir)
            for link in robot.links}


def _named_in_spec(options: FixOptions, name: str) -> bool:
    spec = options.spec
    return spec is not None and spec.link(name) is not None


def decide_link(link: Link, robot: Robot, kin: Kinematics, options: FixOptions,
                meshes: MeshLibrary, cache: BoundsCache, urdf_dir: Path) -> Decision:
    """The link's findings (as ``check`` reports them) and the decision taken from them."""
    findings = value_findings(link, kin, robot) + reference_findings(link, options, urdf_dir)
    bounds = density = None
    outgrows = False
    if link.inertial is not None and (link.collisions or link.visuals):
        judged = geometry_judgement(link, meshes, cache, options, urdf_dir)
        findings += judged.findings
        bounds, density, outgrows = judged.bounds, judged.density, judged.outgrows
    # each unresolved mesh once: "geometry-unreadable" repeats an unresolved one's cause
    mine = [f for f in findings if f.link == link.name]
    unverified = tuple(f.message for f in mine if f.code == "mesh-unresolved") or tuple(
        f.message for f in mine if f.code == "geometry-unreadable")
    decision = _decide(link, kin, findings, bounds, density, options, outgrows,
                       _negligible(link, robot))
    decision, findings = _slip(link, decision, findings, options, meshes, cache, urdf_dir)
    return replace(decision, findings=tuple(findings), unverified=unverified)


def _slip(link: Link, decision: Decision, findings: list[Finding], options: FixOptions,
          meshes: MeshLibrary, cache: BoundsCache, urdf_dir: Path,
          ) -> tuple[Decision, list[Finding]]:
    """A clear one-edit slip (:mod:`urdfinertia.judge.slips`) of a flagged link under the
    default policy: the proposal joins the findings and is applied instead of deriving the
    inertial from the geometry, which keeps every value the slip did not touch."""
    if options.recompute != "needed" or _named_in_spec(options, link.name) \
            or decision.action == Action.KEEP and decision.why == "plausible":
        return decision, findings
    codes = {f.code for f in findings if f.link == link.name}
    found = find_slip(link, codes, meshes, cache, options, urdf_dir)
    if found is None:
        return decision, findings
    line = link.inertial.line if link.inertial is not None else None
    note = Finding(link.name, "warning", "slip-proposed", found.sentence(), line)
    triggers = ", ".join(sorted(codes & SLIP_TRIGGERS))
    return (Decision(link.name, Action.CORRECT, f"{found.edit} (slip: {triggers})",
                     bounds=decision.bounds, slip=found), [*findings, note])


def _decide(link: Link, kin: Kinematics, findings: list[Finding], bounds: Bounds | None,
            density: float | None, options: FixOptions, outgrows: bool,
            negligible: bool) -> Decision:
    name = link.name
    if _named_in_spec(options, name):
        trust = not ({f.code for f in findings} & MASS_DISTRUST)
        return Decision(name, Action.RECOMPUTE, "named in the spec", keep_mass=trust)
    if options.recompute == "all":
        return Decision(name, Action.RECOMPUTE, "every link asked for", keep_mass=True)
    if options.recompute == "links":
        if name in options.links:
            return Decision(name, Action.RECOMPUTE, "named", keep_mass=True)
        return Decision(name, Action.KEEP, "not named")
    massless = link.inertial is None or link.inertial.mass == 0
    if massless and not kin.moves(name):
        if name in kin.parent_joint:
            return Decision(name, Action.LEAVE, "massless, on a fixed joint: left as it is")
        what = "without <inertial>" if link.inertial is None else "with mass 0"
        return Decision(name, Action.LEAVE, f"root link {what}: left as it is (a floating "
                        "base is recomputed only when named)")
    codes = {f.code for f in findings if f.link == name}
    if codes - UNREAD_CODES == {"inertia-zero"} and not kin.moves(name) \
            and name in kin.parent_joint and not (link.collisions or link.visuals):
        # a frame with a token mass (so101's gripper_frame_link: 1e-9 kg, zero tensor):
        # simulators merge it into its parent; a made-up tensor of that size is one MuJoCo
        # refuses (eigenvalues below its 1e-15 floor), where it took the zero tensor
        return Decision(name, Action.LEAVE, "frame on a fixed joint with a zero tensor and "
                        "nothing to compute from: left as it is")
    return decide_from_findings(link, findings, bounds, density, options, outgrows,
                                negligible=negligible)


def _negligible(link: Link, robot: Robot) -> bool:
    """``link``'s written mass is below :data:`NEGLIGIBLE_SHARE` of the robot's."""
    if link.inertial is None:
        return False
    masses = [other.inertial.mass for other in robot.links if other.inertial is not None]
    total = sum(m for m in masses if np.isfinite(m) and m > 0)
    mass = link.inertial.mass
    return bool(np.isfinite(mass) and 0 < mass < NEGLIGIBLE_SHARE * total)


def decide_from_findings(link: Link, findings: list[Finding], bounds: Bounds | None,
                         density: float | None, options: FixOptions,
                         outgrows: bool = False, negligible: bool = False) -> Decision:
    """The default policy for a link that is not a massless frame, from its findings.

    ``density`` is the written mass over the geometry's volume (kg/m^3), when known;
    ``outgrows``: the written body cannot lie in the geometry (CoM outside its box, tensor
    beyond all the mass on the box's far corners).

    A derived value must be more trustworthy than the one it replaces, so nothing is
    derived from geometry that is not the body: geometry that could not be read, or whose
    implied density no material has (a 1 cm marker box holding a motor's mass, a large
    envelope around a light link), or in which the written body cannot lie. There a valid
    inertial is kept as written and an invalid one gets the minimal repair, each with the
    reason.
    """
    name = link.name
    codes = {f.code for f in findings if f.link == name}
    slip = unit_slip(density) if density is not None and "implausible-density" in codes else None
    note = ""
    if slip is not None and slip[1] == "geometry":
        codes -= GEOMETRY_SLIP_CODES
        note = f" (implausible density explained by the geometry: {slip[2]})"
    not_body = None
    if "implausible-density" in codes and density is not None:
        not_body = not_the_body(density)
    elif outgrows and codes & MASS_DISTRUST == set():
        not_body = ("geometry is a marker, not the body (the written CoM lies more than a "
                    "box diagonal outside it, the tensor beyond all the mass on its corners)")
    if not_body is not None:
        codes -= GEOMETRY_CODES
    unread = link.inertial is not None and bool(codes & UNREAD_CODES)
    triggers = [c for c in RECOMPUTE_CODES if c in codes]
    if not triggers:
        if not_body is not None:
            return Decision(name, Action.KEEP, not_body)
        if unread:
            return Decision(name, Action.KEEP, "valid as written; not verified against its "
                            "geometry (unreadable)")
        return Decision(name, Action.KEEP, "plausible" + note)
    why = ", ".join(triggers) + note
    _, refs = select_geometry(link, options.geometry)
    invalid = bool(codes & (INVALID_CODES | {"missing-inertial"}))
    if not_body is not None and not unread and triggers and options.geometry == "auto" \
            and not negligible and len([r for r in (link.collisions, link.visuals) if r]) > 1:
        # the geometry judged is not the body; the link's other geometry may be
        return Decision(name, Action.RECOMPUTE, f"{why}; {not_body}", keep_mass=True,
                        keep_com=_inside(link, bounds), bounds=bounds, plausible_only=True)
    if not_body is not None or unread or not refs:
        cause = (not_body if not_body is not None else
                 "geometry could not be read" if refs else "no geometry to recompute from")
        if invalid:
            return Decision(name, Action.REPAIR, f"{why}; {cause}")
        if negligible:  # a frame body: nothing a simulator does depends on its tensor
            return Decision(name, Action.LEAVE, f"{why}; {cause}: left as it is (under "
                            f"{100 * NEGLIGIBLE_SHARE:g} % of the robot's mass)")
        return Decision(name, Action.LEAVE, f"{why}; {cause}: left as it is",
                        unresolved=True)
    keep_mass = not (codes & MASS_DISTRUST)
    keep_com = keep_mass and not (codes & COM_DISTRUST) and _inside(link, bounds)
    return Decision(name, Action.RECOMPUTE, why, keep_mass=keep_mass, keep_com=keep_com,
                    bounds=bounds)


def not_the_body(density: float) -> str:
    """Why geometry with this implied density (kg/m^3) cannot be the link's body."""
    lo, hi = PLAUSIBLE_DENSITY
    if density > hi:
        return (f"geometry is a marker, not the body (implied density {density:.3g} kg/m^3, "
                f"denser than any material)")
    return (f"geometry is an envelope, not the body (implied density {density:.3g} kg/m^3, "
            f"lighter than any solid part, below {lo:g})")


def _inside(link: Link, bounds: Bounds | None) -> bool:
    """The written CoM lies in the geometry's box (grown by :data:`COM_KEEP_MARGIN`)."""
    if link.inertial is None or bounds is None:
        return False
    com = RawInertial.from_inertial(link.inertial).com
    lo, hi = bounds
    margin = COM_KEEP_MARGIN * float(np.linalg.norm(hi - lo))
    return bool(np.all(np.isfinite(com)) and np.all(com >= lo - margin)
                and np.all(com <= hi + margin))
