"""Which of a link's geometries a derived inertial integrates: ``--geometry auto``, per link.

A link may carry more than one description of its body: collision elements (often stand-ins:
one capsule for a forearm, a box for a hand, a convex hull) and visual elements (usually
the CAD shape); an MJCF body also has the geoms MuJoCo itself counts for inertia. Collision
geometry stays what simulators collide with; this choice is only for the inertial, and is
made only for links whose values are derived (clean links never read their visuals).

Each candidate set is integrated at unit density and judged on what the link still knows
(its kept mass and CoM), in this order:

1. every element read (a set with an element dropped loses against a whole one);
2. a plausible implied density (kept mass over volume within
   :data:`~urdfinertia.body.options.PLAUSIBLE_DENSITY`): a volume that no material fills
   with the kept mass is not the body. With no mass kept, an MJCF body's own geoms
   (what MuJoCo computes with, materials included) are used;
3. an implied density at most :data:`DENSE`: a set that would have to be denser than
   solid titanium throughout is short of the body's volume (an open or thinned shell,
   parts not drawn). Measured (``scripts/bench_cad.py``), this keeps the detailed mesh
   on most links and drops it where it misses volume;
4. a centroid on the kept CoM (within :data:`CENTROID_MATCH` of the box diagonal): the
   inertial was computed from that very geometry (a tool's output, or MuJoCo's), so its
   shape is the one that gave the tensor too;
5. the most faithful kind: a detailed mesh over a convex hull over primitive stand-ins
   (:data:`KINDS`); a mesh is a hull when its volume is at least :data:`CONVEX_RATIO`
   of its convex hull's;
6. among sets of that kind, the centroid nearest the kept CoM (as a fraction of each
   set's box diagonal). Measured (``scripts/bench_cad.py``), letting a far centroid hand
   the choice to a less faithful kind made the error worse, at any threshold tried.

The result says which set was used and why (:class:`GeometryChoice`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from urdfinertia.body.options import PLAUSIBLE_DENSITY, weighable
from urdfinertia.errors import UrdfInertiaError

if TYPE_CHECKING:
    from collections.abc import Sequence

    from urdfinertia.body.parts import MeshSource, Part
    from urdfinertia.descriptions.model import GeometryRef, Link
    from urdfinertia.findings import Finding

#: Kinds of geometry, least to most faithful to the body.
KINDS = ("primitive", "hull", "mesh")
#: A centroid within this fraction of the box diagonal of the kept CoM matches it.
CENTROID_MATCH = 1e-3
#: Words for the kinds, as the table and ``explain`` say them.
KIND_WORDS = {"primitive": "primitive stand-ins", "hull": "convex hull",
              "mesh": "detailed mesh"}
#: A mesh whose volume is at least this fraction of its convex hull's is (taken as) a hull.
CONVEX_RATIO = 0.97
#: kg/m^3: a set that needs a density above this to hold the kept mass would be denser
#: than solid titanium throughout; a link of aluminium, steel and plastic with air inside
#: is lighter, so the set's volume is likely short of the body's. Chosen from materials,
#: not fitted; the error bar uses it too (:mod:`urdfinertia.body.errorbar`).
DENSE = 4500.0


@dataclass(frozen=True, eq=False)
class Candidate:
    """One set of a link's elements, integrated at unit density (link frame)."""

    role: str  # "collision" | "visual" | "geom"
    refs: tuple[GeometryRef, ...]
    parts: tuple[Part, ...]
    dropped: tuple[Finding, ...]
    kind: str
    volume: float  # m^3, cavities subtracted
    centroid: np.ndarray  # (3,) m
    diagonal: float | None  # of the set's box, m


@dataclass(frozen=True)
class GeometryChoice:
    """The geometry a derived inertial integrates, and why.

    role : "collision", "visual" or "geom" (MJCF: the geoms MuJoCo counts for inertia).
    kind : :data:`KINDS`: "primitive", "hull" or "mesh" (detailed).
    why : the reason in plain words.
    offset : centroid-to-kept-CoM distance over the box diagonal (None: no CoM kept).
    diagonal : the chosen set's box diagonal, m (None: not known).
    density : kept mass over the set's volume, kg/m^3 (None: no mass kept).
    others : the candidates not chosen, as "visual (detailed mesh)".
    """

    role: str
    kind: str
    why: str
    offset: float | None = None
    diagonal: float | None = None
    density: float | None = None
    others: tuple[str, ...] = ()

    def __str__(self) -> str:
        return f"{self.role} ({KIND_WORDS[self.kind]}): {self.why}"

    def as_dict(self) -> dict[str, object]:
        return {"role": self.role, "kind": self.kind, "why": self.why,
                "offset": self.offset, "diagonal": self.diagonal, "density": self.density,
                "others": list(self.others)}


