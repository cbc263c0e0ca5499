"""Plain-data (JSON-ready) views of results for ``--json``."""

from __future__ import annotations

from typing import Any

import numpy as np

from urdfinertia.findings import finding_dict
from urdfinertia.inertia.massprops import MassProperties
from urdfinertia.plan.results import FixResult, LinkResult
from urdfinertia.plan.total_mass import mass_change
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
    out: dict[str, Any] = {"link": r.name, "status": r.status.value, "geometry": r.geometry,
                           **decision_dict(r), **before_after_dict(r)}
    if r.reason is not None:
        out["reason"] = r.reason
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


def before_after_dict(r: LinkResult) -> dict[str, Any]:
    """The values as written and what the output carries (None: absent or invalid)."""
    before, after = r.before, r.after
    return {"before": mass_properties_dict(before) if before is not None else None,
            "after": mass_properties_dict(after) if after is not None else None}


def fix_result_dict(result: FixResult) -> dict[str, Any]:
    """The whole ``fix --json`` document of one file."""
    change = mass_change(result.links)
    return {
        "file": str(result.path),
        "robot": result.robot.name,
        "changed": result.changed,
        "links_left": [{"link": r.name, "line": result.left_error(r).line,
                        "reason": r.reason} for r in result.left],
        "robot_findings": [finding_dict(f) for f in result.robot_findings],
        "total_mass": {"before": change.before, "after": change.after,
                       "warning": change.warn and not result.targets,
                       "target": next((t.target for t in result.targets if t.name is None),
                                      None)},
        "mass_targets": [t.as_dict() for t in result.targets],
        "links": [link_dict(r) for r in result.links],
    }
