"""How trustworthy a written inertial is: the rules `check` reports and `fix` acts on.

One home for every judgement of an inertial: :func:`value_findings` looks at the written
numbers alone (missing, NaN, non-positive mass, not positive definite, triangle inequality,
placeholders); :func:`geometry_findings` holds them against the link's geometry (CoM
outside the geometry's box, implied density, tensor size against what the geometry allows
for the written mass, with unit-slip hints). :mod:`urdfinertia.analysis.check` lists the
findings; :mod:`urdfinertia.plan.policy` decides from the same findings which links ``fix``
recomputes and which of their values it keeps.

Severities: "error" (a simulator refuses or misbehaves), "warning" (very likely wrong),
"info" (worth knowing, e.g. masses lumped by fixed joints).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from urdfinertia.body.assemble import assemble
from urdfinertia.body.bounds import BoundsCache, link_bounds
from urdfinertia.body.mass import MassSource
from urdfinertia.body.options import PLAUSIBLE_DENSITY, FixOptions, select_geometry
from urdfinertia.body.parts import geometry_parts
from urdfinertia.cache.library import MeshLibrary
from urdfinertia.descriptions.inertial import RawInertial
from urdfinertia.descriptions.kinematics import FixedGroup, Kinematics
from urdfinertia.descriptions.model import Link, Robot
from urdfinertia.errors import UrdfInertiaError
from urdfinertia.findings import SEVERITIES, Finding  # noqa: F401  (re-exported)
from urdfinertia.inertia.validity import is_placeholder

#: A link's geometry box in the link frame: (lo, hi) corners, m.
Bounds = tuple[np.ndarray, np.ndarray]

#: CoM farther outside the geometry's box than this fraction of the box diagonal: warning.
COM_OUTSIDE_WARN = 0.25
#: ... than this many box diagonals: error (a unit slip, not a modelling choice).
COM_OUTSIDE_ERROR = 10.0
#: A written body whose CoM lies farther outside the geometry's box than this many box
#: diagonals, with a tensor beyond all its mass on the box's far corners, does not lie in
#: that geometry: the geometry is a marker (Cassie's 1 cm "reference" boxes: 1.1 to 1.3
#: diagonals; UR5's wrists, whose written tensors are wrong, 0.3 to 0.4).
MARKER_OUTSIDE = 1.0
#: Written trace / trace of the geometry at the written mass beyond this factor either way.
INERTIA_RATIO_LIMIT = 100.0


#: A link heavier than this (kg) is a unit slip (mm^3 taken as m^3 gives 1e9 times).
ABSURD_MASS = 1e6
#: Inertia components beyond this (kg m^2) describe no robot link.
ABSURD_MOMENT = 1e6


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


@dataclass(frozen=True, eq=False)
class GeometryJudgement:
    """Findings against the geometry, and what they were judged from.

    bounds : box of every geometry element, link frame (None: no geometry or unreadable).
    density : the written mass over the selected geometry's volume, kg/m^3 (None: n/a).
    """

    findings: list[Finding]
    bounds: Bounds | None = None
    density: float | None = None
    #: the written body cannot lie in the geometry: its CoM is outside the box and its
    #: tensor exceeds all its mass on the box's far corners (the geometry is a marker)
    outgrows: bool = False


def geometry_findings(link: Link, meshes: MeshLibrary, cache: BoundsCache,
                      options: FixOptions, urdf_dir: Path) -> list[Finding]:
    """Checks of the written inertial against the link's geometry."""
    return geometry_judgement(link, meshes, cache, options, urdf_dir).findings


