"""Read an MJCF model into the robot model: one link per `<body>`, in MuJoCo's conventions.

* Bodies become links, named by their `name` or, unnamed, `body#K` (the K-th
  `<body>` of the file in document order; `FILE:body#K` in an included file), which
  the writer finds again the same way. The world body is not a link.
* Joints come from nesting: a body with no joint element is welded to its parent (type
  "fixed"), `<freejoint>` is "floating", hinge "revolute", slide "prismatic". A hinge
  or slide brings its axis, limits and effort (`joints`);
  of a body with several joints, the first (a note says so).
* Geoms in MuJoCo's half sizes become the model's full-size shapes
  (`geoms`). Colliding geoms (`contype` or
  `conaffinity` non-zero) are the link's collisions, the others its visuals, and the
  geoms MuJoCo itself counts for inertia (`group` within `inertiagrouprange`, not
  stated massless) are `Link.inertia_geometry`: what `--geometry auto` uses.
* `<inertial>` becomes the model's inertial: `pos` and orientation as the origin,
  `diaginertia` or `fullinertia` (whose off-diagonals are the tensor's own entries,
  as URDF's) along it.

A problem that belongs to one geom drops that geom with a note on its link; one that
belongs to a body's existing inertial drops the inertial (strict reading) with a note.
Only what makes the document as a whole unreadable raises.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from lxml import etree

from urdfinertia.descriptions.mjcf.document import MjcfDocument, Source
from urdfinertia.descriptions.mjcf.geoms import geom_ref, pose_attrs
from urdfinertia.descriptions.mjcf.joints import actuator_efforts, joint_motion
from urdfinertia.descriptions.mjcf.numbers import GeomError, numbers
from urdfinertia.descriptions.mjcf.orientation import matrix_rpy
from urdfinertia.descriptions.model import (
    GeometryRef,
    Implicit,
    Inertial,
    Joint,
    Link,
    Origin,
    Robot,
)
from urdfinertia.errors import UrdfError
from urdfinertia.findings import Finding
from urdfinertia.rules import Rule

_JOINT_TYPES = {"hinge": "revolute", "slide": "prismatic", "ball": "ball", "free": "floating"}
_OFF_AXIS = 1e-9
"""An axis line this far (m) from the body's origin is off it."""
MUJOCO_DENSITY = 1000.0
"""MuJoCo's geom density when none is stated, kg/m^3."""


def body_name(el: etree._Element, src: Source) -> str:
    """A body's link name: its own, or `body#K` by document order (see module doc)."""
    name = el.get("name")
    if name:
        return name
    tag = f"body#{src.body_ordinal[el]}"
    return tag if src.main else f"{src.path.name}:{tag}"


@dataclass
class _Body:
    name: str
    el: etree._Element
    src: Source
    parent: str
    pose: np.ndarray  # in the parent body's frame
    childclass: str
    geoms: list[GeometryRef] = field(default_factory=list)
    counted: list[GeometryRef] = field(default_factory=list)
    joints: list[str] = field(default_factory=list)
    joint_names: list[str] = field(default_factory=list)
    first_joint: tuple[str, str | None, dict[str, str], np.ndarray, int | None] | None = None
    """The first joint element: its type, name, class-resolved attributes, frame in the body."""
    inertial: Inertial | None = None
    notes: list[Finding] = field(default_factory=list)

    def note(self, rule: Rule, message: str, line: int | None = None,
             element: str | None = None) -> None:
        self.notes.append(Finding(rule, self.name, message, line, element))


