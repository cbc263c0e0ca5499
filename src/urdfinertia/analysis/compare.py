"""The `compare` job: per-link differences between two sets of inertials.

Side A is the existing (CAD) inertial or the first URDF; side B is computed from the
geometry (`compare_with_geometry`) or read from a second URDF (`compare_files`).
Both are taken in the link frame about their own CoM.

Metrics (each None when a side lacks what it needs):

- `mass_ratio` = m_B / m_A;
- `com_distance` = |c_B - c_A| in m, and `com_distance_rel` = that over the link size
  `L = sqrt(tr I / m)` of side B (of A when B has none): a radius-of-gyration length, which
  does not depend on where the link frame's origin sits;
- `inertia_rel_error` = ||I_B - I_A||_F / ||I_A||_F (relative to side A);
- `axis_angle_deg`: the largest angle between corresponding principal axes. An axis whose
  moment lies within `DEGENERATE_RTOL` of another's is not unique (any axis in that plane is
  principal), so it is taken at its best choice: the angle from the other side's axis to that
  plane. A (nearly) isotropic tensor has every axis principal, so it agrees with anything (0).

Against the geometry, every link also carries `fix`'s decision (its verdict, the one
`check`, `fix`, `report` and the library give). Side B stays the homogeneous
geometry's value, but a link beyond tolerance that `fix` keeps (plausible as written, or
geometry that is not the body) gets the verdict "kept", not "differs": the homogeneous
model is a model, and what the user acts on is what `fix` would change. `--fail-above`
counts only "differs" and "invalid" links.

The maths here is numpy only; `compare_with_geometry` and `compare_files` only
read files and run [`fix`][urdfinertia.plan.fix].
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from urdfinertia.analysis.matching import Matching, match_names
from urdfinertia.body.options import FixOptions
from urdfinertia.cache.library import MeshLibrary, mesh_library
from urdfinertia.descriptions.formats import read_description
from urdfinertia.descriptions.inertial import RawInertial
from urdfinertia.descriptions.model import Link
from urdfinertia.inertia.massprops import MassProperties
from urdfinertia.plan.fix import fix_robot, link_verdicts
from urdfinertia.plan.policy import every_link
from urdfinertia.plan.results import FixResult, LinkResult

#: Principal moments closer than this fraction of the largest count as equal (degenerate):
#: moments within a few percent give axes that swing with any perturbation of that size.
DEGENERATE_RTOL = 0.05
#: Default thresholds of the verdict (relative CoM distance, inertia error, mass mismatch).
DEFAULT_TOL_COM = 0.05
DEFAULT_TOL_INERTIA = 0.10
DEFAULT_TOL_MASS = 0.05
VERDICTS = ("ok", "differs", "kept", "invalid", "missing")
#: Verdicts that say the written inertial needs attention (``--fail-above`` counts these).
FAILING = ("differs", "invalid")


@dataclass(frozen=True, eq=False)
class LinkComparison:
    """One link, side A against side B (see the module doc for each metric)."""

    link: str
    a: MassProperties | None
    b: MassProperties | None
    mass_ratio: float | None
    com_distance: float | None
    com_distance_rel: float | None
    inertia_rel_error: float | None
    axis_angle_deg: float | None
    verdict: str  # one of VERDICTS
    note: str = ""
    size: float | None = None  # the length L used by com_distance_rel, m
    moments_a: np.ndarray | None = None  # principal moments ascending, even when invalid
    moments_b: np.ndarray | None = None
    #: what ``fix`` would do with the link (:mod:`urdfinertia.plan.policy`); geometry only
    decision: str = ""
    #: the link's verdict under the default policy (geometry only)
    fix: LinkResult | None = None

    def score(self, tol_com: float = DEFAULT_TOL_COM,
              tol_inertia: float = DEFAULT_TOL_INERTIA) -> float:
        """How far past its thresholds the link is (>1: beyond); inf when invalid."""
        if self.verdict == "invalid":
            return math.inf
        parts = [0.0]
        if self.com_distance_rel is not None:
            parts.append(self.com_distance_rel / tol_com)
        if self.inertia_rel_error is not None:
            parts.append(self.inertia_rel_error / tol_inertia)
        return max(parts)


# --- pure maths ----------------------------------------------------------------------
def inertia_rel_error(ia: ArrayLike, ib: ArrayLike) -> float:
    """||I_B - I_A||_F / ||I_A||_F; 0 when both are zero, inf when only A is."""
    a = np.asarray(ia, dtype=np.float64)
    b = np.asarray(ib, dtype=np.float64)
    diff = float(np.linalg.norm(b - a))
    ref = float(np.linalg.norm(a))
    if ref == 0:
        return 0.0 if diff == 0 else math.inf
    return diff / ref


def _separated(moments: np.ndarray, rtol: float) -> tuple[bool, bool, bool]:
    """Which principal axes are unique: their moment differs from both others."""
    tol = rtol * max(abs(float(moments[2])), 1e-300)
    close01 = moments[1] - moments[0] <= tol
    close12 = moments[2] - moments[1] <= tol
    return (not close01, not (close01 or close12), not close12)


def principal_axis_angle(ia: ArrayLike, ib: ArrayLike, rtol: float = DEGENERATE_RTOL,
                         ) -> float:
    """Largest angle (degrees) between corresponding principal axes of two tensors.

    Axes are matched by the order of their moments (smallest with smallest). Where an axis
    is not unique on one side (two moments within ``rtol``), the angle is measured from the
    other side's axis to that side's degenerate plane; an isotropic side matches anything.
    Axis signs are irrelevant (an axis is a line).
    """
    ma, va = np.linalg.eigh(0.5 * (np.asarray(ia, float) + np.asarray(ia, float).T))
    mb, vb = np.linalg.eigh(0.5 * (np.asarray(ib, float) + np.asarray(ib, float).T))
    sa, sb = _separated(ma, rtol), _separated(mb, rtol)
    worst = 0.0
    for k in range(3):
        if sa[k] and sb[k]:
            cos = min(abs(float(va[:, k] @ vb[:, k])), 1.0)
            worst = max(worst, math.degrees(math.acos(cos)))
        elif sa[k] or sb[k]:
            axis, (other_m, other_v, other_s) = (
                (va[:, k], (mb, vb, sb)) if sa[k] else (vb[:, k], (ma, va, sa)))
            unique = [j for j in range(3) if other_s[j]]
            if not unique:
                continue  # isotropic: every axis is principal
            # The degenerate plane is orthogonal to the other side's unique axis.
            sin = min(abs(float(axis @ other_v[:, unique[0]])), 1.0)
            worst = max(worst, math.degrees(math.asin(sin)))
    return worst


def link_size(raw: RawInertial | None) -> float | None:
    """``sqrt(tr I / m)``, m, or None when the values do not give one."""
    if raw is None or not raw.mass_ok:
        return None
    tr = float(np.trace(raw.inertia))
    if not (np.isfinite(tr) and tr > 0):
        return None
    return math.sqrt(tr / raw.mass)


def _problem(raw: RawInertial) -> str | None:
    if not np.isfinite(raw.mass) or raw.mass < 0:
        return f"mass {raw.mass}"
    if not raw.com_ok:
        return "CoM not finite"
    d = raw.diagnosis()
    if not d.finite:
        return "tensor not finite"
    if raw.mass == 0:
        return None if not np.any(raw.inertia) else "zero mass with a tensor"
    if d.zero:
        return "zero tensor"
    if not d.positive_definite:
        return "tensor not positive definite"
    if not d.triangle_ok:
        return f"A+B<C by {d.triangle_excess:.2g} of C"
    return None


def _moments(raw: RawInertial | None) -> np.ndarray | None:
    if raw is None:
        return None
    d = raw.diagnosis()
    return d.moments if d.finite else None


def compare_raw(link: str, a: RawInertial | None, b: RawInertial | None, *,
                tol_com: float = DEFAULT_TOL_COM, tol_inertia: float = DEFAULT_TOL_INERTIA,
                tol_mass: float = DEFAULT_TOL_MASS, missing_a: str = "A has no inertial",
                missing_b: str = "B has no inertial") -> LinkComparison:
    """Compare two unvalidated inertials (link frame, about their CoM)."""
    mp_a = a.mass_properties() if a is not None else None
    mp_b = b.mass_properties() if b is not None else None
    size = link_size(b) or link_size(a)
    moments_a, moments_b = _moments(a), _moments(b)
    if a is None or b is None:
        note = missing_a if a is None else missing_b
        return LinkComparison(link, mp_a, mp_b, None, None, None, None, None, "missing", note,
                              size=size, moments_a=moments_a, moments_b=moments_b)
    ratio = b.mass / a.mass if np.isfinite(a.mass) and a.mass > 0 and np.isfinite(b.mass) \
        else None
    dist = float(np.linalg.norm(b.com - a.com)) if a.com_ok and b.com_ok else None
    rel = dist / size if dist is not None and size else None
    finite = bool(np.all(np.isfinite(a.inertia)) and np.all(np.isfinite(b.inertia)))
    ierr = inertia_rel_error(a.inertia, b.inertia) if finite else None
    angle = principal_axis_angle(a.inertia, b.inertia) if finite else None
    problems = [f"{side}: {p}" for side, p in (("A", _problem(a)), ("B", _problem(b))) if p]
    if problems:
        verdict, note = "invalid", "; ".join(problems)
    elif a.mass == 0 and b.mass == 0:
        verdict, note = "ok", "massless on both sides"
    else:
        beyond = []
        if ratio is None or abs(ratio - 1) > tol_mass:
            beyond.append("mass")
        if rel is None or rel > tol_com:
            beyond.append("CoM")
        if ierr is None or ierr > tol_inertia:
            beyond.append("inertia")
        verdict = "differs" if beyond else "ok"
        note = ("beyond tolerance: " + ", ".join(beyond)) if beyond else ""
    return LinkComparison(link, mp_a, mp_b, ratio, dist, rel, ierr, angle, verdict, note,
                          size=size, moments_a=moments_a, moments_b=moments_b)


# --- jobs ----------------------------------------------------------------------------
def compare_with_geometry(path: str | Path, options: FixOptions | None = None,
                          fix_result: FixResult | None = None, *,
                          tol_com: float = DEFAULT_TOL_COM,
                          tol_inertia: float = DEFAULT_TOL_INERTIA,
                          tol_mass: float = DEFAULT_TOL_MASS,
                          verdicts: Sequence[LinkResult] | None = None,
                          meshes: MeshLibrary | None = None) -> list[LinkComparison]:
    """Existing inertials (A) against the ones computed from geometry (B), with ``fix``'s
    decision for each link.

    ``fix_result``: the geometry's values for every link (``fix`` with every link asked
    for), when already computed; ``verdicts``: the links' verdicts under ``options``.
    Links with neither an inertial nor geometry are left out.
    """
    options = options or FixOptions()
    if meshes is None:
        meshes = mesh_library(options.package_dirs, options.max_faces)
    if fix_result is None:
        robot, data = read_description(path)
        fix_result = fix_robot(robot, data, every_link(options), meshes)
    if verdicts is None:
        verdicts = link_verdicts(fix_result.robot, options, meshes)
    by_name = {v.name: v for v in verdicts}
    out = []
    for r in fix_result.links:
        a = RawInertial.from_inertial(r.previous) if r.previous is not None else None
        b = (RawInertial.from_mass_properties(r.assembly.total)
             if r.assembly is not None else None)
        if a is None and b is None:
            continue
        c = compare_raw(r.name, a, b, tol_com=tol_com, tol_inertia=tol_inertia,
                        tol_mass=tol_mass, missing_a="no <inertial> in the file",
                        missing_b="no geometry to compute from")
        v = by_name[r.name]
        if c.verdict == "differs" and not v.changed:
            c = replace(c, verdict="kept")
        out.append(replace(c, decision=v.planned, fix=v))
    return out


def compare_files(path_a: str | Path, path_b: str | Path, *,
                  tol_com: float = DEFAULT_TOL_COM, tol_inertia: float = DEFAULT_TOL_INERTIA,
                  tol_mass: float = DEFAULT_TOL_MASS) -> list[LinkComparison]:
    """Inertials of description A against description B, links matched by name as
    converters rename them (:mod:`urdfinertia.analysis.matching`), in A's order, then B's
    links A does not have."""
    return match_files(path_a, path_b, tol_com=tol_com, tol_inertia=tol_inertia,
                       tol_mass=tol_mass)[0]


def match_files(path_a: str | Path, path_b: str | Path, *,
                tol_com: float = DEFAULT_TOL_COM, tol_inertia: float = DEFAULT_TOL_INERTIA,
                tol_mass: float = DEFAULT_TOL_MASS) -> tuple[list[LinkComparison], Matching]:
    """:func:`compare_files` and the matching of the links' names it used."""
    robot_a, _ = read_description(path_a)
    robot_b, _ = read_description(path_b)
    links_a = {link.name: link for link in robot_a.links}
    links_b = {link.name: link for link in robot_b.links}
    matching = match_names(list(links_a), list(links_b))
    other = dict(matching.pairs)
    out = []
    for name in [*links_a, *matching.only_b]:
        la = links_a.get(name)
        lb = links_b.get(other[name]) if name in other else (
            links_b[name] if la is None else None)
        ia = _raw(la)
        ib = _raw(lb)
        if ia is None and ib is None:
            continue
        renamed = lb is not None and la is not None and lb.name != name
        c = compare_raw(name, ia, ib, tol_com=tol_com, tol_inertia=tol_inertia,
                        tol_mass=tol_mass, missing_a=_missing("A", la),
                        missing_b=_missing("B", lb))
        if renamed and lb is not None and not c.note:
            c = replace(c, note=f"named {lb.name} in B")
        out.append(c)
    return out, matching