def candidate_sets(link: Link) -> list[tuple[str, tuple[GeometryRef, ...]]]:
    """The link's distinct element sets that may make its inertial, format's own first."""
    out: list[tuple[str, tuple[GeometryRef, ...]]] = []
    if link.inertia_geometry:
        out.append(("geom", link.inertia_geometry))
    for role, refs in (("collision", link.collisions), ("visual", link.visuals)):
        refs = weighable(refs)
        if refs and not any(_same(refs, other) for _, other in out):
            out.append((role, refs))
    return out


def _same(a: tuple[GeometryRef, ...], b: tuple[GeometryRef, ...]) -> bool:
    key = [(r.shape, r.origin, r.line) for r in a]
    return key == [(r.shape, r.origin, r.line) for r in b]


def usable_parts(link: Link, refs: Sequence[GeometryRef], meshes: MeshSource,
                 urdf_dir: Path, found: list[Finding]) -> list[Part]:
    """The parts of every element of ``refs`` that makes them; each that does not is
    dropped with a finding (the error's rule) appended to ``found``."""
    from urdfinertia.body.parts import geometry_parts
    from urdfinertia.findings import Finding

    parts: list[Part] = []
    for ref in refs:
        try:
            parts.extend(geometry_parts(ref, meshes, urdf_dir))
        except UrdfInertiaError as exc:
            found.append(Finding(exc.rule, link.name, f"dropped: {exc.cause}",
                                 exc.line or ref.line, ref.label))
    return parts


def evaluate(link: Link, role: str, refs: tuple[GeometryRef, ...], meshes: MeshSource,
             urdf_dir: Path, detail: bool = True) -> Candidate | None:
    """One candidate set integrated at unit density; None when nothing of it is usable.

    ``detail=False`` (nothing to choose and no CoM to hold it against) skips what needs the
    mesh files' points: the box diagonal (None) and hull detection (a mesh is "mesh").
    """
    found: list[Finding] = []
    # the points first (the box, the hull), then the solids: a mesh read for its points is
    # kept for its solids (the mesh library's order), never read twice
    diagonal = _diagonal(refs, meshes, urdf_dir) if detail else None
    parts = usable_parts(link, refs, meshes, urdf_dir, found)
    signed = [(-p.volume if p.cavity else p.volume) for p in parts]
    volume = float(sum(signed))
    if not parts or not volume > 0:
        return None
    centres = [p.pose[:3, :3] @ p.unit.com + p.pose[:3, 3] for p in parts]
    centroid = sum((v * c for v, c in zip(signed, centres, strict=True)),
                   start=np.zeros(3)) / volume
    if not detail:
        kind = "primitive" if all(p.method.startswith("closed form") for p in parts) \
            else "mesh"
        return Candidate(role, refs, tuple(parts), tuple(found), kind, volume, centroid, None)
    return Candidate(role, refs, tuple(parts), tuple(found), _kind(refs, parts, meshes,
                     urdf_dir), volume, centroid, diagonal)


def _kind(refs: tuple[GeometryRef, ...], parts: Sequence[Part], meshes: MeshSource,
          urdf_dir: Path) -> str:
    """The kind holding most of the set's volume (a mesh counts for "hull" too)."""
    from urdfinertia.descriptions.model import Mesh

    share = {k: 0.0 for k in KINDS}
    by_label = {r.label: r for r in refs}
    for label in dict.fromkeys(p.element for p in parts):
        mine = [p for p in parts if p.element == label]
        volume = sum(p.volume for p in mine)
        ref = by_label.get(label)
        if ref is None or not isinstance(ref.shape, Mesh):
            share["primitive"] += volume
            continue
        share[_mesh_kind(ref, volume, meshes, urdf_dir)] += volume
    total = sum(share.values())
    if total <= 0:
        return "primitive"
    if share["mesh"] >= 0.5 * total:
        return "mesh"
    return "hull" if share["mesh"] + share["hull"] >= 0.5 * total else "primitive"