def geometry_judgement(link: Link, meshes: MeshLibrary, cache: BoundsCache,
                       options: FixOptions, urdf_dir: Path) -> GeometryJudgement:
    """:func:`geometry_findings` with the box and density they were judged from."""
    name = link.name
    assert link.inertial is not None
    raw = RawInertial.from_inertial(link.inertial)
    every = link.collisions + link.visuals
    if not every:
        return GeometryJudgement([])
    role, refs = select_geometry(link, options.geometry)
    try:
        bounds = link_bounds(every, cache, urdf_dir)
        parts = [p for ref in refs for p in geometry_parts(ref, meshes, urdf_dir)]
    except UrdfInertiaError as exc:
        return GeometryJudgement([Finding(name, "warning", "geometry-unreadable",
                        f"geometry checks skipped: {exc.cause}")])
    out: list[Finding] = []
    if bounds is not None and raw.com_ok and raw.mass_ok:
        out.extend(_com_findings(name, raw, *bounds))
    volume = sum(-p.volume if p.cavity else p.volume for p in parts)
    if not (raw.mass_ok and volume > 0):
        return GeometryJudgement(out, bounds)
    rho = raw.mass / volume
    lo, hi = PLAUSIBLE_DENSITY
    if not lo <= rho <= hi:
        out.append(Finding(name, "warning", "implausible-density",
                           f"{raw.mass:.4g} kg in {volume:.4g} m^3 of {role} geometry is "
                           f"{rho:.3g} kg/m^3, outside {lo:g}..{hi:g}{_unit_hint(rho)}"))
    d = raw.diagnosis()
    if d.finite and not d.zero and bounds is not None:
        out.extend(_scale_findings(name, raw, parts, bounds, options))
    outgrows = (bounds is not None and raw.com_ok
                and _outside(raw.com, *bounds) > MARKER_OUTSIDE * _diagonal(*bounds)
                and float(np.trace(raw.inertia)) > _ceiling(raw, *bounds))
    return GeometryJudgement(out, bounds, rho, outgrows)


def _outside(com: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> float:
    """How far ``com`` lies outside the box ``lo..hi`` (0 inside), m."""
    return float(np.linalg.norm(np.maximum(np.maximum(lo - com, com - hi), 0.0)))


def _diagonal(lo: np.ndarray, hi: np.ndarray) -> float:
    return float(np.linalg.norm(hi - lo))


def _ceiling(raw: RawInertial, lo: np.ndarray, hi: np.ndarray) -> float:
    """The largest trace of a tensor about the CoM of the mass in the box ``lo..hi``:
    trace(I_com) = 2 integral |r - c|^2 dm <= 2 m max |corner - c|^2."""
    corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1])
                        for z in (lo[2], hi[2])])
    return 2 * raw.mass * float(np.max(np.sum((corners - raw.com) ** 2, axis=1)))


def _com_findings(name: str, raw: RawInertial, lo: np.ndarray, hi: np.ndarray,
                  ) -> list[Finding]:
    outside = _outside(raw.com, lo, hi)
    diag = _diagonal(lo, hi)
    if diag <= 0 or outside <= COM_OUTSIDE_WARN * diag:
        return []
    rel = outside / diag
    severity = "error" if rel > COM_OUTSIDE_ERROR else "warning"
    return [Finding(name, severity, "com-outside-geometry",
                    f"CoM {np.round(raw.com, 6).tolist()} m is {outside:.4g} m ({rel:.3g} box "
                    f"diagonals) outside the geometry's bounding box "
                    f"{np.round(lo, 4).tolist()}..{np.round(hi, 4).tolist()}")]


#: (factor, which value slipped, hint): ``rho x factor`` in range points at a unit slip.
#: factor < 1: the mass is too large (or the volume too small); > 1: the volume too large,
#: e.g. a millimetre mesh read as metres has 1e9 times its volume.
UNIT_SLIPS = ((1e-3, "mass", "mass in g?"), (1e9, "geometry", "mesh in mm without scale 0.001?"),
              (1e6, "geometry", "mesh in cm without scale 0.01?"),
              (1e3, "mass", "mass 1000x too small?"),
              (1e-9, "geometry", "mesh scaled by 0.001 twice?"))


def unit_slip(rho: float) -> tuple[float, str, str] | None:
    """The first power of 1000 that brings a density into the plausible range, if any."""
    lo, hi = PLAUSIBLE_DENSITY
    for k, blames, why in UNIT_SLIPS:
        if lo <= rho * k <= hi:
            return k, blames, why
    return None


def _unit_hint(rho: float) -> str:
    slip = unit_slip(rho)
    return "" if slip is None else f" (x{slip[0]:g} would fit: {slip[2]})"


def _scale_findings(name: str, raw: RawInertial, parts: list, bounds: tuple,
                    options: FixOptions) -> list[Finding]:
    try:
        geo = assemble(parts, MassSource("kept", raw.mass)).total
    except UrdfInertiaError:
        return []
    written = float(np.trace(raw.inertia))
    computed = float(np.trace(geo.inertia))
    ceiling = _ceiling(raw, *bounds)
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
