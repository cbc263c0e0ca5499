"""The ``fix`` job: recompute the links' inertials from their geometry and patch the file.

Which links, and which of their values are kept, is :mod:`urdfinertia.link.policy`'s rule.

Data flow: read (:mod:`urdf_read`) -> parts (:mod:`parts`) -> assemble (:mod:`assemble`)
-> write (:mod:`urdf_write`). Nothing here touches the file system except through
:func:`fix_file`'s reading; writing the result is the caller's job (:mod:`atomic`).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from urdfinertia.errors import UrdfInertiaError
from urdfinertia.link.options import PLAUSIBLE_DENSITY, FixOptions, select_geometry
from urdfinertia.link.results import FixResult, LinkResult

if TYPE_CHECKING:
    from urdfinertia.cache.library import MeshLibrary
    from urdfinertia.descriptions.model import Link, Robot
    from urdfinertia.link.assemble import Assembly
    from urdfinertia.link.parts import Part

# The computing modules (numpy, lxml, the mesh readers) are imported by the functions that
# use them: a warm batch run needs only FixOptions and reuses every result.


def compute_link(link: Link, options: FixOptions, meshes: MeshLibrary, urdf_dir: Path,
                 *, trust_mass: bool = True) -> LinkResult:
    """Recompute one link, or report why it stays untouched.

    ``trust_mass=False``: the written mass is not kept even with ``options.mass == "keep"``
    (the policy found it implausible, :mod:`urdfinertia.link.policy`).
    """
    from urdfinertia.link.assemble import assemble
    from urdfinertia.link.mass import link_mass_source
    from urdfinertia.link.parts import geometry_parts

    spec = options.spec
    link_spec = spec.link(link.name) if spec is not None else None
    if link_spec is not None:
        parts, _ = link_spec.parts(link, meshes, urdf_dir)
        role = "spec"
        source = link_spec.mass_source(link, options, trust_mass=trust_mass)
    else:
        role, refs = select_geometry(link, options.geometry)
        if not refs:
            return LinkResult(link.name, "untouched", "none", None, link.inertial,
                              ("no geometry: inertial left as it was",))
        parts = []
        for ref in refs:
            parts.extend(geometry_parts(ref, meshes, urdf_dir))
        source = link_mass_source(link, options, trust_mass=trust_mass)
    try:
        try:
            result = assemble(parts, source)
        except ValueError as exc:  # e.g. an overflow from an absurd density or mass
            raise UrdfInertiaError(f"mass properties cannot be computed: {exc}") from None
    except UrdfInertiaError as exc:
        if link_spec is not None:  # the spec, not the URDF, made these parts
            raise exc.with_context(file=link_spec.path, link=link.name) from None
        raise exc.with_context(link=link.name, line=link.line) from None
    warnings = _warnings(parts, result)
    return LinkResult(link.name, "recomputed", role, result, link.inertial, warnings)


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


def fix_robot(robot: Robot, data: bytes, options: FixOptions,
              meshes: MeshLibrary | None = None) -> FixResult:
    """Recompute all links of ``robot`` and return the patched document."""
    from urdfinertia.cache.library import MeshLibrary
    from urdfinertia.descriptions.formats import format_of

    path = robot.path or Path("robot.urdf")
    if meshes is None:
        meshes = MeshLibrary(options.package_dirs, options.max_faces)
    urdf_dir = path.parent
    if options.spec is not None:
        options.spec.check_links(robot)
    # which links are recomputed, and what of them is kept: link/policy.py (issue 14)
    from urdfinertia.link.apply import apply_decision
    from urdfinertia.link.policy import plan_robot

    plan = plan_robot(robot, options, meshes, urdf_dir)
    results = []
    for link in robot.links:
        try:
            results.append(apply_decision(link, plan[link.name], options, meshes, urdf_dir))
        except UrdfInertiaError as exc:
            raise exc.with_context(file=path, link=link.name) from None
    new = {r.name: (r.assembly.total, r.size) for r in results if r.assembly is not None}
    try:
        output = format_of(robot).patch(data, new)
    except UrdfInertiaError as exc:
        raise exc.with_context(file=path) from None
    return FixResult(path, robot, tuple(results), data, output)


def fix_file(path: str | Path, options: FixOptions,
             meshes: MeshLibrary | None = None) -> FixResult:
    from urdfinertia.descriptions.formats import read_description

    robot, data = read_description(path)
    return fix_robot(robot, data, options, meshes)