def _mesh_kind(ref: GeometryRef, volume: float, meshes: MeshSource, urdf_dir: Path) -> str:
    """"hull" when the mesh fills its convex hull, else "mesh"."""
    from urdfinertia.descriptions.model import Mesh

    hull_of = getattr(meshes, "hull_volume", None)
    assert isinstance(ref.shape, Mesh)
    if hull_of is None:
        return "mesh"
    try:
        hull = hull_of(meshes.resolve(ref.shape.filename, urdf_dir), tuple(ref.shape.scale))
    except (UrdfInertiaError, ValueError):
        return "mesh"
    return "hull" if hull > 0 and volume >= CONVEX_RATIO * hull else "mesh"


def _diagonal(refs: tuple[GeometryRef, ...], meshes: MeshSource, urdf_dir: Path,
              ) -> float | None:
    from urdfinertia.body.bounds import BoundsCache, link_bounds
    from urdfinertia.cache.library import MeshLibrary

    if not isinstance(meshes, MeshLibrary):
        return None
    try:
        box = link_bounds(refs, BoundsCache(meshes), urdf_dir)
    except UrdfInertiaError:
        return None
    return None if box is None else float(np.linalg.norm(box[1] - box[0]))


def choose(candidates: Sequence[Candidate], mass: float | None, com: np.ndarray | None,
           ) -> tuple[Candidate, GeometryChoice]:
    """The candidate the inertial integrates (see the module doc), and why."""
    if not candidates:
        raise ValueError("no candidate geometry")
    lo, hi = PLAUSIBLE_DENSITY

    def density(c: Candidate) -> float | None:
        return mass / c.volume if mass is not None and mass > 0 else None

    def plausible(c: Candidate) -> bool:
        d = density(c)
        return d is None or lo <= d <= hi

    def offset(c: Candidate) -> float | None:
        if com is None or c.diagonal is None or not c.diagonal > 0:
            return None
        return float(np.linalg.norm(c.centroid - com)) / c.diagonal

    pool = list(candidates)
    reasons: list[str] = []
    whole = [c for c in pool if not c.dropped]
    if whole and len(whole) < len(pool):
        pool = whole
        reasons.append("every element read")
    own = [c for c in pool if c.role == "geom"]
    if mass is None and own:
        # nothing kept to judge by: the geoms and materials MuJoCo itself computes with
        pool = own
        reasons.append("the geoms MuJoCo counts, no mass kept")
    fits = [c for c in pool if plausible(c)]
    if fits and len(fits) < len(pool):
        pool = fits
        reasons.append("implied density plausible")
    solid = [c for c in pool if (d := density(c)) is None or d <= DENSE]
    if solid and len(solid) < len(pool):
        pool = solid
        reasons.append(f"implied density at most {DENSE:.0f} kg/m³")
    on_com = [c for c in pool if (o := offset(c)) is not None and o < CENTROID_MATCH]
    if on_com and len(on_com) < len(pool):
        pool = on_com
        reasons.append("centroid on the kept CoM")
    rank = {k: i for i, k in enumerate(KINDS)}
    pool.sort(key=lambda c: -rank[c.kind])
    best = pool[0]
    if len(pool) > 1:
        ties = [c for c in pool if c.kind == best.kind]
        if len(ties) < len(pool):
            worse = pool[len(ties)].kind
            reasons.append(f"{KIND_WORDS[best.kind]} over {KIND_WORDS[worse]}")
        with_offset = [c for c in ties if offset(c) is not None]
        if len(with_offset) > 1:
            best = min(with_offset, key=lambda c: offset(c))  # type: ignore[arg-type, return-value]
            reasons.append("centroid nearest the kept CoM")
    if len(candidates) == 1:
        reasons = ["the only geometry"]
    elif not reasons:
        reasons = ["first of equals"]
    others = tuple(f"{c.role} ({KIND_WORDS[c.kind]})" for c in candidates if c is not best)
    d = density(best)
    return best, GeometryChoice(best.role, best.kind, ", ".join(reasons), offset(best),
                                best.diagonal, d if d is None or math.isfinite(d) else None,
                                others)
