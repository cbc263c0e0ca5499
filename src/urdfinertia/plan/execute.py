"""Carry a link's plan out: the verdict a :class:`~.policy.LinkPlan` gives, and nothing else.

Nothing is decided here: the plan holds the action, its grounds and the values to write.
Carrying it out places a kept CoM (the homogeneous solid's tensor about its own centroid,
written at the kept CoM: measured on real robots, adding the parallel-axis term to move it
there makes the error against CAD worse in the tail, p90 76 % -> 104 %), attaches the
error bar of a derived tensor (:mod:`urdfinertia.body.errorbar`) and says what the
derived values show (a mesh repaired, a density no material has, a span of metres), as
findings.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from urdfinertia.body.assemble import Assembly
from urdfinertia.body.errorbar import MassBand, tensor_error_bar
from urdfinertia.body.evidence import LinkEvidence
from urdfinertia.body.options import PLAUSIBLE_DENSITY
from urdfinertia.findings import Finding
from urdfinertia.inertia.massprops import MassProperties
from urdfinertia.judge.robot import LinkJudgement
from urdfinertia.plan.policy import LinkPlan
from urdfinertia.plan.results import Action, LinkResult, Status
from urdfinertia.rules import Rule

VALUES = ("mass", "com", "tensor")


def execute(ev: LinkEvidence, j: LinkJudgement, plan: LinkPlan) -> LinkResult:
    """The verdict of one link under ``plan`` (module doc)."""
    link = ev.link
    written = VALUES if link.inertial is not None else ()
    said = {(f.rule, f.link, f.element) for f in j.findings if f.element}
    findings = j.findings + tuple(f for f in plan.notes
                                  if not f.element or (f.rule, f.link, f.element) not in said)
    stated = link.implicit.mass if link.implicit is not None else None
    base = LinkResult(ev.name, Status.KEPT, plan.action, findings, plan.grounds, plan.because,
                      previous=link.inertial, kept=written, stated_mass=stated)
    if plan.action == Action.KEEP:
        return base
    if plan.action == Action.LEAVE:
        status = Status.LEFT if plan.unresolved else Status.UNTOUCHED
        return replace(base, status=status, geometry="none")
    assert plan.assembly is not None
    if plan.action in (Action.CORRECT, Action.REPAIR):
        return replace(base, status=Status.REPAIRED, geometry=plan.role,
                       assembly=plan.assembly, kept=tuple(v for v in VALUES if v in plan.keep),
                       derived=tuple(v for v in VALUES if v not in plan.keep), slip=plan.slip)
    assembly = plan.assembly
    offset = None
    if "com" in plan.keep and ev.raw is not None:
        com = ev.raw.com
        total = assembly.total
        offset = float(np.linalg.norm(total.com - com))
        assembly = Assembly(MassProperties(total.mass, com, total.inertia), assembly.parts,
                            assembly.mass_source)
    kept = tuple(v for v in VALUES if v in plan.keep)
    choice = plan.choice
    error_bar = None
    if plan.role != "spec":
        diagonal = choice.diagonal if choice is not None else None
        if diagonal is None and j.geometry.bounds is not None:
            lo, hi = j.geometry.bounds
            diagonal = float(np.linalg.norm(hi - lo))
        error_bar = tensor_error_bar(offset, diagonal, *((choice.kind, choice.role,
                                                          choice.density)
                                                         if choice is not None else ()))
        prior = plan.prior
        if prior is not None and error_bar is not None:
            error_bar = replace(error_bar, mass=MassBand(
                prior.low, prior.high, prior.level, prior.density,
                prior.mass / prior.density * 1000.0))
    return replace(base, status=Status.RECOMPUTED, geometry=plan.role, assembly=assembly,
                   findings=findings + derived_notes(ev, assembly), kept=kept,
                   derived=tuple(v for v in VALUES if v not in kept), error_bar=error_bar,
                   choice=choice)


def derived_notes(ev: LinkEvidence, assembly: Assembly) -> tuple[Finding, ...]:
    """What the derived values show: meshes repaired, a density no material has, a span of
    metres (a millimetre mesh without its scale)."""
    out: list[Finding] = []
    name = ev.name
    for pr in assembly.parts:
        p = pr.part
        for note in p.notes:
            out.append(Finding(Rule.MESH_REPAIRED, name, f"{p.name}: {note}", None,
                               p.element))
    parts = [pr.part for pr in assembly.parts]
    volume = sum(-p.volume if p.cavity else p.volume for p in parts)
    if volume > 0:
        rho = assembly.total.mass / volume
        lo, hi = PLAUSIBLE_DENSITY
        if not lo <= rho <= hi:
            out.append(Finding(Rule.DERIVED_FROM_IMPLAUSIBLE, name, f"implied density "
                               f"{rho:.3g} kg/m^3 is outside {lo:g}..{hi:g} (unit slip or "
                               "placeholder mass?)", ev.link.line))
    extent = 0.0
    for p in parts:
        reach = float(np.linalg.norm(p.pose[:3, :3] @ p.unit.com + p.pose[:3, 3]))
        if p.unit.mass:
            reach += math.sqrt(max(float(np.trace(p.unit.inertia)), 0.0)
                               / (2.0 * abs(p.unit.mass)))
        extent = max(extent, reach)
    if extent > 10.0:
        out.append(Finding(Rule.GEOMETRY_SPANS_FAR, name, f"geometry spans {extent:.3g} m: "
                           "millimetre mesh without scale?", ev.link.line))
    return tuple(dict.fromkeys(out))
