"""The ``check`` job: lint the inertials as written, per link, with a severity.

Without a :class:`MeshLibrary` only the values themselves are checked (nothing is
computed). With one, the link's geometry is read for the checks that need it: CoM inside
the geometry's bounding box, implied density, and the tensor's size against what the
geometry allows for the written mass.

Severities: "error" (a simulator refuses or misbehaves), "warning" (very likely wrong),
"info" (worth knowing, e.g. masses lumped by fixed joints).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from urdfinertia.cache.library import MeshLibrary
from urdfinertia.descriptions.inertial import RawInertial
from urdfinertia.descriptions.kinematics import FixedGroup, Kinematics
from urdfinertia.descriptions.model import Link, Robot
from urdfinertia.errors import UrdfInertiaError
from urdfinertia.inertia.massprops import MassProperties, combine
from urdfinertia.link.bounds import BoundsCache

# Findings and their rule ids, and the per-link rules, live one layer down, where
# ``fix``'s policy uses them too.
from urdfinertia.link.findings import (  # noqa: F401  (re-exported: check's API)
    RULES,
    SEVERITIES,
    Finding,
    Rule,
    rule_of,
)
from urdfinertia.link.options import FixOptions
from urdfinertia.link.plausibility import (  # noqa: F401  (re-exported: check's API)
    ABSURD_MASS,
    ABSURD_MOMENT,
    COM_OUTSIDE_ERROR,
    COM_OUTSIDE_WARN,
    INERTIA_RATIO_LIMIT,
    _moments,
    geometry_findings,
    value_findings,
)


def check_robot(robot: Robot, *, meshes: MeshLibrary | None = None,
                options: FixOptions | None = None) -> list[Finding]:
    """All findings for ``robot``, in link order, lumping notes last."""
    options = options or FixOptions()
    kin = Kinematics(robot)
    urdf_dir = robot.path.parent if robot.path is not None else Path(".")
    cache = BoundsCache(meshes) if meshes is not None else None
    findings: list[Finding] = []
    findings.extend(problem_findings(robot))
    for link in robot.links:
        findings.extend(value_findings(link, kin, robot))
        findings.extend(reference_findings(link, options, urdf_dir))
        if meshes is not None and cache is not None and link.inertial is not None:
            findings.extend(geometry_findings(link, meshes, cache, options, urdf_dir))
    for group in kin.groups.values():
        findings.extend(lumped_findings(group, robot))
    return findings


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


def reference_findings(link: Link, options: FixOptions, urdf_dir: Path) -> list[Finding]:
    """Mesh references that do not resolve to a file (loaders fail on them)."""
    from urdfinertia.descriptions.model import Mesh
    from urdfinertia.descriptions.paths import resolve_mesh_path

    out = []
    for ref in (*link.collisions, *link.visuals):
        if not isinstance(ref.shape, Mesh):
            continue
        try:
            resolve_mesh_path(ref.shape.filename, urdf_dir, options.package_dirs)
        except UrdfInertiaError as exc:
            out.append(Finding(link.name, "warning", "mesh-unresolved",
                               f"line {ref.line}: {ref.label}: {exc.cause}", ref.line))
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
        if mp is None or not r.mass_ok:
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
