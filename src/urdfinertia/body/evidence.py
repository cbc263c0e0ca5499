"""What each link brings to its judgement: the written values and the geometry, read once.

A :class:`LinkEvidence` holds a link's written inertial (unvalidated, in the link frame),
its place in the robot (moves, merged by fixed joints, share of the robot's mass) and its
geometry: every candidate set of elements (the format's own inertia geoms, the
collisions, the visuals) integrated at unit density, the box of all of them, and what of
it could not be read. The geometry is computed when first asked for and kept: the
judgement asks for the visuals of a link only when its written values disagree with the
collisions, so a clean robot reads no more than it needs. Whatever is asked, the answers
are the same: the evidence is a function of the files.

:class:`RobotEvidence` holds every link's evidence and what the whole robot says: its
kinematics and the written masses.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from urdfinertia.body.bounds import BoundsCache, link_bounds
from urdfinertia.body.geometry_choice import Candidate, candidate_sets, evaluate
from urdfinertia.body.options import FixOptions, select_geometry
from urdfinertia.descriptions.inertial import RawInertial
from urdfinertia.descriptions.kinematics import Kinematics
from urdfinertia.errors import UrdfInertiaError
from urdfinertia.findings import Finding
from urdfinertia.rules import Rule

if TYPE_CHECKING:
    from urdfinertia.cache.library import MeshLibrary
    from urdfinertia.descriptions.model import Link, Robot
    from urdfinertia.priors.features import RobotFeatures

#: A link's geometry box in the link frame: (lo, hi) corners, m.
Bounds = tuple[np.ndarray, np.ndarray]


@dataclass(eq=False)
class LinkEvidence:
    """One link's written values and geometry (module doc). Geometry is read on demand."""

    link: Link
    robot: RobotEvidence
    _candidates: dict[str, Candidate | None] = field(default_factory=dict)

    @property
    def name(self) -> str:
        return self.link.name

    @property
    def options(self) -> FixOptions:
        return self.robot.options

    @cached_property
    def raw(self) -> RawInertial | None:
        """The written inertial in the link frame, unvalidated (None: none written)."""
        if self.link.inertial is None:
            return None
        with np.errstate(all="ignore"):  # NaN and 1e308 are read as written
            return RawInertial.from_inertial(self.link.inertial)

    @property
    def moves(self) -> bool:
        return self.robot.kin.moves(self.name)

    @property
    def is_root(self) -> bool:
        return self.name not in self.robot.kin.parent_joint

    @cached_property
    def merged_mass(self) -> float:
        """Mass that links fixed to this one (as its group's root) give it, kg."""
        kin = self.robot.kin
        group = kin.group_of(self.name)
        if group.root != self.name:
            return 0.0
        return sum(self.robot.usable_mass(m) for m in group.members if m != self.name)

    @property
    def has_geometry(self) -> bool:
        return bool(self.link.collisions or self.link.visuals)

    @cached_property
    def bounds(self) -> Bounds | None:
        """The box of every geometry element of the link (None: none, or unreadable)."""
        try:
            return link_bounds(self.link.collisions + self.link.visuals,
                               self.robot.bounds_cache, self.robot.urdf_dir)
        except UrdfInertiaError:
            return None

    @cached_property
    def unresolved(self) -> tuple[Finding, ...]:
        """Mesh references that resolve to no file (loaders fail on them)."""
        from urdfinertia.descriptions.model import Mesh
        from urdfinertia.descriptions.paths import resolve_mesh_path

        out = []
        for ref in (*self.link.collisions, *self.link.visuals):
            if not isinstance(ref.shape, Mesh):
                continue
            try:
                resolve_mesh_path(ref.shape.filename, self.robot.urdf_dir,
                                  self.options.package_dirs)
            except UrdfInertiaError as exc:
                out.append(Finding(Rule.MESH_UNRESOLVED, self.name, exc.cause, ref.line,
                                   ref.label))
        return tuple(out)

    @cached_property
    def roles(self) -> tuple[tuple[str, tuple], ...]:
        """The link's candidate sets of elements, (role, refs), the format's own first."""
        if self.options.geometry == "auto":
            return tuple(candidate_sets(self.link))
        role, refs = select_geometry(self.link, self.options.geometry)
        return ((role, refs),) if refs else ()

    @property
    def primary_role(self) -> str:
        """The role the geometry checks start from (:func:`select_geometry`)."""
        return select_geometry(self.link, self.options.geometry)[0]

    def candidate(self, role: str) -> Candidate | None:
        """The set of ``role`` integrated at unit density (None: none, or nothing usable)."""
        if role not in self._candidates:
            found = None
            for r, refs in self.roles:
                if r == role:
                    try:
                        found = evaluate(self.link, r, refs, self.robot.meshes,
                                         self.robot.urdf_dir, detail=True)
                    except (UrdfInertiaError, ValueError, FloatingPointError):
                        found = None
                    break
            self._candidates[role] = found
        return self._candidates[role]

    @property
    def primary(self) -> Candidate | None:
        return self.candidate(self.primary_role)

    def others(self) -> list[Candidate]:
        """Every usable candidate but the primary one, in the order of :attr:`roles`."""
        out = []
        for role, _ in self.roles:
            if role != self.primary_role:
                found = self.candidate(role)
                if found is not None:
                    out.append(found)
        return out

    def all_candidates(self) -> list[Candidate]:
        first = self.primary
        return ([first] if first is not None else []) + self.others()


@dataclass(eq=False)
class RobotEvidence:
    """Every link's evidence, and what the whole robot says."""

    robot: Robot
    options: FixOptions
    meshes: MeshLibrary
    urdf_dir: Path

    @cached_property
    def kin(self) -> Kinematics:
        return Kinematics(self.robot)

    @cached_property
    def bounds_cache(self) -> BoundsCache:
        return BoundsCache(self.meshes)

    @cached_property
    def prior_features(self) -> RobotFeatures:
        """What the mass prior knows of the robot ([`urdfinertia.priors`][urdfinertia.priors]:
        its kind, chain depths, joints)."""
        from urdfinertia.priors.features import robot_features

        return robot_features(self.robot)

    @cached_property
    def links(self) -> dict[str, LinkEvidence]:
        return {link.name: LinkEvidence(link, self) for link in self.robot.links}

    def usable_mass(self, name: str) -> float:
        """The written mass of link ``name`` when finite and positive, else 0 (kg)."""
        inertial = self.robot.link(name).inertial
        if inertial is None:
            return 0.0
        m = inertial.mass
        return float(m) if math.isfinite(m) and 0 < m < 1e30 else 0.0

    @cached_property
    def total_mass(self) -> float:
        """The robot's written mass: the sum of the usable link masses, kg."""
        return float(sum(self.usable_mass(link.name) for link in self.robot.links))


def robot_evidence(robot: Robot, options: FixOptions, meshes: MeshLibrary,
                   urdf_dir: Path | None = None) -> RobotEvidence:
    """The evidence of ``robot`` (its geometry is read when the judgement asks for it)."""
    if urdf_dir is None:
        urdf_dir = robot.path.parent if robot.path is not None else Path(".")
    return RobotEvidence(robot, options, meshes, urdf_dir)