def _raw(link: Link | None) -> RawInertial | None:
    return None if link is None or link.inertial is None else \
        RawInertial.from_inertial(link.inertial)


def _missing(side: str, link: Link | None) -> str:
    """Why side ``side`` has no inertial for a link."""
    if link is None:
        return f"no link of side {side} matches"
    implicit = link.implicit
    if implicit is not None and implicit.mass is not None:
        return (f"{side} states only a mass ({implicit.mass:.6g} kg): the engine derives "
                f"CoM and tensor from its {implicit.source}")
    return f"no <inertial> in {side}" + (f" ({link.name})" if side == "B" else "")


def worst_first(comparisons: Sequence[LinkComparison], tol_com: float = DEFAULT_TOL_COM,
                tol_inertia: float = DEFAULT_TOL_INERTIA) -> list[LinkComparison]:
    """Invalid links first, then by :meth:`LinkComparison.score`, missing ones last."""
    def key(c: LinkComparison) -> tuple[int, float]:
        return (1 if c.verdict == "missing" else 0, -c.score(tol_com, tol_inertia))
    return sorted(comparisons, key=key)


def _median(values: list[float]) -> float | None:
    finite = [v for v in values if v is not None and math.isfinite(v)]
    return float(np.median(finite)) if finite else None


def summary(comparisons: Sequence[LinkComparison], worst: int = 3) -> dict[str, Any]:
    """Counts by verdict, medians of each metric over links that have it, worst links."""
    metrics = ("mass_ratio", "com_distance", "com_distance_rel", "inertia_rel_error",
               "axis_angle_deg")
    out: dict[str, Any] = {
        "links": len(comparisons),
        "verdicts": {v: n for v, n in Counter(c.verdict for c in comparisons).items()},
        "median": {m: _median([getattr(c, m) for c in comparisons]) for m in metrics},
        "worst": {},
    }
    for m in ("com_distance_rel", "inertia_rel_error", "axis_angle_deg"):
        values = [(c, getattr(c, m)) for c in comparisons]
        ranked = [c for c, v in sorted(((c, v) for c, v in values
                                        if v is not None and math.isfinite(v)),
                                       key=lambda cv: -cv[1])]
        out["worst"][m] = [[c.link, getattr(c, m)] for c in ranked[:worst]]
    return out


