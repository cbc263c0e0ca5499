"""The `check` job: lint the inertials as written, per link, with a severity.

`check` is `fix`'s plan without writing: with geometry (the default) its findings are
those of the links' verdicts (`urdfinertia.plan.fix.link_verdicts`), the very
objects `fix` carries out, so what `check` says `fix` would recompute is what `fix`
recomputes. The link's geometry is read for the checks that need it: CoM inside the
geometry's bounding box, implied density, and the tensor's size against what the geometry
allows for the written mass. `geometry=False` checks the written values alone.

A link whose geometry could not be read (a mesh that does not resolve or read) was not verified:
[`CheckResult.unverified`][urdfinertia.analysis.check.CheckResult.unverified] lists them, and
[`CheckResult.exit_code`][urdfinertia.analysis.check.CheckResult.exit_code] counts them as a
failure, since the check could not do what it was asked.

Severities: "error" (a simulator refuses or misbehaves), "warning" (very likely wrong),
"info" (worth knowing, e.g. masses lumped by fixed joints).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from urdfinertia.analysis.statics import (
    DEFAULT_MARGIN,
    Statics,
    robot_statics,
    statics_findings,
    verdict_bodies,
    written_bodies,
)
from urdfinertia.body.options import FixOptions
from urdfinertia.cache.library import MeshLibrary, mesh_library
from urdfinertia.descriptions.inertial import RawInertial
from urdfinertia.descriptions.kinematics import FixedGroup, Kinematics
from urdfinertia.descriptions.model import Robot
from urdfinertia.findings import SEVERITIES, Finding
from urdfinertia.inertia.massprops import MassProperties, combine
from urdfinertia.judge.values import moments_text
from urdfinertia.plan.results import LinkResult, Status
from urdfinertia.plan.total_mass import (
    DEFAULT_MASS_TOLERANCE,
    MassTargetError,
    mass_targets,
    meet_targets,
    target_findings,
    untargeted,
)
from urdfinertia.rules import Rule, Severity


@dataclass(frozen=True, eq=False)
class CheckResult:
    """What `check` found in one description, and what `fix` would do about it.

    Attributes
    ----------
    path : Path
    robot : Robot
    links : tuple of LinkResult
        Every link's verdict (empty with `geometry=False`: nothing was planned).
    findings : tuple of Finding
        The robot's findings in link order, lumping notes last.
    statics : Statics or None
        Total mass, whole CoM and per joint the gravity load (None: statics not asked for).
    """

    path: Path
    robot: Robot
    links: tuple[LinkResult, ...]
    findings: tuple[Finding, ...]
    statics: Statics | None = None

    @property
    def would_recompute(self) -> tuple[str, ...]:
        """Links `fix` (these options) would recompute from their geometry or spec."""
        return tuple(r.name for r in self.links if r.status == Status.RECOMPUTED)

    @property
    def would_change(self) -> tuple[str, ...]:
        """Links whose inertial `fix` would change (recomputed or repaired)."""
        return tuple(r.name for r in self.links if r.changed)

    @property
    def unverified(self) -> tuple[LinkResult, ...]:
        """Links some of whose geometry could not be read: they were not verified."""
        return tuple(r for r in self.links if r.unverified)

    @property
    def left(self) -> tuple[LinkResult, ...]:
        """Links `fix` would leave as they are although they need changing (it exits 1)."""
        return tuple(r for r in self.links if r.status == Status.LEFT)

    def counts(self) -> dict[str, int]:
        """Findings by severity."""
        return {s: sum(f.severity == s for f in self.findings) for s in SEVERITIES}

    def link(self, name: str) -> LinkResult:
        """The verdict of link `name`, as `FixResult.link` gives it.

        Raises
        ------
        KeyError
            No link of that name.
        """
        for r in self.links:
            if r.name == name:
                return r
        raise KeyError(name)

    def failing(self, strict: bool = False) -> tuple[Finding, ...]:
        """The findings that fail the run: errors; with `strict` also every warning that `fix` does
        not keep on purpose ([`LinkResult.keeps`][urdfinertia.plan.results.LinkResult.keeps]): a
        warning on a value `fix` keeps, with the reason said, does not fail `--strict`, so that
        `check --strict` passes on what `fix` wrote."""
        by_name = {r.name: r for r in self.links}
        out = []
        for f in self.findings:
            if f.severity == Severity.ERROR:
                out.append(f)
            elif strict and f.severity == Severity.WARNING:
                r = by_name.get(f.link) if f.link is not None else None
                if r is None or not r.keeps(f):
                    out.append(f)
        return tuple(out)

    def exit_code(self, strict: bool = False) -> int:
        """1 when a finding fails the run
        ([`failing`][urdfinertia.analysis.check.CheckResult.failing]), a link could not be verified
        or `fix` would leave a link that needs changing; else 0 (the command line's exit code
        without a baseline)."""
        return 1 if self.unverified or self.left or self.failing(strict) else 0


def check_robot(robot: Robot, *, meshes: MeshLibrary | None = None,
                options: FixOptions | None = None, geometry: bool = True) -> list[Finding]:
    """All findings for `robot`, in link order, lumping notes last.

    With `geometry` (the default) the links' geometry is read (through `meshes`, a new
    library when None) and the findings are those `fix` acts on; without it only the
    written values and mesh references are checked.
    """
    return list(check_description(robot, meshes=meshes, options=options,
                                  geometry=geometry).findings)


def check_description(robot: Robot, *, meshes: MeshLibrary | None = None,
                      options: FixOptions | None = None,
                      geometry: bool = True, statics: bool = True,
                      effort_margin: float = DEFAULT_MARGIN,
                      mass_tolerance: float = DEFAULT_MASS_TOLERANCE) -> CheckResult:
    """`check` of a robot already read: findings and every link's verdict.

    With `geometry` (the default) the robot is judged as `fix` judges it
    (`urdfinertia.plan.fix.verdicts`): the findings are the verdicts' and the plan is
    `fix`'s. Without it only the written values and mesh references are checked (no
    plan). With `statics` (the default) every joint's gravity load over its range is held
    against its effort limit (`urdfinertia.analysis.statics`): an error when it
    exceeds it, a warning within `effort_margin` of it. Target masses
    (`options.total_mass`, the spec's `total_mass` and `[subtree.NAME] mass`) are held
    against the written masses: UI703 beyond `mass_tolerance` (a fraction); the plan is
    `fix`'s with the targets, or without them where `fix` would refuse them (the
    finding says so). `options.realizable` is the region UI210 tests the written
    inertials in.
    """
    from urdfinertia.plan.fix import verdicts

    options = options or FixOptions()
    targeted = bool(mass_targets(robot, options))
    kin = Kinematics(robot)
    path = robot.path or Path("robot.urdf")
    findings: list[Finding] = []
    links: tuple[LinkResult, ...] = ()
    if geometry:
        if meshes is None:
            meshes = mesh_library(options.package_dirs, options.max_faces)
        found = verdicts(robot, untargeted(options) if targeted else options, meshes)
        links = found.links
        findings.extend(f for f in found.findings if f.rule != Rule.TOTAL_MASS_CHANGED)
        if targeted:
            findings.extend(target_findings(robot, links, options, mass_tolerance))
            try:
                links = meet_targets(robot, links, options)[0]
            except MassTargetError:
                pass  # fix refuses the target: its plan without it (the finding says so)
        for r in links:
            findings.extend(r.findings)
    else:
        findings.extend(values_only(robot, options, meshes))
        if targeted:
            findings.extend(target_findings(robot, (), options, mass_tolerance))
    for group in kin.groups.values():
        findings.extend(lumped_findings(group, robot))
    held = None
    if statics:
        held = robot_statics(robot, verdict_bodies(links) if geometry else written_bodies(robot))
        findings.extend(statics_findings(robot, held, effort_margin))
    return CheckResult(path, robot, links, tuple(findings), held)


def values_only(robot: Robot, options: FixOptions,
                meshes: MeshLibrary | None = None) -> list[Finding]:
    """``check --no-geometry``: the reader's findings, the written values alone and the
    mesh references, per link; no mesh is read."""
    from urdfinertia.body.evidence import robot_evidence
    from urdfinertia.judge.values import value_findings

    evidence = robot_evidence(robot, options, meshes)  # type: ignore[arg-type]
    out: list[Finding] = list(robot.findings_of(None))
    for link in robot.links:
        ev = evidence.links[link.name]
        out.extend(robot.findings_of(link.name))
        out.extend(value_findings(ev))
        out.extend(ev.unresolved)
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
            with np.errstate(all="raise"):
                mp = MassProperties(r.mass, r.com, r.inertia).transformed(pose)
        except (ValueError, FloatingPointError, np.linalg.LinAlgError):
            mp = None
        if mp is None or not (r.mass_ok and r.com_ok and r.tensor_in_range):
            return [Finding(Rule.LUMPED_MASS, group.root, f"{head}; the merged body cannot "
                            "be computed: a member's inertial is invalid")]
        bodies.append(mp)
    try:
        with np.errstate(all="raise"):
            total = combine(bodies)
            moments, _ = total.principal()
            ok = total.is_physical()
    except (ValueError, FloatingPointError, np.linalg.LinAlgError):
        return [Finding(Rule.LUMPED_MASS, group.root, f"{head}; the merged body cannot be "
                        "computed: its members' values overflow")]
    return [Finding(Rule.LUMPED_MASS, group.root, f"{head}: merged body {total.mass:.4g} kg, "
                    f"CoM {np.round(total.com, 4).tolist()} m, principal moments "
                    f"{moments_text(moments)} kg m^2{'' if ok else ' (not physical!)'}")]
