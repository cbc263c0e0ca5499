"""Per-element and per-part breakdown of one link: the paper's section 5 analysis.

For every element p and part q of a link: its mass, its centre of mass in the link frame,
its tensor about its own centre of mass (`I_sp`, eq. 39) and about the link's centre of
mass (`I_p,s`, eq. 43, Huygens-Steiner), and its share of each principal moment of the
link: `e_k^T I_p,s e_k / lambda_k` for the link's principal axes e_k and moments
lambda_k. Since `sum_p I_p,s = I_s` (eq. 44), the shares of all elements add up to 1 on
every axis. Cavities have negative mass and negative shares.

The link's total is what `fix` writes (its verdict, `urdfinertia.plan.fix.link_verdict`):
the kept CoM where `fix` keeps it, the written values of a link `fix` keeps. The
elements are the geometry's homogeneous model, taken about the geometry's own centroid
(where eq. 44 holds), whatever `fix` decided.

No printing here: `urdfinertia.render.table` renders a
[`Breakdown`][urdfinertia.analysis.explain.Breakdown], `breakdown_dict` makes it JSON-ready.
"""

from __future__ import annotations

import difflib
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from urdfinertia.body.assemble import PartResult
from urdfinertia.body.geometry_choice import GeometryChoice
from urdfinertia.body.options import FixOptions
from urdfinertia.cache.library import MeshLibrary, mesh_library
from urdfinertia.descriptions.model import Robot
from urdfinertia.errors import UrdfInertiaError
from urdfinertia.findings import Finding, finding_dict
from urdfinertia.inertia.massprops import MassProperties, combine
from urdfinertia.plan.fix import link_verdict
from urdfinertia.plan.policy import every_link
from urdfinertia.plan.results import LinkResult


@dataclass(frozen=True, eq=False)
class Contribution:
    """One element or part, in the link frame.

    mass : float
        kg, negative for a cavity.
    com : (3,) float or None
        Centre of mass in the link frame, m (None when an element's masses cancel).
    inertia_own : (3, 3) float or None
        ``I_sp``: about its own centre of mass along the link axes, kg m^2.
    inertia_link : (3, 3) float
        ``I_p,s``: about the link's centre of mass along the link axes, kg m^2.
    share : (3,) float
        Fraction of each principal moment of the link (ascending order of moments).
    """

    name: str
    mass: float
    com: np.ndarray | None
    inertia_own: np.ndarray | None
    inertia_link: np.ndarray
    share: np.ndarray
    volume: float
    density: float | None = None  # kg/m^3, parts only
    method: str = ""
    cavity: bool = False


@dataclass(frozen=True, eq=False)
class ElementBreakdown:
    element: Contribution
    parts: tuple[Contribution, ...]


@dataclass(frozen=True, eq=False)
class Breakdown:
    """A link's total (what `fix` writes) and its elements' and parts' contributions.

    Attributes
    ----------
    link : str
    geometry : str
        What the parts come from: "spec", "collision" or "visual".
    mass_source : str
        What the link's mass is taken from (the assembly's `MassSource`, as text).
    total : MassProperties
        What `fix` writes for the link.
    moments : (3,) float
        Principal moments of `total`, ascending, kg m^2.
    axes : (3, 3) float
        Principal axes as columns, in the link frame.
    elements : tuple of ElementBreakdown
        Every element with its parts, in first-seen order.
    findings : tuple of Finding
        The verdict's findings.
    geometry_total : MassProperties or None
        The homogeneous geometry's own mass properties (the elements' sum).
    decision : str
        What `fix` does with the link ("kept: plausible", ...).
    verdict : LinkResult or None
        The link's verdict.
    choice : GeometryChoice or None
        Which geometry the parts are, and why (`--geometry auto` chooses per link).
    """

    link: str
    geometry: str  # "spec" | "collision" | "visual"
    mass_source: str
    total: MassProperties
    moments: np.ndarray  # (3,) principal moments of ``total``, ascending, kg m^2
    axes: np.ndarray  # (3, 3) principal axes as columns, in the link frame
    elements: tuple[ElementBreakdown, ...]
    findings: tuple[Finding, ...] = ()
    geometry_total: MassProperties | None = None
    decision: str = ""
    verdict: LinkResult | None = None
    choice: GeometryChoice | None = None


def _share(inertia_link: np.ndarray, moments: np.ndarray, axes: np.ndarray) -> np.ndarray:
    projected = np.einsum("ik,ij,jk->k", axes, inertia_link, axes)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(moments > 0, projected / np.where(moments > 0, moments, 1.0), 0.0)


def _contribution(name: str, bodies: Sequence[MassProperties], link_com: np.ndarray,
                  moments: np.ndarray, axes: np.ndarray, volume: float, **extra: Any,
                  ) -> Contribution:
    inertia_link = sum((b.about(link_com) for b in bodies), np.zeros((3, 3)))
    try:
        own: MassProperties | None = combine(bodies)
    except ValueError:  # masses cancel: no centre of mass
        own = None
    mass = float(sum(b.mass for b in bodies))
    return Contribution(name, mass, None if own is None else own.com,
                        None if own is None else own.inertia, inertia_link,
                        _share(inertia_link, moments, axes), volume, **extra)


