"""What ``bench_priors.py`` measures on one description file: its CAD links, their geometry
and joints, as plain data (one JSON line per file).

The CAD links are ``bench_cad.py``'s (:func:`bench_cad.plausible_links`: plausible per
``check``, with geometry); every one of a robot is recorded (the robot's total needs them
all) and ``unique`` marks the first occurrence of each across the corpus (mass and
principal moments to 6 digits, :func:`bench_cad.link_key`), which the per-link tables use.

For every candidate geometry of a link (:func:`urdfinertia.body.geometry_choice.
candidate_sets`) the record holds what the tool knows without CAD: volume, centroid, box,
kind and role, and the homogeneous body at the CAD mass (its tensor per kg about its
centroid, the stated materials honoured as ``fix`` does). ``nomass`` is the candidate
``fix`` integrates when the link has no inertial at all, ``kept`` the one it integrates when
the mass and CoM are kept. The tool's own results are measured by running it: ``fix`` with
every inertial withheld (``fix_mass``), ``fix`` with the tensors withheld (``tool``: the
error and stated band, as ``bench_cad.py`` measures them) and, for MJCF, MuJoCo's inertia
from geoms (``mujoco``: mass at its default density and tensor).
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

import numpy as np
from bench_cad import _err, _file_name, _mujoco_tensors, link_key, plausible_links

from urdfinertia.body import geometry_choice
from urdfinertia.body.assemble import assemble
from urdfinertia.body.bounds import BoundsCache, link_bounds
from urdfinertia.body.mass import MassSource
from urdfinertia.body.options import FixOptions
from urdfinertia.cache.library import MeshLibrary
from urdfinertia.descriptions.formats import read_description
from urdfinertia.descriptions.inertial import RawInertial
from urdfinertia.descriptions.model import Link, Robot
from urdfinertia.errors import UrdfInertiaError
from urdfinertia.plan.fix import fix_robot

#: kg/m^3: what ``fix`` integrates a link with no inertial at (``FixOptions().density``).
WATER = FixOptions().density


def _vec(a: Any) -> list[float]:
    return [float(x) for x in np.asarray(a, dtype=np.float64).reshape(-1)]


def _candidate(link: Link, c: geometry_choice.Candidate, mass: float, meshes: MeshLibrary,
               base: Path) -> dict[str, Any] | None:
    parts = list(c.parts)
    try:
        body = assemble(parts, MassSource("kept", mass)).total
        at_water = assemble(parts, MassSource("density", WATER)).total.mass
    except (UrdfInertiaError, ValueError):
        return None
    try:
        box = link_bounds(c.refs, BoundsCache(meshes), base)
    except UrdfInertiaError:
        box = None
    stated = any(p.mass is not None or p.density is not None for p in parts)
    return {"role": c.role, "kind": c.kind, "volume": float(c.volume),
            "centroid": _vec(body.com), "per_kg": _vec(np.asarray(body.inertia) / mass),
            "box": None if box is None else [_vec(box[0]), _vec(box[1])],
            "dropped": len(c.dropped), "elements": len(c.refs), "stated": stated,
            "water_mass": float(at_water)}


def _joints(robot: Robot) -> list[dict[str, Any]]:
    return [{"name": j.name, "type": j.type, "parent": j.parent, "child": j.child,
             "xyz": _vec(j.origin.xyz), "rpy": _vec(j.origin.rpy), "axis": _vec(j.axis),
             "point": _vec(j.axis_point)} for j in robot.joints]


def measure_file(package: str, path: Path, seen: set, meshes: MeshLibrary,
                 ) -> dict[str, Any] | None:
    """The record of one description file; None when it has no CAD link."""
    robot, data = read_description(path)
    plausible = plausible_links(robot, meshes)
    if not plausible:
        return None
    base = path.parent
    samples: list[dict[str, Any]] = []
    for link in plausible:
        assert link.inertial is not None
        raw = RawInertial.from_inertial(link.inertial)
        cands = [c for role, refs in geometry_choice.candidate_sets(link)
                 if (c := geometry_choice.evaluate(link, role, refs, meshes, base)) is not None]
        if not cands:
            continue
        records = [_candidate(link, c, raw.mass, meshes, base) for c in cands]
        kept = [(c, r) for c, r in zip(cands, records, strict=True) if r is not None]
        if not kept:
            continue
        cands = [c for c, _ in kept]
        nomass, _ = geometry_choice.choose(cands, None, None)
        chosen, _ = geometry_choice.choose(cands, raw.mass, np.asarray(raw.com))
        key = link_key(raw)
        unique = key not in seen
        seen.add(key)
        samples.append({"link": link.name, "unique": unique, "mass": raw.mass,
                        "com": _vec(raw.com), "inertia": _vec(raw.inertia),
                        "candidates": [r for _, r in kept], "nomass": cands.index(nomass),
                        "kept": cands.index(chosen), "tool": None, "mujoco": None,
                        "fix_mass": None})
    if not samples:
        return None
    by_name = {s["link"]: s for s in samples}
    _tool_results(robot, data, meshes, by_name)
    if robot.format == "mjcf":
        engine = _mujoco_tensors(path)
        for name, s in by_name.items():
            if engine is not None and name in engine:
                m, tensor = engine[name]
                s["mujoco"] = {"mass": m, "inertia": _vec(tensor)}
    return {"package": package, "file": _file_name(path), "robot": robot.name,
            "format": robot.format, "links": [lk.name for lk in robot.links],
            "joints": _joints(robot), "samples": samples}


def _tool_results(robot: Robot, data: bytes, meshes: MeshLibrary,
                  by_name: dict[str, dict[str, Any]]) -> None:
    """The default ``fix`` with every inertial of the CAD links withheld (their masses), and
    with their tensors withheld (errors and stated bands), as ``bench_cad.py`` runs it."""
    none = tuple(dataclasses.replace(lk, inertial=None) if lk.name in by_name else lk
                 for lk in robot.links)
    for r in fix_robot(dataclasses.replace(robot, links=none), data, FixOptions(),
                       meshes).links:
        if r.name in by_name and r.assembly is not None:
            by_name[r.name]["fix_mass"] = float(r.assembly.total.mass)
    zero = dict(ixx=0.0, ixy=0.0, ixz=0.0, iyy=0.0, iyz=0.0, izz=0.0)
    links = tuple(dataclasses.replace(lk, inertial=dataclasses.replace(lk.inertial, **zero))
                  if lk.name in by_name and lk.inertial is not None else lk
                  for lk in robot.links)
    for r in fix_robot(dataclasses.replace(robot, links=links), data, FixOptions(),
                       meshes).links:
        s = by_name.get(r.name)
        if s is None or r.assembly is None or r.error_bar is None:
            continue
        cad = np.asarray(s["inertia"]).reshape(3, 3)
        s["tool"] = {"error": _err(np.asarray(r.assembly.total.inertia), cad),
                     "band": float(r.error_bar.band)}
