"""The ``check`` job: lint the inertials as written, per link, with a severity.

Without a :class:`MeshLibrary` only the values themselves are checked (nothing is
computed). With one, the link's geometry is read for the checks that need it: CoM inside
the geometry's bounding box, implied density, and the tensor's size against what the
geometry allows for the written mass.

Severities: "error" (a simulator refuses or misbehaves), "warning" (very likely wrong),
"info" (worth knowing, e.g. masses lumped by fixed joints).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from urdfinertia.analysis.bounds import BoundsCache, link_bounds
from urdfinertia.cache.library import MeshLibrary
from urdfinertia.descriptions.inertial import RawInertial
from urdfinertia.descriptions.kinematics import FixedGroup, Kinematics
from urdfinertia.descriptions.model import Link, Robot
from urdfinertia.errors import UrdfInertiaError
from urdfinertia.inertia.massprops import MassProperties, combine
from urdfinertia.inertia.validity import is_placeholder
from urdfinertia.link.assemble import assemble
from urdfinertia.link.options import PLAUSIBLE_DENSITY, FixOptions, select_geometry
from urdfinertia.link.parts import geometry_parts

SEVERITIES = ("error", "warning", "info")
#: CoM farther outside the geometry's box than this fraction of the box diagonal: warning.
COM_OUTSIDE_WARN = 0.25
#: ... than this many box diagonals: error (a unit slip, not a modelling choice).
COM_OUTSIDE_ERROR = 10.0
#: Written trace / trace of the geometry at the written mass beyond this factor either way.
INERTIA_RATIO_LIMIT = 100.0


@dataclass(frozen=True)
class Rule:
    """A kind of finding: ``id`` is stable across versions (SARIF ``ruleId``, baselines);
    ``element`` is what a finding of this kind points at in the file ("inertial", "link" or
    "robot"); ``severity`` is the usual one (SARIF's default level)."""

    id: str
    code: str
    element: str
    severity: str
    summary: str


def _rules(*rows: tuple[str, str, str, str, str]) -> dict[str, Rule]:
    return {code: Rule(rid, code, element, severity, summary)
            for rid, code, element, severity, summary in rows}


#: Every kind of finding, by code: the ONE place rule ids are given. An id is never reused
#: or renumbered (baselines and code-scanning alerts are keyed on it); add new kinds at the
#: end of their block. UI1xx: the written values; UI2xx: against the geometry; UI3xx:
#: the robot as simulators merge it; UI4xx: loading and stepping in the engines; UI5xx:
#: what the reader read past that other loaders refuse.
RULES: dict[str, Rule] = _rules(
    ("UI101", "missing-inertial", "link", "error", "a moving link has no <inertial>"),
    ("UI102", "mass-not-finite", "inertial", "error", "mass is NaN or infinite"),
    ("UI103", "mass-not-positive", "inertial", "error", "a moving link's mass is <= 0"),
    ("UI104", "massless-frame", "inertial", "info", "zero mass on a link that does not move"),
    ("UI105", "com-not-finite", "inertial", "error", "CoM origin is NaN or infinite"),
    ("UI106", "inertia-not-finite", "inertial", "error", "inertia tensor has NaN/inf"),
    ("UI107", "inertia-zero", "inertial", "error", "mass with a zero inertia tensor"),
    ("UI108", "inertia-not-symmetric", "inertial", "error", "inertia tensor not symmetric"),
    ("UI109", "inertia-not-positive-definite", "inertial", "error",
     "inertia tensor not positive definite"),
    ("UI110", "triangle-inequality", "inertial", "error",
     "principal moments violate A + B >= C"),
    ("UI111", "placeholder-inertia", "inertial", "warning",
     "equal diagonal, no products: a placeholder tensor"),
    ("UI112", "mass-absurd", "inertial", "error",
     "a mass no robot link has (a unit slip such as mm^3 read as m^3)"),
    ("UI113", "inertia-absurd", "inertial", "error", "inertia components no robot link has"),
    ("UI201", "geometry-unreadable", "link", "warning", "the link's geometry cannot be read"),
    ("UI202", "implausible-density", "inertial", "warning",
     "mass / geometry volume is no material's density"),
    ("UI203", "com-outside-geometry", "inertial", "warning",
     "CoM far outside the geometry's bounding box"),
    ("UI204", "inertia-vs-geometry", "inertial", "warning",
     "tensor size implausible for the mass and geometry"),
    ("UI205", "mesh-unresolved", "link", "error",
     "a mesh reference does not resolve to a file"),
    ("UI301", "lumped-mass", "link", "info", "fixed joints merge links into this body"),
    ("UI401", "engine-refused", "robot", "error", "a simulator refuses to load the robot"),
    ("UI402", "engine-nan", "robot", "error", "a passive run in a simulator produced NaN"),
    ("UI403", "engine-unstable", "robot", "error",
     "a simulator reported instability in a passive run"),
    ("UI404", "engine-runaway", "link", "error", "a joint speed ran away in a passive run"),
    ("UI405", "engine-crashed", "robot", "error",
     "a simulator crashed or hung loading or stepping the robot"),
    ("UI406", "engine-changes-inertial", "inertial", "warning",
     "a simulator silently replaces the written inertial"),
    ("UI407", "engine-default-inertial", "link", "warning",
     "a simulator gives a link without <inertial> default mass/inertia"),
    ("UI408", "engine-missing", "robot", "info", "a requested simulator is not installed"),
    ("UI409", "engine-regression", "robot", "error",
     "a simulator accepted the input and refuses the fixed output"),
    ("UI410", "engine-skipped", "robot", "info", "the engines cannot load this format"),
    ("UI501", "vector-unparseable", "link", "error",
     "a vector other loaders (urdfdom) cannot parse"),
    ("UI502", "unexpanded-substitution", "link", "error", "an unexpanded $(...) substitution"),
    ("UI503", "zero-size-primitive", "link", "warning", "a primitive of zero or negative size"),
    ("UI504", "unsupported-geometry", "link", "warning",
     "a geometry no inertia can come from (plane, unknown shape, two shapes)"),
    ("UI505", "missing-attribute", "link", "error", "a required attribute is missing"),
    ("UI506", "xml-read-leniently", "robot", "warning",
     "XML that strict parsers refuse (declaration, undeclared prefix, trailing content)"),
)


def rule_of(code: str) -> Rule:
    """The rule of a finding code; an unregistered code (a bug: tests list every code the
    checks emit) gets itself as id rather than crashing a report."""
    found = RULES.get(code)
    return found if found is not None else Rule(code, code, "link", "warning", code)


@dataclass(frozen=True)
class Finding:
    """One problem (or note) about one link; ``link`` is None for the whole robot."""

    link: str | None
    severity: str  # "error" | "warning" | "info"
    code: str
    message: str
    #: line in the description where known (additive: most value checks are per link)
    line: int | None = None

    def __post_init__(self) -> None:
        if self.severity not in SEVERITIES:
            raise ValueError(f"severity must be one of {SEVERITIES}")

    @property
    def rule(self) -> Rule:
        return rule_of(self.code)


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
#: A link heavier than this (kg) is a unit slip (mm^3 taken as m^3 gives 1e9 times).
ABSURD_MASS = 1e6
#: Inertia components beyond this (kg m^2) describe no robot link.
ABSURD_MOMENT = 1e6


def problem_findings(robot: Robot) -> list[Finding]:
    """What the reader read past (elements dropped, values read leniently), with lines."""
    out = []
    for p in robot.problems:
        severity, code = _PROBLEM_FINDINGS.get(p.code, ("warning", p.code))
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


def _lumped_mass(group: FixedGroup, robot: Robot, exclude: str) -> float:
    total = 0.0
    for name in group.members:
        inertial = robot.link(name).inertial
        if name != exclude and inertial is not None and np.isfinite(inertial.mass):
            total += max(inertial.mass, 0.0)
    return total


def value_findings(link: Link, kin: Kinematics, robot: Robot) -> list[Finding]:
    """Checks on the written numbers alone."""
    name = link.name
    moving = kin.moves(name)
    group = kin.group_of(name)
    others = _lumped_mass(group, robot, exclude=name) if group.root == name else 0.0
    if link.inertial is None:
        if not moving:
            return []
        if others > 0:
            return [Finding(name, "warning", "missing-inertial",
                            "moving link has no <inertial>; links fixed to it give it "
                            f"{others:.4g} kg only in simulators that merge fixed joints")]
        return [Finding(name, "error", "missing-inertial",
                        "moving link (child of a non-fixed joint) has no <inertial>")]
    raw = RawInertial.from_inertial(link.inertial)
    out: list[Finding] = []
    # A massless link that does not move, or whose fixed neighbours carry the mass, is a
    # frame, not a body: a warning. A moving body with nothing to merge is an error.
    severe = "error" if moving and others == 0 else "warning"
    if not np.isfinite(raw.mass):
        out.append(Finding(name, "error", "mass-not-finite", f"mass is {raw.mass}"))
    elif raw.mass < 0:
        out.append(Finding(name, "error", "mass-not-positive", f"mass is {raw.mass:.6g} kg"))
    elif raw.mass == 0:
        if moving:
            out.append(Finding(name, severe, "mass-not-positive", "moving link has zero mass"))
        else:
            out.append(Finding(name, "info", "massless-frame",
                               "zero mass on a link that does not move: a frame, not a body"))
    line = link.inertial.line
    if np.isfinite(raw.mass) and raw.mass > ABSURD_MASS:
        out.append(Finding(name, "error", "mass-absurd",
                           f"mass {raw.mass:.4g} kg is beyond any robot link (above "
                           f"{ABSURD_MASS:g} kg): a unit slip, e.g. mm^3 taken as m^3?", line))
    finite = raw.inertia[np.isfinite(raw.inertia)]
    if finite.size and float(np.abs(finite).max()) > ABSURD_MOMENT:
        out.append(Finding(name, "error", "inertia-absurd",
                           f"inertia component {float(np.abs(finite).max()):.4g} kg m^2 is "
                           f"above {ABSURD_MOMENT:g}: a unit slip?", line))
    if not raw.com_ok:
        out.append(Finding(name, "error", "com-not-finite",
                           f"CoM is {raw.com.tolist()} (origin xyz/rpy not finite)"))
    d = raw.diagnosis()
    if not d.finite:
        out.append(Finding(name, "error", "inertia-not-finite", "inertia tensor has NaN/inf"))
        return out
    if d.zero:
        if raw.mass > 0:
            out.append(Finding(name, severe, "inertia-zero",
                               f"{raw.mass:.4g} kg with a zero inertia tensor (a point mass: "
                               "MuJoCo refuses it on a moving body)"))
    elif not d.symmetric:
        out.append(Finding(name, "error", "inertia-not-symmetric",
                           f"tensor asymmetry {d.asymmetry:.3g}"))
    elif not d.positive_definite:
        m = d.moments
        out.append(Finding(name, "error", "inertia-not-positive-definite",
                           f"principal moments {_moments(m)} kg m^2: the smallest is "
                           f"{m[0] / max(abs(m[2]), 1e-300):.3g} of the largest"))
    elif not d.triangle_ok:
        m = d.moments
        out.append(Finding(name, "error", "triangle-inequality",
                           f"principal moments A+B<C by {d.triangle_excess:.3g} of C "
                           f"({_moments(m)} kg m^2); MuJoCo refuses it"))
    if is_placeholder(raw.inertia):
        out.append(Finding(name, "warning", "placeholder-inertia",
                           f"ixx=iyy=izz={raw.inertia[0, 0]:g}, no products: a placeholder, "
                           "not a computed tensor"))
    return out


def _moments(m: np.ndarray) -> str:
    return "(" + ", ".join(f"{x:.4g}" for x in m) + ")"


def geometry_findings(link: Link, meshes: MeshLibrary, cache: BoundsCache,
                      options: FixOptions, urdf_dir: Path) -> list[Finding]:
    """Checks of the written inertial against the link's geometry."""
    name = link.name
    assert link.inertial is not None
    raw = RawInertial.from_inertial(link.inertial)
    every = link.collisions + link.visuals
    if not every:
        return []
    role, refs = select_geometry(link, options.geometry)
    try:
        bounds = link_bounds(every, cache, urdf_dir)
        parts = [p for ref in refs for p in geometry_parts(ref, meshes, urdf_dir)]
    except UrdfInertiaError as exc:
        return [Finding(name, "warning", "geometry-unreadable",
                        f"geometry checks skipped: {exc.cause}")]
    out: list[Finding] = []
    if bounds is not None and raw.com_ok and raw.mass_ok:
        out.extend(_com_findings(name, raw, *bounds))
    volume = sum(-p.volume if p.cavity else p.volume for p in parts)
    if not (raw.mass_ok and volume > 0):
        return out
    rho = raw.mass / volume
    lo, hi = PLAUSIBLE_DENSITY
    if not lo <= rho <= hi:
        out.append(Finding(name, "warning", "implausible-density",
                           f"{raw.mass:.4g} kg in {volume:.4g} m^3 of {role} geometry is "
                           f"{rho:.3g} kg/m^3, outside {lo:g}..{hi:g}{_unit_hint(rho)}"))
    d = raw.diagnosis()
    if d.finite and not d.zero and bounds is not None:
        out.extend(_scale_findings(name, raw, parts, bounds, options))
    return out


def _com_findings(name: str, raw: RawInertial, lo: np.ndarray, hi: np.ndarray,
                  ) -> list[Finding]:
    outside = float(np.linalg.norm(np.maximum(np.maximum(lo - raw.com, raw.com - hi), 0.0)))
    diag = float(np.linalg.norm(hi - lo))
    if diag <= 0 or outside <= COM_OUTSIDE_WARN * diag:
        return []
    rel = outside / diag
    severity = "error" if rel > COM_OUTSIDE_ERROR else "warning"
    return [Finding(name, severity, "com-outside-geometry",
                    f"CoM {np.round(raw.com, 6).tolist()} m is {outside:.4g} m ({rel:.3g} box "
                    f"diagonals) outside the geometry's bounding box "
                    f"{np.round(lo, 4).tolist()}..{np.round(hi, 4).tolist()}")]


def _unit_hint(rho: float) -> str:
    """Which power of 1000 brings a density into the plausible range, if one does."""
    lo, hi = PLAUSIBLE_DENSITY
    # rho x k fits: k < 1 means the mass is too large (or volume too small), k > 1 the
    # volume too large, e.g. a millimetre mesh read as metres has 1e9 times its volume.
    for k, why in ((1e-3, "mass in g?"), (1e9, "mesh in mm without scale 0.001?"),
                   (1e6, "mesh in cm without scale 0.01?"), (1e3, "mass 1000x too small?"),
                   (1e-9, "mesh scaled by 0.001 twice?")):
        if lo <= rho * k <= hi:
            return f" (x{k:g} would fit: {why})"
    return ""


def _scale_findings(name: str, raw: RawInertial, parts: list, bounds: tuple,
                    options: FixOptions) -> list[Finding]:
    try:
        geo = assemble(parts, density=options.density, pinned_mass=raw.mass).total
    except UrdfInertiaError:
        return []
    written = float(np.trace(raw.inertia))
    computed = float(np.trace(geo.inertia))
    lo, hi = bounds
    corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1])
                        for z in (lo[2], hi[2])])
    # trace(I_com) = 2 integral |r - c|^2 dm <= 2 m max |corner - c|^2 for mass in the box.
    ceiling = 2 * raw.mass * float(np.max(np.sum((corners - raw.com) ** 2, axis=1)))
    if computed <= 0:
        return []
    ratio = written / computed
    if 1 / INERTIA_RATIO_LIMIT <= ratio <= INERTIA_RATIO_LIMIT and written <= ceiling:
        return []
    beyond = (f"; more than the {ceiling:.3g} kg m^2 ceiling of all mass on the box's far "
              "corners" if written > ceiling else "")
    side = "larger" if ratio > 1 else "smaller"
    return [Finding(name, "warning", "inertia-vs-geometry",
                    f"tensor trace {written:.4g} kg m^2 is {ratio:.3g}x the geometry's "
                    f"{computed:.4g} at {raw.mass:.4g} kg ({side} than plausible{beyond})")]


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
