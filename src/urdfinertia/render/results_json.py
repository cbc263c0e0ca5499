"""Plain-data (JSON-ready) views of results for ``--json``."""

from __future__ import annotations

from typing import Any

import numpy as np

from urdfinertia.descriptions.model import Problem
from urdfinertia.findings import Finding
from urdfinertia.inertia.massprops import MassProperties
from urdfinertia.plan.apply import mass_change
from urdfinertia.plan.results import FixResult, LinkResult
from urdfinertia.render.decisions import decision_dict


def mass_properties_dict(mp: MassProperties) -> dict[str, Any]:
    moments, axes = mp.principal()
    i = mp.inertia
    return {
        "mass": mp.mass,
        "com": mp.com.tolist(),
        "inertia": {"ixx": i[0, 0], "ixy": i[0, 1], "ixz": i[0, 2],
                    "iyy": i[1, 1], "iyz": i[1, 2], "izz": i[2, 2]},
        "principal_moments": moments.tolist(),
        "principal_axes": axes.T.tolist(),
    }


def link_dict(r: LinkResult) -> dict[str, Any]:
    out: dict[str, Any] = {"link": r.name, "status": str(r.status), "geometry": r.geometry,
                           "warnings": list(r.warnings), **decision_dict(r),
                           **before_after_dict(r)}
    if r.reason is not None:
        out["reason"] = r.reason
    if r.problems:
        out["problems"] = [problem_dict(p) for p in r.problems]
    if r.previous is not None:
        prev = r.previous
        out["previous"] = {"mass": prev.mass, "com": list(prev.origin.xyz),
                           "inertia_in_link_axes": np.asarray(prev.tensor_in_link()).tolist()}
    if r.assembly is not None:
        out["result"] = mass_properties_dict(r.assembly.total)
        out["mass_source"] = str(r.assembly.mass_source)
        out["parts"] = [
            {"name": pr.part.name, "element": pr.part.element, "method": pr.part.method,
             "volume": pr.part.volume, "density": pr.density, "cavity": pr.part.cavity,
             "notes": list(pr.part.notes), "provenance": pr.part.provenance,
             "uncertainty": pr.part.uncertainty, **mass_properties_dict(pr.mass_properties)}
            for pr in r.assembly.parts
        ]
    return out


def finding_dict(f: Finding) -> dict[str, Any]:
    """A finding with its rule id (the fields ``check --json`` gives)."""
    return {"link": f.link, "severity": f.severity, "code": f.code, "rule": f.rule.id,
            "message": f.message, "line": f.line}


def before_after_dict(r: LinkResult) -> dict[str, Any]:
    """The values as written and what the output carries (None: absent or invalid)."""
    before, after = r.before, r.after
    return {"before": mass_properties_dict(before) if before is not None else None,
            "after": mass_properties_dict(after) if after is not None else None}


def problem_dict(p: Problem) -> dict[str, Any]:
    return {"kind": p.kind, "code": p.code, "line": p.line, "link": p.link,
            "element": p.element, "cause": p.cause}


def fix_result_dict(result: FixResult) -> dict[str, Any]:
    change = mass_change(result)
    return {
        "file": str(result.path),
        "robot": result.robot.name,
        "changed": result.changed,
        "links_left": [{"link": r.name, "line": result.left_error(r).line,
                        "reason": r.reason} for r in result.left],
        "document_problems": [problem_dict(p) for p in result.robot.problems
                              if p.link is None],
        "total_mass": {"before": change.before, "after": change.after,
                       "warning": change.warn and not result.targets,
                       "target": next((t.target for t in result.targets if t.name is None),
                                      None)},
        "mass_targets": [t.as_dict() for t in result.targets],
        "links": [link_dict(r) for r in result.links],
    }