class _Reader:
    def __init__(self, doc: MjcfDocument) -> None:
        self.doc = doc
        self.bodies: list[_Body] = []
        self.group_range = doc.inertia_group_range()
        self.efforts, self.joint_notes = actuator_efforts(doc)

    def read(self) -> Robot:
        for el, src in self.doc.children(self.doc.main.root, self.doc.main):
            if el.tag == "worldbody":
                self._walk(el, src, None, np.eye(4), "main")
        seen: set[str] = set()
        for body in self.bodies:
            if body.name in seen:
                raise UrdfError(f"duplicate body name '{body.name}'", file=body.src.path,
                                line=body.el.sourceline)
            seen.add(body.name)
        links = tuple(self._link(b) for b in self.bodies)
        joints = tuple(self._joint(b) for b in self.bodies)
        found = [f for b in self.bodies for f in b.notes] + self.joint_notes
        return Robot(name=self.doc.model_name, links=links, joints=joints,
                     path=self.doc.path, format="mjcf", findings=tuple(found))

    # -- the body tree -------------------------------------------------------------------

    def _walk(self, el: etree._Element, src: Source, body: _Body | None, frame: np.ndarray,
              childclass: str) -> None:
        """Children of a body (or the world, `body` None) or of a frame inside one."""
        for child, csrc in self.doc.children(el, src):
            tag = child.tag
            if tag == "body":
                self._body(child, csrc, body, frame, childclass)
            elif tag == "frame":
                pose = self._pose(child, csrc, child.attrib, body)
                self._walk(child, csrc, body, frame @ pose, child.get("childclass", childclass))
            elif tag == "replicate":
                # MuJoCo copies the content ``count`` times, each copy moved by ``offset``
                # and ``euler``; the first copy stands where the content is written. Every
                # copy's inertial is the same in its own body frame: the one written in
                # the template serves them all, so the template is read as it stands.
                self._walk(child, csrc, body, frame, childclass)
            elif body is None:
                continue  # world geoms, sites, lights: no inertia to fix
            elif tag == "geom":
                self._geom(child, csrc, body, frame, childclass)
            elif tag in ("joint", "freejoint"):
                attrs = self.doc.class_attrs("joint", child.get("class", childclass), child,
                                             csrc)
                kind = "free" if tag == "freejoint" else attrs.get("type", "hinge")
                body.joints.append(_JOINT_TYPES.get(kind, kind))
                if body.first_joint is None:
                    body.first_joint = (body.joints[-1], child.get("name"), attrs, frame,
                                        child.sourceline)
                if child.get("name"):
                    body.joint_names.append(child.get("name"))
            elif tag == "inertial":
                body.inertial = self._inertial(child, csrc, body)
            elif tag in ("attach", "composite", "flexcomp"):
                body.note(Rule.READER_NOTE, f"<{tag}> at {csrc.path.name}:{child.sourceline} "
                          "is not expanded: its bodies and geoms are not seen",
                          child.sourceline)

    def _body(self, el: etree._Element, src: Source, parent: _Body | None, frame: np.ndarray,
              childclass: str) -> None:
        name = body_name(el, src)
        pose = self._pose(el, src, el.attrib, None, link=name)
        body = _Body(name, el, src, parent.name if parent else "world", frame @ pose,
                     el.get("childclass", childclass))
        self.bodies.append(body)
        self._walk(el, src, body, np.eye(4), body.childclass)

    def _pose(self, el: etree._Element, src: Source, attrs: dict[str, str],
              body: _Body | None, link: str | None = None) -> np.ndarray:
        try:
            return pose_attrs(attrs, el.attrib, self.doc)
        except GeomError as exc:
            if body is not None:
                body.note(Rule.VALUE_UNREADABLE, f"<{el.tag}> at line {el.sourceline}: {exc}; "
                          "taken as identity", el.sourceline, f"<{el.tag}> pose")
                return np.eye(4)
            raise UrdfError(str(exc), file=src.path, line=el.sourceline, link=link) from None

    def _geom(self, el: etree._Element, src: Source, body: _Body, frame: np.ndarray,
              childclass: str) -> None:
        attrs = self.doc.class_attrs("geom", el.get("class", childclass), el, src)
        where = f"geom at {src.path.name}:{el.sourceline}"
        try:
            found = geom_ref(el, attrs, self.doc, frame)
        except GeomError as exc:
            body.note(exc.rule, f"dropped: {exc}", el.sourceline, where)
            return
        if found is None:
            return  # a plane or height field: no volume, no inertia in MuJoCo either
        ref, group, note = found
        ref = dataclasses.replace(ref, index=sum(r.role == ref.role for r in body.geoms))
        if note:
            body.note(Rule.READER_NOTE, note, el.sourceline, where)
        body.geoms.append(ref)
        stated_zero = ref.mass == 0.0 or (ref.mass is None and ref.density == 0.0)
        if self.group_range[0] <= group <= self.group_range[1] and not stated_zero:
            body.counted.append(ref)

    def _inertial(self, el: etree._Element, src: Source, body: _Body) -> Inertial | None:
        try:
            return _read_inertial(el, self.doc)
        except GeomError as exc:
            body.note(exc.rule, f"<inertial> at {src.path.name}:{el.sourceline} cannot be "
                      f"read: {exc}", el.sourceline, "inertial")
            return None

    # -- model objects -------------------------------------------------------------------

    def _link(self, body: _Body) -> Link:
        collisions = self._materials(body, [r for r in body.geoms if r.role == "collision"])
        visuals = self._materials(body, [r for r in body.geoms if r.role == "visual"])
        counted = self._materials(body, body.counted)
        # MuJoCo computes a body's mass properties from its geoms where it has no
        # <inertial> (inertiafromgeom "auto", the default) or always ("true")
        mode = self.doc.inertia_from_geom
        implicit = (Implicit("geoms") if mode == "true" or (mode == "auto"
                                                             and body.inertial is None)
                    else None)
        return Link(name=body.name, collisions=tuple(collisions), visuals=tuple(visuals),
                    inertial=body.inertial, line=body.el.sourceline, implicit=implicit,
                    inertia_geometry=tuple(counted),
                    read_only=None if body.src.main else
                    f"defined in included file {body.src.path.name}, which is not written")

    def _materials(self, body: _Body, refs: list[GeometryRef]) -> list[GeometryRef]:
        """Geom materials of a body that has an `<inertial>` become weights.

        MuJoCo ignores geom densities and masses when a body has an explicit inertial;
        a kept mass is then shared among the geoms in the proportions they state (geoms
        stating nothing weigh as MuJoCo's default density). `--mass density` uses the
        stated values as they are.
        """
        has_mass = body.inertial is not None and body.inertial.mass > 0
        stated = any(r.density is not None or r.mass is not None for r in refs)
        if not stated or not has_mass or self.doc.inertia_from_geom == "true":
            return refs
        return [dataclasses.replace(
            r, relative=True,
            density=r.density if r.density is not None or r.mass is not None else MUJOCO_DENSITY)
            for r in refs]

    def _joint(self, body: _Body) -> Joint:
        kinds = [k for k in body.joints if k != "fixed"]
        kind = kinds[0] if kinds else "fixed"
        name = body.joint_names[0] if body.joint_names else f"{body.name}_joint"
        motion: dict[str, object] = {}
        first = body.first_joint
        if first is not None and first[0] in ("revolute", "prismatic"):
            name = first[1] or name
            motion = self._motion(body, first, name)
            if len(kinds) > 1:
                self.joint_notes.append(Finding(
                    Rule.READER_NOTE, body.name, f"body '{body.name}' has {len(kinds)} "
                    f"joints: whole-robot statics judges only the first, '{name}'",
                    body.el.sourceline))
        return Joint(name=name, type=kind, parent=body.parent, child=body.name,
                     origin=_origin(body.pose), line=body.el.sourceline,
                     **motion)  # type: ignore[arg-type]

    def _motion(self, body: _Body, first: tuple[str, str | None, dict[str, str], np.ndarray,
                                                  int | None], name: str) -> dict[str, object]:
        """Axis, limits and effort of a body's first joint (see `.joints`)."""
        kind, own, attrs, frame, line = first
        try:
            motion, point = joint_motion(attrs, kind, frame, self.doc)
        except GeomError as exc:
            self.joint_notes.append(Finding(
                Rule.JOINT_UNREADABLE, body.name, f"joint '{name}' (line {line}): {exc}; its "
                "motion is not read", line, f"joint '{name}'"))
            return {}
        if own is not None and own in self.efforts:
            actuated = self.efforts[own]
            stated = motion.get("effort")
            # actuatorfrcrange clamps what the actuators give together
            motion["effort"] = (None if actuated is None else
                                min(actuated, stated) if isinstance(stated, float)
                                else actuated)
        if float(np.linalg.norm(point)) > _OFF_AXIS:
            motion["axis_point"] = tuple(float(v) for v in point)
        return motion


