"""One link's inertial from its geometry: the per-link computation ``fix`` orchestrates.

:func:`compute_link` turns a link's geometry (or its spec entry) into parts and assembles
them (:mod:`urdfinertia.body.assemble`); an element whose parts cannot be made (a missing
or unreadable mesh, a mesh enclosing no volume) is dropped with a :class:`Problem` and the
link is computed from the rest; a link with nothing usable left, or whose parts cannot be
combined, is left exactly as it was (status "left", with the reason).

Imports go one way: :mod:`.apply` (one link's decision) imports this module and
:mod:`.fix` (the whole robot) imports both; nothing here imports either.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from urdfinertia.body.options import (
    PLAUSIBLE_DENSITY,
    FixOptions,
    select_geometry,
    weighable,
)
from urdfinertia.errors import UrdfInertiaError
from urdfinertia.plan.results import LinkResult, Status

if TYPE_CHECKING:
    from collections.abc import Sequence

    from urdfinertia.body.assemble import Assembly
    from urdfinertia.body.geometry_choice import Candidate, GeometryChoice
    from urdfinertia.body.parts import MeshSource, Part
    from urdfinertia.descriptions.model import Link, Problem

# The computing modules (numpy, lxml, the mesh readers) are imported by the functions that
# use them: a warm batch run needs only FixOptions and reuses every result.


def compute_link(link: Link, options: FixOptions, meshes: MeshSource, urdf_dir: Path,
                 problems: Sequence[Problem] = (), *, trust_mass: bool = True,
                 plausible_only: bool = False) -> LinkResult:
    """Recompute one link, or report why it stays untouched or is left as it was.

    ``trust_mass=False``: the written mass is not kept even with ``options.mass == "keep"``
    (the policy found it implausible, :mod:`urdfinertia.plan.policy`).

    ``problems``: what the reader already read past in this link (dropped elements,
    ignored values); they are reported with the link's result.

    ``plausible_only``: derive only from geometry whose implied density (kept mass over
    volume) is plausible; with none, the link is left as it was.
    """
    from urdfinertia.body.assemble import assemble
    from urdfinertia.body.geometry_choice import usable_parts
    from urdfinertia.body.mass import link_mass_source

    if options.keep_auto and link.auto_inertial:
        return LinkResult(link.name, Status.UNTOUCHED, "none", None, link.inertial,
                          ("auto inertia kept (--keep-auto): the simulator computes it",
                           *link.notes))
    spec = options.spec
    chosen = None
    link_spec = spec.link(link.name) if spec is not None else None
    found = list(problems)
    if link_spec is not None:
        parts, _ = link_spec.parts(link, meshes, urdf_dir)
        role = "spec"
        source = link_spec.mass_source(link, options, trust_mass=trust_mass)
    else:
        choice = _choose(link, options, meshes, urdf_dir, trust_mass, plausible_only)
        if choice is None and plausible_only:
            return LinkResult(link.name, Status.LEFT, "none", None, link.inertial, link.notes,
                              tuple(found), "no geometry of a plausible implied density "
                              "to derive from")
        if choice is None:
            # nothing usable: report every element dropped on the way
            role, refs = select_geometry(link, options.geometry)
            usable_parts(link, refs, meshes, urdf_dir, found)
            if options.geometry == "auto" and role == "collision":
                usable_parts(link, weighable(link.visuals), meshes, urdf_dir, found)
            return _not_computed(link, found)
        candidate, chosen = choice
        role, parts = candidate.role, list(candidate.parts)
        found.extend(candidate.dropped)
        source = link_mass_source(link, options, trust_mass=trust_mass)
    try:
        try:
            result = assemble(parts, source)
        except ValueError as exc:  # e.g. an overflow from an absurd density or mass
            raise UrdfInertiaError(f"mass properties cannot be computed: {exc}") from None
    except UrdfInertiaError as exc:
        if link_spec is not None:  # the spec, not the URDF, made these parts
            raise exc.with_context(file=link_spec.path, link=link.name) from None
        return LinkResult(link.name, Status.LEFT, role, None, link.inertial, link.notes,
                          tuple(found), exc.cause)
    warnings = link.notes + _warnings(parts, result)
    return LinkResult(link.name, Status.RECOMPUTED, role, result, link.inertial, warnings,
                      tuple(found), choice=chosen)


def _choose(link: Link, options: FixOptions, meshes: MeshSource, urdf_dir: Path,
            trust_mass: bool, plausible_only: bool = False,
            ) -> tuple[Candidate, GeometryChoice] | None:
    """The geometry the link's inertial integrates (``--geometry auto``: per link, see
    :mod:`urdfinertia.body.geometry_choice`; an SDFormat ``<inertial auto="true">`` is
    Gazebo's, from the collisions); None when no candidate has a usable part."""
    import numpy as np

    from urdfinertia.body.geometry_choice import candidate_sets, choose, evaluate
    from urdfinertia.descriptions.inertial import RawInertial

    if options.geometry == "auto" and not link.auto_inertial:
        sets = candidate_sets(link)
    else:
        role, refs = select_geometry(link, options.geometry)
        sets = [(role, refs)] if refs else []
    mass = com = None
    if link.inertial is not None:
        raw = RawInertial.from_inertial(link.inertial)
        if trust_mass and options.mass == "keep" and raw.mass_ok and raw.mass > 0:
            mass = raw.mass
            com = raw.com if raw.com_ok else None
    # the kind and box need the mesh points: read when there is a choice or a CoM to hold
    # the geometry against (the policy has read them then already)
    detail = len(sets) > 1 or com is not None
    candidates = [c for role, refs in sets
                  if (c := evaluate(link, role, refs, meshes, urdf_dir, detail)) is not None]
    if not candidates:
        return None
    best, chosen = choose(candidates, mass, com if com is None else np.asarray(com))
    lo, hi = PLAUSIBLE_DENSITY
    if plausible_only and chosen.density is not None and not lo <= chosen.density <= hi:
        return None
    return best, chosen


