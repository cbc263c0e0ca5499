"""What a conversion did to the mass properties: a source description (URDF, MJCF) against
the asset it was converted to (a USD asset from urdf-usd-converter, mujoco-usd-converter
or Isaac's importer; any registered format).

Per link: mass, CoM and tensor (about the CoM, link frame) on both sides, and the total
mass. Every difference beyond round-off (the converters write float32) is named:

- ``dropped``: the source states an inertial, the converted body has none (no MassAPI, or
  one without mass and inertia): the engine derives mass, CoM and inertia from the
  collision shapes at a density (UsdPhysics: 1000 kg/m^3), estimated here;
- ``density-derived``: the converted mass is the collision shapes' volume times a density
  instead of the source's mass (or a massless source link gets mass that way);
- ``defaulted``: the converted mass is 1 kg (and/or a unit tensor), the importers'
  default, where the source says otherwise;
- ``frame-change``: same mass and principal moments, principal axes rotated;
- ``mass``, ``com``, ``inertia``: any other change; ``missing``: a source link with mass
  that is no body of the converted asset; ``extra``: a converted body with mass that the
  source does not have.

- ``mass-only``: the converted body states its mass and no tensor (a UsdPhysics MassAPI
  with ``physics:mass`` alone, valid: the engine derives CoM and tensor from the colliders
  at that mass); the mass counts in the converted total.

Links are matched by name as converters rename them (:mod:`urdfinertia.analysis.matching`:
``link_3.0`` becomes ``link_3_0``, prefixes and paths are dropped); every link left
unmatched on either side is listed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from urdfinertia.analysis.compare import principal_axis_angle
from urdfinertia.analysis.matching import Matching, match_names
from urdfinertia.descriptions.formats import read_description
from urdfinertia.descriptions.model import Link, Robot
from urdfinertia.errors import UrdfInertiaError

#: float32 round-off with margin: relative for mass and tensor, absolute (m) for the CoM
MASS_RTOL = 1e-5
TENSOR_RTOL = 1e-4
COM_ATOL = 1e-5
#: the density engines use where nothing gives one (UsdPhysics, PhysX, Newton), kg/m^3
ENGINE_DENSITY = 1000.0
#: how close a mass must be to volume x density to be called density-derived
DERIVED_RTOL = 1e-3
KINDS = ("dropped", "density-derived", "defaulted", "frame-change", "mass", "com",
         "inertia", "mass-only", "missing", "extra")


@dataclass(frozen=True)
class Side:
    """One side's mass properties of a link (SI, link frame), None where it has none."""

    mass: float | None
    com: np.ndarray | None
    tensor: np.ndarray | None

    @classmethod
    def of(cls, link: Link | None) -> Side:
        if link is None:
            return cls(None, None, None)
        if link.inertial is None:
            implicit = link.implicit
            mass = implicit.mass if implicit is not None else None
            return cls(mass, None, None)
        i = link.inertial
        return cls(float(i.mass), np.asarray(i.origin.xyz, dtype=np.float64),
                   i.tensor_in_link())


@dataclass(frozen=True)
class Difference:
    link: str
    kind: str  # one of KINDS
    message: str


@dataclass
class AgainstReport:
    source: Path
    converted: Path
    links: list[tuple[str, Side, Side]] = field(default_factory=list)
    matching: Matching | None = None
    differences: list[Difference] = field(default_factory=list)
    total_source: float = 0.0
    total_converted: float = 0.0
    #: the converted total as engines see it: bodies without mass at their derived mass
    total_engine: float = 0.0

    def as_dict(self) -> dict[str, Any]:
        def side(s: Side) -> dict[str, Any]:
            return {"mass": s.mass, "com": None if s.com is None else s.com.tolist(),
                    "inertia": None if s.tensor is None else s.tensor.tolist()}

        return {"source": str(self.source), "converted": str(self.converted),
                "total_mass": {"source": self.total_source, "converted": self.total_converted,
                               "engine": self.total_engine},
                "links": [{"link": n, "source": side(a), "converted": side(b)}
                          for n, a, b in self.links],
                "differences": [vars(d) for d in self.differences],
                "matching": None if self.matching is None else {
                    "renamed": [list(p) for p in self.matching.renamed],
                    "only_source": list(self.matching.only_a),
                    "only_converted": list(self.matching.only_b)}}


