"""The `fix` job: judge the robot, plan every link, carry the plan out, patch the file.

The data flow, one way: the robot model and its geometry (`urdfinertia.body.evidence`) -> the
judgement, with the whole robot as evidence (`urdfinertia.judge.robot`) -> the plan of every link
(`urdfinertia.plan.policy`: **where a link's verdict is made**) -> carrying it out
(`urdfinertia.plan.execute`) -> target masses met (`urdfinertia.plan.total_mass`) -> the patched
document. `link_verdicts` stops before the document: it is what `check`, `compare`, `explain`,
`report` and the library render. Nothing here touches the file system except
[`fix_file`][urdfinertia.plan.fix.fix_file]'s reading; writing the result is the caller's job
([`urdfinertia.plan.save`][urdfinertia.plan.save]).

Fault isolation: a link with nothing usable is left exactly as it was, with the reason. Whether that
is acceptable (exit 1) or all-or-nothing (`--strict`) is the caller's decision:
[`FixResult.strict_refusal`][urdfinertia.plan.results.FixResult.strict_refusal] is that policy over
the findings.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from urdfinertia.body.options import FixOptions
from urdfinertia.errors import UrdfError, UrdfInertiaError
from urdfinertia.findings import Finding
from urdfinertia.plan.results import FixResult, LinkResult
from urdfinertia.plan.total_mass import TargetOutcome, mass_change_finding, meet_targets
from urdfinertia.rules import Rule

if TYPE_CHECKING:
    from collections.abc import Mapping

    from urdfinertia.cache.library import MeshLibrary
    from urdfinertia.descriptions.model import Robot
    from urdfinertia.judge.robot import Judgement
    from urdfinertia.plan.policy import LinkPlan


@dataclass(frozen=True, eq=False)
class Verdicts:
    """A robot's verdicts: every link's, the targets met and what is said of the robot."""

    links: tuple[LinkResult, ...]
    targets: tuple[TargetOutcome, ...]
    findings: tuple[Finding, ...]
    judgement: Judgement


def verdicts(robot: Robot, options: FixOptions, meshes: MeshLibrary | None = None,
             ) -> Verdicts:
    """Judge, plan and carry out every link of ``robot`` (module doc); nothing is written."""
    from urdfinertia.body.evidence import robot_evidence
    from urdfinertia.cache.library import mesh_library
    from urdfinertia.judge.robot import judge_robot
    from urdfinertia.plan.execute import execute
    from urdfinertia.plan.policy import plan_robot

    path = robot.path or Path("robot.urdf")
    if meshes is None:
        meshes = mesh_library(options.package_dirs, options.max_faces)
    if options.spec is not None:
        options.spec.check_links(robot)
    evidence = robot_evidence(robot, options, meshes)
    try:
        judgement = judge_robot(evidence)
        plans = plan_robot(judgement)
    except UrdfInertiaError as exc:
        raise exc.with_context(file=path) from None
    results = tuple(execute(evidence.links[link.name], judgement.link(link.name),
                            plans[link.name]) for link in robot.links)
    results, targets = meet_targets(robot, results, options)
    said = [*robot.findings_of(None), *judgement.findings]
    said += [Finding(Rule.MASS_TARGET_MET, None, str(t)) for t in targets]
    change = mass_change_finding(results)
    if change is not None and not targets:
        said.append(change)
    prior = prior_total_finding(results, plans)
    if prior is not None:
        said.append(prior)
    return Verdicts(results, targets, tuple(said), judgement)


def prior_total_finding(results: tuple[LinkResult, ...], plans: Mapping[str, LinkPlan],
                        ) -> Finding | None:
    """The robot's total with the links the mass prior gave a mass, and its band (None:
    the prior gave none, or a target mass replaced what it gave)."""
    from urdfinertia.priors.model import robot_total

    priors = [plan.prior for r in results if (plan := plans[r.name]).prior is not None
              and r.error_bar is not None and r.error_bar.mass is not None]
    if not priors:
        return None
    total = robot_total(priors)
    given = {r.name for r in results if r.error_bar is not None and r.error_bar.mass}
    rest = sum(after.mass for r in results if r.name not in given
               and (after := r.after) is not None)
    text = f"{len(priors)} link(s) with no mass: {total.describe()}"
    if rest > 0:
        text += (f"; the robot with its other masses: {rest + total.water:.3g} kg at "
                 f"1000 kg/m³, {rest + total.mass:.3g} kg with the prior "
                 f"({rest + total.low:.3g}-{rest + total.high:.3g})")
    return Finding(Rule.MASS_PRIOR, None, text)


def link_verdicts(robot: Robot, options: FixOptions,
                  meshes: MeshLibrary | None = None) -> tuple[LinkResult, ...]:
    """Every link's verdict: the one answer ``fix``, ``check``, ``compare``, ``explain``,
    ``report`` and the Python API render (:func:`verdicts`)."""
    return verdicts(robot, options, meshes).links


def link_verdict(robot: Robot, name: str, options: FixOptions,
                 meshes: MeshLibrary | None = None) -> LinkResult:
    """One link's verdict, as :func:`link_verdicts` gives it (the robot is judged as a
    whole: a link's verdict depends on its twins, conventions and the robot's masses)."""
    for r in link_verdicts(robot, options, meshes):
        if r.name == name:
            return r
    raise KeyError(name)


def fix_robot(robot: Robot, data: bytes, options: FixOptions,
              meshes: MeshLibrary | None = None) -> FixResult:
    """Every link's verdict (`verdicts`) and the patched document."""
    from urdfinertia.descriptions.formats import VALUES, NewInertial, format_of

    path = robot.path or Path("robot.urdf")
    found = verdicts(robot, options, meshes)
    missing = [f for f in found.findings if f.rule == Rule.MISSING_LAYER]
    if missing:  # the stage was read incomplete: an override of it would be too
        more = f" (and {len(missing) - 1} more)" if len(missing) > 1 else ""
        raise UrdfError(missing[0].message + more, file=path)
    if options.strict:
        refusal = FixResult(path, robot, found.links, data, data, found.targets,
                            found.findings).strict_refusal()
        if refusal is not None:
            raise refusal
    # the writer is told what was derived: kept values keep their bytes, and so do derived
    # ones equal to the written to round-off (a second --all run rewrites nothing)
    new = {}
    for r in found.links:
        if r.changed and r.assembly is not None:
            derived = (frozenset(r.derived) or frozenset(VALUES)) - _as_written(r)
            if derived:
                new[r.name] = NewInertial(r.assembly.total, r.size, derived)
    try:
        output = format_of(robot).patch(data, new)
    except UrdfInertiaError as exc:
        raise exc.with_context(file=path) from None
    return FixResult(path, robot, found.links, data, output, found.targets, found.findings)


