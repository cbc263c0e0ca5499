"""A composed USD stage read into the robot model.

Links are the prims with `PhysicsRigidBodyAPI` (an articulation's links are such
bodies), found through instances (instance proxies), references and payloads, every
payload loaded. A body's geometry is every `UsdGeom` gprim below it that no nearer body
owns: prims with `PhysicsCollisionAPI` are its collisions, the others its visuals.
Joints are the `UsdPhysics` joints between two bodies. A body whose MassAPI does not
give both mass and inertia has no inertial in the model: the engine computes it from the
collision shapes (:class:`~urdfinertia.descriptions.model.Implicit`, with the mass the
MassAPI states, if any). A missing layer is a finding of the document.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from urdfinertia.descriptions.model import GeometryRef, Implicit, Joint, Link, Origin, Robot
from urdfinertia.descriptions.usd import geometry, mass
from urdfinertia.descriptions.usd.frames import matrix_rpy, quat_matrix, to_numpy, vec3
from urdfinertia.descriptions.usd.stage import Opened, open_stage
from urdfinertia.findings import Finding
from urdfinertia.rules import Rule

DEFAULT_DENSITY = 1000.0
"""UsdPhysics' default density where nothing gives one (kg/m^3, water)"""
_JOINT_TYPES = {
    "PhysicsRevoluteJoint": "revolute", "PhysicsPrismaticJoint": "prismatic",
    "PhysicsFixedJoint": "fixed", "PhysicsSphericalJoint": "ball",
    "PhysicsDistanceJoint": "floating", "PhysicsJoint": "floating",
}


@dataclass
class _Body:
    prim: Any
    name: str
    collisions: list[GeometryRef] = field(default_factory=list)
    visuals: list[GeometryRef] = field(default_factory=list)
    notes: list[Finding] = field(default_factory=list)


@dataclass(frozen=True)
class UsdRobot:
    """The model and what the writer needs to address each link's prim."""

    robot: Robot
    prim_paths: dict[str, str]  # link name -> prim path
    newton: frozenset[str]  # links whose body has NewtonMassAPI applied
    meters_per_unit: float
    kilograms_per_unit: float
    instances: tuple[str, ...] = ()
    """Instance prims with bodies inside: opinions below an instance are ignored by composition, so
    the override makes them not instanceable.
    """


def valid_identifier(name: str) -> str:
    """A name as USD prim names must be (what the converters make of a link name)."""
    out = re.sub(r"[^A-Za-z0-9_]", "_", name)
    return "_" + out if not out or out[0].isdigit() else out


_LAST: list[tuple[str, tuple[tuple[str, int], ...], UsdRobot]] = []
"""The last asset read and the times of every layer it used: `fix` reads the model and then
the override template of the same asset."""


def _stamps(paths: tuple[str, ...]) -> tuple[tuple[str, int], ...] | None:
    try:
        return tuple((p, Path(p).stat().st_mtime_ns) for p in paths)
    except OSError:
        return None


def read(path: Path) -> UsdRobot:
    """The robot of a USD asset. A sublayer, reference or payload that cannot be opened is
    a finding of the document (`missing-layer`, an error: `fix` refuses to write an
    asset read incomplete)."""
    key = str(path.resolve())
    for k, stamps, found in _LAST:
        if k == key and _stamps(tuple(p for p, _ in stamps)) == stamps:
            return found
    found, used = _read(path)
    stamps_now = _stamps(used)
    _LAST.clear()
    if stamps_now is not None:
        _LAST.append((key, stamps_now, found))
    return found


def _read(path: Path) -> tuple[UsdRobot, tuple[str, ...]]:
    opened = open_stage(path)
    used = tuple(str(layer.realPath) for layer in opened.stage.GetUsedLayers()
                 if layer.realPath)
    return _Reader(opened, path).run(), used


