"""A written tensor that is its own geometry's closed form, times a round factor.

Such a value was computed on purpose: from the link's own primitives at the written mass,
then scaled (a rotor's inertia times 10 for a simulation slowed by 10, a visual's
primitive about its own centre). It is kept, and said so, whatever the geometry checks
would say of the factor.
"""

from __future__ import annotations

import numpy as np

from urdfinertia.body.assemble import assemble
from urdfinertia.body.evidence import LinkEvidence
from urdfinertia.body.geometry_choice import Candidate
from urdfinertia.body.mass import MassSource
from urdfinertia.errors import UrdfInertiaError
from urdfinertia.findings import Finding
from urdfinertia.rules import Rule

#: Round factors tried, besides 1 (the closed form itself).
FACTORS = (10.0, 100.0, 1000.0, 0.1, 0.01, 0.001, 2.0, 0.5, 5.0, 0.2)
#: A tensor within this relative (Frobenius) difference of a factor times the closed form
#: reproduces it (a hand computation rounded to three or four digits).
MATCH_RTOL = 2e-3


def closed_form_factor(ev: LinkEvidence, candidates: list[Candidate]) -> tuple[float, str] | None:
    """(factor, role) when the written tensor is ``factor`` times the closed form of one
    candidate made of primitives only, at the written mass; None otherwise."""
    raw = ev.raw
    if raw is None or not raw.mass_ok or not np.all(np.isfinite(raw.inertia)):
        return None
    for c in candidates:
        if c.dropped or not c.parts or not all(p.method.startswith("closed form")
                                               for p in c.parts):
            continue
        try:
            geo = assemble(c.parts, MassSource("kept", raw.mass)).total.inertia
        except (UrdfInertiaError, ValueError, FloatingPointError):
            continue
        scale = float(np.linalg.norm(geo))
        if not scale > 0:
            continue
        for k in (1.0, *FACTORS):
            if float(np.linalg.norm(raw.inertia - k * geo)) <= MATCH_RTOL * k * scale:
                return k, c.role
    return None


def closed_form_finding(ev: LinkEvidence, factor: float, role: str) -> Finding:
    line = ev.link.inertial.line if ev.link.inertial is not None else None
    mass = ev.raw.mass if ev.raw is not None else float("nan")
    return Finding(Rule.CLOSED_FORM_SCALED, ev.name, f"the tensor is the closed form of the "
                   f"{role} geometry at {mass:.4g} kg, times {factor:g}: computed on "
                   "purpose, kept", line, "inertial")
