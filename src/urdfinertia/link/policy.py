"""Which links ``fix`` recomputes, and which of their values it keeps: the one home of that rule.

The default (``recompute="needed"``) recomputes only the links whose inertial is wrong, as
judged by the same rules ``check`` reports (:mod:`urdfinertia.link.plausibility`): missing
on a moving link, invalid (NaN, non-positive mass, not positive definite, triangle
inequality, a zero tensor with a mass), a placeholder, or implausible against the geometry
(implied density, CoM outside the geometry, tensor size, unit slips). Every other link is
kept byte for byte. A recomputed link keeps what is trustworthy: a plausible mass, and a CoM
inside the geometry (the tensor is then the homogeneous solid's own central tensor written at
the kept CoM: measured, shifting it there with the parallel-axis term makes the tail worse).

Massless links stay massless: a link without ``<inertial>`` or with mass 0 that does not
move (on a fixed joint, or the root) is a frame whose mass is lumped elsewhere. A link
whose inertial is invalid but which has no geometry gets ``--repair-only``'s minimal lift.

``recompute="all"`` is the behaviour before this policy (every link with geometry);
``recompute="links"`` recomputes the links named. Links named in a spec are always
recomputed. ``check``, ``compare`` and ``report`` print the same :class:`Decision`.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from urdfinertia.cache.library import MeshLibrary
from urdfinertia.descriptions.inertial import RawInertial
from urdfinertia.descriptions.kinematics import Kinematics
from urdfinertia.descriptions.model import Link, Robot
from urdfinertia.link.bounds import BoundsCache
from urdfinertia.link.options import FixOptions, select_geometry
from urdfinertia.link.plausibility import (
    Bounds,
    Finding,
    geometry_judgement,
    unit_slip,
    value_findings,
)

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
#: A kept CoM lies in the geometry's box grown by this fraction of its diagonal on every
#: side: collision geometry is often a simplified, slightly smaller hull of the CAD part.
COM_KEEP_MARGIN = 0.02

ACTIONS = ("recompute", "keep", "repair", "leave")


@dataclass(frozen=True)
class Decision:
    """What ``fix`` does with one link, and why.

    action : "recompute" (from geometry or spec), "keep" (byte for byte, plausible),
        "repair" (minimal lift of an invalid tensor: nothing to recompute from) or "leave"
        (as it is, e.g. a massless frame).
    why : the reason, e.g. "inertia-zero, com-outside-geometry" or "plausible".
    keep_mass, keep_com : for "recompute", whether the written mass and CoM are trusted.
    bounds : the geometry's box in the link frame, when it was read.
    """

    link: str
    action: str
    why: str
    keep_mass: bool = False
    keep_com: bool = False
    bounds: Bounds | None = None

    def __post_init__(self) -> None:
        if self.action not in ACTIONS:
            raise ValueError(f"action must be one of {ACTIONS}")

    def describe(self, done: bool = True) -> str:
        """"kept: plausible" after a fix, "would be kept: plausible" before one."""
        if self.action == "leave":
            return self.why  # already says what happens ("... left as it is")
        past = {"recompute": "recomputed", "keep": "kept", "repair": "repaired"}[self.action]
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
    name = link.name
    if _named_in_spec(options, name):
        findings = value_findings(link, kin, robot)
        trust = not ({f.code for f in findings} & MASS_DISTRUST)
        return Decision(name, "recompute", "named in the spec", keep_mass=trust)
    if options.recompute == "all":
        return Decision(name, "recompute", "--all", keep_mass=True)
    if options.recompute == "links":
        if name in options.links:
            return Decision(name, "recompute", "named by --links", keep_mass=True)
        return Decision(name, "keep", "not named by --links")
    massless = link.inertial is None or link.inertial.mass == 0
    if massless and not kin.moves(name):
        if name in kin.parent_joint:
            return Decision(name, "leave", "massless, on a fixed joint: left as it is")
        what = "without <inertial>" if link.inertial is None else "with mass 0"
        return Decision(name, "leave", f"root link {what}: left as it is (a floating base "
                        "needs --links NAME or --all)")
    findings = value_findings(link, kin, robot)
    codes = {f.code for f in findings if f.link == name}
    if codes == {"inertia-zero"} and not kin.moves(name) and name in kin.parent_joint \
            and not (link.collisions or link.visuals):
        # a frame with a token mass (so101's gripper_frame_link: 1e-9 kg, zero tensor):
        # simulators merge it into its parent; a made-up tensor of that size is one MuJoCo
        # refuses (eigenvalues below its 1e-15 floor), where it took the zero tensor
        return Decision(name, "leave", "frame on a fixed joint with a zero tensor and "
                        "nothing to compute from: left as it is")
    bounds = density = None
    if link.inertial is not None and (link.collisions or link.visuals):
        judged = geometry_judgement(link, meshes, cache, options, urdf_dir)
        findings += judged.findings
        bounds, density = judged.bounds, judged.density
    return decide_from_findings(link, findings, bounds, density, options)


def decide_from_findings(link: Link, findings: list[Finding], bounds: Bounds | None,
                         density: float | None, options: FixOptions) -> Decision:
    """The default policy for a link that is not a massless frame, from its findings.

    ``density`` is the written mass over the geometry's volume (kg/m^3), when known.
    """
    name = link.name
    codes = {f.code for f in findings if f.link == name}
    slip = unit_slip(density) if density is not None and "implausible-density" in codes else None
    note = ""
    if slip is not None and slip[1] == "geometry":
        codes -= GEOMETRY_SLIP_CODES
        note = f" (implausible density explained by the geometry: {slip[2]})"
    triggers = [c for c in RECOMPUTE_CODES if c in codes]
    if not triggers:
        unread = "geometry-unreadable" in codes
        return Decision(name, "keep", "plausible" + note + (
            " (geometry unreadable: checked as written only)" if unread else ""))
    why = ", ".join(triggers) + note
    _, refs = select_geometry(link, options.geometry)
    if not refs:
        if codes & (INVALID_CODES | {"missing-inertial"}):
            return Decision(name, "repair", f"{why}; no geometry to recompute from")
        return Decision(name, "leave", f"{why}; no geometry to recompute from: left as it is")
    keep_mass = not (codes & MASS_DISTRUST)
    keep_com = keep_mass and not (codes & COM_DISTRUST) and _inside(link, bounds)
    return Decision(name, "recompute", why, keep_mass=keep_mass, keep_com=keep_com,
                    bounds=bounds)


def _inside(link: Link, bounds: Bounds | None) -> bool:
    """The written CoM lies in the geometry's box (grown by :data:`COM_KEEP_MARGIN`)."""
    if link.inertial is None or bounds is None:
        return False
    com = RawInertial.from_inertial(link.inertial).com
    lo, hi = bounds
    margin = COM_KEEP_MARGIN * float(np.linalg.norm(hi - lo))
    return bool(np.all(np.isfinite(com)) and np.all(com >= lo - margin)
                and np.all(com <= hi + margin))
