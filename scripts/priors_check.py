"""``bench_priors.py --check``: the packaged priors on descriptions that were never fitted on.

For each file, every link with geometry is integrated as ``fix`` would with no inertial
(:func:`urdfinertia.body.geometry_choice.choose` with no mass), its features are read
(:mod:`urdfinertia.priors.features`) and the mass prior printed beside 1000 kg/m^3; then the
robot's total with its band (every link, and the moving links alone). This is also the
glue ``fix`` needs to call the priors: features from the chosen candidate and the others.
"""

from __future__ import annotations

from pathlib import Path

from urdfinertia.body import geometry_choice
from urdfinertia.body.bounds import BoundsCache, link_bounds
from urdfinertia.cache.library import MeshLibrary, mesh_library
from urdfinertia.descriptions.formats import read_description
from urdfinertia.descriptions.kinematics import Kinematics
from urdfinertia.descriptions.model import Link
from urdfinertia.errors import UrdfInertiaError
from urdfinertia.priors.features import (
    LinkFeatures,
    RobotFeatures,
    link_features,
    robot_features,
)
from urdfinertia.priors.model import MassPrior, mass_prior, robot_total


def link_prior_features(link: Link, meshes: MeshLibrary, base: Path,
                        robot_feats: RobotFeatures) -> LinkFeatures | None:
    """The features of a link with no inertial, from the geometry ``fix`` integrates."""
    cands = [c for role, refs in geometry_choice.candidate_sets(link)
             if (c := geometry_choice.evaluate(link, role, refs, meshes, base)) is not None]
    if not cands:
        return None
    best, _ = geometry_choice.choose(cands, None, None)
    try:
        box = link_bounds(best.refs, BoundsCache(meshes), base)
    except UrdfInertiaError:
        box = None
    return link_features(link.name, robot_feats, volume=best.volume, box=box,
                         geometry=best.kind, role=best.role,
                         others=tuple(c.volume for c in cands))


def check_files(paths: list[Path], dirs: dict[str, Path]) -> int:
    for path in paths:
        robot, _ = read_description(path)
        meshes = mesh_library(dirs)
        rf = robot_features(robot)
        kin = Kinematics(robot)
        print(f"\n{path.name}: robot '{robot.name}', kind {rf.kind} ({rf.why}); "
              f"{len(robot.links)} links")
        print(f"  {'link':28s} {'at 1000':>8s} {'prior':>8s} {'band':>15s} "
              f"{'kg/m3':>6s}  (kg; at 1000 kg/m3 the mass in kg is the volume in litres)")
        priors: list[tuple[Link, MassPrior]] = []
        for link in robot.links:
            f = link_prior_features(link, meshes, path.parent, rf)
            if f is None:
                continue
            p = mass_prior(f)
            priors.append((link, p))
            print(f"  {link.name:28s} {1000 * f.volume:8.2f} {p.mass:8.2f} "
                  f"{p.low:7.2f}-{p.high:<7.2f} {p.density:6.0f}  "
                  f"({f.part}, {f.geometry}/{f.role})")
        if not priors:
            continue
        every = robot_total([p for _, p in priors])
        moving = [p for lk, p in priors if kin.moves(lk.name)]
        print(f"  every link with geometry ({every.links}): {every.describe()}")
        if moving:
            print(f"  moving links ({len(moving)}): {robot_total(moving).describe()}")
    return 0