def _not_computed(link: Link, found: list[Problem]) -> LinkResult:
    """A link without parts: untouched when it had nothing to compute from, else left."""
    if not found:
        return LinkResult(link.name, Status.UNTOUCHED, "none", None, link.inertial,
                          ("no geometry: inertial left as it was", *link.notes))
    dropped = [p for p in found if p.kind == "dropped"]
    ignored = [p for p in found if p.kind == "ignored"]
    if dropped:
        first = dropped[0]
        more = f" and {len(dropped) - 1} more" if len(dropped) > 1 else ""
        reason = (f"no usable geometry left ({first.element} line {first.line}: "
                  f"{first.cause}{more})")
    elif ignored:
        reason = f"{ignored[0].cause}, and no geometry to compute it from"
    else:  # only lenient notes: nothing wrong with the link itself
        return LinkResult(link.name, Status.UNTOUCHED, "none", None, link.inertial,
                          ("no geometry: inertial left as it was", *link.notes), tuple(found))
    return LinkResult(link.name, Status.LEFT, "none", None, link.inertial, (), tuple(found),
                      reason)


def problem_code(exc: UrdfInertiaError) -> str:
    """Short category of an element error, for reports ("mesh-missing", ...): the
    exception's own :attr:`~urdfinertia.errors.UrdfInertiaError.code`."""
    return exc.code


def _warnings(parts: list[Part], result: Assembly) -> tuple[str, ...]:
    import numpy as np

    out: list[str] = []
    for p in parts:
        for note in p.notes:
            out.append(f"{p.name}: {note}")
    volume = sum(-p.volume if p.cavity else p.volume for p in parts)
    if volume > 0:
        rho = result.total.mass / volume
        lo, hi = PLAUSIBLE_DENSITY
        if not lo <= rho <= hi:
            out.append(f"implied density {rho:.3g} kg/m^3 is outside {lo:g}..{hi:g} "
                       "(unit slip or placeholder mass?)")
    # distance of each part's CoM from the link origin plus its radius of gyration: a thin
    # hollow part in millimetres has a small volume but a large gyration radius
    extent = max(
        float(np.linalg.norm(p.pose[:3, :3] @ p.unit.com + p.pose[:3, 3]))
        + float(np.sqrt(max(np.trace(p.unit.inertia), 0.0) / (2.0 * abs(p.unit.mass))))
        if p.unit.mass else float(np.linalg.norm(p.pose[:3, 3]))
        for p in parts
    )
    if extent > 10.0:
        out.append(f"geometry spans {extent:.3g} m: millimetre mesh without scale?")
    return tuple(dict.fromkeys(out))