#: Derived values within this relative round-off of the written ones keep their bytes.
ROUND_OFF = 1e-12


def _as_written(r: LinkResult) -> frozenset[str]:
    """The values of ``r`` the output would write equal, to :data:`ROUND_OFF`, to the
    written ones ("mass", "com", "tensor")."""
    import numpy as np  # here: a warm run with nothing to change imports no numpy

    before = r.before
    if before is None or r.assembly is None:
        return frozenset()
    after = r.assembly.total
    size = max(r.size, 1e-9)
    same = set()
    if abs(after.mass - before.mass) <= ROUND_OFF * abs(before.mass):
        same.add("mass")
    if float(np.abs(after.com - before.com).max()) <= ROUND_OFF * size:
        same.add("com")
    scale = float(np.abs(before.inertia).max())
    if scale > 0 and float(np.abs(after.inertia - before.inertia).max()) <= ROUND_OFF * scale:
        same.add("tensor")
    return frozenset(same)


def fix_file(path: str | Path, options: FixOptions | None = None,
             meshes: MeshLibrary | None = None) -> FixResult:
    """Read the description at `path` (any format) and fix it
    ([`fix_robot`][urdfinertia.plan.fix.fix_robot]).

    `options` default to `FixOptions()`, the command line's defaults. Nothing is
    written: the patched document is `result.output`.
    """
    from urdfinertia.descriptions.formats import read_description

    robot, data = read_description(path)
    return fix_robot(robot, data, options or FixOptions(), meshes)
