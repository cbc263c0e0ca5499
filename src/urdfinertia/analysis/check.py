"""The ``check`` job: lint the inertials as written, per link, with a severity.

``check`` is ``fix``'s plan without writing: with geometry (the default) its findings are
those of the links' verdicts (:func:`urdfinertia.link.fix.link_verdicts`), the very
objects ``fix`` carries out, so what ``check`` says ``fix`` would recompute is what ``fix``
recomputes. The link's geometry is read for the checks that need it: CoM inside the
geometry's bounding box, implied density, and the tensor's size against what the geometry
allows for the written mass. ``geometry=False`` checks the written values alone.

A link whose geometry could not be read (a mesh that does not resolve or read) was not
verified: :attr:`CheckResult.unverified` lists them, and :meth:`CheckResult.exit_code`
counts them as a failure, since the check could not do what it was asked.

Severities: "error" (a simulator refuses or misbehaves), "warning" (very likely wrong),
"info" (worth knowing, e.g. masses lumped by fixed joints).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

# Findings and their rule ids, and the per-link rules, live one layer down, where
# ``fix``'s policy uses them too.
from urdfinertia.analysis.realizability import robot_realizability
from urdfinertia.analysis.statics import (
    DEFAULT_MARGIN,
    Statics,
    robot_statics,
    statics_findings,
    verdict_bodies,
    written_bodies,
)
from urdfinertia.cache.library import MeshLibrary, mesh_library
from urdfinertia.descriptions.inertial import RawInertial
from urdfinertia.descriptions.kinematics import FixedGroup, Kinematics
from urdfinertia.descriptions.model import Robot
from urdfinertia.inertia.massprops import MassProperties, combine
from urdfinertia.link.findings import (  # noqa: F401  (re-exported: check's API)
    RULES,
    SEVERITIES,
    Finding,
    Rule,
    rule_of,
)
from urdfinertia.link.fix import link_verdicts
from urdfinertia.link.options import FixOptions
from urdfinertia.link.plausibility import (  # noqa: F401  (re-exported: check's API)
    ABSURD_MASS,
    ABSURD_MOMENT,
    COM_OUTSIDE_ERROR,
    COM_OUTSIDE_WARN,
    INERTIA_RATIO_LIMIT,
    _moments,
    geometry_findings,
    reference_findings,
    value_findings,
)
from urdfinertia.link.results import LinkResult, Status
from urdfinertia.link.total_mass import (
    DEFAULT_MASS_TOLERANCE,
    MassTargetError,
    mass_targets,
    meet_targets,
    target_findings,
    untargeted,
)


@dataclass(frozen=True, eq=False)
class CheckResult:
    """What ``check`` found in one description, and what ``fix`` would do about it.

    links : every link's verdict (empty with ``geometry=False``: nothing was planned).
    findings : the robot's findings in link order, lumping notes last.
    """

    path: Path
    robot: Robot
    links: tuple[LinkResult, ...]
    findings: tuple[Finding, ...]
    #: total mass, whole CoM and per joint the gravity load (None: statics not asked for)
    statics: Statics | None = None

    @property
    def would_recompute(self) -> tuple[str, ...]:
        """Links ``fix`` (these options) would recompute from their geometry or spec."""
        return tuple(r.name for r in self.links if r.status == Status.RECOMPUTED)

    @property
    def would_change(self) -> tuple[str, ...]:
        """Links whose inertial ``fix`` would change (recomputed or repaired)."""
        return tuple(r.name for r in self.links if r.changed)

    @property
    def unverified(self) -> tuple[LinkResult, ...]:
        """Links some of whose geometry could not be read: they were not verified."""
        return tuple(r for r in self.links if r.unverified)

    def counts(self) -> dict[str, int]:
        """Findings by severity."""
        return {s: sum(f.severity == s for f in self.findings) for s in SEVERITIES}

    def exit_code(self, strict: bool = False) -> int:
        """1 when an error (a warning too with ``strict``) was found or a link could not be
        verified, else 0 (the command line's exit code without a baseline)."""
        bad = {"error", "warning"} if strict else {"error"}
        return 1 if self.unverified or any(f.severity in bad for f in self.findings) else 0


def check_robot(robot: Robot, *, meshes: MeshLibrary | None = None,
                options: FixOptions | None = None, geometry: bool = True) -> list[Finding]:
    """All findings for ``robot``, in link order, lumping notes last.

    With ``geometry`` (the default) the links' geometry is read (through ``meshes``, a new
    library when None) and the findings are those ``fix`` acts on; without it only the
    written values and mesh references are checked.
    """
    return list(check_description(robot, meshes=meshes, options=options,
                                  geometry=geometry).findings)


def check_description(robot: Robot, *, meshes: MeshLibrary | None = None,
                      options: FixOptions | None = None,
                      geometry: bool = True, statics: bool = True,
                      effort_margin: float = DEFAULT_MARGIN, realizable: str = "ellipsoid",
                      mass_tolerance: float = DEFAULT_MASS_TOLERANCE) -> CheckResult:
    """``check`` of a robot already read: findings and every link's verdict.

    With ``statics`` (the default) every joint's gravity load over its range is held
    against its effort limit (:mod:`urdfinertia.analysis.statics`): an error when it
    exceeds it, a warning within ``effort_margin`` of it.
    ``realizable`` is the region UI210 tests the written inertials in: "ellipsoid" (the
    geometry's bounding ellipsoid) or "hull" (its convex hull; slower).
    Target masses (``options.total_mass``, the spec's ``total_mass`` and ``[subtree.NAME]
    mass``) are held against the written masses: UI703 beyond ``mass_tolerance`` (a
    fraction); the plan is ``fix``'s with the targets, or without them where ``fix``
    would refuse them (the finding says so).
    """
    options = options or FixOptions()
    targeted = bool(mass_targets(robot, options))
    kin = Kinematics(robot)
    urdf_dir = robot.path.parent if robot.path is not None else Path(".")
    path = robot.path or Path("robot.urdf")
    findings: list[Finding] = list(problem_findings(robot))
    links: tuple[LinkResult, ...] = ()
    if geometry:
        if meshes is None:
            meshes = mesh_library(options.package_dirs, options.max_faces)
        links = link_verdicts(robot, untargeted(options) if targeted else options, meshes)
        if targeted:
            findings.extend(target_findings(robot, links, options, mass_tolerance))
            try:
                links = meet_targets(robot, links, options)[0]
            except MassTargetError:
                pass  # fix refuses the target: its plan without it (the finding says so)
        realizing = robot_realizability(robot.links, meshes, urdf_dir, realizable)
        for r in links:
            findings.extend(r.findings)
            findings.extend(f for f in realizing if f.link == r.name)
        if options.slips:  # what the author meant, across links: copies and twins
            from urdfinertia.analysis.twins import twin_findings

            findings.extend(twin_findings(robot, meshes, options, urdf_dir))
    else:
        for link in robot.links:
            findings.extend(value_findings(link, kin, robot))
            findings.extend(reference_findings(link, options, urdf_dir))
        if targeted:
            findings.extend(target_findings(robot, (), options, mass_tolerance))
    for group in kin.groups.values():
        findings.extend(lumped_findings(group, robot))
    held = None
    if statics:
        held = robot_statics(robot, verdict_bodies(links) if geometry else written_bodies(robot))
        findings.extend(statics_findings(robot, held, effort_margin))
    return CheckResult(path, robot, links, tuple(findings), held)


#: Severity and finding code of each problem the reader read past (what other loaders do
#: with it: urdfdom refuses a vector it cannot parse; MuJoCo refuses a zero-size geom).
_PROBLEM_FINDINGS = {
    "bad-number": ("error", "vector-unparseable"),
    "comma-vector": ("error", "vector-unparseable"),
    "unexpanded-substitution": ("error", "unexpanded-substitution"),
    "zero-size": ("warning", "zero-size-primitive"),
    "unsupported-shape": ("warning", "unsupported-geometry"),
    "missing-attribute": ("error", "missing-attribute"),
    "xml-declaration": ("warning", "xml-read-leniently"),
    "undeclared-prefix": ("warning", "xml-read-leniently"),
    "trailing-content": ("warning", "xml-read-leniently"),
}


def problem_findings(robot: Robot) -> list[Finding]:
    """What the reader read past (elements dropped, values read leniently), with lines."""
    out = []
    for p in robot.problems:
        severity, code = _PROBLEM_FINDINGS.get(p.code, (rule_of(p.code).severity, p.code))
        where = f"line {p.line}: " if p.line is not None else ""
        element = f"{p.element}: " if p.element else ""
        out.append(Finding(p.link, severity, code, f"{where}{element}{p.cause}", p.line))
    return out


def lumped_findings(group: FixedGroup, robot: Robot) -> list[Finding]:
    """Note the body that simulators merging fixed joints will see, when it has mass."""
    if len(group.members) < 2:
        return []
    raws = []
    for name, pose in zip(group.members, group.poses, strict=True):
        inertial = robot.link(name).inertial
        if inertial is not None:
            raws.append((name, pose, RawInertial.from_inertial(inertial)))
    carriers = [n for n, _, r in raws if np.isfinite(r.mass) and r.mass > 0]
    if not any(n != group.root for n in carriers):
        return []  # nothing is lumped onto the root
    names = ", ".join(group.members[1:6]) + (", ..." if len(group.members) > 6 else "")
    head = f"fixed joints merge {len(group.members) - 1} link(s) ({names}) into it"
    bodies: list[MassProperties] = []
    for _, pose, r in raws:
        if r.mass == 0 and not np.any(r.inertia):
            continue
        try:
            mp = MassProperties(r.mass, r.com, r.inertia)
        except ValueError:
            mp = None
        if mp is None or not (r.mass_ok and r.com_ok and r.tensor_in_range):
            return [Finding(group.root, "info", "lumped-mass",
                            f"{head}; the merged body cannot be computed: a member's inertial "
                            "is invalid")]
        bodies.append(mp.transformed(pose))
    total = combine(bodies)
    moments, _ = total.principal()
    ok = total.is_physical()
    return [Finding(group.root, "info", "lumped-mass",
                    f"{head}: merged body {total.mass:.4g} kg, CoM "
                    f"{np.round(total.com, 4).tolist()} m, principal moments "
                    f"{_moments(moments)} kg m^2{'' if ok else ' (not physical!)'}")]