def compare_import(source: str | Path, converted: str | Path) -> AgainstReport:
    """Every difference between a description and what it was converted to."""
    src, _ = read_description(source)
    dst, _ = read_description(converted)
    report = AgainstReport(Path(source), Path(converted))
    report.matching = match_names([lk.name for lk in src.links], [lk.name for lk in dst.links])
    by_name = {link.name: link for link in dst.links}
    pairs = dict(report.matching.pairs)
    matched: set[str] = set()
    for link in src.links:
        other = by_name[pairs[link.name]] if link.name in pairs else None
        a = Side.of(link)
        if other is None:
            report.links.append((link.name, a, Side(None, None, None)))
            if a.mass:
                report.differences.append(Difference(
                    link.name, "missing", f"{a.mass:.6g} kg in the source; no body of the "
                    "converted asset matches its name"))
            report.total_source += a.mass or 0.0
            continue
        matched.add(other.name)
        b = Side.of(other)
        report.links.append((link.name, a, b))
        engine = b.mass if b.mass is not None else _derived_mass(other, dst)
        report.total_converted += b.mass or 0.0
        report.total_engine += engine or 0.0
        if a.mass is None and link.inertia_geometry:
            # the source's format computes this body from its geoms (MJCF): so does the
            # engine of the converted asset when it has no mass either
            implicit = _derived_mass(link, src, link.inertia_geometry)
            report.total_source += implicit or 0.0
            report.differences.extend(_implicit(link.name, implicit, b, engine))
            continue
        report.total_source += a.mass or 0.0
        report.differences.extend(_classify(link.name, a, b, other, dst))
    for link in dst.links:
        if link.name not in matched:
            b = Side.of(link)
            report.links.append((link.name, Side(None, None, None), b))
            report.total_converted += b.mass or 0.0
            report.total_engine += b.mass or 0.0
            if b.mass:
                report.differences.append(Difference(
                    link.name, "extra", f"{b.mass:.6g} kg on a body the source does not have"))
    return report


def _implicit(name: str, source: float | None, b: Side,
              engine: float | None) -> list[Difference]:
    """A source body whose format computes its inertial from its geoms (MJCF)."""
    if source is None or engine is None:
        return []
    if b.mass is not None and not math.isclose(b.mass, source, rel_tol=DERIVED_RTOL):
        return [Difference(name, "mass", f"the source's geoms give {source:.6g} kg; "
                           f"converted {b.mass:.6g} kg")]
    if b.mass is None and not math.isclose(engine, source, rel_tol=DERIVED_RTOL):
        return [Difference(name, "density-derived", f"the source's geoms give "
                           f"{source:.6g} kg; the engine derives {engine:.6g} kg from the "
                           "converted collision shapes")]
    return []


def _classify(name: str, a: Side, b: Side, link: Link, robot: Robot) -> list[Difference]:
    if b.mass is None:
        derived = _derived_mass(link, robot)
        est = f"{derived:.6g} kg" if derived is not None else "an engine default"
        if a.mass:
            return [Difference(name, "dropped", f"source {a.mass:.6g} kg; the converted body "
                               f"has no mass and inertia: the engine derives {est} from its "
                               "collision shapes")]
        if derived:
            return [Difference(name, "density-derived", f"massless in the source; the "
                               f"engine gives it {est} from its collision shapes")]
        return []
    if a.mass is None:
        return [] if not b.mass else [Difference(
            name, "extra", f"no inertial in the source; {b.mass:.6g} kg converted")]
    if b.tensor is None:
        change = "" if math.isclose(a.mass, b.mass, rel_tol=MASS_RTOL) else \
            f" (source {a.mass:.6g} kg)"
        return [Difference(name, "mass-only", f"converted {b.mass:.6g} kg{change} with no CoM "
                           "or tensor: the engine derives them from its collision shapes")]
    out: list[Difference] = []
    same_mass = math.isclose(a.mass, b.mass, rel_tol=MASS_RTOL, abs_tol=1e-12)
    if a.tensor is None:  # the source states a mass alone: only that can differ
        return [] if same_mass else [_mass_difference(name, a.mass, b.mass, link, robot)]
    if not same_mass:
        out.append(_mass_difference(name, a.mass, b.mass, link, robot))
    assert a.com is not None and b.com is not None
    moved = float(np.linalg.norm(a.com - b.com))
    if moved > COM_ATOL + MASS_RTOL * float(np.linalg.norm(a.com)):
        out.append(Difference(name, "com", f"CoM moved {moved * 1000:.4g} mm: "
                              f"{_v(a.com)} -> {_v(b.com)} m"))
    assert a.tensor is not None and b.tensor is not None
    scale = max(float(np.abs(a.tensor).max()), float(np.abs(b.tensor).max()), 1e-300)
    if float(np.abs(a.tensor - b.tensor).max()) > TENSOR_RTOL * scale:
        if np.allclose(b.tensor, np.eye(3), rtol=0, atol=1e-9) and \
                not np.allclose(a.tensor, np.eye(3)):
            out.append(Difference(name, "defaulted", "converted tensor is the unit tensor "
                                  "(1 kg m^2 on each axis), an importer default"))
            return out
        ma, mb = np.linalg.eigvalsh(a.tensor), np.linalg.eigvalsh(b.tensor)
        ratio = b.mass / a.mass if a.mass else 1.0
        if np.allclose(mb, ma * ratio, rtol=TENSOR_RTOL, atol=TENSOR_RTOL * scale):
            angle = principal_axis_angle(a.tensor, b.tensor)
            out.append(Difference(name, "frame-change", "same principal moments "
                                  f"({_v(ma)} kg m^2), principal axes rotated by "
                                  f"{angle:.3g} deg"))
        elif same_mass:
            out.append(Difference(name, "inertia", f"principal moments {_v(ma)} -> "
                                  f"{_v(mb)} kg m^2"))
    return out


