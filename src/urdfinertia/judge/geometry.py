"""The written values held against the geometry that represents the body.

A link may carry several descriptions of its body (collisions, visuals, an MJCF body's own
geoms). Geometry that is not the body (contact spheres on a foot, a marker box, a pin, an
envelope around a light link) is no evidence about its density or size. So a written value
is held against every candidate set (:mod:`urdfinertia.body.evidence`), starting with the
primary one (the collisions, or the geoms MuJoCo counts), and:

1. if some complete candidate agrees with it (plausible implied density, tensor size within
   what that geometry allows), the written value fits the body: that candidate represents
   the body, and the others are set aside, said so (``geometry-not-body``). Primitive
   stand-ins are a coarser description than a mesh of the same link: when the primary set
   is primitives and another set has meshes, the meshes are held against the value too,
   and a mesh set of plausible density represents the body over primitives that agree
   (the same link with and without a collision cylinder around its mesh gets one verdict);
2. if none agrees, a candidate far smaller than another (:data:`NOT_BODY_RATIO`) is set
   aside as a marker or contact set, and the most faithful of the rest (a detailed mesh
   over a convex hull over primitive stand-ins) is the body the findings are judged
   against;
3. a density no material has, which no unit slip of the geometry explains (a millimetre
   mesh), or a written body that cannot lie in the geometry at all (its CoM outside the
   box and a tensor beyond all of its mass on the box's corners), says the geometry is not
   the body: no evidence, the value is kept (:attr:`GeometryJudgement.not_body`).

The CoM is held against the box of every element of the link: a body's CoM lies inside
its own extent.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from urdfinertia.body.assemble import assemble
from urdfinertia.body.evidence import Bounds, LinkEvidence
from urdfinertia.body.geometry_choice import KINDS, Candidate
from urdfinertia.body.mass import MassSource
from urdfinertia.body.options import PLAUSIBLE_DENSITY
from urdfinertia.descriptions.inertial import RawInertial
from urdfinertia.descriptions.model import Mesh
from urdfinertia.errors import UrdfInertiaError
from urdfinertia.findings import Finding
from urdfinertia.inertia.slips import Solid
from urdfinertia.judge.values import diagnosis
from urdfinertia.rules import Rule

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
#: A candidate set whose volume is below this fraction of another's of the same link is a
#: marker or contact set, not the body, when the written values agree with neither
#: (four 5 mm contact spheres against a foot mesh: 1/150).
NOT_BODY_RATIO = 1 / 30
#: Rules that hold the written values against one candidate's volume and tensor.
AGAINST_CANDIDATE = frozenset({Rule.IMPLAUSIBLE_DENSITY, Rule.INERTIA_VS_GEOMETRY})

#: (factor, which value slipped, hint): ``rho x factor`` in range points at a unit slip.
#: factor < 1: the mass is too large (or the volume too small); > 1: the volume too large,
#: e.g. a millimetre mesh read as metres has 1e9 times its volume.
UNIT_SLIPS = ((1e-3, "mass", "mass in g?"), (1e9, "geometry", "mesh in mm without scale 0.001?"),
              (1e6, "geometry", "mesh in cm without scale 0.01?"),
              (1e3, "mass", "mass 1000x too small?"),
              (1e-9, "geometry", "mesh scaled by 0.001 twice?"))


@dataclass(frozen=True, eq=False)
class GeometryJudgement:
    """The findings against the geometry, and what they were judged from.

    Attributes
    ----------
    findings : tuple of Finding
        CoM outside the geometry, implied density, tensor size; the candidates set aside.
    body : Candidate or None
        The candidate that represents the body (None: no geometry, none readable, or none
        represents it).
    solid : Solid or None
        ``body`` as the homogeneous solid the slip search holds edits to.
    bounds : (lo, hi) or None
        The box of every geometry element of the link.
    density : float or None
        The written mass over the body's volume, kg/m^3.
    not_body : str or None
        Why no geometry represents the body (the value is then kept as written).
    geometry_slip : str or None
        A unit slip of the geometry that explains its implied density ("mesh in mm without
        scale 0.001?"): the geometry, not the inertial, is wrong.
    mass_slip : str or None
        A unit slip of the mass that would explain the implied density ("mass in g?"). One
        link alone does not show it (a marker's density looks the same): it is the robot's
        to show, through its mass distribution or a convention of the file.
    """

    findings: tuple[Finding, ...] = ()
    body: Candidate | None = None
    solid: Solid | None = None
    bounds: Bounds | None = None
    density: float | None = None
    not_body: str | None = None
    geometry_slip: str | None = None
    mass_slip: str | None = None

    @property
    def rules(self) -> frozenset[Rule]:
        return frozenset(f.rule for f in self.findings)


def judge_geometry(ev: LinkEvidence) -> GeometryJudgement:
    """The written inertial of ``ev`` against its geometry (module doc)."""
    raw = ev.raw
    if raw is None or not ev.has_geometry:
        return GeometryJudgement()
    bounds = ev.bounds
    out: list[Finding] = []
    if bounds is not None and raw.com_ok and raw.mass_ok:
        out.extend(com_findings(ev.name, raw, bounds, ev.link.inertial.line
                                if ev.link.inertial is not None else None))
    usable = raw.mass_ok and math.isfinite(float(np.sum(raw.inertia)))
    if not usable or bounds is None:
        return GeometryJudgement(tuple(out), bounds=bounds)
    first = ev.primary
    candidates = [c for c in ([first] if first is not None else []) if not c.dropped]
    flags = {id(c): candidate_findings(ev, raw, c, bounds) for c in candidates}
    if not candidates or any(flags[id(c)] for c in candidates) or _finer_elsewhere(ev, first):
        # the primary set disagrees, is incomplete or coarse: is another the body?
        for other in ev.others():
            if not other.dropped:
                candidates.append(other)
                flags[id(other)] = candidate_findings(ev, raw, other, bounds)
    if not candidates:
        return GeometryJudgement(tuple(out), bounds=bounds)
    agree = [c for c in candidates if not flags[id(c)]]
    finest = _finest_plausible(candidates, flags)
    if agree and finest is not None and finest not in agree \
            and _rank(finest) > max(_rank(c) for c in agree):
        body = finest
        out.extend(_set_aside(ev, c, f"the {body.role} meshes describe the body in more "
                              "detail than these stand-ins") for c in candidates
                   if c is not body)
        out.extend(flags[id(body)])
    elif agree:
        body = _most_faithful(agree)
        out.extend(_set_aside(ev, c, f"the written values fit the {body.role} geometry, "
                              "not this one") for c in candidates if flags[id(c)])
    else:
        largest = max(c.volume for c in candidates)
        kept = [c for c in candidates if c.volume >= NOT_BODY_RATIO * largest]
        out.extend(_set_aside(ev, c, f"its volume {c.volume:.3g} m^3 is under "
                              f"{NOT_BODY_RATIO:.2g} of another geometry's ({largest:.3g}): "
                              "a marker or contact set") for c in candidates if c not in kept)
        body = _most_faithful(kept)
        out.extend(flags[id(body)])
    density = raw.mass / body.volume
    judged = GeometryJudgement(tuple(out), body, candidate_solid(body, bounds), bounds, density)
    return _not_the_body(ev, raw, judged)


def _rank(c: Candidate) -> int:
    return KINDS.index(c.kind)


def _finer_elsewhere(ev: LinkEvidence, first: Candidate | None) -> bool:
    """The primary set is primitive stand-ins and another role has meshes."""
    if first is None or first.kind != KINDS[0]:
        return False
    return any(role != ev.primary_role and any(isinstance(r.shape, Mesh) for r in refs)
               for role, refs in ev.roles)


def _finest_plausible(candidates: list[Candidate], flags: dict[int, list[Finding]],
                      ) -> Candidate | None:
    """The most faithful candidate whose implied density is plausible (None: none)."""
    ok = [c for c in candidates
          if not any(f.rule is Rule.IMPLAUSIBLE_DENSITY for f in flags[id(c)])]
    return _most_faithful(ok) if ok else None


def _most_faithful(candidates: list[Candidate]) -> Candidate:
    """The most faithful kind (a detailed mesh over a hull over primitives); the first of
    equals in the order the candidates came."""
    rank = {k: i for i, k in enumerate(KINDS)}
    return max(candidates, key=lambda c: (rank[c.kind], -candidates.index(c)))


def _set_aside(ev: LinkEvidence, c: Candidate, why: str) -> Finding:
    return Finding(Rule.GEOMETRY_NOT_BODY, ev.name, f"{c.role} geometry set aside: {why}",
                   c.refs[0].line if c.refs else None, c.role)


def candidate_solid(c: Candidate, bounds: Bounds) -> Solid | None:
    """``c`` as a homogeneous solid of unit mass (None: its parts do not combine)."""
    try:
        unit = assemble(c.parts, MassSource("kept", 1.0)).total
    except (UrdfInertiaError, ValueError, FloatingPointError):
        return None
    return Solid(c.volume, unit.com, unit.inertia, bounds[0], bounds[1])


def _not_the_body(ev: LinkEvidence, raw: RawInertial, judged: GeometryJudgement,
                  ) -> GeometryJudgement:
    """Case 3 of the module doc: geometry that cannot be the body gives no evidence."""
    import dataclasses

    rho = judged.density
    lo, hi = PLAUSIBLE_DENSITY
    if rho is not None and not lo <= rho <= hi:
        slip = unit_slip(rho)
        if slip is not None and slip[1] == "geometry":
            return dataclasses.replace(judged, geometry_slip=slip[2])
        # a mass slip is for the slip search to show (it must fit the body); without one,
        # the geometry is not the body
        return dataclasses.replace(judged, not_body=not_the_body(rho),
                                   mass_slip=None if slip is None else slip[2])
    bounds = judged.bounds
    assert bounds is not None
    if raw.com_ok and _outside(raw.com, *bounds) > MARKER_OUTSIDE * _diagonal(*bounds) \
            and float(np.trace(raw.inertia)) > ceiling(raw, *bounds):
        return dataclasses.replace(judged, not_body=(
            "geometry is a marker, not the body (the written CoM lies more than a box "
            "diagonal outside it, the tensor beyond all the mass on its corners)"))
    return judged


def not_the_body(density: float) -> str:
    """Why geometry with this implied density (kg/m^3) cannot be the link's body."""
    lo, hi = PLAUSIBLE_DENSITY
    if density > hi:
        return (f"geometry is a marker, not the body (implied density {density:.3g} kg/m^3, "
                f"denser than any material)")
    return (f"geometry is an envelope, not the body (implied density {density:.3g} kg/m^3, "
            f"lighter than any solid part, below {lo:g})")


def candidate_findings(ev: LinkEvidence, raw: RawInertial, c: Candidate, bounds: Bounds,
                       ) -> list[Finding]:
    """The written mass and tensor against candidate ``c``: implied density and tensor
    size (empty: they agree)."""
    out = []
    line = ev.link.inertial.line if ev.link.inertial is not None else None
    rho = raw.mass / c.volume
    lo, hi = PLAUSIBLE_DENSITY
    if not lo <= rho <= hi:
        out.append(Finding(Rule.IMPLAUSIBLE_DENSITY, ev.name, f"{raw.mass:.4g} kg in "
                           f"{c.volume:.4g} m^3 of {c.role} geometry is {rho:.3g} kg/m^3, "
                           f"outside {lo:g}..{hi:g}{_unit_hint(rho)}", line, "inertial"))
    d = diagnosis(raw)
    if d.finite and not d.zero:
        found = _scale_finding(ev.name, raw, c, bounds, line)
        if found is not None:
            out.append(found)
    return out


def _scale_finding(name: str, raw: RawInertial, c: Candidate, bounds: Bounds,
                   line: int | None) -> Finding | None:
    try:
        geo = assemble(c.parts, MassSource("kept", raw.mass)).total
    except (UrdfInertiaError, ValueError, FloatingPointError):
        return None
    written = float(np.trace(raw.inertia))
    computed = float(np.trace(geo.inertia))
    top = ceiling(raw, *bounds)
    if not computed > 0:
        return None
    ratio = written / computed
    if 1 / INERTIA_RATIO_LIMIT <= ratio <= INERTIA_RATIO_LIMIT and written <= top:
        return None
    beyond = (f"; more than the {top:.3g} kg m^2 ceiling of all mass on the box's far "
              "corners" if written > top else "")
    side = "larger" if ratio > 1 else "smaller"
    return Finding(Rule.INERTIA_VS_GEOMETRY, name, f"tensor trace {written:.4g} kg m^2 is "
                   f"{ratio:.3g}x the {c.role} geometry's {computed:.4g} at {raw.mass:.4g} kg "
                   f"({side} than plausible{beyond})", line, "inertial")


def com_findings(name: str, raw: RawInertial, bounds: Bounds, line: int | None,
                 ) -> list[Finding]:
    """The written CoM against the box of every geometry element."""
    lo, hi = bounds
    outside = _outside(raw.com, lo, hi)
    diag = _diagonal(lo, hi)
    if diag <= 0 or outside <= COM_OUTSIDE_WARN * diag:
        return []
    rel = outside / diag
    rule = (Rule.COM_FAR_OUTSIDE_GEOMETRY if rel > COM_OUTSIDE_ERROR
            else Rule.COM_OUTSIDE_GEOMETRY)
    return [Finding(rule, name, f"CoM {np.round(raw.com, 6).tolist()} m is {outside:.4g} m "
                    f"({rel:.3g} box diagonals) outside the geometry's bounding box "
                    f"{np.round(lo, 4).tolist()}..{np.round(hi, 4).tolist()}", line,
                    "inertial")]


def _outside(com: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> float:
    """How far ``com`` lies outside the box ``lo..hi`` (0 inside), m."""
    return float(np.linalg.norm(np.maximum(np.maximum(lo - com, com - hi), 0.0)))


def _diagonal(lo: np.ndarray, hi: np.ndarray) -> float:
    return float(np.linalg.norm(hi - lo))


def ceiling(raw: RawInertial, lo: np.ndarray, hi: np.ndarray) -> float:
    """The largest trace of a tensor about the CoM of the mass in the box ``lo..hi``:
    trace(I_com) = 2 integral |r - c|^2 dm <= 2 m max |corner - c|^2."""
    corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1])
                        for z in (lo[2], hi[2])])
    return 2 * raw.mass * float(np.max(np.sum((corners - raw.com) ** 2, axis=1)))


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


def inside(raw: RawInertial, bounds: Bounds | None, margin: float) -> bool:
    """The written CoM lies in the box grown by ``margin`` of its diagonal on every side."""
    if bounds is None or not raw.com_ok:
        return False
    lo, hi = bounds
    grow = margin * _diagonal(lo, hi)
    return bool(np.all(raw.com >= lo - grow) and np.all(raw.com <= hi + grow))