def link_breakdown(result: LinkResult, verdict: LinkResult | None = None) -> Breakdown:
    """The breakdown of a link computed from its parts (elements in first-seen order).

    ``verdict``: the link's verdict under the policy, whose values (what ``fix`` writes)
    become the total; by default ``result``'s own.
    """
    if result.assembly is None:
        raise UrdfInertiaError("link has no geometry and no spec entry: nothing to explain",
                               link=result.name)
    verdict = verdict or result
    try:
        own = combine([pr.mass_properties for pr in result.assembly.parts])
    except ValueError:  # no parts (a repaired link) or masses that cancel
        own = result.assembly.total
    # the elements about the geometry's own centroid, where their shares add up to 1
    moments, axes = own.principal()
    total = verdict.after or result.assembly.total
    groups: dict[str, list[PartResult]] = {}
    for pr in result.assembly.parts:
        groups.setdefault(pr.part.element, []).append(pr)
    elements = []
    for name, prs in groups.items():
        parts = tuple(
            _contribution(pr.part.name, [pr.mass_properties], own.com, moments, axes,
                          -pr.part.volume if pr.part.cavity else pr.part.volume,
                          density=pr.density, method=pr.part.method, cavity=pr.part.cavity)
            for pr in prs)
        element = _contribution(name, [pr.mass_properties for pr in prs], own.com, moments,
                                axes, sum(p.volume for p in parts))
        elements.append(ElementBreakdown(element, parts))
    total_moments, total_axes = total.principal()
    return Breakdown(result.name, result.geometry, str(result.assembly.mass_source), total,
                     total_moments, total_axes, tuple(elements), verdict.findings,
                     geometry_total=own, decision=verdict.decision, verdict=verdict,
                     choice=result.choice)


def explain_link(robot: Robot, name: str, options: FixOptions | None = None,
                 meshes: MeshLibrary | None = None) -> Breakdown:
    """Link ``name`` of ``robot`` as ``fix`` decides it, broken down into its geometry.

    The total is what ``fix`` writes; the elements are the geometry's (or spec's) parts.
    A wrong name raises an error naming the nearest link names.
    """
    options = options or FixOptions()
    path = robot.path or Path("robot.urdf")
    names = [link.name for link in robot.links]
    if name not in names:
        near = difflib.get_close_matches(name, names, n=3, cutoff=0.0)
        raise UrdfInertiaError(f"no link named '{name}' (did you mean: {', '.join(near)}?)",
                               file=path)
    if meshes is None:
        meshes = mesh_library(options.package_dirs, options.max_faces)
    verdict = link_verdict(robot, name, options, meshes)
    try:
        if verdict.assembly is not None and verdict.assembly.parts:
            return link_breakdown(verdict)
        # fix keeps or repairs the link: its parts are the geometry's, the total fix's
        result = link_verdict(robot, name, every_link(options), meshes)
        return link_breakdown(result, verdict)
    except UrdfInertiaError as exc:
        raise exc.with_context(file=path, link=name) from None


def _tensor(t: np.ndarray | None) -> dict[str, float] | None:
    if t is None:
        return None
    return {"ixx": t[0, 0], "iyy": t[1, 1], "izz": t[2, 2],
            "ixy": t[0, 1], "ixz": t[0, 2], "iyz": t[1, 2]}


def contribution_dict(c: Contribution) -> dict[str, Any]:
    out: dict[str, Any] = {
        "name": c.name, "mass": c.mass, "volume": c.volume,
        "com": None if c.com is None else c.com.tolist(),
        "inertia_about_own_com": _tensor(c.inertia_own),
        "inertia_about_link_com": _tensor(c.inertia_link),
        "share_of_principal_moments": c.share.tolist(),
    }
    if c.method:
        out.update(density=c.density, method=c.method, cavity=c.cavity)
    return out


def breakdown_dict(b: Breakdown) -> dict[str, Any]:
    """JSON-ready view; tensors use the URDF sign convention, link frame axes."""
    return {
        "link": b.link,
        "geometry": b.geometry,
        "mass_source": b.mass_source,
        "total": {"mass": b.total.mass, "com": b.total.com.tolist(),
                  "inertia": _tensor(b.total.inertia),
                  "principal_moments": b.moments.tolist(),
                  "principal_axes": b.axes.T.tolist()},
        "elements": [{**contribution_dict(e.element),
                      "parts": [contribution_dict(p) for p in e.parts]} for e in b.elements],
        "findings": [finding_dict(f) for f in b.findings],
        "decision": b.decision,
        "error_bar": (b.verdict.error_bar.as_dict() if b.verdict is not None
                      and b.verdict.error_bar is not None else None),
        "geometry_choice": b.choice.as_dict() if b.choice is not None else None,
        "geometry_total": None if b.geometry_total is None else {
            "mass": b.geometry_total.mass, "com": b.geometry_total.com.tolist(),
            "inertia": _tensor(b.geometry_total.inertia)},
    }
