"""``urdf-inertia fix --repair-only``: make invalid tensors valid, keep everything else.

For people who trust their CAD values: each link's mass and CoM stay as written, valid
tensors are left byte for byte, and an invalid tensor gets the smallest lift of its
principal moments that makes it valid (:func:`tensor_repair.repair_tensor`), in the
link frame's axes. Tensors with nothing to keep (zero, negative definite, non-finite) and
links with an unusable mass are reported and left alone: ``urdf-inertia fix`` computes
those from the geometry.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from urdfinertia.body.assemble import Assembly
from urdfinertia.body.mass import MassSource
from urdfinertia.descriptions.formats import NewInertial, format_of, read_description
from urdfinertia.descriptions.inertial import RawInertial
from urdfinertia.descriptions.model import Link
from urdfinertia.errors import UrdfInertiaError
from urdfinertia.findings import Finding
from urdfinertia.inertia.massprops import MassProperties
from urdfinertia.inertia.tensor_repair import repair_tensor
from urdfinertia.plan.results import Action, FixResult, LinkResult, Status
from urdfinertia.rules import Rule


def repair_link(link: Link) -> LinkResult:
    """The repaired link (status "repaired") or why it stays as written ("untouched")."""
    if link.inertial is None:
        return LinkResult(link.name, Status.UNTOUCHED, Action.LEAVE, geometry="none")
    with np.errstate(all="ignore"):
        raw = RawInertial.from_inertial(link.inertial)

    def untouched(why: str = "") -> LinkResult:
        said = (Finding(Rule.NO_GEOMETRY, link.name, why, link.inertial.line
                        if link.inertial is not None else None),) if why else ()
        return LinkResult(link.name, Status.UNTOUCHED, Action.LEAVE, said,
                          because=Rule.NO_GEOMETRY if why else None,
                          previous=link.inertial)

    valid = raw.mass_ok and np.all(np.isfinite(raw.inertia)) and raw.diagnosis().valid
    if valid:
        return untouched()
    if not raw.mass_ok:
        if raw.mass == 0 and not raw.inertia.any():
            return untouched()  # a massless frame
        return untouched(f"mass {raw.mass} is not usable: not repaired (the geometry can "
                         "give it: run fix without --repair-only)")
    if not raw.com_ok:
        return untouched("CoM is not finite: not repaired (the geometry can give it: run "
                         "fix without --repair-only)")
    try:
        repair = repair_tensor(raw.inertia)
    except (ValueError, np.linalg.LinAlgError) as exc:
        return untouched(f"{exc}: not repaired (the geometry can give it: run fix without "
                         "--repair-only)")
    if not repair.changed:
        return untouched()
    total = MassProperties(raw.mass, raw.com, repair.tensor)
    assembly = Assembly(total, (), MassSource("kept", raw.mass))
    notes = tuple(Finding(Rule.TENSOR_LIFTED, link.name, change, link.inertial.line,
                          "inertial") for change in repair.changes)
    return LinkResult(link.name, Status.REPAIRED, Action.REPAIR, notes,
                      (Rule.TENSOR_LIFTED,), previous=link.inertial, assembly=assembly,
                      kept=("mass", "com"), derived=("tensor",))


def repair_file(path: str | Path) -> FixResult:
    """Repair every invalid tensor of the URDF at ``path``; other bytes are unchanged."""
    robot, data = read_description(path)
    results = tuple(repair_link(link) for link in robot.links)
    # Mass and CoM are kept: the writer changes only the tensor's text
    new = {r.name: NewInertial(r.assembly.total, 1.0, frozenset({"tensor"}))
           for r in results if r.assembly is not None}
    try:
        output = format_of(robot).patch(data, new)
    except UrdfInertiaError as exc:
        raise exc.with_context(file=path) from None
    return FixResult(Path(path), robot, results, data, output)