def _origin(pose: np.ndarray) -> Origin:
    xyz = tuple(float(v) for v in pose[:3, 3])
    return Origin(xyz, matrix_rpy(pose[:3, :3]))  # type: ignore[arg-type]


def _read_inertial(el: etree._Element, doc: MjcfDocument) -> Inertial:
    """The ``<inertial>`` exactly as written: non-finite, negative and absurd values are
    kept for the judgement."""
    attrs = dict(el.attrib)
    if "pos" not in attrs:
        raise GeomError("missing attribute 'pos'")
    if "mass" not in attrs:
        raise GeomError("missing attribute 'mass'")
    pose = pose_attrs(attrs, attrs, doc, finite=False)
    mass = numbers(attrs["mass"], 1, "mass", finite=False)[0]
    if "fullinertia" in attrs:
        f = numbers(attrs["fullinertia"], 6, "fullinertia", finite=False)
        values = (f[0], f[3], f[4], f[1], f[5], f[2])  # ixx ixy ixz iyy iyz izz
    elif "diaginertia" in attrs:
        d = numbers(attrs["diaginertia"], 3, "diaginertia", finite=False)
        values = (d[0], 0.0, 0.0, d[1], 0.0, d[2])
    else:
        raise GeomError("needs diaginertia or fullinertia", rule=Rule.MISSING_ATTRIBUTE)
    if all(math.isfinite(v) for v in pose.flat):
        origin = _origin(pose)
    else:  # lenient reading of a NaN pose: keep it visible to the linter
        origin = Origin(tuple(float(v) for v in pose[:3, 3]), (0.0, 0.0, 0.0))  # type: ignore[arg-type]
    return Inertial(origin, mass, *values, line=el.sourceline)


def robot_from_bytes(data: bytes, path: str | Path) -> Robot:
    """The robot model of an MJCF document (inertial values exactly as written)."""
    doc = MjcfDocument(data, Path(path))
    return _Reader(doc).read()