class _Reader:
    def __init__(self, opened: Opened, path: Path) -> None:
        self.o = opened
        self.path = path
        self.problems: list[Finding] = []

    def run(self) -> UsdRobot:
        from pxr import Usd, UsdGeom, UsdPhysics

        stage = self.o.stage
        cache = UsdGeom.XformCache()
        prims = list(Usd.PrimRange(stage.GetPseudoRoot(), Usd.TraverseInstanceProxies()))
        body_paths = [p for p in prims if p.HasAPI(UsdPhysics.RigidBodyAPI)]
        names = self._names(body_paths)
        bodies = {p.GetPath(): _Body(p, names[p.GetPath()]) for p in body_paths}
        for prim in prims:
            if prim.IsA(UsdGeom.Gprim):
                owner = self._owner(prim, bodies)
                if owner is not None:
                    self._geometry(owner, prim, cache)
        links, newton = [], set()
        for body in bodies.values():
            link, has_newton = self._link(body)
            links.append(link)
            if has_newton:
                newton.add(link.name)
        joints = self._joints(prims, bodies)
        missing = [Finding(Rule.MISSING_LAYER, None, f"layer {m} cannot be opened: what it "
                           "holds is missing from the stage") for m in self.o.missing]
        default = stage.GetDefaultPrim()
        notes = [f for b in bodies.values() for f in b.notes]
        robot = Robot(name=default.GetName() if default else self.path.stem,
                      links=tuple(links), joints=tuple(joints), path=self.path, format="usd",
                      findings=tuple(missing + self.problems + notes))
        instances = []
        for prim in body_paths:
            up = prim
            while up.IsInstanceProxy():
                up = up.GetParent()
            if up != prim:
                instances.append(str(up.GetPath()))
        return UsdRobot(robot, {b.name: str(k) for k, b in bodies.items()},
                        frozenset(newton), self.o.meters_per_unit, self.o.kilograms_per_unit,
                        tuple(dict.fromkeys(instances)))

    @staticmethod
    def _names(body_prims: list[Any]) -> dict[Any, str]:
        """Prim names, or prim paths where two bodies share a name."""
        count: dict[str, int] = {}
        for p in body_prims:
            count[p.GetName()] = count.get(p.GetName(), 0) + 1
        return {p.GetPath(): p.GetName() if count[p.GetName()] == 1 else str(p.GetPath())
                for p in body_prims}

    @staticmethod
    def _owner(prim: Any, bodies: dict[Any, _Body]) -> _Body | None:
        path = prim.GetPath()
        while not path.isEmpty and path != path.absoluteRootPath:
            if path in bodies:
                return bodies[path]
            path = path.GetParentPath()
        return None

    def _geometry(self, body: _Body, prim: Any, cache: Any) -> None:
        from pxr import UsdPhysics

        collision = prim.HasAPI(UsdPhysics.CollisionAPI)
        role = "collision" if collision else "visual"
        refs = body.collisions if collision else body.visuals
        name = str(prim.GetPath().MakeRelativePath(body.prim.GetPath()))
        body_world = to_numpy(cache.GetLocalToWorldTransform(body.prim))
        prim_world = to_numpy(cache.GetLocalToWorldTransform(prim))
        from urdfinertia.descriptions.usd.frames import rigid_and_scale

        try:
            rigid, _ = rigid_and_scale(body_world)
            origin, shape = geometry.element(prim, np.linalg.inv(rigid) @ prim_world,
                                             self.o.meters_per_unit)
        except geometry.ShapeError as exc:
            if collision:  # a visual that gives no volume is no loss
                self.problems.append(Finding(exc.rule, body.name, str(exc),
                                             element=f"{role} {prim.GetPath()}"))
            return
        density = given_mass = None
        if collision:
            own = mass.authored(prim, self.o.meters_per_unit, self.o.kilograms_per_unit)
            density = own.density if own.density else None
            given_mass = own.mass if own.mass else None
            approx = prim.GetAttribute("physics:approximation").Get()
            if approx and approx != "none" and prim.GetTypeName() == "Mesh":
                body.notes.append(Finding(
                    Rule.READER_NOTE, body.name, f"engines collide with its {approx} "
                    "approximation; its volume here is the mesh's own",
                    element=f"collision {name}"))
        refs.append(GeometryRef(role=role, index=len(refs), name=name, origin=origin,
                                shape=shape, density=density, mass=given_mass))

    def _link(self, body: _Body) -> tuple[Link, bool]:
        a = mass.authored(body.prim, self.o.meters_per_unit, self.o.kilograms_per_unit)
        for rule, cause in mass.rule_problems(a):
            self.problems.append(Finding(rule, body.name, cause,
                                         element=f"MassAPI {body.prim.GetPath()}"))
        inertial = mass.inertial(a)
        collisions = body.collisions
        implicit = None
        if inertial is None:
            implicit = Implicit("colliders", a.mass if a.mass and a.mass > 0 else None,
                                a.density if a.density and a.density > 0 else None)
            density = a.density if a.density and a.density > 0 else DEFAULT_DENSITY
            collisions = [r if r.density is not None or r.mass is not None
                          else _with_density(r, density) for r in collisions]
        return Link(name=body.name, collisions=tuple(collisions), visuals=tuple(body.visuals),
                    inertial=inertial, implicit=implicit), a.newton_applied

    def _joints(self, prims: list[Any], bodies: dict[Any, _Body]) -> list[Joint]:
        from pxr import UsdPhysics

        out = []
        for prim in prims:
            if not prim.IsA(UsdPhysics.Joint):
                continue
            j = UsdPhysics.Joint(prim)
            b0 = j.GetBody0Rel().GetTargets()
            b1 = j.GetBody1Rel().GetTargets()
            if not b1 or b1[0] not in bodies:
                continue
            parent = bodies[b0[0]].name if b0 and b0[0] in bodies else "world"
            mpu = self.o.meters_per_unit
            pos = j.GetLocalPos0Attr().Get()
            rot = j.GetLocalRot0Attr().Get()
            xyz = vec3([float(v) * mpu for v in pos]) if pos is not None else (0.0, 0.0, 0.0)
            rpy = (0.0, 0.0, 0.0)
            if rot is not None:
                q = (float(rot.GetReal()), *map(float, rot.GetImaginary()))
                try:
                    rpy = matrix_rpy(quat_matrix(q))
                except ValueError:
                    pass
            kind = _JOINT_TYPES.get(prim.GetTypeName(), "floating")
            out.append(Joint(name=prim.GetName(), type=kind, parent=parent,
                             child=bodies[b1[0]].name, origin=Origin(xyz=xyz, rpy=rpy)))
        return out


def _with_density(ref: GeometryRef, density: float) -> GeometryRef:
    import dataclasses

    return dataclasses.replace(ref, density=density)
