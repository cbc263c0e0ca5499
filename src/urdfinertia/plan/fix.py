"""The ``fix`` job: recompute the links' inertials from their geometry and patch the file.

Which links, and which of their values are kept, is :mod:`urdfinertia.plan.policy`'s rule.

This module orchestrates the robot: the plan (:mod:`.policy`), each link's decision carried
out (:mod:`.apply`, which computes a link through :mod:`.compute`), the strict refusal and
the patched document. Imports go one way, fix -> apply -> compute (an import-linter
contract). Nothing here touches the file system except through :func:`fix_file`'s reading;
writing the result is the caller's job (:mod:`atomic`).

Fault isolation (:mod:`.compute`): a link with nothing usable left is left exactly as it
was, with the reason. Whether that is acceptable (exit 1) or all-or-nothing (``--strict``)
is the caller's decision.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from urdfinertia.body.options import FixOptions
from urdfinertia.errors import UrdfInertiaError
from urdfinertia.plan.compute import compute_link, problem_code  # noqa: F401  (re-exported)
from urdfinertia.plan.results import FixResult, LinkResult
from urdfinertia.plan.total_mass import TargetOutcome, mass_targets, meet_targets

if TYPE_CHECKING:
    from urdfinertia.cache.library import MeshLibrary
    from urdfinertia.descriptions.model import Problem, Robot


def link_verdicts(robot: Robot, options: FixOptions,
                  meshes: MeshLibrary | None = None) -> tuple[LinkResult, ...]:
    """Every link's verdict: the one answer ``fix``, ``check``, ``compare``, ``explain``,
    ``report`` and the Python API render.

    The plan (:func:`urdfinertia.plan.policy.plan_robot`: findings and decision) carried
    out link by link (:func:`urdfinertia.plan.apply.apply_decision`), then scaled to the
    target masses asked for (:mod:`urdfinertia.plan.total_mass`); nothing is written.
    """
    return _verdicts(robot, options, meshes)[0]


def _verdicts(robot: Robot, options: FixOptions, meshes: MeshLibrary | None,
              ) -> tuple[tuple[LinkResult, ...], tuple[TargetOutcome, ...]]:
    from urdfinertia.cache.library import mesh_library
    from urdfinertia.plan.apply import apply_decision
    from urdfinertia.plan.policy import plan_robot

    path = robot.path or Path("robot.urdf")
    if meshes is None:
        meshes = mesh_library(options.package_dirs, options.max_faces)
    urdf_dir = path.parent
    if options.spec is not None:
        options.spec.check_links(robot)
    by_link: dict[str, list[Problem]] = {}
    for problem in robot.problems:
        if problem.link is not None:
            by_link.setdefault(problem.link, []).append(problem)
    plan = plan_robot(robot, options, meshes, urdf_dir)
    results = []
    for link in robot.links:
        try:
            results.append(apply_decision(link, plan[link.name], options, meshes, urdf_dir,
                                          tuple(by_link.get(link.name, ()))))
        except UrdfInertiaError as exc:
            raise exc.with_context(file=path, link=link.name) from None
    return meet_targets(robot, results, options)


def link_verdict(robot: Robot, name: str, options: FixOptions,
                 meshes: MeshLibrary | None = None) -> LinkResult:
    """One link's verdict, as :func:`link_verdicts` gives it, computing that link only."""
    from urdfinertia.body.bounds import BoundsCache
    from urdfinertia.cache.library import mesh_library
    from urdfinertia.descriptions.kinematics import Kinematics
    from urdfinertia.plan.apply import apply_decision
    from urdfinertia.plan.policy import decide_link

    if mass_targets(robot, options):  # a target weighs every link together
        return next(r for r in link_verdicts(robot, options, meshes) if r.name == name)
    path = robot.path or Path("robot.urdf")
    if meshes is None:
        meshes = mesh_library(options.package_dirs, options.max_faces)
    if options.spec is not None:
        options.spec.check_links(robot)
    link = robot.link(name)
    problems = tuple(p for p in robot.problems if p.link == name)
    try:
        decision = decide_link(link, robot, Kinematics(robot), options, meshes,
                               BoundsCache(meshes), path.parent)
        return apply_decision(link, decision, options, meshes, path.parent, problems)
    except UrdfInertiaError as exc:
        raise exc.with_context(file=path, link=name) from None


def fix_robot(robot: Robot, data: bytes, options: FixOptions,
              meshes: MeshLibrary | None = None) -> FixResult:
    """Every link's verdict (:func:`link_verdicts`) and the patched document."""
    from urdfinertia.descriptions.formats import format_of

    path = robot.path or Path("robot.urdf")
    results, targets = _verdicts(robot, options, meshes)
    if options.strict:
        refusal = FixResult(path, robot, results, data, data).strict_refusal()
        if refusal is not None:
            raise refusal
    from urdfinertia.descriptions.formats import VALUES, NewInertial

    # the writer is told what was derived: kept values keep their bytes
    new = {r.name: NewInertial(r.assembly.total, r.size, frozenset(r.derived) or VALUES)
           for r in results if r.assembly is not None}
    try:
        output = format_of(robot).patch(data, new)
    except UrdfInertiaError as exc:
        raise exc.with_context(file=path) from None
    return FixResult(path, robot, results, data, output, targets)


def fix_file(path: str | Path, options: FixOptions | None = None,
             meshes: MeshLibrary | None = None) -> FixResult:
    """Read the description at ``path`` (any format) and fix it (:func:`fix_robot`).

    ``options`` default to ``FixOptions()``, the command line's defaults. Nothing is
    written: the patched document is ``result.output``.
    """
    from urdfinertia.descriptions.formats import read_description

    robot, data = read_description(path)
    return fix_robot(robot, data, options or FixOptions(), meshes)