def comparison_dict(c: LinkComparison) -> dict[str, Any]:
    """JSON-ready view of one comparison (non-finite numbers become None)."""
    def num(x: float | None) -> float | None:
        return float(x) if x is not None and math.isfinite(x) else None

    def side(mp: MassProperties | None, moments: np.ndarray | None) -> dict[str, Any] | None:
        if mp is None:
            return None if moments is None else {"principal_moments": moments.tolist()}
        i = mp.inertia
        return {"mass": mp.mass, "com": mp.com.tolist(),
                "inertia": {"ixx": i[0, 0], "ixy": i[0, 1], "ixz": i[0, 2], "iyy": i[1, 1],
                            "iyz": i[1, 2], "izz": i[2, 2]},
                "principal_moments": mp.principal()[0].tolist()}

    return {"link": c.link, "verdict": c.verdict, "note": c.note, "fix": c.decision,
            "action": str(c.fix.action) if c.fix is not None and c.fix.action else None,
            "mass_ratio": num(c.mass_ratio), "com_distance": num(c.com_distance),
            "com_distance_rel": num(c.com_distance_rel),
            "inertia_rel_error": num(c.inertia_rel_error),
            "axis_angle_deg": num(c.axis_angle_deg), "size": num(c.size),
            "a": side(c.a, c.moments_a), "b": side(c.b, c.moments_b)}