def _mass_difference(name: str, a: float, b: float, link: Link, robot: Robot) -> Difference:
    change = f"source {a:.6g} kg, converted {b:.6g} kg"
    if b == 1.0:
        return Difference(name, "defaulted", f"{change}: 1 kg, the importers' default mass")
    volume, densities = _collision_volume(link, robot)
    for rho in dict.fromkeys([*densities, ENGINE_DENSITY]):
        if volume and math.isclose(b, rho * volume, rel_tol=DERIVED_RTOL):
            return Difference(name, "density-derived", f"{change} = {rho:g} kg/m^3 x the "
                              f"collision volume {volume:.4g} m^3")
    return Difference(name, "mass", change)


def _collision_volume(link: Link, robot: Robot) -> tuple[float | None, list[float]]:
    """Volume of a link's collision shapes (m^3), and the densities they state."""
    from urdfinertia.body.parts import geometry_parts
    from urdfinertia.cache.library import MeshLibrary

    if not link.collisions:
        return None, []
    folder = robot.path.parent if robot.path is not None else Path(".")
    meshes = MeshLibrary()
    volume = 0.0
    try:
        for ref in link.collisions:
            volume += sum(p.volume for p in geometry_parts(ref, meshes, folder))
    except UrdfInertiaError:
        return None, []
    densities = [r.density for r in link.collisions if r.density]
    return volume, densities


def _derived_mass(link: Link, robot: Robot, refs: Any = None) -> float | None:
    """What an engine computes for a body without mass: each element's density (or the
    default) times its volume; None without shapes. ``refs``: the elements the format
    counts (MJCF's geoms), by default the collisions."""
    from urdfinertia.body.parts import geometry_parts
    from urdfinertia.cache.library import MeshLibrary

    refs = link.collisions if refs is None else refs
    if not refs:
        return None
    folder = robot.path.parent if robot.path is not None else Path(".")
    meshes = MeshLibrary()
    total = 0.0
    try:
        for ref in refs:
            parts = geometry_parts(ref, meshes, folder)
            if ref.mass:
                total += ref.mass
            else:
                rho = ref.density or ENGINE_DENSITY
                total += rho * sum(p.volume for p in parts)
    except UrdfInertiaError:
        return None
    return total


def _v(x: np.ndarray) -> str:
    return "(" + ", ".join(f"{float(v):.4g}" for v in x) + ")"


def report_lines(report: AgainstReport) -> list[str]:
    """The conversion's differences, one line each, and the total masses."""
    lines = [f"{d.link}: {d.kind}: {d.message}" for d in report.differences]
    if report.matching is not None and (report.matching.renamed or report.matching.only_a
                                        or report.matching.only_b):
        lines.insert(0, report.matching.summary())
    lines.append(f"total mass: source {report.total_source:.6g} kg, converted "
                 f"{report.total_converted:.6g} kg as authored, {report.total_engine:.6g} kg "
                 "as engines load it")
    counts = {k: sum(1 for d in report.differences if d.kind == k) for k in KINDS}
    named = ", ".join(f"{n} {k}" for k, n in counts.items() if n)
    lines.append(f"{len(report.differences)} difference(s) beyond round-off"
                 + (f": {named}" if named else ""))
    return lines


def is_conversion(a: str | Path, b: str | Path) -> bool:
    """Whether two descriptions are of different formats (one converted from the other)."""
    from urdfinertia.descriptions.formats import detect_format, read_bytes

    return detect_format(read_bytes(a), Path(a)).name != \
        detect_format(read_bytes(b), Path(b)).name
